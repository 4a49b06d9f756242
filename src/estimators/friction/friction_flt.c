/**
 * @file friction_flt.c
 * @brief The friction estimator: one step of docs/ESTIMATOR.md (MODEL.md §5-6 when every
 *        addition is off): conditioner -> SCKF/CKF time update -> meas, step noise -> SCKF gated
 *        update -> sd bounds -> projection -> per-wheel estimate.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_FRICTION_IMPL
#include "rfe/friction.h"

#include "rfe/component/chol.h"
#include "rfe/component/step_noise.h"

#include "estimators/friction/friction_logic.h"
#include "estimators/friction/step_noise_internal.h"
#include "numerics/internal.h"

#define NM ((size_t)RFE_N_MAX)

/* C99 static assertion: the filters' compile-time maxima must hold the estimator's
 * four states and three measurements (a -DRFE_N_MAX=4 -DRFE_M_MAX=3 build is the smallest). */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_maxima_hold_estimator[((RFE_N_MAX >= RFE_WHEELS) && (RFE_M_MAX >= RFE_MEAS)) ? 1 : -1];

/* State index of wheel w: the map T (docs/ESTIMATOR.md). wheels: T = I; sides: fl, rl on
 * the left state 0, fr, rr on the right state 1. */
static size_t state_of(const rfe_friction_t *est, size_t w)
{
    return rfe_friction_state_index(est->params.filter.structure, w);
}

/* mu per wheel = T x. */
static void to_wheels(const rfe_friction_t *est, const rfe_real_t *x,
                      rfe_real_t mu[RFE_WHEELS])
{
    size_t w;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        mu[w] = x[state_of(est, w)];
    }
}

/* h(T x, u) for one cubature point; a point with mu < 0 is evaluated at mu = 0
 * by the load-scaled tyres (absolute Dugoff, MODEL.md §4; Magic Formula, docs/ESTIMATOR.md). */
static rfe_status_t measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n, size_t m)
{
    /* cppcheck-suppress misra-c2012-11.5 ; MISRA-DEV-05: ctx is the est this file passes */
    const rfe_friction_t *est = (const rfe_friction_t *)ctx;
    rfe_real_t mu[RFE_WHEELS];
    (void)n;
    (void)m;
    to_wheels(est, x, mu);
    return rfe_meas_eval(&est->meas, &est->params.vehicle, &est->params.tyre, mu, z);
}

/* sqrt_prior(d, c) (n x n, ld n): the lower Cholesky factor of c^2 11^T + d^2 I; exactly
 * d I when c = 0 (no Cholesky, so the paper preset's factors are bit-exact). */
static rfe_status_t sqrt_prior(rfe_real_t d, rfe_real_t c, size_t n, rfe_real_t *F)
{
    rfe_real_t P[RFE_WHEELS * RFE_WHEELS];
    const rfe_real_t d2 = d * d;
    size_t i;
    size_t j;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            const rfe_real_t diag = (i == j) ? d2 : RFE_R(0.0);
            F[(i * n) + j] = (i == j) ? d : RFE_R(0.0);
            P[(i * n) + j] = (c * c) + diag;
        }
    }
    return (c == RFE_R(0.0)) ? RFE_OK : rfe_chol_factor(P, n, n, F, n);
}

/* The SCKF's prior: x0 = mu0, S0 and S_Q from sqrt_prior (sd0, q_mu with their common
 * parts), S_R = diag(r_ax, r_ay, r_yaw_acc). */
static rfe_status_t init_sckf(rfe_friction_t *est, const rfe_filter_params_t *fp,
                              size_t n)
{
    rfe_real_t x0[RFE_WHEELS];
    rfe_real_t S0[RFE_WHEELS * RFE_WHEELS];
    rfe_real_t SQ[RFE_WHEELS * RFE_WHEELS];
    rfe_real_t SR[RFE_MEAS * RFE_MEAS] = {0};
    size_t i;
    rfe_status_t st;
    for (i = 0u; i < n; ++i) {
        x0[i] = fp->mu0;
    }
    SR[0] = fp->r_ax;
    SR[RFE_MEAS + 1] = fp->r_ay;
    SR[(2 * RFE_MEAS) + 2] = fp->r_yaw_acc;
    st = sqrt_prior(fp->sd0, fp->sd0_common, n, S0);
    if (st == RFE_OK) {
        st = sqrt_prior(fp->q_mu, fp->q_common, n, SQ);
    }
    if (st == RFE_OK) {
        /* the library's own layout: the init called directly, not through its wrapper */
        st = (rfe_sckf_init)(&est->filter.sckf, n, RFE_MEAS, x0, S0, SQ, SR,
                             sizeof(est->filter.sckf), RFE_CONFIG_REAL);
    }
    return st;
}

/* The CKF runs only the paper subset (rfe_params_validate): P0 = sd0^2 I, Q = q_mu^2 I. */
static rfe_status_t init_ckf(rfe_friction_t *est, const rfe_filter_params_t *fp)
{
    rfe_real_t x0[RFE_WHEELS];
    rfe_real_t P0[RFE_WHEELS * RFE_WHEELS];
    rfe_real_t Q[RFE_WHEELS * RFE_WHEELS];
    rfe_real_t R[RFE_MEAS * RFE_MEAS] = {0};
    size_t i;
    size_t j;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        x0[i] = fp->mu0;
        for (j = 0u; j < (size_t)RFE_WHEELS; ++j) {
            const rfe_real_t on = (i == j) ? RFE_R(1.0) : RFE_R(0.0);
            P0[(i * RFE_WHEELS) + j] = on * (fp->sd0 * fp->sd0);
            Q[(i * RFE_WHEELS) + j] = on * (fp->q_mu * fp->q_mu);
        }
    }
    R[0] = fp->r_ax * fp->r_ax;
    R[RFE_MEAS + 1] = fp->r_ay * fp->r_ay;
    R[(2 * RFE_MEAS) + 2] = fp->r_yaw_acc * fp->r_yaw_acc;
    return (rfe_ckf_init)(&est->filter.ckf, RFE_WHEELS, RFE_MEAS, x0, P0, Q, R,
                          sizeof(est->filter.ckf), RFE_CONFIG_REAL);
}

rfe_status_t rfe_friction_init(rfe_friction_t *est, const rfe_params_t *params,
                               size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    const rfe_filter_params_t *fp;
    size_t n;
    rfe_status_t st;

    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*est)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if ((est == NULL) || (params == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_params_validate(params);
    if (st != RFE_OK) {
        return st;
    }
    fp = &params->filter;
    n = (fp->structure == RFE_STRUCT_SIDES) ? 2u : (size_t)RFE_WHEELS;
    /* Nothing below fails for validated parameters (positive sd0, q_mu: the prior is
     * positive definite); a failure would leave the estimator not initialised. */
    st = (fp->kind == RFE_FILTER_CKF) ? init_ckf(est, fp) : init_sckf(est, fp, n);
    if (st == RFE_OK) {
        /* the library's own layout: the inits called directly, not through their wrappers */
        st = (rfe_conditioner_init)(&est->cond, sizeof(est->cond), RFE_CONFIG_REAL);
    }
    if (st == RFE_OK) {
        st = (rfe_monitor_init)(&est->mon, &params->monitor, fp->dt, sizeof(est->mon),
                                RFE_CONFIG_REAL);
    }
    if (st != RFE_OK) {
        return st;
    }
    est->params = *params;
    est->n = n;
    est->backup_cond = est->cond;
    est->backup_mon = est->mon;
    est->magic = RFE_MAGIC_EST;
    return RFE_OK;
}

/* RFE_ERR_RANGE for a physically implausible (finite) sample: limits in config.h. */
static rfe_status_t sample_in_range(const rfe_sample_t *u)
{
    size_t i;
    if ((RFE_FABS(u->delta) > RFE_R(RFE_LIMIT_DELTA)) || (RFE_FABS(u->vx) > RFE_R(RFE_LIMIT_VX)) ||
        (RFE_FABS(u->vy) > RFE_R(RFE_LIMIT_VY)) ||
        (RFE_FABS(u->yaw_rate) > RFE_R(RFE_LIMIT_YAW_RATE)) ||
        (RFE_FABS(u->yaw_acc) > RFE_R(RFE_LIMIT_YAW_ACC)) ||
        (RFE_FABS(u->ax) > RFE_R(RFE_LIMIT_ACC)) || (RFE_FABS(u->ay) > RFE_R(RFE_LIMIT_ACC))) {
        return RFE_ERR_RANGE;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if (RFE_FABS(u->omega[i]) > RFE_R(RFE_LIMIT_OMEGA)) {
            return RFE_ERR_RANGE;
        }
    }
    return RFE_OK;
}

/* Rejects non-finite samples (RFE_ERR_NONFINITE) and physically implausible ones
 * (RFE_ERR_RANGE, limits in config.h). */
static rfe_status_t check_sample(const rfe_sample_t *u)
{
    if (!rfe_is_finite(u->delta) || !rfe_is_finite(u->vx) || !rfe_is_finite(u->vy) ||
        !rfe_is_finite(u->yaw_rate) || !rfe_is_finite(u->yaw_acc) || !rfe_is_finite(u->ax) ||
        !rfe_is_finite(u->ay) || !rfe_all_finite(u->omega, RFE_WHEELS)) {
        return RFE_ERR_NONFINITE;
    }
    return sample_in_range(u);
}

/* Saves / restores what a step changes (filter mean and factor, input filter; in float the
 * monitor, in fixed point the saturation counters) so a failing step changes nothing. */
static void backup(rfe_friction_t *est, int restore)
{
    const rfe_filter_kind_t kind = est->params.filter.kind;
    rfe_real_t *x = (kind == RFE_FILTER_CKF) ? est->filter.ckf.x : est->filter.sckf.x;
    rfe_real_t *F = (kind == RFE_FILTER_CKF) ? est->filter.ckf.P : est->filter.sckf.S;
    size_t i;
    for (i = 0u; i < NM; ++i) {
        if (restore != 0) {
            x[i] = est->backup_x[i];
        } else {
            est->backup_x[i] = x[i];
        }
    }
    for (i = 0u; i < (NM * NM); ++i) {
        if (restore != 0) {
            F[i] = est->backup_S[i];
        } else {
            est->backup_S[i] = F[i];
        }
    }
    if (restore != 0) {
        est->cond = est->backup_cond;
        est->mon = est->backup_mon;
    } else {
        est->backup_cond = est->cond;
        est->backup_mon = est->mon;
    }
}

/* Step 4 runs when any part of it is switched on. */
static int step_noise_active(const rfe_filter_params_t *fp)
{
    const rfe_real_t zero = RFE_R(0.0);
    return ((fp->r_model_rel > zero) || (fp->sd_in_delta > zero) || (fp->sd_in_vx > zero) ||
            (fp->sd_in_vy > zero) || (fp->sd_in_yaw_rate > zero) || (fp->sd_in_omega > zero))
               ? 1
               : 0;
}

/* The monitor's step on this step's innovation (docs/MONITOR.md §2): S_zz repacked to ld
 * RFE_MEAS, the persistent diagonal = the step noise's (pers) + the state's (diag Zc Zc^T). */
static rfe_status_t monitor_step(rfe_friction_t *est, const rfe_sckf_innov_t *in,
                                 const rfe_real_t pers[RFE_MEAS])
{
    rfe_real_t Szz[RFE_MEAS * RFE_MEAS];
    rfe_real_t c[RFE_MEAS];
    size_t r;
    size_t j;
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        for (j = 0u; j < (size_t)RFE_MEAS; ++j) {
            Szz[(r * (size_t)RFE_MEAS) + j] = in->Szz[(r * (size_t)RFE_M_MAX) + j];
        }
        c[r] = pers[r] + in->zz[r];
    }
    return rfe_monitor_step(&est->mon, in->nu, Szz, c, NULL);
}

/* Steps 4-6 (SCKF): this step's S_R at the predicted mean, then the gated update, and the
 * monitor on its innovation when it is on. *updated = 0 when the gate held the step. */
static rfe_status_t sckf_measurement(rfe_friction_t *est, const rfe_sample_t *u,
                                     const rfe_real_t y[RFE_MEAS], int *updated)
{
    const rfe_filter_params_t *fp = &est->params.filter;
    const int mon_on = rfe_flag_on(est->params.monitor.enable);
    rfe_sckf_t *f = &est->filter.sckf;
    rfe_real_t SR[RFE_MEAS * RFE_MEAS];
    rfe_real_t pers[RFE_MEAS] = {RFE_R(0.0), RFE_R(0.0), RFE_R(0.0)};
    rfe_sckf_innov_t innov;
    const rfe_real_t *sr = NULL; /* the filter's diagonal S_R */
    rfe_status_t st = RFE_OK;
    if (step_noise_active(fp) != 0) {
        rfe_real_t mu[RFE_WHEELS];
        to_wheels(est, f->x, mu); /* T x- */
        /* the internal entry: params validated at init, est->meas set up from u just now */
        st = rfe_step_noise_sqrt_core(&est->params, &est->meas, u, mu, SR, pers);
        sr = SR;
    }
    if (st == RFE_OK) {
        st = rfe_sckf_update_ex(f, measure, est, y, sr, fp->info_min, NULL,
                                (mon_on != 0) ? &innov : NULL, updated);
    }
    if ((st == RFE_OK) && (mon_on != 0)) {
        st = monitor_step(est, &innov, pers);
    }
    return st;
}

/* The cap's factor: min_k sd_max / sd_k over sd_k > sd_max (into *c); *scale = 1 if any. */
static void cap_factor(const rfe_filter_params_t *fp, const rfe_real_t *sd, size_t n,
                       rfe_real_t *c, int *scale)
{
    size_t k;
    for (k = 0u; k < n; ++k) {
        if (sd[k] > fp->sd_max) {
            *c = rfe_min(*c, fp->sd_max / sd[k]);
            *scale = 1;
        }
    }
}

/* The floor's factor: max_k f_k / sd_k over sd_k < f_k = sd_floor_rel max(x_k, 0) (into
 * *c; *scale = 1 if any), limited to sd_max / max_k sd_k when the cap is on, so that lifting
 * a well-informed wheel to its floor never lifts another above the cap. */
static void floor_factor(const rfe_filter_params_t *fp, const rfe_real_t *x,
                         const rfe_real_t *sd, size_t n, rfe_real_t *c, int *scale)
{
    rfe_real_t sd_hi = RFE_R(0.0);
    size_t k;
    for (k = 0u; k < n; ++k) {
        const rfe_real_t floor_k = fp->sd_floor_rel * rfe_max(x[k], RFE_R(0.0));
        if (sd[k] < floor_k) {
            *c = rfe_max(*c, floor_k / sd[k]);
            *scale = 1;
        }
        sd_hi = rfe_max(sd_hi, sd[k]);
    }
    if ((*scale != 0) && (fp->sd_max > RFE_R(0.0))) {
        *c = rfe_min(*c, fp->sd_max / sd_hi); /* >= 1: no sd_k is above sd_max here */
    }
}

/* Step 7: one factor c for the whole S (correlations kept): the cap if some sd_k > sd_max,
 * else the floor (limited by the cap). */
static rfe_status_t bound_sd(rfe_friction_t *est)
{
    const rfe_filter_params_t *fp = &est->params.filter;
    rfe_real_t x[RFE_N_MAX];
    rfe_real_t sd[RFE_N_MAX];
    rfe_real_t c = RFE_R(1.0);
    int scale = 0;
    rfe_status_t st;
    if (!(fp->sd_max > RFE_R(0.0)) && !(fp->sd_floor_rel > RFE_R(0.0))) {
        return RFE_OK;
    }
    st = rfe_sckf_get(&est->filter.sckf, x, sd);
    if ((st == RFE_OK) && !rfe_all_finite(sd, est->n)) {
        st = RFE_ERR_NONFINITE; /* S so large its row norms overflow */
    }
    if (st != RFE_OK) {
        return st;
    }
    if (fp->sd_max > RFE_R(0.0)) {
        cap_factor(fp, sd, est->n, &c, &scale);
    }
    if ((scale == 0) && (fp->sd_floor_rel > RFE_R(0.0))) {
        floor_factor(fp, x, sd, est->n, &c, &scale);
    }
    return (scale != 0) ? rfe_sckf_scale(&est->filter.sckf, c) : RFE_OK;
}

/* Steps 3-6 when vx >= v_est_min: the measurement model of the sample, then the update
 * (CKF) or the gated update with the step's S_R (SCKF). */
static rfe_status_t measurement_step(rfe_friction_t *est, const rfe_sample_t *u,
                                     int *updated)
{
    rfe_real_t y[RFE_MEAS];
    rfe_status_t st;
    y[0] = u->ax;
    y[1] = u->ay;
    y[2] = u->yaw_acc;
    st = rfe_meas_setup(&est->meas, &est->params.vehicle, &est->params.tyre, u);
    if (st == RFE_OK) {
        if (est->params.filter.kind == RFE_FILTER_CKF) {
            /* read only after a successful update; set before the call, which keeps the
             * float step's stack on the Cortex-M4F as it was before this function */
            *updated = 1;
            st = rfe_ckf_update(&est->filter.ckf, measure, est, y);
        } else {
            st = sckf_measurement(est, u, y, updated);
        }
    }
    return st;
}

/* Steps 1-8 after the input check. Returns the step's status or an error (the caller
 * rolls back). */
static rfe_status_t filter_step(rfe_friction_t *est, const rfe_sample_t *sample)
{
    const rfe_filter_kind_t kind = est->params.filter.kind;
    const rfe_filter_params_t *fp = &est->params.filter;
    rfe_sample_t u;
    rfe_status_t st;
    int measured = 0;
    int updated = 0;
    int clamped = 0;

    /* 1. Input conditioning (a copy of the sample when tau_v = 0). */
    st = rfe_conditioner_step(&est->cond, fp->dt, fp->tau_v, sample, &u);
    /* 2. Time update of the random walk: process callback NULL (identity). */
    if (st == RFE_OK) {
        st = (kind == RFE_FILTER_CKF) ? rfe_ckf_predict(&est->filter.ckf, NULL, NULL)
                                      : rfe_sckf_predict(&est->filter.sckf, NULL, NULL);
    }
    /* 3. Below v_est_min (standstill, creeping, reversing) tyre forces carry no usable
     * friction information: time update only. 4-6 otherwise. */
    if ((st == RFE_OK) && (u.vx >= fp->v_est_min)) {
        st = measurement_step(est, &u, &updated);
        measured = 1;
    }
    /* 7. Bounds on the sd (SCKF; the CKF runs without them). */
    if ((st == RFE_OK) && (kind != RFE_FILTER_CKF)) {
        st = bound_sd(est);
    }
    /* 8. Friction is physically bounded: after an update, project the mean (not S). */
    if ((st == RFE_OK) && (updated != 0)) {
        st = (kind == RFE_FILTER_CKF)
                 ? rfe_ckf_clamp(&est->filter.ckf, fp->mu_min, fp->mu_max, &clamped)
                 : rfe_sckf_clamp(&est->filter.sckf, fp->mu_min, fp->mu_max, &clamped);
    }
    return (st != RFE_OK) ? st : rfe_friction_step_status(measured, updated, clamped);
}

/* Step 9 on the filter's state: mu = T x, sd = T (row norms of S); validity by the sd when
 * sd_valid > 0, never on a projection bound (the monitor's effect not applied). */
static rfe_status_t filter_estimate(const rfe_friction_t *est, rfe_estimate_t *out)
{
    rfe_real_t x[RFE_N_MAX];
    rfe_real_t sd[RFE_N_MAX];
    const rfe_real_t sd_valid = est->params.filter.sd_valid;
    const rfe_real_t lo = est->params.filter.mu_min;
    const rfe_real_t hi = est->params.filter.mu_max;
    size_t w;
    rfe_status_t st;
    st = (est->params.filter.kind == RFE_FILTER_CKF)
             ? rfe_ckf_get(&est->filter.ckf, x, sd)
             : rfe_sckf_get(&est->filter.sckf, x, sd);
    /* 9. mu = T x, sd = T (row norms of S); validity by sd when sd_valid > 0, never on a
     * projection bound. */
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        const size_t k = state_of(est, w);
        const uint8_t sd_ok = ((sd_valid > RFE_R(0.0)) && (sd[k] <= sd_valid)) ? 1u : 0u;
        const uint8_t inside = ((x[k] > lo) && (x[k] < hi)) ? 1u : 0u;
        out->mu[w] = x[k];
        out->sd[w] = sd[k];
        out->valid[w] = rfe_friction_by_sd(sd_ok, inside);
    }
    out->status = st;
    return st;
}

/* docs/MONITOR.md §2 item 7: while the monitor is on and fired, every flag 0 and the sd
 * inflated. -1 when it is off or not fired (out untouched); else whether a flag was 1. */
static int monitor_effect(const rfe_friction_t *est, rfe_estimate_t *out)
{
    /* no friction distribution inside the bounds has a larger sd (Popoviciu's inequality) */
    const rfe_real_t cap = RFE_R(0.5) * (est->params.filter.mu_max - est->params.filter.mu_min);
    rfe_real_t c = RFE_R(1.0);
    rfe_status_t inflated;
    int any_valid = 0;
    size_t i;
    if ((est->params.monitor.enable == RFE_R(0.0)) || (est->mon.fired == 0u)) {
        return -1;
    }
    /* the monitor is initialised with the estimator: this cannot fail (c stays 1 if it did) */
    inflated = rfe_monitor_inflation(&est->mon, &c);
    (void)inflated;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if (out->valid[i] != 0u) {
            any_valid = 1;
        }
        const rfe_real_t s = out->sd[i] * c;
        out->valid[i] = 0u;
        out->sd[i] = (s < cap) ? s : cap;
    }
    return any_valid;
}

rfe_status_t rfe_friction_get(const rfe_friction_t *est, rfe_estimate_t *out)
{
    rfe_status_t st;
    if ((est == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    st = filter_estimate(est, out);
    /* what the last step reported: no flag and the inflated sd while the monitor is fired */
    (void)monitor_effect(est, out);
    return st;
}

/* After step 9, at every step while fired (so a rejected sample still reports the previous
 * estimate): the effect, and the status of a step that evaluated the model says so. */
static void apply_monitor(const rfe_friction_t *est, rfe_estimate_t *out)
{
    const int any_valid = monitor_effect(est, out);
    if ((any_valid >= 0) && (rfe_friction_monitor_applies(out->status) != 0)) {
        out->status = rfe_friction_monitor_status(out->status, any_valid);
    }
}

/* The periods of a gap whose time updates are made: at most until some state's variance
 * reaches the prior's, sd0^2 + sd0_common^2 (none if it is there already): after a long gap
 * the estimator knows as little as at init, its mean kept. A longer random walk means
 * nothing and feeds the filter numbers it never runs on otherwise (the fuzzer: the CKF after
 * 4e9 periods, the fixed-point CKF after a gap to the friction range's variance). */
static uint32_t gap_steps(const rfe_friction_t *est, uint32_t missed)
{
    const rfe_filter_params_t *fp = &est->params.filter;
    int ckf = 0;
    const rfe_real_t prior = (fp->sd0 * fp->sd0) + (fp->sd0_common * fp->sd0_common);
    rfe_real_t x[RFE_N_MAX];
    rfe_real_t sd[RFE_N_MAX];
    uint32_t k = missed;
    size_t i;
    size_t j;
    rfe_status_t st;
    if (fp->kind == RFE_FILTER_CKF) {
        ckf = 1;
    }
    st = (ckf != 0) ? rfe_ckf_get(&est->filter.ckf, x, sd)
                    : rfe_sckf_get(&est->filter.sckf, x, sd);
    (void)st; /* the estimator's own initialised filter: cannot fail */
    for (i = 0u; i < est->n; ++i) {
        rfe_real_t q = RFE_R(0.0); /* Q_ii */
        if (ckf != 0) {
            q = est->filter.ckf.Q[(i * NM) + i];
        } else {
            for (j = 0u; j <= i; ++j) {
                q += est->filter.sckf.SQ[(i * NM) + j] * est->filter.sckf.SQ[(i * NM) + j];
            }
        }
        if (q > RFE_R(0.0)) {
            const rfe_real_t room = rfe_max(prior - (sd[i] * sd[i]), RFE_R(0.0)) / q;
            if (room < (rfe_real_t)k) {
                k = (uint32_t)room;
            }
        }
    }
    return k;
}

/* The gap's time updates (ESTIMATOR.md "Gaps"): gap_steps of the missed periods, step 7's
 * sd bounds once (SCKF), the input filter restarted. Its callers check, back up and (fixed
 * point) settle the saturation counts. */
static rfe_status_t gap_update(rfe_friction_t *est, uint32_t missed)
{
    const uint32_t k = gap_steps(est, missed);
    rfe_status_t st = (est->params.filter.kind == RFE_FILTER_CKF)
                          ? rfe_ckf_predict_steps(&est->filter.ckf, k)
                          : rfe_sckf_predict_steps(&est->filter.sckf, k);
    if ((st == RFE_OK) && (est->params.filter.kind != RFE_FILTER_CKF)) {
        st = bound_sd(est); /* step 7 once, as after one step's time update */
    }
    if (st == RFE_OK) {
        /* the next sample seeds it, as after init (the library's own layout: no wrapper) */
        st = (rfe_conditioner_init)(&est->cond, sizeof(est->cond), RFE_CONFIG_REAL);
    }
    return st;
}

rfe_status_t rfe_friction_skip(rfe_friction_t *est, uint32_t missed)
{
    rfe_status_t st;
    if (est == NULL) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (missed == 0u) {
        return RFE_OK;
    }
    backup(est, 0);
    st = gap_update(est, missed);
    if (st != RFE_OK) {
        backup(est, 1);
    }
    return st;
}

rfe_status_t rfe_friction_missed(const rfe_friction_t *est, rfe_real_t period, uint32_t *missed)
{
    rfe_real_t dt;
    rfe_real_t lim;
    rfe_real_t n;
    if ((est == NULL) || (missed == NULL)) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if ((rfe_is_finite(period) == 0) || (period < RFE_R(0.0))) {
        return RFE_ERR_RANGE;
    }
    dt = est->params.filter.dt; /* > 0 (validated) */
    lim = (RFE_R(RFE_GAP_PERIODS) * dt) *
          (RFE_R(1.0) + RFE_LDEXP(RFE_R(1.0), -RFE_GAP_STAMP_SHIFT)); /* 2^-20: exact */
    if (period <= lim) {
        *missed = 0u; /* jitter */
        return RFE_OK;
    }
    n = (period / dt) + RFE_R(0.5); /* > 2: its integer part is round(period / dt) */
    *missed = (n >= RFE_R(4294967296.0)) ? UINT32_MAX : ((uint32_t)n - 1u);
    return RFE_OK;
}

rfe_status_t rfe_friction_step_after(rfe_friction_t *est, uint32_t missed,
                                     const rfe_sample_t *sample, rfe_estimate_t *out)
{
    rfe_status_t st;
    rfe_status_t got;
    size_t i;
    int sd_rule = 0;

    if ((est == NULL) || (sample == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    /* 0. Input check: a rejected sample changes nothing, the gap's time updates included. */
    st = check_sample(sample);
    if (st == RFE_OK) {
        backup(est, 0);
        if (missed > 0u) {
            st = gap_update(est, missed);
        }
        if (st == RFE_OK) {
            st = filter_step(est, sample);
        }
        if (rfe_status_is_error(st) != 0) {
            backup(est, 1);
        }
    }
    if (est->params.filter.sd_valid > RFE_R(0.0)) {
        sd_rule = 1; /* the sd rule; else the paper's */
    }
    got = filter_estimate(est, out);
    if (got != RFE_OK) {
        return got;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        out->valid[i] = rfe_friction_valid(st, sd_rule, out->valid[i]);
    }
    out->status = st;
    apply_monitor(est, out);
    return out->status;
}

rfe_status_t rfe_friction_step(rfe_friction_t *est, const rfe_sample_t *sample,
                               rfe_estimate_t *out)
{
    return rfe_friction_step_after(est, 0u, sample, out);
}
