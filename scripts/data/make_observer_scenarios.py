#!/usr/bin/env python3
"""Write the observer scenario logs (scripts/sim/observer_scenarios.py, DATA.md) with the
reference simulator.

    .venv/bin/python scripts/data/make_observer_scenarios.py [--out scenarios/observer]
                                                        [--only NAME ...] [--jobs N]

For every scenario and each of its truth tyres (ObserverScenario.tyres):
    <out>/<name>.csv      Dugoff truth, default sensor noise (seed = 201 + index)
    <out>/<name>.nf.csv   Dugoff truth, noise-free (the ay bias still in ay)
    <out>/<name>.mf.csv   Magic-Formula truth, default noise
One progress line per simulation: runtime, max |beta| [deg], min vx [m/s] and the per-wheel
max |kappa| (fl/fr/rl/rr).  Simulations run in --jobs worker processes (default: all CPUs),
the longest first; deterministic either way: the same command writes the same bytes.
"""

import argparse
import os
import sys
import time

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]

import numpy as np  # noqa: E402

from job_pool import print_jobs  # noqa: E402
from sim import sensors  # noqa: E402
from sim.observer_scenarios import OBS_BY_NAME, OBSERVER_SCENARIOS  # noqa: E402

VARIANTS = {"dugoff": ("default", "none"), "mf": ("default",)}


def stats(sim):
    """max |beta| [deg], min vx [m/s], per-wheel max |kappa| of a simulator output."""
    beta = np.arctan2(sim["vy"], sim["vx"])
    return (float(np.degrees(np.abs(beta)).max()), float(np.min(sim["vx"])),
            np.abs(sim["kappa"]).max(axis=0))


def run_one(job):
    name, tyre, out = job
    sc = OBS_BY_NAME[name]
    t0 = time.perf_counter()
    sim = sensors.run_observer(sc, tyre)
    beta, vx_min, kap = stats(sim)
    table = sensors.observer_table(sim, sc)
    cols = sensors.observer_columns(sc)
    written = []
    for noise in VARIANTS[tyre]:
        tab = sensors.observer_noise(table, sc) if noise == "default" else table
        fname = sensors.file_name(sc.name, tyre, noise)
        path = os.path.join(out, fname)
        with open(path, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(sensors.observer_csv_text(tab, sensors.observer_metadata(sc, noise, tyre),
                                               cols))
        written.append(f"{fname} ({os.path.getsize(path) / 1e6:.2f} MB)")
    el = time.perf_counter() - t0
    return (f"{sc.name:20s} {tyre:6s} {el:6.1f} s  max|beta| {beta:6.2f} deg  min vx "
            f"{vx_min:7.3f}  max|kappa| {'/'.join(f'{v:.3f}' for v in kap)}  -> "
            f"{', '.join(written)}")


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(repo, "scenarios", "observer"),
                    help="output directory (default: <repo>/scenarios/observer)")
    ap.add_argument("--only", nargs="+", metavar="NAME", choices=sorted(OBS_BY_NAME),
                    help="only these scenarios")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="worker processes (default: number of CPUs)")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    selected = [sc for sc in OBSERVER_SCENARIOS if not args.only or sc.name in args.only]
    jobs = [(sc.name, tyre, args.out) for sc in selected for tyre in sc.tyres]
    # longest simulations first, so the worker pool ends together
    jobs.sort(key=lambda j: -OBS_BY_NAME[j[0]].duration)
    seconds = print_jobs(run_one, jobs, args.jobs)
    n_files = sum(len(VARIANTS[j[1]]) for j in jobs)
    print(f"{len(jobs)} simulation(s), {n_files} file(s) in {seconds:.1f} s -> {args.out}")


if __name__ == "__main__":
    main()
