"""Tests of scripts/firmware/pil_budgets.py, the gate of the PIL instruction counts (issue 21):
synthetic counts against synthetic budgets, the JSON of firmware_pil.py read into runs, and the
budget file written and read back."""

import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import pil_budgets  # noqa: E402

BUDGET = 100_000.0  # round, so each percentage below is an exact count of instructions


def run(count, target="m4f-q31", entry="default.sckf", log="brake_in_turn", steps=100):
    return {"target": target, "entry": entry, "log": log, "steps": steps, "instructions_per_step": count}


BUDGETS = [dict(run(BUDGET), source="test")]


def test_over_by_2_1_percent_fails_naming_run_budget_and_count():
    failures, notes = pil_budgets.check([run(102_100.0)], BUDGETS)
    assert len(failures) == 1 and not notes
    msg = failures[0]
    assert "default.sckf on m4f-q31" in msg and "100,000" in msg and "102,100" in msg and "+2.1%" in msg


def test_over_by_1_9_percent_passes():
    assert pil_budgets.check([run(101_900.0)], BUDGETS) == ([], [])


def test_exactly_2_percent_over_passes():
    # the rule is "more than 2 %"
    assert pil_budgets.check([run(102_000.0)], BUDGETS) == ([], [])


def test_missing_entry_fails():
    failures, _ = pil_budgets.check([run(BUDGET, target="m0p-q31")], BUDGETS)
    assert len(failures) == 1 and "m0p-q31" in failures[0] and "no budget" in failures[0]


def test_other_step_count_is_a_missing_entry():
    # the mean over another number of steps is another quantity: no budget applies
    failures, _ = pil_budgets.check([run(BUDGET, steps=20)], BUDGETS)
    assert len(failures) == 1 and "first 20 steps" in failures[0]


def test_far_under_notes_that_the_budget_can_be_lowered():
    failures, notes = pil_budgets.check([run(94_900.0)], BUDGETS)
    assert not failures and len(notes) == 1 and "can be lowered" in notes[0] and "-5.1%" in notes[0]


def test_a_little_under_is_silent():
    assert pil_budgets.check([run(95_100.0)], BUDGETS) == ([], [])


def test_budget_without_a_run_is_not_checked():
    # make pil and make pil-aux each measure a part of the file's runs
    assert pil_budgets.check([], BUDGETS) == ([], [])


def test_measured_reads_every_kind_of_run():
    pil = {"log": "scenarios/brake_in_turn.csv", "obs_log": "scenarios/observer/abs.csv",
           "runs": [{"target": "m4f-f32", "config": "paper.sckf",
                     "instructions_per_step": {"mean": 16030.4, "steps": 100}},
                    {"target": "m3-q31", "config": "paper.sckf"}],  # a run that failed: no count
           "observer_runs": [{"target": "m0p-q31", "tag": "pipeline",
                              "instructions_per_step": {"mean": 814400.4, "steps": 20}}]}
    aux = {"aux_runs": [{"target": "m4f-f32", "entry": "tid", "log": "scenarios/tyre_id/tid.csv",
                         "instructions_per_step": {"mean": 2.5e6, "steps": 20}}],
           "aux_q31_runs": [{"target": "m0p-q31", "entry": "mg_ukf",   # no log of its own
                             "instructions_per_step": {"mean": 134023.0, "steps": 50}}]}
    assert pil_budgets.measured(pil) + pil_budgets.measured(aux) == [
        run(16030.4, "m4f-f32", "paper.sckf"), run(814400.4, "m0p-q31", "pipeline", "abs", 20),
        run(2.5e6, "m4f-f32", "tid", "tid", 20), run(134023.0, "m0p-q31", "mg_ukf", "", 50)]


def test_write_sets_measured_runs_and_keeps_the_others(tmp_path):
    path = str(tmp_path / "budgets.json")
    pil_budgets.write(path, [run(BUDGET), run(5_000.0, entry="mg_ukf")], "first")
    assert pil_budgets.write(path, [run(90_000.0)], "second") == (1, 1)
    budgets = pil_budgets.load(path)
    assert {(b["entry"], b["instructions_per_step"], b["source"]) for b in budgets} == \
        {("default.sckf", 90_000.0, "second"), ("mg_ukf", 5_000.0, "first")}
    assert "about" in json.load(open(path))
    assert pil_budgets.check([run(90_000.0), run(5_000.0, entry="mg_ukf")], budgets) == ([], [])


def test_main_fails_over_budget(tmp_path, capsys):
    budgets, result = tmp_path / "b.json", tmp_path / "pil.json"
    pil_budgets.write(str(budgets), [run(BUDGET)], "test")
    result.write_text(json.dumps({"log": "x/brake_in_turn.csv", "runs": [
        {"target": "m4f-q31", "config": "default.sckf",
         "instructions_per_step": {"mean": 102_100.0, "steps": 100}}]}))
    assert pil_budgets.main([str(budgets), str(result)]) == 1
    assert "FAIL" in capsys.readouterr().out


def test_write_only_sets_the_named_entry_and_keeps_every_other_budget(tmp_path, capsys):
    budgets, result = tmp_path / "b.json", tmp_path / "pil_aux.json"
    pil_budgets.write(str(budgets), [run(BUDGET), run(5_000.0, "m4f-f32", "tid", "tid", 20)], "old")
    result.write_text(json.dumps({"aux_runs": [
        {"target": "m4f-f32", "entry": "tid", "log": "x/tid.csv", "instructions_per_step": {"mean": 6_000.0, "steps": 20}},
        {"target": "m4f-f32", "entry": "tid_sckf", "log": "x/tid.csv",
         "instructions_per_step": {"mean": 143_920.0, "steps": 200}}]}))
    # the option before the positional arguments, as make pil-budgets passes it
    assert pil_budgets.main(["--write", "--only", "tid_sckf", str(budgets), str(result)]) == 0
    got = {(b["entry"], b["instructions_per_step"], b["source"] == "old") for b in pil_budgets.load(str(budgets))}
    assert got == {("default.sckf", BUDGET, True), ("tid", 5_000.0, True), ("tid_sckf", 143_920.0, False)}
    # an entry the results do not hold writes nothing
    try:
        pil_budgets.main([str(budgets), str(result), "--write", "--only", "mg_ukf"])
        assert False, "no run of mg_ukf: must exit"
    except SystemExit as e:
        assert "no measured run of mg_ukf" in str(e)
    assert len(pil_budgets.load(str(budgets))) == 3


def test_the_committed_budgets_are_well_formed():
    path = os.path.join(os.path.dirname(__file__), "..", "..", "firmware", "pil_budgets.json")
    budgets = pil_budgets.load(path)
    keys = [pil_budgets.run_key(b) for b in budgets]
    assert budgets and len(keys) == len(set(keys))
    assert all(b["instructions_per_step"] > 0 and b["source"] for b in budgets)
