/**
 * @file friction_q31.h
 * @brief Fixed-point twin of rfe/friction.h: the friction estimator on int32 Q values
 *        (docs/ESTIMATOR.md "one step", docs/FIXED_POINT.md "Estimator").
 *
 * Composition of the q31 modules, one hop each: sample -> input conditioning
 * (conditioner_q31) -> time update (sckf_q31/ckf_q31) -> kinematics, loads, slips, forces
 * (meas_q31: tyre_q31, obsmat_q31) -> step noise S_R (step_noise_q31) -> cubature points, information
 * gate, measurement update (sckf_q31) -> sd bounds, projection -> model-validity monitor on the
 * step's innovation (monitor_q31, when mon_enable = 1) -> estimate per wheel (T map).
 * The caller owns the rfe_friction_q31_t (no heap); init it once, then step at the sample
 * rate. A rejected sample or a failing step returns an error status and leaves the estimator
 * (filter, input filter, counters) exactly as it was.
 *
 * Formats (fractional bits): the sample in the formats of rfe_sample_q31_t (tyre_q31.h);
 * mu Q29 (RFE_FIX_Q_MU), sd Q30 (RFE_FIX_Q_SD); the parameters those of rfe_params_q31_t.
 *
 * Saturation. Every module counts the values it clamps (rfe/fixed.h); the estimate of each
 * step carries the sum over everything that step ran (`sat`: input filter, measurement model
 * at the sample and at every cubature point, step noise S_R, the filter's predict, gate and
 * update, the sd bounds), and the state keeps the running total since init. A saturation is
 * never silent, and on the bundled logs there is none (test/estimators/friction/test_friction_q31.c).
 */
#ifndef RFE_FRICTION_Q31_H
#define RFE_FRICTION_Q31_H

#include <stdint.h>

#include "rfe/component/ckf_q31.h"
#include "rfe/component/conditioner_q31.h"
#include "rfe/config.h"
#include "rfe/fixed.h"
#include "rfe/component/meas_q31.h"
#include "rfe/component/monitor_q31.h"
#include "rfe/params_q31.h"
#include "rfe/component/sckf_q31.h"
#include "rfe/component/tyre_q31.h"

/* Input limits of rfe_friction_step_q31: the limits of rfe/config.h (RFE_LIMIT_*) in the
 * sample's Q formats. Each is an exact multiple of its format's LSB (the integer below is
 * the config.h value times 2^Q); test/estimators/friction/test_friction_q31.c checks that they equal the
 * conversions of config.h's values, so an override of one (-D) needs the other too. */
#ifndef RFE_FIX_LIMIT_DELTA
#define RFE_FIX_LIMIT_DELTA ((rfe_fix_t)536870912) /**< |delta| <= 1 rad, Q29 */
#endif
#ifndef RFE_FIX_LIMIT_VX
#define RFE_FIX_LIMIT_VX ((rfe_fix_t)838860800) /**< |vx| <= 100 m/s, Q23 */
#endif
#ifndef RFE_FIX_LIMIT_VY
#define RFE_FIX_LIMIT_VY ((rfe_fix_t)419430400) /**< |vy| <= 50 m/s, Q23 */
#endif
#ifndef RFE_FIX_LIMIT_YAW_RATE
#define RFE_FIX_LIMIT_YAW_RATE ((rfe_fix_t)1342177280) /**< |r| <= 10 rad/s, Q27 */
#endif
#ifndef RFE_FIX_LIMIT_YAW_ACC
#define RFE_FIX_LIMIT_YAW_ACC ((rfe_fix_t)1677721600) /**< |r-dot| <= 100 rad/s^2, Q24 */
#endif
#ifndef RFE_FIX_LIMIT_ACC
#define RFE_FIX_LIMIT_ACC ((rfe_fix_t)838860800) /**< |ax|, |ay| <= 50 m/s^2, Q24 */
#endif
#ifndef RFE_FIX_LIMIT_OMEGA
#define RFE_FIX_LIMIT_OMEGA ((rfe_fix_t)2097152000) /**< |omega| <= 500 rad/s, Q22 */
#endif

/** Output of one step (one row of the DATA.md estimate log, in Q formats). */
typedef struct {
    rfe_fix_t mu[RFE_WHEELS];  /**< estimated friction per wheel (T x), Q29 */
    rfe_fix_t sd[RFE_WHEELS];  /**< its standard deviation (T times the state sds), Q30 */
    uint8_t valid[RFE_WHEELS]; /**< sd_valid > 0: sd <= sd_valid; sd_valid = 0 (paper rule):
                                    1 when this step updated (status 0 or 1) */
    rfe_status_t status;       /**< status of the step (same as the return value) */
    uint32_t sat;              /**< saturation events of this step, summed over every module
                                    it ran (0 on an error and from rfe_friction_get_q31) */
} rfe_estimate_q31_t;

/** The holds, per side (structure sides; docs/ESTIMATOR.md step 9): the rear wheels' hold
 *  and the jump hold. */
typedef struct {
    rfe_fix_t mbar[2]; /**< the side's estimate smoothed over one wheelbase of travel, Q29 */
    rfe_fix_t dist[2]; /**< distance its rear wheels still hold [m], Q27 (<= 8 m), 0 = not held */
    rfe_fix_t prev[2]; /**< the side's estimate after the last step, Q29 (the jump's reference) */
    rfe_fix_t jdist[2]; /**< distance both its wheels still hold after a jump [m], Q27, 0 = not held */
    uint8_t held[2];   /**< bit 0 while dist > 0 (its rear wheels are not valid), bit 1 while
                            jdist > 0 (both its wheels are not valid) */
    uint8_t stale;     /**< 1 while a wheel speed is stale (stale_omega > 0): no flag is valid */
    uint8_t yaw_on;    /**< 1 when yaw_rate, yaw_acc hold a sample accepted as it was (0 at
                            init and after a replaced sample: the yaw-rate check restarts; a
                            gap restarts it too) */
    uint32_t pending;  /**< periods rfe_friction_skip_q31 made since the last step: their
                            distance enters the next step's hold (saturating) */
    rfe_fix_t omega[RFE_WHEELS]; /**< the wheel speeds of the last step [rad/s], Q22 */
    rfe_fix_t omega_ref[RFE_WHEELS]; /**< per wheel, the median of the other three when its
                                          speed last changed [rad/s], Q22 */
    rfe_fix_t yaw_rate; /**< the last accepted yaw rate [rad/s], Q27 (the yaw-rate check's) */
    rfe_fix_t yaw_acc;  /**< the yaw acceleration of that sample [rad/s^2], Q24 */
} rfe_friction_hold_q31_t;

/** Estimator state (caller-owned; fields are read-only for the caller). */
typedef struct {
    uint32_t magic;
    rfe_params_q31_t params;
    size_t n;                               /**< state dimension: 4 (wheels) or 2 (sides) */
    rfe_meas_q31_t meas;                    /**< measurement model of the sample being processed */
    rfe_conditioner_q31_t cond;             /**< input filter (docs/ESTIMATOR.md step 1) */
    rfe_conditioner_q31_t backup_cond;      /**< its state before the step (restored on error) */
    rfe_monitor_q31_t mon;                  /**< model-validity monitor (docs/MONITOR.md), SCKF;
                                                 stepped last, after everything that can fail,
                                                 so it needs no backup */
    rfe_sckf_innov_q31_t innov;             /**< scratch: the step's innovation for the monitor
                                                 (in the state, not on the stack: the step's
                                                 deepest call path must fit 2 KiB on a
                                                 Cortex-M0+; meaningless between steps) */
    uint64_t pers[RFE_MEAS];                /**< scratch: the persistent diagonal (Q48,
                                                 RFE_MON_Q31_QP) */
    rfe_friction_hold_q31_t hold;           /**< the holds (docs/ESTIMATOR.md step 9):
                                                 updated last in a step, after everything that
                                                 can fail, so it needs no backup */
    rfe_fix_t backup_x[RFE_N_MAX];          /**< filter mean before the step (Q29) */
    rfe_fix_t backup_S[RFE_N_MAX * RFE_N_MAX]; /**< its S (SCKF, Q30) or P (CKF, Q31) */
    uint32_t step_sat;                      /**< saturations of the step in progress (the
                                                 measurement callback adds to it) */
    uint32_t sat;                           /**< saturation events since init (saturating) */
    /* cppcheck-suppress misra-c2012-19.2 ; MISRA-DEV-03: one live filter, selected by kind */
    union {
        rfe_sckf_q31_t sckf;
        rfe_ckf_q31_t ckf;
        /* cppcheck-suppress misra-c2012-19.2 ; MISRA-DEV-03: (the closing line of the union) */
    } filter;                               /**< params.filter.kind says which is live; its
                                                 own counter `sat` is 0 between steps */
} rfe_friction_q31_t;

/**
 * Validates @p params (rfe_params_validate_q31) and initialises: x0 = mu0 on every state,
 * S0 = sqrt_prior(sd0, sd0_common), S_Q = sqrt_prior(q_mu, q_common) (Q30),
 * S_R = diag(r_ax, r_ay, r_yaw_acc) (Q24), the input filter reset, the counters at 0.
 * sqrt_prior(d, c) is the lower Cholesky factor of c^2 11^T + d^2 I, exactly d I when c = 0
 * (else computed on the matrix scaled by a power of two, so small sds keep their precision).
 * The CKF gets P0 = sd0^2 I, Q = q_mu^2 I (Q31) and R = diag(r^2) (Q24).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; RFE_ERR_RANGE when a prior or process noise
 *         does not fit its format (sd0^2 + sd0_common^2 or q_mu^2 + q_common^2 >= 4, i.e. a
 *         factor entry >= 2; CKF: sd0 or q_mu >= 1, a variance >= 1 outside Q31; r >= 11.3
 *         m/s^2, r^2 outside Q24). The estimator is untouched on every error.
 * @param[out] est     the caller's estimator state; written only on RFE_OK.
 * @param[in]  params  parameters in Q formats (rfe_params_default_q31, or a table made on the
 *                     host from a real calibration); copied.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_friction_init_q31(rfe_friction_q31_t *est,
                                                 const rfe_params_q31_t *params,
                                                 size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_FRICTION_Q31_IMPL), where the name is the function's own. */
#if !defined(RFE_FRICTION_Q31_IMPL)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_friction_init_q31(est, params) \
    rfe_friction_init_q31((est), (params), sizeof(rfe_friction_q31_t), RFE_CONFIG_Q31)
#endif

/**
 * One step (docs/ESTIMATOR.md): input check; input conditioning (tau_v > 0); time update;
 * if vx >= v_est_min the measurement update with y = [ax, ay, yaw_acc], this step's S_R and
 * the information gate; the sd bounds; projection onto [mu_min, mu_max] after an update.
 * @p out receives the posterior and the step's saturation count (or, on a rejected sample
 * or a numerical error, the unchanged previous estimate with valid = 0, sat = 0 and the error
 * status; on RFE_ERR_NULL or RFE_ERR_NOT_INITIALISED nothing is written).
 * @return RFE_OK, RFE_PROJECTED, RFE_NO_UPDATE_LOW_SPEED, RFE_HELD_NOT_OBSERVABLE,
 *         RFE_MODEL_MISMATCH (the monitor is on and fired: every flag 0, the sd inflated;
 *         docs/MONITOR.md §2); errors:
 *         RFE_ERR_NULL, RFE_ERR_NOT_INITIALISED, RFE_ERR_RANGE (a sample outside the limits
 *         RFE_FIX_LIMIT_* above, i.e. config.h's), RFE_ERR_NOT_POSITIVE_DEFINITE (the CKF's
 *         covariance or a factor that is not positive definite).
 * @param[in,out] est     an estimator set up by rfe_friction_init_q31.
 * @param[in]     sample  one sensor sample in the Q formats of rfe/fixed.h.
 * @param[out]    out     this step's estimate per wheel, sd, valid flag, status, saturations.
 */
RFE_NODISCARD rfe_status_t rfe_friction_step_q31(rfe_friction_q31_t *est,
                                                 const rfe_sample_q31_t *sample,
                                                 rfe_estimate_q31_t *out);

/**
 * Current estimate without stepping (status RFE_OK, sat 0). valid: with sd_valid > 0 the sd
 * rule; under the paper rule 0 (no step made it); while the model-validity monitor is fired,
 * 0 and the sd inflated, as the last step reported them (docs/MONITOR.md §2 item 7).
 * @param[in]  est  an estimator set up by rfe_friction_init_q31.
 * @param[out] out  the estimate of its last step.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_friction_get_q31(const rfe_friction_q31_t *est,
                                                rfe_estimate_q31_t *out);

/**
 * A gap in the data: @p missed sample periods without a sample (the twin of
 * rfe_friction_skip: the random walk's time updates of @p missed steps at once, no further
 * than the prior's variance, the sd bounds once, the input filter restarted at the next
 * sample). Saturations join the running total.
 * @param[in,out] est     an estimator set up by rfe_friction_init_q31.
 * @param[in]     missed  the number of sample periods without a sample.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; a numeric error of the filter
 *         (the estimator is then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_friction_skip_q31(rfe_friction_q31_t *est, uint32_t missed);

/**
 * The sample periods missed before a sample that comes @p period after the previous one
 * (the twin of rfe_friction_missed; rfe/common.h): 0 up to RFE_GAP_PERIODS periods dt,
 * widened by 2^-RFE_GAP_STAMP_SHIFT; beyond, round(period / dt) - 1. Q30 holds periods below
 * 2 s: a longer gap is given as the format's largest (2 s saturated), and counts as that.
 * @param[in]  est     an estimator set up by rfe_friction_init_q31.
 * @param[in]  period  the time since the previous sample [s], Q30, >= 0.
 * @param[out] missed  the missed periods.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE (a period < 0;
 *         @p missed untouched).
 */
RFE_NODISCARD rfe_status_t rfe_friction_missed_q31(const rfe_friction_q31_t *est,
                                                   rfe_fix_t period, uint32_t *missed);

/**
 * One step after a gap (the twin of rfe_friction_step_after): rfe_friction_skip_q31(@p
 * missed) and rfe_friction_step_q31 as one call; on any error neither happened. out->sat
 * counts the gap's saturations too. missed = 0: exactly rfe_friction_step_q31.
 * @param[in,out] est     an estimator set up by rfe_friction_init_q31.
 * @param[in]     missed  the sample periods without a sample before this one.
 * @param[in]     sample  one sensor sample in Q formats, as rfe_friction_step_q31.
 * @param[out]    out     this step's estimate, as rfe_friction_step_q31.
 * @return as rfe_friction_step_q31; a numeric error of the gap's time updates.
 */
RFE_NODISCARD rfe_status_t rfe_friction_step_after_q31(rfe_friction_q31_t *est,
                                                       uint32_t missed,
                                                       const rfe_sample_q31_t *sample,
                                                       rfe_estimate_q31_t *out);

/**
 * Sets the per-step input uncertainties of the errors-in-variables terms (the twin of
 * rfe_friction_set_input_noise), for inputs that are estimates themselves (the velocity
 * observer's sd each step, docs/OBSERVER.md §6).
 * @param[in,out] est        an estimator set up by rfe_friction_init_q31.
 * @param[in]     sd_in_vx   input noise sd of vx [m/s], Q23, >= 0.
 * @param[in]     sd_in_vy   input noise sd of vy [m/s], Q23, >= 0.
 * @param[in]     r_yaw_acc  yaw-acceleration noise sd [rad/s^2], Q24, > 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE (the estimator is
 *         then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_friction_set_input_noise_q31(rfe_friction_q31_t *est,
                                                            rfe_fix_t sd_in_vx,
                                                            rfe_fix_t sd_in_vy,
                                                            rfe_fix_t r_yaw_acc);

/**
 * Sets the vehicle mass of the next steps (the twin of rfe_friction_set_mass) through
 * rfe_params_set_mass_q31, which recomputes the constants that depend on it in integer
 * arithmetic. The estimate and its covariance stay as they are.
 * @param[in,out] est  an estimator set up by rfe_friction_init_q31.
 * @param[in]     m    the vehicle mass [kg], Q16 (RFE_FIX_Q_MASS), > 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE (m <= 0, or a mass
 *         whose constants leave their Q formats: rfe_params_set_mass_q31). The estimator is
 *         untouched on every error.
 */
RFE_NODISCARD rfe_status_t rfe_friction_set_mass_q31(rfe_friction_q31_t *est, rfe_fix_t m);

/**
 * Sets the lateral tyre curve of the next steps (the twin of rfe_friction_set_lateral_tyre)
 * through rfe_params_set_lateral_tyre_q31.
 * @param[in,out] est          an estimator set up by rfe_friction_init_q31.
 * @param[in]     cy           cornering stiffness per unit load [1/rad], Q24, > 0.
 * @param[in]     shape_Cy     the lateral shape C, Q24, 1 < C < 2.
 * @param[in]     shape_Ey     the lateral curvature E, Q24, -4 <= E < 1.
 * @param[in]     r_model_rel  the tyre-model error relative to each acceleration, Q30, >= 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE (values
 *         rfe_params_set_lateral_tyre_q31 refuses). The estimator is untouched on every error.
 */
RFE_NODISCARD rfe_status_t rfe_friction_set_lateral_tyre_q31(rfe_friction_q31_t *est, rfe_fix_t cy,
                                                             rfe_fix_t shape_Cy, rfe_fix_t shape_Ey,
                                                             rfe_fix_t r_model_rel);

#endif /* RFE_FRICTION_Q31_H */
