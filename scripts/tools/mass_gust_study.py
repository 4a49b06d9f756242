#!/usr/bin/env python3
"""Issue 19: a gust model beside the force-offset state, measured in the float64 reference
(docs/MASS_GRADE_RESULTS.md "A gust state for the headwind's first 10 s").

    .venv/bin/python scripts/tools/mass_gust_study.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--jobs N] [--logs NAME ...]

The headwind's first 10 s miss issue 19's mass target because the 7 s gust has not averaged
out: a constant force F fitted over 0-10 s takes part of the gust for mass ("The headwind's
first 10 s"). The candidate here gives the gust its own state: a first-order Gauss-Markov
(exponentially correlated) force G beside the slow force F of mass_offset_study,

    (M + m_rot) v-dot = T/r - M g ((f_c + f_r v) cos theta + sin theta) - rho C_d S v^2 / 2
                        - F - G,
    G(t + dt) = phi G(t) + eta,  phi = exp(-dt / tau),  var(eta) = sd_G^2 (1 - phi^2),

the state [v, M, F, G, theta] (n = 5; theta last as in mass_offset_study, so the grade from a_x
in a pause leaves the rows of M, F and G alone). The filter is not the reference's and not the
library's: a subclass of the reference's square-root UKF (scripts/reference/mass_grade.py) with
n = 5, off unless this tool builds it; the reference and the C filter are unchanged.

The gust model's parameters come from the simulator's documented wind law (scenario metadata
of car_headwind, scripts/sim/mass_grade_scenarios.py _hw_wind), never from a fit to a log:

    w(t) = 10 + 3 sin(2 pi t / 7) + 1.5 sin(2 pi t / 2.3 + 1)  m/s,
    gust sd   sigma_w = sqrt(3^2 / 2 + 1.5^2 / 2) = 2.37 m/s (turbulence intensity
              I = sigma_w / 10 = 0.237),
    tau       the lag where the law's autocorrelation (4.5 cos(2 pi l / 7) + 1.125
              cos(2 pi l / 2.3)) / 5.625 first falls to 1/e: 0.935 s (GUST_TAU, computed by
              gust_tau()),

and the drag's linearisation about the mean air speed: a gust w' moves the drag by
k 2 (v + W) w' (k = rho C_d S / 2), so sd_G = 2 k (v + W) sigma_w. Two ways to set sd_G:

  * "fixed": at the headwind's operating point, v 25 m/s, W 10 m/s: 2 0.396 35 2.37 = 66 N
    (the scenario's own gust intensity given to the filter: an oracle on the intensity);
  * "from F": W from the filter's own F (F = k (2 v W + W^2), W = sqrt(v^2 + F / k) - v for
    F > 0, else 0) and sigma_w = I W: no wind, no gusts. Only the turbulence intensity is given.

Also a shorter correlation time as the sensitivity case: Dryden's near-ground longitudinal
scale, L_u = h / (0.177 + 0.000823 h)^1.2 (h in ft, MIL-F-8785C low altitude) at h = 1 m:
7.9 m, over the air speed 35 m/s: 0.23 s.

Measured on every mass and grade log (scenarios/mass_grade/) from the accuracy table's four
starts, the recommended preset of each log's vehicle, without F (the reference), with F alone
(mass_offset_study's sd 300 N, 2 N/sqrt(s)) and with F and G, by the accuracy table's metrics;
and on car_headwind's two halves simulated (mass_headwind_study.make_variants). A second
table is the information bound of the first 10 s (bound_table): a generalised least-squares
fit of M and a constant F on the truth signals with the gust as a Gauss-Markov process.
"""

import argparse
import math
import multiprocessing
import os
import re
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
sys.path.insert(0, os.path.join(ROOT, "scripts", "tools"))

from reference import mass_grade as mg  # noqa: E402
from mass_logs import mass_grade_names  # noqa: E402
import mass_grade_results as mgr  # noqa: E402
import mass_offset_study as mos  # noqa: E402

NX = 5                                  # [v, M, F, G, theta]
IV, IM, IF, IG, IT = 0, 1, 2, 3, 4
# the documented wind law of car_headwind (scripts/sim/mass_grade_scenarios.py _hw_wind)
WIND_MEAN = 10.0                        # m/s
GUSTS = ((3.0, 7.0), (1.5, 2.3))        # (amplitude m/s, period s)
SIGMA_W = math.sqrt(sum(a * a / 2.0 for a, _ in GUSTS))   # 2.37 m/s
TURB_I = SIGMA_W / WIND_MEAN            # 0.237
V_OP = 25.0                             # m/s: the headwind's cruise (its metadata)
DRYDEN_TAU = 0.23                       # s: L_u 7.9 m at 1 m height over 35 m/s air speed
SD_F0, Q_F = 300.0, 2.0                 # F as mass_offset_study's F always on


def gust_tau():
    """The lag (s) at which the documented gusts' autocorrelation first falls to 1/e."""
    lag = np.linspace(0.0, 7.0, 70001)
    var = sum(a * a / 2.0 for a, _ in GUSTS)
    r = sum(a * a / 2.0 * np.cos(2.0 * np.pi * lag / per) for a, per in GUSTS) / var
    return float(lag[int(np.argmax(r < math.exp(-1.0)))])


GUST_TAU = gust_tau()                   # 0.935 s


def drag_k(p):
    return 0.5 * p["mg_rho"] * p["mg_cd"] * p["mg_area"]


def sd_g_fixed(p):
    """The gust force's sd at the headwind's operating point: 2 k (v + W) sigma_w (66 N)."""
    return 2.0 * drag_k(p) * (V_OP + WIND_MEAN) * SIGMA_W


# variants: None (the reference), ("F",) F alone, ("FG", sd_mode, tau): F and G
VARIANTS = (None, ("F",), ("FG", "fixed", GUST_TAU), ("FG", "from F", GUST_TAU),
            ("FG", "fixed", DRYDEN_TAU))
SIM_LOGS = mos.SIM_LOGS
BOUND_TIMES = (5.0, 10.0, 14.0, 20.0, 30.0, 60.0, 120.0)
DENSE_MAX = 20.0                        # s: the dense covariance (a_x noise) up to 1000 samples
_SIM = {}


class MassGradeGust(mos.MassGradeOffset):
    """mass_offset_study's filter with the gust state G (module docstring); every pause,
    start and check as the reference's."""

    IT = IT  # theta's row, after G: the offset study's estimate, walk and pause steps read it

    def __init__(self, params, sd_mode="fixed", tau=GUST_TAU, sd_f0=SD_F0, q_f=Q_F):
        super().__init__(params, sd_f0, q_f)
        if sd_mode not in ("fixed", "from F"):
            raise ValueError("sd_mode is 'fixed' or 'from F'")
        if not tau > 0.0:
            raise ValueError("tau must be positive")
        p = self.p
        self.wm4, wc = mg.weights(p, NX)
        self.w4 = (wc[0], math.sqrt(abs(wc[0])), math.sqrt(wc[1]))
        self.c4 = math.sqrt(NX + mg.lambda_ut(p, NX))
        self.sd_mode, self.tau = sd_mode, tau

    def sd_g(self, v, f):
        """The gust force's stationary sd (N) at speed v and slow force f."""
        p = self.p
        if self.sd_mode == "fixed":
            return sd_g_fixed(p)
        k = drag_k(p)
        if not (f > 0.0 and k > 0.0):
            return 0.0
        w = math.sqrt(v * v + f / k) - v
        return 2.0 * k * (max(v, 0.0) + w) * TURB_I * w

    def _start(self, s):
        mg.MassGrade._start(self, s)
        p = self.p
        self.x = [s.v, p["mg_m0"], self.f0, 0.0, p["mg_theta0"]]
        sg = self.sd_g(s.v, self.f0)
        self.S = [[p["mg_r_v"], 0.0, 0.0, 0.0, 0.0], [0.0, p["mg_sd_m0"], 0.0, 0.0, 0.0],
                  [0.0, 0.0, self.sd_f0, 0.0, 0.0], [0.0, 0.0, 0.0, sg, 0.0],
                  [0.0, 0.0, 0.0, 0.0, p["mg_sd_theta0"]]]
        self.th_prev = self.x[IT]

    def _hold_sqrt(self, s, dt):
        # M and F held, G relaxes towards 0 (its Gauss-Markov prediction), theta walks
        p, S = self.p, self.S
        phi = math.exp(-dt / self.tau)
        qg = self.sd_g(s.v, self.x[IF]) * math.sqrt(1.0 - phi * phi)
        A = [[S[1][0], S[1][1], 0.0, 0.0, 0.0, 0.0, 0.0],
             [S[2][0], S[2][1], S[2][2], 0.0, 0.0, 0.0, 0.0],
             [phi * S[3][0], phi * S[3][1], phi * S[3][2], phi * S[3][3], 0.0, qg, 0.0],
             [S[4][0], S[4][1], S[4][2], S[4][3], S[4][4], 0.0, self._q_theta() * math.sqrt(dt)]]
        if mg.tria(A, 4, 7) is None:
            return mg.ERR_NONFINITE
        self.x[IV] = s.v
        self.x[IG] *= phi
        self.S = [[p["mg_r_v"], 0.0, 0.0, 0.0, 0.0], [0.0, A[0][0], 0.0, 0.0, 0.0],
                  [0.0, A[1][0], A[1][1], 0.0, 0.0], [0.0, A[2][0], A[2][1], A[2][2], 0.0],
                  [0.0, A[3][0], A[3][1], A[3][2], A[3][3]]]
        self.adapt_elapsed = 0.0
        self.m_adapt = self.x[IM]
        return mg.OK

    def _accel(self, q, torque):
        return mos.accel_f(self.p, q[IV], q[IM], q[IF] + q[IG], q[IT], torque)

    def _update_sqrt(self, s, dt):
        p, wm, w = self.p, self.wm4, self.w4
        phi = math.exp(-dt / self.tau)
        pts = mg.sigma_points_sqrt(self.x, self.S, self.c4, NX)
        X = [[q[IV] + dt * self._accel(q, self.torque_prev), q[IM], q[IF], phi * q[IG], q[IT]]
             for q in pts]
        sdt = math.sqrt(dt)
        qg = self.sd_g(self.x[IV], self.x[IF]) * math.sqrt(1.0 - phi * phi)
        sq = (p["mg_q_v"] * sdt, math.sqrt(p["mg_q_mc"] ** 2 + self.q_mv) * sdt, self.q_f * sdt,
              qg, self._q_theta() * sdt)
        xm = mg.mean(X, wm, NX)
        A = [[0.0] * (2 * NX + 1 + NX) for _ in range(NX)]
        mg.centred(X, xm, w, A, 0, NX)
        for r in range(NX):
            A[r][2 * NX + 1 + r] = sq[r]
        if mg.tria(A, NX, 2 * NX + 1 + NX) is None:
            return mg.ERR_NONFINITE
        x = list(xm)
        S = [[A[r][c] if c <= r else 0.0 for c in range(NX)] for r in range(NX)]
        if self.use_ax:
            pts = mg.sigma_points_sqrt(x, S, self.c4, NX)
            Z = [self._accel(q, s.torque) + p["g"] * math.sin(q[IT]) for q in pts]
            zm = mg.mean([[z] for z in Z], wm, NX)
            A = [[0.0] * (2 * NX + 2) for _ in range(1 + NX)]
            mg.centred([[z] for z in Z], zm, w, A, 0, NX)
            mg.centred(pts, x, w, A, 1, NX)
            A[0][2 * NX + 1] = p["mg_r_ax"]
            if mg.tria(A, 1 + NX, 2 * NX + 2) is None:
                return mg.ERR_NONFINITE
            if not A[0][0] > 0.0:
                return mg.ERR_NOT_POSITIVE_DEFINITE
            e = (s.ax - zm[0]) / A[0][0]
            for i in range(NX):
                x[i] += A[1 + i][0] * e
            S = [[A[1 + i][1 + c] for c in range(NX)] for i in range(NX)]
        rv = p["mg_r_v"]
        sz = math.sqrt(S[0][0] * S[0][0] + rv * rv)
        cs, sn, e = S[0][0] / sz, rv / sz, (s.v - x[0]) / sz
        for i in range(NX):
            x[i] += S[i][0] * cs * e
            S[i][0] *= sn
        x[IM] = min(max(x[IM], p["mg_m_min"]), p["mg_m_max"])
        x[IT] = min(max(x[IT], -p["mg_theta_max"]), p["mg_theta_max"])
        self.x, self.S = x, S
        if p["mg_adaptive"] == 1.0 and self.q_mv > 0.0:
            raise ValueError("the study runs the UKF (the recommended preset) only")
        return mg.OK


def make(p, variant):
    if variant is None:
        return mg.MassGrade(p)
    if variant[0] == "F":
        return mos.MassGradeOffset(p, SD_F0, Q_F)
    return MassGradeGust(p, variant[1], variant[2])


def log_cols(name):
    if name.startswith("sim:"):
        return _SIM[name[4:]]
    return mos.log_cols(name)


def one(job):
    name, guess, variant = job
    cols = log_cols(name)
    mt = float(cols["mass_true"][0])
    p = mg.preset(mgr.vehicle(name.replace("sim:", "")), **mg.MG_CONFIGS["recommended"])
    p["mg_m0"] = mt * (1.0 + guess)
    est = make(p, variant)
    outs = [est.step(s) for s in mg.samples(cols, est.p)]
    r = {"t": np.asarray(cols["t"], dtype=float)}
    for k in ("mass", "sd_mass", "grade", "sd_grade", "status"):
        r[k] = np.array([getattr(o, k) for o in outs])
    m = mgr.metrics(name, cols, r)
    m["f_end"] = est.x[IF] if variant is not None else None
    return job, m


def label(variant):
    if variant is None:
        return "without (the reference)"
    if variant[0] == "F":
        return f"F alone: sd {SD_F0:g} N, q {Q_F:g} N/sqrt(s)"
    sd = (f"sd_G {sd_g_fixed(mg.preset('car')):.0f} N" if variant[1] == "fixed"
          else f"sd_G from F (I {TURB_I:.3f})")
    return f"F + G: {sd}, tau {variant[2]:.2f} s"


def table(res, names):
    lines = ["| log | filter | mass error 10 s after the first excitation, starts "
             "-50/-20/+20/+50 % | largest mass error after that | mass error at the end "
             "(worst) | grade RMSE after it (worst) | grade step 2-10 s / flat drift |",
             "|---|---|---|---|---|---|---|"]
    for name in names:
        for v in VARIANTS:
            ms = [res[(name, g, v)] for g in mgr.GUESSES]
            extra = "–"
            if "step" in ms[0]:
                extra = f"{max(m['step'] for m in ms):.2f} deg"
            if "drift" in ms[0]:
                extra = f"{mgr.worst([m['drift'] for m in ms]):+.2f} %"
            lines.append(f"| {name.replace('sim:', 'sim: ')} | {label(v)} | "
                         + " / ".join(f"{m['err10']:+.2f}" for m in ms) + " % | "
                         f"{max(m['err_after'] for m in ms):.2f} % | "
                         f"{mgr.worst([m['err_end'] for m in ms]):+.2f} % | "
                         f"{max(m['rmse'] for m in ms):.3f} deg | {extra} |")
    return "\n".join(lines) + "\n"


def gm_cov(t, sd, tau):
    """The Gauss-Markov covariance sd^2 exp(-|t_i - t_j| / tau)."""
    return sd * sd * np.exp(-np.abs(t[:, None] - t[None, :]) / tau)


def regression(cols, p):
    """mass_offset_study.ls_split's regression on the truth signals: (t, x, y, true mass) with
    y = T/r - k v^2 - m_rot v-dot = M x + F (+ the gust force), x = v-dot + g ((f_c + f_r v)
    cos theta + sin theta)."""
    t = np.asarray(cols["t"], dtype=float)
    v, th = np.asarray(cols["vx_true"], dtype=float), np.asarray(cols["grade_true"], dtype=float)
    a = np.gradient(v, t)
    x = a + p["g"] * ((p["mg_fc"] + p["mg_fr"] * v) * np.cos(th) + np.sin(th))
    y = (np.asarray(cols["drive_torque"], dtype=float) / p["R"]
         - drag_k(p) * v * v - p["mg_m_rot"] * a)
    return t, x, y, float(cols["mass_true"][0])


def gls_bound(cols, p, t1, sd_g, tau, r_ax=0.0):
    """What the first t1 s can tell M, whatever the estimator, if the gust force is a
    Gauss-Markov process (sd_g, tau): the regression y = M x + F + G + e (e white, sd M r_ax:
    a_x's noise as a force; 0: the truth alone), fitted by generalised least squares. Returns
    (the fit's mass error [%], its Cramer-Rao sd [%] = sqrt of (X^T Sigma^-1 X)^-1's M entry
    over the true mass, F [N]). With truth signals the sd is a lower bound for any estimator
    from the sensors under that gust model (the sensors hold less than the truth)."""
    t, x, y, mt = regression(cols, p)
    s = t <= t1 + 1e-9
    n = int(s.sum())
    X = np.column_stack([x[s], np.ones(n)])
    sig = gm_cov(t[s], sd_g, tau) + (mt * r_ax) ** 2 * np.eye(n)
    si_x = np.linalg.solve(sig, X)
    c = np.linalg.inv(X.T @ si_x)
    b = c @ (si_x.T @ y[s])
    return 100.0 * (b[0] - mt) / mt, 100.0 * math.sqrt(c[0, 0]) / mt, float(b[1])


def gls_ar1(cols, p, t1, sd_g, tau):
    """gls_bound without a_x's noise, by whitening instead of the dense covariance (any
    length): a Gauss-Markov G sampled at t_k is AR(1), G_k = phi_k G_(k-1) + e_k with
    phi_k = exp(-(t_k - t_(k-1)) / tau) and var(e_k) = sd^2 (1 - phi_k^2), var(G_0) = sd^2, so
    the rows (z_k - phi_k z_(k-1)) / sqrt(1 - phi_k^2) (the first row z_0) of y and X carry
    white noise of sd sd_g and ordinary least squares on them is the GLS fit."""
    t, x, y, mt = regression(cols, p)
    s = t <= t1 + 1e-9
    t, x, y = t[s], x[s], y[s]
    X = np.column_stack([x, np.ones(len(x))])
    phi = np.exp(-np.diff(t) / tau)
    sc = np.sqrt(1.0 - phi * phi)
    Xw = np.vstack([X[:1], (X[1:] - phi[:, None] * X[:-1]) / sc[:, None]])
    yw = np.concatenate([y[:1], (y[1:] - phi * y[:-1]) / sc])
    c = np.linalg.inv(Xw.T @ Xw) * sd_g * sd_g
    b = np.linalg.lstsq(Xw, yw, rcond=None)[0]
    return 100.0 * (b[0] - mt) / mt, 100.0 * math.sqrt(c[0, 0]) / mt, float(b[1])


def exact_fit(cols, p, t1):
    """The same regression with the documented gusts' structure given (sin and cos of the
    7 s and 2.3 s periods as four more regressors, least squares): an oracle no car has."""
    t, x, y, mt = regression(cols, p)
    s = t <= t1 + 1e-9
    ts = t[s]
    Z = np.column_stack([x[s], np.ones(int(s.sum()))]
                        + [f(2.0 * np.pi * ts / per) for _, per in GUSTS
                           for f in (np.sin, np.cos)])
    b = np.linalg.lstsq(Z, y[s], rcond=None)[0]
    return 100.0 * (b[0] - mt) / mt


def bound_table(cols):
    """Per window [0, t1] and gust model: the GLS fit on the truth (gls_ar1) and, up to 20 s,
    with a_x's noise added (gls_bound, dense), the chance that an unbiased estimate with the
    Cramer-Rao sd lands within 3 % and 2 %, and the oracle fit with the gusts' periods."""
    p = mg.preset("car")
    sd = sd_g_fixed(p)
    lines = ["| fit over | gust model (sd_G, tau) | a_x noise | GLS mass error | Cramer-Rao sd of "
             "M | P(abs error < 3 %) / P(< 2 %) | F fitted | with the gusts' periods given: "
             "LS mass error |", "|---|---|---|---|---|---|---|---|"]
    for t1 in BOUND_TIMES:
        ex = exact_fit(cols, p, t1)
        for tau in (GUST_TAU, DRYDEN_TAU):
            for r_ax in ((0.0, 0.05) if t1 <= DENSE_MAX else (0.0,)):
                e, c, f = (gls_ar1(cols, p, t1, sd, tau) if r_ax == 0.0
                           else gls_bound(cols, p, t1, sd, tau, r_ax))
                p3 = math.erf(3.0 / (c * math.sqrt(2.0)))
                p2 = math.erf(2.0 / (c * math.sqrt(2.0)))
                lines.append(f"| 0–{t1:g} s | {sd:.0f} N, {tau:.2f} s | "
                             f"{'none (truth)' if r_ax == 0.0 else f'{r_ax:g} m/s^2'} | "
                             f"{e:+.1f} % | {c:.1f} % | {p3:.2f} / {p2:.2f} | {f:+.0f} N | "
                             f"{ex:+.1f} % |")
    return "\n".join(lines) + "\n"


def replace(text, name, body):
    pat = re.compile(rf"(<!-- {name}:begin -->\n).*?(<!-- {name}:end -->)", re.S)
    if not pat.search(text):
        raise SystemExit(f"marker {name} not found")
    return pat.sub(lambda m: m.group(1) + body + m.group(2), text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", help="write the tables into this page between their markers")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--logs", nargs="*", help="only these logs (default: every one)")
    a = ap.parse_args(argv)
    names = a.logs or mass_grade_names()
    if "car_headwind" in names:
        import mass_headwind_study
        _SIM.update(mass_headwind_study.make_variants())
        mos._SIM.update(_SIM)
        names = names + ["sim:" + k for k in SIM_LOGS]
    jobs = [(n, g, v) for n in names for v in VARIANTS for g in mgr.GUESSES]
    with multiprocessing.Pool(a.jobs) as pool:
        res = dict(pool.map(one, jobs, chunksize=1))
    t1 = table(res, names)
    print(t1)
    t2 = None
    if "car_headwind" in names:
        t2 = bound_table(mos.log_cols("car_headwind"))
        print(t2)
    if a.page:
        with open(a.page, encoding="utf-8") as fh:
            text = fh.read()
        text = replace(text, "mass-gust", t1)
        if t2 is not None:
            text = replace(text, "mass-gust-bound", t2)
        with open(a.page, "w", encoding="utf-8") as fh:
            fh.write(text)


if __name__ == "__main__":
    main()
