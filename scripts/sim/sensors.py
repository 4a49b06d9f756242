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
    params = Params() if params is None else params
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
    """(key, value) metadata pairs of a log, DATA.md `# key = value` lines."""
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
