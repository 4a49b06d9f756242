/**
 * @file fuzz_tyre_id_flt.c
 * @brief libFuzzer harness of the tyre identifier (docs/TYRE_ID.md): raw bytes -> the
 *        identifier's parameters and the vehicle's (each the default, perturbed or garbage:
 *        fuzz_params.h), the filter, the resampling and the seed, and a sequence of samples
 *        (fuzz_input.h's decoding, mapped below) -> rfe_tyre_id_init and rfe_tyre_id_step
 *        of the float build (or the double build with -DRFE_REAL_DOUBLE), every invariant
 *        checked after every call; a violation prints one line and aborts. It exists because
 *        the identifier must meet what the friction estimator meets: no input, however bad,
 *        may crash it, corrupt it or make it report NaN.
 *
 * Byte 0: bit 0 the bootstrap filter (else the APF), bit 1 systematic resampling (else
 * multinomial), bits 2-4 substeps - 1 (1..8), bit 5 the sigma-point filter of §15 (over
 * bit 0). Bytes 1-8: the seed. Then the identifier's
 * parameters, then the vehicle's (fuzz_params.h each; the filter and resampling may be
 * replaced by any integer there); when their init fails the defaults are used, so the
 * samples are still stepped. Then the records of fuzz_input.h; the 11 decoded values become
 * a sample: delta = delta; dt = 0.001 * vx (nominal 0.02 s, limit 0.1 s = tid_dt_max);
 * vx = 0.2 * omega_fl (limit 100 m/s, nominal 11.6 m/s); yaw rate; ay; ax. At most
 * FZ_TID_STEPS steps per input (a step costs N particles' RK4 and likelihoods).
 *
 * Checked, from rfe/tyre_id.h and docs/TYRE_ID.md §2, §5.5, §7, §12 (not from the code):
 *  - init: RFE_OK or RFE_ERR_PARAM; a refused init writes nothing (memcmp); with valid
 *    parameters the state's derived bounds are §2's exactly (lo = mu_lo Fz0, C_lo, cy_lo Fz0,
 *    E_lo per axle, Fz0 the static axle loads computed as §3.4 and §9 write them, likewise
 *    hi), each lo < hi;
 *  - each step: a non-finite input gives RFE_ERR_NONFINITE; else an input beyond config.h's
 *    limits, an ax that makes an axle load Fz0 -/+ G ax non-positive, or (after the first
 *    accepted sample) dt outside (0, dt_max] gives RFE_ERR_RANGE; else RFE_OK;
 *  - an error leaves the identifier byte-identical (memcmp) and reports the previous
 *    estimate with the error's status;
 *  - RFE_OK: known flags, exactly one of FIRST, HELD, UPDATED, LOST (§7: a lost step draws
 *    the prior again and says only that), RESAMPLED only with UPDATED; every mean and sd finite, sd >= 0; n_eff in [1, N]
 *    (the sigma-point filter: NaN, its mean's parameters inside [lo, hi] exactly, S finite); every particle's
 *    parameters inside their bounds [lo, hi] exactly (the reflection of §5.5), so the means
 *    of D, C, K, E inside them to the rounding of a weighted sum; every log weight <= 0 or
 *    -Inf (normalised: the largest is 0), never NaN; rfe_tyre_id_get returns the estimate.
 * Run: build/fuzz/fuzz_tyre_id_f32 [corpus dirs] (make fuzz / make fuzz-smoke).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "fuzz_params.h"
#include "fuzz_real.h"
#include "rfe/tyre_id.h"

#ifndef FZ_TID_STEPS
#define FZ_TID_STEPS 400
#endif

/** Every flag the identifier may set (rfe/tyre_id.h). */
#define KNOWN_FLAGS \
    (RFE_TID_UPDATED | RFE_TID_RESAMPLED | RFE_TID_HELD | RFE_TID_FIRST | RFE_TID_LOST)

/** Relative slack of a weighted mean of values in [lo, hi]: the weights sum to 1 only to
 *  N roundings, each mean term adds one more. */
#if defined(RFE_REAL_DOUBLE)
#define FZ_TRUE_MIN 4.9406564584124654e-324
#define MEAN_TOL (4.0 * RFE_TID_N * 1.1102230246251565e-16)
#else
#define FZ_TRUE_MIN 1.40129846e-45
#define MEAN_TOL (4.0 * RFE_TID_N * 5.9604645e-08)
#endif

typedef struct {
    rfe_tyre_id_t tid;
    rfe_tyre_id_t before;
    rfe_tyre_id_estimate_t prev;
    int started;
    long k;
} fz_ctx_t;

static void violation(const fz_ctx_t *c, const char *what, const rfe_tyre_id_sample_t *u,
                      int st)
{
    fprintf(stderr,
            "fuzz_tyre_id (%s, N %d): step %ld: %s (status %d)\n  sample: dt %.9g delta %.9g "
            "vx %.9g r %.9g ay %.9g ax %.9g\n",
            FZ_BUILD, RFE_TID_N, c->k, what, st, (double)u->dt, (double)u->delta,
            (double)u->vx, (double)u->yaw_rate, (double)u->ay, (double)u->ax);
    abort();
}

/* The status rfe/tyre_id.h and TYRE_ID.md §12 give the sample. */
static rfe_status_t expected(const fz_ctx_t *c, const rfe_tyre_id_sample_t *u)
{
    const rfe_tid_consts_t *k = &c->tid.c;
    if (!finite(u->dt) || !finite(u->delta) || !finite(u->vx) || !finite(u->yaw_rate) ||
        !finite(u->ay) || !finite(u->ax)) {
        return RFE_ERR_NONFINITE;
    }
    if (beyond(u->delta, RFE_LIMIT_DELTA) || beyond(u->vx, RFE_LIMIT_VX) ||
        beyond(u->yaw_rate, RFE_LIMIT_YAW_RATE) || beyond(u->ay, RFE_LIMIT_ACC) ||
        beyond(u->ax, RFE_LIMIT_ACC)) {
        return RFE_ERR_RANGE;
    }
    /* §3.4 the axle loads, as the constants derived at init give them */
    if (!((k->fz0[0] - k->gx * u->ax) > 0) || !((k->fz0[1] + k->gx * u->ax) > 0)) {
        return RFE_ERR_RANGE;
    }
    if (c->started && (!(u->dt > 0) || u->dt > c->tid.p.dt_max)) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* x inside [lo, hi] widened by MEAN_TOL of the larger magnitude, and by N of the type's
 * smallest subnormal (each term w q of a mean rounds to it absolutely below FLT_MIN). */
static int inside_tol(rfe_real_t x, rfe_real_t lo, rfe_real_t hi)
{
    const double tol =
        MEAN_TOL * fmax(fabs((double)lo), fabs((double)hi)) + RFE_TID_N * FZ_TRUE_MIN;
    return ((double)x >= (double)lo - tol) && ((double)x <= (double)hi + tol);
}

static void check_output(const fz_ctx_t *c, const rfe_tyre_id_sample_t *u,
                         const rfe_tyre_id_estimate_t *e)
{
    /* output index of each particle parameter column (D, C, K, E per axle) */
    static const int out_of_par[RFE_TID_PAR] = {RFE_TID_OUT_D_F, RFE_TID_OUT_C_F,
                                                RFE_TID_OUT_K_F, RFE_TID_OUT_E_F,
                                                RFE_TID_OUT_D_R, RFE_TID_OUT_C_R,
                                                RFE_TID_OUT_K_R, RFE_TID_OUT_E_R};
    const rfe_tid_consts_t *k = &c->tid.c;
    const uint32_t phase =
        e->flags & (RFE_TID_FIRST | RFE_TID_HELD | RFE_TID_UPDATED | RFE_TID_LOST);
    rfe_tyre_id_estimate_t got;
    int i;
    int j;
    if ((e->flags & ~(uint32_t)KNOWN_FLAGS) != 0u) {
        violation(c, "an unknown flag", u, 0);
    }
    if (phase != RFE_TID_FIRST && phase != RFE_TID_HELD && phase != RFE_TID_UPDATED &&
        phase != RFE_TID_LOST) {
        violation(c, "not exactly one of FIRST, HELD, UPDATED, LOST", u, 0);
    }
    if (phase != RFE_TID_UPDATED && (e->flags & RFE_TID_RESAMPLED) != 0u) {
        violation(c, "RESAMPLED without UPDATED", u, 0);
    }
    for (i = 0; i < RFE_TID_OUTPUTS; ++i) {
        if (!finite(e->mean[i]) || !finite(e->sd[i])) {
            violation(c, "a non-finite mean or sd", u, 0);
        }
        if (e->sd[i] < 0) {
            violation(c, "a negative sd", u, 0);
        }
    }
    if (c->tid.p.filter == RFE_TID_SCKF) {
        /* §15.3-15.4: no particles (n_eff NaN); the mean's parameters projected into their
         * bounds exactly, the parameter outputs that mean, S finite */
        if (!isnan((double)e->n_eff)) {
            violation(c, "the sigma-point filter's n_eff not NaN", u, 0);
        }
        for (j = 0; j < RFE_TID_PAR; ++j) {
            const rfe_real_t x = c->tid.sk.x[RFE_TID_STATES + j];
            if (!(x >= k->lo[j] && x <= k->hi[j]) || e->mean[out_of_par[j]] != x) {
                violation(c, "the sigma-point filter's mean outside its bounds", u, 0);
            }
        }
        for (i = 0; i < RFE_TID_SCKF_DIM * RFE_TID_SCKF_DIM; ++i) {
            if (!finite(c->tid.sk.S[i])) {
                violation(c, "the sigma-point filter's S not finite", u, 0);
            }
        }
    } else if (!finite(e->n_eff) || (double)e->n_eff < 1.0 - MEAN_TOL ||
               (double)e->n_eff > RFE_TID_N * (1.0 + MEAN_TOL)) {
        violation(c, "n_eff outside [1, N]", u, 0);
    }
    for (j = 0; j < RFE_TID_PAR; ++j) {
        if (!inside_tol(e->mean[out_of_par[j]], k->lo[j], k->hi[j])) {
            violation(c, "a parameter's mean outside its bounds", u, 0);
        }
    }
    for (i = 0; (c->tid.p.filter != RFE_TID_SCKF) && (i < RFE_TID_N); ++i) {
        /* the particles (unused by the sigma-point filter) */
        const rfe_real_t lw = c->tid.logw[i];
        if (isnan((double)lw) || lw > 0) {
            violation(c, "a log weight NaN or above 0", u, 0);
        }
        for (j = 0; j < RFE_TID_PAR; ++j) {
            const rfe_real_t x = c->tid.x[i][RFE_TID_STATES + j];
            if (!(x >= k->lo[j] && x <= k->hi[j])) {
                violation(c, "a particle's parameter outside its bounds", u, 0);
            }
        }
    }
    if (rfe_tyre_id_get(&c->tid, &got) != RFE_OK || memcmp(&got, e, sizeof got) != 0) {
        violation(c, "get does not return the last estimate", u, 0);
    }
}

static int step(void *ctxp, const fz_sample_t *s)
{
    fz_ctx_t *c = (fz_ctx_t *)ctxp;
    rfe_tyre_id_sample_t u;
    rfe_tyre_id_estimate_t out;
    rfe_status_t st;
    rfe_status_t want;
    if (c->k >= FZ_TID_STEPS) {
        return 1;
    }
    memset(&u, 0, sizeof u);
    u.delta = fz_to_real(s->v[0]);
    u.dt = fz_to_real(0.001 * s->v[1]);
    u.vx = fz_to_real(0.2 * s->v[7]);
    u.yaw_rate = fz_to_real(s->v[3]);
    u.ay = fz_to_real(s->v[6]);
    u.ax = fz_to_real(s->v[5]);
    want = expected(c, &u);
    memcpy(&c->before, &c->tid, sizeof c->tid);
    memset(&out, 0, sizeof out);
    st = rfe_tyre_id_step(&c->tid, &u, &out);
    if (st != want) {
        violation(c, (want == RFE_OK) ? "an error on a sample inside the limits"
                                      : "an input error not reported as its class",
                  &u, (int)st);
    }
    if (out.status != st) {
        violation(c, "the estimate's status is not the returned one", &u, (int)st);
    }
    if (st != RFE_OK) {
        if (memcmp(&c->tid, &c->before, sizeof c->tid) != 0) {
            violation(c, "a refused sample changed the identifier", &u, (int)st);
        }
        c->prev.status = st;
        if (memcmp(&out, &c->prev, sizeof out) != 0) {
            violation(c, "a refused sample did not report the previous estimate", &u, (int)st);
        }
    } else {
        check_output(c, &u, &out);
        c->prev = out;
        c->started = 1;
    }
    ++c->k;
    return 0;
}

/* §2 the bounds of the parameters, per axle from the static loads, against the state's. */
static void check_bounds(const rfe_tyre_id_t *t, const rfe_tyre_id_params_t *tp,
                         const rfe_params_t *veh)
{
    /* in the build's type, grouped as written (§9: m g Lr / (Lf + Lr) left to right), so
     * that a subnormal intermediate rounds as it does in the library */
    const rfe_real_t m = veh->vehicle.m;
    const rfe_real_t g = veh->vehicle.g;
    const rfe_real_t l = veh->vehicle.Lf + veh->vehicle.Lr;
    const rfe_real_t fzr[2] = {((m * g) * veh->vehicle.Lr) / l, ((m * g) * veh->vehicle.Lf) / l};
    int a;
    for (a = 0; a < 2; ++a) {
        const double lo[4] = {(double)(tp->mu_lo * fzr[a]), (double)tp->C_lo,
                              (double)(tp->cy_lo * fzr[a]), (double)tp->E_lo};
        const double hi[4] = {(double)(tp->mu_hi * fzr[a]), (double)tp->C_hi,
                              (double)(tp->cy_hi * fzr[a]), (double)tp->E_hi};
        int j;
        for (j = 0; j < 4; ++j) {
            const double lw = (double)t->c.lo[4 * a + j];
            const double hw = (double)t->c.hi[4 * a + j];
            /* usable bounds (init refuses others), equal to §2's */
            if (!(lw < hw) || lw != lo[j] || hw != hi[j]) {
                fprintf(stderr, "fuzz_tyre_id (%s): bound %d of axle %d is not TYRE_ID.md §2's\n",
                        FZ_BUILD, j, a);
                abort();
            }
        }
    }
}

#define TP_REAL 33
#define VEH_REAL 10

static void tp_fields(rfe_tyre_id_params_t *p, rfe_real_t *real[TP_REAL])
{
    rfe_real_t *const r[TP_REAL] = {
        &p->v_min,  &p->dt_max, &p->sd_r,   &p->sd_ay,  &p->sd_delta,   &p->q_vy,   &p->q_r,
        &p->q_mu,   &p->q_C,    &p->q_cy,   &p->q_E,    &p->mu0,        &p->sd0_mu, &p->sd0_C,
        &p->sd0_E,  &p->sd0_cy_rel, &p->sd0_vy, &p->sd0_r, &p->mu_lo,   &p->mu_hi,  &p->C_lo,
        &p->C_hi,   &p->cy_lo,  &p->cy_hi,  &p->E_lo,   &p->E_hi,       &p->neff_frac,
        &p->rough_k, &p->ellipse, &p->fx_front, &p->ell_min, &p->ell_ax_min, &p->delta_q,
        &p->delta_state_q};
    memcpy(real, r, sizeof r);
}

/* The vehicle and tyre data the identifier reads (rfe/tyre_id.h, init). */
static void veh_fields(rfe_params_t *p, rfe_real_t *real[VEH_REAL])
{
    rfe_real_t *const r[VEH_REAL] = {&p->vehicle.m,      &p->vehicle.Lf,     &p->vehicle.Lr,
                                     &p->vehicle.J,      &p->vehicle.hg,     &p->vehicle.g,
                                     &p->tyre.alpha_max, &p->tyre.cy,        &p->tyre.shape_Cy,
                                     &p->tyre.shape_Ey};
    memcpy(real, r, sizeof r);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    static fz_ctx_t c;
    fz_reader_t r;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_params_t tp_def;
    rfe_params_t veh;
    rfe_params_t veh_def;
    rfe_real_t *tp_real[TP_REAL];
    rfe_real_t *veh_real[VEH_REAL];
    uint32_t ints[4];
    uint32_t *const ints_p[4] = {&ints[0], &ints[1], &ints[2], &ints[3]};
    fzp_fields_t f;
    uint8_t cfg;
    uint64_t seed;
    rfe_status_t st;
    r.p = data;
    r.n = size;
    /* zeroed first, padding included: the harness compares whole states and outputs */
    memset(&tp, 0, sizeof tp);
    memset(&tp_def, 0, sizeof tp_def);
    memset(&veh, 0, sizeof veh);
    memset(&veh_def, 0, sizeof veh_def);
    memset(&c, 0, sizeof c);
    if (rfe_tyre_id_params_default(&tp_def) != RFE_OK || rfe_params_default(&veh_def) != RFE_OK) {
        abort();
    }
    cfg = fz_u8(&r);
    seed = fz_bytes(&r, 8);
    tp = tp_def;
    veh = veh_def;
    tp.filter = (cfg & 1u) ? RFE_TID_SIR : RFE_TID_APF;
    if ((cfg & 32u) != 0u) {
        tp.filter = RFE_TID_SCKF; /* the sigma-point filter (§15) */
    }
    tp.resample = (cfg & 2u) ? RFE_TID_SYSTEMATIC : RFE_TID_MULTINOMIAL;
    tp.substeps = 1u + ((cfg >> 2) & 7u);
    tp_def.filter = tp.filter;
    tp_def.resample = tp.resample;
    tp_def.substeps = tp.substeps;
    /* the integer fields through uint32 copies (two are enums) */
    ints[0] = (uint32_t)tp.filter;
    ints[1] = (uint32_t)tp.resample;
    ints[2] = tp.substeps;
    ints[3] = 0u;
    tp_fields(&tp, tp_real);
    f.real = tp_real;
    f.n_real = TP_REAL;
    f.u32 = ints_p;
    f.n_u32 = 3;
    (void)fzp_decode(&r, &f);
    tp.filter = (rfe_tid_filter_t)ints[0];
    tp.resample = (rfe_tid_resample_t)ints[1];
    tp.substeps = ints[2];
    veh_fields(&veh, veh_real);
    f.real = veh_real;
    f.n_real = VEH_REAL;
    f.u32 = ints_p;
    f.n_u32 = 0;
    (void)fzp_decode(&r, &f);
    memset(&c.tid, 0xA5, sizeof c.tid);
    memcpy(&c.before, &c.tid, sizeof c.tid);
    st = rfe_tyre_id_init(&c.tid, &tp, &veh, seed);
    if (st != RFE_OK && st != RFE_ERR_PARAM) {
        fprintf(stderr, "fuzz_tyre_id (%s): init returned %d\n", FZ_BUILD, (int)st);
        abort();
    }
    if (st != RFE_OK) {
        if (memcmp(&c.tid, &c.before, sizeof c.tid) != 0) {
            fprintf(stderr, "fuzz_tyre_id (%s): a refused init wrote the state\n", FZ_BUILD);
            abort();
        }
        memset(&c.tid, 0, sizeof c.tid);
        tp = tp_def;
        veh = veh_def;
        if (rfe_tyre_id_init(&c.tid, &tp, &veh, seed) != RFE_OK) {
            abort();
        }
    }
    check_bounds(&c.tid, &tp, &veh);
    if (rfe_tyre_id_get(&c.tid, &c.prev) != RFE_OK) {
        abort();
    }
    (void)fz_run(&r, step, &c);
    return 0;
}
