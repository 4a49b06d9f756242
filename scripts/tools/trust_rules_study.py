"""Issue 17: candidate rules for the Magic Formula logs that miss the trust invariant
(docs/MONITOR.md section 8), measured with the float64 reference over every bundled log.

Usage (from the repository root):

    .venv/bin/python scripts/tools/trust_rules_study.py [--scenarios scenarios]
        [--cache build/trust_rules] [--jobs 2] [--soak build/soak/drive_300s.csv
        [--soak-estimate ESTIMATE.csv ...]] [--hold-fired] [--only-soak-rules]
        [--upper-noise DELTA [--logs NAME ... | all]]

Runs the reference (scripts/reference/trusted.py, the default preset with its three trust rules
switched off, then monitor.py, which equal the C double build to 1e-9) once per log (cached as .npz in --cache; the 72 logs take
about 10 min of CPU) and evaluates rules on top of it, each as the trust invariant's figures
(scripts/tools/trust_invariant.py: settled samples, pooled over the wheels) before and after:

- valid-flag rules, applied to the recorded run (the filter is untouched, like step 9's holds):
  * `updates`: a side is valid only while the exponentially weighted share (time constant
    tau) of steps that updated it with its own information >= info_min is >= a_min (for the
    sporadic updates of brake_in_turn.mf and ramp_steer_high_mu.mf);
  * `stale`: a wheel speed exactly equal to its previous sample while the median of the other
    three wheel speeds has moved by more than delta (rad/s) since it last changed is stale:
    both sides are not valid (for the frozen wheel speed); the reference's own rule
    (trusted.StaleOmega, the library's `stale_omega`, docs/MONITOR.md section 9);
- an input rule that changes the filter's input, so it reruns the reference on the logs where
  it acts (on every other log the run is the recorded one, bit for bit):
  * `yaw`: a yaw-rate sample that differs from the previous accepted one, advanced by the
    measured yaw acceleration over dt (trapezoidal), by more than thr (rad/s) is replaced by
    that prediction (for the yaw-rate spikes); the reference's own check (trusted.YawCheck,
    the library's `yaw_check`), rerun with it on.

- the soak drive's rules (docs/MONITOR.md section 10; --soak and --soak-estimate apply them to
  the soak drive's reference run and to mu_replay estimate logs of it):
  * `consider`: the sd of the error a bias of the conditioned vx, vy leaves in the mean,
    propagated with the filter's linearised gain (a Schmidt consider term);
  * `bound margin`: valid only k sd or more above mu_min (the library's `valid_bound_k`,
    docs/MONITOR.md section 11; the base run keeps it off, as the two rules above);
  * `upper evidence`: the updates' evidence against mu + DELTA_UP (rule_evidence);
- two experiments that change the update in the loop through trusted.run's adapt hook
  (trusted.py untouched): --hold-fired (no update while the monitor is fired, every log
  rerun into CACHE/hold_fired) and UpperGate (the information gate at mu + delta too, run
  per log by hand: reference_run(path, upper_gate=0.25)); and UpperNoise (--upper-noise:
  step 4's noise at mu + delta too, MONITOR.md section 12).

Per rule it prints the logs meeting the invariant (the 72 logs), those gained and lost, issue
17's no-loss rule (on the logs meeting the invariant before, the largest fall of the excited-
valid share; at most 5 points allowed) and the share of steps with the mismatch status on the
clean Magic Formula logs (false alarms; at most 1 %), then the five target logs' figures.
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from types import SimpleNamespace

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # scripts: reference
from reference import logs, monitor, params, trusted  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))        # tools: the monitor study
from monitor_results import settled  # noqa: E402  (mu_replay's settled samples, metrics.c)

WHEELS = ("fl", "fr", "rl", "rr")
SIDE_OF_WHEEL = (0, 1, 0, 1)           # structure sides: fl, rl on the left
EXCITE_UTIL, CONSISTENCY_K = 0.5, 2.0                                 # mu_replay's
CONS_MIN, RMSE_MAX, WORST_MAX = 0.9, 0.10, 0.25                       # issue 17's targets
NO_LOSS_MAX, FALSE_ALARM_MAX = 0.05, 0.01                             # issue 17's rules
TARGETS = ("brake_in_turn.mf", "ramp_steer_high_mu.mf",
           "faults/freeze_omega_fl.hard_brake_low_mu.mf",
           "faults/freeze_omega_fl.sine_steer_low_mu.mf",
           "faults/spike_yaw_rate.sine_steer_low_mu.mf")
DELTA_UP = 0.25           # the upper alternative: issue 17's worst error while valid
EVIDENCE_N, EVIDENCE_L, BOUND_K = 100, 0.25, 3.0   # the recommended pair's parameters
UPDATED_STATUS = (0, 1)   # the filter's update (status 4 only replaces them in the output)
KEEP = ("t", "mu", "sd", "valid", "status", "info", "v_gate", "mu_unprojected", "D", "M",
        "nu", "s_zz", "c_pers")


# ---------------------------------------------------------------- figures
def figures(mu, sd, valid, truth, util, s) -> dict:
    """The trust invariant's figures of one run (trust_invariant.figures, from the samples)."""
    err = np.abs(mu - truth)
    sv = s & valid
    f = {"valid": sv.sum() / max(s.sum(), 1), "n_valid": int(sv.sum()),
         "rmse": None, "cons": None, "worst": None, "exc": None}
    if sv.any():
        f["rmse"] = float(np.sqrt(np.mean(err[sv] ** 2)))
        f["cons"] = float(np.mean(err[sv] <= CONSISTENCY_K * sd[sv]))
        f["worst"] = float(err[sv].max())
    if util is not None:
        exc = s & (util >= EXCITE_UTIL)
        if exc.any():
            f["exc"] = float((exc & valid).sum() / exc.sum())
    f["meets"] = f["n_valid"] == 0 or (f["cons"] >= CONS_MIN and f["rmse"] <= RMSE_MAX
                                       and f["worst"] <= WORST_MAX)
    return f


# ---------------------------------------------------------------- rules
def side_rule_to_wheels(side_ok: np.ndarray) -> np.ndarray:
    """(N, 2) per side -> (N, 4) per wheel."""
    return side_ok[:, SIDE_OF_WHEEL]


def rule_updates(status, info, tau_s, a_min, info_min, dt) -> np.ndarray:
    """(N, 2) allowed: the exponentially weighted share (lambda = dt / (tau + dt), over the
    steps that evaluate the model, status != 2) of the steps that updated side j (status 0, 1)
    with its own information >= info_min is >= a_min."""
    lam = dt / (tau_s + dt)
    ind = np.isin(status, (0, 1))[:, None] & (info >= info_min)
    a = np.zeros(2)
    ok = np.zeros((len(status), 2), dtype=bool)
    for k in range(len(status)):
        if status[k] != 2:
            a += lam * (ind[k] - a)
        ok[k] = a >= a_min
    return ok


def rule_stale(omega, delta) -> np.ndarray:
    """(N,) allowed: no wheel speed is stale (the reference's trusted.StaleOmega, the library's
    rule). Wheel i is stale at sample k when omega_i,k equals omega_i,k-1 exactly, is not 0 (a
    wheel at rest or locked reads 0: a state of the car, not of the sensor) and the median of
    the other three wheel speeds has moved by more than delta since omega_i last changed (a
    steady cruise or a noise-free log repeat values too, but with the others as still as it)."""
    rule = trusted.StaleOmega(delta)
    ok = np.ones(len(omega), dtype=bool)
    for k in range(len(omega)):
        rule.update(omega[k])
        ok[k] = not rule.stale
    return ok


def yaw_substitute(t, r, r_dot, thr):
    """The yaw rate as the reference's trusted.YawCheck (the library's check) accepts it, at the
    log's nominal period (the median step of t): r'_k = r_k unless it differs from
    r'_k-1 + dt (r_dot_k + r_dot_k-1) / 2 by more than thr, then that prediction (and the next
    sample is accepted as it is). Returns (r', number of samples replaced)."""
    check = trusted.YawCheck(thr, float(np.median(np.diff(t))))
    out = np.array([check.step(float(r[k]), float(r_dot[k])) for k in range(len(r))])
    return out, int(np.count_nonzero(out != np.asarray(r, dtype=float)))


# ---------------------------------------------------------------- the soak drive's rules
SD_INPUTS = ("sd_in_delta", "sd_in_vx", "sd_in_vy", "sd_in_yaw_rate", None, None,
             "sd_in_omega", "sd_in_omega", "sd_in_omega", "sd_in_omega")   # trusted.run's order


def conditioned_inputs(log, p, vx_gate=None) -> np.ndarray:
    """(N, 10) the inputs u = (delta, vx, vy, r, ax, ay, omega_fl..rr) as the estimator uses
    them: vx, vy through the conditioner (ESTIMATOR.md step 1; vx_gate, the run's own
    conditioned vx, replaces the recomputed one where given: it holds the gaps' restarts)."""
    cond = trusted.Conditioner(p["tau_v"], p["dt"])
    cols = [log.col(c) for c in ("delta", "vx", "vy", "yaw_rate", "ax", "ay")]
    u = np.column_stack(cols + [log.omega()])
    for k in range(len(u)):
        u[k, 1], u[k, 2] = cond.step(u[k, 1], u[k, 2], u[k, 4], u[k, 5], u[k, 3])
    if vx_gate is not None:
        u[:, 1] = vx_gate
    return u


def step_sensitivities(p, u, x_prior, sd_prior):
    """Per step k (rows of u) and side j, at the prior mean x_prior (N, 2) with sd sd_prior:
    the measurement's slopes by mu_j up and down (h(x + d e_j) - h(x), h(x) - h(x - d e_j),
    d = sd_prior_j: the cubature spread), the step's noise R = diag(r^2 + (r_model_rel h)^2) +
    sum_j g_j g_j^T (step 4, every input with sd_j > 0) and g_vx = dh/dvx. Returns
    (up (N, 2, 3), down (N, 2, 3), R (N, 3, 3), g_vx (N, 3), g_vy (N, 3))."""
    T = trusted.WHEELS_OF_SIDES
    n = len(u)
    d = np.maximum(sd_prior, 1e-3)
    xs = [x_prior]
    for j in range(2):
        for s in (1.0, -1.0):
            x = x_prior.copy()
            x[:, j] += s * d[:, j]
            xs.append(x)
    sd_u = np.array([p[k] if k else 0.0 for k in SD_INPUTS])
    steps = []
    for j in np.flatnonzero(sd_u > 0):
        for s in (1.0, -1.0):
            uu = u.copy()
            uu[:, j] += s * 1e-2 * sd_u[j]
            steps.append((j, s, uu))
    us = np.vstack([u] * len(xs) + [st[2] for st in steps])
    mus = np.vstack([x @ T.T for x in xs] + [x_prior @ T.T] * len(steps))
    hs = trusted.h_points(p, us, mus).reshape(-1, n, 3)
    h0 = hs[0]
    up = np.stack([hs[1] - h0, hs[3] - h0], 1)
    down = np.stack([h0 - hs[2], h0 - hs[4]], 1)
    r2 = np.array([p["r_ax"], p["r_ay"], p["r_yaw_acc"]]) ** 2 + (p["r_model_rel"] * h0) ** 2
    R = np.zeros((n, 3, 3))
    R[:, [0, 1, 2], [0, 1, 2]] = r2
    g = {}
    for i in range(0, len(steps), 2):
        j = steps[i][0]
        gj = (hs[len(xs) + i] - hs[len(xs) + i + 1]) / (2e-2 * sd_u[j])   # dh/du_j
        g[j] = gj
        R += sd_u[j] ** 2 * np.einsum("ni,nk->nik", gj, gj)
    return up, down, R, g.get(1, np.zeros((n, 3))), g.get(2, np.zeros((n, 3)))


def rule_consider(p, u, mu, sd, updated, sigma, tau_b=None):
    """The estimate's error from a bias of the conditioned speeds (a Schmidt 'consider' term):
    the filter takes the conditioned vx, vy as carrying white noise (sd_in_vx, sd_in_vy, one
    column of step 4 per step), but their error is low-passed (tau_v) and, at low speed and
    mild slip, one such error moves mu by far more than the sd the filter claims. Per side,
    the error e = sum_b F_b b that a bias b of vx (b = 1) and vy (b = 2) leaves in the mean is
    propagated with the filter's own linearised gain at every update (status 0, 1):
    K = P J^T (J P J^T + R)^-1 at the prior mean and sd (P = diag(sd^2 + q_mu^2) + q_common^2
    11^T, J = dh/dmu by the cubature spread, R step 4's noise), then
        C_b <- a (I - K J) C_b - K g_b sigma_b^2     (the covariance of e with the bias now)
        V   <- A V A^T - A a C_b (K g_b)^T - (A a C_b (K g_b)^T)^T + K g_b g_b^T K^T sigma_b^2,
    A = I - K J,
    with a = exp(-dt / tau_b) per step (tau_b None: a = 1, a bias that persists over the
    estimate's memory); a held step only decorrelates (C_b <- a C_b). Returns (sd_eff (N, 4),
    allowed (N, 4)): sd_eff = sqrt(sd^2 + diag V) per wheel, allowed where sd_eff <= sd_valid.
    sigma: (sigma_vx, sigma_vy), m/s."""
    T = trusted.WHEELS_OF_SIDES
    n = len(u)
    x = mu[:, [0, 1]]
    s = sd[:, [0, 1]]
    xp = np.vstack([x[:1], x[:-1]])
    sp = np.sqrt(np.vstack([s[:1], s[:-1]]) ** 2 + p["q_mu"] ** 2 + p["q_common"] ** 2)
    up, down, R, gvx, gvy = step_sensitivities(p, u, xp, sp)
    J = np.transpose((up + down) / (2.0 * np.maximum(sp, 1e-3))[:, :, None], (0, 2, 1))  # (N,3,2)
    a = 1.0 if tau_b is None else float(np.exp(-p["dt"] / tau_b))
    V = np.zeros((2, 2))
    C = [np.zeros(2), np.zeros(2)]
    var = np.zeros((n, 2))
    qc = p["q_common"] ** 2
    for k in range(n):
        if updated[k]:
            P = np.diag(sp[k] ** 2 - qc) + qc
            Jk = J[k]
            S = Jk @ P @ Jk.T + R[k]
            K = np.linalg.solve(S, Jk @ P).T           # (2, 3) = P J^T S^-1
            A = np.eye(2) - K @ Jk
            V = A @ V @ A.T
            for b, (g, sg) in enumerate(((gvx[k], sigma[0]), (gvy[k], sigma[1]))):
                kg = K @ g
                cross = np.outer(A @ (a * C[b]), kg)
                V = V - cross - cross.T + np.outer(kg, kg) * sg ** 2
                C[b] = A @ (a * C[b]) - kg * sg ** 2
        else:
            C = [a * c for c in C]
        var[k] = np.diag(V)
    sd_eff = np.sqrt(sd ** 2 + (var @ T.T))
    return sd_eff, sd_eff <= p["sd_valid"]


def point_fit(p, u, x, y) -> np.ndarray:
    """(N,) q = (y - h(x))^T R(x)^-1 (y - h(x)): the normalised squared residual of the
    measurement y (N, 3) at the friction x (N, 2, per side), with step 4's noise R evaluated
    at x (its own errors-in-variables columns: a tyre in its linear range passes more of the
    slip noise than a saturated one)."""
    T = trusted.WHEELS_OF_SIDES
    n = len(u)
    sd_u = np.array([p[k] if k else 0.0 for k in SD_INPUTS])
    js = np.flatnonzero(sd_u > 0)
    us = [u]
    for j in js:
        for s in (1.0, -1.0):
            uu = u.copy()
            uu[:, j] += s * 1e-2 * sd_u[j]
            us.append(uu)
    mus = np.tile(x @ T.T, (len(us), 1))
    hs = trusted.h_points(p, np.vstack(us), mus).reshape(-1, n, 3)
    h0 = hs[0]
    R = np.zeros((n, 3, 3))
    R[:, [0, 1, 2], [0, 1, 2]] = (np.array([p["r_ax"], p["r_ay"], p["r_yaw_acc"]]) ** 2
                                  + (p["r_model_rel"] * h0) ** 2)
    for i, j in enumerate(js):
        g = sd_u[j] * (hs[1 + 2 * i] - hs[2 + 2 * i]) / (2e-2 * sd_u[j])
        R += np.einsum("ni,nk->nik", g, g)
    if y is None:
        return R
    nu = y - h0
    return np.einsum("ni,ni->n", nu, np.linalg.solve(R, nu[:, :, None])[:, :, 0])


def point_noise(p, u, x) -> np.ndarray:
    """(N, 3, 3) step 4's R at the friction x (N, 2): point_fit's."""
    return point_fit(p, u, x, None)


def upper_evidence(p, u, y, mu, updated, delta):
    """(N, 2) per side: Lambda_k = (q(x + delta e_j) - q(x)) / 2 at the prior mean x (the
    previous step's estimate) of every update step (0 elsewhere): how much worse the
    measurement fits a friction delta higher on side j than the estimate."""
    x = mu[:, [0, 1]]
    xp = np.vstack([x[:1], x[:-1]])
    out = np.zeros((len(u), 2))
    k = np.flatnonzero(updated)
    if k.size == 0:
        return out
    q0 = point_fit(p, u[k], xp[k], y[k])
    for j in range(2):
        xa = xp[k].copy()
        xa[:, j] = np.minimum(xa[:, j] + delta, p["mu_max"])
        out[k, j] = 0.5 * (point_fit(p, u[k], xa, y[k]) - q0)
    return out


def rule_evidence(lam, updated, n_mem, l_min, mu=None, move=None, reset=None, ds=None,
                  d_mem=None):
    """(N, 2) allowed: L_j >= l_min, L_j <- rho L_j + Lambda_j at every update, unchanged on
    the other steps; rho = exp(-1 / n_mem) (a memory of about n_mem updates), times
    exp(-|x_j,k - x_j,k-1| / move) with mu and move given (evidence about the upper
    alternative of an estimate the update has moved away from fades with the move); L = 0 at
    the steps where reset (N,) is set (the monitor fired: the filter updated on data that
    contradict its model, so nothing before counts); with ds (N,) the distance travelled in
    each step and d_mem (m), L_j also fades by exp(-ds / d_mem) at every step (the road under
    a held estimate may change: evidence is about the road it was gathered on)."""
    L = np.zeros(2)
    ok = np.zeros(lam.shape, dtype=bool)
    x = None if mu is None else mu[:, [0, 1]]
    fade = None if d_mem is None else np.exp(-np.asarray(ds) / d_mem)
    for k in range(len(lam)):
        if fade is not None:
            L = L * fade[k]
        if reset is not None and reset[k]:
            L = np.zeros(2)
        elif updated[k]:
            rho = np.full(2, np.exp(-1.0 / n_mem))
            if move is not None and k > 0:
                rho = rho * np.exp(-np.abs(x[k] - x[k - 1]) / move)
            L = rho * L + lam[k]
        ok[k] = L >= l_min
    return ok


def rule_bound_margin(mu, sd, mu_min, k) -> np.ndarray:
    """(N, 4) allowed: the estimate lies at least k sd above mu_min (step 9 excludes the bound
    itself; a Gaussian claim of mean and sd whose lower tail the projection cut off says
    nothing about the error either)."""
    return mu - mu_min >= k * sd


# ---------------------------------------------------------------- runs
def bundled(scen: Path) -> list[str]:
    return [p.relative_to(scen).as_posix()[:-4]
            for p in sorted(scen.glob("*.csv")) + sorted((scen / "faults").glob("*.csv"))]


def hold_while_fired(p: dict):
    """trusted.run's adapt hook for the experiment 'no measurement update while the monitor
    is fired' (MONITOR.md §10): the monitor runs in the loop on each evaluated step's
    innovation (as monitor.apply does afterwards, so the fired state is the reported one) and,
    while fired, the update takes S_R x 1e4 (R x 1e8: the update leaves the state as it is, to
    ~1e-8 of the gain; the gate and the recorded S_zz keep step 4's S_R)."""
    mon = monitor.Monitor(p, p["dt"])

    def adapt(k, nu, s_zz, zc, s_r, c_pers=None):
        mon.step(nu, s_zz, c_pers)
        return s_r * 1e4 if (mon.fired and mon.p["mon_enable"] > 0) else s_r
    return adapt


class UpperGate:
    """The experiment 'the information gate at the upper alternative too' (MONITOR.md §10): an
    update also needs max_j I_j(x + delta e_j) >= info_min, I_j = J_j^T R^-1 J_j with J_j the
    measurement's slope by mu_j (central difference of step 1e-3) and R step 4's noise, both
    at the prior mean raised by delta on side j (point_fit's R); a step that fails gets
    S_R x 1e4 (no update). It learns the step's inputs and prior by wrapping trusted's
    _step_noise (install() / remove(): the study's own process only; trusted.py untouched)."""

    def __init__(self, p: dict, delta: float):
        self.p, self.delta, self.ctx, self.saved = p, delta, None, None
        self.skipped = 0

    def install(self):
        self.saved = trusted._step_noise

        def wrapped(p, f, T, u, sd_u, persistent=None, reuse=None):
            self.ctx = (np.array(u, copy=True), np.array(f.x, copy=True))
            return self.saved(p, f, T, u, sd_u, persistent, reuse)
        trusted._step_noise = wrapped

    def remove(self):
        trusted._step_noise = self.saved

    def info_alt(self) -> np.ndarray:
        u, x = self.ctx
        p, d = self.p, 1e-3
        out = np.zeros(2)
        for j in range(2):
            xa = np.array(x, dtype=float)
            xa[j] = min(xa[j] + self.delta, p["mu_max"])
            pts = []
            for s in (1.0, -1.0):
                xs = xa.copy()
                xs[j] += s * d
                pts.append(xs)
            T = trusted.WHEELS_OF_SIDES
            hs = trusted.h_points(p, np.tile(u, (2, 1)), np.array(pts) @ T.T)
            J = (hs[0] - hs[1]) / (2 * d)
            R = point_noise(p, u[None, :], xa[None, :])[0]
            out[j] = J @ np.linalg.solve(R, J)
        return out

    def __call__(self, k, nu, s_zz, zc, s_r, c_pers=None):
        if self.info_alt().max() >= self.p["info_min"]:
            return s_r
        self.skipped += 1
        return s_r * 1e4


class UpperNoise(UpperGate):
    """The update-level experiment of MONITOR.md section 12: step 4's noise at the upper
    alternative too. At mild slip the measurement bounds mu from below only, but step 4
    evaluates the model error and the errors-in-variables columns at the prior mean; at a low
    mean the model's tyre is saturated and the slip noise hardly enters R. Here the update uses
    R = R0 + [Ra - R0]+ (the positive part of the difference, by eigenvalues: the smallest
    such upper bound of both in that direction basis), R0 step 4's noise at the prior mean x,
    Ra the same step 4 (trusted._step_noise itself) at min(x + delta, mu_max) on both sides;
    the gate and the monitor keep R0. inflated counts the steps where Ra added anything."""

    def __init__(self, p: dict, delta: float):
        super().__init__(p, delta)
        self.inflated = 0

    def install(self):
        self.saved = trusted._step_noise

        def wrapped(p, f, T, u, sd_u, persistent=None, reuse=None):
            self.ctx = (np.array(u, copy=True), np.array(f.x, copy=True),
                        np.array(f.s_r, copy=True), T, np.array(sd_u, copy=True))
            return self.saved(p, f, T, u, sd_u, persistent, reuse)
        trusted._step_noise = wrapped

    def __call__(self, k, nu, s_zz, zc, s_r, c_pers=None):
        u, x, s_r0, T, sd_u = self.ctx
        xa = np.minimum(x + self.delta, self.p["mu_max"])
        s_a = self.saved(self.p, SimpleNamespace(x=xa, s_r=s_r0), T, u, sd_u)
        return noise_upper_bound(s_r, s_a, self)


def noise_upper_bound(s0, sa, counter=None) -> np.ndarray:
    """The lower Cholesky factor of R0 + [Ra - R0]+ (R0 = s0 s0^T, Ra = sa sa^T; [.]+ keeps
    the positive eigenvalues of the symmetric difference): a noise at least as large as both in
    every direction where Ra exceeds R0, equal to R0 where Ra is smaller. counter (with an
    inflated count) counts the calls that changed R0."""
    r0 = s0 @ s0.T
    d = sa @ sa.T - r0
    w, v = np.linalg.eigh(0.5 * (d + d.T))
    pos = np.maximum(w, 0.0)
    if not np.any(pos > 1e-12 * max(np.trace(r0), 1e-300)):
        return s0
    if counter is not None:
        counter.inflated += 1
    return np.linalg.cholesky(r0 + (v * pos) @ v.T)


def reference_run(path: Path, yaw_thr: float | None = None, hold_fired: bool = False,
                  upper_gate: float | None = None, upper_noise: float | None = None,
                  library_rules: bool = False, lower_bound: float = 0.0,
                  extra: dict | None = None) -> dict:
    """The default preset's reference run and the monitor on one log, its two trust rules off;
    with yaw_thr, with the reference's yaw-rate check at that threshold (n_sub: the samples
    yaw_substitute replaces); with hold_fired, no update while the monitor is fired
    (hold_while_fired); with upper_gate, the information gate at mu + upper_gate too
    (UpperGate); with upper_noise, step 4's noise at mu + upper_noise too (UpperNoise); with
    library_rules, the default preset's three trust rules on (stale_omega, yaw_check,
    valid_bound_k: make trust-invariant's estimator); lower_bound: the reference's
    lower_bound_delta (step 6's one-sided update at mild slip, MONITOR.md section 13; 0: off);
    extra: further parameters set on the preset (the evidence censoring's evid_*, section 14)."""
    log = logs.read_csv_log(str(path))
    n_sub = 0
    if yaw_thr is not None:
        n_sub = yaw_substitute(log.col("t"), log.col("yaw_rate"), log.col("yaw_acc"), yaw_thr)[1]
    p = params.resolve(log.meta, None, source=str(path), preset="default")
    if not library_rules:
        p["stale_omega"] = 0.0      # the base run: the rules are measured on top of it
        p["valid_bound_k"] = 0.0    # (the bound margin, the library's since section 11, too)
        p["yaw_check"] = 0.0 if yaw_thr is None else yaw_thr
    p["lower_bound_delta"] = lower_bound
    p.update(extra or {})
    adapt = hold_while_fired(p) if hold_fired else None
    if upper_gate is not None:
        adapt = UpperGate(p, upper_gate)
    if upper_noise is not None:
        adapt = UpperNoise(p, upper_noise)
    if upper_gate is not None or upper_noise is not None:
        adapt.install()
    try:
        res = trusted.run(log, p, adapt=adapt)
    finally:
        if upper_gate is not None or upper_noise is not None:
            adapt.remove()
    mon = monitor.apply(res, p, p["dt"])
    out = {k: mon[k] for k in KEEP if k in mon}
    out["info"] = res["info"]
    for k in ("censored", "evid_L"):
        if k in res:
            out[k] = res[k]
    out["status_filter"] = res["status"]
    out["n_sub"] = np.array(n_sub)
    out["dt"] = np.array(p["dt"])
    return out


def _cached(args):
    scen, cache, name, hold, lib, lower, extra = args
    f = cache / f"{name.replace('/', '+')}.npz"
    if not f.is_file():
        np.savez(f, **reference_run(scen / f"{name}.csv", hold_fired=hold, library_rules=lib,
                                    lower_bound=lower, extra=extra))
    return name


def load_all(scen: Path, cache: Path, jobs: int, hold_fired: bool = False,
             library_rules: bool = False, lower_bound: float = 0.0, names=None,
             extra: dict | None = None) -> dict:
    cache.mkdir(parents=True, exist_ok=True)
    names = bundled(scen) if names is None else names
    with ProcessPoolExecutor(jobs) as ex:
        list(ex.map(_cached, [(scen, cache, n, hold_fired, library_rules, lower_bound, extra)
                              for n in names]))
    runs = {}
    for n in names:
        with np.load(cache / f"{n.replace('/', '+')}.npz") as z:
            r = {k: z[k] for k in z.files}
        log = logs.read_csv_log(str(scen / f"{n}.csv"))
        r["truth"] = np.stack([log.col(f"mu_{w}") for w in WHEELS], 1)
        r["util"] = (np.stack([log.col(f"util_{w}") for w in WHEELS], 1)
                     if "util_fl" in log.columns else None)
        r["omega"] = log.omega()
        r["settled"] = settled(r["t"], r["truth"])
        add_model_inputs(r, log)
        runs[n] = r
    return runs


def add_model_inputs(r: dict, log, u=None, y=None) -> None:
    """The soak rules' inputs into a run r: p (the default preset with the log's metadata),
    u (the estimator's inputs, default: conditioned_inputs with the run's own vx), y (the
    measurements ax, ay, yaw_acc), updated (the filter updated: status 0, 1, or the run's
    unmonitored status where recorded) and lam (upper_evidence at DELTA_UP)."""
    p = params.resolve(log.meta, None, source="log", preset="default")
    r["p"] = p
    r["u"] = conditioned_inputs(log, p, r.get("v_gate")) if u is None else u
    r["y"] = (np.column_stack([log.col("ax"), log.col("ay"), log.col("yaw_acc")])
              if y is None else y)
    if "status_filter" in r:
        r["updated"] = np.isin(r["status_filter"], UPDATED_STATUS)
    else:   # an estimate log: the monitor's status 4 may stand for an update (or a held step)
        r["updated"] = np.isin(r["status"], UPDATED_STATUS + (monitor.STATUS_MISMATCH,))
    r["lam"] = upper_evidence(p, r["u"], r["y"], r["mu"], r["updated"], DELTA_UP)


def evaluate(runs: dict, allowed=None, replaced=None) -> dict:
    """{log: figures} with the valid flags and-ed with allowed(run) ((N, 4) bool), or, for a
    log in replaced, that run instead of the recorded one."""
    out = {}
    for n, r in runs.items():
        rr = dict(r, **replaced[n]) if replaced and n in replaced else r
        valid = rr["valid"].astype(bool)
        if allowed is not None:
            valid = valid & allowed(rr)
        out[n] = figures(rr["mu"], rr["sd"], valid, rr["truth"], rr["util"], rr["settled"])
        out[n]["mismatch"] = float(np.mean(rr["status"] == monitor.STATUS_MISMATCH))
    return out


def verdict(base: dict, new: dict) -> dict:
    """Logs meeting the invariant, gained, lost; the largest fall of the excited-valid share on
    the logs meeting it before; the largest mismatch share on a clean Magic Formula log."""
    drops = {n: base[n]["exc"] - new[n]["exc"] for n in base
             if base[n]["meets"] and base[n]["exc"] is not None and new[n]["exc"] is not None}
    worst = max(drops, key=drops.get) if drops else None
    clean_mf = [n for n in new if n.endswith(".mf") and not n.startswith("faults/")
                and not n.startswith("wrong_tyre")]
    return {"meets": sum(f["meets"] for f in new.values()),
            "gained": sorted(n for n in new if new[n]["meets"] and not base[n]["meets"]),
            "lost": sorted(n for n in new if base[n]["meets"] and not new[n]["meets"]),
            "drop": drops[worst] if worst else 0.0, "drop_log": worst,
            "false_alarm": max((new[n]["mismatch"] for n in clean_mf), default=0.0)}


def fmt(x, spec=".3f"):
    return "–" if x is None else format(x, spec)


def report(label: str, base: dict, new: dict) -> list[str]:
    v = verdict(base, new)
    ok = v["drop"] <= NO_LOSS_MAX and v["false_alarm"] <= FALSE_ALARM_MAX
    fall = f"{100 * v['drop']:.1f} points" + (f" ({v['drop_log']})" if v["drop"] > 0 else "")
    lines = [f"{label}: meets {v['meets']}/{len(new)}; gained {v['gained'] or 'none'}; "
             f"lost {v['lost'] or 'none'}; excited-valid fall {fall}; mismatch on clean MF "
             f"logs {100 * v['false_alarm']:.1f} %; issue 17's rules {'kept' if ok else 'BROKEN'}"]
    for n in TARGETS:
        b, f = base[n], new[n]
        lines.append(f"    {n}: valid {100 * b['valid']:.0f} -> {100 * f['valid']:.0f} %, RMSE "
                     f"{fmt(b['rmse'])} -> {fmt(f['rmse'])}, consistency {fmt(b['cons'])} -> "
                     f"{fmt(f['cons'])}, worst {fmt(b['worst'])} -> {fmt(f['worst'])}")
    return lines


def rule_soak(r: dict, n_mem=EVIDENCE_N, l_min=EVIDENCE_L, k_bound=BOUND_K, d_mem=None):
    """The recommended pair: the upper evidence (reset while the monitor reports a mismatch)
    and the bound margin; (N, 4) allowed."""
    ds = None if d_mem is None else np.maximum(r["u"][:, 1], 0.0) * float(r["p"]["dt"])
    ok = side_rule_to_wheels(rule_evidence(r["lam"], r["updated"], n_mem, l_min,
                                           reset=r["status"] == monitor.STATUS_MISMATCH,
                                           ds=ds, d_mem=d_mem))
    if k_bound is not None:
        ok &= rule_bound_margin(r["mu"], r["sd"], r["p"]["mu_min"], k_bound)
    return ok


def soak_rules() -> list:
    """(label, rule) of the soak drive's candidates: rule(run) -> (allowed (N, 4), sd or None)."""
    out = []
    for tau_b in (None, 0.3):
        def consider(r, tau_b=tau_b):
            p = r["p"]
            sd_eff, ok = rule_consider(p, r["u"], r["mu"], r["sd"], r["updated"],
                                       (p["sd_in_vx"], p["sd_in_vy"]), tau_b)
            return ok, sd_eff
        out.append((f"consider term, vx and vy bias sd_in_vx/vy, "
                    f"{'persistent' if tau_b is None else f'tau {tau_b} s'}", consider))
    for k in (1.0, 2.0, 3.0):
        out.append((f"bound margin {k:g} sd", lambda r, k=k: (
            rule_bound_margin(r["mu"], r["sd"], r["p"]["mu_min"], k), None)))
    for n_mem, l_min, reset in ((5, 2.0, False), (20, 2.0, False), (100, 2.0, False),
                                (100, 2.0, True), (100, 0.5, True), (100, 0.25, True)):
        def evid(r, n_mem=n_mem, l_min=l_min, reset=reset):
            rs = r["status"] == monitor.STATUS_MISMATCH if reset else None
            return side_rule_to_wheels(rule_evidence(r["lam"], r["updated"], n_mem, l_min,
                                                     reset=rs)), None
        out.append((f"upper evidence (+{DELTA_UP}), {n_mem} updates, L_min {l_min}"
                    + (", reset on mismatch" if reset else ""), evid))
    out.append((f"upper evidence ({EVIDENCE_N} updates, L_min {EVIDENCE_L}, reset) + bound "
                f"margin {BOUND_K:g} sd (recommended)", lambda r: (rule_soak(r), None)))
    out.append((f"the same + fade over 30 m", lambda r: (rule_soak(r, d_mem=30.0), None)))
    return out


def apply_rule(runs: dict, rule) -> dict:
    """{log: {valid, sd}} of a soak rule on every run (for evaluate's replaced)."""
    out = {}
    for n, r in runs.items():
        ok, sd = rule(r)
        out[n] = {"valid": r["valid"].astype(bool) & ok}
        if sd is not None:
            out[n]["sd"] = sd
    return out


def soak_run(path: Path, cache: Path, estimate: Path | None = None,
             hold_fired: bool = False, upper_noise: float | None = None,
             library_rules: bool = False, lower_bound: float = 0.0,
             extra: dict | None = None) -> dict:
    """The soak drive (a sensor log with truth columns) as a run: the reference's (cached in
    cache), or with estimate, a mu_replay estimate log of it (its own vx_est, vy_est,
    yaw_acc_est where it has them: --velocity observer)."""
    log = logs.read_csv_log(str(path))
    if estimate is None:
        f = cache / f"soak+{path.stem}.npz"
        if not f.is_file():
            cache.mkdir(parents=True, exist_ok=True)
            np.savez(f, **reference_run(path, hold_fired=hold_fired, upper_noise=upper_noise,
                                        library_rules=library_rules, lower_bound=lower_bound,
                                        extra=extra))
        with np.load(f) as z:
            r = {k: z[k] for k in z.files}
        u = y = None
    else:
        e = estimate_columns(estimate)
        r = {"t": e["t"], "status": e["status"].astype(int)}
        for k in ("mu", "sd", "valid"):
            r[k] = np.stack([e[f"{k}_{w}"] for w in WHEELS], 1)
        p = params.resolve(log.meta, None, source=str(path), preset="default")
        u = y = None
        if "vx_est" in e:
            u = conditioned_inputs(log, p)
            u[:, 1], u[:, 2] = e["vx_est"], e["vy_est"]
            y = np.column_stack([log.col("ax"), log.col("ay"), e["yaw_acc_est"]])
    r["truth"] = np.stack([log.col(f"mu_{w}") for w in WHEELS], 1)
    r["util"] = np.stack([log.col(f"util_{w}") for w in WHEELS], 1)
    r["settled"] = settled(r["t"], r["truth"])
    add_model_inputs(r, log, u, y)
    return r


def upper_noise_lines(scen: Path, cache: Path, names, delta: float) -> list[str]:
    """MONITOR.md section 12: the named logs' figures (valid, RMSE, consistency, worst,
    excited valid) without and with UpperNoise(delta), each run cached in cache (base) and
    cache/upper_noise_DELTA; one process."""
    lines = [f"step 4's noise at mu + {delta} too (UpperNoise, in the loop):"]
    ucache = cache / f"upper_noise_{delta:g}"
    for c in (cache, ucache):
        c.mkdir(parents=True, exist_ok=True)
    for n in names:
        log = logs.read_csv_log(str(scen / f"{n}.csv"))
        truth = np.stack([log.col(f"mu_{w}") for w in WHEELS], 1)
        util = (np.stack([log.col(f"util_{w}") for w in WHEELS], 1)
                if "util_fl" in log.columns else None)
        figs = []
        for c, un in ((cache, None), (ucache, delta)):
            f = c / f"{n.replace('/', '+')}.npz"
            if not f.is_file():
                np.savez(f, **reference_run(scen / f"{n}.csv", upper_noise=un))
            with np.load(f) as z:
                figs.append(figures(z["mu"], z["sd"], z["valid"].astype(bool), truth, util,
                                    settled(z["t"], truth)))
        b, g = figs
        lines.append(f"    {n}: valid {100 * b['valid']:.1f} -> {100 * g['valid']:.1f} %, RMSE "
                     f"{fmt(b['rmse'])} -> {fmt(g['rmse'])}, consistency {fmt(b['cons'])} -> "
                     f"{fmt(g['cons'])}, worst {fmt(b['worst'])} -> {fmt(g['worst'])}, excited "
                     f"valid {fmt(b['exc'])} -> {fmt(g['exc'])}, meets {b['meets']} -> "
                     f"{g['meets']}")
    return lines


def lower_bound_lines(scen: Path, cache: Path, jobs: int, delta: float, names=None) -> list[str]:
    """MONITOR.md section 13: the logs (default: the 72) with the library's three trust rules
    on, without and with the reference's lower_bound_delta = delta (in the loop), as report()'s
    verdict, then each changed log's figures before -> after and the censored side-steps."""
    base_runs = load_all(scen, cache / "lib_rules", jobs, library_rules=True, names=names)
    new_runs = load_all(scen, cache / f"lower_bound_{delta:g}", jobs, library_rules=True,
                        lower_bound=delta, names=names)
    base, new = evaluate(base_runs), evaluate(new_runs)
    lines = [f"library rules on: meets {sum(f['meets'] for f in base.values())}/{len(base)}"]
    lines += report(f"lower_bound_delta {delta:g} (step 6's one-sided update)", base, new)
    for n in base:
        b, g = base[n], new[n]
        cens = new_runs[n].get("censored")
        nc = 0 if cens is None else int(cens.sum())
        if (b["n_valid"], b["rmse"], b["exc"]) == (g["n_valid"], g["rmse"], g["exc"]) and not nc:
            continue
        lines.append(f"    {n}: valid {100 * b['valid']:.1f} -> {100 * g['valid']:.1f} %, RMSE "
                     f"{fmt(b['rmse'])} -> {fmt(g['rmse'])}, consistency {fmt(b['cons'])} -> "
                     f"{fmt(g['cons'])}, worst {fmt(b['worst'])} -> {fmt(g['worst'])}, excited "
                     f"valid {fmt(b['exc'])} -> {fmt(g['exc'])}, meets {b['meets']} -> "
                     f"{g['meets']}; censored side-steps {nc}")
    return lines


def evidence_params(spec: str, delta: float = DELTA_UP) -> dict:
    """The reference's evidence-censoring parameters of a SPEC (MONITOR.md section 14):
    comma-separated KEY=VALUE with KEY one of l_min, n, l0, free, cap (evid_KEY), on top of
    evid_delta = delta; '' or 'plain': the defaults (L starts at 0, no free updates)."""
    p = {"evid_delta": float(delta)}
    for kv in spec.split(","):
        if kv in ("", "plain"):
            continue
        key, _, val = kv.partition("=")
        if f"evid_{key}" not in params.DEFAULTS or key == "delta" or not val:
            raise ValueError(f"evidence spec {spec!r}: {kv!r} is not KEY=VALUE with KEY one "
                             f"of l_min, n, l0, free, cap")
        p[f"evid_{key}"] = float(val)
    return p


def _soak_cached(args):
    path, cache, lib, extra = args
    return soak_run(path, cache, library_rules=lib, extra=extra)


def evidence_lines(scen: Path, cache: Path, jobs: int, specs, names=None,
                   soak: Path | None = None) -> list[str]:
    """MONITOR.md section 14: the logs (default: the 72) with the library's three trust rules
    on, without and with the reference's evidence censoring of each SPEC (evidence_params, in
    the loop), as report()'s verdict and each changed log's figures; with soak, its figures
    with the rules on and off (soak runs in parallel, jobs processes)."""
    base_runs = load_all(scen, cache / "lib_rules", jobs, library_rules=True, names=names)
    base = evaluate(base_runs)
    lines = [f"library rules on: meets {sum(f['meets'] for f in base.values())}/{len(base)}"]
    tag = {spec: "evid_" + (spec or "plain").replace(",", "_").replace("=", "") for spec in specs}
    for spec in specs:
        new_runs = load_all(scen, cache / tag[spec], jobs, library_rules=True, names=names,
                            extra=evidence_params(spec))
        new = evaluate(new_runs)
        lines += report(f"evidence censoring {spec or 'plain'} (delta {DELTA_UP})", base, new)
        for n in base:
            b, g = base[n], new[n]
            nc = int(new_runs[n]["censored"].sum())
            if (b["n_valid"], b["rmse"], b["exc"]) == (g["n_valid"], g["rmse"], g["exc"]) \
                    and not nc:
                continue
            lines.append(f"    {n}: valid {100 * b['valid']:.1f} -> {100 * g['valid']:.1f} %, "
                         f"RMSE {fmt(b['rmse'])} -> {fmt(g['rmse'])}, consistency "
                         f"{fmt(b['cons'])} -> {fmt(g['cons'])}, worst {fmt(b['worst'])} -> "
                         f"{fmt(g['worst'])}, excited valid {fmt(b['exc'])} -> {fmt(g['exc'])}, "
                         f"meets {b['meets']} -> {g['meets']}; censored side-steps {nc}")
    if soak is not None:
        todo = [(lib, spec) for lib in (True, False) for spec in [None] + list(specs)]
        args = [(soak, cache / (("lib_rules" if spec is None else tag[spec])
                                + ("" if lib else "_off")), lib,
                 None if spec is None else evidence_params(spec)) for lib, spec in todo]
        with ProcessPoolExecutor(jobs) as ex:
            runs = list(ex.map(_soak_cached, args))
        for (lib, spec), r in zip(todo, runs):
            label = (f"the library's rules {'on' if lib else 'off'}, "
                     + ("today" if spec is None else f"evidence censoring {spec or 'plain'}"))
            lines += soak_lines(label, r, [])
            if "censored" in r:
                lines.append(f"    censored side-steps {int(r['censored'].sum())}, steps "
                             f"updated {int(np.isin(r['status_filter'], UPDATED_STATUS).sum())}")
    return lines


def estimate_columns(path: Path) -> dict:
    """{column: float array} of a mu_replay estimate log ('#' metadata, one header row)."""
    with open(path, encoding="utf-8") as fh:
        rows = [ln for ln in fh if not ln.startswith("#")]
    names = rows[0].strip().split(",")
    data = np.loadtxt(rows[1:], delimiter=",", ndmin=2)
    return {c: data[:, i] for i, c in enumerate(names)}


def soak_lines(label: str, r: dict, rules) -> list[str]:
    lines = [f"soak drive, {label}:"]
    for name, rule in [("none (today)", None)] + rules:
        ok, sd = (np.ones_like(r["valid"], dtype=bool), None) if rule is None else rule(r)
        f = figures(r["mu"], r["sd"] if sd is None else sd, r["valid"].astype(bool) & ok,
                    r["truth"], r["util"], r["settled"])
        lines.append(f"    {name}: valid {100 * f['valid']:.1f} %, RMSE {fmt(f['rmse'])}, "
                     f"consistency {fmt(f['cons'])}, worst {fmt(f['worst'])}, excited valid "
                     f"{fmt(f['exc'])}")
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="issue 17: candidate valid and input rules")
    ap.add_argument("--scenarios", default="scenarios", type=Path)
    ap.add_argument("--cache", default="build/trust_rules", type=Path)
    ap.add_argument("--jobs", default=2, type=int)
    ap.add_argument("--soak", type=Path, help="the soak drive (sensor log with truth columns; "
                    "make soak's build/soak/drive_300s.csv): its rules on the reference's run")
    ap.add_argument("--soak-estimate", type=Path, nargs="*", default=[],
                    help="mu_replay estimate logs of --soak (e.g. --velocity observer)")
    ap.add_argument("--hold-fired", action="store_true",
                    help="also the experiment: no update while the monitor is fired (reruns "
                    "the reference on every log, cached in CACHE/hold_fired)")
    ap.add_argument("--only-soak-rules", action="store_true",
                    help="skip the rules of section 8 (stale, updates, yaw)")
    ap.add_argument("--upper-noise", type=float, metavar="DELTA",
                    help="only the experiment of MONITOR.md section 12 (step 4's noise at mu + "
                    "DELTA too, in the loop): --soak's figures with it, then --logs' before and "
                    "after (one process)")
    ap.add_argument("--logs", nargs="*", default=[],
                    help="with --upper-noise: the logs (names as bundled(), e.g. "
                    "accel_low_mu.mf; 'all': the 72)")
    ap.add_argument("--lower-bound", type=float, metavar="DELTA",
                    help="only the experiment of MONITOR.md section 13 (the reference's "
                    "lower_bound_delta = DELTA: step 6's one-sided update at mild slip), with "
                    "the library's three trust rules on: --logs (default all) before and "
                    "after, --jobs processes, cached in CACHE/lib_rules and "
                    "CACHE/lower_bound_DELTA; then --soak's figures, the rules on and off")
    ap.add_argument("--evidence", nargs="*", metavar="SPEC",
                    help="only the experiment of MONITOR.md section 14 (the reference's "
                    "accumulated-evidence censoring in step 6, evid_delta 0.25, in the loop), "
                    "one run of --logs (default all) per SPEC (comma-separated l_min=, n=, "
                    "l0=, free=, cap=; 'plain': the defaults) with the library's three trust rules "
                    "on, --jobs processes, cached in CACHE/evid_SPEC; then --soak's figures, "
                    "the rules on and off")
    a = ap.parse_args(argv)
    if a.evidence is not None:
        print("\n".join(evidence_lines(a.scenarios, a.cache, a.jobs, a.evidence or ["plain"],
                                        None if a.logs in ([], ["all"]) else a.logs, a.soak)))
        return 0
    if a.lower_bound is not None:
        print("\n".join(lower_bound_lines(a.scenarios, a.cache, a.jobs, a.lower_bound,
                                           None if a.logs in ([], ["all"]) else a.logs)))
        if a.soak:
            for lib in (False, True):
                label = "the library's rules " + ("on" if lib else "off")
                runs = [soak_run(a.soak, a.cache / ("lib_rules" if lib else "") , library_rules=lib),
                        soak_run(a.soak, a.cache / (f"lower_bound_{a.lower_bound:g}"
                                                    + ("" if lib else "_off")),
                                 library_rules=lib, lower_bound=a.lower_bound)]
                for name, r in zip(("today", f"lower_bound_delta {a.lower_bound:g}"), runs):
                    print("\n".join(soak_lines(f"{label}, {name}", r, [])))
        return 0
    if a.upper_noise is not None:
        if a.soak:
            r = soak_run(a.soak, a.cache / f"upper_noise_{a.upper_noise:g}",
                         upper_noise=a.upper_noise)
            print("\n".join(soak_lines(f"step 4's noise at mu + {a.upper_noise:g} too", r, [])))
        names = bundled(a.scenarios) if a.logs == ["all"] else a.logs
        print("\n".join(upper_noise_lines(a.scenarios, a.cache, names, a.upper_noise)))
        return 0
    runs = load_all(a.scenarios, a.cache, a.jobs)
    base = evaluate(runs)
    print(f"reference, default preset: meets {sum(f['meets'] for f in base.values())}/{len(base)}")
    rules = soak_rules()
    for name, rule in rules:
        print("\n".join(report(name, base, evaluate(runs, replaced=apply_rule(runs, rule)))))
    if a.soak:
        print("\n".join(soak_lines("reference (measured velocities)", soak_run(a.soak, a.cache),
                                   rules)))
        for est in a.soak_estimate:
            print("\n".join(soak_lines(str(est), soak_run(a.soak, a.cache, est), rules)))
    if a.hold_fired:
        hcache = a.cache / "hold_fired"
        held = load_all(a.scenarios, hcache, a.jobs, hold_fired=True)
        print("\n".join(report("no update while the monitor is fired (in the loop)", base,
                               evaluate(held))))
        pair = ("the soak pair (fade 30 m)", lambda r: (rule_soak(r, d_mem=30.0), None))
        print("\n".join(report("no update while fired + the soak pair (fade 30 m)", base,
                               evaluate(held, replaced=apply_rule(held, pair[1])))))
        if a.soak:
            print("\n".join(soak_lines("reference, no update while fired",
                                       soak_run(a.soak, hcache, hold_fired=True), [pair])))
    if a.only_soak_rules:
        return 0
    for tau, a_min in ((0.1, 0.3), (0.3, 0.1), (0.5, 0.1)):
        def upd(r, tau=tau, a_min=a_min):
            return side_rule_to_wheels(rule_updates(r["status_filter"], r["info"], tau, a_min,
                                                    25.0, float(r["dt"])))
        print("\n".join(report(f"updates tau {tau} s, a_min {a_min}", base, evaluate(runs, upd))))
    for delta in (0.25, 0.5):
        def stale(r, delta=delta):
            return np.repeat(rule_stale(r["omega"], delta)[:, None], 4, 1)
        print("\n".join(report(f"stale wheel speed, delta {delta} rad/s", base,
                               evaluate(runs, stale))))
    thr = 0.1
    replaced = {}
    for n in runs:
        log = logs.read_csv_log(str(a.scenarios / f"{n}.csv"))
        if yaw_substitute(log.col("t"), log.col("yaw_rate"), log.col("yaw_acc"), thr)[1]:
            replaced[n] = reference_run(a.scenarios / f"{n}.csv", thr)
    print(f"yaw-rate check acts on {sorted(replaced)}")
    print("\n".join(report(f"yaw-rate check, thr {thr} rad/s", base,
                           evaluate(runs, replaced=replaced))))
    print("\n".join(report(f"stale wheel speed (delta 0.25 rad/s) and yaw-rate check", base,
                           evaluate(runs, lambda r: np.repeat(rule_stale(r["omega"], 0.25)[:, None],
                                                              4, 1), replaced))))
    # section 10: the soak pair on top of the two rules above (the yaw-checked runs get their
    # own evidence; its inputs u take the log's yaw rate, not the checked one: 2 logs)
    for n in replaced:
        both = dict(runs[n], **replaced[n])
        add_model_inputs(both, logs.read_csv_log(str(a.scenarios / f"{n}.csv")))
        replaced[n] = both
    for label, d_mem in (("", None), (", fade over 30 m", 30.0)):
        print("\n".join(report(
            f"stale wheel speed, yaw-rate check and the soak pair{label}", base,
            evaluate(runs, lambda r, d_mem=d_mem: np.repeat(
                rule_stale(r["omega"], 0.25)[:, None], 4, 1) & rule_soak(r, d_mem=d_mem),
                replaced))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
