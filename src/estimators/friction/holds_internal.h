/**
 * @file holds_internal.h
 * @brief Private entry of step 9's holds (holds_flt.c) for the estimator (friction_flt.c).
 *        Not installed.
 */
#ifndef RFE_HOLDS_INTERNAL_H
#define RFE_HOLDS_INTERNAL_H

#include "rfe/friction.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_friction_holds_update rfe_friction_holds_update_f64
#else
#define rfe_friction_holds_update rfe_friction_holds_update_f32
#endif

/**
 * Step 9's holds after steps 1-8 of an accepted sample (docs/ESTIMATOR.md): over the distance
 * max(vx, 0) dt (missed + 1), the rear wheels' hold (rear_hold_k > 0) and the jump hold
 * (jump_hold_k > 0) of each side, their flags into est->hold.held. Nothing with the structure
 * wheels or with both thresholds 0. Preconditions (not checked): @p est initialised, its step
 * succeeded. Cannot fail.
 */
void rfe_friction_holds_update(rfe_friction_t *est, rfe_real_t vx, uint32_t missed);

#endif /* RFE_HOLDS_INTERNAL_H */
