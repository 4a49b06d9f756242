"""Steps 5-6 as a test of hypotheses (`hyp_update`, `hyp_lr_min`; reference only, not in the
C library; docs/MONITOR.md section 17): a step whose information gate opens only at the
second centre c (info_at > 0) is updated linearised at c, and/or taken only while the
accumulated log likelihood ratio of c against the estimate reaches hyp_lr_min. Off (0, both
presets) the run is today's, bit for bit.
(run: .venv/bin/python -m pytest scripts/reference/test_hypotheses.py -q)"""

from __future__ import annotations

import os

import numpy as np
import pytest

from . import filters, logs, params, trusted
from ._testing import assert_study_keys_off

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
LOG = os.path.join(REPO, "scenarios", "brake_in_turn.mf.csv")   # 10 s, updates from 0.25 s

S_R = np.diag([0.1, 0.2, 0.3])
H = np.array([[1.0, 0.5], [0.0, 2.0], [0.3, -1.0]])    # a linear measurement, full column rank


def lin_h(pts):
    return H @ pts


def _filter(x, s):
    return filters.SCKF(np.array(x, dtype=float), np.array(s, dtype=float), np.zeros((2, 2)), S_R)


S0 = [[0.2, 0.0], [0.05, 0.15]]


def test_off_is_todays_run_bit_for_bit(monkeypatch):
    """hyp_update = hyp_lr_min = 0 (the defaults, in neither preset): with info_at on, the run
    is section 16's, bit for bit, and neither the test nor the moved update is evaluated; with
    info_at off, setting them changes nothing either (they act only on a second centre)."""
    assert_study_keys_off(("hyp_update", "hyp_lr_min", "hyp_warmup"))
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = logs.read_csv_log(LOG)
    p = dict(params.resolve(log.meta, None, source=LOG, preset="default"), info_at=1.0,
             info_mu_h=0.3)
    ref = trusted.run(log, p)
    base = trusted.run(log, dict(p, info_at=0.0))

    def fail(*a, **k):
        raise AssertionError("the test of hypotheses was evaluated while off")
    monkeypatch.setattr(trusted, "_update_at", fail)
    monkeypatch.setattr(trusted, "log_predictive", fail)
    out = trusted.run(log, p)
    off = trusted.run(log, dict(p, info_at=0.0, hyp_update=1.0, hyp_lr_min=2.0))
    for k in ("mu", "sd", "valid", "status", "info"):
        assert np.array_equal(out[k], ref[k]), k
        assert np.array_equal(off[k], base[k]), k
    assert "hyp" not in out and "hyp" not in off


def test_moved_update_equals_todays_for_a_linear_measurement():
    """For h linear (h = H mu) the statistical slope at any centre is H and z_c = H c, so the
    iterated step x + K (y - H c - H (x - c)) is the ordinary update x + K (y - H x), and the
    factor is the same: wherever c lies, the moved update must equal measurement_update.
    (Tolerance 1e-12: a few triangular solves on numbers of order 1-10, rounding only.)"""
    y = np.array([0.4, -0.3, 0.9])
    ref = _filter([0.5, 0.6], S0)
    ref.measurement_update(y, lin_h)
    for c in ([0.5, 0.6], [0.3, 0.3], [0.9, 0.1]):
        f = _filter([0.5, 0.6], S0)
        trusted._update_at(f, y, lin_h, np.array(c))
        assert np.allclose(f.x, ref.x, rtol=0, atol=1e-12), c
        assert np.allclose(f.S @ f.S.T, ref.S @ ref.S.T, rtol=0, atol=1e-12), c


def test_moved_update_follows_the_curve_at_the_centre():
    """A saturating h (slope 1 below 0.4, 0 above) seen from x = 0.9: today's points see no
    slope and the update does not move; moved to c = 0.3 (every point below 0.4 for this S) the
    slope is 1 and z_c = c, so the step is x + K (y - c - (x - c)) = x + K (y - x) with the
    linear model's gain: K = P (P + R)^-1 for h = mu on two channels (third row 0)."""
    def sat(pts):
        return np.vstack([np.minimum(pts, 0.4), np.zeros((1, pts.shape[1]))])
    s = np.diag([0.03, 0.03])
    y = np.array([0.25, 0.28, 0.0])
    f0 = _filter([0.9, 0.9], s)
    f0.measurement_update(y, sat)
    assert np.allclose(f0.x, [0.9, 0.9], atol=1e-12)
    f = _filter([0.9, 0.9], s)
    trusted._update_at(f, y, sat, np.array([0.3, 0.3]))
    r = np.diag(S_R)[:2] ** 2
    gain = 0.03 ** 2 / (0.03 ** 2 + r)
    assert np.allclose(f.x, 0.9 + gain * (y[:2] - 0.9), rtol=0, atol=1e-12)


def test_likelihood_ratio_favours_the_centre_the_data_sit_at():
    """Linear h: both predictives have the covariance H P H^T + R (the same log det), so the
    log ratio of c against x is |S_zz^-1 (y - H x)|^2 / 2 - |S_zz^-1 (y - H c)|^2 / 2: with
    y = H c it is |S_zz^-1 H (c - x)|^2 / 2 > 0, and with y = H x its negative."""
    f = _filter([0.5, 0.6], S0)
    pts = f.points()
    c = np.array([0.3, 0.35])
    z_x, z_c = lin_h(pts), lin_h(pts + (c - f.x)[:, None])
    s_zz = np.linalg.cholesky(H @ f.S @ f.S.T @ H.T + S_R @ S_R.T)
    w = np.linalg.solve(s_zz, H @ (c - f.x))
    expect = 0.5 * float(w @ w)
    for y, sign in ((H @ c, 1.0), (H @ f.x, -1.0)):
        lam = trusted.log_predictive(f, z_c, S_R, y) - trusted.log_predictive(f, z_x, S_R, y)
        assert lam == pytest.approx(sign * expect, rel=1e-10)


def test_cusum_resets_at_zero_and_where_the_estimate_opens_the_gate():
    """L <- max(0, L + lambda) on the steps opened only at c; L = 0 on a step opened at x."""
    hyp = trusted.Hypotheses()
    f = _filter([0.5, 0.6], S0)
    pts = f.points()
    c = np.array([0.3, 0.35])
    keep = {"c": c, "z": lin_h(pts + (c - f.x)[:, None])}
    out = {"hyp": np.zeros(4, dtype=int), "hyp_lr": np.zeros(4), "hyp_L": np.zeros(4)}
    z_x = lin_h(pts)
    assert hyp.step(False, True, f, z_x, keep, S_R, H @ c, out, 0) is c
    first = hyp.L
    assert first > 0
    hyp.step(False, True, f, z_x, keep, S_R, H @ c, out, 1)
    assert hyp.L == pytest.approx(2 * first, rel=1e-12)
    hyp.step(False, True, f, z_x, keep, S_R, H @ f.x - 10 * H @ (c - f.x), out, 2)
    assert hyp.L == 0.0                     # strong evidence for x: floored, not negative
    hyp.L = 5.0
    assert hyp.step(True, True, f, z_x, keep, S_R, H @ c, out, 3) is None
    assert hyp.L == 0.0 and list(out["hyp"]) == [1, 1, 1, 0]


def test_a_run_with_the_test_on_records_it():
    """On a real log with info_at 1 at 0.3: the steps opened only at c are marked, their L is
    never negative, and with hyp_lr_min far above anything reached no such step updates."""
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = logs.read_csv_log(LOG)
    p = dict(params.resolve(log.meta, None, source=LOG, preset="default"), info_at=1.0,
             info_mu_h=0.3)
    out = trusted.run(log, dict(p, hyp_lr_min=1e9))
    opened_c = out["hyp"] == 1
    assert opened_c.any() and np.all(out["hyp_L"] >= 0.0)
    assert np.all(np.isin(out["status"][opened_c], (3,)))


def test_warmup_gives_no_evidence():
    """hyp_warmup 0.03 s at dt 0.01: the first 3 evaluated steps opened only at c are marked but
    add nothing to L (and are held); the 4th counts."""
    p = dict(params.resolve(preset="default"), hyp_warmup=0.03, dt=0.01)
    hyp = trusted.Hypotheses(p)
    f = _filter([0.5, 0.6], S0)
    pts = f.points()
    c = np.array([0.3, 0.35])
    keep = {"c": c, "z": lin_h(pts + (c - f.x)[:, None])}
    out = {"hyp": np.zeros(4, dtype=int), "hyp_lr": np.full(4, np.nan), "hyp_L": np.zeros(4)}
    for k in range(4):
        hyp.step(False, True, f, lin_h(pts), keep, S_R, H @ c, out, k)
        assert hyp.warming() == (k < 3)
    assert list(out["hyp"]) == [1, 1, 1, 1] and list(out["hyp_L"][:3]) == [0.0] * 3
    assert np.isnan(out["hyp_lr"][:3]).all() and out["hyp_L"][3] > 0
