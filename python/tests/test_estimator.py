"""Estimator.run and Estimator.step in memory against rfe.replay (docs/PYTHON.md "In memory").

The in-memory path (src/host/replay_mem.h) reads columns by the CSV reader's rules, sets the
run up by mu_replay's code and steps the same replay core, with no file and no captured fds;
rfe.replay runs mu_replay's main on a file. So the expected values here come from another
path through the C code (the text reader, mu_replay's main, the estimate-log writer and
rfe.read_log), and every comparison is bit for bit: no tolerance.
"""
from __future__ import annotations

import faulthandler
import math
import os
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import rfe
from test_rfe import LOGS, REALS, ROOT


def assert_same_estimates(got: pd.DataFrame, want: pd.DataFrame, real: str, what: str) -> None:
    """Equal columns, and equal values bit for bit. A float run's values are the C floats
    exactly in memory, while replay reads them back from the %.9g text the estimate log holds
    (which rounds back to the same float, not to the same double): so in float the two are
    compared as float32, bit for bit, after checking that the in-memory values are floats."""
    assert list(got.columns) == list(want.columns), what
    a = got.to_numpy(np.float64)
    b = want.to_numpy(np.float64)
    assert a.shape == b.shape, what
    if real == "float":
        t = list(got.columns).index("t")  # t is the input time, a double in every run
        assert np.array_equal(a[:, t].view(np.int64), b[:, t].view(np.int64)), what
        a = np.delete(a, t, axis=1)
        b = np.delete(b, t, axis=1)
        assert np.array_equal(a.astype(np.float32).astype(np.float64).view(np.int64),
                              a.view(np.int64)), what + ": not float values"
        a, b = a.astype(np.float32).view(np.int32), b.astype(np.float32).view(np.int32)
    else:
        a, b = a.view(np.int64), b.view(np.int64)
    bad = np.argwhere(a != b)
    assert bad.size == 0, f"{what}: first difference at row, column {bad[:1].tolist()}"


@pytest.mark.parametrize("real", REALS)
@pytest.mark.parametrize("log", LOGS)
def test_run_in_memory_equals_replay(log: str, real: str) -> None:
    """Every scenario log and the two smallest of each subfolder (faults, observer, mass and
    grade with drive_torque, a car logger's units and names, tyre identification): the
    DataFrame run in memory gives replay's estimates, with the same defaults."""
    sensor = rfe.read_log(ROOT / log)
    got = rfe.Estimator(real=real).run(sensor)
    want = rfe.replay(ROOT / log, real=real, quiet=True)
    assert_same_estimates(got, want, real, log)
    assert got.attrs["stats"]["steps"] == len(sensor)
    assert got.attrs["stats"]["status_counts"] == want.attrs["summary"]["status_counts"]
    assert got.attrs["stats"]["gaps"] == want.attrs["summary"]["gaps"]


def test_run_with_options_equals_replay() -> None:
    """Options and parameters reach the in-memory run as mu_replay's flags: the paper preset
    with the CKF, a parameter mapping, the observer forced on a measuring log, the adaptive
    mass and grade estimator, the truck's mass and grade preset in fixed point, the tyre
    identifier (its columns) and with its curve fed (the
    friction estimator's curve columns too)."""
    mg = "scenarios/mass_grade/" + sorted(os.listdir(ROOT / "scenarios/mass_grade"))[0]
    cases = [("scenarios/brake_in_turn.csv", dict(preset="paper", filter="ckf"), "double"),
             ("scenarios/brake_in_turn.csv", dict(params={"mu0": 0.6, "tau_v": 0.05}), "q31"),
             ("scenarios/cruise.csv", dict(velocity="observer"), "float"),
             (mg, dict(mass_grade="aukf"), "double"),
             ("scenarios/mass_grade/truck_graded_drive.csv", dict(mass_grade_vehicle="truck"),
              "q31"),
             ("scenarios/tyre_id/tid_sine_steer.csv", dict(tyre_id="apf"), "float"),
             ("scenarios/tyre_id/tid_sine_steer.csv", dict(tyre_id="sckf"), "double"),
             ("scenarios/tyre_id/tid_sine_steer.csv",
              dict(tyre_id="sir", params={"tid_feed_sd_rel": 0.05}), "double")]
    for log, options, real in cases:
        est = rfe.Estimator(real=real, **options)
        got = est.run(rfe.read_log(ROOT / log))
        want = rfe.replay(ROOT / log, real=real, quiet=True, **options)
        assert_same_estimates(got, want, real, f"{log} {options}")
        if "mass_grade_vehicle" in options:
            assert want.attrs["meta"]["mass_grade_vehicle"] == "truck"
            assert float(want.attrs["meta"]["mg_cd"]) == 0.6  # the truck's (MASS_GRADE.md §6)
        if "tyre_id" in options:
            assert "tid_flags" in got.columns
            assert ("cy_used" in got.columns) == ("params" in options)
        # the mismatch flag (MASS_GRADE.md §4.8) is a mass and grade column, in every run of
        # that estimator and in no other (it must not ride on the curve feed's columns)
        assert ("mg_mismatch" in got.columns) == ("mass_grade" in log), log


def test_mass_feed_gate_keys_reach_the_run() -> None:
    """The mass feed's excitation gate (mg_feed_excitation, MASS_GRADE.md §10) is the C
    replay's, keys and all: in memory as in mu_replay, with the gate (the default 1 m/s) the
    friction estimator's mass first changes later than without it (0: the sd rule alone) on
    car_grade_step, whose sd rule passes 26 updates before its |ax| sums 1 m/s (test_cli.sh),
    and every row equals the replay's with the same keys."""
    log = ROOT / "scenarios/mass_grade/car_grade_step.csv"
    sensor = rfe.read_log(log)
    first = {}
    for gate in (None, 0.0):
        options = {} if gate is None else dict(params={"mg_feed_excitation": gate})
        got = rfe.Estimator(real="double", **options).run(sensor)
        want = rfe.replay(log, real="double", quiet=True, **options)
        assert_same_estimates(got, want, "double", f"gate {gate}")
        used = got["mass_used"].to_numpy()
        first[gate] = int((used != used[0]).argmax())
        assert first[gate] > 0
    assert first[None] > first[0.0]


def test_mass_feed_check_keys_reach_the_run() -> None:
    """The feed's plausibility checks (mg_feed_slip_max, mg_feed_band, MASS_GRADE.md §10) are
    the C replay's too: on car_grade_step (truth 2100 kg, the estimate fed within 0.3 % of it,
    MASS_GRADE_RESULTS.md) a parameter m of 3000 kg with a band of 5 % (2850-3150 kg) refuses
    every due mass, so mass_used stays m, where the default keys feed; and every row equals
    the replay's with the same keys, the slip hold off or on."""
    log = ROOT / "scenarios/mass_grade/car_grade_step.csv"
    sensor = rfe.read_log(log)
    for params in ({"m": 3000.0, "mg_feed_band": 0.05}, {"mg_feed_slip_max": 0.0}, {}):
        options = dict(params=params) if params else {}
        got = rfe.Estimator(real="double", **options).run(sensor)
        want = rfe.replay(log, real="double", quiet=True, **options)
        assert_same_estimates(got, want, "double", f"checks {params}")
        used = got["mass_used"].to_numpy()
        if "mg_feed_band" in params:
            assert (used == used[0]).all()  # never fed
        else:
            assert (used != used[0]).any()  # fed


def test_mapping_of_arrays_equals_dataframe() -> None:
    """{column: array} with meta= runs as the DataFrame with attrs["meta"] (lists too)."""
    sensor = rfe.read_log(ROOT / "scenarios/hard_brake_low_mu.csv")
    arrays = {c: sensor[c].to_numpy() for c in sensor.columns}
    arrays["t"] = list(arrays["t"])
    est = rfe.Estimator(real="double")
    got = est.run(arrays, meta=sensor.attrs["meta"])
    assert_same_estimates(got, est.run(sensor), "double", "mapping")


STEP_LOGS = ["scenarios/brake_in_turn.csv", "scenarios/car_format/dlc_mu035.csv",
             "scenarios/mass_grade/" + sorted(os.listdir(ROOT / "scenarios/mass_grade"))[0],
             "scenarios/faults/" + sorted(os.listdir(ROOT / "scenarios/faults"))[0]]


@pytest.mark.parametrize("real", REALS)
@pytest.mark.parametrize("log", STEP_LOGS)
def test_step_equals_run(log: str, real: str) -> None:
    """step() sample by sample gives run()'s rows over the same samples, bit for bit: a
    measuring log, a car logger's (units, the observer), a mass and grade log, a fault log.
    The first 400 samples (4 s: the estimators converge, the gaps and faults of the short
    logs are inside) keep the Python loop short."""
    full = rfe.read_log(ROOT / log)
    meta = dict(full.attrs["meta"])
    if "dt" not in meta:  # step() needs dt given: the one mu_replay takes from the stamps
        meta["dt"] = rfe.replay(ROOT / log, quiet=True).attrs["meta"]["dt"]
    sensor = full.iloc[:400].copy()
    sensor.attrs["meta"] = meta  # run() is given the same
    est = rfe.Estimator(real=real)
    want = est.run(sensor)
    rows = [est.step({c: sensor[c].iloc[i] for c in sensor.columns}, meta=meta)
            for i in range(len(sensor))]
    got = pd.DataFrame(rows, columns=list(want.columns))
    assert got.dtypes.equals(want.dtypes)
    assert_same_estimates(got, want, real, log)
    assert est.stats() == want.attrs["stats"]
    est.reset()
    assert est.stats() == {"steps": 0}


def test_step_needs_dt_and_increasing_time() -> None:
    sensor = rfe.read_log(ROOT / "scenarios/cruise.csv")
    meta = {k: v for k, v in sensor.attrs["meta"].items() if k != "dt"}
    sample = {c: sensor[c].iloc[0] for c in sensor.columns}
    with pytest.raises(rfe.UsageError, match="give dt"):
        rfe.Estimator().step(sample, meta=meta)
    est = rfe.Estimator(params={"dt": 0.01})
    est.step(sample, meta=meta)
    with pytest.raises(rfe.InputError, match="time not increasing") as e:
        est.step(sample)
    assert e.value.status is None
    # the refused sample changed nothing: the next one steps as in a run of the two
    second = {c: sensor[c].iloc[1] for c in sensor.columns}
    want = rfe.Estimator(params={"dt": 0.01}).run(sensor.iloc[:2], meta=meta)
    assert est.step(second) == {c: want[c].iloc[1].item() for c in want.columns}
    with pytest.raises(rfe.InputError, match="other columns"):
        est.step(second | {"grade": 0.0, "t": 9.0})  # a column the first sample had not


def test_errors_are_typed_by_status() -> None:
    """In memory the exception class comes from the status the C code returns, with the
    CLI's .status and .exit_code."""
    sensor = rfe.read_log(ROOT / "scenarios/cruise.csv")
    with pytest.raises(rfe.ParamError) as e:
        rfe.Estimator(params={"mu0": -3.0}).run(sensor)
    assert (e.value.status, e.value.exit_code) == (19, 1) and "invalid parameter mu0" in str(e.value)
    with pytest.raises(rfe.RangeError) as e:
        rfe.Estimator(params={"m": 1e9}, real="q31").run(sensor)
    assert e.value.status == 18
    bad = sensor.copy()
    bad.loc[5, "ax"] = math.nan
    with pytest.raises(rfe.NonFiniteError) as e:
        rfe.Estimator(strict=True).run(bad)
    assert e.value.status == 17 and (e.value.line, e.value.col) == (6, 7)  # row 6, column ax
    # without strict the estimator rejects that sample with the same status
    assert rfe.Estimator().run(bad)["status"].iloc[5] == 17
    with pytest.raises(rfe.UsageError) as e:
        rfe.Estimator(real="q32").run(sensor)  # type: ignore[arg-type]
    assert e.value.exit_code == 2 and "--real must be" in e.value.message
    with pytest.raises(rfe.InputError) as e:
        rfe.Estimator().run(sensor.drop(columns=["ay"]))
    assert e.value.status is None and "missing column 'ay'" in e.value.message
    with pytest.raises(rfe.InputError, match="no data rows"):
        rfe.Estimator().run(sensor.iloc[:0])


def test_run_in_memory_captures_no_fds(monkeypatch: pytest.MonkeyPatch,
                                       capfd: pytest.CaptureFixture[str]) -> None:
    """The in-memory run neither goes through the CLI's fd capture nor prints: with the
    capture made to fail it still runs, and fds 1 and 2 stay silent."""
    def no_capture(*args: object, **kwargs: object) -> None:
        raise AssertionError("the in-memory run went through cli.run_captured")
    monkeypatch.setattr(rfe.cli, "run_captured", no_capture)
    sensor = rfe.read_log(ROOT / "scenarios/brake_in_turn.csv")
    sensor.loc[5, "ax"] = math.nan  # mu_replay would print a note on stderr
    rfe.Estimator(real="double").run(sensor)
    assert capfd.readouterr() == ("", "")


def test_estimators_run_in_threads() -> None:
    """Several Estimators in threads of one process: each run owns its C state, so the
    results equal the runs one after the other."""
    logs = ["scenarios/brake_in_turn.csv", "scenarios/cruise.csv",
            "scenarios/car_format/dlc_mu035.csv", "scenarios/hard_brake_low_mu.csv"]
    frames = [rfe.read_log(ROOT / log) for log in logs]
    jobs = [(f, real) for f in frames for real in REALS]
    alone = [rfe.Estimator(real=real).run(f) for f, real in jobs]
    with ThreadPoolExecutor(max_workers=4) as pool:
        together = list(pool.map(lambda job: rfe.Estimator(real=job[1]).run(job[0]), jobs))
    for (f, real), a, b in zip(jobs, alone, together):
        assert_same_estimates(b, a, real, "threads")


def test_run_in_memory_releases_the_gil(tmp_path: Path) -> None:
    """The in-memory C call holds no GIL: its parameter file is a pipe that only this
    thread writes, after the run started (the C set-up blocks opening it). Were the GIL held
    during the call, the writer could never run and the run never end: faulthandler's
    watchdog (a C thread, no GIL) then ends the process with the threads' tracebacks, so a
    hang is a failure, never a pass."""
    sensor = rfe.read_log(ROOT / "scenarios/paper_high_mu_brake.csv")
    fifo = tmp_path / "params.txt"
    os.mkfifo(fifo)
    result: dict[str, object] = {}

    def work() -> None:
        try:
            result["df"] = rfe.Estimator(params=fifo, real="double").run(sensor)
        except BaseException as exc:  # noqa: BLE001 (reported below)
            result["error"] = exc

    faulthandler.dump_traceback_later(300, exit=True)
    worker = threading.Thread(target=work, daemon=True)
    worker.start()
    with open(fifo, "w", encoding="utf-8") as f:  # blocks until the C code opened the pipe
        f.write("mu0 = 0.7\n")
    worker.join(timeout=240)
    faulthandler.cancel_dump_traceback_later()
    assert not worker.is_alive(), "the C run never finished"
    assert "error" not in result, result.get("error")
    want = rfe.Estimator(params={"mu0": 0.7}, real="double").run(sensor)
    assert_same_estimates(result["df"], want, "double", "gil")  # type: ignore[arg-type]
