"""mass_curve_pause_study.py: the correction's terms, and a run through the study's stepping
with the pause (the pause itself is tested in scripts/reference/test_mass_grade.py)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mass_curve_pause_study as cp  # noqa: E402

mg = cp.mg


def test_correction_terms():
    """ay Lr/L sin(delta) - r vy and r vy: 4 * 1.65/3.05 * sin(0.05) - 0.2 * (-0.5)."""
    n = 3
    cols = {"ay": np.full(n, 4.0), "delta": np.full(n, 0.05), "yaw_rate": np.full(n, 0.2)}
    fc, vy_r = cp.terms(cols, {"Lf": "1.4", "Lr": "1.65"}, np.full(n, -0.5))
    assert fc == pytest.approx(np.full(n, 4.0 * 1.65 / 3.05 * np.sin(0.05) + 0.1), rel=1e-15)
    assert vy_r == pytest.approx(np.full(n, -0.1), rel=1e-15)   # rounding only


def test_run_hands_ay_over_and_corrects():
    """run() sets each sample's ay (the pause holds where |ay| > 1) and, corrected, takes
    R M^ fc out of the torque and adds r vy to ax (M^ the start mass before the first step)."""
    p = mg.preset("car", mg_ay_max=1.0, mg_t_curve=0.0, **cp.RECOMMENDED)
    samples = [mg.MgSample(0.01 * k, 10.0, 100.0, ax=0.0) for k in range(4)]
    ay = np.array([0.0, 2.0, 0.0, 0.0])
    outs = cp.run(mg.MassGrade(p), samples, ay, True, np.full(4, 0.01), np.full(4, 0.2))
    assert [o.status for o in outs] == [mg.OK, cp.PAUSED_CURVE, mg.OK, mg.OK]
    assert samples[0].torque == pytest.approx(100.0 - p["R"] * p["mg_m0"] * 0.01, rel=1e-15)
    assert [s.ax for s in samples] == [0.2] * 4 and [s.ay for s in samples] == list(ay)
