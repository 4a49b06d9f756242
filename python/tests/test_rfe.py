"""The rfe package against mu_replay (docs/PYTHON.md "Tests").

Run by `make test-pkg` (in `make test`) on the package built into build/py; MU_REPLAY names
the CLI binary to compare with (default build/mu_replay).
"""
from __future__ import annotations

import faulthandler
import json
import math
import os
import struct
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import rfe

ROOT = Path(__file__).resolve().parents[2]
MU_REPLAY = Path(os.environ.get("MU_REPLAY", ROOT / "build" / "mu_replay"))
# The bundled sensor logs: every scenario log (scenarios/*.csv, the set), and of the
# fault, observer, mass and grade, car-format and tyre identification logs the two smallest of
# each folder (their paths: faults, the observer, the mass and grade estimator, a car
# logger's units and names), so that make test stays fast; RFE_PKG_ALL_LOGS=1 takes every
# log of those folders too (scenarios/golden/ holds estimate logs, not sensor logs).
SUBFOLDERS = ("faults", "observer", "mass_grade", "car_format", "tyre_id")


def bundled_logs() -> list[str]:
    logs = list(ROOT.glob("scenarios/*.csv"))
    for d in SUBFOLDERS:
        found = sorted(ROOT.glob(f"scenarios/{d}/*.csv"), key=lambda p: (p.stat().st_size, p.name))
        logs += found if os.environ.get("RFE_PKG_ALL_LOGS") == "1" else found[:2]
    return sorted(p.relative_to(ROOT).as_posix() for p in logs)


LOGS = bundled_logs()
REALS = ("float", "double", "q31")


def cli(*args: str, cwd: Path = ROOT) -> subprocess.CompletedProcess:
    return subprocess.run([str(MU_REPLAY), *args], cwd=cwd, capture_output=True, text=True)


def bits(x: float) -> int:
    return struct.unpack("<q", struct.pack("<d", x))[0]


def parse_estimate_log(path: Path) -> tuple[list[str], list[list[float]]]:
    """The estimate log's header and rows by float() alone (independent of rfe.read_log)."""
    lines = [ln for ln in path.read_text(encoding="utf-8").splitlines()
             if not ln.startswith("#")]
    return ([c.strip() for c in lines[0].split(",")],
            [[float(c) for c in ln.split(",")] for ln in lines[1:]])


def test_bundled_logs_found() -> None:
    assert len(LOGS) >= 50 + 2 * len(SUBFOLDERS), LOGS


@pytest.mark.parametrize("real", REALS)
@pytest.mark.parametrize("log", LOGS)
def test_replay_equals_mu_replay_bit_for_bit(log: str, real: str, tmp_path: Path) -> None:
    """rfe.replay on a bundled log writes mu_replay's estimate log byte for byte, and its
    DataFrame holds every value of it bit for bit, with mu_replay's defaults. (mu_replay
    runs in its own process meanwhile: the two runs share the two cores.)"""
    ref = tmp_path / "cli.csv"
    proc = subprocess.Popen([str(MU_REPLAY), "--in", log, "--out", str(ref), "--real", real,
                             "--quiet"], cwd=ROOT, stderr=subprocess.PIPE, text=True)
    out = tmp_path / "pkg.csv"
    df = rfe.replay(ROOT / log, real=real, out=out, quiet=True)
    _, err = proc.communicate()
    assert proc.returncode == 0, err
    assert out.read_bytes() == ref.read_bytes()
    text = [ln for ln in ref.read_text(encoding="utf-8").splitlines() if not ln.startswith("#")]
    assert list(df.columns) == [c.strip() for c in text[0].split(",")]
    want = np.loadtxt(text[1:], delimiter=",", dtype=np.float64, ndmin=2)
    assert np.array_equal(df.to_numpy(dtype=np.float64).view(np.int64), want.view(np.int64))


@pytest.mark.parametrize("real", REALS)
def test_dataframe_values_by_float(real: str, tmp_path: Path) -> None:
    """The DataFrame against mu_replay's file parsed by float() alone, cell by cell."""
    log = "scenarios/mu_step_hard_brake.csv"
    ref = tmp_path / "cli.csv"
    assert cli("--in", log, "--out", str(ref), "--real", real, "--quiet").returncode == 0
    header, rows = parse_estimate_log(ref)
    df = rfe.replay(ROOT / log, real=real, quiet=True)
    assert list(df.columns) == header
    for j, name in enumerate(header):
        col = df[name].to_numpy(dtype=np.float64)
        assert [bits(x) for x in col] == [bits(r[j]) for r in rows], name


def test_defaults_are_the_cli_defaults(tmp_path: Path) -> None:
    """No option at all: the same file as mu_replay without options (float, auto)."""
    log = "scenarios/observer/abs_brake_mu02.csv"
    ref = tmp_path / "cli.csv"
    assert cli("--in", log, "--out", str(ref)).returncode == 0
    out = tmp_path / "pkg.csv"
    rfe.replay(ROOT / log, out=out)
    assert out.read_bytes() == ref.read_bytes()


def test_dataframe_source_equals_path() -> None:
    """A log read into a DataFrame (metadata in attrs) replays as the file does, a car
    logger's units and names included."""
    for log in ("scenarios/brake_in_turn.csv", "scenarios/car_format/dlc_mu035.csv",
                "scenarios/mass_grade/" + sorted(os.listdir(ROOT / "scenarios/mass_grade"))[0]):
        a = rfe.replay(ROOT / log, real="double", quiet=True)
        b = rfe.replay(rfe.read_log(ROOT / log), real="double", quiet=True)
        assert np.array_equal(a.to_numpy(np.float64).view(np.int64),
                              b.to_numpy(np.float64).view(np.int64)), log


def test_estimator_run_equals_replay() -> None:
    log = ROOT / "scenarios/hard_brake_low_mu.csv"
    sensor = rfe.read_log(log)
    cols = {c: sensor[c].to_numpy() for c in sensor.columns}
    got = rfe.Estimator(preset="default", real="q31").run(cols, meta=sensor.attrs["meta"])
    want = rfe.replay(log, real="q31", quiet=True)
    assert np.array_equal(got.to_numpy(np.float64).view(np.int64),
                          want.to_numpy(np.float64).view(np.int64))


def test_metrics_equal_cli_json(tmp_path: Path) -> None:
    """rfe.metrics is mu_replay's --metrics JSON, the same C computation."""
    log = "scenarios/mu_step_hard_brake.csv"
    js = tmp_path / "m.json"
    assert cli("--in", log, "--out", str(tmp_path / "e.csv"), "--metrics", str(js),
               "--real", "double").returncode == 0
    want = json.loads(js.read_text(encoding="utf-8"))
    assert rfe.metrics(ROOT / log, real="double", quiet=True) == want["metrics"]
    est = rfe.replay(ROOT / log, real="double", quiet=True)
    assert rfe.metrics(est) == want["metrics"]
    assert est.attrs["summary"]["status_counts"] == want["status_counts"]


def test_tyre_id_passes_through(tmp_path: Path) -> None:
    """tyre_id="apf" is mu_replay's --tyre-id apf: the same file byte for byte, the issue's
    columns in the DataFrame and the identifier's counts in the summary; tyre_id="off" is the
    run without it."""
    log = "scenarios/tyre_id/tid_sine_steer.csv"
    ref = tmp_path / "cli.csv"
    js = tmp_path / "cli.json"
    assert cli("--in", log, "--out", str(ref), "--metrics", str(js), "--tyre-id", "apf",
               "--quiet").returncode == 0
    out = tmp_path / "pkg.csv"
    df = rfe.replay(ROOT / log, tyre_id="apf", out=out, quiet=True)
    assert out.read_bytes() == ref.read_bytes()
    assert list(df.columns[-14:]) == ["mu_id_f", "mu_id_r", "sd_mu_id_f", "sd_mu_id_r",
                                      "B_f", "C_f", "D_f", "E_f", "B_r", "C_r", "D_r", "E_r",
                                      "tid_status", "tid_flags"]
    assert df.attrs["summary"]["tyre_id"] == json.loads(js.read_text(encoding="utf-8"))["tyre_id"]
    off = rfe.replay(ROOT / log, tyre_id="off", quiet=True)
    assert "mu_id_f" not in off.columns and "tyre_id" not in off.attrs["summary"]
    with pytest.raises(rfe.UsageError):
        rfe.replay(ROOT / log, tyre_id="ukf", quiet=True)
    # the sigma-point filter (docs/TYRE_ID.md §15) likewise: --tyre-id sckf byte for byte
    assert cli("--in", log, "--out", str(ref), "--metrics", str(js), "--tyre-id", "sckf",
               "--quiet").returncode == 0
    df = rfe.replay(ROOT / log, tyre_id="sckf", out=out, quiet=True)
    assert out.read_bytes() == ref.read_bytes()
    assert df.attrs["meta"]["tid_filter"] == "sckf"
    assert df.attrs["summary"]["tyre_id"]["filter"] == "sckf"


def test_python_m_rfe_is_mu_replay(tmp_path: Path) -> None:
    """python -m rfe: the same stdout, stderr, exit status and files as mu_replay."""
    env = dict(os.environ)
    py = [sys.executable, "-m", "rfe"]
    cases = [["--help"], ["--bogus"], ["--in", "scenarios/nope.csv", "--out", "x.csv"],
             ["--in", "scenarios/mu_step_hard_brake.csv", "--out", "OUT.csv",
              "--metrics", "OUT.json", "--real", "q31"]]
    for args in cases:
        a = subprocess.run(py + [x.replace("OUT", str(tmp_path / "a")) for x in args],
                           cwd=ROOT, env=env, capture_output=True, text=True)
        b = cli(*[x.replace("OUT", str(tmp_path / "b")) for x in args])
        assert (a.returncode, a.stdout, a.stderr) == (b.returncode, b.stdout, b.stderr), args
    assert (tmp_path / "a.csv").read_bytes() == (tmp_path / "b.csv").read_bytes()
    assert (tmp_path / "a.json").read_bytes() == (tmp_path / "b.json").read_bytes()


def test_usage_error() -> None:
    with pytest.raises(rfe.UsageError) as e:
        rfe.replay(ROOT / "scenarios/cruise.csv", real="q32")
    assert e.value.exit_code == 2 and "--real must be" in e.value.message
    assert isinstance(e.value, ValueError)
    with pytest.raises(TypeError):
        rfe.replay(ROOT / "scenarios/cruise.csv", reel="q31")  # type: ignore[call-arg]


def test_invalid_parameter_raises_param_error() -> None:
    with pytest.raises(rfe.ParamError) as e:
        rfe.replay(ROOT / "scenarios/cruise.csv", params={"mu0": -3.0})
    assert e.value.status == 19 and e.value.exit_code == 1
    assert "invalid parameter mu0" in e.value.message and e.value.line == 1


def test_q31_format_overflow_raises_range_error() -> None:
    with pytest.raises(rfe.RangeError) as e:
        rfe.replay(ROOT / "scenarios/cruise.csv", params={"m": 1e9}, real="q31")
    assert e.value.status == 18


def test_strict_bad_cell_raises_nonfinite_error() -> None:
    sensor = rfe.read_log(ROOT / "scenarios/brake_in_turn.csv")
    sensor.loc[5, "ax"] = math.nan
    with pytest.raises(rfe.NonFiniteError) as e:
        rfe.replay(sensor, strict=True)
    assert e.value.status == 17 and (e.value.line, e.value.col) == (50, 7)
    # without --strict the estimator rejects that sample with the same status, with a note
    with pytest.warns(rfe.RfeWarning, match="bad cells"):
        est = rfe.replay(sensor)
    assert est["status"].iloc[5] == 17


def test_missing_file_raises_input_error() -> None:
    with pytest.raises(rfe.InputError) as e:
        rfe.replay(ROOT / "scenarios/does_not_exist.csv")
    assert e.value.status is None and "cannot open" in e.value.message


def test_run_releases_the_gil(tmp_path: Path) -> None:
    """The C run holds no GIL: it reads its log from a pipe that only this thread writes,
    after the run started. Were the GIL held during the C call, the writer could never run
    and the run never end: faulthandler's watchdog (a C thread, no GIL) then ends the
    process with the threads' tracebacks, so the hang is a failure, never a pass."""
    log = (ROOT / "scenarios/paper_high_mu_brake.csv").read_bytes()
    fifo = tmp_path / "log.csv"
    os.mkfifo(fifo)
    result: dict[str, object] = {}

    def work() -> None:
        try:
            result["df"] = rfe.replay(fifo, real="double", quiet=True)
        except BaseException as exc:  # noqa: BLE001 (reported below)
            result["error"] = exc

    faulthandler.dump_traceback_later(300, exit=True)
    worker = threading.Thread(target=work, daemon=True)
    worker.start()
    with open(fifo, "wb") as f:  # blocks until the C reader opened the pipe
        for i in range(0, len(log), 4096):
            f.write(log[i:i + 4096])
            f.flush()
    worker.join(timeout=240)
    faulthandler.cancel_dump_traceback_later()
    assert not worker.is_alive(), "the C run never finished"
    assert "error" not in result, result.get("error")
    want = rfe.replay(ROOT / "scenarios/paper_high_mu_brake.csv", real="double", quiet=True)
    assert np.array_equal(result["df"].to_numpy(np.float64).view(np.int64),  # type: ignore[union-attr]
                          want.to_numpy(np.float64).view(np.int64))


def test_plot_estimates_draws_what_the_script_draws(tmp_path: Path) -> None:
    """rfe.plot_estimates and scripts/tools/plot_estimates.py draw the same figure (one
    drawing code, python/rfe/plot.py): the same axes, lines and their data, for a log with
    truth and two estimates."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    sys.path.insert(0, str(ROOT / "scripts" / "tools"))
    import plot_estimates as script

    log = ROOT / "scenarios/brake_in_turn.csv"
    a = rfe.replay(log, real="double", quiet=True, out=tmp_path / "a.csv")
    b = rfe.replay(log, real="q31", quiet=True, out=tmp_path / "b.csv")
    got = rfe.plot_estimates(log, [a, b], labels=["double", "q31"], out=tmp_path / "p.png")
    want = script.figure(log, [tmp_path / "a.csv", tmp_path / "b.csv"], ["double", "q31"])
    assert (tmp_path / "p.png").stat().st_size > 0
    assert got._suptitle.get_text() == want._suptitle.get_text()
    assert len(got.axes) == len(want.axes)
    for ga, wa in zip(got.axes, want.axes):
        assert ga.get_title() == wa.get_title()
        assert [ln.get_label() for ln in ga.lines] == [ln.get_label() for ln in wa.lines]
        for gl, wl in zip(ga.lines, wa.lines):
            assert np.array_equal(np.asarray(gl.get_xydata()), np.asarray(wl.get_xydata()))
    plt.close("all")
