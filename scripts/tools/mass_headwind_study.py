#!/usr/bin/env python3
"""Is a headwind detectable from what the mass and grade estimator already has (issue 19,
MASS_GRADE.md section 10 "The headwind")?

    .venv/bin/python scripts/tools/mass_headwind_study.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--no-variants]

The float64 reference (scripts/reference/mass_grade.py, the square-root form the C library
equals) runs every mass and grade log (scenarios/mass_grade/*.csv) in the recommended
configuration (the plain UKF with the accelerometer row and the brake bit of mg_pause_grade:
the reference's MG_CONFIGS["recommended"], the goldens' "recommended", over the vehicle
preset's other keys) and, for the speed row alone, in the
seed's speed-only UKF (mg_use_ax = 0). Its optional probe hands over each update's
innovation and predicted sd; the candidate statistics, each a time series:

- e_ax, e_v: the normalised innovation (innovation / its predicted sd) of the ax row and of
  the speed row, averaged over the updates of a trailing WINDOW_S window (a window is formed
  once it holds at least half its samples as updates);
- NIS_ax, NIS_v: the mean of the squared normalised innovation over the same window;
- drag ratio: the least-squares fit over every update so far of
      T/R - D(v) - m_rot (ax - g sin theta_hat) = M (ax + g (f_c + f_r v)) + beta v^2,
  with D(v) = rho C_d S v^2 / 2 the model's drag and the grade entering through ax (which
  measures v-dot + g sin theta), so M and beta are fitted without the grade; the statistic is
  beta / (rho C_d S / 2), the extra drag as a share of the model's (0 when the model holds; a
  drag error scales with v^2, a mass error with ax + g f). It starts at DRAG_FROM_S.

For each statistic: its largest magnitude on the six clean logs (the false-alarm side; from
WINDOW_S after the start, the window's first full value, which includes the start's
convergence), the threshold a factor FA_MARGIN above it, and on car_headwind its largest
magnitude, the first time it exceeds that threshold (seconds from the start; the log's first
excitation is at 0.0 s, MASS_GRADE_RESULTS.md) and the share of its values above it. Unless
--no-variants, the simulator (scripts/sim/mass_grade_scenarios.py) also makes two variants of
car_headwind, not bundled logs: a steady 10 m/s wind without gusts, and the gusts alone
(the wind minus its 10 m/s mean), to say which part of the wind a statistic sees.

A second table asks whether the ax row's statistic is specific to the wind: the clean logs
run again with the filter given a wrong initial mass (x 0.5, x 1.5 of the truth) or wrong
resistance keys (mg_cd x 0.8 and x 1.2, mg_fc x 1.5), against the same threshold.

A third table measures the reference's model-mismatch monitor (MASS_GRADE.md §4.8): the
filter's own EMA of the ax row's normalised innovation (time constant mg_mm_tau) from
mg.run's e_ax, its threshold MM_MARGIN x the largest |EMA| on the clean logs read from
mg_mm_tau on, and per log (the clean ones, car_headwind, the two variants) the largest |EMA|,
the samples over the threshold (false alarms on a clean log), the first time over it and the
flag's share of the log; run with mg_mm_e = 0 (the flag off), so the threshold is measured,
not assumed, and compared with MM_E_DEFAULT.

With --page the tables go between <!-- mass-headwind:begin/end -->,
<!-- mass-headwind-model:begin/end --> and <!-- mass-mismatch:begin/end --> of the page.
"""

import argparse
import dataclasses
import math
import os
import sys
from pathlib import Path

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts", "reference"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))
sys.path.insert(0, os.path.join(ROOT, "scripts"))

import mass_grade as mg  # noqa: E402
from md_tables import replace_region  # noqa: E402
from mass_logs import mass_grade_names  # noqa: E402

LOG_DIR = os.path.join(ROOT, "scenarios", "mass_grade")
WIND = "car_headwind"
WINDOW_S = 10.0      # s: the innovation statistics' window (issue 19's "within 10 s")
DRAG_FROM_S = 30.0   # s: the drag fit is read from here (one period of the headwind's cruise)
FA_MARGIN = 2.0      # threshold = FA_MARGIN x the largest value on a clean log
# "UKF + ax": the library's recommended preset (the reference's, with the brake bit of
# mg_pause_grade); "UKF": the speed row alone
CONFIGS = {"UKF + ax": mg.MG_CONFIGS["recommended"],
           "UKF": {"mg_adaptive": 0.0, "mg_use_ax": 0.0}}
# (label, configuration, series key, first time read)
STATS = (("e_ax (mean normalised ax innovation)", "UKF + ax", "e_ax", WINDOW_S),
         ("NIS_ax (mean squared, 1 if consistent)", "UKF + ax", "nis_ax", WINDOW_S),
         ("e_v (mean normalised speed innovation)", "UKF + ax", "e_v", WINDOW_S),
         ("NIS_v", "UKF + ax", "nis_v", WINDOW_S),
         ("e_v, speed row only", "UKF", "e_v", WINDOW_S),
         ("NIS_v, speed row only", "UKF", "nis_v", WINDOW_S),
         ("drag ratio beta / (rho C_d S / 2)", "UKF + ax", "drag", DRAG_FROM_S))


def vehicle(name):
    return "truck" if name.startswith("truck") else "car"


def clean_logs():
    return [n for n in mass_grade_names() if n != WIND]


def read(name, rows=None):
    """A log's columns, its first rows only when rows is given (the test's excerpts)."""
    cols, _ = mg.read_log(os.path.join(LOG_DIR, name + ".csv"))
    return cols if rows is None else {k: v[:rows] for k, v in cols.items()}


def run_probed(cols, params):
    """The reference over a log with its probe: per sample t, v, torque, ax, mass, grade,
    status and the normalised innovations e_v, e_ax (NaN where the row was not updated)."""
    est = mg.MassGrade(params)
    cur = {}
    est.probe = lambda row, innov, sd: cur.__setitem__(row, innov / sd)
    out = {k: [] for k in ("t", "v", "torque", "ax", "mass", "grade", "status", "e_v", "e_ax")}
    for s in mg.samples(cols, est.p):
        cur.clear()
        o = est.step(s)
        ok = o.status == mg.OK
        for k, x in (("t", s.t), ("v", s.v), ("torque", s.torque),
                     ("ax", math.nan if s.ax is None else s.ax), ("mass", o.mass),
                     ("grade", o.grade), ("status", o.status),
                     ("e_v", cur.get("v", math.nan) if ok else math.nan),
                     ("e_ax", cur.get("ax", math.nan) if ok else math.nan)):
            out[k].append(x)
    return {k: np.asarray(v, dtype=float) for k, v in out.items()}


def window_mean(x, t, width):
    """Mean of the finite x over the samples in (t_i - width, t_i], for each i whose window
    holds at least half its span's samples finite (NaN elsewhere). Uniform sampling assumed:
    the window is round(width / dt) samples."""
    dt = float(np.median(np.diff(t)))
    n = int(round(width / dt))
    ok = np.isfinite(x)
    c = np.concatenate([[0.0], np.cumsum(np.where(ok, x, 0.0))])
    k = np.concatenate([[0], np.cumsum(ok)])
    out = np.full(len(x), np.nan)
    if len(x) >= n:
        i = np.arange(n - 1, len(x))
        m = k[i + 1] - k[i + 1 - n]
        s = c[i + 1] - c[i + 1 - n]
        good = m >= n // 2
        out[i[good]] = s[good] / m[good]
    return out


def drag_ratio(r, p):
    """The running least-squares drag ratio (module docstring) over the updates so far; NaN
    until the 2 x 2 normal matrix is well conditioned (condition number below 1e12)."""
    k = 0.5 * p["mg_rho"] * p["mg_cd"] * p["mg_area"]
    ok = r["status"] == mg.OK
    v, ax = r["v"], r["ax"]
    y = r["torque"] / p["R"] - k * v * v - p["mg_m_rot"] * (ax - p["g"] * np.sin(r["grade"]))
    phi = ax + p["g"] * (p["mg_fc"] + p["mg_fr"] * v)
    w = np.where(ok, 1.0, 0.0)
    x1, x2 = phi * w, v * v * w
    a11, a12, a22 = np.cumsum(x1 * x1), np.cumsum(x1 * x2), np.cumsum(x2 * x2)
    b1, b2 = np.cumsum(x1 * y * w), np.cumsum(x2 * y * w)
    det = a11 * a22 - a12 * a12
    tr = a11 + a22
    out = np.full(len(v), np.nan)
    good = det > 1e-12 * tr * tr
    out[good] = (a11[good] * b2[good] - a12[good] * b1[good]) / det[good] / k
    return out


def series(cols, name, config):
    """Every statistic's time series of one log in one configuration."""
    p = mg.preset(vehicle(name), **CONFIGS[config])
    r = run_probed(cols, p)
    t = r["t"]
    out = {"t": t, "mass_rel": r["mass"] / float(cols["mass_true"][0]) - 1.0,
           "grade_err": r["grade"] - cols["grade_true"],
           "e_v": window_mean(r["e_v"], t, WINDOW_S),
           "nis_v": window_mean(r["e_v"] ** 2, t, WINDOW_S)}
    if config == "UKF + ax":
        out["e_ax"] = window_mean(r["e_ax"], t, WINDOW_S)
        out["nis_ax"] = window_mean(r["e_ax"] ** 2, t, WINDOW_S)
        out["drag"] = drag_ratio(r, p)
    return out


def grade_rmse(s, t_from=WINDOW_S):
    """The grade's RMSE from t_from to the end, degrees (the accuracy table's reading: its
    first excitation is at 0.0 s on car_headwind)."""
    e = s["grade_err"][s["t"] >= t_from - 1e-9]
    return math.degrees(math.sqrt(float(np.mean(e * e))))


def peak(s, key, t_from):
    """Largest |value| of a series from t_from on, and its signed value."""
    x = np.where(s["t"] >= t_from - 1e-9, s[key], np.nan)
    if not np.any(np.isfinite(x)):
        return math.nan, math.nan
    i = int(np.nanargmax(np.abs(x)))
    return abs(x[i]), x[i]


def first_over(s, key, t_from, thr):
    """(first time |value| > thr from t_from on, or NaN; share of the finite values above)."""
    sel = (s["t"] >= t_from - 1e-9) & np.isfinite(s[key])
    over = sel & (np.abs(s[key]) > thr)
    share = over.sum() / max(sel.sum(), 1)
    return (float(s["t"][np.argmax(over)]) if over.any() else math.nan), share


def study(wind_cols, clean, variants=None):
    """wind_cols: car_headwind's columns; clean: {name: columns}; variants: {label: columns}
    or None. Returns one dict per statistic of STATS."""
    runs = {}
    for cfg in CONFIGS:
        runs[(WIND, cfg)] = series(wind_cols, WIND, cfg)
        for n, c in clean.items():
            runs[(n, cfg)] = series(c, n, cfg)
        for lab, c in (variants or {}).items():
            runs[(lab, cfg)] = series(c, WIND, cfg)
    rows = []
    for label, cfg, key, t0 in STATS:
        cl = {n: peak(runs[(n, cfg)], key, t0)[0] for n in clean}
        worst = max(cl, key=lambda n: cl[n])
        thr = FA_MARGIN * cl[worst]
        hw_abs, hw_signed = peak(runs[(WIND, cfg)], key, t0)
        first, share = first_over(runs[(WIND, cfg)], key, t0, thr)
        row = {"label": label, "config": cfg, "key": key, "from": t0, "clean_max": cl[worst],
               "clean_log": worst, "threshold": thr, "wind_peak": hw_signed,
               "wind_abs": hw_abs, "first": first, "share": share,
               "separates": hw_abs > thr,
               "wind_end": float(runs[(WIND, cfg)][key][-1]),
               "clean_end_max": max(abs(float(runs[(n, cfg)][key][-1])) for n in clean),
               "variants": {lab: peak(runs[(lab, cfg)], key, t0)[1] for lab in (variants or {})},
               "variant_mass": {lab: float(runs[(lab, cfg)]["mass_rel"][-1])
                                for lab in (variants or {})},
               "grade_rmse": {lab: grade_rmse(runs[(lab, cfg)])
                              for lab in (WIND,) + tuple(variants or {})}}
        rows.append(row)
    return rows


# the filter given a wrong initial mass or wrong resistance keys on the clean logs: does the
# ax row's statistic fire on a model error other than the wind, and on a mass error alone?
MODEL_ERRORS = (("mg_m0 = truth x 0.5", "m0", 0.5), ("mg_m0 = truth x 1.5", "m0", 1.5),
                ("mg_cd x 0.8", "mg_cd", 0.8), ("mg_cd x 1.2", "mg_cd", 1.2),
                ("mg_fc x 1.5", "mg_fc", 1.5))


def model_error_rows(clean, threshold):
    """Per MODEL_ERRORS entry, on every clean log (UKF + ax): the e_ax peak from WINDOW_S on
    and the mass error at the end; the logs whose peak exceeds threshold."""
    rows = []
    for label, key, f in MODEL_ERRORS:
        per = {}
        for n, cols in clean.items():
            p = mg.preset(vehicle(n), **CONFIGS["UKF + ax"])
            if key == "m0":
                p["mg_m0"] = float(cols["mass_true"][0]) * f
            else:
                p[key] *= f
            r = run_probed(cols, p)
            s = {"t": r["t"], "e_ax": window_mean(r["e_ax"], r["t"], WINDOW_S)}
            per[n] = (peak(s, "e_ax", WINDOW_S)[0],
                      float(r["mass"][-1]) / float(cols["mass_true"][0]) - 1.0)
        rows.append({"label": label, "per": per,
                     "over": [n for n in per if per[n][0] > threshold]})
    return rows


def model_error_table(rows, threshold):
    out = [f"| the filter given | largest e_ax on a clean log | logs over {threshold:.3f} "
           "(their mass error at the end) |", "|---|---|---|"]
    for r in rows:
        worst = max(r["per"], key=lambda n: r["per"][n][0])
        over = ", ".join(f"{n} ({100.0 * r['per'][n][1]:+.1f} %)" for n in r["over"]) or "none"
        out.append(f"| {r['label']} | {r['per'][worst][0]:.3f} ({worst}) | {over} |")
    return out


MM_MARGIN = 2.0     # the monitor's threshold = MM_MARGIN x the clean logs' largest |EMA|


def mm_series(cols, name, **over):
    """The reference's monitor over one log (UKF + ax, the flag off): t, e_ax, mass error."""
    p = mg.preset(vehicle(name), **CONFIGS["UKF + ax"])
    p.update({"mg_mm_e": 0.0}, **over)
    r = mg.run(cols, p)
    return {"t": r["t"], "e_ax": r["e_ax"], "tau": p["mg_mm_tau"],
            "mass_rel": r["mass"] / float(cols["mass_true"][0]) - 1.0}


def mm_study(wind_cols, clean, variants=None, **over):
    """The monitor's threshold from the clean logs (read from mg_mm_tau on) and, per log,
    (largest |EMA| over the whole log, samples over the threshold, first time over it or NaN,
    share of the samples over it, mass error at the end)."""
    runs = {n: mm_series(c, n, **over) for n, c in clean.items()}
    runs[WIND] = mm_series(wind_cols, WIND, **over)
    for lab, c in (variants or {}).items():
        runs[lab] = mm_series(c, WIND, **over)
    cl = {n: peak(runs[n], "e_ax", runs[n]["tau"])[0] for n in clean}
    worst = max(cl, key=lambda n: cl[n])
    thr = MM_MARGIN * cl[worst]
    per = {}
    for n, r in runs.items():
        over_thr = np.abs(r["e_ax"]) > thr
        i0 = int(np.argmax(over_thr))
        i1 = len(over_thr) - 1 - int(np.argmax(over_thr[::-1]))
        first = float(r["t"][i0]) if over_thr.any() else math.nan
        per[n] = {"peak": float(np.max(np.abs(r["e_ax"]))), "n_over": int(over_thr.sum()),
                  "first": first, "share": float(over_thr.mean()),
                  "last": float(r["t"][i1]) if over_thr.any() else math.nan,
                  "mass_first": float(r["mass_rel"][i0]) if over_thr.any() else math.nan,
                  "end_flag": bool(over_thr[-1]), "e_end": float(r["e_ax"][-1]),
                  "mass_end": float(r["mass_rel"][-1]), "clean": n in clean}
    return {"threshold": thr, "clean_max": cl[worst], "clean_log": worst, "per": per}


def mm_table(res):
    out = [f"Threshold mg_mm_e = {MM_MARGIN:g} x {res['clean_max']:.4f} ({res['clean_log']}, "
           f"read from mg_mm_tau) = {res['threshold']:.4f}; the library's default "
           f"MM_E_DEFAULT = {mg.MM_E_DEFAULT:g}.", "",
           "| log | largest abs(EMA) | samples flagged | first flagged (mass error then) | "
           "last flagged | share flagged | EMA at the end (flag) | mass error at the end |",
           "|---|---|---|---|---|---|---|---|"]
    for n, r in res["per"].items():
        if math.isfinite(r["first"]):
            first = f"{r['first']:.1f} s ({100.0 * r['mass_first']:+.1f} %)"
            last = f"{r['last']:.1f} s"
        else:
            first = last = "never"
        lab = n if n in mass_grade_names() else f"{n} (simulated)"
        out.append(f"| {lab} | {r['peak']:.3f} | {r['n_over']} | {first} | {last} | "
                   f"{100.0 * r['share']:.0f} % | {r['e_end']:+.3f} "
                   f"({'set' if r['end_flag'] else 'clear'}) | {100.0 * r['mass_end']:+.1f} % |")
    return out


def make_variants():
    """car_headwind simulated with a steady 10 m/s wind, and with its gusts alone."""
    import sim.mass_grade_scenarios as sims
    sc = next(x for x in sims.MASS_GRADE_SCENARIOS if x.name == WIND)
    out = {}
    for label, wind in (("steady 10 m/s", sims.const(10.0)),
                        ("gusts alone", lambda t: sims._hw_wind(t) - 10.0)):
        sc2 = dataclasses.replace(sc, res=sims._car_res(wind, label))
        out[label] = sims.noisy(sims.table(sims.run(sc2), sc2), sc2)
    return out


def fmt(x, d=3):
    return "–" if not math.isfinite(x) else f"{x:+.{d}f}"


def table(rows):
    labs = list(rows[0]["variants"])
    head = ("| statistic | configuration | read from | largest on a clean log | threshold "
            f"({FA_MARGIN:g} x) | car_headwind: largest | first over the threshold | "
            "share of the log over it | at the end: car_headwind / largest clean |"
            + "".join(f" {lab} (simulated): largest |" for lab in labs))
    out = [head, "|" + "---|" * (9 + len(labs))]
    for r in rows:
        first = "never" if not math.isfinite(r["first"]) else f"{r['first']:.1f} s"
        out.append(
            f"| {r['label']} | {r['config']} | {r['from']:g} s | {r['clean_max']:.3f} "
            f"({r['clean_log']}) | {r['threshold']:.3f} | {fmt(r['wind_peak'])} | {first} | "
            f"{100.0 * r['share']:.0f} % | {fmt(r['wind_end'])} / {r['clean_end_max']:.3f} |"
            + "".join(f" {fmt(r['variants'][lab])} |" for lab in labs))
    if labs:
        masses = ", ".join(f"{lab} {100.0 * rows[0]['variant_mass'][lab]:+.1f} %" for lab in labs)
        grades = ", ".join(f"{lab} {rows[0]['grade_rmse'][lab]:.3f}°"
                           for lab in (WIND,) + tuple(labs))
        out += ["", f"The simulated variants' mass error at the end (UKF + ax): {masses}; the "
                f"grade RMSE from {WINDOW_S:g} s to the end (UKF + ax): {grades}."]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", help="write the table into this page's mass-headwind markers")
    ap.add_argument("--no-variants", action="store_true",
                    help="skip the two simulated variants of car_headwind")
    a = ap.parse_args(argv)
    clean = {n: read(n) for n in clean_logs()}
    variants = None if a.no_variants else make_variants()
    rows = study(read(WIND), clean, variants)
    mm = mm_table(mm_study(read(WIND), clean, variants))
    lines = table(rows)
    thr = next(r["threshold"] for r in rows if r["key"] == "e_ax")
    more = model_error_table(model_error_rows(clean, thr), thr)
    print("\n".join(lines + [""] + more + [""] + mm))
    if a.page:
        replace_region(Path(a.page), "<!-- mass-headwind:begin -->", "<!-- mass-headwind:end -->",
                       lines, "mass_headwind_study.py")
        replace_region(Path(a.page), "<!-- mass-headwind-model:begin -->",
                       "<!-- mass-headwind-model:end -->", more, "mass_headwind_study.py")
        replace_region(Path(a.page), "<!-- mass-mismatch:begin -->",
                       "<!-- mass-mismatch:end -->", mm, "mass_headwind_study.py")


if __name__ == "__main__":
    main()
