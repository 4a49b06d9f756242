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

/* z = H(u) mu with the H of rfe_meas_setup, the sums of rfe_obsmat_apply in the same order
 * (the same result, bit for bit), without re-checking H at every cubature point: setup built
 * it from finite forces. A non-finite mu is rejected as rfe_obsmat_apply rejects it. */
static rfe_status_t apply_paper(const rfe_real_t H[RFE_H_SIZE], const rfe_real_t mu[RFE_WHEELS],
                                rfe_real_t z[RFE_MEAS])
{
    size_t r;
    size_t i;
    if (!rfe_all_finite(mu, RFE_WHEELS)) {
        return RFE_ERR_NONFINITE;
    }
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        rfe_real_t acc = RFE_R(0.0);
        for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
            acc += H[RFE_H_AT(r, i)] * mu[i];
        }
        z[r] = acc;
    }
    return RFE_OK;
}

/* Absolute mode: z_r = sum_i H_r,i(F(mu_i)), the entries rfe_obsmat_build would put in
 * column i (body-axis force over m, yaw moment over J) summed in wheel order, which is
 * rfe_obsmat_apply(H, ones) bit for bit, without building and re-checking a matrix at every
 * cubature point. z is written only when finite. */
static rfe_status_t body_sums(const rfe_vehicle_t *veh, rfe_real_t delta,
                              const rfe_real_t fx[RFE_WHEELS], const rfe_real_t fy[RFE_WHEELS],
                              rfe_real_t z[RFE_MEAS])
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    rfe_real_t zt[RFE_MEAS] = {RFE_R(0.0), RFE_R(0.0), RFE_R(0.0)};
    const rfe_real_t c = RFE_COS(delta);
    const rfe_real_t s = RFE_SIN(delta);
    size_t i;

    rfe_wheel_positions(veh, px, py);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        /* Front wheels are rotated by delta into body axes, rear wheels are not. */
        const rfe_real_t ci = (i < (size_t)RFE_RL) ? c : RFE_R(1.0);
        const rfe_real_t si = (i < (size_t)RFE_RL) ? s : RFE_R(0.0);
        const rfe_real_t fbx = (fx[i] * ci) - (fy[i] * si);
        const rfe_real_t fby = (fx[i] * si) + (fy[i] * ci);
        zt[0] += fbx / veh->m;
        zt[1] += fby / veh->m;
        zt[2] += ((px[i] * fby) - (py[i] * fbx)) / veh->J;
    }
    if (!rfe_all_finite(zt, RFE_MEAS)) {
        return RFE_ERR_NONFINITE;
    }
    for (i = 0u; i < (size_t)RFE_MEAS; ++i) {
        z[i] = zt[i];
    }
    return RFE_OK;
}

rfe_status_t RFE_FN(rfe_meas_eval)(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                                   const rfe_tyre_params_t *tp, const rfe_real_t mu[RFE_WHEELS],
                                   rfe_real_t z[RFE_MEAS])
{
    rfe_real_t fx[RFE_WHEELS];
    rfe_real_t fy[RFE_WHEELS];
    rfe_status_t st;

    if ((h == NULL) || (veh == NULL) || (tp == NULL) || (mu == NULL) || (z == NULL)) {
        return RFE_ERR_NULL;
    }
    if (h->mode == RFE_TYRE_PAPER) {
        return apply_paper(h->H, mu, z); /* h = H(u) mu */
    }
    /* Absolute mode: forces at this mu (nonlinear in mu), then the same geometry as H's
     * columns: z_r = sum_i H_r,i(F(mu_i)) (MODEL.md §4-5). */
    st = RFE_FN(rfe_tyre_forces_abs)(tp, &h->kin, mu, fx, fy);
    if (st == RFE_OK) {
        st = body_sums(veh, h->delta, fx, fy, z);
    }
    return st;
}
