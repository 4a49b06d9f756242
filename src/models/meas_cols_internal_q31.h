/**
 * @file meas_cols_internal_q31.h
 * @brief Private: the fixed-point input columns' per-wheel rows and columns (meas_cols_q31.c)
 *        for rfe_meas_input_jac_q31 (meas_q31.c), and what both units share. Not installed;
 *        integer operations only. Fixed point only: the float twin (meas_flt.c) forms the
 *        columns in one unit; here they are a unit of their own so that their locals stay
 *        off the step noise's deepest stack path (rfe_meas_input_jac_q31 -> the tyre
 *        derivatives), which must fit the Cortex-M stack budget.
 */
#ifndef RFE_MEAS_COLS_INTERNAL_Q31_H
#define RFE_MEAS_COLS_INTERNAL_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/component/meas_q31.h"
#include "rfe/fixed.h"
#include "rfe/params_q31.h"

#include "numerics/internal_q31.h"
#include "numerics/xf_q31.h"
#include "models/tyre_internal_q31.h"

/* The map in plain Q36 integers for the lateral rows' derivatives (lat_part_q31) and the
 * input columns' body rows (body_part_q31):
 * inv_m, lf_J, lr_J, yf_J, yr_J are int32 in Q38, so each is below 2^-7 (params_q31.h) and
 * |ax|, |ay| <= 2^-7, |rx|, |ry| <= |(x_i / J, y_i / J)| < sqrt(2) 2^-7 = 2^-6.5 (c^2 + s^2
 * = 1): below 2^29.5 in Q36, the Q68 value rounded by 32 bits (1/2 unit, 2^-37 absolute). */
typedef struct {
    int32_t ax;
    int32_t ay;
    int32_t rx;
    int32_t ry;
} lat_q36_t;

/* One wheel's part of the input columns (wheel_prepare_q31): its rows per unit change of its
 * velocity (v_wx, v_wy, omega R) as integers at one exponent, wm[k] 2^base (|wm| <= 2^27; all
 * 0: any = 0), its velocity in wheel axes (Q21), the cos and sin of its steer angle (Q30) and
 * the rows of its turned forces for delta, ftm[r] 2^fte (|ftm| <= 2^30; zeros unless a front
 * wheel with sd_delta > 0). */
typedef struct {
    int32_t wm[9];
    int base;
    int any;
    int32_t vw[2];
    int32_t c;
    int32_t s;
    int32_t ftm[3];
    int fte;
} wheel_cols_q31_t;

/* v 2^k (|v| < 2^63) as an int32, the derivatives' last step to Q24: k < 0 rounds half up
 * once (k = 0 is v itself), k > 0 shifts up exactly while the result stays below 2^62 and
 * saturates beyond it; then saturated to the int32 range (counted in *count). */
static inline rfe_fix_t rfe_meas_q24_of_scaled_q31(int64_t v, int k, uint32_t *count)
{
    int64_t r;
    if (k < 0) {
        r = rfe_fix_shr64_round(v, (unsigned int)(-k));
    } else if ((v == 0) || ((rfe_q31_bitlen64(rfe_q31_mag64(v)) + (unsigned int)k) <= 62u)) {
        r = v * rfe_q31_pow2((unsigned int)k);
    } else {
        r = (v > 0) ? INT64_MAX : -INT64_MAX; /* beyond 2^62: saturates */
    }
    return rfe_fix_sat32(r, count);
}

/* Wheel i's rows per unit change of its velocity (v_wx, v_wy, omega R) into wc->wm, base and
 * any, from its force derivatives fj along unit kappa, tan(alpha) and v_wx, its tan(alpha)
 * (Q26) and its Q36 map bm (meas_cols_q31.c says how). */
void rfe_meas_wheel_rows_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                             const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u, size_t i,
                             int32_t tan_a, const lat_q36_t *bm, const rfe_tyre_jac_q31_t fj[3],
                             wheel_cols_q31_t *wc);

/* The body rows of the force pair (fx, fy) (wheel axes) by bm into wc->ftm, fte (the turn of
 * a front wheel's forces for delta). */
void rfe_meas_turn_rows_q31(const lat_q36_t *bm, rfe_xf_t fx, rfe_xf_t fy, wheel_cols_q31_t *wc);

/* Input j's column of G (Q24, G[r RFE_INPUTS + j]) from the wheels' parts wc: sd_j (in input
 * j's format) times dh/du_j, saturating (counted in *count); 0 for sd_j <= 0. */
void rfe_meas_input_column_q31(const wheel_cols_q31_t wc[RFE_WHEELS],
                               const rfe_vehicle_q31_t *veh, size_t j, rfe_fix_t sdj,
                               rfe_fix_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS], uint32_t *count);

#endif /* RFE_MEAS_COLS_INTERNAL_Q31_H */
