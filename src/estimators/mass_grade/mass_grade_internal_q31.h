/**
 * @file mass_grade_internal_q31.h
 * @brief Fixed-point twin of mass_grade_internal.h: the mass and grade estimator's unscented
 *        Kalman filter in the square-root form (docs/MASS_GRADE.md §3, §4.3 steps 1-7;
 *        docs/FIXED_POINT.md "Mass and grade"), apart from the model
 *        (mass_grade_ukf_q31.c). The state carries S, the lower factor of P = S S^T, with
 *        row r (and the points' coordinate r) in the format of state r (v Q24, M Q14, theta
 *        Q29): a triangularisation treats each row on its own scale (rfe_qr_tria_q31 scales
 *        every row by its own power of two), so Tria(D A) = D Tria(A) for the diagonal D
 *        of the formats and one call serves rows of different formats. The measurement rows
 *        (v, ax) are Q24.
 */
#ifndef RFE_MASS_GRADE_INTERNAL_Q31_H
#define RFE_MASS_GRADE_INTERNAL_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/mass_grade_q31.h"

/** The number of sigma points 2n + 1 and the largest measurement (speed and ax). */
#define RFE_MG_PTS_Q31 7
#define RFE_MG_Z_MAX_Q31 2

/**
 * §3 chi_0 = x, chi_i = x + d_i, chi_{n+i} = x - d_i, d_i = sqrt(n + lambda) S[:, i-1]
 * (each element exactly rounded from the Q29 root; the same d_i on both sides), saturating.
 * @param[in]  x       the mean, state formats.
 * @param[in]  S       the lower factor of P, row r in state r's format.
 * @param[in]  sqrt_c  sqrt(n + lambda), Q29.
 * @param[out] chi     the 7 points, point-major (chi[i n + r]).
 * @param[in,out] sat  saturation count.
 */
void rfe_mg_sigma_points_q31(const rfe_fix_t x[RFE_MG_N_Q31],
                             const rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], rfe_fix_t sqrt_c,
                             rfe_fix_t chi[RFE_MG_PTS_Q31 * RFE_MG_N_Q31], uint32_t *sat);

/**
 * §4.3 step 2 in square-root form: x- = X_0 + sum_{i>=1} w_i (X_i - X_0) (= sum w_m,i X_i,
 * the weights summing to 1 exactly), S- = Tria([sqrt(w_c,i) (X_i - x-)]_i, diag(sq)), so
 * S- S-^T = cov(X, X) + diag(sq)^2 = P-.
 * @param[in]  X   the propagated points, point-major.
 * @param[in]  w   the weights.
 * @param[in]  sq  the square roots of Q's diagonal, state formats.
 * @param[out] xm  x-.
 * @param[out] Sm  S-.
 * @return RFE_OK (the triangularisation's argument checks cannot fail here).
 */
rfe_status_t rfe_mg_predict_q31(const rfe_fix_t X[RFE_MG_PTS_Q31 * RFE_MG_N_Q31],
                                const rfe_mg_weights_q31_t *w, const rfe_fix_t sq[RFE_MG_N_Q31],
                                rfe_fix_t xm[RFE_MG_N_Q31],
                                rfe_fix_t Sm[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat);

/**
 * §4.3 step 7 alone, the speed row in square-root form, the float twin's
 * rfe_mg_correct_speed: linear in the state (ẑ = x_v, P_xz = S[:, 0] S_00: no sigma points),
 * its array [[S row v, r_v], [S, 0]] has two nonzero entries in its first row, so its
 * triangularisation is one Givens rotation of S column 0 with r_v (closed form): s =
 * |(S_00, r_v)|, g = S[:, 0] S_00 / s, S[:, 0] *= r_v / s, x += g (y - x_v) / s. The last row
 * of rfe_mg_correct_q31, and the whole correction of the update without the ax row and of the
 * grade from ax in a pause (§4.2). A row of S with 0 in column 0 keeps its mean and its S row
 * bit for bit.
 * @param[in] r_v  the speed's measurement sd, Q24.
 * @param[in] y    the measured speed, Q24.
 * @param[in,out] x  the prior mean in, the posterior mean out.
 * @param[in,out] S  the prior factor in, the posterior factor out.
 * @param[in,out] sat  saturation count, added to only on success.
 * @return RFE_OK; RFE_ERR_NOT_POSITIVE_DEFINITE (s = 0; x, S and @p sat untouched).
 */
rfe_status_t rfe_mg_correct_speed_q31(rfe_fix_t r_v, rfe_fix_t y, rfe_fix_t x[RFE_MG_N_Q31],
                                      rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat);

/**
 * §4.3 steps 4-7 in square-root form with the ax row (without it the update is
 * rfe_mg_correct_speed_q31 alone), one measurement row at a time, each a 4-row
 * triangularisation (so the library's RFE_N_MAX = 4 suffices): first the ax row by the
 * points @p chi of (x-, S-) and their measurements @p Z (Q24): z = Z_0 + sum_{i>=1}
 * w_i (Z_i - Z_0), the array [[Zc, r_ax], [Xc, 0]] (Zc, Xc the deviations times
 * sqrt(w_c,i)) triangularised to [[s, 0], [g, S']]; then the speed row, linear in the state
 * (h = v: its points' deviations are Xc's v row, ẑ = x-_v): rfe_mg_correct_speed_q31 on
 * (x', S'); each row x += g (y - z) / s. With R diagonal this is the joint update of
 * MASS_GRADE.md §4.3 (S = cov(Z) + R, K = P_xz S^-1, P = P- - K S K^T) in exact arithmetic:
 * conditioning on ax, then on v given ax.
 * @param[in,out] x  x- in, the posterior mean out.
 * @param[in,out] S  S- in, the posterior factor out.
 * @param[out] e_ax  the ax row's normalised innovation (y - z) / s, Q24 (§4.8's monitor).
 * @return RFE_OK; RFE_ERR_NOT_POSITIVE_DEFINITE (a zero innovation sd; x, S, e_ax untouched).
 */
rfe_status_t rfe_mg_correct_q31(const rfe_fix_t chi[RFE_MG_PTS_Q31 * RFE_MG_N_Q31],
                                const rfe_fix_t Z[RFE_MG_PTS_Q31], const rfe_mg_weights_q31_t *w,
                                const rfe_fix_t r[RFE_MG_Z_MAX_Q31],
                                const rfe_fix_t y[RFE_MG_Z_MAX_Q31], rfe_fix_t x[RFE_MG_N_Q31],
                                rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat,
                                rfe_fix_t *e_ax);

#endif /* RFE_MASS_GRADE_INTERNAL_Q31_H */
