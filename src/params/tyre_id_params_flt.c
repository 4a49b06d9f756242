/**
 * @file tyre_id_params_flt.c
 * @brief The tyre identifier's defaults and validation (docs/TYRE_ID.md §2).
 */
#include "rfe/tyre_id_params.h"

#include "numerics/internal.h"
#include "rfe/config.h"

rfe_status_t rfe_tyre_id_params_default(rfe_tyre_id_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    p->filter = RFE_TID_APF;
    p->resample = RFE_TID_MULTINOMIAL;
    p->substeps = 1u;
    p->v_min = RFE_R(5.0);
    p->dt_max = RFE_R(0.1);
    p->sd_r = RFE_R(0.01);
    p->sd_ay = RFE_R(0.2);
    p->sd_delta = RFE_R(0.001);
    p->q_vy = RFE_R(0.02);
    p->q_r = RFE_R(0.01);
    p->q_mu = RFE_R(0.02);
    p->q_C = RFE_R(0.02);
    p->q_cy = RFE_R(0.3);
    p->q_E = RFE_R(0.05);
    p->mu0 = RFE_R(0.7);
    p->sd0_mu = RFE_R(0.3);
    p->sd0_C = RFE_R(0.2);
    p->sd0_E = RFE_R(0.5);
    p->sd0_cy_rel = RFE_R(0.3);
    p->sd0_vy = RFE_R(0.2);
    p->sd0_r = RFE_R(0.01);
    p->mu_lo = RFE_R(0.1);
    p->mu_hi = RFE_R(1.3);
    p->C_lo = RFE_R(1.0);
    p->C_hi = RFE_R(2.0);
    p->cy_lo = RFE_R(4.0);
    p->cy_hi = RFE_R(40.0);
    p->E_lo = RFE_R(-3.0);
    p->E_hi = RFE_R(0.95);
    p->neff_frac = RFE_R(1.0) / RFE_R(3.0); /* the patent's N/3, rounded as the reference's 1/3 */
    p->rough_k = RFE_R(0.2);
    p->ellipse = RFE_R(0.0);
    p->fx_front = RFE_R(0.625);
    p->ell_min = RFE_R(0.1);
    p->ell_ax_min = RFE_R(0.6);
    p->delta_q = RFE_R(0.0);
    p->delta_state_q = RFE_R(0.0);
    return RFE_OK;
}

/* Every real field finite; those that must be > 0, then those that must be >= 0. */
static int reals_ok(const rfe_tyre_id_params_t *p)
{
    const rfe_real_t pos[4] = {p->v_min, p->dt_max, p->sd_r, p->sd_ay};
    const rfe_real_t nonneg[16] = {p->sd_delta, p->q_vy,   p->q_r,      p->q_mu,
                                   p->q_C,      p->q_cy,   p->q_E,      p->sd0_mu,
                                   p->sd0_C,    p->sd0_E,  p->sd0_cy_rel, p->sd0_vy,
                                   p->sd0_r,    p->rough_k, p->delta_q, p->delta_state_q};
    size_t i;
    for (i = 0u; i < 4u; ++i) {
        if (!rfe_is_finite(pos[i]) || !(pos[i] > RFE_R(0.0))) {
            return 0;
        }
    }
    for (i = 0u; i < 16u; ++i) {
        if (!rfe_is_finite(nonneg[i]) || !(nonneg[i] >= RFE_R(0.0))) {
            return 0;
        }
    }
    return (rfe_is_finite(p->mu0) && rfe_is_finite(p->neff_frac) &&
            (p->neff_frac >= RFE_R(0.0)) && (p->neff_frac <= RFE_R(1.0)))
               ? 1
               : 0;
}

/* The friction ellipse's keys (§3.5): the switch 0 or 1, the front share in [0, 1], the
 * factor's floor in (0, 1], the dead band in [0, 20] m/s^2 (2 g: no car brakes harder). */
static int ellipse_ok(const rfe_tyre_id_params_t *p)
{
    return (((p->ellipse == RFE_R(0.0)) || (p->ellipse == RFE_R(1.0))) &&
            (p->fx_front >= RFE_R(0.0)) && (p->fx_front <= RFE_R(1.0)) &&
            (p->ell_min > RFE_R(0.0)) && (p->ell_min <= RFE_R(1.0)) &&
            (p->ell_ax_min >= RFE_R(0.0)) && (p->ell_ax_min <= RFE_R(20.0)))
               ? 1
               : 0;
}

/* Each pair of bounds finite with lo < hi; D, C and K bounded away from 0. */
static int bounds_ok(const rfe_tyre_id_params_t *p)
{
    const rfe_real_t lo[4] = {p->mu_lo, p->C_lo, p->cy_lo, p->E_lo};
    const rfe_real_t hi[4] = {p->mu_hi, p->C_hi, p->cy_hi, p->E_hi};
    size_t i;
    for (i = 0u; i < 4u; ++i) {
        if (!rfe_is_finite(lo[i]) || !rfe_is_finite(hi[i]) || !(lo[i] < hi[i])) {
            return 0;
        }
    }
    return ((p->mu_lo > RFE_R(0.0)) && (p->C_lo > RFE_R(0.0)) && (p->cy_lo > RFE_R(0.0))) ? 1
                                                                                        : 0;
}

rfe_status_t rfe_tyre_id_params_validate(const rfe_tyre_id_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    if (((p->filter != RFE_TID_APF) && (p->filter != RFE_TID_SIR) && (p->filter != RFE_TID_SCKF)) ||
        ((p->resample != RFE_TID_MULTINOMIAL) && (p->resample != RFE_TID_SYSTEMATIC)) ||
        (p->substeps < 1u) || (p->substeps > (uint32_t)RFE_TID_SUBSTEPS_MAX)) {
        return RFE_ERR_PARAM;
    }
    if ((reals_ok(p) == 0) || (bounds_ok(p) == 0) || (ellipse_ok(p) == 0)) {
        return RFE_ERR_PARAM;
    }
    /* §15.7 delta as the sigma-point filter's state and the steering-angle filter of §4.4
     * both model delta: one at a time */
    if ((p->delta_q > RFE_R(0.0)) && (p->delta_state_q > RFE_R(0.0))) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}
