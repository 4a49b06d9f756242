"""prior_study.py's helpers on hand-made values (no reference run)."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import prior_study as ps  # noqa: E402


def test_parse_spec_modes_and_keys():
    assert ps.parse_spec("today") == ("today", {})
    assert ps.parse_spec("mu0=0.3") == ("set", {"mu0": 0.3})
    assert ps.parse_spec("sd0=0.05,sd0_common=0.15") == ("set", {"sd0": 0.05,
                                                                 "sd0_common": 0.15})
    assert ps.parse_spec("warm") == ("warm", {})
    assert ps.parse_spec("cross,sd0_common=0.1") == ("cross", {"sd0_common": 0.1})
    # step 5's second centre (MONITOR.md section 16), alone or with the prior
    assert ps.parse_spec("info_at=1,info_mu_h=0.3") == ("set", {"info_at": 1.0,
                                                                "info_mu_h": 0.3})
    assert ps.parse_spec("warm,info_at=2") == ("warm", {"info_at": 2.0})


@pytest.mark.parametrize("spec", ["", "mu0", "mu0=", "q_mu=0.1", "mu0=0.3,mu0=0.4",
                                  "warm,mu0=0.3", "cross,mu0=0.9", "sd0=abc"])
def test_parse_spec_refuses(spec):
    """Unknown or repeated keys, a missing value, a mu0 where warm/cross choose it, a word."""
    with pytest.raises(ValueError):
        ps.parse_spec(spec)


def test_kept_mu_is_the_mean_of_the_wheels():
    assert ps.kept_mu(np.array([0.2, 0.4, 0.2, 0.4])) == pytest.approx(0.3, abs=1e-15)


def test_cross_donor_is_the_other_end():
    """A low-mu start (mean 0.3, and a split 0.2 / 0.9 with mean 0.55 < 0.6) takes the
    high-mu log's end; a high-mu start (0.85) the low-mu log's."""
    assert ps.cross_donor(np.full(4, 0.3)) == ps.CROSS_HIGH
    assert ps.cross_donor(np.array([0.2, 0.9, 0.2, 0.9])) == ps.CROSS_HIGH
    assert ps.cross_donor(np.full(4, 0.85)) == ps.CROSS_LOW


def test_count_bad_needs_settled_valid_and_error():
    """Four pairs off by 0.3: one settled and valid (counted), one valid not settled, one
    settled not valid, one settled and valid but off by exactly 0.25 (not beyond)."""
    truth = np.full((1, 4), 0.5)
    mu = np.array([[0.8, 0.8, 0.8, 0.75]])
    valid = np.array([[1, 1, 0, 1]])
    s = np.array([[True, False, True, True]])
    assert ps.count_bad(mu, valid, truth, s) == 1


def test_no_loss_over_the_logs_meeting_it_before():
    """a meets and falls 0.10, b does not meet and falls 0.50 (not counted), c meets and
    rises, d meets without excited samples (skipped)."""
    base = {"a": {"meets": True, "exc": 0.9}, "b": {"meets": False, "exc": 0.8},
            "c": {"meets": True, "exc": 0.5}, "d": {"meets": True, "exc": None}}
    new = {"a": {"exc": 0.8}, "b": {"exc": 0.3}, "c": {"exc": 0.7}, "d": {"exc": 0.4}}
    drop, log = ps.no_loss(base, new)
    assert drop == pytest.approx(0.1, abs=1e-12) and log == "a"
    assert ps.no_loss({"c": base["c"]}, {"c": new["c"]}) == (0.0, None)


def test_group_counts_in_summary_order():
    figs = {"x.mf": {"meets": True, "bad": 0}, "y.mf": {"meets": False, "bad": 7},
            "f": {"meets": True, "bad": 2}}
    group_of = {"x.mf": "mf", "y.mf": "mf", "f": "fault"}
    gc = ps.group_counts(figs, group_of)
    assert list(gc) == ["mf", "fault"]
    assert gc["mf"] == (1, 2, 7) and gc["fault"] == (1, 1, 2)


def test_updated_share_counts_updates_among_the_evaluated_steps():
    """Status 2 (low speed) is not evaluated; 0 and 1 updated; 3 (held) and 4 (mismatch) did
    not: here 3 of the 6 evaluated steps over the two runs."""
    runs = {"a": {"status": np.array([2, 0, 1, 3])}, "b": {"status": np.array([2, 2, 4, 0, 3])}}
    assert ps.updated_share(runs) == 0.5


def test_parse_spec_takes_the_hypothesis_keys():
    assert ps.parse_spec("info_at=2,hyp_update=1,hyp_lr_min=2") == (
        "set", {"info_at": 2.0, "hyp_update": 1.0, "hyp_lr_min": 2.0})


def test_parse_spec_takes_the_floor_keys():
    """Section 19's step-7 floor level is a SPEC key like the prior's."""
    assert ps.parse_spec("sd_floor_ref=0.5") == ("set", {"sd_floor_ref": 0.5})
    assert ps.parse_spec("sd_floor_hold=2") == ("set", {"sd_floor_hold": 2.0})


def test_parse_spec_takes_the_local_information_keys():
    """Section 20's step-6 bound is a SPEC key like the prior's."""
    assert ps.parse_spec("sd_local=0.001,sd_local_at=1") == (
        "set", {"sd_local": 0.001, "sd_local_at": 1.0})


def test_parse_spec_takes_the_relinearisation_keys():
    """Section 21's re-linearised step 6 is a SPEC key like the prior's."""
    assert ps.parse_spec("relin_steps=4,relin_gate=1") == (
        "set", {"relin_steps": 4.0, "relin_gate": 1.0})
    assert ps.parse_spec("relin_iter=3") == ("set", {"relin_iter": 3.0})


def test_false_alarm_is_the_largest_mismatch_share_on_a_clean_mf_log():
    """Only the MF group counts (faults, wrong tyre data, banked and Dugoff logs do not)."""
    figs = {"a.mf": {"mismatch": 0.01}, "b.mf": {"mismatch": 0.03}, "c": {"mismatch": 0.5},
            "drop.d.mf": {"mismatch": 0.4}, "bank_curve_neg5.mf": {"mismatch": 0.9}}
    group_of = {"a.mf": "mf", "b.mf": "mf", "c": "dugoff", "drop.d.mf": "fault",
                "bank_curve_neg5.mf": "bank"}
    assert ps.false_alarm(figs, group_of) == 0.03
    assert ps.false_alarm({}, {}) == 0.0
