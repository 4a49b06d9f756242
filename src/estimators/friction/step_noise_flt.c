/**
 * @file step_noise_flt.c
 * @brief Step-noise S_R: sensor noise, relative tyre-model error, input noise propagated by
 *        by the analytic input derivative of h (docs/ESTIMATOR.md step 4).
 */
#include "rfe/component/step_noise.h"

#include "rfe/component/meas.h"
#include "rfe/component/qr.h"

#include "estimators/friction/friction_logic.h"
#include "estimators/friction/step_noise_internal.h"
#include "models/meas_internal.h"
#include "numerics/internal.h"

#define CW ((size_t)RFE_MEAS + (size_t)RFE_INPUTS) /* widest [S_R0, g_1 .. g_8] */

/* The Tria of [S_R0, g_1 .. g_8] is 3 x 11: it must fit the smallest build's maxima. */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_step_noise_tria_fits[((RFE_MEAS + RFE_INPUTS) <= RFE_TRIA_COLS_MAX) &&
                                              (RFE_MEAS <= RFE_N_MAX)
                                          ? 1
                                          : -1];

/* The noise sd of input j (RFE_IN_*, rfe/common.h). */
static rfe_real_t input_sd(const rfe_filter_params_t *fp, size_t j)
{
    const rfe_real_t sd[RFE_INPUTS] = {fp->sd_in_delta,    fp->sd_in_vx,    fp->sd_in_vy,
                                       fp->sd_in_yaw_rate, fp->sd_in_omega, fp->sd_in_omega,
                                       fp->sd_in_omega,    fp->sd_in_omega};
    return sd[j];
}

/* S_R0 into the first RFE_MEAS columns of A (row stride CW): sensor noise and the model
 * error relative to each predicted acceleration h0. */
static void sensor_block(const rfe_filter_params_t *fp, const rfe_real_t h0[RFE_MEAS],
                         rfe_real_t *A, rfe_real_t pers[RFE_MEAS])
{
    rfe_real_t r[RFE_MEAS];
    size_t i;
    size_t j;
    r[0] = fp->r_ax;
    r[1] = fp->r_ay;
    r[2] = fp->r_yaw_acc;
    for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
        const rfe_real_t e = fp->r_model_rel * RFE_FABS(h0[i]);
        pers[i] = e * e; /* a curve error: the same at the next step */
        for (j = 0u; j < (size_t)RFE_MEAS; ++j) {
            A[(i * CW) + j] = (i == j) ? RFE_SQRT((r[i] * r[i]) + (e * e)) : RFE_R(0.0);
        }
    }
}

/* h0 = h(mu, u) from the set-up h, then S_R0 and g_j = sd_j dh/du_j for each noisy input
 * (sd_j > 0), in order, as columns *cols, *cols + 1, ... of A (row stride CW); *cols ends one
 * past the last; the diagonal of the part of A A^T that persists from step to step into pers
 * (the model error's squares, then the low-passed inputs' columns' squares added). The
 * derivatives are analytic, from the set-up h (docs/ESTIMATOR.md step 4): issue 21, instead
 * of the central differences of h over sd_j (16 model evaluations); h0 and they come from one
 * evaluation of the tyres (rfe_meas_nominal_input_jac: rfe_meas_nominal's h0 and
 * rfe_meas_input_jac's columns, bit for bit). */
static rfe_status_t fill(const rfe_params_t *p, rfe_meas_t *h, const rfe_sample_t *u,
                         const rfe_real_t *mu, rfe_real_t *A, size_t *cols,
                         rfe_real_t pers[RFE_MEAS])
{
    rfe_real_t sd[RFE_INPUTS];
    rfe_real_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS];
    rfe_real_t h0[RFE_MEAS];
    rfe_status_t st;
    size_t i;
    size_t j;
    for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
        sd[j] = input_sd(&p->filter, j);
    }
    st = rfe_meas_nominal_input_jac(h, &p->vehicle, &p->tyre, u, mu, sd, h0, G);
    if (st != RFE_OK) {
        return st;
    }
    sensor_block(&p->filter, h0, A, pers);
    for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
        if (!(sd[j] > RFE_R(0.0))) {
            continue;
        }
        for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
            const rfe_real_t g = G[(i * (size_t)RFE_INPUTS) + j];
            A[(i * CW) + *cols] = g;
            if (rfe_input_low_passed(j) != 0) {
                pers[i] += g * g;
            }
        }
        ++(*cols);
    }
    return RFE_OK;
}

rfe_status_t rfe_step_noise_sqrt_core(const rfe_params_t *p, rfe_meas_t *h,
                                     const rfe_sample_t *u,
                                     const rfe_real_t mu[RFE_WHEELS],
                                     rfe_real_t SR[RFE_MEAS * RFE_MEAS],
                                     rfe_real_t pers[RFE_MEAS])
{
    rfe_real_t A[(size_t)RFE_MEAS * CW];
    rfe_real_t pc[RFE_MEAS];
    size_t cols = (size_t)RFE_MEAS;
    rfe_status_t st = fill(p, h, u, mu, A, &cols, pc);

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
            if (pers != NULL) {
                pers[i] = pc[i];
            }
        }
    }
    return st;
}

rfe_status_t rfe_step_noise_sqrt(const rfe_params_t *p, const rfe_sample_t *u,
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
    return rfe_step_noise_sqrt_core(p, &h, u, mu, SR, NULL);
}
