/**
 * @file replay_q31.c
 * @brief The fixed-point part of mu_replay (`--real q31`): double parameter set ->
 *        rfe_params_t (double) -> rfe_params_q31_t (and the observer's
 *        rfe_velocity_params_q31_t, the mass and grade estimator's
 *        rfe_mass_grade_params_q31_t), sensor rows -> rfe_sample_q31_t (or
 *        rfe_velocity_input_q31_t; rfe_mass_grade_input_q31_t), estimator or pipeline steps
 *        -> double estimate rows (exact conversions back).
 *
 * Compiled once. It uses the double library for the parameters (rfe_replay_params_f64,
 * rfe_params_to_q31_f64), so it is always built as a double translation unit.
 */
#if !defined(RFE_REAL_DOUBLE)
#define RFE_REAL_DOUBLE 1
#endif

#include "replay_q31.h"

#include <math.h>
#include <string.h>

#include "rfe/friction_q31.h"
#include "rfe/mass_grade.h"
#include "rfe/mass_grade_q31.h"
#include "rfe/pipeline_q31.h"
#include "host/fixed_conv.h"
#include "log_timing.h"
#include "rfe/component/params_conv.h"

/** The per-log state of a fixed-point replay (replay_q31.h). Opaque outside this file. */
struct rfe_replay_q31_state {
    rfe_pipeline_q31_t pl;        /**< the observer and friction estimator; measured
                                       velocities: pl.friction alone */
    rfe_mass_grade_q31_t mg;      /**< when mg_on */
    rfe_sensor_log_t shape;       /**< the log's has_* flags (no rows, no metadata) */
    rfe_replay_q31_stats_t stats;
    double dt;                    /**< key dt: the gaps of a measuring run */
    double t_prev;                /**< the previous row's time (have_prev) */
    double t_last;                /**< the observer's last accepted row's time (have_last) */
    double t_mg_last;             /**< the mass and grade estimator's (have_mg_last) */
    double mg_R;                  /**< the double parameters' R: the wheels' speed */
    double feed_sd_rel;           /**< key mg_feed_sd_rel */
    rfe_replay_mass_gate_t gate;  /**< the feed's excitation gate (mg_feed_excitation) */
    int have_prev;
    int have_last;
    int have_mg_last;
    int observer;                 /**< the pipeline runs (else the friction estimator alone) */
    int mg_on;                    /**< the mass and grade estimator runs */
    int ready;                    /**< rfe_replay_begin_q31 succeeded */
};

rfe_status_t rfe_replay_params_q31(const rfe_param_set_t *ps, rfe_params_q31_t *q,
                                   size_t *bad_key)
{
    rfe_params_t p;
    rfe_status_t st;
    if ((ps == NULL) || (q == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_replay_params_f64(ps, &p, bad_key);
    if (st == RFE_OK) {
        st = rfe_params_to_q31_f64(&p, q);
    }
    return st;
}

rfe_status_t rfe_replay_observer_params_q31(const rfe_param_set_t *ps, rfe_params_q31_t *q,
                                            rfe_velocity_params_q31_t *vq, size_t *bad_key)
{
    rfe_velocity_params_t vp;
    rfe_status_t st = rfe_replay_params_q31(ps, q, bad_key);
    if (st == RFE_OK) {
        st = rfe_replay_velocity_params_f64(ps, &vp, bad_key);
    }
    if (st == RFE_OK) {
        st = rfe_velocity_params_to_q31_f64(&vp, vq);
    }
    return st;
}

/* The numeric key that alone, on top of the preset, makes the conversion to Q formats fail
 * with RFE_ERR_RANGE, or RFE_PK_NONE (a combination, e.g. dt and tau_v whose gain
 * dt / (tau_v + dt) has too few bits). The word keys (tyre, filter, structure) change no
 * value's format. With @p observer the obs_* keys are tried too (the observer's conversion
 * after the friction one). Called after a conversion that got as far as the formats, so the
 * preset is a valid one. */
static size_t diagnose_range(const rfe_param_set_t *ps, int observer)
{
    size_t k;
    for (k = 0u; k < (size_t)RFE_PK_COUNT; ++k) {
        rfe_param_set_t one;
        rfe_params_q31_t q;
        rfe_velocity_params_q31_t vq;
        rfe_status_t st;
        if ((k >= RFE_PK_NUMERIC) && ((observer == 0) || (rfe_param_is_obs(k) == 0))) {
            continue; /* a word key, or an observer key of a friction-only run */
        }
        (void)rfe_param_set_preset_f64(&one, ps->preset); /* cannot fail: a valid preset */
        if (k < RFE_PK_NUMERIC) {
            one.value[k] = ps->value[k];
        } else {
            one.obs[k - RFE_PK_OBS_FIRST] = ps->obs[k - RFE_PK_OBS_FIRST];
        }
        st = (observer != 0) ? rfe_replay_observer_params_q31(&one, &q, &vq, NULL)
                             : rfe_replay_params_q31(&one, &q, NULL);
        if (st == RFE_ERR_RANGE) {
            return k;
        }
    }
    return RFE_PK_NONE;
}

uint32_t rfe_replay_sample_q31(const rfe_sensor_row_t *row, rfe_sample_q31_t *s)
{
    uint32_t sat = 0u;
    size_t w;
    s->delta = rfe_fix_from_double(row->delta, RFE_FIX_Q_ANGLE, &sat);
    s->vx = rfe_fix_from_double(row->vx, RFE_FIX_Q_SPEED, &sat);
    s->vy = rfe_fix_from_double(row->vy, RFE_FIX_Q_SPEED, &sat);
    s->yaw_rate = rfe_fix_from_double(row->yaw_rate, RFE_FIX_Q_YAWRATE, &sat);
    s->yaw_acc = rfe_fix_from_double(row->yaw_acc, RFE_FIX_Q_ACC, &sat);
    s->ax = rfe_fix_from_double(row->ax, RFE_FIX_Q_ACC, &sat);
    s->ay = rfe_fix_from_double(row->ay, RFE_FIX_Q_ACC, &sat);
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        s->omega[w] = rfe_fix_from_double(row->omega[w], RFE_FIX_Q_OMEGA, &sat);
    }
    return sat;
}

/* Adds one row's saturation counts (of its conversion and of the library's step). */
static void count_sat(rfe_replay_q31_stats_t *stats, uint32_t in_sat, uint32_t step_sat)
{
    if (in_sat != 0u) {
        stats->input_sat += in_sat;
        ++stats->input_sat_rows;
    }
    if (step_sat != 0u) {
        stats->est_sat += step_sat;
        ++stats->est_sat_rows;
        if (step_sat > stats->est_sat_max) {
            stats->est_sat_max = step_sat;
        }
    }
}

/* The sum of two saturation counts, saturating as each count does. */
static uint32_t sat_add(uint32_t a, uint32_t b)
{
    return (a > UINT32_MAX - b) ? UINT32_MAX : a + b;
}

/* One step; a rejected sample logs the unchanged estimate, not valid, with its status. Adds
 * the conversion's saturations to *in_sat; returns the step's. */
static uint32_t step_row(rfe_friction_q31_t *est, const rfe_sensor_row_t *row,
                         rfe_est_row_t *out, uint32_t *in_sat)
{
    rfe_sample_q31_t s;
    rfe_estimate_q31_t e;
    rfe_status_t st;
    size_t w;
    memset(&e, 0, sizeof e);
    if (row->bad != 0u) {
        /* a NaN / Inf cell (csv_log.h RFE_CELLS_KEEP) has no Q value: rejected here as the
         * float library rejects it, the estimate held */
        st = (rfe_friction_get_q31(est, &e) == RFE_OK) ? RFE_ERR_NONFINITE : RFE_ERR_NOT_INITIALISED;
        e.sat = 0u;
    } else {
        *in_sat = sat_add(*in_sat, rfe_replay_sample_q31(row, &s));
        st = rfe_friction_step_q31(est, &s, &e);
    }
    out->t = row->t;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        out->mu[w] = rfe_fix_to_double(e.mu[w], RFE_FIX_Q_MU);
        out->sd[w] = rfe_fix_to_double(e.sd[w], RFE_FIX_Q_SD);
        out->valid[w] = rfe_status_is_error(st) ? 0u : e.valid[w];
    }
    out->status = (int)st;
    out->has_velocity = 0; /* has_mass_grade: the caller's (mass_grade_row sets it) */
    return e.sat;
}

/* rfe_replay_esc_input_q31 on @p row, the period since @p t_prev (NULL: none yet). */
static uint32_t esc_input_row_q31(const rfe_sensor_log_t *log, const rfe_sensor_row_t *row,
                                  const double *t_prev, rfe_velocity_input_q31_t *in)
{
    rfe_velocity_input_t d; /* the double run's sample: which columns, the period, the bits */
    uint32_t sat = 0u;
    size_t w;
    rfe_replay_esc_input_row(log, row, t_prev, &d);
    memset(in, 0, sizeof *in);
    in->dt = rfe_fix_from_double(d.dt, RFE_FIX_Q_DT, &sat);
    in->delta = rfe_fix_from_double(d.delta, RFE_FIX_Q_ANGLE, &sat);
    in->steer_wheel = rfe_fix_from_double(d.steer_wheel, RFE_FIX_Q_STEER_WHEEL, &sat);
    in->yaw_rate = rfe_fix_from_double(d.yaw_rate, RFE_FIX_Q_YAWRATE, &sat);
    in->ax = rfe_fix_from_double(d.ax, RFE_FIX_Q_ACC, &sat);
    in->ay = rfe_fix_from_double(d.ay, RFE_FIX_Q_ACC, &sat);
    in->grade = rfe_fix_from_double(d.grade, RFE_FIX_Q_ANGLE, &sat);
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        in->omega[w] = rfe_fix_from_double(d.omega[w], RFE_FIX_Q_OMEGA, &sat);
        in->p_brake[w] = rfe_fix_from_double(d.p_brake[w], RFE_FIX_Q_PRESSURE, &sat);
        in->torque[w] = rfe_fix_from_double(d.torque[w], RFE_FIX_Q_TORQUE, &sat);
    }
    in->has = d.has;
    return sat;
}

uint32_t rfe_replay_esc_input_q31(const rfe_sensor_log_t *log, size_t i, size_t prev,
                                  rfe_velocity_input_q31_t *in)
{
    return esc_input_row_q31(log, &log->rows[i], (prev < i) ? &log->rows[prev].t : NULL, in);
}

/* Whether the values of the double sample @p d are finite where the float library checks
 * them (rfe_mass_grade_step: dt, v, torque; p_brake with RFE_MG_HAS_PRESSURE, ax with
 * RFE_MG_HAS_AX, vx with RFE_MG_HAS_VX, ay with RFE_MG_HAS_AY). */
static int mg_values_finite(const rfe_mass_grade_input_t *d)
{
    return isfinite(d->dt) && isfinite(d->v) && isfinite(d->torque) &&
           (((d->has & RFE_MG_HAS_PRESSURE) == 0u) || isfinite(d->p_brake)) &&
           (((d->has & RFE_MG_HAS_AX) == 0u) || isfinite(d->ax)) &&
           (((d->has & RFE_MG_HAS_VX) == 0u) || isfinite(d->vx)) &&
           (((d->has & RFE_MG_HAS_AY) == 0u) || isfinite(d->ay));
}

rfe_status_t rfe_replay_mass_grade_input_q31(const rfe_sensor_log_t *log,
                                             const rfe_sensor_row_t *row, const double *t_prev,
                                             double R, rfe_mass_grade_input_q31_t *in,
                                             uint32_t *sat)
{
    rfe_mass_grade_input_t d; /* the double run's sample */
    rfe_status_t st = rfe_replay_mass_grade_input_row_f64(log, row, t_prev, R, &d);
    memset(in, 0, sizeof *in);
    if ((st == RFE_OK) && (mg_values_finite(&d) == 0)) {
        st = RFE_ERR_NONFINITE; /* no Q value: refused as the float library refuses it */
    }
    if (st == RFE_OK) {
        in->dt = rfe_fix_from_double(d.dt, RFE_MG_Q_DT, sat);
        in->v = rfe_fix_from_double(d.v, RFE_MG_Q_V, sat);
        in->torque = rfe_fix_from_double(d.torque, RFE_MG_Q_TORQUE, sat);
        in->ax = rfe_fix_from_double(d.ax, RFE_MG_Q_V, sat);
        in->vx = rfe_fix_from_double(d.vx, RFE_MG_Q_V, sat);
        in->ay = rfe_fix_from_double(d.ay, RFE_MG_Q_V, sat);
        in->p_brake = rfe_fix_from_double(d.p_brake * 1e-6, RFE_MG_Q_PRESSURE, sat); /* MPa */
        in->gear = d.gear;
        in->brake = d.brake;
        in->has = d.has;
    }
    return st;
}

/* One mass and grade step on @p row into @p out (the Q values converted back exactly); a
 * row the library or the sample's checks refuse gets the held estimate and its error status.
 * Adds the conversion's saturations to *in_sat; returns the step's. */
static uint32_t mass_grade_row(rfe_replay_q31_state_t *st, const rfe_sensor_row_t *row,
                               rfe_est_row_t *out, uint32_t *in_sat)
{
    rfe_mass_grade_input_q31_t in;
    /* the estimate of the last step (zero before the first accepted sample), held should the
     * row be refused here; the library's step refusing it gives the same (mass_grade_q31.h) */
    rfe_mass_grade_estimate_q31_t e = st->mg.last;
    rfe_status_t s = rfe_replay_mass_grade_input_q31(&st->shape, row,
                                                     st->have_mg_last ? &st->t_mg_last : NULL,
                                                     st->mg_R, &in, in_sat);
    /* the library's start (mass_grade_q31.h: not started, or a period beyond dt_max), in its
     * Q30, for the feed's gate (replay_real.c's) */
    const int start = ((st->mg.started == 0u) || (in.dt > st->mg.p.dt_max)) ? 1 : 0;
    const double dt = st->have_mg_last ? (row->t - st->t_mg_last) : 0.0;
    if (s == RFE_OK) {
        s = rfe_mass_grade_step_q31(&st->mg, &in, &e);
    }
    if (!rfe_status_is_error(s)) {
        st->t_mg_last = row->t;
        st->have_mg_last = 1;
    }
    rfe_replay_mass_gate_step(&st->gate, rfe_status_is_error(s) ? 0 : start, (int)s, row->ax, dt,
                              rfe_replay_mass_gate_slips(&st->gate, row, st->mg_R));
    st->stats.base.mg_excitation = st->gate.excitation;
    out->has_mass_grade = 1;
    out->mass = rfe_fix_to_double(e.mass, RFE_MG_Q_M);
    out->sd_mass = rfe_fix_to_double(e.sd_mass, RFE_MG_Q_M);
    out->grade = rfe_fix_to_double(e.grade, RFE_MG_Q_TH);
    out->sd_grade = rfe_fix_to_double(e.sd_grade, RFE_MG_Q_TH);
    out->mg_status = (int)s;
    out->grade_walk = (int)st->mg.wq_hi; /* §4.7 the level after this step (an error leaves it) */
    out->mg_mismatch = (int)e.mismatch; /* §4.8 the flag after this step */
    ++st->stats.base.mg_status_count[rfe_replay_status_slot(out->mg_status)];
    return rfe_status_is_error(s) ? 0u : e.sat; /* a refused step saturated nothing */
}

/* The mass and grade step first, so this sample's friction step takes the mass fed from this
 * sample's update (replay_real.c's order and rule, rfe_replay_mass_feed_due). The mass goes
 * from its Q14 to the friction estimator's Q16 (RFE_FIX_Q_MASS: exact below 32768 kg); one
 * beyond that format is not fed, as a mass rfe_friction_set_mass_q31 refuses is not (the
 * last one kept). Returns the step's saturations. */
static uint32_t mass_grade_first(rfe_replay_q31_state_t *st, const rfe_sensor_row_t *row,
                                 rfe_est_row_t *out, uint32_t *in_sat)
{
    int fed = -1;
    uint32_t sat;
    rfe_replay_feed_t due;
    if (st->shape.has_velocity != 0) {
        rfe_replay_mass_gate_vx(&st->gate, row->vx); /* the measured vx: the slip's reference */
    }
    sat = mass_grade_row(st, row, out, in_sat);
    due = rfe_replay_mass_feed_due(st->feed_sd_rel, &st->gate, out);
    rfe_replay_mass_feed_count(due, &st->stats.base);
    if (due == RFE_REPLAY_FEED_DUE) {
        uint32_t over = 0u;
        const rfe_fix_t m = rfe_fix_from_double(out->mass, RFE_FIX_Q_MASS, &over);
        if (over != 0u) {
            fed = (int)RFE_ERR_RANGE;
        } else {
            fed = (int)((st->observer != 0) ? rfe_pipeline_set_mass_q31(&st->pl, m)
                                            : rfe_friction_set_mass_q31(&st->pl.friction, m));
        }
    }
    out->mass_used = rfe_fix_to_double(st->pl.friction.params.vehicle.m, RFE_FIX_Q_MASS);
    st->stats.base.n_mass_fed += (fed == (int)RFE_OK) ? 1u : 0u;
    st->stats.base.mass_used_last = out->mass_used;
    return sat;
}

/* One pipeline step of @p row; returns the step's saturations (mass and grade, observer and
 * friction). */
static uint32_t step_observer_row(rfe_replay_q31_state_t *st, const rfe_sensor_row_t *row,
                                  rfe_est_row_t *out)
{
    rfe_pipeline_q31_t *pl = &st->pl;
    rfe_velocity_input_q31_t in;
    rfe_pipeline_out_q31_t o;
    rfe_status_t s;
    uint32_t in_sat = 0u;
    uint32_t sat = 0u;
    size_t w;
    memset(&o, 0, sizeof o);
    if (st->mg_on != 0) {
        sat = mass_grade_first(st, row, out, &in_sat);
    }
    if (row->bad != 0u) {
        /* a NaN / Inf cell has no Q value: rejected as in float, both estimates held */
        s = ((rfe_friction_get_q31(&pl->friction, &o.friction) == RFE_OK) &&
             (rfe_velocity_get_q31(&pl->velocity, &o.velocity) == RFE_OK)) ? RFE_ERR_NONFINITE
                                                                           : RFE_ERR_NOT_INITIALISED;
        o.friction.sat = 0u;
        o.velocity.sat = 0u;
    } else {
        in_sat = sat_add(in_sat, esc_input_row_q31(&st->shape, row,
                                                   st->have_last ? &st->t_last : NULL, &in));
        if ((st->mg_on != 0) && (st->shape.has_grade == 0)) {
            /* no grade column: this sample's estimated grade (Q29 into the observer's Q29) */
            in.grade = rfe_fix_from_double(out->grade, RFE_FIX_Q_ANGLE, &in_sat);
        }
        /* pipeline_q31.h: on an error o holds the previous estimates, sat 0 */
        s = rfe_pipeline_step_q31(pl, &in, &o);
        if (!rfe_status_is_error(s)) {
            st->t_last = row->t; /* the next period starts here */
            st->have_last = 1;
            st->stats.base.n_gaps += (o.missed > 0u) ? 1u : 0u;
            st->stats.base.n_skipped += o.missed;
            st->stats.base.n_restarts += o.restarted;
            if (st->shape.has_velocity == 0) {
                /* no measured vx: the next row's slip is taken against this observer vx */
                rfe_replay_mass_gate_vx(&st->gate,
                                        rfe_fix_to_double(o.velocity.vx, RFE_FIX_Q_SPEED));
            }
        }
    }
    out->t = row->t;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        out->mu[w] = rfe_fix_to_double(o.friction.mu[w], RFE_FIX_Q_MU);
        out->sd[w] = rfe_fix_to_double(o.friction.sd[w], RFE_FIX_Q_SD);
        out->valid[w] = rfe_status_is_error(s) ? 0u : o.friction.valid[w];
    }
    out->status = (int)s;
    out->has_velocity = 1;
    out->vx = rfe_fix_to_double(o.velocity.vx, RFE_FIX_Q_SPEED);
    out->vy = rfe_fix_to_double(o.velocity.vy, RFE_FIX_Q_SPEED);
    out->beta = rfe_fix_to_double(o.velocity.beta, RFE_FIX_Q_ANGLE);
    out->yaw_acc = rfe_fix_to_double(o.velocity.yaw_acc, RFE_FIX_Q_ACC);
    out->sd_vx = rfe_fix_to_double(o.velocity.sd_vx, RFE_FIX_Q_SPEED);
    out->sd_vy = rfe_fix_to_double(o.velocity.sd_vy, RFE_FIX_Q_SPEED);
    out->sd_beta = rfe_fix_to_double(o.velocity.sd_beta, RFE_FIX_Q_ANGLE);
    sat = sat_add(sat, sat_add(o.velocity.sat, o.friction.sat));
    count_sat(&st->stats, in_sat, sat);
    return sat;
}

/* One friction step on measured velocities: a gap's missed periods time-updated before the
 * sample that ends it; the mass and grade step first (its grade feeds nothing here). */
static uint32_t step_measured_row(rfe_replay_q31_state_t *st, const rfe_sensor_row_t *row,
                                  rfe_est_row_t *out)
{
    const uint32_t missed = st->have_prev ? rfe_log_missed(row->t - st->t_prev, st->dt) : 0u;
    uint32_t in_sat = 0u;
    uint32_t sat = 0u;
    if (missed > 0u) {
        ++st->stats.base.n_gaps;
        if (rfe_friction_skip_q31(&st->pl.friction, missed) == RFE_OK) {
            st->stats.base.n_skipped += missed;
        }
    }
    if (st->mg_on != 0) {
        sat = mass_grade_first(st, row, out, &in_sat);
    }
    sat = sat_add(sat, step_row(&st->pl.friction, row, out, &in_sat));
    count_sat(&st->stats, in_sat, sat);
    return sat;
}

size_t rfe_replay_state_size_q31(void)
{
    return sizeof(rfe_replay_q31_state_t);
}

/* The key of the mass and grade parameters (R, g, an mg_* key) that alone, on top of the
 * set's presets (the friction preset's R and g, the mass and grade config's mg_* keys), makes
 * rfe_mass_grade_params_to_q31_f64 fail with RFE_ERR_RANGE, or RFE_PK_NONE (only a
 * combination does: values the validation refuses alone). */
static size_t diagnose_mg_range(const rfe_param_set_t *ps)
{
    rfe_param_set_t base;
    size_t i;
    (void)rfe_param_set_preset_f64(&base, ps->preset); /* cannot fail: the set's presets */
    (void)rfe_param_set_mass_grade_f64(&base, ps->mg_vehicle, ps->mg_config);
    for (i = 0u; i < 2u + (size_t)RFE_PK_MG_COUNT; ++i) {
        const size_t k = (i == 0u) ? (size_t)RFE_PK_R
                                   : ((i == 1u) ? (size_t)RFE_PK_g : RFE_PK_MG_FIRST + i - 2u);
        rfe_param_set_t one = base;
        rfe_mass_grade_params_t mp;
        rfe_mass_grade_params_q31_t mq;
        if (k < RFE_PK_MG_FIRST) {
            one.value[k] = ps->value[k];
        } else {
            one.mg[k - RFE_PK_MG_FIRST] = ps->mg[k - RFE_PK_MG_FIRST];
        }
        if ((rfe_replay_mass_grade_params_f64(&one, &mp, NULL) == RFE_OK) &&
            (rfe_mass_grade_params_to_q31_f64(&mp, &mq) == RFE_ERR_RANGE)) {
            return k;
        }
    }
    return RFE_PK_NONE;
}

/* Whether this run steps the mass and grade estimator (as the float replay: the set says so
 * and the log has drive_torque), and if so its parameters (the double path, then
 * rfe_mass_grade_params_to_q31_f64) and init. RFE_ERR_RANGE: a value beyond its Q format
 * (*bad_key the key, or RFE_PK_NONE); RFE_ERR_PARAM from the init: a set outside the
 * fixed-point domain (mass_grade_params_q31.h: 1 < n + lambda < 16, w_c,0 >= 0). */
static rfe_status_t mass_grade_init(rfe_replay_q31_state_t *st, const rfe_param_set_t *ps,
                                    const rfe_sensor_log_t *log, size_t *bad_key)
{
    rfe_mass_grade_params_t mp;
    rfe_mass_grade_params_q31_t mq;
    rfe_status_t s = RFE_OK;
    st->mg_on = ((ps->mass_grade != 0) && (log->has_drive_torque != 0)) ? 1 : 0;
    st->feed_sd_rel = ps->mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST];
    st->gate = rfe_replay_mass_gate_of(ps);
    if (st->mg_on != 0) {
        s = rfe_replay_mass_grade_params_f64(ps, &mp, bad_key);
    }
    if ((st->mg_on != 0) && (s == RFE_OK)) {
        st->mg_R = mp.R;
        s = rfe_mass_grade_params_to_q31_f64(&mp, &mq);
        if ((s == RFE_ERR_RANGE) && (bad_key != NULL)) {
            *bad_key = diagnose_mg_range(ps);
        }
    }
    if ((st->mg_on != 0) && (s == RFE_OK)) {
        s = rfe_mass_grade_init_q31(&st->mg, &mq);
    }
    return s;
}

rfe_status_t rfe_replay_begin_q31(rfe_replay_q31_state_t *st, const rfe_param_set_t *ps,
                                  const rfe_sensor_log_t *log, int observer, size_t *bad_key)
{
    rfe_params_q31_t q;
    rfe_velocity_params_q31_t vq;
    rfe_status_t s;
    if ((st == NULL) || (ps == NULL) || (log == NULL)) {
        return RFE_ERR_NULL;
    }
    /* not yet rad/s (and, measuring, a road-wheel angle): csv_log.h; the state untouched */
    if ((log->omega_linear != 0) || ((observer == 0) && (log->has_swa != 0))) {
        return RFE_ERR_RANGE;
    }
    memset(st, 0, sizeof *st); /* padding defined: a run is a function of its input */
    st->shape = rfe_sensor_log_shape(log); /* the columns it has, not its rows nor metadata */
    st->observer = (observer != 0) ? 1 : 0;
    st->dt = ps->value[RFE_PK_dt];
    s = (observer != 0) ? rfe_replay_observer_params_q31(ps, &q, &vq, bad_key)
                        : rfe_replay_params_q31(ps, &q, bad_key);
    if ((s == RFE_ERR_RANGE) && (bad_key != NULL)) {
        *bad_key = diagnose_range(ps, st->observer);
    }
    if (s == RFE_OK) {
        s = (observer != 0) ? rfe_pipeline_init_q31(&st->pl, &q, &vq)
                            : rfe_friction_init_q31(&st->pl.friction, &q);
    }
    if (s == RFE_OK) {
        s = mass_grade_init(st, ps, log, bad_key);
    }
    st->ready = (s == RFE_OK) ? 1 : 0;
    return s;
}

rfe_status_t rfe_replay_step_q31(rfe_replay_q31_state_t *st, const rfe_sensor_row_t *row,
                                 rfe_est_row_t *out, uint32_t *sat)
{
    uint32_t n_sat;
    if ((st == NULL) || (row == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (st->ready == 0) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (st->have_prev && !(row->t > st->t_prev)) {
        return RFE_ERR_RANGE; /* time must increase (the reader's rule for a log) */
    }
    out->has_mass_grade = 0; /* mass_grade_row sets it when the estimator runs */
    out->has_tyre_id = 0;    /* no tyre identifier in fixed point (float and double only) */
    out->has_tyre_feed = 0;
    n_sat = (st->observer != 0) ? step_observer_row(st, row, out) : step_measured_row(st, row, out);
    if (sat != NULL) {
        *sat = n_sat;
    }
    st->t_prev = row->t;
    st->have_prev = 1;
    ++st->stats.base.status_count[rfe_replay_status_slot(out->status)];
    ++st->stats.base.n_steps;
    return RFE_OK;
}

rfe_status_t rfe_replay_feed_q31(rfe_replay_q31_state_t *st, const rfe_sensor_row_t *rows,
                                 size_t n, rfe_est_row_t *out, uint32_t *row_sat)
{
    size_t i;
    rfe_status_t s = ((rows == NULL) || (out == NULL)) ? RFE_ERR_NULL : RFE_OK;
    for (i = 0u; (s == RFE_OK) && (i < n); ++i) {
        s = rfe_replay_step_q31(st, &rows[i], &out[i], (row_sat != NULL) ? &row_sat[i] : NULL);
    }
    return s;
}

rfe_status_t rfe_replay_get_stats_q31(const rfe_replay_q31_state_t *st,
                                      rfe_replay_q31_stats_t *stats)
{
    if ((st == NULL) || (stats == NULL)) {
        return RFE_ERR_NULL;
    }
    *stats = st->stats;
    return RFE_OK;
}

/* A whole log: begin, then every row (the one loop, rfe_replay_feed_q31). */
static rfe_status_t run_log_q31(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                rfe_est_row_t *out, rfe_replay_q31_stats_t *stats,
                                uint32_t *row_sat, size_t *bad_key, int observer)
{
    static rfe_replay_q31_state_t st; /* large; a whole-log run is single-threaded host code */
    rfe_status_t s;
    if ((ps == NULL) || (log == NULL) || (out == NULL) || (stats == NULL)) {
        return RFE_ERR_NULL;
    }
    memset(stats, 0, sizeof *stats);
    s = rfe_replay_begin_q31(&st, ps, log, observer, bad_key);
    if (s == RFE_OK) {
        s = rfe_replay_feed_q31(&st, log->rows, log->n_rows, out, row_sat);
        *stats = st.stats;
    }
    return s;
}

rfe_status_t rfe_replay_run_q31(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                rfe_est_row_t *out, rfe_replay_q31_stats_t *stats,
                                uint32_t *row_sat, size_t *bad_key)
{
    return run_log_q31(ps, log, out, stats, row_sat, bad_key, 0);
}

rfe_status_t rfe_replay_run_observer_q31(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                         rfe_est_row_t *out, rfe_replay_q31_stats_t *stats,
                                         uint32_t *row_sat, size_t *bad_key)
{
    return run_log_q31(ps, log, out, stats, row_sat, bad_key, 1);
}
