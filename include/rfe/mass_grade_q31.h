/**
 * @file mass_grade_q31.h
 * @brief Fixed-point twin of rfe/mass_grade.h: the mass and road-grade estimator on int32 Q
 *        values (docs/MASS_GRADE.md, docs/FIXED_POINT.md "Mass and grade"). Integer
 *        operations only.
 *
 * The same filter (plain UKF or the seed's AUKF, speed alone or with the accelerometer row),
 * the same pause logic (shared with the float twin) and the same statuses, in the
 * square-root form: the state carries the lower Cholesky factor S of P (P = S S^T), each
 * row in the format of its state, and every covariance step is a Householder triangularisation
 * (rfe_qr_tria_q31), so P stays positive semidefinite by construction (FIXED_POINT.md "Mass
 * and grade" shows what the textbook form P- - K S K^T does in Q31).
 *
 * Formats (rfe/mass_grade_params_q31.h): v, vx, ax, ay and their sd Q24; M and its sd Q14; theta and
 * its sd Q29; dt Q30; torque Q14; brake pressure [MPa] Q25; q_mv int64 Q28 [kg^2/s].
 *
 * Saturation. Every clamp in a step counts one; the estimate carries the step's count
 * (`sat`), the state the running total since init. A saturation is not an error.
 */
#ifndef RFE_MASS_GRADE_Q31_H
#define RFE_MASS_GRADE_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/config.h"
#include "rfe/fixed.h"
#include "rfe/mass_grade_bits.h"
#include "rfe/mass_grade_params_q31.h"

/** The state's size n: [v, M, theta]. */
#define RFE_MG_N_Q31 3

/* Input limits (config.h's in the inputs' formats). */
#ifndef RFE_MG_LIMIT_V_Q31
#define RFE_MG_LIMIT_V_Q31 ((rfe_fix_t)1677721600) /**< |v| <= 100 m/s, Q24 */
#endif
#ifndef RFE_MG_LIMIT_TORQUE_Q31
#define RFE_MG_LIMIT_TORQUE_Q31 ((rfe_fix_t)1638400000) /**< |torque| <= 1e5 N m, Q14 */
#endif
#ifndef RFE_MG_LIMIT_AX_Q31
#define RFE_MG_LIMIT_AX_Q31 ((rfe_fix_t)838860800) /**< |ax| <= 50 m/s^2, Q24 */
#endif

/** One sample (fields as rfe_mass_grade_input_t). */
typedef struct {
    rfe_fix_t dt;      /**< period since the previous sample [s], Q30 (first sample: ignored) */
    rfe_fix_t v;       /**< vehicle speed [m/s], Q24 */
    rfe_fix_t torque;  /**< total drive torque at the wheels [N m], Q14 */
    rfe_fix_t p_brake; /**< brake pressure [MPa], Q25 (RFE_MG_HAS_PRESSURE) */
    rfe_fix_t ax;      /**< accelerometer, body x [m/s^2], Q24 (RFE_MG_HAS_AX) */
    rfe_fix_t vx;      /**< the car's speed over ground [m/s], Q24 (RFE_MG_HAS_VX) */
    rfe_fix_t ay;      /**< accelerometer, body y [m/s^2], Q24 (RFE_MG_HAS_AY) */
    int32_t gear;      /**< engaged gear (RFE_MG_HAS_GEAR) */
    uint32_t brake;    /**< brake pedal: 0 released, else pressed (RFE_MG_HAS_BRAKE) */
    uint32_t has;      /**< RFE_MG_HAS_* bits */
} rfe_mass_grade_input_q31_t;

/** Output of one step (fields as rfe_mass_grade_estimate_t, plus the saturations). */
typedef struct {
    rfe_fix_t mass;      /**< M [kg], Q14 */
    rfe_fix_t sd_mass;   /**< sqrt(P_MM) [kg], Q14 */
    rfe_fix_t grade;     /**< theta [rad], Q29 */
    rfe_fix_t sd_grade;  /**< sqrt(P_thth) [rad], Q29 */
    rfe_fix_t v;         /**< the filter's speed [m/s], Q24 */
    rfe_fix_t sd_v;      /**< [m/s], Q24 */
    int64_t q_mv;        /**< the adaptive mass process noise [kg^2/s], Q28 */
    rfe_fix_t e_ax;      /**< §4.8 the EMA of the ax row's normalised innovation [1], Q24 */
    uint32_t mismatch;   /**< §4.8 1: |e_ax| > mm_e (mm_e > 0); else 0 */
    uint32_t sat;        /**< saturations in this step */
    rfe_status_t status; /**< status of the step (same as the return value) */
} rfe_mass_grade_estimate_q31_t;

/** Estimator state (caller-owned; fields read-only for the caller). */
typedef struct {
    uint32_t magic;
    uint32_t started;                        /**< 0 until the first accepted sample */
    rfe_mass_grade_params_q31_t p;           /**< the parameters */
    rfe_fix_t wm0;                           /**< mean weight of the centre point, Q30 */
    rfe_fix_t wi;                            /**< weight of every other point, Q30 */
    rfe_fix_t sqrt_wc0;                      /**< sqrt of the centre's covariance weight, Q30 */
    rfe_fix_t sqrt_wi;                       /**< sqrt(wi), Q30 */
    rfe_fix_t sqrt_c;                        /**< sqrt(n + lambda), Q29 */
    rfe_fix_t x[RFE_MG_N_Q31];               /**< [v Q24, M Q14, theta Q29] */
    rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31]; /**< lower factor of P, row-major, row i in
                                                   state i's format */
    int64_t q_mv;                            /**< adaptive mass process noise [kg^2/s], Q28 */
    int64_t adapt_elapsed;                   /**< time since the adaptation period began [s], Q30 */
    rfe_fix_t m_adapt;                       /**< the mass when it began [kg], Q14 */
    int64_t brake_left;                      /**< hold left after the last braked sample [s], Q30 */
    int64_t shift_left;                      /**< hold left after the last gear change [s], Q30 */
    int64_t curve_left;                      /**< hold left after the last sample over ay_max [s],
                                                  Q30 */
    rfe_fix_t torque_prev;                   /**< the last accepted sample's torque, Q14 */
    int32_t gear;                            /**< the last gear given */
    uint32_t has_gear;                       /**< nonzero once a sample gave a gear */
    uint32_t slip_latched;                   /**< the ABS gate's latch (pause_grade_slip) */
    uint32_t v_free;                         /**< v uncorrelated with M: the last accepted sample
                                                  was a start or a paused one (pause_grade) */
    uint32_t chg_on;                         /**< the change test tripped in this pause
                                                  (pause_grade_dv) */
    int64_t chg_d;                           /**< the change test's residual [m/s], Q24 */
    rfe_fix_t u_prev;                        /**< the test's speed at the last accepted sample
                                                  [m/s], Q24 */
    rfe_fix_t wq_rate;                       /**< §4.7 the grade rate, low-passed [rad/s], Q30 */
    rfe_fix_t wq_ms;                         /**< §4.7 its mean square [rad^2/s^2], Q30 */
    uint32_t wq_hi;                          /**< §4.7 the walk's level: 1 q_theta_hi */
    rfe_fix_t mm_e;                          /**< §4.8 the mismatch monitor's EMA [1], Q24 */
    uint32_t sat;                            /**< saturations since init (stops at UINT32_MAX) */
    rfe_mass_grade_estimate_q31_t last;      /**< the output of the last step */
} rfe_mass_grade_q31_t;

/**
 * Validates and copies the parameters (rfe_mass_grade_params_validate_q31); the next
 * accepted sample starts the filter (MASS_GRADE.md §4.1).
 * @param[out] mg  the estimator state; written only on RFE_OK.
 * @param[in]  p   the parameters (rfe_mass_grade_params_to_q31 of a real set).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; RFE_ERR_ABI (through the wrapper macro, as
 *         rfe_mass_grade_init).
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_init_q31(rfe_mass_grade_q31_t *mg,
                                                   const rfe_mass_grade_params_q31_t *p,
                                                   size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_MASS_GRADE_Q31_IMPL), where the name is the function's own. */
#if !defined(RFE_MASS_GRADE_Q31_IMPL)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_mass_grade_init_q31(mg, p) \
    rfe_mass_grade_init_q31((mg), (p), sizeof(rfe_mass_grade_q31_t), RFE_CONFIG_Q31)
#endif

/**
 * One step (MASS_GRADE.md §4), as rfe_mass_grade_step.
 * @param[in,out] mg   an estimator set up by rfe_mass_grade_init_q31.
 * @param[in]     in   the sample.
 * @param[out]    out  the estimate (on error: the previous one, with the error status).
 * @return RFE_OK; RFE_NO_UPDATE_LOW_SPEED, RFE_MG_PAUSED_BRAKE, RFE_MG_PAUSED_SHIFT,
 *         RFE_MG_PAUSED_SLIP, RFE_MG_PAUSED_CURVE; errors: RFE_ERR_NULL;
 *         RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE (|v|, a given |vx|, |torque|, |ax|, a given |ay|
 *         beyond
 *         the RFE_MG_LIMIT_*_Q31, a `has` bit not RFE_MG_HAS_*, no ax while use_ax, dt <= 0
 *         after the first sample); RFE_ERR_NOT_POSITIVE_DEFINITE (the innovation's factor
 *         has a zero diagonal: never with r_v, r_ax > 0). On error the estimator is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_step_q31(rfe_mass_grade_q31_t *mg,
                                                   const rfe_mass_grade_input_q31_t *in,
                                                   rfe_mass_grade_estimate_q31_t *out);

/**
 * A load change (MASS_GRADE.md §4.5), as rfe_mass_grade_restart.
 * @param[in,out] mg  an estimator set up by rfe_mass_grade_init_q31.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_restart_q31(rfe_mass_grade_q31_t *mg);

/**
 * The estimate of the last step without stepping.
 * @param[in]  mg   an estimator set up by rfe_mass_grade_init_q31.
 * @param[out] out  the estimate.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_get_q31(const rfe_mass_grade_q31_t *mg,
                                                  rfe_mass_grade_estimate_q31_t *out);

#endif /* RFE_MASS_GRADE_Q31_H */
