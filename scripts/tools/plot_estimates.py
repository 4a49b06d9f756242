#!/usr/bin/env python3
"""Draw estimated (and, when the log has it, true) friction per wheel to a PNG.

    .venv/bin/python scripts/tools/plot_estimates.py --sensor LOG.csv \\
        --estimate SCKF.csv --estimate CKF.csv [--label SCKF --label CKF] \\
        --out fig.png [--title TEXT]

One panel per wheel (fl, fr, rl, rr, the paper's Fig. 4-6 style): the true mu from the
sensor log's truth columns when present, each estimate log's mu, and a +-2 sd band around
the first estimate. Samples an estimate reports as not valid are marked by a hatched lane
in that estimate's colour along the bottom of each panel. Under them the manoeuvre (vx,
delta, ax, ay from the sensor log), which shows when friction is observable at all.
Files are DATA.md CSVs, read in SI by the names, units, scales and offsets their metadata
declares (a car's logger's log as mu_replay reads it); columns that are not numbers are
ignored, and an empty, nan or inf cell is a gap in its line.
"""
from __future__ import annotations

import argparse
import csv
import importlib.util
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # scripts/: reference
from reference import log_units, params  # noqa: E402  (DATA.md's column rules, R's default)

# The drawing is the Python package's (python/rfe/plot.py, rfe.plot_estimates), loaded by its
# path: it needs matplotlib only, not the package's compiled extension. This script reads the
# files (in SI, as mu_replay reads them) and hands their columns to it.
_spec = importlib.util.spec_from_file_location(
    "rfe_plot", Path(__file__).resolve().parents[2] / "python" / "rfe" / "plot.py")
_plot = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_plot)
WHEELS = _plot.WHEELS
compose = _plot.compose


def parse_cell(text: str) -> float | None:
    """A cell as a number: empty, nan and inf as NaN (the CLI takes such a cell as a bad
    sample and goes on; one must not lose the whole trace); None when it is no number."""
    text = text.strip()
    if not text:
        return math.nan
    try:
        v = float(text)
    except ValueError:
        return None
    return v if math.isfinite(v) else math.nan


def read_log(path: Path) -> tuple[dict[str, str], dict[str, list[float]]]:
    """(metadata, columns) of a DATA.md CSV, the columns as float lists in SI: the names,
    units, scales and offsets the metadata declares (column_*, unit_*, scale_*, offset_*)
    applied as mu_replay applies them (reference/log_units.py). A column is left out when
    one of its non-empty cells is not a number: DATA.md allows extra columns (a note, a
    driver id) and the plots never need them. Empty, nan and inf cells are NaN (a gap in
    the line)."""
    meta: dict[str, str] = {}
    with path.open(encoding="utf-8-sig") as f:
        lines = list(f)
    body = []
    for line in lines:
        if line.startswith("#"):
            if not body and "=" in line:
                key, value = line[1:].split("=", 1)
                meta[key.strip()] = value.strip()
        elif line.strip() or body:
            body.append(line)
    reader = csv.reader(body)
    header = [h.strip() for h in next(reader, [])]
    cols: dict[str, list[float]] = {name: [] for name in header}
    bad: set[str] = set()
    for row in reader:
        if not row:
            continue
        row = row + [""] * (len(header) - len(row))   # a short row: its missing cells empty
        for name, cell in zip(header, row):
            if name in bad:
                continue
            v = parse_cell(cell)
            if v is None:
                bad.add(name)
            else:
                cols[name].append(v)
    cols = {k: v for k, v in cols.items() if k not in bad}
    try:
        return meta, log_units.to_si(meta, cols, R=rolling_radius(meta), where=str(path))
    except log_units.UnitError as e:
        sys.exit(f"plot_estimates: {e}")


def rolling_radius(meta: dict) -> float:
    """The log's R, else the library's default (as mu_replay without --params). The plots
    use R only to turn a circumferential wheel speed into spin and back (speed_of), where
    it cancels."""
    try:
        return float(meta["R"])
    except (KeyError, ValueError):
        return params.DEFAULTS["R"]


def read_csv(path: Path) -> dict[str, list[float]]:
    """The columns of read_log (for the tools that need no metadata)."""
    return read_log(path)[1]


def figure(sensor: Path, estimates: list[Path], labels: list[str], title: str | None = None):
    """The figure (for plot() to save and the tests to inspect)."""
    import matplotlib
    matplotlib.use("Agg")

    meta, truth = read_log(sensor)
    ests = [read_csv(p) for p in estimates]
    return compose(meta, truth, ests, labels, title, rolling_radius(meta))


def plot(sensor: Path, estimates: list[Path], labels: list[str], out: Path,
         title: str | None = None) -> None:
    import matplotlib.pyplot as plt
    fig = figure(sensor, estimates, labels, title)
    fig.savefig(out, dpi=90)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sensor", type=Path, required=True, help="sensor log (truth columns optional)")
    ap.add_argument("--estimate", type=Path, action="append", required=True,
                    help="estimate log (repeat to overlay several)")
    ap.add_argument("--label", action="append", help="legend label per --estimate")
    ap.add_argument("--out", type=Path, required=True, help="PNG to write")
    ap.add_argument("--title", help="figure title (default: what the logs hold)")
    args = ap.parse_args(argv)
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
