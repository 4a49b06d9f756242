"""MODEL.md sections 3-5 in float64: kinematics, slips, loads, Dugoff tyre, observation.

Every function is vectorised: per-sample inputs are arrays of any shape ``(...)`` and
per-wheel results have a trailing wheel axis of length 4 in the order fl, fr, rl, rr
(MODEL.md section 1).  ``p`` is a parameter dict as produced by ``params.resolve``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

WHEELS = ("fl", "fr", "rl", "rr")


def wheel_positions(p):
    """Wheel centres relative to the CoG (MODEL.md section 1): x_i, y_i, each shape (4,)."""
    x = np.array([p["Lf"], p["Lf"], -p["Lr"], -p["Lr"]])
    y = np.array([p["Bf"] / 2, -p["Bf"] / 2, p["Br"] / 2, -p["Br"] / 2])
    return x, y


def wheel_steer(delta):
    """Per-wheel steer angle delta_i: delta on the front wheels, 0 on the rear, shape (..., 4)."""
    delta = np.asarray(delta, dtype=float)[..., None]
    zero = np.zeros_like(delta)
    return np.concatenate([delta, delta, zero, zero], axis=-1)


# ---------------------------------------------------------------------------------------------
# MODEL.md section 3: kinematics, slips, loads
# ---------------------------------------------------------------------------------------------

def wheel_velocities(p, delta, vx, vy, yaw_rate):
    """Wheel-centre velocity in wheel axes (MODEL.md section 3).

    v_i = (vx - r y_i, vy + r x_i) in body axes, then rotated by delta_i:
      v_wx = v_x,i cos d_i + v_y,i sin d_i ,   v_wy = -v_x,i sin d_i + v_y,i cos d_i
    Returns v_wx, v_wy, delta_i, each shape (..., 4).
    """
    xw, yw = wheel_positions(p)
    vx = np.asarray(vx, dtype=float)[..., None]
    vy = np.asarray(vy, dtype=float)[..., None]
    r = np.asarray(yaw_rate, dtype=float)[..., None]
    vbx = vx - r * yw
    vby = vy + r * xw
    d = wheel_steer(delta)
    c, s = np.cos(d), np.sin(d)
    v_wx = vbx * c + vby * s
    v_wy = -vbx * s + vby * c
    return v_wx, v_wy, d


def slip_angles(p, v_wx, v_wy):
    """alpha_i = -atan2(v_wy, |v_wx|), then bounded to |alpha| <= alpha_max (MODEL.md 3, 4)."""
    alpha = -np.arctan2(v_wy, np.abs(v_wx))
    return np.clip(alpha, -p["alpha_max"], p["alpha_max"])


def longitudinal_slips(p, omega, v_wx):
    """kappa_i = (w_i R - v_wx) / max(|w_i R|, |v_wx|, v_min), clipped to [-1, 1] (MODEL.md 3, 4)."""
    wr = np.asarray(omega, dtype=float) * p["R"]
    den = np.maximum(np.maximum(np.abs(wr), np.abs(v_wx)), p["v_min"])
    return np.clip((wr - v_wx) / den, -1.0, 1.0)


def vertical_loads(p, ax, ay):
    """Quasi-static vertical loads Fz_i (MODEL.md section 3), clamped at >= 0, shape (..., 4)."""
    m, g, hg = p["m"], p["g"], p["hg"]
    lf, lr = p["Lf"], p["Lr"]
    la = lf + lr
    ax = np.asarray(ax, dtype=float)
    ay = np.asarray(ay, dtype=float)
    front_static = m * g * lr / (2 * la)
    rear_static = m * g * lf / (2 * la)
    long_transfer = m * ax * hg / (2 * la)
    lat_front = m * ay * hg * lr / (la * p["Bf"])
    lat_rear = m * ay * hg * lf / (la * p["Br"])
    fz = np.stack([
        front_static - long_transfer - lat_front,   # fl
        front_static - long_transfer + lat_front,   # fr
        rear_static + long_transfer - lat_rear,     # rl
        rear_static + long_transfer + lat_rear,     # rr
    ], axis=-1)
    return np.maximum(fz, 0.0)


# ---------------------------------------------------------------------------------------------
# MODEL.md section 4: Dugoff tyre (paper / normalised mode and absolute / load-scaled mode)
# ---------------------------------------------------------------------------------------------

def velocity_reduction(p, kappa, tan_alpha, v_wx):
    """E = max(0, 1 - eps |v_wx| sqrt(kappa^2 + tan^2 alpha)) (MODEL.md section 4, guards)."""
    e = 1.0 - p["eps"] * np.abs(v_wx) * np.sqrt(kappa * kappa + tan_alpha * tan_alpha)
    return np.maximum(e, 0.0)


def _dugoff_factor(scale, kappa, e, s):
    """g = f(L) / (1 - |kappa|) without dividing two small numbers (MODEL.md section 4 notes).

    L = scale (1 - |kappa|) E / (2 S), f(L) = L (2 - L) if L < 1 else 1, so
      L < 1 :  g = scale E (2 - L) / (2 S)        (finite also at |kappa| = 1)
      L >= 1:  g = 1 / (1 - |kappa|)              (here |kappa| < 1 necessarily)
    S = 0 (kappa = tan alpha = 0) means f = 1, i.e. g = 1/(1-|kappa|) = 1 and zero force.
    ``scale`` is 1 in paper mode and mu in absolute mode.
    """
    one_minus = 1.0 - np.abs(kappa)
    s_pos = s > 0.0
    s_safe = np.where(s_pos, s, 1.0)
    lam = scale * one_minus * e / (2.0 * s_safe)
    below = s_pos & (lam < 1.0)
    g_below = scale * e * (2.0 - lam) / (2.0 * s_safe)
    g_sat = 1.0 / np.where(below, 1.0, one_minus)
    return np.where(below, g_below, g_sat)


def dugoff_normalised(p, fz, kappa, alpha, v_wx):
    """Paper mode: forces per unit mu, F0x, F0y in wheel axes (MODEL.md section 4).

    S = sqrt((Cx_n kappa)^2 + (Cy_n tan alpha)^2), L = (1-|kappa|) E / (2 S),
    F0x = Fz Cx_n kappa/(1-|kappa|) f(L),  F0y = Fz Cy_n tan alpha/(1-|kappa|) f(L).
    """
    ta = np.tan(alpha)
    cxk = p["Cx_n"] * kappa
    cyt = p["Cy_n"] * ta
    s = np.sqrt(cxk * cxk + cyt * cyt)
    e = velocity_reduction(p, kappa, ta, v_wx)
    g = _dugoff_factor(1.0, kappa, e, s)
    return fz * cxk * g, fz * cyt * g


def dugoff_absolute(p, mu, fz, kappa, alpha, v_wx):
    """Absolute (load-scaled) mode: forces Fx, Fy in wheel axes at friction mu (MODEL.md 4).

    Cx = cx Fz, Cy = cy Fz, L = mu (1-|kappa|) E / (2 sqrt(cx^2 kappa^2 + cy^2 tan^2 alpha)),
    Fx = Cx kappa/(1-|kappa|) f(L), Fy = Cy tan alpha/(1-|kappa|) f(L).  mu < 0 is evaluated
    at mu = 0 (zero force).  All arguments broadcast against each other.
    """
    mu = np.maximum(np.asarray(mu, dtype=float), 0.0)
    ta = np.tan(alpha)
    cxk = p["cx"] * kappa
    cyt = p["cy"] * ta
    s = np.sqrt(cxk * cxk + cyt * cyt)
    e = velocity_reduction(p, kappa, ta, v_wx)
    g = _dugoff_factor(mu, kappa, e, s)
    return fz * cxk * g, fz * cyt * g


def magic_absolute(p, mu, fz, kappa, alpha, v_wx):
    """Load-scaled Magic Formula (docs/ESTIMATOR.md "The Magic Formula tyre"): forces Fx, Fy
    in wheel axes at friction mu. s = |(cx k, cy tan a)|, u = (cx k, cy tan a) / s, m = max(mu, 0),
    per direction a = atan2(s, m C), phi = C atan2(s - E (s - m C a), m C), F = Fz m sin(phi) u.
    v_wx is unused (no velocity reduction); all arguments broadcast against each other."""
    del v_wx
    m = np.maximum(np.asarray(mu, dtype=float), 0.0)
    k = np.clip(kappa, -1.0, 1.0)
    ta = np.tan(np.clip(alpha, -p["alpha_max"], p["alpha_max"]))
    cxk = p["cx"] * k
    cyt = p["cy"] * ta
    s = np.sqrt(cxk * cxk + cyt * cyt)
    s_safe = np.where(s > 0.0, s, 1.0)
    ux = np.where(s > 0.0, cxk / s_safe, 0.0)
    uy = np.where(s > 0.0, cyt / s_safe, 0.0)

    def shape(c, e):
        mc = m * c
        a = np.arctan2(s, mc)
        return np.sin(c * np.arctan2(s - e * (s - mc * a), mc))

    gx = shape(p["shape_Cx"], p["shape_Ex"])
    gy = shape(p["shape_Cy"], p["shape_Ey"])
    return fz * m * gx * ux, fz * m * gy * uy


def tyre_absolute(p, mu, fz, kappa, alpha, v_wx):
    """The load-scaled tyre of p["tyre"]: "magic" or (otherwise) the absolute Dugoff."""
    fn = magic_absolute if p.get("tyre") == "magic" else dugoff_absolute
    return fn(p, mu, fz, kappa, alpha, v_wx)


# ---------------------------------------------------------------------------------------------
# MODEL.md section 5: observation
# ---------------------------------------------------------------------------------------------

def body_effects(p, fx, fy, delta_i):
    """Wheel forces (wheel axes) -> [Fbx/m, Fby/m, (x_i Fby - y_i Fbx)/J] (MODEL.md section 5).

    fx, fy, delta_i shape (..., 4); returns shape (..., 3, 4) (rows ax, ay, yaw_acc; columns
    wheels).  With the normalised forces this is H(u); with absolute forces, summing the
    columns gives h(x, u).
    """
    xw, yw = wheel_positions(p)
    c, s = np.cos(delta_i), np.sin(delta_i)
    fbx = fx * c - fy * s
    fby = fx * s + fy * c
    return np.stack([fbx / p["m"], fby / p["m"], (xw * fby - yw * fbx) / p["J"]], axis=-2)


@dataclass
class TyreInputs:
    """Everything of u the tyre needs, per sample and wheel (arrays shape (N, 4))."""
    delta_i: np.ndarray
    v_wx: np.ndarray
    kappa: np.ndarray
    alpha: np.ndarray
    fz: np.ndarray


def tyre_inputs(p, delta, vx, vy, yaw_rate, ax, ay, omega) -> TyreInputs:
    """MODEL.md section 3 for whole logs: omega shape (N, 4), the others shape (N,)."""
    v_wx, v_wy, d = wheel_velocities(p, delta, vx, vy, yaw_rate)
    return TyreInputs(
        delta_i=d,
        v_wx=v_wx,
        kappa=longitudinal_slips(p, omega, v_wx),
        alpha=slip_angles(p, v_wx, v_wy),
        fz=vertical_loads(p, ax, ay),
    )


def observation_matrix(p, ti: TyreInputs):
    """H(u), shape (N, 3, 4): paper mode, y = H(u) x (MODEL.md section 5)."""
    f0x, f0y = dugoff_normalised(p, ti.fz, ti.kappa, ti.alpha, ti.v_wx)
    return body_effects(p, f0x, f0y, ti.delta_i)


def h_absolute(p, ti: TyreInputs, k: int, mu_points):
    """Absolute-mode measurement of sample k at friction points (MODEL.md sections 4-5).

    mu_points: shape (4, P), one column per cubature point.  Returns shape (3, P):
    [sum body-x force / m, sum body-y force / m, yaw moment / J] at each point.
    """
    col = lambda a: a[k][:, None]  # noqa: E731  per-wheel values of sample k as (4, 1)
    fx, fy = tyre_absolute(p, mu_points, col(ti.fz), col(ti.kappa), col(ti.alpha), col(ti.v_wx))
    # body_effects wants the wheel axis last: work on (P, 4) and sum over wheels.
    eff = body_effects(p, fx.T, fy.T, ti.delta_i[k])       # (P, 3, 4)
    return eff.sum(axis=-1).T                                # (3, P)
