/**
 * @file friction_monitor_q31.c
 * @brief The model-validity monitor inside the fixed-point friction estimator
 *        (friction_monitor_q31.h, docs/MONITOR.md §2): its step on the step's innovation and
 *        its effect on the estimate. A unit of its own, so that its locals are no part of
 *        rfe_friction_step_q31's frame, which lies on the estimator's deepest call path (the
 *        Cortex-M0+ stack budget). Integer operations only.
 */
#include "estimators/friction/friction_monitor_q31.h"

#include "estimators/friction/friction_logic.h"
#include "numerics/internal_q31.h"

/* The monitor's step on this step's innovation (docs/MONITOR.md §2), after steps 7-8 so that
 * nothing fails after it: S_zz repacked in place to ld RFE_MEAS (each entry moves to a lower
 * index, read before it is overwritten), the persistent diagonal = the step noise's + the
 * state's (diag Zc Zc^T, Q24, >= 0, to Q48): below 3 2^62 + 2^55 < 2^64 (step_noise_pers_q31.c),
 * so the uint64 sum cannot wrap. */
rfe_status_t rfe_friction_monitor_step_q31(rfe_friction_q31_t *est)
{
    rfe_sckf_innov_q31_t *in = &est->innov;
    size_t r;
    size_t j;
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        for (j = 0u; j < (size_t)RFE_MEAS; ++j) {
            in->Szz[(r * (size_t)RFE_MEAS) + j] = in->Szz[(r * (size_t)RFE_M_MAX) + j];
        }
        if (in->zz[r] > 0) {
            est->pers[r] += (uint64_t)in->zz[r] << (RFE_MON_Q31_QP - (unsigned int)RFE_FIX_Q_ACC);
        }
    }
    return rfe_monitor_step_q31(&est->mon, in->nu, in->Szz, est->pers, NULL, &est->step_sat);
}

/* docs/MONITOR.md §2 item 7: while the monitor is on and fired, every flag 0 and the sd
 * inflated (Q30, saturating: an sd beyond 2 is counted in *count). */
int rfe_friction_monitor_effect_q31(const rfe_friction_q31_t *est, rfe_estimate_q31_t *out,
                                    uint32_t *count)
{
    /* (mu_max - mu_min) / 2 in Q30 is mu_max - mu_min in Q29: no friction distribution
     * inside the bounds has a larger sd (Popoviciu's inequality); below 2, so it fits Q30 */
    const rfe_fix_t cap = est->params.filter.mu_max - est->params.filter.mu_min;
    rfe_fix_t c = RFE_MON_Q31_ONE_F;
    rfe_status_t inflated;
    int any_valid = 0;
    size_t i;
    if ((est->params.monitor.enable == 0u) || (est->mon.fired == 0u)) {
        return -1;
    }
    /* the monitor is initialised with the estimator: this cannot fail (c stays 1 if it did) */
    inflated = rfe_monitor_inflation_q31(&est->mon, &c);
    (void)inflated;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if (out->valid[i] != 0u) {
            any_valid = 1;
        }
        /* sd c >= cap, compared before the product is narrowed: nothing saturates there */
        const int64_t wide = (int64_t)out->sd[i] * (int64_t)c;
        out->valid[i] = 0u;
        if (wide >= ((int64_t)cap * (int64_t)RFE_MON_Q31_ONE_F)) {
            out->sd[i] = cap;
        } else {
            out->sd[i] = rfe_fix_mul(out->sd[i], c, RFE_MON_Q31_QF, count);
        }
    }
    return any_valid;
}

/* After step 9, at every step while fired (a rejected sample still reports the previous
 * estimate): the effect, its saturations counted in the step's and the running counts, and
 * the status of a step that evaluated the model says so. */
void rfe_friction_monitor_apply_q31(rfe_friction_q31_t *est, rfe_estimate_q31_t *out)
{
    uint32_t count = 0u;
    const int any_valid = rfe_friction_monitor_effect_q31(est, out, &count);
    if (any_valid < 0) {
        return;
    }
    if (rfe_friction_monitor_applies(out->status) != 0) {
        out->status = rfe_friction_monitor_status(out->status, any_valid);
    }
    /* a rejected step reports sat 0: its inflation repeats the previous step's, counted there */
    if (rfe_status_is_error(out->status) == 0) {
        rfe_q31_sat_add(&out->sat, count);
        rfe_q31_sat_add(&est->sat, count);
    }
}
