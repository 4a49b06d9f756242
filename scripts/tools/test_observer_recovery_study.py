"""observer_recovery_study.py: its saturation runs and windows on hand-made traces, and its trace
on the low-mu lane change with the reference observer fed a constant friction (no C build)."""

from __future__ import annotations

import math

import pytest

import observer_recovery_study as study
from observer_results import ROOT
from reference import logs, observer, params

LOG = ROOT / "scenarios" / "observer" / "dlc_mu035.csv"


def _rec(us):
    """A trace with model steps of utilisation @p us (None: a step without a model update)."""
    return [dict(t=0.1 * k, vy=0.0, by=0.0, dby44=0.0,
                 model=None if u is None else dict(u=u, k_v=1.0, k_b=-1.0, nu=0.0, dby=0.0,
                                                   dvy=0.0))
            for k, u in enumerate(us)]


def test_a_run_of_saturated_model_steps_ends_only_at_a_model_step_below():
    # steps without a model update (obs_lat_every > 1) neither end nor start a run
    rec = _rec([0.5, 0.9, None, 0.85, 0.3, None, 0.95, None])
    assert study.saturations(rec, 0.8) == [(1, 3), (6, 6)]
    assert study.saturations(rec, 0.9) == [(1, 1), (6, 6)]
    assert study.saturations(_rec([0.1, None, 0.2]), 0.8) == []


def test_a_window_starts_after_the_run_and_is_cut_at_the_next_one():
    us = [0.9, 0.1, 0.1, 0.1, 0.9, 0.1]
    rec = _rec(us)
    n = len(rec)
    cols = dict(vx_true=[10.0] * n, vy_true=[0.0] * n, beta_true=[0.0] * n, ay=[0.0] * n,
                **{f"mu_{w}": [0.35] * n for w in study.WHEELS})
    rows = study.window_rows(rec, cols, dict(g=9.81), 0.8, 10.0, [0.0] * n)
    # the first window runs to the step before the next run (t = 0.3), the second to the end
    assert [r["win"] for r in rows] == [pytest.approx((0.1, 0.3)), pytest.approx((0.5, 0.5))]
    rows = study.window_rows(rec, cols, dict(g=9.81), 0.8, 0.15, [0.0] * n)
    assert rows[0]["win"] == pytest.approx((0.1, 0.1))  # 0.15 s after the last step at t = 0


def _trace(**kw):
    log = logs.read_csv_log(str(LOG), required=("t", "vx_true", "vy_true", "beta_true"))
    c = log.columns
    p = observer.params_with_defaults(params.from_metadata(log.meta))
    n = len(c["t"])
    mu = ([[0.35] * n for _ in range(4)], [[0.05] * n for _ in range(4)])
    return c, p, study.trace(c, p, mu, **kw)


def test_the_model_row_puts_into_b_y_against_vy_and_a_pinned_offset_stays():
    c, p, rec = _trace()
    models = [r["model"] for r in rec if r["model"] is not None]
    # obs_lat_every 8: one model update every 8th step at vx >= obs_v_lat_min (the whole log)
    assert abs(len(models) - len(rec) / p["obs_lat_every"]) <= 1
    # the predict's F = [[1, -dt], [0, 1]] makes cov(vy, b_y) negative, so the model row moves
    # b_y against vy: K_b / K_v = P01 / P00 < 0 wherever the row has gain
    assert sum(1 for m in models if m["k_b"] / m["k_v"] < 0.0) >= 0.95 * len(models)
    zero = [0.0] * len(rec)
    _, _, pinned = _trace(pin_by=zero)
    assert all(r["by"] == 0.0 for r in pinned)
    # b_y's variance and covariance zeroed after every step: the predict's cov(vy, b_y) is then
    # p01 - dt p11 = 0, so the model row has no gain on b_y at all
    _, _, no_state = _trace(pin_by=zero, pin="cov")
    assert all(r["model"]["k_b"] == 0.0 for r in no_state if r["model"] is not None)
    # the value pinned with the covariance free: the model row still has gain on b_y
    _, _, value = _trace(pin_by=zero, pin="value")
    assert any(r["model"]["k_b"] != 0.0 for r in value if r["model"] is not None)
    # a hold forever from the start (u_sat 0) leaves b_y to §4.4 alone: the model row's recorded
    # change of b_y is 0 on every step
    _, _, held = _trace(hold=(0.0, math.inf))
    assert all(r["model"]["dby"] == 0.0 for r in held if r["model"] is not None)


def test_the_offset_truth_is_the_bias_plus_the_bank():
    c = dict(t=[0.0, 0.01], bank_true=[0.0, -math.radians(5.0)])
    # the observer settles at -0.855 m/s² on the -5° bank (g sin 5° = 0.855)
    assert study.truth_offset(c, {"ay_bias": "0.1"}, 9.81) == pytest.approx(
        [0.1, 0.1 - 9.81 * math.sin(math.radians(5.0))])
    assert study.truth_offset(dict(t=[0.0]), {}, 9.81) == [0.0]


def test_the_phase_shares_split_the_whole_squared_error():
    c, p, rec = _trace()
    sh = study.phase_shares(rec, c, p, 0.8, 1.0)
    assert abs(sum(f for f, _, _ in sh.values()) - 1.0) < 1e-12
    assert sum(n for _, _, n in sh.values()) > 0
