#!/usr/bin/env python3
"""The coefficients of the float32 build's sine and cosine (src/numerics/trig_f32.h,
rfe_sin_f32, rfe_cos_f32, rfe_tan_f32).

    python3 scripts/tools/sincos_minimax.py

After the reduction to r in [-pi/4, pi/4], z = r^2:
- sin r = r + r z S(z), S of degree 2 (SIN_TERMS = 3 coefficients), fitted for the least maximum
  *relative* error of sin r (a small slip angle keeps its relative precision);
- cos r = 1 + z C(z), C of degree 3 (COS_TERMS = 4), fitted for the least maximum relative error
  of cos r (>= cos(pi/4) there, so that is also the absolute error within a factor 1.42).
Both by Lawson's iteration, as scripts/tools/atan_minimax.py: weighted least squares whose
weights grow where the error is largest, which converges to the minimax (equioscillating)
solution. Prints the coefficients rounded to float32 as C literals and each fit's error in exact
arithmetic; test_sincos_minimax.py checks that the library's constants are these. One term fewer
would leave 1.8e-6 (sine) and 3.8e-8 (cosine) in exact arithmetic, too much for float32's 6e-8.
"""

from __future__ import annotations

import functools

import numpy as np

import minimax

SIN_TERMS = 3
COS_TERMS = 4
QUARTER_PI = np.pi / 4.0


@functools.lru_cache(maxsize=None)
def fit(kind: str, iters: int = 300) -> tuple[np.ndarray, float]:
    """(coefficients c_k of z^k, max relative error of the polynomial against sin or cos)."""
    r = minimax.grid(QUARTER_PI)
    z = r * r
    if kind == "sin":
        terms = SIN_TERMS
        # sin r = r (1 + z S): the relative error is z dS / (sin r / r)
        f = (np.sin(r) / r - 1.0) / z
        wt = z / (np.sin(r) / r)
    elif kind == "cos":
        terms = COS_TERMS
        # cos r = 1 + z C: the relative error is z dC / cos r
        f = (np.cos(r) - 1.0) / z
        wt = z / np.cos(r)
    else:
        raise ValueError(f"kind must be 'sin' or 'cos', not {kind!r}")
    a = np.stack([z ** k for k in range(terms)], axis=1)
    c = minimax.lawson(a * wt[:, None], f * wt, iters)
    return c, float(np.max(np.abs((a @ c - f) * wt)))


def main() -> None:
    for kind in ("sin", "cos"):
        c, err = fit(kind)
        lits = ", ".join(f"{float(np.float32(x))!r}f" for x in c)
        print(f"/* {kind}: relative error of the fit in exact arithmetic: {err:.3e} */")
        print(f"{{{lits}}}")


if __name__ == "__main__":
    main()
