"""Step 6's one-sided update at mild slip (`lower_bound_delta`, reference only, not in the C
library; docs/MONITOR.md section 13): off (0) it is today's update, bit for bit; on, a side's
downward move is made only when the measurement would still carry information about that
side's friction Delta higher.
(run: .venv/bin/python -m pytest scripts/reference/test_lower_bound.py -q)"""

from __future__ import annotations

import os

import numpy as np
import pytest

from . import estimate, filters, logs, params, trusted

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
# brake_in_turn.mf: Magic Formula truth 0.85, steady cornering below the limit before the
# brake (MONITOR.md section 8: marginal updates pull the estimate down there); 10 s, ~1 s to run.
LOG = os.path.join(REPO, "scenarios", "brake_in_turn.mf.csv")


def _log():
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    return logs.read_csv_log(LOG)


def _params(log, delta):
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    p["lower_bound_delta"] = delta
    return p


def test_off_never_enters_the_one_sided_update(monkeypatch):
    """lower_bound_delta = 0 (the default of both presets) takes step 6's plain
    measurement_update: the one-sided path is never called and the run has no censoring."""
    log = _log()
    p = _params(log, 0.0)
    assert params.DEFAULTS["lower_bound_delta"] == 0.0
    assert "lower_bound_delta" not in params.PRESETS["default"]

    def fail(*a, **k):
        raise AssertionError("the one-sided update ran with lower_bound_delta = 0")
    monkeypatch.setattr(trusted, "_one_sided_update", fail)
    out = trusted.run(log, p)
    assert "censored" not in out
    assert np.any(out["status"] == 0)     # the run did update (so the path was reachable)


def test_no_downward_move_is_the_plain_update_bit_for_bit():
    """With no side moving down, the one-sided update performs measurement_update's
    operations: the same mean and factor, exactly (no tolerance: the same float64 operations
    in the same order). A linear h with orthogonal columns and diagonal prior and noise gives
    a diagonal, positive gain, so an innovation positive on both rows raises both sides."""
    h_mat = np.array([[2.0, 0.0], [0.0, 3.0], [0.0, 0.0]])
    x0, s0 = np.array([0.4, 0.5]), np.diag([0.1, 0.2])
    s_r = np.diag([0.05, 0.05, 0.05])
    y = h_mat @ (x0 + 0.1)

    def make():
        f = filters.SCKF(x0, s0, np.zeros((2, 2)), s_r)
        return f
    a, b = make(), make()
    a.measurement_update(y, lambda pts: h_mat @ pts)
    kept, info_a = trusted._one_sided_update(params.resolve(preset="default"), b,
                                             trusted.WHEELS_OF_SIDES, None, None, y,
                                             lambda pts: h_mat @ pts, s_r)
    assert kept.all() and np.all(np.isnan(info_a))  # nothing moved down, nothing evaluated
    assert np.array_equal(a.x, b.x) and np.array_equal(a.S, b.S)
    assert np.all(b.x > x0)


def test_on_censors_downward_moves_the_data_do_not_support():
    """lower_bound_delta = 0.25 on brake_in_turn.mf: some downward moves are censored (the
    log's cornering below the limit, MONITOR.md section 8); at every censored step that
    side's mean is exactly the previous step's (a zero gain row: x + 0); every censored side
    had its information at the upper alternative below info_min, and a side kept with that
    information below info_min moved up; and the run differs from the one with the option
    off."""
    log = _log()
    on = trusted.run(log, _params(log, 0.25))
    off = trusted.run(log, _params(log, 0.0))
    cens, info_a = on["censored"], on["info_up"]
    p = _params(log, 0.25)
    assert cens.sum() > 0
    k_c, side = np.nonzero(cens)
    assert np.all(k_c > 0)
    wheel = np.where(side == 0, 0, 1)        # fl (left), fr (right): the side's front wheel
    assert np.array_equal(on["mu_unprojected"][k_c, wheel], on["mu"][k_c - 1, wheel])
    assert np.all(info_a[cens] < p["info_min"])
    # a side kept although its information up there is low must have moved up (or not at all)
    k_u, side_u = np.nonzero(~np.isnan(info_a) & ~cens & (info_a < p["info_min"]))
    assert k_u.size > 0
    wheel_u = np.where(side_u == 0, 0, 1)
    assert np.all(on["mu_unprojected"][k_u, wheel_u] >= on["mu"][k_u - 1, wheel_u])
    assert not np.array_equal(on["mu"], off["mu"])


def test_estimate_log_records_the_key_only_when_set():
    """The reference-only key stays out of an estimate log's metadata at 0 (the goldens and
    the C library's logs list the library's keys only) and is recorded when set."""
    p = params.resolve(preset="default")
    keys = [k for k, _ in estimate.metadata("sckf", p["tyre"], LOG, p, None, "default")]
    assert "lower_bound_delta" not in keys and "valid_bound_k" in keys
    p["lower_bound_delta"] = 0.25
    meta = dict(estimate.metadata("sckf", p["tyre"], LOG, p, None, "default"))
    assert meta["lower_bound_delta"] == 0.25
