/**
 * @file soak_run.c
 * @brief One soak run in the number type of the build (float, or double with
 *        -DRFE_REAL_DOUBLE): parameters from the library preset and the log's metadata (as
 *        mu_replay), then every row stepped and checked (see soak.h, invariants.h).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "invariants.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/friction.h"
#include "soak.h"

int soak_params_of(const rfe_sensor_log_t *log, const char *name, rfe_preset_t preset,
                   rfe_params_t *p)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(p, 0, sizeof(*p)); /* padding included: rejected rows are compared with memcmp */
    if (rfe_param_set_preset(&ps, preset) != 0 || rfe_replay_preset_fn(preset)(p) != RFE_OK) {
        return -1;
    }
    if (rfe_param_set_apply_meta(&ps, log, name, &err) != 0) {
        fprintf(stderr, "soak: %s: %s\n", name, err.msg);
        return -1;
    }
#define RFE_SET_(key, member, unit, doc) p->member = (rfe_real_t)ps.value[RFE_PK_##key];
    RFE_PARAM_KEYS(RFE_SET_)
#undef RFE_SET_
    p->tyre.mode = ps.tyre;
    p->filter.structure = ps.structure;
    return 0;
}

static int params_for(const rfe_sensor_log_t *log, const char *name, const soak_cfg_t *cfg,
                      rfe_params_t *p)
{
    const rfe_preset_t preset = cfg->preset_default ? RFE_PRESET_DEFAULT : RFE_PRESET_PAPER;
    if (soak_params_of(log, name, preset, p) != 0) {
        return -1;
    }
    p->filter.kind = cfg->ckf ? RFE_FILTER_CKF : RFE_FILTER_SCKF;
    return 0;
}

int soak_run(const rfe_sensor_log_t *log, const char *log_name, const soak_cfg_t *cfg,
             soak_result_t *res)
{
    static rfe_friction_t est, before;
    rfe_params_t p;
    rfe_estimate_t out;
    double sq = 0.0;
    long n_cons = 0;
    size_t i;
    clock_t c0;
    memset(res, 0, sizeof(*res));
    res->first_violation_step = -1;
    res->mu_lo = res->sd_lo = INFINITY;
    res->mu_hi = res->sd_hi = -INFINITY;
    if (params_for(log, log_name, cfg, &p) != 0 || rfe_friction_init(&est, &p) != RFE_OK) {
        fprintf(stderr, "soak: %s: init failed\n", cfg->name);
        return -1;
    }
    c0 = clock();
    for (i = 0; i < log->n_rows; ++i) {
        const rfe_sensor_row_t *row = &log->rows[i];
        rfe_sample_t u;
        rfe_status_t st, want;
        char why[INV_WHY];
        int w, bad = 0;
        rfe_replay_sample_from_row(row, &u);
        want = inv_classify_sample(&u);
        if (want != RFE_OK) {
            memcpy(&before, &est, sizeof(est));
        }
        st = rfe_friction_step(&est, &u, &out);
        ++res->steps;
        ++res->status[(st >= 0 && st < SOAK_STATUS_SLOTS) ? st : SOAK_STATUS_SLOTS - 1];
        if (want != RFE_OK) {
            ++res->rejected;
            if (st != want || memcmp(&est, &before, sizeof(est)) != 0) {
                snprintf(why, sizeof(why), "out-of-limits row: status %d (want %d) or state changed",
                         (int)st, (int)want);
                bad = 1;
            }
        } else if (rfe_status_is_error(st)) {
            ++res->failed_valid;
            snprintf(why, sizeof(why), "a row inside the limits failed with status %d (%s)",
                     (int)st, rfe_status_str(st));
            bad = 1;
        }
        if (!bad && inv_check_step(&est, &out, st, why)) {
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
            const double mu = (double)out.mu[w], sd = (double)out.sd[w];
            res->at_bound += (out.mu[w] == p.filter.mu_min || out.mu[w] == p.filter.mu_max);
            /* beyond the rounding of the cap (S <- (sd_max / sd) S lands within ulps) */
            res->sd_over_cap += (p.filter.sd_max > 0 && sd > 1.00001 * (double)p.filter.sd_max);
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
