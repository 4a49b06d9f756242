/**
 * @file soak_run_pipeline.c
 * @brief One soak run of the composed pipeline (rfe/pipeline.h: the velocity observer, then
 *        the friction estimator on its outputs) in the number type of the build (float, or
 *        double with -DRFE_REAL_DOUBLE): parameters and ESC samples exactly as
 *        `mu_replay --velocity observer` derives them (rfe_replay_params,
 *        rfe_replay_velocity_params, rfe_replay_esc_input), every row stepped and checked.
 *
 * Invariants at every step (any break is a violation; see soak.h):
 *  - no error status: the drive stays inside every input limit and its period is the
 *    observer's (the friction soak of the same drive refuses no row either); were one
 *    returned, the pipeline must be untouched (checked too);
 *  - the friction estimator inside the pipeline: inv_check_step (invariants.h), as the
 *    friction soak checks it;
 *  - the observer: every output finite, every sd finite and positive (sd_beta where beta
 *    is estimated), the status the
 *    returned one, and each two-state filter's covariance positive definite up to rounding:
 *    p00 > 0, p11 > 0 and p01^2 <= p00 p11 (1 + KF2_PSD_ULPS eps). The filters update P in
 *    the plain form P - K H P, whose every element carries a few roundings of its largest
 *    term; 32 eps of the product bounds that with room (as invariants.h's CKF symmetry
 *    bound), while a covariance that lost definiteness misses it by far more.
 * Besides: vx and vy against the log's vx, vy columns (the simulator's, with the default
 * sensor noise) where vx >= v_lat_min, reported, not asserted (the soak asserts robustness).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "invariants.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/pipeline.h"
#include "soak.h"

#define KF2_PSD_ULPS 32.0

static int params_for(const rfe_sensor_log_t *log, const char *name, rfe_params_t *p,
                      rfe_velocity_params_t *vp)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(p, 0, sizeof(*p));
    memset(vp, 0, sizeof(*vp));
    if (rfe_param_set_preset(&ps, RFE_PRESET_DEFAULT) != 0) {
        return -1;
    }
    if (rfe_param_set_apply_meta(&ps, log, name, &err) != 0) {
        fprintf(stderr, "soak: %s: %s\n", name, err.msg);
        return -1;
    }
    return (rfe_replay_params(&ps, p, NULL) == RFE_OK &&
            rfe_replay_velocity_params(&ps, vp, NULL) == RFE_OK) ? 0 : -1;
}

static int kf2_fails(const rfe_kf2_t *f, const char *name, char *why)
{
    const double p00 = (double)f->p00, p01 = (double)f->p01, p11 = (double)f->p11;
    if (!isfinite(f->x[0]) || !isfinite(f->x[1]) || !(p00 > 0.0) || !(p11 > 0.0) ||
        !(p01 * p01 <= p00 * p11 * (1.0 + KF2_PSD_ULPS * INV_EPS))) {
        snprintf(why, INV_WHY, "observer filter %s: x = (%.9g, %.9g), P = [%.9g %.9g; . %.9g] "
                 "not finite or not positive definite", name, (double)f->x[0], (double)f->x[1],
                 p00, p01, p11);
        return 1;
    }
    return 0;
}

static int observer_fails(const rfe_pipeline_t *pl, const rfe_velocity_estimate_t *v, char *why)
{
    const double out[4] = {v->vx, v->vy, v->beta, v->yaw_acc};
    const double sd[4] = {v->sd_vx, v->sd_vy, v->sd_beta, v->sd_yaw_acc};
    /* sd_beta = |(vx svy, vy svx)| / max(vx^2 + vy^2, v_lat_min^2) (OBSERVER.md §5) is 0 at
     * a standstill (vx = vy = 0): positive is asserted only where beta is estimated
     * (vx >= v_lat_min), non-negative everywhere */
    const int beta_on = (v->vx >= pl->velocity.p.v_lat_min);
    int k;
    if (v->status != RFE_OK) {
        snprintf(why, INV_WHY, "observer status %d in an accepted step", (int)v->status);
        return 1;
    }
    for (k = 0; k < 4; ++k) {
        if (!isfinite(out[k]) || !isfinite(sd[k]) ||
            (!(sd[k] > 0.0) && !((k == 2) && !beta_on && (sd[k] == 0.0)))) {
            snprintf(why, INV_WHY, "observer output %d = %.9g, sd %.9g: not finite or sd not "
                     "positive", k, out[k], sd[k]);
            return 1;
        }
    }
    return kf2_fails(&pl->velocity.yaw, "yaw", why) || kf2_fails(&pl->velocity.lon, "lon", why) ||
           kf2_fails(&pl->velocity.lat, "lat", why);
}

int soak_run_pipeline(const rfe_sensor_log_t *log, const char *log_name, const soak_cfg_t *cfg,
                      soak_result_t *res)
{
    static rfe_pipeline_t pl, before;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_out_t out;
    double sq = 0.0, sq_vx = 0.0, sq_vy = 0.0;
    long n_cons = 0, n_v = 0, cons_vx = 0, cons_vy = 0, far_vx = 0;
    size_t i;
    clock_t c0;
    memset(res, 0, sizeof(*res));
    res->first_violation_step = -1;
    res->mu_lo = res->sd_lo = INFINITY;
    res->mu_hi = res->sd_hi = -INFINITY;
    memset(&pl, 0, sizeof(pl)); /* padding included: a refused row is compared with memcmp */
    if (params_for(log, log_name, &p, &vp) != 0 || rfe_pipeline_init(&pl, &p, &vp) != RFE_OK) {
        fprintf(stderr, "soak: %s: pipeline init failed\n", cfg->name);
        return -1;
    }
    c0 = clock();
    for (i = 0; i < log->n_rows; ++i) {
        const rfe_sensor_row_t *row = &log->rows[i];
        rfe_velocity_input_t in;
        rfe_status_t st;
        char why[INV_WHY];
        int w, bad = 0;
        rfe_replay_esc_input(log, i, i - 1u, &in); /* i = 0: SIZE_MAX, none */
        memcpy(&before, &pl, sizeof(pl));
        st = rfe_pipeline_step(&pl, &in, &out);
        ++res->steps;
        ++res->status[(st >= 0 && st < SOAK_STATUS_SLOTS) ? st : SOAK_STATUS_SLOTS - 1];
        if (rfe_status_is_error(st)) {
            ++res->failed_valid;
            snprintf(why, sizeof(why), "status %d (%s)%s", (int)st, rfe_status_str(st),
                     memcmp(&pl, &before, sizeof(pl)) != 0 ? " and the pipeline changed" : "");
            bad = 1;
        }
        if (!bad && (inv_check_step(&pl.friction, &out.friction, st, why) ||
                     observer_fails(&pl, &out.velocity, why))) {
            bad = 1;
        }
        if (bad) {
            if (res->violations++ == 0) {
                res->first_violation_step = (long)i;
                snprintf(res->first_violation, sizeof(res->first_violation), "t = %.2f s: %s",
                         row->t, why);
            }
        }
        res->projected += (st == RFE_PROJECTED);
        for (w = 0; w < 4; ++w) {
            const double mu = (double)out.friction.mu[w], sd = (double)out.friction.sd[w];
            res->at_bound += (out.friction.mu[w] == p.filter.mu_min || out.friction.mu[w] == p.filter.mu_max);
            res->sd_over_cap += (p.filter.sd_max > 0 && sd > 1.00001 * (double)p.filter.sd_max);
            res->mu_lo = fmin(res->mu_lo, mu);
            res->mu_hi = fmax(res->mu_hi, mu);
            res->sd_lo = fmin(res->sd_lo, sd);
            res->sd_hi = fmax(res->sd_hi, sd);
            if (out.friction.valid[w] && log->has_truth) {
                const double e = fabs(mu - row->mu_true[w]);
                ++res->n_valid;
                sq += e * e;
                res->max_err_valid = fmax(res->max_err_valid, e);
                n_cons += (e <= 2.0 * sd);
            }
        }
        if (!rfe_status_is_error(st) && row->vx >= (double)vp.v_lat_min) {
            const double ex = fabs((double)out.velocity.vx - row->vx);
            const double ey = fabs((double)out.velocity.vy - row->vy);
            ++n_v;
            sq_vx += ex * ex;
            sq_vy += ey * ey;
            res->obs_max_err_vx = fmax(res->obs_max_err_vx, ex);
            res->obs_max_err_vy = fmax(res->obs_max_err_vy, ey);
            cons_vx += (ex <= 2.0 * (double)out.velocity.sd_vx);
            far_vx += (ex > 1.0); /* the figure ROBUSTNESS.md quotes for the lock-out */
            cons_vy += (ey <= 2.0 * (double)out.velocity.sd_vy);
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
