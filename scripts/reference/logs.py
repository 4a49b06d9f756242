"""Sensor-log reader and estimate-log writer (DATA.md).

CSV, comma separated, '#' metadata lines (``# key = value``) before one header row; columns
are looked up by name, in any order, extra columns ignored.  Numbers are parsed with Python's
float() (correctly rounded, like C strtod) and written with repr() (shortest round-trip
representation), so a C double build reads exactly the same values.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np

from .model import WHEELS

INPUT_COLUMNS = ("t", "delta", "vx", "vy", "yaw_rate", "yaw_acc", "ax", "ay") + tuple(
    "omega_" + w for w in WHEELS)
TRUTH_COLUMNS = tuple("mu_" + w for w in WHEELS)
ESTIMATE_COLUMNS = (("t",) + tuple("mu_" + w for w in WHEELS) + tuple("sd_" + w for w in WHEELS)
                    + tuple("valid_" + w for w in WHEELS) + ("status",))


class LogError(ValueError):
    """Malformed log file."""


@dataclass
class CsvLog:
    path: str
    meta: dict = field(default_factory=dict)      # metadata key -> value string, file order
    columns: dict = field(default_factory=dict)   # column name -> float64 array

    def __len__(self):
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def col(self, name):
        try:
            return self.columns[name]
        except KeyError:
            raise LogError(f"{self.path}: missing column {name!r}") from None

    def omega(self):
        """Wheel spin speeds, shape (N, 4), order fl, fr, rl, rr."""
        return np.stack([self.col("omega_" + w) for w in WHEELS], axis=-1)

    def truth(self):
        """True friction (N, 4) when the log carries it, else None."""
        if all(c in self.columns for c in TRUTH_COLUMNS):
            return np.stack([self.columns[c] for c in TRUTH_COLUMNS], axis=-1)
        return None


def _parse_meta(line: str):
    body = line.lstrip("#").strip()
    if "=" not in body:
        return None
    key, value = body.split("=", 1)
    return key.strip(), value.strip()


def read_csv_log(path: str, required=INPUT_COLUMNS) -> CsvLog:
    """Read a sensor (or estimate) log: metadata dict and float columns by name."""
    log = CsvLog(path=path)
    header = None
    rows = []
    with open(path, encoding="utf-8") as fh:
        for lineno, line in enumerate(fh, 1):
            s = line.strip()
            if not s:
                continue
            if s.startswith("#"):
                if header is None:
                    kv = _parse_meta(s)
                    if kv is not None and kv[0]:
                        log.meta[kv[0]] = kv[1]
                continue
            cells = [c.strip() for c in s.split(",")]
            if header is None:
                header = cells
                continue
            if len(cells) != len(header):
                raise LogError(f"{path}:{lineno}: {len(cells)} fields, header has {len(header)}")
            try:
                rows.append([float(c) for c in cells])
            except ValueError as exc:
                raise LogError(f"{path}:{lineno}: {exc}") from None
    if header is None:
        raise LogError(f"{path}: no header row")
    data = np.array(rows, dtype=float).reshape(len(rows), len(header))
    for j, name in enumerate(header):
        log.columns[name] = data[:, j].copy()
    for name in required:
        log.col(name)
    return log


def fmt(v) -> str:
    """Float as its shortest round-trip decimal (repr); integers as integers."""
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    return repr(float(v))


def write_estimate_log(path: str, meta: list, t, mu, sd, valid, status):
    """Write an estimate log (DATA.md): metadata lines, header, one row per sample.

    meta: list of (key, value) pairs written as ``# key = value``; floats via repr.
    """
    d = os.path.dirname(path)
    if d:
        os.makedirs(d, exist_ok=True)
    lines = []
    for key, value in meta:
        lines.append(f"# {key} = {fmt(value) if isinstance(value, float) else value}\n")
    lines.append(",".join(ESTIMATE_COLUMNS) + "\n")
    for k in range(len(t)):
        cells = [repr(float(t[k]))]
        cells += [repr(float(v)) for v in mu[k]]
        cells += [repr(float(v)) for v in sd[k]]
        cells += [str(int(v)) for v in valid[k]]
        cells.append(str(int(status[k])))
        lines.append(",".join(cells) + "\n")
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        fh.writelines(lines)
