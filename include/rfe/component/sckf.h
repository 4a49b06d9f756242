/**
 * @file sckf.h
 * @brief Generic square-root cubature Kalman filter (MODEL.md §6).
 *
 * The filter knows nothing about tyres: the process model f and measurement model h are
 * callbacks with a context pointer. State, square-root factors and scratch live in the
 * caller-owned rfe_sckf_t; sizes are bounded by RFE_N_MAX / RFE_M_MAX.
 * Matrices passed in or out are row-major, n x n (or m x m), leading dimension = columns.
 * On any error the filter state is left exactly as it was.
 */
#ifndef RFE_SCKF_H
#define RFE_SCKF_H

#include "rfe/config.h"
#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_sckf_init      rfe_sckf_init_f64
#define rfe_sckf_predict   rfe_sckf_predict_f64
#define rfe_sckf_predict_steps rfe_sckf_predict_steps_f64
#define rfe_sckf_update    rfe_sckf_update_f64
#define rfe_sckf_update_ex rfe_sckf_update_ex_f64
#define rfe_sckf_update_linear rfe_sckf_update_linear_f64
#define rfe_sckf_scale     rfe_sckf_scale_f64
#define rfe_sckf_get       rfe_sckf_get_f64
#define rfe_sckf_clamp     rfe_sckf_clamp_f64
#else
#define rfe_sckf_init      rfe_sckf_init_f32
#define rfe_sckf_predict   rfe_sckf_predict_f32
#define rfe_sckf_predict_steps rfe_sckf_predict_steps_f32
#define rfe_sckf_update    rfe_sckf_update_f32
#define rfe_sckf_update_ex rfe_sckf_update_ex_f32
#define rfe_sckf_update_linear rfe_sckf_update_linear_f32
#define rfe_sckf_scale     rfe_sckf_scale_f32
#define rfe_sckf_get       rfe_sckf_get_f32
#define rfe_sckf_clamp     rfe_sckf_clamp_f32
#endif

/** Process model x_next = f(x) for one cubature point (n values). */
typedef rfe_status_t (*rfe_process_fn_t)(void *ctx, const rfe_real_t *x, rfe_real_t *x_next,
                                         size_t n);
/** Measurement model z = h(x) for one cubature point (n values in, m out). */
typedef rfe_status_t (*rfe_measure_fn_t)(void *ctx, const rfe_real_t *x, rfe_real_t *z,
                                         size_t n, size_t m);

/** Scratch shared by the cubature filters (contents meaningless between calls). */
typedef struct {
    rfe_real_t pts[RFE_CUB_MAX * RFE_N_MAX];     /**< cubature points, one per row */
    rfe_real_t zpts[RFE_CUB_MAX * RFE_M_MAX];    /**< their measurements, one per row */
    rfe_real_t A[RFE_N_MAX * RFE_TRIA_COLS_MAX]; /**< Tria() input / output */
    rfe_real_t B[RFE_N_MAX * RFE_TRIA_COLS_MAX]; /**< second work matrix */
    rfe_real_t Kt[RFE_M_MAX * RFE_N_MAX];        /**< gain, transposed (m x n, ld RFE_N_MAX) */
    rfe_real_t Szz[RFE_M_MAX * RFE_M_MAX];       /**< innovation sqrt-covariance (CKF: Pzz) */
    rfe_real_t Lz[RFE_M_MAX * RFE_M_MAX];        /**< CKF: Cholesky factor of Pzz */
    rfe_real_t xn[RFE_N_MAX];                    /**< candidate mean */
    rfe_real_t zhat[RFE_M_MAX];                  /**< predicted measurement */
} rfe_cub_scratch_t;

/** The innovation of one measurement update, before the update (rfe_sckf_update_ex's
 *  innov_out): what the filter claims about y, for a test of that claim
 *  (rfe/component/monitor.h). */
typedef struct {
    rfe_real_t nu[RFE_M_MAX];              /**< y - z_hat */
    rfe_real_t Szz[RFE_M_MAX * RFE_M_MAX]; /**< its covariance's lower factor Tria([Zc, SR]),
                                                row-major, ld RFE_M_MAX (upper part 0) */
    rfe_real_t zz[RFE_M_MAX];              /**< diag(Zc Zc^T): the state's share of it */
} rfe_sckf_innov_t;

/** SCKF state (caller-owned). Fields are read-only for the caller. */
typedef struct {
    uint32_t magic;                          /**< set by init; guards use before init */
    size_t n;                                /**< state dimension, 1..RFE_N_MAX */
    size_t m;                                /**< measurement dimension, 1..RFE_M_MAX */
    rfe_real_t x[RFE_N_MAX];                 /**< posterior mean */
    rfe_real_t S[RFE_N_MAX * RFE_N_MAX];     /**< lower-triangular sqrt of P, ld RFE_N_MAX */
    rfe_real_t SQ[RFE_N_MAX * RFE_N_MAX];    /**< sqrt of Q, ld RFE_N_MAX */
    rfe_real_t SR[RFE_M_MAX * RFE_M_MAX];    /**< sqrt of R, ld RFE_M_MAX */
    rfe_cub_scratch_t w;                     /**< scratch */
} rfe_sckf_t;

/**
 * Initialises the filter: x0 (n), S0 (n x n lower-triangular sqrt of P0), SQ (n x n),
 * SR (m x m). Only the lower triangles of S0, SQ, SR are read.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_SIZE; RFE_ERR_NONFINITE; RFE_ERR_ABI (below). The
 *         filter is untouched on every error.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_init(rfe_sckf_t *f, size_t n, size_t m,
                                        const rfe_real_t *x0, const rfe_real_t *S0,
                                        const rfe_real_t *SQ, const rfe_real_t *SR,
                                        size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_SCKF_IMPL), where the name is the function's own. */
#if !defined(RFE_SCKF_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_sckf_init_f64(f, n, m, x0, S0, SQ, SR) \
    rfe_sckf_init_f64((f), (n), (m), (x0), (S0), (SQ), (SR), sizeof(rfe_sckf_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_sckf_init_f32(f, n, m, x0, S0, SQ, SR) \
    rfe_sckf_init_f32((f), (n), (m), (x0), (S0), (SQ), (SR), sizeof(rfe_sckf_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * Time update: X_j = S xi_j + x, X*_j = f(X_j), x- = mean X*_j,
 * S- = Tria([(X*_j - x-)/sqrt(2n), SQ]). @p process NULL means f(x) = x (random walk).
 * @return RFE_OK, or the callback's / Tria's error (state untouched).
 */
RFE_NODISCARD rfe_status_t rfe_sckf_predict(rfe_sckf_t *f, rfe_process_fn_t process,
                                           void *ctx);

/**
 * @p k time updates of the random walk f(x) = x at once (a gap of k sample periods):
 * x- = x, S- = Tria([S, sqrt(k) SQ]), i.e. P- = P + k Q, in O(1) whatever k. k = 0 changes
 * nothing. @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; Tria's error (state
 * untouched).
 */
RFE_NODISCARD rfe_status_t rfe_sckf_predict_steps(rfe_sckf_t *f, uint32_t k);

/**
 * Measurement update with measurement y (m values): cubature points from S-, Z_j = h(X_j),
 * S_zz = Tria([Zc, SR]), P_xz = Xc Zc^T, K = (P_xz / S_zz^T) / S_zz, x = x- + K (y - z),
 * S = Tria([Xc - K Zc, K SR]).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE (y or a callback output);
 *         RFE_ERR_NOT_POSITIVE_DEFINITE (S_zz singular); the callback's error.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_update(rfe_sckf_t *f, rfe_measure_fn_t measure,
                                          void *ctx, const rfe_real_t *y);

/**
 * Measurement update with a step-specific noise factor and an information gate
 * (docs/ESTIMATOR.md steps 5-6). From the predicted x-, S- (call after rfe_sckf_predict):
 *  1. cubature points X_j = S- xi_j + x-, Z_j = h(X_j), z, centred Xc (n x 2n), Zc (m x 2n);
 *  2. when @p info_min > 0 or @p info_out is not NULL, the Fisher information per state by
 *     statistical linearisation: P_zx = Zc Xc^T, J^T = S-^T \ (S- \ P_zx^T) (two
 *     triangular solves), W = SR \ J (forward solve), I_k = sum_r W_rk^2 (the diagonal of
 *     J^T R^-1 J); with info_min > 0 and max_k I_k < info_min the step is held: x, S stay
 *     the predicted ones, *updated = 0;
 *  3. otherwise the update of rfe_sckf_update with SR in place of the filter's S_R,
 *     reusing the points and Z_j of 1; *updated = 1.
 * With SR = NULL (the filter's S_R), info_min <= 0 and info_out = NULL this is
 * rfe_sckf_update, bit for bit.
 * @param SR        m x m lower-triangular sqrt of this step's R (only the lower triangle is
 *                  read, leading dimension m), or NULL for the filter's own S_R. The
 *                  information needs diag(SR) > 0.
 * @param info_min  gate threshold; <= 0: no gate. Must be finite.
 * @param info_out  n values I_k (written on success, also when held), or NULL.
 * @param innov_out the innovation y - z_hat, S_zz = Tria([Zc, SR]) and diag(Zc Zc^T) of the
 *                  predicted points (written on success, also when held: S_zz is then
 *                  computed for it), or NULL.
 * @param updated   required: 1 when the state was updated, 0 when held.
 * @return RFE_OK (updated or held); RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED;
 *         RFE_ERR_NONFINITE (y, SR, info_min, a callback output, or an overflowing
 *         information); RFE_ERR_NOT_POSITIVE_DEFINITE (S- or SR with a zero diagonal when the
 *         information is computed, S_zz singular); the callback's error. On error nothing
 *         is written.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_update_ex(rfe_sckf_t *f, rfe_measure_fn_t measure,
                                             void *ctx, const rfe_real_t *y,
                                             const rfe_real_t *SR, rfe_real_t info_min,
                                             rfe_real_t *info_out, rfe_sckf_innov_t *innov_out,
                                             int *updated);

/**
 * rfe_sckf_update_ex for a measurement function linear in the state, h(x) = H x (no constant
 * term: h(0) = 0; the friction estimator's paper tyre, h = H(u) T x): the third-degree rule is
 * exact for it, so the update runs on the n columns of S- instead of the 2n cubature points
 * (docs/ESTIMATOR.md "The linear update"): z = h(x-), Zc = [h(S- e_1) .. h(S- e_n)] = H S-,
 * Xc = S-, the same products Xc Xc^T, Zc Zc^T, Xc Zc^T as the points' (so the same x, S,
 * information and innovation in exact arithmetic, n + 1 evaluations of h instead of 2n).
 * Arguments, outputs and errors as rfe_sckf_update_ex's; for an h that is not linear the
 * result is not the cubature filter's.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_update_linear(rfe_sckf_t *f, rfe_measure_fn_t measure,
                                                 void *ctx, const rfe_real_t *y,
                                                 const rfe_real_t *SR, rfe_real_t info_min,
                                                 rfe_real_t *info_out,
                                                 rfe_sckf_innov_t *innov_out, int *updated);

/**
 * Scales the square-root factor, S <- c S (P <- c^2 P: every standard deviation by c,
 * correlations kept). @p c must be finite and > 0 (else RFE_ERR_RANGE); a product that
 * overflows gives RFE_ERR_NONFINITE. On error S is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_sckf_scale(rfe_sckf_t *f, rfe_real_t c);

/** Copies the mean (n) and the standard deviations sqrt(diag(S S^T)) (n); either may be NULL. */
RFE_NODISCARD rfe_status_t rfe_sckf_get(const rfe_sckf_t *f, rfe_real_t *x, rfe_real_t *sd);

/** Projects the mean onto [lo, hi] element-wise (S untouched); *clamped = 1 if any moved. */
RFE_NODISCARD rfe_status_t rfe_sckf_clamp(rfe_sckf_t *f, rfe_real_t lo, rfe_real_t hi,
                                         int *clamped);

#endif /* RFE_SCKF_H */
