/**
 * @file meas.h
 * @brief The measurement model h(mu, u) of one sample (MODEL.md §3-5): predicted
 *        y = [ax, ay, r-dot] from a friction value per wheel.
 *
 * rfe_meas_setup does the per-sample work once (kinematics, slips, loads; in paper tyre mode
 * also H(u), in the load-scaled modes (absolute, magic) cos/sin of delta and each wheel's
 * friction-independent tyre
 * terms); rfe_meas_eval is then cheap enough for every cubature point:
 *  - paper tyre:    h = H(u) mu (linear in mu);
 *  - absolute tyre: the load-scaled Dugoff forces at each wheel's mu (mu < 0 evaluated as 0),
 *                   through the same geometry as H's columns: h_r = sum_i H_r,i(F(mu_i)).
 * The model keeps no pointer to the parameters: pass the same ones to setup and eval.
 */
#ifndef RFE_MEAS_H
#define RFE_MEAS_H

#include "rfe/component/obsmat.h"
#include "rfe/component/tyre.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_meas_setup rfe_meas_setup_f64
#define rfe_meas_eval  rfe_meas_eval_f64
#else
#define rfe_meas_setup rfe_meas_setup_f32
#define rfe_meas_eval  rfe_meas_eval_f32
#endif

/** One sample's measurement model (caller-owned; fields read-only for the caller). */
typedef struct {
    rfe_tyre_mode_t mode;                /**< tyre mode it was set up for */
    rfe_real_t delta;                    /**< steer angle of the sample */
    rfe_wheel_kin_t kin;                 /**< kinematics, slips, loads of the sample */
    rfe_real_t H[RFE_H_SIZE];            /**< paper mode: H(u) */
    rfe_real_t cos_delta;                /**< load-scaled modes: cos of delta (paper mode: 0) */
    rfe_real_t sin_delta;                /**< load-scaled modes: sin of delta (paper mode: 0) */
    /** load-scaled modes: each wheel's friction-independent tyre terms, so that eval does only
     *  the friction-dependent rest at each cubature point (paper mode: zeros) */
    rfe_dugoff_pre_t pre[RFE_WHEELS];
    /* the tyre parameters pre was computed with: eval recomputes the terms for others */
    rfe_real_t pre_cx;                   /**< cx of the set-up */
    rfe_real_t pre_cy;                   /**< cy of the set-up */
    rfe_real_t pre_eps;                  /**< eps of the set-up */
    rfe_real_t pre_alpha_max;            /**< alpha_max of the set-up */
} rfe_meas_t;

/**
 * Sets the model up for sample @p u (uses delta, vx, vy, yaw_rate, ax, ay, omega) and the
 * tyre mode tp->mode.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE; the tyre's errors (@p h then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_setup(rfe_meas_t *h, const rfe_vehicle_t *veh,
                                         const rfe_tyre_params_t *tp,
                                         const rfe_sample_t *u);

/**
 * z = h(mu, u) for the sample of the last rfe_meas_setup.
 * @param mu friction per wheel (fl, fr, rl, rr)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE; the tyre's / obsmat's errors.
 */
RFE_NODISCARD rfe_status_t rfe_meas_eval(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                        const rfe_tyre_params_t *tp,
                                        const rfe_real_t mu[RFE_WHEELS],
                                        rfe_real_t z[RFE_MEAS]);

#endif /* RFE_MEAS_H */
