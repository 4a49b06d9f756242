/**
 * @file eiv_flt.c
 * @brief Step-noise S_R: sensor noise, relative tyre-model error, input noise propagated by
 *        central differences (docs/ESTIMATOR.md step 4).
 */
#include "rfe/component/eiv.h"

#include "rfe/component/meas.h"
#include "rfe/component/qr.h"

#include "estimators/friction/eiv_internal.h"
#include "numerics/internal.h"
#include "models/meas_internal.h"
#include "models/tyre_internal.h"

#define CW ((size_t)RFE_MEAS + (size_t)RFE_EIV_INPUTS) /* widest [S_R0, g_1 .. g_8] */

/* The Tria of [S_R0, g_1 .. g_8] is 3 x 11: it must fit the smallest build's maxima. */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_eiv_tria_fits[((RFE_MEAS + RFE_EIV_INPUTS) <= RFE_TRIA_COLS_MAX) &&
                                              (RFE_MEAS <= RFE_N_MAX)
                                          ? 1
                                          : -1];

/* Input j of the sample (0 delta, 1 vx, 2 vy, 3 r, 4.. omega_fl..rr) and its noise sd. */
static rfe_real_t *input_slot(rfe_sample_t *u, size_t j)
{
    rfe_real_t *slot;
    switch (j) {
    case 0u:
        slot = &u->delta;
        break;
    case 1u:
        slot = &u->vx;
        break;
    case 2u:
        slot = &u->vy;
        break;
    case 3u:
        slot = &u->yaw_rate;
        break;
    default:
        slot = &u->omega[j - 4u];
        break;
    }
    return slot;
}

static rfe_real_t input_sd(const rfe_filter_params_t *fp, size_t j)
{
    const rfe_real_t sd[RFE_EIV_INPUTS] = {fp->sd_in_delta,    fp->sd_in_vx,    fp->sd_in_vy,
                                           fp->sd_in_yaw_rate, fp->sd_in_omega, fp->sd_in_omega,
                                           fp->sd_in_omega,    fp->sd_in_omega};
    return sd[j];
}

/* z = h(mu, u) for sample u (its own kinematics). */
static rfe_status_t h_at(const rfe_params_t *p, const rfe_sample_t *u, const rfe_real_t *mu,
                         rfe_real_t z[RFE_MEAS])
{
    rfe_meas_t h;
    rfe_status_t st = rfe_meas_setup(&h, &p->vehicle, &p->tyre, u);
    if (st == RFE_OK) {
        st = rfe_meas_eval(&h, &p->vehicle, &p->tyre, mu, z);
    }
    return st;
}

/* S_R0 into the first RFE_MEAS columns of A (row stride CW): sensor noise and the model
 * error relative to each predicted acceleration h0. */
static void sensor_block(const rfe_filter_params_t *fp, const rfe_real_t h0[RFE_MEAS],
                         rfe_real_t *A)
{
    rfe_real_t r[RFE_MEAS];
    size_t i;
    size_t j;
    r[0] = fp->r_ax;
    r[1] = fp->r_ay;
    r[2] = fp->r_yaw_acc;
    for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
        const rfe_real_t e = fp->r_model_rel * RFE_FABS(h0[i]);
        for (j = 0u; j < (size_t)RFE_MEAS; ++j) {
            A[(i * CW) + j] = (i == j) ? RFE_SQRT((r[i] * r[i]) + (e * e)) : RFE_R(0.0);
        }
    }
}

/* g_j = (h(u + sd_j e_j) - h(u - sd_j e_j)) / 2 for each noisy input, in order, as columns
 * *cols, *cols + 1, ... of A (row stride CW); *cols ends one past the last. */
static rfe_status_t input_columns(const rfe_params_t *p, const rfe_sample_t *u,
                                  const rfe_real_t *mu, rfe_real_t *A, size_t *cols)
{
    size_t i;
    size_t j;
    for (j = 0u; j < (size_t)RFE_EIV_INPUTS; ++j) {
        const rfe_real_t sd = input_sd(&p->filter, j);
        rfe_sample_t up = *u;
        rfe_sample_t um = *u;
        rfe_real_t zp[RFE_MEAS];
        rfe_real_t zm[RFE_MEAS];
        rfe_status_t st;
        if (!(sd > RFE_R(0.0))) {
            continue;
        }
        *input_slot(&up, j) += sd;
        *input_slot(&um, j) -= sd;
        st = h_at(p, &up, mu, zp);
        if (st == RFE_OK) {
            st = h_at(p, &um, mu, zm);
        }
        if (st != RFE_OK) {
            return st;
        }
        for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
            A[(i * CW) + *cols] = (zp[i] - zm[i]) / RFE_R(2.0);
        }
        ++(*cols);
    }
    return RFE_OK;
}

/* ---- load-scaled tyre modes (absolute, magic): only the wheels an input reaches are evaluated again -------------
 * h(mu, u) is the sum, in wheel order, of four per-wheel terms (meas_internal.h), each a
 * function of that wheel's kinematics, its load and cos/sin of delta. The loads depend on ax,
 * ay only (never perturbed); delta reaches the front wheels' kinematics and terms, vx, vy and
 * r every wheel, omega_i only wheel i's kappa. A perturbed h therefore takes the nominal
 * terms of every other wheel (which passed the model's checks): the same values summed in
 * the same order, and the same statuses (the set-up's check of the perturbed input, then the
 * forces' checks of the wheels evaluated, in wheel order, then the sums'). */

/* The nominal terms of the four wheels from the set-up model h: rfe_meas_eval's forces (with
 * its checks, in its order) and terms. */
static rfe_status_t nominal_terms(const rfe_params_t *p, const rfe_meas_t *h,
                                  const rfe_real_t *mu, rfe_real_t t[RFE_MEAS_COLS])
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_real_t fx = RFE_R(0.0);
        rfe_real_t fy = RFE_R(0.0);
        const rfe_status_t st = rfe_tyre_dugoff_abs_pre(
            &p->tyre, &h->pre[i], h->kin.kappa[i], h->kin.alpha[i], h->kin.fz[i],
            h->kin.vwx[i], mu[i], &fx, &fy);
        if (st != RFE_OK) {
            return st;
        }
        rfe_meas_wheel_terms(&p->vehicle, h->cos_delta, h->sin_delta, i, fx, fy,
                             &t[i * (size_t)RFE_MEAS]);
    }
    return RFE_OK;
}

/* 1 when input j (0 delta, 1 vx, 2 vy, 3 r, 4.. omega_fl..rr) reaches wheel i: delta the
 * front wheels, vx, vy and r every wheel, omega_i wheel i (bit i of the input's mask; wheels
 * in the order fl, fr, rl, rr). */
static int reaches(size_t j, size_t i)
{
    static const uint8_t wheel_mask[RFE_EIV_INPUTS] = {0x3u, 0xFu, 0xFu, 0xFu, 0x1u, 0x2u, 0x4u, 0x8u};
    return ((((uint32_t)wheel_mask[j] >> i) & 1u) != 0u) ? 1 : 0;
}

/* Terms of wheel i (reached by input j) for the perturbed sample up; c, s: cos, sin of
 * up->delta. A wheel speed changes kappa only (vwx, alpha and tan alpha are the nominal). */
static rfe_status_t perturbed_terms(const rfe_params_t *p, const rfe_meas_t *h,
                                    const rfe_sample_t *up, size_t j, size_t i, rfe_real_t c,
                                    rfe_real_t s, rfe_real_t mu, rfe_real_t t[RFE_MEAS])
{
    rfe_dugoff_pre_t pre;
    rfe_real_t vwx = h->kin.vwx[i];
    rfe_real_t alpha = h->kin.alpha[i];
    rfe_real_t kappa;
    rfe_real_t fx = RFE_R(0.0);
    rfe_real_t fy = RFE_R(0.0);
    rfe_status_t st;
    if (j >= 4u) {
        kappa = rfe_tyre_wheel_kappa(&p->vehicle, &p->tyre, up->omega[i], vwx);
        rfe_tyre_dugoff_pre_tan(&p->tyre, kappa, h->pre[i].tan_a, vwx, &pre);
    } else {
        rfe_tyre_wheel_kin(&p->vehicle, &p->tyre, up, c, s, i, &vwx, &alpha, &kappa);
        rfe_tyre_dugoff_pre(&p->tyre, kappa, alpha, vwx, &pre);
    }
    st = rfe_tyre_dugoff_abs_pre(&p->tyre, &pre, kappa, alpha, h->kin.fz[i], vwx, mu,
                                 &fx, &fy);
    if (st == RFE_OK) {
        rfe_meas_wheel_terms(&p->vehicle, c, s, i, fx, fy, t);
    }
    return st;
}

/* z = h(mu, up) for up = u with input j perturbed (its value already checked finite), from
 * the nominal terms of the wheels j does not reach. */
static rfe_status_t h_perturbed(const rfe_params_t *p, const rfe_meas_t *h,
                                const rfe_sample_t *up, size_t j, const rfe_real_t *mu,
                                const rfe_real_t nom[RFE_MEAS_COLS], rfe_real_t z[RFE_MEAS])
{
    rfe_real_t t[RFE_MEAS_COLS];
    rfe_real_t c = h->cos_delta;
    rfe_real_t s = h->sin_delta;
    size_t i;
    size_t r;
    if (j == 0u) {
        c = RFE_COS(up->delta);
        s = RFE_SIN(up->delta);
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_real_t *ti = &t[i * (size_t)RFE_MEAS];
        if (reaches(j, i) != 0) {
            const rfe_status_t st = perturbed_terms(p, h, up, j, i, c, s, mu[i], ti);
            if (st != RFE_OK) {
                return st;
            }
        } else {
            for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
                ti[r] = nom[(i * (size_t)RFE_MEAS) + r];
            }
        }
    }
    return rfe_meas_sum_terms(t, z);
}

/* h at the perturbed sample up: the set-up's check of its one changed input (u's others
 * passed it), then h_perturbed. */
static rfe_status_t h_at_perturbed(const rfe_params_t *p, const rfe_meas_t *h,
                                   rfe_sample_t *up, size_t j, const rfe_real_t *mu,
                                   const rfe_real_t nom[RFE_MEAS_COLS], rfe_real_t z[RFE_MEAS])
{
    if (!rfe_is_finite(*input_slot(up, j))) {
        return RFE_ERR_NONFINITE;
    }
    return h_perturbed(p, h, up, j, mu, nom, z);
}

/* input_columns for a model set up in a load-scaled mode: the same columns and statuses. */
static rfe_status_t input_columns_abs(const rfe_params_t *p, const rfe_meas_t *h,
                                      const rfe_sample_t *u, const rfe_real_t *mu,
                                      const rfe_real_t nom[RFE_MEAS_COLS], rfe_real_t *A,
                                      size_t *cols)
{
    size_t i;
    size_t j;
    for (j = 0u; j < (size_t)RFE_EIV_INPUTS; ++j) {
        const rfe_real_t sd = input_sd(&p->filter, j);
        rfe_sample_t up = *u;
        rfe_sample_t um = *u;
        rfe_real_t zp[RFE_MEAS];
        rfe_real_t zm[RFE_MEAS];
        rfe_status_t st;
        if (!(sd > RFE_R(0.0))) {
            continue;
        }
        *input_slot(&up, j) += sd;
        *input_slot(&um, j) -= sd;
        st = h_at_perturbed(p, h, &up, j, mu, nom, zp);
        if (st == RFE_OK) {
            st = h_at_perturbed(p, h, &um, j, mu, nom, zm);
        }
        if (st != RFE_OK) {
            return st;
        }
        for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
            A[(i * CW) + *cols] = (zp[i] - zm[i]) / RFE_R(2.0);
        }
        ++(*cols);
    }
    return RFE_OK;
}

/* [S_R0, g_1 ..] into A (row stride CW), *cols its columns: absolute mode from the set-up h
 * (nominal terms reused), paper mode by evaluations of the model. */
static rfe_status_t fill(const rfe_params_t *p, const rfe_meas_t *h, const rfe_sample_t *u,
                         const rfe_real_t *mu, rfe_real_t *A, size_t *cols)
{
    rfe_real_t h0[RFE_MEAS];
    rfe_status_t st;
    if (h->mode != RFE_TYRE_PAPER) {
        rfe_real_t nom[RFE_MEAS_COLS];
        st = nominal_terms(p, h, mu, nom);
        if (st == RFE_OK) {
            st = rfe_meas_sum_terms(nom, h0);
        }
        if (st == RFE_OK) {
            sensor_block(&p->filter, h0, A);
            st = input_columns_abs(p, h, u, mu, nom, A, cols);
        }
    } else {
        /* h0 = h(mu, u) from the model set up at u (a non-finite mu: RFE_ERR_NONFINITE) */
        st = rfe_meas_eval(h, &p->vehicle, &p->tyre, mu, h0);
        if (st == RFE_OK) {
            sensor_block(&p->filter, h0, A);
            st = input_columns(p, u, mu, A, cols);
        }
    }
    return st;
}

rfe_status_t rfe_eiv_sqrt_noise_core(const rfe_params_t *p, const rfe_meas_t *h,
                                     const rfe_sample_t *u,
                                     const rfe_real_t mu[RFE_WHEELS],
                                     rfe_real_t SR[RFE_MEAS * RFE_MEAS])
{
    rfe_real_t A[(size_t)RFE_MEAS * CW];
    size_t cols = (size_t)RFE_MEAS;
    rfe_status_t st = fill(p, h, u, mu, A, &cols);

    if (st == RFE_OK) {
        st = rfe_qr_tria(A, (size_t)RFE_MEAS, cols, CW);
    }
    if (st == RFE_OK) {
        size_t i;
        size_t j;
        for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
            for (j = 0u; j < (size_t)RFE_MEAS; ++j) {
                SR[(i * (size_t)RFE_MEAS) + j] = (j <= i) ? A[(i * CW) + j] : RFE_R(0.0);
            }
        }
    }
    return st;
}

rfe_status_t rfe_eiv_sqrt_noise(const rfe_params_t *p, const rfe_sample_t *u,
                                const rfe_real_t mu[RFE_WHEELS],
                                rfe_real_t SR[RFE_MEAS * RFE_MEAS])
{
    rfe_meas_t h;
    rfe_status_t st;

    if ((p == NULL) || (u == NULL) || (mu == NULL) || (SR == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_params_validate(p) != RFE_OK) {
        return RFE_ERR_PARAM;
    }
    if (!rfe_all_finite(mu, RFE_WHEELS)) {
        return RFE_ERR_NONFINITE;
    }
    st = rfe_meas_setup(&h, &p->vehicle, &p->tyre, u);
    if (st != RFE_OK) {
        return st;
    }
    return rfe_eiv_sqrt_noise_core(p, &h, u, mu, SR);
}
