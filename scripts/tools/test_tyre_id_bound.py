"""The bound machinery of scripts/tools/tyre_id_bound.py against answers known in closed form:
a linear-Gaussian toy (its Fisher information is sum A^T R^-1 A + P0^-1 exactly, and its MAP
estimate's error covariance averaged over the prior is J^-1), the Magic Formula's analytic
derivative in D, and two properties of the tool on the bundled logs (no lateral excitation:
no information on D; the two central-difference steps agree).  About 3 s.
"""
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path[:0] = [str(ROOT / "scripts"), str(ROOT / "scripts" / "tools")]
import tyre_id_bound as B  # noqa: E402
from reference import tyre_id as T  # noqa: E402

N_K, M, N = 40, 2, 3          # samples, outputs, unknowns of the toy


def toy():
    """y_k = A_k theta (+ noise): A (N_K, M, N), R sds, prior sds and mean, a truth."""
    g = np.random.default_rng(7)
    a = g.standard_normal((N_K, M, N))
    a[:, :, 2] *= 0.05            # a weakly observed unknown: the prior matters for it
    return a, np.array([0.5, 2.0]), np.array([1.0, 3.0, 0.7]), np.array([0.2, -1.0, 0.4]), \
        np.array([0.9, 1.0, 0.0])


def linear(a):
    return lambda phi: np.einsum("kmn,bn->kbm", a, phi)


def closed_form_J(a, r_sd, prior_sd, meas):
    j = np.diag(1.0 / prior_sd ** 2)
    out = []
    for k in range(N_K):
        if meas[k]:
            j = j + a[k].T @ np.diag(1.0 / r_sd ** 2) @ a[k]
        out.append(j)
    return np.array(out)


def test_central_differences_of_a_linear_map_are_its_matrix():
    a, _, prior_sd, _, truth = toy()
    y0, s = B.central_diff(linear(a), truth, 1e-3 * prior_sd)
    # exact up to rounding: |y| <= ~10, step >= 7e-4, so the quotient's rounding is below
    # 10 * 2.2e-16 / 7e-4 ~ 3e-12
    np.testing.assert_allclose(s, a, rtol=0, atol=1e-10)
    np.testing.assert_allclose(y0, a @ truth, rtol=0, atol=1e-12)


def test_fisher_is_the_closed_form_and_the_bound_its_inverse():
    a, r_sd, prior_sd, _, truth = toy()
    meas = np.ones(N_K, dtype=bool)
    meas[[0, 5, 6]] = False       # samples that do not measure add nothing
    _, s = B.central_diff(linear(a), truth, 1e-3 * prior_sd)
    j = B.fisher_cumulative(s, meas, r_sd, prior_sd)
    jc = closed_form_J(a, r_sd, prior_sd, meas)
    # the sensitivities agree to 1e-10 (above); J's entries are sums of 40 products of them
    np.testing.assert_allclose(j, jc, rtol=1e-8)
    for i in range(N):
        np.testing.assert_allclose(B.bound_sd(j, i),
                                   np.sqrt(np.linalg.inv(jc)[:, i, i]), rtol=1e-8)


def test_prior_only_bound_is_the_prior_sd():
    a, r_sd, prior_sd, _, truth = toy()
    _, s = B.central_diff(linear(a), truth, 1e-3 * prior_sd)
    j = B.fisher_cumulative(s, np.zeros(N_K, dtype=bool), r_sd, prior_sd)
    for i in range(N):
        np.testing.assert_allclose(B.bound_sd(j, i), prior_sd[i], rtol=1e-14)


def test_bound_falls_monotonically_with_more_data():
    a, r_sd, prior_sd, _, truth = toy()
    _, s = B.central_diff(linear(a), truth, 1e-3 * prior_sd)
    j = B.fisher_cumulative(s, np.ones(N_K, dtype=bool), r_sd, prior_sd)
    for i in range(N):
        b = B.bound_sd(j, i)
        assert b[0] < prior_sd[i]
        # J grows in the Loewner order, so each diagonal of J^-1 cannot rise; 1e-12 relative:
        # the inverse's rounding on a matrix of condition below 1e4
        assert np.all(np.diff(b) <= 1e-12 * b[:-1])
        # 39 more samples: the well observed unknowns narrow by more than half, the weak one
        # (its column scaled by 0.05) by less, but still narrows
        assert b[-1] < (0.5 if i < 2 else 0.95) * b[0]


def test_known_unknowns_are_the_limit_of_a_sharp_prior():
    """bound_sd with keep (the others known) is the bound whose prior pins the others."""
    a, r_sd, prior_sd, _, truth = toy()
    _, s = B.central_diff(linear(a), truth, 1e-3 * prior_sd)
    meas = np.ones(N_K, dtype=bool)
    keep = [0, 2]
    sharp = prior_sd.copy()
    sharp[1] = 1e-7               # unknown 1 known to 1e-7: its coupling leaves ~1e-14
    b_keep = B.bound_sd(B.fisher_cumulative(s, meas, r_sd, prior_sd), 2, keep)
    b_sharp = B.bound_sd(B.fisher_cumulative(s, meas, r_sd, sharp), 2)
    np.testing.assert_allclose(b_keep, b_sharp, rtol=1e-6)
    assert np.all(b_keep <= B.bound_sd(B.fisher_cumulative(s, meas, r_sd, prior_sd), 2))


def test_map_mse_over_the_prior_is_the_bound_and_at_one_truth_its_formula():
    """Monte Carlo of the exact MAP of the toy (all samples): its squared error averaged over
    truths drawn from the prior is J^-1 (Van Trees met with equality), and at one truth it is
    map_mse's, below J^-1 there (the truth within the prior's spread of its mean)."""
    a, r_sd, prior_sd, prior_mean, truth = toy()
    meas = np.ones(N_K, dtype=bool)
    _, s = B.central_diff(linear(a), truth, 1e-3 * prior_sd)
    j = B.fisher_cumulative(s, meas, r_sd, prior_sd)[-1]
    ji = np.linalg.inv(j)
    f = a.reshape(N_K * M, N)
    w = np.tile(1.0 / r_sd ** 2, N_K)
    pinv = 1.0 / prior_sd ** 2
    g = np.random.default_rng(11)
    n_mc = 20000

    def map_errors(th):
        y = th @ f.T + np.tile(r_sd, N_K) * g.standard_normal((n_mc, N_K * M))
        # the MAP: J theta = F^T R^-1 y + P0^-1 m, one column a draw
        est = np.linalg.solve(j, ((y * w) @ f + pinv * prior_mean).T).T
        return est - th
    th_prior = prior_mean + prior_sd * g.standard_normal((n_mc, N))
    e = map_errors(th_prior)
    # a variance estimated from 20,000 draws has a relative sd sqrt(2/20000) = 1 %: 5 sds
    np.testing.assert_allclose(np.mean(e ** 2, axis=0), np.diag(ji), rtol=0.05)
    e1 = map_errors(np.tile(truth, (n_mc, 1)))
    for i in range(N):
        mse = B.map_mse(j[None], prior_sd, prior_mean - truth, i)[0]
        np.testing.assert_allclose(np.mean(e1[:, i] ** 2), mse, rtol=0.05)
    # this truth lies within one prior sd of the mean: the MAP beats J^-1 in every unknown
    assert all(B.map_mse(j[None], prior_sd, prior_mean - truth, i)[0] < ji[i, i]
               for i in range(N))


def test_model_sensitivity_in_D_is_the_analytic_derivative():
    """dFy/dD of the identifier's Magic Formula at fixed C, K, E (B = K/(C D)) by
    central_diff through tyre_id._Model.forces, against
    sin(C phi) + D cos(C phi) C / (1 + psi^2) (1 - E + E/(1 + x^2)) (-x / D)."""
    p = B.identifier_params()
    model = T._Model(p, T.NUMPY)
    D, C, K, E = 7000.0, 1.4, 15.0 * 8000.0, -0.5
    th0 = np.array([D, C, K, E, 6000.0, 1.5, 17.0 * 6000.0, 0.3])
    for vy in (0.1, 0.5, 1.2):    # front slips from linear to past the peak
        def f(phi):
            th = np.tile(th0, (phi.shape[0], 1))
            th[:, 0] = phi[:, 0]
            fy, _ = model.forces(np.full(phi.shape[0], vy), np.zeros(phi.shape[0]), th,
                                 0.05, 20.0)
            return fy[None, :, None]
        _, s = B.central_diff(f, np.array([D]), np.array([1e-4 * 0.3 * D]))
        t = np.tan(0.05 - np.arctan2(vy, 20.0))
        b = K / (C * D)
        x = b * t
        psi = x - E * (x - np.arctan(x))
        phi = np.arctan(psi)
        d = np.sin(C * phi) + D * np.cos(C * phi) * C / (1.0 + psi ** 2) * \
            (1.0 - E + E / (1.0 + x * x)) * (-x / D)
        # truncation (h/D)^2 ~ 1e-9 relative, rounding 1e-16 * 1e4 N / 0.2 N ~ 5e-12
        np.testing.assert_allclose(s[0, 0, 0], d, rtol=1e-6, atol=1e-9)


def test_straight_log_gives_no_information_on_D_and_steps_agree():
    """tid_straight (delta 0, from rest in yaw): every trajectory of the batch has zero slip,
    so dy/dD = 0 and the bound on mu stays the prior sd tid_sd0_mu; on the high-mu ramp the
    two central-difference steps agree."""
    res = B.bound_log(("tid_straight", 1e-4, 1e-3))
    p = B.identifier_params()
    for a in "fr":
        assert res[f"nlim_{a}"] == 0
        assert res[f"lin_{a}"] == pytest.approx(p["tid_sd0_mu"], rel=1e-12)
        assert res[f"final_{a}"] == pytest.approx(p["tid_sd0_mu"], rel=1e-12)
    ramp = B.bound_log(("tid_ramp_steer_high_mu", 1e-4, 1e-3))
    for a in "fr":
        # central differences err by O(h^2): a 10x step changes a converged bound by well
        # under 1 % (measured 4e-4); an unconverged one (step too large or too small for
        # the rounding) would not agree
        assert ramp[f"step_dev_{a}"] < 1e-2
        # the ramp reaches the limit: the data say far more than the prior
        assert ramp[f"final_{a}"] < 0.1 * p["tid_sd0_mu"]
