"""The textbook-form runs of mass_grade_textbook.py (docs/MASS_GRADE_RESULTS.md "Why the
square-root form"): the hook reproduces the reference, the float32 run is float32 throughout,
and the two failures the page reports happen where it says (about 6 s in all).

Reproducible to the step: the float32 run uses no BLAS (the reference writes every 3x3 sum as
a loop of scalar operations; np.dot, @ or np.linalg would sum in a CPU-dependent order, with
or without FMA), numpy's float32 scalar + - * / and sqrt are IEEE and exactly rounded, and
sin/cos are glibc's double values rounded once to float32. The int32-P run is double
arithmetic in Python floats with exact power-of-two scaling and integer rounding.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import mass_grade_textbook as tb  # noqa: E402
from reference import mass_grade as mg  # noqa: E402

EPS32 = 2.0 ** -24


def test_the_hook_through_numpy_float64_is_the_reference_bit_for_bit():
    # Every operation routed through an Arith of numpy float64 scalars (IEEE double, np.sqrt
    # exactly rounded like math.sqrt) and an identity store_cov: the outputs must equal the
    # reference's plain run exactly, so the hook leaves nothing out and changes nothing.
    f64np = mg.Arith(real=np.float64, sqrt=np.sqrt, sin=lambda x: np.float64(math.sin(x)),
                     cos=lambda x: np.float64(math.cos(x)), store_cov=lambda P: [r[:] for r in P])
    cols, p = tb.job_params(("car_gear_shift", "AUKF + ax", None))
    cols = {k: v[:1200] for k, v in cols.items()}
    ref = mg.run(cols, p, form="textbook")
    est = mg.MassGrade(p, f64np, form="textbook")
    for k, s in enumerate(mg.samples(cols, est.p)):
        o = est.step(s)
        got = [o.mass, o.sd_mass, o.grade, o.sd_grade, o.v, o.sd_v, o.q_mv, o.status]
        want = [ref[c][k] for c in ("mass", "sd_mass", "grade", "sd_grade", "v", "sd_v", "q_mv",
                                    "status")]
        assert got == want, k
    assert type(est.P[1][1]) is np.float64


def test_the_float32_run_never_calls_double_math(monkeypatch):
    # A float32 value through math.sqrt/sin/cos would come back a double and be rounded only
    # at its next use: every such call must go through the Arith instead.
    class Strict:
        isfinite = staticmethod(math.isfinite)

        def __getattr__(self, name):
            raise AssertionError(f"math.{name} on the float32 path")
    monkeypatch.setattr(mg, "math", Strict())
    cols, p = tb.job_params(("car_stop_and_go", "AUKF + ax", None))
    r = tb.run(cols, p, "f32", rows=600)
    assert all(type(v) is np.float32 for v in r["x"])
    assert all(type(v) is np.float32 or v == 0.0 for row in r["P"] for v in row)


def test_float32_textbook_loses_definiteness_on_the_long_tight_cruise():
    # The cruise of car_flat_cruise played 4 times with the tight process noise: the f64 filter
    # stays clear of singularity (margin min_j L_jj^2/P_jj >= 100 float32 ulps on every step),
    # the float32 one's update leaves a P that is not positive definite at step 10774, and
    # from the next step its Cholesky of the sigma points fails (status 21, the state kept).
    cols, p = tb.job_params((None, "UKF + ax", "car_flat_cruise's cruise x4, tight Q"))
    rows = 10800
    ref = tb.run(cols, p, "f64", rows)
    f32 = tb.run(cols, p, "f32", rows)
    assert not np.any(ref["status"] == mg.ERR_NOT_POSITIVE_DEFINITE)
    assert np.nanmin(ref["margin"][1:]) >= 100 * EPS32
    npd = np.flatnonzero(~(f32["margin"][1:] > 0.0)) + 1
    assert len(npd) > 0 and npd[0] == 10774
    fails = np.flatnonzero(f32["status"] == mg.ERR_NOT_POSITIVE_DEFINITE)
    assert np.array_equal(fails, np.arange(10775, rows))
    # up to the step before, the two agree within a few sd: the failure is not a divergence
    k = npd[0] - 1
    assert abs(f32["mass"][k] - ref["mass"][k]) <= 5.0 * ref["sd_mass"][k]


def test_int32_covariance_fails_early_where_float32_holds():
    # car_flat_cruise with the tight process noise, speed only: P_MM falls to ~0.1 kg^2, a few
    # dozen LSB of the Q8 an int32 P_MM needs for the truck's 4e6 kg^2; the rounded P stops
    # being positive definite at step 1815 and the filter freezes (status 21), while the
    # float32 and f64 filters, with margins >= 5e-4, go on.
    cols, p = tb.job_params((None, "UKF", "car_flat_cruise, tight Q"))
    rows = 1900
    ref = tb.run(cols, p, "f64", rows)
    q = tb.run(cols, p, "q31P", rows)
    f32 = tb.run(cols, p, "f32", rows)
    s = tb.summary(ref, q)
    assert s["first_npd"] == 1815 and s["n_21"] > 0
    assert q["sat"] == 0
    assert tb.summary(ref, f32)["first_npd"] is None
    assert np.nanmin(ref["margin"][1:]) >= 5e-4


def test_q31_store_rounds_and_saturates():
    st = tb.Q31Store()
    P = [[2e-3, 1e-3, 0.0], [1e-3, 1e7, -3.0], [0.0, -3.0, 1e-3]]
    out = st(P)
    assert out[1][1] == (2 ** 31 - 1) / 2 ** 8 and st.sat == 1     # 1e7 kg^2 > Q8's range
    assert out[0][0] == round(2e-3 * 2 ** 38) / 2 ** 38
    assert out[1][2] == out[2][1] == -3.0                           # exact in Q23
    assert out[0][1] == round(1e-3 * 2 ** 23) / 2 ** 23
