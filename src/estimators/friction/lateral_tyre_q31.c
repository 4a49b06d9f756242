/**
 * @file lateral_tyre_q31.c
 * @brief The fixed-point friction estimator's lateral tyre curve set at run time
 *        (rfe_friction_set_lateral_tyre_q31; twin of lateral_tyre_flt.c). Integer operations
 *        only.
 */
#include "rfe/friction_q31.h"

#include "numerics/internal_q31.h"

rfe_status_t rfe_friction_set_lateral_tyre_q31(rfe_friction_q31_t *est, rfe_fix_t cy,
                                               rfe_fix_t shape_Cy, rfe_fix_t shape_Ey,
                                               rfe_fix_t r_model_rel)
{
    if (est == NULL) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    /* rfe_params_set_lateral_tyre_q31 validates the whole set; values it refuses leave the
     * set, and so the estimator, untouched */
    return (rfe_params_set_lateral_tyre_q31(&est->params, cy, shape_Cy, shape_Ey, r_model_rel) ==
            RFE_OK)
               ? RFE_OK
               : RFE_ERR_RANGE;
}
