"""trust_rules_study.py's rules and verdict on hand-made series (no reference run)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import trust_rules_study as trs  # noqa: E402


def test_stale_wheel_only_when_the_others_move():
    """Wheel fl follows the others (0.1 rad/s per sample) until sample 4, then repeats its
    value: its reference is the others' median at sample 4 (10.4), which moves 0.1, 0.2, 0.3
    at samples 5, 6, 7, so with delta 0.25 it is stale from sample 7 on."""
    k = np.arange(12)
    omega = np.repeat((10.0 + 0.1 * k)[:, None], 4, 1)
    omega[5:, 0] = omega[4, 0]
    ok = trs.rule_stale(omega, 0.25)
    assert ok[:7].all() and not ok[7:].any()


def test_still_or_resting_wheels_are_not_stale():
    """Four equal, constant wheel speeds (a noise-free cruise) and a wheel at 0 (locked) while
    the others decelerate: nothing is stale."""
    assert trs.rule_stale(np.full((50, 4), 68.376), 0.25).all()
    omega = np.repeat((60.0 - 0.5 * np.arange(30))[:, None], 4, 1)
    omega[10:, 1] = 0.0
    assert trs.rule_stale(omega, 0.25).all()


def test_yaw_spike_replaced_by_the_prediction():
    """r = c t with a measured r_dot = c: every sample is its own prediction (no replacement).
    A +0.5 rad/s spike at one sample is replaced by c t there, and the next sample, again on
    the line, is kept."""
    t = 0.01 * np.arange(100)
    c = 0.3
    r = c * t
    out, n = trs.yaw_substitute(t, r, np.full_like(t, c), 0.1)
    assert n == 0 and np.array_equal(out, r)
    r_spiked = r.copy()
    r_spiked[40] += 0.5
    out, n = trs.yaw_substitute(t, r_spiked, np.full_like(t, c), 0.1)
    assert n == 1
    # the prediction sums dt c per step from r_0: equal to c t up to rounding (1e-12 >> the
    # 1e-16 relative rounding of 100 additions of numbers below 1)
    assert out[40] == pytest.approx(c * t[40], abs=1e-12)
    assert np.array_equal(np.delete(out, 40), np.delete(r, 40))


def test_updates_share_per_side():
    """Every step updates (status 0); side 0 has information 30 >= 25, side 1 has 10. With
    tau = dt (lambda 1/2) side 0's share is 1 - 2^-(k+1): >= 0.7 from k = 1 on; side 1 never
    qualifies. A low-speed step (status 2) leaves the shares alone."""
    status = np.array([0, 0, 2, 0])
    info = np.tile([30.0, 10.0], (4, 1))
    ok = trs.rule_updates(status, info, 0.01, 0.7, 25.0, 0.01)
    assert ok[:, 0].tolist() == [False, True, True, True]
    assert not ok[:, 1].any()


def test_figures_and_verdict():
    """Two settled wheel-samples valid with errors 0.1 (sd 0.1) and 0.3 (sd 0.1): RMSE
    sqrt(0.05), consistency 1/2, worst 0.3: not met; valid on none: met. The verdict counts
    the gain, and the excited-valid fall on a log that met the invariant before."""
    mu = np.array([[0.5, 0.5, 0.5, 0.5]] * 2)
    truth = np.array([[0.4, 0.5, 0.5, 0.5], [0.5, 0.8, 0.5, 0.5]])
    sd = np.full((2, 4), 0.1)
    valid = np.array([[1, 0, 0, 0], [0, 1, 0, 0]], dtype=bool)
    util = np.full((2, 4), 0.6)
    s = np.ones((2, 4), dtype=bool)
    f = trs.figures(mu, sd, valid, truth, util, s)
    assert f["rmse"] == pytest.approx(np.sqrt(0.05)) and f["cons"] == 0.5
    assert f["worst"] == pytest.approx(0.3) and not f["meets"]
    none = trs.figures(mu, sd, np.zeros((2, 4), dtype=bool), truth, util, s)
    assert none["meets"] and none["exc"] == 0.0
    # log a: valid on its one wheel-sample with no error (sample 1, wheel 0) before, on none
    # after: met both times, excited-valid 1/8 -> 0; log b: f before, nothing valid after
    ok_a = np.zeros((2, 4), dtype=bool)
    ok_a[1, 0] = True
    a_before = trs.figures(mu, sd, ok_a, truth, util, s)
    assert a_before["meets"] and a_before["exc"] == pytest.approx(1 / 8)
    base = {"a": dict(a_before, mismatch=0.0), "b": dict(f, mismatch=0.0)}
    v = trs.verdict(base, {"a": dict(none, mismatch=0.0), "b": dict(none, mismatch=0.02)})
    assert v["gained"] == ["b"] and v["lost"] == [] and v["meets"] == 2
    assert v["drop"] == pytest.approx(1 / 8) and v["drop_log"] == "a"
    assert v["false_alarm"] == 0.0  # neither name is a clean Magic Formula log (*.mf)
    v = trs.verdict({"x.mf": dict(none, mismatch=0.0)}, {"x.mf": dict(none, mismatch=0.02)})
    assert v["false_alarm"] == 0.02


def test_upper_evidence_sum_reset_and_fade():
    """Side 0 gets Lambda = 1 at every update, side 1 gets 0. With n_mem = 1e9 (rho = 1 to
    1e-9) L_0 counts the updates: 1, 2, (held: 2), 3 and passes l_min = 2.5 only at the last
    step; side 1 never passes. A reset at step 2 restarts the count (0, then 1). A fade over
    d_mem = ds / ln 2 halves L at every step before the update adds: 1, 1.5, 0.75, 1.375."""
    lam = np.tile([1.0, 0.0], (4, 1))
    upd = np.array([True, True, False, True])
    ok = trs.rule_evidence(lam, upd, 1e9, 2.5)
    assert ok[:, 0].tolist() == [False, False, False, True] and not ok[:, 1].any()
    ok = trs.rule_evidence(lam, upd, 1e9, 0.5, reset=np.array([False, False, True, False]))
    assert ok[:, 0].tolist() == [True, True, False, True]
    ds = np.full(4, 1.0)
    ok = trs.rule_evidence(lam, upd, 1e9, 1.2, ds=ds, d_mem=1.0 / np.log(2.0))
    assert ok[:, 0].tolist() == [False, True, False, True]


def test_bound_margin():
    """mu 0.05 + 3 sd exactly passes with k = 3 (>=), a hair less does not; k = 0 is step 9's
    bound itself (every mean on or above mu_min passes)."""
    mu = np.array([[0.05 + 3 * 0.02, 0.05 + 3 * 0.02 - 1e-9, 0.05, 0.6]])
    sd = np.full((1, 4), 0.02)
    assert trs.rule_bound_margin(mu, sd, 0.05, 3.0).tolist() == [[True, False, False, True]]
    assert trs.rule_bound_margin(mu, sd, 0.05, 0.0).all()


def _braking_inputs(kappa):
    """One straight-line sample at 20 m/s, every wheel at slip kappa (the default preset's
    vehicle keys: R from params.DEFAULTS)."""
    p = trs.params.resolve(None, None, preset="default")
    vx = 20.0
    u = np.array([[0.0, vx, 0.0, 0.0, -3.0, 0.0] + [vx * (1.0 + kappa) / p["R"]] * 4])
    return p, u


def test_point_fit_is_a_quadratic_form_zero_at_the_model():
    """y = h(x, u) fits exactly (q = 0 to rounding); q is a quadratic form in the residual, so
    doubling a residual e multiplies q by 4 (R depends on x and u only)."""
    p, u = _braking_inputs(-0.05)
    x = np.array([[0.5, 0.5]])
    y0 = trs.trusted.h_points(p, u, x @ trs.trusted.WHEELS_OF_SIDES.T)
    assert trs.point_fit(p, u, x, y0)[0] == pytest.approx(0.0, abs=1e-20)
    e = np.array([[0.3, -0.1, 0.05]])
    q1 = trs.point_fit(p, u, x, y0 + e)[0]
    assert q1 > 0 and trs.point_fit(p, u, x, y0 + 2 * e)[0] == pytest.approx(4 * q1, rel=1e-12)


def test_upper_evidence_at_the_limit_and_in_the_linear_range():
    """A measurement made by the model at mu 0.5 rejects mu 0.75 strongly at a slip beyond
    the peak (-0.2: the force is mu-bound) and hardly in the linear range (-0.002: the force is
    the slip stiffness's, mu-free), the soak drive's case; no update, no evidence."""
    lams = []
    for kappa in (-0.2, -0.002):
        p, u = _braking_inputs(kappa)
        mu = np.full((2, 4), 0.5)
        y = trs.trusted.h_points(p, np.vstack([u, u]), mu)
        lam = trs.upper_evidence(p, np.vstack([u, u]), y, mu, np.array([False, True]), 0.25)
        assert lam[0].tolist() == [0.0, 0.0] and np.all(lam[1] > 0)
        lams.append(lam[1, 0])
    assert lams[0] > 100 * lams[1]


def test_hold_while_fired_scales_the_update_noise_only_while_fired():
    """The default preset's monitor counts its first mon_warmup / dt = 100 evaluated steps
    only; zero innovations leave it quiet (the update gets step 4's S_R itself); then
    innovations of 100 sd (NIS 3e4 per step, D's weight 1/51 puts D above any fire level at
    once) fire it, and the update gets S_R x 1e4."""
    p = trs.params.resolve(None, None, preset="default")
    adapt = trs.hold_while_fired(p)
    s_r, s_zz, c = np.eye(3) * 0.05, np.eye(3), np.zeros(3)
    for k in range(101):
        assert adapt(k, np.zeros(3), s_zz, None, s_r, c) is s_r
    out = adapt(101, np.full(3, 100.0), s_zz, None, s_r, c)
    assert np.array_equal(out, s_r * 1e4)


def test_upper_gate_wraps_and_restores_step_noise():
    """install() replaces trusted._step_noise (by the wrapper that records the step's inputs
    and prior mean), remove() puts the original back. With those set by hand: at the limit
    (slip -0.2, mu 0.5, the alternative 0.75) the step carries information far above info_min
    and the update keeps S_R; in the linear range (slip -0.002) it carries none and the update
    gets S_R x 1e4."""
    original = trs.trusted._step_noise
    for kappa, passes in ((-0.2, True), (-0.002, False)):
        p, u = _braking_inputs(kappa)
        gate = trs.UpperGate(p, 0.25)
        gate.install()
        try:
            assert trs.trusted._step_noise is not original
            f = type("F", (), {"x": np.array([0.5, 0.5]), "s_r": np.eye(3) * 0.05})()
            gate.ctx = (u[0], f.x)
            s_r = np.eye(3) * 0.05
            out = gate(0, None, None, None, s_r)
            assert (out is s_r) == passes and (passes or np.array_equal(out, s_r * 1e4))
        finally:
            gate.remove()
        assert trs.trusted._step_noise is original


def _psd(m, tol):
    """m's smallest eigenvalue is above -tol."""
    return np.linalg.eigvalsh(0.5 * (m + m.T)).min() > -tol


def test_noise_upper_bound_is_the_larger_of_both():
    """Diagonal noises share their eigenbasis, so R0 + [Ra - R0]+ is their elementwise
    maximum: diag(1, 4, 9) and diag(4, 1, 9) give diag(4, 4, 9). A general pair: the result is
    at least each of them (R - R0 and R - Ra positive semidefinite, to 1e-12 of rounding in
    numbers of order 10). Ra <= R0 leaves s0 itself, uncounted."""
    counter = type("C", (), {"inflated": 0})()
    s0, sa = np.diag([1.0, 2.0, 3.0]), np.diag([2.0, 1.0, 3.0])
    out = trs.noise_upper_bound(s0, sa, counter)
    assert out @ out.T == pytest.approx(np.diag([4.0, 4.0, 9.0]), abs=1e-12)
    assert counter.inflated == 1
    rng = np.random.default_rng(1)
    a, b = rng.normal(size=(3, 3)), rng.normal(size=(3, 3))
    s0, sa = np.linalg.cholesky(a @ a.T + np.eye(3)), np.linalg.cholesky(b @ b.T + np.eye(3))
    out = trs.noise_upper_bound(s0, sa, counter)
    r = out @ out.T
    assert _psd(r - s0 @ s0.T, 1e-12) and _psd(r - sa @ sa.T, 1e-12)
    assert not _psd(s0 @ s0.T - sa @ sa.T, 0.0)    # the pair is not ordered: both bounds bind
    assert not _psd(sa @ sa.T - s0 @ s0.T, 0.0)
    assert trs.noise_upper_bound(s0, 0.5 * s0, counter) is s0 and counter.inflated == 2


def test_upper_noise_inflates_a_saturated_low_mean_at_mild_slip():
    """The soak drive's case: mild braking slip (-0.01) with the prior mean at 0.1 (the
    model's tyre saturated, the slip noise hardly enters step 4's R) against 0.35 (the tyre in
    its linear range, the slip noise enters): the update's noise exceeds step 4's at the prior
    mean (trace larger) and is at least the one at 0.35; install()/remove() restore
    trusted._step_noise."""
    original = trs.trusted._step_noise
    p, u = _braking_inputs(-0.01)
    T = trs.trusted.WHEELS_OF_SIDES
    sd_u = np.array([p[k] if k else 0.0 for k in trs.SD_INPUTS])
    base = np.diag([p["r_ax"], p["r_ay"], p["r_yaw_acc"]])
    un = trs.UpperNoise(p, 0.25)
    un.install()
    try:
        assert trs.trusted._step_noise is not original
        f = type("F", (), {"x": np.array([0.1, 0.1]), "s_r": base})()
        s_r = trs.trusted._step_noise(p, f, T, u[0], sd_u)     # records the context
        out = un(0, None, None, None, s_r)
    finally:
        un.remove()
    assert trs.trusted._step_noise is original
    fa = type("F", (), {"x": np.array([0.35, 0.35]), "s_r": base})()
    ra = trs.trusted._step_noise(p, fa, T, u[0], sd_u)
    r, r0 = out @ out.T, s_r @ s_r.T
    assert un.inflated == 1 and np.trace(r) > np.trace(r0)
    # both bounds to 1e-9 of rounding relative to R's scale (entries about 1e-2 .. 1)
    assert _psd(r - r0, 1e-9) and _psd(r - ra @ ra.T, 1e-9)


def test_evidence_params_parse_the_spec():
    """MONITOR.md section 14's SPEC: evid_delta 0.25 always, the named evid_* keys set, the
    other keys left to the defaults; an unknown or valueless key is refused."""
    assert trs.evidence_params("plain") == {"evid_delta": 0.25}
    assert trs.evidence_params("free=5,l0=2") == {"evid_delta": 0.25, "evid_free": 5.0,
                                                 "evid_l0": 2.0}
    for bad in ("free", "delta=0.5", "rho=1", "free=5,x=1"):
        with pytest.raises(ValueError):
            trs.evidence_params(bad)
