"""tyre_id_m4_count.py: the particle count that fits the issue's budget, from made-up counts whose
answer is worked out by hand; the lower rate's decimation, scored on the samples it ran; the
table's pooling on made-up runs; and the page's table in step with the script's measured
counts (its configurations, counts and shares; the accuracy figures are the page's, from the
make target's run, not recomputed here)."""

import math
import re
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import tyre_id_m4_count as M  # noqa: E402
import tyre_id_results as R  # noqa: E402
from reference import tyre_id_sckf as TS  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402

# Made-up counts: 240,000 at 32 particles and 1,920,000 at 256, so 7,500 per particle
# ((1,920,000 - 240,000) / 224) and nothing fixed (240,000 - 32 x 7,500 = 0); 336,000 / 7,500
# = 44.8, so 44 fit; 256 particles need 1,920,000 / 336,000 = 5.71, so every 6th sample.
COUNTS = {32: (240000, 300000), 256: (1920000, 2500000)}


def test_budget_is_a_fifth_of_168_mhz_at_100_hz():
    assert M.BUDGET == 336000


def test_count_that_fits_on_made_up_counts():
    fixed, per = M.per_particle(COUNTS, (32, 256))
    assert per == pytest.approx(7500.0) and fixed == pytest.approx(0.0, abs=1e-6)
    assert M.n_fit(M.BUDGET, COUNTS, (32, 256)) == 44
    assert M.cost(44, COUNTS, (32, 256)) == (pytest.approx(330000.0), False)
    assert M.cost(256, COUNTS, (32, 256)) == (1920000.0, True)
    assert M.every_for(256, M.BUDGET, COUNTS, (32, 256), {}) == 6
    # one particle more than the fit is over the budget, the fit is not
    assert 45 * per > M.BUDGET >= 44 * per
    cfg = M.configurations(COUNTS, (32, 256), {})
    assert [(c[2], c[3]) for c in cfg] == [(44, 1), (256, 1), (1024, 1), (256, 6), (0, 1)]


def test_a_measured_pair_around_the_budget_decides_the_count():
    # the line says 44 (above), but 40 was measured at 330,000 (within) and 41 at 337,000
    # (over): 40 fits. A count between measurements is on the line through its two
    # neighbours: 36 halfway between 32 (240,000) and 40 (330,000) is 285,000; 300 beyond
    # the largest, on the line through the two largest, 41 (337,000) and 256 (1,920,000):
    # 1,583,000 / 215 a particle, 1,920,000 + 44 x 1,583,000 / 215 = 2,243,962.8; with
    # only 40 and 41 measured, 7,000 a particle and 42 at 344,000
    counts = {**COUNTS, 40: (330000, 400000), 41: (337000, 410000)}
    assert M.n_fit(M.BUDGET, counts, (32, 256)) == 40
    assert M.cost(36, counts) == (pytest.approx(285000.0), False)
    assert M.cost(300, counts) == (pytest.approx(2243962.79), False)
    only = {40: (330000, 400000), 41: (337000, 410000)}
    assert M.cost(42, only) == (pytest.approx(344000.0), False)
    lines = M.table([_run("tid_sine_steer", "apf", 40, 1, 1, 2.0, 0.1, 0.3, 0.05)], counts,
                    (32, 256), seeds=(1,), low={})
    assert "measured: 330,000 at 40 particles, 337,000 at 41" in lines[0]
    assert "up to 400,000 at 40" in lines[0] and "so 40 particles fit at 100 Hz" in lines[0]


def test_lower_rate_is_the_smallest_factor_measured_within_the_budget():
    # 256 particles measured at every 6th sample: 2,100,000 a step, over 6 x 336,000 =
    # 2,016,000; at every 7th: 2,150,000, within 7 x 336,000 = 2,352,000 (91.4 %): every 7,
    # 14.3 Hz, though the 100 Hz count (1,920,000) alone would say 6
    low = {(256, 6): (2100000, 2900000), (256, 7): (2150000, 2950000)}
    assert M.every_for(256, M.BUDGET, COUNTS, (32, 256), {}) == 6
    assert M.every_for(256, M.BUDGET, COUNTS, (32, 256), low) == 7
    assert M.low_cost(256, 7, low, COUNTS, (32, 256)) == (2150000.0, True)
    runs = [_run("tid_sine_steer", "apf", 256, 1, 7, 2.0, 0.1, 0.3, 0.05)]
    rows = [ln for ln in M.table(runs, COUNTS, (32, 256), (1,), low) if ln.startswith("| APF")]
    assert rows == ["| APF | 256 | 14.3 | 2,150,000 | 91 % | 2.0 | 2.0 | 0.100 | 0.100 "
                    "| 0.30 (0.30) | 0.050 |"]


def test_decimated_run_is_the_identifier_on_every_nth_sample():
    # the SCKF (deterministic) on every 5th sample of the sine steer: the same final K as
    # the filter run on those samples by hand, and not the 100 Hz run's
    log, every = "tid_sine_steer", 5
    res = R.measure((log, "sckf", 0, 1, False, every))
    c = read_csv_log(str(R.ROOT / "scenarios" / "tyre_id" / f"{log}.csv")).columns
    dec = {k: np.asarray(v)[::every] for k, v in c.items()}
    out = TS.run(dec, {})
    assert res["every"] == every
    assert res["mean_K_f"] == out["K_f"][-1]
    assert res["mean_K_f"] != TS.run(c, {})["K_f"][-1]
    # scored on the decimated samples: beta's RMSE from 0.5 s over those
    k0 = int(np.searchsorted(dec["t"], R.T_SKIP))
    beta = math.degrees(math.sqrt(float(np.mean((out["beta"][k0:] - dec["beta_true"][k0:]) ** 2))))
    assert res["beta"] == pytest.approx(beta, rel=1e-12)


def _run(log, filt, n, seed, every, curve, mulim, sdlin, beta):
    r = {"log": log, "filter": filt, "n": n, "seed": seed, "every": every, "beta": beta}
    for a in "fr":
        r[f"curve_{a}"], r[f"mulim_{a}"], r[f"sdlin_{a}"] = curve, mulim, sdlin
    return r


def test_table_pools_the_steering_logs_and_every_log_for_the_spread():
    # 44 particles: a steering log (curve 2, mu 0.1, sd 0.3, beta 0.05), the straight log
    # (curve 50, mu NaN, sd 0.25, beta 9) and a braking log (curve 40, mu 0.9, sd 0.15, beta
    # 9): curve, mu and beta come from the steering log only; the spread's minimum (0.15) and
    # median (0.25) from all three
    nan = float("nan")
    runs = [_run("tid_sine_steer", "apf", 44, 1, 1, 2.0, 0.1, 0.3, 0.05),
            _run("tid_straight", "apf", 44, 1, 1, 50.0, nan, 0.25, 9.0),
            _run("tid_brake_in_turn_low_mu", "apf", 44, 1, 1, 40.0, 0.9, 0.15, 9.0)]
    lines = M.table(runs, COUNTS, (32, 256), seeds=(1,), low={})
    rows = [ln for ln in lines if ln.startswith("| APF")]
    assert rows == ["| APF | 44 | 100 | ≈ 330,000 | 98 % | 2.0 | 2.0 | 0.100 | 0.100 "
                    "| 0.15 (0.25) | 0.050 |"]
    assert "0 + 7,500 per particle" in lines[0] and "44 particles fit at 100 Hz" in lines[0]


def _page_rows():
    text = (R.ROOT / "docs" / "TYRE_ID_RESULTS.md").read_text()
    begin, end = M.MARK
    assert begin in text and end in text
    region = text.split(begin, 1)[1].split(end, 1)[0]
    return region, [ln for ln in region.splitlines() if re.match(r"\| (APF|SCKF) \|", ln)]


def test_page_table_is_in_step_with_the_measured_counts():
    region, rows = _page_rows()
    fixed, per = M.per_particle()
    nf = M.n_fit()
    assert f"{nf} particles fit at {M.RATE_HZ} Hz" in region
    assert f"{fixed:,.0f} + {per:,.0f} per particle" in region
    # the count that fits was measured itself, and it is within the budget
    assert nf in M.PIL_COUNTS and M.PIL_COUNTS[nf][0] <= M.BUDGET
    cfg = M.configurations()
    assert len(rows) == len(cfg)
    for row, (label, filt, n, every) in zip(rows, cfg):
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert cells[0] == label
        assert cells[1] == (R.SCKF_POINTS if filt == "sckf" else str(n))
        assert cells[2] == format(M.RATE_HZ / every, ".3g")
        if filt == "sckf":
            c = float(M.PIL_SCKF)
        elif every > 1:
            # measured at that rate, and the next higher rate was measured over the budget
            c, measured = M.low_cost(n, every)
            assert measured and M.PIL_LOW[(n, every - 1)][0] > M.BUDGET * (every - 1)
        else:
            c = M.cost(n)[0]
        assert cells[3].lstrip("≈ ") == f"{c:,.0f}"
        assert cells[4] == f"{100.0 * c / every / M.BUDGET:.0f} %"
