/**
 * @file fuzz_step_q31.c
 * @brief libFuzzer harness of the fixed-point estimator: the same inputs as fuzz_step_flt.c
 *        (fuzz_input.h: configuration byte and samples in double), each sample rounded to the
 *        Q formats of rfe_sample_q31_t (rfe_fix_from_double: a value beyond its format
 *        saturates to the format's end; a NaN becomes 0, the one value a Q format cannot
 *        carry), then rfe_friction_step_q31 and every invariant after every step
 *        (invariants.h, the q31 block); a violation prints one line and aborts.
 *
 * Checked after each step:
 *  - a sample with a Q value beyond its RFE_FIX_LIMIT_* gets exactly RFE_ERR_RANGE, the whole
 *    rfe_friction_q31_t is bit-identical afterwards and the output is the previous estimate
 *    with valid 0 and sat 0;
 *  - a sample inside the limits never gets an input error; an internal error (allowed for the
 *    CKF only: RFE_ERR_NOT_POSITIVE_DEFINITE) leaves mean, factor or covariance, input filter
 *    and saturation counter as they were; the SCKF must not fail at all;
 *  - the invariants: x and mu in [mu_min, mu_max] (exact integers), S lower-triangular with a
 *    positive diagonal or P symmetric positive definite, sd > 0, valid in {0, 1}.
 * Saturations inside the estimator are not violations (they are counted and reported by the
 * estimate), but a step with saturations is printed once per run when FUZZ_Q31_SHOW_SAT is set.
 * Parameters: the double presets converted by rfe_params_to_q31_f64 (as mu_replay --real q31).
 */
#if !defined(RFE_REAL_DOUBLE)
#define RFE_REAL_DOUBLE 1
#endif
#define INV_Q31 1

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "invariants.h"
#include "rfe/friction_q31.h"
#include "host/fixed_conv.h"
#include "rfe/component/params_conv.h"

typedef struct {
    rfe_friction_q31_t est;
    rfe_friction_q31_t before;
    rfe_estimate_q31_t prev;
    long k;
} fz_ctx_q31_t;

static void violation(const fz_ctx_q31_t *c, const char *what, const rfe_sample_q31_t *u, int st)
{
    fprintf(stderr,
            "fuzz_step (q31): step %ld: %s (status %d)\n  sample (Q): delta %d vx %d vy %d "
            "r %d rdot %d ax %d ay %d omega %d %d %d %d\n",
            c->k, what, st, (int)u->delta, (int)u->vx, (int)u->vy, (int)u->yaw_rate,
            (int)u->yaw_acc, (int)u->ax, (int)u->ay, (int)u->omega[0], (int)u->omega[1],
            (int)u->omega[2], (int)u->omega[3]);
    abort();
}

static int beyond(rfe_fix_t v, rfe_fix_t lim) { return (v > lim) || (v < -lim); }

static int filter_equal(const rfe_friction_q31_t *a, const rfe_friction_q31_t *b)
{
    if (a->params.filter.kind == RFE_FILTER_CKF) {
        return memcmp(a->filter.ckf.x, b->filter.ckf.x, sizeof a->filter.ckf.x) == 0 &&
               memcmp(a->filter.ckf.P, b->filter.ckf.P, sizeof a->filter.ckf.P) == 0 &&
               memcmp(&a->cond, &b->cond, sizeof a->cond) == 0 && a->sat == b->sat;
    }
    return memcmp(a->filter.sckf.x, b->filter.sckf.x, sizeof a->filter.sckf.x) == 0 &&
           memcmp(a->filter.sckf.S, b->filter.sckf.S, sizeof a->filter.sckf.S) == 0 &&
           memcmp(&a->cond, &b->cond, sizeof a->cond) == 0 && a->sat == b->sat;
}

static int step(void *ctxp, const fz_sample_t *s)
{
    fz_ctx_q31_t *c = (fz_ctx_q31_t *)ctxp;
    rfe_sample_q31_t u;
    rfe_estimate_q31_t out;
    rfe_status_t st;
    uint32_t conv_sat = 0u;
    char why[INV_WHY];
    int w, out_of_limits;
    u.delta = rfe_fix_from_double(s->v[0], RFE_FIX_Q_ANGLE, &conv_sat);
    u.vx = rfe_fix_from_double(s->v[1], RFE_FIX_Q_SPEED, &conv_sat);
    u.vy = rfe_fix_from_double(s->v[2], RFE_FIX_Q_SPEED, &conv_sat);
    u.yaw_rate = rfe_fix_from_double(s->v[3], RFE_FIX_Q_YAWRATE, &conv_sat);
    u.yaw_acc = rfe_fix_from_double(s->v[4], RFE_FIX_Q_ACC, &conv_sat);
    u.ax = rfe_fix_from_double(s->v[5], RFE_FIX_Q_ACC, &conv_sat);
    u.ay = rfe_fix_from_double(s->v[6], RFE_FIX_Q_ACC, &conv_sat);
    for (w = 0; w < 4; ++w) {
        u.omega[w] = rfe_fix_from_double(s->v[7 + w], RFE_FIX_Q_OMEGA, &conv_sat);
    }
    out_of_limits = beyond(u.delta, RFE_FIX_LIMIT_DELTA) || beyond(u.vx, RFE_FIX_LIMIT_VX) ||
                    beyond(u.vy, RFE_FIX_LIMIT_VY) || beyond(u.yaw_rate, RFE_FIX_LIMIT_YAW_RATE) ||
                    beyond(u.yaw_acc, RFE_FIX_LIMIT_YAW_ACC) || beyond(u.ax, RFE_FIX_LIMIT_ACC) ||
                    beyond(u.ay, RFE_FIX_LIMIT_ACC);
    for (w = 0; w < 4; ++w) {
        out_of_limits = out_of_limits || beyond(u.omega[w], RFE_FIX_LIMIT_OMEGA);
    }
    memcpy(&c->before, &c->est, sizeof c->est);
    st = rfe_friction_step_q31(&c->est, &u, &out);
    if (out_of_limits) {
        if (st != RFE_ERR_RANGE) {
            violation(c, "a sample beyond the limits was not rejected with RFE_ERR_RANGE", &u,
                      (int)st);
        }
        if (memcmp(&c->est, &c->before, sizeof c->est) != 0) {
            violation(c, "a rejected sample changed the estimator", &u, (int)st);
        }
        if (memcmp(out.mu, c->prev.mu, sizeof out.mu) != 0 ||
            memcmp(out.sd, c->prev.sd, sizeof out.sd) != 0 || out.sat != 0u) {
            violation(c, "a rejected sample did not report the previous estimate", &u, (int)st);
        }
    } else if (rfe_status_is_error(st)) {
        if (c->est.params.filter.kind != RFE_FILTER_CKF) {
            violation(c, "the SCKF failed on a sample inside the limits", &u, (int)st);
        }
        if (st != RFE_ERR_NOT_POSITIVE_DEFINITE) {
            violation(c, "the CKF failed with an unexpected status", &u, (int)st);
        }
        if (!filter_equal(&c->est, &c->before)) {
            violation(c, "a failed step did not restore the filter", &u, (int)st);
        }
    }
    if (inv_check_step_q31(&c->est, &out, st, why)) {
        violation(c, why, &u, (int)st);
    }
#if defined(FUZZ_Q31_SHOW_SAT)
    if (out.sat != 0u) {
        static int shown;
        if (!shown) {
            shown = 1;
            fprintf(stderr, "fuzz_step (q31): step %ld: %u saturation(s)\n", c->k, out.sat);
        }
    }
#endif
    if (!rfe_status_is_error(st)) {
        c->prev = out;
    }
    ++c->k;
    return 0;
}

static void gap_violation(const fz_ctx_q31_t *c, const char *what, uint32_t missed, int st)
{
    fprintf(stderr, "fuzz_step (q31): after step %ld: a gap of %u periods: %s (status %d)\n",
            c->k, (unsigned)missed, what, st);
    abort();
}

/* A gap (rfe_friction_skip_q31): it cannot fail on an initialised estimator; 0 periods
 * change nothing; else the mean held bit for bit, the input filter restarted, and the
 * step's invariants on what get reports. */
static int gap(void *ctxp, uint32_t missed)
{
    fz_ctx_q31_t *c = (fz_ctx_q31_t *)ctxp;
    rfe_estimate_q31_t out;
    rfe_status_t st;
    char why[INV_WHY];
    const int ckf = (c->est.params.filter.kind == RFE_FILTER_CKF);
    memcpy(&c->before, &c->est, sizeof c->est);
    st = rfe_friction_skip_q31(&c->est, missed);
    if (st != RFE_OK) {
        gap_violation(c, "failed", missed, (int)st);
    }
    if (missed == 0u) {
        if (memcmp(&c->est, &c->before, sizeof c->est) != 0) {
            gap_violation(c, "0 periods changed the estimator", missed, (int)st);
        }
    } else if (memcmp(ckf ? c->est.filter.ckf.x : c->est.filter.sckf.x,
                      ckf ? c->before.filter.ckf.x : c->before.filter.sckf.x,
                      sizeof c->est.filter.sckf.x) != 0 ||
               c->est.cond.started != 0u) {
        gap_violation(c, "the mean moved or the input filter was not restarted", missed, (int)st);
    }
    if (rfe_friction_get_q31(&c->est, &out) != RFE_OK) {
        gap_violation(c, "get failed", missed, (int)st);
    }
    if (inv_check_step_q31(&c->est, &out, RFE_OK, why)) {
        gap_violation(c, why, missed, (int)st);
    }
    c->prev = out; /* what a rejected sample now reports */
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fz_ctx_q31_t c;
    fz_reader_t r;
    fz_config_t cfg;
    rfe_params_t p;
    rfe_params_q31_t q;
    r.p = data;
    r.n = size;
    memset(&p, 0, sizeof p);
    memset(&q, 0, sizeof q); /* padding included: the harness compares whole estimators */
    cfg = fz_config(&r);
    if ((cfg.preset_default ? rfe_params_default_f64(&p) : rfe_params_paper_f64(&p)) != RFE_OK) {
        abort();
    }
    if (cfg.ckf && !cfg.preset_default) {
        p.filter.kind = RFE_FILTER_CKF;
    }
    if (cfg.ckf && cfg.preset_default) {
        p.monitor.enable = 0.0; /* the preset has the monitor on: here off */
    }
    if (cfg.toggle_tyre) {
        p.tyre.mode = (p.tyre.mode == RFE_TYRE_PAPER) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_PAPER;
    }
    if (cfg.mu0_choice == 1) {
        p.filter.mu0 = p.filter.mu_min;
    } else if (cfg.mu0_choice == 2) {
        p.filter.mu0 = p.filter.mu_max;
    } else if (cfg.mu0_choice == 3) {
        p.filter.mu0 = 0.3;
    }
    memset(&c, 0, sizeof c);
    if (rfe_params_to_q31_f64(&p, &q) != RFE_OK || rfe_friction_init_q31(&c.est, &q) != RFE_OK ||
        rfe_friction_get_q31(&c.est, &c.prev) != RFE_OK) {
        fprintf(stderr, "fuzz_step (q31): init failed for a preset\n");
        abort();
    }
    (void)fz_run_gaps(&r, step, gap, &c);
    return 0;
}
