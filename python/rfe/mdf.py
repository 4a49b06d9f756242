"""rfe.read_mdf: an MDF4 recording as a sensor log (docs/PYTHON.md "MDF4 input").

A mapping file (TOML) names, for each sensor-log column of docs/spec/DATA.md, the MDF
channel that holds it, its unit and its scale and offset, and gives the vehicle's metadata
(the steering ratio, ...). The channels, each at its own rate, are resampled onto one uniform
grid, the estimator's step. No unit is converted here: the units, scales and offsets become
the log's ``unit_*``/``scale_*``/``offset_*`` metadata (DATA.md "Units, scales and names of a
recorded log"), which mu_replay's C reader applies when the frame is replayed, so units are
converted once, in one place, with the same words and the same errors as a CSV's.

Mapping file::

    dt = 0.01                      # the grid step in s (default: the fastest channel's period)

    [meta]                         # written as the log's "# key = value" metadata
    obs_steer_ratio = 15.8

    [columns.swa]                  # a DATA.md column
    channel = "SAS_Angle"          # the MDF channel's name
    unit = "deg"                   # a DATA.md unit word (default: the channel's own unit,
                                   # or SI when it has none)
    scale = 1.0                    # optional, SI = factor(unit) * (scale * value + offset)
    offset = 0.0                   # optional
    method = "linear"              # optional: "linear" or "previous" (zero-order hold)
    optional = false               # optional: true = skipped, and reported, when absent
"""
from __future__ import annotations

import math
import os
import sys
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from . import errors

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10 has no tomllib
    tomllib = None

# Columns that hold a discrete state: resampled by holding the last value (zero-order hold),
# since a gear of 2.5 or a brake flag of 0.5 means nothing. Every other column is continuous
# and linearly interpolated.
DISCRETE_COLUMNS = frozenset({"gear", "brake"})
METHODS = ("linear", "previous")
_COLUMN_KEYS = {"channel", "unit", "scale", "offset", "method", "optional"}


class MissingChannelError(errors.InputError):
    """A channel the mapping requires is not in the MDF file; ``missing`` lists every one
    as (column, channel) pairs."""

    def __init__(self, missing: list[tuple[str, str]], file: str | None = None) -> None:
        names = ", ".join(f"{ch} (for {col})" for col, ch in missing)
        super().__init__(f"missing MDF channel{'s' if len(missing) > 1 else ''}: {names}",
                         file=file)
        self.missing = missing


class MappingError(errors.InputError):
    """A malformed mapping file (an unknown key, a wrong type, a bad method, a bad dt)."""


def load_mapping(mapping: str | os.PathLike | Mapping[str, Any]) -> dict[str, Any]:
    """Reads and checks a mapping (a TOML file, or the same structure as a dict)."""
    where = None
    if not isinstance(mapping, Mapping):
        where = os.fspath(mapping)
        if tomllib is None:  # pragma: no cover
            raise MappingError("a mapping file needs Python 3.11 (tomllib); pass a dict",
                               file=where)
        try:
            with open(where, "rb") as f:
                mapping = tomllib.load(f)
        except OSError as e:
            raise errors.InputError(f"cannot read the mapping: {e.strerror}", file=where) from e
        except tomllib.TOMLDecodeError as e:
            raise MappingError(f"not TOML: {e}", file=where) from e
    unknown = set(mapping) - {"dt", "meta", "columns"}
    if unknown:
        raise MappingError(f"unknown mapping key(s): {', '.join(sorted(unknown))}", file=where)
    dt = mapping.get("dt")
    if dt is not None and (isinstance(dt, bool) or not isinstance(dt, (int, float))
                           or not math.isfinite(dt) or dt <= 0):
        raise MappingError(f"dt must be a positive number of seconds, not {dt!r}", file=where)
    columns = mapping.get("columns")
    if not isinstance(columns, Mapping) or not columns:
        raise MappingError("the mapping names no column ([columns.<name>] tables)", file=where)
    if "t" in columns:
        raise MappingError("t is the grid's time, not a channel: remove [columns.t]",
                           file=where)
    checked: dict[str, dict[str, Any]] = {}
    for col, spec in columns.items():
        if isinstance(spec, str):
            spec = {"channel": spec}
        if not isinstance(spec, Mapping) or not isinstance(spec.get("channel"), str):
            raise MappingError(f"column {col}: needs channel = \"<MDF channel name>\"",
                               file=where)
        bad = set(spec) - _COLUMN_KEYS
        if bad:
            raise MappingError(f"column {col}: unknown key(s) {', '.join(sorted(bad))}",
                               file=where)
        method = spec.get("method", "previous" if col in DISCRETE_COLUMNS else "linear")
        if method not in METHODS:
            raise MappingError(f"column {col}: method {method!r} is not one of {METHODS}",
                               file=where)
        for key in ("scale", "offset"):
            v = spec.get(key)
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))):
                raise MappingError(f"column {col}: {key} must be a number", file=where)
        unit = spec.get("unit")
        if unit is not None and not isinstance(unit, str):
            raise MappingError(f"column {col}: unit must be a unit word", file=where)
        checked[col] = dict(channel=spec["channel"], unit=unit, scale=spec.get("scale"),
                            offset=spec.get("offset"), method=method,
                            optional=bool(spec.get("optional", False)))
    meta = mapping.get("meta", {})
    if not isinstance(meta, Mapping):
        raise MappingError("[meta] must be a table of key = value", file=where)
    return {"dt": dt, "meta": dict(meta), "columns": checked}


def resample(t_grid: np.ndarray, t: np.ndarray, x: np.ndarray, method: str) -> np.ndarray:
    """One channel's samples (t, x) at the grid's times.

    ``linear``: the straight line between the two samples around each grid time (numpy's
    ``interp``; a grid time equal to a sample time gives that sample exactly).
    ``previous``: the last sample at or before each grid time (zero-order hold).
    The grid must lie within [t[0], t[-1]] (read_mdf makes it so)."""
    t = np.asarray(t, dtype=np.float64)
    x = np.asarray(x, dtype=np.float64)
    if method == "linear":
        return np.interp(t_grid, t, x)
    if method == "previous":
        return x[np.searchsorted(t, t_grid, side="right") - 1]
    raise ValueError(f"method {method!r} is not one of {METHODS}")


def read_mdf(path: str | os.PathLike, mapping: str | os.PathLike | Mapping[str, Any],
             *, dt: float | None = None) -> pd.DataFrame:
    """Reads an MDF4 file's channels through a mapping as a DATA.md sensor log.

    Args:
        path: the MDF4 (.mf4) file.
        mapping: the mapping file (TOML, module docstring) or its content as a dict.
        dt: the grid step in s; overrides the mapping's ``dt``; default: the median period
            of the fastest channel.

    Returns:
        A DataFrame: ``t`` (s, the uniform grid) and each mapped column found, in the
        channel's own unit, resampled onto the grid; ``attrs["meta"]``: the mapping's
        ``[meta]`` and each column's ``unit_*``/``scale_*``/``offset_*`` key, which the C
        reader converts to SI when the frame is replayed (a wrong unit word is refused
        there, as in a CSV); ``attrs["skipped"]``: the optional columns whose channel is
        absent, as (column, channel).

    The grid runs from the latest first sample to the earliest last sample of the channels
    used, in steps of dt: t_k = t_start + k * dt.

    Raises:
        MissingChannelError: required channels absent (every one is listed).
        MappingError: a malformed mapping.
        InputError: the file cannot be read, a channel has fewer than two samples or
            unordered time stamps, or the channels share no time span.
    """
    try:
        from asammdf import MDF
    except ImportError as e:  # pragma: no cover
        raise ImportError("rfe.read_mdf needs asammdf: pip install rfe[mdf]") from e
    spec = load_mapping(mapping)
    where = os.fspath(path)
    if not Path(where).is_file():
        raise errors.InputError("cannot open the MDF file: no such file", file=where)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mdf = MDF(where)
    try:
        present = set(mdf.channels_db)
        missing = [(c, s["channel"]) for c, s in spec["columns"].items()
                   if s["channel"] not in present and not s["optional"]]
        if missing:
            raise MissingChannelError(missing, file=where)
        skipped = [(c, s["channel"]) for c, s in spec["columns"].items()
                   if s["channel"] not in present]
        signals: dict[str, tuple[np.ndarray, np.ndarray, str]] = {}
        for col, s in spec["columns"].items():
            if s["channel"] in present:
                sig = mdf.get(s["channel"], raw=False)
                signals[col] = (np.asarray(sig.timestamps, dtype=np.float64),
                                np.asarray(sig.samples, dtype=np.float64), str(sig.unit or ""))
    finally:
        mdf.close()
    for col, (t, _, _) in signals.items():
        if t.size < 2 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
            raise errors.InputError(f"channel {spec['columns'][col]['channel']} (for {col}):"
                                    " needs two or more samples with increasing time stamps",
                                    file=where)
    step = dt if dt is not None else spec["dt"]
    if step is None:  # the median period, rid of the time stamps' rounding (12 digits)
        step = float(f"{min(float(np.median(np.diff(t))) for t, _, _ in signals.values()):.12g}")
    t_start = max(float(t[0]) for t, _, _ in signals.values())
    t_end = min(float(t[-1]) for t, _, _ in signals.values())
    if not t_end > t_start:
        raise errors.InputError("the channels share no time span", file=where)
    # a grid time past t_end by the rounding of k * step only (1e-9 of a step) is kept: the
    # channels' last samples stand there
    n = int(math.floor((t_end - t_start) / step + 1e-9)) + 1
    grid = t_start + np.arange(n, dtype=np.float64) * step
    data: dict[str, np.ndarray] = {"t": grid}
    meta: dict[str, Any] = dict(spec["meta"])
    for col, (t, x, mdf_unit) in signals.items():
        s = spec["columns"][col]
        data[col] = resample(grid, t, x, s["method"])
        unit = s["unit"] if s["unit"] is not None else mdf_unit
        if unit:
            meta[f"unit_{col}"] = unit
        if s["scale"] is not None:
            meta[f"scale_{col}"] = float(s["scale"])
        if s["offset"] is not None:
            meta[f"offset_{col}"] = float(s["offset"])
    df = pd.DataFrame(data)
    df.attrs["meta"] = meta
    df.attrs["skipped"] = skipped
    if skipped:
        warnings.warn("optional MDF channel(s) absent, column(s) skipped: " +
                      ", ".join(f"{ch} (for {col})" for col, ch in skipped),
                      errors.RfeWarning, stacklevel=2)
    return df
