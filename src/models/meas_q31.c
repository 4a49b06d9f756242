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

#include "rfe/component/fxmath.h"

#include "numerics/fxmath_internal_q31.h"
#include "numerics/internal_q31.h"
#include "numerics/xf_q31.h"
#include "models/meas_inputs.h"
#include "models/tyre_internal_q31.h"
#include "models/meas_cols_internal_q31.h"
#include "models/meas_internal_q31.h"

/* Entries of the four wheels' terms side by side (wheel i at i RFE_MEAS). */
#define COLS ((size_t)RFE_WHEELS * (size_t)RFE_MEAS)

/* 1.0 in Q30, 2^30 (cos of an unsteered wheel). */
#define ONE_Q30 ((int32_t)0x40000000)

/* In the load-scaled tyre modes (absolute Dugoff, Magic Formula), h(mu, u) is
 * z_r = sat(sum_i t_i,r) (exact int64 sum of the four wheels' terms): the column of H
 * (MODEL.md §5) that wheel i's forces F(mu_i) give, with the entries rfe_obsmat_build_q31
 * computes, bit for bit. A caller may therefore reuse the terms of the wheels an input change
 * does not touch. */

/* Wheel i's terms (Q24, RFE_MEAS entries: its column of H at its forces) from its
 * friction-independent tyre terms pre (of rfe_tyre_dugoff_pre_q31 at tp), friction mu (Q29),
 * load fz (Q15, >= 0) and c, s = cos, sin of delta (Q30; ignored for the rear wheels); the
 * forces of tp->mode's curve (rfe_tyre_dugoff_abs_pre_q31, as rfe_tyre_forces_abs_q31 chooses
 * it; tp passed rfe_tyre_abs_params_ok_q31); saturations
 * (forces, entries) counted in *sat. */
static void body_terms_q31(const rfe_vehicle_q31_t *veh, rfe_fix_t fx, rfe_fix_t fy, int32_t c,
                           int32_t s, size_t i, rfe_fix_t col[RFE_MEAS], uint32_t *sat);

static void wheel_terms_q31(const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
                            const rfe_dugoff_pre_q31_t *pre, rfe_fix_t mu, rfe_fix_t fz,
                            int32_t c, int32_t s, size_t i, rfe_fix_t col[RFE_MEAS],
                            uint32_t *sat)
{
    rfe_fix_t fx = 0;
    rfe_fix_t fy = 0;
    /* the curve of tp's mode, as rfe_tyre_forces_abs_q31 chooses it */
    rfe_tyre_dugoff_abs_pre_q31(tp, pre, mu, fz, &fx, &fy, sat);
    body_terms_q31(veh, fx, fy, c, s, i, col, sat);
}

/* Wheel i's terms (Q24) of its forces fx, fy (Q15, wheel axes): wheel_terms_q31's geometry. */
static void body_terms_q31(const rfe_vehicle_q31_t *veh, rfe_fix_t fx, rfe_fix_t fy, int32_t c,
                           int32_t s, size_t i, rfe_fix_t col[RFE_MEAS], uint32_t *sat)
{
    /* Front wheels are rotated by delta into body axes, rear wheels are not; x_i / J and
     * y_i / J (MODEL.md §1 positions), Q38. As rfe_obsmat_build_q31's column i. */
    const int64_t ci = (i < (size_t)RFE_RL) ? (int64_t)c : (int64_t)ONE_Q30;
    const int64_t si = (i < (size_t)RFE_RL) ? (int64_t)s : 0;
    const int64_t px_J = (i < (size_t)RFE_RL) ? (int64_t)veh->lf_J : -(int64_t)veh->lr_J;
    const int64_t y_J = (i < (size_t)RFE_RL) ? (int64_t)veh->yf_J : (int64_t)veh->yr_J;
    const int64_t py_J = ((i == (size_t)RFE_FL) || (i == (size_t)RFE_RL)) ? y_J : -y_J;
    int64_t fbx;
    int64_t fby;
    int64_t m3;

    /* Exact Q45: |fx c - fy s| <= |(fx, fy)| |(c, s)| <= 2^31.5 2^30 (1 + 2^-30) < 2^62. */
    fbx = rfe_fix_mul_m31(fx, ci) - rfe_fix_mul_m31(fy, si);
    fby = rfe_fix_mul_m31(fx, si) + rfe_fix_mul_m31(fy, ci);
    /* [Fbx/m, Fby/m] (Q45 x Q38 / 2^59 -> Q24) and (x_i Fby - y_i Fbx)/J (two Q30 terms
     * < 2^39.5, rounded once more to Q24). */
    m3 = rfe_q31_mul64x32(fby, px_J, 53u) - rfe_q31_mul64x32(fbx, py_J, 53u);
    col[0] = rfe_fix_sat32(rfe_q31_mul64x32(fbx, veh->inv_m, 59u), sat);
    col[1] = rfe_fix_sat32(rfe_q31_mul64x32(fby, veh->inv_m, 59u), sat);
    col[2] = rfe_fix_narrow(m3, 6u, sat);
}

/* z_r = the saturated sum of the four wheels' terms (col[i RFE_MEAS + r], wheel i), counted
 * in *sat. */
static void sum_terms_q31(const rfe_fix_t col[COLS], rfe_fix_t z[RFE_MEAS], uint32_t *sat)
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
 * cx, cy, eps and alpha_max only, not on the shape factors, so the record of those four
 * (and of the set-up's mode: a Magic Formula set-up leaves out E and 1 - |k|, which only the
 * Dugoff curve reads) is all eval needs to know whether it may use them. */
static void setup_pre_q31(rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp)
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if ((tp->mode != RFE_TYRE_PAPER) && (rfe_tyre_dugoff_params_ok_q31(tp) != 0)) {
            /* every field written (dugoff_pre_e) */
            rfe_tyre_dugoff_pre_q31(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i],
                                    &h->pre[i]);
        } else {
            const rfe_dugoff_pre_q31_t zero = {0, 0, 0, 0, 0, 0, 0u};
            h->pre[i] = zero;
        }
    }
    h->pre_cx = tp->cx;
    h->pre_cy = tp->cy;
    h->pre_eps = tp->eps;
    h->pre_alpha_max = tp->alpha_max;
}

/* 1 for the three tyre modes (paper, absolute, magic). */
static int mode_ok_q31(rfe_tyre_mode_t mode)
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
    if (mode_ok_q31(tp->mode) == 0) {
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
    setup_pre_q31(h, tp);
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

/* 1 when pre was computed with these tyre parameters (the shape factors do not enter pre; an
 * absolute (Dugoff) set-up serves an evaluation in either load-scaled mode, a Magic Formula
 * set-up, without E and 1 - |k| (rfe_tyre_dugoff_pre_q31), a Magic Formula one only). */
static int pre_matches_q31(const rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp)
{
    return ((h->pre_cx == tp->cx) && (h->pre_cy == tp->cy) && (h->pre_eps == tp->eps) &&
            (h->pre_alpha_max == tp->alpha_max) &&
            ((h->mode != RFE_TYRE_MAGIC) || (tp->mode == RFE_TYRE_MAGIC)))
               ? 1
               : 0;
}

/* The load-scaled evaluation's checks, in their order: the tyre parameters, then no wheel
 * with a negative load. */
static rfe_status_t abs_inputs_ok_q31(const rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp)
{
    size_t i;
    if (rfe_tyre_abs_params_ok_q31(tp) == 0) {
        return RFE_ERR_PARAM;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if (h->kin.fz[i] < 0) {
            return RFE_ERR_RANGE;
        }
    }
    return RFE_OK;
}

/* Load-scaled modes: forces at this mu (nonlinear in mu; the curve of tp->mode, as
 * rfe_tyre_forces_abs_q31 chooses it), then the same geometry as H's columns:
 * z_r = sum_i H_r,i(F(mu_i)) (MODEL.md §4-5). The checks of rfe_tyre_forces_abs_q31, in its
 * order. */
static rfe_status_t eval_abs_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                  const rfe_tyre_params_q31_t *tp,
                                  const rfe_fix_t mu[RFE_WHEELS], rfe_fix_t z[RFE_MEAS],
                                  uint32_t *sat)
{
    rfe_fix_t col[COLS];
    uint32_t count = 0u;
    int cached;
    size_t i;
    rfe_status_t st;

    st = abs_inputs_ok_q31(h, tp);
    if (st != RFE_OK) {
        return st;
    }
    cached = pre_matches_q31(h, tp);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_dugoff_pre_q31_t fresh;
        const rfe_dugoff_pre_q31_t *pre = &h->pre[i];
        if (cached == 0) {
            rfe_tyre_dugoff_pre_q31(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i],
                                    &fresh);
            pre = &fresh;
        }
        wheel_terms_q31(veh, tp, pre, mu[i], h->kin.fz[i], h->cos_delta, h->sin_delta, i,
                        &col[i * (size_t)RFE_MEAS], &count);
    }
    sum_terms_q31(col, z, &count);
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
    return eval_abs_q31(h, veh, tp, mu, z, sat);
}

/* ---- the model at a perturbed input (the step noise, docs/ESTIMATOR.md step 4) ---------------
 * Load-scaled modes: only the wheels an input reaches are evaluated again (meas_inputs.h);
 * the others keep their nominal terms and saturation counts: the same integers as a full
 * evaluation, so the same sums and counts. */

/* generated by scripts/codegen/twins.py from meas_input_slot: do not edit; make twins */
/* Input j (RFE_IN_*) of the sample. */
static rfe_fix_t *input_slot_q31(rfe_sample_q31_t *u, size_t j)
{
    rfe_fix_t *slot;
    switch (j) {
    case RFE_IN_DELTA:
        slot = &u->delta;
        break;
    case RFE_IN_VX:
        slot = &u->vx;
        break;
    case RFE_IN_VY:
        slot = &u->vy;
        break;
    case RFE_IN_YAW_RATE:
        slot = &u->yaw_rate;
        break;
    default:
        slot = &u->omega[j - (size_t)RFE_IN_OMEGA];
        break;
    }
    return slot;
}
/* end generated */

/* The nominal terms of the four wheels and each one's saturation count (its kinematics'
 * from the set-up, its forces' and entries'). */
static void nominal_terms_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                              const rfe_tyre_params_q31_t *tp, const rfe_fix_t *mu,
                              rfe_meas_terms_q31_t *nom)
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        nom->cnt[i] = h->sat_vwx[i] + h->sat_fz[i];
        wheel_terms_q31(veh, tp, &h->pre[i], mu[i], h->kin.fz[i], h->cos_delta, h->sin_delta,
                        i, &nom->t[i * (size_t)RFE_MEAS], &nom->cnt[i]);
    }
}

rfe_status_t rfe_meas_nominal_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                  const rfe_tyre_params_q31_t *tp,
                                  const rfe_fix_t mu[RFE_WHEELS], rfe_meas_terms_q31_t *nom,
                                  rfe_fix_t z[RFE_MEAS], uint32_t *sat)
{
    uint32_t count = 0u;
    size_t i;
    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (mu == NULL) || (nom == NULL) ||
        (z == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (h->mode == RFE_TYRE_PAPER) {
        return rfe_meas_eval_q31(h, veh, tp, mu, z, sat);
    }
    nominal_terms_q31(h, veh, tp, mu, nom);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_q31_sat_add(&count, nom->cnt[i]);
    }
    sum_terms_q31(nom->t, z, &count);
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

/* Terms of wheel i (reached by input j) for the perturbed sample up; c, s: cos/sin of
 * up->delta. Its saturation count into *cnt. */
static void perturbed_terms_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *up,
                                size_t j, size_t i, int32_t c, int32_t s, rfe_fix_t mu,
                                rfe_fix_t t[RFE_MEAS], uint32_t *cnt)
{
    rfe_dugoff_pre_q31_t pre;
    *cnt = h->sat_fz[i];
    if (j >= (size_t)RFE_IN_OMEGA) {
        /* a wheel speed: kappa changes; vwx, alpha and so tan alpha are the nominal ones */
        const rfe_fix_t kappa = rfe_tyre_wheel_kappa_q31(veh, tp, up, c, s, i);
        *cnt += h->sat_vwx[i];
        rfe_tyre_dugoff_pre_tan_q31(tp, kappa, h->pre[i].tan_a, h->kin.vwx[i], &pre);
    } else {
        rfe_fix_t vwx = 0;
        rfe_fix_t alpha = 0;
        rfe_fix_t kappa = 0;
        rfe_tyre_wheel_kin_q31(veh, tp, up, c, s, i, &vwx, &alpha, &kappa, cnt);
        rfe_tyre_dugoff_pre_q31(tp, kappa, alpha, vwx, &pre);
    }
    wheel_terms_q31(veh, tp, &pre, mu, h->kin.fz[i], c, s, i, t, cnt);
}

/* z = h(mu, up) (Q24) for the sample u with input j perturbed (up), from the nominal
 * terms of the wheels j does not reach. */
static void perturbed_sum_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                              const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *up,
                              size_t j, const rfe_fix_t *mu, const rfe_meas_terms_q31_t *nom,
                              rfe_fix_t z[RFE_MEAS], uint32_t *count)
{
    rfe_fix_t col[COLS];
    int32_t c = h->cos_delta;
    int32_t s = h->sin_delta;
    size_t i;
    size_t r;
    if (j == (size_t)RFE_IN_DELTA) {
        rfe_q31_sincos_q29(up->delta, &s, &c); /* every angle */
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_fix_t *ci = &col[i * (size_t)RFE_MEAS];
        uint32_t cnt = nom->cnt[i];
        if (rfe_input_reaches(j, i) != 0) {
            perturbed_terms_q31(h, veh, tp, up, j, i, c, s, mu[i], ci, &cnt);
        } else {
            for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
                ci[r] = nom->t[(i * (size_t)RFE_MEAS) + r];
            }
        }
        rfe_q31_sat_add(count, cnt);
    }
    sum_terms_q31(col, z, count);
}

rfe_status_t rfe_meas_eval_perturbed_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                         const rfe_tyre_params_q31_t *tp,
                                         const rfe_meas_terms_q31_t *nom,
                                         const rfe_sample_q31_t *u, size_t j, rfe_fix_t d,
                                         const rfe_fix_t mu[RFE_WHEELS], rfe_fix_t z[RFE_MEAS],
                                         uint32_t *sat)
{
    rfe_sample_q31_t up;
    uint32_t count = 0u;
    rfe_status_t st = RFE_OK;
    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (nom == NULL) || (u == NULL) ||
        (mu == NULL) || (z == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (j >= (size_t)RFE_INPUTS) {
        return RFE_ERR_PARAM;
    }
    up = *u;
    *input_slot_q31(&up, j) = rfe_fix_add(*input_slot_q31(&up, j), d, &count);
    if (h->mode == RFE_TYRE_PAPER) {
        /* the model of the perturbed sample, set up and evaluated in full */
        rfe_meas_q31_t hp;
        st = rfe_meas_setup_q31(&hp, veh, tp, &up, &count);
        if (st == RFE_OK) {
            st = rfe_meas_eval_q31(&hp, veh, tp, mu, z, &count);
        }
    } else {
        perturbed_sum_q31(h, veh, tp, &up, j, mu, nom, z, &count);
    }
    if (st == RFE_OK) {
        rfe_q31_sat_add(sat, count);
    }
    return st;
}

/* ---- the lateral rows and their derivatives (docs/OBSERVER.md §4.2) -------------------------- */

/* Wheel i's input change per unit of vy (meas_flt.c vy_direction) in rfe_xf_t: ci, si Q30 the
 * cos, sin of its steer angle, t30 its tan(alpha) (Q26). den = max(|omega R|, |v_wx|, v_min)
 * in Q51, as the kinematics form it. Each numerator is formed exactly in int64 and divided
 * once (one rounding each, 2^-30 relative): ci 2^26 + t sgn(v_wx) si in Q56 (|t| < 5.8 2^26 <
 * 2^29, so |t si| < 2^59 and the sum < 2^59.3), (1 + own) si in Q60 ((1 + own) <= 2 in Q30,
 * the product <= 2^61); si = 0 (the rear wheels, no steer) gives d.k = 0 without a division. */
static rfe_slip_dir_q31_t vy_direction_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                           const rfe_tyre_params_q31_t *tp,
                                           const rfe_sample_q31_t *u, size_t i, int32_t ci,
                                           int32_t si, int32_t tan_a)
{
    const int32_t vwx = h->kin.vwx[i];
    const int32_t kappa = h->kin.kappa[i];
    const int sv = rfe_q31_sign(vwx);
    rfe_slip_dir_q31_t d;
    d.vwx = rfe_xf_of(si, 30);
    d.tan_a = rfe_xf_make(0, 0);
    d.k = rfe_xf_make(0, 0);
    if ((rfe_q31_within(h->kin.alpha[i], tp->alpha_max - 1) != 0) && (vwx != 0)) {
        /* -(ci + t sgn(v_wx) si) / |v_wx| */
        const int64_t ts = (int64_t)((sv > 0) ? tan_a : -tan_a) * (int64_t)si;
        const int64_t num = ((int64_t)ci * rfe_q31_pow2(26u)) + ts;
        const rfe_xf_t avx = rfe_xf_of((vwx < 0) ? -vwx : vwx, (int)RFE_FIX_Q_SPEED);
        d.tan_a = rfe_xf_neg(rfe_xf_div(rfe_xf_make(num, -56), avx));
    }
    if ((rfe_q31_within(kappa, ONE_Q30 - 1) != 0) && (si != 0)) {
        /* -(1 + [den = |v_wx|] kappa sgn(v_wx)) si / den, all three in Q51 */
        const uint64_t avr = rfe_q31_mag64((int64_t)u->omega[i] * (int64_t)veh->R);
        const uint64_t avx = (uint64_t)((vwx < 0) ? -(int64_t)vwx : (int64_t)vwx) << 28;
        const uint64_t vmin = (uint64_t)tp->v_min << 28;
        const uint64_t big = (avr > avx) ? avr : avx;
        const uint64_t den = (big > vmin) ? big : vmin;
        int64_t one_own = ONE_Q30;
        if ((avx > avr) && (avx > vmin)) {
            one_own += (sv > 0) ? kappa : -(int64_t)kappa;
        }
        d.k = rfe_xf_neg(rfe_xf_div(rfe_xf_make(one_own * (int64_t)si, -60),
                                    rfe_xf_make((int64_t)den, -51)));
    }
    return d;
}

/* Wheel i's friction-independent tyre terms for the derivative (meas_flt.c jac_pre). */
static void jac_pre_q31(const rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp, int cached,
                        size_t i, rfe_dugoff_pre_q31_t *pre)
{
    if (h->mode == RFE_TYRE_PAPER) {
        rfe_tyre_norm_pre_q31(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i], pre);
    } else if (cached != 0) {
        *pre = h->pre[i];
    } else {
        rfe_tyre_dugoff_pre_q31(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i], pre);
    }
}

/* Wheel i's map of a force pair (wheel axes) into the body terms (ax, ay, r-dot): the rotation
 * by the steer angle folded into the geometry, ax += fx ay - fy ax, ay += fx ax + fy ay and
 * r-dot += fx rx + fy ry with (c, s the steer angle's cos and sin on the front axle, 1 and 0 on
 * the rear; x_i / J, y_i / J the signed lever arms of wheel_terms_q31):
 *   ax = s / m,  ay = c / m,  rx = s x_i / J - c y_i / J,  ry = c x_i / J + s y_i / J.
 * Each coefficient is formed exactly in int64 (Q30 x Q38 = Q68, each product < 2^61, a sum of
 * two < 2^62), then rounded once to Q36 (lat_map_q36): four products and four sums per force
 * pair instead of eight and six. */
/* The map's four coefficients exactly in Q68 (k = ax, ay, rx, ry). */
static void lat_coef_q31(const rfe_vehicle_q31_t *veh, int32_t c, int32_t s, size_t i,
                         int64_t k[4])
{
    const int32_t px_J = (i < (size_t)RFE_RL) ? veh->lf_J : -veh->lr_J;
    const int32_t y_J = (i < (size_t)RFE_RL) ? veh->yf_J : veh->yr_J;
    const int32_t py_J = ((i == (size_t)RFE_FL) || (i == (size_t)RFE_RL)) ? y_J : -y_J;
    const int32_t ci = (i < (size_t)RFE_RL) ? c : ONE_Q30;
    const int32_t si = (i < (size_t)RFE_RL) ? s : 0;
    k[0] = rfe_fix_mul32x32(si, veh->inv_m);
    k[1] = rfe_fix_mul32x32(ci, veh->inv_m);
    k[2] = rfe_fix_mul32x32(si, px_J) - rfe_fix_mul32x32(ci, py_J);
    k[3] = rfe_fix_mul32x32(ci, px_J) + rfe_fix_mul32x32(si, py_J);
}

/* The map in plain Q36 integers (lat_q36_t, meas_cols_internal_q31.h). */
static void lat_map_q36(const rfe_vehicle_q31_t *veh, int32_t c, int32_t s, size_t i,
                        lat_q36_t *b)
{
    int64_t k[4];
    lat_coef_q31(veh, c, s, i, k);
    b->ax = (int32_t)rfe_fix_shr64_round(k[0], 32u);
    b->ay = (int32_t)rfe_fix_shr64_round(k[1], 32u);
    b->rx = (int32_t)rfe_fix_shr64_round(k[2], 32u);
    b->ry = (int32_t)rfe_fix_shr64_round(k[3], 32u);
}

/* One wheel's part of the lateral rows (ay, r-dot) for a force pair (fx, fy), integers at one
 * exponent per wheel: t[r] 2^e (any = 0: both forces 0, t = 0). */
typedef struct {
    int64_t t[2];
    int e;
    int any;
} lat_part_q31_t;

/* The mantissa of a (|a.m| <= 2^30) at exponent e >= a.e, rounded half up (0 when a is 0):
 * rfe_fix_shr64_round's integer, formed in 32 bits by rfe_xf_round (shifts 1 .. 33, where
 * |a.m| < 2^(30 + sh)). A shift beyond 33 is taken as 33: |a.m| / 2^sh <= 2^-3 rounds to 0
 * at either. */
static int32_t xf_mant_at_q31(rfe_xf_t a, int e)
{
    int32_t v = a.m; /* sh = 0: the mantissa itself (0 when a is 0) */
    const int sh = e - a.e;
    if (sh > 0) {
        const unsigned int s = (sh > 33) ? 33u : (unsigned int)sh;
        v = rfe_xf_round((int64_t)a.m, s);
    }
    return v;
}

/* Wheel i's part of the lateral rows of (fx, fy) by the Q36 map b: both mantissas at the larger
 * exponent E (the smaller one rounded half up there, 1/2 unit = 2^-31 of the larger force),
 * |m| <= 2^30, times the coefficients (|.| < 2^29.5): each product < 2^59.5, the row's two
 * < 2^60.5, exact, at exponent E - 36. */
static void lat_part_q31(const lat_q36_t *b, rfe_xf_t fx, rfe_xf_t fy, lat_part_q31_t *p)
{
    p->t[0] = 0;
    p->t[1] = 0;
    p->e = 0;
    p->any = 0;
    if ((fx.m != 0) || (fy.m != 0)) {
        int e = (fx.m != 0) ? fx.e : fy.e;
        int64_t mx;
        int64_t my;
        if ((fy.m != 0) && (fy.e > e)) {
            e = fy.e;
        }
        mx = (int64_t)xf_mant_at_q31(fx, e);
        my = (int64_t)xf_mant_at_q31(fy, e);
        p->t[0] = (mx * (int64_t)b->ax) + (my * (int64_t)b->ay);
        p->t[1] = (mx * (int64_t)b->rx) + (my * (int64_t)b->ry);
        p->e = e - 36;
        p->any = 1;
    }
}

/* The largest exponent of the wheels' parts p (0 when no wheel has one): both lateral rows
 * sum at it, so it is found once for the two (lat_row_q31). */
static int lat_emax_q31(const lat_part_q31_t p[RFE_WHEELS])
{
    int emax = 0;
    int any = 0;
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if ((p[i].any != 0) && ((any == 0) || (p[i].e > emax))) {
            emax = p[i].e;
            any = 1;
        }
    }
    return emax;
}

/* Row r of the sum over the wheels' parts p in Q24, rounded half up and saturating (counted in
 * *count): every part at the largest exponent E of the wheels' (@p emax, lat_emax_q31; a
 * smaller one rounded half up, 1/2 unit of 2^E), the sum of four parts < 2^60.5 each <
 * 2^62.5 exact, then rounded once to Q24 (or shifted up exactly while below 2^62, saturating
 * beyond: q24_of_scaled_q31). */
static rfe_fix_t lat_row_q31(const lat_part_q31_t p[RFE_WHEELS], size_t r, int emax,
                             uint32_t *count)
{
    int64_t sum = 0;
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if (p[i].any != 0) {
            const int sh = emax - p[i].e;
            sum += rfe_fix_shr64_round(p[i].t[r], (unsigned int)sh);
        }
    }
    return rfe_meas_q24_of_scaled_q31(sum, emax + 24, count);
}

/* Wheel i's Dugoff/Magic Formula pre-computed terms and its slip's direction of change by vy,
 * for the lateral rows' derivatives. */
static void wheel_dir_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                          const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u, int cached,
                          size_t i, rfe_dugoff_pre_q31_t *pre, rfe_slip_dir_q31_t *d)
{
    const int32_t ci = (i < (size_t)RFE_RL) ? h->cos_delta : ONE_Q30;
    const int32_t si = (i < (size_t)RFE_RL) ? h->sin_delta : 0;
    jac_pre_q31(h, tp, cached, i, pre);
    *d = vy_direction_q31(h, veh, tp, u, i, ci, si, pre->tan_a);
}

/* Wheel i's force derivatives, mapped to the body once (Q36, lat_map_q36), as its parts of the
 * sums by vy (pv) and by its friction along dmu_i (pm). */
static void wheel_add_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh, size_t i,
                          const rfe_tyre_jac_q31_t *f, rfe_fix_t dmu_i, lat_part_q31_t *pv,
                          lat_part_q31_t *pm)
{
    const rfe_xf_t sd = rfe_xf_of(dmu_i, 30);
    lat_q36_t bm;
    lat_map_q36(veh, h->cos_delta, h->sin_delta, i, &bm);
    lat_part_q31(&bm, f->dfx, f->dfy, pv);
    lat_part_q31(&bm, rfe_xf_mul(f->mfx, sd), rfe_xf_mul(f->mfy, sd), pm);
}

/* The wheels' parts of the derivatives' sums: by vy in pv, by mu along dmu in pm. */
static void lateral_sums_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                             const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u,
                             const rfe_fix_t *mu, const rfe_fix_t *dmu,
                             lat_part_q31_t pv[RFE_WHEELS], lat_part_q31_t pm[RFE_WHEELS])
{
    const int cached = pre_matches_q31(h, tp);
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_dugoff_pre_q31_t pre;
        rfe_slip_dir_q31_t d;
        rfe_tyre_jac_q31_t f;
        wheel_dir_q31(h, veh, tp, u, cached, i, &pre, &d);
        rfe_tyre_pre_jac_q31(tp, &pre, h->kin.kappa[i], h->kin.vwx[i], h->kin.fz[i], mu[i], &d,
                             &f);
        wheel_add_q31(h, veh, i, &f, dmu[i], &pv[i], &pm[i]);
    }
}

/* Load-scaled set-up, Magic Formula curve: z = h(mu, u) of rfe_meas_eval_q31 and the sums of
 * lateral_sums_q31 in one pass over the wheels, each wheel's curve (per direction two atan2
 * and a sine) evaluated once for its forces and their derivatives: the same integers. The
 * checks of eval_abs_q31, in its order. */
static rfe_status_t lateral_magic_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                      const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u,
                                      const rfe_fix_t *mu, const rfe_fix_t *dmu,
                                      rfe_fix_t z[RFE_MEAS], lat_part_q31_t pv[RFE_WHEELS],
                                      lat_part_q31_t pm[RFE_WHEELS], uint32_t *count)
{
    rfe_fix_t col[COLS];
    int cached;
    size_t i;
    const rfe_status_t st = abs_inputs_ok_q31(h, tp);
    if (st != RFE_OK) {
        return st;
    }
    cached = pre_matches_q31(h, tp);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_dugoff_pre_q31_t pre;
        rfe_slip_dir_q31_t d;
        rfe_tyre_jac_q31_t f;
        rfe_fix_t fx = 0;
        rfe_fix_t fy = 0;
        wheel_dir_q31(h, veh, tp, u, cached, i, &pre, &d);
        rfe_tyre_magic_pre_jac_q31(tp, &pre, h->kin.fz[i], mu[i], &d, &fx, &fy, count, &f);
        body_terms_q31(veh, fx, fy, h->cos_delta, h->sin_delta, i, &col[i * (size_t)RFE_MEAS],
                       count);
        wheel_add_q31(h, veh, i, &f, dmu[i], &pv[i], &pm[i]);
    }
    sum_terms_q31(col, z, count);
    return RFE_OK;
}

rfe_status_t rfe_meas_lateral_jac_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                      const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u,
                                      const rfe_fix_t mu[RFE_WHEELS],
                                      const rfe_fix_t dmu[RFE_WHEELS],
                                      rfe_meas_lateral_q31_t *out, uint32_t *sat)
{
    rfe_fix_t z[RFE_MEAS];
    lat_part_q31_t pv[RFE_WHEELS];
    lat_part_q31_t pm[RFE_WHEELS];
    uint32_t count = 0u;
    size_t r;
    int ev;
    int em;
    rfe_status_t st;
    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL) || (mu == NULL) ||
        (dmu == NULL) || (out == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_tyre_dugoff_params_ok_q31(tp) == 0) {
        return RFE_ERR_PARAM; /* paper mode's tangents need alpha_max; eval checks the rest */
    }
    if ((h->mode != RFE_TYRE_PAPER) && (tp->mode == RFE_TYRE_MAGIC)) {
        st = lateral_magic_q31(h, veh, tp, u, mu, dmu, z, pv, pm, &count);
    } else {
        st = rfe_meas_eval_q31(h, veh, tp, mu, z, &count);
        if (st == RFE_OK) {
            lateral_sums_q31(h, veh, tp, u, mu, dmu, pv, pm);
        }
    }
    if (st != RFE_OK) {
        return st;
    }
    ev = lat_emax_q31(pv);
    em = lat_emax_q31(pm);
    for (r = 0u; r < 2u; ++r) {
        out->z[r] = z[r + 1u];
        out->d_vy[r] = lat_row_q31(pv, r, ev, &count);
        out->d_mu[r] = lat_row_q31(pm, r, em, &count);
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

/* ---- the derivatives of h by the inputs (for the step noise, docs/ESTIMATOR.md step 4) ------ */

/* Wheel i's velocity in wheel axes (vw[0] = v_wx, vw[1] = v_wy) in Q21 (int32); c, s the cos,
 * sin of its steer angle (Q30). The body velocity at the wheel, v_i = (vx - r y_i, vy + r x_i):
 * vx, vy Q23 and r y_i (Q27 x Q29 = Q56, exact) in Q56 would overflow, so each is rounded to
 * Q21 (r y_i once, 2^-22 m/s): |vx| + |r y_i| < 256 + 16 4 < 2^8.4, < 2^29.4 in Q21; rotated
 * (Q21 x Q30, a sum of two < 2^60.9) and rounded once more to Q21 (|v_w| <= |v_i| < 2^8.9 m/s):
 * within 2^-21 m/s of the exact. */
static void wheel_velocity_q31(const rfe_vehicle_q31_t *veh, const rfe_sample_q31_t *u,
                               size_t i, int32_t c, int32_t s, int32_t vw[2])
{
    const int64_t x = (i < (size_t)RFE_RL) ? (int64_t)veh->Lf : -(int64_t)veh->Lr;
    const int64_t yy = (i < (size_t)RFE_RL) ? (int64_t)veh->yf : (int64_t)veh->yr;
    const int64_t y = ((i == (size_t)RFE_FL) || (i == (size_t)RFE_RL)) ? yy : -yy;
    const int64_t r = (int64_t)u->yaw_rate;
    const int64_t vbx = rfe_fix_shr64_round((int64_t)u->vx, 2u) - rfe_fix_shr64_round(r * y, 35u);
    const int64_t vby = rfe_fix_shr64_round((int64_t)u->vy, 2u) + rfe_fix_shr64_round(r * x, 35u);
    vw[0] = (int32_t)rfe_fix_shr64_round((vbx * (int64_t)c) + (vby * (int64_t)s), 30u);
    vw[1] = (int32_t)rfe_fix_shr64_round((vby * (int64_t)c) - (vbx * (int64_t)s), 30u);
}

/* Wheel i's forces' derivatives along unit changes of kappa, tan(alpha) and v_wx (meas_flt.c
 * wheel_basis; the Magic Formula's fj[2] is zero: its curve does not depend on v_wx; its curves
 * are evaluated once for both, rfe_tyre_magic_basis_q31) and, where turn != 0, its forces
 * (wheel axes) at mu_i for the turn of the front forces by delta: the curve's (load-scaled
 * modes; its saturations are the nominal evaluation's, not counted again), mu F0 in paper mode
 * (fj[0].mfx, fj[0].mfy are F0 there). */
static void wheel_basis_q31(const rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp,
                            const rfe_dugoff_pre_q31_t *pre, size_t i, rfe_fix_t mu, int turn,
                            rfe_tyre_jac_q31_t fj[3], rfe_xf_t f[2], rfe_fix_t fm[2],
                            uint32_t *fcnt)
{
    const rfe_xf_t zero = rfe_xf_make(0, 0);
    rfe_fix_t fx = 0;
    rfe_fix_t fy = 0;
    uint32_t scratch = 0u;
    fj[2].dfx = zero;
    fj[2].dfy = zero;
    if (tp->mode == RFE_TYRE_MAGIC) {
        /* the Magic Formula's forces at mu with their clamp counts (*fcnt): the nominal ones
         * of rfe_meas_nominal_input_jac_q31 */
        rfe_tyre_magic_basis_q31(tp, pre, h->kin.fz[i], mu, &fx, &fy, fcnt, fj);
    } else {
        const rfe_xf_t one = rfe_xf_make(1, 0);
        size_t b;
        for (b = 0u; b < 3u; ++b) {
            rfe_slip_dir_q31_t e;
            e.k = (b == 0u) ? one : zero;
            e.tan_a = (b == 1u) ? one : zero;
            e.vwx = (b == 2u) ? one : zero;
            rfe_tyre_dugoff_pre_jac_q31(tp, pre, h->kin.kappa[i], h->kin.vwx[i], h->kin.fz[i],
                                        mu, &e, &fj[b]);
        }
        if ((turn != 0) && (h->mode != RFE_TYRE_PAPER)) {
            rfe_tyre_dugoff_abs_pre_q31(tp, pre, mu, h->kin.fz[i], &fx, &fy, &scratch);
        }
    }
    fm[0] = fx;
    fm[1] = fy;
    f[0] = rfe_xf_of(fx, (int)RFE_FIX_Q_FORCE);
    f[1] = rfe_xf_of(fy, (int)RFE_FIX_Q_FORCE);
    if (h->mode == RFE_TYRE_PAPER) {
        const rfe_xf_t mux = rfe_xf_of(mu, (int)RFE_FIX_Q_MU);
        f[0] = rfe_xf_mul(mux, fj[0].mfx);
        f[1] = rfe_xf_mul(mux, fj[0].mfy);
    }
}

/* Wheel i's part of the input columns (wheel_cols_q31_t): its rows per unit velocity change
 * (rfe_meas_wheel_rows_q31), its velocity, and for delta the rows of the turn of its forces,
 * d(R(delta) F) = R(delta) (dF + (-Fy, Fx)) (rfe_meas_turn_rows_q31). Out of line
 * (RFE_XF_OUTLINE), so its locals are not in rfe_meas_input_jac_q31's frame beside the four
 * wheels' columns while the tyre derivatives run below it (Cortex-M0+: 752 B -> 368 + 288 B on
 * that path). */
RFE_XF_OUTLINE static void wheel_prepare_q31(const rfe_meas_q31_t *h,
                                             const rfe_vehicle_q31_t *veh,
                                             const rfe_tyre_params_q31_t *tp,
                                             const rfe_sample_q31_t *u, int cached, size_t i,
                                             rfe_fix_t mu, const rfe_fix_t *sd,
                                             wheel_cols_q31_t *wc, rfe_fix_t fm[2],
                                             uint32_t *fcnt)
{
    lat_q36_t bm;
    rfe_dugoff_pre_q31_t pre;
    rfe_tyre_jac_q31_t fj[3];
    rfe_xf_t f[2];
    int turn = 0;
    if ((i < (size_t)RFE_RL) && (sd[RFE_IN_DELTA] > 0)) {
        turn = 1;
    }
    wc->c = (i < (size_t)RFE_RL) ? h->cos_delta : ONE_Q30;
    wc->s = (i < (size_t)RFE_RL) ? h->sin_delta : 0;
    jac_pre_q31(h, tp, cached, i, &pre);
    wheel_basis_q31(h, tp, &pre, i, mu, turn, fj, f, fm, fcnt);
    lat_map_q36(veh, h->cos_delta, h->sin_delta, i, &bm);
    rfe_meas_wheel_rows_q31(h, veh, tp, u, i, pre.tan_a, &bm, fj, wc);
    wheel_velocity_q31(veh, u, i, wc->c, wc->s, wc->vw);
    rfe_meas_turn_rows_q31(&bm, rfe_xf_neg(f[1]), f[0], wc);
}

/* The argument checks of rfe_meas_input_jac_q31 after the NULLs: the tangents' bound (paper
 * mode too), then the load-scaled evaluation's. */
static rfe_status_t input_jac_ok_q31(const rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp)
{
    rfe_status_t st = RFE_OK;
    if (rfe_tyre_dugoff_params_ok_q31(tp) == 0) {
        st = RFE_ERR_PARAM; /* paper mode's tangents need alpha_max */
    } else if (h->mode != RFE_TYRE_PAPER) {
        st = abs_inputs_ok_q31(h, tp);
    } else {
        /* paper mode: nothing more */
    }
    return st;
}

rfe_status_t rfe_meas_input_jac_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                    const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u,
                                    const rfe_fix_t mu[RFE_WHEELS],
                                    const rfe_fix_t sd[RFE_INPUTS],
                                    rfe_fix_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS], uint32_t *sat)
{
    wheel_cols_q31_t wc[RFE_WHEELS];
    uint32_t count = 0u;
    int cached;
    size_t i;
    rfe_status_t st;
    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL) || (mu == NULL) ||
        (sd == NULL) || (G == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    st = input_jac_ok_q31(h, tp);
    if (st != RFE_OK) {
        return st;
    }
    cached = pre_matches_q31(h, tp);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_fix_t fm[2];
        uint32_t scratch = 0u; /* the forces' counts: the derivative counts none */
        wheel_prepare_q31(h, veh, tp, u, cached, i, mu[i], sd, &wc[i], fm, &scratch);
    }
    for (i = 0u; i < (size_t)RFE_INPUTS; ++i) {
        rfe_meas_input_column_q31(wc, veh, i, sd[i], G, &count);
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

int rfe_meas_one_pass_ok_q31(const rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp)
{
    /* tp's mode is MAGIC too: pre_matches_q31 requires it of a MAGIC set-up */
    return ((h != NULL) && (tp != NULL) && (h->mode == RFE_TYRE_MAGIC) &&
            (pre_matches_q31(h, tp) != 0))
               ? 1
               : 0;
}

/* 1 when none of rfe_meas_nominal_input_jac_q31's arrays and counter is NULL. */
static int one_pass_outputs_ok_q31(const rfe_fix_t *mu, const rfe_fix_t *sd, const rfe_fix_t *z,
                                   const rfe_fix_t *G, const uint32_t *sat)
{
    return ((mu != NULL) && (sd != NULL) && (z != NULL) && (G != NULL) && (sat != NULL)) ? 1 : 0;
}

rfe_status_t rfe_meas_nominal_input_jac_q31(const rfe_meas_q31_t *h,
                                            const rfe_vehicle_q31_t *veh,
                                            const rfe_tyre_params_q31_t *tp,
                                            const rfe_sample_q31_t *u,
                                            const rfe_fix_t mu[RFE_WHEELS],
                                            const rfe_fix_t sd[RFE_INPUTS],
                                            rfe_fix_t z[RFE_MEAS],
                                            rfe_fix_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS],
                                            uint32_t *sat)
{
    wheel_cols_q31_t wc[RFE_WHEELS];
    int64_t acc[RFE_MEAS] = {0, 0, 0};
    uint32_t ncount = 0u;
    uint32_t count = 0u;
    size_t i;
    size_t r;
    rfe_status_t st;
    if ((veh == NULL) || (u == NULL) || (one_pass_outputs_ok_q31(mu, sd, z, G, sat) == 0)) {
        return RFE_ERR_NULL;
    }
    if (rfe_meas_one_pass_ok_q31(h, tp) == 0) {
        /* also h or tp NULL */
        if ((h == NULL) || (tp == NULL)) {
            return RFE_ERR_NULL;
        }
        return RFE_ERR_PARAM; /* the caller makes the two calls */
    }
    /* rfe_meas_nominal_q31 makes no check in this mode; rfe_meas_input_jac_q31's, in order */
    st = input_jac_ok_q31(h, tp);
    if (st != RFE_OK) {
        return st;
    }
    /* each wheel's basis with its forces at mu and their clamp counts, which give its nominal
     * terms (nominal_terms_q31's count: the set-up's, the forces', the entries'), summed per
     * row as sum_terms_q31 sums them (four int32 in int64, exact, then saturated) without the
     * twelve terms side by side (the stack) */
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        uint32_t cnt = h->sat_vwx[i] + h->sat_fz[i];
        rfe_fix_t fm[2];
        rfe_fix_t col[RFE_MEAS];
        wheel_prepare_q31(h, veh, tp, u, 1, i, mu[i], sd, &wc[i], fm, &cnt);
        body_terms_q31(veh, fm[0], fm[1], h->cos_delta, h->sin_delta, i, col, &cnt);
        for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
            acc[r] += (int64_t)col[r];
        }
        rfe_q31_sat_add(&ncount, cnt);
    }
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        z[r] = rfe_fix_sat32(acc[r], &ncount);
    }
    for (i = 0u; i < (size_t)RFE_INPUTS; ++i) {
        rfe_meas_input_column_q31(wc, veh, i, sd[i], G, &count);
    }
    rfe_q31_sat_add(sat, ncount);
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}
