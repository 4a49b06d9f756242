#!/usr/bin/env python3
"""Issue 19: the grade's two-level random walk (mg_q_theta_hi, MASS_GRADE.md §4.7), measured.

    .venv/bin/python scripts/tools/mass_grade_walk_study.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--jobs N]

Every mass and grade log (scenarios/mass_grade/, scripts/tools/mass_logs.py), its vehicle's
recommended preset (the reference's MG_CONFIGS), from the accuracy table's four initial masses
(-50, -20, +20, +50 % of the truth), in three walks: fixed (mg_q_theta 0.004, the walk off),
a fixed looser walk (mg_q_theta 0.006) and the two-level walk (mg_q_theta 0.004 while the grade rests,
mg_q_theta_hi 0.008 while it moves, rate thresholds 0.002 / 0.001 rad/s, low-pass 1 s, mean of
the square 3 s). Measured as the accuracy table measures (mass_grade_results.metrics): the
worst grade RMSE from 10 s after the first excitation, the largest |mass error| after it, and
on car_grade_step the worst grade error 2-10 s after the step; and the share of the updates
run with the loose level. With --page the table is written between the markers
<!-- mass-grade-walk:begin/end -->.
"""

import argparse
import multiprocessing
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from reference import mass_grade as mg  # noqa: E402
from mass_logs import MG_DIR, mass_grade_names  # noqa: E402
import mass_grade_results as mgr  # noqa: E402

TWO_LEVEL = {"mg_q_theta": 0.004, "mg_q_theta_hi": 0.008, "mg_theta_rate_on": 0.002,
             "mg_theta_rate_off": 0.001, "mg_theta_rate_tau": 1.0, "mg_theta_rate_avg": 3.0}
# the recommended preset has the two-level walk on (MG_CONFIGS): the fixed walks turn it off
WALKS = {"fixed 0.004": {"mg_q_theta_hi": 0.0},
         "fixed 0.006": {"mg_q_theta": 0.006, "mg_q_theta_hi": 0.0}, "two-level": TWO_LEVEL}
TARGET_DEG = 0.3            # issue 19: grade RMSE on the graded drives


def one(job):
    name, guess, walk = job
    cols, _ = mg.read_log(os.path.join(MG_DIR, name + ".csv"))
    mt = float(cols["mass_true"][0])
    p = mg.preset(mgr.vehicle(name), **mg.MG_CONFIGS["recommended"])
    p.update(WALKS[walk], mg_m0=mt * (1.0 + guess))
    est = mg.MassGrade(p)
    outs, hi = [], []
    for s in mg.samples(cols, est.p):
        outs.append(est.step(s))
        hi.append(est.wq_hi)
    r = {"t": np.asarray(cols["t"], dtype=float)}
    for k in ("mass", "sd_mass", "grade", "sd_grade", "status"):
        r[k] = np.array([getattr(o, k) for o in outs])
    m = mgr.metrics(name, cols, r)
    ok = r["status"] == mg.OK
    m["hi_share"] = float(np.mean(np.asarray(hi)[ok])) if ok.any() else 0.0
    return job, m


def table(res, names):
    walks = list(WALKS)
    head = "| log | " + " | ".join(f"grade RMSE, {w}" for w in walks) + " | " + " | ".join(
        f"largest mass error, {w}" for w in walks) + " | loose level's share of the updates |"
    lines = [head, "|---" * (2 + 2 * len(walks)) + "|"]
    for n in names:
        ms = {w: [res[(n, g, w)] for g in mgr.GUESSES] for w in walks}
        rm = [f"{max(m['rmse'] for m in ms[w]):.3f} deg" for w in walks]
        if "step" in ms[walks[0]][0]:
            rm = [f"{r} (step {max(m['step'] for m in ms[w]):.2f})" for r, w in zip(rm, walks)]
        me = [f"{max(m['err_after'] for m in ms[w]):.2f} %" for w in walks]
        share = max(m["hi_share"] for m in ms["two-level"]) * 100.0
        lines.append(f"| {n} | " + " | ".join(rm) + " | " + " | ".join(me) + f" | {share:.0f} % |")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", help="write the table into this page between its markers")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    a = ap.parse_args(argv)
    names = mass_grade_names()
    jobs = [(n, g, w) for n in names for w in WALKS for g in mgr.GUESSES]
    with multiprocessing.Pool(a.jobs) as pool:
        res = dict(pool.map(one, jobs))
    lines = table(res, names)
    print("\n".join(lines))
    if a.page:
        with open(a.page, encoding="utf-8") as f:
            text = f.read()
        text = mgr.replace_block(text, "walk", "\n".join(lines) + "\n")
        with open(a.page, "w", encoding="utf-8") as f:
            f.write(text)


if __name__ == "__main__":
    main()
