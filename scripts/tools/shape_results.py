#!/usr/bin/env python3
"""Measure the shape-ambiguity rules (scripts/reference/shape.py) on every bundled log.

    .venv/bin/python scripts/tools/shape_results.py [--jobs 2] [--cache build/shape]
        [--only NAME ...] [--page docs/MONITOR.md] [--json FILE]

The float64 reference of the default preset (scripts/reference/trusted.py, equal to the C
double build to 1e-9) with the monitor applied (scripts/reference/monitor.py, as the library
has it on), on the 72 logs of the trust invariant (scripts/tools/trust_invariant.py: every
scenarios/*.csv, both truth tyres, noisy and noise-free, and scenarios/faults/*.csv), and the
same estimator with each second tyre hypothesis of shape.py as its shadow. Per log, pooled over
the four wheels and mu_replay's settled samples (monitor_results.figures): valid share, excited
valid share (true utilisation >= 0.5), RMSE, consistency and worst case when valid, and
whether the log meets issue 17's invariant (trust_invariant.meets). Writes the tables between
<!-- shape-NAME:begin/end --> of the page. Runs are cached in --cache as .npz keyed by the log
and the reference sources (delete the directory to recompute).
"""
from __future__ import annotations

import argparse
import hashlib
import json
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
from reference import logs, monitor, params, shape, trusted  # noqa: E402
sys.path.insert(0, str(ROOT / "scripts" / "tools"))
from md_tables import replace_region  # noqa: E402
from monitor_results import WHEELS, figures, fmt, pct  # noqa: E402
from trust_invariant import CONS_MIN, RMSE_MAX, WORST_MAX, bundled_logs  # noqa: E402

RUNS = ("base",) + shape.HYPOTHESES
VARIANTS = tuple((h, r) for h in shape.HYPOTHESES for r in shape.RULES)
MAX_DROP = 0.05   # issue 17: the excited-valid share drops by at most 5 points where it works


def group(name: str) -> str:
    """mf: Magic Formula truth (*.mf.csv and the fault logs, all on it); dugoff: the
    normalised-Dugoff truth, noisy and noise-free (*.csv, *.nf.csv)."""
    return "mf" if name.endswith(".mf.csv") else "dugoff"


def cache_key(path: Path, run: str, p: dict) -> str:
    """The log (path, size, mtime), the run, the estimator's sources and its parameters (the
    shadow's included: shape.py's rules act on the cached runs and are not part of the key)."""
    st = path.stat()
    files = ("trusted.py", "model.py", "filters.py", "params.py")
    src = "".join((ROOT / "scripts" / "reference" / f).read_text() for f in files)
    par = json.dumps(sorted((k, str(v)) for k, v in p.items()))
    h = hashlib.sha1(f"{path}:{st.st_size}:{int(st.st_mtime)}:{run}:{src}:{par}".encode())
    return h.hexdigest()[:16]


def run_params(path: Path, run: str):
    """The log and the parameter set of one run: the default preset, or its shadow."""
    log = logs.read_csv_log(str(path))
    p = params.resolve(log.meta, None, source=str(path), preset="default")
    return log, (p if run == "base" else shape.shadow_params(p, run))


def run_one(args) -> tuple[str, str, dict]:
    """One (log, run) through the reference: the default preset or its shadow; cached."""
    path, run, cache = args
    log, p = run_params(path, run)
    f = Path(cache) / f"{path.name}.{run}.{cache_key(path, run, p)}.npz"
    if f.is_file():
        with np.load(f) as z:
            return str(path), run, {k: z[k] for k in z.files}
    res = trusted.run(log, p)
    keep = {k: res[k] for k in ("t", "mu", "sd", "valid", "status", "nu", "s_zz", "c_pers")}
    keep["truth"] = np.stack([log.col(f"mu_{w}") for w in WHEELS], 1)
    keep["util"] = (np.stack([log.col(f"util_{w}") for w in WHEELS], 1)
                    if "util_fl" in log.columns else np.full((len(log), 4), np.nan))
    keep["dt"] = np.array(p["dt"])
    keep["sd_valid"] = np.array(p["sd_valid"])
    Path(cache).mkdir(parents=True, exist_ok=True)
    np.savez(f, **keep)
    return str(path), run, keep


def meets(fg: dict) -> bool:
    """Issue 17's invariant (trust_invariant.meets on the reference's figures)."""
    return fg["valid"] == 0 or ((fg["cons_valid"] or 0) >= CONS_MIN
                                and (fg["rmse_valid"] or 0) <= RMSE_MAX
                                and (fg["max_err_valid"] or 0) <= WORST_MAX)


def measure(paths, jobs: int, cache: Path) -> dict:
    """{log name: {label: figures}}: "today" (the default preset with the monitor) and one
    label per (hypothesis, rule)."""
    todo = [(p, r, str(cache)) for p in paths for r in RUNS]
    got = {}
    with ProcessPoolExecutor(max_workers=max(jobs, 1)) as ex:
        for i, (path, run, r) in enumerate(ex.map(run_one, todo), 1):
            got[(path, run)] = r
            print(f"[{i}/{len(todo)}] {Path(path).name} {run}", flush=True, file=sys.stderr)
    mon_p = dict(monitor.MON_DEFAULTS)
    out = {}
    for path in paths:
        base = got[(str(path), "base")]
        a = monitor.apply(base, mon_p, float(base["dt"]))
        figs = {"today": figures(a)}
        for hyp, rule in VARIANTS:
            b = got[(str(path), hyp)]
            lr = (shape.likelihood_ratio(base, b, float(base["dt"])) if rule == "agree_lr"
                  else None)
            c = shape.combine(a, b, rule, float(base["sd_valid"]), lr=lr)
            figs[f"{hyp}/{rule}"] = figures(c)
        out[path.relative_to(ROOT / "scenarios").as_posix()] = figs
    return out


def summary(res: dict, labels=None, ok=meets) -> dict:
    """Per label: logs meeting the invariant (all, Dugoff truth, MF truth); on the MF-truth logs
    that meet it today, the largest drop of the excited-valid share and the logs that drop by
    more than MAX_DROP or stop meeting it. @p labels: the runs ("today" first; default this
    study's), @p ok: the invariant on one run's figures (default meets, on the reference's;
    trust_invariant.meets on mu_replay's)."""
    labels = labels or ["today"] + [f"{h}/{r}" for h, r in VARIANTS]
    today_ok = [n for n, f in res.items() if group(n) == "mf" and ok(f["today"])]
    out = {}
    for lab in labels:
        n_meet = {g: sum(ok(f[lab]) for n, f in res.items() if g in ("all", group(n)))
                  for g in ("all", "dugoff", "mf")}
        n_tot = {g: sum(1 for n in res if g in ("all", group(n))) for g in ("all", "dugoff", "mf")}
        drops, lost = [], []
        for n in today_ok:
            e0, e1 = res[n]["today"]["excited_valid"], res[n][lab]["excited_valid"]
            if e0 is not None and e1 is not None:
                drops.append((e0 - e1, n))
            if not ok(res[n][lab]):
                lost.append(n)
        worst = max(drops) if drops else (0.0, None)
        out[lab] = {"meets": n_meet, "total": n_tot, "worst_drop": worst[0],
                    "worst_drop_log": worst[1],
                    "over_drop": sorted(n for d, n in drops if d > MAX_DROP + 1e-12),
                    "lost": lost, "n_today_ok_mf": len(today_ok)}
    return out


def summary_table(s: dict) -> list[str]:
    lines = ["| run | logs meeting the invariant: all / Dugoff truth / MF truth | MF-truth logs "
             "meeting it today: largest drop of the excited-valid share (log) | of those, "
             "dropping > 5 points | of those, no longer meeting it |", "|---|---|---|---|---|"]
    for lab, v in s.items():
        m, t = v["meets"], v["total"]
        lines.append(f"| {lab} | {m['all']}/{t['all']} / {m['dugoff']}/{t['dugoff']} / "
                     f"{m['mf']}/{t['mf']} | {100 * v['worst_drop']:.1f} points "
                     f"({v['worst_drop_log'] or '–'}) | {len(v['over_drop'])}/{v['n_today_ok_mf']} | "
                     f"{len(v['lost'])}/{v['n_today_ok_mf']} |")
    return lines


def log_table(res: dict, labels) -> list[str]:
    head = "| log | " + " | ".join(labels) + " |"
    lines = [head, "|" + "|".join(["---"] * (len(labels) + 1)) + "|"]
    for n, f in res.items():
        cells = []
        for lab in labels:
            g = f[lab]
            cells.append(f"{pct(g['valid'])} / {pct(g['excited_valid'])} / {fmt(g['rmse_valid'])} / "
                         f"{pct(g['cons_valid'])} / {fmt(g['max_err_valid'])} / "
                         f"{'yes' if meets(g) else '**no**'}")
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    return lines


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenarios", type=Path, default=ROOT / "scenarios")
    ap.add_argument("--cache", type=Path, default=ROOT / "build" / "shape")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", nargs="*", help="only these log names (a quick look; no --page)")
    ap.add_argument("--page", type=Path, help="rewrite the tables of this page (docs/MONITOR.md)")
    ap.add_argument("--json", type=Path, help="write the per-log figures and the summary")
    a = ap.parse_args(argv)
    paths = [p.resolve() for p in bundled_logs(a.scenarios)]
    if a.only:
        paths = [p for p in paths if p.name in a.only]
    res = measure(paths, a.jobs, a.cache)
    s = summary(res)
    labels = ["today"] + [f"{h}/{r}" for h, r in VARIANTS]
    tables = {"summary": summary_table(s), "logs": log_table(res, labels)}
    for k, v in tables.items():
        print(f"\n## {k}\n" + "\n".join(v))
    if a.json:
        a.json.write_text(json.dumps({"logs": res, "summary": s}, indent=1, default=float))
    if a.page and not a.only:
        for k, v in tables.items():
            replace_region(a.page, f"<!-- shape-{k}:begin -->", f"<!-- shape-{k}:end -->", v,
                           "shape_results")
        print(f"updated the tables in {a.page}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
