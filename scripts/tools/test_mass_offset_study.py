"""scripts/tools/mass_offset_study.py: its force-offset filter learns an unmodelled constant force
that the reference's filter takes for mass, leaves a log without one alone, and its table takes
the worst of the four starts."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mass_offset_study as os_  # noqa: E402
from mass_offset_study import mg  # noqa: E402

M_TRUE = 1800.0
DT = 0.02


def drive(f_extra, seconds=60.0, amp=200.0):
    """A straight flat drive integrated with the study's own model (accel_f, the car preset's
    resistances and rotating mass), an extra force f_extra [N] on the car the whole time, the
    drive torque a 10 s sine of amplitude amp [N m] about 300 N m so that a_x varies (what separates M from F); no
    noise. Returns MgSamples with a_x = v-dot (flat road)."""
    p = mg.preset("car", **mg.MG_CONFIGS["recommended"])
    v, out = 20.0, []
    for k in range(int(seconds / DT) + 1):
        t = k * DT
        torque = 300.0 + amp * math.sin(2.0 * math.pi * t / 10.0)
        a = os_.accel_f(p, v, M_TRUE, f_extra, 0.0, torque)
        out.append(mg.MgSample(t, v, torque, ax=a))
        v += DT * a
    return p, out


def run(est, samples):
    for s in samples:
        e = est.step(s)
    return e


def test_offset_state_learns_the_force_the_reference_takes_for_mass():
    p, samples = drive(200.0)
    p = dict(p, mg_m0=M_TRUE * 1.2)
    base = run(mg.MassGrade(p), samples)
    off_est = os_.MassGradeOffset(p, 300.0, 2.0)
    off = run(off_est, samples)
    # the reference explains 200 N with mass: at 300 N m / 0.325 m about 920 N of drive
    # force, a mass error of the order of 200 / 920 ~ 20 % (more than 5 % whatever a_x's mix)
    assert abs(base.mass - M_TRUE) / M_TRUE > 0.05
    # the offset filter: within 1 % of the mass (issue 19's 2 % target, halved: noise-free)
    # and the force within 10 % of 200 N (its walk, 2 N/sqrt(s), moves it by ~15 N over 60 s
    # when unexcited; the sine excites it)
    assert abs(off.mass - M_TRUE) / M_TRUE < 0.01
    assert abs(off_est.x[os_.IF] - 200.0) < 20.0
    assert abs(off.grade) < 1e-3          # a flat road stays flat (1 mrad)


def test_offset_state_stays_near_zero_without_an_extra_force():
    p, samples = drive(0.0)
    p = dict(p, mg_m0=M_TRUE * 0.8)
    est = os_.MassGradeOffset(p, 300.0, 2.0)
    e = run(est, samples)
    # nothing to learn: the force within 20 N of 0 (1 % of the drive force's swing, 600 N)
    # and the mass within 1 %
    assert abs(est.x[os_.IF]) < 20.0
    assert abs(e.mass - M_TRUE) / M_TRUE < 0.01


def test_offset_filter_refuses_what_it_does_not_implement():
    p = mg.preset("car", **mg.MG_CONFIGS["recommended"])
    try:
        os_.MassGradeOffset(dict(p, mg_ut_alpha=0.5), 300.0, 2.0)
    except ValueError:
        pass
    else:
        raise AssertionError("alpha != 1 accepted")


def test_gated_filter_is_the_reference_until_the_ax_row_shows_a_bias():
    # without an extra force the ax row's mean normalised innovation stays inside the
    # threshold: every estimate equals the reference's, bit for bit (the same code runs)
    p, samples = drive(0.0, seconds=30.0)
    p = dict(p, mg_m0=M_TRUE * 0.8)
    ref, gated = mg.MassGrade(p), os_.MassGradeOffsetGated(p, 300.0, 2.0, 0.1)
    for s in samples:
        assert ref.step(s) == gated.step(s)
    assert not gated.released


def test_gated_filter_releases_the_force_on_a_biased_drive_and_learns_it():
    # 200 N the model does not know: the reference takes it for mass, so its ax row's
    # innovation is biased over the sine's phases; the test releases F once its 10 s window is
    # formed (>= 5 s of updates) and F then takes the force (within 10 %) and the mass ends
    # within 1 % (the always-on test's bounds)
    p, samples = drive(200.0, seconds=120.0)
    p = dict(p, mg_m0=M_TRUE * 1.2)
    est = os_.MassGradeOffsetGated(p, 300.0, 2.0, 0.1, ax_sd_min=0.15)
    e = run(est, samples)
    assert est.released and 5.0 <= est.t_release < 60.0
    assert abs(est.x[os_.IF] - 200.0) < 20.0
    assert abs(e.mass - M_TRUE) / M_TRUE < 0.01


def test_gated_filter_needs_the_excitation_to_release():
    # the biased drive above, whose a_x sd over the window is about 0.2 m/s^2 (615 N of drive
    # force's swing over 2000 kg: amplitude 0.3, sd 0.3 / sqrt(2)): released with the gate at
    # 0.15 (the test above); with the gate at 0.25, above that sd, the bias test fires but F
    # stays closed and every estimate is the reference's
    p, samples = drive(200.0, seconds=60.0)
    p = dict(p, mg_m0=M_TRUE * 1.2)
    ref = mg.MassGrade(p)
    gated = os_.MassGradeOffsetGated(p, 300.0, 2.0, 0.1, ax_sd_min=0.25)
    for s in samples:
        assert ref.step(s) == gated.step(s)
    assert not gated.released


def test_release_adds_only_the_mass_variance():
    # P' = P + (sd_m_add M)^2 e_M e_M^T in [v, M, F, theta], F uncorrelated with sd_f0
    p = mg.preset("car", **mg.MG_CONFIGS["recommended"])
    est = os_.MassGradeOffsetGated(p, 300.0, 2.0, 0.1)
    est.x = [20.0, 1800.0, 0.01]
    est.S = [[0.05, 0.0, 0.0], [3.0, 40.0, 0.0], [0.001, -0.002, 0.004]]
    P3 = [[sum(est.S[i][k] * est.S[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    est._release(1.0)
    S = est.S
    P4 = [[sum(S[i][k] * S[j][k] for k in range(4)) for j in range(4)] for i in range(4)]
    idx = (0, 1, 3)
    for a in range(3):
        for b in range(3):
            add = (0.1 * 1800.0) ** 2 if a == b == 1 else 0.0
            # the triangularisation's rounding: a few ulps of the largest term (3.4e4 kg^2)
            assert abs(P4[idx[a]][idx[b]] - (P3[a][b] + add)) <= 1e-9 * (1.0 + abs(P3[a][b] + add))
    assert P4[2][2] == 300.0 ** 2 and all(P4[2][j] == 0.0 for j in (0, 1, 3))
    assert est.x == [20.0, 1800.0, 0.0, 0.01]


def test_table_takes_the_worst_start():
    res = {}
    for v in [None] + list(os_.VARIANTS):
        for k, g in enumerate(os_.mgr.GUESSES):
            res[("car_x", g, v, None)] = {"err10": (-1.0) ** k * k, "err_after": 0.5 * k,
                                          "err_end": 0.1 * k, "rmse": 0.1 * (k + 1),
                                          "f_end": 10.0 * k, "t_release": None}
    lines = os_.table(res, ["car_x"]).strip().split("\n")
    assert len(lines) == 2 + 1 + len(os_.VARIANTS)
    row = lines[3].split(" | ")
    # starts k = 0..3: err10 0, -1, 2, -3 (worst -3), largest 1.5, end 0.3, rmse 0.4, F 0..30 N
    assert row[2] == "-3.00 %" and row[3] == "1.50 %" and row[4] == "+0.30 %"
    assert row[5] == "0.400 deg" and row[7] == "+0 … +30 N |"
    # the gated row: never released on any start
    assert lines[-1].endswith("| never released |")


def test_curve_empties_the_bias_test_window():
    # the biased drive the gated filter releases on (above), with one a_y sample every 4 s:
    # at 1.0 m/s^2, above ay_reset 0.5, each empties the 10 s window, which then never holds
    # the 5 s of updates the test needs, so F stays closed and every estimate is the
    # reference's (the recommended preset has no curve pause: the reference ignores a_y);
    # at 0.3 m/s^2, below ay_reset, the same drive releases as without a_y
    p, samples = drive(200.0, seconds=60.0)
    p = dict(p, mg_m0=M_TRUE * 1.2)

    def with_ay(ay):
        return [mg.MgSample(s.t, s.v, s.torque, ax=s.ax,
                            ay=ay if round(s.t / DT) % round(4.0 / DT) == 0 else 0.0)
                for s in samples]

    ref = mg.MassGrade(p)
    safe = os_.MassGradeOffsetGated(p, 300.0, 2.0, 0.1, ax_sd_min=0.15, ay_reset=0.5)
    for s in with_ay(1.0):
        assert ref.step(s) == safe.step(s)
    assert not safe.released
    safe = os_.MassGradeOffsetGated(p, 300.0, 2.0, 0.1, ax_sd_min=0.15, ay_reset=0.5)
    plain = os_.MassGradeOffsetGated(p, 300.0, 2.0, 0.1, ax_sd_min=0.15)
    run(safe, with_ay(0.3))
    run(plain, samples)
    assert safe.released and safe.t_release == plain.t_release


def test_key_table_shows_both_gates():
    res = {}
    for k, key in enumerate(os_.KEY_ERRORS):
        res[("car_x", -0.2, None, key)] = {"err_end": 1.0 + k, "err_after": 2.0,
                                           "t_release": None, "f_end": None}
        res[("car_x", -0.2, os_.GATED_ALL[0], key)] = {"err_end": 30.0, "err_after": 31.0,
                                                       "t_release": 46.9, "f_end": 183.0}
        res[("car_x", -0.2, os_.GATED_ALL[1], key)] = {"err_end": 1.0 + k, "err_after": 2.0,
                                                       "t_release": None, "f_end": None}
    lines = os_.key_table(res, ["car_x"]).strip().split("\n")
    assert len(lines) == 2 + len(os_.KEY_ERRORS)
    row = lines[2].split(" | ")
    assert row[2:5] == ["+1.00 %", "+30.00 %", "+1.00 %"]
    assert row[8] == "46.9 s (+183 N at the end)" and row[9] == "never |"


def _truth_cols(samples):
    """The truth columns ls_split reads, from the synthetic drive (flat: grade 0)."""
    return {"t": np.array([s.t for s in samples]), "vx_true": np.array([s.v for s in samples]),
            "grade_true": np.zeros(len(samples)), "mass_true": np.full(len(samples), M_TRUE),
            "drive_torque": np.array([s.torque for s in samples])}


def test_ls_split_separates_a_constant_force_on_an_excited_drive():
    # the drive's model is ls_split's (accel_f, flat), so with F fitted the fit returns the
    # truth; its only error is v-dot's central difference (np.gradient) of Euler steps, half a
    # step's change of a (0.02 s x 0.2 m/s^3 = 4e-3 m/s^2 at most, about zero on average over
    # the sine): measured 0.002 % and 0.02 N, so 0.05 % and 1 N. Without F the 200 N must go
    # into the mass: 200 N over the mean regressor a + g f (~0.17 m/s^2 x 1800 kg = 300 N)
    # is of the order of +20 %, so more than +10 %
    p, samples = drive(200.0, seconds=60.0)
    for t1 in (10.0, 60.0):
        e0, e1, f1 = os_.ls_split(_truth_cols(samples), p, t1)
        assert e0 > 10.0
        assert abs(e1) < 0.05 and abs(f1 - 200.0) < 1.0
    p, samples = drive(0.0, seconds=20.0)
    e0, e1, f1 = os_.ls_split(_truth_cols(samples), p, 10.0)
    assert abs(e0) < 0.05 and abs(e1) < 0.05 and abs(f1) < 1.0


def test_early_variants_build_their_filters():
    p = mg.preset("car", **mg.MG_CONFIGS["recommended"])
    _, samples = drive(0.0, seconds=0.1)
    prior = os_.make(p, os_.EARLY[2])
    assert isinstance(prior, os_.MassGradeOffset)
    prior.step(samples[0])
    assert prior.x[os_.IF] == os_.EARLY[2][2] and prior.S[os_.IF][os_.IF] == os_.EARLY[2][0]
    fast = os_.make(p, os_.EARLY[-1])
    assert isinstance(fast, os_.MassGradeOffsetGated)
    assert (fast.window, fast.threshold, fast.ay_reset) == (2.0, 0.396, 0.5)
    # the default prior mean stays 0 (the tables above: F starts at 0)
    plain = os_.make(p, (300.0, 2.0))
    plain.step(samples[0])
    assert plain.x[os_.IF] == 0.0


def test_early_table_lists_every_start():
    res = {}
    for v in os_.EARLY:
        for k, g in enumerate(os_.mgr.GUESSES):
            rel = 1.0 if (v is not None and len(v) > 5 and k < 2) else None
            res[("car_x", g, v, None)] = {"err10": k - 1.5, "err_after": 3.0, "err_end": 0.5,
                                          "rmse": 0.2, "f10": 10.0 * k if v else None,
                                          "t_release": rel}
    lines = os_.early_table(res, ["car_x"]).strip().split("\n")
    assert len(lines) == 2 + len(os_.EARLY)
    row = lines[2].split(" | ")
    assert row[2] == "-1.50 / -0.50 / +0.50 / +1.50 %" and row[3] == "–"
    assert lines[-1].endswith("| 1.0–1.0 s (2 of 4) |")
    assert lines[3].split(" | ")[3] == "+0 … +30 N"
    line = os_.fast_release_line(res, ["car_x"])
    assert "car_x (2 of 4 starts; -1.50 % at 10 s, +0.50 % at the end)" in line
