"""Tests of the car-format logs (scripts/data/make_car_format_logs.py, DATA.md "Units,
scales and names of a recorded log"):

1. the committed logs are what the generator writes (metadata and header exactly, numbers
   within one signal resolution: a value on a rounding boundary may fall either way when an
   ulp differs between machines);
2. read back by DATA.md's rule (SI = factor(unit) * (scale * value + offset), names through
   column_*) with the Python tools' one reader of it (reference/log_units.py, independent
   of the generator), each log gives its source scenario's SI signals at the kept rows,
   within half a signal resolution (the quantisation) in SI.
"""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = [HERE, os.path.dirname(HERE)]
import make_car_format_logs as gen  # noqa: E402
from reference import log_units, logs  # noqa: E402

OUT = os.path.join(ROOT, "scenarios", "car_format")
SRC = os.path.join(ROOT, "scenarios", "observer")
# DATA.md's unit words and their factors to SI (each word names one unit), for the tolerances.
FACTOR = {word: f for units in log_units.UNITS.values() for word, f in units.items()}


def read_raw(path):
    """(metadata lines, header, float rows) as text and numbers, no interpretation."""
    meta, rows, header = [], [], None
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            if line.startswith("#"):
                meta.append(line)
            elif header is None:
                header = line.rstrip("\n").split(",")
            else:
                rows.append([float(x) for x in line.split(",")])
    return meta, header, np.array(rows)


def step_of(vendor):
    """The signal resolution of a vendor column, in the log's units (0 = not quantised)."""
    kinds = {"SteeringWheelAngle": "swa", "YawRate": "yaw", "LongAccel": "acc",
             "LatAccel_SAE": "acc", "Time_ms": None}
    for prefix, kind in (("WheelSpeed_", "wheel"), ("BrakePressure_", "p"),
                         ("DriveTorque_", "torque")):
        if vendor.startswith(prefix):
            return gen.RESOLUTION[kind]
    kind = kinds.get(vendor)
    return gen.RESOLUTION[kind] if kind else 0.0


# REQ-CSV-005
@pytest.mark.parametrize("name", gen.SOURCES)
def test_committed_logs_are_the_generator_s(name, tmp_path):
    gen.main(["--src", SRC, "--out", str(tmp_path)])
    m0, h0, r0 = read_raw(os.path.join(OUT, name + ".csv"))
    m1, h1, r1 = read_raw(os.path.join(tmp_path, name + ".csv"))
    assert m0 == m1 and h0 == h1 and r0.shape == r1.shape
    for j, vendor in enumerate(h0):
        # one resolution step for a boundary flip; 1e-6 for the 6-decimal text of the rest
        tol = max(step_of(vendor), 1e-6) * 1.0001
        assert np.max(np.abs(r0[:, j] - r1[:, j])) <= tol, vendor


# REQ-CSV-005
@pytest.mark.parametrize("name", gen.SOURCES)
def test_read_back_by_data_md_gives_the_source(name):
    path = os.path.join(OUT, name + ".csv")
    meta_lines, header, rows = read_raw(path)
    meta = dict(ln[1:].strip().split(" = ", 1) for ln in meta_lines if " = " in ln)
    src = logs.read_csv_log(os.path.join(SRC, name + ".csv"), required=()).columns
    idx = np.arange(0, len(src["t"]), 2)
    ratio = float(meta["obs_steer_ratio"])
    R = float(meta["R"])
    cols = log_units.to_si(meta, {h: rows[:, j] for j, h in enumerate(header)}, where=path)

    def si(column):
        return np.asarray(cols[column])

    def check(got, want, half_step_si):
        assert np.max(np.abs(got - want)) <= half_step_si * 1.0001 + 1e-9

    # time: the stamps move by at most the jitter (and the 0.1 ms stamp resolution)
    check(si("t") - si("t")[0], src["t"][idx] - src["t"][0], gen.JITTER_MS * 2e-3 + 0.05e-3)
    check(si("swa") / ratio, src["delta"][idx], gen.RESOLUTION["swa"] / 2 * FACTOR["deg"] / ratio)
    check(si("yaw_rate"), src["yaw_rate"][idx], gen.RESOLUTION["yaw"] / 2 * FACTOR["deg/s"])
    check(si("ax"), src["ax"][idx], gen.RESOLUTION["acc"] / 2 * FACTOR["g"])
    check(si("ay"), src["ay"][idx], gen.RESOLUTION["acc"] / 2 * FACTOR["g"])
    for w in gen.WHEELS:
        check(si("omega_" + w), src["omega_" + w][idx],
              gen.RESOLUTION["wheel"] / 2 * FACTOR["km/h"] / R)
        check(si("p_" + w), src["p_" + w][idx], gen.RESOLUTION["p"] / 2 * FACTOR["bar"])
    assert "dt" not in meta  # the period must come from the stamps
