"""Truth tyre models of the reference vehicle simulator.

Both models are written as *per-unit-load* functions: they return (fx, fy) such that the
wheel-axis tyre forces are Fx = Fz*fx, Fy = Fz*fy.  That is exact for both models, because
at fixed slip and friction their forces are proportional to the vertical load (no load
sensitivity of the friction coefficient or of the stiffness per unit load).  The simulator
uses this to solve the load <-> force algebraic loop (see vehicle.py).

Scalar (math-module) code on purpose: the simulator calls these 4 times per derivative
evaluation and Python floats are ~20x faster than numpy on 4-element arrays.
Use :func:`vectorised` to evaluate them over arrays (tests, plots).

"dugoff" (default truth, MODEL.md section 4, paper mode)
    Fx = mu*F0x, Fy = mu*F0y with the normalised Dugoff forces F0 (stiffness Cx_n*mu*Fz,
    Cy_n*mu*Fz).  Singularity-free form:
        a = 1 - |kappa|,  t = tan(alpha),  S = sqrt((Cx_n*kappa)^2 + (Cy_n*t)^2)
        e = max(0, 1 - eps*|v_wx|*sqrt(kappa^2 + t^2))
        L = a*e/(2S);  f(L)/a = 1/a          if S == 0 or L >= 1   (then a > 0)
                       f(L)/a = e*(2-L)/(2S)  if L < 1              (no division by a)
        F0x/Fz = Cx_n*kappa*f(L)/a,  F0y/Fz = Cy_n*t*f(L)/a

"mf" (Magic-Formula-type truth whose slip stiffness does not scale with mu)
    Pure slip: Fx0 = D sin(Cx atan(Bx k - Ex (Bx k - atan(Bx k)))), D = mu*Fz,
    Bx = cx/(Cx*mu) so that the slope at zero slip Bx*Cx*D = cx*Fz whatever mu is; lateral
    alike with tan(alpha) as the slip, cy, Cy, Ey.  Peak = mu*Fz exactly (Cx, Cy > 1 and
    Ex, Ey < 1 so that the sine argument reaches pi/2).
    Combined slip: the "similarity" / isotropic normalised-slip method.  Normalised slips
        rho_x = cx*kappa/mu,  rho_y = cy*tan(alpha)/mu,  rho = sqrt(rho_x^2 + rho_y^2)
    (rho is the utilisation a linear tyre would have), and with the pure-slip shape
    functions G(rho) = sin(C atan(x - E (x - atan x))), x = rho/C  (so Fx0 = mu*Fz*Gx(rho_x)):
        Fx = mu*Fz*(rho_x/rho)*Gx(rho) = Fz*cx*kappa*Gx(rho)/rho
        Fy = mu*Fz*(rho_y/rho)*Gy(rho) = Fz*cy*tan(alpha)*Gy(rho)/rho
    This reduces exactly to the pure-slip curves, keeps |F| <= mu*Fz (|G| <= 1), and is
    smooth everywhere: G(rho)/rho is an even analytic function of rho (a series is used
    below rho = 1e-4), finite at zero slip, at a locked wheel (kappa = -1) and at standstill
    (kappa = 0 by the v_min guard, |alpha| bounded by alpha_max).  No velocity term (eps
    is a Dugoff parameter).  mu <= 0 gives zero force.
    Shape factors (Params.mf_Cx, mf_Ex, mf_Cy, mf_Ey) default to 1.65, 0.0, 1.3, -1.0:
    at mu = 0.85 the longitudinal peak is at kappa ~ 0.10 and the lateral at alpha ~ 7.8 deg;
    beyond the peak the force falls to sin(C*pi/2)*mu*Fz (0.52 / 0.81 of the peak).
"""

from math import atan, sin, sqrt, tan

__all__ = ["dugoff_unit", "dugoff_normalised", "mf_unit", "mf_shape_over_rho",
           "TRUTH_TYRES", "vectorised"]


def dugoff_unit(kappa, alpha, vwx_abs, mu, p):
    """Paper-mode Dugoff forces per unit load: (mu*F0x/Fz, mu*F0y/Fz).

    kappa in [-1, 1], |alpha| <= alpha_max (callers clip), vwx_abs = |v_wx| >= 0.
    """
    t = tan(alpha)
    a = 1.0 - abs(kappa)
    cxk = p.Cx_n * kappa
    cyt = p.Cy_n * t
    S = sqrt(cxk * cxk + cyt * cyt)
    e = 1.0 - p.eps * vwx_abs * sqrt(kappa * kappa + t * t)
    if e < 0.0:
        e = 0.0
    if S == 0.0:
        g = 1.0  # kappa = 0 and alpha = 0: a = 1, f = 1, forces are zero anyway
    else:
        L = a * e / (2.0 * S)
        if L < 1.0:
            g = e * (2.0 - L) / (2.0 * S)  # = f(L)/a with f = L(2-L)
        else:
            g = 1.0 / a  # L >= 1 with S > 0 implies a > 0
    return mu * cxk * g, mu * cyt * g


def dugoff_normalised(kappa, alpha, vwx_abs, Fz, p):
    """MODEL.md section 4 normalised forces (F0x, F0y) for load Fz (mu = 1 in dugoff_unit)."""
    fx, fy = dugoff_unit(kappa, alpha, vwx_abs, 1.0, p)
    return Fz * fx, Fz * fy


def mf_shape_over_rho(rho, C, E):
    """G(rho)/rho for G(rho) = sin(C*atan(x - E*(x - atan(x)))), x = rho/C, rho >= 0."""
    if rho < 1e-4:
        # G = rho - rho^3*((1+E)/(3C^2) + 1/6) + O(rho^5)
        return 1.0 - rho * rho * ((1.0 + E) / (3.0 * C * C) + 1.0 / 6.0)
    x = rho / C
    return sin(C * atan(x - E * (x - atan(x)))) / rho


def mf_unit(kappa, alpha, vwx_abs, mu, p):
    """Magic-Formula combined-slip forces per unit load (see module docstring)."""
    if mu <= 0.0:
        return 0.0, 0.0
    t = tan(alpha)
    cxk = p.cx * kappa
    cyt = p.cy * t
    rho = sqrt(cxk * cxk + cyt * cyt) / mu
    return (cxk * mf_shape_over_rho(rho, p.mf_Cx, p.mf_Ex),
            cyt * mf_shape_over_rho(rho, p.mf_Cy, p.mf_Ey))


TRUTH_TYRES = {"dugoff": dugoff_unit, "mf": mf_unit}


def vectorised(fn, kappa, alpha, vwx_abs, mu, p):
    """Evaluate a per-unit-load tyre function elementwise over broadcast numpy arrays."""
    import numpy as np
    k, a, v, m = np.broadcast_arrays(*(np.asarray(z, dtype=float)
                                        for z in (kappa, alpha, vwx_abs, mu)))
    fx = np.empty(k.shape)
    fy = np.empty(k.shape)
    for idx in np.ndindex(k.shape):
        fx[idx], fy[idx] = fn(float(k[idx]), float(a[idx]), float(v[idx]), float(m[idx]), p)
    return fx, fy
