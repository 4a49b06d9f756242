"""Plots of estimates, as scripts/tools/plot_estimates.py draws them (that script draws with
this module's functions): one panel per wheel (fl, fr, rl, rr) with the true mu when the
sensor log has it, each estimate's mu, a +-2 sd band around the first estimate and a
hatched lane where an estimate is not valid; under them the manoeuvre (speed and steering,
accelerations). Matplotlib only: no part of it needs the compiled extension.
"""
from __future__ import annotations

import math
import os
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure

    Log = str | os.PathLike | pd.DataFrame

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


def steer_angle(meta: dict, sensor: dict) -> list[float] | None:
    """delta, or from a steering-wheel angle: swa / obs_steer_ratio (DATA.md); None when
    the log has neither (or swa without the ratio)."""
    if "delta" in sensor:
        return sensor["delta"]
    if "swa" in sensor and "obs_steer_ratio" in meta:
        ratio = float(meta["obs_steer_ratio"])
        return [a / ratio for a in sensor["swa"]]
    return None


def speed_of(meta: dict, sensor: dict, R: float) -> tuple[str, list[float]] | None:
    """(label, values) for the speed panel: the log's vx, else the wheels' mean
    circumferential speed with the rolling radius R (a production car logs no vx)."""
    if "vx" in sensor:
        return "vx", sensor["vx"]
    wheels = [sensor.get(f"omega_{w}") for w in WHEELS]
    if any(w is None for w in wheels):
        return None
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


def draw_manoeuvre(ax_v, ax_a, sensor: dict, meta: dict | None = None,
                   R: float = math.nan) -> None:
    """Speed and steering (left), accelerations (right): friction is observable only where
    the tyres work, i.e. where ax or ay is large. R: the rolling radius of a speed from the
    wheels (a log without vx)."""
    meta = meta or {}
    t = sensor.get("t", [])
    speed = speed_of(meta, sensor, R)
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


def compose(meta: dict, truth: dict, ests: list[dict], labels: list[str],
            title: str | None = None, R: float = math.nan) -> Figure:
    """The figure of a sensor log's columns (``truth``: name -> values in SI, with its
    metadata ``meta``) and of estimate logs' columns (``ests``), one label each: a panel
    per wheel (the true mu when the log has it, each estimate's mu, the first one's +-2 sd
    band, a hatched lane where an estimate is not valid) and the manoeuvre under them."""
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(13, 9), layout="constrained")
    grid = fig.add_gridspec(3, 2, height_ratios=(1, 1, 0.8))
    first = fig.add_subplot(grid[0, 0])
    mu_axes = [first] + [fig.add_subplot(grid[i // 2, i % 2], sharex=first, sharey=first)
                         for i in range(1, 4)]
    for ax, w in zip(mu_axes, WHEELS):
        draw_wheel(ax, w, truth, ests, labels)
    draw_manoeuvre(fig.add_subplot(grid[2, 0], sharex=first),
                   fig.add_subplot(grid[2, 1], sharex=first), truth, meta, R)
    # one legend for the four wheels: every entry any panel drew, once
    entries: dict[str, object] = {}
    for ax in mu_axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            entries.setdefault(lab, h)
    fig.legend(list(entries.values()), list(entries), loc="outside right upper", fontsize=8)
    fig.suptitle(title or default_title(truth))
    return fig


def _columns(log: Log) -> tuple[dict[str, str], dict[str, Any]]:
    """(metadata, name -> float array) of a DataFrame or a DATA.md CSV path; the columns that
    are not numbers are left out."""
    import numpy as np

    if not hasattr(log, "columns"):
        from .replay import read_log
        log = read_log(log)
    cols = {}
    for name in log.columns:
        try:
            cols[str(name)] = np.asarray(log[name], dtype=np.float64)
        except (TypeError, ValueError):
            continue
    return dict(log.attrs.get("meta", {}) or {}), cols


def plot_estimates(sensor: Log, estimates: Log | Sequence[Log],
                   labels: Sequence[str] | None = None, title: str | None = None,
                   out: str | os.PathLike | None = None) -> Figure:
    """The figure of scripts/tools/plot_estimates.py for a sensor log and estimates.

    Args:
        sensor: the sensor log, a path or a DataFrame (:func:`rfe.read_log`); its columns
            are drawn as they are, so a car logger's log in other units than SI (its
            unit_*/scale_* keys) is drawn in those units.
        estimates: one estimate log or a list of them, each a DataFrame (:func:`rfe.replay`)
            or a path.
        labels: one legend label per estimate (default: "estimate 1", ...).
        title: the figure's title (default: what the logs hold).
        out: when given, the figure is also saved there (90 dpi, as the script does).

    Returns:
        the matplotlib Figure (with a wheel speed but no vx, the speed uses the rolling
        radius R of the first estimate's metadata, the value its run used).
    """
    if not isinstance(estimates, (list, tuple)):
        estimates = [estimates]
    labels = list(labels) if labels is not None else \
        [f"estimate {k + 1}" for k in range(len(estimates))]
    if len(labels) != len(estimates):
        raise ValueError("plot_estimates: give one label per estimate")
    meta, truth = _columns(sensor)
    ests = [_columns(e) for e in estimates]
    R = math.nan
    for m in [e[0] for e in ests] + [meta]:
        try:
            R = float(m["R"])
            break
        except (KeyError, ValueError):
            continue
    fig = compose(meta, truth, [e[1] for e in ests], labels, title, R)
    if out is not None:
        fig.savefig(out, dpi=90)
    return fig
