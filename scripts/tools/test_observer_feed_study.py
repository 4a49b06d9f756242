"""observer_feed_study.py's bookkeeping on data written here (no replay run)."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import observer_feed_study as fs  # noqa: E402
from demo import WHEELS  # noqa: E402


def test_swap_log_replaces_only_the_named_columns(tmp_path):
    """The metadata and every other column stay as written; the named ones take the new values
    row by row."""
    src = tmp_path / "a.csv"
    src.write_text("# dt = 0.01\n# seed = 3\nt,vx,vy,ax\n0.0,20.0,0.1,0.5\n0.01,20.1,0.2,0.6\n")
    new = tmp_path / "b.csv"
    fs.swap_log(src, new, {"vy": [1.5, -2.25]})
    assert new.read_text() == ("# dt = 0.01\n# seed = 3\nt,vx,vy,ax\n0.0,20.0,1.5,0.5\n"
                               "0.01,20.1,-2.25,0.6\n")


def _logs(t, truth, meas_mu, meas_valid, obs_mu, obs_valid):
    """A sensor log and two estimate logs with the same values on every wheel."""
    sensor = {"t": t, **{f"mu_{w}": truth for w in WHEELS}}
    meas = {**{f"mu_{w}": meas_mu for w in WHEELS}, **{f"valid_{w}": meas_valid for w in WHEELS}}
    obs = {**{f"mu_{w}": obs_mu for w in WHEELS}, **{f"valid_{w}": obs_valid for w in WHEELS}}
    return sensor, meas, obs


def test_valid_split_counts_the_settled_samples_of_each_set():
    """The first second is not settled (mu_replay's settle start): its sample is left out
    although both runs claim it. Of the settled ones: one valid in both (errors 0.1 and 0.2),
    one only with the observer (0.3), one only measured (0.4), one in neither: counts are per
    wheel, so 4 times each."""
    t = [0.0, 1.0, 1.5, 2.0, 2.5]
    sensor, meas, obs = _logs(t, [0.5] * 5,
                              [9.0, 0.6, 0.5, 0.9, 0.5], [1, 1, 0, 1, 0],
                              [9.0, 0.7, 0.8, 0.5, 0.5], [1, 1, 1, 0, 0])
    cells = [c.strip() for c in fs.valid_split(sensor, meas, obs).split("|")]
    assert cells == ["4", "0.100", "0.200", "4", "0.300", "4", "0.400"]


def _table(measured, off, on):
    return {"x.csv": {"measured": measured, "off": off, "on": on}}


def test_rule_misses_rmse_half_and_consistency_half():
    """The RMSE half: up by more than 0.02 (0.13 against 0.10 misses, 0.115 does not). The
    consistency half counts only where the measured run is at least 90 % (95 % → 85 %
    misses, 80 % → 70 % does not). A log never valid with measured velocities is not judged;
    one not valid on observer inputs has no RMSE to miss."""
    assert fs.rule_misses(_table((0.10, 0.5, 0.95), None, (0.13, 0.5, 0.95)), "on") == \
        (["x.csv"], [])
    assert fs.rule_misses(_table((0.10, 0.5, 0.95), None, (0.115, 0.5, 0.85)), "on") == \
        ([], ["x.csv"])
    assert fs.rule_misses(_table((0.10, 0.5, 0.80), None, (0.115, 0.5, 0.70)), "on") == ([], [])
    assert fs.rule_misses(_table((None, 0.0, 1.0), None, (0.5, 0.3, 0.1)), "on") == ([], [])
    assert fs.rule_misses(_table((0.10, 0.5, 0.95), None, (None, 0.0, 1.0)), "on") == ([], [])


def test_costs_valid_share_and_never_excited():
    """A log meeting the rule with "off" whose valid share drops by more than 5 points is a
    cost (40 % → 30 %), by 5 points or less not (40 % → 36 %); a log missing it with "off" is
    not counted; a log 0 % valid with both measured velocities and "off" that becomes valid
    is listed."""
    meets = (0.10, 0.40, 0.95)
    assert fs.costs(_table(meets, meets, (0.10, 0.30, 0.95)), "on") == (["x.csv 40 % → 30 %"], [])
    assert fs.costs(_table(meets, meets, (0.10, 0.36, 0.95)), "on") == ([], [])
    missed = (0.20, 0.40, 0.95)
    assert fs.costs(_table(meets, missed, (0.10, 0.10, 0.95)), "on") == ([], [])
    never = (None, 0.0, 1.0)
    assert fs.costs(_table(never, never, (0.2, 0.01, 1.0)), "on") == ([], ["x.csv"])
