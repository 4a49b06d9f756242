"""Why the friction estimator on observer inputs misses issue 16's rule on the high-mu ramp
steer (docs/OBSERVER_RESULTS.md "The high-μ ramp steer on observer inputs"): per time
window, the observer's vx, vy and yaw-acceleration errors against the noise-free twin next to
each run's friction, and which observer output, swapped alone into the measured-velocity path,
makes the miss ("Feeding the friction estimator a larger sd", table 3's method).

    .venv/bin/python scripts/tools/observer_ramp_study.py [--replay build/mu_replay] \
        [--out build/observer_ramp] [--window 1.0] [--log ramp_steer_high_mu ...] \
        [--params FILE]

Every run is `mu_replay --preset default --real float` as observer_results.py runs the trust
table (the observer run with the reported sd(vy)'s floor off, so the estimate log's sd_vx,
sd_vy are what the friction estimator was fed; no friction output changes, OBSERVER.md §6).
The truth is each log's noise-free twin (observer_feed_study.truth_logs: scenarios/NAME.nf.csv,
or the simulator's Magic Formula twin, checked against the bundled noisy log byte for byte).
--params passes a parameter file to the observer runs only (a candidate setting).

Tables (markdown on stdout), per log:
1. Per window: the friction estimate's samples valid (settled, the four wheels) and their
   RMSE with measured velocities and on observer inputs; the observer's vx, vy, yaw_acc error
   mean / RMS against the truth and the sds it fed (sd_vx, sd_vy); the measured columns' own
   error RMS (the noise the measured run lives with); the largest tyre utilisation.
2. The measured-velocity path with the observer's vx, vy or yaw_acc swapped in alone, all
   three, and all three but one (the rest of the run unchanged, constant sd_in_vx, sd_in_vy),
   per window (valid n / RMSE) and for the whole log (RMSE when valid / valid / consistency).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from demo import WHEELS, fmt, read_csv, settled_mask  # noqa: E402
from observer_feed_study import ROOT, replay, swap_log, trust_text, truth_logs  # noqa: E402

SRC = {"vx": "vx_est", "vy": "vy_est", "yaw_acc": "yaw_acc_est"}
SWAPS = (("observer vx", ("vx",)), ("observer vy", ("vy",)), ("observer ṙ", ("yaw_acc",)),
         ("observer vx, vy, ṙ", ("vx", "vy", "yaw_acc")), ("all but vx", ("vy", "yaw_acc")),
         ("all but vy", ("vx", "yaw_acc")), ("all but ṙ", ("vx", "vy")))


def windows(t: list[float], width: float) -> list[tuple[float, float]]:
    """[a, b) windows of @p width from 0 covering @p t (the last one closed)."""
    edges, a = [], 0.0
    while a < t[-1]:
        edges.append((a, a + width))
        a += width
    return edges


def in_window(t: float, a: float, b: float, last: float) -> bool:
    return a <= t < b or (b >= last and t == last)


def stats(x: list[float]) -> tuple[float | None, float | None]:
    """(mean, RMS) or (None, None) when empty."""
    if not x:
        return None, None
    return sum(x) / len(x), math.sqrt(sum(v * v for v in x) / len(x))


def friction_window(sensor: dict, est: dict, a: float, b: float) -> tuple[int, float | None]:
    """Settled samples valid in [a, b), pooled over the wheels, and their μ RMSE."""
    last, err = sensor["t"][-1], []
    for w in WHEELS:
        for k, ok in enumerate(settled_mask(sensor, w)):
            if ok and est[f"valid_{w}"][k] and in_window(sensor["t"][k], a, b, last):
                err.append(est[f"mu_{w}"][k] - sensor[f"mu_{w}"][k])
    return len(err), stats(err)[1]


def fw(cell: tuple[int, float | None]) -> str:
    return f"{cell[0]} / {fmt(cell[1])}"


def ms(x: list[float], spec: str = "+.3f") -> str:
    m, r = stats(x)
    return "–" if m is None else f"{format(m, spec)} / {r:.3f}"


def window_table(sensor: dict, tru: dict, meas: dict, obs: dict, width: float) -> list[str]:
    t, last = sensor["t"], sensor["t"][-1]
    lines = ["| t [s] | friction valid n / RMSE, measured | on observer inputs | "
             "vx error mean / RMS [m/s] | sd_vx | vy error mean / RMS [m/s] | sd_vy | "
             "ṙ error mean / RMS [rad/s²] | measured vx / vy / ṙ error RMS | max utilisation |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for a, b in windows(t, width):
        ks = [k for k, tk in enumerate(t) if in_window(tk, a, b, last)]
        err = {c: [obs[SRC[c]][k] - tru[c][k] for k in ks] for c in SRC}
        noise = [stats([sensor[c][k] - tru[c][k] for k in ks])[1] for c in SRC]
        util = max(tru[f"util_{w}"][k] for w in WHEELS for k in ks)
        lines.append(
            f"| {a:.1f}–{b:.1f} | {fw(friction_window(sensor, meas, a, b))} | "
            f"{fw(friction_window(sensor, obs, a, b))} | {ms(err['vx'])} | "
            f"{stats([obs['sd_vx'][k] for k in ks])[0]:.3f} | {ms(err['vy'])} | "
            f"{stats([obs['sd_vy'][k] for k in ks])[0]:.3f} | {ms(err['yaw_acc'])} | "
            + " / ".join(f"{v:.3f}" for v in noise) + f" | {util:.2f} |")
    return lines


def swap_table(binary: Path, log: Path, sensor: dict, meas: tuple, obs: tuple, out: Path,
               width: float) -> list[str]:
    runs = [("measured", meas)]
    for label, cols in SWAPS:
        sw = out / f"{log.stem}.swap.csv"
        swap_log(log, sw, {c: obs[0][SRC[c]] for c in cols})
        runs.append((label, replay(binary, sw, out, "swapped", "measured")))
    runs.append(("pipeline", obs))
    lines = ["| t [s] | " + " | ".join(r[0] for r in runs) + " |",
             "|---|" + "---|" * len(runs)]
    for a, b in windows(sensor["t"], width):
        cells = [fw(friction_window(sensor, r[1][0], a, b)) for r in runs]
        if any(not c.startswith("0 /") for c in cells):
            lines.append(f"| {a:.1f}–{b:.1f} | " + " | ".join(cells) + " |")
    lines.append("| whole log | " + " | ".join(trust_text(r[1][1]) for r in runs) + " |")
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "observer_ramp")
    ap.add_argument("--window", type=float, default=1.0, help="window width, s")
    ap.add_argument("--log", action="append", default=None,
                    help="log name in scenarios/ (repeatable; default: ramp_steer_high_mu "
                         "and ramp_steer_high_mu.mf)")
    ap.add_argument("--params", type=Path, default=None,
                    help="parameter file for the observer runs (a candidate setting)")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    names = a.log or ["ramp_steer_high_mu", "ramp_steer_high_mu.mf"]
    truth = truth_logs(names, a.out)
    for name in names:
        log = ROOT / "scenarios" / f"{name}.csv"
        sensor, tru = read_csv(log), read_csv(truth[name])
        if len(tru["t"]) != len(sensor["t"]):
            sys.exit(f"observer_ramp_study: {truth[name]} is not {log}'s twin")
        meas = replay(a.replay, log, a.out, "measured", "measured")
        par = a.params
        if par is not None:  # keep the fed sd(vy) readable: the output floor off as well
            par = a.out / "candidate.par"
            par.write_text(a.params.read_text().rstrip("\n") + "\nobs_vy_out_floor_mu = 0\n")
        obs = replay(a.replay, log, a.out, "observer", "observer", params=par)
        print(f"### {name}\n")
        print("\n".join(window_table(sensor, tru, meas[0], obs[0], a.window)) + "\n")
        print("\n".join(swap_table(a.replay, log, sensor, meas, obs, a.out, a.window)) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
