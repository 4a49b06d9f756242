"""Rewrite observer scenarios in the format of a recorded production car's log (DATA.md
"Units, scales and names of a recorded log"), to test that the library does not assume the
simulator's conventions.

Usage (from the repository root):

    .venv/bin/python scripts/data/make_car_format_logs.py [--src scenarios/observer]
        [--out scenarios/car_format]

Each output log is its source scenario as a logger on a car's CAN bus would have written it:
- 50 Hz (every second 100 Hz sample), time stamps in ms with a jitter of up to +-JITTER_MS
  (the samples stay where they were taken; only the stamps move, as a logger's receive
  time does), and no `dt` metadata;
- the steering-wheel angle in degrees (delta times STEER_RATIO), declared with
  `obs_steer_ratio`;
- yaw rate in deg/s, accelerations in g with ay in the SAE sense (positive to the right,
  `scale_ay = -1`), wheel speeds as circumferential speeds in km/h (omega times R), brake
  pressures in bar, drive torques in N m;
- the values quantised to the signal resolutions of a CAN database (RESOLUTION);
- vendor column names (`column_<name>` metadata), and an engine-speed column the library
  does not read.
The truth columns (mu_*, vx_true, vy_true, beta_true, yaw_acc_true) stay SI, for scoring.
Deterministic: the jitter comes from a fixed seed per log.
"""

from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np

sys.path[:0] = [os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]
from reference import logs  # noqa: E402

SOURCES = ("sine_dwell_mu09", "abs_brake_mu02", "dlc_mu035", "abs_brake_split_mu")
STEER_RATIO = 15.8
JITTER_MS = 3.0  # below half the 20 ms period: the stamps stay in order
WHEELS = ("fl", "fr", "rl", "rr")
W_UP = ("FL", "FR", "RL", "RR")
# Signal resolutions of a typical chassis CAN database, in the log's units.
RESOLUTION = {"swa": 0.1, "yaw": 0.01, "acc": 0.001, "wheel": 0.01, "p": 0.1, "torque": 1.0}
# vendor name, library name, unit, scale
CHANNELS = [("Time_ms", "t", "ms", None), ("SteeringWheelAngle", "swa", "deg", None),
            ("YawRate", "yaw_rate", "deg/s", None), ("LongAccel", "ax", "g", None),
            ("LatAccel_SAE", "ay", "g", -1.0)] + \
           [(f"WheelSpeed_{u}", f"omega_{w}", "km/h", None) for w, u in zip(WHEELS, W_UP)] + \
           [(f"BrakePressure_{u}", f"p_{w}", "bar", None) for w, u in zip(WHEELS, W_UP)] + \
           [(f"DriveTorque_{u}", f"torque_{w}", None, None) for w, u in zip(WHEELS, W_UP)]
TRUTH = tuple(f"mu_{w}" for w in WHEELS) + ("vx_true", "vy_true", "beta_true", "yaw_acc_true")
# The log's vehicle metadata that stays (a car's calibration); the simulator's own keys go.
KEEP_META = ("m", "Lf", "Lr", "Bf", "Br", "R", "J", "hg", "g", "cx", "cy", "eps")


def quantise(x, step):
    return np.round(np.asarray(x) / step) * step


def convert(path, seed):
    """(metadata lines, header, rows) of the car-format version of one scenario."""
    log = logs.read_csv_log(path, required=("t", "delta", "yaw_rate", "ax", "ay"))
    c, meta = log.columns, dict(log.meta)
    R = float(meta["R"])
    idx = np.arange(0, len(c["t"]), 2)
    rng = np.random.default_rng(seed)
    stamp = c["t"][idx] * 1000.0 + rng.uniform(-JITTER_MS, JITTER_MS, len(idx))
    stamp = np.round(stamp - stamp[0] + 1000.0 * c["t"][0], 1)  # a logger's 0.1 ms resolution
    g0 = 9.80665
    vals = {"t": stamp,
            "swa": quantise(np.degrees(c["delta"][idx] * STEER_RATIO), RESOLUTION["swa"]),
            "yaw_rate": quantise(np.degrees(c["yaw_rate"][idx]), RESOLUTION["yaw"]),
            "ax": quantise(c["ax"][idx] / g0, RESOLUTION["acc"]),
            "ay": quantise(-c["ay"][idx] / g0, RESOLUTION["acc"])}
    for w in WHEELS:
        vals[f"omega_{w}"] = quantise(c[f"omega_{w}"][idx] * R * 3.6, RESOLUTION["wheel"])
        vals[f"p_{w}"] = quantise(c[f"p_{w}"][idx] * 10.0, RESOLUTION["p"])
        vals[f"torque_{w}"] = quantise(c[f"torque_{w}"][idx], RESOLUTION["torque"])
    lines = [f"scenario = {meta['scenario']}_car_format",
             f"description = {os.path.basename(path)} as a production car's logger writes it "
             f"(scripts/data/make_car_format_logs.py): 50 Hz, stamps in ms with up to "
             f"+-{JITTER_MS:g} ms jitter, steering-wheel angle in deg (ratio {STEER_RATIO:g}), "
             f"deg/s, g (ay SAE), wheel speeds km/h, bar, vendor names",
             f"source = {os.path.basename(path)}", f"seed = {seed}",
             f"truth_tyre = {meta.get('truth_tyre', '?')}",
             f"drive_layout = {meta.get('drive_layout', '?')}",
             f"obs_steer_ratio = {STEER_RATIO!r}"]
    lines += [f"{k} = {meta[k]}" for k in KEEP_META if k in meta]
    for vendor, name, unit, scale in CHANNELS:
        lines.append(f"column_{name} = {vendor}")
        if unit is not None:
            lines.append(f"unit_{name} = {unit}")
        if scale is not None:
            lines.append(f"scale_{name} = {scale!r}")
    header = [v for v, _, _, _ in CHANNELS] + ["EngineSpeed_rpm"] + list(TRUTH)
    engine = np.round(np.maximum(800.0, c["omega_fl"][idx] * 30.0 / math.pi * 3.2))
    cols = [vals[n] for _, n, _, _ in CHANNELS] + [engine] + [c[k][idx] for k in TRUTH]
    return lines, header, zip(*cols)


def fmt(x):
    x = float(x)
    return repr(round(x, 6)) if abs(x) < 1e6 else repr(x)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--src", default="scenarios/observer")
    ap.add_argument("--out", default="scenarios/car_format")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    for seed, name in enumerate(SOURCES, start=1):
        src = os.path.join(a.src, name + ".csv")
        lines, header, rows = convert(src, seed)
        dst = os.path.join(a.out, name + ".csv")
        with open(dst, "w", encoding="utf-8", newline="\n") as fh:
            fh.writelines(f"# {ln}\n" for ln in lines)
            fh.write(",".join(header) + "\n")
            for r in rows:
                fh.write(",".join(fmt(x) for x in r) + "\n")
        print(f"[car-format] {src} -> {dst}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
