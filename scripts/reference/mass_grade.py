"""Reference mass and road-grade estimator (docs/MASS_GRADE.md), float64.

The seed's adaptive unscented Kalman filter (AUKF) on the longitudinal model, its plain UKF
baseline, and the accelerometer row (MASS_GRADE.md §5).  Written from the page only, in plain
Python floats with every sum in the page's order (no BLAS, no NumPy on the filter's path), so
a C double port can be compared with it bit for bit.

Two covariance forms, chosen by the argument `form` (not a parameter: the library has one
form, the parameters are the vehicle's and the filter's, and a golden's metadata lists
parameters only):

- "sqrt" (the default): the square-root form of the C library (float, double: src/estimators/
  mass_grade/mass_grade_ukf_flt.c; Q31: mass_grade_ukf_q31.c). The state carries the lower
  factor S of P = S S^T; the time update, the ax row, the hold and the adaptation are each one
  Householder triangularisation (tria(), the operations of src/numerics/qr_flt.c in their
  order), the speed row one Givens rotation. The reference of the C float/double build and of
  its goldens (scenarios/golden/mass_grade/).
- "textbook": the full-covariance form of the page's equations (P- = sum w_c D D^T + Q,
  P = P- - K S K^T), which scripts/tools/mass_grade_textbook.py runs in float32 and with an
  int32 P to show where it loses positive definiteness.

    est = MassGrade(params)        # params: a dict over MG_DEFAULTS (preset(name) gives one)
    out = est.step(sample)         # sample: MgSample; out: MgEstimate (mass, grade, sd, status)
    tab = run(columns, params)     # a whole mass-and-grade log -> dict of output arrays

Section numbers in the comments are the page's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

# §4.8 the model-mismatch monitor's threshold: twice the largest |EMA| on the eight clean
# mass and grade logs read from mg_mm_tau on (scripts/tools/mass_headwind_study.py, the
# "mismatch monitor" table of MASS_GRADE_RESULTS.md)
MM_E_DEFAULT = 0.3

# §6 Parameters: keys, defaults (the passenger-car preset), units in MASS_GRADE.md §6.
MG_DEFAULTS: dict[str, float] = {
    "R": 0.325,             # rolling radius, m (the vehicle key of DATA.md)
    "g": 9.81,              # gravity, m/s^2 (the vehicle key of DATA.md)
    "mg_fc": 0.010,         # rolling-resistance coefficient, constant part
    "mg_fr": 0.00015,       # rolling-resistance coefficient, speed part, s/m
    "mg_rho": 1.2,          # air density, kg/m^3
    "mg_cd": 0.30,          # drag coefficient
    "mg_area": 2.2,         # frontal area, m^2
    "mg_m_rot": 45.4,       # equivalent mass of the rotating parts, kg (0: the seed's model)
    "mg_m0": 1830.0,        # initial mass, kg
    "mg_theta0": 0.0,       # initial grade, rad
    "mg_sd_m0": 500.0,      # initial sd of the mass, kg
    "mg_sd_theta0": 0.05,   # initial sd of the grade, rad
    "mg_q_v": 0.02,         # process noise of v, m/s per sqrt(s)
    "mg_q_mc": 1.0,         # constant part of the mass process noise, kg per sqrt(s)
    "mg_q_mv0": 300.0,      # initial adaptive part, kg per sqrt(s)
    "mg_q_theta": 0.004,    # process noise of the grade, rad per sqrt(s)
    "mg_r_v": 0.05,         # speed measurement noise sd, m/s
    "mg_r_ax": 0.1,         # ax measurement noise sd (sensor and model), m/s^2
    "mg_ut_alpha": 1.0,     # sigma-point spread alpha
    "mg_ut_beta": 2.0,      # prior-distribution parameter beta
    "mg_ut_kappa": 0.0,     # secondary scaling kappa
    "mg_adaptive": 1.0,     # 1: AUKF (eqs. 22-25), 0: plain UKF
    "mg_t_adapt": 1.0,      # period of the adaptation, s (0: every step)
    "mg_mv_stop": 1e-3,     # the adaptation ends when q_mv <= mg_mv_stop * q_mc
    "mg_use_ax": 0.0,       # 1: the accelerometer row (§5); 0: the seed's speed only
    "mg_v_min": 3.0,        # below this speed the filter pauses, m/s
    "mg_t_brake": 1.0,      # pause after the last braked sample, s
    "mg_t_shift": 1.0,      # pause after a gear change, s
    "mg_p_brake_on": 1.0e5,  # brake pressure above which the brake is on, Pa
    "mg_slip_max": 0.05,    # |v - vx| > this * max(|vx|, mg_v_min) pauses (vx given); 0: off
    "mg_ay_max": 0.0,       # |ay| > this pauses (ay given): the curve pause, m/s^2; 0: off
    "mg_t_curve": 1.0,      # pause after the last sample with |ay| > mg_ay_max, s
    "mg_pause_grade": 0.0,  # pauses that keep learning the grade from ax (mg_use_ax 1), a
                            # sum of 1 brake, 2 gear shift, 4 curve (§4.2); 0: none
    "mg_pause_grade_slip": 0.05,  # in such a pause, |v - vx| > this * max(|vx|, mg_v_min)
                            # (vx given) holds instead: the ABS gate (§4.2); 0: no gate
    "mg_pause_grade_dv": 0.2,  # the change test of such a pause: it learns only once the
                            # speed (vx if given, else v) has left the held grade's
                            # prediction by more than this, m/s (§4.2); 0: no test
    "mg_m_min": 300.0,      # mass bounds: the mean is projected onto them, kg
    "mg_m_max": 60000.0,
    "mg_theta_max": 0.35,   # grade bound |theta|, rad
    "mg_dt_max": 1.0,       # a longer sample period restarts the filter, s
    # §4.7 the grade's two-level walk; off by default (mg_q_theta_hi 0): mg_q_theta always
    "mg_q_theta_hi": 0.0,   # the grade's looser walk while the grade moves, rad per sqrt(s)
    "mg_theta_rate_on": 0.002,   # the grade rate's RMS above which the walk loosens, rad/s
    "mg_theta_rate_off": 0.001,  # ... below which it tightens again, rad/s (<= _on)
    "mg_theta_rate_tau": 1.0,    # time constant of the grade rate's low-pass, s
    "mg_theta_rate_avg": 3.0,    # time constant of the mean of its square, s
    # the model-mismatch monitor on the ax row (issue 19; MASS_GRADE.md §4.8): an EMA of the ax
    # row's normalised innovation, its flag when |EMA| > mg_mm_e (0: never)
    "mg_mm_tau": 10.0,      # its time constant, s (issue 19's 10 s), in [mg_dt_max, 60]
    "mg_mm_e": MM_E_DEFAULT,  # the flag's threshold on |EMA| (dimensionless); 0: off
}


# Vehicle presets (§6): the passenger car is MG_DEFAULTS; the truck the seed's 5758 kg truck
# with the simulator's truck data (scripts/sim/mass_grade_scenarios.py).
MG_PRESETS: dict[str, dict[str, float]] = {
    "car": {},
    "truck": {"R": 0.45, "mg_fc": 0.0065, "mg_fr": 0.00005, "mg_cd": 0.60, "mg_area": 6.0,
              "mg_m_rot": 158.0, "mg_m0": 4000.0, "mg_sd_m0": 2000.0, "mg_q_mc": 3.0,
              "mg_q_mv0": 1000.0},
}

# §6 "Presets": the library's configurations over a vehicle's values (rfe_mass_grade_params_preset,
# RFE_MG_RECOMMENDED and RFE_MG_SEED): the recommended one (plain UKF with the accelerometer row
# and the brake bit of mg_pause_grade) and the seed's (its AUKF on speed and torque, adapted
# every step, no rotating mass). Every script that runs "the recommended preset" takes it here.
MG_CONFIGS: dict[str, dict[str, float]] = {
    "recommended": {"mg_adaptive": 0.0, "mg_use_ax": 1.0, "mg_pause_grade": 1.0,
                    "mg_q_theta_hi": 0.008},
    "seed": {"mg_adaptive": 1.0, "mg_use_ax": 0.0, "mg_m_rot": 0.0, "mg_t_adapt": 0.0},
}

# §7 Status codes (the library's enum, include/rfe/common.h, and the codes this page adds)
OK = 0
NO_UPDATE_LOW_SPEED = 2
PAUSED_BRAKE = 5
PAUSED_SHIFT = 6
PAUSED_SLIP = 7
PAUSED_CURVE = 8
ERR_NONFINITE = 17
ERR_RANGE = 18
ERR_PARAM = 19
ERR_NOT_POSITIVE_DEFINITE = 21
# mg_pause_grade's bits: the pauses during which the grade keeps being learned from ax (§4.2)
PAUSE_GRADE_BITS = {PAUSED_BRAKE: 1, PAUSED_SHIFT: 2, PAUSED_CURVE: 4}

N = 3           # state [v, M, theta]
V_MAX = 100.0   # input limits (include/rfe/config.h: |vx| <= 100 m/s)
T_MAX = 1.0e5   # |drive torque| <= 1e5 N m
AX_MAX = 50.0   # |ax| <= 50 m/s^2


class Arith:
    """The arithmetic the filter runs in: real(v) makes a number of it, sqrt/sin/cos its
    functions, store_cov(P) what becomes of a covariance when the filter stores it. F64 below
    (Python floats, P stored as computed) is the page's and every caller's here; the hook lets
    scripts/tools/mass_grade_textbook.py run the same steps in float32 or with an int32 P."""

    def __init__(self, real=float, sqrt=math.sqrt, sin=math.sin, cos=math.cos, store_cov=None):
        self.real, self.sqrt, self.sin, self.cos = real, sqrt, sin, cos
        self.store_cov = store_cov if store_cov is not None else (lambda P: P)


F64 = Arith()


class ParamError(ValueError):
    """An invalid parameter (status 19); the message names the key."""


def preset(name="car", **overrides):
    """A full parameter dict: MG_DEFAULTS, then the vehicle preset, then overrides (which may
    may set any key of MG_DEFAULTS)."""
    p = dict(MG_DEFAULTS)
    p.update(MG_PRESETS[name])
    for k, v in overrides.items():
        if k not in p:
            raise ParamError(f"unknown key {k}")
        p[k] = float(v)
    return p


def validate(p):
    """§6 rules; raises ParamError naming the first key that breaks one."""
    for k in MG_DEFAULTS:
        if k not in p:
            raise ParamError(f"{k}: missing")
        if not math.isfinite(p[k]):
            raise ParamError(f"{k}: not finite")
    positive = ("R", "g", "mg_m0", "mg_sd_m0", "mg_sd_theta0", "mg_q_mc", "mg_r_v", "mg_r_ax",
                "mg_ut_alpha", "mg_m_min", "mg_theta_max", "mg_dt_max", "mg_q_v", "mg_q_theta")
    for k in positive:
        if not p[k] > 0.0:
            raise ParamError(f"{k}: must be > 0")
    nonneg = ("mg_fc", "mg_fr", "mg_rho", "mg_cd", "mg_area", "mg_m_rot", "mg_q_mv0",
              "mg_t_adapt", "mg_mv_stop", "mg_v_min", "mg_t_brake", "mg_t_shift",
              "mg_p_brake_on", "mg_slip_max", "mg_ay_max", "mg_t_curve", "mg_ut_beta",
              "mg_pause_grade_slip", "mg_pause_grade_dv")
    for k in nonneg:
        if not p[k] >= 0.0:
            raise ParamError(f"{k}: must be >= 0")
    for k in ("mg_adaptive", "mg_use_ax"):
        if p[k] not in (0.0, 1.0):
            raise ParamError(f"{k}: must be 0 or 1")
    if p["mg_pause_grade"] not in tuple(float(b) for b in range(8)):
        raise ParamError("mg_pause_grade: must be an integer in 0..7")
    if not p["mg_pause_grade_slip"] <= 1.0:
        raise ParamError("mg_pause_grade_slip: must be <= 1")
    if not p["mg_pause_grade_dv"] <= 10.0:
        raise ParamError("mg_pause_grade_dv: must be <= 10 m/s")
    w = p                   # §4.7's keys (finite: above)
    if w["mg_q_theta_hi"] != 0.0 and not p["mg_q_theta"] <= w["mg_q_theta_hi"] <= 0.1:
        raise ParamError("mg_q_theta_hi: must be 0 or in [mg_q_theta, 0.1] rad/sqrt(s)")
    if not 0.0 < w["mg_theta_rate_off"] <= w["mg_theta_rate_on"] <= 0.1:
        raise ParamError("mg_theta_rate_off, mg_theta_rate_on: need 0 < off <= on <= 0.1 rad/s")
    if not p["mg_dt_max"] <= p["mg_mm_tau"] <= 60.0:
        raise ParamError("mg_mm_tau: must lie in [mg_dt_max, 60] s")
    if not 0.0 <= p["mg_mm_e"] <= 100.0:
        raise ParamError("mg_mm_e: must lie in [0, 100]")
    for k in ("mg_theta_rate_tau", "mg_theta_rate_avg"):
        if not p["mg_dt_max"] <= w[k] <= 60.0:
            raise ParamError(f"{k}: must lie in [mg_dt_max, 60] s")
    if not p["mg_m_min"] < p["mg_m0"] < p["mg_m_max"]:
        raise ParamError("mg_m0: must lie inside (mg_m_min, mg_m_max)")
    if not abs(p["mg_theta0"]) < p["mg_theta_max"] < 1.5:
        raise ParamError("mg_theta_max: must exceed |mg_theta0| and stay below 1.5 rad")
    lam = lambda_ut(p)
    if not N + lam > 0.0:
        raise ParamError("mg_ut_kappa: n + lambda must be > 0")
    if p["mg_adaptive"] == 1.0 and p["mg_mv_stop"] * p["mg_q_mc"] ** 2 >= p["mg_q_mv0"] ** 2:
        raise ParamError("mg_q_mv0: the adaptation would end before it starts")


def lambda_ut(p, n=N):
    """§3 lambda = alpha^2 (n + kappa) - n; n the state's size (N, the filter's; another for
    a study that adds states, scripts/tools/mass_offset_study.py)."""
    a = p["mg_ut_alpha"]
    return a * a * (n + p["mg_ut_kappa"]) - n


def weights(p, n=N):
    """§3 eqs. (12)-(14), eq. (14) corrected: w_m,i = w_c,i = 1 / (2 (n + lambda)); n as in
    lambda_ut."""
    lam = lambda_ut(p, n)
    c = n + lam
    wm = [lam / c] + [1.0 / (2.0 * c)] * (2 * n)
    wc = [lam / c + (1.0 - p["mg_ut_alpha"] ** 2 + p["mg_ut_beta"])] + [1.0 / (2.0 * c)] * (2 * n)
    return wm, wc


def cholesky(a, ar=F64):
    """§3 lower factor L of a symmetric 3x3 a (L L^T = a), row by row, column by column;
    a pivot exactly 0 gives a zero column (a state known exactly: its row and column of a
    are 0); a negative pivot returns None."""
    L = [[0.0] * N for _ in range(N)]
    for j in range(N):
        d = a[j][j]
        for k in range(j):
            d -= L[j][k] * L[j][k]
        if d < 0.0:
            return None
        if d == 0.0:
            continue            # column j stays 0 (every a[i][j] - sum is 0 for a PSD a)
        L[j][j] = ar.sqrt(d)
        for i in range(j + 1, N):
            s = a[i][j]
            for k in range(j):
                s -= L[i][k] * L[j][k]
            L[i][j] = s / L[j][j]
    return L


def sigma_points(x, P, c, ar=F64):
    """§3 eqs. (8)/(15): chi_0 = x, chi_i = x + L[:, i-1], chi_{n+i} = x - L[:, i-1],
    L the lower Cholesky factor of c*P (c = n + lambda, P scaled element by element)."""
    L = cholesky([[c * P[i][j] for j in range(N)] for i in range(N)], ar)
    if L is None:
        return None
    pts = [list(x)]
    for i in range(N):
        pts.append([x[r] + L[r][i] for r in range(N)])
    for i in range(N):
        pts.append([x[r] - L[r][i] for r in range(N)])
    return pts


def accel(p, v, m, theta, torque, ar=F64):
    """§1 model: v-dot = (T/R - M g ((fc + fr v) cos theta + sin theta) - rho cd S v^2 / 2)
    / (M + m_rot), with M clamped to [mg_m_min, mg_m_max] (a sigma point may leave them)."""
    m = min(max(m, p["mg_m_min"]), p["mg_m_max"])
    f = p["mg_fc"] + p["mg_fr"] * v
    drag = 0.5 * p["mg_rho"] * p["mg_cd"] * p["mg_area"] * v * v
    force = torque / p["R"] - m * p["g"] * (f * ar.cos(theta) + ar.sin(theta)) - drag
    return force / (m + p["mg_m_rot"])


def f_state(p, x, torque, dt, ar=F64):
    """§2 eq. (4): Euler step of the model with the previous sample's torque."""
    return [x[0] + dt * accel(p, x[0], x[1], x[2], torque, ar), x[1], x[2]]


def h_meas(p, x, torque, use_ax, ar=F64):
    """§2 eq. (6) and §5: z = [v] or [v, a_x] with a_x = v-dot(x, T_k) + g sin theta."""
    if not use_ax:
        return [x[0]]
    return [x[0], accel(p, x[0], x[1], x[2], torque, ar) + p["g"] * ar.sin(x[2])]


@dataclass
class MgSample:
    """One sample (§1): time, speed, drive torque at the wheels; optional brake flag, brake
    pressure, gear, accelerometer, the car's speed over ground vx from another source than
    the wheels (the slip pause's reference, §4.2) and the lateral accelerometer ay (the curve
    pause's, §4.2) (None: not on the bus)."""
    t: float
    v: float
    torque: float
    brake: float | None = None
    brake_pressure: float | None = None
    gear: float | None = None
    ax: float | None = None
    vx: float | None = None
    ay: float | None = None


@dataclass
class MgEstimate:
    mass: float
    sd_mass: float
    grade: float
    sd_grade: float
    v: float
    sd_v: float
    q_mv: float        # the adaptive part of the mass process noise, kg^2/s
    status: int
    e_ax: float = 0.0  # §4.8 the EMA of the ax row's normalised innovation (0 without the row)
    mismatch: bool = False  # §4.8 |e_ax| > mg_mm_e (mg_mm_e > 0): the model is contradicted


FORMS = ("sqrt", "textbook")


class MassGrade:
    """§4 the estimator's state and step; form "sqrt" (the library's) or "textbook" (module
    docstring). The textbook form runs in any Arith; the square-root form in F64 only."""

    def __init__(self, params, ar=F64, form="sqrt"):
        if form not in FORMS:
            raise ValueError(f"form: {form!r} is not one of {FORMS}")
        if form == "sqrt" and ar is not F64:
            raise ValueError("form 'sqrt': the reference runs it in float64 only")
        self.ar = ar
        self.form = form
        p = {k: ar.real(v) for k, v in params.items()}
        validate(p)
        self.p = p
        self.wm, self.wc = weights(p)
        self.c = N + lambda_ut(p)
        if form == "sqrt":
            # its roots (the C init's): sqrt(|w_c,0|), sqrt(w_i), sqrt(n + lambda)
            self.sqrt_wc0 = math.sqrt(abs(self.wc[0]))
            self.sqrt_wi = math.sqrt(self.wc[1])
            self.sqrt_c = math.sqrt(self.c)
        self.use_ax = p["mg_use_ax"] == 1.0
        if form != "sqrt" and p["mg_pause_grade"] != 0.0 and self.use_ax:
            raise ValueError("mg_pause_grade: the square-root form only")
        if form != "sqrt" and p["mg_q_theta_hi"] != 0.0:
            raise ValueError("mg_q_theta_hi: the square-root form only")
        self.started = False
        # an optional observer of the innovations, None by default (then nothing is called):
        # probe(row, innovation, sd) with row "ax" or "v", the innovation y - z-hat and its
        # predicted sd, at each update of the square-root form (scripts/tools/
        # mass_headwind_study.py); it reads, never writes, so the filter computes the same
        self.probe = None

    # -- §4.1 start and restart -------------------------------------------------------------
    def _start(self, s):
        p = self.p
        self.x = [s.v, p["mg_m0"], p["mg_theta0"]]
        # the square-root form: S = diag(r_v, sd_m0, sd_theta0)
        self.S = [[p["mg_r_v"], 0.0, 0.0], [0.0, p["mg_sd_m0"], 0.0], [0.0, 0.0, p["mg_sd_theta0"]]]
        self.P = self.ar.store_cov([[p["mg_r_v"] ** 2, 0.0, 0.0], [0.0, p["mg_sd_m0"] ** 2, 0.0],
                                    [0.0, 0.0, p["mg_sd_theta0"] ** 2]])
        self.q_mv = p["mg_q_mv0"] ** 2 if p["mg_adaptive"] == 1.0 else 0.0
        self.adapt_elapsed = 0.0    # time since the start of the current adaptation period
        self.m_adapt = self.x[1]    # the mass at its start
        self.brake_left = 0.0       # pause left after the last braked sample, s
        self.shift_left = 0.0       # pause left after the last gear change, s
        self.curve_left = 0.0       # pause left after the last sample over mg_ay_max, s
        self.gear = s.gear
        self.slip_latched = False   # the ABS gate's latch (§4.2)
        self.v_free = True          # v uncorrelated with M: a start or a paused sample last (§4.2)
        self.chg_d = 0.0            # the change test's residual in this pause, m/s (§4.2)
        self.chg_on = False         # the change test tripped: the pause learns to its end
        self.u_prev = s.v if s.vx is None else s.vx   # the test's speed at the last sample
        # §4.7 the grade's two-level walk: the grade rate's low-pass, the mean of its square,
        # the level (False: mg_q_theta, True: mg_q_theta_hi) and the grade at the last sample
        self.wq_rate = 0.0
        self.wq_ms = 0.0
        self.wq_hi = False
        self.th_prev = self.x[2]
        # §4.8 the model-mismatch monitor's EMA of the ax row's normalised innovation
        self.mm_e = 0.0
        self.started = True

    def _estimate(self, status):
        if self.form == "sqrt":
            e_max = self.p["mg_mm_e"]
            return MgEstimate(self.x[1], self.sd[1], self.x[2], self.sd[2], self.x[0], self.sd[0],
                              self.q_mv, status, self.mm_e,
                              e_max > 0.0 and abs(self.mm_e) > e_max)
        P, sqrt = self.P, self.ar.sqrt
        return MgEstimate(self.x[1], sqrt(P[1][1]), self.x[2], sqrt(P[2][2]),
                          self.x[0], sqrt(P[0][0]), self.q_mv, status)

    def _check(self, s):
        vals = [s.t, s.v, s.torque] + [v for v in (s.brake, s.brake_pressure, s.gear, s.ax, s.vx,
                                                   s.ay) if v is not None]
        if not all(math.isfinite(v) for v in vals):
            return ERR_NONFINITE
        if abs(s.v) > V_MAX or abs(s.torque) > T_MAX:
            return ERR_RANGE
        if s.ax is not None and abs(s.ax) > AX_MAX:
            return ERR_RANGE
        if s.ay is not None and abs(s.ay) > AX_MAX:
            return ERR_RANGE
        if s.vx is not None and abs(s.vx) > V_MAX:
            return ERR_RANGE
        if self.use_ax and s.ax is None:
            return ERR_RANGE
        if self.started and not s.t > self.t_prev:
            return ERR_RANGE
        return OK

    def step(self, s: MgSample) -> MgEstimate:
        """One sample; an error status leaves the state as it was."""
        err = self._check(s)
        if err != OK:
            if not self.started:
                return MgEstimate(math.nan, math.nan, math.nan, math.nan, math.nan, math.nan,
                                  math.nan, err)
            return self._estimate(err)
        if self.form == "sqrt":
            return self._step_sqrt(s)
        p = self.p
        if not self.started or s.t - self.t_prev > p["mg_dt_max"]:
            self._start(s)
            status = self._pause_status(s, 0.0)
            self.t_prev, self.torque_prev = s.t, s.torque
            return self._estimate(status)
        saved = (self.brake_left, self.shift_left, self.curve_left, self.gear)
        dt = self.ar.real(s.t - self.t_prev)   # the period: the time stamps are not state
        status = self._pause_status(s, dt)
        if status != OK:
            self._hold(s, dt)
        else:
            st = self._update(s, dt)
            if st != OK:
                self.brake_left, self.shift_left, self.curve_left, self.gear = saved
                return self._estimate(st)
        self.t_prev, self.torque_prev = s.t, s.torque
        return self._estimate(status)

    # -- the square-root form (the C library's steps, mass_grade_flt.c) ------------------------
    _SAVED = ("x", "S", "q_mv", "adapt_elapsed", "m_adapt", "brake_left", "shift_left",
              "curve_left", "gear", "started", "slip_latched", "v_free", "chg_d", "chg_on",
              "u_prev", "wq_rate", "wq_ms", "wq_hi", "th_prev", "mm_e")

    def _step_sqrt(self, s):
        """As step(), in the square-root form: the work on a copy of the state, restored on an
        error (C: rfe_mass_grade_step works on a copy); a start, hold or update whose S, q_mv
        or sds are not finite is refused (17)."""
        p = self.p
        saved = {k: getattr(self, k, None) for k in self._SAVED}
        saved["x"] = list(saved["x"]) if saved["x"] is not None else None
        saved["S"] = [list(r) for r in saved["S"]] if saved["S"] is not None else None
        started = not self.started or s.t - self.t_prev > p["mg_dt_max"]
        if started:
            self._start(s)
            status = self._pause_status(s, 0.0)
            self._slip_latch(s, status)
            st = OK
        else:
            dt = s.t - self.t_prev             # the period: the time stamps are not state
            status = self._pause_status(s, dt)
            self._slip_latch(s, status)
            if status == OK:
                st = self._update_sqrt(s, dt)
            elif self._pause_grade(status) and not self.slip_latched and self._changed(s, dt):
                st = self._grade_ax_sqrt(s, dt)
            else:
                st = self._hold_sqrt(s, dt)
            if not (self._pause_grade(status) and not self.slip_latched):
                self.chg_d, self.chg_on = 0.0, False
            self.u_prev = s.v if s.vx is None else s.vx
        if st == OK:
            S = self.S
            sd = (math.sqrt(S[0][0] * S[0][0]), math.sqrt(S[1][0] * S[1][0] + S[1][1] * S[1][1]),
                  math.sqrt((S[2][0] * S[2][0] + S[2][1] * S[2][1]) + S[2][2] * S[2][2]))
            if not (all(math.isfinite(v) for r in S for v in r) and math.isfinite(self.q_mv)
                    and all(math.isfinite(v) for v in sd)):
                st = ERR_NONFINITE
        if st != OK:
            for k, v in saved.items():
                setattr(self, k, v)
            if not self.started:
                return MgEstimate(math.nan, math.nan, math.nan, math.nan, math.nan, math.nan,
                                  math.nan, st)
            return self._estimate(st)
        self.sd = sd
        if not started:
            self._walk_level(dt)
        # §4.2 v uncorrelated with M after a start or a paused sample (the hold sets S_Mv = 0,
        # the grade from ax keeps it), not after an update: decided from what the sample did,
        # not by S_Mv == 0, which an update's rounding can reach in one number type only
        # (C: rfe_mg_v_free)
        self.v_free = started or status != OK
        self.t_prev, self.torque_prev = s.t, s.torque
        return self._estimate(status)

    def _hold_sqrt(self, s, dt):
        """§4.2 the hold: S = [[r_v, 0, 0], [0, T]], T T^T = S_23 S_23^T + diag(0, q_theta^2 dt)
        by a 2 x 4 triangularisation of the mass and grade rows with the noise column."""
        p, S = self.p, self.S
        A = [[S[1][0], S[1][1], 0.0, 0.0],
             [S[2][0], S[2][1], S[2][2], self._q_theta() * math.sqrt(dt)]]
        if tria(A, 2, 4) is None:
            return ERR_NONFINITE
        self.x[0] = s.v
        self.S = [[p["mg_r_v"], 0.0, 0.0], [0.0, A[0][0], 0.0], [0.0, A[1][0], A[1][1]]]
        self.adapt_elapsed = 0.0
        self.m_adapt = self.x[1]
        return OK

    def _q_theta(self):
        """§4.7 the grade's random walk density for this sample's time update: mg_q_theta, or
        mg_q_theta_hi while the walk is loosened (mg_q_theta_hi 0: never)."""
        p = self.p
        return p["mg_q_theta_hi"] if self.wq_hi else p["mg_q_theta"]

    def _walk_level(self, dt):
        """§4.7 after each accepted sample but a start: with d the grade's change over it,
        r += d / tau - (dt / tau) r (the grade rate, low-passed, no division by dt) and
        s += (dt / avg) (r^2 - s) (its mean square); the walk loosens once s > rate_on^2
        and tightens once s < rate_off^2 (hysteresis), used from the next sample on."""
        p = self.p
        d = self.x[2] - self.th_prev
        self.th_prev = self.x[2]
        if p["mg_q_theta_hi"] == 0.0:
            return
        tau, avg = p["mg_theta_rate_tau"], p["mg_theta_rate_avg"]
        self.wq_rate += d / tau - (dt / tau) * self.wq_rate
        self.wq_ms += (dt / avg) * (self.wq_rate * self.wq_rate - self.wq_ms)
        on, off = p["mg_theta_rate_on"], p["mg_theta_rate_off"]
        if self.wq_hi:
            self.wq_hi = not self.wq_ms < off * off
        else:
            self.wq_hi = self.wq_ms > on * on

    def _pause_grade(self, status):
        """§4.2: the pause @status keeps learning the grade from ax (its bit of mg_pause_grade
        set) and v is uncorrelated with M (v_free: the last accepted sample was a start or a
        paused one, which leave S_Mv = 0; so the first sample of a pause that follows an update
        holds as before and the next ones learn)."""
        bit = PAUSE_GRADE_BITS.get(status, 0)
        bits = int(self.p["mg_pause_grade"]) if self.use_ax else 0   # the grade from ax needs ax
        return (bits & bit) != 0 and self.v_free

    def _changed(self, s, dt):
        """§4.2 the change test of a pause that may learn the grade: with u = vx if given,
        else v, the residual d += (u - u_prev) - dt (a_x - g sin theta) of the held grade
        theta, summed from the pause's first learning-eligible sample; the pause learns once
        |d| > mg_pause_grade_dv (a latch to the pause's end), and at once where
        mg_pause_grade_dv is 0. Held grades that a_x and the speed confirm stay untouched."""
        p = self.p
        if p["mg_pause_grade_dv"] == 0.0 or self.chg_on:
            return True
        u = s.v if s.vx is None else s.vx
        self.chg_d += (u - self.u_prev) - dt * (s.ax - p["g"] * math.sin(self.x[2]))
        self.chg_on = abs(self.chg_d) > p["mg_pause_grade_dv"]
        return self.chg_on

    def _slip_latch(self, s, status):
        """§4.2 the ABS gate of the grade from ax in a pause: the latch is set at a paused
        sample whose wheels slip, vx given, mg_pause_grade_slip > 0 and
        |v - vx| > mg_pause_grade_slip * max(|vx|, mg_v_min) (the wheels lock or cycle under
        the ABS: v-dot is not the car's), stays set through the rest of the pause and clears
        at the first sample that is not paused (and on a start that is not). While it is set,
        a pause whose bit of mg_pause_grade is set holds as without the bit."""
        p = self.p
        slip = (s.vx is not None and p["mg_pause_grade_slip"] > 0.0
                and abs(s.v - s.vx) > p["mg_pause_grade_slip"] * max(abs(s.vx), p["mg_v_min"]))
        self.slip_latched = status != OK and (self.slip_latched or slip)

    def _grade_ax_sqrt(self, s, dt):
        """§4.2 the grade from ax in a pause: M and its row of S (so P_MM, P_Mv = 0, P_Mtheta)
        untouched; v and theta run the kinematic model v-dot = a_x - g sin theta (ax as the
        input, its sd r_ax added to v's process noise) on S's columns 0 and 2 (theta given the
        held M: S_theta,M stays), then the speed row. An EKF step of two states:
        F = [[1, -g cos(theta) dt], [0, 1]]; [L 0] = Tria([F L, diag(q_v', q_theta sqrt dt)])
        with q_v'^2 = q_v^2 dt + (r_ax dt)^2, L = [[S_vv, 0], [S_theta,v, S_theta,theta]]; then
        one Givens rotation of L's column 0 with r_v."""
        p, S, x = self.p, self.S, self.x
        gc = p["g"] * math.cos(x[2]) * dt
        v = x[0] + dt * (s.ax - p["g"] * math.sin(x[2]))
        rax = p["mg_r_ax"] * dt
        qv = math.sqrt(p["mg_q_v"] * p["mg_q_v"] * dt + rax * rax)
        A = [[S[0][0] - gc * S[2][0], -gc * S[2][2], qv, 0.0],
             [S[2][0], S[2][2], 0.0, self._q_theta() * math.sqrt(dt)]]
        if tria(A, 2, 4) is None:
            return ERR_NONFINITE
        rv = p["mg_r_v"]
        sz = math.sqrt(A[0][0] * A[0][0] + rv * rv)
        if not sz > 0.0:
            return ERR_NOT_POSITIVE_DEFINITE
        if not math.isfinite(sz):
            return ERR_NONFINITE
        cs, sn, e = A[0][0] / sz, rv / sz, (s.v - v) / sz
        v += A[0][0] * cs * e
        th = x[2] + A[1][0] * cs * e
        if not (math.isfinite(v) and math.isfinite(th)):
            return ERR_NONFINITE
        x[0] = v
        x[2] = min(max(th, -p["mg_theta_max"]), p["mg_theta_max"])
        S[0][0] = A[0][0] * sn
        S[2][0] = A[1][0] * sn
        S[2][2] = A[1][1]
        self.adapt_elapsed = 0.0
        self.m_adapt = x[1]
        return OK

    def _update_sqrt(self, s, dt):
        """§4.3 in square-root form (mass_grade_ukf_flt.c), then the projection and the
        adaptation."""
        p, wm = self.p, self.wm
        w = (self.wc[0], self.sqrt_wc0, self.sqrt_wi)
        # time update: the points of (x, S) through f; Q's roots
        pts = sigma_points_sqrt(self.x, self.S, self.sqrt_c)
        X = [f_state(p, x, self.torque_prev, dt) for x in pts]
        sdt = math.sqrt(dt)
        sq = (p["mg_q_v"] * sdt, math.sqrt(p["mg_q_mc"] * p["mg_q_mc"] + self.q_mv) * sdt,
              self._q_theta() * sdt)
        xm = mean(X, wm)
        A = [[0.0] * (2 * N + 1 + N) for _ in range(N)]
        centred(X, xm, w, A, 0)
        for r in range(N):
            A[r][2 * N + 1 + r] = sq[r]
        if tria(A, N, 2 * N + 1 + N) is None:
            return ERR_NONFINITE
        if w[0] < 0.0 and downdate(A, N, [w[1] * (X[0][r] - xm[r]) for r in range(N)]) != OK:
            return ERR_NOT_POSITIVE_DEFINITE
        x = list(xm)
        S = [[A[r][c] if c <= r else 0.0 for c in range(N)] for r in range(N)]
        mm_e = self.mm_e
        # the ax row by the points of (x-, S-)
        if self.use_ax:
            pts = sigma_points_sqrt(x, S, self.sqrt_c)
            Z = [accel(p, q[0], q[1], q[2], s.torque) + p["g"] * math.sin(q[2]) for q in pts]
            zm = mean([[z] for z in Z], wm)
            A = [[0.0] * (2 * N + 2) for _ in range(1 + N)]
            centred([[z] for z in Z], zm, w, A, 0)
            centred(pts, x, w, A, 1)
            A[0][2 * N + 1] = p["mg_r_ax"]
            if tria(A, 1 + N, 2 * N + 2) is None:
                return ERR_NONFINITE
            if w[0] < 0.0:
                v = [w[1] * (Z[0] - zm[0])] + [w[1] * (pts[0][i] - x[i]) for i in range(N)]
                if downdate(A, 1 + N, v) != OK:
                    return ERR_NOT_POSITIVE_DEFINITE
            if not A[0][0] > 0.0:
                return ERR_NOT_POSITIVE_DEFINITE
            e = (s.ax - zm[0]) / A[0][0]
            if self.probe is not None:
                self.probe("ax", s.ax - zm[0], A[0][0])
            # §4.8 the monitor: EMA of the normalised innovation, dt / mg_mm_tau <= 1
            mm_e += (dt / p["mg_mm_tau"]) * (e - mm_e)
            for i in range(N):
                x[i] += A[1 + i][0] * e
            S = [[A[1 + i][1 + c] for c in range(N)] for i in range(N)]
        # the speed row: one Givens rotation of S's column 0 with r_v
        rv = p["mg_r_v"]
        sz = math.sqrt(S[0][0] * S[0][0] + rv * rv)
        innov = s.v - x[0]
        if not sz > 0.0:
            return ERR_NOT_POSITIVE_DEFINITE
        if not math.isfinite(sz):
            return ERR_NONFINITE               # S_00^2 overflowed (the C float build's check)
        cs, sn, e = S[0][0] / sz, rv / sz, innov / sz
        if self.probe is not None:
            self.probe("v", innov, sz)
        for i in range(N):
            g = S[i][0] * cs
            x[i] += g * e
            S[i][0] *= sn
        if not (all(math.isfinite(v) for v in x) and all(math.isfinite(v) for r in S for v in r)):
            return ERR_NONFINITE
        # §4.3 projection of the mean onto the bounds
        x[1] = min(max(x[1], p["mg_m_min"]), p["mg_m_max"])
        x[2] = min(max(x[2], -p["mg_theta_max"]), p["mg_theta_max"])
        self.x, self.S = x, S
        self.mm_e = mm_e
        if p["mg_adaptive"] == 1.0 and self.q_mv > 0.0:
            return self._adapt_sqrt(dt)
        return OK

    def _adapt_sqrt(self, dt):
        """§4.4 as _adapt, P's mass row and column scaled in square-root form: S' = Tria([D S,
        sqrt(lambda - lambda^2) |S row M| e2]), D = diag(1, lambda, 1)."""
        p, S = self.p, self.S
        self.adapt_elapsed += dt
        span = self.adapt_elapsed
        if span < p["mg_t_adapt"] - 0.5 * dt:
            return OK
        d = (self.x[1] - self.m_adapt) * (self.x[1] - self.m_adapt)
        qs = self.q_mv * span
        lam = 0.5 * abs(qs - d) / (qs + d) if qs + d > 0.0 else 0.5
        self.q_mv *= lam
        sd_m = math.sqrt(S[1][0] * S[1][0] + S[1][1] * S[1][1])
        A = [[S[0][0], 0.0, 0.0, 0.0],
             [lam * S[1][0], lam * S[1][1], 0.0, math.sqrt(lam - lam * lam) * sd_m],
             [S[2][0], S[2][1], S[2][2], 0.0]]
        if tria(A, N, 4) is None:
            return ERR_NONFINITE
        self.S = [[A[r][c] if c <= r else 0.0 for c in range(N)] for r in range(N)]
        if self.q_mv <= p["mg_mv_stop"] * (p["mg_q_mc"] * p["mg_q_mc"]):
            self.q_mv = 0.0
        self.adapt_elapsed = 0.0
        self.m_adapt = self.x[1]
        return OK

    # -- §4.2 pause logic ---------------------------------------------------------------------
    def _pause_status(self, s, dt):
        """§4.2; the delays count down by the sample period dt (0 on a start), so they stay
        as exact as the period in float32 however long the drive. A delay ends at the sample
        where less than half a period of it is left: a delay of whole periods then holds the
        same samples whatever the rounding of the periods' sum."""
        p = self.p
        self.brake_left = max(self.brake_left - dt, 0.0)
        self.shift_left = max(self.shift_left - dt, 0.0)
        self.curve_left = max(self.curve_left - dt, 0.0)
        brake = (s.brake is not None and s.brake >= 0.5) or (
            s.brake_pressure is not None and s.brake_pressure > p["mg_p_brake_on"])
        if brake:
            self.brake_left = p["mg_t_brake"]
        if s.gear is not None:
            if self.gear is not None and s.gear != self.gear:
                self.shift_left = p["mg_t_shift"]
            self.gear = s.gear
        # cornering: the drive torque also pays the tyres' cornering resistance and ax reads
        # the sideslip term -r vy, neither in the straight-road model (MASS_GRADE_RESULTS.md
        # "A curve pause"; 0: no curve pause)
        curve = s.ay is not None and p["mg_ay_max"] > 0.0 and abs(s.ay) > p["mg_ay_max"]
        if curve:
            self.curve_left = p["mg_t_curve"]
        if brake or self.brake_left > 0.5 * dt:
            return PAUSED_BRAKE
        if self.shift_left > 0.5 * dt:
            return PAUSED_SHIFT
        # the driven wheels slip: v (the wheels') departs from the car's vx, so T/r is not the
        # force that accelerates the car (0: no slip pause)
        if (s.vx is not None and p["mg_slip_max"] > 0.0
                and abs(s.v - s.vx) > p["mg_slip_max"] * max(abs(s.vx), p["mg_v_min"])):
            return PAUSED_SLIP
        if curve or self.curve_left > 0.5 * dt:
            return PAUSED_CURVE
        if s.v < p["mg_v_min"]:
            return NO_UPDATE_LOW_SPEED
        return OK

    def _hold(self, s, dt):
        """§4.2: M, theta held; theta's variance grows by its random walk; v restarts at the
        measured speed, uncorrelated; the adaptation's clock restarts."""
        p, P = self.p, self.P
        P[2][2] += p["mg_q_theta"] ** 2 * dt
        self.x[0] = s.v
        P[0][0] = p["mg_r_v"] ** 2
        for j in (1, 2):
            P[0][j] = 0.0
            P[j][0] = 0.0
        self.adapt_elapsed = 0.0
        self.m_adapt = self.x[1]
        self.P = self.ar.store_cov(P)

    # -- §3 and §4.3: one UKF step, then the adaptation ---------------------------------------
    def _update(self, s, dt):
        p, wm, wc, c = self.p, self.wm, self.wc, self.c
        # time update, eqs. (8)-(11): Q = diag(q_v^2, q_mc^2 + q_mv, q_theta^2) dt
        ar = self.ar
        pts = sigma_points(self.x, self.P, c, ar)
        if pts is None:
            return ERR_NOT_POSITIVE_DEFINITE
        prop = [f_state(p, x, self.torque_prev, dt, ar) for x in pts]
        xm = [0.0] * N
        for i in range(2 * N + 1):
            for r in range(N):
                xm[r] += wm[i] * prop[i][r]
        Pm = cov(prop, xm, prop, xm, wc)
        q = (p["mg_q_v"] ** 2 * dt, (p["mg_q_mc"] ** 2 + self.q_mv) * dt, p["mg_q_theta"] ** 2 * dt)
        for r in range(N):
            Pm[r][r] += q[r]
        Pm = ar.store_cov(Pm)
        # measurement update, eqs. (15)-(21), on points redrawn from (x_{t|t-1}, P_{t|t-1})
        pts = sigma_points(xm, Pm, c, ar)
        if pts is None:
            return ERR_NOT_POSITIVE_DEFINITE
        Z = [h_meas(p, x, s.torque, self.use_ax, ar) for x in pts]
        nz = len(Z[0])
        zm = [0.0] * nz
        for i in range(2 * N + 1):
            for r in range(nz):
                zm[r] += wm[i] * Z[i][r]
        S = cov(Z, zm, Z, zm, wc)
        S[0][0] += p["mg_r_v"] ** 2
        y = [s.v]
        if self.use_ax:
            S[1][1] += p["mg_r_ax"] ** 2
            y.append(s.ax)
        Pxz = cov(pts, xm, Z, zm, wc)
        Si = inverse(S)
        K = [[sum_ordered(Pxz[r][a] * Si[a][b] for a in range(nz)) for b in range(nz)]
             for r in range(N)]
        x = [xm[r] + sum_ordered(K[r][b] * (y[b] - zm[b]) for b in range(nz)) for r in range(N)]
        # eq. (21) P = P_{t|t-1} - K S K^T, upper triangle computed, then mirrored
        KS = [[sum_ordered(K[r][a] * S[a][b] for a in range(nz)) for b in range(nz)]
              for r in range(N)]
        P = [[0.0] * N for _ in range(N)]
        for r in range(N):
            for col in range(r, N):
                P[r][col] = Pm[r][col] - sum_ordered(KS[r][b] * K[col][b] for b in range(nz))
                P[col][r] = P[r][col]
        # §4.3 projection of the mean onto the bounds
        x[1] = min(max(x[1], p["mg_m_min"]), p["mg_m_max"])
        x[2] = min(max(x[2], -p["mg_theta_max"]), p["mg_theta_max"])
        self.x, self.P = x, ar.store_cov(P)
        if p["mg_adaptive"] == 1.0 and self.q_mv > 0.0:
            self._adapt(dt)
        return OK

    def _adapt(self, dt):
        """§4.4 eqs. (22)-(25), once per adaptation period mg_t_adapt (every step when 0);
        dt is this sample's period, added to the time since the period began. The period is
        over at the sample where less than half a sample period of it is left (as the pause
        delays, §4.2)."""
        p, P = self.p, self.P
        self.adapt_elapsed += dt
        span = self.adapt_elapsed
        if span < p["mg_t_adapt"] - 0.5 * dt:
            return
        d = (self.x[1] - self.m_adapt) ** 2      # (M_t - M_{t-1})^2 over the period
        qs = self.q_mv * span                    # q_mv over the same period, kg^2
        # eq. (24) as corrected (§4.4); 1/2, its limit at D = 0, where q_s underflowed to 0
        lam = 0.5 * abs(qs - d) / (qs + d) if qs + d > 0.0 else 0.5
        self.q_mv *= lam                         # eq. (23)
        for e in range(N):                       # eq. (25): p_2e = p_e2 <- lambda_u p_2e
            if e != 1:
                P[1][e] *= lam
                P[e][1] = P[1][e]
        P[1][1] *= lam
        self.P = self.ar.store_cov(P)
        if self.q_mv <= p["mg_mv_stop"] * p["mg_q_mc"] ** 2:
            self.q_mv = 0.0                      # q_22 has converged to q_mc: adaptation ends
        self.adapt_elapsed = 0.0
        self.m_adapt = self.x[1]


# ---- the square-root form's arithmetic (the C library's operations, in its order) ----------
TRIA_SAFE_LO = 2.0 ** -256  # qr_flt.c (double): rows with maxima inside are reduced unscaled
TRIA_SAFE_HI = 2.0 ** 256
DBL_MIN_EXP, DBL_MAX_EXP = -1021, 1024


# The three helpers below take the state's size n (default N, the filter's), so that a study
# with more states (scripts/tools/mass_offset_study.py, n = 4) runs the same operations.
def sigma_points_sqrt(x, S, sqrt_c, n=N):
    """§3 chi_0 = x, chi_i = x + d_i, chi_{n+i} = x - d_i, d_i = sqrt(n + lambda) S[:, i-1]."""
    d = [[sqrt_c * S[r][i] for r in range(n)] for i in range(n)]
    return ([list(x)] + [[x[r] + d[i][r] for r in range(n)] for i in range(n)]
            + [[x[r] - d[i][r] for r in range(n)] for i in range(n)])


def mean(X, wm, n=N):
    """sum_i w_m,i X_i, i = 0..2n in order."""
    m = [0.0] * len(X[0])
    for i in range(2 * n + 1):
        for r in range(len(m)):
            m[r] += wm[i] * X[i][r]
    return m


def centred(X, m, w, A, row0, n=N):
    """Columns 0..2n of A's rows row0..: sqrt(w_c,i) (X_i - m); the centre's 0 when w_c,0 < 0
    (w = (w_c,0, sqrt|w_c,0|, sqrt w_i))."""
    for i in range(2 * n + 1):
        sw = w[2] if i > 0 else (0.0 if w[0] < 0.0 else w[1])
        for r in range(len(m)):
            A[row0 + r][i] = sw * (X[i][r] - m[r])


def _scale_row(row, cols, e):
    """row[:cols] *= 2^e as qr_flt.c's scale_row: one factor while 2^e is normal."""
    if DBL_MIN_EXP - 1 <= e < DBL_MAX_EXP:
        if e != 0:
            f = math.ldexp(1.0, e)
            for j in range(cols):
                row[j] *= f
    else:
        for j in range(cols):
            row[j] = math.ldexp(row[j], e)


def tria(A, rows, cols):
    """The lower triangle S (rows x rows) of A Q = [S 0], S S^T = A A^T, in place: the
    Householder Tria of src/numerics/qr_flt.c (rfe_qr_tria) operation for operation (rows
    scaled by powers of two when a row maximum lies outside [2^-256, 2^256], each row's tail
    reflected onto its diagonal, the diagonal made nonnegative). None when A is not finite."""
    bigs, scaled = [], False
    for i in range(rows):
        big = 0.0
        for j in range(cols):
            if not math.isfinite(A[i][j]):
                return None
            a = abs(A[i][j])
            big = big if big > a else a      # rfe_max(big, |a|)
        if big > 0.0 and (big < TRIA_SAFE_LO or big > TRIA_SAFE_HI):
            scaled = True
        bigs.append(big)
    exps = [math.frexp(b)[1] if b > 0.0 else 0 for b in bigs]
    if scaled:
        for i in range(rows):
            _scale_row(A[i], cols, -exps[i])
    for k in range(rows):
        ss = 0.0
        for j in range(k, cols):
            ss += A[k][j] * A[k][j]
        norm = math.sqrt(ss)
        if norm > 0.0:
            x0 = A[k][k]
            sgn = -1.0 if x0 < 0.0 else 1.0
            vtv = 2.0 * norm * (norm + abs(x0))
            A[k][k] = x0 + sgn * norm
            for i in range(k + 1, rows):
                dot = 0.0
                for j in range(k, cols):
                    dot += A[i][j] * A[k][j]
                scale = 2.0 * dot / vtv
                for j in range(k, cols):
                    A[i][j] -= scale * A[k][j]
            A[k][k] = -sgn * norm
            for j in range(k + 1, cols):
                A[k][j] = 0.0
    for k in range(rows):
        if A[k][k] < 0.0:
            for i in range(k, rows):
                A[i][k] = -A[i][k]
    if scaled:
        for i in range(rows):
            _scale_row(A[i], i + 1, exps[i])
    return A


def downdate(L, k, v):
    """L' L'^T = L L^T - v v^T for the lower k x k L (nonnegative diagonal) in place, by
    hyperbolic rotations (mass_grade_ukf_flt.c downdate): OK, or ERR_NOT_POSITIVE_DEFINITE."""
    v = list(v)
    for j in range(k):
        ljj = L[j][j]
        r2 = (ljj - v[j]) * (ljj + v[j])
        if not r2 > 0.0:
            if ljj != 0.0 or v[j] != 0.0:
                return ERR_NOT_POSITIVE_DEFINITE
            continue
        rr = math.sqrt(r2)
        c, s = rr / ljj, v[j] / ljj
        L[j][j] = rr
        for i in range(j + 1, k):
            L[i][j] = (L[i][j] - s * v[i]) / c
            v[i] = c * v[i] - s * L[i][j]
    return OK


def sum_ordered(terms):
    """A sum in the order given (left to right), as the C port writes it."""
    s = 0.0
    for t in terms:
        s += t
    return s


def cov(A, am, B, bm, wc):
    """sum_i wc_i (A_i - am)(B_i - bm)^T, i = 0..2n in order."""
    out = [[0.0] * len(bm) for _ in range(len(am))]
    for i in range(2 * N + 1):
        da = [A[i][r] - am[r] for r in range(len(am))]
        db = [B[i][r] - bm[r] for r in range(len(bm))]
        for r in range(len(am)):
            for col in range(len(bm)):
                out[r][col] += wc[i] * da[r] * db[col]
    return out


def inverse(S):
    """1x1: 1/s; 2x2: the adjugate over the determinant."""
    if len(S) == 1:
        return [[1.0 / S[0][0]]]
    det = S[0][0] * S[1][1] - S[0][1] * S[1][0]
    return [[S[1][1] / det, -S[0][1] / det], [-S[1][0] / det, S[0][0] / det]]


# ---- logs ---------------------------------------------------------------------------------
def speed_from_wheels(cols, R):
    """§1 the speed input from a DATA.md log: the mean of the four wheel speeds times R."""
    import numpy as np
    om = np.column_stack([cols[f"omega_{w}"] for w in ("fl", "fr", "rl", "rr")])
    return (om[:, 0] + om[:, 1] + om[:, 2] + om[:, 3]) / 4.0 * R


def samples(cols, p):
    """MgSample per row of a log (dict column -> array): v from the wheels (speed_from_wheels),
    drive_torque, and brake, brake_pressure, gear, ax, ay where the log has them."""
    v = speed_from_wheels(cols, p["R"])
    n = len(v)
    keys = ("brake", "brake_pressure", "gear", "ax")
    opt = {k: cols.get(k) for k in keys + ("ay",)}
    for i in range(n):
        yield MgSample(float(cols["t"][i]), float(v[i]), float(cols["drive_torque"][i]),
                       *(None if opt[k] is None else float(opt[k][i]) for k in keys),
                       ay=None if opt["ay"] is None else float(opt["ay"][i]))


def run(cols, params, form="sqrt"):
    """Run a whole log; returns arrays t, mass, sd_mass, grade, sd_grade, v, sd_v, q_mv, status,
    walk (§4.7: the grade walk's level after each sample, 1 loose, 0 tight), e_ax and
    mismatch (§4.8: the monitor's EMA and its flag, 1 set)."""
    import numpy as np
    est = MassGrade(params, form=form)
    outs, walk = [], []
    for s in samples(cols, est.p):
        outs.append(est.step(s))
        walk.append(1 if est.wq_hi else 0)  # §4.7 the level after the step (the next one's)
    res = {"t": np.asarray(cols["t"], dtype=float)}
    for k in ("mass", "sd_mass", "grade", "sd_grade", "v", "sd_v", "q_mv", "status"):
        res[k] = np.array([getattr(o, k) for o in outs])
    res["walk"] = np.array(walk, dtype=int)
    res["e_ax"] = np.array([o.e_ax for o in outs])
    res["mismatch"] = np.array([1 if o.mismatch else 0 for o in outs], dtype=int)
    return res


def read_log(path):
    """A DATA.md log: (columns dict of float arrays, metadata dict of strings)."""
    import numpy as np
    meta, header, rows = {}, None, []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            if line.startswith("#"):
                k, _, v = line[1:].partition("=")
                meta[k.strip()] = v.strip()
            elif header is None:
                header = line.strip().split(",")
            else:
                rows.append(line)
    data = np.loadtxt(rows, delimiter=",", ndmin=2)
    return {c: data[:, j] for j, c in enumerate(header)}, meta
