#!/usr/bin/env python3
"""The docs' tables agree with the code:

- the README's status table: the status codes and names of include/rfe/common.h;
- the parameter tables: docs/spec/DATA.md "Parameter file" (the paper preset),
  docs/ESTIMATOR.md "Parameters added to DATA.md" (both presets), docs/MONITOR.md §2 (the
  mon_* keys, both presets) and docs/OBSERVER.md §2 (the obs_* keys, their defaults). Every
  value a table gives is the one `mu_replay --preset paper|default` records in its estimate
  log (the library's presets; with --velocity observer for the obs_* keys), and every key
  mu_replay records is in its table: obs_* in OBSERVER.md, mon_* in MONITOR.md, the others
  in DATA.md or ESTIMATOR.md, and in ESTIMATOR.md when the two presets differ in it (DATA.md
  gives the paper preset only);
- the Python reference's observer defaults (scripts/reference/observer.py OBS_DEFAULTS)
  are the library's;
- the statements the presets decide: the README's intro names the default's and the paper
  preset's tyre models and the default structure, and DATA.md never calls `dt` ignored.

usage: check_doc_tables.py path/to/mu_replay [--root DIR]   (run by test/host/test_cli.sh;
exit 1 on a difference, one line per difference; --root: read the docs and sources under DIR
instead of this repository, for the tests)
"""
import ast
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

# Metadata of an estimate log that is not a parameter (mu_replay's write_estimates; the
# saturation_* counters only in q31 runs, which this check does not make).
NOT_PARAMS = {"generator", "preset", "velocity", "real", "input", "param_file"}
# The observer keys the reference does not have: the steering ratio converts a log's
# steering-wheel angle for mu_replay; the reference observer takes the road-wheel angle.
OBS_NOT_IN_REFERENCE = {"obs_steer_ratio"}


def read(rel, root=ROOT):
    with open(os.path.join(root, rel), encoding="utf-8") as f:
        return f.read()


def code_statuses(root=ROOT):
    """{code: name} of the rfe_status_t enum (RFE_ERR_FIRST is an alias, not a status)."""
    enum = re.search(r"typedef enum \{(.*?)\} rfe_status_t;", read("include/rfe/common.h", root),
                     re.S)
    pairs = re.findall(r"\b(RFE_[A-Z_]+)\s*=\s*(\d+)", enum.group(1))
    return {int(v): k for k, v in pairs if k != "RFE_ERR_FIRST"}


def readme_statuses(root=ROOT):
    sec = read("README.md", root).split("## Status codes", 1)[1].split("\n## ", 1)[0]
    return {int(c): n for c, n in re.findall(r"^\| (\d+) \| `(RFE_[A-Z_]+)` \|", sec, re.M)}


def preset_meta(binary, preset, observer=False):
    """The parameters (`# key = value` lines but NOT_PARAMS) of the estimate log of a run
    with @p preset; with @p observer the velocity observer's too."""
    with tempfile.TemporaryDirectory() as d:
        log = os.path.join(d, "in.csv")
        out = os.path.join(d, "out.csv")
        with open(log, "w", encoding="utf-8") as f:
            f.write("t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
                    "0,0,20,0,0,0,0,0,61.5,61.5,61.5,61.5\n")
        subprocess.run([binary, "--in", log, "--out", out, "--preset", preset, "-q"]
                       + (["--velocity", "observer"] if observer else []), check=True)
        with open(out, encoding="utf-8") as f:
            meta = dict(re.findall(r"^# (\S+) = (.*)$", f.read(), re.M))
    return {k: v for k, v in meta.items() if k not in NOT_PARAMS}


def reference_obs_defaults(root=ROOT):
    """OBS_DEFAULTS of scripts/reference/observer.py, read without importing it (the check
    runs on the system Python, which may lack numpy)."""
    tree = ast.parse(read("scripts/reference/observer.py", root))
    for node in tree.body:
        target = node.target if isinstance(node, ast.AnnAssign) else \
            (node.targets[0] if isinstance(node, ast.Assign) else None)
        if isinstance(target, ast.Name) and target.id == "OBS_DEFAULTS":
            return ast.literal_eval(node.value)
    raise SystemExit("check_doc_tables: no OBS_DEFAULTS in scripts/reference/observer.py")


def table_rows(text, header_start, where):
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
    raise SystemExit(f"check_doc_tables: {where}: no table starting '{header_start}'")


def same(doc, code):
    # "0 (off)", "0 (paper rule)", "0.05 each", "`wheels`": the value itself
    doc = re.sub(r"\(.*?\)|\beach\b|`", "", doc).strip()
    try:
        return float(doc) == float(code)
    except ValueError:
        return doc == code


def check_preset_table(problems, where, rows, cols):
    """Each value of @p rows (key cell first: one key or several, with one value each or one
    for all) against @p cols [(column, {key: value}, preset name)]. Returns the keys listed."""
    listed = []
    for row in rows:
        keys = re.findall(r"`([A-Za-z_0-9]+)`", row[0])
        listed += keys
        for col, meta, preset in cols:
            values = [v.strip() for v in row[col].split(",")]
            if len(values) == 1:
                values = values * len(keys)
            elif len(values) != len(keys):
                problems.append(f"{where}: {len(keys)} keys ({', '.join(keys)}) but "
                                f"{len(values)} values in the {preset} column")
                continue
            for key, value in zip(keys, values):
                if key not in meta:
                    problems.append(f"{where}: key '{key}' is not a parameter mu_replay records")
                elif not same(value, meta[key]):
                    problems.append(f"{where}: {key} = {value} in the {preset} column, the "
                                    f"library's {preset} preset has {meta[key]}")
    return listed


def missing(problems, where, listed, wanted, why=""):
    for key in sorted(set(wanted) - set(listed)):
        problems.append(f"{where}: no row for '{key}'{why}")


# The README's intro names each preset's tyre model and the default's structure the way the
# presets' recorded keys say (issue 18: it once called Dugoff the default).
TYRE_NAMES = {"magic": "Magic Formula", "paper": "Dugoff", "dugoff": "Dugoff"}
STRUCTURE_WORDS = {"sides": "one μ per side", "wheels": "under each wheel"}


def check_statements(problems, paper, default, root=ROOT):
    """The prose statements the code decides: the README's intro (the text before its first
    section) on the presets' tyre models and the default structure; DATA.md never calls the
    `dt` metadata ignored (it is the parameter of "The sample period")."""
    intro = read("README.md", root).split("\n## ", 1)[0]
    wants = [f"{TYRE_NAMES.get(default.get('tyre'), default.get('tyre'))} tyre by default",
             f"{TYRE_NAMES.get(paper.get('tyre'), paper.get('tyre'))} in the paper preset",
             STRUCTURE_WORDS.get(default.get("structure"), str(default.get("structure")))]
    for want in wants:
        if want not in " ".join(intro.split()):
            problems.append(f"README.md intro: does not say '{want}' (the library's presets: "
                            f"default tyre {default.get('tyre')}, structure "
                            f"{default.get('structure')}; paper tyre {paper.get('tyre')})")
    for clause in re.split(r"[.;:]\s", " ".join(read("docs/spec/DATA.md", root).split())):
        if "`dt`" in clause and "ignored" in clause:
            problems.append(f"docs/spec/DATA.md: '{clause.strip()}': the dt metadata is the "
                            f"sample period's parameter, not ignored")


def check(binary, root=ROOT):
    """The differences, one line each (empty: the docs agree with the code)."""
    problems = []
    code, doc = code_statuses(root), readme_statuses(root)
    for c in sorted(set(code) | set(doc)):
        if code.get(c) != doc.get(c):
            problems.append(f"README.md status table: code {c} is {doc.get(c)}, "
                            f"include/rfe/common.h says {code.get(c)}")
    paper, default = preset_meta(binary, "paper"), preset_meta(binary, "default")
    obs_paper = preset_meta(binary, "paper", observer=True)
    obs_default = preset_meta(binary, "default", observer=True)

    check_statements(problems, paper, default, root)

    # the friction estimator's keys: DATA.md (paper) and ESTIMATOR.md (both presets)
    where_data = "docs/spec/DATA.md \"Parameter file\""
    in_data = check_preset_table(
        problems, where_data,
        table_rows(read("docs/spec/DATA.md", root), "| key | paper preset | unit |", where_data),
        [(1, paper, "paper")])
    where_est = "docs/ESTIMATOR.md \"Parameters added to DATA.md\""
    in_est = check_preset_table(
        problems, where_est,
        table_rows(read("docs/ESTIMATOR.md", root), "| key | paper preset | default preset |",
                   where_est),
        [(1, paper, "paper"), (2, default, "default")])
    friction = {k for k in set(paper) | set(default) if not k.startswith(("mon_", "obs_"))}
    not_in_data = friction - set(in_data)
    missing(problems, where_est, in_est, not_in_data,
            " (a key of the library's presets that DATA.md's table does not list either)")
    missing(problems, where_est, in_est,
            {k for k in friction - not_in_data if paper.get(k) != default.get(k)},
            " (the presets differ in it; DATA.md gives the paper preset only)")

    # the model-validity monitor's keys: MONITOR.md §2 (both presets)
    where_mon = "docs/MONITOR.md \"Parameters\""
    in_mon = check_preset_table(
        problems, where_mon,
        table_rows(read("docs/MONITOR.md", root), "| key | paper preset | default preset |",
                   where_mon),
        [(1, paper, "paper"), (2, default, "default")])
    missing(problems, where_mon, in_mon,
            {k for k in set(paper) | set(default) if k.startswith("mon_")})

    # the velocity observer's keys: OBSERVER.md §2 (one column: the same in both presets)
    where_obs = "docs/OBSERVER.md §2 \"Parameters\""
    in_obs = check_preset_table(
        problems, where_obs,
        table_rows(read("docs/OBSERVER.md", root), "| key | default | unit |", where_obs),
        [(1, obs_default, "default"), (1, obs_paper, "paper")])
    obs_keys = {k for k in set(obs_paper) | set(obs_default) if k.startswith("obs_")}
    missing(problems, where_obs, in_obs, obs_keys)

    # the Python reference's observer defaults
    where_ref = "scripts/reference/observer.py OBS_DEFAULTS"
    ref = reference_obs_defaults(root)
    for key, value in sorted(ref.items()):
        if key not in obs_default:
            problems.append(f"{where_ref}: key '{key}' is not a parameter mu_replay records")
        elif not same(repr(value), obs_default[key]):
            problems.append(f"{where_ref}: {key} = {value!r}, the library's default is "
                            f"{obs_default[key]}")
    missing(problems, where_ref, ref, obs_keys - OBS_NOT_IN_REFERENCE)
    return problems, len(code)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    binary = argv[0]
    root = argv[argv.index("--root") + 1] if "--root" in argv else ROOT
    problems, n_status = check(binary, root)
    for p in problems:
        print(p)
    print(f"doc tables: {n_status} status codes, the paper and default presets, the monitor's "
          f"and the observer's parameters: "
          f"{'OK' if not problems else str(len(problems)) + ' difference(s)'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
