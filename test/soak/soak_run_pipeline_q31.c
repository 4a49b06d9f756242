/**
 * @file soak_run_pipeline_q31.c
 * @brief One soak run of the fixed-point composed pipeline (rfe/pipeline_q31.h: the velocity
 *        observer, then the friction estimator on its outputs): parameters and ESC samples
 *        exactly as `mu_replay --real q31 --velocity observer` derives them
 *        (rfe_replay_observer_params_q31, rfe_replay_esc_input_q31: replay_q31.c), every row
 *        stepped and checked, saturations counted. A double translation unit (the parameter
 *        path is the double library's), as soak_run_q31.c.
 *
 * Invariants at every step (any break is a violation; see soak.h), those of the float
 * pipeline's soak (soak_run_pipeline.c) in the Q formats:
 *  - no error status (the drive stays inside every input limit; the float and double
 *    pipelines refuse no row of it either); were one returned, the pipeline must be
 *    untouched (checked too);
 *  - the friction estimator inside the pipeline: inv_check_step_q31 (invariants.h);
 *  - the observer: every sd positive (sd_beta where beta is estimated), its own status
 *    RFE_OK, and each two-state
 *    filter's covariance positive definite up to its rounding: p00 > 0, p11 > 0 and
 *    p01^2 <= (p00 + e)(p11 + e), e = KF2_Q31_PSD_LSB. Each element of P leaves
 *    rfe_kf2_update_q31 with three roundings of one LSB at most (its product, its ratio
 *    and its difference, kf2_q31.c), and rfe_kf2_predict_q31's p00 with four; 8 LSB per
 *    element bounds the sum with room, while a P that lost definiteness misses it by far
 *    more than a few LSB of its diagonal.
 * Besides: vx and vy against the log's vx, vy columns where vx >= v_lat_min, reported, not
 * asserted, as the float pipeline's.
 */
#if !defined(RFE_REAL_DOUBLE)
#define RFE_REAL_DOUBLE 1
#endif
#define INV_Q31 1

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "host/fixed_conv.h"
#include "invariants.h"
#include "param_file.h"
#include "replay_q31.h"
#include "replay_real.h"
#include "rfe/pipeline_q31.h"
#include "soak.h"

#define KF2_Q31_PSD_LSB 8.0

static int params_for(const rfe_sensor_log_t *log, const char *name, rfe_params_q31_t *q,
                      rfe_velocity_params_q31_t *vq)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(q, 0, sizeof(*q));
    memset(vq, 0, sizeof(*vq));
    if (rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT) != 0) {
        return -1;
    }
    if (rfe_param_set_apply_meta(&ps, log, name, &err) != 0) {
        fprintf(stderr, "soak: %s: %s\n", name, err.msg);
        return -1;
    }
    /* mu_replay --real q31 --velocity observer's own conversion (replay_q31.c) */
    return rfe_replay_observer_params_q31(&ps, q, vq, NULL) == RFE_OK ? 0 : -1;
}

static int kf2_fails(const rfe_kf2_q31_t *f, const char *name, char *why)
{
    const double p00 = (double)f->p00, p01 = (double)f->p01, p11 = (double)f->p11;
    if (!(f->p00 > 0) || !(f->p11 > 0) ||
        !(p01 * p01 <= (p00 + KF2_Q31_PSD_LSB) * (p11 + KF2_Q31_PSD_LSB))) {
        snprintf(why, INV_WHY, "q31 observer filter %s: P = [%.17g %.17g; . %.17g] (LSB) not "
                 "positive definite", name, p00, p01, p11);
        return 1;
    }
    return 0;
}

static int observer_fails(const rfe_pipeline_q31_t *pl, const rfe_velocity_estimate_q31_t *v,
                          char *why)
{
    const rfe_fix_t sd[4] = {v->sd_vx, v->sd_vy, v->sd_beta, v->sd_yaw_acc};
    /* sd_beta = |(vx svy, vy svx)| / max(vx^2 + vy^2, v_lat_min^2) (OBSERVER.md §5) is 0 at
     * a standstill (vx = vy = 0) and may round to 0 just off it: positive is asserted only
     * where beta is estimated (vx >= v_lat_min), non-negative everywhere */
    const int beta_on = (v->vx >= pl->velocity.p.v_lat_min);
    int k;
    if (v->status != RFE_OK) {
        snprintf(why, INV_WHY, "q31 observer status %d in an accepted step", (int)v->status);
        return 1;
    }
    for (k = 0; k < 4; ++k) {
        if (!(sd[k] > 0) && !((k == 2) && !beta_on && (sd[k] == 0))) {
            snprintf(why, INV_WHY, "q31 observer sd %d = %ld LSB: not positive", k, (long)sd[k]);
            return 1;
        }
    }
    return kf2_fails(&pl->velocity.yaw, "yaw", why) || kf2_fails(&pl->velocity.lon, "lon", why) ||
           kf2_fails(&pl->velocity.lat, "lat", why);
}

/* The friction part of one step's output into the summary (as soak_run_q31.c does). */
static void count_friction(const rfe_params_q31_t *q, const rfe_sensor_row_t *row, int has_truth,
                           const rfe_estimate_q31_t *out, soak_result_t *res, double *sq,
                           long *n_cons)
{
    int w;
    for (w = 0; w < 4; ++w) {
        const double mu = rfe_fix_to_double(out->mu[w], RFE_FIX_Q_MU);
        const double sd = rfe_fix_to_double(out->sd[w], RFE_FIX_Q_SD);
        res->at_bound += (out->mu[w] == q->filter.mu_min || out->mu[w] == q->filter.mu_max);
        res->mu_lo = fmin(res->mu_lo, mu);
        res->mu_hi = fmax(res->mu_hi, mu);
        res->sd_lo = fmin(res->sd_lo, sd);
        res->sd_hi = fmax(res->sd_hi, sd);
        if (out->valid[w] && has_truth) {
            const double e = fabs(mu - row->mu_true[w]);
            ++res->n_valid;
            *sq += e * e;
            res->max_err_valid = fmax(res->max_err_valid, e);
            *n_cons += (e <= 2.0 * sd);
        }
    }
}

int soak_run_pipeline_q31(const rfe_sensor_log_t *log, const char *log_name,
                          const soak_cfg_t *cfg, soak_result_t *res)
{
    static rfe_pipeline_q31_t pl, before;
    rfe_params_q31_t q;
    rfe_velocity_params_q31_t vq;
    rfe_pipeline_out_q31_t out;
    double sq = 0.0, sq_vx = 0.0, sq_vy = 0.0;
    long n_cons = 0, n_v = 0, cons_vx = 0, cons_vy = 0, far_vx = 0;
    double v_min;
    size_t i;
    clock_t c0;
    memset(res, 0, sizeof(*res));
    res->first_violation_step = -1;
    res->mu_lo = res->sd_lo = INFINITY;
    res->mu_hi = res->sd_hi = -INFINITY;
    memset(&pl, 0, sizeof(pl)); /* padding included: a refused row is compared with memcmp */
    if (params_for(log, log_name, &q, &vq) != 0 || rfe_pipeline_init_q31(&pl, &q, &vq) != RFE_OK) {
        fprintf(stderr, "soak: q31 %s: pipeline init failed\n", cfg->name);
        return -1;
    }
    v_min = rfe_fix_to_double(vq.v_lat_min, RFE_FIX_Q_SPEED);
    c0 = clock();
    for (i = 0; i < log->n_rows; ++i) {
        const rfe_sensor_row_t *row = &log->rows[i];
        rfe_velocity_input_q31_t in;
        rfe_status_t st;
        char why[INV_WHY];
        int bad = 0;
        if (rfe_replay_esc_input_q31(log, i, i - 1u, &in) != 0u) {
            ++res->input_sat_rows;
        }
        memcpy(&before, &pl, sizeof(pl));
        st = rfe_pipeline_step_q31(&pl, &in, &out);
        ++res->steps;
        ++res->status[(st >= 0 && st < SOAK_STATUS_SLOTS) ? st : SOAK_STATUS_SLOTS - 1];
        if (rfe_status_is_error(st)) {
            ++res->failed_valid;
            snprintf(why, sizeof(why), "q31 status %d (%s)%s", (int)st, rfe_status_str(st),
                     memcmp(&pl, &before, sizeof(pl)) != 0 ? " and the pipeline changed" : "");
            bad = 1;
        }
        if (!bad && (inv_check_step_q31(&pl.friction, &out.friction, st, why) ||
                     observer_fails(&pl, &out.velocity, why))) {
            bad = 1;
        }
        if (bad && res->violations++ == 0) {
            res->first_violation_step = (long)i;
            snprintf(res->first_violation, sizeof(res->first_violation), "t = %.2f s: %s", row->t,
                     why);
        }
        res->projected += (st == RFE_PROJECTED);
        if (!rfe_status_is_error(st) && (out.velocity.sat + out.friction.sat) != 0u) {
            const unsigned long s = (unsigned long)out.velocity.sat + out.friction.sat;
            ++res->sat_steps;
            res->sat_total += s;
            res->sat_max = s > res->sat_max ? s : res->sat_max;
        }
        count_friction(&q, row, log->has_truth, &out.friction, res, &sq, &n_cons);
        if (!rfe_status_is_error(st) && row->vx >= v_min) {
            const double ex = fabs(rfe_fix_to_double(out.velocity.vx, RFE_FIX_Q_SPEED) - row->vx);
            const double ey = fabs(rfe_fix_to_double(out.velocity.vy, RFE_FIX_Q_SPEED) - row->vy);
            ++n_v;
            sq_vx += ex * ex;
            sq_vy += ey * ey;
            res->obs_max_err_vx = fmax(res->obs_max_err_vx, ex);
            res->obs_max_err_vy = fmax(res->obs_max_err_vy, ey);
            cons_vx += (ex <= 2.0 * rfe_fix_to_double(out.velocity.sd_vx, RFE_FIX_Q_SPEED));
            far_vx += (ex > 1.0);
            cons_vy += (ey <= 2.0 * rfe_fix_to_double(out.velocity.sd_vy, RFE_FIX_Q_SPEED));
        }
    }
    res->us_per_step = 1e6 * (double)(clock() - c0) / CLOCKS_PER_SEC / (double)(res->steps ? res->steps : 1);
    if (res->n_valid > 0) {
        res->rmse_valid = sqrt(sq / (double)res->n_valid);
        res->consistent_valid = (double)n_cons / (double)res->n_valid;
    }
    if (n_v > 0) {
        res->obs_steps = n_v;
        res->obs_rmse_vx = sqrt(sq_vx / (double)n_v);
        res->obs_rmse_vy = sqrt(sq_vy / (double)n_v);
        res->obs_cons_vx = (double)cons_vx / (double)n_v;
        res->obs_far_vx = (double)far_vx / (double)n_v;
        res->obs_cons_vy = (double)cons_vy / (double)n_v;
    }
    return 0;
}
