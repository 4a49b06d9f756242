/**
 * @file velocity_params_flt.c
 * @brief The observer's defaults and validation (docs/OBSERVER.md §2).
 */
#include "rfe/velocity_params.h"

#include "numerics/internal.h"

rfe_status_t rfe_velocity_params_default(rfe_velocity_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    p->driven = RFE_DRIVEN_FL | RFE_DRIVEN_FR;
    p->lat_every = 8u;
    p->steer_ratio = RFE_R(16.0);
    p->dt_min = RFE_R(0.001);
    p->dt_max = RFE_R(0.1);
    p->q_jerk = RFE_R(0.5);
    p->sd_r = RFE_R(0.005);
    p->sd_ax = RFE_R(0.05);
    p->sd_ay = RFE_R(0.05);
    p->q_bx = RFE_R(0.005);
    p->q_by = RFE_R(0.05);
    p->sd_wheel = RFE_R(0.05);
    p->sd_wheel_rel = RFE_R(0.005);
    p->k_gate = RFE_R(3.0);
    p->k_agree = RFE_R(3.0);
    p->v_stand = RFE_R(0.3);
    p->q_vx_brake = RFE_R(0.0);
    p->ax_brake_on = RFE_R(0.5);
    p->ax_drive_on = RFE_R(0.5);
    p->p_brake_on = RFE_R(0.2);
    p->torque_on = RFE_R(50.0);
    p->sd_model_ay = RFE_R(0.3);
    p->model_ay_rel = RFE_R(0.15);
    p->sd_model_rdot = RFE_R(0.0);
    p->sd_vydot = RFE_R(1.0);
    p->vydot_rdot = RFE_R(15.0);
    p->vydot_rerr = RFE_R(25.0);
    p->v_lat_min = RFE_R(3.0);
    p->sd_lowspeed = RFE_R(0.1);
    p->mu_default = RFE_R(1.0);
    p->sd_mu_default = RFE_R(0.3);
    p->mu_margin = RFE_R(0.1);
    p->sd_vx0 = RFE_R(1.0);
    p->sd_bx0 = RFE_R(0.3);
    p->sd_vy0 = RFE_R(0.3);
    p->sd_by0 = RFE_R(0.1);
    p->sd_vy_lin = RFE_R(0.3);
    p->lin_r_tol = RFE_R(0.01);
    p->lin_r_rel = RFE_R(0.05);
    p->lin_ay_max = RFE_R(3.0);
    p->lin_ay_steady = RFE_R(4.0);
    p->lin_dwell = RFE_R(0.125);
    p->lin_mu_gain = RFE_R(2.0);
    p->vy_out_floor_mu = RFE_R(4.0);
    p->ay_turn = RFE_R(1.0);
    p->q_bx_turn = RFE_R(0.03);
    return RFE_OK;
}

/* The fields that must be > 0, then those that must be >= 0 (docs/OBSERVER.md §2). */
static int positive_ok(const rfe_velocity_params_t *p)
{
    const rfe_real_t v[9] = {p->q_jerk,     p->sd_r,      p->sd_ax,
                             p->sd_ay,      p->v_lat_min, p->sd_lowspeed,
                             p->mu_default, p->sd_vydot,  p->steer_ratio};
    size_t i;
    for (i = 0u; i < 9u; ++i) {
        if (!rfe_is_finite(v[i]) || !(v[i] > RFE_R(0.0))) {
            return 0;
        }
    }
    return 1;
}

static int non_negative_ok(const rfe_velocity_params_t *p)
{
    const rfe_real_t v[] = {p->ay_turn, p->q_bx_turn, p->vydot_rerr, p->vy_out_floor_mu, p->lin_mu_gain, p->sd_vy_lin, p->lin_r_tol, p->lin_r_rel, p->lin_ay_max, p->lin_ay_steady, p->lin_dwell, p->sd_model_rdot, p->vydot_rdot, p->q_bx, p->q_by, p->sd_wheel, p->sd_wheel_rel, p->k_gate,
                              p->k_agree, p->v_stand, p->q_vx_brake,
                              p->ax_brake_on, p->ax_drive_on, p->p_brake_on, p->torque_on,
                              p->sd_model_ay, p->model_ay_rel, p->sd_mu_default,
                              p->mu_margin, p->sd_vx0, p->sd_bx0, p->sd_vy0, p->sd_by0};
    size_t i;
    for (i = 0u; i < (sizeof(v) / sizeof(v[0])); ++i) {
        if (!rfe_is_finite(v[i]) || !(v[i] >= RFE_R(0.0))) {
            return 0;
        }
    }
    return 1;
}

/* The fields with an upper bound (after non_negative_ok: finite). */
static int upper_bounds_ok(const rfe_velocity_params_t *p)
{
    /* lin_dwell: counted in the format of dt (Q30 in fixed point); lin_mu_gain: the
     * fixed-point floor's product stays within int64; vy_out_floor_mu: §5's factor, Q24 in
     * fixed point; vydot_rerr: Q24 in fixed point (below 128), and its term within the
     * Q24 sd (128 m/s^2) for a yaw error up to 1.28 rad/s (OBSERVER.md §4.4) */
    return ((p->lin_dwell <= RFE_R(1.0)) && (p->lin_mu_gain <= RFE_R(4.0)) &&
            (p->vy_out_floor_mu <= RFE_R(8.0)) && (p->vydot_rerr <= RFE_R(100.0))) ? 1 : 0;
}

rfe_status_t rfe_velocity_params_validate(const rfe_velocity_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    if ((p->driven == 0u) || ((p->driven & ~RFE_DRIVEN_ALL) != 0u)) {
        return RFE_ERR_PARAM;
    }
    if ((p->lat_every == 0u) || (p->lat_every > RFE_VEL_LAT_EVERY_MAX)) {
        return RFE_ERR_PARAM;
    }
    if (!rfe_is_finite(p->dt_min) || !rfe_is_finite(p->dt_max) || !(p->dt_min > RFE_R(0.0)) ||
        !(p->dt_min <= p->dt_max) || !(p->dt_max <= RFE_R(1.0))) {
        return RFE_ERR_PARAM;
    }
    if ((positive_ok(p) == 0) || (non_negative_ok(p) == 0) || (upper_bounds_ok(p) == 0)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}
