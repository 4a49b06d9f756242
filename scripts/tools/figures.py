#!/usr/bin/env python3
"""Write the results pages' figures (SVG) into docs/figures/ from the studies' own runs.

    .venv/bin/python scripts/tools/figures.py [--replay build/mu_replay] [--out docs/figures]
        [--work build/figures] [--jobs 2]

mass_error_vs_time.svg   the mass-and-grade estimator's mass error vs time from the four
                         initial masses of scripts/tools/mass_grade_results.py (-50, -20, +20,
                         +50 %), float64 reference, on truck_graded_drive and car_hilly_road:
                         the recommended preset "UKF + ax" beside the seed's AUKF
                         (mass_grade_results.one and plot_mass_error)
tyre_curve_vs_truth.svg  the lateral force curves the reference SCKF identifies (its defaults)
                         against the Magic Formula truth on tid_ramp_steer_high_mu and
                         tid_ramp_steer_low_mu (tyre_id_results.run_filter and plot_curves)
observer_beta.svg        beta estimate vs truth with the +-2 sd band of the C observer
                         (build/mu_replay --velocity observer, --real float, as
                         scripts/tools/observer_results.py runs it) on dlc_mu035, Magic
                         Formula truth; the samples at the limit (|ay| >= 0.5 mu g) shaded
Every file is deterministic: the Agg backend, a fixed SVG hash salt, no date in the metadata
and text kept as text (no embedded glyphs), so a re-run on the same package versions gives
the same bytes.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import os
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]

import numpy as np  # noqa: E402

ROOT = HERE.parent.parent
# the rcParams that make an SVG the same bytes run after run (ids are hashed with the salt)
SVG_RC = {"svg.hashsalt": "rfe-figures", "svg.fonttype": "none", "path.simplify": True}
MASS_LOGS = ("truck_graded_drive", "car_hilly_road")
MASS_CONFIGS = ("AUKF", "UKF + ax")   # the seed's filter beside the recommended preset
MASS_EVERY = 10                        # draw every 10th sample: 0.1 s, the mass moves slowly
TYRE_LOGS = ("tid_ramp_steer_high_mu", "tid_ramp_steer_low_mu")
OBSERVER_LOG = ROOT / "scenarios" / "observer" / "dlc_mu035.mf.csv"
G = 9.81
BETA_MIN_VX = 3.0                      # m/s, as observer_results (beta of a creeping car)


def save_svg(fig, path: Path) -> None:
    """Save @p fig as a deterministic SVG at @p path and close it."""
    import matplotlib
    import matplotlib.pyplot as plt
    path.parent.mkdir(parents=True, exist_ok=True)
    with matplotlib.rc_context(SVG_RC):
        fig.savefig(path, format="svg", metadata={"Date": None})
    plt.close(fig)


def mass_figure(jobs: int):
    import mass_grade_results as M
    from reference import mass_grade as mg
    runs_jobs = [(n, g, c) for n in MASS_LOGS for c in MASS_CONFIGS for g in M.GUESSES]
    with multiprocessing.Pool(jobs) as pool:
        runs = dict(pool.map(M.one, runs_jobs))
    logs = {n: mg.read_log(str(ROOT / "scenarios" / "mass_grade" / f"{n}.csv"))[0]
            for n in MASS_LOGS}
    panels = [(n, (c,)) for n in MASS_LOGS for c in MASS_CONFIGS]
    return M.plot_mass_error(runs, logs, panels, every=MASS_EVERY)


def tyre_figure():
    import tyre_id_results as TI
    from reference.logs import read_csv_log
    panels = []
    for log in TYRE_LOGS:
        c = read_csv_log(str(ROOT / "scenarios" / "tyre_id" / f"{log}.csv")).columns
        out = TI.run_filter(c, "sckf", 0, 0)
        panels.append((f"{log}: SCKF (defaults) vs truth", c, out, 0))
    return TI.plot_curves(panels)


def beta_figure(t, beta_true, beta_est, sd_beta, limit, title):
    """beta estimate and truth [deg] over t with the +-2 sd band; @p limit (bool per sample)
    shaded. Arrays in rad; NaN where beta is not scored."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = np.asarray(t, dtype=float)
    bt, be, sd = (np.degrees(np.asarray(x, dtype=float)) for x in (beta_true, beta_est, sd_beta))
    fig, ax = plt.subplots(figsize=(8, 3.6))
    ax.fill_between(t, be - 2.0 * sd, be + 2.0 * sd, color="C0", alpha=0.25, lw=0,
                    label="estimate ± 2 sd")
    ax.plot(t, bt, "k-", lw=1.2, label="truth")
    ax.plot(t, be, "C0-", lw=1.0, label="estimate")
    lo, hi = ax.get_ylim()
    ax.fill_between(t, lo, hi, where=np.asarray(limit, dtype=bool), color="C3", alpha=0.08,
                    lw=0, label="|ay| ≥ 0.5 μg")
    ax.set_ylim(lo, hi)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("β [deg]")
    ax.set_title(title, fontsize=9)
    ax.legend(fontsize=7, loc="best")
    fig.tight_layout()
    return fig


def observer_figure(replay: Path, work: Path):
    import observer_results as O
    work.mkdir(parents=True, exist_ok=True)
    est = O.read_csv(O.replay(replay, OBSERVER_LOG, work, "observer", "float")["estimate"])
    tru = O.read_csv(OBSERVER_LOG)
    vx = np.asarray(tru["vx_true"], dtype=float)
    keep = vx >= BETA_MIN_VX
    mu = np.mean([np.asarray(tru["mu_" + w], dtype=float) for w in O.WHEELS], axis=0)
    limit = np.abs(np.asarray(tru["ay"], dtype=float)) >= 0.5 * mu * G
    t = np.asarray(tru["t"], dtype=float)

    def masked(x):
        return np.where(keep, np.asarray(x, dtype=float), math.nan)
    return beta_figure(t, masked(tru["beta_true"]), masked(est["beta_est"]),
                       masked(est["sd_beta"]), limit & keep,
                       "dlc_mu035, Magic Formula truth: the observer's β (float, defaults)")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--replay", type=Path, default=ROOT / "build" / "mu_replay")
    ap.add_argument("--out", type=Path, default=ROOT / "docs" / "figures")
    ap.add_argument("--work", type=Path, default=ROOT / "build" / "figures")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    a = ap.parse_args(argv)
    for name, make in (("mass_error_vs_time.svg", lambda: mass_figure(a.jobs)),
                       ("tyre_curve_vs_truth.svg", tyre_figure),
                       ("observer_beta.svg", lambda: observer_figure(a.replay, a.work))):
        save_svg(make(), a.out / name)
        print(f"figures: {a.out / name}", file=sys.stderr, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
