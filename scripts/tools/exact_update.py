"""Issue 17 (docs/MONITOR.md section 21): a log's first updates, the filter's against the
exact Bayes update on a grid, in the float64 reference only.

Usage (from the repository root):

    .venv/bin/python scripts/tools/exact_update.py [--scenarios scenarios]
        [--updates 2] [--step 0.005] LOG [LOG ...]

Runs the default preset with the library's three trust rules (trust_rules_study.reference_run,
as prior_study) on each LOG (a name as scenarios/NAME.csv) with relin_steps = 1 (today's
update, bit for bit), and at its first --updates updates takes the prior (x-, S-), step 4's
S_R, y and h as the run has them. It prints, per update: the prior; the exact posterior of
that Gaussian prior and the Gaussian likelihood N(y; h(mu), S_R S_R^T) on a grid of
--step over [mu_min, mu_max]^2 (its mean, sd, mode, the likelihood's maximum and its log
ratio against the prior mean, the NIS |S_R^-1 (y - h)|^2 at the truth's mu and at that
maximum, P(mu < 0.3) per side); then the posterior of today's update and of the recursive
update (N 2, 4) and the iterated posterior linearisation (2, 3 iterations) from the same
prior. The grid's mass beyond [mu_min, mu_max] is not represented (the projection's bounds).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
from scipy.linalg import solve_triangular

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # scripts: reference
from reference import filters, logs, params, trusted  # noqa: E402
sys.path.insert(0, str(Path(__file__).resolve().parent))        # tools
import trust_rules_study as trs  # noqa: E402

LOW = 0.3       # P(mu < LOW): the low hypothesis of sections 15-17


def grid_posterior(x0, s0, s_r, y, z, pts):
    """The exact posterior of N(x0, S0 S0^T) and y ~ N(h(mu), S_R S_R^T) on the grid points
    pts (n, G), z = h(pts) (m, G): normalised weights w (G,), mean, sd, mode, the likelihood's
    log at every point (G,)."""
    d = solve_triangular(s0, pts - x0[:, None], lower=True)
    r = solve_triangular(s_r, y[:, None] - z, lower=True)
    loglik = -0.5 * np.einsum("ij,ij->j", r, r)
    lw = -0.5 * np.einsum("ij,ij->j", d, d) + loglik
    w = np.exp(lw - lw.max())
    w /= w.sum()
    mean = pts @ w
    sd = np.sqrt(((pts - mean[:, None]) ** 2) @ w)
    return w, mean, sd, pts[:, int(np.argmax(lw))], loglik


_RECURSIVE = trusted.recursive_update     # the run's is replaced by a spy (first_updates)
VARIANTS = (("today", lambda f, y, h, s: f.measurement_update(y, h)),
            ("R2", lambda f, y, h, s: _RECURSIVE(f, y, h, 2, s)),
            ("R4", lambda f, y, h, s: _RECURSIVE(f, y, h, 4, s)),
            ("I2", lambda f, y, h, s: trusted.iterated_posterior_update(f, y, h, 2, s)),
            ("I3", lambda f, y, h, s: trusted.iterated_posterior_update(f, y, h, 3, s)))


def first_updates(path: Path, n_first: int, step: float) -> list[dict]:
    """The first n_first updates of the run on path, each evaluated when it happens (h is the
    run's closure over that step's inputs, so it is evaluated inside the run)."""
    log = logs.read_csv_log(str(path))
    p = params.resolve(log.meta, None, source=str(path), preset="default")
    truth = np.stack([log.col(f"mu_{w}") for w in trs.WHEELS], 1)
    t = log.col("t")
    g = np.arange(p["mu_min"], p["mu_max"] + 0.5 * step, step)
    pts = np.stack([c.ravel() for c in np.meshgrid(g, g, indexing="ij")])
    rec = []
    k_now = {"k": -1}       # the step: the conditioner runs once per step, before the update
    orig, cond_step = trusted.recursive_update, trusted.Conditioner.step

    def at(v):
        return int(np.argmin(np.abs(pts - np.asarray(v, dtype=float)[:, None]).sum(axis=0)))

    def spy(f, y, hfun, n, s_r):
        if len(rec) < n_first:
            y = np.asarray(y, dtype=float)
            w, mean, sd, mode, loglik = grid_posterior(f.x, f.S, f.s_r, y, hfun(pts), pts)
            k = k_now["k"]
            tr = truth[k][[0, 1]]        # fl (left side), fr (right side)
            i_ml = int(np.argmax(loglik))
            row = dict(t=t[k], x=f.x.copy(), sd=f.sd(), mean=mean, post_sd=sd, mode=mode,
                       ml=pts[:, i_ml], llr=loglik[i_ml] - loglik[at(f.x)],
                       nis_truth=-2.0 * loglik[at(tr)], nis_ml=-2.0 * loglik[i_ml], truth=tr,
                       low=[float(w[pts[j] < LOW].sum()) for j in range(2)], filters={})
            for lab, fn in VARIANTS:
                g2 = filters.SCKF(f.x.copy(), f.S.copy(), f.s_q, f.s_r.copy())
                fn(g2, y, hfun, s_r)
                row["filters"][lab] = (g2.x.copy(), g2.sd())
            rec.append(row)
        return orig(f, y, hfun, n, s_r)

    def counting(self, *a):
        k_now["k"] += 1
        return cond_step(self, *a)
    trusted.recursive_update, trusted.Conditioner.step = spy, counting
    try:
        trs.reference_run(path, library_rules=True, extra=dict(relin_steps=1.0))
    finally:
        trusted.recursive_update, trusted.Conditioner.step = orig, cond_step
    return rec


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="issue 17: the first updates against the exact one")
    ap.add_argument("logs", nargs="+")
    ap.add_argument("--scenarios", default="scenarios", type=Path)
    ap.add_argument("--updates", default=2, type=int)
    ap.add_argument("--step", default=0.005, type=float)
    a = ap.parse_args(argv)
    pair = lambda v: f"{v[0]:.2f}/{v[1]:.2f}"   # noqa: E731
    print("| log, update (t) | prior (sd) | truth | exact mean (sd) | mode | likelihood max "
          "(log ratio to x-) | NIS at truth, at max | P(mu < 0.3) | "
          + " | ".join(lab for lab, _ in VARIANTS) + " |")
    for name in a.logs:
        for i, r in enumerate(first_updates(a.scenarios / f"{name}.csv", a.updates, a.step)):
            print(f"| {name} {i + 1} ({r['t']:.2f} s) | {pair(r['x'])} ({pair(r['sd'])}) | "
                  f"{pair(r['truth'])} | {pair(r['mean'])} ({pair(r['post_sd'])}) | "
                  f"{pair(r['mode'])} | {pair(r['ml'])} ({r['llr']:.2f}) | "
                  f"{r['nis_truth']:.1f}, {r['nis_ml']:.1f} | {pair(r['low'])} | "
                  + " | ".join(f"{pair(x)} ({pair(s)})" for x, s in r["filters"].values())
                  + " |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
