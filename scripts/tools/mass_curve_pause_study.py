#!/usr/bin/env python3
"""Issue 19: a curve pause for the mass filter, or the cornering resistance taken out of the
drive force, measured in the float64 reference (scripts/reference/mass_grade.py) on every
observer log, the observer logs with the car's resistances and the mass and grade logs.

    .venv/bin/python scripts/tools/mass_curve_pause_study.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--jobs N]

make mass-curve (mass_curve_study.py) showed why the mass is wrong on a steady curve: the
drive torque also pays the cornering resistance F_c = M (ay Lr/L sin(delta) - r vy), which the
straight-road model reads as mass, and the ax row reads the sideslip term -r vy as grade.
Variants here (the pause is the library's mg_ay_max, off by default; the correction is not):

- off: the filter as it is;
- pause |ay| > A (A = 0.5, 1, 2 m/s^2): the reference's curve pause, mg_ay_max = A and
  mg_t_curve = HOLD (MASS_GRADE.md §4.2: a sample whose |ay| exceeds A holds the filter as a
  braked one does, M and theta held, and the hold lasts HOLD s after the last such sample;
  status 8);
- F_c out: no pause; every sample's torque less R M^ (ay Lr/L sin(delta) - r vy) and its ax
  plus r vy, M^ the filter's mass before the sample, vy the log's measured vy (the observer
  scenarios carry it, noisy; the velocity observer's estimate would take its place in a car);
  the mass and grade logs have no vy: 0 there.

Runs: the observer logs (scenarios/observer/, noisy and noise-free, the samples of
mass_slip_ramp_study.py: wheels' speed, summed torque, brake pressure, ax, the log's vx) with
the simulator's resistances (mg_fc = mg_fr = mg_rho = 0, the model of those logs), the
observer logs with the car's resistances (scenarios/observer_res/) with the car preset, both in
the recommended preset (UKF with the ax row) from 1.0, 0.8 and 1.2 times the log's m; the mass
and grade logs (scenarios/mass_grade/) in their vehicle's recommended preset and the seed's
AUKF (speed only) from 0.8 times the truth, vx_true as the ground speed. Per run: the mass
error at the end, the grade RMSE against grade_true over the whole log, the share of samples
the curve pause held. With --page the text goes between <!-- mass-curve-pause:begin --> and
<!-- mass-curve-pause:end -->.
"""

import math
import multiprocessing
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from mass_slip_ramp_study import (RECOMMENDED, SIM_RESISTANCES, mass_grade_log,  # noqa: E402
                                  mass_grade_logs, mg, observer_log, observer_samples, res_logs,
                                  study_main, true_speed_samples)

PAUSED_CURVE = mg.PAUSED_CURVE
HOLD = 1.0                  # s: the curve pause's hold after the last sample over A (mg_t_brake's)
THRESHOLDS = (0.5, 1.0, 2.0)  # m/s^2
STARTS = (1.0, 0.8, 1.2)    # mg_m0 as a share of the log's m
MG_START = 0.8              # the mass and grade logs' start as a share of the truth
# name -> (ay threshold or 0, correct by F_c)
VARIANTS = {"off": (0.0, False)}
VARIANTS.update({f"pause |ay| > {a:g}": (a, False) for a in THRESHOLDS})
VARIANTS["F_c out"] = (0.0, True)
MG_CONFIGS = {"UKF + ax": RECOMMENDED, "AUKF": {"mg_adaptive": 1.0, "mg_use_ax": 0.0}}


def run(est, samples, ay, corr, fc_terms, vy_r):
    """Steps @est through @samples; @fc_terms per sample (ay Lr/L sin(delta) - r vy) and
    @vy_r (r vy) are taken out of the torque and put into ax when @corr. Returns the outputs."""
    outs = []
    R = est.p["R"]
    for k, s in enumerate(samples):
        s.ay = float(ay[k])
        if corr:
            m_hat = est.x[1] if est.started else est.p["mg_m0"]
            s.torque -= R * m_hat * float(fc_terms[k])
            if s.ax is not None:
                s.ax += float(vy_r[k])
        outs.append(est.step(s))
    return outs


def summary(outs, cols, m):
    grade = np.array([o.grade for o in outs])
    err = grade - cols["grade_true"]
    return {"mass_err": (outs[-1].mass - m) / m, "sd": outs[-1].sd_mass / m,
            "grade_rmse": float(np.sqrt(np.mean(err * err))),
            "curve": float(np.mean([o.status == PAUSED_CURVE for o in outs])),
            "ok": float(np.mean([o.status == mg.OK for o in outs]))}


def terms(cols, meta, vy):
    lr_l = float(meta["Lr"]) / (float(meta["Lf"]) + float(meta["Lr"]))
    r = cols["yaw_rate"]
    return cols["ay"] * lr_l * np.sin(cols["delta"]) - r * vy, r * vy


def observer_job(job):
    name, start, variant = job
    cols, meta, m = observer_log(name)
    ay_max, corr = VARIANTS[variant]
    over = {} if name.split(".", 1)[0].endswith("_res") else SIM_RESISTANCES
    est = mg.MassGrade(mg.preset("car", mg_m0=m * start, mg_ay_max=ay_max, mg_t_curve=HOLD,
                                 **RECOMMENDED, **over))
    fc, vy_r = terms(cols, meta, cols["vy"])
    outs = run(est, observer_samples(cols, est.p["R"]), cols["ay"], corr, fc, vy_r)
    return ("obs", name, start, variant), summary(outs, cols, m)


def mass_grade_job(job):
    name, cfg, variant = job
    cols, meta, vehicle = mass_grade_log(name)
    m = float(cols["mass_true"][-1])
    ay_max, corr = VARIANTS[variant]
    est = mg.MassGrade(mg.preset(vehicle, mg_m0=MG_START * float(cols["mass_true"][0]),
                                 mg_ay_max=ay_max, mg_t_curve=HOLD, **MG_CONFIGS[cfg]))
    samples = true_speed_samples(cols, est.p)
    meta.setdefault("Lf", "1.4")
    meta.setdefault("Lr", "1.65")
    fc, vy_r = terms(cols, meta, np.zeros_like(cols["t"]))
    outs = run(est, samples, cols["ay"], corr, fc, vy_r)
    return ("mg", name, cfg, variant), summary(outs, cols, m)


def cell(r, paused=True):
    text = f"{r['mass_err']:+.1%}, {1e3 * r['grade_rmse']:.2f}"
    return text + (f", {r['curve']:.0%}" if paused and r["curve"] > 0.0 else "")


def tables(res, obs_names, mg_names):
    heads = list(VARIANTS)
    lines = [f"Mass error at the end, grade RMSE over the log (mrad) and, where the curve pause "
             f"held any sample, the share it held (hold {HOLD:g} s after the last sample over "
             "the threshold); the observer logs from 1.0, 0.8, 1.2 × m, the simulator's "
             "resistances (the `_res` logs: the car preset's), recommended preset; float64 "
             "reference:", "",
             "| log | mg_m0 | " + " | ".join(heads) + " |", "|---|---|" + "---|" * len(heads)]
    never = []
    for n in obs_names:
        if max(res[("obs", n, s, v)]["curve"] for s in STARTS for v in heads) == 0.0:
            never.append(n)
            continue
        for s in STARTS:
            lines.append(f"| {n[:-4]} | {s:.1f} m | "
                         + " | ".join(cell(res[("obs", n, s, v)]) for v in heads) + " |")
    same = all(res[("obs", n, s, v)] == res[("obs", n, s, "off")]
               for n in never for s in STARTS for v in heads if v.startswith("pause"))
    lines += ["", f"Not listed: the {len(never)} logs no threshold held a sample of ("
              + ", ".join(n[:-4] for n in never) + "); there every pause ends "
              + ("as off, to the bit." if same else "NOT as off (a bug).")]
    if never:
        moved = max((abs(res[("obs", n, s, "F_c out")]["mass_err"]
                         - res[("obs", n, s, "off")]["mass_err"]), n)
                    for n in never for s in STARTS)
        lines.append(f"On them F_c out moves the mass at the end by at most "
                     f"{moved[0]:.2%} of m ({moved[1][:-4]}).")
    lines += ["", f"The mass and grade logs from {MG_START:g} × the truth, vx_true as the ground "
              "speed (no vy: 0 in F_c out): mass error at the end, grade RMSE (mrad), share "
              "held:", "",
              "| log | configuration | " + " | ".join(heads) + " |",
              "|---|---|" + "---|" * len(heads)]
    for n in mg_names:
        for c in MG_CONFIGS:
            lines.append(f"| {n[:-4]} | {c} | " + " | ".join(
                cell(res[("mg", n, c, v)]) for v in heads) + " |")
    return "\n".join(lines)


def results_text(n_jobs):
    """Every run of the study on @n_jobs processes: the page's text."""
    obs_dir = os.path.join(ROOT, "scenarios", "observer")
    obs_names = sorted(f for f in os.listdir(obs_dir)
                       if f.endswith(".csv") and not f.endswith(".mf.csv")) + [
        n for n in res_logs() if not n.endswith(".mf.csv")]
    mg_names = mass_grade_logs()
    jobs = [("mg", n, c, v) for n in mg_names for c in MG_CONFIGS for v in VARIANTS]
    jobs += [("obs", n, s, v) for n in obs_names for s in STARTS for v in VARIANTS]
    with multiprocessing.Pool(n_jobs) as pool:
        res = dict(pool.map(lambda_job, jobs, chunksize=1))
    return tables(res, obs_names, mg_names)


def main(argv=None):
    study_main(argv, __doc__, "mass-curve-pause", "mass_curve_pause_study", results_text)


def lambda_job(job):
    return observer_job(job[1:]) if job[0] == "obs" else mass_grade_job(job[1:])


if __name__ == "__main__":
    main()
