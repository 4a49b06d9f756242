"""Tyre identification scenarios (issue 20, docs/TYRE_ID.md §8): a Magic Formula truth with
known B, C, D, E per axle, front and rear unlike each other and unlike the parameter file.

The truth tyre is the simulator's "mf" (tyres.py) with its lateral keys set per axle through
vehicle.simulate's tyre_map: cornering stiffness per unit load cy, shape factor C (mf_Cy) and
curvature E (mf_Ey).  With no longitudinal slip (no brake, no drive torque: the wheels roll
free) each wheel's lateral force is exactly the pure-slip Magic Formula in the lateral slip
tan(alpha),
    Fy = D sin(C atan(B t - E (B t - atan(B t)))),  t = tan(alpha),
    D = mu Fz,  B = cy / (C mu),
so the per-axle truth is D = mu (Fz_left + Fz_right) (the axle's instantaneous load), and C,
E, B as above.  The logs' metadata keep the parameter file's tyre data (cy = 15, mf_Cy 1.3,
mf_Ey -1, the other logs' values) and list the truth's as truth_* lines (as
wrong_tyre_data does), which an estimator ignores.

Front tyre: the simulator's default lateral curve (cy 15, C 1.3, E -1: a rounded peak); rear:
stiffer per unit load and sharper (cy 17, C 1.5, E 0.3), so the car understeers and the front
axle reaches its peak first.  The tyre change swaps both axles to other tyres at one instant
(a softer front with a sharp peak, C 1.6, E 0.4; a softer rear with a rounded one).

The two brake-in-turn logs (issue 20's friction ellipse, docs/TYRE_ID.md §3.5) brake all four
wheels in a steady turn (ABS off, the wheels never near locking), so for those seconds the
wheels slip longitudinally and each wheel's lateral force is the simulator's combined-slip
force (tyres.py, the similarity method), below the pure-slip curve.  Their truth columns are
defined as on the other logs: D, C, B, E of the pure-slip curve at the axle's instantaneous
load (D = mu (Fz_left + Fz_right)), and Fy_*_true the force the axle actually transmits.  The
brake is released 4 s before the end, so the final curve the accuracy tables score is the
pure-slip one at about the static load again.
"""

from dataclasses import dataclass, replace
from math import pi, sin
from typing import Callable

from .scenarios import (KMH, ZERO4, const, double_lane_change, pulse, ramp, uniform_mu, DLC_P,
                        DLC_T)

__all__ = ["AxleTyre", "TidScenario", "TID_SCENARIOS", "TID_BY_NAME", "FRONT", "REAR",
           "FRONT_2", "REAR_2"]


@dataclass(frozen=True)
class AxleTyre:
    """Lateral Magic Formula of one axle: cy per unit load [1/rad], shape C, curvature E."""
    cy: float
    C: float
    E: float

    def params(self, p):
        return replace(p, cy=self.cy, mf_Cy=self.C, mf_Ey=self.E)

    def text(self):
        return f"cy {self.cy:g}, C {self.C:g}, E {self.E:g}"


FRONT = AxleTyre(15.0, 1.3, -1.0)
REAR = AxleTyre(17.0, 1.5, 0.3)
FRONT_2 = AxleTyre(11.0, 1.6, 0.4)
REAR_2 = AxleTyre(13.0, 1.3, -0.5)


@dataclass(frozen=True)
class TidScenario:
    name: str
    index: int               # noise seed = 301 + index
    description: str
    v0: float                # m/s
    duration: float          # s
    steer: Callable          # delta(t) [rad]
    mu: float                # uniform road friction
    tyres: tuple = ((0.0, FRONT, REAR),)   # (from t, front, rear), t ascending, first at 0
    pressure: Callable = const(ZERO4)      # wheel-cylinder pressures (fl, fr, rl, rr) [MPa]

    @property
    def seed(self):
        return 301 + self.index

    def inputs(self, t):
        return self.steer(t), self.pressure(t), ZERO4

    def axle_tyres(self, t):
        """(front, rear) AxleTyre in force at time t."""
        cur = self.tyres[0]
        for seg in self.tyres:
            if t >= seg[0]:
                cur = seg
        return cur[1], cur[2]

    def tyre_map(self, p):
        """vehicle.simulate's tyre_map: t -> four Params (the Params built once)."""
        segs = [(t0, f.params(p), r.params(p)) for t0, f, r in self.tyres]

        def per_wheel(t):
            cur = segs[0]
            for seg in segs:
                if t >= seg[0]:
                    cur = seg
            return (cur[1], cur[1], cur[2], cur[2])
        return per_wheel

    def mu_map(self):
        return uniform_mu(self.mu)


def _sine(amp, f):
    return lambda t: amp * sin(2.0 * pi * f * t)


# Chosen inputs.  The ramp steers reach the front axle's peak at about 2/3 of the ramp (as
# the friction scenarios' ramp_steer_*, here without cruise control: no drive torque, the car
# slows by the tyres' induced drag); the lane changes are the friction scenarios' shape with
# amplitudes that bring the front axle to its peak.
RS_T0 = 1.0
SINE_F = 0.5
TC_T = 8.0           # s, the tyre change
_TEXT_TYRES = f"front {FRONT.text()}; rear {REAR.text()}"


def _ramp_steer(name, index, v0, mu, d_end):
    return TidScenario(
        name, index,
        f"slow ramp steer to the limit: v0 = {v0 / KMH:g} km/h, mu = {mu:g}, delta ramped 0 -> "
        f"{d_end:g} rad from t = {RS_T0:g} s to 10 s, no brake, no drive torque; truth tyres "
        f"{_TEXT_TYRES}",
        v0, 10.0, lambda t: ramp(t, RS_T0, 10.0 - RS_T0, d_end), mu)


def _dlc(name, index, v0, mu, amp):
    return TidScenario(
        name, index,
        f"double lane change: v0 = {v0 / KMH:g} km/h, mu = {mu:g}, delta = {amp:g} rad * "
        f"sin(2*pi*(t-t1)/{DLC_P:g}) over one period from t1 = {DLC_T[0]:g} s, the mirror image "
        f"from t2 = {DLC_T[1]:g} s, no brake, no drive torque; truth tyres {_TEXT_TYRES}",
        v0, 10.0, double_lane_change(amp, DLC_P, *DLC_T), mu)


# Braking in a steady turn: delta ramped to its value over 1 s from t = 1 s and held, the same
# pressure on all wheels from BIT_T_ON to BIT_T_OFF (0.2 s ramps; the simulator's brake gains
# put 62.5 % of the torque on the front axle, the identifier's tid_fx_front), released 4 s
# before the end.  High mu: ay ~ 4.4 m/s^2 before, ax ~ -3.5 m/s^2 while braking, the rear
# left wheel's utilisation up to 0.9, beta below 1.7 deg; low mu: ay ~ 1.8, ax ~ -1.3,
# utilisation up to 0.82 (measured when chosen).
BIT_T_ON, BIT_T_OFF, BIT_TR = 4.0, 6.0, 0.2
BIT_HIGH = (0.9, 0.03, 2.2)      # mu, delta [rad], pressure [MPa]
BIT_LOW = (0.3, 0.012, 0.8)


def _brake_in_turn(name, index, v0, cfg):
    mu, d, p = cfg
    return TidScenario(
        name, index,
        f"braking in a turn: v0 = {v0 / KMH:g} km/h, mu = {mu:g}, delta ramped 0 -> {d:g} rad "
        f"from t = {RS_T0:g} s over 1 s then held, p = {p:g} MPa all wheels from t = "
        f"{BIT_T_ON:g} s to {BIT_T_OFF:g} s ({BIT_TR:g} s ramps), ABS off, no drive torque; "
        f"truth tyres {_TEXT_TYRES} (pure slip; combined slip while braking)",
        v0, 10.0, lambda t: ramp(t, RS_T0, 1.0, d), mu,
        pressure=lambda t: (pulse(t, BIT_T_ON, BIT_T_OFF, BIT_TR, p),) * 4)


TID_SCENARIOS = [
    _ramp_steer("tid_ramp_steer_high_mu", 0, 80.0 * KMH, 0.9, 0.09),
    _ramp_steer("tid_ramp_steer_low_mu", 1, 80.0 * KMH, 0.3, 0.03),
    TidScenario(
        "tid_sine_steer", 2,
        f"sine steer: v0 = 80 km/h, mu = 0.85, delta = 0.05*sin(2*pi*{SINE_F:g}*t) rad, no "
        f"brake, no drive torque; truth tyres {_TEXT_TYRES}",
        80.0 * KMH, 10.0, _sine(0.05, SINE_F), 0.85),
    _dlc("tid_dlc_high_mu", 3, 80.0 * KMH, 1.0, 0.095),
    _dlc("tid_dlc_low_mu", 4, 60.0 * KMH, 0.3, 0.05),
    TidScenario(
        "tid_tyre_change", 5,
        f"tyre change mid-log: v0 = 90 km/h, mu = 0.85, delta = 0.05*sin(2*pi*{SINE_F:g}*t) "
        f"rad, no brake, no drive torque; truth tyres {_TEXT_TYRES} until t = {TC_T:g} s, "
        f"then front {FRONT_2.text()}; rear {REAR_2.text()}",
        90.0 * KMH, 16.0, _sine(0.05, SINE_F), 0.85,
        ((0.0, FRONT, REAR), (TC_T, FRONT_2, REAR_2))),
    TidScenario(
        "tid_straight", 6,
        f"straight driving: v0 = 80 km/h, mu = 0.85, delta = 0, no brake, no drive torque: "
        f"no lateral force, no tyre parameter observable; truth tyres {_TEXT_TYRES}",
        80.0 * KMH, 8.0, const(0.0), 0.85),
    _brake_in_turn("tid_brake_in_turn_high_mu", 7, 80.0 * KMH, BIT_HIGH),
    _brake_in_turn("tid_brake_in_turn_low_mu", 8, 80.0 * KMH, BIT_LOW),
]

TID_BY_NAME = {s.name: s for s in TID_SCENARIOS}
