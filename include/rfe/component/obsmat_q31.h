/**
 * @file obsmat_q31.h
 * @brief Fixed-point twin of rfe/component/obsmat.h: the observation matrix H(u) (MODEL.md §5) and
 *        h(x, u) = H x on int32 Q values (docs/FIXED_POINT.md, "Tyre, kinematics and
 *        observation matrix").
 *
 * Column i of H is wheel i's body-axis force per unit mu divided by m (rows 1, 2) and its yaw
 * moment x_i Fby - y_i Fbx divided by J (row 3), from the precomputed 1/m, x_i/J and y_i/J of
 * rfe_vehicle_q31_t. H is row-major 3 x 4 (the layout of rfe/component/obsmat.h: element (row, wheel)
 * at RFE_H_Q31_AT(row, wheel)), entries in Q24 [m/s^2 or rad/s^2 per unit mu, +-128].
 * Saturation: one count in `*sat` per clamped output element; no intermediate saturates.
 * On an error nothing is written.
 */
#ifndef RFE_OBSMAT_Q31_H
#define RFE_OBSMAT_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"
#include "rfe/fixed.h"
#include "rfe/params_q31.h"

/** Element (row, wheel) of a row-major 3x4 H (same layout as RFE_H_AT of rfe/component/obsmat.h). */
#define RFE_H_Q31_AT(row, wheel) (((size_t)(row) * (size_t)RFE_WHEELS) + (size_t)(wheel))
/** Number of elements of H (RFE_MEAS x RFE_WHEELS). */
#define RFE_H_Q31_SIZE ((size_t)RFE_MEAS * (size_t)RFE_WHEELS)

/**
 * Builds H (Q24) from the wheel-axis forces per unit mu (paper mode: F0x, F0y, Q15), rotating
 * the front wheels by @p delta (Q29). Passing absolute forces gives the matrix whose row sums
 * are the accelerations those forces cause (absolute mode).
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_obsmat_build_q31(const rfe_vehicle_q31_t *veh, rfe_fix_t delta,
                                                const rfe_fix_t fx[RFE_WHEELS],
                                                const rfe_fix_t fy[RFE_WHEELS],
                                                rfe_fix_t H[RFE_H_Q31_SIZE], uint32_t *sat);

/**
 * y = H x: predicted [ax, ay, r-dot] (Q24) for the friction vector @p x (Q29). Each y_r is
 * the exactly rounded sum of the exact products (error <= 0.5 LSB of Q24).
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_obsmat_apply_q31(const rfe_fix_t H[RFE_H_Q31_SIZE],
                                                const rfe_fix_t x[RFE_WHEELS],
                                                rfe_fix_t y[RFE_MEAS], uint32_t *sat);

#endif /* RFE_OBSMAT_Q31_H */
