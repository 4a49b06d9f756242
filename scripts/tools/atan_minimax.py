#!/usr/bin/env python3
"""The coefficients of the float32 build's atan (src/numerics/trig_f32.h, rfe_atan2_f32).

    python3 scripts/tools/atan_minimax.py

atan(t) = t P(t^2) on t in [0, 1], P of degree 8 in t^2 (9 coefficients), fitted for the least
maximum *relative* error of atan (so small slip angles keep their relative precision) by
Lawson's iteration: weighted least squares whose weights grow where the error is largest, which
converges to the minimax (equioscillating) solution. Prints the coefficients rounded to float32
as C literals and the fit's error in exact arithmetic; test_atan_minimax.py checks that the
library's constants are these.
"""

from __future__ import annotations

import functools

import numpy as np

import minimax

TERMS = 9


@functools.lru_cache(maxsize=None)
def fit(terms: int = TERMS, iters: int = 300) -> tuple[np.ndarray, float]:
    """(coefficients c_k of t^(2k), max relative error of t P(t^2) against atan t)."""
    t = minimax.grid(1.0)
    a = np.stack([t ** (2 * k) for k in range(terms)], axis=1)
    f = np.arctan(t) / t
    c = minimax.lawson(a, f, iters)
    return c, float(np.max(np.abs(a @ c - f)))


def main() -> None:
    c, err = fit()
    lits = ", ".join(f"{float(np.float32(x))!r}f" for x in c)
    print(f"/* relative error of the fit in exact arithmetic: {err:.3e} */")
    print(f"{{{lits}}}")


if __name__ == "__main__":
    main()
