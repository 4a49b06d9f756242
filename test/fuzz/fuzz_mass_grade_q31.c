/**
 * @file fuzz_mass_grade_q31.c
 * @brief libFuzzer harness of the fixed-point mass and grade estimator: the inputs of
 *        fuzz_mass_grade_flt.c (the same configuration byte, parameter decoding and sample
 *        mapping), the parameters converted by rfe_mass_grade_params_to_q31_f64 and each
 *        sample value rounded to its Q format of rfe_mass_grade_input_q31_t
 *        (rfe_fix_from_double: a value beyond its format saturates to the format's end; a NaN
 *        becomes 0, the one value a Q format cannot carry), then rfe_mass_grade_init_q31 and
 *        rfe_mass_grade_step_q31 with every invariant after every call; a violation prints
 *        one line and aborts.
 *
 * Checked, from rfe/mass_grade_q31.h and docs/MASS_GRADE.md §4.1, §7 (not from the code):
 *  - init: RFE_OK or RFE_ERR_PARAM, the same verdict as
 *    rfe_mass_grade_params_validate_q31, a refused init writes nothing (memcmp); a set the
 *    conversion refuses, or the init, falls back to the preset;
 *  - each step: a sample with |v|, |torque| or (given) |ax| beyond the RFE_MG_LIMIT_*_Q31,
 *    unknown `has` bits, no ax while use_ax, or (after the first accepted sample) dt <= 0
 *    gives RFE_ERR_RANGE; else the status is OK or a hold (2, 5, 6), never an error (the
 *    square-root form has no failing factorisation: r_v, r_ax > 0);
 *  - an error leaves the estimator bit-identical and reports the previous estimate with the
 *    error's status;
 *  - a non-error gives every sd >= 0, q_mv >= 0, the mass in [m_min, m_max], |grade| <=
 *    theta_max, the factor's diagonal >= 0, the running saturation count grown by the step's
 *    (saturating), and rfe_mass_grade_get_q31 returns the estimate.
 * Run: build/fuzz/fuzz_mass_grade_q31 [corpus dirs] (make fuzz / make fuzz-smoke).
 */
#if !defined(RFE_REAL_DOUBLE)
#define RFE_REAL_DOUBLE 1
#endif

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "fuzz_params.h"
#include "host/fixed_conv.h"
#include "rfe/component/params_conv.h"
#include "rfe/mass_grade_q31.h"

typedef struct {
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_q31_t before;
    rfe_mass_grade_estimate_q31_t prev;
    uint32_t has_base;
    int started;
    long k;
} fz_ctx_q31_t;

static void violation(const fz_ctx_q31_t *c, const char *what,
                      const rfe_mass_grade_input_q31_t *u, int st)
{
    fprintf(stderr,
            "fuzz_mass_grade (q31): step %ld: %s (status %d)\n  sample (Q): dt %ld v %ld torque "
            "%ld p_brake %ld ax %ld gear %ld brake %lu has %#lx\n",
            c->k, what, st, (long)u->dt, (long)u->v, (long)u->torque, (long)u->p_brake,
            (long)u->ax, (long)u->gear, (unsigned long)u->brake, (unsigned long)u->has);
    abort();
}

/* |v| > lim without forming |INT32_MIN|. */
static int beyond_q(rfe_fix_t v, rfe_fix_t lim)
{
    return (v > lim) || (v < -lim);
}

/* The status rfe/mass_grade_q31.h promises for the sample's checks. */
static rfe_status_t input_class(const fz_ctx_q31_t *c, const rfe_mass_grade_input_q31_t *u)
{
    const int has_ax = (u->has & RFE_MG_HAS_AX) != 0u;
    if (((u->has & ~(uint32_t)RFE_MG_HAS_ALL) != 0u) || beyond_q(u->v, RFE_MG_LIMIT_V_Q31) ||
        beyond_q(u->torque, RFE_MG_LIMIT_TORQUE_Q31) ||
        (has_ax && beyond_q(u->ax, RFE_MG_LIMIT_AX_Q31)) || ((c->mg.p.use_ax == 1u) && !has_ax) ||
        (((u->has & RFE_MG_HAS_VX) != 0u) && beyond_q(u->vx, RFE_MG_LIMIT_V_Q31)) ||
        (((u->has & RFE_MG_HAS_AY) != 0u) && beyond_q(u->ay, RFE_MG_LIMIT_AX_Q31)) ||
        (c->started && !(u->dt > 0))) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

static void check_state(const fz_ctx_q31_t *c, const rfe_mass_grade_input_q31_t *u,
                        const rfe_mass_grade_estimate_q31_t *e, int st, uint32_t sat_before)
{
    const rfe_mass_grade_params_q31_t *p = &c->mg.p;
    rfe_mass_grade_estimate_q31_t got;
    uint32_t want_sat;
    if (e->sd_mass < 0 || e->sd_grade < 0 || e->sd_v < 0 || e->q_mv < 0) {
        violation(c, "a negative sd or q_mv", u, st);
    }
    if (e->mass < p->m_min || e->mass > p->m_max) {
        violation(c, "the mass outside [m_min, m_max]", u, st);
    }
    if (e->grade < -p->theta_max || e->grade > p->theta_max) {
        violation(c, "|grade| beyond theta_max", u, st);
    }
    if (c->mg.S[0] < 0 || c->mg.S[4] < 0 || c->mg.S[8] < 0) {
        violation(c, "a negative diagonal of the factor", u, st);
    }
    want_sat = (sat_before > UINT32_MAX - e->sat) ? UINT32_MAX : sat_before + e->sat;
    if (c->mg.sat != want_sat) {
        violation(c, "the running saturation count is not grown by the step's", u, st);
    }
    if (rfe_mass_grade_get_q31(&c->mg, &got) != RFE_OK || memcmp(&got, e, sizeof got) != 0) {
        violation(c, "get does not return the last estimate", u, st);
    }
}

/* A double to an integer type without undefined behaviour: 0 when not finite or too big. */
static long to_long(double x, double lim)
{
    return (isfinite(x) && fabs(x) < lim) ? (long)x : 0L;
}

static int step(void *ctxp, const fz_sample_t *s)
{
    fz_ctx_q31_t *c = (fz_ctx_q31_t *)ctxp;
    rfe_mass_grade_input_q31_t u;
    rfe_mass_grade_estimate_q31_t out;
    rfe_status_t st;
    rfe_status_t want;
    uint32_t conv_sat = 0u;
    uint32_t sat_before;
    memset(&u, 0, sizeof u);
    /* the float harness's mapping, then each value rounded to its format */
    u.dt = rfe_fix_from_double(0.01 * s->v[1], RFE_MG_Q_DT, &conv_sat);
    u.v = rfe_fix_from_double(0.2 * s->v[7], RFE_MG_Q_V, &conv_sat);
    u.torque = rfe_fix_from_double(1e4 * s->v[3], RFE_MG_Q_TORQUE, &conv_sat);
    u.p_brake = rfe_fix_from_double(1e4 * s->v[4] * 1e-6, RFE_MG_Q_PRESSURE, &conv_sat);
    u.ax = rfe_fix_from_double(s->v[5], RFE_MG_Q_V, &conv_sat);
    u.vx = rfe_fix_from_double((0.2 * s->v[7]) + (10.0 * s->v[0]), RFE_MG_Q_V, &conv_sat);
    u.ay = rfe_fix_from_double(s->v[6], RFE_MG_Q_V, &conv_sat);
    u.gear = (int32_t)to_long(s->v[8] / 50.0, 1e6);
    u.brake = (uint32_t)((s->v[9] > 58.0) ? to_long(s->v[9] - 58.0, 4e9) : 0L);
    u.has = c->has_base ^ (uint32_t)to_long(s->v[10] - 58.0, 2e9);
    if (s->v[2] >= 0.5 * RFE_LIMIT_VY) {
        if (rfe_mass_grade_restart_q31(&c->mg) != RFE_OK) {
            violation(c, "restart failed", &u, -1);
        }
        c->started = 0;
    }
    want = input_class(c, &u);
    memcpy(&c->before, &c->mg, sizeof c->mg);
    sat_before = c->mg.sat;
    memset(&out, 0, sizeof out);
    st = rfe_mass_grade_step_q31(&c->mg, &u, &out);
    if (out.status != st) {
        violation(c, "the estimate's status is not the returned one", &u, (int)st);
    }
    if (want != RFE_OK) {
        if (st != want) {
            violation(c, "an input error not reported as its class", &u, (int)st);
        }
    } else if (!(st == RFE_OK || st == RFE_NO_UPDATE_LOW_SPEED || st == RFE_MG_PAUSED_BRAKE ||
                 st == RFE_MG_PAUSED_SHIFT || st == RFE_MG_PAUSED_SLIP || st == RFE_MG_PAUSED_CURVE)) {
        violation(c, "an error on a sample inside the limits", &u, (int)st);
    }
    if (rfe_status_is_error(st)) {
        if (memcmp(&c->mg, &c->before, sizeof c->mg) != 0) {
            violation(c, "a refused sample changed the estimator", &u, (int)st);
        }
        c->prev.status = st;
        if (memcmp(&out, &c->prev, sizeof out) != 0) {
            violation(c, "a refused sample did not report the previous estimate", &u, (int)st);
        }
    } else {
        check_state(c, &u, &out, (int)st, sat_before);
        c->prev = out;
        c->started = 1;
    }
    ++c->k;
    return 0;
}

/* The parameter struct's fields for fuzz_params.h (as fuzz_mass_grade_flt.c). */
static void fields_of(rfe_mass_grade_params_t *p, rfe_real_t *real[44], uint32_t *u32[2])
{
    rfe_real_t *const r[44] = {
        &p->R,        &p->g,         &p->fc,      &p->fr,        &p->rho,     &p->cd,
        &p->area,     &p->m_rot,     &p->m0,      &p->theta0,    &p->sd_m0,   &p->sd_theta0,
        &p->q_v,      &p->q_mc,      &p->q_mv0,   &p->q_theta,   &p->r_v,     &p->r_ax,
        &p->ut_alpha, &p->ut_beta,   &p->ut_kappa, &p->t_adapt,  &p->mv_stop, &p->v_min,
        &p->t_brake,  &p->t_shift,   &p->p_brake_on, &p->m_min,  &p->m_max,   &p->theta_max,
        &p->dt_max,   &p->slip_max,  &p->ay_max,  &p->t_curve, &p->pause_grade,
        &p->pause_grade_slip, &p->pause_grade_dv, &p->q_theta_hi, &p->theta_rate_on,
        &p->theta_rate_off, &p->theta_rate_tau, &p->theta_rate_avg, &p->mm_tau, &p->mm_e};
    memcpy(real, r, sizeof r);
    u32[0] = &p->adaptive;
    u32[1] = &p->use_ax;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fz_ctx_q31_t c;
    static const uint32_t has_of[4] = {
        0u, RFE_MG_HAS_AX, RFE_MG_HAS_AX | RFE_MG_HAS_BRAKE | RFE_MG_HAS_PRESSURE,
        RFE_MG_HAS_ALL};
    fz_reader_t r;
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_t preset;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_params_q31_t qpreset;
    rfe_real_t *real[44];
    uint32_t *u32[2];
    fzp_fields_t f;
    uint8_t cfg;
    rfe_status_t st = RFE_ERR_PARAM;
    rfe_status_t valid = RFE_ERR_PARAM;
    r.p = data;
    r.n = size;
    /* zeroed first, padding included: the harness compares whole estimators and outputs */
    memset(&p, 0, sizeof p);
    memset(&preset, 0, sizeof preset);
    memset(&q, 0, sizeof q);
    memset(&qpreset, 0, sizeof qpreset);
    memset(&c, 0, sizeof c);
    cfg = fz_u8(&r);
    if (rfe_mass_grade_params_preset(&preset, (cfg & 1u) ? RFE_MG_TRUCK : RFE_MG_CAR,
                                     (cfg & 2u) ? RFE_MG_SEED : RFE_MG_RECOMMENDED) != RFE_OK ||
        rfe_mass_grade_params_to_q31(&preset, &qpreset) != RFE_OK) {
        abort();
    }
    c.has_base = has_of[(cfg >> 2) & 3u];
    p = preset;
    fields_of(&p, real, u32);
    f.real = real;
    f.n_real = 44;
    f.u32 = u32;
    f.n_u32 = 2;
    (void)fzp_decode(&r, &f);
    memset(&c.mg, 0xA5, sizeof c.mg);
    memcpy(&c.before, &c.mg, sizeof c.mg);
    if (rfe_mass_grade_params_to_q31(&p, &q) == RFE_OK) {
        valid = rfe_mass_grade_params_validate_q31(&q);
        st = rfe_mass_grade_init_q31(&c.mg, &q);
        if (st != valid || (st != RFE_OK && st != RFE_ERR_PARAM)) {
            fprintf(stderr, "fuzz_mass_grade (q31): init %d, validate %d\n", (int)st, (int)valid);
            abort();
        }
    }
    if (st != RFE_OK) {
        if (memcmp(&c.mg, &c.before, sizeof c.mg) != 0) {
            fprintf(stderr, "fuzz_mass_grade (q31): a refused init wrote the state\n");
            abort();
        }
        memset(&c.mg, 0, sizeof c.mg);
        if (rfe_mass_grade_init_q31(&c.mg, &qpreset) != RFE_OK) {
            abort();
        }
    }
    if (rfe_mass_grade_get_q31(&c.mg, &c.prev) != RFE_OK) {
        abort();
    }
    (void)fz_run(&r, step, &c);
    return 0;
}
