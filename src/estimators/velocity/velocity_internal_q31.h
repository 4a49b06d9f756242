/**
 * @file velocity_internal_q31.h
 * @brief The fixed-point observer's steps (twins of velocity_internal.h, name for name with
 *        _q31): the yaw-rate differentiator (yaw_acc_q31.c), the longitudinal filter
 *        (longitudinal_q31.c) and the lateral filter (lateral_q31.c); velocity_q31.c
 *        composes them. Each works on the filter it is given, adds its saturations to
 *        `*sat` and leaves both untouched on error. Integer operations only.
 */
#ifndef RFE_VELOCITY_INTERNAL_Q31_H
#define RFE_VELOCITY_INTERNAL_Q31_H

#include <stdint.h>

#include "rfe/velocity_q31.h"

/* The filters' state formats (docs/FIXED_POINT.md "Observer"). */
#define RFE_VEL_Q31_QR 27u    /**< yaw rate r: Q27 (RFE_FIX_Q_YAWRATE) */
#define RFE_VEL_Q31_QRDOT 24u /**< yaw acceleration: Q24 (RFE_FIX_Q_ACC) */
#define RFE_VEL_Q31_QV 23u    /**< vx, vy: Q23 (RFE_FIX_Q_SPEED) */
#define RFE_VEL_Q31_QB 24u    /**< offsets b_x, b_y: Q24 (RFE_FIX_Q_ACC) */
#define RFE_VEL_Q31_QDT 30u   /**< dt, the filters' f01: Q30 (RFE_FIX_Q_DT) */
#define RFE_VEL_Q31_QONE 30u  /**< an H entry of 1: Q30 */
#define RFE_VEL_Q31_ONE ((rfe_fix_t)1073741824)        /**< 1 in Q30 (an H entry) */
#define RFE_VEL_Q31_SD_RDOT0 ((rfe_fix_t)16777216)     /**< 1 rad/s^2 in Q24: r-dot's initial sd */

/** x^2 of an int32 in Q(q) as a variance in Q(2 q), clamped to RFE_KF2_Q31_PMAX (counted). */
static inline int64_t rfe_vel_var_q31(rfe_fix_t x, uint32_t *sat)
{
    int64_t v = (int64_t)x * (int64_t)x;
    if (v > RFE_KF2_Q31_PMAX) {
        rfe_fix_count_sat(sat);
        v = RFE_KF2_Q31_PMAX;
    }
    return v;
}

/** A sum of variances clamped to RFE_KF2_Q31_PMAX (counted). */
static inline int64_t rfe_vel_pmax_q31(int64_t v, uint32_t *sat)
{
    int64_t r = v;
    if (v > RFE_KF2_Q31_PMAX) {
        rfe_fix_count_sat(sat);
        r = RFE_KF2_Q31_PMAX;
    }
    return r;
}

/** round(v c / 2^s) clamped to +-RFE_KF2_Q31_PMAX (counted): rfe_kf2_scale_q31 on the
 *  callers' arguments, which always are in its domain (|v| <= PMAX, 1 <= s <= 62). */
static inline int64_t rfe_vel_scale_q31(int64_t v, rfe_fix_t c, unsigned int s, uint32_t *sat)
{
    int64_t y = 0;
    const rfe_status_t st = rfe_kf2_scale_q31(v, c, s, &y, sat);
    (void)st;
    return y;
}

/** (dt sd)^2 for dt Q30 (<= 1 s) and sd Q24: Q46, the variance of a Q23 state (dt sd
 *  exact in Q54, then two exactly rounded products). */
static inline int64_t rfe_vel_dt_var_q31(rfe_fix_t dt, rfe_fix_t sd, uint32_t *sat)
{
    const int64_t v = rfe_vel_scale_q31((int64_t)dt * (int64_t)sd, dt, 30u, sat); /* Q54 */
    return rfe_vel_scale_q31(v, sd, 32u, sat);                                  /* Q46 */
}

/** §3 each wheel's speed translated to the CoG, at lateral speed @p vy (Q23). */
void rfe_vel_wheel_refs_q31(const rfe_vehicle_q31_t *veh, const rfe_velocity_input_q31_t *in,
                            rfe_fix_t vy, rfe_fix_t refs[RFE_WHEELS], uint32_t *sat);

/** §3.2 one step of the differentiator [r, r-dot] with the measured yaw rate @p r (Q27). */
rfe_status_t rfe_vel_yaw_acc_step_q31(rfe_kf2_q31_t *f, const rfe_velocity_params_q31_t *p,
                                      rfe_fix_t dt, rfe_fix_t r, uint32_t *sat);

/** §3.3-3.5 one step of [vx, b_x]; @p vy_prev is the lateral filter's last vy. */
rfe_status_t rfe_vel_longitudinal_step_q31(rfe_kf2_q31_t *f, const rfe_velocity_params_q31_t *p,
                                           const rfe_vehicle_q31_t *veh,
                                           const rfe_velocity_input_q31_t *in,
                                           rfe_fix_t vy_prev, uint32_t *flags, uint32_t *sat);

/** §4 one step of [vy, b_y] at this step's @p vx, with the friction @p mu (NULL: the
 *  default), and of the time the yaw rate has stayed on its reference (@p on_ref, Q30,
 *  §4.2b); both written only on RFE_OK. */
rfe_status_t rfe_vel_lateral_step_q31(rfe_kf2_q31_t *f, rfe_fix_t *on_ref,
                                      const rfe_velocity_q31_t *obs,
                                      const rfe_velocity_input_q31_t *in, rfe_fix_t vx,
                                      const rfe_velocity_mu_q31_t *mu, uint32_t *flags,
                                      uint32_t *sat);

/** §5 the reported sd(vy)'s floor, Q23 (velocity_internal.h's rfe_vel_sd_vy_floor): vx Q23,
 *  the friction @p mu Q29 and its sd Q30 (NULL: the default); a result beyond Q23
 *  saturates, counted in @p sat. */
rfe_fix_t rfe_vel_sd_vy_floor_q31(const rfe_velocity_q31_t *obs,
                                  const rfe_velocity_input_q31_t *in, rfe_fix_t vx,
                                  const rfe_velocity_mu_q31_t *mu, uint32_t *sat);

#endif /* RFE_VELOCITY_INTERNAL_Q31_H */
