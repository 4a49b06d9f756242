#!/usr/bin/env python3
"""Issue 19: the mass error the slip pause leaves on the mu = 0.3 traction logs, measured in
the float64 reference (scripts/reference/mass_grade.py), and a rollback of the filter at the
pause's onset as a candidate fix (not in the library: MASS_GRADE.md "The slip pause").

    .venv/bin/python scripts/tools/mass_slip_ramp_study.py [--page docs/MASS_GRADE.md]
                     [--jobs N]

The observer scenarios with wheel torques (scenarios/observer/, the samples mu_replay builds
from them with --velocity measured: v the mean wheel speed times R, drive_torque the sum of
torque_*, brake_pressure the largest p_* in Pa, ax, and the log's measured vx as the slip
pause's ground speed) run through the reference's recommended preset (UKF with the ax row
and the brake bit of mg_pause_grade), the filter started at the log's m, 0.8 m and 1.2 m. Variants:

- off: mg_slip_max = 0 (the filter before the pause); pause: the default key (0.05);
- rollback T (T = 0.05, 0.1, 0.2 s): the pause, and at its onset (a slip-paused sample after
  one that was not) the filter's M, theta, their rows of S and q_mv are set back to a
  snapshot taken between T and 2T of updates earlier (two slots, shifted every T of update
  time), so what the updates learned in the torque ramp before the slip crossed 0.05 is
  discarded; the hold then runs as usual (Rollback below);
- sim's resistances, off / pause: mg_fc = mg_fr = mg_rho = 0, the resistances of the
  simulator that wrote these logs (scripts/sim/vehicle.py: no rolling resistance, no drag)
  instead of the car preset's.

The logs with the car's resistances (scenarios/observer_res/, make observer-res-scenarios: the
traction logs and the hill climb with the car preset's rolling resistance and drag in the
simulator, <name>_res) run with the car preset as it is, now the model of the log, off and
pause, from the three starts: their own tables follow the traction logs' (the mass at the end;
its course from m as the simulator's-resistances table).

The first table is the six traction logs; then the largest change any rollback makes to the
mass at the end of the other observer logs against the pause, and on the seven mass and grade
logs (scenarios/mass_grade/, their vehicle's recommended preset) with their true speed vx_true
handed over as the ground speed: the mass error at the end and the grade's RMSE, pause
against each rollback. With --page the text goes between <!-- mass-slip-ramp:begin --> and
<!-- mass-slip-ramp:end -->.
"""

import argparse
import math
import multiprocessing
import os
import sys
from pathlib import Path

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from reference import mass_grade as mg  # noqa: E402
from mass_online_friction import PRESSURES, TORQUES, logs  # noqa: E402
from mass_sensitivity import log_mass  # noqa: E402
from md_tables import replace_region  # noqa: E402
from mass_logs import MG_DIR, mass_grade_logs  # noqa: E402,F401  (mass_grade_logs: re-exported)

STARTS = (1.0, 0.8, 1.2)            # mg_m0 as a share of the log's m
ROLLBACKS = (0.05, 0.1, 0.2)        # the rollback's snapshot period T, s
SIM_RESISTANCES = {"mg_fc": 0.0, "mg_fr": 0.0, "mg_rho": 0.0}
# the library's recommended preset (UKF, the ax row, the brake bit of mg_pause_grade), taken from
# the reference so that the studies run what the library ships
RECOMMENDED = mg.MG_CONFIGS["recommended"]
# name -> (parameter overrides, rollback period T or 0)
VARIANTS = {"off": ({"mg_slip_max": 0.0}, 0.0), "pause": ({}, 0.0)}
VARIANTS.update({f"rollback {t:g} s": ({}, t) for t in ROLLBACKS})
VARIANTS.update({"sim's resistances, off": (dict(SIM_RESISTANCES, mg_slip_max=0.0), 0.0),
                 "sim's resistances, pause": (dict(SIM_RESISTANCES), 0.0)})
TRACTION = "traction_"
RAMP_T = 0.5            # the traction logs' torque ramp begins at 0.5 s (their description)
TIMES = (0.5, 0.6, 0.65, 0.7, 0.8, 1.0, 1.5, 3.0, 8.0)   # s, the mass's course in the ramp


class Rollback(mg.MassGrade):
    """The reference's filter (square-root form) with the rollback at the slip pause's onset:
    two slots of (M, theta, S's mass and grade rows, q_mv), both the state at a start; after
    each update the update time since the current slot grows by dt, and where less than half
    a period of T is left the slots shift (previous = current, current = now). At a
    slip-paused sample whose last accepted step was not slip-paused the previous slot comes
    back (then both slots are it and the clock restarts), and the hold follows as for any
    paused sample (it keeps M, theta; the speed's row it sets afresh). T = 0: the reference."""

    _SAVED = mg.MassGrade._SAVED + ("rb_cur", "rb_prev", "rb_elapsed", "last_status")

    def __init__(self, params, period):
        super().__init__(params)
        if not (math.isfinite(period) and period >= 0.0):
            raise mg.ParamError("rollback period: must be finite and >= 0")
        self.period = period
        self.last_status = mg.OK
        self.restores = 0

    def snapshot(self):
        S = self.S
        return (self.x[1], self.x[2], S[1][0], S[1][1], S[2][0], S[2][1], S[2][2], self.q_mv)

    def _reset_slots(self):
        self.rb_cur = self.rb_prev = self.snapshot()
        self.rb_elapsed = 0.0

    def _start(self, s):
        super()._start(s)
        self._reset_slots()

    def _pause_status(self, s, dt):
        status = super()._pause_status(s, dt)
        if (self.period > 0.0 and dt > 0.0 and status == mg.PAUSED_SLIP
                and self.last_status != mg.PAUSED_SLIP):
            m, th, s10, s11, s20, s21, s22, q = self.rb_prev
            self.x[1], self.x[2], self.q_mv = m, th, q
            self.S = [list(self.S[0]), [s10, s11, 0.0], [s20, s21, s22]]
            self._reset_slots()
            self.restores += 1
        return status

    def _update_sqrt(self, s, dt):
        st = super()._update_sqrt(s, dt)
        if st == mg.OK and self.period > 0.0:
            self.rb_elapsed += dt
            if self.rb_elapsed >= self.period - 0.5 * dt:
                self.rb_prev = self.rb_cur
                self.rb_cur = self.snapshot()
                self.rb_elapsed = 0.0
        return st

    def step(self, s):
        out = super().step(s)
        if out.status < mg.ERR_NONFINITE:
            self.last_status = out.status
        return out


def observer_samples(cols, R):
    """mu_replay's samples of an observer log with --velocity measured (replay_real.c
    rfe_replay_mass_grade_input_row): the wheels' speed, the summed torque, the largest brake
    pressure in Pa, ax, the log's vx."""
    v = mg.speed_from_wheels(cols, R)
    torque = cols[TORQUES[0]] + cols[TORQUES[1]] + cols[TORQUES[2]] + cols[TORQUES[3]]
    pressure = np.max(np.vstack([cols[c] for c in PRESSURES]), axis=0) * 1e6
    return [mg.MgSample(float(cols["t"][i]), float(v[i]), float(torque[i]),
                        brake_pressure=float(pressure[i]), ax=float(cols["ax"][i]),
                        vx=float(cols["vx"][i])) for i in range(len(v))]


RES_DIR = os.path.join(ROOT, "scenarios", "observer_res")
RES_SUFFIX = "_res"
RES_VARIANTS = ("off", "pause")     # the car preset is these logs' model: no override


def log_path(name):
    """The observer log @name: a <scenario>_res log in scenarios/observer_res/."""
    stem = name.split(".", 1)[0]
    folder = RES_DIR if stem.endswith(RES_SUFFIX) else os.path.join(ROOT, "scenarios", "observer")
    return os.path.join(folder, name)


def res_logs():
    return sorted(f for f in os.listdir(RES_DIR) if f.endswith(".csv")) \
        if os.path.isdir(RES_DIR) else []


# What the mass studies share (this one and mass_curve_pause_study.py): the logs, how they are
# read and fed to the reference, and the command line that prints the text and writes the page.


def observer_log(name):
    """The observer log @name (log_path): (columns, metadata, the vehicle's mass m)."""
    path = log_path(name)
    cols, meta = mg.read_log(path)
    return cols, meta, log_mass(path)


def mass_grade_log(name):
    """The mass and grade log @name: (columns, metadata, its vehicle's preset: truck or car)."""
    cols, meta = mg.read_log(os.path.join(MG_DIR, name))
    return cols, meta, "truck" if name.startswith("truck") else "car"


def true_speed_samples(cols, p):
    """The reference's samples of a mass and grade log (parameters @p) with the log's vx_true
    handed over as the ground speed."""
    samples = list(mg.samples(cols, p))
    for s, vx in zip(samples, cols["vx_true"]):
        s.vx = float(vx)
    return samples


def study_main(argv, doc, region, who, results_text):
    """A mass study's command line (--page, --jobs): prints results_text(jobs) and, with
    --page, writes it between <!-- @region:begin --> and <!-- @region:end --> (as @who)."""
    ap = argparse.ArgumentParser(description=doc.splitlines()[0])
    ap.add_argument("--page", help=f"Markdown page whose {region} region is rewritten")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    a = ap.parse_args(argv)
    text = results_text(a.jobs)
    print(text)
    if a.page:
        replace_region(Path(a.page), f"<!-- {region}:begin -->", f"<!-- {region}:end -->",
                       text.splitlines(), who)


def observer_job(job):
    name, start, variant = job
    cols, _, m = observer_log(name)
    over, period = VARIANTS[variant]
    est = Rollback(mg.preset("car", mg_m0=m * start, **RECOMMENDED, **over), period)
    outs = [est.step(s) for s in observer_samples(cols, est.p["R"])]
    end = outs[-1]
    # the measured slip the pause tests, before the ramp (no torque: the noise of v and vx)
    # and from the ramp's start to the first slip-held sample (the updates the ramp moves)
    held = next((k for k, o in enumerate(outs) if o.status == mg.PAUSED_SLIP), len(outs))
    slip = [abs(s.v - s.vx) / max(abs(s.vx), est.p["mg_v_min"])
            for s in observer_samples(cols, est.p["R"])]
    t = cols["t"]
    course = [next(o for o, tk in zip(outs, t) if tk >= x - 1e-9) for x in TIMES if x <= t[-1]]
    return (name, start, variant), {
        "course": [(o.mass, o.sd_mass) for o in course],
        # how many sd off at worst from the ramp's start on: confidently wrong or not
        "worst_z": max(abs(o.mass - m) / o.sd_mass for o, tk in zip(outs, t) if tk >= RAMP_T),
        "m": m, "mass": end.mass, "sd": end.sd_mass, "restores": est.restores,
        "n_ok": sum(o.status == mg.OK for o in outs),
        "slip_before": max(x for x, tk in zip(slip, t) if tk < RAMP_T),
        "slip_ramp": max((x for x, tk in zip(slip[:held], t[:held]) if tk >= RAMP_T),
                         default=math.nan)}


def mass_grade_job(job):
    name, variant = job
    cols, _, vehicle = mass_grade_log(name)
    over, period = VARIANTS[variant]
    est = Rollback(mg.preset(vehicle, **RECOMMENDED, **over), period)
    grade = [est.step(s).grade for s in true_speed_samples(cols, est.p)]
    err = np.asarray(grade) - cols["grade_true"]
    return (name, variant), {"mass_err": (est.x[1] - cols["mass_true"][-1]) / cols["mass_true"][-1],
                             "grade_rmse": float(np.sqrt(np.mean(err * err))),
                             "restores": est.restores}


def cell(r):
    return f"{(r['mass'] - r['m']) / r['m']:+.1%} ({r['sd'] / r['m']:.1%})"


def course_rows(obs, names, pairs):
    """Rows of the mass's course from m: (variant, label) pairs per log."""
    rows = []
    for n in names:
        for v, label in pairs:
            r = obs[(n, 1.0, v)]
            rows.append(f"| {n[:-4]} | {label} | " + " | ".join(
                f"{(mass - r['m']) / r['m']:+.1%} ({sd / r['m']:.1%})" for mass, sd in r["course"])
                + f" | {r['worst_z']:.1f} |")
    return rows


def course_head(n_times):
    return ["| log | pause | " + " | ".join(f"{x:g} s" for x in TIMES[:n_times])
            + " | largest \\|M − m\\| / sd |", "|---|---|" + "---|" * (n_times + 1)]


def res_tables(obs, res_names):
    """The text of the logs with the car's resistances (keys as the jobs')."""
    if not res_names:
        return []
    lines = ["With the car preset's rolling resistance and drag in the simulator "
             "(scenarios/observer_res/, the car preset now the logs' model): the mass at the "
             "end against m (sd_mass / m), the slip pause off and on:", "",
             "| log | mg_m0 | off | pause |", "|---|---|---|---|"]
    for n in res_names:
        for s in STARTS:
            lines.append(f"| {n[:-4]} | {s:.1f} m | "
                         + " | ".join(cell(obs[(n, s, v)]) for v in RES_VARIANTS) + " |")
    n_times = min(len(obs[(n, 1.0, "off")]["course"]) for n in res_names)
    lines += ["", "The same from m: the mass against m (sd / m) at times in the ramp and after, "
              "and its largest distance from m in sd from 0.5 s on:", ""]
    lines += course_head(n_times)
    lines += [row for row in course_rows(obs, res_names, (("off", "off"), ("pause", "on")))]
    held = [obs[(n, 1.0, "pause")]["n_ok"] for n in res_names]
    lines += ["", "Updates (status 0) with the pause, from m: " + ", ".join(
        f"{n[:-4]} {k}" for n, k in zip(res_names, held)) + ".", ""]
    return lines


def tables(obs, names, mgr, mg_names, res_names=()):
    """The page's text from the results (keys as the jobs')."""
    traction = [n for n in names if n.startswith(TRACTION)]
    heads = list(VARIANTS)
    rows = ["| log | mg_m0 | " + " | ".join(heads) + " |", "|---|---|" + "---|" * len(heads)]
    for n in traction:
        for s in STARTS:
            rows.append(f"| {n[:-4]} | {s:.1f} m | "
                        + " | ".join(cell(obs[(n, s, v)]) for v in heads) + " |")
    lines = ["Mass at the end against m (sd_mass / m), float64 reference:", ""] + rows + [""]
    before = [obs[(n, 1.0, "pause")]["slip_before"] for n in traction]
    ramp = [obs[(n, 1.0, "pause")]["slip_ramp"] for n in traction]
    lines += [f"The measured slip |v − vx| / max(|vx|, mg_v_min) on the {len(traction)} "
              f"traction logs: before the torque ramp (t < {RAMP_T:g} s, no drive torque: "
              f"the noise of v and vx) up to {min(before):.4f}…{max(before):.4f}; from "
              f"{RAMP_T:g} s to the first slip-held sample (the ramp's updates) up to "
              f"{min(ramp):.4f}…{max(ramp):.4f}.", ""]
    lines += ["With the simulator's resistances, from m: the mass against m (sd / m) at times in "
              "the ramp and after, without and with the pause, and its largest distance from m "
              "in sd from the ramp's start on:", "",
              "| log | pause | " + " | ".join(f"{x:g} s" for x in TIMES)
              + " | largest \\|M − m\\| / sd |",
              "|---|---|" + "---|" * (len(TIMES) + 1)]
    for n in traction:
        for v, label in (("sim's resistances, off", "off"), ("sim's resistances, pause", "on")):
            r = obs[(n, 1.0, v)]
            lines.append(f"| {n[:-4]} | {label} | " + " | ".join(
                f"{(mass - r['m']) / r['m']:+.1%} ({sd / r['m']:.1%})" for mass, sd in r["course"])
                + f" | {r['worst_z']:.1f} |")
    lines.append("")
    lines += res_tables(obs, list(res_names))
    others = [n for n in names if n not in traction]
    rb = [v for v in heads if v.startswith("rollback")]
    for v in rb:
        moved = [(abs(obs[(n, s, v)]["mass"] - obs[(n, s, "pause")]["mass"]), n)
                 for n in others for s in STARTS]
        big, where = max(moved)
        onsets = sum(obs[(n, s, v)]["restores"] for n in others for s in STARTS)
        lines.append(f"The other {len(others)} observer logs, {v} against the pause: "
                     f"{onsets} rollbacks over the {len(STARTS)} starts, the largest change of "
                     f"the mass at the end {big:.3g} kg"
                     + (f" ({where[:-4]})." if big > 0.0 else "."))
    lines += ["", f"The {len(mg_names)} mass and grade logs with vx_true as the ground speed "
                  "(their vehicle's recommended preset): mass error at the end, grade RMSE "
                  "(mrad), rollbacks:", "",
              "| log | " + " | ".join(["pause"] + rb) + " |", "|---|" + "---|" * (1 + len(rb))]
    for n in mg_names:
        lines.append(f"| {n[:-4]} | " + " | ".join(
            f"{mgr[(n, v)]['mass_err']:+.2%}, {1e3 * mgr[(n, v)]['grade_rmse']:.3f}, "
            f"{mgr[(n, v)]['restores']}" for v in ["pause"] + rb) + " |")
    return "\n".join(lines)


def results_text(n_jobs):
    """Every run of the study on @n_jobs processes: the page's text."""
    names = logs()
    mg_names = mass_grade_logs()
    res_names = res_logs()
    obs_jobs = [(n, s, v) for n in names for s in STARTS for v in VARIANTS
                if n.startswith(TRACTION) or v == "pause" or v.startswith("rollback")]
    obs_jobs += [(n, s, v) for n in res_names for s in STARTS for v in RES_VARIANTS]
    mg_jobs = [(n, v) for n in mg_names for v in VARIANTS
               if v == "pause" or v.startswith("rollback")]
    with multiprocessing.Pool(n_jobs) as pool:
        mgr = dict(pool.map(mass_grade_job, mg_jobs, chunksize=1))
        obs = dict(pool.map(observer_job, obs_jobs, chunksize=4))
    return tables(obs, names, mgr, mg_names, res_names)


def main(argv=None):
    study_main(argv, __doc__, "mass-slip-ramp", "mass_slip_ramp_study", results_text)


if __name__ == "__main__":
    main()
