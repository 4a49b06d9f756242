"""Tests of scripts/firmware/firmware_opt.py's parts that need no cross-build or QEMU: the flags
of a setting and the table with its changes against the shipped setting."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import firmware_opt  # noqa: E402


def test_flags_of_settings():
    assert firmware_opt.flags("O2") == "-O2"
    assert firmware_opt.flags("Os-lto") == "-Os -flto"


def row(setting, flash, paper, default, equal=True, lib=1000):
    return {"target": "m0p-q31", "machine": "microbit", "setting": setting,
            "flags": firmware_opt.flags(setting), "library_flash_map": lib if "lto" not in setting else None,
            "library_and_program_flash": flash,
            "instructions_per_step": {"paper.sckf": paper, "default.sckf": default},
            "outputs_equal": {"paper.sckf": True, "default.sckf": equal}}


def test_table_against_the_shipped_setting_and_verdict():
    res = {"log": "brake_in_turn.csv", "steps": 100, "shipped": {"m0p": "-Os"},
           "rows": [row("Os", 2000, 100.0, 1000.0), row("O2", 3000, 90.0, 800.0),
                    row("O2-lto", 1800, 95.0, 900.0, equal=False)]}
    lines = firmware_opt.markdown(res)
    table = [ln for ln in lines if ln.startswith("| Cortex-M0+")]
    assert table[0].split(" | ")[1] == "`-Os` (shipped)"
    assert "(+50.0 %)" in table[1] and "800 (-20.0 %)" in table[1]
    assert "– (LTO)" in table[2] and table[2].endswith("| **differ** |")
    verdict = [ln for ln in lines if ln.startswith("- Cortex-M0+")][0]
    assert "fewest instructions on `default.sckf` with `-O2` (-20.0 %, flash +50.0 %)" in verdict
    # -O2 -flto is smaller, but its outputs differ: it is not recommended
    assert "smallest with `-Os` (flash +0.0 %" in verdict


def test_a_setting_smaller_and_faster_everywhere_is_named():
    res = {"log": "brake_in_turn.csv", "steps": 100, "shipped": {"m0p": "-Os"},
           "rows": [row("Os", 2000, 100.0, 1000.0), row("Os-lto", 1900, 99.0, 1000.0),
                    row("O2", 1900, 101.0, 900.0)]}   # faster on one configuration only
    verdict = [ln for ln in firmware_opt.markdown(res) if ln.startswith("- Cortex-M0+")][0]
    assert "`-Os -flto` is smaller (flash -5.0 %) and faster on every configuration" in verdict
    assert "`-O2` is smaller" not in verdict
