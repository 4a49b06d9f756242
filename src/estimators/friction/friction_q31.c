/**
 * @file friction_q31.c
 * @brief The friction estimator on int32 Q values (the twin of friction_flt.c): one step of
 *        docs/ESTIMATOR.md (MODEL.md §5-6 when every addition is off): conditioner -> SCKF/CKF
 *        time update -> meas, step noise -> SCKF gated update -> sd bounds -> projection ->
 *        per-wheel estimate. Integer operations only.
 *
 * Saturation accounting: the modules the step calls with a counter (conditioner, measurement
 * setup, step noise, and the measurement callback at every cubature point) add to
 * est->step_sat; the filter counts in its own state (f->sat), which the estimator empties
 * into the step's total after every successful step (so it is 0 between steps and the total
 * is exact, whatever the filter's counter would have reached). A failing step restores the
 * filter, the input filter and both counters.
 *
 * Internal formats (fractional bits, docs/FIXED_POINT.md "Estimator"):
 *  - sqrt_prior: the matrix c^2 11^T + d^2 I of Q30 sds is factored scaled by 2^(2k) (k such
 *    that max(c, d) 2^k is in [1/2, 1)), in Q29 (< 2), into a Q30 factor, then scaled back by
 *    2^-k with one rounding: error 0.5 LSB30 + 2^-k (Cholesky bound of rfe/component/chol_q31.h);
 *  - sd bounds: the factor c of rfe_sckf_scale_q31 in Q24 (RFE_Q31_QC), the cap ratio
 *    sd_max / sd_k exactly rounded; the floor f_k = sd_floor_rel max(x_k, 0) exact in int64
 *    (Q59), compared exactly with sd_k and divided by it with one rounding.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_FRICTION_Q31_IMPL
#include "rfe/friction_q31.h"

#include "rfe/component/chol_q31.h"
#include "rfe/component/step_noise_q31.h"
#include "rfe/component/fxmath.h"

#include "estimators/friction/friction_logic.h"
#include "estimators/friction/friction_monitor_q31.h"
#include "estimators/friction/step_noise_internal_q31.h"
#include "numerics/internal_q31.h"

#define NM ((size_t)RFE_N_MAX)
#define NW ((size_t)RFE_WHEELS)

/* Formats (fractional bits) as unsigned shift counts. */
#define QPRIOR 29u                         /* sqrt_prior's scaled matrix (< 4) */
#define QSD ((unsigned int)RFE_FIX_Q_SD)   /* sd, S: Q30 */
#define QACC ((unsigned int)RFE_FIX_Q_ACC) /* r_ax ...: Q24 */
#define QFLOOR 59u                         /* sd_floor_rel (Q30) times x (Q29) */
#define ONE_QC ((rfe_fix_t)16777216)       /* 1.0 in Q24 (RFE_Q31_QC) */

/* The generic filters' Q formats (rfe/component/sckf_q31.h) are the estimator's: the state is mu
 * (RFE_FIX_Q_MU) and the measurements are accelerations (RFE_FIX_Q_ACC, rfe/params_q31.h). */
#if (RFE_Q31_QX != RFE_FIX_Q_MU) || (RFE_Q31_QZ != RFE_FIX_Q_ACC)
#error "the filters' RFE_Q31_QX / RFE_Q31_QZ differ from RFE_FIX_Q_MU / RFE_FIX_Q_ACC"
#endif

/* C99 static assertion: the filters' compile-time maxima must hold the estimator's
 * four states and three measurements (a -DRFE_N_MAX=4 -DRFE_M_MAX=3 build is the smallest). */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_maxima_hold_estimator_q31[((RFE_N_MAX >= RFE_WHEELS) && (RFE_M_MAX >= RFE_MEAS)) ? 1 : -1];

/* State index of wheel w: the map T (docs/ESTIMATOR.md). wheels: T = I; sides: fl, rl on
 * the left state 0, fr, rr on the right state 1. */
static size_t state_of_q31(const rfe_friction_q31_t *est, size_t w)
{
    return rfe_friction_state_index(est->params.filter.structure, w);
}

/* mu per wheel = T x (Q29). */
static void to_wheels_q31(const rfe_friction_q31_t *est, const rfe_fix_t *x,
                          rfe_fix_t mu[RFE_WHEELS])
{
    size_t w;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        mu[w] = x[state_of_q31(est, w)];
    }
}

/* h(T x, u) for one cubature point (x Q29, z Q24); a point with mu < 0 is evaluated at mu = 0
 * by the load-scaled tyres (absolute Dugoff, MODEL.md §4; Magic Formula, docs/ESTIMATOR.md). */
static rfe_status_t measure_q31(void *ctx, const rfe_fix_t *x, rfe_fix_t *z, size_t n, size_t m)
{
    /* cppcheck-suppress misra-c2012-11.5 ; MISRA-DEV-05: ctx is the est this file passes */
    rfe_friction_q31_t *est = (rfe_friction_q31_t *)ctx;
    rfe_fix_t mu[RFE_WHEELS];
    (void)n;
    (void)m;
    to_wheels_q31(est, x, mu);
    /* its saturations go to the step's count (so est is not const here) */
    return rfe_meas_eval_q31(&est->meas, &est->params.vehicle, &est->params.tyre, mu, z,
                             &est->step_sat);
}

/* The power of two k >= -1 that brings v (Q30, > 0) into [2^29, 2^30) as v 2^k. */
static int norm_exponent_q31(rfe_fix_t v)
{
    int k = 0;
    uint32_t u = (uint32_t)v;
    if (u >= 0x40000000u) {
        k = -1;
    } else {
        while ((u != 0u) && (u < 0x20000000u)) {
            u <<= 1;
            ++k;
        }
    }
    return k;
}

/* v 2^k for k >= -1 (Q30; the right shift rounds half up). */
static rfe_fix_t scale_pow2_q31(rfe_fix_t v, int k)
{
    uint32_t unused = 0u; /* v 2^k < 2^30 by the choice of k: never saturates */
    return (k < 0) ? rfe_fix_shr_round(v, 1u) : rfe_fix_shl(v, (unsigned int)k, &unused);
}

/* sqrt_prior_q31(d, c) (n x n, ld n, Q30): the lower Cholesky factor of c^2 11^T + d^2 I; exactly
 * d I when c = 0 (no Cholesky, so the paper preset's factors are exact). d > 0, c >= 0.
 * RFE_ERR_RANGE when the factor does not fit Q30 (c^2 + d^2 >= 4). */
static rfe_status_t sqrt_prior_q31(rfe_fix_t d, rfe_fix_t c, size_t n, rfe_fix_t *F)
{
    rfe_fix_t P[RFE_WHEELS * RFE_WHEELS];
    uint32_t count = 0u;
    const int k = norm_exponent_q31(rfe_fix_max(c, d));
    const int64_t cs = (int64_t)scale_pow2_q31(c, k); /* < 2^30 */
    const int64_t ds = (int64_t)scale_pow2_q31(d, k);
    size_t i;
    rfe_status_t st = RFE_OK;

    for (i = 0u; i < (n * n); ++i) {
        const size_t r = i / n;
        const size_t col = i % n;
        /* (c^2 + [i = j] d^2) 2^(2k) in Q29 (< 2): Q60 rounded by 31 bits */
        int64_t diag = 0;
        F[i] = 0;
        if (r == col) {
            diag = ds * ds;
            F[i] = d;
        }
        P[i] = rfe_fix_narrow((cs * cs) + diag, (2u * QSD) - QPRIOR, &count);
    }
    if (c > 0) {
        rfe_fix_t L[RFE_WHEELS * RFE_WHEELS];
        st = rfe_chol_factor_q31(P, n, n, L, n, QPRIOR, QSD, &count);
        for (i = 0u; (st == RFE_OK) && (i < (n * n)); ++i) {
            /* back by 2^-k: a rounding right shift, or (k = -1) a doubling that may leave
             * the format */
            F[i] = (k >= 0) ? rfe_fix_shr_round(L[i], (unsigned int)k)
                            : rfe_fix_shl(L[i], 1u, &count);
        }
    }
    return ((st == RFE_OK) && (count != 0u)) ? RFE_ERR_RANGE : st;
}

/* v^2 from Q(q) into Q(2q - s) as int32, or RFE_ERR_RANGE when it does not fit. */
static rfe_status_t square_into_q31(rfe_fix_t v, unsigned int s, rfe_fix_t *out)
{
    uint32_t count = 0u;
    *out = rfe_fix_narrow((int64_t)v * (int64_t)v, s, &count);
    return (count != 0u) ? RFE_ERR_RANGE : RFE_OK;
}

/* The SCKF's prior: x0 = mu0, S0 and S_Q from sqrt_prior_q31 (sd0, q_mu with their common
 * parts), S_R = diag(r_ax, r_ay, r_yaw_acc). */
static rfe_status_t init_sckf_q31(rfe_friction_q31_t *est, const rfe_filter_params_q31_t *fp,
                                  size_t n)
{
    rfe_fix_t x0[RFE_WHEELS];
    rfe_fix_t S0[RFE_WHEELS * RFE_WHEELS];
    rfe_fix_t SQ[RFE_WHEELS * RFE_WHEELS];
    rfe_fix_t SR[RFE_MEAS * RFE_MEAS] = {0};
    size_t i;
    rfe_status_t st;
    for (i = 0u; i < n; ++i) {
        x0[i] = fp->mu0;
    }
    SR[0] = fp->r_ax;
    SR[RFE_MEAS + 1] = fp->r_ay;
    SR[(2 * RFE_MEAS) + 2] = fp->r_yaw_acc;
    st = sqrt_prior_q31(fp->sd0, fp->sd0_common, n, S0);
    if (st == RFE_OK) {
        st = sqrt_prior_q31(fp->q_mu, fp->q_common, n, SQ);
    }
    if (st == RFE_OK) {
        /* the library's own layout: the init called directly, not through its wrapper */
        st = (rfe_sckf_init_q31)(&est->filter.sckf, n, RFE_MEAS, x0, S0, SQ, SR,
                                 sizeof(est->filter.sckf), RFE_CONFIG_Q31);
    }
    return st;
}

/* The CKF runs only the paper subset (rfe_params_validate_q31): P0 = sd0^2 I, Q = q_mu^2 I
 * (Q60 -> Q31), R = diag(r^2) (Q48 -> Q24). */
static rfe_status_t init_ckf_q31(rfe_friction_q31_t *est, const rfe_filter_params_q31_t *fp)
{
    rfe_fix_t x0[RFE_WHEELS];
    rfe_fix_t P0[RFE_WHEELS * RFE_WHEELS] = {0};
    rfe_fix_t Q[RFE_WHEELS * RFE_WHEELS] = {0};
    rfe_fix_t R[RFE_MEAS * RFE_MEAS] = {0};
    rfe_fix_t p0 = 0;
    rfe_fix_t q = 0;
    const unsigned int sp = (2u * QSD) - RFE_Q31_QP;
    const unsigned int sr = (2u * QACC) - RFE_Q31_QR;
    size_t i;
    rfe_status_t st = square_into_q31(fp->sd0, sp, &p0);
    if (st == RFE_OK) {
        st = square_into_q31(fp->q_mu, sp, &q);
    }
    if (st == RFE_OK) {
        st = square_into_q31(fp->r_ax, sr, &R[0]);
    }
    if (st == RFE_OK) {
        st = square_into_q31(fp->r_ay, sr, &R[RFE_MEAS + 1]);
    }
    if (st == RFE_OK) {
        st = square_into_q31(fp->r_yaw_acc, sr, &R[(2 * RFE_MEAS) + 2]);
    }
    for (i = 0u; i < NW; ++i) {
        x0[i] = fp->mu0;
        P0[(i * NW) + i] = p0;
        Q[(i * NW) + i] = q;
    }
    if (st == RFE_OK) {
        /* the library's own layout: the init called directly, not through its wrapper */
        st = (rfe_ckf_init_q31)(&est->filter.ckf, NW, RFE_MEAS, x0, P0, Q, R,
                                sizeof(est->filter.ckf), RFE_CONFIG_Q31);
    }
    return st;
}

/* The monitor's scratch set to 0. */
static void clear_scratch_q31(rfe_friction_q31_t *est)
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_M_MAX; ++i) {
        est->innov.nu[i] = 0;
        est->innov.zz[i] = 0;
    }
    for (i = 0u; i < ((size_t)RFE_M_MAX * (size_t)RFE_M_MAX); ++i) {
        est->innov.Szz[i] = 0;
    }
    for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
        est->pers[i] = 0;
    }
}

rfe_status_t rfe_friction_init_q31(rfe_friction_q31_t *est, const rfe_params_q31_t *params,
                                   size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    const rfe_filter_params_q31_t *fp;
    size_t n;
    rfe_status_t st;

    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*est)) || (config != RFE_CONFIG_Q31)) {
        return RFE_ERR_ABI;
    }
    if ((est == NULL) || (params == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_params_validate_q31(params);
    if (st != RFE_OK) {
        return st;
    }
    fp = &params->filter;
    n = (fp->structure == RFE_STRUCT_SIDES) ? 2u : NW;
    /* A failure (a prior that does not fit its format) leaves the estimator not initialised;
     * the filter init writes only after its own checks, which validated sizes pass. */
    st = (fp->kind == RFE_FILTER_CKF) ? init_ckf_q31(est, fp) : init_sckf_q31(est, fp, n);
    if (st == RFE_OK) {
        st = rfe_conditioner_init_q31(&est->cond);
    }
    if (st == RFE_OK) {
        st = rfe_monitor_init_q31(&est->mon, &params->monitor);
    }
    if (st != RFE_OK) {
        return st;
    }
    est->params = *params;
    est->n = n;
    est->backup_cond = est->cond;
    clear_scratch_q31(est); /* defined bytes in whole-state copies */
    est->step_sat = 0u;
    est->sat = 0u;
    est->magic = RFE_MAGIC_EST_Q31;
    return RFE_OK;
}


/* RFE_ERR_RANGE for a physically implausible sample: the limits of config.h in Q formats. */
static rfe_status_t check_sample_q31(const rfe_sample_q31_t *u)
{
    size_t i;
    if ((rfe_q31_within(u->delta, RFE_FIX_LIMIT_DELTA) == 0) ||
        (rfe_q31_within(u->vx, RFE_FIX_LIMIT_VX) == 0) ||
        (rfe_q31_within(u->vy, RFE_FIX_LIMIT_VY) == 0) ||
        (rfe_q31_within(u->yaw_rate, RFE_FIX_LIMIT_YAW_RATE) == 0) ||
        (rfe_q31_within(u->yaw_acc, RFE_FIX_LIMIT_YAW_ACC) == 0) ||
        (rfe_q31_within(u->ax, RFE_FIX_LIMIT_ACC) == 0) ||
        (rfe_q31_within(u->ay, RFE_FIX_LIMIT_ACC) == 0)) {
        return RFE_ERR_RANGE;
    }
    for (i = 0u; i < NW; ++i) {
        if (rfe_q31_within(u->omega[i], RFE_FIX_LIMIT_OMEGA) == 0) {
            return RFE_ERR_RANGE;
        }
    }
    return RFE_OK;
}

/* Saves / restores what a step changes (filter mean and factor, input filter; in float the
 * monitor, in fixed point the saturation counters) so a failing step changes nothing. */
static void backup_q31(rfe_friction_q31_t *est, int restore)
{
    const rfe_filter_kind_t kind = est->params.filter.kind;
    rfe_fix_t *x = (kind == RFE_FILTER_CKF) ? est->filter.ckf.x : est->filter.sckf.x;
    rfe_fix_t *F = (kind == RFE_FILTER_CKF) ? est->filter.ckf.P : est->filter.sckf.S;
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
        /* the filter's counter is 0 between steps, so restoring sets it to 0 */
        if (kind == RFE_FILTER_CKF) {
            est->filter.ckf.sat = 0u;
        } else {
            est->filter.sckf.sat = 0u;
        }
    } else {
        est->backup_cond = est->cond;
    }
    est->step_sat = 0u;
}

/* Step 4 runs when any part of it is switched on. */
static int step_noise_active_q31(const rfe_filter_params_q31_t *fp)
{
    const rfe_fix_t zero = 0;
    return ((fp->r_model_rel > zero) || (fp->sd_in_delta > zero) || (fp->sd_in_vx > zero) ||
            (fp->sd_in_vy > zero) || (fp->sd_in_yaw_rate > zero) || (fp->sd_in_omega > zero))
               ? 1
               : 0;
}

/* Steps 4-6 (SCKF): this step's S_R at the predicted mean, then the gated update; with the
 * monitor on, the step noise's persistent diagonal and the innovation go to the scratch
 * est->pers, est->innov for monitor_step_q31. *updated = 0 when the gate held the step. */
static rfe_status_t sckf_measurement_q31(rfe_friction_q31_t *est, const rfe_sample_q31_t *u,
                                         const rfe_fix_t y[RFE_MEAS], int *updated)
{
    const rfe_filter_params_q31_t *fp = &est->params.filter;
    rfe_sckf_q31_t *f = &est->filter.sckf;
    rfe_fix_t SR[RFE_MEAS * RFE_MEAS];
    const rfe_fix_t *sr = NULL; /* the filter's diagonal S_R */
    rfe_status_t st = RFE_OK;
    /* the monitor's scratch (enable is 0 or 1, validated); est->pers stays 0 without S_R */
    rfe_fix_t *pers = (est->params.monitor.enable != 0u) ? est->pers : NULL;
    if (step_noise_active_q31(fp) != 0) {
        rfe_fix_t mu[RFE_WHEELS];
        to_wheels_q31(est, f->x, mu); /* T x- */
        /* the internal entry: params validated at init, est->meas set up from u just now */
        st = rfe_step_noise_sqrt_core_q31(&est->params, &est->meas, u, mu, SR, pers,
                                          &est->step_sat);
        sr = SR;
    }
    if (st == RFE_OK) {
        st = rfe_sckf_update_ex_q31(f, measure_q31, est, y, sr, fp->info_min, NULL,
                                    (pers != NULL) ? &est->innov : NULL, updated);
    }
    return st;
}

/* round(num / den) for num >= 0, den > 0, saturating (counted) to the int32 range. */
static rfe_fix_t div_round_pos_q31(uint64_t num, uint64_t den, uint32_t *count)
{
    uint64_t q = num / den;
    if ((num % den) >= (den - (num % den))) { /* remainder >= den / 2: ties up */
        ++q;
    }
    if (q > (uint64_t)RFE_FIX_MAX) {
        rfe_fix_count_sat(count);
        q = (uint64_t)RFE_FIX_MAX;
    }
    return (rfe_fix_t)q;
}

/* The floor's factor: max over the states with sd_k < f_k = sd_floor_rel max(x_k, 0) of
 * f_k / sd_k (Q24, into *c); *scale = 1 when some state is below its floor. */
static void floor_factor_q31(const rfe_friction_q31_t *est, const rfe_fix_t *x,
                             const rfe_fix_t *sd, rfe_fix_t *c, int *scale, uint32_t *count)
{
    const rfe_filter_params_q31_t *fp = &est->params.filter;
    size_t k;
    for (k = 0u; k < est->n; ++k) {
        /* f_k in Q59 (both factors >= 0: < 2^62), sd_k in Q30: compared exactly in Q59 */
        const uint64_t f59 = (uint64_t)fp->sd_floor_rel * (uint64_t)rfe_fix_max(x[k], 0);
        const uint64_t sd59 = (uint64_t)sd[k] << (QFLOOR - QSD);
        if (sd59 < f59) {
            /* f / sd in Q24 = f59 / (sd30 2^5), one rounding. sd_k > 0 always (S- carries
             * S_Q, whose diagonal is >= q_mu > 0); a zero sd would count as 1 LSB (the
             * factor then saturates, counted), where the float twin fails on infinity. */
            const uint64_t den = (uint64_t)rfe_fix_max(sd[k], 1) << (QFLOOR - QSD - RFE_Q31_QC);
            *c = rfe_fix_max(*c, div_round_pos_q31(f59, den, count));
            *scale = 1;
        }
    }
}

/* The floor's factor c (Q24, > 1) limited so that no sd_k c exceeds sd_max: c = min(c,
 * sd_max / max_k sd_k), rounded to nearest (sd_max 2^24 / sd_hi < c: cannot saturate). */
static rfe_fix_t cap_floor_factor_q31(const rfe_friction_q31_t *est, const rfe_fix_t *sd,
                                      rfe_fix_t c, uint32_t *count)
{
    const rfe_fix_t sd_max = est->params.filter.sd_max;
    rfe_fix_t sd_hi = 1;
    size_t k;
    for (k = 0u; k < est->n; ++k) {
        sd_hi = rfe_fix_max(sd_hi, sd[k]);
    }
    if ((uint64_t)sd_hi * (uint64_t)c > ((uint64_t)sd_max << RFE_Q31_QC)) {
        return div_round_pos_q31((uint64_t)sd_max << RFE_Q31_QC, (uint64_t)sd_hi, count);
    }
    return c;
}

/* Step 7: one factor c (Q24) for the whole S (correlations kept). Cap: c = min_k sd_max / sd_k
 * over sd_k > sd_max; else floor: c = max_k f_k / sd_k over sd_k < f_k,
 * f_k = sd_floor_rel max(x_k, 0), limited to sd_max / max_k sd_k so that lifting a
 * well-informed wheel to its floor never lifts another above the cap. */
static rfe_status_t bound_sd_q31(rfe_friction_q31_t *est)
{
    const rfe_filter_params_q31_t *fp = &est->params.filter;
    rfe_fix_t x[RFE_N_MAX];
    rfe_fix_t sd[RFE_N_MAX];
    rfe_fix_t c = ONE_QC;
    int scale = 0;
    rfe_status_t st;
    if ((fp->sd_max <= 0) && (fp->sd_floor_rel <= 0)) {
        return RFE_OK;
    }
    st = rfe_sckf_get_q31(&est->filter.sckf, x, sd);
    if ((st == RFE_OK) && (fp->sd_max > 0)) {
        size_t k;
        for (k = 0u; k < est->n; ++k) {
            if (sd[k] > fp->sd_max) {
                /* sd_max / sd_k in Q24 (shift 24 - 30 + 30), exactly rounded, < 1; cannot
                 * fail (sd_k > 0) */
                rfe_fix_t ck = 0;
                st = rfe_fix_div(fp->sd_max, sd[k], (int)RFE_Q31_QC, &ck, &est->step_sat);
                c = rfe_fix_min(c, ck);
                scale = 1;
            }
        }
    }
    if ((st == RFE_OK) && (scale == 0) && (fp->sd_floor_rel > 0)) {
        floor_factor_q31(est, x, sd, &c, &scale, &est->step_sat);
        if ((scale != 0) && (fp->sd_max > 0)) {
            c = cap_floor_factor_q31(est, sd, c, &est->step_sat);
        }
    }
    if ((st == RFE_OK) && (scale != 0)) {
        /* c rounds to 0 only for a cap below 2^-24 of the sd: keep the smallest factor */
        st = rfe_sckf_scale_q31(&est->filter.sckf, rfe_fix_max(c, 1));
    }
    return st;
}

/* Steps 3-6 when vx >= v_est_min: the measurement model of the sample, then the update
 * (CKF) or the gated update with the step's S_R (SCKF). */
static rfe_status_t measurement_step_q31(rfe_friction_q31_t *est, const rfe_sample_q31_t *u,
                                         int *updated)
{
    rfe_fix_t y[RFE_MEAS];
    rfe_status_t st;
    y[0] = u->ax;
    y[1] = u->ay;
    y[2] = u->yaw_acc;
    st = rfe_meas_setup_q31(&est->meas, &est->params.vehicle, &est->params.tyre, u,
                            &est->step_sat);
    if (st == RFE_OK) {
        if (est->params.filter.kind == RFE_FILTER_CKF) {
            /* read only after a successful update; set before the call, which keeps the
             * float step's stack on the Cortex-M4F as it was before this function */
            *updated = 1;
            st = rfe_ckf_update_q31(&est->filter.ckf, measure_q31, est, y);
        } else {
            st = sckf_measurement_q31(est, u, y, updated);
        }
    }
    return st;
}

/* Steps 1-8 after the input check. Returns the step's status or an error (the caller
 * rolls back). */
static rfe_status_t filter_step_q31(rfe_friction_q31_t *est, const rfe_sample_q31_t *sample)
{
    const rfe_filter_kind_t kind = est->params.filter.kind;
    const rfe_filter_params_q31_t *fp = &est->params.filter;
    rfe_sample_q31_t u;
    rfe_status_t st;
    int measured = 0;
    int updated = 0;
    int clamped = 0;

    /* 1. Input conditioning (a copy of the sample when tau_v = 0). */
    st = rfe_conditioner_step_q31(&est->cond, fp->dt, fp->tau_v, fp->b_v, sample, &u,
                                  &est->step_sat);
    /* 2. Time update of the random walk: process callback NULL (identity). */
    if (st == RFE_OK) {
        st = (kind == RFE_FILTER_CKF) ? rfe_ckf_predict_q31(&est->filter.ckf, NULL, NULL)
                                      : rfe_sckf_predict_q31(&est->filter.sckf, NULL, NULL);
    }
    /* 3. Below v_est_min (standstill, creeping, reversing) tyre forces carry no usable
     * friction information: time update only. 4-6 otherwise. */
    if ((st == RFE_OK) && (u.vx >= fp->v_est_min)) {
        st = measurement_step_q31(est, &u, &updated);
        measured = 1;
    }
    /* 7. Bounds on the sd (SCKF; the CKF runs without them). */
    if ((st == RFE_OK) && (kind != RFE_FILTER_CKF)) {
        st = bound_sd_q31(est);
    }
    /* 8. Friction is physically bounded: after an update, project the mean (not S). */
    if ((st == RFE_OK) && (updated != 0)) {
        st = (kind == RFE_FILTER_CKF)
                 ? rfe_ckf_clamp_q31(&est->filter.ckf, fp->mu_min, fp->mu_max, &clamped)
                 : rfe_sckf_clamp_q31(&est->filter.sckf, fp->mu_min, fp->mu_max, &clamped);
    }
    /* The monitor on the innovation of a step that evaluated the model (SCKF, monitor on);
     * the float twin runs it inside sckf_measurement, on the innovation it keeps there. */
    if ((st == RFE_OK) && (measured != 0) && (est->params.monitor.enable != 0u)) {
        st = rfe_friction_monitor_step_q31(est);
    }
    return (st != RFE_OK) ? st : rfe_friction_step_status(measured, updated, clamped);
}

/* After a successful step: the filter's count joins the step's, both go to the running
 * total, the filter's counter is emptied. Returns the step's count. */
static uint32_t settle_counts_q31(rfe_friction_q31_t *est)
{
    uint32_t *fsat = (est->params.filter.kind == RFE_FILTER_CKF) ? &est->filter.ckf.sat
                                                                 : &est->filter.sckf.sat;
    uint32_t step = est->step_sat;
    rfe_q31_sat_add(&step, *fsat);
    rfe_q31_sat_add(&est->sat, step);
    *fsat = 0u;
    est->step_sat = 0u;
    return step;
}

/* Step 9 on the filter's state: mu = T x, sd = T (row norms of S); validity by the sd when
 * sd_valid > 0, never on a projection bound (the monitor's effect not applied). */
static rfe_status_t filter_estimate_q31(const rfe_friction_q31_t *est, rfe_estimate_q31_t *out)
{
    rfe_fix_t x[RFE_N_MAX];
    rfe_fix_t sd[RFE_N_MAX];
    const rfe_fix_t sd_valid = est->params.filter.sd_valid;
    const rfe_fix_t lo = est->params.filter.mu_min;
    const rfe_fix_t hi = est->params.filter.mu_max;
    size_t w;
    rfe_status_t st;
    st = (est->params.filter.kind == RFE_FILTER_CKF)
             ? rfe_ckf_get_q31(&est->filter.ckf, x, sd)
             : rfe_sckf_get_q31(&est->filter.sckf, x, sd);
    /* 9. mu = T x, sd = T (row norms of S); validity by sd when sd_valid > 0, never on a
     * projection bound. */
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        const size_t k = state_of_q31(est, w);
        const uint8_t sd_ok = ((sd_valid > 0) && (sd[k] <= sd_valid)) ? 1u : 0u;
        const uint8_t inside = ((x[k] > lo) && (x[k] < hi)) ? 1u : 0u;
        out->mu[w] = x[k];
        out->sd[w] = sd[k];
        out->valid[w] = rfe_friction_by_sd(sd_ok, inside);
    }
    out->status = st;
    out->sat = 0u;
    return st;
}

rfe_status_t rfe_friction_get_q31(const rfe_friction_q31_t *est, rfe_estimate_q31_t *out)
{
    uint32_t count = 0u; /* sat is 0 from get: the inflation's saturations were the step's */
    rfe_status_t st;
    if ((est == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    st = filter_estimate_q31(est, out);
    /* what the last step reported: no flag and the inflated sd while the monitor is fired */
    (void)rfe_friction_monitor_effect_q31(est, out, &count);
    return st;
}

/* The periods of a gap whose time updates are made (friction_flt.c gap_steps): at most until
 * some state's variance reaches the prior's, sd0^2 + sd0_common^2. In Q60: the prior's and
 * P_ii = sd_i^2 from Q30 sds, Q_ii = |row i of S_Q|^2 (Q30) or the CKF's Q_ii (Q31);
 * non-negative, so unsigned. */
static uint32_t gap_steps_q31(const rfe_friction_q31_t *est, uint32_t missed)
{
    const rfe_filter_params_q31_t *fp = &est->params.filter;
    int ckf = 0;
    const uint64_t s0 = (uint64_t)fp->sd0;        /* > 0, Q30 (validated) */
    const uint64_t sc = (uint64_t)fp->sd0_common; /* >= 0, Q30 */
    const uint64_t bound = (s0 * s0) + (sc * sc);
    rfe_fix_t x[RFE_N_MAX];
    rfe_fix_t sd[RFE_N_MAX];
    uint32_t k = missed;
    size_t i;
    rfe_status_t st;
    if (fp->kind == RFE_FILTER_CKF) {
        ckf = 1;
    }
    st = (ckf != 0) ? rfe_ckf_get_q31(&est->filter.ckf, x, sd)
                    : rfe_sckf_get_q31(&est->filter.sckf, x, sd);
    (void)st; /* the estimator's own initialised filter: cannot fail */
    for (i = 0u; i < est->n; ++i) {
        const uint64_t p = (uint64_t)sd[i] * (uint64_t)sd[i];
        uint64_t q = 0u;
        if (ckf != 0) {
            q = ((uint64_t)rfe_fix_max(est->filter.ckf.Q[(i * NM) + i], 0)) << 29u;
        } else {
            rfe_fix_t qn = 0; /* |row i of S_Q|, exactly rounded (Q30) */
            uint32_t unused = 0u;
            const rfe_status_t nst = rfe_fix_norm(&est->filter.sckf.SQ[i * NM], i + 1u, &qn,
                                                  &unused);
            (void)nst; /* fails only for NULL arguments, which these are not */
            q = (uint64_t)qn * (uint64_t)qn;
        }
        if (q > 0u) {
            const uint64_t room = (bound > p) ? ((bound - p) / q) : 0u;
            if (room < (uint64_t)k) {
                k = (uint32_t)room;
            }
        }
    }
    return k;
}

/* The gap's time updates (ESTIMATOR.md "Gaps"): gap_steps_q31 of the missed periods, step 7's
 * sd bounds once (SCKF), the input filter restarted. Its callers check, back up and (fixed
 * point) settle the saturation counts. */
static rfe_status_t gap_update_q31(rfe_friction_q31_t *est, uint32_t missed)
{
    const uint32_t k = gap_steps_q31(est, missed);
    rfe_status_t st = (est->params.filter.kind == RFE_FILTER_CKF)
                          ? rfe_ckf_predict_steps_q31(&est->filter.ckf, k)
                          : rfe_sckf_predict_steps_q31(&est->filter.sckf, k);
    if ((st == RFE_OK) && (est->params.filter.kind != RFE_FILTER_CKF)) {
        st = bound_sd_q31(est); /* step 7 once, as after one step's time update */
    }
    if (st == RFE_OK) {
        st = rfe_conditioner_init_q31(&est->cond); /* the next sample seeds it */
    }
    return st;
}

rfe_status_t rfe_friction_skip_q31(rfe_friction_q31_t *est, uint32_t missed)
{
    rfe_status_t st;
    if (est == NULL) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (missed == 0u) {
        return RFE_OK;
    }
    backup_q31(est, 0);
    st = gap_update_q31(est, missed);
    if (st != RFE_OK) {
        backup_q31(est, 1);
    } else {
        (void)settle_counts_q31(est);
    }
    return st;
}

rfe_status_t rfe_friction_missed_q31(const rfe_friction_q31_t *est, rfe_fix_t period,
                                     uint32_t *missed)
{
    uint64_t dt;
    uint64_t lim;
    if ((est == NULL) || (missed == NULL)) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (period < 0) {
        return RFE_ERR_RANGE;
    }
    dt = (uint64_t)est->params.filter.dt; /* Q30, > 0 (validated) */
    lim = (uint64_t)RFE_GAP_PERIODS * dt;
    lim += lim >> (uint32_t)RFE_GAP_STAMP_SHIFT; /* widened by 2^-20, floored (< 1 LSB) */
    if ((uint64_t)period <= lim) {
        *missed = 0u; /* jitter */
    } else {
        /* round(period / dt), exactly (half up): < 2^31 (period < 2 s, dt >= 1 LSB), >= 2 */
        const uint64_t n = ((2u * (uint64_t)period) + dt) / (2u * dt);
        *missed = (uint32_t)n - 1u;
    }
    return RFE_OK;
}

rfe_status_t rfe_friction_step_after_q31(rfe_friction_q31_t *est, uint32_t missed,
                                         const rfe_sample_q31_t *sample, rfe_estimate_q31_t *out)
{
    rfe_status_t st;
    rfe_status_t got;
    uint32_t step_sat = 0u;
    size_t i;
    int sd_rule = 0;

    if ((est == NULL) || (sample == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    /* 0. Input check: a rejected sample changes nothing, the gap's time updates included. */
    st = check_sample_q31(sample);
    if (st == RFE_OK) {
        backup_q31(est, 0);
        if (missed > 0u) {
            st = gap_update_q31(est, missed);
        }
        if (st == RFE_OK) {
            st = filter_step_q31(est, sample);
        }
        if (rfe_status_is_error(st) != 0) {
            backup_q31(est, 1);
        } else {
            step_sat = settle_counts_q31(est);
        }
    }
    if (est->params.filter.sd_valid > 0) {
        sd_rule = 1; /* the sd rule; else the paper's */
    }
    got = filter_estimate_q31(est, out);
    if (got != RFE_OK) {
        return got;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        out->valid[i] = rfe_friction_valid(st, sd_rule, out->valid[i]);
    }
    out->status = st;
    out->sat = step_sat;
    rfe_friction_monitor_apply_q31(est, out);
    return out->status;
}

rfe_status_t rfe_friction_step_q31(rfe_friction_q31_t *est, const rfe_sample_q31_t *sample,
                                   rfe_estimate_q31_t *out)
{
    return rfe_friction_step_after_q31(est, 0u, sample, out);
}
