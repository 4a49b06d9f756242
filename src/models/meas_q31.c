/**
 * @file meas_q31.c
 * @brief Fixed-point twin of meas_flt.c: the measurement model h(mu, u) of one sample, paper
 *        (H(u) mu) or a load-scaled tyre (absolute Dugoff or Magic Formula). Integer operations
 *        only (rfe/component/meas_q31.h).
 *
 * The set-up keeps, beside the kinematics, cos/sin of delta and (load-scaled modes) each
 * wheel's friction-independent tyre terms (the same for both curves), so an evaluation at a
 * cubature point computes only the friction-dependent rest and the columns of H those forces
 * give (the entries of rfe_obsmat_build_q31, bit for bit), summed exactly:
 * rfe_obsmat_apply_q31(H, ones) is the saturated int64 sum of each row, since H 2^29 / 2^29
 * leaves no fraction to round.
 */
#include "rfe/component/meas_q31.h"

#include "numerics/internal_q31.h"
#include "models/meas_internal_q31.h"
#include "models/tyre_internal_q31.h"

/* 1.0 in Q30, 2^30 (cos of an unsteered wheel). */
#define ONE_Q30 ((int32_t)0x40000000)

void rfe_meas_wheel_column_q31(const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
                               const rfe_dugoff_pre_q31_t *pre, rfe_fix_t mu, rfe_fix_t fz,
                               int32_t c, int32_t s, size_t i, rfe_fix_t col[RFE_MEAS],
                               uint32_t *sat)
{
    /* Front wheels are rotated by delta into body axes, rear wheels are not; x_i / J and
     * y_i / J (MODEL.md §1 positions), Q38. As rfe_obsmat_build_q31's column i. */
    const int64_t ci = (i < (size_t)RFE_RL) ? (int64_t)c : (int64_t)ONE_Q30;
    const int64_t si = (i < (size_t)RFE_RL) ? (int64_t)s : 0;
    const int64_t px_J = (i < (size_t)RFE_RL) ? (int64_t)veh->lf_J : -(int64_t)veh->lr_J;
    const int64_t y_J = (i < (size_t)RFE_RL) ? (int64_t)veh->yf_J : (int64_t)veh->yr_J;
    const int64_t py_J = ((i == (size_t)RFE_FL) || (i == (size_t)RFE_RL)) ? y_J : -y_J;
    rfe_fix_t fx = 0;
    rfe_fix_t fy = 0;
    int64_t fbx;
    int64_t fby;
    int64_t m3;

    /* the curve of tp's mode, as rfe_tyre_forces_abs_q31 chooses it */
    if (tp->mode == RFE_TYRE_MAGIC) {
        rfe_tyre_magic_mu_q31(tp, pre, mu, fz, &fx, &fy, sat);
    } else {
        rfe_tyre_dugoff_mu_q31(pre, mu, fz, &fx, &fy, sat);
    }
    /* Exact Q45: |fx c - fy s| <= |(fx, fy)| |(c, s)| <= 2^31.5 2^30 (1 + 2^-30) < 2^62. */
    fbx = ((int64_t)fx * ci) - ((int64_t)fy * si);
    fby = ((int64_t)fx * si) + ((int64_t)fy * ci);
    /* [Fbx/m, Fby/m] (Q45 x Q38 / 2^59 -> Q24) and (x_i Fby - y_i Fbx)/J (two Q30 terms
     * < 2^39.5, rounded once more to Q24). */
    m3 = rfe_q31_mul64x32(fby, px_J, 53u) - rfe_q31_mul64x32(fbx, py_J, 53u);
    col[0] = rfe_fix_sat32(rfe_q31_mul64x32(fbx, veh->inv_m, 59u), sat);
    col[1] = rfe_fix_sat32(rfe_q31_mul64x32(fby, veh->inv_m, 59u), sat);
    col[2] = rfe_fix_narrow(m3, 6u, sat);
}

void rfe_meas_sum_columns_q31(const rfe_fix_t col[RFE_MEAS_Q31_COLS], rfe_fix_t z[RFE_MEAS],
                              uint32_t *sat)
{
    size_t r;
    size_t i;
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        int64_t acc = 0; /* four int32: exact */
        for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
            acc += (int64_t)col[(i * (size_t)RFE_MEAS) + r];
        }
        z[r] = rfe_fix_sat32(acc, sat);
    }
}

/* Load-scaled modes (absolute, magic): each wheel's friction-independent tyre terms (zeros
 * when the tyre's Dugoff parameters are invalid, which eval then rejects). They depend on
 * cx, cy, eps and alpha_max only, not on the mode or the shape factors, so the record of
 * those four is all eval needs to know whether it may use them. */
static void meas_setup_pre(rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp)
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        const rfe_dugoff_pre_q31_t zero = {0, 0, 0, 0, 0, 0, 0u};
        h->pre[i] = zero;
        if ((tp->mode != RFE_TYRE_PAPER) && (rfe_tyre_dugoff_params_ok_q31(tp) != 0)) {
            rfe_tyre_dugoff_pre_q31(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i],
                                    &h->pre[i]);
        }
    }
    h->pre_cx = tp->cx;
    h->pre_cy = tp->cy;
    h->pre_eps = tp->eps;
    h->pre_alpha_max = tp->alpha_max;
}

/* 1 for the three tyre modes (paper, absolute, magic). */
static int meas_mode_ok(rfe_tyre_mode_t mode)
{
    return ((mode == RFE_TYRE_PAPER) || (mode == RFE_TYRE_ABSOLUTE) || (mode == RFE_TYRE_MAGIC))
               ? 1
               : 0;
}

rfe_status_t rfe_meas_setup_q31(rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u,
                                uint32_t *sat)
{
    rfe_wheel_kin_q31_t kin;
    rfe_tyre_kin_extra_q31_t extra;
    rfe_fix_t H[RFE_H_Q31_SIZE] = {0};
    uint32_t count = 0u;
    rfe_status_t st;
    size_t i;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (meas_mode_ok(tp->mode) == 0) {
        return RFE_ERR_PARAM;
    }
    st = rfe_tyre_kinematics_ex_q31(veh, tp, u, &kin, &extra);
    if ((st == RFE_OK) && (tp->mode == RFE_TYRE_PAPER)) {
        rfe_fix_t f0x[RFE_WHEELS];
        rfe_fix_t f0y[RFE_WHEELS];
        st = rfe_tyre_forces_norm_q31(tp, &kin, f0x, f0y, &count);
        if (st == RFE_OK) {
            st = rfe_obsmat_build_q31(veh, u->delta, f0x, f0y, H, &count);
        }
    }
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        count += extra.sat_vwx[i] + extra.sat_fz[i]; /* at most 2 each */
        h->sat_vwx[i] = extra.sat_vwx[i];
        h->sat_fz[i] = extra.sat_fz[i];
    }
    h->mode = tp->mode;
    h->delta = u->delta;
    h->kin = kin;
    for (i = 0u; i < RFE_H_Q31_SIZE; ++i) {
        h->H[i] = H[i];
    }
    h->cos_delta = extra.cos_delta;
    h->sin_delta = extra.sin_delta;
    meas_setup_pre(h, tp);
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

/* 1 when pre was computed with these tyre parameters (the mode and the shape factors do not
 * enter pre: a set-up in one load-scaled mode serves an evaluation in the other). */
static int meas_pre_matches(const rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp)
{
    return ((h->pre_cx == tp->cx) && (h->pre_cy == tp->cy) && (h->pre_eps == tp->eps) &&
            (h->pre_alpha_max == tp->alpha_max))
               ? 1
               : 0;
}

/* Load-scaled modes: forces at this mu (nonlinear in mu; the curve of tp->mode, as
 * rfe_tyre_forces_abs_q31 chooses it), then the same geometry as H's columns:
 * z_r = sum_i H_r,i(F(mu_i)) (MODEL.md §4-5). The checks of rfe_tyre_forces_abs_q31, in its
 * order. */
static rfe_status_t meas_eval_abs(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                  const rfe_tyre_params_q31_t *tp,
                                  const rfe_fix_t mu[RFE_WHEELS], rfe_fix_t z[RFE_MEAS],
                                  uint32_t *sat)
{
    rfe_fix_t col[RFE_MEAS_Q31_COLS];
    uint32_t count = 0u;
    int cached;
    size_t i;

    if (rfe_tyre_abs_params_ok_q31(tp) == 0) {
        return RFE_ERR_PARAM;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if (h->kin.fz[i] < 0) {
            return RFE_ERR_RANGE;
        }
    }
    cached = meas_pre_matches(h, tp);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_dugoff_pre_q31_t fresh;
        const rfe_dugoff_pre_q31_t *pre = &h->pre[i];
        if (cached == 0) {
            rfe_tyre_dugoff_pre_q31(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i],
                                    &fresh);
            pre = &fresh;
        }
        rfe_meas_wheel_column_q31(veh, tp, pre, mu[i], h->kin.fz[i], h->cos_delta,
                                  h->sin_delta, i, &col[i * (size_t)RFE_MEAS], &count);
    }
    rfe_meas_sum_columns_q31(col, z, &count);
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

rfe_status_t rfe_meas_eval_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                               const rfe_tyre_params_q31_t *tp, const rfe_fix_t mu[RFE_WHEELS],
                               rfe_fix_t z[RFE_MEAS], uint32_t *sat)
{
    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (mu == NULL) || (z == NULL) ||
        (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (h->mode == RFE_TYRE_PAPER) {
        return rfe_obsmat_apply_q31(h->H, mu, z, sat); /* h = H(u) mu */
    }
    return meas_eval_abs(h, veh, tp, mu, z, sat);
}
