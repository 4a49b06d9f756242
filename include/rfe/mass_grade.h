/**
 * @file mass_grade.h
 * @brief The vehicle mass and road-grade estimator (docs/MASS_GRADE.md): speed, drive
 *        torque and optionally brake, gear and the accelerometer in; mass and grade, each
 *        with its sd, out.
 *
 * One unscented Kalman filter on x = [v, M, theta] and the longitudinal model: the plain UKF
 * or the seed's adaptive one (AUKF), on the speed alone or with the accelerometer row. The
 * caller owns the rfe_mass_grade_t (no heap); init it once, then step at the sample rate. A
 * rejected sample returns an error status and leaves the estimator as it was.
 *
 * @code
 * #include "rfe/mass_grade.h"
 *
 * static rfe_mass_grade_t mg;                   // caller-owned, no heap
 *
 * rfe_status_t mass_grade_setup(void)
 * {
 *     rfe_mass_grade_params_t p;
 *     rfe_status_t st = rfe_mass_grade_params_default(&p); // car, UKF + accelerometer
 *     if (st == RFE_OK) {
 *         st = rfe_mass_grade_init(&mg, &p);
 *     }
 *     return st;
 * }
 *
 * void mass_grade_task(const rfe_mass_grade_input_t *in) // SI units
 * {
 *     rfe_mass_grade_estimate_t e;
 *     if (!rfe_status_is_error(rfe_mass_grade_step(&mg, in, &e))) {
 *         // e.mass, e.grade and their sd; e.status says whether the filter updated
 *     }
 * }
 * @endcode
 */
#ifndef RFE_MASS_GRADE_H
#define RFE_MASS_GRADE_H

#include "rfe/config.h"
#include "rfe/mass_grade_bits.h"
#include "rfe/mass_grade_params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_mass_grade_init    rfe_mass_grade_init_f64
#define rfe_mass_grade_step    rfe_mass_grade_step_f64
#define rfe_mass_grade_get     rfe_mass_grade_get_f64
#define rfe_mass_grade_restart rfe_mass_grade_restart_f64
#else
#define rfe_mass_grade_init    rfe_mass_grade_init_f32
#define rfe_mass_grade_step    rfe_mass_grade_step_f32
#define rfe_mass_grade_get     rfe_mass_grade_get_f32
#define rfe_mass_grade_restart rfe_mass_grade_restart_f32
#endif

/** The state's size n: [v, M, theta]. */
#define RFE_MG_N 3

/** One sample (MASS_GRADE.md §1), SI units. The optional inputs count only when their
 *  RFE_MG_HAS_* bit is set in `has`. */
typedef struct {
    rfe_real_t dt;      /**< period since the previous sample [s] (first sample: ignored) */
    rfe_real_t v;       /**< vehicle speed [m/s] */
    rfe_real_t torque;  /**< total drive torque at the wheels [N m] (negative: engine or
                             motor braking) */
    rfe_real_t p_brake; /**< brake pressure [Pa] (RFE_MG_HAS_PRESSURE) */
    rfe_real_t ax;      /**< accelerometer, body x, specific force [m/s^2] (RFE_MG_HAS_AX;
                             required with use_ax) */
    rfe_real_t vx;      /**< the car's speed over ground from another source than the wheels
                             (a measurement or an observer) [m/s] (RFE_MG_HAS_VX): the slip
                             pause's reference (§4.2) */
    rfe_real_t ay;      /**< accelerometer, body y, specific force [m/s^2] (RFE_MG_HAS_AY):
                             the curve pause's input (§4.2) */
    int32_t gear;       /**< engaged gear (RFE_MG_HAS_GEAR); a change starts a hold */
    uint32_t brake;     /**< brake pedal: 0 released, else pressed (RFE_MG_HAS_BRAKE) */
    uint32_t has;       /**< RFE_MG_HAS_* bits */
} rfe_mass_grade_input_t;

/** Output of one step. */
typedef struct {
    rfe_real_t mass;     /**< M [kg] */
    rfe_real_t sd_mass;  /**< sqrt(P_MM) [kg] */
    rfe_real_t grade;    /**< theta [rad], uphill positive */
    rfe_real_t sd_grade; /**< sqrt(P_thth) [rad] */
    rfe_real_t v;        /**< the filter's speed [m/s] */
    rfe_real_t sd_v;     /**< [m/s] */
    rfe_real_t q_mv;     /**< the adaptive part of the mass process noise [kg^2/s] (0 in the
                              UKF and once the adaptation has ended) */
    rfe_real_t e_ax;     /**< §4.8 the EMA of the ax row's normalised innovation (0 without
                              the row) [1] */
    uint32_t mismatch;   /**< §4.8 1: |e_ax| > mm_e (mm_e > 0), the model is contradicted
                              (a feed of the mass should hold); else 0 */
    rfe_status_t status; /**< status of the step (same as the return value) */
} rfe_mass_grade_estimate_t;

/** Estimator state (caller-owned; fields read-only for the caller). */
typedef struct {
    uint32_t magic;
    uint32_t started;                 /**< 0 until the first accepted sample after init or
                                           a restart */
    rfe_mass_grade_params_t p;        /**< the parameters */
    rfe_real_t wm0;                   /**< mean weight of the centre point (§3) */
    rfe_real_t wc0;                   /**< covariance weight of the centre point (its sign) */
    rfe_real_t wi;                    /**< weight of every other point */
    rfe_real_t sqrt_wc0;              /**< sqrt(|w_c,0|) */
    rfe_real_t sqrt_wi;               /**< sqrt(w_i) */
    rfe_real_t sqrt_c;                /**< sqrt(n + lambda): the points' spread factor */
    rfe_real_t x[RFE_MG_N];           /**< [v, M, theta] */
    rfe_real_t S[RFE_MG_N * RFE_MG_N]; /**< the lower factor of its covariance P = S S^T,
                                           row-major (the square-root form, §4.3) */
    rfe_real_t q_mv;                  /**< adaptive mass process noise [kg^2/s] */
    rfe_real_t adapt_elapsed;         /**< time since the adaptation period began [s] */
    rfe_real_t m_adapt;               /**< the mass when it began [kg] */
    rfe_real_t brake_left;            /**< hold left after the last braked sample [s] */
    rfe_real_t shift_left;            /**< hold left after the last gear change [s] */
    rfe_real_t curve_left;            /**< hold left after the last sample over ay_max [s] */
    rfe_real_t torque_prev;           /**< the last accepted sample's torque [N m] */
    int32_t gear;                     /**< the last gear given */
    uint32_t has_gear;                /**< nonzero once a sample gave a gear */
    uint32_t slip_latched;            /**< the ABS gate's latch (§4.2, pause_grade_slip): the
                                           wheels slipped in this pause, which then holds */
    uint32_t v_free;                  /**< v uncorrelated with M: the last accepted sample was a
                                           start or a paused one (§4.2, pause_grade) */
    uint32_t chg_on;                  /**< the change test tripped in this pause (§4.2,
                                           pause_grade_dv): it learns to its end */
    rfe_real_t chg_d;                 /**< the change test's residual in this pause [m/s] */
    rfe_real_t u_prev;                /**< the test's speed (vx if given, else v) at the last
                                           accepted sample [m/s] */
    rfe_real_t wq_rate;               /**< §4.7 the grade rate, low-passed [rad/s] */
    rfe_real_t wq_ms;                 /**< §4.7 its mean square [rad^2/s^2] */
    uint32_t wq_hi;                   /**< §4.7 the walk's level: 1 q_theta_hi, 0 q_theta */
    rfe_real_t mm_e;                  /**< §4.8 the mismatch monitor's EMA [1] */
    rfe_mass_grade_estimate_t last;   /**< the output of the last step */
} rfe_mass_grade_t;

/**
 * Validates and copies the parameters; the next accepted sample starts the filter (§4.1).
 * @param[out] mg  the estimator state; written only on RFE_OK.
 * @param[in]  p   the parameters (rfe_mass_grade_params_default or _preset, then tuning).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (rfe_mass_grade_params_validate fails).
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another number
 *       type than the library (the configuration word carries both, as for every init).
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_init(rfe_mass_grade_t *mg,
                                               const rfe_mass_grade_params_t *p,
                                               size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_MASS_GRADE_IMPL), where the name is the function's own. */
#if !defined(RFE_MASS_GRADE_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_mass_grade_init_f64(mg, p) \
    rfe_mass_grade_init_f64((mg), (p), sizeof(rfe_mass_grade_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_mass_grade_init_f32(mg, p) \
    rfe_mass_grade_init_f32((mg), (p), sizeof(rfe_mass_grade_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * One step (MASS_GRADE.md §4): a start on the first sample and after a period longer than
 * dt_max; else the hold of §4.2 or the filter's update (§4.3) and the adaptation (§4.4).
 * @param[in,out] mg   an estimator set up by rfe_mass_grade_init.
 * @param[in]     in   the sample.
 * @param[out]    out  the estimate (on error: the previous one, with the error status;
 *                     before the first accepted sample every value is 0).
 * @return RFE_OK (updated); RFE_NO_UPDATE_LOW_SPEED, RFE_MG_PAUSED_BRAKE,
 *         RFE_MG_PAUSED_SHIFT, RFE_MG_PAUSED_SLIP, RFE_MG_PAUSED_CURVE (held, or started on
 *         a sample that would hold; in a pause whose bit pause_grade sets, M held and the
 *         grade learned from ax until the wheels slip beyond pause_grade_slip against a
 *         given vx (the ABS gate: the rest of that pause holds), §4.2); errors: RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NONFINITE (an input);
 *         RFE_ERR_RANGE (|v| or a given |vx| > RFE_LIMIT_VX, |torque| > RFE_LIMIT_DRIVE_TORQUE,
 *         |ax| or a given |ay| > RFE_LIMIT_ACC, a `has` bit not RFE_MG_HAS_*, no ax while use_ax, dt <= 0
 *         after the first sample); RFE_ERR_NOT_POSITIVE_DEFINITE (a negative pivot or
 *         innovation determinant in the filter, or a variance the update made negative); RFE_ERR_NONFINITE also when the start, a
 *         hold or the update overflows (valid parameters whose squares overflow the number
 *         type, e.g. r_v = 1e30 in float). On error the estimator is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_step(rfe_mass_grade_t *mg,
                                               const rfe_mass_grade_input_t *in,
                                               rfe_mass_grade_estimate_t *out);

/**
 * A load change (MASS_GRADE.md §4.5): passengers or cargo changed at a stop, so the mass
 * learned is no longer the vehicle's. The next accepted sample starts the filter afresh
 * (§4.1: m0, theta0 and their sd, the adaptation re-armed). The parameters stay; the last
 * estimate stays until then.
 * @param[in,out] mg  an estimator set up by rfe_mass_grade_init.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_restart(rfe_mass_grade_t *mg);

/**
 * The estimate of the last step without stepping.
 * @param[in]  mg   an estimator set up by rfe_mass_grade_init.
 * @param[out] out  the estimate.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_get(const rfe_mass_grade_t *mg,
                                              rfe_mass_grade_estimate_t *out);

#endif /* RFE_MASS_GRADE_H */
