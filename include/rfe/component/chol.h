/**
 * @file chol.h
 * @brief Cholesky factorisation, used only by the full-covariance CKF baseline.
 */
#ifndef RFE_CHOL_H
#define RFE_CHOL_H

#include "rfe/config.h"
#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_chol_factor rfe_chol_factor_f64
#else
#define rfe_chol_factor rfe_chol_factor_f32
#endif

/**
 * L lower-triangular with L L^T = P, read from the lower triangle of P (n x n, row-major,
 * leading dimensions ldp, ldl). L must not alias P; its upper triangle is set to zero.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE (n = 0 or > RFE_N_MAX, ld < n);
 *         RFE_ERR_NONFINITE; RFE_ERR_NOT_POSITIVE_DEFINITE when a pivot is not > 0
 *         (the contents of L are then unspecified).
 */
RFE_NODISCARD rfe_status_t rfe_chol_factor(const rfe_real_t *P, size_t n, size_t ldp,
                                          rfe_real_t *L, size_t ldl);

#endif /* RFE_CHOL_H */
