/**
 * @file pipeline.h
 * @brief The composed entry for firmware: one ESC sample in; the friction per wheel and
 *        vx, vy, beta, yaw acceleration out, each with its sd (docs/OBSERVER.md §6).
 *
 * Each step runs the velocity observer (rfe/velocity.h) with the friction estimator's
 * previous estimate, hands the friction estimator (rfe/friction.h) the observer's vx, vy
 * and yaw acceleration as its inputs, and their sd as its per-step input noise
 * (rfe_friction_set_input_noise: sd_in_vx, sd_in_vy, and sqrt(r_yaw_acc^2 + sd(r-dot)^2)).
 * The parameters' filter.dt must be the nominal sample period (the friction estimator's
 * input filter uses it); each sample's own period is its dt.
 *
 * Gaps (docs/OBSERVER.md §6): a sample whose dt is longer than two periods (rfe/common.h
 * RFE_GAP_PERIODS) makes the friction estimator's time updates of the missed periods first
 * (rfe_friction_missed, rfe_friction_step_after; out.missed says how many); a dt beyond the
 * observer's obs_dt_max also starts the observer afresh at that sample (rfe_velocity_restart;
 * out.restarted). A dt shorter than half of filter.dt is refused (RFE_ERR_RANGE: the caller
 * runs faster than filter.dt says, and the friction step would take it as a whole period).
 * A rejected sample changes nothing, its gap included: give dt as the time since the last
 * accepted sample, so that the next one makes up for it.
 *
 * @code
 * #include "rfe/pipeline.h"
 *
 * static rfe_pipeline_t pl;                     // caller-owned, no heap
 *
 * rfe_status_t pipeline_setup(void)
 * {
 *     rfe_params_t p;
 *     rfe_velocity_params_t vp;
 *     rfe_status_t st = rfe_params_default(&p);
 *     if (st == RFE_OK) {
 *         st = rfe_velocity_params_default(&vp);
 *     }
 *     if (st == RFE_OK) {
 *         st = rfe_pipeline_init(&pl, &p, &vp);
 *     }
 *     return st;
 * }
 *
 * void esc_task_100hz(const rfe_velocity_input_t *in)
 * {
 *     rfe_pipeline_out_t o;
 *     if (!rfe_status_is_error(rfe_pipeline_step(&pl, in, &o))) {
 *         // o.friction.mu[w], o.friction.sd[w], o.friction.valid[w]; o.velocity.vx, ...
 *     }
 * }
 * @endcode
 */
#ifndef RFE_PIPELINE_H
#define RFE_PIPELINE_H

#include "rfe/friction.h"
#include "rfe/velocity.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_pipeline_init rfe_pipeline_init_f64
#define rfe_pipeline_step rfe_pipeline_step_f64
#define rfe_pipeline_set_mass rfe_pipeline_set_mass_f64
#else
#define rfe_pipeline_init rfe_pipeline_init_f32
#define rfe_pipeline_step rfe_pipeline_step_f32
#define rfe_pipeline_set_mass rfe_pipeline_set_mass_f32
#endif

/** Output of one step. */
typedef struct {
    rfe_estimate_t friction;          /**< mu, sd, valid per wheel and the friction status */
    rfe_velocity_estimate_t velocity; /**< vx, vy, beta, r-dot, their sd, flags, status */
    uint32_t missed;    /**< the sample periods before this sample that the friction estimator
                             time-updated at once (a gap: rfe_friction_missed), else 0 */
    uint32_t restarted; /**< 1 when the observer started afresh at this sample (a period
                             beyond obs_dt_max: rfe_velocity_restart), else 0 */
} rfe_pipeline_out_t;

/** Pipeline state (caller-owned; fields read-only for the caller). */
typedef struct {
    uint32_t started;           /**< 0 until the first accepted sample */
    rfe_real_t r_yaw_acc;       /**< the friction estimator's own r-dot noise (params) */
    rfe_velocity_t velocity;    /**< the observer */
    rfe_friction_t friction;    /**< the friction estimator */
    rfe_estimate_t last;        /**< its last estimate (the observer's friction input) */
} rfe_pipeline_t;

/**
 * Initialises both estimators.
 * @param[out] pl  the pipeline state.
 * @param[in]  p   vehicle, tyre and friction-filter parameters (rfe_params_default, then
 *                 your calibration); the observer uses the same vehicle and tyre.
 * @param[in]  vp  the observer's parameters (rfe_velocity_params_default, then tuning).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; rfe_friction_init's errors.
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_pipeline_init(rfe_pipeline_t *pl, const rfe_params_t *p,
                                             const rfe_velocity_params_t *vp,
                                             size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_PIPELINE_IMPL), where the name is the function's own. */
#if !defined(RFE_PIPELINE_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_pipeline_init_f64(pl, p, vp) \
    rfe_pipeline_init_f64((pl), (p), (vp), sizeof(rfe_pipeline_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_pipeline_init_f32(pl, p, vp) \
    rfe_pipeline_init_f32((pl), (p), (vp), sizeof(rfe_pipeline_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * One step: the observer, then the friction estimator on its outputs.
 * @param[in,out] pl   a pipeline set up by rfe_pipeline_init.
 * @param[in]     in   one ESC sample (rfe_velocity_input_t).
 * @param[out]    out  both estimates.
 * @return the observer's error (then nothing changed), else the friction estimator's status
 *         (on its error the observer's step, its restart and the gap's time updates are
 *         undone too, so the pipeline is untouched).
 */
RFE_NODISCARD rfe_status_t rfe_pipeline_step(rfe_pipeline_t *pl, const rfe_velocity_input_t *in,
                                             rfe_pipeline_out_t *out);

/**
 * Sets the vehicle mass of both estimators between steps (rfe_friction_set_mass, then the
 * observer's copy of the same vehicle), e.g. the mass and grade estimator's (docs/
 * MASS_GRADE.md §10).
 * @param[in,out] pl  a pipeline set up by rfe_pipeline_init.
 * @param[in]     m   the vehicle mass [kg], finite and > 0.
 * @return rfe_friction_set_mass's status; on an error the pipeline is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_pipeline_set_mass(rfe_pipeline_t *pl, rfe_real_t m);

#endif /* RFE_PIPELINE_H */
