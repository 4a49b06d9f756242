"""Parquet input and output (docs/PYTHON.md "Parquet"): a log's doubles are stored as
doubles, so a Parquet sensor log replays bit for bit as its CSV, and an estimate log written
as Parquet reads back as the DataFrame replay returns."""
from __future__ import annotations

import warnings
from pathlib import Path

import pandas as pd
import pytest

import rfe

ROOT = Path(__file__).resolve().parents[2]
LOGS = ["scenarios/brake_in_turn.csv", "scenarios/car_format/dlc_mu035.csv"]


def quiet_replay(source, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rfe.RfeWarning)
        return rfe.replay(source, **kw)


@pytest.mark.parametrize("log", LOGS)
def test_parquet_sensor_log_replays_as_its_csv(log, tmp_path):
    sensor = rfe.read_log(ROOT / log)
    rfe.write_parquet(sensor, tmp_path / "log.parquet")
    back = rfe.read_parquet(tmp_path / "log.parquet")
    pd.testing.assert_frame_equal(back, sensor, check_exact=True)
    assert back.attrs["meta"] == sensor.attrs["meta"]
    est = quiet_replay(tmp_path / "log.parquet", real="double")
    ref = quiet_replay(ROOT / log, real="double")
    pd.testing.assert_frame_equal(est, ref, check_exact=True)


def test_estimates_written_as_parquet(tmp_path):
    est = quiet_replay(ROOT / LOGS[0], real="q31", out=tmp_path / "est.parquet")
    back = rfe.read_parquet(tmp_path / "est.parquet")
    pd.testing.assert_frame_equal(back, est, check_exact=True)
    assert back.attrs["meta"] == est.attrs["meta"] and back.attrs["meta"]["real"] == "q31"
    assert back["status"].dtype == est["status"].dtype == "int64"


def test_unreadable_parquet_raises(tmp_path):
    (tmp_path / "bad.parquet").write_text("not parquet", encoding="utf-8")
    with pytest.raises(rfe.InputError, match="Parquet"):
        rfe.replay(tmp_path / "bad.parquet")
