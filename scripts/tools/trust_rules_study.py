"""Issue 17: candidate rules for the Magic Formula logs that miss the trust invariant
(docs/MONITOR.md section 8), measured with the float64 reference over every bundled log.

Usage (from the repository root):

    .venv/bin/python scripts/tools/trust_rules_study.py [--scenarios scenarios]
        [--cache build/trust_rules] [--jobs 2]

Runs the reference (scripts/reference/trusted.py, the default preset with its two trust rules
switched off, then monitor.py, which equal the C double build to 1e-9) once per log (cached as .npz in --cache; the 72 logs take
about 10 min of CPU) and evaluates rules on top of it, each as the trust invariant's figures
(scripts/tools/trust_invariant.py: settled samples, pooled over the wheels) before and after:

- valid-flag rules, applied to the recorded run (the filter is untouched, like step 9's holds):
  * `updates`: a side is valid only while the exponentially weighted share (time constant
    tau) of steps that updated it with its own information >= info_min is >= a_min (for the
    sporadic updates of brake_in_turn.mf and ramp_steer_high_mu.mf);
  * `stale`: a wheel speed exactly equal to its previous sample while the median of the other
    three wheel speeds has moved by more than delta (rad/s) since it last changed is stale:
    both sides are not valid (for the frozen wheel speed); the reference's own rule
    (trusted.StaleOmega, the library's `stale_omega`, docs/MONITOR.md section 9);
- an input rule that changes the filter's input, so it reruns the reference on the logs where
  it acts (on every other log the run is the recorded one, bit for bit):
  * `yaw`: a yaw-rate sample that differs from the previous accepted one, advanced by the
    measured yaw acceleration over dt (trapezoidal), by more than thr (rad/s) is replaced by
    that prediction (for the yaw-rate spikes); the reference's own check (trusted.YawCheck,
    the library's `yaw_check`), rerun with it on.

Per rule it prints the logs meeting the invariant (the 72 logs), those gained and lost, issue
17's no-loss rule (on the logs meeting the invariant before, the largest fall of the excited-
valid share; at most 5 points allowed) and the share of steps with the mismatch status on the
clean Magic Formula logs (false alarms; at most 1 %), then the five target logs' figures.
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # scripts: reference
from reference import logs, monitor, params, trusted  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))        # tools: the monitor study
from monitor_results import settled  # noqa: E402  (mu_replay's settled samples, metrics.c)

WHEELS = ("fl", "fr", "rl", "rr")
SIDE_OF_WHEEL = (0, 1, 0, 1)           # structure sides: fl, rl on the left
EXCITE_UTIL, CONSISTENCY_K = 0.5, 2.0                                 # mu_replay's
CONS_MIN, RMSE_MAX, WORST_MAX = 0.9, 0.10, 0.25                       # issue 17's targets
NO_LOSS_MAX, FALSE_ALARM_MAX = 0.05, 0.01                             # issue 17's rules
TARGETS = ("brake_in_turn.mf", "ramp_steer_high_mu.mf",
           "faults/freeze_omega_fl.hard_brake_low_mu.mf",
           "faults/freeze_omega_fl.sine_steer_low_mu.mf",
           "faults/spike_yaw_rate.sine_steer_low_mu.mf")
KEEP = ("t", "mu", "sd", "valid", "status", "info")


# ---------------------------------------------------------------- figures
def figures(mu, sd, valid, truth, util, s) -> dict:
    """The trust invariant's figures of one run (trust_invariant.figures, from the samples)."""
    err = np.abs(mu - truth)
    sv = s & valid
    f = {"valid": sv.sum() / max(s.sum(), 1), "n_valid": int(sv.sum()),
         "rmse": None, "cons": None, "worst": None, "exc": None}
    if sv.any():
        f["rmse"] = float(np.sqrt(np.mean(err[sv] ** 2)))
        f["cons"] = float(np.mean(err[sv] <= CONSISTENCY_K * sd[sv]))
        f["worst"] = float(err[sv].max())
    if util is not None:
        exc = s & (util >= EXCITE_UTIL)
        if exc.any():
            f["exc"] = float((exc & valid).sum() / exc.sum())
    f["meets"] = f["n_valid"] == 0 or (f["cons"] >= CONS_MIN and f["rmse"] <= RMSE_MAX
                                       and f["worst"] <= WORST_MAX)
    return f


# ---------------------------------------------------------------- rules
def side_rule_to_wheels(side_ok: np.ndarray) -> np.ndarray:
    """(N, 2) per side -> (N, 4) per wheel."""
    return side_ok[:, SIDE_OF_WHEEL]


def rule_updates(status, info, tau_s, a_min, info_min, dt) -> np.ndarray:
    """(N, 2) allowed: the exponentially weighted share (lambda = dt / (tau + dt), over the
    steps that evaluate the model, status != 2) of the steps that updated side j (status 0, 1)
    with its own information >= info_min is >= a_min."""
    lam = dt / (tau_s + dt)
    ind = np.isin(status, (0, 1))[:, None] & (info >= info_min)
    a = np.zeros(2)
    ok = np.zeros((len(status), 2), dtype=bool)
    for k in range(len(status)):
        if status[k] != 2:
            a += lam * (ind[k] - a)
        ok[k] = a >= a_min
    return ok


def rule_stale(omega, delta) -> np.ndarray:
    """(N,) allowed: no wheel speed is stale (the reference's trusted.StaleOmega, the library's
    rule). Wheel i is stale at sample k when omega_i,k equals omega_i,k-1 exactly, is not 0 (a
    wheel at rest or locked reads 0: a state of the car, not of the sensor) and the median of
    the other three wheel speeds has moved by more than delta since omega_i last changed (a
    steady cruise or a noise-free log repeat values too, but with the others as still as it)."""
    rule = trusted.StaleOmega(delta)
    ok = np.ones(len(omega), dtype=bool)
    for k in range(len(omega)):
        rule.update(omega[k])
        ok[k] = not rule.stale
    return ok


def yaw_substitute(t, r, r_dot, thr):
    """The yaw rate as the reference's trusted.YawCheck (the library's check) accepts it, at the
    log's nominal period (the median step of t): r'_k = r_k unless it differs from
    r'_k-1 + dt (r_dot_k + r_dot_k-1) / 2 by more than thr, then that prediction (and the next
    sample is accepted as it is). Returns (r', number of samples replaced)."""
    check = trusted.YawCheck(thr, float(np.median(np.diff(t))))
    out = np.array([check.step(float(r[k]), float(r_dot[k])) for k in range(len(r))])
    return out, int(np.count_nonzero(out != np.asarray(r, dtype=float)))


# ---------------------------------------------------------------- runs
def bundled(scen: Path) -> list[str]:
    return [p.relative_to(scen).as_posix()[:-4]
            for p in sorted(scen.glob("*.csv")) + sorted((scen / "faults").glob("*.csv"))]


def reference_run(path: Path, yaw_thr: float | None = None) -> dict:
    """The default preset's reference run and the monitor on one log, its two trust rules off;
    with yaw_thr, with the reference's yaw-rate check at that threshold (n_sub: the samples
    yaw_substitute replaces)."""
    log = logs.read_csv_log(str(path))
    n_sub = 0
    if yaw_thr is not None:
        n_sub = yaw_substitute(log.col("t"), log.col("yaw_rate"), log.col("yaw_acc"), yaw_thr)[1]
    p = params.resolve(log.meta, None, source=str(path), preset="default")
    p["stale_omega"] = 0.0      # the base run: the rules are measured on top of it
    p["yaw_check"] = 0.0 if yaw_thr is None else yaw_thr
    res = trusted.run(log, p)
    mon = monitor.apply(res, p, p["dt"])
    out = {k: mon[k] for k in KEEP if k in mon}
    out["info"] = res["info"]
    out["status_filter"] = res["status"]
    out["n_sub"] = np.array(n_sub)
    out["dt"] = np.array(p["dt"])
    return out


def _cached(args):
    scen, cache, name = args
    f = cache / f"{name.replace('/', '+')}.npz"
    if not f.is_file():
        np.savez(f, **reference_run(scen / f"{name}.csv"))
    return name


def load_all(scen: Path, cache: Path, jobs: int) -> dict:
    cache.mkdir(parents=True, exist_ok=True)
    names = bundled(scen)
    with ProcessPoolExecutor(jobs) as ex:
        list(ex.map(_cached, [(scen, cache, n) for n in names]))
    runs = {}
    for n in names:
        with np.load(cache / f"{n.replace('/', '+')}.npz") as z:
            r = {k: z[k] for k in z.files}
        log = logs.read_csv_log(str(scen / f"{n}.csv"))
        r["truth"] = np.stack([log.col(f"mu_{w}") for w in WHEELS], 1)
        r["util"] = (np.stack([log.col(f"util_{w}") for w in WHEELS], 1)
                     if "util_fl" in log.columns else None)
        r["omega"] = log.omega()
        r["settled"] = settled(r["t"], r["truth"])
        runs[n] = r
    return runs


def evaluate(runs: dict, allowed=None, replaced=None) -> dict:
    """{log: figures} with the valid flags and-ed with allowed(run) ((N, 4) bool), or, for a
    log in replaced, that run instead of the recorded one."""
    out = {}
    for n, r in runs.items():
        rr = dict(r, **replaced[n]) if replaced and n in replaced else r
        valid = rr["valid"].astype(bool)
        if allowed is not None:
            valid = valid & allowed(rr)
        out[n] = figures(rr["mu"], rr["sd"], valid, rr["truth"], rr["util"], rr["settled"])
        out[n]["mismatch"] = float(np.mean(rr["status"] == monitor.STATUS_MISMATCH))
    return out


def verdict(base: dict, new: dict) -> dict:
    """Logs meeting the invariant, gained, lost; the largest fall of the excited-valid share on
    the logs meeting it before; the largest mismatch share on a clean Magic Formula log."""
    drops = {n: base[n]["exc"] - new[n]["exc"] for n in base
             if base[n]["meets"] and base[n]["exc"] is not None and new[n]["exc"] is not None}
    worst = max(drops, key=drops.get) if drops else None
    clean_mf = [n for n in new if n.endswith(".mf") and not n.startswith("faults/")
                and not n.startswith("wrong_tyre")]
    return {"meets": sum(f["meets"] for f in new.values()),
            "gained": sorted(n for n in new if new[n]["meets"] and not base[n]["meets"]),
            "lost": sorted(n for n in new if base[n]["meets"] and not new[n]["meets"]),
            "drop": drops[worst] if worst else 0.0, "drop_log": worst,
            "false_alarm": max((new[n]["mismatch"] for n in clean_mf), default=0.0)}


def fmt(x, spec=".3f"):
    return "–" if x is None else format(x, spec)


def report(label: str, base: dict, new: dict) -> list[str]:
    v = verdict(base, new)
    ok = v["drop"] <= NO_LOSS_MAX and v["false_alarm"] <= FALSE_ALARM_MAX
    fall = f"{100 * v['drop']:.1f} points" + (f" ({v['drop_log']})" if v["drop"] > 0 else "")
    lines = [f"{label}: meets {v['meets']}/{len(new)}; gained {v['gained'] or 'none'}; "
             f"lost {v['lost'] or 'none'}; excited-valid fall {fall}; mismatch on clean MF "
             f"logs {100 * v['false_alarm']:.1f} %; issue 17's rules {'kept' if ok else 'BROKEN'}"]
    for n in TARGETS:
        b, f = base[n], new[n]
        lines.append(f"    {n}: valid {100 * b['valid']:.0f} -> {100 * f['valid']:.0f} %, RMSE "
                     f"{fmt(b['rmse'])} -> {fmt(f['rmse'])}, consistency {fmt(b['cons'])} -> "
                     f"{fmt(f['cons'])}, worst {fmt(b['worst'])} -> {fmt(f['worst'])}")
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="issue 17: candidate valid and input rules")
    ap.add_argument("--scenarios", default="scenarios", type=Path)
    ap.add_argument("--cache", default="build/trust_rules", type=Path)
    ap.add_argument("--jobs", default=2, type=int)
    a = ap.parse_args(argv)
    runs = load_all(a.scenarios, a.cache, a.jobs)
    base = evaluate(runs)
    print(f"reference, default preset: meets {sum(f['meets'] for f in base.values())}/{len(base)}")
    for tau, a_min in ((0.1, 0.3), (0.3, 0.1), (0.5, 0.1)):
        def upd(r, tau=tau, a_min=a_min):
            return side_rule_to_wheels(rule_updates(r["status_filter"], r["info"], tau, a_min,
                                                    25.0, float(r["dt"])))
        print("\n".join(report(f"updates tau {tau} s, a_min {a_min}", base, evaluate(runs, upd))))
    for delta in (0.25, 0.5):
        def stale(r, delta=delta):
            return np.repeat(rule_stale(r["omega"], delta)[:, None], 4, 1)
        print("\n".join(report(f"stale wheel speed, delta {delta} rad/s", base,
                               evaluate(runs, stale))))
    thr = 0.1
    replaced = {}
    for n in runs:
        log = logs.read_csv_log(str(a.scenarios / f"{n}.csv"))
        if yaw_substitute(log.col("t"), log.col("yaw_rate"), log.col("yaw_acc"), thr)[1]:
            replaced[n] = reference_run(a.scenarios / f"{n}.csv", thr)
    print(f"yaw-rate check acts on {sorted(replaced)}")
    print("\n".join(report(f"yaw-rate check, thr {thr} rad/s", base,
                           evaluate(runs, replaced=replaced))))
    print("\n".join(report(f"stale wheel speed (delta 0.25 rad/s) and yaw-rate check", base,
                           evaluate(runs, lambda r: np.repeat(rule_stale(r["omega"], 0.25)[:, None],
                                                              4, 1), replaced))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
