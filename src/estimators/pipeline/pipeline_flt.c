/**
 * @file pipeline_flt.c
 * @brief The composed entry (rfe/pipeline.h): observer, then friction on its outputs.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_PIPELINE_IMPL
#include "rfe/pipeline.h"

#include "numerics/internal.h"

rfe_status_t rfe_pipeline_init(rfe_pipeline_t *pl, const rfe_params_t *p,
                               const rfe_velocity_params_t *vp,
                               size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    rfe_status_t st;
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*pl)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if ((pl == NULL) || (p == NULL) || (vp == NULL)) {
        return RFE_ERR_NULL;
    }
    /* the library's own layout: the inits called directly, not through their wrappers */
    st = (rfe_velocity_init)(&pl->velocity, vp, p, sizeof(pl->velocity), RFE_CONFIG_REAL);
    if (st == RFE_OK) {
        st = (rfe_friction_init)(&pl->friction, p, sizeof(pl->friction), RFE_CONFIG_REAL);
    }
    if (st == RFE_OK) {
        st = rfe_friction_get(&pl->friction, &pl->last);
    }
    if (st == RFE_OK) {
        pl->r_yaw_acc = p->filter.r_yaw_acc;
        pl->started = 0u;
    }
    return st;
}

/* The friction estimator's sample from the ESC sample and the observer's estimate (its
 * road-wheel angle: the observer applies the steering ratio). */
static void friction_sample(const rfe_velocity_input_t *in, const rfe_velocity_estimate_t *v,
                            rfe_sample_t *u)
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

/* The sample's period against the friction estimator's fixed one (OBSERVER.md §6 "Gaps"):
 * shorter than half of filter.dt it would count as a whole period (the caller runs faster
 * than filter.dt says): RFE_ERR_RANGE. Beyond the observer's longest (obs_dt_max) the
 * observer restarts, this sample its first (*restarted = 1). The first sample's is ignored. */
static rfe_status_t check_period(rfe_pipeline_t *pl, const rfe_velocity_input_t *in,
                                 uint32_t *restarted)
{
    rfe_status_t st = RFE_OK;
    *restarted = 0u;
    if (pl->started == 0u) {
        return RFE_OK;
    }
    if (in->dt < (RFE_R(0.5) * pl->friction.params.filter.dt)) {
        return RFE_ERR_RANGE;
    }
    if ((rfe_is_finite(in->dt) != 0) && (in->dt > pl->velocity.p.dt_max)) {
        st = rfe_velocity_restart(&pl->velocity);
        *restarted = 1u; /* the pipeline's own initialised observer: st is RFE_OK */
    }
    return st;
}

/* What a step may change in the pipeline's observer (rfe_velocity_step: the three filters,
 * the time on r_ref, the last output; check_period: started), kept to undo a
 * step: a copy of these members, not of the whole observer with its parameters, vehicle and
 * tyre, which no step writes (issue 21: the copy cost more than the members). A field a step
 * writes added to rfe_velocity_t must be added here (the pipeline tests' untouched-on-error
 * cases compare the whole pipeline). The input noise the friction step's set-up writes
 * (rfe_friction_set_input_noise: sd_in_vx, sd_in_vy, r_yaw_acc) is kept with it. */
typedef struct {
    rfe_kf2_t yaw;
    rfe_kf2_t lon;
    rfe_kf2_t lat;
    rfe_real_t r_on_ref;
    rfe_velocity_estimate_t last;
    uint32_t started;
    rfe_real_t sd_in_vx;
    rfe_real_t sd_in_vy;
    rfe_real_t r_yaw_acc;
} pl_undo_t;

static void undo_save(const rfe_pipeline_t *pl, pl_undo_t *k)
{
    k->yaw = pl->velocity.yaw;
    k->lon = pl->velocity.lon;
    k->lat = pl->velocity.lat;
    k->r_on_ref = pl->velocity.r_on_ref;
    k->last = pl->velocity.last;
    k->started = pl->velocity.started;
    k->sd_in_vx = pl->friction.params.filter.sd_in_vx;
    k->sd_in_vy = pl->friction.params.filter.sd_in_vy;
    k->r_yaw_acc = pl->friction.params.filter.r_yaw_acc;
}

/* The observer and the friction estimator's input noise as before the step. */
static void undo_restore(rfe_pipeline_t *pl, const pl_undo_t *k)
{
    pl->velocity.yaw = k->yaw;
    pl->velocity.lon = k->lon;
    pl->velocity.lat = k->lat;
    pl->velocity.r_on_ref = k->r_on_ref;
    pl->velocity.last = k->last;
    pl->velocity.started = k->started;
    pl->friction.params.filter.sd_in_vx = k->sd_in_vx;
    pl->friction.params.filter.sd_in_vy = k->sd_in_vy;
    pl->friction.params.filter.r_yaw_acc = k->r_yaw_acc;
}

rfe_status_t rfe_pipeline_step(rfe_pipeline_t *pl, const rfe_velocity_input_t *in,
                               rfe_pipeline_out_t *out)
{
    pl_undo_t before;
    rfe_velocity_mu_t mu;
    rfe_sample_t u;
    uint32_t missed = 0u;
    uint32_t restarted;
    size_t i;
    rfe_status_t st;
    if ((pl == NULL) || (in == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    for (i = 0u; i < RFE_WHEELS; ++i) {
        mu.mu[i] = rfe_max(pl->last.mu[i], RFE_R(0.0));
        mu.sd[i] = pl->last.sd[i];
    }
    out->missed = 0u;
    out->restarted = 0u;
    undo_save(pl, &before);
    st = check_period(pl, in, &restarted);
    if (st != RFE_OK) {
        out->velocity = pl->velocity.last; /* as the observer reports a refused sample */
        out->velocity.status = st;
        out->friction = pl->last;
        out->friction.status = st;
        return st;
    }
    st = rfe_velocity_step(&pl->velocity, in, (pl->started != 0u) ? &mu : NULL, &out->velocity);
    if (st != RFE_OK) {
        undo_restore(pl, &before); /* the restart undone */
        out->friction = pl->last;
        return st;
    }
    if (pl->started != 0u) {
        /* the periods the friction estimator missed: in->dt is finite and > 0 here (the
         * observer checked it), so this cannot fail */
        const rfe_status_t gst = rfe_friction_missed(&pl->friction, in->dt, &missed);
        (void)gst;
    }
    friction_sample(in, &out->velocity, &u);
    {
        const rfe_real_t s = out->velocity.sd_yaw_acc;
        st = rfe_friction_set_input_noise(&pl->friction, out->velocity.sd_vx,
                                          out->velocity.sd_vy,
                                          RFE_SQRT((pl->r_yaw_acc * pl->r_yaw_acc) + (s * s)));
    }
    if (st == RFE_OK) {
        st = rfe_friction_step_after(&pl->friction, missed, &u, &out->friction);
    }
    if (rfe_status_is_error(st) != 0) {
        undo_restore(pl, &before); /* undo the observer's step and the input noise: */
        /* the pipeline is untouched */
        out->friction = pl->last;
        out->friction.status = st;
        return st;
    }
    out->missed = missed;
    out->restarted = restarted;
    pl->last = out->friction;
    pl->started = 1u;
    return st;
}

rfe_status_t rfe_pipeline_set_mass(rfe_pipeline_t *pl, rfe_real_t m)
{
    rfe_status_t st = RFE_ERR_NULL;
    if (pl != NULL) {
        st = rfe_friction_set_mass(&pl->friction, m);
        if (st == RFE_OK) {
            /* the observer took the same vehicle at init: it keeps being the same */
            pl->velocity.veh = pl->friction.params.vehicle;
        }
    }
    return st;
}
