/**
 * @file vehicle.h
 * @brief Private vehicle geometry shared by the floating-point models (tyre_flt.c,
 *        obsmat_flt.c, meas_flt.c; not installed): where the wheels sit (MODEL.md §1).
 */
#ifndef RFE_MODELS_VEHICLE_H
#define RFE_MODELS_VEHICLE_H

#include "rfe/params.h"

#include "numerics/internal.h"

/* Wheel positions relative to the CoG (MODEL.md §1): front x = +Lf, rear x = -Lr,
 * left y = +B/2, right y = -B/2. */
static inline void rfe_wheel_positions(const rfe_vehicle_t *veh, rfe_real_t px[RFE_WHEELS],
                                       rfe_real_t py[RFE_WHEELS])
{
    px[RFE_FL] = veh->Lf;
    px[RFE_FR] = veh->Lf;
    px[RFE_RL] = -veh->Lr;
    px[RFE_RR] = -veh->Lr;
    py[RFE_FL] = RFE_R(0.5) * veh->Bf;
    py[RFE_FR] = RFE_R(-0.5) * veh->Bf;
    py[RFE_RL] = RFE_R(0.5) * veh->Br;
    py[RFE_RR] = RFE_R(-0.5) * veh->Br;
}

#endif /* RFE_MODELS_VEHICLE_H */
