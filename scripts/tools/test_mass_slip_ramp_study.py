"""mass_slip_ramp_study.py: the rollback variant against the reference on the first 0.7 s of
traction_rwd_mu03 (the torque ramp from 0.5 s, the first slip-paused sample at 0.61 s), and the
page's text on results written here."""

import math
import os
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mass_slip_ramp_study as rs  # noqa: E402

mg = rs.mg
LOG = os.path.join(rs.ROOT, "scenarios", "observer", "traction_rwd_mu03.csv")
N_SAMPLES = 71          # t = 0 ... 0.70 s


def _samples():
    cols, _ = mg.read_log(LOG)
    return rs.observer_samples(cols, mg.MG_DEFAULTS["R"])[:N_SAMPLES]


def _params():
    return mg.preset("car", **rs.RECOMMENDED)


def _run(est, samples):
    return [est.step(s) for s in samples]


def _fields(o):
    return (o.mass, o.sd_mass, o.grade, o.sd_grade, o.v, o.sd_v, o.q_mv, o.status)


def test_period_zero_is_the_reference_bit_for_bit():
    """T = 0: no snapshot, no restore: every output equals the reference's, the slip pause
    acting (the statuses include 7)."""
    s = _samples()
    ref = _run(mg.MassGrade(_params()), s)
    rb = _run(rs.Rollback(_params(), 0.0), s)
    assert [_fields(o) for o in rb] == [_fields(o) for o in ref]
    assert any(o.status == mg.PAUSED_SLIP for o in ref)


def test_no_slip_onset_no_change():
    """The same samples without vx (no slip pause, so no onset): T = 0.1 s equals the
    reference bit for bit although its slots shift every 10 updates."""
    s = _samples()
    for x in s:
        x.vx = None
    ref = _run(mg.MassGrade(_params()), s)
    est = rs.Rollback(_params(), 0.1)
    rb = _run(est, s)
    assert [_fields(o) for o in rb] == [_fields(o) for o in ref]
    assert est.restores == 0 and est.rb_prev != est.rb_cur


def test_onset_restores_the_previous_slot():
    """T = 0.05 s at dt = 0.01 s: the slots shift after every 5th update (the clock reaches
    0.05 >= T - dt/2 at the 5th, 0.04 < 0.045 at the 4th). Samples 1 ... 60 are updates (0
    is the start), so at the onset (sample 61) the previous slot is the state after sample
    55: the output's mass and grade are the reference's after sample 55 bit for bit (the
    hold keeps M and theta), and the held samples after it keep them. Without the restore
    the mass would be the reference's at 60, which differs."""
    s = _samples()
    ref = _run(mg.MassGrade(_params()), s)
    first = next(k for k, o in enumerate(ref) if o.status == mg.PAUSED_SLIP)
    assert first == 61 and all(o.status == mg.OK for o in ref[:first])
    est = rs.Rollback(_params(), 0.05)
    rb = _run(est, s)
    assert [_fields(o) for o in rb[:first]] == [_fields(o) for o in ref[:first]]
    assert (rb[first].mass, rb[first].grade) == (ref[55].mass, ref[55].grade)
    assert rb[first].mass != ref[first].mass          # what the pause alone keeps: sample 60's
    # the hold's 2 x 4 triangularisation recomputes the mass row of S from the restored one:
    # its norm, sd_mass, the same up to rounding (a few ulps of the 2-row Householder)
    assert rb[first].sd_mass == pytest.approx(ref[55].sd_mass, rel=1e-12)
    assert est.restores == 1
    held = [o for o in rb[first:] if o.status == mg.PAUSED_SLIP]
    assert len(held) > 5 and all(o.mass == ref[55].mass for o in held)


def test_course_and_worst_distance():
    """The mass's course at TIMES is the output of the first sample at or after each (t = 0.6
    s: sample 60), and the largest |M - m| / sd from 0.5 s on is at least that of any sample
    from there, computed here from the outputs."""
    cols, _ = mg.read_log(LOG)
    s = rs.observer_samples(cols, mg.MG_DEFAULTS["R"])
    ref = _run(mg.MassGrade(mg.preset("car", **rs.RECOMMENDED, **rs.SIM_RESISTANCES,
                                      mg_slip_max=0.0)), s)
    _, r = rs.observer_job(("traction_rwd_mu03.csv", 1.0, "sim's resistances, off"))
    assert r["course"][rs.TIMES.index(0.6)] == (ref[60].mass, ref[60].sd_mass)
    z = [abs(o.mass - 1830.0) / o.sd_mass for o, t in zip(ref, cols["t"]) if t >= 0.5]
    assert r["worst_z"] == max(z)


def test_bad_period_refused():
    for bad in (-0.1, math.nan, math.inf):
        with pytest.raises(mg.ParamError):
            rs.Rollback(_params(), bad)


def _res(mass, sd=10.0, m=1000.0, restores=0):
    return {"m": m, "mass": mass, "sd": sd, "restores": restores, "n_ok": 1,
            "slip_before": 0.02, "slip_ramp": 0.04, "worst_z": 3.25,
            "course": [(mass, sd)] * len(rs.TIMES)}


def test_tables():
    """A traction log gets a row per start with each variant's error and sd against m; the
    other logs' largest change against the pause per rollback; the mass and grade rows."""
    names = ["traction_x.csv", "other.csv"]
    obs = {}
    for s in rs.STARTS:
        for v in rs.VARIANTS:
            obs[("traction_x.csv", s, v)] = _res(950.0 if v == "pause" else 1020.0)
            obs[("other.csv", s, v)] = _res(1000.0 + (2.5 if v == "rollback 0.1 s" else 0.0),
                                            restores=1 if v.startswith("rollback") else 0)
    mgr = {("a.csv", v): {"mass_err": 0.01, "grade_rmse": 0.0012, "restores": 0}
           for v in rs.VARIANTS}
    text = rs.tables(obs, names, mgr, ["a.csv"])
    rows = [r for r in text.splitlines() if r.startswith("| traction_x |") and " m | " in r]
    assert len(rows) == len(rs.STARTS)
    assert rows[0].startswith("| traction_x | 1.0 m | +2.0% (1.0%) | -5.0% (1.0%) | +2.0%")
    assert "rollback 0.1 s against the pause: 3 rollbacks over the 3 starts, the largest " \
           "change of the mass at the end 2.5 kg (other)." in text
    assert "rollback 0.05 s against the pause: 3 rollbacks over the 3 starts, the largest " \
           "change of the mass at the end 0 kg." in text
    assert "| a | +1.00%, 1.200, 0 |" in text
    course = [r for r in text.splitlines() if r.startswith("| traction_x | o")]
    assert course == ["| traction_x | off |" + " +2.0% (1.0%) |" * len(rs.TIMES) + " 3.2 |",
                      "| traction_x | on |" + " +2.0% (1.0%) |" * len(rs.TIMES) + " 3.2 |"]
    assert "up to 0.0200…0.0200; from 0.5 s to the first slip-held sample (the ramp's " \
           "updates) up to 0.0400…0.0400." in text


def test_res_tables_and_paths():
    """The logs with the car's resistances: a row per start with the pause off and on, the
    course from m with both, the updates with the pause; a _res log is read from
    scenarios/observer_res/, the others from scenarios/observer/."""
    obs = {}
    for s in rs.STARTS:
        obs[("traction_x_res.csv", s, "off")] = _res(1001.0)
        obs[("traction_x_res.csv", s, "pause")] = _res(1040.0, sd=20.0)
    text = "\n".join(rs.res_tables(obs, ["traction_x_res.csv"]))
    rows = [r for r in text.splitlines() if r.startswith("| traction_x_res |") and " m | " in r]
    assert rows == [f"| traction_x_res | {s:.1f} m | +0.1% (1.0%) | +4.0% (2.0%) |"
                    for s in rs.STARTS]
    course = [r for r in text.splitlines() if r.startswith("| traction_x_res | o")]
    assert course == ["| traction_x_res | off |" + " +0.1% (1.0%) |" * len(rs.TIMES) + " 3.2 |",
                      "| traction_x_res | on |" + " +4.0% (2.0%) |" * len(rs.TIMES) + " 3.2 |"]
    assert "Updates (status 0) with the pause, from m: traction_x_res 1." in text
    assert rs.res_tables(obs, []) == []
    assert rs.log_path("hill_res.mf.csv") == os.path.join(rs.ROOT, "scenarios", "observer_res",
                                                          "hill_res.mf.csv")
    assert rs.log_path("hill.csv") == os.path.join(rs.ROOT, "scenarios", "observer", "hill.csv")


def test_shared_study_helpers(tmp_path, capsys):
    """What the mass studies share (mass_curve_pause_study.py uses it too): the mass and grade
    logs (the .csv names, sorted; truck_* in the truck preset, the others in the car's), their
    samples with vx_true as the ground speed (one a row, otherwise the reference's own), and
    the command line: --jobs handed to the study, its text printed and written between the
    page's markers with the rest of the page kept."""
    names = rs.mass_grade_logs()
    assert names and names == sorted(names) and all(n.endswith(".csv") for n in names)
    assert "truck_graded_drive.csv" in names and "car_gear_shift.csv" in names
    assert rs.mass_grade_log("truck_graded_drive.csv")[2] == "truck"
    cols, _, vehicle = rs.mass_grade_log("car_gear_shift.csv")
    assert vehicle == "car"
    p = mg.preset(vehicle)
    plain = list(mg.samples(cols, p))
    got = rs.true_speed_samples(cols, p)
    assert len(got) == len(plain) == len(cols["t"])
    assert [s.vx for s in got] == [float(v) for v in cols["vx_true"]]
    assert all(a.vx is None for a in plain)
    assert [(s.t, s.v, s.torque, s.ax) for s in got] == [(s.t, s.v, s.torque, s.ax) for s in plain]
    page = tmp_path / "page.md"
    page.write_text("head\n<!-- x-y:begin -->\nold\n<!-- x-y:end -->\ntail\n")
    seen = []
    rs.study_main(["--page", str(page), "--jobs", "3"], "title\nmore", "x-y", "who",
                  lambda n: seen.append(n) or "a\nb")
    assert seen == [3]
    assert capsys.readouterr().out == "a\nb\n"
    assert page.read_text() == "head\n<!-- x-y:begin -->\na\nb\n<!-- x-y:end -->\ntail\n"
