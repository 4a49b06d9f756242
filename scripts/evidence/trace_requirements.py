#!/usr/bin/env python3
"""Requirements traceability: docs/REQUIREMENTS.md -> tests -> result of the last run.

Reads
  * the requirements: every table row `| REQ-<AREA>-<NNN> | text | source | verification |`
    of docs/REQUIREMENTS.md;
  * the tests and the requirements each names: the cmocka tests registered in
    test/**/test_*.c, host included (cmocka_unit_test*(name)), the CLI script
    test/host/test_cli.sh (one test case, `test_cli`) and the pytest tests scripts/**/test_*.py; a test's IDs are the
    `REQ-...` tokens in the comment block directly above its definition (REQUIREMENTS.md,
    "Conventions");
  * the results of the last run: the JUnit XML files under build/results/<tree>/ written by
    `make test-c` (cmocka, CMOCKA_MESSAGE_OUTPUT=XML) and `make test-py` (pytest --junitxml).
    It never runs a test.

Writes the matrix as markdown, HTML and JSON, prints a summary and exits 1 when
  * a requirement verified by `test` has no passing test (none tagged, none run, or one failed),
  * a test cites an unknown requirement, or a requirement ID is defined twice,
  * a result file cannot be read.
A requirement verified by `make <target>` needs that target to be defined (Makefile or
mk/*.mk); a target not defined yet is reported as pending (a warning). Untagged tests are
listed and counted, never an error.

usage: trace_requirements.py [--root .] [--results build/results] [--out build/trace]
"""
from __future__ import annotations

import argparse
import ast
import glob
import html
import json
import os
import re
import sys
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

REQ_RE = re.compile(r"REQ-[A-Z0-9]+-\d{3}")
ROW_RE = re.compile(r"^\|\s*(REQ-[A-Z0-9]+-\d{3})\s*\|(.*)\|\s*$")
C_REG_RE = re.compile(r"cmocka_unit_test(?:_setup|_teardown|_setup_teardown|_prestate)?\s*\(\s*(\w+)")
# The trees of make test-c (f32, f64, q31, host, cli) and make test-py (py); the sanitizer,
# coverage and MC/DC runs write theirs beside them (asan-*, cov-*, mcdc-*), not read by default.
DEFAULT_TREES = ("f32", "f64", "q31", "host", "cli", "py")


@dataclass
class Requirement:
    rid: str
    text: str
    source: str
    verification: str
    by_test: bool = False
    targets: list = field(default_factory=list)
    withdrawn: bool = False


@dataclass
class Test:
    file: str          # path relative to the root
    name: str
    reqs: list
    line: int
    runs: list = field(default_factory=list)   # (tree, result, message)

    @property
    def key(self):
        return f"{self.file}::{self.name}"

    @property
    def result(self):
        res = [r for _, r, _ in self.runs]
        if not res:
            return "NOT RUN"
        if any(r == "FAIL" for r in res):
            return "FAIL"
        if any(r == "PASS" for r in res):
            return "PASS"
        return "SKIP"


def parse_requirements(path):
    reqs, errors = {}, []
    with open(path, encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            m = ROW_RE.match(line.rstrip("\n"))
            if not m:
                continue
            cells = [c.strip() for c in m.group(2).split("|")]
            if len(cells) < 3:
                errors.append(f"{path}:{n}: {m.group(1)}: expected | ID | text | source | verification |")
                continue
            text, source, ver = " | ".join(cells[:-2]), cells[-2], cells[-1]
            rid = m.group(1)
            if rid in reqs:
                errors.append(f"{path}:{n}: {rid} defined twice")
                continue
            r = Requirement(rid, text, source, ver)
            for item in (s.strip() for s in ver.split(",")):
                if item == "test":
                    r.by_test = True
                elif item.startswith("make "):
                    r.targets.append(item[5:].strip())
                elif item == "withdrawn":
                    r.withdrawn = True
                else:
                    errors.append(f"{path}:{n}: {rid}: unknown verification '{item}' "
                                  "(test, make <target>, withdrawn)")
            reqs[rid] = r
    return reqs, errors


def comment_block_above(lines, i, py):
    """The IDs in the contiguous comment block directly above line i (0-based)."""
    j = i
    if py:
        while j > 0 and lines[j - 1].strip().startswith("@"):
            j -= 1
    ids = []
    while j > 0:
        s = lines[j - 1].strip()
        is_comment = (s.startswith("#") if py else
                      (s.startswith(("/*", "*", "//")) or s.endswith("*/")))
        if not s or not is_comment:
            break
        ids = REQ_RE.findall(s) + ids
        j -= 1
    return ids


def collect_c_tests(root, rel):
    lines = open(os.path.join(root, rel), encoding="utf-8", errors="replace").read().split("\n")
    text = "\n".join(lines)
    names, tests = [], []
    for m in C_REG_RE.finditer(text):
        if m.group(1) not in names:
            names.append(m.group(1))
    for name in names:
        pat = re.compile(r"^\s*(?:static\s+)?void\s+" + re.escape(name) + r"\s*\(")
        idx = [i for i, l in enumerate(lines) if pat.match(l) and not l.rstrip().endswith(";")]
        if not idx:
            tests.append(Test(rel, name, [], 0))
            continue
        i = idx[0]
        tests.append(Test(rel, name, comment_block_above(lines, i, False), i + 1))
    return tests


def collect_py_tests(root, rel):
    """pytest functions (module level or in a class) found by parsing the file, so that text
    that only looks like a test (in a string) is not taken for one."""
    text = open(os.path.join(root, rel), encoding="utf-8").read()
    lines = text.split("\n")
    tests = []
    for node in ast.walk(ast.parse(text, filename=rel)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.name.startswith("test_"):
            first = min([node.lineno] + [d.lineno for d in node.decorator_list])
            tests.append(Test(rel, node.name, comment_block_above(lines, first - 1, True), node.lineno))
    tests.sort(key=lambda t: t.line)
    return tests


def collect_sh_test(root, rel):
    ids = []
    with open(os.path.join(root, rel), encoding="utf-8") as f:
        for n, line in enumerate(f, 1):
            if n == 1 and line.startswith("#!"):
                continue
            if not line.startswith("#"):
                break
            ids += REQ_RE.findall(line)
    return [Test(rel, "test_cli", ids, 1)]


# Folders of test/ that hold no cmocka test programs (harnesses, fixtures, data, helpers).
NOT_TESTS = ("test/fuzz/", "test/soak/", "test/structural/", "test/nofloat/", "test/support/",
             "test/vectors/")


def c_test_files(root):
    """The cmocka test programs: test/**/test_*.c outside NOT_TESTS."""
    return sorted(rel for rel in glob.glob("test/**/test_*.c", root_dir=root, recursive=True)
                  if not rel.startswith(NOT_TESTS))


def collect_tests(root):
    tests = []
    for rel in c_test_files(root):
        tests += collect_c_tests(root, rel)
    if os.path.isfile(os.path.join(root, "test/host/test_cli.sh")):
        tests += collect_sh_test(root, "test/host/test_cli.sh")
    for rel in sorted(glob.glob("scripts/**/test_*.py", root_dir=root, recursive=True)):
        tests += collect_py_tests(root, rel)
    return tests


def case_result(tc):
    for tag in ("failure", "error"):
        e = tc.find(tag)
        if e is not None:
            msg = (e.get("message") or "") + ("\n" + e.text if e.text else "")
            return "FAIL", msg.strip()
    if tc.find("skipped") is not None:
        return "SKIP", ""
    return "PASS", ""


def attach_results(root, results_dir, tests, trees):
    """Adds (tree, result, message) to every test found in the XML files. Returns
    (errors, unmatched result cases, files read)."""
    errors, unmatched, files = [], [], []
    by_c = {}
    by_py = {}
    c_file = {}                 # stem -> test program (stems are unique across test/)
    for t in tests:
        stem = os.path.splitext(os.path.basename(t.file))[0]
        if t.file.endswith(".py"):
            by_py.setdefault((stem, t.name), t)
        else:
            by_c.setdefault((t.file, t.name), t)
            c_file.setdefault(stem, t.file)
    for path in sorted(glob.glob(os.path.join(results_dir, "*", "*.xml"))):
        tree = os.path.basename(os.path.dirname(path))
        if tree not in trees:
            continue
        files.append(os.path.relpath(path, root))
        try:
            xroot = ET.parse(path).getroot()
        except (ET.ParseError, OSError) as e:
            errors.append(f"{path}: not readable JUnit XML ({e})")
            continue
        stem = os.path.splitext(os.path.basename(path))[0]
        for tc in xroot.iter("testcase"):
            name = tc.get("name", "")
            res, msg = case_result(tc)
            if tree == "py":
                mod = (tc.get("classname") or "").split(".")
                mstem = next((p for p in reversed(mod) if p.startswith("test_")), "")
                t = by_py.get((mstem, name.split("[")[0]))
            elif tree == "cli":
                t = by_c.get(("test/host/test_cli.sh", name))
            else:
                src = c_file.get(stem, f"test/{stem}.c")
                t = by_c.get((src, name))
            if t is None:
                unmatched.append(f"{os.path.relpath(path, root)}: {name}")
                continue
            t.runs.append((tree, res, msg))
    return errors, unmatched, files


def defined_targets(root):
    targets = set()
    for mk in [os.path.join(root, "Makefile")] + sorted(glob.glob(os.path.join(root, "mk", "*.mk"))):
        if not os.path.isfile(mk):
            continue
        for line in open(mk, encoding="utf-8"):
            m = re.match(r"^([A-Za-z0-9_.%/ -]+?)\s*::?(?!=)", line)
            if m and not line.startswith(("\t", "#")):
                targets.update(m.group(1).split())
    return targets


def build(root, results_dir, trees=DEFAULT_TREES):
    reqs, errors = parse_requirements(os.path.join(root, "docs/REQUIREMENTS.md"))
    tests = collect_tests(root)
    xml_errors, unmatched, files = attach_results(root, results_dir, tests, trees)
    errors += xml_errors
    warnings = []
    if not files:
        errors.append(f"no JUnit XML under {os.path.relpath(results_dir, root)}/*/: run make test-c test-py first")
    for t in tests:
        for rid in t.reqs:
            if rid not in reqs:
                errors.append(f"{t.file}:{t.line}: {t.name} cites unknown requirement {rid}")
            elif reqs[rid].withdrawn:
                errors.append(f"{t.file}:{t.line}: {t.name} cites withdrawn requirement {rid}")
        if t.reqs and not t.runs:
            warnings.append(f"{t.file}: {t.name} is tagged but has no result in the last run")
    targets = defined_targets(root)
    rows = []
    for rid, r in reqs.items():
        linked = [t for t in tests if rid in t.reqs]
        passing = [t for t in linked if t.result == "PASS"]
        failing = [t for t in linked if t.result == "FAIL"]
        tstat = []
        for tg in r.targets:
            tstat.append((tg, tg.split()[0] in targets))
        if r.withdrawn:
            status = "WITHDRAWN"
        elif r.by_test and (failing or not passing):
            status = "FAIL"
            why = ("a linked test failed" if failing else
                   "no linked test ran and passed" if linked else "no test names it")
            errors.append(f"{rid}: {why}")
        elif r.by_test:
            status = "PASS"
        elif tstat and all(ok for _, ok in tstat):
            status = "BY TARGET"
        else:
            status = "PENDING"
        for tg, ok in tstat:
            if not ok:
                warnings.append(f"{rid}: verifying target 'make {tg}' is not defined (yet)")
        if failing and not r.by_test:
            errors.append(f"{rid}: a linked test failed")
        rows.append({"id": rid, "text": r.text, "source": r.source, "verification": r.verification,
                     "status": status, "targets": [{"target": tg, "defined": ok} for tg, ok in tstat],
                     "tests": [{"test": t.key, "result": t.result,
                                "runs": [f"{tr}:{res}" for tr, res, _ in t.runs]} for t in linked]})
    return reqs, tests, rows, errors, warnings, unmatched, files


def write_outputs(out, tests, rows, errors, warnings, unmatched, files):
    os.makedirs(out, exist_ok=True)
    tagged = [t for t in tests if t.reqs]
    untagged = [t for t in tests if not t.reqs]
    summary = {
        "requirements": len(rows),
        "by_status": {s: sum(1 for r in rows if r["status"] == s) for s in
                      ("PASS", "FAIL", "BY TARGET", "PENDING", "WITHDRAWN")},
        "tests": len(tests), "tagged": len(tagged), "untagged": len(untagged),
        "tests_passed": sum(1 for t in tests if t.result == "PASS"),
        "tests_failed": sum(1 for t in tests if t.result == "FAIL"),
        "tests_not_run": sum(1 for t in tests if t.result == "NOT RUN"),
        "result_files": files, "errors": errors, "warnings": warnings,
    }
    with open(os.path.join(out, "matrix.json"), "w", encoding="utf-8") as f:
        json.dump({"summary": summary, "requirements": rows,
                   "untagged_tests": [t.key for t in untagged],
                   "unmatched_results": unmatched}, f, indent=1)
    md = ["# Traceability matrix", "",
          "Generated by `scripts/evidence/trace_requirements.py` from docs/REQUIREMENTS.md, the REQ tags of "
          "the tests and the JUnit XML of the last run (build/results/).", "",
          f"{summary['requirements']} requirements: " +
          ", ".join(f"{v} {k.lower()}" for k, v in summary["by_status"].items() if v) +
          f". {summary['tests']} tests ({summary['tagged']} tagged, {summary['untagged']} untagged); "
          f"{summary['tests_passed']} passed, {summary['tests_failed']} failed, "
          f"{summary['tests_not_run']} not run.", ""]
    if errors:
        md += ["## Errors", ""] + [f"- {e}" for e in errors] + [""]
    if warnings:
        md += ["## Warnings", ""] + [f"- {w}" for w in warnings] + [""]
    md += ["## Requirement → tests", "", "| requirement | status | verified by | tests (result: runs) |",
           "|---|---|---|---|"]
    for r in rows:
        tl = "<br>".join(f"`{t['test']}` {t['result']} ({', '.join(t['runs'])})" for t in r["tests"]) or "–"
        md.append(f"| {r['id']} | {r['status']} | {r['verification']} | {tl} |")
    md += ["", "## Untagged tests", ""] + ([f"- `{t.key}` ({t.result})" for t in untagged] or ["none"])
    with open(os.path.join(out, "matrix.md"), "w", encoding="utf-8") as f:
        f.write("\n".join(md) + "\n")
    colour = {"PASS": "#c8f7c5", "FAIL": "#f7c5c5", "BY TARGET": "#dde8ff", "PENDING": "#fff2b3",
              "WITHDRAWN": "#eee", "SKIP": "#fff2b3", "NOT RUN": "#fff2b3"}
    h = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>Traceability matrix</title>",
         "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
         "td,th{border:1px solid #bbb;padding:3px 6px;vertical-align:top;font-size:13px}"
         "code{font-size:12px}</style></head><body><h1>Traceability matrix</h1>",
         f"<p>{html.escape(md[4])}</p>"]
    for title, items in (("Errors", errors), ("Warnings", warnings)):
        if items:
            h.append(f"<h2>{title}</h2><ul>" + "".join(f"<li>{html.escape(i)}</li>" for i in items) + "</ul>")
    h.append("<table><tr><th>requirement</th><th>text</th><th>source</th><th>status</th>"
             "<th>verified by</th><th>tests</th></tr>")
    for r in rows:
        tl = "<br>".join(
            f"<span style='background:{colour.get(t['result'], '#fff')}'><code>{html.escape(t['test'])}</code> "
            f"{t['result']}</span> <small>({html.escape(', '.join(t['runs']))})</small>" for t in r["tests"]) or "–"
        h.append(f"<tr id='{r['id']}'><td><b>{r['id']}</b></td><td>{html.escape(r['text'])}</td>"
                 f"<td>{html.escape(r['source'])}</td>"
                 f"<td style='background:{colour[r['status']]}'>{r['status']}</td>"
                 f"<td>{html.escape(r['verification'])}</td><td>{tl}</td></tr>")
    h.append("</table><h2>Untagged tests</h2><ul>" +
             "".join(f"<li><code>{html.escape(t.key)}</code> {t.result}</li>" for t in untagged) +
             "</ul></body></html>")
    with open(os.path.join(out, "matrix.html"), "w", encoding="utf-8") as f:
        f.write("\n".join(h) + "\n")
    return summary


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--root", default=".")
    ap.add_argument("--results", default=None, help="default: ROOT/build/results")
    ap.add_argument("--out", default=None, help="default: ROOT/build/trace")
    ap.add_argument("--trees", default=",".join(DEFAULT_TREES),
                    help="result sub-folders to read (default: %(default)s)")
    a = ap.parse_args(argv)
    root = os.path.abspath(a.root)
    results = os.path.abspath(a.results or os.path.join(root, "build/results"))
    out = os.path.abspath(a.out or os.path.join(root, "build/trace"))
    trees = tuple(t for t in a.trees.split(",") if t)
    _, tests, rows, errors, warnings, unmatched, files = build(root, results, trees)
    s = write_outputs(out, tests, rows, errors, warnings, unmatched, files)
    for w in warnings:
        print(f"trace: warning: {w}")
    for e in errors:
        print(f"trace: ERROR: {e}")
    bs = s["by_status"]
    print(f"trace: {s['requirements']} requirements ({bs['PASS']} passed by test, {bs['BY TARGET']} by make "
          f"target, {bs['PENDING']} pending, {bs['FAIL']} failing); {s['tests']} tests "
          f"({s['tagged']} tagged, {s['untagged']} untagged), {s['tests_passed']} passed in "
          f"{len(files)} result files; matrix {os.path.relpath(out, root)}/matrix.{{md,html,json}}")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
