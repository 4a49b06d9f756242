/**
 * @file fuzz_step_flt.c
 * @brief libFuzzer harness: raw bytes -> configuration + a sequence of samples
 *        (fuzz_input.h) -> rfe_friction_step of the float build (or the double build with
 *        -DRFE_REAL_DOUBLE), with every invariant checked after every step; a violation
 *        prints one line and aborts (libFuzzer keeps the input as a crash artifact).
 *
 * Checked after each step:
 *  - the sample's class by the config.h limits (NaN/Inf -> RFE_ERR_NONFINITE, else out of
 *    limits -> RFE_ERR_RANGE) is exactly the status returned, and then the whole
 *    rfe_friction_t is bit-identical to before and the output is the previous estimate
 *    with valid = 0;
 *  - a sample inside the limits never gets an input error; an internal error (allowed for
 *    the CKF only: RFE_ERR_NOT_POSITIVE_DEFINITE, or RFE_ERR_NONFINITE from an overflow)
 *    leaves mean, covariance and input filter as they were; the SCKF must not fail at all
 *    on such a sample;
 *  - the invariants of test/support/invariants.h (S lower-triangular with positive
 *    diagonal, or P symmetric positive definite; x and mu in [mu_min, mu_max]; outputs
 *    finite; sd > 0; valid in {0, 1}).
 * And after each gap (rfe_friction_skip, fuzz_input.h op 1): 0 periods change nothing; else
 * the mean held bit for bit, the input filter restarted, the invariants above; a failure
 * only as RFE_ERR_NONFINITE with the filter restored.
 * Run: build/fuzz/fuzz_step_f32 [corpus dirs] (make fuzz / make fuzz-smoke).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "fuzz_real.h"
#include "invariants.h"
#include "rfe/friction.h"

typedef struct {
    rfe_friction_t est;
    rfe_friction_t before;
    rfe_estimate_t prev;
    long k;
} fz_ctx_t;

static void violation(const fz_ctx_t *c, const char *what, const rfe_sample_t *u, int st)
{
    fprintf(stderr,
            "fuzz_step (%s): step %ld: %s (status %d)\n  sample: delta %.9g vx %.9g vy %.9g "
            "r %.9g rdot %.9g ax %.9g ay %.9g omega %.9g %.9g %.9g %.9g\n",
            FZ_BUILD, c->k, what, st, (double)u->delta, (double)u->vx, (double)u->vy,
            (double)u->yaw_rate, (double)u->yaw_acc, (double)u->ax, (double)u->ay,
            (double)u->omega[0], (double)u->omega[1], (double)u->omega[2], (double)u->omega[3]);
    abort();
}

static int step(void *ctxp, const fz_sample_t *s)
{
    fz_ctx_t *c = (fz_ctx_t *)ctxp;
    rfe_sample_t u;
    rfe_estimate_t out;
    rfe_status_t st, want;
    char why[INV_WHY];
    int w;
    u.delta = fz_to_real(s->v[0]);
    u.vx = fz_to_real(s->v[1]);
    u.vy = fz_to_real(s->v[2]);
    u.yaw_rate = fz_to_real(s->v[3]);
    u.yaw_acc = fz_to_real(s->v[4]);
    u.ax = fz_to_real(s->v[5]);
    u.ay = fz_to_real(s->v[6]);
    for (w = 0; w < 4; ++w) {
        u.omega[w] = fz_to_real(s->v[7 + w]);
    }
    want = inv_classify_sample(&u);
    memcpy(&c->before, &c->est, sizeof c->est);
    st = rfe_friction_step(&c->est, &u, &out);
    if (want != RFE_OK) {
        if (st != want) {
            violation(c, "input error not reported as its class", &u, (int)st);
        }
        if (memcmp(&c->est, &c->before, sizeof c->est) != 0) {
            violation(c, "a rejected sample changed the estimator", &u, (int)st);
        }
        if (memcmp(out.mu, c->prev.mu, sizeof out.mu) != 0 ||
            memcmp(out.sd, c->prev.sd, sizeof out.sd) != 0) {
            violation(c, "a rejected sample did not report the previous estimate", &u, (int)st);
        }
    } else if (rfe_status_is_error(st)) {
        if (c->est.params.filter.kind != RFE_FILTER_CKF) {
            violation(c, "the SCKF failed on a sample inside the limits", &u, (int)st);
        }
        if (st != RFE_ERR_NOT_POSITIVE_DEFINITE && st != RFE_ERR_NONFINITE) {
            violation(c, "the CKF failed with an unexpected status", &u, (int)st);
        }
        if (!inv_filter_equal(&c->est, &c->before)) {
            violation(c, "a failed step did not restore the filter", &u, (int)st);
        }
    }
    if (inv_check_step(&c->est, &out, st, why)) {
        violation(c, why, &u, (int)st);
    }
    if (!rfe_status_is_error(st)) {
        c->prev = out;
    }
    ++c->k;
    return 0;
}

static void gap_violation(const fz_ctx_t *c, const char *what, uint32_t missed, int st)
{
    fprintf(stderr, "fuzz_step (%s): after step %ld: a gap of %u periods: %s (status %d)\n",
            FZ_BUILD, c->k, (unsigned)missed, what, st);
    abort();
}

static int gap(void *ctxp, uint32_t missed)
{
    fz_ctx_t *c = (fz_ctx_t *)ctxp;
    rfe_estimate_t out;
    rfe_status_t st;
    char why[INV_WHY];
    const int ckf = (c->est.params.filter.kind == RFE_FILTER_CKF);
    memcpy(&c->before, &c->est, sizeof c->est);
    st = rfe_friction_skip(&c->est, missed);
    if (st != RFE_OK) {
        if (st != RFE_ERR_NONFINITE || !inv_filter_equal(&c->est, &c->before)) {
            gap_violation(c, "failed, or failed without restoring the filter", missed, (int)st);
        }
    } else if (missed == 0u) {
        if (memcmp(&c->est, &c->before, sizeof c->est) != 0) {
            gap_violation(c, "0 periods changed the estimator", missed, (int)st);
        }
    } else if (memcmp(ckf ? c->est.filter.ckf.x : c->est.filter.sckf.x,
                      ckf ? c->before.filter.ckf.x : c->before.filter.sckf.x,
                      sizeof c->est.filter.sckf.x) != 0 ||
               c->est.cond.started != 0u) {
        gap_violation(c, "the mean moved or the input filter was not restarted", missed, (int)st);
    }
    if (rfe_friction_get(&c->est, &out) != RFE_OK) {
        gap_violation(c, "get failed", missed, (int)st);
    }
    if (inv_check_step(&c->est, &out, RFE_OK, why)) {
        gap_violation(c, why, missed, (int)st);
    }
    c->prev = out; /* what a rejected sample now reports */
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fz_ctx_t c;
    fz_reader_t r;
    fz_config_t cfg;
    rfe_params_t p;
    r.p = data;
    r.n = size;
    memset(&p, 0, sizeof p); /* padding included: the harness compares whole estimators */
    cfg = fz_config(&r);
    if ((cfg.preset_default ? rfe_params_default(&p) : rfe_params_paper(&p)) !=
        RFE_OK) {
        abort();
    }
    if (cfg.ckf && !cfg.preset_default) {
        p.filter.kind = RFE_FILTER_CKF;
    }
    if (cfg.ckf && cfg.preset_default) {
        p.monitor.enable = (rfe_real_t)0.0; /* the preset has the monitor on: here off */
    }
    if (cfg.toggle_tyre) {
        p.tyre.mode = (p.tyre.mode == RFE_TYRE_PAPER) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_PAPER;
    }
    if (cfg.mu0_choice == 1) {
        p.filter.mu0 = p.filter.mu_min;
    } else if (cfg.mu0_choice == 2) {
        p.filter.mu0 = p.filter.mu_max;
    } else if (cfg.mu0_choice == 3) {
        p.filter.mu0 = (rfe_real_t)0.3;
    }
    memset(&c, 0, sizeof c);
    if (rfe_friction_init(&c.est, &p) != RFE_OK ||
        rfe_friction_get(&c.est, &c.prev) != RFE_OK) {
        fprintf(stderr, "fuzz_step: init failed for a preset\n");
        abort();
    }
    (void)fz_run_gaps(&r, step, gap, &c);
    return 0;
}
