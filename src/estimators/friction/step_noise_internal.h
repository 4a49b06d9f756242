/**
 * @file step_noise_internal.h
 * @brief Private entry of the step noise (step_noise_flt.c) for the estimator (friction_flt.c).
 *        Not installed.
 */
#ifndef RFE_STEP_NOISE_INTERNAL_H
#define RFE_STEP_NOISE_INTERNAL_H

#include "rfe/component/step_noise.h"
#include "rfe/component/meas.h"
#include "rfe/params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_step_noise_sqrt_core rfe_step_noise_sqrt_core_f64
#else
#define rfe_step_noise_sqrt_core rfe_step_noise_sqrt_core_f32
#endif

/**
 * rfe_step_noise_sqrt without its checks, for a caller that has already set up the
 * measurement model @p h of the same sample @p u with p->vehicle and p->tyre (the nominal
 * h(mu, u) is then one evaluation of @p h): the same S_R, bit for bit, and the same
 * statuses after the checks. Preconditions (not checked): every pointer valid, @p p passed
 * rfe_params_validate (the estimator's, validated at init), rfe_meas_setup(h,
 * &p->vehicle, &p->tyre, u) returned RFE_OK. A non-finite @p mu gives RFE_ERR_NONFINITE (from
 * the evaluation). @p pers, when not NULL, receives the diagonal of the part of S_R S_R^T
 * that does not change from one step to the next (the model monitor's persistent share,
 * docs/MONITOR.md §1): (r_model_rel |h0_r|)^2 plus the squares of the low-passed inputs'
 * columns (rfe_input_low_passed: vx, vy).
 * On RFE_OK in the load-scaled modes @p h keeps the tyre forces at @p mu for its cubature
 * points (rfe_meas_nominal_input_jac, models/meas_internal.h): rfe_meas_eval's results stay
 * bit for bit the same.
 * @return RFE_OK; RFE_ERR_NONFINITE and the tyre's errors (@p SR, @p pers then untouched).
 */
RFE_NODISCARD rfe_status_t rfe_step_noise_sqrt_core(const rfe_params_t *p,
                                                  rfe_meas_t *h,
                                                  const rfe_sample_t *u,
                                                  const rfe_real_t mu[RFE_WHEELS],
                                                  rfe_real_t SR[RFE_MEAS * RFE_MEAS],
                                                  rfe_real_t pers[RFE_MEAS]);

#endif /* RFE_STEP_NOISE_INTERNAL_H */
