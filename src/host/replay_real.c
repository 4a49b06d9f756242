/**
 * @file replay_real.c
 * @brief The precision-specific part of mu_replay: double parameter set -> rfe_params_t,
 *        sensor rows -> rfe_sample_t, estimator steps -> double estimate rows.
 *
 * Compiled twice (float by default, double with -DRFE_REAL_DOUBLE); public names carry the
 * precision suffix (replay_real.h) so both objects link into one program. Keep everything else out of this file.
 */
#include "replay_real.h"

#include <math.h>
#include <string.h>

#include "rfe/friction.h"
#include "rfe/pipeline.h"
#include "rfe/params.h"
#include "rfe/velocity_params.h"

#include "log_timing.h"

static rfe_status_t preset_params(rfe_preset_t preset, rfe_params_t *p);
static void set_key(rfe_params_t *p, const rfe_param_set_t *ps, size_t k);
static rfe_status_t to_lib_params(const rfe_param_set_t *ps, rfe_params_t *p);
static size_t diagnose_params(const rfe_param_set_t *ps);
static void step_row(rfe_friction_t *est, const rfe_sensor_row_t *row, rfe_est_row_t *out);

/* Where each numeric key lives in rfe_params_t of this precision (the RFE_PARAM_KEYS
 * table): one table instead of a switch, so a new key needs no code here. */
static const size_t k_member_offset[RFE_PK_NUMERIC] = {
#define RFE_OFFSET_(key, member, unit, doc) offsetof(rfe_params_t, member),
    RFE_PARAM_KEYS(RFE_OFFSET_)
#undef RFE_OFFSET_
};

/* Compile-time check (C99 has no static_assert): every keyed member is an rfe_real_t, as
 * set_key's memcpy assumes. A non-real key would make this array size negative. */
#define RFE_IS_REAL_(key, member, unit, doc)                                               \
    typedef char rfe_key_is_real_##key[(sizeof(((rfe_params_t *)0)->member) == sizeof(rfe_real_t)) ? 1 : -1];
RFE_PARAM_KEYS(RFE_IS_REAL_)
#undef RFE_IS_REAL_

/* Where each observer key after obs_driven lives in rfe_velocity_params_t (RFE_OBS_KEYS). */
static const size_t k_obs_offset[RFE_PK_OBS_COUNT - 1u] = {
#define RFE_OFFSET_(key, member, unit, doc) offsetof(rfe_velocity_params_t, member),
    RFE_OBS_KEYS(RFE_OFFSET_)
#undef RFE_OFFSET_
};

/* As above: every observer key after obs_driven is an rfe_real_t. */
#define RFE_IS_REAL_(key, member, unit, doc)                                               \
    typedef char rfe_key_is_real_##key[(sizeof(((rfe_velocity_params_t *)0)->member) == sizeof(rfe_real_t)) ? 1 : -1];
RFE_OBS_KEYS(RFE_IS_REAL_)
#undef RFE_IS_REAL_

rfe_replay_preset_fn_t rfe_replay_preset_fn(rfe_preset_t preset)
{
    switch (preset) {
    case RFE_PRESET_DEFAULT:
        return rfe_params_default;
    case RFE_PRESET_PAPER:
        return rfe_params_paper;
    default:
        return NULL;
    }
}

/* The library's parameters of @p preset; RFE_ERR_PARAM for an unknown preset. */
static rfe_status_t preset_params(rfe_preset_t preset, rfe_params_t *p)
{
    const rfe_replay_preset_fn_t fill = rfe_replay_preset_fn(preset);
    return (fill != NULL) ? fill(p) : RFE_ERR_PARAM;
}

int rfe_param_set_preset(rfe_param_set_t *ps, rfe_preset_t preset)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    size_t k;
    if ((ps == NULL) || (preset_params(preset, &p) != RFE_OK) ||
        (rfe_velocity_params_default(&vp) != RFE_OK)) {
        return -1;
    }
    memset(ps, 0, sizeof *ps);
    ps->preset = preset;
    for (k = 0u; k < RFE_PK_NUMERIC; ++k) {
        rfe_real_t v;
        memcpy(&v, (const char *)&p + k_member_offset[k], sizeof v);
        ps->value[k] = (double)v;
    }
    ps->tyre = p.tyre.mode;
    ps->filter = p.filter.kind;
    ps->structure = p.filter.structure;
    ps->obs[0] = (double)vp.driven;
    for (k = 1u; k < RFE_PK_OBS_COUNT; ++k) {
        rfe_real_t v;
        memcpy(&v, (const char *)&vp + k_obs_offset[k - 1u], sizeof v);
        ps->obs[k] = (double)v;
    }
    return 0;
}

/* Key k of the set into rfe_params_t, rounded to the build's real type. */
static void set_key(rfe_params_t *p, const rfe_param_set_t *ps, size_t k)
{
    if (k < RFE_PK_NUMERIC) {
        const rfe_real_t v = (rfe_real_t)ps->value[k];
        memcpy((char *)p + k_member_offset[k], &v, sizeof v);
    } else if (k == (size_t)RFE_PK_TYRE) {
        p->tyre.mode = ps->tyre;
    } else if (k == (size_t)RFE_PK_FILTER) {
        p->filter.kind = ps->filter;
    } else if (k == (size_t)RFE_PK_STRUCTURE) {
        p->filter.structure = ps->structure;
    } else {
        /* an observer key: rfe_replay_velocity_params */
    }
}

/* Observer key @p k of the set into @p vp; 0, or -1 when obs_driven is not an integer
 * bit mask 0..15 (a double would otherwise be truncated without a word). */
static int set_obs_key(rfe_velocity_params_t *vp, const rfe_param_set_t *ps, size_t k)
{
    const double v = ps->obs[k - RFE_PK_OBS_FIRST];
    if (k == RFE_PK_OBS_FIRST) {
        if (!((v >= 0.0) && (v <= 15.0) && (v == floor(v)))) {
            return -1;
        }
        vp->driven = (uint32_t)v;
    } else {
        const rfe_real_t r = (rfe_real_t)v;
        memcpy((char *)vp + k_obs_offset[k - RFE_PK_OBS_FIRST - 1u], &r, sizeof r);
    }
    return 0;
}

/* The preset first, so a library field without a key keeps the preset's value. */
static rfe_status_t to_lib_params(const rfe_param_set_t *ps, rfe_params_t *p)
{
    size_t k;
    const rfe_status_t st = preset_params(ps->preset, p); /* fails only for a bad preset */
    for (k = 0u; (st == RFE_OK) && (k < (size_t)RFE_PK_COUNT); ++k) {
        set_key(p, ps, k);
    }
    return st;
}

/* Which key alone makes validation fail, starting from the (valid) library preset. The
 * filter key is also blamed when the set is valid except for filter = ckf (the CKF baseline
 * runs only the paper subset, rfe_params_validate). */
static size_t diagnose_params(const rfe_param_set_t *ps)
{
    size_t k;
    rfe_params_t all;
    if ((ps->filter == RFE_FILTER_CKF) && (to_lib_params(ps, &all) == RFE_OK)) {
        all.filter.kind = RFE_FILTER_SCKF;
        if (rfe_params_validate(&all) == RFE_OK) {
            return (size_t)RFE_PK_FILTER;
        }
    }
    for (k = 0u; k < (size_t)RFE_PK_COUNT; ++k) {
        rfe_params_t p;
        if (preset_params(ps->preset, &p) != RFE_OK) {
            return RFE_PK_NONE; /* the preset itself is unknown: no key to blame */
        }
        set_key(&p, ps, k);
        if (rfe_params_validate(&p) != RFE_OK) {
            return k;
        }
    }
    return RFE_PK_NONE;
}

rfe_status_t rfe_replay_velocity_params(const rfe_param_set_t *ps, rfe_velocity_params_t *vp,
                                        size_t *bad_key)
{
    size_t k;
    int bad;
    if ((ps == NULL) || (vp == NULL)) {
        return RFE_ERR_NULL;
    }
    if (bad_key != NULL) {
        *bad_key = RFE_PK_NONE;
    }
    bad = (rfe_velocity_params_default(vp) != RFE_OK) ? -1 : 0; /* cannot fail: vp is set */
    for (k = RFE_PK_OBS_FIRST; k < (size_t)RFE_PK_COUNT; ++k) {
        bad |= set_obs_key(vp, ps, k);
    }
    if ((bad == 0) && (rfe_velocity_params_validate(vp) == RFE_OK)) {
        return RFE_OK;
    }
    /* Which key alone makes it fail, from the (valid) defaults. */
    for (k = RFE_PK_OBS_FIRST; (bad_key != NULL) && (k < (size_t)RFE_PK_COUNT); ++k) {
        rfe_velocity_params_t one;
        if ((rfe_velocity_params_default(&one) != RFE_OK) || (set_obs_key(&one, ps, k) != 0) ||
            (rfe_velocity_params_validate(&one) != RFE_OK)) {
            *bad_key = k;
            break;
        }
    }
    return RFE_ERR_PARAM;
}

void rfe_replay_sample_from_row(const rfe_sensor_row_t *row, rfe_sample_t *s)
{
    size_t w;
    s->delta = (rfe_real_t)row->delta;
    s->vx = (rfe_real_t)row->vx;
    s->vy = (rfe_real_t)row->vy;
    s->yaw_rate = (rfe_real_t)row->yaw_rate;
    s->yaw_acc = (rfe_real_t)row->yaw_acc;
    s->ax = (rfe_real_t)row->ax;
    s->ay = (rfe_real_t)row->ay;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        s->omega[w] = (rfe_real_t)row->omega[w];
    }
}

/* One step. On a rejected sample the estimator is unchanged: log its current estimate,
 * not valid, with the error status, and carry on. */
static void step_row(rfe_friction_t *est, const rfe_sensor_row_t *row, rfe_est_row_t *out)
{
    rfe_sample_t s;
    rfe_estimate_t e;
    rfe_status_t st;
    size_t w;
    rfe_replay_sample_from_row(row, &s);
    memset(&e, 0, sizeof e);
    /* friction.h: on a rejected sample e holds the previous estimate, valid = 0. */
    st = rfe_friction_step(est, &s, &e);
    out->t = row->t;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        out->mu[w] = (double)e.mu[w];
        out->sd[w] = (double)e.sd[w];
        out->valid[w] = rfe_status_is_error(st) ? 0u : e.valid[w];
    }
    out->status = (int)st;
    out->has_velocity = 0;
}

rfe_status_t rfe_replay_params(const rfe_param_set_t *ps, rfe_params_t *p,
                               size_t *bad_key)
{
    rfe_status_t st;
    if ((ps == NULL) || (p == NULL)) {
        return RFE_ERR_NULL;
    }
    if (bad_key != NULL) {
        *bad_key = RFE_PK_NONE;
    }
    st = to_lib_params(ps, p);
    if (st == RFE_OK) {
        st = rfe_params_validate(p);
    }
    if ((st == RFE_ERR_PARAM) && (bad_key != NULL)) {
        *bad_key = diagnose_params(ps);
    }
    return st;
}

rfe_status_t rfe_replay_run(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                            rfe_est_row_t *out, rfe_replay_stats_t *stats,
                            size_t *bad_key)
{
    rfe_params_t p;
    rfe_friction_t est;
    rfe_status_t st;
    size_t i;
    if ((ps == NULL) || (log == NULL) || (out == NULL) || (stats == NULL)) {
        return RFE_ERR_NULL;
    }
    memset(stats, 0, sizeof *stats);
    if ((log->omega_linear != 0) || (log->has_swa != 0)) {
        return RFE_ERR_RANGE; /* not yet rad/s and road-wheel angle: csv_log.h */
    }
    st = rfe_replay_params(ps, &p, bad_key);
    if (st == RFE_OK) {
        st = rfe_friction_init(&est, &p);
    }
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0u; i < log->n_rows; ++i) {
        /* a gap: the missed periods' time updates before the sample that ends it */
        const uint32_t missed = rfe_log_missed_before(log, i, ps->value[RFE_PK_dt]);
        if (missed > 0u) {
            ++stats->n_gaps;
            if (rfe_friction_skip(&est, missed) == RFE_OK) {
                stats->n_skipped += missed;
            }
        }
        step_row(&est, &log->rows[i], &out[i]);
        ++stats->status_count[rfe_replay_status_slot(out[i].status)];
    }
    stats->n_steps = log->n_rows;
    return RFE_OK;
}

void rfe_replay_esc_input(const rfe_sensor_log_t *log, size_t i, size_t prev,
                          rfe_velocity_input_t *in)
{
    const rfe_sensor_row_t *row = &log->rows[i];
    size_t w;
    memset(in, 0, sizeof *in);
    in->dt = (prev < i) ? (rfe_real_t)(row->t - log->rows[prev].t) : (rfe_real_t)0.0;
    in->delta = (rfe_real_t)row->delta;
    in->steer_wheel = log->has_swa ? (rfe_real_t)row->swa : (rfe_real_t)0.0;
    in->yaw_rate = (rfe_real_t)row->yaw_rate;
    in->ax = (rfe_real_t)row->ax;
    in->ay = (rfe_real_t)row->ay;
    in->grade = log->has_grade ? (rfe_real_t)row->grade : (rfe_real_t)0.0;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        in->omega[w] = (rfe_real_t)row->omega[w];
        in->p_brake[w] = log->has_pressure ? (rfe_real_t)row->p_brake[w] : (rfe_real_t)0.0;
        in->torque[w] = log->has_torque ? (rfe_real_t)row->torque[w] : (rfe_real_t)0.0;
    }
    in->has = (log->has_pressure ? RFE_VEL_HAS_PRESSURE : 0u) |
              (log->has_torque ? RFE_VEL_HAS_TORQUE : 0u) |
              (log->has_swa ? RFE_VEL_HAS_STEER_WHEEL : 0u);
}

rfe_status_t rfe_replay_run_observer(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                     rfe_est_row_t *out, rfe_replay_stats_t *stats,
                                     size_t *bad_key)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    static rfe_pipeline_t pl; /* large; the replay is single-threaded host code */
    rfe_status_t st;
    size_t i;
    size_t w;
    size_t last = SIZE_MAX; /* the last accepted row: none yet */
    if ((ps == NULL) || (log == NULL) || (out == NULL) || (stats == NULL)) {
        return RFE_ERR_NULL;
    }
    memset(stats, 0, sizeof *stats);
    if (log->omega_linear != 0) {
        return RFE_ERR_RANGE; /* wheel speeds not yet rad/s: rfe_sensor_log_wheel_radius */
    }
    st = rfe_replay_params(ps, &p, bad_key);
    if (st == RFE_OK) {
        st = rfe_replay_velocity_params(ps, &vp, bad_key);
    }
    if (st == RFE_OK) {
        st = rfe_pipeline_init(&pl, &p, &vp);
    }
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0u; i < log->n_rows; ++i) {
        rfe_velocity_input_t in;
        rfe_pipeline_out_t o;
        rfe_replay_esc_input(log, i, last, &in);
        memset(&o, 0, sizeof o);
        st = rfe_pipeline_step(&pl, &in, &o);
        if (!rfe_status_is_error(st)) {
            last = i; /* the next period starts here */
            stats->n_gaps += (o.missed > 0u) ? 1u : 0u;
            stats->n_skipped += o.missed;
            stats->n_restarts += o.restarted;
        }
        out[i].t = log->rows[i].t;
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            out[i].mu[w] = (double)o.friction.mu[w];
            out[i].sd[w] = (double)o.friction.sd[w];
            out[i].valid[w] = rfe_status_is_error(st) ? 0u : o.friction.valid[w];
        }
        out[i].status = (int)st;
        out[i].has_velocity = 1;
        out[i].vx = (double)o.velocity.vx;
        out[i].vy = (double)o.velocity.vy;
        out[i].beta = (double)o.velocity.beta;
        out[i].yaw_acc = (double)o.velocity.yaw_acc;
        out[i].sd_vx = (double)o.velocity.sd_vx;
        out[i].sd_vy = (double)o.velocity.sd_vy;
        out[i].sd_beta = (double)o.velocity.sd_beta;
        ++stats->status_count[rfe_replay_status_slot(out[i].status)];
    }
    stats->n_steps = log->n_rows;
    return RFE_OK;
}
