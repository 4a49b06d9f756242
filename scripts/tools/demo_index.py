"""The demo's index page: one markdown file linking every table and plot a run wrote.

Links are relative to the index, so build/demo/ can be moved or attached whole. Only the
files of this run are listed (a --no-plots run leaves an earlier run's PNGs behind).
"""
from __future__ import annotations

import os
from pathlib import Path

INDEX = "index.md"


def link(title: str, path: Path, base: Path) -> str:
    rel = Path(os.path.relpath(path, base)).as_posix()
    return f"- [{title}](<{rel}>)"


def by_scenario(plots: list[tuple[str, Path]]) -> list[tuple[str, list[tuple[str, Path]]]]:
    """The plots grouped by their scenario (a title's text before its first ':'), scenarios
    in name order, each group's Magic Formula truth plot first (the default preset's
    realistic case) and the paper-truth (Dugoff) plots beside it, in the order given."""
    groups: dict[str, list[tuple[str, Path]]] = {}
    for title, path in plots:
        groups.setdefault(title.split(":", 1)[0], []).append((title, path))
    return [(name, sorted(group, key=lambda tp: "Magic Formula" not in tp[0]))
            for name, group in sorted(groups.items())]


def write_index(out_dir: Path, tables: list[tuple[str, Path]],
                plots: list[tuple[str, Path]]) -> Path:
    """out_dir/index.md with a section of (title, file) links per kind, the plots grouped by
    scenario (by_scenario); returns its path."""
    lines = ["# rfe demo", "", "Written by `scripts/tools/demo.py` (`make demo`); the estimate "
             "logs and metrics (`*.csv`, `*.json`) are beside it.", "", "## Tables", ""]
    lines += [link(t, p, out_dir) for t, p in tables] or ["(none)"]
    lines += ["", "## Plots", ""]
    if not plots:
        lines.append("(none: run without --no-plots)")
    for scenario, group in by_scenario(plots):
        lines += [f"### {scenario}", ""] + [link(t, p, out_dir) for t, p in group] + [""]
    index = out_dir / INDEX
    index.write_text("\n".join(lines) + "\n")
    return index


def summary_line(out_dir: Path, index: Path, n_plots: int, n_tables: int) -> str:
    return (f"demo: {n_plots} plot{'s' * (n_plots != 1)} and {n_tables} "
            f"table{'s' * (n_tables != 1)} in {out_dir}/ (estimate logs and metrics beside "
            f"them); index: {index}")
