/**
 * @file qr_q31.h
 * @brief Fixed-point twin of rfe/component/qr.h: Householder triangularisation Tria() and the two
 *        triangular solves on int32 Q values (docs/FIXED_POINT.md, "Linear algebra and
 *        filters").
 *
 * Matrices are row-major with an explicit leading dimension, as in rfe/component/qr.h; sizes are
 * bounded by RFE_N_MAX rows and RFE_TRIA_COLS_MAX columns; no memory is allocated. Integer
 * operations only (int32 storage, int64 intermediates), bit-identical on every platform.
 * Saturation follows rfe/fixed.h: symmetric clamping to [-INT32_MAX, INT32_MAX], each clamp
 * counted in the caller's `*sat` (added only when the call succeeds). Every function checks
 * all its arguments first and leaves its outputs (and `*sat`) untouched on an error.
 */
#ifndef RFE_QR_Q31_H
#define RFE_QR_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"
#include "rfe/config.h"
#include "rfe/fixed.h"

/**
 * Tria(A), in place: A (rows x cols, cols >= rows; every element in one common Q format)
 * is reduced by Householder reflections applied from the right (a QR of A^T) to [S 0], S
 * lower-triangular in the same Q format, S S^T = A A^T, diag(S) >= 0. Rank-deficient input
 * gives zero (or, for a nearly dependent row, rounding-size) diagonal entries; a zero row
 * gives an exactly zero row.
 *
 * Block scaling: before each reflection k, the unreduced part of every remaining row
 * (columns k..cols-1) is scaled by its own power of two so that its norm lies in
 * [2^29, 2^30) (exact when scaling up; rounded half up when scaling down, which happens
 * only for a row whose norm is >= 2^30 LSB, i.e. at the first reflection for rows near the
 * top of the format); the exponent is carried per row. Norms and dot products are exact in
 * (u)int64; the reflection coefficient 2 (a.v)/(v.v) is rounded to Q30 by long division.
 * Each finished entry S_ik is rounded (half up) into the input format as soon as it is
 * final. Error: S S^T = (A + E)(A + E)^T + F with |row i of E| <= 8 rows 2^-29 |a_i| (at
 * most ~6.4 units of 2^-29 of the remaining row norm per reflection: element roundings, the
 * Q30 coefficient, the rounded norm, a first down-scaling; derived in test/numerics/test_qr_q31.c)
 * and F from the final rounding of S (0.5 LSB per entry).
 * Saturation: an entry of S beyond the int32 range (a row norm above INT32_MAX) is clamped
 * and counted.
 * @param sat saturation counter (required)
 * @return RFE_OK; RFE_ERR_NULL (A or sat); RFE_ERR_SIZE if rows = 0, rows > RFE_N_MAX,
 *         cols < rows, cols > RFE_TRIA_COLS_MAX or lda < cols (A then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_qr_tria_q31(rfe_fix_t *A, size_t rows, size_t cols, size_t lda,
                                           uint32_t *sat);

/**
 * Tria of A = [B, L] (rows x cols), L lower-triangular rows x rows in its last columns (its
 * strictly upper triangle zero; e.g. a filter's [S, S_Q] or [Zc, S_R]): the result of
 * rfe_qr_tria_q31 on the same arguments, the same integers, without its operations on the
 * zeros right of L's diagonal (row i's tail ends at column cols - rows + i at every
 * reflection). L's strictly upper triangle is neither read nor written.
 * @param sat saturation counter (required)
 * @return as rfe_qr_tria_q31.
 */
RFE_NODISCARD rfe_status_t rfe_qr_tria_lt_q31(rfe_fix_t *A, size_t rows, size_t cols, size_t lda,
                                              uint32_t *sat);

/**
 * Tria of A = [L1, L2] (n x 2n), both blocks lower-triangular (the twin of rfe_qr_tria_pair):
 * rfe_qr_tria_lt_q31(A, n, 2n, lda, sat), the same integers as rfe_qr_tria_q31.
 * @return as rfe_qr_tria_q31.
 */
RFE_NODISCARD rfe_status_t rfe_qr_tria_pair_q31(rfe_fix_t *A, size_t n, size_t lda,
                                                uint32_t *sat);

/**
 * Forward substitution L X = B for X (L n x n lower-triangular in Q(ql), B n x ncols in
 * Q(qb)), X over B in Q(qx) with shift = qx - qb + ql (the convention of rfe_fix_div).
 * Each x_i = round((b_i 2^shift - sum_{j<i} L_ij x_j) / L_ii): the numerator is exact in
 * int64 (saturating, counted, if it ever left the int64 range) and the division exactly
 * rounded (ties away from zero), so the only error is 0.5 LSB of Q(qx) per element plus
 * the propagation of the earlier elements' rounding through L_ij / L_ii.
 * Only the lower triangle of L is read. An x_i beyond the int32 range saturates (counted).
 * @param shift in [0, 31]
 * @param sat   saturation counter (required)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE (n = 0 or > RFE_N_MAX, ldl < n, ncols = 0,
 *         ldb < ncols); RFE_ERR_RANGE (shift outside [0, 31]); RFE_ERR_NOT_POSITIVE_DEFINITE
 *         if a diagonal entry of L is not > 0 (B then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_qr_solve_lower_q31(const rfe_fix_t *L, size_t n, size_t ldl,
                                                  rfe_fix_t *B, size_t ncols, size_t ldb,
                                                  int shift, uint32_t *sat);

/** Back substitution L^T X = B for X, same conventions as rfe_qr_solve_lower_q31. */
RFE_NODISCARD rfe_status_t rfe_qr_solve_lower_t_q31(const rfe_fix_t *L, size_t n, size_t ldl,
                                                    rfe_fix_t *B, size_t ncols, size_t ldb,
                                                    int shift, uint32_t *sat);

#endif /* RFE_QR_Q31_H */
