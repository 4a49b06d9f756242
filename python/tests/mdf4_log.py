"""An MDF4 recording written by asammdf from a bundled scenario log, and its mapping file
(docs/PYTHON.md "MDF4 input"): a car logger's channel names, two rates (10 ms, 20 ms) and
units (steering-wheel angle in degrees with a steering ratio, wheel speeds in km/h, deg/s,
accelerations in g with the lateral one in the SAE sense).

    python python/tests/mdf4_log.py scenarios/brake_in_turn.csv OUT.mf4 OUT.toml

The test (test_mdf4.py) generates it in a temporary folder; nothing binary is committed.
"""
from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

STEER_RATIO = 15.8
R = 0.325          # the rolling radius the km/h wheel speeds are written with (and read back)
G = 9.80665        # DATA.md's g
# column -> (channel, unit, scale, period in samples of the scenario (1: 10 ms, 2: 20 ms),
#            SI value -> channel value)
CHANNELS = {
    "yaw_rate": ("YawRate", "deg/s", None, 1, lambda x: np.degrees(x)),
    "ax": ("LongAccel", "g", None, 1, lambda x: x / G),
    "ay": ("LatAccel", "g", -1.0, 1, lambda x: -x / G),
    "omega_fl": ("WheelSpeed_FL", "km/h", None, 1, lambda x: x * R * 3.6),
    "omega_fr": ("WheelSpeed_FR", "km/h", None, 1, lambda x: x * R * 3.6),
    "omega_rl": ("WheelSpeed_RL", "km/h", None, 1, lambda x: x * R * 3.6),
    "omega_rr": ("WheelSpeed_RR", "km/h", None, 1, lambda x: x * R * 3.6),
    "swa": ("SAS_Angle", "deg", None, 2, None),  # from delta, below
    "vx": ("VehSpd_Long", "km/h", None, 2, lambda x: x * 3.6),
    "vy": ("VehSpd_Lat", "m/s", None, 2, lambda x: x),
    "yaw_acc": ("YawAccel", "deg/s^2", None, 1, lambda x: np.degrees(x)),
    "mu_fl": ("Ref_Mu_FL", "1", None, 2, lambda x: x),
    "mu_fr": ("Ref_Mu_FR", "1", None, 2, lambda x: x),
    "mu_rl": ("Ref_Mu_RL", "1", None, 2, lambda x: x),
    "mu_rr": ("Ref_Mu_RR", "1", None, 2, lambda x: x),
}
# mapped, optional, and not recorded: skipped and reported
ABSENT_OPTIONAL = {"p_fl": ("BrkPrs_FL", "bar")}


def channel_values(log, every: int | None = None) -> dict[str, tuple[str, str, np.ndarray,
                                                                   np.ndarray]]:
    """column -> (channel, unit, time stamps, values) of the recording of a sensor log;
    ``every``: one rate for all channels (in samples of the log) instead of CHANNELS'."""
    t = log["t"].to_numpy(dtype=np.float64)
    out = {}
    for col, (name, unit, _, own, fn) in CHANNELS.items():
        if col == "swa":
            x = np.degrees(log["delta"].to_numpy(dtype=np.float64) * STEER_RATIO)
        else:
            x = fn(log[col].to_numpy(dtype=np.float64))
        k = every or own
        out[col] = (name, unit, t[::k], np.asarray(x, dtype=np.float64)[::k])
    return out


def mapping_text(dt: float = 0.01) -> str:
    lines = [f"dt = {dt!r}", "", "[meta]", f"obs_steer_ratio = {STEER_RATIO!r}", f"R = {R!r}", ""]
    for col, (name, unit, scale, _, _) in CHANNELS.items():
        lines += [f"[columns.{col}]", f'channel = "{name}"', f'unit = "{unit}"']
        if scale is not None:
            lines.append(f"scale = {scale!r}")
        if col.startswith("mu_"):
            lines.append("optional = true")
        lines.append("")
    for col, (name, unit) in ABSENT_OPTIONAL.items():
        lines += [f"[columns.{col}]", f'channel = "{name}"', f'unit = "{unit}"',
                  "optional = true", ""]
    return "\n".join(lines)


def write_mdf(channels: dict[str, tuple[str, str, np.ndarray, np.ndarray]], path) -> None:
    """One channel group per rate, as a logger records them."""
    from asammdf import MDF, Signal
    groups: dict[bytes, list] = {}
    for name, unit, t, x in channels.values():
        groups.setdefault(t.tobytes(), []).append(
            Signal(samples=x, timestamps=t, name=name, unit=unit))
    mdf = MDF(version="4.10")
    for sigs in groups.values():
        mdf.append(sigs, comment="rfe test recording")
    mdf.save(path, overwrite=True)
    mdf.close()


def main(argv: list[str]) -> int:
    import rfe
    scenario, out, mapping = argv
    log = rfe.read_log(scenario)
    write_mdf(channel_values(log), Path(out))
    Path(mapping).write_text(mapping_text(), encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
