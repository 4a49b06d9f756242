#!/usr/bin/env python3
"""Measure the model-validity monitor (scripts/reference/monitor.py) on the bundled logs.

    .venv/bin/python scripts/tools/monitor_results.py [--jobs 2] [--cache build/monitor]
        [--page docs/MONITOR.md]

Runs the float64 reference of the default preset (scripts/reference/trusted.py, equal to the
C double build to 1e-9) on every bundled log of both truth tyres (scenarios/*.csv: Dugoff
truth, *.mf.csv Magic Formula truth, *.nf.csv noise-free Dugoff truth; a log whose metadata
has truth_* lines, wrong_tyre_data, is a group of its own, never a clean one), on the fault logs
(scenarios/faults/, except spike_ax_beyond_limit, whose samples the library refuses) and on
the banked curves of scenarios/observer/ (measured velocities), recording each step's
innovation; applies the monitor to the recorded run (it does not feed back), and runs the
estimator twice more with covariance matching of R in the loop (always; only while fired).
Writes the tables between the markers <!-- monitor-NAME:begin/end --> of the page.
Each run is cached in --cache as .npz keyed by the log's name, size and mtime and the
variant (delete the directory to recompute).

Figures per log, pooled over the four wheels as the trust table (docs/RESULTS.md), over the
settled samples of mu_replay (from 1 s, and 0.5 s after each change of that wheel's true mu):
valid share, excited valid (true utilisation >= 0.5), RMSE when valid, consistency when valid
(|error| <= 2 sd among the valid samples), max |error| while valid; "mismatch" the share of
all steps with the monitor's status; "t fire" the first step it fires; "t claim" the first
settled sample the estimator (without the monitor) reports valid with |error| > 2 sd.
"""
from __future__ import annotations

import argparse
import hashlib
import os
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
from reference import logs, monitor, params, trusted  # noqa: E402
from sim import faults  # noqa: E402
sys.path.insert(0, str(ROOT / "scripts" / "tools"))
from md_tables import replace_region  # noqa: E402

WHEELS = ("fl", "fr", "rl", "rr")
SETTLE_START_S, SETTLE_AFTER_CHANGE_S, CHANGE_MIN = 1.0, 0.5, 1e-9   # mu_replay's (metrics.c)
EXCITE_UTIL, CONSISTENCY_K = 0.5, 2.0                                 # mu_replay's
TARGET_ERR, TARGET_CONS = 0.25, 0.9                                   # issue 17's targets
VARIANTS = ("base", "cm_always", "cm_fired")
CM_GROUPS = ("mf", "wrong", "fault", "bank")   # covariance matching measured on these (run time)
SKIP_FAULTS = faults.REFUSED_BY_LIBRARY   # beyond the input limits: the library refuses them
OBSERVER_LOGS = ("bank_curve_neg5.mf.csv", "bank_curve_pos5.mf.csv", "bank_curve_neg5.csv")


def wrong_tyre(path: Path) -> bool:
    """Whether the log's truth tyre is not its parameter file's: `# truth_<key>` metadata
    lines other than truth_tyre (scripts/sim/scenarios.py, wrong_tyre_data). Such a log is
    never a clean one."""
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            if not line.startswith("#"):
                return False
            key = line[1:].partition("=")[0].strip()
            if key.startswith("truth_") and key != "truth_tyre":
                return True
    return False


def log_set(scen: Path) -> list[tuple[str, str, Path]]:
    """(group, name, path): clean MF, Dugoff, noise-free Dugoff, wrong tyre data (both truth
    tyres, noisy and noise-free), faults, banked curves."""
    out = []
    for p in sorted(scen.glob("*.csv")):
        g = "mf" if p.name.endswith(".mf.csv") else "nf" if p.name.endswith(".nf.csv") else "dugoff"
        if wrong_tyre(p):
            g = "wrong"
        out.append((g, p.name[: -len(".csv")], p))
    for p in sorted((scen / "faults").glob("*.csv")):
        if not p.name.startswith(SKIP_FAULTS):
            out.append(("fault", p.name[: -len(".csv")], p))
    for name in OBSERVER_LOGS:
        p = scen / "observer" / name
        if p.is_file():
            out.append(("bank", name[: -len(".csv")], p))
    return out


def cache_key(path: Path, variant: str) -> str:
    """The log (name, size, mtime), the variant and the reference sources the run depends on
    (monitor.py only for the covariance-matching runs, which run it in the loop)."""
    st = path.stat()
    files = ("trusted.py", "model.py", "filters.py", "params.py")
    files += ("monitor.py",) if variant != "base" else ()
    src = "".join((ROOT / "scripts" / "reference" / f).read_text() for f in files)
    h = hashlib.sha1(f"{path.name}:{st.st_size}:{int(st.st_mtime)}:{variant}:{src}".encode())
    return h.hexdigest()[:16]


def run_one(args) -> tuple[str, str, dict]:
    """One (log, variant) through the reference; cached."""
    path, variant, cache = args
    f = Path(cache) / f"{path.name}.{variant}.{cache_key(path, variant)}.npz"
    if f.is_file():
        with np.load(f) as z:
            return str(path), variant, {k: z[k] for k in z.files}
    log = logs.read_csv_log(str(path))
    p = params.resolve(log.meta, None, source=str(path), preset="default")
    adapt = None
    if variant != "base":
        adapt = monitor.CovarianceMatching(p, p["dt"], where=variant.split("_", 1)[1])
    res = trusted.run(log, p, adapt=adapt)
    keep = {k: res[k] for k in ("t", "mu", "sd", "valid", "status", "nu", "s_zz", "c_pers")}
    keep["truth"] = np.stack([log.col(f"mu_{w}") for w in WHEELS], 1)
    keep["util"] = (np.stack([log.col(f"util_{w}") for w in WHEELS], 1)
                    if "util_fl" in log.columns else np.full((len(log), 4), np.nan))
    keep["dt"] = np.array(p["dt"])
    Path(cache).mkdir(parents=True, exist_ok=True)
    np.savez(f, **keep)
    return str(path), variant, keep


def settled(t, truth) -> np.ndarray:
    """(N, 4) mask of mu_replay's settled samples per wheel."""
    mask = np.zeros(truth.shape, dtype=bool)
    for w in range(truth.shape[1]):
        t_change = None
        for k in range(len(t)):
            if k > 0 and abs(truth[k, w] - truth[k - 1, w]) > CHANGE_MIN:
                t_change = t[k]
            mask[k, w] = not (t[k] < t[0] + SETTLE_START_S
                              or (t_change is not None and t[k] < t_change + SETTLE_AFTER_CHANGE_S))
    return mask


def figures(r: dict) -> dict:
    """Trust figures of one run (keys as the module docstring)."""
    t, mu, sd, valid, truth = r["t"], r["mu"], r["sd"], r["valid"].astype(bool), r["truth"]
    s = settled(t, truth)
    err = np.abs(mu - truth)
    sv = s & valid
    exc = s & (r["util"] >= EXCITE_UTIL)
    cons = err <= CONSISTENCY_K * sd
    claim = sv & ~cons
    out = {
        "valid": sv.sum() / max(s.sum(), 1),
        "excited_valid": (exc & valid).sum() / exc.sum() if exc.sum() else None,
        "rmse_valid": float(np.sqrt(np.mean(err[sv] ** 2))) if sv.any() else None,
        "cons_valid": float(cons[sv].mean()) if sv.any() else None,
        "max_err_valid": float(err[sv].max()) if sv.any() else None,
        "consistency": float(cons[s].mean()) if s.any() else None,
        "mismatch": float(np.mean(r["status"] == monitor.STATUS_MISMATCH)),
        "fired_share": float(np.mean(r["fired"])) if "fired" in r else 0.0,
        "t_claim": float(t[np.argmax(claim.any(1))]) if claim.any() else None,
        "n_bad": int((sv & (err > TARGET_ERR)).sum()),
    }
    fired = r.get("fired")
    out["t_fire"] = float(t[np.argmax(fired)]) if fired is not None and fired.any() else None
    return out


def fmt(x, spec=".3f"):
    return "–" if x is None else format(x, spec)


def pct(x):
    return "–" if x is None else f"{100 * x:.0f} %"


def meets(fg) -> bool:
    """Issue 17's per-log targets: consistency when valid >= 0.9, max error while valid <= 0.25."""
    return fg["valid"] == 0 or ((fg["cons_valid"] or 0) >= TARGET_CONS
                                and (fg["max_err_valid"] or 0) <= TARGET_ERR)


def fault_onset(name: str):
    for fl in faults.FAULTS:
        if faults.file_name(fl)[: -len(".csv")] == name:
            return fl.window[0]
    return None


def trust_table(rows, variants, onset=False) -> list[str]:
    """One row per log and variant: the figures without the monitor, with it, and (variants)
    with it and covariance matching. onset: a column with the fault's first time."""
    head = ("| log | run | valid | excited valid | RMSE valid | consistency valid | "
            "max err valid | meets | consistency | mismatch steps | fired steps | t claim [s] | "
            + ("onset [s] | " if onset else "") + "t fire [s] |")
    lines = [head, "|" + "|".join(["---"] * (14 if onset else 13)) + "|"]
    for group, name, figs in rows:
        for label, fg in figs:
            if label not in variants:
                continue
            lines.append(
                f"| {name} | {label} | {pct(fg['valid'])} | {pct(fg['excited_valid'])} | "
                f"{fmt(fg['rmse_valid'])} | {pct(fg['cons_valid'])} | {fmt(fg['max_err_valid'])} | "
                f"{'yes' if meets(fg) else '**no**'} | {pct(fg['consistency'])} | "
                f"{100 * fg['mismatch']:.1f} % | {100 * fg['fired_share']:.1f} % | "
                f"{fmt(fg['t_claim'], '.2f')} | "
                + (f"{fmt(fg.get('onset'), '.2f')} | " if onset else "")
                + f"{fmt(fg['t_fire'], '.2f')} |")
    return lines


def nis_table(runs) -> list[str]:
    """What the innovations of the clean MF logs look like: the NIS's mean over the evaluated
    steps (the model claims 3), its share above the 1-step 99.9 % point, the mean and sd of
    the normalised innovation per channel (claimed 0 and 1), the mean persistent share c, and
    the monitor's largest D and |M| after the warm-up against their fire limits at that step."""
    lines = ["| log | steps | mean NIS | NIS > 16.27 | mean e ax/ay/ṙ | sd e ax/ay/ṙ | "
             "mean c ax/ay/ṙ | max D/D_fire | max abs M/M_fire ax/ay/ṙ | mismatch steps | "
             "fired steps |", "|" + "|".join(["---"] * 11) + "|"]
    for name, r, res in runs:
        ok = np.all(np.isfinite(res["nu"]), axis=1)
        d, e, c = [], [], []
        for k in np.flatnonzero(ok):
            dk, ek, ck = monitor.normalise(res["nu"][k], res["s_zz"][k], res["c_pers"][k])
            d.append(dk)
            e.append(ek)
            c.append(ck)
        d, e, c = np.array(d), np.array(e), np.array(c)
        rd, rm = r["D_ratio"], r["M_ratio"]
        lines.append(f"| {name} | {ok.sum()} | {d.mean():.2f} | {100 * np.mean(d > 16.266):.1f} % | "
                     + "/".join(f"{x:+.2f}" for x in e.mean(0)) + " | "
                     + "/".join(f"{x:.2f}" for x in e.std(0)) + " | "
                     + "/".join(f"{x:.2f}" for x in c.mean(0)) + f" | {np.nanmax(rd):.2f} | "
                     + "/".join(f"{x:.2f}" for x in np.nanmax(rm, 0))
                     + f" | {100 * np.mean(r['status'] == monitor.STATUS_MISMATCH):.1f} % | "
                     f"{100 * np.mean(r['fired']):.1f} % |")
    return lines


def limit_ratios(res, p, dt):
    """Per step, the monitor's D / D_fire and |M_r| / M_fire,r (NaN before the statistics
    start), replayed with monitor.Monitor."""
    mon = monitor.Monitor(p, dt)
    n = len(res["status"])
    rd, rm = np.full(n, np.nan), np.full((n, monitor.M_CHANNELS), np.nan)
    for k in range(n):
        if res["status"][k] != 2 and np.all(np.isfinite(res["nu"][k])):
            mon.step(res["nu"][k], res["s_zz"][k], res["c_pers"][k])
        if mon.C is not None:
            d_f, _, m_f, _ = monitor.limits(mon.C, mon.th)
            rd[k], rm[k] = mon.D / d_f, np.abs(mon.M) / m_f
    return rd, rm


def update_page(page: Path, name: str, lines: list[str]) -> None:
    replace_region(page, f"<!-- monitor-{name}:begin -->", f"<!-- monitor-{name}:end -->",
                   lines, "monitor_results")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", type=Path, default=ROOT / "scenarios")
    ap.add_argument("--cache", type=Path, default=ROOT / "build" / "monitor")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--page", type=Path, help="rewrite the tables of this page (docs/MONITOR.md)")
    a = ap.parse_args(argv)
    sel = log_set(a.scenarios)
    jobs = [(p, v, str(a.cache)) for g, _, p in sel for v in VARIANTS
            if v == "base" or g in CM_GROUPS]
    got = {}
    with ProcessPoolExecutor(max_workers=max(a.jobs, 1)) as ex:
        for i, (path, variant, r) in enumerate(ex.map(run_one, jobs), 1):
            got[(path, variant)] = r
            print(f"[{i}/{len(jobs)}] {Path(path).name} {variant}", flush=True, file=sys.stderr)
    p_mon = dict(monitor.MON_DEFAULTS)
    rows, clean_runs, summary = [], [], {}
    for group, name, path in sel:
        figs = []
        base = got[(str(path), "base")]
        dt = float(base["dt"])
        figs.append(("without", figures(base)))
        mon = monitor.apply(base, p_mon, dt)
        figs.append(("monitor", figures(mon)))
        figs.append(("monitor, white", figures(monitor.apply(base, p_mon, dt, use_c=False))))
        figs.append(("monitor, no warm-up",
                     figures(monitor.apply(base, dict(p_mon, mon_warmup=0.0), dt))))
        figs.append(("monitor, no inflation",
                     figures(monitor.apply(base, dict(p_mon, mon_inflate=0.0), dt))))
        for v in VARIANTS[1:] if group in CM_GROUPS else ():
            rv = got[(str(path), v)]
            figs.append((v.replace("cm_", "monitor + CM "), figures(monitor.apply(rv, p_mon, dt))))
        if group == "fault":
            onset = fault_onset(name)
            figs = [(lab, dict(fg, t_claim=fg["t_claim"], onset=onset)) for lab, fg in figs]
        rows.append((group, name, figs))
        if group == "mf":
            rd, rm = limit_ratios(base, p_mon, dt)
            clean_runs.append((name, dict(mon, D_ratio=rd, M_ratio=rm), base))
        summary.setdefault(group, []).append(figs)
    th = monitor.thresholds(p_mon, 0.01)
    thr = ["| persistent share c̄ (all channels) | Pearson a, b, ν of D | D_fire | D_clear | "
           "M_fire | M_clear |", "|---|---|---|---|---|---|"]
    for c in (0.0, 0.1, 0.3, 0.5, 0.8, 1.0):
        cc = np.full(monitor.M_CHANNELS, c)
        a_, b_, nu_ = monitor.pearson(cc, th)
        d_f, d_c, m_f, m_c = monitor.limits(cc, th)
        thr.append(f"| {c:.1f} | {a_:.3f}, {b_:.4f}, {nu_:.1f} | {d_f:.3f} | {d_c:.3f} | "
                   f"{m_f[0]:.3f} | {m_c[0]:.3f} |")
    thr.append("")
    thr.append(f"λ_d = λ_m = {th.l_d:.5f} (τ 0.5 s), hold {th.hold_steps} steps, warm-up "
               f"{th.warmup_steps} steps.")
    out = {
        "thresholds": thr,
        "clean": nis_table(clean_runs),
        "mf": trust_table([r for r in rows if r[0] == "mf"], ("without", "monitor")),
        "dugoff": trust_table([r for r in rows if r[0] in ("dugoff", "nf")], ("without", "monitor")),
        "wrong": trust_table([r for r in rows if r[0] == "wrong"], ("without", "monitor")),
        "faults": trust_table([r for r in rows if r[0] in ("fault", "bank")], ("without", "monitor"),
                              onset=True),
        "cm": trust_table([r for r in rows], ("monitor + CM always", "monitor + CM fired")),
    }
    tot = {}
    labels = ("without", "monitor", "monitor, white", "monitor, no warm-up", "monitor, no inflation",
              "monitor + CM always", "monitor + CM fired")
    for lab in labels:
        for group in ("mf", "dugoff", "nf", "wrong", "fault", "bank"):
            fl = [dict(f)[lab] for f in summary.get(group, []) if lab in dict(f)]
            tot[(lab, group)] = (sum(meets(f) for f in fl), len(fl),
                                 max((f["mismatch"] for f in fl), default=0.0),
                                 max((f["fired_share"] for f in fl), default=0.0),
                                 sum(f["n_bad"] for f in fl))
    groups = ("mf", "dugoff", "nf", "wrong", "fault", "bank")
    lines = ["| run | logs meeting both targets: MF / Dugoff / noise-free Dugoff / wrong tyre data / "
             "faults / banked | "
             "(wheel, sample) pairs valid with error > 0.25, same order | largest share of steps "
             "in mismatch status on a clean MF log | largest share fired |",
             "|---|---|---|---|---|"]
    for lab in labels:
        cells = " / ".join(f"{tot[(lab, g)][0]}/{tot[(lab, g)][1]}" if tot[(lab, g)][1] else "–"
                           for g in groups)
        bad = " / ".join(str(tot[(lab, g)][4]) if tot[(lab, g)][1] else "–" for g in groups)
        lines.append(f"| {lab} | {cells} | {bad} | {100 * tot[(lab, 'mf')][2]:.1f} % | "
                     f"{100 * tot[(lab, 'mf')][3]:.1f} % |")
    out["summary"] = lines
    for k, v in out.items():
        print(f"\n## {k}\n" + "\n".join(v))
    if a.page:
        for k, v in out.items():
            update_page(a.page, k, v)
        print(f"updated the tables in {a.page}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
