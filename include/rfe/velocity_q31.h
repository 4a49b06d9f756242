/**
 * @file velocity_q31.h
 * @brief Fixed-point twin of rfe/velocity.h: the velocity and sideslip observer on int32 Q
 *        values (docs/OBSERVER.md, docs/FIXED_POINT.md "Observer"). Integer operations only.
 *
 * Same three two-state filters (rfe/component/kf2_q31.h), same step order and decisions
 * (shared with the float twin: rfe/velocity_bits.h and the private velocity_logic.h), the
 * lateral filter on the friction estimator's Q31 measurement model (meas_q31.h). The caller
 * owns the rfe_velocity_q31_t (no heap); a rejected sample returns an error status and
 * leaves the observer as it was.
 *
 * Formats (fractional bits): dt Q30; delta, grade, beta Q29; steering-wheel angle Q26; yaw
 * rate Q27; ax, ay, yaw acceleration and the offsets Q24; wheel speeds Q22; pressures Q25;
 * torques Q15; speeds Q23; friction Q29 and its sd Q30.
 *
 * Saturation. Every clamp anywhere in a step (filters, measurement model, wheel references,
 * outputs) counts one; the estimate carries the step's count (`sat`), the state the running
 * total since init. A saturation is not an error.
 */
#ifndef RFE_VELOCITY_Q31_H
#define RFE_VELOCITY_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/component/kf2_q31.h"
#include "rfe/config.h"
#include "rfe/fixed.h"
#include "rfe/friction_q31.h"
#include "rfe/params_q31.h"
#include "rfe/velocity_bits.h"
#include "rfe/velocity_params_q31.h"

/* Input limits of the observer beyond friction_q31.h's RFE_FIX_LIMIT_* (delta, yaw rate,
 * accelerations, wheel speeds): config.h's in the inputs' formats. */
#ifndef RFE_FIX_LIMIT_PRESSURE
#define RFE_FIX_LIMIT_PRESSURE ((rfe_fix_t)1677721600) /**< |p| <= 50 MPa, Q25 */
#endif
#ifndef RFE_FIX_LIMIT_TORQUE
#define RFE_FIX_LIMIT_TORQUE ((rfe_fix_t)655360000) /**< |torque| <= 20000 N m, Q15 */
#endif
#ifndef RFE_FIX_LIMIT_GRADE
#define RFE_FIX_LIMIT_GRADE ((rfe_fix_t)322122547) /**< |grade| <= 0.6 rad, Q29 (the largest
                                                        Q29 value not above 0.6) */
#endif
#ifndef RFE_FIX_LIMIT_MU_IN
#define RFE_FIX_LIMIT_MU_IN ((rfe_fix_t)1073741824) /**< a friction input <= 2, Q29 */
#endif

/** One ESC sample (fields as rfe_velocity_input_t). */
typedef struct {
    rfe_fix_t dt;                  /**< period since the previous sample [s], Q30 */
    rfe_fix_t delta;               /**< front road-wheel angle [rad], Q29 */
    rfe_fix_t steer_wheel;         /**< steering-wheel angle [rad], Q26 (RFE_VEL_HAS_STEER_WHEEL) */
    rfe_fix_t yaw_rate;            /**< r [rad/s], Q27 */
    rfe_fix_t ax;                  /**< accelerometer, body x [m/s^2], Q24 */
    rfe_fix_t ay;                  /**< accelerometer, body y [m/s^2], Q24 */
    rfe_fix_t omega[RFE_WHEELS];   /**< wheel spin speeds [rad/s], Q22 */
    rfe_fix_t p_brake[RFE_WHEELS]; /**< wheel-cylinder pressures [MPa], Q25 */
    rfe_fix_t torque[RFE_WHEELS];  /**< drive torques at the wheels [N m], Q15 */
    rfe_fix_t grade;               /**< known road grade [rad], Q29 */
    uint32_t has;                  /**< RFE_VEL_HAS_* bits */
} rfe_velocity_input_q31_t;

/** The friction the lateral model uses (fields as rfe_velocity_mu_t). */
typedef struct {
    rfe_fix_t mu[RFE_WHEELS]; /**< friction per wheel, Q29 */
    rfe_fix_t sd[RFE_WHEELS]; /**< its sd, Q30 */
} rfe_velocity_mu_q31_t;

/** Output of one step (fields as rfe_velocity_estimate_t, plus the saturations). */
typedef struct {
    rfe_fix_t vx;          /**< [m/s], Q23 */
    rfe_fix_t vy;          /**< [m/s], Q23 */
    rfe_fix_t beta;        /**< sideslip [rad], Q29 (0 below v_lat_min) */
    rfe_fix_t yaw_acc;     /**< r-dot [rad/s^2], Q24 */
    rfe_fix_t delta;       /**< the road-wheel angle used [rad], Q29 */
    rfe_fix_t sd_vx;       /**< [m/s], Q23 */
    rfe_fix_t sd_vy;       /**< [m/s], Q23 */
    rfe_fix_t sd_beta;     /**< [rad], Q29 */
    rfe_fix_t sd_yaw_acc;  /**< [rad/s^2], Q24 */
    rfe_fix_t bx;          /**< longitudinal offset [m/s^2], Q24 */
    rfe_fix_t by;          /**< lateral offset [m/s^2], Q24 */
    uint32_t flags;        /**< RFE_VEL_FLAG_* bits */
    rfe_status_t status;   /**< status of the step (same as the return value) */
    uint32_t sat;          /**< saturations of this step (0 on an error and from get) */
} rfe_velocity_estimate_q31_t;

/** Observer state (caller-owned; fields read-only for the caller). */
typedef struct {
    uint32_t magic;
    uint32_t started;                 /**< 0 until the first accepted sample, then the
                                           phase of the next step, 1 .. p.lat_every (the
                                           lateral model's rows on phase 1, §4.2) */
    rfe_velocity_params_q31_t p;      /**< the observer's parameters */
    rfe_vehicle_q31_t veh;            /**< vehicle (the friction calibration's) */
    rfe_tyre_params_q31_t tyre;       /**< tyre model (the friction calibration's) */
    rfe_kf2_q31_t yaw;                /**< [r Q27, r-dot Q24] */
    rfe_kf2_q31_t lon;                /**< [vx Q23, b_x Q24] */
    rfe_kf2_q31_t lat;                /**< [vy Q23, b_y Q24] */
    rfe_fix_t r_on_ref;               /**< time the yaw rate has stayed on its neutral
                                           reference, at most p.lin_dwell [s], Q30 */
    rfe_velocity_estimate_q31_t last; /**< the output of the last step */
    rfe_fix_t sd_vy_filter;           /**< the lateral filter's own sd(vy) at the last step,
                                           before the reported floor (§5), Q23: the friction
                                           estimator's vy input noise in the pipeline (§6) */
    uint32_t sat;                     /**< saturations since init (saturating) */
} rfe_velocity_q31_t;

/**
 * Validates and copies the parameters; the next accepted sample initialises the filters.
 * @param[out] obs  the observer state; written only on RFE_OK.
 * @param[in]  vp   the observer's parameters (rfe_velocity_params_default_q31, or converted).
 * @param[in]  veh  the vehicle and tyre (the friction estimator's rfe_params_q31_t; its
 *                  filter part is not used).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_init_q31(rfe_velocity_q31_t *obs,
                                                 const rfe_velocity_params_q31_t *vp,
                                                 const rfe_params_q31_t *veh,
                                                 size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_VELOCITY_Q31_IMPL), where the name is the function's own. */
#if !defined(RFE_VELOCITY_Q31_IMPL)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_velocity_init_q31(obs, vp, veh) \
    rfe_velocity_init_q31((obs), (vp), (veh), sizeof(rfe_velocity_q31_t), RFE_CONFIG_Q31)
#endif

/**
 * One step (OBSERVER.md §3-§5).
 * @param[in,out] obs  an observer set up by rfe_velocity_init_q31.
 * @param[in]     in   the sample; dt within [dt_min, dt_max] (but on the first sample).
 * @param[in]     mu   the friction estimator's last estimate, or NULL (then mu_default).
 * @param[out]    out  the estimate (on error: the previous one, with the error status and
 *                     sat 0).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE (dt, or an input
 *         beyond the RFE_FIX_LIMIT_* limits, a friction outside [0, 2] or a negative sd);
 *         the model's and filters' errors. On error the observer is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_step_q31(rfe_velocity_q31_t *obs,
                                                 const rfe_velocity_input_q31_t *in,
                                                 const rfe_velocity_mu_q31_t *mu,
                                                 rfe_velocity_estimate_q31_t *out);

/**
 * A gap longer than dt_max: the next accepted sample starts the filters afresh (the twin of
 * rfe_velocity_restart).
 * @param[in,out] obs  an observer set up by rfe_velocity_init_q31.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_restart_q31(rfe_velocity_q31_t *obs);

/**
 * The estimate of the last step without stepping (sat 0).
 * @param[in]  obs  an observer set up by rfe_velocity_init_q31.
 * @param[out] out  the estimate.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_get_q31(const rfe_velocity_q31_t *obs,
                                                rfe_velocity_estimate_q31_t *out);

#endif /* RFE_VELOCITY_Q31_H */
