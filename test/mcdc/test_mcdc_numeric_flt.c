/**
 * @file test_mcdc_numeric_flt.c
 * @brief Coverage of numeric corners the module tests do not reach (make coverage,
 *        docs/COVERAGE_JUSTIFICATION.md): Tria() on rows of subnormal numbers, where the
 *        power-of-two row scaling cannot be a single normal factor 2^e and is applied
 *        element by element (ldexp).
 *
 * Exact expectations, no tolerance: a row [3, 4, 0]·2^m (2^m the smallest subnormal of the
 * build's type) has the norm 5·2^m, which is representable; Tria() scales the row by a power
 * of two (exact), forms the norm of [3, 4, 0]·2^k exactly (√25 = 5) and scales back
 * (exact), so S = [5·2^m] bit for bit, and the tail of the row is zeroed. The same at the
 * top of the range, [3, 4, 0]·2^M with 5·2^M still finite, where the scaling factor 2^e is
 * below the normal range.
 *
 * And the CKF's time update when only the covariance overflows: a finite P0 near the top of
 * the range, an identity process: the propagated mean stays finite while the cubature
 * points' second moment overflows; the step must fail with RFE_ERR_NONFINITE and change
 * nothing (compared with memcmp).
 */
#include "test_common.h"

#include <float.h>
#include <string.h>

#include "rfe/component/ckf.h"
#include "rfe/component/qr.h"

#if defined(RFE_REAL_DOUBLE)
#define TRUE_MIN_EXP (DBL_MIN_EXP - DBL_MANT_DIG) /* 2^-1074 */
#define TOP_EXP (DBL_MAX_EXP - 3)                 /* 5 * 2^1021 < DBL_MAX */
#define HUGE_VAR (DBL_MAX / 4)
#define HUGE_Q (DBL_MAX * 0.9)
#else
#define TRUE_MIN_EXP (FLT_MIN_EXP - FLT_MANT_DIG) /* 2^-149 */
#define TOP_EXP (FLT_MAX_EXP - 3)                 /* 5 * 2^125 < FLT_MAX */
#define HUGE_VAR (FLT_MAX / 4)
#define HUGE_Q (FLT_MAX * 0.9f)
#endif

/* REQ-QR-002 */
static void test_mcdc_tria_subnormal_row_exact(void **state)
{
    const rfe_real_t tm = (rfe_real_t)ldexp(1.0, TRUE_MIN_EXP);
    rfe_real_t A[3];
    (void)state;
    assert_true(tm > (rfe_real_t)0.0); /* the smallest subnormal exists (no flush to zero) */
    A[0] = (rfe_real_t)3.0 * tm;
    A[1] = (rfe_real_t)4.0 * tm;
    A[2] = (rfe_real_t)0.0;
    assert_int_equal(rfe_qr_tria(A, 1u, 3u, 3u), RFE_OK);
    assert_true(A[0] == (rfe_real_t)5.0 * tm);
    assert_true((A[1] == (rfe_real_t)0.0) && (A[2] == (rfe_real_t)0.0));
    /* the same with the signs flipped and the order changed: S keeps a non-negative diagonal */
    A[0] = (rfe_real_t)-4.0 * tm;
    A[1] = (rfe_real_t)0.0;
    A[2] = (rfe_real_t)3.0 * tm;
    assert_int_equal(rfe_qr_tria(A, 1u, 3u, 3u), RFE_OK);
    assert_true(A[0] == (rfe_real_t)5.0 * tm);
    assert_true((A[1] == (rfe_real_t)0.0) && (A[2] == (rfe_real_t)0.0));
}

/* REQ-QR-002 */
static void test_mcdc_tria_subnormal_and_normal_rows(void **state)
{
    /* row 0 normal, row 1 subnormal and parallel to row 0: S(1,1) must be 0 and S(1,0) the
     * projection |row 1|, with the factor exactly as for normal numbers scaled by 2^m (the
     * rows [3, 4, 0] and [3, 4, 0]·2^m·2: S = [[5, 0], [10·2^m, 0]]) */
    const rfe_real_t tm = (rfe_real_t)ldexp(1.0, TRUE_MIN_EXP);
    rfe_real_t A[6] = {3, 4, 0, 0, 0, 0};
    (void)state;
    A[3] = (rfe_real_t)6.0 * tm;
    A[4] = (rfe_real_t)8.0 * tm;
    assert_int_equal(rfe_qr_tria(A, 2u, 3u, 3u), RFE_OK);
    assert_true(A[0] == (rfe_real_t)5.0);
    assert_true(A[3] == (rfe_real_t)10.0 * tm);
    assert_true(A[4] == (rfe_real_t)0.0);
    assert_true((A[1] == (rfe_real_t)0.0) && (A[2] == (rfe_real_t)0.0) && (A[5] == (rfe_real_t)0.0));
}

/* REQ-QR-002 */
static void test_mcdc_tria_huge_row_exact(void **state)
{
    const rfe_real_t tp = (rfe_real_t)ldexp(1.0, TOP_EXP);
    rfe_real_t A[3];
    (void)state;
    A[0] = (rfe_real_t)3.0 * tp;
    A[1] = (rfe_real_t)-4.0 * tp;
    A[2] = (rfe_real_t)0.0;
    assert_int_equal(rfe_qr_tria(A, 1u, 3u, 3u), RFE_OK);
    assert_true(A[0] == (rfe_real_t)5.0 * tp);
    assert_true((A[1] == (rfe_real_t)0.0) && (A[2] == (rfe_real_t)0.0));
}

static rfe_status_t identity_process(void *ctx, const rfe_real_t *x, rfe_real_t *x_next, size_t n)
{
    size_t i;
    (void)ctx;
    for (i = 0u; i < n; ++i) {
        x_next[i] = x[i];
    }
    return RFE_OK;
}

/* REQ-CKF-003 */
static void test_mcdc_ckf_predict_covariance_overflow_untouched(void **state)
{
    /* n = 2: the points are x ± sqrt(2) S e_i with S S^T = P0 = (MAX/4) I (finite); their
     * second moment is P0 again (finite), but adding Q = 0.9 MAX I overflows P- while the
     * mean x- = x (identity process, equal weights) stays finite */
    static rfe_ckf_t f, before;
    const rfe_real_t x0[2] = {(rfe_real_t)0.5, (rfe_real_t)0.5};
    const rfe_real_t P0[4] = {(rfe_real_t)HUGE_VAR, 0, 0, (rfe_real_t)HUGE_VAR};
    const rfe_real_t Q[4] = {(rfe_real_t)HUGE_Q, 0, 0, (rfe_real_t)HUGE_Q};
    const rfe_real_t R[1] = {(rfe_real_t)1.0};
    (void)state;
    assert_int_equal(rfe_ckf_init(&f, 2u, 1u, x0, P0, Q, R), RFE_OK);
    memcpy(&before, &f, sizeof f);
    assert_int_equal(rfe_ckf_predict(&f, identity_process, NULL), RFE_ERR_NONFINITE);
    /* the state (not the scratch, whose contents are meaningless between calls) */
    assert_memory_equal(f.x, before.x, sizeof f.x);
    assert_memory_equal(f.P, before.P, sizeof f.P);
    assert_int_equal(f.magic, before.magic);
    /* and it still works: a sane covariance predicts */
    {
        const rfe_real_t P1[4] = {1, 0, 0, 1}, Q1[4] = {(rfe_real_t)0.01, 0, 0, (rfe_real_t)0.01};
        assert_int_equal(rfe_ckf_init(&f, 2u, 1u, x0, P1, Q1, R), RFE_OK);
        assert_int_equal(rfe_ckf_predict(&f, identity_process, NULL), RFE_OK);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mcdc_tria_subnormal_row_exact),
        cmocka_unit_test(test_mcdc_tria_subnormal_and_normal_rows),
        cmocka_unit_test(test_mcdc_tria_huge_row_exact),
        cmocka_unit_test(test_mcdc_ckf_predict_covariance_overflow_untouched),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
