#!/usr/bin/env python3
"""Collects the certification evidence into one folder and writes its index.html.

Copies, from the build tree, what `make evidence` ran: coverage (gcovr HTML, Cobertura XML,
summary, the justification report), MC/DC (llvm-cov report, HTML, summary, gaps), MISRA
(cppcheck reports) with docs/MISRA.md, the traceability matrix, the JUnit XML of the last
test run, the requirements and coverage-justification documents, the firmware size/stack
outputs when build/firmware/ exists, and the tool versions. A part that is missing is listed
as "not built" rather than failing, so the index always says what the folder holds.

usage: evidence_index.py --build build --out build/evidence [--cc gcc] [--mcdc-cc clang-19]
           [--llvm-cov llvm-cov-19] [--clang-tidy clang-tidy-19]
"""
from __future__ import annotations

import argparse
import datetime
import glob
import html
import json
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET


def sh(cmd):
    try:
        r = subprocess.run(cmd, shell=True, capture_output=True, text=True, timeout=60)
        out = (r.stdout or r.stderr).strip().split("\n")
        return out[0] if out and out[0] else "not available"
    except (OSError, subprocess.SubprocessError):
        return "not available"


def copy(src, dst):
    if os.path.isdir(src):
        shutil.copytree(src, dst, dirs_exist_ok=True)
        return True
    if os.path.isfile(src):
        os.makedirs(os.path.dirname(dst), exist_ok=True)
        shutil.copy2(src, dst)
        return True
    return False


def md_page(md_path, html_path, title):
    """A markdown file shown as preformatted text in an HTML page (no renderer needed)."""
    text = open(md_path, encoding="utf-8").read()
    with open(html_path, "w", encoding="utf-8") as f:
        f.write(f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
                "</head><body><pre style='white-space:pre-wrap'>" + html.escape(text) + "</pre></body></html>\n")


def junit_totals(results):
    tot = {"files": 0, "tests": 0, "failures": 0, "skipped": 0, "unreadable": 0}
    per = []
    for p in sorted(glob.glob(os.path.join(results, "*", "*.xml"))):
        tot["files"] += 1
        try:
            root = ET.parse(p).getroot()
        except ET.ParseError:
            tot["unreadable"] += 1
            continue
        n = f = s = 0
        for tc in root.iter("testcase"):
            n += 1
            if tc.find("failure") is not None or tc.find("error") is not None:
                f += 1
            elif tc.find("skipped") is not None:
                s += 1
        tot["tests"] += n
        tot["failures"] += f
        tot["skipped"] += s
        per.append((os.path.relpath(p, results), n, f, s))
    return tot, per


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default="build")
    ap.add_argument("--out", default="build/evidence")
    ap.add_argument("--cc", default="gcc")
    ap.add_argument("--mcdc-cc", default="clang-19")
    ap.add_argument("--llvm-cov", default="llvm-cov-19")
    ap.add_argument("--clang-tidy", default="clang-tidy-19")
    a = ap.parse_args(argv)
    b, out = a.build, a.out
    os.makedirs(out, exist_ok=True)
    parts = []   # (title, link or None, note)

    # coverage
    cov_note = "not built (make coverage)"
    if copy(os.path.join(b, "coverage"), os.path.join(out, "coverage")):
        cx = os.path.join(out, "coverage", "coverage.xml")
        if os.path.isfile(cx):
            r = ET.parse(cx).getroot()
            cov_note = (f"gcovr over src/ (float, double, q31; unit, golden, host, CLI tests): lines "
                        f"{100 * float(r.get('line-rate', 0)):.1f} % ({r.get('lines-covered')} of "
                        f"{r.get('lines-valid')}), branches {100 * float(r.get('branch-rate', 0)):.1f} % "
                        f"({r.get('branches-covered')} of {r.get('branches-valid')})")
        parts.append(("Statement and branch coverage (gcovr HTML)", "coverage/index.html", cov_note))
        parts.append(("Coverage, Cobertura XML", "coverage/coverage.xml", ""))
        if os.path.isfile(os.path.join(out, "coverage", "justified.md")):
            md_page(os.path.join(out, "coverage", "justified.md"), os.path.join(out, "coverage", "justified.html"),
                    "Uncovered lines and their justification")
            parts.append(("Uncovered lines and MC/DC gaps with their justification", "coverage/justified.html",
                          "checked by scripts/evidence/evidence_coverage.py"))
    else:
        parts.append(("Statement and branch coverage", None, cov_note))

    # MC/DC
    mcdc = os.path.join(b, "mcdc")
    if copy(mcdc, os.path.join(out, "mcdc")):
        note = ""
        sj = os.path.join(out, "mcdc", "summary.json")
        if os.path.isfile(sj):
            t = json.load(open(sj, encoding="utf-8"))["data"][0]["totals"]
            m = t.get("mcdc", {})
            note = (f"MC/DC {m.get('percent', 0):.1f} % ({m.get('covered', 0)} of {m.get('count', 0)} "
                    f"conditions); lines {t['lines']['percent']:.1f} %, branches {t['branches']['percent']:.1f} %")
        for f in ("summary.md", "gaps.md"):
            if os.path.isfile(os.path.join(out, "mcdc", f)):
                md_page(os.path.join(out, "mcdc", f), os.path.join(out, "mcdc", f[:-3] + ".html"), f)
        parts.append(("MC/DC summary (per file)", "mcdc/summary.html", note))
        parts.append(("MC/DC report (llvm-cov report --show-mcdc-summary)", "mcdc/report.txt", ""))
        parts.append(("MC/DC per line (llvm-cov show --show-mcdc, HTML)", "mcdc/html/index.html", ""))
        parts.append(("MC/DC gaps (decisions with a condition not shown independent)", "mcdc/gaps.html", ""))
        if os.path.isfile(os.path.join(out, "mcdc", "justified.md")):
            md_page(os.path.join(out, "mcdc", "justified.md"), os.path.join(out, "mcdc", "justified.html"),
                    "MC/DC gaps and their justification")
            parts.append(("MC/DC gaps with their justification", "mcdc/justified.html",
                          "checked by scripts/evidence/evidence_coverage.py (make mcdc)"))
        failed = os.path.join(out, "mcdc", "failed.txt")
        if os.path.isfile(failed) and os.path.getsize(failed):
            parts.append(("MC/DC run: tests that failed", "mcdc/failed.txt", "coverage measured anyway"))
    else:
        parts.append(("MC/DC", None, "not built (make mcdc)"))

    # MISRA
    misra = os.path.join(b, "misra")
    got = False
    for f in sorted(glob.glob(os.path.join(misra, "*.txt")) + glob.glob(os.path.join(misra, "*.xml"))):
        copy(f, os.path.join(out, "misra", os.path.basename(f)))
        got = True
    copy("docs/MISRA.md", os.path.join(out, "misra", "MISRA.md"))
    md_page("docs/MISRA.md", os.path.join(out, "misra", "MISRA.html"), "MISRA deviations")
    if got:
        for f in sorted(os.listdir(os.path.join(out, "misra"))):
            if f.endswith((".txt", ".xml")):
                parts.append((f"MISRA C:2012 report (cppcheck), {f}", f"misra/{f}", ""))
    else:
        parts.append(("MISRA C:2012 report", None, "not built (make misra)"))
    parts.append(("Static analysis, deviations and their justification (docs/MISRA.md)", "misra/MISRA.html", ""))

    # traceability
    tr = os.path.join(b, "trace")
    if copy(tr, os.path.join(out, "trace")):
        note = ""
        mj = os.path.join(out, "trace", "matrix.json")
        if os.path.isfile(mj):
            s = json.load(open(mj, encoding="utf-8"))["summary"]
            bs = s["by_status"]
            note = (f"{s['requirements']} requirements: {bs['PASS']} passed by test, {bs['BY TARGET']} by make "
                    f"target, {bs['PENDING']} pending, {bs['FAIL']} failing; {s['tests']} tests "
                    f"({s['tagged']} tagged), {len(s['errors'])} errors")
        parts.append(("Traceability matrix (requirement → tests → result)", "trace/matrix.html", note))
        parts.append(("Traceability matrix, markdown / JSON", "trace/matrix.md", ""))
    else:
        parts.append(("Traceability matrix", None, "not built (make trace)"))
    for d in ("REQUIREMENTS.md", "COVERAGE_JUSTIFICATION.md"):
        p = os.path.join("docs", d)
        if os.path.isfile(p):
            copy(p, os.path.join(out, "docs", d))
            md_page(p, os.path.join(out, "docs", d[:-3] + ".html"), d)
            parts.append((f"docs/{d}", f"docs/{d[:-3]}.html", ""))

    # test results
    res = os.path.join(b, "results")
    tot, per = junit_totals(res)
    if tot["files"]:
        for p in glob.glob(os.path.join(res, "*", "*.xml")):
            copy(p, os.path.join(out, "results", os.path.relpath(p, res)))
        rows = "".join(f"<tr><td><a href='{html.escape(p)}'>{html.escape(p)}</a></td><td>{n}</td><td>{f}</td>"
                       f"<td>{s}</td></tr>" for p, n, f, s in per)
        with open(os.path.join(out, "results", "index.html"), "w", encoding="utf-8") as f:
            f.write("<!DOCTYPE html><html><head><meta charset='utf-8'><title>Test results</title></head><body>"
                    "<h1>JUnit XML of the last run</h1><table border=1 cellpadding=3><tr><th>file</th>"
                    f"<th>tests</th><th>failures</th><th>skipped</th></tr>{rows}</table></body></html>\n")
        trees = sorted({p.split(os.sep)[0] for p, _, _, _ in per})
        parts.append(("Test results (JUnit XML, one file per test binary and tree)", "results/index.html",
                      f"{tot['tests']} test cases in {tot['files']} files ({', '.join(trees)}), "
                      f"{tot['failures']} failed, {tot['skipped']} skipped"))
    else:
        parts.append(("Test results", None, "not built (make test-c test-py)"))

    # firmware (issue 5): size/stack table. The firmware work writes build/firmware/report.json
    # (make firmware-check: sizes, worst-case stacks, budgets) and pil.json (make pil), and
    # `make firmware-table` puts the table into docs/FIRMWARE.md's section "Measured: size,
    # stack and emulated runs".
    fw = os.path.join(b, "firmware")
    fw_files = [p for p in sorted(glob.glob(os.path.join(fw, "*")))
                if os.path.isfile(p) and p.endswith((".md", ".txt", ".csv", ".json", ".html"))
                and os.path.getsize(p) < 2_000_000]
    for p in fw_files:
        copy(p, os.path.join(out, "firmware", os.path.basename(p)))
        parts.append((f"Firmware size/stack: {os.path.basename(p)}", f"firmware/{os.path.basename(p)}",
                      "from build/firmware/ (make firmware, make pil)"))
    fw_page = "docs/FIRMWARE.md"
    page = open(fw_page, encoding="utf-8").read() if os.path.isfile(fw_page) else ""
    m = re.search(r"^## Measured.*?(?=^## |\Z)", page, re.S | re.M)
    if m and ("|" in m.group(0)):
        os.makedirs(os.path.join(out, "firmware"), exist_ok=True)
        with open(os.path.join(out, "firmware", "README_firmware.md"), "w", encoding="utf-8") as f:
            f.write(m.group(0))
        md_page(os.path.join(out, "firmware", "README_firmware.md"),
                os.path.join(out, "firmware", "README_firmware.html"), "Firmware table")
        parts.append(("Firmware size and stack table (docs/FIRMWARE.md, make firmware-table)",
                      "firmware/README_firmware.html", ""))
    if not fw_files and not (m and "|" in m.group(0)):
        parts.append(("Firmware size and stack table", None, "not built (make firmware, make firmware-table)"))

    # tool versions
    versions = [
        ("C compiler (library, tests, gcov)", sh(f"{a.cc} --version")),
        ("gcov", sh("gcov --version")),
        ("clang (MC/DC)", sh(f"{a.mcdc_cc} --version")),
        ("llvm-cov", sh(f"{a.llvm_cov} --version | grep -i version")),
        ("cmocka", sh("dpkg-query -W -f='${Version}' libcmocka-dev")),
        ("cppcheck (MISRA addon)", sh("cppcheck --version")),
        ("clang-tidy", sh(f"{a.clang_tidy} --version | grep -i 'version'")),
        ("arm-none-eabi-gcc", sh("arm-none-eabi-gcc --version")),
        ("valgrind", sh("valgrind --version")),
        ("Python", sys.version.split()[0]),
        ("gcovr", sh(f"{sys.executable} -m gcovr --version")),
        ("lizard", sh(f"{sys.executable} -m lizard --version")),
        ("pytest", sh(f"{sys.executable} -m pytest --version")),
        ("git commit", sh("git rev-parse HEAD") + (" (working tree modified)" if sh("git status --porcelain | head -1") not in ("", "not available") else "")),
    ]
    with open(os.path.join(out, "versions.txt"), "w", encoding="utf-8") as f:
        for k, v in versions:
            f.write(f"{k}: {v}\n")
    parts.append(("Tool versions", "versions.txt", ""))

    when = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    items = []
    for title, link, note in parts:
        t = f"<a href='{html.escape(link)}'>{html.escape(title)}</a>" if link else html.escape(title)
        items.append(f"<tr><td>{t}</td><td>{html.escape(note)}</td></tr>")
    vers = "".join(f"<tr><td>{html.escape(k)}</td><td>{html.escape(v)}</td></tr>" for k, v in versions)
    with open(os.path.join(out, "index.html"), "w", encoding="utf-8") as f:
        f.write("<!DOCTYPE html><html><head><meta charset='utf-8'><title>rfe certification evidence</title>"
                "<style>body{font-family:sans-serif;margin:2em}td,th{border:1px solid #bbb;padding:4px 8px;"
                "vertical-align:top}table{border-collapse:collapse}</style></head><body>"
                "<h1>rfe — certification evidence</h1>"
                f"<p>Generated by <code>make evidence</code> (mk/evidence.mk, scripts/evidence/evidence_index.py), {when}.</p>"
                "<table><tr><th>part</th><th>summary</th></tr>" + "".join(items) + "</table>"
                "<h2>Tool versions</h2><table>" + vers + "</table></body></html>\n")
    print(f"evidence: {len(parts)} parts in {out}/index.html")
    return 0


if __name__ == "__main__":
    sys.exit(main())
