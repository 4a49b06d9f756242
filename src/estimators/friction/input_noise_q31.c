/**
 * @file input_noise_q31.c
 * @brief The fixed-point friction estimator's per-step input uncertainties
 *        (rfe_friction_set_input_noise_q31; twin of input_noise_flt.c), for inputs that are
 *        estimates themselves (docs/OBSERVER.md §6). Integer operations only.
 */
#include "rfe/friction_q31.h"

#include "numerics/internal_q31.h"

rfe_status_t rfe_friction_set_input_noise_q31(rfe_friction_q31_t *est, rfe_fix_t sd_in_vx,
                                              rfe_fix_t sd_in_vy, rfe_fix_t r_yaw_acc)
{
    if (est == NULL) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if ((sd_in_vx < 0) || (sd_in_vy < 0) || (r_yaw_acc <= 0)) {
        return RFE_ERR_RANGE;
    }
    est->params.filter.sd_in_vx = sd_in_vx;
    est->params.filter.sd_in_vy = sd_in_vy;
    est->params.filter.r_yaw_acc = r_yaw_acc;
    return RFE_OK;
}
