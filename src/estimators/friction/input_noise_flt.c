/**
 * @file input_noise_flt.c
 * @brief The friction estimator's per-step input uncertainties (rfe_friction_set_input_noise),
 *        for inputs that are estimates themselves (docs/OBSERVER.md §6).
 */
#include "rfe/friction.h"

#include "numerics/internal.h"

rfe_status_t rfe_friction_set_input_noise(rfe_friction_t *est, rfe_real_t sd_in_vx,
                                          rfe_real_t sd_in_vy, rfe_real_t r_yaw_acc)
{
    if (est == NULL) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (!rfe_is_finite(sd_in_vx) || !rfe_is_finite(sd_in_vy) || !rfe_is_finite(r_yaw_acc) ||
        !(sd_in_vx >= RFE_R(0.0)) || !(sd_in_vy >= RFE_R(0.0)) || !(r_yaw_acc > RFE_R(0.0))) {
        return RFE_ERR_RANGE;
    }
    est->params.filter.sd_in_vx = sd_in_vx;
    est->params.filter.sd_in_vy = sd_in_vy;
    est->params.filter.r_yaw_acc = r_yaw_acc;
    return RFE_OK;
}
