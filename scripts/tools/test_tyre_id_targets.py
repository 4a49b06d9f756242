"""tyre_id_targets.py: issue 20's mu targets per log, filter and axle, read from the accuracy
table, on a made-up table whose verdicts are decided by hand, and the page's table in step
with the page's accuracy table."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import tyre_id_targets as tt  # noqa: E402

# Two logs of the accuracy table's shape (its header as tyre_id_results.py writes it). Log x:
# the APF's front median 0.050 (on the limit: meets) and worst seed 0.051 (misses), rear 0.120
# (misses, worst 0.130); sd 0.20 (on the limit: meets) and 0.19 (misses). The SCKF: front
# 0.020 (worst the same: no bracket), rear never at the limit; sd 0.30, never linear. Log y:
# the APF never at the limit, never linear.
PAGE = """text
<!-- tyre-id-accuracy:begin -->
legend

| log | filter | curve f % (t_max) | curve r % (t_max) | mu@lim f | mu@lim r | min sd_mu linear f / r | beta RMSE deg | ms/step |
|---|---|---|---|---|---|---|---|---|
| x | APF | 1.0 [2.0] (0.1) | 1.0 [2.0] (0.1) | 0.050 [0.051] | 0.120 [0.130] | 0.20 / 0.19 | 0.1 | 1.0 |
| x | SCKF | 1.0 [1.0] (0.1) | 1.0 [1.0] (0.1) | 0.020 [0.020] | – [–] | 0.30 / – | 0.1 | 1.0 |
| y | APF | – [–] (0.000) | – [–] (0.000) | – [–] | – [–] | – / – | 0.1 | 1.0 |
<!-- tyre-id-accuracy:end -->
<!-- tyre-id-targets:begin -->
<!-- tyre-id-targets:end -->
"""


def test_parse_reads_median_worst_and_the_spread():
    rows = tt.parse(PAGE)
    assert rows[0] == ("x", "APF", (0.05, 0.051), (0.12, 0.13), (0.2, 0.19))
    assert rows[1] == ("x", "SCKF", (0.02, 0.02), (None, None), (0.3, None))
    assert rows[2] == ("y", "APF", (None, None), (None, None), (None, None))


def test_table_verdicts_on_hand_made_rows():
    lines = tt.table(tt.parse(PAGE))
    rows = [ln for ln in lines if ln.startswith("| x") or ln.startswith("| y")]
    assert rows == [
        "| x | APF | 0.050 yes [0.051 no] | 0.120 no [0.130 no] | 0.20 yes | 0.19 no |",
        "| x | SCKF | 0.020 yes | – | 0.30 yes | – |",
        "| y | APF | – | – | – | – |"]
    # APF: 1 median meets (0.050), none on every seed, of 2 cells; sd 1 of 2. SCKF: 1 / 1 of 1,
    # sd 1 of 1
    assert lines[-1].endswith("APF 1 / 0 of 2, 1 of 2; SCKF 1 / 1 of 1, 1 of 1.")


def test_a_changed_header_is_refused():
    with pytest.raises(SystemExit):
        tt.parse(PAGE.replace("mu@lim f", "mu at lim f"))


def test_main_writes_the_region(tmp_path):
    page = tmp_path / "p.md"
    page.write_text(PAGE)
    tt.main(["--page", str(page)])
    region = page.read_text().split(tt.MARK[0], 1)[1].split(tt.MARK[1], 1)[0]
    assert region.strip().splitlines() == tt.table(tt.parse(PAGE))


def test_the_targets_are_tyre_id_results_own():
    import tyre_id_results as tr
    t = {k: (how, lim) for k, how, lim in tr.TARGETS}
    assert t["mulim"] == ("<=", tt.MULIM_MAX) and t["sdlin"] == (">=", tt.SDLIN_MIN)


def test_the_page_is_in_step_with_its_accuracy_table():
    """docs/TYRE_ID_RESULTS.md's targets table is the script's output from the page's own
    accuracy table (rewritten by make tyre-id-results; never by hand)."""
    text = (Path(tt.ROOT) / "docs" / "TYRE_ID_RESULTS.md").read_text()
    region = text.split(tt.MARK[0], 1)[1].split(tt.MARK[1], 1)[0]
    assert region.strip("\n").splitlines() == tt.table(tt.parse(text))
