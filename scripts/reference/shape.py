"""Shape ambiguity: a second tyre-shape hypothesis beside the estimator's (docs/MONITOR.md
section 6, issue 17), float64 reference. A design study: off unless asked for, it changes
nothing of trusted.run or monitor.py.

The default preset's estimator fits one free parameter, mu, to a fixed tyre curve (the
Magic Formula of the parameter file). When the true curve has another shape, mu absorbs the
difference and the innovations stay consistent (docs/MONITOR.md section 5), so no test of the
innovations can see it. The rule studied here runs a shadow estimator, the same estimator
(ESTIMATOR.md, every step) with a second tyre hypothesis, on the same inputs, and compares:

  hypotheses (shadow_params):
    "paper":  the normalised Dugoff curve of MODEL.md section 4 (force = mu x the curve at
              mu = 1; Cx_n, Cy_n, eps of the parameter file): the other family of the
              project's two truth tyres;
    "mf_tol": the Magic Formula with stiffness and shape moved by `tol` (cx, shape_Cy
              x (1 + tol); cy, shape_Cx x (1 - tol)): the parameter file's tyre data off by
              what issue 17's wrong-tyre-data logs assume (30 %).
  rules (combine), per wheel and sample, with the primary's mu, sd, valid after the monitor
  (mu_a, sd_a, v_a) and the shadow's (mu_b, sd_b, v_b), d = mu_b - mu_a:
    "agree":   valid = v_a and v_b and |d| <= k sqrt(sd_a^2 + sd_b^2); mu, sd the primary's;
    "sd_term": sd = sqrt(sd_a^2 + d^2) where v_b (the shadow's mu is determined), valid =
               v_a and sd <= sd_valid; where not v_b, valid = v_a and sd = sd_a
               (the ambiguity enters the sd; the flag follows the sd rule of ESTIMATOR.md
               step 9);
    "agree_lr": "agree", except where the innovations favour the primary: valid = v_a and
               (the "agree" test or L > 0), L the exponentially weighted mean (time constant
               TAU_LR) of l_a - l_b over the steps that evaluate the measurement model,
               l = -|S_zz \\ nu|^2 / 2 - sum log diag S_zz the Gaussian log-likelihood of each
               run's own innovation (a likelihood ratio test of the two hypotheses, threshold 0).
The reported mu is always the primary's: the rule only says when it may be trusted.
"""
from __future__ import annotations

import numpy as np
from scipy.linalg import solve_triangular

HYPOTHESES = ("paper", "mf_tol")
RULES = ("agree", "sd_term", "agree_lr")
TOL = 0.3          # the tyre data's assumed tolerance (issue 17's wrong tyre data: 30 %)
K_AGREE = 2.0      # the agreement band in combined sd (the consistency test's 2 sd)
TAU_LR = 1.0       # s, the likelihood ratio's averaging time (twice the monitor's 0.5 s window)


def shadow_params(p: dict, hypothesis: str, tol: float = TOL) -> dict:
    """The parameter set of the shadow estimator: p with the tyre of the second hypothesis,
    everything else (noise, gate, bounds, holds, sd rule) unchanged."""
    q = dict(p)
    if hypothesis == "paper":
        q["tyre"] = "paper"
    elif hypothesis == "mf_tol":
        q["tyre"] = "magic"
        q["cx"], q["cy"] = p["cx"] * (1.0 + tol), p["cy"] * (1.0 - tol)
        q["shape_Cx"], q["shape_Cy"] = p["shape_Cx"] * (1.0 - tol), p["shape_Cy"] * (1.0 + tol)
    else:
        raise ValueError(f"unknown hypothesis {hypothesis!r}")
    return q


def loglik(res: dict) -> np.ndarray:
    """Per step the Gaussian log-likelihood of the recorded innovation (trusted.run's nu, s_zz)
    less the constant, -|S_zz \\ nu|^2 / 2 - sum log |diag S_zz|; NaN where the step did not
    evaluate the measurement model (low speed)."""
    n = len(res["status"])
    out = np.full(n, np.nan)
    for k in range(n):
        nu = res["nu"][k]
        if res["status"][k] != 2 and np.all(np.isfinite(nu)):
            w = solve_triangular(res["s_zz"][k], nu, lower=True)
            out[k] = -0.5 * float(w @ w) - float(np.sum(np.log(np.abs(np.diag(res["s_zz"][k])))))
    return out


def likelihood_ratio(a: dict, b: dict, dt: float, tau: float = TAU_LR) -> np.ndarray:
    """L_k: the exponentially weighted mean of l_a - l_b (weight dt / (tau + dt), L_0 = 0,
    unchanged at steps that evaluate no model)."""
    delta = loglik(a) - loglik(b)
    lam = dt / (tau + dt)
    out = np.zeros(len(delta))
    acc = 0.0
    for k, x in enumerate(delta):
        if np.isfinite(x):
            acc = (1.0 - lam) * acc + lam * x
        out[k] = acc
    return out


def combine(a: dict, b: dict, rule: str, sd_valid: float, k: float = K_AGREE,
            lr: np.ndarray | None = None) -> dict:
    """The primary run a (after the monitor) with the shadow run b: a copy of a whose valid
    and sd follow `rule` (module docstring). Arrays (N, 4) mu, sd, valid in both; lr (N,):
    likelihood_ratio(a, b), needed by "agree_lr"."""
    out = {key: np.array(v, copy=True) for key, v in a.items() if isinstance(v, np.ndarray)}
    va, vb = a["valid"].astype(bool), b["valid"].astype(bool)
    d = b["mu"] - a["mu"]
    if rule in ("agree", "agree_lr"):
        band = k * np.sqrt(a["sd"] ** 2 + b["sd"] ** 2)
        ok = vb & (np.abs(d) <= band)
        if rule == "agree_lr":
            if lr is None:
                raise ValueError("rule agree_lr needs the likelihood ratio lr")
            ok = ok | (np.asarray(lr)[:, None] > 0.0)
        out["valid"] = (va & ok).astype(int)
    elif rule == "sd_term":
        sd = np.where(vb, np.sqrt(a["sd"] ** 2 + d ** 2), a["sd"])
        out["sd"] = sd
        out["valid"] = (va & (sd <= sd_valid)).astype(int)
    else:
        raise ValueError(f"unknown rule {rule!r}")
    return out
