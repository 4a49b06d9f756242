"""Sensor logs: noise-free sensor table from a simulation, additive sensor noise, CSV text.

Sensor log format: shared/docs/DATA.md.  Every row is the instantaneous true state of the
logged instant (the same derivative evaluation the simulator used there) plus, in the noisy
variant, additive white Gaussian noise with the standard deviations of NOISE_SD.  The noise
of a scenario comes from numpy Generator(PCG64(seed)), drawn as one (rows x NOISY_COLUMNS)
standard-normal block in the column order below, so a log is reproducible bit for bit.
No noise on t or on the truth columns mu_* and util_*.

Truth columns (scoring only; DATA.md readers ignore extra columns):
    mu_fl .. mu_rr      road friction under each wheel
    util_fl .. util_rr  tyre utilisation sqrt(Fx^2 + Fy^2)/(mu*Fz) of the truth tyre at that
                        sample (0 where mu*Fz = 0); mu*Fz is the peak force of both truth
                        tyres, so util near 1 means the wheel works at its friction limit.  Floats are written with repr() (shortest
round-trip form), so the noise-free log holds the simulator's doubles exactly.
"""

import numpy as np

from .scenarios import Scenario
from .vehicle import ESTIMATOR_KEYS, MF_KEYS, SIM_KEYS, Params, simulate

__all__ = ["WHEELS", "COLUMNS", "NOISE_SD", "NOISY_COLUMNS", "DEFAULT_RATE", "DT",
           "run", "sensor_table", "utilisation", "add_noise", "metadata", "csv_text", "file_name",
           "summary"]

WHEELS = ("fl", "fr", "rl", "rr")
COLUMNS = (["t", "delta", "vx", "vy", "yaw_rate", "yaw_acc", "ax", "ay"]
           + [f"omega_{w}" for w in WHEELS] + [f"mu_{w}" for w in WHEELS]
           + [f"util_{w}" for w in WHEELS])
NOISE_SD = dict([("delta", 0.001), ("vx", 0.05), ("vy", 0.05), ("yaw_rate", 0.005),
                 ("yaw_acc", 0.05), ("ax", 0.05), ("ay", 0.05)]
                + [(f"omega_{w}", 0.05) for w in WHEELS])
NOISY_COLUMNS = [c for c in COLUMNS if c in NOISE_SD]
DT = 0.01              # s, log period
DEFAULT_RATE = 4000    # Hz, RK4 integration rate (40 sub-steps per log step)


def run(sc: Scenario, tyre="dugoff", params=None, rate=DEFAULT_RATE, duration=None):
    """Simulate a scenario; returns the simulator output dict (vehicle.simulate)."""
    params = sc.truth_params(Params() if params is None else params)  # truth tyre (scenarios.py)
    return simulate(sc.make_inputs(params), sc.mu, sc.v0, sc.duration if duration is None else duration,
                    params, tyre, DT, rate)


def sensor_table(sim):
    """Noise-free sensor columns (dict column -> 1-D array) from a simulator output."""
    tab = {c: np.asarray(sim[c], dtype=float).copy()
           for c in ("t", "delta", "vx", "vy", "yaw_rate", "yaw_acc", "ax", "ay")}
    util = utilisation(sim)
    for i, w in enumerate(WHEELS):
        tab[f"omega_{w}"] = sim["omega"][:, i].copy()
        tab[f"mu_{w}"] = sim["mu"][:, i].copy()
        tab[f"util_{w}"] = util[:, i].copy()
    return tab


def utilisation(sim):
    """Truth tyre utilisation sqrt(Fx^2 + Fy^2)/(mu Fz), shape (N, 4); 0 where mu Fz = 0."""
    mu_fz = sim["mu"] * sim["Fz"]
    return np.divide(np.hypot(sim["Fx"], sim["Fy"]), mu_fz,
                     out=np.zeros_like(mu_fz), where=mu_fz > 0)


def add_noise(table, seed):
    """Copy of table with additive white Gaussian sensor noise (NOISE_SD), fixed seed."""
    rng = np.random.Generator(np.random.PCG64(seed))
    n = len(table["t"])
    z = rng.standard_normal((n, len(NOISY_COLUMNS)))
    out = {c: v.copy() for c, v in table.items()}
    for j, c in enumerate(NOISY_COLUMNS):
        out[c] = table[c] + NOISE_SD[c] * z[:, j]
    return out


def metadata(sc: Scenario, noise, tyre, params=None, rate=DEFAULT_RATE):
    """(key, value) metadata pairs of a log, DATA.md `# key = value` lines.  params: the
    vehicle's parameter file (default Params()), never the scenario's truth-tyre overrides."""
    params = Params() if params is None else params
    meta = [("scenario", sc.name), ("description", sc.description), ("dt", DT),
            ("seed", sc.seed if noise == "default" else "none"), ("noise", noise),
            ("truth_tyre", tyre), ("abs", "on" if sc.abs is not None else "off"),
            ("driver_steer", "yaw_controller" if sc.yaw is not None else "open_loop")]
    meta += params.items(ESTIMATOR_KEYS) + params.items(SIM_KEYS)
    if tyre == "mf":
        meta += params.items(MF_KEYS)
    meta += [(f"noise_{c}", NOISE_SD[c] if noise == "default" else 0.0)
             for c in NOISY_COLUMNS]
    meta += [("sim_integrator", "rk4"), ("sim_rate", rate), ("v0", sc.v0),
             ("duration", sc.duration)]
    # A truth tyre unlike the parameter file (scenarios.py, wrong_tyre_data): the keys above
    # keep the file's values; the truth's follow as information the estimator ignores.
    meta += [(f"truth_{k}", v) for k, v in sc.truth]
    return meta


def _fmt(v):
    if isinstance(v, float):
        return repr(v)
    return str(v)


def csv_text(table, meta):
    lines = [f"# {k} = {_fmt(v)}" for k, v in meta]
    lines.append(",".join(COLUMNS))
    cols = [table[c].tolist() for c in COLUMNS]
    for row in zip(*cols):
        lines.append(",".join(map(repr, row)))
    return "\n".join(lines) + "\n"


def file_name(name, tyre, noise):
    return name + (".mf" if tyre == "mf" else "") + (".nf" if noise == "none" else "") + ".csv"


def summary(sim):
    """Per-wheel maxima of |kappa|, |alpha| and utilisation sqrt(Fx^2+Fy^2)/(mu Fz), the
    per-wheel share of samples with utilisation >= 0.5 ("excited") and the minimum vx
    (informational: how far into the nonlinear tyre range a log goes)."""
    util = utilisation(sim)
    return dict(kappa=np.abs(sim["kappa"]).max(axis=0), alpha=np.abs(sim["alpha"]).max(axis=0),
                util=util.max(axis=0), excited=(util >= 0.5).mean(axis=0),
                min_vx=float(np.min(sim["vx"])))


# ---- observer scenarios (observer_scenarios.py): extra inputs and truth columns -------------
#
# Written only for the observer scenarios; the functions above (and so the friction logs)
# are unchanged.  Columns, in this order:
#     COLUMNS (as above; vx, vy and yaw_acc stand for an optical sensor on a test car, noisy
#              as above), then
#     p_fl..p_rr            applied wheel-cylinder brake pressure [MPa], noisy
#     torque_fl..torque_rr  applied drive torque at the wheel [N m], noisy
#     grade                 known road grade [rad] (only when the scenario declares it
#                           known), noisy
#     vx_true, vy_true      true CoG velocity, body axes [m/s]            (no noise)
#     beta_true             atan2(vy_true, vx_true) [rad]                 (no noise; 0 at
#                           exact standstill, ill-defined as vx -> 0)
#     yaw_acc_true          true r_dot [rad/s^2]                          (no noise)
#     grade_true, bank_true road grade and bank under the CoG [rad]       (no noise)
# ay carries the scenario's constant sensor bias ay_bias (a fault, not noise: in both
# variants), added before the noise.  The noise block is one (rows x OBS_NOISY_COLUMNS)
# standard-normal draw of Generator(PCG64(seed)) in column order, as add_noise.

OBS_INPUTS = [f"p_{w}" for w in WHEELS] + [f"torque_{w}" for w in WHEELS]
OBS_TRUTH = ["vx_true", "vy_true", "beta_true", "yaw_acc_true", "grade_true", "bank_true"]
OBS_NOISE_SD = dict(NOISE_SD, **{f"p_{w}": 0.02 for w in WHEELS},
                    **{f"torque_{w}": 5.0 for w in WHEELS}, grade=0.001)


def observer_columns(sc):
    return COLUMNS + OBS_INPUTS + (["grade"] if sc.grade_known else []) + OBS_TRUTH


def observer_noisy_columns(sc):
    return [c for c in observer_columns(sc) if c in OBS_NOISE_SD]


def run_observer(sc, tyre="dugoff", params=None, rate=None, duration=None):
    """Simulate an observer scenario at its own log period, rate, road, low-speed floor and
    driving resistances (none unless sc.res is set; then the output has "fx_ext")."""
    params = Params() if params is None else params
    ext = None if sc.res is None else sc.res.ext(params)
    return simulate(sc.make_inputs(params), sc.mu, sc.v0,
                    sc.duration if duration is None else duration, params, tyre, sc.dt,
                    sc.rate if rate is None else rate, sc.road, sc.v_low, ext=ext)


def observer_table(sim, sc):
    """Noise-free observer-log columns (the ay bias included) from a simulator output."""
    tab = sensor_table(sim)
    tab["ay"] = tab["ay"] + sc.ay_bias
    for i, w in enumerate(WHEELS):
        tab[f"p_{w}"] = sim["pressure"][:, i].copy()
        tab[f"torque_{w}"] = sim["drive"][:, i].copy()
    if sc.grade_known:
        tab["grade"] = np.asarray(sim["grade"], dtype=float).copy()
    tab["vx_true"] = np.asarray(sim["vx"], dtype=float).copy()
    tab["vy_true"] = np.asarray(sim["vy"], dtype=float).copy()
    tab["beta_true"] = np.arctan2(tab["vy_true"], tab["vx_true"])
    tab["yaw_acc_true"] = np.asarray(sim["yaw_acc"], dtype=float).copy()
    tab["grade_true"] = np.asarray(sim["grade"], dtype=float).copy()
    tab["bank_true"] = np.asarray(sim["bank"], dtype=float).copy()
    return tab


def observer_noise(table, sc):
    """Copy of an observer table with the sensor noise of OBS_NOISE_SD (seed sc.seed)."""
    rng = np.random.Generator(np.random.PCG64(sc.seed))
    cols = observer_noisy_columns(sc)
    z = rng.standard_normal((len(table["t"]), len(cols)))
    out = {c: v.copy() for c, v in table.items()}
    for j, c in enumerate(cols):
        out[c] = table[c] + OBS_NOISE_SD[c] * z[:, j]
    return out


def observer_metadata(sc, noise, tyre, params=None):
    """Metadata of an observer log: the friction logs' keys plus the observer options."""
    params = Params() if params is None else params
    meta = [("scenario", sc.name), ("description", sc.description), ("dt", sc.dt),
            ("seed", sc.seed if noise == "default" else "none"), ("noise", noise),
            ("truth_tyre", tyre), ("abs", "on" if sc.abs is not None else "off"),
            ("driver_steer", "path_follower" if sc.path is not None else
             "yaw_controller" if sc.yaw is not None else "open_loop"),
            ("drive_layout", sc.layout), ("tcs", "on" if sc.tcs is not None else "off"),
            ("cruise_control", "on" if sc.speed is not None else "off"),
            ("road", sc.road.text if sc.road is not None else "flat"),
            ("grade_known", "yes" if sc.grade_known else "no"), ("ay_bias", float(sc.ay_bias)),
            ("sim_v_low", "none" if sc.v_low is None else float(sc.v_low))]
    meta += params.items(ESTIMATOR_KEYS) + params.items(SIM_KEYS)
    if tyre == "mf":
        meta += params.items(MF_KEYS)
    meta += [(f"noise_{c}", OBS_NOISE_SD[c] if noise == "default" else 0.0)
             for c in observer_noisy_columns(sc)]
    meta += [("sim_integrator", "rk4"), ("sim_rate", sc.rate), ("v0", sc.v0),
             ("duration", sc.duration)]
    if sc.res is not None:   # the mass and grade logs' keys (DATA.md); none without
        r = sc.res
        meta += [("sim_fc", r.fc), ("sim_fr", r.fr), ("sim_rho", r.rho), ("sim_cd", r.cd),
                 ("sim_area", r.area), ("sim_wind", r.wind_text)]
    return meta


def observer_csv_text(table, meta, columns):
    lines = [f"# {k} = {_fmt(v)}" for k, v in meta]
    lines.append(",".join(columns))
    cols = [table[c].tolist() for c in columns]
    for row in zip(*cols):
        lines.append(",".join(map(repr, row)))
    return "\n".join(lines) + "\n"
