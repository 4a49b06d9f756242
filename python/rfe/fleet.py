"""Fleet replay: many logs at once on Dask (docs/PYTHON.md "Fleet replay").

    python -m rfe.fleet drives/ --mapping car.toml --real q31 --out fleet-out
    python -m rfe.fleet 'scenarios/*.csv' --out fleet-out --workers 2

One task per log, ``rfe.replay`` of that log on a ``dask.distributed`` worker (a
LocalCluster of worker processes by default, or ``--scheduler ADDR``). DIR receives one
estimate log per input (``estimates/<path>.parquet``), ``summary.csv`` (one row per log and
an overall row) and ``report.html`` (rfe.fleet_report). Every accuracy figure is the C
code's (the replay's ``attrs["summary"]``, mu_replay's --metrics JSON); the fleet adds only
what no run computes: the share of steps flagged valid without truth, the histograms of the
estimates per surface, and the sums over the fleet.

A run captures the process's file descriptors 1 and 2 (rfe.cli), so a process replays one
log at a time: the workers are processes with one thread each. A log that fails (a corrupt
file, missing channels) is a row with its error; the others go on; the exit status is 1 when
any failed. Needs dask, distributed, pyarrow and matplotlib (``pip install .[fleet]``).
"""
from __future__ import annotations

import argparse
import glob
import inspect
import math
import os
import sys
import time
import traceback
import uuid
import warnings
from collections.abc import Callable, Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from . import errors, parquet
from .replay import MDF_SUFFIXES, replay

LOG_SUFFIXES = (".csv", *MDF_SUFFIXES, *parquet.SUFFIXES)
WHEELS = ("fl", "fr", "rl", "rr")
# The estimates' histogram: fixed bins, so that each worker's counts add up. They span the
# library's default projection interval [mu_min, mu_max] = [0.05, 1.2] with room on both sides.
MU_BINS = np.linspace(0.0, 1.3, 53)          # 0.025 wide
# A surface is the true mu of a wheel's sample rounded to this step: the simulated surfaces
# (0.2, 0.35, 0.85, ...) are each one surface, a ramp of truth a few neighbouring ones.
SURFACE_STEP = 0.05
OVERALL = "ALL"
# rfe.replay's keywords that the fleet sets itself (not command-line options)
_OWN = {"source", "out", "quiet", "mapping"}


def find_logs(specs: Iterable[str]) -> list[Path]:
    """The logs named by files, folders (every log below, recursively) and glob patterns;
    sorted, without duplicates. Raises UsageError for a name that matches nothing."""
    found: dict[Path, None] = {}
    for spec in specs:
        p = Path(spec)
        if p.is_dir():
            hits = [q for q in p.rglob("*") if q.is_file() and q.suffix.lower() in LOG_SUFFIXES]
        elif p.is_file():
            hits = [p]
        else:
            hits = [Path(q) for q in glob.glob(spec, recursive=True)
                    if Path(q).is_file() and Path(q).suffix.lower() in LOG_SUFFIXES]
        if not hits:
            raise errors.UsageError(f"no log found at '{spec}' (files, folders or globs of "
                                    f"{', '.join(LOG_SUFFIXES)})", exit_code=2)
        for q in hits:
            found[q.resolve()] = None
    return sorted(found)


def estimate_paths(logs: Sequence[Path], out: Path) -> list[Path]:
    """Where each log's estimates go: ``out/estimates/`` + the log's path below the folder
    all logs share, with the suffix ``.parquet`` (so two drives of the same name in two
    folders stay apart)."""
    root = Path(os.path.commonpath([str(p.parent) for p in logs])) if logs else Path(".")
    return [out / "estimates" / p.relative_to(root).with_suffix(".parquet") for p in logs]


def _truth(path: Path, mapping: Any) -> pd.DataFrame | None:
    """The sensor log's true mu per wheel (columns fl..rr, SI), or None when it has none.
    A recorded log's column_mu_*, scale_mu_*, offset_mu_* keys apply (mu's unit is 1)."""
    suffix = path.suffix.lower()
    if suffix in MDF_SUFFIXES:
        from .mdf import read_mdf
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", errors.RfeWarning)  # replay reported them
            sensor = read_mdf(path, mapping)
    elif suffix in parquet.SUFFIXES:
        sensor = parquet.read_parquet(path)
    else:
        sensor = _csv_truth(path)
    meta = sensor.attrs.get("meta", {}) or {}
    cols = {}
    for w in WHEELS:
        name = str(meta.get(f"column_mu_{w}", f"mu_{w}"))
        if name not in sensor.columns:
            return None
        scale = float(meta.get(f"scale_mu_{w}", 1.0))
        offset = float(meta.get(f"offset_mu_{w}", 0.0))
        cols[w] = scale * sensor[name].to_numpy(dtype=np.float64) + offset
    return pd.DataFrame(cols)


def _csv_truth(path: Path) -> pd.DataFrame:
    """The truth columns of a DATA.md CSV and its metadata, read by pandas' C parser
    (correctly rounded) and only those columns: rfe.read_log of the whole log would cost a
    task a third of the C replay's time again."""
    meta: dict[str, str] = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            if not line.startswith("#"):
                break
            key, sep, value = line[1:].partition("=")
            if sep:
                meta[key.strip()] = value.strip()
    names = {str(meta.get(f"column_mu_{w}", f"mu_{w}")) for w in WHEELS}
    sensor = pd.read_csv(path, comment="#", skipinitialspace=True,
                         usecols=lambda c: c.strip() in names)
    sensor.columns = [c.strip() for c in sensor.columns]
    sensor.attrs["meta"] = meta
    return sensor


def surface_histograms(est: pd.DataFrame, truth: pd.DataFrame) -> dict[str, list[int]]:
    """Counts of the valid estimates of every wheel in MU_BINS (np.histogram's bins: the
    last one closed), per surface (the wheel's true mu rounded to SURFACE_STEP, as text
    "0.85"); samples with a NaN on either side and estimates outside the bins are left out.
    One bincount over (surface, bin) pairs: a histogram call per surface and wheel cost a task
    a third of its replay on a log whose truth ramps through many surfaces."""
    nbins = len(MU_BINS) - 1
    mu = np.concatenate([est[f"mu_{w}"].to_numpy(dtype=np.float64) for w in WHEELS])
    valid = np.concatenate([est[f"valid_{w}"].to_numpy() != 0 for w in WHEELS])
    true = np.concatenate([truth[w].to_numpy(dtype=np.float64) for w in WHEELS])
    keep = valid & np.isfinite(mu) & np.isfinite(true) & (mu >= MU_BINS[0]) & (mu <= MU_BINS[-1])
    mu, true = mu[keep], true[keep]
    idx = np.minimum(np.searchsorted(MU_BINS, mu, side="right") - 1, nbins - 1)
    surfaces, which = np.unique(np.round(true / SURFACE_STEP), return_inverse=True)
    counts = np.bincount(which.ravel() * nbins + idx,
                         minlength=len(surfaces) * nbins).reshape(len(surfaces), nbins)
    return {f"{s * SURFACE_STEP:.2f}": c.tolist() for s, c in zip(surfaces, counts)}


def replay_one(log: str, estimates: str, options: Mapping[str, Any],
               mapping: Any = None) -> dict[str, Any]:
    """One fleet task (run on a worker): rfe.replay of ``log`` with ``options``, its
    estimates written to ``estimates`` (Parquet). Never raises: a failure is returned as
    ``error`` (the exception's type and message) so that the other logs go on."""
    start = time.perf_counter()
    est_path = Path(estimates)
    result: dict[str, Any] = {"log": log, "error": None, "usage": False, "warnings": []}
    try:
        est_path.unlink(missing_ok=True)  # no stale estimates of an earlier fleet run
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always", errors.RfeWarning)
            df = replay(log, out=est_path, quiet=True,
                        mapping=mapping if Path(log).suffix.lower() in MDF_SUFFIXES else None,
                        **options)
        result["warnings"] = [str(w.message) for w in caught
                              if issubclass(w.category, errors.RfeWarning)]
        summary = df.attrs["summary"]
        result["summary"] = summary
        result["valid_steps"] = int((df[[f"valid_{w}" for w in WHEELS]] != 0).all(axis=1).sum())
        result["histograms"] = {}
        if summary.get("metrics") is not None:
            truth = _truth(Path(log), mapping)
            if truth is not None and len(truth) == len(df):
                result["histograms"] = surface_histograms(df, truth)
    except errors.UsageError as e:
        result["error"] = f"{type(e).__name__}: {e}"
        result["usage"] = True
    except Exception as e:  # noqa: BLE001 - any failure is this log's, reported in its row
        result["error"] = f"{type(e).__name__}: {e}"
        if not isinstance(e, errors.RfeError):
            result["traceback"] = traceback.format_exc()
    result["seconds"] = time.perf_counter() - start
    return result


# ---------------------------------------------------------------- the summary table

STATUS_PREFIX = "status_"
INT_COLUMNS = ("steps", "valid_steps", "n_settled", "n_valid")
COUNT_COLUMNS = ("sat_estimator", "sat_estimator_steps", "sat_input", "sat_input_rows",
                 "bad_rows", "gaps", "warnings")


def summary_row(log: str, estimates: str, result: Mapping[str, Any]) -> dict[str, Any]:
    """A log's row: what its replay summary says (mu_replay's --metrics JSON: steps, status
    counts, saturation, bad rows, gaps and the mean series' accuracy of src/host/metrics.h),
    and valid_steps, the steps whose four wheels are all flagged valid (the rule of
    metrics.h's mean series, over every step: a log without truth has no settled samples)."""
    row: dict[str, Any] = {"log": log, "estimates": estimates, "error": result.get("error") or ""}
    summary = result.get("summary")
    if summary is None:
        return row
    row["real"] = summary.get("real")
    row["steps"] = summary["steps"]
    row["valid_steps"] = result["valid_steps"]
    row["valid_share"] = result["valid_steps"] / summary["steps"] if summary["steps"] else math.nan
    mean = (summary.get("metrics") or {}).get("mean")
    if mean is not None:
        for key in ("n_settled", "n_valid", "frac_valid", "consistency_valid", "rmse_valid"):
            value = mean.get(key)
            row[key] = math.nan if value is None else value
    for code, count in (summary.get("status_counts") or {}).items():
        row[f"{STATUS_PREFIX}{int(code)}"] = count
    sat = summary.get("saturation")
    if sat is not None:
        row["sat_estimator"] = sat["estimator_total"]
        row["sat_estimator_steps"] = sat["estimator_steps"]
        row["sat_input"] = sat["input_values"]
        row["sat_input_rows"] = sat["input_rows"]
    row["bad_rows"] = summary["bad_cells"]["rows"]
    row["gaps"] = summary["gaps"]["count"]
    row["warnings"] = len(result.get("warnings", []))
    row["seconds"] = result.get("seconds", math.nan)
    return row


def overall_row(rows: pd.DataFrame) -> dict[str, Any]:
    """The fleet's row, pooled over the completed logs' rows, as if the logs were one:
    counts are summed; valid_share = sum(valid_steps) / sum(steps); frac_valid =
    sum(n_valid) / sum(n_settled) and consistency_valid = sum(consistency_valid * n_valid)
    / sum(n_valid) over the logs with truth; rmse_valid = sqrt(sum(rmse_valid^2 * n_valid)
    / sum(n_valid)) over the logs with valid settled samples (the RMSE of all of them)."""
    done = rows[rows["error"] == ""]
    failed = len(rows) - len(done)
    row: dict[str, Any] = {"log": OVERALL, "estimates": "",
                           "error": f"{failed} of {len(rows)} logs failed" if failed else ""}
    if done.empty:
        return row
    row["steps"] = int(done["steps"].sum())
    row["valid_steps"] = int(done["valid_steps"].sum())
    row["valid_share"] = row["valid_steps"] / row["steps"] if row["steps"] else math.nan
    if "n_settled" in done and done["n_settled"].notna().any():
        truth = done[done["n_settled"].notna()]
        row["n_settled"] = int(truth["n_settled"].sum())
        row["n_valid"] = int(truth["n_valid"].sum())
        row["frac_valid"] = row["n_valid"] / row["n_settled"] if row["n_settled"] else math.nan
        has = truth[truth["n_valid"] > 0]
        n = has["n_valid"].sum()
        row["consistency_valid"] = float((has["consistency_valid"] * has["n_valid"]).sum() / n) \
            if n else math.nan
        rmse = has[has["rmse_valid"].notna()]
        m = rmse["n_valid"].sum()
        sq = (rmse["rmse_valid"] ** 2 * rmse["n_valid"]).sum()
        row["rmse_valid"] = math.sqrt(float(sq / m)) if m else math.nan
    for col in rows.columns:
        if col.startswith(STATUS_PREFIX) or col in COUNT_COLUMNS:
            if done[col].notna().any():
                row[col] = int(done[col].sum())
    return row


def summary_table(rows: Sequence[Mapping[str, Any]]) -> pd.DataFrame:
    """The per-log rows in a fixed column order (status columns by code) and the overall
    row last."""
    df = pd.DataFrame(list(rows))
    statuses = sorted((c for c in df.columns if c.startswith(STATUS_PREFIX)),
                      key=lambda c: int(c[len(STATUS_PREFIX):]))
    order = ["log", "error", "real", "steps", "valid_steps", "valid_share", "n_settled",
             "n_valid", "frac_valid", "consistency_valid", "rmse_valid", *statuses,
             *COUNT_COLUMNS, "seconds", "estimates"]
    df = df.reindex(columns=[c for c in order if c in df.columns])
    table = pd.concat([df, pd.DataFrame([overall_row(df)])], ignore_index=True)
    table = table.reindex(columns=df.columns)
    for col in table.columns:  # counts as integers, empty where a log has none
        if col in INT_COLUMNS or col.startswith(STATUS_PREFIX) or col in COUNT_COLUMNS:
            table[col] = table[col].astype("Int64")
    return table


def worst_first(rows: pd.DataFrame) -> pd.DataFrame:
    """The per-log rows, worst first: the failed logs, then by valid_share ascending (the
    share of steps the estimator vouches for, which every log has), ties by rmse_valid
    descending (a log without truth after those with)."""
    logs = rows[rows["log"] != OVERALL].copy()
    logs["_failed"] = logs["error"] != ""
    if "valid_share" not in logs:  # every log failed
        logs["valid_share"] = math.nan
    logs["_rmse"] = -logs["rmse_valid"].fillna(-math.inf) if "rmse_valid" in logs else 0.0
    logs = logs.sort_values(["_failed", "valid_share", "_rmse", "log"],
                            ascending=[False, True, True, True], na_position="first",
                            kind="mergesort")
    return logs.drop(columns=["_failed", "_rmse"])


# ---------------------------------------------------------------- running on Dask

class Progress:
    """A progress bar on stderr: redrawn in place on a terminal, one line per log
    otherwise (a CI log); nothing when quiet. Failures are printed either way."""

    def __init__(self, total: int, quiet: bool, stream: Any = None) -> None:
        self.total, self.done, self.failed = total, 0, 0
        self.quiet = quiet
        self.stream = stream if stream is not None else sys.stderr
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.start = time.perf_counter()

    def update(self, log: str, error: str | None, detail: str | None = None) -> None:
        """One more log done; ``error`` its failure, ``detail`` a traceback worth showing
        (a failure that is not the library's)."""
        self.done += 1
        if error:
            self.failed += 1
            self._clear()
            print(f"rfe.fleet: {log}: {error}", file=self.stream)
            if detail:
                print(detail, file=self.stream, end="")
        if self.quiet:
            return
        rate = self.done / max(time.perf_counter() - self.start, 1e-9)
        text = f"{self.done}/{self.total} logs, {self.failed} failed, {rate:.1f} logs/s"
        if self.tty:
            width = 30
            fill = width * self.done // max(self.total, 1)
            self.stream.write(f"\r[{'#' * fill}{' ' * (width - fill)}] {text}")
            if self.done == self.total:
                self.stream.write("\n")
        else:
            self.stream.write(f"{text}: {Path(log).name} {'failed' if error else 'ok'}\n")
        self.stream.flush()

    def _clear(self) -> None:
        if self.tty and not self.quiet:
            self.stream.write("\r" + " " * 79 + "\r")


# No dashboard (it needs bokeh), and the scheduler's HTTP endpoints on a free port rather than
# 8787, which a second cluster on the machine would find taken (and warn).
QUIET_CLUSTER = {"dashboard_address": None, "scheduler_kwargs": {"dashboard_address": ":0"}}


def _client(workers: int | None, scheduler: str | None) -> tuple[Any, Any]:
    """A dask.distributed client: on the scheduler at ``scheduler``, or on a LocalCluster of
    ``workers`` processes with one thread each (one replay at a time per process)."""
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as e:  # pragma: no cover
        raise ImportError("the fleet replay needs dask and distributed: "
                          "pip install rfe[fleet]") from e
    if scheduler:
        return Client(scheduler), None
    import dask
    # A worker that dies on a log (a crash in C) would die again on it: no retry on another
    # worker (distributed's default of 3 is for workers lost at random); _gather runs the
    # other logs it held again by themselves.
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):
        cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                               processes=True, **QUIET_CLUSTER)
    return Client(cluster), cluster


def run(logs: Sequence[str | os.PathLike], out: str | os.PathLike, *,
        workers: int | None = None, scheduler: str | None = None, client: Any = None,
        mapping: str | os.PathLike | Mapping[str, Any] | None = None, quiet: bool = False,
        report: bool = True,
        progress_stream: Any = None, **options: Any) -> pd.DataFrame:
    """Replays every log on Dask into ``out`` and returns the summary table (also written
    as ``out/summary.csv``; ``out/report.html`` unless ``report=False``).

    Args:
        logs: files, folders or glob patterns of sensor logs (.csv, .parquet, and .mf4 with
            ``mapping``).
        out: the output folder (created).
        workers: the LocalCluster's worker processes (default: the machine's cores).
        scheduler: a dask scheduler's address instead of a LocalCluster (its workers must
            import rfe and see the logs and ``out`` at the same paths).
        client: an existing dask.distributed Client to use instead of either.
        mapping: the MDF4 mapping (a file, or the dict rfe.read_mdf takes) of the .mf4 logs.
        quiet: no progress bar (failures are still printed on stderr).
        **options: rfe.replay's options (preset, params, real, velocity, ...).
    Raises:
        UsageError: no log found, an .mf4 without mapping, or options every run refuses.
    """
    out_dir = Path(out).resolve()
    # not the estimates of an earlier run into the same folder (drives/ --out drives/fleet)
    found = [p for p in find_logs([os.fspath(p) for p in logs]) if out_dir not in p.parents]
    if not found:
        raise errors.UsageError(f"every log found is inside the output folder {out_dir}",
                                exit_code=2)
    if mapping is None and any(p.suffix.lower() in MDF_SUFFIXES for p in found):
        raise errors.UsageError("MDF4 logs need --mapping (docs/PYTHON.md \"MDF4 input\")",
                                exit_code=2)
    est = estimate_paths(found, out_dir)
    for p in {e.parent for e in est}:
        p.mkdir(parents=True, exist_ok=True)
    mapping_arg = mapping if mapping is None or isinstance(mapping, Mapping) else \
        os.path.abspath(mapping)  # a path the workers find whatever their folder
    own, cluster = (client, None) if client is not None else _client(workers, scheduler)
    results: dict[int, dict[str, Any]] = {}
    try:
        results = _gather(own, found, est, options, mapping_arg,
                          Progress(len(found), quiet, progress_stream))
    finally:
        if client is None:
            own.close()
            if cluster is not None:
                cluster.close()
    usage = [r for r in results.values() if r.get("usage")]
    if usage:
        raise errors.UsageError(usage[0]["error"], exit_code=2)
    rows = [summary_row(str(found[i]), os.path.relpath(est[i], out_dir)
                        if results[i].get("error") is None else "", results[i])
            for i in range(len(found))]
    table = summary_table(rows)
    table.to_csv(out_dir / "summary.csv", index=False)
    if report:
        from .fleet_report import write_report
        hist: dict[str, np.ndarray] = {}
        for r in results.values():
            for surface, counts in (r.get("histograms") or {}).items():
                hist[surface] = hist.get(surface, 0) + np.asarray(counts, dtype=np.int64)
        write_report(out_dir / "report.html", table, worst_first(table), hist, MU_BINS,
                     options={**options, "mapping": mapping})
    return table


def _gather(client: Any, logs: Sequence[Path], est: Sequence[Path],
            options: Mapping[str, Any], mapping: Any, progress: Progress,
            task: Callable[..., dict[str, Any]] = replay_one) -> dict[int, dict[str, Any]]:
    """Submits one task per log and collects the results as they come. A task that raises
    on the cluster's side is that log's failure, except a worker's death (KilledWorker):
    distributed blames every task the dying worker held, so a log that crashes its worker
    can take the logs queued behind it along; those run again at the end, one at a time, and
    only a log that kills its worker alone, on each of ALONE_TRIES tries, is reported so. Stops early on a usage error,
    which every log would repeat. ``task`` is replay_one (another function in the tests)."""
    from dask.distributed import as_completed
    run_id = uuid.uuid4().hex[:8]  # keys unique per fleet run: a reused client caches none

    def submit(i: int, tag: str = "") -> Any:
        return client.submit(task, str(logs[i]), str(est[i]), dict(options), mapping,
                             key=f"rfe-fleet-{run_id}-{i}{tag}-{logs[i].name}", pure=False)

    def outcome(fut: Any, i: int) -> dict[str, Any]:
        try:
            return fut.result()
        except Exception as e:  # noqa: BLE001 - the cluster's failure of this log's task
            return {"log": str(logs[i]), "error": f"{type(e).__name__}: {e}", "usage": False,
                    "killed": type(e).__name__ == "KilledWorker"}

    def released(fut: Any, i: int) -> dict[str, Any]:
        """outcome(fut, i); the future released, so a later worker death has no result of
        it to recompute."""
        res = outcome(fut, i)
        fut.release()
        return res

    futures = {submit(i): i for i in range(len(logs))}
    results: dict[int, dict[str, Any]] = {}
    killed: list[int] = []
    for fut in as_completed(list(futures)):
        i = futures.pop(fut)
        res = released(fut, i)
        if res.get("killed"):
            killed.append(i)
            continue
        results[i] = res
        progress.update(str(logs[i]), res.get("error"), res.get("traceback"))
        if res.get("usage"):
            for other in futures:
                other.cancel()
            return results
    for i in sorted(killed):  # alone now: nothing else on the worker to take down
        results[i] = _alone(lambda tag, i=i: released(submit(i, tag), i))
        progress.update(str(logs[i]), results[i].get("error"), results[i].get("traceback"))
    return results


# How often a log the first round lost with its worker runs again alone before it counts as
# the one that kills its worker: once more than the first try, because a worker restarting
# after the previous death can still be blamed for it on a loaded machine (seen once in CI:
# the log run alone after the crashing one was reported as killed); a log that kills its
# worker on both tries, alone each time, is the crashing one.
ALONE_TRIES = 2


def _alone(run: Callable[[str], dict[str, Any]]) -> dict[str, Any]:
    """run(tag) with the tags -alone1, -alone2, ... until a try is not a worker's death or
    ALONE_TRIES tries died: the last try's result."""
    res: dict[str, Any] = {}
    for k in range(1, ALONE_TRIES + 1):
        res = run(f"-alone{k}")
        if not res.get("killed"):
            break
    return res


# ---------------------------------------------------------------- the command line

# Choices of mu_replay's options (its --help), checked before the cluster starts.
CHOICES = {"preset": ("default", "paper"), "filter": ("sckf", "ckf"),
           "tyre": ("paper", "absolute", "magic"), "real": ("float", "double", "q31"),
           "velocity": ("auto", "observer", "measured"), "mass_grade": ("ukf", "aukf", "off"),
           "mass_grade_vehicle": ("car", "truck")}


def replay_options() -> dict[str, inspect.Parameter]:
    """rfe.replay's keyword options that the fleet passes through (taken from its
    signature, so an option added to replay joins the command line)."""
    return {name: p for name, p in inspect.signature(replay).parameters.items()
            if p.kind is inspect.Parameter.KEYWORD_ONLY and name not in _OWN}


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="python -m rfe.fleet",
        description="Replays many sensor logs on Dask (one task per log) and writes each "
                    "log's estimates (Parquet), summary.csv and report.html into DIR "
                    "(docs/PYTHON.md \"Fleet replay\").",
        epilog="Exit status: 0 every log replayed, 1 some log failed (its row in "
               "summary.csv and a line on stderr say why), 2 bad usage.")
    ap.add_argument("logs", nargs="+", metavar="LOGS",
                    help="sensor logs: files, folders (every .csv, .mf4, .parquet below) or "
                         "glob patterns")
    ap.add_argument("--out", required=True, metavar="DIR", help="output folder (created)")
    ap.add_argument("--workers", type=int, default=None, metavar="N",
                    help="LocalCluster worker processes, one thread each "
                         "(default: the machine's cores)")
    ap.add_argument("--scheduler", metavar="ADDR",
                    help="a running dask scheduler (tcp://host:8786) instead of a LocalCluster")
    ap.add_argument("--mapping", metavar="FILE", help="the MDF4 mapping of the .mf4 logs")
    ap.add_argument("--quiet", "-q", action="store_true", help="no progress bar")
    ap.add_argument("--no-report", action="store_true", help="no report.html")
    for name, p in replay_options().items():
        flag = "--" + name.replace("_", "-")
        if p.default is False:
            ap.add_argument(flag, dest=name, action="store_true",
                            help=f"mu_replay's {flag}")
        else:
            ap.add_argument(flag, dest=name, choices=CHOICES.get(name),
                            metavar=None if name in CHOICES else
                            ("FILE" if name == "params" else "VALUE"),
                            help=f"mu_replay's {flag} (python -m rfe --help)")
    return ap


def main(argv: Sequence[str] | None = None,
         stderr: Callable[[str], None] | None = None) -> int:
    args = parser().parse_args(argv)
    say = stderr or (lambda s: print(s, file=sys.stderr))
    if args.workers is not None and args.workers < 1:
        say("rfe.fleet: --workers must be at least 1")
        return 2
    options = {name: getattr(args, name) for name in replay_options()
               if getattr(args, name) not in (None, False)}
    if "params" in options:
        options["params"] = os.path.abspath(options["params"])
    start = time.perf_counter()
    try:
        table = run(args.logs, args.out, workers=args.workers, scheduler=args.scheduler,
                    mapping=args.mapping, quiet=args.quiet, report=not args.no_report,
                    **options)
    except errors.UsageError as e:
        say(f"rfe.fleet: {e}")
        return 2
    logs = table[table["log"] != OVERALL]
    failed = int((logs["error"] != "").sum())
    if not args.quiet:
        say(f"rfe.fleet: {len(logs) - failed} of {len(logs)} logs replayed, {failed} failed, "
            f"in {time.perf_counter() - start:.1f} s; {Path(args.out) / 'summary.csv'}")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
