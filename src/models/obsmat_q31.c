/**
 * @file obsmat_q31.c
 * @brief Fixed-point twin of obsmat_flt.c: H(u) of MODEL.md §5 and h(x, u) = H x.
 *        Integer operations only (rfe/component/obsmat_q31.h).
 *
 * Formats: forces Q15, cos/sin of delta Q30, body-axis forces Fbx, Fby exact int64 Q45,
 * 1/m, x_i/J, y_i/J Q38; rows 1-2 are one exactly rounded product each (Q45 x Q38 -> Q24);
 * row 3 sums two products rounded to Q30 (2^-30 each) and rounds once to Q24.
 */
#include "rfe/component/obsmat_q31.h"

#include "rfe/component/fxmath.h"

#include "numerics/fxmath_internal_q31.h"
#include "numerics/internal_q31.h"

/* 1.0 in Q30, 2^30 (cos of an unsteered wheel). */
#define ONE_Q30 ((int32_t)0x40000000)

rfe_status_t rfe_obsmat_build_q31(const rfe_vehicle_q31_t *veh, rfe_fix_t delta,
                                  const rfe_fix_t fx[RFE_WHEELS], const rfe_fix_t fy[RFE_WHEELS],
                                  rfe_fix_t H[RFE_H_Q31_SIZE], uint32_t *sat)
{
    rfe_fix_t out[RFE_H_Q31_SIZE];
    int64_t px_J[RFE_WHEELS];
    int64_t py_J[RFE_WHEELS];
    uint32_t count = 0u;
    int32_t c = 0;
    int32_t s = 0;
    size_t i;

    if ((veh == NULL) || (fx == NULL) || (fy == NULL) || (H == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    rfe_q31_sincos_q29(delta, &s, &c); /* every angle */
    /* x_i / J and y_i / J (MODEL.md §1 positions), Q38; |.| <= 2^31 as int64. */
    px_J[RFE_FL] = veh->lf_J;
    px_J[RFE_FR] = veh->lf_J;
    px_J[RFE_RL] = -(int64_t)veh->lr_J;
    px_J[RFE_RR] = -(int64_t)veh->lr_J;
    py_J[RFE_FL] = veh->yf_J;
    py_J[RFE_FR] = -(int64_t)veh->yf_J;
    py_J[RFE_RL] = veh->yr_J;
    py_J[RFE_RR] = -(int64_t)veh->yr_J;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        /* Front wheels are rotated by delta into body axes, rear wheels are not. */
        const int64_t ci = (i < (size_t)RFE_RL) ? (int64_t)c : (int64_t)ONE_Q30;
        const int64_t si = (i < (size_t)RFE_RL) ? (int64_t)s : 0;
        /* Exact Q45: |fx c - fy s| <= |(fx, fy)| |(c, s)| <= 2^31.5 2^30 (1 + 2^-30) < 2^62. */
        const int64_t fbx = ((int64_t)fx[i] * ci) - ((int64_t)fy[i] * si);
        const int64_t fby = ((int64_t)fx[i] * si) + ((int64_t)fy[i] * ci);
        /* Column i: [Fbx/m, Fby/m] (Q45 x Q38 / 2^59 -> Q24, < 2^34.5 before saturation) and
         * (x_i Fby - y_i Fbx)/J (two Q30 terms < 2^39.5, rounded once more to Q24). */
        const int64_t m3 =
            rfe_q31_mul64x32(fby, px_J[i], 53u) - rfe_q31_mul64x32(fbx, py_J[i], 53u);

        out[RFE_H_Q31_AT(0, i)] = rfe_fix_sat32(rfe_q31_mul64x32(fbx, veh->inv_m, 59u), &count);
        out[RFE_H_Q31_AT(1, i)] = rfe_fix_sat32(rfe_q31_mul64x32(fby, veh->inv_m, 59u), &count);
        out[RFE_H_Q31_AT(2, i)] = rfe_fix_narrow(m3, 6u, &count);
    }
    for (i = 0u; i < RFE_H_Q31_SIZE; ++i) {
        H[i] = out[i];
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

rfe_status_t rfe_obsmat_apply_q31(const rfe_fix_t H[RFE_H_Q31_SIZE],
                                  const rfe_fix_t x[RFE_WHEELS], rfe_fix_t y[RFE_MEAS],
                                  uint32_t *sat)
{
    rfe_fix_t out[RFE_MEAS];
    uint32_t count = 0u;
    size_t r;
    size_t i;

    if ((H == NULL) || (x == NULL) || (y == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        /* Each product p = H x (Q24 x Q29 = Q53, |p| <= 2^62; 32 x 32 -> 64) is split as
         * p = 4 q + l, q = floor(p / 4), 0 <= l < 4: the four q (|q| <= 2^60) sum to S
         * (|S| <= 2^62) and the four l to L <= 12 without overflow, and the sum 4 S + L is
         * rounded half up to Q24 exactly once: floor((4 S + L + 2^28) / 2^29) =
         * floor((S + 2^26 + floor(L / 4)) / 2^27) (4 S + L + 2^28 = 4 (S + 2^26) + L). The
         * same integer as the split at 2^29 it replaced (issue 21: fewer 64-bit operations,
         * and no libgcc 64-bit multiply on the Cortex-M0+). */
        int64_t q = 0;
        uint32_t l = 0u;
        for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
            const int64_t p = rfe_fix_mul32x32(H[RFE_H_Q31_AT(r, i)], x[i]);
            q += rfe_fix_shr64_floor(p, 2u);
            l += (uint32_t)((uint64_t)p & 3u);
        }
        out[r] = rfe_fix_sat32(
            rfe_fix_shr64_floor((q + rfe_q31_pow2(26u)) + (int64_t)(l >> 2), 27u), &count);
    }
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        y[r] = out[r];
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}
