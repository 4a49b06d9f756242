"""Why the friction estimator on observer inputs misses issue 16's rule on the high-mu ramp
steer (docs/OBSERVER_RESULTS.md "The high-μ ramp steer on observer inputs"): per time
window, the observer's vx, vy and yaw-acceleration errors against the noise-free twin next to
each run's friction, and which observer output, swapped alone into the measured-velocity path,
makes the miss ("Feeding the friction estimator a larger sd", table 3's method).

    .venv/bin/python scripts/tools/observer_ramp_study.py [--replay build/mu_replay] \
        [--out build/observer_ramp] [--window 1.0] [--log ramp_steer_high_mu ...] \
        [--params FILE] [--mechanism]

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
3. With --mechanism (docs/OBSERVER_RESULTS.md "The low-μ ramp steer on observer inputs"): vy's
   parts, from the reference observer (double, observer_spin_diag.reference_run's input: the
   pipeline's friction one step late; the largest |vy| difference to the C run is printed)
   run again with the truth's friction (sd 0.05), with the linear range (§4.2b) off
   (obs_sd_vy_lin 0) and with both: per window the friction fed (mean over the wheels, its sd)
   and the truth's, the smallest friction the model row took (after §4.2's raise and the
   steady turn's floor), vy's error in the four runs, the share of steps the linear range was
   taken and its vy's error, the change of vy and of b_y made by the model row, the linear row
   and §4.4 (sums over the window, the fed run), b_y at the window's end (its truth 0 on these
   flat, unbiased logs), and the model's ay at the truth's vx, vy and friction minus the
   truth's ay with the vy error that asks of the row (-(that) / (d ay / d vy)).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
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


def row_kind(h0: float, h1: float) -> str:
    """Which of the lateral filter's updates (OBSERVER.md §4) a row (h0, h1) is: "model"
    (§4.2, on vy with its slope), "linear" (§4.2b and §4.3, vy itself) or "s44" (§4.4, b_y)."""
    if h1 == 0.0 and h0 != 1.0:
        return "model"
    return "linear" if h1 == 0.0 else "s44"


def traced_run(c: dict, p: dict, mu, over: dict | None = None) -> dict:
    """The reference observer over the columns @p c with the friction @p mu ((mu, sd) per wheel
    and step) and the parameters @p p changed by @p over; per step: vy, b_y, the linear row's
    vy (nan on a step without it), the smallest friction the model row took (nan without one)
    and each row kind's change of (vy, b_y)."""
    from reference import observer
    pp = dict(p, **(over or {}))
    obs = observer.Observer(pp)
    n = len(c["t"])
    rec = {k: [math.nan] * n for k in ("vy", "by", "vy_lin", "mu_model")}
    rec.update({k: [[0.0, 0.0] for _ in range(n)] for k in ("model", "linear", "s44")})
    k_now = [0]
    upd, jac = obs.lat.update, obs.model_rows_jac

    def update(h0, h1, innovation, r):
        x0, x1 = obs.lat.x
        out = upd(h0, h1, innovation, r)
        d = rec[row_kind(h0, h1)][k_now[0]]
        d[0] += obs.lat.x[0] - x0
        d[1] += obs.lat.x[1] - x1
        if row_kind(h0, h1) == "linear":
            rec["vy_lin"][k_now[0]] = x0 + innovation
        return out

    def rows(s, vx, vy, m, dm):
        rec["mu_model"][k_now[0]] = min(m)
        return jac(s, vx, vy, m, dm)

    obs.lat.update, obs.model_rows_jac = update, rows
    for k in range(n):
        s = observer.Sample(t=float(c["t"][k]), delta=float(c["delta"][k]),
                            yaw_rate=float(c["yaw_rate"][k]), ax=float(c["ax"][k]),
                            ay=float(c["ay"][k]),
                            omega=tuple(float(c["omega_" + w][k]) for w in WHEELS))
        s.mu = tuple(float(mu[0][i][k]) for i in range(4))
        s.sd_mu = tuple(float(mu[1][i][k]) for i in range(4))
        k_now[0] = k
        obs.step(s)
        rec["vy"][k], rec["by"][k] = obs.lat.x
    return rec


def nanmean(x: list[float]) -> float | None:
    v = [a for a in x if not math.isnan(a)]
    return sum(v) / len(v) if v else None


def f3(x: float | None, spec: str = "+.3f") -> str:
    return "–" if x is None else format(x, spec)


def mechanism_table(log: Path, truth: Path, est: dict, width: float) -> list[str]:
    """Table 3 (see the module doc)."""
    from observer_spin_diag import reference_run
    from reference import observer
    tru = read_csv(truth)
    c, p, ref = reference_run(log, est, truth)
    n = len(c["t"])
    fed = ([[max(est["mu_" + w][max(k - 1, 0)], 0.0) for k in range(n)] for w in WHEELS],
           [[est["sd_" + w][max(k - 1, 0)] for k in range(n)] for w in WHEELS])
    true_mu = ([tru["mu_" + w] for w in WHEELS], [[0.05] * n for _ in WHEELS])
    off = {"obs_sd_vy_lin": 0.0}
    runs = [traced_run(c, p, fed), traced_run(c, p, true_mu), traced_run(c, p, fed, off),
            traced_run(c, p, true_mu, off)]
    gap = max(abs(a - b) for a, b in zip(ref["vy"], est["vy_est"]))
    obs = observer.Observer(p)
    ask, dev = [math.nan] * n, [math.nan] * n
    for k in range(n):
        if tru["vx"][k] < p["obs_v_lat_min"]:
            continue
        s = observer.Sample(t=float(tru["t"][k]), delta=float(tru["delta"][k]),
                            yaw_rate=float(tru["yaw_rate"][k]), ax=float(tru["ax"][k]),
                            ay=float(tru["ay"][k]),
                            omega=tuple(float(tru["omega_" + w][k]) for w in WHEELS))
        (ay_m, _), (h0, _), _ = obs.model_rows_jac(
            s, tru["vx"][k], tru["vy"][k], tuple(tru["mu_" + w][k] for w in WHEELS), (0.05,) * 4)
        dev[k] = ay_m - tru["ay"][k]
        ask[k] = -dev[k] / h0 if h0 != 0.0 else math.nan
    lines = [f"The reference observer against the C run: max |vy| difference {gap:.1e} m/s.\n",
             "| t [s] | friction fed, mean (sd) | truth | model row's friction, min | "
             "vy error [m/s]: fed / true μ / fed, linear off / true μ, linear off | "
             "linear range taken | its vy error [m/s] | Δvy model / linear / §4.4 [m/s] | "
             "Δb_y model / linear / §4.4 [m/s²] | b_y at the end [m/s²] | "
             "model ay − truth ay at the truth [m/s²] | vy it asks [m/s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    last = c["t"][-1]
    for a, b in windows(list(c["t"]), width):
        ks = [k for k in range(n) if in_window(c["t"][k], a, b, last)]
        m = [runs[0][key] for key in ("model", "linear", "s44")]
        lin = [k for k in ks if not math.isnan(runs[0]["vy_lin"][k])]
        lines.append(
            f"| {a:.1f}–{b:.1f} | "
            f"{stats([fed[0][i][k] for i in range(4) for k in ks])[0]:.2f} "
            f"({stats([fed[1][i][k] for i in range(4) for k in ks])[0]:.2f}) | "
            f"{stats([tru['mu_' + w][k] for w in WHEELS for k in ks])[0]:.2f} | "
            f"{f3(nanmean([runs[0]['mu_model'][k] for k in ks]), '.2f')} | "
            + " / ".join(f"{stats([r['vy'][k] - tru['vy'][k] for k in ks])[0]:+.3f}" for r in runs)
            + f" | {100 * len(lin) / len(ks):.0f} % | "
            f"{f3(stats([runs[0]['vy_lin'][k] - tru['vy'][k] for k in lin])[0])} | "
            + " / ".join(f"{sum(x[k][0] for k in ks):+.3f}" for x in m) + " | "
            + " / ".join(f"{sum(x[k][1] for k in ks):+.3f}" for x in m)
            + f" | {runs[0]['by'][ks[-1]]:+.3f} | {f3(nanmean([dev[k] for k in ks]))} | "
            f"{f3(nanmean([ask[k] for k in ks]))} |")
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
    ap.add_argument("--mechanism", action="store_true",
                    help="also table 3: vy's parts from the reference observer")
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
        if a.mechanism:
            print("\n".join(mechanism_table(log, truth[name], obs[0], a.window)) + "\n")
        sys.stdout.flush()


if __name__ == "__main__":
    main()
