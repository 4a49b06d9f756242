/**
 * @file fuzz_velocity_q31.c
 * @brief libFuzzer harness of the fixed-point velocity observer: the inputs of
 *        fuzz_velocity_flt.c (fuzz_input.h's decoding, the same fields and configuration
 *        byte), each value rounded to its Q format of rfe_velocity_input_q31_t
 *        (rfe_fix_from_double: a value beyond its format saturates to the format's end; a NaN
 *        becomes 0, the one value a Q format cannot carry), then rfe_velocity_step_q31 and
 *        every invariant after every step; a violation prints one line and aborts.
 *
 * The 11 decoded values, as in fuzz_velocity_flt.c: delta (Q29); dt = 0.001 * v1 (Q30);
 * grade = 0.012 * v2 (Q29); yaw rate (Q27); steering-wheel angle = 0.16 * v4 (Q26); ax, ay
 * (Q24); omega fl..rr (Q22). Configuration byte: bit 0 all-wheel drive (else front), bit 1
 * the steering-wheel angle instead of delta, bit 2 the other tyre mode, bits 3-4 the friction
 * input: none, 0.2 (sd 0.02), 1.0 (sd 0.3), 2.5 (beyond the documented 0..2: every step must
 * be RFE_ERR_RANGE), in Q29 / Q30.
 *
 * Checked after each step, against the rules of rfe/velocity_q31.h written out here:
 *  - the status is the class of the sample: a Q value beyond its RFE_FIX_LIMIT_* (the
 *    road-wheel angle taken from the steering wheel when that is what the sample gives: its
 *    Q26 / Q24 quotient exactly rounded, ties away from zero), a friction beyond [0, 2] or a
 *    negative sd, or (after the first accepted sample) dt outside [dt_min, dt_max] gives
 *    RFE_ERR_RANGE; else RFE_OK, never an error;
 *  - on an error the observer is bit-identical to before and the output is the previous
 *    estimate with that status and sat 0;
 *  - on RFE_OK the outputs are inside their documented ranges: every sd >= 0, vx >= 0,
 *    |beta| <= pi (Q29) and beta 0 below v_lat_min, no unknown flag, the reported road-wheel
 *    angle the one used, and the observer's running saturation count grown by the step's
 *    (saturating at UINT32_MAX).
 * Parameters: the double defaults converted by rfe_params_to_q31_f64 and
 * rfe_velocity_params_to_q31_f64 (as mu_replay --real q31).
 * Run: build/fuzz/fuzz_velocity_q31 [corpus dirs] (make fuzz / make fuzz-smoke).
 */
#if !defined(RFE_REAL_DOUBLE)
#define RFE_REAL_DOUBLE 1
#endif

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "host/fixed_conv.h"
#include "rfe/component/params_conv.h"
#include "rfe/velocity_q31.h"

/** Every flag the observer may set (rfe/velocity_bits.h). */
#define KNOWN_FLAGS                                                                        \
    (RFE_VEL_FLAG_VX_WHEEL | RFE_VEL_FLAG_BRAKING | RFE_VEL_FLAG_DRIVING |                 \
     RFE_VEL_FLAG_VY_MODEL | RFE_VEL_FLAG_VY_LOWSPEED | RFE_VEL_FLAG_MU_RAISED | \
     RFE_VEL_FLAG_VY_LINEAR)

/** pi in Q29, rounded up: the largest |beta| an exactly rounded atan2 may give. */
#define PI_Q29 1686629714

typedef struct {
    rfe_velocity_q31_t obs;
    rfe_velocity_q31_t before;
    rfe_velocity_estimate_q31_t prev;
    rfe_velocity_mu_q31_t mu;
    const rfe_velocity_mu_q31_t *mu_in; /**< NULL: no friction input */
    int steer_wheel;
    int started;
    long k;
} fz_ctx_q31_t;

static void violation(const fz_ctx_q31_t *c, const char *what, const rfe_velocity_input_q31_t *u,
                      int st)
{
    fprintf(stderr,
            "fuzz_velocity (q31): step %ld: %s (status %d)\n  sample (Q): dt %d delta %d sw %d "
            "r %d ax %d ay %d grade %d omega %d %d %d %d\n",
            c->k, what, st, (int)u->dt, (int)u->delta, (int)u->steer_wheel, (int)u->yaw_rate,
            (int)u->ax, (int)u->ay, (int)u->grade, (int)u->omega[0], (int)u->omega[1],
            (int)u->omega[2], (int)u->omega[3]);
    abort();
}

static int beyond(rfe_fix_t v, rfe_fix_t lim) { return (v > lim) || (v < -lim); }

/* The road-wheel angle of a steering-wheel angle sw (Q26) through the ratio (Q24, > 0), in
 * Q29: sw 2^27 / ratio rounded to nearest, ties away from zero (rfe_fix_div's rule),
 * saturated to the int32 range; computed here in int64 (|sw| 2^28 < 2^60). */
static rfe_fix_t road_wheel_angle(rfe_fix_t sw, rfe_fix_t ratio)
{
    const int64_t mag = (int64_t)((sw < 0) ? -(int64_t)sw : (int64_t)sw) * ((int64_t)1 << 27);
    const int64_t q = (2 * mag + (int64_t)ratio) / (2 * (int64_t)ratio);
    const int64_t s = (sw < 0) ? -q : q;
    return (s > RFE_FIX_MAX) ? RFE_FIX_MAX : ((s < -RFE_FIX_MAX) ? -RFE_FIX_MAX : (rfe_fix_t)s);
}

/* The status rfe/velocity_q31.h promises for this sample (@p delta: the angle it uses). */
static rfe_status_t expected(const fz_ctx_q31_t *c, const rfe_velocity_input_q31_t *u,
                             rfe_fix_t delta)
{
    const rfe_velocity_params_q31_t *p = &c->obs.p;
    int i;
    if (beyond(delta, RFE_FIX_LIMIT_DELTA) || beyond(u->yaw_rate, RFE_FIX_LIMIT_YAW_RATE) ||
        beyond(u->ax, RFE_FIX_LIMIT_ACC) || beyond(u->ay, RFE_FIX_LIMIT_ACC) ||
        beyond(u->grade, RFE_FIX_LIMIT_GRADE)) {
        return RFE_ERR_RANGE;
    }
    for (i = 0; i < 4; ++i) {
        if (beyond(u->omega[i], RFE_FIX_LIMIT_OMEGA) ||
            (c->mu_in && (c->mu_in->mu[i] < 0 || c->mu_in->mu[i] > RFE_FIX_LIMIT_MU_IN ||
                          c->mu_in->sd[i] < 0))) {
            return RFE_ERR_RANGE;
        }
    }
    if (c->started && (u->dt < p->dt_min || u->dt > p->dt_max)) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

static void check_output(const fz_ctx_q31_t *c, const rfe_velocity_input_q31_t *u,
                         const rfe_velocity_estimate_q31_t *e, int st)
{
    const uint32_t want_sat =
        (c->before.sat > UINT32_MAX - e->sat) ? UINT32_MAX : c->before.sat + e->sat;
    if (e->sd_vx < 0 || e->sd_vy < 0 || e->sd_beta < 0 || e->sd_yaw_acc < 0) {
        violation(c, "a negative sd", u, st);
    }
    if (e->vx < 0) {
        violation(c, "vx below 0", u, st);
    }
    if (beyond(e->beta, PI_Q29)) {
        violation(c, "|beta| beyond pi", u, st);
    }
    if ((e->vx < c->obs.p.v_lat_min) && (e->beta != 0)) {
        violation(c, "beta not 0 below v_lat_min", u, st);
    }
    if ((e->flags & ~(uint32_t)KNOWN_FLAGS) != 0u) {
        violation(c, "an unknown flag", u, st);
    }
    if (c->obs.sat != want_sat) {
        violation(c, "the running saturation count did not grow by the step's", u, st);
    }
}

static int step(void *ctxp, const fz_sample_t *s)
{
    fz_ctx_q31_t *c = (fz_ctx_q31_t *)ctxp;
    rfe_velocity_input_q31_t u;
    rfe_velocity_estimate_q31_t out;
    rfe_status_t st;
    rfe_status_t want;
    rfe_fix_t delta;
    uint32_t conv_sat = 0u;
    int w;
    memset(&u, 0, sizeof u);
    u.delta = rfe_fix_from_double(s->v[0], RFE_FIX_Q_ANGLE, &conv_sat);
    u.dt = rfe_fix_from_double(0.001 * s->v[1], RFE_FIX_Q_DT, &conv_sat);
    u.grade = rfe_fix_from_double(0.012 * s->v[2], RFE_FIX_Q_ANGLE, &conv_sat);
    u.yaw_rate = rfe_fix_from_double(s->v[3], RFE_FIX_Q_YAWRATE, &conv_sat);
    u.steer_wheel = rfe_fix_from_double(0.16 * s->v[4], RFE_FIX_Q_STEER_WHEEL, &conv_sat);
    u.ax = rfe_fix_from_double(s->v[5], RFE_FIX_Q_ACC, &conv_sat);
    u.ay = rfe_fix_from_double(s->v[6], RFE_FIX_Q_ACC, &conv_sat);
    for (w = 0; w < 4; ++w) {
        u.omega[w] = rfe_fix_from_double(s->v[7 + w], RFE_FIX_Q_OMEGA, &conv_sat);
    }
    u.has = c->steer_wheel ? RFE_VEL_HAS_STEER_WHEEL : 0u;
    delta = c->steer_wheel ? road_wheel_angle(u.steer_wheel, c->obs.p.steer_ratio) : u.delta;
    want = expected(c, &u, delta);
    memcpy(&c->before, &c->obs, sizeof c->obs);
    memset(&out, 0, sizeof out);
    st = rfe_velocity_step_q31(&c->obs, &u, c->mu_in, &out);
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
        c->prev.sat = 0u;
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
    static fz_ctx_q31_t c;
    static const double mu_choice[4] = {0.0, 0.2, 1.0, 2.5};
    static const double sd_choice[4] = {0.0, 0.02, 0.3, 0.1};
    fz_reader_t r;
    fz_config_t cfg;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_params_q31_t q;
    rfe_velocity_params_q31_t vq;
    uint32_t conv_sat = 0u;
    int w;
    r.p = data;
    r.n = size;
    /* zeroed first, padding included: the harness compares whole observers and outputs */
    memset(&q, 0, sizeof q);
    memset(&vq, 0, sizeof vq);
    memset(&c, 0, sizeof c);
    cfg = fz_config(&r);
    if (rfe_params_default_f64(&p) != RFE_OK || rfe_velocity_params_default_f64(&vp) != RFE_OK) {
        abort();
    }
    vp.driven = cfg.preset_default ? RFE_DRIVEN_ALL : (RFE_DRIVEN_FL | RFE_DRIVEN_FR);
    c.steer_wheel = cfg.ckf;
    if (cfg.toggle_tyre) {
        p.tyre.mode = (p.tyre.mode == RFE_TYRE_MAGIC) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_MAGIC;
    }
    for (w = 0; w < 4; ++w) {
        c.mu.mu[w] = rfe_fix_from_double(mu_choice[cfg.mu0_choice & 3], RFE_FIX_Q_MU, &conv_sat);
        c.mu.sd[w] = rfe_fix_from_double(sd_choice[cfg.mu0_choice & 3], RFE_FIX_Q_SD, &conv_sat);
    }
    c.mu_in = (cfg.mu0_choice == 0) ? NULL : &c.mu;
    if (rfe_params_to_q31_f64(&p, &q) != RFE_OK ||
        rfe_velocity_params_to_q31_f64(&vp, &vq) != RFE_OK ||
        rfe_velocity_init_q31(&c.obs, &vq, &q) != RFE_OK ||
        rfe_velocity_get_q31(&c.obs, &c.prev) != RFE_OK) {
        fprintf(stderr, "fuzz_velocity (q31): init failed\n");
        abort();
    }
    (void)fz_run(&r, step, &c);
    return 0;
}
