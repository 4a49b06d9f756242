"""The fleet replay's report.html (rfe.fleet): one self-contained page, its plots embedded
as PNG (base64), readable offline and mailable as one file.

Drawn with matplotlib's Agg backend (no display needed on a build server): the distribution
of the logs' valid share, the histograms of the valid estimates per surface where the logs
have truth, and the summary table with the worst logs first.
"""
from __future__ import annotations

import base64
import html
import io
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

# columns of the report's table, in this order (those the summary has)
TABLE_COLUMNS = ("log", "error", "real", "steps", "valid_share", "frac_valid",
                 "consistency_valid", "rmse_valid", "sat_estimator", "sat_input", "bad_rows",
                 "gaps", "warnings")


def _png(fig: Any) -> str:
    """The figure as an <img> with its PNG inline."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=96, bbox_inches="tight")
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    return f'<img alt="" src="data:image/png;base64,{data}">'


def valid_share_plot(table: pd.DataFrame) -> str:
    """Histogram of the completed logs' valid share (0..1, 20 bins)."""
    import matplotlib.pyplot as plt
    logs = table[(table["log"] != "ALL") & (table["error"] == "")]
    fig, ax = plt.subplots(figsize=(6.0, 3.0))
    shares = logs["valid_share"].dropna() if "valid_share" in logs else []
    ax.hist(shares, bins=np.linspace(0.0, 1.0, 21), color="#4878a8",
            edgecolor="white")
    ax.set_xlabel("valid share (steps with all four wheels valid)")
    ax.set_ylabel("logs")
    ax.set_xlim(0.0, 1.0)
    img = _png(fig)
    plt.close(fig)
    return img


def surface_plot(hist: Mapping[str, np.ndarray], bins: np.ndarray) -> str:
    """One panel per surface (true mu): the valid estimates' histogram and the truth."""
    import matplotlib.pyplot as plt
    surfaces = sorted(hist, key=float)
    cols = min(3, len(surfaces))
    rows = math.ceil(len(surfaces) / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.4 * rows), squeeze=False)
    centres = 0.5 * (bins[:-1] + bins[1:])
    for ax, s in zip(axes.flat, surfaces):
        counts = np.asarray(hist[s])
        ax.bar(centres, counts, width=np.diff(bins), color="#6a9f58", edgecolor="white")
        ax.axvline(float(s), color="black", linestyle="--", linewidth=1.0)
        ax.set_title(f"true \u03bc \u2248 {s} ({int(counts.sum())} samples)", fontsize=9)
        ax.set_xlim(bins[0], bins[-1])
        ax.set_xlabel("estimated \u03bc", fontsize=8)
    for ax in list(axes.flat)[len(surfaces):]:
        ax.set_visible(False)
    fig.tight_layout()
    img = _png(fig)
    plt.close(fig)
    return img


def _cell(value: Any) -> str:
    if isinstance(value, float):
        return "" if math.isnan(value) else f"{value:.4g}"
    return html.escape(str(value))


def _table(df: pd.DataFrame) -> str:
    cols = [c for c in TABLE_COLUMNS if c in df.columns] + \
        [c for c in df.columns if c.startswith("status_")]
    head = "".join(f"<th>{html.escape(c)}</th>" for c in cols)
    body = []
    for _, r in df.iterrows():
        cls = ' class="failed"' if r.get("error") else ""
        body.append(f"<tr{cls}>" + "".join(f"<td>{_cell(r.get(c, ''))}</td>" for c in cols)
                    + "</tr>")
    return f"<table><thead><tr>{head}</tr></thead><tbody>{''.join(body)}</tbody></table>"


def write_report(path: Path, table: pd.DataFrame, worst: pd.DataFrame,
                 hist: Mapping[str, np.ndarray], bins: np.ndarray,
                 options: Mapping[str, Any]) -> None:
    """Writes report.html: the overall row, the plots, the logs worst first."""
    import matplotlib
    matplotlib.use("Agg")
    overall = table[table["log"] == "ALL"]
    n = len(table) - 1
    failed = int((table.loc[table["log"] != "ALL", "error"] != "").sum())
    opts = ", ".join(f"{k} = {v}" for k, v in options.items() if v not in (None, False)) \
        or "mu_replay's defaults"
    from .replay import STATUS_TEXT
    codes = sorted(int(c[len("status_"):]) for c in table.columns if c.startswith("status_"))
    legend = "; ".join(f"status_{k}: {html.escape(STATUS_TEXT.get(k, '?').rstrip('.'))}"
                       for k in codes)
    surfaces = surface_plot(hist, bins) if hist else \
        "<p>No log has truth columns (mu_fl..mu_rr): no histograms per surface.</p>"
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>rfe fleet replay</title>
<style>
body {{ font-family: sans-serif; margin: 1.5em; }}
table {{ border-collapse: collapse; font-size: 0.85em; }}
th, td {{ border: 1px solid #bbb; padding: 2px 6px; text-align: right; }}
td:first-child, td:nth-child(2) {{ text-align: left; }}
tr.failed td {{ background: #f6d5d5; }}
</style></head><body>
<h1>Fleet replay</h1>
<p>{n} logs, {failed} failed; options: {html.escape(opts)}.
Figures of the accuracy are mu_replay's (src/host/metrics.h, mean series); the overall row
pools the logs (docs/PYTHON.md "Fleet replay").</p>
<h2>Overall</h2>
{_table(overall)}
<h2>Valid share per log</h2>
{valid_share_plot(table)}
<h2>Estimated &mu; per surface (valid samples, every wheel, logs with truth)</h2>
{surfaces}
<h2>Logs, worst first</h2>
<p>Failed logs first, then by valid share ascending, then by RMSE when valid descending.
Steps per status of the friction estimator: {legend}.</p>
{_table(worst)}
</body></html>
"""
    path.write_text(page, encoding="utf-8")
