"""Where the observer's vx goes wrong in a spin (docs/OBSERVER_RESULTS.md "The spin's vx"):
per time window, which vx source the longitudinal filter used, how far each wheel's
reference (its speed translated to the CoG, OBSERVER.md §3) is from the truth, each
wheel's longitudinal slip, and what the ax integration adds through r vy.

    .venv/bin/python scripts/tools/observer_spin_diag.py [--replay build/mu_replay] \
        [--log scenarios/observer/sine_dwell_mu035.mf.csv] [--real double] [--window 0.5] \
        [--truth scenarios/NAME.nf.csv]

A friction log (scenarios/NAME.csv) has measured vx, vy instead of vx_true, vy_true: pass
its noise-free twin as --truth.

It runs the composed pipeline (`mu_replay --velocity observer`, default preset), then the
reference observer (scripts/reference/observer.py) on the same log with the pipeline's
friction estimate one step late, as the pipeline feeds it: in double the two agree (the
maximum |vx| difference is printed), so the reference's flags and states are the C run's.
Columns: braking (flag 2) and wheel-corrected (flag 1) shares; each wheel's reference minus
vx_true (with the previous vy, as the filter takes it); each wheel's slip
(omega R - v_wx) / v_wx at the truth, v_wx its speed along its heading; the estimated vy
minus vy_true; r (vy - vy_true), what the wrong vy adds to the predicted v-dot_x; ax - b_x (the
tyres' push) and ax + r vy - b_x (vx's rate, which the driving state took before
2026-12-07). Nothing is typed by hand.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from demo import read_csv  # noqa: E402
from observer_results import ROOT, replay  # noqa: E402
from reference import logs, observer, params  # noqa: E402

WHEELS = ("fl", "fr", "rl", "rr")


def reference_run(log_path: Path, est: dict, truth: Path | None = None):
    """The reference observer on @p log_path with the pipeline's friction one step late.
    The truth is the log's vx_true, vy_true or, with @p truth, that log's vx, vy (a friction
    log's noise-free twin, scenarios/NAME.nf.csv, whose vx, vy are the truth)."""
    if truth is None:
        log = logs.read_csv_log(str(log_path), required=("t", "vx_true", "vy_true"))
        c = log.columns
    else:
        log = logs.read_csv_log(str(log_path), required=("t",))
        tw = logs.read_csv_log(str(truth), required=("t", "vx", "vy")).columns
        c = log.columns
        if len(tw["t"]) != len(c["t"]) or max(abs(tw["t"] - c["t"])) > 1e-9:
            raise SystemExit(f"{truth}: not {log_path}'s twin (time columns differ)")
        c["vx_true"], c["vy_true"] = tw["vx"], tw["vy"]
    if "beta_true" not in c:
        c["beta_true"] = [math.atan2(y, x) for x, y in zip(c["vx_true"], c["vy_true"])]
    p = observer.params_with_defaults(params.from_metadata(log.meta))
    n = len(c["t"])
    mu = ([[max(est["mu_" + w][max(k - 1, 0)], 0.0) for k in range(n)] for w in WHEELS],
          [[est["sd_" + w][max(k - 1, 0)] for k in range(n)] for w in WHEELS])
    return c, p, observer.run(c, p, mu)


def windows(t, width):
    edges, a = [], 0.0
    while a < t[-1]:
        edges.append((a, a + width))
        a += width
    return edges


def mean(v):
    return sum(v) / len(v) if v else float("nan")


def table(c, p, out, width: float) -> list[str]:
    obs = observer.Observer(p)
    n = len(c["t"])
    rows = []
    for k in range(1, n):
        s = observer.Sample(t=c["t"][k], delta=c["delta"][k], yaw_rate=c["yaw_rate"][k],
                            ax=c["ax"][k], ay=c["ay"][k],
                            omega=tuple(c["omega_" + w][k] for w in WHEELS))
        vy_prev, bx_prev = out["vy"][k - 1], out["bx"][k - 1]  # the predict keeps b_x
        refs = obs.wheel_refs(s, vy_prev)
        r, vxt = s.yaw_rate, c["vx_true"][k]
        vyt = c["vy_true"][k]
        slip = []
        for i, (xi, yi) in enumerate(obs.pos):  # v_wx: the wheel's speed along its heading
            d = s.delta if i < 2 else 0.0
            v_wx = (vxt - r * yi) * math.cos(d) + (vyt + r * xi) * math.sin(d)
            slip.append((s.omega[i] * p["R"] - v_wx) / v_wx)
        rows.append(dict(
            t=s.t, beta=abs(math.degrees(c["beta_true"][k])), err=out["vx"][k] - vxt,
            brake=int(out["flags"][k]) & observer.FLAG_BRAKING != 0,
            wheel=int(out["flags"][k]) & observer.FLAG_VX_WHEEL != 0,
            refs=[v - vxt for v in refs], slip=slip, dvy=vy_prev - c["vy_true"][k],
            rdvy=r * (vy_prev - c["vy_true"][k]), push=s.ax - bx_prev,
            rate=s.ax + r * vy_prev - bx_prev))
    lines = ["| t [s] | max \\|β_true\\| [°] | vx error mean / max [m/s] | braking | "
             "wheel update | ref − vx_true fl / fr / rl / rr [m/s] | slip fl / fr / rl / rr [%] | "
             "vy error [m/s] | r·(vy − vy_true) [m/s²] | ax − b_x [m/s²] | ax + r·vy − b_x [m/s²] |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for a, b in windows([r["t"] for r in rows], width):
        w = [r for r in rows if a <= r["t"] < b or (b >= rows[-1]["t"] and r["t"] == rows[-1]["t"])]
        if not w:
            continue
        lines.append(
            f"| {a:.1f}–{b:.1f} | {max(r['beta'] for r in w):.1f} "
            f"| {mean([r['err'] for r in w]):+.3f} / {max(abs(r['err']) for r in w):.3f} "
            f"| {100 * mean([r['brake'] for r in w]):.0f} % | {100 * mean([r['wheel'] for r in w]):.0f} % | "
            + " / ".join(f"{mean([r['refs'][i] for r in w]):+.3f}" for i in range(4))
            + " | " + " / ".join(f"{100 * mean([r['slip'][i] for r in w]):+.2f}" for i in range(4))
            + f" | {mean([r['dvy'] for r in w]):+.2f} | {mean([r['rdvy'] for r in w]):+.2f} "
            f"| {mean([r['push'] for r in w]):+.2f} | {mean([r['rate'] for r in w]):+.2f} |")
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--log", type=Path,
                    default=ROOT / "scenarios" / "observer" / "sine_dwell_mu035.mf.csv")
    ap.add_argument("--real", default="double", choices=("float", "double"))
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "observer_spin")
    ap.add_argument("--window", type=float, default=0.5, help="window width, s")
    ap.add_argument("--truth", type=Path, default=None,
                    help="noise-free twin whose vx, vy are the truth (friction logs: "
                         "scenarios/NAME.nf.csv); default: the log's vx_true, vy_true")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    est = read_csv(replay(a.replay, a.log, a.out, "observer", a.real)["estimate"])
    c, p, out = reference_run(a.log, est, a.truth)
    dvx = max(abs(x - y) for x, y in zip(out["vx"], est["vx_est"]))
    e = [x - y for x, y in zip(est["vx_est"], c["vx_true"])]
    print(f"{a.log.name} ({a.real}): vx RMSE {math.sqrt(mean([x * x for x in e])):.3f} m/s, "
          f"max {max(abs(x) for x in e):.3f} m/s; reference vs C: max |vx difference| {dvx:.1e} m/s")
    print("\n".join(table(c, p, out, a.window)))


if __name__ == "__main__":
    main()
