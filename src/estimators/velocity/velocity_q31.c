/**
 * @file velocity_q31.c
 * @brief The velocity and sideslip observer in fixed point (docs/OBSERVER.md; twin of
 *        velocity_flt.c): input checks, the first sample, the step order (velocity_logic.h)
 *        and the outputs (§5). Integer operations only.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_VELOCITY_Q31_IMPL
#include "rfe/velocity_q31.h"

#include "rfe/component/fxmath.h"

#include "estimators/velocity/velocity_internal_q31.h"
#include "estimators/velocity/velocity_logic.h"
#include "numerics/fxmath_internal_q31.h"
#include "numerics/internal_q31.h"

rfe_status_t rfe_velocity_init_q31(rfe_velocity_q31_t *obs, const rfe_velocity_params_q31_t *vp,
                                   const rfe_params_q31_t *veh,
                                   size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*obs)) || (config != RFE_CONFIG_Q31)) {
        return RFE_ERR_ABI;
    }
    if ((obs == NULL) || (vp == NULL) || (veh == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((rfe_velocity_params_validate_q31(vp) != RFE_OK) ||
        (rfe_params_validate_q31(veh) != RFE_OK)) {
        return RFE_ERR_PARAM;
    }
    obs->p = *vp;
    obs->veh = veh->vehicle;
    obs->tyre = veh->tyre;
    obs->started = 0u;
    obs->r_on_ref = 0;
    obs->sd_vy_filter = 0;
    {
        /* the filters' formats, their states at 0 until the first sample (constant formats
         * and sds: these cannot fail); member writes keep the caller's padding bytes */
        const rfe_status_t s1 = rfe_kf2_init_q31(&obs->yaw, RFE_VEL_Q31_QR, RFE_VEL_Q31_QRDOT,
                                                 RFE_VEL_Q31_QDT, 0, 0, 0, 0);
        const rfe_status_t s2 = rfe_kf2_init_q31(&obs->lon, RFE_VEL_Q31_QV, RFE_VEL_Q31_QB,
                                                 RFE_VEL_Q31_QDT, 0, 0, 0, 0);
        const rfe_status_t s3 = rfe_kf2_init_q31(&obs->lat, RFE_VEL_Q31_QV, RFE_VEL_Q31_QB,
                                                 RFE_VEL_Q31_QDT, 0, 0, 0, 0);
        (void)s1;
        (void)s2;
        (void)s3;
    }
    obs->last = (rfe_velocity_estimate_q31_t){0};
    obs->sat = 0u;
    obs->magic = RFE_MAGIC_VEL_Q31;
    return RFE_OK;
}


/* §1 the per-wheel inputs inside their limits: |omega|, |p|, |torque|, 0 <= mu <= 2,
 * sd >= 0. */
static int wheels_in_range_q31(const rfe_velocity_input_q31_t *in, const rfe_velocity_mu_q31_t *mu)
{
    size_t i;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        if ((rfe_q31_within(in->omega[i], RFE_FIX_LIMIT_OMEGA) == 0) ||
            (rfe_q31_within(in->p_brake[i], RFE_FIX_LIMIT_PRESSURE) == 0) ||
            (rfe_q31_within(in->torque[i], RFE_FIX_LIMIT_TORQUE) == 0)) {
            return 0;
        }
        if ((mu != NULL) &&
            ((mu->mu[i] < 0) || (mu->mu[i] > RFE_FIX_LIMIT_MU_IN) || (mu->sd[i] < 0))) {
            return 0;
        }
    }
    return 1;
}

/* §1 the inputs inside the limits; on a later sample dt in range. @p in already carries
 * the road-wheel angle (road_wheel_input_q31). */
static rfe_status_t check_input_q31(const rfe_velocity_q31_t *obs,
                                    const rfe_velocity_input_q31_t *in,
                                    const rfe_velocity_mu_q31_t *mu)
{
    if ((rfe_q31_within(in->delta, RFE_FIX_LIMIT_DELTA) == 0) ||
        (rfe_q31_within(in->yaw_rate, RFE_FIX_LIMIT_YAW_RATE) == 0) ||
        (rfe_q31_within(in->ax, RFE_FIX_LIMIT_ACC) == 0) ||
        (rfe_q31_within(in->ay, RFE_FIX_LIMIT_ACC) == 0) ||
        (rfe_q31_within(in->grade, RFE_FIX_LIMIT_GRADE) == 0) || (wheels_in_range_q31(in, mu) == 0)) {
        return RFE_ERR_RANGE;
    }
    if ((obs->started != 0u) && ((in->dt < obs->p.dt_min) || (in->dt > obs->p.dt_max))) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* §1 the sample with its road-wheel angle: delta, or steer_wheel / steer_ratio (Q26 / Q24
 * into Q29) when the sample gives the steering-wheel angle. The one place the ratio is
 * applied. */
static void road_wheel_input_q31(const rfe_velocity_q31_t *obs,
                                 const rfe_velocity_input_q31_t *in, rfe_velocity_input_q31_t *u,
                                 uint32_t *sat)
{
    *u = *in;
    if ((in->has & RFE_VEL_HAS_STEER_WHEEL) != 0u) {
        /* steer_ratio > 0 after the parameter check: the division is defined */
        const rfe_status_t st = rfe_fix_div(in->steer_wheel, obs->p.steer_ratio,
                                            (int)RFE_FIX_Q_ANGLE - RFE_FIX_Q_STEER_WHEEL +
                                                RFE_FIX_Q_RATIO,
                                            &u->delta, sat);
        (void)st;
        u->has = in->has & ~RFE_VEL_HAS_STEER_WHEEL;
    }
}

/* The root of a variance in Q(2 q) (int64 >= 0, or clamped to 0) in Q(q), rounded. */
static rfe_fix_t sd_of_q31(int64_t var, uint32_t *sat)
{
    const uint64_t root = rfe_q31_sqrt_round((var > 0) ? (uint64_t)var : 0u);
    return rfe_fix_sat32((int64_t)root, sat);
}

/* v (int64, |v| < 2^63) as m 2^e with |m| < 2^30 (one rounding when it is longer). */
static rfe_fix_t narrow_q31(int64_t v, unsigned int *e)
{
    *e = rfe_q31_norm_shift(rfe_q31_mag64_any(v), 30u);
    return rfe_q31_shr_to32(v, *e);
}

/* §5 sd of beta = sqrt(vx^2 svy^2 + vy^2 svx^2) / max(vx^2 + vy^2, vmin^2), Q29: the two
 * products (Q46) and the denominator (Q46) carried as 30-bit mantissas. */
static rfe_fix_t sd_beta_q31(rfe_fix_t vx, rfe_fix_t vy, rfe_fix_t svx, rfe_fix_t svy,
                             rfe_fix_t vmin, uint32_t *sat)
{
    const int64_t a = (int64_t)vx * (int64_t)svy;
    const int64_t b = (int64_t)vy * (int64_t)svx;
    const int64_t v2 = rfe_fix_add64((int64_t)vx * (int64_t)vx, (int64_t)vy * (int64_t)vy, sat);
    const int64_t n2 = (v2 > ((int64_t)vmin * (int64_t)vmin)) ? v2 : ((int64_t)vmin * (int64_t)vmin);
    unsigned int ea;
    unsigned int en;
    rfe_fix_t ab[2];
    rfe_fix_t norm = 0;
    rfe_fix_t mn;
    rfe_fix_t q = 0;
    rfe_status_t st;
    /* one shift for both products so their norm keeps their ratio */
    ea = rfe_q31_norm_shift(((rfe_q31_mag64_any(a) > rfe_q31_mag64_any(b)) ? rfe_q31_mag64_any(a) : rfe_q31_mag64_any(b)), 30u);
    ab[0] = rfe_q31_shr_to32(a, ea);
    ab[1] = rfe_q31_shr_to32(b, ea);
    mn = narrow_q31(n2, &en);
    st = rfe_fix_norm(ab, 2u, &norm, sat);
    /* norm Q(46 - ea) / mn Q(46 - en) into Q29: shift 29 - (46 - ea) + (46 - en); mn > 0
     * (vmin > 0) */
    if (st == RFE_OK) {
        st = rfe_fix_div(norm, mn, (29 + (int)ea) - (int)en, &q, sat);
    }
    (void)st;
    return q;
}

/* §5 the outputs of the filters; the reported sd(vy) with its floor when due (@p plan, @p mu:
 * the step's friction input), the filter's own kept in obs->sd_vy_filter. */
static void outputs_q31(rfe_velocity_q31_t *obs, const rfe_velocity_input_q31_t *in,
                        rfe_vel_plan_t plan, const rfe_velocity_mu_q31_t *mu, uint32_t flags,
                        uint32_t step_sat, rfe_velocity_estimate_q31_t *e)
{
    uint32_t sat = step_sat;
    const rfe_fix_t vx = obs->lon.x[0];
    const rfe_fix_t vy = obs->lat.x[0];
    const rfe_fix_t vmin = obs->p.v_lat_min;
    const rfe_fix_t svx = sd_of_q31(obs->lon.p00, &sat);
    rfe_fix_t svy = sd_of_q31(obs->lat.p00, &sat);
    rfe_fix_t beta = 0;
    obs->sd_vy_filter = svy;
    if (rfe_vel_out_floor_due(plan, (obs->p.vy_out_floor_mu > 0) ? 1 : 0, (vx >= vmin) ? 1 : 0) !=
        0) {
        svy = rfe_fix_max(svy, rfe_vel_sd_vy_floor_q31(obs, in, vx, mu, &sat));
    }
    if (vx >= vmin) {
        beta = rfe_q31_atan2_q29(vy, vx); /* every pair */
    }
    e->vx = vx;
    e->vy = vy;
    e->beta = beta;
    e->sd_vx = svx;
    e->sd_vy = svy;
    e->sd_beta = sd_beta_q31(vx, vy, svx, svy, vmin, &sat);
    e->yaw_acc = obs->yaw.x[1];
    e->delta = in->delta;
    e->sd_yaw_acc = sd_of_q31(obs->yaw.p11, &sat);
    e->bx = obs->lon.x[1];
    e->by = obs->lat.x[1];
    e->flags = flags;
    e->status = RFE_OK;
    e->sat = sat;
}

/* §3.0 the first sample initialises every filter. */
static rfe_status_t start_q31(rfe_velocity_q31_t *o, const rfe_velocity_input_q31_t *in,
                              uint32_t *sat)
{
    rfe_fix_t refs[RFE_WHEELS];
    int64_t sum;
    rfe_fix_t mean;
    rfe_status_t st;
    rfe_vel_wheel_refs_q31(&o->veh, in, 0, refs, sat);
    sum = (((int64_t)refs[0] + (int64_t)refs[1]) + (int64_t)refs[2]) + (int64_t)refs[3];
    mean = (rfe_fix_t)rfe_fix_shr64_round(sum, 2u); /* the mean of four int32 fits */
    st = rfe_kf2_init_q31(&o->yaw, RFE_VEL_Q31_QR, RFE_VEL_Q31_QRDOT, RFE_VEL_Q31_QDT,
                          in->yaw_rate, 0, o->p.sd_r, RFE_VEL_Q31_SD_RDOT0);
    if (st == RFE_OK) {
        st = rfe_kf2_init_q31(&o->lon, RFE_VEL_Q31_QV, RFE_VEL_Q31_QB, RFE_VEL_Q31_QDT,
                              rfe_fix_max(mean, 0), 0, o->p.sd_vx0, o->p.sd_bx0);
    }
    if (st == RFE_OK) {
        st = rfe_kf2_init_q31(&o->lat, RFE_VEL_Q31_QV, RFE_VEL_Q31_QB, RFE_VEL_Q31_QDT, 0, 0,
                              o->p.sd_vy0, o->p.sd_by0);
    }
    if (st == RFE_OK) {
        o->r_on_ref = 0;
    }
    return st;
}

/* §3.1 one stage of a later sample (the order: velocity_logic.h); @p vy_prev is the
 * lateral filter's vy before this step. */
static rfe_status_t run_stage_q31(rfe_velocity_q31_t *o, rfe_vel_stage_t stage,
                                  const rfe_velocity_input_q31_t *in, rfe_fix_t vy_prev,
                                  const rfe_velocity_mu_q31_t *mu, uint32_t *flags,
                                  uint32_t *sat)
{
    rfe_status_t st;
    if (stage == RFE_VEL_STAGE_YAW) {
        st = rfe_vel_yaw_acc_step_q31(&o->yaw, &o->p, in->dt, in->yaw_rate, sat);
    } else if (stage == RFE_VEL_STAGE_LONGITUDINAL) {
        st = rfe_vel_longitudinal_step_q31(&o->lon, &o->p, &o->veh, in, vy_prev, flags, sat);
    } else {
        st = rfe_vel_lateral_step_q31(&o->lat, &o->r_on_ref, o, in, o->lon.x[0], mu, flags, sat);
    }
    return st;
}

rfe_status_t rfe_velocity_step_q31(rfe_velocity_q31_t *obs, const rfe_velocity_input_q31_t *sample,
                                   const rfe_velocity_mu_q31_t *mu,
                                   rfe_velocity_estimate_q31_t *out)
{
    rfe_kf2_q31_t keep[3]; /* the filters before the step, put back on an error */
    rfe_velocity_input_q31_t u;
    const rfe_velocity_input_q31_t *in = &u;
    rfe_vel_plan_t plan;
    uint32_t flags = 0u;
    uint32_t sat = 0u;
    rfe_status_t st;
    if ((obs == NULL) || (sample == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (obs->magic != RFE_MAGIC_VEL_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    road_wheel_input_q31(obs, sample, &u, &sat);
    st = check_input_q31(obs, in, mu);
    /* only the three filters change until the step has succeeded (velocity_flt.c) */
    plan = rfe_vel_plan(obs->started);
    keep[0] = obs->yaw;
    keep[1] = obs->lon;
    keep[2] = obs->lat;
    if ((st == RFE_OK) && (plan == RFE_VEL_PLAN_START)) {
        st = start_q31(obs, in, &sat);
    } else if (st == RFE_OK) {
        const rfe_fix_t vy_prev = obs->lat.x[0];
        size_t k;
        for (k = 0u; (k < (size_t)RFE_VEL_STAGES) && (st == RFE_OK); ++k) {
            st = run_stage_q31(obs, rfe_vel_stage(k), in, vy_prev, mu, &flags, &sat);
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
        out->sat = 0u;
        return st;
    }
    obs->started = rfe_vel_next_phase(plan, obs->started, obs->p.lat_every);
    outputs_q31(obs, in, plan, mu, flags, sat, &obs->last);
    rfe_q31_sat_add(&obs->sat, obs->last.sat);
    *out = obs->last;
    return RFE_OK;
}

/* generated by scripts/codegen/twins.py from velocity_restart: do not edit; make twins */
rfe_status_t rfe_velocity_restart_q31(rfe_velocity_q31_t *obs)
{
    if (obs == NULL) {
        return RFE_ERR_NULL;
    }
    if (obs->magic != RFE_MAGIC_VEL_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    obs->started = 0u; /* the next accepted sample is a first one (§3.0) */
    return RFE_OK;
}
/* end generated */

rfe_status_t rfe_velocity_get_q31(const rfe_velocity_q31_t *obs, rfe_velocity_estimate_q31_t *out)
{
    if ((obs == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (obs->magic != RFE_MAGIC_VEL_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    *out = obs->last;
    out->sat = 0u;
    return RFE_OK;
}
