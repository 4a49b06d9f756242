/**
 * @file velocity.h
 * @brief The velocity and sideslip observer (docs/OBSERVER.md): the sensors of a car with
 *        ESC in; vx, vy, sideslip beta and yaw acceleration, each with its sd, out.
 *
 * Three two-state Kalman filters (rfe/component/kf2.h): the yaw-rate differentiator, the
 * longitudinal filter [vx, b_x] on wheel speeds and ax, the lateral filter [vy, b_y] on
 * ay - r vx and the friction estimator's measurement model. The caller owns the
 * rfe_velocity_t (no heap); init it once, then step at the sample rate. A rejected sample
 * returns an error status and leaves the observer as it was.
 *
 * @code
 * #include "rfe/velocity.h"
 *
 * static rfe_velocity_t obs;                    // caller-owned, no heap
 *
 * rfe_status_t observer_setup(void)
 * {
 *     rfe_params_t veh;                          // vehicle and tyre: the friction calibration
 *     rfe_velocity_params_t vp;
 *     rfe_status_t st = rfe_params_default(&veh);
 *     if (st == RFE_OK) {
 *         st = rfe_velocity_params_default(&vp);
 *     }
 *     if (st == RFE_OK) {
 *         vp.driven = RFE_DRIVEN_RL | RFE_DRIVEN_RR; // a rear-driven car
 *         st = rfe_velocity_init(&obs, &vp, &veh);
 *     }
 *     return st;
 * }
 *
 * void observer_task(const rfe_velocity_input_t *in)  // SI units, ISO 8855 axes
 * {
 *     rfe_velocity_estimate_t e;
 *     if (!rfe_status_is_error(rfe_velocity_step(&obs, in, NULL, &e))) {
 *         // e.vx, e.vy, e.beta, e.yaw_acc and their sd
 *     }
 * }
 * @endcode
 */
#ifndef RFE_VELOCITY_H
#define RFE_VELOCITY_H

#include "rfe/component/kf2.h"
#include "rfe/config.h"
#include "rfe/params.h"
#include "rfe/velocity_bits.h"
#include "rfe/velocity_params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_velocity_init rfe_velocity_init_f64
#define rfe_velocity_step rfe_velocity_step_f64
#define rfe_velocity_get  rfe_velocity_get_f64
#define rfe_velocity_restart rfe_velocity_restart_f64
#else
#define rfe_velocity_init rfe_velocity_init_f32
#define rfe_velocity_step rfe_velocity_step_f32
#define rfe_velocity_get  rfe_velocity_get_f32
#define rfe_velocity_restart rfe_velocity_restart_f32
#endif

/* The bits of has and flags (RFE_VEL_HAS_*, RFE_VEL_FLAG_*): rfe/velocity_bits.h. */

/** One ESC sample (OBSERVER.md §1), SI units, ISO 8855 axes, wheels fl fr rl rr. */
typedef struct {
    rfe_real_t dt;                  /**< period since the previous sample [s] (first: ignored) */
    rfe_real_t delta;               /**< front road-wheel angle [rad] */
    rfe_real_t steer_wheel;         /**< steering-wheel angle [rad] (RFE_VEL_HAS_STEER_WHEEL) */
    rfe_real_t yaw_rate;            /**< r [rad/s] */
    rfe_real_t ax;                  /**< accelerometer, body x [m/s^2] */
    rfe_real_t ay;                  /**< accelerometer, body y [m/s^2] */
    rfe_real_t omega[RFE_WHEELS];   /**< wheel spin speeds [rad/s] */
    rfe_real_t p_brake[RFE_WHEELS]; /**< wheel-cylinder pressures [MPa] (RFE_VEL_HAS_PRESSURE) */
    rfe_real_t torque[RFE_WHEELS];  /**< drive torques at the wheels [N m] (RFE_VEL_HAS_TORQUE) */
    rfe_real_t grade;               /**< known road grade [rad], uphill positive; 0 if unknown */
    uint32_t has;                   /**< RFE_VEL_HAS_* bits */
} rfe_velocity_input_t;

/** The friction the lateral model uses: the friction estimator's last output. */
typedef struct {
    rfe_real_t mu[RFE_WHEELS]; /**< friction per wheel */
    rfe_real_t sd[RFE_WHEELS]; /**< its sd */
} rfe_velocity_mu_t;

/** Output of one step. */
typedef struct {
    rfe_real_t vx;         /**< [m/s] */
    rfe_real_t vy;         /**< [m/s] */
    rfe_real_t beta;       /**< sideslip atan2(vy, vx) [rad] (0 below v_lat_min) */
    rfe_real_t yaw_acc;    /**< r-dot [rad/s^2] */
    rfe_real_t delta;      /**< the road-wheel angle used [rad] (steer_wheel / steer_ratio
                                when the sample gives the steering-wheel angle) */
    rfe_real_t sd_vx;      /**< [m/s] */
    rfe_real_t sd_vy;      /**< [m/s] */
    rfe_real_t sd_beta;    /**< [rad] */
    rfe_real_t sd_yaw_acc; /**< [rad/s^2] */
    rfe_real_t bx;         /**< longitudinal offset (accelerometer, unknown grade) [m/s^2] */
    rfe_real_t by;         /**< lateral offset (accelerometer, bank) [m/s^2] */
    uint32_t flags;        /**< RFE_VEL_FLAG_* bits */
    rfe_status_t status;   /**< status of the step (same as the return value) */
} rfe_velocity_estimate_t;

/** Observer state (caller-owned; fields read-only for the caller). */
typedef struct {
    uint32_t magic;
    uint32_t started;                 /**< 0 until the first accepted sample, then the
                                           phase of the next step, 1 .. p.lat_every (the
                                           lateral model's rows on phase 1, §4.2) */
    rfe_velocity_params_t p;          /**< the observer's parameters */
    rfe_vehicle_t veh;                /**< vehicle (the friction calibration's) */
    rfe_tyre_params_t tyre;           /**< tyre model (the friction calibration's) */
    rfe_kf2_t yaw;                    /**< [r, r-dot] */
    rfe_kf2_t lon;                    /**< [vx, b_x] */
    rfe_kf2_t lat;                    /**< [vy, b_y] */
    rfe_real_t r_on_ref;              /**< time the yaw rate has stayed on its neutral
                                           reference, at most p.lin_dwell [s] (§4.2b) */
    rfe_velocity_estimate_t last;     /**< the output of the last step */
    rfe_real_t sd_vy_filter;          /**< the lateral filter's own sd(vy) at the last step,
                                           before the reported floor (§5, vy_out_floor_mu):
                                           the friction estimator's vy input noise in the
                                           pipeline (§6) [m/s] */
} rfe_velocity_t;

/**
 * Validates and copies the parameters; the next accepted sample initialises the filters.
 * @param[out] obs  the observer state; written only on RFE_OK.
 * @param[in]  vp   the observer's parameters (rfe_velocity_params_default, then tuning).
 * @param[in]  veh  the vehicle and tyre (the friction estimator's rfe_params_t; its filter
 *                  part is not used).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (rfe_velocity_params_validate or
 *         rfe_params_validate fails).
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_init(rfe_velocity_t *obs,
                                             const rfe_velocity_params_t *vp,
                                             const rfe_params_t *veh,
                                             size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_VELOCITY_IMPL), where the name is the function's own. */
#if !defined(RFE_VELOCITY_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_velocity_init_f64(obs, vp, veh) \
    rfe_velocity_init_f64((obs), (vp), (veh), sizeof(rfe_velocity_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_velocity_init_f32(obs, vp, veh) \
    rfe_velocity_init_f32((obs), (vp), (veh), sizeof(rfe_velocity_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * One step (OBSERVER.md §3-§5).
 * @param[in,out] obs  an observer set up by rfe_velocity_init.
 * @param[in]     in   the sample; dt within [dt_min, dt_max] (but on the first sample; after
 *                     a longer gap, rfe_velocity_restart first).
 * @param[in]     mu   the friction estimator's last estimate, or NULL (then mu_default).
 * @param[out]    out  the estimate (on error: the previous one, with the error status).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NONFINITE (an input);
 *         RFE_ERR_RANGE (dt, or an input outside config.h's limits, a pressure beyond +-RFE_LIMIT_PRESSURE,
 *         a friction outside [0, 2] or a negative sd); the model's and filters' errors. On
 *         error the observer is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_step(rfe_velocity_t *obs,
                                             const rfe_velocity_input_t *in,
                                             const rfe_velocity_mu_t *mu,
                                             rfe_velocity_estimate_t *out);

/**
 * A gap longer than dt_max (OBSERVER.md §1): the filters cannot bridge it (their ax
 * integration and the yaw-rate differentiator assume a short period), so the next accepted
 * sample starts them afresh, as the first after init (§3.0). The parameters stay; the last
 * estimate stays until then. The composed pipeline calls it itself (rfe/pipeline.h).
 * @param[in,out] obs  an observer set up by rfe_velocity_init.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_restart(rfe_velocity_t *obs);

/**
 * The estimate of the last step without stepping.
 * @param[in]  obs  an observer set up by rfe_velocity_init.
 * @param[out] out  the estimate.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_get(const rfe_velocity_t *obs,
                                            rfe_velocity_estimate_t *out);

#endif /* RFE_VELOCITY_H */
