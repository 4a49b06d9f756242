/**
 * @file fuzz_mass_grade_flt.c
 * @brief libFuzzer harness of the mass and grade estimator (docs/MASS_GRADE.md): raw bytes
 *        -> parameters (a preset, perturbed or garbage: fuzz_params.h) and a sequence of
 *        samples (fuzz_input.h's decoding, mapped below) -> rfe_mass_grade_init and
 *        rfe_mass_grade_step of the float build (or the double build with -DRFE_REAL_DOUBLE),
 *        every invariant checked after every call; a violation prints one line and aborts.
 *        It exists because the estimator must meet what the friction estimator meets: no
 *        input, however bad, may crash it, corrupt it or make it report NaN.
 *
 * Byte 0: bit 0 the truck (else the car), bit 1 the seed's configuration (else the
 * recommended one), bits 2-3 the optional inputs every sample carries besides those the
 * value below adds (0: none; 1: ax; 2: ax, brake flag, pressure; 3: all). Then the
 * parameters (fuzz_params.h); when their init fails the preset is used, so the samples are
 * still stepped. Then the records of fuzz_input.h; the 11 decoded values become a sample
 * (scaled so that the decoder's limit is the estimator's limit or about it):
 *   dt = 0.01 * v1 (nominal 0.2 s, limit 1 s = the presets' dt_max: beyond it a restart);
 *   v = 0.2 * omega_fl (limit 100 m/s = RFE_LIMIT_VX); torque = 1e4 * yaw_rate (limit 1e5
 *   N m = RFE_LIMIT_DRIVE_TORQUE); p_brake = 1e4 * yaw_acc [Pa] (limit 1e6); ax = ax;
 *   gear = omega_fr / 50 truncated (when finite and within +-1e6, else 0); brake =
 *   omega_rl - 58 truncated when positive and finite (any uint32), else 0;
 *   has = the configuration's bits XOR (omega_rr - 58) truncated (so the nominal 58 gives
 *   the configuration's bits, and a perturbation sets unknown bits too);
 *   vy >= 25 (half its limit) calls rfe_mass_grade_restart before the step.
 *
 * Checked, from rfe/mass_grade.h and docs/MASS_GRADE.md §4.1, §6, §7 (not from the code):
 *  - init: RFE_OK or RFE_ERR_PARAM, the same verdict as rfe_mass_grade_params_validate, and
 *    a refused init writes nothing (memcmp);
 *  - each step: the status is one of the codes of §7; a sample with a non-finite value it
 *    carries gives RFE_ERR_NONFINITE, else one beyond the limits, with unknown `has` bits,
 *    without ax while use_ax, or (after the first accepted sample) dt <= 0 gives
 *    RFE_ERR_RANGE; else the status is OK, a hold (2, 5, 6) or one of the filter's failures
 *    (21, 17 on an overflow);
 *  - an error leaves the estimator byte-identical (memcmp) and reports the previous estimate
 *    with the error's status;
 *  - a non-error gives a finite estimate with every sd >= 0 and q_mv >= 0, the mass in
 *    [m_min, m_max] and |grade| <= theta_max (the projection, §4.3 step 8), the state finite
 *    with a covariance of non-negative diagonal, and rfe_mass_grade_get returns it.
 * Run: build/fuzz/fuzz_mass_grade_f32 [corpus dirs] (make fuzz / make fuzz-smoke).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "fuzz_params.h"
#include "fuzz_real.h"
#include "rfe/mass_grade.h"

typedef struct {
    rfe_mass_grade_t mg;
    rfe_mass_grade_t before;
    rfe_mass_grade_estimate_t prev;
    uint32_t has_base;
    int started;
    long k;
} fz_ctx_t;

static void violation(const fz_ctx_t *c, const char *what, const rfe_mass_grade_input_t *u,
                      int st)
{
    fprintf(stderr,
            "fuzz_mass_grade (%s): step %ld: %s (status %d)\n  sample: dt %.9g v %.9g torque "
            "%.9g p_brake %.9g ax %.9g gear %ld brake %lu has %#lx\n",
            FZ_BUILD, c->k, what, st, (double)u->dt, (double)u->v, (double)u->torque,
            (double)u->p_brake, (double)u->ax, (long)u->gear, (unsigned long)u->brake,
            (unsigned long)u->has);
    abort();
}

/* The input class rfe/mass_grade.h gives the sample: RFE_OK or the error it must return. */
static rfe_status_t input_class(const fz_ctx_t *c, const rfe_mass_grade_input_t *u)
{
    const int has_ax = (u->has & RFE_MG_HAS_AX) != 0u;
    if (!finite(u->dt) || !finite(u->v) || !finite(u->torque) ||
        (((u->has & RFE_MG_HAS_PRESSURE) != 0u) && !finite(u->p_brake)) ||
        (has_ax && !finite(u->ax)) || (((u->has & RFE_MG_HAS_VX) != 0u) && !finite(u->vx)) ||
        (((u->has & RFE_MG_HAS_AY) != 0u) && !finite(u->ay))) {
        return RFE_ERR_NONFINITE;
    }
    if (((u->has & ~(uint32_t)RFE_MG_HAS_ALL) != 0u) || beyond(u->v, RFE_LIMIT_VX) ||
        beyond(u->torque, RFE_LIMIT_DRIVE_TORQUE) || (has_ax && beyond(u->ax, RFE_LIMIT_ACC)) ||
        (((u->has & RFE_MG_HAS_VX) != 0u) && beyond(u->vx, RFE_LIMIT_VX)) ||
        (((u->has & RFE_MG_HAS_AY) != 0u) && beyond(u->ay, RFE_LIMIT_ACC)) ||
        ((c->mg.p.use_ax == 1u) && !has_ax) || (c->started && !(u->dt > 0))) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* Two estimates equal field by field (bitwise: NaN included); the double build's struct
 * has tail padding, which a struct copy need not carry. */
static int same_estimate(const rfe_mass_grade_estimate_t *a, const rfe_mass_grade_estimate_t *b)
{
    const rfe_real_t va[7] = {a->mass, a->sd_mass, a->grade, a->sd_grade, a->v, a->sd_v, a->q_mv};
    const rfe_real_t vb[7] = {b->mass, b->sd_mass, b->grade, b->sd_grade, b->v, b->sd_v, b->q_mv};
    return (memcmp(va, vb, sizeof va) == 0) && (a->status == b->status);
}

static void check_state(const fz_ctx_t *c, const rfe_mass_grade_input_t *u,
                        const rfe_mass_grade_estimate_t *e, int st)
{
    const rfe_mass_grade_params_t *p = &c->mg.p;
    const rfe_real_t v[7] = {e->mass, e->sd_mass, e->grade, e->sd_grade, e->v, e->sd_v, e->q_mv};
    rfe_mass_grade_estimate_t got;
    int i;
    for (i = 0; i < 7; ++i) {
        if (!finite(v[i])) {
            violation(c, "a non-finite estimate", u, st);
        }
    }
    if (e->sd_mass < 0 || e->sd_grade < 0 || e->sd_v < 0 || e->q_mv < 0) {
        violation(c, "a negative sd or q_mv", u, st);
    }
    if (e->mass < p->m_min || e->mass > p->m_max) {
        violation(c, "the mass outside [m_min, m_max]", u, st);
    }
    if (e->grade < -p->theta_max || e->grade > p->theta_max) {
        violation(c, "|grade| beyond theta_max", u, st);
    }
    for (i = 0; i < RFE_MG_N * RFE_MG_N; ++i) {
        if (!finite(c->mg.S[i])) {
            violation(c, "a non-finite covariance factor", u, st);
        }
    }
    for (i = 0; i < RFE_MG_N; ++i) {
        if (!finite(c->mg.x[i]) || c->mg.S[i * (RFE_MG_N + 1)] < 0) {
            violation(c, "a non-finite state or a negative diagonal of the factor", u, st);
        }
    }
    if (rfe_mass_grade_get(&c->mg, &got) != RFE_OK || !same_estimate(&got, e)) {
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
    fz_ctx_t *c = (fz_ctx_t *)ctxp;
    rfe_mass_grade_input_t u;
    rfe_mass_grade_estimate_t out;
    rfe_status_t st;
    rfe_status_t want;
    memset(&u, 0, sizeof u);
    u.dt = fz_to_real(0.01 * s->v[1]);
    u.v = fz_to_real(0.2 * s->v[7]);
    u.torque = fz_to_real(1e4 * s->v[3]);
    u.p_brake = fz_to_real(1e4 * s->v[4]);
    u.ax = fz_to_real(s->v[5]);
    u.vx = fz_to_real((0.2 * s->v[7]) + (10.0 * s->v[0])); /* the steer field: the slip */
    u.ay = fz_to_real(s->v[6]);
    u.gear = (int32_t)to_long(s->v[8] / 50.0, 1e6);
    u.brake = (uint32_t)((s->v[9] > 58.0) ? to_long(s->v[9] - 58.0, 4e9) : 0L);
    u.has = c->has_base ^ (uint32_t)to_long(s->v[10] - 58.0, 2e9);
    if (s->v[2] >= 0.5 * RFE_LIMIT_VY) {
        if (rfe_mass_grade_restart(&c->mg) != RFE_OK) {
            violation(c, "restart failed", &u, -1);
        }
        c->started = 0;
    }
    want = input_class(c, &u);
    memcpy(&c->before, &c->mg, sizeof c->mg);
    memset(&out, 0, sizeof out);
    st = rfe_mass_grade_step(&c->mg, &u, &out);
    if (out.status != st) {
        violation(c, "the estimate's status is not the returned one", &u, (int)st);
    }
    if (want != RFE_OK) {
        if (st != want) {
            violation(c, "an input error not reported as its class", &u, (int)st);
        }
    } else if (!(st == RFE_OK || st == RFE_NO_UPDATE_LOW_SPEED || st == RFE_MG_PAUSED_BRAKE ||
                 st == RFE_MG_PAUSED_SHIFT || st == RFE_MG_PAUSED_SLIP || st == RFE_MG_PAUSED_CURVE || st == RFE_ERR_NOT_POSITIVE_DEFINITE ||
                 st == RFE_ERR_NONFINITE)) {
        violation(c, "a status §7 does not list for a sample inside the limits", &u, (int)st);
    }
    if (rfe_status_is_error(st)) {
        if (memcmp(&c->mg, &c->before, sizeof c->mg) != 0) {
            violation(c, "a refused sample changed the estimator", &u, (int)st);
        }
        c->prev.status = st;
        if (!same_estimate(&out, &c->prev)) {
            violation(c, "a refused sample did not report the previous estimate", &u, (int)st);
        }
    } else {
        check_state(c, &u, &out, (int)st);
        c->prev = out;
        c->started = 1;
    }
    ++c->k;
    return 0;
}

/* The parameter struct's fields for fuzz_params.h. */
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
    static fz_ctx_t c;
    static const uint32_t has_of[4] = {
        0u, RFE_MG_HAS_AX, RFE_MG_HAS_AX | RFE_MG_HAS_BRAKE | RFE_MG_HAS_PRESSURE,
        RFE_MG_HAS_ALL};
    fz_reader_t r;
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_t preset;
    rfe_real_t *real[44];
    uint32_t *u32[2];
    fzp_fields_t f;
    uint8_t cfg;
    rfe_status_t st;
    rfe_status_t valid;
    r.p = data;
    r.n = size;
    /* zeroed first, padding included: the harness compares whole estimators and outputs */
    memset(&p, 0, sizeof p);
    memset(&preset, 0, sizeof preset);
    memset(&c, 0, sizeof c);
    cfg = fz_u8(&r);
    if (rfe_mass_grade_params_preset(&preset, (cfg & 1u) ? RFE_MG_TRUCK : RFE_MG_CAR,
                                     (cfg & 2u) ? RFE_MG_SEED : RFE_MG_RECOMMENDED) != RFE_OK) {
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
    valid = rfe_mass_grade_params_validate(&p);
    memset(&c.mg, 0xA5, sizeof c.mg);
    memcpy(&c.before, &c.mg, sizeof c.mg);
    st = rfe_mass_grade_init(&c.mg, &p);
    if (st != valid || (st != RFE_OK && st != RFE_ERR_PARAM)) {
        fprintf(stderr, "fuzz_mass_grade (%s): init %d, validate %d\n", FZ_BUILD, (int)st,
                (int)valid);
        abort();
    }
    if (st != RFE_OK) {
        if (memcmp(&c.mg, &c.before, sizeof c.mg) != 0) {
            fprintf(stderr, "fuzz_mass_grade (%s): a refused init wrote the state\n", FZ_BUILD);
            abort();
        }
        memset(&c.mg, 0, sizeof c.mg);
        if (rfe_mass_grade_init(&c.mg, &preset) != RFE_OK) {
            abort();
        }
    }
    if (rfe_mass_grade_get(&c.mg, &c.prev) != RFE_OK) {
        abort();
    }
    (void)fz_run(&r, step, &c);
    return 0;
}
