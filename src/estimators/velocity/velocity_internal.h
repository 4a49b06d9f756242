/**
 * @file velocity_internal.h
 * @brief The velocity observer's steps (docs/OBSERVER.md), one module each: the yaw-rate
 *        differentiator (yaw_acc_flt.c, §3.2), the longitudinal filter
 *        (longitudinal_flt.c, §3.3-3.5) and the lateral filter (lateral_flt.c, §4).
 *        velocity_flt.c composes them. Each works on the filter it is given and leaves it
 *        untouched on error.
 */
#ifndef RFE_VELOCITY_INTERNAL_H
#define RFE_VELOCITY_INTERNAL_H

#include "rfe/velocity.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_vel_wheel_refs        rfe_vel_wheel_refs_f64
#define rfe_vel_yaw_acc_step      rfe_vel_yaw_acc_step_f64
#define rfe_vel_longitudinal_step rfe_vel_longitudinal_step_f64
#define rfe_vel_lateral_step      rfe_vel_lateral_step_f64
#define rfe_vel_sd_vy_floor       rfe_vel_sd_vy_floor_f64
#else
#define rfe_vel_wheel_refs        rfe_vel_wheel_refs_f32
#define rfe_vel_yaw_acc_step      rfe_vel_yaw_acc_step_f32
#define rfe_vel_longitudinal_step rfe_vel_longitudinal_step_f32
#define rfe_vel_lateral_step      rfe_vel_lateral_step_f32
#define rfe_vel_sd_vy_floor       rfe_vel_sd_vy_floor_f32
#endif

/** §3 each wheel's speed translated to the CoG, at lateral speed @p vy. */
void rfe_vel_wheel_refs(const rfe_vehicle_t *veh, const rfe_velocity_input_t *in, rfe_real_t vy,
                        rfe_real_t refs[RFE_WHEELS]);

/** §3.2 one step of the differentiator [r, r-dot] with the measured yaw rate @p r. */
rfe_status_t rfe_vel_yaw_acc_step(rfe_kf2_t *f, const rfe_velocity_params_t *p, rfe_real_t dt,
                                  rfe_real_t r);

/** §3.3-3.5 one step of [vx, b_x]; @p vy_prev is the lateral filter's last vy. Sets the
 *  braking / driving / wheel flags in @p flags. */
rfe_status_t rfe_vel_longitudinal_step(rfe_kf2_t *f, const rfe_velocity_params_t *p,
                                       const rfe_vehicle_t *veh, const rfe_velocity_input_t *in,
                                       rfe_real_t vy_prev, uint32_t *flags);

/** §4 one step of [vy, b_y] at this step's @p vx, with the friction @p mu (NULL: the
 *  default), and of the time the yaw rate has stayed on its reference (@p on_ref, §4.2b);
 *  both written only on RFE_OK. Sets the model / low-speed / raised-friction / linear-range
 *  flags in @p flags. */
rfe_status_t rfe_vel_lateral_step(rfe_kf2_t *f, rfe_real_t *on_ref, const rfe_velocity_t *obs,
                                  const rfe_velocity_input_t *in, rfe_real_t vx,
                                  const rfe_velocity_mu_t *mu, uint32_t *flags);

/** §5 the reported sd(vy)'s floor: vy_out_floor_mu |vx ay / (cy g)| max_i sd_i / m_i, m_i the
 *  friction @p mu (NULL: the default) raised to (1 + mu_margin) |ay| / g as §4.2 raises it
 *  (wheels with m_i = 0 left out), at this step's @p vx. The caller decides whether it
 *  applies (rfe_vel_out_floor_due). */
rfe_real_t rfe_vel_sd_vy_floor(const rfe_velocity_t *obs, const rfe_velocity_input_t *in,
                               rfe_real_t vx, const rfe_velocity_mu_t *mu);

#endif /* RFE_VELOCITY_INTERNAL_H */
