"""observer_spin_diag.py: its windows and its per-window table, on the spin log itself with the
reference observer fed a constant friction (no C build needed)."""

from __future__ import annotations

import math

import observer_spin_diag as diag
from observer_results import ROOT

LOG = ROOT / "scenarios" / "observer" / "sine_dwell_mu035.mf.csv"


def test_windows_cover_the_log_in_equal_widths():
    w = diag.windows([0.0, 0.4, 1.2], 0.5)
    assert w == [(0.0, 0.5), (0.5, 1.0), (1.0, 1.5)]


def test_the_table_has_one_row_per_window_and_the_rear_wheels_see_vx():
    from demo import read_csv  # the pipeline's estimate format, built here by hand
    log = read_csv(LOG)
    n = len(log["t"])
    est = {f"{k}_{w}": [v] * n for w in diag.WHEELS for k, v in (("mu", 0.35), ("sd", 0.1))}
    c, p, out = diag.reference_run(LOG, est)
    lines = diag.table(c, p, out, 1.0)
    rows = lines[2:]
    assert len(rows) == math.ceil(c["t"][-1] / 1.0)
    # the rear wheels roll free (no drive torque in this log): their reference, the speed
    # translated to the CoG with r and the half track, is vx_true within the slip the
    # Magic Formula truth needs for its rolling resistance and the noise of omega (a few
    # cm/s; the diagnosis measured within 0.08 m/s, 0.15 leaves a margin)
    for line in rows:
        cells = [x.strip() for x in line.strip("|").split("|")]
        rl, rr = (float(x) for x in cells[5].split("/")[2:4])
        assert abs(rl) < 0.15 and abs(rr) < 0.15, line


RAMP = ROOT / "scenarios" / "ramp_steer_low_mu.csv"
RAMP_TRUTH = ROOT / "scenarios" / "ramp_steer_low_mu.nf.csv"


def _constant_friction(log, mu):
    from demo import read_csv
    n = len(read_csv(log)["t"])
    return {f"{k}_{w}": [v] * n for w in diag.WHEELS for k, v in (("mu", mu), ("sd", 0.1))}


def test_a_friction_log_takes_its_twin_as_the_truth_and_its_driven_wheels_slip():
    from demo import read_csv
    c, p, out = diag.reference_run(RAMP, _constant_friction(RAMP, 0.3), RAMP_TRUTH)
    twin = read_csv(RAMP_TRUTH)
    assert list(c["vx_true"]) == twin["vx"] and list(c["vy_true"]) == twin["vy"]
    last = diag.table(c, p, out, 1.0)[-1]
    cells = [x.strip() for x in last.strip("|").split("|")]
    fl, fr, rl, rr = (float(x) for x in cells[6].split("/"))
    # the cruise control's torque is on the front wheels (the log's description): at the
    # end of the low-mu ramp they slip forward (the diagnosis measured 1.6 / 1.1 %), the
    # undriven rear wheels roll (0.01 %); 0.5 % and 0.1 % leave a margin for the noise
    assert fl > 0.5 and fr > 0.5, last
    assert abs(rl) < 0.1 and abs(rr) < 0.1, last


def test_a_truth_that_is_not_the_logs_twin_is_refused(tmp_path):
    lines = RAMP_TRUTH.read_text().splitlines()
    short = tmp_path / "short.nf.csv"
    short.write_text("\n".join(lines[:-1]) + "\n")  # one row fewer
    import pytest
    with pytest.raises(SystemExit):
        diag.reference_run(RAMP, _constant_friction(RAMP, 0.3), short)
