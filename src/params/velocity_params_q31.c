/**
 * @file velocity_params_q31.c
 * @brief The observer's defaults (an integer table) and validation in Q formats
 *        (rfe/velocity_params_q31.h). Integer operations only.
 */
#include "rfe/velocity_params_q31.h"

#include <stddef.h>

rfe_status_t rfe_velocity_params_default_q31(rfe_velocity_params_q31_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    /* rfe_velocity_params_to_q31_f64(rfe_velocity_params_default_f64) (the test checks it
     * bit for bit); the real value in each comment */
    p->driven = RFE_DRIVEN_FL | RFE_DRIVEN_FR;
    p->lat_every = 8u;
    p->steer_ratio = 268435456; /* 16, Q24 */
    p->dt_min = 1073742; /* 0.001 s, Q30 */
    p->dt_max = 107374182; /* 0.1 s, Q30 */
    p->q_jerk = 8388608; /* 0.5 rad/s^3 sqrt(s), Q24 */
    p->sd_r = 671089; /* 0.005 rad/s, Q27 */
    p->sd_ax = 838861; /* 0.05 m/s^2, Q24 */
    p->sd_ay = 838861; /* 0.05 m/s^2, Q24 */
    p->q_bx = 83886; /* 0.005 m/s^2/sqrt(s), Q24 */
    p->q_by = 838861; /* 0.05 m/s^2/sqrt(s), Q24 */
    p->sd_wheel = 419430; /* 0.05 m/s, Q23 */
    p->sd_wheel_rel = 5368709; /* 0.005, Q30 */
    p->k_gate = 50331648; /* 3 sd, Q24 */
    p->k_agree = 50331648; /* 3 sd, Q24 */
    p->v_stand = 2516582; /* 0.3 m/s, Q23 */
    p->q_vx_brake = 0; /* off (OBSERVER.md §2), Q23 */
    p->ax_brake_on = 8388608; /* 0.5 m/s^2, Q24 */
    p->ax_drive_on = 8388608; /* 0.5 m/s^2, Q24 */
    p->p_brake_on = 6710886; /* 0.2 MPa, Q25 */
    p->torque_on = 1638400; /* 50 N m, Q15 */
    p->sd_model_ay = 5033165; /* 0.3 m/s^2, Q24 */
    p->model_ay_rel = 161061274; /* 0.15, Q30 */
    p->sd_model_rdot = 0; /* off (OBSERVER.md §2), Q24 */
    p->sd_vydot = 16777216; /* 1 m/s^2, Q24 */
    p->vydot_rdot = 251658240; /* 15 m/s^2 per rad/s^2, Q24 */
    p->vydot_rerr = 419430400; /* 25 m/s^2 per rad/s, Q24 */
    p->v_lat_min = 25165824; /* 3 m/s, Q23 */
    p->sd_lowspeed = 838861; /* 0.1 m/s, Q23 */
    p->mu_default = 536870912; /* 1, Q29 */
    p->sd_mu_default = 322122547; /* 0.3, Q30 */
    p->mu_margin = 107374182; /* 0.1, Q30 */
    p->sd_vx0 = 8388608; /* 1 m/s, Q23 */
    p->sd_bx0 = 5033165; /* 0.3 m/s^2, Q24 */
    p->sd_vy0 = 2516582; /* 0.3 m/s, Q23 */
    p->sd_by0 = 1677722; /* 0.1 m/s^2, Q24 */
    p->sd_vy_lin = 2516582; /* 0.3 m/s, Q23 */
    p->lin_r_tol = 1342177; /* 0.01 rad/s, Q27 */
    p->lin_r_rel = 53687091; /* 0.05, Q30 */
    p->lin_ay_max = 50331648; /* 3 m/s^2, Q24 */
    p->lin_ay_steady = 67108864; /* 4 m/s^2, Q24 */
    p->lin_dwell = 134217728; /* 0.125 s, Q30 */
    p->lin_mu_gain = 33554432; /* 2, Q24 */
    p->vy_out_floor_mu = 67108864; /* 4, Q24 */
    p->ay_turn = 16777216; /* 1 m/s^2, Q24 */
    p->q_bx_turn = 503316; /* 0.03 m/s^2/sqrt(s), Q24 */
    return RFE_OK;
}

/* The fields that must be > 0, then those that must be >= 0 (docs/OBSERVER.md §2). */
static int positive_ok_q31(const rfe_velocity_params_q31_t *p)
{
    const rfe_fix_t v[9] = {p->q_jerk,     p->sd_r,      p->sd_ax,
                            p->sd_ay,      p->v_lat_min, p->sd_lowspeed,
                            p->mu_default, p->sd_vydot,  p->steer_ratio};
    size_t i;
    for (i = 0u; i < 9u; ++i) {
        if (v[i] <= 0) {
            return 0;
        }
    }
    return 1;
}

static int non_negative_ok_q31(const rfe_velocity_params_q31_t *p)
{
    const rfe_fix_t v[] = {p->ay_turn, p->q_bx_turn, p->vydot_rerr, p->vy_out_floor_mu, p->lin_mu_gain, p->sd_vy_lin, p->lin_r_tol, p->lin_r_rel, p->lin_ay_max, p->lin_ay_steady, p->lin_dwell, p->sd_model_rdot, p->vydot_rdot, p->q_bx, p->q_by, p->sd_wheel, p->sd_wheel_rel,
                             p->k_gate, p->k_agree, p->v_stand, p->q_vx_brake, p->ax_brake_on, p->ax_drive_on, p->p_brake_on,
                             p->torque_on, p->sd_model_ay, p->model_ay_rel, p->sd_mu_default,
                             p->mu_margin, p->sd_vx0, p->sd_bx0, p->sd_vy0, p->sd_by0};
    size_t i;
    for (i = 0u; i < (sizeof(v) / sizeof(v[0])); ++i) {
        if (v[i] < 0) {
            return 0;
        }
    }
    return 1;
}

/* The fields with an upper bound. */
static int upper_bounds_ok_q31(const rfe_velocity_params_q31_t *p)
{
    /* lin_dwell at most 1 s: the dwell plus a period stays within Q30; lin_mu_gain at most 4
     * (Q24): gain times |ay| stays within int64; vy_out_floor_mu at most 8 (Q24), as the
     * float check; vydot_rerr at most 100 (Q24: 1677721600), as the float check */
    return ((p->lin_dwell <= RFE_FIX_ONE(30)) && (p->lin_mu_gain <= RFE_FIX_ONE(26)) &&
            (p->vy_out_floor_mu <= RFE_FIX_ONE(27)) &&
            (p->vydot_rerr <= 1677721600)) ? 1 : 0;
}

rfe_status_t rfe_velocity_params_validate_q31(const rfe_velocity_params_q31_t *p)
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
    if ((p->dt_min <= 0) || (p->dt_min > p->dt_max) || (p->dt_max > RFE_FIX_ONE(30))) {
        return RFE_ERR_PARAM;
    }
    if ((positive_ok_q31(p) == 0) || (non_negative_ok_q31(p) == 0) ||
        (upper_bounds_ok_q31(p) == 0)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}
