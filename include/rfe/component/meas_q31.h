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

#include <stddef.h>
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

/** The nominal per-wheel terms of h(mu, u) at the set-up sample (caller-owned, written by
 *  rfe_meas_nominal_q31): in the load-scaled modes wheel i's column of H at its forces
 *  F(mu_i) (Q24) at t[i RFE_MEAS ..] and that wheel's saturation count (its kinematics' from
 *  the set-up, its forces' and entries'); paper mode: unused. */
typedef struct {
    rfe_fix_t t[(size_t)RFE_WHEELS * (size_t)RFE_MEAS]; /**< wheel i's terms at i RFE_MEAS, Q24 */
    uint32_t cnt[RFE_WHEELS];           /**< wheel i's saturations */
} rfe_meas_terms_q31_t;

/**
 * z = h(mu, u) (Q24) for the sample u of the last rfe_meas_setup_q31, and (load-scaled
 * modes) the per-wheel terms that rfe_meas_eval_perturbed_q31 reuses for the wheels an input
 * change does not reach. Paper mode: z as rfe_meas_eval_q31. Load-scaled modes: the exact
 * sum of the wheels' terms from the set-up's friction-independent tyre terms, the integers of
 * rfe_meas_eval_q31 (with the set-up's kinematics counts). Preconditions of the load-scaled
 * modes (not checked, as the estimator guarantees them): @p tp is the set-up's and passed
 * rfe_params_validate_q31.
 * @param[in]  h   the model set up by rfe_meas_setup_q31 with @p veh and @p tp
 * @param[in]  veh vehicle parameters of the set-up
 * @param[in]  tp  tyre parameters of the set-up
 * @param[in]  mu  friction per wheel (fl, fr, rl, rr), Q29
 * @param[out] nom the nominal terms and counts (load-scaled modes; paper mode: untouched)
 * @param[out] z   h(mu, u), Q24
 * @param[in,out] sat saturation counter (required), added to on success
 * @return RFE_OK; RFE_ERR_NULL; the errors of rfe_meas_eval_q31 in paper mode (@p nom, @p z,
 *         *sat then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_nominal_q31(const rfe_meas_q31_t *h,
                                                const rfe_vehicle_q31_t *veh,
                                                const rfe_tyre_params_q31_t *tp,
                                                const rfe_fix_t mu[RFE_WHEELS],
                                                rfe_meas_terms_q31_t *nom,
                                                rfe_fix_t z[RFE_MEAS], uint32_t *sat);

/**
 * z = h(mu, u + d e_j) (Q24): the model at the set-up's sample u with its input @p j
 * (RFE_IN_*, rfe/common.h) changed by @p d (saturating, counted), the integers and counts
 * rfe_meas_setup_q31 and rfe_meas_eval_q31 at that sample give. Paper mode does exactly that;
 * the load-scaled modes evaluate again only the wheels input j reaches (delta: the front
 * wheels, vx, vy, r: all, omega_w: wheel w's slip) and take the other wheels' terms and
 * counts from @p nom (preconditions as rfe_meas_nominal_q31).
 * @param[in]  h   the model set up by rfe_meas_setup_q31(h, veh, tp, u, .)
 * @param[in]  veh vehicle parameters of the set-up
 * @param[in]  tp  tyre parameters of the set-up
 * @param[in]  nom the terms of rfe_meas_nominal_q31(h, veh, tp, mu, ...) (load-scaled modes)
 * @param[in]  u   the set-up's sample
 * @param[in]  j   the input to change: RFE_IN_DELTA .. RFE_INPUTS - 1
 * @param[in]  d   the change of input j, in that input's format
 * @param[in]  mu  friction per wheel (fl, fr, rl, rr), Q29, as given to rfe_meas_nominal_q31
 * @param[out] z   h(mu, u + d e_j), Q24
 * @param[in,out] sat saturation counter (required), added to on success
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (@p j out of range); in paper mode the errors
 *         of the set-up and evaluation (@p z, *sat then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_eval_perturbed_q31(
    const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
    const rfe_meas_terms_q31_t *nom, const rfe_sample_q31_t *u, size_t j, rfe_fix_t d,
    const rfe_fix_t mu[RFE_WHEELS], rfe_fix_t z[RFE_MEAS], uint32_t *sat);

/** The lateral rows of h(mu, u) and their first derivatives (rfe_meas_lateral_jac_q31), Q24:
 *  index 0 the lateral acceleration ay (row 1 of h), index 1 the yaw acceleration r-dot. */
typedef struct {
    rfe_fix_t z[2];    /**< the rows at (mu, u): rfe_meas_eval_q31's z[1], z[2] [m/s^2, rad/s^2] */
    rfe_fix_t d_vy[2]; /**< their derivatives by vy [1/s, rad/(m s)] */
    rfe_fix_t d_mu[2]; /**< sum_i dz/dmu_i dmu_i [m/s^2, rad/s^2] */
} rfe_meas_lateral_q31_t;

/**
 * Fixed-point twin of rfe_meas_lateral_jac (rfe/component/meas.h): the rows ay and r-dot of
 * h(mu, u) at the set-up's sample (the integers and counts of rfe_meas_eval_q31), their
 * derivatives by vy and by the per-wheel friction in the direction @p dmu, analytically in one
 * pass over the wheels (docs/OBSERVER.md §4.2). The derivatives are the float formulas in
 * rfe_xf_t (numerics/xf_q31.h: 30 significant bits and a power of two, 2^-30 relative per
 * operation; docs/FIXED_POINT.md "Observer" gives the error) rounded once to Q24, saturating
 * (counted) beyond +-128.
 * @param[in]  h   the model set up by rfe_meas_setup_q31(h, veh, tp, u, .)
 * @param[in]  veh vehicle parameters of the set-up
 * @param[in]  tp  tyre parameters of the set-up
 * @param[in]  u   the set-up's sample (its wheel speeds are read: kappa's derivative)
 * @param[in]  mu  friction per wheel, Q29
 * @param[in]  dmu the direction of the friction derivative per wheel, Q30 (the observer: sd)
 * @param[out] out the rows and their derivatives, Q24
 * @param[in,out] sat saturation counter (required), added to on success
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (tyre parameters); rfe_meas_eval_q31's errors
 *         (@p out, *sat then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_lateral_jac_q31(const rfe_meas_q31_t *h,
                                                    const rfe_vehicle_q31_t *veh,
                                                    const rfe_tyre_params_q31_t *tp,
                                                    const rfe_sample_q31_t *u,
                                                    const rfe_fix_t mu[RFE_WHEELS],
                                                    const rfe_fix_t dmu[RFE_WHEELS],
                                                    rfe_meas_lateral_q31_t *out, uint32_t *sat);

/**
 * Fixed-point twin of rfe_meas_input_jac (rfe/component/meas.h): G = dh/du diag(sd), the
 * step noise's input columns in analytic form (the step noise uses them since issue 21:
 * docs/FIXED_POINT.md "Analytic input derivatives"), analytically from one set-up:
 * the float formulas in rfe_xf_t (numerics/xf_q31.h: 30 significant bits and a power of two,
 * 2^-30 relative per operation; docs/FIXED_POINT.md "Analytic input derivatives" gives the error) rounded once
 * to Q24, saturating (counted) beyond +-128. A column whose sd is <= 0 is 0 (not formed).
 * @param[in]  h   the model set up by rfe_meas_setup_q31(h, veh, tp, u, .)
 * @param[in]  veh vehicle parameters of the set-up
 * @param[in]  tp  tyre parameters of the set-up
 * @param[in]  u   the set-up's sample
 * @param[in]  mu  friction per wheel, Q29
 * @param[in]  sd  the scale of each input's column, in that input's format (the sample's:
 *                 delta Q29, vx, vy Q23, r Q27, omega Q22; for the step noise sd_in_*)
 * @param[out] G   row-major RFE_MEAS x RFE_INPUTS, Q24: G[r RFE_INPUTS + j] = sd_j dh_r/du_j
 * @param[in,out] sat saturation counter (required), added to on success
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (tyre parameters); RFE_ERR_RANGE (load-scaled
 *         modes: a negative load) (@p G, *sat then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_meas_input_jac_q31(const rfe_meas_q31_t *h,
                                                  const rfe_vehicle_q31_t *veh,
                                                  const rfe_tyre_params_q31_t *tp,
                                                  const rfe_sample_q31_t *u,
                                                  const rfe_fix_t mu[RFE_WHEELS],
                                                  const rfe_fix_t sd[RFE_INPUTS],
                                                  rfe_fix_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS],
                                                  uint32_t *sat);

#endif /* RFE_MEAS_Q31_H */
