#!/usr/bin/env python3
"""What the online mass does for the friction estimator when the mass it was given is wrong
(issue 19, deliverable 4: "what a +-20 % mass error does to the friction estimate with and
without the online mass"), on the logs that carry what the mass and grade estimator needs.

    .venv/bin/python scripts/tools/mass_online_friction.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--mu-replay build/mu_replay] [--jobs N] [--folder observer|observer_res]

The friction scenarios (scenarios/*.csv) have no drive torque; the observer scenarios
(scenarios/observer/*.csv) carry the simulator's drive torque per wheel (torque_*, N m at the
wheel) and brake pressure per wheel (p_*, MPa) beside the friction truth. Each is written with
two more columns, drive_torque = torque_fl + torque_fr + torque_rl + torque_rr (DATA.md: the
total at the wheels) and brake_pressure = max(p_*) in Pa, and replayed by the C library
(`mu_replay`, float, default preset, measured velocities) with the log's mass m x 0.8, 1.0
and 1.2 in a parameter file, with the mass and grade estimator off and on (`ukf`, the
default: it feeds its mass to the friction estimator by the mg_feed_sd_rel rule, MASS_GRADE.md
section 10), on three times: without the excitation gate (mg_feed_excitation = 0, the rule
before it), with it but without the feed's slip hold and band (mg_feed_slip_max = 0,
mg_feed_band = 0), and with the default keys (the gate, the slip hold and the band); the three
runs with the estimator on are made twice: with the car preset's driving resistances (what a
user whose resistances are wrong gets) and with the simulator's (SIM_RESISTANCES:
scripts/sim/vehicle.py, which wrote these logs, applies neither rolling resistance nor drag,
so mg_fc = mg_fr = mg_rho = 0; every other key the preset's, the simulator's car being the
preset's: R, m_rot = 4 Iw / R^2).
Figures pooled over the four wheels and every log as mass_sensitivity.py pools
them (valid share, RMSE when valid, consistency when valid, largest error when valid); the
last columns count logs whose RMSE when valid rose / fell by more than 0.02 against the same
log with its own mass and the estimator off.
A second table, from the runs with the log's own mass, lists each log where any run fed
the mass: the first sample fed, the share of samples fed, the friction estimator's mass at the
end against the log's m (no gate -> gate -> gate and checks), the gate's sum at the end
without the checks (the JSON's excitation_end, m/s) and, with them, the updates the slip held
and the samples the band refused (n_slip_held, n_band_refused); then the same three runs with
the simulator's resistances (first fed, mass_used at the end) and the filter's own mass at the
end of the default run (the JSON's end mass), car preset -> simulator's resistances; a log fed
with either resistances is listed.
With --page the tables go between <!-- mass-online:begin/end --> and
<!-- mass-online-gate:begin/end --> of the page.
With --folder observer_res the same runs on the observer logs simulated with the car preset's
rolling resistance and drag (scenarios/observer_res/, make observer-res-scenarios: the car
preset is their model, the "simulator's (none)" runs are the wrong resistances there), the
tables between <!-- mass-online-res:begin/end --> and <!-- mass-online-gate-res:begin/end -->.
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

from mass_sensitivity import WHEELS, WORSE, log_mass, pooled, pooled_cells  # noqa: E402
from md_tables import replace_region  # noqa: E402
from replay_args import replay_args  # noqa: E402

FACTORS = (0.8, 1.0, 1.2)
# the driving resistances of the simulator that wrote the observer logs (scripts/sim/vehicle.py:
# "No aerodynamic drag, no rolling resistance"); the car preset's are mg_fc = 0.01,
# mg_fr = 0.00015, mg_rho = 1.2 (with mg_cd, mg_area, which then multiply 0)
SIM_RESISTANCES = "mg_fc = 0\nmg_fr = 0\nmg_rho = 0\n"
FEED_MODES = ("ukf-nogate", "ukf-nochecks", "ukf")
SIM_MODES = tuple(f"{m}-sim" for m in FEED_MODES)
MODES = ("off",) + FEED_MODES + SIM_MODES
LABELS = {"off": "off", "ukf-nogate": "on (ukf), mass fed, no gate",
          "ukf-nochecks": "on (ukf), mass fed through the gate",
          "ukf": "on (ukf), through the gate, slip hold and band"}
# the keys each mode writes into the run's parameter file
MODE_KEYS = {"off": "", "ukf-nogate": "mg_feed_excitation = 0\nmg_feed_slip_max = 0\n"
             "mg_feed_band = 0\n", "ukf-nochecks": "mg_feed_slip_max = 0\nmg_feed_band = 0\n",
             "ukf": ""}
for _m in FEED_MODES:
    LABELS[f"{_m}-sim"] = LABELS[_m]
    MODE_KEYS[f"{_m}-sim"] = MODE_KEYS[_m] + SIM_RESISTANCES


def resistances(mode):
    """The table's resistance cell of @mode: none (the estimator off), the car preset's or the
    simulator's."""
    if mode == "off":
        return "–"
    return "simulator's (none)" if mode.endswith("-sim") else "car preset"
TORQUES = ("torque_fl", "torque_fr", "torque_rl", "torque_rr")
PRESSURES = ("p_fl", "p_fr", "p_rl", "p_rr")


FOLDERS = ("observer", "observer_res")


def logs(folder="observer"):
    """The scenarios of scenarios/@folder with friction truth, wheel torques and brake
    pressures."""
    d = os.path.join(ROOT, "scenarios", folder)
    out = []
    for f in sorted(os.listdir(d)):
        if f.endswith(".csv"):
            with open(os.path.join(d, f), encoding="utf-8") as fh:
                header = next(line for line in fh if not line.startswith("#")).strip().split(",")
            if {"mu_fl", *TORQUES, *PRESSURES} <= set(header):
                out.append(f)
    return out


def with_drive_torque(src, dst):
    """Copies the log @src to @dst with drive_torque (the sum of torque_*, N m) and
    brake_pressure (max of p_*, MPa -> Pa) appended to every row; metadata unchanged."""
    with open(src, encoding="utf-8") as fi, open(dst, "w", encoding="utf-8") as fo:
        idx = None
        for line in fi:
            if line.startswith("#"):
                fo.write(line)
                continue
            cells = line.rstrip("\n").split(",")
            if idx is None:
                idx = ([cells.index(c) for c in TORQUES], [cells.index(c) for c in PRESSURES])
                fo.write(",".join(cells + ["drive_torque", "brake_pressure"]) + "\n")
                continue
            torque = sum(float(cells[i]) for i in idx[0])
            pressure = max(float(cells[i]) for i in idx[1]) * 1e6
            fo.write(",".join(cells + [repr(torque), repr(pressure)]) + "\n")


def one(job):
    exe, folder, name, factor, mode = job
    src = os.path.join(ROOT, "scenarios", folder, name)
    with tempfile.TemporaryDirectory() as tmp:
        log = os.path.join(tmp, name)
        with_drive_torque(src, log)
        params = os.path.join(tmp, "mass.params")
        with open(params, "w", encoding="utf-8") as fh:
            fh.write(f"m = {log_mass(src) * factor!r}\n")
            fh.write(MODE_KEYS[mode])
        out, js = os.path.join(tmp, "est.csv"), os.path.join(tmp, "m.json")
        r = subprocess.run([exe, "--in", log, "--out", out, "--params", params,
                            "--velocity", "measured", "--mass-grade", mode.split("-")[0],
                            "--metrics", js, "--quiet"], capture_output=True, text=True,
                           check=False)
        if r.returncode != 0:
            raise SystemExit(f"mass_online_friction: {name} x{factor} {mode}: exit "
                             f"{r.returncode}: {r.stderr.strip()}")
        with open(js, encoding="utf-8") as fh:
            doc = json.load(fh)
        feed = None
        if mode != "off":
            feed = dict(doc["mass_grade"]["feed"])
            feed["first"] = first_fed(out)
            feed["mass_est_end"] = doc["mass_grade"]["end"]["mass"]
    return job[2:], ([doc["metrics"][w] for w in WHEELS], feed)


def first_fed(est):
    """(time of the first sample whose mass_used differs from the first row's or None,
    the number of rows) of the estimate log @est."""
    with open(est, encoding="utf-8") as fh:
        rows = csv.DictReader(line for line in fh if not line.startswith("#"))
        first, n, m0 = None, 0, None
        for r in rows:
            n += 1
            m0 = r["mass_used"] if m0 is None else m0
            if first is None and r["mass_used"] != m0:
                first = float(r["t"])
    return first, n


def table(results, names):
    """The pooled friction figures per mass given and run. A run with the simulator's
    resistances gets its own row only where a cell differs from the same run's with the car
    preset's; the line under the table counts those equal to the digits printed."""
    rows = ["| mass given | mass and grade estimator | its resistances | valid | RMSE valid | "
            f"consistency | max valid | logs worse by > {WORSE} | better by > {WORSE} |",
            "|---|---|---|---|---|---|---|---|---|"]
    base = [pooled(results[(n, 1.0, "off")][0]) for n in names]
    same = 0
    for factor in FACTORS:
        cells = {}
        for mode in MODES:
            text, worse, better = pooled_cells(
                [pooled(results[(n, factor, mode)][0]) for n in names], base)
            ref = factor == 1.0 and mode == "off"
            cells[mode] = (f"{text} | {'–' if ref else f'{worse} of {len(names)}'} | "
                           f"{'–' if ref else f'{better} of {len(names)}'} |")
            if mode in SIM_MODES and cells[mode] == cells[mode[:-4]]:
                same += 1
                continue
            rows.append(f"| m × {factor:.1f} | {LABELS[mode]} | {resistances(mode)} | "
                        f"{cells[mode]}")
    rows += ["", f"With the simulator's resistances (mg_fc = mg_fr = mg_rho = 0) {same} of "
             f"{len(FACTORS) * len(SIM_MODES)} runs with the estimator on give the car preset's "
             "figures to the digits printed" + (" (not listed)." if same else ".")]
    return "\n".join(rows)


def gate_table(results, names, folder="observer"):
    """Per log that feeds in any run (own mass), with either resistances: no gate -> gate ->
    gate and checks (car preset, then the simulator's), and the filter's own mass at the end of
    the default run, car preset -> simulator's resistances."""
    def cells(feed, m):
        (first, n) = feed["first"]
        if first is None:
            return "never", "0%", "m kept"
        return (f"{first:.1f} s", f"{feed['n_fed'] / n:.0%}",
                f"{(feed['mass_used_end'] - m) / m:+.1%}")
    rows = ["| log | m | first fed: no gate → gate → gate and checks | samples fed "
            "| mass_used at the end vs m | excitation at the end | slip held / band refused "
            "| simulator's resistances: first fed | its mass_used at the end vs m "
            "| filter's mass at the end vs m: car preset → simulator's |",
            "|---|---|---|---|---|---|---|---|---|---|"]
    src = os.path.join(ROOT, "scenarios", folder)
    for n in names:
        runs = [results[(n, 1.0, mode)][1] for mode in FEED_MODES]
        sims = [results[(n, 1.0, mode)][1] for mode in SIM_MODES]
        if all(r["n_fed"] == 0 for r in runs + sims):
            continue
        m = log_mass(os.path.join(src, n))
        c = [cells(r, m) for r in runs]
        d = [cells(r, m) for r in sims]
        rows.append(f"| {n[:-4]} | {m:.0f} kg | {' → '.join(x[0] for x in c)} | "
                    f"{' → '.join(x[1] for x in c)} | {' → '.join(x[2] for x in c)} | "
                    f"{runs[1]['excitation_end']:.2f} m/s | "
                    f"{runs[2]['n_slip_held']} / {runs[2]['n_band_refused']} | "
                    f"{' → '.join(x[0] for x in d)} | {' → '.join(x[2] for x in d)} | "
                    f"{(runs[2]['mass_est_end'] - m) / m:+.1%} → "
                    f"{(sims[2]['mass_est_end'] - m) / m:+.1%} |")
    return "\n".join(rows)


def main():
    a = replay_args(__doc__, "mass_online_friction", jobs=os.cpu_count() or 1,
                    extra=lambda ap: ap.add_argument("--folder", choices=FOLDERS,
                                                     default="observer"))
    names = logs(a.folder)
    jobs = [(a.mu_replay, a.folder, n, f, m) for n in names for f in FACTORS for m in MODES]
    results = {}
    with multiprocessing.Pool(a.jobs) as pool:
        for i, (key, wheels) in enumerate(pool.imap_unordered(one, jobs), 1):
            results[key] = wheels
            if i % 50 == 0 or i == len(jobs):  # progress, a line per 50 runs
                print(f"mass_online_friction: {i}/{len(jobs)} runs", file=sys.stderr)
    text = table(results, names)
    gate = gate_table(results, names, a.folder)
    print(text)
    print(gate)
    tag = "-res" if a.folder == "observer_res" else ""
    if a.page:
        replace_region(Path(a.page), f"<!-- mass-online{tag}:begin -->",
                       f"<!-- mass-online{tag}:end -->", text.splitlines(), "mass_online_friction")
        replace_region(Path(a.page), f"<!-- mass-online-gate{tag}:begin -->",
                       f"<!-- mass-online-gate{tag}:end -->", gate.splitlines(),
                       "mass_online_friction")


if __name__ == "__main__":
    main()
