/**
 * @file conditioner_q31.c
 * @brief Complementary filter for vx, vy on int32 Q values (the twin of conditioner_flt.c,
 *        docs/ESTIMATOR.md step 1). Integer operations only.
 *
 * Formats (fractional bits) and ranges, for every int32 input (no precondition):
 *  - a = ax + r v_y: ax Q24 (|ax| < 2^7) times 2^26 plus r Q27 times v_y Q23 (exact, Q50,
 *    |r v_y| <= 2^62), rounded to Q40: |a| < (2^7 + 2^12) 2^40 < 2^52.1;
 *  - dt a: dt Q30 (< 2^31) times a Q40 needs up to 83 bits; rfe_q31_mul64x32 forms it exactly
 *    and rounds once to Q46: |dt a| < 2^59.1;
 *  - px = v_x 2^23 + dt a (Q46): |px| < 2^54 + 2^59.1 < 2^60;
 *  - (1 - b) px: rfe_q31_mul64x32 again, (1 - b) in [0, 2^30] (Q30), rounded to Q46 (< 2^60);
 *    b vx_measured: Q30 times Q23, exact (< 2^61), rounded to Q46;
 *  - the sum (< 2^61) rounded once to Q23 and saturated (counted) to the int32 range.
 * So the new speed is within 0.5 LSB23 + 2^-39 m/s of the exact blend of the Q inputs
 * (four roundings at 2^-46 .. 2^-41, the Q40 one weighted by dt (1 - b) < 2), and a
 * saturation can only come from the final narrowing (a speed beyond +-256 m/s).
 */
#include "rfe/component/conditioner_q31.h"

#include "numerics/internal_q31.h"

/** Marks an initialised rfe_conditioner_q31_t (distinct from the float filter's word). */
#define RFE_MAGIC_COND_Q31 0x434E4433u /* "CND3" */

/* Formats (fractional bits), as unsigned shift counts. */
#define QA 40u                                      /* the acceleration a = ax +- r v [m/s^2] */
#define QP 46u                                      /* the predicted speed, the blend [m/s] */
#define QACC ((unsigned int)RFE_FIX_Q_ACC)          /* ax, ay: Q24 */
#define QV ((unsigned int)RFE_FIX_Q_SPEED)          /* vx, vy: Q23 */
#define QDT ((unsigned int)RFE_FIX_Q_DT)            /* dt, b: Q30 */
#define QRW ((unsigned int)RFE_FIX_Q_YAWRATE + QV)  /* r v: Q50 */
#define ONE_Q30 ((rfe_fix_t)1073741824)             /* 1.0 in Q30 (RFE_FIX_ONE(30)) */

/* 2^s as an int64 multiplier (s <= 62): a left shift is a multiplication by it. */
static int64_t cnd_pow2(unsigned int s)
{
    const uint64_t p = (uint64_t)1u << s;
    return (int64_t)p;
}

rfe_status_t rfe_conditioner_init_q31(rfe_conditioner_q31_t *c)
{
    if (c == NULL) {
        return RFE_ERR_NULL;
    }
    c->started = 0u;
    c->vx = 0;
    c->vy = 0;
    c->magic = RFE_MAGIC_COND_Q31;
    return RFE_OK;
}

/* Argument checks of rfe_conditioner_step_q31, in the order of its documented statuses. */
static rfe_status_t cnd_check_step(const rfe_conditioner_q31_t *c, rfe_fix_t dt, rfe_fix_t tau_v,
                                   rfe_fix_t b_v, const rfe_sample_q31_t *in,
                                   const rfe_sample_q31_t *out, const uint32_t *sat)
{
    if ((c == NULL) || (in == NULL) || (out == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (c->magic != RFE_MAGIC_COND_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if ((dt <= 0) || (tau_v < 0) || (b_v <= 0) || (b_v > ONE_Q30)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}

/* One speed: (1 - b) (v + dt (acc + rw)) + b v_meas in Q46, rounded to Q23.
 * v, v_meas Q23; acc Q24; rw = +-r w (the yaw-rate term) Q50, |rw| <= 2^62; dt, b Q30. */
static rfe_fix_t cnd_blend(rfe_fix_t v, int64_t rw, rfe_fix_t acc, rfe_fix_t dt, rfe_fix_t b,
                           rfe_fix_t v_meas, uint32_t *sat)
{
    const int64_t a50 = ((int64_t)acc * cnd_pow2(QRW - QACC)) + rw; /* < 2^62 + 2^57 */
    const int64_t a40 = rfe_fix_shr64_round(a50, QRW - QA);
    const int64_t inc = rfe_q31_mul64x32(a40, (int64_t)dt, (QDT + QA) - QP);
    const int64_t px = ((int64_t)v * cnd_pow2(QP - QV)) + inc;
    const int64_t one_minus_b = (int64_t)ONE_Q30 - (int64_t)b;
    const int64_t keep = rfe_q31_mul64x32(px, one_minus_b, QDT);
    const int64_t take = rfe_fix_shr64_round((int64_t)b * (int64_t)v_meas, (QDT + QV) - QP);
    return rfe_fix_narrow(keep + take, QP - QV, sat);
}

rfe_status_t rfe_conditioner_step_q31(rfe_conditioner_q31_t *c, rfe_fix_t dt, rfe_fix_t tau_v,
                                      rfe_fix_t b_v, const rfe_sample_q31_t *in,
                                      rfe_sample_q31_t *out, uint32_t *sat)
{
    rfe_fix_t vx;
    rfe_fix_t vy;
    uint32_t count = 0u;
    const rfe_status_t st = cnd_check_step(c, dt, tau_v, b_v, in, out, sat);
    if (st != RFE_OK) {
        return st;
    }
    if (tau_v == 0) {
        *out = *in; /* off */
        return RFE_OK;
    }
    if (c->started == 0u) {
        vx = in->vx; /* the first accepted sample initialises */
        vy = in->vy;
    } else {
        /* Predict with the accelerometer and the yaw rate (both from the old state), then
         * blend in the measured speeds. */
        const int64_t r_vy = (int64_t)in->yaw_rate * (int64_t)c->vy; /* Q50, <= 2^62 */
        const int64_t r_vx = (int64_t)in->yaw_rate * (int64_t)c->vx;
        vx = cnd_blend(c->vx, r_vy, in->ax, dt, b_v, in->vx, &count);
        vy = cnd_blend(c->vy, -r_vx, in->ay, dt, b_v, in->vy, &count);
    }
    *out = *in;
    out->vx = vx;
    out->vy = vy;
    c->vx = vx;
    c->vy = vy;
    c->started = 1u;
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}
