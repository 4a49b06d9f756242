"""Tests of scripts/firmware/pil_profile.py's parts that need neither QEMU nor valgrind: the
reading of callgrind_annotate's output and the table of per-function counts."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import pil_profile  # noqa: E402

ANNOTATE = """\
--------------------------------------------------------------------------------
Ir
--------------------------------------------------------------------------------
2,000 (100.0%)  PROGRAM TOTALS

--------------------------------------------------------------------------------
Ir            file:function
--------------------------------------------------------------------------------
1,200 (60.00%)  src/numerics/fxmath_q31.c:rfe_q31_atan2_quad1 [/x/default.sckf]
  600 (30.00%)  src/numerics/qr_q31.c:rfe_qr_tria_q31 [/x/default.sckf]
  100 ( 5.00%)  src/numerics/qr_q31.c:rfe_qr_tria_q31'2 [/x/default.sckf]
  100 ( 5.00%)  ???:memcpy [/usr/lib/libc.so.6]
"""


def test_parse_annotate_per_step_with_recursion_merged():
    prof = pil_profile.parse_annotate(ANNOTATE, steps=10)
    assert prof["total"] == 200.0
    assert prof["functions"] == [["rfe_q31_atan2_quad1", 120.0], ["rfe_qr_tria_q31", 70.0], ["memcpy", 10.0]]


def test_parse_annotate_without_totals_is_none():
    assert pil_profile.parse_annotate("no profile here\n", steps=1) is None


def test_table_rows_shares_and_rest():
    run = {"core": "m4f", "profile": {"total": 1000.0, "functions": [
        ["f", 600.0, 2.0, "a.o"], ["g", 300.0, 1.0, "b.o"], ["h", 100.0, 5.0, "libgcc"]]}}
    host = {"total": 800.0, "functions": [["f", 500.0], ["h", 100.0]]}
    lines = pil_profile.table([run], host)
    rows = {ln.split("|")[1].strip(): [c.strip() for c in ln.split("|")[2:-1]] for ln in lines[2:]}
    assert rows["`f`"] == ["a.o", "600 (60.0 %)", "2.0", "500"]
    assert rows["`g`"] == ["b.o", "300 (30.0 %)", "1.0", "–"]   # not a host function: inlined there
    # every function is listed here, so nothing is left for the rest row on the target; the
    # host's 200 instructions outside the listed functions are
    assert rows["every other function"] == ["", "0 (0.0 %)", "", "200"]
    assert rows["**the step**"] == ["", "**1,000**", "", "**800**"]
