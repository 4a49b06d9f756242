/**
 * @file yaw_acc_q31.c
 * @brief The yaw-rate differentiator in fixed point (docs/OBSERVER.md §3.2; twin of
 *        yaw_acc_flt.c): [r Q27, r-dot Q24], white jerk, updated with the measured r.
 */
#include "estimators/velocity/velocity_internal_q31.h"

#include "numerics/internal_q31.h"

rfe_status_t rfe_vel_yaw_acc_step_q31(rfe_kf2_q31_t *f, const rfe_velocity_params_q31_t *p,
                                      rfe_fix_t dt, rfe_fix_t r, uint32_t *sat)
{
    rfe_kf2_q31_t k;
    uint32_t cnt = 0u;
    /* q_jerk^2 Q48 (exact, < 2^62, clamped to PMAX); then the products by dt (Q30) */
    const int64_t qj = rfe_vel_var_q31(p->q_jerk, &cnt);
    const int64_t qj_dt = rfe_vel_scale_q31(qj, dt, 30u, &cnt);                 /* Q48 */
    const int64_t qj_dt2 = rfe_vel_scale_q31(qj_dt, dt, 24u, &cnt);             /* Q54 */
    const int64_t q00 = (rfe_vel_scale_q31(qj_dt2, dt, 30u, &cnt) + 1) / 3;     /* Q54 */
    const int64_t q01 = rfe_vel_scale_q31(qj_dt, dt, 28u, &cnt);                /* Q51, / 2 */
    rfe_kf2_meas_q31_t m;
    rfe_status_t st;
    k = *f;
    st = rfe_kf2_predict_q31(&k, dt, 0, q00, qj_dt, q01, &cnt);
    if (st == RFE_OK) {
        m.h0 = RFE_VEL_Q31_ONE;
        m.h1 = 0;
        m.qh0 = RFE_VEL_Q31_QONE;
        m.qh1 = RFE_VEL_Q31_QONE;
        m.qz = RFE_VEL_Q31_QR;
        m.nu = rfe_fix_sub(r, k.x[0], &cnt);
        m.r = rfe_vel_var_q31(p->sd_r, &cnt);
        st = rfe_kf2_update_q31(&k, &m, &cnt);
    }
    if (st == RFE_OK) {
        *f = k;
        rfe_q31_sat_add(sat, cnt);
    }
    return st;
}
