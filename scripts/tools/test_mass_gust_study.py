"""scripts/tools/mass_gust_study.py: the gust model's parameters follow from the documented wind
law, the gust state relaxes as a Gauss-Markov process, the filter learns mass and a constant
force on a drive with gusts, and the information bound is the textbook least-squares sd in the
white-noise limit."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mass_gust_study as gs  # noqa: E402
from mass_gust_study import mg, mos  # noqa: E402

M_TRUE = 1800.0
DT = 0.02


def autocorr(lag):
    # the documented gusts 3 sin(2 pi t / 7) + 1.5 sin(2 pi t / 2.3 + 1): a sum of sines has
    # the autocorrelation sum (A^2 / 2) cos(2 pi lag / T) over its variance sum A^2 / 2
    return ((4.5 * math.cos(2.0 * math.pi * lag / 7.0)
             + 1.125 * math.cos(2.0 * math.pi * lag / 2.3)) / 5.625)


def test_gust_parameters_follow_from_the_wind_law():
    assert math.isclose(gs.SIGMA_W, math.sqrt(5.625), rel_tol=1e-12)
    # tau is the first lag where the autocorrelation falls to 1/e: on the grid of 1e-4 s the
    # value at tau is below 1/e and the value 1e-4 s earlier above it
    assert autocorr(gs.GUST_TAU) < math.exp(-1.0) < autocorr(gs.GUST_TAU - 1e-4)
    assert 0.9 < gs.GUST_TAU < 1.0
    # sd_G at the operating point: 2 k (v + W) sigma_w, k = 0.5 1.2 0.30 2.2 = 0.396
    p = mg.preset("car")
    assert math.isclose(gs.sd_g_fixed(p), 2.0 * 0.396 * 35.0 * math.sqrt(5.625), rel_tol=1e-12)


def test_sd_from_f_is_the_fixed_sd_at_the_operating_point_and_zero_without_wind():
    p = mg.preset("car", **mg.MG_CONFIGS["recommended"])
    est = gs.MassGradeGust(p, "from F")
    k = 0.396
    f = k * (2.0 * 25.0 * 10.0 + 100.0)     # a 10 m/s headwind's extra drag at 25 m/s
    # W recovered from F is 10 m/s and sigma_w = I W = 2.37 m/s: the fixed sd (rounding only)
    assert math.isclose(est.sd_g(25.0, f), gs.sd_g_fixed(p), rel_tol=1e-9)
    assert est.sd_g(25.0, 0.0) == 0.0 and est.sd_g(25.0, -50.0) == 0.0


def test_hold_relaxes_the_gust_as_a_gauss_markov_process():
    # one held sample of dt: G's mean times phi = exp(-dt / tau), its variance
    # phi^2 P_GG + sd_G^2 (1 - phi^2), its covariances with M and F times phi, and M's and F's
    # own (co)variances unchanged
    p = mg.preset("car", **mg.MG_CONFIGS["recommended"])
    est = gs.MassGradeGust(p, "fixed")
    est.step(mg.MgSample(0.0, 20.0, 300.0, ax=0.0))
    est.x = [20.0, 1800.0, 100.0, 40.0, 0.01]
    est.S = [[0.05, 0, 0, 0, 0], [3.0, 40.0, 0, 0, 0], [1.0, -5.0, 50.0, 0, 0],
             [0.5, 2.0, -10.0, 30.0, 0], [0.001, -0.002, 0.0, 0.001, 0.004]]
    S0 = [list(r) for r in est.S]
    P0 = np.array(S0) @ np.array(S0).T
    dt = 0.02
    assert est._hold_sqrt(mg.MgSample(dt, 20.1, 0.0, ax=0.0), dt) == mg.OK
    P1 = np.array(est.S) @ np.array(est.S).T
    phi = math.exp(-dt / gs.GUST_TAU)
    sd = gs.sd_g_fixed(p)
    assert math.isclose(est.x[gs.IG], 40.0 * phi, rel_tol=1e-15)
    # the triangularisation's rounding: 1e-9 relative to the entries (of order 1e3 N^2)
    assert abs(P1[3, 3] - (phi * phi * P0[3, 3] + sd * sd * (1.0 - phi * phi))) < 1e-9 * 1e3
    for j in (1, 2):
        assert abs(P1[3, j] - phi * P0[3, j]) < 1e-9 * 1e3
    for i, j in ((1, 1), (1, 2), (2, 2)):
        assert abs(P1[i, j] - P0[i, j]) < 1e-9 * 2e3


def gusty_drive(f_const, gust_amp, seconds=60.0):
    """mass_offset_study's synthetic drive (flat, torque a 10 s sine about 300 N m) with a
    constant extra force f_const and a 7 s sinusoidal gust force of amplitude gust_amp [N];
    no noise, a_x = v-dot."""
    p = mg.preset("car", **mg.MG_CONFIGS["recommended"])
    v, out = 20.0, []
    for k in range(int(seconds / DT) + 1):
        t = k * DT
        torque = 300.0 + 200.0 * math.sin(2.0 * math.pi * t / 10.0)
        f = f_const + gust_amp * math.sin(2.0 * math.pi * t / 7.0)
        a = mos.accel_f(p, v, M_TRUE, f, 0.0, torque)
        out.append(mg.MgSample(t, v, torque, ax=a))
        v += DT * a
    return p, out


def test_gust_filter_learns_mass_and_force_on_a_gusty_drive():
    # 200 N constant plus an 80 N 7 s gust (the headwind's 7 s gust moves the drag by 83 N)
    # over 120 s: the reference takes the force for mass (more than 10 % off: 200 N of about
    # 920 N of drive force); the F + G filter ends within issue 19's 2 % (noise-free) and F
    # within 20 N of 200 N (10 %, as mass_offset_study's test)
    p, samples = gusty_drive(200.0, 80.0, seconds=120.0)
    p = dict(p, mg_m0=M_TRUE * 1.2)
    ref, off = mg.MassGrade(p), mos.MassGradeOffset(p, gs.SD_F0, gs.Q_F)
    est = gs.MassGradeGust(p, "fixed")
    for s in samples:
        e, e_ref, e_off = est.step(s), ref.step(s), off.step(s)
    assert e.status == mg.OK
    assert abs(e_ref.mass - M_TRUE) / M_TRUE > 0.10
    assert abs(e.mass - M_TRUE) / M_TRUE < 0.02
    assert abs(est.x[gs.IF] - 200.0) < 20.0
    assert len(est.sd) == gs.NX and all(math.isfinite(v) for v in est.sd)
    # the gust state's price: it takes part of what the a_x row says, so the mass's sd stays
    # above F alone's (measured 31.7 against 11.5 kg; asserted only as larger by half)
    assert e.sd_mass > 1.5 * e_off.sd_mass


def test_gust_filter_leaves_a_still_drive_alone():
    # no extra force, sd_G from F: G's sd is 0 while F is not positive, and the mass ends
    # within 1 % (the offset study's bound for the same drive), F within 20 N of 0
    p, samples = gusty_drive(0.0, 0.0)
    p = dict(p, mg_m0=M_TRUE * 0.8)
    est = gs.MassGradeGust(p, "from F")
    for s in samples:
        e = est.step(s)
    assert abs(e.mass - M_TRUE) / M_TRUE < 0.01
    assert abs(est.x[gs.IF]) < 20.0


def test_bound_is_ordinary_least_squares_in_the_white_noise_limit():
    # tau far below the sample period makes Sigma = sd^2 I: the GLS fit is the OLS fit and
    # its sd the textbook sd sqrt((X^T X)^-1_MM) sd; on exact data the mass is the truth
    n = 501
    t = np.arange(n) * DT
    v = 20.0 + 2.0 * np.sin(2.0 * np.pi * t / 10.0)
    p = mg.preset("car")
    a = np.gradient(v, t)
    x = a + p["g"] * (p["mg_fc"] + p["mg_fr"] * v)
    f_true = 150.0
    y = M_TRUE * x + f_true
    torque = (y + 0.5 * 1.2 * 0.30 * 2.2 * v * v + p["mg_m_rot"] * a) * p["R"]
    cols = {"t": t, "vx_true": v, "grade_true": np.zeros(n), "mass_true": np.full(n, M_TRUE),
            "drive_torque": torque}
    err, sd, f = gs.gls_bound(cols, p, t[-1], 66.0, 1e-6)
    assert abs(err) < 1e-6 and abs(f - f_true) < 1e-6    # exact data: rounding only
    X = np.column_stack([x, np.ones(n)])
    sd_ols = 66.0 * math.sqrt(np.linalg.inv(X.T @ X)[0, 0]) / M_TRUE * 100.0
    assert math.isclose(sd, sd_ols, rel_tol=1e-6)
    # a correlated gust (tau 1 s) carries less information than white noise of the same sd
    assert gs.gls_bound(cols, p, t[-1], 66.0, 1.0)[1] > sd


def test_whitened_bound_equals_the_dense_one():
    # gls_ar1 (AR(1) whitening) and gls_bound without a_x noise (the dense covariance) are
    # two derivations of the same GLS fit: equal to rounding (1e-6 relative: a 251 x 251
    # solve of a covariance whose condition grows with tau / dt)
    n = 251
    t = np.arange(n) * DT
    v = 20.0 + 2.0 * np.sin(2.0 * np.pi * t / 10.0)
    p = mg.preset("car")
    gust = 60.0 * np.sin(2.0 * np.pi * t / 7.0)
    a = np.gradient(v, t)
    x = a + p["g"] * (p["mg_fc"] + p["mg_fr"] * v)
    torque = ((M_TRUE * x + 150.0 + gust) + 0.5 * 1.2 * 0.30 * 2.2 * v * v
              + p["mg_m_rot"] * a) * p["R"]
    cols = {"t": t, "vx_true": v, "grade_true": np.zeros(n), "mass_true": np.full(n, M_TRUE),
            "drive_torque": torque}
    dense = gs.gls_bound(cols, p, t[-1], 66.0, 1.0)
    white = gs.gls_ar1(cols, p, t[-1], 66.0, 1.0)
    for d, w in zip(dense, white):
        assert math.isclose(d, w, rel_tol=1e-6)


def test_table_lists_every_start_and_takes_the_worst_end():
    res = {}
    for v in gs.VARIANTS:
        for k, g in enumerate(gs.mgr.GUESSES):
            res[("car_x", g, v)] = {"err10": (-1.0) ** k * k, "err_after": 0.5 * k,
                                    "err_end": -0.1 * k, "rmse": 0.1 * (k + 1)}
    lines = gs.table(res, ["car_x"]).strip().split("\n")
    assert len(lines) == 2 + len(gs.VARIANTS)
    row = lines[2].split(" | ")
    # starts k = 0..3 in GUESSES' order: err10 0, -1, 2, -3; largest 1.5; end -0.3; rmse 0.4
    assert row[2] == "+0.00 / -1.00 / +2.00 / -3.00 %"
    assert row[3] == "1.50 %" and row[4] == "-0.30 %" and row[5] == "0.400 deg"
    assert row[1] == "without (the reference)" and row[6] == "– |"
