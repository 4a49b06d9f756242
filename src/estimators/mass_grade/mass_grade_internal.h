/**
 * @file mass_grade_internal.h
 * @brief The mass and grade estimator's unscented Kalman filter in the square-root form
 *        (docs/MASS_GRADE.md §3, §4.3 steps 1-7), apart from the model: the sigma points of
 *        (x, S), the moments of propagated points and the measurement update from measured
 *        points (mass_grade_ukf_flt.c), each covariance step one triangularisation
 *        (rfe_qr_tria) of the lower factor S of P = S S^T, the steps of the Q31 twin
 *        (mass_grade_internal_q31.h). mass_grade_flt.c propagates the points through the
 *        longitudinal model; the tests through a linear one, where the filter must be the
 *        Kalman filter. Every sum runs in the order the reference writes
 *        (scripts/reference/mass_grade.py, form "sqrt").
 */
#ifndef RFE_MASS_GRADE_INTERNAL_H
#define RFE_MASS_GRADE_INTERNAL_H

#include "rfe/mass_grade.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_mg_sigma_points  rfe_mg_sigma_points_f64
#define rfe_mg_predict       rfe_mg_predict_f64
#define rfe_mg_correct       rfe_mg_correct_f64
#define rfe_mg_correct_speed rfe_mg_correct_speed_f64
#else
#define rfe_mg_sigma_points  rfe_mg_sigma_points_f32
#define rfe_mg_predict       rfe_mg_predict_f32
#define rfe_mg_correct       rfe_mg_correct_f32
#define rfe_mg_correct_speed rfe_mg_correct_speed_f32
#endif

/** The number of sigma points 2n + 1 and the largest measurement (speed and ax). */
#define RFE_MG_PTS 7
#define RFE_MG_Z_MAX 2

/** The weights of §3 (state fields wm0, wc0, wi, their roots and the spread's root). */
typedef struct {
    rfe_real_t wm0;      /**< mean weight of the centre point */
    rfe_real_t wc0;      /**< covariance weight of the centre point (read for its sign) */
    rfe_real_t wi;       /**< weight of every other point */
    rfe_real_t sqrt_wc0; /**< sqrt(|w_c,0|) */
    rfe_real_t sqrt_wi;  /**< sqrt(w_i) */
    rfe_real_t sqrt_c;   /**< sqrt(n + lambda) */
} rfe_mg_weights_t;

/**
 * §3 chi_0 = x, chi_i = x + d_i, chi_{n+i} = x - d_i, d_i = sqrt(n + lambda) S[:, i-1]
 * (element by element; the same d_i on both sides).
 */
void rfe_mg_sigma_points(const rfe_real_t x[RFE_MG_N], const rfe_real_t S[RFE_MG_N * RFE_MG_N],
                         rfe_real_t sqrt_c, rfe_real_t chi[RFE_MG_PTS * RFE_MG_N]);

/**
 * §4.3 step 2 in square-root form: x- = sum w_m,i X_i, S- = Tria([sqrt(w_c,i) (X_i - x-)]_i,
 * diag(sq)), so S- S-^T = cov(X, X) + diag(sq)^2 = P-. A negative w_c,0 leaves the centre's
 * column out of the array and downdates S- by sqrt(-w_c,0) (X_0 - x-) after it.
 * @return RFE_OK; RFE_ERR_NONFINITE (a point not finite); RFE_ERR_NOT_POSITIVE_DEFINITE (the
 *         downdate of a negative w_c,0 leaves P- indefinite). xm, Sm are written either way.
 */
rfe_status_t rfe_mg_predict(const rfe_real_t X[RFE_MG_PTS * RFE_MG_N], const rfe_mg_weights_t *w,
                            const rfe_real_t sq[RFE_MG_N], rfe_real_t xm[RFE_MG_N],
                            rfe_real_t Sm[RFE_MG_N * RFE_MG_N]);

/**
 * §4.3 step 7 alone, the speed row in square-root form: linear in the state (z = x_v, so its
 * cross terms P_xz = S S[0, :]^T = S[:, 0] S_00, S lower triangular: no sigma points), one
 * Givens rotation of S's column 0 with r_v: s = sqrt(S_00^2 + r_v^2), g = S[:, 0] S_00 / s,
 * S[:, 0] *= r_v / s, x += g (y_v - x_v) / s. The last row of rfe_mg_correct, and the whole
 * correction of the update without the ax row and of the grade from ax in a pause (§4.2),
 * neither of which has sigma points. A row of S with 0 in column 0 keeps its mean and its S
 * row bit for bit.
 * @param[in] r_v  the speed's measurement sd.
 * @param[in] y    the measured speed.
 * @param[in,out] x  the prior mean in, the posterior mean out.
 * @param[in,out] S  the prior factor in, the posterior factor out.
 * @return RFE_OK; RFE_ERR_NOT_POSITIVE_DEFINITE (s = 0: S_00 = r_v = 0); RFE_ERR_NONFINITE
 *         (S_00^2 overflowed); x, S untouched on an error.
 */
rfe_status_t rfe_mg_correct_speed(rfe_real_t r_v, rfe_real_t y, rfe_real_t x[RFE_MG_N],
                                  rfe_real_t S[RFE_MG_N * RFE_MG_N]);

/**
 * §4.3 steps 4-7 in square-root form with the ax row, one measurement row at a time (the Q31
 * twin's steps; without the ax row the update is rfe_mg_correct_speed alone): first the ax
 * row by the points @p chi of (x-, S-) and their measurements @p Z:
 * z = sum w_m,i Z_i, the array [[Zc, r_ax], [Xc, 0]] (Zc, Xc the deviations times
 * sqrt(w_c,i)) triangularised to [[s, 0], [g, S']], x += g (y - z) / s; then the speed row,
 * linear in the state (its points' deviations are Xc's v row, z = x_v): rfe_mg_correct_speed
 * on (x', S'). With R diagonal this is the joint update S = cov(Z) + R,
 * K = P_xz S^-1, P = P- - K S K^T in exact arithmetic: conditioning on ax, then on v.
 * @param[in] Z  the ax row's measurements of the points.
 * @param[in] r  the measurement sds [r_v, r_ax].
 * @param[in,out] x  x- in, the posterior mean out.
 * @param[in,out] S  S- in, the posterior factor out.
 * @param[out] e_ax  the ax row's normalised innovation (y - z) / s (§4.8's monitor reads it).
 * @return RFE_OK; RFE_ERR_NOT_POSITIVE_DEFINITE (a zero innovation sd, or the downdate of a
 *         negative w_c,0 fails); RFE_ERR_NONFINITE (a point or measurement not finite, or the
 *         speed row's innovation sd overflows); x, S, e_ax untouched on an error.
 */
rfe_status_t rfe_mg_correct(const rfe_real_t chi[RFE_MG_PTS * RFE_MG_N],
                            const rfe_real_t Z[RFE_MG_PTS], const rfe_mg_weights_t *w,
                            const rfe_real_t r[RFE_MG_Z_MAX], const rfe_real_t y[RFE_MG_Z_MAX],
                            rfe_real_t x[RFE_MG_N], rfe_real_t S[RFE_MG_N * RFE_MG_N],
                            rfe_real_t *e_ax);

#endif /* RFE_MASS_GRADE_INTERNAL_H */
