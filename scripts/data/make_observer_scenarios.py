#!/usr/bin/env python3
"""Write the observer scenario logs (scripts/sim/observer_scenarios.py, DATA.md) with the
reference simulator.

    .venv/bin/python scripts/data/make_observer_scenarios.py [--out scenarios/observer]
                                                        [--only NAME ...] [--jobs N]
                                                        [--resistances | --loop]

For every scenario and each of its truth tyres (ObserverScenario.tyres):
    <out>/<name>.csv      Dugoff truth, default sensor noise (seed = 201 + index)
    <out>/<name>.nf.csv   Dugoff truth, noise-free (the ay bias still in ay)
    <out>/<name>.mf.csv   Magic-Formula truth, default noise
With --resistances the same for the observer scenarios with the car's driving resistances
(mass_grade_scenarios.OBS_RES_SCENARIOS: <name>_res, noisy only, default --out
scenarios/observer_res): the logs of the mass filter's model-matched studies.
With --loop the friction loop's scenario (observer_scenarios.OBS_LOOP_SCENARIOS: a mu step
while cornering, default --out scenarios/observer_loop), written like the observer logs.
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
from sim.mass_grade_scenarios import OBS_RES_BY_NAME, OBS_RES_SCENARIOS  # noqa: E402
from sim.observer_scenarios import (OBS_BY_NAME, OBS_LOOP_BY_NAME, OBS_LOOP_SCENARIOS,  # noqa: E402
                                    OBSERVER_SCENARIOS)

VARIANTS = {"dugoff": ("default", "none"), "mf": ("default",)}
RES_VARIANTS = {"dugoff": ("default",), "mf": ("default",)}   # the _res logs: noisy only
BY_NAME = dict(OBS_BY_NAME, **OBS_RES_BY_NAME, **OBS_LOOP_BY_NAME)


def variants(sc, tyre):
    return (VARIANTS if sc.res is None else RES_VARIANTS)[tyre]


def stats(sim):
    """max |beta| [deg], min vx [m/s], per-wheel max |kappa| of a simulator output."""
    beta = np.arctan2(sim["vy"], sim["vx"])
    return (float(np.degrees(np.abs(beta)).max()), float(np.min(sim["vx"])),
            np.abs(sim["kappa"]).max(axis=0))


def run_one(job):
    name, tyre, out = job
    sc = BY_NAME[name]
    t0 = time.perf_counter()
    sim = sensors.run_observer(sc, tyre)
    beta, vx_min, kap = stats(sim)
    table = sensors.observer_table(sim, sc)
    cols = sensors.observer_columns(sc)
    written = []
    for noise in variants(sc, tyre):
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
    ap.add_argument("--out", help="output directory (default: <repo>/scenarios/observer, "
                    "with --resistances <repo>/scenarios/observer_res, with --loop "
                    "<repo>/scenarios/observer_loop)")
    ap.add_argument("--only", nargs="+", metavar="NAME", choices=sorted(BY_NAME),
                    help="only these scenarios")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="worker processes (default: number of CPUs)")
    which = ap.add_mutually_exclusive_group()
    which.add_argument("--resistances", action="store_true",
                       help="the scenarios with the car's driving resistances (<name>_res)")
    which.add_argument("--loop", action="store_true",
                       help="the friction loop's scenario (a mu step while cornering)")
    args = ap.parse_args(argv)
    folder, scenarios = (("observer_res", OBS_RES_SCENARIOS) if args.resistances else
                         ("observer_loop", OBS_LOOP_SCENARIOS) if args.loop else
                         ("observer", OBSERVER_SCENARIOS))
    if args.out is None:
        args.out = os.path.join(repo, "scenarios", folder)
    os.makedirs(args.out, exist_ok=True)
    selected = [sc for sc in scenarios if not args.only or sc.name in args.only]
    jobs = [(sc.name, tyre, args.out) for sc in selected for tyre in sc.tyres]
    # longest simulations first, so the worker pool ends together
    jobs.sort(key=lambda j: -BY_NAME[j[0]].duration)
    seconds = print_jobs(run_one, jobs, args.jobs)
    n_files = sum(len(variants(BY_NAME[j[0]], j[1])) for j in jobs)
    print(f"{len(jobs)} simulation(s), {n_files} file(s) in {seconds:.1f} s -> {args.out}")


if __name__ == "__main__":
    main()
