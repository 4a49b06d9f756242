"""Tests of check_data_names.py: a dropped column fails, a reworded or grown table passes."""

import os
import sys

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__))]

import check_data_names  # noqa: E402

SHARED = "| column | meaning |\n|---|---|\n| t | time |\n| vx, vy | velocity |\n"


def run(tmp_path, own):
    (tmp_path / "s.md").write_text(SHARED)
    (tmp_path / "o.md").write_text(own)
    return check_data_names.main([str(tmp_path / "s.md"), str(tmp_path / "o.md")])


def test_grown_and_reworded_passes(tmp_path):
    own = SHARED.replace("velocity", "velocity (optional)") + "| p_fl | pressure |\n"
    assert run(tmp_path, own) == 0


def test_a_dropped_name_fails(tmp_path, capsys):
    assert run(tmp_path, SHARED.replace("| vx, vy |", "| vx |")) == 1
    assert "vy" in capsys.readouterr().out


def test_usage(tmp_path):
    assert check_data_names.main([]) == 2
