/**
 * @file eiv_q31.c
 * @brief Step-noise S_R on int32 Q values (the twin of eiv_flt.c, docs/ESTIMATOR.md step 4):
 *        sensor noise, relative tyre-model error, input noise propagated by central
 *        differences. Integer operations only.
 *
 * Everything is in Q24 (RFE_FIX_Q_ACC) except the perturbed sample, whose fields keep their
 * own formats (the input noise sds share them). The saturations counted: the measurement
 * model's (kinematics, forces, H, h), a perturbed input beyond its format, r_model_rel |h|
 * beyond +-128 m/s^2 (r_model_rel > 1 only), an entry of S_R beyond the format (Tria). A
 * halved difference of two int32 cannot leave the int32 range.
 */
#include "rfe/component/eiv_q31.h"

#include "rfe/component/fxmath.h"
#include "rfe/component/meas_q31.h"
#include "rfe/component/qr_q31.h"

#include "estimators/friction/eiv_internal_q31.h"
#include "numerics/internal_q31.h"
#include "models/meas_internal_q31.h"
#include "models/tyre_internal_q31.h"

#define CW ((size_t)RFE_MEAS + (size_t)RFE_EIV_Q31_INPUTS) /* widest [S_R0, g_1 .. g_8] */

/* The Tria of [S_R0, g_1 .. g_8] is 3 x 11: it must fit the smallest build's maxima. */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_eiv_q31_tria_fits[((RFE_MEAS + RFE_EIV_Q31_INPUTS) <= RFE_TRIA_COLS_MAX) &&
                                                  (RFE_MEAS <= RFE_N_MAX)
                                              ? 1
                                              : -1];

/* Input j of the sample (0 delta, 1 vx, 2 vy, 3 r, 4.. omega_fl..rr). */
static rfe_fix_t *eiv_input_slot(rfe_sample_q31_t *u, size_t j)
{
    rfe_fix_t *slot;
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

/* The noise sd of input j, in the format of that input. */
static rfe_fix_t eiv_input_sd(const rfe_filter_params_q31_t *fp, size_t j)
{
    const rfe_fix_t sd[RFE_EIV_Q31_INPUTS] = {fp->sd_in_delta,    fp->sd_in_vx,
                                              fp->sd_in_vy,       fp->sd_in_yaw_rate,
                                              fp->sd_in_omega,    fp->sd_in_omega,
                                              fp->sd_in_omega,    fp->sd_in_omega};
    return sd[j];
}

/* z = h(mu, u) (Q24) for sample u (its own kinematics). */
static rfe_status_t eiv_h_at(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
                             const rfe_fix_t *mu, rfe_fix_t z[RFE_MEAS], uint32_t *count)
{
    rfe_meas_q31_t h;
    rfe_status_t st = rfe_meas_setup_q31(&h, &p->vehicle, &p->tyre, u, count);
    if (st == RFE_OK) {
        st = rfe_meas_eval_q31(&h, &p->vehicle, &p->tyre, mu, z, count);
    }
    return st;
}

/* S_R0 into the first RFE_MEAS columns of A (row stride CW, Q24): sensor noise and the model
 * error relative to each predicted acceleration h0. */
static void eiv_sensor_block(const rfe_filter_params_q31_t *fp, const rfe_fix_t h0[RFE_MEAS],
                             rfe_fix_t *A, uint32_t *count)
{
    rfe_fix_t r[RFE_MEAS];
    size_t i;
    size_t j;
    r[0] = fp->r_ax;
    r[1] = fp->r_ay;
    r[2] = fp->r_yaw_acc;
    for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
        /* r_model_rel (Q30) |h| (Q24): Q54 rounded to Q24; then sqrt(r^2 + e^2), exactly
         * rounded (rfe_fix_norm fails only for NULL pointers, which these are not). */
        rfe_fix_t v[2];
        rfe_fix_t norm = 0;
        rfe_status_t st;
        v[0] = r[i];
        v[1] = rfe_fix_mul(fp->r_model_rel, rfe_fix_abs(h0[i], count), RFE_FIX_Q_SD, count);
        st = rfe_fix_norm(v, 2u, &norm, count);
        (void)st;
        for (j = 0u; j < (size_t)RFE_MEAS; ++j) {
            A[(i * CW) + j] = (i == j) ? norm : 0;
        }
    }
}

/* g_j = (h(u + sd_j e_j) - h(u - sd_j e_j)) / 2 (Q24) for each noisy input, in order, as
 * columns *cols, *cols + 1, ... of A (row stride CW); *cols ends one past the last. */
static rfe_status_t eiv_input_columns(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
                                      const rfe_fix_t *mu, rfe_fix_t *A, size_t *cols,
                                      uint32_t *count)
{
    size_t i;
    size_t j;
    for (j = 0u; j < (size_t)RFE_EIV_Q31_INPUTS; ++j) {
        const rfe_fix_t sd = eiv_input_sd(&p->filter, j);
        rfe_sample_q31_t up = *u;
        rfe_sample_q31_t um = *u;
        rfe_fix_t zp[RFE_MEAS];
        rfe_fix_t zm[RFE_MEAS];
        rfe_status_t st;
        if (sd <= 0) {
            continue;
        }
        *eiv_input_slot(&up, j) = rfe_fix_add(*eiv_input_slot(&up, j), sd, count);
        *eiv_input_slot(&um, j) = rfe_fix_sub(*eiv_input_slot(&um, j), sd, count);
        st = eiv_h_at(p, &up, mu, zp, count);
        if (st == RFE_OK) {
            st = eiv_h_at(p, &um, mu, zm, count);
        }
        if (st != RFE_OK) {
            return st;
        }
        for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
            /* the exact difference (< 2^32) halved, rounded half up: fits the int32 range */
            A[(i * CW) + *cols] = rfe_fix_narrow((int64_t)zp[i] - (int64_t)zm[i], 1u, count);
        }
        ++(*cols);
    }
    return RFE_OK;
}

/* ---- load-scaled tyre modes (absolute, magic): only the wheels an input reaches are
 * evaluated again -------------------------------------------------------------------------
 * h(mu, u) is the exact sum of four per-wheel columns (meas_internal_q31.h), each a function
 * of that wheel's kinematics, its load and cos/sin of delta. The loads depend on ax, ay only
 * (never perturbed); delta reaches the front wheels' kinematics and columns, vx, vy and r
 * every wheel, omega_i only wheel i's kappa. A perturbed h therefore takes the nominal
 * column (and saturation count) of every other wheel: the same integers as a full
 * evaluation, so the same sums and counts. */

/* The nominal columns of the four wheels and each one's saturation count (its kinematics'
 * from the set-up, its forces' and entries'). */
typedef struct {
    rfe_fix_t col[RFE_MEAS_Q31_COLS];
    uint32_t cnt[RFE_WHEELS];
} eiv_cols_t;

static void eiv_nominal_columns(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                                const rfe_fix_t *mu, eiv_cols_t *nom)
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        nom->cnt[i] = h->sat_vwx[i] + h->sat_fz[i];
        rfe_meas_wheel_column_q31(&p->vehicle, &p->tyre, &h->pre[i], mu[i], h->kin.fz[i],
                                  h->cos_delta, h->sin_delta, i,
                                  &nom->col[i * (size_t)RFE_MEAS], &nom->cnt[i]);
    }
}

/* 1 when input j (0 delta, 1 vx, 2 vy, 3 r, 4.. omega_fl..rr) reaches wheel i: delta the
 * front wheels, vx, vy and r every wheel, omega_i wheel i (bit i of the input's mask; wheels
 * in the order fl, fr, rl, rr). */
static int eiv_reaches(size_t j, size_t i)
{
    static const uint8_t wheel_mask[RFE_EIV_Q31_INPUTS] = {0x3u, 0xFu, 0xFu, 0xFu, 0x1u, 0x2u, 0x4u, 0x8u};
    return ((((uint32_t)wheel_mask[j] >> i) & 1u) != 0u) ? 1 : 0;
}

/* Column of wheel i (reached by input j) for the perturbed sample up; c, s: cos/sin of
 * up->delta. Its saturation count into *cnt. */
static void eiv_wheel_column(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                             const rfe_sample_q31_t *up, size_t j, size_t i, int32_t c,
                             int32_t s, rfe_fix_t mu, rfe_fix_t col[RFE_MEAS], uint32_t *cnt)
{
    rfe_dugoff_pre_q31_t pre;
    *cnt = h->sat_fz[i];
    if (j >= 4u) {
        /* a wheel speed: kappa changes; vwx, alpha and so tan alpha are the nominal ones */
        const rfe_fix_t kappa = rfe_tyre_wheel_kappa_q31(&p->vehicle, &p->tyre, up, c, s, i);
        *cnt += h->sat_vwx[i];
        rfe_tyre_dugoff_pre_tan_q31(&p->tyre, kappa, h->pre[i].tan_a, h->kin.vwx[i], &pre);
    } else {
        rfe_fix_t vwx = 0;
        rfe_fix_t alpha = 0;
        rfe_fix_t kappa = 0;
        rfe_tyre_wheel_kin_q31(&p->vehicle, &p->tyre, up, c, s, i, &vwx, &alpha, &kappa, cnt);
        rfe_tyre_dugoff_pre_q31(&p->tyre, kappa, alpha, vwx, &pre);
    }
    rfe_meas_wheel_column_q31(&p->vehicle, &p->tyre, &pre, mu, h->kin.fz[i], c, s, i, col, cnt);
}

/* z = h(mu, up) (Q24) for the sample u with input j perturbed (up), from the nominal
 * columns of the wheels j does not reach. */
static void eiv_h_perturbed(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                            const rfe_sample_q31_t *up, size_t j, const rfe_fix_t *mu,
                            const eiv_cols_t *nom, rfe_fix_t z[RFE_MEAS], uint32_t *count)
{
    rfe_fix_t col[RFE_MEAS_Q31_COLS];
    int32_t c = h->cos_delta;
    int32_t s = h->sin_delta;
    size_t i;
    size_t r;
    if (j == 0u) {
        const rfe_status_t st = rfe_fix_sincos(up->delta, &s, &c); /* every angle: no error */
        (void)st;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        rfe_fix_t *ci = &col[i * (size_t)RFE_MEAS];
        uint32_t cnt = nom->cnt[i];
        if (eiv_reaches(j, i) != 0) {
            eiv_wheel_column(p, h, up, j, i, c, s, mu[i], ci, &cnt);
        } else {
            for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
                ci[r] = nom->col[(i * (size_t)RFE_MEAS) + r];
            }
        }
        rfe_q31_sat_add(count, cnt);
    }
    rfe_meas_sum_columns_q31(col, z, count);
}

/* eiv_input_columns for a model set up in a load-scaled mode: the same columns. */
static void eiv_input_columns_abs(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                                  const rfe_sample_q31_t *u, const rfe_fix_t *mu,
                                  const eiv_cols_t *nom, rfe_fix_t *A, size_t *cols,
                                  uint32_t *count)
{
    size_t i;
    size_t j;
    for (j = 0u; j < (size_t)RFE_EIV_Q31_INPUTS; ++j) {
        const rfe_fix_t sd = eiv_input_sd(&p->filter, j);
        rfe_sample_q31_t up = *u;
        rfe_sample_q31_t um = *u;
        rfe_fix_t zp[RFE_MEAS];
        rfe_fix_t zm[RFE_MEAS];
        if (sd <= 0) {
            continue;
        }
        *eiv_input_slot(&up, j) = rfe_fix_add(*eiv_input_slot(&up, j), sd, count);
        *eiv_input_slot(&um, j) = rfe_fix_sub(*eiv_input_slot(&um, j), sd, count);
        eiv_h_perturbed(p, h, &up, j, mu, nom, zp, count);
        eiv_h_perturbed(p, h, &um, j, mu, nom, zm, count);
        for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
            /* the exact difference (< 2^32) halved, rounded half up: fits the int32 range */
            A[(i * CW) + *cols] = rfe_fix_narrow((int64_t)zp[i] - (int64_t)zm[i], 1u, count);
        }
        ++(*cols);
    }
}

/* [S_R0, g_1 ..] into A (row stride CW), *cols its columns: the load-scaled modes (absolute,
 * magic) from the set-up h (nominal columns reused), paper mode by full evaluations. */
static rfe_status_t eiv_fill(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                             const rfe_sample_q31_t *u, const rfe_fix_t *mu, rfe_fix_t *A,
                             size_t *cols, uint32_t *count)
{
    rfe_fix_t h0[RFE_MEAS];
    rfe_status_t st = RFE_OK;
    if (h->mode != RFE_TYRE_PAPER) {
        eiv_cols_t nom;
        size_t i;
        eiv_nominal_columns(p, h, mu, &nom);
        for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
            rfe_q31_sat_add(count, nom.cnt[i]);
        }
        rfe_meas_sum_columns_q31(nom.col, h0, count);
        eiv_sensor_block(&p->filter, h0, A, count);
        eiv_input_columns_abs(p, h, u, mu, &nom, A, cols, count);
    } else {
        st = eiv_h_at(p, u, mu, h0, count);
        if (st == RFE_OK) {
            eiv_sensor_block(&p->filter, h0, A, count);
            st = eiv_input_columns(p, u, mu, A, cols, count);
        }
    }
    return st;
}

rfe_status_t rfe_eiv_sqrt_noise_core_q31(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                                         const rfe_sample_q31_t *u,
                                         const rfe_fix_t mu[RFE_WHEELS],
                                         rfe_fix_t SR[RFE_MEAS * RFE_MEAS], uint32_t *sat)
{
    rfe_fix_t A[(size_t)RFE_MEAS * CW];
    size_t cols = (size_t)RFE_MEAS;
    uint32_t count = 0u;
    rfe_status_t st;

    st = eiv_fill(p, h, u, mu, A, &cols, &count);
    if (st == RFE_OK) {
        st = rfe_qr_tria_q31(A, (size_t)RFE_MEAS, cols, CW, &count);
    }
    if (st == RFE_OK) {
        size_t i;
        size_t j;
        for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
            for (j = 0u; j < (size_t)RFE_MEAS; ++j) {
                SR[(i * (size_t)RFE_MEAS) + j] = (j <= i) ? A[(i * CW) + j] : 0;
            }
        }
        rfe_q31_sat_add(sat, count);
    }
    return st;
}

rfe_status_t rfe_eiv_sqrt_noise_q31(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
                                    const rfe_fix_t mu[RFE_WHEELS],
                                    rfe_fix_t SR[RFE_MEAS * RFE_MEAS], uint32_t *sat)
{
    rfe_meas_q31_t h;
    uint32_t scratch = 0u; /* the set-up's counts enter through h (its per-wheel counts) */
    rfe_status_t st;

    if ((p == NULL) || (u == NULL) || (mu == NULL) || (SR == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_params_validate_q31(p) != RFE_OK) {
        return RFE_ERR_PARAM;
    }
    st = rfe_meas_setup_q31(&h, &p->vehicle, &p->tyre, u, &scratch);
    if (st != RFE_OK) {
        return st;
    }
    return rfe_eiv_sqrt_noise_core_q31(p, &h, u, mu, SR, sat);
}
