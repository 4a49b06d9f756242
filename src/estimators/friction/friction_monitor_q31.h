/**
 * @file friction_monitor_q31.h
 * @brief Private entries of the fixed-point estimator's monitor wiring (friction_monitor_q31.c)
 *        for friction_q31.c. Not installed; integer operations only.
 */
#ifndef RFE_FRICTION_MONITOR_Q31_H
#define RFE_FRICTION_MONITOR_Q31_H

#include "rfe/friction_q31.h"

/**
 * The monitor's step on the step's innovation in est->innov and the persistent diagonal in
 * est->pers (both scratch, consumed here): S_zz repacked in place to ld RFE_MEAS, the
 * persistent diagonal the step noise's plus diag(Zc Zc^T); saturations into est->step_sat.
 * Precondition: the monitor is on and this step evaluated the model (SCKF).
 * @return the status of rfe_monitor_step_q31 (the monitor untouched on an error).
 */
rfe_status_t rfe_friction_monitor_step_q31(rfe_friction_q31_t *est);

/**
 * The monitor's effect on an estimate (docs/MONITOR.md §2 item 7): while the monitor is on and
 * fired, every flag 0 and the sd inflated (Q30, saturating; saturations added to *count).
 * @return -1 when the monitor is off or not fired (out untouched); else 1 when a flag was 1
 *         before, 0 when none was.
 */
int rfe_friction_monitor_effect_q31(const rfe_friction_q31_t *est, rfe_estimate_q31_t *out,
                                    uint32_t *count);

/**
 * After step 9: while the monitor is on and fired, every flag is 0 and the sd is inflated at
 * every step (Q30, saturating; counted in out->sat and est->sat unless the step is an error,
 * whose output repeats the previous estimate with sat 0), and the status of a step that
 * evaluated the model says so (rfe_friction_monitor_status).
 */
void rfe_friction_monitor_apply_q31(rfe_friction_q31_t *est, rfe_estimate_q31_t *out);

#endif /* RFE_FRICTION_MONITOR_Q31_H */
