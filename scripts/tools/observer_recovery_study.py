"""The lateral offset after a saturation (docs/OBSERVER_RESULTS.md "The offset's recovery after
a saturation", issue 16's low-mu misses): per window after each saturation of the model's tyres,
the offset b_y's error, what the model row's gain put into b_y, what §4.4 put into it, and the
errors of vy and beta.

    .venv/bin/python scripts/tools/observer_recovery_study.py [--replay build/mu_replay] \
        [--log scenarios/observer/dlc_mu035.csv] [--real double] [--u-sat 0.8] [--window 1.0] \
        [--hold T_REC ...] [--decouple T_REC ...]

It runs the composed pipeline (`mu_replay --velocity observer`, default preset) for the friction
estimate, then the reference observer (scripts/reference/observer.py) on the same log with that
estimate one step late, as the pipeline feeds it (observer_spin_diag.reference_run's input), and
records every model-row update of the lateral filter (OBSERVER.md §4.2): its gains K = P H^T / S
on vy and on b_y, and its innovation. A model step is saturated when its utilisation
u = |ay| / (g min mu_i) reaches --u-sat, mu_i the friction the row takes (the input raised to
(1 + obs_mu_margin) |ay| / g, §4.2, so u <= 1 / 1.1). A saturation is a run of saturated model
steps; its window is the --window seconds after its last one (cut at the next saturation).
b_y's truth is the log's ay_bias (metadata) plus g sin(bank_true) (the low-mu logs are flat and
unbiased: 0). Columns per
window: b_y error at the exit and its mean / max |.|; the model row's gain on b_y (K_b, per
m/s^2 of innovation; mean over the window's model steps) and its ratio to the gain on vy
(K_b / K_v, 1/s); what the model row and §4.4 put into b_y over the window (sums, m/s^2); vy
error mean / max |.| (m/s); beta RMSE below 0.5 mu g (deg, the table's split, mean of the four
wheels' truth friction). Nothing is typed by hand.
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
from observer_spin_diag import WHEELS  # noqa: E402
from reference import logs, observer, params  # noqa: E402


def trace(c: dict, p: dict, mu, pin_by: list | None = None,
          hold: tuple[float, float] | None = None, pin: str = "all",
          decouple: tuple[float, float] | None = None) -> list[dict]:
    """Run the reference observer over the columns @p c with the friction @p mu ((mu, sd) per
    wheel, or None) and record per step: t, vy, b_y, the model row's update (None on a step
    without one: gains k_v, k_b, innovation, utilisation u) and §4.4's change of b_y. With
    @p pin_by (per step), b_y is pinned there after every step (its variance and covariance 0):
    an oracle offset, the bound of what any rule on b_y alone can give; @p pin "value" pins b_y's
    value only (its covariance as the filter has it), "cov" zeroes only its variance and
    covariance after every step (the model row then has no gain on b_y, §4.4 only the one step's
    q_by: nearly a filter without the offset state). With @p decouple =
    (u_sat, T_rec), cov(vy, b_y) is zeroed after each step within T_rec s of the last model step
    whose utilisation reached u_sat while the yaw rate was off §4.2b's neutral reference (the
    decoupling measured in C, OBSERVER_RESULTS.md). With @p hold = (u_sat, T_rec) the
    model row leaves b_y and its variance alone (a Schmidt update) on its steps within T_rec s of
    the last one whose utilisation reached u_sat (the rule measured in C, OBSERVER_RESULTS.md)."""
    obs = observer.Observer(p)
    rec: list[dict] = []
    cur: dict = {}
    since = [math.inf]
    off = [math.inf]
    orig = obs.lat.update

    def update(h0, h1, innovation, r):
        x0, x1 = obs.lat.x
        ph0 = obs.lat.P[0][0] * h0 + obs.lat.P[0][1] * h1
        ph1 = obs.lat.P[0][1] * h0 + obs.lat.P[1][1] * h1
        p11 = obs.lat.P[1][1]
        s = orig(h0, h1, innovation, r)
        if h1 == 0.0 and h0 != 1.0 and "model" not in cur:  # §4.2's lateral row
            if hold is not None and cur["u"] >= hold[0]:
                since[0] = 0.0
            if hold is not None and since[0] < hold[1]:
                obs.lat.x[1], obs.lat.P[1][1] = x1, p11
            cur["model"] = dict(k_v=ph0 / s, k_b=ph1 / s, nu=innovation,
                                dby=obs.lat.x[1] - x1, dvy=obs.lat.x[0] - x0)
        elif h0 == 0.0 and h1 == 1.0:                       # §4.4
            cur["dby44"] = obs.lat.x[1] - x1
        return s

    obs.lat.update = update
    n = len(c["t"])
    margin = 1.0 + p["obs_mu_margin"]
    for k in range(n):
        s = observer.Sample(t=float(c["t"][k]), delta=float(c["delta"][k]),
                            yaw_rate=float(c["yaw_rate"][k]), ax=float(c["ax"][k]),
                            ay=float(c["ay"][k]),
                            omega=tuple(float(c["omega_" + w][k]) for w in WHEELS))
        if mu is not None:
            s.mu = tuple(float(mu[0][i][k]) for i in range(4))
            s.sd_mu = tuple(float(mu[1][i][k]) for i in range(4))
        cur.clear()
        mu_in = s.mu if s.mu is not None else (p["obs_mu_default"],) * 4
        low = margin * abs(s.ay) / p["g"]
        cur["u"] = abs(s.ay) / (p["g"] * min(max(x, low) for x in mu_in)) if s.ay else 0.0
        if k:
            since[0] += s.t - float(c["t"][k - 1])
            off[0] += s.t - float(c["t"][k - 1])
        if decouple is not None and cur["u"] >= decouple[0] and k % p["obs_lat_every"] == 0:
            r_ref = obs.lon.x[0] * s.delta / (p["Lf"] + p["Lr"])
            if abs(s.yaw_rate - r_ref) > p["obs_lin_r_tol"] + p["obs_lin_r_rel"] * abs(r_ref):
                off[0] = 0.0
        obs.step(s)
        if pin_by is not None and pin in ("all", "value"):
            obs.lat.x[1] = pin_by[k]
        if pin_by is not None and pin in ("all", "cov"):
            obs.lat.P[0][1] = obs.lat.P[1][0] = obs.lat.P[1][1] = 0.0
        if decouple is not None and off[0] < decouple[1]:
            obs.lat.P[0][1] = obs.lat.P[1][0] = 0.0
        m = cur.get("model")
        if m is not None:
            m["u"] = cur["u"]
        rec.append(dict(t=s.t, vy=obs.lat.x[0], by=obs.lat.x[1], model=m and dict(m),
                        dby44=cur.get("dby44", 0.0)))
    return rec


def truth_offset(c: dict, meta: dict, g: float) -> list[float]:
    """b_y's truth per step: the accelerometer's bias (metadata ay_bias) plus the bank's
    g sin(bank_true) (the column when present; the observer's b_y settles there on the banks)."""
    bias = float(meta.get("ay_bias", 0.0))
    bank = c.get("bank_true")
    return [bias + (g * math.sin(float(bank[k])) if bank is not None else 0.0)
            for k in range(len(c["t"]))]


def saturations(rec: list[dict], u_sat: float) -> list[tuple[int, int]]:
    """(first, last) step index of each run of saturated model steps (u >= @p u_sat); model
    steps below it end a run, steps without a model update do not."""
    runs, start, last = [], None, None
    for k, r in enumerate(rec):
        m = r["model"]
        if m is None:
            continue
        if m["u"] >= u_sat:
            start = k if start is None else start
            last = k
        elif start is not None:
            runs.append((start, last))
            start = None
    if start is not None:
        runs.append((start, last))
    return runs


def window_rows(rec, c, p, u_sat: float, width: float, by_true: list) -> list[dict]:
    """One dict per saturation: the window after its last saturated step (up to @p width s,
    cut at the next saturation's first step); @p by_true: b_y's truth per step."""
    runs = saturations(rec, u_sat)
    g = p["g"]
    rows = []
    for j, (a, b) in enumerate(runs):
        end_t = rec[b]["t"] + width
        stop = runs[j + 1][0] if j + 1 < len(runs) else len(rec)
        idx = [k for k in range(b + 1, stop) if rec[k]["t"] <= end_t]
        if not idx:
            continue
        models = [rec[k]["model"] for k in idx if rec[k]["model"] is not None]
        ebeta = []
        for k in idx:
            if c["vx_true"][k] < 3.0:
                continue
            mu_t = sum(c["mu_" + w][k] for w in WHEELS) / 4.0
            if abs(c["ay"][k]) < 0.5 * mu_t * g:
                vx_est = c["vx_true"][k]  # beta's error from vy alone (vx within mm/s here)
                ebeta.append(math.degrees(math.atan2(rec[k]["vy"], vx_est) - c["beta_true"][k]))
        eby = [rec[k]["by"] - by_true[k] for k in idx]
        evy = [rec[k]["vy"] - c["vy_true"][k] for k in idx]
        inside = range(a + 1, b + 1)
        rows.append(dict(
            sat=(rec[a]["t"], rec[b]["t"]),
            vy_exit=rec[b]["vy"] - c["vy_true"][b],
            dby_sat=(sum(rec[k]["model"]["dby"] for k in inside if rec[k]["model"] is not None),
                     sum(rec[k]["dby44"] for k in inside)),
            vy_sat=(rec[a]["vy"] - c["vy_true"][a],
                    sum(rec[k]["model"]["dvy"] for k in inside if rec[k]["model"] is not None),
                    -sum((rec[k - 1]["by"] - by_true[k - 1]) * (rec[k]["t"] - rec[k - 1]["t"])
                         for k in inside)), win=(rec[idx[0]]["t"], rec[idx[-1]]["t"]),
            by_exit=rec[b]["by"] - by_true[b],
            by_mean=sum(abs(x) for x in eby) / len(eby), by_max=max(abs(x) for x in eby),
            k_b=sum(m["k_b"] for m in models) / len(models) if models else float("nan"),
            ratio=(sum(m["k_b"] / m["k_v"] for m in models if m["k_v"]) / len(models)
                   if models else float("nan")),
            dby_model=sum(m["dby"] for m in models),
            dby44=sum(rec[k]["dby44"] for k in idx),
            vy_mean=sum(evy) / len(evy), vy_max=max(abs(x) for x in evy),
            beta_lin=(math.sqrt(sum(e * e for e in ebeta) / len(ebeta)) if ebeta else None)))
    return rows


def phase_shares(rec, c, p, u_sat: float, width: float) -> dict:
    """Where beta's error below 0.5 mu g lies: its squared error summed over the saturated
    stretches (first to last saturated model step), the windows after them (as window_rows) and
    the rest, as shares of the whole, with the RMSE of each part (deg) and its sample count."""
    runs = saturations(rec, u_sat)
    phase = ["rest"] * len(rec)
    for j, (a, b) in enumerate(runs):
        for k in range(a, b + 1):
            phase[k] = "saturated"
        stop = runs[j + 1][0] if j + 1 < len(runs) else len(rec)
        for k in range(b + 1, stop):
            if rec[k]["t"] <= rec[b]["t"] + width:
                phase[k] = "after"
    acc = {q: [0.0, 0] for q in ("saturated", "after", "rest")}
    for k, r in enumerate(rec):
        if c["vx_true"][k] < 3.0:
            continue
        mu_t = sum(c["mu_" + w][k] for w in WHEELS) / 4.0
        if abs(c["ay"][k]) < 0.5 * mu_t * p["g"]:
            e = math.degrees(math.atan2(r["vy"], c["vx_true"][k]) - c["beta_true"][k])
            acc[phase[k]][0] += e * e
            acc[phase[k]][1] += 1
    total = sum(v[0] for v in acc.values())
    return {q: (v[0] / total if total else 0.0, math.sqrt(v[0] / v[1]) if v[1] else None, v[1])
            for q, v in acc.items()}


def table(rows: list[dict]) -> list[str]:
    lines = ["| saturated [s] | Δb_y model / §4.4 while saturated [m/s²] | vy error at entry [m/s] "
             "| while saturated: Δvy model row / −∫ b_y error dt [m/s] | vy error at exit [m/s] "
             "| window [s] | b_y error at exit [m/s²] | b_y error mean / max "
             "[m/s²] | K_b [1] | K_b / K_v [1/s] | Δb_y model / §4.4 [m/s²] | vy error mean / "
             "max [m/s] | β RMSE < 0.5 μg [°] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        beta = "–" if r["beta_lin"] is None else f"{r['beta_lin']:.2f}"
        lines.append(
            f"| {r['sat'][0]:.2f}–{r['sat'][1]:.2f} "
            f"| {r['dby_sat'][0]:+.2f} / {r['dby_sat'][1]:+.2f} | {r['vy_sat'][0]:+.3f} "
            f"| {r['vy_sat'][1]:+.3f} / {r['vy_sat'][2]:+.3f} | {r['vy_exit']:+.3f} "
            f"| {r['win'][0]:.2f}–{r['win'][1]:.2f} "
            f"| {r['by_exit']:+.2f} | {r['by_mean']:.2f} / {r['by_max']:.2f} "
            f"| {r['k_b']:+.3f} | {r['ratio']:+.2f} | {r['dby_model']:+.2f} / {r['dby44']:+.2f} "
            f"| {r['vy_mean']:+.3f} / {r['vy_max']:.3f} | {beta} |")
    return lines


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--log", type=Path, default=ROOT / "scenarios" / "observer" / "dlc_mu035.csv")
    ap.add_argument("--real", default="double", choices=("float", "double"))
    ap.add_argument("--out", type=Path, default=ROOT / "build" / "observer_recovery")
    ap.add_argument("--u-sat", type=float, default=0.8, help="utilisation of a saturated step")
    ap.add_argument("--window", type=float, default=1.0, help="window after a saturation, s")
    ap.add_argument("--hold", type=float, nargs="*", default=[],
                    help="T_rec values [s] of the Schmidt hold to run the reference with")
    ap.add_argument("--decouple", type=float, nargs="*", default=[],
                    help="T_rec values [s] of the decoupling to run the reference with")
    a = ap.parse_args()
    a.out.mkdir(parents=True, exist_ok=True)
    est = read_csv(replay(a.replay, a.log, a.out, "observer", a.real)["estimate"])
    log = logs.read_csv_log(str(a.log), required=("t", "vx_true", "vy_true", "beta_true"))
    c = log.columns
    p = observer.params_with_defaults(params.from_metadata(log.meta))
    n = len(c["t"])
    mu = ([[max(est["mu_" + w][max(k - 1, 0)], 0.0) for k in range(n)] for w in WHEELS],
          [[est["sd_" + w][max(k - 1, 0)] for k in range(n)] for w in WHEELS])
    rec = trace(c, p, mu)
    dvy = max(abs(r["vy"] - v) for r, v in zip(rec, est["vy_est"]))
    by_true = truth_offset(c, log.meta, p["g"])
    print(f"{a.log.name} ({a.real}): reference vs C max |vy difference| {dvy:.1e} m/s; "
          f"b_y truth {min(by_true):+.3f} … {max(by_true):+.3f} m/s² (ay_bias + g sin(bank))")
    print("\n".join(table(window_rows(rec, c, p, a.u_sat, a.window, by_true))))
    sh = phase_shares(rec, c, p, a.u_sat, a.window)
    print("β error below 0.5 μg, share of its squared sum / RMSE [°] / samples: " + "; ".join(
        f"{q} {100 * f:.0f} % / {'–' if e is None else f'{e:.2f}'} / {n}"
        for q, (f, e, n) in sh.items()))
    runs = [("the reference as it runs", {}),
            ("b_y pinned to its truth", dict(pin_by=by_true)),
            ("b_y's value pinned to its truth, its covariance free",
             dict(pin_by=by_true, pin="value")),
            ("b_y's variance and covariance zeroed (no offset state)",
             dict(pin_by=by_true, pin="cov"))]
    runs += [(f"b_y held by the model row for {t:g} s after u >= {a.u_sat:g}",
              dict(hold=(a.u_sat, t))) for t in a.hold]
    runs += [(f"cov(vy, b_y) zeroed for {t:g} s after u >= {a.u_sat:g} off r_ref",
              dict(decouple=(a.u_sat, t))) for t in a.decouple]
    for label, kw in runs:
        whole = phase_shares(trace(c, p, mu, **kw), c, p, a.u_sat, a.window)
        sq = sum(e * e * n for _, e, n in whole.values() if e is not None)
        cnt = sum(n for _, _, n in whole.values())
        print(f"β RMSE below 0.5 μg, {label}: {math.sqrt(sq / cnt) if cnt else float('nan'):.2f}°")


if __name__ == "__main__":
    main()
