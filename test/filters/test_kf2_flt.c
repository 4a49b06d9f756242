/**
 * @file test_kf2_flt.c
 * @brief The two-state Kalman filter against the textbook matrix formulas, and its
 *        argument checks (every error leaves the filter untouched).
 *
 * Tolerance: the expected values are the same products and sums written as full 2 x 2
 * matrix algebra (F P F^T + Q, P H^T / S, P - K S K^T) in double; the filter's fused
 * scalar forms differ by a few roundings of O(1) numbers: 1e-12 in double, 1e-5 in float
 * (a few ulps of 6e-8 on values up to ~10).
 */
#include "test_common.h"

#include <string.h>

#include "rfe/component/kf2.h"

#if defined(RFE_REAL_DOUBLE)
#define TOL 1e-12
#define BIG 1e200 /* finite, but its square overflows */
#define NEAR_MAX 1.5e308 /* finite, but twice it overflows */
#else
#define TOL 1e-5
#define BIG 1e30
#define NEAR_MAX 3e38
#endif

static void mat_mul(const double A[2][2], const double B[2][2], double C[2][2])
{
    int i, j, k;
    for (i = 0; i < 2; ++i) {
        for (j = 0; j < 2; ++j) {
            C[i][j] = 0.0;
            for (k = 0; k < 2; ++k) {
                C[i][j] += A[i][k] * B[k][j];
            }
        }
    }
}

/* REQ-OBS-001 */
static void test_predict_and_update_match_matrix_algebra(void **state)
{
    /* a fixed, well-conditioned case and a second with a negative correlation */
    const double P0[2][2][2] = {{{2.0, 0.3}, {0.3, 0.5}}, {{0.7, -0.4}, {-0.4, 1.5}}};
    const double f01s[2] = {-0.01, 0.2};
    int c;
    (void)state;
    for (c = 0; c < 2; ++c) {
        rfe_kf2_t f;
        const double f01 = f01s[c], u = 0.3, q00 = 0.01, q11 = 0.002, q01 = 0.001;
        const double F[2][2] = {{1.0, f01}, {0.0, 1.0}};
        const double Ft[2][2] = {{1.0, 0.0}, {f01, 1.0}};
        double FP[2][2], P1[2][2];
        const double x0[2] = {1.5, -0.2};
        const double h0 = 0.8, h1 = -0.3, nu = 0.25, r = 0.04;
        double S, K0, K1;
        f.x[0] = (rfe_real_t)x0[0];
        f.x[1] = (rfe_real_t)x0[1];
        f.p00 = (rfe_real_t)P0[c][0][0];
        f.p01 = (rfe_real_t)P0[c][0][1];
        f.p11 = (rfe_real_t)P0[c][1][1];
        assert_int_equal(rfe_kf2_predict(&f, (rfe_real_t)f01, (rfe_real_t)u, (rfe_real_t)q00,
                                         (rfe_real_t)q11, (rfe_real_t)q01), RFE_OK);
        mat_mul(F, P0[c], FP);
        mat_mul(FP, Ft, P1);
        P1[0][0] += q00;
        P1[0][1] += q01;
        P1[1][0] += q01;
        P1[1][1] += q11;
        assert_close(f.x[0], x0[0] + f01 * x0[1] + u, TOL, 0.0, "predict x0");
        assert_close(f.x[1], x0[1], TOL, 0.0, "predict x1");
        assert_close(f.p00, P1[0][0], TOL, 0.0, "predict p00");
        assert_close(f.p01, P1[0][1], TOL, 0.0, "predict p01");
        assert_close(f.p11, P1[1][1], TOL, 0.0, "predict p11");
        assert_int_equal(rfe_kf2_update(&f, (rfe_real_t)h0, (rfe_real_t)h1, (rfe_real_t)nu,
                                        (rfe_real_t)r), RFE_OK);
        S = h0 * (P1[0][0] * h0 + P1[0][1] * h1) + h1 * (P1[1][0] * h0 + P1[1][1] * h1) + r;
        K0 = (P1[0][0] * h0 + P1[0][1] * h1) / S;
        K1 = (P1[1][0] * h0 + P1[1][1] * h1) / S;
        assert_close(f.x[0], x0[0] + f01 * x0[1] + u + K0 * nu, TOL, 0.0, "update x0");
        assert_close(f.x[1], x0[1] + K1 * nu, TOL, 0.0, "update x1");
        assert_close(f.p00, P1[0][0] - K0 * S * K0, TOL, 0.0, "update p00");
        assert_close(f.p01, P1[0][1] - K0 * S * K1, TOL, 0.0, "update p01");
        assert_close(f.p11, P1[1][1] - K1 * S * K1, TOL, 0.0, "update p11");
    }
}

static void test_init(void **state)
{
    rfe_kf2_t f;
    (void)state;
    assert_int_equal(rfe_kf2_init(&f, 1.0f, 2.0f, 0.5f, 3.0f), RFE_OK);
    assert_close(f.x[0], 1.0, 0.0, 0.0, "x0");
    assert_close(f.x[1], 2.0, 0.0, 0.0, "x1");
    assert_close(f.p00, 0.25, 0.0, 0.0, "p00");
    assert_close(f.p01, 0.0, 0.0, 0.0, "p01");
    assert_close(f.p11, 9.0, 0.0, 0.0, "p11");
    assert_int_equal(rfe_kf2_init(NULL, 1.0f, 2.0f, 0.5f, 3.0f), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_init(&f, (rfe_real_t)NAN, 2.0f, 0.5f, 3.0f), RFE_ERR_NONFINITE);
    assert_int_equal(rfe_kf2_init(&f, 1.0f, 2.0f, -0.5f, 3.0f), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_init(&f, 1.0f, 2.0f, 0.5f, -3.0f), RFE_ERR_RANGE);
}

/* The init as its wrapper would call it from a caller compiled otherwise (another size of
 * the state, another configuration word) writes nothing; through the wrapper it is accepted. */
/* REQ-ABI-001 */
static void test_init_refuses_other_layout_or_word(void **state)
{
    rfe_kf2_t f;
    rfe_kf2_t before;
    (void)state;
    memset(&f, 0x5A, sizeof f);
    before = f;
    assert_int_equal((rfe_kf2_init)(&f, 1.0f, 2.0f, 0.5f, 3.0f, sizeof f + 8u, RFE_CONFIG_REAL),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_kf2_init)(&f, 1.0f, 2.0f, 0.5f, 3.0f, sizeof f, RFE_CONFIG_REAL ^ 3u),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_kf2_init)(&f, 1.0f, 2.0f, 0.5f, 3.0f, sizeof f,
                                    RFE_CONFIG_REAL ^ (1u << 16u)), RFE_ERR_ABI);
    assert_int_equal((rfe_kf2_init)(NULL, 1.0f, 2.0f, 0.5f, 3.0f, sizeof f, RFE_CONFIG_REAL ^ 3u),
                     RFE_ERR_ABI);
    assert_memory_equal(&f, &before, sizeof f);
    assert_int_equal(rfe_kf2_init(&f, 1.0f, 2.0f, 0.5f, 3.0f), RFE_OK);
    assert_close(f.p11, 9.0, 0.0, 0.0, "p11");
}

/* REQ-OBS-001 */
static void test_errors_leave_the_filter_untouched(void **state)
{
    rfe_kf2_t f;
    rfe_kf2_t before;
    (void)state;
    assert_int_equal(rfe_kf2_init(&f, 1.0f, 2.0f, 0.5f, 3.0f), RFE_OK);
    before = f;
    assert_int_equal(rfe_kf2_predict(NULL, 0.1f, 0.0f, 0.0f, 0.0f, 0.0f), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_predict(&f, (rfe_real_t)INFINITY, 0.0f, 0.0f, 0.0f, 0.0f),
                     RFE_ERR_NONFINITE);
    /* an overflowing result */
    assert_int_equal(rfe_kf2_predict(&f, (rfe_real_t)BIG, 0.0f, 0.0f, 0.0f, 0.0f),
                     RFE_ERR_NONFINITE);
    assert_int_equal(rfe_kf2_update(NULL, 1.0f, 0.0f, 0.0f, 1.0f), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_update(&f, 1.0f, 0.0f, (rfe_real_t)NAN, 1.0f), RFE_ERR_NONFINITE);
    assert_int_equal(rfe_kf2_update(&f, 1.0f, 0.0f, 0.0f, -1.0f), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_update(&f, 0.0f, 0.0f, 1.0f, 0.0f), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_kf2_update(&f, (rfe_real_t)BIG, 0.0f, 1.0f, 0.0f), RFE_ERR_NONFINITE);
    assert_memory_equal(&f, &before, sizeof(f));
    /* an update whose result overflows: x0 near the maximum plus a gain ~1 times it */
    assert_int_equal(rfe_kf2_init(&f, (rfe_real_t)NEAR_MAX, 0.0f, 1.0f, 1.0f), RFE_OK);
    before = f;
    assert_int_equal(rfe_kf2_update(&f, 1.0f, 0.0f, (rfe_real_t)NEAR_MAX, 1e-6f),
                     RFE_ERR_NONFINITE);
    assert_memory_equal(&f, &before, sizeof(f));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_predict_and_update_match_matrix_algebra),
        cmocka_unit_test(test_init),
        cmocka_unit_test(test_init_refuses_other_layout_or_word),
        cmocka_unit_test(test_errors_leave_the_filter_untouched),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
