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
#define rfe_friction_yaw_check rfe_friction_yaw_check_f64
#else
#define rfe_friction_holds_update rfe_friction_holds_update_f32
#define rfe_friction_yaw_check rfe_friction_yaw_check_f32
#endif

/**
 * Step 0b, the yaw-rate input check (docs/ESTIMATOR.md): *u = *sample, its yaw rate replaced by
 * the last accepted one advanced by the measured yaw acceleration over dt (trapezoidal) when
 * it differs from that prediction by more than yaw_check. Checks nothing when yaw_check = 0,
 * at the first sample and after a gap (@p periods > 0). Preconditions (not checked): @p est
 * initialised, @p sample checked (step 0). Cannot fail.
 */
void rfe_friction_yaw_check(const rfe_friction_t *est, const rfe_sample_t *sample,
                            rfe_sample_t *u, uint32_t periods);

/**
 * Step 9's state after steps 1-8 of an accepted @p sample, @p u the step's (its yaw rate
 * checked; docs/ESTIMATOR.md): the accepted yaw rate and yaw acceleration (the next yaw-rate
 * check's; it restarts after a replaced sample), the stale-wheel-speed rule
 * (stale_omega > 0) into est->hold.stale, then over the distance max(vx, 0) dt (periods + 1),
 * the rear wheels' hold (rear_hold_k > 0) and the jump hold (jump_hold_k > 0) of each side,
 * their flags into est->hold.held (nothing with the structure wheels or with both thresholds
 * 0). Preconditions (not checked): @p est initialised, its step succeeded. Cannot fail.
 */
void rfe_friction_holds_update(rfe_friction_t *est, const rfe_sample_t *sample,
                               const rfe_sample_t *u, uint32_t periods);

#endif /* RFE_HOLDS_INTERNAL_H */
