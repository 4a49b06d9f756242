#!/usr/bin/env python3
"""Write the fault-injection logs (scripts/sim/faults.py) from the bundled clean logs.

    .venv/bin/python scripts/data/make_fault_scenarios.py [--scenarios scenarios]
                                                     [--out scenarios/faults] [--check]

Each fault log is scenarios/<base>.csv with one sensor fault applied (faults.FAULTS),
written as <out>/<fault>.<base>.csv; deterministic (fixed seeds), so the same bundled logs
give the same bytes.  --check writes nothing and exits 1 when a file is missing or differs
(the fault logs are stale: run `make fault-scenarios`).
"""

import argparse
import os
import sys

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)

from sim import faults  # noqa: E402


def main(argv=None):
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenarios", default=os.path.join(repo, "scenarios"))
    ap.add_argument("--out", default=os.path.join(repo, "scenarios", "faults"))
    ap.add_argument("--check", action="store_true", help="compare instead of writing")
    a = ap.parse_args(argv)
    stale = []
    if not a.check:
        os.makedirs(a.out, exist_ok=True)
    for f in faults.FAULTS:
        text = faults.make(f, a.scenarios)
        path = os.path.join(a.out, faults.file_name(f))
        if a.check:
            try:
                with open(path, encoding="utf-8") as fh:
                    same = fh.read() == text
            except OSError:
                same = False
            if not same:
                stale.append(path)
            continue
        with open(path, "w", encoding="utf-8", newline="\n") as fh:
            fh.write(text)
        print(f"{faults.file_name(f):50s} {f.description}")
    if a.check:
        for p in stale:
            print(f"stale or missing: {p} (run make fault-scenarios)")
        return 1 if stale else 0
    print(f"{len(faults.FAULTS)} fault log(s) -> {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
