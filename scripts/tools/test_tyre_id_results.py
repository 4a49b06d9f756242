"""tyre_id_results.py puts the augmented-state SCKF into its three tables: its row per log,
its sigma-point count in place of a particle count, and its identifiability rows, from one
deterministic run (the figures themselves are the page's, not asserted here)."""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import tyre_id_results as R  # noqa: E402
from reference import tyre_id_sckf as TS  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402

LOG = "tid_sine_steer"


def test_sckf_row_is_its_own_run_in_every_table():
    sckf = R.measure((LOG, "sckf", 64, 1))
    apf = R.measure((LOG, "apf", 64, 1))
    # the scored run is tyre_id_sckf.run with the defaults (not the particle filter)
    c = read_csv_log(str(R.ROOT / "scenarios" / "tyre_id" / f"{LOG}.csv")).columns
    out = TS.run(c, {})
    assert sckf["mean_K_f"] == out["K_f"][-1] and sckf["mean_D_r"] == out["D_r"][-1]
    assert sckf["mean_K_f"] != apf["mean_K_f"]
    acc, cnt, idt = R.tables([apf, sckf], 64, [1])
    assert sum(line.startswith(f"| {LOG} | SCKF |") for line in acc) == 1
    assert sum(line.startswith(f"| SCKF | – ({TS.N_POINTS} points) |") for line in cnt) == 1
    assert [line.split(" | ")[2] for line in idt if line.startswith(f"| {LOG} | f |")] == \
        ["APF", "SCKF"]
    # the SCKF's curve cell is its own figure: the median over one run is that run
    row = next(line for line in acc if line.startswith(f"| {LOG} | SCKF |"))
    assert row.split(" | ")[2].startswith(format(sckf["curve_f"], ".1f") + " [")
    assert np.isfinite(sckf["curve_f"])
