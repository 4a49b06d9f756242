/**
 * @file params_conv.h
 * @brief Real-valued parameters (rfe_params_t) to the fixed-point ones (rfe_params_q31_t):
 *        part of the float and double libraries (host tools, calibration, tests), never of
 *        the fixed-point library.
 */
#ifndef RFE_PARAMS_CONV_H
#define RFE_PARAMS_CONV_H

#include "rfe/mass_grade_params.h"
#include "rfe/mass_grade_params_q31.h"
#include "rfe/params.h"
#include "rfe/params_q31.h"
#include "rfe/velocity_params.h"
#include "rfe/velocity_params_q31.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_params_to_q31 rfe_params_to_q31_f64
#define rfe_velocity_params_to_q31 rfe_velocity_params_to_q31_f64
#define rfe_mass_grade_params_to_q31 rfe_mass_grade_params_to_q31_f64
#else
#define rfe_params_to_q31 rfe_params_to_q31_f32
#define rfe_velocity_params_to_q31 rfe_velocity_params_to_q31_f32
#define rfe_mass_grade_params_to_q31 rfe_mass_grade_params_to_q31_f32
#endif

/**
 * Converts @p p to Q formats (params_q31.h), each value rounded to nearest (ties away from
 * zero), and computes the derived constants from the real values (in double precision in
 * both builds, then rounded once).
 * @return RFE_OK;
 *         RFE_ERR_NULL if a pointer is NULL;
 *         RFE_ERR_PARAM if rfe_params_validate(p) fails;
 *         RFE_ERR_RANGE if a value (base or derived) does not fit its format: it rounds beyond
 *         +-INT32_MAX, a nonzero value rounds to 0 (an "off" switch must not be created by
 *         rounding), or a value that rfe_params_validate_q31 requires to carry 16 significant
 *         bits has fewer (see there), or alpha_max rounds to 1.5 rad or more, or a monitor
 *         weight is below 2^-14 (tau > 16383 dt) or a quantile above 8 (p < ~1e-15).
 *         The monitor's constants are those of rfe_monitor_init at the filter's dt.
 *         On error @p q is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_params_to_q31(const rfe_params_t *p, rfe_params_q31_t *q);

/**
 * Converts the observer's parameters @p p to Q formats (velocity_params_q31.h), each value
 * rounded to nearest like rfe_params_to_q31 (the same rounding, one converter).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM if rfe_velocity_params_validate(p) fails;
 *         RFE_ERR_RANGE if a value rounds beyond +-INT32_MAX or a nonzero value rounds to 0.
 *         On error @p q is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_params_to_q31(const rfe_velocity_params_t *p,
                                                      rfe_velocity_params_q31_t *q);

/**
 * Converts the mass and grade estimator's parameters @p p to Q formats
 * (mass_grade_params_q31.h; pressures from Pa to MPa), each value rounded to nearest like
 * rfe_params_to_q31.
 * The fixed-point domain beyond the formats (n + lambda in (1, 16), w_c,0 in [0, 4)) is
 * rfe_mass_grade_params_validate_q31's, in the fixed-point library: rfe_mass_grade_init_q31
 * refuses a converted set outside it.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM if rfe_mass_grade_params_validate(p) fails;
 *         RFE_ERR_RANGE if a value rounds beyond +-INT32_MAX or a nonzero value rounds to 0
 *         (m_max >= 131072 kg, dt_max >= 2 s, t_brake >= 128 s, f_r >= 0.031 s/m, ...).
 *         On error @p q is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_params_to_q31(const rfe_mass_grade_params_t *p,
                                                        rfe_mass_grade_params_q31_t *q);

#endif /* RFE_PARAMS_CONV_H */
