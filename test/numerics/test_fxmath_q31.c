/**
 * @file test_fxmath_q31.c
 * @brief The fixed-point primitives (rfe/fixed.h), the host conversions (host/fixed_conv.h)
 *        and the integer math (rfe/component/fxmath.h) against exact integer references and libm.
 *
 * Tolerances: each is the worst-case error the algorithm guarantees (fxmath.h), plus the
 * error of the double reference where it matters:
 *  - exact integer results (saturating helpers, shifts, products, isqrt64, sqrt, norm, div)
 *    are compared bit for bit with integer references (exact rounding: error <= 0.5 LSB);
 *  - atan2, Q29: 0.5 LSB (1/2^30 rad) for the final rounding + atan(2^-39) = 1.82e-12 rad
 *    CORDIC residual + < 1e-15 rad int64 truncation in 40 steps at |(x, y)| >= 2^59 +
 *    ~4e-16 rad for libm atan2: TOL_ATAN2 = 9.4e-10 rad;
 *  - sin, cos, Q30: 0.5 LSB (1/2^31) + 1.82e-12 (the residual angle moves the result by at
 *    most that) + < 1e-15: TOL_SINCOS = 4.7e-10;
 *  - tan, Q26: 0.5 LSB (1/2^27) + 1.82e-12 * (1 + tan^2) (<= 3.7e-10 at |angle| = 1.5,
 *    tan^2 = 199) + < 1e-14: TOL_TAN = 7.9e-9.
 * The Magic Formula's shorter routines (src/numerics/fxmath_internal_q31.h, derived in fxmath_q31.c):
 *  - rfe_q31_atan2_quad1, Q31: 2^-32 final rounding + 3.49 2^-32 (rounding of x in the 11
 *    CORDIC steps) + 2^-33 (division remainder) + 2^-34.6 (atan q ~ q) + 2^-36.8 (table)
 *    < 5.2 2^-32, + ~2e-16 rad for libm atan2: TOL_ATAN2_Q1 = 5.2 2^-32 + 1e-15 = 1.211e-9 rad;
 *  - rfe_q31_sin_q55, Q30: 2^-31 final rounding + 2^-33 (table) + < 2^-35 (polynomial,
 *    arithmetic) = 6.15e-10, + ~1e-16 for libm sin (and the rounding of the Q55 angle to a
 *    double, < 2^-51 rad): TOL_SIN_Q55 = 6.15e-10 + 1e-15.
 * The estimators' angle functions built on those two (fxmath_internal_q31.h):
 *  - rfe_q31_atan2_q29, Q29: 1.211e-9 (rfe_q31_atan2_quad1) + 2^-30 (rounding to Q29) + 1.3e-10
 *    (pi in Q31), + 1.317e-9 when an input exceeds 2^30 (the common scaling to 30 bits turns
 *    the vector by <= (sqrt 2 / 2) 2^-29), + ~1e-15 for libm atan2 and the int64 -> double
 *    conversion (relative 2^-53): TOL_ATAN2_Q29_SMALL = 2.27e-9, TOL_ATAN2_Q29 = 3.59e-9;
 *  - rfe_q31_sincos_q29, Q30: rfe_q31_sin_q55's 6.15e-10 + 2^-56 (pi, pi/2 in Q55) + 1e-15:
 *    TOL_SINCOS_Q29 = 6.16e-10;
 *  - rfe_q31_tan_q29, Q26: 2^-27 (rounding) + eps (1 + |tan a|) / (cos a - eps) with
 *    eps = 6.16e-10 (the quotient of a sine and a cosine each off by eps), + 1e-14 (libm):
 *    tol_tan_q29(a), a bound per angle.
 * The measured worst cases are printed (docs/FIXED_POINT.md quotes them).
 */
#include "test_common.h"

#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "rfe/fixed.h"
#include "host/fixed_conv.h"
#include "rfe/component/fxmath.h"
#include "numerics/fxmath_internal_q31.h"
#include "test_light.h"
#include "test_rng.h"

/* Light mode (valgrind): every 10th value of the long sweeps and random loops. */
#define LIGHT_STEP ((int)rfe_test_stride(10u))

#define TOL_ATAN2 9.4e-10
#define TOL_SINCOS 4.7e-10
#define TOL_TAN 7.9e-9
#define TOL_ATAN2_Q1 (5.2 / 4294967296.0 + 1e-15)
#define TOL_SIN_Q55 (6.15e-10 + 1e-15)
#define TOL_ATAN2_Q29_SMALL 2.27e-9
#define TOL_ATAN2_Q29 3.59e-9
#define TOL_SINCOS_Q29 6.16e-10

#define TEST_PI 3.14159265358979323846

#define LSB29 (1.0 / 536870912.0)
#define LSB30 (1.0 / 1073741824.0)
#define LSB26 (1.0 / 67108864.0)

/* Sentinel an output must keep after an error. */
#define UNTOUCHED32 ((int32_t)0x5A5A5A5A)
#define UNTOUCHED_SAT 77u

/* ---- deterministic integers from the shared fixed-seed generator -------------------------- */

/* Uniform-ish over all of int32 (53 random bits scaled to [-2^31, 2^31)). */
static int32_t rand_i32(void) { return (int32_t)floor(ldexp(rng_uniform(), 31)); }

static uint64_t rand_u64(void)
{
    const uint64_t hi = (uint64_t)(uint32_t)rand_i32();
    const uint64_t lo = (uint64_t)(uint32_t)rand_i32();
    return (hi << 32) | lo;
}

/* Random integer in [0, k). */
static unsigned rand_below(unsigned k) { return (unsigned)(rand_u64() % k); }

/* Random int32 with a random bit length (log-uniform magnitude) and sign: exercises small
 * and large values alike. */
static int32_t rand_i32_log(void)
{
    const unsigned bits = rand_below(33u); /* 0 .. 32 */
    int64_t m = (bits == 0u) ? 0 : (int64_t)(rand_u64() >> (64u - bits));
    if (rand_u64() & 1u) {
        m = -m;
    }
    if (m > INT32_MAX) {
        m = INT32_MAX;
    }
    if (m < INT32_MIN) {
        m = INT32_MIN;
    }
    return (int32_t)m;
}

/* ---- independent integer references --------------------------------------------------- */

/* floor(a / 2^s) without shifting a negative value. */
static int64_t ref_floor_shift(int64_t a, unsigned s)
{
    if (s >= 64u) {
        return (a < 0) ? -1 : 0;
    }
    if (s == 63u) {
        return (a < 0) ? -1 : 0;
    }
    if (a >= 0) {
        return a / ((int64_t)1 << s);
    }
    /* floor(a / 2^s) = -ceil(-a / 2^s) = -((-a - 1) / 2^s) - 1, with -a - 1 = -(a + 1). */
    return -((-(a + 1)) / ((int64_t)1 << s)) - 1;
}

/* floor(a / 2^s + 1/2) from the floor and the remainder a - floor * 2^s. */
static int64_t ref_round_shift(int64_t a, unsigned s)
{
    int64_t f;
    int64_t rem;
    if (s == 0u) {
        return a;
    }
    if (s >= 64u) {
        return 0;
    }
    f = ref_floor_shift(a, s);
    if (s == 63u) {
        /* a in [-2^63, 2^63): a / 2^63 in [-1, 1); rounds to -1 below -1/2, to 1 at or
         * above 1/2, else 0. */
        if (a < -((int64_t)1 << 62)) {
            return -1;
        }
        return (a >= ((int64_t)1 << 62)) ? 1 : 0;
    }
    rem = a - f * ((int64_t)1 << s); /* in [0, 2^s) */
    return f + ((rem >= ((int64_t)1 << (s - 1u))) ? 1 : 0);
}

/* Symmetric int32 saturation, with the expected count. */
static int32_t ref_sat(int64_t v, uint32_t *count)
{
    if (v > INT32_MAX) {
        ++*count;
        return INT32_MAX;
    }
    if (v < -INT32_MAX) {
        ++*count;
        return -INT32_MAX;
    }
    return (int32_t)v;
}

/* The int64 with the two's-complement pattern u (no implementation-defined conversion). */
static int64_t u2s(uint64_t u)
{
    return (u <= (uint64_t)INT64_MAX) ? (int64_t)u : -(int64_t)(UINT64_MAX - u) - 1;
}

static uint64_t umag(int32_t v) { return (v < 0) ? (uint64_t)(-(int64_t)v) : (uint64_t)v; }

/* ---- saturating helpers and shifts ---------------------------------------------------- */

/* REQ-FXP-001 REQ-FXP-008 */
static void test_sat32_and_counter(void **state)
{
    uint32_t sat = 0u;
    (void)state;
    assert_int_equal(rfe_fix_sat32(0, &sat), 0);
    assert_int_equal(rfe_fix_sat32(INT32_MAX, &sat), INT32_MAX);
    assert_int_equal(rfe_fix_sat32(-INT32_MAX, &sat), -INT32_MAX);
    assert_int_equal(sat, 0u);
    assert_int_equal(rfe_fix_sat32((int64_t)INT32_MAX + 1, &sat), INT32_MAX);
    assert_int_equal(rfe_fix_sat32(INT32_MIN, &sat), -INT32_MAX); /* symmetric range */
    assert_int_equal(rfe_fix_sat32(INT64_MAX, &sat), INT32_MAX);
    assert_int_equal(rfe_fix_sat32(INT64_MIN, &sat), -INT32_MAX);
    assert_int_equal(sat, 4u);
    /* The counter itself saturates. */
    sat = UINT32_MAX - 1u;
    (void)rfe_fix_sat32(INT64_MAX, &sat);
    assert_true(sat == UINT32_MAX);
    (void)rfe_fix_sat32(INT64_MAX, &sat);
    assert_true(sat == UINT32_MAX);
    rfe_fix_count_sat(&sat);
    assert_true(sat == UINT32_MAX);
    assert_int_equal(RFE_FIX_ONE(30), 1073741824);
    assert_int_equal(RFE_FIX_ONE(0), 1);
}

/* REQ-FXP-001 */
static void test_add_sub_neg_abs(void **state)
{
    static const int32_t edge[] = {0, 1, -1, 2, -2, INT32_MAX, INT32_MIN, INT32_MAX - 1,
                                   INT32_MIN + 1, 1 << 30, -(1 << 30)};
    const size_t ne = sizeof(edge) / sizeof(edge[0]);
    uint32_t sat = 0u;
    uint32_t want = 0u;
    size_t i;
    size_t j;
    long k;
    (void)state;
    rng_seed(101u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        const int32_t a = (k < 121) ? edge[(size_t)k % ne] : rand_i32();
        const int32_t b =
            (k < 121) ? edge[(size_t)k / ne] : ((k & 1) ? rand_i32() : rand_i32_log());
        assert_int_equal(rfe_fix_add(a, b, &sat), ref_sat((int64_t)a + b, &want));
        assert_int_equal(rfe_fix_sub(a, b, &sat), ref_sat((int64_t)a - b, &want));
        assert_int_equal(rfe_fix_neg(a, &sat), ref_sat(-(int64_t)a, &want));
        assert_int_equal(rfe_fix_abs(a, &sat), ref_sat((a < 0) ? -(int64_t)a : a, &want));
        assert_int_equal(sat, want);
    }
    assert_true(want > 0u);
    for (i = 0; i < ne; ++i) {
        for (j = 0; j < ne; ++j) {
            const int32_t a = edge[i];
            const int32_t b = edge[j];
            assert_int_equal(rfe_fix_min(a, b), (a < b) ? a : b);
            assert_int_equal(rfe_fix_max(a, b), (a > b) ? a : b);
            if (a <= b) {
                assert_int_equal(rfe_fix_clamp(0, a, b), (0 < a) ? a : ((0 > b) ? b : 0));
            }
        }
    }
    assert_int_equal(rfe_fix_clamp(5, -3, 3), 3);
    assert_int_equal(rfe_fix_clamp(-5, -3, 3), -3);
    assert_int_equal(rfe_fix_clamp(2, -3, 3), 2);
}

/* REQ-FXP-001 */
static void test_shifts(void **state)
{
    static const int64_t edge[] = {0, 1, -1, 2, -2, 3, -3, 5, -5, 6, -6, INT64_MAX, INT64_MIN,
                                   INT64_MAX - 1, INT64_MIN + 1, INT32_MIN, INT32_MAX};
    const size_t ne = sizeof(edge) / sizeof(edge[0]);
    size_t i;
    unsigned s;
    long k;
    (void)state;
    /* Floor semantics on negative values (the implementation-defined >> is never used). */
    assert_true(rfe_fix_shr64_floor(-1, 1u) == -1);
    assert_true(rfe_fix_shr64_floor(-2, 1u) == -1);
    assert_true(rfe_fix_shr64_floor(-3, 1u) == -2);
    assert_true(rfe_fix_shr64_floor(-5, 2u) == -2);
    assert_true(rfe_fix_shr64_floor(5, 2u) == 1);
    assert_true(rfe_fix_shr64_floor(INT64_MIN, 63u) == -1);
    assert_true(rfe_fix_shr64_floor(INT64_MIN, 64u) == -1);
    assert_true(rfe_fix_shr64_floor(INT64_MAX, 63u) == 0);
    assert_true(rfe_fix_shr64_floor(INT64_MAX, 200u) == 0);
    assert_true(rfe_fix_shr64_floor(INT64_MIN, 1u) == INT64_MIN / 2);
    /* Round half up: -0.5 -> 0, -1.5 -> -1, -0.75 -> -1, 0.5 -> 1, 1.5 -> 2. */
    assert_true(rfe_fix_shr64_round(-1, 1u) == 0);
    assert_true(rfe_fix_shr64_round(-3, 1u) == -1);
    assert_true(rfe_fix_shr64_round(-3, 2u) == -1);
    assert_true(rfe_fix_shr64_round(1, 1u) == 1);
    assert_true(rfe_fix_shr64_round(3, 1u) == 2);
    assert_true(rfe_fix_shr64_round(INT64_MAX, 1u) == ((int64_t)1 << 62));
    assert_true(rfe_fix_shr64_round(INT64_MIN, 64u) == 0);
    assert_true(rfe_fix_shr64_round(INT64_MIN, 63u) == -1);
    assert_int_equal(rfe_fix_shr_round(-7, 2u), -2);
    assert_int_equal(rfe_fix_shr_round(INT32_MIN, 31u), -1);
    assert_int_equal(rfe_fix_shr_round(INT32_MIN, 32u), 0); /* -1/2 rounds up to 0 */
    /* the int32 form (32-bit operations) against the int64 reference at every shift, on the
     * int32 edges and the ties of each shift (a = +-2^(s-1), +-3 2^(s-1)) */
    for (s = 0u; s <= 70u; ++s) {
        const int32_t e32[] = {INT32_MIN, INT32_MIN + 1, -1, 0, 1, INT32_MAX - 1, INT32_MAX};
        size_t j;
        for (j = 0u; j < (sizeof(e32) / sizeof(e32[0])); ++j) {
            assert_true((int64_t)rfe_fix_shr_round(e32[j], s) == ref_round_shift(e32[j], s));
        }
        if ((s >= 1u) && (s <= 30u)) {
            const int32_t h = (int32_t)1 << (s - 1u);
            assert_true((int64_t)rfe_fix_shr_round(h, s) == ref_round_shift(h, s));
            assert_true((int64_t)rfe_fix_shr_round(-h, s) == ref_round_shift(-h, s));
            assert_true((int64_t)rfe_fix_shr_round(3 * h, s) == ref_round_shift(3 * h, s));
            assert_true((int64_t)rfe_fix_shr_round(-3 * h, s) == ref_round_shift(-3 * h, s));
        }
    }
    for (i = 0; i < ne; ++i) {
        for (s = 0u; s <= 70u; ++s) {
            assert_true(rfe_fix_shr64_floor(edge[i], s) == ref_floor_shift(edge[i], s));
            assert_true(rfe_fix_shr64_round(edge[i], s) == ref_round_shift(edge[i], s));
        }
        /* the 32-bit-halves forms the Cortex-M0+ build uses (RFE_FIX_SHIFT64_W32), checked
         * here on the host against the references at every shift they take */
        for (s = 1u; s <= 63u; ++s) {
            assert_true(rfe_fix_shr64_floor_w32(edge[i], s) == ref_floor_shift(edge[i], s));
        }
        for (s = 0u; s <= 63u; ++s) {
            const uint64_t bit = ((uint64_t)edge[i] >> s) & 1u;
            assert_true((uint64_t)rfe_fix_bit64_w32(edge[i], s) == bit);
        }
    }
    rng_seed(202u);
    for (k = 0; k < 300000; k += LIGHT_STEP) {
        const int64_t a = u2s(rand_u64());
        const int64_t b = (int64_t)(rand_u64() >> (1u + rand_below(63u))) * ((k & 1) ? -1 : 1);
        s = rand_below(66u);
        assert_true(rfe_fix_shr64_floor(a, s) == ref_floor_shift(a, s));
        assert_true(rfe_fix_shr64_round(a, s) == ref_round_shift(a, s));
        assert_true(rfe_fix_shr64_floor(b, s) == ref_floor_shift(b, s));
        assert_true(rfe_fix_shr64_round(b, s) == ref_round_shift(b, s));
        {
            const int32_t a32 = (int32_t)(a >> 32); /* any int32 */
            assert_true((int64_t)rfe_fix_shr_round(a32, s) == ref_round_shift(a32, s));
        }
        if (s <= 63u) {
            const uint64_t ua = (uint64_t)a;
            assert_true(rfe_fix_ushr64_w32(ua, s) == (ua >> s));
        }
        if ((s >= 1u) && (s <= 63u)) {
            assert_true(rfe_fix_shr64_floor_w32(a, s) == ref_floor_shift(a, s));
            assert_true(rfe_fix_shr64_floor_w32(b, s) == ref_floor_shift(b, s));
            assert_true((uint64_t)rfe_fix_bit64_w32(a, s) == (((uint64_t)a >> s) & 1u));
        }
    }
}

/* REQ-FXP-001 */
static void test_shl_rescale_mul_narrow(void **state)
{
    uint32_t sat = 0u;
    uint32_t want = 0u;
    long k;
    (void)state;
    assert_int_equal(rfe_fix_shl(0, 100u, &sat), 0);
    assert_int_equal(rfe_fix_shl(1, 30u, &sat), 1 << 30);
    assert_int_equal(rfe_fix_shl(-1, 31u, &sat), -INT32_MAX); /* -2^31 saturates (symmetric) */
    assert_int_equal(rfe_fix_shl(1, 31u, &sat), INT32_MAX);
    assert_int_equal(rfe_fix_shl(-1, 32u, &sat), -INT32_MAX);
    assert_int_equal(rfe_fix_shl(1, 200u, &sat), INT32_MAX);
    assert_int_equal(sat, 4u);
    sat = 0u;
    assert_int_equal(rfe_fix_rescale(3, 4u, 6u, &sat), 12);  /* Q4 -> Q6 */
    assert_int_equal(rfe_fix_rescale(-3, 4u, 3u, &sat), -1); /* -1.5 rounds up to -1 */
    assert_int_equal(rfe_fix_rescale(-5, 4u, 3u, &sat), -2); /* -2.5 -> -2 */
    assert_int_equal(rfe_fix_rescale(1 << 20, 0u, 12u, &sat), INT32_MAX);
    assert_int_equal(sat, 1u);
    assert_int_equal(rfe_fix_narrow((int64_t)3 << 40, 40u, &sat), 3);
    assert_int_equal(rfe_fix_narrow(INT64_MAX, 1u, &sat), INT32_MAX);
    assert_int_equal(sat, 2u);
    /* mul: exact product, rounded half up, saturated: against the integer reference. */
    sat = 0u;
    assert_int_equal(rfe_fix_mul(INT32_MIN, INT32_MIN, 31u, &sat), INT32_MAX); /* 2^31 */
    assert_int_equal(rfe_fix_mul(INT32_MIN, INT32_MIN, 32u, &sat), 1 << 30);
    assert_int_equal(rfe_fix_mul(INT32_MIN, INT32_MAX, 31u, &sat), -INT32_MAX);
    assert_int_equal(rfe_fix_mul(-3, 1, 1u, &sat), -1);
    assert_int_equal(rfe_fix_mul(1 << 30, 1 << 30, 30u, &sat), 1 << 30); /* 1.0 * 1.0 in Q30 */
    assert_int_equal(sat, 1u);
    rng_seed(303u);
    sat = 0u;
    for (k = 0; k < 300000; k += LIGHT_STEP) {
        const int32_t a = (k & 1) ? rand_i32() : rand_i32_log();
        const int32_t b = (k & 2) ? rand_i32() : rand_i32_log();
        const unsigned s = rand_below(64u);
        const unsigned t = rand_below(40u);
        const int64_t p = (int64_t)a * b;
        assert_int_equal(rfe_fix_mul(a, b, s, &sat), ref_sat(ref_round_shift(p, s), &want));
        assert_int_equal(rfe_fix_shl(a, t, &sat),
                         ref_sat((t > 31u) ? ((a == 0) ? 0 : ((a < 0) ? INT64_MIN : INT64_MAX))
                                           : a * ((int64_t)1 << t), &want));
        assert_int_equal(sat, want);
    }
}

/* REQ-FXP-001 */
static void test_add64(void **state)
{
    uint32_t sat = 0u;
    (void)state;
    assert_true(rfe_fix_add64(1, 2, &sat) == 3);
    assert_true(rfe_fix_add64(INT64_MAX - 1, 1, &sat) == INT64_MAX);
    assert_true(rfe_fix_add64(-INT64_MAX + 1, -1, &sat) == -INT64_MAX);
    assert_int_equal(sat, 0u);
    assert_true(rfe_fix_add64(INT64_MAX, 1, &sat) == INT64_MAX);
    assert_true(rfe_fix_add64(-INT64_MAX, -1, &sat) == -INT64_MAX);
    assert_true(rfe_fix_add64(INT64_MIN, 0, &sat) == -INT64_MAX);
    assert_true(rfe_fix_add64(INT64_MIN, INT64_MIN, &sat) == -INT64_MAX);
    assert_true(rfe_fix_add64(INT64_MAX, INT64_MAX, &sat) == INT64_MAX);
    assert_int_equal(sat, 5u);
    assert_true(rfe_fix_add64(INT64_MAX, INT64_MIN, &sat) == -1);
    assert_int_equal(sat, 5u);
}

/* ---- host conversions ------------------------------------------------------------------- */

/* REQ-FXP-001 */
static void test_conv(void **state)
{
    uint32_t sat = 0u;
    (void)state;
    assert_int_equal(rfe_fix_from_double(0.0, 30u, &sat), 0);
    assert_int_equal(rfe_fix_from_double(1.0, 30u, &sat), 1 << 30);
    assert_int_equal(rfe_fix_from_double(0.5, 0u, &sat), 1);   /* ties up */
    assert_int_equal(rfe_fix_from_double(-0.5, 0u, &sat), 0);
    assert_int_equal(rfe_fix_from_double(-1.5, 0u, &sat), -1);
    assert_int_equal(rfe_fix_from_double(0.49999999999999994, 0u, &sat), 0);
    assert_int_equal(rfe_fix_from_double(2147483646.5, 0u, &sat), INT32_MAX);
    assert_int_equal(rfe_fix_from_double(-2147483647.5, 0u, &sat), -INT32_MAX);
    assert_int_equal(sat, 0u);
    assert_int_equal(rfe_fix_from_double(2147483647.5, 0u, &sat), INT32_MAX);
    assert_int_equal(rfe_fix_from_double(-2147483647.75, 0u, &sat), -INT32_MAX);
    assert_int_equal(rfe_fix_from_double(4.0, 30u, &sat), INT32_MAX);
    assert_int_equal(rfe_fix_from_double(-HUGE_VAL, 3u, &sat), -INT32_MAX);
    assert_int_equal(rfe_fix_from_double(NAN, 3u, &sat), 0);
    assert_int_equal(sat, 5u);
    assert_true(rfe_fix_to_double(RFE_FIX_PI_Q29, 29u) == 1686629713.0 / 536870912.0);
    assert_true(rfe_fix_to_double(INT32_MIN, 31u) == -1.0);
    assert_true(rfe_fix64_to_double((int64_t)1 << 40, 41u) == 0.5);
    /* The Q29 angle constants are pi, pi/2, pi/4 rounded to nearest. */
    assert_int_equal(RFE_FIX_PI_Q29, rfe_fix_from_double(TEST_PI, 29u, &sat));
    assert_int_equal(RFE_FIX_HALF_PI_Q29, rfe_fix_from_double(TEST_PI / 2.0, 29u, &sat));
    assert_int_equal(RFE_FIX_QUARTER_PI_Q29, rfe_fix_from_double(TEST_PI / 4.0, 29u, &sat));
    assert_int_equal(RFE_FIX_TAN_LIMIT_Q29, rfe_fix_from_double(1.5, 29u, &sat));
}

/* ---- square roots and norm -------------------------------------------------------------- */

/* floor(sqrt(x)) == r exactly: r^2 <= x < (r + 1)^2, overflow-free. */
static void check_isqrt(uint64_t x)
{
    uint32_t r = 0u;
    uint64_t rr;
    assert_int_equal(rfe_fix_isqrt64(x, &r), RFE_OK);
    rr = (uint64_t)r * r;
    assert_true(rr <= x);
    if (r != UINT32_MAX) {
        assert_true(x - rr < 2u * (uint64_t)r + 1u); /* x < r^2 + 2r + 1 */
    }
}

/* REQ-FXP-002 */
static void test_isqrt64(void **state)
{
    uint32_t r = 123u;
    uint64_t k;
    long i;
    (void)state;
    assert_int_equal(rfe_fix_isqrt64(5u, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_isqrt64(0u, &r), RFE_OK);
    assert_int_equal(r, 0u);
    assert_int_equal(rfe_fix_isqrt64(UINT64_MAX, &r), RFE_OK);
    assert_true(r == UINT32_MAX);
    for (k = 0u; k < 5000u; ++k) {
        check_isqrt(k);
    }
    for (k = 1u; k < 5000u; ++k) { /* around perfect squares, small and near 2^64 */
        const uint64_t big = (uint64_t)UINT32_MAX - k;
        check_isqrt(k * k - 1u);
        check_isqrt(k * k);
        check_isqrt(k * k + 1u);
        check_isqrt(big * big - 1u);
        check_isqrt(big * big);
        check_isqrt(big * big + 1u);
        check_isqrt(big * big + 2u * big); /* (big + 1)^2 - 1 */
    }
    rng_seed(404u);
    for (i = 0; i < 300000; i += LIGHT_STEP) {
        check_isqrt(rand_u64() >> rand_below(64u));
    }
    printf("[fxmath] isqrt64: exact (floor) over %d cases\n", 300000 + 5000 + 7 * 4999);
}

/* round(sqrt(x 2^e)) == r exactly (ties up), and |r - sqrt| in LSB for the record. */
static double check_sqrt(int32_t x, unsigned qi, unsigned qo)
{
    int32_t r = UNTOUCHED32;
    uint32_t sat = 0u;
    const int e = 2 * (int)qo - (int)qi;
    const double exact = sqrt(ldexp((double)x, e));
    assert_int_equal(rfe_fix_sqrt(x, qi, qo, &r, &sat), RFE_OK);
    if (e >= 0 && (double)x * ldexp(1.0, e) > 4611686016279904256.0) { /* > 2^62 - 2^31 */
        assert_int_equal(r, INT32_MAX);
        assert_int_equal(sat, 1u);
        return 0.0;
    }
    assert_int_equal(sat, 0u);
    assert_true(r >= 0);
    if (e >= 0) {
        /* N = x 2^e < 2^62 exact; round(sqrt N) = r  <=>  r^2 - r < N <= r^2 + r. */
        const uint64_t n = (uint64_t)x << e;
        const uint64_t r2 = (uint64_t)r * (uint64_t)r;
        assert_true(n <= r2 + (uint64_t)r);
        assert_true((r == 0) || (n > r2 - (uint64_t)r));
    } else {
        /* (2r - 1)^2 2^k <= 4x < (2r + 1)^2 2^k, all exact in double (<= 2^34 * 2^k). */
        const double lo = (2.0 * r - 1.0) * (2.0 * r - 1.0);
        const double hi = (2.0 * r + 1.0) * (2.0 * r + 1.0);
        const double x4 = ldexp(4.0 * x, e);
        assert_true((r == 0) || (lo <= x4));
        assert_true(x4 < hi);
    }
    return fabs((double)r - exact);
}

/* REQ-FXP-002 */
static void test_sqrt(void **state)
{
    static const int32_t edge[] = {0, 1, 2, 3, 4, 9, 1 << 30, INT32_MAX, INT32_MAX - 1, 46340,
                                   46341, 0x3FFFFFFF};
    int32_t r = UNTOUCHED32;
    uint32_t sat = UNTOUCHED_SAT;
    double worst = 0.0;
    unsigned qi;
    unsigned qo;
    size_t i;
    long count = 0;
    (void)state;
    /* Errors: outputs and counter untouched. */
    assert_int_equal(rfe_fix_sqrt(4, 0u, 0u, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_sqrt(4, 0u, 0u, &r, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_sqrt(-1, 0u, 0u, &r, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_sqrt(INT32_MIN, 0u, 0u, &r, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_sqrt(4, 32u, 0u, &r, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_sqrt(4, 0u, 32u, &r, &sat), RFE_ERR_RANGE);
    assert_int_equal(r, UNTOUCHED32);
    assert_int_equal(sat, UNTOUCHED_SAT);
    /* Known values: sqrt(2) in Q30 from 2 in Q30; sqrt(0.25) Q31 -> 0.5 Q31; ties. */
    assert_int_equal(rfe_fix_sqrt(2 << 29, 29u, 30u, &r, &sat), RFE_OK);
    assert_int_equal(r, 1518500250); /* round(sqrt(2) 2^30) = 1518500249.99 -> ...250 */
    assert_int_equal(rfe_fix_sqrt(1 << 29, 31u, 31u, &r, &sat), RFE_OK);
    assert_int_equal(r, 1 << 30);
    assert_int_equal(rfe_fix_sqrt(9, 2u, 0u, &r, &sat), RFE_OK); /* sqrt(9/4) = 1.5 -> 2 */
    assert_int_equal(r, 2);
    assert_int_equal(rfe_fix_sqrt(INT32_MAX, 31u, 31u, &r, &sat), RFE_OK); /* never saturates */
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(rfe_fix_sqrt(1, 0u, 31u, &r, &sat), RFE_OK); /* 1.0 -> Q31 saturates */
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(sat, UNTOUCHED_SAT + 1u);
    for (qi = 0u; qi <= 31u; ++qi) {
        for (qo = 0u; qo <= 31u; ++qo) {
            for (i = 0; i < sizeof(edge) / sizeof(edge[0]); ++i) {
                const double d = check_sqrt(edge[i], qi, qo);
                worst = (d > worst) ? d : worst;
                ++count;
            }
        }
    }
    rng_seed(505u);
    for (i = 0; i < 200000; i += LIGHT_STEP) {
        int32_t x = rand_i32_log();
        const double d =
            check_sqrt((x < 0) ? ((x == INT32_MIN) ? INT32_MAX : -x) : x, rand_below(32u),
                       rand_below(32u));
        worst = (d > worst) ? d : worst;
        ++count;
    }
    printf("[fxmath] sqrt: exactly rounded, max |err| = %.6f LSB over %ld cases\n", worst, count);
    assert_true(worst <= 0.5 + 1e-6);
}

/* 128-bit sum of squares in (hi, lo) for the reference. */
static void add128(uint64_t *hi, uint64_t *lo, uint64_t v)
{
    *lo += v;
    if (*lo < v) {
        ++*hi;
    }
}

static double check_norm(const int32_t *v, size_t n)
{
    uint64_t hi = 0u;
    uint64_t lo = 0u;
    double ssd = 0.0;
    int32_t r = UNTOUCHED32;
    uint32_t sat = 0u;
    size_t i;
    for (i = 0; i < n; ++i) {
        const uint64_t m = umag(v[i]);
        add128(&hi, &lo, m * m);
        ssd += (double)v[i] * (double)v[i];
    }
    assert_int_equal(rfe_fix_norm(v, n, &r, &sat), RFE_OK);
    if ((hi != 0u) || (lo > 4611686016279904256u)) { /* S > 2^62 - 2^31: rounds above MAX */
        assert_int_equal(r, INT32_MAX);
        assert_int_equal(sat, 1u);
        return 0.0;
    }
    assert_int_equal(sat, 0u);
    {
        const uint64_t r2 = (uint64_t)r * (uint64_t)r;
        assert_true(lo <= r2 + (uint64_t)r);
        assert_true((r == 0) || (lo > r2 - (uint64_t)r));
    }
    return fabs((double)r - sqrt(ssd));
}

/* REQ-FXP-002 */
static void test_norm(void **state)
{
    static int32_t big[100000];
    int32_t v[16];
    int32_t r = UNTOUCHED32;
    uint32_t sat = UNTOUCHED_SAT;
    double worst = 0.0;
    size_t i;
    size_t j;
    long count = 0;
    (void)state;
    v[0] = 3;
    v[1] = -4;
    assert_int_equal(rfe_fix_norm(NULL, 2u, &r, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_norm(v, 2u, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_norm(v, 2u, &r, NULL), RFE_ERR_NULL);
    assert_int_equal(r, UNTOUCHED32);
    assert_int_equal(sat, UNTOUCHED_SAT);
    assert_int_equal(rfe_fix_norm(v, 2u, &r, &sat), RFE_OK);
    assert_int_equal(r, 5);
    assert_int_equal(rfe_fix_norm(v, 0u, &r, &sat), RFE_OK);
    assert_int_equal(r, 0);
    v[0] = INT32_MIN; /* |v| = 2^31 > INT32_MAX */
    assert_int_equal(rfe_fix_norm(v, 1u, &r, &sat), RFE_OK);
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(sat, UNTOUCHED_SAT + 1u);
    v[0] = INT32_MAX; /* (2^31 - 1)^2 + 1 stays below the threshold */
    v[1] = 1;
    assert_int_equal(rfe_fix_norm(v, 2u, &r, &sat), RFE_OK);
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(sat, UNTOUCHED_SAT + 1u);
    for (i = 0; i < 16u; ++i) { /* many large terms: stops at the second, no wrap-around */
        v[i] = (i & 1u) ? INT32_MIN : INT32_MAX;
    }
    assert_int_equal(rfe_fix_norm(v, 16u, &r, &sat), RFE_OK);
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(sat, UNTOUCHED_SAT + 2u);
    v[0] = 1 << 30; /* S = 3 * 2^60 */
    v[1] = 1 << 30;
    v[2] = -(1 << 30);
    v[3] = 0;
    worst = check_norm(v, 4u);
    /* A long vector of small values (QR column of a large filter). */
    for (i = 0; i < 100000u; i += LIGHT_STEP) {
        big[i] = (int32_t)((i % 7u) + 1u) * ((i & 1u) ? -1 : 1);
    }
    {
        const double d = check_norm(big, 100000u);
        worst = (d > worst) ? d : worst;
    }
    rng_seed(606u);
    for (i = 0; i < 200000u; i += LIGHT_STEP) {
        const size_t n = rand_below(13u);
        const unsigned mode = rand_below(4u);
        for (j = 0; j < n; ++j) {
            v[j] = (mode == 0u) ? rand_i32() : (mode == 1u) ? (rand_i32() >> 3) : rand_i32_log();
        }
        {
            const double d = check_norm(v, n);
            worst = (d > worst) ? d : worst;
        }
        ++count;
    }
    printf("[fxmath] norm: exactly rounded, max |err| = %.6f LSB over %ld vectors\n", worst,
           count);
    assert_true(worst <= 0.5 + 1e-6);
}

/* Threshold case separately: S = (2^31 - 1) * 2^31 = 2^62 - 2^31 is the largest unsaturated. */
/* REQ-FXP-002 */
static void test_norm_threshold(void **state)
{
    int32_t v[2];
    int32_t r = 0;
    uint32_t sat = 0u;
    (void)state;
    /* rfe_fix_sqrt at the same threshold: x = 2^31 - 1 from Q31 to Q31 is N = 2^62 - 2^31. */
    assert_int_equal(rfe_fix_sqrt(INT32_MAX, 31u, 31u, &r, &sat), RFE_OK);
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(sat, 0u);
    /* The norm: (2^31 - 1)^2 = 2^62 - 2^32 + 1 leaves room for w^2 <= 2^31 - 1, w <= 46340. */
    v[0] = INT32_MAX;
    v[1] = 46340; /* S = 2^62 - 2^31 - 88047: rounds to 2^31 - 1 */
    assert_int_equal(rfe_fix_norm(v, 2u, &r, &sat), RFE_OK);
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(sat, 0u);
    v[1] = 46341; /* S = 2^62 - 2^31 + 4634 > (2^31 - 1/2)^2: rounds to 2^31, saturates */
    assert_int_equal(rfe_fix_norm(v, 2u, &r, &sat), RFE_OK);
    assert_int_equal(r, INT32_MAX);
    assert_int_equal(sat, 1u);
}

/* ---- division --------------------------------------------------------------------------- */

/* Checks q = round(a 2^s / b) (ties away from zero, symmetric saturation). Exact integer
 * reference for |s| <= 31, from unsigned __int128 (GCC's and Clang's) for every other shift
 * (|a| 2^62 and |b| 2^62 fit 94 bits), and a double bound (0.5 LSB + the reference's 2^-20)
 * as well. Returns |q - a 2^s / b| in LSB when unsaturated. */
static double check_div(int32_t a, int32_t b, int s)
{
    int32_t q = UNTOUCHED32;
    uint32_t sat = 0u;
    const int neg = (a < 0) != (b < 0);
    const double exact = ldexp((double)a / (double)b, s);
    assert_int_equal(rfe_fix_div(a, b, s, &q, &sat), RFE_OK);
    {
        unsigned __int128 n = umag(a);
        unsigned __int128 d = umag(b);
        unsigned __int128 m;
        if (s >= 0) {
            n <<= s;
        } else {
            d <<= -s;
        }
        m = n / d + ((2u * (n % d) >= d) ? 1u : 0u);
        if (m > (unsigned __int128)INT32_MAX) {
            assert_int_equal(q, neg ? -INT32_MAX : INT32_MAX);
            assert_int_equal(sat, 1u);
        } else {
            assert_int_equal(sat, 0u);
            assert_true(q == (neg ? -(int64_t)m : (int64_t)m));
        }
    }
    if ((s >= -31) && (s <= 31)) {
        uint64_t n = umag(a);
        uint64_t d = umag(b);
        uint64_t m;
        if (s >= 0) {
            n <<= s;
        } else {
            d <<= -s;
        }
        m = n / d + ((2u * (n % d) >= d) ? 1u : 0u);
        if (m > (uint64_t)INT32_MAX) {
            assert_int_equal(q, neg ? -INT32_MAX : INT32_MAX);
            assert_int_equal(sat, 1u);
            return 0.0;
        }
        assert_int_equal(sat, 0u);
        assert_true(q == (neg ? -(int64_t)m : (int64_t)m));
        return fabs((double)q - exact);
    }
    if (fabs(exact) >= 2147483647.5 + 1e-3) {
        assert_int_equal(q, neg ? -INT32_MAX : INT32_MAX);
        assert_int_equal(sat, 1u);
        return 0.0;
    }
    if (fabs(exact) < 2147483647.5 - 1e-3) {
        assert_int_equal(sat, 0u);
        assert_true(fabs((double)q - exact) <= 0.5 + ldexp(1.0, -20));
        return fabs((double)q - exact);
    }
    return 0.0; /* within 1e-3 of the saturation boundary: no double verdict */
}

/* REQ-FXP-002 */
static void test_div(void **state)
{
    static const int32_t edge[] = {0, 1, -1, 2, -2, 3, -3, 7, INT32_MAX, INT32_MIN,
                                   INT32_MAX - 1, INT32_MIN + 1, 1 << 30, 46341};
    const size_t ne = sizeof(edge) / sizeof(edge[0]);
    int32_t q = UNTOUCHED32;
    uint32_t sat = UNTOUCHED_SAT;
    double worst = 0.0;
    size_t i;
    size_t j;
    int s;
    long k;
    long count = 0;
    (void)state;
    assert_int_equal(rfe_fix_div(1, 2, 0, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_div(1, 2, 0, &q, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_div(1, 0, 0, &q, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_div(0, 0, 5, &q, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_div(1, 2, 63, &q, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_div(1, 2, -63, &q, &sat), RFE_ERR_RANGE);
    assert_int_equal(q, UNTOUCHED32);
    assert_int_equal(sat, UNTOUCHED_SAT);
    /* Ties away from zero; saturation of -2^31; reciprocal; format change. */
    sat = 0u;
    assert_int_equal(rfe_fix_div(1, 2, 0, &q, &sat), RFE_OK);
    assert_int_equal(q, 1);
    assert_int_equal(rfe_fix_div(-1, 2, 0, &q, &sat), RFE_OK);
    assert_int_equal(q, -1);
    assert_int_equal(rfe_fix_div(5, -2, 0, &q, &sat), RFE_OK);
    assert_int_equal(q, -3);
    assert_int_equal(rfe_fix_div(INT32_MIN, -1, 0, &q, &sat), RFE_OK);
    assert_int_equal(q, INT32_MAX);
    assert_int_equal(rfe_fix_div(INT32_MIN, 1, 0, &q, &sat), RFE_OK);
    assert_int_equal(q, -INT32_MAX);
    assert_int_equal(sat, 2u);
    assert_int_equal(rfe_fix_div(1, 4 << 20, 30 + 20, &q, &sat), RFE_OK); /* 1/4 Q20 -> Q30 */
    assert_int_equal(q, 1 << 28);
    assert_int_equal(rfe_fix_div(1, 1 << 20, 30 + 20, &q, &sat), RFE_OK); /* 1/1.0 -> Q30 */
    assert_int_equal(q, 1 << 30);
    assert_int_equal(rfe_fix_div(1, INT32_MIN, 61, &q, &sat), RFE_OK);
    assert_int_equal(q, -(1 << 30));
    assert_int_equal(rfe_fix_div(1, INT32_MIN, 62, &q, &sat), RFE_OK); /* -2^31 */
    assert_int_equal(q, -INT32_MAX);
    assert_int_equal(rfe_fix_div(0, INT32_MIN, 62, &q, &sat), RFE_OK);
    assert_int_equal(q, 0);
    assert_int_equal(rfe_fix_div(INT32_MIN, 1, -32, &q, &sat), RFE_OK); /* -1/2 -> -1 */
    assert_int_equal(q, -1);
    assert_int_equal(rfe_fix_div(INT32_MIN, 1, -33, &q, &sat), RFE_OK); /* -1/4 -> 0 */
    assert_int_equal(q, 0);
    assert_int_equal(rfe_fix_div(INT32_MAX, 1, -62, &q, &sat), RFE_OK);
    assert_int_equal(q, 0);
    assert_int_equal(sat, 3u);
    for (i = 0; i < ne; ++i) {
        for (j = 0; j < ne; ++j) {
            if (edge[j] == 0) {
                continue;
            }
            for (s = -62; s <= 62; ++s) {
                const double d = check_div(edge[i], edge[j], s);
                worst = (d > worst) ? d : worst;
                ++count;
            }
        }
    }
    rng_seed(707u);
    for (k = 0; k < 400000; k += LIGHT_STEP) {
        const int32_t a = (k & 1) ? rand_i32() : rand_i32_log();
        int32_t b = (k & 2) ? rand_i32() : rand_i32_log();
        /* Mostly shifts that keep the quotient in range, some anywhere in [-62, 62]. */
        const int sh = (k & 4) ? (int)rand_below(125u) - 62 : (int)rand_below(63u) - 31;
        b = (b == 0) ? 3 : b;
        {
            const double d = check_div(a, b, sh);
            worst = (d > worst) ? d : worst;
        }
        ++count;
    }
    printf("[fxmath] div: exactly rounded, max |err| = %.6f LSB over %ld cases\n", worst, count);
    assert_true(worst <= 0.5 + ldexp(1.0, -20));
}

/* ---- atan2 ------------------------------------------------------------------------------- */

static double atan2_worst = 0.0;
static long atan2_count = 0;

static int32_t check_atan2(int32_t y, int32_t x)
{
    int32_t a = UNTOUCHED32;
    double want;
    double err;
    assert_int_equal(rfe_fix_atan2(y, x, &a), RFE_OK);
    want = atan2((double)y, (double)x);
    err = fabs((double)a * LSB29 - want);
    if (err > atan2_worst) {
        atan2_worst = err;
    }
    ++atan2_count;
    ASSERT_LE(err, TOL_ATAN2, "atan2");
    assert_true((a >= -RFE_FIX_PI_Q29) && (a <= RFE_FIX_PI_Q29));
    if (y != INT32_MIN) { /* exactly odd in y */
        int32_t b = 0;
        assert_int_equal(rfe_fix_atan2(-y, x, &b), RFE_OK);
        assert_int_equal(b, (y == 0) ? a : -a);
    }
    return a;
}

/* REQ-FXP-002 */
static void test_atan2(void **state)
{
    static const int32_t edge[] = {0, 1, -1, 2, -2, INT32_MAX, INT32_MIN, INT32_MAX - 1,
                                   INT32_MIN + 1, 1 << 30, -(1 << 30), 46341, 12345678};
    const size_t ne = sizeof(edge) / sizeof(edge[0]);
    size_t i;
    size_t j;
    long k;
    int x;
    int y;
    (void)state;
    assert_int_equal(rfe_fix_atan2(1, 1, NULL), RFE_ERR_NULL);
    /* Axes and the origin: exact values. */
    assert_int_equal(check_atan2(0, 0), 0);
    assert_int_equal(check_atan2(0, 5), 0);
    assert_int_equal(check_atan2(0, -5), RFE_FIX_PI_Q29);
    assert_int_equal(check_atan2(0, INT32_MIN), RFE_FIX_PI_Q29);
    assert_int_equal(check_atan2(7, 0), RFE_FIX_HALF_PI_Q29);
    assert_int_equal(check_atan2(-7, 0), -RFE_FIX_HALF_PI_Q29);
    assert_int_equal(check_atan2(INT32_MIN, 0), -RFE_FIX_HALF_PI_Q29);
    assert_int_equal(check_atan2(INT32_MAX, INT32_MAX), RFE_FIX_QUARTER_PI_Q29);
    assert_int_equal(check_atan2(INT32_MIN, INT32_MIN), -(RFE_FIX_PI_Q29 - RFE_FIX_QUARTER_PI_Q29));
    assert_int_equal(check_atan2(1, INT32_MAX), 0); /* 4.7e-10 rad = 0.25 LSB */
    assert_int_equal(check_atan2(-1, INT32_MIN), -RFE_FIX_PI_Q29);
    for (i = 0; i < ne; ++i) {
        for (j = 0; j < ne; ++j) {
            (void)check_atan2(edge[i], edge[j]);
        }
    }
    for (y = -64; y <= 64; ++y) {
        for (x = -64; x <= 64; ++x) {
            (void)check_atan2((int32_t)y, (int32_t)x);
        }
    }
    /* Dense angle grid at random radii (1 .. 2^31), every quadrant. */
    rng_seed(808u);
    for (k = 0; k < 262144; k += LIGHT_STEP) {
        const double th = -TEST_PI + (2.0 * TEST_PI * (double)k) / 262144.0;
        const double rad = ldexp(1.0, (int)rand_below(31u)) * (1.0 + 0.999 * fabs(rng_uniform()));
        const double xd = rad * cos(th);
        const double yd = rad * sin(th);
        (void)check_atan2((int32_t)fmax(fmin(yd, 2147483647.0), -2147483648.0),
                          (int32_t)fmax(fmin(xd, 2147483647.0), -2147483648.0));
    }
    for (k = 0; k < 400000; k += LIGHT_STEP) {
        (void)check_atan2((k & 1) ? rand_i32() : rand_i32_log(),
                          (k & 2) ? rand_i32() : rand_i32_log());
    }
    printf("[fxmath] atan2: max |err| = %.3e rad (%.4f LSB Q29) over %ld points, bound %.1e\n",
           atan2_worst, atan2_worst / LSB29, atan2_count, TOL_ATAN2);
}

/* ---- sin, cos, tan ----------------------------------------------------------------------- */

static double sincos_worst = 0.0;
static long sincos_count = 0;

static void check_sincos(int32_t ang)
{
    int32_t s = UNTOUCHED32;
    int32_t c = UNTOUCHED32;
    const double a = (double)ang * LSB29;
    double es;
    double ec;
    assert_int_equal(rfe_fix_sincos(ang, &s, &c), RFE_OK);
    es = fabs((double)s * LSB30 - sin(a));
    ec = fabs((double)c * LSB30 - cos(a));
    sincos_worst = fmax(sincos_worst, fmax(es, ec));
    ++sincos_count;
    ASSERT_LE(es, TOL_SINCOS, "sin");
    ASSERT_LE(ec, TOL_SINCOS, "cos");
    assert_true((s >= -(1 << 30)) && (s <= (1 << 30)) && (c >= -(1 << 30)) && (c <= (1 << 30)));
    if (ang != INT32_MIN) { /* sin odd, cos even, exactly */
        int32_t s2 = 0;
        int32_t c2 = 0;
        assert_int_equal(rfe_fix_sincos(-ang, &s2, &c2), RFE_OK);
        assert_int_equal(s2, -s);
        assert_int_equal(c2, c);
    }
}

/* REQ-FXP-002 */
static void test_sincos(void **state)
{
    static const int32_t edge[] = {0, 1, -1, RFE_FIX_PI_Q29, -RFE_FIX_PI_Q29, RFE_FIX_PI_Q29 + 1,
                                   RFE_FIX_HALF_PI_Q29, -RFE_FIX_HALF_PI_Q29,
                                   RFE_FIX_HALF_PI_Q29 + 1, RFE_FIX_HALF_PI_Q29 - 1,
                                   RFE_FIX_QUARTER_PI_Q29, INT32_MAX, INT32_MIN, INT32_MIN + 1};
    int32_t s = UNTOUCHED32;
    int32_t c = UNTOUCHED32;
    size_t i;
    long k;
    (void)state;
    assert_int_equal(rfe_fix_sincos(0, NULL, &c), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_sincos(0, &s, NULL), RFE_ERR_NULL);
    assert_int_equal(s, UNTOUCHED32);
    assert_int_equal(c, UNTOUCHED32);
    assert_int_equal(rfe_fix_sincos(0, &s, &c), RFE_OK);
    assert_int_equal(s, 0);
    assert_int_equal(c, 1 << 30);
    assert_int_equal(rfe_fix_sincos(RFE_FIX_HALF_PI_Q29, &s, &c), RFE_OK);
    assert_int_equal(s, 1 << 30);
    for (i = 0; i < sizeof(edge) / sizeof(edge[0]); ++i) {
        check_sincos(edge[i]);
    }
    /* Every 2^12-th angle over the whole int32 range (+-4 rad; light mode: every 10th of
     * those, the edges above), then random angles. */
    for (k = 0; k < (1L << 20); k += LIGHT_STEP) {
        check_sincos((int32_t)(INT32_MIN + k * 4096L + 1234L));
    }
    rng_seed(909u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        check_sincos((k & 1) ? rand_i32() : rand_i32_log());
    }
    printf("[fxmath] sincos: max |err| = %.3e (%.4f LSB Q30) over %ld angles, bound %.1e\n",
           sincos_worst, sincos_worst / LSB30, sincos_count, TOL_SINCOS);
}

static double tan_worst = 0.0;
static double tan_worst_rel = 0.0;
static long tan_count = 0;

static void check_tan(int32_t ang)
{
    int32_t t = UNTOUCHED32;
    int32_t t2 = 0;
    const double want = tan((double)ang * LSB29);
    double err;
    assert_int_equal(rfe_fix_tan(ang, &t), RFE_OK);
    err = fabs((double)t * LSB26 - want);
    tan_worst = fmax(tan_worst, err);
    if (fabs(want) >= 0.1) {
        tan_worst_rel = fmax(tan_worst_rel, err / fabs(want));
    }
    ++tan_count;
    ASSERT_LE(err, TOL_TAN, "tan");
    assert_int_equal(rfe_fix_tan(-ang, &t2), RFE_OK);
    assert_int_equal(t2, -t);
}

/* REQ-FXP-002 */
static void test_tan(void **state)
{
    const int32_t lim = RFE_FIX_TAN_LIMIT_Q29;
    int32_t t = UNTOUCHED32;
    long k;
    (void)state;
    assert_int_equal(rfe_fix_tan(0, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_fix_tan(lim + 1, &t), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_tan(-lim - 1, &t), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_tan(INT32_MIN, &t), RFE_ERR_RANGE);
    assert_int_equal(rfe_fix_tan(INT32_MAX, &t), RFE_ERR_RANGE);
    assert_int_equal(t, UNTOUCHED32);
    assert_int_equal(rfe_fix_tan(0, &t), RFE_OK);
    assert_int_equal(t, 0);
    assert_int_equal(rfe_fix_tan(RFE_FIX_QUARTER_PI_Q29, &t), RFE_OK);
    assert_int_equal(t, 1 << 26);
    check_tan(lim);
    check_tan(lim - 1);
    check_tan(1);
    check_tan(0);
    /* every 2^11-th angle over [-1.5, 1.5] rad (light mode: every 10th of those; both ends
     * are checked above) */
    for (k = 0; k <= 786432; k += LIGHT_STEP) {
        check_tan((int32_t)(-lim + k * 2048L));
    }
    rng_seed(1010u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        const int32_t a = (int32_t)((k & 1) ? rand_i32() % (lim + 1) : rand_i32_log() % (lim + 1));
        check_tan(a);
    }
    printf("[fxmath] tan: max |err| = %.3e (%.4f LSB Q26), max rel err %.2e (|tan| >= 0.1) "
           "over %ld angles, bound %.1e\n",
           tan_worst, tan_worst / LSB26, tan_worst_rel, tan_count, TOL_TAN);
}

/* ---- the Magic Formula's atan2 and sine (fxmath_internal_q31.h) ---------------------------- */

#define Q31_HALF_PI 3373259426u                       /* round(pi/2 2^31) */
#define Q55_PI INT64_C(113187804032455044)            /* round(pi 2^55) */
#define Q55_HALF_PI INT64_C(56593902016227522)        /* round(pi/2 2^55) */
#define TWO30 1073741824u

static double atq_worst = 0.0;
static long atq_count = 0;

/* rfe_q31_atan2_quad1 as first written, its 22 division digits one non-restoring step each
 * (the library now forms their sum with one division where the core divides in one
 * instruction): the reference its integers must equal. The same constants: atan(1/2) and pi/2
 * in Q61, 2^-i - atan(2^-i) in Q38 for i = 2 .. 11. */
static uint32_t atan2_quad1_steps(uint32_t y, uint32_t x)
{
    static const int32_t corr_q38[10] = {1380254570, 177297749, 22317338, 2794565, 349474,
                                         43689,      5461,      683,      85,      11};
    const uint32_t a = (y > x) ? y : x;
    const uint32_t b = (y > x) ? x : y;
    int64_t z = 0;
    if (b != 0u) {
        unsigned int sh = 0u;
        unsigned int s1 = 2u;
        uint32_t cpos = 1u;
        uint32_t dpos = 1u;
        int32_t corr = 0;
        int32_t lead;
        int32_t xx;
        int32_t w;
        unsigned int i;
        while ((a << sh) < (1u << 29)) {
            ++sh;
        }
        xx = (int32_t)(a << sh);
        w = (int32_t)(b << sh);
        {
            const uint32_t m = (uint32_t)w;
            w = (w - xx) + w;
            xx += (int32_t)((m + 1u) >> 1);
        }
        for (i = 0u; i < 10u; ++i) {
            uint32_t m;
            cpos += cpos;
            if (w >= 0) {
                m = (uint32_t)w;
                w = (w - xx) + w;
                cpos += 1u;
                corr += corr_q38[i];
            } else {
                m = (uint32_t)(-w);
                w = (w + xx) + w;
                corr -= corr_q38[i];
            }
            xx += (int32_t)(((m >> s1) + 1u) >> 1);
            s1 += 2u;
        }
        if (w >= 0) {
            w -= xx;
            lead = 4194304;
        } else {
            w += xx;
            lead = -4194304;
        }
        while (dpos < 4194304u) {
            dpos += dpos;
            if (w >= 0) {
                w = (w - xx) + w;
                dpos += 1u;
            } else {
                w = (w + xx) + w;
            }
        }
        {
            const int32_t steps = ((2 * (int32_t)(cpos - 1024u)) + 1) - 1024;
            const int32_t digits = lead + (((2 * (int32_t)(dpos - 4194304u)) + 1) - 4194304);
            z = ((INT64_C(1069098597953152948) + ((int64_t)steps * (INT64_C(1) << 50))) -
                 ((int64_t)corr * (INT64_C(1) << 23))) +
                ((int64_t)digits * (INT64_C(1) << 28));
        }
    }
    if (y > x) {
        z = INT64_C(3622009729038561421) - z;
    }
    z += INT64_C(1) << 29;
    return (uint32_t)((uint64_t)z >> 30);
}

static uint32_t check_atan2_quad1(uint32_t y, uint32_t x)
{
    const uint32_t a = rfe_q31_atan2_quad1(y, x);
    assert_int_equal(a, atan2_quad1_steps(y, x)); /* the same integer as the digit steps */
    const double want = ((x == 0u) && (y == 0u)) ? 0.0 : atan2((double)y, (double)x);
    const double err = fabs(ldexp((double)a, -31) - want);
    atq_worst = fmax(atq_worst, err);
    ++atq_count;
    ASSERT_LE(err, TOL_ATAN2_Q1, "atan2_quad1");
    assert_true(a <= Q31_HALF_PI);
    return a;
}

/* A value in [0, 2^30] with a random bit length (0 .. 31). */
static uint32_t rand_u30_log(void)
{
    const unsigned bits = rand_below(32u);
    const uint32_t v = (bits == 0u) ? 0u : (uint32_t)(rand_u64() >> (64u - bits));
    return (v > TWO30) ? TWO30 : v;
}

/* REQ: rfe_q31_atan2_quad1 (the Magic Formula's first-quadrant atan2, Q31) is within
 * TOL_ATAN2_Q1 of libm, and the integer of its digit-by-digit form (atan2_quad1_steps), over
 * every 0 <= x, y <= 2^30: the axes and the origin exactly
 * (0 -> 0, y > 0 at x = 0 -> round(pi/2 2^31)), every pair up to 64, the edges of the
 * normalisation (2^29 - 1, 2^29, 2^30) and the diagonal, a dense angle grid at random radii,
 * near-axis and near-diagonal pairs and random pairs (uniform and log-uniform magnitudes); the
 * result never leaves [0, pi/2]. */
/* REQ-FXP-002 */
static void test_atan2_quad1(void **state)
{
    static const uint32_t edge[] = {0u, 1u, 2u, 3u, 1000u, (1u << 29) - 1u, 1u << 29,
                                    (1u << 29) + 1u, TWO30 - 1u, TWO30, 12345678u, 987654321u};
    const size_t ne = sizeof(edge) / sizeof(edge[0]);
    size_t i;
    size_t j;
    long k;
    uint32_t x;
    uint32_t y;
    (void)state;
    atq_worst = 0.0;
    atq_count = 0;
    /* Axes and the origin: exact. */
    assert_int_equal(check_atan2_quad1(0u, 0u), 0);
    assert_int_equal(check_atan2_quad1(0u, 1u), 0);
    assert_int_equal(check_atan2_quad1(0u, TWO30), 0);
    assert_int_equal(check_atan2_quad1(1u, 0u), Q31_HALF_PI);
    assert_int_equal(check_atan2_quad1(TWO30, 0u), Q31_HALF_PI);
    /* The diagonal: pi/4 2^31 = 1686629713.07. */
    assert_int_equal(check_atan2_quad1(TWO30, TWO30), 1686629713u);
    assert_int_equal(check_atan2_quad1(7u, 7u), 1686629713u);
    for (i = 0; i < ne; ++i) {
        for (j = 0; j < ne; ++j) {
            (void)check_atan2_quad1(edge[i], edge[j]);
        }
    }
    for (y = 0u; y <= 64u; ++y) {
        for (x = 0u; x <= 64u; ++x) {
            (void)check_atan2_quad1(y, x);
        }
    }
    /* Dense angle grid over [0, pi/2] at random radii up to 2^30. */
    rng_seed(1111u);
    for (k = 0; k <= 262144; ++k) {
        const double th = (0.5 * TEST_PI * (double)k) / 262144.0;
        const double rad = ldexp(1.0, (int)rand_below(31u)) * (1.0 + 0.999 * fabs(rng_uniform()));
        (void)check_atan2_quad1((uint32_t)fmin(rad * sin(th), (double)TWO30),
                                (uint32_t)fmin(rad * cos(th), (double)TWO30));
    }
    /* Near the axes and the diagonal, at the largest and the smallest normalised scale. */
    for (k = 0; k < 4096; ++k) {
        const uint32_t big = (k & 1) ? TWO30 - (uint32_t)rand_below(1024u)
                                     : (1u << 29) + (uint32_t)rand_below(1024u);
        const uint32_t small = (uint32_t)rand_below(4096u);
        (void)check_atan2_quad1(small, big);
        (void)check_atan2_quad1(big, small);
        (void)check_atan2_quad1(big - small, big);
        (void)check_atan2_quad1(big, big - small);
    }
    for (k = 0; k < 400000; k += LIGHT_STEP) {
        const uint32_t yy = (k & 1) ? (uint32_t)rand_below(TWO30 + 1u) : rand_u30_log();
        const uint32_t xx = (k & 2) ? (uint32_t)rand_below(TWO30 + 1u) : rand_u30_log();
        (void)check_atan2_quad1(yy, xx);
    }
    printf("[fxmath] atan2_quad1: max |err| = %.3e rad (%.3f 2^-32, %.4f LSB Q29) over %ld "
           "pairs, bound %.3e\n",
           atq_worst, ldexp(atq_worst, 32), atq_worst / LSB29, atq_count, TOL_ATAN2_Q1);
}

static double sinq_worst = 0.0;
static long sinq_count = 0;

static int32_t check_sin_q55(int64_t phi)
{
    const int32_t g = rfe_q31_sin_q55(phi);
    const double err = fabs((double)g * LSB30 - sin(ldexp((double)phi, -55)));
    sinq_worst = fmax(sinq_worst, err);
    ++sinq_count;
    ASSERT_LE(err, TOL_SIN_Q55, "sin_q55");
    assert_true((g >= 0) && (g <= (1 << 30)));
    return g;
}

/* REQ: rfe_q31_sin_q55 (the Magic Formula's sine of a Q55 angle in [0, pi], Q30) is within
 * TOL_SIN_Q55 of libm: exactly 0 at 0 and pi and 1 at pi/2; at every table node k/32 and
 * next to it, at the ties of the node rounding (k + 1/2)/32 and of the rounding of d to Q36,
 * at both sides of the reflection at pi/2, on a dense grid and at random angles; the result
 * never leaves [0, 1]. */
/* REQ-FXP-002 */
static void test_sin_q55(void **state)
{
    const int64_t node = (int64_t)1 << 50; /* 1/32 rad in Q55 */
    long k;
    int d;
    (void)state;
    sinq_worst = 0.0;
    sinq_count = 0;
    assert_int_equal(check_sin_q55(0), 0);
    assert_int_equal(check_sin_q55(Q55_PI), 0);
    assert_int_equal(check_sin_q55(Q55_HALF_PI), 1 << 30);
    for (d = -2; d <= 2; ++d) {
        (void)check_sin_q55(Q55_HALF_PI + d);
        if (d >= 0) {
            (void)check_sin_q55(d);
            (void)check_sin_q55(Q55_PI - d);
        }
    }
    for (k = 0; k <= 101; ++k) {
        for (d = -3; d <= 3; ++d) {
            const int64_t at[3] = {k * node, k * node + node / 2, k * node + ((int64_t)1 << 18)};
            size_t i;
            for (i = 0; i < 3u; ++i) {
                const int64_t phi = at[i] + d;
                if ((phi >= 0) && (phi <= Q55_PI)) {
                    (void)check_sin_q55(phi);
                }
            }
        }
    }
    for (k = 0; k <= (1L << 20); ++k) { /* every 2^-20-th of [0, pi] */
        (void)check_sin_q55((int64_t)floor(ldexp((double)Q55_PI, -20) * (double)k));
    }
    rng_seed(1212u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        (void)check_sin_q55((int64_t)(rand_u64() % (uint64_t)(Q55_PI + 1)));
    }
    printf("[fxmath] sin_q55: max |err| = %.3e (%.4f LSB Q30) over %ld angles, bound %.3e\n",
           sinq_worst, sinq_worst / LSB30, sinq_count, TOL_SIN_Q55);
}

/* ---- the estimators' atan2, sin/cos and tan (fxmath_internal_q31.h) -------------------------- */

#define Q29_PI 1686629713    /* round(pi 2^29) = round(1686629713.07) */
#define Q29_HALF_PI 843314857 /* round(pi/2 2^29) = round(843314856.53) */

static double at29_worst = 0.0;
static long at29_count = 0;

static int32_t check_atan2_q29(int64_t y, int64_t x)
{
    const int32_t a = rfe_q31_atan2_q29(y, x);
    const double want = ((x == 0) && (y == 0)) ? 0.0 : atan2((double)y, (double)x);
    const double err = fabs((double)a * LSB29 - want);
    const int small = (x <= (int64_t)TWO30) && (x >= -(int64_t)TWO30) && (y <= (int64_t)TWO30) &&
                      (y >= -(int64_t)TWO30);
    at29_worst = fmax(at29_worst, err);
    ++at29_count;
    ASSERT_LE(err, small ? TOL_ATAN2_Q29_SMALL : TOL_ATAN2_Q29, "atan2_q29");
    assert_true((a >= -Q29_PI) && (a <= Q29_PI));
    return a;
}

/* An int64 of random sign and bit length 0 .. 63 (|.| <= 2^62). */
static int64_t rand_i62_log(void)
{
    const unsigned bits = rand_below(63u);
    const int64_t v = (bits == 0u) ? 0 : (int64_t)(rand_u64() >> (64u - bits));
    return (rand_u64() & 1u) ? -v : v;
}

/* REQ: rfe_q31_atan2_q29 (the kinematics' and the observer's atan2, Q29, whole plane) is
 * within TOL_ATAN2_Q29_SMALL of libm when |x|, |y| <= 2^30 and TOL_ATAN2_Q29 up to 2^62: the
 * axes exactly ((0, 0) -> 0, (0, x < 0) -> +pi, (y, 0) -> +-pi/2), odd in y, every pair in
 * [-40, 40]^2, a dense angle grid around the circle at random radii, the edges of the
 * scaling (2^30, 2^30 + 1, 2^62) and random pairs of log-uniform magnitudes; the result never
 * leaves [-pi, pi]. */
/* REQ-FXP-002 */
static void test_atan2_q29(void **state)
{
    static const int64_t edge[] = {0, 1, -1, 2, 1000, -1000, (int64_t)1 << 29, (int64_t)TWO30,
                                   -(int64_t)TWO30, (int64_t)TWO30 + 1, -((int64_t)TWO30 + 1),
                                   INT32_MAX, INT32_MIN, (int64_t)1 << 62, -((int64_t)1 << 62),
                                   ((int64_t)1 << 62) - 1};
    const size_t ne = sizeof(edge) / sizeof(edge[0]);
    size_t i;
    size_t j;
    long k;
    int64_t x;
    int64_t y;
    (void)state;
    at29_worst = 0.0;
    at29_count = 0;
    assert_int_equal(check_atan2_q29(0, 0), 0);
    assert_int_equal(check_atan2_q29(0, 5), 0);
    assert_int_equal(check_atan2_q29(0, -5), Q29_PI);
    assert_int_equal(check_atan2_q29(0, -((int64_t)1 << 62)), Q29_PI);
    assert_int_equal(check_atan2_q29(7, 0), Q29_HALF_PI);
    assert_int_equal(check_atan2_q29(-7, 0), -Q29_HALF_PI);
    for (i = 0; i < ne; ++i) {
        for (j = 0; j < ne; ++j) {
            const int32_t a = check_atan2_q29(edge[i], edge[j]);
            if (edge[i] != 0) { /* odd in y off the negative x axis */
                assert_int_equal(check_atan2_q29(-edge[i], edge[j]), -a);
            }
        }
    }
    for (y = -40; y <= 40; ++y) {
        for (x = -40; x <= 40; ++x) {
            (void)check_atan2_q29(y, x);
        }
    }
    rng_seed(1313u);
    for (k = 0; k < 262144; k += LIGHT_STEP) {
        const double th = (2.0 * TEST_PI * (double)k) / 262144.0 - TEST_PI;
        const double rad = ldexp(1.0, (int)rand_below(62u)) * (1.0 + 0.999 * fabs(rng_uniform()));
        (void)check_atan2_q29((int64_t)fmax(fmin(rad * sin(th), 4.6e18), -4.6e18),
                              (int64_t)fmax(fmin(rad * cos(th), 4.6e18), -4.6e18));
    }
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        (void)check_atan2_q29(rand_i62_log(), rand_i62_log());
    }
    printf("[fxmath] atan2_q29: max |err| = %.3e rad (%.4f LSB Q29) over %ld pairs, bound %.3e "
           "(%.3e with |x|, |y| <= 2^30)\n",
           at29_worst, at29_worst / LSB29, at29_count, TOL_ATAN2_Q29, TOL_ATAN2_Q29_SMALL);
}

static double sc29_worst = 0.0;
static long sc29_count = 0;

static void check_sincos_q29(int32_t a)
{
    int32_t s = 0;
    int32_t c = 0;
    const double ang = (double)a * LSB29;
    double err;
    rfe_q31_sincos_q29(a, &s, &c);
    err = fmax(fabs((double)s * LSB30 - sin(ang)), fabs((double)c * LSB30 - cos(ang)));
    sc29_worst = fmax(sc29_worst, err);
    ++sc29_count;
    ASSERT_LE(err, TOL_SINCOS_Q29, "sincos_q29");
    assert_true((s >= -(1 << 30)) && (s <= (1 << 30)) && (c >= -(1 << 30)) && (c <= (1 << 30)));
}

/* REQ: rfe_q31_sincos_q29 (the kinematics' and the observer's sin and cos, Q30) is within
 * TOL_SINCOS_Q29 of libm over every int32 angle: 0 (0 and 1 exactly), around each multiple of
 * pi/2 (the branches of the reduction), the ends INT32_MIN and INT32_MAX, a dense grid over the
 * whole range and random angles; the results never leave [-1, 1]. */
/* REQ-FXP-002 */
static void test_sincos_q29(void **state)
{
    /* the multiples of pi/2 inside +-4 rad */
    static const int32_t mult[] = {0, Q29_HALF_PI, Q29_PI, -Q29_HALF_PI, -Q29_PI};
    int32_t s = 1;
    int32_t c = 0;
    size_t i;
    long k;
    int d;
    (void)state;
    sc29_worst = 0.0;
    sc29_count = 0;
    rfe_q31_sincos_q29(0, &s, &c);
    assert_int_equal(s, 0);
    assert_int_equal(c, 1 << 30);
    check_sincos_q29(INT32_MIN);
    check_sincos_q29(INT32_MAX);
    check_sincos_q29(INT32_MIN + 1);
    for (i = 0; i < sizeof(mult) / sizeof(mult[0]); ++i) {
        for (d = -4; d <= 4; ++d) {
            check_sincos_q29(mult[i] + d);
        }
    }
    for (k = -(1L << 19); k < (1L << 19); ++k) { /* every 2^12-th Q29 step over all int32 */
        check_sincos_q29((int32_t)(k * 4096L + (long)rand_below(4096u)));
    }
    rng_seed(1414u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        check_sincos_q29(rand_i32());
    }
    printf("[fxmath] sincos_q29: max |err| = %.3e (%.4f LSB Q30) over %ld angles, bound %.3e\n",
           sc29_worst, sc29_worst / LSB30, sc29_count, TOL_SINCOS_Q29);
}

static double tan29_worst = 0.0; /* the largest error as a share of its bound */
static long tan29_count = 0;

static void check_tan_q29(int32_t a)
{
    const double ang = (double)a * LSB29;
    const double t = tan(ang);
    const double eps = TOL_SINCOS_Q29;
    const double tol = ldexp(1.0, -27) + eps * (1.0 + fabs(t)) / (cos(ang) - eps) + 1e-14;
    const int32_t q = rfe_q31_tan_q29(a);
    const double err = fabs((double)q * LSB26 - t);
    tan29_worst = fmax(tan29_worst, err / tol);
    ++tan29_count;
    ASSERT_LE(err, tol, "tan_q29");
    assert_int_equal(rfe_q31_tan_q29(-a), -q); /* odd, bit for bit */
}

/* REQ: rfe_q31_tan_q29 (the kinematics' tan of a slip angle, Q26) is within its bound per
 * angle, 2^-27 + eps (1 + |tan a|) / (cos a - eps), of libm over |a| <= 1.5 rad: 0 exactly, the
 * ends of the domain, a dense grid and random angles; odd bit for bit. */
/* REQ-FXP-002 */
static void test_tan_q29(void **state)
{
    long k;
    (void)state;
    tan29_worst = 0.0;
    tan29_count = 0;
    assert_int_equal(rfe_q31_tan_q29(0), 0);
    check_tan_q29(RFE_FIX_TAN_LIMIT_Q29);
    check_tan_q29(RFE_FIX_TAN_LIMIT_Q29 - 1);
    check_tan_q29(1);
    for (k = 0; k <= (1L << 18); k += LIGHT_STEP) { /* both ends checked above */
        check_tan_q29((int32_t)(((int64_t)RFE_FIX_TAN_LIMIT_Q29 * k) >> 18));
    }
    rng_seed(1515u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        check_tan_q29((int32_t)rand_below((unsigned)RFE_FIX_TAN_LIMIT_Q29 + 1u));
    }
    printf("[fxmath] tan_q29: max |err| / bound = %.3f over %ld angles\n", tan29_worst,
           tan29_count);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sat32_and_counter),
        cmocka_unit_test(test_add_sub_neg_abs),
        cmocka_unit_test(test_shifts),
        cmocka_unit_test(test_shl_rescale_mul_narrow),
        cmocka_unit_test(test_add64),
        cmocka_unit_test(test_conv),
        cmocka_unit_test(test_isqrt64),
        cmocka_unit_test(test_sqrt),
        cmocka_unit_test(test_norm),
        cmocka_unit_test(test_norm_threshold),
        cmocka_unit_test(test_div),
        cmocka_unit_test(test_atan2),
        cmocka_unit_test(test_sincos),
        cmocka_unit_test(test_tan),
        cmocka_unit_test(test_atan2_quad1),
        cmocka_unit_test(test_sin_q55),
        cmocka_unit_test(test_atan2_q29),
        cmocka_unit_test(test_sincos_q29),
        cmocka_unit_test(test_tan_q29),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
