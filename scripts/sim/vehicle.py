"""Reference vehicle dynamics (stands in for the paper's CarSim).

Planar two-track model, 7 DOF: body-axis velocities vx, vy, yaw rate r and the four wheel
spin speeds omega_i (order fl, fr, rl, rr), plus integrated kinematic states: distance
travelled along the CoG path s (the road friction map is indexed by it), heading psi and
global position X, Y (not logged; for plots).  ISO 8855 axes (x forward, y left, z up).

Kinematics, slips and loads are exactly MODEL.md section 3; tyre forces come from a truth
tyre of tyres.py.  Equations of motion (body axes; front forces rotated by delta):
    m (vx_dot - r vy) = sum Fbx,   m (vy_dot + r vx) = sum Fby
    J r_dot = sum (x_i Fby_i - y_i Fbx_i)
    Iw omega_dot_i = T_drive_i - kb_i p_i tanh(omega_i/brake_omega_eps) - R Fx_i
No aerodynamic drag, no rolling resistance (as the paper).

Road grade and bank (optional, ``road``; off by default, and then the code path and every
number are those of the flat road).  A road gives grade theta(s) and bank phi(s) as
functions of the CoG path distance s.  Sign conventions (ISO 8855 axes, x forward, y left,
z up; the body's x-y plane is the local road plane, x along the road):
    theta > 0  uphill: the road rises in the direction of travel (nose up).
    phi   > 0  the road rises to the LEFT (left wheels higher; a positive rotation about
               x, ISO roll sense): gravity pulls the car to the right (-y).
Gravity in body axes is then g_b = (-g sin(theta), -g sin(phi) cos(theta),
-g cos(phi) cos(theta)) (pitch theta, then roll phi).  The equations of motion become
    vx_dot = sum Fbx/m + r vy - g sin(theta)
    vy_dot = sum Fby/m - r vx - g sin(phi) cos(theta)
(no moment: gravity acts at the CoG), and the loads' static part is the normal component:
Fz_i = cos(theta) cos(phi) Fz0_i + Gx_i ax + Gy_i ay.  The logged ax, ay stay sum F/m: that
is the *specific force*, what an accelerometer fixed to the body measures, so
    ax_meas = (vx_dot - r vy) + g sin(theta)
    ay_meas = (vy_dot + r vx) + g sin(phi) cos(theta)
(a car held by its tyres on a bank, vy_dot = r = 0, reads ay = +g sin(phi): the tyres push
it up the slope, to the left).  Integrating ax, ay without removing gravity therefore
drifts.  The grade and bank are applied to the body as pitch and roll directly: the car's
heading relative to the road tangent (its sideslip, a few degrees) is neglected in the
projection, as are the pitch / roll rates of a changing grade (theta'(s)*v, the road's
curvature in the vertical plane) and any suspension roll or pitch; X, Y stay the
horizontal-plane integrals of the body velocities.

Low speed (optional, ``v_low`` [m/s]; off by default).  The slip denominators of MODEL.md
(max(|omega R|, |v_wx|, v_min) for kappa, |v_wx| for alpha) make the tyres infinitely stiff
as the car stops (the wheel-spin eigenvalue ~ -R^2*Cx*Fz/(Iw*v) leaves RK4's stability
region below ~0.6 m/s at 4 kHz, and alpha jumps to +-alpha_max).  With v_low set, both
denominators are floored at v_low:
    kappa = (omega R - v_wx) / max(|omega R|, |v_wx|, v_min, v_low)
    alpha = -atan2(v_wy, max(|v_wx|, v_low))
identical to MODEL.md above v_low, and below it a linear (viscous) tyre whose stiffness
per unit speed stays bounded (the usual low-speed regularisation, cf. a tyre relaxation
length): the car can creep and stop, the states decay smoothly to zero at standstill.  The
existing scenarios never set it (they stay above 4 m/s); the creep scenario uses 2 m/s,
where the spin eigenvalue is ~ -3600 1/s (h*lambda ~ 0.9 at 4 kHz).  Below v_low a log is
not model-matched with MODEL.md's slips (the metadata says sim_v_low).

Vertical loads use the quasi-static MODEL.md formula with the TRUE body accelerations of
the same instant, ax = sum Fbx/m and ay = sum Fby/m (what an accelerometer at the CoG
measures; not vx_dot).  Loads depend on forces which depend on loads: the algebraic loop
is solved at every derivative evaluation.  Both truth tyres give forces proportional to Fz
at fixed slip and mu (F_i = Fz_i * f_i), so ax, ay are a piecewise-linear function of
themselves (piecewise through the Fz >= 0 clamp); the fixed point is found by Newton
iteration with an active set for the clamp (exact in one step while the clamp set does
not change), iterated until the change is below 1e-12 relative (floor 1 m/s^2), then
checked by one plain fixed-point evaluation.  The logged ax, ay are sum F/m evaluated with
the converged loads, so an estimator that computes loads from the logged ax, ay with the
MODEL.md formula reproduces the forces (and ax, ay, r_dot) to rounding.

Tyre per wheel and over time (optional, ``tyre_map``; off by default, and then every wheel
uses ``p``'s tyre parameters as always).  tyre_map(t) returns four Params, one per wheel
(fl, fr, rl, rr), whose tyre keys (cx, cy, mf_*, ...) the truth tyre of that wheel uses at
time t: front and rear tyres that differ, or a tyre whose curve changes mid-log (issue 20's
tyre identification scenarios, scripts/data/make_tyre_id_scenarios.py).  The vehicle keys
(m, Lf, ..., v_min, alpha_max) are always ``p``'s.  A change in time is a step of the
right-hand side; a scenario puts it on a log instant.

Integration: classical RK4 with a fixed sub-step (Params-independent setting `rate`,
default 4 kHz = 40 sub-steps per 0.01 s log step).  The wheel-spin mode has an
eigenvalue of about -R^2*Cx*Fz/(Iw*v) (~ -1900 1/s at 4 m/s on mu 0.85), which RK4 at
4 kHz integrates stably (h*lambda ~ 0.5) and accurately.  Deterministic: pure Python
floats, no threads, no randomness.  Closed-loop inputs (ABS, driver steering; control.py)
are discrete controllers updated at sub-step boundaries and held in between, so RK4 only
ever integrates smooth right-hand sides.

Driving resistances (optional, ``ext``; off by default, and then the code path and every
number are those above).  The mass and grade scenarios (mass_grade_scenarios.py, and there
the observer scenarios' _res twins through ObserverScenario.res) add the
forces of a longitudinal model that the tyres do not carry: rolling resistance and
aerodynamic drag, with a wind.  ``ext(t, vx, theta)`` returns one body-x force [N] (negative
resists) acting at the CoG; it enters the fixed point of the accelerations as a constant
term, m*ax = sum Fz_i(a)*b_x,i + F_ext, so ax stays the specific force (the drag is a
non-gravitational force, an accelerometer measures it) and the loads see it through ax.
The rolling resistance is applied to the body, not as a moment at each wheel: the wheel
slips are then those of the drive torque alone (MODEL.md's tyres have no rolling
resistance), and the longitudinal balance is the same.
"""

from dataclasses import dataclass, fields
from math import atan2, cos, hypot, sin, tanh

from .tyres import TRUTH_TYRES

__all__ = ["Params", "ESTIMATOR_KEYS", "SIM_KEYS", "MF_KEYS", "wheel_geometry",
           "wheel_slips", "load_coefficients", "loads", "Vehicle", "simulate"]


@dataclass(frozen=True)
class Params:
    """Vehicle, tyre and simulator parameters (MODEL.md section 2 defaults)."""
    m: float = 1830.0        # kg
    Lf: float = 1.40         # m, CoG to front axle
    Lr: float = 1.65         # m, CoG to rear axle
    Bf: float = 1.60         # m, front track
    Br: float = 1.60         # m, rear track
    R: float = 0.325         # m, effective rolling radius
    J: float = 3234.0        # kg m^2, yaw inertia
    hg: float = 0.54         # m, CoG height
    g: float = 9.81          # m/s^2
    Cx_n: float = 20.0       # 1/rad, paper-mode normalised longitudinal stiffness
    Cy_n: float = 15.0       # 1/rad, paper-mode normalised cornering stiffness
    cx: float = 20.0         # absolute-mode / MF longitudinal stiffness per unit Fz
    cy: float = 15.0         # absolute-mode / MF cornering stiffness per unit Fz
    eps: float = 0.015       # s/m, Dugoff velocity-reduction factor
    v_min: float = 0.5       # m/s, slip denominator guard
    alpha_max: float = 1.4   # rad, slip angle bound
    kb_f: float = 300.0      # N m / MPa, front brake gain per wheel
    kb_r: float = 180.0      # N m / MPa, rear brake gain per wheel
    Iw: float = 1.2          # kg m^2, wheel spin inertia
    brake_omega_eps: float = 0.5  # rad/s, brake torque = kb p tanh(omega/brake_omega_eps)
    mf_Cx: float = 1.65      # MF truth shape factors (tyres.py)
    mf_Ex: float = 0.0
    mf_Cy: float = 1.3
    mf_Ey: float = -1.0

    def items(self, keys):
        return [(k, getattr(self, k)) for k in keys]


# Keys the estimator reads from a log's metadata (DATA.md), then simulator-only information.
ESTIMATOR_KEYS = ("m", "Lf", "Lr", "Bf", "Br", "R", "J", "hg", "g", "Cx_n", "Cy_n",
                  "cx", "cy", "eps", "v_min", "alpha_max")
SIM_KEYS = ("kb_f", "kb_r", "Iw", "brake_omega_eps")
MF_KEYS = ("mf_Cx", "mf_Ex", "mf_Cy", "mf_Ey")
assert set(ESTIMATOR_KEYS + SIM_KEYS + MF_KEYS) == {f.name for f in fields(Params)}


def wheel_geometry(p):
    """Wheel positions (x_i, y_i) relative to the CoG, order fl, fr, rl, rr."""
    return ((p.Lf, 0.5 * p.Bf), (p.Lf, -0.5 * p.Bf), (-p.Lr, 0.5 * p.Br), (-p.Lr, -0.5 * p.Br))


def wheel_slips(p, delta, vx, vy, r, omega, v_low=None):
    """MODEL.md section 3 for one sample: returns (v_wx[4], kappa[4], alpha[4]).
    v_low: optional low-speed floor of the slip denominators (module docstring)."""
    c, s = cos(delta), sin(delta)
    vwx_all, kap_all, alp_all = [], [], []
    for i, (xi, yi) in enumerate(wheel_geometry(p)):
        vxi = vx - r * yi
        vyi = vy + r * xi
        if i < 2:
            vwx = vxi * c + vyi * s
            vwy = -vxi * s + vyi * c
        else:
            vwx, vwy = vxi, vyi
        if v_low is None:
            alpha = -atan2(vwy, abs(vwx))
        else:
            alpha = -atan2(vwy, max(abs(vwx), v_low))
        if alpha > p.alpha_max:
            alpha = p.alpha_max
        elif alpha < -p.alpha_max:
            alpha = -p.alpha_max
        wr = omega[i] * p.R
        if v_low is None:
            kappa = (wr - vwx) / max(abs(wr), abs(vwx), p.v_min)
        else:
            kappa = (wr - vwx) / max(abs(wr), abs(vwx), p.v_min, v_low)
        if kappa > 1.0:
            kappa = 1.0
        elif kappa < -1.0:
            kappa = -1.0
        vwx_all.append(vwx)
        kap_all.append(kappa)
        alp_all.append(alpha)
    return vwx_all, kap_all, alp_all


def load_coefficients(p):
    """Fz_i = Fz0_i + Gx_i*ax + Gy_i*ay (before the >= 0 clamp), MODEL.md section 3."""
    La = p.Lf + p.Lr
    f0 = p.m * p.g * p.Lr / (2.0 * La)
    r0 = p.m * p.g * p.Lf / (2.0 * La)
    gx = p.m * p.hg / (2.0 * La)
    gyf = p.m * p.hg * p.Lr / (La * p.Bf)
    gyr = p.m * p.hg * p.Lf / (La * p.Br)
    return (f0, f0, r0, r0), (-gx, -gx, gx, gx), (-gyf, gyf, -gyr, gyr)


def loads(p, ax, ay):
    Fz0, Gx, Gy = load_coefficients(p)
    return [max(0.0, Fz0[i] + Gx[i] * ax + Gy[i] * ay) for i in range(4)]


class Vehicle:
    """Derivative function of the 11-element state
    [vx, vy, r, omega_fl, omega_fr, omega_rl, omega_rr, s, psi, X, Y]."""

    def __init__(self, p, tyre, inputs, mu_map, road=None, v_low=None, tyre_map=None, ext=None):
        """inputs(t) -> (delta, (p_fl..p_rr) MPa, (T_fl..T_rr) N m);
        mu_map(x_road, left) -> mu under a wheel at road position x_road (CoG path
        distance + the wheel's x offset) on the left (True) or right (False) side;
        road: None (flat) or an object with grade(s), bank(s) [rad] of the CoG path
        distance s (module docstring for the signs); v_low: low-speed slip floor or None;
        tyre_map: None (p's tyre on every wheel) or t -> four Params (module docstring);
        ext: None or ext(t, vx, theta) -> external body-x force [N] (driving resistances)."""
        self.tyre_map = tyre_map
        self.road = road
        self.ext = ext
        self.v_low = v_low
        self.p = p
        self.tyre_fn = TRUTH_TYRES[tyre]
        self.inputs = inputs
        self.mu_map = mu_map
        self.geom = wheel_geometry(p)
        self.Fz0, self.Gx, self.Gy = load_coefficients(p)
        self.kb = (p.kb_f, p.kb_f, p.kb_r, p.kb_r)
        self.a_guess = (0.0, 0.0)

    def mu_at(self, s):
        return [self.mu_map(s + xi, yi > 0.0) for (xi, yi) in self.geom]

    def solve_accelerations(self, bx, by, Fz0=None, fx_ext=None):
        """Fixed point a = sum_i Fz_i(a) * b_i / m (b_i = body-axis force per unit load);
        Fz0: static loads (default the flat road's); fx_ext: external body-x force [N]
        added to m*ax (None: none, the arithmetic of the model without it)."""
        p = self.p
        Gx, Gy = self.Gx, self.Gy
        if Fz0 is None:
            Fz0 = self.Fz0
        ax, ay = self.a_guess
        for _ in range(50):
            A11 = A22 = p.m
            A12 = A21 = b1 = b2 = 0.0
            for i in range(4):
                if Fz0[i] + Gx[i] * ax + Gy[i] * ay > 0.0:
                    A11 -= Gx[i] * bx[i]
                    A12 -= Gy[i] * bx[i]
                    A21 -= Gx[i] * by[i]
                    A22 -= Gy[i] * by[i]
                    b1 += Fz0[i] * bx[i]
                    b2 += Fz0[i] * by[i]
            if fx_ext is not None:
                b1 += fx_ext
            det = A11 * A22 - A12 * A21
            nax = (b1 * A22 - A12 * b2) / det
            nay = (A11 * b2 - A21 * b1) / det
            change = max(abs(nax - ax), abs(nay - ay))
            ax, ay = nax, nay
            if change <= 1e-12 * max(1.0, abs(ax), abs(ay)):
                break
        else:
            raise RuntimeError("load/force fixed point did not converge")
        self.a_guess = (ax, ay)
        return ax, ay

    def __call__(self, t, y, aux=False):
        p = self.p
        vx, vy, r = y[0], y[1], y[2]
        omega = y[3:7]
        s, psi = y[7], y[8]
        delta, pres, tdrive = self.inputs(t)
        mu = self.mu_at(s)
        vwx, kappa, alpha = wheel_slips(p, delta, vx, vy, r, omega, self.v_low)
        c, sn = cos(delta), sin(delta)
        fx, fy, bx, by = [], [], [], []
        tp = (p, p, p, p) if self.tyre_map is None else self.tyre_map(t)
        for i in range(4):
            ux, uy = self.tyre_fn(kappa[i], alpha[i], abs(vwx[i]), mu[i], tp[i])
            fx.append(ux)
            fy.append(uy)
            if i < 2:
                bx.append(ux * c - uy * sn)
                by.append(ux * sn + uy * c)
            else:
                bx.append(ux)
                by.append(uy)
        fx_ext = None
        if self.road is None:
            theta = phi = 0.0
            Fz0 = self.Fz0
            if self.ext is not None:
                fx_ext = self.ext(t, vx, theta)
            ax_s, ay_s = self.solve_accelerations(bx, by, None, fx_ext)
        else:
            theta, phi = self.road.grade(s), self.road.bank(s)
            cn = cos(theta) * cos(phi)
            Fz0 = [cn * f for f in self.Fz0]
            if self.ext is not None:
                fx_ext = self.ext(t, vx, theta)
            ax_s, ay_s = self.solve_accelerations(bx, by, Fz0, fx_ext)
        Fz = [max(0.0, Fz0[i] + self.Gx[i] * ax_s + self.Gy[i] * ay_s) for i in range(4)]
        sum_x = sum_y = mz = 0.0
        for i, (xi, yi) in enumerate(self.geom):
            fbx = Fz[i] * bx[i]
            fby = Fz[i] * by[i]
            sum_x += fbx
            sum_y += fby
            mz += xi * fby - yi * fbx
        if fx_ext is not None:
            sum_x += fx_ext
        ax = sum_x / p.m
        ay = sum_y / p.m
        if abs(ax - ax_s) > 1e-9 * max(1.0, abs(ax)) or abs(ay - ay_s) > 1e-9 * max(1.0, abs(ay)):
            raise RuntimeError("load/force fixed point check failed")
        r_dot = mz / p.J
        if self.road is None:
            dy = [ax + r * vy, ay - r * vx, r_dot]
        else:
            dy = [ax + r * vy - p.g * sin(theta), ay - r * vx - p.g * sin(phi) * cos(theta),
                  r_dot]
        for i in range(4):
            tb = self.kb[i] * pres[i] * tanh(omega[i] / p.brake_omega_eps)
            dy.append((tdrive[i] - tb - p.R * Fz[i] * fx[i]) / p.Iw)
        dy.append(hypot(vx, vy))
        dy.append(r)
        dy.append(vx * cos(psi) - vy * sin(psi))
        dy.append(vx * sin(psi) + vy * cos(psi))
        if not aux:
            return dy
        info = dict(delta=delta, ax=ax, ay=ay, yaw_acc=r_dot, mu=mu, kappa=kappa,
                    alpha=alpha, vwx=vwx, Fz=Fz, Fx=[Fz[i] * fx[i] for i in range(4)],
                    Fy=[Fz[i] * fy[i] for i in range(4)], pressure=list(pres),
                    drive=list(tdrive), vx_dot=dy[0], vy_dot=dy[1], grade=theta, bank=phi,
                    fx_ext=0.0 if fx_ext is None else fx_ext)
        return dy, info


LOG_SCALARS = ("t", "delta", "vx", "vy", "yaw_rate", "yaw_acc", "ax", "ay", "s", "psi", "X", "Y",
               "vx_dot", "vy_dot", "grade", "bank")
LOG_WHEEL = ("omega", "mu", "kappa", "alpha", "vwx", "Fz", "Fx", "Fy", "pressure", "drive")


def simulate(inputs, mu_map, v0, duration, p=None, tyre="dugoff", dt_log=0.01, rate=4000,
             road=None, v_low=None, tyre_map=None, ext=None):
    """Integrate from straight running at v0 (free-rolling wheels, kappa = 0) and return a
    dict of numpy arrays sampled every dt_log: scalars of LOG_SCALARS (shape (N,)) and
    per-wheel arrays of LOG_WHEEL (shape (N, 4)), all instantaneous values of the same
    derivative evaluation at each logged instant.

    inputs is a function of time, or a closed-loop controller (control.ClosedLoopInputs:
    anything with an ``update(t, y)`` method and a ``rate`` in Hz); a controller is updated
    at every multiple of 1/rate (before that instant's derivative evaluation, so also
    before each logged evaluation) and holds its outputs in between.  road, v_low: see
    Vehicle (both off by default); tyre_map: per-wheel tyre over time (Vehicle, off by
    default); ext: the driving resistances (Vehicle, off by default; when given, the output
    also has "fx_ext", the force at each logged instant).  vx_dot, vy_dot are the body-axis
    velocity derivatives (kinematic, gravity included), grade and bank the road's at the CoG."""
    import numpy as np
    p = Params() if p is None else p
    veh = Vehicle(p, tyre, inputs, mu_map, road, v_low, tyre_map, ext)
    n_log = int(round(duration / dt_log)) + 1
    nsub = int(round(rate * dt_log))
    if nsub < 1 or abs(nsub - rate * dt_log) > 1e-9:
        raise ValueError("rate must be a multiple of 1/dt_log")
    h = dt_log / nsub
    ctrl = inputs if hasattr(inputs, "update") else None
    if ctrl is not None:
        every = int(round(rate / ctrl.rate))
        if every < 1 or abs(every * ctrl.rate - rate) > 1e-9:
            raise ValueError("rate must be a multiple of the controller rate")
    log_rate = round(1.0 / dt_log)
    exact_rate = abs(log_rate * dt_log - 1.0) < 1e-12  # t_k = k/100 prints as 0.03, not
    delta0 = inputs(0.0)[0]
    vwx0, _, _ = wheel_slips(p, delta0, v0, 0.0, 0.0, [0.0] * 4, v_low)
    y = [v0, 0.0, 0.0] + [v / p.R for v in vwx0] + [0.0, 0.0, 0.0, 0.0]
    out = {k: np.empty(n_log) for k in LOG_SCALARS}
    out.update({k: np.empty((n_log, 4)) for k in LOG_WHEEL})
    if ext is not None:
        out["fx_ext"] = np.empty(n_log)
    n = len(y)
    for k in range(n_log):
        t0 = k / log_rate if exact_rate else k * dt_log  # 0.030000000000000002
        if ctrl is not None and (k * nsub) % every == 0:
            ctrl.update(t0, y)
        k1, info = veh(t0, y, aux=True)
        out["t"][k] = t0
        out["vx"][k], out["vy"][k], out["yaw_rate"][k] = y[0], y[1], y[2]
        out["omega"][k] = y[3:7]
        out["s"][k], out["psi"][k], out["X"][k], out["Y"][k] = y[7], y[8], y[9], y[10]
        for key in ("delta", "ax", "ay", "yaw_acc", "vx_dot", "vy_dot", "grade", "bank"):
            out[key][k] = info[key]
        for key in LOG_WHEEL[1:]:
            out[key][k] = info[key]
        if ext is not None:
            out["fx_ext"][k] = info["fx_ext"]
        if k == n_log - 1:
            break
        for j in range(nsub):
            t = t0 + j * h
            if j > 0:
                if ctrl is not None and (k * nsub + j) % every == 0:
                    ctrl.update(t, y)
                k1 = veh(t, y)
            y2 = [y[i] + 0.5 * h * k1[i] for i in range(n)]
            k2 = veh(t + 0.5 * h, y2)
            y3 = [y[i] + 0.5 * h * k2[i] for i in range(n)]
            k3 = veh(t + 0.5 * h, y3)
            y4 = [y[i] + h * k3[i] for i in range(n)]
            k4 = veh(t + h, y4)
            y = [y[i] + (h / 6.0) * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]) for i in range(n)]
    return out
