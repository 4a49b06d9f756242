"""mass_pause_grade_study.py: its summary of a run and its verdict table on hand-made results
(the mode itself is tested in scripts/reference/test_mass_grade.py)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mass_pause_grade_study as pg  # noqa: E402

mg = pg.mg


def test_summary_counts_only_the_three_pauses():
    """Grade errors 0, 3, 4 and 0 rad at statuses OK, brake, curve, low speed: RMSE over the
    log sqrt(25/4) = 2.5, over the held samples (brake, curve) sqrt(25/2), held share 1/2."""
    est = lambda st, g: mg.MgEstimate(1500.0, 1.0, g, 0.0, 0.0, 0.0, 0.0, st)
    outs = [est(mg.OK, 0.0), est(mg.PAUSED_BRAKE, 3.0), est(mg.PAUSED_CURVE, 4.0),
            est(mg.NO_UPDATE_LOW_SPEED, 0.0)]
    r = pg.summary(outs, {"grade_true": np.zeros(4)}, 1000.0)
    assert r["mass_err"] == pytest.approx(0.5, rel=1e-15)
    assert r["rmse"] == pytest.approx(2.5, rel=1e-15)
    assert r["rmse_held"] == pytest.approx(np.sqrt(12.5), rel=1e-15)
    assert r["held"] == 0.5


def test_verdict_counts_better_and_worse():
    """A brake run 1 mrad worse and 1 % of m farther: one run moved, 0 / 1 on both; a curve
    run 0.01 mrad better (under the 0.05 mrad threshold): moved, neither better nor worse."""
    base = {"mass_err": 0.01, "rmse": 1e-3, "rmse_held": 1e-3, "held": 0.1}
    res = {("obs", "a.csv", 1.0, "off"): base,
           ("obs", "a.csv", 1.0, "brake"): dict(base, rmse=2e-3, mass_err=-0.02),
           ("obs", "a.csv", 1.0, "curve"): dict(base, rmse=0.99e-3)}
    jobs = [k for k in res if k[3] != "off"]
    text = "\n".join(pg.verdict(res, jobs))
    assert "| brake | 1 | 0 / 1 | +1.00 (a 1.0) | 0 / 1 | +1.00% (a 1.0) |" in text
    assert "| curve | 1 | 0 / 0 |" in text
    assert "| shift | 0 | 0 / 0 |" in text
