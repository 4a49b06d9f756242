/**
 * @file meas_internal.h
 * @brief Private per-wheel pieces of the absolute-mode measurement model (meas_flt.c) for the
 *        step noise (eiv_flt.c). Not installed.
 *
 * In absolute tyre mode rfe_meas_eval's z is the sum, in wheel order from 0, of each wheel's
 * terms (body-axis force over m, yaw moment over J: the entries rfe_obsmat_build would put
 * in its column), rejected when not finite. A caller may keep the terms of the wheels an
 * input change does not touch and sum them with the others in the same order: the same bits.
 */
#ifndef RFE_MEAS_INTERNAL_H
#define RFE_MEAS_INTERNAL_H

#include <stddef.h>

#include "rfe/component/meas.h"
#include "rfe/params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_meas_wheel_terms rfe_meas_wheel_terms_f64
#define rfe_meas_sum_terms   rfe_meas_sum_terms_f64
#else
#define rfe_meas_wheel_terms rfe_meas_wheel_terms_f32
#define rfe_meas_sum_terms   rfe_meas_sum_terms_f32
#endif

/** The four wheels' terms side by side (wheel i at i RFE_MEAS). */
#define RFE_MEAS_COLS ((size_t)RFE_WHEELS * (size_t)RFE_MEAS)

/** Wheel @p i's terms of z from its forces @p fx, @p fy (wheel axes) and c, s = cos, sin of
 *  delta (ignored for the rear wheels). */
void rfe_meas_wheel_terms(const rfe_vehicle_t *veh, rfe_real_t c, rfe_real_t s, size_t i,
                          rfe_real_t fx, rfe_real_t fy, rfe_real_t t[RFE_MEAS]);

/** z = the sums of the four wheels' terms in wheel order from 0.
 *  @return RFE_OK; RFE_ERR_NONFINITE when a sum is not finite (@p z then untouched). */
RFE_NODISCARD rfe_status_t rfe_meas_sum_terms(const rfe_real_t t[RFE_MEAS_COLS],
                                             rfe_real_t z[RFE_MEAS]);

#endif /* RFE_MEAS_INTERNAL_H */
