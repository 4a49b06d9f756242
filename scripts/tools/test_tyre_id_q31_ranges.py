"""The measurement behind docs/FIXED_POINT.md "Tyre identifier: why there is no Q31 twin"
(scripts/tools/tyre_id_q31_ranges.py), on the first 300 samples of the high-mu ramp steer
(256 particles, APF, seed 1: 20 draws, about 0.5 s). The page's table covers every sample of
every log of scenarios/tyre_id/ (nine); these check the three claims the section rests on,
each of which the measurement could contradict.
"""
import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(ROOT / "scripts" / "tools"))
from reference import tyre_id as T  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402
import tyre_id_q31_ranges as Q  # noqa: E402

LOG, N_STEPS = "tid_ramp_steer_high_mu", 300


@pytest.fixture(scope="module")
def probe():
    return Q.measure(LOG, 256, "apf", N_STEPS)


def test_the_probe_changes_nothing_the_filter_computes(probe):
    """The instrumented run is the reference's: same statuses, same means. The probe only
    reads; a changed path (another parent, another draw) would move the means by at least
    the smallest parent weight's share (1e-6 relative, the page's table), so 1e-12 relative
    (about 4500 ulp, room for nothing but identical arithmetic in another call order) tells
    the two apart."""
    _, stats, est = probe
    c = read_csv_log(str(ROOT / "scenarios" / "tyre_id" / f"{LOG}.csv")).columns
    ref = T.run(c, {"tid_n": 256.0, "tid_filter": "apf"}, seed=1, n_steps=N_STEPS)
    assert stats["steps"] == N_STEPS and stats["draws"] > 0
    assert [e.status for e in est] == list(ref["status"].astype(int))
    for k in ("beta", "r", "D_f", "K_f", "D_r", "K_r"):
        np.testing.assert_allclose([e.mean[k] for e in est], ref[k], rtol=1e-12, atol=0.0)


def test_log_weight_spread_exceeds_what_q31_exp_resolves(probe):
    """A Q31 weight exp(l - M) resolves l - M down to ln 2^-31 = -21.49: below that it rounds
    to 0. The log weights within one normalisation spread far wider (the page: up to 563), so
    a fixed-point log-sum-exp must flush particles to zero weight; the section claims it does
    on many steps, not on one."""
    _, st, _ = probe
    assert st["max_spread"] > -Q.LN_Q31
    assert st["norms_with_below"] >= 0.1 * st["norms"]


def test_flushing_to_zero_drops_no_parent_but_decisions_sit_inside_the_error(probe):
    """The two halves of the section's conclusion. (1) Exact and bounded is possible for the
    weights: every parent drawn had a normalised weight above 2^-31, so a Q31 weight (LSB
    2^-31) that flushes the rest to 0 would have lost none of them. (2) It cannot track the
    double filter: some draw position lies within 2^-14 of a cumulative-weight boundary. The
    relative weight error a Q31 likelihood would carry per step, derived in the page from the
    Q31 Magic Formula's force bound, is up to 1.9e-4 = 2^-12.4, so 2^-14 is the conservative
    side: a position that close to a boundary could go to the neighbouring parent in the
    fixed-point twin, and the two filters part there."""
    _, st, _ = probe
    assert st["min_parent_w"] > 2.0 ** -31
    assert st["gaps_below_2^-14"] > 0
    assert math.isfinite(st["min_gap"]) and st["min_gap"] < 2.0 ** -14
