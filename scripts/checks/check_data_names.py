#!/usr/bin/env python3
"""The project's DATA.md still documents every column and key of the shared DATA.md.

    python3 scripts/checks/check_data_names.py SHARED_DATA.md PROJECT_DATA.md

docs/spec/DATA.md started as a copy of the shared specification and grows with the new
estimators (optional columns, new inputs, new keys). It may reword a row, but it must not
drop a name: every name in the first cell of a table row of the shared file (`vx, vy`,
`mu_fl, mu_fr, ...`, a key) must appear in the first cell of a table row of the project's.
Exit 0 when it does, 1 listing the lost names, 2 on a usage error.
"""

from __future__ import annotations

import re
import sys


def first_cell_names(text: str) -> set[str]:
    names: set[str] = set()
    for line in text.splitlines():
        if line.startswith("|") and not re.match(r"^\|\s*-", line):
            cell = line.split("|")[1]
            names.update(n for n in re.findall(r"[A-Za-z_][\w]*", cell))
    return names


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2:
        print(__doc__.split("\n")[2].strip(), file=sys.stderr)
        return 2
    with open(argv[0], encoding="utf-8") as f:
        shared = first_cell_names(f.read())
    with open(argv[1], encoding="utf-8") as f:
        own = first_cell_names(f.read())
    lost = sorted(shared - own)
    if lost:
        print(f"check_data_names: {argv[1]} no longer documents: {', '.join(lost)}")
        return 1
    print(f"check_data_names: {len(shared)} names of {argv[0]} all documented in {argv[1]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
