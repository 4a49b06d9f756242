"""Tests of the reference tyre identifier (docs/TYRE_ID.md) and its random stream.

Tolerances are derived where they are stated; none depends on a BLAS kernel (the identifier
uses no matrix product; scipy's expm, in the RK4 test, is compared far above rounding).
"""

import math
import os

import numpy as np
import pytest
from scipy.linalg import expm

from . import tyre_id as T
from .logs import read_csv_log
from .philox import (MASK64, TWO_PI, Stream, block_ref, normals_from_words,
                     uniforms_from_words, words)

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TID_LOGS = os.path.join(ROOT, "scenarios", "tyre_id")

# Random123 tests/kat_vectors (D. E. Shaw Research), the three philox4x64 10-round lines:
# counter c0..c3, key k0 k1, expected output words.
KAT_4X64_10 = [
    ((0, 0, 0, 0), (0, 0),
     (0x16554d9eca36314c, 0xdb20fe9d672d0fdc, 0xd7e772cee186176b, 0x7e68b68aec7ba23b)),
    ((MASK64,) * 4, (MASK64, MASK64),
     (0x87b092c3013fe90b, 0x438c3c67be8d0224, 0x9cc7d7c69cd777b6, 0xa09caebf594f0ba0)),
    ((0x243f6a8885a308d3, 0x13198a2e03707344, 0xa4093822299f31d0, 0x082efa98ec4e6c89),
     (0x452821e638d01377, 0xbe5466cf34e90c6c),
     (0xa528f45403e61d95, 0x38c72dbd566e9788, 0xa5a1610e72fd18b5, 0x57bd43b5e52b7fe6)),
]


def _numpy_block(counter, key):
    """One block of numpy.random.Philox at exactly this counter (it adds 1 before a block)."""
    v = sum(int(c) << (64 * i) for i, c in enumerate(counter)) - 1
    v %= 1 << 256
    start = np.array([(v >> (64 * i)) & MASK64 for i in range(4)], dtype=np.uint64)
    bg = np.random.Philox(counter=start, key=np.array(key, dtype=np.uint64))
    return tuple(int(x) for x in bg.random_raw(4))


# ---- §6 the stream -----------------------------------------------------------------------

@pytest.mark.parametrize("counter,key,expected", KAT_4X64_10)
def test_philox_numpy_matches_random123_kat(counter, key, expected):
    assert _numpy_block(counter, key) == expected


@pytest.mark.parametrize("counter,key,expected", KAT_4X64_10)
def test_philox_plain_integer_rounds_match_random123_kat(counter, key, expected):
    assert tuple(block_ref(counter, key)) == expected


@pytest.mark.parametrize("c1,c2", [(0, 0), (0, 3), (7, 2), (MASK64, 4)])
def test_stream_words_are_the_blocks_of_their_counters(c1, c2):
    # c1 = 0 makes the one-below start borrow through two words: the stream must still
    # begin at block (0, c1, c2, 0)
    w = [int(x) for x in words((12345, 0), c1, c2, 0, 10)]
    ref = [x for j in range(3) for x in block_ref((j, c1, c2, 0), (12345, 0))]
    assert w == ref[:10]


def test_uniform_from_known_words():
    w = np.array([0, MASK64, 1 << 63, (1 << 12) - 1, 1 << 12], dtype=np.uint64)
    u = uniforms_from_words(w)
    # exact: ((w >> 12) + 0.5) * 2^-52
    assert u[0] == 2.0 ** -53 and u[1] == 1.0 - 2.0 ** -53
    assert u[2] == 0.5 + 2.0 ** -53
    assert u[3] == u[0]                       # the low 12 bits are dropped
    assert u[4] == 1.5 * 2.0 ** -52
    assert (u > 0.0).all() and (u < 1.0).all()


def test_normal_from_known_words_is_box_muller():
    w = np.array([1 << 63, 0, MASK64, 1 << 62], dtype=np.uint64)   # u = .5+, tiny, 1-, .25+
    ua, ub = 0.5 + 2.0 ** -53, 2.0 ** -53
    uc, ud = 1.0 - 2.0 ** -53, 0.25 + 2.0 ** -53
    z = normals_from_words(w, T.LIBM)
    # libm backend: the page's formula, bit for bit
    assert z[0] == math.sqrt(-2.0 * math.log(ua)) * math.cos(TWO_PI * ub)
    assert z[1] == math.sqrt(-2.0 * math.log(ua)) * math.sin(TWO_PI * ub)
    assert z[2] == math.sqrt(-2.0 * math.log(uc)) * math.cos(TWO_PI * ud)
    assert z[3] == math.sqrt(-2.0 * math.log(uc)) * math.sin(TWO_PI * ud)
    # by hand: u_a = 1/2 gives rho = sqrt(2 ln 2), u_b -> 0 gives angle 0
    assert z[0] == pytest.approx(math.sqrt(2.0 * math.log(2.0)), rel=1e-15)
    assert abs(z[1]) < 1e-14
    # numpy backend: within a few ulp of libm (its SIMD log/cos/sin may differ in the last bit)
    assert np.allclose(normals_from_words(w, T.NUMPY), z, rtol=1e-14, atol=1e-14)


def test_normals_are_standard():
    z = Stream(7, T.NUMPY).normals(3, 1, 40000)
    # mean sd 1/sqrt(n) = 0.005, variance sd sqrt(2/n) = 0.007: 5 sd bounds
    assert abs(z.mean()) < 0.025 and abs(z.var() - 1.0) < 0.035


# ---- §5 weights and resampling -----------------------------------------------------------

def test_multinomial_on_hand_weights():
    w = np.array([0.1, 0.2, 0.3, 0.4])
    u = np.array([0.05, 0.15, 0.35, 0.95, 0.1, 0.0999])
    # cumulative 0.1, 0.3, 0.6, 1.0: the smallest i with u*S < C_i (u = 0.1 lands on C_0,
    # not below it, so index 1)
    assert T.resample_multinomial(w, u).tolist() == [0, 1, 2, 3, 1, 0]


def test_systematic_on_hand_weights():
    w = np.array([0.1, 0.2, 0.3, 0.4])
    # x_j = (j + 0.5)/4 = 0.125, 0.375, 0.625, 0.875
    assert T.resample_systematic(w, 0.5, 4).tolist() == [1, 2, 3, 3]
    # equal weights: every particle exactly once (no drift on even weights) ...
    for u0 in (2.0 ** -53, 0.5, 0.999):
        assert T.resample_systematic(np.full(8, 0.125), u0, 8).tolist() == list(range(8))
    # ... except where j + u0 rounds up to j + 1 (u0 within an ulp of 1): the position then
    # lands on C_j, and the rule (x < C_i) takes the next particle; a port must do the same
    assert T.resample_systematic(np.full(8, 0.125), 1.0 - 2.0 ** -53, 8).tolist() == \
        [0, 2, 3, 4, 5, 6, 7, 7]


def test_unnormalised_weights_give_the_same_draws():
    # the comparison is u*S < C_i on the unnormalised sums: scaling every weight by a power
    # of two scales S and C exactly
    w = np.array([0.1, 0.2, 0.3, 0.4])
    u = np.linspace(0.01, 0.99, 50)
    assert (T.resample_multinomial(w * 2.0 ** -900, u) == T.resample_multinomial(w, u)).all()


def test_log_weights_do_not_underflow():
    logw = np.array([-1e4, -1e4 - 1.0, -1e4 - 2.0])
    with np.errstate(under="ignore"):
        assert np.exp(logw).sum() == 0.0            # linear weights would all be 0
    w, lw = T.normalise_log(logw)
    e = np.exp([0.0, -1.0, -2.0])
    assert np.allclose(w, e / e.sum(), rtol=1e-15)
    assert np.allclose(np.exp(lw), w, rtol=1e-14)
    assert T.normalise_log(np.full(3, -math.inf)) == (None, None)


def test_reflect_at_the_bounds():
    lo, hi = np.array([1.0]), np.array([2.0])
    x = np.array([[0.75], [2.5], [1.5], [-5.0], [9.0], [1.0], [2.0]])
    y = T.reflect(x, lo, hi)[:, 0].tolist()
    # one reflection at lo, then one at hi (0.75 -> 1.25, 2.5 -> 1.5), then a clip for steps
    # wider than the box (-5 -> 7 -> -3 -> 1; 9 -> -5 -> 1)
    assert y == [1.25, 1.5, 1.5, 1.0, 1.0, 1.0, 2.0]


def test_bounds_hold_after_roughening():
    tid = T.init({"tid_n": 64})
    tid._initialise(0.0)
    tid.k = 5
    # particles on both bounds: the widest spread roughening can see, perturbations of up to
    # K N^(-1/8) * range * |z| leave the box and must be reflected back
    tid.th[:32] = tid.lo
    tid.th[32:] = tid.hi
    w = np.full(64, 1.0 / 64)
    w[0] = 0.5
    w /= np.cumsum(w)[-1]
    cols = np.concatenate([tid.x, tid.th], axis=1)
    new, parents = tid._rough_resample(w, 3.7, cols)
    assert new.shape == (64, 10) and (parents >= 0).all() and (parents < 64).all()
    assert (new[:, 2:] >= tid.lo).all() and (new[:, 2:] <= tid.hi).all()
    assert (new[:3] == cols[np.argsort(-w, kind="stable")[:3]]).all()   # floor(3.7) kept
    assert not (new[3:, 2:] == cols[parents[3:], 2:]).all()            # the rest perturbed


# ---- §4 RK4 ------------------------------------------------------------------------------

def test_rk4_on_the_linear_single_track_matches_the_matrix_exponential():
    # Linear bicycle (cornering stiffnesses Kf, Kr) at vx = 20 m/s: x = (vy, r),
    # x' = A x + b delta
    m, J, Lf, Lr, Kf, Kr, vx = 1830.0, 3234.0, 1.40, 1.65, 145700.0, 123600.0, 20.0
    A = np.array([[-(Kf + Kr) / (m * vx), (Lr * Kr - Lf * Kf) / (m * vx) - vx],
                  [(Lr * Kr - Lf * Kf) / (J * vx), -(Lf * Lf * Kf + Lr * Lr * Kr) / (J * vx)]])
    b = np.array([Kf / m, Lf * Kf / J])
    delta = 0.02

    def f(vy, r):
        return A[0, 0] * vy + A[0, 1] * r + b[0] * delta, A[1, 0] * vy + A[1, 1] * r + b[1] * delta

    x0 = np.array([0.1, -0.05])
    xs = -np.linalg.solve(A, b * delta)          # the steady state
    n_steps = 100

    def err(h, n):
        a, c = np.array([x0[0]]), np.array([x0[1]])
        for _ in range(n):
            a, c = T.rk4(f, a, c, h)
        exact = xs + expm(A * (h * n)) @ (x0 - xs)
        return np.abs(np.array([a[0], c[0]]) - exact).max()

    h = 0.01
    # RK4 is the 4th-order Taylor polynomial of exp(hA): one step errs by at most
    # sum_{k>=5} |hA|^k/k! |x - xs| <= |hA|^5/120 e^|hA| |x0 - xs| (the step contracts)
    nrm = np.linalg.norm(A * h, 2)
    bound = n_steps * nrm ** 5 / 120.0 * math.exp(nrm) * np.linalg.norm(x0 - xs) * math.sqrt(2)
    e1, e2 = err(h, n_steps), err(h / 2.0, 2 * n_steps)     # both to t = 1 s
    assert 0.0 < e1 <= bound
    # fourth order: halving h divides the error by about 2^4 = 16 (10..24: the leading term
    # dominates at |hA| ~ 0.2, scipy's expm and rounding sit ~1e-15 below it)
    assert 10.0 < e1 / e2 < 24.0


# ---- the filter on the logs --------------------------------------------------------------

def _log(name):
    return read_csv_log(os.path.join(TID_LOGS, name + ".csv")).columns


def _sample(c, k):
    return {key: float(c[key][k]) for key in T.SAMPLE_KEYS}


def test_apf_with_the_truth_parameters_tracks_beta():
    c = _log("tid_sine_steer")
    tid = T.init({"tid_n": 32, "tid_q_mu": 0.0, "tid_q_C": 0.0, "tid_q_cy": 0.0, "tid_q_E": 0.0})
    fz = tid.fz0
    # the log's truth (its truth_* metadata): front cy 15, C 1.3, E -1; rear 17, 1.5, 0.3; mu 0.85
    truth = np.array([0.85 * fz[0], 1.3, 15.0 * fz[0], -1.0, 0.85 * fz[1], 1.5, 17.0 * fz[1], 0.3])
    err = []
    for k in range(len(c["t"])):
        e = tid.step(_sample(c, k))
        if k == 0:
            tid.th[:] = truth
        err.append(e.mean["beta"] - c["beta_true"][k])
    rmse = math.degrees(math.sqrt(np.mean(np.square(err[100:]))))
    # measured 0.010 deg (peak beta 1.65 deg): the steering noise (0.001 rad) through the
    # lateral dynamics and the single-track simplification.  0.05 deg is 5x that, and half
    # of what a front stiffness 20 % off gives on this log (0.115 deg)
    assert rmse < 0.05


def test_straight_driving_keeps_the_spread_of_mu():
    c = _log("tid_straight")
    out = T.run(c, {"tid_n": 1024})
    # nothing is identifiable without lateral force: the prior sd is 0.3, and the issue's
    # target is a spread >= 0.2 where the tyre stayed linear.  Measured with 1024 particles,
    # seeds 1-3: smallest 0.26-0.29 (the resamplings, 2 % of the steps, cost some spread);
    # with 64-256 particles it dips to 0.09-0.27 (docs/TYRE_ID_RESULTS.md)
    assert out["sd_mu_f"].min() >= 0.2 and out["sd_mu_r"].min() >= 0.2


def test_same_seed_same_run_other_seed_other_run():
    c = _log("tid_dlc_high_mu")
    a = T.run(c, {"tid_n": 32}, n_steps=150)
    b = T.run(c, {"tid_n": 32}, n_steps=150)
    d = T.run(c, {"tid_n": 32}, seed=2, n_steps=150)
    assert all((a[k] == b[k]).all() for k in a)
    assert not (a["mu_f"] == d["mu_f"]).all()


def test_libm_and_numpy_backends_agree():
    # the same algorithm; the backends' atan2/tan/atan/exp/log differ in the last bit on
    # some CPUs.  Over 60 steps of 16 particles with no resampling decision flipped such
    # differences stay near rounding: 1e-9 relative leaves a factor ~1e6 above it
    c = _log("tid_dlc_high_mu")
    a = T.run(c, {"tid_n": 16}, backend="numpy", n_steps=60)
    b = T.run(c, {"tid_n": 16}, backend="libm", n_steps=60)
    assert (a["status"] == b["status"]).all()
    for k in T.OUTPUT_NAMES:
        assert np.allclose(a[k], b[k], rtol=1e-9, atol=1e-12), k


def test_bad_parameters_are_refused():
    with pytest.raises(ValueError):
        T.init({"tid_filter": "ukf"})
    with pytest.raises(ValueError):
        T.init({"tid_n": 1})
    with pytest.raises(ValueError):
        T.init({"tid_mu0": 2.0})     # prior mean outside [tid_mu_lo, tid_mu_hi]
