/**
 * @file meas_inputs.h
 * @brief Private, shared by both number types (meas_flt.c, meas_q31.c; no real type in it):
 *        which wheels a perturbed input of the sample reaches (the inputs RFE_IN_* of
 *        rfe/common.h). Not installed.
 *
 * h(mu, u) is the sum, in wheel order, of four per-wheel terms, each a function of that
 * wheel's kinematics, its load and cos/sin of delta. The loads depend on ax, ay only (never
 * perturbed); delta reaches the front wheels' kinematics and terms, vx, vy and r every
 * wheel, omega_w only wheel w's kappa. A perturbed h therefore reuses the nominal terms of
 * every other wheel.
 */
#ifndef RFE_MODELS_MEAS_INPUTS_H
#define RFE_MODELS_MEAS_INPUTS_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"

/** 1 when input @p j (RFE_IN_*, below RFE_INPUTS) reaches wheel @p i: bit i of the input's
 *  mask (wheels in the order fl, fr, rl, rr). */
static inline int rfe_input_reaches(size_t j, size_t i)
{
    static const uint8_t wheel_mask[RFE_INPUTS] = {0x3u, 0xFu, 0xFu, 0xFu,
                                                   0x1u, 0x2u, 0x4u, 0x8u};
    return ((((uint32_t)wheel_mask[j] >> i) & 1u) != 0u) ? 1 : 0;
}

#endif /* RFE_MODELS_MEAS_INPUTS_H */
