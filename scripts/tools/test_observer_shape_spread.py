"""observer_shape_spread.py: its family members against the project's tyre functions, and its
envelope and fit on constructed curves (no C build)."""

from __future__ import annotations

import numpy as np

import observer_shape_spread as study
from reference import model


def test_the_dugoff_member_is_the_normalised_curve_at_the_models_stiffness():
    # MODEL.md §4: mu F0 with Cy_n = cy / mu is the absolute Dugoff at cy; equal to rounding
    # (a few ulps of forces of order 1: 1e-12 relative)
    p = study.model_params()
    for mu in study.MUS:
        al = np.linspace(1e-3, 0.3, 50)
        z = np.zeros_like(al)
        q = dict(p, Cy_n=p["cy"] / mu)
        _, f0 = model.dugoff_normalised(q, np.ones_like(al), z, al, np.full_like(al, study.V_WHEEL))
        f = study.fy(p, mu, al, "dugoff")
        assert np.allclose(f, mu * f0, rtol=1e-12, atol=0.0)


def test_the_models_slip_gives_the_asked_utilisation():
    # bisection to 200 halvings: the force at the slip found is u mu to 1e-9
    p = study.model_params()
    for mu in study.MUS:
        for u in (0.1, 0.5, study.U_MAX):
            a = study.model_alpha(p, mu, u)
            assert abs(study.fy(p, mu, np.array([a]), "magic")[0] - u * mu) <= 1e-9


def test_matched_stiffness_leaves_no_error_at_zero_utilisation_and_the_file_one_does():
    # at u 0.001 the shapes agree to O(u^2); the file's cy x 0.7 is -30 % there
    p = study.model_params()
    d = study.errors(p, [1e-3], "matched")
    assert max(abs(v[0]) for v in d.values()) < 1e-4
    d = study.errors(p, [1e-3], "file")
    assert abs(d[("mf_tol", 0.35)][0] + 0.3) < 1e-3


def test_envelope_and_fit():
    s = np.array([0.0, 0.2, 0.1, 0.3, 0.25])
    assert list(study.envelope(s)) == [0.0, 0.2, 0.2, 0.3, 0.3]
    # a knee built from known parameters is found again (u_k on the tool's 0.01 grid)
    u = np.linspace(0.02, study.U_MAX, 45)
    s_max, u_k = study.fit(u, study.knee(u, 0.07, 0.49))
    assert abs(u_k - 0.49) < 1e-9 and abs(s_max - 0.07) < 1e-12
