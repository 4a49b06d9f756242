/**
 * @file vehicle_mass_flt.c
 * @brief The friction estimator's vehicle mass set at run time (rfe_friction_set_mass), for a
 *        mass that is estimated online (docs/MASS_GRADE.md §10).
 */
#include "rfe/friction.h"

#include "numerics/internal.h"

rfe_status_t rfe_friction_set_mass(rfe_friction_t *est, rfe_real_t m)
{
    if (est == NULL) {
        return RFE_ERR_NULL;
    }
    if (est->magic != RFE_MAGIC_EST) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (!rfe_is_finite(m)) {
        return RFE_ERR_NONFINITE;
    }
    /* a finite mass > 0 keeps the validated set valid; anything else is refused untouched */
    return (rfe_params_set_mass(&est->params, m) == RFE_OK) ? RFE_OK : RFE_ERR_RANGE;
}
