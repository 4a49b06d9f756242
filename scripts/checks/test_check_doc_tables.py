"""Tests of scripts/checks/check_doc_tables.py on doctored copies of the docs: a copy of
every file the check reads goes to tmp_path, one of them is changed, and the check runs on
the copy (--root). It runs build/mu_replay for the library's values (make build/mu_replay;
skipped without it, as the other tests that run it)."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__))]

import check_doc_tables as cdt  # noqa: E402

REPO = Path(cdt.ROOT)
REPLAY = REPO / "build" / "mu_replay"
FILES = ["README.md", "include/rfe/common.h", "docs/spec/DATA.md", "docs/ESTIMATOR.md",
         "docs/MONITOR.md", "docs/OBSERVER.md", "scripts/reference/observer.py"]

pytestmark = pytest.mark.skipif(not REPLAY.is_file(),
                                reason="needs build/mu_replay (make build/mu_replay)")


@pytest.fixture
def root(tmp_path):
    for rel in FILES:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(REPO / rel, tmp_path / rel)
    return tmp_path


def doctor(root, rel, old, new):
    """Replace the one occurrence of @p old in the copy of @p rel by @p new."""
    path = root / rel
    text = path.read_text(encoding="utf-8")
    assert text.count(old) == 1, f"{rel}: '{old}' occurs {text.count(old)} times"
    path.write_text(text.replace(old, new), encoding="utf-8")


def problems(root):
    return cdt.check(str(REPLAY), str(root))[0]


# REQ-DOC-001
def test_the_docs_as_they_are_agree(root):
    assert problems(root) == []


# REQ-DOC-001
def test_a_changed_monitor_default_is_caught(root):
    doctor(root, "docs/MONITOR.md", "| `mon_hold` | 0.5 | 0.5 |", "| `mon_hold` | 0.5 | 7.5 |")
    assert problems(root) == ["docs/MONITOR.md \"Parameters\": mon_hold = 7.5 in the default "
                              "column, the library's default preset has 0.5"]


# REQ-DOC-001
def test_a_changed_paper_value_of_the_monitor_is_caught(root):
    doctor(root, "docs/MONITOR.md", "| `mon_warmup` | 1.0 |", "| `mon_warmup` | – |")
    assert problems(root) == ["docs/MONITOR.md \"Parameters\": mon_warmup = – in the paper "
                              "column, the library's paper preset has 1"]


# REQ-DOC-001
def test_a_deleted_monitor_row_is_caught(root):
    doctor(root, "docs/MONITOR.md", "| `mon_inflate` | 1 | 1 | – | 1: sd × √max(1, D/m) while "
           "fired; 0: sd untouched |\n", "")
    assert problems(root) == ["docs/MONITOR.md \"Parameters\": no row for 'mon_inflate'"]


# REQ-DOC-001
def test_a_deleted_estimator_row_is_caught(root):
    doctor(root, "docs/ESTIMATOR.md", "| `sd_valid` | 0 (paper rule) | 0.15 | – | an estimate is "
           "valid when its sd ≤ sd_valid and it is not on a projection bound |\n", "")
    assert problems(root) == ["docs/ESTIMATOR.md \"Parameters added to DATA.md\": no row for "
                              "'sd_valid' (a key of the library's presets that DATA.md's table "
                              "does not list either)"]


# REQ-DOC-001
def test_a_key_the_presets_differ_in_must_be_in_estimator_md(root):
    # sd0 is in DATA.md's table too, but only ESTIMATOR.md gives the default preset's value
    doctor(root, "docs/ESTIMATOR.md",
           "| `sd0` | 0.3 | 0.1 | – | prior sd, differential (per-state) part |\n", "")
    found = problems(root)
    assert len(found) == 1 and "no row for 'sd0' (the presets differ in it" in found[0], found


# REQ-DOC-001
def test_a_changed_observer_default_is_caught(root):
    doctor(root, "docs/OBSERVER.md", "| `obs_k_gate` | 3 |", "| `obs_k_gate` | 4 |")
    found = problems(root)
    # one line per preset (the column is the default of both)
    assert found == [f"docs/OBSERVER.md §2 \"Parameters\": obs_k_gate = 4 in the {p} column, "
                     f"the library's {p} preset has 3" for p in ("default", "paper")]


# REQ-DOC-001
def test_a_changed_one_of_a_pair_in_the_observer_table_is_caught(root):
    doctor(root, "docs/OBSERVER.md", "| 0.005, 0.05 | m/s²/√s |", "| 0.005, 0.5 | m/s²/√s |")
    assert any("obs_q_by = 0.5 in the default column" in p for p in problems(root))


# REQ-DOC-001
def test_a_deleted_observer_row_is_caught(root):
    doctor(root, "docs/OBSERVER.md", "| `obs_v_stand` | 0.3 | m/s | every wheel reference below "
           "this: standing |\n", "")
    assert problems(root) == ["docs/OBSERVER.md §2 \"Parameters\": no row for 'obs_v_stand'"]


# REQ-DOC-001
def test_a_row_with_fewer_values_than_keys_is_caught(root):
    doctor(root, "docs/OBSERVER.md", "| `obs_sd_vx0`, `obs_sd_bx0` | 1.0, 0.3 |",
           "| `obs_sd_vx0`, `obs_sd_bx0`, `obs_sd_vy0` | 1.0, 0.3 |")
    assert any("3 keys (obs_sd_vx0, obs_sd_bx0, obs_sd_vy0) but 2 values" in p
               for p in problems(root))


# REQ-DOC-001
def test_the_reference_observer_defaults_are_the_librarys(root):
    doctor(root, "scripts/reference/observer.py", '"obs_sd_r": 0.005,', '"obs_sd_r": 0.006,')
    doctor(root, "scripts/reference/observer.py",
           '    "obs_v_stand": 0.3,         # every wheel below this: standing, m/s\n', "")
    assert problems(root) == [
        "scripts/reference/observer.py OBS_DEFAULTS: obs_sd_r = 0.006, the library's default "
        "is 0.005",
        "scripts/reference/observer.py OBS_DEFAULTS: no row for 'obs_v_stand'"]


# REQ-DOC-001
def test_the_command_line_exits_1_and_names_the_difference(root):
    doctor(root, "docs/MONITOR.md", "| `mon_hold` | 0.5 | 0.5 |", "| `mon_hold` | 0.5 | 7.5 |")
    run = subprocess.run([sys.executable, cdt.__file__, str(REPLAY), "--root", str(root)],
                         capture_output=True, text=True, check=False)
    assert run.returncode == 1
    assert "mon_hold = 7.5" in run.stdout and "1 difference(s)" in run.stdout


# REQ-DOC-001: the review's statements (issue 18) that contradicted the code
def test_an_intro_calling_dugoff_the_default_is_caught(root):
    doctor(root, "README.md", "Magic Formula tyre by default, Dugoff in the paper preset",
           "Dugoff tyre by default, Magic Formula in the paper preset")
    found = problems(root)
    assert len(found) == 2 and all(p.startswith("README.md intro:") for p in found)
    assert "'Magic Formula tyre by default'" in found[0]


# REQ-DOC-001
def test_an_intro_promising_each_of_the_four_wheels_is_caught(root):
    doctor(root, "README.md", "(by default one μ per side,", "(each of the four wheels,")
    found = problems(root)
    assert len(found) == 1 and "'one μ per side'" in found[0]


# REQ-DOC-001
def test_data_md_calling_the_dt_metadata_ignored_is_caught(root):
    doctor(root, "docs/spec/DATA.md", "`dt` there is the parameter of",
           "`dt` there is ignored, not the parameter of")
    found = problems(root)
    assert len(found) == 1 and found[0].startswith("docs/spec/DATA.md:")
