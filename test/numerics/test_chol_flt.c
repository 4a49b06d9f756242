/**
 * @file test_chol_flt.c
 * @brief Unit tests of the Cholesky factorisation rfe_chol_factor (CKF baseline, MODEL.md §6).
 *        Built twice: float32 and double.
 *
 * Random SPD matrices come from the fixed-seed xorshift generator (test_rng.h, deterministic).
 * Residuals are evaluated in double from the exact rfe_real_t inputs.
 */
#include "test_common.h"

#include <string.h>

#include "rfe/component/chol.h"
#include "rfe/component/qr.h"
#include "test_guard.h"
#include "test_rng.h"

/* ---- tolerances ------------------------------------------------------------------------
 * Cholesky is backward stable: |L L^T - P|_ij <= ~(n+1) eps sqrt(P_ii P_jj); the residual
 * below is scaled that way. Seeded P = G G^T + 0.5 I (G entries in [-1, 1)). */
#if defined(RFE_REAL_DOUBLE)
/* double: (n+1) eps with n <= 8 -> 2e-15 bound (seen 3.9e-16). */
#define TOL_CHOL 2e-15
/* double: chol(A A^T) vs Tria(A), both backward stable; forward error ~ cond(A) eps with
 * seeded cond(A) < ~10 (seen 3.3e-16). */
#define TOL_VS_TRIA 5e-15
#else
/* float32: (n+1) eps with n <= 8 -> 1.1e-6 bound (seen 1.7e-7). */
#define TOL_CHOL 1.1e-6
/* float32: forward error ~ cond(A) eps, cond(A) < ~10 (seen 1.5e-7). */
#define TOL_VS_TRIA 2e-6
#endif

/* ---- buffers (guard words and padding: test_guard.h) ------------------------------------ */
#define NM ((size_t)RFE_N_MAX)
#define LD_MAX (NM + 3u)
#define BUF_N (((NM + 1u) * LD_MAX) + GUARD_N)

/* ---- helpers ---------------------------------------------------------------------------- */

/* Fills buf with guard words, then P (n x n, ld ldp) = G G^T + 0.5 I rounded to rfe_real_t
 * (exactly symmetric), padding columns PAD_VAL. G is returned (n x cols, ld cols) if wanted. */
static void make_spd(rfe_real_t *buf, size_t n, size_t ldp, rfe_real_t *G, size_t cols)
{
    static rfe_real_t g[NM * 3u * NM];
    size_t i;
    size_t j;
    size_t k;
    guard_fill(buf, BUF_N);
    for (i = 0u; i < (n * cols); ++i) {
        g[i] = (rfe_real_t)rng_uniform();
    }
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < ldp; ++j) {
            double acc = (i == j) ? 0.5 : 0.0;
            if (j >= n) {
                AT(buf, ldp, i, j) = PAD_VAL;
                continue;
            }
            for (k = 0u; k < cols; ++k) {
                acc += (double)g[(i * cols) + k] * (double)g[(j * cols) + k];
            }
            AT(buf, ldp, i, j) = (rfe_real_t)acc;
        }
    }
    if (G != NULL) {
        memcpy(G, g, n * cols * sizeof g[0]);
    }
}

/* max_ij |(L L^T - P)_ij| / sqrt(P_ii P_jj), P read from its lower triangle. */
static double chol_residual(const rfe_real_t *P, size_t ldp, const rfe_real_t *L, size_t ldl,
                            size_t n)
{
    double worst = 0.0;
    size_t i;
    size_t j;
    size_t k;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j <= i; ++j) {
            double acc = 0.0;
            for (k = 0u; k <= j; ++k) {
                acc += (double)AT(L, ldl, i, k) * (double)AT(L, ldl, j, k);
            }
            worst = fmax(worst, fabs(acc - (double)AT(P, ldp, i, j)) /
                                    sqrt((double)AT(P, ldp, i, i) * (double)AT(P, ldp, j, j)));
        }
    }
    return worst;
}

/* L lower-triangular with positive diagonal and exact zeros above it; L's padding columns
 * (pre-set to PAD_VAL) and the guard words after the buffer untouched. */
static void assert_chol_structure(const rfe_real_t *L, size_t n, size_t ldl)
{
    size_t i;
    size_t j;
    for (i = 0u; i < n; ++i) {
        assert_true(AT(L, ldl, i, i) > (rfe_real_t)0.0);
        for (j = i + 1u; j < n; ++j) {
            assert_true(AT(L, ldl, i, j) == (rfe_real_t)0.0);
        }
        for (j = n; j < ldl; ++j) {
            assert_true(AT(L, ldl, i, j) == PAD_VAL);
        }
    }
    for (i = n * ldl; i < BUF_N; ++i) {
        assert_true(L[i] == GUARD_VAL);
    }
}

/* L buffer: every element a non-zero sentinel, so "upper triangle zeroed" is a real check. */
static void prefill_l(rfe_real_t *L, size_t n, size_t ldl)
{
    size_t i;
    size_t j;
    guard_fill(L, BUF_N);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < ldl; ++j) {
            AT(L, ldl, i, j) = (j < n) ? (rfe_real_t)99.0 : PAD_VAL;
        }
    }
}

/* ---- tests ------------------------------------------------------------------------------ */

/* REQ-CHOL-001 */
static void test_rfe_chol_factor_random_spd(void **state)
{
    static rfe_real_t P[BUF_N];
    static rfe_real_t Pref[BUF_N];
    static rfe_real_t L[BUF_N];
    size_t n;
    size_t ldp;
    size_t ldl;
    int rep;
    (void)state;
    rng_seed(101u);
    for (n = 1u; n <= NM; ++n) {
        for (ldp = n; ldp <= (n + 3u); ldp += 3u) {
            for (ldl = n; ldl <= (n + 2u); ldl += 2u) {
                for (rep = 0; rep < 4; ++rep) {
                    make_spd(P, n, ldp, NULL, n);
                    memcpy(Pref, P, sizeof P);
                    prefill_l(L, n, ldl);
                    assert_int_equal(rfe_chol_factor(P, n, ldp, L, ldl), RFE_OK);
                    assert_memory_equal(P, Pref, sizeof P); /* input is const */
                    assert_chol_structure(L, n, ldl);
                    ASSERT_LE(chol_residual(P, ldp, L, ldl, n), TOL_CHOL, "L L^T - P");
                }
            }
        }
    }
}

/* Exact cases: diagonal P = diag(k^2) gives diag(k); P = [4 2; 2 10] gives [2 0; 1 3]. */
/* REQ-CHOL-001 */
static void test_rfe_chol_factor_exact_small(void **state)
{
    static rfe_real_t L[BUF_N];
    static const rfe_real_t P2[4] = {4, 2, 2, 10};
    rfe_real_t D[NM * NM];
    size_t i;
    size_t j;
    (void)state;
    prefill_l(L, 2u, 2u);
    assert_int_equal(rfe_chol_factor(P2, 2u, 2u, L, 2u), RFE_OK);
    assert_true(L[0] == (rfe_real_t)2.0);
    assert_true(L[1] == (rfe_real_t)0.0);
    assert_true(L[2] == (rfe_real_t)1.0);
    assert_true(L[3] == (rfe_real_t)3.0);
    for (i = 0u; i < NM; ++i) {
        for (j = 0u; j < NM; ++j) {
            D[(i * NM) + j] = (i == j) ? (rfe_real_t)((i + 1u) * (i + 1u)) : (rfe_real_t)0.0;
        }
    }
    prefill_l(L, NM, NM);
    assert_int_equal(rfe_chol_factor(D, NM, NM, L, NM), RFE_OK);
    for (i = 0u; i < NM; ++i) {
        for (j = 0u; j < NM; ++j) {
            assert_true(AT(L, NM, i, j) ==
                        ((i == j) ? (rfe_real_t)(i + 1u) : (rfe_real_t)0.0));
        }
    }
}

/* Only the lower triangle of P is read: garbage (even NaN) in the strict upper triangle
 * changes nothing. */
/* REQ-CHOL-001 */
static void test_rfe_chol_factor_reads_lower_triangle_only(void **state)
{
    static rfe_real_t P[BUF_N];
    static rfe_real_t L[BUF_N];
    static rfe_real_t Lref[BUF_N];
    const size_t n = 6u;
    size_t i;
    size_t j;
    (void)state;
    rng_seed(102u);
    make_spd(P, n, n, NULL, n);
    prefill_l(Lref, n, n);
    assert_int_equal(rfe_chol_factor(P, n, n, Lref, n), RFE_OK);
    for (i = 0u; i < n; ++i) {
        for (j = i + 1u; j < n; ++j) {
            AT(P, n, i, j) = ((j % 2u) == 0u) ? (rfe_real_t)NAN : (rfe_real_t)-1e6;
        }
    }
    prefill_l(L, n, n);
    assert_int_equal(rfe_chol_factor(P, n, n, L, n), RFE_OK);
    assert_memory_equal(L, Lref, sizeof L);
}

/* chol(A A^T) equals Tria(A) (both are the unique lower factor with positive diagonal). */
/* REQ-CHOL-001 */
static void test_rfe_chol_factor_matches_tria(void **state)
{
    static rfe_real_t P[BUF_N];
    static rfe_real_t L[BUF_N];
    static rfe_real_t G[NM * 3u * NM];
    size_t n;
    size_t i;
    size_t j;
    (void)state;
    rng_seed(103u);
    for (n = 1u; n <= NM; ++n) {
        const size_t cols = 2u * n;
        make_spd(P, n, n, G, cols);
        /* remove the + 0.5 I so that P = G G^T exactly as Tria sees it (up to rounding) */
        for (i = 0u; i < n; ++i) {
            double acc = 0.0;
            for (j = 0u; j < cols; ++j) {
                acc += (double)G[(i * cols) + j] * (double)G[(i * cols) + j];
            }
            AT(P, n, i, i) = (rfe_real_t)acc;
        }
        prefill_l(L, n, n);
        assert_int_equal(rfe_chol_factor(P, n, n, L, n), RFE_OK);
        assert_int_equal(rfe_qr_tria(G, n, cols, cols), RFE_OK);
        for (i = 0u; i < n; ++i) {
            for (j = 0u; j <= i; ++j) {
                ASSERT_LE(fabs((double)AT(L, n, i, j) - (double)AT(G, cols, i, j)) /
                              sqrt((double)AT(P, n, i, i)),
                          TOL_VS_TRIA, "chol(A A^T) - Tria(A)");
            }
        }
    }
}

/* Not positive definite: the first failing pivot is not > 0. */
/* REQ-CHOL-002 */
static void test_rfe_chol_factor_not_positive_definite(void **state)
{
    static rfe_real_t L[BUF_N];
    /* indefinite (eigenvalues 3, -1) */
    static const rfe_real_t indef[4] = {1, 2, 2, 1};
    /* singular, exactly: pivot 2 is 1 - 1 = 0 */
    static const rfe_real_t sing[4] = {1, 1, 1, 1};
    /* negative diagonal first / later */
    static const rfe_real_t negd0[4] = {-1, 0, 0, 1};
    static const rfe_real_t negd1[9] = {4, 0, 0, 0, 9, 0, 0, 0, -0.25};
    /* zero matrix */
    static const rfe_real_t zero[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
    /* 3 x 3 indefinite with positive diagonal: [2 1 2; 1 2 1; 2 1 2] is singular,
     * [1 0.9 0.9; 0.9 1 -0.9; 0.9 -0.9 1] is indefinite (det < 0) */
    static const rfe_real_t indef3[9] = {1, 0.9f, 0.9f, 0.9f, 1, -0.9f, 0.9f, -0.9f, 1};
    /* rank 1 of size 8: pivot 2 is exactly 0 */
    static rfe_real_t ones[NM * NM];
    size_t i;
    (void)state;
    for (i = 0u; i < (NM * NM); ++i) {
        ones[i] = (rfe_real_t)1.0;
    }
    prefill_l(L, 2u, 2u);
    assert_int_equal(rfe_chol_factor(indef, 2u, 2u, L, 2u), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor(sing, 2u, 2u, L, 2u), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor(negd0, 2u, 2u, L, 2u), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor(negd1, 3u, 3u, L, 3u), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor(zero, 3u, 3u, L, 3u), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor(indef3, 3u, 3u, L, 3u), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor(ones, NM, NM, L, NM), RFE_ERR_NOT_POSITIVE_DEFINITE);
    /* the 1 x 1 cases */
    assert_int_equal(rfe_chol_factor(zero, 1u, 1u, L, 1u), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor(negd0, 1u, 1u, L, 1u), RFE_ERR_NOT_POSITIVE_DEFINITE);
    /* guard words after L never written, even on failure */
    for (i = NM * NM; i < BUF_N; ++i) {
        assert_true(L[i] == GUARD_VAL);
    }
}

/* Random SPD with one diagonal entry pushed below the Schur complement: indefinite. */
/* REQ-CHOL-002 */
static void test_rfe_chol_factor_random_indefinite(void **state)
{
    static rfe_real_t P[BUF_N];
    static rfe_real_t L[BUF_N];
    size_t n;
    size_t k;
    (void)state;
    rng_seed(104u);
    for (n = 2u; n <= NM; ++n) {
        for (k = 0u; k < n; ++k) {
            make_spd(P, n, n, NULL, n);
            AT(P, n, k, k) = (rfe_real_t)-0.1; /* P_kk < 0: never PD */
            prefill_l(L, n, n);
            assert_int_equal(rfe_chol_factor(P, n, n, L, n),
                             RFE_ERR_NOT_POSITIVE_DEFINITE);
        }
    }
}

/* REQ-CHOL-003 */
static void test_rfe_chol_factor_nonfinite(void **state)
{
    static rfe_real_t P[BUF_N];
    static rfe_real_t L[BUF_N];
    const size_t n = 5u;
    const rfe_real_t bad[3] = {(rfe_real_t)NAN, (rfe_real_t)INFINITY, (rfe_real_t)-INFINITY};
    /* diagonal first, off-diagonal interior, last element of the lower triangle */
    static const size_t pos[4][2] = {{0u, 0u}, {3u, 1u}, {4u, 4u}, {4u, 0u}};
    size_t b;
    size_t p;
    (void)state;
    rng_seed(105u);
    for (b = 0u; b < 3u; ++b) {
        for (p = 0u; p < 4u; ++p) {
            make_spd(P, n, n, NULL, n);
            AT(P, n, pos[p][0], pos[p][1]) = bad[b];
            prefill_l(L, n, n);
            assert_int_equal(rfe_chol_factor(P, n, n, L, n), RFE_ERR_NONFINITE);
            assert_true(L[n * n] == GUARD_VAL);
        }
    }
}

/* REQ-CHOL-003 */
static void test_rfe_chol_factor_size_errors(void **state)
{
    static rfe_real_t P[BUF_N];
    static rfe_real_t L[BUF_N];
    static rfe_real_t Lref[BUF_N];
    /* n, ldp, ldl */
    static const size_t cases[][3] = {
        {0u, 4u, 4u},               /* n 0 */
        {NM + 1u, NM + 1u, NM + 1u}, /* n > RFE_N_MAX */
        {4u, 3u, 4u},               /* ldp < n */
        {4u, 4u, 3u},               /* ldl < n */
    };
    size_t c;
    (void)state;
    rng_seed(106u);
    make_spd(P, NM, LD_MAX, NULL, NM);
    prefill_l(L, NM, LD_MAX);
    memcpy(Lref, L, sizeof L);
    for (c = 0u; c < (sizeof cases / sizeof cases[0]); ++c) {
        assert_int_equal(rfe_chol_factor(P, cases[c][0], cases[c][1], L, cases[c][2]),
                         RFE_ERR_SIZE);
        assert_memory_equal(L, Lref, sizeof L);
    }
}

/* REQ-CHOL-003 */
static void test_rfe_chol_factor_null(void **state)
{
    static rfe_real_t P[BUF_N];
    static rfe_real_t L[BUF_N];
    (void)state;
    rng_seed(107u);
    make_spd(P, 3u, 3u, NULL, 3u);
    assert_int_equal(rfe_chol_factor(NULL, 3u, 3u, L, 3u), RFE_ERR_NULL);
    assert_int_equal(rfe_chol_factor(P, 3u, 3u, NULL, 3u), RFE_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_chol_factor_random_spd),
        cmocka_unit_test(test_rfe_chol_factor_exact_small),
        cmocka_unit_test(test_rfe_chol_factor_reads_lower_triangle_only),
        cmocka_unit_test(test_rfe_chol_factor_matches_tria),
        cmocka_unit_test(test_rfe_chol_factor_not_positive_definite),
        cmocka_unit_test(test_rfe_chol_factor_random_indefinite),
        cmocka_unit_test(test_rfe_chol_factor_nonfinite),
        cmocka_unit_test(test_rfe_chol_factor_size_errors),
        cmocka_unit_test(test_rfe_chol_factor_null),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
