/**
 * @file pipeline_q31.h
 * @brief Fixed-point twin of rfe/pipeline.h: one ESC sample in Q formats in; the friction
 *        per wheel and vx, vy, beta, yaw acceleration out, each with its sd
 *        (docs/OBSERVER.md §6). Integer operations only.
 *
 * Each step runs the velocity observer (rfe/velocity_q31.h) with the friction estimator's
 * previous estimate, hands the friction estimator (rfe/friction_q31.h) the observer's vx,
 * vy and yaw acceleration as its inputs, and their sd as its per-step input noise
 * (rfe_friction_set_input_noise_q31: sd_in_vx, sd_in_vy, and sqrt(r_yaw_acc^2 +
 * sd(r-dot)^2), Q24). The parameters' filter.dt must be the nominal sample period; each
 * sample's own period is its dt. Gaps as rfe/pipeline.h: beyond two periods the friction
 * estimator's time updates of the missed ones first (out.missed), beyond obs_dt_max the
 * observer afresh (out.restarted); shorter than half of filter.dt refused (RFE_ERR_RANGE). Q30 holds a dt below 2 s: give a longer gap as the
 * format's largest value (it then counts as 2 s for the friction estimator).
 */
#ifndef RFE_PIPELINE_Q31_H
#define RFE_PIPELINE_Q31_H

#include <stdint.h>

#include "rfe/friction_q31.h"
#include "rfe/velocity_q31.h"

/** Output of one step. */
typedef struct {
    rfe_estimate_q31_t friction;          /**< mu, sd, valid per wheel, status, sat */
    rfe_velocity_estimate_q31_t velocity; /**< vx, vy, beta, r-dot, their sd, flags, status,
                                               sat */
    uint32_t missed;    /**< the sample periods before this sample that the friction estimator
                             time-updated at once (rfe_friction_missed_q31), else 0 */
    uint32_t restarted; /**< 1 when the observer started afresh at this sample (a period
                             beyond obs_dt_max), else 0 */
} rfe_pipeline_out_q31_t;

/** Pipeline state (caller-owned; fields read-only for the caller). */
typedef struct {
    uint32_t started;             /**< 0 until the first accepted sample */
    rfe_fix_t r_yaw_acc;          /**< the friction estimator's own r-dot noise, Q24 */
    rfe_velocity_q31_t velocity;  /**< the observer */
    rfe_friction_q31_t friction;  /**< the friction estimator */
    rfe_estimate_q31_t last;      /**< its last estimate (the observer's friction input) */
} rfe_pipeline_q31_t;

/**
 * Initialises both estimators.
 * @param[out] pl  the pipeline state.
 * @param[in]  p   vehicle, tyre and friction-filter parameters in Q formats; the observer
 *                 uses the same vehicle and tyre.
 * @param[in]  vp  the observer's parameters in Q formats.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; rfe_friction_init_q31's errors.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_pipeline_init_q31(rfe_pipeline_q31_t *pl,
                                                 const rfe_params_q31_t *p,
                                                 const rfe_velocity_params_q31_t *vp,
                                                 size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_PIPELINE_Q31_IMPL), where the name is the function's own. */
#if !defined(RFE_PIPELINE_Q31_IMPL)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_pipeline_init_q31(pl, p, vp) \
    rfe_pipeline_init_q31((pl), (p), (vp), sizeof(rfe_pipeline_q31_t), RFE_CONFIG_Q31)
#endif

/**
 * One step: the observer, then the friction estimator on its outputs.
 * @param[in,out] pl   a pipeline set up by rfe_pipeline_init_q31.
 * @param[in]     in   one ESC sample (rfe_velocity_input_q31_t).
 * @param[out]    out  both estimates.
 * @return the observer's error (then nothing changed), else the friction estimator's status
 *         (on its error the observer's step, its restart and the gap's time updates are
 *         undone too, so the pipeline is untouched).
 */
RFE_NODISCARD rfe_status_t rfe_pipeline_step_q31(rfe_pipeline_q31_t *pl,
                                                 const rfe_velocity_input_q31_t *in,
                                                 rfe_pipeline_out_q31_t *out);

/**
 * Sets the vehicle mass of both estimators between steps (the twin of rfe_pipeline_set_mass:
 * rfe_friction_set_mass_q31, then the observer's copy of the same vehicle, its constants
 * that depend on the mass included).
 * @param[in,out] pl  a pipeline set up by rfe_pipeline_init_q31.
 * @param[in]     m   the vehicle mass [kg], Q16 (RFE_FIX_Q_MASS), > 0.
 * @return rfe_friction_set_mass_q31's status; on an error the pipeline is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_pipeline_set_mass_q31(rfe_pipeline_q31_t *pl, rfe_fix_t m);

#endif /* RFE_PIPELINE_Q31_H */
