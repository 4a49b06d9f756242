#!/usr/bin/env python3
"""Measure the reference tyre identifier (docs/TYRE_ID.md) on the tyre identification logs
(scenarios/tyre_id/) and write the tables of docs/TYRE_ID_RESULTS.md between their markers.

    .venv/bin/python scripts/tools/tyre_id_results.py [--page docs/TYRE_ID_RESULTS.md]
        [--logs scenarios/tyre_id] [--n 64 256 1024 2048] [--seeds 1 2 3] [--jobs 2]

Every (log, filter, particle count, seed) is one run of scripts/reference/tyre_id.py with its
defaults; the augmented-state SCKF (scripts/reference/tyre_id_sckf.py, the same defaults) is
deterministic and has no particles: one run per log, its row "SCKF" with 2n = 20 cubature
points in place of a particle count.  Figures (docs/TYRE_ID_RESULTS.md says how each is defined):
  curve    RMSE of the identified lateral force curve against the truth's, per axle, in % of
           the truth's peak D, over the slip range the log excited: tan(alpha) from 0 to the
           largest |tan(alpha_true)| of the axle (after the tyre change on tid_tyre_change),
           the curves from the final means of D, C, K, E (B = K / (C D));
  mu@lim   |mu_id - mu| where |ay| > 0.6 mu g (the tyre near its limit), RMSE over those
           samples, per axle;
  sd_lin   the smallest sd of mu_id per axle while that axle's tyre has stayed linear (its
           truth utilisation has not yet passed 0.5), from 0.5 s;
  beta     RMSE of beta [deg] from 0.5 s;
  mu@brake |mu_id - mu| where the log's |ax| > AX_BRAKE (1.0 m/s^2: braking), RMSE over those
           samples, per axle (the --ellipse table only; "–" on the logs that do not brake).
With --ellipse only the runs at --main-n particles (and the SCKF's) are made, each without and
with the friction ellipse (ELLIPSE: tid_ellipse 1, tid_ell_ax_min at its default, the dead band
0.6 m/s^2; docs/TYRE_ID.md section 3.5), and one table goes between
<!-- tyre-id-results-ellipse:begin/end -->: each figure's median without -> with, the largest
|ax| of the log, and per filter how many (log, axle) cells meet each target without and with.
With --delta-filter the same table without and with the steering-angle filter (DELTA_FILTER:
tid_delta_q 0.05, docs/TYRE_ID.md section 4.4), between <!-- tyre-id-results-delta-filter:... -->.
With --delta-state the SCKF only, three runs per log: off, the steering-angle filter
(DELTA_FILTER) and delta as a state of the SCKF (DELTA_STATE: tid_delta_state_q, docs/TYRE_ID.md
section 15.7), one table between <!-- tyre-id-results-delta-state:... -->, and the target counts
for every density of --state-q.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import os
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]

import numpy as np  # noqa: E402

from md_tables import replace_region  # noqa: E402
from reference import tyre_id as T  # noqa: E402
from reference import tyre_id_sckf as TS  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402

ROOT = HERE.parent.parent
LOGS = ("tid_ramp_steer_high_mu", "tid_ramp_steer_low_mu", "tid_sine_steer", "tid_dlc_high_mu",
        "tid_dlc_low_mu", "tid_tyre_change", "tid_straight", "tid_brake_in_turn_high_mu",
        "tid_brake_in_turn_low_mu")
MARK = {k: (f"<!-- tyre-id-{k}:begin -->", f"<!-- tyre-id-{k}:end -->")
        for k in ("accuracy", "count", "ident", "results-ellipse", "results-delta-filter",
                  "results-delta-state", "results-spread")}
T_SKIP = 0.5          # s, the start not scored (prior)
# m/s^2: the samples scored as braking (mu@brake).  Above the logs' |ax| without a brake (at
# most 0.55: drag and the accelerometer's noise, sd 0.05) and below the lightest braking (the
# low-mu brake in turn, about 1.3)
AX_BRAKE = 1.0
# the logs that brake in a turn (the friction ellipse's, TYRE_ID.md section 3.5): their own rows
# in the per-log tables, not pooled into the filters' and particle counts' summary, whose
# medians stay the lateral-only steering logs' as the page's text quotes them
BRAKING = ("tid_brake_in_turn_high_mu", "tid_brake_in_turn_low_mu")
FILTERS = ("apf", "sir", "sckf")
SCKF_POINTS = f"– ({TS.N_POINTS} points)"
ELLIPSE = {"tid_ellipse": 1.0}   # --ellipse: the friction ellipse, its dead band at the default
# --delta-filter: the steering-angle filter (TYRE_ID.md section 4.4) at the density measured in
# docs/TYRE_ID_RESULTS.md "The steering-angle filter" (0.05 rad/s^2/sqrt(s))
DELTA_FILTER = {"tid_delta_q": 0.05}
# --delta-state: delta as a state of the SCKF (TYRE_ID.md section 15.7), its random walk's
# density matched to the fastest steering of the logs: the high-mu lane change's road-wheel
# rate peaks at 0.095 rad * 2 pi / 1.6 s = 0.37 rad/s, a change of 0.0037 rad a 10 ms sample,
# which a random walk gives as its one-sd step q sqrt(h) with q = 0.37 * sqrt(0.01) = 0.037
DELTA_STATE_Q = 0.04
# the identification targets (issue 20; the page's definitions): curve <= 5 % of the peak,
# mu at the limit within 0.05, the sd of mu while linear >= 0.2
# --spread: delta as a state (DELTA_STATE_Q) with each remedy for the spread of mu while the tyre
# is linear (docs/TYRE_ID_RESULTS.md "Keeping the spread while linear"): (label, extra keys)
SPREAD_REMEDIES = (("D's process noise tid_q_mu 0.1 (default 0.02)", {"tid_q_mu": 0.1}),
                   ("D's prior sd tid_sd0_mu 0.4 (default 0.3)", {"tid_sd0_mu": 0.4}),
                   ("D frozen below utilisation 0.3 (tid_d_freeze_u, §15.8)",
                    {"tid_d_freeze_u": 0.3}),
                   ("D frozen below utilisation 0.45 (tid_d_freeze_u, §15.8)",
                    {"tid_d_freeze_u": 0.45}),
                   ("D frozen below utilisation 0.5 (tid_d_freeze_u, §15.8)",
                    {"tid_d_freeze_u": 0.5}))
TARGETS = (("curve", "<=", 5.0), ("mulim", "<=", 0.05), ("sdlin", ">=", 0.2))


def run_filter(c, filt, n, seed, ellipse=False, n_steps=None, delta_filter=False):
    """One reference run of @p filt on the log columns @p c at its defaults (the particle
    filters: tid_n @p n, seed @p seed); @p ellipse adds ELLIPSE's keys, @p delta_filter
    DELTA_FILTER's (True) or, a number > 0, delta as a state of the SCKF with that
    tid_delta_state_q, or, a dict, delta as a state at DELTA_STATE_Q with those keys added."""
    extra = dict(ELLIPSE) if ellipse else {}
    if isinstance(delta_filter, dict):
        extra.update({"tid_delta_state_q": DELTA_STATE_Q, **delta_filter})
    elif delta_filter is True:
        extra.update(DELTA_FILTER)
    elif delta_filter:
        extra["tid_delta_state_q"] = float(delta_filter)
    if filt == "sckf":
        return TS.run(c, extra, n_steps=n_steps)
    return T.run(c, {"tid_n": float(n), "tid_filter": filt, **extra}, seed=seed,
                 n_steps=n_steps)


def curves(c, out, axle, k0):
    """The truth's and the final identified lateral force curves of @p axle over the slip
    range the log excited from sample @p k0: (grid of tan(alpha) from 0 to t_max, truth,
    identified, D_true, t_max); grid, truth and identified are None when t_max < 1e-3."""
    a = "f" if axle == 0 else "r"
    t_abs = np.abs(np.tan(c[f"alpha_{a}_true"][k0:]))
    t_max = float(t_abs.max())
    D, C, B, E = (float(c[f"{k}_{a}_true"][-1]) for k in "DCBE")
    if t_max < 1e-3:
        return None, None, None, D, t_max
    grid = np.linspace(0.0, t_max, 201)
    truth = T.mf_force(grid, D, C, B, E)
    Di, Ci, Ki, Ei = (out[f"{k}_{a}"][-1] for k in "DCKE")
    ident = T.mf_force(grid, Di, Ci, Ki / (Ci * Di), Ei)
    return grid, truth, ident, D, t_max


def curve_rmse(c, out, axle, k0):
    """RMSE in % of D_true of the final identified curve vs the truth over [0, t_max]."""
    grid, truth, ident, D, t_max = curves(c, out, axle, k0)
    if grid is None:
        return math.nan, t_max
    return 100.0 * math.sqrt(float(np.mean((ident - truth) ** 2))) / D, t_max


def plot_curves(panels):
    """The figure of identified lateral force curves against the truth: one axis per panel
    (title, log columns, run output, k0), both axles, the force [kN] over the slip angle
    [deg] the log excited (curves())."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(panels), figsize=(5.5 * len(panels), 4), squeeze=False)
    for ax, (title, c, out, k0) in zip(axes[0], panels):
        for axle, name, colour in ((0, "front", "C0"), (1, "rear", "C1")):
            grid, truth, ident, _, _ = curves(c, out, axle, k0)
            if grid is None:
                continue
            alpha = np.degrees(np.arctan(grid))
            ax.plot(alpha, truth / 1e3, "-", color=colour, lw=1.2, label=f"{name}, truth")
            ax.plot(alpha, ident / 1e3, "--", color=colour, lw=1.2, label=f"{name}, identified")
        ax.set_xlabel("slip angle [deg]")
        ax.set_ylabel("lateral force [kN]")
        ax.set_title(title, fontsize=9)
        ax.legend(fontsize=7)
    fig.tight_layout()
    return fig


def measure(job):
    """job = (log, filter, n, seed[, ellipse[, every[, delta_filter]]]) -> the figures of one
    run (a dict). every > 1: the identifier runs on every every-th sample of the log (its rate
    divided by every, h = every sample periods) and is scored on those samples."""
    log, filt, n, seed = job[:4]
    ellipse = bool(job[4]) if len(job) > 4 else False
    every = int(job[5]) if len(job) > 5 else 1
    delta_filter = job[6] if len(job) > 6 else False
    c = read_csv_log(str(ROOT / "scenarios" / "tyre_id" / f"{log}.csv")).columns
    if every > 1:
        c = {k: np.asarray(v)[::every] for k, v in c.items()}
    t0 = time.perf_counter()
    out = run_filter(c, filt, n, seed, ellipse, delta_filter=delta_filter)
    cost = (time.perf_counter() - t0) / len(c["t"])
    t = c["t"]
    k_sk = int(np.searchsorted(t, T_SKIP))
    k0 = int(np.searchsorted(t, 8.0)) if log == "tid_tyre_change" else 0
    res = {"log": log, "filter": filt, "n": n, "seed": seed, "ms": 1e3 * cost,
           "ellipse": ellipse, "every": every, "delta_filter": delta_filter, "ax_max": float(np.max(np.abs(c["ax"])))}
    g = 9.81
    ay = np.abs(c["ay"])
    for axle, a, w in ((0, "f", ("fl", "fr")), (1, "r", ("rl", "rr"))):
        res[f"curve_{a}"], res[f"tmax_{a}"] = curve_rmse(c, out, axle, k0)
        mu = 0.5 * (c[f"mu_{w[0]}"] + c[f"mu_{w[1]}"])
        lim = ay > 0.6 * mu * g
        lim[:k_sk] = False
        err = out[f"mu_{a}"][lim] - mu[lim]
        res[f"mulim_{a}"] = math.sqrt(float(np.mean(err ** 2))) if lim.any() else math.nan
        res[f"nlim_{a}"] = int(lim.sum())
        brk = np.abs(c["ax"]) > AX_BRAKE
        brk[:k_sk] = False
        err = out[f"mu_{a}"][brk] - mu[brk]
        res[f"mubrk_{a}"] = math.sqrt(float(np.mean(err ** 2))) if brk.any() else math.nan
        util = np.maximum(c[f"util_{w[0]}"], c[f"util_{w[1]}"])
        passed = np.nonzero(util > 0.5)[0]
        k_end = int(passed[0]) if passed.size else len(t)
        sd = out[f"sd_mu_{a}"][k_sk:k_end]
        res[f"sdlin_{a}"] = float(sd.min()) if sd.size else math.nan
        # identifiability: final posterior sd / prior sd and final error of K and D
        for p in ("D", "C", "K", "E"):
            res[f"sdfin_{p}_{a}"] = float(out[f"sd_{p}_{a}"][-1])
            res[f"mean_{p}_{a}"] = float(out[f"{p}_{a}"][-1])
        res[f"Ktrue_{a}"] = float(c[f"B_{a}_true"][-1] * c[f"C_{a}_true"][-1]
                                  * c[f"D_{a}_true"][-1])
        res[f"Dtrue_{a}"] = float(c[f"D_{a}_true"][-1])
    res["beta"] = math.degrees(math.sqrt(float(np.mean(
        (out["beta"][k_sk:] - c["beta_true"][k_sk:]) ** 2))))
    return res


def fmt(v, spec):
    return "–" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)


def agg(rows, key, how=np.median):
    v = [r[key] for r in rows if not math.isnan(r[key])]
    return float(how(v)) if v else math.nan


def tables(results, n_main, seeds):
    by = {}
    for r in results:
        by.setdefault((r["log"], r["filter"], r["n"]), []).append(r)
    acc = [f"{n_main} particles, median over seeds {', '.join(map(str, seeds))} (the worst "
           "seed in brackets for the curve and mu at the limit); SCKF: deterministic, one run "
           f"({TS.N_POINTS} cubature points). Curve: % of the peak; "
           "t_max: the largest |tan(alpha)| the axle saw.", "",
           "| log | filter | curve f % (t_max) | curve r % (t_max) | mu@lim f | mu@lim r "
           "| min sd_mu linear f / r | beta RMSE deg | ms/step |",
           "|---|---|---|---|---|---|---|---|---|"]
    for log in LOGS:
        for filt in FILTERS:
            rows = by.get((log, filt, n_main), [])
            if not rows:
                continue
            cell = []
            for a in "fr":
                cell.append(f"{fmt(agg(rows, 'curve_' + a), '.1f')} "
                            f"[{fmt(agg(rows, 'curve_' + a, np.max), '.1f')}] "
                            f"({fmt(rows[0]['tmax_' + a], '.3f')})")
            for a in "fr":
                cell.append(f"{fmt(agg(rows, 'mulim_' + a), '.3f')} "
                            f"[{fmt(agg(rows, 'mulim_' + a, np.max), '.3f')}]")
            cell.append(f"{fmt(agg(rows, 'sdlin_f', np.min), '.2f')} / "
                        f"{fmt(agg(rows, 'sdlin_r', np.min), '.2f')}")
            cell.append(fmt(agg(rows, "beta"), ".3f"))
            cell.append(fmt(agg(rows, "ms"), ".2f"))
            acc.append(f"| {log} | {filt.upper()} | " + " | ".join(cell) + " |")
    cnt = ["Median over the steering logs that do not brake (all but tid_straight and "
           f"{' and '.join(BRAKING)}, which have their rows above) and seeds; curve and mu at "
           "the limit of both axles pooled.", "",
           "| filter | particles | curve % median | curve % worst | mu@lim median | "
           "mu@lim worst | beta RMSE deg median | ms/step (Python) |",
           "|---|---|---|---|---|---|---|---|"]
    ns = sorted({r["n"] for r in results})
    for filt in FILTERS:
        for n in ns:
            rows = [r for r in results if r["filter"] == filt and r["n"] == n
                    and r["log"] != "tid_straight" and r["log"] not in BRAKING]
            if not rows:
                continue
            label = SCKF_POINTS if filt == "sckf" else str(n)
            cv = [r[f"curve_{a}"] for r in rows for a in "fr" if not math.isnan(r[f"curve_{a}"])]
            ml = [r[f"mulim_{a}"] for r in rows for a in "fr" if not math.isnan(r[f"mulim_{a}"])]
            cnt.append(f"| {filt.upper()} | {label} | {fmt(float(np.median(cv)), '.1f')} | "
                       f"{fmt(float(np.max(cv)), '.1f')} | {fmt(float(np.median(ml)), '.3f')} | "
                       f"{fmt(float(np.max(ml)), '.3f')} | "
                       f"{fmt(float(np.median([r['beta'] for r in rows])), '.3f')} | "
                       f"{fmt(float(np.median([r['ms'] for r in rows])), '.2f')} |")
    p = T.TID_DEFAULTS
    prior = {"D": p["tid_sd0_mu"], "C": p["tid_sd0_C"], "K": p["tid_sd0_cy_rel"],
             "E": p["tid_sd0_E"]}
    idt = [f"APF, {n_main} particles, seed {seeds[0]}, and the SCKF: the final sd of each "
           "parameter over its "
           "prior sd (D as D/Fz0 against tid_sd0_mu, K as K/(cy Fz0) against tid_sd0_cy_rel; "
           "below 0.3: identified), and the final errors of K and D in % of the truth.", "",
           "| log | axle | filter | sd D | sd C | sd K | sd E | K error % | D error % |",
           "|---|---|---|---|---|---|---|---|---|"]
    params = {"m": 1830.0, "g": 9.81, "Lf": 1.40, "Lr": 1.65, "cy": 15.0}
    La = params["Lf"] + params["Lr"]
    fz0 = {"f": params["m"] * params["g"] * params["Lr"] / La,
           "r": params["m"] * params["g"] * params["Lf"] / La}
    for log, a, filt in ((lg, ax, f) for lg in LOGS for ax in "fr" for f in ("apf", "sckf")):
        rows = [r for r in by.get((log, filt, n_main), []) if r["seed"] == seeds[0]]
        if not rows:
            continue
        r = rows[0]
        scale = {"D": fz0[a], "C": 1.0, "K": params["cy"] * fz0[a], "E": 1.0}
        ratios = [r[f"sdfin_{q}_{a}"] / scale[q] / prior[q] for q in "DCKE"]
        ek = 100.0 * (r[f"mean_K_{a}"] / r[f"Ktrue_{a}"] - 1.0)
        ed = 100.0 * (r[f"mean_D_{a}"] / r[f"Dtrue_{a}"] - 1.0)
        idt.append(f"| {log} | {a} | {filt.upper()} | "
                   + " | ".join(fmt(x, ".2f") for x in ratios)
                   + f" | {ek:+.0f} | {ed:+.0f} |")
    return acc, cnt, idt


def meets(v, how, lim):
    return (v <= lim) if how == "<=" else (v >= lim)


def ellipse_table(off, on, n_main, seeds, what=None):
    """The --ellipse table from the runs without (@p off) and with (@p on) the ellipse (or,
    @p what given, with what @p what names)."""
    def group(results):
        by = {}
        for r in results:
            by.setdefault((r["log"], r["filter"]), []).append(r)
        return by
    b0, b1 = group(off), group(on)
    if what is None:
        what = ("the friction ellipse (tid_ellipse 1, "
                f"tid_ell_ax_min {T.TID_DEFAULTS['tid_ell_ax_min']:g} m/s²)")
    lines = [f"{n_main} particles (APF, SIR), median over seeds {', '.join(map(str, seeds))}; "
             f"SCKF one run. Each cell: without → with {what}; \"=\" where the two "
             "print the same. |ax| max: the log's largest |ax|, m/s²; mu@brake: over the samples "
             f"whose |ax| > {AX_BRAKE:g} m/s² (\"–\": the log does not brake).", "",
             "| log | filter | \\|ax\\| max | curve f % | curve r % | mu@lim f | mu@lim r "
             "| mu@brake f | mu@brake r | min sd_mu linear f / r | beta RMSE deg |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]

    def pair(r0, r1, key, spec, how=np.median):
        a, b = fmt(agg(r0, key, how), spec), fmt(agg(r1, key, how), spec)
        return f"{a} =" if a == b else f"{a} → {b}"
    for log in LOGS:
        for filt in FILTERS:
            r0, r1 = b0.get((log, filt), []), b1.get((log, filt), [])
            if not r0 or not r1:
                continue
            cell = [fmt(r0[0]["ax_max"], ".2f")]
            cell += [pair(r0, r1, "curve_" + a, ".1f") for a in "fr"]
            cell += [pair(r0, r1, "mulim_" + a, ".3f") for a in "fr"]
            cell += [pair(r0, r1, "mubrk_" + a, ".3f") for a in "fr"]
            cell.append(pair(r0, r1, "sdlin_f", ".2f", np.min) + " / "
                        + pair(r0, r1, "sdlin_r", ".2f", np.min))
            cell.append(pair(r0, r1, "beta", ".3f"))
            lines.append(f"| {log} | {filt.upper()} | " + " | ".join(cell) + " |")
    lines += ["", "(log, axle) cells of the median that meet each target, without → with "
              "(curve ≤ 5 %, mu@lim ≤ 0.05, min sd_mu linear ≥ 0.2 over its seeds; cells "
              "without a figure not counted):", "",
              "| filter | curve ≤ 5 % | mu@lim ≤ 0.05 | sd_mu linear ≥ 0.2 |",
              "|---|---|---|---|"]
    for filt in FILTERS:
        cell = []
        for key, how, lim in TARGETS:
            cnt = []
            for by in (b0, b1):
                ok = tot = 0
                for (log, f), rows in by.items():
                    if f != filt:
                        continue
                    for a in "fr":
                        v = agg(rows, f"{key}_{a}", np.min if key == "sdlin" else np.median)
                        if not math.isnan(v):
                            tot += 1
                            ok += meets(v, how, lim)
                cnt.append(f"{ok}/{tot}")
            cell.append(" → ".join(cnt))
        lines.append(f"| {filt.upper()} | " + " | ".join(cell) + " |")
    return lines


def delta_state_table(runs, qs):
    """The --delta-state table (SCKF): each cell off -> steering-angle filter -> delta as a
    state (DELTA_STATE_Q), then the target counts of every density of @p qs."""
    def rows(d):
        return {r["log"]: [r] for r in runs if r["delta_filter"] == d}
    variants = [rows(False), rows(True), rows(DELTA_STATE_Q)]
    lines = ["SCKF, one run per log. Each cell: off → the steering-angle filter (tid_delta_q "
             f"{DELTA_FILTER['tid_delta_q']:g}, §4.4) → δ as a state (tid_delta_state_q "
             f"{DELTA_STATE_Q:g} rad/√s, §15.7). mu@lim, sd_mu linear, beta as the tables above.",
             "", "| log | curve f % | curve r % | mu@lim f | mu@lim r | min sd_mu linear f | "
             "min sd_mu linear r | beta RMSE deg |", "|---|---|---|---|---|---|---|---|"]
    keys = (("curve_f", ".1f"), ("curve_r", ".1f"), ("mulim_f", ".3f"), ("mulim_r", ".3f"),
            ("sdlin_f", ".2f"), ("sdlin_r", ".2f"), ("beta", ".3f"))
    for log in LOGS:
        if not all(log in v for v in variants):
            continue
        cell = [" → ".join(fmt(v[log][0][k], spec) for v in variants) for k, spec in keys]
        lines.append(f"| {log} | " + " | ".join(cell) + " |")
    lines += ["", "(log, axle) cells that meet each target (cells without a figure not counted):",
              "", "| SCKF variant | curve ≤ 5 % | mu@lim ≤ 0.05 | sd_mu linear ≥ 0.2 | "
              "beta RMSE deg, median over the logs |", "|---|---|---|---|---|"]
    names = [(False, "off (the default)"),
             (True, f"steering-angle filter, tid_delta_q {DELTA_FILTER['tid_delta_q']:g}")]
    names += [(q, f"δ as a state, tid_delta_state_q {q:g}") for q in qs]
    for d, name in names:
        by = rows(d)
        cell = []
        for key, how, lim in TARGETS:
            vals = [by[log][0][f"{key}_{a}"] for log in by for a in "fr"]
            vals = [v for v in vals if not math.isnan(v)]
            cell.append(f"{sum(meets(v, how, lim) for v in vals)}/{len(vals)}")
        cell.append(fmt(float(np.median([by[log][0]["beta"] for log in by])), ".3f"))
        lines.append(f"| {name} | " + " | ".join(cell) + " |")
    return lines


def spread_table(runs, remedies):
    """The --spread table (SCKF): per (log, axle) cell the figures off -> delta as a state
    (DELTA_STATE_Q) -> each of @p remedies (label, keys) on top, then the target counts."""
    variants = [(False, "off (the default)"),
                (DELTA_STATE_Q, f"δ as a state, tid_delta_state_q {DELTA_STATE_Q:g}")]
    variants += [(keys, f"δ as a state + {label}") for label, keys in remedies]

    def rows(d):
        return {r["log"]: r for r in runs if r["delta_filter"] == d
                and type(r["delta_filter"]) is type(d)}
    by = [rows(d) for d, _ in variants]
    lines = ["SCKF, one run per log. Each cell: " + " → ".join(
        ["off", "δ as a state"] + [f"({i + 1})" for i in range(len(remedies))])
        + "; the remedies: " + "; ".join(f"({i + 1}) {label}" for i, (label, _)
                                        in enumerate(remedies)) + ".", "",
        "| log | curve f % | curve r % | mu@lim f | mu@lim r | min sd_mu linear f | "
        "min sd_mu linear r | beta RMSE deg |", "|---|---|---|---|---|---|---|---|"]
    keys = (("curve_f", ".1f"), ("curve_r", ".1f"), ("mulim_f", ".3f"), ("mulim_r", ".3f"),
            ("sdlin_f", ".2f"), ("sdlin_r", ".2f"), ("beta", ".3f"))
    for log in LOGS:
        if not all(log in v for v in by):
            continue
        cell = [" → ".join(fmt(v[log][k], spec) for v in by) for k, spec in keys]
        lines.append(f"| {log} | " + " | ".join(cell) + " |")
    lines += ["", "(log, axle) cells that meet each target (cells without a figure not counted):",
              "", "| SCKF variant | curve ≤ 5 % | mu@lim ≤ 0.05 | sd_mu linear ≥ 0.2 | "
              "beta RMSE deg, median over the logs |", "|---|---|---|---|---|"]
    for (_, name), v in zip(variants, by):
        cell = []
        for key, how, lim in TARGETS:
            vals = [v[log][f"{key}_{a}"] for log in v for a in "fr"]
            vals = [x for x in vals if not math.isnan(x)]
            cell.append(f"{sum(meets(x, how, lim) for x in vals)}/{len(vals)}")
        cell.append(fmt(float(np.median([v[log]["beta"] for log in v])), ".3f"))
        lines.append(f"| {name} | " + " | ".join(cell) + " |")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", default=str(ROOT / "docs" / "TYRE_ID_RESULTS.md"))
    ap.add_argument("--n", type=int, nargs="+", default=[64, 256, 1024, 2048])
    ap.add_argument("--main-n", type=int, default=1024)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--ellipse", action="store_true",
                    help="only the --main-n runs, without and with the friction ellipse "
                    "(tid_ellipse 1 at the default dead band): the table 'with the friction "
                    "ellipse'")
    ap.add_argument("--delta-filter", action="store_true",
                    help="only the --main-n runs, without and with the steering-angle filter "
                    "(DELTA_FILTER): the table 'The steering-angle filter'")
    ap.add_argument("--delta-state", action="store_true",
                    help="the SCKF only: off, the steering-angle filter and delta as a state "
                    "(the table 'The steering angle as a state of the SCKF')")
    ap.add_argument("--state-q", type=float, nargs="+", default=[0.01, 0.02, DELTA_STATE_Q, 0.1],
                    help="--delta-state: the tid_delta_state_q densities counted (rad/sqrt(s))")
    ap.add_argument("--spread", action="store_true",
                    help="the SCKF only: off, delta as a state and delta as a state with each "
                    "remedy of SPREAD_REMEDIES (the table 'Keeping the spread while linear')")
    args = ap.parse_args(argv)
    if args.spread:
        variants = [False, DELTA_STATE_Q] + [keys for _, keys in SPREAD_REMEDIES]
        jobs = [(log, "sckf", args.main_n, args.seeds[0], False, 1, d)
                for d in variants for log in LOGS]
        t0 = time.perf_counter()
        with multiprocessing.Pool(args.jobs) as pool:
            results = pool.map(measure, jobs, chunksize=1)
        print(f"{len(jobs)} runs in {time.perf_counter() - t0:.0f} s")
        lines = spread_table(results, SPREAD_REMEDIES)
        replace_region(Path(args.page), *MARK["results-spread"], lines, "tyre_id_results")
        print("\n".join(lines))
        return
    if args.delta_state:
        qs = sorted(set(args.state_q) | {DELTA_STATE_Q})
        jobs = [(log, "sckf", args.main_n, args.seeds[0], False, 1, d)
                for d in [False, True] + qs for log in LOGS]
        t0 = time.perf_counter()
        with multiprocessing.Pool(args.jobs) as pool:
            results = pool.map(measure, jobs, chunksize=1)
        print(f"{len(jobs)} runs in {time.perf_counter() - t0:.0f} s")
        lines = delta_state_table(results, qs)
        replace_region(Path(args.page), *MARK["results-delta-state"], lines, "tyre_id_results")
        print("\n".join(lines))
        return
    if args.delta_filter:
        jobs = [(log, filt, args.main_n, s, False, 1, d) for d in (False, True) for log in LOGS
                for filt in ("apf", "sir") for s in args.seeds]
        jobs += [(log, "sckf", args.main_n, args.seeds[0], False, 1, d) for d in (False, True)
                 for log in LOGS]
        t0 = time.perf_counter()
        with multiprocessing.Pool(args.jobs) as pool:
            results = pool.map(measure, jobs, chunksize=1)
        print(f"{len(jobs)} runs in {time.perf_counter() - t0:.0f} s")
        what = ("the steering-angle filter (tid_delta_q "
                f"{DELTA_FILTER['tid_delta_q']:g} rad/s²/√s, TYRE_ID.md §4.4)")
        lines = ellipse_table([r for r in results if not r["delta_filter"]],
                              [r for r in results if r["delta_filter"]], args.main_n, args.seeds,
                              what)
        replace_region(Path(args.page), *MARK["results-delta-filter"], lines, "tyre_id_results")
        print("\n".join(lines))
        return
    if args.ellipse:
        jobs = [(log, filt, args.main_n, s, e) for e in (False, True) for log in LOGS
                for filt in ("apf", "sir") for s in args.seeds]
        jobs += [(log, "sckf", args.main_n, args.seeds[0], e) for e in (False, True)
                 for log in LOGS]
        t0 = time.perf_counter()
        with multiprocessing.Pool(args.jobs) as pool:
            results = pool.map(measure, jobs, chunksize=1)
        print(f"{len(jobs)} runs in {time.perf_counter() - t0:.0f} s")
        lines = ellipse_table([r for r in results if not r["ellipse"]],
                              [r for r in results if r["ellipse"]], args.main_n, args.seeds)
        replace_region(Path(args.page), *MARK["results-ellipse"], lines, "tyre_id_results")
        print("\n".join(lines))
        return
    jobs = [(log, filt, n, s) for n in sorted(args.n, reverse=True) for log in LOGS
            for filt in ("apf", "sir") for s in args.seeds]
    jobs += [(log, "sckf", args.main_n, args.seeds[0]) for log in LOGS]
    t0 = time.perf_counter()
    with multiprocessing.Pool(args.jobs) as pool:
        results = pool.map(measure, jobs, chunksize=1)
    print(f"{len(jobs)} runs in {time.perf_counter() - t0:.0f} s")
    acc, cnt, idt = tables(results, args.main_n, args.seeds)
    page = Path(args.page)
    for key, lines in (("accuracy", acc), ("count", cnt), ("ident", idt)):
        replace_region(page, *MARK[key], lines, "tyre_id_results")
        print("\n".join(lines))


if __name__ == "__main__":
    main()
