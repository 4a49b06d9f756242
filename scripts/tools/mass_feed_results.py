#!/usr/bin/env python3
"""How far the friction estimator's mass is from the truth once the replay feeds it the mass and
grade estimator's mass (mg_feed_sd_rel, docs/MASS_GRADE.md section 10).

    .venv/bin/python scripts/tools/mass_feed_results.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--mu-replay build/mu_replay]

Every mass and grade log (scenarios/mass_grade/*.csv) is replayed by the C library
(`mu_replay`, float, the default `--mass-grade ukf`, the default mg_feed_sd_rel; the truck
logs, truck_*, with `--mass-grade-vehicle truck`, the others with the car's keys) with a wrong
vehicle mass given by a parameter file: the log's m x 0.8, x 1.0 and x 1.2 (the estimator's
own start, mg_m0, is the preset's either way), each three times: without the excitation gate
(mg_feed_excitation = 0, mg_feed_slip_max = 0, mg_feed_band = 0: the sd rule alone), with the
gate but without the slip hold and the band (mg_feed_slip_max = 0, mg_feed_band = 0) and with
the default keys; the columns with arrows give no gate -> gate -> gate and checks. Per run,
from the estimate log and the JSON:
    first fed      the time of the first sample whose mass_est the friction estimator took
    fed            the share of samples fed
    m error start  (m given - mass_true) / mass_true: the friction estimator's error unfed
    mass_used end  (mass_used - mass_true) / mass_true at the last sample
    mass_est end   (mass_est - mass_true) / mass_true at the last sample
    refused        the default run's samples the band refused (n_band_refused)
With --page the table goes between <!-- mass-feed:begin/end --> of the page.
"""

import csv
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from mass_sensitivity import log_mass  # noqa: E402
from mass_logs import MG_DIR, mass_grade_logs  # noqa: E402
from md_tables import replace_region  # noqa: E402
from replay_args import replay_args  # noqa: E402

FACTORS = (0.8, 1.0, 1.2)
# the keys each run writes into its parameter file: no gate, the gate alone, the defaults
RUN_KEYS = ("mg_feed_excitation = 0\nmg_feed_slip_max = 0\nmg_feed_band = 0\n",
            "mg_feed_slip_max = 0\nmg_feed_band = 0\n", "")


def vehicle(path):
    """The mass and grade preset a log is run with: truck for the truck logs, else car."""
    return "truck" if os.path.basename(path).startswith("truck_") else "car"


def one(exe, path, factor, keys):
    """(first fed t or None, samples fed, samples, the JSON's object) of the run with the
    parameter file's extra lines @keys (RUN_KEYS)."""
    with tempfile.TemporaryDirectory() as tmp:
        params = os.path.join(tmp, "mass.params")
        with open(params, "w", encoding="utf-8") as fh:
            fh.write(f"m = {log_mass(path) * factor!r}\n")
            fh.write(keys)
        out, js = os.path.join(tmp, "est.csv"), os.path.join(tmp, "m.json")
        r = subprocess.run([exe, "--in", path, "--out", out, "--params", params,
                            "--metrics", js, "--quiet", "--mass-grade-vehicle", vehicle(path)],
                           capture_output=True, text=True,
                           check=False)
        if r.returncode != 0:
            raise SystemExit(f"mass_feed_results: {path} x{factor}: exit {r.returncode}: "
                             f"{r.stderr.strip()}")
        with open(out, encoding="utf-8") as fh:
            rows = list(csv.DictReader(line for line in fh if not line.startswith("#")))
        with open(js, encoding="utf-8") as fh:
            mg = json.load(fh)["mass_grade"]
    m0 = float(rows[0]["mass_used"])
    first = next((float(x["t"]) for x in rows if float(x["mass_used"]) != m0), None)
    return first, mg["feed"]["n_fed"], len(rows), mg


def true_mass_end(path):
    with open(path, encoding="utf-8") as fh:
        rows = csv.DictReader(line for line in fh if not line.startswith("#"))
        last = None
        for last in rows:
            pass
    return float(last["mass_true"])


def main():
    a = replay_args(__doc__, "mass_feed_results")
    rows = ["| log | m given | first fed at: no gate → gate → gate and checks | samples fed "
            "| m error unfed | mass_used error at the end | mass_est error at the end "
            "| band refused |",
            "|---|---|---|---|---|---|---|---|"]
    for name in mass_grade_logs():
        path = os.path.join(MG_DIR, name)
        mt = true_mass_end(path)
        for factor in FACTORS:
            runs = [one(a.mu_replay, path, factor, keys) for keys in RUN_KEYS]
            firsts = ["never" if r[0] is None else f"{r[0]:.2f} s" for r in runs]
            fed = [f"{r[1] / r[2]:.1%}" for r in runs]
            used = [f"{(r[3]['feed']['mass_used_end'] - mt) / mt:+.2%}" for r in runs]
            est = runs[1][3]["end"]["mass"]
            rows.append(f"| {name[:-4]} | m × {factor:.1f} | {' → '.join(firsts)} | "
                        f"{' → '.join(fed)} | {(log_mass(path) * factor - mt) / mt:+.1%} | "
                        f"{' → '.join(used)} | {(est - mt) / mt:+.2%} | "
                        f"{runs[2][3]['feed']['n_band_refused']} |")
    text = "\n".join(rows)
    print(text)
    if a.page:
        replace_region(Path(a.page), "<!-- mass-feed:begin -->", "<!-- mass-feed:end -->",
                       text.splitlines(), "mass_feed_results")


if __name__ == "__main__":
    main()
