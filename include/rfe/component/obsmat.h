/**
 * @file obsmat.h
 * @brief Observation matrix H(u) (MODEL.md §5): y = [ax, ay, r-dot] = H(u) x.
 *
 * Column i is wheel i's body-axis force per unit mu divided by m (rows 1, 2) and its yaw
 * moment x_i*Fby - y_i*Fbx divided by J (row 3). Matrices are row-major flat arrays.
 */
#ifndef RFE_OBSMAT_H
#define RFE_OBSMAT_H

#include "rfe/params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_obsmat_build rfe_obsmat_build_f64
#define rfe_obsmat_apply rfe_obsmat_apply_f64
#else
#define rfe_obsmat_build rfe_obsmat_build_f32
#define rfe_obsmat_apply rfe_obsmat_apply_f32
#endif

/** Element (row, wheel) of a row-major 3x4 H. */
#define RFE_H_AT(row, wheel) (((size_t)(row) * (size_t)RFE_WHEELS) + (size_t)(wheel))
/** Number of elements of H (RFE_MEAS x RFE_WHEELS). */
#define RFE_H_SIZE ((size_t)RFE_MEAS * (size_t)RFE_WHEELS)

/**
 * Builds H (3x4, row-major) from the wheel-axis forces per unit mu (paper mode: F0x, F0y),
 * rotating the front wheels by delta. Passing absolute forces instead gives the
 * matrix whose row sums are the accelerations those forces cause (used by absolute mode).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE.
 */
RFE_NODISCARD rfe_status_t rfe_obsmat_build(const rfe_vehicle_t *veh, rfe_real_t delta,
                                           const rfe_real_t fx[RFE_WHEELS],
                                           const rfe_real_t fy[RFE_WHEELS],
                                           rfe_real_t H[RFE_H_SIZE]);

/** h(x, u) = H x: predicted [ax, ay, r-dot] for the friction vector @p x. */
RFE_NODISCARD rfe_status_t rfe_obsmat_apply(const rfe_real_t H[RFE_H_SIZE],
                                           const rfe_real_t x[RFE_WHEELS],
                                           rfe_real_t y[RFE_MEAS]);

#endif /* RFE_OBSMAT_H */
