#!/usr/bin/env python3
"""Write the scenario sensor logs (MODEL.md section 8, DATA.md) with the reference simulator.

    .venv/bin/python scripts/data/make_scenarios.py [--out scenarios] [--only NAME ...]
                                               [--tyre dugoff|mf] [--noise default|none]
                                               [--jobs N]

Default: every scenario, with the Dugoff (model-matched) truth tyre in both noise variants
and with the Magic-Formula truth tyre with default noise:
    <out>/<name>.csv      Dugoff truth, default sensor noise (seed = scenario index + 1)
    <out>/<name>.nf.csv   Dugoff truth, noise-free
    <out>/<name>.mf.csv   Magic-Formula truth (stiffness not scaling with mu), default noise
(make_goldens.py, demo.py and the reference tests skip the *.mf* files.)  --tyre restricts
the output to one truth tyre and then writes both of its noise variants (--tyre mf also
writes <name>.mf.nf.csv); --noise restricts it to one noise variant.  One progress line
per simulation: runtime, minimum vx and the per-wheel maxima of |kappa|, |alpha| [rad],
tyre utilisation sqrt(Fx^2+Fy^2)/(mu Fz) and the share of samples with utilisation >= 0.5
(order fl/fr/rl/rr).  Simulations run in --jobs worker processes (default: all CPUs);
deterministic either way: the same command writes the same bytes.
"""

import argparse
import os
import sys
import time

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)

from job_pool import print_jobs  # noqa: E402
from sim import sensors  # noqa: E402
from sim.scenarios import BY_NAME, SCENARIOS  # noqa: E402

V_END_MIN = 4.0  # m/s, every scenario must keep vx above this
DEFAULT_VARIANTS = {"dugoff": ("default", "none"), "mf": ("default",)}


def plan(tyre=None, noise=None):
    """{tyre: noise variants} to write for the command-line choices."""
    if tyre is not None:
        jobs = {tyre: ("default", "none")}
    else:
        jobs = dict(DEFAULT_VARIANTS)
    if noise is not None:
        jobs = {t: tuple(v for v in vs if v == noise) for t, vs in jobs.items()}
    return {t: vs for t, vs in jobs.items() if vs}


def run_one(job):
    """Simulate one (scenario, tyre) and write its noise variants; returns a report line."""
    name, tyre, variants, out, rate = job
    sc = BY_NAME[name]
    t0 = time.perf_counter()
    sim = sensors.run(sc, tyre=tyre, rate=rate)
    stats = sensors.summary(sim)
    if stats["min_vx"] <= V_END_MIN:
        raise SystemExit(f"{sc.name} ({tyre}): vx fell to {stats['min_vx']:.2f} m/s "
                         f"(must stay above {V_END_MIN} m/s)")
    table = sensors.sensor_table(sim)
    written = []
    for noise in variants:
        tab = sensors.add_noise(table, sc.seed) if noise == "default" else table
        meta = sensors.metadata(sc, noise, tyre, rate=rate)
        fname = sensors.file_name(sc.name, tyre, noise)
        path = os.path.join(out, fname)
        with open(path, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(sensors.csv_text(tab, meta))
        written.append(f"{fname} ({os.path.getsize(path) / 1e6:.2f} MB)")
    el = time.perf_counter() - t0
    slash = "/".join
    return (f"{sc.name:20s} {tyre:6s} {el:5.2f} s  min vx {stats['min_vx']:6.2f}"
            f"  max|kappa| {slash(f'{v:.3f}' for v in stats['kappa'])}"
            f"  max|alpha| {slash(f'{v:.3f}' for v in stats['alpha'])}"
            f"  max util {slash(f'{v:.3f}' for v in stats['util'])}"
            f"  util>=0.5 {slash(f'{v:.2f}' for v in stats['excited'])}"
            f"  -> {', '.join(written)}")


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(repo, "scenarios"),
                    help="output directory (default: <repo>/scenarios)")
    ap.add_argument("--only", nargs="+", metavar="NAME", choices=sorted(BY_NAME),
                    help="only these scenarios")
    ap.add_argument("--tyre", choices=("dugoff", "mf"),
                    help="only this truth tyre, both noise variants (default: dugoff both "
                         "variants + mf with default noise)")
    ap.add_argument("--noise", choices=("default", "none"),
                    help="write only this noise variant")
    ap.add_argument("--rate", type=int, default=sensors.DEFAULT_RATE,
                    help=f"RK4 integration rate, Hz (default {sensors.DEFAULT_RATE})")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1,
                    help="worker processes (default: number of CPUs)")
    args = ap.parse_args(argv)

    os.makedirs(args.out, exist_ok=True)
    selected = [sc for sc in SCENARIOS if not args.only or sc.name in args.only]
    jobs = [(sc.name, tyre, variants, args.out, args.rate)
            for sc in selected for tyre, variants in plan(args.tyre, args.noise).items()]
    n_files = sum(len(j[2]) for j in jobs)
    seconds = print_jobs(run_one, jobs, args.jobs, ordered=True)
    print(f"{len(jobs)} simulation(s), {n_files} file(s) in {seconds:.1f} s -> {args.out}")


if __name__ == "__main__":
    main()
