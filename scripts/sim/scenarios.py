"""Scenario definitions (MODEL.md section 8).

A scenario is its initial speed, duration and input functions:
    steer(t)     road-wheel angle delta [rad] (front wheels)
    pressure(t)  wheel-cylinder pressures (fl, fr, rl, rr) [MPa]
    drive(t)     drive torques (fl, fr, rl, rr) [N m]
    mu(x, left)  road friction at road position x [m] (CoG path distance at t = 0 is 0; a
                 wheel sits at s + x_i) on the left (True) / right (False) side.
    abs, yaw     optional closed-loop controllers (control.py): per-wheel ABS acting on
                 the driver's pressure, driver yaw-rate controller acting on delta.
    cruise       optional cruise control (control.SpeedConfig: a PI on the speed, its torque
                 on the front wheels) that holds the speed through a steering manoeuvre.
    truth        optional truth-tyre parameters that differ from the vehicle's parameter
                 file ((key, value) pairs over Params()): the simulator's tyre uses them,
                 while the log's metadata keeps the parameter file's values (the keys the
                 estimator reads) and lists the truth's apart as `truth_<key>` lines, which
                 the estimator ignores (sensors.metadata).  Only wrong_tyre_data sets it.
The description string records the inputs (and says when ABS / the steering controller
are active) and is written to the log metadata.
All scenarios keep vx > 4 m/s to the end (with both truth tyres) and no wheel locks or
spins up; the hard_brake scenarios use the ABS of control.py to brake at the limit.

Issue 17 ("never confidently wrong") adds scenarios the trust table did not have (indices
13-18): a double lane change and a slow ramp steer to the limit on mu 0.3 and 0.9, braking in
a turn on mu 0.3, and wrong tyre data.  wrong_tyre_data is a sine steer then ABS braking on
mu 0.85 by a car whose true tyre is not the one of its parameter file: longitudinal stiffness
+30 % (cx, Cx_n 20 -> 26), cornering stiffness -30 % (cy, Cy_n 15 -> 10.5) and shape 30 %
off: the Magic Formula truth's shape factors C (mf_Cx 1.65 -> 1.155, mf_Cy 1.3 -> 1.69; the
directions keep 1 < C < 2, so the peak force stays mu*Fz and the truth mu keeps its meaning)
and, for the Dugoff truth, which has no shape factor, its velocity-reduction factor eps
(0.015 -> 0.0195, which shapes the force past the peak).  The log's metadata gives the
parameter file's values (cx = 20, cy = 15, Cx_n = 20, Cy_n = 15, eps = 0.015, mf_* as the
other logs), the truth's values are in its `truth_*` metadata lines and in the description.
"""

from dataclasses import dataclass, replace
from math import pi, sin
from typing import Callable, Optional

from .control import AbsConfig, ClosedLoopInputs, ObserverInputs, SpeedConfig, YawConfig

__all__ = ["Scenario", "SCENARIOS", "BY_NAME", "KMH"]

KMH = 1.0 / 3.6
ZERO4 = (0.0, 0.0, 0.0, 0.0)


@dataclass(frozen=True)
class Scenario:
    name: str
    index: int               # 0-based; noise seed = index + 1
    description: str
    v0: float                # m/s
    duration: float          # s
    steer: Callable
    pressure: Callable
    drive: Callable
    mu: Callable
    abs: Optional[AbsConfig] = None   # per-wheel ABS on the driver's pressure (control.py)
    yaw: Optional[YawConfig] = None   # driver yaw-rate controller on delta (control.py)
    cruise: Optional[SpeedConfig] = None  # cruise control, front-wheel torque (control.py)
    truth: tuple = ()        # truth-tyre parameters unlike the parameter file's: (key, value)

    @property
    def seed(self):
        return self.index + 1

    @property
    def closed_loop(self):
        return self.abs is not None or self.yaw is not None or self.cruise is not None

    def truth_params(self, p):
        """The simulator's parameters: the vehicle's p with the truth-tyre overrides."""
        return replace(p, **dict(self.truth)) if self.truth else p

    def inputs(self, t):
        """Open-loop driver inputs (delta, pressures, drive torques) at time t."""
        return self.steer(t), self.pressure(t), self.drive(t)

    def make_inputs(self, p):
        """What the simulator integrates: the open-loop inputs, or a fresh closed-loop
        controller (ABS / driver steering) for vehicle parameters p."""
        if not self.closed_loop:
            return self.inputs
        if self.cruise is not None:
            return ObserverInputs(p, self.steer, self.pressure, self.drive, self.abs, self.yaw,
                                  None, self.cruise, None, "fwd")
        return ClosedLoopInputs(p, self.steer, self.pressure, self.drive, self.abs, self.yaw)


def ramp(t, t0, t_ramp, value):
    """0 before t0, linear to value over t_ramp, then value."""
    if t <= t0:
        return 0.0
    if t >= t0 + t_ramp:
        return value
    return value * (t - t0) / t_ramp


def pulse(t, t_on, t_off, t_ramp, value):
    """ramp up at t_on, ramp down (same ramp time) at t_off."""
    return ramp(t, t_on, t_ramp, value) - ramp(t, t_off, t_ramp, value)


def double_lane_change(amp, period, t1, t2):
    """Two one-period sine steering pulses (out at t1, back at t2, mirrored): the lateral
    offset of a lane change each (ISO 3888-1-like, open loop)."""
    def steer(t):
        if t1 < t <= t1 + period:
            return amp * sin(2.0 * pi * (t - t1) / period)
        if t2 < t <= t2 + period:
            return -amp * sin(2.0 * pi * (t - t2) / period)
        return 0.0
    return steer


def const(value):
    return lambda t: value


def uniform_mu(mu):
    return lambda x, left: mu


def _fmt(x):
    return f"{x:g}"


# ---- chosen inputs (see the report / README of scripts/sim) -------------------------------
P_PAPER = 0.45                    # MPa, all wheels from t = 0 (the paper)
V_PAPER = 80.0 * KMH
MU_STEP_X = 100.0                 # m
SPLIT_P, SPLIT_T0, SPLIT_TR, SPLIT_V0 = 1.3, 1.0, 0.2, 100.0 * KMH
SINE_F = 0.5                      # Hz
SINE_A_HIGH = 0.042               # rad -> peak ay ~ 5 m/s^2 on mu 0.85
SINE_A_LOW = 0.040                # rad -> peak ay ~ 2.75 m/s^2 on mu 0.4
ACC_T, ACC_T0, ACC_TR, ACC_V0 = 330.0, 0.5, 1.0, 30.0 * KMH
BIT_DELTA, BIT_STEER_TR = 0.025, 0.5
BIT_P, BIT_T_ON, BIT_T_OFF, BIT_TR = 1.6, 2.0, 6.0, 0.2
# Near-limit braking with ABS (control.py): the driver's pressure P_HARD is far above what
# any wheel can take (~1.5 MPa on mu 0.3, ~5 MPa on mu 0.85), so every wheel is ABS-controlled.
P_HARD, HARD_TR = 8.0, 0.2        # MPa, s (ramp-in and release)
HB_HIGH_V0, HB_HIGH_T = 120.0 * KMH, (1.0, 4.0)
HB_LOW_V0, HB_LOW_T = 100.0 * KMH, (1.0, 8.0)
MSB_V0, MSB_T, MSB_X, MSB_MU = 120.0 * KMH, (1.0, 7.0), 90.0, (0.8, 0.3)
SMB_V0, SMB_T, SMB_MU = 100.0 * KMH, (1.0, 5.0), (0.85, 0.3)


def _paper(name, index, mu_fn, mu_text):
    return Scenario(
        name, index,
        f"paper braking: v0 = 80 km/h, {mu_text}, p = {_fmt(P_PAPER)} MPa all wheels from "
        f"t = 0, no drive torque, delta = 0",
        V_PAPER, 10.0, const(0.0), const((P_PAPER,) * 4), const(ZERO4), mu_fn)


def _mu_step(x, left):
    return 0.85 if x < MU_STEP_X else 0.20


def _split(x, left):
    return 0.85 if left else 0.30


def _split_pressure(t):
    v = ramp(t, SPLIT_T0, SPLIT_TR, SPLIT_P)
    return (v, v, v, v)


def _sine(a):
    return lambda t: a * sin(2.0 * pi * SINE_F * t)


def _acc_drive(t):
    v = ramp(t, ACC_T0, ACC_TR, ACC_T)
    return (v, v, 0.0, 0.0)


def _bit_steer(t):
    return ramp(t, 0.0, BIT_STEER_TR, BIT_DELTA)


def _bit_pressure(t):
    v = pulse(t, BIT_T_ON, BIT_T_OFF, BIT_TR, BIT_P)
    return (v, v, v, v)


def _hard_pressure(t_on, t_off):
    def pressure(t):
        v = pulse(t, t_on, t_off, HARD_TR, P_HARD)
        return (v, v, v, v)
    return pressure


def _msb_mu(x, left):
    return MSB_MU[0] if x < MSB_X else MSB_MU[1]


def _smb_mu(x, left):
    return SMB_MU[0] if left else SMB_MU[1]


ABS = AbsConfig()
DRIVER_YAW = YawConfig()

# ---- issue 17's scenarios (indices 13-18) --------------------------------------------------
# Double lane change: two one-period sine pulses of the road-wheel angle, the second the
# mirror image of the first (ISO 3888-1-like, open loop; the observer's dlc_* use the same
# shape).  Amplitudes chosen to reach the tyres' limit without spinning the car (measured:
# make_scenarios.py prints the per-wheel utilisation).
DLC_P, DLC_T = 1.6, (1.0, 3.4)                # s: period, start of each pulse
DLC_HIGH = (80.0 * KMH, 0.9, 0.085)           # v0, mu, amplitude [rad]
DLC_LOW = (60.0 * KMH, 0.3, 0.045)
# Slow ramp steer at constant speed (cruise control on the front wheels) from 0 at RS_T0 to
# the final angle at the end of the log: the steady-state lateral acceleration of the
# (neutral-steer in the linear range) car is ~ v^2*delta/L, so the ramp passes the tyres'
# limit at about 2/3 of it and the rest of the log runs saturated.
RS_V, RS_T0 = 80.0 * KMH, 1.0
RS_END = {"high": (0.9, 0.08), "low": (0.3, 0.027)}  # mu, final delta [rad] at t = 10 s
CRUISE_RS = SpeedConfig(const(RS_V))
# Braking in a turn on mu 0.3: brake_in_turn's manoeuvre with steering and pressure scaled by
# about 0.3/0.85 (its accelerations scaled to the lower friction).
BIT_LOW_DELTA, BIT_LOW_P = 0.009, 0.56
# Wrong tyre data (module docstring): truth-tyre overrides, 30 % off the parameter file.
WRONG_TYRE = (("Cx_n", 26.0), ("cx", 26.0), ("Cy_n", 10.5), ("cy", 10.5), ("eps", 0.0195),
              ("mf_Cx", 1.155), ("mf_Cy", 1.69))
WT_V0, WT_MU, WT_A, WT_STEER_T, WT_T = 100.0 * KMH, 0.85, 0.03, (0.5, 4.5), (5.5, 8.0)


def _dlc(name, index, cfg):
    v0, mu, amp = cfg
    return Scenario(
        name, index,
        f"double lane change: v0 = {_fmt(round(v0 / KMH, 6))} km/h, mu = {_fmt(mu)}, "
        f"delta = {_fmt(amp)} rad * sin(2*pi*(t-t1)/{_fmt(DLC_P)}) over one period from "
        f"t1 = {_fmt(DLC_T[0])} s, the mirror image from t2 = {_fmt(DLC_T[1])} s "
        f"(ISO 3888-1-like, open loop), no brake, no drive torque",
        v0, 10.0, double_lane_change(amp, DLC_P, *DLC_T), const(ZERO4), const(ZERO4), uniform_mu(mu))


def _ramp_steer(name, index, key):
    mu, d_end = RS_END[key]
    return Scenario(
        name, index,
        f"slow ramp steer to the limit: {_fmt(RS_V / KMH)} km/h held by cruise control "
        f"(PI, torque on the front wheels), mu = {_fmt(mu)}, delta ramped 0 -> {_fmt(d_end)} "
        f"rad from t = {_fmt(RS_T0)} s to 10 s, no brake",
        RS_V, 10.0, lambda t: ramp(t, RS_T0, 10.0 - RS_T0, d_end), const(ZERO4),
        const(ZERO4), uniform_mu(mu), cruise=CRUISE_RS)


def _bit_low_steer(t):
    return ramp(t, 0.0, BIT_STEER_TR, BIT_LOW_DELTA)


def _bit_low_pressure(t):
    v = pulse(t, BIT_T_ON, BIT_T_OFF, BIT_TR, BIT_LOW_P)
    return (v, v, v, v)


def _wt_steer(t):
    if WT_STEER_T[0] < t <= WT_STEER_T[1]:
        return WT_A * sin(2.0 * pi * SINE_F * (t - WT_STEER_T[0]))
    return 0.0


def _wrong_tyre_text():
    return "true " + ", ".join(f"{k} = {_fmt(v)}" for k, v in WRONG_TYRE)


def _hard(name, index, v0, window, mu_fn, mu_text, yaw=None, steer_text="delta = 0"):
    return Scenario(
        name, index,
        f"hard braking with ABS: v0 = {_fmt(v0 / KMH)} km/h, {mu_text}, driver pressure "
        f"{_fmt(P_HARD)} MPa all wheels from t = {_fmt(window[0])} s to {_fmt(window[1])} s "
        f"({_fmt(HARD_TR)} s ramps), {ABS.text()}, no drive torque, {steer_text}",
        v0, 10.0, const(0.0), _hard_pressure(*window), const(ZERO4), mu_fn, ABS, yaw)


SCENARIOS = [
    _paper("paper_low_mu_brake", 0, uniform_mu(0.4), "mu = 0.4 everywhere"),
    _paper("paper_high_mu_brake", 1, uniform_mu(0.85), "mu = 0.85 everywhere"),
    _paper("paper_mu_step", 2, _mu_step,
           f"mu = 0.85 for road x < {_fmt(MU_STEP_X)} m then 0.20 (each wheel at its own x)"),
    Scenario(
        "split_mu_brake", 3,
        f"split-mu straight braking: v0 = 100 km/h, mu left 0.85 / right 0.30, "
        f"p = {_fmt(SPLIT_P)} MPa all wheels ramped in over {_fmt(SPLIT_TR)} s from "
        f"t = {_fmt(SPLIT_T0)} s, no drive torque, delta = 0 (open loop)",
        SPLIT_V0, 10.0, const(0.0), _split_pressure, const(ZERO4), _split),
    Scenario(
        "sine_steer_high_mu", 4,
        f"sine steer: v0 = 80 km/h, mu = 0.85, delta = {_fmt(SINE_A_HIGH)}*sin(2*pi*"
        f"{_fmt(SINE_F)}*t) rad, no brake, no drive torque",
        V_PAPER, 10.0, _sine(SINE_A_HIGH), const(ZERO4), const(ZERO4), uniform_mu(0.85)),
    Scenario(
        "sine_steer_low_mu", 5,
        f"sine steer: v0 = 80 km/h, mu = 0.4, delta = {_fmt(SINE_A_LOW)}*sin(2*pi*"
        f"{_fmt(SINE_F)}*t) rad, no brake, no drive torque",
        V_PAPER, 10.0, _sine(SINE_A_LOW), const(ZERO4), const(ZERO4), uniform_mu(0.4)),
    Scenario(
        "accel_low_mu", 6,
        f"front-wheel-drive acceleration: v0 = 30 km/h, mu = 0.3, drive torque "
        f"{_fmt(ACC_T)} N m on each front wheel ramped in over {_fmt(ACC_TR)} s from "
        f"t = {_fmt(ACC_T0)} s then held, no brake, delta = 0",
        ACC_V0, 10.0, const(0.0), const(ZERO4), _acc_drive, uniform_mu(0.3)),
    Scenario(
        "brake_in_turn", 7,
        f"braking in a turn: v0 = 80 km/h, mu = 0.85, delta ramped 0 -> {_fmt(BIT_DELTA)} "
        f"rad over {_fmt(BIT_STEER_TR)} s from t = 0 then held, p = {_fmt(BIT_P)} MPa all "
        f"wheels from t = {_fmt(BIT_T_ON)} s to {_fmt(BIT_T_OFF)} s ({_fmt(BIT_TR)} s "
        f"ramps), no drive torque",
        V_PAPER, 10.0, _bit_steer, _bit_pressure, const(ZERO4), uniform_mu(0.85)),
    Scenario(
        "cruise", 8,
        "cruise: v0 = 80 km/h, mu = 0.85, no inputs (delta = 0, no brake, no drive "
        "torque): tyre forces stay zero, friction not observable",
        V_PAPER, 10.0, const(0.0), const(ZERO4), const(ZERO4), uniform_mu(0.85)),
    _hard("hard_brake_high_mu", 9, HB_HIGH_V0, HB_HIGH_T, uniform_mu(0.85),
          "mu = 0.85 everywhere"),
    _hard("hard_brake_low_mu", 10, HB_LOW_V0, HB_LOW_T, uniform_mu(0.3),
          "mu = 0.3 everywhere"),
    _hard("mu_step_hard_brake", 11, MSB_V0, MSB_T, _msb_mu,
          f"mu = {_fmt(MSB_MU[0])} for road x < {_fmt(MSB_X)} m then {_fmt(MSB_MU[1])} "
          f"(each wheel at its own x; front wheels cross at t ~ 3.1 s)"),
    _hard("split_mu_hard_brake", 12, SMB_V0, SMB_T, _smb_mu,
          f"split mu: left {_fmt(SMB_MU[0])} / right {_fmt(SMB_MU[1])}", DRIVER_YAW,
          DRIVER_YAW.text()),
    _dlc("double_lane_change_high_mu", 13, DLC_HIGH),
    _dlc("double_lane_change_low_mu", 14, DLC_LOW),
    _ramp_steer("ramp_steer_high_mu", 15, "high"),
    _ramp_steer("ramp_steer_low_mu", 16, "low"),
    Scenario(
        "brake_in_turn_low_mu", 17,
        f"braking in a turn: v0 = 80 km/h, mu = 0.3, delta ramped 0 -> {_fmt(BIT_LOW_DELTA)} "
        f"rad over {_fmt(BIT_STEER_TR)} s from t = 0 then held, p = {_fmt(BIT_LOW_P)} MPa all "
        f"wheels from t = {_fmt(BIT_T_ON)} s to {_fmt(BIT_T_OFF)} s ({_fmt(BIT_TR)} s "
        f"ramps), no drive torque (brake_in_turn scaled to mu 0.3)",
        V_PAPER, 10.0, _bit_low_steer, _bit_low_pressure, const(ZERO4), uniform_mu(0.3)),
    Scenario(
        "wrong_tyre_data", 18,
        f"wrong tyre data: the truth tyre is not the parameter file's (metadata): "
        f"{_wrong_tyre_text()} (stiffness and shape 30 % off; truth_* lines); "
        f"v0 = {_fmt(WT_V0 / KMH)} km/h, mu = {_fmt(WT_MU)}, delta = {_fmt(WT_A)}*sin(2*pi*"
        f"{_fmt(SINE_F)}*(t-{_fmt(WT_STEER_T[0])})) rad from t = {_fmt(WT_STEER_T[0])} s to "
        f"{_fmt(WT_STEER_T[1])} s, then hard braking with ABS: driver pressure "
        f"{_fmt(P_HARD)} MPa all wheels from t = {_fmt(WT_T[0])} s to {_fmt(WT_T[1])} s "
        f"({_fmt(HARD_TR)} s ramps), {ABS.text()}, no drive torque",
        WT_V0, 10.0, _wt_steer, _hard_pressure(*WT_T), const(ZERO4), uniform_mu(WT_MU), ABS,
        truth=WRONG_TYRE),
]

BY_NAME = {s.name: s for s in SCENARIOS}
