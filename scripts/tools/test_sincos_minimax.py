"""The float32 build's sine and cosine coefficients (src/numerics/trig_f32.h, rfe_sin_poly_f32,
rfe_cos_poly_f32) are the fits of scripts/tools/sincos_minimax.py, and the fits are the minimax
ones they claim to be."""

from __future__ import annotations

import os
import re
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import sincos_minimax  # noqa: E402

ROOT = os.path.join(os.path.dirname(__file__), "..", "..")


def library_coefficients(name: str) -> list[float]:
    """The coefficients c_0 .. c_n of z^k of the Horner scheme in the function `name`, read
    from its literals with the sign each is written with (the innermost, a factor, first)."""
    with open(os.path.join(ROOT, "src", "numerics", "trig_f32.h"), encoding="utf-8") as f:
        text = f.read()
    start = text.index(f"static inline float {name}(float r)")
    body = text[start:text.index("return", start)]
    first = re.search(r"\((-?\d+\.\d+(?:e-?\d+)?)f \* z\)", body)
    assert first is not None, body
    rest = re.findall(r"([+-]) (\d+\.\d+(?:e-?\d+)?)f;", body)
    coeffs = [float(first.group(1))] + [(-1.0 if s == "-" else 1.0) * float(v) for s, v in rest]
    return coeffs[::-1]


@pytest.mark.parametrize("kind, name", [("sin", "rfe_sin_poly_f32"), ("cos", "rfe_cos_poly_f32")])
def test_the_library_uses_the_fitted_coefficients(kind, name):
    c, _ = sincos_minimax.fit(kind)
    lib = library_coefficients(name)
    assert len(lib) == len(c)
    # As test_atan_minimax.py: the least-squares solve's last bits depend on the BLAS kernel;
    # rounded to float32 (2^-24 relative) a coefficient may land one float ulp apart: 2^-22.
    for k, (got, want) in enumerate(zip(lib, c)):
        assert abs(got - want) <= 2.0 ** -22 * abs(want), (kind, k, got, want)


@pytest.mark.parametrize("kind, stated, terms", [("sin", 3.8e-9, sincos_minimax.SIN_TERMS),
                                                 ("cos", 6.4e-11, sincos_minimax.COS_TERMS)])
def test_the_fit_equioscillates_below_its_stated_error(kind, stated, terms):
    c, err = sincos_minimax.fit(kind)
    # trig_f32.h states these relative errors in exact arithmetic.
    assert err <= stated
    r = np.linspace(1e-6, np.pi / 4.0, 200001)
    z = r * r
    poly = np.polyval(c[::-1], z)
    if kind == "sin":
        rel = (r + r * z * poly) / np.sin(r) - 1.0
    else:
        rel = (1.0 + z * poly) / np.cos(r) - 1.0
    assert np.max(np.abs(rel)) <= stated * 1.01  # the grid's maximum is the fit's, to rounding
    # A minimax error alternates in sign at terms + 1 extrema of (almost) equal size.
    big = rel[np.abs(rel) >= 0.9 * np.max(np.abs(rel))]
    changes = int(np.sum(np.diff(np.sign(big)) != 0))
    assert changes >= terms


def test_an_unknown_kind_is_refused():
    with pytest.raises(ValueError):
        sincos_minimax.fit("tan")
