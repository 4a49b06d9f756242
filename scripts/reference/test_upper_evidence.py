"""Step 9's upper evidence (`evid_up_delta` > 0; docs/ESTIMATOR.md step 9, MONITOR.md sections
10 and 22): off (0, both presets) the run is today's, bit for bit; on, a valid-flag rule only
(mean, sd and status untouched) that reproduces the rule trust_rules_study.py measured on the
recorded run, written there independently (its own step-4 noise by central differences).
(run: .venv/bin/python -m pytest scripts/reference/test_upper_evidence.py -q)"""

from __future__ import annotations

import math
import os
import sys

import numpy as np
import pytest

from . import estimate, logs, monitor, params, trusted

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
# brake_in_turn.mf: one of the two Magic Formula logs the rule was measured to heal (MONITOR.md
# section 10); about 2 s per run.
LOG = os.path.join(REPO, "scenarios", "brake_in_turn.mf.csv")
ON = {"evid_up_delta": 0.25, "evid_up_n": 100.0, "evid_up_l_min": 0.25}   # section 10's


def _log():
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    return logs.read_csv_log(LOG)


def _params(log, **kw):
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    p.update(kw)
    return p


def test_off_is_todays_run_bit_for_bit(monkeypatch):
    """evid_up_delta = 0 (both presets) never enters the rule, whatever evid_up_n and
    evid_up_l_min say: the same mean, sd, flags and status, exactly, and no rule output."""
    assert params.DEFAULTS["evid_up_delta"] == 0.0
    assert not any(k.startswith("evid_up_") for pre in params.PRESETS.values() for k in pre)
    log = _log()
    ref = trusted.run(log, _params(log))

    def fail(*a, **k):
        raise AssertionError("the upper evidence ran with evid_up_delta = 0")
    monkeypatch.setattr(trusted.UpperEvidence, "step", fail)
    out = trusted.run(log, _params(log, evid_up_n=3.0, evid_up_l_min=50.0))
    assert "evid_up_L" not in out
    for k in ("mu", "sd", "valid", "status"):
        assert np.array_equal(out[k], ref[k]), k
    assert np.any(ref["valid"])     # flags that the rule would have had to clear


def test_recursion_and_reset():
    """L <- rho L + Lambda on a step with an update, unchanged without one; flags while
    L >= l_min; the monitor's mismatch (fired, an updated step) sets L to 0."""
    p = dict(params.resolve(preset="default"), evid_up_delta=0.25, evid_up_n=4.0,
             evid_up_l_min=1.0)
    ev = trusted.UpperEvidence(p, 2)
    rho = math.exp(-0.25)
    assert list(ev.step(np.array([1.5, 0.5]))) == [True, False]
    assert list(ev.step(None)) == [True, False]                    # held: L kept
    assert ev.L == pytest.approx([1.5, 0.5], abs=0.0)
    ok = ev.step(np.array([-1.0, 0.6]))
    # 1.5 rho - 1 = 0.168 < 1, 0.5 rho + 0.6 = 0.989 < 1: both withheld
    assert ev.L == pytest.approx([1.5 * rho - 1.0, 0.5 * rho + 0.6], rel=1e-15)
    assert not ok.any()
    ev.mon.fired = True                   # as if the monitor fired at this step
    ev.mon.step = lambda *a, **k: True
    ev.monitor(0, np.zeros(3), np.eye(3), np.zeros(3), False)
    assert np.array_equal(ev.L, np.zeros(2))
    ev.L = np.array([2.0, 2.0])
    ev.monitor(3, np.zeros(3), np.eye(3), np.zeros(3), False)     # held, no flag: no mismatch
    assert np.array_equal(ev.L, [2.0, 2.0])


def test_reproduces_the_studys_rule_on_brake_in_turn():
    """On: the mean, sd and status are today's; the flags are today's and-ed with
    trust_rules_study.rule_evidence's (L reset where the base run reports the mismatch, its
    Lambda from its own step-4 noise by central differences of step 1e-2 sd instead of the
    reference's Richardson columns): flag for flag the same here (a flag could differ only where
    L lies within the two derivatives' difference of l_min, or at a held step the rule clears
    whose base status is 4). And the log's settled figures are those of section 10."""
    sys.path.insert(0, os.path.join(REPO, "scripts", "tools"))
    import trust_rules_study as study
    log = _log()
    p0 = _params(log, stale_omega=0.0, valid_bound_k=0.0, yaw_check=0.0)   # the study's base
    base = monitor.apply(trusted.run(log, p0), p0, p0["dt"])
    on = monitor.apply(trusted.run(log, dict(p0, **ON)), p0, p0["dt"])
    for k in ("mu", "sd", "status"):
        assert np.array_equal(on[k], base[k]), k
    r = dict(base, valid=base["valid"].astype(bool))
    study.add_model_inputs(r, log)
    ok = study.side_rule_to_wheels(study.rule_evidence(
        r["lam"], r["updated"], 100, 0.25, reset=base["status"] == monitor.STATUS_MISMATCH))
    expect = base["valid"].astype(bool) & ok
    assert np.array_equal(on["valid"].astype(bool), expect)
    assert expect.sum() < base["valid"].astype(bool).sum()          # the rule withheld flags
    truth = np.stack([log.col(f"mu_{w}") for w in study.WHEELS], 1)
    f = study.figures(on["mu"], on["sd"], on["valid"].astype(bool), truth, None,
                      study.settled(on["t"], truth))
    assert f["meets"] and f["cons"] == 1.0 and f["worst"] < 0.1     # section 10: 0.094


def test_estimate_log_records_the_keys_only_when_on():
    """Off, no evid_up_* key in an estimate log's metadata (the goldens stay as they were);
    on, all three."""
    p = params.resolve(preset="default")
    keys = [k for k, _ in estimate.metadata("sckf", p["tyre"], LOG, p, None, "default")]
    assert not any(k.startswith("evid_up_") for k in keys) and "valid_bound_k" in keys
    meta = dict(estimate.metadata("sckf", p["tyre"], LOG, dict(p, **ON), None, "default"))
    assert {k: meta[k] for k in ON} == ON
