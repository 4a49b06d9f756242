"""The lateral model's rate (obs_lat_every, docs/OBSERVER.md §4.2): the observer's accuracy
and the friction estimator's trust on observer inputs at each rate, through the C library
(build/mu_replay --velocity observer --params with obs_lat_every = N).

    .venv/bin/python scripts/tools/observer_rate_study.py [--replay build/mu_replay] \
        [--every 1 2 4 8] [--out build/observer_rate] [--real float|double]

Prints, per rate: the accuracy of every observer scenario (scenarios/observer/*.csv: vx RMSE
and max, beta RMSE and max, beta RMSE below 0.5 mu g and at the limit, as
observer_results.py measures them), then the friction estimator's trust on observer inputs on
every noisy bundled log (RMSE when valid, valid share, consistency, pooled over the wheels),
next to measured velocities. The figures of docs/OBSERVER_RESULTS.md "The lateral model's
rate" come from this output; nothing there is typed by hand.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from demo import fmt  # noqa: E402
from observer_results import (ROOT, err_cells, errors, pct, regime_cells,  # noqa: E402
                              replay, trust_cells)


def params_file(out: Path, every: int) -> Path:
    par = out / f"lat_every_{every}.par"
    par.write_text(f"# the lateral model's rows every {every}-th step\nobs_lat_every = {every}\n")
    return par


def name_of(log: Path) -> str:
    return log.name.replace(".mf.csv", " (MF)").replace(".csv", "")


def accuracy(binary: Path, out: Path, real: str, rates: list[int]) -> list[str]:
    lines = ["| scenario | lat_every | vx RMSE [m/s] | vx max [m/s] | β RMSE [°] | β max [°] | "
             "β RMSE, \\|ay\\| < 0.5 μg [°] | β RMSE, at the limit [°] |",
             "|---|---|---|---|---|---|---|---|"]
    logs = sorted(p for p in (ROOT / "scenarios" / "observer").glob("*.csv")
                  if not p.name.endswith(".nf.csv"))
    for k, log in enumerate(logs, 1):
        for n in rates:
            info = replay(binary, log, out, "observer", real, params_file(out, n))
            ex, eb, _ = errors(info["estimate"], log)
            lines.append(f"| {name_of(log)} | {n} | {err_cells(ex, eb)} | "
                         f"{regime_cells(info['estimate'], log)} |")
        print(f"[accuracy {k}/{len(logs)}] {log.name}", file=sys.stderr, flush=True)
    return lines


def trust(binary: Path, out: Path, real: str, rates: list[int]) -> list[str]:
    head = " | ".join(f"N = {n}" for n in rates)
    lines = [f"| scenario | RMSE valid: measured, {head} | valid: measured, {head} | "
             f"consistency: measured, {head} |", "|---|---|---|---|"]
    logs = sorted(p for p in (ROOT / "scenarios").glob("*.csv") if not p.name.endswith(".nf.csv"))
    for k, log in enumerate(logs, 1):
        cells = [trust_cells(replay(binary, log, out, "measured", real)["metrics"])]
        cells += [trust_cells(replay(binary, log, out, "observer", real,
                                     params_file(out, n))["metrics"]) for n in rates]
        lines.append(f"| {name_of(log)} | " + " / ".join(fmt(c[0]) for c in cells) + " | "
                     + " / ".join(pct(c[1]) for c in cells) + " | "
                     + " / ".join(pct(c[2]) for c in cells) + " |")
        print(f"[trust {k}/{len(logs)}] {log.name}", file=sys.stderr, flush=True)
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "observer_rate")
    ap.add_argument("--real", choices=("float", "double"), default="float")
    ap.add_argument("--every", type=int, nargs="+", default=[1, 2, 4, 8])
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    acc = accuracy(a.replay, a.out, a.real, a.every)
    print("\n".join(acc), flush=True)
    tr = trust(a.replay, a.out, a.real, a.every)
    print("\n".join([""] + tr))
    return 0


if __name__ == "__main__":
    sys.exit(main())
