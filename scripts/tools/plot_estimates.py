#!/usr/bin/env python3
"""Draw estimated vs true friction per wheel (the paper's Fig. 4-6 style) to a PNG.

    .venv/bin/python scripts/tools/plot_estimates.py --sensor LOG.csv \\
        --estimate SCKF.csv --estimate CKF.csv [--label SCKF --label CKF] \\
        --out fig.png [--title TEXT]

One panel per wheel (fl, fr, rl, rr): the true mu from the sensor log's truth columns when
present, each estimate log's mu, and a +-2 sd band around the first estimate. Samples an
estimate reports as not valid are shaded grey. Files are DATA.md CSVs.
"""
from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path

WHEELS = ("fl", "fr", "rl", "rr")
STYLES = (("tab:blue", "-"), ("tab:orange", "--"), ("tab:green", ":"), ("tab:red", "-."))


def read_csv(path: Path) -> dict[str, list[float]]:
    """Columns of a DATA.md CSV ('#' metadata lines skipped) as float lists."""
    with path.open() as f:
        rows = [line for line in f if not line.startswith("#")]
    reader = csv.DictReader(rows)
    cols: dict[str, list[float]] = {name: [] for name in reader.fieldnames or []}
    for row in reader:
        for k, v in row.items():
            cols[k].append(float(v))
    return cols


def plot(sensor: Path, estimates: list[Path], labels: list[str], out: Path, title: str) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    truth = read_csv(sensor)
    ests = [read_csv(p) for p in estimates]
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5), sharex=True, sharey=True)
    for ax, w in zip(axes.flat, WHEELS):
        if ests and f"valid_{w}" in ests[0]:
            t, valid = ests[0]["t"], ests[0][f"valid_{w}"]
            dt = (t[1] - t[0]) if len(t) > 1 else 0.01
            for ti, v in zip(t, valid):
                if v == 0:
                    ax.axvspan(ti - dt / 2, ti + dt / 2, color="0.85", lw=0)
        if f"mu_{w}" in truth:
            ax.plot(truth["t"], truth[f"mu_{w}"], color="black", lw=1.5, label="true μ")
        for k, (est, label) in enumerate(zip(ests, labels)):
            color, ls = STYLES[k % len(STYLES)]
            ax.plot(est["t"], est[f"mu_{w}"], color=color, ls=ls, lw=1.2, label=f"{label} μ̂")
            if k == 0:
                lo = [m - 2 * s for m, s in zip(est[f"mu_{w}"], est[f"sd_{w}"])]
                hi = [m + 2 * s for m, s in zip(est[f"mu_{w}"], est[f"sd_{w}"])]
                ax.fill_between(est["t"], lo, hi, color=color, alpha=0.15, lw=0,
                                label=f"{label} ±2 sd")
        ax.set_title(w)
        ax.set_ylim(0.0, 1.3)
        ax.grid(alpha=0.3)
    for ax in axes[1]:
        ax.set_xlabel("t [s]")
    for ax in axes[:, 0]:
        ax.set_ylabel("μ")
    axes[0, 0].legend(loc="lower left", fontsize=8)
    fig.suptitle(title + "   (grey: not valid)")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sensor", type=Path, required=True, help="sensor log (truth columns optional)")
    ap.add_argument("--estimate", type=Path, action="append", required=True,
                    help="estimate log (repeat to overlay several)")
    ap.add_argument("--label", action="append", help="legend label per --estimate")
    ap.add_argument("--out", type=Path, required=True, help="PNG to write")
    ap.add_argument("--title", default="estimated vs true friction")
    args = ap.parse_args()
    labels = args.label or [p.stem for p in args.estimate]
    if len(labels) != len(args.estimate):
        ap.error("give one --label per --estimate")
    for p in [args.sensor, *args.estimate]:
        if not p.is_file():
            sys.exit(f"plot_estimates: {p}: no such file")
    plot(args.sensor, args.estimate, labels, args.out, args.title)
    print(f"wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
