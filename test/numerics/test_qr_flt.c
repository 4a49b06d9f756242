/**
 * @file test_qr_flt.c
 * @brief Unit tests of Tria() (rfe_qr_tria) and the triangular solves (rfe_qr_solve_lower,
 *        rfe_qr_solve_lower_t), MODEL.md §6. Built twice: float32 and double.
 *
 * Every random input comes from the fixed-seed xorshift generator (test_rng.h), so a run
 * is deterministic. Products and residuals are evaluated in double from the exact
 * rfe_real_t inputs, so the only error measured is the library's.
 */
#include "test_common.h"

#include <stdint.h>
#include <string.h>

#include "rfe/component/qr.h"
#include "test_guard.h"
#include "test_rng.h"

/* ---- tolerances ------------------------------------------------------------------------
 * Residuals are row-scaled: |(S S^T - A A^T)_ij| / (|a_i| |a_j|), because Householder
 * triangularisation from the right is backward stable row by row (each row of A picks up
 * an error of a few eps * |a_i| per reflection). Measured worst cases on the seeded inputs
 * are quoted; each bound keeps a margin of at least 5x over them. */
#if defined(RFE_REAL_DOUBLE)
/* double: <= 10 reflections (RFE_TRIA_ROWS_MAX) of rows <= 30 long, eps 2.2e-16 * ~10 *
 * sqrt(30) ~ 1.2e-14 bound (seen 1.3e-15 at 8 x 24). */
#define TOL_TRIA 1.2e-14
/* double: Q^T = S^-1 A, error ~ cond(S) * eps; seeded cond(S) < ~50 (seen 4.9e-15). */
#define TOL_ORTH 5e-14
/* double: substitution with n <= 8, cond(L) < 30 by construction (seen 4.4e-16). */
#define TOL_SOLVE 5e-15
/* double: a dependent row keeps a remainder of a few eps * |a_k| (seen 2.6e-16). */
#define TOL_RANKDEF 5e-15
#else
/* float32: eps 1.2e-7 * ~10 reflections * sqrt(30) ~ 6.6e-6 bound (seen 5.6e-7 at 8 x 24). */
#define TOL_TRIA 6.6e-6
/* float32: cond(S) < ~50 on the seeded shapes (cols = rows + 1 is the worst) * eps * a few
 * (seen 7.6e-6). */
#define TOL_ORTH 5e-5
/* float32: substitution with n <= 8, cond(L) < 30 * eps (seen 2.0e-7). */
#define TOL_SOLVE 2e-6
/* float32: dependent-row remainder, a few eps * sqrt(cols) (seen 7.2e-8). */
#define TOL_RANKDEF 1e-6
#endif

/* ---- buffers (guard words and padding: test_guard.h) ------------------------------------ */
#define NM ((size_t)RFE_N_MAX)            /* the solves' row bound */
#define TR ((size_t)RFE_TRIA_ROWS_MAX)    /* Tria's row bound (10: the tyre identifier's SCKF) */
#define TC ((size_t)RFE_TRIA_COLS_LIMIT)  /* Tria's column bound (30) */
#define LD_MAX (TC + 5u)                   /* widest leading dimension used */
#define BUF_N (((TR + 1u) * LD_MAX) + GUARD_N)

/* ---- helpers ---------------------------------------------------------------------------- */

/* Sets every element of buf[0..BUF_N) to the guard value, then A (rows x cols, ld lda)
 * to random values scaled per row; the columns cols..lda-1 are padding (PAD_VAL). */
static void fill_matrix(rfe_real_t *buf, size_t rows, size_t cols, size_t lda)
{
    size_t i;
    size_t j;
    guard_fill(buf, BUF_N);
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j < lda; ++j) {
            AT(buf, lda, i, j) = (j < cols) ? (rfe_real_t)rng_uniform() : PAD_VAL;
        }
    }
}

/* Copy of A in double (exact), ld cols. */
static void to_double(const rfe_real_t *A, size_t rows, size_t cols, size_t lda, double *out)
{
    size_t i;
    size_t j;
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j < cols; ++j) {
            out[(i * cols) + j] = (double)AT(A, lda, i, j);
        }
    }
}

static double row_norm(const double *A0, size_t cols, size_t i)
{
    double ss = 0.0;
    size_t j;
    for (j = 0u; j < cols; ++j) {
        ss += A0[(i * cols) + j] * A0[(i * cols) + j];
    }
    return sqrt(ss);
}

/* Structure of the Tria output: [S 0] with S lower-triangular (exact zeros right of the
 * diagonal), diag(S) >= 0, padding columns and the guard words after the buffer untouched. */
static void assert_tria_structure(const rfe_real_t *buf, size_t rows, size_t cols, size_t lda)
{
    size_t i;
    size_t j;
    for (i = 0u; i < rows; ++i) {
        assert_true(AT(buf, lda, i, i) >= (rfe_real_t)0.0);
        for (j = i + 1u; j < cols; ++j) {
            assert_true(AT(buf, lda, i, j) == (rfe_real_t)0.0);
        }
        for (j = cols; j < lda; ++j) {
            assert_true(AT(buf, lda, i, j) == PAD_VAL);
        }
    }
    for (i = rows * lda; i < BUF_N; ++i) {
        assert_true(buf[i] == GUARD_VAL);
    }
}

/* max_ij |(S S^T - A0 A0^T)_ij| / (|a_i| |a_j|); a zero row must map to an exactly zero row. */
static double tria_residual(const double *A0, const rfe_real_t *S, size_t lds, size_t rows,
                            size_t cols)
{
    double worst = 0.0;
    size_t i;
    size_t j;
    size_t k;
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j < rows; ++j) {
            double aa = 0.0;
            double ss = 0.0;
            double scale = row_norm(A0, cols, i) * row_norm(A0, cols, j);
            for (k = 0u; k < cols; ++k) {
                aa += A0[(i * cols) + k] * A0[(j * cols) + k];
            }
            for (k = 0u; k < rows; ++k) {
                ss += (double)AT(S, lds, i, k) * (double)AT(S, lds, j, k);
            }
            if (scale == 0.0) {
                scale = 1.0;
                if (ss != 0.0) {
                    worst = INFINITY; /* zero row must give an exactly zero S row */
                }
            }
            worst = fmax(worst, fabs(ss - aa) / scale);
        }
    }
    return worst;
}

/* max |Q^T Q - I| with Q^T = S^-1 A0 (rows x cols) from rfe_qr_solve_lower. */
static double orth_residual(const double *A0, const rfe_real_t *S, size_t lds, size_t rows,
                            size_t cols)
{
    static rfe_real_t qt[NM * LD_MAX];
    double worst = 0.0;
    size_t i;
    size_t j;
    size_t k;
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j < cols; ++j) {
            qt[(i * cols) + j] = (rfe_real_t)A0[(i * cols) + j];
        }
    }
    assert_int_equal(rfe_qr_solve_lower(S, rows, lds, qt, cols, cols), RFE_OK);
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j < rows; ++j) {
            double acc = 0.0;
            for (k = 0u; k < cols; ++k) {
                acc += (double)qt[(i * cols) + k] * (double)qt[(j * cols) + k];
            }
            worst = fmax(worst, fabs(acc - ((i == j) ? 1.0 : 0.0)));
        }
    }
    return worst;
}

/* Runs Tria on buf (rows x cols, ld lda), checks status, structure and S S^T = A A^T. */
static void check_tria(rfe_real_t *buf, size_t rows, size_t cols, size_t lda, double *A0)
{
    to_double(buf, rows, cols, lda, A0);
    assert_int_equal(rfe_qr_tria(buf, rows, cols, lda), RFE_OK);
    assert_tria_structure(buf, rows, cols, lda);
    ASSERT_LE(tria_residual(A0, buf, lda, rows, cols), TOL_TRIA, "S S^T - A A^T (row-scaled)");
}

/* ---- Tria: random full-rank inputs ------------------------------------------------------ */

/* REQ-QR-001 */
static void test_rfe_qr_tria_random_all_shapes(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[TR * LD_MAX];
    size_t rows;
    size_t cols;
    size_t pad;
    int rep;
    (void)state;
    rng_seed(1u);
    /* every shape up to Tria's bounds: the tyre identifier's SCKF reduces 10 x 30 and 10 x 22 */
    for (rows = 1u; rows <= TR; ++rows) {
        for (cols = rows; cols <= (3u * rows); ++cols) {
            for (pad = 0u; pad <= 3u; pad += 3u) {
                for (rep = 0; rep < 3; ++rep) {
                    fill_matrix(buf, rows, cols, cols + pad);
                    check_tria(buf, rows, cols, cols + pad, A0);
                }
            }
        }
    }
}

/* The shapes the filter uses (n = 4, m = 3): predict 4 x 12 = [Xc | S_Q], update 4 x 11 =
 * [Xc - K Zc | K S_R], innovation 3 x 11 = [Zc | S_R], all at ld RFE_TRIA_COLS_MAX. */
/* REQ-QR-001 */
static void test_rfe_qr_tria_filter_shapes(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    static const size_t shapes[3][2] = {{4u, 12u}, {4u, 11u}, {3u, 11u}};
    size_t s;
    size_t i;
    size_t j;
    int rep;
    (void)state;
    rng_seed(2u);
    for (s = 0u; s < 3u; ++s) {
        const size_t rows = shapes[s][0];
        const size_t cols = shapes[s][1];
        for (rep = 0; rep < 20; ++rep) {
            fill_matrix(buf, rows, cols, TC);
            /* last block lower-triangular like S_Q / S_R, spread scales like a filter */
            for (i = 0u; i < rows; ++i) {
                for (j = 0u; j < cols; ++j) {
                    if ((j >= (cols - rows)) && ((j - (cols - rows)) > i)) {
                        AT(buf, TC, i, j) = (rfe_real_t)0.0;
                    } else if (j >= (cols - rows)) {
                        AT(buf, TC, i, j) *= (rfe_real_t)0.01;
                    }
                }
            }
            check_tria(buf, rows, cols, TC, A0);
            ASSERT_LE(orth_residual(A0, buf, TC, rows, cols), TOL_ORTH, "Q^T Q - I (filter)");
        }
    }
}

/* issue 21: rfe_qr_tria reduces the filter's shapes at ld RFE_TRIA_COLS_MAX (4 x 8, 3 x 11,
 * 4 x 11) in copies unrolled for their constant sizes; the same matrix at another
 * leading dimension (ld = cols) takes the run-time reduction. Both perform the same
 * operations in the same order (the builds do not contract a*b + c into a fused multiply-add:
 * -std=c99 sets -ffp-contract=off), so they agree bit for bit; the bound below allows, should
 * a compiler fuse differently in the two copies, one rounding of eps |a_i| per multiply-add
 * of each of the <= rows reflections over <= cols elements of a row:
 * rows cols eps |a_i| <= 4 * 11 * eps |a_i| (about 5.2e-6 |a_i| in float32, 9.8e-15 in
 * double). Inputs as the filter's: a lower-triangular last block at 0.01 the scale, a row
 * scaled by 2^-40 in some repetitions so the power-of-two row scaling runs too. */
/* REQ-QR-001 */
static void test_rfe_qr_tria_fixed_shapes_match_runtime(void **state)
{
    static rfe_real_t fixed[BUF_N];
    static rfe_real_t runtime[BUF_N];
    static const size_t shapes[3][2] = {{4u, 8u}, {3u, 11u}, {4u, 11u}};
    const size_t ld = (size_t)RFE_TRIA_COLS_MAX;
    const double eps = (sizeof(rfe_real_t) == sizeof(float)) ? 1.1920929e-7 : 2.220446e-16;
    size_t s;
    size_t i;
    size_t j;
    int rep;
    (void)state;
    rng_seed(21u);
    for (s = 0u; s < 3u; ++s) {
        const size_t rows = shapes[s][0];
        const size_t cols = shapes[s][1];
        for (rep = 0; rep < 20; ++rep) {
            fill_matrix(fixed, rows, cols, ld);
            for (i = 0u; i < rows; ++i) {
                for (j = cols - rows; j < cols; ++j) {
                    AT(fixed, ld, i, j) = ((j - (cols - rows)) > i)
                                              ? (rfe_real_t)0.0
                                              : (rfe_real_t)(AT(fixed, ld, i, j) * 0.01);
                }
                if (((rep % 5) == 4) && (i == 1u)) {
                    for (j = 0u; j < cols; ++j) {
                        AT(fixed, ld, i, j) = (rfe_real_t)ldexp((double)AT(fixed, ld, i, j), -40);
                    }
                }
            }
            guard_fill(runtime, BUF_N);
            for (i = 0u; i < rows; ++i) {
                for (j = 0u; j < cols; ++j) {
                    AT(runtime, cols, i, j) = AT(fixed, ld, i, j);
                }
            }
            assert_int_equal(rfe_qr_tria(fixed, rows, cols, ld), RFE_OK);
            assert_int_equal(rfe_qr_tria(runtime, rows, cols, cols), RFE_OK);
            assert_tria_structure(fixed, rows, cols, ld);
            for (i = 0u; i < rows; ++i) {
                double norm = 0.0;
                for (j = 0u; j <= i; ++j) {
                    norm += (double)AT(runtime, cols, i, j) * (double)AT(runtime, cols, i, j);
                }
                for (j = 0u; j <= i; ++j) {
                    ASSERT_LE(fabs((double)AT(fixed, ld, i, j) - (double)AT(runtime, cols, i, j)),
                              (double)(rows * cols) * eps * sqrt(norm),
                              "fixed-shape Tria vs run-time Tria");
                }
            }
        }
    }
}

/* rfe_qr_tria_lt and rfe_qr_tria_pair (the twins of the Q31 ones) give rfe_qr_tria's bits on
 * [B, L] (L lower-triangular) and [L1, L2] of the filters' shapes, and its errors. */
/* REQ-QR-001 */
static void test_rfe_qr_tria_lt_is_tria(void **state)
{
    static rfe_real_t a[BUF_N];
    static rfe_real_t b[BUF_N];
    static const size_t shapes[3][2] = {{4u, 8u}, {3u, 11u}, {2u, 5u}};
    const size_t ld = (size_t)RFE_TRIA_COLS_MAX;
    size_t s;
    size_t i;
    size_t j;
    (void)state;
    rng_seed(22u);
    for (s = 0u; s < 3u; ++s) {
        const size_t rows = shapes[s][0];
        const size_t cols = shapes[s][1];
        fill_matrix(a, rows, cols, ld);
        for (i = 0u; i < rows; ++i) {
            for (j = (cols - rows) + i + 1u; j < cols; ++j) {
                AT(a, ld, i, j) = (rfe_real_t)0.0;
            }
        }
        memcpy(b, a, sizeof b);
        assert_int_equal(rfe_qr_tria_lt(a, rows, cols, ld), RFE_OK);
        assert_int_equal(rfe_qr_tria(b, rows, cols, ld), RFE_OK);
        assert_memory_equal(a, b, sizeof a);
    }
    assert_int_equal(rfe_qr_tria_lt(NULL, 2u, 4u, 4u), RFE_ERR_NULL);
    assert_int_equal(rfe_qr_tria_lt(a, 3u, 2u, 4u), RFE_ERR_SIZE);
    /* rfe_qr_tria_pair on [L1, L2], both lower-triangular: n = 4 is its unrolled copy with
     * the zeros of both blocks skipped, the others rfe_qr_tria's; the same bits either way */
    for (s = 1u; s <= 4u; ++s) {
        fill_matrix(a, s, 2u * s, ld);
        for (i = 0u; i < s; ++i) {
            for (j = i + 1u; j < s; ++j) {
                AT(a, ld, i, j) = (rfe_real_t)0.0;
                AT(a, ld, i, s + j) = (rfe_real_t)0.0;
            }
        }
        memcpy(b, a, sizeof b);
        assert_int_equal(rfe_qr_tria_pair(a, s, ld), RFE_OK);
        assert_int_equal(rfe_qr_tria(b, s, 2u * s, ld), RFE_OK);
        assert_memory_equal(a, b, sizeof a);
    }
    assert_int_equal(rfe_qr_tria_pair(NULL, 2u, ld), RFE_ERR_NULL);
    assert_int_equal(rfe_qr_tria_pair(a, 4u, 7u), RFE_ERR_SIZE);
}

/* REQ-QR-001 */
static void test_rfe_qr_tria_orthogonal_factor(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    size_t rows;
    size_t cols;
    int rep;
    (void)state;
    rng_seed(3u);
    for (rows = 1u; rows <= NM; ++rows) {
        /* cols = rows is the worst-conditioned case of a random matrix: keep it, but
         * also the wide shapes the filter uses */
        for (cols = rows + 1u; cols <= (3u * rows); cols += rows) {
            for (rep = 0; rep < 4; ++rep) {
                fill_matrix(buf, rows, cols, cols);
                check_tria(buf, rows, cols, cols, A0);
                ASSERT_LE(orth_residual(A0, buf, cols, rows, cols), TOL_ORTH, "Q^T Q - I");
            }
        }
    }
}

/* A lower-triangular input with positive diagonal is its own Tria (uniqueness of the
 * Cholesky factor of A A^T); a negative diagonal entry flips that column's sign. */
/* REQ-QR-001 */
static void test_rfe_qr_tria_lower_input_fixed_point(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    const size_t n = NM;
    size_t i;
    size_t j;
    (void)state;
    rng_seed(4u);
    fill_matrix(buf, n, n, n);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            if (j > i) {
                AT(buf, n, i, j) = (rfe_real_t)0.0;
            } else if (j == i) {
                AT(buf, n, i, j) = (rfe_real_t)(1.5 + (0.5 * rng_uniform()));
                if ((i % 3u) == 1u) {
                    AT(buf, n, i, j) = -AT(buf, n, i, j);
                }
            }
        }
    }
    check_tria(buf, n, n, n, A0);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j <= i; ++j) {
            const double sign = ((j % 3u) == 1u) ? -1.0 : 1.0;
            ASSERT_LE(fabs((double)AT(buf, n, i, j) - (sign * A0[(i * n) + j])),
                      TOL_TRIA * row_norm(A0, n, i), "Tria(L) = L D, D = sign(diag L)");
        }
    }
}

/* ---- Tria: rank-deficient inputs -------------------------------------------------------- */

/* REQ-QR-002 */
static void test_rfe_qr_tria_repeated_rows(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    const size_t rows = 4u;
    const size_t cols = 11u;
    size_t j;
    (void)state;
    rng_seed(5u);
    fill_matrix(buf, rows, cols, cols);
    for (j = 0u; j < cols; ++j) {
        AT(buf, cols, 2u, j) = AT(buf, cols, 0u, j); /* row 2 = row 0 */
    }
    check_tria(buf, rows, cols, cols, A0);
    /* row 2 of S equals row 0 of S: S(2,0) = S(0,0), S(2,1) = S(2,2) = 0 */
    ASSERT_LE(fabs((double)AT(buf, cols, 2u, 0u) - (double)AT(buf, cols, 0u, 0u)),
              TOL_RANKDEF * row_norm(A0, cols, 0u), "S(2,0) - S(0,0)");
    ASSERT_LE(fabs((double)AT(buf, cols, 2u, 1u)), TOL_RANKDEF * row_norm(A0, cols, 0u), "S(2,1)");
    ASSERT_LE((double)AT(buf, cols, 2u, 2u), TOL_RANKDEF * row_norm(A0, cols, 0u), "S(2,2)");
    /* and the independent row 3 after it keeps a proper positive pivot */
    assert_true(AT(buf, cols, 3u, 3u) > (rfe_real_t)0.01);
}

/* REQ-QR-002 */
static void test_rfe_qr_tria_many_repeated_rows(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    const size_t rows = NM;
    const size_t cols = 2u * NM;
    size_t i;
    size_t j;
    (void)state;
    rng_seed(6u);
    fill_matrix(buf, rows, cols, cols);
    for (i = 2u; i < rows; ++i) {
        for (j = 0u; j < cols; ++j) {
            AT(buf, cols, i, j) = AT(buf, cols, i % 2u, j); /* rank 2 */
        }
    }
    check_tria(buf, rows, cols, cols, A0);
    for (i = 2u; i < rows; ++i) {
        ASSERT_LE((double)AT(buf, cols, i, i), TOL_RANKDEF * row_norm(A0, cols, i),
                  "diag of a dependent row");
    }
}

/* REQ-QR-002 */
static void test_rfe_qr_tria_zero_row(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    const size_t rows = 5u;
    const size_t cols = 9u;
    size_t z;
    size_t i;
    size_t j;
    (void)state;
    rng_seed(7u);
    for (z = 0u; z < rows; ++z) {
        fill_matrix(buf, rows, cols, cols + 2u);
        for (j = 0u; j < cols; ++j) {
            AT(buf, cols + 2u, z, j) = (rfe_real_t)0.0;
        }
        check_tria(buf, rows, cols, cols + 2u, A0);
        for (j = 0u; j < cols; ++j) {
            assert_true(AT(buf, cols + 2u, z, j) == (rfe_real_t)0.0); /* exactly zero row */
        }
        for (i = 0u; i < rows; ++i) {
            if (i != z) {
                assert_true(AT(buf, cols + 2u, i, i) > (rfe_real_t)0.0);
            }
        }
    }
}

/* REQ-QR-002 */
static void test_rfe_qr_tria_all_zero(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    const size_t rows = NM;
    const size_t cols = TC;
    size_t i;
    size_t j;
    (void)state;
    fill_matrix(buf, rows, cols, cols);
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j < cols; ++j) {
            AT(buf, cols, i, j) = (rfe_real_t)0.0;
        }
    }
    check_tria(buf, rows, cols, cols, A0);
    for (i = 0u; i < (rows * cols); ++i) {
        assert_true(buf[i] == (rfe_real_t)0.0);
    }
}

/* REQ-QR-002 */
static void test_rfe_qr_tria_rank_one(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    const size_t rows = 5u;
    const size_t cols = 9u;
    double u[5];
    double v[9];
    double vnorm = 0.0;
    size_t i;
    size_t j;
    (void)state;
    rng_seed(8u);
    fill_matrix(buf, rows, cols, cols);
    for (i = 0u; i < rows; ++i) {
        u[i] = rng_uniform();
    }
    u[0] = -0.75; /* negative leading entry: S(:,0) = sign(u0) u |v| */
    for (j = 0u; j < cols; ++j) {
        v[j] = rng_uniform();
    }
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j < cols; ++j) {
            AT(buf, cols, i, j) = (rfe_real_t)(u[i] * v[j]);
        }
    }
    check_tria(buf, rows, cols, cols, A0);
    for (j = 0u; j < cols; ++j) {
        vnorm += v[j] * v[j];
    }
    vnorm = sqrt(vnorm);
    for (i = 0u; i < rows; ++i) {
        ASSERT_LE(fabs((double)AT(buf, cols, i, 0u) - (-u[i] * vnorm)),
                  TOL_RANKDEF * 2.0 * vnorm, "S(:,0) = -u * norm(v)");
        for (j = 1u; j <= i; ++j) {
            ASSERT_LE(fabs((double)AT(buf, cols, i, j)), TOL_RANKDEF * 2.0 * vnorm,
                      "S(i,j>0) of a rank-1 matrix");
        }
    }
}

/* Kahan matrix (n = 8, c = 0.285): K_ii = s^i, K_ij = -c s^i (j > i); the classic trap for
 * QR-based rank decisions. Tria of K (upper) and of K^T (lower: a fixed point). */
/* REQ-QR-002 */
static void test_rfe_qr_tria_kahan(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    const size_t n = NM;
    const double c = 0.285;
    const double s = sqrt(1.0 - (c * c));
    size_t i;
    size_t j;
    int transpose;
    (void)state;
    for (transpose = 0; transpose <= 1; ++transpose) {
        fill_matrix(buf, n, n, n);
        for (i = 0u; i < n; ++i) {
            for (j = 0u; j < n; ++j) {
                const size_t r = (transpose != 0) ? j : i;
                const size_t q = (transpose != 0) ? i : j;
                double k = 0.0;
                if (q == r) {
                    k = pow(s, (double)r);
                } else if (q > r) {
                    k = -c * pow(s, (double)r);
                }
                AT(buf, n, i, j) = (rfe_real_t)k;
            }
        }
        check_tria(buf, n, n, n, A0);
        ASSERT_LE(orth_residual(A0, buf, n, n, n), TOL_ORTH, "Q^T Q - I (Kahan)");
        if (transpose != 0) {
            for (i = 0u; i < n; ++i) {
                for (j = 0u; j <= i; ++j) {
                    ASSERT_LE(fabs((double)AT(buf, n, i, j) - A0[(i * n) + j]),
                              TOL_TRIA * row_norm(A0, n, i), "Tria(K^T) = K^T");
                }
            }
        }
    }
}

/* Rows of very different size (1 and 1e-6): the residual is row-scaled, so the small rows
 * must be as accurate relative to their own norm as the large ones. */
/* REQ-QR-002 */
static void test_rfe_qr_tria_badly_scaled_rows(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    static const size_t shapes[3][2] = {{4u, 11u}, {4u, 12u}, {NM, TC}};
    size_t s;
    size_t i;
    size_t j;
    int order;
    (void)state;
    rng_seed(9u);
    for (s = 0u; s < 3u; ++s) {
        const size_t rows = shapes[s][0];
        const size_t cols = shapes[s][1];
        for (order = 0; order <= 1; ++order) {
            fill_matrix(buf, rows, cols, cols);
            for (i = 0u; i < rows; ++i) {
                const rfe_real_t scale =
                    (((i + (size_t)order) % 2u) == 0u) ? (rfe_real_t)1.0 : (rfe_real_t)1e-6;
                for (j = 0u; j < cols; ++j) {
                    AT(buf, cols, i, j) *= scale;
                }
            }
            check_tria(buf, rows, cols, cols, A0);
            /* Q^T = S^-1 A is invariant under row scaling: still orthonormal */
            ASSERT_LE(orth_residual(A0, buf, cols, rows, cols), TOL_ORTH, "Q^T Q - I (scaled)");
        }
    }
}

/* Finite input at the top of the range (float: 1e19, double: 1e154): A A^T overflows but S
 * (of the size of A) is representable. The call must not report success with a non-finite S. */
/* REQ-QR-002 */
static void test_rfe_qr_tria_large_finite_entries(void **state)
{
    static rfe_real_t buf[BUF_N];
    const size_t rows = 4u;
    const size_t cols = 12u;
#if defined(RFE_REAL_DOUBLE)
    const rfe_real_t big = (rfe_real_t)1e154;
#else
    const rfe_real_t big = (rfe_real_t)1e19;
#endif
    size_t i;
    size_t j;
    rfe_status_t st;
    int all_finite = 1;
    (void)state;
    rng_seed(10u);
    fill_matrix(buf, rows, cols, cols);
    for (i = 0u; i < (rows * cols); ++i) {
        buf[i] *= big;
    }
    st = rfe_qr_tria(buf, rows, cols, cols);
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j <= i; ++j) {
            if (!isfinite(AT(buf, cols, i, j))) {
                all_finite = 0;
            }
        }
    }
    if ((st == RFE_OK) && (all_finite == 0)) {
        print_error("rfe_qr_tria returned RFE_OK with a non-finite S for finite input "
                    "(|a_ij| ~ %g)\n",
                    (double)big);
        fail();
    }
}

/* Rows at the bottom of the range (float: 1e-25, double: 1e-170): squares underflow but
 * S (of the size of A) is representable. Expected [S 0] with S relative to the row size:
 * a1 = t [1 2 -1] against a0 = [1 2 3] gives S(1,0) = 2t / sqrt(14), S(1,1) = t sqrt(6 - 4/14). */
/* REQ-QR-002 */
static void test_rfe_qr_tria_tiny_row(void **state)
{
    static rfe_real_t buf[BUF_N];
#if defined(RFE_REAL_DOUBLE)
    const rfe_real_t t = (rfe_real_t)1e-170;
#else
    const rfe_real_t t = (rfe_real_t)1e-25;
#endif
    (void)state;
    fill_matrix(buf, 2u, 3u, 3u);
    AT(buf, 3u, 0u, 0u) = (rfe_real_t)1.0;
    AT(buf, 3u, 0u, 1u) = (rfe_real_t)2.0;
    AT(buf, 3u, 0u, 2u) = (rfe_real_t)3.0;
    AT(buf, 3u, 1u, 0u) = t;
    AT(buf, 3u, 1u, 1u) = (rfe_real_t)2.0 * t;
    AT(buf, 3u, 1u, 2u) = -t;
    assert_int_equal(rfe_qr_tria(buf, 2u, 3u, 3u), RFE_OK);
    assert_tria_structure(buf, 2u, 3u, 3u); /* the tail of row 1 must be zeroed */
    ASSERT_LE(fabs(((double)AT(buf, 3u, 0u, 0u)) - sqrt(14.0)), TOL_TRIA * 4.0, "S(0,0)");
    ASSERT_LE(fabs(((double)AT(buf, 3u, 1u, 0u) / (double)t) - (2.0 / sqrt(14.0))),
              TOL_TRIA * 4.0, "S(1,0) / t");
    ASSERT_LE(fabs(((double)AT(buf, 3u, 1u, 1u) / (double)t) - sqrt(6.0 - (4.0 / 14.0))),
              TOL_TRIA * 4.0, "S(1,1) / t");
}

/* ---- Tria: errors ----------------------------------------------------------------------- */

/* REQ-QR-005 */
static void test_rfe_qr_tria_null(void **state)
{
    (void)state;
    assert_int_equal(rfe_qr_tria(NULL, 4u, 12u, 12u), RFE_ERR_NULL);
}

/* REQ-QR-005 */
static void test_rfe_qr_tria_size_errors(void **state)
{
    static rfe_real_t buf[BUF_N];
    static rfe_real_t ref[BUF_N];
    /* rows, cols, lda */
    static const size_t cases[][3] = {
        {0u, 4u, 4u},                      /* rows 0 */
        {TR + 1u, TR + 1u, TR + 1u},       /* rows > RFE_TRIA_ROWS_MAX */
        {4u, 3u, 4u},                      /* cols < rows */
        {4u, TC + 1u, TC + 1u},            /* cols > RFE_TRIA_COLS_LIMIT */
        {4u, 12u, 11u},                    /* lda < cols */
        {1u, 0u, 0u},                      /* cols 0 < rows */
    };
    size_t c;
    (void)state;
    rng_seed(11u);
    for (c = 0u; c < (sizeof cases / sizeof cases[0]); ++c) {
        fill_matrix(buf, TR + 1u, LD_MAX, LD_MAX);
        memcpy(ref, buf, sizeof buf);
        assert_int_equal(rfe_qr_tria(buf, cases[c][0], cases[c][1], cases[c][2]),
                         RFE_ERR_SIZE);
        assert_memory_equal(buf, ref, sizeof buf);
    }
}

/* REQ-QR-005 */
static void test_rfe_qr_tria_nonfinite_untouched(void **state)
{
    static rfe_real_t buf[BUF_N];
    static rfe_real_t ref[BUF_N];
    const size_t rows = 4u;
    const size_t cols = 11u;
    const size_t lda = TC;
    const rfe_real_t bad[3] = {(rfe_real_t)NAN, (rfe_real_t)INFINITY, (rfe_real_t)-INFINITY};
    /* first, interior, last element of the matrix */
    static const size_t pos[3][2] = {{0u, 0u}, {2u, 5u}, {3u, 10u}};
    size_t b;
    size_t p;
    (void)state;
    rng_seed(12u);
    for (b = 0u; b < 3u; ++b) {
        for (p = 0u; p < 3u; ++p) {
            fill_matrix(buf, rows, cols, lda);
            AT(buf, lda, pos[p][0], pos[p][1]) = bad[b];
            memcpy(ref, buf, sizeof buf);
            assert_int_equal(rfe_qr_tria(buf, rows, cols, lda), RFE_ERR_NONFINITE);
            /* every element, the padding and the guard words after the matrix */
            assert_memory_equal(buf, ref, sizeof buf);
        }
    }
}

/* Non-finite values outside the rows x cols window (padding, after the buffer) are not
 * part of A: they must neither be read as input nor be written. */
/* REQ-QR-005 */
static void test_rfe_qr_tria_nonfinite_padding_ignored(void **state)
{
    static rfe_real_t buf[BUF_N];
    static double A0[NM * LD_MAX];
    const size_t rows = 3u;
    const size_t cols = 11u;
    const size_t lda = 13u;
    size_t i;
    (void)state;
    rng_seed(13u);
    fill_matrix(buf, rows, cols, lda);
    for (i = 0u; i < rows; ++i) {
        AT(buf, lda, i, cols) = (rfe_real_t)NAN;
    }
    to_double(buf, rows, cols, lda, A0);
    assert_int_equal(rfe_qr_tria(buf, rows, cols, lda), RFE_OK);
    for (i = 0u; i < rows; ++i) {
        assert_true(isnan(AT(buf, lda, i, cols)));
        assert_true(AT(buf, lda, i, cols + 1u) == PAD_VAL);
    }
    ASSERT_LE(tria_residual(A0, buf, lda, rows, cols), TOL_TRIA, "S S^T - A A^T");
}

/* ---- triangular solves ------------------------------------------------------------------ */

typedef rfe_status_t (*solve_fn_t)(const rfe_real_t *, size_t, size_t, rfe_real_t *, size_t,
                                   size_t);

/* Random lower-triangular L (diag in [1, 2], |off-diag| <= 0.5, cond < 30 for n <= 8) with
 * finite garbage in the strict upper triangle, which the solves must not read. */
static void make_lower(rfe_real_t *L, size_t n, size_t ldl)
{
    size_t i;
    size_t j;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < ldl; ++j) {
            if (j < i) {
                AT(L, ldl, i, j) = (rfe_real_t)(0.5 * rng_uniform());
            } else if (j == i) {
                AT(L, ldl, i, j) = (rfe_real_t)(1.5 + (0.5 * rng_uniform()));
            } else {
                AT(L, ldl, i, j) = (rfe_real_t)1000.0;
            }
        }
    }
}

/* Round trip: B = op(L) X in double, rounded; solve; compare with X. op = L or L^T.
 * Columns ncols..ldb-1 of B and the guard words after B must keep their values. */
static void solve_round_trip(solve_fn_t solve, int transposed, uint64_t seed)
{
    static rfe_real_t L[NM * (NM + 2u)];
    static rfe_real_t B[BUF_N];
    static double X[NM * 8u];
    size_t n;
    size_t ncols;
    size_t i;
    size_t j;
    size_t k;
    size_t ldl;
    size_t ldb;
    rng_seed(seed);
    for (n = 1u; n <= NM; ++n) {
        for (ncols = 1u; ncols <= 5u; ++ncols) {
            for (ldl = n; ldl <= (n + 2u); ldl += 2u) {
                for (ldb = ncols; ldb <= (ncols + 3u); ldb += 3u) {
                    make_lower(L, n, ldl);
                    guard_fill(B, BUF_N);
                    for (i = 0u; i < n; ++i) {
                        for (j = 0u; j < ncols; ++j) {
                            X[(i * ncols) + j] = rng_uniform();
                        }
                        for (j = ncols; j < ldb; ++j) {
                            AT(B, ldb, i, j) = PAD_VAL;
                        }
                    }
                    for (i = 0u; i < n; ++i) {
                        for (j = 0u; j < ncols; ++j) {
                            double acc = 0.0;
                            for (k = 0u; k < n; ++k) {
                                const double lik = (transposed != 0)
                                                       ? ((i <= k) ? (double)AT(L, ldl, k, i) : 0.0)
                                                       : ((k <= i) ? (double)AT(L, ldl, i, k) : 0.0);
                                acc += lik * X[(k * ncols) + j];
                            }
                            AT(B, ldb, i, j) = (rfe_real_t)acc;
                        }
                    }
                    assert_int_equal(solve(L, n, ldl, B, ncols, ldb), RFE_OK);
                    for (i = 0u; i < n; ++i) {
                        for (j = 0u; j < ncols; ++j) {
                            ASSERT_LE(fabs((double)AT(B, ldb, i, j) - X[(i * ncols) + j]),
                                      TOL_SOLVE, "solution error");
                        }
                        for (j = ncols; j < ldb; ++j) {
                            assert_true(AT(B, ldb, i, j) == PAD_VAL);
                        }
                    }
                    for (i = n * ldb; i < BUF_N; ++i) {
                        assert_true(B[i] == GUARD_VAL);
                    }
                }
            }
        }
    }
}

/* REQ-QR-003 */
static void test_rfe_qr_solve_lower_round_trip(void **state)
{
    (void)state;
    solve_round_trip(rfe_qr_solve_lower, 0, 21u);
}

/* REQ-QR-003 */
static void test_rfe_qr_solve_lower_t_round_trip(void **state)
{
    (void)state;
    solve_round_trip(rfe_qr_solve_lower_t, 1, 22u);
}

/* Hand-checked 3 x 3 example with exactly representable data. */
/* REQ-QR-003 */
static void test_rfe_qr_solve_lower_known_solution(void **state)
{
    static const rfe_real_t L[9] = {2, 0, 0, 1, 4, 0, -1, 2, 8};
    /* X = [1 -2; 0.5 3; -0.25 1]:  L X = [2 -4; 3 10; -2 16],  L^T X = [2.75 -2; 1.5 14; -2 8] */
    rfe_real_t B[6] = {2, -4, 3, 10, -2, 16};
    rfe_real_t Bt[6] = {2.75, -2, 1.5, 14, -2, 8};
    static const rfe_real_t X[6] = {1, -2, 0.5, 3, -0.25, 1};
    size_t i;
    (void)state;
    assert_int_equal(rfe_qr_solve_lower(L, 3u, 3u, B, 2u, 2u), RFE_OK);
    assert_int_equal(rfe_qr_solve_lower_t(L, 3u, 3u, Bt, 2u, 2u), RFE_OK);
    for (i = 0u; i < 6u; ++i) {
        assert_true(B[i] == X[i]);  /* exact: every intermediate is a short dyadic */
        assert_true(Bt[i] == X[i]);
    }
}

static void solve_not_pd(solve_fn_t solve)
{
    static rfe_real_t L[NM * NM];
    static rfe_real_t B[BUF_N];
    static rfe_real_t ref[BUF_N];
    const size_t n = 5u;
    const rfe_real_t bad[3] = {(rfe_real_t)0.0, (rfe_real_t)-1.5, (rfe_real_t)NAN};
    size_t b;
    size_t k;
    size_t i;
    rng_seed(31u);
    for (b = 0u; b < 3u; ++b) {
        for (k = 0u; k < n; ++k) {
            make_lower(L, n, n);
            AT(L, n, k, k) = bad[b];
            for (i = 0u; i < BUF_N; ++i) {
                B[i] = (i < (n * 4u)) ? (rfe_real_t)rng_uniform() : GUARD_VAL;
            }
            memcpy(ref, B, sizeof B);
            assert_int_equal(solve(L, n, n, B, 3u, 4u), RFE_ERR_NOT_POSITIVE_DEFINITE);
            assert_memory_equal(B, ref, sizeof B);
        }
    }
}

/* REQ-QR-004 */
static void test_rfe_qr_solve_lower_not_positive_diagonal(void **state)
{
    (void)state;
    solve_not_pd(rfe_qr_solve_lower);
}

/* REQ-QR-004 */
static void test_rfe_qr_solve_lower_t_not_positive_diagonal(void **state)
{
    (void)state;
    solve_not_pd(rfe_qr_solve_lower_t);
}

static void solve_errors(solve_fn_t solve)
{
    static rfe_real_t L[(NM + 1u) * (NM + 1u)];
    static rfe_real_t B[BUF_N];
    static rfe_real_t ref[BUF_N];
    /* n, ldl, ncols, ldb */
    static const size_t cases[][4] = {
        {0u, 4u, 2u, 2u},                /* n 0 */
        {NM + 1u, NM + 1u, 2u, 2u},      /* n > RFE_N_MAX */
        {4u, 3u, 2u, 2u},                /* ldl < n */
        {4u, 4u, 0u, 2u},                /* ncols 0 */
        {4u, 4u, 3u, 2u},                /* ldb < ncols */
    };
    size_t c;
    size_t i;
    rng_seed(41u);
    for (i = 0u; i < ((NM + 1u) * (NM + 1u)); ++i) {
        L[i] = (rfe_real_t)0.0;
    }
    for (i = 0u; i <= NM; ++i) {
        L[(i * (NM + 1u)) + i] = (rfe_real_t)1.0; /* diagonal fine at every ld used */
        L[(i * 4u) + i] = (rfe_real_t)1.0;
        L[(i * 3u) + i] = (rfe_real_t)1.0;
    }
    for (i = 0u; i < BUF_N; ++i) {
        B[i] = (rfe_real_t)rng_uniform();
    }
    memcpy(ref, B, sizeof B);
    for (c = 0u; c < (sizeof cases / sizeof cases[0]); ++c) {
        assert_int_equal(solve(L, cases[c][0], cases[c][1], B, cases[c][2], cases[c][3]),
                         RFE_ERR_SIZE);
        assert_memory_equal(B, ref, sizeof B);
    }
    assert_int_equal(solve(NULL, 4u, 4u, B, 2u, 2u), RFE_ERR_NULL);
    assert_int_equal(solve(L, 4u, 4u, NULL, 2u, 2u), RFE_ERR_NULL);
    assert_memory_equal(B, ref, sizeof B);
}

/* REQ-QR-005 */
static void test_rfe_qr_solve_lower_errors(void **state)
{
    (void)state;
    solve_errors(rfe_qr_solve_lower);
}

/* REQ-QR-005 */
static void test_rfe_qr_solve_lower_t_errors(void **state)
{
    (void)state;
    solve_errors(rfe_qr_solve_lower_t);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_qr_tria_random_all_shapes),
        cmocka_unit_test(test_rfe_qr_tria_filter_shapes),
        cmocka_unit_test(test_rfe_qr_tria_fixed_shapes_match_runtime),
        cmocka_unit_test(test_rfe_qr_tria_lt_is_tria),
        cmocka_unit_test(test_rfe_qr_tria_orthogonal_factor),
        cmocka_unit_test(test_rfe_qr_tria_lower_input_fixed_point),
        cmocka_unit_test(test_rfe_qr_tria_repeated_rows),
        cmocka_unit_test(test_rfe_qr_tria_many_repeated_rows),
        cmocka_unit_test(test_rfe_qr_tria_zero_row),
        cmocka_unit_test(test_rfe_qr_tria_all_zero),
        cmocka_unit_test(test_rfe_qr_tria_rank_one),
        cmocka_unit_test(test_rfe_qr_tria_kahan),
        cmocka_unit_test(test_rfe_qr_tria_badly_scaled_rows),
        cmocka_unit_test(test_rfe_qr_tria_large_finite_entries),
        cmocka_unit_test(test_rfe_qr_tria_tiny_row),
        cmocka_unit_test(test_rfe_qr_tria_null),
        cmocka_unit_test(test_rfe_qr_tria_size_errors),
        cmocka_unit_test(test_rfe_qr_tria_nonfinite_untouched),
        cmocka_unit_test(test_rfe_qr_tria_nonfinite_padding_ignored),
        cmocka_unit_test(test_rfe_qr_solve_lower_round_trip),
        cmocka_unit_test(test_rfe_qr_solve_lower_t_round_trip),
        cmocka_unit_test(test_rfe_qr_solve_lower_known_solution),
        cmocka_unit_test(test_rfe_qr_solve_lower_not_positive_diagonal),
        cmocka_unit_test(test_rfe_qr_solve_lower_t_not_positive_diagonal),
        cmocka_unit_test(test_rfe_qr_solve_lower_errors),
        cmocka_unit_test(test_rfe_qr_solve_lower_t_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
