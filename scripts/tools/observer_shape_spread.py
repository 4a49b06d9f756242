"""The tyre-shape spread of the observer's model row (docs/OBSERVER_RESULTS.md "The model row's
error from the tyre-shape family", issue 16): sigma_shape(u), the relative lateral-force error of
the observer's tyre model against a family of plausible tyres, as a function of the model's
utilisation u, and its fit to the rule's parameters.

    .venv/bin/python scripts/tools/observer_shape_spread.py [--stiffness matched|file]

The observer's model (OBSERVER.md §4.2) is the default preset's tyre, the Magic Formula of the
parameter file (model.magic_absolute). One wheel in pure lateral slip (kappa 0, Fz 1), at the
friction mu and the wheel speed v of each operating point (mu 0.35 and 0.9, v 20 m/s: the low-
and high-mu logs of issue 16's table; v enters only the Dugoff velocity reduction). For a model
utilisation u = Fy_model / (mu Fz) on the model's rising branch (u < 1), alpha_m(u) is the model's
slip angle there, and each member j of the family gives

    d_j(u) = (Fy_j(alpha_m(u)) - Fy_model(alpha_m(u))) / Fy_model(alpha_m(u))

the relative error the model row's ay makes when the car's tyre is j (ay is the sum of such
forces over the wheels, all at about the same utilisation in the single-track view). The family:

  dugoff: the normalised Dugoff curve of MODEL.md §4 (the project's other truth tyre) at the
          same mu and the model's cornering stiffness: mu F0 with Cy_n = cy / mu, which is the
          absolute Dugoff (model.dugoff_absolute) with the parameter file's cy and eps;
  mf_tol: the Magic Formula with the tyre data off by issue 17's 30 % (shape.shadow_params
          "mf_tol": cx, shape_Cy x 1.3; cy, shape_Cx x 0.7).

--stiffness matched (the rule's choice): each member's cornering stiffness set to the model's
(mf_tol's cy back to the file's; dugoff has it already), so d_j(0) = 0 and d_j is the shape's
error alone; a stiffness error is a relative error of ay constant in u, which obs_model_ay_rel
(rel0) already states. --stiffness file: mf_tol with its cy x 0.7 as well (d(0) = -0.3).

    RMS(u) = sqrt(mean over j and the operating points of d_j(u)^2)

(the RMS: the row's R is a variance, and with no preference among the family's members the
mean of the squared errors is the variance of the model's error about the car's tyre);
sigma_shape(u) is its running maximum over u (envelope), and the rule's two-parameter form
s_max min(1, (u / u_k)^2) is fitted to it by least squares (fit). The page's rule takes
rel(u) = sqrt(rel0^2 + sigma_shape(u)^2). The tool prints the table and the fit's two
numbers; nothing is typed by hand.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from reference import model, params, shape  # noqa: E402

MUS = (0.35, 0.9)        # the operating points' friction: issue 16's low- and high-mu logs
V_WHEEL = 20.0           # m/s, the wheel speed of the operating points (Dugoff's eps only)
U_MAX = 1.0 / 1.1        # §4.2 raises the friction to 1.1 |ay| / g: the model's u <= 0.91
U_TABLE = (0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, U_MAX)


def model_params() -> dict:
    """The observer's model tyre: the default preset's parameter set."""
    return params.resolve(preset="default")


def fy(p: dict, mu: float, alpha: np.ndarray, tyre: str) -> np.ndarray:
    """Lateral force per unit Fz of one wheel in pure lateral slip."""
    q = dict(p)
    q["tyre"] = tyre
    z = np.zeros_like(alpha)
    _, f = model.tyre_absolute(q, mu, np.ones_like(alpha), z, alpha, np.full_like(alpha, V_WHEEL))
    return f


def model_alpha(p: dict, mu: float, u: float) -> float:
    """The model's slip angle at utilisation u on its rising branch (bisection: the force
    rises monotonically up to its peak mu Fz)."""
    lo, hi = 0.0, 0.0
    a = 1e-4
    while fy(p, mu, np.array([a]), "magic")[0] < mu and a < p["alpha_max"]:
        hi = a
        a *= 1.05
    hi = a                       # the peak's slip (or alpha_max)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if fy(p, mu, np.array([mid]), "magic")[0] < u * mu:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def members(p: dict, stiffness: str) -> dict[str, dict]:
    """The family: name -> (parameter set, tyre)."""
    tol = shape.shadow_params(p, "mf_tol")
    if stiffness == "matched":
        tol["cy"] = p["cy"]
    elif stiffness != "file":
        raise ValueError(f"unknown stiffness {stiffness!r}")
    return {"dugoff": dict(p, tyre="dugoff"), "mf_tol": dict(tol, tyre="magic")}


def errors(p: dict, us, stiffness: str = "matched") -> dict[tuple[str, float], np.ndarray]:
    """d_j(u) per (member, mu) over the utilisations us."""
    out = {}
    for mu in MUS:
        al = np.array([model_alpha(p, mu, u) for u in us])
        f_m = fy(p, mu, al, "magic")
        for name, q in members(p, stiffness).items():
            out[(name, mu)] = (fy(q, mu, al, q["tyre"]) - f_m) / f_m
    return out


def sigma(d: dict) -> np.ndarray:
    """The RMS over the family and the operating points."""
    return np.sqrt(np.mean(np.stack(list(d.values())) ** 2, axis=0))


def envelope(s) -> np.ndarray:
    """The running maximum over u: the model is no better known at a higher utilisation than
    at a lower one (the RMS's dip near u 0.7 is the dugoff member's sign change, not a shape
    the family agrees on)."""
    return np.maximum.accumulate(np.asarray(s))


def knee(u, s_max: float, u_k: float):
    """The rule's two-parameter form: s_max min(1, (u / u_k)^2)."""
    return s_max * np.minimum(1.0, (np.asarray(u) / u_k) ** 2)


def fit(us, s) -> tuple[float, float]:
    """(s_max, u_k) of knee() by least squares on the envelope over the grid: u_k on a 0.01
    grid in [0.1, U_MAX], s_max in closed form for each."""
    us, s = np.asarray(us), np.asarray(s)
    best = None
    for u_k in np.arange(0.1, U_MAX + 1e-9, 0.01):
        b = knee(us, 1.0, u_k)
        s_max = float(b @ s / (b @ b))
        err = float(np.sum((s_max * b - s) ** 2))
        if best is None or err < best[0]:
            best = (err, s_max, float(u_k))
    return best[1], best[2]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--stiffness", choices=("matched", "file"), default="matched")
    args = ap.parse_args(argv)
    p = model_params()
    grid = np.linspace(0.02, U_MAX, 45)
    env = envelope(sigma(errors(p, grid, args.stiffness)))
    s_max, u_k = fit(grid, env)
    dt = errors(p, U_TABLE, args.stiffness)
    st = sigma(dt)
    et = envelope(st)
    names = list(dt)
    print(f"stiffness {args.stiffness}; model: magic, cy {p['cy']}, shape_Cy {p['shape_Cy']}, "
          f"shape_Ey {p['shape_Ey']}; v {V_WHEEL} m/s")
    print("| u | " + " | ".join(f"{nm} μ {mu}" for nm, mu in names)
          + " | RMS | σ_shape (envelope) | fit |")
    print("|---" * (len(names) + 4) + "|")
    for i, u in enumerate(U_TABLE):
        cells = " | ".join(f"{dt[k][i]:+.3f}" for k in names)
        print(f"| {u:.2f} | {cells} | {st[i]:.3f} | {et[i]:.3f} | {knee(u, s_max, u_k):.3f} |")
    resid = float(np.max(np.abs(knee(grid, s_max, u_k) - env)))
    print(f"fit σ_shape(u) = {s_max:.4f} min(1, (u / {u_k:.2f})^2); max |fit - envelope| "
          f"{resid:.4f} over u in [0.02, {U_MAX:.3f}]")
    return 0


if __name__ == "__main__":
    sys.exit(main())
