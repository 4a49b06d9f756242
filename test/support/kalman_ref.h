/**
 * @file kalman_ref.h
 * @brief Test support: the textbook Kalman filter, in double with explicit matrices, that
 *        the SCKF and CKF tests use as the exact reference on the linear-Gaussian model
 *        x_next = F x + w (cov Q), y = H x + v (cov R). Each test fills kf_ref_t from its
 *        own problem (prior, Q, R); F and H are passed per step.
 */
#ifndef RFE_TEST_KALMAN_REF_H
#define RFE_TEST_KALMAN_REF_H

#include <stddef.h>

#include "rfe/config.h"
#include "rfe/types.h"

/** Reference filter state (used by the UKF reference of test_ckf_flt.c as well). */
typedef struct {
    size_t n;
    size_t m;
    double x[RFE_N_MAX];
    double P[RFE_N_MAX][RFE_N_MAX];
    double Q[RFE_N_MAX][RFE_N_MAX];
    double R[RFE_N_MAX][RFE_N_MAX]; /**< leading m x m block (needs RFE_M_MAX <= RFE_N_MAX) */
} kf_ref_t;

/** x- = F x,  P- = F P F^T + Q  (F NULL: identity). */
void kf_ref_predict(kf_ref_t *r, const double F[][RFE_N_MAX]);

/** Sz = H P- H^T + R,  K = P- H^T Sz^-1 (Cholesky solve),  x = x- + K (y - H x-),
 *  P = (I - K H) P- (I - K H)^T + K R K^T  (Joseph form). H is m x n. */
void kf_ref_update(kf_ref_t *r, const double H[][RFE_N_MAX], const rfe_real_t *y);

#endif /* RFE_TEST_KALMAN_REF_H */
