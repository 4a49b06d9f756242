"""first_update_noise.py: the conditioner's start-up sd against the reference's own Conditioner
(Monte Carlo), and the breakdown's identities on the first update of a log with its twin."""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import first_update_noise as fun  # noqa: E402
from reference import trusted  # noqa: E402  (first_update_noise put scripts on the path)

REPO = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("k", [0, 1, 25, 30, 200])
def test_conditioner_sd_is_the_conditioners(k):
    """trusted.Conditioner on N independent noise draws (true vx, ax, r all 0, so the r-coupling
    the formula neglects is exactly 0): the sample sd of its output k steps after its start.
    N = 40000: the sample sd's relative standard error is 1 / sqrt(2 N) = 0.35 %; 5 of them
    (1.8 %) as the tolerance (fixed seed, so not flaky)."""
    n, tau, dt, sd_v, sd_a = 40000, 0.3, 0.01, 0.05, 0.05
    rng = np.random.default_rng(17)
    c = trusted.Conditioner(tau, dt)
    zero = np.zeros(n)
    for _ in range(k + 1):
        vx, _ = c.step(sd_v * rng.standard_normal(n), zero, sd_a * rng.standard_normal(n),
                       zero, 0.0)
    assert np.std(vx) == pytest.approx(fun.conditioner_sd(k, tau, dt, sd_v, sd_a), rel=0.018)


def test_conditioner_sd_limits():
    """k = 0: the first raw sample's sd; tau = 0 (b = 1): the raw speed's at any k; large k: the
    recursion's fixed point var = ((1-b)^2 dt^2 sd_a^2 + b^2 sd_v^2) / (1 - (1-b)^2), solved by
    hand; 2000 steps leave (1-b)^4000 ~ 1e-56 of the start: to rounding."""
    assert fun.conditioner_sd(0, 0.3, 0.01, 0.05, 0.05) == 0.05
    assert fun.conditioner_sd(40, 0.0, 0.01, 0.05, 0.05) == pytest.approx(0.05, rel=1e-12)
    b = 0.01 / 0.31
    fixed = np.sqrt(((1 - b) ** 2 * (0.01 * 0.05) ** 2 + (b * 0.05) ** 2) / (1 - (1 - b) ** 2))
    assert fun.conditioner_sd(2000, 0.3, 0.01, 0.05, 0.05) == pytest.approx(fixed, rel=1e-9)


def test_breakdown_identities(tmp_path):
    """On the first update of brake_in_turn.mf with its noise-free twin (made here): every input
    made clean and y made clean leaves the model's own error at the truth, which section 20
    measured below 0.15 m/s^2 (E_y 0 against -1) and at 0.25 s (utilisation 0.16) is far
    smaller: 0.02 bounds it; the sensor term's realised error is y - y_clean, i.e. exactly the
    difference of the e row with and without clean y when the inputs are kept (to rounding)."""
    sys.path.insert(0, str(REPO / "scripts" / "data"))
    import make_scenarios
    make_scenarios.main(["--out", str(tmp_path), "--only", "brake_in_turn", "--tyre", "mf",
                         "--noise", "none", "--jobs", "1"])
    rec = fun.first_updates(REPO / "scenarios" / "brake_in_turn.mf.csv",
                            tmp_path / "brake_in_turn.mf.nf.csv", 1)
    assert len(rec) == 1
    r = rec[0]
    assert np.all(np.abs(r["rows"]["all clean (shape)"][0]) < 0.02)
    e, e_cy = r["rows"]["e"][0], r["rows"]["clean y"][0]
    np.testing.assert_allclose(e - e_cy, r["terms"]["sensor"][1], atol=1e-12)
    # the conditioner's start: brake_in_turn evaluates from its first sample, 0.25 s = 25 steps
    assert r["t"] == pytest.approx(0.25)
