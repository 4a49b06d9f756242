"""Honest on an unobserved friction (issues 16, 17): the reference observer's study options
(scripts/reference/observer.py STUDY_DEFAULTS) measured on the loop's mu step and on every
observer log of docs/OBSERVER_RESULTS.md's accuracy table.

    .venv/bin/python scripts/tools/observer_honest_study.py [--replay build/mu_replay] \
        [--out build/observer_honest] [--jobs 2]

Per log: `mu_replay --velocity observer --real double` runs the C pipeline (the loop: the
observer takes the friction estimator's estimate and sd of the step before); the float64
reference observer is then run on the same samples with that friction input, one step late as
the pipeline feeds it, once per option set. With the options off it must equal the C
observer (the table's first column says how closely it does: the friction input is the C's
printed digits, repr of a double, so it is the same input). The options are measured OPEN LOOP:
the friction trace is the default loop's, a changed sd(vy) would also change the friction
estimator's input noise, which this study does not re-run.

Figures per log and option set: vx RMSE, beta RMSE and max (beta where vx_true >= 3 m/s, as
observer_results.py), and the share of those samples where |beta error| > 2 sd(beta) (a
consistent estimate: about 5 %). On turn_mu_step also the figures on the mu 0.5 phase.
"""

from __future__ import annotations

import argparse
import math
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
from reference import logs, observer, params  # noqa: E402

WHEELS = ("fl", "fr", "rl", "rr")
BETA_MIN_VX = 3.0          # m/s, as observer_results.py (obs_v_lat_min)
LOW_MU = 0.7               # turn_mu_step's mu 0.5 phase: truth friction below this
OFF = {"obs_vy_out_floor_mu": 0.0}  # the output floor off (4 by default since 2026-12-07)
OPTIONS = {                # option sets: name -> the study keys set
    "off": OFF,
    "stiff 1": {**OFF, "obs_stiff_mu": 1.0},
    "floor 2": {**OFF, "obs_vy_floor_mu": 2.0},
    "floor 4": {**OFF, "obs_vy_floor_mu": 4.0},
    "out floor 2": {"obs_vy_out_floor_mu": 2.0},
    "out floor 4": {"obs_vy_out_floor_mu": 4.0},
}


def c_run(binary: Path, log: Path, out: Path) -> dict:
    est = out / f"{log.parent.name}.{log.stem}.csv"
    cmd = [str(binary), "--in", str(log), "--out", str(est), "--preset", "default",
           "--real", "double", "--velocity", "observer", "--quiet"]
    subprocess.run(cmd, check=True, capture_output=True)
    return logs.read_csv_log(str(est), required=("t",)).columns


def figures(o, tru, sel=None):
    """vx RMSE, beta RMSE [deg], beta max [deg], share |beta err| > 2 sd(beta), median sd(beta)
    [deg]."""
    ok = tru["vx_true"] >= BETA_MIN_VX
    if sel is not None:
        ok = ok & sel
    ex = o["vx"] - tru["vx_true"]
    eb = (o["beta"] - tru["beta_true"])[ok]
    out = (o["sd_beta"])[ok]
    if sel is not None:
        ex = ex[sel]
    return (math.sqrt(float(np.mean(ex ** 2))), math.degrees(math.sqrt(float(np.mean(eb ** 2)))),
            math.degrees(float(np.max(np.abs(eb)))), float(np.mean(np.abs(eb) > 2.0 * out)),
            math.degrees(float(np.median(out))))


def one(args):
    binary, log, out = args
    lg = logs.read_csv_log(str(log))
    c = lg.columns
    est = c_run(binary, log, out)
    n = len(c["t"])
    # the pipeline's friction input at step k: the estimator's output of step k - 1
    mu = [np.concatenate(([est["mu_" + w][0]], est["mu_" + w][:-1])) for w in WHEELS]
    sd = [np.concatenate(([est["sd_" + w][0]], est["sd_" + w][:-1])) for w in WHEELS]
    base = observer.params_with_defaults(params.from_metadata(lg.meta))
    rows = {}
    low = None
    if all("mu_" + w in c for w in WHEELS) and "observer_loop" in str(log):
        low = np.mean([c["mu_" + w] for w in WHEELS], axis=0) < LOW_MU
    dev = None
    for name, over in OPTIONS.items():
        o = observer.run(c, {**base, **over}, (mu, sd))
        if name == "off":
            dev = float(np.max(np.abs(o["vy"] - est["vy_est"])))
        rows[name] = (figures(o, c), figures(o, c, low) if low is not None else None)
    assert n == len(est["t"])
    return log, dev, rows


def cell(f) -> str:
    return f"{f[0]:.3f} / {f[1]:.2f} / {f[2]:.2f} / {100 * f[3]:.0f} % / {f[4]:.2f}"


def name_of(log: Path) -> str:
    return log.name.replace(".mf.csv", " (MF)").replace(".csv", "")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "observer_honest")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    loop = sorted(p for p in (ROOT / "scenarios" / "observer_loop").glob("*.csv")
                  if not p.name.endswith(".nf.csv"))
    obs = sorted(p for p in (ROOT / "scenarios" / "observer").glob("*.csv")
                 if not p.name.endswith(".nf.csv"))
    heads = list(OPTIONS)
    lines = ["| scenario | ref − C max \\|Δvy\\| [m/s] | " + " | ".join(heads) + " |",
             "|---|---|" + "---|" * len(heads)]
    low_lines = list(lines)
    with ProcessPoolExecutor(a.jobs) as ex:
        for log, dev, rows in ex.map(one, [(a.replay, p, a.out) for p in loop + obs]):
            lines.append(f"| {name_of(log)} | {dev:.1e} | "
                         + " | ".join(cell(rows[h][0]) for h in heads) + " |")
            if rows["off"][1] is not None:
                low_lines.append(f"| {name_of(log)}, μ 0.5 phase | {dev:.1e} | "
                                 + " | ".join(cell(rows[h][1]) for h in heads) + " |")
            print(lines[-1], file=sys.stderr, flush=True)
    print("cells: vx RMSE [m/s] / β RMSE [°] / β max [°] / share |β err| > 2 sd(β) / "
          "median sd(β) [°]")
    print("\n".join(low_lines))
    print()
    print("\n".join(lines))
    return 0


if __name__ == "__main__":
    sys.exit(main())
