#!/usr/bin/env python3
"""The tools outside the Python pins whose version can change a test's outcome, checked
against the versions the gates were calibrated with (Debian 12's packages, which `make deps`
installs). Prints one line per tool; fails naming what a mismatch would change.

    python3 scripts/checks/check_tools.py [--warn] [--only NAME ...]

--warn (make test TOOL_PINS=warn) reports a mismatch and goes on: for trying the suite on
another distribution, knowing which gates may then disagree. A tool that is not installed is
reported as such: `make deps` installs it (the gates that need it fail without it anyway).
Pins are prefixes of the version (major[.minor]), which point releases of Debian 12 keep, or
a minimum ("3.11+").
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys

# name, command, regex for the version in its first output line, pinned prefix, what it decides
PINS = [
    ("python3", ["python3", "--version"], r"Python (\S+)", "3.11+",
     "the venv's interpreter: the pinned wheels (numpy 2.4.6 ...) and the reference's output"),
    ("gcc", ["gcc", "-dumpfullversion"], r"(\S+)", "12.",
     "warnings under -Werror, and which lines gcov attributes (docs/COVERAGE_JUSTIFICATION.md)"),
    ("cppcheck", ["cppcheck", "--version"], r"Cppcheck (\S+)", "2.10",
     "the MISRA addon's findings, gated at zero beyond docs/MISRA.md's deviations"),
    ("clang-tidy-19", ["clang-tidy-19", "--version"], r"LLVM version (\S+)", "19.",
     "the findings of the .clang-tidy checks"),
    ("clang-19", ["clang-19", "--version"], r"clang version (\S+)", "19.",
     "MC/DC counting and the libFuzzer harnesses"),
    ("arm-none-eabi-gcc", ["arm-none-eabi-gcc", "-dumpfullversion"], r"(\S+)", "12.",
     "the firmware's flash and stack budgets and the PIL instruction counts"),
    ("qemu-system-arm", ["qemu-system-arm", "--version"], r"version (\S+)", "7.",
     "the PIL runs and their instruction counts"),
    ("valgrind", ["valgrind", "--version"], r"valgrind-(\S+)", "3.19",
     "memcheck's error set"),
]


def version(cmd: list[str], regex: str) -> str | None:
    """The tool's version, or None when it is not installed."""
    if shutil.which(cmd[0]) is None:
        return None
    r = subprocess.run(cmd, capture_output=True, text=True, check=False)
    first = (r.stdout or r.stderr).strip().splitlines()[:1] or [""]
    m = re.search(regex, first[0])
    return m.group(1) if m else first[0]


def matches(v: str, pin: str) -> bool:
    """v within pin: a prefix ("12.") or a minimum ("3.11+")."""
    if pin.endswith("+"):
        nums = lambda s: [int(x) for x in re.findall(r"\d+", s)]  # noqa: E731
        return nums(v)[:len(nums(pin))] >= nums(pin)
    return v.startswith(pin)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--warn", action="store_true", help="report mismatches, do not fail")
    ap.add_argument("--only", nargs="+", metavar="NAME", choices=[p[0] for p in PINS])
    a = ap.parse_args(argv)
    bad = 0
    for name, cmd, regex, pin, decides in PINS:
        if a.only and name not in a.only:
            continue
        v = version(cmd, regex)
        if v is None:
            print(f"tools: {name}: not installed (make deps installs it)")
        elif matches(v, pin):
            print(f"tools: {name} {v} (pinned {pin}{'' if pin.endswith('+') else '*'})")
        else:
            bad += 1
            print(f"tools: {name} {v} is not the pinned {pin}*: it decides {decides}",
                  file=sys.stdout if a.warn else sys.stderr)
    if bad and not a.warn:
        print(f"tools: {bad} tool(s) outside their pins (above). Install Debian 12's packages "
              "(make deps), or run make test TOOL_PINS=warn to go on knowing those gates may "
              "disagree", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
