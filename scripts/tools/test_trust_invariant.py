"""Issue 17's trust invariant over every bundled log, in float, double and Q31 (trust_invariant.py).

Runs build/mu_replay (make build/mu_replay; skipped without it) with the default preset on the
72 logs of scenarios/ and scenarios/faults/ in the three precisions, about 15 s. A log meets the
invariant when consistency when valid >= 0.9, RMSE when valid <= 0.10 and the worst case when
valid <= 0.25 (issue 17's targets, exact: no tolerance is added to them), or when it is never
valid.

The invariant does not hold on every log yet (issue 17 stays open). KNOWN_FAILURES names each
log where it fails today and why; the test asserts both ways, so it fails when a log outside
the list breaks the invariant (a regression) and when a listed log starts to meet it (then the
entry is removed: the list can only shrink honestly). The three precisions agree on every
log's verdict (measured; they are asserted separately).

Healed by the rule "never valid on a projection bound" (ESTIMATOR.md step 9): hard_brake_low_mu
(Dugoff truth: consistency when valid 80 % -> 99 %) and faults/offset_ax.cruise.mf (valid at
mu_min, error 0.80, in the monitor's warm-up: now never valid). Healed by the jump hold
(ESTIMATOR.md step 9): split_mu_hard_brake.mf and .nf (a jump at the brake onset, worst 0.467 ->
0.071 and 0.563 -> 0.141), faults/spike_ax.hard_brake_low_mu.mf (0.451 -> 0.076) and
faults/spike_ay.sine_steer_low_mu.mf (0.468 -> 0.237). Healed by the stale-wheel-speed rule
(ESTIMATOR.md step 9; docs/MONITOR.md section 9): faults/freeze_omega_fl.hard_brake_low_mu.mf
(worst 0.676 -> 0.076) and faults/freeze_omega_fl.sine_steer_low_mu.mf (0.424 -> 0.168); by the
yaw-rate input check (step 0b): faults/spike_yaw_rate.sine_steer_low_mu.mf (0.359 -> 0.167).
Healed by the bound margin (valid_bound_k 3, step 9; docs/MONITOR.md section 11), claims near
mu_min: hard_brake_low_mu.nf (consistency 83 % -> 100 %), paper_low_mu_brake.nf and
paper_mu_step.nf (now never valid; were valid near mu_min, 0.327 and 0.120 off),
ramp_steer_low_mu.nf (worst 0.250 -> 0.110) and split_mu_hard_brake (0.800 -> 0.133).
44 of the 72 logs meet the invariant, in float, double and Q31 alike.
"""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import trust_invariant as ti  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
REPLAY = REPO / "build" / "mu_replay"

DUGOFF = "normalised-Dugoff truth: the free mu absorbs the wrong curve, the innovations stay consistent"
KNOWN_FAILURES = {
    # the tyre-model mismatch no innovation test sees (docs/MONITOR.md §5)
    **{f"{s}.csv": DUGOFF for s in (
        "accel_low_mu", "brake_in_turn", "brake_in_turn.nf", "hard_brake_high_mu",
        "hard_brake_high_mu.nf",
        "mu_step_hard_brake", "mu_step_hard_brake.nf", "paper_low_mu_brake",
        "paper_mu_step", "sine_steer_high_mu",
        "sine_steer_low_mu", "sine_steer_low_mu.nf", "split_mu_brake", "split_mu_brake.nf",
        # issue 17's new manoeuvres (measured: valid / RMSE / consistency / worst when valid,
        # the same in float, double and Q31)
        "double_lane_change_high_mu", "double_lane_change_high_mu.nf",   # 42 % / 0.156 / 95 % / 0.241
        "double_lane_change_low_mu", "double_lane_change_low_mu.nf",     # 3 % / 0.244 / 26 % / 0.671
        "ramp_steer_high_mu", "ramp_steer_high_mu.nf",                   # 46 % / 0.218 / 48 % / 0.372
        "ramp_steer_low_mu",                                             # 30 % / 0.083 / 76 % / 0.201
        "brake_in_turn_low_mu", "brake_in_turn_low_mu.nf")},            # 76 % / 0.150 / 1 % / 0.203
    # Magic Formula truth (accel_low_mu.mf and mu_step_hard_brake.mf meet it since the rear
    # wheels' hold, docs/ESTIMATOR.md step 9: consistency 88.8 % -> 92 %, worst 0.326 -> 0.112)
    # docs/MONITOR.md section 8: the two below are held estimates (status 3) from a few updates
    # at marginal information, read low through the truth's lateral curvature, that step 9's sd
    # rule keeps valid; the rules that heal them take right claims from other logs
    "brake_in_turn.mf.csv": "cornering before the brake: valid while held at 0.58-0.71 (truth "
        "0.85), sd 0.10-0.13: RMSE when valid 0.139, worst 0.273",
    "ramp_steer_high_mu.mf.csv": "ramp steer on mu 0.9: below the limit (utilisation 0.3-0.5) the "
        "truth's lateral curvature (E -1, the estimator's 0) reads as a lower mu, valid at 0.6 with "
        "sd 0.13: consistency when valid 78 %, RMSE 0.175, worst 0.308",
    # wrong tyre data (cx +30 %, cy -30 %, shape 30 % off the parameter file): in the sine steer
    # the softer true cornering stiffness drives one side to mu_min, valid with sd ~0.01, the
    # other to mu_max (not valid); the monitor does not fire. The ABS braking at the limit
    # then finds mu 0.85 again.
    "wrong_tyre_data.csv": "wrong tyre data: valid at mu_min in the sine steer, worst 0.800",
    "wrong_tyre_data.nf.csv": "wrong tyre data: valid at mu_min in the sine steer, worst 0.800",
    "wrong_tyre_data.mf.csv": "wrong tyre data: valid at mu_min in the sine steer, worst 0.800",
}


@pytest.fixture(scope="module")
def measured(tmp_path_factory):
    if not REPLAY.is_file():
        pytest.skip("needs build/mu_replay (make build/mu_replay)")
    return ti.measure(REPLAY, REPO / "scenarios", tmp_path_factory.mktemp("trust"))


def test_every_bundled_log_is_measured(measured):
    names = {n for n, _ in measured}
    assert len(names) == 72  # 19 manoeuvres x (Dugoff, noise-free Dugoff, MF) + 15 fault logs
    assert set(KNOWN_FAILURES) <= names  # no entry for a log that is not bundled


@pytest.mark.parametrize("real", ti.PRECISIONS)
def test_trust_invariant_on_every_log(measured, real):
    names = sorted({n for n, _ in measured})
    broken = [n for n in names if n not in KNOWN_FAILURES and not ti.meets(measured[(n, real)])]
    healed = [n for n in names if n in KNOWN_FAILURES and ti.meets(measured[(n, real)])]
    assert not broken, f"{real}: the invariant broke on {broken}: " + "; ".join(
        ti.row(n, measured) for n in broken)
    assert not healed, f"{real}: now met, remove from KNOWN_FAILURES: {healed}"


def test_figures_pool_the_wheels():
    """figures() by hand on two wheels with valid samples and two without: RMSE pooled as RMS
    by sample count, consistency by sample count, the worst case the larger maximum."""
    w = {"n_settled": 10, "n_valid": 0, "rmse_valid": None, "consistency_valid": None,
         "max_abs_err_valid": None}
    m = {"fl": dict(w, n_valid=4, rmse_valid=0.1, consistency_valid=1.0, max_abs_err_valid=0.2),
         "fr": dict(w, n_valid=1, rmse_valid=0.3, consistency_valid=0.0, max_abs_err_valid=0.3),
         "rl": w, "rr": w}
    f = ti.figures(m)
    assert f["valid"] == pytest.approx(5 / 40)
    assert f["rmse_valid"] == pytest.approx(((4 * 0.01 + 0.09) / 5) ** 0.5)
    assert f["cons_valid"] == pytest.approx(0.8)
    assert f["worst_valid"] == 0.3
    assert not ti.meets(f)  # consistency 0.8 < 0.9
    assert ti.meets(ti.figures({k: w for k in ti.WHEELS}))  # never valid: claims nothing
