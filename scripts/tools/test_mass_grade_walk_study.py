"""scripts/tools/mass_grade_walk_study.py: its walks are valid filters and its table takes the
worst of the four starts."""
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mass_grade_walk_study as ws  # noqa: E402
from mass_grade_walk_study import mg  # noqa: E402


def test_walks_are_valid_and_the_two_level_walk_is_on():
    for over in ws.WALKS.values():
        p = mg.preset("car", **mg.MG_CONFIGS["recommended"])
        p.update(over)
        mg.MassGrade(p)                 # raises ParamError on an invalid key
    assert ws.WALKS["two-level"]["mg_q_theta_hi"] > ws.WALKS["two-level"]["mg_q_theta"]
    # the fixed walks turn the preset's two-level walk off
    assert ws.WALKS["fixed 0.004"]["mg_q_theta_hi"] == 0.0
    assert ws.WALKS["fixed 0.006"]["mg_q_theta_hi"] == 0.0


def test_table_takes_the_worst_start():
    res = {}
    for w in ws.WALKS:
        for k, g in enumerate(ws.mgr.GUESSES):
            res[("car_x", g, w)] = {"rmse": 0.1 * (k + 1), "err_after": 0.5 * k,
                                    "hi_share": 0.25 * k}
    lines = ws.table(res, ["car_x"])
    assert len(lines) == 3
    row = lines[2].split(" | ")
    # four starts: rmse 0.1..0.4, mass error 0..1.5 %, loose share 0..75 %: the largest each
    assert row[1] == "0.400 deg" and row[4] == "1.50 %" and row[-1] == "75 % |"
