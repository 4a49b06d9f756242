"""Tests of the model-validity monitor (scripts/reference/monitor.py, docs/MONITOR.md).

Synthetic innovations of known covariance: the false-alarm probability each threshold was
derived for is met within its binomial band, a known bias or variance excess is detected
within the delay derived from the averages' step response, the hysteresis holds and clears
as specified, and apply() acts on valid, status and sd as specified. Fast (< 5 s).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import chi2, norm

from . import logs, monitor, params, trusted

DT = 0.01
M = monitor.M_CHANNELS
N_REP = 20_000          # independent replicates for the false-alarm tests
N_STEPS = 300           # steps before the test instant: (1 - l)^300 = 3e-3 of the start left
BAND_SIGMA = 4.0        # binomial band: P(|X - np| > 4 sd) ~ 6e-5 (normal approximation)


def _random_factor(rng):
    """A lower-triangular S_zz with positive diagonal and correlated channels."""
    a = rng.normal(size=(M, M))
    return np.linalg.cholesky(a @ a.T + 0.5 * np.eye(M))


def _stationary_stats(th, rng, n_rep=N_REP, n_steps=N_STEPS, s_zz=None, c=0.0):
    """D, M, C of n_rep independent monitors after n_steps innovations that are exactly what
    the model claims: nu = S_zz w, w = sqrt(1 - c) white + sqrt(c) persistent (one draw per
    replicate, held for all steps), so each channel has variance S_rr and persistent share c
    (S_zz = I here keeps the shares per channel exact). Normalised by the claimed S_zz with
    monitor.normalise's algebra, vectorised."""
    s_zz = np.eye(M) if s_zz is None else s_zz
    inv = np.linalg.inv(s_zz)
    diag_sd = np.sqrt(np.einsum("ij,ij->i", s_zz, s_zz))
    persistent = math.sqrt(c) * rng.normal(size=(n_rep, M))
    cc = np.full((n_rep, M), c)
    D, Mm, C = np.full(n_rep, float(M)), np.zeros((n_rep, M)), cc.copy()
    for _ in range(n_steps):
        nu = (math.sqrt(1.0 - c) * rng.normal(size=(n_rep, M)) + persistent) @ s_zz.T
        w = nu @ inv.T
        D, Mm, C = monitor.ewma(D, Mm, C, np.einsum("ij,ij->i", w, w), nu / diag_sd, cc, th)
    return D, Mm, C


def _binomial_band(n, p):
    sd = math.sqrt(n * p * (1.0 - p))
    return n * p - BAND_SIGMA * sd, n * p + BAND_SIGMA * sd


# REQ-MON-001
def test_normalise_matches_the_covariance():
    """d = nu^T (S S^T)^-1 nu, e_r = nu_r / sqrt((S S^T)_rr), c_r = C_rr / (S S^T)_rr, computed
    here with an explicit inverse (rounding only: 1e-12 relative)."""
    rng = np.random.default_rng(1)
    for _ in range(20):
        s = _random_factor(rng)
        nu = rng.normal(size=M)
        cov = s @ s.T
        c_pers = rng.uniform(0, 1, size=M) * np.diag(cov)
        d, e, c = monitor.normalise(nu, s, c_pers)
        assert d == pytest.approx(float(nu @ np.linalg.inv(cov) @ nu), rel=1e-12)
        np.testing.assert_allclose(e, nu / np.sqrt(np.diag(cov)), rtol=1e-12)
        np.testing.assert_allclose(c, c_pers / np.diag(cov), rtol=1e-12)


# REQ-MON-001
@pytest.mark.parametrize("nu", [3.0, 3.5, 12.0, 173.0])
@pytest.mark.parametrize("q", [0.95, 0.9995])
def test_wilson_hilferty_quantile(nu, q):
    """The C-computable chi-square quantile at the effective dofs the monitor meets (173:
    white innovations; 3-12: persistent shares 0.1-1). Measured against scipy's exact ppf,
    Wilson-Hilferty's relative error at nu >= 3 is below 0.6 % at the 95 % point and at the
    99.95 % point (the fire threshold) it lies above the exact value by at most 2.3 %: it
    errs on the side of fewer false alarms. Bounds: |err| <= 0.01 at 95 %, 0 <= err <= 0.025
    at 99.95 %."""
    z = norm.ppf(q)
    exact = chi2.ppf(q, nu)
    wh = float(monitor._chi2_wh_z(nu, z))
    assert wh == pytest.approx(monitor.chi2_quantile_wh(nu, q), rel=1e-12)
    if q < 0.99:
        assert abs(wh / exact - 1.0) <= 0.01
    else:
        assert 0.0 <= wh / exact - 1.0 <= 0.025


# REQ-MON-001
@pytest.mark.parametrize("c", [0.0, 0.3, 1.0])
def test_thresholds_from_the_false_alarm_probability(c):
    """The limits at the defaults, derived here from their definitions independently:
    l = dt / (tau + dt), l' = l / (2 - l), l3 = l^3 / (1 - (1 - l)^3); sigma^2 = c + (1 - c) l';
    cumulants k1 = m, k2 = m (2 sigma^4 + 2 l' (1 - c)^2), k3 = m (8 sigma^6 + 8 l3 (1 - c)^3);
    D_fire = k1 - b nu + b chi2.ppf(1 - p/2, nu), b = k3 / (4 k2), nu = 8 k2^3 / k3^2 (exact
    ppf here: the Wilson-Hilferty form lies within +2.5 % of it at the fire point and 1 % at
    the clear point, test above); M_fire = norm.ppf(1 - p / (4 m)) sqrt(l' (1 - c) + c). At c = 1
    the persistent part is all: D ~ chi2(m) exactly (a = 0, b = 1, nu = m)."""
    p = monitor.MON_DEFAULTS
    th = monitor.thresholds(p, DT)
    lam = DT / (p["mon_tau_nis"] + DT)
    lp, l3 = lam / (2 - lam), lam ** 3 / (1 - (1 - lam) ** 3)
    sig2 = c + (1 - c) * lp
    k2 = M * (2 * sig2 ** 2 + 2 * lp * (1 - c) ** 2)
    k3 = M * (8 * sig2 ** 3 + 8 * l3 * (1 - c) ** 3)
    b, nu = k3 / (4 * k2), 8 * k2 ** 3 / k3 ** 2
    a = M - b * nu
    cc = np.full(M, c)
    got = monitor.pearson(cc, th)
    np.testing.assert_allclose(got, (a, b, nu), rtol=1e-12, atol=1e-12)
    if c == 1.0:
        np.testing.assert_allclose(got, (0.0, 1.0, M), atol=1e-12)
    d_fire, d_clear, m_fire, m_clear = monitor.limits(cc, th)
    rel_fire = (d_fire - a) / (b * chi2.ppf(1 - p["mon_p_fire"] / 2, nu)) - 1.0
    rel_clear = (d_clear - a) / (b * chi2.ppf(1 - p["mon_p_clear"] / 2, nu)) - 1.0
    assert 0.0 <= rel_fire <= 0.025, rel_fire       # the 99.95 % point (test above)
    assert abs(rel_clear) <= 0.01, rel_clear        # the 95 % point (test above)
    sd = math.sqrt(lp * (1 - c) + c)
    np.testing.assert_allclose(m_fire, norm.ppf(1 - p["mon_p_fire"] / (4 * M)) * sd, rtol=1e-12)
    np.testing.assert_allclose(m_clear, norm.ppf(1 - p["mon_p_clear"] / (4 * M)) * sd, rtol=1e-12)
    assert th.hold_steps == 50 and th.warmup_steps == 100
    assert d_clear < d_fire and np.all(m_clear < m_fire)


# REQ-MON-002
@pytest.mark.parametrize("c", [0.0, 0.3])
def test_false_alarm_rate_within_its_binomial_band(c):
    """Innovations exactly as the model claims (white, or with a persistent share c = 0.3 held
    over the whole window): at one instant of N_REP independent monitors (stationary after
    N_STEPS), the NIS test exceeds D_fire with probability p/2 and the three channels' mean
    tests together with p/2 (each two-sided at p/(2m)), so the fire condition holds with
    probability <= p. p = 0.04 here so that the band is narrow (400 expected alarms of each
    test). The NIS count must lie in its 4-sd binomial band (this tests the scaled-chi-square
    approximation with its effective dof), the channels' union between the largest single
    channel and the Bonferroni sum (the channels are dependent when S_zz correlates them)."""
    rng = np.random.default_rng(7)
    p = dict(monitor.MON_DEFAULTS, mon_p_fire=0.04)
    th = monitor.thresholds(p, DT)
    s_zz = _random_factor(rng) if c == 0.0 else None
    D, Mm, C = _stationary_stats(th, rng, s_zz=s_zz, c=c)
    d_fire, _, m_fire, _ = monitor.limits(C, th)
    n_d = int(np.sum(D > d_fire))
    n_m = int(np.sum(np.any(np.abs(Mm) > m_fire, axis=1)))
    n_any = int(np.sum(monitor.over_fire(D, Mm, C, th)))
    lo, hi = _binomial_band(N_REP, 0.02)
    assert lo <= n_d <= hi, (n_d, lo, hi)
    lo_m, _ = _binomial_band(N_REP, 0.02 / M)
    _, hi_m = _binomial_band(N_REP, 0.02)
    assert lo_m <= n_m <= hi_m, (n_m, lo_m, hi_m)
    assert n_any <= _binomial_band(N_REP, 0.04)[1], n_any


# REQ-MON-002
def test_fraction_of_steps_in_mismatch_on_white_innovations():
    """One white sequence of 15 000 steps (150 s) through the defaults' hysteresis. Each
    firing lasts at least the hold (50 steps) plus the excursion of an average with memory
    1/l = 51 steps; p = 1e-3 of the steps exceed a threshold, in runs of tens of steps, so a
    firing every few thousand steps: measured over 600 s, 4 firings per 300 s and 0.9-1.0 %
    of the steps in the mismatch state. Asserted: at most 2 % (the sampling spread of ~2
    firings of ~70 steps in 150 s) and at most 6 firings."""
    rng = np.random.default_rng(11)
    mon = monitor.Monitor(monitor.MON_DEFAULTS, DT)
    n = 15_000
    w = rng.normal(size=(n, M))
    fired = events = 0
    prev = False
    for k in range(n):
        now = mon.step_stats(float(w[k] @ w[k]), w[k])
        fired += now
        events += now and not prev
        prev = now
    print(f"share of steps in mismatch: {fired / n:.4f}, {events} firings")
    assert fired / n <= 0.02 and events <= 6, (fired / n, events)


# REQ-MON-004
def test_warmup_ignores_the_first_steps():
    """The first mon_warmup s (100 steps) of evaluated steps change no statistic, however
    large the innovation; low-speed steps (NaN) do not count; the 101st evaluated step does."""
    mon = monitor.Monitor(monitor.MON_DEFAULTS, DT)
    big, eye = np.full(M, 100.0), np.eye(M)
    for _ in range(20):
        mon.step(np.full(M, np.nan), eye)
    for _ in range(100):
        assert not mon.step(big, eye)
    assert mon.D == M and np.all(mon.M == 0.0)
    assert mon.step(big, eye)


def _first_fire(th, rng, n_rep, scale=1.0, bias=None, n_steps=400):
    """Step index (1-based) at which each of n_rep monitors first exceeds a fire threshold."""
    D, Mm, C = np.full(n_rep, float(M)), np.zeros((n_rep, M)), np.zeros((n_rep, M))
    first = np.full(n_rep, n_steps + 1)
    for k in range(1, n_steps + 1):
        nu = scale * rng.normal(size=(n_rep, M))
        if bias is not None:
            nu = nu + bias
        D, Mm, C = monitor.ewma(D, Mm, C, np.einsum("ij,ij->i", nu, nu), nu, C, th)
        hit = monitor.over_fire(D, Mm, C, th) & (first > n_steps)
        first[hit] = k
    return first


# REQ-MON-003
def test_detection_delay_of_a_bias():
    """A bias of b = 0.6 sd on the ay channel (S_zz = I, white: c = 0). Expected M_ay after k steps:
    b (1 - (1 - l)^k), which crosses M_fire at k* = ln(1 - M_fire / b) / ln(1 - l); its noise
    sd at k* is sigma_k = sqrt(l / (2 - l) (1 - (1 - l)^(2k))), so the crossing scatters by
    about dk = sigma_k / (slope b l (1 - l)^k*). The NIS test alone would need
    E D = m + b^2 = 3.36 < D_fire: the mean test decides. The median delay must lie within
    k* +- 2 dk (the median of a first-passage time sits at or before the mean crossing), and
    the 95th percentile before k* + 4 dk."""
    rng = np.random.default_rng(3)
    th = monitor.thresholds(monitor.MON_DEFAULTS, DT)
    b = 0.6
    lam = th.l_m
    m_fire = float(monitor.limits(np.zeros(M), th)[2][1])
    k_star = math.log(1 - m_fire / b) / math.log(1 - lam)
    sig = math.sqrt(lam / (2 - lam) * (1 - (1 - lam) ** (2 * k_star)))
    dk = sig / (b * lam * (1 - lam) ** k_star)
    first = _first_fire(th, rng, 4000, bias=np.array([0.0, b, 0.0]))
    med, p95 = np.median(first), np.percentile(first, 95)
    assert k_star - 2 * dk <= med <= k_star + 2 * dk, (med, k_star, dk)
    assert p95 <= k_star + 4 * dk, (p95, k_star, dk)


# REQ-MON-003
def test_detection_delay_of_a_variance_excess():
    """Innovations 2x larger than claimed (variance ratio 4, E d = 12). E D_k = 12 - 9 (1 - l)^k
    crosses D_fire at k* = ln((12 - D_fire) / 9) / ln(1 - l); the scatter of D at k* (sd of
    the EWMA of 4 chi2_3: 4 sqrt(6 l / (2 - l)) = 0.97 at stationarity, less before) over the
    slope 9 l (1 - l)^k* gives dk. Median within k* +- 2 dk + 1, 95th percentile <= k* + 4 dk + 1
    (the +1: the delay is an integer step)."""
    rng = np.random.default_rng(5)
    th = monitor.thresholds(monitor.MON_DEFAULTS, DT)
    lam = th.l_d
    d_fire = float(monitor.limits(np.zeros(M), th)[0])
    k_star = math.log((12.0 - d_fire) / 9.0) / math.log(1 - lam)
    sig = 4.0 * math.sqrt(6.0 * lam / (2 - lam) * (1 - (1 - lam) ** (2 * k_star)))
    dk = sig / (9.0 * lam * (1 - lam) ** k_star)
    first = _first_fire(th, rng, 4000, scale=2.0, n_steps=100)
    med, p95 = np.median(first), np.percentile(first, 95)
    assert k_star - 2 * dk - 1 <= med <= k_star + 2 * dk + 1, (med, k_star, dk)
    assert p95 <= k_star + 4 * dk + 1, (p95, k_star, dk)


# REQ-MON-004
def test_hysteresis_holds_then_clears():
    """A burst of large NIS fires the monitor; it stays fired for mon_hold (50 steps) after
    the last exceedance even with zero innovations, and clears on the first step after the
    hold at which D < D_clear and |M| < M_clear."""
    mon = monitor.Monitor(monitor.MON_DEFAULTS, DT)
    d_fire, d_clear, _, _ = monitor.limits(np.zeros(M), mon.th)
    zero = np.zeros(M)
    for _ in range(100):
        assert not mon.step_stats(3.0, zero)          # D stays at m = 3 < D_clear
    steps = 0
    while not mon.step_stats(100.0, zero):
        steps += 1
    assert steps < 5                                   # D jumps by l (100 - 3) ~ 1.9 per step
    last_over = None
    for k in range(1, 400):
        fired = mon.step_stats(0.0, zero)
        if mon.D > d_fire:
            last_over = k
        if not fired:
            break
    # D decays from above D_fire; the clear needs hold steps after the last exceedance and
    # D < D_clear (here D already falls below D_clear within the hold)
    assert k == last_over + mon.th.hold_steps
    assert mon.D < d_clear


# REQ-MON-004
def test_apply_acts_on_valid_status_and_sd():
    """apply(): while fired every valid flag is 0, status 0/1/3 becomes 4 and sd is multiplied
    by sqrt(D / m), at every step, low speed included (docs/MONITOR.md §2 item 7); a low-speed
    step (status 2, no innovation) keeps its status and leaves the statistics as they were."""
    n = 300
    rng = np.random.default_rng(9)
    nu = rng.normal(size=(n, M))
    nu[100:150] *= 4.0                                  # variance ratio 16 for 0.5 s
    status = np.zeros(n, dtype=int)
    status[10:20] = 2
    nu[10:20] = np.nan
    status[140:145] = 2                                 # low speed while fired
    nu[140:145] = np.nan
    status[200:210] = 3
    res = {"t": np.arange(n) * DT, "mu": np.full((n, 4), 0.5), "sd": np.full((n, 4), 0.05),
           "valid": np.ones((n, 4), dtype=int), "status": status, "nu": nu,
           "s_zz": np.broadcast_to(np.eye(M), (n, M, M)).copy(), "c_pers": np.zeros((n, M))}
    out = monitor.apply(res, monitor.MON_DEFAULTS, DT)
    f = out["fired"]
    assert f[100:150].any() and not f[:100].any()
    assert np.all(out["valid"][f] == 0) and np.all(out["valid"][~f] == 1)
    low = status == 2
    assert f[140:145].all()                             # the burst keeps it fired
    assert np.all(out["status"][f & ~low] == monitor.STATUS_MISMATCH)
    assert np.all(out["status"][low] == 2)              # low speed keeps its status
    assert np.all(out["status"][~f] == status[~f])
    c = np.sqrt(np.maximum(1.0, out["D"][f] / M))
    assert c.max() > 1.5                                # the burst's variance ratio shows
    np.testing.assert_allclose(out["sd"][f], 0.05 * np.repeat(c[:, None], 4, 1), rtol=1e-12)
    np.testing.assert_array_equal(out["sd"][~f], 0.05)
    np.testing.assert_array_equal(out["D"][10:20], out["D"][9])   # frozen at low speed
    # the cap: with sd 0.3 the inflated sd 0.3 c would pass (mu_max - mu_min) / 2 = 0.575
    # (the library's bounds) where c > 1.92; there it is the cap, elsewhere 0.3 c
    res["sd"] = np.full((n, 4), 0.3)
    out = monitor.apply(res, monitor.MON_DEFAULTS, DT)
    cap = 0.5 * (params.DEFAULTS["mu_max"] - params.DEFAULTS["mu_min"])
    over = 0.3 * c > cap
    assert over.any() and (~over).any()
    np.testing.assert_allclose(out["sd"][f][over], cap, rtol=0, atol=0)
    np.testing.assert_allclose(out["sd"][f][~over], 0.3 * np.repeat(c[~over, None], 4, 1),
                               rtol=1e-12)


# REQ-MON-005
def test_recorded_innovation_is_y_minus_the_prediction(tmp_path):
    """trusted.run records nu = y - z_hat at every step with a measurement evaluation. With
    the paper preset (h = H(u) x linear, no input filter) z_hat = H(u_k) x_(k-1) exactly
    (the cubature points are symmetric about the mean), computed here from model.py's H and
    the previous posterior mean (1e-12: rounding of the point average)."""
    from . import model
    path = "scenarios/paper_low_mu_brake.csv"
    log = logs.read_csv_log(path)
    log.columns = {k: v[:120] for k, v in log.columns.items()}
    p = params.resolve(log.meta, None, source=path, preset="paper")
    p["structure"] = "wheels"
    res = trusted.run(log, p)
    ti = model.tyre_inputs(p, log.col("delta"), log.col("vx"), log.col("vy"), log.col("yaw_rate"),
                           log.col("ax"), log.col("ay"), log.omega())
    H = model.observation_matrix(p, ti)
    y = np.stack([log.col("ax"), log.col("ay"), log.col("yaw_acc")], -1)
    x_prev = np.vstack([np.full(4, p["mu0"]), res["mu_unprojected"][:-1]])
    x_prev[1:] = res["mu"][:-1]
    ok = np.all(np.isfinite(res["nu"]), axis=1)
    assert ok.sum() > 100
    for k in np.flatnonzero(ok):
        np.testing.assert_allclose(res["nu"][k], y[k] - H[k] @ x_prev[k], atol=1e-12)
