"""The fleet replay (docs/PYTHON.md "Fleet replay"): python -m rfe.fleet over a few bundled
logs, an MDF4 recording and two broken logs, on a LocalCluster of two worker processes.

One fleet run (a module fixture) serves every test. Three CSV logs from two folders (a
braking in a turn on 0.85, a cruise where nothing is observable and every step is held, a
car logger's log in its own units), one MDF4 recording through its mapping and two broken
logs cover every path of a task: replayed with truth, replayed with nothing valid, read
through a mapping, failed on a corrupt file, failed on missing channels; two workers make
the tasks really run side by side in separate processes. More logs would add run time, not
paths. In q31, so that the saturation counts are in the summary too and the options are seen
to reach the workers.
"""
from __future__ import annotations

import faulthandler
import io
import math
import os
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import mdf4_log
import rfe
from rfe import fleet

ROOT = Path(__file__).resolve().parents[2]
LOGS = ["scenarios/brake_in_turn.csv", "scenarios/cruise.csv",
        "scenarios/car_format/dlc_mu035.csv"]
REAL = "q31"


def quiet_replay(source, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rfe.RfeWarning)
        return rfe.replay(source, **kw)


@pytest.fixture(scope="module")
def drives(tmp_path_factory) -> dict[str, Path]:
    """The fleet's inputs: the bundled logs, the MDF4 recording and its mapping, a CSV cut
    off in the middle of a row and a log without the wheel speeds."""
    d = tmp_path_factory.mktemp("drives")
    scenario = rfe.read_log(ROOT / "scenarios/brake_in_turn.csv")
    mdf4_log.write_mdf(mdf4_log.channel_values(scenario), d / "recorded.mf4")
    (d / "mapping.toml").write_text(mdf4_log.mapping_text(), encoding="utf-8")
    text = (ROOT / "scenarios/cruise.csv").read_text(encoding="utf-8")
    (d / "cut.csv").write_text(text[:len(text) // 2], encoding="utf-8")
    lines = [ln for ln in text.splitlines() if not ln.startswith("#")][:200]
    (d / "no_wheels.csv").write_text(
        "\n".join(",".join(ln.split(",")[:8]) for ln in lines) + "\n", encoding="utf-8")
    return {"dir": d, "mf4": d / "recorded.mf4", "mapping": d / "mapping.toml",
            "cut": d / "cut.csv", "no_wheels": d / "no_wheels.csv"}


@pytest.fixture(scope="module")
def run(drives, tmp_path_factory):
    """python -m rfe.fleet over the logs: (the completed process, the output folder)."""
    out = tmp_path_factory.mktemp("fleet")
    args = [sys.executable, "-m", "rfe.fleet", *(str(ROOT / p) for p in LOGS),
            str(drives["mf4"]), str(drives["cut"]), str(drives["no_wheels"]),
            "--mapping", str(drives["mapping"]), "--real", REAL, "--workers", "2",
            "--out", str(out)]
    proc = subprocess.run(args, cwd=ROOT, capture_output=True, text=True, env=os.environ)
    return proc, out


@pytest.fixture(scope="module")
def summary(run) -> pd.DataFrame:
    _, out = run
    # pandas 3 parses floats correctly rounded (its default), so each number is the double
    # written (to_csv writes the shortest round-trip text)
    return pd.read_csv(out / "summary.csv",
                       keep_default_na=False, na_values=[""])


def good_logs(drives) -> list[Path]:
    return [ROOT / p for p in LOGS] + [drives["mf4"]]


def row_of(summary: pd.DataFrame, log: Path) -> pd.Series:
    rows = summary[summary["log"] == str(log.resolve())]
    assert len(rows) == 1, (log, summary["log"].tolist())
    return rows.iloc[0]


def test_broken_logs_are_reported_and_the_others_complete(run, summary, drives):
    proc, out = run
    assert proc.returncode == 1, proc.stderr  # some log failed
    cut, no_wheels = row_of(summary, drives["cut"]), row_of(summary, drives["no_wheels"])
    assert "wrong column count" in cut["error"] and "InputError" in cut["error"]
    assert "missing columns 'omega_fl'" in no_wheels["error"]
    for log in (drives["cut"], drives["no_wheels"]):
        assert f"rfe.fleet: {log.resolve()}: InputError" in proc.stderr
    for log in good_logs(drives):
        row = row_of(summary, log)
        assert pd.isna(row["error"]), row["error"]
        assert (out / row["estimates"]).is_file()
    assert len(summary) == len(LOGS) + 3 + 1       # every log and the overall row, last
    assert summary["log"].iloc[-1] == fleet.OVERALL
    assert summary["error"].iloc[-1] == "2 of 6 logs failed"


def test_estimates_equal_replay_exactly(run, summary, drives):
    """Each per-log Parquet holds rfe.replay's DataFrame of the same log, bit for bit."""
    _, out = run
    for log in good_logs(drives):
        kw = {"mapping": drives["mapping"]} if log.suffix == ".mf4" else {}
        ref = quiet_replay(log, real=REAL, **kw)
        got = rfe.read_parquet(out / row_of(summary, log)["estimates"])
        pd.testing.assert_frame_equal(got, ref, check_exact=True)
        assert got.attrs["meta"] == ref.attrs["meta"]
        assert got.attrs["meta"]["real"] == REAL


def test_summary_rows_are_the_replay_summary(summary, drives):
    """Each row is the replay's summary (mu_replay's --metrics JSON): the same numbers."""
    for log in good_logs(drives):
        kw = {"mapping": drives["mapping"]} if log.suffix == ".mf4" else {}
        est = quiet_replay(log, real=REAL, **kw)
        s, row = est.attrs["summary"], row_of(summary, log)
        assert row["steps"] == s["steps"] == len(est)
        statuses = {int(c[len("status_"):]): int(row[c]) for c in summary.columns
                    if c.startswith("status_") and not pd.isna(row[c])}
        assert statuses == {int(k): v for k, v in s["status_counts"].items()}
        assert row["sat_estimator"] == s["saturation"]["estimator_total"]
        assert row["sat_input"] == s["saturation"]["input_values"]
        assert row["gaps"] == s["gaps"]["count"] and row["bad_rows"] == s["bad_cells"]["rows"]
        mean = rfe.metrics(est)["mean"]
        for key in ("n_settled", "n_valid", "frac_valid", "consistency_valid", "rmse_valid"):
            want = math.nan if mean[key] is None else mean[key]
            assert row[key] == want or (math.isnan(want) and pd.isna(row[key])), key
        # steps whose four valid flags are all 1, counted here row by row
        flags = est[["valid_fl", "valid_fr", "valid_rl", "valid_rr"]].to_numpy().tolist()
        all_valid = sum(1 for f in flags if f == [1, 1, 1, 1])
        assert row["valid_steps"] == all_valid
        assert row["valid_share"] == all_valid / len(est)


def test_overall_row_pools_the_logs(summary):
    """The overall row, derived here from the per-log rows with plain sums (docs/PYTHON.md:
    the logs pooled as if they were one). Integers exactly; the ratios to 1e-12 relative:
    each is a few products and a sum of four terms, evaluated in a different order than the
    fleet's pandas sums, so they differ by a few roundings of 2^-53 each at most."""
    logs = summary[(summary["log"] != fleet.OVERALL) & summary["error"].isna()]
    total = summary.iloc[-1]
    for col in ["steps", "valid_steps", "n_settled", "n_valid", "sat_estimator", "gaps"] + \
            [c for c in summary.columns if c.startswith("status_")]:
        assert total[col] == sum(int(v) for v in logs[col] if not pd.isna(v)), col
    assert total["valid_share"] == pytest.approx(
        sum(logs["valid_steps"]) / sum(logs["steps"]), rel=1e-12)
    assert total["frac_valid"] == pytest.approx(
        sum(logs["n_valid"]) / sum(logs["n_settled"]), rel=1e-12)
    pooled = [(r["n_valid"], r["consistency_valid"], r["rmse_valid"])
              for _, r in logs.iterrows() if r["n_valid"] > 0]
    n = math.fsum(p[0] for p in pooled)
    assert total["consistency_valid"] == pytest.approx(
        math.fsum(p[0] * p[1] for p in pooled) / n, rel=1e-12)
    assert total["rmse_valid"] == pytest.approx(
        math.sqrt(math.fsum(p[0] * p[2] ** 2 for p in pooled) / n), rel=1e-12)


def test_report_lists_the_worst_log_first(run, summary):
    _, out = run
    page = (out / "report.html").read_text(encoding="utf-8")
    assert page.count('src="data:image/png;base64,') == 2   # valid share, surfaces
    assert 'src="http' not in page and "<link" not in page   # self-contained
    worst_table = page.split("worst first</h2>", 1)[1]
    logs = summary[summary["log"] != fleet.OVERALL]
    positions = {log: worst_table.index(f"<td>{log}</td>") for log in logs["log"]}
    failed = logs[logs["error"].notna()]["log"]
    done = logs[logs["error"].isna()]
    # the failed logs, then a completed log of the lowest valid share (found here; the cruise,
    # where nothing is observable, has share 0, and so may the low-mu lane change, whose
    # estimates the bound margin keeps from being valid: ties are in any order)
    share = done.set_index("log")["valid_share"]
    order = sorted(positions, key=positions.get)
    assert set(order[:len(failed)]) == set(failed)
    assert share[order[len(failed)]] == share.min()
    assert share[[log for log in share.index if log.endswith("cruise.csv")]].tolist() == [0.0]
    assert list(share[order[len(failed):]]) == sorted(share)   # worst first, all the way down


def test_surface_histograms_count_every_valid_sample():
    """The histogram of a log with one surface (0.85) holds each valid wheel sample once."""
    log = ROOT / "scenarios/brake_in_turn.csv"
    est = quiet_replay(log)
    truth = rfe.read_log(log)
    hist = fleet.surface_histograms(est, truth[["mu_fl", "mu_fr", "mu_rl", "mu_rr"]]
                                    .set_axis(list(fleet.WHEELS), axis=1))
    assert list(hist) == ["0.85"]
    valid = int((est[["valid_fl", "valid_fr", "valid_rl", "valid_rr"]] != 0).to_numpy().sum())
    assert sum(hist["0.85"]) == valid > 0
    want = sum(np.histogram(est.loc[est[f"valid_{w}"] != 0, f"mu_{w}"], bins=fleet.MU_BINS)[0]
               for w in fleet.WHEELS)
    assert hist["0.85"] == want.tolist()


def test_surface_histograms_split_the_surfaces():
    """Two surfaces, the bins' edges included (np.histogram's rule: the last bin closed)."""
    est = pd.DataFrame({**{f"mu_{w}": [0.0, 1.3, 0.3125, 0.34] for w in fleet.WHEELS},
                        **{f"valid_{w}": [1, 1, 1, 0] for w in fleet.WHEELS}})
    truth = pd.DataFrame({w: [0.2, 0.2, 0.87, 0.87] for w in fleet.WHEELS})
    hist = fleet.surface_histograms(est, truth)
    assert sorted(hist) == ["0.20", "0.85"]
    n = len(fleet.MU_BINS) - 1
    assert hist["0.20"] == [4] + [0] * (n - 2) + [4]   # 0.0 in the first bin, 1.3 the last
    low = [0] * n
    low[12] = 4                                        # 0.3125: mid-bin [0.3, 0.325)
    assert hist["0.85"] == low                         # 0.34 is not valid


def test_usage_errors_exit_2(drives, tmp_path, capsys):
    assert fleet.main([str(tmp_path / "nothing*.csv"), "--out", str(tmp_path)]) == 2
    assert "no log found" in capsys.readouterr().err
    assert fleet.main([str(drives["mf4"]), "--out", str(tmp_path)]) == 2
    assert "need --mapping" in capsys.readouterr().err
    with pytest.raises(SystemExit) as e:
        fleet.main([str(drives["cut"]), "--out", str(tmp_path), "--real", "quad"])
    assert e.value.code == 2


def test_the_output_folder_is_no_input(tmp_path, capsys):
    """Replaying a folder into a folder inside it again does not take the first run's
    estimates (Parquet) for sensor logs."""
    old = tmp_path / "drives" / "fleet" / "estimates" / "drive.parquet"
    old.parent.mkdir(parents=True)
    old.write_bytes(b"")
    assert fleet.main([str(tmp_path / "drives"), "--out", str(tmp_path / "drives" / "fleet")]) == 2
    assert "inside the output folder" in capsys.readouterr().err


def test_find_logs_takes_folders_and_globs(drives):
    by_folder = fleet.find_logs([str(drives["dir"])])
    assert [p.name for p in by_folder] == ["cut.csv", "no_wheels.csv", "recorded.mf4"]
    assert fleet.find_logs([str(drives["dir"] / "*.csv")]) == by_folder[:2]
    paths = fleet.estimate_paths([ROOT / LOGS[0], ROOT / LOGS[2]], Path("/o"))
    assert paths == [Path("/o/estimates/brake_in_turn.parquet"),
                     Path("/o/estimates/car_format/dlc_mu035.parquet")]


def test_every_log_failed_still_gives_summary_and_report(tmp_path):
    """With no log replayed the table has the errors and the overall row, and the report is
    written (an empty distribution, no surfaces) instead of failing on absent columns."""
    rows = [fleet.summary_row(f"/d/{n}.csv", "", {"error": f"InputError: {n}"})
            for n in ("a", "b")]
    table = fleet.summary_table(rows)
    assert table["log"].tolist() == ["/d/a.csv", "/d/b.csv", fleet.OVERALL]
    assert table["error"].iloc[-1] == "2 of 2 logs failed"
    from rfe.fleet_report import write_report
    write_report(tmp_path / "report.html", table, fleet.worst_first(table), {}, fleet.MU_BINS,
                 options={})
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert "InputError: a" in page and "No log has truth columns" in page


def crash_on_crash_csv(log, estimates, options, mapping):
    """replay_one, except that a log named crash.csv ends its worker process at once, as a
    crash in C would."""
    if Path(log).name == "crash.csv":
        os._exit(3)
    return fleet.replay_one(log, estimates, options, mapping)


def test_a_log_that_kills_its_worker_takes_no_other_log_along(tmp_path):
    """One worker, so the logs queued on it die with it (distributed blames each of them);
    they run again alone and complete, and only the crashing log is reported."""
    import cloudpickle
    import dask
    from dask.distributed import Client, LocalCluster
    cloudpickle.register_pickle_by_value(sys.modules[__name__])  # the workers lack this file
    crash = tmp_path / "crash.csv"
    crash.write_text((ROOT / "scenarios/cruise.csv").read_text(encoding="utf-8"), encoding="utf-8")
    logs = [crash, ROOT / "scenarios/brake_in_turn.csv", ROOT / "scenarios/cruise.csv"]
    est = fleet.estimate_paths(logs, tmp_path / "out")
    for p in est:
        p.parent.mkdir(parents=True, exist_ok=True)
    stream = io.StringIO()
    # A hang guard, not a timing: an early version of this test (distributed's default of
    # three retries) hung once; should it ever hang again, the run ends with every thread's
    # traceback after 10 minutes instead of using up CI's 90.
    faulthandler.dump_traceback_later(600, exit=True)
    # a dead worker's tasks fail at once instead of after three more deaths (distributed's
    # default, for workers lost at random): the same path, a fraction of the worker restarts
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), \
            LocalCluster(n_workers=1, threads_per_worker=1, processes=True,
                         **fleet.QUIET_CLUSTER) as cluster, Client(cluster) as client:
        results = fleet._gather(client, logs, est, {}, None,
                                fleet.Progress(len(logs), quiet=True, stream=stream),
                                task=crash_on_crash_csv)
    faulthandler.cancel_dump_traceback_later()
    assert results[0]["error"].startswith("KilledWorker")
    assert results[1]["error"] is None and results[2]["error"] is None
    assert est[1].is_file() and est[2].is_file()
    assert stream.getvalue().count("rfe.fleet: ") == 1   # the crashing log alone


def test_a_log_lost_with_its_worker_runs_alone_again_until_it_survives_or_dies_twice():
    """fleet._alone: a try that completes (or fails otherwise) ends the retries; a worker's
    death is tried once more under a new tag; a log whose worker dies on every try keeps the
    last death. A stand-in for the cluster records the tags it was run under."""
    def runner(outcomes):
        tags = []

        def run(tag):
            tags.append(tag)
            return outcomes[len(tags) - 1]
        return run, tags

    died = {"error": "KilledWorker: ...", "killed": True}
    done = {"error": None}
    run, tags = runner([done])
    assert fleet._alone(run) is done and tags == ["-alone1"]
    run, tags = runner([died, done])
    assert fleet._alone(run) is done and tags == ["-alone1", "-alone2"]
    failed = {"error": "InputError: ...", "killed": False}
    run, tags = runner([died, failed])
    assert fleet._alone(run) is failed and tags == ["-alone1", "-alone2"]
    last = {"error": "KilledWorker: again", "killed": True}
    run, tags = runner([died, last, done])
    assert fleet._alone(run) is last and len(tags) == fleet.ALONE_TRIES == 2
