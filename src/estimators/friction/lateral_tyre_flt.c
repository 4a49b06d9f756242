/**
 * @file lateral_tyre_flt.c
 * @brief The friction estimator's lateral tyre curve set at run time
 *        (rfe_friction_set_lateral_tyre), for a curve that is identified online (the tyre
 *        identifier, docs/TYRE_ID.md §14).
 */
#include "rfe/friction.h"

#include "numerics/internal.h"

rfe_status_t rfe_friction_set_lateral_tyre(rfe_friction_t *est, rfe_real_t cy, rfe_real_t shape_Cy,
                                           rfe_real_t shape_Ey, rfe_real_t r_model_rel)
{
    const rfe_real_t v[4] = {cy, shape_Cy, shape_Ey, r_model_rel};
    if (est == NULL) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (rfe_all_finite(v, 4u) == 0) {
        return RFE_ERR_NONFINITE;
    }
    /* values the validation accepts keep the set valid; anything else is refused untouched */
    return (rfe_params_set_lateral_tyre(&est->params, cy, shape_Cy, shape_Ey, r_model_rel) == RFE_OK)
               ? RFE_OK
               : RFE_ERR_RANGE;
}
