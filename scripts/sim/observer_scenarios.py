"""Scenarios that break velocity and sideslip observers (issue 16), with truth columns.

The friction scenarios of scenarios.py keep vx > 4 m/s, a flat road and at least one wheel
rolling freely.  A vx / vy / beta observer on production sensors (steer, r, ax, ay, four
wheel speeds, optionally brake pressures, drive torques and a known grade) fails where those
assumptions fail; each scenario below targets one such failure.  Written by
scripts/data/make_observer_scenarios.py to scenarios/observer/ (sensor-log format and the
extra columns: docs/spec/DATA.md; the physics options: vehicle.py, control.py).

| name | purpose (what it breaks) |
|---|---|
| abs_brake_mu02 | ABS braking from 100 km/h on mu 0.2: every wheel slips ~10 %, no wheel gives vx |
| abs_brake_mu09 | ABS braking from 100 km/h on mu 0.9: -8 m/s^2, all four wheels slip |
| abs_brake_split_mu | ABS braking from 100 km/h on split mu 0.9 / 0.2 with counter-steering |
| traction_rwd_mu03 | full throttle, rear drive, mu 0.3: driven wheels spin (TCS holds ~15 %) |
| traction_awd_mu03 | full throttle, all-wheel drive, mu 0.3: all four wheels spin (TCS) |
| sine_dwell_mu09 | NHTSA-style sine with dwell (0.7 Hz, 500 ms dwell) at 80 km/h, mu 0.9 |
| sine_dwell_mu035 | the same on mu 0.35 (smaller amplitude) |
| dlc_mu09 | ISO 3888-like double lane change (steering profile) at 80 km/h, mu 0.9 |
| dlc_mu035 | the same on mu 0.35 at 60 km/h |
| circle_r60 | steady-state circle, radius 60 m at 15.5 m/s (ay ~ 4 m/s^2), mu 0.9 |
| bank_curve_pos5 | left-hand curve (radius 100 m, 20 m/s) on a +5 deg bank (adverse: rises left) |
| bank_curve_neg5 | the same curve on a -5 deg bank (rises right: the outside, a banked curve) |
| ay_bias_straight | straight, mild sine steering, 25 m/s, ay bias 0.1 m/s^2 |
| ay_bias_curve | gentle curve (radius 400 m, 25 m/s), ay bias 0.1 m/s^2 |
| long_straight_bias | 600 s straight at 25 m/s, ay bias 0.1, small driver corrections (drift) |
| creep_stop | creeping at 1-1.5 m/s with steering, then braking to a standstill, held 5 s |
| hill_known_grade | cruise at 60 km/h over a +-6 % hill, the grade known (logged `grade` column) |

Every scenario's noise seed is 201 + its index (the friction scenarios use 1-13, the fault
logs 101-115).  The long straight logs every 0.02 s (at 0.01 s it would be ~35 MB per
variant; at 0.02 s it is 17 MB noisy, 15 MB noise-free) and is written with the Dugoff truth only (on a straight at constant speed
the tyre forces are tiny, where both truth tyres are the same linear tyre); the rest are
written like the friction scenarios: Dugoff noisy + noise-free, Magic Formula noisy.

No scenario here has rolling resistance or drag (as the paper; ObserverScenario.res None).
mass_grade_scenarios.OBS_RES_SCENARIOS are twins of three of them with the car's resistances
for the mass and grade studies (<name>_res, scenarios/observer_res/, make
observer-res-scenarios).

On low mu the Magic-Formula car is less forgiving than the Dugoff one (its force falls past
the peak): with the same steering, sine_dwell_mu035 and dlc_mu035 reach |beta| ~ 3.8-3.9 deg
with Dugoff but 12-17 deg with mf, where the car is still sliding at the end of the log.
"""

from dataclasses import dataclass
from math import pi, radians, sin
from typing import Callable, Optional

from .control import (DRIVE_SPLIT, AbsConfig, ObserverInputs, PathConfig, SpeedConfig,
                      TcsConfig, YawConfig)
from .scenarios import (DLC_P, DLC_T, KMH, ZERO4, Scenario, const, double_lane_change, pulse,
                        ramp, uniform_mu)

__all__ = ["Road", "ObserverScenario", "OBSERVER_SCENARIOS", "OBS_BY_NAME", "SEED_BASE",
           "OBS_LOOP_SCENARIOS", "OBS_LOOP_BY_NAME"]

SEED_BASE = 201


class Road:
    """Road grade theta(s) and bank phi(s) [rad] of the CoG path distance s [m]; signs as
    vehicle.py (theta > 0 uphill, phi > 0 the road rises to the left)."""

    def __init__(self, grade=None, bank=None, text="flat"):
        self._grade = grade
        self._bank = bank
        self.text = text

    def grade(self, s):
        return 0.0 if self._grade is None else self._grade(s)

    def bank(self, s):
        return 0.0 if self._bank is None else self._bank(s)


@dataclass(frozen=True)
class ObserverScenario(Scenario):
    """A Scenario plus the observer options (all off by default):
    layout     drive layout of drive(t)'s request and the cruise torque ("fwd", "rwd",
               "awd", "none"; DRIVE_SPLIT); drive(t) is the driver's per-wheel request
    tcs        traction control; speed: cruise control; path: path-curvature follower
    road       Road (grade, bank) or None (flat); grade_known: log the `grade` column
    ay_bias    constant ay sensor bias [m/s^2], added before the noise (both variants)
    v_low      low-speed slip floor [m/s] (vehicle.py) or None
    dt, rate   log period [s] and RK4 rate [Hz]
    tyres      truth tyres to write
    res        driving resistances (mass_grade_scenarios.Resistance: rolling resistance
               m g (fc + fr v) cos(theta) and drag 0.5 rho cd area v^2, vehicle.py ``ext``)
               or None: none, as the paper (every log of OBSERVER_SCENARIOS)"""
    layout: str = "fwd"
    tcs: Optional[TcsConfig] = None
    speed: Optional[SpeedConfig] = None
    path: Optional[PathConfig] = None
    road: Optional[Road] = None
    grade_known: bool = False
    ay_bias: float = 0.0
    v_low: Optional[float] = None
    dt: float = 0.01
    rate: int = 4000
    tyres: tuple = ("dugoff", "mf")
    res: Optional[object] = None

    @property
    def seed(self):
        return SEED_BASE + self.index

    @property
    def closed_loop(self):
        return True

    def make_inputs(self, p):
        return ObserverInputs(p, self.steer, self.pressure, self.drive, self.abs, self.yaw,
                              self.tcs, self.speed, self.path, self.layout, self.v_low)


def _fmt(x):
    return f"{x:g}"


def _split_request(total, layout, t_on, t_ramp):
    """Driver torque request: `total` N m ramped in at t_on, split by the layout."""
    shares = DRIVE_SPLIT[layout]

    def drive(t):
        v = ramp(t, t_on, t_ramp, total)
        return tuple(v * f for f in shares)
    return drive


def _pressure_pulse(value, t_on, t_off, t_ramp):
    def pressure(t):
        v = pulse(t, t_on, t_off, t_ramp, value)
        return (v, v, v, v)
    return pressure


def _ramp_s(s0, length, value):
    """Profile of the path distance: 0 before s0, linear to value over length, then value."""
    return lambda s: ramp(s, s0, length, value)


# ---- ABS braking ------------------------------------------------------------------------
ABS = AbsConfig()
# Split mu 0.9 / 0.2 gives twice the yaw moment of scenarios.py's 0.85 / 0.3: with the
# default driver (YawConfig()) the Magic-Formula car spins (vx < 0).  An alert driver: twice
# the gains, twice the steering rate, up to 0.3 rad (|beta| stays ~5 deg).
SPLIT_DRIVER = YawConfig(k_r=1.0, k_psi=2.0, rate_max=1.0, delta_max=0.3)
P_HARD, HARD_TR = 8.0, 0.2          # MPa, s: far above what any wheel takes (as scenarios.py)
V_ABS = 100.0 * KMH
SPLIT_MU = (0.9, 0.2)


def _split_mu(x, left):
    return SPLIT_MU[0] if left else SPLIT_MU[1]


def _abs(name, index, mu_fn, mu_text, window, duration, yaw=None, steer_text="delta = 0"):
    return ObserverScenario(
        name, index,
        f"ABS braking: v0 = 100 km/h, {mu_text}, driver pressure {_fmt(P_HARD)} MPa all "
        f"wheels from t = {_fmt(window[0])} s to {_fmt(window[1])} s ({_fmt(HARD_TR)} s "
        f"ramps), {ABS.text()}, no drive torque, {steer_text}",
        V_ABS, duration, const(0.0), _pressure_pulse(P_HARD, window[0], window[1], HARD_TR),
        const(ZERO4), mu_fn, ABS, yaw, layout="none")


# ---- traction-limited acceleration --------------------------------------------------------
TCS = TcsConfig()
TRACTION_V0, TRACTION_T, TRACTION_T0, TRACTION_TR = 20.0 * KMH, 2400.0, 0.5, 0.3


def _traction(name, index, layout, text):
    return ObserverScenario(
        name, index,
        f"traction-limited acceleration, {text}: v0 = 20 km/h, mu = 0.3, driver torque "
        f"request {_fmt(TRACTION_T)} N m in total ramped in over {_fmt(TRACTION_TR)} s from "
        f"t = {_fmt(TRACTION_T0)} s then held, split {layout}, {TCS.text()}, no brake, "
        f"delta = 0",
        TRACTION_V0, 8.0, const(0.0), const(ZERO4),
        _split_request(TRACTION_T, layout, TRACTION_T0, TRACTION_TR), uniform_mu(0.3),
        layout=layout, tcs=TCS)


# ---- sine with dwell, double lane change --------------------------------------------------
SWD_F, SWD_DWELL, SWD_T0 = 0.7, 0.5, 1.0    # Hz, s, s
V_SWD = 80.0 * KMH


def sine_with_dwell(amp, f=SWD_F, dwell=SWD_DWELL, t0=SWD_T0):
    """NHTSA FMVSS 126 shape: amp*sin(2 pi f (t-t0)) up to its second peak (3/4 period),
    held at -amp for `dwell` s, then the last quarter period back to 0."""
    t_peak = t0 + 0.75 / f

    def steer(t):
        if t <= t0:
            return 0.0
        if t <= t_peak:
            return amp * sin(2.0 * pi * f * (t - t0))
        if t <= t_peak + dwell:
            return -amp
        if t <= t_peak + dwell + 0.25 / f:
            return amp * sin(2.0 * pi * f * (t - t0 - dwell))
        return 0.0
    return steer


SWD_A_HIGH, SWD_A_LOW = 0.07, 0.03          # rad road-wheel angle (tuned: |beta| > 3 deg)
DLC_A_HIGH, DLC_A_LOW = 0.08, 0.08            # rad (the period and pulse times: DLC_P, DLC_T)
V_DLC_LOW = 60.0 * KMH


def _swd(name, index, mu, amp):
    return ObserverScenario(
        name, index,
        f"sine with dwell: v0 = 80 km/h, mu = {_fmt(mu)}, delta = {_fmt(amp)} rad * "
        f"sin(2*pi*{_fmt(SWD_F)}*(t-{_fmt(SWD_T0)})) to its second peak, held "
        f"{_fmt(SWD_DWELL)} s, then back to 0 (NHTSA FMVSS 126 shape, open loop), no brake, "
        f"no drive torque",
        V_SWD, 7.0, sine_with_dwell(amp), const(ZERO4), const(ZERO4), uniform_mu(mu),
        layout="none")


def _dlc(name, index, mu, amp, v0):
    return ObserverScenario(
        name, index,
        f"double lane change: v0 = {_fmt(round(v0 / KMH, 6))} km/h, mu = {_fmt(mu)}, "
        f"delta = {_fmt(amp)} rad * sin(2*pi*(t-t1)/{_fmt(DLC_P)}) over one period from "
        f"t1 = {_fmt(DLC_T[0])} s, the mirror image from t2 = {_fmt(DLC_T[1])} s "
        f"(ISO 3888-1-like, open loop), no brake, no drive torque",
        v0, 8.0, double_lane_change(amp, DLC_P, *DLC_T), const(ZERO4), const(ZERO4),
        uniform_mu(mu), layout="none")


# ---- steady circle, banked curve, ay bias, long straight -----------------------------------
def _curve(radius, t0, t_ramp):
    return lambda t: ramp(t, t0, t_ramp, 1.0 / radius)


CIRCLE_R, CIRCLE_V = 60.0, 15.5           # m, m/s: ay = V^2/R = 4.0 m/s^2
BANK_R, BANK_V, BANK_DEG, BANK_S0, BANK_LEN = 100.0, 20.0, 5.0, 40.0, 40.0
BIAS = 0.1                                # m/s^2
BIAS_V, BIAS_R = 25.0, 400.0
LONG_T, LONG_V, LONG_DT = 600.0, 25.0, 0.02


def _cruise(v):
    return SpeedConfig(const(v))


def _bank_curve(name, index, deg):
    road = Road(bank=_ramp_s(BANK_S0, BANK_LEN, radians(deg)),
                text=f"bank 0 -> {_fmt(deg)} deg over s = {_fmt(BANK_S0)}..."
                     f"{_fmt(BANK_S0 + BANK_LEN)} m then held (positive: rises to the left)")
    path = PathConfig(lambda t: ramp(t * BANK_V, BANK_S0, BANK_LEN, 1.0 / BANK_R))
    return ObserverScenario(
        name, index,
        f"banked left-hand curve: v = {_fmt(BANK_V)} m/s held by cruise control (fwd), "
        f"mu = 0.9, path curvature 0 -> 1/{_fmt(BANK_R)} 1/m over the same {_fmt(BANK_LEN)} m "
        f"as the {road.text}; {path.text()}",
        BANK_V, 15.0, const(0.0), const(ZERO4), const(ZERO4), uniform_mu(0.9),
        layout="fwd", speed=_cruise(BANK_V), path=path, road=road)


def _bias_steer(t):
    return 0.01 * sin(2.0 * pi * 0.2 * t)


def _long_corrections(t):
    """Small driver corrections: three incommensurate sines, ~2 mrad road-wheel angle."""
    return (0.0012 * sin(2.0 * pi * 0.071 * t) + 0.0008 * sin(2.0 * pi * 0.23 * t + 1.0)
            + 0.0005 * sin(2.0 * pi * 0.61 * t + 2.0))


# ---- creep and stop, hill ---------------------------------------------------------------
CREEP_V0, CREEP_V, CREEP_V_LOW = 3.0, 1.2, 2.0
CREEP_STOP_T, CREEP_P, CREEP_T = 12.0, 2.0, 20.0


def _creep_speed(t):
    if t >= CREEP_STOP_T:
        return None
    return CREEP_V0 + (CREEP_V - CREEP_V0) * min(t / 3.0, 1.0)


def _creep_steer(t):
    return pulse(t, 4.0, 8.0, 1.0, 0.15)


def _creep_pressure(t):
    v = ramp(t, CREEP_STOP_T, 0.5, CREEP_P)
    return (v, v, v, v)


HILL_V, HILL_G = 60.0 * KMH, 0.06         # m/s, rad


def _hill_grade(s):
    # 0 until 50 m, up to +HILL_G over 50 m, held 100 m, down to -HILL_G over 100 m,
    # held 100 m, back to 0 over 50 m
    return (ramp(s, 50.0, 50.0, HILL_G) - ramp(s, 200.0, 100.0, 2.0 * HILL_G)
            + ramp(s, 400.0, 50.0, HILL_G))


OBSERVER_SCENARIOS = [
    _abs("abs_brake_mu02", 0, uniform_mu(0.2), "mu = 0.2 everywhere", (1.0, 8.0), 10.0),
    _abs("abs_brake_mu09", 1, uniform_mu(0.9), "mu = 0.9 everywhere", (1.0, 3.5), 6.0),
    _abs("abs_brake_split_mu", 2, _split_mu,
         f"split mu: left {_fmt(SPLIT_MU[0])} / right {_fmt(SPLIT_MU[1])}", (1.0, 5.0), 8.0,
         SPLIT_DRIVER, SPLIT_DRIVER.text()),
    _traction("traction_rwd_mu03", 3, "rwd", "rear-wheel drive"),
    _traction("traction_awd_mu03", 4, "awd", "all-wheel drive"),
    _swd("sine_dwell_mu09", 5, 0.9, SWD_A_HIGH),
    _swd("sine_dwell_mu035", 6, 0.35, SWD_A_LOW),
    _dlc("dlc_mu09", 7, 0.9, DLC_A_HIGH, V_SWD),
    _dlc("dlc_mu035", 8, 0.35, DLC_A_LOW, V_DLC_LOW),
    ObserverScenario(
        "circle_r60", 9,
        f"steady-state circle: radius {_fmt(CIRCLE_R)} m at {_fmt(CIRCLE_V)} m/s held by "
        f"cruise control (fwd), ay ~ {_fmt(round(CIRCLE_V ** 2 / CIRCLE_R, 3))} m/s^2, "
        f"mu = 0.9, path curvature ramped 0 -> 1/{_fmt(CIRCLE_R)} 1/m over 2 s from t = 1 s; "
        f"{PathConfig(None).text()}",
        CIRCLE_V, 20.0, const(0.0), const(ZERO4), const(ZERO4), uniform_mu(0.9),
        layout="fwd", speed=_cruise(CIRCLE_V), path=PathConfig(_curve(CIRCLE_R, 1.0, 2.0))),
    _bank_curve("bank_curve_pos5", 10, BANK_DEG),
    _bank_curve("bank_curve_neg5", 11, -BANK_DEG),
    ObserverScenario(
        "ay_bias_straight", 12,
        f"straight with mild steering and an ay sensor bias of {_fmt(BIAS)} m/s^2: "
        f"v = {_fmt(BIAS_V)} m/s held by cruise control (fwd), mu = 0.9, delta = 0.01 rad * "
        f"sin(2*pi*0.2*t)",
        BIAS_V, 20.0, _bias_steer, const(ZERO4), const(ZERO4), uniform_mu(0.9),
        layout="fwd", speed=_cruise(BIAS_V), ay_bias=BIAS),
    ObserverScenario(
        "ay_bias_curve", 13,
        f"gentle left-hand curve with an ay sensor bias of {_fmt(BIAS)} m/s^2: v = "
        f"{_fmt(BIAS_V)} m/s held by cruise control (fwd), mu = 0.9, path curvature ramped "
        f"0 -> 1/{_fmt(BIAS_R)} 1/m over 2 s from t = 2 s; {PathConfig(None).text()}",
        BIAS_V, 20.0, const(0.0), const(ZERO4), const(ZERO4), uniform_mu(0.9),
        layout="fwd", speed=_cruise(BIAS_V), path=PathConfig(_curve(BIAS_R, 2.0, 2.0)),
        ay_bias=BIAS),
    ObserverScenario(
        "long_straight_bias", 14,
        f"{_fmt(LONG_T)} s straight with an ay sensor bias of {_fmt(BIAS)} m/s^2: v = "
        f"{_fmt(LONG_V)} m/s held by cruise control (fwd), mu = 0.9, small driver corrections "
        f"(0.0012 sin(2 pi 0.071 t) + 0.0008 sin(2 pi 0.23 t + 1) + 0.0005 sin(2 pi 0.61 t "
        f"+ 2) rad) on top of {YawConfig().text()}; logged every {_fmt(LONG_DT)} s",
        LONG_V, LONG_T, _long_corrections, const(ZERO4), const(ZERO4), uniform_mu(0.9),
        yaw=YawConfig(), layout="fwd", speed=_cruise(LONG_V), ay_bias=BIAS, dt=LONG_DT,
        tyres=("dugoff",)),
    ObserverScenario(
        "creep_stop", 15,
        f"creep and stop: v0 = {_fmt(CREEP_V0)} m/s, cruise control (fwd) to "
        f"{_fmt(CREEP_V)} m/s over 3 s, delta pulse 0.15 rad from t = 4 s to 8 s (1 s "
        f"ramps), cruise off and p = {_fmt(CREEP_P)} MPa all wheels ramped in over 0.5 s at "
        f"t = {_fmt(CREEP_STOP_T)} s, held to standstill until t = {_fmt(CREEP_T)} s; "
        f"mu = 0.9; low-speed slip floor v_low = {_fmt(CREEP_V_LOW)} m/s",
        CREEP_V0, CREEP_T, _creep_steer, _creep_pressure, const(ZERO4), uniform_mu(0.9),
        layout="fwd", speed=SpeedConfig(_creep_speed), v_low=CREEP_V_LOW),
    ObserverScenario(
        "hill_known_grade", 16,
        f"hill with known grade: v = 60 km/h held by cruise control (fwd), mu = 0.9, "
        f"grade 0 -> +{_fmt(HILL_G)} rad over s = 50..100 m, held, -> -{_fmt(HILL_G)} rad "
        f"over s = 200..300 m, held, -> 0 over s = 400..450 m; delta = 0; the grade is "
        f"logged (column grade)",
        HILL_V, 35.0, const(0.0), const(ZERO4), const(ZERO4), uniform_mu(0.9),
        layout="fwd", speed=_cruise(HILL_V),
        road=Road(grade=_hill_grade, text=f"hill +-{_fmt(HILL_G)} rad"), grade_known=True),
]

OBS_BY_NAME = {s.name: s for s in OBSERVER_SCENARIOS}


# ---- the friction loop: a mu step while cornering ------------------------------------------
# Not in OBSERVER_SCENARIOS (whose goldens, results tables and car-format twins cover the 17
# above): the closed-loop test of the observer's model row fed by the friction estimator's own
# output (OBSERVER.md §4 step 2, §6; test/estimators/pipeline/test_pipeline_loop_*.c) reads it
# from scenarios/observer_loop/ (make observer-loop-scenarios).  The circle_r60 turn (ay ~ 4
# m/s^2, 0.45 g) on a road whose friction steps 0.9 -> 0.5 -> 0.9 along the path: on 0.5 the
# turn uses 0.82 of the friction, so the friction estimator sees it and its output moves, and
# a too high or too low friction in the model row would show as a vy error.  Index 30: seed
# 231, clear of OBSERVER_SCENARIOS' 201-217 and of the mass and grade logs' 301+.
LOOP_MU = (0.9, 0.5)
LOOP_S = (155.0, 310.0)     # m: the steps at t ~ 10 s and ~ 20 s (15.5 m/s from t ~ 0)
LOOP_T = 30.0


def _loop_mu(s, left):
    return LOOP_MU[1] if LOOP_S[0] <= s < LOOP_S[1] else LOOP_MU[0]


OBS_LOOP_SCENARIOS = [
    ObserverScenario(
        "turn_mu_step", 30,
        f"mu step while cornering: the circle_r60 turn (radius {_fmt(CIRCLE_R)} m at "
        f"{_fmt(CIRCLE_V)} m/s held by cruise control (fwd), path curvature ramped 0 -> "
        f"1/{_fmt(CIRCLE_R)} 1/m over 2 s from t = 1 s) on mu = {_fmt(LOOP_MU[0])}, "
        f"{_fmt(LOOP_MU[1])} for road s in [{_fmt(LOOP_S[0])}, {_fmt(LOOP_S[1])}) m (each "
        f"wheel at its own s), then {_fmt(LOOP_MU[0])} again; {PathConfig(None).text()}",
        CIRCLE_V, LOOP_T, const(0.0), const(ZERO4), const(ZERO4), _loop_mu,
        layout="fwd", speed=_cruise(CIRCLE_V), path=PathConfig(_curve(CIRCLE_R, 1.0, 2.0))),
]
OBS_LOOP_BY_NAME = {s.name: s for s in OBS_LOOP_SCENARIOS}
