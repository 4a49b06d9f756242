"""Tests of scripts/checks/check_tools.py: a tool outside its pin fails the check (and only warns
with --warn); a missing tool is reported, not failed."""

import os
import sys

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)

import check_tools  # noqa: E402

FAKE = [sys.executable, "-c", "print('faketool 4.5.6')"]


def _pins(monkeypatch, pin, cmd=FAKE):
    monkeypatch.setattr(check_tools, "PINS", [("fake", cmd, r"faketool (\S+)", pin, "nothing")])


# REQ-REF-004
def test_pins_match_prefix_and_minimum():
    assert check_tools.matches("12.2.0", "12.") and not check_tools.matches("13.1.0", "12.")
    assert check_tools.matches("3.11.7", "3.11+") and check_tools.matches("3.12.1", "3.11+")
    assert not check_tools.matches("3.10.9", "3.11+") and check_tools.matches("4.0", "3.11+")


# REQ-REF-004
def test_outside_the_pin_fails_and_warn_goes_on(monkeypatch, capsys):
    _pins(monkeypatch, "4.5")
    assert check_tools.main([]) == 0 and "faketool" not in capsys.readouterr().err
    _pins(monkeypatch, "5.")
    assert check_tools.main([]) == 1
    err = capsys.readouterr().err
    assert "fake 4.5.6 is not the pinned 5.*: it decides nothing" in err and "TOOL_PINS=warn" in err
    assert check_tools.main(["--warn"]) == 0


# REQ-REF-004
def test_missing_tool_is_reported(monkeypatch, capsys):
    _pins(monkeypatch, "5.", cmd=["no-such-tool-anywhere", "--version"])
    assert check_tools.main([]) == 0
    assert "fake: not installed" in capsys.readouterr().out
