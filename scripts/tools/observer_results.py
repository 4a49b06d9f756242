"""Measure the velocity observer through the C library (build/mu_replay --velocity observer)
and write the tables of docs/OBSERVER_RESULTS.md (issue 16's figures).

    .venv/bin/python scripts/tools/observer_results.py [--replay build/mu_replay] \
        [--page docs/OBSERVER_RESULTS.md] [--out build/observer] [--real float|double]

1. Observer accuracy on the observer scenarios (scenarios/observer/*.csv, noisy, both truth
   tyres): vx and beta RMSE and maximum error against the truth columns vx_true, beta_true
   (beta where vx_true >= 3 m/s: below, the sideslip of a creeping car is not defined).
2. The friction estimator's trust on observer inputs next to measured velocities: every
   noisy bundled log (scenarios/*.csv), default preset, pooled over the wheels as the
   trust table of docs/RESULTS.md does: RMSE where valid, valid share, consistency.
Every figure is printed as it is measured (progress on stderr) and written between the
page's markers; nothing is typed by hand.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from demo import WHEELS, fmt, pooled, read_csv, update_page  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
ACC = ("<!-- observer-accuracy:begin -->", "<!-- observer-accuracy:end -->")
TRUST = ("<!-- observer-trust:begin -->", "<!-- observer-trust:end -->")
BETA_MIN_VX = 3.0  # m/s, as obs_v_lat_min


def replay(binary: Path, log: Path, out: Path, velocity: str, real: str) -> dict:
    est = out / f"{log.stem}.{velocity}.{real}.csv"
    met = out / f"{log.stem}.{velocity}.{real}.json"
    cmd = [str(binary), "--in", str(log), "--out", str(est), "--preset", "default",
           "--real", real, "--velocity", velocity, "--metrics", str(met), "--quiet"]
    res = subprocess.run(cmd, capture_output=True, text=True)
    if res.returncode != 0:
        sys.exit(f"observer_results: {' '.join(cmd)} failed: {res.stderr.strip()}")
    return {"metrics": json.loads(met.read_text())["metrics"], "estimate": est}


def rms(x):
    return math.sqrt(sum(v * v for v in x) / len(x)) if x else float("nan")


def accuracy_rows(binary: Path, out: Path, real: str) -> list[str]:
    lines = ["| scenario | truth tyre | vx RMSE [m/s] | vx max [m/s] | β RMSE [°] | β max [°] | "
             "max \\|β\\| [°] |", "|---|---|---|---|---|---|---|"]
    logs = sorted(p for p in (ROOT / "scenarios" / "observer").glob("*.csv")
                  if not p.name.endswith(".nf.csv"))
    for k, log in enumerate(logs, 1):
        info = replay(binary, log, out, "observer", real)
        est, tru = read_csv(info["estimate"]), read_csv(log)
        ex = [a - b for a, b in zip(est["vx_est"], tru["vx_true"])]
        eb = [math.degrees(a - b) for a, b, v in zip(est["beta_est"], tru["beta_true"],
                                                     tru["vx_true"]) if v >= BETA_MIN_VX]
        bmax = max(abs(math.degrees(b)) for b in tru["beta_true"])
        truth = "Magic Formula" if ".mf" in log.name else "Dugoff"
        name = log.name.replace(".mf.csv", "").replace(".csv", "")
        lines.append(f"| {name} | {truth} | {rms(ex):.3f} | {max(map(abs, ex)):.3f} | "
                     f"{fmt(rms(eb), '.2f') if eb else '–'} | "
                     f"{fmt(max(map(abs, eb)), '.2f') if eb else '–'} | {bmax:.1f} |")
        print(f"[accuracy {k}/{len(logs)}] {log.name}", file=sys.stderr, flush=True)
    return lines


def trust_rows(binary: Path, out: Path, real: str) -> list[str]:
    pct = lambda x: "–" if x is None else f"{100 * x:.0f} %"  # noqa: E731
    lines = ["| scenario | truth tyre | RMSE valid, measured | RMSE valid, observer | "
             "valid, measured | valid, observer | consistency, measured | "
             "consistency, observer |", "|---|---|---|---|---|---|---|---|"]
    logs = sorted(p for p in (ROOT / "scenarios").glob("*.csv") if not p.name.endswith(".nf.csv"))
    for k, log in enumerate(logs, 1):
        row = []
        for velocity in ("measured", "observer"):
            m = replay(binary, log, out, velocity, real)["metrics"]
            has_valid = sum(m[w]["n_valid"] or 0 for w in WHEELS) > 0
            row.append((pooled(m, "rmse_valid", "n_valid", square=True) if has_valid else None,
                        pooled(m, "frac_valid", "n_settled"),
                        pooled(m, "consistency", "n_settled")))
        truth = "Magic Formula" if ".mf" in log.name else "Dugoff"
        name = log.name.replace(".mf.csv", "").replace(".csv", "")
        (rm, vm, cm), (ro, vo, co) = row
        lines.append(f"| {name} | {truth} | {fmt(rm)} | {fmt(ro)} | {pct(vm)} | {pct(vo)} | "
                     f"{pct(cm)} | {pct(co)} |")
        print(f"[trust {k}/{len(logs)}] {log.name}", file=sys.stderr, flush=True)
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--page", type=Path, default=ROOT / "docs" / "OBSERVER_RESULTS.md")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "observer")
    ap.add_argument("--real", choices=("float", "double"), default="float")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    acc = accuracy_rows(a.replay, a.out, a.real)
    trust = trust_rows(a.replay, a.out, a.real)
    print("\n".join(acc + [""] + trust))
    update_page(a.page, acc, *ACC)
    update_page(a.page, trust, *TRUST)
    return 0


if __name__ == "__main__":
    sys.exit(main())
