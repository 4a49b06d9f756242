/**
 * @file holds_flt.c
 * @brief Step 9's holds of the friction estimator (docs/ESTIMATOR.md): the rear wheels' hold and
 *        the jump hold, updated last in a step, with the stale-wheel-speed rule; and step 0b,
 *        the yaw-rate input check. A unit of its own (holds_internal.h) so that its frame
 *        stays off the step's deepest stack path, as in the fixed-point twin.
 */
#include "estimators/friction/holds_internal.h"

#include "estimators/friction/friction_logic.h"
#include "numerics/internal.h"

/* Side j's rear wheels' hold after a step of ds with the smoothing gain a: RFE_HOLD_REAR while
 * held. */
static uint8_t rear_hold_side(rfe_friction_t *est, size_t j, rfe_real_t x, rfe_real_t sd,
                              rfe_real_t a, rfe_real_t ds, rfe_real_t len)
{
    est->hold.mbar[j] += a * (x - est->hold.mbar[j]);
    est->hold.dist[j] = (est->hold.dist[j] > ds) ? (est->hold.dist[j] - ds) : RFE_R(0.0);
    if (RFE_FABS(x - est->hold.mbar[j]) > (est->params.filter.rear_hold_k * sd)) {
        est->hold.dist[j] = len;
    }
    return (est->hold.dist[j] > RFE_R(0.0)) ? RFE_HOLD_REAR : 0u;
}

/* Side j's jump hold after a step of ds: RFE_HOLD_JUMP while held. */
static uint8_t jump_hold_side(rfe_friction_t *est, size_t j, rfe_real_t x, rfe_real_t sd,
                              rfe_real_t ds)
{
    est->hold.jdist[j] = (est->hold.jdist[j] > ds) ? (est->hold.jdist[j] - ds) : RFE_R(0.0);
    if (RFE_FABS(x - est->hold.prev[j]) > (est->params.filter.jump_hold_k * sd)) {
        est->hold.jdist[j] = est->params.filter.jump_hold_len;
    }
    est->hold.prev[j] = x;
    return (est->hold.jdist[j] > RFE_R(0.0)) ? RFE_HOLD_JUMP : 0u;
}

void rfe_friction_yaw_check(const rfe_friction_t *est, const rfe_sample_t *sample,
                            rfe_sample_t *u, uint32_t periods)
{
    const rfe_real_t thr = est->params.filter.yaw_check;
    *u = *sample;
    if (rfe_friction_yaw_checked((thr > RFE_R(0.0)) ? 1 : 0, est->hold.yaw_on, periods) != 0) {
        const rfe_real_t pred =
            est->hold.yaw_rate +
            ((est->params.filter.dt * RFE_R(0.5)) * (sample->yaw_acc + est->hold.yaw_acc));
        if (RFE_FABS(sample->yaw_rate - pred) > thr) {
            u->yaw_rate = pred;
        }
    }
}

/* The median of the three wheel speeds other than wheel w's. */
static rfe_real_t median_others(const rfe_real_t omega[RFE_WHEELS], size_t w)
{
    const rfe_real_t a = omega[(w + 1u) & 3u];
    const rfe_real_t b = omega[(w + 2u) & 3u];
    const rfe_real_t c = omega[(w + 3u) & 3u];
    return rfe_max(rfe_min(a, b), rfe_min(rfe_max(a, b), c));
}

/* Step 9's stale-wheel-speed rule (docs/ESTIMATOR.md): per wheel, its reference restarts at
 * the others' median when its speed changed or reads 0; else it is stale when that median
 * moved by more than stale_omega since. est->hold.stale: any wheel stale at this sample. */
static void stale_update(rfe_friction_t *est, const rfe_real_t omega[RFE_WHEELS])
{
    const rfe_real_t delta = est->params.filter.stale_omega;
    uint8_t stale = 0u;
    size_t w;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        const rfe_real_t others = median_others(omega, w);
        const uint8_t rule = rfe_friction_stale_wheel(
            (omega[w] == est->hold.omega[w]) ? 1 : 0, (omega[w] == RFE_R(0.0)) ? 1 : 0,
            (RFE_FABS(others - est->hold.omega_ref[w]) > delta) ? 1 : 0);
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

/* Step 9's holds (docs/ESTIMATOR.md; structure sides), over the distance
 * ds = max(vx, 0) dt (missed + 1) of this step. The rear wheels' hold (rear_hold_k > 0): each
 * side's estimate is smoothed over one wheelbase L (mbar += min(1, ds / L) (x - mbar)) and the
 * hold's distance runs down; a side whose estimate lies more than rear_hold_k sd from mbar has
 * just moved, on what its front wheels reached first: its rear wheels reach it one wheelbase
 * later, so they hold for L. The jump hold (jump_hold_k > 0): a step that moved a side's
 * estimate by more than jump_hold_k sd (its new sd) was not described by the sd the filter
 * claimed a step before (a spike, a sudden slip), so both its wheels hold for jump_hold_len. */
static void holds_sides(rfe_friction_t *est, rfe_real_t vx, uint32_t missed)
{
    const rfe_real_t k_hold = est->params.filter.rear_hold_k;
    const rfe_real_t k_jump = est->params.filter.jump_hold_k;
    const rfe_real_t len = est->params.vehicle.Lf + est->params.vehicle.Lr;
    rfe_real_t x[RFE_N_MAX];
    rfe_real_t sd[RFE_N_MAX];
    rfe_real_t ds;
    rfe_real_t a = RFE_R(1.0);
    rfe_status_t st;
    size_t j;
    if (((k_hold <= RFE_R(0.0)) && (k_jump <= RFE_R(0.0))) || (est->n != 2u)) {
        return;
    }
    /* n = 2 is the SCKF's (structure sides): its get cannot fail after init */
    st = rfe_sckf_get(&est->filter.sckf, x, sd);
    (void)st;
    ds = ((vx > RFE_R(0.0)) ? vx : RFE_R(0.0)) *
         (est->params.filter.dt * ((rfe_real_t)missed + RFE_R(1.0)));
    if (ds < len) {
        a = ds / len;
    }
    for (j = 0u; j < 2u; ++j) {
        uint8_t held = 0u;
        if (k_hold > RFE_R(0.0)) {
            held = rear_hold_side(est, j, x[j], sd[j], a, ds, len);
        }
        if (k_jump > RFE_R(0.0)) {
            held = (uint8_t)(held | jump_hold_side(est, j, x[j], sd[j], ds));
        }
        est->hold.held[j] = held;
    }
}

void rfe_friction_holds_update(rfe_friction_t *est, const rfe_sample_t *sample,
                               const rfe_sample_t *u, uint32_t periods)
{
    /* the accepted sample: the next check predicts from it, unless the check replaced it
     * (then the next sample restarts the check: a departure that persists is no spike) */
    est->hold.yaw_rate = u->yaw_rate;
    est->hold.yaw_acc = u->yaw_acc;
    est->hold.yaw_on = (u->yaw_rate == sample->yaw_rate) ? 1u : 0u;
    if (est->params.filter.stale_omega > RFE_R(0.0)) {
        stale_update(est, u->omega);
    }
    holds_sides(est, u->vx, periods);
}
