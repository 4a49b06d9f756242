#!/usr/bin/env python3
"""Run the estimator on every bundled scenario and show how well it tracks the true friction.

For each sensor log in scenarios/ (with default sensor noise, and noise-free `*.nf.csv`),
runs build/mu_replay with the SCKF and the CKF (paper configuration), collects the accuracy
the CLI computes (--metrics JSON), writes a table, and draws estimate-vs-truth plots per
wheel (plot_estimates.py: default preset, paper SCKF and CKF, the manoeuvre under them);
the Magic Formula truth logs (`*.mf.csv`) are plotted with the default preset.
Each table goes to <out>/<name>.md with its title and column legend and to the console
split to at most 120 characters a line (demo_tables.py); <out>/index.md links every table
and plot of the run (demo_index.py).
The fixed-point estimator (`--real q31`) runs beside it: its deviation from the float64
reference in the accuracy table, from the double run in the trust table, and a table of
|mu_q31 - mu_double| per scenario and configuration (all 39 logs; settled samples as
mu_replay defines them), with the valid-flag agreement and the saturation counts.

    .venv/bin/python scripts/tools/demo.py --replay build/mu_replay --out build/demo
    .venv/bin/python scripts/tools/demo.py ... --trust --results docs/RESULTS.md --readme README.md
                                       # also rewrite the tables of docs/RESULTS.md (accuracy,
                                       # trust, q31) and the README's headline table
    .venv/bin/python scripts/tools/demo.py ... --plot-q31   # plots with the q31 estimate too

`make readme-table` runs the second form. The headline table (markers headline:begin/end in
the README) is a few columns of the trust table: the default preset on the Magic Formula
truth, one row per excited manoeuvre and one for the never-excited logs together.

The accuracy numbers come from mu_replay itself (one definition of "settled", RMSE, ...);
this script only adds the mean standard deviation over the same time span (t >= 1 s) and
the run-to-run deviations (over the same settled samples).
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(Path(__file__).resolve().parent))   # scripts/tools: plot_estimates
from plot_estimates import plot, read_csv  # noqa: E402  (one plotting/reading code path)
from demo_tables import write_table  # noqa: E402
from md_tables import replace_region  # noqa: E402
from wheel_figures import WHEELS, pooled, worst_valid  # noqa: E402  (re-exported)
from demo_index import summary_line, write_index  # noqa: E402
SETTLE_START_S = 1.0  # same as mu_replay's default settle start
SETTLE_AFTER_CHANGE_S = 0.5  # mu_replay's default: settled again 0.5 s after a truth change
CHANGE_MIN = 1e-9  # mu_replay's smallest truth step that counts as a change
BEGIN, END = "<!-- accuracy:begin -->", "<!-- accuracy:end -->"
TRUST_BEGIN, TRUST_END = "<!-- trust:begin -->", "<!-- trust:end -->"
Q31_BEGIN, Q31_END = "<!-- q31:begin -->", "<!-- q31:end -->"
HEADLINE_BEGIN, HEADLINE_END = "<!-- headline:begin -->", "<!-- headline:end -->"
Q31_TOL = 0.005  # the requirement on |mu_q31 - mu_double| at settled samples (issue)

# Scenario classes of the trustworthiness targets (docs/RESULTS.md): excited = the tyres
# work near their limit; steering = cornering; never = friction is not observable (mild
# braking, cruising, the moderate split-mu braking whose high side stays linear); wrong tyre =
# the car's tyre is not its parameter file's (stiffness and shape 30 % off, scenarios.py).
CLASSES = {
    "hard_brake_high_mu": "excited", "hard_brake_low_mu": "excited",
    "mu_step_hard_brake": "excited", "split_mu_hard_brake": "excited",
    "accel_low_mu": "excited",
    "sine_steer_high_mu": "steering", "sine_steer_low_mu": "steering",
    "brake_in_turn": "steering",
    "paper_low_mu_brake": "never", "paper_high_mu_brake": "never", "paper_mu_step": "never",
    "cruise": "never", "split_mu_brake": "never",
    # issue 17's scenarios
    "double_lane_change_high_mu": "steering", "double_lane_change_low_mu": "steering",
    "ramp_steer_high_mu": "steering", "ramp_steer_low_mu": "steering",
    "brake_in_turn_low_mu": "steering",
    "wrong_tyre_data": "wrong tyre",
}


def scenario_logs(scen_dir: Path) -> list[Path]:
    """Noisy and noise-free sensor logs, Dugoff truth (skip other truth tyres)."""
    logs = [p for p in sorted(scen_dir.glob("*.csv")) if ".mf" not in p.name]
    return logs


def mf_logs(scen_dir: Path) -> list[Path]:
    """The Magic Formula truth logs (default noise)."""
    return sorted(scen_dir.glob("*.mf.csv"))


def run_replay(replay: Path, log: Path, out_dir: Path, filt: str, real: str,
               preset: str = "paper", velocity: str = "auto") -> dict:
    stem = log.name[: -len(".csv")] + ("" if velocity == "auto" else f".{velocity}")
    est = out_dir / f"{stem}.{preset}.{filt}.{real}.csv"
    met = out_dir / f"{stem}.{preset}.{filt}.{real}.json"
    cmd = [str(replay), "--in", str(log), "--out", str(est), "--preset", preset, "--filter", filt,
           "--real", real, "--velocity", velocity, "--metrics", str(met), "--quiet"]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"demo: {' '.join(cmd)} failed: {res.stderr.strip()}")
    info = json.loads(met.read_text())
    est_cols = read_csv(est)
    t = est_cols["t"]
    idx = [i for i, ti in enumerate(t) if ti >= t[0] + SETTLE_START_S]
    info["mean_sd"] = {w: sum(est_cols[f"sd_{w}"][i] for i in idx) / max(len(idx), 1) for w in WHEELS}
    info["estimate_file"] = est
    return info


def max_dev_from_golden(est_file: Path, golden: Path) -> float | None:
    """Largest |mu - mu_reference| over all rows and wheels (None without a golden file)."""
    if not golden.is_file():
        return None
    a, b = read_csv(est_file), read_csv(golden)
    return max(abs(x - y) for w in WHEELS for x, y in zip(a[f"mu_{w}"], b[f"mu_{w}"]))


def settled_mask(sensor: dict, w: str) -> list[bool]:
    """mu_replay's settled samples of wheel w (src/host/metrics.c): t >= t0 + 1 s and not
    within 0.5 s after the last change of that wheel's true mu."""
    t, truth = sensor["t"], sensor[f"mu_{w}"]
    t_change, mask = None, []
    for k, tk in enumerate(t):
        if k > 0 and abs(truth[k] - truth[k - 1]) > CHANGE_MIN:
            t_change = tk
        mask.append(not (tk < t[0] + SETTLE_START_S
                         or (t_change is not None and tk < t_change + SETTLE_AFTER_CHANGE_S)))
    return mask


def run_deviation(a_file: Path, b_file: Path, sensor: dict) -> tuple[float, float]:
    """(max |mu_a - mu_b| over settled samples of every wheel, share of (sample, wheel) pairs
    whose valid flags agree) of two estimate logs of the same sensor log."""
    a, b = read_csv(a_file), read_csv(b_file)
    worst, agree, n = 0.0, 0, 0
    for w in WHEELS:
        for ok, x, y in zip(settled_mask(sensor, w), a[f"mu_{w}"], b[f"mu_{w}"]):
            if ok:
                worst = max(worst, abs(x - y))
        agree += sum(va == vb for va, vb in zip(a[f"valid_{w}"], b[f"valid_{w}"]))
        n += len(a[f"valid_{w}"])
    return worst, agree / max(n, 1)


def fmt(x, spec=".3f"):
    return "–" if x is None else format(x, spec)


def table_rows(results: list[tuple[str, str, dict, dict]]) -> list[str]:
    """One row per (scenario, noise): SCKF accuracy, and the float32 deviation of the SCKF
    and the CKF from the float64 reference (the paper's SCKF-vs-CKF precision question), and
    the same for the fixed-point (q31) SCKF and CKF."""
    head = ("| scenario | noise | RMSE fl | RMSE fr | RMSE rl | RMSE rr | max err | max rel | "
            "mean-μ RMSE | t_conv [s] | mean sd | Δref SCKF | Δref CKF | Δref q31 SCKF | "
            "Δref q31 CKF |")
    lines = [head, "|" + "|".join(["---"] * 15) + "|"]
    for scen, noise, sckf, ckf in results:
        m = sckf["metrics"]
        rm = [m[w]["rmse"] for w in WHEELS]
        mx = max(m[w]["max_abs_err"] for w in WHEELS)
        mr = max(m[w]["max_rel_err"] for w in WHEELS)
        tc = [m[w]["t_converge_s"] for w in WHEELS]
        tconv = "never" if any(x is None for x in tc) else f"{max(tc):.2f}"
        sd = sum(sckf["mean_sd"].values()) / 4.0
        dev = [fmt(r[k], ".1e") for k in ("golden_dev", "golden_dev_q31") for r in (sckf, ckf)]
        lines.append(f"| {scen} | {noise} | " + " | ".join(fmt(x) for x in rm)
                     + f" | {mx:.3f} | {100 * mr:.0f} % | {fmt(m['mean']['rmse'])} | {tconv} | {sd:.3f}"
                     + " | " + " | ".join(dev) + " |")
    return lines


def update_page(page: Path, lines: list[str], begin: str = BEGIN, end: str = END) -> None:
    """Replace the text between the markers begin ... end of a markdown page by lines."""
    replace_region(page, begin, end, lines, "demo")


def check_markers(page: Path, pairs: list[tuple[str, str]]) -> None:
    """Exit unless page exists and holds every begin ... end pair (checked before the runs)."""
    if not page.is_file():
        sys.exit(f"demo: {page}: no such file")
    text = page.read_text()
    for begin, end in pairs:
        if begin not in text or end not in text:
            sys.exit(f"demo: {page} has no {begin} ... {end} section")


def trust_rows(runs: list[tuple[str, str, str, dict]]) -> list[str]:
    """The trustworthiness table: one row per (scenario, truth tyre, preset); "worst valid" the
    largest |error| while valid, "consistency valid" the share of the valid samples within
    2 sd; the last column the largest |mu_q31 - mu_double| of that configuration over the
    settled samples."""
    head = ("| scenario | class | truth | preset | RMSE fl/fr/rl/rr | max err fl/fr/rl/rr | "
            "mean-μ RMSE | RMSE valid | worst valid | consistency valid | valid | "
            "excited valid | consistency | re-conv [s] | Δμ q31 |")
    lines = [head, "|" + "|".join(["---"] * 15) + "|"]
    for scen, truth, preset, info in runs:
        m = info["metrics"]
        rm = "/".join(fmt(m[w]["rmse"], ".2f") for w in WHEELS)
        mx = "/".join(fmt(m[w]["max_abs_err"], ".2f") for w in WHEELS)
        n_valid = [m[w]["n_valid"] or 0 for w in WHEELS]
        rv = pooled(m, "rmse_valid", "n_valid", square=True)
        fv = pooled(m, "frac_valid", "n_settled")
        ex = pooled(m, "frac_valid_excited", "n_excited")
        co = pooled(m, "consistency", "n_settled")
        cv = pooled(m, "consistency_valid", "n_valid")
        rc = [m[w]["reconverge_s"] for w in WHEELS if m[w]["n_changes"]]
        rcs = "–" if not rc else ("never" if any(x is None for x in rc) else f"{max(rc):.2f}")
        pct = lambda x: "–" if x is None else f"{100 * x:.0f} %"  # noqa: E731
        lines.append(f"| {scen} | {CLASSES.get(scen, '?')} | {truth} | {preset} | {rm} | {mx} | "
                     f"{fmt(m['mean']['rmse'], '.3f')} | {fmt(rv, '.3f') if sum(n_valid) else '–'} | "
                     f"{fmt(worst_valid(m), '.3f')} | {pct(cv)} | {pct(fv)} | {pct(ex)} | {pct(co)} | {rcs} | "
                     f"{fmt(info.get('q31_dev'), '.1e')} |")
    return lines


HEADLINE_TRUTH, HEADLINE_PRESET = "MF", "default"
TRUTH_NAMES = {"MF": "Magic Formula", "Dugoff": "Dugoff"}


def headline_rows(runs: list[tuple[str, str, str, dict]]) -> list[str]:
    """The README's headline table, from the runs of the trust table (same metrics, same
    pooling over the wheels): the default preset on the Magic Formula truth, one row per
    excited manoeuvre (RMSE where valid, share of the excited samples and of the settled
    samples reported valid, and the worst case when valid: the largest |error| while valid),
    then one row for all never-excited logs together, each column
    the worst of those logs (the highest figure: there every valid sample is a false claim).
    The last two columns: the same log run as a production car's (vx, vy, yaw_acc from the
    velocity observer, info["observer"])."""
    pct = lambda x: "–" if x is None else f"{100 * x:.0f} %"  # noqa: E731
    lines = ["| manoeuvre | truth tyre | RMSE when valid | worst case when valid | "
             "excited samples valid | settled samples valid | RMSE when valid, observer | "
             "settled valid, observer |",
             "|---|---|---|---|---|---|---|---|"]
    sel = [r for r in runs if r[1] == HEADLINE_TRUTH and r[2] == HEADLINE_PRESET]
    never = []
    def valid_figures(m):
        has_valid = sum(m[w]["n_valid"] or 0 for w in WHEELS) > 0
        return (pooled(m, "rmse_valid", "n_valid", square=True) if has_valid else None,
                worst_valid(m), pooled(m, "frac_valid_excited", "n_excited"),
                pooled(m, "frac_valid", "n_settled"))

    for scen, truth, _, info in sel:
        rv, wv, ex, fv = valid_figures(info["metrics"])
        orv, _, _, ofv = valid_figures(info["observer"]["metrics"])
        if CLASSES.get(scen) == "excited":
            lines.append(f"| {scen} | {TRUTH_NAMES.get(truth, truth)} | {fmt(rv)} | {fmt(wv)} | "
                         f"{pct(ex)} | {pct(fv)} | {fmt(orv)} | {pct(ofv)} |")
        elif CLASSES.get(scen) == "never":
            never.append((rv, wv, ex, fv, orv, ofv))
    if never:
        worst = [max((x[k] for x in never if x[k] is not None), default=None) for k in range(6)]
        lines.append(f"| never excited ({len(never)} log{'s' if len(never) > 1 else ''}, worst) | "
                     f"{TRUTH_NAMES.get(HEADLINE_TRUTH, HEADLINE_TRUTH)} | {fmt(worst[0])} | "
                     f"{fmt(worst[1])} | {pct(worst[2])} | {pct(worst[3])} | {fmt(worst[4])} | "
                     f"{pct(worst[5])} |")
    return lines


def trust_runs(replay: Path, scen_dir: Path, out_dir: Path, real: str
               ) -> list[tuple[str, str, str, dict]]:
    """Default preset next to the paper baseline, on every noisy log of both truth tyres:
    (scenario, truth tyre, preset, replay info) in the order of the trust table."""
    runs = []
    logs = sorted(p for p in scen_dir.glob("*.csv") if not p.name.endswith(".nf.csv"))
    for k, log in enumerate(logs, 1):
        stem = log.name[: -len(".csv")]
        truth = "MF" if stem.endswith(".mf") else "Dugoff"
        scen = stem[: -len(".mf")] if stem.endswith(".mf") else stem
        sensor = read_csv(log)
        for preset in ("paper", "default"):
            info = run_replay(replay, log, out_dir, "sckf", real, preset)
            q31 = run_replay(replay, log, out_dir, "sckf", "q31", preset)
            dbl = run_replay(replay, log, out_dir, "sckf", "double", preset)
            info["q31_dev"] = run_deviation(q31["estimate_file"], dbl["estimate_file"], sensor)[0]
            if preset == HEADLINE_PRESET:  # the headline's production-car columns
                info["observer"] = run_replay(replay, log, out_dir, "sckf", real, preset,
                                              "observer")
            runs.append((scen, truth, preset, info))
        print(f"[trust {k}/{len(logs)}] {stem}", flush=True)
    order = {"excited": 0, "steering": 1, "never": 2}
    runs.sort(key=lambda r: (r[1] != "MF", order.get(CLASSES.get(r[0], ""), 3), r[0],
                             r[2] != "default"))
    return runs


Q31_CONFIGS = (("paper", "sckf", "paper SCKF"), ("paper", "ckf", "paper CKF"),
               ("default", "sckf", "default"))
NOISE_ORDER = (("nf", "none"), ("", "default"), ("mf", "MF"))


def q31_table(replay: Path, scen_dir: Path, out_dir: Path) -> list[str]:
    """|mu_q31 - mu_double| over settled samples, per scenario (noise-free / default noise /
    Magic Formula truth) and configuration, with the valid-flag agreement and the estimator's
    saturation count; a closing summary line."""
    rows: dict[str, dict] = {}
    worst = {label: 0.0 for _, _, label in Q31_CONFIGS}
    min_agree, total_sat, n_logs = 1.0, 0, 0
    logs = sorted(scen_dir.glob("*.csv"))
    for k, log in enumerate(logs, 1):
        stem = log.name[: -len(".csv")]
        variant = stem.rsplit(".", 1)[1] if "." in stem else ""
        scen = stem.rsplit(".", 1)[0] if variant else stem
        sensor = read_csv(log)
        row = rows.setdefault(scen, {"agree": 1.0, "sat": 0})
        for preset, filt, label in Q31_CONFIGS:
            q31 = run_replay(replay, log, out_dir, filt, "q31", preset)
            dbl = run_replay(replay, log, out_dir, filt, "double", preset)
            dev, agree = run_deviation(q31["estimate_file"], dbl["estimate_file"], sensor)
            sat = q31["saturation"]["estimator_total"] + q31["saturation"]["input_values"]
            row[(label, variant)] = dev
            row["agree"] = min(row["agree"], agree)
            row["sat"] += sat
            worst[label] = max(worst[label], dev)
            min_agree = min(min_agree, agree)
            total_sat += sat
        n_logs += 1
        print(f"[q31 {k}/{len(logs)}] {stem}", flush=True)
    head = ("| scenario | " + " | ".join(f"{label} none/default/MF" for _, _, label in Q31_CONFIGS)
            + " | valid agree | saturations |")
    lines = [head, "|" + "|".join(["---"] * (len(Q31_CONFIGS) + 3)) + "|"]
    for scen in sorted(rows):
        row = rows[scen]
        cells = ["/".join(fmt(row.get((label, v)), ".1e") for v, _ in NOISE_ORDER)
                 for _, _, label in Q31_CONFIGS]
        lines.append(f"| {scen} | " + " | ".join(cells)
                     + f" | {100 * row['agree']:.1f} % | {row['sat']} |")
    lines.append("")
    lines.append(f"Largest |μ_q31 − μ_double| over the settled samples of all {n_logs} logs: "
                 + ", ".join(f"{label} {worst[label]:.1e}" for _, _, label in Q31_CONFIGS)
                 + f" (required: ≤ {Q31_TOL}); valid flags agree on ≥ {100 * min_agree:.1f} % of "
                 f"the samples of every log; {total_sat} saturations.")
    return lines


def plot_mf_logs(args) -> list[tuple[str, Path]]:
    """The Magic Formula truth logs (the realistic case: a tyre whose stiffness does not
    scale with mu) with the default preset, the configuration made for them; (title, PNG)."""
    plots = []
    for log in mf_logs(args.scenarios):
        stem = log.name[: -len(".csv")]
        files = [run_replay(args.replay, log, args.out, "sckf", args.real, "default")
                 ["estimate_file"]]
        labels = ["default"]
        if args.plot_q31:
            files.append(run_replay(args.replay, log, args.out, "sckf", "q31", "default")
                         ["estimate_file"])
            labels.append("default q31")
        title = f"{stem[: -len('.mf')]}: Magic Formula truth, default noise, {args.real}"
        plot(log, files, labels, args.out / f"{stem}.png", title)
        plots.append((title, args.out / f"{stem}.png"))
        print(f"[MF] {stem}: plotted", flush=True)
    return plots


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--scenarios", type=Path, default=ROOT / "scenarios")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "demo")
    ap.add_argument("--real", choices=("float", "double"), default="float")
    ap.add_argument("--results", "--page", type=Path, metavar="PAGE",
                    help="rewrite the accuracy, trust (with --trust) and fixed-point tables "
                    "between their markers in this page (docs/RESULTS.md)")
    ap.add_argument("--readme", type=Path,
                    help="rewrite the headline table (markers headline:begin/end) in this "
                    "README; needs --trust")
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--trust", action="store_true",
                    help="also the default-vs-paper trustworthiness table (both truth tyres)")
    ap.add_argument("--plot-q31", action="store_true",
                    help="add the fixed-point (q31) default-preset estimate to the plots")
    args = ap.parse_args(argv)
    if args.readme and not args.trust:
        ap.error("--readme (the headline table) needs --trust")
    # fail before minutes of replays, not after
    if args.results:
        check_markers(args.results, [(BEGIN, END), (Q31_BEGIN, Q31_END)]
                      + ([(TRUST_BEGIN, TRUST_END)] if args.trust else []))
    if args.readme:
        check_markers(args.readme, [(HEADLINE_BEGIN, HEADLINE_END)])

    args.out.mkdir(parents=True, exist_ok=True)
    logs = scenario_logs(args.scenarios)
    if not logs:
        sys.exit(f"demo: no sensor logs in {args.scenarios}")
    results, plots, tables = [], [], []
    t0 = time.time()
    for k, log in enumerate(logs, 1):
        stem = log.name[: -len(".csv")]
        scen = stem[: -len(".nf")] if stem.endswith(".nf") else stem
        noise = "none" if stem.endswith(".nf") else "default"
        runs, infos = {}, {}
        for filt in ("sckf", "ckf"):
            golden = args.scenarios / "golden" / f"{stem}.paper.{filt}.csv"
            info = run_replay(args.replay, log, args.out, filt, args.real)
            info["golden_dev"] = max_dev_from_golden(info["estimate_file"], golden)
            q31 = run_replay(args.replay, log, args.out, filt, "q31")
            info["golden_dev_q31"] = max_dev_from_golden(q31["estimate_file"], golden)
            infos[filt] = info
            runs[filt] = info["estimate_file"]
        results.append((scen, noise, infos["sckf"], infos["ckf"]))
        if not args.no_plots:
            default = run_replay(args.replay, log, args.out, "sckf", args.real, "default")
            files = [default["estimate_file"], runs["sckf"], runs["ckf"]]
            labels = ["default", "paper SCKF", "paper CKF"]
            if args.plot_q31:
                files.append(run_replay(args.replay, log, args.out, "sckf", "q31",
                                        "default")["estimate_file"])
                labels.append("default q31")
            title = (f"{scen}: Dugoff truth, "
                     f"{'noise-free' if noise == 'none' else 'default noise'}, {args.real}")
            plot(log, files, labels, args.out / f"{stem}.png", title)
            plots.append((title, args.out / f"{stem}.png"))
        print(f"[{k}/{len(logs)}] {stem}: done ({time.time() - t0:.1f} s)", flush=True)
    if not args.no_plots:
        plots += plot_mf_logs(args)

    results.sort(key=lambda r: (r[0], r[1] != "none"))
    lines = table_rows(results)
    write_table(args.out, "accuracy", lines, tables)
    if args.trust:
        truns = trust_runs(args.replay, args.scenarios, args.out, args.real)
        tl, hl = trust_rows(truns), headline_rows(truns)
        write_table(args.out, "trust", tl, tables)
        write_table(args.out, "headline", hl, tables)
    ql = q31_table(args.replay, args.scenarios, args.out)
    write_table(args.out, "q31", ql, tables)
    print()
    if args.results:
        update_page(args.results, lines)
        if args.trust:
            update_page(args.results, tl, TRUST_BEGIN, TRUST_END)
        update_page(args.results, ql, Q31_BEGIN, Q31_END)
        print(f"updated the tables in {args.results}")
    if args.readme:
        update_page(args.readme, hl, HEADLINE_BEGIN, HEADLINE_END)
        print(f"updated the headline table in {args.readme}")
    index = write_index(args.out, tables, plots)
    print(summary_line(args.out, index, len(plots), len(tables)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
