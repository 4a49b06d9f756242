#!/usr/bin/env python3
"""Every public symbol of the libraries is greppable by its full name (docs/LAYOUT.md).

    python3 scripts/checks/check_names.py --lib build/f32/librfe.a:_f32 \
        --lib build/f64/librfe.a:_f64 --lib build/q31/librfe_q31.a: [--root DIR]

For each archive, every global symbol it defines (nm) must
  - end with the archive's suffix (`_f32`, `_f64`; an empty suffix checks nothing), so the
    float, double and fixed-point libraries link into one program without clashes, and
  - be written out, as a whole word, in a header under include/ or src/: the declaration, or
    the header's block that maps the short name the sources use to the full one
    (`#define rfe_sckf_init rfe_sckf_init_f32`).
Exit 0 when both hold, 1 with one line per symbol that breaks them, 2 on a usage error.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys


def defined_globals(archive: str) -> list[str]:
    """The global symbols an archive defines, sorted (nm --defined-only -g)."""
    out = subprocess.run(["nm", "-g", "--defined-only", archive], check=True,
                         capture_output=True, text=True).stdout
    return sorted({f[2] for f in (line.split() for line in out.splitlines()) if len(f) == 3})


def header_words(root: str) -> set[str]:
    """Every identifier written in a header under root/include and root/src."""
    words: set[str] = set()
    for top in ("include", "src"):
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in files:
                if f.endswith(".h"):
                    with open(os.path.join(d, f), encoding="utf-8") as fh:
                        words.update(re.findall(r"\b\w+\b", fh.read()))
    return words


def problems(symbols: list[str], suffix: str, words: set[str]) -> list[str]:
    out = []
    for s in symbols:
        if suffix and not s.endswith(suffix):
            out.append(f"{s}: does not end with {suffix}")
        if s not in words:
            out.append(f"{s}: its full name is written in no header of include/ or src/")
    return out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lib", action="append", required=True, metavar="ARCHIVE:SUFFIX")
    ap.add_argument("--root", default=".")
    a = ap.parse_args(argv)
    words = header_words(a.root)
    bad, count = [], 0
    for spec in a.lib:
        archive, sep, suffix = spec.partition(":")
        if not sep or not os.path.isfile(archive):
            print(f"check_names: {spec}: expected an existing ARCHIVE:SUFFIX", file=sys.stderr)
            return 2
        syms = defined_globals(archive)
        count += len(syms)
        bad += [f"{archive}: {p}" for p in problems(syms, suffix, words)]
    for line in bad:
        print(line)
    if bad:
        print(f"check_names: {len(bad)} problem(s): every public symbol must carry its type's "
              "suffix and be written out in a header (docs/LAYOUT.md)")
        return 1
    print(f"check_names: {count} public symbols in {len(a.lib)} libraries, each written out in a header")
    return 0


if __name__ == "__main__":
    sys.exit(main())
