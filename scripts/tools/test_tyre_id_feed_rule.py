"""The feed's taint and refresh (tyre_id_feed_rule.py, docs/MONITOR.md section 7) on made-up
samples at 64 Hz (a period of 1/64 s, exact in binary, so a refresh of 0.5 s is exactly 32
periods) whose decisions are counted here by hand: the defaults' thresholds are
k * sd_ay = 5 * 0.2 = 1 m/s^2 (outlier and excitation alike) and 0.5 m/s^2 of |ax|."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from tyre_id_feed_rule import FeedTaint  # noqa: E402

DT = 1.0 / 64.0


def run(rule, samples, i0=0):
    """samples: (ay, ax, ay_p, updated) per row, the first at row i0; per row (reset,
    may_feed after the step), feeding whenever it may (the feed's other conditions met)."""
    out = []
    for i, (ay, ax, ay_p, upd) in enumerate(samples, i0):
        reset = rule.before(ay, ax, ay_p)
        rule.after(i * DT, ay, upd)
        may = rule.may_feed(ay)
        if may:
            rule.fed()
        out.append((reset, may))
    return out


def test_a_spike_resets_once_and_holds_the_feed_for_the_refresh():
    rule = FeedTaint(refresh=0.5)
    cornering = [(2.0, 0.0, 2.0, True)] * 10                 # ay 2 m/s^2, predicted
    spike = [(7.0, 0.0, 2.0, True)]                           # 5 m/s^2 off: > 1 m/s^2
    second = [(6.0, 0.0, 2.0, True)]                          # another, while tainted
    res = run(rule, cornering + spike + [(2.0, 0.0, 2.0, True)] * 20 + second
              + [(2.0, 0.0, 2.0, True)] * 60)
    assert all(may for _, may in res[:10]) and not any(r for r, _ in res[:10])
    assert res[10] == (True, False)                 # the spike: reset, tainted
    assert res[31] == (False, False)                # the second: no reset (already tainted)
    # refreshed after 0.5 s of excited samples counted from the second spike: the 32nd row
    # after it adds the 32nd period (32 / 64 s = 0.5 s; 31 give less); but its ay (2 m/s^2)
    # is not below 1 m/s^2, so the feed waits for a calm sample
    assert rule.fresh >= 0.5 and not rule.tainted
    assert not any(may for _, may in res[32:])
    res = run(rule, [(2.0, 0.0, 2.0, True)] * 3 + [(0.5, 0.0, 0.5, True)]
              + [(2.0, 0.0, 2.0, True)] * 3, len(res))
    assert [may for _, may in res] == [False] * 3 + [True] * 4   # calm: fed, then as before


def test_a_small_residual_and_no_estimate_taint_nothing():
    rule = FeedTaint(refresh=0.5)
    # the first row (no estimate before it) 7 m/s^2 off; then 0.9 m/s^2 off (below 1) on a
    # step that does not update; then 7 m/s^2 off again, after that step: no prediction to test
    res = run(rule, [(9.0, 0.0, 2.0, True), (2.9, 0.0, 2.0, False), (9.0, 0.0, 2.0, True)])
    assert res == [(False, True)] * 3
    assert run(rule, [(9.0, 0.0, 2.0, True)], 3) == [(True, False)]  # now tested: 7 > 1
    assert FeedTaint(refresh=0.5, outlier_k=0.0, ref_ok=True).before(9.0, 0.0, 2.0) is False


def test_braking_taints_without_reset_and_coasting_never_refreshes():
    rule = FeedTaint(refresh=0.5)
    brake = [(0.3, -4.5, 0.3, True)] * 50            # |ax| 4.5 > 0.5: held
    coast = [(0.4, -0.1, 0.4, True)] * 300           # |ay| 0.4 < 1: no lateral force to learn
    res = run(rule, brake + coast)
    assert not any(r for r, _ in res)                # a hold never resets the model error
    assert not any(may for _, may in res)            # 4.7 s of coasting do not refresh it
    turn = [(1.5, 0.0, 1.5, True)] * 60
    res = run(rule, turn, len(brake + coast))
    # the first turn row adds the period from the last coasting row: 32 rows reach 0.5 s and
    # lift the taint; the turn's 1.5 m/s^2 is no calm sample, so nothing is fed yet
    assert not rule.tainted and not any(may for _, may in res)
    assert rule.may_feed(0.8) and not rule.may_feed(1.0)     # below 1 m/s^2 only
