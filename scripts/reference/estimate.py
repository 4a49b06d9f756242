"""Run the reference estimator (MODEL.md section 6) on one sensor log and write its estimate log.

Usage, from the repository root (both forms work):

    .venv/bin/python -m scripts.reference.estimate --in SENSOR.csv --out EST.csv \
        [--preset paper|default] [--params FILE] [--filter sckf|ckf] [--tyre paper|absolute|magic]

--preset default (the default) runs docs/ESTIMATOR.md (trusted.py); --preset paper runs the
paper's filter of MODEL.md section 6, as below.
    .venv/bin/python scripts/reference/estimate.py --in SENSOR.csv --out EST.csv ...

Per sample k (row k of the output is the posterior after sample k):
  1. time update of the random walk through the cubature points (SCKF: Tria; CKF: full P);
  2. if the logged vx < v_est_min: no measurement update, status 2, valid 0;
     else measurement update with y = [ax, ay, yaw_acc] and u of that sample, then projection
     of the mean onto [mu_min, mu_max]: status 1 if any component was clamped, else 0; valid 1.
Tyre modes: "paper" (h = H(u) x, normalised Dugoff), "absolute" (load-scaled Dugoff,
h evaluated at each cubature point, mu < 0 evaluated at 0) and "magic" (load-scaled Magic
Formula, docs/ESTIMATOR.md, evaluated likewise).
"""

from __future__ import annotations

import argparse
import os
import sys

if __package__ in (None, ""):           # run as a script: make the package importable
    sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    import reference  # noqa: F401,E402
    __package__ = "reference"

import numpy as np  # noqa: E402

from . import filters, logs, model, monitor, params, runtime, trusted  # noqa: E402

FILTERS = ("sckf", "ckf")
TYRES = ("paper", "absolute", "magic")
STATUS_OK, STATUS_CLAMPED, STATUS_LOW_SPEED = 0, 1, 2


def make_filter(kind: str, p: dict, n: int = 4):
    """Initial filter of MODEL.md section 6 from the parameters (DATA.md keys)."""
    x0 = np.full(n, p["mu0"])
    r_sd = np.array([p["r_ax"], p["r_ay"], p["r_yaw_acc"]])
    if kind == "sckf":
        return filters.SCKF(x0, p["sd0"] * np.eye(n), p["q_mu"] * np.eye(n), np.diag(r_sd))
    if kind == "ckf":
        return filters.CKF(x0, p["sd0"] ** 2 * np.eye(n), p["q_mu"] ** 2 * np.eye(n),
                           np.diag(r_sd ** 2))
    raise ValueError(f"unknown filter {kind!r}")


def run(log: logs.CsvLog, p: dict, kind: str = "sckf", tyre: str = "paper"):
    """Run one filter over a whole sensor log. Returns dict of arrays t, mu, sd, valid, status."""
    if tyre not in TYRES:
        raise ValueError(f"unknown tyre mode {tyre!r}")
    p = dict(p, tyre=tyre)      # model.h_absolute picks the load-scaled curve from p["tyre"]
    ti = model.tyre_inputs(p, log.col("delta"), log.col("vx"), log.col("vy"),
                           log.col("yaw_rate"), log.col("ax"), log.col("ay"), log.omega())
    ys = np.stack([log.col("ax"), log.col("ay"), log.col("yaw_acc")], axis=-1)
    vx = log.col("vx")
    H = model.observation_matrix(p, ti) if tyre == "paper" else None   # (N, 3, 4)

    f = make_filter(kind, p)
    if kind == "sckf" and tyre == "paper":
        f.linear = True     # h = H(u) x: the update's exact n-column form (filters.SCKF)
    n_rows = len(log)
    mu = np.empty((n_rows, 4))
    sd = np.empty((n_rows, 4))
    valid = np.zeros((n_rows, 4), dtype=int)
    status = np.empty(n_rows, dtype=int)
    mu_unprojected = np.empty((n_rows, 4))      # diagnostics (compare.py): the mean before
    t = log.col("t")
    for k in range(n_rows):                     # projection, and vx, the low-speed gate's input
        filters.gap_time_update(f, t, k, p)     # a gap (ESTIMATOR.md "Gaps")
        f.time_update()
        if vx[k] < p["v_est_min"]:
            status[k] = STATUS_LOW_SPEED
        else:
            if tyre == "paper":
                h = H[k].__matmul__                         # Z_j = H(u_k) X_j (MODEL.md 5)
            else:
                h = lambda pts, k=k: model.h_absolute(p, ti, k, pts)  # noqa: E731  (MODEL.md 4)
            f.measurement_update(ys[k], h)
            mu_unprojected[k] = f.x
            f.x, clamped = filters.project(f.x, p["mu_min"], p["mu_max"])
            status[k] = STATUS_CLAMPED if clamped else STATUS_OK
            valid[k, :] = 1
        if status[k] == STATUS_LOW_SPEED:
            mu_unprojected[k] = f.x
        mu[k] = f.x
        sd[k] = f.sd()
    return {"t": log.col("t"), "mu": mu, "sd": sd, "valid": valid, "status": status,
            "v_gate": vx, "mu_unprojected": mu_unprojected}


def metadata(kind: str, tyre: str, input_path: str, p: dict, param_file: str | None = None,
             preset: str = "paper"):
    """Metadata lines of an estimate log: generator, preset, filter, tyre, structure, input,
    the numerical machinery that computed it (runtime.py: BLAS kernel, numpy SIMD paths),
    then every parameter (the reference-only ones only when set)."""
    meta = [("generator", "scripts/reference"), ("preset", preset), ("filter", kind),
            ("tyre", tyre), ("structure", p.get("structure", "wheels")),
            ("input", os.path.basename(input_path))]
    if param_file:
        meta.append(("param_file", os.path.basename(param_file)))
    meta += runtime.metadata()
    # every key but the reference-only ones (not in the C library's estimate logs), which are
    # recorded only when they are set; a rule's keys of WHEN_ON all while the rule is on
    def recorded(k):
        if k in params.WHEN_ON_KEYS:
            return any(p[on] > 0 and k in keys for on, keys in params.WHEN_ON.items())
        return k not in params.REFERENCE_ONLY or p[k] != params.DEFAULTS[k]
    meta += [(k, float(p[k])) for k in params.DEFAULTS if recorded(k)]
    return meta


def estimate_file(in_path: str, out_path: str, param_file: str | None = None,
                  kind: str = "sckf", tyre: str | None = None, preset: str = "paper",
                  overrides: dict | None = None):
    """Read a sensor log, resolve parameters, run, write the estimate log. Returns run()'s dict.
    tyre None: the preset's tyre; overrides: key = value pairs applied last. With mon_enable
    1 the model-validity monitor (monitor.py) acts on the run's valid, status and sd."""
    log = logs.read_csv_log(in_path)
    p = params.resolve(log.meta, param_file, source=in_path, preset=preset)
    p.update(overrides or {})
    if tyre is not None:
        p["tyre"] = tyre
    if p["mon_enable"] > 0 and (preset == "paper" or kind != "sckf"):
        raise params.ParamError("the monitor (mon_enable = 1) runs on the default preset's SCKF")
    if preset == "paper":
        res = run(log, p, kind, p["tyre"])
    else:
        if kind != "sckf":
            raise params.ParamError("the CKF baseline needs --preset paper")
        res = trusted.run(log, p)
        if p["mon_enable"] > 0:
            res = monitor.apply(res, p, p["dt"])
    logs.write_estimate_log(out_path, metadata(kind, p["tyre"], in_path, p, param_file, preset),
                            res["t"], res["mu"], res["sd"], res["valid"], res["status"])
    return res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--in", dest="inp", required=True, help="sensor log (DATA.md)")
    ap.add_argument("--out", required=True, help="estimate log to write")
    ap.add_argument("--params", default=None, help="parameter file (key = value)")
    ap.add_argument("--filter", default="sckf", choices=FILTERS)
    ap.add_argument("--tyre", default=None, choices=TYRES, help="default: the preset's")
    ap.add_argument("--preset", default="default", choices=tuple(params.PRESETS))
    a = ap.parse_args(argv)
    try:
        estimate_file(a.inp, a.out, a.params, a.filter, a.tyre, a.preset)
    except (params.ParamError, logs.LogError, OSError) as exc:
        print(f"estimate: error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
