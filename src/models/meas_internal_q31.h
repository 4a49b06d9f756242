/**
 * @file meas_internal_q31.h
 * @brief Private entry of meas_q31.c for the step noise (step_noise_q31.c): the nominal
 *        model value and the input derivative from one evaluation of the tyre forces (twin of
 *        meas_internal.h). Not installed; integer operations only.
 */
#ifndef RFE_MEAS_INTERNAL_Q31_H
#define RFE_MEAS_INTERNAL_Q31_H

#include "rfe/component/meas_q31.h"

/** 1 when rfe_meas_nominal_input_jac_q31 applies to the set-up @p h and the tyre @p tp: a
 *  Magic Formula set-up evaluated with the set-up's tyre parameters (those pre depends on) in
 *  Magic Formula mode; else 0 (also for NULL). */
int rfe_meas_one_pass_ok_q31(const rfe_meas_q31_t *h, const rfe_tyre_params_q31_t *tp);

/** Where rfe_meas_one_pass_ok_q31(h, tp): rfe_meas_nominal_q31(h, veh, tp, mu, ., z, .)
 *  followed by rfe_meas_input_jac_q31(h, veh, tp, u, mu, sd, G, .), the same z, G, saturation
 *  count and statuses, bit for bit (@p z, @p G meaningful and *sat added to only on RFE_OK):
 *  the nominal forces are the ones the derivative evaluates anyway (rfe_tyre_magic_basis_q31's
 *  fx, fy are the operations of rfe_tyre_dugoff_abs_pre_q31's Magic Formula, with the same
 *  clamp counts), so each wheel's curve pair is evaluated once (issue 21: the four Magic
 *  Formula curve pairs at the nominal friction, ~3 k instructions a step on the Cortex-M4).
 *  Elsewhere RFE_ERR_PARAM with nothing written: the caller makes the two calls (not made
 *  here, so that their frames are never below this one's on the stack). Unlike the float twin
 *  it keeps no forces for the cubature points (rfe_meas_q31_t has no room within the state's
 *  2,048 B budget). @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; the errors of
 *  rfe_meas_input_jac_q31's checks. */
RFE_NODISCARD rfe_status_t rfe_meas_nominal_input_jac_q31(
    const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
    const rfe_sample_q31_t *u, const rfe_fix_t mu[RFE_WHEELS], const rfe_fix_t sd[RFE_INPUTS],
    rfe_fix_t z[RFE_MEAS], rfe_fix_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS], uint32_t *sat);

#endif /* RFE_MEAS_INTERNAL_Q31_H */
