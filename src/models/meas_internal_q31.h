/**
 * @file meas_internal_q31.h
 * @brief Private per-wheel piece of the fixed-point measurement model (meas_q31.c) for the
 *        step noise (eiv_q31.c). Not installed; integer operations only.
 *
 * In the load-scaled tyre modes (absolute Dugoff, Magic Formula), h(mu, u) is
 * z_r = sat(sum_i col_i,r) (exact int64 sum of the four wheels' columns): the column of H
 * (MODEL.md §5) that wheel i's forces F(mu_i) give, with
 * the entries rfe_obsmat_build_q31 computes, bit for bit. A caller may therefore reuse the
 * columns of the wheels an input change does not touch.
 */
#ifndef RFE_MEAS_INTERNAL_Q31_H
#define RFE_MEAS_INTERNAL_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/fixed.h"
#include "rfe/component/meas_q31.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre_q31.h"

/** Entries of the four wheels' columns side by side (wheel i at i RFE_MEAS). */
#define RFE_MEAS_Q31_COLS ((size_t)RFE_WHEELS * (size_t)RFE_MEAS)

/** Column @p i (Q24, RFE_MEAS entries) of wheel @p i from its friction-independent tyre
 *  terms @p pre (of rfe_tyre_dugoff_pre_q31 at @p tp), friction @p mu (Q29), load @p fz (Q15,
 *  >= 0) and c, s = cos, sin of delta (Q30; ignored for the rear wheels); the forces of
 *  tp->mode's curve (rfe_tyre_magic_mu_q31 in magic mode, rfe_tyre_dugoff_mu_q31
 *  otherwise, as rfe_tyre_forces_abs_q31; @p tp passed rfe_tyre_abs_params_ok_q31); saturations (forces, entries)
 *  counted in *sat. */
void rfe_meas_wheel_column_q31(const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
                               const rfe_dugoff_pre_q31_t *pre, rfe_fix_t mu, rfe_fix_t fz,
                               int32_t c, int32_t s, size_t i, rfe_fix_t col[RFE_MEAS],
                               uint32_t *sat);

/** z_r = the saturated sum of the four columns (col[i RFE_MEAS + r], wheel i), counted in
 *  *sat. */
void rfe_meas_sum_columns_q31(const rfe_fix_t col[RFE_MEAS_Q31_COLS], rfe_fix_t z[RFE_MEAS],
                              uint32_t *sat);

#endif /* RFE_MEAS_INTERNAL_Q31_H */
