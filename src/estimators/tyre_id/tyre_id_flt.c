/**
 * @file tyre_id_flt.c
 * @brief The tyre identifier (docs/TYRE_ID.md): the input checks, the prior (§4.2), the
 *        auxiliary particle filter (§5.2) and the bootstrap filter (§5.6) with the patent's
 *        resampling (§5.4-5.5), and the outputs (§7); the sigma-point filter of §15 is
 *        tyre_id_sckf_flt.c's.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_TYRE_ID_IMPL
#include "rfe/tyre_id.h"

#include "estimators/tyre_id/tyre_id_internal.h"
#include "numerics/internal.h"

/* The purposes of the random stream, its counter word c2 (§6.3; 3 is reserved). */
#define PURPOSE_INIT 0u
#define PURPOSE_PROCESS 1u
#define PURPOSE_RESAMPLE 2u
#define PURPOSE_ROUGH 4u

/* Normal pairs per particle: the prior and the process noise (10 columns), the roughening
 * (8 parameters). */
#define PAIRS_DIM (RFE_TID_DIM / 2)
#define PAIRS_PAR (RFE_TID_PAR / 2)

/* The prior's centre, spread, bounds and walk of the axle with static load fz, into the four
 * parameter slots from j (§2, §4.2, §4.3). */
static void axle_constants(rfe_tid_consts_t *c, size_t j, rfe_real_t fz,
                           const rfe_tyre_id_params_t *p, const rfe_tyre_params_t *ty)
{
    c->lo[j] = p->mu_lo * fz;
    c->lo[j + 1u] = p->C_lo;
    c->lo[j + 2u] = p->cy_lo * fz;
    c->lo[j + 3u] = p->E_lo;
    c->hi[j] = p->mu_hi * fz;
    c->hi[j + 1u] = p->C_hi;
    c->hi[j + 2u] = p->cy_hi * fz;
    c->hi[j + 3u] = p->E_hi;
    c->q[j] = p->q_mu * fz;
    c->q[j + 1u] = p->q_C;
    c->q[j + 2u] = p->q_cy * fz;
    c->q[j + 3u] = p->q_E;
    c->mean0[j] = p->mu0 * fz;
    c->mean0[j + 1u] = ty->shape_Cy;
    c->mean0[j + 2u] = ty->cy * fz;
    c->mean0[j + 3u] = ty->shape_Ey;
    c->sd0[j] = p->sd0_mu * fz;
    c->sd0[j + 1u] = p->sd0_C;
    c->sd0[j + 2u] = (p->sd0_cy_rel * ty->cy) * fz;
    c->sd0[j + 3u] = p->sd0_E;
}

/* 1 when the derived constants can be used: every one finite, each parameter's bounds
 * lo < hi, and the smallest C D above 0 with K / (C D) finite (B, §7). Valid parameters and
 * vehicle data may still give none of this: the products with the axle loads underflow or
 * overflow where their factors did not (found by fuzz_tyre_id: m = 1.8e-27 kg, Lf = 1.4e-20 m
 * in float made D's bounds [0, 0], and B = 0 / 0). */
static int consts_usable(const rfe_tid_consts_t *c)
{
    const rfe_real_t cd_lo = c->lo[RFE_TID_C_F - RFE_TID_STATES] * c->lo[RFE_TID_D_F - RFE_TID_STATES];
    const rfe_real_t cd_lo_r = c->lo[RFE_TID_C_R - RFE_TID_STATES] * c->lo[RFE_TID_D_R - RFE_TID_STATES];
    const rfe_real_t v[3] = {c->fz0[0], c->fz0[1], c->gx};
    int ok = 1;
    size_t e;
    if ((rfe_all_finite(v, 3u) == 0) || (rfe_all_finite(c->lo, (size_t)RFE_TID_PAR) == 0) ||
        (rfe_all_finite(c->hi, (size_t)RFE_TID_PAR) == 0) ||
        (rfe_all_finite(c->q, (size_t)RFE_TID_PAR) == 0) ||
        (rfe_all_finite(c->sd0, (size_t)RFE_TID_PAR) == 0)) {
        ok = 0;
    }
    for (e = 0u; e < (size_t)RFE_TID_PAR; ++e) {
        if (!(c->lo[e] < c->hi[e])) {
            ok = 0;
        }
    }
    if (!(cd_lo > RFE_R(0.0)) || !(cd_lo_r > RFE_R(0.0)) ||
        (rfe_is_finite(c->hi[RFE_TID_K_F - RFE_TID_STATES] / cd_lo) == 0) ||
        (rfe_is_finite(c->hi[RFE_TID_K_R - RFE_TID_STATES] / cd_lo_r) == 0)) {
        ok = 0;
    }
    return ok;
}

/* The constants of §2-§5.5 from the parameters and the vehicle; 0 when a prior mean lies
 * outside its bounds (lo < hi is the parameters' own check) or they cannot be used
 * (consts_usable). */
static int derive(rfe_tid_consts_t *c, const rfe_tyre_id_params_t *p, const rfe_params_t *veh)
{
    const rfe_vehicle_t *v = &veh->vehicle;
    const rfe_real_t la = v->Lf + v->Lr;
    size_t e;
    c->m = v->m;
    c->Lf = v->Lf;
    c->Lr = v->Lr;
    c->J = v->J;
    c->alpha_max = veh->tyre.alpha_max;
    /* §3.4 Fz0_f = ((m g) Lr) / L, Fz0_r = ((m g) Lf) / L, G = (m hg) / L */
    c->fz0[0] = ((v->m * v->g) * v->Lr) / la;
    c->fz0[1] = ((v->m * v->g) * v->Lf) / la;
    c->gx = (v->m * v->hg) / la;
    /* §3.5 each axle's share of m ax, and the ellipse's bound on (Fx / (lam D))^2 */
    c->kxm[0] = p->fx_front * v->m;
    c->kxm[1] = (RFE_R(1.0) - p->fx_front) * v->m;
    c->u_max = RFE_R(1.0) - (p->ell_min * p->ell_min);
    axle_constants(c, 0u, c->fz0[0], p, &veh->tyre);
    axle_constants(c, 4u, c->fz0[1], p, &veh->tyre);
    /* §5.5 rho = K N^(-1/8), with the C library's pow (§9) */
    c->rough = p->rough_k * RFE_POW((rfe_real_t)RFE_TID_N, RFE_R(-1.0) / (rfe_real_t)RFE_TID_PAR);
    for (e = 0u; e < (size_t)RFE_TID_PAR; ++e) {
        if (!(c->lo[e] <= c->mean0[e]) || !(c->mean0[e] <= c->hi[e])) {
            return 0;
        }
    }
    return consts_usable(c);
}

rfe_status_t rfe_tyre_id_init(rfe_tyre_id_t *tid, const rfe_tyre_id_params_t *tp,
                              const rfe_params_t *veh, uint64_t seed, size_t size,
                              uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    rfe_tid_consts_t c;
    size_t i;
    size_t e;
    /* A caller built with another particle count, other maxima or another number type lays
     * the state out differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*tid)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if ((tid == NULL) || (tp == NULL) || (veh == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((rfe_tyre_id_params_validate(tp) != RFE_OK) || (rfe_params_validate(veh) != RFE_OK) ||
        (derive(&c, tp, veh) == 0)) {
        return RFE_ERR_PARAM;
    }
    tid->p = *tp;
    tid->c = c;
    tid->seed = seed;
    tid->k = 0u;
    tid->started = 0u;
    tid->prev_delta = RFE_R(0.0);
    tid->prev_vx = RFE_R(0.0);
    tid->prev_ax = RFE_R(0.0);
    for (i = 0u; i < 5u; ++i) {
        tid->dlt[i] = RFE_R(0.0);
    }
    tid->sd_delta = tp->sd_delta;
    for (i = 0u; i < (size_t)RFE_TID_N; ++i) {
        for (e = 0u; e < (size_t)RFE_TID_DIM; ++e) {
            tid->x[i][e] = RFE_R(0.0);
        }
        tid->logw[i] = RFE_R(0.0);
    }
    tid->last = (rfe_tyre_id_estimate_t){0};
    tid->sk = (rfe_tid_sckf_t){0};
    tid->magic = RFE_MAGIC_TID;
    return RFE_OK;
}

/* Normal pair p of the stream s (the identifier's own: the call cannot fail). */
static void normal_pair(rfe_philox_t *s, size_t p, rfe_real_t z[2])
{
    const rfe_status_t st = rfe_philox_normal_pair(s, (uint64_t)p, z);
    (void)st; /* fails only for NULL arguments, which these are not */
}

/* The stream of this sample and purpose (§6.3): key (seed, 0), counter (j, k, purpose, 0). */
static void stream_of(const rfe_tyre_id_t *t, uint64_t purpose, rfe_philox_t *s)
{
    const rfe_status_t st = rfe_philox_stream(s, t->seed, t->k, purpose);
    (void)st; /* fails only for a NULL stream */
}

/* §4.2 the prior at this sample (purpose 0): vy = 0 + sd0_vy z0, r = r_m + sd0_r z1,
 * theta = reflect(mean0 + sd0 z); log weights 0. */
static void draw_prior(rfe_tyre_id_t *t, rfe_real_t r_meas)
{
    rfe_philox_t s;
    size_t i;
    stream_of(t, PURPOSE_INIT, &s);
    for (i = 0u; i < (size_t)RFE_TID_N; ++i) {
        rfe_real_t z[RFE_TID_DIM];
        size_t e;
        for (e = 0u; e < (size_t)PAIRS_DIM; ++e) {
            normal_pair(&s, (i * (size_t)PAIRS_DIM) + e, &z[2u * e]);
        }
        t->x[i][RFE_TID_VY] = RFE_R(0.0) + (t->p.sd0_vy * z[0]);
        t->x[i][RFE_TID_R] = r_meas + (t->p.sd0_r * z[1]);
        for (e = 0u; e < (size_t)RFE_TID_PAR; ++e) {
            t->x[i][RFE_TID_STATES + e] =
                rfe_tid_reflect(t->c.mean0[e] + (t->c.sd0[e] * z[RFE_TID_STATES + e]),
                                t->c.lo[e], t->c.hi[e]);
        }
        t->logw[i] = RFE_R(0.0);
    }
}

/* §4.3 the process noise's scale per column, q s with s = sqrt(h): (q_vy s, q_r s, q_e s),
 * the same products for every particle, so made once a step. */
static void noise_scales(const rfe_tyre_id_t *t, rfe_real_t sq, rfe_real_t qs[RFE_TID_DIM])
{
    size_t e;
    qs[RFE_TID_VY] = t->p.q_vy * sq;
    qs[RFE_TID_R] = t->p.q_r * sq;
    for (e = 0u; e < (size_t)RFE_TID_PAR; ++e) {
        qs[RFE_TID_STATES + e] = t->c.q[e] * sq;
    }
}

/* §4.3 the process noise of slot i (purpose 1) on the columns src, into dst, with the scales
 * qs of noise_scales: vy + (q_vy s) z0, r + (q_r s) z1, reflect(theta + (q s) z). */
static void add_noise(const rfe_tyre_id_t *t, rfe_philox_t *s, size_t i,
                      const rfe_real_t qs[RFE_TID_DIM], const rfe_real_t src[RFE_TID_DIM],
                      rfe_real_t dst[RFE_TID_DIM])
{
    rfe_real_t z[RFE_TID_DIM];
    size_t e;
    for (e = 0u; e < (size_t)PAIRS_DIM; ++e) {
        normal_pair(s, (i * (size_t)PAIRS_DIM) + e, &z[2u * e]);
    }
    dst[RFE_TID_VY] = src[RFE_TID_VY] + (qs[RFE_TID_VY] * z[0]);
    dst[RFE_TID_R] = src[RFE_TID_R] + (qs[RFE_TID_R] * z[1]);
    for (e = 0u; e < (size_t)RFE_TID_PAR; ++e) {
        const size_t col = RFE_TID_STATES + e;
        dst[col] = rfe_tid_reflect(src[col] + (qs[col] * z[col]), t->c.lo[e], t->c.hi[e]);
    }
}

/* The columns of particle i with its states replaced by its auxiliary point. */
static void aux_columns(const rfe_tyre_id_t *t, size_t i, rfe_real_t out[RFE_TID_DIM])
{
    size_t e;
    out[RFE_TID_VY] = t->aux[i][0];
    out[RFE_TID_R] = t->aux[i][1];
    for (e = RFE_TID_STATES; e < (size_t)RFE_TID_DIM; ++e) {
        out[e] = t->x[i][e];
    }
}

/* §5.4-5.5 the patent's resampling on the first-stage weights t->w (N_eff n_eff): slot
 * j < L the particle of rank j, slot L + j a copy of parent j (purpose 2) with its
 * parameters roughened (purpose 4), into t->nx with the ancestors in t->idx. */
static void rough_resample(rfe_tyre_id_t *t, rfe_real_t n_eff)
{
    const size_t n = (size_t)RFE_TID_N;
    const size_t keep = (n_eff >= (rfe_real_t)RFE_TID_N) ? n : (size_t)n_eff; /* floor */
    rfe_real_t spread[RFE_TID_PAR];
    rfe_philox_t s;
    size_t j;
    size_t e;
    rfe_tid_order(t->w, n, t->order, t->tmp);
    rfe_tid_cumsum(t->w, n, t->cum);
    stream_of(t, PURPOSE_RESAMPLE, &s);
    rfe_tid_draw(t->cum, n, &s, t->p.resample, n - keep, &t->idx[keep]);
    /* E_e rho: the parameters' range over every particle before the resampling */
    for (e = 0u; e < (size_t)RFE_TID_PAR; ++e) {
        rfe_real_t lo = t->x[0][RFE_TID_STATES + e];
        rfe_real_t hi = lo;
        for (j = 1u; j < n; ++j) {
            lo = rfe_min(lo, t->x[j][RFE_TID_STATES + e]);
            hi = rfe_max(hi, t->x[j][RFE_TID_STATES + e]);
        }
        spread[e] = (hi - lo) * t->c.rough;
    }
    for (j = 0u; j < keep; ++j) {
        t->idx[j] = t->order[j];
        aux_columns(t, (size_t)t->order[j], t->nx[j]);
    }
    stream_of(t, PURPOSE_ROUGH, &s);
    for (j = keep; j < n; ++j) {
        rfe_real_t z[RFE_TID_PAR];
        aux_columns(t, (size_t)t->idx[j], t->nx[j]);
        for (e = 0u; e < (size_t)PAIRS_PAR; ++e) {
            normal_pair(&s, (j * (size_t)PAIRS_PAR) + e, &z[2u * e]);
        }
        for (e = 0u; e < (size_t)RFE_TID_PAR; ++e) {
            const size_t col = RFE_TID_STATES + e;
            t->nx[j][col] = rfe_tid_reflect(t->nx[j][col] + (spread[e] * z[e]), t->c.lo[e],
                                            t->c.hi[e]);
        }
    }
}

/* Every weight zero: the prior again at this sample (§7, LOST). */
static uint32_t lost(rfe_tyre_id_t *t, rfe_real_t r_meas)
{
    draw_prior(t, r_meas);
    return RFE_TID_LOST;
}

/* The noise-free RK4 step of every particle at the period's mean inputs (§4.1). */
static void aux_points(rfe_tyre_id_t *t, const rfe_tyre_id_sample_t *smp)
{
    const rfe_tid_input_t ub = rfe_tid_mean_input(t, smp);
    size_t i;
    for (i = 0u; i < (size_t)RFE_TID_N; ++i) {
        rfe_tid_rk4(t, t->x[i], &ub, smp->dt, t->aux[i]);
    }
}

/* §5.2 the auxiliary particle filter's step at the sample's inputs u. */
static uint32_t apf_step(rfe_tyre_id_t *t, const rfe_tyre_id_sample_t *smp,
                         const rfe_tid_input_t *u)
{
    const size_t n = (size_t)RFE_TID_N;
    rfe_real_t qs[RFE_TID_DIM];
    uint32_t flags = RFE_TID_UPDATED;
    rfe_philox_t s;
    rfe_real_t n_eff;
    size_t i;
    noise_scales(t, RFE_SQRT(smp->dt), qs);
    aux_points(t, smp);
    /* first stage: lambda_i = l_i + l(mu_i, theta_i), normalised (cum holds lambda) */
    for (i = 0u; i < n; ++i) {
        t->la[i] = rfe_tid_loglik(t, t->aux[i][0], t->aux[i][1], &t->x[i][RFE_TID_STATES], u,
                                  smp->yaw_rate, smp->ay, NULL);
        t->cum[i] = t->logw[i] + t->la[i];
    }
    if (rfe_tid_normalise(t->cum, n, t->w, NULL) == 0) {
        return lost(t, smp->yaw_rate);
    }
    n_eff = rfe_tid_neff(t->w, n);
    stream_of(t, PURPOSE_PROCESS, &s);
    if (n_eff < (t->p.neff_frac * (rfe_real_t)RFE_TID_N)) {
        /* the draw; second stage l_j = l(x_j) - l(mu_a_j, theta_a_j) (the auxiliary points
         * are in nx now: aux takes the particle's forces for the outputs) */
        rough_resample(t, n_eff);
        for (i = 0u; i < n; ++i) {
            add_noise(t, &s, i, qs, t->nx[i], t->x[i]);
            t->logw[i] = rfe_tid_loglik(t, t->x[i][RFE_TID_VY], t->x[i][RFE_TID_R],
                                        &t->x[i][RFE_TID_STATES], u, smp->yaw_rate, smp->ay,
                                        t->aux[i]) -
                         t->la[t->idx[i]];
        }
        flags |= RFE_TID_RESAMPLED;
    } else {
        /* no draw: l_i + l(x_i) (the first stage's factor cancels); aux_i, read, takes the
         * particle's forces for the outputs */
        for (i = 0u; i < n; ++i) {
            rfe_real_t cols[RFE_TID_DIM];
            aux_columns(t, i, cols);
            add_noise(t, &s, i, qs, cols, t->x[i]);
            t->logw[i] = t->logw[i] + rfe_tid_loglik(t, t->x[i][RFE_TID_VY], t->x[i][RFE_TID_R],
                                                     &t->x[i][RFE_TID_STATES], u,
                                                     smp->yaw_rate, smp->ay, t->aux[i]);
        }
    }
    if (rfe_tid_normalise(t->logw, n, t->w, t->logw) == 0) {
        return lost(t, smp->yaw_rate);
    }
    return flags;
}

/* §5.6 the bootstrap filter's step: propagate with noise, weigh, resample N parents (no
 * roughening) when N_eff < neff_frac N. */
static uint32_t sir_step(rfe_tyre_id_t *t, const rfe_tyre_id_sample_t *smp,
                         const rfe_tid_input_t *u)
{
    const size_t n = (size_t)RFE_TID_N;
    rfe_real_t qs[RFE_TID_DIM];
    uint32_t flags = RFE_TID_UPDATED;
    rfe_philox_t s;
    size_t i;
    noise_scales(t, RFE_SQRT(smp->dt), qs);
    aux_points(t, smp);
    stream_of(t, PURPOSE_PROCESS, &s);
    for (i = 0u; i < n; ++i) {
        rfe_real_t cols[RFE_TID_DIM];
        aux_columns(t, i, cols);
        add_noise(t, &s, i, qs, cols, t->x[i]);
        t->logw[i] = t->logw[i] + rfe_tid_loglik(t, t->x[i][RFE_TID_VY], t->x[i][RFE_TID_R],
                                                 &t->x[i][RFE_TID_STATES], u, smp->yaw_rate,
                                                 smp->ay, NULL);
    }
    if (rfe_tid_normalise(t->logw, n, t->w, t->logw) == 0) {
        return lost(t, smp->yaw_rate);
    }
    if (rfe_tid_neff(t->w, n) < (t->p.neff_frac * (rfe_real_t)RFE_TID_N)) {
        size_t e;
        rfe_tid_cumsum(t->w, n, t->cum);
        stream_of(t, PURPOSE_RESAMPLE, &s);
        rfe_tid_draw(t->cum, n, &s, t->p.resample, n, t->idx);
        for (i = 0u; i < n; ++i) {
            for (e = 0u; e < (size_t)RFE_TID_DIM; ++e) {
                t->nx[i][e] = t->x[t->idx[i]][e];
            }
        }
        for (i = 0u; i < n; ++i) {
            for (e = 0u; e < (size_t)RFE_TID_DIM; ++e) {
                t->x[i][e] = t->nx[i][e];
            }
            t->logw[i] = RFE_R(0.0);
        }
        flags |= RFE_TID_RESAMPLED;
    }
    return flags;
}

/* §7 output q of particle i (its forces in aux, its beta in la, the axle loads fz). */
static void outputs_of(const rfe_tyre_id_t *t, size_t i, const rfe_real_t fz[2],
                       rfe_real_t q[RFE_TID_OUTPUTS])
{
    const rfe_real_t *x = t->x[i];
    size_t e;
    q[RFE_TID_OUT_BETA] = t->la[i];
    q[RFE_TID_OUT_R] = x[RFE_TID_R];
    q[RFE_TID_OUT_VY] = x[RFE_TID_VY];
    q[RFE_TID_OUT_FY_F] = t->aux[i][0];
    q[RFE_TID_OUT_FY_R] = t->aux[i][1];
    for (e = 0u; e < (size_t)RFE_TID_PAR; ++e) {
        q[RFE_TID_OUT_D_F + e] = x[RFE_TID_STATES + e];
    }
    q[RFE_TID_OUT_B_F] = x[RFE_TID_K_F] / (x[RFE_TID_C_F] * x[RFE_TID_D_F]);
    q[RFE_TID_OUT_B_R] = x[RFE_TID_K_R] / (x[RFE_TID_C_R] * x[RFE_TID_D_R]);
    q[RFE_TID_OUT_MU_F] = x[RFE_TID_D_F] / fz[0];
    q[RFE_TID_OUT_MU_R] = x[RFE_TID_D_R] / fz[1];
}

/* §7 the sd of output k when the plain sum of squares overflowed (a spread beyond the
 * square root of the type's range, with data scaled far beyond a car's: found by
 * fuzz_tyre_id, m = 1.8e23 kg in float): the same sum with every value divided by the
 * largest magnitude first. Never reached on a car's data, so the double build's plain sums
 * stay the reference's bit for bit. */
static void rescaled_sd(rfe_tyre_id_t *t, const rfe_real_t fz[2], size_t k)
{
    rfe_tyre_id_estimate_t *e = &t->last;
    rfe_real_t q[RFE_TID_OUTPUTS];
    rfe_real_t s = RFE_FABS(e->mean[k]);
    rfe_real_t acc = RFE_R(0.0);
    size_t i;
    for (i = 0u; i < (size_t)RFE_TID_N; ++i) {
        if (t->w[i] != RFE_R(0.0)) {
            outputs_of(t, i, fz, q);
            s = rfe_max(s, RFE_FABS(q[k]));
        }
    }
    if ((s > RFE_R(0.0)) && (rfe_is_finite(s) != 0)) {
        for (i = 0u; i < (size_t)RFE_TID_N; ++i) {
            if (t->w[i] != RFE_R(0.0)) {
                rfe_real_t d;
                outputs_of(t, i, fz, q);
                d = (q[k] / s) - (e->mean[k] / s);
                acc += t->w[i] * (d * d);
            }
        }
        e->sd[k] = s * RFE_SQRT(acc);
    }
}

/* §7 weighted means and sds at this sample's inputs (sums in particle order; a particle of
 * weight 0 adds exactly 0 and is skipped, so a diverged one cannot turn a sum into NaN).
 * forces_in_aux: the APF stepped, and unless the step was lost (new particles) its second stage
 * left every particle's forces at these inputs in aux (rfe_tid_ay's, bit for bit
 * rfe_tid_forces'), so they are not computed again. */
static void estimate(rfe_tyre_id_t *t, const rfe_tyre_id_sample_t *smp,
                     const rfe_tid_input_t *u, uint32_t flags, int forces_in_aux)
{
    const size_t n = (size_t)RFE_TID_N;
    rfe_tyre_id_estimate_t *e = &t->last;
    rfe_real_t fz[2];
    rfe_real_t q[RFE_TID_OUTPUTS];
    size_t i;
    size_t k;
    /* the weights are normalised log weights: their maximum is 0, never lost */
    (void)rfe_tid_normalise(t->logw, n, t->w, NULL);
    rfe_tid_mu_loads(t, smp->ax, fz);
    for (i = 0u; i < n; ++i) {
        if ((forces_in_aux == 0) || ((flags & RFE_TID_LOST) != 0u)) {
            rfe_tid_forces(t, t->x[i], u, &t->aux[i][0], &t->aux[i][1]);
        }
        t->la[i] = RFE_ATAN2(t->x[i][RFE_TID_VY], smp->vx);
    }
    for (k = 0u; k < (size_t)RFE_TID_OUTPUTS; ++k) {
        e->mean[k] = RFE_R(0.0);
        e->sd[k] = RFE_R(0.0);
    }
    for (i = 0u; i < n; ++i) {
        if (t->w[i] != RFE_R(0.0)) {
            outputs_of(t, i, fz, q);
            for (k = 0u; k < (size_t)RFE_TID_OUTPUTS; ++k) {
                e->mean[k] += t->w[i] * q[k];
            }
        }
    }
    for (i = 0u; i < n; ++i) {
        if (t->w[i] != RFE_R(0.0)) {
            outputs_of(t, i, fz, q);
            for (k = 0u; k < (size_t)RFE_TID_OUTPUTS; ++k) {
                const rfe_real_t d = q[k] - e->mean[k];
                e->sd[k] += t->w[i] * (d * d);
            }
        }
    }
    for (k = 0u; k < (size_t)RFE_TID_OUTPUTS; ++k) {
        e->sd[k] = RFE_SQRT(e->sd[k]);
        if (rfe_is_finite(e->sd[k]) == 0) {
            rescaled_sd(t, fz, k);
        }
    }
    e->n_eff = rfe_tid_neff(t->w, n);
    e->flags = flags;
    e->status = RFE_OK;
}

/* §1 the sample: finite; inside config.h's limits, with positive axle loads (§3.4);
 * after the first, dt in (0, dt_max]. */
static rfe_status_t check_tid_sample(const rfe_tyre_id_t *t, const rfe_tyre_id_sample_t *smp)
{
    const rfe_real_t v[6] = {smp->dt, smp->delta, smp->vx, smp->yaw_rate, smp->ay, smp->ax};
    if (rfe_all_finite(v, 6u) == 0) {
        return RFE_ERR_NONFINITE;
    }
    if ((RFE_FABS(smp->delta) > RFE_R(RFE_LIMIT_DELTA)) ||
        (RFE_FABS(smp->vx) > RFE_R(RFE_LIMIT_VX)) ||
        (RFE_FABS(smp->yaw_rate) > RFE_R(RFE_LIMIT_YAW_RATE)) ||
        (RFE_FABS(smp->ay) > RFE_R(RFE_LIMIT_ACC)) || (RFE_FABS(smp->ax) > RFE_R(RFE_LIMIT_ACC))) {
        return RFE_ERR_RANGE;
    }
    /* an ax that would lift an axle is outside the model */
    if (!((t->c.fz0[0] - (t->c.gx * smp->ax)) > RFE_R(0.0)) ||
        !((t->c.fz0[1] + (t->c.gx * smp->ax)) > RFE_R(0.0))) {
        return RFE_ERR_RANGE;
    }
    if ((t->started != 0u) && (!(smp->dt > RFE_R(0.0)) || (smp->dt > t->p.dt_max))) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* §4.4 the steering-angle filter (delta_q > 0): a two-state Kalman filter of delta and its
 * rate (constant rate, white acceleration of density delta_q, the measured delta with sd
 * sd_delta) replaces the sample's delta by its posterior mean and the steering noise by its
 * posterior sd; the first sample starts it at (delta, 0) with p00 = sd_delta^2. Each
 * operation rounded as the reference's (tyre_id.py _delta_filter). */
static void delta_filter(rfe_tyre_id_t *t, rfe_tyre_id_sample_t *s)
{
    const rfe_real_t q = t->p.delta_q;
    const rfe_real_t rv = t->p.sd_delta * t->p.sd_delta;
    rfe_real_t *f = t->dlt;
    if (t->started == 0u) {
        f[0] = s->delta;
        f[1] = RFE_R(0.0);
        f[2] = rv;
        f[3] = RFE_R(0.0);
        f[4] = RFE_R(0.0);
    } else {
        const rfe_real_t h = s->dt;
        const rfe_real_t qq = q * q;
        const rfe_real_t d = f[0] + (h * f[1]);
        const rfe_real_t p00 =
            (f[2] + (h * ((RFE_R(2.0) * f[3]) + (h * f[4])))) + ((((qq * h) * h) * h) / RFE_R(3.0));
        const rfe_real_t p01 = (f[3] + (h * f[4])) + (((qq * h) * h) * RFE_R(0.5));
        const rfe_real_t p11 = f[4] + (qq * h);
        const rfe_real_t sv = p00 + rv;
        const rfe_real_t k0 = p00 / sv;
        const rfe_real_t k1 = p01 / sv;
        const rfe_real_t e = s->delta - d;
        f[0] = d + (k0 * e);
        f[1] = f[1] + (k1 * e);
        f[4] = p11 - (k1 * p01);
        f[3] = p01 - (k0 * p01);
        f[2] = p00 - (k0 * p00);
    }
    t->sd_delta = RFE_SQRT(f[2]);
    s->delta = f[0];
}

rfe_status_t rfe_tyre_id_step(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *s,
                              rfe_tyre_id_estimate_t *out)
{
    rfe_tyre_id_sample_t sf;
    rfe_tid_input_t u;
    uint32_t flags;
    int forces_in_aux = 0;
    rfe_status_t st;
    if ((tid == NULL) || (s == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (tid->magic != RFE_MAGIC_TID) {
        return RFE_ERR_NOT_INITIALISED;
    }
    st = check_tid_sample(tid, s);
    if (st != RFE_OK) {
        *out = tid->last;
        out->status = st;
        return st;
    }
    sf = *s;
    if (tid->p.delta_q > RFE_R(0.0)) {
        delta_filter(tid, &sf);
    }
    u.delta = sf.delta;
    u.cd = RFE_COS(sf.delta);
    u.sd = RFE_SIN(sf.delta);
    u.vx = sf.vx;
    u.ax = sf.ax;
    if (tid->started == 0u) {
        if (tid->p.filter == RFE_TID_SCKF) {
            rfe_tid_sckf_prior(tid, sf.yaw_rate, sf.delta);
        } else {
            draw_prior(tid, sf.yaw_rate);
        }
        tid->started = 1u;
        flags = RFE_TID_FIRST;
    } else if ((sf.vx < tid->p.v_min) || (tid->prev_vx < tid->p.v_min)) {
        flags = RFE_TID_HELD;
    } else if (tid->p.filter == RFE_TID_APF) {
        flags = apf_step(tid, &sf, &u);
        forces_in_aux = 1;
    } else if (tid->p.filter == RFE_TID_SIR) {
        flags = sir_step(tid, &sf, &u);
    } else {
        flags = rfe_tid_sckf_step(tid, &sf, &u);
    }
    tid->prev_delta = sf.delta;
    tid->prev_vx = sf.vx;
    tid->prev_ax = sf.ax;
    if (tid->p.filter == RFE_TID_SCKF) {
        rfe_tid_sckf_estimate(tid, &sf, &u, flags);
    } else {
        estimate(tid, &sf, &u, flags, forces_in_aux);
    }
    tid->k += 1u;
    *out = tid->last;
    return RFE_OK;
}

rfe_status_t rfe_tyre_id_get(const rfe_tyre_id_t *tid, rfe_tyre_id_estimate_t *out)
{
    if ((tid == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (tid->magic != RFE_MAGIC_TID) {
        return RFE_ERR_NOT_INITIALISED;
    }
    *out = tid->last;
    return RFE_OK;
}
