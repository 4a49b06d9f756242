/**
 * @file soak_run_q31.c
 * @brief One soak run of the fixed-point estimator (rfe_friction_*_q31): parameters from the
 *        library preset and the log's metadata, and every row in the Q formats of
 *        rfe_sample_q31_t, both by mu_replay --real q31's own conversions
 *        (rfe_replay_params_q31, rfe_replay_sample_q31: replay_q31.c), stepped and
 *        checked (invariants.h, the q31 block), saturations counted. A double translation
 *        unit (the parameter path is the double library's).
 */
#if !defined(RFE_REAL_DOUBLE)
#define RFE_REAL_DOUBLE 1
#endif
#define INV_Q31 1

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "invariants.h"
#include "param_file.h"
#include "replay_q31.h"
#include "replay_real.h"
#include "rfe/friction_q31.h"
#include "host/fixed_conv.h"
#include "soak.h"

static int params_for(const rfe_sensor_log_t *log, const char *name, const soak_cfg_t *cfg,
                      rfe_params_q31_t *q)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(q, 0, sizeof(*q)); /* padding included: rejected rows are compared with memcmp */
    if (rfe_param_set_preset_f64(&ps, cfg->preset_default ? RFE_PRESET_DEFAULT : RFE_PRESET_PAPER) != 0) {
        return -1;
    }
    if (rfe_param_set_apply_meta(&ps, log, name, &err) != 0) {
        fprintf(stderr, "soak: %s: %s\n", name, err.msg);
        return -1;
    }
    ps.filter = cfg->ckf ? RFE_FILTER_CKF : RFE_FILTER_SCKF;
    /* mu_replay --real q31's own conversion (replay_q31.c) */
    return rfe_replay_params_q31(&ps, q, NULL) == RFE_OK ? 0 : -1;
}

/* The row's class by the config.h limits, in double: 0 when a value is beyond its limit
 * (+-Inf included: it saturates to the format's end, beyond the limit, and the q31 step
 * reports RFE_ERR_RANGE). A NaN converts to 0 (counted as a saturation of the conversion),
 * so it does not make a row out of limits here. */
static int row_in_limits(const rfe_sensor_row_t *row)
{
    const double v[11] = {row->delta, row->vx, row->vy, row->yaw_rate, row->yaw_acc, row->ax,
                          row->ay, row->omega[0], row->omega[1], row->omega[2], row->omega[3]};
    const double lim[11] = {RFE_LIMIT_DELTA, RFE_LIMIT_VX, RFE_LIMIT_VY, RFE_LIMIT_YAW_RATE,
                            RFE_LIMIT_YAW_ACC, RFE_LIMIT_ACC, RFE_LIMIT_ACC, RFE_LIMIT_OMEGA,
                            RFE_LIMIT_OMEGA, RFE_LIMIT_OMEGA, RFE_LIMIT_OMEGA};
    int k;
    for (k = 0; k < 11; ++k) {
        if (!isnan(v[k]) && fabs(v[k]) > lim[k]) {
            return 0;
        }
    }
    return 1;
}

int soak_run_q31(const rfe_sensor_log_t *log, const char *log_name, const soak_cfg_t *cfg,
                 soak_result_t *res)
{
    static rfe_friction_q31_t est, before;
    rfe_params_q31_t q;
    rfe_estimate_q31_t out;
    double sq = 0.0;
    long n_cons = 0;
    size_t i;
    clock_t c0;
    memset(res, 0, sizeof(*res));
    res->first_violation_step = -1;
    res->mu_lo = res->sd_lo = INFINITY;
    res->mu_hi = res->sd_hi = -INFINITY;
    if (params_for(log, log_name, cfg, &q) != 0 || rfe_friction_init_q31(&est, &q) != RFE_OK) {
        fprintf(stderr, "soak: q31 %s: init failed\n", cfg->name);
        return -1;
    }
    c0 = clock();
    for (i = 0; i < log->n_rows; ++i) {
        const rfe_sensor_row_t *row = &log->rows[i];
        rfe_sample_q31_t u;
        rfe_status_t st;
        char why[INV_WHY];
        const int in_limits = row_in_limits(row);
        int w, bad = 0;
        if (rfe_replay_sample_q31(row, &u) != 0u) {
            ++res->input_sat_rows;
        }
        if (!in_limits) {
            memcpy(&before, &est, sizeof(est));
        }
        st = rfe_friction_step_q31(&est, &u, &out);
        ++res->steps;
        ++res->status[(st >= 0 && st < SOAK_STATUS_SLOTS) ? st : SOAK_STATUS_SLOTS - 1];
        if (!in_limits) {
            ++res->rejected;
            if (st != RFE_ERR_RANGE || memcmp(&est, &before, sizeof(est)) != 0) {
                snprintf(why, sizeof(why), "q31 out-of-limits row: status %d or state changed",
                         (int)st);
                bad = 1;
            }
        } else if (rfe_status_is_error(st)) {
            ++res->failed_valid;
            snprintf(why, sizeof(why), "q31: a row inside the limits failed with status %d (%s)",
                     (int)st, rfe_status_str(st));
            bad = 1;
        }
        if (!bad && inv_check_step_q31(&est, &out, st, why)) {
            bad = 1;
        }
        if (bad && res->violations++ == 0) {
            res->first_violation_step = (long)i;
            snprintf(res->first_violation, sizeof(res->first_violation), "t = %.2f s: %s", row->t,
                     why);
        }
        res->projected += (st == RFE_PROJECTED);
        if (out.sat != 0u) {
            ++res->sat_steps;
            res->sat_total += out.sat;
            res->sat_max = out.sat > res->sat_max ? out.sat : res->sat_max;
        }
        for (w = 0; w < 4; ++w) {
            const double mu = rfe_fix_to_double(out.mu[w], RFE_FIX_Q_MU);
            const double sd = rfe_fix_to_double(out.sd[w], RFE_FIX_Q_SD);
            res->at_bound += (out.mu[w] == q.filter.mu_min || out.mu[w] == q.filter.mu_max);
            res->sd_over_cap += (q.filter.sd_max > 0 &&
                                 sd > 1.00001 * rfe_fix_to_double(q.filter.sd_max, RFE_FIX_Q_SD));
            res->mu_lo = fmin(res->mu_lo, mu);
            res->mu_hi = fmax(res->mu_hi, mu);
            res->sd_lo = fmin(res->sd_lo, sd);
            res->sd_hi = fmax(res->sd_hi, sd);
            if (out.valid[w] && log->has_truth) {
                const double e = fabs(mu - row->mu_true[w]);
                ++res->n_valid;
                sq += e * e;
                res->max_err_valid = fmax(res->max_err_valid, e);
                n_cons += (e <= 2.0 * sd);
            }
        }
    }
    res->us_per_step = 1e6 * (double)(clock() - c0) / CLOCKS_PER_SEC / (double)(res->steps ? res->steps : 1);
    if (res->n_valid > 0) {
        res->rmse_valid = sqrt(sq / (double)res->n_valid);
        res->consistent_valid = (double)n_cons / (double)res->n_valid;
    }
    return 0;
}
