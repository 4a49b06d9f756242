/**
 * @file vehicle_mass_q31.c
 * @brief The fixed-point friction estimator's vehicle mass set at run time
 *        (rfe_friction_set_mass_q31; twin of vehicle_mass_flt.c). Integer operations only.
 */
#include "rfe/friction_q31.h"

#include "numerics/internal_q31.h"

rfe_status_t rfe_friction_set_mass_q31(rfe_friction_q31_t *est, rfe_fix_t m)
{
    if (est == NULL) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    /* rfe_params_set_mass_q31 recomputes the mass's constants and validates the whole set;
     * a mass it refuses leaves the set, and so the estimator, untouched */
    return (rfe_params_set_mass_q31(&est->params, m) == RFE_OK) ? RFE_OK : RFE_ERR_RANGE;
}
