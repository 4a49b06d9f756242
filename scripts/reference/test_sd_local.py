"""Step 6's local-information bound (`sd_local`, `sd_local_at`; reference only, not in the C
library; docs/MONITOR.md section 20): after an update, S is scaled by one factor so that no
variance is below the posterior of the linearisation at the mean, P_loc = (P-^-1 + W^T W)^-1,
W = S_R^-1 dh/dx. Off (0, both presets) the bound is never evaluated.
(run: .venv/bin/python -m pytest scripts/reference/test_sd_local.py -q)"""

from __future__ import annotations

import os

import numpy as np
import pytest

from . import filters, logs, params, trusted
from ._testing import assert_study_keys_off

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
LOG = os.path.join(REPO, "scenarios", "brake_in_turn.mf.csv")   # first update at 0.25 s
KEYS = ("sd_local", "sd_local_at")
S_R = np.diag([0.2, 0.3, 0.4])


def _filter(x, s):
    return filters.SCKF(np.array(x), np.array(s), np.eye(2) * 1e-3, S_R)


def _update(f, h):
    """One SCKF update with h (maps (2, P) points to (3, P)); returns the prior (x-, S-)."""
    x0, s0 = f.x.copy(), f.S.copy()
    f.measurement_update(np.array([0.1, -0.2, 0.05]), h)
    return x0, s0


def test_linear_h_is_never_bound():
    """h = A x: the cubature update is the exact Kalman update (ESTIMATOR.md "The linear
    update"), whose posterior is P_loc itself, so the factor is 1 to rounding (1e-12 of 1) and
    S moves by at most that."""
    a = np.array([[1.0, 0.5], [-0.3, 2.0], [0.7, 0.1]])
    f = _filter([0.5, 0.6], [[0.3, 0.0], [0.1, 0.2]])
    h = lambda pts: a @ pts   # noqa: E731
    x0, s0 = _update(f, h)
    s_post = f.S.copy()
    c = trusted._local_information_bound(dict(sd_local=1e-3), f, h, x0, s0, S_R)
    assert abs(c - 1.0) < 1e-12
    assert np.allclose(f.S, s_post, rtol=1e-12, atol=0.0)


def test_a_flat_mean_keeps_the_prior_variance():
    """h flat at the mean but steep over the spread (a tyre saturating only at a low mu):
    h_r(x) = g_r * max(0, 0.2 - x_0)^2 has zero slope at x- = 0.5, so P_loc = P- and the bound
    lifts the posterior back to the prior where it fell most: every P+_kk c^2 >= P-_kk, with
    equality (to 1e-12) at that state; the mean is step 6's (the factor scales S only)."""
    g = np.array([5.0, -3.0, 1.0])
    h = lambda pts: np.outer(g, np.maximum(0.0, 0.2 - pts[0]) ** 2)   # noqa: E731
    f = _filter([0.5, 0.5], [[0.32, 0.0], [0.25, 0.2]])
    x0, s0 = _update(f, h)
    x_post, p_post = f.x.copy(), f.S @ f.S.T
    p_prior = s0 @ s0.T
    assert np.max(np.diag(p_post) / np.diag(p_prior)) < 0.99   # the spread claimed information
    c = trusted._local_information_bound(dict(sd_local=1e-3), f, h, x0, s0, S_R)
    ratio = np.diag(f.S @ f.S.T) / np.diag(p_prior)
    assert c > 1.0
    assert abs(np.min(ratio) - 1.0) < 1e-12
    assert np.all(ratio >= 1.0 - 1e-12)
    assert np.allclose(f.S @ f.S.T, c * c * p_post, rtol=1e-12)   # one factor: the shape kept
    assert np.array_equal(f.x, x_post)


def test_off_never_evaluates_the_bound(monkeypatch):
    """The keys are 0 by default, in neither preset and reference only; off, the bound is never
    called and the run records no factor."""
    assert_study_keys_off(KEYS)
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = _head(logs.read_csv_log(LOG), 40)

    def fail(*a, **k):
        raise AssertionError("the bound was evaluated while off")
    monkeypatch.setattr(trusted, "_local_information_bound", fail)
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    out = trusted.run(log, p)
    assert "sd_local_c" not in out


def _head(log, n):
    return logs.CsvLog(log.path, dict(log.meta), {k: v[:n] for k, v in log.columns.items()})


def test_on_lifts_the_sd_of_brake_in_turn_s_first_update():
    """brake_in_turn.mf's first update (0.25 s; MONITOR.md section 20: step 5's information 28
    from the spread, 0.5 at the mean): on, the factor there is > 1 and both sds after it are
    larger than today's, while the mean of that step is today's (the bound scales S only)."""
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = _head(logs.read_csv_log(LOG), 27)     # up to 0.26 s
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    today = trusted.run(log, p)
    on = trusted.run(log, dict(p, sd_local=1e-3))
    k = int(np.flatnonzero(np.isin(today["status"], (0, 1)))[0])
    assert abs(today["t"][k] - 0.25) < 1e-9
    assert on["sd_local_c"][k] > 1.0
    assert np.all(on["sd"][k] > today["sd"][k])
    assert np.array_equal(on["mu"][k], today["mu"][k])
