/**
 * @file holds_flt.c
 * @brief Step 9's holds of the friction estimator (docs/ESTIMATOR.md): the rear wheels' hold and
 *        the jump hold, updated last in a step. A unit of its own (holds_internal.h) so that
 *        its frame stays off the step's deepest stack path, as in the fixed-point twin.
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

/* Step 9's holds (docs/ESTIMATOR.md; structure sides), over the distance
 * ds = max(vx, 0) dt (missed + 1) of this step. The rear wheels' hold (rear_hold_k > 0): each
 * side's estimate is smoothed over one wheelbase L (mbar += min(1, ds / L) (x - mbar)) and the
 * hold's distance runs down; a side whose estimate lies more than rear_hold_k sd from mbar has
 * just moved, on what its front wheels reached first: its rear wheels reach it one wheelbase
 * later, so they hold for L. The jump hold (jump_hold_k > 0): a step that moved a side's
 * estimate by more than jump_hold_k sd (its new sd) was not described by the sd the filter
 * claimed a step before (a spike, a sudden slip), so both its wheels hold for jump_hold_len. */
void rfe_friction_holds_update(rfe_friction_t *est, rfe_real_t vx, uint32_t missed)
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
