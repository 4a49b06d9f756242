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
#define rfe_meas_setup           rfe_meas_setup_f64
#define rfe_meas_eval            rfe_meas_eval_f64
#define rfe_meas_nominal         rfe_meas_nominal_f64
#define rfe_meas_eval_perturbed  rfe_meas_eval_perturbed_f64
#define rfe_meas_lateral_jac     rfe_meas_lateral_jac_f64
#define rfe_meas_input_jac       rfe_meas_input_jac_f64
#else
#define rfe_meas_setup           rfe_meas_setup_f32
#define rfe_meas_eval            rfe_meas_eval_f32
#define rfe_meas_nominal         rfe_meas_nominal_f32
#define rfe_meas_eval_perturbed  rfe_meas_eval_perturbed_f32
#define rfe_meas_lateral_jac     rfe_meas_lateral_jac_f32
#define rfe_meas_input_jac       rfe_meas_input_jac_f32
#endif

/** One sample's measurement model (caller-owned; fields read-only for the caller). */
typedef struct {
    rfe_tyre_mode_t mode;                /**< tyre mode it was set up for */
    rfe_real_t delta;                    /**< steer angle of the sample */
    rfe_wheel_kin_t kin;                 /**< kinematics, slips, loads of the sample */
    rfe_real_t H[RFE_H_SIZE];            /**< paper mode: H(u) (load-scaled modes: zeros) */
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
    /* load-scaled modes: each wheel's forces at one friction, kept by the step noise's
     * evaluation at the predicted friction (rfe_meas_nominal_input_jac) for the cubature
     * points of rfe_meas_eval that leave a wheel's friction there (the same operations on the
     * same values: the same forces); valid with the tyre parameters they were computed with
     * (pre_* and memo_shape), reset by rfe_meas_setup */
    rfe_real_t memo_mu[RFE_WHEELS];      /**< the friction of each kept force */
    rfe_real_t memo_fx[RFE_WHEELS];      /**< Fx at memo_mu */
    rfe_real_t memo_fy[RFE_WHEELS];      /**< Fy at memo_mu */
    rfe_real_t memo_shape[4];            /**< shape_Cx, shape_Ex, shape_Cy, shape_Ey */
    int memo_valid;                      /**< 1 when the memo_* hold forces */
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

/** The nominal per-wheel terms of h(mu, u) at the set-up sample (caller-owned, written by
 *  rfe_meas_nominal): in the load-scaled modes wheel i's body-axis force over m and yaw
 *  moment over J at t[i RFE_MEAS ..], the entries rfe_obsmat_build would put in its column
 *  (paper mode: unused). */
typedef struct {
    rfe_real_t t[(size_t)RFE_WHEELS * (size_t)RFE_MEAS]; /**< wheel i's terms at i RFE_MEAS */
} rfe_meas_terms_t;

/**
 * z = h(mu, u) for the sample u of the last rfe_meas_setup, and (load-scaled modes) the
 * per-wheel terms that rfe_meas_eval_perturbed reuses for the wheels an input change does
 * not reach. Paper mode: z as rfe_meas_eval. Load-scaled modes: the forces with the set-up's
 * friction-independent tyre terms (the parameters @p tp must be the set-up's), each wheel's
 * terms, z their sum in wheel order: rfe_meas_eval's result and statuses, bit for bit.
 * @param[in]  h   the model set up by rfe_meas_setup with @p veh and @p tp
 * @param[in]  veh vehicle parameters of the set-up
 * @param[in]  tp  tyre parameters of the set-up
 * @param[in]  mu  friction per wheel (fl, fr, rl, rr)
 * @param[out] nom the nominal terms (load-scaled modes; paper mode: untouched)
 * @param[out] z   h(mu, u)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE; the tyre's errors (@p nom, @p z then
 *         untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_nominal(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                           const rfe_tyre_params_t *tp,
                                           const rfe_real_t mu[RFE_WHEELS],
                                           rfe_meas_terms_t *nom, rfe_real_t z[RFE_MEAS]);

/**
 * z = h(mu, u + d e_j): the model at the set-up's sample u with its input @p j (RFE_IN_*,
 * rfe/common.h) changed by @p d, bit for bit what rfe_meas_setup and rfe_meas_eval at that
 * sample give, and the same statuses. Paper mode does exactly that; the load-scaled modes
 * evaluate again only the wheels input j reaches (delta: the front wheels, vx, vy, r: all,
 * omega_w: wheel w's slip) and take the other wheels' terms from @p nom.
 * @param[in]  h   the model set up by rfe_meas_setup(h, veh, tp, u)
 * @param[in]  veh vehicle parameters of the set-up
 * @param[in]  tp  tyre parameters of the set-up
 * @param[in]  nom the terms of rfe_meas_nominal(h, veh, tp, mu, ...) (load-scaled modes)
 * @param[in]  u   the set-up's sample (only its input j is read in the load-scaled modes)
 * @param[in]  j   the input to change: RFE_IN_DELTA .. RFE_INPUTS - 1
 * @param[in]  d   the change of input j (its unit)
 * @param[in]  mu  friction per wheel (fl, fr, rl, rr), as given to rfe_meas_nominal
 * @param[out] z   h(mu, u + d e_j)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (@p j out of range); RFE_ERR_NONFINITE (the
 *         changed input, or a result, not finite); the tyre's errors (@p z then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_eval_perturbed(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                                  const rfe_tyre_params_t *tp,
                                                  const rfe_meas_terms_t *nom,
                                                  const rfe_sample_t *u, size_t j, rfe_real_t d,
                                                  const rfe_real_t mu[RFE_WHEELS],
                                                  rfe_real_t z[RFE_MEAS]);

/**
 * G = dh/du diag(sd): the derivatives of h(mu, u) by the sample's inputs (RFE_IN_*: delta, vx, vy, r,
 * omega_fl .. omega_rr; ax, ay are not inputs of the step noise), analytically from one
 * set-up: the step noise's input columns in analytic form (docs/ESTIMATOR.md step 4 and its
 * design record, where their effect is measured; the step noise uses them since issue 21): per wheel the forces' derivatives along kappa, tan(alpha)
 * and v_wx (rfe_tyre_pre_jac), chained with each input's change of the wheel's slips, and for
 * delta the turn of the front forces into the body axes. Where a slip is at its bound
 * (|kappa| = 1, |alpha| = alpha_max) its derivative is 0 (the clamp's); at a kink of the model
 * (den of kappa switching speeds, Dugoff's L = 1) the derivative of the branch the sample is
 * on. In every tyre mode (paper: dH(u)/du mu).
 * @param[in]  h   the model set up by rfe_meas_setup(h, veh, tp, u)
 * @param[in]  veh vehicle parameters of the set-up
 * @param[in]  tp  tyre parameters (the set-up's, or others: their terms are recomputed)
 * @param[in]  u   the set-up's sample
 * @param[in]  mu  friction per wheel (fl, fr, rl, rr)
 * @param[in]  sd  the scale of each input's column (for the step noise the input noise sds
 *                 sd_in_*, in the input's unit; 1 gives the derivatives themselves)
 * @param[out] G   row-major RFE_MEAS x RFE_INPUTS: G[r RFE_INPUTS + j] = sd_j dh_r/du_j
 *                 (m/s^2 or rad/s^2 per unit of input j: rad, m/s, rad/s, times sd_j)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE (mu, or a sum, not finite); the tyre's
 *         errors (@p G then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_input_jac(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                             const rfe_tyre_params_t *tp, const rfe_sample_t *u,
                                             const rfe_real_t mu[RFE_WHEELS],
                                             const rfe_real_t sd[RFE_INPUTS],
                                             rfe_real_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS]);

/** The lateral rows of h(mu, u) and their first derivatives (rfe_meas_lateral_jac): index 0
 *  the lateral acceleration ay (row 1 of h), index 1 the yaw acceleration r-dot (row 2). */
typedef struct {
    rfe_real_t z[2];    /**< the rows at (mu, u): rfe_meas_eval's z[1], z[2], bit for bit */
    rfe_real_t d_vy[2]; /**< their derivatives by vy [1/s, rad/(m s)] */
    rfe_real_t d_mu[2]; /**< their derivatives by the per-wheel friction in the direction
                             dmu: sum_i dz/dmu_i dmu_i [m/s^2, rad/s^2 per unit of dmu] */
} rfe_meas_lateral_t;

/**
 * The rows ay and r-dot of h(mu, u) at the set-up's sample, with their derivatives by vy and
 * by the friction in the direction @p dmu, analytically, in one pass over the four wheels
 * (docs/OBSERVER.md §4.2): the chain vy -> each wheel's velocity in wheel axes (d v_wx =
 * sin delta_i, d v_wy = cos delta_i) -> tan alpha and kappa (0 where alpha_max or the kappa
 * clip bounds them) -> the tyre's forces (paper F = mu F0, absolute Dugoff, Magic Formula;
 * rfe_tyre_pre_jac) -> the body terms. The load-scaled modes reuse the set-up's tyre terms
 * (so no further slip angle or tangent: two atan2 and one sine and cosine per direction and
 * wheel in magic mode); paper mode computes each wheel's tangent again.
 * @param[in]  h   the model set up by rfe_meas_setup(h, veh, tp, u)
 * @param[in]  veh vehicle parameters of the set-up
 * @param[in]  tp  tyre parameters of the set-up
 * @param[in]  u   the set-up's sample (its wheel speeds are read: kappa's derivative)
 * @param[in]  mu  friction per wheel (fl, fr, rl, rr)
 * @param[in]  dmu the direction of the friction derivative, per wheel (the observer: sd(mu))
 * @param[out] out the rows and their derivatives
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE (mu, dmu or a result not finite); the
 *         tyre's errors, as rfe_meas_eval's (@p out then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_lateral_jac(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                               const rfe_tyre_params_t *tp,
                                               const rfe_sample_t *u,
                                               const rfe_real_t mu[RFE_WHEELS],
                                               const rfe_real_t dmu[RFE_WHEELS],
                                               rfe_meas_lateral_t *out);

#endif /* RFE_MEAS_H */
