/**
 * @file meas_flt.c
 * @brief Measurement model h(mu, u) of one sample: paper (H(u) mu) or a load-scaled tyre
 *        (absolute Dugoff or Magic Formula).
 */
#include "rfe/component/meas.h"

#include "rfe/component/obsmat.h"

#include "numerics/internal.h"
#include "models/vehicle.h"
#include "models/meas_inputs.h"
#include "models/meas_internal.h"
#include "models/tyre_internal.h"

/* The four wheels' terms side by side (wheel i at i RFE_MEAS). */
#define COLS ((size_t)RFE_WHEELS * (size_t)RFE_MEAS)

/* FOUR_WHEELS: sums over the wheels are written out for four of them. */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_meas_four_wheels[(RFE_WHEELS == 4) ? 1 : -1];

/* Wheel i's column of H cleared (a load-scaled set-up's: H is paper mode's only), and its
 * kept force (every set-up's: none is kept yet). Called per wheel with constant indices, so
 * the stores stay stores: loops over the struct's arrays became memset calls (issue 16).
 * Every field of h is written by a set-up, as before. */
static void clear_column(rfe_meas_t *h, size_t i)
{
    h->H[RFE_H_AT(0u, i)] = RFE_R(0.0);
    h->H[RFE_H_AT(1u, i)] = RFE_R(0.0);
    h->H[RFE_H_AT(2u, i)] = RFE_R(0.0);
}

static void clear_memo(rfe_meas_t *h, size_t i)
{
    h->memo_mu[i] = RFE_R(0.0);
    h->memo_fx[i] = RFE_R(0.0);
    h->memo_fy[i] = RFE_R(0.0);
    h->memo_shape[i] = RFE_R(0.0);
}

/* The tyre parameters the set-up's terms belong to, and no kept forces (both modes). */
static void setup_record(rfe_meas_t *h, const rfe_tyre_params_t *tp)
{
    h->pre_cx = tp->cx;
    h->pre_cy = tp->cy;
    h->pre_eps = tp->eps;
    h->pre_alpha_max = tp->alpha_max;
    /* FOUR_WHEELS */
    clear_memo(h, 0u);
    clear_memo(h, 1u);
    clear_memo(h, 2u);
    clear_memo(h, 3u);
    h->memo_valid = 0;
}

/* Paper mode: the kinematics and H(u) built aside and written to h only when both succeed
 * (the forces or H can fail after the kinematics); no cos, sin or tyre terms (zeros). */
static rfe_status_t setup_paper(rfe_meas_t *h, const rfe_vehicle_t *veh,
                                const rfe_tyre_params_t *tp, const rfe_sample_t *u)
{
    rfe_wheel_kin_t kin;
    rfe_real_t H[RFE_H_SIZE] = {0};
    rfe_real_t f0x[RFE_WHEELS];
    rfe_real_t f0y[RFE_WHEELS];
    rfe_real_t c = RFE_R(0.0);
    rfe_real_t s = RFE_R(0.0);
    size_t i;
    rfe_status_t st = rfe_tyre_kinematics_cs(veh, tp, u, &kin, &c, &s);
    if (st == RFE_OK) {
        st = rfe_tyre_forces_norm(tp, &kin, f0x, f0y);
    }
    if (st == RFE_OK) {
        st = rfe_obsmat_build(veh, u->delta, f0x, f0y, H);
    }
    if (st != RFE_OK) {
        return st;
    }
    h->kin = kin;
    for (i = 0u; i < RFE_H_SIZE; ++i) {
        h->H[i] = H[i];
    }
    h->cos_delta = RFE_R(0.0);
    h->sin_delta = RFE_R(0.0);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        const rfe_dugoff_pre_t zero = {RFE_R(0.0), RFE_R(0.0), RFE_R(0.0), RFE_R(0.0),
                                       RFE_R(0.0), RFE_R(0.0), RFE_R(0.0)};
        h->pre[i] = zero;
    }
    return RFE_OK;
}

/* Load-scaled modes (absolute, magic): the kinematics straight into h (they write nothing
 * on an error and nothing fails after them), with the cos and sin of delta they computed;
 * H zero; each wheel's friction-independent tyre terms (rfe_tyre_dugoff_pre writes every
 * field). Issue 16: no kinematics or H built aside and copied, no cos and sin computed twice,
 * no terms cleared and then written: the same h as before. */
static rfe_status_t setup_scaled(rfe_meas_t *h, const rfe_vehicle_t *veh,
                                 const rfe_tyre_params_t *tp, const rfe_sample_t *u)
{
    rfe_real_t c = RFE_R(0.0);
    rfe_real_t s = RFE_R(0.0);
    size_t i;
    const rfe_status_t st = rfe_tyre_kinematics_cs(veh, tp, u, &h->kin, &c, &s);
    if (st != RFE_OK) {
        return st;
    }
    /* FOUR_WHEELS */
    clear_column(h, 0u);
    clear_column(h, 1u);
    clear_column(h, 2u);
    clear_column(h, 3u);
    h->cos_delta = c;
    h->sin_delta = s;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_tyre_dugoff_pre(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i], &h->pre[i]);
    }
    return RFE_OK;
}

rfe_status_t rfe_meas_setup(rfe_meas_t *h, const rfe_vehicle_t *veh,
                            const rfe_tyre_params_t *tp, const rfe_sample_t *u)
{
    rfe_status_t st;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL)) {
        return RFE_ERR_NULL;
    }
    if (tp->mode == RFE_TYRE_PAPER) {
        st = setup_paper(h, veh, tp, u);
    } else {
        st = setup_scaled(h, veh, tp, u);
    }
    if (st != RFE_OK) {
        return st;
    }
    h->mode = tp->mode;
    h->delta = u->delta;
    setup_record(h, tp);
    return RFE_OK;
}

/* z = H(u) mu with the H of rfe_meas_setup, the sums of rfe_obsmat_apply in the same order
 * (the same result, bit for bit), without re-checking H at every cubature point: setup built
 * it from finite forces. A non-finite mu is rejected as rfe_obsmat_apply rejects it. */
static rfe_status_t apply_paper(const rfe_real_t H[RFE_H_SIZE], const rfe_real_t mu[RFE_WHEELS],
                                rfe_real_t z[RFE_MEAS])
{
    size_t r;
    if (!rfe_all_finite(mu, RFE_WHEELS)) {
        return RFE_ERR_NONFINITE;
    }
    /* the four wheels written out (FOUR_WHEELS): acc += H[r][i] mu[i] from acc = 0, in wheel
     * order, without the inner loop's counting (issue 21) */
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        z[r] = (((RFE_R(0.0) + (H[RFE_H_AT(r, 0u)] * mu[0])) + (H[RFE_H_AT(r, 1u)] * mu[1])) +
                (H[RFE_H_AT(r, 2u)] * mu[2])) +
               (H[RFE_H_AT(r, 3u)] * mu[3]);
    }
    return RFE_OK;
}

/* Wheel i's terms of z (the entries rfe_obsmat_build would put in its column): body-axis
 * force over m and yaw moment over J, (px, py) its position. */
static void wheel_terms(const rfe_vehicle_t *veh, rfe_real_t c, rfe_real_t s, size_t i,
                        rfe_real_t px, rfe_real_t py, rfe_real_t fx, rfe_real_t fy,
                        rfe_real_t t[RFE_MEAS])
{
    /* Front wheels are rotated by delta into body axes, rear wheels are not. */
    const rfe_real_t ci = (i < (size_t)RFE_RL) ? c : RFE_R(1.0);
    const rfe_real_t si = (i < (size_t)RFE_RL) ? s : RFE_R(0.0);
    const rfe_real_t fbx = (fx * ci) - (fy * si);
    const rfe_real_t fby = (fx * si) + (fy * ci);
    t[0] = fbx / veh->m;
    t[1] = fby / veh->m;
    t[2] = ((px * fby) - (py * fbx)) / veh->J;
}

/* Wheel i's terms of z from its forces fx, fy (wheel axes) and c, s = cos, sin of delta
 * (ignored for the rear wheels). */
static void wheel_terms_of(const rfe_vehicle_t *veh, rfe_real_t c, rfe_real_t s, size_t i,
                           rfe_real_t fx, rfe_real_t fy, rfe_real_t t[RFE_MEAS])
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    rfe_wheel_positions(veh, px, py);
    wheel_terms(veh, c, s, i, px[i], py[i], fx, fy, t);
}

/* z = the sums of the four wheels' terms in wheel order from 0: RFE_ERR_NONFINITE when a
 * sum is not finite (z then untouched). In the load-scaled modes z is this sum of the terms,
 * so a caller may keep the terms of the wheels an input change does not touch and sum them
 * with the others in the same order: the same bits. */
static rfe_status_t sum_terms(const rfe_real_t t[COLS], rfe_real_t z[RFE_MEAS])
{
    rfe_real_t zt[RFE_MEAS];
    size_t r;
    /* zt[r] = 0 + t_0 + t_1 + t_2 + t_3 (wheel order; the leading 0 + keeps a -0 sum +0, as the
     * loop's did) written out for the four wheels (FOUR_WHEELS): a third of the loop's
     * instructions on a Cortex-M4F (issue 21) */
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        zt[r] = (((RFE_R(0.0) + t[r]) + t[(size_t)RFE_MEAS + r]) + t[(2u * (size_t)RFE_MEAS) + r]) +
                t[(3u * (size_t)RFE_MEAS) + r];
    }
    if (!rfe_all_finite(zt, RFE_MEAS)) {
        return RFE_ERR_NONFINITE;
    }
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        z[r] = zt[r];
    }
    return RFE_OK;
}

/* Absolute mode: z_r = sum_i H_r,i(F(mu_i)), the entries rfe_obsmat_build would put in
 * column i (body-axis force over m, yaw moment over J) summed in wheel order, which is
 * rfe_obsmat_apply(H, ones) bit for bit, without building and re-checking a matrix at every
 * cubature point. z is written only when finite. */
static rfe_status_t body_sums(const rfe_vehicle_t *veh, const rfe_meas_t *h,
                              const rfe_real_t fx[RFE_WHEELS], const rfe_real_t fy[RFE_WHEELS],
                              rfe_real_t z[RFE_MEAS])
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    rfe_real_t t[COLS];
    size_t i;

    rfe_wheel_positions(veh, px, py);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        /* cos, sin of h->delta, from the set-up */
        wheel_terms(veh, h->cos_delta, h->sin_delta, i, px[i], py[i], fx[i], fy[i],
                    &t[i * (size_t)RFE_MEAS]);
    }
    return sum_terms(t, z);
}

/* 1 when pre was computed with these tyre parameters (a NaN parameter never matches); the
 * mode too, since only magic mode fills the direction cosines. */
static int pre_matches(const rfe_meas_t *h, const rfe_tyre_params_t *tp)
{
    return ((h->mode == tp->mode) && (h->pre_cx == tp->cx) && (h->pre_cy == tp->cy) && (h->pre_eps == tp->eps) &&
            (h->pre_alpha_max == tp->alpha_max))
               ? 1
               : 0;
}

/* 1 when h keeps forces (memo_valid) computed with these Magic Formula shapes (a NaN never
 * matches); pre_matches covers the other tyre parameters the forces depend on. */
static int memo_matches(const rfe_meas_t *h, const rfe_tyre_params_t *tp)
{
    return ((h->memo_valid != 0) && (h->memo_shape[0] == tp->shape_Cx) &&
            (h->memo_shape[1] == tp->shape_Ex) && (h->memo_shape[2] == tp->shape_Cy) &&
            (h->memo_shape[3] == tp->shape_Ey))
               ? 1
               : 0;
}

/* rfe_tyre_forces_abs(tp, &h->kin, mu, fx, fy) with the set-up's friction-independent
 * terms (recomputed when tp is not the set-up's tyre): the same checks in the same order,
 * the same forces. */
static rfe_status_t forces_abs(const rfe_meas_t *h, const rfe_tyre_params_t *tp,
                               const rfe_real_t mu[RFE_WHEELS], rfe_real_t fx[RFE_WHEELS],
                               rfe_real_t fy[RFE_WHEELS])
{
    const int cached = pre_matches(h, tp);
    int memo = 0;
    rfe_real_t tx[RFE_WHEELS];
    rfe_real_t ty[RFE_WHEELS];
    size_t i;

    if ((cached != 0) && (memo_matches(h, tp) != 0)) {
        memo = 1;
    }

    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_dugoff_pre_t fresh;
        const rfe_dugoff_pre_t *pre = &h->pre[i];
        rfe_status_t st;
        if ((memo != 0) && (mu[i] == h->memo_mu[i])) {
            /* kept at this friction (after the same checks, passed): the same forces; -0 and
             * +0 compare equal and both are evaluated at max(mu, 0) = +0 */
            tx[i] = h->memo_fx[i];
            ty[i] = h->memo_fy[i];
            continue;
        }
        if (cached == 0) {
            rfe_tyre_dugoff_pre(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i],
                                &fresh);
            pre = &fresh;
        }
        st = rfe_tyre_dugoff_abs_pre(tp, pre, h->kin.kappa[i], h->kin.alpha[i],
                                     h->kin.fz[i], h->kin.vwx[i], mu[i], &tx[i],
                                     &ty[i]);
        if (st != RFE_OK) {
            return st;
        }
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        fx[i] = tx[i];
        fy[i] = ty[i];
    }
    return RFE_OK;
}

rfe_status_t rfe_meas_eval(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                           const rfe_tyre_params_t *tp, const rfe_real_t mu[RFE_WHEELS],
                           rfe_real_t z[RFE_MEAS])
{
    rfe_real_t fx[RFE_WHEELS];
    rfe_real_t fy[RFE_WHEELS];
    rfe_status_t st;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (mu == NULL) || (z == NULL)) {
        return RFE_ERR_NULL;
    }
    if (h->mode == RFE_TYRE_PAPER) {
        return apply_paper(h->H, mu, z); /* h = H(u) mu */
    }
    /* Load-scaled modes: forces at this mu (nonlinear in mu), then the same geometry as H's
     * columns: z_r = sum_i H_r,i(F(mu_i)) (MODEL.md §4-5). */
    st = forces_abs(h, tp, mu, fx, fy);
    if (st == RFE_OK) {
        st = body_sums(veh, h, fx, fy, z);
    }
    return st;
}

/* ---- the model at a perturbed input (the step noise, docs/ESTIMATOR.md step 4) ---------------
 * Load-scaled modes: only the wheels an input reaches are evaluated again (meas_inputs.h);
 * the others keep their nominal terms (which passed the model's checks): the same values
 * summed in the same order, and the same statuses (the set-up's check of the perturbed input,
 * then the forces' checks of the wheels evaluated, in wheel order, then the sums'). */

/* generated by scripts/codegen/twins.py from meas_input_slot: do not edit; make twins */
/* Input j (RFE_IN_*) of the sample. */
static rfe_real_t *input_slot(rfe_sample_t *u, size_t j)
{
    rfe_real_t *slot;
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

/* The nominal terms of the four wheels from the set-up model h: rfe_meas_eval's forces (with
 * its checks, in its order) and terms. */
static rfe_status_t nominal_terms(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                  const rfe_tyre_params_t *tp, const rfe_real_t *mu,
                                  rfe_real_t t[COLS])
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_real_t fx = RFE_R(0.0);
        rfe_real_t fy = RFE_R(0.0);
        const rfe_status_t st = rfe_tyre_dugoff_abs_pre(
            tp, &h->pre[i], h->kin.kappa[i], h->kin.alpha[i], h->kin.fz[i],
            h->kin.vwx[i], mu[i], &fx, &fy);
        if (st != RFE_OK) {
            return st;
        }
        wheel_terms_of(veh, h->cos_delta, h->sin_delta, i, fx, fy, &t[i * (size_t)RFE_MEAS]);
    }
    return RFE_OK;
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_meas_nominal(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                              const rfe_tyre_params_t *tp, const rfe_real_t mu[RFE_WHEELS],
                              rfe_meas_terms_t *nom, rfe_real_t z[RFE_MEAS])
{
    rfe_real_t t[COLS];
    rfe_status_t st;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (mu == NULL) || (nom == NULL) ||
        (z == NULL)) {
        return RFE_ERR_NULL;
    }
    if (h->mode == RFE_TYRE_PAPER) {
        return rfe_meas_eval(h, veh, tp, mu, z); /* a non-finite mu: RFE_ERR_NONFINITE */
    }
    st = nominal_terms(h, veh, tp, mu, t);
    if (st == RFE_OK) {
        st = sum_terms(t, z);
    }
    if (st == RFE_OK) {
        size_t k;
        for (k = 0u; k < COLS; ++k) {
            nom->t[k] = t[k];
        }
    }
    return st;
}

/* Terms of wheel i (reached by input j) for the perturbed sample up; c, s: cos, sin of
 * up->delta. A wheel speed changes kappa only (vwx, alpha and tan alpha are the nominal). */
static rfe_status_t perturbed_terms(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                    const rfe_tyre_params_t *tp, const rfe_sample_t *up,
                                    size_t j, size_t i, rfe_real_t c, rfe_real_t s,
                                    rfe_real_t mu, rfe_real_t t[RFE_MEAS])
{
    rfe_dugoff_pre_t pre;
    rfe_real_t vwx = h->kin.vwx[i];
    rfe_real_t alpha = h->kin.alpha[i];
    rfe_real_t kappa;
    rfe_real_t fx = RFE_R(0.0);
    rfe_real_t fy = RFE_R(0.0);
    rfe_status_t st;
    if (j >= (size_t)RFE_IN_OMEGA) {
        kappa = rfe_tyre_wheel_kappa(veh, tp, up->omega[i], vwx);
        rfe_tyre_dugoff_pre_tan(tp, kappa, h->pre[i].tan_a, vwx, &pre);
    } else {
        rfe_tyre_wheel_kin(veh, tp, up, c, s, i, &vwx, &alpha, &kappa);
        rfe_tyre_dugoff_pre(tp, kappa, alpha, vwx, &pre);
    }
    st = rfe_tyre_dugoff_abs_pre(tp, &pre, kappa, alpha, h->kin.fz[i], vwx, mu, &fx, &fy);
    if (st == RFE_OK) {
        wheel_terms_of(veh, c, s, i, fx, fy, t);
    }
    return st;
}

/* z = h(mu, up) for up = u with input j perturbed (its value already checked finite), from
 * the nominal terms of the wheels j does not reach. */
static rfe_status_t perturbed_sum(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                  const rfe_tyre_params_t *tp, const rfe_sample_t *up,
                                  size_t j, const rfe_real_t *mu, const rfe_real_t nom[COLS],
                                  rfe_real_t z[RFE_MEAS])
{
    rfe_real_t t[COLS];
    rfe_real_t c = h->cos_delta;
    rfe_real_t s = h->sin_delta;
    size_t i;
    size_t r;
    if (j == (size_t)RFE_IN_DELTA) {
        c = RFE_COS(up->delta);
        s = RFE_SIN(up->delta);
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_real_t *ti = &t[i * (size_t)RFE_MEAS];
        if (rfe_input_reaches(j, i) != 0) {
            const rfe_status_t st = perturbed_terms(h, veh, tp, up, j, i, c, s, mu[i], ti);
            if (st != RFE_OK) {
                return st;
            }
        } else {
            for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
                ti[r] = nom[(i * (size_t)RFE_MEAS) + r];
            }
        }
    }
    return sum_terms(t, z);
}

rfe_status_t rfe_meas_eval_perturbed(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                     const rfe_tyre_params_t *tp, const rfe_meas_terms_t *nom,
                                     const rfe_sample_t *u, size_t j, rfe_real_t d,
                                     const rfe_real_t mu[RFE_WHEELS], rfe_real_t z[RFE_MEAS])
{
    rfe_sample_t up;
    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (nom == NULL) || (u == NULL) ||
        (mu == NULL) || (z == NULL)) {
        return RFE_ERR_NULL;
    }
    if (j >= (size_t)RFE_INPUTS) {
        return RFE_ERR_PARAM;
    }
    up = *u;
    *input_slot(&up, j) += d;
    if (h->mode == RFE_TYRE_PAPER) {
        /* the model of the perturbed sample, set up and evaluated in full */
        rfe_meas_t hp;
        rfe_status_t st = rfe_meas_setup(&hp, veh, tp, &up);
        if (st == RFE_OK) {
            st = rfe_meas_eval(&hp, veh, tp, mu, z);
        }
        return st;
    }
    /* the set-up's check of the one changed input (u's others passed it) */
    if (!rfe_is_finite(*input_slot(&up, j))) {
        return RFE_ERR_NONFINITE;
    }
    return perturbed_sum(h, veh, tp, &up, j, mu, nom->t, z);
}

/* ---- the lateral rows and their derivatives (docs/OBSERVER.md §4.2) -------------------------- */

/* Wheel i's input change per unit of vy (ci, si: cos, sin of its steer angle): d v_wx = si,
 * d v_wy = ci, so, with t = tan(alpha) = -v_wy / |v_wx| where alpha is inside its bound,
 *   d tan(alpha) = -(ci + t sgn(v_wx) si) / |v_wx|   (0 where |alpha| >= alpha_max or v_wx = 0),
 *   d kappa = -(1 + [den = |v_wx|] kappa sgn(v_wx)) si / den   (0 where |kappa| >= 1),
 * with den = max(|omega R|, |v_wx|, v_min) following |v_wx| when it exceeds both others. */
static rfe_slip_dir_t vy_direction(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                   const rfe_tyre_params_t *tp, const rfe_sample_t *u,
                                   size_t i, rfe_real_t ci, rfe_real_t si, rfe_real_t tan_a)
{
    const rfe_real_t vwx = h->kin.vwx[i];
    const rfe_real_t avx = RFE_FABS(vwx);
    const rfe_real_t kappa = h->kin.kappa[i];
    rfe_slip_dir_t d;
    d.vwx = si;
    d.tan_a = RFE_R(0.0);
    d.k = RFE_R(0.0);
    if ((RFE_FABS(h->kin.alpha[i]) < tp->alpha_max) && (avx > RFE_R(0.0))) {
        d.tan_a = -(ci + ((tan_a * rfe_sgn(vwx)) * si)) / avx;
    }
    if (RFE_FABS(kappa) < RFE_R(1.0)) {
        const rfe_real_t avr = RFE_FABS(u->omega[i] * veh->R);
        const rfe_real_t den = rfe_max(rfe_max(avr, avx), tp->v_min);
        const rfe_real_t own = ((avx > avr) && (avx > tp->v_min)) ? (kappa * rfe_sgn(vwx))
                                                                   : RFE_R(0.0);
        d.k = (-(RFE_R(1.0) + own) * si) / den;
    }
    return d;
}

/* Wheel i's friction-independent tyre terms for the derivative: the set-up's (load-scaled
 * modes with its tyre), recomputed for other tyre parameters, or paper mode's with the
 * normalised stiffnesses (the set-up keeps none there). */
static void jac_pre(const rfe_meas_t *h, const rfe_tyre_params_t *tp, int cached, size_t i,
                    rfe_dugoff_pre_t *pre)
{
    if (h->mode == RFE_TYRE_PAPER) {
        rfe_tyre_norm_pre(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i], pre);
    } else if (cached != 0) {
        *pre = h->pre[i];
    } else {
        rfe_tyre_dugoff_pre(tp, h->kin.kappa[i], h->kin.alpha[i], h->kin.vwx[i], pre);
    }
}

/* The three sets of wheel terms (at mu, by vy, by mu along dmu) of the four wheels. */
static rfe_status_t lateral_terms(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                  const rfe_tyre_params_t *tp, const rfe_sample_t *u,
                                  const rfe_real_t *mu, const rfe_real_t *dmu, rfe_real_t t[COLS],
                                  rfe_real_t tv[COLS], rfe_real_t tm[COLS])
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    rfe_real_t c = h->cos_delta;
    rfe_real_t s = h->sin_delta;
    const int cached = pre_matches(h, tp);
    size_t i;
    if (h->mode == RFE_TYRE_PAPER) {
        c = RFE_COS(h->delta);
        s = RFE_SIN(h->delta);
    }
    rfe_wheel_positions(veh, px, py);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        /* front wheels steer: the vy direction in wheel axes */
        const rfe_real_t ci = (i < (size_t)RFE_RL) ? c : RFE_R(1.0);
        const rfe_real_t si = (i < (size_t)RFE_RL) ? s : RFE_R(0.0);
        const size_t o = i * (size_t)RFE_MEAS;
        rfe_dugoff_pre_t pre;
        rfe_slip_dir_t d;
        rfe_tyre_jac_t f;
        rfe_status_t st;
        jac_pre(h, tp, cached, i, &pre);
        d = vy_direction(h, veh, tp, u, i, ci, si, pre.tan_a);
        st = rfe_tyre_pre_jac(tp, &pre, h->kin.kappa[i], h->kin.alpha[i], h->kin.fz[i],
                              h->kin.vwx[i], mu[i], &d, &f);
        if (st != RFE_OK) {
            return st;
        }
        /* the body terms are linear in the forces: the same map for each derivative */
        wheel_terms(veh, c, s, i, px[i], py[i], f.fx, f.fy, &t[o]);
        wheel_terms(veh, c, s, i, px[i], py[i], f.dfx, f.dfy, &tv[o]);
        wheel_terms(veh, c, s, i, px[i], py[i], f.mfx * dmu[i], f.mfy * dmu[i], &tm[o]);
    }
    return RFE_OK;
}

rfe_status_t rfe_meas_lateral_jac(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                  const rfe_tyre_params_t *tp, const rfe_sample_t *u,
                                  const rfe_real_t mu[RFE_WHEELS],
                                  const rfe_real_t dmu[RFE_WHEELS], rfe_meas_lateral_t *out)
{
    rfe_real_t t[COLS];
    rfe_real_t tv[COLS];
    rfe_real_t tm[COLS];
    rfe_real_t z[RFE_MEAS];
    rfe_real_t zv[RFE_MEAS];
    rfe_real_t zm[RFE_MEAS];
    rfe_status_t st;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL) || (mu == NULL) ||
        (dmu == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    st = lateral_terms(h, veh, tp, u, mu, dmu, t, tv, tm);
    if (st == RFE_OK) {
        st = sum_terms(t, z);
    }
    if ((st == RFE_OK) && (h->mode == RFE_TYRE_PAPER)) {
        st = apply_paper(h->H, mu, z); /* rfe_meas_eval's z = H(u) mu, bit for bit */
    }
    if (st == RFE_OK) {
        st = sum_terms(tv, zv);
    }
    if (st == RFE_OK) {
        st = sum_terms(tm, zm);
    }
    if (st == RFE_OK) {
        size_t r;
        for (r = 0u; r < 2u; ++r) {
            out->z[r] = z[r + 1u];
            out->d_vy[r] = zv[r + 1u];
            out->d_mu[r] = zm[r + 1u];
        }
    }
    return st;
}

/* ---- the derivatives of h by the inputs (for the step noise, docs/ESTIMATOR.md step 4) ------ */

/* Wheel i's slip direction for a change dvwx, dvwy of its velocity in wheel axes and dvr of
 * its rolling speed omega R, with t = tan(alpha) = -v_wy / |v_wx| (alpha inside its bound):
 *   d tan(alpha) = -(dvwy + t sgn(v_wx) dvwx) / |v_wx|   (0 where |alpha| >= alpha_max or v_wx = 0),
 *   d kappa = (dvr (1 - [den = |omega R|] kappa sgn(omega R))
 *              - dvwx (1 + [den = |v_wx|] kappa sgn(v_wx))) / den   (0 where |kappa| >= 1),
 * den = max(|omega R|, |v_wx|, v_min): the quotient rule where den follows one of the two speeds
 * (vy_direction is the case dvwx = si, dvwy = ci, dvr = 0). The factors that do not depend on
 * the change, once per wheel (input_dir_t, input_dir_of), then each input's direction
 * (input_direction): the same operations as one evaluation. */
typedef struct {
    rfe_real_t ts;  /* t sgn(v_wx) */
    rfe_real_t avx; /* |v_wx| */
    rfe_real_t ar;  /* 1 - [den = |omega R|] kappa sgn(omega R) */
    rfe_real_t ax;  /* 1 + [den = |v_wx|] kappa sgn(v_wx) */
    rfe_real_t den;
    int t_on; /* |alpha| < alpha_max and v_wx != 0 */
    int k_on; /* |kappa| < 1 */
} input_dir_t;

static void input_dir_of(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                         const rfe_tyre_params_t *tp, const rfe_sample_t *u, size_t i,
                         rfe_real_t tan_a, input_dir_t *c)
{
    const rfe_real_t vwx = h->kin.vwx[i];
    const rfe_real_t avx = RFE_FABS(vwx);
    const rfe_real_t kappa = h->kin.kappa[i];
    c->avx = avx;
    c->ts = tan_a * rfe_sgn(vwx);
    c->t_on = 0;
    c->k_on = 0;
    if ((RFE_FABS(h->kin.alpha[i]) < tp->alpha_max) && (avx > RFE_R(0.0))) {
        c->t_on = 1;
    }
    if (RFE_FABS(kappa) < RFE_R(1.0)) {
        c->k_on = 1;
    }
    c->ar = RFE_R(1.0);
    c->ax = RFE_R(1.0);
    c->den = RFE_R(1.0);
    if (c->k_on != 0) {
        const rfe_real_t vr = u->omega[i] * veh->R;
        const rfe_real_t avr = RFE_FABS(vr);
        const rfe_real_t own_x =
            ((avx > avr) && (avx > tp->v_min)) ? (kappa * rfe_sgn(vwx)) : RFE_R(0.0);
        const rfe_real_t own_r =
            ((avr >= avx) && (avr > tp->v_min)) ? (kappa * rfe_sgn(vr)) : RFE_R(0.0);
        c->den = rfe_max(rfe_max(avr, avx), tp->v_min);
        c->ar = RFE_R(1.0) - own_r;
        c->ax = RFE_R(1.0) + own_x;
    }
}

static rfe_slip_dir_t input_direction(const input_dir_t *c, const rfe_real_t dv[3])
{
    rfe_slip_dir_t d;
    d.vwx = dv[0];
    d.tan_a = RFE_R(0.0);
    d.k = RFE_R(0.0);
    if (c->t_on != 0) {
        d.tan_a = -(dv[1] + (c->ts * dv[0])) / c->avx;
    }
    if (c->k_on != 0) {
        d.k = ((dv[2] * c->ar) - (dv[0] * c->ax)) / c->den;
    }
    return d;
}

/* Wheel i's velocity change (dv: d v_wx, d v_wy in wheel axes, d(omega R)) per unit of input j
 * (RFE_IN_*, one that reaches the wheel); ci, si: cos, sin of its steer angle; vwx, vwy its
 * velocity in wheel axes. Returns 1 for delta, whose change also turns the wheel's forces into
 * the body axes (d(ci, si)/d delta = (-si, ci)). Body velocity v_i = (vx - r y_i, vy + r x_i). */
static int input_change(const rfe_vehicle_t *veh, size_t j, rfe_real_t px, rfe_real_t py,
                        rfe_real_t ci, rfe_real_t si, rfe_real_t vwx, rfe_real_t vwy,
                        rfe_real_t dv[3])
{
    int turns = 0;
    dv[0] = RFE_R(0.0);
    dv[1] = RFE_R(0.0);
    dv[2] = RFE_R(0.0);
    if (j == (size_t)RFE_IN_DELTA) {
        /* the wheel axes turn by d delta: d v_w = (v_wy, -v_wx) */
        dv[0] = vwy;
        dv[1] = -vwx;
        turns = 1;
    } else if (j >= (size_t)RFE_IN_OMEGA) {
        dv[2] = veh->R;
    } else if (j == (size_t)RFE_IN_YAW_RATE) {
        /* the body velocity's change (-y_i, x_i), rotated into wheel axes */
        dv[0] = (-py * ci) + (px * si);
        dv[1] = (py * si) + (px * ci);
    } else {
        /* vx: the body velocity's change (1, 0); vy: (0, 1) */
        const rfe_real_t dbx = (j == (size_t)RFE_IN_VX) ? RFE_R(1.0) : RFE_R(0.0);
        const rfe_real_t dby = (j == (size_t)RFE_IN_VY) ? RFE_R(1.0) : RFE_R(0.0);
        dv[0] = (dbx * ci) + (dby * si);
        dv[1] = (-dbx * si) + (dby * ci);
    }
    return turns;
}

/* Wheel i's forces' derivatives along unit changes of kappa (fj[0]), tan(alpha) (fj[1]) and
 * v_wx (fj[2]): the forces are differentiable in the three, so any direction is their linear
 * combination. The Magic Formula curve does not depend on v_wx (magic_jac reads no d->vwx):
 * its fj[2] is zero without evaluating it. */
static rfe_status_t wheel_basis(const rfe_meas_t *h, const rfe_tyre_params_t *tp,
                                const rfe_dugoff_pre_t *pre, size_t i, rfe_real_t mu,
                                rfe_tyre_jac_t fj[3])
{
    size_t b;
    fj[2].dfx = RFE_R(0.0);
    fj[2].dfy = RFE_R(0.0);
    if (tp->mode == RFE_TYRE_MAGIC) {
        /* both directions from one evaluation of the curves (rfe_tyre_magic_basis) */
        return rfe_tyre_magic_basis(tp, pre, h->kin.kappa[i], h->kin.alpha[i], h->kin.fz[i],
                                    h->kin.vwx[i], mu, fj);
    }
    for (b = 0u; b < 3u; ++b) {
        rfe_slip_dir_t e;
        rfe_status_t st;
        e.k = (b == 0u) ? RFE_R(1.0) : RFE_R(0.0);
        e.tan_a = (b == 1u) ? RFE_R(1.0) : RFE_R(0.0);
        e.vwx = (b == 2u) ? RFE_R(1.0) : RFE_R(0.0);
        st = rfe_tyre_pre_jac(tp, pre, h->kin.kappa[i], h->kin.alpha[i], h->kin.fz[i],
                              h->kin.vwx[i], mu, &e, &fj[b]);
        if (st != RFE_OK) {
            return st;
        }
    }
    return RFE_OK;
}

/* Wheel i's terms of dh/du_j for every input j added to acc[j RFE_MEAS + r] (zeros for the
 * inputs that do not reach it: +0 added, as sum_terms adds every wheel's terms); acc0 not
 * NULL: its terms of h at mu (the forces of the derivative's evaluation) added to acc0 and
 * the forces into f0. Called for the wheels in order from acc = acc0 = 0, the sums are
 * sum_terms' (((0 + t_0) + t_1) + t_2) + t_3, bit for bit, without the 96 terms side by side
 * (issue 21: 288 B less stack). */
static rfe_status_t wheel_input_terms(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                      const rfe_tyre_params_t *tp, const rfe_sample_t *u,
                                      int cached, size_t i, rfe_real_t c, rfe_real_t s,
                                      rfe_real_t mu, rfe_real_t *acc, rfe_real_t *acc0,
                                      rfe_real_t f0[2])
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    const rfe_real_t ci = (i < (size_t)RFE_RL) ? c : RFE_R(1.0);
    const rfe_real_t si = (i < (size_t)RFE_RL) ? s : RFE_R(0.0);
    rfe_dugoff_pre_t pre;
    rfe_tyre_jac_t fj[3];
    input_dir_t dc;
    rfe_real_t tw[RFE_MEAS];
    rfe_real_t vbx;
    rfe_real_t vby;
    size_t j;
    rfe_status_t st;
    rfe_wheel_positions(veh, px, py);
    jac_pre(h, tp, cached, i, &pre);
    st = wheel_basis(h, tp, &pre, i, mu, fj);
    if (st != RFE_OK) {
        return st;
    }
    if (acc0 != NULL) {
        size_t r;
        wheel_terms(veh, c, s, i, px[i], py[i], fj[0].fx, fj[0].fy, tw);
        for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
            acc0[r] += tw[r];
        }
        f0[0] = fj[0].fx;
        f0[1] = fj[0].fy;
    }
    input_dir_of(h, veh, tp, u, i, pre.tan_a, &dc);
    vbx = u->vx - (u->yaw_rate * py[i]);
    vby = u->vy + (u->yaw_rate * px[i]);
    for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
        rfe_real_t *aj = &acc[j * (size_t)RFE_MEAS];
        tw[0] = RFE_R(0.0);
        tw[1] = RFE_R(0.0);
        tw[2] = RFE_R(0.0);
        if (rfe_input_reaches(j, i) != 0) {
            rfe_real_t dv[3];
            rfe_slip_dir_t d;
            rfe_real_t dfx;
            rfe_real_t dfy;
            const int turns = input_change(veh, j, px[i], py[i], ci, si, (vbx * ci) + (vby * si),
                                           (-vbx * si) + (vby * ci), dv);
            d = input_direction(&dc, dv);
            dfx = ((d.k * fj[0].dfx) + (d.tan_a * fj[1].dfx)) + (d.vwx * fj[2].dfx);
            dfy = ((d.k * fj[0].dfy) + (d.tan_a * fj[1].dfy)) + (d.vwx * fj[2].dfy);
            if (turns != 0) {
                /* the body terms rotate the forces by delta: d(R(delta) F) = R(delta) (dF + (-Fy, Fx)) */
                dfx -= fj[0].fy;
                dfy += fj[0].fx;
            }
            /* the body terms are linear in the forces: the same map for the derivative */
            wheel_terms(veh, c, s, i, px[i], py[i], dfx, dfy, tw);
        }
        aj[0] += tw[0];
        aj[1] += tw[1];
        aj[2] += tw[2];
    }
    return RFE_OK;
}

/* G[r RFE_INPUTS + j] = sd_j times input j's sum over the wheels (acc[j RFE_MEAS + r]);
 * RFE_ERR_NONFINITE when a scaled sum is not finite (a huge sd times a finite derivative, or
 * a sum that is not finite itself: an infinite or NaN sum times any sd is not finite, so this
 * one check returns what sum_terms' check of each sum then this one returned), G then
 * untouched. */
static rfe_status_t scaled_columns(const rfe_real_t *acc, const rfe_real_t sd[RFE_INPUTS],
                                   rfe_real_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS])
{
    rfe_real_t g[(size_t)RFE_INPUTS * (size_t)RFE_MEAS];
    size_t r;
    size_t j;
    for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
        for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
            g[(r * (size_t)RFE_INPUTS) + j] = acc[(j * (size_t)RFE_MEAS) + r] * sd[j];
        }
    }
    if (!rfe_all_finite(g, (size_t)RFE_INPUTS * (size_t)RFE_MEAS)) {
        return RFE_ERR_NONFINITE;
    }
    for (j = 0u; j < ((size_t)RFE_INPUTS * (size_t)RFE_MEAS); ++j) {
        G[j] = g[j];
    }
    return RFE_OK;
}

/* rfe_meas_input_jac after its NULL checks; z not NULL (the load-scaled modes with the
 * set-up's tyre only): also z = h(mu, u) from the same forces (rfe_meas_nominal's sum, its
 * check first) and, f not NULL, each wheel's forces into f (fx, fy per wheel). */
static rfe_status_t input_jac_core(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                   const rfe_tyre_params_t *tp, const rfe_sample_t *u,
                                   const rfe_real_t mu[RFE_WHEELS],
                                   const rfe_real_t sd[RFE_INPUTS],
                                   rfe_real_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS],
                                   rfe_real_t *z, rfe_real_t *f)
{
    rfe_real_t acc[(size_t)RFE_INPUTS * (size_t)RFE_MEAS];
    rfe_real_t acc0[RFE_MEAS] = {RFE_R(0.0), RFE_R(0.0), RFE_R(0.0)};
    rfe_real_t c = h->cos_delta;
    rfe_real_t s = h->sin_delta;
    const int cached = pre_matches(h, tp);
    rfe_status_t st = RFE_OK;
    size_t i;
    if (h->mode == RFE_TYRE_PAPER) {
        c = RFE_COS(h->delta);
        s = RFE_SIN(h->delta);
    }
    for (i = 0u; i < ((size_t)RFE_INPUTS * (size_t)RFE_MEAS); ++i) {
        acc[i] = RFE_R(0.0);
    }
    for (i = 0u; (i < (size_t)RFE_WHEELS) && (st == RFE_OK); ++i) {
        st = wheel_input_terms(h, veh, tp, u, cached, i, c, s, mu[i], acc,
                               (z != NULL) ? acc0 : NULL, (f != NULL) ? &f[2u * i] : NULL);
    }
    if ((st == RFE_OK) && (z != NULL)) {
        if (!rfe_all_finite(acc0, RFE_MEAS)) {
            st = RFE_ERR_NONFINITE; /* rfe_meas_nominal's check of its sum */
        } else {
            z[0] = acc0[0];
            z[1] = acc0[1];
            z[2] = acc0[2];
        }
    }
    if (st == RFE_OK) {
        st = scaled_columns(acc, sd, G);
    }
    return st;
}

rfe_status_t rfe_meas_input_jac(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                const rfe_tyre_params_t *tp, const rfe_sample_t *u,
                                const rfe_real_t mu[RFE_WHEELS],
                                const rfe_real_t sd[RFE_INPUTS],
                                rfe_real_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS])
{
    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL) || (mu == NULL) ||
        (sd == NULL) || (G == NULL)) {
        return RFE_ERR_NULL;
    }
    return input_jac_core(h, veh, tp, u, mu, sd, G, NULL, NULL);
}

/* Keeps the four wheels' forces f (fx, fy per wheel) at mu in h for rfe_meas_eval, with the
 * shapes of tp they were computed with. */
static void keep_forces(rfe_meas_t *h, const rfe_tyre_params_t *tp,
                        const rfe_real_t mu[RFE_WHEELS], const rfe_real_t f[2u * (size_t)RFE_WHEELS])
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        h->memo_mu[i] = mu[i];
        h->memo_fx[i] = f[2u * i];
        h->memo_fy[i] = f[(2u * i) + 1u];
    }
    h->memo_shape[0] = tp->shape_Cx;
    h->memo_shape[1] = tp->shape_Ex;
    h->memo_shape[2] = tp->shape_Cy;
    h->memo_shape[3] = tp->shape_Ey;
    h->memo_valid = 1;
}

rfe_status_t rfe_meas_nominal_input_jac(rfe_meas_t *h, const rfe_vehicle_t *veh,
                                        const rfe_tyre_params_t *tp, const rfe_sample_t *u,
                                        const rfe_real_t mu[RFE_WHEELS],
                                        const rfe_real_t sd[RFE_INPUTS], rfe_real_t z[RFE_MEAS],
                                        rfe_real_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS])
{
    rfe_real_t z0[RFE_MEAS];
    rfe_real_t f0[2u * (size_t)RFE_WHEELS];
    rfe_real_t *zp = NULL;
    rfe_status_t st = RFE_OK;
    size_t i;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL) || (mu == NULL) ||
        (sd == NULL) || (z == NULL) || (G == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((h->mode == RFE_TYRE_PAPER) || (pre_matches(h, tp) == 0)) {
        /* the two calls (paper mode's z is H(u) mu, not the derivative's forces) */
        rfe_meas_terms_t nom;
        st = rfe_meas_nominal(h, veh, tp, mu, &nom, z0);
    } else {
        /* z from the derivative's forces: rfe_meas_nominal's checks are each wheel's tyre
         * checks, which the derivative makes in the same order, then the sum's */
        zp = z0;
    }
    if (st == RFE_OK) {
        st = input_jac_core(h, veh, tp, u, mu, sd, G, zp, f0);
    }
    if (st != RFE_OK) {
        return st;
    }
    if (zp != NULL) {
        keep_forces(h, tp, mu, f0);
    }
    for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
        z[i] = z0[i];
    }
    return RFE_OK;
}
