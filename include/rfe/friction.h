/**
 * @file friction.h
 * @brief The friction estimator: one sensor sample in, four mu estimates out.
 *
 * Composition of the modules, one hop each (docs/ESTIMATOR.md "one step"): sample ->
 * input conditioning (conditioner) -> time update (sckf/ckf) -> kinematics, loads, slips,
 * forces (meas: tyre, obsmat) -> step noise S_R (step_noise) -> cubature points, information gate,
 * measurement update (sckf) -> sd bounds, projection -> estimate per wheel (T map).
 * The caller owns the rfe_friction_t (no heap); init it once, then step at the sample
 * rate. A rejected sample or a failing step returns an error status and leaves the
 * estimator (filter, input filter) as it was.
 *
 * This is the integrator's header: it and rfe/params.h (presets, validation) are all an
 * application needs. rfe/component/ holds the parts, for those who build their own filter.
 * Write the short names; a float build links the _f32 functions, -DRFE_REAL_DOUBLE the _f64.
 *
 * @code
 * #include "rfe/friction.h"
 *
 * static rfe_friction_t est;                 // caller-owned, no heap
 *
 * rfe_status_t friction_setup(void)
 * {
 *     rfe_params_t p;
 *     rfe_status_t st = rfe_params_default(&p);
 *     if (st == RFE_OK) {
 *         p.vehicle.m = 1650.0f;             // your vehicle's calibration
 *         st = rfe_friction_init(&est, &p);   // RFE_ERR_PARAM names a bad calibration
 *     }
 *     return st;
 * }
 *
 * void friction_task_100hz(const rfe_sample_t *s)   // SI units, ISO 8855 axes
 * {
 *     rfe_estimate_t e;
 *     if (!rfe_status_is_error(rfe_friction_step(&est, s, &e))) {
 *         // e.mu[w], e.sd[w], e.valid[w] for w = RFE_FL .. RFE_RR
 *     }
 * }
 * @endcode
 */
#ifndef RFE_FRICTION_H
#define RFE_FRICTION_H

#include "rfe/component/ckf.h"
#include "rfe/config.h"
#include "rfe/component/conditioner.h"
#include "rfe/component/meas.h"
#include "rfe/component/monitor.h"
#include "rfe/params.h"
#include "rfe/component/sckf.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_friction_init rfe_friction_init_f64
#define rfe_friction_step rfe_friction_step_f64
#define rfe_friction_get  rfe_friction_get_f64
#define rfe_friction_set_input_noise rfe_friction_set_input_noise_f64
#define rfe_friction_set_mass        rfe_friction_set_mass_f64
#define rfe_friction_set_lateral_tyre rfe_friction_set_lateral_tyre_f64
#define rfe_friction_skip rfe_friction_skip_f64
#define rfe_friction_missed rfe_friction_missed_f64
#define rfe_friction_step_after rfe_friction_step_after_f64
#else
#define rfe_friction_init rfe_friction_init_f32
#define rfe_friction_step rfe_friction_step_f32
#define rfe_friction_get  rfe_friction_get_f32
#define rfe_friction_set_input_noise rfe_friction_set_input_noise_f32
#define rfe_friction_set_mass        rfe_friction_set_mass_f32
#define rfe_friction_set_lateral_tyre rfe_friction_set_lateral_tyre_f32
#define rfe_friction_skip rfe_friction_skip_f32
#define rfe_friction_missed rfe_friction_missed_f32
#define rfe_friction_step_after rfe_friction_step_after_f32
#endif

/** Output of one step (one row of the DATA.md estimate log). */
typedef struct {
    rfe_real_t mu[RFE_WHEELS];    /**< estimated friction per wheel (T x) */
    rfe_real_t sd[RFE_WHEELS];    /**< its standard deviation (T times the state sds) */
    uint8_t valid[RFE_WHEELS];    /**< sd_valid > 0: sd <= sd_valid; sd_valid = 0 (paper
                                       rule): 1 when this step updated (status 0 or 1) */
    rfe_status_t status;          /**< status of the step (same as the return value) */
} rfe_estimate_t;

/** The holds, per side (structure sides; docs/ESTIMATOR.md step 9): the rear wheels' hold
 *  and the jump hold. */
typedef struct {
    rfe_real_t mbar[2]; /**< the side's estimate smoothed over one wheelbase of travel */
    rfe_real_t dist[2]; /**< distance its rear wheels still hold [m], 0 = not held */
    rfe_real_t prev[2]; /**< the side's estimate after the last step (the jump hold's reference) */
    rfe_real_t jdist[2]; /**< distance both its wheels still hold after a jump [m], 0 = not held */
    uint8_t held[2];    /**< bit 0 while dist > 0 (its rear wheels are not valid), bit 1 while
                             jdist > 0 (both its wheels are not valid) */
    uint8_t stale;      /**< 1 while a wheel speed is stale (stale_omega > 0): no flag is valid */
    uint8_t yaw_on;     /**< 1 when yaw_rate, yaw_acc hold a sample accepted as it was (0 at
                             init and after a replaced sample: the yaw-rate check restarts; a
                             gap restarts it too) */
    uint32_t pending;   /**< periods rfe_friction_skip made since the last step: their
                             distance enters the next step's hold (saturating) */
    rfe_real_t omega[RFE_WHEELS]; /**< the wheel speeds of the last step [rad/s] */
    rfe_real_t omega_ref[RFE_WHEELS]; /**< per wheel, the median of the other three when its
                                           speed last changed [rad/s] */
    rfe_real_t yaw_rate; /**< the last accepted yaw rate [rad/s] (the yaw-rate check's) */
    rfe_real_t yaw_acc;  /**< the yaw acceleration of that sample [rad/s^2] */
} rfe_friction_hold_t;

/** Estimator state (caller-owned; fields are read-only for the caller). */
typedef struct {
    uint32_t magic;
    rfe_params_t params;
    size_t n;                         /**< state dimension: 4 (wheels) or 2 (sides) */
    rfe_meas_t meas;                  /**< measurement model of the sample being processed */
    rfe_conditioner_t cond;           /**< input filter (docs/ESTIMATOR.md step 1) */
    rfe_conditioner_t backup_cond;    /**< its state before the step (restored on error) */
    rfe_monitor_t mon;                /**< model-validity monitor (docs/MONITOR.md), SCKF */
    rfe_monitor_t backup_mon;         /**< its state before the step (restored on error) */
    rfe_friction_hold_t hold;         /**< the holds (docs/ESTIMATOR.md step 9):
                                           updated last in a step, after everything that can
                                           fail, so it needs no backup */
    rfe_real_t backup_x[RFE_N_MAX];   /**< filter mean before the step (restored on error) */
    rfe_real_t backup_S[RFE_N_MAX * RFE_N_MAX]; /**< its S (SCKF) or P (CKF) */
    /* cppcheck-suppress misra-c2012-19.2 ; MISRA-DEV-03: one live filter, selected by kind */
    union {
        rfe_sckf_t sckf;
        rfe_ckf_t ckf;
        /* cppcheck-suppress misra-c2012-19.2 ; MISRA-DEV-03: (the closing line of the union) */
    } filter;                          /**< params.filter.kind says which is live */
} rfe_friction_t;

/**
 * Validates @p params (rfe_params_validate) and initialises: x0 = mu0 on every state,
 * S0 = sqrt_prior(sd0, sd0_common), S_Q = sqrt_prior(q_mu, q_common),
 * S_R = diag(r_ax, r_ay, r_yaw_acc), the input filter reset. sqrt_prior(d, c) is the lower
 * Cholesky factor of c^2 11^T + d^2 I, exactly d I when c = 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; RFE_ERR_NONFINITE when a prior or process
 *         noise with a common-mode part is so large that its covariance overflows;
 *         RFE_ERR_NOT_POSITIVE_DEFINITE when its common-mode part so dominates that the
 *         covariance is singular in the working precision (sd0_common / sd0 beyond about
 *         1e3 in float, 1e8 in double) (the estimator is untouched on every error).
 * @param[out] est     the caller's estimator state; written only on RFE_OK.
 * @param[in]  params  vehicle, tyre and filter parameters (rfe_params_default, then your
 *                     calibration); copied, so the caller may reuse it.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_friction_init(rfe_friction_t *est,
                                             const rfe_params_t *params,
                                             size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_FRICTION_IMPL), where the name is the function's own. */
#if !defined(RFE_FRICTION_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_friction_init_f64(est, params) \
    rfe_friction_init_f64((est), (params), sizeof(rfe_friction_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_friction_init_f32(est, params) \
    rfe_friction_init_f32((est), (params), sizeof(rfe_friction_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * One step (docs/ESTIMATOR.md): input check; input conditioning (tau_v > 0); time update;
 * if vx >= v_est_min the measurement update with y = [ax, ay, yaw_acc], this step's S_R and
 * the information gate; the sd bounds; projection onto [mu_min, mu_max] after an update.
 * @p out receives the posterior (or, on a rejected sample or a numerical error, the unchanged
 * previous estimate with valid = 0 and the error status; on RFE_ERR_NULL or
 * RFE_ERR_NOT_INITIALISED nothing is written).
 * @return RFE_OK, RFE_PROJECTED, RFE_NO_UPDATE_LOW_SPEED, RFE_HELD_NOT_OBSERVABLE,
 *         RFE_MODEL_MISMATCH (the monitor is on and fired: every flag 0, the sd inflated;
 *         docs/MONITOR.md §2); errors:
 *         RFE_ERR_NULL, RFE_ERR_NOT_INITIALISED, RFE_ERR_NONFINITE, RFE_ERR_RANGE (see
 *         config.h limits), RFE_ERR_NOT_POSITIVE_DEFINITE (CKF; an overflowing prior).
 * @param[in,out] est     an estimator set up by rfe_friction_init.
 * @param[in]     sample  one sensor sample (SI units, ISO 8855 axes, wheels fl fr rl rr).
 * @param[out]    out     this step's estimate per wheel, with its sd, valid flag and status.
 */
RFE_NODISCARD rfe_status_t rfe_friction_step(rfe_friction_t *est,
                                             const rfe_sample_t *sample,
                                             rfe_estimate_t *out);

/**
 * Current estimate without stepping (status RFE_OK). valid: with sd_valid > 0 the sd rule;
 * under the paper rule 0 (no step made it); while the model-validity monitor is fired, 0 and
 * the sd inflated, as the last step reported them (docs/MONITOR.md §2 item 7).
 * @param[in]  est  an estimator set up by rfe_friction_init.
 * @param[out] out  the estimate of its last step.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_friction_get(const rfe_friction_t *est,
                                            rfe_estimate_t *out);

/**
 * A gap in the data: @p missed sample periods passed without a sample (a dropped CAN frame,
 * a logger's gap; the caller knows its period). Their time updates at once, in O(1): the
 * random walk's process noise of @p missed steps (P += missed Q; the friction is held), but
 * no further than the prior's variance (sd0^2 + sd0_common^2), then the sd bounds of step 7
 * once (SCKF); the input filter restarts at the next sample (its integrated speeds cannot
 * bridge the gap). The monitor keeps its window. docs/ESTIMATOR.md "Gaps". missed = 0
 * changes nothing.
 * @param[in,out] est     an estimator set up by rfe_friction_init.
 * @param[in]     missed  the number of sample periods without a sample.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; a numeric error of the filter
 *         (the estimator is then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_friction_skip(rfe_friction_t *est, uint32_t missed);

/**
 * The sample periods missed before a sample that comes @p period after the previous one
 * (rfe/common.h, docs/ESTIMATOR.md "Gaps"): 0 up to RFE_GAP_PERIODS periods dt (jitter; one
 * dropped sample), widened by 2^-RFE_GAP_STAMP_SHIFT for the time stamps' rounding; beyond,
 * round(period / dt) - 1, at most UINT32_MAX. dt is the parameters' filter.dt.
 * @param[in]  est     an estimator set up by rfe_friction_init.
 * @param[in]  period  the time since the previous sample [s], finite and >= 0.
 * @param[out] missed  the missed periods (what rfe_friction_skip or rfe_friction_step_after
 *                     takes).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE (a period not finite
 *         or < 0; @p missed untouched).
 */
RFE_NODISCARD rfe_status_t rfe_friction_missed(const rfe_friction_t *est, rfe_real_t period,
                                               uint32_t *missed);

/**
 * One step after a gap: rfe_friction_skip(@p missed) and rfe_friction_step as one call, so
 * that a rejected sample or a numeric error leaves the estimator as it was before the gap's
 * time updates too (the composed pipeline's step, rfe/pipeline.h). missed = 0: exactly
 * rfe_friction_step.
 * @param[in,out] est     an estimator set up by rfe_friction_init.
 * @param[in]     missed  the sample periods without a sample before this one
 *                        (rfe_friction_missed).
 * @param[in]     sample  one sensor sample, as rfe_friction_step.
 * @param[out]    out     this step's estimate, as rfe_friction_step.
 * @return as rfe_friction_step; a numeric error of the gap's time updates.
 */
RFE_NODISCARD rfe_status_t rfe_friction_step_after(rfe_friction_t *est, uint32_t missed,
                                                   const rfe_sample_t *sample,
                                                   rfe_estimate_t *out);

/**
 * Sets the input uncertainties of the next steps' errors-in-variables terms (docs/
 * ESTIMATOR.md steps 4-5): sd_in_vx, sd_in_vy and the yaw-acceleration noise r_yaw_acc,
 * for inputs that are themselves estimates (the velocity observer's sd each step,
 * docs/OBSERVER.md §6). They act where the errors-in-variables terms are on (an sd_in_* or
 * r_model_rel > 0 at init, as in the default preset); otherwise the step's noise is the
 * constant one of init.
 * @param[in,out] est        an estimator set up by rfe_friction_init.
 * @param[in]     sd_in_vx   input noise sd of vx [m/s], finite and >= 0.
 * @param[in]     sd_in_vy   input noise sd of vy [m/s], finite and >= 0.
 * @param[in]     r_yaw_acc  yaw-acceleration noise sd [rad/s^2], finite and > 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE (the estimator is
 *         then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_friction_set_input_noise(rfe_friction_t *est,
                                                        rfe_real_t sd_in_vx,
                                                        rfe_real_t sd_in_vy,
                                                        rfe_real_t r_yaw_acc);

/**
 * Sets the vehicle mass of the next steps (issue 19: the mass and grade estimator's estimate,
 * docs/MASS_GRADE.md §10) through rfe_params_set_mass. The mass is a parameter of the model
 * (the loads and h = F/m), not a state: the estimate and its covariance stay as they are, a
 * valid prior for the new model, and a large change shows in the next innovations, which the
 * monitor and the information gate already judge (docs/ESTIMATOR.md).
 * @param[in,out] est  an estimator set up by rfe_friction_init.
 * @param[in]     m    the vehicle mass [kg], finite and > 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NONFINITE (m not finite);
 *         RFE_ERR_RANGE (m <= 0). The estimator is untouched on every error.
 */
RFE_NODISCARD rfe_status_t rfe_friction_set_mass(rfe_friction_t *est, rfe_real_t m);

/**
 * Sets the lateral tyre curve of the next steps (issue 20: the tyre identifier's cornering
 * stiffness and shape, docs/TYRE_ID.md §14) through rfe_params_set_lateral_tyre, with the
 * tyre-model error r_model_rel that carries the curve's uncertainty into the step's
 * measurement noise. Parameters of the model, not states: the estimate and its covariance
 * stay as they are, as with rfe_friction_set_mass.
 * @param[in,out] est          an estimator set up by rfe_friction_init.
 * @param[in]     cy           cornering stiffness per unit load [1/rad], > 0.
 * @param[in]     shape_Cy     the lateral Magic Formula's shape C, 1 < C < 2.
 * @param[in]     shape_Ey     its curvature E, -4 <= E < 1.
 * @param[in]     r_model_rel  the tyre-model error relative to each predicted acceleration,
 *                             >= 0 (0 with the paper preset's CKF).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NONFINITE (a value not
 *         finite); RFE_ERR_RANGE (a value rfe_params_validate refuses). The estimator is
 *         untouched on every error.
 */
RFE_NODISCARD rfe_status_t rfe_friction_set_lateral_tyre(rfe_friction_t *est, rfe_real_t cy,
                                                         rfe_real_t shape_Cy, rfe_real_t shape_Ey,
                                                         rfe_real_t r_model_rel);

#endif /* RFE_FRICTION_H */
