/**
 * @file holds_internal_q31.h
 * @brief Private entry of the fixed-point step 9's holds (holds_q31.c) for friction_q31.c. Not
 *        installed; integer operations only.
 */
#ifndef RFE_HOLDS_INTERNAL_Q31_H
#define RFE_HOLDS_INTERNAL_Q31_H

#include "rfe/friction_q31.h"

/**
 * rfe_friction_yaw_check in integers (holds_internal.h): the prediction in Q27, saturated to
 * the format (a count into est->step_sat). Preconditions (not checked): @p est initialised,
 * @p sample checked (step 0). Cannot fail.
 */
void rfe_friction_yaw_check_q31(rfe_friction_q31_t *est, const rfe_sample_q31_t *sample,
                                rfe_sample_q31_t *u, uint32_t periods);

/**
 * rfe_friction_holds_update in integers (holds_internal.h), saturations into est->step_sat.
 * Preconditions (not checked): @p est initialised, its step succeeded. Cannot fail.
 */
void rfe_friction_holds_update_q31(rfe_friction_q31_t *est, const rfe_sample_q31_t *sample,
                                   const rfe_sample_q31_t *u, uint32_t periods);

#endif /* RFE_HOLDS_INTERNAL_Q31_H */
