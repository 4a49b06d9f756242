#!/usr/bin/env python3
"""Write the scenario sensor logs (MODEL.md section 8, DATA.md) with the reference simulator.

    .venv/bin/python scripts/make_scenarios.py [--out scenarios] [--only NAME ...]
                                               [--tyre dugoff|mf] [--noise default|none]

Default: every scenario, both noise variants, Dugoff (model-matched) truth tyre:
    <out>/<name>.csv      default sensor noise (seed = scenario index + 1)
    <out>/<name>.nf.csv   noise-free
With --tyre mf the Magic-Formula truth tyre is used and the files are <name>.mf.csv and
<name>.mf.nf.csv.  --noise restricts the output to one variant.  One progress line per
scenario: runtime, minimum vx and the per-wheel maxima of |kappa|, |alpha| [rad] and tyre
utilisation sqrt(Fx^2+Fy^2)/(mu Fz) (order fl/fr/rl/rr).  Deterministic: the same command
writes the same bytes.
"""

import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from sim import sensors  # noqa: E402
from sim.scenarios import BY_NAME, SCENARIOS  # noqa: E402

V_END_MIN = 4.0  # m/s, every scenario must keep vx above this


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(repo, "scenarios"),
                    help="output directory (default: <repo>/scenarios)")
    ap.add_argument("--only", nargs="+", metavar="NAME", choices=sorted(BY_NAME),
                    help="only these scenarios")
    ap.add_argument("--tyre", choices=("dugoff", "mf"), default="dugoff",
                    help="truth tyre model (default dugoff)")
    ap.add_argument("--noise", choices=("default", "none"),
                    help="write only this noise variant (default: both)")
    ap.add_argument("--rate", type=int, default=sensors.DEFAULT_RATE,
                    help=f"RK4 integration rate, Hz (default {sensors.DEFAULT_RATE})")
    args = ap.parse_args(argv)

    os.makedirs(args.out, exist_ok=True)
    variants = [args.noise] if args.noise else ["default", "none"]
    selected = [sc for sc in SCENARIOS if not args.only or sc.name in args.only]
    t_all = time.perf_counter()
    slash = "/".join
    for sc in selected:
        t0 = time.perf_counter()
        sim = sensors.run(sc, tyre=args.tyre, rate=args.rate)
        stats = sensors.summary(sim)
        if stats["min_vx"] <= V_END_MIN:
            raise SystemExit(f"{sc.name}: vx fell to {stats['min_vx']:.2f} m/s "
                             f"(must stay above {V_END_MIN} m/s)")
        table = sensors.sensor_table(sim)
        written = []
        for noise in variants:
            tab = sensors.add_noise(table, sc.seed) if noise == "default" else table
            meta = sensors.metadata(sc, noise, args.tyre, rate=args.rate)
            name = sensors.file_name(sc.name, args.tyre, noise)
            with open(os.path.join(args.out, name), "w", encoding="utf-8", newline="\n") as fh:
                fh.write(sensors.csv_text(tab, meta))
            written.append(name)
        el = time.perf_counter() - t0
        print(f"{sc.name:20s} {el:5.2f} s  min vx {stats['min_vx']:6.2f}"
              f"  max|kappa| {slash(f'{v:.4f}' for v in stats['kappa'])}"
              f"  max|alpha| {slash(f'{v:.4f}' for v in stats['alpha'])}"
              f"  max util {slash(f'{v:.3f}' for v in stats['util'])}"
              f"  -> {', '.join(written)}", flush=True)
    print(f"{len(selected)} scenario(s) in {time.perf_counter() - t_all:.1f} s -> {args.out}")


if __name__ == "__main__":
    main()
