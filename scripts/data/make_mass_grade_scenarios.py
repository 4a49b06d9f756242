#!/usr/bin/env python3
"""Write the mass and grade scenario logs (scripts/sim/mass_grade_scenarios.py, DATA.md "Mass
and grade logs") with the reference simulator.

    .venv/bin/python scripts/data/make_mass_grade_scenarios.py [--out scenarios/mass_grade]
                                                            [--only NAME ...] [--jobs N]

One noisy log per scenario, <out>/<name>.csv (seed 301 + index).  One progress line per
simulation: runtime, speed range [km/h], max |a| and mean |a| [m/s^2], grade range [deg],
file size.  Simulations run in --jobs worker processes (default: all CPUs), the longest
first; deterministic either way: the same command writes the same bytes.
"""

import argparse
import os
import sys
import time

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                 os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]

import numpy as np  # noqa: E402

from job_pool import print_jobs  # noqa: E402
from sim import mass_grade_scenarios as mg  # noqa: E402


def run_one(job):
    name, out = job
    sc = mg.MG_BY_NAME[name]
    t0 = time.perf_counter()
    sim = mg.run(sc)
    tab = mg.table(sim, sc)
    path = os.path.join(out, sc.name + ".csv")
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(mg.csv_text(mg.noisy(tab, sc), mg.metadata(sc)))
    a = np.asarray(sim["vx_dot"])
    g = np.degrees(np.asarray(sim["grade"]))
    v = np.asarray(sim["vx"]) * 3.6
    return (f"{sc.name:20s} {time.perf_counter() - t0:6.1f} s  v {v.min():5.1f}..{v.max():5.1f} "
            f"km/h  max|a| {np.abs(a).max():.3f} mean|a| {np.abs(a).mean():.3f} m/s^2  grade "
            f"{g.min():+.2f}..{g.max():+.2f} deg  s {sim['s'][-1]:.0f} m  -> {sc.name}.csv "
            f"({os.path.getsize(path) / 1e6:.2f} MB)")


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(repo, "scenarios", "mass_grade"),
                    help="output directory (default: <repo>/scenarios/mass_grade)")
    ap.add_argument("--only", nargs="+", metavar="NAME", choices=sorted(mg.MG_BY_NAME),
                    help="only these scenarios")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="worker processes (default: number of CPUs)")
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    sel = [sc for sc in mg.MASS_GRADE_SCENARIOS if not args.only or sc.name in args.only]
    # longest simulations first (sub-steps), so the worker pool ends together
    sel.sort(key=lambda sc: -sc.duration * sc.rate)
    jobs = [(sc.name, args.out) for sc in sel]
    seconds = print_jobs(run_one, jobs, args.jobs)
    print(f"{len(jobs)} log(s) in {seconds:.1f} s -> {args.out}")


if __name__ == "__main__":
    main()
