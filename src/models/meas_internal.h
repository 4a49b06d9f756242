/**
 * @file meas_internal.h
 * @brief Private entry of meas_flt.c for the step noise (step_noise_flt.c): the nominal
 *        model value and the input derivative from one evaluation of the tyre forces. Not
 *        installed.
 */
#ifndef RFE_MEAS_INTERNAL_H
#define RFE_MEAS_INTERNAL_H

#include "rfe/component/meas.h"

/* Full name: _f32 in the float build, _f64 with RFE_REAL_DOUBLE (rfe/types.h). */
#if defined(RFE_REAL_DOUBLE)
#define rfe_meas_nominal_input_jac rfe_meas_nominal_input_jac_f64
#else
#define rfe_meas_nominal_input_jac rfe_meas_nominal_input_jac_f32
#endif

/** rfe_meas_nominal(h, veh, tp, mu, ., z) followed by rfe_meas_input_jac(h, veh, tp, u, mu,
 *  sd, G): the same z, G and statuses, bit for bit (@p z, @p G written only on RFE_OK). In
 *  the load-scaled modes with the set-up's tyre parameters the nominal forces are the ones the
 *  derivative evaluates anyway (rfe_tyre_pre_jac's and rfe_tyre_magic_basis's fx, fy are the
 *  operations of rfe_tyre_dugoff_abs_pre), so each wheel's tyre is evaluated once (issue 21:
 *  the Magic Formula's four curve pairs at the nominal friction); otherwise the two calls.
 *  On RFE_OK in that case the four wheels' forces at @p mu are kept in h (memo_*) for
 *  rfe_meas_eval, which takes a kept force for a wheel whose friction it is given again (issue
 *  21: the cubature points that leave a state at the predicted mean; rfe_meas_eval's results
 *  and statuses unchanged, bit for bit). */
RFE_NODISCARD rfe_status_t rfe_meas_nominal_input_jac(
    rfe_meas_t *h, const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
    const rfe_sample_t *u, const rfe_real_t mu[RFE_WHEELS], const rfe_real_t sd[RFE_INPUTS],
    rfe_real_t z[RFE_MEAS], rfe_real_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS]);

#endif /* RFE_MEAS_INTERNAL_H */
