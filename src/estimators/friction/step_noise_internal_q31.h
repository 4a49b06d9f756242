/**
 * @file step_noise_internal_q31.h
 * @brief Private entry of the fixed-point step noise (step_noise_q31.c) for the estimator
 *        (friction_q31.c). Not installed; integer operations only.
 */
#ifndef RFE_STEP_NOISE_INTERNAL_Q31_H
#define RFE_STEP_NOISE_INTERNAL_Q31_H

#include <stdint.h>

#include "rfe/component/step_noise_q31.h"
#include "rfe/fixed.h"
#include "rfe/component/meas_q31.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre_q31.h"

/**
 * rfe_step_noise_sqrt_q31 without its checks, for a caller that has already set up the
 * measurement model @p h of the same sample @p u with p->vehicle and p->tyre: the same S_R
 * and count, bit for bit (the load-scaled tyre modes, absolute and magic, reuse h's
 * kinematics, friction-independent tyre terms and the columns of the wheels an input does
 * not reach; paper mode evaluates as the public function). Preconditions (not checked): every pointer valid, @p p passed
 * rfe_params_validate_q31 (the estimator's, validated at init), rfe_meas_setup_q31(h,
 * &p->vehicle, &p->tyre, u, .) returned RFE_OK.
 * @p pers, when not NULL, receives the diagonal of the part of S_R S_R^T that persists from
 * step to step (Q48 as uint64, RFE_MON_Q31_QP; step_noise_internal.h's twin: (r_model_rel
 * |h0_r|)^2 plus the squares of the low-passed inputs' columns), exact and never saturating;
 * with pers NULL nothing of it is computed (the same S_R and count as without it).
 * @return RFE_OK; the errors of rfe_step_noise_sqrt_q31 after its checks (@p SR, *sat then
 *         untouched; @p pers, filled in place, then unspecified).
 */
rfe_status_t rfe_step_noise_sqrt_core_q31(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                                         const rfe_sample_q31_t *u,
                                         const rfe_fix_t mu[RFE_WHEELS],
                                         rfe_fix_t SR[RFE_MEAS * RFE_MEAS],
                                         uint64_t pers[RFE_MEAS], uint32_t *sat);

/**
 * z = h(mu, u) (Q24) for sample @p u, its model set up again (paper mode's h0 in the step
 * noise: the set-up's saturations are counted once more into *count, as they always were;
 * the committed goldens hold these counts). Preconditions as rfe_step_noise_sqrt_core_q31's.
 * @return RFE_OK, or the error of rfe_meas_setup_q31 / rfe_meas_eval_q31.
 */
rfe_status_t rfe_step_noise_h0_q31(const rfe_params_q31_t *p, const rfe_sample_q31_t *u,
                                   const rfe_fix_t *mu, rfe_fix_t z[RFE_MEAS], uint32_t *count);

/** The noise sd of input j (RFE_IN_*, rfe/common.h; j < RFE_INPUTS), in that input's format. */
rfe_fix_t rfe_step_noise_input_sd_q31(const rfe_filter_params_q31_t *fp, size_t j);

/**
 * The diagonal of the part of A A^T that persists from step to step (Q48 as uint64,
 * RFE_MON_Q31_QP), from the step noise's array A = [S_R0, g_1 ..] (Q24) before its Tria (row
 * stride @p lda, the columns of the inputs with sd > 0 in input order): the model error's
 * square e_i^2 = A_ii^2 - r_i^2 (A_ii = sqrt(r_i^2 + e_i^2) rounded, so within A_ii 2^-24 of
 * e_i^2, and >= 0) plus the squares of the low-passed inputs' columns (step_noise_flt.c's
 * pers), every square exact. At most three squares, each <= 2^62: no overflow, no saturation.
 */
void rfe_step_noise_pers_q31(const rfe_filter_params_q31_t *fp, const rfe_fix_t *A, size_t lda,
                             uint64_t pers[RFE_MEAS]);

#endif /* RFE_STEP_NOISE_INTERNAL_Q31_H */
