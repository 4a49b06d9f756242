/**
 * @file step_noise_pers_q31.c
 * @brief The step noise's persistent diagonal, the input-noise table and paper mode's h0
 *        (step_noise_q31.c's helpers, step_noise_internal_q31.h). A unit of its own so that
 *        the compiler cannot fold them (h0's set-up model: 288 B) into
 *        rfe_step_noise_sqrt_core_q31's frame: that function is on the estimator's deepest
 *        call path, which must fit the Cortex-M0+ stack budget.
 *        Integer operations only.
 */
#include "estimators/friction/friction_logic.h"
#include "estimators/friction/step_noise_internal_q31.h"
#include "numerics/internal_q31.h"

rfe_status_t rfe_step_noise_h0_q31(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
                                   const rfe_fix_t *mu, rfe_fix_t z[RFE_MEAS], uint32_t *count)
{
    rfe_meas_q31_t h;
    rfe_status_t st = rfe_meas_setup_q31(&h, &p->vehicle, &p->tyre, u, count);
    if (st == RFE_OK) {
        st = rfe_meas_eval_q31(&h, &p->vehicle, &p->tyre, mu, z, count);
    }
    return st;
}

rfe_fix_t rfe_step_noise_input_sd_q31(const rfe_filter_params_q31_t *fp, size_t j)
{
    const rfe_fix_t sd[RFE_INPUTS] = {fp->sd_in_delta,    fp->sd_in_vx,
                                      fp->sd_in_vy,       fp->sd_in_yaw_rate,
                                      fp->sd_in_omega,    fp->sd_in_omega,
                                      fp->sd_in_omega,    fp->sd_in_omega};
    return sd[j];
}

void rfe_step_noise_pers_q31(const rfe_filter_params_q31_t *fp, const rfe_fix_t *A, size_t lda,
                             uint64_t pers[RFE_MEAS])
{
    rfe_fix_t r[RFE_MEAS];
    size_t i;
    size_t j;
    r[0] = fp->r_ax;
    r[1] = fp->r_ay;
    r[2] = fp->r_yaw_acc;
    /* Squares of Q24 values are Q48 (RFE_MON_Q31_QP) exactly. A_ii >= r_i > 0 (A_ii is
     * sqrt(r_i^2 + e_i^2) rounded to the nearest integer, r_i an integer), so the difference
     * is >= 0; each square is <= 2^62, and with at most two low-passed inputs (vx, vy:
     * rfe_input_low_passed) the sum stays below 3 2^62 < 2^64. */
    for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
        const uint64_t a = rfe_q31_mag64((int64_t)A[(i * lda) + i]);
        const uint64_t ri = rfe_q31_mag64((int64_t)r[i]);
        size_t col = (size_t)RFE_MEAS;
        pers[i] = (a * a) - (ri * ri);
        for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
            if (rfe_step_noise_input_sd_q31(fp, j) > 0) {
                if (rfe_input_low_passed(j) != 0) {
                    const uint64_t g = rfe_q31_mag64((int64_t)A[(i * lda) + col]);
                    pers[i] += g * g;
                }
                ++col;
            }
        }
    }
}
