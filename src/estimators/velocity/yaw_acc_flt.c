/**
 * @file yaw_acc_flt.c
 * @brief The yaw-rate differentiator (docs/OBSERVER.md §3.2): a constant-yaw-acceleration
 *        Kalman filter driven by white jerk, updated with the measured yaw rate.
 */
#include "estimators/velocity/velocity_internal.h"

#include "numerics/internal.h"

rfe_status_t rfe_vel_yaw_acc_step(rfe_kf2_t *f, const rfe_velocity_params_t *p, rfe_real_t dt,
                                  rfe_real_t r)
{
    rfe_kf2_t k;
    const rfe_real_t qj = p->q_jerk * p->q_jerk;
    rfe_status_t st;
    k = *f;
    st = rfe_kf2_predict(&k, dt, RFE_R(0.0), (qj * dt * dt * dt) / RFE_R(3.0),
                                      qj * dt, (qj * dt * dt) / RFE_R(2.0));
    if (st == RFE_OK) {
        st = rfe_kf2_update(&k, RFE_R(1.0), RFE_R(0.0), r - k.x[0], p->sd_r * p->sd_r);
    }
    if (st == RFE_OK) {
        *f = k;
    }
    return st;
}
