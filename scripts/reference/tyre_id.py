"""Reference tyre identifier (docs/TYRE_ID.md): vehicle state and the eight lateral Magic
Formula parameters (D, C, B, E per axle) by an auxiliary particle filter (the fourth seed's
method, CN104408265) or a plain bootstrap (SIR) particle filter.  float64, NumPy.

    tid = init(params, seed)          # params: keys of params.DEFAULTS and TID_DEFAULTS
    est = tid.step(sample)            # sample: t, delta, vx, yaw_rate, ay, ax (SI)
    est.status, est.mean["mu_f"], est.sd["mu_f"], ...
    out = run(columns, params, ...)   # a whole sensor log -> dict of arrays

Every operation whose order changes a bit is written in the page's order (§9): sequential
sums (np.cumsum / np.add.accumulate, never np.sum, which sums pairwise), the elementwise
arithmetic as the page parenthesises it.  The elementary functions (atan2, tan, atan, sin,
cos, exp, log, sqrt) come from a backend: "numpy" (its ufuncs: fast; on CPUs with AVX-512
some are NumPy's own SIMD kernels and differ from the C library's in the last bit) or "libm"
(Python's math module, i.e. the platform's C library, element by element: slow, and what a C
port linked against the same libm reproduces bit for bit).  The tests check that both give
the same estimates to rounding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .params import DEFAULTS as VEHICLE_DEFAULTS
from .philox import Stream

__all__ = ["TID_DEFAULTS", "TID_CHOICES", "PARAM_NAMES", "STATE_NAMES", "OUTPUT_NAMES",
           "Backend", "NUMPY", "LIBM", "TyreId", "Estimate", "init", "run", "mf_force",
           "normalise_log", "resample_multinomial", "resample_systematic", "reflect",
           "ST_UPDATED", "ST_RESAMPLED", "ST_HELD", "ST_FIRST", "ST_LOST"]

# §2 parameters of the identifier (the vehicle's and the tyre data's come from params.DEFAULTS:
# m, Lf, Lr, J, hg, g, cy, shape_Cy, shape_Ey, alpha_max).
TID_DEFAULTS: dict[str, float] = {
    "tid_n": 256.0,           # particles (a compile-time constant in C)
    "tid_seed": 1.0,          # key word k0 of the random stream
    "tid_substeps": 1.0,      # RK4 steps per sample period
    "tid_v_min": 5.0,         # below this vx (this or the previous sample) the step holds, m/s
    "tid_sd_r": 0.01,         # likelihood sd of the yaw rate (sensor + model), rad/s
    "tid_sd_ay": 0.2,         # likelihood sd of ay (sensor and model), m/s^2
    "tid_sd_delta": 0.001,    # steering-angle noise, through each particle's front slope, rad
    "tid_q_vy": 0.02,         # process noise density of vy, m/s per sqrt(s)
    "tid_q_r": 0.01,          # process noise density of r, rad/s per sqrt(s)
    "tid_q_mu": 0.02,         # random walk of D / Fz0 (per axle), 1 per sqrt(s)
    "tid_q_C": 0.02,          # random walk of C, 1 per sqrt(s)
    "tid_q_cy": 0.3,          # random walk of K / Fz0 (cornering stiffness per load), 1/rad per sqrt(s)
    "tid_q_E": 0.05,          # random walk of E, 1 per sqrt(s)
    "tid_mu0": 0.7,           # prior mean of D / Fz0
    "tid_sd0_mu": 0.3,        # prior sd of D / Fz0
    "tid_sd0_C": 0.2,         # prior sd of C (mean: shape_Cy)
    "tid_sd0_cy_rel": 0.3,    # prior sd of K / Fz0 relative to its mean cy
    "tid_sd0_E": 0.5,         # prior sd of E (mean: shape_Ey)
    "tid_sd0_vy": 0.2,        # prior sd of vy (mean 0), m/s
    "tid_sd0_r": 0.01,        # prior sd of r (mean: the first measured yaw rate), rad/s
    "tid_mu_lo": 0.1,         # bounds of D / Fz0
    "tid_mu_hi": 1.3,
    "tid_C_lo": 1.0,          # bounds of C
    "tid_C_hi": 2.0,
    "tid_cy_lo": 4.0,         # bounds of K / Fz0, 1/rad
    "tid_cy_hi": 40.0,
    "tid_E_lo": -3.0,         # bounds of E (E < 1: the curve keeps its peak)
    "tid_E_hi": 0.95,
    "tid_neff_frac": 1.0 / 3.0,  # resample when N_eff < tid_neff_frac * N (the patent: N/3)
    "tid_rough_k": 0.2,       # roughening constant K (Gordon et al. 1993)
    "tid_ellipse": 0.0,       # 1: the axle forces under ax (load and friction ellipse, §3.5); 0: off
    "tid_fx_front": 0.625,    # §3.5 the front axle's share of m ax
    "tid_ell_min": 0.1,       # §3.5 the smallest factor the ellipse leaves of a lateral force
    "tid_ell_ax_min": 0.6,    # §3.5 m/s^2: below this |ax| the ellipse takes ax as 0 (0: none)
    "tid_delta_q": 0.0,       # §4.4 the steering-angle filter's white-acceleration noise density,
                              # rad/s^2 per sqrt(s) (0: off, the measured delta as read)
    "tid_delta_state_q": 0.0,  # §15.7 the SCKF only: delta as a state, its random walk's
                               # density, rad per sqrt(s) (0: off, delta an input)
    "tid_d_freeze_u": 0.0,    # §15.8 the SCKF only: D_a's gain is 0 while the utilisation the
                              # predicted mean gives that axle, |Fy_a| / D_a, is below this (0: off)
}
TID_CHOICES = {"tid_filter": ("apf", "sir"),
               "tid_resample": ("multinomial", "systematic")}  # first of each: the default

STATE_NAMES = ("vy", "r")
# §4 a particle's parameters: per axle D, C, the cornering stiffness K = B C D and E (the
# patent's B is K / (C D))
PARAM_NAMES = ("D_f", "C_f", "K_f", "E_f", "D_r", "C_r", "K_r", "E_r")
NPAR = len(PARAM_NAMES)                         # 8 parameters, roughened
DIM = len(STATE_NAMES) + NPAR                   # 10 columns of a particle
OUTPUT_NAMES = ("beta", "r", "vy", "Fy_f", "Fy_r") + PARAM_NAMES + \
    ("B_f", "B_r", "mu_f", "mu_r")

# §6.3 purposes (counter word c2)
P_INIT, P_PROCESS, P_RESAMPLE, P_ROUGH = 0, 1, 2, 4    # 3 reserved

# §7 status bits
ST_UPDATED, ST_RESAMPLED, ST_HELD, ST_FIRST, ST_LOST = 1, 2, 4, 8, 16


class Backend:
    """The elementary functions of one backend (module docstring)."""

    def __init__(self, name):
        self.name = name
        if name == "numpy":
            self.atan2, self.tan, self.atan = np.arctan2, np.tan, np.arctan
            self.sin, self.cos, self.exp, self.log = np.sin, np.cos, np.exp, np.log
            self.sqrt = np.sqrt
        elif name == "libm":
            def lift(f):
                return np.vectorize(f, otypes=[np.float64])
            self.atan2, self.tan, self.atan = lift(math.atan2), lift(math.tan), lift(math.atan)
            self.sin, self.cos = lift(math.sin), lift(math.cos)
            self.exp, self.log = lift(math.exp), lift(_log)
            self.sqrt = np.sqrt          # IEEE: correctly rounded in both
        else:
            raise ValueError(f"unknown backend {name!r}")


def _log(x):
    return math.log(x) if x > 0.0 else (-math.inf if x == 0.0 else math.nan)


NUMPY = Backend("numpy")
LIBM = Backend("libm")


# ---- §3 the model -------------------------------------------------------------------------

def mf_force(t, D, C, B, E, fn=NUMPY):
    """§3.2 F = D sin(C atan(B t - E (B t - atan(B t)))) in the lateral slip t = tan(alpha)."""
    bt = B * t
    return D * fn.sin(C * fn.atan(bt - E * (bt - fn.atan(bt))))


def mf_force_slope(t, D, C, B, E, fn=NUMPY):
    """§3.2 (F, dF/dalpha) at t = tan(alpha):
    dF/dalpha = D C cos(C phi) / (1 + psi^2) * (1 - E + E / (1 + x^2)) * B * (1 + t^2),
    x = B t, psi = x - E (x - atan x), phi = atan psi."""
    x = B * t
    psi = x - E * (x - fn.atan(x))
    cphi = C * fn.atan(psi)
    f = D * fn.sin(cphi)
    dpsi = (1.0 - E) + E / (1.0 + x * x)
    slope = ((((D * C) * fn.cos(cphi)) / (1.0 + psi * psi)) * dpsi) * (B * (1.0 + t * t))
    return f, slope


def b_of(th, j):
    """§4 B = K / (C D) of the axle whose columns start at j."""
    return th[:, j + 2] / (th[:, j + 1] * th[:, j])


class _Model:
    """Vehicle constants of §3 and the right-hand side f(x, theta, u)."""

    def __init__(self, p, fn):
        self.m, self.Lf, self.Lr, self.J = p["m"], p["Lf"], p["Lr"], p["J"]
        self.a_max = p["alpha_max"]
        self.fn = fn
        # §3.5 the friction ellipse: the axle loads (§3.4), each axle's share of m ax
        self.ell = p["tid_ellipse"] != 0.0
        La = p["Lf"] + p["Lr"]
        self.fz0 = (p["m"] * p["g"] * p["Lr"] / La, p["m"] * p["g"] * p["Lf"] / La)
        self.gx = p["m"] * p["hg"] / La
        self.kxm = (p["tid_fx_front"] * p["m"], (1.0 - p["tid_fx_front"]) * p["m"])
        self.u_max = 1.0 - p["tid_ell_min"] * p["tid_ell_min"]
        self.ax_min = p["tid_ell_ax_min"]

    def scales(self, th, ax):
        """§3.5 (s_f, s_r): the factor of each axle's pure-slip force under ax, the load's
        lam = Fz / Fz0 times the friction ellipse's sqrt(1 - min(rho^2, 1 - ell_min^2)),
        rho = Fx / (lam D), Fx the axle's share of m ax; None when tid_ellipse is off."""
        if not self.ell:
            return None
        if abs(ax) < self.ax_min:
            ax = 0.0  # the dead band: lam = 1 and rho = 0 exactly, the factor 1
        lam = ((self.fz0[0] - self.gx * ax) / self.fz0[0],
               (self.fz0[1] + self.gx * ax) / self.fz0[1])
        out = []
        for a, j in ((0, 0), (1, 4)):
            rho = (self.kxm[a] * ax) / (lam[a] * th[:, j])
            u = np.minimum(rho * rho, self.u_max)
            out.append(lam[a] * np.sqrt(1.0 - u))
        return out

    def slips(self, vy, r, delta, vx):
        """§3.1 tan(alpha) of the front and rear axle (alpha clipped to +-alpha_max)."""
        fn = self.fn
        a_f = delta - fn.atan2(vy + self.Lf * r, vx)
        a_r = -fn.atan2(vy - self.Lr * r, vx)
        a_f = np.minimum(np.maximum(a_f, -self.a_max), self.a_max)
        a_r = np.minimum(np.maximum(a_r, -self.a_max), self.a_max)
        return fn.tan(a_f), fn.tan(a_r)

    def forces(self, vy, r, th, delta, vx, ax=0.0):
        """(Fy_f, Fy_r) of each particle at inputs (delta, vx), §3.1-3.2."""
        t_f, t_r = self.slips(vy, r, delta, vx)
        f = mf_force(t_f, th[:, 0], th[:, 1], b_of(th, 0), th[:, 3], self.fn)
        rr = mf_force(t_r, th[:, 4], th[:, 5], b_of(th, 4), th[:, 7], self.fn)
        sc = self.scales(th, ax)
        if sc is not None:
            f, rr = f * sc[0], rr * sc[1]
        return f, rr

    def rhs(self, vy, r, th, delta, cd, vx, ax=0.0):
        """§3.3 (vy', r') with cd = cos(delta)."""
        f, rr = self.forces(vy, r, th, delta, vx, ax)
        fyc = f * cd
        ay = (fyc + rr) / self.m
        return ay - r * vx, (self.Lf * fyc - self.Lr * rr) / self.J

    def rk4(self, vy, r, th, delta, vx, h, n_sub, ax=0.0):
        """§4: n_sub classical RK4 steps of h / n_sub, inputs held."""
        cd = self.fn.cos(np.float64(delta))
        return rk4(lambda a, b: self.rhs(a, b, th, delta, cd, vx, ax), vy, r, h, n_sub)


def rk4(f, a, b, h, n_sub=1):
    """§4 n_sub classical RK4 steps of h / n_sub of (a, b)' = f(a, b), in the page's order."""
    hs = h / n_sub
    h2, h6 = 0.5 * hs, hs / 6.0
    for _ in range(n_sub):
        k1a, k1b = f(a, b)
        k2a, k2b = f(a + h2 * k1a, b + h2 * k1b)
        k3a, k3b = f(a + h2 * k2a, b + h2 * k2b)
        k4a, k4b = f(a + hs * k3a, b + hs * k3b)
        a = a + h6 * (((k1a + 2.0 * k2a) + 2.0 * k3a) + k4a)
        b = b + h6 * (((k1b + 2.0 * k2b) + 2.0 * k3b) + k4b)
    return a, b


# ---- §5 weights and resampling ------------------------------------------------------------

def normalise_log(logw, fn=NUMPY):
    """§5.1 log-sum-exp: (w, log-normalised weights) from log weights; None if every weight is
    -inf.  w_i = e_i / S, e_i = exp(l_i - max l), S the sequential sum of e."""
    mx = np.max(logw)
    if not mx > -math.inf:
        return None, None
    e = fn.exp(logw - mx)
    s = np.cumsum(e)[-1]
    return e / s, (logw - mx) - fn.log(np.float64(s))


def _search(cum, x):
    """Smallest i with x < cum[i] (N - 1 if none), for each x."""
    return np.minimum(np.searchsorted(cum, x, side="right"), cum.shape[0] - 1)


def resample_multinomial(w, u):
    """§5.3 index of each uniform u_j: smallest i with u_j * S < C_i, C the sequential
    cumulative sum of w, S = C_{N-1}."""
    cum = np.cumsum(w)
    return _search(cum, u * cum[-1])


def resample_systematic(w, u0, m):
    """§5.3 m indices at x_j = (j + u0) * (S / m), j = 0 .. m-1."""
    cum = np.cumsum(w)
    step = cum[-1] / m
    return _search(cum, (np.arange(m, dtype=np.float64) + u0) * step)


def reflect(x, lo, hi):
    """§5.5 one reflection at each bound, then a clip (a step wider than the interval)."""
    y = np.where(x < lo, lo + (lo - x), x)
    y = np.where(y > hi, hi - (y - hi), y)
    return np.minimum(np.maximum(y, lo), hi)


# ---- the filter ---------------------------------------------------------------------------

@dataclass
class Estimate:
    t: float
    status: int
    n_eff: float
    mean: dict
    sd: dict


class _SampleSteps:
    """The step both identifiers share (§4.1, §15.1): the prior at the first sample; held
    while this sample's or the previous one's vx is below tid_v_min; else the filter's update
    (_update gives its status bits); then the outputs (_estimate). The previous sample's
    (t, delta, vx) is self.prev, None before the first."""

    def _delta_filter(self, s: dict) -> dict:
        """§4.4 the steering-angle filter: with tid_delta_q > 0 the sample's delta is replaced
        by a two-state (delta, its rate) Kalman filter's posterior mean, and the steering
        noise of §5.1 (the particle filters) and §15.3 (the SCKF) by its posterior sd; with 0
        the sample and tid_sd_delta as they are."""
        p = self.p
        q = p["tid_delta_q"]
        self.sd_delta = p["tid_sd_delta"]
        if q == 0.0:
            return s
        rv = p["tid_sd_delta"] * p["tid_sd_delta"]
        if self.prev is None:
            self.dk = [s["delta"], 0.0, rv, 0.0, 0.0]      # delta, rate, p00, p01, p11
        else:
            d, dd, p00, p01, p11 = self.dk
            h = s["t"] - self.prev[0]
            qq = q * q
            # predict: constant rate, white acceleration of density q
            d = d + (h * dd)
            p00 = (p00 + (h * ((2.0 * p01) + (h * p11)))) + (((qq * h) * h) * h) / 3.0
            p01 = (p01 + (h * p11)) + (((qq * h) * h) * 0.5)
            p11 = p11 + (qq * h)
            # update on the measured delta
            sv = p00 + rv
            k0 = p00 / sv
            k1 = p01 / sv
            e = s["delta"] - d
            d = d + (k0 * e)
            dd = dd + (k1 * e)
            p11 = p11 - (k1 * p01)
            p01 = p01 - (k0 * p01)
            p00 = p00 - (k0 * p00)
            self.dk = [d, dd, p00, p01, p11]
        self.sd_delta = math.sqrt(self.dk[2])
        return dict(s, delta=self.dk[0])

    def step(self, s: dict) -> Estimate:
        """One sample: s has t, delta, vx, yaw_rate, ay, ax (SI)."""
        status = 0
        s = self._delta_filter(s)
        if self.prev is None:
            self._initialise(s["yaw_rate"], s["delta"])
            status |= ST_FIRST
        elif s["vx"] < self.p["tid_v_min"] or self.prev[2] < self.p["tid_v_min"]:
            status |= ST_HELD
        else:
            status |= self._update(s)
        self.prev = (s["t"], s["delta"], s["vx"], s["ax"])
        est = self._estimate(s, status)
        self.k += 1
        return est


class TyreId(_SampleSteps):
    """One identifier (init, then step per sample)."""

    def __init__(self, params: dict, seed: int | None = None, backend: str = "numpy"):
        p = dict(VEHICLE_DEFAULTS)
        p.update(TID_DEFAULTS)
        for k, allowed in TID_CHOICES.items():
            p.setdefault(k, allowed[0])
        p.update(params)
        for k, allowed in TID_CHOICES.items():
            if p[k] not in allowed:
                raise ValueError(f"{k} must be one of {allowed}, not {p[k]!r}")
        self.p = p
        self.fn = NUMPY if backend == "numpy" else LIBM if backend == "libm" else None
        if self.fn is None:
            raise ValueError(f"unknown backend {backend!r}")
        self.n = int(p["tid_n"])
        if self.n < 2 or self.n != p["tid_n"]:
            raise ValueError("tid_n must be an integer >= 2")
        self.stream = Stream(int(p["tid_seed"] if seed is None else seed), self.fn)
        self.model = _Model(p, self.fn)
        La = p["Lf"] + p["Lr"]
        # §3.4 static axle loads (D's scale) and the load transfer by ax
        self.fz0 = (p["m"] * p["g"] * p["Lr"] / La, p["m"] * p["g"] * p["Lf"] / La)
        self.gx = p["m"] * p["hg"] / La
        lo, hi, q, mean, sd = [], [], [], [], []
        for fz in self.fz0:
            lo += [p["tid_mu_lo"] * fz, p["tid_C_lo"], p["tid_cy_lo"] * fz, p["tid_E_lo"]]
            hi += [p["tid_mu_hi"] * fz, p["tid_C_hi"], p["tid_cy_hi"] * fz, p["tid_E_hi"]]
            q += [p["tid_q_mu"] * fz, p["tid_q_C"], p["tid_q_cy"] * fz, p["tid_q_E"]]
            mean += [p["tid_mu0"] * fz, p["shape_Cy"], p["cy"] * fz, p["shape_Ey"]]
            sd += [p["tid_sd0_mu"] * fz, p["tid_sd0_C"], (p["tid_sd0_cy_rel"] * p["cy"]) * fz,
                   p["tid_sd0_E"]]
        self.lo, self.hi = np.array(lo), np.array(hi)
        self.q_th, self.mean0, self.sd0 = np.array(q), np.array(mean), np.array(sd)
        if not (math.isfinite(p["tid_delta_q"]) and p["tid_delta_q"] >= 0.0):
            raise ValueError("tid_delta_q must be finite and >= 0")
        if not (math.isfinite(p["tid_delta_state_q"]) and p["tid_delta_state_q"] >= 0.0):
            raise ValueError("tid_delta_state_q must be finite and >= 0")
        if not (math.isfinite(p["tid_d_freeze_u"]) and 0.0 <= p["tid_d_freeze_u"] < 1.0):
            raise ValueError("tid_d_freeze_u must be in [0, 1)")
        if not np.all(self.lo < self.hi):
            raise ValueError("every lower bound must be below its upper bound")
        if not (self.lo <= self.mean0).all() or not (self.mean0 <= self.hi).all():
            raise ValueError("the prior means must lie within the bounds")
        # §5.4 roughening scale K N^(-1/d), once
        self.rough = p["tid_rough_k"] * math.pow(self.n, -1.0 / NPAR)
        self.k = 0               # the sample counter (counter word c1)
        self.prev = None         # the previous sample's (t, delta, vx)
        self.x = None            # (N, 2) states vy, r
        self.th = None           # (N, 8) parameters
        self.logw = None         # (N,) log weights

    def mu_loads(self, ax):
        """§3.4 the loads of mu = D / Fz: the axle loads at ax; with §3.5 on, the static
        loads (D is then the peak at the static load, lam D the peak at ax)."""
        if self.p["tid_ellipse"] != 0.0:
            return self.fz0
        return self.fz0[0] - self.gx * ax, self.fz0[1] + self.gx * ax

    # §4.1 the prior
    def _initialise(self, r_meas, delta_meas=0.0):
        """(delta_meas: the SCKF's, §15.7; the particle filters do not use it)"""
        n, p = self.n, self.p
        z = self.stream.normals(self.k, P_INIT, n * DIM).reshape(n, DIM)
        self.x = np.empty((n, 2))
        self.x[:, 0] = 0.0 + p["tid_sd0_vy"] * z[:, 0]
        self.x[:, 1] = r_meas + p["tid_sd0_r"] * z[:, 1]
        self.th = reflect(self.mean0 + self.sd0 * z[:, 2:], self.lo, self.hi)
        self.logw = np.zeros(n)

    def _loglik(self, vy, r, th, s, cd, sd_):
        """§5.1 log-likelihood of the sample's (yaw_rate, ay) per particle: Gaussian, the ay
        variance grown by the steering sensor's noise through the particle's own front slope
        (errors in variables), constants common to all particles dropped."""
        p = self.p
        t_f, t_r = self.model.slips(vy, r, s["delta"], s["vx"])
        f, slope = mf_force_slope(t_f, th[:, 0], th[:, 1], b_of(th, 0), th[:, 3], self.fn)
        rr = mf_force(t_r, th[:, 4], th[:, 5], b_of(th, 4), th[:, 7], self.fn)
        sc = self.model.scales(th, s["ax"])
        if sc is not None:
            f, slope, rr = f * sc[0], slope * sc[0], rr * sc[1]
        ay = ((f * cd) + rr) / p["m"]
        g = ((slope * cd) - (f * sd_)) / p["m"]          # d ay / d delta
        gs = g * self.sd_delta
        var = p["tid_sd_ay"] * p["tid_sd_ay"] + gs * gs
        e1 = (s["yaw_rate"] - r) / p["tid_sd_r"]
        e2 = s["ay"] - ay
        ll = -0.5 * (e1 * e1 + (e2 * e2) / var) - 0.5 * self.fn.log(var)
        return np.where(np.isfinite(ll), ll, -math.inf)

    def _noise(self, vy, r, th):
        """§4.2 process noise on propagated states and parameters (row i: particle i)."""
        n, p = self.n, self.p
        sq = math.sqrt(self.h)
        z = self.stream.normals(self.k, P_PROCESS, n * DIM).reshape(n, DIM)
        vy = vy + (p["tid_q_vy"] * sq) * z[:, 0]
        r = r + (p["tid_q_r"] * sq) * z[:, 1]
        th = reflect(th + (self.q_th * sq) * z[:, 2:], self.lo, self.hi)
        return vy, r, th

    def _draw(self, w, purpose, m, scheme):
        """§5.3 m indices from weights w: multinomial (uniform j -> index j) or systematic."""
        if scheme == "systematic":
            return resample_systematic(w, self.stream.uniforms(self.k, purpose, 1)[0], m)
        return resample_multinomial(w, self.stream.uniforms(self.k, purpose, m))

    def _rough_resample(self, w, n_eff, cols):
        """§5.4 the patent's resampling of the particle columns cols (N x d): the
        floor(N_eff) heaviest kept in order of weight, every other slot a perturbed copy of
        a parent drawn from w with its parameters roughened (and reflected into their bounds;
        the states are copied: the dynamics tie them to the parameters).
        Returns (new columns, the parent of each slot)."""
        n = self.n
        keep = min(int(math.floor(n_eff)), n)
        order = np.argsort(-w, kind="stable")
        parents = self._draw(w, P_RESAMPLE, n - keep, self.p["tid_resample"])
        th = cols[:, 2:]
        spread = (np.max(th, axis=0) - np.min(th, axis=0)) * self.rough
        z = self.stream.normals(self.k, P_ROUGH, n * NPAR).reshape(n, NPAR)[keep:]
        new = cols[parents]
        new[:, 2:] = reflect(new[:, 2:] + spread * z, self.lo, self.hi)
        return (np.concatenate([cols[order[:keep]], new], axis=0),
                np.concatenate([order[:keep], parents]))

    def _update(self, s):
        p, n, fn = self.p, self.n, self.fn
        self.h = s["t"] - self.prev[0]
        d_bar = 0.5 * (self.prev[1] + s["delta"])
        v_bar = 0.5 * (self.prev[2] + s["vx"])
        cd = fn.cos(np.float64(s["delta"]))
        sd_ = fn.sin(np.float64(s["delta"]))
        # §4 the noise-free RK4 step of every particle (the APF's auxiliary points)
        a_bar = 0.5 * (self.prev[3] + s["ax"])
        mu_vy, mu_r = self.model.rk4(self.x[:, 0], self.x[:, 1], self.th, d_bar, v_bar,
                                     self.h, int(p["tid_substeps"]), a_bar)
        status = ST_UPDATED
        if p["tid_filter"] == "apf":
            # §5.2 first stage: the predicted likelihood at the auxiliary points
            la = self._loglik(mu_vy, mu_r, self.th, s, cd, sd_)
            w1, _ = normalise_log(self.logw + la, fn)
            if w1 is None:
                return self._lost(s)
            n_eff1 = 1.0 / np.cumsum(w1 * w1)[-1]
            if n_eff1 < p["tid_neff_frac"] * n:
                cols, idx = self._rough_resample(
                    w1, n_eff1, np.concatenate([np.stack([mu_vy, mu_r], axis=1), self.th], 1))
                vy, r, th = self._noise(cols[:, 0], cols[:, 1], cols[:, 2:])
                ll = self._loglik(vy, r, th, s, cd, sd_)
                logw = ll - la[idx]                 # second stage
                status |= ST_RESAMPLED
            else:
                vy, r, th = self._noise(mu_vy, mu_r, self.th)
                ll = self._loglik(vy, r, th, s, cd, sd_)
                logw = self.logw + ll               # no draw: the first stage's la cancels
        else:
            vy, r, th = self._noise(mu_vy, mu_r, self.th)
            ll = self._loglik(vy, r, th, s, cd, sd_)
            logw = self.logw + ll
        w, lw = normalise_log(logw, fn)
        if w is None:
            return self._lost(s)
        self.x = np.stack([vy, r], axis=1)
        self.th = th
        self.logw = lw
        if p["tid_filter"] == "sir":
            n_eff = 1.0 / np.cumsum(w * w)[-1]
            if n_eff < p["tid_neff_frac"] * n:  # §5.3 plain copies, every slot drawn
                idx = self._draw(w, P_RESAMPLE, n, p["tid_resample"])
                self.x, self.th = self.x[idx], self.th[idx]
                self.logw = np.zeros(n)
                status |= ST_RESAMPLED
        return status

    def _lost(self, s):
        """Every weight zero (a non-finite state on every particle): start again (§4.1)."""
        self._initialise(s["yaw_rate"])
        return ST_LOST

    def _estimate(self, s, status):
        """§7 weighted means and sds of the outputs at this sample's inputs."""
        fn, p = self.fn, self.p
        w, _ = normalise_log(self.logw, fn)
        vy, r = self.x[:, 0], self.x[:, 1]
        f, rr = self.model.forces(vy, r, self.th, s["delta"], s["vx"], s["ax"])
        fz_f, fz_r = self.mu_loads(s["ax"])
        q = {"beta": fn.atan2(vy, np.full_like(vy, s["vx"])), "r": r, "vy": vy,
             "Fy_f": f, "Fy_r": rr}
        for j, k in enumerate(PARAM_NAMES):
            q[k] = self.th[:, j]
        q["B_f"], q["B_r"] = b_of(self.th, 0), b_of(self.th, 4)
        q["mu_f"] = self.th[:, 0] / fz_f
        q["mu_r"] = self.th[:, 4] / fz_r
        mean, sd = {}, {}
        for k in OUTPUT_NAMES:
            m = np.cumsum(w * q[k])[-1]
            d = q[k] - m
            mean[k] = float(m)
            sd[k] = float(np.sqrt(np.cumsum(w * (d * d))[-1]))
        n_eff = float(1.0 / np.cumsum(w * w)[-1])
        return Estimate(float(s["t"]), status, n_eff, mean, sd)


def init(params: dict, seed: int | None = None, backend: str = "numpy") -> TyreId:
    return TyreId(params, seed, backend)


SAMPLE_KEYS = ("t", "delta", "vx", "yaw_rate", "ay", "ax")


def run(columns: dict, params: dict, seed: int | None = None, backend: str = "numpy",
        n_steps: int | None = None) -> dict:
    """A whole log (dict column -> array) -> dict of arrays: t, status, n_eff, and each
    output's mean (name) and sd (sd_name)."""
    tid = init(params, seed, backend)
    n = len(columns["t"]) if n_steps is None else n_steps
    out = {k: np.empty(n) for k in ("t", "status", "n_eff")}
    for k in OUTPUT_NAMES:
        out[k] = np.empty(n)
        out["sd_" + k] = np.empty(n)
    cols = [np.asarray(columns[k], dtype=float) for k in SAMPLE_KEYS]
    for i in range(n):
        e = tid.step({k: float(c[i]) for k, c in zip(SAMPLE_KEYS, cols)})
        out["t"][i], out["status"][i], out["n_eff"][i] = e.t, e.status, e.n_eff
        for k in OUTPUT_NAMES:
            out[k][i] = e.mean[k]
            out["sd_" + k][i] = e.sd[k]
    return out
