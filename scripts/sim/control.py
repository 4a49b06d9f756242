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
