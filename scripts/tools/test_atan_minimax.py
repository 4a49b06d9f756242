"""The float32 build's atan coefficients (src/numerics/trig_f32.h, rfe_atan2_f32) are the fit of
scripts/tools/atan_minimax.py, and the fit is the minimax one it claims to be."""

from __future__ import annotations

import os
import re
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import atan_minimax  # noqa: E402

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")


def library_coefficients() -> list[float]:
    """c_0 .. c_8 of rfe_atan2_f32's Horner scheme: c_0 = 1 is implicit (t P = t + t^3 P'),
    the others are its float literals from the innermost (c_8) out, the constants pi/2, pi and
    0 excepted."""
    with open(os.path.join(ROOT, "src", "numerics", "trig_f32.h"), encoding="utf-8") as f:
        text = f.read()
    start = text.index("static inline float rfe_atan2_f32(float y, float x)")
    body = text[start:text.index("return (y < 0.0f)", start)]
    lits = [float(v[:-1]) for v in re.findall(r"\b\d+\.\d+f\b", body)]
    lits = [v for v in lits if v not in (0.0, 1.57079637, 3.14159274)]
    assert len(lits) == atan_minimax.TERMS - 1, lits
    signs = re.findall(r"([+-]) (\d+\.\d+f)\b", body)  # the sign each literal is added with
    sign = {float(v[:-1]): (-1.0 if s == "-" else 1.0) for s, v in signs}
    first = lits[0]  # c_8, the product's factor: its own sign
    coeffs = [first] + [sign[v] * v for v in lits[1:]]
    return [1.0] + coeffs[::-1]


@pytest.fixture(scope="module")
def fitted():
    """The fit, once for both tests (it is deterministic; ~3 s each time)."""
    return atan_minimax.fit()


def test_the_library_uses_the_fitted_coefficients(fitted):
    c, _ = fitted
    lib = library_coefficients()
    assert len(lib) == atan_minimax.TERMS
    # The fit runs a least-squares solve whose last bits depend on the BLAS kernel; rounded to
    # float32 (2^-24 relative) a coefficient may land one float ulp apart, never more: 2^-22.
    for k, (got, want) in enumerate(zip(lib, c)):
        assert abs(got - want) <= 2.0 ** -22 * max(abs(want), 1e-3), (k, got, want)


def test_the_fit_equioscillates_below_its_stated_error(fitted):
    c, err = fitted
    # trig_f32.h states 1.4e-8 relative in exact arithmetic for the 9-term fit.
    assert err <= 1.4e-8
    t = np.linspace(1e-6, 1.0, 200001)
    rel = np.polyval(c[::-1], t * t) - np.arctan(t) / t
    # A minimax error alternates in sign at TERMS + 1 extrema of (almost) equal size: count the
    # sign changes between points where |error| is within 10 % of its maximum.
    big = rel[np.abs(rel) >= 0.9 * np.max(np.abs(rel))]
    changes = int(np.sum(np.diff(np.sign(big)) != 0))
    assert changes >= atan_minimax.TERMS
