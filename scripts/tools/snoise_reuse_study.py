#!/usr/bin/env python3
"""Issue 21's candidate 'the step noise every N steps when the inputs move little', measured in
the float64 reference (scripts/reference/trusted.py StepNoiseReuse; not in the library).

    .venv/bin/python scripts/tools/snoise_reuse_study.py [--jobs 2] [--variants every2,...]
        [--logs STEM ...] [--md FILE] [--page docs/BENCHMARKS.md]

Runs the default preset (monitor on, as the goldens: trusted.run, then monitor.apply) on every
bundled sensor log of scenarios/*.csv (19 manoeuvres x noisy, .mf, .nf) once with the option
off and once per variant. A variant is `everyN` (step 4's input columns recomputed on every
N-th evaluating step, reused in between) or `moveA` / `moveA_everyN` (recomputed when any input
moved by more than A of its sd since they were computed; with _everyN also when N steps old),
each optionally prefixed `vxvy_` (only the columns of the conditioner's low-passed vx, vy reused,
4 of the 16 evaluations; the other inputs' columns computed every step).
Per log and variant: max |dmu| against the option off (every step, every wheel), the trust
figures of monitor_results.py (mu_replay's settled samples, pooled over the wheels): valid
share, RMSE when valid, consistency when valid (|error| <= 2 sd), and the count of valid flags
(step x wheel) and statuses (steps) that differ from off; and the share of evaluating steps
(those that reach step 4) that recompute the columns. --md writes the per-log table, --page the
summary between <!-- TAG:begin/end --> of the page (--tag, default snoise-reuse; the vx, vy
variants have their own, snoise-reuse-vxvy).
"""
from __future__ import annotations

import argparse
import re
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
from reference import logs, monitor, params, trusted  # noqa: E402
sys.path.insert(0, str(ROOT / "scripts" / "tools"))
import monitor_results as mr  # noqa: E402
from md_tables import replace_region  # noqa: E402

VARIANTS = ("every2", "every3", "every5", "move3", "move3_every5", "move10_every5")
VXVY_VARIANTS = ("vxvy_every2", "vxvy_every5")
TAG = "snoise-reuse"
SNOISE_SHARE = 0.69   # the step noise's share of the float32 step (issue 21, Cortex-M4F)
N_EVALS = 16          # step 4's input columns: 2 model evaluations per input with sd > 0


def markers(tag: str) -> tuple[str, str]:
    return f"<!-- {tag}:begin -->", f"<!-- {tag}:end -->"


def reused_evals(name: str) -> int:
    """How many of the N_EVALS evaluations a variant may skip: 4 (vx, vy) or all."""
    return 2 * len(trusted.PERSISTENT_INPUTS) if name.startswith("vxvy_") else N_EVALS


def parse_variant(name: str) -> trusted.StepNoiseReuse | None:
    """'off' -> None; 'everyN', 'moveA', 'moveA_everyN', each optionally prefixed 'vxvy_'
    (only vx's and vy's columns reused) -> the option."""
    if name == "off":
        return None
    inputs = None
    rule = name
    if name.startswith("vxvy_"):
        inputs, rule = trusted.PERSISTENT_INPUTS, name[len("vxvy_"):]
    m = re.fullmatch(r"(?:every(\d+))|(?:move([0-9.eE+-]+)(?:_every(\d+))?)", rule)
    if not m:
        raise ValueError(f"unknown variant {name!r} ([vxvy_]everyN, moveA, moveA_everyN)")
    if m.group(1):
        return trusted.StepNoiseReuse(every=int(m.group(1)), inputs=inputs)
    every = int(m.group(3)) if m.group(3) else 10 ** 9
    return trusted.StepNoiseReuse(every=every, move=float(m.group(2)), inputs=inputs)


def run_one(path: Path, variant: str, stop: float | None = None) -> dict:
    """The default preset with the monitor on one log (to t <= stop), option as variant."""
    log = logs.read_csv_log(str(path))
    if stop is not None:
        keep = log.col("t") <= stop
        log.columns = {c: v[keep] for c, v in log.columns.items()}
    p = params.resolve(log.meta, None, source=str(path), preset="default")
    reuse = parse_variant(variant)
    res = trusted.run(log, p, reuse=reuse)
    if p["mon_enable"] > 0:
        res = monitor.apply(res, p, p["dt"])
    out = {k: res[k] for k in ("t", "mu", "sd", "valid", "status", "fired")}
    out["truth"] = np.stack([log.col(f"mu_{w}") for w in mr.WHEELS], 1)
    out["util"] = (np.stack([log.col(f"util_{w}") for w in mr.WHEELS], 1)
                   if "util_fl" in log.columns else np.full((len(log), 4), np.nan))
    out["share"] = reuse.computed / reuse.used if reuse is not None and reuse.used else 1.0
    out["used"] = reuse.used if reuse is not None else int(np.sum(res["status"] != 2))
    return out


def _job(args):
    path, variant = args
    return path.name, variant, run_one(path, variant)


def compare(off: dict, r: dict) -> dict:
    """One variant's run against the option off on the same log."""
    fg = mr.figures(r)
    return {"dmu": float(np.max(np.abs(r["mu"] - off["mu"]))),
            "flags": int(np.sum(r["valid"] != off["valid"])),
            "statuses": int(np.sum(r["status"] != off["status"])),
            "share": r["share"], "used": r["used"],
            "valid": fg["valid"], "rmse": fg["rmse_valid"], "cons": fg["cons_valid"]}


def fmt(x, spec=".3f"):
    return "–" if x is None else format(x, spec)


def pct(x):
    return "–" if x is None else f"{100 * x:.0f} %"


def log_table(names, res, variants) -> list[str]:
    """Per log: off's trust figures, then per variant max |dmu|, flips and recompute share."""
    head = ("| log | off: valid / RMSE / consistency when valid | "
            + " | ".join(f"{v}: max dmu / flags / statuses / recomputed" for v in variants) + " |")
    lines = [head, "|" + "|".join(["---"] * (2 + len(variants))) + "|"]
    for n in names:
        o = mr.figures(res[(n, "off")])
        cells = [f"{pct(o['valid'])} / {fmt(o['rmse_valid'])} / {pct(o['cons_valid'])}"]
        for v in variants:
            c = compare(res[(n, "off")], res[(n, v)])
            cells.append(f"{c['dmu']:.1e} / {c['flags']} / {c['statuses']} / {pct(c['share'])}")
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    return lines


def summary_table(names, res, variants) -> list[str]:
    """Per variant over every log: recompute share (pooled over the evaluating steps), the
    float32 saving it implies (an estimate), max |dmu| and where, logs with a flip, flips, and
    the trust figures' largest moves against off."""
    head = ("| variant | recomputed (of evaluating steps) | float32 step saved (estimate) | "
            "max abs dmu (log) | median over logs of max abs dmu | logs with a flip | "
            "valid flags / statuses flipped | valid share, largest change | "
            "RMSE when valid, largest change | consistency when valid, largest change |")
    lines = [head, "|" + "|".join(["---"] * 10) + "|"]
    for v in variants:
        cs = {n: compare(res[(n, "off")], res[(n, v)]) for n in names}
        offs = {n: mr.figures(res[(n, "off")]) for n in names}
        used = sum(c["used"] for c in cs.values())
        share = sum(c["share"] * c["used"] for c in cs.values()) / used
        worst = max(names, key=lambda n: cs[n]["dmu"])

        def dmax(key_c, key_o):
            ds = [(cs[n][key_c] - offs[n][key_o], n) for n in names
                  if cs[n][key_c] is not None and offs[n][key_o] is not None]
            d, n = max(ds, key=lambda x: abs(x[0]))
            return d, n
        dv, nv = dmax("valid", "valid")
        dr, nr = dmax("rmse", "rmse_valid")
        dc, nc = dmax("cons", "cons_valid")
        lines.append(
            f"| {v} | {100 * share:.1f} % | "
            f"~{100 * SNOISE_SHARE * reused_evals(v) / N_EVALS * (1 - share):.0f} % | "
            f"{cs[worst]['dmu']:.3f} (`{worst}`) | "
            f"{np.median([c['dmu'] for c in cs.values()]):.1e} | "
            f"{sum(1 for c in cs.values() if c['flags'] or c['statuses'])} of {len(names)} | "
            f"{sum(c['flags'] for c in cs.values())} / {sum(c['statuses'] for c in cs.values())} | "
            f"{100 * dv:+.1f} pp (`{nv}`) | {dr:+.3f} (`{nr}`) | {100 * dc:+.1f} pp (`{nc}`) |")
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenarios", default=str(ROOT / "scenarios"), type=Path)
    ap.add_argument("--variants", default=",".join(VARIANTS))
    ap.add_argument("--logs", nargs="*", help="log stems (default: every scenarios/*.csv)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--md", type=Path, help="write the per-log table as markdown")
    ap.add_argument("--page", type=Path, help="rewrite the <!-- TAG:begin/end --> region")
    ap.add_argument("--tag", default=TAG, help=f"the page region's marker (default {TAG})")
    a = ap.parse_args(argv)
    variants = [v for v in a.variants.split(",") if v]
    for v in variants:
        parse_variant(v)
    paths = (sorted(a.scenarios.glob("*.csv")) if not a.logs
             else [a.scenarios / f"{s}.csv" for s in a.logs])
    jobs = [(pth, v) for pth in paths for v in ["off"] + variants]
    res = {}
    with ProcessPoolExecutor(max_workers=a.jobs) as ex:
        for name, v, r in ex.map(_job, jobs):
            res[(name, v)] = r
            print(f"snoise_reuse_study: {name} {v}", flush=True)
    names = [pth.name for pth in paths]
    table = log_table(names, res, variants)
    summ = summary_table(names, res, variants)
    print("\n".join(summ + [""] + table), flush=True)
    if a.md:
        a.md.write_text("\n".join(table) + "\n")
    if a.page:
        replace_region(a.page, *markers(a.tag), summ, "snoise_reuse_study")
    return 0


if __name__ == "__main__":
    sys.exit(main())
