"""Tests of scripts/firmware/firmware_pil.py's call stack (next_stack), which the inclusive
counts of make pil-profile are built on, and of the sigma-point tyre identifier's comparison
with the host double build (aux_compare_double, the bound of SCKF_EPS_PER_STEP) on rows of its
measured PIL output (testdata/tid_sckf_pil_rows.json)."""

import copy
import json
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import firmware_pil as fp  # noqa: E402

MAIN, STEP, F, G = 0, 1, 2, 3


def test_call_and_return():
    s = fp.next_stack((), MAIN, False)            # the step starts inside main
    s = fp.next_stack(s, STEP, True)              # call
    s = fp.next_stack(s, F, True)                 # call
    assert s == (MAIN, STEP, F)
    assert fp.next_stack(s, F, False) == s        # another block of F
    assert fp.next_stack(s, STEP, False) == (MAIN, STEP)   # return
    assert fp.next_stack(s, MAIN, False) == (MAIN,)        # two returns at once (a tail call's)


def test_tail_call_returns_to_the_callers_caller():
    s = fp.next_stack((MAIN, STEP, F), G, True)   # F ends with b G: G pushed above F
    assert s == (MAIN, STEP, F, G)
    assert fp.next_stack(s, STEP, False) == (MAIN, STEP)    # G's return lands in STEP


def test_recursion_pops_to_the_innermost_frame():
    s = fp.next_stack((MAIN, F), F, True)         # F calls itself
    s = fp.next_stack(s, G, True)
    assert fp.next_stack(s, F, False) == (MAIN, F, F)


# ---- tid_sckf: the target against the host double build -----------------------------------

SCKF = fp.AUX_ENTRIES["tid_sckf"]
NAMES = SCKF["fields"]
MEASURED = json.load(open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "testdata",
                                       "tid_sckf_pil_rows.json")))


def rows(key):
    return [{"discrete": tuple(r["discrete"]), "words": list(r["words"])} for r in MEASURED[key]]


def word(x):
    return f"{struct.unpack('<I', struct.pack('<f', x))[0]:08x}"


def moved(field, factor, row=9):
    """The measured target rows with one output of one row moved from the double value by
    `factor` times the bound (relative to the double value plus its sd for a mean, to itself
    for an sd), away from the target's own value so the target's difference only adds."""
    t, d = rows("target"), rows("double")
    bound = fp.aux_double_bound(SCKF, MEASURED["rows_run"])
    k = NAMES.index(field)
    b = fp.obs_value(d[row]["words"][k])
    scale = abs(b) + (fp.obs_value(d[row]["words"][NAMES.index("sd_" + field[5:])])
                      if field.startswith("mean_") else 0.0)
    sign = 1.0 if fp.obs_value(t[row]["words"][k]) >= b else -1.0
    t[row]["words"][k] = word(b + sign * factor * bound * scale)
    return t, d, bound


def test_sckf_bound_is_the_golden_tests_per_step_rule():
    # 300 eps of float32 per step: over the goldens' 200 steps 3.6e-3, within the 4e-3 of
    # test_tyre_id_golden_flt.c; over the entry's 400 rows twice that
    assert math.isclose(fp.aux_double_bound(SCKF, 200), 200 * 300 * 2.0 ** -24) and \
        fp.aux_double_bound(SCKF, 200) <= 4e-3
    assert math.isclose(fp.aux_double_bound(SCKF, 400), 7.152557373046875e-3)
    # with delta as a state (TYRE_ID.md §15.7, Tria 11 x 33): 363 eps per step, within the
    # golden test's SCKF_DS_TOL (5e-3) over its 200 steps
    ds = fp.AUX_ENTRIES["tid_sckf_dstate"]
    assert math.isclose(fp.aux_double_bound(ds, 200), 200 * 363 * 2.0 ** -24) and \
        fp.aux_double_bound(ds, 200) <= 5e-3
    # the other entries keep AUX_TOLERANCE (host float32 vs double)
    assert all(fp.aux_double_bound(k, 400) is None for t, k in fp.AUX_ENTRIES.items()
               if t not in ("tid_sckf", "tid_sckf_dstate"))


def test_sckf_measured_output_is_within_the_bound():
    t, d = rows("target"), rows("double")
    bound = fp.aux_double_bound(SCKF, MEASURED["rows_run"])
    bad, first, fields = fp.aux_compare_double(t, d, NAMES, bound)
    assert (bad, first) == (0, None)
    worst = max(e["max_rel_diff"] for e in fields.values())
    # measured: 5.5e-5 of value plus sd (sd_b_f), 1/130 of the bound; not bit-identical to double
    assert 1e-5 < worst < bound / 100
    assert fields["n_eff"]["bit_identical"] == len(t)      # NaN in both


def test_sckf_mean_just_beyond_the_bound_fails_and_just_within_passes():
    for field in ("mean_d_r", "mean_e_r", "mean_mu_r", "mean_r"):   # the four AUX_TOLERANCE failed
        t, d, bound = moved(field, 1.01)
        bad, first, fields = fp.aux_compare_double(t, d, NAMES, bound)
        assert bad == 1 and first.startswith("row 9:") and fields[field]["max_rel_diff"] > bound
        t, d, bound = moved(field, 0.99)
        assert fp.aux_compare_double(t, d, NAMES, bound)[0] == 0


def test_sckf_sd_beyond_the_bound_fails():
    t, d, bound = moved("sd_d_r", 1.01)
    assert fp.aux_compare_double(t, d, NAMES, bound)[0] == 1
    t, d, bound = moved("sd_d_r", 0.99)
    assert fp.aux_compare_double(t, d, NAMES, bound)[0] == 0


def test_sckf_pil_aux_perturb_fails():
    # PIL_AUX_PERTURB's change for this entry: bit 20 of the first sd's mantissa (2^-4 to 2^-3)
    t, d = rows("target"), rows("double")
    k = NAMES.index("sd_beta")
    t[5]["words"][k] = f"{int(t[5]['words'][k], 16) ^ (1 << 20):08x}"
    assert fp.aux_compare_double(t, d, NAMES, fp.aux_double_bound(SCKF, MEASURED["rows_run"]))[0] == 1


def test_sckf_status_nan_and_missing_rows_fail():
    bound = fp.aux_double_bound(SCKF, MEASURED["rows_run"])
    t, d = rows("target"), rows("double")
    t[3]["discrete"] = (t[3]["discrete"][0] ^ 1, t[3]["discrete"][1])
    assert fp.aux_compare_double(t, d, NAMES, bound)[0] == 1
    t = rows("target")
    t[3]["words"][NAMES.index("mean_mu_r")] = "7fc00000"        # NaN where double is finite
    assert fp.aux_compare_double(t, d, NAMES, bound)[0] == 1
    t = copy.deepcopy(rows("target"))[:-1]
    assert fp.aux_compare_double(t, d, NAMES, bound)[0] == 1
