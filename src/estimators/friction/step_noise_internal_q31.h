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
 * step to step (Q24; step_noise_internal.h's twin: (r_model_rel |h0_r|)^2 plus the squares
 * of the low-passed inputs' columns), each square rounded and every saturation counted;
 * with pers NULL nothing of it is computed (the same S_R and count as without it).
 * @return RFE_OK; the errors of rfe_step_noise_sqrt_q31 after its checks (@p SR, @p pers,
 *         *sat then untouched).
 */
rfe_status_t rfe_step_noise_sqrt_core_q31(const rfe_params_q31_t *p, const rfe_meas_q31_t *h,
                                         const rfe_sample_q31_t *u,
                                         const rfe_fix_t mu[RFE_WHEELS],
                                         rfe_fix_t SR[RFE_MEAS * RFE_MEAS],
                                         rfe_fix_t pers[RFE_MEAS], uint32_t *sat);

#endif /* RFE_STEP_NOISE_INTERNAL_Q31_H */
