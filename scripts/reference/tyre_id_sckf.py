"""Reference augmented-state square-root cubature Kalman filter for tyre identification
(docs/TYRE_ID.md §15): the sigma-point baseline of issue 20's comparison, over the same model,
parameters, priors, bounds, process noise and measurements as the particle filters of
tyre_id.py, with the library's SCKF machinery (filters.SCKF: cubature points, Tria).  float64,
NumPy; deterministic (no random stream).

    f = init(params)                  # params: keys of params.DEFAULTS and tyre_id.TID_DEFAULTS
    est = f.step(sample)              # sample: t, delta, vx, yaw_rate, ay, ax (SI)
    out = run(columns, params)        # a whole sensor log -> dict of arrays (tyre_id.run's keys)

The state is x = (vy, r, D_f, C_f, K_f, E_f, D_r, C_r, K_r, E_r): tyre_id.py's particle,
n = 10, 2n = 20 cubature points.  Bounds: every cubature point is evaluated with its
parameters clipped into [lo, hi] (the model is not defined outside: C D > 0, E < 1), and the
mean's parameters are projected onto [lo, hi] after each update (filters.project, as the
friction SCKF projects mu); the square-root covariance is left as the update made it.
With tid_delta_state_q > 0 (§15.7, off by default) delta is an eleventh state, last: a random
walk of that density, measured by the steering sensor (a third measurement row, sd
tid_sd_delta), each cubature point's RK4 step and ay at its own delta.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import solve_triangular

from . import tyre_id as T
from .filters import SCKF, project, tria
from .params import DEFAULTS as VEHICLE_DEFAULTS

__all__ = ["TyreIdSCKF", "init", "run", "N_POINTS"]

N_POINTS = 2 * T.DIM           # cubature points per step: 20


class TyreIdSCKF(T._SampleSteps):
    """One augmented-state SCKF identifier (init, then step per sample: tyre_id._SampleSteps)."""

    def __init__(self, params: dict, backend: str = "numpy"):
        p = dict(VEHICLE_DEFAULTS)
        p.update(T.TID_DEFAULTS)
        p.update(params)
        self.p = p
        # the elementary functions (tyre_id.py's backends; libm: the C library's, as its goldens)
        self.fn = T.NUMPY if backend == "numpy" else T.LIBM if backend == "libm" else None
        if self.fn is None:
            raise ValueError(f"unknown backend {backend!r}")
        self.model = T._Model(p, self.fn)
        # the particle filter's scales, priors, bounds and noise (tyre_id.TyreId.__init__)
        ref = T.TyreId(params)
        self.fz0, self.gx = ref.fz0, ref.gx
        self.mu_loads = ref.mu_loads
        self.lo, self.hi = ref.lo, ref.hi
        self.q_th, self.mean0, self.sd0 = ref.q_th, ref.mean0, ref.sd0
        # §15.7 the steering angle as a state (tid_delta_state_q > 0): x grows by delta, last
        self.dstate = p["tid_delta_state_q"] > 0.0
        if self.dstate and p["tid_delta_q"] > 0.0:
            raise ValueError("tid_delta_state_q and tid_delta_q exclude each other")
        self.n_x = T.DIM + (1 if self.dstate else 0)
        self.u_freeze = p["tid_d_freeze_u"]      # §15.8 (0: off)
        self.f = None            # the filters.SCKF
        self.prev = None         # the previous sample's (t, delta, vx)
        self.k = 0

    # §15.2 the prior: the particle filter's Gaussian, unreflected
    def _initialise(self, r_meas, delta_meas=0.0):
        p = self.p
        x0 = np.concatenate([[0.0, r_meas], self.mean0])
        s0 = np.concatenate([[p["tid_sd0_vy"], p["tid_sd0_r"]], self.sd0])
        if self.dstate:      # §15.7 delta starts at the measured one, with the sensor's sd
            x0 = np.concatenate([x0, [delta_meas]])
            s0 = np.concatenate([s0, [p["tid_sd_delta"]]])
        m = 3 if self.dstate else 2
        self.f = SCKF(x0, np.diag(s0), np.zeros((self.n_x, self.n_x)), np.zeros((m, m)))

    def _clip(self, pts):
        """Cubature points (DIM, 2n) -> (vy, r, theta (2n, 8)) with theta clipped to bounds."""
        th = np.minimum(np.maximum(pts[2:T.DIM].T, self.lo), self.hi)
        return pts[0], pts[1], th

    def _process(self, d_bar, v_bar, h, a_bar=0.0):
        """The RK4 step of §4.1 of every cubature point; the parameters are a random walk."""
        n_sub = int(self.p["tid_substeps"])

        def f(pts):
            vy, r, th = self._clip(pts)
            # §15.7: each point's own delta (the state's, held over the period)
            d = pts[T.DIM] if self.dstate else d_bar
            vy1, r1 = self.model.rk4(vy, r, th, d, v_bar, h, n_sub, a_bar)
            out = pts.copy()
            out[0], out[1] = vy1, r1
            return out
        return f

    def _measure(self, s, cd):
        """h(X): (r, ay_p) of every cubature point at the sample's delta, vx (§5.1's ay_p)."""
        def h(pts):
            vy, r, th = self._clip(pts)
            if self.dstate:  # §15.7: ay at each point's delta, and delta itself measured
                d = pts[T.DIM]
                f, rr = self.model.forces(vy, r, th, d, s["vx"], s["ax"])
                return np.stack([r, ((f * self.fn.cos(d)) + rr) / self.p["m"], d])
            f, rr = self.model.forces(vy, r, th, s["delta"], s["vx"], s["ax"])
            return np.stack([r, ((f * cd) + rr) / self.p["m"]])
        return h

    def _s_r(self, s, cd, sd_):
        """§15.3 measurement noise: diag(tid_sd_r, sqrt(tid_sd_ay^2 + (g tid_sd_delta)^2)),
        g = d ay / d delta of §5.1 at the predicted mean (parameters clipped); with the
        steering-angle filter of §4.4 its posterior sd in place of tid_sd_delta."""
        p = self.p
        if self.dstate:      # §15.7: delta is a state; its sensor a measurement row
            return np.diag([p["tid_sd_r"], p["tid_sd_ay"], p["tid_sd_delta"]])
        x = self.f.x[:, None]
        vy, r, th = self._clip(x)
        t_f, _ = self.model.slips(vy, r, s["delta"], s["vx"])
        f, slope = T.mf_force_slope(t_f, th[:, 0], th[:, 1], T.b_of(th, 0), th[:, 3], self.fn)
        sc = self.model.scales(th, s["ax"])
        if sc is not None:
            f, slope = f * sc[0], slope * sc[0]
        g = float(((slope[0] * cd) - (f[0] * sd_)) / p["m"])
        gs = g * self.sd_delta
        return np.diag([p["tid_sd_r"], math.sqrt(p["tid_sd_ay"] * p["tid_sd_ay"] + gs * gs)])

    def _frozen(self, s):
        """§15.8 the rows of D_a whose axle the predicted mean puts below tid_d_freeze_u of its
        friction: |Fy_a| / D_a at the mean (parameters clipped), at delta (the state's with
        §15.7), vx, ax of the sample."""
        x = self.f.x[:, None]
        vy, r, th = self._clip(x)
        d = x[T.DIM] if self.dstate else s["delta"]
        f, rr = self.model.forces(vy, r, th, d, s["vx"], s["ax"])
        rows = []
        for j, fy in ((2, f[0]), (6, rr[0])):
            if abs(float(fy)) < self.u_freeze * float(th[0, j - 2]):
                rows.append(j)
        return rows

    def _update_frozen(self, y, h, rows):
        """filters.SCKF.measurement_update with the gain's @p rows set to 0 (§15.8): x = x- +
        K (y - z), S = Tria([Xc - K Zc, K S_R]), the Joseph form, is the covariance of the
        estimate for any gain, so the frozen rows keep their predicted mean and sd."""
        f = self.f
        pts = f.points()
        z_pts = np.asarray(h(pts), dtype=float)
        z_hat = z_pts.mean(axis=1)
        xc = (pts - f.x[:, None]) / f.sqrt_2n
        zc = (z_pts - z_hat[:, None]) / f.sqrt_2n
        s_zz = tria(np.hstack([zc, f.s_r]))
        w_t = solve_triangular(s_zz, (xc @ zc.T).T, lower=True, check_finite=False)
        k_gain = solve_triangular(s_zz, w_t, lower=True, trans="T", check_finite=False).T
        k_gain[rows, :] = 0.0
        f.x = f.x + k_gain @ (y - z_hat)
        f.S = tria(np.hstack([xc - k_gain @ zc, k_gain @ f.s_r]))

    def _project(self):
        self.f.x[2:T.DIM], _ = project(self.f.x[2:T.DIM], self.lo, self.hi)

    def _update(self, s):
        p, fn = self.p, self.fn
        h = s["t"] - self.prev[0]
        d_bar = 0.5 * (self.prev[1] + s["delta"])
        v_bar = 0.5 * (self.prev[2] + s["vx"])
        cd = float(fn.cos(np.float64(s["delta"])))
        sd_ = float(fn.sin(np.float64(s["delta"])))
        sq = math.sqrt(h)
        # §15.3 time update: cubature points through RK4, S- = Tria([Xc*, S_Q])
        q = [[p["tid_q_vy"] * sq, p["tid_q_r"] * sq], self.q_th * sq]
        if self.dstate:      # §15.7 delta's random walk
            q.append([p["tid_delta_state_q"] * sq])
        self.f.s_q = np.diag(np.concatenate(q))
        a_bar = 0.5 * (self.prev[3] + s["ax"])
        self.f.propagate(self._process(d_bar, v_bar, h, a_bar))
        self._project()
        # measurement update on (r_m, ay_m)
        self.f.s_r = self._s_r(s, cd, sd_)
        y = [s["yaw_rate"], s["ay"]] + ([s["delta"]] if self.dstate else [])
        frozen = self._frozen(s) if self.u_freeze > 0.0 else []
        if frozen:
            self._update_frozen(np.array(y), self._measure(s, cd), frozen)
        else:
            self.f.measurement_update(np.array(y), self._measure(s, cd))
        self._project()
        if not (np.isfinite(self.f.x).all() and np.isfinite(self.f.S).all()):
            self._initialise(s["yaw_rate"], s["delta"])
            return T.ST_LOST
        return T.ST_UPDATED

    def _estimate(self, s, status):
        """§15.4 outputs: the states and parameters from (x, S); beta, Fy and B as the mean
        and sd of the cubature points of (x, S) at this sample's inputs (weights 1/(2n))."""
        x, sd_x = self.f.x, self.f.sd()
        pts = self.f.points()
        vy, r, th = self._clip(pts)
        d = pts[T.DIM] if self.dstate else s["delta"]
        f, rr = self.model.forces(vy, r, th, d, s["vx"], s["ax"])
        q = {"beta": self.fn.atan2(vy, np.full_like(vy, s["vx"])), "Fy_f": f, "Fy_r": rr,
             "B_f": T.b_of(th, 0), "B_r": T.b_of(th, 4)}
        mean, sd = {}, {}
        for k, v in q.items():
            m = float(np.mean(v))
            mean[k] = m
            sd[k] = float(np.sqrt(np.mean((v - m) ** 2)))
        for j, k in enumerate(T.STATE_NAMES + T.PARAM_NAMES):
            mean[k], sd[k] = float(x[j]), float(sd_x[j])
        fz_f, fz_r = self.mu_loads(s["ax"])
        mean["mu_f"], sd["mu_f"] = mean["D_f"] / fz_f, sd["D_f"] / fz_f
        mean["mu_r"], sd["mu_r"] = mean["D_r"] / fz_r, sd["D_r"] / fz_r
        return T.Estimate(float(s["t"]), status, math.nan, mean, sd)


def init(params: dict, backend: str = "numpy") -> TyreIdSCKF:
    return TyreIdSCKF(params, backend)


def run(columns: dict, params: dict, n_steps: int | None = None,
        backend: str = "numpy") -> dict:
    """A whole log -> dict of arrays with tyre_id.run's keys (n_eff: NaN, no particles)."""
    tid = init(params, backend)
    n = len(columns["t"]) if n_steps is None else n_steps
    out = {k: np.empty(n) for k in ("t", "status", "n_eff")}
    for k in T.OUTPUT_NAMES:
        out[k] = np.empty(n)
        out["sd_" + k] = np.empty(n)
    cols = [np.asarray(columns[k], dtype=float) for k in T.SAMPLE_KEYS]
    for i in range(n):
        e = tid.step({k: float(c[i]) for k, c in zip(T.SAMPLE_KEYS, cols)})
        out["t"][i], out["status"][i], out["n_eff"][i] = e.t, e.status, e.n_eff
        for k in T.OUTPUT_NAMES:
            out[k][i] = e.mean[k]
            out["sd_" + k][i] = e.sd[k]
    return out
