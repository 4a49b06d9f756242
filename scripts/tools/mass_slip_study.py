#!/usr/bin/env python3
"""What the library's slip pause (MASS_GRADE.md §4.2, mg_slip_max) does to the mass and grade
filter's own estimate, measured with the C library through mu_replay.

    .venv/bin/python scripts/tools/mass_slip_study.py [--page docs/MASS_GRADE.md]
                     [--mu-replay build/mu_replay] [--jobs N]

The observer scenarios with wheel torques (scenarios/observer/*.csv, written with
drive_torque and brake_pressure as mass_online_friction.py writes them) are replayed with
their measured velocities (`--velocity measured`: the replay hands the log's vx to the
filter as its ground speed), `--mass-grade ukf` (the recommended preset), the log's mass m
as the friction estimator's, and the filter's start mg_m0 at m, 0.8 m and 1.2 m; each once
with the slip pause off (mg_slip_max = 0: the filter before it) and once with the default
key. From the run's JSON: the filter's mass at the end against m (the simulator's mass),
its sd there, and the samples the slip held (status 7). The first table lists the logs
where any run held a sample by slip; a line says how far the others moved (0 kg means the
pause never acted there). The mass and grade logs (scenarios/mass_grade/, replayed behind the
observer: no measured vx, so nothing is handed to the filter) are replayed with the key at 0
and at its default, and their mass, sd and grade columns compared byte for byte.
The traction logs run once more with the simulator's resistances (mg_fc = mg_fr = mg_rho = 0:
scripts/sim/vehicle.py has neither rolling resistance nor drag) instead of the car preset's,
the pause off and on (the last column of the first table).
The logs with the car's resistances (scenarios/observer_res/, make observer-res-scenarios: the
traction logs and the hill climb simulated with the car preset's rolling resistance and drag)
run as the first table's, with the car preset unchanged (now their model): their own table.
With --page the text goes between <!-- mass-slip:begin --> and <!-- mass-slip:end -->.
"""

import csv
import json
import multiprocessing
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from mass_online_friction import SIM_RESISTANCES, logs, with_drive_torque  # noqa: E402
from mass_sensitivity import log_mass  # noqa: E402
from mass_logs import mass_grade_logs  # noqa: E402
from md_tables import replace_region  # noqa: E402
from replay_args import replay_args  # noqa: E402

STARTS = (1.0, 0.8, 1.2)   # mg_m0 as a share of the log's m
SLIP = ("0", "default")    # mg_slip_max: off (the filter before the pause), the default key
MG_COLUMNS = ("mass_est", "sd_mass", "grade_est", "sd_grade")


def run(exe, log, params_text, extra):
    """mu_replay on @log with a parameter file of @params_text: (JSON doc, estimate log)."""
    with tempfile.TemporaryDirectory() as tmp:
        params = os.path.join(tmp, "p.params")
        with open(params, "w", encoding="utf-8") as fh:
            fh.write(params_text)
        out, js = os.path.join(tmp, "est.csv"), os.path.join(tmp, "m.json")
        r = subprocess.run([exe, "--in", log, "--out", out, "--params", params,
                            "--mass-grade", "ukf", "--metrics", js, "--quiet"] + extra,
                           capture_output=True, text=True, check=False)
        if r.returncode != 0:
            raise SystemExit(f"mass_slip_study: {log}: exit {r.returncode}: {r.stderr.strip()}")
        with open(js, encoding="utf-8") as fh:
            doc = json.load(fh)
        with open(out, encoding="utf-8") as fh:
            est = fh.read()
    return doc, est


RES_DIR = os.path.join(ROOT, "scenarios", "observer_res")


def log_path(name):
    """The observer log @name: a <scenario>_res log in scenarios/observer_res/."""
    folder = RES_DIR if name.split(".", 1)[0].endswith("_res") else \
        os.path.join(ROOT, "scenarios", "observer")
    return os.path.join(folder, name)


def res_logs():
    return sorted(f for f in os.listdir(RES_DIR) if f.endswith(".csv")) \
        if os.path.isdir(RES_DIR) else []


def observer_job(job):
    exe, name, start, slip, sim = job
    src = log_path(name)
    m = log_mass(src)
    with tempfile.TemporaryDirectory() as tmp:
        log = os.path.join(tmp, name)
        with_drive_torque(src, log)
        text = f"m = {m!r}\nmg_m0 = {m * start!r}\n"
        text += "mg_slip_max = 0\n" if slip == "0" else ""
        text += SIM_RESISTANCES if sim else ""
        doc, _ = run(exe, log, text, ["--velocity", "measured"])
    mg = doc["mass_grade"]
    return (name, start, slip, sim), {"mass": mg["end"]["mass"], "sd": mg["end"]["sd_mass"],
                                 "m": m, "n_slip": int(mg["status_counts"].get("7", 0)),
                                 "n_ok": int(mg["status_counts"].get("0", 0))}


def mg_columns(est):
    rows = csv.DictReader(line for line in est.splitlines() if not line.startswith("#"))
    return [tuple(r[c] for c in MG_COLUMNS) for r in rows]


def mass_grade_job(job):
    exe, name, slip = job
    text = "mg_slip_max = 0\n" if slip == "0" else ""
    doc, est = run(exe, os.path.join(ROOT, "scenarios", "mass_grade", name), text, [])
    return (name, slip), (mg_columns(est), int(doc["mass_grade"]["status_counts"].get("7", 0)))


def pct(x):
    return f"{x:+.1%}"


def tables(obs, names, mg, mg_names, sim=None, res=None, res_names=()):
    """The page's text; @sim: the runs with the simulator's resistances, keyed as @obs (the
    logs whose samples were held), or None (no such column); @res: the runs of the logs
    @res_names with the car's resistances, keyed as @obs (none: no such table)."""
    held = [n for n in names if any(obs[(n, s, "default")]["n_slip"] for s in STARTS)]
    lines = slip_rows(obs, held, sim)
    others = [n for n in names if n not in held]
    moved = max((abs(obs[(n, s, "default")]["mass"] - obs[(n, s, "0")]["mass"])
                 for n in others for s in STARTS), default=0.0)
    lines += ["", f"The other {len(others)} observer logs: no sample held by slip at any "
                  f"start; the largest change of the mass at the end {moved:.3g} kg."]
    same = [n for n in mg_names if mg[(n, "0")][0] == mg[(n, "default")][0]]
    n7 = sum(mg[(n, "default")][1] for n in mg_names)
    lines.append(f"The {len(mg_names)} mass and grade logs (behind the observer, no measured vx): "
                 f"{len(same)} of {len(mg_names)} with mass_est, sd_mass, grade_est, sd_grade "
                 f"equal byte for byte with the key at 0 and at its default; {n7} samples held "
                 "by slip.")
    if res and res_names:
        lines += ["", "With the car preset's rolling resistance and drag in the simulator "
                      "(scenarios/observer_res/, the car preset unchanged):", ""]
        lines += slip_rows(res, list(res_names), None)
    return "\n".join(lines)


def slip_rows(obs, held, sim):
    """The rows of the logs @held: off -> on per start (and @sim's, when it has them all)."""
    extra = sim is not None and all((n, s, k) in sim for n in held for s in STARTS for k in SLIP)
    rows = ["| log | mg_m0 | mass at the end vs m: pause off → on | sd_mass / m: off → on "
            "| samples held by slip | updates: off → on |"
            + (" sim's resistances: mass vs m (sd / m), off → on |" if extra else ""),
            "|---|---|---|---|---|---|" + ("---|" if extra else "")]
    for n in held:
        for s in STARTS:
            a, b = obs[(n, s, "0")], obs[(n, s, "default")]
            m = a["m"]
            row = (f"| {n[:-4]} | {s:.1f} m | {pct((a['mass'] - m) / m)} → "
                   f"{pct((b['mass'] - m) / m)} | {a['sd'] / m:.1%} → {b['sd'] / m:.1%} "
                   f"| {b['n_slip']} | {a['n_ok']} → {b['n_ok']} |")
            if extra:
                c, d = sim[(n, s, "0")], sim[(n, s, "default")]
                row += (f" {pct((c['mass'] - m) / m)} ({c['sd'] / m:.1%}) → "
                        f"{pct((d['mass'] - m) / m)} ({d['sd'] / m:.1%}) |")
            rows.append(row)
    return rows


def main():
    a = replay_args(__doc__, "mass_slip_study", jobs=os.cpu_count() or 1)
    names = logs()
    mg_names = mass_grade_logs()
    with multiprocessing.Pool(a.jobs) as pool:
        obs = dict(pool.map(observer_job, [(a.mu_replay, n, s, k, False) for n in names
                                           for s in STARTS for k in SLIP]))
        obs = {key[:3]: v for key, v in obs.items()}
        held = [n for n in names if any(obs[(n, s, "default")]["n_slip"] for s in STARTS)]
        sim = dict(pool.map(observer_job, [(a.mu_replay, n, s, k, True) for n in held
                                           for s in STARTS for k in SLIP]))
        sim = {key[:3]: v for key, v in sim.items()}
        mg = dict(pool.map(mass_grade_job, [(a.mu_replay, n, k) for n in mg_names
                                            for k in SLIP]))
        res_names = res_logs()
        res = dict(pool.map(observer_job, [(a.mu_replay, n, s, k, False) for n in res_names
                                           for s in STARTS for k in SLIP]))
        res = {key[:3]: v for key, v in res.items()}
    text = tables(obs, names, mg, mg_names, sim, res, res_names)
    print(text)
    if a.page:
        replace_region(Path(a.page), "<!-- mass-slip:begin -->", "<!-- mass-slip:end -->",
                       text.splitlines(), "mass_slip_study")


if __name__ == "__main__":
    main()
