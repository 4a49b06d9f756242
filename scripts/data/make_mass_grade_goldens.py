"""Generate the golden trajectories of the mass and grade estimator (docs/MASS_GRADE.md) with
the float64 reference (scripts/reference/mass_grade.py), for the C tests to compare against.

Usage (from the repository root):

    .venv/bin/python scripts/data/make_mass_grade_goldens.py [--scenarios scenarios/mass_grade] \
        [--out scenarios/golden/mass_grade]

For every log <name>.csv of --scenarios and each configuration CONFIGS gives it, it writes
<out>/<name>.<config>.csv: the row index k, t and the estimator's outputs (mass, sd_mass,
grade, sd_grade, v, sd_v, q_mv, status, walk) on every STRIDE-th row, on every row whose status
or walk differs from the previous row's (the pause logic's transitions, the grade walk's level
switches, MASS_GRADE.md §4.7) and on the last row. walk is the grade walk's level after the
row (1 loose: mg_q_theta_hi, 0 tight: mg_q_theta; the next sample's time update uses it). The
metadata records every parameter (the vehicle preset of the log: truck for truck_*, else
car; then the configuration's keys), so the C test runs exactly what the reference ran.
Deterministic: plain Python floats, no BLAS on the estimator's path.
"""

from __future__ import annotations

import argparse
import os
import sys

sys.path[:0] = [os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]

from reference import mass_grade as mg  # noqa: E402

STRIDE = 10
OUTPUTS = ("mass", "sd_mass", "grade", "sd_grade", "v", "sd_v", "q_mv", "status", "walk", "e_ax",
           "mismatch")
# The library's presets (docs/MASS_GRADE.md §6 "Presets"): the recommended one (plain UKF with
# the accelerometer row) and the seed's (its AUKF on speed and torque, adapted every step,
# no rotating mass); and the two other combinations on a few logs, so that every branch of
# the filter meets the reference: the AUKF with its adaptation period and the ax row, the
# plain UKF on speed alone.
PRESETS = {
    "recommended": mg.MG_CONFIGS["recommended"],
    "seed": mg.MG_CONFIGS["seed"],
    "aukf_ax": {"mg_adaptive": 1.0, "mg_use_ax": 1.0},
    "ukf": {"mg_adaptive": 0.0, "mg_use_ax": 0.0},
    # the recommended preset learning the grade from ax in the brake and shift pauses
    # (MASS_GRADE.md §4.2, mg_pause_grade; the brake bit alone by default) from their second sample, the
    # change test off (mg_pause_grade_dv 0), so that the learning itself meets the reference
    # on every such sample
    "pause_grade": {"mg_adaptive": 0.0, "mg_use_ax": 1.0, "mg_pause_grade": 3.0,
                    "mg_pause_grade_dv": 0.0},
    # the recommended preset without the grade's two-level walk (MASS_GRADE.md §4.7; on in
    # the preset), on the two logs whose grade the walk was for: the fixed walk's path
    "walk_off": {**mg.MG_CONFIGS["recommended"], "mg_q_theta_hi": 0.0},
}
EXTRA = {"car_gear_shift": ("aukf_ax", "pause_grade"),
         "car_stop_and_go": ("aukf_ax", "pause_grade"),
         "car_hilly_road": ("ukf", "walk_off"), "car_long_curve_crest": ("walk_off",),
         "truck_graded_drive": ("ukf",)}


def vehicle(name):
    return "truck" if name.startswith("truck") else "car"


def configs(name):
    return ("recommended", "seed") + EXTRA.get(name, ())


def golden(path, config):
    """(metadata pairs, column names, rows) of one log's golden in one configuration."""
    name = os.path.basename(path)[:-4]
    cols, _ = mg.read_log(path)
    p = mg.preset(vehicle(name), **PRESETS[config])
    r = mg.run(cols, p)
    st, wk, mm = r["status"], r["walk"], r["mismatch"]
    # every row whose status, walk level or mismatch flag (§4.8) changed: the C tests then
    # know the double's walk level on every sample (the last golden row's at or before it)
    keep = [k for k in range(len(st))
            if k % STRIDE == 0 or k == len(st) - 1
            or (k > 0 and (st[k] != st[k - 1] or wk[k] != wk[k - 1] or mm[k] != mm[k - 1]))]
    meta = [("source", os.path.basename(path)), ("generator", "scripts/reference/mass_grade.py"),
            ("vehicle", vehicle(name)), ("config", config), ("stride", STRIDE)]
    meta += [(k, p[k]) for k in mg.MG_DEFAULTS]
    rows = [[float(k), float(r["t"][k])] + [float(r[o][k]) for o in OUTPUTS] for k in keep]
    return meta, ("k", "t") + OUTPUTS, rows


def write(path, meta, cols, rows):
    with open(path, "w", encoding="utf-8", newline="\n") as fh:
        for k, v in meta:
            fh.write(f"# {k} = {v!r}\n" if isinstance(v, float) else f"# {k} = {v}\n")
        fh.write(",".join(cols) + "\n")
        for row in rows:
            fh.write(",".join(repr(v) for v in row) + "\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenarios", default=os.path.join("scenarios", "mass_grade"))
    ap.add_argument("--out", default=os.path.join("scenarios", "golden", "mass_grade"))
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    files = sorted(os.path.join(a.scenarios, f) for f in os.listdir(a.scenarios)
                   if f.endswith(".csv"))
    for f in files:
        name = os.path.basename(f)[:-4]
        for c in configs(name):
            out = os.path.join(a.out, f"{name}.{c}.csv")
            write(out, *golden(f, c))
            print(f"{out}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
