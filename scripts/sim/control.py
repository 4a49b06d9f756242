"""Closed-loop inputs of the reference simulator: per-wheel ABS and a driver yaw controller.

A scenario's driver inputs are functions of time (scenarios.py).  For near-limit braking the
driver's wheel-cylinder pressure would lock the wheels, so closed-loop scenarios pass it
through a per-wheel anti-lock controller, and split-mu braking adds a driver who
counter-steers against the yaw the asymmetric brake forces cause.  Both are discrete-time
controllers, as in a real vehicle, deterministic and stateful: one fresh
:class:`ClosedLoopInputs` per simulation (Scenario.make_inputs()).

Timing.  The controller runs at ``rate`` (default 1 kHz; the simulator's integration rate
must be a multiple of it).  At every tick, before the derivative evaluations of the next
integration sub-steps, :meth:`ClosedLoopInputs.update` reads the true state and sets the
inputs (delta, four pressures, four drive torques), which are then held constant until the
next tick (zero-order hold, valve / actuator latching).  Ticks coincide with sub-step
boundaries and with every logged instant, so the logged delta is exactly the one the
vehicle saw, and doubling the integration rate does not move the ticks (the closed loop
converges like the open loop does).  Because the pressure is an *input* of the tyre-road
model (it does not appear in MODEL.md sections 3-5), a closed-loop log is model-matched
exactly like an open-loop one.

ABS (per wheel, independent control on all four wheels, no select-low):
    Slip kappa_i from the true state with MODEL.md section 3 (a real ECU estimates a
    reference speed from the wheel speeds; the simulator uses the true one).
    e = kappa_i - kappa_target, kappa_target = -0.10 (braking slip 10 %: the flat top of
    the Dugoff curve, utilisation ~0.85-0.88; the peak of the mf tyre at mu 0.85, and just
    past its peak at mu 0.3, where it gives ~0.81).
    Inactive: the wheel gets the driver's pressure p_d(t).  It activates when the slip
    exceeds the target (e < 0) while the driver brakes; the integrator starts at the
    pressure currently applied (bumpless).  Active: PI slip control
        I <- clip(I + Ki*e*T, 0, p_d),   p_cmd = clip(I + Kp*e, 0, p_d)
    (the applied pressure never exceeds the driver's).  It deactivates when the PI output
    is no longer below the driver's pressure (p_cmd = p_d and e >= 0: the driver is braking
    less than the road allows, e.g. on release) or the wheel is slower than v_off = 2 m/s.
    Gain scheduling: around the target the tyre force barely changes with slip (near the
    peak), so the wheel is an integrator from pressure to slip with gain
    b = R*kb_i/(Iw*v_wx,i) [1/(MPa s)]; Kp = kp_n/b, Ki = ki_n/b give the same closed loop
    at every speed and on front and rear (kb_f, kb_r): kp_n = 60 1/s, ki_n = 900 1/s^2
    (natural frequency 30 rad/s, damping 1).  The tyre's own slope adds damping below
    the peak and removes some past it (mf at mu 0.3: about -260/v 1/s, well inside 60).
    Hydraulics: the applied pressure moves towards p_cmd at most at the build rate
    60 MPa/s and the dump rate 200 MPa/s (one step per tick).
    The result is a steady slip near the target on every wheel (no lock, no controller
    limit cycle; the first activation and a friction drop give one damped overshoot).

Driver yaw controller (optional, split-mu):
    delta = delta_d(t) - k_r*r - k_psi*psi (psi the heading, the integral of r, so this is
    PI control of the yaw rate to zero), rate-limited to 0.5 rad/s and clipped to
    |delta| <= 0.15 rad (road-wheel angle).
"""

from .vehicle import wheel_slips

__all__ = ["AbsConfig", "YawConfig", "ClosedLoopInputs"]

CTRL_RATE = 1000  # Hz


class AbsConfig:
    """ABS tuning (see the module docstring).  Plain attributes, all SI/MPa."""

    def __init__(self, kappa_target=-0.10, kp_n=60.0, ki_n=900.0, build_rate=60.0,
                 dump_rate=200.0, v_off=2.0):
        self.kappa_target = kappa_target
        self.kp_n = kp_n
        self.ki_n = ki_n
        self.build_rate = build_rate
        self.dump_rate = dump_rate
        self.v_off = v_off

    def text(self):
        return (f"ABS active on every wheel (slip target {self.kappa_target:g}, PI, "
                f"build {self.build_rate:g} / dump {self.dump_rate:g} MPa/s)")


class YawConfig:
    """Driver yaw-rate controller gains and limits."""

    def __init__(self, k_r=0.5, k_psi=1.0, rate_max=0.5, delta_max=0.15):
        self.k_r = k_r
        self.k_psi = k_psi
        self.rate_max = rate_max
        self.delta_max = delta_max

    def text(self):
        return (f"driver counter-steers: delta = -{self.k_r:g}*r - {self.k_psi:g}*psi, "
                f"<= {self.rate_max:g} rad/s, |delta| <= {self.delta_max:g} rad")


def _clip(x, lo, hi):
    return lo if x < lo else hi if x > hi else x


class ClosedLoopInputs:
    """inputs(t) for vehicle.Vehicle with controller state; simulate() calls update() at
    every controller tick (attribute ``rate``, Hz) with the state vector y."""

    def __init__(self, p, steer, pressure, drive, abs_cfg=None, yaw_cfg=None,
                 rate=CTRL_RATE):
        self.p = p
        self.steer, self.pressure, self.drive = steer, pressure, drive
        self.abs_cfg, self.yaw_cfg = abs_cfg, yaw_cfg
        self.rate = rate
        self.T = 1.0 / rate
        self.kb = (p.kb_f, p.kb_f, p.kb_r, p.kb_r)
        self.delta = float(steer(0.0))
        self.pw = [float(v) for v in pressure(0.0)]   # applied wheel-cylinder pressures
        self.tdrive = tuple(float(v) for v in drive(0.0))
        self.active = [False] * 4
        self.integ = [0.0] * 4
        self.n_active_ticks = [0] * 4   # statistics (tests)

    def __call__(self, t):
        return self.delta, tuple(self.pw), self.tdrive

    def update(self, t, y):
        p, T = self.p, self.T
        vx, vy, r = y[0], y[1], y[2]
        omega = y[3:7]
        delta = float(self.steer(t))
        yc = self.yaw_cfg
        if yc is not None:
            want = delta - yc.k_r * r - yc.k_psi * y[8]
            step = _clip(want - self.delta, -yc.rate_max * T, yc.rate_max * T)
            delta = _clip(self.delta + step, -yc.delta_max, yc.delta_max)
        self.delta = delta
        self.tdrive = tuple(float(v) for v in self.drive(t))
        pd_all = self.pressure(t)
        ac = self.abs_cfg
        if ac is None:
            self.pw = [float(v) for v in pd_all]
            return
        vwx, kappa, _ = wheel_slips(p, delta, vx, vy, r, omega)
        self._apply_abs(pd_all, vwx, kappa)

    def _apply_abs(self, pd_all, vwx, kappa):
        """One ABS tick on the driver's pressures pd_all (module docstring)."""
        p, T, ac = self.p, self.T, self.abs_cfg
        for i in range(4):
            pd = float(pd_all[i])
            v = abs(vwx[i])
            e = kappa[i] - ac.kappa_target
            cmd = pd
            if v < ac.v_off or pd <= 0.0:
                self.active[i] = False
            else:
                if not self.active[i] and e < 0.0:
                    self.active[i] = True
                    self.integ[i] = min(self.pw[i], pd)
                if self.active[i]:
                    b = p.R * self.kb[i] / (p.Iw * v)
                    integ = _clip(self.integ[i] + (ac.ki_n / b) * e * T, 0.0, pd)
                    ps = integ + (ac.kp_n / b) * e
                    self.integ[i] = integ
                    if ps >= pd and e >= 0.0:
                        self.active[i] = False
                    else:
                        cmd = _clip(ps, 0.0, pd)
                        self.n_active_ticks[i] += 1
            dp = cmd - self.pw[i]
            if dp > ac.build_rate * T:
                dp = ac.build_rate * T
            elif dp < -ac.dump_rate * T:
                dp = -ac.dump_rate * T
            self.pw[i] += dp


# ---- observer scenarios (observer_scenarios.py): traction control, cruise and path control --
#
# Extensions used only by the observer scenarios; ClosedLoopInputs above only had its ABS tick
# moved into _apply_abs (the same operations in the same order), so the scenarios of
# scenarios.py integrate bit for bit as before.
#
# Drive layouts: the driver's torque request and the cruise controller's torque are split
# over the wheels by fixed fractions (DRIVE_SPLIT): fwd / rwd 1/2 per driven wheel, awd 1/4
# per wheel (a locked centre and open axle differentials idealised as fixed shares).
#
# TCS (traction control, per driven wheel, the mirror of the ABS above):
#     e = kappa_i - kappa_target, kappa_target = +0.15 (driving slip 15 %).  Inactive: the
#     wheel gets its requested torque T_d.  Activates when e > 0 while T_d > 0 (integrator
#     starts at the applied torque).  Active: PI on slip
#         I <- clip(I - Ki*e*T, 0, T_d),   T_cmd = clip(I - Kp*e, 0, T_d)
#     (never more than requested, never braking); deactivates when T_cmd = T_d and e <= 0,
#     or the wheel is slower than v_off.  Gain scheduling as the ABS: near the peak the wheel
#     integrates torque into slip with gain b = R/(Iw*v_wx) [1/(N m s)], Kp = kp_n/b,
#     Ki = ki_n/b, kp_n = 60 1/s, ki_n = 900 1/s^2.  Actuator (engine torque reduction and
#     brake intervention lumped): the applied torque moves towards T_cmd (T_d when inactive)
#     at most at rate_max = 6000 N m/s.
#
# Cruise control (SpeedConfig): a PI on the speed error e = v*(t) - hypot(vx, vy), total
# torque T = Kp*e + Ki*integral(e) clipped to [t_min, t_max] (negative = engine braking /
# recuperation; anti-windup by clamping the integrator), split by the drive layout and added
# to the driver's torque request.  v*(t) = None switches it off (torque 0, integrator reset).
# Gains: the car integrates torque into speed with gain 1/(R m) ~ 1/595 (m/s^2)/(N m), so
# Kp = 600 N m/(m/s) gives ~1 rad/s bandwidth, Ki = 300 N m/m.
#
# Path control (PathConfig): the driver follows a path of curvature c(t) [1/m] (positive =
# turning left): yaw-rate target r* = c*V, V = hypot(vx, vy); delta = (Lf+Lr)*c (kinematic
# feed-forward) + k_p*(r* - r) + k_i*integral(r* - r), rate-limited and clipped like the yaw
# controller, plus the open-loop steer(t) (driver corrections).  Steady state: r = c*V, a
# circle of radius 1/c whatever the understeer.


DRIVE_SPLIT = {"none": (0.0, 0.0, 0.0, 0.0), "fwd": (0.5, 0.5, 0.0, 0.0),
               "rwd": (0.0, 0.0, 0.5, 0.5), "awd": (0.25, 0.25, 0.25, 0.25)}


class TcsConfig:
    """Traction-control tuning (see above).  SI units."""

    def __init__(self, kappa_target=0.15, kp_n=60.0, ki_n=900.0, rate_max=6000.0, v_off=1.0):
        self.kappa_target = kappa_target
        self.kp_n = kp_n
        self.ki_n = ki_n
        self.rate_max = rate_max
        self.v_off = v_off

    def text(self):
        return (f"TCS active on the driven wheels (slip target {self.kappa_target:g}, PI, "
                f"<= {self.rate_max:g} N m/s)")


class SpeedConfig:
    """Cruise control: target speed v_target(t) [m/s] (or None: off)."""

    def __init__(self, v_target, kp=600.0, ki=300.0, t_min=-1000.0, t_max=2000.0):
        self.v_target = v_target
        self.kp, self.ki = kp, ki
        self.t_min, self.t_max = t_min, t_max

    def text(self):
        return (f"cruise control PI (Kp {self.kp:g} N m s/m, Ki {self.ki:g} N m/m, "
                f"torque in [{self.t_min:g}, {self.t_max:g}] N m)")


class PathConfig:
    """Driver path follower: target curvature curvature(t) [1/m]."""

    def __init__(self, curvature, k_p=0.05, k_i=0.5, rate_max=0.5, delta_max=0.3):
        self.curvature = curvature
        self.k_p, self.k_i = k_p, k_i
        self.rate_max, self.delta_max = rate_max, delta_max

    def text(self):
        return (f"driver follows the path curvature: delta = L*c + {self.k_p:g}*(c*V - r) + "
                f"{self.k_i:g}*int(c*V - r), <= {self.rate_max:g} rad/s, |delta| <= "
                f"{self.delta_max:g} rad")


class ObserverInputs(ClosedLoopInputs):
    """ClosedLoopInputs plus drive layout, TCS, cruise and path control (above).  Order at a
    tick: steering (path / yaw controller on steer(t)), drive torque (driver + cruise, split,
    then TCS), brake pressure (driver, then ABS as in ClosedLoopInputs)."""

    def __init__(self, p, steer, pressure, drive, abs_cfg=None, yaw_cfg=None, tcs_cfg=None,
                 speed_cfg=None, path_cfg=None, layout="fwd", v_low=None, rate=CTRL_RATE):
        super().__init__(p, steer, pressure, drive, abs_cfg, yaw_cfg, rate)
        self.tcs_cfg, self.speed_cfg, self.path_cfg = tcs_cfg, speed_cfg, path_cfg
        self.split = DRIVE_SPLIT[layout]
        self.v_low = v_low
        self.tw = list(self.tdrive)            # applied drive torques
        self.tcs_active = [False] * 4
        self.tcs_integ = [0.0] * 4
        self.n_tcs_ticks = [0] * 4
        self.speed_integ = 0.0
        self.path_integ = 0.0
        self.tdrive = tuple(self.tw)

    def _steer(self, t, y):
        delta = float(self.steer(t))
        pc, yc, T = self.path_cfg, self.yaw_cfg, self.T
        r = y[2]
        if pc is not None:
            c = float(pc.curvature(t))
            err = c * (y[0] * y[0] + y[1] * y[1]) ** 0.5 - r
            self.path_integ += err * T
            want = delta + (self.p.Lf + self.p.Lr) * c + pc.k_p * err + pc.k_i * self.path_integ
            rate_max, delta_max = pc.rate_max, pc.delta_max
        elif yc is not None:
            want = delta - yc.k_r * r - yc.k_psi * y[8]
            rate_max, delta_max = yc.rate_max, yc.delta_max
        else:
            return delta
        step = _clip(want - self.delta, -rate_max * T, rate_max * T)
        return _clip(self.delta + step, -delta_max, delta_max)

    def _drive(self, t, y, kappa, vwx):
        req = [float(v) for v in self.drive(t)]
        sc = self.speed_cfg
        if sc is not None:
            vt = sc.v_target(t)
            if vt is None:
                self.speed_integ = 0.0
            else:
                e = float(vt) - (y[0] * y[0] + y[1] * y[1]) ** 0.5
                integ = _clip(self.speed_integ + sc.ki * e * self.T, sc.t_min, sc.t_max)
                self.speed_integ = integ
                total = _clip(integ + sc.kp * e, sc.t_min, sc.t_max)
                req = [req[i] + self.split[i] * total for i in range(4)]
        tc = self.tcs_cfg
        if tc is None:
            self.tw = req
            return
        p, T = self.p, self.T
        for i in range(4):
            td = req[i]
            v = abs(vwx[i])
            e = kappa[i] - tc.kappa_target
            cmd = td
            if v < tc.v_off or td <= 0.0:
                self.tcs_active[i] = False
            else:
                if not self.tcs_active[i] and e > 0.0:
                    self.tcs_active[i] = True
                    self.tcs_integ[i] = min(self.tw[i], td)
                if self.tcs_active[i]:
                    b = p.R / (p.Iw * v)
                    integ = _clip(self.tcs_integ[i] - (tc.ki_n / b) * e * T, 0.0, td)
                    ts = integ - (tc.kp_n / b) * e
                    self.tcs_integ[i] = integ
                    if ts >= td and e <= 0.0:
                        self.tcs_active[i] = False
                    else:
                        cmd = _clip(ts, 0.0, td)
                        self.n_tcs_ticks[i] += 1
            self.tw[i] += _clip(cmd - self.tw[i], -tc.rate_max * T, tc.rate_max * T)

    def update(self, t, y):
        p = self.p
        vx, vy, r = y[0], y[1], y[2]
        self.delta = self._steer(t, y)
        vwx, kappa, _ = wheel_slips(p, self.delta, vx, vy, r, y[3:7], self.v_low)
        self._drive(t, y, kappa, vwx)
        self.tdrive = tuple(self.tw)
        pd_all = self.pressure(t)
        if self.abs_cfg is None:
            self.pw = [float(v) for v in pd_all]
            return
        self._apply_abs(pd_all, vwx, kappa)
