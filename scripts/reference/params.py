"""Parameters of the reference estimator (DATA.md "Parameter file", MODEL.md section 2).

Precedence: DEFAULTS < the sensor log's ``# key = value`` metadata lines (only known keys;
every other metadata key such as ``scenario``, ``dt``, ``seed``, ``kb_f``, ``Iw`` is
information and ignored) < an explicit parameter file (where an unknown key is an error
reported as ``file:line``).
"""

from __future__ import annotations

# Keys and defaults.  Order here is the order they are written into estimate-log metadata.
DEFAULTS: dict[str, float] = {
    # vehicle (MODEL.md section 2)
    "m": 1830.0,          # mass, kg
    "Lf": 1.40,           # CoG to front axle, m
    "Lr": 1.65,           # CoG to rear axle, m
    "Bf": 1.60,           # front track, m
    "Br": 1.60,           # rear track, m
    "R": 0.325,           # effective rolling radius, m
    "J": 3234.0,          # yaw moment of inertia, kg m^2
    "hg": 0.54,           # CoG height, m
    "g": 9.81,            # gravity, m/s^2
    # tyre (MODEL.md section 4)
    "Cx_n": 20.0,         # normalised longitudinal stiffness, paper mode, 1/rad
    "Cy_n": 15.0,         # normalised cornering stiffness, paper mode, 1/rad
    "cx": 20.0,           # longitudinal stiffness per unit Fz, absolute mode
    "cy": 15.0,           # cornering stiffness per unit Fz, absolute mode
    "eps": 0.015,         # Dugoff velocity-reduction factor, s/m
    "v_min": 0.5,         # slip denominator guard, m/s (MODEL.md section 3)
    "alpha_max": 1.4,     # slip-angle bound, rad (MODEL.md section 4)
    "shape_Cx": 1.65,     # Magic Formula shape factor C, longitudinal (tyre = magic)
    "shape_Ex": 0.0,      # Magic Formula curvature factor E, longitudinal
    "shape_Cy": 1.3,      # Magic Formula shape factor C, lateral
    "shape_Ey": 0.0,      # Magic Formula curvature factor E, lateral
    # filter (MODEL.md section 6)
    "mu0": 0.5,           # initial estimate on every wheel
    "sd0": 0.3,           # initial standard deviation, S0 = sd0 I
    "q_mu": 0.003,        # process noise sd per step, S_Q = q_mu I
    "r_ax": 0.05,         # measurement noise sd of ax, m/s^2
    "r_ay": 0.05,         # measurement noise sd of ay, m/s^2
    "r_yaw_acc": 0.05,    # measurement noise sd of yaw acceleration, rad/s^2
    "mu_min": 0.05,       # projection bounds of the mean
    "mu_max": 1.2,
    "v_est_min": 3.0,     # below this logged vx: time update only (status 2), m/s
    # observability-aware additions (docs/ESTIMATOR.md); these values switch them all off,
    # which is the paper preset
    "sd0_common": 0.0,    # prior sd, common-mode part
    "q_common": 0.0,      # process-noise sd per step, common-mode part
    "dt": 0.01,           # sample period, s
    "tau_v": 0.0,         # complementary-filter time constant for vx, vy, s (0: off)
    "sd_in_delta": 0.0,   # input noise sd of delta, rad (errors in variables)
    "sd_in_vx": 0.0,      # input noise sd of the filtered vx, m/s
    "sd_in_vy": 0.0,      # input noise sd of the filtered vy, m/s
    "sd_in_yaw_rate": 0.0,  # input noise sd of r, rad/s
    "sd_in_omega": 0.0,   # input noise sd of each wheel speed, rad/s
    "r_model_rel": 0.0,   # tyre-model error relative to each predicted acceleration
    "info_min": 0.0,      # Fisher-information gate, 1/mu^2 (0: off)
    "sd_max": 0.0,        # bound on every sd (0: off)
    "sd_floor_rel": 0.0,  # floor on sd as a fraction of mu (0: off)
    "sd_valid": 0.0,      # valid when sd <= sd_valid, off the mu bounds (0: valid when updated)
    "rear_hold_k": 0.0,   # sides: a move beyond this many sd holds the rear wheels (0: off)
    "jump_hold_k": 0.0,   # sides: a step moving beyond this many sd holds both wheels (0: off)
    "jump_hold_len": 0.0,  # the distance that jump hold lasts, m
    "stale_omega": 0.0,   # a repeated wheel speed while the others' median moved more: stale, rad/s (0: off)
    "yaw_check": 0.0,     # a yaw rate this far from its prediction is replaced by it, rad/s (0: off)
    "valid_bound_k": 0.0,  # the bound margin: valid only mu - mu_min >= this many sd (0: off)
    # step 9 (ESTIMATOR.md, MONITOR.md sections 10, 22): the upper evidence. Per state the
    # evidence L against mu + evid_up_delta, L <- rho L + Lambda at every update (rho =
    # exp(-1 / evid_up_n)), 0 while the monitor reports a mismatch; valid only while L >= l_min
    "evid_up_delta": 0.0,  # the upper alternative's distance, mu (0: off, today's flags)
    "evid_up_n": 100.0,    # L's memory, updates (1 .. 10000)
    "evid_up_l_min": 0.25,  # the evidence a valid flag needs, nats (0 .. 100)
    # step 5, reference only (MONITOR.md section 16): where the gate judges the information
    "info_at": 0.0,       # 0: at the estimate; 1: also at the hypothesis info_mu_h (both sides);
    #                       2: also around the cubature point whose prediction is nearest the data
    "info_mu_h": 0.3,     # info_at 1's hypothesis, mu
    # steps 5-6, reference only (MONITOR.md section 17): a step the gate opens only at the
    # second centre c (info_at > 0) as a test of hypotheses
    "hyp_update": 0.0,    # 1: that step's update linearised at c (the points moved by c - x); 0: at x
    "hyp_lr_min": 0.0,    # > 0: that step is taken only while the accumulated log likelihood ratio
    #                       of c against x (CUSUM, reset at a step the estimate's gate opens)
    #                       reaches this many nats, else held (status 3); 0: off
    "hyp_warmup": 0.0,    # the first this many s of evaluated steps give hyp_lr_min no evidence
    #                       (a step opened only at c is then held; the monitor's mon_warmup), s
    "lower_bound_delta": 0.0,  # step 6, reference only: a side's downward move is skipped when the
    #                            data's information at mu + this is below info_min (0: off)
    # step 6, reference only (MONITOR.md section 14): accumulated-evidence censoring. A side's
    # downward move is skipped while its evidence L against mu + evid_delta is below evid_l_min
    "evid_delta": 0.0,    # the upper alternative's distance (0: off)
    "evid_l_min": 2.0,    # the evidence a downward move needs (2: a 95 % sequential test)
    "evid_n": 100.0,      # L's memory, updates: L <- exp(-1 / evid_n) L + Lambda at each update
    "evid_l0": 0.0,       # L at the start of a run (the prior's level; 0: no evidence yet)
    "evid_free": 0.0,     # a side is never censored before this many updates on its own information
    "evid_cap": 0.0,      # 1: a side whose upper alternative mu_max clips (x + evid_delta > mu_max)
    #                       is not censored (at the bound its evidence cannot build up); 0: it is
    # step 7, reference only (MONITOR.md section 19): an sd floor that does not fall with a low
    # or a dropped mean. The floor on side k is sd_floor_rel * max(x_k, sd_floor_ref,
    # the largest x_k of the last sd_floor_hold s)
    "sd_floor_ref": 0.0,  # the floor never below sd_floor_rel * this mu (0: off)
    "sd_floor_hold": 0.0,  # the floor follows the largest mean of this many s (0: off), s
    # step 6, reference only (MONITOR.md section 20): an update claims no more information than
    # the data carry at the mean: after it, S is scaled (one factor) so that no variance is below
    # the posterior of the local linearisation, J = dh/dx at sd_local_at's mean by central
    # differences of step sd_local
    "sd_local": 0.0,      # the central differences' step, mu (0: off)
    "sd_local_at": 0.0,   # 0: J at the prior mean x-; 1: at the posterior mean x+
    # step 6, reference only (MONITOR.md section 21): the update re-linearised. relin_steps N:
    # the recursive update (N sub-updates with R N, points regenerated before each);
    # relin_iter M: the iterated posterior linearisation (M iterations, the statistical
    # linear regression at the current posterior applied to the prior); one of the two
    "relin_steps": 0.0,   # N sub-updates (0: off; 1: today's update)
    "relin_iter": 0.0,    # M iterations (0: off; 1: today's update)
    "relin_gate": 0.0,    # 1: the final linearisation's information must pass info_min too,
    #                       else the step is undone (0: today's gate only)
    # model-validity monitor (docs/MONITOR.md section 2; monitor.py); on in the default preset
    "mon_enable": 0.0,    # 1: acts on valid, status, sd (SCKF); 0: off
    "mon_tau_nis": 0.5,   # time constant of the NIS average D, s
    "mon_tau_mean": 0.5,  # time constant of the innovation means M_r and shares, s
    "mon_p_fire": 1e-3,   # per-step probability, under the model, of exceeding a fire threshold
    "mon_p_clear": 0.1,   # the same for the clear thresholds (mon_p_fire < mon_p_clear < 1)
    "mon_hold": 0.5,      # shortest time fired after the last exceedance, s
    "mon_warmup": 1.0,    # evaluated steps at the start that only count, s
    "mon_inflate": 1.0,   # 1: reported sd x sqrt(max(1, D/3)) while fired; 0: sd untouched
}

# Keys of the reference only (not in the C library yet; docs/ESTIMATOR.md): an estimate log
# records them only when set, so the goldens (the library's keys) stay as they are.
REFERENCE_ONLY = frozenset({"info_at", "info_mu_h", "hyp_update", "hyp_lr_min",
                            "hyp_warmup",
                            "lower_bound_delta", "evid_delta",
                            "evid_l_min", "evid_n", "evid_l0", "evid_free", "evid_cap",
                            "sd_floor_ref", "sd_floor_hold", "sd_local", "sd_local_at",
                            "relin_steps", "relin_iter", "relin_gate",
                            "evid_up_delta", "evid_up_n", "evid_up_l_min"})

# Keys an estimate log records, all of them, only while the rule they belong to is on (its
# first key > 0), so that the logs and goldens of runs without it stay as they were: step 9's
# upper evidence (reference only on main; its C port, MONITOR.md section 22, wrote them alike).
WHEN_ON = {"evid_up_delta": ("evid_up_delta", "evid_up_n", "evid_up_l_min")}
WHEN_ON_KEYS = frozenset(k for keys in WHEN_ON.values() for k in keys)

# The two presets (docs/ESTIMATOR.md): numeric values and the word-valued choices.
PRESETS: dict[str, dict] = {
    "paper": {"structure": "wheels", "tyre": "paper"},
    "default": {
        "structure": "sides", "tyre": "magic",
        "sd0": 0.1, "sd0_common": 0.3, "q_mu": 0.002, "q_common": 0.006,
        "tau_v": 0.3, "sd_in_delta": 0.001, "sd_in_vx": 0.01, "sd_in_vy": 0.01,
        "sd_in_yaw_rate": 0.005, "sd_in_omega": 0.05, "r_model_rel": 0.05,
        "info_min": 25.0, "sd_max": 0.32, "sd_floor_rel": 0.15, "sd_valid": 0.15,
        "rear_hold_k": 2.0, "jump_hold_k": 2.0, "jump_hold_len": 1.5, "mon_enable": 1.0,
        "stale_omega": 0.25, "yaw_check": 0.1, "valid_bound_k": 3.0,
    },
}


class ParamError(ValueError):
    """A malformed or unknown entry in a parameter file."""


def _parse_line(line: str):
    """Split ``key = value`` (comments after '#' removed). Returns None for blank lines."""
    body = line.split("#", 1)[0].strip()
    if not body:
        return None
    if "=" not in body:
        raise ValueError("expected 'key = value'")
    key, value = body.split("=", 1)
    key, value = key.strip(), value.strip()
    if not key:
        raise ValueError("empty key")
    return key, value


def read_param_file(path: str) -> dict[str, float]:
    """Read an explicit parameter file; unknown keys and bad values raise ParamError(file:line)."""
    out: dict[str, float] = {}
    with open(path, encoding="utf-8") as fh:
        for lineno, line in enumerate(fh, 1):
            where = f"{path}:{lineno}"
            try:
                kv = _parse_line(line)
            except ValueError as exc:
                raise ParamError(f"{where}: {exc}: {line.rstrip()!r}") from None
            if kv is None:
                continue
            key, value = kv
            if key not in DEFAULTS:
                raise ParamError(f"{where}: unknown parameter key {key!r}")
            try:
                out[key] = float(value)
            except ValueError:
                raise ParamError(f"{where}: value of {key!r} is not a number: {value!r}") from None
    return out


def from_metadata(meta: dict[str, str], source: str = "log") -> dict[str, float]:
    """Known parameter keys from a sensor log's ``# key = value`` metadata; others ignored."""
    out: dict[str, float] = {}
    for key, value in meta.items():
        if key in DEFAULTS:
            try:
                out[key] = float(value)
            except ValueError:
                raise ParamError(f"{source}: metadata {key!r} is not a number: {value!r}") from None
    return out


def resolve(meta: dict[str, str] | None = None, param_file: str | None = None,
            source: str = "log", preset: str = "paper") -> dict:
    """Preset < log metadata < parameter file. Numeric keys, plus 'structure' and 'tyre'."""
    if preset not in PRESETS:
        raise ParamError(f"unknown preset {preset!r}")
    p: dict = dict(DEFAULTS)
    p.update(PRESETS[preset])
    if meta:
        p.update(from_metadata(meta, source))
    if param_file:
        p.update(read_param_file(param_file))
    return p
