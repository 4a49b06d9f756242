"""Scenarios for the mass and road-grade estimator (issue 19, docs/MASS_GRADE.md).

Drives on graded roads (all straight but one) with the longitudinal forces the friction and
observer scenarios leave out: rolling resistance and aerodynamic drag (vehicle.py ``ext``), a
wind, a torque gap at each gear shift, brake applications.  Written by
scripts/data/make_mass_grade_scenarios.py to scenarios/mass_grade/ (columns: docs/spec/DATA.md
"Mass and grade logs").

| name | vehicle | purpose |
|---|---|---|
| truck_graded_drive | truck 5758 kg | the seed's TruckSim drive: 560 s, ~10 km, grade varying over ~5.5 deg, gentle speed changes (|a| < 0.4 m/s^2) |
| car_hilly_road | car 2000 kg (4 occupants and luggage) | hills of +-6 %, speed 55-85 km/h by cruise control |
| car_hilly_road_light | car 1500 kg (driver only, no luggage) | car_hilly_road's road and speed at the light end of issue 19's 1 500-2 100 kg |
| car_stop_and_go | car 1650 kg (driver only) | three stops by the brake pedal on a 2 % climb: the pause logic |
| car_gear_shift | car 1800 kg, automated manual gearbox | acceleration through four shifts, each a 0.5 s torque gap |
| car_headwind | car 1900 kg | gentle hills at 90 km/h into a gusty 10 m/s headwind the model does not know |
| car_grade_step | car 2100 kg | a ramp onto a car park: 0 -> 10 % over 5 m at 18 km/h |
| car_flat_cruise | car 1750 kg | one acceleration, then 160 s of constant speed on a flat road: no excitation |
| car_valley_brake | car 1850 kg | a long moderate brake (0.8 MPa, 11 s, no ABS) through a valley's sag: the grade goes -6 % -> +2 % while the pedal is pressed (mg_pause_grade's brake case) |
| car_long_curve_crest | car 1700 kg | a 200 m radius curve at 80 km/h (a_y ~2.5 m/s^2, ~16 s) over a crest: +5 % -> -4 % within the curve (mg_pause_grade's curve case) |

All but car_long_curve_crest (steered by a path follower) are straight (delta = 0); all on
mu 0.9, with the Dugoff truth tyre (the tyres work far below their limit here, where both
truth tyres are the same linear tyre) and a front-driven car / rear-driven truck.  The drive
torque is the cruise controller's (control.SpeedConfig) plus, in car_gear_shift, the
driver's.  Each log's noise seed is 301 + its index.

Log size.  A row of the DATA.md columns printed with repr() is ~330 bytes; the truck's
560 s would be 18 MB at 100 Hz.  So the mass and grade logs (a) carry what a production
car's chassis CAN gives (no vx, vy, yaw_acc), (b) are logged at 50 Hz (cars) and 20 Hz
(the truck's 560 s), and (c) print each noisy sensor value rounded to a resolution far
below its noise (RESOLUTION: 1e-6 rad, 1e-5 m/s^2 and rad/s, 0.01 N m, 1 Pa; noise sd
0.001 rad, 0.05, 10 N m, 2e4 Pa), as a CAN database's scaling would.  Only the noisy
variant is written.
"""

from dataclasses import dataclass, field, replace
from math import cos, pi, radians, sin, tanh
from typing import Callable, Optional

import numpy as np

from .control import ObserverInputs, PathConfig, SpeedConfig
from .observer_scenarios import OBS_BY_NAME, Road
from .scenarios import KMH, ZERO4, const, ramp, uniform_mu
from .vehicle import ESTIMATOR_KEYS, SIM_KEYS, Params, simulate

__all__ = ["Resistance", "MassGradeScenario", "MASS_GRADE_SCENARIOS", "MG_BY_NAME", "SEED_BASE",
           "CAR", "TRUCK", "COLUMNS", "NOISE_SD", "RESOLUTION", "run", "table", "noisy",
           "metadata", "csv_text", "m_rot", "OBS_RES_SCENARIOS", "OBS_RES_BY_NAME",
           "with_resistances"]

SEED_BASE = 301
V_EPS = 0.5   # m/s, the rolling resistance's sign is smoothed as tanh(vx / V_EPS) at standstill


@dataclass(frozen=True)
class Resistance:
    """Rolling resistance m*g*(fc + fr*vx)*cos(theta) and drag 0.5*rho*cd*area*(vx+w)|vx+w|,
    w(t) the headwind [m/s] (positive against the direction of travel)."""
    fc: float
    fr: float
    rho: float
    cd: float
    area: float
    wind: Callable = const(0.0)
    wind_text: str = "still air"

    def ext(self, p):
        """vehicle.py's ext(t, vx, theta) for the vehicle parameters p."""
        m, g = p.m, p.g

        def force(t, vx, theta):
            va = vx + self.wind(t)
            roll = m * g * (self.fc + self.fr * vx) * cos(theta) * tanh(vx / V_EPS)
            return -roll - 0.5 * self.rho * self.cd * self.area * va * abs(va)
        return force

    def text(self):
        return (f"rolling resistance m g ({self.fc:g} + {self.fr:g} v) cos(theta), drag "
                f"0.5 {self.rho:g} {self.cd:g} {self.area:g} v_air^2, {self.wind_text}")


# The passenger car: the simulator's car (vehicle.Params) at its loaded mass; the truck: a
# two-axle medium truck with the seed's mass.  J scales with the mass (same gyradius).
CAR = Params()
CAR_RES = dict(fc=0.010, fr=0.00015, rho=1.2, cd=0.30, area=2.2)
TRUCK = Params(m=5758.0, Lf=2.0, Lr=1.8, Bf=1.9, Br=1.8, R=0.45, J=21000.0, hg=1.0,
               kb_f=900.0, kb_r=900.0, Iw=8.0)
TRUCK_RES = dict(fc=0.0065, fr=0.00005, rho=1.2, cd=0.60, area=6.0)


def car(m):
    return Params(m=m, J=CAR.J * m / CAR.m)


def m_rot(p):
    """Equivalent mass of the four wheels' spin inertia, 4*Iw/R^2 [kg]: the drive torque
    accelerates the wheels' rotation too (docs/MASS_GRADE.md §1)."""
    return 4.0 * p.Iw / (p.R * p.R)


class MassGradeInputs(ObserverInputs):
    """ObserverInputs (cruise control, drive layout) with a torque gap: the applied drive
    torque is the controller's times gap(t) in [0, 1] (a gear shift's clutch opening)."""

    def __init__(self, p, steer, pressure, drive, speed_cfg, layout, gap, v_low, path_cfg=None):
        super().__init__(p, steer, pressure, drive, speed_cfg=speed_cfg, layout=layout,
                         v_low=v_low, path_cfg=path_cfg)
        self.gap = gap

    def update(self, t, y):
        super().update(t, y)
        k = self.gap(t)
        if k != 1.0:
            self.tdrive = tuple(k * v for v in self.tw)


@dataclass(frozen=True)
class MassGradeScenario:
    name: str
    index: int
    description: str
    params: Params
    res: Resistance
    v0: float
    duration: float
    speed: SpeedConfig
    road: Road
    layout: str = "fwd"
    pressure: Callable = const(ZERO4)      # driver's brake pressure per wheel, MPa
    drive: Callable = const(ZERO4)         # driver's torque request per wheel, N m
    gap: Callable = const(1.0)             # torque-gap factor of the applied drive torque
    gear: Callable = const(1)              # engaged gear (1 for a single-speed drive)
    v_low: Optional[float] = None
    path: Optional[PathConfig] = None      # the driver's path follower (None: straight)
    dt: float = 0.02
    rate: int = 1000
    extra: tuple = field(default=())       # more (key, value) metadata

    @property
    def seed(self):
        return SEED_BASE + self.index

    def make_inputs(self):
        return MassGradeInputs(self.params, const(0.0), self.pressure, self.drive, self.speed,
                               self.layout, self.gap, self.v_low, self.path)


def run(sc, duration=None):
    """Simulate a scenario (vehicle.simulate with its road and resistances)."""
    return simulate(sc.make_inputs(), uniform_mu(0.9), sc.v0,
                    sc.duration if duration is None else duration, sc.params, "dugoff", sc.dt,
                    sc.rate, sc.road, sc.v_low, ext=sc.res.ext(sc.params))


# ---- log columns -------------------------------------------------------------------------
WHEELS = ("fl", "fr", "rl", "rr")
COLUMNS = (["t", "delta", "yaw_rate", "ax", "ay"] + [f"omega_{w}" for w in WHEELS]
           + ["drive_torque", "brake", "brake_pressure", "gear", "vx_true", "grade_true",
              "mass_true"])
NOISE_SD = dict([("delta", 0.001), ("yaw_rate", 0.005), ("ax", 0.05), ("ay", 0.05)]
                + [(f"omega_{w}", 0.05) for w in WHEELS]
                + [("drive_torque", 10.0), ("brake_pressure", 2.0e4)])
NOISY = [c for c in COLUMNS if c in NOISE_SD]
# decimals each column is printed with (round(x, d)); far below the noise sd above
RESOLUTION = dict([("t", 6), ("delta", 6), ("yaw_rate", 5), ("ax", 5), ("ay", 5)]
                  + [(f"omega_{w}", 5) for w in WHEELS]
                  + [("drive_torque", 2), ("brake_pressure", 0), ("vx_true", 9),
                     ("grade_true", 10), ("mass_true", 3)])
BRAKE_ON = 1e-6   # MPa: the pedal is pressed when the driver's pressure exceeds this


def table(sim, sc):
    """Noise-free log columns of a simulator output."""
    n = len(sim["t"])
    tab = {c: np.asarray(sim[c], dtype=float).copy() for c in ("t", "delta", "yaw_rate", "ax",
                                                                 "ay")}
    for i, w in enumerate(WHEELS):
        tab[f"omega_{w}"] = sim["omega"][:, i].copy()
    tab["drive_torque"] = sim["drive"].sum(axis=1)
    p_driver = np.array([sc.pressure(t)[0] for t in sim["t"]])
    tab["brake"] = (p_driver > BRAKE_ON).astype(float)
    tab["brake_pressure"] = sim["pressure"].mean(axis=1) * 1e6
    tab["gear"] = np.array([float(sc.gear(t)) for t in sim["t"]])
    tab["vx_true"] = np.asarray(sim["vx"], dtype=float).copy()
    tab["grade_true"] = np.asarray(sim["grade"], dtype=float).copy()
    tab["mass_true"] = np.full(n, sc.params.m)
    return tab


def noisy(tab, sc):
    """Copy with additive white Gaussian noise: one (rows x NOISY) standard-normal block of
    Generator(PCG64(seed)) in column order, as the other logs (sensors.add_noise)."""
    rng = np.random.Generator(np.random.PCG64(sc.seed))
    z = rng.standard_normal((len(tab["t"]), len(NOISY)))
    out = {c: v.copy() for c, v in tab.items()}
    for j, c in enumerate(NOISY):
        out[c] = tab[c] + NOISE_SD[c] * z[:, j]
    return out


def metadata(sc):
    p = sc.params
    meta = [("scenario", sc.name), ("description", sc.description), ("dt", sc.dt),
            ("seed", sc.seed), ("noise", "default"), ("truth_tyre", "dugoff"), ("abs", "off"),
            ("driver_steer", "open_loop" if sc.path is None else "path_follower"),
            ("drive_layout", sc.layout), ("tcs", "off"),
            ("cruise_control", "on"), ("road", sc.road.text), ("grade_known", "no"),
            ("ay_bias", 0.0), ("sim_v_low", "none" if sc.v_low is None else float(sc.v_low))]
    meta += p.items(ESTIMATOR_KEYS) + p.items(SIM_KEYS)
    meta += [(f"noise_{c}", NOISE_SD[c]) for c in NOISY]
    # the drive line (DATA.md "Drive-line metadata"): the torque is logged at the wheels
    meta += [("driveline_torque_at", "wheels"), ("driveline_m_rot", m_rot(p))]
    r = sc.res
    meta += [("sim_fc", r.fc), ("sim_fr", r.fr), ("sim_rho", r.rho), ("sim_cd", r.cd),
             ("sim_area", r.area), ("sim_wind", r.wind_text)]
    meta += list(sc.extra)
    meta += [("sim_integrator", "rk4"), ("sim_rate", sc.rate), ("v0", sc.v0),
             ("duration", sc.duration)]
    return meta


def _cell(c, v):
    d = RESOLUTION.get(c)
    if c in ("brake", "gear"):
        return str(int(v))
    return repr(round(v, d)) if d is not None else repr(v)


def csv_text(tab, meta):
    lines = [f"# {k} = {v!r}" if isinstance(v, float) else f"# {k} = {v}" for k, v in meta]
    lines.append(",".join(COLUMNS))
    cols = [tab[c].tolist() for c in COLUMNS]
    for row in zip(*cols):
        lines.append(",".join(_cell(c, v) for c, v in zip(COLUMNS, row)))
    return "\n".join(lines) + "\n"


# ---- the scenarios ------------------------------------------------------------------------
def _fmt(x):
    return f"{x:g}"


def _cruise(v_target, p, t_min, t_max):
    """Cruise PI scaled to the vehicle: the car's gains (control.SpeedConfig, for ~1/(R m) =
    1/595) times R*m/595, so every vehicle gets the same ~1 rad/s speed loop."""
    k = p.R * p.m / 595.0
    return SpeedConfig(v_target, kp=600.0 * k, ki=300.0 * k, t_min=t_min, t_max=t_max)


# Truck: 560 s, v between ~46 and ~83 km/h, |a| < 0.4, mean |a| ~ 0.1 (the seed's figures),
# a grade over ~5.5 deg with one stretch of fast change near s = 7.2 km (the seed's "near
# 400 s the grade changes sharply").
TRUCK_T, TRUCK_V = 560.0, 17.9


def _truck_v(t):
    return TRUCK_V + 4.5 * sin(2.0 * pi * t / 200.0) + 0.6 * sin(2.0 * pi * t / 61.0 + 1.0)


def _truck_grade(s):
    deg = (1.8 * sin(2.0 * pi * s / 2600.0) + 1.0 * sin(2.0 * pi * s / 950.0 + 0.5)
           + ramp(s, 7100.0, 60.0, 1.6) - ramp(s, 7250.0, 60.0, 1.6))
    return radians(deg)


# Car on hills: +-6 % crests every ~600 m, speed 55-85 km/h.
def _hilly_v(t):
    return 70.0 * KMH + 8.0 * KMH * sin(2.0 * pi * t / 45.0) + 3.0 * KMH * sin(2.0 * pi * t / 13.0)


def _hilly_grade(s):
    return 0.06 * sin(2.0 * pi * s / 600.0) * (0.6 + 0.4 * sin(2.0 * pi * s / 1700.0))


# Stop and go: 0 <-> ~45 km/h, three stops by the brake pedal (cruise off while braking).
SG_STOPS = ((20.0, 28.0), (55.0, 62.0), (90.0, 96.0))   # brake on, brake off [s]
SG_P = 2.0                                              # MPa, a firm stop
SG_GRADE = 0.02


def _sg_v(t):
    for on, off in SG_STOPS:
        if on <= t < off:
            return None
    base = 45.0 * KMH
    for on, off in SG_STOPS:
        if off <= t < off + 12.0:     # pull away: 12 s ramp from standstill
            return min(base, base * (t - off) / 10.0)
    return base


def _sg_pressure(t):
    v = 0.0
    for on, off in SG_STOPS:
        if on <= t < off:
            v = ramp(t, on, 0.5, SG_P) - ramp(t, off - 0.3, 0.3, SG_P)
    return (v, v, v, v)


# Gear shift: acceleration at 0.7 m/s^2 from 15 to ~90 km/h through shifts 1-2-3-4-5.
GS_SHIFTS = (5.0, 11.0, 19.0, 30.0)     # s, each a torque gap: 0.15 s down, 0.2 s open, 0.15 s up
GS_GAP = (0.15, 0.2, 0.15)
GS_A, GS_T = 0.7, 30.0                  # m/s^2, s: the speed target's ramp


def _gs_gear(t):
    return 1 + sum(1 for ts in GS_SHIFTS if t >= ts + GS_GAP[0])


def _gs_gap(t):
    for ts in GS_SHIFTS:
        down, hold, up = GS_GAP
        if ts <= t < ts + down + hold + up:
            x = t - ts
            if x < down:
                return 1.0 - x / down
            if x < down + hold:
                return 0.0
            return (x - down - hold) / up
    return 1.0


def _gs_v(t):
    return 15.0 * KMH + GS_A * min(t, GS_T)


def _gs_grade(s):
    return ramp(s, 300.0, 60.0, 0.04)


# Headwind: 90 km/h, gentle hills, wind 10 m/s with gusts.
def _hw_v(t):
    return 25.0 + 1.5 * sin(2.0 * pi * t / 30.0)


def _hw_wind(t):
    return 10.0 + 3.0 * sin(2.0 * pi * t / 7.0) + 1.5 * sin(2.0 * pi * t / 2.3 + 1.0)


def _hw_grade(s):
    return 0.03 * sin(2.0 * pi * s / 900.0)


# Grade step: accelerate 5 -> 12 m/s and back (mass learning), then at 18 km/h up a ramp of
# 10 % reached over 5 m (s = GSTEP_S).
GSTEP_S = 330.0


def _gstep_v(t):
    return 5.0 + ramp(t, 3.0, 10.0, 7.0) - ramp(t, 20.0, 10.0, 7.0)


def _gstep_grade(s):
    return ramp(s, GSTEP_S, 5.0, 0.10)


# Flat cruise: 20 -> 27 m/s in the first 20 s, then constant.
def _flat_v(t):
    return 20.0 + ramp(t, 2.0, 18.0, 7.0)


# Valley brake (mg_pause_grade's case, brake bit): accelerate 20 -> 25 m/s on the flat, down
# a -6 % descent, then a long moderate (non-ABS) brake application that carries the car
# through the valley's sag: the grade goes -6 % -> +2 % while the pedal is pressed.
VB_ON, VB_OFF, VB_P = 32.0, 43.0, 0.8     # brake on, off [s], pressure [MPa]: ~1.3 m/s^2 of brake
VB_DOWN_S, VB_SAG_S, VB_SAG_LEN = 350.0, 775.0, 170.0   # m: descent, sag start, sag length
VB_V_OFF = 11.0                           # m/s, about the speed at the release


def _vb_v(t):
    if VB_ON <= t < VB_OFF:
        return None
    if t < VB_ON:
        return 20.0 + ramp(t, 2.0, 10.0, 5.0)
    return VB_V_OFF + ramp(t, VB_OFF + 1.0, 16.0, 22.0 - VB_V_OFF)   # back to 22 m/s at 0.7 m/s^2


def _vb_pressure(t):
    v = 0.0
    if VB_ON <= t < VB_OFF:
        v = ramp(t, VB_ON, 0.5, VB_P) - ramp(t, VB_OFF - 0.5, 0.5, VB_P)
    return (v, v, v, v)


def _vb_grade(s):
    return (ramp(s, VB_DOWN_S, 100.0, -0.06)
            + ramp(s, VB_SAG_S, VB_SAG_LEN, 0.08))


# Long curve over a crest (mg_pause_grade's case, curve bit): a 200 m radius curve of ~15 s at
# 80 km/h (a_y ~2.5 m/s^2) over a crest whose grade goes +5 % -> -4 % within the curve.
LC_V, LC_R = 22.0, 200.0                  # m/s, m
LC_IN, LC_OUT, LC_EASE = 30.0, 46.0, 2.0  # s: curve entry, exit starts; clothoid ease [s]
LC_UP_S, LC_CREST_S, LC_CREST_LEN = 250.0, 700.0, 260.0   # m: climb, crest start, length


def _lc_v(t):
    return 18.0 + ramp(t, 2.0, 10.0, LC_V - 18.0)


def _lc_curvature(t):
    return ramp(t, LC_IN, LC_EASE, 1.0 / LC_R) - ramp(t, LC_OUT, LC_EASE, 1.0 / LC_R)


def _lc_grade(s):
    return ramp(s, LC_UP_S, 100.0, 0.05) - ramp(s, LC_CREST_S, LC_CREST_LEN, 0.09)


def _car_res(wind=const(0.0), wind_text="still air"):
    return Resistance(**CAR_RES, wind=wind, wind_text=wind_text)


def _car_cruise(v, p):
    return _cruise(v, p, -1500.0, 3500.0)


_C2000, _C1650, _C1800, _C1900, _C2100, _C1750 = (car(m) for m in (2000.0, 1650.0, 1800.0, 1900.0,
                                                                  2100.0, 1750.0))
_C1850, _C1700, _C1500 = car(1850.0), car(1700.0), car(1500.0)

MASS_GRADE_SCENARIOS = [
    MassGradeScenario(
        "truck_graded_drive", 0,
        "the seed's truck drive: 5758 kg two-axle truck (rear drive), 560 s, v* = 17.9 + "
        "4.5 sin(2 pi t/200) + 0.6 sin(2 pi t/61 + 1) m/s held by cruise control, grade "
        "1.8 sin(2 pi s/2600) + 1.0 sin(2 pi s/950 + 0.5) deg plus a 1.6 deg bump over "
        "s = 7100..7310 m, straight, " + Resistance(**TRUCK_RES).text(),
        TRUCK, Resistance(**TRUCK_RES), _truck_v(0.0), TRUCK_T,
        _cruise(_truck_v, TRUCK, -6000.0, 12000.0),
        Road(grade=_truck_grade, text="rolling grade over ~5.5 deg (description)"),
        layout="rwd", gear=const(6), dt=0.05, rate=1000),
    MassGradeScenario(
        "car_hilly_road", 1,
        "passenger car 2000 kg (4 occupants and luggage) on hills: grade 0.06 sin(2 pi s/600) "
        "(0.6 + 0.4 sin(2 pi s/1700)), v* = 70 + 8 sin(2 pi t/45) + 3 sin(2 pi t/13) km/h by "
        "cruise control (fwd), single-speed drive, " + _car_res().text(),
        _C2000, _car_res(), _hilly_v(0.0), 150.0, _car_cruise(_hilly_v, _C2000),
        Road(grade=_hilly_grade, text="hills +-6 % (description)")),
    MassGradeScenario(
        "car_stop_and_go", 2,
        f"stop and go: car 1650 kg on a constant {_fmt(SG_GRADE)} rad climb, 45 km/h by cruise "
        f"control, three stops by the brake pedal ({_fmt(SG_P)} MPa all wheels; brake on/off "
        f"at {', '.join(f'{a:g}/{b:g}' for a, b in SG_STOPS)} s, cruise off meanwhile), pull "
        f"away over 10 s; single-speed drive; low-speed slip floor 2 m/s; " + _car_res().text(),
        _C1650, _car_res(), 45.0 * KMH, 120.0, _car_cruise(_sg_v, _C1650),
        Road(grade=const(SG_GRADE), text=f"constant grade {_fmt(SG_GRADE)} rad"),
        pressure=_sg_pressure, v_low=2.0, rate=2000),
    MassGradeScenario(
        "car_gear_shift", 3,
        f"gear shifts: car 1800 kg with an automated manual gearbox, v* rising {_fmt(GS_A)} "
        f"m/s^2 from 15 km/h for {_fmt(GS_T)} s, then held, by cruise control, "
        f"shifts 1-2-3-4-5 at {', '.join(_fmt(t) for t in GS_SHIFTS)} s, each a torque gap "
        f"(down {_fmt(GS_GAP[0])} s, open {_fmt(GS_GAP[1])} s, up {_fmt(GS_GAP[2])} s; the "
        "gear column changes when the clutch is open), grade 0 -> 0.04 rad over s = 300..360 m, "
        + _car_res().text(),
        _C1800, _car_res(), 15.0 * KMH, 50.0, _car_cruise(_gs_v, _C1800),
        Road(grade=lambda s: _gs_grade(s), text="0 -> 0.04 rad over s = 300..360 m"),
        gap=_gs_gap, gear=_gs_gear, rate=2000),
    MassGradeScenario(
        "car_headwind", 4,
        "headwind: car 1900 kg at 25 + 1.5 sin(2 pi t/30) m/s by cruise control into a wind of "
        "10 + 3 sin(2 pi t/7) + 1.5 sin(2 pi t/2.3 + 1) m/s, grade 0.03 sin(2 pi s/900), "
        + _car_res(_hw_wind, "headwind (description)").text(),
        _C1900, _car_res(_hw_wind, "headwind 10 m/s with gusts"), _hw_v(0.0), 120.0,
        _car_cruise(_hw_v, _C1900), Road(grade=_hw_grade, text="0.03 sin(2 pi s/900)")),
    MassGradeScenario(
        "car_grade_step", 5,
        f"ramp onto a car park: car 2100 kg, v* = 5 m/s, up to 12 m/s over 3..13 s and back "
        f"over 20..30 s, the road flat, then 0 -> 0.10 rad over s = {_fmt(GSTEP_S)}.."
        f"{_fmt(GSTEP_S + 5.0)} m (reached at ~48 s) and held; " + _car_res().text(),
        _C2100, _car_res(), 5.0, 65.0, _car_cruise(_gstep_v, _C2100),
        Road(grade=_gstep_grade, text=f"grade step 0 -> 0.10 rad at s = {_fmt(GSTEP_S)} m"),
        rate=2000),
    MassGradeScenario(
        "car_flat_cruise", 6,
        "flat cruise: car 1750 kg, v* = 20 m/s rising to 27 m/s over 2..20 s, then constant to "
        "180 s on a flat road: no excitation after 20 s; " + _car_res().text(),
        _C1750, _car_res(), 20.0, 180.0, _car_cruise(_flat_v, _C1750),
        Road(text="flat")),
    MassGradeScenario(
        "car_valley_brake", 7,
        f"valley brake: car 1850 kg, v* = 20 m/s rising to 25 m/s over 2..12 s by cruise "
        f"control (fwd), grade 0 -> -0.06 rad over s = {_fmt(VB_DOWN_S)}..{_fmt(VB_DOWN_S + 100)}"
        f" m, then the valley's sag -0.06 -> +0.02 rad over s = {_fmt(VB_SAG_S)}.."
        f"{_fmt(VB_SAG_S + VB_SAG_LEN)} m, driven through under a long moderate brake "
        f"({_fmt(VB_P)} MPa all wheels, no ABS action; on/off at {_fmt(VB_ON)}/{_fmt(VB_OFF)} s, "
        f"cruise off meanwhile), then v* = {_fmt(VB_V_OFF)} -> 22 m/s over "
        f"{_fmt(VB_OFF + 1)}..{_fmt(VB_OFF + 17)} s on the +0.02 rad climb; single-speed drive; "
        + _car_res().text(),
        _C1850, _car_res(), 20.0, 70.0, _car_cruise(_vb_v, _C1850),
        Road(grade=_vb_grade, text="-0.06 rad descent into a sag to +0.02 rad (description)"),
        pressure=_vb_pressure, rate=2000),
    MassGradeScenario(
        "car_long_curve_crest", 8,
        f"long curve over a crest: car 1700 kg, v* = 18 m/s rising to {_fmt(LC_V)} m/s over "
        f"2..12 s by cruise control (fwd), grade 0 -> +0.05 rad over s = {_fmt(LC_UP_S)}.."
        f"{_fmt(LC_UP_S + 100)} m, then the crest +0.05 -> -0.04 rad over s = "
        f"{_fmt(LC_CREST_S)}..{_fmt(LC_CREST_S + LC_CREST_LEN)} m, driven in a curve of radius "
        f"{_fmt(LC_R)} m (path curvature 0 -> 1/{_fmt(LC_R)} 1/m over {_fmt(LC_IN)}.."
        f"{_fmt(LC_IN + LC_EASE)} s, back to 0 over {_fmt(LC_OUT)}..{_fmt(LC_OUT + LC_EASE)} s; "
        f"{PathConfig(None).text()}); single-speed drive; " + _car_res().text(),
        _C1700, _car_res(), 18.0, 70.0, _car_cruise(_lc_v, _C1700),
        Road(grade=_lc_grade, text="+0.05 rad climb over a crest to -0.04 rad (description)"),
        path=PathConfig(_lc_curvature), rate=2000),
    # issue 19's passenger car spans 1 500-2 100 kg (1-4 occupants and luggage): the hilly
    # road again at the light end (car_hilly_road is the heavy one), its own noise seed
    MassGradeScenario(
        "car_hilly_road_light", 9,
        "passenger car 1500 kg (driver only, no luggage) on car_hilly_road's hills: grade "
        "0.06 sin(2 pi s/600) (0.6 + 0.4 sin(2 pi s/1700)), v* = 70 + 8 sin(2 pi t/45) + "
        "3 sin(2 pi t/13) km/h by cruise control (fwd), single-speed drive, "
        + _car_res().text(),
        _C1500, _car_res(), _hilly_v(0.0), 150.0, _car_cruise(_hilly_v, _C1500),
        Road(grade=_hilly_grade, text="hills +-6 % (description)")),
]

MG_BY_NAME = {s.name: s for s in MASS_GRADE_SCENARIOS}


# ---- observer scenarios with the car's resistances (scenarios/observer_res/) ----------------
# The observer logs (observer_scenarios.py) have no rolling resistance and no drag, as the
# paper; the mass filter's car preset has both (mg_fc = 0.01, mg_fr = 0.00015, mg_rho = 1.2,
# mg_cd = 0.30, mg_area = 2.2 = CAR_RES, the simulator's car being the preset's).  These
# twins add CAR_RES to the scenarios the mass studies use (the mu 0.3 traction logs and the
# hill climb), so the preset's model matches the log.  Same index as the original, so the
# same noise seed: a twin differs from its original by the resistances alone.  Written noisy
# only (make_observer_scenarios.py --resistances), with the truth tyres below: the traction
# logs with both (the slip differs), the hill with Dugoff (its tyres stay linear), 3.6 MB.
OBS_RES_TYRES = {"traction_rwd_mu03": ("dugoff", "mf"), "traction_awd_mu03": ("dugoff", "mf"),
                 "hill_known_grade": ("dugoff",)}


def with_resistances(sc, res, suffix="_res", tyres=None):
    """The observer scenario @sc with the driving resistances @res (observer_scenarios
    ObserverScenario.res), renamed <name><suffix>, the resistances appended to its
    description; @tyres: its truth tyres (None: sc's)."""
    return replace(sc, name=sc.name + suffix, description=sc.description + "; " + res.text(),
                   res=res, tyres=sc.tyres if tyres is None else tyres)


OBS_RES_SCENARIOS = [with_resistances(OBS_BY_NAME[n], _car_res(), tyres=t)
                     for n, t in OBS_RES_TYRES.items()]
OBS_RES_BY_NAME = {s.name: s for s in OBS_RES_SCENARIOS}
