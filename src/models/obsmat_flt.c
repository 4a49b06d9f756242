/**
 * @file obsmat_flt.c
 * @brief Observation matrix H(u) of MODEL.md §5 and h(x, u) = H x.
 */
#include "rfe/component/obsmat.h"

#include "numerics/internal.h"
#include "models/vehicle.h"

rfe_status_t rfe_obsmat_build(const rfe_vehicle_t *veh, rfe_real_t delta,
                              const rfe_real_t fx[RFE_WHEELS],
                              const rfe_real_t fy[RFE_WHEELS],
                              rfe_real_t H[RFE_H_SIZE])
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    rfe_real_t c;
    rfe_real_t s;
    size_t i;

    if ((veh == NULL) || (fx == NULL) || (fy == NULL) || (H == NULL)) {
        return RFE_ERR_NULL;
    }
    if (!rfe_is_finite(delta) || !rfe_all_finite(fx, RFE_WHEELS) ||
        !rfe_all_finite(fy, RFE_WHEELS)) {
        return RFE_ERR_NONFINITE;
    }
    rfe_wheel_positions(veh, px, py);
    c = RFE_COS(delta);
    s = RFE_SIN(delta);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        /* Front wheels are rotated by delta into body axes, rear wheels are not. */
        const rfe_real_t ci = (i < (size_t)RFE_RL) ? c : RFE_R(1.0);
        const rfe_real_t si = (i < (size_t)RFE_RL) ? s : RFE_R(0.0);
        const rfe_real_t fbx = (fx[i] * ci) - (fy[i] * si);
        const rfe_real_t fby = (fx[i] * si) + (fy[i] * ci);
        /* Column i: [Fbx/m, Fby/m, (x_i Fby - y_i Fbx)/J]. */
        H[RFE_H_AT(0, i)] = fbx / veh->m;
        H[RFE_H_AT(1, i)] = fby / veh->m;
        H[RFE_H_AT(2, i)] = ((px[i] * fby) - (py[i] * fbx)) / veh->J;
    }
    return RFE_OK;
}

rfe_status_t rfe_obsmat_apply(const rfe_real_t H[RFE_H_SIZE],
                              const rfe_real_t x[RFE_WHEELS], rfe_real_t y[RFE_MEAS])
{
    size_t r;
    size_t i;

    if ((H == NULL) || (x == NULL) || (y == NULL)) {
        return RFE_ERR_NULL;
    }
    if (!rfe_all_finite(H, RFE_H_SIZE) ||
        !rfe_all_finite(x, RFE_WHEELS)) {
        return RFE_ERR_NONFINITE;
    }
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        rfe_real_t acc = RFE_R(0.0);
        for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
            acc += H[RFE_H_AT(r, i)] * x[i];
        }
        y[r] = acc;
    }
    return RFE_OK;
}
