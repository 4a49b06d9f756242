/**
 * @file step_noise_q31.c
 * @brief Step-noise S_R on int32 Q values (the twin of step_noise_flt.c, docs/ESTIMATOR.md step 4):
 *        sensor noise, relative tyre-model error, input noise propagated by the analytic
 *        input derivative of h. Integer operations only.
 *
 * Everything is in Q24 (RFE_FIX_Q_ACC) except the input noise sds, which keep their inputs'
 * formats. The saturations counted: the measurement model's (kinematics, forces, H, h), an
 * input column beyond +-128 (rfe_meas_input_jac_q31), r_model_rel |h| beyond +-128 m/s^2
 * (r_model_rel > 1 only), an entry of S_R beyond the format (Tria).
 */
#include "rfe/component/step_noise_q31.h"

#include "rfe/component/fxmath.h"
#include "rfe/component/meas_q31.h"
#include "rfe/component/qr_q31.h"

#include "estimators/friction/friction_logic.h"
#include "estimators/friction/step_noise_internal_q31.h"
#include "models/meas_internal_q31.h"
#include "numerics/internal_q31.h"

#define CW ((size_t)RFE_MEAS + (size_t)RFE_INPUTS) /* widest [S_R0, g_1 .. g_8] */

/* The Tria of [S_R0, g_1 .. g_8] is 3 x 11: it must fit the smallest build's maxima. */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_step_noise_q31_tria_fits[((RFE_MEAS + RFE_INPUTS) <= RFE_TRIA_COLS_MAX) &&
                                                  (RFE_MEAS <= RFE_N_MAX)
                                              ? 1
                                              : -1];

/* S_R0 into the first RFE_MEAS columns of A (row stride CW, Q24): sensor noise and the model
 * error relative to each predicted acceleration h0. */
static void sensor_block_q31(const rfe_filter_params_q31_t *fp, const rfe_fix_t h0[RFE_MEAS],
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

/* g_j = sd_j dh/du_j (Q24) for each noisy input (sd_j > 0), in order, as columns *cols,
 * *cols + 1, ... of A (row stride CW); *cols ends one past the last. The derivatives are
 * analytic, from the set-up h (rfe_meas_input_jac_q31; docs/FIXED_POINT.md "Analytic input
 * derivatives" gives their error): issue 21, instead of the central differences of h over
 * sd_j (16 model evaluations). */
static rfe_status_t input_columns_q31(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                                      const rfe_sample_q31_t *u, const rfe_fix_t *mu,
                                      rfe_fix_t *h0, rfe_fix_t *A, size_t *cols,
                                      uint32_t *count)
{
    rfe_fix_t sd[RFE_INPUTS];
    rfe_fix_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS];
    rfe_status_t st;
    size_t i;
    size_t j;
    for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
        sd[j] = rfe_step_noise_input_sd_q31(&p->filter, j);
    }
    if (h0 != NULL) {
        /* h0 with the derivative: one evaluation of the tyres (meas_internal_q31.h) */
        st = rfe_meas_nominal_input_jac_q31(h, &p->vehicle, &p->tyre, u, mu, sd, h0, G, count);
    } else {
        st = rfe_meas_input_jac_q31(h, &p->vehicle, &p->tyre, u, mu, sd, G, count);
    }
    if (st != RFE_OK) {
        return st;
    }
    for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
        if (sd[j] <= 0) {
            continue;
        }
        for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
            A[(i * CW) + *cols] = G[(i * (size_t)RFE_INPUTS) + j];
        }
        ++(*cols);
    }
    return RFE_OK;
}

/* [S_R0, g_1 ..] into A (row stride CW), *cols its columns: h0 and (the load-scaled modes,
 * absolute and magic) the nominal terms from the set-up h (rfe_meas_nominal_q31), paper mode
 * h0 from the model set up again (rfe_step_noise_h0_q31); then S_R0 and the input columns. */
static rfe_status_t fill_q31(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                             const rfe_sample_q31_t *u, const rfe_fix_t *mu, rfe_fix_t *A,
                             size_t *cols, uint32_t *count)
{
    rfe_meas_terms_q31_t nom; /* written in the load-scaled modes, read only there */
    rfe_fix_t h0[RFE_MEAS];
    rfe_status_t st;
    if (rfe_meas_one_pass_ok_q31(h, &p->tyre) != 0) {
        /* h0 (rfe_meas_nominal_q31's) and the input columns in one pass; the sensor block,
         * which reads h0, after them: its columns come first in A all the same */
        st = input_columns_q31(p, h, u, mu, h0, A, cols, count);
        if (st == RFE_OK) {
            sensor_block_q31(&p->filter, h0, A, count);
        }
        return st;
    }
    if (h->mode != RFE_TYRE_PAPER) {
        st = rfe_meas_nominal_q31(h, &p->vehicle, &p->tyre, mu, &nom, h0, count);
    } else {
        st = rfe_step_noise_h0_q31(p, u, mu, h0, count);
    }
    if (st == RFE_OK) {
        sensor_block_q31(&p->filter, h0, A, count);
        st = input_columns_q31(p, h, u, mu, NULL, A, cols, count);
    }
    return st;
}

rfe_status_t rfe_step_noise_sqrt_core_q31(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                                         const rfe_sample_q31_t *u,
                                         const rfe_fix_t mu[RFE_WHEELS],
                                         rfe_fix_t SR[RFE_MEAS * RFE_MEAS],
                                         uint64_t pers[RFE_MEAS], uint32_t *sat)
{
    rfe_fix_t A[(size_t)RFE_MEAS * CW];
    size_t cols = (size_t)RFE_MEAS;
    uint32_t count = 0u;
    rfe_status_t st;

    st = fill_q31(p, h, u, mu, A, &cols, &count);
    if (st == RFE_OK) {
        if (pers != NULL) {
            /* in its own unit, so it is no part of this frame (the deepest path's) */
            rfe_step_noise_pers_q31(&p->filter, A, CW, pers);
        }
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

rfe_status_t rfe_step_noise_sqrt_q31(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
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
    return rfe_step_noise_sqrt_core_q31(p, &h, u, mu, SR, NULL, sat);
}
