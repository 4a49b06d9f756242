/**
 * @file qr_flt.c
 * @brief Householder Tria() and triangular solves (MODEL.md §6).
 */
#include "rfe/qr.h"

#include "internal.h"

#define AT(M, ld, i, j) ((M)[((i) * (ld)) + (j)])

/* Binary exponent e of the largest |element| of a row (max in [2^(e-1), 2^e)); 0 for a
 * zero row. */
static int row_exponent(const rfe_real_t *row, size_t cols)
{
    rfe_real_t big = RFE_R(0.0);
    int e = 0;
    size_t j;
    for (j = 0u; j < cols; ++j) {
        big = rfe_max(big, RFE_FABS(row[j]));
    }
    if (big > RFE_R(0.0)) {
        (void)RFE_FREXP(big, &e);
    }
    return e;
}

/* row[0..cols) *= 2^e (exact barring overflow/underflow of the result). */
static void scale_row(rfe_real_t *row, size_t cols, int e)
{
    if (e != 0) {
        size_t j;
        for (j = 0u; j < cols; ++j) {
            row[j] = RFE_LDEXP(row[j], e);
        }
    }
}

/* Euclidean norm of row k of A from column k on. */
static rfe_real_t row_tail_norm(const rfe_real_t *A, size_t lda, size_t k, size_t cols)
{
    rfe_real_t ss = RFE_R(0.0);
    size_t j;
    for (j = k; j < cols; ++j) {
        ss += AT(A, lda, k, j) * AT(A, lda, k, j);
    }
    return RFE_SQRT(ss);
}

/* One Householder reflection H = I - 2 v v^T / (v^T v) from the right that maps row k's
 * tail x = A[k][k..] onto (-sign(x0) |x|, 0, ..., 0); v = x + sign(x0) |x| e_0 avoids
 * cancellation. Applied to rows k..rows-1; v is kept in row k's tail until done. */
static void reflect_row(rfe_real_t *A, size_t rows, size_t cols, size_t lda, size_t k,
                        rfe_real_t norm)
{
    const rfe_real_t x0 = AT(A, lda, k, k);
    const rfe_real_t sgn = (x0 < RFE_R(0.0)) ? RFE_R(-1.0) : RFE_R(1.0);
    /* v^T v = 2 |x| (|x| + |x0|). */
    const rfe_real_t vtv = RFE_R(2.0) * norm * (norm + RFE_FABS(x0));
    size_t i;
    size_t j;

    AT(A, lda, k, k) = x0 + (sgn * norm); /* row k's tail now holds v */
    for (i = k + 1u; i < rows; ++i) {
        rfe_real_t dot = RFE_R(0.0);
        rfe_real_t scale;
        for (j = k; j < cols; ++j) {
            dot += AT(A, lda, i, j) * AT(A, lda, k, j);
        }
        scale = RFE_R(2.0) * dot / vtv;
        for (j = k; j < cols; ++j) {
            AT(A, lda, i, j) -= scale * AT(A, lda, k, j);
        }
    }
    /* Row k itself becomes (-sign(x0) |x|, 0, ...). */
    AT(A, lda, k, k) = -sgn * norm;
    for (j = k + 1u; j < cols; ++j) {
        AT(A, lda, k, j) = RFE_R(0.0);
    }
}

/* Non-negative diagonal of the lower-triangular rows x rows S in A: flipping a column's sign
 * leaves S S^T unchanged. */
static void make_diagonal_nonnegative(rfe_real_t *A, size_t rows, size_t lda)
{
    size_t i;
    size_t k;
    for (k = 0u; k < rows; ++k) {
        if (AT(A, lda, k, k) < RFE_R(0.0)) {
            for (i = k; i < rows; ++i) {
                AT(A, lda, i, k) = -AT(A, lda, i, k);
            }
        }
    }
}

rfe_status_t RFE_FN(rfe_qr_tria)(rfe_real_t *A, size_t rows, size_t cols, size_t lda)
{
    int exps[RFE_N_MAX];
    size_t i;
    size_t k;

    if (A == NULL) {
        return RFE_ERR_NULL;
    }
    if ((rows == 0u) || (rows > (size_t)RFE_N_MAX) || (cols < rows) ||
        (cols > RFE_TRIA_COLS_SZ) || (lda < cols)) {
        return RFE_ERR_SIZE;
    }
    for (i = 0u; i < rows; ++i) {
        if (!rfe_all_finite(&AT(A, lda, i, 0u), cols)) {
            return RFE_ERR_NONFINITE;
        }
    }
    /* Rows are scaled by powers of two so the sums of squares neither overflow nor
     * underflow: with A = D A', S = D S'. Power-of-two scaling is exact, so in the normal
     * range the result is bit-identical to the unscaled reduction. */
    for (i = 0u; i < rows; ++i) {
        exps[i] = row_exponent(&AT(A, lda, i, 0u), cols);
        scale_row(&AT(A, lda, i, 0u), cols, -exps[i]);
    }
    /* A^T = Q R  <=>  A Q = R^T = [S 0]: zero each row's tail right of the diagonal. */
    for (k = 0u; k < rows; ++k) {
        const rfe_real_t norm = row_tail_norm(A, lda, k, cols);
        if (norm > RFE_R(0.0)) {
            reflect_row(A, rows, cols, lda, k, norm);
        }
        /* norm == 0: the tail is already zero (rank-deficient input); S(k,k) = 0. */
    }
    make_diagonal_nonnegative(A, rows, lda);
    for (i = 0u; i < rows; ++i) {
        scale_row(&AT(A, lda, i, 0u), i + 1u, exps[i]); /* S = D S' */
    }
    return RFE_OK;
}

/* Shared checks of the triangular solves; all diagonal entries must be > 0. */
static rfe_status_t check_solve(const rfe_real_t *L, size_t n, size_t ldl, const rfe_real_t *B,
                                size_t ncols, size_t ldb)
{
    size_t i;
    if ((L == NULL) || (B == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((n == 0u) || (n > (size_t)RFE_N_MAX) || (ldl < n) || (ncols == 0u) || (ldb < ncols)) {
        return RFE_ERR_SIZE;
    }
    for (i = 0u; i < n; ++i) {
        if (!(AT(L, ldl, i, i) > RFE_R(0.0))) { /* also rejects NaN */
            return RFE_ERR_NOT_POSITIVE_DEFINITE;
        }
    }
    return RFE_OK;
}

rfe_status_t RFE_FN(rfe_qr_solve_lower)(const rfe_real_t *L, size_t n, size_t ldl, rfe_real_t *B,
                                        size_t ncols, size_t ldb)
{
    size_t c;
    size_t i;
    size_t j;
    const rfe_status_t st = check_solve(L, n, ldl, B, ncols, ldb);

    if (st != RFE_OK) {
        return st;
    }
    /* x_i = (b_i - sum_{j<i} L_ij x_j) / L_ii, column by column. */
    for (c = 0u; c < ncols; ++c) {
        for (i = 0u; i < n; ++i) {
            rfe_real_t acc = AT(B, ldb, i, c);
            for (j = 0u; j < i; ++j) {
                acc -= AT(L, ldl, i, j) * AT(B, ldb, j, c);
            }
            AT(B, ldb, i, c) = acc / AT(L, ldl, i, i);
        }
    }
    return RFE_OK;
}

rfe_status_t RFE_FN(rfe_qr_solve_lower_t)(const rfe_real_t *L, size_t n, size_t ldl,
                                          rfe_real_t *B, size_t ncols, size_t ldb)
{
    size_t c;
    size_t j;
    const rfe_status_t st = check_solve(L, n, ldl, B, ncols, ldb);

    if (st != RFE_OK) {
        return st;
    }
    /* x_i = (b_i - sum_{j>i} L_ji x_j) / L_ii, from the last row up. */
    for (c = 0u; c < ncols; ++c) {
        size_t up;
        for (up = 0u; up < n; ++up) {
            const size_t i = n - 1u - up; /* rows n-1 .. 0 */
            rfe_real_t acc = AT(B, ldb, i, c);
            for (j = i + 1u; j < n; ++j) {
                acc -= AT(L, ldl, j, i) * AT(B, ldb, j, c);
            }
            AT(B, ldb, i, c) = acc / AT(L, ldl, i, i);
        }
    }
    return RFE_OK;
}
