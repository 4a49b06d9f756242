"""observer_ramp_study.py's windows and per-window cells on data written here (no replay run)."""

import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import observer_ramp_study as rs  # noqa: E402
from demo import WHEELS  # noqa: E402


def test_windows_cover_the_log_and_the_last_sample_falls_in_the_last_window():
    """[a, b) windows of the width from 0; a sample at the last window's upper edge (the log's
    end) is counted in it, not dropped."""
    t = [0.0, 0.5, 1.0, 1.5, 2.0]
    w = rs.windows(t, 1.0)
    assert w == [(0.0, 1.0), (1.0, 2.0)]
    inside = [[tk for tk in t if rs.in_window(tk, a, b, t[-1])] for a, b in w]
    assert inside == [[0.0, 0.5], [1.0, 1.5, 2.0]]


def test_stats_are_the_mean_and_the_rms():
    """(mean, RMS) of (+0.1, -0.3): (-0.1, sqrt(0.05)); none for an empty window."""
    m, r = rs.stats([0.1, -0.3])
    assert math.isclose(m, -0.1) and math.isclose(r, math.sqrt(0.05))
    assert rs.stats([]) == (None, None)


def test_friction_window_pools_the_settled_valid_samples_of_the_four_wheels():
    """The first second is not settled (mu_replay's settle start) and is left out although
    valid; of the settled samples in [1, 2) the valid ones count on every wheel: errors +0.1
    (t = 1.0) and -0.2 (t = 1.5, not valid on fl only), so 4 + 3 = 7 samples with RMS
    sqrt((4 * 0.01 + 3 * 0.04) / 7)."""
    t = [0.0, 1.0, 1.5, 2.5]
    sensor = {"t": t, **{f"mu_{w}": [0.5] * 4 for w in WHEELS}}
    est = {f"mu_{w}": [9.0, 0.6, 0.3, 9.0] for w in WHEELS}
    est.update({f"valid_{w}": [1, 1, 1, 1] for w in WHEELS})
    est["valid_fl"] = [1, 1, 0, 1]
    n, r = rs.friction_window(sensor, est, 1.0, 2.0)
    assert n == 7
    assert math.isclose(r, math.sqrt((4 * 0.01 + 3 * 0.04) / 7))
    assert rs.friction_window(sensor, est, 0.0, 1.0) == (0, None)  # not settled yet


def test_window_table_has_the_observers_errors_against_the_truth():
    """One row per window: the observer's vx, vy, yaw_acc errors (estimate minus truth) as
    mean / RMS, the fed sds' mean, the measured columns' error RMS and the largest utilisation;
    every number here is chosen so that the cell can be computed by hand."""
    t = [0.0, 0.5]
    sensor = {"t": t, "vx": [20.1, 19.9], "vy": [0.0, 0.0], "yaw_acc": [0.0, 0.0],
              **{f"mu_{w}": [0.9, 0.9] for w in WHEELS}}
    tru = {"t": t, "vx": [20.0, 20.0], "vy": [-0.1, -0.1], "yaw_acc": [0.0, 0.0],
           **{f"util_{w}": [0.2, 0.6] for w in WHEELS}}
    est = {"vx_est": [20.02, 20.04], "vy_est": [-0.2, -0.1], "yaw_acc_est": [0.1, -0.1],
           "sd_vx": [0.01, 0.03], "sd_vy": [0.02, 0.02],
           **{f"mu_{w}": [0.9, 0.9] for w in WHEELS}, **{f"valid_{w}": [0, 0] for w in WHEELS}}
    lines = rs.window_table(sensor, tru, est, est, 1.0)
    assert len(lines) == 3
    cells = [c.strip() for c in lines[2].strip("|").split("|")]
    assert cells[0] == "0.0–1.0" and cells[1] == "0 / –" and cells[2] == "0 / –"
    assert cells[3] == "+0.030 / 0.032"   # vx errors +0.02, +0.04
    assert cells[4] == "0.020"            # sd_vx mean
    assert cells[5] == "-0.050 / 0.071"   # vy errors -0.1, 0
    assert cells[7] == "+0.000 / 0.100"   # yaw_acc errors +0.1, -0.1
    assert cells[8] == "0.100 / 0.100 / 0.000"  # the measured vx, vy, yaw_acc errors' RMS
    assert cells[9] == "0.60"


def test_row_kind_names_the_lateral_filters_three_updates():
    """OBSERVER.md §4: the model row observes vy through its slope d ay / d vy (h = (slope, 0),
    negative on a car that corners), the linear range and the low-speed row observe vy itself
    (h = (1, 0)), §4.4 observes b_y (h = (0, 1))."""
    assert rs.row_kind(-4.7, 0.0) == "model"
    assert rs.row_kind(1.0, 0.0) == "linear"
    assert rs.row_kind(0.0, 1.0) == "s44"


def test_nanmean_skips_the_steps_without_the_row():
    """A window's mean over the steps a row ran (nan elsewhere); none when it never ran."""
    assert math.isclose(rs.nanmean([0.2, math.nan, 0.4]), 0.3)
    assert rs.nanmean([math.nan]) is None
    assert rs.f3(None) == "–" and rs.f3(0.0414) == "+0.041"
