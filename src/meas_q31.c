/**
 * @file meas_q31.c
 * @brief Fixed-point twin of meas_flt.c: the measurement model h(mu, u) of one sample, paper
 *        (H(u) mu) or absolute Dugoff. Integer operations only (rfe/meas_q31.h).
 */
#include "rfe/meas_q31.h"

#include "internal_q31.h"

rfe_status_t rfe_meas_setup_q31(rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                                const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u,
                                uint32_t *sat)
{
    rfe_wheel_kin_q31_t kin;
    rfe_fix_t H[RFE_H_Q31_SIZE] = {0};
    uint32_t count = 0u;
    rfe_status_t st;
    size_t i;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((tp->mode != RFE_TYRE_PAPER) && (tp->mode != RFE_TYRE_ABSOLUTE)) {
        return RFE_ERR_PARAM;
    }
    st = rfe_tyre_kinematics_q31(veh, tp, u, &kin, &count);
    if ((st == RFE_OK) && (tp->mode == RFE_TYRE_PAPER)) {
        rfe_fix_t f0x[RFE_WHEELS];
        rfe_fix_t f0y[RFE_WHEELS];
        st = rfe_tyre_forces_norm_q31(tp, &kin, f0x, f0y, &count);
        if (st == RFE_OK) {
            st = rfe_obsmat_build_q31(veh, u->delta, f0x, f0y, H, &count);
        }
    }
    if (st != RFE_OK) {
        return st;
    }
    h->mode = tp->mode;
    h->delta = u->delta;
    h->kin = kin;
    for (i = 0u; i < RFE_H_Q31_SIZE; ++i) {
        h->H[i] = H[i];
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

rfe_status_t rfe_meas_eval_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                               const rfe_tyre_params_q31_t *tp, const rfe_fix_t mu[RFE_WHEELS],
                               rfe_fix_t z[RFE_MEAS], uint32_t *sat)
{
    static const rfe_fix_t ones[RFE_WHEELS] = {
        RFE_FIX_ONE(RFE_FIX_Q_MU), RFE_FIX_ONE(RFE_FIX_Q_MU), RFE_FIX_ONE(RFE_FIX_Q_MU),
        RFE_FIX_ONE(RFE_FIX_Q_MU)};
    rfe_fix_t fx[RFE_WHEELS];
    rfe_fix_t fy[RFE_WHEELS];
    rfe_fix_t Hf[RFE_H_Q31_SIZE];
    rfe_fix_t zt[RFE_MEAS];
    uint32_t count = 0u;
    rfe_status_t st;
    size_t r;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (mu == NULL) || (z == NULL) ||
        (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (h->mode == RFE_TYRE_PAPER) {
        return rfe_obsmat_apply_q31(h->H, mu, z, sat); /* h = H(u) mu */
    }
    /* Absolute mode: forces at this mu (nonlinear in mu), then the same geometry as H's
     * columns: z_r = sum_i H_r,i(F(mu_i)) (MODEL.md §4-5). */
    st = rfe_tyre_forces_abs_q31(tp, &h->kin, mu, fx, fy, &count);
    if (st == RFE_OK) {
        st = rfe_obsmat_build_q31(veh, h->delta, fx, fy, Hf, &count);
    }
    if (st == RFE_OK) {
        st = rfe_obsmat_apply_q31(Hf, ones, zt, &count);
    }
    if (st != RFE_OK) {
        return st;
    }
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        z[r] = zt[r];
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}
