#!/usr/bin/env python3
"""MC/DC summary of `make mcdc`: the figure, per file, and the decisions not fully covered.

Inputs: the `llvm-cov export --summary-only` JSON (totals and per file: lines, branches,
MC/DC conditions) and the `llvm-cov show --show-mcdc` text (the decisions, their conditions
and which independence pairs were shown). Writes OUT/summary.md (the figure and a per-file
table) and OUT/gaps.md and OUT/gaps.json (every decision with an uncovered condition: file,
line, the source line, the conditions not independently shown). With --page FILE (alias
--readme, the former name) it replaces the block between `<!-- mcdc:begin -->` and
`<!-- mcdc:end -->` in FILE (`make mcdc-readme`: docs/EVIDENCE.md) by the figure and the
per-file table.

usage: evidence_mcdc.py --summary summary.json --show show.txt --out DIR [--page docs/EVIDENCE.md]
"""
from __future__ import annotations

import argparse
import json
import os
import re
import sys

FILE_RE = re.compile(r"^(/\S+\.[ch]):$")
LINE_RE = re.compile(r"^\s*(\d+)\|\s*([\d.kMG]*)\|(.*)$")
DEC_RE = re.compile(r"MC/DC Decision Region \((\d+):(\d+)\) to \((\d+):(\d+)\)")
COND_RE = re.compile(r"Condition (C\d+) --> \((\d+):(\d+)\)")
PAIR_RE = re.compile(r"(C\d+)-Pair: (.*)$")
PCT_RE = re.compile(r"MC/DC Coverage for Decision: ([\d.]+)%")


FUNC_RE = re.compile(r"^[A-Za-z_][\w \t\*]*?\b(\w+)\s*\(")
KEYWORDS = {"if", "for", "while", "switch", "return", "sizeof", "do", "else"}


def find_function(text_of, line):
    """The function whose definition (in column 0) precedes `line`; text_of(n) gives the
    source text of line n (1-based, '' when unknown). The name is the short one the source
    writes; a _f32/_f64 suffix, where a source spells the full name, is not part of it."""
    for n in range(line, 0, -1):
        s = text_of(n)
        if not s or s[0] in " \t#/*}{":
            continue
        m = FUNC_RE.match(s)
        if m and not s.rstrip().endswith(";"):
            name = m.group(1)
            if name not in KEYWORDS:
                return re.sub(r"_(f32|f64)$", "", name)
    return "?"


def rel(path, root):
    try:
        return os.path.relpath(path, root)
    except ValueError:
        return path


def parse_show(path, root):
    """Decisions with at least one condition not independently shown, per file."""
    gaps = []
    cur_file, src = None, {}
    dec = None
    with open(path, encoding="utf-8", errors="replace") as f:
        lines = f.read().split("\n")
    # first pass: source text per file and line
    for line in lines:
        m = FILE_RE.match(line)
        if m:
            cur_file = rel(m.group(1), root)
            src.setdefault(cur_file, {})
            continue
        m = LINE_RE.match(line)
        if m and cur_file:
            src[cur_file][int(m.group(1))] = m.group(3)
    cur_file = None
    seen = set()
    for line in lines:
        m = FILE_RE.match(line)
        if m:
            cur_file = rel(m.group(1), root)
            continue
        m = DEC_RE.search(line)
        if m:
            dec = {"file": cur_file, "line": int(m.group(1)), "col": int(m.group(2)),
                   "end_line": int(m.group(3)), "conditions": {}, "uncovered": []}
            continue
        if dec is None:
            continue
        m = COND_RE.search(line)
        if m:
            dec["conditions"][m.group(1)] = (int(m.group(2)), int(m.group(3)))
            continue
        m = PAIR_RE.search(line)
        if m and "not covered" in m.group(2):
            dec["uncovered"].append(m.group(1))
            continue
        m = PCT_RE.search(line)
        if m:
            dec["percent"] = float(m.group(1))
            if dec["uncovered"]:
                text = src.get(dec["file"], {}).get(dec["line"], "").strip()
                dec["text"] = text
                fl_ = src.get(dec["file"], {})
                dec["function"] = find_function(lambda n: fl_.get(n, ""), dec["line"])
                conds = []
                fl = src.get(dec["file"], {})
                for c in dec["uncovered"]:
                    ln, col = dec["conditions"].get(c, (0, 0))
                    conds.append({"cond": c, "line": ln, "col": col,
                                  "at": fl.get(ln, "")[max(col - 1, 0):max(col - 1, 0) + 40].strip()})
                dec["uncovered"] = conds
                key = (dec["file"], dec["line"], dec["col"], tuple(c["cond"] for c in conds))
                if key not in seen:   # the same decision of the f32 and f64 builds
                    seen.add(key)
                    gaps.append(dec)
            dec = None
    return gaps


def figure(totals):
    m = totals.get("mcdc", {})
    return m.get("covered", 0), m.get("count", 0), m.get("percent", 0.0)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--summary", required=True)
    ap.add_argument("--show", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--root", default=".")
    ap.add_argument("--tool", default="llvm-cov")
    ap.add_argument("--page", "--readme", dest="page", default=None)
    a = ap.parse_args(argv)
    root = os.path.abspath(a.root)
    data = json.load(open(a.summary, encoding="utf-8"))["data"][0]
    cov, cnt, pct = figure(data["totals"])
    files = []
    for fe in data["files"]:
        s = fe["summary"]
        files.append((rel(fe["filename"], root), s["lines"], s["branches"], s.get("mcdc", {})))
    files.sort()
    gaps = parse_show(a.show, root)
    lt = data["totals"]["lines"]
    bt = data["totals"]["branches"]
    head = (f"**MC/DC over `src/`: {pct:.1f} %** ({cov} of {cnt} conditions independently shown; "
            f"clang `-fcoverage-mcdc`, {a.tool}; float, double and q31 builds with the unit, golden, "
            f"host and CLI tests). Lines {lt['percent']:.1f} %, branches {bt['percent']:.1f} % "
            f"(clang's count). {len(gaps)} decisions with a condition not independently shown "
            f"(`build/mcdc/gaps.md`).")
    failed_path = os.path.join(a.out, "failed.txt")
    if os.path.isfile(failed_path) and os.path.getsize(failed_path):
        failed = open(failed_path, encoding="utf-8").read().split()
        head += (f" **{len(failed)} test binaries failed in the MC/DC build** ({', '.join(failed)}); "
                 "the figure counts what the rest executed.")
    table = ["| file | lines | branches | MC/DC conditions | MC/DC |", "|---|---|---|---|---|"]
    for name, l, b, m in files:
        mc = f"{m.get('covered', 0)}/{m.get('count', 0)}"
        mp = f"{m['percent']:.1f} %" if m.get("count") else "–"
        table.append(f"| `{name}` | {l['percent']:.1f} % | {b['percent']:.1f} % | {mc} | {mp} |")
    os.makedirs(a.out, exist_ok=True)
    with open(os.path.join(a.out, "summary.md"), "w", encoding="utf-8") as f:
        f.write("# MC/DC (make mcdc)\n\n" + head + "\n\n" + "\n".join(table) + "\n")
    with open(os.path.join(a.out, "gaps.json"), "w", encoding="utf-8") as f:
        json.dump(gaps, f, indent=1)
    g = ["# MC/DC gaps", "", "Decisions in `src/` with at least one condition whose independent effect "
         "no test showed (llvm-cov `show --show-mcdc`). The float and double builds of one decision "
         "are listed once when both miss the same condition.", "",
         "| file | line | decision | conditions not shown |", "|---|---|---|---|"]
    for d in gaps:
        cs = ", ".join(f"{c['cond']} `{c['at']}`" for c in d["uncovered"])
        g.append(f"| `{d['file']}` | {d['line']} | `{d['text'][:90]}` | {cs} |")
    with open(os.path.join(a.out, "gaps.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(g) + "\n")
    print(f"mcdc: {pct:.1f} % of {cnt} conditions ({cov} independently shown); "
          f"{len(gaps)} decisions with gaps")
    if a.page:
        text = open(a.page, encoding="utf-8").read()
        b, e = "<!-- mcdc:begin -->", "<!-- mcdc:end -->"
        if b not in text or e not in text:
            print(f"{a.page}: no {b} … {e} block", file=sys.stderr)
            return 1
        pre, rest = text.split(b, 1)
        _, post = rest.split(e, 1)
        with open(a.page, "w", encoding="utf-8") as f:
            f.write(pre + b + "\n" + head + "\n\n" + "\n".join(table) + "\n" + e + post)
        print(f"mcdc: figure written to {a.page}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
