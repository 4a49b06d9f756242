"""tyre_id_results.py puts the augmented-state SCKF into its three tables: its row per log,
its sigma-point count in place of a particle count, and its identifiability rows, from one
deterministic run (the figures themselves are the page's, not asserted here)."""

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import tyre_id_results as R  # noqa: E402
from reference import tyre_id_sckf as TS  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402

LOG = "tid_sine_steer"


def test_sckf_row_is_its_own_run_in_every_table():
    sckf = R.measure((LOG, "sckf", 64, 1))
    apf = R.measure((LOG, "apf", 64, 1))
    # the scored run is tyre_id_sckf.run with the defaults (not the particle filter)
    c = read_csv_log(str(R.ROOT / "scenarios" / "tyre_id" / f"{LOG}.csv")).columns
    out = TS.run(c, {})
    assert sckf["mean_K_f"] == out["K_f"][-1] and sckf["mean_D_r"] == out["D_r"][-1]
    assert sckf["mean_K_f"] != apf["mean_K_f"]
    acc, cnt, idt = R.tables([apf, sckf], 64, [1])
    assert sum(line.startswith(f"| {LOG} | SCKF |") for line in acc) == 1
    assert sum(line.startswith(f"| SCKF | – ({TS.N_POINTS} points) |") for line in cnt) == 1
    assert [line.split(" | ")[2] for line in idt if line.startswith(f"| {LOG} | f |")] == \
        ["APF", "SCKF"]
    # the SCKF's curve cell is its own figure: the median over one run is that run
    row = next(line for line in acc if line.startswith(f"| {LOG} | SCKF |"))
    assert row.split(" | ")[2].startswith(format(sckf["curve_f"], ".1f") + " [")
    assert np.isfinite(sckf["curve_f"])


# --ellipse: tid_ellipse 1 at the default dead band (0.6 m/s^2).  A braking excerpt
# (brake_in_turn.mf to 2.5 s: braking from 2 s, |ax| 2.6 m/s^2 at 2.4 s) and a steering one
# (tid_sine_steer to 3 s, |ax| below 0.25 m/s^2 on the whole log, inside the band).
BRAKE, STEER = "brake_in_turn.mf", "tid_sine_steer"
N_BRAKE, N_STEER = 251, 301


def test_ellipse_option_turns_the_ellipse_on():
    assert R.ELLIPSE == {"tid_ellipse": 1.0}
    assert R.T.TID_DEFAULTS["tid_ellipse"] == 0.0     # the option, not the default, turns it on
    cb = read_csv_log(str(R.ROOT / "scenarios" / f"{BRAKE}.csv")).columns
    k24 = int(round(2.4 / 0.01))
    assert abs(cb["ax"][k24]) > 2.0
    off = R.run_filter(cb, "sckf", 64, 1, False, N_BRAKE)
    on = R.run_filter(cb, "sckf", 64, 1, True, N_BRAKE)
    # the ellipse's own run (TS.run with tid_ellipse 1), and not the lateral-only one: into
    # the braking the rear D differs (the page: 4,054 N without, 7,436 N with the band)
    ref = TS.run(cb, {"tid_ellipse": 1.0}, n_steps=N_BRAKE)
    assert on["D_r"][k24] == ref["D_r"][k24]
    assert on["D_r"][k24] > 1.2 * off["D_r"][k24]
    # the particle filter gets the keys too
    apf_off = R.run_filter(cb, "apf", 64, 1, False, N_BRAKE)
    apf_on = R.run_filter(cb, "apf", 64, 1, True, N_BRAKE)
    assert apf_on["D_r"][k24] != apf_off["D_r"][k24]


def test_ellipse_option_inside_the_band_keeps_the_lateral_only_run():
    cs = read_csv_log(str(R.ROOT / "scenarios" / "tyre_id" / f"{STEER}.csv")).columns
    assert float(np.max(np.abs(cs["ax"]))) < 0.6
    for filt in ("sckf", "apf"):
        off = R.run_filter(cs, filt, 64, 1, False, N_STEER)
        on = R.run_filter(cs, filt, 64, 1, True, N_STEER)
        # inside the band the forces are the lateral-only model's bit for bit (both factors
        # exactly 1), so every parameter and state estimate is the same
        for k in ("D_f", "K_f", "C_r", "E_r", "beta", "sd_K_f"):
            assert np.array_equal(on[k], off[k]), (filt, k)
        # mu = D / Fz: with the ellipse over the static load (TYRE_ID.md section 3.4), without
        # it over the load at ax; compared to 1e-12 relative (one division's rounding)
        fz0 = 1830.0 * 9.81 * 1.65 / 3.05
        assert np.allclose(on["mu_f"], on["D_f"] / fz0, rtol=1e-12, atol=0.0)
        assert not np.array_equal(on["mu_f"], off["mu_f"])


def test_ellipse_table_marks_moved_and_equal_cells_and_counts_targets():
    base = {"n": 1024, "seed": 1, "ms": 1.0, "ax_max": 0.5, "beta": 0.1, "curve_f": 4.0,
            "curve_r": 6.0, "mulim_f": 0.04, "mulim_r": 0.04, "sdlin_f": 0.3, "sdlin_r": 0.3,
            "tmax_f": 0.1, "tmax_r": 0.1, "mubrk_f": float("nan"), "mubrk_r": float("nan")}
    off = [dict(base, log=STEER, filter="sckf", ellipse=False)]
    on = [dict(base, log=STEER, filter="sckf", ellipse=True, mulim_r=0.06)]
    brake = "tid_brake_in_turn_high_mu"
    off.append(dict(base, log=brake, filter="sckf", ellipse=False, mubrk_f=0.2, mubrk_r=0.3))
    on.append(dict(base, log=brake, filter="sckf", ellipse=True, mubrk_f=0.2, mubrk_r=0.1))
    lines = R.ellipse_table(off, on, 1024, [1])
    row = next(line for line in lines if line.startswith(f"| {STEER} | SCKF |"))
    cells = row.split(" | ")
    assert cells[3] == "4.0 =" and cells[6] == "0.040 → 0.060"
    # mu@brake after mu@lim: "–" where the log does not brake, else without -> with
    assert cells[7] == "– =" and cells[8] == "– ="
    cells = next(line for line in lines if line.startswith(f"| {brake} | SCKF |")).split(" | ")
    assert cells[7] == "0.200 =" and cells[8] == "0.300 → 0.100"
    summ = next(line for line in lines if line.startswith("| SCKF | "))
    # per log: curve f meets (4.0), r does not (6.0); mu@lim r leaves the target on the sine
    # steer only; sd meets on both (mu@brake is not a target)
    assert summ == "| SCKF | 2/4 → 2/4 | 4/4 → 3/4 | 4/4 → 4/4 |"


def test_mu_at_brake_scores_the_braking_of_the_brake_in_turn_logs_only():
    # AX_BRAKE separates the logs that brake from those that do not: every other log's |ax|
    # stays below it (drag and noise), the brake-in-turn logs exceed it only while braked
    # (pressure from 4 s to 6 s with 0.2 s ramps; the deceleration lags by the wheels' slip)
    for log in R.LOGS:
        c = read_csv_log(str(R.ROOT / "scenarios" / "tyre_id" / f"{log}.csv")).columns
        brk = np.abs(c["ax"]) > R.AX_BRAKE
        if not log.startswith("tid_brake_in_turn"):
            assert not brk.any(), log
            continue
        t = c["t"][brk]
        assert t.min() > 4.0 and t.max() < 6.4, log
        # most of the braked window (4.2 s to 6.0 s at full pressure) is scored
        assert brk.sum() > 150, log


def test_summary_pools_the_steering_logs_that_do_not_brake():
    # the summary's medians are the lateral-only steering logs' (the page's text quotes them):
    # a braking log's row with an outlying curve must not move them
    base = {"filter": "sckf", "n": 1024, "seed": 1, "ms": 1.0, "beta": 0.1, "mulim_f": 0.04,
            "mulim_r": 0.04, "sdlin_f": 0.3, "sdlin_r": 0.3, "tmax_f": 0.1, "tmax_r": 0.1}
    for k in ("D", "C", "K", "E"):
        for a in "fr":
            base.update({f"sdfin_{k}_{a}": 1.0, f"mean_{k}_{a}": 1.0})
    base.update(Ktrue_f=1.0, Ktrue_r=1.0, Dtrue_f=1.0, Dtrue_r=1.0)
    rows = [dict(base, log=STEER, curve_f=1.0, curve_r=3.0),
            dict(base, log=R.BRAKING[0], curve_f=50.0, curve_r=60.0)]
    acc, cnt, _ = R.tables(rows, 1024, [1])
    assert sum(line.startswith(f"| {R.BRAKING[0]} | SCKF |") for line in acc) == 1
    summ = next(line for line in cnt if line.startswith("| SCKF |")).split(" | ")
    assert summ[2:4] == ["2.0", "3.0"]      # median and worst of 1.0 and 3.0 only


def test_delta_state_option_sets_the_state_key_and_the_table_counts_each_density():
    """--delta-state: a number in the job's delta slot runs the SCKF with delta as a state at
    that tid_delta_state_q (n = 11: it differs from the run without), True the steering-angle
    filter; the table chains off -> filter -> state per cell and counts targets per density."""
    c = read_csv_log(str(R.ROOT / "scenarios" / "tyre_id" / f"{LOG}.csv")).columns
    n = 60
    off = R.run_filter(c, "sckf", 0, 1, n_steps=n)
    on = R.run_filter(c, "sckf", 0, 1, n_steps=n, delta_filter=R.DELTA_STATE_Q)
    ref = TS.run(c, {"tid_delta_state_q": R.DELTA_STATE_Q}, n_steps=n)
    assert np.array_equal(on["K_f"], ref["K_f"]) and not np.array_equal(on["K_f"], off["K_f"])
    base = {"log": STEER, "filter": "sckf", "beta": 0.1, "curve_f": 4.0, "curve_r": 6.0,
            "mulim_f": 0.04, "mulim_r": 0.04, "sdlin_f": 0.3, "sdlin_r": 0.3}
    runs = [dict(base, delta_filter=False), dict(base, delta_filter=True, curve_r=5.0),
            dict(base, delta_filter=R.DELTA_STATE_Q, curve_r=1.0, sdlin_r=0.1),
            dict(base, delta_filter=0.01, mulim_f=0.2)]
    lines = R.delta_state_table(runs, [0.01, R.DELTA_STATE_Q])
    cells = next(line for line in lines if line.startswith(f"| {STEER} |")).split(" | ")
    assert cells[2] == "6.0 → 5.0 → 1.0" and cells[6] == "0.30 → 0.30 → 0.10"
    counts = [line for line in lines if line.startswith("| off") or line.startswith("| st")
              or line.startswith("| δ")]
    assert counts[0].startswith("| off (the default) | 1/2 | 2/2 | 2/2 |")
    assert counts[1].split(" | ")[1] == "2/2"             # curve r 5.0 meets <= 5
    assert counts[2].split(" | ")[1:4] == ["1/2", "1/2", "2/2"]   # 0.01: mu@lim f 0.2 misses
    assert counts[3].split(" | ")[1:4] == ["2/2", "2/2", "1/2"]   # 0.04: sd r 0.1 misses


def test_spread_option_adds_the_remedy_keys_to_the_state_and_counts_each_variant():
    """--spread: a dict in the job's delta slot runs the SCKF with delta as a state at
    DELTA_STATE_Q and those keys on top (here the D freeze, which changes the run); the table
    chains off -> state -> each remedy per cell and counts the targets per variant, keeping
    the variant False (off) apart from a remedy whose figures happen to match."""
    c = read_csv_log(str(R.ROOT / "scenarios" / "tyre_id" / f"{LOG}.csv")).columns
    n = 60
    keys = {"tid_d_freeze_u": 0.45}
    on = R.run_filter(c, "sckf", 0, 1, n_steps=n, delta_filter=keys)
    ref = TS.run(c, {"tid_delta_state_q": R.DELTA_STATE_Q, **keys}, n_steps=n)
    state = R.run_filter(c, "sckf", 0, 1, n_steps=n, delta_filter=R.DELTA_STATE_Q)
    assert np.array_equal(on["sd_D_f"], ref["sd_D_f"])
    assert not np.array_equal(on["sd_D_f"], state["sd_D_f"])
    base = {"log": STEER, "filter": "sckf", "beta": 0.1, "curve_f": 4.0, "curve_r": 6.0,
            "mulim_f": 0.04, "mulim_r": 0.04, "sdlin_f": 0.3, "sdlin_r": 0.3}
    runs = [dict(base, delta_filter=False),
            dict(base, delta_filter=R.DELTA_STATE_Q, sdlin_r=0.1),
            dict(base, delta_filter=dict(keys), sdlin_r=0.25, curve_r=7.0)]
    lines = R.spread_table(runs, [("freeze", keys)])
    cells = next(line for line in lines if line.startswith(f"| {STEER} |")).split(" | ")
    assert cells[2] == "6.0 → 6.0 → 7.0" and cells[6] == "0.30 → 0.10 → 0.25"
    counts = [line.split(" | ")[1:4] for line in lines
              if line.startswith("| off") or line.startswith("| δ")]
    assert counts == [["1/2", "2/2", "2/2"], ["1/2", "2/2", "1/2"], ["1/2", "2/2", "2/2"]]
