/**
 * @file qr_flt.c
 * @brief Householder Tria() and triangular solves (MODEL.md §6).
 */
#include "rfe/component/qr.h"

#include <float.h>

#include "numerics/internal.h"

#if defined(RFE_REAL_DOUBLE)
#define RFE_REAL_MIN_EXP DBL_MIN_EXP
#define RFE_REAL_MAX_EXP DBL_MAX_EXP
/* Row maxima Tria() reduces unscaled: squares and sums of up to RFE_TRIA_COLS_LIMIT of them
 * stay far inside the normal range (2^+-256 of 2^+-1022). */
#define TRIA_SAFE_LO RFE_R(8.6361685550944446e-78) /* 2^-256 */
#define TRIA_SAFE_HI RFE_R(1.1579208923731620e+77) /* 2^256 */
#else
#define RFE_REAL_MIN_EXP FLT_MIN_EXP
#define RFE_REAL_MAX_EXP FLT_MAX_EXP
/* As above for float: 2^+-30 of 2^+-126. */
#define TRIA_SAFE_LO RFE_R(9.31322574615478515625e-10) /* 2^-30 */
#define TRIA_SAFE_HI RFE_R(1073741824.0)               /* 2^30 */
#endif

#define AT(M, ld, i, j) ((M)[((i) * (ld)) + (j)])

/* The reduction's helpers inlined into tria_reduce, and tria_reduce into each of its calls
 * with constant sizes (rfe_qr_tria's fixed shapes below), on every core. */
#if defined(__GNUC__)
/* MISRA-DEV-02: a GNU attribute (Rule 1.2, language extension), only under __GNUC__ */
#define TRIA_INLINE __attribute__((always_inline)) inline
/* the rare path (a row to scale, a NaN) once, not inlined into each unrolled copy: with three
 * entries calling them, inlining it cost ~1 kB of the Cortex-M4F's flash */
#define TRIA_COLD __attribute__((noinline))
#else
#define TRIA_INLINE inline
#define TRIA_COLD
#endif

/* Largest |element| of a row; -1 when the row holds a NaN or an infinity. */
static rfe_real_t row_max(const rfe_real_t *row, size_t cols)
{
    rfe_real_t big = RFE_R(0.0);
    size_t j;
    for (j = 0u; j < cols; ++j) {
        if (!rfe_is_finite(row[j])) {
            return RFE_R(-1.0);
        }
        big = rfe_max(big, RFE_FABS(row[j]));
    }
    return big;
}

/* The maxima of all rows into bigs; *scaled = 1 when one of them lies outside
 * [TRIA_SAFE_LO, TRIA_SAFE_HI] (zero rows aside). Returns -1 when A holds a NaN/Inf. */
static TRIA_COLD int row_maxima(const rfe_real_t *A, size_t rows, size_t cols, size_t lda,
                      rfe_real_t *bigs, int *scaled)
{
    size_t i;
    *scaled = 0;
    for (i = 0u; i < rows; ++i) {
        const rfe_real_t big = row_max(&AT(A, lda, i, 0u), cols);
        if (big < RFE_R(0.0)) {
            return -1;
        }
        if ((big > RFE_R(0.0)) && ((big < TRIA_SAFE_LO) || (big > TRIA_SAFE_HI))) {
            *scaled = 1;
        }
        bigs[i] = big;
    }
    return 0;
}

/* The columns of row i that can be non-zero while it is reduced: [.., g0) and [g1, end).
 * tri 0 (dense): up to cols. tri 1, A = [B, L] with L lower-triangular in the last rows
 * columns (rfe_qr_tria_lt): up to L's diagonal, cols - rows + i. tri 2, A = [L1, L2] with
 * both n x n blocks lower-triangular (rfe_qr_tria_pair, cols = 2 rows): up to i, then n..n+i.
 * Reflection j < k mixes only row j's columns, so row i keeps this shape until its own
 * reflection; the dense reduction's operations on the zeros outside are exact (a product 0,
 * a sum + 0, x - s 0 = x), so skipping them gives the same result. */
static TRIA_INLINE void tail_span(int tri, size_t rows, size_t cols, size_t i, size_t *g0,
                                  size_t *g1, size_t *end)
{
    if (tri == 2) {
        *g0 = i + 1u;
        *g1 = rows;
        *end = rows + i + 1u;
    } else {
        *end = (tri != 0) ? ((cols - rows) + i + 1u) : cols;
        *g0 = *end;
        *g1 = *end;
    }
}

/* The common case of row_maxima in one sum of squares per row (issue 21: a third of the
 * Cortex-M4F's instructions per element): 1 when every row's sum of squares ss (from 0, in
 * column order) is finite with TRIA_SS_LO <= ss <= TRIA_SS_HI, which proves what row_maxima
 * would find: no NaN or infinity (either makes ss NaN or infinite) and every row maximum big
 * in [TRIA_SAFE_LO, TRIA_SAFE_HI], so no scaling. The computed ss lies within a factor
 * (1 + cols u) of the exact sum of squares (u the unit roundoff, cols u < 2^-8 for any cols
 * below 2^16) apart from the squares that underflow (each below the smallest normal number,
 * so below 2^-60 TRIA_SS_LO in all), and big^2 <= sum <= cols big^2: ss <= TRIA_SS_HI =
 * TRIA_SAFE_HI^2 / 2 gives big^2 < TRIA_SAFE_HI^2; ss >= TRIA_SS_LO = 2 cols TRIA_SAFE_LO^2
 * gives cols big^2 > cols TRIA_SAFE_LO^2 (both bounds exact, normal numbers in float and
 * double for cols <= RFE_TRIA_COLS_LIMIT_SZ). 0 otherwise (a
 * zero or tiny row, a huge one, a NaN): the caller then takes row_maxima, whose result decides
 * as before; either way the reduction is the same, bit for bit. */
static TRIA_INLINE int rows_plainly_safe(const rfe_real_t *A, size_t rows, size_t cols, size_t lda,
                                         int tri)
{
    /* TRIA_SS_LO (with this cols), TRIA_SS_HI */
    const rfe_real_t ss_lo = (RFE_R(2.0) * (rfe_real_t)cols) * (TRIA_SAFE_LO * TRIA_SAFE_LO);
    const rfe_real_t ss_hi = (TRIA_SAFE_HI * TRIA_SAFE_HI) * RFE_R(0.5);
    size_t i;
    size_t j;
    for (i = 0u; i < rows; ++i) {
        const rfe_real_t *row = &AT(A, lda, i, 0u);
        rfe_real_t ss = RFE_R(0.0);
        size_t g0;
        size_t g1;
        size_t end;
        tail_span(tri, rows, cols, i, &g0, &g1, &end); /* the zeros outside add exactly 0 */
        for (j = 0u; j < g0; ++j) {
            ss += row[j] * row[j];
        }
        for (j = g1; j < end; ++j) {
            ss += row[j] * row[j];
        }
        if (!((ss >= ss_lo) && (ss <= ss_hi))) { /* also a NaN */
            return 0;
        }
    }
    return 1;
}

/* Binary exponent e of a row maximum big (big in [2^(e-1), 2^e)); 0 for a zero row. */
static int max_exponent(rfe_real_t big)
{
    int e = 0;
    if (big > RFE_R(0.0)) {
        (void)RFE_FREXP(big, &e);
    }
    return e;
}

/* row[0..cols) *= 2^e (exact barring overflow/underflow of the result). While 2^e is a
 * normal number the product x * 2^e is rounded once, exactly as ldexp(x, e) rounds, so one
 * ldexp for the factor replaces one per element with the same result, bit for bit. */
static void scale_row(rfe_real_t *row, size_t cols, int e)
{
    size_t j;
    if ((e >= (RFE_REAL_MIN_EXP - 1)) && (e < RFE_REAL_MAX_EXP)) {
        if (e != 0) {
            const rfe_real_t f = RFE_LDEXP(RFE_R(1.0), e);
            for (j = 0u; j < cols; ++j) {
                row[j] *= f;
            }
        }
    } else {
        for (j = 0u; j < cols; ++j) {
            row[j] = RFE_LDEXP(row[j], e);
        }
    }
}

/* Euclidean norm of row k of A from column k on. */
static TRIA_INLINE rfe_real_t row_tail_norm(const rfe_real_t *A, size_t lda, size_t k, size_t g0,
                                           size_t g1, size_t end)
{
    rfe_real_t ss = RFE_R(0.0);
    size_t j;
    for (j = k; j < g0; ++j) {
        ss += AT(A, lda, k, j) * AT(A, lda, k, j);
    }
    for (j = g1; j < end; ++j) {
        ss += AT(A, lda, k, j) * AT(A, lda, k, j);
    }
    return RFE_SQRT(ss);
}

/* One Householder reflection H = I - 2 v v^T / (v^T v) from the right that maps row k's
 * tail x = A[k][k..] onto (-sign(x0) |x|, 0, ..., 0); v = x + sign(x0) |x| e_0 avoids
 * cancellation. Applied to rows k..rows-1; v is kept in row k's tail until done. */
static TRIA_INLINE void reflect_row(rfe_real_t *A, size_t rows, size_t lda, size_t k, size_t g0,
                                    size_t g1, size_t end, rfe_real_t norm)
{
    const rfe_real_t x0 = AT(A, lda, k, k);
    const rfe_real_t sgn = (x0 < RFE_R(0.0)) ? RFE_R(-1.0) : RFE_R(1.0);
    /* v^T v = 2 |x| (|x| + |x0|). */
    const rfe_real_t vtv = RFE_R(2.0) * norm * (norm + RFE_FABS(x0));
    size_t i;
    size_t j;

    AT(A, lda, k, k) = x0 + (sgn * norm); /* row k's tail now holds v (zero outside its span) */
    for (i = k + 1u; i < rows; ++i) {
        rfe_real_t dot = RFE_R(0.0);
        rfe_real_t scale;
        for (j = k; j < g0; ++j) {
            dot += AT(A, lda, i, j) * AT(A, lda, k, j);
        }
        for (j = g1; j < end; ++j) {
            dot += AT(A, lda, i, j) * AT(A, lda, k, j);
        }
        scale = RFE_R(2.0) * dot / vtv;
        for (j = k; j < g0; ++j) {
            AT(A, lda, i, j) -= scale * AT(A, lda, k, j);
        }
        for (j = g1; j < end; ++j) {
            AT(A, lda, i, j) -= scale * AT(A, lda, k, j);
        }
    }
    /* Row k itself becomes (-sign(x0) |x|, 0, ...). The zero is computed, 0 * norm = +0
     * exactly (norm finite and > 0), not a literal: a loop storing a constant is compiled
     * into a memset call, which costs ~40 instructions for these few elements on the
     * Cortex-M4F (issue 21). */
    {
        const rfe_real_t zero = RFE_R(0.0) * norm;
        AT(A, lda, k, k) = -sgn * norm;
        for (j = k + 1u; j < g0; ++j) {
            AT(A, lda, k, j) = zero;
        }
        for (j = g1; j < end; ++j) {
            AT(A, lda, k, j) = zero;
        }
    }
}

/* Non-negative diagonal of the lower-triangular rows x rows S in A: flipping a column's sign
 * leaves S S^T unchanged. */
static TRIA_INLINE void make_diagonal_nonnegative(rfe_real_t *A, size_t rows, size_t lda)
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

/* Tria of the checked rows x cols A (ld lda): the whole reduction, inlined by rfe_qr_tria
 * once with run-time sizes and once per fixed shape, where the constant sizes let the
 * compiler unroll the loops; every instance performs the same operations in the same
 * order, so the results agree bit for bit. */
static TRIA_INLINE rfe_status_t tria_reduce(rfe_real_t *A, size_t rows, size_t cols, size_t lda,
                                             int tri)
{
    rfe_real_t bigs[RFE_TRIA_ROWS_SZ];
    int exps[RFE_TRIA_ROWS_SZ];
    int scaled = 0;
    size_t i;
    size_t k;

    if ((rows_plainly_safe(A, rows, cols, lda, tri) == 0) &&
        (row_maxima(A, rows, cols, lda, bigs, &scaled) != 0)) {
        return RFE_ERR_NONFINITE;
    }
    /* Rows are scaled by powers of two so the sums of squares neither overflow nor
     * underflow: with A = D A', S = D S'. Power-of-two scaling is exact, so the result is
     * the unscaled reduction's wherever that stays in the normal range; rows whose maxima
     * all lie in [TRIA_SAFE_LO, TRIA_SAFE_HI] (every matrix of the estimator) are reduced
     * unscaled. */
    if (scaled != 0) {
        for (i = 0u; i < rows; ++i) {
            exps[i] = max_exponent(bigs[i]);
            scale_row(&AT(A, lda, i, 0u), cols, -exps[i]);
        }
    }
    /* A^T = Q R  <=>  A Q = R^T = [S 0]: zero each row's tail right of the diagonal. */
    for (k = 0u; k < rows; ++k) {
        size_t g0;
        size_t g1;
        size_t end;
        rfe_real_t norm;
        tail_span(tri, rows, cols, k, &g0, &g1, &end); /* v's span: row k's tail */
        norm = row_tail_norm(A, lda, k, g0, g1, end);
        if (norm > RFE_R(0.0)) {
            reflect_row(A, rows, lda, k, g0, g1, end, norm);
        }
        /* norm == 0: the tail is already zero (rank-deficient input); S(k,k) = 0. */
    }
    make_diagonal_nonnegative(A, rows, lda);
    if (scaled != 0) {
        for (i = 0u; i < rows; ++i) {
            scale_row(&AT(A, lda, i, 0u), i + 1u, exps[i]); /* S = D S' */
        }
    }
    return RFE_OK;
}

/* The shapes the filters reduce in their scratch (ld RFE_TRIA_COLS_SZ) with n = 4 states
 * and m = 3 measurements (the firmware's RFE_N_MAX, RFE_M_MAX; issue 21): the random
 * walk's [S, S_Q] (4 x 8), the innovation's [Zc, S_R] (3 x 11) and the posterior's
 * [Xc - K Zc, K S_R] (4 x 11); not a process's [X*c, S_Q] (4 x 12), which the estimator
 * never reduces (its state is a random walk) and whose copy would cost 3 kB of flash, over
 * the Cortex-M4F's 64 kB budget. Each gets its own
 * unrolled copy of tria_reduce (the checks above and lda == RFE_TRIA_COLS_SZ keep it in
 * bounds): the walk's in rfe_qr_tria_pair (both blocks triangular, tri 2), the innovation's
 * in rfe_qr_tria_lt (S_R triangular, tri 1), the posterior's in rfe_qr_tria; any other shape
 * or leading dimension takes the run-time one. */
/* 1 when Tria takes a rows x cols matrix of leading dimension lda (rfe/component/qr.h). */
static TRIA_INLINE int tria_size_ok(size_t rows, size_t cols, size_t lda)
{
    return ((rows >= 1u) && (rows <= RFE_TRIA_ROWS_SZ) && (cols >= rows) &&
            (cols <= RFE_TRIA_COLS_LIMIT_SZ) && (lda >= cols))
               ? 1
               : 0;
}

rfe_status_t rfe_qr_tria(rfe_real_t *A, size_t rows, size_t cols, size_t lda)
{
    rfe_status_t st;

    if (A == NULL) {
        return RFE_ERR_NULL;
    }
    if (tria_size_ok(rows, cols, lda) == 0) {
        return RFE_ERR_SIZE;
    }
    if ((lda == RFE_TRIA_COLS_SZ) && (rows == 4u) && (cols == 11u)) {
        st = tria_reduce(A, 4u, 11u, RFE_TRIA_COLS_SZ, 0);
    } else {
        st = tria_reduce(A, rows, cols, lda, 0);
    }
    return st;
}

/* The innovation's shape (3 x 11) unrolled with its shorter tails (tria_reduce, tri 1); any
 * other shape is rfe_qr_tria's dense reduction, the same result. */
rfe_status_t rfe_qr_tria_lt(rfe_real_t *A, size_t rows, size_t cols, size_t lda)
{
    rfe_status_t st;
    if ((A != NULL) && (lda == RFE_TRIA_COLS_SZ) && (rows == 3u) && (cols == 11u)) {
        st = tria_reduce(A, 3u, 11u, RFE_TRIA_COLS_SZ, 1);
    } else {
        st = rfe_qr_tria(A, rows, cols, lda);
    }
    return st;
}

/* The random walk's shape (n = 4) unrolled with its tails (tria_reduce, tri 2); any other n
 * is rfe_qr_tria's dense reduction, the same result. */
rfe_status_t rfe_qr_tria_pair(rfe_real_t *A, size_t n, size_t lda)
{
    rfe_status_t st;
    if ((A != NULL) && (lda == RFE_TRIA_COLS_SZ) && (n == 4u)) {
        st = tria_reduce(A, 4u, 8u, RFE_TRIA_COLS_SZ, 2);
    } else {
        st = rfe_qr_tria(A, n, 2u * n, lda);
    }
    return st;
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

/* x_i = (b_i - sum_{j<i} L_ij x_j) / L_ii, column by column (checked arguments). */
static TRIA_INLINE void solve_lower_body(const rfe_real_t *L, size_t n, size_t ldl,
                                         rfe_real_t *B, size_t ncols, size_t ldb)
{
    size_t c;
    size_t i;
    size_t j;
    for (c = 0u; c < ncols; ++c) {
        for (i = 0u; i < n; ++i) {
            rfe_real_t acc = AT(B, ldb, i, c);
            for (j = 0u; j < i; ++j) {
                acc -= AT(L, ldl, i, j) * AT(B, ldb, j, c);
            }
            AT(B, ldb, i, c) = acc / AT(L, ldl, i, i);
        }
    }
}

/* x_i = (b_i - sum_{j>i} L_ji x_j) / L_ii, from the last row up (checked arguments). */
static TRIA_INLINE void solve_lower_t_body(const rfe_real_t *L, size_t n, size_t ldl,
                                           rfe_real_t *B, size_t ncols, size_t ldb)
{
    size_t c;
    size_t j;
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
}

/* The solves unrolled, like Tria, for the gain's shape with n = 4 states and m = 3
 * measurements (issue 21): S_zz (3 x 3) against P_xz^T (4 columns); the same operations in
 * the same order as the run-time loops, so the same results bit for bit. (The information's
 * S- (4 x 4) against P_xz (3 columns) is left to the run-time loops: the paper preset does not
 * gate, and its copy would cost 1 kB of the Cortex-M4F's flash.) */
rfe_status_t rfe_qr_solve_lower(const rfe_real_t *L, size_t n, size_t ldl, rfe_real_t *B,
                                size_t ncols, size_t ldb)
{
    const rfe_status_t st = check_solve(L, n, ldl, B, ncols, ldb);

    if (st != RFE_OK) {
        return st;
    }
    if ((n == 3u) && (ncols == 4u)) {
        solve_lower_body(L, 3u, ldl, B, 4u, ldb);
    } else {
        solve_lower_body(L, n, ldl, B, ncols, ldb);
    }
    return RFE_OK;
}

rfe_status_t rfe_qr_solve_lower_t(const rfe_real_t *L, size_t n, size_t ldl,
                                  rfe_real_t *B, size_t ncols, size_t ldb)
{
    const rfe_status_t st = check_solve(L, n, ldl, B, ncols, ldb);

    if (st != RFE_OK) {
        return st;
    }
    if ((n == 3u) && (ncols == 4u)) {
        solve_lower_t_body(L, 3u, ldl, B, 4u, ldb);
    } else {
        solve_lower_t_body(L, n, ldl, B, ncols, ldb);
    }
    return RFE_OK;
}
