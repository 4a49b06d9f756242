/**
 * @file ckf.h
 * @brief Full-covariance cubature Kalman filter: the paper's baseline (MODEL.md §6).
 *
 * Same API shape as the SCKF, but carries P and takes a Cholesky factor of it at every
 * step, P = P- - K Pzz K^T. Algebraically identical to the SCKF; it differs in finite
 * precision, where P can lose positive definiteness (the step then fails with
 * RFE_ERR_NOT_POSITIVE_DEFINITE and leaves the state as it was).
 */
#ifndef RFE_CKF_H
#define RFE_CKF_H

#include "rfe/component/sckf.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_ckf_init    rfe_ckf_init_f64
#define rfe_ckf_predict rfe_ckf_predict_f64
#define rfe_ckf_predict_steps rfe_ckf_predict_steps_f64
#define rfe_ckf_update  rfe_ckf_update_f64
#define rfe_ckf_get     rfe_ckf_get_f64
#define rfe_ckf_clamp   rfe_ckf_clamp_f64
#else
#define rfe_ckf_init    rfe_ckf_init_f32
#define rfe_ckf_predict rfe_ckf_predict_f32
#define rfe_ckf_predict_steps rfe_ckf_predict_steps_f32
#define rfe_ckf_update  rfe_ckf_update_f32
#define rfe_ckf_get     rfe_ckf_get_f32
#define rfe_ckf_clamp   rfe_ckf_clamp_f32
#endif

/** CKF state (caller-owned). */
typedef struct {
    uint32_t magic;
    size_t n;
    size_t m;
    rfe_real_t x[RFE_N_MAX];              /**< posterior mean */
    rfe_real_t P[RFE_N_MAX * RFE_N_MAX];  /**< posterior covariance, ld RFE_N_MAX */
    rfe_real_t Q[RFE_N_MAX * RFE_N_MAX];  /**< process-noise covariance */
    rfe_real_t R[RFE_M_MAX * RFE_M_MAX];  /**< measurement-noise covariance */
    rfe_real_t L[RFE_N_MAX * RFE_N_MAX];  /**< scratch: Cholesky factor */
    rfe_real_t Pn[RFE_N_MAX * RFE_N_MAX]; /**< scratch: candidate covariance */
    rfe_cub_scratch_t w;                  /**< scratch */
} rfe_ckf_t;

/**
 * Initialises from x0 (n), P0 (n x n), Q (n x n), R (m x m), all full symmetric matrices.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE; RFE_ERR_NONFINITE; RFE_ERR_ABI (below). The
 *         filter is untouched on every error.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_ckf_init(rfe_ckf_t *f, size_t n, size_t m,
                                       const rfe_real_t *x0, const rfe_real_t *P0,
                                       const rfe_real_t *Q, const rfe_real_t *R,
                                       size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_CKF_IMPL), where the name is the function's own. */
#if !defined(RFE_CKF_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_ckf_init_f64(f, n, m, x0, P0, Q, R) \
    rfe_ckf_init_f64((f), (n), (m), (x0), (P0), (Q), (R), sizeof(rfe_ckf_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_ckf_init_f32(f, n, m, x0, P0, Q, R) \
    rfe_ckf_init_f32((f), (n), (m), (x0), (P0), (Q), (R), sizeof(rfe_ckf_t), RFE_CONFIG_REAL)
#endif
#endif
/** Time update: points from chol(P), P- = sum w X* X*^T - x- x-^T + Q. */
RFE_NODISCARD rfe_status_t rfe_ckf_predict(rfe_ckf_t *f, rfe_process_fn_t process,
                                          void *ctx);
/** @p k time updates of the random walk at once (a gap of k sample periods): x- = x,
 *  P- = P + k Q; k = 0 changes nothing. RFE_ERR_NONFINITE if P- overflows (state untouched). */
RFE_NODISCARD rfe_status_t rfe_ckf_predict_steps(rfe_ckf_t *f, uint32_t k);
/** Measurement update: Pzz = sum w Z Z^T - z z^T + R, Pxz = sum w X Z^T - x- z^T, K = Pxz Pzz^-1. */
RFE_NODISCARD rfe_status_t rfe_ckf_update(rfe_ckf_t *f, rfe_measure_fn_t measure,
                                         void *ctx, const rfe_real_t *y);
/** Mean and sqrt(diag(P)); either may be NULL. */
RFE_NODISCARD rfe_status_t rfe_ckf_get(const rfe_ckf_t *f, rfe_real_t *x, rfe_real_t *sd);
/** Projects the mean onto [lo, hi] (P untouched). */
RFE_NODISCARD rfe_status_t rfe_ckf_clamp(rfe_ckf_t *f, rfe_real_t lo, rfe_real_t hi,
                                        int *clamped);

#endif /* RFE_CKF_H */
