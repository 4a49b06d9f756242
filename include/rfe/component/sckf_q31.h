/**
 * @file sckf_q31.h
 * @brief Fixed-point twin of rfe/component/sckf.h: the generic square-root cubature Kalman filter
 *        on int32 Q values (MODEL.md §6, docs/ESTIMATOR.md steps 5-7, docs/FIXED_POINT.md
 *        "Linear algebra and filters").
 *
 * Same API shape as the float filter: the process model f and the measurement model h are
 * callbacks with a context pointer; state, square-root factors and scratch live in the
 * caller-owned rfe_sckf_q31_t; sizes are bounded by RFE_N_MAX / RFE_M_MAX; matrices passed
 * in or out are row-major, n x n (or m x m), leading dimension = columns. On any error the
 * filter state (its saturation counter included) is left exactly as it was.
 *
 * Number formats at the interface (fractional bits, int32):
 *  - RFE_Q31_QX = 29: the mean x, x0, the cubature points handed to the callbacks and
 *    returned by the process model, the clamp bounds (range +-4, LSB 1.9e-9);
 *  - RFE_Q31_QS = 30: S, S0, S_Q, the centred state deviations and the standard deviations
 *    of rfe_sckf_get_q31 (range +-2, LSB 9.3e-10);
 *  - RFE_Q31_QZ = 24: measurements y, h(x) from the measurement model, S_R (filter and step
 *    factor), S_zz and the innovations (range +-128, LSB 6.0e-8);
 *  - RFE_Q31_QI = 10: the information I_k and the gate threshold info_min [1/mu^2] (range
 *    +-2.1e6, LSB 9.8e-4);
 *  - RFE_Q31_QC = 24: the factor c of rfe_sckf_scale_q31 (range (0, 128), LSB 6.0e-8).
 * Internal formats (docs/FIXED_POINT.md): the whitened deviations S_zz \ [Zc, S_R] and the
 * whitened gain G = P_xz S_zz^-T in Q30 (both bounded by construction: the rows of the
 * first are orthonormal, |G_ir| <= sd_i); the whitened innovation S_zz \ (y - z) in Q24;
 * the statistical linearisation J in Q20 [m/s^2 per mu, +-2048]; S_R \ J in Q16 [1/mu].
 *
 * Saturation (rfe/fixed.h): results beyond a format's range are clamped symmetrically and
 * counted in the state's counter `sat` (itself saturating at UINT32_MAX), which a step adds
 * to only when it succeeds. Integer arithmetic only: bit-identical on every platform.
 */
#ifndef RFE_SCKF_Q31_H
#define RFE_SCKF_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"
#include "rfe/config.h"
#include "rfe/fixed.h"

/** Fractional bits of the mean, the cubature points and the clamp bounds (mu). */
#define RFE_Q31_QX 29u
/** Fractional bits of the square-root factors S, S0, S_Q, the centred deviations, sd. */
#define RFE_Q31_QS 30u
/** Fractional bits of measurements, h(x), S_R, S_zz, innovations [m/s^2, rad/s^2]. */
#define RFE_Q31_QZ 24u
/** Fractional bits of the information I_k and of info_min [1/mu^2]. */
#define RFE_Q31_QI 10u
/** Fractional bits of the factor c of rfe_sckf_scale_q31. */
#define RFE_Q31_QC 24u

/** Process model x_next = f(x) for one cubature point (n values, Q29 in and out). */
typedef rfe_status_t (*rfe_process_fn_q31_t)(void *ctx, const rfe_fix_t *x, rfe_fix_t *x_next,
                                             size_t n);
/** Measurement model z = h(x) for one cubature point (n values in Q29, m out in Q24). */
typedef rfe_status_t (*rfe_measure_fn_q31_t)(void *ctx, const rfe_fix_t *x, rfe_fix_t *z,
                                             size_t n, size_t m);

/** Scratch shared by the fixed-point cubature filters (contents meaningless between calls;
 *  formats of each use in src/filters/sckf_q31.c and src/filters/ckf_q31.c). */
typedef struct {
    rfe_fix_t pts[RFE_CUB_MAX * RFE_N_MAX];     /**< cubature points, one per row (Q29) */
    rfe_fix_t zpts[RFE_CUB_MAX * RFE_M_MAX];    /**< their measurements, one per row (Q24) */
    rfe_fix_t A[RFE_N_MAX * RFE_TRIA_COLS_MAX]; /**< Tria() input / output, solves */
    rfe_fix_t B[RFE_N_MAX * RFE_TRIA_COLS_MAX]; /**< second work matrix */
    rfe_fix_t Kt[RFE_M_MAX * RFE_N_MAX];        /**< gain, transposed (m x n, ld RFE_N_MAX) */
    rfe_fix_t Szz[RFE_M_MAX * RFE_M_MAX];       /**< innovation sqrt-covariance (CKF: Pzz) */
    rfe_fix_t Lz[RFE_M_MAX * RFE_M_MAX];        /**< CKF: Cholesky factor of Pzz */
    rfe_fix_t xn[RFE_N_MAX];                    /**< candidate mean (Q29) */
    rfe_fix_t zhat[RFE_M_MAX];                  /**< predicted measurement (Q24) */
} rfe_cub_scratch_q31_t;

/** The innovation of one measurement update, before the update (rfe_sckf_update_ex_q31's
 *  innov_out; sckf.h's rfe_sckf_innov_t). */
typedef struct {
    rfe_fix_t nu[RFE_M_MAX];              /**< y - z_hat (Q24, saturating) */
    rfe_fix_t Szz[RFE_M_MAX * RFE_M_MAX]; /**< Tria([Zc, SR]) (Q24), ld RFE_M_MAX, upper part 0 */
    rfe_fix_t zz[RFE_M_MAX];              /**< diag(Zc Zc^T) (Q24, saturating) */
} rfe_sckf_innov_q31_t;

/** SCKF state (caller-owned). Fields are read-only for the caller. */
typedef struct {
    uint32_t magic;                       /**< set by init; guards use before init */
    size_t n;                             /**< state dimension, 1..RFE_N_MAX */
    size_t m;                             /**< measurement dimension, 1..RFE_M_MAX */
    rfe_fix_t x[RFE_N_MAX];               /**< posterior mean (Q29) */
    rfe_fix_t S[RFE_N_MAX * RFE_N_MAX];   /**< lower-triangular sqrt of P, ld RFE_N_MAX (Q30) */
    rfe_fix_t SQ[RFE_N_MAX * RFE_N_MAX];  /**< sqrt of Q, ld RFE_N_MAX (Q30) */
    rfe_fix_t SR[RFE_M_MAX * RFE_M_MAX];  /**< sqrt of R, ld RFE_M_MAX (Q24) */
    uint32_t sat;                         /**< saturation events since init (saturating) */
    rfe_cub_scratch_q31_t w;              /**< scratch */
} rfe_sckf_q31_t;

/**
 * Initialises the filter: x0 (n, Q29), S0 (n x n lower-triangular sqrt of P0, Q30),
 * SQ (n x n, Q30), SR (m x m, Q24). Only the lower triangles of S0, SQ, SR are read.
 * The saturation counter starts at 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE (n outside 1..RFE_N_MAX or above 8, the largest
 *         n the cubature constants are tabulated for; m outside 1..RFE_M_MAX); RFE_ERR_ABI
 *         (below). The filter is untouched on every error.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_init_q31(rfe_sckf_q31_t *f, size_t n, size_t m,
                                             const rfe_fix_t *x0, const rfe_fix_t *S0,
                                             const rfe_fix_t *SQ, const rfe_fix_t *SR,
                                             size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_SCKF_Q31_IMPL), where the name is the function's own. */
#if !defined(RFE_SCKF_Q31_IMPL)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_sckf_init_q31(f, n, m, x0, S0, SQ, SR) \
    rfe_sckf_init_q31((f), (n), (m), (x0), (S0), (SQ), (SR), \
                      sizeof(rfe_sckf_q31_t), RFE_CONFIG_Q31)
#endif

/**
 * Time update: X_j = S xi_j + x, X*_j = f(X_j), x- = mean X*_j,
 * S- = Tria([(X*_j - x-)/sqrt(2n), SQ]). @p process NULL means f(x) = x (random walk).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; the callback's error (state
 *         untouched).
 */
RFE_NODISCARD rfe_status_t rfe_sckf_predict_q31(rfe_sckf_q31_t *f, rfe_process_fn_q31_t process,
                                                void *ctx);

/**
 * @p k time updates of the random walk at once (sckf.h's rfe_sckf_predict_steps): x- = x,
 * S- = Tria([S, sqrt(k) SQ]), sqrt(k) exactly rounded in Q16, each sqrt(k) SQ_ij rounded
 * once to Q30 (saturating, counted); k = 0 changes nothing. Q30 holds an sd below 2, so a k
 * beyond the count at which sqrt(k) times a row norm of SQ reaches 1 (an sd of 1 added:
 * more than any friction's range) acts as that count (the float twin has no such limit).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED (state untouched).
 */
RFE_NODISCARD rfe_status_t rfe_sckf_predict_steps_q31(rfe_sckf_q31_t *f, uint32_t k);

/**
 * Measurement update with measurement y (m values, Q24): cubature points from S-,
 * Z_j = h(X_j), S_zz = Tria([Zc, SR]), then, in whitened form (algebraically the float
 * twin's K = (P_xz / S_zz^T) / S_zz): W = S_zz \ [Zc, SR], G = [Xc 0] W^T (= K S_zz),
 * x = x- + G (S_zz \ (y - z)), S = Tria([Xc, 0] - G W) (= Tria([Xc - K Zc, K SR])).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NOT_POSITIVE_DEFINITE
 *         (S_zz singular); the callback's error. On error nothing is written.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_update_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure,
                                               void *ctx, const rfe_fix_t *y);

/**
 * Measurement update with a step-specific noise factor and an information gate
 * (docs/ESTIMATOR.md steps 5-6), as rfe_sckf_update_ex of the float filter. From the
 * predicted x-, S- (call after rfe_sckf_predict_q31):
 *  1. cubature points X_j = S- xi_j + x-, Z_j = h(X_j), z, centred Xc (n x 2n), Zc;
 *  2. when @p info_min > 0 or @p info_out is not NULL, the Fisher information per state:
 *     U = S- \ Xc, J^T = S-^T \ (U Zc^T) (= S-^T \ (S- \ P_xz)), W = SR \ J,
 *     I_k = sum_r W_rk^2 (Q10, saturating); with info_min > 0 and max_k I_k < info_min the
 *     step is held: x, S stay the predicted ones, *updated = 0;
 *  3. otherwise the update of rfe_sckf_update_q31 with SR in place of the filter's S_R,
 *     reusing the points and Z_j of 1; *updated = 1.
 * With SR = NULL (the filter's S_R), info_min <= 0 and info_out = NULL this is
 * rfe_sckf_update_q31, bit for bit.
 * @param SR        m x m lower-triangular sqrt of this step's R (Q24, only the lower triangle
 *                  is read, leading dimension m), or NULL for the filter's own S_R. The
 *                  information needs diag(SR) > 0.
 * @param info_min  gate threshold [1/mu^2] in Q10; <= 0: no gate.
 * @param info_out  n values I_k in Q10 (written on success, also when held), or NULL.
 * @param innov_out the innovation, S_zz and diag(Zc Zc^T) of the predicted points (written on
 *                  success, also when held: S_zz is then computed for it; its saturations
 *                  counted in f->sat), or NULL.
 * @param updated   required: 1 when the state was updated, 0 when held.
 * @return RFE_OK (updated or held); RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED;
 *         RFE_ERR_NOT_POSITIVE_DEFINITE (S- or SR with a zero diagonal when the information is
 *         computed, S_zz singular); the callback's error. On error nothing is written.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_update_ex_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure,
                                                  void *ctx, const rfe_fix_t *y,
                                                  const rfe_fix_t *SR, rfe_fix_t info_min,
                                                  rfe_fix_t *info_out,
                                                  rfe_sckf_innov_q31_t *innov_out, int *updated);

/**
 * rfe_sckf_update_ex_q31 for a measurement function linear in the state, h(x) = H x (h(0) =
 * 0), as rfe_sckf_update_linear of the float filter: z = h(x-), Xc = S- (Q30, exact),
 * Zc = [h(S- e_1) .. h(S- e_n)] (the columns rounded to Q29 for the callback, Q24), n
 * columns instead of 2n (docs/ESTIMATOR.md "The linear update", docs/FIXED_POINT.md).
 * Arguments, outputs and errors as rfe_sckf_update_ex_q31's.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_update_linear_q31(rfe_sckf_q31_t *f,
                                                      rfe_measure_fn_q31_t measure, void *ctx,
                                                      const rfe_fix_t *y, const rfe_fix_t *SR,
                                                      rfe_fix_t info_min, rfe_fix_t *info_out,
                                                      rfe_sckf_innov_q31_t *innov_out,
                                                      int *updated);

/**
 * Scales the square-root factor, S <- c S (P <- c^2 P), c in Q24 (RFE_Q31_QC). @p c must be
 * > 0 (else RFE_ERR_RANGE, S untouched). An element of c S beyond the Q30 range saturates
 * (counted in f->sat).
 */
RFE_NODISCARD rfe_status_t rfe_sckf_scale_q31(rfe_sckf_q31_t *f, rfe_fix_t c);

/**
 * Copies the mean (n, Q29) and the standard deviations sqrt(diag(S S^T)) (n, Q30, the
 * exactly rounded norm of each row of S); either may be NULL. An sd at or above 2 (outside
 * Q30) is reported as RFE_FIX_MAX; the state is const, so this is not counted in f->sat
 * (a filter of mu never gets there: S entries are standard deviations of mu).
 */
RFE_NODISCARD rfe_status_t rfe_sckf_get_q31(const rfe_sckf_q31_t *f, rfe_fix_t *x, rfe_fix_t *sd);

/** Projects the mean onto [lo, hi] (Q29) element-wise (S untouched); *clamped = 1 if any moved.
 *  @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE if lo > hi. */
RFE_NODISCARD rfe_status_t rfe_sckf_clamp_q31(rfe_sckf_q31_t *f, rfe_fix_t lo, rfe_fix_t hi,
                                              int *clamped);

#endif /* RFE_SCKF_Q31_H */
