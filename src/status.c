/**
 * @file status.c
 * @brief Names of the status codes (precision-independent: compiled once per library).
 */
#include "rfe/types.h"

const char *rfe_status_str(rfe_status_t s)
{
    const char *name;
    switch (s) {
    case RFE_OK: name = "ok"; break;
    case RFE_PROJECTED: name = "projected onto [mu_min, mu_max]"; break;
    case RFE_NO_UPDATE_LOW_SPEED: name = "no update: speed below v_est_min"; break;
    case RFE_ERR_NULL: name = "null pointer"; break;
    case RFE_ERR_NONFINITE: name = "non-finite input"; break;
    case RFE_ERR_RANGE: name = "input out of range"; break;
    case RFE_ERR_PARAM: name = "invalid parameter"; break;
    case RFE_ERR_SIZE: name = "dimension exceeds compile-time maximum"; break;
    case RFE_ERR_NOT_POSITIVE_DEFINITE: name = "matrix not positive definite"; break;
    case RFE_ERR_NOT_INITIALISED: name = "not initialised"; break;
    default: name = "unknown status"; break;
    }
    return name;
}
