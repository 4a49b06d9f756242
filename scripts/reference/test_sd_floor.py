"""Step 7's sd floor level (`sd_floor_ref`, `sd_floor_hold`; reference only, not in the C
library; docs/MONITOR.md section 19): the floor sd_floor_rel * max(x_k, sd_floor_ref, the
largest x_k of the last sd_floor_hold s) instead of sd_floor_rel * x_k. Off (0, both presets)
the run is today's, bit for bit.
(run: .venv/bin/python -m pytest scripts/reference/test_sd_floor.py -q)"""

from __future__ import annotations

import os

import numpy as np
import pytest

from . import logs, params, trusted
from ._testing import assert_study_keys_off

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
LOG = os.path.join(REPO, "scenarios", "brake_in_turn.mf.csv")   # 10 s, updates from 0.25 s
KEYS = ("sd_floor_ref", "sd_floor_hold")


def _p(**over):
    return dict(params.resolve(preset="default"), dt=0.01, **over)


def test_level_takes_the_reference_and_the_window():
    """ref 0.5: a mean below it is floored at it, above it is kept; hold 0.03 s at dt 0.01 = 3
    steps, the current one included: a drop is remembered for two more steps, then forgotten;
    a gap's read (record False) neither enters nor advances the window."""
    m = trusted.FloorMemory(_p(sd_floor_ref=0.5), 2)
    assert np.array_equal(m.level(np.array([0.3, 0.7]), True), [0.5, 0.7])
    m = trusted.FloorMemory(_p(sd_floor_hold=0.03), 1)
    got = [float(m.level(np.array([x]), True)[0]) for x in (0.9, 0.6, 0.6, 0.6, 0.4)]
    assert got == [0.9, 0.9, 0.9, 0.6, 0.6]
    assert float(m.level(np.array([0.2]), False)[0]) == 0.6     # read only
    assert float(m.level(np.array([0.2]), True)[0]) == 0.6      # 0.6, 0.4 still in the window
    assert float(m.level(np.array([0.2]), True)[0]) == 0.4
    assert float(m.level(np.array([0.2]), True)[0]) == 0.2


def test_bound_sd_floors_at_the_level():
    """A wrongly low mean 0.3 with sd 0.01: today's floor 0.15 * 0.3 = 0.045, with ref 0.5 it is
    0.15 * 0.5 = 0.075 (the factor c = 0.075 / 0.01 scales S, so the sd is the floor exactly,
    to rounding: 1e-12)."""
    class F:
        def __init__(self):
            self.x, self.S = np.array([0.3]), np.array([[0.01]])

        def sd(self):
            return np.sqrt(np.sum(self.S ** 2, axis=1))
    p = _p(sd_floor_ref=0.5)
    f = F()
    trusted._bound_sd(p, f)
    assert abs(f.sd()[0] - 0.045) < 1e-12
    f = F()
    trusted._bound_sd(p, f, trusted.FloorMemory(p, 1))
    assert abs(f.sd()[0] - 0.075) < 1e-12


def test_off_is_todays_run_bit_for_bit(monkeypatch):
    """The keys are 0 by default and in neither preset; off, the memory is never built (the run
    is today's code path); at its neutral setting (ref below any mean, a window of one step:
    the level is x itself) the memory path gives today's run bit for bit too."""
    assert_study_keys_off(KEYS)
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = logs.read_csv_log(LOG)
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    neutral = trusted.run(log, dict(p, sd_floor_ref=1e-9, sd_floor_hold=p["dt"]))

    def fail(*a, **k):
        raise AssertionError("the floor memory was built while off")
    monkeypatch.setattr(trusted, "FloorMemory", fail)
    today = trusted.run(log, p)
    for k in ("mu", "sd", "valid", "status", "info"):
        assert np.array_equal(neutral[k], today[k]), k


def test_on_changes_the_run_where_the_mean_is_low():
    """brake_in_turn.mf (MONITOR.md section 8: the mean runs at 0.6-0.7 of a 0.85 truth in
    places): ref 1.0 lifts every floor to at least 0.15 = sd_valid, so every sd after step 7 is
    at least sd_valid and fewer samples are valid than today (which has valid samples)."""
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    log = logs.read_csv_log(LOG)
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    today = trusted.run(log, p)
    on = trusted.run(log, dict(p, sd_floor_ref=1.0))
    assert not np.array_equal(on["sd"], today["sd"])
    assert 0 <= on["valid"].sum() < today["valid"].sum()
