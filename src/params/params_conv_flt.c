/**
 * @file params_conv_flt.c
 * @brief rfe_params_t -> rfe_params_q31_t (rfe/component/params_conv.h). A float translation unit: it
 *        is built into the float and double libraries, never into the fixed-point one.
 *
 * Every value is first widened to double (explicit casts: the float build then converts the
 * float parameters exactly), derived constants are computed in double from the real values
 * (relative error ~1e-16, far below the 2^-31 resolution of any Q format used) and each value
 * is rounded once to its format.
 */
#include "rfe/component/params_conv.h"

#include "rfe/component/fxmath.h" /* RFE_FIX_TAN_LIMIT_Q29 only: no call into the fixed-point library */

#include "numerics/internal.h"
#include "numerics/round_half_up.h"

/* Smallest magnitude, in LSB, of a value that must carry 16 significant bits. */
#define MIN_SIGNIFICANT 65536.0

/* Conversion state: set to 1 when a value does not fit its format. */
typedef struct {
    int bad;
} conv_t;

/* round(x * 2^q) to nearest, ties up (numerics/round_half_up.h, the host's rule too); flags a value that is not finite, rounds
 * beyond +-INT32_MAX, is nonzero but rounds to 0, or (need16) is nonzero and below 2^16 LSB. */
static rfe_fix_t to_q(conv_t *c, double x, int q, int need16)
{
    const double y = ldexp(x, q);
    rfe_fix_t v = 0;

    if (!(fabs(y) <= (double)RFE_FIX_MAX)) { /* also NaN and +-inf */
        c->bad = 1;
    } else {
        const double r = rfe_round_half_up(y);
        if (!(fabs(r) <= (double)RFE_FIX_MAX) ||
            ((x != 0.0) && ((r == 0.0) || ((need16 != 0) && (fabs(r) < MIN_SIGNIFICANT))))) {
            c->bad = 1;
        } else {
            v = (rfe_fix_t)r;
        }
    }
    return v;
}

static void conv_vehicle(conv_t *c, const rfe_vehicle_t *v, rfe_vehicle_q31_t *q)
{
    const double m = (double)v->m;
    const double Lf = (double)v->Lf;
    const double Lr = (double)v->Lr;
    const double Bf = (double)v->Bf;
    const double Br = (double)v->Br;
    const double J = (double)v->J;
    const double hg = (double)v->hg;
    const double g = (double)v->g;
    const double La = Lf + Lr;

    q->m = to_q(c, m, RFE_FIX_Q_MASS, 1);
    q->Lf = to_q(c, Lf, RFE_FIX_Q_LEN, 1);
    q->Lr = to_q(c, Lr, RFE_FIX_Q_LEN, 1);
    q->Bf = to_q(c, Bf, RFE_FIX_Q_LEN, 1);
    q->Br = to_q(c, Br, RFE_FIX_Q_LEN, 1);
    q->R = to_q(c, (double)v->R, RFE_FIX_Q_LEN, 0);
    q->J = to_q(c, J, RFE_FIX_Q_INERTIA, 1);
    q->hg = to_q(c, hg, RFE_FIX_Q_LEN, 1);
    q->g = to_q(c, g, RFE_FIX_Q_ACC, 1);
    /* Derived (MODEL.md §3 loads, §5 H). */
    q->yf = to_q(c, 0.5 * Bf, RFE_FIX_Q_LEN, 1);
    q->yr = to_q(c, 0.5 * Br, RFE_FIX_Q_LEN, 1);
    q->inv_m = to_q(c, 1.0 / m, RFE_FIX_Q_INV, 1);
    q->lf_J = to_q(c, Lf / J, RFE_FIX_Q_INV, 1);
    q->lr_J = to_q(c, Lr / J, RFE_FIX_Q_INV, 1);
    q->yf_J = to_q(c, 0.5 * Bf / J, RFE_FIX_Q_INV, 1);
    q->yr_J = to_q(c, 0.5 * Br / J, RFE_FIX_Q_INV, 1);
    q->fz_static_f = to_q(c, m * g * Lr / (2.0 * La), RFE_FIX_Q_FORCE, 1);
    q->fz_static_r = to_q(c, m * g * Lf / (2.0 * La), RFE_FIX_Q_FORCE, 1);
    q->k_pitch = to_q(c, m * hg / (2.0 * La), RFE_FIX_Q_KLOAD, 1);
    q->k_roll_f = to_q(c, m * hg * Lr / (La * Bf), RFE_FIX_Q_KLOAD, 1);
    q->k_roll_r = to_q(c, m * hg * Lf / (La * Br), RFE_FIX_Q_KLOAD, 1);
}

/* The rounded shape factors still inside 1 < C < 2 and E < 1 (Q24; E >= -4 holds after
 * rounding whenever it held before: -4 is exact). */
static int shape_fits(rfe_fix_t C, rfe_fix_t E)
{
    const rfe_fix_t one = RFE_FIX_ONE(RFE_FIX_Q_STIFF);
    return (C > one) && (C < (2 * one)) && (E < one);
}

static void conv_tyre(conv_t *c, const rfe_tyre_params_t *t, rfe_tyre_params_q31_t *q)
{
    q->mode = t->mode;
    q->Cx_n = to_q(c, (double)t->Cx_n, RFE_FIX_Q_STIFF, 0);
    q->Cy_n = to_q(c, (double)t->Cy_n, RFE_FIX_Q_STIFF, 0);
    q->cx = to_q(c, (double)t->cx, RFE_FIX_Q_STIFF, 0);
    q->cy = to_q(c, (double)t->cy, RFE_FIX_Q_STIFF, 0);
    q->eps = to_q(c, (double)t->eps, RFE_FIX_Q_EPS, 0);
    q->v_min = to_q(c, (double)t->v_min, RFE_FIX_Q_SPEED, 0);
    q->alpha_max = to_q(c, (double)t->alpha_max, RFE_FIX_Q_ANGLE, 0);
    q->shape_Cx = to_q(c, (double)t->shape_Cx, RFE_FIX_Q_STIFF, 0);
    q->shape_Ex = to_q(c, (double)t->shape_Ex, RFE_FIX_Q_STIFF, 0);
    q->shape_Cy = to_q(c, (double)t->shape_Cy, RFE_FIX_Q_STIFF, 0);
    q->shape_Ey = to_q(c, (double)t->shape_Ey, RFE_FIX_Q_STIFF, 0);
    /* rfe_params_validate keeps alpha_max < 1.5 rad; the rounded value must stay below too
     * (the fixed-point tan's domain, RFE_FIX_TAN_LIMIT_Q29, ends at 1.5 rad). */
    if (q->alpha_max >= RFE_FIX_TAN_LIMIT_Q29) {
        c->bad = 1;
    }
    /* The same for the shape factors' open bounds (1 < C < 2, E < 1): a value within half an
     * LSB (2^-25) of one rounds onto it (C = 1 + 1e-9, E = 1 - 1e-9). */
    if (!shape_fits(q->shape_Cx, q->shape_Ex) || !shape_fits(q->shape_Cy, q->shape_Ey)) {
        c->bad = 1;
    }
}

static void conv_filter(conv_t *c, const rfe_filter_params_t *f, rfe_filter_params_q31_t *q)
{
    const double dt = (double)f->dt;
    const double tau = (double)f->tau_v;

    q->kind = f->kind;
    q->structure = f->structure;
    q->mu0 = to_q(c, (double)f->mu0, RFE_FIX_Q_MU, 0);
    q->sd0 = to_q(c, (double)f->sd0, RFE_FIX_Q_SD, 0);
    q->q_mu = to_q(c, (double)f->q_mu, RFE_FIX_Q_SD, 0);
    q->r_ax = to_q(c, (double)f->r_ax, RFE_FIX_Q_ACC, 0);
    q->r_ay = to_q(c, (double)f->r_ay, RFE_FIX_Q_ACC, 0);
    q->r_yaw_acc = to_q(c, (double)f->r_yaw_acc, RFE_FIX_Q_ACC, 0);
    q->mu_min = to_q(c, (double)f->mu_min, RFE_FIX_Q_MU, 0);
    q->mu_max = to_q(c, (double)f->mu_max, RFE_FIX_Q_MU, 0);
    q->v_est_min = to_q(c, (double)f->v_est_min, RFE_FIX_Q_SPEED, 0);
    q->sd0_common = to_q(c, (double)f->sd0_common, RFE_FIX_Q_SD, 0);
    q->q_common = to_q(c, (double)f->q_common, RFE_FIX_Q_SD, 0);
    q->dt = to_q(c, dt, RFE_FIX_Q_DT, 1);
    q->tau_v = to_q(c, tau, RFE_FIX_Q_TAU, 1);
    q->sd_in_delta = to_q(c, (double)f->sd_in_delta, RFE_FIX_Q_ANGLE, 0);
    q->sd_in_vx = to_q(c, (double)f->sd_in_vx, RFE_FIX_Q_SPEED, 0);
    q->sd_in_vy = to_q(c, (double)f->sd_in_vy, RFE_FIX_Q_SPEED, 0);
    q->sd_in_yaw_rate = to_q(c, (double)f->sd_in_yaw_rate, RFE_FIX_Q_YAWRATE, 0);
    q->sd_in_omega = to_q(c, (double)f->sd_in_omega, RFE_FIX_Q_OMEGA, 0);
    q->r_model_rel = to_q(c, (double)f->r_model_rel, RFE_FIX_Q_SD, 0);
    q->info_min = to_q(c, (double)f->info_min, RFE_FIX_Q_INFO, 0);
    q->sd_max = to_q(c, (double)f->sd_max, RFE_FIX_Q_SD, 0);
    q->sd_floor_rel = to_q(c, (double)f->sd_floor_rel, RFE_FIX_Q_SD, 0);
    q->sd_valid = to_q(c, (double)f->sd_valid, RFE_FIX_Q_SD, 0);
    q->rear_hold_k = to_q(c, (double)f->rear_hold_k, RFE_FIX_Q_HOLD, 0);
    q->jump_hold_k = to_q(c, (double)f->jump_hold_k, RFE_FIX_Q_HOLD, 0);
    q->jump_hold_len = to_q(c, (double)f->jump_hold_len, RFE_FIX_Q_HOLD_LEN, 0);
    q->stale_omega = to_q(c, (double)f->stale_omega, RFE_FIX_Q_OMEGA, 0);
    q->yaw_check = to_q(c, (double)f->yaw_check, RFE_FIX_Q_YAWRATE, 0);
    q->valid_bound_k = to_q(c, (double)f->valid_bound_k, RFE_FIX_Q_BOUND_K, 0);
    q->b_v = to_q(c, dt / (tau + dt), RFE_FIX_Q_DT, 1);
}

/* The monitor's integer constants: rfe_monitor_consts' weights, quantiles and step counts at
 * dt (in the real type of this build, as rfe_monitor_init has them), each rounded to its format. A weight
 * needs 16 significant bits (>= 2^-14: tau <= 16383 dt) and a quantile at most 8 (a
 * probability >= ~1e-15): else RFE_ERR_RANGE (also when the init finds 1 - p equal to 1). */
static void conv_monitor(conv_t *c, const rfe_monitor_params_t *mp, rfe_real_t dt,
                         rfe_monitor_params_q31_t *q)
{
    rfe_monitor_consts_t k = {0};
    /* mp was validated at this dt (rfe_params_validate); the constants are refused only for a
     * probability so small that 1 - p rounds to 1 in the real type: beyond any quantile's
     * format */
    if (rfe_monitor_consts(mp, dt, &k) != RFE_OK) {
        c->bad = 1;
    }
    q->enable = 0u;
    if (mp->enable != RFE_R(0.0)) {
        q->enable = 1u;
    }
    q->inflate = 0u;
    if (mp->inflate != RFE_R(0.0)) {
        q->inflate = 1u;
    }
    q->hold_steps = k.hold_steps;
    q->warmup_steps = k.warmup_steps;
    q->l_d = to_q(c, (double)k.l_d, RFE_FIX_Q_MON_L, 1);
    q->l_m = to_q(c, (double)k.l_m, RFE_FIX_Q_MON_L, 1);
    q->z_d_fire = to_q(c, (double)k.z_d_fire, RFE_FIX_Q_MON_Z, 0);
    q->z_d_clear = to_q(c, (double)k.z_d_clear, RFE_FIX_Q_MON_Z, 0);
    q->z_m_fire = to_q(c, (double)k.z_m_fire, RFE_FIX_Q_MON_Z, 0);
    q->z_m_clear = to_q(c, (double)k.z_m_clear, RFE_FIX_Q_MON_Z, 0);
    if ((q->z_d_fire > RFE_FIX_MON_Z_MAX) || (q->z_m_fire > RFE_FIX_MON_Z_MAX)) {
        c->bad = 1;
    }
}

rfe_status_t rfe_params_to_q31(const rfe_params_t *p, rfe_params_q31_t *q)
{
    rfe_params_q31_t t;
    conv_t c = {0};
    rfe_status_t st;

    if ((p == NULL) || (q == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_params_validate(p);
    if (st != RFE_OK) {
        return st;
    }
    conv_vehicle(&c, &p->vehicle, &t.vehicle);
    conv_tyre(&c, &p->tyre, &t.tyre);
    conv_filter(&c, &p->filter, &t.filter);
    conv_monitor(&c, &p->monitor, p->filter.dt, &t.monitor);
    if (c.bad != 0) {
        return RFE_ERR_RANGE;
    }
    *q = t;
    return RFE_OK;
}

rfe_status_t rfe_velocity_params_to_q31(const rfe_velocity_params_t *p,
                                        rfe_velocity_params_q31_t *q)
{
    rfe_velocity_params_q31_t t;
    conv_t c = {0};
    rfe_status_t st;

    if ((p == NULL) || (q == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_velocity_params_validate(p);
    if (st != RFE_OK) {
        return st;
    }
    t.driven = p->driven;
    t.lat_every = p->lat_every;
    t.steer_ratio = to_q(&c, (double)p->steer_ratio, RFE_FIX_Q_RATIO, 0);
    t.dt_min = to_q(&c, (double)p->dt_min, RFE_FIX_Q_DT, 0);
    t.dt_max = to_q(&c, (double)p->dt_max, RFE_FIX_Q_DT, 0);
    t.q_jerk = to_q(&c, (double)p->q_jerk, RFE_FIX_Q_ACC, 0);
    t.sd_r = to_q(&c, (double)p->sd_r, RFE_FIX_Q_YAWRATE, 0);
    t.sd_ax = to_q(&c, (double)p->sd_ax, RFE_FIX_Q_ACC, 0);
    t.sd_ay = to_q(&c, (double)p->sd_ay, RFE_FIX_Q_ACC, 0);
    t.q_bx = to_q(&c, (double)p->q_bx, RFE_FIX_Q_ACC, 0);
    t.q_by = to_q(&c, (double)p->q_by, RFE_FIX_Q_ACC, 0);
    t.sd_wheel = to_q(&c, (double)p->sd_wheel, RFE_FIX_Q_SPEED, 0);
    t.sd_wheel_rel = to_q(&c, (double)p->sd_wheel_rel, RFE_FIX_Q_SD, 0);
    t.k_gate = to_q(&c, (double)p->k_gate, RFE_FIX_Q_RATIO, 0);
    t.k_agree = to_q(&c, (double)p->k_agree, RFE_FIX_Q_RATIO, 0);
    t.v_stand = to_q(&c, (double)p->v_stand, RFE_FIX_Q_SPEED, 0);
    t.q_vx_brake = to_q(&c, (double)p->q_vx_brake, RFE_FIX_Q_SPEED, 0);
    t.ax_brake_on = to_q(&c, (double)p->ax_brake_on, RFE_FIX_Q_ACC, 0);
    t.ax_drive_on = to_q(&c, (double)p->ax_drive_on, RFE_FIX_Q_ACC, 0);
    t.p_brake_on = to_q(&c, (double)p->p_brake_on, RFE_FIX_Q_PRESSURE, 0);
    t.torque_on = to_q(&c, (double)p->torque_on, RFE_FIX_Q_TORQUE, 0);
    t.sd_model_ay = to_q(&c, (double)p->sd_model_ay, RFE_FIX_Q_ACC, 0);
    t.model_ay_rel = to_q(&c, (double)p->model_ay_rel, RFE_FIX_Q_SD, 0);
    t.sd_model_rdot = to_q(&c, (double)p->sd_model_rdot, RFE_FIX_Q_ACC, 0);
    t.sd_vydot = to_q(&c, (double)p->sd_vydot, RFE_FIX_Q_ACC, 0);
    t.vydot_rdot = to_q(&c, (double)p->vydot_rdot, RFE_FIX_Q_RATIO, 0);
    t.vydot_rerr = to_q(&c, (double)p->vydot_rerr, RFE_FIX_Q_RATIO, 0);
    t.v_lat_min = to_q(&c, (double)p->v_lat_min, RFE_FIX_Q_SPEED, 0);
    t.sd_lowspeed = to_q(&c, (double)p->sd_lowspeed, RFE_FIX_Q_SPEED, 0);
    t.mu_default = to_q(&c, (double)p->mu_default, RFE_FIX_Q_MU, 0);
    t.sd_mu_default = to_q(&c, (double)p->sd_mu_default, RFE_FIX_Q_SD, 0);
    t.mu_margin = to_q(&c, (double)p->mu_margin, RFE_FIX_Q_SD, 0);
    t.sd_vx0 = to_q(&c, (double)p->sd_vx0, RFE_FIX_Q_SPEED, 0);
    t.sd_bx0 = to_q(&c, (double)p->sd_bx0, RFE_FIX_Q_ACC, 0);
    t.sd_vy0 = to_q(&c, (double)p->sd_vy0, RFE_FIX_Q_SPEED, 0);
    t.sd_by0 = to_q(&c, (double)p->sd_by0, RFE_FIX_Q_ACC, 0);
    t.sd_vy_lin = to_q(&c, (double)p->sd_vy_lin, RFE_FIX_Q_SPEED, 0);
    t.lin_r_tol = to_q(&c, (double)p->lin_r_tol, RFE_FIX_Q_YAWRATE, 0);
    t.lin_r_rel = to_q(&c, (double)p->lin_r_rel, RFE_FIX_Q_SD, 0);
    t.lin_ay_max = to_q(&c, (double)p->lin_ay_max, RFE_FIX_Q_ACC, 0);
    t.lin_ay_steady = to_q(&c, (double)p->lin_ay_steady, RFE_FIX_Q_ACC, 0);
    t.lin_dwell = to_q(&c, (double)p->lin_dwell, RFE_FIX_Q_DT, 0);
    t.lin_mu_gain = to_q(&c, (double)p->lin_mu_gain, RFE_FIX_Q_RATIO, 0);
    t.vy_out_floor_mu = to_q(&c, (double)p->vy_out_floor_mu, RFE_FIX_Q_RATIO, 0);
    t.ay_turn = to_q(&c, (double)p->ay_turn, RFE_FIX_Q_ACC, 0);
    t.q_bx_turn = to_q(&c, (double)p->q_bx_turn, RFE_FIX_Q_ACC, 0);
    /* dt_max = 1 s and lin_dwell = 1 s are Q30's 2^30 exactly: within int32 */
    if (c.bad != 0) {
        return RFE_ERR_RANGE;
    }
    *q = t;
    return RFE_OK;
}

rfe_status_t rfe_mass_grade_params_to_q31(const rfe_mass_grade_params_t *p,
                                          rfe_mass_grade_params_q31_t *q)
{
    rfe_mass_grade_params_q31_t t;
    conv_t c = {0};
    rfe_status_t st;

    if ((p == NULL) || (q == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_mass_grade_params_validate(p);
    if (st != RFE_OK) {
        return st;
    }
    t.R = to_q(&c, (double)p->R, RFE_MG_Q_R, 0);
    t.g = to_q(&c, (double)p->g, RFE_MG_Q_G, 0);
    t.fc = to_q(&c, (double)p->fc, RFE_MG_Q_FC, 0);
    t.fr = to_q(&c, (double)p->fr, RFE_MG_Q_FR, 0);
    t.rho = to_q(&c, (double)p->rho, RFE_MG_Q_COEF, 0);
    t.cd = to_q(&c, (double)p->cd, RFE_MG_Q_COEF, 0);
    t.area = to_q(&c, (double)p->area, RFE_MG_Q_COEF, 0);
    t.m_rot = to_q(&c, (double)p->m_rot, RFE_MG_Q_M, 0);
    t.m0 = to_q(&c, (double)p->m0, RFE_MG_Q_M, 0);
    t.theta0 = to_q(&c, (double)p->theta0, RFE_MG_Q_TH, 0);
    t.sd_m0 = to_q(&c, (double)p->sd_m0, RFE_MG_Q_M, 0);
    t.sd_theta0 = to_q(&c, (double)p->sd_theta0, RFE_MG_Q_TH, 0);
    t.q_v = to_q(&c, (double)p->q_v, RFE_MG_Q_V, 0);
    t.q_mc = to_q(&c, (double)p->q_mc, RFE_MG_Q_M, 0);
    t.q_mv0 = to_q(&c, (double)p->q_mv0, RFE_MG_Q_M, 0);
    t.q_theta = to_q(&c, (double)p->q_theta, RFE_MG_Q_TH, 0);
    t.r_v = to_q(&c, (double)p->r_v, RFE_MG_Q_V, 0);
    t.r_ax = to_q(&c, (double)p->r_ax, RFE_MG_Q_V, 0);
    t.ut_alpha = to_q(&c, (double)p->ut_alpha, RFE_MG_Q_UT, 0);
    t.ut_beta = to_q(&c, (double)p->ut_beta, RFE_MG_Q_UT, 0);
    t.ut_kappa = to_q(&c, (double)p->ut_kappa, RFE_MG_Q_UT, 0);
    t.adaptive = p->adaptive;
    t.use_ax = p->use_ax;
    t.t_adapt = to_q(&c, (double)p->t_adapt, RFE_MG_Q_TIME, 0);
    t.mv_stop = to_q(&c, (double)p->mv_stop, RFE_MG_Q_COEF, 0);
    t.v_min = to_q(&c, (double)p->v_min, RFE_MG_Q_V, 0);
    t.t_brake = to_q(&c, (double)p->t_brake, RFE_MG_Q_TIME, 0);
    t.t_shift = to_q(&c, (double)p->t_shift, RFE_MG_Q_TIME, 0);
    t.p_brake_on = to_q(&c, (double)p->p_brake_on * 1e-6, RFE_MG_Q_PRESSURE, 0); /* Pa -> MPa */
    t.slip_max = to_q(&c, (double)p->slip_max, RFE_MG_Q_FC, 0);
    t.ay_max = to_q(&c, (double)p->ay_max, RFE_MG_Q_V, 0);
    t.t_curve = to_q(&c, (double)p->t_curve, RFE_MG_Q_TIME, 0);
    t.pause_grade = (uint32_t)p->pause_grade; /* validated above: an integer in 0..7 */
    t.pause_grade_slip = to_q(&c, (double)p->pause_grade_slip, RFE_MG_Q_FC, 0);
    t.pause_grade_dv = to_q(&c, (double)p->pause_grade_dv, RFE_MG_Q_V, 0);
    t.m_min = to_q(&c, (double)p->m_min, RFE_MG_Q_M, 0);
    t.m_max = to_q(&c, (double)p->m_max, RFE_MG_Q_M, 0);
    t.theta_max = to_q(&c, (double)p->theta_max, RFE_MG_Q_TH, 0);
    t.dt_max = to_q(&c, (double)p->dt_max, RFE_MG_Q_DT, 0);
    t.q_theta_hi = to_q(&c, (double)p->q_theta_hi, RFE_MG_Q_TH, 0);
    t.theta_rate_on = to_q(&c, (double)p->theta_rate_on, RFE_MG_Q_RATE, 0);
    t.theta_rate_off = to_q(&c, (double)p->theta_rate_off, RFE_MG_Q_RATE, 0);
    t.theta_rate_tau = to_q(&c, (double)p->theta_rate_tau, RFE_MG_Q_TIME, 0);
    t.theta_rate_avg = to_q(&c, (double)p->theta_rate_avg, RFE_MG_Q_TIME, 0);
    t.mm_tau = to_q(&c, (double)p->mm_tau, RFE_MG_Q_TIME, 0);
    t.mm_e = to_q(&c, (double)p->mm_e, RFE_MG_Q_E, 0);
    if (c.bad != 0) {
        return RFE_ERR_RANGE;
    }
    *q = t;
    return RFE_OK;
}
