#!/usr/bin/env python3
"""`make help`: one line per target, from the `## description` line that stands directly
above each rule in the Makefile and mk/*.mk, so the list cannot drift from the rules.

    python3 scripts/checks/make_help.py [--check] [FILE ...]

--check (`make help-check`, part of make test): every .PHONY target has a description, and
every description sits directly above a rule. Exit 1 naming what is missing, else 0.
"""

from __future__ import annotations

import argparse
import glob
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RULE_RE = re.compile(r"^([a-z][a-z0-9-]*(?:[ \t]+[a-z][a-z0-9-]*)*)[ \t]*:(?!=)")


def makefiles(root: str) -> list[str]:
    """The Makefile, then mk/lib.mk, then the other fragments: the order make reads them."""
    mk = sorted(glob.glob(os.path.join(root, "mk", "*.mk")))
    lib = [f for f in mk if f.endswith(os.sep + "lib.mk")]
    return [os.path.join(root, "Makefile")] + lib + [f for f in mk if f not in lib]


def parse(paths: list[str]):
    """(targets: list of (file, target, description)), phony targets, problems."""
    targets, phony, problems = [], set(), []
    for path in paths:
        text = open(path, encoding="utf-8").read()
        for m in re.finditer(r"^\.PHONY:(.*)$", text.replace("\\\n", " "), re.M):
            phony |= set(m.group(1).split())
        desc, desc_line = None, 0
        for n, line in enumerate(text.splitlines(), 1):
            if line.startswith("## "):
                desc, desc_line = line[3:].strip(), n
                continue
            m = RULE_RE.match(line)
            if desc is not None:
                if m:
                    for t in m.group(1).split():
                        targets.append((os.path.relpath(path, ROOT), t, desc))
                else:
                    problems.append(f"{os.path.relpath(path, ROOT)}:{desc_line}: a ## line "
                                    "not directly above a rule")
                desc = None
    return targets, phony, problems


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--check", action="store_true")
    ap.add_argument("files", nargs="*")
    a = ap.parse_args(argv)
    paths = a.files or makefiles(ROOT)
    targets, phony, problems = parse(paths)
    described = {t for _, t, _ in targets}
    problems += [f"target {t} (.PHONY) has no ## description" for t in sorted(phony - described)]
    if a.check:
        for p in problems:
            print(f"help: {p}", file=sys.stderr)
        if problems:
            return 1
        print(f"help: {len(described)} targets, each with its description")
        return 0
    print("rfe: make TARGET [VARIABLE=value ...]; the targets, by the file that defines them:")
    width = max((len(t) for _, t, _ in targets), default=0)
    last = None
    for f, t, d in targets:
        if f != last:
            print(f"\n{f}:")
            last = f
        print(f"  {t:<{width}}  {d}")
    for p in problems:
        print(f"help: {p}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
