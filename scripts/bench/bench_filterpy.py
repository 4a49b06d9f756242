"""The Python peer of the benchmark: FilterPy's CubatureKalmanFilter on the same model.

The estimator a Python user would pick: filterpy.kalman.CubatureKalmanFilter (the
full-covariance CKF of Arasaratnam and Haykin), with
  - fx: the random walk f(x) = x of MODEL.md section 5;
  - hx: the measurement function of scripts/reference (paper tyre: H(u_k) x with H from
    reference.model.observation_matrix; absolute tyre: reference.model.h_absolute);
  - the paper preset's x0, P0 = sd0^2 I, Q = q_mu^2 I, R = diag(r^2) from the log's metadata
    (reference.params.resolve), the same low-speed rule (no update below v_est_min) and the
    projection of the mean onto [mu_min, mu_max] after each update.
FilterPy's update() reuses the points its predict() drew from the previous posterior (before
Q was added); MODEL.md section 6 (and this library) draws the update's points from the
predicted P-. To run the same algorithm the points are redrawn after predict() with
FilterPy's own spherical_radial_sigmas(x-, P-) ("same algorithm", the one timed); "stock"
runs FilterPy unchanged, for the record of how far that is.

Usage: .venv/bin/python scripts/bench/bench_filterpy.py --log LOG.csv [--tyre paper|absolute]
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np

sys.path[:0] = [os.path.dirname(os.path.abspath(__file__)),  # this folder, and scripts/
                os.path.dirname(os.path.dirname(os.path.abspath(__file__)))]  # (sim, reference)
from reference import logs, model, params  # noqa: E402

from filterpy.kalman import CubatureKalmanFilter  # noqa: E402
from filterpy.kalman.CubatureKalmanFilter import spherical_radial_sigmas  # noqa: E402


def _fx(x, dt):
    return x


class Problem:
    """The log, its parameters and the per-sample measurement functions."""

    def __init__(self, log_path: str, tyre: str):
        log = logs.read_csv_log(log_path)
        self.p = p = params.resolve(log.meta, None, source=log_path, preset="paper")
        p["tyre"] = tyre
        self.tyre = tyre
        self.ti = model.tyre_inputs(p, log.col("delta"), log.col("vx"), log.col("vy"),
                                    log.col("yaw_rate"), log.col("ax"), log.col("ay"),
                                    log.omega())
        self.ys = np.stack([log.col("ax"), log.col("ay"), log.col("yaw_acc")], axis=-1)
        self.vx = log.col("vx")
        self.H = model.observation_matrix(p, self.ti) if tyre == "paper" else None
        self.k = 0

    def hx(self, x):
        """h(x, u_k) of one cubature point (4,) -> (3,)."""
        if self.tyre == "paper":
            return self.H[self.k] @ x
        return model.h_absolute(self.p, self.ti, self.k, x.reshape(4, 1))[:, 0]


def run(prob: Problem, same_algorithm: bool = True):
    """One pass over the log; returns mu, shape (N, 4)."""
    p = prob.p
    ckf = CubatureKalmanFilter(dim_x=4, dim_z=3, dt=p.get("dt", 0.01), hx=prob.hx, fx=_fx)
    ckf.x = np.full(4, p["mu0"])
    ckf.P = p["sd0"] ** 2 * np.eye(4)
    ckf.Q = p["q_mu"] ** 2 * np.eye(4)
    ckf.R = np.diag([p["r_ax"] ** 2, p["r_ay"] ** 2, p["r_yaw_acc"] ** 2])
    n = len(prob.vx)
    mu = np.empty((n, 4))
    for k in range(n):
        prob.k = k
        ckf.predict()
        if prob.vx[k] >= p["v_est_min"]:
            if same_algorithm:
                ckf.sigmas_f = spherical_radial_sigmas(ckf.x, ckf.P)
            ckf.update(prob.ys[k][:, None])
            ckf.x = np.clip(ckf.x, p["mu_min"], p["mu_max"])
        mu[k] = np.asarray(ckf.x).ravel()
    return mu


def timed(prob: Problem, reps: int):
    """(mu, per-step seconds: median, min, max) over reps passes."""
    per_step = []
    mu = None
    for _ in range(reps):
        t0 = time.perf_counter()
        mu = run(prob, True)
        per_step.append((time.perf_counter() - t0) / len(prob.vx))
    return mu, statistics.median(per_step), min(per_step), max(per_step)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--log", required=True)
    ap.add_argument("--tyre", default="paper", choices=("paper", "absolute"))
    ap.add_argument("--reps", type=int, default=3)
    a = ap.parse_args(argv)
    prob = Problem(a.log, a.tyre)
    mu, med, lo, hi = timed(prob, a.reps)
    print(f"FilterPy CKF ({a.tyre} tyre): {med * 1e6:.1f} us/step (min {lo * 1e6:.1f}, "
          f"max {hi * 1e6:.1f}); final mu {np.round(mu[-1], 4)}")
    stock = run(prob, False)
    print(f"stock FilterPy (points from the previous posterior) vs same algorithm: "
          f"max |dmu| {np.max(np.abs(stock - mu)):.2e}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
