"""The shape-ambiguity rules (scripts/reference/shape.py) and the claim docs/MONITOR.md section 6
makes from shape_results.py: a second tyre hypothesis takes a confidently wrong estimate's
valid flags away on a normalised-Dugoff-truth log, and takes as many away on a Magic Formula
log where the estimate is right (more than issue 17's 5 points of the excited-valid share).

And the one rule that keeps the Magic Formula logs' valid share (the likelihood-gated agreement
with the tolerance hypothesis) gains only where that hypothesis is the truth tyre.
The rules are checked on constructed inputs whose answer follows from the definitions, in
every test run. The claim is checked on three bundled logs through the reference itself (no
cache: nine runs, about 80 s of one core), so it runs where the claim is made: `make
shape-results` sets RFE_SHAPE_CLAIM=1 and runs these tests after writing the tables. `make
test` skips the three (a negative study result: no library behaviour depends on it, and
80 s is a tenth of make test's budget); the full 72-log figures are the page's tables.
"""
import math
import os
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "scripts"))
sys.path.insert(0, str(ROOT / "scripts" / "tools"))
from reference import monitor, params, shape  # noqa: E402
import shape_results as sr  # noqa: E402


def test_shadow_params_change_only_the_tyre():
    p = params.resolve(None, None, preset="default")
    q = shape.shadow_params(p, "paper")
    assert q["tyre"] == "paper" and p["tyre"] == "magic"
    assert {k for k in p if p[k] != q[k]} == {"tyre"}
    t = shape.shadow_params(p, "mf_tol", tol=0.3)
    assert {k for k in p if p[k] != t[k]} == {"cx", "cy", "shape_Cx", "shape_Cy"}
    assert t["cx"] == pytest.approx(1.3 * p["cx"]) and t["cy"] == pytest.approx(0.7 * p["cy"])
    assert t["shape_Cx"] == pytest.approx(0.7 * p["shape_Cx"])
    assert t["shape_Cy"] == pytest.approx(1.3 * p["shape_Cy"])
    with pytest.raises(ValueError):
        shape.shadow_params(p, "linear")


def run(mu, sd, valid):
    return {"mu": np.array(mu, float), "sd": np.array(sd, float),
            "valid": np.array(valid, int), "status": np.zeros(len(mu), int)}


def test_agree_rule():
    # rows: agree (|d| = 0.05 <= 2 sqrt(0.03^2 + 0.04^2) = 0.10); disagree (|d| = 0.11);
    # primary not valid; shadow not valid. Four wheels each, the same per row.
    a = run([[0.5] * 4] * 4, [[0.03] * 4] * 4, [[1] * 4, [1] * 4, [0] * 4, [1] * 4])
    b = run([[0.55] * 4, [0.61] * 4, [0.5] * 4, [0.5] * 4], [[0.04] * 4] * 4,
            [[1] * 4, [1] * 4, [1] * 4, [0] * 4])
    c = shape.combine(a, b, "agree", sd_valid=0.15)
    assert c["valid"][:, 0].tolist() == [1, 0, 0, 0]
    np.testing.assert_array_equal(c["mu"], a["mu"])     # the primary's estimate, untouched
    np.testing.assert_array_equal(c["sd"], a["sd"])


def test_sd_term_rule():
    # d = 0.12: sd = sqrt(0.05^2 + 0.12^2) = 0.13 <= 0.15, valid; d = 0.20: sd > 0.15, not
    # valid; shadow not valid: the primary's sd and flag
    a = run([[0.5] * 4] * 3, [[0.05] * 4] * 3, [[1] * 4] * 3)
    b = run([[0.62] * 4, [0.70] * 4, [0.9] * 4], [[0.02] * 4] * 3, [[1] * 4, [1] * 4, [0] * 4])
    c = shape.combine(a, b, "sd_term", sd_valid=0.15)
    assert c["sd"][:, 0] == pytest.approx([0.13, math.hypot(0.05, 0.20), 0.05])
    assert c["valid"][:, 0].tolist() == [1, 0, 1]


def test_likelihood_ratio_and_agree_lr():
    # nu = 0 in both; b's factor twice a's: l_a - l_b = 3 log 2 per step, so
    # L_k = 3 log 2 (1 - (1 - lam)^(k+1)) over the evaluated steps; a low-speed step (status 2)
    # leaves L unchanged
    n, dt = 6, 0.01
    ra = {"nu": np.zeros((n, 3)), "s_zz": np.array([np.eye(3)] * n), "status": np.zeros(n, int)}
    rb = dict(ra, s_zz=np.array([2 * np.eye(3)] * n))
    ra["status"][3] = 2
    ra["nu"][3] = np.nan
    lam = dt / (shape.TAU_LR + dt)
    evaluated = np.cumsum(ra["status"] != 2)
    want = 3 * math.log(2) * (1 - (1 - lam) ** evaluated)
    assert shape.likelihood_ratio(ra, rb, dt) == pytest.approx(want, rel=1e-12)
    # agree_lr: where L > 0 the primary's flag stands although the shadow disagrees
    a = run([[0.5] * 4] * 2, [[0.01] * 4] * 2, [[1] * 4] * 2)
    b = run([[0.9] * 4] * 2, [[0.01] * 4] * 2, [[1] * 4] * 2)
    c = shape.combine(a, b, "agree_lr", sd_valid=0.15, lr=np.array([-0.1, 0.1]))
    assert c["valid"][:, 0].tolist() == [0, 1]
    with pytest.raises(ValueError):
        shape.combine(a, b, "agree_lr", sd_valid=0.15)


claim = pytest.mark.skipif(os.environ.get("RFE_SHAPE_CLAIM") != "1",
                           reason="the study's claim runs with make shape-results (RFE_SHAPE_CLAIM=1)")

CLAIM_LOGS = ("paper_low_mu_brake.csv", "sine_steer_low_mu.mf.csv", "wrong_tyre_data.mf.csv")


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    paths = [(ROOT / "scenarios" / n).resolve() for n in CLAIM_LOGS]
    return sr.measure(paths, jobs=1, cache=tmp_path_factory.mktemp("shape"))


@claim
def test_second_hypothesis_heals_a_dugoff_log(measured):
    # normalised-Dugoff truth, mild braking on mu 0.2: valid ~99 % at an error ~0.33 today
    # (docs/RESULTS.md "Trust invariant"); the normalised-Dugoff shadow disagrees and the
    # "agree" rule withdraws the flags, so the log meets the invariant
    f = measured["paper_low_mu_brake.csv"]
    assert not sr.meets(f["today"])
    assert sr.meets(f["paper/agree"])
    # the tolerance hypothesis (the MF shape 30 % off) does not see this mismatch
    assert not sr.meets(f["mf_tol/agree"])


@claim
def test_second_hypothesis_costs_a_magic_formula_log(measured):
    # Magic Formula truth, where the estimate is right today: the same shadow disagrees with
    # it (its stiffness scales with mu) and the rule withdraws the flags there too, far beyond
    # issue 17's allowance of 5 points of the excited-valid share
    f = measured["sine_steer_low_mu.mf.csv"]
    assert sr.meets(f["today"])
    assert f["today"]["excited_valid"] - f["paper/agree"]["excited_valid"] > sr.MAX_DROP


@claim
def test_likelihood_gate_keeps_the_share_and_heals_only_its_own_truth(measured):
    # mf_tol/agree_lr: on the Magic Formula log the innovations favour the primary, the flags
    # stay (drop within the 5 points); on wrong_tyre_data.mf, whose truth tyre is exactly the
    # tolerance hypothesis (30 % off), the log meets the invariant; on the Dugoff-truth log,
    # whose curve is neither hypothesis, it does not
    mf = measured["sine_steer_low_mu.mf.csv"]
    assert mf["today"]["excited_valid"] - mf["mf_tol/agree_lr"]["excited_valid"] <= sr.MAX_DROP
    wrong = measured["wrong_tyre_data.mf.csv"]
    assert not sr.meets(wrong["today"]) and sr.meets(wrong["mf_tol/agree_lr"])
    assert not sr.meets(measured["paper_low_mu_brake.csv"]["mf_tol/agree_lr"])
