#!/usr/bin/env python3
"""Write the tyre identification logs (scripts/sim/tyre_id_scenarios.py, docs/TYRE_ID.md §8,
DATA.md "Tyre identification truth") with the reference simulator.

    .venv/bin/python scripts/data/make_tyre_id_scenarios.py [--out scenarios/tyre_id]
                                                        [--only NAME ...] [--jobs N]

One log per scenario, <out>/<name>.csv: the Magic Formula truth (per axle, tyre_map) with the
default sensor noise of the friction logs (sensors.NOISE_SD; seed 301 + index), the sensor
columns of DATA.md, the observer logs' vx_true, vy_true, beta_true, yaw_acc_true, and the
per-axle truth: B, C, D, E, the lateral force and the slip angle of each axle.  Deterministic:
the same command writes the same bytes.
"""

import argparse
import os
import sys
import time

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]

import numpy as np  # noqa: E402

from job_pool import print_jobs  # noqa: E402
from sim import sensors  # noqa: E402
from sim.tyre_id_scenarios import TID_BY_NAME, TID_SCENARIOS  # noqa: E402
from sim.vehicle import ESTIMATOR_KEYS, MF_KEYS, SIM_KEYS, Params, simulate  # noqa: E402

TRUTH = ["vx_true", "vy_true", "beta_true", "yaw_acc_true"]
AXLE_TRUTH = [f"{k}_{a}_true" for a in ("f", "r") for k in ("B", "C", "D", "E")] + \
    ["Fy_f_true", "Fy_r_true", "alpha_f_true", "alpha_r_true"]
COLUMNS = list(sensors.COLUMNS) + TRUTH + AXLE_TRUTH


def table(sc, sim, p):
    """Noise-free columns of one log (dict column -> array)."""
    tab = sensors.sensor_table(sim)
    vx, vy, r = (np.asarray(sim[k], dtype=float) for k in ("vx", "vy", "yaw_rate"))
    tab["vx_true"], tab["vy_true"] = vx.copy(), vy.copy()
    tab["beta_true"] = np.arctan2(vy, vx)
    tab["yaw_acc_true"] = np.asarray(sim["yaw_acc"], dtype=float).copy()
    t = sim["t"]
    for a, (i, j) in (("f", (0, 1)), ("r", (2, 3))):
        tyre = [sc.axle_tyres(float(tk))[0 if a == "f" else 1] for tk in t]
        mu_axle = 0.5 * (sim["mu"][:, i] + sim["mu"][:, j])
        C = np.array([ty.C for ty in tyre])
        tab[f"C_{a}_true"] = C
        tab[f"E_{a}_true"] = np.array([ty.E for ty in tyre])
        # peak of the axle at its present load (each wheel's peak is mu Fz, tyres.py)
        tab[f"D_{a}_true"] = sim["mu"][:, i] * sim["Fz"][:, i] + sim["mu"][:, j] * sim["Fz"][:, j]
        # slope at zero slip B C D = cy Fz: B = cy / (C mu)
        tab[f"B_{a}_true"] = np.array([ty.cy for ty in tyre]) / (C * mu_axle)
        tab[f"Fy_{a}_true"] = sim["Fy"][:, i] + sim["Fy"][:, j]
    d = np.asarray(sim["delta"], dtype=float)
    tab["alpha_f_true"] = d - np.arctan2(vy + p.Lf * r, vx)
    tab["alpha_r_true"] = -np.arctan2(vy - p.Lr * r, vx)
    return tab


def metadata(sc, p, rate):
    meta = [("scenario", sc.name), ("description", sc.description), ("dt", sensors.DT),
            ("seed", sc.seed), ("noise", "default"), ("truth_tyre", "mf"), ("abs", "off"),
            ("driver_steer", "open_loop")]
    meta += p.items(ESTIMATOR_KEYS) + p.items(SIM_KEYS) + p.items(MF_KEYS)
    meta += [(f"noise_{c}", sensors.NOISE_SD[c]) for c in sensors.NOISY_COLUMNS]
    meta += [("sim_integrator", "rk4"), ("sim_rate", rate), ("v0", sc.v0),
             ("duration", sc.duration)]
    # the truth tyres, per axle and from when (information an estimator ignores)
    for k, (t0, f, r) in enumerate(sc.tyres):
        sfx = "" if k == 0 else f"_{k}"
        if k > 0:
            meta.append((f"truth_from{sfx}", float(t0)))
        meta += [(f"truth_cy_f{sfx}", f.cy), (f"truth_mf_Cy_f{sfx}", f.C),
                 (f"truth_mf_Ey_f{sfx}", f.E), (f"truth_cy_r{sfx}", r.cy),
                 (f"truth_mf_Cy_r{sfx}", r.C), (f"truth_mf_Ey_r{sfx}", r.E)]
    return meta


def csv_text(tab, meta):
    lines = [f"# {k} = {v!r}" if isinstance(v, float) else f"# {k} = {v}" for k, v in meta]
    lines.append(",".join(COLUMNS))
    cols = [tab[c].tolist() for c in COLUMNS]
    for row in zip(*cols):
        lines.append(",".join(map(repr, row)))
    return "\n".join(lines) + "\n"


def run_one(job):
    name, out, rate = job
    sc = TID_BY_NAME[name]
    p = Params()
    t0 = time.perf_counter()
    sim = simulate(sc.inputs, sc.mu_map(), sc.v0, sc.duration, p, "mf", sensors.DT, rate,
                   tyre_map=sc.tyre_map(p))
    tab = sensors.add_noise(table(sc, sim, p), sc.seed)
    path = os.path.join(out, sc.name + ".csv")
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        fh.write(csv_text(tab, metadata(sc, p, rate)))
    util = sensors.utilisation(sim).max(axis=0)
    return (f"{sc.name:24s} {time.perf_counter() - t0:5.1f} s  min vx "
            f"{float(np.min(sim['vx'])):6.2f}  max|beta| "
            f"{np.degrees(np.abs(tab['beta_true'])).max():5.2f} deg  max util "
            f"{'/'.join(f'{u:.3f}' for u in util)}  -> {path} "
            f"({os.path.getsize(path) / 1e6:.2f} MB)")


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default=os.path.join(repo, "scenarios", "tyre_id"))
    ap.add_argument("--only", nargs="+", metavar="NAME", choices=sorted(TID_BY_NAME))
    ap.add_argument("--rate", type=int, default=sensors.DEFAULT_RATE)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = ap.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    jobs = [(sc.name, args.out, args.rate) for sc in TID_SCENARIOS
            if not args.only or sc.name in args.only]
    jobs.sort(key=lambda j: -TID_BY_NAME[j[0]].duration)  # longest first
    seconds = print_jobs(run_one, jobs, args.jobs, ordered=True)
    print(f"{len(jobs)} log(s) in {seconds:.1f} s -> {args.out}")


if __name__ == "__main__":
    main()
