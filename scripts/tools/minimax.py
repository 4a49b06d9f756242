"""Lawson's iteration for minimax polynomial fits, shared by atan_minimax.py and
sincos_minimax.py (the float32 build's own elementary functions, src/numerics/trig_f32.h)."""

from __future__ import annotations

import numpy as np


def grid(hi: float) -> np.ndarray:
    """Points in (0, hi]: Chebyshev-spaced (dense at the ends) and a uniform grid."""
    x = np.unique(np.concatenate([np.cos(np.linspace(0.0, np.pi, 4001)) * hi / 2.0 + hi / 2.0,
                                  np.linspace(0.0, hi, 2001)]))
    return x[x > 0.0]


def lawson(a: np.ndarray, f: np.ndarray, iters: int) -> np.ndarray:
    """The coefficients c minimising max |a c - f| over the rows: weighted least squares whose
    weights grow where the error is largest, which converges to the minimax (equioscillating)
    solution."""
    w = np.ones(len(f))
    c = np.zeros(a.shape[1])
    for _ in range(iters):
        sw = np.sqrt(w)
        c = np.linalg.lstsq(a * sw[:, None], f * sw, rcond=None)[0]
        e = np.abs(a @ c - f)
        w = w * e
        w /= w.sum()
    return c
