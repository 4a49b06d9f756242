/**
 * @file mass_grade_internal.h
 * @brief The mass and grade estimator's unscented Kalman filter (docs/MASS_GRADE.md §3,
 *        §4.3 steps 1-7), apart from the model: the sigma points of (x, P), the moments of
 *        propagated points and the measurement update from measured points
 *        (mass_grade_ukf_flt.c). mass_grade_flt.c propagates the points through the
 *        longitudinal model; the tests through a linear one, where the filter must be the
 *        Kalman filter. Every sum runs in the order the page writes.
 */
#ifndef RFE_MASS_GRADE_INTERNAL_H
#define RFE_MASS_GRADE_INTERNAL_H

#include "rfe/mass_grade.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_mg_sigma_points rfe_mg_sigma_points_f64
#define rfe_mg_predict      rfe_mg_predict_f64
#define rfe_mg_correct      rfe_mg_correct_f64
#else
#define rfe_mg_sigma_points rfe_mg_sigma_points_f32
#define rfe_mg_predict      rfe_mg_predict_f32
#define rfe_mg_correct      rfe_mg_correct_f32
#endif

/** The number of sigma points 2n + 1 and the largest measurement (speed and ax). */
#define RFE_MG_PTS 7
#define RFE_MG_Z_MAX 2

/** The weights of §3 (state fields wm0, wc0, wi and the spread c = n + lambda). */
typedef struct {
    rfe_real_t wm0; /**< mean weight of the centre point */
    rfe_real_t wc0; /**< covariance weight of the centre point */
    rfe_real_t wi;  /**< weight of every other point */
    rfe_real_t c;   /**< n + lambda */
} rfe_mg_weights_t;

/**
 * §3 chi_0 = x, chi_i = x + L[:, i-1], chi_{n+i} = x - L[:, i-1], L the lower Cholesky
 * factor of c P (element by element), a zero pivot giving a zero column.
 * @return RFE_OK; RFE_ERR_NOT_POSITIVE_DEFINITE (a negative pivot; chi partly written).
 */
rfe_status_t rfe_mg_sigma_points(const rfe_real_t x[RFE_MG_N],
                                 const rfe_real_t P[RFE_MG_N * RFE_MG_N], rfe_real_t c,
                                 rfe_real_t chi[RFE_MG_PTS * RFE_MG_N]);

/**
 * §4.3 step 2: x- = sum wm_i X_i, P- = sum wc_i (X_i - x-)(X_i - x-)^T + diag(q).
 */
void rfe_mg_predict(const rfe_real_t X[RFE_MG_PTS * RFE_MG_N], const rfe_mg_weights_t *w,
                    const rfe_real_t q[RFE_MG_N], rfe_real_t xm[RFE_MG_N],
                    rfe_real_t Pm[RFE_MG_N * RFE_MG_N]);

/**
 * §4.3 steps 4-7 with the points @p chi of (x-, P-) and their measurements @p Z (nz = 1 or
 * 2 rows): S = cov(Z) + diag(r2), P_xz, K = P_xz S^-1, x = x- + K (y - z), P = P- - K S K^T.
 * @param[in,out] x  x- in, the posterior mean out.
 * @param[in,out] P  P- in, the posterior covariance out.
 * @return RFE_OK; RFE_ERR_NOT_POSITIVE_DEFINITE (S not positive definite; x, P untouched).
 */
rfe_status_t rfe_mg_correct(const rfe_real_t chi[RFE_MG_PTS * RFE_MG_N],
                            const rfe_real_t Z[RFE_MG_PTS * RFE_MG_Z_MAX], size_t nz,
                            const rfe_mg_weights_t *w, const rfe_real_t r2[RFE_MG_Z_MAX],
                            const rfe_real_t y[RFE_MG_Z_MAX], rfe_real_t x[RFE_MG_N],
                            rfe_real_t P[RFE_MG_N * RFE_MG_N]);

#endif /* RFE_MASS_GRADE_INTERNAL_H */
