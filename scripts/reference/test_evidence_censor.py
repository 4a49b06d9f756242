"""Step 6's accumulated-evidence censoring (`evid_delta` > 0; reference only, not in the C
library; docs/MONITOR.md section 14): off (0, both presets) the run is today's, bit for bit;
on, a side's downward move is censored (zero gain row) while its evidence L against the upper
alternative is below evid_l_min, once the side has had evid_free updates on its own
information; L starts at evid_l0.
(run: .venv/bin/python -m pytest scripts/reference/test_evidence_censor.py -q)"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from . import estimate, filters, logs, params, trusted

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
# brake_in_turn.mf: 10 s of Magic Formula truth 0.85 with updates from 0.25 s (MONITOR.md
# section 8); about 1 s to run, 2 s with the evidence on.
LOG = os.path.join(REPO, "scenarios", "brake_in_turn.mf.csv")

# A linear measurement with orthogonal columns and diagonal prior and noise: the gain is
# diagonal and positive, so the sign of each side's move is the sign of its innovation row.
H = np.array([[2.0, 0.0], [0.0, 3.0], [0.0, 0.0]])
X0, S0, S_R = np.array([0.4, 0.5]), np.diag([0.1, 0.2]), np.diag([0.05, 0.05, 0.05])


def _log():
    if not os.path.exists(LOG):
        pytest.skip(f"{LOG} not found")
    return logs.read_csv_log(LOG)


def _params(log, **evid):
    p = params.resolve(log.meta, None, source=LOG, preset="default")
    p.update({f"evid_{k}": v for k, v in evid.items()})
    return p


def _filter():
    return filters.SCKF(X0, S0, np.zeros((2, 2)), S_R)


def _step(ev, p, f, y, own, monkeypatch, lam):
    """One Evidence.update on the linear case with Lambda = lam (the model-based evidence is
    replaced: this checks the decision and the recursion, not the tyre model)."""
    monkeypatch.setattr(trusted, "upper_evidence", lambda *a, **k: np.array(lam, dtype=float))
    return ev.update(p, f, None, None, None, y, lambda pts: H @ pts, S_R, S_R, own)


def test_off_is_todays_run_bit_for_bit(monkeypatch):
    """evid_delta = 0 (the default of both presets) never enters the evidence path, whatever
    the other evid_* keys say: the same mean, sd, flags and status as the default run, exactly
    (the same float64 operations), and no censoring output."""
    assert params.DEFAULTS["evid_delta"] == 0.0
    assert not any(k.startswith("evid_") for pre in params.PRESETS.values() for k in pre)
    log = _log()
    ref = trusted.run(log, _params(log))

    def fail(*a, **k):
        raise AssertionError("the evidence censoring ran with evid_delta = 0")
    monkeypatch.setattr(trusted.Evidence, "update", fail)
    out = trusted.run(log, _params(log, l0=5.0, free=3.0, l_min=0.5, n=10.0))
    assert "censored" not in out and "evid_L" not in out
    for k in ("mu", "sd", "valid", "status"):
        assert np.array_equal(out[k], ref[k]), k
    assert np.any(ref["status"] == 0)      # the run did update (so the path was reachable)


def test_censors_a_downward_move_only_when_armed_and_short_of_evidence(monkeypatch):
    """Both sides move down (y below h(x0) on both rows). Update 1: no side armed yet
    (evid_free 2), both move although L is short. Update 2: both armed; side 0's L =
    rho 3 + 3 >= 2 keeps its move, side 1's L = rho 0.5 + 0.5 < 2 censors it: its mean is
    exactly the previous one (a zero gain row: x + 0), side 0's falls."""
    p = dict(params.resolve(preset="default"), evid_delta=0.25, evid_l_min=2.0, evid_n=100.0,
             evid_l0=0.0, evid_free=2.0)
    rho = math.exp(-1.0 / 100.0)
    ev, f = trusted.Evidence(p, 2), _filter()
    y = H @ (X0 - 0.1)
    kept = _step(ev, p, f, y, [True, True], monkeypatch, [3.0, 0.5])
    assert kept.all() and np.all(f.x < X0)
    x1 = f.x.copy()
    kept = _step(ev, p, f, y, [True, True], monkeypatch, [3.0, 0.5])
    assert np.array_equal(kept, [True, False])
    assert f.x[1] == x1[1] and f.x[0] < x1[0]
    assert ev.L == pytest.approx([3.0 * rho + 3.0, 0.5 * rho + 0.5], rel=1e-15)  # two roundings
    assert np.array_equal(ev.n_own, [2, 2])


def test_counts_only_own_information_and_never_censors_an_upward_move(monkeypatch):
    """A side counts towards evid_free only on updates with its own information (own[j]);
    an upward move is kept whatever L says."""
    p = dict(params.resolve(preset="default"), evid_delta=0.25, evid_l_min=2.0, evid_n=100.0,
             evid_l0=0.0, evid_free=1.0)
    ev, f = trusted.Evidence(p, 2), _filter()
    kept = _step(ev, p, f, H @ (X0 - 0.1), [True, False], monkeypatch, [-5.0, -5.0])
    assert np.array_equal(kept, [False, True])     # side 0 armed by this update, side 1 not
    assert np.array_equal(ev.n_own, [1, 0])
    x1 = f.x.copy()
    kept = _step(ev, p, f, H @ (x1 + 0.1), [True, True], monkeypatch, [-5.0, -5.0])
    assert kept.all() and np.all(f.x > x1)


def test_start_at_the_threshold_censors_the_first_step_short_of_it(monkeypatch):
    """evid_l0 = evid_l_min: the first update keeps a move whose Lambda makes up the decay
    (L = 2 rho + 0.05 = 2.030 >= 2) and censors one that does not (2 rho + 0 = 1.980)."""
    p = dict(params.resolve(preset="default"), evid_delta=0.25, evid_l_min=2.0, evid_n=100.0,
             evid_l0=2.0, evid_free=0.0)
    ev, f = trusted.Evidence(p, 2), _filter()
    kept = _step(ev, p, f, H @ (X0 - 0.1), [True, True], monkeypatch, [0.05, 0.0])
    assert np.array_equal(kept, [True, False])
    assert f.x[1] == X0[1] and f.x[0] < X0[0]


def test_cap_leaves_a_side_near_mu_max_uncensored(monkeypatch):
    """evid_cap 1: a side whose alternative mu_max clips (x + 0.25 > mu_max) is not censored,
    the other (0.4 + 0.25 <= mu_max) is, with the same L short of evid_l_min; evid_cap 0
    censors both."""
    for cap, want in ((1.0, [False, True]), (0.0, [False, False])):
        p = dict(params.resolve(preset="default"), evid_delta=0.25, evid_l_min=2.0,
                 evid_n=100.0, evid_l0=0.0, evid_free=0.0, evid_cap=cap)
        x0 = np.array([0.4, p["mu_max"] - 0.1])
        f = filters.SCKF(x0, S0, np.zeros((2, 2)), S_R)
        kept = _step(trusted.Evidence(p, 2), p, f, H @ (x0 - 0.1), [True, True], monkeypatch,
                     [0.0, 0.0])
        assert np.array_equal(kept, want), cap
        assert np.array_equal(f.x[~kept], x0[~kept]) and np.all(f.x[kept] < x0[kept])


def test_on_a_log_the_censored_side_keeps_its_mean_and_lacked_evidence():
    """evid_delta 0.25 on brake_in_turn.mf: moves are censored; at each censored side-step the
    side's unprojected mean is exactly the previous step's estimate and its recorded L (after
    the step's update of L) is below evid_l_min; with evid_free 5 no side is censored before
    its fifth update on its own information."""
    log = _log()
    on = trusted.run(log, _params(log, delta=0.25))
    cens, L = on["censored"], on["evid_L"]
    assert cens.sum() > 0
    k_c, side = np.nonzero(cens)
    assert np.all(k_c > 0)
    wheel = np.where(side == 0, 0, 1)        # fl (left), fr (right): the side's front wheel
    assert np.array_equal(on["mu_unprojected"][k_c, wheel], on["mu"][k_c - 1, wheel])
    assert np.all(L[k_c, side] < 2.0)
    free = trusted.run(log, _params(log, delta=0.25, free=5.0))
    own = np.cumsum((free["info"] >= 25.0) & (free["status"] != 2)[:, None], axis=0)
    k_f, side_f = np.nonzero(free["censored"])
    assert np.all(own[k_f, side_f] >= 5)


def test_estimate_log_records_the_keys_only_when_set():
    """The reference-only keys stay out of an estimate log's metadata at their defaults."""
    p = params.resolve(preset="default")
    keys = [k for k, _ in estimate.metadata("sckf", p["tyre"], LOG, p, None, "default")]
    assert not any(k.startswith("evid_") for k in keys)
    p["evid_delta"] = 0.25
    meta = dict(estimate.metadata("sckf", p["tyre"], LOG, p, None, "default"))
    assert meta["evid_delta"] == 0.25 and "evid_free" not in meta
