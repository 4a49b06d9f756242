"""Issue 17: the prior (mu0, sd0, sd0_common; docs/MONITOR.md section 15) and where step 5's
information gate judges (info_at, info_mu_h; section 16) measured against the trust invariant,
in the float64 reference only.

Usage (from the repository root):

    .venv/bin/python scripts/tools/prior_study.py [--scenarios scenarios]
        [--cache build/prior_study] [--jobs 2] [--variants SPEC ...] [--logs NAME ...]

Runs the reference of the default preset with the library's three trust rules on (the
estimator make trust-invariant measures: scripts/reference/trusted.py + monitor.py, equal to
the C double build to 1e-9; trust_rules_study.reference_run with library_rules) on every log
of MONITOR.md's summary table (monitor_results.log_set: the clean Magic Formula logs, the
Dugoff logs, the noise-free Dugoff logs, wrong tyre data, the faults the library accepts, the
banked curves), once per SPEC, and prints per SPEC and group the logs meeting the invariant
(consistency when valid >= 0.9, RMSE when valid <= 0.10, worst error when valid <= 0.25, on
settled samples pooled over the wheels: trust_rules_study.figures), the (wheel, sample) pairs
valid with error > 0.25, and issue 17's no-loss rule against today (on the logs that meet the
invariant today, the largest fall of the excited-valid share; at most 5 points), and the
largest mismatch-status share on a clean MF log (the monitor's false alarms).

SPEC (comma-separated, no spaces):
  today                       the default preset as it is (always run: the reference);
  KEY=VALUE[,KEY=VALUE...]    preset parameters set (mu0, sd0, sd0_common, info_at,
                              info_mu_h, hyp_update, hyp_lr_min,
                              hyp_warmup, sd_floor_ref, sd_floor_hold, sd_local,
                              sd_local_at, relin_steps, relin_iter, relin_gate),
                              e.g. mu0=0.3 or
                              info_at=1,info_mu_h=0.3 or info_at=2,hyp_update=1;
  warm[,KEY=VALUE...]         each log driven twice in a row: mu0 = the estimate today's run
                              of the same log ends with (the mean of the four wheels' last
                              estimate: one number kept over ignition), the other keys set;
  cross[,KEY=VALUE...]        the same, but mu0 = the end of a DIFFERENT log: a high-mu log's
                              (CROSS_HIGH) for a log whose truth starts below CROSS_SPLIT, a
                              low-mu log's (CROSS_LOW) otherwise (the worst case of a kept mu0).
Runs are cached per SPEC and log as .npz in CACHE/<spec> (delete it after changing the code).
"""

from __future__ import annotations

import argparse
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # scripts: reference
from reference import logs, monitor  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))        # tools
from monitor_results import log_set, settled  # noqa: E402
import trust_rules_study as trs  # noqa: E402

GROUPS = ("mf", "dugoff", "nf", "wrong", "fault", "bank")   # MONITOR.md's summary order
GROUP_LABEL = {"mf": "MF", "dugoff": "Dugoff", "nf": "noise-free Dugoff",
               "wrong": "wrong tyre data", "fault": "faults", "bank": "banked"}
PRIOR_KEYS = ("mu0", "sd0", "sd0_common", "info_at", "info_mu_h",   # + step 5: section 16
              "hyp_update", "hyp_lr_min", "hyp_warmup",          # + steps 5-6: section 17
              "sd_floor_ref", "sd_floor_hold",                    # + step 7: section 19
              "sd_local", "sd_local_at",                          # + step 6: section 20
              "relin_steps", "relin_iter", "relin_gate")          # + step 6: section 21
CROSS_SPLIT = 0.6                       # a truth starting below: a low-mu log
CROSS_HIGH, CROSS_LOW = "hard_brake_high_mu.mf", "hard_brake_low_mu.mf"   # the donors
MISMATCH = monitor.STATUS_MISMATCH       # the monitor's false alarm on a clean log
BAD_ERR = trs.WORST_MAX                 # issue 17's worst error while valid


def parse_spec(spec: str) -> tuple[str, dict]:
    """(mode, overrides) of a SPEC: mode 'today', 'set', 'warm' or 'cross'; overrides
    {key: float} with key one of PRIOR_KEYS (warm and cross may not set mu0)."""
    if spec == "today":
        return "today", {}
    parts = spec.split(",")
    mode = "set"
    if parts[0] in ("warm", "cross"):
        mode, parts = parts[0], parts[1:]
    over = {}
    for kv in parts:
        key, _, val = kv.partition("=")
        if key not in PRIOR_KEYS or not val:
            raise ValueError(f"spec {spec!r}: {kv!r} is not KEY=VALUE with KEY one of "
                             f"{', '.join(PRIOR_KEYS)}")
        if key in over:
            raise ValueError(f"spec {spec!r}: {key} set twice")
        over[key] = float(val)
    if mode == "set" and not over:
        raise ValueError(f"spec {spec!r}: nothing set")
    if mode != "set" and "mu0" in over:
        raise ValueError(f"spec {spec!r}: {mode} chooses mu0 itself")
    return mode, over


def kept_mu(mu_end: np.ndarray) -> float:
    """The one number kept over ignition: the mean of the four wheels' last estimate."""
    return float(np.mean(mu_end))


def cross_donor(truth_start: np.ndarray) -> str:
    """The log whose end feeds a log starting at this truth (per wheel): a high-mu log's for a
    low-mu start (mean below CROSS_SPLIT), a low-mu log's otherwise."""
    return CROSS_HIGH if float(np.mean(truth_start)) < CROSS_SPLIT else CROSS_LOW


def count_bad(mu, valid, truth, s, err_max=BAD_ERR) -> int:
    """(wheel, sample) pairs settled, valid and off by more than err_max."""
    return int((s & valid.astype(bool) & (np.abs(mu - truth) > err_max)).sum())


def no_loss(base: dict, new: dict):
    """(largest fall of the excited-valid share, its log) over the logs meeting the invariant
    in base (a log without excited samples in either run is skipped); (0.0, None) if none."""
    drops = {n: base[n]["exc"] - new[n]["exc"] for n in base
             if base[n]["meets"] and base[n]["exc"] is not None
             and new[n]["exc"] is not None}
    if not drops:
        return 0.0, None
    n = max(drops, key=drops.get)
    return max(drops[n], 0.0), (n if drops[n] > 0 else None)


def group_counts(figs: dict, group_of: dict) -> dict:
    """{group: (meeting, logs, bad pairs)} in GROUPS order (groups with no log left out)."""
    out = {}
    for g in GROUPS:
        names = [n for n in figs if group_of[n] == g]
        if names:
            out[g] = (sum(figs[n]["meets"] for n in names), len(names),
                      sum(figs[n]["bad"] for n in names))
    return out


def false_alarm(figs: dict, group_of: dict) -> float:
    """The largest share of samples with the mismatch status on a clean Magic Formula log (the
    MF group: not a fault, not wrong tyre data, not banked)."""
    return max((figs[n]["mismatch"] for n in figs if group_of[n] == "mf"), default=0.0)


def updated_share(runs: dict) -> float:
    """The share of the evaluated steps (status not 2, the low-speed skip) that updated
    (status 0 or 1, as the monitor leaves it), pooled over the runs."""
    st = np.concatenate([r["status"] for r in runs.values()])
    ev = st != 2
    return float(np.isin(st[ev], (0, 1)).mean()) if ev.any() else float("nan")


def _run(args):
    path, name, f, over = args
    if f.is_file():
        return name
    r = trs.reference_run(path, library_rules=True, extra=over)
    f.parent.mkdir(parents=True, exist_ok=True)
    np.savez(f, **{k: r[k] for k in ("t", "mu", "sd", "valid", "status")})
    return name


def tag_of(spec: str) -> str:
    return spec.replace(",", "_").replace("=", "")


def run_spec(items, spec: str, cache: Path, jobs: int, ends: dict | None, starts: dict) -> dict:
    """{name: run} of one SPEC over items [(group, name, path)]; ends: today's {name: kept
    mu} (warm, cross)."""
    mode, over = parse_spec(spec)
    todo = []
    for _, name, path in items:
        o = dict(over)
        if mode == "warm":
            o["mu0"] = ends[name]
        elif mode == "cross":
            o["mu0"] = ends[cross_donor(starts[name])]
        todo.append((path, name, cache / tag_of(spec) / f"{name.replace('/', '+')}.npz", o))
    with ProcessPoolExecutor(jobs) as ex:
        list(ex.map(_run, todo))
    runs = {}
    for path, name, f, o in todo:
        with np.load(f) as z:
            runs[name] = {k: z[k] for k in z.files}
        runs[name]["mu0"] = o.get("mu0")
    return runs


def evaluate(runs: dict, truths: dict) -> dict:
    out = {}
    for n, r in runs.items():
        truth, util, s = truths[n]
        f = trs.figures(r["mu"], r["sd"], r["valid"].astype(bool), truth, util, s)
        f["bad"] = count_bad(r["mu"], r["valid"], truth, s)
        f["mismatch"] = float(np.mean(r["status"] == MISMATCH))
        out[n] = f
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="issue 17: the prior against the trust invariant")
    ap.add_argument("--scenarios", default="scenarios", type=Path)
    ap.add_argument("--cache", default="build/prior_study", type=Path)
    ap.add_argument("--jobs", default=2, type=int)
    ap.add_argument("--variants", nargs="*", default=["mu0=0.3"], metavar="SPEC")
    ap.add_argument("--logs", nargs="*", default=[], help="names as log_set (default: all)")
    ap.add_argument("--detail", action="store_true", help="each changed log's figures")
    a = ap.parse_args(argv)
    for spec in a.variants:
        parse_spec(spec)   # fail before any run
    items = [(g, n, p) for g, n, p in log_set(a.scenarios) if not a.logs or n in a.logs]
    group_of = {n: g for g, n, _ in items}
    truths, starts = {}, {}
    for _, n, p in items:
        log = logs.read_csv_log(str(p))
        truth = np.stack([log.col(f"mu_{w}") for w in trs.WHEELS], 1)
        util = (np.stack([log.col(f"util_{w}") for w in trs.WHEELS], 1)
                if "util_fl" in log.columns else None)
        truths[n] = (truth, util, settled(log.col("t"), truth))
        starts[n] = truth[0]
    need_donors = any(parse_spec(s)[0] == "cross" for s in a.variants)
    base_items = list(items)
    if need_donors:
        have = {n for _, n, _ in items}
        base_items += [(g, n, p) for g, n, p in log_set(a.scenarios)
                       if n in (CROSS_HIGH, CROSS_LOW) and n not in have]
    base_runs = run_spec(base_items, "today", a.cache, a.jobs, None, starts)
    ends = {n: kept_mu(r["mu"][-1]) for n, r in base_runs.items()}
    base = evaluate({n: base_runs[n] for n in group_of}, truths)

    def line(label, figs):
        gc = group_counts(figs, group_of)
        meets = " / ".join(f"{m}/{k}" for m, k, _ in gc.values())
        bad = " / ".join(str(b) for _, _, b in gc.values())
        tot = sum(m for m, _, _ in gc.values())
        return f"| {label} | {meets} ({tot}/{len(figs)}) | {bad} |"

    print("| prior | logs meeting the invariant: "
          + " / ".join(GROUP_LABEL[g] for g in GROUPS if g in set(group_of.values()))
          + " (all) | valid pairs with error > 0.25, same order | gained | lost | "
          "no loss: largest excited-valid fall |", flush=True)
    print(line("today", base) + " – | – | – |", flush=True)
    print(f"    updated: {100 * updated_share({n: base_runs[n] for n in group_of}):.1f} %; "
          f"mismatch on clean MF logs at most {100 * false_alarm(base, group_of):.1f} %", flush=True)
    if need_donors:
        print(f"cross donors: {CROSS_HIGH} ends at {ends[CROSS_HIGH]:.3f}, "
              f"{CROSS_LOW} at {ends[CROSS_LOW]:.3f}", flush=True)
    for spec in a.variants:
        if spec == "today":
            continue
        runs = run_spec(items, spec, a.cache, a.jobs, ends, starts)
        new = evaluate(runs, truths)
        gained = sorted(n for n in new if new[n]["meets"] and not base[n]["meets"])
        lost = sorted(n for n in new if base[n]["meets"] and not new[n]["meets"])
        drop, drop_log = no_loss(base, new)
        verdict = "kept" if drop <= trs.NO_LOSS_MAX else "**broken**"
        print(line(spec, new) + f" {', '.join(gained) or 'none'} | {', '.join(lost) or 'none'}"
              f" | {verdict} ({100 * drop:.1f}" + (f", {drop_log}" if drop_log else "")
              + ") |", flush=True)
        print(f"    updated: {100 * updated_share(runs):.1f} %; mismatch on clean MF logs at "
              f"most {100 * false_alarm(new, group_of):.1f} %", flush=True)
        if a.detail:
            for n in new:
                b, g = base[n], new[n]
                if (b["n_valid"], b["rmse"], b["exc"]) == (g["n_valid"], g["rmse"], g["exc"]):
                    continue
                mu0 = runs[n]["mu0"]
                print(f"    {n}" + (f" (mu0 {mu0:.3f})" if mu0 is not None else "")
                      + f": valid {100 * b['valid']:.1f} -> {100 * g['valid']:.1f} %, RMSE "
                      f"{trs.fmt(b['rmse'])} -> {trs.fmt(g['rmse'])}, consistency "
                      f"{trs.fmt(b['cons'])} -> {trs.fmt(g['cons'])}, worst "
                      f"{trs.fmt(b['worst'])} -> {trs.fmt(g['worst'])}, excited valid "
                      f"{trs.fmt(b['exc'])} -> {trs.fmt(g['exc'])}, bad {b['bad']} -> "
                      f"{g['bad']}, meets {b['meets']} -> {g['meets']}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
