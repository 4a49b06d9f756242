"""Tests of the fault injection (faults.py) and of the committed scenarios/faults/ logs."""

import os
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
sys.path[:0] = [os.path.dirname(HERE), os.path.join(os.path.dirname(HERE), "data")]

from sim import faults  # noqa: E402
import make_fault_scenarios  # noqa: E402

SCEN = os.path.join(REPO, "scenarios")
FAULT_DIR = os.path.join(SCEN, "faults")
DT = 0.01


def _logs(f):
    clean = faults.read_log(os.path.join(SCEN, f.base + ".csv"))
    return clean, faults.apply(f, *clean)


# REQ-ROB-008
def test_committed_fault_logs_are_up_to_date():
    """REQ: scenarios/faults/ is exactly what make fault-scenarios writes from the bundled logs."""
    assert make_fault_scenarios.main(["--scenarios", SCEN, "--out", FAULT_DIR, "--check"]) == 0


# REQ-ROB-008
def test_fault_logs_are_deterministic():
    """REQ: the same fault on the same clean log gives the same bytes (fixed seeds)."""
    for f in faults.FAULTS:
        assert faults.make(f, SCEN) == faults.make(f, SCEN)


# REQ-ROB-008
def test_faults_cover_the_issue_list():
    """REQ: spikes on ax, ay, yaw rate; a dropped sample; a frozen wheel speed; an
    accelerometer offset."""
    kinds = {(f.kind, f.column) for f in faults.FAULTS}
    for want in [("spike", "ax"), ("spike", "ay"), ("spike", "yaw_rate"), ("drop", None),
                 ("freeze", "omega_fl"), ("offset", "ax"), ("offset", "ay")]:
        assert want in kinds


# REQ-ROB-008
@pytest.mark.parametrize("f", faults.FAULTS, ids=faults.file_name)
def test_fault_changes_only_what_it_says(f):
    """REQ: a fault log equals its clean twin except where (and how) the fault acts; the
    fault column flags exactly those rows."""
    (cmeta, chead, crows), (fmeta, fhead, frows) = _logs(f)
    assert fhead == chead + ["fault"]
    assert fmeta[:len(cmeta)] == cmeta
    assert f"# fault = {f.name}" in fmeta and f"# fault_base = {f.base}.csv" in fmeta
    ti = chead.index("t")
    flag = [int(r[-1]) for r in frows]
    if f.kind == "drop":
        assert len(frows) == len(crows) - f.count
        kept = {r[ti] for r in frows}
        t = [float(r[ti]) for r in frows]
        for i, r in enumerate(frows):
            assert r[:-1] == next(c for c in crows if c[ti] == r[ti])
            if flag[i]:
                assert t[i] - t[i - 1] == pytest.approx(2 * DT, abs=1e-9)
            elif i:
                assert t[i] - t[i - 1] == pytest.approx(DT, abs=1e-9)
        assert len(crows) - len(kept) == f.count
        return
    assert len(frows) == len(crows)
    c = chead.index(f.column)
    t = [float(r[ti]) for r in crows]
    t_fault = [t[i] for i in range(len(t)) if flag[i]]
    for i, (cr, fr) in enumerate(zip(crows, frows)):
        others = [k for k in range(len(chead)) if k != c]
        assert [fr[k] for k in others] == [cr[k] for k in others]
        if not flag[i]:
            assert fr[c] == cr[c]
            continue
        assert f.window[0] <= t[i] <= f.window[1]
        d = float(fr[c]) - float(cr[c])
        if f.kind == "spike":
            assert abs(d) == pytest.approx(f.magnitude, abs=1e-9)
        elif f.kind == "offset":
            assert d == pytest.approx(f.magnitude, abs=1e-9)
        else:  # freeze: the value at the first frozen row
            assert fr[c] == frows[flag.index(1)][c]
    if f.kind == "spike":
        assert sum(flag) == f.count
        assert min(b - a for a, b in zip(t_fault, t_fault[1:])) >= faults.MIN_GAP - 1e-9
    elif f.kind == "freeze":
        assert t_fault[0] == pytest.approx(f.window[0]) and t_fault[-1] < f.window[1]
