#!/usr/bin/env python3
"""Run the estimator on every bundled scenario and show how well it tracks the true friction.

For each sensor log in scenarios/ (with default sensor noise, and noise-free `*.nf.csv`),
runs build/mu_replay with the SCKF and the CKF (paper configuration), collects the accuracy
the CLI computes (--metrics JSON), prints a table, and draws estimate-vs-truth plots per
wheel (the paper's Fig. 4-6 style, SCKF vs CKF, with the SCKF's +-2 sd band).

    .venv/bin/python scripts/demo.py --replay build/mu_replay --out build/demo
    .venv/bin/python scripts/demo.py ... --readme README.md   # also rewrite the README table

The accuracy numbers come from mu_replay itself (one definition of "settled", RMSE, ...);
this script only adds the mean standard deviation over the same time span (t >= 1 s).
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
from pathlib import Path

WHEELS = ("fl", "fr", "rl", "rr")
ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from plot_estimates import plot, read_csv  # noqa: E402  (one plotting/reading code path)
SETTLE_START_S = 1.0  # same as mu_replay's default settle start
BEGIN, END = "<!-- accuracy:begin -->", "<!-- accuracy:end -->"


def scenario_logs(scen_dir: Path) -> list[Path]:
    """Noisy and noise-free sensor logs, Dugoff truth (skip other truth tyres)."""
    logs = [p for p in sorted(scen_dir.glob("*.csv")) if ".mf" not in p.name]
    return logs


def run_replay(replay: Path, log: Path, out_dir: Path, filt: str, real: str) -> dict:
    stem = log.name[: -len(".csv")]
    est = out_dir / f"{stem}.paper.{filt}.{real}.csv"
    met = out_dir / f"{stem}.paper.{filt}.{real}.json"
    cmd = [str(replay), "--in", str(log), "--out", str(est), "--preset", "paper", "--filter", filt,
           "--tyre", "paper", "--real", real, "--metrics", str(met), "--quiet"]
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


def fmt(x, spec=".3f"):
    return "–" if x is None else format(x, spec)


def table_rows(results: list[tuple[str, str, dict, dict]]) -> list[str]:
    """One row per (scenario, noise): SCKF accuracy, and the float32 deviation of the SCKF
    and the CKF from the float64 reference (the paper's SCKF-vs-CKF precision question)."""
    head = ("| scenario | noise | RMSE fl | RMSE fr | RMSE rl | RMSE rr | max err | max rel | "
            "mean-μ RMSE | t_conv [s] | mean sd | Δref SCKF | Δref CKF |")
    lines = [head, "|" + "|".join(["---"] * 13) + "|"]
    for scen, noise, sckf, ckf in results:
        m = sckf["metrics"]
        rm = [m[w]["rmse"] for w in WHEELS]
        mx = max(m[w]["max_abs_err"] for w in WHEELS)
        mr = max(m[w]["max_rel_err"] for w in WHEELS)
        tc = [m[w]["t_converge_s"] for w in WHEELS]
        tconv = "never" if any(x is None for x in tc) else f"{max(tc):.2f}"
        sd = sum(sckf["mean_sd"].values()) / 4.0
        dev = [fmt(r["golden_dev"], ".1e") for r in (sckf, ckf)]
        lines.append(f"| {scen} | {noise} | " + " | ".join(fmt(x) for x in rm)
                     + f" | {mx:.3f} | {100 * mr:.0f} % | {fmt(m['mean']['rmse'])} | {tconv} | {sd:.3f}"
                     + f" | {dev[0]} | {dev[1]} |")
    return lines


def update_readme(readme: Path, lines: list[str]) -> None:
    text = readme.read_text()
    if BEGIN not in text or END not in text:
        sys.exit(f"demo: {readme} has no {BEGIN} ... {END} section")
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    readme.write_text(head + BEGIN + "\n" + "\n".join(lines) + "\n" + END + tail)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--scenarios", type=Path, default=ROOT / "scenarios")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "demo")
    ap.add_argument("--real", choices=("float", "double"), default="float")
    ap.add_argument("--readme", type=Path, help="rewrite the accuracy table in this README")
    ap.add_argument("--no-plots", action="store_true")
    args = ap.parse_args()

    args.out.mkdir(parents=True, exist_ok=True)
    logs = scenario_logs(args.scenarios)
    if not logs:
        sys.exit(f"demo: no sensor logs in {args.scenarios}")
    results = []
    t0 = time.time()
    for k, log in enumerate(logs, 1):
        stem = log.name[: -len(".csv")]
        scen = stem[: -len(".nf")] if stem.endswith(".nf") else stem
        noise = "none" if stem.endswith(".nf") else "default"
        runs, infos = {}, {}
        for filt in ("sckf", "ckf"):
            info = run_replay(args.replay, log, args.out, filt, args.real)
            info["golden_dev"] = max_dev_from_golden(
                info["estimate_file"], args.scenarios / "golden" / f"{stem}.paper.{filt}.csv")
            infos[filt] = info
            runs[filt] = info["estimate_file"]
        results.append((scen, noise, infos["sckf"], infos["ckf"]))
        if not args.no_plots:
            plot(log, [runs["sckf"], runs["ckf"]], ["SCKF", "CKF"], args.out / f"{stem}.png",
                 f"{scen} ({'noise-free' if noise == 'none' else 'default noise'}), "
                 f"paper configuration, {args.real}")
        print(f"[{k}/{len(logs)}] {stem}: done ({time.time() - t0:.1f} s)", flush=True)

    results.sort(key=lambda r: (r[0], r[1] != "none"))
    lines = table_rows(results)
    print()
    print("\n".join(lines))
    (args.out / "accuracy.md").write_text("\n".join(lines) + "\n")
    print(f"\nestimate logs, metrics and plots: {args.out}/ (accuracy.md, <scenario>.png)")
    if args.readme:
        update_readme(args.readme, lines)
        print(f"updated the accuracy table in {args.readme}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
