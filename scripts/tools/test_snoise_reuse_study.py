"""Issue 21's step noise every N steps (trusted.StepNoiseReuse, snoise_reuse_study.py), on an
excerpt of brake_in_turn (to 1.5 s, about 150 steps, a few seconds).

Exact comparisons: with every = 1 the option computes the same columns by the same operations in
the same order as the option off, so equality is bit for bit (no tolerance); every = 2 reuses
columns computed at other inputs and x-, so the estimate must move (the assertion fails if the
option is not wired into step 4).
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import snoise_reuse_study as st  # noqa: E402

LOG = st.ROOT / "scenarios" / "brake_in_turn.csv"
STOP = 1.5


@pytest.fixture(scope="module")
def off():
    return st.run_one(LOG, "off", STOP)


def test_every_one_is_the_option_off_bit_for_bit(off):
    r = st.run_one(LOG, "every1", STOP)
    for k in ("mu", "sd", "valid", "status"):
        assert np.array_equal(r[k], off[k]), k
    assert r["share"] == 1.0 and r["used"] == off["used"] > 100


def test_every_two_reuses_and_moves_the_estimate(off):
    r = st.run_one(LOG, "every2", STOP)
    # every evaluating step of this excerpt is consecutive (vx above v_est_min from the start:
    # used equals the steps without status 2), so the columns are computed on every second
    assert r["used"] == off["used"] == int(np.sum(off["status"] != 2))
    assert r["share"] == math.ceil(r["used"] / 2) / r["used"]
    assert np.max(np.abs(r["mu"] - off["mu"])) > 0.0


def test_vxvy_every_one_is_the_option_off_bit_for_bit(off):
    # only vx's and vy's columns held, each recomputed every step: the same columns by the same
    # operations in the same order as off (no tolerance)
    r = st.run_one(LOG, "vxvy_every1", STOP)
    for k in ("mu", "sd", "valid", "status"):
        assert np.array_equal(r[k], off[k]), k
    assert r["share"] == 1.0 and r["used"] == off["used"]


def test_vxvy_every_two_reuses_only_vx_vy_and_moves_the_estimate(off):
    r = st.run_one(LOG, "vxvy_every2", STOP)
    assert r["used"] == off["used"]
    assert r["share"] == math.ceil(r["used"] / 2) / r["used"]
    # vx's and vy's reused columns move the estimate (fails if the subset is never reused) ...
    assert np.max(np.abs(r["mu"] - off["mu"])) > 0.0
    # ... and the other inputs' columns are recomputed: not the all-inputs variant (fails if
    # the subset is ignored and every column reused)
    a = st.run_one(LOG, "every2", STOP)
    assert np.max(np.abs(r["mu"] - a["mu"])) > 0.0
    assert st.reused_evals("vxvy_every2") == 4 and st.reused_evals("every2") == st.N_EVALS


def test_move_rule():
    # a tiny threshold: the noisy inputs move every step, every step recomputes (= off)
    r = st.run_one(LOG, "move1e-9", STOP)
    assert r["share"] == 1.0
    # a huge one without an age limit: computed once for the one evaluating stretch
    r = st.run_one(LOG, "move1e9", STOP)
    assert r["share"] == 1.0 / r["used"]


def test_bad_variants_are_refused():
    for bad in ("every0", "move0", "sometimes", "every2x", "vxvy_", "vxvy_every0", "vx_every2"):
        with pytest.raises(ValueError):
            st.parse_variant(bad)
    for inputs in ((), (1, 1), (-1,)):
        with pytest.raises(ValueError):
            st.trusted.StepNoiseReuse(every=2, inputs=inputs)
    assert st.parse_variant("off") is None
