/**
 * @file pipeline_q31.c
 * @brief The composed entry in fixed point (rfe/pipeline_q31.h; twin of pipeline_flt.c):
 *        observer, then friction on its outputs. Integer operations only.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_PIPELINE_Q31_IMPL
#include "rfe/pipeline_q31.h"

#include "rfe/component/fxmath.h"

#include "numerics/internal_q31.h"

rfe_status_t rfe_pipeline_init_q31(rfe_pipeline_q31_t *pl, const rfe_params_q31_t *p,
                                   const rfe_velocity_params_q31_t *vp,
                                   size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    rfe_status_t st;
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*pl)) || (config != RFE_CONFIG_Q31)) {
        return RFE_ERR_ABI;
    }
    if ((pl == NULL) || (p == NULL) || (vp == NULL)) {
        return RFE_ERR_NULL;
    }
    /* the library's own layout: the inits called directly, not through their wrappers */
    st = (rfe_velocity_init_q31)(&pl->velocity, vp, p, sizeof(pl->velocity), RFE_CONFIG_Q31);
    if (st == RFE_OK) {
        st = (rfe_friction_init_q31)(&pl->friction, p, sizeof(pl->friction), RFE_CONFIG_Q31);
    }
    if (st == RFE_OK) {
        st = rfe_friction_get_q31(&pl->friction, &pl->last);
    }
    if (st == RFE_OK) {
        pl->r_yaw_acc = p->filter.r_yaw_acc;
        pl->started = 0u;
    }
    return st;
}

/* The friction estimator's sample from the ESC sample and the observer's estimate (its
 * road-wheel angle: the observer applies the steering ratio). */
static void friction_sample_q31(const rfe_velocity_input_q31_t *in,
                                const rfe_velocity_estimate_q31_t *v, rfe_sample_q31_t *u)
{
    size_t i;
    u->delta = v->delta;
    u->vx = v->vx;
    u->vy = v->vy;
    u->yaw_rate = in->yaw_rate;
    u->yaw_acc = v->yaw_acc;
    u->ax = in->ax;
    u->ay = in->ay;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        u->omega[i] = in->omega[i];
    }
}

/* The sample's period against the fixed one (pipeline_flt.c check_period): shorter than
 * half of filter.dt, RFE_ERR_RANGE; beyond obs_dt_max the observer restarts, this sample its
 * first (*restarted = 1). The first sample's is ignored. */
static rfe_status_t check_period_q31(rfe_pipeline_q31_t *pl, const rfe_velocity_input_q31_t *in,
                                     uint32_t *restarted)
{
    rfe_status_t st = RFE_OK;
    *restarted = 0u;
    if (pl->started == 0u) {
        return RFE_OK;
    }
    if (in->dt < (pl->friction.params.filter.dt / 2)) {
        return RFE_ERR_RANGE;
    }
    if (in->dt > pl->velocity.p.dt_max) {
        st = rfe_velocity_restart_q31(&pl->velocity);
        *restarted = 1u; /* the pipeline's own initialised observer: st is RFE_OK */
    }
    return st;
}

/* What a step may change in the pipeline's observer (rfe_velocity_q31_step: the three filters,
 * the time on r_ref, the last output, the counts; check_period_q31: started), kept to undo a
 * step: a copy of these members, not of the whole observer with its parameters, vehicle and
 * tyre, which no step writes (issue 21: the copy cost more than the members). A field a step
 * writes added to rfe_velocity_q31_t must be added here (the pipeline tests' untouched-on-error
 * cases compare the whole pipeline). The input noise the friction step's set-up writes
 * (rfe_friction_set_input_noise_q31: sd_in_vx, sd_in_vy, r_yaw_acc) is kept with it. */
typedef struct {
    rfe_kf2_q31_t yaw;
    rfe_kf2_q31_t lon;
    rfe_kf2_q31_t lat;
    rfe_fix_t r_on_ref;
    rfe_velocity_estimate_q31_t last;
    uint32_t sat;
    uint32_t started;
    rfe_fix_t sd_in_vx;
    rfe_fix_t sd_in_vy;
    rfe_fix_t r_yaw_acc;
} pl_undo_q31_t;

static void undo_save_q31(const rfe_pipeline_q31_t *pl, pl_undo_q31_t *k)
{
    k->yaw = pl->velocity.yaw;
    k->lon = pl->velocity.lon;
    k->lat = pl->velocity.lat;
    k->r_on_ref = pl->velocity.r_on_ref;
    k->last = pl->velocity.last;
    k->sat = pl->velocity.sat;
    k->started = pl->velocity.started;
    k->sd_in_vx = pl->friction.params.filter.sd_in_vx;
    k->sd_in_vy = pl->friction.params.filter.sd_in_vy;
    k->r_yaw_acc = pl->friction.params.filter.r_yaw_acc;
}

/* The observer and the friction estimator's input noise as before the step. */
static void undo_restore_q31(rfe_pipeline_q31_t *pl, const pl_undo_q31_t *k)
{
    pl->velocity.yaw = k->yaw;
    pl->velocity.lon = k->lon;
    pl->velocity.lat = k->lat;
    pl->velocity.r_on_ref = k->r_on_ref;
    pl->velocity.last = k->last;
    pl->velocity.sat = k->sat;
    pl->velocity.started = k->started;
    pl->friction.params.filter.sd_in_vx = k->sd_in_vx;
    pl->friction.params.filter.sd_in_vy = k->sd_in_vy;
    pl->friction.params.filter.r_yaw_acc = k->r_yaw_acc;
}

rfe_status_t rfe_pipeline_step_q31(rfe_pipeline_q31_t *pl, const rfe_velocity_input_q31_t *in,
                                   rfe_pipeline_out_q31_t *out)
{
    pl_undo_q31_t before;
    rfe_velocity_mu_q31_t mu;
    rfe_sample_q31_t u;
    uint32_t sat = 0u;
    uint32_t missed = 0u;
    uint32_t restarted;
    size_t i;
    rfe_status_t st;
    if ((pl == NULL) || (in == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    for (i = 0u; i < RFE_WHEELS; ++i) {
        mu.mu[i] = rfe_fix_max(pl->last.mu[i], 0);
        mu.sd[i] = pl->last.sd[i];
    }
    out->missed = 0u;
    out->restarted = 0u;
    undo_save_q31(pl, &before);
    st = check_period_q31(pl, in, &restarted);
    if (st != RFE_OK) {
        out->velocity = pl->velocity.last; /* as the observer reports a refused sample */
        out->velocity.status = st;
        out->velocity.sat = 0u;
        out->friction = pl->last;
        out->friction.status = st;
        out->friction.sat = 0u;
        return st;
    }
    st = rfe_velocity_step_q31(&pl->velocity, in, (pl->started != 0u) ? &mu : NULL,
                               &out->velocity);
    if (st != RFE_OK) {
        undo_restore_q31(pl, &before); /* the restart undone */
        out->friction = pl->last;
        out->friction.sat = 0u;
        return st;
    }
    if (pl->started != 0u) {
        /* the periods the friction estimator missed: in->dt > 0 here (the observer checked
         * it), so this cannot fail */
        const rfe_status_t gst = rfe_friction_missed_q31(&pl->friction, in->dt, &missed);
        (void)gst;
    }
    friction_sample_q31(in, &out->velocity, &u);
    {
        /* sqrt(r_yaw_acc^2 + sd(r-dot)^2), Q24, exactly rounded */
        const rfe_fix_t v[2] = {pl->r_yaw_acc, out->velocity.sd_yaw_acc};
        rfe_fix_t r = 0;
        st = rfe_fix_norm(v, 2u, &r, &sat);
        if (st == RFE_OK) {
            st = rfe_friction_set_input_noise_q31(&pl->friction, out->velocity.sd_vx,
                                                  out->velocity.sd_vy, r);
        }
    }
    if (st == RFE_OK) {
        st = rfe_friction_step_after_q31(&pl->friction, missed, &u, &out->friction);
    }
    if (rfe_status_is_error(st) != 0) {
        undo_restore_q31(pl, &before); /* undo the observer's step and the input noise: */
        /* the pipeline is untouched */
        out->friction = pl->last;
        out->friction.status = st;
        out->friction.sat = 0u;
        return st;
    }
    rfe_q31_sat_add(&out->friction.sat, sat);
    out->missed = missed;
    out->restarted = restarted;
    pl->last = out->friction;
    pl->started = 1u;
    return st;
}

rfe_status_t rfe_pipeline_set_mass_q31(rfe_pipeline_q31_t *pl, rfe_fix_t m)
{
    rfe_status_t st = RFE_ERR_NULL;
    if (pl != NULL) {
        st = rfe_friction_set_mass_q31(&pl->friction, m);
        if (st == RFE_OK) {
            /* the observer took the same vehicle at init: it keeps being the same */
            pl->velocity.veh = pl->friction.params.vehicle;
        }
    }
    return st;
}
