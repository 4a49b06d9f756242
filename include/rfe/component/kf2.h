/**
 * @file kf2.h
 * @brief A two-state linear Kalman filter (docs/OBSERVER.md: the velocity observer's three
 *        filters): state x = [x0, x1], symmetric covariance P stored as p00, p01, p11.
 *
 * Predict with F = [[1, f01], [0, 1]] and an input on the first state; update with one
 * scalar measurement. Both leave the filter untouched on error.
 */
#ifndef RFE_KF2_H
#define RFE_KF2_H

#include "rfe/config.h"
#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_kf2_init    rfe_kf2_init_f64
#define rfe_kf2_predict rfe_kf2_predict_f64
#define rfe_kf2_update  rfe_kf2_update_f64
#else
#define rfe_kf2_init    rfe_kf2_init_f32
#define rfe_kf2_predict rfe_kf2_predict_f32
#define rfe_kf2_update  rfe_kf2_update_f32
#endif

/** Two-state filter (caller-owned; plain data, copy it to keep a snapshot). */
typedef struct {
    rfe_real_t x[2];  /**< mean */
    rfe_real_t p00;   /**< covariance: var(x0) */
    rfe_real_t p01;   /**< covariance: cov(x0, x1) */
    rfe_real_t p11;   /**< covariance: var(x1) */
} rfe_kf2_t;

/**
 * Sets x = [x0, x1], P = diag(sd0^2, sd1^2).
 * @param[out] f         the filter.
 * @param[in]  x0, x1    the initial mean.
 * @param[in]  sd0, sd1  the initial sds, finite and >= 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE; RFE_ERR_RANGE (a negative sd);
 *         RFE_ERR_ABI (below). The filter is untouched on every error.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library (the state's layout depends on the number type).
 */
RFE_NODISCARD rfe_status_t rfe_kf2_init(rfe_kf2_t *f, rfe_real_t x0, rfe_real_t x1,
                                        rfe_real_t sd0, rfe_real_t sd1,
                                        size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_KF2_IMPL), where the name is the function's own. */
#if !defined(RFE_KF2_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_kf2_init_f64(f, x0, x1, sd0, sd1) \
    rfe_kf2_init_f64((f), (x0), (x1), (sd0), (sd1), sizeof(rfe_kf2_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_kf2_init_f32(f, x0, x1, sd0, sd1) \
    rfe_kf2_init_f32((f), (x0), (x1), (sd0), (sd1), sizeof(rfe_kf2_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * Time update x <- F x + [u, 0], P <- F P F^T + Q with F = [[1, f01], [0, 1]],
 * Q = [[q00, q01], [q01, q11]]:
 *   p00 <- p00 + 2 f01 p01 + f01^2 p11 + q00,  p01 <- p01 + f01 p11 + q01,  p11 <- p11 + q11.
 * @param[in,out] f  the filter.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE (an argument or the result).
 */
RFE_NODISCARD rfe_status_t rfe_kf2_predict(rfe_kf2_t *f, rfe_real_t f01, rfe_real_t u,
                                           rfe_real_t q00, rfe_real_t q11, rfe_real_t q01);

/**
 * Scalar measurement update with H = [h0, h1], innovation @p nu and noise variance @p r:
 * S = H P H^T + r, K = P H^T / S, x <- x + K nu, P <- P - K K^T S.
 * @param[in,out] f  the filter.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE (an argument or the result);
 *         RFE_ERR_RANGE (r < 0); RFE_ERR_NOT_POSITIVE_DEFINITE (S <= 0).
 */
RFE_NODISCARD rfe_status_t rfe_kf2_update(rfe_kf2_t *f, rfe_real_t h0, rfe_real_t h1,
                                          rfe_real_t nu, rfe_real_t r);

#endif /* RFE_KF2_H */
