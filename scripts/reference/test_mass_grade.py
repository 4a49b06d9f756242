"""Tests of the mass and grade reference (scripts/reference/mass_grade.py, docs/MASS_GRADE.md).

Fast (a few seconds): one run of a 560 s log, the rest on a few synthetic steps."""

import math
import os

import numpy as np
import pytest

from reference import mass_grade as mg

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LOGS = os.path.join(REPO, "scenarios", "mass_grade")


def test_weights_sum_to_one():
    # §3: sum w_m = lambda/(n+lambda) + 2n/(2(n+lambda)) = 1 exactly in arithmetic; the sum of
    # 7 doubles of size <= |lambda/(n+lambda)| is within a few ulp of it (1e-12 relative).
    for a, k in ((1.0, 0.0), (0.5, 1.0), (1e-3, 0.0), (2.0, -1.0)):
        p = mg.preset(mg_ut_alpha=a, mg_ut_kappa=k)
        wm, wc = mg.weights(p)
        scale = max(1.0, abs(wm[0]))
        assert abs(sum(wm) - 1.0) <= 1e-12 * scale
        # w_c differs from w_m only in w_c,0, by 1 - alpha^2 + beta
        assert abs(sum(wc) - (2.0 - a * a + p["mg_ut_beta"])) <= 1e-12 * scale


def test_cholesky_factor_zero_pivot_and_negative():
    A = [[4.0, 2.0, 0.4], [2.0, 5.0, 1.0], [0.4, 1.0, 3.0]]
    L = mg.cholesky(A)
    for i in range(3):
        for j in range(3):
            s = sum(L[i][k] * L[j][k] for k in range(3))
            assert abs(s - A[i][j]) <= 1e-15 * 8  # a few ulp of entries <= 5
    # a state known exactly: its row and column 0 -> a zero column, the rest factored
    Z = [[4.0, 0.0, 0.4], [0.0, 0.0, 0.0], [0.4, 0.0, 3.0]]
    Lz = mg.cholesky(Z)
    assert Lz[1] == [0.0, 0.0, 0.0] and Lz[2][1] == 0.0
    assert mg.cholesky([[1.0, 0.0, 0.0], [0.0, -1e-9, 0.0], [0.0, 0.0, 1.0]]) is None


def _cov(est):
    """The estimator's P: stored (textbook form) or S S^T (square-root form)."""
    if est.form == "textbook":
        return np.array(est.P)
    S = np.array(est.S)
    return S @ S.T


@pytest.mark.parametrize("form", mg.FORMS)
def test_ukf_is_the_kalman_filter_on_a_linear_model(monkeypatch, form):
    # The unscented transform propagates mean and covariance exactly through a linear map
    # (the sigma points match the first two moments; chi_0 - mean = 0, so the beta term adds
    # nothing), so with a linear f and h the UKF is the Kalman filter.  Compared after 50
    # steps; entries up to ~1e5 (P_MM), ~1e3 operations each: 1e-9 relative is far above the
    # rounding (~1e-13) and far below any algorithmic difference.
    F = np.array([[1.0, -1e-5, -0.2], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    monkeypatch.setattr(mg, "f_state", lambda p, x, T, dt, ar=None: list(F @ np.array(x)))
    monkeypatch.setattr(mg, "h_meas", lambda p, x, T, use_ax, ar=None: [x[0]])
    # bounds far away, so that the projection (§4.3 step 8, not a Kalman step) never acts
    p = mg.preset(mg_adaptive=0.0, mg_v_min=0.0, mg_m_min=1.0, mg_m_max=1e6,
                  mg_theta_max=1.4)
    est = mg.MassGrade(p, form=form)
    rng = np.random.default_rng(3)
    dt = 0.02
    xt = np.array([20.0, 2000.0, 0.02])       # measurements of a true linear system
    zs = []
    for _ in range(51):
        zs.append(xt[0] + 0.05 * rng.standard_normal())
        xt = F @ xt
    est_bounds = (p["mg_m_min"], p["mg_m_max"])
    est.step(mg.MgSample(0.0, zs[0], 0.0))
    x = np.array([zs[0], p["mg_m0"], 0.0])
    P = np.diag([p["mg_r_v"] ** 2, p["mg_sd_m0"] ** 2, p["mg_sd_theta0"] ** 2])
    Q = np.diag([p["mg_q_v"] ** 2, p["mg_q_mc"] ** 2, p["mg_q_theta"] ** 2]) * dt
    H = np.array([[1.0, 0.0, 0.0]])
    for k in range(1, 51):
        out = est.step(mg.MgSample(k * dt, zs[k], 0.0))
        assert out.status == mg.OK
        x = F @ x
        P = F @ P @ F.T + Q
        S = H @ P @ H.T + p["mg_r_v"] ** 2
        K = P @ H.T / S
        x = x + (K * (zs[k] - x[0])).ravel()
        P = P - K @ S @ K.T
    assert est_bounds[0] < x[1] < est_bounds[1]
    assert np.allclose(est.x, x, rtol=1e-9, atol=1e-9)
    assert np.allclose(_cov(est), P, rtol=1e-9, atol=1e-12)


def _adapting(q_mv, m_now, m_a, span=1.0):
    p = mg.preset()
    est = mg.MassGrade(p, form="textbook")
    est.step(mg.MgSample(0.0, 20.0, 300.0))
    est.q_mv = q_mv
    est.x[1], est.m_adapt, est.adapt_elapsed = m_now, m_a, 0.0
    est.P = [[0.01, 2.0, 0.001], [2.0, 400.0, 0.1], [0.001, 0.1, 1e-4]]
    return p, est


def test_adaptation_shrinks_q_mv_and_the_mass_row_as_specified():
    # §4.4: lambda_u = 1/2 |q_s - D| / (q_s + D); q_mv and the mass row and column of P scale
    # by lambda_u, P_22 once; the other entries untouched.  Same operations as the spec on
    # exactly representable inputs: compared to 1e-15 relative.
    p, est = _adapting(q_mv=900.0, m_now=1810.0, m_a=1800.0)
    P0 = [row[:] for row in est.P]
    est._adapt(1.0)
    lam = 0.5 * abs(900.0 - 100.0) / (900.0 + 100.0)   # D = 10^2, q_s = 900 * 1 s
    assert est.q_mv == pytest.approx(lam * 900.0, rel=1e-15)
    assert est.P[1][1] == pytest.approx(lam * P0[1][1], rel=1e-15)
    assert est.P[0][1] == est.P[1][0] == pytest.approx(lam * P0[0][1], rel=1e-15)
    assert est.P[2][1] == est.P[1][2] == pytest.approx(lam * P0[1][2], rel=1e-15)
    assert est.P[0][0] == P0[0][0] and est.P[2][2] == P0[2][2] and est.P[0][2] == P0[0][2]
    assert est.m_adapt == 1810.0 and est.adapt_elapsed == 0.0
    # 0 <= lambda_u <= 1/2 whatever D: the shrink factor the seed calls < 1
    for d in (0.0, 1.0, 900.0, 1e6):
        _, e = _adapting(q_mv=900.0, m_now=1800.0 + math.sqrt(d), m_a=1800.0)
        e._adapt(1.0)
        assert 0.0 <= e.q_mv <= 0.5 * 900.0 * (1.0 + 1e-15)


def test_square_root_adaptation_is_the_textbook_scaling():
    # §4.4 in square-root form: S' = Tria([D S, sqrt(lambda - lambda^2) |S row M| e2]) has
    # S' S'^T = D P D + (lambda - lambda^2) P_MM e2 e2^T, i.e. the mass row and column of P
    # scaled by lambda, P_MM once, the rest unchanged: a few roundings of entries of P's
    # scale (the reflections), so 1e-14 of sqrt(P_ii P_jj).
    P0 = np.array([[0.01, 1.5, 2e-4], [1.5, 400.0, 0.1], [2e-4, 0.1, 1e-4]])
    est = mg.MassGrade(mg.preset())
    est.step(mg.MgSample(0.0, 20.0, 300.0))
    est.q_mv, est.x[1], est.m_adapt, est.adapt_elapsed = 900.0, 1810.0, 1800.0, 0.0
    est.S = np.linalg.cholesky(P0).tolist()
    assert est._adapt_sqrt(1.0) == mg.OK
    lam = 0.5 * abs(900.0 - 100.0) / (900.0 + 100.0)
    D = np.diag([1.0, lam, 1.0])
    want = D @ P0 @ D
    want[1, 1] = lam * P0[1, 1]
    S = np.array(est.S)
    scale = np.sqrt(np.outer(np.diag(P0), np.diag(P0)))
    assert np.all(np.abs(S @ S.T - want) <= 1e-14 * scale)
    assert np.all(np.triu(S, 1) == 0.0) and np.all(np.diag(S) >= 0.0)
    assert est.q_mv == pytest.approx(lam * 900.0, rel=1e-15)


def test_tria_is_the_lower_factor_of_a_a_transpose():
    # tria(A) (the port of qr_flt.c) returns S lower triangular with a nonnegative diagonal and
    # S S^T = A A^T: compared to numpy at 1e-14 of the scale (a few dozen roundings of sums
    # of <= 10 products); also through the power-of-two scaling (a row of 1e-300, whose
    # squares would underflow: the same S divided by 1e300 in that row, 1e-14 relative).
    rng = np.random.default_rng(7)
    for rows, cols in ((2, 4), (3, 4), (3, 10), (4, 8)):
        A = rng.standard_normal((rows, cols)) * np.array([1e-2, 1e3, 1.0, 1e-4])[:rows, None]
        S = np.array(mg.tria(A.tolist(), rows, cols))[:, :rows]
        want = A @ A.T
        scale = np.sqrt(np.outer(np.diag(want), np.diag(want)))
        assert np.all(np.abs(S @ S.T - want) <= 1e-14 * scale)
        assert np.all(np.triu(S, 1) == 0.0) and np.all(np.diag(S) >= 0.0)
    A = rng.standard_normal((3, 5))
    tiny = A.copy()
    tiny[1] *= 1e-300
    S = np.array(mg.tria(A.tolist(), 3, 5))[:, :3]
    St = np.array(mg.tria(tiny.tolist(), 3, 5))[:, :3]
    assert np.allclose(St[1] * 1e300, S[1], rtol=1e-14, atol=0.0)
    assert mg.tria([[1.0, math.inf]], 1, 2) is None


def test_downdate_removes_a_rank_one_term_or_fails():
    # L' L'^T = L L^T - v v^T (1e-13 of the scale: hyperbolic rotations lose digits as the
    # difference nears singular; here it stays well conditioned); an indefinite difference
    # is refused.
    P = np.array([[4.0, 2.0, 0.4], [2.0, 5.0, 1.0], [0.4, 1.0, 3.0]])
    v = np.array([0.5, 1.0, -0.3])
    L = np.linalg.cholesky(P).tolist()
    assert mg.downdate(L, 3, v.tolist()) == mg.OK
    L = np.array(L)
    assert np.all(np.abs(L @ L.T - (P - np.outer(v, v))) <= 1e-13 * 5.0)
    L = np.linalg.cholesky(P).tolist()
    assert mg.downdate(L, 3, [3.0, 0.0, 0.0]) == mg.ERR_NOT_POSITIVE_DEFINITE


@pytest.mark.parametrize("config", ({"mg_adaptive": 0.0, "mg_use_ax": 1.0},
                                    {"mg_adaptive": 1.0, "mg_use_ax": 0.0}))
def test_square_root_form_is_the_textbook_form_in_double(config):
    # The two covariance forms are the same filter in exact arithmetic (the joint update with
    # a diagonal R equals the sequential ax-then-v one); in double they differ by rounding
    # carried through the run: on the gear-shift log the mass and grade within 1e-6 of their
    # sd (measured 1.4e-11: rounding 1e-16 carried by a condition of P up to 1e8), every
    # status equal.
    cols, _ = mg.read_log(os.path.join(LOGS, "car_gear_shift.csv"))
    p = mg.preset(**config)
    a = mg.run(cols, p)
    b = mg.run(cols, p, form="textbook")
    assert np.array_equal(a["status"], b["status"])
    assert np.all(np.abs(a["mass"] - b["mass"]) <= 1e-6 * b["sd_mass"])
    assert np.all(np.abs(a["grade"] - b["grade"]) <= 1e-6 * b["sd_grade"])
    assert np.all(np.abs(a["sd_mass"] - b["sd_mass"]) <= 1e-6 * b["sd_mass"])


def test_forms_are_chosen_by_argument():
    with pytest.raises(ValueError):
        mg.MassGrade(mg.preset(), form="joseph")
    with pytest.raises(ValueError):   # the square-root form is the float64 reference only
        mg.MassGrade(mg.preset(), ar=mg.Arith(real=float), form="sqrt")


def test_adaptation_waits_for_its_period_and_ends_at_the_stop_threshold():
    p, est = _adapting(q_mv=900.0, m_now=1810.0, m_a=1800.0)
    est._adapt(0.5)                           # mg_t_adapt = 1 s not yet over: nothing
    assert est.q_mv == 900.0
    stop = p["mg_mv_stop"] * p["mg_q_mc"] ** 2
    p, est = _adapting(q_mv=stop * 1.5, m_now=1800.0, m_a=1800.0)  # D = 0: lambda_u = 1/2
    est._adapt(1.0)
    assert est.q_mv == 0.0                    # 0.75 * stop <= stop: the adaptation ended


def test_bad_parameters_are_rejected():
    for key, val in (("mg_m0", 0.0), ("mg_m0", 1e9), ("R", -0.3), ("mg_r_v", 0.0),
                     ("mg_adaptive", 0.5), ("mg_ut_kappa", -3.0), ("mg_q_mc", float("nan")),
                     ("mg_fc", -0.01), ("mg_theta_max", 2.0), ("mg_slip_max", -0.01),
                     ("mg_slip_max", float("inf")), ("mg_ay_max", -0.5), ("mg_t_curve", -1.0),
                     ("mg_ay_max", float("nan")), ("mg_pause_grade", 8.0),
                     ("mg_pause_grade", 2.5), ("mg_pause_grade", -1.0),
                     ("mg_pause_grade", float("nan")), ("mg_pause_grade_slip", -0.01),
                     ("mg_pause_grade_slip", 1.0625), ("mg_pause_grade_slip", float("nan")),
                     ("mg_pause_grade_dv", -0.01), ("mg_pause_grade_dv", 10.0625),
                     ("mg_pause_grade_dv", float("nan")), ("mg_pause_grade_dv", float("inf"))):
        with pytest.raises(mg.ParamError):
            mg.MassGrade(mg.preset(**{key: val}))
    # the grade from ax needs ax: without it the bits are inert, not refused
    mg.MassGrade(mg.preset(mg_use_ax=0.0, mg_pause_grade=1.0))
    mg.MassGrade(mg.preset(mg_use_ax=0.0, mg_pause_grade=1.0), form="textbook")
    with pytest.raises(ValueError):         # the square-root form's step only
        mg.MassGrade(mg.preset(mg_use_ax=1.0, mg_pause_grade=1.0), form="textbook")
    with pytest.raises(mg.ParamError):
        mg.preset(mg_unknown=1.0)


def test_refused_samples_leave_the_state_unchanged():
    est = mg.MassGrade(mg.preset(mg_use_ax=1.0))
    est.step(mg.MgSample(0.0, 20.0, 300.0, ax=0.1))
    est.step(mg.MgSample(0.02, 20.0, 300.0, ax=0.1))
    before = (list(est.x), [r[:] for r in est.S], est.q_mv, est.t_prev)
    for s, code in ((mg.MgSample(0.04, float("nan"), 300.0, ax=0.1), mg.ERR_NONFINITE),
                    (mg.MgSample(0.04, 20.0, 300.0), mg.ERR_RANGE),          # no ax
                    (mg.MgSample(0.02, 20.0, 300.0, ax=0.1), mg.ERR_RANGE),  # t not rising
                    (mg.MgSample(0.04, 150.0, 300.0, ax=0.1), mg.ERR_RANGE),
                    (mg.MgSample(0.04, 20.0, 300.0, ax=0.1, vx=float("nan")), mg.ERR_NONFINITE),
                    (mg.MgSample(0.04, 20.0, 300.0, ax=0.1, vx=-101.0), mg.ERR_RANGE)):
        assert est.step(s).status == code
        assert (list(est.x), est.S, est.q_mv, est.t_prev) == before


def test_pause_holds_mass_and_grade_while_braking():
    # §4.2 on the stop-and-go log: while paused M and theta keep their values exactly, the
    # grade's variance grows, and the filter resumes (status 0) after each stop.
    cols, _ = mg.read_log(os.path.join(LOGS, "car_stop_and_go.csv"))
    r = mg.run(cols, mg.preset(mg_m0=1650.0 * 0.8, mg_use_ax=1.0))
    st = r["status"]
    paused = st == mg.PAUSED_BRAKE
    assert paused.any() and (st == mg.NO_UPDATE_LOW_SPEED).any()
    idx = np.flatnonzero(paused[1:] & paused[:-1]) + 1
    assert np.all(r["mass"][idx] == r["mass"][idx - 1])
    assert np.all(r["grade"][idx] == r["grade"][idx - 1])
    assert np.all(r["sd_grade"][idx] > r["sd_grade"][idx - 1])
    # the brake flag of the log is 1 exactly where the pedal is pressed; every such sample
    # is paused
    assert np.all(paused[cols["brake"] == 1.0])
    assert st[-1] == mg.OK


def test_slip_pause_holds_mass_and_grade():
    # §4.2 step 3: with the ground speed vx given, a sample whose wheels' speed departs from
    # it by more than mg_slip_max * max(|vx|, mg_v_min) is held like a braked one (M, theta
    # exact, the grade's variance growing, v restarted at the wheels' speed); the same
    # samples without vx are learned from; the threshold is strict; 0 turns it off.
    def cruise(est, n, t0=0.0, v=20.0, **kw):
        return [est.step(mg.MgSample(t0 + 0.02 * k, v, 300.0, ax=0.1, **kw)) for k in range(n)]

    def slipping(est, n, t0, **kw):
        return [est.step(mg.MgSample(t0 + 0.02 * k, 22.0, 3000.0, ax=0.5, **kw))
                for k in range(n)]

    p = mg.preset(mg_use_ax=1.0, mg_adaptive=0.0)
    est = mg.MassGrade(p)
    learned = cruise(est, 50, vx=20.0)[-1]
    assert learned.status == mg.OK
    out = slipping(est, 50, 1.0, vx=20.0)             # 2 m/s of slip at 20 m/s: 0.1 > 0.05
    assert all(o.status == mg.PAUSED_SLIP for o in out)
    assert all(o.mass == learned.mass and o.grade == learned.grade for o in out)
    assert all(b.sd_grade > a.sd_grade for a, b in zip(out, out[1:]))
    assert out[-1].v == 22.0 and out[-1].sd_v == p["mg_r_v"]
    est = mg.MassGrade(p)
    cruise(est, 50, vx=20.0)
    free = slipping(est, 50, 1.0)                      # vx not given: learned
    assert all(o.status == mg.OK for o in free) and abs(free[-1].mass - learned.mass) > 10.0
    # the threshold: 1/8 of vx = 16 is 2 m/s exactly; at it updated, beyond held; below
    # mg_v_min the reference is mg_v_min; the slip comes after the brake, before low speed
    est = mg.MassGrade(mg.preset(mg_use_ax=1.0, mg_slip_max=0.125))
    cruise(est, 5, vx=20.0)
    step = lambda t, v, vx, **kw: est.step(mg.MgSample(t, v, 300.0, ax=0.1, vx=vx, **kw)).status
    assert step(1.0, 18.0, 16.0) == mg.OK
    assert step(1.02, 18.5, 16.0) == mg.PAUSED_SLIP
    assert step(1.04, 13.5, 16.0) == mg.PAUSED_SLIP
    assert step(1.06, 1.5, 1.0) == mg.PAUSED_SLIP       # 0.5 > 0.125 * 3
    assert step(1.08, 1.25, 1.0) == mg.NO_UPDATE_LOW_SPEED
    assert step(1.10, 22.0, 16.0, brake=1.0) == mg.PAUSED_BRAKE
    est = mg.MassGrade(mg.preset(mg_use_ax=1.0, mg_slip_max=0.0))
    assert all(o.status == mg.OK for o in slipping(est, 5, 0.0, vx=20.0))


def test_curve_pause_holds_mass_and_grade_and_its_delay():
    # §4.2 step 4: with ay given and mg_ay_max > 0, a sample with |ay| > mg_ay_max and those
    # less than mg_t_curve after the last such one are held like braked ones (M, theta exact,
    # the grade's variance growing); strict threshold; after slip, before low speed; the
    # same samples without ay, or with mg_ay_max = 0, are learned from.
    def drive(est, n, t0, ay=None, v=20.0):
        return [est.step(mg.MgSample(t0 + 0.01 * k, v + 0.02 * k, 3000.0, ax=0.5, ay=ay))
                for k in range(n)]

    p = mg.preset(mg_use_ax=1.0, mg_adaptive=0.0, mg_ay_max=1.0, mg_t_curve=0.2)
    est = mg.MassGrade(p)
    learned = drive(est, 50, 0.0, ay=0.0)[-1]
    assert learned.status == mg.OK
    held = drive(est, 30, 0.5, ay=-1.5) + drive(est, 25, 0.8, ay=0.2)
    st = [o.status for o in held]
    # 30 curve samples, then 19 whose delay left exceeds half a period (0.19 ... 0.01 s)
    assert st == [mg.PAUSED_CURVE] * 49 + [mg.OK] * 6
    assert all(o.mass == learned.mass and o.grade == learned.grade for o in held[:49])
    assert all(b.sd_grade > a.sd_grade for a, b in zip(held[:49], held[1:49]))
    assert held[-1].mass != learned.mass
    for ay, over in ((None, {}), (-1.5, {"mg_ay_max": 0.0})):   # no ay; the pause off
        est = mg.MassGrade(dict(p, **over))
        drive(est, 50, 0.0, ay=0.0)
        assert all(o.status == mg.OK for o in drive(est, 30, 0.5, ay=ay))
    est = mg.MassGrade(dict(p, mg_t_curve=0.0))
    step = lambda t, ay, **kw: est.step(mg.MgSample(t, kw.pop("v", 20.0), 300.0, ax=0.1,
                                                    ay=ay, **kw)).status
    assert step(0.0, 1.0) == mg.OK                       # at the threshold: updated
    assert step(0.01, 1.0 + 1e-9) == mg.PAUSED_CURVE
    assert step(0.02, 0.0) == mg.OK                      # no delay with mg_t_curve = 0
    assert step(0.03, 2.0, v=1.0) == mg.PAUSED_CURVE     # before low speed
    assert step(0.04, 2.0, vx=10.0) == mg.PAUSED_SLIP    # after slip
    assert step(0.05, 2.0, brake=1.0) == mg.PAUSED_BRAKE
    assert step(0.06, float("nan")) == mg.ERR_NONFINITE
    assert step(0.06, 50.5) == mg.ERR_RANGE


def test_pause_grade_learns_the_grade_and_holds_the_mass():
    # §4.2 mg_pause_grade: braking on a 0.05 rad climb (v-dot = -2 m/s^2, ax = v-dot + g sin
    # theta, exact data), the first braked sample holds (v was correlated with M after the
    # updates) and the next ones keep M and S's mass row (P_MM, P_Mv = 0, P_Mtheta) bit for
    # bit while theta runs to the truth: under a tenth of its error after 2 s (measured
    # 38 -> 1.9 mrad; the C tests measure the same); its sd shrinks. With the brake bit unset
    # (the other two set) the same samples hold theta bit for bit; the slip and low-speed
    # pauses hold with every bit. The change test off (mg_pause_grade_dv 0: the learning mode
    # itself; test_change_test_holds_confirmed_grades_and_learns_contradicted runs it).
    theta = 0.05

    def run(bits, **over):
        over.setdefault("mg_pause_grade_dv", 0.0)
        est = mg.MassGrade(mg.preset(mg_use_ax=1.0, mg_adaptive=0.0, mg_pause_grade=bits,
                                     **over))
        for k in range(50):
            est.step(mg.MgSample(0.02 * k, 20.0, 300.0, ax=0.1))
        outs, rows = [], []
        for k in range(101):
            outs.append(est.step(mg.MgSample(1.0 + 0.02 * k, 20.0 - 0.04 * k, -2000.0,
                                             brake=1.0, ax=-2.0 + 9.81 * math.sin(theta))))
            rows.append((list(est.S[1]), est.S[2][1], est.x[1]))
        return est, outs, rows

    _, outs, rows = run(1.0)
    first = outs[0]
    assert all(o.status == mg.PAUSED_BRAKE for o in outs)
    assert rows[0][0][0] == 0.0 and all(r == rows[0] for r in rows)
    assert all(o.mass == first.mass and o.sd_mass == first.sd_mass for o in outs)
    err0, err = abs(first.grade - theta), abs(outs[-1].grade - theta)
    assert err0 > 0.02 and err < 0.1 * err0
    assert outs[-1].sd_grade < first.sd_grade
    _, off, _ = run(6.0)
    assert all(o.grade == off[0].grade and o.mass == off[0].mass for o in off)
    # the slip and the low speed hold with every bit (no brake delay: mg_t_brake 0)
    est, _, _ = run(7.0, mg_t_brake=0.0)
    g0 = est.x[2]
    o = est.step(mg.MgSample(3.1, 22.0, 3000.0, ax=0.5, vx=18.0))
    assert o.status == mg.PAUSED_SLIP and o.grade == g0
    o = est.step(mg.MgSample(3.12, 1.0, 300.0, ax=0.5))
    assert o.status == mg.NO_UPDATE_LOW_SPEED and o.grade == g0


def test_pause_grade_decides_v_free_from_the_last_sample_not_from_s_mv():
    # §4.2 "v uncorrelated with M" is what the last accepted sample did (a start or a paused
    # sample: v_free; C rfe_mg_v_free), never the value of S_Mv, which an update's rounding
    # can bring to 0 in one number type only (the Q31 twin's Q14 mass row on the noise-free
    # ABS logs, FIXED_POINT.md "Mass and grade"): after updates, with S_Mv forced to exactly
    # 0, the first braked sample still holds (v = the measured speed, S_vv = r_v, theta
    # kept) and the next learns; after a start on a sample that is not paused, the first
    # braked sample learns.
    theta = 0.05
    brake = lambda t, k: mg.MgSample(t, 20.0 - 0.04 * k, -2000.0, brake=1.0,
                                     ax=-2.0 + 9.81 * math.sin(theta))
    est = mg.MassGrade(mg.preset(mg_use_ax=1.0, mg_adaptive=0.0, mg_pause_grade=1.0,
                                 mg_pause_grade_dv=0.0))   # the decision of v_free alone
    for k in range(50):
        assert est.step(mg.MgSample(0.02 * k, 20.0, 300.0, ax=0.1)).status == mg.OK
    assert not est.v_free and est.S[1][0] != 0.0
    est.S[1][0] = 0.0
    g0 = est.x[2]
    o = est.step(brake(1.0, 0))
    assert o.status == mg.PAUSED_BRAKE and o.grade == g0
    assert est.x[0] == 20.0 and est.S[0][0] == est.p["mg_r_v"] and est.v_free
    o = est.step(brake(1.02, 1))
    assert o.status == mg.PAUSED_BRAKE and o.grade != g0
    # a start (the gap beyond mg_dt_max) on a cruise sample: status 0 and v_free
    assert est.step(mg.MgSample(100.0, 20.0, 300.0, ax=0.1)).status == mg.OK
    assert est.v_free
    g0 = est.x[2]
    o = est.step(brake(100.02, 0))
    assert o.status == mg.PAUSED_BRAKE and o.grade != g0


def test_abs_gate_holds_the_rest_of_a_pause_whose_wheels_slip():
    # §4.2 mg_pause_grade_slip: with the brake bit, a brake pause whose wheels cycle as under
    # ABS (vx given, 6 samples 12 % behind it, 4 samples 1 %) holds from its first slipping
    # sample to its end exactly as with the bit off (the latch stays through the samples
    # under the gate); a steady brake at 1 % (under the gate) learns exactly as without the
    # gate; an update clears the latch; a gate of 0 never sets it. The C twins' tests
    # (test_abs_gate_*) check the same in float, double and Q31.
    theta = 0.05

    def run(bits, slip, **over):
        est = mg.MassGrade(mg.preset(mg_use_ax=1.0, mg_adaptive=0.0, mg_pause_grade=bits,
                                     **over))
        for k in range(50):
            est.step(mg.MgSample(0.02 * k, 20.0, 300.0, ax=0.1))
        outs, latch = [], []
        for k in range(101):
            vx = 20.0 - 0.04 * k
            outs.append(est.step(mg.MgSample(1.0 + 0.02 * k, (1.0 - slip(k)) * vx, -2000.0,
                                             brake=1.0, ax=-2.0 + 9.81 * math.sin(theta),
                                             vx=vx)))
            latch.append(est.slip_latched)
        return est, outs, latch

    cycle = lambda k: 0.12 if k % 10 < 6 else 0.01
    assert mg.MG_DEFAULTS["mg_pause_grade_slip"] == 0.05
    _, held, _ = run(0.0, cycle)
    _, gated, latch = run(1.0, cycle)
    assert gated == held and all(latch)
    _, ungated, latch = run(1.0, cycle, mg_pause_grade_slip=0.0)
    assert ungated != held and not any(latch)
    steady = lambda k: 0.01
    est, gated, latch = run(1.0, steady)
    _, ungated, _ = run(1.0, steady, mg_pause_grade_slip=0.0)
    assert gated == ungated and not any(latch)
    # learned: under a fifth of the start's error after 2 s (the exact-data bound of a tenth,
    # test_pause_grade_learns_the_grade_and_holds_the_mass, plus the bias of the 1 % slip:
    # the wheels decelerate 1 % slower than the car, 0.02 m/s^2 ~ 2 mrad of grade; measured
    # 38 -> 3.8 mrad)
    assert abs(gated[-1].grade - theta) < 0.2 * abs(gated[0].grade - theta)
    est, _, _ = run(1.0, cycle, mg_t_brake=0.0)
    assert est.slip_latched
    o = est.step(mg.MgSample(3.1, 18.0, 300.0, ax=0.1, vx=18.0))
    assert o.status == mg.OK and not est.slip_latched


def test_change_test_holds_confirmed_grades_and_learns_contradicted():
    # §4.2 mg_pause_grade_dv (0.2 m/s by default): braking on a 0.05 rad climb with the brake
    # bit (the samples of test_pause_grade_learns_the_grade_and_holds_the_mass). The held
    # grade right (set to the truth): every sample holds, theta bit for bit (the learning's
    # noise never added). The held grade of the cruise (0.012 rad, 0.038 off): the samples
    # hold until the residual sum (u - u_prev) - dt (ax - g sin theta), growing by
    # g (sin 0.05 - sin theta_held) dt = 7.5e-3 m/s a sample, passes 0.2 m/s (the sample
    # computed here from the samples' definition; in float64 the sum's rounding cannot move
    # it), then learns to under a tenth of the error by the pause's end (the learning mode's
    # bound). Wheels 0.3 m/s behind a right vx hold (the test reads vx where given); the
    # same wheels without vx trip at the first eligible sample.
    theta = 0.05
    ax = -2.0 + 9.81 * math.sin(theta)

    def start():
        est = mg.MassGrade(mg.preset(mg_use_ax=1.0, mg_adaptive=0.0, mg_pause_grade=1.0))
        for k in range(50):
            est.step(mg.MgSample(0.02 * k, 20.0, 300.0, ax=0.1))
        return est

    def brake(k, behind=0.0, vx=False):
        v = 20.0 - 0.04 * k
        return mg.MgSample(1.0 + 0.02 * k, v - (behind if k > 0 else 0.0), -2000.0,
                           brake=1.0, ax=ax, vx=v if vx else None)

    assert mg.MG_DEFAULTS["mg_pause_grade_dv"] == 0.2
    est = start()
    est.x[2] = theta
    for k in range(151):
        o = est.step(brake(k))
        assert o.status == mg.PAUSED_BRAKE and o.grade == theta and not est.chg_on
    est = start()
    held = est.x[2]
    d, trip = 0.0, None
    for k in range(1, 200):
        d += -0.04 - 0.02 * (ax - 9.81 * math.sin(held))
        if abs(d) > 0.2:
            trip = k
            break
    assert 20 < trip < 35
    outs = [est.step(brake(k)) for k in range(151)]
    assert all(o.grade == held for o in outs[:trip])
    assert outs[trip].grade != held and est.chg_on
    err0 = abs(held - theta)
    assert abs(outs[-1].grade - theta) < 0.1 * err0
    est = start()
    est.x[2] = theta
    for k in range(101):
        o = est.step(brake(k, 0.3, vx=True))
        assert o.grade == theta and not est.chg_on and not est.slip_latched
    est = start()
    est.x[2] = theta
    est.step(brake(0, 0.3))
    o = est.step(brake(1, 0.3))
    assert est.chg_on and o.grade != theta


def test_ukf_with_ax_meets_the_mass_target_on_the_truck_drive():
    # Issue 19's target, 2 % within 10 s of the first excitation from a 20 % error, on the
    # seed-like truck drive; measured 0.6 % worst over four starts (MASS_GRADE_RESULTS.md),
    # so 2 % holds with margin without being a tuned bound.  Also: P symmetric by
    # construction and its diagonal positive all the way.
    cols, _ = mg.read_log(os.path.join(LOGS, "truck_graded_drive.csv"))
    mt = cols["mass_true"][0]
    r = mg.run(cols, mg.preset("truck", mg_m0=0.8 * mt, mg_adaptive=0.0, mg_use_ax=1.0))
    t = r["t"]
    err = np.abs(r["mass"] - mt) / mt
    assert np.all(err[t >= 10.0] <= 0.02)
    assert np.all(r["sd_mass"] > 0.0) and np.all(r["sd_grade"] > 0.0)
    assert np.all(r["status"] == mg.OK)


@pytest.mark.parametrize("start", [0.5, 1.5])
def test_recommended_preset_meets_the_targets_on_the_light_hilly_road(start):
    # Issue 19's passenger car at the light end of 1 500-2 100 kg (car_hilly_road_light,
    # 1500 kg, the hilly road's hills of +-6 %), from the widest starts (-50 and +50 %): the
    # mass within 2 % from 10 s after the first excitation on (the first sample, not paused,
    # where the true |dv/dt| reaches 0.1 m/s^2, as MASS_GRADE_RESULTS.md reads it) and the
    # grade RMSE from then on within 0.3 deg.  Both bounds are the targets, not tuned
    # to the log: measured 0.51 % and 0.257 deg worst over four starts (MASS_GRADE_RESULTS.md).
    cols, _ = mg.read_log(os.path.join(LOGS, "car_hilly_road_light.csv"))
    mt = float(cols["mass_true"][0])
    assert mt == 1500.0
    r = mg.run(cols, mg.preset("car", **mg.MG_CONFIGS["recommended"], mg_m0=start * mt))
    t = r["t"]
    acc = np.gradient(cols["vx_true"], t)
    exc = np.flatnonzero((np.abs(acc) >= 0.1) & (r["status"] == mg.OK))
    assert exc.size
    after = t >= t[exc[0]] + 10.0
    assert np.count_nonzero(after) > 0.9 * len(t)     # the targets read on most of the log
    assert np.all(np.abs(r["mass"][after] - mt) / mt <= 0.02)
    ge = r["grade"][after] - cols["grade_true"][after]
    assert np.sqrt(np.mean(ge ** 2)) <= np.radians(0.3)


GOLDEN_MG = os.path.join(REPO, "scenarios", "golden", "mass_grade")


# REQ-MG-001
@pytest.mark.skipif(not os.path.isdir(GOLDEN_MG), reason="no mass and grade goldens")
@pytest.mark.parametrize("name,config", [("car_gear_shift", "aukf_ax"),
                                         ("car_stop_and_go", "recommended"),
                                         ("car_stop_and_go", "pause_grade")])
def test_mass_grade_goldens_are_up_to_date(name, config):
    # The committed goldens (make mass-grade-goldens) are what the reference writes now: the
    # same rows (index, status), the values within 1e-9 relative (plain Python floats on
    # the estimator's path; only glibc's sin, cos and pow could differ by an ulp on another
    # machine, ~1e-16, far below), and the configuration it records.
    import sys
    sys.path.insert(0, os.path.join(REPO, "scripts", "data"))
    import make_mass_grade_goldens as mmg
    meta, cols, rows = mmg.golden(os.path.join(LOGS, name + ".csv"), config)
    now = np.array(rows)
    path = os.path.join(GOLDEN_MG, f"{name}.{config}.csv")
    with open(path, encoding="utf-8") as fh:
        lines = fh.read().splitlines()
    old_meta = dict(ln[2:].split(" = ", 1) for ln in lines if ln.startswith("# "))
    body = [ln for ln in lines if not ln.startswith("#")]
    assert body[0].split(",") == list(cols)
    old = np.array([[float(v) for v in ln.split(",")] for ln in body[1:]])
    assert now.shape == old.shape
    k, st = cols.index("k"), cols.index("status")
    assert np.array_equal(now[:, k], old[:, k]) and np.array_equal(now[:, st], old[:, st])
    assert np.allclose(now, old, rtol=1e-9, atol=1e-12)
    for key, val in meta:
        assert old_meta[key] == (repr(val) if isinstance(val, float) else str(val))


# -- §4.7 the grade's two-level walk ---------------------------------------------------------
def _walk_filter(**over):
    est = mg.MassGrade(mg.preset("car", mg_use_ax=1.0, mg_adaptive=0.0, **over))
    est.step(mg.MgSample(0.0, 10.0, 0.0, None, None, None, 0.0))   # a start
    return est


def _ramp(est, rate, seconds, dt=0.01):
    """Drive §4.7's level logic alone with a grade that moves at @rate rad/s."""
    for _ in range(int(round(seconds / dt))):
        est.x[2] += rate * dt
        est._walk_level(dt)


def test_walk_loosens_on_a_moving_grade_and_keeps_its_level_between_thresholds():
    # thresholds 2 and 1 mrad/s (RMS of the low-passed rate); after 20 s (> 6 tau of the
    # 3 s mean) of a steady ramp s is within 0.2 % of rate^2, so the level is decided by
    # rate against the thresholds with a wide margin each time (5, 1.5, 0.5 mrad/s)
    est = _walk_filter(mg_q_theta_hi=0.008)
    assert not est.wq_hi and est._q_theta() == 0.004
    _ramp(est, 0.005, 20.0)
    assert est.wq_hi and est._q_theta() == 0.008
    _ramp(est, 0.0015, 20.0)            # between off and on: stays loose (hysteresis)
    assert est.wq_hi
    _ramp(est, 0.0005, 20.0)            # below off: tight again
    assert not est.wq_hi and est._q_theta() == 0.004
    _ramp(est, 0.0015, 20.0)            # between: stays tight
    assert not est.wq_hi


def test_walk_off_never_loosens():
    est = _walk_filter()                # mg_q_theta_hi 0 (the default): off
    _ramp(est, 0.01, 20.0)
    assert not est.wq_hi and est._q_theta() == 0.004


def test_walk_with_equal_levels_computes_what_the_fixed_walk_does():
    # mg_q_theta_hi = mg_q_theta: the level may switch but q_theta is the same, so the
    # estimates are bit-identical to the walk off: the statistic touches nothing else
    cols, _ = mg.read_log(os.path.join(LOGS, "car_hilly_road.csv"))
    cols = {k: v[:3000] for k, v in cols.items()}
    base = mg.run(cols, mg.preset("car", mg_use_ax=1.0, mg_adaptive=0.0))
    p = mg.preset("car", mg_use_ax=1.0, mg_adaptive=0.0)
    p.update(mg_q_theta_hi=0.004, mg_theta_rate_on=1e-4, mg_theta_rate_off=1e-4)
    same = mg.run(cols, p)
    for k in ("mass", "grade", "sd_mass", "sd_grade", "status"):
        assert np.array_equal(base[k], same[k])


@pytest.mark.parametrize("over", [{"mg_q_theta_hi": 0.003},            # below mg_q_theta
                                  {"mg_q_theta_hi": 0.2},              # above 0.1
                                  {"mg_theta_rate_off": 0.003},        # off > on
                                  {"mg_theta_rate_off": 0.0},
                                  {"mg_theta_rate_tau": 0.5},          # < mg_dt_max (1 s)
                                  {"mg_theta_rate_avg": 61.0}])
def test_walk_keys_are_validated(over):
    p = mg.preset("car")
    p.update(over)
    with pytest.raises(mg.ParamError):
        mg.MassGrade(p)


def test_walk_keys_are_library_defaults_and_off():
    # §4.7's keys are MG_DEFAULTS' (every golden's metadata and the C parameter files carry
    # them), with the two-level walk off, so the goldens are the fixed walk's
    d = mg.MG_DEFAULTS
    assert d["mg_q_theta_hi"] == 0.0
    assert (d["mg_theta_rate_on"], d["mg_theta_rate_off"]) == (0.002, 0.001)
    assert (d["mg_theta_rate_tau"], d["mg_theta_rate_avg"]) == (1.0, 3.0)
    with pytest.raises(mg.ParamError):
        mg.preset("car", mg_no_such_key=1.0)


# -- §4.8 the model-mismatch monitor ---------------------------------------------------------

def _headwind(rows):
    cols, _ = mg.read_log(os.path.join(LOGS, "car_headwind.csv"))
    return {k: v[:rows] for k, v in cols.items()}


def test_mismatch_ema_is_the_ax_rows_normalised_innovation_averaged():
    # the EMA recomputed from the probe's innovations with §4.8's recursion m += (dt/tau)(e - m)
    # on the updates that ran the ax row (status 0), m = 0 at the start: the same operations
    # in the same order as the filter's, so equal to the bit; tau 2 s (not the default) shows
    # the key is read
    cols = _headwind(1500)
    p = mg.preset("car", **mg.MG_CONFIGS["recommended"], mg_mm_tau=2.0)
    est = mg.MassGrade(p)
    seen = {}
    est.probe = lambda row, innov, sd: seen.__setitem__(row, innov / sd)
    m, t_prev, flagged = 0.0, None, 0
    for s in mg.samples(cols, est.p):
        seen.clear()
        o = est.step(s)
        if o.status == mg.OK and "ax" in seen:
            m += ((s.t - t_prev) / 2.0) * (seen["ax"] - m)
        t_prev = s.t
        assert o.e_ax == m
        assert o.mismatch == (abs(m) > p["mg_mm_e"])
        flagged += o.mismatch
    # 30 s of the headwind: the flag sets (its first 20 s of windowed mean already cross,
    # MASS_GRADE_RESULTS.md), so the comparison above covered both values of the flag
    assert flagged > 0


def test_mismatch_monitor_changes_no_estimate_and_mg_mm_e_zero_never_flags():
    cols = _headwind(1000)
    base = mg.run(cols, mg.preset("car", **mg.MG_CONFIGS["recommended"]))
    off = mg.run(cols, mg.preset("car", **mg.MG_CONFIGS["recommended"], mg_mm_e=0.0,
                                 mg_mm_tau=30.0))
    # the monitor only reads the update: every estimate the same to the bit
    for k in ("mass", "sd_mass", "grade", "sd_grade", "v", "status"):
        assert np.array_equal(base[k], off[k]), k
    assert not off["mismatch"].any() and np.any(off["e_ax"] != 0.0)
    # the default threshold is the measured one (2 x 0.150, MASS_GRADE_RESULTS.md)
    assert mg.MG_DEFAULTS["mg_mm_e"] == 0.3 and mg.MG_DEFAULTS["mg_mm_tau"] == 10.0


def test_mismatch_ema_is_zero_without_the_ax_row_and_after_a_restart():
    cols = _headwind(600)
    seed = mg.run(cols, mg.preset("car", **mg.MG_CONFIGS["seed"]))
    assert np.all(seed["e_ax"] == 0.0) and not seed["mismatch"].any()
    est = mg.MassGrade(mg.preset("car", **mg.MG_CONFIGS["recommended"]))
    last = None
    for s in mg.samples(cols, est.p):
        last = est.step(s)
    assert last.e_ax != 0.0
    # a period over mg_dt_max (1 s) restarts the filter (§4.1): the EMA starts again at 0
    s = mg.MgSample(last_t := float(cols["t"][-1]) + 2.0, 20.0, 300.0, ax=0.1)
    assert last_t > 0.0 and est.step(s).e_ax == 0.0


@pytest.mark.parametrize("over", [{"mg_mm_tau": 0.5},      # < mg_dt_max (1 s)
                                  {"mg_mm_tau": 61.0},
                                  {"mg_mm_e": -0.1},
                                  {"mg_mm_e": 101.0},
                                  {"mg_mm_e": float("nan")}])
def test_mismatch_keys_are_validated(over):
    p = mg.preset("car")
    p.update(over)
    with pytest.raises(mg.ParamError):
        mg.MassGrade(p)
