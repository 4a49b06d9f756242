#!/usr/bin/env python3
"""Issue 19: why the mass filter's mass is wrong on the observer logs' steady curves (the +5 deg
banked curve: -60 % with the car preset's resistances, +90 % with the simulator's, never fed;
MASS_GRADE_RESULTS.md "The online mass"), measured in the float64 reference
(scripts/reference/mass_grade.py).

    .venv/bin/python scripts/tools/mass_curve_study.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--jobs N]

The longitudinal model (MASS_GRADE.md §1) is a straight road's. In a curve two terms it does
not have appear (body axes, x forward; steady state, the car's speed held by cruise control):

- the cornering resistance: the drive torque pays for the lateral tyre forces' component
  against the direction of travel. From the body-x balance m (vx_dot - r vy) = sum of the
  body-x tyre forces and the front wheels' steer delta:
  T/R - (m + m_rot) vx_dot ~ F_c = m (ay Lr/(Lf + Lr) sin(delta) - r vy)
  (the front axle's lateral force m ay Lr/L from the yaw moment balance, turned by delta,
  and the sideslip's centripetal term); the drive torque's longitudinal forces at the front
  wheels are neglected (their 1 - cos delta ~ 5e-4).
- the accelerometer's sideslip term: ax = vx_dot - r vy (DATA.md), which the ax row
  (MASS_GRADE.md §5) reads as v_dot + g sin(theta), so -r vy appears as grade.

A banked road adds nothing to the body-x balance directly (gravity's body-x component is
-g sin(theta), theta the grade; the bank's g sin(phi) cos(theta) is lateral), but the tyres
carry it: ay (the specific force, what the tyres push) is V^2/R_c + g sin(phi), so F_c grows
on an adverse bank and shrinks on a favourable one.

Per log (the observer logs with a steady curve, scenarios/observer/): over t >= T_STEADY the
mean T/R - (m + m_rot) vx_dot (what the torque pays beyond accelerating the car: the
simulator has no rolling resistance, no drag, no grade on these logs), the mean of F_c above
from the log's ay, delta, yaw_rate and the truth vy_true, the mean -r vy; then the filter
(the recommended preset, UKF with the ax row, started at the log's m, the samples of
mass_slip_ramp_study.py) with the car preset's resistances, and with the simulator's
(mg_fc = mg_fr = mg_rho = 0) as the logs are, with the torque less R F_c, with ax + r vy, and
with both: the mass at the end against m (sd_mass / m) and the grade at the end.
With --page the table goes between <!-- mass-curve:begin --> and <!-- mass-curve:end -->.
"""

import multiprocessing
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from mass_slip_ramp_study import (RECOMMENDED, SIM_RESISTANCES, TORQUES,  # noqa: E402
                                  log_path, mg, observer_samples, study_main)
from mass_sensitivity import log_mass  # noqa: E402

LOGS = ("bank_curve_pos5", "bank_curve_neg5", "circle_r60", "ay_bias_curve")
SUFFIXES = (".nf.csv", ".csv")
T_STEADY = 6.0          # s: every curve is entered by then (bank 2-4 s, circle 1-3 s, bias 2-4 s)
# name -> (resistance overrides, correct the torque by F_c, correct ax by r vy)
VARIANTS = {"car preset": ({}, False, False), "sim's": (SIM_RESISTANCES, False, False),
            "sim's, T - R F_c": (SIM_RESISTANCES, True, False),
            "sim's, ax + r vy": (SIM_RESISTANCES, False, True),
            "sim's, both": (SIM_RESISTANCES, True, True)}


def cornering_force(cols, p, m):
    """F_c = m (ay Lr/(Lf + Lr) sin(delta) - r vy) per sample [N], the geometry p's."""
    return m * (cols["ay"] * p["Lr"] / (p["Lf"] + p["Lr"]) * np.sin(cols["delta"])
                - cols["yaw_rate"] * cols["vy_true"])


def log_meta(path):
    """The log's vehicle keys the study uses."""
    _, meta = mg.read_log(path)
    return {k: float(meta[k]) for k in ("Lf", "Lr", "R", "Iw")}


def steady(cols, p, m):
    """Means over t >= T_STEADY: the force the torque pays beyond accelerating the car,
    F_c, -r vy, ay; and vx's range there."""
    t = cols["t"]
    k = t >= T_STEADY - 1e-9
    m_rot = 4.0 * p["Iw"] / (p["R"] * p["R"])
    vx = cols["vx_true"][k]
    vdot = (vx[-1] - vx[0]) / (t[k][-1] - t[k][0])
    torque = sum(cols[c][k] for c in TORQUES)
    return {"paid": float(np.mean(torque) / p["R"] - (m + m_rot) * vdot),
            "f_c": float(np.mean(cornering_force(cols, p, m)[k])),
            "rvy": float(np.mean(-cols["yaw_rate"][k] * cols["vy_true"][k])),
            "ay": float(np.mean(cols["ay"][k]))}


def job(args):
    name, variant = args
    path = log_path(name)
    cols, _ = mg.read_log(path)
    m = log_mass(path)
    p = log_meta(path)
    over, fix_torque, fix_ax = VARIANTS[variant]
    est = mg.MassGrade(mg.preset("car", mg_m0=m, **RECOMMENDED, **over))
    f_c = cornering_force(cols, p, m)
    out = None
    for k, s in enumerate(observer_samples(cols, est.p["R"])):
        if fix_torque:
            s.torque -= est.p["R"] * f_c[k]
        if fix_ax:
            s.ax += cols["yaw_rate"][k] * cols["vy_true"][k]
        out = est.step(s)
    res = {"m": m, "mass": out.mass, "sd": out.sd_mass, "grade": out.grade}
    if variant == "car preset":
        res["steady"] = steady(cols, p, m)
    return (name, variant), res


def table(res, names):
    heads = list(VARIANTS)
    lines = [f"Steady curve (t ≥ {T_STEADY:g} s): the force the drive torque pays at constant "
             "speed, T/R − (m + m_rot)·v̇x (the simulator has no other resistance), against "
             "F_c = m·(ay·Lr/L·sin δ − r·vy); ay; −r·vy (the accelerometer's sideslip "
             "term). "
             "Then the mass at the end against m (sd_mass / m) and the grade at the end (mrad), "
             "float64 reference, recommended preset, from m:", "",
             "| log | T/R − (m + m_rot)·v̇x | F_c | ay | −r·vy | "
             + " | ".join(heads) + " |", "|---|---|---|---|---|" + "---|" * len(heads)]
    for n in names:
        st = res[(n, "car preset")]["steady"]
        cells = []
        for v in heads:
            r = res[(n, v)]
            cells.append(f"{(r['mass'] - r['m']) / r['m']:+.1%} ({r['sd'] / r['m']:.1%}), "
                         f"{1e3 * r['grade']:+.1f}")
        lines.append(f"| {n[:-4]} | {st['paid']:.0f} N | {st['f_c']:.0f} N | "
                     f"{st['ay']:.3f} m/s² | {st['rvy']:+.3f} m/s² | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def results_text(n_jobs):
    """The study's table: every log and its noise-free twin, every variant."""
    names = [n + s for n in LOGS for s in SUFFIXES]
    jobs = [(n, v) for n in names for v in VARIANTS]
    with multiprocessing.Pool(n_jobs) as pool:
        res = dict(pool.map(job, jobs, chunksize=2))
    return table(res, names)


def main(argv=None):
    study_main(argv, __doc__, "mass-curve", "mass_curve_study", results_text)


if __name__ == "__main__":
    main()
