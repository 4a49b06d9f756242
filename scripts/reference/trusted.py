"""Reference implementation of docs/ESTIMATOR.md: the observability-aware estimator.

float64, numpy; it shares no code with the C library (it is the yardstick for the C
library's default preset). Steps, as numbered in docs/ESTIMATOR.md:
  1. complementary filters for vx, vy;  2. time update;  3. low-speed skip;
  4. step measurement noise S_R: model error and errors in variables (input derivatives);
  5. statistical linearisation over the cubature points -> Fisher information, gate;
  6. measurement update with S_R;  7. sd bounds by one factor for the whole S;
  8. projection;  9. output, validity.
Structure "sides": x = [mu_left, mu_right] (fl, rl left; fr, rr right); "wheels": four mu.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from scipy.linalg import solve_triangular

from . import filters, model, monitor

WHEELS_OF_SIDES = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 0.0], [0.0, 1.0]])  # fl fr rl rr

def sqrt_prior(n: int, sd: float, sd_common: float) -> np.ndarray:
    """Lower-triangular factor of sd_common^2 11^T + sd^2 I (exactly sd I when sd_common = 0)."""
    if sd_common == 0.0:
        return sd * np.eye(n)
    return np.linalg.cholesky(sd_common ** 2 * np.ones((n, n)) + sd ** 2 * np.eye(n))


class Conditioner:
    """Complementary filters for vx, vy (accelerometers integrated, speeds as the slow truth)."""

    def __init__(self, tau: float, dt: float):
        self.b = dt / (tau + dt) if tau > 0 else 1.0
        self.dt = dt
        self.vx = self.vy = None

    def step(self, vx, vy, ax, ay, r):
        if self.vx is None:
            self.vx, self.vy = vx, vy
            return vx, vy
        px = self.vx + self.dt * (ax + r * self.vy)   # vx_dot = ax + r vy
        py = self.vy + self.dt * (ay - r * self.vx)   # vy_dot = ay - r vx
        self.vx = (1.0 - self.b) * px + self.b * vx
        self.vy = (1.0 - self.b) * py + self.b * vy
        return self.vx, self.vy


class YawCheck:
    """The yaw-rate input check (docs/ESTIMATOR.md step 0b, before step 1): a yaw rate that
    differs by more than thr from the last accepted one advanced by the measured yaw
    acceleration over dt (trapezoidal) is replaced by that prediction. Restarted (the next
    sample accepted as it is) at init, after a gap (like the conditioner) and after a replaced
    sample (a departure that persists is a step of the yaw rate, not a spike: without the
    restart the check would hold the old rate for ever). thr = 0: off."""

    def __init__(self, thr: float, dt: float):
        self.thr, self.dt = thr, dt
        self.r = self.r_dot = None

    def step(self, r: float, r_dot: float) -> float:
        kept = True
        if self.thr > 0 and self.r is not None:
            pred = self.r + (self.dt * 0.5) * (r_dot + self.r_dot)
            if abs(r - pred) > self.thr:
                r, kept = pred, False
        self.r, self.r_dot = (r if kept else None), r_dot
        return r


class StaleOmega:
    """The stale-wheel-speed rule (docs/ESTIMATOR.md step 9, a valid-flag rule like the
    holds): wheel i is stale when omega_i equals its previous sample exactly, is not 0, and
    the median of the other three wheel speeds has moved by more than delta since omega_i
    last changed. While any wheel is stale every flag is 0. delta = 0: off."""

    def __init__(self, delta: float):
        self.delta = delta
        self.prev = np.zeros(4)     # the library's state starts at 0: the first sample changes
        self.ref = np.zeros(4)
        self.stale = False

    def update(self, omega) -> None:
        if not self.delta > 0:
            return
        self.stale = False
        for w in range(4):
            a, b, c = (omega[j] for j in range(4) if j != w)
            others = max(min(a, b), min(max(a, b), c))     # the median of three
            if omega[w] != self.prev[w] or omega[w] == 0.0:
                self.ref[w] = others
            elif abs(others - self.ref[w]) > self.delta:
                self.stale = True
        self.prev = np.array(omega, dtype=float)


def h_point(p, u, mu4):
    """h(mu, u) for one input vector u = (delta, vx, vy, r, ax, ay, w1..w4) and mu per wheel
    (absolute / magic tyre: the load-scaled curve at mu; paper tyre: H(u) mu)."""
    return h_points(p, np.asarray(u, dtype=float)[None, :], np.asarray(mu4, dtype=float)[None, :])[0]


def h_points(p, us, mus):
    """h at P points at once: us shape (P, 10) input vectors, mus shape (P, 4) mu per wheel;
    returns (P, 3). Row i is h_point(p, us[i], mus[i]) with the same elementwise operations
    (the model functions broadcast over the leading axis); one call instead of P saves the
    reference most of its time in step 4's 17 evaluations per step."""
    us = np.ascontiguousarray(us, dtype=float)
    mus = np.ascontiguousarray(mus, dtype=float)    # rows as h_point's own arrays
    ti = model.tyre_inputs(p, us[:, 0], us[:, 1], us[:, 2], us[:, 3], us[:, 4], us[:, 5],
                           us[:, 6:10])
    if p["tyre"] == "paper":
        hm = model.observation_matrix(p, ti)
        return np.stack([hm[i] @ mus[i] for i in range(us.shape[0])])
    fx, fy = model.tyre_absolute(p, mus, ti.fz, ti.kappa, ti.alpha, ti.v_wx)
    return model.body_effects(p, fx, fy, ti.delta_i).sum(axis=-1)


class Hold:
    """Step 9's rear-wheel hold (docs/ESTIMATOR.md; structure sides, rear_hold_k > 0): each
    side's estimate smoothed over one wheelbase L of travel (mbar) and the distance its rear
    wheels still hold (dist). A side whose estimate lies more than rear_hold_k sd from mbar has
    just moved on what its front wheels reached first; its rear wheels reach it one wheelbase
    later, so they hold for L. And the jump hold (jump_hold_k > 0): a side whose estimate moved
    in this step by more than jump_hold_k sd from the last step's holds both its wheels for
    jump_hold_len of travel (jdist, jheld). The library's hold_update, operation for operation."""

    def __init__(self, p: dict):
        self.k = p["rear_hold_k"]
        self.len = p["Lf"] + p["Lr"]
        self.dt = p["dt"]
        self.mbar = [p["mu0"], p["mu0"]]
        self.dist = [0.0, 0.0]
        self.held = [False, False]
        self.k_jump = p["jump_hold_k"]
        self.jump_len = p["jump_hold_len"]
        self.prev = [p["mu0"], p["mu0"]]
        self.jdist = [0.0, 0.0]
        self.jheld = [False, False]

    def update(self, x, sd, vx: float, missed: int) -> None:
        ds = max(vx, 0.0) * (self.dt * (missed + 1.0))
        a = ds / self.len if ds < self.len else 1.0
        for j in range(2):
            if self.k > 0:
                self.mbar[j] += a * (x[j] - self.mbar[j])
                self.dist[j] = self.dist[j] - ds if self.dist[j] > ds else 0.0
                if abs(x[j] - self.mbar[j]) > self.k * sd[j]:
                    self.dist[j] = self.len
                self.held[j] = self.dist[j] > 0.0
            if self.k_jump > 0:
                self.jdist[j] = self.jdist[j] - ds if self.jdist[j] > ds else 0.0
                if abs(x[j] - self.prev[j]) > self.k_jump * sd[j]:
                    self.jdist[j] = self.jump_len
                self.prev[j] = x[j]
                self.jheld[j] = self.jdist[j] > 0.0


class StepNoiseReuse:
    """Issue 21's candidate 'propagate the step noise every N steps when the inputs move little'
    (a study in this reference, docs/BENCHMARKS.md "The step noise every N steps"; not the
    specified estimator, not in the library; off unless an instance is passed to run()).
    Step 4's errors-in-variables columns g_j (16 model evaluations) are computed on one step and
    reused on the following ones; S_R0 (the model error at this step's x-, one evaluation) and
    Tria([S_R0, g_j]) are still formed every step. The columns are recomputed when
      - every: they are `every` evaluating steps old (every = 1: every step, equal to off);
      - move (None: no such rule): any input j with sd_j > 0 moved by more than move * sd_j
        since they were computed;
      - the step before did not evaluate h (low speed) or a gap restarted the conditioner.
    inputs (None: all): the indices into u of the inputs whose columns are reused (e.g.
    PERSISTENT_INPUTS, the low-passed vx, vy: 4 of the 16 evaluations); the other inputs'
    columns are computed every step, and the move rule looks at the reused inputs only.
    computed counts the steps that recomputed them, used the steps that needed them."""

    def __init__(self, every: int = 1, move: float | None = None, inputs=None):
        if int(every) != every or every < 1:
            raise ValueError(f"every must be an integer >= 1, got {every!r}")
        if move is not None and not move > 0:
            raise ValueError(f"move must be > 0 or None, got {move!r}")
        if inputs is not None:
            inputs = tuple(int(j) for j in inputs)
            if not inputs or len(set(inputs)) != len(inputs) or min(inputs) < 0:
                raise ValueError(f"inputs must be distinct indices >= 0 or None, got {inputs!r}")
        self.every, self.move, self.inputs = int(every), move, inputs
        self.cols = None        # [(j, g_j)] of the last computation
        self.u = None           # the inputs they were computed at
        self.age = 0            # evaluating steps since then
        self.computed = self.used = 0

    def drop(self) -> None:
        """Forget the columns (a step without h, or a gap)."""
        self.cols = None

    def due(self, u, sd_u) -> bool:
        """Whether this evaluating step recomputes the columns (advances the age)."""
        self.used += 1
        self.age += 1
        fresh = self.cols is not None and self.age < self.every
        if fresh and self.move is not None:
            m = sd_u > 0
            if self.inputs is not None:
                m &= np.isin(np.arange(m.size), self.inputs)
            fresh = not np.any(np.abs(u[m] - self.u[m]) > self.move * sd_u[m])
        if not fresh:
            self.cols, self.u, self.age = None, np.array(u, copy=True), 0
            self.computed += 1
        return not fresh


def run(log, p: dict, adapt=None, reuse: StepNoiseReuse | None = None):
    """Run over a sensor log; returns dict t, mu (N,4), sd (N,4), valid (N,4), status, info,
    and nu (N,3), s_zz (N,3,3): the innovation y - z_hat and the lower factor of its
    covariance at every step that evaluates the measurement, c_pers (N,3) the diagonal of that
    covariance's persistent part (Zc Zc^T, the model error, the low-passed vx, vy; NaN at low
    speed; the inputs of monitor.py). adapt (None: off; a measurement of monitor.py, not the specified estimator):
    called as adapt(k, nu, s_zz, zc, s_r, c_pers) after the innovation, returns the S_R this step's
    update uses instead of s_r (the gate and the recorded S_zz keep s_r). reuse (None: off; a
    StepNoiseReuse, issue 21's study): step 4's input columns reused over steps; out["snoise"]
    (N,) then marks the steps that recomputed them."""
    T = WHEELS_OF_SIDES if p["structure"] == "sides" else np.eye(4)
    n = T.shape[1]
    f = filters.SCKF(np.full(n, p["mu0"]), sqrt_prior(n, p["sd0"], p["sd0_common"]),
                     sqrt_prior(n, p["q_mu"], p["q_common"]),
                     np.diag([p["r_ax"], p["r_ay"], p["r_yaw_acc"]]))
    f.linear = p["tyre"] == "paper"     # h = H(u) T x: the n-column update (filters.SCKF)
    cond = Conditioner(p["tau_v"], p["dt"])
    yaw = YawCheck(p["yaw_check"], p["dt"])
    stale = StaleOmega(p["stale_omega"])
    # input order of the errors-in-variables columns: delta, vx, vy, r, (ax, ay: none), omega
    sd_u = np.array([p["sd_in_delta"], p["sd_in_vx"], p["sd_in_vy"], p["sd_in_yaw_rate"],
                     0.0, 0.0] + [p["sd_in_omega"]] * 4)
    cols = [log.col(c) for c in ("delta", "vx", "vy", "yaw_rate", "ax", "ay")]
    omega = log.omega()
    ys = np.stack([log.col("ax"), log.col("ay"), log.col("yaw_acc")], axis=-1)
    N = len(log)
    out = {k: np.zeros((N, 4)) for k in ("mu", "sd")}
    out["valid"] = np.zeros((N, 4), dtype=int)
    out["status"] = np.zeros(N, dtype=int)
    out["info"] = np.zeros((N, n))
    out["v_gate"] = np.zeros(N)                 # diagnostics (compare.py): the gate's vx and
    out["mu_unprojected"] = np.zeros((N, 4))    # the mean before projection
    out["nu"] = np.full((N, 3), np.nan)         # innovation y - z_hat and its factor S_zz of
    out["s_zz"] = np.full((N, 3, 3), np.nan)    # every step that evaluates h (monitor.py)
    out["c_pers"] = np.full((N, 3), np.nan)     # diag of its persistent part (monitor.py)
    if reuse is not None:
        out["snoise"] = np.zeros(N, dtype=bool)
    if p["lower_bound_delta"] > 0:     # the sides whose downward move step 6 skipped, and
        out["censored"] = np.zeros((N, n), dtype=bool)     # the information it decided on
        out["info_up"] = np.full((N, n), np.nan)
    evid = Evidence(p, n) if p["evid_delta"] > 0 else None
    upper = UpperEvidence(p, n) if p["evid_up_delta"] > 0 else None
    if upper is not None:      # step 9's upper evidence: Lambda of each update, L after the step
        out["evid_up_lam"] = np.zeros((N, n))
        out["evid_up_L"] = np.zeros((N, n))
    hyp = (Hypotheses(p) if p["info_at"] > 0 and (p["hyp_update"] > 0 or p["hyp_lr_min"] > 0)
           else None)
    if hyp is not None:     # per step: 1 gate opened only at c; the log LR and L (section 17)
        out["hyp"] = np.zeros(N, dtype=int)
        out["hyp_lr"] = np.full(N, np.nan)
        out["hyp_L"] = np.zeros(N)
    if evid is not None:                # the sides step 6 censored, and the evidence L after
        out["censored"] = np.zeros((N, n), dtype=bool)     # each step (MONITOR.md section 14)
        out["evid_L"] = np.zeros((N, n))
    if p["sd_local"] > 0:      # the factor step 6's local-information bound applied
        out["sd_local_c"] = np.ones(N)
    relin = _relin_mode(p)
    if relin is not None:      # the final linearisation's information (section 21)
        out["relin_info"] = np.full((N, n), np.nan)
    floor_mem = (FloorMemory(p, n) if p["sd_floor_ref"] > 0 or p["sd_floor_hold"] > 0
                 else None)       # step 7's floor level (section 19; None: today's)
    t = log.col("t")
    hold = Hold(p) if (p["structure"] == "sides"
                           and (p["rear_hold_k"] > 0 or p["jump_hold_k"] > 0)) else None
    for k in range(N):
        missed = filters.gap_periods(t[k] - t[k - 1], p["dt"]) if k > 0 else 0
        if filters.gap_time_update(f, t, k, p):     # a gap (ESTIMATOR.md "Gaps")
            _bound_sd(p, f, floor_mem, record=False)
            cond.vx = cond.vy = None    # the input filter restarts at this sample
            yaw.r = None                # and so does the yaw-rate check
            if reuse is not None:
                reuse.drop()
        delta, vx_m, vy_m, r, ax, ay = (c[k] for c in cols)
        r = yaw.step(r, ys[k][2])                                       # 0b
        vx, vy = cond.step(vx_m, vy_m, ax, ay, r)                       # 1
        u = np.array([delta, vx, vy, r, ax, ay, *omega[k]])
        f.time_update()                                                 # 2
        status = 2                                                      # 3
        if vx >= p["v_est_min"]:
            if reuse is not None:
                out["snoise"][k] = reuse.due(u, sd_u)
            s_r = _step_noise(p, f, T, u, sd_u, out["c_pers"][k], reuse)  # 4
            hfun = lambda pts: h_points(  # noqa: E731
                p, np.tile(u, (pts.shape[1], 1)), (T @ pts).T).T
            pts = f.points()
            z_pts = hfun(pts)
            cen = f.centred(hfun)       # (z, Xc, Zc): the n-column form for the paper tyre
            zc = _innovation(cen, s_r, ys[k], out, k)
            s_r_used = s_r if adapt is None else adapt(k, out["nu"][k], out["s_zz"][k], zc, s_r,
                                                       out["c_pers"][k])
            update = True
            alt = None          # the second centre, when only it opened the gate (section 17)
            if p["info_min"] > 0:                                       # 5
                out["info"][k] = _information_of(f, cen[1], cen[2], s_r)
                if p["info_at"] > 0:    # the gate judges a second centre too (reference only)
                    at_x = bool(out["info"][k].max() >= p["info_min"])
                    keep = {} if hyp is not None else None
                    out["info"][k] = np.maximum(out["info"][k], _information_alt(
                        p, f, pts, z_pts, s_r, ys[k], hfun, keep))
                    if hyp is not None:
                        alt = hyp.step(at_x, bool(out["info"][k].max() >= p["info_min"]),
                                       f, z_pts, keep, s_r, ys[k], out, k)
                update = bool(out["info"][k].max() >= p["info_min"])
                if alt is not None and p["hyp_lr_min"] > 0 and (hyp.L < p["hyp_lr_min"]
                                                                or hyp.warming()):
                    update = False      # the data do not favour the centre that opened it
            status = 3
            lam_up = None
            if update and upper is not None:    # at x- and step 4's noise, before step 6
                lam_up = upper_evidence(p, f.x, T, u, sd_u, ys[k], s_r, f.s_r,
                                        p["evid_up_delta"])
            if update:                                                  # 6
                saved, f.s_r = f.s_r, s_r_used
                if alt is not None and p["hyp_update"] > 0:
                    kept = True
                    _update_at(f, ys[k], hfun, alt)
                elif p["lower_bound_delta"] > 0:
                    kept, out["info_up"][k] = _one_sided_update(p, f, T, u, sd_u, ys[k],
                                                                hfun, saved)
                    out["censored"][k] = ~kept
                elif evid is not None:
                    own = out["info"][k] >= p["info_min"]   # the sides updated on their own
                    kept = evid.update(p, f, T, u, sd_u, ys[k], hfun, s_r, saved, own)
                    out["censored"][k] = ~kept
                else:
                    kept = True
                    x_prior, s_prior = f.x.copy(), f.S.copy()
                    if relin is None:
                        f.measurement_update(ys[k], hfun)
                    else:               # reference only (MONITOR.md section 21)
                        info_fin = relin(f, ys[k], hfun, s_r)
                        out["relin_info"][k] = info_fin
                        if p["relin_gate"] > 0 and not info_fin.max() >= p["info_min"]:
                            f.x, f.S = x_prior, s_prior     # undone: as a closed gate
                            kept = False
                    if p["sd_local"] > 0:   # reference only (MONITOR.md section 20)
                        out["sd_local_c"][k] = _local_information_bound(
                            p, f, hfun, x_prior if p["sd_local_at"] == 0 else f.x,
                            s_prior, s_r_used)
                f.s_r = saved
                status = 0 if np.any(kept) else 3
        elif reuse is not None:
            reuse.drop()
        _bound_sd(p, f, floor_mem)                                      # 7
        out["v_gate"][k] = vx
        out["mu_unprojected"][k] = T @ f.x
        f.x, clamped = filters.project(f.x, p["mu_min"], p["mu_max"])  # 8
        if clamped and status == 0:
            status = 1
        sd = f.sd()                                                     # 9
        if hold is not None:        # the rear wheels' hold, updated last in the step
            hold.update(f.x, sd, vx, missed)
        stale.update(omega[k])      # the stale-wheel-speed rule, last as well
        out["mu"][k] = T @ f.x
        out["sd"][k] = T @ sd
        if p["sd_valid"] > 0:   # by the sd, never on a projection bound (ESTIMATOR.md step 9)
            ok = (sd <= p["sd_valid"]) & (f.x > p["mu_min"]) & (f.x < p["mu_max"])
            ok &= f.x - p["mu_min"] >= p["valid_bound_k"] * sd    # the bound margin (0: off)
            out["valid"][k] = (T @ ok.astype(float)).astype(int)
        else:
            out["valid"][k] = 1 if status in (0, 1) else 0
        if hold is not None:        # a held side's rear wheel (rl: side 0, rr: side 1), and
            for w, side in ((0, 0), (1, 1), (2, 0), (3, 1)):   # both wheels of a jumped side
                if (w >= 2 and hold.held[side]) or hold.jheld[side]:
                    out["valid"][k][w] = 0
        if stale.stale:             # a stale wheel speed: no flag (the shared road state
            out["valid"][k] = 0     # carries its error to the other side, MONITOR.md 8)
        if upper is not None:       # the upper evidence, last of step 9; then the monitor
            ok_up = upper.step(lam_up if status in (0, 1) else None)
            if p["sd_valid"] > 0:   # with the sd rule (as the bound margin; C's step 9)
                out["valid"][k] = out["valid"][k] * (T @ ok_up.astype(float)).astype(int)
            upper.monitor(status, out["nu"][k], out["s_zz"][k], out["c_pers"][k],
                          bool(np.any(out["valid"][k])))
            out["evid_up_lam"][k] = 0.0 if lam_up is None or status not in (0, 1) else lam_up
            out["evid_up_L"][k] = upper.L
        out["status"][k] = status
        if evid is not None:
            out["evid_L"][k] = evid.L
    out["t"] = log.col("t")
    return out


PERSISTENT_INPUTS = (1, 2)   # vx, vy: low-passed by the conditioner (monitor.py: persistent)


# Step 4's input derivative: the step of the difference quotients relative to sd_j.
RICHARDSON_REL_STEP = 1e-3


def _input_columns(p, u, mu, sd_u, todo):
    """{j: g_j} for the inputs j in todo: g_j = sd_j dh/du_j at (mu, u), from h alone (not from
    the library's analytic formulas, so the goldens check them): Richardson's extrapolation of
    central differences, R = (4 D(s/2) - D(s)) / 3 with D(s) = (h(u + s e_j) - h(u - s e_j)) /
    (2 s) and s = RICHARDSON_REL_STEP sd_j; the four points of every input in one h_points call.
    Error of g_j = sd_j R. Truncation (Taylor: D(s) = h' + s^2 h^(3) / 6 + s^4 h^(5) / 120 + ...,
    the s^2 terms cancel in R, the s^4 ones leave -s^4 h^(5) / 480): sd_j s^4 |h^(5)| / 480 =
    1e-12 / 480 (sd_j^5 |h^(5)|), with sd_j^5 |h^(5)| the fifth-order change of h over one sd_j,
    at most of the order of |h| (<= ~15 m/s^2, rad/s^2) on the smooth branches: < 1e-13.
    Rounding: each h carries ~2 eps |h| (eps = 2^-53); R weighs the four values by 4/3 / s
    (twice) and 1/3 / (2 s) (twice), 3/s in all, so sd_j R carries ~3 / 1e-3 x 2 eps |h| =
    6.7e-13 |h| <= 1e-11: well inside the 1e-9 at which the library's double build must match
    the reference. Where a slip clamp or a branch of the model (|kappa| = 1, alpha_max, the
    kappa denominator's switch, Dugoff's L = 1) lies within s of u, the quotient straddles it
    and differs from the library's branch derivative; a sample must lie within 1e-3 sd_j of a
    kink for that (the library's double build and this agreed within 4.2e-10 on the goldens'
    logs in issue 21's measurement)."""
    n = len(todo)
    sd = sd_u[todo]
    du = np.zeros((n, u.size))
    du[np.arange(n), todo] = RICHARDSON_REL_STEP * sd
    pts = np.vstack([u + du, u - du, u + du / 2.0, u - du / 2.0])
    hs = h_points(p, pts, np.tile(mu, (4 * n, 1)))
    s = RICHARDSON_REL_STEP * sd[:, None]
    d_full = (hs[:n] - hs[n:2 * n]) / (2.0 * s)
    d_half = (hs[2 * n:3 * n] - hs[3 * n:]) / s
    g = sd[:, None] * (4.0 * d_half - d_full) / 3.0
    return dict(zip(todo, g))


def _step_noise(p, f, T, u, sd_u, persistent=None, reuse=None):
    """Step 4: S_R0 = diag(sqrt(r^2 + (r_model_rel |h(T x-)|)^2)), then Tria([S_R0, g_j]) with
    g_j = sd_j dh/du_j (issue 21: the library's analytic input derivative, rfe_meas_input_jac;
    here an independent derivative, _input_columns). Untouched when both additions are off.
    persistent (a 3-array or None): receives the diagonal of the parts of R that are not
    white from step to step, (r_model_rel |h|)^2 + g_vx^2 + g_vy^2 (monitor.py). reuse (a
    StepNoiseReuse or None): its columns when it holds them, else computed and kept in it (those
    of its inputs; the other inputs' columns are computed every step)."""
    if persistent is not None:
        persistent[:] = 0.0
    if p["r_model_rel"] <= 0 and not np.any(sd_u > 0):
        return f.s_r
    xw = T @ f.x
    r_sd = np.diag(f.s_r)
    model_err = p["r_model_rel"] * np.abs(h_point(p, u, xw))
    s_r = np.diag(np.sqrt(r_sd ** 2 + model_err ** 2))
    held = dict(reuse.cols) if reuse is not None and reuse.cols is not None else {}
    todo = [j for j, sj in enumerate(sd_u) if j not in held and sj > 0]
    if todo:
        fresh = _input_columns(p, u, xw, sd_u, todo)
    jcols = []
    for j in range(len(sd_u)):
        if j in held:
            jcols.append((j, held[j]))
        elif j in todo:
            jcols.append((j, fresh[j]))
    if reuse is not None and reuse.cols is None:
        reuse.cols = [(j, g) for j, g in jcols if reuse.inputs is None or j in reuse.inputs]
    cols = []
    for j, g in jcols:
        cols.append(g)
        if persistent is not None and j in PERSISTENT_INPUTS:
            persistent += g ** 2
    if persistent is not None:
        persistent += model_err ** 2
    return filters.tria(np.hstack([s_r, np.stack(cols, 1)])) if cols else s_r


def _innovation(cen, s_r, y, out, k):
    """nu = y - z_hat and S_zz = Tria([Zc, S_R]) of the predicted points (MODEL.md section 6,
    the quantities the update would use; cen = f.centred(h)), into out["nu"][k],
    out["s_zz"][k]. Returns Zc."""
    z_hat, _, zc = cen
    out["nu"][k] = np.asarray(y, dtype=float) - z_hat
    out["c_pers"][k] += np.einsum("ij,ij->i", zc, zc)     # the state's share: persistent too
    out["s_zz"][k] = filters.tria(np.hstack([zc, s_r]))
    return zc


def _information(f, pts, z_pts, s_r):
    """Step 5: J = P_zx (S S^T)^-1 by two triangular solves, W = S_R \\ J, I_k = sum_r W_rk^2
    (pts: the predicted cubature points, z_pts = h at each)."""
    xc = (pts - f.x[:, None]) / f.sqrt_2n
    zc = (z_pts - z_pts.mean(axis=1)[:, None]) / f.sqrt_2n
    return _information_of(f, xc, zc, s_r)


def _information_of(f, xc, zc, s_r):
    """_information from the centred columns Xc, Zc (f.centred: the 2n points', or the n
    columns of the linear form)."""
    p_zx = zc @ xc.T                                                     # (m, n)
    y = solve_triangular(f.S, p_zx.T, lower=True)                        # S Y = P_zx^T
    j_t = solve_triangular(f.S, y, lower=True, trans="T")                # S^T J^T = Y
    w = solve_triangular(s_r, j_t.T, lower=True)                         # S_R W = J
    return np.einsum("ij,ij->j", w, w)


def info_centre(p, f, pts, z_pts, s_r, y):
    """Step 5's second centre (`info_at` > 0; reference only, MONITOR.md section 16): 1: the
    hypothesis info_mu_h on every side; 2: the cubature point whose prediction is nearest the
    data, |S_R^-1 (y - z_i)| smallest (the first such point on a tie)."""
    if p["info_at"] == 1:
        return np.full(f.n, p["info_mu_h"])
    if p["info_at"] == 2:
        d = solve_triangular(s_r, np.asarray(y, dtype=float)[:, None] - z_pts, lower=True)
        return pts[:, int(np.argmin(np.einsum("ij,ij->j", d, d)))].copy()
    raise ValueError(f"info_at must be 0, 1 or 2, not {p['info_at']}")


def _information_alt(p, f, pts, z_pts, s_r, y, hfun, keep=None):
    """Step 5's information around the second centre c (info_centre): the same statistical
    linearisation over the cubature points moved by c - x (same spread S: the same centred
    points, so only h at the 2n moved points is new). keep (a dict or None): receives c
    ("c") and h at the moved points ("z"), for section 17's test of hypotheses."""
    c = info_centre(p, f, pts, z_pts, s_r, y)
    moved = pts + (c - f.x)[:, None]
    z_alt = hfun(moved)
    if keep is not None:
        keep["c"], keep["z"] = c, np.asarray(z_alt, dtype=float)
    return _information(f, pts, z_alt, s_r)


def _predictive(f, z_pts, s_r):
    """(z_hat, Zc, S_zz) of the predicted points z_pts (the update's quantities)."""
    z_hat = z_pts.mean(axis=1)
    zc = (z_pts - z_hat[:, None]) / f.sqrt_2n
    return z_hat, zc, filters.tria(np.hstack([zc, s_r]))


def log_predictive(f, z_pts, s_r, y):
    """log N(y; z_hat, S_zz S_zz^T) up to the constant -m/2 log(2 pi) (the same for every
    centre): -|S_zz^-1 (y - z_hat)|^2 / 2 - log det S_zz, the likelihood of the measurement
    under mu ~ N(centre, P) through the statistical linearisation at that centre's points."""
    z_hat, _, s_zz = _predictive(f, z_pts, s_r)
    w = solve_triangular(s_zz, np.asarray(y, dtype=float) - z_hat, lower=True)
    return float(-0.5 * (w @ w) - np.sum(np.log(np.abs(np.diag(s_zz)))))


class Hypotheses:
    """Steps 5-6 as a test of hypotheses (`hyp_update`, `hyp_lr_min` with info_at > 0;
    reference only, not in the C library; MONITOR.md section 17). At a step whose gate opens
    only at the second centre c (today's information at x below info_min on every side, at
    c not), lambda = log N(y; z_c, S_zz,c) - log N(y; z_x, S_zz,x) (log_predictive: the same
    spread S and step 4's S_R at x for both) and L <- max(0, L + lambda), a CUSUM: the floor
    at 0 is its reset, and L = 0 as well at every step whose gate opens at x itself (the test
    is only for the steps the estimate cannot judge). One number of memory. With hyp_warmup
    > 0 the first hyp_warmup s of evaluated steps (counted as the monitor counts its warm-up:
    the input conditioner starts from the raw measured vx, vy) give no evidence: L stays 0 and
    a step opened only at c is held (with hyp_lr_min > 0)."""

    def __init__(self, p: dict | None = None):
        self.L = 0.0
        self.seen = 0
        self.warmup = monitor.steps(p["hyp_warmup"], p["dt"]) if p and p["hyp_warmup"] > 0 else 0

    def warming(self) -> bool:
        return self.seen <= self.warmup

    def step(self, at_x, opened, f, z_pts, keep, s_r, y, out, k):
        """Returns the centre c when the gate opened only at c (else None), L updated."""
        self.seen += 1
        if at_x:
            self.L = 0.0
        elif opened and not self.warming():
            lam = log_predictive(f, keep["z"], s_r, y) - log_predictive(f, z_pts, s_r, y)
            self.L = max(0.0, self.L + lam)
            out["hyp"][k], out["hyp_lr"][k] = 1, lam
        elif opened:
            out["hyp"][k] = 1
        out["hyp_L"][k] = self.L
        return keep["c"] if opened and not at_x else None


def _update_at(f, y, hfun, c):
    """Step 6 linearised at the centre c instead of at x- (`hyp_update`, MONITOR.md section
    17): the cubature points moved by c - x-, Z_j = h(X_j + c - x-), z_c their mean, Zc, Xc
    (the spread is today's), S_zz = Tria([Zc, S_R]), K = P_xz S_zz^-T S_zz^-1 and
    J_c = P_zx P^-1 (the statistical slope at c), then the iterated-filter step from c:
    x = x- + K (y - z_c - J_c (x- - c)), S = Tria([Xc - K Zc, K S_R]) (f.s_r: the update's
    noise). At c = x- it is measurement_update's step."""
    c = np.asarray(c, dtype=float)
    pts = f.points()
    xc = (pts - f.x[:, None]) / f.sqrt_2n
    z_hat, zc, s_zz = _predictive(f, np.asarray(hfun(pts + (c - f.x)[:, None]), dtype=float),
                                  f.s_r)
    p_xz = xc @ zc.T
    w_t = solve_triangular(s_zz, p_xz.T, lower=True, check_finite=False)
    k_gain = solve_triangular(s_zz, w_t, lower=True, trans="T", check_finite=False).T
    yy = solve_triangular(f.S, p_xz, lower=True)                         # S Y = P_xz
    j_c = solve_triangular(f.S, yy, lower=True, trans="T").T             # J_c = P_zx P^-1
    nu = np.asarray(y, dtype=float) - z_hat - j_c @ (f.x - c)
    f.x = f.x + k_gain @ nu
    f.S = filters.tria(np.hstack([xc - k_gain @ zc, k_gain @ f.s_r]))
    return k_gain


def _one_sided_update(p, f, T, u, sd_u, y, hfun, s_r_base):
    """Step 6 with `lower_bound_delta` = Delta > 0 (reference only, not in the C library;
    MONITOR.md section 13). At mild slip a measurement bounds mu from below only: the force is
    the slip stiffness's for any mu above the utilisation, so it may raise a side's mu but
    gives no ground to lower it. The update's gain K is formed as in
    filters.SCKF.measurement_update (f.s_r: the update's noise). A side j whose move
    (K nu)_j is downward keeps it only when the measurement would still carry information
    about mu_j at the upper alternative x_a = min(x- + Delta, mu_max) (every side):
    I_j^a = J_j^T Ra^-1 J_j >= info_min, J_j = dh/dmu_j at x_a (central difference of step
    UPPER_SLOPE_STEP), Ra = step 4's noise there (_step_noise from s_r_base: a tyre in its
    linear range passes more of the slip noise). Otherwise its gain row is zero: a Schmidt
    "consider" update, its mean and variance stay, the other sides keep their optimal gain
    rows and the covariance is the Joseph form's, Tria([Xc - K Zc, K S_R]) with that K. With
    nothing censored the operations are measurement_update's, bit for bit. Returns the (n,)
    bool of the sides kept (updated) and the (n,) I^a (NaN where not evaluated)."""
    info_a = np.full(f.n, np.nan)

    def censor(down):
        info_a[:] = _information_upper(p, f, T, u, sd_u, s_r_base)
        return down & (info_a < p["info_min"])
    return _censored_update(f, y, hfun, censor), info_a


def _censored_update(f, y, hfun, censor):
    """Step 6 with some sides' gain rows zeroed (the censoring options): the gain K as in
    filters.SCKF.measurement_update (f.s_r: the update's noise); censor(down) is called with the
    (n,) bool of the sides whose move (K nu)_j is downward, only when there is one, and returns
    the sides to censor: their gain rows are zero, so their means and variances stay, the others
    keep their optimal rows (Schmidt's consider update), and the covariance is the Joseph
    form's, Tria([Xc - K Zc, K S_R]) with that K. With nothing censored the operations are
    measurement_update's, bit for bit. Returns the (n,) bool of the sides kept."""
    z_hat, xc, zc = f.centred(hfun)
    s_zz = filters.tria(np.hstack([zc, f.s_r]))
    w_t = solve_triangular(s_zz, (xc @ zc.T).T, lower=True, check_finite=False)
    k_gain = solve_triangular(s_zz, w_t, lower=True, trans="T", check_finite=False).T
    nu = np.asarray(y, dtype=float) - z_hat
    kept = np.ones(f.n, dtype=bool)
    down = (k_gain @ nu) < 0.0
    if np.any(down):
        kept = ~np.asarray(censor(down), dtype=bool)
        k_gain = k_gain * kept[:, None]
    f.x = f.x + k_gain @ nu
    f.S = filters.tria(np.hstack([xc - k_gain @ zc, k_gain @ f.s_r]))
    return kept


class Evidence:
    """Step 6's accumulated-evidence censoring (`evid_delta` > 0; reference only, not in the C
    library; MONITOR.md sections 13-14). Per side j the evidence against the upper alternative
    x- + evid_delta e_j: at every update (a step that passes the gate), before the decision,
    L_j <- rho L_j + Lambda_j, rho = exp(-1 / evid_n), Lambda_j = (q(x_j^a) - q(x-)) / 2 with
    q(x) = (y - h(x))^T R(x)^-1 (y - h(x)) at the point x (h at the means, R step 4's noise
    evaluated at x: a tyre in its linear range passes more of the slip noise) and
    x_j^a = x- with its j-th entry min(x-_j + evid_delta, mu_max). A side's downward move is
    censored (_censored_update) while L_j < evid_l_min, once the side is armed: it has had
    evid_free updates on its own information (I_j >= info_min; counted at every update, the
    step's own included) and, with evid_cap > 0, while x-_j + evid_delta <= mu_max (where
    mu_max clips the alternative it lies less than evid_delta above; at the bound it is the
    estimate, Lambda_j = 0, L only decays and the side could never come down).
    L starts at evid_l0. The per-side memory is L (2 numbers) and, with
    evid_free > 0, the update counts (2 small integers)."""

    def __init__(self, p: dict, n: int):
        self.L = np.full(n, float(p["evid_l0"]))
        self.n_own = np.zeros(n, dtype=int)
        self.rho = float(np.exp(-1.0 / p["evid_n"]))

    def update(self, p, f, T, u, sd_u, y, hfun, s_r, s_r_base, own):
        """One update step: L and the counts, then step 6 (f.s_r: the update's noise; s_r: step
        4's at x-, s_r_base: its base for step 4 elsewhere). Returns the sides kept."""
        self.L = self.rho * self.L + upper_evidence(p, f.x, T, u, sd_u, y, s_r, s_r_base)
        self.n_own += np.asarray(own, dtype=int)
        armed = self.n_own >= p["evid_free"]
        if p["evid_cap"] > 0:       # mu_max clips the alternative (at the bound Lambda = 0)
            armed &= f.x + p["evid_delta"] <= p["mu_max"]
        return _censored_update(f, y, hfun,
                                lambda down: down & armed & (self.L < p["evid_l_min"]))


class UpperEvidence:
    """Step 9's upper evidence (`evid_up_delta` > 0; docs/ESTIMATOR.md step 9, MONITOR.md
    sections 10 and 22): a valid-flag rule, the filter untouched. Per state j, at every step
    that updated (status 0, 1): L_j <- rho L_j + Lambda_j, rho = exp(-1 / evid_up_n), Lambda_j
    upper_evidence's at the prior mean x- with step 4's noise at each point; other steps leave
    L. State j's wheels are valid only while L_j >= evid_up_l_min. After the step, while the
    monitor (in the loop, fed as monitor.apply feeds it) reports the mismatch (status 4: it is
    fired and the step updated, or held with a flag 1 after this rule), L = 0: the update was
    on data that contradict the model, so nothing before counts. L starts at 0."""

    def __init__(self, p: dict, n: int):
        self.p = p
        self.L = np.zeros(n)
        self.rho = float(np.exp(-1.0 / p["evid_up_n"]))
        self.mon = monitor.Monitor(p, p["dt"])
        self.enable = self.mon.p["mon_enable"] > 0

    def step(self, lam) -> np.ndarray:
        """L after this step's update (lam: its Lambda, None on a step without an update);
        returns the states whose flags may stay (L >= evid_up_l_min)."""
        if lam is not None:
            self.L = self.rho * self.L + lam
        return self.L >= self.p["evid_up_l_min"]

    def monitor(self, status, nu, s_zz, c_pers, any_valid) -> None:
        """The monitor's step on this step's innovation (monitor.apply's), then the reset."""
        if status != 2 and np.all(np.isfinite(nu)):
            self.mon.step(nu, s_zz, c_pers)
        if self.enable and self.mon.fired and (status in (0, 1)
                                               or (status == 3 and any_valid)):
            self.L = np.zeros_like(self.L)


def upper_evidence(p, x, T, u, sd_u, y, s_r, s_r_base, delta=None):
    """(n,) Lambda_j = (q(x^a_j) - q(x)) / 2, the evidence of one measurement y against side j's
    friction delta (default evid_delta) higher (Evidence, UpperEvidence). s_r: step 4's noise
    factor at x; s_r_base: the base factor step 4 starts from (the filter's constant noise)."""
    delta = p["evid_delta"] if delta is None else delta
    def q(xx, s):
        w = solve_triangular(s, np.asarray(y, dtype=float) - h_point(p, u, T @ xx), lower=True)
        return float(w @ w)
    q0 = q(x, s_r)
    lam = np.empty(x.size)
    for j in range(x.size):
        xa = np.array(x, dtype=float, copy=True)
        xa[j] = min(xa[j] + delta, p["mu_max"])
        s_a = _step_noise(p, SimpleNamespace(x=xa, s_r=s_r_base), T, u, sd_u)
        lam[j] = 0.5 * (q(xa, s_a) - q0)
    return lam


UPPER_SLOPE_STEP = 1e-3   # central-difference step of dh/dmu at the upper alternative


def _information_upper(p, f, T, u, sd_u, s_r_base):
    """I_j^a = J_j^T Ra^-1 J_j per side at x_a = min(x- + lower_bound_delta, mu_max) (see
    _one_sided_update): the Fisher information the measurement would carry about mu_j if mu
    were that much higher, with step 4's noise there."""
    n, d = f.n, UPPER_SLOPE_STEP
    xa = np.minimum(f.x + p["lower_bound_delta"], p["mu_max"])
    s_a = _step_noise(p, SimpleNamespace(x=xa, s_r=s_r_base), T, u, sd_u)
    xs = np.vstack([xa + d * np.eye(n), xa - d * np.eye(n)])             # (2n, n)
    hs = h_points(p, np.tile(u, (2 * n, 1)), xs @ T.T)                   # (2n, 3)
    jac = (hs[:n] - hs[n:]).T / (2.0 * d)                                # (3, n)
    w = solve_triangular(s_a, jac, lower=True)
    return np.einsum("ij,ij->j", w, w)


def _relin_mode(p):
    """Step 6 re-linearised (MONITOR.md section 21; reference only): None when off (both keys
    0), else relin(f, y, hfun, s_r) -> the final linearisation's information (n,), f updated
    (f.s_r: the update's noise; s_r: step 4's, the gate's)."""
    n_steps, n_iter = int(p["relin_steps"]), int(p["relin_iter"])
    if n_steps != p["relin_steps"] or n_iter != p["relin_iter"] or n_steps < 0 or n_iter < 0:
        raise ValueError("relin_steps and relin_iter must be integers >= 0")
    if n_steps > 0 and n_iter > 0:
        raise ValueError("relin_steps and relin_iter are two designs: set one of them")
    if n_steps > 0:
        return lambda f, y, hfun, s_r: recursive_update(f, y, hfun, n_steps, s_r)
    if n_iter > 0:
        return lambda f, y, hfun, s_r: iterated_posterior_update(f, y, hfun, n_iter, s_r)
    return None


def recursive_update(f, y, hfun, n_steps: int, s_r_gate):
    """The recursive update filter (Zanetti, JGCD 2012), the equal split: n_steps sub-updates,
    each filters.SCKF.measurement_update with the noise factor sqrt(n_steps) f.s_r (R n_steps)
    and the same y, the cubature points regenerated from the current sub-posterior before each.
    For a linear h the n_steps updates are one update with R; n_steps = 1 is that call with
    f.s_r (times 1.0: the same numbers). Returns the information of the last sub-step's
    linearisation (its points, its sub-prior S) with s_r_gate, the full noise (step 5's form)."""
    s_r = f.s_r
    f.s_r = np.sqrt(float(n_steps)) * s_r
    try:
        for i in range(n_steps):
            if i == n_steps - 1:
                _, xc, zc = f.centred(hfun)
                info = _information_of(f, xc, zc, s_r_gate)
            f.measurement_update(y, hfun)
    finally:
        f.s_r = s_r
    return info


def iterated_posterior_update(f, y, hfun, n_iter: int, s_r_gate):
    """The iterated posterior linearisation filter (Garcia-Fernandez, Svensson, Morelande,
    Saerkkae, IEEE TSP 2015) in square-root form. Iteration 1 is
    filters.SCKF.measurement_update (today's). Iteration j >= 2: the statistical linear
    regression of h over the cubature points of the current posterior (x_j-1, S_j-1),
    A = P_zx P^-1, Omega^1/2 = Zc - A Xc (Omega = P_zz - A P A^T exactly, as A P = P_zx),
    applied to the prior (x-, S-): S_zz = Tria([A S-, Omega^1/2, S_R]), K = S- (A S-)^T
    S_zz^-T S_zz^-1, x = x- + K (y - z - A (x- - x_j-1)), S = Tria([S- - K A S-, K Omega^1/2,
    K S_R]) (f.s_r: the update's noise). For a linear h Omega = 0 and every iteration is the
    first's posterior. Returns the information of the last linearisation (A, or the prior's
    slope when n_iter = 1) with s_r_gate, the full noise (step 5's form)."""
    x0, s0 = f.x.copy(), f.S.copy()
    y = np.asarray(y, dtype=float)
    _, xc, zc = f.centred(hfun)
    info = _information_of(f, xc, zc, s_r_gate)
    f.measurement_update(y, hfun)
    for _ in range(n_iter - 1):
        z_hat, xc, zc = f.centred(hfun)
        yy = solve_triangular(f.S, xc @ zc.T, lower=True)              # S Y = P_xz
        a = solve_triangular(f.S, yy, lower=True, trans="T").T         # A = P_zx P^-1
        om = zc - a @ xc                                               # Omega^1/2
        a_s0 = a @ s0
        s_zz = filters.tria(np.hstack([a_s0, om, f.s_r]))
        w_t = solve_triangular(s_zz, a_s0 @ s0.T, lower=True, check_finite=False)
        k_gain = solve_triangular(s_zz, w_t, lower=True, trans="T", check_finite=False).T
        x_new = x0 + k_gain @ (y - z_hat - a @ (x0 - f.x))
        f.S = filters.tria(np.hstack([s0 - k_gain @ a_s0, k_gain @ om, k_gain @ f.s_r]))
        f.x = x_new
        w = solve_triangular(s_r_gate, a, lower=True)                  # S_R W = A
        info = np.einsum("ij,ij->j", w, w)
    return info


def _local_information_bound(p, f, hfun, x_at, s_prior, s_r) -> float:
    """Step 6's local-information bound (`sd_local` > 0; reference only, MONITOR.md section
    20): W = S_R^-1 J, J = dh/dx at x_at (central differences of step sd_local per state),
    P_loc = (P-^-1 + W^T W)^-1; S (after the update) is scaled by one factor c = max(1,
    max_k sqrt(P_loc,kk / P+_kk)), so that the update claims no more information about any
    state than the data carry at x_at (the cubature spread's secant can claim far more).
    Returns c."""
    n = len(f.x)
    eps = p["sd_local"]
    pts = np.repeat(np.asarray(x_at, dtype=float)[:, None], 2 * n, axis=1)
    for j in range(n):
        pts[j, 2 * j] += eps
        pts[j, 2 * j + 1] -= eps
    z = hfun(pts)                                                       # (m, 2n)
    jac = (z[:, 0::2] - z[:, 1::2]) / (2.0 * eps)                       # (m, n)
    w = solve_triangular(s_r, jac, lower=True)
    p_prior = s_prior @ s_prior.T
    p_loc = np.linalg.inv(np.linalg.inv(p_prior) + w.T @ w)
    p_post = f.S @ f.S.T
    c = float(np.sqrt(np.max(np.diag(p_loc) / np.diag(p_post))))
    if c > 1.0:
        f.S = f.S * c
        return c
    return 1.0


class FloorMemory:
    """Step 7's floor level, reference only (MONITOR.md section 19): per side max(x_k,
    sd_floor_ref, the largest x_k of the last sd_floor_hold s), so that a low or a dropped
    mean does not shrink its own floor. The window counts steps (round(sd_floor_hold / dt),
    the current one included); a gap's time update only reads it."""

    def __init__(self, p: dict, n: int):
        self.ref = p["sd_floor_ref"]
        m = int(round(p["sd_floor_hold"] / p["dt"])) if p["sd_floor_hold"] > 0 else 0
        self.past = np.full((m, n), -np.inf) if m > 0 else None
        self.i = 0

    def level(self, x: np.ndarray, record: bool) -> np.ndarray:
        lev = np.maximum(x, self.ref) if self.ref > 0 else np.array(x, dtype=float)
        if self.past is not None:
            if record:
                self.past[self.i] = x
                self.i = (self.i + 1) % self.past.shape[0]
            lev = np.maximum(lev, self.past.max(axis=0))
        return lev


def _bound_sd(p, f, memory: FloorMemory | None = None, record: bool = True):
    """Step 7: one factor c for the whole S: cap at sd_max, else floor at sd_floor_rel mu
    (limited to sd_max / max sd). memory (None: today's floor): mu replaced by its level."""
    sd = f.sd()
    c = 1.0
    if p["sd_max"] > 0 and np.any(sd > p["sd_max"]):
        c = float(np.min(p["sd_max"] / sd))
    elif p["sd_floor_rel"] > 0:
        lev = f.x if memory is None else memory.level(f.x, record)
        floor = p["sd_floor_rel"] * np.maximum(lev, 0.0)
        if np.any(sd < floor):
            c = float(np.max(floor / sd))
            if p["sd_max"] > 0:  # the floor never lifts another wheel above the cap
                c = min(c, float(p["sd_max"] / np.max(sd)))
    if c != 1.0:
        f.S = f.S * c
