"""Step 5's information gate judged at a second centre too (`info_at` > 0; reference only, not
in the C library; docs/MONITOR.md section 16): off (0, both presets) the run is today's, bit
for bit; on, the gate takes, per side, the larger of the information around the estimate and
around the second centre (1: the hypothesis info_mu_h; 2: the cubature point whose
prediction is nearest the data).
(run: .venv/bin/python -m pytest scripts/reference/test_info_at.py -q)"""

from __future__ import annotations

import os

import numpy as np
import pytest

from . import filters, logs, params, trusted

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
LOG = os.path.join(REPO, "scenarios", "brake_in_turn.mf.csv")   # 10 s, updates from 0.25 s

SAT = 0.4                                   # the toy tyre's force saturates at this mu
S_R = np.diag([0.1, 0.1, 0.1])


def sat_h(pts):
    """A toy measurement: each side's force grows with mu up to SAT, then stays (the slope by
    mu is 1 below SAT and 0 above, like a tyre at a slip that saturates only at low mu)."""
    return np.vstack([np.minimum(pts, SAT), np.zeros((1, pts.shape[1]))])


def _filter(x):
    return filters.SCKF(np.array(x, dtype=float), np.diag([0.05, 0.05]), np.zeros((2, 2)), S_R)


def _p(**kw):
    return dict(params.resolve(preset="default"), **kw)


def test_off_is_todays_run_bit_for_bit(monkeypatch):
    """info_at = 0 (the default, in neither preset) never evaluates a second centre, whatever
    info_mu_h says: the same mean, sd, flags, status and information, exactly."""
    assert params.DEFAULTS["info_at"] == 0.0
    assert not any(k.startswith("info_at") for pre in params.PRESETS.values() for k in pre)
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = logs.read_csv_log(LOG)
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    ref = trusted.run(log, p)

    def fail(*a, **k):
        raise AssertionError("a second centre was evaluated with info_at = 0")
    monkeypatch.setattr(trusted, "_information_alt", fail)
    out = trusted.run(log, dict(p, info_mu_h=0.9))
    for k in ("mu", "sd", "valid", "status", "info"):
        assert np.array_equal(out[k], ref[k]), k
    assert np.any(ref["status"] == 0)      # the run did update (the gate was reached)


def test_hypothesis_sees_what_the_estimate_cannot():
    """Estimate 0.9, sd 0.05: every cubature point (0.9 -+ sqrt(2) 0.05) lies above SAT, so
    the information there is 0. Around info_mu_h 0.3 every point lies below SAT, where h is
    mu itself: J = [[1, 0], [0, 1], [0, 0]] exactly, and I_j = sum_r (J_rj / 0.1)^2 = 100.
    (Tolerance 1e-9: two triangular solves on numbers of order 1e2, rounding only.)"""
    f = _filter([0.9, 0.9])
    pts = f.points()
    z = sat_h(pts)
    y = np.zeros(3)
    assert np.allclose(trusted._information(f, pts, z, S_R), 0.0, atol=1e-9)
    alt = trusted._information_alt(_p(info_at=1.0, info_mu_h=0.3), f, pts, z, S_R, y, sat_h)
    assert np.allclose(alt, 100.0, rtol=0, atol=1e-9)
    # at info_mu_h = the estimate, the moved points are the points: today's information
    same = trusted._information_alt(_p(info_at=1.0, info_mu_h=0.9), f, pts, z, S_R, y, sat_h)
    assert np.allclose(same, 0.0, atol=1e-9)


def test_nearest_point_is_the_one_whose_prediction_matches_the_data():
    """info_at 2: with data equal to one cubature point's prediction (below SAT, so h is
    one-to-one there) the centre is that point; data far below every prediction pick the
    lowest point on the side that moves the prediction (a -sqrt(2) sd point)."""
    f = _filter([0.3, 0.35])
    pts = f.points()
    z = sat_h(pts)
    p = _p(info_at=2.0)
    for i in range(pts.shape[1]):
        assert np.array_equal(trusted.info_centre(p, f, pts, z, S_R, z[:, i]), pts[:, i])
    low = trusted.info_centre(p, f, pts, z, S_R, np.array([0.0, 0.35, 0.0]))
    assert low[0] == pts[0].min() and low[1] == pytest.approx(0.35, abs=1e-12)


def test_unknown_choice_is_refused():
    f = _filter([0.5, 0.5])
    pts = f.points()
    with pytest.raises(ValueError):
        trusted.info_centre(_p(info_at=3.0), f, pts, sat_h(pts), S_R, np.zeros(3))
