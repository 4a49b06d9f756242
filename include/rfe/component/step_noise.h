/**
 * @file step_noise.h
 * @brief This step's measurement-noise factor S_R (docs/ESTIMATOR.md step 4): sensor noise,
 *        tyre-model error relative to the predicted accelerations, and the noise of the
 *        inputs propagated through the measurement model ("errors in variables").
 *
 *   h = h(mu, u) at the given (predicted) friction, u the (conditioned) sample;
 *   S_R0 = diag( sqrt(r_r^2 + (r_model_rel |h_r|)^2) ),  r = ax, ay, r-dot;
 *   for each input j in the order delta, vx, vy, r, omega_fl, omega_fr, omega_rl, omega_rr
 *   with sd_j > 0:  g_j = (h(mu, u + sd_j e_j) - h(mu, u - sd_j e_j)) / 2
 *   (kinematics, slips and loads recomputed for the perturbed input; ax, ay not perturbed);
 *   S_R = Tria([S_R0, g_1, ...])  (lower-triangular, S_R S_R^T = S_R0 S_R0^T + sum g g^T).
 */
#ifndef RFE_STEP_NOISE_H
#define RFE_STEP_NOISE_H

#include "rfe/params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_step_noise_sqrt rfe_step_noise_sqrt_f64
#else
#define rfe_step_noise_sqrt rfe_step_noise_sqrt_f32
#endif

/**
 * S_R (3 x 3, row-major, lower-triangular, upper triangle zero) for sample @p u at friction
 * @p mu (per wheel), with r_ax, r_ay, r_yaw_acc, r_model_rel and sd_in_* of @p p.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (rfe_params_validate fails);
 *         RFE_ERR_NONFINITE and the tyre's errors (@p SR then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_step_noise_sqrt(const rfe_params_t *p,
                                             const rfe_sample_t *u,
                                             const rfe_real_t mu[RFE_WHEELS],
                                             rfe_real_t SR[RFE_MEAS * RFE_MEAS]);

#endif /* RFE_STEP_NOISE_H */
