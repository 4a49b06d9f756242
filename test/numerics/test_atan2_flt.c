/**
 * @file test_atan2_flt.c
 * @brief The float32 build's atan2 (rfe_atan2_f32, src/numerics/trig_f32.h) against double
 *        atan2. Built twice (the function is float in both; RFE_ATAN2 maps to it only in the
 *        float32 build, to libm's atan2 in the double build, which this checks too).
 *
 * Bound, derived (each term the worst case over the domain):
 *  - the polynomial t P(t^2) in float32, Horner: 1.12e-7 absolute, 1.46e-7 relative to atan t
 *    (measured over 4e5 points by scripts/tools/atan_minimax.py's evaluation in float32, with
 *    the fit's own 1.4e-8 in it; a fused multiply-add, as the Cortex-M4F may contract, only
 *    removes roundings);
 *  - t = lo / hi rounded (2^-24 relative): moves atan t by <= t 2^-24 / (1 + t^2) <= 3.0e-8;
 *  - pi/2 - a above the diagonal: pi/2 in float is 4.4e-8 off, the difference rounds by
 *    <= 6.0e-8 (half an ulp below 2);
 *  - pi - a for x < 0: pi in float is 8.7e-8 off, the difference rounds by <= 1.2e-7;
 *  - the float result against the double reference: exact (the comparison is in double).
 * Sum over the worst path (above the diagonal, x < 0): 1.12e-7 + 3.0e-8 + 4.4e-8 + 6.0e-8 +
 * 8.7e-8 + 1.2e-7 = 4.5e-7 rad: TOL_ABS. Below the diagonal with x > 0 (every slip angle at
 * a moderate slip, the Magic Formula's angles) no reflection: 1.46e-7 + 6.0e-8 (the division)
 * relative, plus half an ulp of the result (6.0e-8 relative): TOL_REL = 2.7e-7.
 */
#include "test_common.h"

#include <float.h>
#include <stdio.h>

#include "numerics/internal.h"
#include "test_rng.h"

#define TOL_ABS 4.5e-7
#define TOL_REL 2.7e-7
#define TEST_PI 3.14159265358979323846

static double worst_abs = 0.0;
static double worst_rel = 0.0;
static long count = 0;

static float check(float y, float x)
{
    const float a = rfe_atan2_f32(y, x);
    const double want = atan2((double)y, (double)x);
    const double err = fabs((double)a - want);
    worst_abs = fmax(worst_abs, err);
    ++count;
    ASSERT_LE(err, TOL_ABS, "rfe_atan2_f32 absolute");
    if ((x > 0.0f) && (fabsf(y) <= x) && (want != 0.0)) {
        const double rel = err / fabs(want);
        worst_rel = fmax(worst_rel, rel);
        ASSERT_LE(rel, TOL_REL, "rfe_atan2_f32 relative");
    }
    /* odd in y, bit for bit */
    assert_true(rfe_atan2_f32(-y, x) == ((y == 0.0f) ? a : -a));
    return a;
}

/* A float of random sign with a magnitude log-uniform over [2^-60, 2^60]. */
static float rand_f_log(void)
{
    const double m = ldexp(1.0 + fabs(rng_uniform()), (int)(rng_uniform() * 60.0));
    return (float)((rng_uniform() < 0.0) ? -m : m);
}

/* REQ: the float32 build's atan2 is within TOL_ABS of double atan2 everywhere and within
 * TOL_REL relative below the diagonal for x > 0: the axes and the origin exactly (0 -> 0,
 * the negative x axis -> pi in float, the y axis -> +-pi/2 in float), odd in y bit for bit,
 * a dense angle grid around the circle at random radii from 2^-60 to 2^60, near-axis and
 * near-diagonal pairs, small angles down to 2^-60 rad and random pairs; an infinite input is
 * libm's answer. */
/* REQ-NUM-001 */
static void test_atan2_f32(void **state)
{
    long k;
    (void)state;
    assert_true(check(0.0f, 0.0f) == 0.0f);
    assert_true(check(0.0f, 3.0f) == 0.0f);
    assert_true(check(0.0f, -3.0f) == 3.14159274f);
    assert_true(check(2.0f, 0.0f) == 1.57079637f);
    assert_true(check(-2.0f, 0.0f) == -1.57079637f);
    (void)check(1.0f, 1.0f);
    (void)check(-1.0f, -1.0f);
    (void)check(FLT_MAX, FLT_MAX);
    (void)check(FLT_MIN, 1.0f);
    assert_true(rfe_atan2_f32(1.0f, INFINITY) == atan2f(1.0f, INFINITY));
    assert_true(rfe_atan2_f32(INFINITY, -INFINITY) == atan2f(INFINITY, -INFINITY));
    rng_seed(2121u);
    for (k = 0; k < 400000; ++k) {
        const double th = (2.0 * TEST_PI * (double)k) / 400000.0 - TEST_PI;
        const double r = ldexp(1.0 + fabs(rng_uniform()), (int)(rng_uniform() * 60.0));
        (void)check((float)(r * sin(th)), (float)(r * cos(th)));
    }
    for (k = 0; k < 60; ++k) { /* small angles, both sides of the axes and the diagonal */
        const float e = (float)ldexp(1.0, -(int)k);
        (void)check(e, 1.0f);
        (void)check(1.0f, e);
        (void)check(e, -1.0f);
        (void)check(1.0f + e, 1.0f);
        (void)check(1.0f, 1.0f + e);
    }
    for (k = 0; k < 200000; ++k) {
        (void)check(rand_f_log(), rand_f_log());
    }
    printf("[numerics] rfe_atan2_f32: max |err| = %.3e rad (bound %.1e), max relative below the "
           "diagonal for x > 0 = %.3e (bound %.1e) over %ld pairs\n",
           worst_abs, TOL_ABS, worst_rel, TOL_REL, count);
}

/* REQ: the build's RFE_ATAN2 is that function in float32 and libm's atan2 in double. */
/* REQ-NUM-001 */
static void test_build_mapping(void **state)
{
    const rfe_real_t y = RFE_R(0.3);
    const rfe_real_t x = RFE_R(-0.7);
    (void)state;
#if defined(RFE_REAL_DOUBLE)
    assert_true(RFE_ATAN2(y, x) == atan2(y, x));
#else
    assert_true(RFE_ATAN2(y, x) == rfe_atan2_f32(y, x));
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_atan2_f32),
        cmocka_unit_test(test_build_mapping),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
