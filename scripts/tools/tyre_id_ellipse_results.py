#!/usr/bin/env python3
"""The reference tyre identifier without and with the friction ellipse (tid_ellipse,
docs/TYRE_ID.md section 3.5) over the braking of the brake-in-turn logs, and the table of
docs/TYRE_ID_RESULTS.md "The friction ellipse in the identifier" between its markers.

    .venv/bin/python scripts/tools/tyre_id_ellipse_results.py [--page docs/TYRE_ID_RESULTS.md]
        [--jobs 2]

Every (log, filter) of ROWS is run three times by the reference
(scripts/reference/tyre_id_sckf.py for the SCKF; scripts/reference/tyre_id.py for the APF at
tid_n particles, seed SEED), with the defaults and RUNS: tid_ellipse 0 (without); 1 without
its dead band (tid_ell_ax_min 0, the ellipse as first built: with); and 1 with the band at its
default (with band). The brake-in-turn logs brake from T_BRAKE to T_END
(scenarios/*.csv's description). Figures of each run:
    rear D before -> into   the rear axle's D at T_BEFORE and at T_INTO, N
    rear D mean             its mean over [T_BRAKE, T_END]
    cy at T_INTO            what the feed would give the friction estimator (docs/TYRE_ID.md
                            section 14), (K_f + K_r) / (Fz0_f + Fz0_r), 1/rad
    cy mean (max)           its mean (and largest value) over [T_BRAKE, T_END]
With --page the table goes between <!-- tyre-id-ellipse:begin/end --> of the page.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]

import numpy as np  # noqa: E402

from md_tables import replace_region  # noqa: E402
from reference import tyre_id as T  # noqa: E402
from reference import tyre_id_sckf as TS  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402

ROOT = HERE.parent.parent
ROWS = (("brake_in_turn.mf", "sckf"), ("brake_in_turn", "sckf"), ("brake_in_turn.nf", "sckf"),
        ("brake_in_turn_low_mu", "sckf"), ("brake_in_turn_low_mu.mf", "sckf"),
        ("brake_in_turn_low_mu.nf", "sckf"), ("brake_in_turn.mf", "apf"),
        ("brake_in_turn", "apf"))
T_BEFORE = 1.9        # s, a sample before the braking
T_INTO = 2.4          # s, a sample 0.4 s into it (the pressure's ramp ends at 2.2 s)
T_BRAKE, T_END = 2.0, 6.0   # s, the braking of the brake-in-turn logs
SEED = 1              # the APF's seed (tid_n at its default, 256)
MARK = ("<!-- tyre-id-ellipse:begin -->", "<!-- tyre-id-ellipse:end -->")
# the keys of each run beside the defaults: without, with (no dead band), with the default band
RUNS = ({"tid_ellipse": 0.0}, {"tid_ellipse": 1.0, "tid_ell_ax_min": 0.0}, {"tid_ellipse": 1.0})


def static_loads(params=None):
    """(Fz0_f, Fz0_r) of the reference's vehicle (TYRE_ID.md section 3.4), N."""
    p = dict(T.VEHICLE_DEFAULTS)
    p.update(params or {})
    la = p["Lf"] + p["Lr"]
    return p["m"] * p["g"] * p["Lr"] / la, p["m"] * p["g"] * p["Lf"] / la


def figures(t, out, fz0):
    """The docstring's figures of one run's outputs @p out (tyre_id.run's keys) at times @p t:
    (D_r before, D_r into, D_r mean, cy into, cy mean, cy max)."""
    cy = (out["K_f"] + out["K_r"]) / (fz0[0] + fz0[1])
    k_before = int(np.searchsorted(t, T_BEFORE - 1e-9))
    k_into = int(np.searchsorted(t, T_INTO - 1e-9))
    win = (t >= T_BRAKE - 1e-9) & (t <= T_END + 1e-9)
    return (float(out["D_r"][k_before]), float(out["D_r"][k_into]),
            float(np.mean(out["D_r"][win])), float(cy[k_into]), float(np.mean(cy[win])),
            float(np.max(cy[win])))


def measure(job):
    """One run: job = (log, filter, k[, n_steps]) -> figures(), k the index of its keys in
    RUNS; n_steps the first samples only (a test's excerpt)."""
    log, filt, k = job[:3]
    n_steps = job[3] if len(job) > 3 else None
    c = read_csv_log(str(ROOT / "scenarios" / f"{log}.csv")).columns
    params = dict(RUNS[k])
    if filt == "sckf":
        out = TS.run(c, params, n_steps=n_steps)
    else:
        out = T.run(c, params, seed=SEED, n_steps=n_steps)
    t = np.asarray(c["t"], dtype=float)[:len(out["t"])]
    return figures(t, out, static_loads())


def row(log, filt, runs):
    """One line of the table from the figures of the runs of RUNS, in order."""
    return (f"| {log} | {filt.upper()} | "
            + " / ".join(f"{r[0]:,.0f} → {r[1]:,.0f}" for r in runs) + " | "
            + " / ".join(f"{r[2]:,.0f}" for r in runs) + " | "
            + " / ".join(f"{r[3]:.1f}" for r in runs) + " | "
            + " / ".join(f"{r[4]:.1f} ({r[5]:.1f})" for r in runs) + " |")


def table(res):
    """The table's lines from @p res: (log, filter, k) -> figures(), k indexing RUNS."""
    lines = [f"| log | filter | rear D at {T_BEFORE:g} s → {T_INTO:g} s, N: without / with / "
             f"with band | rear D, mean over {T_BRAKE:g}–{T_END:g} s | cy at {T_INTO:g} s "
             f"| cy, mean over {T_BRAKE:g}–{T_END:g} s (max) |",
             "|---|---|---|---|---|---|"]
    for log, filt in ROWS:
        lines.append(row(log, filt, [res[(log, filt, k)] for k in range(len(RUNS))]))
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", default="")
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args(argv)
    jobs = [(log, filt, k) for log, filt in ROWS for k in range(len(RUNS))]
    with multiprocessing.Pool(max(1, a.jobs)) as pool:
        res = dict(zip(jobs, pool.map(measure, jobs, chunksize=1)))
    lines = table(res)
    print("\n".join(lines))
    if a.page:
        replace_region(Path(a.page), *MARK, lines, "tyre_id_ellipse_results")


if __name__ == "__main__":
    main()
