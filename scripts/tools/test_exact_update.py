"""exact_update.py's grid posterior on hand-made values (no reference run), and its capture on
the first update of a log."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import exact_update as eu  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
LOG = REPO / "scenarios" / "brake_in_turn.mf.csv"


def test_grid_posterior_of_a_linear_gaussian_is_kalmans():
    """y = H mu + e: the exact posterior is the Kalman one, N(x0 + K (y - H x0), (I - K H) P0).
    The prior and likelihood are narrow enough that the grid [-1, 2]^2 holds the posterior's
    mass to 1e-20 (its sd < 0.2, mean within [0.2, 0.8]: 6 sd from either edge), so the only
    error is the midpoint sum's on a 0.005 grid: the mean to 1e-6 (symmetric weights), the sd
    to 1e-4 (step^2 / 12 / (2 sd) ~ 1e-5 of the variance's sum)."""
    h = np.array([[1.0, 0.5], [-0.3, 2.0], [0.7, 0.1]])
    s_r = np.diag([0.5, 0.6, 0.4])
    x0 = np.array([0.5, 0.6])
    s0 = np.array([[0.2, 0.0], [0.05, 0.15]])
    y = np.array([0.9, 1.0, 0.3])
    g = np.arange(-1.0, 2.0 + 0.0025, 0.005)
    pts = np.stack([c.ravel() for c in np.meshgrid(g, g, indexing="ij")])
    w, mean, sd, mode, loglik = eu.grid_posterior(x0, s0, s_r, y, h @ pts, pts)
    p0, r = s0 @ s0.T, s_r @ s_r.T
    k = p0 @ h.T @ np.linalg.inv(h @ p0 @ h.T + r)
    x_k = x0 + k @ (y - h @ x0)
    p_k = p0 - k @ h @ p0
    assert abs(w.sum() - 1.0) < 1e-12
    assert np.allclose(mean, x_k, rtol=0.0, atol=1e-6)
    assert np.allclose(sd, np.sqrt(np.diag(p_k)), rtol=0.0, atol=1e-4)
    assert np.allclose(mode, x_k, rtol=0.0, atol=0.005)       # the grid's nearest point
    assert loglik.shape == (pts.shape[1],) and np.all(loglik <= 0.0)


def test_first_update_is_the_runs():
    """The captured first update of brake_in_turn.mf is at 0.25 s from the prior mean 0.5 (mu0;
    the random walk leaves the mean), and today's update from it is MONITOR.md section 20's
    0.367 / 0.383 (given to 3 decimals there)."""
    if not LOG.exists():
        pytest.skip(f"{LOG} not found")
    r = eu.first_updates(LOG, 1, 0.05)
    assert len(r) == 1
    assert abs(r[0]["t"] - 0.25) < 1e-9
    assert np.allclose(r[0]["x"], 0.5, atol=1e-12)
    x, _ = r[0]["filters"]["today"]
    assert np.allclose(x, [0.367, 0.383], atol=5e-4)
