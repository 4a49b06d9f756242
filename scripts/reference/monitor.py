"""Model-validity monitor on the estimator's innovations (docs/MONITOR.md), float64 reference.

The estimator's measurement model claims that the innovation nu_k = y_k - z_hat_k is
N(0, S_zz,k S_zz,k^T) and white. The monitor tests that claim over a window and, when the
data contradict it, marks the estimate not valid with a status of its own and inflates the
reported sd. It reads the innovations only: it never changes the filter (it is not an update
gate), so it is applied to a recorded run (trusted.run's nu, s_zz) or step by step.

Per step k at which the measurement model was evaluated (MODEL.md section 6's nu, S_zz;
S = S_zz S_zz^T; C the diagonal of S's persistent part, trusted.run's c_pers: the state's
Zc Zc^T, the tyre-model error (r_model_rel |h|)^2 and the low-passed vx, vy columns, errors
that do not change from one step to the next and so do not average out):
  w_k   = S_zz \\ nu_k                         whitened innovation (forward solve), m = 3
  d_k   = |w_k|^2                               NIS, chi-square with m dof under the model
  e_k,r = nu_k,r / sqrt(S_rr)                   normalised innovation of channel r (ax, ay, r-dot)
  c_k,r = C_rr / S_rr in [0, 1]                 its persistent share
  D_k   = (1 - l_d) D_k-1 + l_d d_k,     D_0 = m     l_d = dt / (mon_tau_nis + dt)
  M_k,r = (1 - l_m) M_k-1,r + l_m e_k,r, M_0 = 0     l_m = dt / (mon_tau_mean + dt)
  c̄_k,r = (1 - l_m) c̄_k-1,r + l_m c_k,r, c̄_0 = c_1
Under the model, an innovation is a white part (share 1 - c) plus a persistent part (share c,
constant over the window): M_r is normal with variance sigma_r^2 = l' (1 - c̄_r) + c̄_r
(l' = l_m / (2 - l_m)); D has mean m and variance 2 sum_r [c̄_r^2 + 2 l' c̄_r (1 - c̄_r) +
l' (1 - c̄_r)^2] (l' with l_d), approximated by a + b chi2(nu_d) with its first three
cumulants matched (Pearson; pearson() has the cumulants). Thresholds from the per-step
false-alarm probability p = mon_p_fire, half to the NIS test, half to the 3 channels'
two-sided mean tests (Bonferroni):
  D_fire = a + b chi2_{nu_d}^{-1}(1 - p/2),   M_fire,r = z(1 - p / (4 m)) sigma_r
and the clear thresholds likewise from mon_p_clear. Chi-square quantiles by Wilson-Hilferty
(the form the C library can compute): chi2_nu^{-1}(q) ~ nu (1 - 2/(9 nu) + z(q) sqrt(2/(9 nu)))^3.
The first mon_warmup s of evaluated steps only count (the input conditioner starts from the
raw measured vx, vy, whose error is then larger than its claimed sd_in_vx for about 3 tau_v).
Hysteresis: fire when D_k > D_fire or any |M_k,r| > M_fire,r; stay at least mon_hold s after
the last exceedance; clear when D_k < D_clear and every |M_k,r| < M_clear,r. Low-speed steps
(no innovation) leave the statistics and the state unchanged.
While fired: every valid flag 0, status RFE_MODEL_MISMATCH (4) in place of 0 and 1, and of 3
when a flag would have been 1 (a held, not valid step keeps 3: the status says why the estimate
is not valid), and the reported sd multiplied by sqrt(max(1, D_k / m)) (the innovations' variance ratio).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import solve_triangular
from scipy.special import ndtri

from . import params

M_CHANNELS = 3
STATUS_MISMATCH = 4
CHANNELS = ("ax", "ay", "yaw_acc")

# Parameters (parameter-file keys, docs/MONITOR.md section "Parameters"): the library's values
# (params.py; the default preset has it on, the paper preset off), switched on.
MON_DEFAULTS: dict[str, float] = {**{k: v for k, v in params.DEFAULTS.items()
                                     if k.startswith("mon_")}, "mon_enable": 1.0}


def lam(tau: float, dt: float) -> float:
    """EWMA weight per step, l = dt / (tau + dt) (as the input conditioner's b)."""
    return dt / (tau + dt)


def z_quantile(q: float) -> float:
    """Standard-normal quantile z(q)."""
    return float(ndtri(q))


def chi2_quantile_wh(nu: float, q: float) -> float:
    """Wilson-Hilferty chi-square quantile: nu (1 - 2/(9 nu) + z(q) sqrt(2/(9 nu)))^3."""
    a = 2.0 / (9.0 * nu)
    return nu * (1.0 - a + z_quantile(q) * math.sqrt(a)) ** 3


STEPS_SLACK = 1e-6  # a duration within 1e-6 (relative) of a whole number of periods is that number


def steps(t: float, dt: float) -> int:
    """ceil(t / dt) with STEPS_SLACK, as the C library counts (float: 0.5 / 0.01 = 50.0000007)."""
    return int(math.ceil((t / dt) * (1.0 - STEPS_SLACK)))


@dataclass(frozen=True)
class Thresholds:
    """The constants the thresholds are built from (per-step thresholds: limits())."""
    l_d: float          # EWMA weight of D
    l_m: float          # EWMA weight of M and of the persistent shares c
    z_d_fire: float     # z(1 - p_fire / 2): the NIS test's quantile
    z_d_clear: float
    z_m_fire: float     # z(1 - p_fire / (4 m)): each channel's two-sided mean test
    z_m_clear: float
    hold_steps: int
    warmup_steps: int
    m: int


def thresholds(p: dict, dt: float, m: int = M_CHANNELS) -> Thresholds:
    """The monitor's constants from its parameters (module docstring)."""
    return Thresholds(lam(p["mon_tau_nis"], dt), lam(p["mon_tau_mean"], dt),
                      z_quantile(1.0 - p["mon_p_fire"] / 2.0),
                      z_quantile(1.0 - p["mon_p_clear"] / 2.0),
                      z_quantile(1.0 - p["mon_p_fire"] / (4.0 * m)),
                      z_quantile(1.0 - p["mon_p_clear"] / (4.0 * m)),
                      steps(p["mon_hold"], dt), steps(p["mon_warmup"], dt), m)


def _chi2_wh_z(nu, z):
    """Wilson-Hilferty chi-square quantile at the normal quantile z (elementwise in nu)."""
    a = 2.0 / (9.0 * nu)
    return nu * np.maximum(1.0 - a + z * np.sqrt(a), 0.0) ** 3


def pearson(c, th: Thresholds):
    """(a, b, nu): D ~ a + b chi2(nu) under the model, the three cumulants of D matched
    (Pearson). Per channel r the whitened innovation is a persistent part (share c_r, held over
    the window) plus a white part (share 1 - c_r); D is then the sum over r of
    A_r = sigma_r^2 chi2(1), sigma_r^2 = c_r + (1 - c_r) l' (the channel's averaged innovation,
    squared) and B_r, the average of the white part's squares about its own mean, with
    E B_r = (1 - c_r)(1 - l'), var B_r = 2 l' (1 - c_r)^2, third cumulant 8 l3 (1 - c_r)^3;
    l' = l_d / (2 - l_d) = sum of the squared weights, l3 = l_d^3 / (1 - (1 - l_d)^3) = sum of
    their cubes. k1 = m, k2 = sum 2 sigma^4 + 2 l' (1 - c)^2, k3 = sum 8 sigma^6 + 8 l3 (1 - c)^3;
    b = k3 / (4 k2), nu = 8 k2^3 / k3^2, a = k1 - b nu. (c = 1: a = 0, b = 1, nu = m, exact.)"""
    c = np.clip(np.asarray(c, dtype=float), 0.0, 1.0)
    lp = th.l_d / (2.0 - th.l_d)
    l3 = th.l_d ** 3 / (1.0 - (1.0 - th.l_d) ** 3)
    sig2 = c + (1.0 - c) * lp
    k2 = np.sum(2.0 * sig2 ** 2 + 2.0 * lp * (1.0 - c) ** 2, axis=-1)
    k3 = np.sum(8.0 * sig2 ** 3 + 8.0 * l3 * (1.0 - c) ** 3, axis=-1)
    b = k3 / (4.0 * k2)
    nu = 8.0 * k2 ** 3 / k3 ** 2
    return th.m - b * nu, b, nu


def limits(c, th: Thresholds):
    """(D_fire, D_clear, M_fire (.., m), M_clear (.., m)) for persistent shares c (.., m):
    D_x = a + b chi2_nu^{-1}(1 - p_x / 2) (pearson(), Wilson-Hilferty), M_x,r = z_x sigma_r
    with sigma_r^2 = l' (1 - c_r) + c_r, l' = l_m / (2 - l_m)."""
    c = np.clip(np.asarray(c, dtype=float), 0.0, 1.0)
    a, b, nu = pearson(c, th)
    d_fire = a + b * _chi2_wh_z(nu, th.z_d_fire)
    d_clear = a + b * _chi2_wh_z(nu, th.z_d_clear)
    lp = th.l_m / (2.0 - th.l_m)
    sig = np.sqrt(lp * (1.0 - c) + c)
    return d_fire, d_clear, th.z_m_fire * sig, th.z_m_clear * sig


def normalise(nu: np.ndarray, s_zz: np.ndarray, c_pers=None):
    """(d, e, c): the NIS |S_zz \\ nu|^2, the per-channel nu_r / sqrt(S_rr) and the persistent
    shares c_r = C_rr / S_rr (S = S_zz S_zz^T; C_rr = c_pers, None: 0, white innovations)."""
    w = solve_triangular(s_zz, nu, lower=True, check_finite=False)
    s_rr = np.einsum("ij,ij->i", s_zz, s_zz)
    c = np.zeros(nu.shape) if c_pers is None else np.clip(np.asarray(c_pers) / s_rr, 0.0, 1.0)
    return float(w @ w), nu / np.sqrt(s_rr), c


def ewma(D, M, C, d, e, c, th: Thresholds):
    """One step of the averages (elementwise; channels last): D' = (1 - l_d) D + l_d d,
    M' = (1 - l_m) M + l_m e, C' = (1 - l_m) C + l_m c."""
    return ((1.0 - th.l_d) * D + th.l_d * np.asarray(d, dtype=float),
            (1.0 - th.l_m) * M + th.l_m * np.asarray(e, dtype=float),
            (1.0 - th.l_m) * C + th.l_m * np.asarray(c, dtype=float))


def over_fire(D, M, C, th: Thresholds):
    """A fire threshold exceeded: D > D_fire or any |M_r| > M_fire,r (elementwise)."""
    d_fire, _, m_fire, _ = limits(C, th)
    return (D > d_fire) | np.any(np.abs(M) > m_fire, axis=-1)


def under_clear(D, M, C, th: Thresholds):
    """Every statistic below its clear threshold (elementwise)."""
    _, d_clear, _, m_clear = limits(C, th)
    return (D < d_clear) & np.all(np.abs(M) < m_clear, axis=-1)


class Monitor:
    """The monitor's state (D, M, C, fired, hold counter) and its step."""

    def __init__(self, p: dict, dt: float, m: int = M_CHANNELS):
        self.p = {**MON_DEFAULTS, **{k: v for k, v in p.items() if k in MON_DEFAULTS}}
        self.th = thresholds(self.p, dt, m)
        self.m = m
        self.D = float(m)
        self.M = np.zeros(m)
        self.C = None            # set to the first step's shares
        self.fired = False
        self.hold = 0
        self.seen = 0            # evaluated steps so far (warm-up)

    def step_stats(self, d: float, e, c=None) -> bool:
        """Advance D, M, C and the hysteresis with one step's NIS d, normalised innovations e
        and persistent shares c (None: white); returns the mismatch state after the step."""
        th = self.th
        c = np.zeros(self.m) if c is None else np.asarray(c, dtype=float)
        if self.C is None:
            self.C = c.copy()
        D, self.M, self.C = ewma(self.D, self.M, self.C, d, e, c, th)
        self.D = float(D)
        under = bool(under_clear(self.D, self.M, self.C, th))
        if bool(over_fire(self.D, self.M, self.C, th)):
            self.fired, self.hold = True, th.hold_steps
        elif self.fired:
            self.hold = max(self.hold - 1, 0)
            if self.hold == 0 and under:
                self.fired = False
        return self.fired

    def step(self, nu, s_zz, c_pers=None) -> bool:
        """One step with an innovation (None or NaN: low speed, nothing changes)."""
        if nu is None or not np.all(np.isfinite(nu)):
            return self.fired
        self.seen += 1
        if self.seen <= self.th.warmup_steps:
            return self.fired
        d, e, c = normalise(np.asarray(nu, dtype=float), np.asarray(s_zz, dtype=float), c_pers)
        return self.step_stats(d, e, c)

    def inflation(self) -> float:
        """c = sqrt(max(1, D / m)) while fired and mon_inflate, else 1."""
        if not (self.fired and self.p["mon_inflate"] > 0):
            return 1.0
        return math.sqrt(max(1.0, self.D / self.m))


def apply(res: dict, p: dict, dt: float, use_c: bool = True) -> dict:
    """The monitor over a recorded run (trusted.run's output): returns a copy with valid, sd
    and status as the monitor leaves them, plus the per-step D, M (N, 3), fired, inflation.
    use_c False: every innovation treated as white (c = 0; the naive test, for comparison).
    The inflated sd is capped at (mu_max - mu_min) / 2 (p's bounds, else the library's):
    no distribution of friction inside the bounds has a larger sd (Popoviciu's inequality)."""
    mon = Monitor(p, dt)
    sd_cap = 0.5 * (p.get("mu_max", params.DEFAULTS["mu_max"])
                    - p.get("mu_min", params.DEFAULTS["mu_min"]))
    n = len(res["status"])
    out = {k: np.array(v, copy=True) for k, v in res.items() if isinstance(v, np.ndarray)}
    out["D"], out["M"] = np.full(n, np.nan), np.full((n, M_CHANNELS), np.nan)
    out["fired"], out["inflation"] = np.zeros(n, dtype=bool), np.ones(n)
    enable = mon.p["mon_enable"] > 0
    for k in range(n):
        nu = res["nu"][k]
        if res["status"][k] != 2 and np.all(np.isfinite(nu)):
            mon.step(nu, res["s_zz"][k], res["c_pers"][k] if use_c else None)
        out["D"][k], out["M"][k] = mon.D, mon.M
        out["fired"][k] = mon.fired
        c = mon.inflation()
        out["inflation"][k] = c
        if enable and mon.fired:
            # every step while fired: no flag, the inflated sd (also at low speed, where the
            # estimate carried over is the one the data contradicted). The status says why the
            # estimate is not valid: an updated step, or a held one that would be valid,
            # reports the mismatch; a held step whose flags are all 0 keeps "not observable",
            # and low speed keeps its own
            if res["status"][k] in (0, 1) or (res["status"][k] == 3 and np.any(res["valid"][k])):
                out["status"][k] = STATUS_MISMATCH
            out["valid"][k] = 0
            out["sd"][k] = np.minimum(res["sd"][k] * c, sd_cap)
    return out


class CovarianceMatching:
    """In-loop adaptive measurement noise (Sage-Husa, per channel), a measurement for
    docs/MONITOR.md: r2_c = (1 - l) r2_c + l (nu_c^2 - (Zc Zc^T)_cc) estimates the actual
    noise variance of channel c; the step's S_R is scaled row by row by
    a_c = sqrt(max(1, r2_c / (S_R S_R^T)_cc)) (never below the nominal R). where = "always"
    or "fired" (only while the monitor, run in the loop on the nominal innovations, is
    fired). The monitor's own statistics see the nominal S_zz."""

    def __init__(self, p: dict, dt: float, tau: float = 0.5, where: str = "always"):
        self.mon = Monitor(p, dt)
        self.l = lam(tau, dt)
        self.where = where
        self.r2 = None
        self.scale = np.ones(M_CHANNELS)

    def __call__(self, k, nu, s_zz, zc, s_r, c_pers=None):
        r_nom = np.einsum("ij,ij->i", s_r, s_r)
        sample = nu ** 2 - np.einsum("ij,ij->i", zc, zc)
        self.r2 = r_nom.copy() if self.r2 is None else self.r2
        a = np.sqrt(np.maximum(1.0, self.r2 / r_nom))     # from the steps before k
        fired = self.mon.fired
        self.r2 = (1.0 - self.l) * self.r2 + self.l * sample
        self.mon.step(nu, s_zz, c_pers)
        if self.where == "fired" and not fired:
            a = np.ones(M_CHANNELS)
        self.scale = a
        return a[:, None] * s_r
