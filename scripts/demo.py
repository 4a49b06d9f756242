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
TRUST_BEGIN, TRUST_END = "<!-- trust:begin -->", "<!-- trust:end -->"

# Scenario classes of the trustworthiness targets (README): excited = the tyres work near
# their limit; steering = cornering; never = friction is not observable (mild braking,
# cruising, the moderate split-mu braking whose high side stays linear).
CLASSES = {
    "hard_brake_high_mu": "excited", "hard_brake_low_mu": "excited",
    "mu_step_hard_brake": "excited", "split_mu_hard_brake": "excited",
    "accel_low_mu": "excited",
    "sine_steer_high_mu": "steering", "sine_steer_low_mu": "steering",
    "brake_in_turn": "steering",
    "paper_low_mu_brake": "never", "paper_high_mu_brake": "never", "paper_mu_step": "never",
    "cruise": "never", "split_mu_brake": "never",
}


def scenario_logs(scen_dir: Path) -> list[Path]:
    """Noisy and noise-free sensor logs, Dugoff truth (skip other truth tyres)."""
    logs = [p for p in sorted(scen_dir.glob("*.csv")) if ".mf" not in p.name]
    return logs


def run_replay(replay: Path, log: Path, out_dir: Path, filt: str, real: str,
               preset: str = "paper") -> dict:
    stem = log.name[: -len(".csv")]
    est = out_dir / f"{stem}.{preset}.{filt}.{real}.csv"
    met = out_dir / f"{stem}.{preset}.{filt}.{real}.json"
    cmd = [str(replay), "--in", str(log), "--out", str(est), "--preset", preset, "--filter", filt,
           "--real", real, "--metrics", str(met), "--quiet"]
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


def update_readme(readme: Path, lines: list[str], begin: str = BEGIN, end: str = END) -> None:
    text = readme.read_text()
    if begin not in text or end not in text:
        sys.exit(f"demo: {readme} has no {begin} ... {end} section")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    readme.write_text(head + begin + "\n" + "\n".join(lines) + "\n" + end + tail)


def pooled(m: dict, key: str, weight: str, square: bool = False):
    """A per-wheel figure pooled over the four wheels, weighted by each wheel's sample count
    (RMS figures pooled as RMS). None when no wheel has samples."""
    num = den = 0.0
    for w in WHEELS:
        x, n = m[w].get(key), m[w].get(weight) or 0
        if x is None or n == 0:
            continue
        num += n * (x * x if square else x)
        den += n
    if den == 0:
        return None
    return (num / den) ** 0.5 if square else num / den


def trust_rows(runs: list[tuple[str, str, str, dict]]) -> list[str]:
    """The trustworthiness table: one row per (scenario, truth tyre, preset)."""
    head = ("| scenario | class | truth | preset | RMSE fl/fr/rl/rr | max err fl/fr/rl/rr | "
            "mean-μ RMSE | RMSE valid | valid | excited valid | consistency | re-conv [s] |")
    lines = [head, "|" + "|".join(["---"] * 12) + "|"]
    for scen, truth, preset, info in runs:
        m = info["metrics"]
        rm = "/".join(fmt(m[w]["rmse"], ".2f") for w in WHEELS)
        mx = "/".join(fmt(m[w]["max_abs_err"], ".2f") for w in WHEELS)
        n_valid = [m[w]["n_valid"] or 0 for w in WHEELS]
        rv = pooled(m, "rmse_valid", "n_valid", square=True)
        fv = pooled(m, "frac_valid", "n_settled")
        ex = pooled(m, "frac_valid_excited", "n_excited")
        co = pooled(m, "consistency", "n_settled")
        rc = [m[w]["reconverge_s"] for w in WHEELS if m[w]["n_changes"]]
        rcs = "–" if not rc else ("never" if any(x is None for x in rc) else f"{max(rc):.2f}")
        pct = lambda x: "–" if x is None else f"{100 * x:.0f} %"  # noqa: E731
        lines.append(f"| {scen} | {CLASSES.get(scen, '?')} | {truth} | {preset} | {rm} | {mx} | "
                     f"{fmt(m['mean']['rmse'], '.3f')} | {fmt(rv, '.3f') if sum(n_valid) else '–'} | "
                     f"{pct(fv)} | {pct(ex)} | {pct(co)} | {rcs} |")
    return lines


def trust_table(replay: Path, scen_dir: Path, out_dir: Path, real: str) -> list[str]:
    """Default preset next to the paper baseline, on every noisy log of both truth tyres."""
    runs = []
    logs = sorted(p for p in scen_dir.glob("*.csv") if not p.name.endswith(".nf.csv"))
    for k, log in enumerate(logs, 1):
        stem = log.name[: -len(".csv")]
        truth = "MF" if stem.endswith(".mf") else "Dugoff"
        scen = stem[: -len(".mf")] if stem.endswith(".mf") else stem
        for preset in ("paper", "default"):
            runs.append((scen, truth, preset, run_replay(replay, log, out_dir, "sckf", real, preset)))
        print(f"[trust {k}/{len(logs)}] {stem}", flush=True)
    order = {"excited": 0, "steering": 1, "never": 2}
    runs.sort(key=lambda r: (r[1] != "MF", order.get(CLASSES.get(r[0], ""), 3), r[0],
                             r[2] != "default"))
    return trust_rows(runs)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--scenarios", type=Path, default=ROOT / "scenarios")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "demo")
    ap.add_argument("--real", choices=("float", "double"), default="float")
    ap.add_argument("--readme", type=Path, help="rewrite the accuracy table in this README")
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--trust", action="store_true",
                    help="also the default-vs-paper trustworthiness table (both truth tyres)")
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
            default = run_replay(args.replay, log, args.out, "sckf", args.real, "default")
            plot(log, [default["estimate_file"], runs["sckf"], runs["ckf"]],
                 ["default", "paper SCKF", "paper CKF"], args.out / f"{stem}.png",
                 f"{scen} ({'noise-free' if noise == 'none' else 'default noise'}), {args.real}")
        print(f"[{k}/{len(logs)}] {stem}: done ({time.time() - t0:.1f} s)", flush=True)

    results.sort(key=lambda r: (r[0], r[1] != "none"))
    lines = table_rows(results)
    print()
    print("\n".join(lines))
    (args.out / "accuracy.md").write_text("\n".join(lines) + "\n")
    print(f"\nestimate logs, metrics and plots: {args.out}/ (accuracy.md, <scenario>.png)")
    if args.trust:
        tl = trust_table(args.replay, args.scenarios, args.out, args.real)
        print("\n".join(tl))
        (args.out / "trust.md").write_text("\n".join(tl) + "\n")
    if args.readme:
        update_readme(args.readme, lines)
        if args.trust:
            update_readme(args.readme, tl, TRUST_BEGIN, TRUST_END)
        print(f"updated the tables in {args.readme}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
