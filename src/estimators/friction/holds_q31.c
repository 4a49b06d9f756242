/**
 * @file holds_q31.c
 * @brief Step 9's holds of the fixed-point friction estimator (docs/ESTIMATOR.md): the rear
 *        wheels' hold and the jump hold, updated last in a step, in integers. A unit of its own
 *        (holds_internal_q31.h) so that its frame stays off the step's deepest stack path (on
 *        the Cortex-M0+, -Os inlines a static one into the step: 2076 B against the 2 KiB
 *        budget).
 */
#include "estimators/friction/holds_internal_q31.h"

#include "estimators/friction/friction_logic.h"
#include "numerics/internal_q31.h"

/* The distance of one step and its missed periods, Q27 (holds_flt.c's ds =
 * max(vx, 0) dt (missed + 1)), clamped at len, the longer of the wheelbase and jump_hold_len: a
 * longer step empties both holds and smooths with a = 1 as the float twin's does. vx (Q23) dt
 * (Q30) rounded to Q27 is below 2^36; len / d1 bounds the multiple. */
static int64_t hold_distance_q31(rfe_fix_t vx, rfe_fix_t dt, uint32_t missed, int64_t len)
{
    const int64_t d1 = rfe_fix_shr64_round((int64_t)((vx > 0) ? vx : 0) * (int64_t)dt, 26u);
    int64_t ds = len;
    if (d1 == 0) {
        ds = 0;
    } else if ((int64_t)missed < (len / d1)) { /* missed + 1 <= floor(len / d1) */
        ds = d1 * ((int64_t)missed + 1); /* <= len */
    } else {
        /* beyond one wheelbase: len */
    }
    return ds;
}

/* |x - ref| > k sd, the holds' test in Q54: |x - ref| Q29 times 2^25 against k Q24 times sd
 * Q30, both below 2^62. */
static int beyond_q31(rfe_fix_t x, rfe_fix_t ref, rfe_fix_t k, rfe_fix_t sd, uint32_t *sat)
{
    const rfe_fix_t dev = rfe_fix_abs(rfe_fix_sub(x, ref, sat), sat);
    return (((int64_t)dev * rfe_q31_pow2(25u)) > ((int64_t)k * (int64_t)sd)) ? 1 : 0;
}

/* Side j's rear wheels' hold after a step of ds with the smoothing gain a (Q30):
 * RFE_HOLD_REAR while held. */
static uint8_t rear_hold_side_q31(rfe_friction_q31_t *est, size_t j, rfe_fix_t x, rfe_fix_t sd,
                                  rfe_fix_t a, int64_t ds, int64_t len, uint32_t *sat)
{
    const rfe_fix_t diff = rfe_fix_sub(x, est->hold.mbar[j], sat);
    est->hold.mbar[j] = rfe_fix_add(est->hold.mbar[j], rfe_fix_mul(a, diff, 30u, sat), sat);
    est->hold.dist[j] = (est->hold.dist[j] > ds) ? (rfe_fix_t)(est->hold.dist[j] - ds) : 0;
    if (beyond_q31(x, est->hold.mbar[j], est->params.filter.rear_hold_k, sd, sat) != 0) {
        est->hold.dist[j] = (rfe_fix_t)len;
    }
    return (est->hold.dist[j] > 0) ? RFE_HOLD_REAR : 0u;
}

/* Side j's jump hold after a step of ds: RFE_HOLD_JUMP while held. */
static uint8_t jump_hold_side_q31(rfe_friction_q31_t *est, size_t j, rfe_fix_t x, rfe_fix_t sd,
                                  int64_t ds, uint32_t *sat)
{
    est->hold.jdist[j] = (est->hold.jdist[j] > ds) ? (rfe_fix_t)(est->hold.jdist[j] - ds) : 0;
    if (beyond_q31(x, est->hold.prev[j], est->params.filter.jump_hold_k, sd, sat) != 0) {
        est->hold.jdist[j] = est->params.filter.jump_hold_len;
    }
    est->hold.prev[j] = x;
    return (est->hold.jdist[j] > 0) ? RFE_HOLD_JUMP : 0u;
}

/* Step 9's holds, holds_flt.c's rfe_friction_holds_update in integers: len = Lf + Lr in Q27 (their exact
 * Q29 sum rounded by 2 bits; <= 8 m), a = ds / len in Q30 exactly rounded, mbar += a (x - mbar)
 * in Q29, the holds' distances in Q27 (jump_hold_len Q27 as given), the tests in Q54. */
void rfe_friction_holds_update_q31(rfe_friction_q31_t *est, rfe_fix_t vx, uint32_t missed)
{
    const rfe_fix_t k_hold = est->params.filter.rear_hold_k;
    const rfe_fix_t k_jump = est->params.filter.jump_hold_k;
    const int64_t len = rfe_fix_shr64_round(
        (int64_t)est->params.vehicle.Lf + (int64_t)est->params.vehicle.Lr, 2u);
    const int64_t jlen = (int64_t)est->params.filter.jump_hold_len;
    rfe_fix_t x[RFE_N_MAX];
    rfe_fix_t sd[RFE_N_MAX];
    int64_t ds;
    rfe_fix_t a = RFE_FIX_ONE(30);
    uint32_t sat = 0u;
    rfe_status_t st;
    size_t j;
    if (((k_hold <= 0) && (k_jump <= 0)) || (est->n != 2u)) {
        return;
    }
    /* n = 2 is the SCKF's (structure sides): its get cannot fail after init */
    st = rfe_sckf_get_q31(&est->filter.sckf, x, sd);
    (void)st;
    ds = hold_distance_q31(vx, est->params.filter.dt, missed, (len > jlen) ? len : jlen);
    if (ds < len) {
        /* ds < len <= 2^30: both fit int32; the quotient < 1 (Q30) cannot saturate */
        st = rfe_fix_div((rfe_fix_t)ds, (rfe_fix_t)len, 30, &a, &sat);
        (void)st;
    }
    for (j = 0u; j < 2u; ++j) {
        uint8_t held = 0u;
        if (k_hold > 0) {
            held = rear_hold_side_q31(est, j, x[j], sd[j], a, ds, len, &sat);
        }
        if (k_jump > 0) {
            held = (uint8_t)(held | jump_hold_side_q31(est, j, x[j], sd[j], ds, &sat));
        }
        est->hold.held[j] = held;
    }
    rfe_q31_sat_add(&est->step_sat, sat);
}
