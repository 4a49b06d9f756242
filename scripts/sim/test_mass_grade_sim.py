"""The simulator's driving resistances and the mass and grade logs (mass_grade_scenarios.py)."""

import os
from math import radians, sin

import numpy as np

from .mass_grade_scenarios import (COLUMNS, MASS_GRADE_SCENARIOS, Resistance, m_rot)
from .observer_scenarios import Road
from .scenarios import ZERO4, const, uniform_mu
from .vehicle import Params, simulate

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
LOGS = os.path.join(REPO, "scenarios", "mass_grade")


def test_external_force_decelerates_the_car_and_the_wheels_and_reaches_ax():
    # A constant -500 N on a 3 deg climb, no torque: the wheels' spin inertia adds
    # m_rot = 4 Iw/R^2 to the mass, so v_dot = (F - m g sin theta)/(m + m_rot) once the tyre
    # slip has settled (the slip's time constant is ~1 ms; after 0.5 s the remaining error
    # is the tiny rolling slip's drift, < 1e-4 relative).  ax is the specific force
    # v_dot + g sin theta.
    p = Params()
    th = radians(3.0)
    sim = simulate(lambda t: (0.0, ZERO4, ZERO4), uniform_mu(0.9), 20.0, 1.0, p, "dugoff",
                   0.01, 1000, Road(grade=const(th)), None, ext=lambda t, vx, theta: -500.0)
    want = (-500.0 - p.m * p.g * sin(th)) / (p.m + m_rot(p))
    k = np.searchsorted(sim["t"], 0.5)
    assert abs(sim["vx_dot"][k] - want) <= 1e-4 * abs(want)
    assert abs(sim["ax"][k] - (sim["vx_dot"][k] + p.g * sin(th))) <= 1e-9
    assert np.all(sim["fx_ext"] == -500.0)


def test_resistance_force_matches_its_formula():
    r = Resistance(0.01, 0.0002, 1.2, 0.3, 2.2, wind=const(5.0))
    p = Params()
    f = r.ext(p)(0.0, 20.0, 0.05)
    roll = p.m * p.g * (0.01 + 0.0002 * 20.0) * np.cos(0.05) * np.tanh(20.0 / 0.5)
    assert abs(f - (-roll - 0.5 * 1.2 * 0.3 * 2.2 * 25.0 ** 2)) <= 1e-9


def test_committed_logs_have_the_columns_and_stay_small():
    names = sorted(f for f in os.listdir(LOGS) if f.endswith(".csv"))
    assert names == sorted(sc.name + ".csv" for sc in MASS_GRADE_SCENARIOS)
    total = 0
    for f in names:
        path = os.path.join(LOGS, f)
        total += os.path.getsize(path)
        assert os.path.getsize(path) <= 2_000_000       # the brief's per-file budget
        with open(path, encoding="utf-8") as fh:
            header = next(line for line in fh if not line.startswith("#"))
        assert header.strip().split(",") == COLUMNS
    assert total <= 8_000_000


RES_LOGS = os.path.join(REPO, "scenarios", "observer_res")


def test_observer_res_logs_complete_small_and_regenerate():
    """scenarios/observer_res/ (make observer-res-scenarios) holds the noisy log of every
    OBS_RES_SCENARIOS scenario and truth tyre, nothing else, within the size the list states;
    the first 0.5 s of each Dugoff log regenerates bit for bit (the simulation is
    deterministic and a shorter run takes the same steps; the noise is one row-major PCG64
    block, so a prefix of rows draws the same numbers), metadata included."""
    from . import sensors
    from .mass_grade_scenarios import OBS_RES_SCENARIOS
    expect = sorted(sensors.file_name(sc.name, tyre, "default")
                    for sc in OBS_RES_SCENARIOS for tyre in sc.tyres)
    assert sorted(f for f in os.listdir(RES_LOGS) if f.endswith(".csv")) == expect
    # 3.6 MB written, the hill's 35 s 1.9 of them: a budget for the five, not a measurement
    assert sum(os.path.getsize(os.path.join(RES_LOGS, f)) for f in expect) <= 4_000_000
    for sc in OBS_RES_SCENARIOS:
        n = round(0.5 / sc.dt) + 1
        sim = sensors.run_observer(sc, duration=0.5)
        tab = sensors.observer_noise(sensors.observer_table(sim, sc), sc)
        cols = sensors.observer_columns(sc)
        with open(os.path.join(RES_LOGS, sensors.file_name(sc.name, "dugoff", "default")),
                  encoding="utf-8") as fh:
            text = fh.read()
        lines = [line for line in text.splitlines() if not line.startswith("#")]
        mine = sensors.observer_csv_text(tab, [], cols).splitlines()
        assert lines[0] == ",".join(cols) and lines[1:n + 1] == mine[1:], sc.name
        meta = dict(line[2:].split(" = ", 1) for line in text.splitlines()
                    if line.startswith("# "))
        assert meta == {k: sensors._fmt(v) for k, v in
                        sensors.observer_metadata(sc, "default", "dugoff")}
        assert meta["sim_fc"] == "0.01" and meta["sim_rho"] == "1.2"
