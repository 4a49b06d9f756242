/**
 * @file estimator_flt.c
 * @brief The friction estimator: sample -> tyre -> H -> SCKF/CKF -> estimate (MODEL.md §5-6).
 */
#include "rfe/estimator.h"

#include "rfe/obsmat.h"

#include "internal.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)

/* C99 static assertion: the filters' compile-time maxima must hold the estimator's
 * four states and three measurements (a -DRFE_N_MAX=4 -DRFE_M_MAX=3 build is the smallest). */
typedef char rfe_assert_maxima_hold_estimator[((RFE_N_MAX >= RFE_WHEELS) && (RFE_M_MAX >= RFE_MEAS)) ? 1 : -1];

/* Paper mode: h(x, u) = H(u) x, with H built once per sample. */
static rfe_status_t measure_paper(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n,
                                  size_t m)
{
    const rfe_estimator_t *est = (const rfe_estimator_t *)ctx;
    (void)n;
    (void)m;
    return RFE_FN(rfe_obsmat_apply)(est->H, x, z);
}

/* Absolute mode: forces at this cubature point's mu (nonlinear in mu), then the same
 * geometry as H's columns: z_r = sum_i H_r,i(F(mu_i)) (MODEL.md §4-5). */
static rfe_status_t measure_absolute(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n,
                                     size_t m)
{
    static const rfe_real_t ones[RFE_WHEELS] = {RFE_R(1.0), RFE_R(1.0), RFE_R(1.0), RFE_R(1.0)};
    const rfe_estimator_t *est = (const rfe_estimator_t *)ctx;
    rfe_real_t fx[RFE_WHEELS];
    rfe_real_t fy[RFE_WHEELS];
    rfe_real_t Hf[RFE_MEAS * RFE_WHEELS];
    rfe_status_t st;
    (void)n;
    (void)m;
    st = RFE_FN(rfe_tyre_forces_abs)(&est->params.tyre, &est->kin, x, fx, fy);
    if (st == RFE_OK) {
        st = RFE_FN(rfe_obsmat_build)(&est->params.vehicle, est->delta, fx, fy, Hf);
    }
    if (st == RFE_OK) {
        st = RFE_FN(rfe_obsmat_apply)(Hf, ones, z);
    }
    return st;
}

rfe_status_t RFE_FN(rfe_estimator_init)(rfe_estimator_t *est, const rfe_params_t *params)
{
    rfe_real_t x0[RFE_WHEELS];
    rfe_real_t P0[RFE_WHEELS * RFE_WHEELS];
    rfe_real_t Q[RFE_WHEELS * RFE_WHEELS];
    rfe_real_t R[RFE_MEAS * RFE_MEAS];
    const rfe_filter_params_t *fp;
    rfe_status_t st;
    size_t i;
    size_t j;
    const int ckf = (params != NULL) && (params->filter.kind == RFE_FILTER_CKF);

    if ((est == NULL) || (params == NULL)) {
        return RFE_ERR_NULL;
    }
    st = RFE_FN(rfe_params_validate)(params);
    if (st != RFE_OK) {
        return st;
    }
    fp = &params->filter;
    /* x0 = mu0 on every wheel; S0 = sd0 I, S_Q = q_mu I, S_R = diag(r) (squared for the CKF). */
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        x0[i] = fp->mu0;
        for (j = 0u; j < (size_t)RFE_WHEELS; ++j) {
            const rfe_real_t on = (i == j) ? RFE_R(1.0) : RFE_R(0.0);
            P0[(i * RFE_WHEELS) + j] = on * (ckf ? (fp->sd0 * fp->sd0) : fp->sd0);
            Q[(i * RFE_WHEELS) + j] = on * (ckf ? (fp->q_mu * fp->q_mu) : fp->q_mu);
        }
    }
    for (i = 0u; i < (size_t)(RFE_MEAS * RFE_MEAS); ++i) {
        R[i] = RFE_R(0.0);
    }
    R[0] = ckf ? (fp->r_ax * fp->r_ax) : fp->r_ax;
    R[RFE_MEAS + 1] = ckf ? (fp->r_ay * fp->r_ay) : fp->r_ay;
    R[(2 * RFE_MEAS) + 2] = ckf ? (fp->r_yaw_acc * fp->r_yaw_acc) : fp->r_yaw_acc;

    if (ckf) {
        st = RFE_FN(rfe_ckf_init)(&est->filter.ckf, RFE_WHEELS, RFE_MEAS, x0, P0, Q, R);
    } else {
        st = RFE_FN(rfe_sckf_init)(&est->filter.sckf, RFE_WHEELS, RFE_MEAS, x0, P0, Q, R);
    }
    if (st != RFE_OK) {
        return st;
    }
    est->params = *params;
    est->delta = RFE_R(0.0);
    est->magic = RFE_MAGIC_EST;
    return RFE_OK;
}

/* Rejects non-finite samples (RFE_ERR_NONFINITE) and physically implausible ones
 * (RFE_ERR_RANGE, limits in config.h). */
static rfe_status_t check_sample(const rfe_sample_t *u)
{
    size_t i;
    if (!rfe_is_finite(u->delta) || !rfe_is_finite(u->vx) || !rfe_is_finite(u->vy) ||
        !rfe_is_finite(u->yaw_rate) || !rfe_is_finite(u->yaw_acc) || !rfe_is_finite(u->ax) ||
        !rfe_is_finite(u->ay) || !rfe_all_finite(u->omega, RFE_WHEELS)) {
        return RFE_ERR_NONFINITE;
    }
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

/* Saves / restores the filter's mean and factor so a failing step changes nothing. */
static void backup(rfe_estimator_t *est, int restore)
{
    const int ckf = (est->params.filter.kind == RFE_FILTER_CKF);
    rfe_real_t *x = ckf ? est->filter.ckf.x : est->filter.sckf.x;
    rfe_real_t *F = ckf ? est->filter.ckf.P : est->filter.sckf.S;
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
}

/* Time update, measurement update with y = [ax, ay, r-dot], projection. */
static rfe_status_t filter_step(rfe_estimator_t *est, const rfe_sample_t *u, int do_update)
{
    const int ckf = (est->params.filter.kind == RFE_FILTER_CKF);
    const rfe_measure_fn_t h =
        (est->params.tyre.mode == RFE_TYRE_ABSOLUTE) ? measure_absolute : measure_paper;
    const rfe_real_t y[RFE_MEAS] = {u->ax, u->ay, u->yaw_acc};
    const rfe_real_t lo = est->params.filter.mu_min;
    const rfe_real_t hi = est->params.filter.mu_max;
    int clamped = 0;
    rfe_status_t st;

    /* Random walk x_k = x_{k-1} + w: process callback NULL (identity). */
    st = ckf ? RFE_FN(rfe_ckf_predict)(&est->filter.ckf, NULL, NULL)
             : RFE_FN(rfe_sckf_predict)(&est->filter.sckf, NULL, NULL);
    if ((st != RFE_OK) || (do_update == 0)) {
        return (st != RFE_OK) ? st : RFE_NO_UPDATE_LOW_SPEED;
    }
    st = ckf ? RFE_FN(rfe_ckf_update)(&est->filter.ckf, h, est, y)
             : RFE_FN(rfe_sckf_update)(&est->filter.sckf, h, est, y);
    if (st == RFE_OK) {
        /* Friction is physically bounded: project the mean, leave the factor. */
        st = ckf ? RFE_FN(rfe_ckf_clamp)(&est->filter.ckf, lo, hi, &clamped)
                 : RFE_FN(rfe_sckf_clamp)(&est->filter.sckf, lo, hi, &clamped);
    }
    if ((st == RFE_OK) && (clamped != 0)) {
        st = RFE_PROJECTED;
    }
    return st;
}

rfe_status_t RFE_FN(rfe_estimator_get)(const rfe_estimator_t *est, rfe_estimate_t *out)
{
    size_t i;
    rfe_status_t st;
    if ((est == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    st = (est->params.filter.kind == RFE_FILTER_CKF)
             ? RFE_FN(rfe_ckf_get)(&est->filter.ckf, out->mu, out->sd)
             : RFE_FN(rfe_sckf_get)(&est->filter.sckf, out->mu, out->sd);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        out->valid[i] = 0u;
    }
    out->status = st;
    return st;
}

rfe_status_t RFE_FN(rfe_estimator_step)(rfe_estimator_t *est, const rfe_sample_t *sample,
                                        rfe_estimate_t *out)
{
    rfe_status_t st;
    rfe_status_t got;
    int do_update;
    size_t i;

    if ((est == NULL) || (sample == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    st = check_sample(sample);
    /* Below v_est_min (standstill, creeping, reversing) tyre forces carry no usable
     * friction information: time update only. */
    do_update = (sample->vx >= est->params.filter.v_est_min) ? 1 : 0;
    if ((st == RFE_OK) && (do_update != 0)) {
        /* Everything the measurement model needs for this sample, before the filter moves. */
        rfe_real_t f0x[RFE_WHEELS];
        rfe_real_t f0y[RFE_WHEELS];
        st = RFE_FN(rfe_tyre_kinematics)(&est->params.vehicle, &est->params.tyre, sample,
                                         &est->kin);
        if ((st == RFE_OK) && (est->params.tyre.mode == RFE_TYRE_PAPER)) {
            st = RFE_FN(rfe_tyre_forces_norm)(&est->params.tyre, &est->kin, f0x, f0y);
            if (st == RFE_OK) {
                st = RFE_FN(rfe_obsmat_build)(&est->params.vehicle, sample->delta, f0x, f0y,
                                              est->H);
            }
        }
        est->delta = sample->delta;
    }
    if (st == RFE_OK) {
        backup(est, 0);
        st = filter_step(est, sample, do_update);
        if (rfe_status_is_error(st)) {
            backup(est, 1);
        }
    }
    got = RFE_FN(rfe_estimator_get)(est, out);
    if (got != RFE_OK) {
        return got;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        out->valid[i] = ((st == RFE_OK) || (st == RFE_PROJECTED)) ? 1u : 0u;
    }
    out->status = st;
    return st;
}
