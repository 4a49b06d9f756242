/**
 * @file test_trig_flt.c
 * @brief The float32 build's sine, cosine and tangent (rfe_sin_f32, rfe_cos_f32, rfe_tan_f32,
 *        src/numerics/trig_f32.h) against double sin, cos and tan. Built twice (the functions
 *        are float in both; RFE_SIN, RFE_COS and RFE_TAN map to them only in the float32
 *        build, to libm's in the double build, which this checks too).
 *
 * Bounds, derived (u = 2^-24, the float32 unit roundoff; |x| <= RFE_TRIG_F32_MAX):
 *  - the polynomials in float32 on r in [-pi/4, pi/4], measured once over every float there
 *    (each odd or even bit for bit, so the positive half covers both): sin_poly within
 *    7.24e-8 of sin r relative, cos_poly within 6.90e-8 of cos r absolute (9.67e-8 relative),
 *    the fits' own 3.8e-9 and 6.4e-11 in them (scripts/tools/sincos_minimax.py);
 *  - the reduction (trig_f32.h): r within u |r| + 1.03e-10 of x - k pi/2, so within
 *    u pi/4 + 1.03e-10 = 4.69e-8 absolute (|k| pi/2 - x's rounding to k moves r past pi/4 by
 *    at most 3e-5, where the polynomials' error is the same to a part in 10^3);
 *  - sin path (sin x = +-sin r): 7.24e-8 sin(pi/4) + 4.69e-8 (|d sin| <= 1) = 9.81e-8;
 *  - cos path (sin x = +-cos r): 6.90e-8 + 4.69e-8 sin(pi/4) (|d cos| <= sin(pi/4)) = 1.02e-7;
 *  - the float result against the double reference: exact (the comparison is in double).
 * So TOL_ABS = 1.03e-7 for sine and cosine over |x| <= 199. For |x| <= pi/4 (k = 0, r = x
 * exactly) the sine is within 7.24e-8 relative: TOL_SIN_REL = 7.3e-8 (a slip angle keeps its
 * relative precision down to the smallest float). The tangent, relative, over |x| <= 1.5
 * (MODEL.md's clamp keeps every slip angle below 1.5 rad): k = 0 sin_poly / cos_poly,
 * 7.24e-8 + 9.67e-8 + u (the division) = 2.29e-7; k = +-1, -cos r / sin r with |r| >= 0.0708:
 * cos r relative 9.67e-8 + tan(pi/4) 4.69e-8, sin r relative 7.24e-8 + u + 1.65e-13 / 0.0708
 * (r cot r <= 1), the division u: 3.35e-7: TOL_TAN_REL = 3.4e-7. newlib's sinf and cosf are
 * within half an ulp (<= 3e-8 here); these cost about half their instructions on the
 * Cortex-M4F (BENCHMARKS.md "What was made faster").
 */
#include "test_common.h"

#include <float.h>
#include <stdio.h>

#include "numerics/internal.h"
#include "test_rng.h"

#define TOL_ABS 1.03e-7
#define TOL_SIN_REL 7.3e-8
#define TOL_TAN_REL 3.4e-7
#define TEST_PI 3.14159265358979323846

static double worst_sin = 0.0;
static double worst_cos = 0.0;
static double worst_sin_rel = 0.0;
static double worst_tan_rel = 0.0;
static long count = 0;

/* Every bound on one argument, and the symmetries bit for bit. */
static void check(float x)
{
    const float s = rfe_sin_f32(x);
    const float c = rfe_cos_f32(x);
    const double es = fabs((double)s - sin((double)x));
    const double ec = fabs((double)c - cos((double)x));
    worst_sin = fmax(worst_sin, es);
    worst_cos = fmax(worst_cos, ec);
    ++count;
    ASSERT_LE(es, TOL_ABS, "rfe_sin_f32 absolute");
    ASSERT_LE(ec, TOL_ABS, "rfe_cos_f32 absolute");
    if ((fabsf(x) < 0.785f) && (x != 0.0f)) {
        const double rel = es / fabs(sin((double)x));
        worst_sin_rel = fmax(worst_sin_rel, rel);
        ASSERT_LE(rel, TOL_SIN_REL, "rfe_sin_f32 relative below pi/4");
    }
    if ((fabsf(x) <= 1.5f) && (x != 0.0f)) {
        const double t = tan((double)x);
        const double rel = fabs((double)rfe_tan_f32(x) - t) / fabs(t);
        worst_tan_rel = fmax(worst_tan_rel, rel);
        ASSERT_LE(rel, TOL_TAN_REL, "rfe_tan_f32 relative below 1.5 rad");
    }
    /* sine and tangent odd, cosine even, bit for bit */
    assert_true(rfe_sin_f32(-x) == -s);
    assert_true(rfe_cos_f32(-x) == c);
    assert_true(rfe_tan_f32(-x) == -rfe_tan_f32(x));
}

/* REQ: the float32 build's sine and cosine are within TOL_ABS of double sin and cos over
 * |x| <= 199 rad, the sine within TOL_SIN_REL relative below pi/4, the tangent within
 * TOL_TAN_REL relative below 1.5 rad; odd and even bit for bit; 0 exactly at 0 (cos 1);
 * beyond 199 rad, infinite or NaN, libm's answer. Points: a dense grid over the range, the
 * floats next to every multiple of pi/4 up to 199 (where the reduction changes quadrant and
 * r is smallest), small arguments down to 2^-60 and random ones. */
/* REQ-NUM-002 */
static void test_sin_cos_tan_f32(void **state)
{
    long k;
    (void)state;
    assert_true(rfe_sin_f32(0.0f) == 0.0f);
    assert_true(rfe_cos_f32(0.0f) == 1.0f);
    assert_true(rfe_tan_f32(0.0f) == 0.0f);
    assert_true(rfe_sin_f32(200.0f) == sinf(200.0f));
    assert_true(rfe_cos_f32(-1.0e6f) == cosf(-1.0e6f));
    assert_true(rfe_tan_f32(300.0f) == tanf(300.0f));
    assert_true(isnan(rfe_sin_f32(NAN)) && isnan(rfe_cos_f32(INFINITY)) &&
                isnan(rfe_tan_f32(-INFINITY)));
    for (k = 0; k <= 200000; ++k) {
        check((float)(199.0 * (double)k / 200000.0));
    }
    for (k = 0; k <= 253; ++k) { /* every multiple of pi/4 to 199 rad, and its neighbours */
        const float m = (float)((TEST_PI / 4.0) * (double)k);
        check(m);
        check(nextafterf(m, 0.0f));
        check(nextafterf(m, 200.0f));
    }
    for (k = 0; k < 60; ++k) {
        check((float)ldexp(1.0, -(int)k));
        check((float)ldexp(1.5, -(int)k));
    }
    rng_seed(2122u);
    for (k = 0; k < 100000; ++k) {
        check((float)(199.0 * fabs(rng_uniform())));
        check((float)(1.5 * fabs(rng_uniform())));
    }
    printf("[numerics] rfe_sin_f32 / rfe_cos_f32: max |err| %.3e / %.3e (bound %.2e), sine "
           "relative below pi/4 %.3e (bound %.1e), tangent relative below 1.5 rad %.3e (bound "
           "%.1e), over %ld arguments\n",
           worst_sin, worst_cos, TOL_ABS, worst_sin_rel, TOL_SIN_REL, worst_tan_rel, TOL_TAN_REL,
           count);
}

/* REQ: the build's RFE_SIN, RFE_COS and RFE_TAN are these in float32 and libm's in double. */
/* REQ-NUM-002 */
static void test_build_mapping(void **state)
{
    const rfe_real_t x = RFE_R(-2.7);
    (void)state;
#if defined(RFE_REAL_DOUBLE)
    assert_true(RFE_SIN(x) == sin(x));
    assert_true(RFE_COS(x) == cos(x));
    assert_true(RFE_TAN(x) == tan(x));
#else
    assert_true(RFE_SIN(x) == rfe_sin_f32(x));
    assert_true(RFE_COS(x) == rfe_cos_f32(x));
    assert_true(RFE_TAN(x) == rfe_tan_f32(x));
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sin_cos_tan_f32),
        cmocka_unit_test(test_build_mapping),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
