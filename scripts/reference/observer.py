"""Reference velocity and sideslip observer (docs/OBSERVER.md), float64, scalar arithmetic.

Independent of the C library: written from docs/OBSERVER.md only, in plain Python floats
(no BLAS, no vectorisation), so the C double build can be compared with it to 1e-9.

    obs = Observer(params)            # params: vehicle keys of params.DEFAULTS + OBS_DEFAULTS
    out = obs.step(sample)            # sample: dict of the ESC inputs (Sample fields)
    tab = run(log_columns, params)    # a whole sensor log -> dict of output arrays

Every number and step of the page appears here in the same order; the section numbers in the
comments are the page's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

# §2 The observer's parameters (keys of a parameter file), with their defaults.
OBS_DEFAULTS: dict[str, float] = {
    "obs_driven": 3.0,          # driven wheels, bit mask fl=1 fr=2 rl=4 rr=8 (3: front drive)
    "obs_lat_every": 8.0,       # the model's rows (§4.2) every obs_lat_every-th step (8; 1: every)
    "obs_dt_min": 0.001,        # shortest accepted sample period, s
    "obs_dt_max": 0.1,          # longest accepted sample period, s
    "obs_q_jerk": 0.5,          # yaw-jerk density of the yaw-rate differentiator, rad/s^3 sqrt(s)
    "obs_sd_r": 0.005,          # yaw-rate sensor noise sd, rad/s
    "obs_sd_ax": 0.05,          # ax sensor noise sd per sample, m/s^2
    "obs_q_bx": 0.005,          # random walk of the longitudinal offset, m/s^2 per sqrt(s)
    "obs_ay_turn": 1.0,         # a turn: |ay| at least this, m/s^2 (0: off)
    "obs_q_bx_turn": 0.03,      # random walk of b_x in a turn while not braking
    "obs_sd_wheel": 0.05,       # wheel reference noise sd, m/s
    "obs_sd_wheel_rel": 0.005,  # wheel reference error relative to speed (radius, slip)
    "obs_k_gate": 3.0,          # plausibility gate on a wheel, in sd
    "obs_k_agree": 3.0,         # wheels this close (in sd) agree: re-acquired outside the gate
    "obs_v_stand": 0.3,         # every wheel below this: standing, m/s
    "obs_q_vx_brake": 0.0,      # growth of vx's sd while braking without a wheel, m/s per sqrt(s)
    "obs_ax_brake_on": 0.5,     # deceleration above which the car is braking, m/s^2
    "obs_ax_drive_on": 0.5,     # acceleration above which the car is driving, m/s^2
    "obs_p_brake_on": 0.2,      # brake pressure above which the car is braking, MPa
    "obs_torque_on": 50.0,      # drive torque above which a wheel is driven, N m
    "obs_sd_ay": 0.05,          # ay sensor noise sd per sample, m/s^2
    "obs_q_by": 0.05,           # random walk of the lateral offset (bias, bank), m/s^2 per sqrt(s)
    "obs_sd_model_ay": 0.3,     # single-track model error, m/s^2
    "obs_model_ay_rel": 0.15,   # model error relative to |ay| (0.1 before 2026-12-07)
    "obs_sd_model_rdot": 0.0,   # model error of the yaw acceleration, rad/s^2 (0: row off)
    "obs_v_lat_min": 3.0,       # below this vx, vy follows the rear-axle kinematics, m/s
    "obs_sd_lowspeed": 0.1,     # sd of the low-speed kinematic vy, m/s
    "obs_mu_default": 1.0,      # friction the model uses while none is supplied
    "obs_sd_mu_default": 0.3,   # its sd
    "obs_mu_margin": 0.1,       # the measured ay raises the model's friction to (1 + margin) |ay| / g
    "obs_sd_vydot": 1.0,        # the lateral acceleration of the sideslip, v-dot_y, as noise, m/s^2
    "obs_vydot_rdot": 15.0,     # its growth with |r-dot|, m/s^2 per rad/s^2
    "obs_vydot_rerr": 25.0,     # its growth with max(0, |r| - |vx delta / L|) at vx >= v_lat_min
                                # (the car sliding out), m/s^2 per rad/s (0: off, <= 100)
    "obs_sd_vx0": 1.0,          # initial sd of vx, m/s
    "obs_sd_bx0": 0.3,          # initial sd of the longitudinal offset, m/s^2
    "obs_sd_vy0": 0.3,          # initial sd of vy, m/s
    "obs_sd_by0": 0.1,          # initial sd of the lateral offset, m/s^2
    "obs_sd_vy_lin": 0.3,       # sd of the linear range's vy (§4.2b), m/s (0: off)
    "obs_lin_r_tol": 0.01,      # the linear range: |r - vx delta / L| within this, rad/s
    "obs_lin_r_rel": 0.05,      # ... plus this share of |vx delta / L|
    "obs_lin_ay_max": 3.0,      # ... and |ay| at most this, m/s^2
    "obs_lin_ay_steady": 4.0,   # ... or at most this in a steady turn, m/s^2
    "obs_lin_dwell": 0.125,     # a steady turn: r on vx delta / L this long, s (at most 1)
    "obs_lin_mu_gain": 2.0,     # in that steady turn the model's friction >= this |ay| / g (<= 4)
    "obs_vy_out_floor_mu": 4.0,  # §5 reported sd(vy) >= this |vx ay / (cy g)| max sd_mu / mu,
                                 # the filter's P, gains and estimate untouched (0: off, <= 8)
}

# Reference-only options (issue 17, docs/OBSERVER_RESULTS.md "Honest on an unobserved
# friction"): not parameters of the C library (mu_replay does not know them, the goldens do
# not record them), both 0 (off) by default, so the reference equals the C build with them off.
# (The study's third rule, obs_vy_out_floor_mu, is a C parameter now: OBS_DEFAULTS.)
STUDY_DEFAULTS: dict[str, float] = {
    "obs_stiff_mu": 0.0,        # rows' R widened by a stiffness C(mu): d ln C / d ln mu (0: off)
    "obs_vy_floor_mu": 0.0,     # sd(vy) >= this |vx ay / (cy g)| sd_mu / mu (0: off)
    # (issue 16, OBSERVER_RESULTS.md "A cornering-stiffness scale learned by the lateral
    # filter") a third lateral state c_s, a scale on cy in the model row and the linear range;
    # the candidate's values are observer_stiffness_study.A (prior sd 0.3, walk 0.05, [0.2, 1.5],
    # r-dot 0.5)
    "obs_cs_on": 0.0,           # 1: the lateral filter carries c_s (prior 1; 0: today's filter)
    "obs_cs_sd0": 0.0,          # c_s's prior sd
    "obs_q_cs": 0.0,            # c_s's random walk while excited, 1 / sqrt(s)
    "obs_cs_min": 0.0,          # c_s clipped to [obs_cs_min, obs_cs_max] after each update
    "obs_cs_max": 0.0,          # (0: no upper bound)
    "obs_cs_rdot_on": 0.0,      # excited: r off r_ref (§4.2b) or |r-dot| >= this, rad/s^2
                                # (0: r off r_ref only)
    "obs_cs_walk_all": 0.0,     # 1: the walk on every step, excited or not
    "obs_cs_ay_on": 0.0,        # excited only with |ay| at least this too, m/s^2 (0: off)
    "obs_cs_consider": 0.0,     # 1: on steps not excited the rows leave c_s and its variance
                                # (a Schmidt update: c_s a consider parameter there)
    "obs_cs_row_only": 0.0,     # 1: c_s in the model row only, §4.2b's linear range keeps cy
    # (OBSERVER_RESULTS.md "The stiffness scale learned only where excited") on steps not
    # excited c_s relaxes to the tyre data's 1: an Ornstein-Uhlenbeck step of this time
    # constant, s (its mean and variance towards 1 and obs_cs_sd0^2; 0: off)
    "obs_cs_tau": 0.0,
}


# §5 output flags
FLAG_VX_WHEEL = 1        # vx corrected by a wheel reference this step
FLAG_BRAKING = 2         # driving state: braking
FLAG_DRIVING = 4         # driving state: driving
FLAG_VY_MODEL = 8        # vy corrected by the single-track model
FLAG_VY_LOWSPEED = 16    # vy corrected by the low-speed kinematics
FLAG_MU_RAISED = 32      # the measured ay raised the model's friction
FLAG_VY_LINEAR = 64      # vy corrected by the linear range (§4.2b)


@dataclass
class Sample:
    """One ESC sample (§1), SI units."""
    t: float
    delta: float
    yaw_rate: float
    ax: float
    ay: float
    omega: tuple
    p_brake: tuple | None = None      # per wheel, MPa, or None
    torque: tuple | None = None       # per wheel, N m, or None
    grade: float = 0.0                # known road grade, rad (uphill positive)
    mu: tuple | None = None           # friction per wheel (the friction estimator's last), or None
    sd_mu: tuple = (0.0, 0.0, 0.0, 0.0)  # its sd


@dataclass
class Kf2:
    """A two-state Kalman filter, state x, covariance P (2 x 2, symmetric)."""
    x: list = field(default_factory=lambda: [0.0, 0.0])
    P: list = field(default_factory=lambda: [[0.0, 0.0], [0.0, 0.0]])

    def predict(self, f01, u, q0, q1, q01=0.0):
        """x <- F x + [u, 0], P <- F P F^T + Q, with F = [[1, f01], [0, 1]]."""
        x0, x1 = self.x
        p00, p01, p11 = self.P[0][0], self.P[0][1], self.P[1][1]
        self.x = [x0 + f01 * x1 + u, x1]
        n00 = p00 + 2.0 * f01 * p01 + f01 * f01 * p11 + q0
        n01 = p01 + f01 * p11 + q01
        n11 = p11 + q1
        self.P = [[n00, n01], [n01, n11]]

    def update(self, h0, h1, innovation, r):
        """Scalar update with H = [h0, h1]: S = H P H^T + r, K = P H^T / S,
        x <- x + K innovation, P <- P - K K^T S. Returns S."""
        p00, p01, p11 = self.P[0][0], self.P[0][1], self.P[1][1]
        ph0 = p00 * h0 + p01 * h1
        ph1 = p01 * h0 + p11 * h1
        s = h0 * ph0 + h1 * ph1 + r
        k0, k1 = ph0 / s, ph1 / s
        self.x = [self.x[0] + k0 * innovation, self.x[1] + k1 * innovation]
        n00 = p00 - k0 * k0 * s
        n01 = p01 - k0 * k1 * s
        n11 = p11 - k1 * k1 * s
        self.P = [[n00, n01], [n01, n11]]
        return s


@dataclass
class Kf3:
    """The lateral filter with the stiffness scale (study): state [vy, b_y, c_s], covariance P
    (3 x 3, symmetric). F = [[1, f01, 0], [0, 1, 0], [0, 0, 1]]; the sums are ordered so that
    with c_s's variance and covariances 0 every number equals Kf2's bit for bit (the c_s terms
    add an exact 0.0 last)."""
    x: list = field(default_factory=lambda: [0.0, 0.0, 1.0])
    P: list = field(default_factory=lambda: [[0.0] * 3 for _ in range(3)])

    def predict(self, f01, u, q0, q1, q01=0.0, q2=0.0):
        x0, x1, x2 = self.x
        P = self.P
        p00, p01, p11 = P[0][0], P[0][1], P[1][1]
        p02, p12, p22 = P[0][2], P[1][2], P[2][2]
        self.x = [x0 + f01 * x1 + u, x1, x2]
        n00 = p00 + 2.0 * f01 * p01 + f01 * f01 * p11 + q0
        n01 = p01 + f01 * p11 + q01
        n11 = p11 + q1
        n02 = p02 + f01 * p12
        self.P = [[n00, n01, n02], [n01, n11, p12], [n02, p12, p22 + q2]]

    def update(self, h0, h1, innovation, r, h2=0.0):
        """Scalar update with H = [h0, h1, h2] (as Kf2.update). Returns S."""
        P = self.P
        p00, p01, p11 = P[0][0], P[0][1], P[1][1]
        p02, p12, p22 = P[0][2], P[1][2], P[2][2]
        ph0 = p00 * h0 + p01 * h1 + p02 * h2
        ph1 = p01 * h0 + p11 * h1 + p12 * h2
        ph2 = p02 * h0 + p12 * h1 + p22 * h2
        s = h0 * ph0 + h1 * ph1 + h2 * ph2 + r
        k0, k1, k2 = ph0 / s, ph1 / s, ph2 / s
        self.x = [self.x[0] + k0 * innovation, self.x[1] + k1 * innovation,
                  self.x[2] + k2 * innovation]
        n00 = p00 - k0 * k0 * s
        n01 = p01 - k0 * k1 * s
        n11 = p11 - k1 * k1 * s
        n02 = p02 - k0 * k2 * s
        n12 = p12 - k1 * k2 * s
        n22 = p22 - k2 * k2 * s
        self.P = [[n00, n01, n02], [n01, n11, n12], [n02, n12, n22]]
        return s


def wheel_positions(p):
    """(x_i, y_i) of fl, fr, rl, rr relative to the CoG (MODEL.md §1)."""
    return ((p["Lf"], 0.5 * p["Bf"]), (p["Lf"], -0.5 * p["Bf"]),
            (-p["Lr"], 0.5 * p["Br"]), (-p["Lr"], -0.5 * p["Br"]))


class Observer:
    """The observer of docs/OBSERVER.md."""

    def __init__(self, params: dict):
        self.p = {**STUDY_DEFAULTS, **params}
        self.pos = wheel_positions(self.p)
        self.driven = int(self.p["obs_driven"])
        self.pm = model_params(self.p)
        self.started = False
        self.t = 0.0
        self.yaw = Kf2()
        self.lon = Kf2()
        self.cs_on = self.p["obs_cs_on"] > 0.0
        self.lat = Kf3() if self.cs_on else Kf2()
        self.r_on_ref = 0.0                       # §4.2b time r has stayed on r_ref, s
        self.lat_every = int(self.p["obs_lat_every"])
        if not (1 <= self.lat_every <= 8 and self.lat_every == self.p["obs_lat_every"]):
            raise ValueError("obs_lat_every must be an integer in 1 .. 8")
        self.phase = 1                            # §4.2 the model's rows on phase 1
        self.sd_vy_out_floor = 0.0                # (study) the output sd(vy)'s floor, m/s

    # §3.1 the wheel references
    def wheel_refs(self, s: Sample, vy):
        out = []
        for i, (xi, yi) in enumerate(self.pos):
            d = s.delta if i < 2 else 0.0
            v_w = s.omega[i] * self.p["R"]
            out.append((v_w - (vy + s.yaw_rate * xi) * math.sin(d)) / math.cos(d)
                       + s.yaw_rate * yi)
        return out

    def start(self, s: Sample):
        """§3.0 the first sample initialises."""
        p = self.p
        refs = self.wheel_refs(s, 0.0)
        vx0 = max(sum(refs) / 4.0, 0.0)
        self.yaw.x = [s.yaw_rate, 0.0]
        self.yaw.P = [[p["obs_sd_r"] ** 2, 0.0], [0.0, 1.0]]
        self.lon.x = [vx0, 0.0]
        self.lon.P = [[p["obs_sd_vx0"] ** 2, 0.0], [0.0, p["obs_sd_bx0"] ** 2]]
        self.lat.x = [0.0, 0.0]
        self.lat.P = [[p["obs_sd_vy0"] ** 2, 0.0], [0.0, p["obs_sd_by0"] ** 2]]
        if self.cs_on:
            # (study) c_s's prior 1, uncorrelated with vy and b_y
            self.lat.x = [0.0, 0.0, 1.0]
            self.lat.P = [[p["obs_sd_vy0"] ** 2, 0.0, 0.0], [0.0, p["obs_sd_by0"] ** 2, 0.0],
                          [0.0, 0.0, p["obs_cs_sd0"] ** 2]]
        self.r_on_ref = 0.0
        self.sd_vy_out_floor = 0.0
        self.phase = 1                            # the next step evaluates the model
        self.t = s.t
        self.started = True
        return self.output(0)

    def step(self, s: Sample):
        if not self.started:
            return self.start(s)
        p = self.p
        dt = s.t - self.t
        if not (p["obs_dt_min"] <= dt <= p["obs_dt_max"]):
            raise ValueError(f"sample period {dt} outside [obs_dt_min, obs_dt_max]")
        self.t = s.t
        flags = 0

        # §3.2 yaw rate and its derivative: constant yaw acceleration, white jerk
        qj = p["obs_q_jerk"] ** 2
        self.yaw.predict(dt, 0.0, qj * dt * dt * dt / 3.0, qj * dt, qj * dt * dt / 2.0)
        self.yaw.update(1.0, 0.0, s.yaw_rate - self.yaw.x[0], p["obs_sd_r"] ** 2)

        # §3.4 the tyres' longitudinal push, without the rotation's r vy: a car that slides
        # out slows along its body axis with no brake on (OBSERVER_RESULTS.md "The spin's vx");
        # b_x is the predicted one, which the predict keeps, so the driving state (and with
        # it b_x's walk) comes first
        vy_prev = self.lat.x[0]
        a_lon = s.ax - p["g"] * math.sin(s.grade)
        a_net = a_lon - self.lon.x[1]

        # §3.4 driving state
        braking = a_net < -p["obs_ax_brake_on"]
        if s.p_brake is not None and max(s.p_brake) > p["obs_p_brake_on"]:
            braking = True
        driven = self.driven
        driving = (not braking) and a_net > p["obs_ax_drive_on"]
        if s.torque is not None:
            driven = sum(1 << i for i in range(4) if s.torque[i] > p["obs_torque_on"])
            driving = (not braking) and driven != 0
        # a turn, not braking: the driven wheels carry its drag with ax near 0 (not free while
        # rolling) and b_x follows r (vy error) at q_bx_turn (OBSERVER_RESULTS.md "The low-μ
        # ramp steer's vx bias")
        turning = (not braking) and p["obs_ay_turn"] > 0.0 and abs(s.ay) >= p["obs_ay_turn"]
        flags |= FLAG_BRAKING if braking else (FLAG_DRIVING if driving else 0)

        # §3.3 longitudinal: predict with the accelerometer
        a_kin = a_lon + s.yaw_rate * vy_prev
        sx = dt * p["obs_sd_ax"]
        q_bx = p["obs_q_bx_turn"] if turning else p["obs_q_bx"]
        self.lon.predict(-dt, dt * a_kin, sx * sx, (q_bx * q_bx) * dt)
        vx_pred = self.lon.x[0]

        # §3.5 plausible wheels and the reference. A free-rolling wheel measures vx; a braked
        # wheel turns slower than it rolls, so it bounds vx from below; a driven wheel bounds
        # it from above.
        refs = self.wheel_refs(s, vy_prev)
        sd_w = p["obs_sd_wheel"] + p["obs_sd_wheel_rel"] * abs(vx_pred)
        gate = p["obs_k_gate"] * math.sqrt(self.lon.P[0][0] + sd_w * sd_w)
        ok = [i for i in range(4) if abs(refs[i] - vx_pred) <= gate]
        free = [] if braking else [i for i in ok
                                   if not ((driving or turning) and (driven >> i) & 1)]
        z = None
        r = sd_w * sd_w
        if free:
            z = sum(refs[i] for i in free) / len(free)
            r = r / len(free)
        elif braking and ok:
            z = max(refs[i] for i in ok)
            z = z if z > vx_pred else None
        elif driving and ok:
            z = min(refs[i] for i in ok)
            z = z if z < vx_pred else None
        if z is None:
            # re-acquisition: the gate guards against one slipping wheel, not against a
            # prediction drifted away from all of them; rolling with the wheels in agreement,
            # or standing (brake held) without decelerating: their mean, the prediction's
            # variance re-inflated by the innovation squared
            rolling = not braking and not driving
            agree = max(refs) - min(refs) <= p["obs_k_agree"] * sd_w
            standing = max(refs) < p["obs_v_stand"] and a_net >= -p["obs_ax_brake_on"] \
                and not driving
            if (rolling and agree) or standing:
                z = sum(refs) / 4.0
                r = sd_w * sd_w / 4.0
                self.lon.P[0][0] += (z - vx_pred) * (z - vx_pred)
        if z is not None:
            self.lon.update(1.0, 0.0, z - vx_pred, r)
            flags |= FLAG_VX_WHEEL
        elif braking:
            # braking unchecked: ax's error while braking (pitch, scale) grows vx's variance
            self.lon.P[0][0] += p["obs_q_vx_brake"] ** 2 * dt
        if self.lon.x[0] < 0.0:                   # forward driving only
            self.lon.x[0] = 0.0
        vx = self.lon.x[0]

        # §4.1 lateral: predict with the accelerometer
        sy = dt * p["obs_sd_ay"]
        if self.cs_on:
            # (study) c_s's walk only while a transient excites it (OBSERVER_RESULTS.md "A
            # cornering-stiffness scale ..."): r off the neutral r_ref or |r-dot| large
            r_ref0 = vx * (s.delta / (p["Lf"] + p["Lr"]))
            excited = vx >= p["obs_v_lat_min"] and abs(s.ay) >= p["obs_cs_ay_on"] and (
                abs(s.yaw_rate - r_ref0) > p["obs_lin_r_tol"] + p["obs_lin_r_rel"] * abs(r_ref0)
                or (p["obs_cs_rdot_on"] > 0.0 and abs(self.yaw.x[1]) >= p["obs_cs_rdot_on"]))
            q2 = (p["obs_q_cs"] ** 2) * dt if (excited or p["obs_cs_walk_all"] > 0.0) else 0.0
            self.cs_excited = excited
            if not excited and p["obs_cs_tau"] > 0.0:
                self.relax_cs(dt)
            self.lat.predict(-dt, dt * (s.ay - s.yaw_rate * vx), sy * sy,
                             (p["obs_q_by"] * p["obs_q_by"]) * dt, 0.0, q2)
        else:
            self.lat.predict(-dt, dt * (s.ay - s.yaw_rate * vx), sy * sy,
                             (p["obs_q_by"] * p["obs_q_by"]) * dt)
        vy_pred = self.lat.x[0]
        on_ref = 0.0                              # below v_lat_min the time on r_ref restarts
        r_over = 0.0                              # §4.4 the yaw rate beyond r_ref, rad/s
        if vx >= p["obs_v_lat_min"]:
            # §4.2b the linear range, decided first (the model's friction floor depends on
            # it): the yaw rate of the neutral single-track model and a moderate ay (or a
            # higher one in a steady turn: r on r_ref for obs_lin_dwell)
            length = p["Lf"] + p["Lr"]
            r_ref = vx * (s.delta / length)
            yaw_linear = abs(s.yaw_rate - r_ref) <= p["obs_lin_r_tol"] + p["obs_lin_r_rel"] * abs(r_ref)
            r_over = max(0.0, abs(s.yaw_rate) - abs(r_ref))
            if not yaw_linear:
                on_ref = 0.0
            elif self.r_on_ref >= p["obs_lin_dwell"]:
                on_ref = self.r_on_ref
            else:
                on_ref = min(self.r_on_ref + dt, p["obs_lin_dwell"])
            dwelled = on_ref >= p["obs_lin_dwell"]
            steady = abs(s.ay) <= p["obs_lin_ay_steady"] and dwelled
            linear = p["obs_sd_vy_lin"] > 0.0 and yaw_linear and (abs(s.ay) <= p["obs_lin_ay_max"]
                                                                  or steady)
            # (study) the friction's relative sd (the input raised to what ay proves, as §4.2's)
            # and the linear model's slip part of vy, vx ay / (cy g)
            rel_mu = self.mu_rel_sd(s)
            vy_slip = vx * s.ay / (p["cy"] * p["g"])
        if vx >= p["obs_v_lat_min"] and self.phase == 1:
            # §4.2 the lateral acceleration of the friction estimator's model (MODEL.md §3-5)
            # at vy, at this step's friction (raised to what the measured ay proves, and in a
            # steady turn of the linear range to obs_lin_mu_gain |ay| / g: its tyres are linear)
            gain = 1.0 + p["obs_mu_margin"]
            if linear and dwelled:
                gain = max(gain, p["obs_lin_mu_gain"])
            mu_low = gain * abs(s.ay) / p["g"]
            if s.mu is None:
                mu_in, sd_in = (p["obs_mu_default"],) * 4, (p["obs_sd_mu_default"],) * 4
            else:
                mu_in, sd_in = s.mu, s.sd_mu
            if min(mu_in) < mu_low:
                flags |= FLAG_MU_RAISED
            mu = tuple(max(m, mu_low) for m in mu_in)
            # the rows at vy_pred, their derivatives by vy and by the friction along its sd
            pm_c, h2 = None, 0.0
            if self.cs_on:
                # (study) the model's tyre at c_s cy; dy/dc_s by a central difference
                cs = self.lat.x[2]
                pm_c = dict(self.pm, cy=cs * self.pm["cy"])
                eps = 1e-4
                ay_hi = self.model_rows(s, vx, vy_pred, mu, dict(self.pm, cy=(cs + eps) * self.pm["cy"]))[0]
                ay_lo = self.model_rows(s, vx, vy_pred, mu, dict(self.pm, cy=(cs - eps) * self.pm["cy"]))[0]
                h2 = (ay_hi - ay_lo) / (2.0 * eps)
            (ay_model, rd_model), (h0, h1), (e_ay, e_rd) = self.model_rows_jac(
                s, vx, vy_pred, mu, sd_in, pm_c)
            r = (p["obs_sd_model_ay"] ** 2 + (p["obs_model_ay_rel"] * s.ay) ** 2 + e_ay ** 2)
            if p["obs_stiff_mu"] > 0.0:
                # (study) a stiffness C(mu) with d ln C / d ln mu = obs_stiff_mu moves the tyres'
                # ay by that times |ay| sd_mu / mu at a fixed slip
                r += (p["obs_stiff_mu"] * abs(s.ay) * rel_mu) ** 2
            if self.lat_every > 1:
                # §4.2 every N-th step at variance r / N: the information per second of an
                # update every step at r (N = 1 takes no arithmetic: bit for bit unchanged)
                r = r / self.lat_every
            if self.cs_on:
                before = (self.lat.x[2], self.lat.P[2][2])
                self.lat.update(h0, 0.0, s.ay - ay_model, r, h2)
                self.clip_cs(before)
            else:
                self.lat.update(h0, 0.0, s.ay - ay_model, r)
            flags |= FLAG_VY_MODEL
            # the yaw moment balance: the differentiator's r-dot against the model's, linearised
            # at the same vy_pred, the innovation at the vy the lateral row left
            # (on when obs_sd_model_rdot > 0)
            if p["obs_sd_model_rdot"] > 0.0:
                r1 = p["obs_sd_model_rdot"] ** 2 + e_rd ** 2 + self.yaw.P[1][1]
                if self.lat_every > 1:
                    r1 = r1 / self.lat_every          # §4.2 as the lateral row's
                self.lat.update(h1, 0.0,
                                self.yaw.x[1] - (rd_model + h1 * (self.lat.x[0] - vy_pred)), r1)
        if vx >= p["obs_v_lat_min"]:
            # §4.2b the linear range (decided above): vy is the linear model's, whatever the
            # friction
            if linear:
                cs_lin = self.cs_on and p["obs_cs_row_only"] <= 0.0
                cy_c = p["cy"] if not cs_lin else self.lat.x[2] * p["cy"]
                vy_lin = vx * ((p["Lr"] * s.delta) / length - s.ay / (cy_c * p["g"]))
                r_lin = p["obs_sd_vy_lin"] ** 2
                if p["obs_stiff_mu"] > 0.0:
                    # (study) its slip part scales with 1 / C(mu)
                    r_lin += (p["obs_stiff_mu"] * vy_slip * rel_mu) ** 2
                if cs_lin:
                    # (study) the row vy + vx ay / (c_s cy g) = vx Lr delta / L
                    h2 = -vx * s.ay / (self.lat.x[2] * cy_c * p["g"])
                    before = (self.lat.x[2], self.lat.P[2][2])
                    self.lat.update(1.0, 0.0, vy_lin - self.lat.x[0], r_lin, h2)
                    self.clip_cs(before)
                else:
                    self.lat_update(1.0, 0.0, vy_lin - self.lat.x[0], r_lin)
                flags |= FLAG_VY_LINEAR
        else:
            # §4.3 low speed: the rear axle rolls without side slip, vy = Lr r
            self.lat_update(1.0, 0.0, p["Lr"] * s.yaw_rate - vy_pred, p["obs_sd_lowspeed"] ** 2)
            flags |= FLAG_VY_LOWSPEED
        # §4.4 no sideslip accelerates for long: ay - r vx = b_y + v-dot_y, with v-dot_y as
        # noise, holds b_y where the model cannot (a saturated tyre tells nothing about vy);
        # larger while r changes and while the car yaws beyond r_ref (sliding out: the
        # oversteer side only, OBSERVER_RESULTS.md "§4.4's noise grown with the yaw-rate error")
        sv = (p["obs_sd_vydot"] + p["obs_vydot_rdot"] * abs(self.yaw.x[1])) + p["obs_vydot_rerr"] * r_over
        self.lat_update(0.0, 1.0, (s.ay - s.yaw_rate * vx) - self.lat.x[1], sv * sv)
        if p["obs_vy_floor_mu"] > 0.0 and vx >= p["obs_v_lat_min"]:
            # (study) no row sees a constant vy error from the tyre's stiffness: its sd is a floor
            # (raising P00 alone keeps P positive semi-definite)
            floor = p["obs_vy_floor_mu"] * vy_slip * rel_mu
            self.lat.P[0][0] = max(self.lat.P[0][0], floor * floor)
        self.sd_vy_out_floor = 0.0
        if p["obs_vy_out_floor_mu"] > 0.0 and vx >= p["obs_v_lat_min"]:
            # §5 (obs_vy_out_floor_mu) only on what the observer reports: the filter's gains
            # unchanged
            self.sd_vy_out_floor = abs(p["obs_vy_out_floor_mu"] * vy_slip * rel_mu)
        self.r_on_ref = on_ref
        # §4.2 the next step's phase: the model's rows every obs_lat_every-th step
        self.phase = 1 if self.phase >= self.lat_every else self.phase + 1
        return self.output(flags)

    def lat_update(self, h0, h1, innovation, r):
        """§4.3, §4.4's rows: today's update; (study) with c_s, through its covariance it moves
        c_s too, and clip_cs applies (a consider parameter stays where it was)."""
        if not self.cs_on:
            return self.lat.update(h0, h1, innovation, r)
        before = (self.lat.x[2], self.lat.P[2][2])
        out = self.lat.update(h0, h1, innovation, r)
        self.clip_cs(before)
        return out

    def relax_cs(self, dt):
        """(study) c_s's relaxation on a step not excited: the exact discretisation of an
        Ornstein-Uhlenbeck process of time constant obs_cs_tau about the tyre data's 1 with
        stationary sd obs_cs_sd0 (F22 = a = exp(-dt / tau), Q22 = (1 - a^2) sd0^2): a learned
        scale that nothing confirms drifts back, and its sd back to the prior's."""
        a = math.exp(-dt / self.p["obs_cs_tau"])
        P = self.lat.P
        self.lat.x[2] = 1.0 + a * (self.lat.x[2] - 1.0)
        P[0][2] *= a
        P[2][0] = P[0][2]
        P[1][2] *= a
        P[2][1] = P[1][2]
        P[2][2] = a * a * P[2][2] + (1.0 - a * a) * self.p["obs_cs_sd0"] ** 2

    def clip_cs(self, before):
        """(study) c_s within [obs_cs_min, obs_cs_max], its covariance kept; with
        obs_cs_consider on a step not excited, c_s and its variance as @p before (x2, P22) had
        them (the update's cross-covariances P02 - k0 ph2, P12 - k1 ph2 are the Schmidt
        filter's already)."""
        if self.p["obs_cs_consider"] > 0.0 and not self.cs_excited:
            self.lat.x[2], self.lat.P[2][2] = before
        self.lat.x[2] = max(self.lat.x[2], self.p["obs_cs_min"])
        if self.p["obs_cs_max"] > 0.0:
            self.lat.x[2] = min(self.lat.x[2], self.p["obs_cs_max"])

    def mu_rel_sd(self, s):
        """(study) max over the wheels of sd_mu / mu, the friction input (or the default) raised to
        (1 + obs_mu_margin) |ay| / g as §4.2 raises it (at least that, so never a division by 0
        while the car corners; 0 when it does not)."""
        p = self.p
        if s.mu is None:
            mu_in, sd_in = (p["obs_mu_default"],) * 4, (p["obs_sd_mu_default"],) * 4
        else:
            mu_in, sd_in = s.mu, s.sd_mu
        mu_low = (1.0 + p["obs_mu_margin"]) * abs(s.ay) / p["g"]
        rel = 0.0
        for m, sd in zip(mu_in, sd_in):
            m = max(m, mu_low)
            if m > 0.0:
                rel = max(rel, sd / m)
        return rel

    def model_rows(self, s, vx, vy, mu, pm=None):
        """MODEL.md §3-5: the lateral and yaw rows (ay, r-dot) of h(mu, u) at
        u = (delta, vx, vy, r, ax, ay, omega),
        with the tyre of the configuration (p["tyre"]: "paper" normalised Dugoff, forces
        mu F0(u); "dugoff" absolute Dugoff; "magic" Magic Formula)."""
        import numpy as np
        from . import model
        pm = self.pm if pm is None else pm
        ti = model.tyre_inputs(pm, np.array([s.delta]), np.array([vx]), np.array([vy]),
                               np.array([s.yaw_rate]), np.array([s.ax]), np.array([s.ay]),
                               np.array([s.omega]))
        m = np.array(mu, dtype=float)
        if pm["tyre"] == "paper":
            hm = model.observation_matrix(pm, ti)[0]
            return float(hm[1] @ m), float(hm[2] @ m)
        z = model.h_absolute(pm, ti, 0, m[:, None])
        return float(z[1, 0]), float(z[2, 0])

    def model_rows_jac(self, s, vx, vy, mu, dmu, pm=None):
        """§4.2: the rows (ay, r-dot) of h(mu, u) at vy (model_rows), their derivatives by vy and
        their derivative by the per-wheel friction in the direction dmu, analytically, wheel by
        wheel as the page writes them (scalar floats)."""
        pm = self.pm if pm is None else pm
        z = self.model_rows(s, vx, vy, mu, pm)
        d_vy, d_mu = [0.0, 0.0], [0.0, 0.0]
        fz = vertical_loads(pm, s.ax, s.ay)
        c, sn = math.cos(s.delta), math.sin(s.delta)
        for i, (xi, yi) in enumerate(self.pos):
            ci, si = (c, sn) if i < 2 else (1.0, 0.0)
            f = wheel_force_jac(pm, s, vx, vy, i, xi, yi, ci, si, fz[i], mu[i])
            for row, (gx, gy) in enumerate(((f[2], f[3]), (f[4] * dmu[i], f[5] * dmu[i]))):
                fbx, fby = gx * ci - gy * si, gx * si + gy * ci
                out = d_vy if row == 0 else d_mu
                out[0] += fby / pm["m"]
                out[1] += (xi * fby - yi * fbx) / pm["J"]
        return z, tuple(d_vy), tuple(d_mu)

    def output(self, flags):
        """§5 the outputs and their sd."""
        vx, vy = self.lon.x[0], self.lat.x[0]
        svx = math.sqrt(max(self.lon.P[0][0], 0.0))
        svy = max(math.sqrt(max(self.lat.P[0][0], 0.0)), self.sd_vy_out_floor)
        vmin = self.p["obs_v_lat_min"]
        n2 = max(vx * vx + vy * vy, vmin * vmin)
        beta = math.atan2(vy, vx) if vx >= vmin else 0.0
        sbeta = math.sqrt((vx * vx) * (svy * svy) + (vy * vy) * (svx * svx)) / n2
        out = dict(vx=vx, vy=vy, beta=beta, yaw_acc=self.yaw.x[1], sd_vx=svx, sd_vy=svy,
                   sd_beta=sbeta, sd_yaw_acc=math.sqrt(max(self.yaw.P[1][1], 0.0)),
                   bx=self.lon.x[1], by=self.lat.x[1], flags=flags)
        if self.cs_on:
            out["cs"] = self.lat.x[2]                 # (study) the stiffness scale and its sd
            out["sd_cs"] = math.sqrt(max(self.lat.P[2][2], 0.0))
        return out


OUTPUTS = ("vx", "vy", "beta", "yaw_acc", "sd_vx", "sd_vy", "sd_beta", "sd_yaw_acc", "bx", "by",
           "flags")


def _sgn(x):
    return 1.0 if x > 0.0 else (-1.0 if x < 0.0 else 0.0)


def vertical_loads(p, ax, ay):
    """MODEL.md §3 quasi-static loads fl, fr, rl, rr, clamped at >= 0."""
    la = p["Lf"] + p["Lr"]
    mg = p["m"] * p["g"]
    fs, rs = mg * p["Lr"] / (2.0 * la), mg * p["Lf"] / (2.0 * la)
    pitch = p["m"] * ax * p["hg"] / (2.0 * la)
    rf = p["m"] * ay * p["hg"] * p["Lr"] / (la * p["Bf"])
    rr = p["m"] * ay * p["hg"] * p["Lf"] / (la * p["Br"])
    return [max(v, 0.0) for v in (fs - pitch - rf, fs - pitch + rf, rs + pitch - rr, rs + pitch + rr)]


def _dugoff_jac(k, t, dk, dt, dv, c1, c2, eps, vwx, mu_s, fz):
    """§4.2 the Dugoff forces fz (c1 k, c2 t) g at the friction scale mu_s and their derivatives
    along (dk, dt, d vwx) and by mu_s."""
    S = math.sqrt((c1 * k) ** 2 + (c2 * t) ** 2)
    slip = math.sqrt(k * k + t * t)
    e = max(1.0 - eps * abs(vwx) * slip, 0.0)
    omk = 1.0 - abs(k)
    if S <= 0.0:
        # the limit S -> 0: g = 1 (L -> infinity), or 0 at mu_s = 0 (no force at any slip)
        g, dg, dg_mu = (1.0 if mu_s > 0.0 else 0.0), 0.0, 0.0
    else:
        lam = mu_s * omk * e / (2.0 * S)
        if lam < 1.0:
            q = mu_s / (2.0 * S)
            g = q * e * (2.0 - lam)
            ds = ((c1 * k) * (c1 * dk) + (c2 * t) * (c2 * dt)) / S
            de = 0.0
            if e > 0.0:
                de = -eps * (_sgn(vwx) * dv * slip + abs(vwx) * (k * dk + t * dt) / slip)
            dq = -q * ds / S
            dl = (dq * omk - q * _sgn(k) * dk) * e + q * omk * de
            dg = (dq * e + q * de) * (2.0 - lam) - q * e * dl
            dg_mu = e * (1.0 - lam) / S
        else:
            g = 1.0 / omk
            dg = _sgn(k) * dk / (omk * omk)
            dg_mu = 0.0
    return (fz * c1 * k * g, fz * c2 * t * g, fz * c1 * (dk * g + k * dg),
            fz * c2 * (dt * g + t * dg), fz * c1 * k * dg_mu, fz * c2 * t * dg_mu)


def _magic_shape_jac(s, m, C, E):
    """G = sin(C atan2(n, mC)), n = s - E (s - mC atan2(s, mC)), and dG/ds (0 at m = 0)."""
    mc = m * C
    a = math.atan2(s, mc)
    n = s - E * (s - mc * a)
    phi = C * math.atan2(n, mc)
    g_s = 0.0
    if mc > 0.0:
        g_s = math.cos(phi) * C * ((1.0 - E) + E * mc * mc / (mc * mc + s * s)) * mc / (mc * mc + n * n)
    return math.sin(phi), g_s


def wheel_force_jac(p, s, vx, vy, i, xi, yi, ci, si, fz, mu):
    """§4.2 wheel i: (Fx, Fy, dFx/dvy, dFy/dvy, dFx/dmu, dFy/dmu) in wheel axes at friction mu."""
    vbx, vby = vx - s.yaw_rate * yi, vy + s.yaw_rate * xi
    vwx, vwy = vbx * ci + vby * si, -vbx * si + vby * ci
    amax = p["alpha_max"]
    alpha = min(max(-math.atan2(vwy, abs(vwx)), -amax), amax)
    vr = s.omega[i] * p["R"]
    den = max(max(abs(vr), abs(vwx)), p["v_min"])
    k = min(max((vr - vwx) / den, -1.0), 1.0)
    t = math.tan(alpha)
    # the vy direction: d vwx = si, d vwy = ci through the slip angle and the slip
    dt = -(ci + t * _sgn(vwx) * si) / abs(vwx) if (abs(alpha) < amax and abs(vwx) > 0.0) else 0.0
    dk = 0.0
    if abs(k) < 1.0:
        own = k * _sgn(vwx) if (abs(vwx) > abs(vr) and abs(vwx) > p["v_min"]) else 0.0
        dk = -(1.0 + own) * si / den
    dv = si
    tyre = p["tyre"]
    if tyre == "paper":
        f = _dugoff_jac(k, t, dk, dt, dv, p["Cx_n"], p["Cy_n"], p["eps"], vwx, 1.0, fz)
        return (mu * f[0], mu * f[1], mu * f[2], mu * f[3], f[0], f[1])
    if tyre != "magic":
        f = _dugoff_jac(k, t, dk, dt, dv, p["cx"], p["cy"], p["eps"], vwx, max(mu, 0.0), fz)
        return f if mu > 0.0 else (f[0], f[1], f[2], f[3], 0.0, 0.0)
    m = max(mu, 0.0)
    cxk, cyt = p["cx"] * k, p["cy"] * t
    sl = math.sqrt(cxk * cxk + cyt * cyt)
    ux, uy = (cxk / sl, cyt / sl) if sl > 0.0 else (0.0, 0.0)
    gx, gxs = _magic_shape_jac(sl, m, p["shape_Cx"], p["shape_Ex"])
    gy, gys = _magic_shape_jac(sl, m, p["shape_Cy"], p["shape_Ey"])
    fm = fz * m
    cdk, cdt = p["cx"] * dk, p["cy"] * dt
    if sl > 0.0:
        ds = ux * cdk + uy * cdt
        dux, duy = (cdk - ux * ds) / sl, (cdt - uy * ds) / sl
        dfx = fm * (gxs * ds * ux + gx * dux)
        dfy = fm * (gys * ds * uy + gy * duy)
        mfx = fz * ux * (gx - sl * gxs) if m > 0.0 else 0.0
        mfy = fz * uy * (gy - sl * gys) if m > 0.0 else 0.0
    else:
        dfx, dfy, mfx, mfy = fm * gxs * cdk, fm * gys * cdt, 0.0, 0.0
    return (fm * gx * ux, fm * gy * uy, dfx, dfy, mfx, mfy)


def model_params(p):
    """The friction model's parameters (vehicle, tyre) out of the observer's dict."""
    from .params import DEFAULTS
    q = dict(DEFAULTS)
    q.update({k: v for k, v in p.items() if k in DEFAULTS})
    q["tyre"] = p.get("tyre", "magic")
    return q


def params_with_defaults(known: dict | None = None, **over):
    """The friction estimator's default preset (its vehicle and tyre are the observer's),
    the observer's defaults, then @p known (e.g. params.from_metadata of a log), then @p over."""
    from .params import DEFAULTS, PRESETS
    p = dict(DEFAULTS)
    p.update(PRESETS["default"])
    p.update(OBS_DEFAULTS)
    if known:
        p.update(known)
    p.update(over)
    return p


def run(cols: dict, params: dict, mu=None):
    """Run the observer over a sensor log's columns (DATA.md names); optional columns
    p_fl.., torque_fl.., grade are used when present. mu: optional (mu, sd) with mu[w], sd[w]
    arrays per wheel (the friction estimate the observer's model uses). Returns a dict of output arrays (OUTPUTS)."""
    import numpy as np
    n = len(cols["t"])
    wheels = ("fl", "fr", "rl", "rr")
    has_p = all(f"p_{w}" in cols for w in wheels)
    has_t = all(f"torque_{w}" in cols for w in wheels)
    obs = Observer(params)
    out = {k: np.zeros(n) for k in OUTPUTS}
    for k in range(n):
        s = Sample(t=float(cols["t"][k]), delta=float(cols["delta"][k]),
                   yaw_rate=float(cols["yaw_rate"][k]), ax=float(cols["ax"][k]),
                   ay=float(cols["ay"][k]),
                   omega=tuple(float(cols[f"omega_{w}"][k]) for w in wheels),
                   p_brake=tuple(float(cols[f"p_{w}"][k]) for w in wheels) if has_p else None,
                   torque=tuple(float(cols[f"torque_{w}"][k]) for w in wheels) if has_t else None,
                   grade=float(cols["grade"][k]) if "grade" in cols else 0.0)
        if mu is not None:
            s.mu = tuple(float(mu[0][w][k]) for w in range(4))
            s.sd_mu = tuple(float(mu[1][w][k]) for w in range(4))
        o = obs.step(s)
        for key in OUTPUTS:
            out[key][k] = o[key]
        if obs.cs_on:                                 # (study) c_s and its sd
            for key in ("cs", "sd_cs"):
                out.setdefault(key, np.zeros(n))[k] = o[key]
    return out
