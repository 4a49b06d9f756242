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


def test_first_fed_is_the_first_change_of_mass_used(tmp_path):
    """first_fed: the time of the first row whose mass_used differs from the first row's, and
    the number of rows; None when it never changes."""
    est = tmp_path / "est.csv"
    est.write_text("# mg_feed_excitation = 1\n"
                   "t,mass_used\n0,1830\n0.02,1830\n0.04,1701.5\n0.06,1830\n")
    assert mo.first_fed(est) == (0.04, 4)
    est.write_text("t,mass_used\n0,1830\n0.02,1830\n")
    assert mo.first_fed(est) == (None, 2)


def test_gate_table_lists_the_logs_fed_in_any_run():
    """One row per log fed in any run, no gate -> gate -> gate and checks; a log fed in none is
    left out; a run that never feeds keeps the parameter m; the last column is the checked
    run's slip-held and band-refused counts."""
    m = mo.log_mass(str(Path(mo.ROOT) / "scenarios" / "observer" / "long_straight_bias.csv"))
    never = {"n_fed": 0, "mass_used_end": m, "excitation_end": 0.01, "first": (None, 100),
             "n_slip_held": 7, "n_band_refused": 3}
    fed = {"n_fed": 50, "mass_used_end": 2.0 * m, "excitation_end": 0.01, "first": (1.5, 100),
           "n_slip_held": 0, "n_band_refused": 0}
    results = {("long_straight_bias.csv", 1.0, "ukf-nogate"): (None, fed),
               ("long_straight_bias.csv", 1.0, "ukf-nochecks"): (None, fed),
               ("long_straight_bias.csv", 1.0, "ukf"): (None, never),
               ("creep_stop.csv", 1.0, "ukf-nogate"): (None, never),
               ("creep_stop.csv", 1.0, "ukf-nochecks"): (None, never),
               ("creep_stop.csv", 1.0, "ukf"): (None, never)}
    rows = mo.gate_table(results, ["creep_stop.csv", "long_straight_bias.csv"]).splitlines()
    assert len(rows) == 3       # header, rule, one log
    assert rows[2] == (f"| long_straight_bias | {m:.0f} kg | 1.5 s → 1.5 s → never | "
                       "50% → 50% → 0% | +100.0% → +100.0% → m kept | 0.01 m/s | 7 / 3 |")


def test_modes_set_the_feed_keys():
    """The no-gate run turns every feed check off, the gate-only run the slip hold and the band,
    the default run none (the library's and the replay's defaults)."""
    assert "mg_feed_excitation = 0" in mo.MODE_KEYS["ukf-nogate"]
    assert "mg_feed_excitation" not in mo.MODE_KEYS["ukf-nochecks"]
    for mode in ("ukf-nogate", "ukf-nochecks"):
        assert "mg_feed_slip_max = 0" in mo.MODE_KEYS[mode]
        assert "mg_feed_band = 0" in mo.MODE_KEYS[mode]
    assert mo.MODE_KEYS["ukf"] == "" and mo.MODE_KEYS["off"] == ""
