"""Sensor faults injected into clean sensor logs (the robustness issue).

A fault log is a bundled scenario log (the "clean twin": simulator output plus the default
sensor noise, scenarios/<base>.csv) with one kind of sensor fault applied, deterministically
(numpy Generator(PCG64(seed)) picks the instants).  Every field the fault does not touch
keeps the clean twin's text byte for byte, so the two logs differ exactly where the fault
acts.  Kinds:

    spike   single-sample spikes of +-magnitude (sign drawn) added to one column at `count`
            instants inside `window` (at least MIN_GAP apart): a glitch on ax, ay or the
            yaw rate;
    drop    `count` single rows removed inside `window` (never two adjacent): the logger
            missed a sample, so t jumps by 2 dt there (time-step jitter);
    freeze  one column holds its value at window[0] until window[1] (a wheel-speed channel
            stuck at its last value, then back);
    offset  `magnitude` added to one column from window[0] to window[1] (an accelerometer
            offset: 0.5 m/s^2 is a 3 degree slope or bank, or a mounting error).

The log gets four metadata lines (fault, fault_description, fault_base, fault_seed) after
the clean twin's, and one extra column `fault`: 1 on every row the fault touched (for a
drop: the row after each gap), else 0.  DATA.md readers ignore both.
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np

__all__ = ["Fault", "FAULTS", "MIN_GAP", "read_log", "apply", "fault_text", "file_name"]

MIN_GAP = 0.5  # s, between two spikes or two dropped rows of one log


@dataclass(frozen=True)
class Fault:
    name: str          # fault id, the file name's first part
    base: str          # clean twin, scenarios/<base>.csv
    kind: str          # spike | drop | freeze | offset
    column: str | None
    magnitude: float   # spike: +-size; offset: value added; else unused
    count: int         # spike, drop: number of instants
    window: tuple      # (t0, t1) [s]
    seed: int
    description: str


# The clean twins: Magic Formula truth (the tyre the default preset is judged on), default
# noise. ABS braking on mu 0.3 (estimate valid ~99 % of the time), sine steer on mu 0.4
# (valid ~90 %), cruise (friction unobservable: a fault must not make it look observable).
BRAKE, STEER, CRUISE = "hard_brake_low_mu.mf", "sine_steer_low_mu.mf", "cruise.mf"

# Faults whose samples lie beyond the library's input limits (rfe/config.h RFE_LIMIT_*): the
# C library refuses those samples (RFE_ERR_RANGE, estimate unchanged) while the reference
# has no limits, so they are judged by the robustness tests, not against reference goldens.
REFUSED_BY_LIBRARY = ("spike_ax_beyond_limit",)

FAULTS = [
    Fault("spike_ax", BRAKE, "spike", "ax", 5.0, 8, (1.5, 7.5), 101,
          "8 single-sample spikes of +-5 m/s^2 on ax, 1.5-7.5 s (ABS braking)"),
    Fault("spike_ax", STEER, "spike", "ax", 5.0, 8, (1.0, 9.0), 102,
          "8 single-sample spikes of +-5 m/s^2 on ax, 1-9 s (sine steer)"),
    Fault("spike_ax", CRUISE, "spike", "ax", 5.0, 8, (1.0, 9.0), 103,
          "8 single-sample spikes of +-5 m/s^2 on ax, 1-9 s (cruise, friction unobservable)"),
    Fault("spike_ay", BRAKE, "spike", "ay", 5.0, 8, (1.5, 7.5), 104,
          "8 single-sample spikes of +-5 m/s^2 on ay, 1.5-7.5 s (ABS braking)"),
    Fault("spike_ay", STEER, "spike", "ay", 5.0, 8, (1.0, 9.0), 105,
          "8 single-sample spikes of +-5 m/s^2 on ay, 1-9 s (sine steer)"),
    Fault("spike_yaw_rate", BRAKE, "spike", "yaw_rate", 0.5, 8, (1.5, 7.5), 106,
          "8 single-sample spikes of +-0.5 rad/s on the yaw rate, 1.5-7.5 s (ABS braking)"),
    Fault("spike_yaw_rate", STEER, "spike", "yaw_rate", 0.5, 8, (1.0, 9.0), 107,
          "8 single-sample spikes of +-0.5 rad/s on the yaw rate, 1-9 s (sine steer)"),
    Fault("spike_ax_beyond_limit", BRAKE, "spike", "ax", 60.0, 4, (1.5, 7.5), 108,
          "4 single-sample spikes of +-60 m/s^2 on ax (beyond the 50 m/s^2 input limit), "
          "1.5-7.5 s (ABS braking)"),
    Fault("drop", BRAKE, "drop", None, 0.0, 10, (1.0, 9.0), 109,
          "10 single samples missing (t jumps by 2 dt), 1-9 s (ABS braking)"),
    Fault("drop", STEER, "drop", None, 0.0, 10, (1.0, 9.0), 110,
          "10 single samples missing (t jumps by 2 dt), 1-9 s (sine steer)"),
    Fault("freeze_omega_fl", BRAKE, "freeze", "omega_fl", 0.0, 0, (2.0, 4.0), 111,
          "omega_fl stuck at its value of t = 2 s until 4 s, then back (ABS braking)"),
    Fault("freeze_omega_fl", STEER, "freeze", "omega_fl", 0.0, 0, (2.0, 4.0), 112,
          "omega_fl stuck at its value of t = 2 s until 4 s, then back (sine steer)"),
    Fault("offset_ax", BRAKE, "offset", "ax", 0.5, 0, (0.0, 1e9), 113,
          "ax offset +0.5 m/s^2 for the whole log (a 3 degree slope) (ABS braking)"),
    Fault("offset_ax", CRUISE, "offset", "ax", 0.5, 0, (0.0, 1e9), 114,
          "ax offset +0.5 m/s^2 for the whole log (cruise, friction unobservable)"),
    Fault("offset_ay", STEER, "offset", "ay", 0.5, 0, (0.0, 1e9), 115,
          "ay offset +0.5 m/s^2 for the whole log (a 3 degree bank) (sine steer)"),
]


def file_name(f: Fault) -> str:
    """<fault>.<base>.csv, e.g. spike_ax.hard_brake_low_mu.mf.csv."""
    return f"{f.name}.{f.base}.csv"


def read_log(path):
    """A sensor log as text: (metadata lines, header names, rows as lists of field texts)."""
    meta, header, rows = [], None, []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            line = line.rstrip("\n")
            if header is None:
                if line.startswith("#") or not line.strip():
                    meta.append(line)
                else:
                    header = line.split(",")
            elif line:
                rows.append(line.split(","))
    if header is None:
        raise ValueError(f"{path}: no header")
    return meta, header, rows


def _pick(rng, t, window, count, min_gap, avoid_adjacent=False):
    """count row indices with t inside window, at least min_gap apart (drawn in order)."""
    cand = np.flatnonzero((t >= window[0]) & (t <= window[1]))
    chosen = []
    for _ in range(100000):
        if len(chosen) == count:
            break
        i = int(cand[rng.integers(len(cand))])
        if all(abs(t[i] - t[j]) >= min_gap for j in chosen):
            chosen.append(i)
    if len(chosen) != count:
        raise ValueError("window too small for the fault count")
    return sorted(chosen)


def apply(f: Fault, meta, header, rows):
    """The fault log (meta, header, rows) from the clean twin's text; the twin is unchanged."""
    rng = np.random.Generator(np.random.PCG64(f.seed))
    t = np.array([float(r[header.index("t")]) for r in rows])
    rows = [list(r) for r in rows]
    flag = [0] * len(rows)
    if f.kind == "drop":
        gone = set(_pick(rng, t, f.window, f.count, MIN_GAP))
        out_rows, out_flag = [], []
        for i, r in enumerate(rows):
            if i in gone:
                continue
            out_rows.append(r)
            out_flag.append(1 if (i - 1) in gone else 0)
        rows, flag = out_rows, out_flag
    else:
        c = header.index(f.column)
        if f.kind == "spike":
            for i in _pick(rng, t, f.window, f.count, MIN_GAP):
                sign = 1.0 if rng.integers(2) else -1.0
                rows[i][c] = repr(float(rows[i][c]) + sign * f.magnitude)
                flag[i] = 1
        elif f.kind == "freeze":
            i0 = int(np.flatnonzero(t >= f.window[0])[0])
            for i in np.flatnonzero((t >= f.window[0]) & (t < f.window[1])):
                rows[i][c] = rows[i0][c]
                flag[i] = 1
        elif f.kind == "offset":
            for i in np.flatnonzero((t >= f.window[0]) & (t < f.window[1])):
                rows[i][c] = repr(float(rows[i][c]) + f.magnitude)
                flag[i] = 1
        else:
            raise ValueError(f"unknown fault kind {f.kind!r}")
    meta = list(meta) + [f"# fault = {f.name}", f"# fault_description = {f.description}",
                         f"# fault_base = {f.base}.csv", f"# fault_seed = {f.seed}"]
    header = list(header) + ["fault"]
    rows = [r + [str(flag[i])] for i, r in enumerate(rows)]
    return meta, header, rows


def fault_text(meta, header, rows) -> str:
    return "\n".join(list(meta) + [",".join(header)] + [",".join(r) for r in rows]) + "\n"


def make(f: Fault, scenarios_dir: str) -> str:
    """The text of one fault log, from scenarios_dir/<base>.csv."""
    meta, header, rows = read_log(os.path.join(scenarios_dir, f.base + ".csv"))
    return fault_text(*apply(f, meta, header, rows))
