/**
 * @file replay_q31.c
 * @brief The fixed-point part of mu_replay (`--real q31`): double parameter set ->
 *        rfe_params_t (double) -> rfe_params_q31_t, sensor rows -> rfe_sample_q31_t,
 *        estimator steps -> double estimate rows (exact conversions back).
 *
 * Compiled once. It uses the double library for the parameters (rfe_replay_params_f64,
 * rfe_params_to_q31_f64), so it is always built as a double translation unit.
 */
#if !defined(RFE_REAL_DOUBLE)
#define RFE_REAL_DOUBLE 1
#endif

#include "replay_q31.h"

#include <string.h>

#include "rfe/friction_q31.h"
#include "host/fixed_conv.h"
#include "rfe/component/params_conv.h"

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

/* The numeric key that alone, on top of the preset, makes the conversion to Q formats fail
 * with RFE_ERR_RANGE, or RFE_PK_NONE (a combination, e.g. dt and tau_v whose gain
 * dt / (tau_v + dt) has too few bits). The word keys (tyre, filter, structure) change no
 * value's format. Called after a conversion that got as far as the formats, so the preset
 * is a valid one. */
static size_t diagnose_range(const rfe_param_set_t *ps)
{
    size_t k;
    for (k = 0u; k < RFE_PK_NUMERIC; ++k) {
        rfe_param_set_t one;
        rfe_params_q31_t q;
        (void)rfe_param_set_preset_f64(&one, ps->preset); /* cannot fail: a valid preset */
        one.value[k] = ps->value[k];
        if (rfe_replay_params_q31(&one, &q, NULL) == RFE_ERR_RANGE) {
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

/* One step; a rejected sample logs the unchanged estimate, not valid, with its status. */
static uint32_t step_row(rfe_friction_q31_t *est, const rfe_sensor_row_t *row,
                         rfe_est_row_t *out, rfe_replay_q31_stats_t *stats)
{
    rfe_sample_q31_t s;
    rfe_estimate_q31_t e;
    rfe_status_t st;
    uint32_t in_sat;
    size_t w;
    in_sat = rfe_replay_sample_q31(row, &s);
    memset(&e, 0, sizeof e);
    st = rfe_friction_step_q31(est, &s, &e);
    out->t = row->t;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        out->mu[w] = rfe_fix_to_double(e.mu[w], RFE_FIX_Q_MU);
        out->sd[w] = rfe_fix_to_double(e.sd[w], RFE_FIX_Q_SD);
        out->valid[w] = rfe_status_is_error(st) ? 0u : e.valid[w];
    }
    out->status = (int)st;
    out->has_velocity = 0; /* the fixed-point observer does not exist yet */
    if (in_sat != 0u) {
        stats->input_sat += in_sat;
        ++stats->input_sat_rows;
    }
    if (e.sat != 0u) {
        stats->est_sat += e.sat;
        ++stats->est_sat_rows;
        if (e.sat > stats->est_sat_max) {
            stats->est_sat_max = e.sat;
        }
    }
    return e.sat;
}

rfe_status_t rfe_replay_run_q31(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                rfe_est_row_t *out, rfe_replay_q31_stats_t *stats,
                                uint32_t *row_sat, size_t *bad_key)
{
    rfe_params_q31_t q;
    rfe_friction_q31_t est;
    rfe_status_t st;
    size_t i;
    if ((ps == NULL) || (log == NULL) || (out == NULL) || (stats == NULL)) {
        return RFE_ERR_NULL;
    }
    memset(stats, 0, sizeof *stats);
    if ((log->omega_linear != 0) || (log->has_swa != 0)) {
        return RFE_ERR_RANGE; /* not yet rad/s and road-wheel angle: csv_log.h */
    }
    st = rfe_replay_params_q31(ps, &q, bad_key);
    if ((st == RFE_ERR_RANGE) && (bad_key != NULL)) {
        *bad_key = diagnose_range(ps);
    }
    if (st == RFE_OK) {
        st = rfe_friction_init_q31(&est, &q);
    }
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0u; i < log->n_rows; ++i) {
        const uint32_t sat = step_row(&est, &log->rows[i], &out[i], stats);
        if (row_sat != NULL) {
            row_sat[i] = sat;
        }
        ++stats->base.status_count[rfe_replay_status_slot(out[i].status)];
    }
    stats->base.n_steps = log->n_rows;
    return RFE_OK;
}
