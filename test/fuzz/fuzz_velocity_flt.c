/**
 * @file fuzz_velocity_flt.c
 * @brief libFuzzer harness: raw bytes -> configuration + a sequence of ESC samples
 *        (fuzz_input.h's decoding, the fields mapped below) -> rfe_velocity_step of the
 *        float build (or the double build with -DRFE_REAL_DOUBLE), every invariant checked
 *        after every step; a violation prints one line and aborts.
 *
 * The 11 decoded values become an ESC sample (each scaled so that the decoder's limit is
 * the observer's limit or just past it): delta; dt = 0.001 * v1 (the decoder's nominal
 * 20 -> 0.02 s, its limit 100 -> 0.1 s = obs_dt_max); grade = 0.012 * v2 (limit 0.6 rad);
 * yaw rate; steering-wheel angle = 0.16 * v4 (limit 16 rad = delta's limit at the default
 * ratio 16); ax; ay; omega fl..rr. Configuration byte: bit 0 all-wheel drive (else front),
 * bit 1 the steering-wheel angle instead of delta, bit 2 a Magic Formula tyre (else the
 * preset's), bits 3-4 the friction input: none, 0.2 (sd 0.02), 1.0 (sd 0.3), 2.5 (beyond
 * the documented 0..2: every step must be RFE_ERR_RANGE).
 *
 * Checked after each step, against the rules of rfe/velocity.h written out here:
 *  - a non-finite input gives RFE_ERR_NONFINITE; else an input beyond config.h's limits, a
 *    friction beyond [0, 2], or (after the first accepted sample) dt outside [dt_min,
 *    dt_max] gives RFE_ERR_RANGE; else RFE_OK, never an error;
 *  - on an error the observer is bit-identical to before and the output is the previous
 *    estimate with that status;
 *  - on RFE_OK every output is finite, every sd >= 0, vx >= 0, |beta| <= pi, no unknown flag.
 * Run: build/fuzz/fuzz_velocity_f32 [corpus dirs] (make fuzz / make fuzz-smoke).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "fuzz_real.h"
#include "rfe/velocity.h"

/** Every flag the observer may set (rfe/velocity.h). */
#define KNOWN_FLAGS                                                                        \
    (RFE_VEL_FLAG_VX_WHEEL | RFE_VEL_FLAG_BRAKING | RFE_VEL_FLAG_DRIVING |                 \
     RFE_VEL_FLAG_VY_MODEL | RFE_VEL_FLAG_VY_LOWSPEED | RFE_VEL_FLAG_MU_RAISED | \
     RFE_VEL_FLAG_VY_LINEAR)

typedef struct {
    rfe_velocity_t obs;
    rfe_velocity_t before;
    rfe_velocity_estimate_t prev;
    rfe_velocity_mu_t mu;
    const rfe_velocity_mu_t *mu_in; /**< NULL: no friction input */
    int steer_wheel;
    int started;
    long k;
} fz_ctx_t;

static void violation(const fz_ctx_t *c, const char *what, const rfe_velocity_input_t *u,
                      int st)
{
    fprintf(stderr,
            "fuzz_velocity (%s): step %ld: %s (status %d)\n  sample: dt %.9g delta %.9g sw %.9g "
            "r %.9g ax %.9g ay %.9g grade %.9g omega %.9g %.9g %.9g %.9g\n",
            FZ_BUILD, c->k, what, st, (double)u->dt, (double)u->delta, (double)u->steer_wheel,
            (double)u->yaw_rate, (double)u->ax, (double)u->ay, (double)u->grade,
            (double)u->omega[0], (double)u->omega[1], (double)u->omega[2], (double)u->omega[3]);
    abort();
}

/* The status rfe/velocity.h promises for this sample (the road-wheel angle already taken
 * from the steering wheel when that is what the sample gives). */
static rfe_status_t expected(const fz_ctx_t *c, const rfe_velocity_input_t *u, rfe_real_t delta)
{
    const rfe_real_t v[7] = {u->dt, u->delta, u->steer_wheel, u->yaw_rate, u->ax, u->ay,
                             u->grade};
    const rfe_velocity_params_t *p = &c->obs.p;
    int i;
    for (i = 0; i < 7; ++i) {
        if (!finite(v[i])) {
            return RFE_ERR_NONFINITE;
        }
    }
    for (i = 0; i < 4; ++i) {
        if (!finite(u->omega[i]) || (c->mu_in && (!finite(c->mu_in->mu[i]) ||
                                                  !finite(c->mu_in->sd[i])))) {
            return RFE_ERR_NONFINITE;
        }
    }
    if (!finite(delta)) {
        return RFE_ERR_RANGE; /* a finite steering-wheel angle that overflows the division */
    }
    /* the limits compared in the build's number type, as the library does */
    if (beyond(delta, RFE_LIMIT_DELTA) || beyond(u->yaw_rate, RFE_LIMIT_YAW_RATE) ||
        beyond(u->ax, RFE_LIMIT_ACC) || beyond(u->ay, RFE_LIMIT_ACC) ||
        beyond(u->grade, RFE_LIMIT_GRADE)) {
        return RFE_ERR_RANGE;
    }
    for (i = 0; i < 4; ++i) {
        if (beyond(u->omega[i], RFE_LIMIT_OMEGA) ||
            (c->mu_in && (c->mu_in->mu[i] < 0 || c->mu_in->mu[i] > 2 || c->mu_in->sd[i] < 0))) {
            return RFE_ERR_RANGE;
        }
    }
    if (c->started && (u->dt < p->dt_min || u->dt > p->dt_max)) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

static void check_output(const fz_ctx_t *c, const rfe_velocity_input_t *u,
                         const rfe_velocity_estimate_t *e, int st)
{
    const rfe_real_t v[12] = {e->vx,    e->vy,    e->beta,  e->yaw_acc, e->delta,   e->sd_vx,
                              e->sd_vy, e->sd_beta, e->sd_yaw_acc, e->bx,   e->by,      e->vx};
    int i;
    for (i = 0; i < 12; ++i) {
        if (!finite(v[i])) {
            violation(c, "a non-finite output", u, st);
        }
    }
    if (e->sd_vx < 0 || e->sd_vy < 0 || e->sd_beta < 0 || e->sd_yaw_acc < 0) {
        violation(c, "a negative sd", u, st);
    }
    if (e->vx < 0) {
        violation(c, "vx below 0", u, st);
    }
    if (fabs((double)e->beta) > 3.14159266) {
        violation(c, "|beta| beyond pi", u, st);
    }
    if ((e->flags & ~(uint32_t)KNOWN_FLAGS) != 0u) {
        violation(c, "an unknown flag", u, st);
    }
}

static int step(void *ctxp, const fz_sample_t *s)
{
    fz_ctx_t *c = (fz_ctx_t *)ctxp;
    rfe_velocity_input_t u;
    rfe_velocity_estimate_t out;
    rfe_status_t st;
    rfe_status_t want;
    rfe_real_t delta;
    int w;
    memset(&u, 0, sizeof u);
    u.delta = fz_to_real(s->v[0]);
    u.dt = fz_to_real(0.001 * s->v[1]);
    u.grade = fz_to_real(0.012 * s->v[2]);
    u.yaw_rate = fz_to_real(s->v[3]);
    u.steer_wheel = fz_to_real(0.16 * s->v[4]);
    u.ax = fz_to_real(s->v[5]);
    u.ay = fz_to_real(s->v[6]);
    for (w = 0; w < 4; ++w) {
        u.omega[w] = fz_to_real(s->v[7 + w]);
    }
    u.has = c->steer_wheel ? RFE_VEL_HAS_STEER_WHEEL : 0u;
    delta = c->steer_wheel ? u.steer_wheel / c->obs.p.steer_ratio : u.delta;
    want = expected(c, &u, delta);
    memcpy(&c->before, &c->obs, sizeof c->obs);
    memset(&out, 0, sizeof out);
    st = rfe_velocity_step(&c->obs, &u, c->mu_in, &out);
    if (st != want) {
        violation(c, (want == RFE_OK) ? "an error on a sample inside the limits"
                                      : "an input error not reported as its class",
                  &u, (int)st);
    }
    if (st != RFE_OK) {
        if (memcmp(&c->obs, &c->before, sizeof c->obs) != 0) {
            violation(c, "a rejected sample changed the observer", &u, (int)st);
        }
        c->prev.status = st;
        if (memcmp(&out, &c->prev, sizeof out) != 0) {
            violation(c, "a rejected sample did not report the previous estimate", &u, (int)st);
        }
    } else {
        check_output(c, &u, &out, (int)st);
        if (out.delta != delta) {
            violation(c, "the reported road-wheel angle is not the one used", &u, (int)st);
        }
        c->prev = out;
        c->started = 1;
    }
    ++c->k;
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fz_ctx_t c;
    static const rfe_real_t mu_choice[4] = {0, (rfe_real_t)0.2, (rfe_real_t)1.0, (rfe_real_t)2.5};
    static const rfe_real_t sd_choice[4] = {0, (rfe_real_t)0.02, (rfe_real_t)0.3, (rfe_real_t)0.1};
    fz_reader_t r;
    fz_config_t cfg;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    int w;
    r.p = data;
    r.n = size;
    /* zeroed first, padding included: the harness compares whole observers and outputs */
    memset(&p, 0, sizeof p);
    memset(&vp, 0, sizeof vp);
    memset(&c, 0, sizeof c);
    cfg = fz_config(&r);
    if (rfe_params_default(&p) != RFE_OK || rfe_velocity_params_default(&vp) != RFE_OK) {
        abort();
    }
    vp.driven = cfg.preset_default ? RFE_DRIVEN_ALL : (RFE_DRIVEN_FL | RFE_DRIVEN_FR);
    c.steer_wheel = cfg.ckf;
    if (cfg.toggle_tyre) {
        p.tyre.mode = (p.tyre.mode == RFE_TYRE_MAGIC) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_MAGIC;
    }
    for (w = 0; w < 4; ++w) {
        c.mu.mu[w] = mu_choice[cfg.mu0_choice & 3];
        c.mu.sd[w] = sd_choice[cfg.mu0_choice & 3];
    }
    c.mu_in = (cfg.mu0_choice == 0) ? NULL : &c.mu;
    if (rfe_velocity_init(&c.obs, &vp, &p) != RFE_OK ||
        rfe_velocity_get(&c.obs, &c.prev) != RFE_OK) {
        fprintf(stderr, "fuzz_velocity: init failed\n");
        abort();
    }
    (void)fz_run(&r, step, &c);
    return 0;
}
