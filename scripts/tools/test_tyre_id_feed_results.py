"""The rule and the log list of tyre_id_feed_results.py, on figures decided by hand.

A run is (RMSE when valid, consistency when valid, valid share, share fed). "Helps": a lower
RMSE, a consistency no lower and a valid share at most 5 points lower than without the feed;
"hurts": an RMSE higher by more than 0.02 or a consistency lower by more than 0.05; no verdict
(None) when either run has no valid sample.
"""

import os
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import tyre_id_feed_results as fr  # noqa: E402

BASE = (0.20, 0.90, 0.50, 0.0)


def test_helps_needs_all_three():
    assert fr.helps(BASE, (0.10, 0.95, 0.50, 0.5)) is True
    assert fr.helps(BASE, (0.10, 0.90, 0.46, 0.5)) is True       # 4 points fewer valid: allowed
    assert fr.helps(BASE, (0.20, 0.95, 0.50, 0.5)) is False      # RMSE not lower
    assert fr.helps(BASE, (0.10, 0.89, 0.50, 0.5)) is False      # consistency lower
    assert fr.helps(BASE, (0.10, 0.95, 0.44, 0.5)) is False      # 6 points fewer valid


def test_hurts_on_either_figure():
    assert fr.hurts(BASE, (0.22, 0.85, 0.50, 0.5)) is False      # both on their limits
    assert fr.hurts(BASE, (0.221, 0.95, 0.50, 0.5)) is True      # RMSE 0.021 higher
    assert fr.hurts(BASE, (0.10, 0.84, 0.50, 0.5)) is True       # consistency 0.06 lower
    assert fr.hurts(BASE, (0.10, 0.95, 0.10, 0.5)) is False      # fewer valid alone: no


def test_no_verdict_without_valid_samples():
    assert fr.helps((None, None, 0.0, 0.0), (0.10, 0.95, 0.50, 0.5)) is None
    assert fr.helps(BASE, (None, None, 0.0, 0.5)) is None
    assert fr.hurts(BASE, (None, None, 0.0, 0.5)) is None


def test_labels_say_the_evidence():
    assert [fr.label(f) for f in ((0.05, 0.0), (0.1, 0.25))] == ["0.05", "0.1 e0.25"]


def test_logs_are_the_steering_scenarios_and_exist():
    logs = fr.logs()
    assert len(logs) == 3 * len(fr.STEERING) + len(os.listdir(Path(fr.ROOT) / "scenarios" / "tyre_id"))
    assert "scenarios/brake_in_turn.mf.csv" in logs and "scenarios/wrong_tyre_data.csv" in logs
    for log in logs:
        assert (Path(fr.ROOT) / log).is_file(), log
