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
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # scripts/: reference
from reference import log_units, params  # noqa: E402  (DATA.md's column rules, R's default)

WHEELS = ("fl", "fr", "rl", "rr")
# (colour, line style, marker, width) per estimate. Estimates often coincide (the paper's
# SCKF and CKF agree to 1e-5), so each differs in colour and dash, the second is drawn wide
# under the others and the later ones carry sparse markers: a line hidden by another still
# shows.
STYLES = (("tab:blue", "-", None, 1.3), ("tab:orange", "-", None, 2.8),
          ("tab:green", "--", "o", 1.1), ("tab:red", "-.", "x", 1.1))
MARKS_PER_LINE = 12
# Smallest y ranges of the manoeuvre panel: sensor noise on a steady run (0.05 m/s, 0.06 deg,
# 0.05 m/s^2) then looks flat instead of filling the panel like a manoeuvre.
DELTA_SPAN_MIN_DEG = 2.0
ACC_SPAN_MIN = 2.0   # m/s^2, either side of zero
VX_SPAN_MIN = 5.0    # m/s, around the mean
LANE = 0.04  # height of one estimate's not-valid lane, as a fraction of the panel


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


def steer_angle(meta: dict, sensor: dict) -> list[float] | None:
    """delta, or from a steering-wheel angle: swa / obs_steer_ratio (DATA.md); None when
    the log has neither (or swa without the ratio)."""
    if "delta" in sensor:
        return sensor["delta"]
    if "swa" in sensor and "obs_steer_ratio" in meta:
        ratio = float(meta["obs_steer_ratio"])
        return [a / ratio for a in sensor["swa"]]
    return None


def speed_of(meta: dict, sensor: dict) -> tuple[str, list[float]] | None:
    """(label, values) for the speed panel: the log's vx, else the wheels' mean
    circumferential speed (a production car logs no vx)."""
    if "vx" in sensor:
        return "vx", sensor["vx"]
    wheels = [sensor.get(f"omega_{w}") for w in WHEELS]
    if any(w is None for w in wheels):
        return None
    R = rolling_radius(meta)
    return "wheels ω̄·R", [R * sum(ws) / len(ws) for ws in zip(*wheels)]


def has_truth(sensor: dict) -> bool:
    return all(f"mu_{w}" in sensor for w in WHEELS)


def default_title(sensor: dict) -> str:
    """Say only what is drawn: without truth columns there is nothing to compare against."""
    return "estimated vs true friction" if has_truth(sensor) else \
        "estimated friction (the sensor log has no truth)"


def shade_not_valid(ax, est: dict, w: str, k: int, color: str, label: str) -> None:
    """Estimate k's not-valid samples of wheel w as a hatched lane (lane k from the bottom):
    hatched and per estimate so it reads apart from the solid sd band and from the others."""
    if f"valid_{w}" not in est:
        return
    invalid = [v == 0 for v in est[f"valid_{w}"]]
    if not any(invalid):
        return
    from matplotlib.colors import to_rgba
    ax.fill_between(est["t"], k * LANE, (k + 1) * LANE, where=invalid, step="mid",
                    transform=ax.get_xaxis_transform(), facecolor=to_rgba(color, 0.2),
                    edgecolor=color, hatch="////", lw=0, label=f"{label} not valid")


def draw_wheel(ax, w: str, truth: dict, ests: list[dict], labels: list[str]) -> None:
    if f"mu_{w}" in truth:
        ax.plot(truth["t"], truth[f"mu_{w}"], color="black", lw=1.5, label="true μ", zorder=10)
    for k, (est, label) in enumerate(zip(ests, labels)):
        color, ls, marker, lw = STYLES[k % len(STYLES)]
        n = len(est["t"])
        every = max(n // MARKS_PER_LINE, 1)
        # markers of different estimates offset from each other, so they do not stack
        ax.plot(est["t"], est[f"mu_{w}"], color=color, ls=ls, lw=lw, marker=marker, ms=4,
                markevery=(k * every // len(STYLES), every), label=f"{label} μ̂", zorder=3 + k)
        if k == 0 and f"sd_{w}" in est:
            lo = [m - 2 * s for m, s in zip(est[f"mu_{w}"], est[f"sd_{w}"])]
            hi = [m + 2 * s for m, s in zip(est[f"mu_{w}"], est[f"sd_{w}"])]
            ax.fill_between(est["t"], lo, hi, color=color, alpha=0.15, lw=0,
                            label=f"{label} ±2 sd", zorder=1)
        shade_not_valid(ax, est, w, k, color, label)
    ax.set_title(w)
    ax.set_ylim(0.0, 1.3)
    ax.set_ylabel("μ")
    ax.grid(alpha=0.3)


def finite(values) -> list[float]:
    return [v for v in values if math.isfinite(v)]


def draw_manoeuvre(ax_v, ax_a, sensor: dict, meta: dict | None = None) -> None:
    """Speed and steering (left), accelerations (right): friction is observable only where
    the tyres work, i.e. where ax or ay is large."""
    meta = meta or {}
    t = sensor.get("t", [])
    speed = speed_of(meta, sensor)
    if speed:
        ax_v.plot(t, speed[1], color="black", lw=1.2, label=speed[0])
        ax_v.set_ylabel(f"{speed[0]} [m/s]")
        seen = finite(speed[1])
        if seen and max(seen) - min(seen) < VX_SPAN_MIN:
            mid = (min(seen) + max(seen)) / 2
            ax_v.set_ylim(mid - VX_SPAN_MIN / 2, mid + VX_SPAN_MIN / 2)
    else:
        ax_v.set_ylabel("vx [m/s]")
    delta = steer_angle(meta, sensor)
    if delta is not None:
        ax_d = ax_v.twinx()
        deg = [math.degrees(d) for d in delta]
        ax_d.plot(t, deg, color="tab:purple", lw=0.8, alpha=0.7, label="δ")
        span = max(max((abs(d) for d in finite(deg)), default=0.0) * 1.1, DELTA_SPAN_MIN_DEG)
        ax_d.set_ylim(-span, span)
        ax_d.set_ylabel("δ [deg]")
        h1, l1 = ax_v.get_legend_handles_labels()
        h2, l2 = ax_d.get_legend_handles_labels()
        ax_v.legend(h1 + h2, l1 + l2, loc="upper right", fontsize=8)
    ax_v.set_title("manoeuvre: speed and steering")
    for name, color in (("ax", "tab:brown"), ("ay", "tab:cyan")):
        if name in sensor:
            ax_a.plot(t, sensor[name], color=color, lw=1.0, label=name)
    ax_a.set_ylabel("a [m/s²]")
    lo, hi = ax_a.get_ylim()
    ax_a.set_ylim(min(lo, -ACC_SPAN_MIN), max(hi, ACC_SPAN_MIN))
    ax_a.set_title("manoeuvre: accelerations")
    if ax_a.lines:
        ax_a.legend(loc="upper right", fontsize=8)
    for ax in (ax_v, ax_a):
        ax.grid(alpha=0.3)
        ax.set_xlabel("t [s]")


def figure(sensor: Path, estimates: list[Path], labels: list[str], title: str | None = None):
    """The figure (for plot() to save and the tests to inspect)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    meta, truth = read_log(sensor)
    ests = [read_csv(p) for p in estimates]
    fig = plt.figure(figsize=(13, 9), layout="constrained")
    grid = fig.add_gridspec(3, 2, height_ratios=(1, 1, 0.8))
    first = fig.add_subplot(grid[0, 0])
    mu_axes = [first] + [fig.add_subplot(grid[i // 2, i % 2], sharex=first, sharey=first)
                         for i in range(1, 4)]
    for ax, w in zip(mu_axes, WHEELS):
        draw_wheel(ax, w, truth, ests, labels)
    draw_manoeuvre(fig.add_subplot(grid[2, 0], sharex=first),
                   fig.add_subplot(grid[2, 1], sharex=first), truth, meta)
    # one legend for the four wheels: every entry any panel drew, once
    entries: dict[str, object] = {}
    for ax in mu_axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(lab, h)
    fig.legend(list(entries.values()), list(entries), loc="outside right upper", fontsize=8)
    fig.suptitle(title or default_title(truth))
    return fig


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
