"""The rule and the log list of tyre_id_feed_results.py, on figures decided by hand.

A run is (RMSE when valid, consistency when valid, valid share, share fed). "Helps": a lower
RMSE, a consistency no lower and a valid share at most 5 points lower than without the feed;
"hurts": an RMSE higher by more than 0.02 or a consistency lower by more than 0.05; no verdict
(None) when either run has no valid sample. "Meets" (issue 20's targets): an RMSE when valid
<= 0.08 and a consistency when valid >= 0.9. Each fed column of the first table is one filter
(APF, SIR, SCKF) at one feed, the other tables' pairs the APF's and the SCKF's, and a run hands
its filter to mu_replay (checked with a stand-in for mu_replay).
"""

import json
import os
import stat
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import tyre_id_feed_results as fr  # noqa: E402

BASE = (0.20, 0.90, 0.50, 0.0)


def test_helps_needs_all_three():
    assert fr.helps(BASE, (0.10, 0.95, 0.50, 0.5)) is True
    assert fr.helps(BASE, (0.10, 0.90, 0.46, 0.5)) is True       # 4 points fewer valid: allowed
    assert fr.helps(BASE, (0.20, 0.95, 0.50, 0.5)) is False      # RMSE not lower
    assert fr.helps(BASE, (0.10, 0.89, 0.50, 0.5)) is False      # consistency lower
    assert fr.helps(BASE, (0.10, 0.95, 0.44, 0.5)) is False      # 6 points fewer valid


def test_hurts_on_either_figure():
    assert fr.hurts(BASE, (0.22, 0.85, 0.50, 0.5)) is False      # both on their limits
    assert fr.hurts(BASE, (0.221, 0.95, 0.50, 0.5)) is True      # RMSE 0.021 higher
    assert fr.hurts(BASE, (0.10, 0.84, 0.50, 0.5)) is True       # consistency 0.06 lower
    assert fr.hurts(BASE, (0.10, 0.95, 0.10, 0.5)) is False      # fewer valid alone: no


def test_no_verdict_without_valid_samples():
    assert fr.helps((None, None, 0.0, 0.0), (0.10, 0.95, 0.50, 0.5)) is None
    assert fr.helps(BASE, (None, None, 0.0, 0.5)) is None
    assert fr.hurts(BASE, (None, None, 0.0, 0.5)) is None


def test_labels_say_the_evidence():
    assert [fr.label(f) for f in ((0.05, 0.0), (0.1, 0.25))] == ["0.05", "0.1 e0.25"]
    assert [fr.label(f, "S") for f in ((0.05, 0.0), (0.1, 0.25))] == ["S0.05", "S0.1 e0.25"]


def test_columns_are_every_feed_of_each_filter():
    cols = fr.columns()
    assert {c[0] for c in cols} == {"apf", "sir", "sckf"}
    assert len(cols) == len(fr.FEED_FILTERS) * len(fr.FEEDS)
    # the particle filters side by side, the SCKF last; its A and S columns as before the SIR
    assert [c[1] for c in cols[::len(fr.FEEDS)]] == ["A", "B", "S"]
    # the hold, ellipse and band tables keep the APF and the SCKF only
    assert {p[0] for p in fr.hold_columns() + fr.ellipse_columns()} == {"apf", "sckf"}
    for flt, letter in fr.FEED_FILTERS:
        assert [c[2] for c in cols if c[0] == flt] == list(fr.FEEDS)
        assert {c[1] for c in cols if c[0] == flt} == {letter}
    labels = [fr.label(c[2], c[1]) for c in cols]
    assert len(set(labels)) == len(labels)             # no two columns read the same


def test_hold_columns_pair_no_hold_with_the_default():
    """The before -> after table: each filter's ungated feeds once with tid_feed_ax_max 0 (a
    third entry, named in the label) and once without the key (its default)."""
    pairs = fr.hold_columns()
    assert len(pairs) == len(fr.FILTERS) * len(fr.HOLD_FEEDS)
    for flt, letter, before, after in pairs:
        assert before == (after[0], after[1], 0.0) and len(after) == 2
        assert after in fr.HOLD_FEEDS
    assert fr.label((0.05, 0.0, 0.0), "S") == "S0.05 a0"
    assert fr.label((0.05, 0.0), "S") == "S0.05"


def test_meets_issue_20_targets_on_their_limits():
    assert fr.meets((0.08, 0.90, 0.5, 0.5)) is True
    assert fr.meets((0.081, 0.95, 0.5, 0.5)) is False    # RMSE above 0.08
    assert fr.meets((0.05, 0.89, 0.5, 0.5)) is False     # consistency below 0.9
    assert fr.meets((None, None, 0.0, 0.5)) is None


def _stand_in(tmp_path):
    """An executable that records its arguments (and its --params file's text in
    params.txt) and writes a --metrics JSON: wheels fl, fr
    with 100 and 300 valid of 400 settled samples, RMSE when valid 0.1 and 0.2, consistency
    when valid 1.0 and 0.8, rr and rl without samples; 25 of 100 steps fed."""
    exe = tmp_path / "mu_replay"
    rec = tmp_path / "args.json"

    def wheel(nv, r, c):
        return {"n_settled": 400, "n_valid": nv, "rmse_valid": r, "consistency_valid": c,
                "frac_valid": nv / 400}

    empty = {"n_settled": 0, "n_valid": 0, "rmse_valid": None, "consistency_valid": None,
             "frac_valid": None}
    j = {"steps": 100, "metrics": {"fl": wheel(100, 0.1, 1.0), "fr": wheel(300, 0.2, 0.8),
                                   "rl": empty, "rr": empty},
         "tyre_id": {"feed": {"n_fed": 25}}}
    exe.write_text(f"""#!{sys.executable}
import json, sys
a = sys.argv[1:]
json.dump(a, open({str(rec)!r}, "w"))
if "--params" in a:
    open({str(tmp_path / "params.txt")!r}, "w").write(open(a[a.index("--params") + 1]).read())
json.dump({j!r}, open(a[a.index("--metrics") + 1], "w"))
""")
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    return str(exe), rec


def test_run_hands_the_filter_and_feed_to_the_replay(tmp_path):
    exe, rec = _stand_in(tmp_path)
    r = fr.run(exe, "scenarios/brake_in_turn.mf.csv", "sckf", (0.1, 0.25))
    args = json.loads(rec.read_text())
    assert args[args.index("--tyre-id") + 1] == "sckf"
    assert "--params" in args
    # pooled as wheel_figures does: RMS weighted by n_valid, shares by their counts
    assert abs(r[0] - ((100 * 0.1 ** 2 + 300 * 0.2 ** 2) / 400) ** 0.5) < 1e-12
    assert abs(r[1] - (100 * 1.0 + 300 * 0.8) / 400) < 1e-12
    assert abs(r[2] - 0.5) < 1e-12                     # 400 valid of 800 settled
    assert r[3] == 0.25


def test_run_writes_the_hold_only_when_the_feed_sets_it(tmp_path):
    exe, rec = _stand_in(tmp_path)
    par = tmp_path / "params.txt"
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "sckf", (0.1, 0.0, 0.0))
    assert "tid_feed_ax_max = 0.0" in par.read_text().splitlines()
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "sckf", (0.1, 0.25))
    lines = par.read_text().splitlines()
    assert "tid_feed_evidence = 0.25" in lines
    assert not any(x.startswith("tid_feed_ax_max") for x in lines)   # the key's default


def test_run_without_the_identifier_names_no_filter(tmp_path):
    exe, rec = _stand_in(tmp_path)
    r = fr.run(exe, "scenarios/brake_in_turn.mf.csv", None, None)
    args = json.loads(rec.read_text())
    assert "--tyre-id" not in args and "--params" not in args
    assert r[3] == 0.0


def test_logs_are_the_steering_scenarios_and_exist():
    logs = fr.logs()
    assert len(logs) == 3 * len(fr.STEERING) + len(os.listdir(Path(fr.ROOT) / "scenarios" / "tyre_id"))
    assert "scenarios/brake_in_turn.mf.csv" in logs and "scenarios/wrong_tyre_data.csv" in logs
    for log in logs:
        assert (Path(fr.ROOT) / log).is_file(), log


def test_ellipse_columns_pair_each_feed_without_and_with_the_ellipse():
    """The third table: each filter's ungated feeds, held at the default (the main table's run
    the base, the hold key not written) and not held (a0), each without tid_ellipse and with
    it (a fourth entry, 1, named E)."""
    pairs = fr.ellipse_columns()
    assert len(pairs) == 2 * len(fr.FILTERS) * len(fr.HOLD_FEEDS)
    for flt, letter, before, after in pairs:
        assert len(after) == 5 and after[3] == 1.0 and after[:2] == before[:2]
        assert after[2] == (before[2] if len(before) > 2 else None)
        assert after[4] == 0.0                       # the ellipse without its dead band
    assert fr.label((0.05, 0.0, None, 1.0, 0.0), "S") == "S0.05 E"
    assert fr.label((0.05, 0.0, 0.0, 1.0, 0.0), "S") == "S0.05 a0 E"


def test_band_columns_are_the_ellipse_columns_at_the_default_band():
    """The fourth table: the same pairs with tid_ell_ax_min at the key's default (the
    reference's TID_DEFAULTS, the C library's rfe_tyre_id_params_default), named EbX."""
    sys.path.insert(0, str(Path(fr.ROOT) / "scripts"))
    from reference import tyre_id as T
    assert fr.BAND == T.TID_DEFAULTS["tid_ell_ax_min"] > 0
    pairs = fr.ellipse_columns(fr.BAND)
    assert [p[:3] for p in pairs] == [p[:3] for p in fr.ellipse_columns()]
    assert all(p[3][4] == fr.BAND and p[3][:4] == q[3][:4]
               for p, q in zip(pairs, fr.ellipse_columns()))
    assert fr.label((0.1, 0.0, 0.0, 1.0, 0.6), "A") == "A0.1 a0 Eb0.6"


def test_run_writes_the_ellipse_and_leaves_the_held_default(tmp_path):
    exe, _ = _stand_in(tmp_path)
    par = tmp_path / "params.txt"
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "sckf", (0.1, 0.0, None, 1.0))
    lines = par.read_text().splitlines()
    assert "tid_ellipse = 1.0" in lines
    assert not any(x.startswith("tid_feed_ax_max") for x in lines)   # the key's default
    assert not any(x.startswith("tid_ell_ax_min") for x in lines)    # the band's default
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "sckf", (0.1, 0.0, None, 1.0, 0.0))
    assert "tid_ell_ax_min = 0.0" in par.read_text().splitlines()
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "sckf", (0.1, 0.0, 0.0))
    assert not any(x.startswith("tid_ellipse") for x in par.read_text().splitlines())


def test_spread_is_median_min_max_without_the_runs_lacking_a_figure():
    """Hand-made figures: the median of an odd count is the middle one, of an even count the
    mean of the middle two; None (a run without a valid sample) is left out."""
    assert fr.spread([0.3, None, 0.1, 0.2]) == (0.2, 0.1, 0.3)
    assert fr.spread([4, 1, 3, 2]) == (2.5, 1, 4)
    assert fr.spread([7]) == (7, 7, 7)
    assert fr.spread([None, None]) is None


def test_seed_cell_prints_the_range_only_where_the_seeds_differ_at_its_digits():
    assert fr.seed_cell([0.087, 0.178, 0.063, 0.100, 0.090], ".3f") == "0.090 [0.063–0.178]"
    assert fr.seed_cell([0.1001, 0.1004, 0.1002], ".3f") == "0.100"     # equal at 3 digits
    assert fr.seed_cell([0.1, None, 0.3], ".3f") == "0.200 [0.100–0.300] (2 of 3 seeds)"
    assert fr.seed_cell([None, None], ".3f") == "–"
    assert fr.seed_cell([0.42, 0.46, 0.38], ".0%") == "42% [38%–46%]"
    assert fr.count_cell([10, 8, 11, 9, 10]) == "10 [8–11]"
    assert fr.count_cell([3, 3, 3]) == "3"
    assert fr.count_cell([1, 2]) == "1.5 [1–2]"


def test_run_writes_the_seed_only_when_given(tmp_path):
    exe, _ = _stand_in(tmp_path)
    par = tmp_path / "params.txt"
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "apf", (0.1, 0.0), 3)
    assert "tid_seed = 3" in par.read_text().splitlines()
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "apf", (0.1, 0.0))
    assert not any(x.startswith("tid_seed") for x in par.read_text().splitlines())


def test_seed_jobs_repeat_only_the_seeded_filters_beyond_the_first_seed():
    jobs = fr.seed_jobs(["scenarios/a.csv"])
    assert {j[1] for j in jobs} == set(fr.SEEDED) == {"apf", "sir"}
    assert sorted({j[3] for j in jobs}) == list(fr.SEEDS[1:])
    assert len(jobs) == 2 * len(fr.FEEDS) * (len(fr.SEEDS) - 1)
    assert fr.SEEDS[0] == 1                          # the preset's tid_seed (RFE_TID_SEED_DEFAULT)


# Two logs, one feed, the APF (and SIR) over three seeds and the SCKF once, figures decided by
# hand (the APF's and the SCKF's in test_feed_table_aggregates_the_seeds).
FA, FB, FF = "scenarios/a.csv", "scenarios/b.csv", (0.1, 0.0)
FEED_RES = {(FA, None, None): (0.20, 0.90, 0.50, 0.0), (FB, None, None): (0.10, 1.00, 0.50, 0.0),
            (FA, "apf", FF): (0.10, 0.95, 0.50, 0.4), (FA, "apf", FF, 2): (0.25, 0.95, 0.50, 0.6),
            (FA, "apf", FF, 3): (0.15, 0.95, 0.50, 0.5), (FA, "sckf", FF): (0.10, 0.95, 0.50, 0.5),
            (FB, "apf", FF): (0.05, 1.00, 0.50, 0.5), (FB, "apf", FF, 2): (0.05, 1.00, 0.50, 0.5),
            (FB, "apf", FF, 3): (0.05, 1.00, 0.50, 0.5), (FB, "sckf", FF): (None, None, 0.0, 0.3)}


def test_feed_table_aggregates_the_seeds(monkeypatch):
    """Two logs, one feed, the APF over three seeds and the SCKF once, figures decided by hand
    (the table without the SIR column: its A and S columns as they were before it).
    Log a (off 0.20 / 0.90 / 50 %): the APF's seeds 0.10 (helps), 0.25 (hurts: 0.05 higher),
    0.15 (helps); the SCKF 0.10 (helps). Log b (off 0.10 / 1.00): every APF seed 0.05 and 1.00
    (helps, meets); the SCKF without a valid sample (no verdict)."""
    monkeypatch.setattr(fr, "FEEDS", (FF,))
    monkeypatch.setattr(fr, "SEEDS", (1, 2, 3))
    monkeypatch.setattr(fr, "FEED_FILTERS", fr.FILTERS)
    rows = fr.feed_table([FA, FB], dict(FEED_RES))
    assert rows[2] == ("| a | 0.200 / 0.150 [0.100–0.250] / 0.100 | 0.90 / 0.95 / 0.95 "
                       "| 50% / 50% / 50% | 50% [40%–60%] / 50% | 2/3 / yes | 1/3 / no |")
    assert rows[3] == ("| b | 0.100 / 0.050 / – | 1.00 / 1.00 / – | 50% / 50% / 0% "
                       "| 50% / 30% | 3/3 / – | 0/3 / – |")
    text = "\n".join(rows)
    # per seed the APF helps on 2, 1, 2 logs and hurts on 0, 1, 0 of 2; the SCKF 1 / 0 of 1
    assert "A0.1: 2 [1–2] / 0 [0–1] of 2; S0.1: 1 / 0 of 1." in text
    # log b helped on every seed, log a on some; log a hurt on some
    assert "A0.1: 1 / 1; 0 / 1." in text
    # meets: off none of 2; the APF log b on every seed; the SCKF log a misses (0.10 > 0.08)
    assert "off: 0 of 2; A0.1: 1 of 2; S0.1: 0 of 1." in text


def test_feed_table_adds_the_sir_column_between_the_apf_and_the_sckf(monkeypatch):
    """The same logs with the bootstrap filter (B) over the same three seeds, figures decided by
    hand. Log a (off 0.20 / 0.90 / 50 %): SIR seed 1 0.30 (hurts: 0.10 higher), seed 2 0.18 with
    consistency 0.88 (lower: no help; 0.02 lower: no hurt), seed 3 0.12 (helps). Log b (off
    0.10 / 1.00): seed 1 without a valid sample (no verdict), seeds 2 and 3 0.07 with
    consistency 0.97 (lower: no help; 0.03 lower: no hurt; meets: 0.07 <= 0.08, 0.97 >= 0.9).
    The APF's and the SCKF's cells are those of the table without SIR, character for
    character."""
    monkeypatch.setattr(fr, "FEEDS", (FF,))
    monkeypatch.setattr(fr, "SEEDS", (1, 2, 3))
    res = dict(FEED_RES)
    for key, runs in (((FA, "sir", FF), ((0.30, 0.95, 0.50, 0.7), (0.18, 0.88, 0.50, 0.6),
                                         (0.12, 0.95, 0.50, 0.5))),
                      ((FB, "sir", FF), ((None, None, 0.0, 0.2), (0.07, 0.97, 0.50, 0.4),
                                         (0.07, 0.97, 0.50, 0.4)))):
        res[key] = runs[0]                           # seed 1: the preset's run, no seed key
        res[key + (2,)], res[key + (3,)] = runs[1], runs[2]
    rows = fr.feed_table([FA, FB], res)
    assert rows[0].startswith("| log | RMSE when valid: off / A0.1 / B0.1 / S0.1 |")
    assert rows[2] == ("| a | 0.200 / 0.150 [0.100–0.250] / 0.180 [0.120–0.300] / 0.100 "
                       "| 0.90 / 0.95 / 0.95 [0.88–0.95] / 0.95 | 50% / 50% / 50% / 50% "
                       "| 50% [40%–60%] / 60% [50%–70%] / 50% | 2/3 / 1/3 / yes "
                       "| 1/3 / 1/3 / no |")
    assert rows[3] == ("| b | 0.100 / 0.050 / 0.070 (2 of 3 seeds) / – "
                       "| 1.00 / 1.00 / 0.97 (2 of 3 seeds) / – | 50% / 50% / 50% [0%–50%] / 0% "
                       "| 50% / 40% [20%–40%] / 30% | 3/3 / 0/2 / – | 0/3 / 0/2 / – |")
    text = "\n".join(rows)
    assert "Seeds: the APF's and SIR's columns (A0.1, B0.1) are the median over tid_seed 1, 2, 3" \
        in text
    # per seed SIR helps on 0, 0, 1 logs and hurts on 1, 0, 0, of 1, 2, 2 with a verdict
    assert ("A0.1: 2 [1–2] / 0 [0–1] of 2; B0.1: 0 [0–1] / 0 [0–1] of 2 [1–2]; "
            "S0.1: 1 / 0 of 1.") in text
    # log a helped on some seeds and hurt on some; log b neither
    assert "A0.1: 1 / 1; 0 / 1; B0.1: 0 / 1; 0 / 1." in text
    # meets per seed: none, log b, log b, of 1, 2, 2 logs with a valid sample
    assert "off: 0 of 2; A0.1: 1 of 2; B0.1: 1 [0–1] of 2 [1–2]; S0.1: 0 of 1." in text


def test_run_hands_sir_and_its_seed_to_the_replay(tmp_path):
    exe, rec = _stand_in(tmp_path)
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "sir", (0.05, 0.25), 4)
    args = json.loads(rec.read_text())
    assert args[args.index("--tyre-id") + 1] == "sir"
    lines = (tmp_path / "params.txt").read_text().splitlines()
    assert "tid_seed = 4" in lines and "tid_feed_sd_rel = 0.05" in lines


# Two logs and one before -> after pair per filter for the hold table's tests (the seeded APF
# over three seeds, the SCKF once), figures decided by hand. Log a, off 0.20 / 0.90 / 50 %:
# the APF before 0.30 (hurts off), 0.10 (helps off), 0.25 (hurts off) and after 0.10, 0.10,
# 0.30, so against its own seed's before the change helps on seed 1, is "=" on seed 2 (the same
# RMSE) and hurts on seed 3 (0.05 higher); the SCKF 0.15 -> 0.07 (helps; after meets). Log b,
# off 0.10 / 1.00: every APF before 0.05 (helps off, meets), after no valid sample on seed 1
# and 0.05 on seeds 2 and 3 ("="); the SCKF 0.05 -> 0.05.
HA, HB = "scenarios/a.csv", "scenarios/b.csv"
HOLD_PAIRS = [("apf", "A", (0.1, 0.0, 0.0), (0.1, 0.0)),
              ("sckf", "S", (0.1, 0.0, 0.0), (0.1, 0.0))]


def _hold_res():
    b, f = (0.1, 0.0, 0.0), (0.1, 0.0)
    res = {(HA, None, None): (0.20, 0.90, 0.50, 0.0), (HB, None, None): (0.10, 1.00, 0.50, 0.0),
           (HA, "sckf", b): (0.15, 0.95, 0.50, 0.5), (HA, "sckf", f): (0.07, 0.95, 0.50, 0.3),
           (HB, "sckf", b): (0.05, 1.00, 0.50, 0.5), (HB, "sckf", f): (0.05, 1.00, 0.50, 0.5)}
    for key, runs in (((HA, "apf", b), ((0.30, 0.80, 0.50, 0.6), (0.10, 0.95, 0.50, 0.4),
                                        (0.25, 0.90, 0.50, 0.5))),
                      ((HA, "apf", f), ((0.10, 0.95, 0.50, 0.2), (0.10, 0.95, 0.50, 0.4),
                                        (0.30, 0.90, 0.50, 0.5))),
                      ((HB, "apf", b), ((0.05, 1.00, 0.50, 0.5),) * 3),
                      ((HB, "apf", f), ((None, None, 0.0, 0.1), (0.05, 1.00, 0.50, 0.5),
                                        (0.05, 1.00, 0.50, 0.5)))):
        res[key] = runs[0]                           # seed 1: the preset's run, no seed key
        res[key + (2,)], res[key + (3,)] = runs[1], runs[2]
    return res


def test_hold_table_aggregates_the_seeds_pairing_before_and_after_by_seed(monkeypatch):
    monkeypatch.setattr(fr, "SEEDS", (1, 2, 3))
    rows = fr.hold_table([HA, HB], _hold_res(), HOLD_PAIRS, fr.HOLD_WORDS)
    assert rows[2] == ("| a | 0.200 / 0.250 [0.100–0.300] → 0.100 [0.100–0.300] / 0.150 → 0.070 "
                       "| 0.90 / 0.90 [0.80–0.95] → 0.95 [0.90–0.95] / 0.95 → 0.95 "
                       "| 50% / 50% → 50% / 50% → 50% "
                       "| 50% [40%–60%] → 40% [20%–50%] / 50% → 30% "
                       "| helps 1/3, hurts 1/3 / helps |")
    assert rows[3] == ("| b | 0.100 / 0.050 → 0.050 (2 of 3 seeds) / 0.050 → 0.050 "
                       "| 1.00 / 1.00 → 1.00 (2 of 3 seeds) / 1.00 → 1.00 "
                       "| 50% / 50% → 50% [0%–50%] / 50% → 50% "
                       "| 50% → 50% [10%–50%] / 50% → 50% | = (2 of 3 seeds) / = |")
    text = "\n".join(rows)
    # against off per seed: before helps 1, 2, 1 and hurts 1, 0, 1; after helps 1, 2, 1 and
    # hurts 0, 0, 1; the SCKF helps both logs before and after
    assert "A0.1: 1 [1–2] / 1 [0–1] → 1 [1–2] / 0 [0–1]; S0.1: 2 / 0 → 2 / 0." in text
    # meets per seed: before log b on every seed; after log b on seeds 2 and 3 only; the SCKF
    # log b before, both after (0.07 <= 0.08)
    assert "A0.1: 1 → 1 [0–1]; S0.1: 1 → 2." in text
    # the hold against no hold per seed: helps 1, 0, 0, hurts 0, 0, 1 (log a)
    assert "A0.1: 0 [0–1] / 0 [0–1]; S0.1: 1 / 0." in text
    assert "Seeds: the APF's pairs (A0.1) are run with tid_seed 1, 2, 3" in text
    # log a helped on some seeds and hurt on some; log b on none
    assert rows[-1].endswith("A0.1: 0 / 1; 0 / 1.")


def test_hold_table_of_one_seed_is_the_single_run_table(monkeypatch):
    """With one seed every cell is the run's figure and the verdicts words, as the tables
    were before the seeds (no range, no seed sentence)."""
    monkeypatch.setattr(fr, "SEEDS", (1,))
    rows = fr.hold_table([HA, HB], _hold_res(), HOLD_PAIRS, fr.HOLD_WORDS)
    assert rows[2] == ("| a | 0.200 / 0.300 → 0.100 / 0.150 → 0.070 | 0.90 / 0.80 → 0.95 / "
                       "0.95 → 0.95 | 50% / 50% → 50% / 50% → 50% | 60% → 20% / 50% → 30% "
                       "| helps / helps |")
    assert rows[3] == ("| b | 0.100 / 0.050 → – / 0.050 → 0.050 | 1.00 / 1.00 → – / "
                       "1.00 → 1.00 | 50% / 50% → 0% / 50% → 50% | 50% → 10% / 50% → 50% "
                       "| – / = |")
    assert len(rows) == 6 and rows[4] == ""
    # seed 1 against off: before helps b, hurts a (0.30); after helps a, b has no verdict
    assert rows[5].endswith("A0.1: 1 / 1 → 1 / 0; S0.1: 2 / 0 → 2 / 0. Meets issue 20's "
                            "targets: A0.1: 1 → 0; S0.1: 1 → 2. The hold against no hold, "
                            "helps / hurts: A0.1: 1 / 0; S0.1: 1 / 0.")


def test_change_cell_counts_the_seeds_with_a_verdict():
    assert fr.change_cell([True], [False], 1) == "helps"
    assert fr.change_cell([False], [True], 1) == "hurts"
    assert fr.change_cell([False], [False], 1) == "="
    assert fr.change_cell([None], [None], 1) == "–"
    assert fr.change_cell([True, False, None], [False, True, None], 3) == "helps 1/2, hurts 1/2"
    assert fr.change_cell([False] * 5, [True] * 5, 5) == "hurts 5/5"
    assert fr.change_cell([False] * 5, [False] * 5, 5) == "="
    assert fr.change_cell([None] * 3, [None] * 3, 3) == "–"


class _Reads(dict):
    """A run table that records every key a table reads."""

    def __init__(self, *a):
        super().__init__(*a)
        self.read = set()

    def __getitem__(self, key):
        self.read.add(key)
        return super().__getitem__(key)


def test_the_jobs_are_exactly_the_runs_the_five_tables_read(monkeypatch):
    """Every run main() starts is read by a table and every run a table reads is started, each
    once: the seeded filter's runs once per seed in every table, the rest once."""
    monkeypatch.setattr(fr, "SEEDS", (1, 2, 3))
    names = [HA, HB]
    jobs = fr.all_jobs(names)
    assert len(jobs) == len(set(jobs))
    res = _Reads((j, (0.1, 0.9, 0.5, 0.5)) for j in jobs)
    fr.feed_table(names, res)
    fr.hold_table(names, res)
    fr.hold_table(names, res, fr.ellipse_columns(), fr.ELLIPSE_WORDS)
    fr.hold_table(names, res, fr.ellipse_columns(fr.BAND), fr.BAND_WORDS)
    fr.hold_table(names, res, fr.dstate_columns(), fr.DSTATE_WORDS)
    assert res.read == set(jobs)
    # per log: off, and per filter of the APF and the SCKF the first table's 4 feeds, the
    # hold's 2 unheld feeds, the ellipse's and the band's 4 each; the APF's on each of the 3
    # seeds; SIR the first table's 4 feeds on each of the 3 seeds; the SCKF's 4 feeds once
    # more with the delta state (deterministic: one run each)
    per_filter = len(fr.FEEDS) + len(fr.HOLD_FEEDS) + 2 * 2 * len(fr.HOLD_FEEDS)
    assert len(jobs) == len(names) * (1 + per_filter * (3 + 1) + len(fr.FEEDS) * 3
                                      + len(fr.FEEDS))


def test_map_progress_keeps_order_and_reports(capsys):
    """The results come back in the items' order whatever the threads' finishing order (the
    early items sleep longest), and the progress lines count every run: with 7 items and
    every=3, lines at 3, 6 and the last (7) (sorted: two threads may print out of order)."""
    import time as _time

    def slow_square(x):
        _time.sleep(0.002 * (7 - x))
        return x * x

    got = fr.map_progress(slow_square, list(range(7)), 3, "t", every=3)
    assert got == [x * x for x in range(7)]
    err = capsys.readouterr().err.splitlines()
    assert sorted(ln.split(" runs")[0] for ln in err) == ["t: 3 / 7", "t: 6 / 7", "t: 7 / 7"]


def test_dstate_columns_pair_each_sckf_feed_with_the_delta_state():
    """The fifth table: the SCKF (deterministic, not seeded) at every feed of the first table,
    each "before" the first table's S run (the same key) and each "after" the same feed with
    tid_delta_state_q 0.04 (a sixth entry, named dX) and nothing else written."""
    pairs = fr.dstate_columns()
    assert [p[2] for p in pairs] == list(fr.FEEDS)
    assert {(p[0], p[1]) for p in pairs} == {("sckf", "S")} and "sckf" not in fr.SEEDED
    assert {(p[0], p[2]) for p in pairs} <= {(c[0], c[2]) for c in fr.columns()}
    for _, _, before, after in pairs:
        assert after == (before[0], before[1], None, None, None, 0.04)
    assert fr.DSTATE_Q == 0.04          # TYRE_ID_RESULTS.md's recommendation for the SCKF
    assert fr.label(pairs[0][3], "S") == "S0.05 d0.04"
    assert fr.label(pairs[3][3], "S") == "S0.1 e0.25 d0.04"


def test_run_writes_the_delta_state_and_no_key_left_at_none(tmp_path):
    exe, rec = _stand_in(tmp_path)
    fr.run(exe, "scenarios/brake_in_turn.mf.csv", "sckf", (0.1, 0.25, None, None, None, 0.04))
    args = json.loads(rec.read_text())
    assert args[args.index("--tyre-id") + 1] == "sckf"
    lines = (tmp_path / "params.txt").read_text().splitlines()
    assert lines == ["tid_feed_sd_rel = 0.1", "tid_feed_evidence = 0.25",
                     "tid_delta_state_q = 0.04"]


def test_dstate_table_compares_the_delta_state_with_the_same_feed(monkeypatch):
    """One log, the SCKF at one feed, figures decided by hand: off 0.20 / 0.90 / 50 %; delta
    an input 0.12 / 0.95 / 50 % (helps off); delta a state 0.07 / 0.95 / 48 % (helps off, and
    against the input: lower RMSE, same consistency, 2 points fewer valid; meets: 0.07 <=
    0.08, 0.95 >= 0.9)."""
    f = (0.1, 0.0)
    monkeypatch.setattr(fr, "FEEDS", (f,))
    after = (0.1, 0.0, None, None, None, fr.DSTATE_Q)
    res = {(HA, None, None): (0.20, 0.90, 0.50, 0.0), (HA, "sckf", f): (0.12, 0.95, 0.50, 0.6),
           (HA, "sckf", after): (0.07, 0.95, 0.48, 0.5)}
    rows = fr.hold_table([HA], res, fr.dstate_columns(), fr.DSTATE_WORDS)
    assert rows[0].startswith("| log | RMSE when valid: off / S0.1 → S0.1 d0.04 |")
    assert rows[2] == ("| a | 0.200 / 0.120 → 0.070 | 0.90 / 0.95 → 0.95 | 50% / 50% → 48% "
                       "| 60% → 50% | helps |")
    assert rows[4].endswith("S0.1 d0.04: 1 / 0 → 1 / 0. Meets issue 20's targets: "
                            "S0.1 d0.04: 0 → 1. The δ state against δ an input, helps / hurts: "
                            "S0.1 d0.04: 1 / 0.")
    assert len(rows) == 5                 # no seed sentences: the SCKF is deterministic
