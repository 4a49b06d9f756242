/**
 * @file chol_q31.h
 * @brief Fixed-point twin of rfe/component/chol.h: Cholesky factorisation on int32 Q values, used
 *        only by the full-covariance CKF baseline (rfe/component/ckf_q31.h).
 */
#ifndef RFE_CHOL_Q31_H
#define RFE_CHOL_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"
#include "rfe/config.h"
#include "rfe/fixed.h"

/**
 * L lower-triangular with L L^T = P, read from the lower triangle of P (n x n, row-major,
 * leading dimensions ldp, ldl; P in Q(q_p), L in Q(q_l), q_p <= 2 q_l <= q_p + 31). L must
 * not alias P; its upper triangle is set to zero.
 * Every pivot d_j = P_jj - sum_k L_jk^2 and numerator P_ij - sum_k L_ik L_jk is exact in
 * int64 (Q(2 q_l); P shifted up exactly; a sum that left the int64 range would saturate and
 * be counted), L_jj = round(sqrt(d_j)) and L_ij = round(numerator / L_jj) are exactly
 * rounded, so L L^T = P + E with |E_ij| <= L_jj / 2 LSB (i > j) and
 * |E_jj| <= L_jj LSB + 1/4 LSB^2 (LSB of Q(q_l)): the computed factor is the exact factor of
 * a matrix within rounding of P. An entry beyond the int32 range saturates (counted).
 * @param sat saturation counter (required; added to only on success)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE (n = 0 or > RFE_N_MAX, ld < n);
 *         RFE_ERR_RANGE (formats outside q_p <= 2 q_l <= q_p + 31, q_p or q_l > 31);
 *         RFE_ERR_NOT_POSITIVE_DEFINITE when a pivot is not > 0 (the contents of L are then
 *         unspecified, *sat untouched).
 */
RFE_NODISCARD rfe_status_t rfe_chol_factor_q31(const rfe_fix_t *P, size_t n, size_t ldp,
                                               rfe_fix_t *L, size_t ldl, unsigned int q_p,
                                               unsigned int q_l, uint32_t *sat);

#endif /* RFE_CHOL_Q31_H */
