"""mass_curve_pause_study.py: the study's curve pause holds the filter while |ay| is over the
threshold and for its hold after, and is the reference itself when off; the correction's
terms."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mass_curve_pause_study as cp  # noqa: E402

mg = cp.mg


def _samples(n=300, dt=0.01):
    """An accelerating car (2 m/s^2 beyond the preset's resistances at 1830 kg): the mass
    filter learns from every update."""
    p = mg.preset("car")
    out = []
    for k in range(n):
        v = 10.0 + 2.0 * k * dt
        torque = p["R"] * (1830.0 + p["mg_m_rot"]) * 2.0 + p["R"] * 1830.0 * 9.81 * 0.01
        out.append(mg.MgSample(k * dt, v, torque, ax=2.0))
    return out


def _run(ay, ay_max, hold=0.2):
    est = cp.CurvePause(mg.preset("car", **cp.RECOMMENDED), ay_max, hold)
    return est, [o for s, a in zip(_samples(), ay)
                 for o in [(setattr(est, "ay", a), est.step(s))[1]]]


def test_off_is_the_reference():
    ay = np.full(300, 3.0)
    _, outs = _run(ay, 0.0)
    ref = mg.MassGrade(mg.preset("car", **cp.RECOMMENDED))
    assert [o.mass for o in outs] == [ref.step(s).mass for s in _samples()]


def test_curve_holds_mass_and_grade_then_hold_time():
    """|ay| = 1.5 over 1 m/s^2 on samples 100..149: those and the 19 samples less than 0.2 s
    after the last (the brake's rule: the hold ends where under half a period is left) are held, M and theta bit for
    bit; the filter learns before and after (the mass moves)."""
    ay = np.zeros(300)
    ay[100:150] = -1.5
    _, outs = _run(ay, 1.0)
    held = [k for k, o in enumerate(outs) if o.status == cp.PAUSED_CURVE]
    assert held == list(range(100, 169))
    assert all(outs[k].mass == outs[99].mass and outs[k].grade == outs[99].grade
               for k in held)
    assert outs[99].mass != outs[50].mass and outs[299].mass != outs[168].mass
    # under the threshold nothing is held
    _, quiet = _run(np.full(300, 0.99), 1.0)
    assert all(o.status != cp.PAUSED_CURVE for o in quiet)


def test_correction_terms():
    """ay Lr/L sin(delta) - r vy and r vy: 4 * 1.65/3.05 * sin(0.05) - 0.2 * (-0.5)."""
    n = 3
    cols = {"ay": np.full(n, 4.0), "delta": np.full(n, 0.05), "yaw_rate": np.full(n, 0.2)}
    fc, vy_r = cp.terms(cols, {"Lf": "1.4", "Lr": "1.65"}, np.full(n, -0.5))
    assert fc == pytest.approx(np.full(n, 4.0 * 1.65 / 3.05 * np.sin(0.05) + 0.1), rel=1e-15)
    assert vy_r == pytest.approx(np.full(n, -0.1), rel=1e-15)   # rounding only
