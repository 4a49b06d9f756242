/**
 * @file conditioner_flt.c
 * @brief Complementary filter for vx, vy (docs/ESTIMATOR.md step 1).
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_CONDITIONER_IMPL
#include "rfe/component/conditioner.h"

#include "numerics/internal.h"

rfe_status_t rfe_conditioner_init(rfe_conditioner_t *c, size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*c)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if (c == NULL) {
        return RFE_ERR_NULL;
    }
    c->started = 0u;
    c->vx = RFE_R(0.0);
    c->vy = RFE_R(0.0);
    c->magic = RFE_MAGIC_COND;
    return RFE_OK;
}

/* Argument checks of rfe_conditioner_step, in the order of its documented statuses. */
static rfe_status_t check_step(const rfe_conditioner_t *c, rfe_real_t dt, rfe_real_t tau_v,
                               const rfe_sample_t *in, const rfe_sample_t *out)
{
    if ((c == NULL) || (in == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (c->magic != RFE_MAGIC_COND) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (!rfe_is_finite(dt) || !(dt > RFE_R(0.0)) || !rfe_is_finite(tau_v) ||
        !(tau_v >= RFE_R(0.0))) {
        return RFE_ERR_PARAM;
    }
    if (!rfe_is_finite(in->vx) || !rfe_is_finite(in->vy) || !rfe_is_finite(in->ax) ||
        !rfe_is_finite(in->ay) || !rfe_is_finite(in->yaw_rate)) {
        return RFE_ERR_NONFINITE;
    }
    return RFE_OK;
}

rfe_status_t rfe_conditioner_step(rfe_conditioner_t *c, rfe_real_t dt, rfe_real_t tau_v,
                                  const rfe_sample_t *in, rfe_sample_t *out)
{
    rfe_real_t vx;
    rfe_real_t vy;
    const rfe_status_t st = check_step(c, dt, tau_v, in, out);
    if (st != RFE_OK) {
        return st;
    }
    if (tau_v == RFE_R(0.0)) {
        *out = *in; /* off */
        return RFE_OK;
    }
    if (c->started == 0u) {
        vx = in->vx; /* the first accepted sample initialises */
        vy = in->vy;
    } else {
        const rfe_real_t b = dt / (tau_v + dt);
        /* Predict with the accelerometer and the yaw rate (both from the old state), then
         * blend in the measured speeds. */
        const rfe_real_t px = c->vx + (dt * (in->ax + (in->yaw_rate * c->vy)));
        const rfe_real_t py = c->vy + (dt * (in->ay - (in->yaw_rate * c->vx)));
        vx = ((RFE_R(1.0) - b) * px) + (b * in->vx);
        vy = ((RFE_R(1.0) - b) * py) + (b * in->vy);
    }
    if (!rfe_is_finite(vx) || !rfe_is_finite(vy)) {
        return RFE_ERR_NONFINITE;
    }
    *out = *in;
    out->vx = vx;
    out->vy = vy;
    c->vx = vx;
    c->vy = vy;
    c->started = 1u;
    return RFE_OK;
}
