#!/usr/bin/env python3
"""What a wrong vehicle mass costs the friction estimator (issue 19, deliverable 4: "measure
and state what a +-20 % mass error does to the friction estimate").

    .venv/bin/python scripts/tools/mass_sensitivity.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--mu-replay build/mu_replay] [--jobs N]

Every bundled friction scenario with truth (scenarios/*.csv: noise-free, noisy and Magic
Formula truth) is replayed by the C library (`mu_replay`, float, measured velocities) with the
log's own mass m and with m x 0.8 and m x 1.2 given by a parameter file, in the default and
the paper preset. Per run the CLI's accuracy JSON gives, per wheel over settled samples
(README, RESULTS.md): the samples reported valid, their RMSE, their largest error and their
consistency (|error| <= 2 sd). Pooled over the four wheels and every log of a preset:
    valid         the share of settled samples reported valid
    RMSE valid    sqrt of the mean squared error over the samples reported valid
    consistency   the share of valid samples within 2 sd
    max valid     the largest |error| of a sample reported valid
    logs worse    logs whose pooled RMSE when valid rose by more than 0.02 over the log's own
                  mass (issue 16's threshold for "no worse"); logs better: fell by more
With --page the table goes between <!-- mass-sensitivity:begin/end --> of the page.
"""

import json
import math
import multiprocessing
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from md_tables import replace_region  # noqa: E402
from replay_args import replay_args  # noqa: E402
FACTORS = (0.8, 1.0, 1.2)
PRESETS = ("default", "paper")
WHEELS = ("fl", "fr", "rl", "rr")
WORSE = 0.02  # issue 16's "RMSE-when-valid rises by at most 0.02"


def logs():
    """The friction scenarios with truth (the golden set's sensor logs)."""
    d = os.path.join(ROOT, "scenarios")
    out = []
    for f in sorted(os.listdir(d)):
        if f.endswith(".csv"):
            with open(os.path.join(d, f), encoding="utf-8") as fh:
                head = [line for line in (fh.readline() for _ in range(200))
                        if not line.startswith("#")]
            if head and "mu_fl" in head[0].split(","):
                out.append(f)
    return out


def log_mass(path):
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            if not line.startswith("#"):
                break
            m = re.match(r"#\s*m\s*=\s*([0-9.eE+-]+)\s*$", line)
            if m:
                return float(m.group(1))
    raise SystemExit(f"mass_sensitivity: {path}: no '# m = ...' metadata line")


def one(job):
    exe, name, preset, factor = job
    path = os.path.join(ROOT, "scenarios", name)
    with tempfile.TemporaryDirectory() as tmp:
        params = os.path.join(tmp, "mass.params")
        with open(params, "w", encoding="utf-8") as fh:
            fh.write(f"m = {log_mass(path) * factor!r}\n")
        out, js = os.path.join(tmp, "est.csv"), os.path.join(tmp, "m.json")
        r = subprocess.run([exe, "--in", path, "--out", out, "--preset", preset,
                            "--params", params, "--velocity", "measured", "--metrics", js,
                            "--quiet"], capture_output=True, text=True, check=False)
        if r.returncode != 0:
            raise SystemExit(f"mass_sensitivity: {name} {preset} x{factor}: exit "
                             f"{r.returncode}: {r.stderr.strip()}")
        with open(js, encoding="utf-8") as fh:
            met = json.load(fh)["metrics"]
    return job[1:], [met[w] for w in WHEELS]


def pooled(wheels):
    """(settled, valid, sum of squared errors when valid, consistent valid, max |err| valid)."""
    settled = valid = cons = 0
    sse = worst = 0.0
    for w in wheels:
        n = w["n_valid"]
        settled += w["n_settled"]
        valid += n
        if n:
            sse += n * w["rmse_valid"] ** 2
            cons += round(w["consistency_valid"] * n)
            worst = max(worst, w["max_abs_err_valid"])
    return settled, valid, sse, cons, worst


def pooled_cells(runs, bases):
    """The figures of one table row over the logs: @runs the pooled() tuples of the row's runs,
    @bases those of the same logs' reference runs (None: no comparison). Returns the cells
    "valid | RMSE valid | consistency | max valid" and the logs whose RMSE when valid rose /
    fell by more than WORSE against their reference (logs without valid samples either way
    are not counted)."""
    tot = [0, 0, 0.0, 0, 0.0]
    worse = better = 0
    for p, b in zip(runs, bases if bases is not None else [None] * len(runs)):
        for i in range(4):
            tot[i] += p[i]
        tot[4] = max(tot[4], p[4])
        if b is not None and p[1] and b[1]:
            change = math.sqrt(p[2] / p[1]) - math.sqrt(b[2] / b[1])
            worse += change > WORSE
            better += change < -WORSE
    settled, valid, sse, cons, worst = tot
    rmse = math.sqrt(sse / valid) if valid else float("nan")
    text = (f"{valid / settled:.1%} | {rmse:.3f} | "
            f"{cons / valid if valid else float('nan'):.3f} | {worst:.3f}")
    return text, worse, better


def table(results, names):
    rows = ["| preset | mass given | valid | RMSE valid | consistency | max valid | "
            f"logs worse by > {WORSE} | better by > {WORSE} |", "|---|---|---|---|---|---|---|---|"]
    for preset in PRESETS:
        base = [pooled(results[(n, preset, 1.0)]) for n in names]
        for factor in FACTORS:
            text, worse, better = pooled_cells([pooled(results[(n, preset, factor)]) for n in names],
                                               None if factor == 1.0 else base)
            rows.append(f"| {preset} | m × {factor:.1f} | {text} | "
                        f"{'–' if factor == 1.0 else f'{worse} of {len(names)}'} | "
                        f"{'–' if factor == 1.0 else f'{better} of {len(names)}'} |")
    return "\n".join(rows)


def main():
    a = replay_args(__doc__, "mass_sensitivity", jobs=os.cpu_count() or 1)
    names = logs()
    jobs = [(a.mu_replay, n, p, f) for n in names for p in PRESETS for f in FACTORS]
    results = {}
    with multiprocessing.Pool(a.jobs) as pool:
        for k, (key, wheels) in enumerate(pool.imap_unordered(one, jobs), 1):
            results[key] = wheels
            if k % 50 == 0 or k == len(jobs):
                print(f"mass_sensitivity: {k}/{len(jobs)} runs", file=sys.stderr)
    text = table(results, names)
    print(text)
    if a.page:
        replace_region(Path(a.page), "<!-- mass-sensitivity:begin -->",
                       "<!-- mass-sensitivity:end -->", text.splitlines(), "mass_sensitivity")


if __name__ == "__main__":
    main()
