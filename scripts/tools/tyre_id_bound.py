#!/usr/bin/env python3
"""An information bound for mu from D (issue 20): the Bayesian Cramer-Rao (Van Trees) bound of
the tyre identifier's own model on the tyre identification logs, and the SCKF beside it; writes
the table of docs/TYRE_ID_RESULTS.md "An information bound for mu from D" between its markers.

    .venv/bin/python scripts/tools/tyre_id_bound.py [--page docs/TYRE_ID_RESULTS.md]
        [--logs NAME ...] [--eps 1e-4] [--eps-check 1e-3] [--no-sckf] [--jobs 2]

The model is the identifier's (scripts/reference/tyre_id.py, the SCKF's too): the single-track
RK4 step of each sample period (inputs the mean of the two samples' delta and vx, one RK4 step,
tid_substeps), the Magic Formula per axle in (D, C, K, E), outputs y_k = [r_k, ay_k] at the
sample's delta and vx; held samples (vx below tid_v_min) neither step nor measure.  It is
driven by the TRUE steering angle (the scenario's steer(t): a perfect steering sensor) and the
truth vx, from the truth's initial state (vy 0, r 0: every log starts straight), with the
truth's parameters per axle at the static load: D = mu Fz0, K = cy Fz0 (cy = B C mu of the
truth columns), C, E.  The unknowns theta are what the identifier does not know: the initial
state (vy0, r0) and D, C, K, E per axle; on tid_tyre_change the shape (C, K, E per axle) of each
tyre set is its own unknown (the change time and a road friction that stays known to be the same
are given: more than the identifier knows, so the bound stays a lower one).

Fisher information J(k) = sum_{j <= k} S_j^T R^-1 S_j + P0^-1, S_j = dy_j/dtheta by central
differences of the whole simulated trajectory (step eps times each unknown's prior sd; a second
step --eps-check must agree), R = diag(tid_sd_r^2, tid_sd_ay^2) (the identifier's likelihood
sds), P0 = diag of the identifier's prior sds (tid_sd0_*); no process noise and no steering
noise, so the bound is optimistic for the identifier (a valid lower bound).  The bound on the
sd of mu_a at sample k: sqrt([J(k)^-1]_{D_a, D_a}) / Fz0_a; also with C and E known (the rows
and columns of D, K and the initial state only) and with the logs' own sensor noise
(sensors.NOISE_SD: r 0.005 rad/s, ay 0.05 m/s^2) in R.

Beside it: the RMS error at the truth of the linearised MAP estimate with the identifier's
prior means and the sensor noise (map_mse: the Van Trees bound is a bound on the error averaged
over the prior; at one truth near the prior mean an estimator goes below it, and this is by how
much in the linearised problem); the SCKF (tyre_id_sckf.py, defaults and tid_delta_state_q
0.04) on the logs, and in the model's world (the truth's simulated [r, ay] plus the sensor
noise, --mc seeds, with exact delta and with the sensor's delta noise).

Windows (scripts/tools/tyre_id_results.py's): mu@lim, the samples from 0.5 s where the log's
|ay| > 0.6 mu g; linear, from 0.5 s until the axle's truth utilisation first passes 0.5.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]

import numpy as np  # noqa: E402

from md_tables import replace_region  # noqa: E402
from reference import tyre_id as T  # noqa: E402
from reference.logs import read_csv_log  # noqa: E402
from reference.params import DEFAULTS as VEHICLE_DEFAULTS  # noqa: E402
from sim.sensors import NOISE_SD  # noqa: E402
from sim.tyre_id_scenarios import TID_BY_NAME  # noqa: E402
import tyre_id_results as R  # noqa: E402

ROOT = HERE.parent.parent
MARK = ("<!-- tyre-id-bound:begin -->", "<!-- tyre-id-bound:end -->")
MU_TARGET = 0.05      # issue 20: mu from D within 0.05 at the limit
SD_TARGET = 0.2       # issue 20: the spread >= 0.2 where the tyre stayed linear
G = 9.81              # the results tool's g of the mu@lim window
SCKF_VARIANTS = ((False, "SCKF defaults"),
                 (R.DELTA_STATE_Q, f"SCKF tid_delta_state_q {R.DELTA_STATE_Q:g}"))


def identifier_params() -> dict:
    """The identifier's parameters: the vehicle's and tyre_id's defaults."""
    p = dict(VEHICLE_DEFAULTS)
    p.update(T.TID_DEFAULTS)
    return p


def static_loads(p: dict) -> tuple:
    """(Fz0_f, Fz0_r): the static axle loads, D's scale (tyre_id.TyreId.fz0)."""
    La = p["Lf"] + p["Lr"]
    return p["m"] * p["g"] * p["Lr"] / La, p["m"] * p["g"] * p["Lf"] / La


# ---- the generic machinery: central differences, Fisher information, the bound ------------

def central_diff(f, phi0, steps):
    """Sensitivities dY/dphi of a batch function f: (B, n) -> (N, B, m), by central
    differences with the step steps[i] for unknown i; returns (Y0 (N, m), S (N, m, n))."""
    phi0 = np.asarray(phi0, dtype=float)
    n = phi0.size
    batch = np.repeat(phi0[None, :], 1 + 2 * n, axis=0)
    for i in range(n):
        batch[1 + 2 * i, i] += steps[i]
        batch[2 + 2 * i, i] -= steps[i]
    y = f(batch)
    s = (y[:, 1::2, :] - y[:, 2::2, :]) / (2.0 * np.asarray(steps))[None, :, None]
    return y[:, 0, :], np.transpose(s, (0, 2, 1))


def fisher_cumulative(S, meas, r_sd, prior_sd):
    """J(k) = P0^-1 + sum_{j <= k, meas_j} S_j^T R^-1 S_j for every sample k: (N, n, n).
    S (N, m, n); meas (N,) bool (the samples that measure); r_sd (m,) measurement sds;
    prior_sd (n,) the Gaussian prior's sds (np.inf: no prior information)."""
    w = S / np.asarray(r_sd, dtype=float)[None, :, None]
    info = np.einsum("kmi,kmj->kij", w, w) * np.asarray(meas, dtype=float)[:, None, None]
    j = np.cumsum(info, axis=0)
    return j + np.diag(1.0 / np.asarray(prior_sd, dtype=float) ** 2)[None, :, :]


def bound_sd(J, idx, keep=None):
    """sqrt([J(k)^-1]_{idx, idx}) for every k, with only the unknowns @p keep free (the
    others known: their rows and columns dropped); idx indexes the full theta."""
    if keep is not None:
        keep = list(keep)
        J = J[:, keep][:, :, keep]
        idx = keep.index(idx)
    return np.sqrt(np.linalg.inv(J)[:, idx, idx])


def map_mse(J, prior_sd, d, idx):
    """The mean squared error at one truth of the MAP estimate of the linearised problem, the
    [idx, idx] element of M(k) = J^-1 (J - P0^-1) J^-1 + b b^T, b = J^-1 P0^-1 d, for every k:
    J (N, n, n) of fisher_cumulative with the data's own noise, d = prior mean - truth.  Its
    mean over truths drawn from the prior is J^-1 (the Van Trees bound is met with equality
    in the linear-Gaussian case); at one truth within the prior's spread of its mean it is
    below J^-1 (M = J^-1 - J^-1 P0^-1 (P0 - d d^T) P0^-1 J^-1)."""
    pinv = np.diag(1.0 / np.asarray(prior_sd, dtype=float) ** 2)
    ji = np.linalg.inv(J)
    b = ji @ (pinv @ np.asarray(d, dtype=float))
    var = np.einsum("kij,kjl,kml->kim", ji, J - pinv[None], ji)
    return var[:, idx, idx] + b[:, idx] ** 2


# ---- the identifier's model on a log ----------------------------------------------------------

class Problem:
    """One log's unknowns, their truth and prior sds, and the simulated outputs."""

    def __init__(self, log: str, p: dict | None = None):
        self.log = log
        self.p = identifier_params() if p is None else p
        c = read_csv_log(str(ROOT / "scenarios" / "tyre_id" / f"{log}.csv")).columns
        self.c = c
        self.t = np.asarray(c["t"], dtype=float)
        sc = TID_BY_NAME[log]
        self.delta = np.array([sc.steer(float(tk)) for tk in self.t])   # the true delta
        self.vx = np.asarray(c["vx_true"], dtype=float)
        self.fz0 = static_loads(self.p)
        self.model = T._Model(self.p, T.NUMPY)
        mu = {a: 0.5 * (np.asarray(c[f"mu_{w[0]}"]) + np.asarray(c[f"mu_{w[1]}"]))
              for a, w in (("f", ("fl", "fr")), ("r", ("rl", "rr")))}
        self.mu = mu
        for a in "fr":   # D shared by the segments: the road's mu must not change
            if not np.all(mu[a] == mu[a][0]):
                raise ValueError(f"{log}: mu of axle {a} changes; the bound assumes it does not")
        # the tyre sets: a new segment where the truth's C or E changes (tid_tyre_change)
        ce = np.stack([c["C_f_true"], c["E_f_true"], c["C_r_true"], c["E_r_true"]], axis=1)
        starts = [0] + [k for k in range(1, len(self.t)) if np.any(ce[k] != ce[k - 1])]
        self.seg_start = np.array(starts)
        self.seg = np.searchsorted(self.seg_start, np.arange(len(self.t)), side="right") - 1
        p = self.p
        names, truth, sd0 = ["vy0", "r0"], [0.0, 0.0], [p["tid_sd0_vy"], p["tid_sd0_r"]]
        if abs(float(c["vy_true"][0])) > 0.0 or abs(self.delta[0]) > 1e-12:
            raise ValueError(f"{log}: does not start straight (vy0, r0 = 0 assumed)")
        for a, fz in zip("fr", self.fz0):
            names.append(f"D_{a}")
            truth.append(float(mu[a][0]) * fz)
            sd0.append(p["tid_sd0_mu"] * fz)
        for s, k0 in enumerate(starts):
            for a, fz in zip("fr", self.fz0):
                C = float(c[f"C_{a}_true"][k0])
                E = float(c[f"E_{a}_true"][k0])
                cy = float(c[f"B_{a}_true"][k0]) * C * float(mu[a][0])   # B = cy / (C mu)
                names += [f"C_{a}{s}", f"K_{a}{s}", f"E_{a}{s}"]
                truth += [C, cy * fz, E]
                sd0 += [p["tid_sd0_C"], (p["tid_sd0_cy_rel"] * p["cy"]) * fz, p["tid_sd0_E"]]
        self.names, self.truth, self.sd0 = names, np.array(truth), np.array(sd0)
        # the identifier's prior means (tyre_id.TyreId.mean0; vy0 0 and r0 the first measured
        # yaw rate, taken as the truth's 0: the states are not what the MAP figure is about)
        mean0 = dict(zip(T.PARAM_NAMES, T.TyreId({}).mean0))
        self.prior_mean = np.array([0.0, 0.0] + [mean0[nm[:3]] for nm in names[2:]])
        self.iD = {a: names.index(f"D_{a}") for a in "fr"}
        # the unknowns left when C and E are known
        self.keep_dk = [i for i, nm in enumerate(names) if not nm.startswith(("C_", "E_"))]
        # the samples that step and measure (tyre_id._SampleSteps: the first initialises, a
        # sample holds when its or the previous sample's vx is below tid_v_min)
        vmin = p["tid_v_min"]
        self.meas = np.zeros(len(self.t), dtype=bool)
        self.meas[1:] = (self.vx[1:] >= vmin) & (self.vx[:-1] >= vmin)

    def th_of(self, phi, s):
        """(B, 8) particle parameters (tyre_id.PARAM_NAMES order) of segment s."""
        cols = []
        for a in "fr":
            cols.append(phi[:, self.iD[a]])
            for q in "CKE":
                cols.append(phi[:, self.names.index(f"{q}_{a}{s}")])
        return np.stack(cols, axis=1)

    def simulate(self, phi):
        """The outputs [r, ay] of each row of phi (B, n): (N, B, 2); rows of samples that do
        not measure hold the state's r and the model's ay at that sample (not used)."""
        m, n_sub = self.model, int(self.p["tid_substeps"])
        th = [self.th_of(phi, s) for s in range(len(self.seg_start))]
        vy, r = phi[:, 0].copy(), phi[:, 1].copy()
        out = np.empty((len(self.t), phi.shape[0], 2))
        for k in range(len(self.t)):
            tk = th[self.seg[k]]
            if self.meas[k]:
                h = self.t[k] - self.t[k - 1]
                d_bar = 0.5 * (self.delta[k - 1] + self.delta[k])
                v_bar = 0.5 * (self.vx[k - 1] + self.vx[k])
                vy, r = m.rk4(vy, r, tk, d_bar, v_bar, h, n_sub)
            f, rr = m.forces(vy, r, tk, self.delta[k], self.vx[k])
            out[k, :, 0] = r
            out[k, :, 1] = ((f * math.cos(self.delta[k])) + rr) / self.p["m"]
        return out

    def sensitivities(self, eps):
        return central_diff(self.simulate, self.truth, eps * self.sd0)

    def model_log(self, seed, sd_delta):
        """A log of the model's world: the truth's simulated [r, ay] with the logs' sensor
        noise (sensors.NOISE_SD), delta the true one plus white noise of sd @p sd_delta, the
        true vx, ax 0 (unused with tid_ellipse 0); numpy Generator(PCG64(seed))."""
        y0 = self.simulate(self.truth[None, :])[:, 0, :]
        g = np.random.default_rng(seed)
        n = len(self.t)
        z = g.standard_normal((3, n))
        return {"t": self.t, "delta": self.delta + sd_delta * z[0], "vx": self.vx,
                "yaw_rate": y0[:, 0] + NOISE_SD["yaw_rate"] * z[1],
                "ay": y0[:, 1] + NOISE_SD["ay"] * z[2], "ax": np.zeros(n)}

    # the results tool's windows (tyre_id_results.measure)
    def windows(self, a):
        """(mu@lim mask, linear window's sample range (k_sk, k_end)) of axle a."""
        c, t = self.c, self.t
        k_sk = int(np.searchsorted(t, R.T_SKIP))
        w = ("fl", "fr") if a == "f" else ("rl", "rr")
        lim = np.abs(np.asarray(c["ay"])) > 0.6 * self.mu[a] * G
        lim[:k_sk] = False
        util = np.maximum(c[f"util_{w[0]}"], c[f"util_{w[1]}"])
        passed = np.nonzero(util > 0.5)[0]
        k_end = int(passed[0]) if passed.size else len(t)
        return lim, (k_sk, k_end)


def rms(x):
    return float(np.sqrt(np.mean(np.square(x)))) if len(x) else math.nan


def bound_log(job):
    """job = (log, eps, eps_check) -> per-axle figures of the bound (a dict)."""
    log, eps, eps_check = job
    t0 = time.perf_counter()
    pb = Problem(log)
    p = pb.p
    y0, S = pb.sensitivities(eps)
    _, S2 = pb.sensitivities(eps_check)
    r_id = np.array([p["tid_sd_r"], p["tid_sd_ay"]])
    r_sensor = np.array([NOISE_SD["yaw_rate"], NOISE_SD["ay"]])
    J = fisher_cumulative(S, pb.meas, r_id, pb.sd0)
    J2 = fisher_cumulative(S2, pb.meas, r_id, pb.sd0)
    Js = fisher_cumulative(S, pb.meas, r_sensor, pb.sd0)
    res = {"log": log, "seconds": 0.0}
    # how far the model's trajectory is from the log's (the world the bound describes vs the
    # log's): RMS of ay and r against the log's measured ones over the measured samples, and
    # the largest |ay| of each
    m = pb.meas
    res["fit_ay"] = rms(y0[m, 1] - np.asarray(pb.c["ay"])[m])
    res["fit_r"] = rms(y0[m, 0] - np.asarray(pb.c["yaw_rate"])[m])
    res["ay_max_model"] = float(np.max(np.abs(y0[m, 1])))
    res["ay_max_log"] = float(np.max(np.abs(np.asarray(pb.c["ay"])[m])))
    for ai, a in enumerate("fr"):
        fz = pb.fz0[ai]
        iD = pb.iD[a]
        b = bound_sd(J, iD) / fz
        b2 = bound_sd(J2, iD) / fz
        bk = bound_sd(J, iD, pb.keep_dk) / fz
        bs = bound_sd(Js, iD) / fz
        bks = bound_sd(Js, iD, pb.keep_dk) / fz
        mp = np.sqrt(map_mse(Js, pb.sd0, pb.prior_mean - pb.truth, iD)) / fz
        lim, (k_sk, k_end) = pb.windows(a)
        res[f"step_dev_{a}"] = float(np.max(np.abs(b2 - b) / b))
        res[f"nlim_{a}"] = int(lim.sum())
        res[f"rms_{a}"] = rms(b[lim])
        res[f"rms_ck_{a}"] = rms(bk[lim])
        res[f"rms_sens_{a}"] = rms(bs[lim])
        res[f"rms_ck_sens_{a}"] = rms(bks[lim])
        res[f"rms_map_{a}"] = rms(mp[lim])
        ks = np.nonzero(lim)[0]
        res[f"start_{a}"] = float(b[ks[0]]) if ks.size else math.nan
        res[f"start_sens_{a}"] = float(bs[ks[0]]) if ks.size else math.nan
        res[f"start_map_{a}"] = float(mp[ks[0]]) if ks.size else math.nan
        res[f"tstart_{a}"] = float(pb.t[ks[0]]) if ks.size else math.nan
        lin = k_end > k_sk
        res[f"lin_{a}"] = float(b[k_end - 1]) if lin else math.nan
        res[f"lin_ck_{a}"] = float(bk[k_end - 1]) if lin else math.nan
        res[f"lin_sens_{a}"] = float(bs[k_end - 1]) if lin else math.nan
        res[f"lin_map_{a}"] = float(mp[k_end - 1]) if lin else math.nan
        res[f"lin_full_{a}"] = k_end == len(pb.t)   # never past 0.5: the whole log
        res[f"final_{a}"] = float(b[-1])
    res["seconds"] = time.perf_counter() - t0
    return res


def sckf_log(job):
    """job = (log, variant) -> the SCKF's mu@lim RMSE and its own sd over the window, and the
    smallest sd while linear, per axle (tyre_id_results.run_filter, its defaults)."""
    log, variant = job
    pb = Problem(log)
    out = R.run_filter(pb.c, "sckf", 0, 0, delta_filter=variant)
    res = {"log": log, "variant": variant}
    for a in "fr":
        lim, (k_sk, k_end) = pb.windows(a)
        err = out[f"mu_{a}"][lim] - pb.mu[a][lim]
        res[f"rmse_{a}"] = rms(err)
        res[f"sd_{a}"] = rms(out[f"sd_mu_{a}"][lim])
        sd = out[f"sd_mu_{a}"][k_sk:k_end]
        res[f"sdlin_{a}"] = float(sd.min()) if sd.size else math.nan
    return res


MC_SEED0 = 1000      # the Monte Carlo's noise seeds: MC_SEED0 + 0 .. n - 1
MC_DELTA = ((0.0, "exact δ"), (NOISE_SD["delta"], f"δ noise {NOISE_SD['delta']:g} rad"))


def sckf_mc(job):
    """job = (log, sd_delta, n_seeds) -> the SCKF (defaults) on n_seeds logs of the model's
    world (Problem.model_log): per axle sqrt of the mean over seeds and the mu@lim window of
    the squared error (comparable with the bound's RMS@lim with the sensor noise: the mean of
    MSE_k is at least the mean of bound_k^2), and the smallest and largest per-seed RMSE."""
    log, sd_delta, n_seeds = job
    pb = Problem(log)
    mse = {a: [] for a in "fr"}
    for s in range(n_seeds):
        out = R.run_filter(pb.model_log(MC_SEED0 + s, sd_delta), "sckf", 0, 0)
        for a in "fr":
            lim, _ = pb.windows(a)
            mse[a].append(float(np.mean((out[f"mu_{a}"][lim] - pb.mu[a][lim]) ** 2))
                          if lim.any() else math.nan)
    res = {"log": log, "sd_delta": sd_delta}
    for a in "fr":
        m = np.array(mse[a])
        res[f"mc_{a}"] = float(np.sqrt(np.mean(m)))
        res[f"mc_lo_{a}"] = float(np.sqrt(np.min(m)))
        res[f"mc_hi_{a}"] = float(np.sqrt(np.max(m)))
    return res


def fmt(v, spec=".3f"):
    return "–" if v is None or (isinstance(v, float) and math.isnan(v)) else format(v, spec)


def table(bounds, sckf, eps, eps_check, mc=(), n_mc=0):
    p = identifier_params()
    sr = f"{NOISE_SD['yaw_rate']:g} rad/s, {NOISE_SD['ay']:g} m/s²"
    lines = [f"**VT**: the Van Trees bound on the sd of μ = D/Fz0 of the identifier's own model "
             "(true δ and vx, the truth's parameters and initial state, the prior sds "
             "tid_sd0_*, no process noise), the Fisher information at the truth, with R = "
             f"diag(tid_sd_r, tid_sd_ay) = diag({p['tid_sd_r']:g} rad/s, {p['tid_sd_ay']:g} "
             f"m/s²) (**id**) or the logs' sensor noise diag({sr}) (**sens**). **MAP**: the "
             "RMS error at this truth of the linearised MAP estimate with the identifier's "
             "prior means (sens). RMS@lim: over the μ@lim window (target ≤ "
             f"{MU_TARGET:g}); **C,E known**: VT with C and E given; **start**: at the window's "
             "first sample (its time, s); **lin end**: at the linear window's last sample (the "
             f"spread target ≥ {SD_TARGET:g}; * the axle never passed 0.5: the log's end). "
             "**SCKF**: on the log, its μ@lim RMSE / the RMS of its own sd over the window, and "
             f"its smallest sd while linear; \"{SCKF_VARIANTS[0][1]}\" → "
             f"\"{SCKF_VARIANTS[1][1]}\". Central differences with a step of {eps:g} prior "
             f"sd; against {eps_check:g} the bound (id) differs by at most "
             f"{max(max(b['step_dev_f'], b['step_dev_r']) for b in bounds):.1e} (relative, "
             "every sample of every log).", "",
             "| log | axle | μ@lim samples | VT RMS@lim id / sens | C,E known id / sens "
             "| MAP RMS@lim | start VT id / sens, MAP (t) | SCKF μ@lim RMSE / sd "
             "| lin end VT id / C,E known / sens | SCKF min sd lin |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    by = {(r["log"], r["variant"]): r for r in sckf}
    for b in bounds:
        log = b["log"]
        for a in "fr":
            sk = [by.get((log, v)) for v, _ in SCKF_VARIANTS]
            if all(s is not None for s in sk):
                mulim = " → ".join(f"{fmt(s[f'rmse_{a}'])} / {fmt(s[f'sd_{a}'])}" for s in sk)
                sdlin = " → ".join(fmt(s[f"sdlin_{a}"], ".2f") for s in sk)
            else:
                mulim = sdlin = "(not run)"
            star = "*" if b[f"lin_full_{a}"] else ""
            if b[f"nlim_{a}"]:
                lim = (f"{fmt(b[f'rms_{a}'])} / {fmt(b[f'rms_sens_{a}'])} | "
                       f"{fmt(b[f'rms_ck_{a}'])} / {fmt(b[f'rms_ck_sens_{a}'])} | "
                       f"{fmt(b[f'rms_map_{a}'])} | {fmt(b[f'start_{a}'])} / "
                       f"{fmt(b[f'start_sens_{a}'])}, {fmt(b[f'start_map_{a}'])} "
                       f"({fmt(b[f'tstart_{a}'], '.2f')})")
            else:
                lim = "– | – | – | –"
            lin = (f"{fmt(b[f'lin_{a}'])} / {fmt(b[f'lin_ck_{a}'])} / "
                   f"{fmt(b[f'lin_sens_{a}'])}{star}" if not math.isnan(b[f"lin_{a}"]) else "–")
            lines.append(f"| {log} | {a} | {b[f'nlim_{a}']} | {lim} | {mulim} | {lin} "
                         f"| {sdlin} |")
    cells = [(b, a) for b in bounds for a in "fr" if b[f"nlim_{a}"] > 0]
    lines += ["", f"(log, axle) cells with a μ@lim window: {len(cells)}. Cells whose RMS@lim is "
              f"above {MU_TARGET:g}:", ""]
    for key, what in (("rms", "VT id"), ("rms_sens", "VT sens"), ("rms_ck_sens",
                                                                   "VT sens, C and E known"),
                      ("rms_map", "MAP")):
        above = [f"{b['log']} {a}" for b, a in cells if b[f"{key}_{a}"] > MU_TARGET]
        lines.append(f"- {what}: {len(above)}" + (f" ({', '.join(above)})" if above else ""))
    lin = [(b, a) for b in bounds for a in "fr" if not math.isnan(b[f"lin_{a}"])]
    for key, what in (("lin", "VT id"), ("lin_sens", "VT sens")):
        below = [f"{b['log']} {a}" for b, a in lin if b[f"{key}_{a}"] < SD_TARGET]
        lines.append(f"- {what} at the linear window's end below {SD_TARGET:g}: {len(below)} of "
                     f"{len(lin)}" + (f" ({', '.join(below)})" if below else ""))
    if mc:
        lines += ["", f"The SCKF (defaults) in the model's world, {n_mc} noise seeds a log "
                  "(the model's [r, ay] at the truth plus the logs' sensor noise, "
                  f"{sr}; the true vx), the same μ@lim window: √(mean squared error over the "
                  "seeds and the window) [smallest – largest per-seed RMSE], each cell "
                  + " → ".join(f"\"{w}\"" for _, w in MC_DELTA) + "; beside it VT sens and "
                  "MAP of the same world.", "",
                  "| log | axle | VT sens | MAP | SCKF √MSE [per-seed range] |",
                  "|---|---|---|---|---|"]
        by = {(r["log"], r["sd_delta"]): r for r in mc}
        for b in bounds:
            for a in "fr":
                rows = [by.get((b["log"], d)) for d, _ in MC_DELTA]
                if not b[f"nlim_{a}"] or any(r is None for r in rows):
                    continue
                cell = " → ".join(f"{r[f'mc_{a}']:.3f} [{r[f'mc_lo_{a}']:.3f} – "
                                  f"{r[f'mc_hi_{a}']:.3f}]" for r in rows)
                lines.append(f"| {b['log']} | {a} | {fmt(b[f'rms_sens_{a}'])} | "
                             f"{fmt(b[f'rms_map_{a}'])} | {cell} |")
    lines += ["", "The model's trajectory against the log (the bound describes the model's "
              "world: the identifier's single-track model at the truth's parameters, driven by "
              "the true δ and vx): RMS of ay and r against the log's sensors over the log, and "
              "the largest |ay| of each.", "",
              "| log | ay RMS m/s² | r RMS rad/s | max \\|ay\\| model / log m/s² |",
              "|---|---|---|---|"]
    for b in bounds:
        lines.append(f"| {b['log']} | {b['fit_ay']:.3f} | {b['fit_r']:.4f} | "
                     f"{b['ay_max_model']:.2f} / {b['ay_max_log']:.2f} |")
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", default=str(ROOT / "docs" / "TYRE_ID_RESULTS.md"))
    ap.add_argument("--logs", nargs="+", default=list(R.LOGS), choices=R.LOGS, metavar="LOG")
    ap.add_argument("--eps", type=float, default=1e-4,
                    help="central-difference step, in units of each unknown's prior sd")
    ap.add_argument("--eps-check", type=float, default=1e-3,
                    help="the second step the first is checked against")
    ap.add_argument("--no-sckf", action="store_true", help="the bound only (no SCKF runs)")
    ap.add_argument("--mc", type=int, default=20, metavar="N",
                    help="noise seeds of the SCKF's Monte Carlo in the model's world (0: none)")
    ap.add_argument("--no-write", action="store_true", help="print the table, leave the page")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    jobs = [(log, args.eps, args.eps_check) for log in args.logs]
    sjobs = [] if args.no_sckf else [(log, v) for v, _ in SCKF_VARIANTS for log in args.logs]
    mjobs = [] if args.no_sckf or args.mc <= 0 else \
        [(log, d, args.mc) for d, _ in MC_DELTA for log in args.logs if log != "tid_straight"]
    bounds, sckf, mc = [], [], []
    with multiprocessing.Pool(args.jobs) as pool:
        for r in pool.imap(bound_log, jobs):
            bounds.append(r)
            print(f"[bound] {r['log']:28s} {r['seconds']:5.1f} s  RMS@lim f/r "
                  f"{fmt(r['rms_f'])} / {fmt(r['rms_r'])}  lin end f/r {fmt(r['lin_f'])} / "
                  f"{fmt(r['lin_r'])}  step check {max(r['step_dev_f'], r['step_dev_r']):.1e}",
                  flush=True)
        for r in pool.imap(sckf_log, sjobs):
            sckf.append(r)
            print(f"[sckf ] {r['log']:28s} {str(r['variant']):5s} μ@lim f/r "
                  f"{fmt(r['rmse_f'])} / {fmt(r['rmse_r'])}", flush=True)
        for r in pool.imap(sckf_mc, mjobs):
            mc.append(r)
            print(f"[mc   ] {r['log']:28s} sd_delta {r['sd_delta']:g}  sqrt(MSE) f/r "
                  f"{fmt(r['mc_f'])} / {fmt(r['mc_r'])}", flush=True)
    lines = table(bounds, sckf, args.eps, args.eps_check, mc, args.mc)
    n_runs = len(jobs) + len(sjobs) + len(mjobs) * max(args.mc, 0)
    print(f"{n_runs} runs in {time.perf_counter() - t0:.0f} s")
    print("\n".join(lines))
    if not args.no_write:
        replace_region(Path(args.page), *MARK, lines, "tyre_id_bound")


if __name__ == "__main__":
    main()
