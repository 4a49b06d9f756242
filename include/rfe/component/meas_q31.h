/**
 * @file meas_q31.h
 * @brief Fixed-point twin of rfe/component/meas.h: the measurement model h(mu, u) of one sample
 *        (MODEL.md §3-5), predicted y = [ax, ay, r-dot] (Q24) from a friction value per wheel
 *        (Q29).
 *
 * rfe_meas_setup_q31 does the per-sample work once (kinematics, slips, loads, cos/sin of delta;
 * in paper tyre mode also H(u), in the load-scaled modes (absolute, magic) each wheel's
 * friction-independent tyre terms); rfe_meas_eval_q31 is then cheap enough for every
 * cubature point:
 *  - paper tyre:    h = H(u) mu (linear in mu);
 *  - absolute tyre: the load-scaled Dugoff forces at each wheel's mu (mu < 0 evaluated as 0),
 *                   through the same geometry as H's columns: h_r = sum_i H_r,i(F(mu_i));
 *  - magic tyre:    the same with the load-scaled Magic Formula forces
 *                   (rfe_tyre_magic_abs_q31).
 * A model set up in a load-scaled mode is evaluated with the curve of the mode of the tyre
 * parameters given to eval (rfe_tyre_forces_abs_q31's choice).
 * The model keeps no pointer to the parameters: pass the same ones to setup and eval.
 * Saturation: `*sat` gets one count per clamped value anywhere in the chain (kinematics
 * outputs, forces, H entries, z); on an error nothing is written.
 */
#ifndef RFE_MEAS_Q31_H
#define RFE_MEAS_Q31_H

#include <stdint.h>

#include "rfe/fixed.h"
#include "rfe/component/obsmat_q31.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre_q31.h"

/** One sample's measurement model (caller-owned; fields read-only for the caller). */
typedef struct {
    rfe_tyre_mode_t mode;          /**< tyre mode it was set up for */
    rfe_fix_t delta;               /**< steer angle of the sample [rad], Q29 */
    rfe_wheel_kin_q31_t kin;       /**< kinematics, slips, loads of the sample */
    rfe_fix_t H[RFE_H_Q31_SIZE];   /**< paper mode: H(u), Q24 (load-scaled modes: zeros) */
    rfe_fix_t cos_delta;           /**< cos of delta, Q30 */
    rfe_fix_t sin_delta;           /**< sin of delta, Q30 */
    /** load-scaled modes (absolute, magic): each wheel's friction-independent tyre terms, so
     *  that eval does only the friction-dependent rest at each cubature point (paper mode:
     *  zeros); they depend on neither the mode nor the shape factors */
    rfe_dugoff_pre_q31_t pre[RFE_WHEELS];
    /* the tyre parameters pre was computed with: eval recomputes the terms for others (the
     * only ones pre depends on) */
    rfe_fix_t pre_cx;              /**< cx of the set-up, Q24 */
    rfe_fix_t pre_cy;              /**< cy of the set-up, Q24 */
    rfe_fix_t pre_eps;             /**< eps of the set-up, Q32 */
    rfe_fix_t pre_alpha_max;       /**< alpha_max of the set-up, Q29 */
    uint32_t sat_vwx[RFE_WHEELS];  /**< saturations of each wheel's vwx in the set-up */
    uint32_t sat_fz[RFE_WHEELS];   /**< saturations of each wheel's load in the set-up */
} rfe_meas_q31_t;

/**
 * Sets the model up for sample @p u (uses delta, vx, vy, yaw_rate, ax, ay, omega) and the tyre
 * mode tp->mode.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (tyre parameters, or an unknown mode); the
 *         tyre's errors (@p h then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_setup_q31(rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                              const rfe_tyre_params_q31_t *tp,
                                              const rfe_sample_q31_t *u, uint32_t *sat);

/**
 * z = h(mu, u) (Q24) for the sample of the last rfe_meas_setup_q31.
 * @param mu friction per wheel (fl, fr, rl, rr), Q29
 * @return RFE_OK; RFE_ERR_NULL; the tyre's / obsmat's errors.
 */
RFE_NODISCARD rfe_status_t rfe_meas_eval_q31(const rfe_meas_q31_t *h,
                                             const rfe_vehicle_q31_t *veh,
                                             const rfe_tyre_params_q31_t *tp,
                                             const rfe_fix_t mu[RFE_WHEELS],
                                             rfe_fix_t z[RFE_MEAS], uint32_t *sat);

#endif /* RFE_MEAS_Q31_H */
