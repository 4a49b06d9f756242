/**
 * @file holds_q31.c
 * @brief Step 9's holds of the fixed-point friction estimator (docs/ESTIMATOR.md): the rear
 *        wheels' hold and the jump hold, updated last in a step, with the stale-wheel-speed
 *        rule; and step 0b, the yaw-rate input check; in integers. A unit of its own
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

/* holds_flt.c's in integers: the prediction r + dt (r_dot + r_dot_prev) / 2 with dt Q30 and the
 * yaw accelerations Q24 (|r_dot| <= RFE_LIMIT_YAW_ACC = 100 after step 0: the sum < 2^32, the
 * product < 2^63) in Q54, halved and rounded to Q27; the test in 64 bits (exact); the
 * prediction saturated to Q27's +-16 rad/s where it replaces the sample. */
void rfe_friction_yaw_check_q31(rfe_friction_q31_t *est, const rfe_sample_q31_t *sample,
                                rfe_sample_q31_t *u, uint32_t periods)
{
    const rfe_fix_t thr = est->params.filter.yaw_check;
    *u = *sample;
    if (rfe_friction_yaw_checked((thr > 0) ? 1 : 0, est->hold.yaw_on, periods) != 0) {
        const int64_t acc = (int64_t)sample->yaw_acc + (int64_t)est->hold.yaw_acc;
        const int64_t pred = (int64_t)est->hold.yaw_rate +
                             rfe_fix_shr64_round((int64_t)est->params.filter.dt * acc, 28u);
        const int64_t dev = (int64_t)sample->yaw_rate - pred;
        if (((dev < 0) ? -dev : dev) > (int64_t)thr) {
            u->yaw_rate = rfe_fix_sat32(pred, &est->step_sat);
        }
    }
}

/* The median of the three wheel speeds other than wheel w's (Q22). */
static rfe_fix_t median_others_q31(const rfe_fix_t omega[RFE_WHEELS], size_t w)
{
    const rfe_fix_t a = omega[(w + 1u) & 3u];
    const rfe_fix_t b = omega[(w + 2u) & 3u];
    const rfe_fix_t c = omega[(w + 3u) & 3u];
    const rfe_fix_t lo = (a < b) ? a : b;
    const rfe_fix_t hi = (a < b) ? b : a;
    const rfe_fix_t mid = (hi < c) ? hi : c;
    return (lo > mid) ? lo : mid;
}

/* holds_flt.c's stale_update in integers: the speeds Q22, the move |others - ref| in 64 bits
 * (exact). */
static void stale_update_q31(rfe_friction_q31_t *est, const rfe_fix_t omega[RFE_WHEELS])
{
    const int64_t delta = (int64_t)est->params.filter.stale_omega;
    uint8_t stale = 0u;
    size_t w;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        const rfe_fix_t others = median_others_q31(omega, w);
        const int64_t move = (int64_t)others - (int64_t)est->hold.omega_ref[w];
        const uint8_t rule = rfe_friction_stale_wheel((omega[w] == est->hold.omega[w]) ? 1 : 0,
                                                      (omega[w] == 0) ? 1 : 0,
                                                      (((move < 0) ? -move : move) > delta) ? 1 : 0);
        if (rule == RFE_STALE_RESTART) {
            est->hold.omega_ref[w] = others;
        }
        if (rule == RFE_STALE_STALE) {
            stale = 1u;
        }
        est->hold.omega[w] = omega[w];
    }
    est->hold.stale = stale;
}

/* Step 9's holds, holds_flt.c's rfe_friction_holds_update in integers: len = Lf + Lr in Q27 (their exact
 * Q29 sum rounded by 2 bits; <= 8 m), a = ds / len in Q30 exactly rounded, mbar += a (x - mbar)
 * in Q29, the holds' distances in Q27 (jump_hold_len Q27 as given), the tests in Q54. */
static void holds_sides_q31(rfe_friction_q31_t *est, rfe_fix_t vx, uint32_t missed)
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

void rfe_friction_holds_update_q31(rfe_friction_q31_t *est, const rfe_sample_q31_t *sample,
                                   const rfe_sample_q31_t *u, uint32_t periods)
{
    /* the accepted sample: the next check predicts from it, unless the check replaced it
     * (then the next sample restarts the check: a departure that persists is no spike) */
    est->hold.yaw_rate = u->yaw_rate;
    est->hold.yaw_acc = u->yaw_acc;
    est->hold.yaw_on = (u->yaw_rate == sample->yaw_rate) ? 1u : 0u;
    if (est->params.filter.stale_omega > 0) {
        stale_update_q31(est, u->omega);
    }
    holds_sides_q31(est, u->vx, periods);
}
