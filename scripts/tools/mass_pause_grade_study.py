#!/usr/bin/env python3
"""Issue 19: the grade learned from ax during the mass filter's pauses (mg_pause_grade), measured
in the float64 reference (scripts/reference/mass_grade.py) on the mass and grade logs and on
the observer logs (noisy, noise-free, the `_res` ones with the car's resistances).

    .venv/bin/python scripts/tools/mass_pause_grade_study.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--jobs N]

In a pause (brake, gear shift, curve) the filter holds M and theta. With the accelerometer
row on, the grade stays observable without the mass model (v-dot = a_x - g sin theta), so
mg_pause_grade lets the chosen pauses run that kinematic model on v and theta while M and its
row of S stay untouched (MASS_GRADE.md §4.2). Variants, all in the recommended preset (UKF with
the ax row) with the curve pause at its documented setting for a car that corners (mg_ay_max
1 m/s^2, mg_t_curve 1 s), mg_pause_grade 0 (off, the filter as it is), 1 (brake), 2 (shift),
4 (curve), 7 (all three), each with the ABS gate at its default (mg_pause_grade_slip 0.05:
a paused sample whose wheels slip beyond 5 % of vx ends the grade's learning until the pause
ends) and the change test at its default (mg_pause_grade_dv 0.2 m/s: a pause learns only once
the speed, vx where given, has left the held grade's prediction by 0.2 m/s), and 1 twice more:
without the change test ("brake, no test": the mode as it was before the test) and without
either ("brake, no gate": as it was before the gate).
Runs: the mass and grade logs in their vehicle's preset from 0.8 times the truth;
the observer logs (the samples of mass_slip_ramp_study.py, the simulator's resistances, the
`_res` logs the car preset's) from the log's m. A log whose run with mg_pause_grade off held
no sample in a brake, shift or curve pause is run once only: no variant can change it (the
pause kind decides alone, MASS_GRADE.md §4.2). Per run: the mass error at the end, the grade RMSE against grade_true over the log and
over the samples paused by brake, shift or curve, and their share. For the two logs made for
the mode (CASES: the grade changes within a long brake pause and within a long curve pause)
also the grade RMSE in the AFTER s after the pauses, the worst grade error in and after them
and the mass's move after them (summary()).
"""

import multiprocessing
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from mass_slip_ramp_study import (RECOMMENDED, SIM_RESISTANCES, log_path, mg,  # noqa: E402
                                  observer_samples, res_logs, study_main)
from mass_sensitivity import log_mass  # noqa: E402
from mass_logs import mass_grade_logs  # noqa: E402

CURVE = {"mg_ay_max": 1.0, "mg_t_curve": 1.0}   # MASS_GRADE.md §4.2's setting for a car that corners
VARIANTS = {"off": 0, "brake, no gate": 1, "brake, no test": 1, "brake": 1, "shift": 2,
            "curve": 4, "all": 7}
# the variants run without the ABS gate and the change test (mg_pause_grade_slip 0,
# mg_pause_grade_dv 0: the brake bit as it was before both) and without the change test (the
# brake bit as it was before it); every other runs with both at their defaults (MASS_GRADE.md
# §4.2)
UNGATED = {"brake, no gate": {"mg_pause_grade_slip": 0.0, "mg_pause_grade_dv": 0.0},
           "brake, no test": {"mg_pause_grade_dv": 0.0}}
OBS_STARTS = (1.0,)
MG_STARTS = (0.8,)
PAUSES = (mg.PAUSED_BRAKE, mg.PAUSED_SHIFT, mg.PAUSED_CURVE)
AFTER = 5.0     # s: the catch-up after a pause the figures look at (the update's recovery)
# the logs made for the mode: the grade changes within a long brake pause (-6 % -> +2 %) and
# within a long curve pause (+5 % -> -4 %), scripts/sim/mass_grade_scenarios.py
CASES = ("car_valley_brake.csv", "car_long_curve_crest.csv")


def summary(outs, cols, m):
    """A run's figures: the mass error at the end; the grade RMSE over the log, over the
    brake, shift and curve pauses (`held`, their share) and over the samples within AFTER s
    after a paused one that are not paused themselves (the catch-up); the worst |grade error|
    over those two sets; and the mass's move in that catch-up, max |M - M at the last paused
    sample before| / m."""
    grade = np.array([o.grade for o in outs])
    mass = np.array([o.mass for o in outs])
    err = grade - cols["grade_true"]
    held = np.array([o.status in PAUSES for o in outs])
    t = np.asarray(cols["t"], dtype=float)
    after = np.zeros(len(outs), dtype=bool)
    move = 0.0
    t_held, m_held = -np.inf, 0.0
    for k in range(len(outs)):
        if held[k]:
            t_held, m_held = t[k], mass[k]
        elif t[k] - t_held <= AFTER:
            after[k] = True
            move = max(move, abs(mass[k] - m_held) / m)
    rms = lambda sel: float(np.sqrt(np.mean(err[sel] ** 2))) if sel.any() else float("nan")
    both = held | after
    return {"mass_err": (outs[-1].mass - m) / m,
            "rmse": float(np.sqrt(np.mean(err * err))),
            "rmse_held": rms(held),
            "held": float(np.mean(held)),
            "rmse_after": rms(after),
            "peak": float(np.max(np.abs(err[both]))) if both.any() else float("nan"),
            "mass_move": float(move)}


def observer_job(name, start, variant):
    path = log_path(name)
    cols, _ = mg.read_log(path)
    m = log_mass(path)
    over = {} if name.split(".", 1)[0].endswith("_res") else SIM_RESISTANCES
    est = mg.MassGrade(mg.preset("car", mg_m0=m * start, **CURVE,
                                 **dict(RECOMMENDED, mg_pause_grade=VARIANTS[variant]), **over,
                                 **UNGATED.get(variant, {})))
    samples = observer_samples(cols, est.p["R"])
    for s, ay in zip(samples, cols["ay"]):
        s.ay = float(ay)
    return summary([est.step(s) for s in samples], cols, m)


def mass_grade_job(name, start, variant, true_speed=False):
    cols, _ = mg.read_log(os.path.join(ROOT, "scenarios", "mass_grade", name))
    vehicle = "truck" if name.startswith("truck") else "car"
    m = float(cols["mass_true"][-1])
    est = mg.MassGrade(mg.preset(vehicle, mg_m0=start * float(cols["mass_true"][0]),
                                 **CURVE, **dict(RECOMMENDED, mg_pause_grade=VARIANTS[variant]),
                                 **UNGATED.get(variant, {})))
    samples = list(mg.samples(cols, est.p))
    for s, vx in zip(samples, cols["vx_true"]):
        s.vx = float(vx)
        if true_speed:
            s.v = s.vx      # the car's speed in place of the wheels' (no brake or drive slip)
    return summary([est.step(s) for s in samples], cols, m)


def job(j):
    kind, name, start, variant = j
    if kind == "true":
        return j, mass_grade_job(name, start, variant, true_speed=True)
    f = observer_job if kind == "obs" else mass_grade_job
    return j, f(name, start, variant)


def cell(r):
    held = "" if r["held"] == 0.0 else f", {1e3 * r['rmse_held']:.2f}"
    return f"{r['mass_err']:+.2%}, {1e3 * r['rmse']:.2f}{held}"


def table(res, kind, names, starts):
    heads = list(VARIANTS)
    lines = ["| log | mg_m0 | held | " + " | ".join(heads) + " |",
             "|---|---|---|" + "---|" * len(heads)]
    quiet = []
    for n in names:
        if max(res[(kind, n, s, "off")]["held"] for s in starts) == 0.0:
            quiet.append(n)
            continue
        for s in starts:
            r0 = res[(kind, n, s, "off")]
            if r0["held"] == 0.0:
                continue
            lines.append(f"| {n[:-4]} | {s:.1f} | {r0['held']:.0%} | "
                         + " | ".join(cell(res[(kind, n, s, v)]) for v in heads) + " |")
    if quiet:
        lines += ["", f"Not listed: {len(quiet)} logs with no brake, shift or curve pause ("
                  + ", ".join(n[:-4] for n in quiet) + ")."]
    return lines


def case_table(res, names, start):
    """The logs whose grade changes within a pause, one row per variant."""
    lines = [f"| log | mg_pause_grade | grade RMSE in the pauses | in the {AFTER:g} s after | "
             "over the log | worst \\|grade error\\| in and after | mass error at the end | "
             "mass move after |", "|---|---|---|---|---|---|---|---|"]
    for n in names:
        for v, bits in VARIANTS.items():
            r = res.get(("mg", n, start, v))
            if r is None:
                continue
            lines.append(f"| {n[:-4]} | {v} ({bits}) | {1e3 * r['rmse_held']:.2f} | "
                         f"{1e3 * r['rmse_after']:.2f} | {1e3 * r['rmse']:.2f} | "
                         f"{1e3 * r['peak']:.1f} | {r['mass_err']:+.2%} | "
                         f"{r['mass_move']:.2%} |")
    return lines


def same(r, r0):
    """Two runs' figures equal (a figure of no sample, nan, is the same in both)."""
    return all(r[k] == r0[k] or (np.isnan(r[k]) and np.isnan(r0[k])) for k in r0)


def gate_table(res, jobs):
    """The ABS gate and the change test before -> after: every run whose brake bit the gate or
    the test changed, and car_valley_brake (the mode's case): grade RMSE over the brake, shift
    and curve pauses and over the AFTER s after them (mrad), the mass error at the end, with
    mg_pause_grade off, with the brake bit without the gate, with it, and with the test too."""
    lines = [f"| log | mg_m0 | off: pauses, {AFTER:g} s after, mass | brake, no gate | "
             "brake, gated | brake, gated and tested |", "|---|---|---|---|---|---|"]
    f = lambda r: (f"{1e3 * r['rmse_held']:.2f}, {1e3 * r['rmse_after']:.2f}, "
                   f"{r['mass_err']:+.2%}")
    for j in jobs:
        if j[3] != "brake" or j[0] == "true":
            continue
        r, r0 = res[j[:3] + ("brake, no test",)], res[j[:3] + ("brake, no gate",)]
        if same(r, r0) and same(res[j], r) and j[1] != "car_valley_brake.csv":
            continue
        lines.append(f"| {j[1][:-4]} | {j[2]:.1f} | {f(res[j[:3] + ('off',)])} | {f(r0)} | "
                     f"{f(r)} | {f(res[j])} |")
    return lines


def verdict(res, jobs):
    """Per variant: the runs it changed, how many it helped / hurt in grade RMSE (more than
    0.05 mrad) and in |mass error| (more than 0.05 % of m), and the worst of each."""
    lines = ["", "| variant | runs moved | grade RMSE better / worse | worst grade RMSE change "
             "(mrad) | \\|mass error\\| better / worse | worst \\|mass error\\| change |",
             "|---|---|---|---|---|---|"]
    for v in list(VARIANTS)[1:]:
        moved = better = worse = mb = mw = 0
        worst_g, worst_m = (0.0, ""), (0.0, "")
        for j in jobs:
            if j[3] != v or j not in res or j[0] == "true":
                continue
            r, r0 = res[j], res[j[:3] + ("off",)]
            if same(r, r0):
                continue
            moved += 1
            dg = 1e3 * (r["rmse"] - r0["rmse"])
            dm = abs(r["mass_err"]) - abs(r0["mass_err"])
            better += dg < -0.05
            worse += dg > 0.05
            mb += dm < -5e-4
            mw += dm > 5e-4
            tag = f"{j[1][:-4]} {j[2]:.1f}"
            worst_g = max(worst_g, (dg, tag))
            worst_m = max(worst_m, (dm, tag))
        lines.append(f"| {v} | {moved} | {better} / {worse} | {worst_g[0]:+.2f} ({worst_g[1]}) | "
                     f"{mb} / {mw} | {worst_m[0]:+.2%} ({worst_m[1]}) |")
    return lines


def results_text(n_jobs):
    """The study's text: every log and start without the mode, then the runs it changes."""
    obs_dir = os.path.join(ROOT, "scenarios", "observer")
    obs_names = sorted(f for f in os.listdir(obs_dir)
                       if f.endswith(".csv") and not f.endswith(".mf.csv")) + [
        n for n in res_logs() if not n.endswith(".mf.csv")]
    mg_names = mass_grade_logs()
    first = [("mg", n, s, "off") for n in mg_names for s in MG_STARTS]
    first += [("obs", n, s, "off") for n in obs_names for s in OBS_STARTS]
    with multiprocessing.Pool(n_jobs) as pool:
        res = dict(pool.map(job, first, chunksize=1))
        jobs = [j[:3] + (v,) for j in first if res[j]["held"] > 0.0 for v in list(VARIANTS)[1:]]
        true = [("true",) + j[1:3] + (v,) for j in first
                if j[0] == "mg" and res[j]["held"] > 0.0 for v in VARIANTS]
        res.update(pool.map(job, jobs + true, chunksize=1))
    text = ["Cells: mass error at the end, grade RMSE over the log (mrad) and, where the run "
            "held samples, the grade RMSE over the brake, shift and curve pauses (mrad); "
            "`held`: their share with mg_pause_grade off. Recommended preset (UKF with the ax "
            "row), curve pause at 1 m/s^2 for 1 s, the ABS gate mg_pause_grade_slip at 0.05 but in "
            "`brake, no gate` (0), the change test mg_pause_grade_dv at 0.2 m/s but in `brake, "
            "no gate` and `brake, no test` (0); float64 reference. The mass and grade logs "
            "(vx_true as the ground speed):", ""]
    text += table(res, "mg", mg_names, MG_STARTS)
    text += ["", "The observer logs (the simulator's resistances; `_res`: the car preset's):", ""]
    text += table(res, "obs", obs_names, OBS_STARTS)
    text += verdict(res, jobs)
    text += ["", "The ABS gate (mg_pause_grade_slip 0.05) and the change test (mg_pause_grade_dv "
             "0.2 m/s) before -> after, the brake bit: every run either changed, and "
             "car_valley_brake; grade RMSE over the pauses and over "
             f"the {AFTER:g} s after them (mrad), mass error at the end:", ""]
    text += gate_table(res, jobs)
    text += ["", "The mass and grade logs that pause again, with the car's speed vx_true in place "
             "of the wheels' (no brake or drive slip in v; a diagnosis, not a configuration):",
             ""]
    text += table(res, "true", [n for n in mg_names if ("true", n, MG_STARTS[0], "off") in res],
                  MG_STARTS)
    cases = [n for n in CASES if n in mg_names]
    if cases:
        text += ["", "The logs whose grade changes within a long pause (" + ", ".join(
            n[:-4] for n in cases) + "), wheel speeds as above, from "
            f"{MG_STARTS[0]:g} times the mass: grade RMSE (mrad) over the brake, shift and "
            f"curve pauses, over the non-paused samples within {AFTER:g} s after one, over the "
            "log; the worst |grade error| over both (mrad); the mass error at the end; the "
            f"mass's move in those {AFTER:g} s (the largest |M - M at the pause's end| / m):", ""]
        text += case_table(res, cases, MG_STARTS[0])
    return "\n".join(text)


def main(argv=None):
    study_main(argv, __doc__, "mass-pause-grade", "mass_pause_grade_study", results_text)


if __name__ == "__main__":
    main()
