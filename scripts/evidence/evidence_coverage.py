#!/usr/bin/env python3
"""Every line of src/ left uncovered by the coverage run is tested or justified.

Reads the Cobertura XML of `make coverage` (gcovr) and the justification table of
docs/COVERAGE_JUSTIFICATION.md, rows

    | file | function | marker | kind | justification |

where `file` is the source path (src/...), `function` the enclosing function without the
_f32/_f64 suffix (or `*` for any), `marker` a piece of the source line in backticks (a
grep-able substring of the line as written, whitespace-trimmed), `kind` `line` (a line gcov
saw not executed), `mcdc` (a decision whose conditions were not all shown independent, the
marker on the decision's first line) or `line, mcdc`. A row covers every such line/decision
in that function of that file whose text contains the marker, so it survives edits that only
move lines; when the code on the line changes, the row must be revisited.

Fails (exit 1), listing them, when an uncovered line (or, with --mcdc, an MC/DC gap) has no
row. Rows that match nothing are reported as stale (a warning: the code was covered or
changed). Writes --out (markdown): each uncovered line / gap with its justification.

usage: evidence_coverage.py --cobertura build/coverage/coverage.xml
           --justifications docs/COVERAGE_JUSTIFICATION.md [--mcdc build/mcdc/show.txt]
           [--out build/coverage/justified.md]
"""
from __future__ import annotations

import argparse
import os
import re
import sys
import xml.etree.ElementTree as ET

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)
import evidence_mcdc  # noqa: E402  (same folder)

ROW_RE = re.compile(r"^\|\s*`?(src/[^|`]+?)`?\s*\|\s*`?([^|`]+?)`?\s*\|\s*`(.+?)`\s*\|\s*([a-z, ]+?)\s*\|(.*)\|\s*$")


def strip_suffix(name):
    return re.sub(r"_(f32|f64)$", "", name)


class Sources:
    def __init__(self, root):
        self.root = root
        self.cache = {}

    def lines(self, rel):
        if rel not in self.cache:
            try:
                with open(os.path.join(self.root, rel), encoding="utf-8", errors="replace") as f:
                    self.cache[rel] = f.read().split("\n")
            except OSError:
                self.cache[rel] = []
        return self.cache[rel]

    def text(self, rel, line):
        ls = self.lines(rel)
        return ls[line - 1].strip() if 0 < line <= len(ls) else ""

    def function(self, rel, line):
        """The function whose definition precedes `line` (definitions start in column 0)."""
        ls = self.lines(rel)
        return evidence_mcdc.find_function(lambda n: ls[n - 1] if 0 < n <= len(ls) else "", line)


def parse_rows(path):
    rows = []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            m = ROW_RE.match(line.rstrip("\n"))
            if not m:
                continue
            kinds = {k.strip() for k in m.group(4).split(",") if k.strip()}
            rows.append({"file": m.group(1).strip(), "function": m.group(2).strip(),
                         "marker": m.group(3).strip(), "kinds": kinds,
                         "why": m.group(5).strip(), "line": n, "used": 0})
    return rows


def uncovered_lines(cobertura, root):
    """(file, line, note) of every source line of src/ no build executed, and of the first line
    of every function variant (e.g. the _f32 twin) never called although another build of the
    same lines ran. gcovr lists a line once per function variant that contains it; a line
    counts as executed when any variant executed it."""
    out = []
    tree = ET.parse(cobertura).getroot()
    for cls in tree.iter("class"):
        fn = cls.get("filename", "")
        if not fn.startswith("src/"):
            continue
        hits = {}
        lines = cls.find("lines")
        for ln in (lines.iter("line") if lines is not None else []):
            n = int(ln.get("number"))
            hits[n] = max(hits.get(n, 0), int(ln.get("hits", "0")))
        for n in sorted(hits):
            if hits[n] == 0:
                out.append((fn, n, ""))
        methods = cls.find("methods")
        for m in (methods.iter("method") if methods is not None else []):
            ml = [(int(l.get("number")), int(l.get("hits", "0"))) for l in m.iter("line")]
            if ml and all(h == 0 for _, h in ml) and any(hits.get(n, 0) > 0 for n, _ in ml):
                out.append((fn, min(n for n, _ in ml), f"function {m.get('name')} never called"))
    return sorted(out)


def match(rows, kind, rel, func, text):
    for r in rows:
        if kind in r["kinds"] and r["file"] == rel and r["function"] in ("*", func) \
                and r["marker"] in text:
            r["used"] += 1
            return r
    return None


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--cobertura", default=None, help="gcovr Cobertura XML (omit: MC/DC only)")
    ap.add_argument("--justifications", required=True)
    ap.add_argument("--mcdc", default=None, help="llvm-cov show --show-mcdc text output")
    ap.add_argument("--out", default=None)
    ap.add_argument("--root", default=".")
    a = ap.parse_args(argv)
    root = os.path.abspath(a.root)
    src = Sources(root)
    rows = parse_rows(a.justifications)
    report, missing = [], []
    for rel, n, note in (uncovered_lines(a.cobertura, root) if a.cobertura else []):
        text, func = src.text(rel, n), src.function(rel, n)
        r = match(rows, "line", rel, func, text)
        report.append(("line", rel, n, func, text + (f"  [{note}]" if note else ""), r))
        if r is None:
            missing.append(f"{rel}:{n} ({func}): " + (note + f" `{text}`" if note else f"uncovered line `{text}`"))
    gaps = []
    if a.mcdc:
        gaps = evidence_mcdc.parse_show(a.mcdc, root)
        for d in gaps:
            text, func = d["text"], d["function"]  # as llvm-cov showed the source
            r = match(rows, "mcdc", d["file"], func, text)
            conds = ", ".join(f"{c['cond']} {c['at']}" for c in d["uncovered"])
            report.append(("mcdc", d["file"], d["line"], func, f"{text}  [{conds}]", r))
            if r is None:
                missing.append(f"{d['file']}:{d['line']} ({func}): MC/DC gap `{text}` — {conds}")
    checked = ({"line"} if a.cobertura else set()) | ({"mcdc"} if a.mcdc else set())
    stale = [r for r in rows if r["used"] == 0 and (r["kinds"] & checked)]
    if a.out:
        os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
        md = ["# Uncovered lines and MC/DC gaps, with their justification", "",
              "Generated by `scripts/evidence/evidence_coverage.py` from "
              + " and ".join(f"`{x}`" for x in (a.cobertura, a.mcdc) if x) +
              f" against `{a.justifications}`.", "",
              f"{sum(1 for x in report if x[0] == 'line')} uncovered lines, {len(gaps)} MC/DC gaps; "
              f"{len(missing)} without justification; {len(stale)} stale justification rows.", "",
              "| kind | where | function | code | justification |", "|---|---|---|---|---|"]
        for kind, rel, n, func, text, r in report:
            why = r["why"] if r else "**NOT JUSTIFIED**"
            md.append(f"| {kind} | `{rel}:{n}` | {func} | `{text[:100]}` | {why} |")
        if stale:
            md += ["", "Stale rows (match nothing):", ""] + \
                  [f"- {a.justifications}:{r['line']}: {r['file']} {r['function']} `{r['marker']}`" for r in stale]
        with open(a.out, "w", encoding="utf-8") as f:
            f.write("\n".join(md) + "\n")
    for r in stale:
        print(f"coverage-justify: warning: {a.justifications}:{r['line']}: row matches nothing "
              f"({r['file']} {r['function']} `{r['marker']}`)")
    n_lines = sum(1 for x in report if x[0] == "line")
    if missing:
        for m in missing:
            print(f"coverage-justify: NOT JUSTIFIED: {m}")
        print(f"coverage-justify: {len(missing)} uncovered item(s) without a row in {a.justifications}: "
              "test them or add a row (file | function | `marker` | kind | justification)")
        return 1
    print("coverage-justify: all " +
          " and ".join(x for x in ((f"{n_lines} uncovered lines" if a.cobertura else ""),
                                   (f"{len(gaps)} MC/DC gaps" if a.mcdc else "")) if x) +
          f" of src/ are justified in {a.justifications}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
