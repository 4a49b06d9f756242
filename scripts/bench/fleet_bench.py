"""Logs per second of the fleet replay (python -m rfe.fleet) with 1 and 2 workers, and its
overhead against a plain loop over rfe.replay in one process (docs/PYTHON.md "Fleet replay").

    make fleet-bench                          # builds the package, writes docs/PYTHON.md
    PYTHONPATH=build/py python scripts/bench/fleet_bench.py [--logs GLOB] [--reps N] [--no-page]

A benchmark, not a test (it gates nothing). Each configuration runs --reps times over the
same logs; the table gives the median wall time and the range (the machine may be shared:
the load average at the start is in the page). The plain loop is rfe.replay(log,
out=estimates.parquet) per log, the work a task does; the fleet adds its own figures
(valid share, histograms), the scheduling and the report. "cluster running" times
rfe.fleet.run on a LocalCluster started beforehand (what a user with a cluster pays per
batch); "end to end" includes starting and stopping the cluster (what one command pays).
"""
from __future__ import annotations

import argparse
import datetime
import glob
import math
import os
import platform
import resource
import statistics
import sys
import tempfile
import time
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts" / "tools"))
from md_tables import replace_region  # noqa: E402

import rfe  # noqa: E402
from rfe import fleet  # noqa: E402

PAGE = ROOT / "docs" / "PYTHON.md"
README = ROOT / "README.md"


def cpu_name() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def cpu_seconds() -> float:
    """User and system CPU time of this process and of its ended children (the cluster's
    worker processes once it has stopped), which another job on the machine does not
    inflate as it does the wall time."""
    me = resource.getrusage(resource.RUSAGE_SELF)
    kids = resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def plain_loop(logs: list[Path], out: Path) -> tuple[float, float]:
    start, cpu = time.perf_counter(), cpu_seconds()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", rfe.RfeWarning)
        for i, log in enumerate(logs):
            rfe.replay(log, out=out / f"{i}.parquet", quiet=True)
    return time.perf_counter() - start, cpu_seconds() - cpu


def fleet_running(logs: list[Path], out: Path, workers: int, reps: int) -> list[float]:
    from dask.distributed import Client, LocalCluster
    times = []
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      **fleet.QUIET_CLUSTER) as cluster, Client(cluster) as client:
        fleet.run(logs[:workers], out, client=client, quiet=True)  # workers import rfe
        for _ in range(reps):
            start = time.perf_counter()
            fleet.run(logs, out, client=client, quiet=True)
            times.append(time.perf_counter() - start)
    return times


def fleet_end_to_end(logs: list[Path], out: Path, workers: int) -> tuple[float, float]:
    start, cpu = time.perf_counter(), cpu_seconds()
    fleet.run(logs, out, workers=workers, quiet=True)
    return time.perf_counter() - start, cpu_seconds() - cpu


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--logs", default="scenarios/*.csv", help="glob of the logs (%(default)s)")
    ap.add_argument("--reps", type=int, default=5, help="runs per configuration (%(default)s)")
    ap.add_argument("--no-page", action="store_true", help="print only, leave docs/PYTHON.md")
    args = ap.parse_args(argv)
    logs = sorted(Path(p).resolve() for p in glob.glob(str(ROOT / args.logs)))
    steps = sum(sum(1 for ln in open(p, encoding="utf-8") if not ln.startswith("#")) - 1
                for p in logs)
    load = os.getloadavg()[0]
    rows = []
    rate, e2e_cpu = {}, {}
    with tempfile.TemporaryDirectory(prefix="fleet-bench-") as d:
        out = Path(d)
        plain_loop(logs[:2], out)  # the extension loaded and warm
        loop_runs = [plain_loop(logs, out) for _ in range(args.reps)]
        loop = statistics.median(t for t, _ in loop_runs)
        loop_cpu = statistics.median(c for _, c in loop_runs)
        rows.append(("plain loop over rfe.replay, one process", loop_runs))
        for workers in (1, 2):
            running = fleet_running(logs, out / "f", workers, args.reps)
            rows.append((f"rfe.fleet, {workers} worker{'s' * (workers > 1)}, cluster running",
                         [(t, math.nan) for t in running]))
            rate[workers] = len(logs) / statistics.median(running)
            e2e = [fleet_end_to_end(logs, out / "e", workers) for _ in range(args.reps)]
            e2e_cpu[workers] = statistics.median(c for _, c in e2e)
            rows.append((f"rfe.fleet, {workers} worker{'s' * (workers > 1)}, end to end "
                         "(cluster start and stop)", e2e))
    stamp = datetime.datetime.now(datetime.timezone.utc).replace(microsecond=0).isoformat()
    lines = [f"Measured by `make fleet-bench` on {cpu_name()} ({os.cpu_count()} cores, load "
             f"average {load:.1f} at the start), {len(logs)} logs `{args.logs}` ({steps:,} "
             f"steps, default options: float), median of {args.reps} runs; generated {stamp}.",
             "",
             "| run | wall time [s], median (min–max) | logs/s | time against the plain loop "
             "| CPU time [s] (all processes) | CPU time against the plain loop |",
             "|---|---|---|---|---|---|"]
    for name, runs in rows:
        times = [t for t, _ in runs]
        t, cpu = statistics.median(times), statistics.median(c for _, c in runs)
        cpu_cells = "– | –" if math.isnan(cpu) else f"{cpu:.2f} | {cpu / loop_cpu:.2f}×"
        lines.append(f"| {name} | {t:.2f} ({min(times):.2f}–{max(times):.2f}) | "
                     f"{len(logs) / t:.1f} | {t / loop:.2f}× | {cpu_cells} |")
    # the README's line, short for its budget: the cluster-running rates (what a batch takes)
    # and the whole command's CPU time on 2 workers against the loop's
    readme = [f"`make fleet-bench`: {rate[2]:.1f} logs/s on 2 workers, {rate[1]:.1f} on 1, "
              f"{len(logs) / loop:.1f} in a plain loop ({e2e_cpu[2] / loop_cpu:.1f}× its CPU time)."]
    print("\n".join(lines + [""] + readme))
    if not args.no_page:
        replace_region(PAGE, "<!-- fleet-bench:begin -->", "<!-- fleet-bench:end -->", lines,
                       "fleet_bench")
        replace_region(README, "<!-- fleet:begin -->", "<!-- fleet:end -->", readme,
                       "fleet_bench")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
