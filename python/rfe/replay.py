"""rfe.replay, rfe.metrics and rfe.Estimator: mu_replay's run from Python.

A replay is one call of mu_replay's C main (rfe.cli) with the options as its flags, the
estimate log written by the C writer and read back exactly (each value is written as the
shortest text that reads back as the same double, and read with a correctly rounded parser),
so a DataFrame holds what ``mu_replay`` writes, bit for bit, in float, double and q31.
Estimator.run and .step on columns in memory take no file: rfe.inmem.
"""
from __future__ import annotations

import csv
import json
import math
import os
import tempfile
import warnings
from collections.abc import Mapping
from pathlib import Path
from typing import Any, Literal, Union

import numpy as np
import pandas as pd

from . import cli, errors, parquet
from ._rfe import ffi, lib

Source = Union[str, os.PathLike, pd.DataFrame]
Real = Literal["float", "double", "q31"]

STATUS_TEXT: dict[int, str] = {
    s: ffi.string(lib.rfe_py_status_str(s)).decode() for s in range(32)}

# keyword -> mu_replay flag; None = the CLI's default (the flag is not given).
_VALUE_OPTIONS = {"preset": "--preset", "filter": "--filter", "tyre": "--tyre",
                  "real": "--real", "velocity": "--velocity", "mass_grade": "--mass-grade",
                  "tyre_id": "--tyre-id", "mass_grade_vehicle": "--mass-grade-vehicle"}
_FLAG_OPTIONS = {"strict": "--strict", "require_params": "--require-params", "quiet": "--quiet"}


def _fmt(v: Any) -> str:
    """A cell or parameter value as text that reads back as the same double."""
    if isinstance(v, (bool, np.bool_)):
        return "1" if v else "0"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        f = float(v)
        return repr(f) if math.isfinite(f) else ("nan" if math.isnan(f) else
                                                 ("inf" if f > 0 else "-inf"))
    return str(v)


def write_log(df: pd.DataFrame, path: str | os.PathLike) -> None:
    """Writes a DataFrame as a DATA.md sensor log: ``df.attrs["meta"]`` (a mapping) as
    ``# key = value`` lines, the header, one row per sample; every number in the shortest
    text that reads back as the same double (NaN as ``nan``)."""
    meta = df.attrs.get("meta", {}) or {}
    with open(path, "w", encoding="utf-8", newline="\n") as f:
        for k, v in meta.items():
            f.write(f"# {k} = {_fmt(v)}\n")
        f.write(",".join(str(c) for c in df.columns) + "\n")
        cols = [df[c].to_numpy() for c in df.columns]
        for i in range(len(df)):
            f.write(",".join(_fmt(col[i]) for col in cols) + "\n")


def read_log(path: str | os.PathLike) -> pd.DataFrame:
    """Reads a DATA.md CSV (sensor or estimate log) as it is written: the ``# key = value``
    metadata into ``attrs["meta"]`` (strings), each column as int64 when every cell is an
    integer, else float64, each number correctly rounded (numpy's parser, or float()), so the
    shortest-round-trip text of an estimate log gives back its doubles bit for bit (an
    empty cell is NaN). No unit conversion: a recorded car's log keeps its unit_*/scale_*
    keys, which the C reader applies when the frame is replayed."""
    meta: dict[str, str] = {}
    with open(path, encoding="utf-8", newline="") as f:
        lines = iter(f)
        header = ""
        for line in lines:
            if line.startswith("#"):
                key, sep, value = line[1:].partition("=")
                if sep:
                    meta[key.strip()] = value.strip()
                continue
            header = line
            break
        names = [c.strip() for c in next(csv.reader([header]))] if header else []
        body = list(lines)
    try:  # numpy's parser rounds correctly too (Python's own dtoa), and fast
        table = np.loadtxt(body, delimiter=",", dtype=np.float64, ndmin=2)
        cells = [table[:, j] for j in range(len(names))] if len(body) else [[] for _ in names]
    except ValueError:  # empty cells, text columns: cell by cell
        cells = [[] for _ in names]
        for row in csv.reader(body):
            for j, text in enumerate(row[:len(names)]):
                cells[j].append(text.strip())
    data: dict[str, np.ndarray] = {}
    for name, col in zip(names, cells):
        data[name] = _column(col)
    df = pd.DataFrame(data)
    df.attrs["meta"] = meta
    return df


def _column(col: Any) -> np.ndarray:
    """One column: int64 when every value is an integer, else float64 (empty text: NaN),
    else the text."""
    if isinstance(col, np.ndarray):
        values = col
    else:
        try:
            values = np.array([float(x) if x else math.nan for x in col], dtype=np.float64)
        except ValueError:
            return np.array(col, dtype=object)
    if values.size and np.all(np.isfinite(values)) and np.all(values == np.round(values)) \
            and np.all(np.abs(values) < 2.0**53):
        return values.astype(np.int64)
    return values


def _args(options: Mapping[str, Any]) -> list[str]:
    args: list[str] = []
    for key, value in options.items():
        if key in _VALUE_OPTIONS:
            if value is not None:
                args += [_VALUE_OPTIONS[key], str(value)]
        elif key in _FLAG_OPTIONS:
            if value:
                args.append(_FLAG_OPTIONS[key])
        else:
            raise TypeError(f"replay() got an unexpected keyword argument '{key}'")
    return args


def _run(source: Source, params: Mapping[str, float] | str | os.PathLike | None,
         options: Mapping[str, Any], out: str | os.PathLike | None,
         tmp: Path) -> tuple[Path, dict[str, Any], str]:
    """One mu_replay run in ``tmp``: (estimate log path, the --metrics JSON, stdout)."""
    if isinstance(source, pd.DataFrame):
        in_path = tmp / "dataframe.csv"
        write_log(source, in_path)
    else:
        in_path = Path(os.fspath(source))
    out_path = Path(os.fspath(out)) if out is not None else tmp / "estimate.csv"
    json_path = tmp / "metrics.json"
    args = ["--in", str(in_path), "--out", str(out_path), "--metrics", str(json_path)]
    if isinstance(params, Mapping):
        p = tmp / "params.txt"
        p.write_text("".join(f"{k} = {_fmt(v)}\n" for k, v in params.items()),
                     encoding="utf-8")
        args += ["--params", str(p)]
    elif params is not None:
        args += ["--params", os.fspath(params)]
    args += _args(options)
    rc, stdout, stderr = cli.run_captured(args)
    if rc != 0:
        raise errors.from_cli(rc, stderr, STATUS_TEXT)
    for line in stderr.splitlines():
        warnings.warn(line, errors.RfeWarning, stacklevel=3)
    summary = json.loads(json_path.read_text(encoding="utf-8"))
    return out_path, summary, stdout


def replay(source: Source, *, params: Mapping[str, float] | str | os.PathLike | None = None,
           out: str | os.PathLike | None = None, preset: str | None = None,
           filter: str | None = None, tyre: str | None = None, real: Real | None = None,
           velocity: str | None = None, mass_grade: str | None = None,
           tyre_id: str | None = None, mass_grade_vehicle: str | None = None,
           strict: bool = False, require_params: bool = False, quiet: bool = False,
           mapping: str | os.PathLike | Mapping[str, Any] | None = None) -> pd.DataFrame:
    """Runs the estimator over a sensor log as ``mu_replay`` does, with its defaults.

    Args:
        source: a sensor log (path), or a DataFrame of its columns with the metadata in
            ``attrs["meta"]`` (as :func:`read_log` gives it); an MDF4 file (``.mf4``,
            ``.mdf``) with ``mapping``, read by :func:`rfe.read_mdf`; a Parquet file
            (``.parquet``, ``.pq``: :func:`rfe.read_parquet`).
        params: a parameter file, or a mapping key -> value written as one (--params).
        out: also keep the estimate log at this path (byte for byte mu_replay's --out);
            a ``.parquet`` (``.pq``) path: as Parquet (:func:`rfe.write_parquet`).
        preset, filter, tyre, real, velocity, mass_grade, tyre_id, mass_grade_vehicle, strict,
            require_params, quiet: mu_replay's options of the same names
            (``tyre_id="apf"`` is ``--tyre-id apf``, ``mass_grade_vehicle="truck"``
            ``--mass-grade-vehicle truck``; None / False: the CLI's default).
        mapping: the mapping file (or dict) of an MDF4 source (docs/PYTHON.md "MDF4 input").

    Returns:
        The estimate log's columns (t, mu_*, sd_*, valid_*, status, and the observer's, the
        mass and grade estimator's and the tyre identifier's when they ran), exactly as
        mu_replay writes them;
        ``attrs``: ``meta`` (the estimate log's metadata), ``summary`` (the --metrics JSON:
        steps, status counts, bad cells, gaps, accuracy) and ``report`` (the table
        mu_replay prints).

    Raises:
        UsageError: an option mu_replay refuses (exit status 2).
        InputError: malformed input or a failed run (exit status 1); a subclass per
            library status (ParamError, RangeError, NonFiniteError, ...).
    Notes and warnings mu_replay prints are issued as :class:`RfeWarning`.
    """
    options = dict(preset=preset, filter=filter, tyre=tyre, real=real, velocity=velocity,
                   mass_grade=mass_grade, tyre_id=tyre_id, mass_grade_vehicle=mass_grade_vehicle,
                   strict=strict, require_params=require_params, quiet=quiet)
    source = _sensor_source(source, mapping)
    out_parquet = out is not None and Path(os.fspath(out)).suffix.lower() in parquet.SUFFIXES
    with tempfile.TemporaryDirectory(prefix="rfe-") as d:
        out_path, summary, stdout = _run(source, params, options,
                                         None if out_parquet else out, Path(d))
        df = read_log(out_path)
    if out_parquet:
        parquet.write_parquet(df, out)
    df.attrs["summary"] = summary
    df.attrs["report"] = stdout
    return df


MDF_SUFFIXES = (".mf4", ".mdf")


def _sensor_source(source: Source, mapping: Any) -> Source:
    """An MDF4 path read through its mapping into a DataFrame; other sources as they are."""
    is_mdf = not isinstance(source, pd.DataFrame) and \
        Path(os.fspath(source)).suffix.lower() in MDF_SUFFIXES
    if is_mdf:
        if mapping is None:
            raise errors.UsageError("an MDF4 source needs mapping= (docs/PYTHON.md "
                                    "\"MDF4 input\")", exit_code=2)
        from .mdf import read_mdf
        return read_mdf(source, mapping)
    if mapping is not None:
        raise errors.UsageError("mapping= is for an MDF4 source (.mf4) only", exit_code=2)
    if not isinstance(source, pd.DataFrame) and \
            Path(os.fspath(source)).suffix.lower() in parquet.SUFFIXES:
        return parquet.read_parquet(source)
    return source


def metrics(source: Source | pd.DataFrame, **options: Any) -> dict[str, Any]:
    """The accuracy of a run against the log's truth columns, by the CLI's definitions
    (src/host/metrics.h, computed by its C code): mu_replay's --metrics JSON ``metrics``
    object (per wheel fl..rr and the mean), or None when the log has no truth columns.
    ``source`` and ``options`` as :func:`replay`; an estimate DataFrame returned by
    :func:`replay` gives its run's metrics without running again."""
    if isinstance(source, pd.DataFrame) and "summary" in source.attrs and not options:
        return source.attrs["summary"]["metrics"]
    return replay(source, **options).attrs["summary"]["metrics"]


class Estimator:
    """A configured estimator: the preset, parameters, precision and velocity source of a
    run, applied to logs, to columns of samples in memory (:meth:`run`) or to one sample at a
    time (:meth:`step`).

    Args:
        preset: "default" or "paper" (the library's parameter sets).
        params: a mapping key -> value or a parameter file (docs/spec/DATA.md keys).
        real: "float" (default), "double" or "q31".
        velocity: "auto" (default), "observer" or "measured".
        **options: the other options of :func:`replay` (filter, tyre, mass_grade, tyre_id,
            strict, require_params).

    A DataFrame or a mapping of columns runs in memory (no file, nothing printed, the GIL
    released while the C code steps), with the estimates of :func:`replay` bit for bit (a
    float run's values are its floats exactly, which ``replay`` reads back from their
    ``%.9g`` text: equal as float32). Each run, and each Estimator's :meth:`step` state, is
    its own C memory, so Estimators may run in several threads at once; one Estimator's
    :meth:`step` is not for two threads at a time.
    """

    def __init__(self, preset: str = "default",
                 params: Mapping[str, float] | str | os.PathLike | None = None,
                 real: Real = "float", velocity: str = "auto", **options: Any) -> None:
        _args(options)  # unknown keywords: TypeError now, not at the first run
        self.preset = preset
        self.params = params
        self.real = real
        self.velocity = velocity
        self.options = options
        self._stepper: Any = None

    def _mem_args(self, name: str) -> tuple[list[str], str | None]:
        """mu_replay's arguments of this configuration for a run in memory, and the
        parameters given as a mapping as `key = value` text (None: none or a file)."""
        if "quiet" in self.options:
            raise TypeError("quiet is for replay(): a run in memory prints nothing")
        args = ["--in", name, "--out", "(memory)", "--preset", str(self.preset),
                "--real", str(self.real), "--velocity", str(self.velocity)] + _args(self.options)
        text = None
        if isinstance(self.params, Mapping):
            text = "".join(f"{k} = {_fmt(v)}\n" for k, v in self.params.items())
        elif self.params is not None:
            args += ["--params", os.fspath(self.params)]
        return args, text

    def _open(self, columns: Mapping[str, Any], meta: Mapping[str, Any], name: str) -> Any:
        from .inmem import Run
        args, text = self._mem_args(name)
        run = Run(args, text, columns, meta)
        if run.preset_vehicle:
            warnings.warn(f"{name}: vehicle parameters (m, Lf, Lr, Bf, Br, R, J, hg) in "
                          "neither the metadata nor params: the preset's values stand in "
                          "(require_params=True makes this an error)", errors.RfeWarning,
                          stacklevel=3)
        return run

    def run(self, data: Source | Mapping[str, Any],
            meta: Mapping[str, Any] | None = None) -> pd.DataFrame:
        """Runs over a whole log.

        Args:
            data: a DataFrame (metadata in ``attrs["meta"]``) or a mapping column -> array
                (NumPy arrays, lists): run in memory, every sample stepped in C in one call;
                a path: :func:`replay` of that file.
            meta: the log's metadata (replaces ``attrs["meta"]``).

        Returns:
            The estimate log's columns (t, mu_*, sd_*, valid_*, status, and the observer's,
            the mass and grade estimator's and the tyre identifier's when they ran), equal to
            :func:`replay`'s; in memory ``attrs["stats"]`` holds the run's counters (steps,
            status counts, gaps, q31 saturations).

        Raises:
            UsageError, InputError and its per-status subclasses, as :func:`replay`; in memory
            the class is chosen by the status the C code returns.
        """
        if not isinstance(data, (pd.DataFrame, Mapping)):
            return replay(data, params=self.params, preset=self.preset, real=self.real,
                          velocity=self.velocity, **self.options)
        from .inmem import columns_of
        columns, frame_meta = columns_of(data)
        run = self._open(columns, dict(meta) if meta is not None else frame_meta, "DataFrame")
        df = run.frame(run.feed(columns))
        df.attrs["stats"] = run.stats()
        return df

    def step(self, sample: Mapping[str, Any],
             meta: Mapping[str, Any] | None = None) -> dict[str, float | int]:
        """Steps one sample, the state kept in this Estimator: n calls give the rows
        :meth:`run` gives for the same n samples, bit for bit.

        Args:
            sample: column -> value (the columns of a sensor log, ``t`` included); every
                sample must have the columns of the first.
            meta: the log's metadata (vehicle keys, units), taken at the first sample (after
                construction or :meth:`reset`).

        Returns:
            The sample's estimate row: column -> value (integers for valid_*, status).

        Raises:
            UsageError: dt given neither in ``params`` nor in ``meta`` (a whole run takes it
                from the time stamps' median, which one sample cannot give).
            InputError and its subclasses: as :meth:`run`; a time not after the last one's.
        """
        columns = {k: [v] for k, v in sample.items()}
        if self._stepper is None:
            run = self._open(columns, dict(meta or {}), "sample")
            if not run.dt_given:
                raise errors.UsageError("step(): give dt (params or meta): a run over samples "
                                        "one at a time cannot take it from the time stamps",
                                        exit_code=2)
            self._stepper = run
        row = self._stepper.feed(columns)
        df = self._stepper.frame(row)
        return {c: df[c].iloc[0].item() for c in df.columns}

    def reset(self) -> None:
        """Forgets the state of :meth:`step`: the next sample starts a new run."""
        self._stepper = None

    def stats(self) -> dict[str, Any]:
        """The counters of the samples :meth:`step` has stepped (as ``attrs["stats"]``)."""
        return self._stepper.stats() if self._stepper is not None else {"steps": 0}
