#!/usr/bin/env python3
"""Simulated mixed driving for the soak run: SECONDS of trips, seeded, as one sensor log.

    .venv/bin/python scripts/data/soak_drive.py --seconds 3600 [--seed 1] [--jobs N]
                                           [--rate 2000] --out build/soak/drive_3600s.csv

A trip starts and ends parked (the steering wheel turned at rest), sometimes with a
reversing manoeuvre, and is a series of stop-and-go cycles of 30-150 s: creeping away, an
acceleration, driving segments drawn at random and simulated with the reference simulator
(scripts/sim, 7 DOF, RK4), each starting at the speed the previous one ended with
(straight, free-rolling: each segment ends with 1 s of released controls so the seams are
small), braking to a stop, waiting 1-10 s.  Driving segments: cruise, accelerate
(front-wheel drive, 30-75 % of the torque the road takes at rest), mild braking, ABS
braking at the limit, sine steer, a lane change, braking in a turn; the road of each
segment is uniform mu 0.2 .. 0.85, split mu or a mu step; the truth tyre of a trip is the
Magic Formula (70 %) or the Dugoff.
Below 5 m/s the simulator is too stiff to integrate (the wheel-spin mode, vehicle.py), so
standstill, creeping, reversing and the last metres of a stop are kinematic: consistent
speeds, accelerations and rolling wheels, tyre forces implied (there the estimator only
runs its time update anyway, v_est_min = 3 m/s).  Default sensor noise on every row (its
own seed per segment).  The integration rate defaults to 2 kHz (RK4 stays stable down to
~2 m/s on mu 0.85; the bundled scenarios use 4 kHz): the soak needs plausible driving, not
golden accuracy: an hour simulates in ~13 CPU-minutes.  Trips are independent
and simulated in --jobs worker processes; the log is the same for any --jobs.
Extra column `phase` (ignored by DATA.md readers): 0 parked, 1 kinematic low speed,
2 cruise, 3 accelerate, 4 brake, 5 ABS brake, 6 sine steer, 7 lane change, 8 brake in turn.
"""

import argparse
import math
import multiprocessing
import os
import sys
import time

import numpy as np

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)

from sim import sensors  # noqa: E402
from sim.control import AbsConfig  # noqa: E402
from sim.scenarios import Scenario, pulse, ramp  # noqa: E402
from sim.vehicle import ESTIMATOR_KEYS, Params  # noqa: E402

DT = sensors.DT
P = Params()
R = P.R
L = P.Lf + P.Lr
V_SIM_MIN = 5.0      # m/s: below this, kinematic phases
V_MAX = 38.0         # m/s
SETTLE = 1.0         # s of released controls at the end of each simulated segment
PHASE = dict(parked=0, kinematic=1, cruise=2, accelerate=3, brake=4, abs_brake=5,
             sine=6, lane_change=7, brake_turn=8)
COLUMNS = list(sensors.COLUMNS) + ["phase"]


def road(rng):
    """(mu(x, left) function, typical mu, text) of a segment's road."""
    u = rng.random()
    if u < 0.80:
        mu = float(rng.choice([0.85, 0.85, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2]))
        return (lambda x, left: mu), mu, f"mu {mu:g}"
    if u < 0.90:
        return (lambda x, left: 0.85 if left else 0.3), 0.3, "split mu 0.85/0.3"
    a, b = (0.85, 0.3) if rng.random() < 0.5 else (0.3, 0.85)
    x0 = float(rng.uniform(20.0, 120.0))
    return (lambda x, left: a if x < x0 else b), min(a, b), f"mu {a:g} -> {b:g} at {x0:.0f} m"


def zero4(t):
    return (0.0, 0.0, 0.0, 0.0)


def segment(rng, v, first=False):
    """Draw one driving segment at speed v (the first of a cycle accelerates):
    (kind, duration, steer, pressure, drive, abs, road, text)."""
    mu_fn, mu, text = road(rng)
    g = P.g
    kinds = ["cruise", "accelerate", "brake", "abs_brake", "sine", "lane_change", "brake_turn"]
    weights = np.array([2, 2.5, 1.5, 1, 1.5, 1, 1])
    if v > V_MAX - 4.0:
        weights[1] = 0.0
    if v < 9.0:
        weights[[2, 3, 6]] = 0.0
    if v < 15.0:
        weights[1] *= 3.0
    kind = kinds[int(rng.choice(len(kinds), p=weights / weights.sum()))]
    if first:
        kind = "accelerate"
    steer, pres, drive, abs_cfg = (lambda t: 0.0), zero4, zero4, None
    if kind == "cruise":
        dur = float(rng.uniform(4.0, 15.0))
    elif kind == "accelerate":
        # below the road's limit (no traction control in the simulator: a torque above
        # mu Fz R spins the driven wheels up without bound, and accelerating unloads the
        # front axle by ~10 %); near the limit the wheels slip
        fz_front = P.m * P.g * P.Lr / (2.0 * L)
        torque = float(rng.uniform(0.3, 0.75)) * mu * fz_front * R
        a_est = 2.0 * torque / R / P.m
        dur = float(min(rng.uniform(3.0, 10.0), max(1.0, (V_MAX - v) / a_est))) + SETTLE
        drive = lambda t, T=torque, d=dur - SETTLE: (pulse(t, 0.2, d, 0.3, T),) * 2 + (0.0, 0.0)  # noqa: E731
    elif kind in ("brake", "brake_turn"):
        p = float(rng.uniform(0.3, 1.5))
        a_est = min(1.6 * p, 0.8 * mu * g)
        dur = float(min(rng.uniform(2.0, 6.0), max(0.5, (v - 7.0) / a_est))) + SETTLE
        pres = lambda t, pp=p, d=dur - SETTLE: (pulse(t, 0.2, d, 0.2, pp),) * 4  # noqa: E731
        if kind == "brake_turn":
            ay = float(rng.uniform(0.2, 0.5)) * mu * g
            delta = min(0.08, ay * L / (v * v) * (1.0 + v * v / 400.0))
            steer = lambda t, dl=delta, d=dur - SETTLE: pulse(t, 0.0, d, 0.5, dl)  # noqa: E731
    elif kind == "abs_brake":
        a_est = 0.9 * mu * g
        dur = float(min(rng.uniform(1.0, 4.0), max(0.3, (v - 8.0) / a_est))) + SETTLE
        pres = lambda t, d=dur - SETTLE: (pulse(t, 0.2, d, 0.2, 8.0),) * 4  # noqa: E731
        abs_cfg = AbsConfig()
    else:  # sine, lane_change
        ay = float(rng.uniform(0.2, 0.6)) * mu * g
        delta = min(0.1, ay * L / (v * v) * (1.0 + v * v / 400.0))
        f = float(rng.uniform(0.2, 0.8))
        periods = 1 if kind == "lane_change" else int(rng.integers(2, 6))
        dur = periods / f + SETTLE
        steer = lambda t, a=delta, ff=f, n=periods: (  # noqa: E731
            a * math.sin(2 * math.pi * ff * t) if t < n / ff else 0.0)
    dur = round(dur / DT) * DT
    return kind, dur, steer, pres, drive, abs_cfg, mu_fn, text


def kinematic(v_from, v_to, dur, delta_fn, mu, phase):
    """Rows of a kinematic phase: vx linear from v_from to v_to over dur (rows at
    t = 0, dt, ..., dur - dt), consistent accelerations, wheels rolling at vx/R."""
    n = int(round(dur / DT))
    t = np.arange(n) * DT
    vx = v_from + (v_to - v_from) * t / dur if dur > 0 else np.full(n, v_from)
    ax = np.full(n, (v_to - v_from) / dur if dur > 0 else 0.0)
    delta = np.array([delta_fn(x) for x in t])
    r = vx * np.tan(delta) / L
    tab = {"t": t, "delta": delta, "vx": vx, "vy": np.zeros(n), "yaw_rate": r,
           "yaw_acc": np.gradient(r, DT) if n > 1 else np.zeros(n), "ax": ax, "ay": r * vx}
    for w in sensors.WHEELS:
        tab[f"omega_{w}"] = vx / R
        tab[f"mu_{w}"] = np.full(n, mu)
        tab[f"util_{w}"] = np.minimum(np.hypot(ax, r * vx) / (mu * P.g), 1.0)
    tab["phase"] = np.full(n, PHASE[phase], dtype=float)
    return tab


def simulate(kind, v0, dur, steer, pres, drive, abs_cfg, mu_fn, text, tyre, rate):
    sc = Scenario("soak_" + kind, 0, text, v0, dur, steer, pres, drive, mu_fn, abs_cfg, None)
    sim = sensors.run(sc, tyre=tyre, rate=rate)
    tab = sensors.sensor_table(sim)
    n = len(tab["t"]) - 1  # the last row is the next segment's first
    below = np.flatnonzero(tab["vx"][:n] < V_SIM_MIN - 1.0)
    if below.size:
        n = int(below[0])
    tab = {k: v[:n] for k, v in tab.items()}
    tab["phase"] = np.full(n, PHASE[kind], dtype=float)
    return tab, float(sim["vx"][n])


def trip(job):
    """One trip of `length` seconds: stop-and-go cycles (launch, driving segments, stop,
    wait) between parking at the start and at the end; returns (rows, truth tyre)."""
    seed, index, length, rate = job
    rng = np.random.Generator(np.random.PCG64([seed, index]))
    tyre = "mf" if rng.random() < 0.7 else "dugoff"
    parts, t_used = [], 0.0
    mu_park = float(rng.choice([0.85, 0.6, 0.3]))
    k = 0

    def add(tab):
        nonlocal t_used
        tab = dict(tab)
        tab["t"] = tab["t"] + t_used
        parts.append(tab)
        t_used += len(tab["vx"]) * DT

    def noise_seed():
        nonlocal k
        k += 1
        return seed * 100003 + index * 1009 + k

    park = round(float(rng.uniform(2.0, 8.0)), 2)
    turn = float(rng.uniform(-0.5, 0.5))
    add(kinematic(0.0, 0.0, park, lambda t: turn * min(1.0, t / 3.0), mu_park, "parked"))
    if rng.random() < 0.3:  # reversing out of a parking space
        add(kinematic(0.0, -2.0, 2.0, lambda t: -0.4, mu_park, "kinematic"))
        add(kinematic(-2.0, 0.0, 2.0, lambda t: -0.4, mu_park, "kinematic"))
    stop_need = lambda vv: max(vv - V_SIM_MIN, 0.0) / 2.0 + SETTLE + 2.5 + 2.0  # noqa: E731
    while length - t_used > 20.0:
        # one stop-and-go cycle: creep away, drive, stop, wait
        cycle_end = t_used + float(rng.uniform(30.0, 150.0))
        add(kinematic(0.0, V_SIM_MIN, 3.0, lambda t: 0.0, mu_park, "kinematic"))
        v, first = V_SIM_MIN, True
        while v >= V_SIM_MIN:
            remaining = min(length, cycle_end) - t_used
            if remaining < stop_need(v) + 4.0:
                break
            kind, dur, steer, pres, drive, abs_cfg, mu_fn, text = segment(rng, v, first)
            first = False
            if dur > remaining - stop_need(v) - 2.0:
                kind, dur, steer, pres, drive, abs_cfg = ("cruise", round(max(1.0, remaining - stop_need(v) - 2.0), 2),
                                                          (lambda t: 0.0), zero4, zero4, None)
            tab, v = simulate(kind, v, dur, steer, pres, drive, abs_cfg, mu_fn, text, tyre, rate)
            add(sensors.add_noise(tab, noise_seed()))
        if v > V_SIM_MIN + 0.5:  # brake to V_SIM_MIN at ~2 m/s^2
            p = 2.0 / 1.6
            dur = round((v - V_SIM_MIN) / 2.0 + SETTLE, 2)
            tab, v = simulate("brake", v, dur, lambda t: 0.0,
                              lambda t, pp=p, d=dur - SETTLE: (pulse(t, 0.1, d, 0.2, pp),) * 4,
                              zero4, None, lambda x, left: 0.85, "mu 0.85", tyre, rate)
            add(sensors.add_noise(tab, noise_seed()))
        add(kinematic(v, 0.0, 2.5, lambda t: 0.0, mu_park, "kinematic"))
        wait = round(min(float(rng.uniform(1.0, 10.0)), max(length - t_used, 0.0)), 2)
        if wait >= DT:
            add(kinematic(0.0, 0.0, wait, lambda t: 0.0, mu_park, "parked"))
    rest = round(length - t_used, 2)
    if rest >= DT:
        add(kinematic(0.0, 0.0, rest, lambda t: 0.0, mu_park, "parked"))
    out = {c: np.concatenate([p[c] for p in parts]) for c in COLUMNS}
    # sensor noise on the kinematic rows too (the simulated ones already have it)
    kin = out["phase"] <= PHASE["kinematic"]
    noisy = sensors.add_noise({c: out[c][kin] for c in COLUMNS}, seed * 7919 + index)
    for c in sensors.NOISY_COLUMNS:
        out[c][kin] = noisy[c]
    return out, tyre


def plan(seconds, seed):
    """Trip lengths (60 .. 300 s) summing to seconds, from the seed."""
    rng = np.random.Generator(np.random.PCG64([seed, 999]))
    lengths = []
    while sum(lengths) < seconds:
        lengths.append(float(rng.uniform(60.0, 300.0)))
    scale = seconds / sum(lengths)
    lengths = [round(x * scale, 2) for x in lengths]
    lengths[-1] = round(seconds - sum(lengths[:-1]), 2)
    return lengths


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seconds", type=float, required=True)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--rate", type=int, default=2000, help="RK4 rate, Hz (default 2000)")
    ap.add_argument("--out", required=True)
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    lengths = plan(a.seconds, a.seed)
    jobs = [(a.seed, i, x, a.rate) for i, x in enumerate(lengths)]
    if a.jobs > 1 and len(jobs) > 1:
        with multiprocessing.Pool(min(a.jobs, len(jobs))) as pool:
            trips = pool.map(trip, jobs, chunksize=1)
    else:
        trips = [trip(j) for j in jobs]
    t_off, parts = 0.0, []
    for tab, _ in trips:
        tab = dict(tab)
        tab["t"] = np.round(tab["t"] + t_off, 2)
        parts.append(tab)
        t_off += len(tab["t"]) * DT
    out = {c: np.concatenate([p[c] for p in parts]) for c in COLUMNS}
    n = len(out["t"])
    meta = [("scenario", "soak"), ("description",
            f"{len(lengths)} trips of simulated mixed driving, {a.seconds:g} s, seed {a.seed} "
            f"(scripts/data/soak_drive.py)"), ("dt", DT), ("seed", a.seed), ("noise", "default"),
            ("truth_tyre", "/".join(t for _, t in trips)), ("sim_rate", a.rate)]
    meta += P.items(ESTIMATOR_KEYS)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    tmp = a.out + ".tmp"
    with open(tmp, "w", encoding="utf-8", newline="\n") as fh:
        for k, v in meta:
            fh.write(f"# {k} = {v}\n")
        fh.write(",".join(COLUMNS) + "\n")
        cols = [out[c] for c in COLUMNS]
        fmt = ["%.2f"] + ["%.10g"] * (len(COLUMNS) - 2) + ["%d"]
        block = np.column_stack(cols)
        np.savetxt(fh, block, fmt=fmt, delimiter=",")
    os.replace(tmp, a.out)
    phases = {k: int((out["phase"] == v).sum()) for k, v in PHASE.items()}
    print(f"soak drive: {len(lengths)} trips, {n} rows ({n * DT:.0f} s), min vx "
          f"{out['vx'].min():.2f} m/s, max vx {out['vx'].max():.1f} m/s, rows per phase {phases}, "
          f"{time.perf_counter() - t0:.0f} s -> {a.out}")


if __name__ == "__main__":
    main()
