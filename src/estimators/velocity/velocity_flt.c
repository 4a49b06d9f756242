/**
 * @file velocity_flt.c
 * @brief The velocity and sideslip observer (docs/OBSERVER.md): input checks, the first
 *        sample, the step order (yaw rate, longitudinal, lateral) and the outputs (§5).
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_VELOCITY_IMPL
#include "rfe/velocity.h"

#include "estimators/velocity/velocity_internal.h"
#include "estimators/velocity/velocity_logic.h"
#include "numerics/internal.h"

rfe_status_t rfe_velocity_init(rfe_velocity_t *obs, const rfe_velocity_params_t *vp,
                               const rfe_params_t *veh,
                               size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*obs)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if ((obs == NULL) || (vp == NULL) || (veh == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((rfe_velocity_params_validate(vp) != RFE_OK) || (rfe_params_validate(veh) != RFE_OK)) {
        return RFE_ERR_PARAM;
    }
    obs->p = *vp;
    obs->veh = veh->vehicle;
    obs->tyre = veh->tyre;
    obs->started = 0u;
    obs->yaw = (rfe_kf2_t){{RFE_R(0.0), RFE_R(0.0)}, RFE_R(0.0), RFE_R(0.0), RFE_R(0.0)};
    obs->lon = obs->yaw;
    obs->lat = obs->yaw;
    obs->r_on_ref = RFE_R(0.0);
    obs->sd_vy_filter = RFE_R(0.0);
    obs->last = (rfe_velocity_estimate_t){0};
    obs->magic = RFE_MAGIC_VEL;
    return RFE_OK;
}

/* §1 every input finite. */
static int inputs_finite(const rfe_velocity_input_t *in, const rfe_velocity_mu_t *mu)
{
    const rfe_real_t v[7] = {in->dt,  in->delta, in->steer_wheel, in->yaw_rate,
                             in->ax,  in->ay,    in->grade};
    if ((rfe_all_finite(v, 7u) == 0) || (rfe_all_finite(in->omega, RFE_WHEELS) == 0) ||
        (rfe_all_finite(in->p_brake, RFE_WHEELS) == 0) ||
        (rfe_all_finite(in->torque, RFE_WHEELS) == 0)) {
        return 0;
    }
    if ((mu != NULL) &&
        ((rfe_all_finite(mu->mu, RFE_WHEELS) == 0) || (rfe_all_finite(mu->sd, RFE_WHEELS) == 0))) {
        return 0;
    }
    return 1;
}

/* §1 the per-wheel inputs inside their limits: |omega|, |p| (a pressure sensor reads a
 * little below 0 around zero), |torque|, 0 <= mu <= 2, sd >= 0. */
static int wheels_in_range(const rfe_velocity_input_t *in, const rfe_velocity_mu_t *mu)
{
    size_t i;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        if ((RFE_FABS(in->omega[i]) > RFE_R(RFE_LIMIT_OMEGA)) ||
            (RFE_FABS(in->p_brake[i]) > RFE_R(RFE_LIMIT_PRESSURE)) ||
            (RFE_FABS(in->torque[i]) > RFE_R(RFE_LIMIT_TORQUE))) {
            return 0;
        }
        if ((mu != NULL) && ((mu->mu[i] < RFE_R(0.0)) || (mu->mu[i] > RFE_R(2.0)) ||
                             (mu->sd[i] < RFE_R(0.0)))) {
            return 0;
        }
    }
    return 1;
}

/* §1 the inputs: finite, inside config.h's limits; on a later sample dt in range. @p in
 * already carries the road-wheel angle (road_wheel_input). */
static rfe_status_t check_input(const rfe_velocity_t *obs, const rfe_velocity_input_t *in,
                                const rfe_velocity_mu_t *mu)
{
    if ((RFE_FABS(in->delta) > RFE_R(RFE_LIMIT_DELTA)) ||
        (RFE_FABS(in->yaw_rate) > RFE_R(RFE_LIMIT_YAW_RATE)) ||
        (RFE_FABS(in->ax) > RFE_R(RFE_LIMIT_ACC)) || (RFE_FABS(in->ay) > RFE_R(RFE_LIMIT_ACC)) ||
        (RFE_FABS(in->grade) > RFE_R(RFE_LIMIT_GRADE)) || (wheels_in_range(in, mu) == 0)) {
        return RFE_ERR_RANGE;
    }
    if ((obs->started != 0u) && ((in->dt < obs->p.dt_min) || (in->dt > obs->p.dt_max))) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* §1 the sample with its road-wheel angle: delta, or steer_wheel / steer_ratio when the
 * sample gives the steering-wheel angle. The one place the ratio is applied. */
static rfe_status_t road_wheel_input(const rfe_velocity_t *obs, const rfe_velocity_input_t *in,
                                     const rfe_velocity_mu_t *mu, rfe_velocity_input_t *u)
{
    if (inputs_finite(in, mu) == 0) {
        return RFE_ERR_NONFINITE;
    }
    *u = *in;
    if ((in->has & RFE_VEL_HAS_STEER_WHEEL) != 0u) {
        u->delta = in->steer_wheel / obs->p.steer_ratio;
        u->has = in->has & ~RFE_VEL_HAS_STEER_WHEEL;
    }
    return RFE_OK;
}

/* §5 the outputs of the filters; the reported sd(vy) with its floor when due (@p plan, @p mu:
 * the step's friction input), the filter's own kept in obs->sd_vy_filter. */
static void outputs(rfe_velocity_t *obs, const rfe_velocity_input_t *in, rfe_vel_plan_t plan,
                    const rfe_velocity_mu_t *mu, uint32_t flags, rfe_velocity_estimate_t *e)
{
    const rfe_real_t vx = obs->lon.x[0];
    const rfe_real_t vy = obs->lat.x[0];
    const rfe_real_t vmin = obs->p.v_lat_min;
    const rfe_real_t svx = RFE_SQRT(rfe_max(obs->lon.p00, RFE_R(0.0)));
    const rfe_real_t svy_kf = RFE_SQRT(rfe_max(obs->lat.p00, RFE_R(0.0)));
    const rfe_real_t svy =
        (rfe_vel_out_floor_due(plan, (obs->p.vy_out_floor_mu > RFE_R(0.0)) ? 1 : 0,
                               (vx >= vmin) ? 1 : 0) != 0)
            ? rfe_max(svy_kf, rfe_vel_sd_vy_floor(obs, in, vx, mu))
            : svy_kf;
    const rfe_real_t n2 = rfe_max((vx * vx) + (vy * vy), vmin * vmin);
    obs->sd_vy_filter = svy_kf;
    e->vx = vx;
    e->vy = vy;
    e->beta = (vx >= vmin) ? RFE_ATAN2(vy, vx) : RFE_R(0.0);
    e->sd_vx = svx;
    e->sd_vy = svy;
    e->sd_beta = RFE_SQRT(((vx * vx) * (svy * svy)) + ((vy * vy) * (svx * svx))) / n2;
    e->yaw_acc = obs->yaw.x[1];
    e->delta = in->delta;
    e->sd_yaw_acc = RFE_SQRT(rfe_max(obs->yaw.p11, RFE_R(0.0)));
    e->bx = obs->lon.x[1];
    e->by = obs->lat.x[1];
    e->flags = flags;
    e->status = RFE_OK;
}

/* §3.0 the first sample initialises every filter. */
static rfe_status_t start(rfe_velocity_t *o, const rfe_velocity_input_t *in)
{
    rfe_real_t refs[RFE_WHEELS];
    rfe_real_t mean;
    rfe_status_t st;
    rfe_vel_wheel_refs(&o->veh, in, RFE_R(0.0), refs);
    mean = (((refs[0] + refs[1]) + refs[2]) + refs[3]) / RFE_R(4.0);
    /* the library's own layout: the inits called directly, not through their wrappers */
    st = (rfe_kf2_init)(&o->yaw, in->yaw_rate, RFE_R(0.0), o->p.sd_r, RFE_R(1.0),
                        sizeof(o->yaw), RFE_CONFIG_REAL);
    if (st == RFE_OK) {
        st = (rfe_kf2_init)(&o->lon, rfe_max(mean, RFE_R(0.0)), RFE_R(0.0), o->p.sd_vx0,
                            o->p.sd_bx0, sizeof(o->lon), RFE_CONFIG_REAL);
    }
    if (st == RFE_OK) {
        st = (rfe_kf2_init)(&o->lat, RFE_R(0.0), RFE_R(0.0), o->p.sd_vy0, o->p.sd_by0,
                            sizeof(o->lat), RFE_CONFIG_REAL);
    }
    if (st == RFE_OK) {
        o->r_on_ref = RFE_R(0.0);
    }
    return st;
}

/* §3.1 one stage of a later sample (the order: velocity_logic.h); @p vy_prev is the
 * lateral filter's vy before this step. */
static rfe_status_t run_stage(rfe_velocity_t *o, rfe_vel_stage_t stage,
                              const rfe_velocity_input_t *in, rfe_real_t vy_prev,
                              const rfe_velocity_mu_t *mu, uint32_t *flags)
{
    rfe_status_t st;
    if (stage == RFE_VEL_STAGE_YAW) {
        st = rfe_vel_yaw_acc_step(&o->yaw, &o->p, in->dt, in->yaw_rate);
    } else if (stage == RFE_VEL_STAGE_LONGITUDINAL) {
        st = rfe_vel_longitudinal_step(&o->lon, &o->p, &o->veh, in, vy_prev, flags);
    } else {
        st = rfe_vel_lateral_step(&o->lat, &o->r_on_ref, o, in, o->lon.x[0], mu, flags);
    }
    return st;
}

rfe_status_t rfe_velocity_step(rfe_velocity_t *obs, const rfe_velocity_input_t *sample,
                               const rfe_velocity_mu_t *mu, rfe_velocity_estimate_t *out)
{
    rfe_kf2_t keep[3]; /* the filters before the step, put back on an error */
    rfe_velocity_input_t u;
    const rfe_velocity_input_t *in = &u;
    rfe_vel_plan_t plan;
    uint32_t flags = 0u;
    rfe_status_t st;
    if ((obs == NULL) || (sample == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (obs->magic != RFE_MAGIC_VEL) {
        return RFE_ERR_NOT_INITIALISED;
    }
    st = road_wheel_input(obs, sample, mu, &u);
    if (st == RFE_OK) {
        st = check_input(obs, in, mu);
    }
    /* The step changes only the three filters until it has succeeded: they are kept and put
     * back on an error, so the observer is left as it was without copying its parameters
     * twice per step (a whole-state copy was 6 % of the step on the Cortex-M4). */
    plan = rfe_vel_plan(obs->started);
    keep[0] = obs->yaw;
    keep[1] = obs->lon;
    keep[2] = obs->lat;
    if ((st == RFE_OK) && (plan == RFE_VEL_PLAN_START)) {
        st = start(obs, in);
    } else if (st == RFE_OK) {
        const rfe_real_t vy_prev = obs->lat.x[0];
        size_t k;
        for (k = 0u; (k < (size_t)RFE_VEL_STAGES) && (st == RFE_OK); ++k) {
            st = run_stage(obs, rfe_vel_stage(k), in, vy_prev, mu, &flags);
        }
    } else {
        /* the checks failed: nothing to compute */
    }
    if (st != RFE_OK) {
        obs->yaw = keep[0];
        obs->lon = keep[1];
        obs->lat = keep[2];
        *out = obs->last;
        out->status = st;
        return st;
    }
    obs->started = rfe_vel_next_phase(plan, obs->started, obs->p.lat_every);
    outputs(obs, in, plan, mu, flags, &obs->last);
    *out = obs->last;
    return RFE_OK;
}

/* generated by scripts/codegen/twins.py from velocity_restart: do not edit; make twins */
rfe_status_t rfe_velocity_restart(rfe_velocity_t *obs)
{
    if (obs == NULL) {
        return RFE_ERR_NULL;
    }
    if (obs->magic != RFE_MAGIC_VEL) {
        return RFE_ERR_NOT_INITIALISED;
    }
    obs->started = 0u; /* the next accepted sample is a first one (§3.0) */
    return RFE_OK;
}
/* end generated */

rfe_status_t rfe_velocity_get(const rfe_velocity_t *obs, rfe_velocity_estimate_t *out)
{
    if ((obs == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (obs->magic != RFE_MAGIC_VEL) {
        return RFE_ERR_NOT_INITIALISED;
    }
    *out = obs->last;
    return RFE_OK;
}
