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


INCLUSIVE = """\
2,000 (100.0%)  PROGRAM TOTALS
2,000 (100.0%)  /x/src/estimators/friction/friction_flt.c:rfe_friction_step_f32
2,000 (100.0%)  src/estimators/friction/friction_flt.c:rfe_friction_step_f32 [/x/default.sckf]
1,500 (75.00%)  /x/src/models/meas_flt.c:rfe_meas_eval_perturbed_f32
1,400 (70.00%)  src/models/meas_flt.c:rfe_meas_eval_perturbed_f32 [/x/default.sckf]
"""


def test_parse_annotate_inclusive_takes_the_largest_spelling():
    # each line holds all of the function's callees: summing the two spellings would double it
    prof = pil_profile.parse_annotate(INCLUSIVE, steps=10, inclusive=True)
    assert prof["functions"] == [["rfe_friction_step_f32", 200.0], ["rfe_meas_eval_perturbed_f32", 150.0]]


def test_parse_annotate_without_totals_is_none():
    assert pil_profile.parse_annotate("no profile here\n", steps=1) is None


def test_table_rows_shares_and_host_columns():
    run = {"core": "m4f", "profile": {"total": 1000.0, "functions": [
        ["step", 100.0, 1.0, "a.o", 1000.0], ["f", 600.0, 2.0, "a.o", 900.0], ["g", 300.0, 1.0, "b.o", 300.0]]}}
    host = {"total": 800.0, "inclusive": {"step": 800.0, "f": 700.0}, "self": {"step": 100.0, "f": 700.0}}
    lines = pil_profile.table([run], host)
    rows = {ln.split("|")[1].strip(): [c.strip() for c in ln.split("|")[2:-1]] for ln in lines[2:]}
    assert "`step`" not in rows   # it wraps the whole step: the total row says it
    assert rows["`f`"] == ["a.o", "900 (90.0 %)", "600", "2.0", "700", "700"]
    assert rows["`g`"] == ["b.o", "300 (30.0 %)", "300", "1.0", "–", "–"]   # inlined on the host
    assert rows["**the step**"] == ["", "**1,000**", "", "", "**800**", ""]
