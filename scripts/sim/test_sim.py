"""Tests of the reference vehicle simulator (pytest, about 25 s).

    .venv/bin/python -m pytest scripts/sim -q

Tolerances:
    MODEL_RTOL = 1e-9   model match: H(u)*mu_truth against logged [ax, ay, yaw_acc], relative
                        (plus MODEL_ATOL = 1e-12 for values that are exactly zero); the sim
                        solves its load fixed point to 1e-12 and logs repr() doubles, so
                        anything above ~1e-13 means the sim and MODEL.md disagree.
    VEC_RTOL = 1e-9     against shared/vectors/model_vectors.csv (MODEL.md's own figure).
    noise: sample sd within 10 % of the stated sd (N ~ 1000: sampling sd ~2.2 %, so ~4.5
           sigma), sample mean within 4.5 sd/sqrt(N).
"""

import csv
import io
import math
from pathlib import Path

import numpy as np
import pytest

from . import sensors, tyres
from .scenarios import BY_NAME, MSB_T, MSB_MU, P_HARD, SCENARIOS
from .vehicle import Params, load_coefficients, loads, wheel_slips

MODEL_RTOL = 1e-9
MODEL_ATOL = 1e-12
VEC_RTOL = 1e-9
NOISE_SD_RTOL = 0.10
NOISE_MEAN_SIGMAS = 4.5

REPO = Path(__file__).resolve().parents[2]
SCEN_DIR = REPO / "scenarios"
# The in-repo copy of shared/vectors (kept in sync by `make vectors`).
VECTOR_FILE = REPO / "test" / "vectors" / "model_vectors.csv"
WHEELS = sensors.WHEELS
P = Params()


# ---------------------------------------------------------------------------------------
# Independent vectorised implementation of MODEL.md sections 3-5 (numpy, per row)
# ---------------------------------------------------------------------------------------
def model_eval(p, delta, vx, vy, r, ax, ay, omega):
    """Rows -> dict(kappa, alpha, fz, f0x, f0y (N,4), H (N,3,4)), straight from MODEL.md."""
    delta, vx, vy, r, ax, ay = (np.asarray(a, float)[:, None] for a in (delta, vx, vy, r, ax, ay))
    omega = np.asarray(omega, float)
    xi = np.array([p.Lf, p.Lf, -p.Lr, -p.Lr])
    yi = np.array([p.Bf / 2, -p.Bf / 2, p.Br / 2, -p.Br / 2])
    d = np.where(np.array([True, True, False, False]), delta, 0.0)
    vxi, vyi = vx - r * yi, vy + r * xi
    vwx = vxi * np.cos(d) + vyi * np.sin(d)
    vwy = -vxi * np.sin(d) + vyi * np.cos(d)
    alpha = np.clip(-np.arctan2(vwy, np.abs(vwx)), -p.alpha_max, p.alpha_max)
    wr = omega * p.R
    kappa = np.clip((wr - vwx) / np.maximum(np.maximum(np.abs(wr), np.abs(vwx)), p.v_min), -1, 1)
    La = p.Lf + p.Lr
    m, g, hg = p.m, p.g, p.hg
    fz = np.concatenate([
        m * g * p.Lr / (2 * La) - m * ax * hg / (2 * La) - m * ay * hg * p.Lr / (La * p.Bf),
        m * g * p.Lr / (2 * La) - m * ax * hg / (2 * La) + m * ay * hg * p.Lr / (La * p.Bf),
        m * g * p.Lf / (2 * La) + m * ax * hg / (2 * La) - m * ay * hg * p.Lf / (La * p.Br),
        m * g * p.Lf / (2 * La) + m * ax * hg / (2 * La) + m * ay * hg * p.Lf / (La * p.Br)],
        axis=1)
    fz = np.maximum(fz, 0.0)
    ta = np.tan(alpha)
    S = np.hypot(p.Cx_n * kappa, p.Cy_n * ta)
    e = np.maximum(1 - p.eps * np.abs(vwx) * np.sqrt(kappa ** 2 + ta ** 2), 0.0)
    a = 1 - np.abs(kappa)
    with np.errstate(divide="ignore", invalid="ignore"):
        L = np.where(S > 0, a * e / (2 * S), np.inf)
        f = np.where(L < 1, L * (2 - L), 1.0)
        # f(L)/(1-|kappa|): plain division where safe, the L<1 limit e(2-L)/(2S) near |kappa|=1
        fac = np.where(a > 1e-6, f / a, np.where(L < 1, e * (2 - L) / (2 * S), 1.0 / a))
    f0x = fz * p.Cx_n * kappa * fac
    f0y = fz * p.Cy_n * ta * fac
    c, s = np.cos(delta[:, 0]), np.sin(delta[:, 0])
    H = np.zeros((len(c), 3, 4))
    for i in range(4):
        if i < 2:
            bx = f0x[:, i] * c - f0y[:, i] * s
            by = f0x[:, i] * s + f0y[:, i] * c
        else:
            bx, by = f0x[:, i], f0y[:, i]
        H[:, 0, i] = bx / p.m
        H[:, 1, i] = by / p.m
        H[:, 2, i] = (xi[i] * by - yi[i] * bx) / p.J
    return dict(kappa=kappa, alpha=alpha, fz=fz, f0x=f0x, f0y=f0y, H=H)


def read_log_text(text):
    """Sensor-log text -> (meta dict, columns dict)."""
    meta, lines = {}, []
    for line in text.splitlines():
        if line.startswith("#"):
            k, _, v = line[1:].partition("=")
            meta[k.strip()] = v.strip()
        elif line:
            lines.append(line)
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    header = rows[0]
    data = np.array([[float(x) for x in row] for row in rows[1:]])
    return meta, {h: data[:, j] for j, h in enumerate(header)}


def check_model_match(cols, p=P):
    om = np.stack([cols[f"omega_{w}"] for w in WHEELS], axis=1)
    mu = np.stack([cols[f"mu_{w}"] for w in WHEELS], axis=1)
    res = model_eval(p, cols["delta"], cols["vx"], cols["vy"], cols["yaw_rate"],
                     cols["ax"], cols["ay"], om)
    pred = np.einsum("nij,nj->ni", res["H"], mu)
    meas = np.stack([cols["ax"], cols["ay"], cols["yaw_acc"]], axis=1)
    err = np.abs(pred - meas)
    bound = MODEL_RTOL * np.abs(meas) + MODEL_ATOL
    worst = float(np.max(err / bound))
    assert worst <= 1.0, f"model mismatch: worst err/bound = {worst:.3g}"
    return res


# ---------------------------------------------------------------------------------------
# Fixtures (simulations shared by several tests)
# ---------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def mu_step():
    sc = BY_NAME["paper_mu_step"]
    sim = sensors.run(sc)
    return sc, sim, sensors.sensor_table(sim)


SHORT_RUNS = {"split_mu_brake": 3.0, "brake_in_turn": 3.5, "sine_steer_low_mu": 2.0,
              "accel_low_mu": 2.5}


@pytest.fixture(scope="module", params=sorted(SHORT_RUNS))
def short_run(request):
    sc = BY_NAME[request.param]
    sim = sensors.run(sc, duration=SHORT_RUNS[request.param])
    return sc, sim


# ---------------------------------------------------------------------------------------
# MODEL.md conformance
# ---------------------------------------------------------------------------------------
def _vectors():
    lines = [l for l in VECTOR_FILE.read_text().splitlines() if l and not l.startswith("#")]
    rows = list(csv.DictReader(lines))
    return rows, {k: np.array([float(r[k]) for r in rows]) for k in rows[0] if k != "case"}


def _wheels(v, name):
    return np.stack([v[f"{name}_{w}"] for w in WHEELS], axis=1)


def _close(a, b, rtol, atol=1e-12):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.all(np.abs(a - b) <= rtol * np.abs(b) + atol * max(1.0, float(np.max(np.abs(b)))))


# REQ-SIM-001
def test_independent_model_reproduces_shared_vectors():
    _, v = _vectors()
    res = model_eval(P, v["delta"], v["vx"], v["vy"], v["yaw_rate"], v["ax"], v["ay"],
                     _wheels(v, "omega"))
    for key, col in (("kappa", "kappa"), ("alpha", "alpha"), ("fz", "fz"),
                     ("f0x", "f0x"), ("f0y", "f0y")):
        assert _close(res[key], _wheels(v, col), VEC_RTOL), key
    H = np.stack([v[f"H{i}{j}"] for i in (1, 2, 3) for j in (1, 2, 3, 4)], axis=1)
    assert _close(res["H"].reshape(-1, 12), H, VEC_RTOL)


# REQ-SIM-001
def test_simulator_model_functions_reproduce_shared_vectors():
    rows, v = _vectors()
    for k in range(len(rows)):
        om = [v[f"omega_{w}"][k] for w in WHEELS]
        vwx, kap, alp = wheel_slips(P, v["delta"][k], v["vx"][k], v["vy"][k],
                                    v["yaw_rate"][k], om)
        fz = loads(P, v["ax"][k], v["ay"][k])
        f0 = [tyres.dugoff_normalised(kap[i], alp[i], abs(vwx[i]), fz[i], P) for i in range(4)]
        case = rows[k]["case"]
        assert _close(kap, _wheels(v, "kappa")[k], VEC_RTOL), case
        assert _close(alp, _wheels(v, "alpha")[k], VEC_RTOL), case
        assert _close(fz, _wheels(v, "fz")[k], VEC_RTOL), case
        assert _close([f[0] for f in f0], _wheels(v, "f0x")[k], VEC_RTOL), case
        assert _close([f[1] for f in f0], _wheels(v, "f0y")[k], VEC_RTOL), case


# REQ-SIM-001
def test_model_match_mu_step_written_log(mu_step):
    """The key property: the noise-free log as written (repr doubles) is model-matched."""
    sc, sim, table = mu_step
    text = sensors.csv_text(table, sensors.metadata(sc, "none", "dugoff"))
    meta, cols = read_log_text(text)
    assert list(cols) == sensors.COLUMNS
    assert np.array_equal(cols["t"], np.arange(1001) / 100.0)  # 0.00 .. 10.00 s, 100 Hz
    assert meta["dt"] == "0.01" and meta["seed"] == "none" and meta["noise"] == "none"
    for c in sensors.COLUMNS:
        assert np.array_equal(cols[c], table[c]), c  # repr round-trips exactly
    res = check_model_match(cols)
    # the logged instant is the one the simulator used: same loads, same slips
    assert np.allclose(res["fz"], sim["Fz"], rtol=1e-12, atol=0)
    assert np.allclose(res["kappa"], sim["kappa"], rtol=1e-12, atol=1e-15)


# REQ-SIM-001
def test_model_match_combined_slip(short_run):
    sc, sim = short_run
    res = check_model_match(sensors.sensor_table(sim))
    # and the forces themselves (not only their sums) are mu * F0
    assert np.allclose(sim["Fx"], sim["mu"] * res["f0x"], rtol=1e-10, atol=1e-9)
    assert np.allclose(sim["Fy"], sim["mu"] * res["f0y"], rtol=1e-10, atol=1e-9)


COMMITTED_NF = sorted(SCEN_DIR.glob("*.nf.csv")) if SCEN_DIR.is_dir() else []
COMMITTED_NF = [f for f in COMMITTED_NF if not f.name.endswith(".mf.nf.csv")]


# REQ-SIM-002
@pytest.mark.skipif(not COMMITTED_NF, reason="no scenarios/*.nf.csv generated yet")
@pytest.mark.parametrize("path", COMMITTED_NF, ids=lambda f: f.name)
def test_committed_logs(path):
    """Generated logs: model-matched, vx > 4 m/s, 100 Hz, noisy twin has the stated noise."""
    meta, cols = read_log_text(path.read_text())
    assert meta["truth_tyre"] == "dugoff" and meta["noise"] == "none"
    # the truth tyre: the metadata's (parameter file's) values, or truth_* where the log's
    # tyre is not its parameter file's (wrong_tyre_data)
    p = Params(**{k: float(meta.get(f"truth_{k}", meta[k]))
                  for k in ("m", "Lf", "Lr", "Bf", "Br", "R", "J", "hg", "g", "Cx_n", "Cy_n",
                            "eps", "v_min", "alpha_max")})
    res = check_model_match(cols, p)
    # util = |mu F0| / (mu Fz) = |F0| / Fz for the Dugoff truth (every row)
    util = np.stack([cols[f"util_{w}"] for w in WHEELS], axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        expect = np.where(res["fz"] > 0, np.hypot(res["f0x"], res["f0y"]) / res["fz"], 0.0)
    assert np.allclose(util, expect, rtol=1e-9, atol=1e-12)
    assert cols["vx"].min() > 4.0
    assert len(cols["t"]) == round(float(meta["duration"]) / 0.01) + 1
    assert np.array_equal(cols["t"], np.arange(len(cols["t"])) / 100.0)
    noisy = path.with_name(path.name[: -len(".nf.csv")] + ".csv")
    if noisy.is_file():
        _, ncols = read_log_text(noisy.read_text())
        check_noise(cols, ncols)


# ---------------------------------------------------------------------------------------
# Physics sanity
# ---------------------------------------------------------------------------------------
# REQ-SIM-002
def test_paper_braking_distance_and_deceleration(mu_step):
    _, sim, _ = mu_step
    assert np.all(sim["ax"][1:] < 0) and np.all(np.diff(sim["vx"]) < 0)
    t100 = float(np.interp(100.0, sim["s"], sim["t"]))
    assert 4.5 <= t100 <= 5.3, t100
    # ~0.07 g from 0.45 MPa (MODEL.md section 2)
    assert 0.065 * P.g < -sim["ax"][-1] < 0.08 * P.g
    assert sim["vx"][-1] > 4.0


# REQ-SIM-002
def test_mu_step_front_before_rear(mu_step):
    _, sim, table = mu_step
    first = {w: int(np.argmax(table[f"mu_{w}"] == 0.2)) for w in WHEELS}
    assert all(table[f"mu_{w}"][0] == 0.85 for w in WHEELS)
    assert first["fl"] == first["fr"] > 0 and first["rl"] == first["rr"]
    assert first["fl"] < first["rl"]
    # each wheel switches when its own road position (s + x_i) passes 100 m
    s = sim["s"]
    assert s[first["fl"]] + P.Lf >= 100.0 > s[first["fl"] - 1] + P.Lf
    assert s[first["rl"]] - P.Lr >= 100.0 > s[first["rl"] - 1] - P.Lr
    # the lower friction shows up as a larger slip on the wheels that crossed
    k = sim["kappa"]
    assert abs(k[first["fl"] + 20, 0]) > 2 * abs(k[first["fl"] - 2, 0])


# REQ-SIM-002
def test_straight_braking_symmetry(mu_step):
    _, sim, table = mu_step
    assert np.max(np.abs(table["vy"])) < 1e-12 and np.max(np.abs(table["yaw_rate"])) < 1e-12
    assert np.max(np.abs(table["ay"])) < 1e-12 and np.max(np.abs(table["yaw_acc"])) < 1e-12
    assert np.array_equal(table["omega_fl"], table["omega_fr"])
    assert np.array_equal(table["omega_rl"], table["omega_rr"])


# REQ-SIM-003
def test_integration_converged():
    """RK4 at the default rate agrees with twice the rate (combined braking and steering)."""
    sc = BY_NAME["brake_in_turn"]
    a = sensors.run(sc, duration=2.5)
    b = sensors.run(sc, rate=2 * sensors.DEFAULT_RATE, duration=2.5)
    for key in ("vx", "vy", "yaw_rate", "ax", "ay", "yaw_acc", "omega"):
        assert np.max(np.abs(a[key] - b[key])) < 1e-6, key


# REQ-SIM-002
def test_scenario_definitions():
    assert [s.name for s in SCENARIOS] == [
        "paper_low_mu_brake", "paper_high_mu_brake", "paper_mu_step", "split_mu_brake",
        "sine_steer_high_mu", "sine_steer_low_mu", "accel_low_mu", "brake_in_turn", "cruise",
        "hard_brake_high_mu", "hard_brake_low_mu", "mu_step_hard_brake",
        "split_mu_hard_brake",
        # issue 17
        "double_lane_change_high_mu", "double_lane_change_low_mu", "ramp_steer_high_mu",
        "ramp_steer_low_mu", "brake_in_turn_low_mu", "wrong_tyre_data"]
    assert len({s.seed for s in SCENARIOS}) == len(SCENARIOS)
    for s in SCENARIOS:
        assert "\n" not in s.description and s.duration == 10.0
        assert ("ABS active" in s.description) == (s.abs is not None)
        assert s.closed_loop == ("hard_brake" in s.name or s.name.startswith("ramp_steer")
                                 or s.name == "wrong_tyre_data")
        assert bool(s.truth) == (s.name == "wrong_tyre_data")


# REQ-SIM-002
def test_wrong_tyre_data_metadata_is_the_parameter_file():
    """The wrong-tyre-data log's metadata gives the parameter file's tyre (what the estimator
    reads), every truth value 30 % off it, in truth_* lines the estimator ignores."""
    sc = BY_NAME["wrong_tyre_data"]
    truth = dict(sc.truth)
    assert set(truth) == {"Cx_n", "cx", "Cy_n", "cy", "eps", "mf_Cx", "mf_Cy"}
    for k, v in truth.items():
        assert abs(abs(v / getattr(P, k) - 1.0) - 0.30) < 1e-12, k
    for tyre in ("dugoff", "mf"):
        meta = dict(sensors.metadata(sc, "default", tyre))
        for k, v in truth.items():
            if k in meta:
                assert meta[k] == getattr(P, k), k
            assert meta[f"truth_{k}"] == v
    # the simulator runs the truth tyre: the MF shape keeps 1 < C < 2 (peak force mu*Fz)
    tp = sc.truth_params(P)
    assert 1.0 < tp.mf_Cx < 2.0 and 1.0 < tp.mf_Cy < 2.0
    assert sc.truth_params(P).cx == 26.0 and BY_NAME["cruise"].truth_params(P) is P


# ---------------------------------------------------------------------------------------
# Determinism and noise
# ---------------------------------------------------------------------------------------
# REQ-SIM-002
def test_deterministic_bytes():
    sc = BY_NAME["brake_in_turn"]
    texts = []
    for _ in range(2):
        table = sensors.sensor_table(sensors.run(sc, duration=0.5))
        texts.append(sensors.csv_text(table, sensors.metadata(sc, "none", "dugoff"))
                     + sensors.csv_text(sensors.add_noise(table, sc.seed),
                                        sensors.metadata(sc, "default", "dugoff")))
    assert texts[0] == texts[1]


def check_noise(clean, noisy):
    n = len(clean["t"])
    for c in sensors.COLUMNS:
        d = noisy[c] - clean[c]
        sd = sensors.NOISE_SD.get(c, 0.0)
        if sd == 0.0:
            assert np.array_equal(noisy[c], clean[c]), c
            continue
        assert abs(d.std(ddof=1) / sd - 1) < NOISE_SD_RTOL, c
        assert abs(d.mean()) < NOISE_MEAN_SIGMAS * sd / math.sqrt(n), c


# REQ-SIM-003
def test_noise_statistics(mu_step):
    sc, _, table = mu_step
    noisy = sensors.add_noise(table, sc.seed)
    check_noise(table, noisy)
    # different columns get independent noise, different seeds different noise
    z = np.stack([(noisy[c] - table[c]) / sensors.NOISE_SD[c] for c in sensors.NOISY_COLUMNS])
    corr = np.corrcoef(z)
    assert np.max(np.abs(corr - np.eye(len(z)))) < 0.15
    other = sensors.add_noise(table, sc.seed + 1)
    assert not np.array_equal(other["ax"], noisy["ax"])


# REQ-SIM-002
def test_metadata_keys(mu_step):
    sc = mu_step[0]
    for noise in ("default", "none"):
        meta = dict(sensors.metadata(sc, noise, "dugoff"))
        for k in ("scenario", "description", "dt", "seed", "noise", "truth_tyre", "m", "Lf",
                  "Lr", "Bf", "Br", "R", "J", "hg", "g", "Cx_n", "Cy_n", "cx", "cy", "eps",
                  "v_min", "alpha_max", "kb_f", "kb_r", "Iw"):
            assert k in meta, k
    assert dict(sensors.metadata(sc, "none", "dugoff"))["seed"] == "none"
    assert dict(sensors.metadata(sc, "default", "dugoff"))["seed"] == 3
    assert sensors.file_name("x", "mf", "none") == "x.mf.nf.csv"
    assert sensors.file_name("x", "dugoff", "default") == "x.csv"


# ---------------------------------------------------------------------------------------
# Tyres
# ---------------------------------------------------------------------------------------
# REQ-SIM-004
@pytest.mark.parametrize("mu", [0.1, 0.3, 0.6, 0.85, 1.2])
def test_mf_peak_and_stiffness(mu):
    fz = 4500.0
    k = np.linspace(0.0, 1.0, 200001)
    fx, _ = tyres.vectorised(tyres.mf_unit, k, 0.0, 20.0, mu, P)
    assert abs(fz * fx.max() / (mu * fz) - 1) < 0.01
    a = np.linspace(0.0, 1.4, 100001)
    _, fy = tyres.vectorised(tyres.mf_unit, 0.0, a, 20.0, mu, P)
    assert abs(fz * fy.max() / (mu * fz) - 1) < 0.01
    h = 1e-6
    sx = fz * (tyres.mf_unit(h, 0.0, 20.0, mu, P)[0] - tyres.mf_unit(-h, 0.0, 20.0, mu, P)[0]) / (2 * h)
    sy = fz * (tyres.mf_unit(0.0, h, 20.0, mu, P)[1] - tyres.mf_unit(0.0, -h, 20.0, mu, P)[1]) / (2 * h)
    assert abs(sx / (P.cx * fz) - 1) < 1e-6
    assert abs(sy / (P.cy * fz) - 1) < 1e-6  # d tan(alpha)/d alpha = 1 at 0


# REQ-SIM-004
def test_mf_combined_slip_bounded_smooth_finite():
    kp, ap = np.linspace(0, 1, 101)[1:], np.linspace(0, 1.4, 71)[1:]
    k = np.concatenate([-kp[::-1], [0.0], kp])[:, None, None]   # exactly symmetric grids
    a = np.concatenate([-ap[::-1], [0.0], ap])[None, :, None]
    mu = np.array([0.05, 0.3, 0.9])[None, None, :]
    fx, fy = tyres.vectorised(tyres.mf_unit, k, a, 0.0, mu, P)
    assert np.all(np.isfinite(fx)) and np.all(np.isfinite(fy))
    assert np.all(np.hypot(fx, fy) <= mu * (1 + 1e-12))
    # odd symmetry, zero at zero slip, continuous across the rho ~ 1e-4 series switch
    assert np.allclose(fx, -fx[::-1], atol=1e-15) and np.allclose(fy, -fy[:, ::-1], atol=1e-15)
    assert tyres.mf_unit(0.0, 0.0, 0.0, 0.5, P) == (0.0, 0.0)
    for C, E in ((P.mf_Cx, P.mf_Ex), (P.mf_Cy, P.mf_Ey)):
        lo = tyres.mf_shape_over_rho(1e-4 * (1 - 1e-12), C, E)
        hi = tyres.mf_shape_over_rho(1e-4, C, E)
        assert abs(lo - hi) < 1e-14
    assert tyres.mf_unit(0.1, 0.1, 0.0, 0.0, P) == (0.0, 0.0)


# REQ-SIM-001
def test_dugoff_singularity_free():
    # kappa -> +-1: f(L)/(1-|kappa|) stays finite and continuous
    for sgn in (1.0, -1.0):
        at = tyres.dugoff_unit(sgn, 0.05, 15.0, 0.8, P)
        near = tyres.dugoff_unit(sgn * (1 - 1e-9), 0.05, 15.0, 0.8, P)
        assert all(math.isfinite(v) for v in at)
        assert abs(at[0] - near[0]) < 1e-6 and abs(at[1] - near[1]) < 1e-6
    assert tyres.dugoff_unit(0.0, 0.0, 20.0, 0.8, P) == (0.0, 0.0)
    # eps factor clamped at 0 -> zero force at huge slip speed
    assert tyres.dugoff_unit(-0.9, 0.0, 500.0, 0.8, P) == (-0.0, 0.0) or \
        tyres.dugoff_unit(-0.9, 0.0, 500.0, 0.8, P) == (0.0, 0.0)
    # linear range (L >= 1): F = mu*Cx*kappa/(1-|kappa|)
    fx, _ = tyres.dugoff_unit(0.001, 0.0, 0.0, 0.7, P)
    assert abs(fx - 0.7 * P.Cx_n * 0.001 / 0.999) < 1e-15


# REQ-SIM-001
@pytest.mark.parametrize("name", ["dugoff", "mf"])
def test_tyres_per_unit_load_and_loads_fixed_point(name):
    """The simulator's load solver relies on F = Fz * f(kappa, alpha, v, mu)."""
    fn = tyres.TRUTH_TYRES[name]
    fx, fy = fn(-0.05, 0.03, 20.0, 0.6, P)
    assert abs(fx) <= 0.6 and abs(fy) <= 0.6
    Fz0, Gx, Gy = load_coefficients(P)
    assert abs(sum(Fz0) - P.m * P.g) < 1e-9 and abs(sum(Gx)) < 1e-12 and abs(sum(Gy)) < 1e-12


# ---------------------------------------------------------------------------------------
# Near-limit braking: ABS, utilisation, closed-loop integration
# ---------------------------------------------------------------------------------------
KAPPA_TARGET = BY_NAME["hard_brake_high_mu"].abs.kappa_target
# Short runs that cover what each test needs (the committed logs cover the full 10 s).
ABS_RUNS = {("hard_brake_high_mu", "dugoff"): 4.5, ("hard_brake_low_mu", "dugoff"): 3.0,
            ("hard_brake_low_mu", "mf"): 3.0, ("mu_step_hard_brake", "dugoff"): 5.5}


@pytest.fixture(scope="module", params=sorted(ABS_RUNS), ids=lambda k: f"{k[0]}-{k[1]}")
def abs_run(request):
    name, tyre = request.param
    sc = BY_NAME[name]
    return sc, tyre, sensors.run(sc, tyre=tyre, duration=ABS_RUNS[request.param])


def _driver_pressure(sc, t):
    return np.array([sc.pressure(float(tk)) for tk in t])


# REQ-SIM-004
def test_abs_no_lock_bounded_slip(abs_run):
    """No wheel locks or slows to a crawl, slip stays bounded, ABS never adds pressure."""
    sc, tyre, sim = abs_run
    k = sim["kappa"]
    assert k.min() > -0.4, k.min(axis=0)       # worst case: mf front wheels onto the mu step
    wheel_speed = sim["omega"] * P.R
    assert np.all(wheel_speed > 0.5 * sim["vwx"]), "a wheel is locking"
    pd = _driver_pressure(sc, sim["t"])
    assert np.all(sim["pressure"] <= pd + 1e-12)
    braking = pd[:, 0] == P_HARD
    # with the driver at 8 MPa every wheel is pressure-limited by the ABS
    assert np.all(sim["pressure"][braking] < 0.8 * P_HARD)


# REQ-SIM-004
def test_abs_holds_target_slip_without_limit_cycle(abs_run):
    """0.7 s after braking starts and away from mu changes, every wheel sits at the target
    slip: no lock, no controller or integrator limit cycle (slip and pressure steady)."""
    sc, tyre, sim = abs_run
    t = sim["t"]
    t_on, t_off = 1.0, ABS_RUNS[(sc.name, tyre)] - 0.3
    if sc.name == "mu_step_hard_brake":
        t_off = 2.9                                # front wheels reach the step at ~3.07 s
    steady = (t >= t_on + 0.7) & (t <= min(t_off, 4.0))
    assert steady.sum() >= 50
    k = sim["kappa"][steady]
    assert np.max(np.abs(k - KAPPA_TARGET)) < 0.003, np.max(np.abs(k - KAPPA_TARGET), axis=0)
    dp = np.diff(sim["pressure"][steady], axis=0)
    assert np.max(np.abs(dp)) < 0.02             # MPa per 10 ms: a slow drift, no chatter


# REQ-SIM-004
def test_hard_braking_reaches_the_limit(abs_run):
    sc, tyre, sim = abs_run
    util = sensors.utilisation(sim)
    assert util[:, :2].max() >= 0.8, util.max(axis=0)   # front wheels near the limit
    t = sim["t"]
    steady = (t >= 1.7) & (t <= 2.9)
    assert util[steady].min() >= 0.8 if tyre == "dugoff" else util[steady].min() >= 0.75


# REQ-SIM-002
def test_mu_step_happens_while_braking(abs_run):
    sc, tyre, sim = abs_run
    if sc.name != "mu_step_hard_brake":
        pytest.skip("mu step only")
    mu = sim["mu"]
    i_front = int(np.argmax(mu[:, 0] == MSB_MU[1]))
    i_rear = int(np.argmax(mu[:, 2] == MSB_MU[1]))
    assert 0 < i_front < i_rear
    t_step = sim["t"][i_front]
    assert MSB_T[0] + 1.0 < t_step and MSB_T[1] - t_step >= 2.0  # established, then >= 2 s
    util = sensors.utilisation(sim)
    before = (sim["t"] >= t_step - 0.5) & (sim["t"] < t_step)
    after = sim["t"] >= t_step + 0.5
    assert np.all(util[before, :2] >= 0.8) and np.all(util[after, :2] >= 0.8)
    assert np.max(np.abs(sim["kappa"][after] - KAPPA_TARGET)) < 0.01


# REQ-SIM-001
def test_utilisation_column_matches_truth_tyre(abs_run):
    """util_* of the sensor table against the truth tyre re-evaluated at the logged slips."""
    sc, tyre, sim = abs_run
    table = sensors.sensor_table(sim)
    rows = np.arange(0, len(sim["t"]), 37)
    fx, fy = tyres.vectorised(tyres.TRUTH_TYRES[tyre], sim["kappa"][rows], sim["alpha"][rows],
                              np.abs(sim["vwx"][rows]), sim["mu"][rows], P)
    expect = np.hypot(fx, fy) / sim["mu"][rows]
    util = np.stack([table[f"util_{w}"][rows] for w in WHEELS], axis=1)
    assert np.allclose(util, expect, rtol=1e-12, atol=1e-15)


# REQ-SIM-003
def test_closed_loop_integration_converged():
    """ABS + driver steering at 4 kHz against 8 kHz: the controller ticks (1 kHz) do not
    move, so the closed loop converges like the open loop."""
    sc = BY_NAME["split_mu_hard_brake"]
    a = sensors.run(sc, duration=2.0)
    b = sensors.run(sc, rate=2 * sensors.DEFAULT_RATE, duration=2.0)
    for key in ("vx", "vy", "yaw_rate", "ax", "ay", "yaw_acc", "omega", "delta", "pressure"):
        assert np.max(np.abs(a[key] - b[key])) < 1e-6, key
    with pytest.raises(ValueError):
        sensors.run(sc, rate=1500, duration=0.1)


SPLIT_NF = SCEN_DIR / "split_mu_hard_brake.nf.csv"


# REQ-SIM-004
@pytest.mark.skipif(not SPLIT_NF.is_file(), reason="scenarios not generated yet")
def test_split_mu_hard_brake_stays_sane():
    _, cols = read_log_text(SPLIT_NF.read_text())
    assert np.max(np.abs(cols["yaw_rate"])) < 0.15
    assert np.max(np.abs(cols["delta"])) <= BY_NAME["split_mu_hard_brake"].yaw.delta_max
    util = np.stack([cols[f"util_{w}"] for w in WHEELS], axis=1)
    braking = (cols["t"] > 1.7) & (cols["t"] < 4.9)
    assert np.all(util[braking] >= 0.8)           # both sides at their (different) limits


COMMITTED_MF = sorted(SCEN_DIR.glob("*.mf.csv")) if SCEN_DIR.is_dir() else []


# REQ-SIM-002
def test_every_scenario_has_committed_mf_log():
    if not COMMITTED_NF:
        pytest.skip("no scenarios generated yet")
    assert sorted(f.name for f in COMMITTED_MF) == sorted(f"{s.name}.mf.csv" for s in SCENARIOS)


# REQ-SIM-002
@pytest.mark.parametrize("path", COMMITTED_MF, ids=lambda f: f.name)
def test_committed_mf_logs(path):
    meta, cols = read_log_text(path.read_text())
    assert meta["truth_tyre"] == "mf" and meta["noise"] == "default"
    assert list(cols) == sensors.COLUMNS
    assert cols["vx"].min() > 4.0
    util = np.stack([cols[f"util_{w}"] for w in WHEELS], axis=1)
    assert util.min() >= 0.0 and util.max() <= 1.0 + 1e-12


# REQ-SIM-002
def test_make_scenarios_plan():
    import importlib.util
    spec = importlib.util.spec_from_file_location("make_scenarios",
                                                  REPO / "scripts" / "data" / "make_scenarios.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.plan() == {"dugoff": ("default", "none"), "mf": ("default",)}
    assert mod.plan("mf") == {"mf": ("default", "none")}
    assert mod.plan(None, "none") == {"dugoff": ("none",)}
