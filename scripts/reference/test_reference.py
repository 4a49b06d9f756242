"""Tests of the reference estimator (run: .venv/bin/python -m pytest scripts/reference -q).

1. model.py reproduces shared/vectors/model_vectors.csv (MODEL.md sections 3-5);
2. filters.py reproduces shared/vectors/sckf_step_vectors.csv (one SCKF step, section 6);
3. SCKF and CKF agree on a whole log (same filter algebraically), both tyre modes;
4. SCKF on a linear-Gaussian toy problem equals a textbook Kalman filter;
5. parameters, log I/O, the CLI (module and script form) and make_goldens (naming, determinism);
6. when scenarios/*.csv exist: SCKF == CKF on them, and scenarios/golden/ is up to date
   (compare.py: within a tolerance, decisions exactly; its own tests are in section 8).
Synthetic sensor logs are generated here from model.py with a known friction.
"""

from __future__ import annotations

import csv
import glob
import os
import subprocess
import sys

import numpy as np
import pytest

from . import compare, estimate, filters, logs, model, params, runtime, trusted

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
# The in-repo copy of shared/vectors (refreshed by `make vectors`).
VECTORS = os.environ.get("RFE_VECTORS", os.path.join(REPO, "test", "vectors"))
W = model.WHEELS
P = params.resolve()


def _read_vectors(name):
    path = os.path.join(VECTORS, name)
    if not os.path.exists(path):
        pytest.skip(f"{path} not found")
    with open(path, encoding="utf-8") as fh:
        return list(csv.DictReader(line for line in fh if not line.startswith("#")))


def _wheels(row, prefix):
    return np.array([float(row[prefix + w]) for w in W])


def _tyre_inputs_of(row):
    one = lambda k: np.array([float(row[k])])  # noqa: E731
    omega = _wheels(row, "omega_")[None, :]
    return model.tyre_inputs(P, one("delta"), one("vx"), one("vy"), one("yaw_rate"),
                             one("ax"), one("ay"), omega)


def _max_rel(a, b):
    """Max error relative to max(|b|, 1) (absolute for values below 1)."""
    return float(np.max(np.abs(np.asarray(a) - b) / np.maximum(np.abs(b), 1.0)))


# ---------------------------------------------------------------------------------------------
# 1-2: shared test vectors
# ---------------------------------------------------------------------------------------------

# REQ-REF-001
def test_model_vectors():
    rows = _read_vectors("model_vectors.csv")
    assert len(rows) >= 71
    worst = {}
    for row in rows:
        ti = _tyre_inputs_of(row)
        got = {
            "kappa_": ti.kappa[0], "alpha_": ti.alpha[0], "fz_": ti.fz[0],
        }
        f0x, f0y = model.dugoff_normalised(P, ti.fz, ti.kappa, ti.alpha, ti.v_wx)
        got["f0x_"], got["f0y_"] = f0x[0], f0y[0]
        for mu, tag in ((0.3, "03"), (0.8, "08")):
            fx, fy = model.dugoff_absolute(P, mu, ti.fz, ti.kappa, ti.alpha, ti.v_wx)
            got[f"fx_abs_mu{tag}_"], got[f"fy_abs_mu{tag}_"] = fx[0], fy[0]
        for prefix, value in got.items():
            err = _max_rel(value, _wheels(row, prefix))
            assert err < 1e-9, (row["case"], prefix, value, _wheels(row, prefix))
            worst[prefix] = max(worst.get(prefix, 0.0), err)
        h_ref = np.array([float(row[f"H{i}{j}"]) for i in range(1, 4) for j in range(1, 5)])
        h_got = model.observation_matrix(P, ti)[0].reshape(-1)
        err = _max_rel(h_got, h_ref)
        assert err < 1e-9, (row["case"], "H", h_got, h_ref)
        worst["H"] = max(worst.get("H", 0.0), err)
    print("model vectors, max error rel. to max(|ref|,1):", worst)


# REQ-TYRE-007
def test_magic_tyre_matches_simulator_truth():
    """The estimator's Magic Formula tyre at the simulator's shape factors == the simulator's
    MF truth (an independent implementation: similarity method written with G(rho)/rho), and
    its properties: slope cx Fz at zero slip for every mu, peak mu Fz, |F| <= mu Fz, zero at
    mu <= 0. 1e-12: the two forms differ only by rounding of O(10) operations."""
    sys.path.insert(0, os.path.join(REPO, "scripts"))
    from sim import tyres as sim_tyres      # noqa: E402  (the simulator package)
    from sim.vehicle import Params as SimParams  # noqa: E402
    sp = SimParams()
    p = dict(P, tyre="magic", shape_Cx=sp.mf_Cx, shape_Ex=sp.mf_Ex, shape_Cy=sp.mf_Cy,
             shape_Ey=sp.mf_Ey, cx=sp.cx, cy=sp.cy)
    fz = 4321.0
    for mu in (0.05, 0.3, 0.85, 1.2):
        for kappa in (-1.0, -0.3, -0.05, -1e-6, 0.0, 2e-3, 0.08, 0.5):
            for alpha in (-0.6, -0.05, 0.0, 1e-5, 0.1, 1.0):
                fx, fy = model.magic_absolute(p, mu, fz, kappa, alpha, 20.0)
                ux, uy = sim_tyres.mf_unit(kappa, alpha, 20.0, mu, sp)
                assert abs(fx - fz * ux) <= 1e-12 * fz and abs(fy - fz * uy) <= 1e-12 * fz
                assert np.hypot(fx, fy) <= mu * fz * (1 + 1e-12)
    for mu in (0.2, 1.0):                     # slope at zero slip does not depend on mu
        fx, _ = model.magic_absolute(p, mu, fz, 1e-7, 0.0, 0.0)
        assert abs(fx / (fz * 1e-7) - p["cx"]) < 1e-5 * p["cx"]
        kap = np.linspace(0.0, 1.0, 20001)   # pure-slip peak mu Fz
        fxs, _ = model.magic_absolute(p, mu, fz, kap, 0.0, 0.0)
        assert abs(fxs.max() - mu * fz) < 1e-6 * fz
    for mu in (0.0, -0.2):
        fx, fy = model.magic_absolute(p, mu, fz, 0.1, 0.1, 0.0)
        assert fx == 0.0 and fy == 0.0


# REQ-REF-001
def test_absolute_h_matches_forces():
    """h_absolute at equal mu on every wheel == column sums of body_effects of the forces."""
    rows = _read_vectors("model_vectors.csv")
    for row in rows:
        ti = _tyre_inputs_of(row)
        pts = np.array([[0.3, 0.8, -0.1, 0.0]] * 4)       # one point per column
        z = model.h_absolute(P, ti, 0, pts)
        for j, mu in enumerate((0.3, 0.8, 0.0, 0.0)):
            fx = _wheels(row, f"fx_abs_mu{'03' if mu == 0.3 else '08'}_") if mu else np.zeros(4)
            fy = _wheels(row, f"fy_abs_mu{'03' if mu == 0.3 else '08'}_") if mu else np.zeros(4)
            ref = model.body_effects(P, fx, fy, ti.delta_i[0]).sum(axis=-1)
            np.testing.assert_allclose(z[:, j], ref, rtol=1e-9, atol=1e-9)


def test_sckf_linear_form_equals_points():
    """The linear update (filters.SCKF.linear: z = h(x-), Xc = S-, Zc = H S-; docs/ESTIMATOR.md
    "The linear update") gives the 2n points' step on h = H x: the same x and S within rounding,
    on random steps (S-, H, y, S_R). Both are the same exact algebra, the Tria and solves of
    well-conditioned values ~1 (cond(S-), cond(S_zz) < 1e2): a few eps cond^2 -> 1e-11."""
    rng = np.random.default_rng(21)
    n, m = 4, 3
    worst = 0.0
    for _ in range(200):
        x0 = rng.standard_normal(n)
        s0 = np.tril(rng.standard_normal((n, n))) + 2 * np.eye(n)
        sr = np.tril(rng.standard_normal((m, m))) + 2 * np.eye(m)
        H = rng.standard_normal((m, n))
        y = rng.standard_normal(m)
        a = filters.SCKF(x0, s0, 0.01 * np.eye(n), sr)
        b = filters.SCKF(x0, s0, 0.01 * np.eye(n), sr)
        b.linear = True
        a.measurement_update(y, H.__matmul__)
        b.measurement_update(y, H.__matmul__)
        np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-11)
        np.testing.assert_allclose(b.S, a.S, rtol=0, atol=1e-11)
        worst = max(worst, float(np.max(np.abs(b.S - a.S))), float(np.max(np.abs(b.x - a.x))))
    print(f"linear form vs points: max |dx|, |dS| {worst:.3g}")


# REQ-REF-001
def test_sckf_step_vectors():
    rows = _read_vectors("sckf_step_vectors.csv")
    assert len(rows) >= 12
    worst_x = worst_s = 0.0
    for row in rows:
        ti = _tyre_inputs_of(row)
        H = model.observation_matrix(P, ti)[0]
        x0 = _wheels(row, "x0_")
        s0 = np.array([[float(row[f"S0_{i}{j}"]) for j in range(1, 5)] for i in range(1, 5)])
        x1 = _wheels(row, "x1_")
        s1 = np.array([[float(row[f"S1_{i}{j}"]) for j in range(1, 5)] for i in range(1, 5)])
        y = [float(row["y_ax"]), float(row["y_ay"]), float(row["y_yaw_acc"])]
        f = filters.SCKF(x0, s0, P["q_mu"] * np.eye(4),
                         np.diag([P["r_ax"], P["r_ay"], P["r_yaw_acc"]]))
        f.time_update()
        f.measurement_update(y, H.__matmul__)
        x, clamped = filters.project(f.x, P["mu_min"], P["mu_max"])
        assert clamped == bool(int(row["projected"])), row["case"]
        np.testing.assert_allclose(x, x1, rtol=1e-9, atol=1e-12, err_msg=row["case"])
        np.testing.assert_allclose(f.S, s1, rtol=1e-9, atol=1e-12, err_msg=row["case"])
        assert np.all(np.triu(f.S, 1) == 0) and np.all(np.diag(f.S) >= 0)
        worst_x = max(worst_x, _max_rel(x, x1))
        worst_s = max(worst_s, float(np.max(np.abs(f.S - s1))))
    print(f"sckf step vectors: max |x1 err| {worst_x:.3g}, max |S1 err| {worst_s:.3g}")


# ---------------------------------------------------------------------------------------------
# Synthetic sensor logs built from model.py with a known friction
# ---------------------------------------------------------------------------------------------

def synthetic_columns(n=1001, dt=0.01, tyre="paper", mu_true=(0.8, 0.8, 0.6, 0.6),
                      noise=0.0, seed=1, p=P):
    """A braking-and-steering manoeuvre; y = [ax, ay, yaw_acc] from the model at mu_true.

    Speed falls from 22 m/s to below v_est_min at the end (exercises status 2); slips and
    steer vary with time.  ax, ay feed back into the loads: a few fixed-point iterations make
    the log self-consistent.  Optional white measurement noise (seeded).
    """
    t = np.arange(n) * dt
    tau = t / t[-1]
    vx = 22.0 * (1.0 - tau) + 0.5 * tau                       # ends at 0.5 m/s
    delta = 0.06 * np.sin(2 * np.pi * 0.4 * t)
    vy = 0.2 * np.sin(2 * np.pi * 0.4 * t + 0.3)
    yaw_rate = vx * delta / (p["Lf"] + p["Lr"])
    kappa_cmd = np.stack([-0.02 - 0.06 * tau, -0.03 - 0.05 * tau,
                          -0.01 - 0.04 * tau, -0.015 - 0.03 * tau], axis=-1)
    kappa_cmd += 0.01 * np.sin(2 * np.pi * 0.7 * t)[:, None]
    v_wx, _, _ = model.wheel_velocities(p, delta, vx, vy, yaw_rate)
    omega = v_wx * (1.0 + kappa_cmd) / p["R"]
    mu = np.broadcast_to(np.asarray(mu_true, dtype=float), (n, 4)).copy()
    ax = np.zeros(n)
    ay = np.zeros(n)
    for _ in range(6):
        ti = model.tyre_inputs(p, delta, vx, vy, yaw_rate, ax, ay, omega)
        if tyre == "paper":
            y = np.einsum("kij,kj->ki", model.observation_matrix(p, ti), mu)
        else:
            y = np.stack([model.h_absolute(p, ti, k, mu[k][:, None])[:, 0] for k in range(n)])
        ax, ay = y[:, 0], y[:, 1]
    yaw_acc = y[:, 2]
    if noise:
        rng = np.random.default_rng(seed)
        ax = ax + noise * rng.standard_normal(n)
        ay = ay + noise * rng.standard_normal(n)
        yaw_acc = yaw_acc + noise * rng.standard_normal(n)
    cols = {"t": t, "delta": delta, "vx": vx, "vy": vy, "yaw_rate": yaw_rate,
            "yaw_acc": yaw_acc, "ax": ax, "ay": ay}
    for i, w in enumerate(W):
        cols["omega_" + w] = omega[:, i]
    for i, w in enumerate(W):
        cols["mu_" + w] = mu[:, i]
    return cols


def write_sensor_log(path, cols, meta=(("scenario", "synthetic"), ("dt", "0.01"))):
    """Sensor log in DATA.md format; columns deliberately not in the canonical order."""
    names = list(cols)[::-1] + ["extra"]
    with open(path, "w", encoding="utf-8") as fh:
        for k, v in meta:
            fh.write(f"# {k} = {v}\n")
        fh.write(",".join(names) + "\n")
        for k in range(len(cols["t"])):
            fh.write(",".join(repr(float(cols[c][k])) if c != "extra" else "7" for c in names) + "\n")


@pytest.fixture(scope="module")
def synth_log(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("synth") / "synth.csv")
    write_sensor_log(path, synthetic_columns(noise=0.05))
    return logs.read_csv_log(path)


@pytest.fixture(scope="module")
def synth_log_abs(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("synth") / "synth_abs.csv")
    write_sensor_log(path, synthetic_columns(tyre="absolute", noise=0.05, seed=2))
    return logs.read_csv_log(path)


# ---------------------------------------------------------------------------------------------
# 3-4: filter properties
# ---------------------------------------------------------------------------------------------

def _assert_same_run(a, b, tol=1e-9):
    np.testing.assert_array_equal(a["status"], b["status"])
    np.testing.assert_array_equal(a["valid"], b["valid"])
    dmu = float(np.max(np.abs(a["mu"] - b["mu"])))
    dsd = float(np.max(np.abs(a["sd"] - b["sd"])))
    assert dmu < tol and dsd < tol, (dmu, dsd)
    return dmu, dsd


# REQ-REF-001
@pytest.mark.parametrize("tyre", ["paper", "absolute"])
def test_sckf_equals_ckf(tyre, synth_log, synth_log_abs):
    log = synth_log if tyre == "paper" else synth_log_abs
    a = estimate.run(log, P, "sckf", tyre)
    b = estimate.run(log, P, "ckf", tyre)
    dmu, dsd = _assert_same_run(a, b)
    assert np.any(a["status"] == 2) and np.any(a["status"] == 0)
    print(f"{tyre}: SCKF vs CKF max |dmu| {dmu:.3g}, max |dsd| {dsd:.3g}")


# REQ-REF-001
def test_low_speed_rows(synth_log):
    res = estimate.run(synth_log, P, "sckf", "paper")
    low = synth_log.col("vx") < P["v_est_min"]
    assert np.all(res["status"][low] == 2) and np.all(res["valid"][low] == 0)
    assert np.all(res["status"][~low] <= 1) and np.all(res["valid"][~low] == 1)
    # time update only: the mean does not move, the sd grows by the random walk
    k = np.flatnonzero(low)
    assert np.allclose(res["mu"][k[1:]], res["mu"][k[:-1]], rtol=0, atol=1e-15)
    np.testing.assert_allclose(res["sd"][k[1:]] ** 2, res["sd"][k[:-1]] ** 2 + P["q_mu"] ** 2,
                               rtol=1e-12)


# REQ-REF-001
def test_noise_free_model_matched_fits_measurement(tmp_path):
    """On noise-free paper-mode data the posterior explains y: H(u) x ~ y at the end."""
    path = str(tmp_path / "nf.csv")
    write_sensor_log(path, synthetic_columns(noise=0.0))
    log = logs.read_csv_log(path)
    res = estimate.run(log, P, "sckf", "paper")
    ti = model.tyre_inputs(P, log.col("delta"), log.col("vx"), log.col("vy"), log.col("yaw_rate"),
                           log.col("ax"), log.col("ay"), log.omega())
    H = model.observation_matrix(P, ti)
    y = np.stack([log.col("ax"), log.col("ay"), log.col("yaw_acc")], axis=-1)
    ok = np.flatnonzero(res["status"] == 0)
    k = ok[len(ok) // 2:]
    resid = np.einsum("kij,kj->ki", H[k], res["mu"][k]) - y[k]
    assert np.max(np.abs(resid)) < 0.05
    assert np.all(res["mu"] >= P["mu_min"]) and np.all(res["mu"] <= P["mu_max"])


# REQ-REF-001
def test_sckf_equals_textbook_kf():
    """Linear-Gaussian toy problem: random walk + y = H_k x + v; no projection."""
    rng = np.random.default_rng(7)
    n, m = 4, 3
    sq = 0.01 * np.eye(n)
    sr = np.diag([0.1, 0.2, 0.05])
    x0 = rng.standard_normal(n)
    s0 = np.tril(rng.standard_normal((n, n))) + 2 * np.eye(n)
    f = filters.SCKF(x0, s0, sq, sr)
    x, Pk = x0.copy(), s0 @ s0.T
    Q, R = sq @ sq.T, sr @ sr.T
    for _ in range(200):
        H = rng.standard_normal((m, n))
        y = rng.standard_normal(m)
        f.time_update()
        f.measurement_update(y, H.__matmul__)
        Pk = Pk + Q                                     # textbook predict
        Sk = H @ Pk @ H.T + R                           # textbook update
        K = Pk @ H.T @ np.linalg.inv(Sk)
        x = x + K @ (y - H @ x)
        Pk = (np.eye(n) - K @ H) @ Pk
        Pk = 0.5 * (Pk + Pk.T)
        np.testing.assert_allclose(f.x, x, rtol=1e-10, atol=1e-12)
        np.testing.assert_allclose(f.S @ f.S.T, Pk, rtol=1e-9, atol=1e-12)
    # the CKF follows the same path
    g = filters.CKF(x0, s0 @ s0.T, Q, R)
    rng = np.random.default_rng(7)
    rng.standard_normal(n), rng.standard_normal((n, n))
    for _ in range(200):
        H = rng.standard_normal((m, n))
        y = rng.standard_normal(m)
        g.time_update()
        g.measurement_update(y, H.__matmul__)
    np.testing.assert_allclose(g.x, x, rtol=1e-9, atol=1e-12)


# REQ-REF-001
def test_tria():
    rng = np.random.default_rng(3)
    for shape in ((4, 12), (3, 11), (4, 4)):
        a = rng.standard_normal(shape)
        s = filters.tria(a)
        assert s.shape == (shape[0], shape[0])
        assert np.all(np.triu(s, 1) == 0) and np.all(np.diag(s) >= 0)
        np.testing.assert_allclose(s @ s.T, a @ a.T, rtol=1e-12, atol=1e-12)


# REQ-REF-001
def test_projection():
    x, c = filters.project(np.array([0.0, 0.5, 1.3, 1.2]), 0.05, 1.2)
    assert c and list(x) == [0.05, 0.5, 1.2, 1.2]
    x, c = filters.project(np.array([0.05, 1.2, 0.7, 0.3]), 0.05, 1.2)
    assert not c


# ---------------------------------------------------------------------------------------------
# 5: parameters, I/O, CLI, make_goldens
# ---------------------------------------------------------------------------------------------

# REQ-REF-003
def test_param_precedence(tmp_path):
    meta = {"m": "1500", "scenario": "x", "kb_f": "300", "q_mu": "0.01", "seed": "3"}
    pf = tmp_path / "p.txt"
    pf.write_text("# comment\n\nq_mu = 0.002   # trailing comment\nsd0=0.2\n")
    p = params.resolve(meta, str(pf))
    assert p["m"] == 1500.0 and p["q_mu"] == 0.002 and p["sd0"] == 0.2 and p["J"] == 3234.0
    assert "kb_f" not in p and "scenario" not in p


# REQ-REF-003
@pytest.mark.parametrize("text,needle", [
    ("m = 1500\nmass = 3\n", ":2: unknown parameter key 'mass'"),
    ("m = heavy\n", ":1: value of 'm' is not a number"),
    ("\n\nm 1500\n", ":3:"),
])
def test_param_file_errors(tmp_path, text, needle):
    pf = tmp_path / "bad.txt"
    pf.write_text(text)
    with pytest.raises(params.ParamError) as exc:
        params.read_param_file(str(pf))
    assert str(pf) + needle in str(exc.value)


# REQ-REF-003
def test_log_metadata_overrides_defaults(tmp_path):
    path = str(tmp_path / "meta.csv")
    cols = synthetic_columns(n=300)
    write_sensor_log(path, cols, meta=(("scenario", "s"), ("r_ax", "0.2"), ("Iw", "1.2")))
    out = str(tmp_path / "est.csv")
    estimate.estimate_file(path, out)
    est = logs.read_csv_log(out, required=logs.ESTIMATE_COLUMNS)
    assert est.meta["r_ax"] == "0.2" and est.meta["input"] == "meta.csv"
    assert est.meta["generator"] == "scripts/reference" and est.meta["filter"] == "sckf"
    p = params.resolve({"r_ax": "0.2"})
    ref = estimate.run(logs.read_csv_log(path), p, "sckf", "paper")
    np.testing.assert_array_equal(est.col("mu_fl"), ref["mu"][:, 0])
    np.testing.assert_array_equal(est.col("t"), cols["t"])


# REQ-REF-003
def test_cli_module_and_script(tmp_path, synth_log):
    src = synth_log.path
    outs = []
    for form in (["-m", "scripts.reference.estimate"], [os.path.join(HERE, "estimate.py")]):
        for kind, tyre in (("sckf", "paper"), ("ckf", "paper"), ("sckf", "absolute")):
            out = str(tmp_path / f"{len(outs)}.csv")
            subprocess.run([sys.executable, *form, "--in", src, "--out", out, "--filter", kind,
                            "--tyre", tyre, "--preset", "paper"], cwd=REPO, check=True)
            outs.append(out)
    for a, b in zip(outs[:3], outs[3:]):
        with open(a, "rb") as fa, open(b, "rb") as fb:
            assert fa.read() == fb.read()
    est = logs.read_csv_log(outs[0], required=logs.ESTIMATE_COLUMNS)
    with open(outs[0], encoding="utf-8") as fh:
        header = [line for line in fh if not line.startswith("#")][0].strip().split(",")
    assert header == list(logs.ESTIMATE_COLUMNS)
    ref = estimate.run(synth_log, P, "sckf", "paper")
    np.testing.assert_array_equal(est.col("mu_rr"), ref["mu"][:, 3])
    np.testing.assert_array_equal(est.col("sd_fl"), ref["sd"][:, 0])
    np.testing.assert_array_equal(est.col("status"), ref["status"])
    # bad parameter file -> exit 1 with file:line
    pf = tmp_path / "bad.txt"
    pf.write_text("nope = 1\n")
    r = subprocess.run([sys.executable, "-m", "scripts.reference.estimate", "--in", src,
                        "--out", str(tmp_path / "x.csv"), "--params", str(pf)],
                       cwd=REPO, capture_output=True, text=True)
    assert r.returncode == 1 and f"{pf}:1" in r.stderr


# REQ-REF-002
def test_make_goldens_naming_and_determinism(tmp_path):
    sc = tmp_path / "scen"
    sc.mkdir()
    cols = synthetic_columns(n=150)   # short: the names and the bytes are the claim, not the estimates
    for name in ("a.csv", "a.nf.csv", "a.mf.csv", "a.mf.nf.csv", "notes.txt"):
        if name.endswith(".csv"):
            write_sensor_log(str(sc / name), cols)
        else:
            (sc / name).write_text("x")
    # the monitor's goldens: noisy Magic Formula logs and the fault logs the library accepts
    (sc / "faults").mkdir()
    for name in ("drop.a.mf.csv", "spike_ax_beyond_limit.a.mf.csv"):
        write_sensor_log(str(sc / "faults" / name), cols)
    script = os.path.join(REPO, "scripts", "data", "make_goldens.py")
    digests = []
    for run in range(2):
        out = tmp_path / f"gold{run}"
        subprocess.run([sys.executable, script, "--scenarios", str(sc), "--out", str(out)],
                       check=True, capture_output=True)
        files = sorted(os.listdir(out))
        assert files == ["a.absolute.sckf.csv", "a.default.sckf.csv", "a.nf.paper.ckf.csv",
                         "a.nf.paper.sckf.csv", "a.paper.ckf.csv", "a.paper.sckf.csv", "monitor"]
        mon = sorted(os.listdir(out / "monitor"))
        assert mon == ["a.mf.monitor.sckf.csv", "drop.a.mf.monitor.sckf.csv"]
        digests.append({f: (out / f).read_bytes() for f in files[:-1]}
                       | {f: (out / "monitor" / f).read_bytes() for f in mon})
    assert digests[0] == digests[1]


# ---------------------------------------------------------------------------------------------
# 6: on the simulator's scenarios, when they exist
# ---------------------------------------------------------------------------------------------

SCENARIOS = sorted(f for f in glob.glob(os.path.join(REPO, "scenarios", "*.csv"))
                   if ".mf" not in os.path.basename(f))


# REQ-REF-001 REQ-ACC-003
@pytest.mark.skipif(not SCENARIOS, reason="no scenarios/*.csv yet")
@pytest.mark.parametrize("path", SCENARIOS, ids=os.path.basename)
def test_scenario_sckf_equals_ckf(path):
    log = logs.read_csv_log(path)
    p = params.resolve(log.meta, source=path)
    _assert_same_run(estimate.run(log, p, "sckf", "paper"), estimate.run(log, p, "ckf", "paper"))


# The reference's goldens; the fixed-point estimator's own goldens (*.q31.csv, written by
# `mu_replay --real q31`, `make goldens-q31`) are checked bit for bit by test/golden/test_golden_q31.c.
# Every golden is regenerated and compared by `make check-kernels` (its as-is run, part of
# `make test`); here only those of its subset logs, so the two do not repeat the same work.
def _kernel_subset() -> tuple[str, ...]:
    """The stems of scripts/checks/check_kernels.py's DEFAULT_SUBSET (read, not copied)."""
    import importlib.util
    spec = importlib.util.spec_from_file_location(
        "check_kernels", os.path.join(REPO, "scripts", "checks", "check_kernels.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return tuple(f[:-len(".csv")] for f in mod.DEFAULT_SUBSET.split(","))


KERNEL_SUBSET = _kernel_subset()
GOLDENS = sorted(g for g in glob.glob(os.path.join(REPO, "scenarios", "golden", "*.csv"))
                 if not g.endswith(".q31.csv")
                 and os.path.basename(g).rsplit(".", 3)[0] in KERNEL_SUBSET)


# REQ-REF-002
@pytest.mark.skipif(not GOLDENS, reason="no scenarios/golden/*.csv yet")
@pytest.mark.parametrize("golden", GOLDENS, ids=os.path.basename)
def test_goldens_up_to_date(golden, tmp_path):
    """Each golden file agrees with what the reference writes now from its input: mu and sd
    within compare.TOL_MU / TOL_SD (1e-9; the BLAS kernel and numpy's SIMD paths of this CPU
    round differently from the machine that wrote it, compare.py), t, statuses, valid flags
    and metadata (less the machinery keys) exactly."""
    stem, tag, kind, _ = os.path.basename(golden).rsplit(".", 3)
    preset, tyre = ("default", None) if tag == "default" else ("paper", tag)
    src = os.path.join(REPO, "scenarios", stem + ".csv")
    assert os.path.exists(src), f"golden without its sensor log: {src}"
    out = str(tmp_path / "now.csv")
    res = estimate.estimate_file(src, out, None, kind, tyre, preset)
    result = compare.compare_logs(golden, out, actual_diag=compare.diagnostics(res))
    assert result.ok, compare.report(result)


# ---------------------------------------------------------------------------------------------
# 7: the observability-aware estimator (docs/ESTIMATOR.md, trusted.py)
# ---------------------------------------------------------------------------------------------

DEFAULT_GOLDENS = sorted(glob.glob(os.path.join(REPO, "scenarios", "golden", "*.default.sckf.csv"))
                         + glob.glob(os.path.join(REPO, "scenarios", "golden", "monitor", "*.csv")))


# REQ-EST-010
@pytest.mark.skipif(not DEFAULT_GOLDENS, reason="no default goldens yet")
def test_default_never_valid_on_a_bound():
    """ESTIMATOR.md step 9: with the sd rule an estimate on a projection bound is not valid,
    whatever its sd. Over every default-preset golden (the reference's output, which
    test_goldens_up_to_date ties to the code): no row valid at mu_min or mu_max, and the case
    occurs (rows on a bound with sd <= sd_valid exist), so the test is not vacuous. Exact
    comparisons: the projection writes the bound itself."""
    at_bound_small_sd = 0
    for g in DEFAULT_GOLDENS:
        e = logs.read_csv_log(g, required=())
        lo, hi, sd_valid = (float(e.meta[k]) for k in ("mu_min", "mu_max", "sd_valid"))
        assert sd_valid > 0, g
        for w in ("fl", "fr", "rl", "rr"):
            on = (e.col("mu_" + w) <= lo) | (e.col("mu_" + w) >= hi)
            assert not np.any(e.col("valid_" + w)[on] > 0), f"{g}: valid_{w} on a bound"
            at_bound_small_sd += int(np.sum(on & (e.col("sd_" + w) <= sd_valid)))
    assert at_bound_small_sd > 0

# REQ-REF-001 REQ-ACC-004
def test_trusted_with_additions_off_is_the_paper_filter(synth_log):
    """docs/ESTIMATOR.md: with every addition off (paper preset values) the steps reduce to
    MODEL.md section 6; trusted.run must then reproduce estimate.run (1e-12: same algebra,
    summation order aside)."""
    p = params.resolve(None, None, preset="paper")
    a = estimate.run(synth_log, p, "sckf", "paper")
    b = trusted.run(synth_log, p)
    np.testing.assert_allclose(b["mu"], a["mu"], atol=1e-12, rtol=0)
    np.testing.assert_allclose(b["sd"], a["sd"], atol=1e-12, rtol=0)
    np.testing.assert_array_equal(b["valid"], a["valid"])
    np.testing.assert_array_equal(b["status"], a["status"])


# REQ-REF-001 REQ-EST-020 REQ-EST-021
def test_yaw_check_hand_example():
    """ESTIMATOR.md step 0b with yaw_check 0.125, dt 0.01 (every rate exact in binary): the first
    sample is accepted; 0.625 after 0.5 (yaw_acc 0) is exactly 0.125 away and kept; 0.875 is
    0.25 away and replaced by the prediction 0.625; the next 0.875 is accepted (the check
    restarts after a replacement); then 1.5 with yaw_acc 2 is replaced by 0.875 + 0.005 * 2.
    Off (0): a jump passes; after a restart (r None, as a gap does) too."""
    c = trusted.YawCheck(0.125, 0.01)
    assert [c.step(r, 0.0) for r in (0.5, 0.625, 0.875, 0.875)] == [0.5, 0.625, 0.625, 0.875]
    assert c.step(1.5, 2.0) == 0.875 + (0.01 * 0.5) * 2.0
    c.r = None
    assert c.step(-1.0, 0.0) == -1.0
    off = trusted.YawCheck(0.0, 0.01)
    assert [off.step(r, 0.0) for r in (0.0, 2.0)] == [0.0, 2.0]


# REQ-REF-001 REQ-EST-020 REQ-EST-021
def test_stale_omega_hand_example():
    """ESTIMATOR.md step 9's stale rule with stale_omega 0.25: four still wheels are never
    stale; fl held at 60 while the others fall 0.0625 per sample (exact) is stale once they moved
    more than 0.25 (from the 5th sample; 0.25 exactly is not more); a change clears it; a wheel
    at 0 is exempt; delta 0 is off."""
    r = trusted.StaleOmega(0.25)
    for _ in range(5):
        r.update([60.0] * 4)
        assert not r.stale
    got = []
    for k in range(9):
        w = 60.0 - 0.0625 * k
        r.update([60.0, w, w, w])
        got.append(r.stale)
    assert got == [False] * 5 + [True] * 4
    r.update([59.0] * 4)
    assert not r.stale
    for k in range(9):
        w = 58.0 - 0.0625 * k
        r.update([0.0, w, w, w])
        assert not r.stale
    off = trusted.StaleOmega(0.0)
    for k in range(9):
        w = 60.0 - 0.0625 * k
        off.update([60.0, w, w, w])
        assert not off.stale


# REQ-REF-001 REQ-EST-020 REQ-EST-021
def test_trust_rules_leave_a_clean_log_alone(synth_log):
    """The two rules on (default preset) and off on a clean synthetic log: the same run, bit for
    bit (no spike, no frozen wheel: neither acts)."""
    p = params.resolve(None, None, preset="default")
    assert p["stale_omega"] == 0.25 and p["yaw_check"] == 0.1
    a = trusted.run(synth_log, p)
    b = trusted.run(synth_log, dict(p, stale_omega=0.0, yaw_check=0.0))
    for k in ("mu", "sd", "valid", "status"):
        np.testing.assert_array_equal(a[k], b[k])


# REQ-REF-001 REQ-EST-022
def test_bound_margin_on_a_log():
    """ESTIMATOR.md step 9's bound margin (valid_bound_k 3, the default preset's) on the noise-free
    low-mu hard brake, whose ABS estimate sits near mu_min (MONITOR.md section 10 gains it): mu,
    sd and status as with the margin off, bit for bit, and each flag = the flag without it and
    mu - mu_min >= 3 sd (per wheel: T is 0/1, so mu and sd are the state's exactly). At least
    one flag is cleared (the rule acts here); k = 0 is today's rule."""
    path = os.path.join(REPO, "scenarios", "hard_brake_low_mu.nf.csv")
    if not os.path.isfile(path):
        pytest.skip("no scenarios/hard_brake_low_mu.nf.csv")
    log = logs.read_csv_log(path)
    p = params.resolve(log.meta, None, source=path, preset="default")
    assert p["valid_bound_k"] == 3.0
    a = trusted.run(log, p)
    b = trusted.run(log, dict(p, valid_bound_k=0.0))
    for k in ("mu", "sd", "status"):
        np.testing.assert_array_equal(a[k], b[k])
    want = b["valid"].astype(bool) & (b["mu"] - p["mu_min"] >= 3.0 * b["sd"])
    np.testing.assert_array_equal(a["valid"].astype(bool), want)
    assert np.sum(b["valid"].astype(bool) & ~want) > 0
    assert params.resolve(None, None, preset="paper")["valid_bound_k"] == 0.0


# REQ-REF-001
def test_conditioner_hand_example():
    """tau = 0.09, dt = 0.01: b = 0.1. First sample initialises to the measurement; second:
    px = 20 + 0.01 (-2 + 0.1 * 0.5) = 19.9805, py = 0.5 + 0.01 (0.3 - 0.1 * 20) = 0.483;
    vx = 0.9 * 19.9805 + 0.1 * 19.0 = 19.88245, vy = 0.9 * 0.483 + 0.1 * 0.4 = 0.4747."""
    c = trusted.Conditioner(0.09, 0.01)
    assert c.step(20.0, 0.5, -2.0, 0.3, 0.1) == (20.0, 0.5)
    vx, vy = c.step(19.0, 0.4, -2.0, 0.3, 0.1)
    assert abs(vx - 19.88245) < 1e-12 and abs(vy - 0.4747) < 1e-12


# REQ-REF-001 REQ-ACC-004
def test_trusted_holds_when_nothing_is_observable(tmp_path):
    """Steady cruising: no tyre works, so every step is held (status 3), the mean stays at
    mu0, the sd sits at the sd_max bound and nothing is reported valid."""
    n = 300
    cols = {"t": np.arange(n) * 0.01, "delta": np.zeros(n), "vx": np.full(n, 22.0),
            "vy": np.zeros(n), "yaw_rate": np.zeros(n), "yaw_acc": np.zeros(n),
            "ax": np.zeros(n), "ay": np.zeros(n)}
    for w in model.WHEELS:
        cols[f"omega_{w}"] = np.full(n, 22.0 / 0.325)
    path = str(tmp_path / "cruise.csv")
    write_sensor_log(path, cols)
    p = params.resolve(None, None, preset="default")
    res = trusted.run(logs.read_csv_log(path), p)
    assert np.all(res["status"] == 3) and not res["valid"].any()
    np.testing.assert_allclose(res["mu"], p["mu0"], atol=1e-12)
    assert np.all(res["sd"] <= p["sd_max"] + 1e-12) and res["sd"][-1, 0] > 0.3
    np.testing.assert_array_equal(res["mu"][:, 0], res["mu"][:, 2])   # sides: fl == rl


# REQ-EST-015 REQ-REF-001
@pytest.mark.parametrize("preset,kind", [("default", "sckf"), ("paper", "sckf"), ("paper", "ckf")])
def test_gaps_reference_and_library_agree(tmp_path, preset, kind):
    """docs/ESTIMATOR.md "Gaps", independently twice: the reference (filters.gap_steps,
    trusted.py / estimate.py) and the C library through mu_replay (rfe_friction_skip, the
    double build) on a Magic Formula hard brake with three gaps in it (30 and 2 periods cut
    out, a 30 s outage: long enough to reach the prior's variance before the next update).
    Double against double: mu and sd within 1e-9 (compare.TOL_MU, the golden bound),
    statuses and valid flags exact; and the gaps must show (the sd after the long one above
    the sd before it, at most the prior's), so the test cannot pass on a run that ignores
    them."""
    replay = os.path.join(REPO, "build", "mu_replay")
    if not os.path.isfile(replay):
        pytest.skip("needs build/mu_replay (make build/mu_replay)")
    src = os.path.join(REPO, "scenarios", "hard_brake_low_mu.mf.csv")
    with open(src, encoding="utf-8") as fh:
        lines = fh.read().splitlines()
    head = next(i for i, ln in enumerate(lines) if not ln.startswith("#"))
    rows = lines[head + 1:]
    keep = []
    for i, r in enumerate(rows):
        if 300 <= i < 330 or 500 <= i < 502:
            continue                                    # 30 and 2 periods cut out
        if i >= 620:                                    # a 30 s outage before row 620
            t_s, rest = r.split(",", 1)
            r = f"{float(t_s) + 30.0:.10g},{rest}"
        keep.append(r)
    gapped = str(tmp_path / "gapped.csv")
    with open(gapped, "w", encoding="utf-8") as fh:
        fh.write("\n".join(lines[:head + 1] + keep) + "\n")
    ref = estimate.estimate_file(gapped, str(tmp_path / "ref.csv"), None, kind, None, preset)
    out = str(tmp_path / "c.csv")
    res = subprocess.run([replay, "--in", gapped, "--out", out, "--preset", preset,
                          "--filter", kind, "--real", "double", "--quiet"],
                         capture_output=True, text=True)
    assert res.returncode == 0, res.stderr
    c = logs.read_csv_log(out, required=())
    for i, w in enumerate(model.WHEELS):
        np.testing.assert_allclose(c.col("mu_" + w), ref["mu"][:, i], atol=compare.TOL_MU, rtol=0)
        np.testing.assert_allclose(c.col("sd_" + w), ref["sd"][:, i], atol=compare.TOL_SD, rtol=0)
        np.testing.assert_array_equal(c.col("valid_" + w).astype(int), ref["valid"][:, i])
    np.testing.assert_array_equal(c.col("status").astype(int), ref["status"])
    p = params.resolve(None, None, preset=preset)
    t = c.col("t")
    after = int(np.flatnonzero(np.diff(t) > 1.0)[0]) + 1       # the sample after the long gap
    assert c.col("sd_fl")[after] > c.col("sd_fl")[after - 1]
    prior = p["sd0"] ** 2 + p["sd0_common"] ** 2
    assert c.col("sd_fl")[after] ** 2 <= prior * (1 + 1e-9)


# ---------------------------------------------------------------------------------------------
# 8: golden comparison across machines (compare.py, runtime.py)
# ---------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def default_run(tmp_path_factory):
    """A default-preset estimate log of the synthetic log (short: 300 rows), its run's
    diagnostics and the path; the tests below perturb copies of it."""
    d = tmp_path_factory.mktemp("cmp")
    src = str(d / "s.csv")
    write_sensor_log(src, synthetic_columns(n=300, noise=0.05))
    out = str(d / "s.default.sckf.csv")
    res = estimate.estimate_file(src, out, None, "sckf", None, "default")
    return out, res


def _rewrite(path, dst, edit):
    """Copy an estimate log, passing (row index, column name -> cell string) of every data row
    and the metadata lines through edit functions; returns dst."""
    with open(path, encoding="utf-8") as fh:
        lines = fh.read().splitlines()
    meta = [ln for ln in lines if ln.startswith("#")]
    body = [ln for ln in lines if not ln.startswith("#")]
    header = body[0].split(",")
    rows = [dict(zip(header, ln.split(","))) for ln in body[1:]]
    meta = edit.get("meta", lambda m: m)(meta)
    for k, row in enumerate(rows):
        edit.get("row", lambda k, r: None)(k, row)
    with open(dst, "w", encoding="utf-8") as fh:
        fh.write("\n".join(meta + [body[0]] + [",".join(r[c] for c in header) for r in rows]) + "\n")
    return dst


def _shift(col, k0, delta):
    def row(k, r):
        if k == k0:
            r[col] = repr(float(r[col]) + delta)
    return {"row": row}


# REQ-REF-002 REQ-REF-004
@pytest.mark.parametrize("col", ["mu_fl", "sd_rr"])
def test_compare_tolerance_catches_1e6_and_accepts_1e13(default_run, tmp_path, col):
    """A golden moved by 1e-6 fails (names the row and the value); by 1e-13, well inside the
    1e-9 tolerance (the kernels differ by <= ~1e-11), it passes."""
    out, res = default_run
    same = compare.compare_logs(out, out)
    assert same.ok and same.max_dmu == 0.0 and same.rows == 300
    bad = compare.compare_logs(_rewrite(out, str(tmp_path / "b.csv"), _shift(col, 150, 1e-6)), out)
    assert not bad.ok
    msg = compare.report(bad)
    assert "first row 150" in msg and col in msg and "beyond 1e-09" in msg
    assert compare.compare_logs(_rewrite(out, str(tmp_path / "g.csv"), _shift(col, 150, 1e-13)),
                                out).ok


# REQ-REF-004
def test_compare_decisions_exact_with_margin(default_run, tmp_path):
    """A flipped valid flag or status fails even though every number agrees; the message names
    the row and how far the deciding quantity stood from its threshold."""
    out, res = default_run
    diag = compare.diagnostics(res)
    valid = np.flatnonzero(res["valid"][:, 0] == 1)
    updated = np.flatnonzero(res["status"] == 0)
    assert valid.size and updated.size, "fixture must contain valid and updated rows"
    kv, ks = int(valid[0]), int(updated[0])

    def flip_valid(k, r):
        if k == kv:
            r["valid_fl"] = "0"
    r1 = compare.compare_logs(_rewrite(out, str(tmp_path / "v.csv"), {"row": flip_valid}), out)
    msg = compare.report(r1)
    assert not r1.ok and f"row {kv} " in msg and "sd gate: sd_fl" in msg and "margins" in msg

    def flip_status(k, r):
        if k == ks:
            r["status"] = "3"
    r2 = compare.compare_logs(_rewrite(out, str(tmp_path / "s.csv"), {"row": flip_status}), out,
                              actual_diag=diag)
    msg = compare.report(r2)
    thr = float(params.resolve(preset="default")["info_min"])
    margin = diag["info_max"][ks] - thr
    assert not r2.ok and f"row {ks} " in msg and "information gate" in msg
    assert f"margin {margin:+.3g})" in msg and margin > 0


# REQ-REF-004
def test_compare_metadata_ignores_only_the_machinery(default_run, tmp_path):
    """Which BLAS kernel wrote a golden is recorded and ignored; any other key must match."""
    out, _ = default_run
    with open(out, encoding="utf-8") as fh:
        meta = dict(logs._parse_meta(ln) for ln in fh if ln.startswith("#"))
    assert set(runtime.RUNTIME_KEYS) <= set(meta) and "openblas" in meta["blas"].lower()

    def other_kernel(m):
        return [("# blas = openblas 0.0 Prescott, 1 thread" if ln.startswith("# blas") else ln)
                for ln in m]
    assert compare.compare_logs(_rewrite(out, str(tmp_path / "k.csv"), {"meta": other_kernel}),
                                out).ok

    def other_param(m):
        return [("# info_min = 26.0" if ln.startswith("# info_min") else ln) for ln in m]
    r = compare.compare_logs(_rewrite(out, str(tmp_path / "p.csv"), {"meta": other_param}), out)
    assert not r.ok and "metadata info_min" in compare.report(r)


# REQ-REF-004
def test_compare_nan_is_a_difference(default_run, tmp_path):
    out, _ = default_run

    def nan(k, r):
        if k == 10:
            r["mu_rl"] = "nan"
    r = compare.compare_logs(_rewrite(out, str(tmp_path / "n.csv"), {"row": nan}), out)
    assert not r.ok and "first row 10" in compare.report(r)
