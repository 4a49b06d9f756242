/**
 * @file step_noise_q31.h
 * @brief Fixed-point twin of rfe/component/step_noise.h: this step's measurement-noise factor S_R
 *        (docs/ESTIMATOR.md step 4) on int32 Q values (docs/FIXED_POINT.md, "Estimator").
 *
 *   h = h(mu, u) at the given (predicted) friction, u the (conditioned) sample;
 *   S_R0 = diag( sqrt(r_r^2 + (r_model_rel |h_r|)^2) ),  r = ax, ay, r-dot;
 *   for each input j in the order delta, vx, vy, r, omega_fl, omega_fr, omega_rl, omega_rr
 *   with sd_j > 0:  g_j = (h(mu, u + sd_j e_j) - h(mu, u - sd_j e_j)) / 2
 *   (kinematics, slips and loads recomputed for the perturbed input; ax, ay not perturbed);
 *   S_R = Tria([S_R0, g_1, ...])  (lower-triangular, S_R S_R^T = S_R0 S_R0^T + sum g g^T).
 *
 * Formats: h, S_R0, g_j and S_R in Q24 (RFE_FIX_Q_ACC, the SCKF's RFE_Q31_QZ); the input
 * noise sds are in the format of their signal (rfe_filter_params_q31_t), so u +- sd_j e_j is
 * one saturating integer addition. Errors against the exact values of the same Q inputs:
 * r_model_rel |h_r| rounded to Q24 (0.5 LSB), the norm exactly rounded (0.5 LSB), each g_j
 * the halved difference of two model evaluations (each within the measurement model's own
 * bound, docs/FIXED_POINT.md) rounded half up (0.5 LSB), and the Tria of rfe/component/qr_q31.h.
 */
#ifndef RFE_STEP_NOISE_Q31_H
#define RFE_STEP_NOISE_Q31_H

#include <stdint.h>

#include "rfe/fixed.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre_q31.h"

/**
 * S_R (3 x 3, row-major, lower-triangular, upper triangle zero; Q24) for sample @p u at
 * friction @p mu (per wheel, Q29), with r_ax, r_ay, r_yaw_acc, r_model_rel and sd_in_* of
 * @p p (the arguments of rfe_step_noise_sqrt plus the saturation counter).
 * @param sat saturation counter (required): one count per clamped value anywhere in the
 *            chain (the model evaluations, a perturbed input, r_model_rel |h|, the halved
 *            differences, S_R); added to only on success.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (rfe_params_validate_q31 fails); the
 *         measurement model's errors (@p SR and *sat then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_step_noise_sqrt_q31(const rfe_params_q31_t *p,
                                                  const rfe_sample_q31_t *u,
                                                  const rfe_fix_t mu[RFE_WHEELS],
                                                  rfe_fix_t SR[RFE_MEAS * RFE_MEAS],
                                                  uint32_t *sat);

#endif /* RFE_STEP_NOISE_Q31_H */
