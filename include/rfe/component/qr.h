/**
 * @file qr.h
 * @brief Householder triangularisation Tria() and triangular solves (MODEL.md §6).
 *
 * Matrices are row-major with an explicit leading dimension (elements between rows).
 * Tria takes up to RFE_TRIA_ROWS_MAX rows and RFE_TRIA_COLS_LIMIT columns (rfe/config.h: the
 * generic filters' sizes or the tyre identifier's 10-state filter), the solves up to RFE_N_MAX
 * rows; no memory is allocated and nothing large sits on the stack (the input is reduced in
 * place).
 */
#ifndef RFE_QR_H
#define RFE_QR_H

#include "rfe/config.h"
#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_qr_tria          rfe_qr_tria_f64
#define rfe_qr_tria_lt       rfe_qr_tria_lt_f64
#define rfe_qr_tria_pair     rfe_qr_tria_pair_f64
#define rfe_qr_solve_lower   rfe_qr_solve_lower_f64
#define rfe_qr_solve_lower_t rfe_qr_solve_lower_t_f64
#else
#define rfe_qr_tria          rfe_qr_tria_f32
#define rfe_qr_tria_lt       rfe_qr_tria_lt_f32
#define rfe_qr_tria_pair     rfe_qr_tria_pair_f32
#define rfe_qr_solve_lower   rfe_qr_solve_lower_f32
#define rfe_qr_solve_lower_t rfe_qr_solve_lower_t_f32
#endif

/**
 * Tria(A), in place: A (rows x cols, cols >= rows) is reduced by Householder reflections
 * applied from the right (a QR of A^T) to [S 0], with S lower-triangular,
 * S S^T = A A^T and diag(S) >= 0. Rank-deficient input gives zero diagonal entries.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE if rows > RFE_TRIA_ROWS_MAX,
 *         cols > RFE_TRIA_COLS_LIMIT, cols < rows or lda < cols; RFE_ERR_NONFINITE if A holds NaN/Inf (A then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_qr_tria(rfe_real_t *A, size_t rows, size_t cols, size_t lda);

/**
 * Tria of A = [B, L] (rows x cols), L lower-triangular rows x rows in its last columns, its
 * strictly upper triangle zero (the twin of rfe_qr_tria_lt_q31): rfe_qr_tria's result on the
 * same arguments (bit for bit: the operations it skips, on the zeros right of L's diagonal,
 * are exact). The filters' innovation shape (3 x 11) has its own unrolled copy; any other
 * shape is rfe_qr_tria's reduction.
 * @return as rfe_qr_tria.
 */
RFE_NODISCARD rfe_status_t rfe_qr_tria_lt(rfe_real_t *A, size_t rows, size_t cols, size_t lda);

/**
 * Tria of A = [L1, L2] (n x 2n), both blocks lower-triangular with zero strictly upper
 * triangles (a random walk's [S, S_Q]; the twin of rfe_qr_tria_pair_q31): rfe_qr_tria(A, n,
 * 2n, lda)'s result, skipping its exact operations on the zeros (row k's tail is column k
 * and n..n+k); n = 4 has its own unrolled copy.
 * @return as rfe_qr_tria.
 */
RFE_NODISCARD rfe_status_t rfe_qr_tria_pair(rfe_real_t *A, size_t n, size_t lda);

/**
 * Forward substitution L X = B for X (L n x n lower-triangular, B n x ncols), X over B.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE; RFE_ERR_NOT_POSITIVE_DEFINITE if a diagonal
 *         entry of L is not > 0 (B then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_qr_solve_lower(const rfe_real_t *L, size_t n, size_t ldl,
                                             rfe_real_t *B, size_t ncols, size_t ldb);

/** Back substitution L^T X = B for X, same conventions as rfe_qr_solve_lower. */
RFE_NODISCARD rfe_status_t rfe_qr_solve_lower_t(const rfe_real_t *L, size_t n, size_t ldl,
                                               rfe_real_t *B, size_t ncols, size_t ldb);

#endif /* RFE_QR_H */
