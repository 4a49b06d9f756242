#!/usr/bin/env python3
"""The README's status table and the preset tables of docs/spec/DATA.md ("Parameter file",
the paper preset) and docs/ESTIMATOR.md ("Parameters added to DATA.md", both presets) agree
with the code: the status codes and names of include/rfe/common.h, and the values that
`mu_replay --preset paper|default` records in its estimate log (the library's presets).

usage: check_doc_tables.py path/to/mu_replay   (run by test/host/test_cli.sh; exit 1 on a
difference, one line per difference)
"""
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def read(rel):
    with open(os.path.join(ROOT, rel), encoding="utf-8") as f:
        return f.read()


def code_statuses():
    """{code: name} of the rfe_status_t enum (RFE_ERR_FIRST is an alias, not a status)."""
    enum = re.search(r"typedef enum \{(.*?)\} rfe_status_t;", read("include/rfe/common.h"), re.S)
    pairs = re.findall(r"\b(RFE_[A-Z_]+)\s*=\s*(\d+)", enum.group(1))
    return {int(v): k for k, v in pairs if k != "RFE_ERR_FIRST"}


def readme_statuses():
    sec = read("README.md").split("## Status codes", 1)[1].split("\n## ", 1)[0]
    return {int(c): n for c, n in re.findall(r"^\| (\d+) \| `(RFE_[A-Z_]+)` \|", sec, re.M)}


def preset_meta(binary, preset):
    """The estimate log's `# key = value` lines of a run with @p preset."""
    with tempfile.TemporaryDirectory() as d:
        log = os.path.join(d, "in.csv")
        out = os.path.join(d, "out.csv")
        with open(log, "w", encoding="utf-8") as f:
            f.write("t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
                    "0,0,20,0,0,0,0,0,61.5,61.5,61.5,61.5\n")
        subprocess.run([binary, "--in", log, "--out", out, "--preset", preset, "-q"], check=True)
        with open(out, encoding="utf-8") as f:
            return dict(re.findall(r"^# (\S+) = (.*)$", f.read(), re.M))


def table_rows(text, header_start):
    """Rows (lists of cells) of the markdown table whose header row starts with @p header_start."""
    lines = text.splitlines()
    for i, line in enumerate(lines):
        if line.startswith(header_start):
            rows = []
            for row in lines[i + 2:]:
                if not row.startswith("|"):
                    break
                rows.append([c.strip() for c in row.strip("|").split("|")])
            return rows
    raise SystemExit(f"check_doc_tables: no table starting '{header_start}'")


def same(doc, code):
    # "0 (off)", "0 (paper rule)", "0.05 each", "`wheels`": the value itself
    doc = re.sub(r"\(.*?\)|\beach\b|`", "", doc).strip()
    try:
        return float(doc) == float(code)
    except ValueError:
        return doc == code


def check_preset_table(problems, where, rows, key_col, cols, metas):
    for row in rows:
        keys = re.findall(r"`([A-Za-z_0-9]+)`", row[key_col])
        for col, meta, preset in cols:
            values = [v.strip() for v in row[col].split(",")]
            if len(values) != len(keys):
                values = values * len(keys) if len(values) == 1 else values
            for key, value in zip(keys, values):
                if key not in meta:
                    problems.append(f"{where}: key '{key}' is not a parameter mu_replay records")
                elif not same(value, meta[key]):
                    problems.append(f"{where}: {key} = {value} in the {preset} column, the "
                                    f"library's {preset} preset has {meta[key]}")


def main():
    binary = sys.argv[1]
    problems = []
    code, doc = code_statuses(), readme_statuses()
    for c in sorted(set(code) | set(doc)):
        if code.get(c) != doc.get(c):
            problems.append(f"README.md status table: code {c} is {doc.get(c)}, "
                            f"include/rfe/common.h says {code.get(c)}")
    paper, default = preset_meta(binary, "paper"), preset_meta(binary, "default")
    check_preset_table(problems, "docs/spec/DATA.md \"Parameter file\"",
                       table_rows(read("docs/spec/DATA.md"), "| key | paper preset | unit |"),
                       0, [(1, paper, "paper")], None)
    check_preset_table(problems, "docs/ESTIMATOR.md \"Parameters added to DATA.md\"",
                       table_rows(read("docs/ESTIMATOR.md"),
                                  "| key | paper preset | default preset |"),
                       0, [(1, paper, "paper"), (2, default, "default")], None)
    for p in problems:
        print(p)
    print(f"doc tables: {len(code)} status codes, the paper and default presets: "
          f"{'OK' if not problems else str(len(problems)) + ' difference(s)'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
