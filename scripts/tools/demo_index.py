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


def write_index(out_dir: Path, tables: list[tuple[str, Path]],
                plots: list[tuple[str, Path]]) -> Path:
    """out_dir/index.md with a section of (title, file) links per kind; returns its path."""
    lines = ["# rfe demo", "", "Written by `scripts/tools/demo.py` (`make demo`); the estimate "
             "logs and metrics (`*.csv`, `*.json`) are beside it.", "", "## Tables", ""]
    lines += [link(t, p, out_dir) for t, p in tables] or ["(none)"]
    lines += ["", "## Plots", ""]
    lines += [link(t, p, out_dir) for t, p in plots] or ["(none: run without --no-plots)"]
    index = out_dir / INDEX
    index.write_text("\n".join(lines) + "\n")
    return index


def summary_line(out_dir: Path, index: Path, n_plots: int, n_tables: int) -> str:
    return (f"demo: {n_plots} plot{'s' * (n_plots != 1)} and {n_tables} "
            f"table{'s' * (n_tables != 1)} in {out_dir}/ (estimate logs and metrics beside "
            f"them); index: {index}")
