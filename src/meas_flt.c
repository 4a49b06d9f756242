/**
 * @file meas_flt.c
 * @brief Measurement model h(mu, u) of one sample: paper (H(u) mu) or absolute Dugoff.
 */
#include "rfe/meas.h"

#include "rfe/obsmat.h"

#include "internal.h"

rfe_status_t RFE_FN(rfe_meas_setup)(rfe_meas_t *h, const rfe_vehicle_t *veh,
                                    const rfe_tyre_params_t *tp, const rfe_sample_t *u)
{
    rfe_wheel_kin_t kin;
    rfe_real_t H[RFE_H_SIZE] = {0};
    rfe_status_t st;
    size_t i;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (u == NULL)) {
        return RFE_ERR_NULL;
    }
    st = RFE_FN(rfe_tyre_kinematics)(veh, tp, u, &kin);
    if ((st == RFE_OK) && (tp->mode == RFE_TYRE_PAPER)) {
        rfe_real_t f0x[RFE_WHEELS];
        rfe_real_t f0y[RFE_WHEELS];
        st = RFE_FN(rfe_tyre_forces_norm)(tp, &kin, f0x, f0y);
        if (st == RFE_OK) {
            st = RFE_FN(rfe_obsmat_build)(veh, u->delta, f0x, f0y, H);
        }
    }
    if (st != RFE_OK) {
        return st;
    }
    h->mode = tp->mode;
    h->delta = u->delta;
    h->kin = kin;
    for (i = 0u; i < RFE_H_SIZE; ++i) {
        h->H[i] = H[i];
    }
    return RFE_OK;
}

rfe_status_t RFE_FN(rfe_meas_eval)(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                   const rfe_tyre_params_t *tp, const rfe_real_t mu[RFE_WHEELS],
                                   rfe_real_t z[RFE_MEAS])
{
    static const rfe_real_t ones[RFE_WHEELS] = {RFE_R(1.0), RFE_R(1.0), RFE_R(1.0), RFE_R(1.0)};
    rfe_real_t fx[RFE_WHEELS];
    rfe_real_t fy[RFE_WHEELS];
    rfe_real_t Hf[RFE_H_SIZE];
    rfe_status_t st;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (mu == NULL) || (z == NULL)) {
        return RFE_ERR_NULL;
    }
    if (h->mode == RFE_TYRE_PAPER) {
        return RFE_FN(rfe_obsmat_apply)(h->H, mu, z); /* h = H(u) mu */
    }
    /* Absolute mode: forces at this mu (nonlinear in mu), then the same geometry as H's
     * columns: z_r = sum_i H_r,i(F(mu_i)) (MODEL.md §4-5). */
    st = RFE_FN(rfe_tyre_forces_abs)(tp, &h->kin, mu, fx, fy);
    if (st == RFE_OK) {
        st = RFE_FN(rfe_obsmat_build)(veh, h->delta, fx, fy, Hf);
    }
    if (st == RFE_OK) {
        st = RFE_FN(rfe_obsmat_apply)(Hf, ones, z);
    }
    return st;
}
