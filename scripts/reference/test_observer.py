"""Tests of the reference velocity and sideslip observer (docs/OBSERVER.md).

1. its two-state Kalman filter equals the textbook matrix formulas (numpy);
2. a freely rolling wheel's reference is vx exactly (MODEL.md §3 run forwards);
3. the yaw-rate differentiator has the lag, gain and noise OBSERVER.md §3.2 states;
4. on the bundled scenarios (noisy logs, truth from the noise-free twins) vx and beta meet
   issue 16's targets, with the model's tyre matching the simulator's truth tyre;
5. an ay bias and a too-low friction do not make vy run away; bad periods are rejected;
6. the model rows' analytic derivatives (§4.2) are central differences of the model, in every
   tyre mode.
"""

from __future__ import annotations

import glob
import math
import os

import numpy as np
import pytest

from . import logs, model, observer, params

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
SCEN = os.path.join(REPO, "scenarios")
W = model.WHEELS


def test_kf2_matches_the_matrix_formulas():
    rng = np.random.default_rng(7)
    for _ in range(50):
        a = rng.standard_normal((2, 2))
        P = a @ a.T + 0.1 * np.eye(2)
        x = rng.standard_normal(2)
        f01, u, q0, q1, q01 = rng.standard_normal(5) * 0.1
        q0, q1 = abs(q0), abs(q1)
        kf = observer.Kf2(list(x), P.tolist())
        kf.predict(f01, u, q0, q1, q01)
        F = np.array([[1.0, f01], [0.0, 1.0]])
        Q = np.array([[q0, q01], [q01, q1]])
        xe, Pe = F @ x + np.array([u, 0.0]), F @ P @ F.T + Q
        # 1e-12: two orderings of a few products and sums of O(1) numbers (~1e-15 each)
        assert np.allclose(kf.x, xe, atol=1e-12) and np.allclose(kf.P, Pe, atol=1e-12)
        H = rng.standard_normal(2)
        nu, r = rng.standard_normal(), abs(rng.standard_normal()) + 0.01
        kf.update(H[0], H[1], nu, r)
        S = H @ Pe @ H + r
        K = Pe @ H / S
        assert np.allclose(kf.x, xe + K * nu, atol=1e-12)
        assert np.allclose(kf.P, Pe - np.outer(K, K) * S, atol=1e-12)


def test_a_free_rolling_wheel_reference_is_vx():
    p = observer.params_with_defaults()
    ob = observer.Observer(p)
    rng = np.random.default_rng(3)
    for _ in range(20):
        vx, vy, r, d = 5 + 30 * rng.random(), rng.normal(0, 1), rng.normal(0, 0.3), rng.normal(0, 0.1)
        pm = observer.model_params(p)
        v_wx, _, _ = model.wheel_velocities(pm, np.array([d]), np.array([vx]), np.array([vy]),
                                            np.array([r]))
        omega = tuple(v_wx[0] / pm["R"])
        s = observer.Sample(t=0.0, delta=d, yaw_rate=r, ax=0.0, ay=0.0, omega=omega)
        # 1e-9 m/s: the forward and the inverse formula round differently (~1e-14 relative)
        assert np.allclose(ob.wheel_refs(s, vy), vx, atol=1e-9)


def _steps(p, rates, dt=0.01):
    ob = observer.Observer(p)
    out = []
    for k, r in enumerate(rates):
        out.append(ob.step(observer.Sample(t=k * dt, delta=0.0, yaw_rate=float(r), ax=0.0,
                                           ay=0.0, omega=(60.0,) * 4))["yaw_acc"])
    return np.array(out)


# REQ-OBS-005
@pytest.mark.parametrize("f", [0.25, 1.0, 2.0])
def test_differentiator_lag_and_gain(f):
    p = observer.params_with_defaults()
    t = np.arange(0, 20, 0.01)
    a = 0.2
    rd = _steps(p, a * np.sin(2 * np.pi * f * t))[1000:]       # after the start-up
    w = 2 * np.pi * f
    tt = t[1000:]
    # least squares fit rd = G cos(w t - w tau) (the derivative of a sin is a w cos)
    A = np.column_stack([np.cos(w * tt), np.sin(w * tt)])
    c, s = np.linalg.lstsq(A, rd, rcond=None)[0]
    gain = math.hypot(c, s) / (a * w)
    delay = math.atan2(s, c) / w
    # OBSERVER.md: 0.04 s and within 1.5 % of unit gain; the fit of a noise-free run is
    # exact to ~1e-6, the page rounds the delay to 0.04 (0.040-0.042 s over 0.25-2 Hz)
    assert 0.035 <= delay <= 0.045
    assert abs(gain - 1.0) <= 0.015


# REQ-OBS-005
def test_differentiator_noise():
    """The output noise of the yaw-rate differentiator on white yaw-rate noise, exactly.

    Its Kalman gains depend on the constant dt, R and Q only, never on the data, so once they
    have converged the differentiator is a linear time-invariant filter and white input noise
    of sd s leaves s * ||h||_2 on its output, h its impulse response. h is measured through the
    whole observer step: an impulse after 2000 steps (20 s, the gains settled), checked linear
    (two amplitudes) and time-invariant (two onsets), 600 steps long (its tail is checked to be
    negligible). This replaces a 40,000-step Monte-Carlo run with the same claim, exact."""
    p = observer.params_with_defaults()
    n0, m = 2000, 600

    def response(onset, amp):
        x = np.zeros(onset + m)
        x[onset] = amp
        return _steps(p, x)[onset:] / amp

    h = response(n0, 1e-3)
    # linear and time-invariant to rounding (1e-9 relative: ~1e7 ulps of double, far
    # above the rounding of a few hundred operations, far below any nonlinearity that matters)
    assert np.allclose(response(n0, 3e-3), h, rtol=1e-9, atol=1e-9 * np.max(np.abs(h)))
    assert np.allclose(response(n0 + 300, 1e-3), h, rtol=1e-9, atol=1e-9 * np.max(np.abs(h)))
    # the response has died out: the truncated tail adds nothing to ||h||
    assert np.max(np.abs(h[-100:])) < 1e-12 * np.max(np.abs(h))
    sd = p["obs_sd_r"] * math.sqrt(float(np.sum(h ** 2)))
    # OBSERVER.md: 0.053 rad/s^2, rounded to two digits: the exact value within half a unit
    # of its last digit
    assert abs(sd - 0.053) <= 0.0005


# Bundled logs outside the premise of issue 16's targets below (the observer given the
# simulator's own tyre, below the limit while steering), measured beta RMSE: asserted to fail
# (strict), so a change that meets the targets there is seen.
OUTSIDE_TARGETS = {
    "ramp_steer_low_mu": "the ramp steer runs the tyres saturated on mu 0.3 for its last "
                         "third while cornering: beta RMSE 0.61 deg",
    "wrong_tyre_data": "the observer's tyre is the parameter file's, 30 % off the car's by "
                       "construction: beta RMSE 0.36 deg",
}


def _pairs():
    out = []
    for f in sorted(glob.glob(os.path.join(SCEN, "*.nf.csv"))):
        noisy = f.replace(".nf.csv", ".csv")
        if os.path.exists(noisy):
            name = os.path.basename(noisy)[:-4]
            marks = ([pytest.mark.xfail(strict=True, reason=OUTSIDE_TARGETS[name])]
                     if name in OUTSIDE_TARGETS else [])
            out.append(pytest.param(noisy, f, id=name, marks=marks))
    return out


def _pairs_at_rates(rates=(1, 2, 8)):
    """_pairs at each obs_lat_every N (§4.2: the model's rows every N-th step at variance
    r / N), the same targets and the same expected failures at every N."""
    return [pytest.param(*pr.values, n, id=f"{pr.id}-N{n}", marks=pr.marks)
            for n in rates for pr in _pairs()]


def _run_with_truth_mu(path, sd_mu=0.05, **over):
    log = logs.read_csv_log(path)
    c = log.columns
    meta = params.from_metadata(log.meta)
    p = observer.params_with_defaults(meta, tyre="paper", **over)  # the simulator's Dugoff
    mu = ([c["mu_" + w] for w in W], [np.full(len(c["t"]), sd_mu)] * 4)
    return c, observer.run(c, p, mu)


@pytest.mark.skipif(not _pairs(), reason="no bundled scenarios")
@pytest.mark.parametrize("noisy,truth,every", _pairs_at_rates())
def test_scenario_targets(noisy, truth, every):
    c, o = _run_with_truth_mu(noisy, obs_lat_every=float(every))
    tr = logs.read_csv_log(truth).columns
    ex = o["vx"] - tr["vx"]
    eb = np.degrees(o["beta"] - np.arctan2(tr["vy"], tr["vx"]))
    # issue 16's targets: vx RMSE <= 0.15 m/s, max <= 0.5 m/s; beta RMSE <= 0.3 deg (these
    # scenarios stay below the limit except the hard-braking ones, which are straight)
    assert np.sqrt(np.mean(ex ** 2)) <= 0.15
    assert np.max(np.abs(ex)) <= 0.5
    assert np.sqrt(np.mean(eb ** 2)) <= 0.3


def _with(path, **cols):
    log = logs.read_csv_log(path)
    c = dict(log.columns)
    c.update(cols)
    return c


@pytest.mark.skipif(not os.path.exists(os.path.join(SCEN, "sine_steer_high_mu.csv")),
                    reason="no bundled scenarios")
def test_an_ay_bias_does_not_drift():
    path = os.path.join(SCEN, "sine_steer_high_mu.csv")
    c = _with(path)
    c["ay"] = c["ay"] + 0.1                                   # issue 16: 0.1 m/s^2 bias
    p = observer.params_with_defaults(tyre="paper")
    o = observer.run(c, p, ([c["mu_" + w] for w in W], [np.full(len(c["t"]), 0.05)] * 4))
    tr = logs.read_csv_log(path.replace(".csv", ".nf.csv")).columns
    eb = np.degrees(o["beta"] - np.arctan2(tr["vy"], tr["vx"]))
    # pure integration would drift by 0.1 * t: 1 m/s, 2.6 deg after 10 s at 22 m/s; the
    # model holds vy: the error stays below the 0.3 deg target and b_y finds the bias
    # (0.1 within 0.03: the offset also absorbs the model's own error, ~0.01 m/s^2 here)
    assert np.sqrt(np.mean(eb[500:] ** 2)) <= 0.3
    assert abs(o["by"][-1] - 0.1) <= 0.03


def _wrong_mu_errors(sd_mu):
    path = os.path.join(SCEN, "sine_steer_high_mu.csv")
    c = _with(path)
    n = len(c["t"])
    p = observer.params_with_defaults(tyre="paper")
    # the friction estimator claims 0.2 on a 0.85 road (peak ay 5 m/s^2)
    o = observer.run(c, p, ([np.full(n, 0.2)] * 4, [np.full(n, sd_mu)] * 4))
    tr = logs.read_csv_log(path.replace(".csv", ".nf.csv")).columns
    b_true = np.degrees(np.arctan2(tr["vy"], tr["vx"]))
    return o, np.abs(np.degrees(o["beta"]) - b_true), np.max(np.abs(b_true))


# REQ-OBS-006
@pytest.mark.skipif(not os.path.exists(os.path.join(SCEN, "sine_steer_high_mu.csv")),
                    reason="no bundled scenarios")
def test_a_confidently_wrong_friction_does_not_run_away():
    o, err, b_max = _wrong_mu_errors(0.02)
    assert np.any(o["flags"].astype(int) & observer.FLAG_MU_RAISED)
    # The ay lower bound keeps mu >= 1.1 |ay|/g (0.56 at the 5 m/s^2 peaks), so the model
    # never saturates below the measured ay. With the simulator's tyre, whose stiffness
    # scales with mu, a 0.56 road is 0.66 times as stiff: the model alone would put beta at
    # up to ~2.3 times the truth. The observer believes a confident friction (OBSERVER.md
    # §4.2), so the error is that of the model, bounded by 3 |beta_true|max (5.2 deg), and
    # it does not grow: the last 2 s stay below the first 2 s.
    assert np.max(err) <= 3.0 * b_max
    assert np.max(err[-200:]) <= np.max(err[:200])


@pytest.mark.skipif(not os.path.exists(os.path.join(SCEN, "sine_steer_high_mu.csv")),
                    reason="no bundled scenarios")
def test_an_honest_friction_sd_limits_the_error():
    # the same wrong 0.2 with the sd the friction estimator reports for a friction it has
    # not observed (its sd_max, 0.32; here 0.3): the model is trusted less and the error
    # drops below 1.5 |beta_true|max (2.6 deg; measured 1.9)
    _, err, b_max = _wrong_mu_errors(0.3)
    _, err_conf, _ = _wrong_mu_errors(0.02)
    assert np.max(err) <= 1.5 * b_max
    assert np.max(err) < np.max(err_conf)


BANK = os.path.join(SCEN, "observer", "bank_curve_neg5.csv")


def _bank_beta_rmse(mu0, gain):
    """beta RMSE [deg] (vx_true >= 3 m/s) of the reference on the -5 deg banked curve with
    the friction input held at mu0 (sd 0.06) and obs_lin_mu_gain = gain; and its flags."""
    log = logs.read_csv_log(BANK)
    c = log.columns
    n = len(c["t"])
    p = observer.params_with_defaults(params.from_metadata(log.meta), obs_lin_mu_gain=gain)
    o = observer.run(c, p, ([np.full(n, mu0)] * 4, [np.full(n, 0.06)] * 4))
    m = c["vx_true"] >= 3.0
    e = np.degrees(o["beta"] - c["beta_true"])[m]
    return float(np.sqrt(np.mean(e ** 2))), o["flags"].astype(int)


# REQ-OBS-012
@pytest.mark.skipif(not os.path.exists(BANK), reason="no bundled observer scenarios")
def test_the_steady_turns_friction_floor_on_the_adverse_bank():
    # OBSERVER.md §4.2: the pipeline's friction loop holds the friction estimate at 0.2-0.4
    # on this mu 0.9 road (OBSERVER_RESULTS.md); held at 0.3, the margin's bound
    # 1.1 * 3.2 / 9.81 = 0.36 leaves the model's tyres near their limit and vy is pulled off
    # the linear range's: beta misses issue 16's 0.3 deg (measured 0.37). The floor
    # 2 * 3.2 / 9.81 = 0.65 in the steady turn puts them back in their linear range: within
    # the target with margin (measured 0.13; the bound 0.2 is the target less a third).
    without, _ = _bank_beta_rmse(0.3, 0.0)
    with_floor, flags = _bank_beta_rmse(0.3, 2.0)
    assert without > 0.3
    assert with_floor <= 0.2
    assert np.any(flags & observer.FLAG_MU_RAISED)
    # with the true friction the floor (0.65 < 0.9) never binds: the model is the same and
    # beta as good as the reference gets here (measured 0.07 either way)
    true_mu, _ = _bank_beta_rmse(0.9, 2.0)
    assert true_mu <= 0.1


@pytest.mark.parametrize("tyre", ["paper", "dugoff", "magic"])
def test_model_row_derivatives_are_the_models(tyre):
    """§4.2: d(ay, r-dot)/dvy and the friction derivative along sd against central differences
    of model_rows. Bound: a central difference D(h) errs by its truncation, which
    |D(2h) - D(h)| over-estimates threefold, and by rounding 1e-13 / h; a kink (alpha_max, the
    kappa clip, E = 0, mu = 0) within 2h of the point shows as a large |D(2h) - D(h)| and
    loosens the bound there, so at least 90 % of the bounds must be below 1e-5 relative."""
    ob = observer.Observer(observer.params_with_defaults(tyre=tyre))
    rng = np.random.default_rng(16)
    h, tight, n = 1e-4, 0, 0
    for _ in range(300):
        vx = rng.uniform(3.0, 45.0)
        s = observer.Sample(t=0.0, delta=rng.uniform(-0.4, 0.4), yaw_rate=rng.uniform(-0.8, 0.8),
                            ax=rng.uniform(-9.0, 5.0), ay=rng.uniform(-9.0, 9.0),
                            omega=tuple(vx * rng.uniform(0.8, 1.1, 4) / 0.3))
        vy = rng.uniform(-3.0, 3.0)
        mu = tuple(rng.uniform(0.05, 1.3, 4))
        sd = tuple(rng.uniform(0.0, 0.4, 4))
        z, d_vy, d_mu = ob.model_rows_jac(s, vx, vy, mu, sd)
        assert z == ob.model_rows(s, vx, vy, mu)

        def diff(step, by_vy):
            if by_vy:
                hi, lo = ob.model_rows(s, vx, vy + step, mu), ob.model_rows(s, vx, vy - step, mu)
            else:
                hi = ob.model_rows(s, vx, vy, tuple(m + step * d for m, d in zip(mu, sd)))
                lo = ob.model_rows(s, vx, vy, tuple(m - step * d for m, d in zip(mu, sd)))
            return [(a - b) / (2.0 * step) for a, b in zip(hi, lo)]

        for an, by_vy in ((d_vy, True), (d_mu, False)):
            d1, d2 = diff(h, by_vy), diff(2.0 * h, by_vy)
            for r in range(2):
                bound = abs(d2[r] - d1[r]) + 1e-13 / h + 1e-9 * abs(an[r])
                assert abs(an[r] - d1[r]) <= bound, (tyre, by_vy, r, an[r], d1[r], d2[r])
                tight += bound <= 1e-5 * max(abs(an[r]), 1.0)
                n += 1
    assert tight >= 0.9 * n


def test_a_bad_period_is_rejected():
    ob = observer.Observer(observer.params_with_defaults())
    s = observer.Sample(t=0.0, delta=0.0, yaw_rate=0.0, ax=0.0, ay=0.0, omega=(60.0,) * 4)
    ob.step(s)
    with pytest.raises(ValueError):
        ob.step(observer.Sample(t=0.5, delta=0.0, yaw_rate=0.0, ax=0.0, ay=0.0,
                                omega=(60.0,) * 4))


GOLDEN_OBS = os.path.join(SCEN, "golden", "observer")


@pytest.mark.skipif(not os.path.isdir(GOLDEN_OBS), reason="no observer goldens")
@pytest.mark.parametrize("name,every", [("brake_in_turn.csv", None),
                                        ("sine_steer_low_mu.csv", None),
                                        ("brake_in_turn_low_mu.csv", 1),
                                        ("sine_steer_low_mu.csv", 1)])
def test_observer_goldens_are_up_to_date(name, every):
    # None: the observer's default obs_lat_every (scenarios/golden/observer); 1:
    # scenarios/golden/observer_every1 (OBSERVER.md §4.2, the C tests' reference for the
    # every-step path)
    import sys
    sys.path.insert(0, os.path.join(REPO, "scripts", "data"))
    import make_observer_goldens as mog
    meta, cols, rows = mog.golden(os.path.join(SCEN, name), every)
    now = np.array([list(r) for r in rows])
    folder = GOLDEN_OBS if every is None else GOLDEN_OBS + f"_every{every}"
    g = logs.read_csv_log(os.path.join(folder, name), required=cols)
    old = np.column_stack([g.columns[c] for c in cols])
    assert now.shape == old.shape
    # 1e-9 absolute: the observer's path is plain float64 except the model's 4-term dot
    # products (numpy may sum them in another order on another CPU: ~1e-16 relative), and
    # the filters are stable; the flags (last column) exactly
    assert np.max(np.abs(now[:, :-1] - old[:, :-1])) <= 1e-9
    assert np.array_equal(now[:, -1], old[:, -1])
    assert dict(meta)["source"] == g.meta["source"]


@pytest.mark.skipif(not os.path.isdir(GOLDEN_OBS + "_out_floor0"), reason="no floor-off goldens")
@pytest.mark.parametrize("name", ["brake_in_turn_low_mu.csv", "sine_steer_low_mu.csv"])
def test_the_floor_off_goldens_are_up_to_date(name):
    # scenarios/golden/observer_out_floor0: obs_vy_out_floor_mu 0 (OBSERVER.md §5; the
    # default is 4), the C double build's reference with the floor off; the bounds of the
    # test above
    import sys
    sys.path.insert(0, os.path.join(REPO, "scripts", "data"))
    import make_observer_goldens as mog
    meta, cols, rows = mog.golden(os.path.join(SCEN, name), None, 0.0)
    now = np.array([list(r) for r in rows])
    g = logs.read_csv_log(os.path.join(GOLDEN_OBS + "_out_floor0", name), required=cols)
    old = np.column_stack([g.columns[c] for c in cols])
    assert now.shape == old.shape
    assert np.max(np.abs(now[:, :-1] - old[:, :-1])) <= 1e-9
    assert np.array_equal(now[:, -1], old[:, -1])
    assert dict(meta)["obs_vy_out_floor_mu"] == 0.0
    # the default's floor acts on these logs: the default golden's sd(vy) above the off
    # one's somewhere
    d = logs.read_csv_log(os.path.join(GOLDEN_OBS, name), required=cols)
    assert float(d.meta["obs_vy_out_floor_mu"]) == 4.0
    assert np.any(d.columns["sd_vy"] > g.columns["sd_vy"] + 1e-6)
    # and leaves the estimate (the goldens were written on other CPUs: the bound above)
    assert np.max(np.abs(g.columns["vy"] - d.columns["vy"])) <= 1e-9


def _turn_flags(every, n=12):
    """A steady turn at 20 m/s (ay 2.5 m/s^2): the flags of the later steps 1..n."""
    ob = observer.Observer(observer.params_with_defaults(obs_lat_every=float(every)))
    out = []
    for k in range(n + 1):
        s = observer.Sample(t=0.01 * k, delta=0.02, yaw_rate=0.12, ax=0.0, ay=2.5,
                            omega=(20.0 / ob.p["R"],) * 4)
        o = ob.step(s)
        if k > 0:
            out.append(int(o["flags"]))
    return out


@pytest.mark.parametrize("every", [1, 2, 3, 4])
def test_the_models_rate(every):
    # §4.2 the model's rows on the later steps 1, 1 + N, 1 + 2N, ... and on no other
    flags = _turn_flags(every)
    got = [(f & observer.FLAG_VY_MODEL) != 0 for f in flags]
    assert got == [(k - 1) % every == 0 for k in range(1, len(flags) + 1)]


def test_the_models_rate_is_checked():
    for bad in (0.0, 9.0, 2.5):
        with pytest.raises(ValueError):
            observer.Observer(observer.params_with_defaults(obs_lat_every=bad))


# Honest on an unobserved friction (issue 17; docs/OBSERVER_RESULTS.md "Honest on an
# unobserved friction"): the reference-only study options of observer.STUDY_DEFAULTS, and the
# one ported to the library (obs_vy_out_floor_mu, OBS_DEFAULTS).
LOOP = os.path.join(SCEN, "observer_loop", "turn_mu_step.csv")
# the friction input the C loop feeds on the mu 0.5 phase (OBSERVER.md §6 "The loop": the
# estimator at its bound, 1.1-1.2, sd 0.58), held constant: no C binary needed
LOOP_MU, LOOP_SD = 1.15, 0.58


def _loop_run(**over):
    log = logs.read_csv_log(LOOP)
    c = log.columns
    n = len(c["t"])
    p = observer.params_with_defaults(params.from_metadata(log.meta), **over)
    o = observer.run(c, p, ([np.full(n, LOOP_MU)] * 4, [np.full(n, LOOP_SD)] * 4))
    low = np.mean([c["mu_" + w] for w in W], axis=0) < 0.7      # the mu 0.5 phase
    return c, p, o, (c["vx_true"] >= 3.0) & low


def _slip_floor(c, p, o, k):
    """k |vx ay / (cy g)| sd_mu / mu, mu raised to (1 + obs_mu_margin) |ay| / g, written from
    the option's definition with the observer's own vx."""
    mu = np.maximum(LOOP_MU, (1.0 + p["obs_mu_margin"]) * np.abs(c["ay"]) / p["g"])
    return k * np.abs(o["vx"] * c["ay"] / (p["cy"] * p["g"])) * LOOP_SD / mu


def test_the_study_options_are_off_and_not_the_librarys():
    # off by default, and not among the parameters the C library and the goldens record
    assert all(v == 0.0 for v in observer.STUDY_DEFAULTS.values())
    assert not set(observer.STUDY_DEFAULTS) & set(observer.OBS_DEFAULTS)


@pytest.mark.skipif(not os.path.exists(LOOP), reason="no loop scenario")
def test_the_output_floor_makes_the_mu_step_honest_and_leaves_the_estimate():
    assert observer.OBS_DEFAULTS["obs_vy_out_floor_mu"] == 4.0   # on by default
    c, _, off, m = _loop_run(obs_vy_out_floor_mu=0.0)
    _, p, on, _ = _loop_run()
    e_off = np.abs(off["beta"] - c["beta_true"])[m]
    e_on = np.abs(on["beta"] - c["beta_true"])[m]
    # off: confidently wrong (measured: every sample of the phase beyond 2 sd)
    assert np.mean(e_off > 2.0 * off["sd_beta"][m]) > 0.9
    # on: at most the 4.6 % a consistent Gaussian estimate leaves beyond 2 sd (measured 0 %)
    assert np.mean(e_on > 2.0 * on["sd_beta"][m]) <= 0.05
    # the floor is on the output only: the estimate is the same arithmetic, bit for bit
    for key in ("vx", "vy", "beta", "sd_vx"):
        assert np.array_equal(on[key], off[key])
    fast = on["vx"] >= p["obs_v_lat_min"]
    # 1e-12 relative: the same few products in another order
    assert np.all(on["sd_vy"][fast] >= _slip_floor(c, p, on, 4.0)[fast] * (1.0 - 1e-12))


@pytest.mark.skipif(not os.path.exists(LOOP), reason="no loop scenario")
def test_the_state_floor_bounds_sd_vy():
    # the reported sd's floor off in both runs (4 by default): the state floor alone
    c, p, o, _ = _loop_run(obs_vy_floor_mu=2.0, obs_vy_out_floor_mu=0.0)
    fast = o["vx"] >= p["obs_v_lat_min"]
    # 1e-12 relative: as above (sd is the square root of the floored P00)
    assert np.all(o["sd_vy"][fast] >= _slip_floor(c, p, o, 2.0)[fast] * (1.0 - 1e-12))
    assert np.any(o["sd_vy"][fast] > 3.0 * _loop_run(obs_vy_out_floor_mu=0.0)[2]["sd_vy"][fast])


# REQ-OBS-027: §4.4's noise grown by obs_vydot_rerr max(0, |r| - |vx delta / L|) (the car
# sliding out). Two reference observers, the term off and at its default 25, through
# test_velocity_flt.c's turn: equal while the yaw rate is under r_ref; on the first step of
# the slide (the steering taken back, r held: r-dot 0) the posteriors differ by §4.4's row
# alone, in information form P_on^-1 - P_off^-1 = H^T H (1/R_on - 1/R_off) and
# P_on^-1 x_on - P_off^-1 x_off = H^T z (1/R_on - 1/R_off), H = [0, 1], z = ay - r vx; below
# v_lat_min the term is 0.
def test_the_yaw_error_grows_the_offsets_noise():
    p_on = observer.params_with_defaults()
    assert p_on["obs_vydot_rerr"] == 25.0                 # the default (OBSERVER.md §2)
    p_off = dict(p_on, obs_vydot_rerr=0.0)
    off, on = observer.Observer(p_off), observer.Observer(p_on)
    length = p_on["Lf"] + p_on["Lr"]
    omega = (20.0 / p_on["R"],) * 4
    r = 20.0 * 0.06 / length - 0.05
    for k in range(101):
        s = observer.Sample(t=k * 0.01, delta=0.06, yaw_rate=r, ax=0.0, ay=20.0 * r, omega=omega)
        assert off.step(s) == on.step(s)
    delta = (r - 0.2) * length / 20.0
    s = observer.Sample(t=1.01, delta=delta, yaw_rate=r, ax=0.0, ay=20.0 * r - 2.0, omega=omega)
    off.step(s)
    on.step(s)
    vx = on.lon.x[0]
    r_over = abs(r) - abs(vx * (delta / length))
    assert r_over > 0.19 and abs(on.yaw.x[1]) < 0.1
    s0 = p_on["obs_sd_vydot"] + p_on["obs_vydot_rdot"] * abs(on.yaw.x[1])
    dinf = 1.0 / (s0 + 25.0 * r_over) ** 2 - 1.0 / s0 ** 2
    i_off, i_on = np.linalg.inv(np.array(off.lat.P)), np.linalg.inv(np.array(on.lat.P))
    y_off, y_on = i_off @ np.array(off.lat.x), i_on @ np.array(on.lat.x)
    # 1e-9 relative: two 2x2 inverses of a P with condition number below 10 in float64
    scale, sy = np.abs(i_off).max(), np.abs(y_off).max()
    assert np.allclose(i_on - i_off, [[0.0, 0.0], [0.0, dinf]], rtol=0.0, atol=1e-9 * scale)
    z = s.ay - s.yaw_rate * vx
    assert np.allclose(y_on - y_off, [0.0, z * dinf], rtol=0.0, atol=1e-9 * sy)
    # below v_lat_min, r far beyond r_ref: equal
    off, on = observer.Observer(p_off), observer.Observer(p_on)
    for k in range(21):
        s = observer.Sample(t=k * 0.01, delta=0.03, yaw_rate=0.5, ax=0.0, ay=0.0,
                            omega=(2.0 / p_on["R"],) * 4)
        assert off.step(s) == on.step(s)


def _turn_with_driven_slip(ay_turn):
    """1 s straight at 20 m/s, then 2 s with ay 2 m/s^2 (r = 0, delta = 0: the references are
    omega R) and the driven front wheels 0.1 m/s fast, rolling with no torque signal (the
    C tests' turn_with_driven_slip). Returns the last vx."""
    p = dict(observer.params_with_defaults(), obs_ay_turn=ay_turn)
    ob = observer.Observer(p)
    out = None
    for k in range(300):
        fast = 20.1 if k >= 100 else 20.0
        omega = (fast / p["R"], fast / p["R"], 20.0 / p["R"], 20.0 / p["R"])
        out = ob.step(observer.Sample(t=k * 0.01, delta=0.0, yaw_rate=0.0, ax=0.0,
                                      ay=2.0 if k >= 100 else 0.0, omega=omega))
        if k > 0:
            assert out["flags"] & (observer.FLAG_BRAKING | observer.FLAG_DRIVING
                                   | observer.FLAG_VX_WHEEL) == observer.FLAG_VX_WHEEL
    return out["vx"]


# REQ-OBS-028
def test_rolling_in_a_turn_leaves_the_driven_wheels_out():
    p = observer.params_with_defaults()
    assert (p["obs_ay_turn"], p["obs_q_bx_turn"]) == (1.0, 0.03)   # OBSERVER.md §2
    # noise-free, references constant for 2 s: the rear wheels' 20 m/s within 0.01 m/s (a
    # fifth of the 0.05 between the rear wheels and the four wheels' mean); off (0, the rule
    # before 2026-12-07) vx follows the four wheels, above their mean less that bound
    assert abs(_turn_with_driven_slip(1.0) - 20.0) <= 0.01
    assert _turn_with_driven_slip(0.0) > 20.04


# REQ-OBS-028
def test_a_turn_walks_bx_faster_unless_braking():
    p = observer.params_with_defaults()

    def p11_after(ay, brake):
        ob = observer.Observer(p)
        for k in range(101):
            last = k == 100
            ob.step(observer.Sample(t=k * 0.01, delta=0.0, yaw_rate=0.0, ax=0.0,
                                    ay=ay if last else 0.0, omega=(20.0 / p["R"],) * 4,
                                    torque=(0.0,) * 4,
                                    p_brake=(3.0 if (last and brake) else 0.0,) * 4))
        return ob.lon.P[1][1]
    # the same wheels corrected vx (a torque signal, none above obs_torque_on), and the
    # update's p01^2 / S does not depend on p11: the turn adds (q_turn^2 - q^2) dt exactly,
    # to double rounding of a p11 of ~1e-3 (1e-15), bounded at 1e-12
    dq = (p["obs_q_bx_turn"] ** 2 - p["obs_q_bx"] ** 2) * 0.01
    assert abs((p11_after(2.0, False) - p11_after(0.5, False)) - dq) <= 1e-12
    assert p11_after(2.0, True) == p11_after(0.5, True)   # braking: obs_q_bx either way
