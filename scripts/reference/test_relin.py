"""Step 6 re-linearised (`relin_steps`: the recursive update; `relin_iter`: the iterated
posterior linearisation; `relin_gate`; reference only, not in the C library;
docs/MONITOR.md section 21). Off (0, both presets) neither is evaluated and the run is
today's; for a linear h and for N = 1 / one iteration both are today's update.
(run: .venv/bin/python -m pytest scripts/reference/test_relin.py -q)"""

from __future__ import annotations

import os

import numpy as np
import pytest

from . import filters, logs, params, trusted
from ._testing import assert_study_keys_off

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
LOG = os.path.join(REPO, "scenarios", "brake_in_turn.mf.csv")   # first update at 0.25 s
KEYS = ("relin_steps", "relin_iter", "relin_gate")
S_R = np.diag([0.2, 0.3, 0.4])
Y = np.array([0.1, -0.2, 0.05])
S0 = [[0.3, 0.0], [0.1, 0.2]]
A_LIN = np.array([[1.0, 0.5], [-0.3, 2.0], [0.7, 0.1]])   # full column rank


def _filter(x=(0.5, 0.6), s=S0):
    return filters.SCKF(np.array(x, dtype=float), np.array(s, dtype=float), np.eye(2) * 1e-3,
                        S_R)


def lin_h(pts):
    return A_LIN @ pts


def sat_h(pts):
    """A saturating 'tyre': smooth, steep at a low x_0 and flat above it, plus a linear part
    in x_1 (nonlinear enough that re-linearising moves the result)."""
    g = np.array([5.0, -3.0, 1.0])
    return np.outer(g, np.tanh(3.0 * pts[0])) + np.outer([0.2, 0.1, -0.4], pts[1])


def _today(h):
    f = _filter()
    f.measurement_update(Y, h)
    return f


def test_off_is_never_evaluated(monkeypatch):
    """The keys are 0 by default, in neither preset and reference only; off, neither update
    is called and the run records no final information."""
    assert_study_keys_off(KEYS)
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = _head(logs.read_csv_log(LOG), 40)

    def fail(*a, **k):
        raise AssertionError("a re-linearised update was evaluated while off")
    monkeypatch.setattr(trusted, "recursive_update", fail)
    monkeypatch.setattr(trusted, "iterated_posterior_update", fail)
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    out = trusted.run(log, p)
    assert "relin_info" not in out


def test_one_step_and_one_iteration_are_today_bit_for_bit():
    """N = 1 is measurement_update with f.s_r times sqrt(1) = 1 (the same numbers), and the
    first iteration is that call: x and S equal to the bit, on a nonlinear h."""
    ref = _today(sat_h)
    for upd in (lambda f: trusted.recursive_update(f, Y, sat_h, 1, S_R),
                lambda f: trusted.iterated_posterior_update(f, Y, sat_h, 1, S_R)):
        f = _filter()
        upd(f)
        assert np.array_equal(f.x, ref.x)
        assert np.array_equal(f.S, ref.S)
        assert np.array_equal(f.s_r, S_R)    # the update's noise restored


@pytest.mark.parametrize("n", [2, 4])
def test_linear_h_is_one_update(n):
    """h = A x: the cubature update is the exact Kalman update, N of them with R N add up to
    one with R (information adds), and the IPLF's regression is A itself with Omega = 0, so
    every iteration is the first's posterior. Tolerance 1e-12: a few rounding steps of
    O(1) numbers (the products' conditioning is that of A, S0 and S_R, all near 1)."""
    ref = _today(lin_h)
    for upd in (lambda f: trusted.recursive_update(f, Y, lin_h, n, S_R),
                lambda f: trusted.iterated_posterior_update(f, Y, lin_h, n, S_R)):
        f = _filter()
        upd(f)
        assert np.allclose(f.x, ref.x, rtol=0.0, atol=1e-12)
        assert np.allclose(f.S @ f.S.T, ref.S @ ref.S.T, rtol=0.0, atol=1e-12)


def test_recursive_update_is_the_covariance_form_applied_n_times():
    """On a nonlinear h the square-root recursive update equals the covariance-form cubature
    filter (filters.CKF: its own points from chol(P), its own formulas) updated N = 3 times
    with R 3. Tria's S has a non-negative diagonal, so its points are chol(P)'s up to rounding;
    1e-10 covers the rounding of three updates (each ~1e-15 relative, amplified by the
    tanh's slope 3 and the gains below 10)."""
    n = 3
    f = _filter()
    trusted.recursive_update(f, Y, sat_h, n, S_R)
    s0 = np.array(S0)
    c = filters.CKF(np.array([0.5, 0.6]), s0 @ s0.T, np.zeros((2, 2)), n * S_R @ S_R.T)
    for _ in range(n):
        c.measurement_update(Y, sat_h)
    assert np.allclose(f.x, c.x, rtol=0.0, atol=1e-10)
    assert np.allclose(f.S @ f.S.T, c.P, rtol=0.0, atol=1e-10)


def _iplf_covariance(x0, p0, r, h, n_iter):
    """The IPLF in covariance form, written from the paper's equations with numpy's inverse
    (independent of the square-root code): points from chol(P_j); A = Psi^T P_j^-1,
    b = z - A x_j, Omega = Phi - A P_j A^T; x = x0 + K (y - A x0 - b), K = P0 A^T (A P0 A^T +
    R + Omega)^-1, P = P0 - K (A P0 A^T + R + Omega) K^T. Iteration 1 at the prior."""
    n = x0.size
    xi = np.hstack([np.eye(n), -np.eye(n)]) * np.sqrt(n)
    x, p = x0.copy(), p0.copy()
    for _ in range(n_iter):
        pts = np.linalg.cholesky(p) @ xi + x[:, None]
        z = h(pts)
        z_bar = z.mean(axis=1)
        psi = (pts - x[:, None]) @ (z - z_bar[:, None]).T / (2 * n)
        phi = (z - z_bar[:, None]) @ (z - z_bar[:, None]).T / (2 * n)
        a = psi.T @ np.linalg.inv(p)
        b = z_bar - a @ x
        om = phi - a @ p @ a.T
        s = a @ p0 @ a.T + r + om
        k = p0 @ a.T @ np.linalg.inv(s)
        x = x0 + k @ (Y - a @ x0 - b)
        p = p0 - k @ s @ k.T
    return x, p


@pytest.mark.parametrize("m", [2, 3])
def test_iterated_update_is_the_papers_covariance_form(m):
    """On a nonlinear h the square-root IPLF equals the paper's covariance form (above) to
    1e-10 (rounding of m iterations of O(1) numbers, the same amplification as above), and
    it differs from today's update by far more (re-linearising moves it), so the comparison
    can fail."""
    f = _filter()
    trusted.iterated_posterior_update(f, Y, sat_h, m, S_R)
    s0 = np.array(S0)
    x, p = _iplf_covariance(np.array([0.5, 0.6]), s0 @ s0.T, S_R @ S_R.T, sat_h, m)
    assert np.allclose(f.x, x, rtol=0.0, atol=1e-10)
    assert np.allclose(f.S @ f.S.T, p, rtol=0.0, atol=1e-10)
    assert np.max(np.abs(f.x - _today(sat_h).x)) > 1e-4


def test_the_final_information_is_the_last_linearisations():
    """The information returned is step 5's, I_k = sum_r (S_R^-1 J)_rk^2: for the IPLF of the
    last regression's A (recomputed here from the covariance form's last iterate), for the
    recursive update of the last sub-step's slope over its points; with one step / one
    iteration both are today's gate's information at the prior, bit for bit."""
    f = _filter()
    _, xc, zc = f.centred(sat_h)
    gate = trusted._information_of(f, xc, zc, S_R)
    for upd in (trusted.recursive_update, trusted.iterated_posterior_update):
        assert np.array_equal(upd(_filter(), Y, sat_h, 1, S_R), gate)
    s0 = np.array(S0)
    x1, p1 = _iplf_covariance(np.array([0.5, 0.6]), s0 @ s0.T, S_R @ S_R.T, sat_h, 1)
    pts = np.linalg.cholesky(p1) @ (np.hstack([np.eye(2), -np.eye(2)]) * np.sqrt(2)) + x1[:, None]
    z = sat_h(pts)
    psi = (pts - x1[:, None]) @ (z - z.mean(axis=1)[:, None]).T / 4
    w = np.linalg.inv(S_R) @ (psi.T @ np.linalg.inv(p1))
    info = trusted.iterated_posterior_update(_filter(), Y, sat_h, 2, S_R)
    assert np.allclose(info, np.sum(w * w, axis=0), rtol=1e-9, atol=0.0)   # rounding
    assert np.max(np.abs(info - gate)) > 1e-3     # and not the prior's


def test_both_at_once_is_refused():
    with pytest.raises(ValueError):
        trusted._relin_mode(dict(relin_steps=2.0, relin_iter=2.0))
    with pytest.raises(ValueError):
        trusted._relin_mode(dict(relin_steps=1.5, relin_iter=0.0))
    assert trusted._relin_mode(dict(relin_steps=0.0, relin_iter=0.0)) is None


def _head(log, n):
    return logs.CsvLog(log.path, dict(log.meta), {k: v[:n] for k, v in log.columns.items()})


def test_on_a_log_one_step_with_the_gate_is_today():
    """relin_steps = 1 with relin_gate = 1 on brake_in_turn.mf's first 3 s: the final
    linearisation is the prior's, so the added gate is today's gate and the run is today's bit
    for bit; the recorded information equals step 5's at every update. With N = 2 the first
    update (0.25 s) differs (the option acts on the log)."""
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = _head(logs.read_csv_log(LOG), 300)
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    today = trusted.run(log, p)
    one = trusted.run(log, dict(p, relin_steps=1.0, relin_gate=1.0))
    for k in ("mu", "sd", "valid", "status", "info"):
        assert np.array_equal(one[k], today[k]), k
    upd = np.isin(today["status"], (0, 1))
    assert upd.any()
    assert np.array_equal(one["relin_info"][upd], today["info"][upd])
    assert np.all(np.isnan(one["relin_info"][~upd]))
    two = trusted.run(log, dict(p, relin_steps=2.0))
    k = int(np.flatnonzero(upd)[0])
    assert abs(today["t"][k] - 0.25) < 1e-9
    assert not np.array_equal(two["mu"][k], today["mu"][k])
