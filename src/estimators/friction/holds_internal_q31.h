/**
 * @file holds_internal_q31.h
 * @brief Private entry of the fixed-point step 9's holds (holds_q31.c) for friction_q31.c. Not
 *        installed; integer operations only.
 */
#ifndef RFE_HOLDS_INTERNAL_Q31_H
#define RFE_HOLDS_INTERNAL_Q31_H

#include "rfe/friction_q31.h"

/**
 * rfe_friction_holds_update in integers (holds_internal.h): @p vx Q23, saturations into
 * est->step_sat. Preconditions (not checked): @p est initialised, its step succeeded. Cannot
 * fail.
 */
void rfe_friction_holds_update_q31(rfe_friction_q31_t *est, rfe_fix_t vx, uint32_t missed);

#endif /* RFE_HOLDS_INTERNAL_Q31_H */
