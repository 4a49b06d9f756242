"""Markdown tables for a file (title and column legend) and for a console (width-bounded),
and the script-written regions of the docs pages (replace_region).

The demo's tables are 15 columns wide; a terminal line of 200+ characters wraps into
noise, so console_table() splits the columns into groups that fit, each group repeating
the key column(s) so every row stays identifiable.
"""
from __future__ import annotations

import re
import textwrap

CONSOLE_WIDTH = 120
_SEPARATOR = re.compile(r"^:?-+:?$")


def cells(line: str) -> list[str]:
    return [c.strip() for c in line.strip().strip("|").split("|")]


def markdown_doc(title: str, lines: list[str], legend: list[tuple[str, str]]) -> str:
    """A stand-alone markdown file: '# title', the table (and any lines after it), then one
    bullet per column saying what it holds."""
    out = [f"# {title}", "", *lines, "", "Columns:", ""]
    out += [f"- *{name}*: {text}" for name, text in legend]
    return "\n".join(out) + "\n"


def console_table(title: str, lines: list[str], width: int = CONSOLE_WIDTH,
                  keep: int = 1) -> list[str]:
    """The table as aligned plain text, no line longer than width: columns beyond the first
    `keep` go into as many groups as needed. Lines that are not table rows are wrapped."""
    rows = [cells(ln) for ln in lines if ln.startswith("|")]
    rows = [r for r in rows if not all(_SEPARATOR.match(c) for c in r)]
    out = [title, "=" * min(len(title), width)]
    if rows:
        n = max(len(r) for r in rows)
        rows = [r + [""] * (n - len(r)) for r in rows]
        widths = [max(len(r[i]) for r in rows) for i in range(n)]
        keep = min(keep, n)
        base = sum(widths[:keep]) + 2 * keep
        groups: list[list[int]] = []
        used = base
        for i in range(keep, n):
            if not groups or used + widths[i] + 2 > width:
                groups.append([])
                used = base
            groups[-1].append(i)
            used += widths[i] + 2
        for g, cols in enumerate(groups or [[]]):
            if g:
                out.append("")
            idx = list(range(keep)) + cols
            for k, r in enumerate(rows):
                out.append("  ".join(r[i].ljust(widths[i]) for i in idx).rstrip()[:width])
                if k == 0:
                    out.append("  ".join("-" * widths[i] for i in idx)[:width])
    for ln in lines:
        if not ln.startswith("|") and ln.strip():
            out += [""] + textwrap.wrap(ln, width)
    return out


def replace_region(page, begin: str, end: str, lines: list[str], who: str) -> None:
    """Replace the text between the markers begin ... end of a markdown page by lines; exit
    with a message naming the tool (who) when the page lacks the markers."""
    text = page.read_text()
    if begin not in text or end not in text:
        raise SystemExit(f"{who}: {page} has no {begin} ... {end} section")
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    page.write_text(head + begin + "\n" + "\n".join(lines) + "\n" + end + tail)
