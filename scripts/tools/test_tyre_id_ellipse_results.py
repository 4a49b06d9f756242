"""tyre_id_ellipse_results.py on an excerpt: brake_in_turn.mf to 2.5 s (the braking starts at
2 s), the SCKF without and with tid_ellipse (without and with its dead band). Its figures are
the reference's own outputs at the named times, cy is the summed K over the summed static
load, and the page's claim holds on the excerpt: without the ellipse the rear D collapses
0.4 s into the braking, with it it does not."""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import tyre_id_ellipse_results as R  # noqa: E402
from reference import tyre_id_sckf as TS  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402

LOG = "brake_in_turn.mf"
N = 251  # samples 0 ... 2.5 s


def test_figures_are_the_reference_outputs_at_their_times():
    c = read_csv_log(str(R.ROOT / "scenarios" / f"{LOG}.csv")).columns
    out = TS.run(c, {"tid_ellipse": 1.0, "tid_ell_ax_min": 0.0}, n_steps=N)
    t = np.asarray(c["t"], dtype=float)[:N]
    f = R.measure((LOG, "sckf", 1, N))
    k19, k24 = int(round(1.9 / 0.01)), int(round(2.4 / 0.01))   # the log's 10 ms samples
    assert abs(t[k19] - 1.9) < 1e-9 and abs(t[k24] - 2.4) < 1e-9
    assert f[0] == out["D_r"][k19] and f[1] == out["D_r"][k24]
    # the static loads sum to m g (the reference's car: 1830 kg, 9.81 m/s^2), so cy is the
    # summed K over the car's weight; compared to 1e-12 relative (a division's rounding)
    fz0 = R.static_loads()
    assert abs(fz0[0] + fz0[1] - 1830.0 * 9.81) < 1e-9
    cy = (out["K_f"][k24] + out["K_r"][k24]) / (1830.0 * 9.81)
    assert abs(f[3] - cy) <= 1e-12 * cy
    # the window 2 ... 2.5 s of the excerpt: 51 samples, 2.0 included
    win = slice(int(round(2.0 / 0.01)), N)
    assert abs(f[2] - float(np.mean(out["D_r"][win]))) <= 1e-9 * f[2]
    assert f[5] == float(np.max((out["K_f"][win] + out["K_r"][win]) / (fz0[0] + fz0[1])))


def test_the_ellipse_keeps_the_rear_peak_into_the_braking():
    off = R.measure((LOG, "sckf", 0, N))
    on = R.measure((LOG, "sckf", 1, N))
    band = R.measure((LOG, "sckf", 2, N))
    # the dead band (0.6 m/s^2) leaves the run before the braking as without the ellipse, bit
    # for bit (|ax| below 0.2 there), and 0.4 s into the braking (|ax| 2.6) it is the ellipse's
    assert band[0] == off[0]
    assert band[1] >= band[0]
    # before the braking both runs agree within 1 % (ax is small: the ellipse barely acts)
    assert abs(on[0] - off[0]) < 0.01 * off[0]
    # 0.4 s into it the lateral-only model's rear D has fallen by more than a third, the
    # ellipse's has not fallen (the page: 7,208 -> 4,054 N against 7,251 -> 7,360 N)
    assert off[1] < 0.67 * off[0]
    assert on[1] >= on[0]
    # and the cy it would feed stays nearer the truth's 15 /rad
    assert abs(on[3] - 15.0) < abs(off[3] - 15.0)


def test_table_has_one_row_per_run_pair_in_order():
    res = {(log, filt, e): (7000.0 + e, 4000.0, 4500.0, 18.2, 18.0, 18.5)
           for log, filt in R.ROWS for e in range(len(R.RUNS))}
    lines = R.table(res)
    assert len(lines) == 2 + len(R.ROWS)
    assert [ln.split(" | ")[0:2] for ln in lines[2:]] == \
        [[f"| {log}", filt.upper()] for log, filt in R.ROWS]
    assert lines[2].split(" | ")[2] == "7,000 → 4,000 / 7,001 → 4,000 / 7,002 → 4,000"
    assert lines[2].endswith("| 18.0 (18.5) / 18.0 (18.5) / 18.0 (18.5) |")
    # the runs: without, with (no band), with the default band
    assert R.RUNS[0]["tid_ellipse"] == 0.0 and R.RUNS[1] == {"tid_ellipse": 1.0,
                                                             "tid_ell_ax_min": 0.0}
    assert R.RUNS[2] == {"tid_ellipse": 1.0}
