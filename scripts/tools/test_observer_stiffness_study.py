"""observer_stiffness_study.py and the reference observer's stiffness scale c_s (study option
obs_cs_on): off-equivalence bit for bit, convergence on a synthetic linear-tyre car of known
stiffness, the walk frozen in a steady turn, and the tool's truth ratios (no C build)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import observer_stiffness_study as study
from observer_results import ROOT
from reference import logs, observer, params
from sim.vehicle import Params as SimParams

LOG = ROOT / "scenarios" / "observer" / "dlc_mu035.csv"
ON = study.A


def _linear_car(c_true: float, steer, t_end: float, vx: float = 20.0, dt: float = 0.01):
    """A single-track car at constant vx whose axles' cornering stiffness is c_true cy per unit
    static axle load (linear tyres), noise-free; the columns run() takes, plus vy_true.
    Euler with 20 substeps per sample (the car's fastest pole is ~10 1/s, so the step is 0.5 ms:
    its integration error is far below what the asserts resolve)."""
    p = observer.params_with_defaults()
    m, lf, lr, jz, g = p["m"], p["Lf"], p["Lr"], p["J"], p["g"]
    la = lf + lr
    cf = c_true * p["cy"] * m * g * lr / la
    cr = c_true * p["cy"] * m * g * lf / la
    pos = observer.wheel_positions(p)
    n = int(round(t_end / dt)) + 1
    cols = {k: np.zeros(n) for k in ("t", "delta", "yaw_rate", "ax", "ay", "vy_true",
                                     "omega_fl", "omega_fr", "omega_rl", "omega_rr")}
    vy = r = 0.0
    sub = 20
    for k in range(n):
        t = k * dt
        d = steer(t)
        fyf = cf * (d - (vy + lf * r) / vx)
        fyr = cr * (-(vy - lr * r) / vx)
        ay = (fyf + fyr) / m
        cols["t"][k], cols["delta"][k], cols["yaw_rate"][k] = t, d, r
        cols["ay"][k], cols["ax"][k], cols["vy_true"][k] = ay, -r * vy, vy
        for i, (xi, yi) in enumerate(pos):
            di = d if i < 2 else 0.0
            vwx = (vx - r * yi) * math.cos(di) + (vy + r * xi) * math.sin(di)
            cols["omega_" + ("fl", "fr", "rl", "rr")[i]][k] = vwx / p["R"]
        for j in range(sub):
            dd = steer(t + j * dt / sub)
            fyf = cf * (dd - (vy + lf * r) / vx)
            fyr = cr * (-(vy - lr * r) / vx)
            vy, r = (vy + dt / sub * ((fyf + fyr) / m - r * vx),
                     r + dt / sub * (lf * fyf - lr * fyr) / jz)
    return cols, p


def _sine(t):
    return 0.015 * math.sin(2.0 * math.pi * 0.5 * (t - 1.0)) if t >= 1.0 else 0.0


def _dlc_head():
    """The first 6 s of the low-mu lane change, its parameters and a constant friction input
    (0.35, sd 0.1): the setup of the bit-for-bit tests."""
    log = logs.read_csv_log(str(LOG), required=("t",))
    c = {k: v[:600] for k, v in log.columns.items()}
    p = observer.params_with_defaults(params.from_metadata(log.meta))
    n = len(c["t"])
    return c, p, ([[0.35] * n] * 4, [[0.1] * n] * 4)


def test_with_its_prior_and_walk_zero_the_scale_is_todays_filter_bit_for_bit():
    # c_s fixed at 1 (sd 0, walk 0): every added term of the 3-state filter is an exact 0.0
    # and cy * 1.0 == cy, so the same process computes the same floats: exact equality is the
    # claim (a tolerance would hide an ordering change of the sums)
    c, p, mu = _dlc_head()
    base = observer.run(c, p, mu)
    same = observer.run(c, {**p, **ON, "obs_cs_sd0": 0.0, "obs_q_cs": 0.0}, mu)
    for key in observer.OUTPUTS:
        assert np.array_equal(base[key], same[key]), key
    assert np.all(same["cs"] == 1.0)
    # the control: with its prior sd the state moves, so the comparison above can fail
    moved = observer.run(c, {**p, **ON}, mu)
    assert not np.array_equal(base["vy"], moved["vy"])


@pytest.mark.parametrize("c_true", [0.5, 1.0])
def test_on_a_linear_tyre_car_the_scale_converges_to_its_stiffness_ratio(c_true):
    cols, p = _linear_car(c_true, _sine, 20.0)
    on = observer.run(cols, {**p, **ON})
    # the model's Magic Formula (C 1.3, E 0) bends as rho (1 - 0.364 rho^2); at this car's peak
    # utilisation (|ay| / g below 0.25 on the default mu 1, asserted) that is < 2.3 % of the
    # force, so the scale it fits lies within 2.3 % of c_true (0.023 at c_true 1, the tolerance);
    # the mean over the last 5 s takes out the walk's wander between the steering's peaks
    u = max(abs(a) for a in cols["ay"]) / p["g"]
    assert u < 0.25
    tail = on["cs"][-500:]
    assert abs(float(np.mean(tail)) - c_true) < 0.023
    # and the filter knows it learned: sd from the prior 0.3 to below a third of it (the walk
    # of 0.05 / sqrt(s) while excited keeps it above 0 by design)
    assert on["sd_cs"][-1] < 0.1
    if c_true != 1.0:
        # the learned stiffness is what the car needs: vy closer to the truth than today's
        # filter with the file's cy (half the RMSE at least; the slip is twice the file's)
        off = observer.run(cols, p)
        e_on = np.sqrt(np.mean((on["vy"][200:] - cols["vy_true"][200:]) ** 2))
        e_off = np.sqrt(np.mean((off["vy"][200:] - cols["vy_true"][200:]) ** 2))
        assert e_on < 0.5 * e_off


def test_in_a_steady_turn_the_walk_freezes_and_the_sd_does_not_grow():
    def ramp(t):  # a 1 s ramp to 0.02 rad, then held: r on r_ref, r-dot 0
        return 0.02 * min(max(t - 1.0, 0.0), 1.0)
    cols, p = _linear_car(0.7, ramp, 14.0)
    gated = observer.run(cols, {**p, **ON})
    free = observer.run(cols, {**p, **ON, "obs_cs_walk_all": 1.0})
    k4 = int(round(4.0 / 0.01))   # 2 s after the ramp: the yaw rate has settled on r_ref
    # frozen: the updates only shrink c_s's variance (1e-12: the sqrt of a variance that only
    # falls cannot rise by more than rounding)
    assert np.all(np.diff(gated["sd_cs"][k4:]) <= 1e-12)
    # the control: with the walk on every step the variance grows into the unobservable direction
    assert free["sd_cs"][-1] > gated["sd_cs"][-1] + 0.01


def test_the_truth_ratios_are_the_simulators_slope_and_secant():
    sp = SimParams()
    p = observer.params_with_defaults()
    n = 3
    c = dict(t=np.arange(n) * 0.01, vx_true=np.full(n, 20.0), vy_true=np.array([-0.2, 0.0, -0.5]),
             yaw_rate=np.zeros(n), **{f"mu_{w}": np.full(n, 0.35) for w in study.WHEELS})
    slope, secant = study.truth_ratios(c, p, sp, "dugoff")
    # the Dugoff truth's slope at zero slip is mu Cy_n per unit load (MODEL.md §4); the
    # difference quotient at 1e-6 rad differs by its velocity reduction eps vx 1e-6 ~ 3e-7
    assert slope == pytest.approx([0.35 * sp.Cy_n / p["cy"]] * n, abs=1e-5)
    assert secant[1] is None      # alpha_r = 0: below ALPHA_MIN
    # a Magic Formula truth with the model's own shape (C 1.3, E 0) and cy: both ratios are 1
    # (the inversion undoes the same formula: rounding only)
    mf = SimParams(mf_Cy=p["shape_Cy"], mf_Ey=p["shape_Ey"], cy=p["cy"])
    slope, secant = study.truth_ratios(c, p, mf, "mf")
    assert slope == pytest.approx([1.0] * n, abs=1e-6)
    assert secant[0] == pytest.approx(1.0, abs=1e-9)
    assert secant[2] == pytest.approx(1.0, abs=1e-9)


def test_as_a_consider_parameter_the_scale_keeps_its_prior_but_widens_vy():
    # obs_cs_consider with an excitation never met (|ay| >= 100 m/s^2): every row leaves c_s and
    # its variance (a Schmidt update), so both stay at the prior exactly (restored values, no
    # arithmetic); the filter still carries c_s's uncertainty into vy's, so vy's sd differs from
    # today's filter (the control that c_s is in the filter at all)
    cols, p = _linear_car(0.7, _sine, 6.0)
    cons = observer.run(cols, {**p, **ON, "obs_cs_consider": 1.0, "obs_cs_ay_on": 100.0})
    assert np.all(cons["cs"] == 1.0)
    assert np.all(cons["sd_cs"] == ON["obs_cs_sd0"])
    off = observer.run(cols, p)
    assert np.max(np.abs(cons["sd_vy"] - off["sd_vy"])) > 1e-3


# OBSERVER_RESULTS.md "The stiffness scale learned only where excited": variant D (C with c_s
# learned only where |ay| >= 1 m/s^2 and a transient excite it, a consider parameter elsewhere,
# relaxing to 1 with obs_cs_tau)
D = study.D


def test_the_relaxation_key_alone_and_d_with_a_fixed_scale_are_todays_filter_bit_for_bit():
    # off: obs_cs_tau without obs_cs_on changes nothing; D with c_s's prior sd and walk 0 keeps
    # c_s at exactly 1 (the relaxation's 1 + a (1 - 1) and (1 - a^2) 0 are exact), so every
    # number is today's: exact equality is the claim, as in the first test
    c, p, mu = _dlc_head()
    base = observer.run(c, p, mu)
    key_only = observer.run(c, {**p, "obs_cs_tau": D["obs_cs_tau"]}, mu)
    fixed = observer.run(c, {**p, **D, "obs_cs_sd0": 0.0, "obs_q_cs": 0.0}, mu)
    for key in observer.OUTPUTS:
        assert np.array_equal(base[key], key_only[key]), key
        assert np.array_equal(base[key], fixed[key]), key
    assert np.all(fixed["cs"] == 1.0)


def _noisy_straight(seed: int = 7, t_end: float = 60.0):
    """The linear car driving straight (steer 0), its delta and yaw-rate sensors with white
    noise of the observer's own sd's: the errors-in-variables case of the section above."""
    cols, p = _linear_car(0.9, lambda t: 0.0, t_end)
    rng = np.random.default_rng(seed)
    n = len(cols["t"])
    cols["delta"] = cols["delta"] + rng.normal(0.0, 0.001, n)
    cols["yaw_rate"] = cols["yaw_rate"] + rng.normal(0.0, p["obs_sd_r"], n)
    return cols, p


def test_the_gate_freezes_the_scale_on_a_straight():
    cols, p = _noisy_straight()
    assert max(abs(a) for a in cols["ay"]) < D["obs_cs_ay_on"]   # no step can be excited
    gated = observer.run(cols, {**p, **D})
    # no step is excited, every row leaves c_s (consider) and the relaxation holds 1 at 1:
    # exactly 1 on every step, and its sd stays the prior's (the OU step keeps sd0^2 at sd0^2
    # up to rounding: 1e-12)
    assert np.all(gated["cs"] == 1.0)
    assert np.all(np.abs(gated["sd_cs"] - D["obs_cs_sd0"]) < 1e-12)
    # the control: C ungated on the same straight moves c_s (the drift the gate is for)
    free = observer.run(cols, {**p, **study.LATER["C: model row only"]})
    assert np.max(np.abs(free["cs"] - 1.0)) > 0.01


def test_the_relaxation_has_its_time_constant():
    # from c_s 0.5 (sd 0.1, covariances with vy and b_y) the steps of one time constant take
    # c_s - 1 to e^-1 of it, c_s's covariances to e^-1 and its variance to sd0^2 + (P22 - sd0^2)
    # e^-2 (the OU process's exact discretisation: the product of n steps' a is exp(-n dt / tau)
    # up to n roundings, 6000 * 2.2e-16 ~ 1e-12, so 1e-10 tolerances)
    p = observer.params_with_defaults(**D)
    obs = observer.Observer(p)
    obs.lat.x = [0.1, 0.0, 0.5]
    obs.lat.P = [[0.04, 0.001, 0.002], [0.001, 0.01, 0.003], [0.002, 0.003, 0.01]]
    dt = 0.02
    n = int(round(p["obs_cs_tau"] / dt))
    for _ in range(n):
        obs.relax_cs(dt)
    e1 = math.exp(-1.0)
    s0 = p["obs_cs_sd0"] ** 2
    assert obs.lat.x[2] == pytest.approx(1.0 - 0.5 * e1, abs=1e-10)
    assert obs.lat.P[0][2] == pytest.approx(0.002 * e1, abs=1e-10)
    assert obs.lat.P[1][2] == pytest.approx(0.003 * e1, abs=1e-10)
    assert obs.lat.P[2][0] == obs.lat.P[0][2] and obs.lat.P[2][1] == obs.lat.P[1][2]
    assert obs.lat.P[2][2] == pytest.approx(s0 + (0.01 - s0) * e1 * e1, abs=1e-10)
    assert obs.lat.x[:2] == [0.1, 0.0] and obs.lat.P[0][0] == 0.04   # vy, b_y untouched
