"""mass_online_friction.py's log list and the columns it appends, on a log written here."""

import csv
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
    # the logs with the car's resistances (--folder observer_res): their own folder only
    res = mo.logs("observer_res")
    assert "hill_known_grade_res.csv" in res and all(n[:-4].split(".")[0].endswith("_res")
                                                      for n in res)


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
    left out; a run that never feeds keeps the parameter m; the seventh column is the checked
    run's slip-held and band-refused counts; then the runs with the simulator's resistances
    (first fed, mass_used at the end) and the filter's own mass at the end of the two default
    runs, car preset -> simulator's. A log fed only with the simulator's resistances is
    listed too."""
    m = mo.log_mass(str(Path(mo.ROOT) / "scenarios" / "observer" / "long_straight_bias.csv"))
    never = {"n_fed": 0, "mass_used_end": m, "excitation_end": 0.01, "first": (None, 100),
             "n_slip_held": 7, "n_band_refused": 3, "mass_est_end": 0.9 * m}
    fed = {"n_fed": 50, "mass_used_end": 2.0 * m, "excitation_end": 0.01, "first": (1.5, 100),
           "n_slip_held": 0, "n_band_refused": 0, "mass_est_end": 2.0 * m}
    right = {"n_fed": 25, "mass_used_end": 1.001 * m, "excitation_end": 1.5,
             "first": (3.0, 100), "n_slip_held": 0, "n_band_refused": 0,
             "mass_est_end": 1.001 * m}
    results = {}
    for mode in mo.FEED_MODES:
        results[("long_straight_bias.csv", 1.0, mode)] = (None, never if mode == "ukf" else fed)
        results[("long_straight_bias.csv", 1.0, f"{mode}-sim")] = (None, never)
        results[("creep_stop.csv", 1.0, mode)] = (None, never)
        results[("creep_stop.csv", 1.0, f"{mode}-sim")] = (None, never)
        results[("hill_known_grade.csv", 1.0, mode)] = (None, never)
        results[("hill_known_grade.csv", 1.0, f"{mode}-sim")] = (None, right)
    names = ["creep_stop.csv", "hill_known_grade.csv", "long_straight_bias.csv"]
    rows = mo.gate_table(results, names).splitlines()
    assert len(rows) == 4       # header, rule, two logs
    assert rows[0].count("|") == rows[1].count("|") == rows[2].count("|") == 11
    assert rows[2] == (f"| hill_known_grade | {m:.0f} kg | never → never → never | "
                       "0% → 0% → 0% | m kept → m kept → m kept | 0.01 m/s | 7 / 3 | "
                       "3.0 s → 3.0 s → 3.0 s | +0.1% → +0.1% → +0.1% | -10.0% → +0.1% |")
    assert rows[3] == (f"| long_straight_bias | {m:.0f} kg | 1.5 s → 1.5 s → never | "
                       "50% → 50% → 0% | +100.0% → +100.0% → m kept | 0.01 m/s | 7 / 3 | "
                       "never → never → never | m kept → m kept → m kept | -10.0% → -10.0% |")


def test_table_has_both_resistances_per_mass():
    """Per mass given: the estimator off, then the three feeds with the car preset's
    resistances; a run with the simulator's gets a row (the resistance column says which)
    only where its figures differ from the car preset's, and the line under the table counts
    the others. Each row's figures are its own runs' (a run with every settled sample valid
    and error 0.1 against the reference's 0.2 counts as better by more than 0.02)."""
    def wheels(err):
        return [{"n_settled": 10, "n_valid": 10, "rmse_valid": err, "consistency_valid": 1.0,
                 "max_abs_err_valid": err}] * 4
    results = {}
    for f in mo.FACTORS:
        for mode in mo.MODES:
            err = 0.1 if mode == "ukf-sim" and f == 0.8 else 0.2
            results[("a.csv", f, mode)] = (wheels(err), None)
    lines = mo.table(results, ["a.csv"]).splitlines()
    rows = [r for r in lines if r.startswith("|")]
    assert len(rows) == 2 + len(mo.FACTORS) * 4 + 1
    assert rows[2].startswith("| m × 0.8 | off | – | 100.0% | 0.200 |")
    assert rows[3] == ("| m × 0.8 | on (ukf), mass fed, no gate | car preset | "
                       "100.0% | 0.200 | 1.000 | 0.200 | 0 of 1 | 0 of 1 |")
    assert rows[6] == ("| m × 0.8 | on (ukf), through the gate, slip hold and band | "
                       "simulator's (none) | 100.0% | 0.100 | 1.000 | 0.100 | 0 of 1 | 1 of 1 |")
    assert rows[7].startswith("| m × 1.0 | off | – |") and rows[7].endswith("| – | – |")
    assert "simulator's" not in "".join(rows[7:])
    assert lines[-1] == ("With the simulator's resistances (mg_fc = mg_fr = mg_rho = 0) 8 of 9 "
                         "runs with the estimator on give the car preset's figures to the "
                         "digits printed (not listed).")


def test_sim_resistances_are_the_observer_logs_vehicle():
    """The observer logs' simulator has no driving resistance: the committed 600 s cruise
    (long_straight_bias.nf, 25 m/s held by cruise control on a flat road) holds its speed with a
    total wheel torque of about 0 (its first 20 s: |mean| under 0.1 N m, i.e. under 0.31 N at
    R = 0.325 m, against the 494 N the car preset's m g (fc + fr v) + rho cd S v^2 / 2 is at
    25 m/s). SIM_RESISTANCES, on the car preset of the float64 reference, leaves a model whose
    coasting car does not slow (0 exactly: every resistance term multiplies 0), where the
    preset itself decelerates by 0.26 m/s^2 at 25 m/s."""
    sys.path.insert(0, str(Path(mo.ROOT) / "scripts" / "reference"))
    import mass_grade as mg  # noqa: E402
    log = Path(mo.ROOT) / "scenarios" / "observer" / "long_straight_bias.nf.csv"
    with open(log, encoding="utf-8") as fh:
        rows = csv.DictReader(line for line in fh if not line.startswith("#"))
        torques = [sum(float(r[c]) for c in mo.TORQUES)
                   for r, _ in zip(rows, range(1000))]
    assert abs(sum(torques) / len(torques)) < 0.1
    keys = dict(line.split(" = ") for line in mo.SIM_RESISTANCES.splitlines())
    m = mo.log_mass(str(log))
    assert mg.accel(mg.preset("car", **keys), 25.0, m, 0.0, 0.0) == 0.0
    # the preset: (1830 * 9.81 * (0.01 + 0.00015 * 25) + 0.5 * 1.2 * 0.3 * 2.2 * 625)
    # / (1830 + 45.4) = 0.2636 m/s^2
    assert abs(mg.accel(mg.preset("car"), 25.0, m, 0.0, 0.0) + 0.2636) < 1e-4


def test_modes_set_the_feed_keys():
    """The no-gate run turns every feed check off, the gate-only run the slip hold and the band,
    the default run none (the library's and the replay's defaults)."""
    assert "mg_feed_excitation = 0" in mo.MODE_KEYS["ukf-nogate"]
    assert "mg_feed_excitation" not in mo.MODE_KEYS["ukf-nochecks"]
    for mode in ("ukf-nogate", "ukf-nochecks"):
        assert "mg_feed_slip_max = 0" in mo.MODE_KEYS[mode]
        assert "mg_feed_band = 0" in mo.MODE_KEYS[mode]
    assert mo.MODE_KEYS["ukf"] == "" and mo.MODE_KEYS["off"] == ""
    # each feed mode once more with the simulator's resistances added, nothing else changed
    for mode in mo.FEED_MODES:
        assert mo.MODE_KEYS[f"{mode}-sim"] == mo.MODE_KEYS[mode] + mo.SIM_RESISTANCES
    assert mo.SIM_RESISTANCES == "mg_fc = 0\nmg_fr = 0\nmg_rho = 0\n"
