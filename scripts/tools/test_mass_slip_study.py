"""mass_slip_study.py's tables on results written here (no replay run)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mass_slip_study as ms  # noqa: E402


def _obs(mass_off, mass_on, n_slip, m=1000.0):
    """The observer results of one log at every start: pause off and on."""
    out = {}
    for s in ms.STARTS:
        out[("0", s)] = {"mass": mass_off, "sd": 2.0, "m": m, "n_slip": 0, "n_ok": 100}
        out[("default", s)] = {"mass": mass_on, "sd": 20.0, "m": m, "n_slip": n_slip,
                               "n_ok": 100 - n_slip}
    return out


def test_held_logs_tabled_the_others_summed():
    """A log with samples held by slip gets a row per start (errors against m, sd over m,
    the held samples, the updates); one without is only in the summary line, with the largest
    change of its mass at the end; the mass and grade logs are compared column for column."""
    obs = {}
    for name, (off, on, n) in {"slips.csv": (900.0, 960.0, 40),
                               "clean.csv": (1010.0, 1010.5, 0)}.items():
        for (k, s), v in _obs(off, on, n).items():
            obs[(name, s, k)] = v
    cols = [("1", "2", "3", "4")]
    mg = {("a.csv", "0"): (cols, 0), ("a.csv", "default"): (cols, 0),
          ("b.csv", "0"): (cols, 0), ("b.csv", "default"): ([("1", "2", "3", "5")], 0)}
    text = ms.tables(obs, ["slips.csv", "clean.csv"], mg, ["a.csv", "b.csv"])
    rows = [r for r in text.splitlines() if r.startswith("| slips")]
    assert len(rows) == len(ms.STARTS)
    assert rows[0] == "| slips | 1.0 m | -10.0% → -4.0% | 0.2% → 2.0% | 40 | 100 → 60 |"
    assert "clean" not in "".join(r for r in text.splitlines() if r.startswith("|"))
    assert "The other 1 observer logs" in text and "change of the mass at the end 0.5 kg" in text
    assert "1 of 2 with mass_est" in text


def test_sim_resistances_column():
    """With the runs of the simulator's resistances for every held log, each row gains their
    mass error and sd against m, pause off and on; without them (None or a log missing) the
    table keeps its six columns."""
    obs = {}
    for (k, s), v in _obs(900.0, 960.0, 40).items():
        obs[("slips.csv", s, k)] = v
    sim = {}
    for (k, s), v in _obs(1001.0, 1080.0, 40).items():
        sim[("slips.csv", s, k)] = v
    cols = [("1", "2", "3", "4")]
    mg = {("a.csv", "0"): (cols, 0), ("a.csv", "default"): (cols, 0)}
    text = ms.tables(obs, ["slips.csv"], mg, ["a.csv"], sim)
    rows = [r for r in text.splitlines() if r.startswith("| slips")]
    assert rows[0] == ("| slips | 1.0 m | -10.0% → -4.0% | 0.2% → 2.0% | 40 | 100 → 60 |"
                       " +0.1% (0.2%) → +8.0% (2.0%) |")
    del sim[("slips.csv", ms.STARTS[-1], "0")]
    text = ms.tables(obs, ["slips.csv"], mg, ["a.csv"], sim)
    assert [r for r in text.splitlines() if r.startswith("| slips")][0].count("|") == 7


def test_res_logs_table_and_paths():
    """The logs with the car's resistances get their own rows (every log listed, held or not),
    after the summary lines; none given: no such table. A _res log is read from
    scenarios/observer_res/."""
    obs = {}
    for (k, s), v in _obs(900.0, 960.0, 40).items():
        obs[("slips.csv", s, k)] = v
    res = {}
    for name, (off, on, n) in {"slips_res.csv": (990.0, 1050.0, 40),
                               "hill_res.csv": (1002.0, 1002.0, 0)}.items():
        for (k, s), v in _obs(off, on, n).items():
            res[(name, s, k)] = v
    cols = [("1", "2", "3", "4")]
    mg = {("a.csv", "0"): (cols, 0), ("a.csv", "default"): (cols, 0)}
    names = ["hill_res.csv", "slips_res.csv"]
    text = ms.tables(obs, ["slips.csv"], mg, ["a.csv"], None, res, names)
    after = text.split("simulator (scenarios/observer_res/", 1)[1].splitlines()
    assert [r for r in after if r.startswith("| slips_res")][0] == \
        "| slips_res | 1.0 m | -1.0% → +5.0% | 0.2% → 2.0% | 40 | 100 → 60 |"
    assert [r for r in after if r.startswith("| hill_res")][0] == \
        "| hill_res | 1.0 m | +0.2% → +0.2% | 0.2% → 2.0% | 0 | 100 → 100 |"
    assert "observer_res" not in ms.tables(obs, ["slips.csv"], mg, ["a.csv"])
    assert ms.log_path("hill_res.mf.csv") == str(Path(ms.RES_DIR) / "hill_res.mf.csv")
    assert ms.log_path("hill.csv").endswith(str(Path("scenarios", "observer", "hill.csv")))
