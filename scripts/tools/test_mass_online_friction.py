"""mass_online_friction.py's log list and the columns it appends, on a log written here."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mass_online_friction as mo  # noqa: E402


def test_drive_torque_and_brake_pressure_appended(tmp_path):
    """drive_torque is the sum of the four wheel torques, brake_pressure the largest wheel
    pressure in Pa (MPa x 1e6); metadata and the other cells are kept as they were."""
    src = tmp_path / "in.csv"
    src.write_text("# m = 1830\n"
                   "t,torque_fl,torque_fr,torque_rl,torque_rr,p_fl,p_fr,p_rl,p_rr\n"
                   "0.0,10,20.5,-3,0,0.5,2.25,0.125,1\n")
    dst = tmp_path / "out.csv"
    mo.with_drive_torque(src, dst)
    lines = dst.read_text().splitlines()
    assert lines[0] == "# m = 1830"
    assert lines[1].endswith(",drive_torque,brake_pressure")
    cells = lines[2].split(",")
    assert cells[:9] == "0.0,10,20.5,-3,0,0.5,2.25,0.125,1".split(",")
    assert float(cells[9]) == 27.5          # 10 + 20.5 - 3 + 0, exact in binary
    assert float(cells[10]) == 2.25e6       # max pressure, MPa -> Pa, exact


def test_logs_are_the_observer_scenarios_with_torques():
    logs = mo.logs()
    assert len(logs) >= 50      # the bundled observer scenarios
    assert "traction_awd_mu03.csv" in logs and all(n.endswith(".csv") for n in logs)
