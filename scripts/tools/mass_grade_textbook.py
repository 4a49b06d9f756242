#!/usr/bin/env python3
"""Run the textbook (full-covariance) mass and grade filter in float32 and with an int32
covariance, and say where its covariance stops being positive definite (issue 19).

    .venv/bin/python scripts/tools/mass_grade_textbook.py [--page docs/MASS_GRADE_RESULTS.md]
                     [--jobs N] [--rows K] [--logs NAME ...]
                     [--lib-f32 build/f32/test/tools/mg_run_flt --lib-q31 build/q31/test/tools/mg_run_q31]

(`make mass-grade-textbook` runs it with the library's drivers and writes the page.)

The filter is the float64 reference's own textbook step (scripts/reference/mass_grade.py,
form="textbook", through its Arith hook), not a copy:
  f64   the reference as it is (Python floats);
  f32   every arithmetic result a numpy float32 (parameters and samples rounded to float32 once,
        the period dt from the double time stamps rounded once, as the C float build gets it);
        sqrt is IEEE float32 (np.sqrt, exactly rounded), sin/cos the double libm value rounded
        once to float32. No BLAS: the reference writes every 3x3 sum as a loop of scalar
        operations, and numpy's float32 scalar + - * / are IEEE, so the run is bit-reproducible
        on any CPU (np.dot, @ and np.linalg would not be: their summation order and FMA use
        depend on the CPU);
  q31P  the reference in double, except that each covariance it stores (the start, P- after
        the prediction, P after the update, the hold, the adaptation) is rounded to int32 in a
        fixed format per entry with saturation (P_ij in Q(a_i + a_j), a = A_Q31 below): the
        finest int32 format that still holds the largest variance docs/FIXED_POINT.md "Mass
        and grade" measured (P_vv, P_tt <= 2.5e-3, P_MM <= 4.0e6 kg^2 -> Q38, Q38, Q8). The
        Q31 twin's own formats (v Q24, M Q14, theta Q29) squared (Q48, Q28, Q58) do not fit an
        int32 P, which is why it carries the factor S. Everything else in double: a best case
        for a textbook Q31 filter, whose failures are then the covariance's storage alone.
Per run: the first step whose stored P is not positive definite (a Cholesky of it in double
with a pivot <= 0, or a NaN), the steps whose sigma points could not be drawn (status 21,
RFE_ERR_NOT_POSITIVE_DEFINITE: the reference then keeps its state, the filter frozen), the
steps whose status differs from f64's, the worst |mass - mass_f64| (kg) and the
smallest definiteness margin min_j L_jj^2 / P_jj (1 for a diagonal P, 0 at singularity).
A failed step keeps the reference's state and its time stamp, so the period to the next sample
grows and after mg_dt_max (1 s) the filter restarts from mg_m0 (§4.1). With --lib-f32/--lib-q31
the library's own estimator runs the same samples and parameters (test/tools/mg_run_flt.c: the
float build, the square-root form since issue 19's fix (it ran the textbook form before);
mg_run_q31.c: the Q31 twin, the square-root form), its
period from row to row as in the C golden tests: a float run that fails stays frozen to the end.
Configurations: UKF and AUKF, each on speed alone and with the accelerometer row, on the log's
vehicle preset (truck for truck_*), the keys of MASS_GRADE.md §6 otherwise; plus stress runs
that look for the float32 failure beyond the bundled logs (STRESS below).
With --page the table goes between <!-- mass-grade-textbook:begin/end --> of the page.
"""

import argparse
import functools
import math
import multiprocessing
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "scripts"))

from reference import mass_grade as mg  # noqa: E402
from mass_logs import mass_grade_names  # noqa: E402

LOGS = os.path.join(ROOT, "scenarios", "mass_grade")
CONFIGS = (("UKF", 0.0, 0.0), ("UKF + ax", 0.0, 1.0), ("AUKF", 1.0, 0.0), ("AUKF + ax", 1.0, 1.0))
A_Q31 = (19, 4, 19)          # P_ij in Q(a_i + a_j): P_vv Q38, P_MM Q8, P_tt Q38, P_vM Q23, ...
I32_MAX, I32_MIN = 2 ** 31 - 1, -(2 ** 31)


def _f32_fn(fn):
    # the double libm value rounded once (glibc's sin/cos are correctly rounded in practice;
    # numpy's float32 sin/cos are SIMD kernels that may differ by an ulp between CPUs)
    return lambda x: np.float32(fn(float(x)))


F32 = mg.Arith(real=np.float32, sqrt=np.sqrt, sin=_f32_fn(math.sin), cos=_f32_fn(math.cos))


class Q31Store:
    """store_cov for the q31P arithmetic: each entry rounded to nearest in its format,
    saturated to int32; counts the saturated entries."""

    def __init__(self, a=A_Q31):
        self.q = [[a[i] + a[j] for j in range(3)] for i in range(3)]
        self.sat = 0

    def __call__(self, P):
        out = [[0.0] * 3 for _ in range(3)]
        for i in range(3):
            for j in range(3):
                v = P[i][j]
                if math.isnan(v):
                    out[i][j] = v
                    continue
                k = math.ldexp(v, self.q[i][j])
                k = math.floor(k + 0.5) if math.isfinite(k) else (I32_MAX if k > 0 else I32_MIN)
                if k > I32_MAX or k < I32_MIN:
                    self.sat += 1
                    k = min(max(k, I32_MIN), I32_MAX)
                out[i][j] = math.ldexp(float(k), -self.q[i][j])
        return out


def arith(kind):
    if kind == "f64":
        return mg.F64
    if kind == "f32":
        return F32
    if kind == "q31P":
        st = Q31Store()
        return mg.Arith(store_cov=st)
    raise ValueError(kind)


def margin(P):
    """min_j L_jj^2 / P_jj of the stored P (in double; exact for float32 entries): <= 0 or NaN
    when P is not positive definite."""
    a = [[float(P[i][j]) for j in range(3)] for i in range(3)]
    if any(math.isnan(v) for r in a for v in r):
        return math.nan
    L = [[0.0] * 3 for _ in range(3)]
    worst = math.inf
    for j in range(3):
        d = a[j][j]
        for k in range(j):
            d -= L[j][k] * L[j][k]
        if not a[j][j] > 0.0 or not d > 0.0:
            return min(d / a[j][j], 0.0) if a[j][j] > 0.0 else -math.inf
        worst = min(worst, d / a[j][j])
        L[j][j] = math.sqrt(d)
        for i in range(j + 1, 3):
            s = a[i][j]
            for k in range(j):
                s -= L[i][k] * L[j][k]
            L[i][j] = s / L[j][j]
    return worst


def samples(cols, p, kind, rows=None):
    """The reference's samples of a log, each value rounded to float32 for f32 (t stays
    double: the filter takes only the period, rounded in its step)."""
    out = []
    for i, s in enumerate(mg.samples(cols, p)):
        if rows is not None and i >= rows:
            break
        if kind == "f32":
            s = mg.MgSample(s.t, *(None if v is None else np.float32(v)
                                   for v in (s.v, s.torque, s.brake, s.brake_pressure, s.gear,
                                             s.ax)))
        out.append(s)
    return out


def run(cols, p, kind, rows=None):
    """One run: arrays mass, sd_mass, status, margin per step, and the saturation count."""
    ar = arith(kind)
    est = mg.MassGrade(p, ar, form="textbook")
    n = len(cols["t"]) if rows is None else min(rows, len(cols["t"]))
    mass, sd, status, marg = (np.empty(n) for _ in range(4))
    with np.errstate(all="ignore"):
        for k, s in enumerate(samples(cols, est.p, kind, rows)):
            o = est.step(s)
            mass[k], sd[k], status[k] = float(o.mass), float(o.sd_mass), o.status
            marg[k] = margin(est.P) if est.started else math.nan
    sat = ar.store_cov.sat if isinstance(ar.store_cov, Q31Store) else 0
    return {"mass": mass, "sd_mass": sd, "status": status, "margin": marg, "sat": sat,
            "x": est.x, "P": est.P}


def summary(ref, r):
    """The figures of one run against the f64 run of the same log and parameters."""
    # a failure: the stored P not positive definite, or the filter's own Cholesky of
    # (n + lambda) P or P- (in its arithmetic) failed: status 21, the state kept
    bad = np.flatnonzero((~(r["margin"] > 0.0) & ~np.isnan(ref["margin"]))
                         | (r["status"] == mg.ERR_NOT_POSITIVE_DEFINITE))
    npd = np.flatnonzero(r["status"] == mg.ERR_NOT_POSITIVE_DEFINITE)
    dm = np.abs(r["mass"] - ref["mass"])
    dm = np.where(np.isnan(dm) & ~np.isnan(ref["mass"]), np.inf, dm)
    return {"first_npd": int(bad[0]) if len(bad) else None, "n_npd": int(len(bad)),
            "first_21": int(npd[0]) if len(npd) else None, "n_21": int(len(npd)),
            "n_status": int(np.sum(r["status"] != ref["status"])),
            "dmass": float(np.nanmax(dm)) if len(dm) else 0.0,
            "end_mass": float(r["mass"][-1]), "end_sd": float(r["sd_mass"][-1]),
            "min_margin": float(np.nanmin(r["margin"])), "sat": r["sat"], "steps": len(r["mass"])}


def vehicle(name):
    return "truck" if name.startswith("truck") else "car"


# Stress runs, beyond the bundled logs, with the process noise of
# test_square_root_form_stays_definite (docs/FIXED_POINT.md "Mass and grade"; TIGHT_Q):
#   the flat cruise as it is (acceleration 2-20 s, then 160 s of constant speed);
#   its cruise alone (from row CRUISE_FROM, 30 s), played 4 times back to back (600 s, the
#   speed continuous at the seams): the speed then determines only one combination of M and
#   theta (T/R = M g (f + theta) + drag), so P's (M, theta) block tends to singular.
TIGHT_Q = {"mg_q_mc": 1e-3, "mg_q_theta": 1e-7, "mg_q_v": 1e-6}
CRUISE_FROM = 1500
STRESS = {
    "car_flat_cruise, tight Q": ("car_flat_cruise", 0, 1, TIGHT_Q),
    "car_flat_cruise's cruise x4, tight Q": ("car_flat_cruise", CRUISE_FROM, 4, TIGHT_Q),
}


def repeat(cols, times):
    """The log played `times` times back to back, the time stamps continuing."""
    if times == 1:
        return cols
    t = cols["t"]
    dt = float(t[1] - t[0])
    span = float(t[-1] - t[0]) + dt
    out = {k: np.concatenate([v] * times) for k, v in cols.items()}
    out["t"] = np.concatenate([t + i * span for i in range(times)])
    return out


def job_params(job):
    name, cfg, stress = job
    _, adaptive, use_ax = next(c for c in CONFIGS if c[0] == cfg)
    log, start, times, extra = STRESS[stress] if stress else (name, 0, 1, {})
    cols, _ = mg.read_log(os.path.join(LOGS, log + ".csv"))
    cols = repeat({k: v[start:] for k, v in cols.items()}, times)
    return cols, mg.preset(vehicle(log), mg_adaptive=adaptive, mg_use_ax=use_ax, **extra)


LOG_COLS = ("t", "omega_fl", "omega_fr", "omega_rl", "omega_rr", "drive_torque", "ax",
            "brake_pressure", "gear", "brake")   # what the drivers read (test/support/mg_logs.h)


def run_c(driver, cols, p, rows=None):
    """The library's estimator over the same samples: driver is build/f32/test/tools/mg_run_flt
    (the float build, the textbook form) or build/q31/test/tools/mg_run_q31 (the square-root
    form); the log and the parameters go through a temporary directory. Returns its summary
    (test/tools/mg_run_common.h) as a dict."""
    n = len(cols["t"]) if rows is None else min(rows, len(cols["t"]))
    with tempfile.TemporaryDirectory() as d:
        par, log = os.path.join(d, "params"), os.path.join(d, "log.csv")
        with open(par, "w", encoding="utf-8") as fh:
            fh.writelines(f"# {k} = {float(p[k])!r}\n" for k in mg.MG_DEFAULTS)
        np.savetxt(log, np.column_stack([cols[c][:n] for c in LOG_COLS]), fmt="%.17g",
                   delimiter=",", header=",".join(LOG_COLS), comments="")
        out = subprocess.run([driver, par, log], check=True, capture_output=True, text=True)
    vals = dict(kv.split("=") for kv in out.stdout.split())
    return {k: (float(v) if k in ("mass", "sd_mass") else int(v)) for k, v in vals.items()}


def one(job, drivers=None):
    cols, p = job_params(job[:3])
    rows = job[3]
    ref = run(cols, p, "f64", rows)
    out = {"f64": summary(ref, ref)}
    for kind in ("f32", "q31P"):
        out[kind] = summary(ref, run(cols, p, kind, rows))
    for kind, driver in (drivers or {}).items():
        out[kind] = run_c(driver, cols, p, rows)
    return job[:3], out


def fmt_fail(s):
    """'-' or 'step k (n)': the first failed step and how many failed (of them status 21)."""
    if s["first_npd"] is None:
        return "–"
    return f"step {s['first_npd']} ({s['n_npd']}; {s['n_21']} st. 21)"


def fmt_dm(s):
    return "NaN" if not math.isfinite(s["dmass"]) else f"{s['dmass']:.2g} kg"


def fmt_c(c):
    """A library run: '–' or the first failed step (status 21 or P not positive definite,
    how many; nonfinite estimates), and its saturations (Q31)."""
    first = min((v for v in (c["first21"], c["first_npd"]) if v >= 0), default=None)
    txt = "–" if first is None else f"step {first} ({max(c['n21'], c['npd'])}; " \
                                     f"{c['n21']} st. 21)"
    if c["nonfinite"]:
        txt += f", {c['nonfinite']} NaN"
    if c["sat"]:
        txt += f", {c['sat']} sat."
    return txt


def table(res):
    lib = "lib_f32" in next(iter(res.values()))
    head = ["log", "configuration", "steps", "smallest margin f64 / f32 / int32-P",
            "f32: first failure (failed steps; status 21)", "f32: worst \\|Δmass\\|",
            "int32-P: first failure (failed; status 21)", "int32-P: worst \\|Δmass\\|"]
    if lib:
        head += ["library float (square root)", "library Q31 (square root)"]
    head += ["mass at the end: f64 / f32 / int32-P" + (" / library float / Q31" if lib else "")]
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for (name, cfg, stress), o in res.items():
        f64, f, q = o["f64"], o["f32"], o["q31P"]
        label = f"*{stress}*" if stress else name
        row = [label, cfg, str(f64["steps"]), f"{f64['min_margin']:.2g} / "
               f"{f['min_margin']:.2g} / {q['min_margin']:.2g}", fmt_fail(f), fmt_dm(f),
               fmt_fail(q), fmt_dm(q)]
        ends = [f64["end_mass"], f["end_mass"], q["end_mass"]]
        if lib:
            row += [fmt_c(o["lib_f32"]), fmt_c(o["lib_q31"])]
            ends += [o["lib_f32"]["mass"], o["lib_q31"]["mass"]]
        row.append(" / ".join(f"{m:.0f}" for m in ends) + " kg")
        lines.append("| " + " | ".join(row) + " |")
    return "\n".join(lines) + "\n"


def replace_block(text, name, body):
    pat = re.compile(rf"(<!-- {name}:begin -->\n).*?(<!-- {name}:end -->)", re.S)
    if not pat.search(text):
        raise SystemExit(f"marker {name} not found")
    return pat.sub(lambda m: m.group(1) + body + m.group(2), text)


def jobs_all(rows=None, logs=None):
    names = mass_grade_names()
    if logs:
        names = [n for n in names if n in logs]
    jobs = [(n, c[0], None, rows) for n in names for c in CONFIGS]
    jobs += [(None, c[0], s, rows) for s in STRESS for c in CONFIGS]
    return jobs


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--page", help="write the table into this page between its markers")
    ap.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--rows", type=int, help="only the first ROWS rows of each log")
    ap.add_argument("--logs", nargs="*", help="only these logs (names without .csv)")
    ap.add_argument("--lib-f32", help="the float driver (build/f32/test/tools/mg_run_flt)")
    ap.add_argument("--lib-q31", help="the Q31 driver (build/q31/test/tools/mg_run_q31)")
    a = ap.parse_args(argv)
    drivers = {k: os.path.abspath(v) for k, v in (("lib_f32", a.lib_f32), ("lib_q31", a.lib_q31))
               if v}
    if len(drivers) == 1:
        raise SystemExit("give both --lib-f32 and --lib-q31, or neither")
    jobs = jobs_all(a.rows, a.logs)
    # longest first, so that the pool's two workers end together
    jobs.sort(key=lambda j: -(STRESS[j[2]][2] * 9e5 if j[2]
                              else os.path.getsize(os.path.join(LOGS, j[0] + ".csv"))))
    with multiprocessing.Pool(a.jobs) as pool:
        res = dict(pool.map(functools.partial(one, drivers=drivers), jobs, chunksize=1))
    order = {j[:3]: i for i, j in enumerate(jobs_all(a.rows, a.logs))}
    res = dict(sorted(res.items(), key=lambda kv: order[kv[0]]))
    t = table(res)
    print(t)
    if a.page:
        with open(a.page, encoding="utf-8") as f:
            text = f.read()
        text = replace_block(text, "mass-grade-textbook", t)
        with open(a.page, "w", encoding="utf-8") as f:
            f.write(text)


if __name__ == "__main__":
    main()
