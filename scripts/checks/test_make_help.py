"""Tests of scripts/checks/make_help.py: make help lists every described target, and --check fails
on a .PHONY target without a description or a ## line that describes no rule."""

import os
import sys

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)

import make_help  # noqa: E402


def mk(tmp_path, text):
    p = tmp_path / "Makefile"
    p.write_text(text)
    return str(p)


# REQ-QA-010
def test_help_lists_described_targets(tmp_path, capsys):
    f = mk(tmp_path, ".PHONY: a b\n## does a\na: b\n\techo a\n## does b\nb:\n\techo b\n")
    assert make_help.main(["--check", f]) == 0
    assert make_help.main([f]) == 0
    out = capsys.readouterr().out
    assert "a  does a" in out and "b  does b" in out


# REQ-QA-010
def test_check_fails_on_undescribed_phony_and_stray_line(tmp_path, capsys):
    f = mk(tmp_path, ".PHONY: a \\\n  c\n## does a\na:\n\techo\n## stray\n\nc:\n\techo\n")
    assert make_help.main(["--check", f]) == 1
    err = capsys.readouterr().err
    assert "target c (.PHONY) has no ## description" in err and "not directly above a rule" in err


# REQ-QA-010
def test_the_repository_describes_every_target(capsys):
    assert make_help.main(["--check"]) == 0
