/**
 * @file ckf_q31.h
 * @brief Fixed-point twin of rfe/component/ckf.h: the full-covariance cubature Kalman filter (the
 *        paper's baseline, MODEL.md §6) on int32 Q values.
 *
 * Same API shape as the float CKF: it carries P and takes a Cholesky factor of it at every
 * step, P = P- - K Pzz K^T (the textbook form, no symmetrisation or Joseph form). It exists
 * to measure what the square-root form buys in fixed point (docs/FIXED_POINT.md, "Linear
 * algebra and filters"): the SCKF carries standard deviations (1e-3 .. 0.3, >= 20 bits in
 * Q30), this filter variances (1e-6 .. 0.1 in Q31, where a variance of 1e-6 keeps 2147 LSB,
 * 11 bits). When P stops being positive definite the step fails with
 * RFE_ERR_NOT_POSITIVE_DEFINITE and leaves the state as it was.
 *
 * Formats (fractional bits): x, x0, the points and the clamp bounds Q29 (RFE_Q31_QX);
 * P, P0, Q Q31 (RFE_Q31_QP, mu^2, range +-1, LSB 4.7e-10); y, h(x) Q24 (RFE_Q31_QZ);
 * R and Pzz Q24 (RFE_Q31_QR, (m/s^2)^2, range +-128, LSB 6.0e-8); internally chol(P) Q30
 * (as S), chol(Pzz) Q24, P_xz and K Pzz Q30 (mu m/s^2), the gain K Q26 (mu per m/s^2, +-32).
 * Saturation is counted in the state's `sat` (added to only by a successful step).
 */
#ifndef RFE_CKF_Q31_H
#define RFE_CKF_Q31_H

#include "rfe/component/sckf_q31.h"

/** Fractional bits of the covariances P, P0, Q [mu^2]. */
#define RFE_Q31_QP 31u
/** Fractional bits of the measurement covariances R, Pzz [(m/s^2)^2]. */
#define RFE_Q31_QR 24u

/** CKF state (caller-owned). */
typedef struct {
    uint32_t magic;
    size_t n;
    size_t m;
    rfe_fix_t x[RFE_N_MAX];              /**< posterior mean (Q29) */
    rfe_fix_t P[RFE_N_MAX * RFE_N_MAX];  /**< posterior covariance, ld RFE_N_MAX (Q31) */
    rfe_fix_t Q[RFE_N_MAX * RFE_N_MAX];  /**< process-noise covariance (Q31) */
    rfe_fix_t R[RFE_M_MAX * RFE_M_MAX];  /**< measurement-noise covariance (Q24) */
    uint32_t sat;                        /**< saturation events since init (saturating) */
    rfe_cub_scratch_q31_t w;             /**< scratch (the Cholesky factor of P, Q30, in w.A
                                              and the candidate covariance, Q31, in w.B) */
} rfe_ckf_q31_t;

/** Initialises from x0 (n, Q29), P0 (n x n, Q31), Q (n x n, Q31), R (m x m, Q24), all full
 *  symmetric matrices (leading dimension = columns). The saturation counter starts at 0.
 *  @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE (as rfe_sckf_init_q31); RFE_ERR_ABI (below).
 *  The filter is untouched on every error.
 *  @note The call goes through a macro of the full name that adds the caller's
 *        sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *        nothing written, when the caller was compiled with other maxima or another
 *        number type than the library. */
RFE_NODISCARD rfe_status_t rfe_ckf_init_q31(rfe_ckf_q31_t *f, size_t n, size_t m,
                                            const rfe_fix_t *x0, const rfe_fix_t *P0,
                                            const rfe_fix_t *Q, const rfe_fix_t *R,
                                            size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_CKF_Q31_IMPL), where the name is the function's own. */
#if !defined(RFE_CKF_Q31_IMPL)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_ckf_init_q31(f, n, m, x0, P0, Q, R) \
    rfe_ckf_init_q31((f), (n), (m), (x0), (P0), (Q), (R), \
                     sizeof(rfe_ckf_q31_t), RFE_CONFIG_Q31)
#endif
/** Time update: points from chol(P), P- = sum w X* X*^T - x- x-^T + Q (the moment sums
 *  in int64 on products rounded to Q54, one rounding to Q31).
 *  @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NOT_POSITIVE_DEFINITE;
 *  the callback's error (state untouched). */
RFE_NODISCARD rfe_status_t rfe_ckf_predict_q31(rfe_ckf_q31_t *f, rfe_process_fn_q31_t process,
                                               void *ctx);
/** @p k time updates of the random walk at once (ckf.h's rfe_ckf_predict_steps): x- = x,
 *  P- = P + k Q, exact in int64 then saturating to Q31 (counted); k = 0 changes nothing.
 *  @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED. */
RFE_NODISCARD rfe_status_t rfe_ckf_predict_steps_q31(rfe_ckf_q31_t *f, uint32_t k);
/** Measurement update: Pzz = sum w Z Z^T - z z^T + R, Pxz = sum w X Z^T - x- z^T,
 *  K = Pxz Pzz^-1 (Cholesky of Pzz, two triangular solves), x = x- + K (y - z),
 *  P = P- - K Pzz K^T.
 *  @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NOT_POSITIVE_DEFINITE (P-
 *  or Pzz); the callback's error (state untouched). */
RFE_NODISCARD rfe_status_t rfe_ckf_update_q31(rfe_ckf_q31_t *f, rfe_measure_fn_q31_t measure,
                                              void *ctx, const rfe_fix_t *y);
/** Mean (Q29) and sqrt(max(P_ii, 0)) (Q30, exactly rounded); either may be NULL. */
RFE_NODISCARD rfe_status_t rfe_ckf_get_q31(const rfe_ckf_q31_t *f, rfe_fix_t *x, rfe_fix_t *sd);
/** Projects the mean onto [lo, hi] (Q29; P untouched); RFE_ERR_RANGE if lo > hi. */
RFE_NODISCARD rfe_status_t rfe_ckf_clamp_q31(rfe_ckf_q31_t *f, rfe_fix_t lo, rfe_fix_t hi,
                                             int *clamped);

#endif /* RFE_CKF_Q31_H */
