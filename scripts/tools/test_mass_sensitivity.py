"""The pooling of mass_sensitivity.py on wheels whose figures are known by hand.

Two wheels: 10 valid samples of RMSE 0.1 (9 within 2 sd) and 30 of RMSE 0.2 (30 within), 100
settled each. Pooled: 40 of 200 valid; RMSE sqrt((10 * 0.01 + 30 * 0.04) / 40) =
sqrt(1.3 / 40); 39 of 40 consistent. The sums of squares are formed from the RMSEs the CLI
writes, so the pooled RMSE equals the hand value to rounding (1e-12).
"""

import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mass_sensitivity as ms  # noqa: E402


def wheel(n_settled, n_valid, rmse, cons, worst):
    return {"n_settled": n_settled, "n_valid": n_valid, "rmse_valid": rmse,
            "consistency_valid": cons, "max_abs_err_valid": worst}


def test_pooled_weights_each_wheel_by_its_valid_samples():
    settled, valid, sse, cons, worst = ms.pooled(
        [wheel(100, 10, 0.1, 0.9, 0.3), wheel(100, 30, 0.2, 1.0, 0.25),
         wheel(100, 0, float("nan"), float("nan"), float("nan"))])
    assert (settled, valid, cons) == (300, 40, 39)
    assert math.isclose(math.sqrt(sse / valid), math.sqrt(1.3 / 40), rel_tol=1e-12)
    assert worst == 0.3


def test_table_counts_logs_moved_beyond_the_threshold():
    base = [wheel(100, 100, 0.10, 1.0, 0.2)]
    results = {}
    for preset in ms.PRESETS:
        results[("a", preset, 1.0)] = base
        results[("b", preset, 1.0)] = base
        # log a: 0.10 -> 0.13 (worse by 0.03) at 0.8, 0.115 (within) at 1.2; log b: 0.07
        results[("a", preset, 0.8)] = [wheel(100, 100, 0.13, 1.0, 0.2)]
        results[("a", preset, 1.2)] = [wheel(100, 100, 0.115, 1.0, 0.2)]
        results[("b", preset, 0.8)] = [wheel(100, 100, 0.07, 1.0, 0.2)]
        results[("b", preset, 1.2)] = base
    rows = ms.table(results, ["a", "b"]).splitlines()
    row08 = next(r for r in rows if r.startswith("| default | m × 0.8"))
    row12 = next(r for r in rows if r.startswith("| default | m × 1.2"))
    assert row08.endswith("| 1 of 2 | 1 of 2 |")
    assert row12.endswith("| 0 of 2 | 0 of 2 |")
