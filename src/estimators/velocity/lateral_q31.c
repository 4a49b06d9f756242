/**
 * @file lateral_q31.c
 * @brief The lateral filter [vy Q23, b_y Q24] in fixed point (docs/OBSERVER.md §4; twin of
 *        lateral_flt.c, the same steps in the same order): ay - r vx integrated, held by the
 *        friction estimator's Q31 measurement model (rfe/component/meas_q31.h) at its last
 *        friction, which the measured ay bounds from below: its lateral acceleration
 *        against the measured ay, its yaw acceleration against the differentiator's.
 */
#include "estimators/velocity/velocity_internal_q31.h"

#include "rfe/component/fxmath.h"
#include "rfe/component/meas_q31.h"

#include "numerics/internal_q31.h"

#include "estimators/velocity/velocity_logic.h"

/* The model's rows ay and r-dot of h(mu, u) at vy (Q23) and their derivatives by vy and by
 * the friction in the direction of its sd (Q30) (§4.2), Q24, from one set-up at vy. */
static rfe_status_t model_rows_q31(const rfe_velocity_q31_t *obs,
                                   const rfe_velocity_input_q31_t *in, rfe_fix_t vx,
                                   rfe_fix_t vy, const rfe_fix_t mu[RFE_WHEELS],
                                   const rfe_fix_t sd[RFE_WHEELS], rfe_meas_lateral_q31_t *rows,
                                   uint32_t *sat)
{
    rfe_meas_q31_t h;
    rfe_sample_q31_t u;
    size_t i;
    rfe_status_t st;
    u.delta = in->delta;
    u.vx = vx;
    u.vy = vy;
    u.yaw_rate = in->yaw_rate;
    u.yaw_acc = 0; /* not used by the model */
    u.ax = in->ax;
    u.ay = in->ay;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        u.omega[i] = in->omega[i];
    }
    st = rfe_meas_setup_q31(&h, &obs->veh, &obs->tyre, &u, sat);
    if (st == RFE_OK) {
        st = rfe_meas_lateral_jac_q31(&h, &obs->veh, &obs->tyre, &u, mu, sd, rows, sat);
    }
    return st;
}

/* The model's friction (§4.2), Q29: the input or the default, raised to what the measured
 * ay proves, (1 + margin) |ay| / g, and in a steady turn of the linear range (@p lin_floor)
 * to at least lin_mu_gain |ay| / g; and its sd (Q30). Returns 1 when the bound raised a
 * wheel. */
static int model_friction_q31(const rfe_velocity_params_q31_t *p, rfe_fix_t g, rfe_fix_t ay,
                              int lin_floor, const rfe_velocity_mu_q31_t *in,
                              rfe_fix_t mu[RFE_WHEELS], rfe_fix_t sd_mu[RFE_WHEELS],
                              uint32_t *sat)
{
    /* the gain in Q30: 1 + margin (below 2^32), or lin_mu_gain Q24 times 2^6 (exact; at most
     * 4, 2^32, after the parameter check); times |ay| Q24 (below 2^31): Q54 below 2^63,
     * exact in int64; over g Q24 into Q29 after one rounding shift to Q53 (g > 0 after the
     * parameter check) */
    const int64_t margin = (int64_t)RFE_FIX_ONE(30) + (int64_t)p->mu_margin;
    const int64_t steady = (int64_t)p->lin_mu_gain * (int64_t)64;
    const int64_t higher = (steady > margin) ? steady : margin;
    const int64_t gain = (lin_floor != 0) ? higher : margin;
    const int64_t num = gain * (int64_t)rfe_fix_abs(ay, sat);
    const rfe_fix_t mu_low = rfe_q31_div_round(rfe_fix_shr64_round(num, 1u), g, sat);
    int raised = 0;
    size_t i;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        const rfe_fix_t m = (in != NULL) ? in->mu[i] : p->mu_default;
        if (m < mu_low) {
            raised = 1;
        }
        mu[i] = rfe_fix_max(m, mu_low);
        sd_mu[i] = (in != NULL) ? in->sd[i] : p->sd_mu_default;
    }
    return raised;
}

/* §5 the reported sd(vy)'s floor k s rho (lateral_flt.c's rfe_vel_sd_vy_floor), without a
 * division per wheel: the wheel of the largest rho = sd_i / m_i (sd Q30, m Q29, the friction
 * raised to the margin's bound as model_friction_q31 raises it) found by exact cross
 * products (each below 2^62 in int64); s = |vx ay / (cy g)| as linear_update_q31 forms it
 * (ay Q24 over cy g Q20 into Q29, times vx Q23 into Q23); s sd (Q23 Q30 = Q53, below 2^62)
 * rounded to Q52 over m (Q29) into Q23, one rounded division; times k (Q24) into Q23. Bound:
 * m >= (1 + margin) |ay| / g, so s rho <= vx sd / (cy (1 + margin)), within Q23 (256 m/s)
 * for vx, sd and cy of a car; beyond it the quotient and the product saturate, counted. */
rfe_fix_t rfe_vel_sd_vy_floor_q31(const rfe_velocity_q31_t *obs,
                                  const rfe_velocity_input_q31_t *in, rfe_fix_t vx,
                                  const rfe_velocity_mu_q31_t *mu, uint32_t *sat)
{
    rfe_fix_t mm[RFE_WHEELS];
    rfe_fix_t sd[RFE_WHEELS];
    rfe_fix_t best_sd = 0;
    rfe_fix_t best_m = RFE_FIX_ONE(29);
    rfe_fix_t out = 0;
    size_t i;
    (void)model_friction_q31(&obs->p, obs->veh.g, in->ay, 0, mu, mm, sd, sat);
    for (i = 0u; i < RFE_WHEELS; ++i) {
        if ((mm[i] > 0) && (((int64_t)sd[i] * (int64_t)best_m) > ((int64_t)best_sd * (int64_t)mm[i]))) {
            best_sd = sd[i];
            best_m = mm[i];
        }
    }
    if (best_sd > 0) {
        const rfe_fix_t cg = rfe_fix_mul(obs->tyre.cy, obs->veh.g, 28u, sat);
        rfe_fix_t b = 0;
        const rfe_status_t s = rfe_fix_div(in->ay, cg, 25, &b, sat);
        const rfe_fix_t slip = rfe_fix_abs(rfe_fix_mul(vx, b, 29u, sat), sat);
        const rfe_fix_t srho = rfe_q31_div_round(
            rfe_fix_shr64_round((int64_t)slip * (int64_t)best_sd, 1u), best_m, sat);
        (void)s; /* cy g > 0 after the parameter checks */
        out = rfe_fix_mul(obs->p.vy_out_floor_mu, srho, 24u, sat);
    }
    return out;
}

/* The model at this step (§4.2): its friction (raised to what ay proves, and in a steady
 * turn of the linear range to its floor, @p lin_floor) and its rows at the prediction
 * @p vy_pred. */
static rfe_status_t model_q31(const rfe_velocity_q31_t *obs, const rfe_velocity_input_q31_t *in,
                              rfe_fix_t vx, rfe_fix_t vy_pred, int lin_floor,
                              const rfe_velocity_mu_q31_t *mu, rfe_meas_lateral_q31_t *z,
                              uint32_t *fl, uint32_t *sat)
{
    rfe_fix_t mm[RFE_WHEELS];
    rfe_fix_t m_sd[RFE_WHEELS];
    if (model_friction_q31(&obs->p, obs->veh.g, in->ay, lin_floor, mu, mm, m_sd, sat) != 0) {
        *fl |= RFE_VEL_FLAG_MU_RAISED;
    }
    return model_rows_q31(obs, in, vx, vy_pred, mm, m_sd, z, sat);
}

/* §4.2 a model row's variance @p r (>= 0, at most RFE_KF2_Q31_PMAX) at lat_every @p n
 * (1 .. 8): round(r / n) when n > 1 (an update every n-th step at r / n carries the
 * information per second of one every step at r), by exact integer division: (r + n / 2) / n
 * in uint64 (no overflow: r + 4 < 2^63), within 1/2 LSB of r / n, the nearest integer (ties
 * of even n upward); r itself at n = 1 (no arithmetic: bit for bit the every-step filter).
 * lateral_flt.c's rate_var. */
static int64_t rate_var_q31(int64_t r, uint32_t n)
{
    int64_t v = r;
    if (n > 1u) {
        const uint64_t d = (uint64_t)n;
        const uint64_t q = ((uint64_t)r + (d / 2u)) / d;
        v = (int64_t)q;
    }
    return v;
}

/* §4.2 the lateral-acceleration row: h0 = d ay / d vy (Q24), the innovation ay - ay0 and
 * the noise sd_model_ay^2 + (model_ay_rel ay)^2 + ((d ay / d mu) . sd)^2 (Q48), over
 * lat_every (rate_var_q31). */
static void ay_row_q31(const rfe_velocity_params_q31_t *p, const rfe_velocity_input_q31_t *in,
                       const rfe_meas_lateral_q31_t *z, rfe_kf2_meas_q31_t *m, uint32_t *sat)
{
    const rfe_fix_t e_mu = z->d_mu[0];
    const rfe_fix_t rel = rfe_fix_mul(p->model_ay_rel, in->ay, 30u, sat);
    int64_t r = rfe_fix_add64(rfe_vel_var_q31(p->sd_model_ay, sat), rfe_vel_var_q31(rel, sat),
                              sat);
    r = rfe_fix_add64(r, rfe_vel_var_q31(e_mu, sat), sat);
    m->h0 = z->d_vy[0];
    m->h1 = 0;
    m->qh0 = RFE_VEL_Q31_QB;
    m->qh1 = RFE_VEL_Q31_QB;
    m->qz = RFE_VEL_Q31_QB;
    m->nu = rfe_fix_sub(in->ay, z->z[0], sat);
    m->r = rate_var_q31(rfe_vel_pmax_q31(r, sat), p->lat_every);
}

/* §4.2 the yaw moment balance: the differentiator's r-dot (Q24) against the model's, both
 * rows linearised at vy_pred; the innovation at the vy the lateral row left, @p vy_now:
 * r-dot - (rdot0 + h1 (vy_now - vy_pred)), h1 Q24 times Q23 into Q24 (shift 23); the noise
 * sd_model_rdot^2 + ((d rdot / d mu) . sd)^2 + the differentiator's p11 (all Q48), over
 * lat_every (rate_var_q31). */
static void rdot_row_q31(const rfe_velocity_q31_t *obs, const rfe_meas_lateral_q31_t *z,
                         rfe_fix_t vy_pred, rfe_fix_t vy_now, rfe_kf2_meas_q31_t *m,
                         uint32_t *sat)
{
    const rfe_velocity_params_q31_t *p = &obs->p;
    const rfe_fix_t h1 = z->d_vy[1];
    const rfe_fix_t e_mu = z->d_mu[1];
    const rfe_fix_t lin =
        rfe_fix_add(z->z[1], rfe_fix_mul(h1, rfe_fix_sub(vy_now, vy_pred, sat), 23u, sat), sat);
    int64_t r = rfe_fix_add64(rfe_vel_var_q31(p->sd_model_rdot, sat), rfe_vel_var_q31(e_mu, sat),
                              sat);
    r = rfe_fix_add64(r, obs->yaw.p11, sat);
    m->h0 = h1;
    m->h1 = 0;
    m->qh0 = RFE_VEL_Q31_QRDOT;
    m->qh1 = RFE_VEL_Q31_QRDOT;
    m->qz = RFE_VEL_Q31_QRDOT;
    m->nu = rfe_fix_sub(obs->yaw.x[1], lin, sat);
    m->r = rate_var_q31(rfe_vel_pmax_q31(r, sat), p->lat_every);
}

/* §4.2b the linear range, lateral_flt.c's linear_range in integers (decided before the
 * model's update): r_ref = vx (delta / L) (Q29 / Q29 into Q27, times Q23 into Q27), the test
 * on |r - r_ref| against lin_r_tol + lin_r_rel |r_ref| (Q27) and |ay| against lin_ay_max
 * (Q24). L > 0 after the parameter checks, so the division does not fail; a quotient beyond
 * its format saturates, counted. The time on r_ref (@p on_ref, updated) and lin_dwell are
 * Q30: it grows only while below lin_dwell <= 1 s, by dt <= dt_max <= 1 s, so the sum stays
 * below 2 s, within Q30. @p lin_floor: 1 when taken in a steady turn (rfe_vel_lin_floor);
 * @p r_over: §4.4's yaw rate beyond r_ref (Q27). Returns 1 when taken. */
static int linear_range_q31(const rfe_velocity_q31_t *obs, const rfe_velocity_input_q31_t *in,
                            rfe_fix_t vx, rfe_fix_t *on_ref, int *lin_floor, rfe_fix_t *r_over,
                            uint32_t *sat)
{
    const rfe_velocity_params_q31_t *p = &obs->p;
    const rfe_fix_t len = rfe_fix_add(obs->veh.Lf, obs->veh.Lr, sat);
    rfe_fix_t dl = 0;
    rfe_fix_t r_ref;
    rfe_fix_t a_ref; /* |r_ref|, Q27 */
    rfe_fix_t r_err;
    rfe_fix_t r_tol;
    rfe_fix_t ay_abs;
    rfe_vel_on_ref_t act;
    int on;
    rfe_status_t s;
    s = rfe_fix_div(in->delta, len, 27, &dl, sat);
    (void)s; /* L > 0 (above) */
    r_ref = rfe_fix_mul(vx, dl, 23u, sat);
    a_ref = rfe_fix_abs(r_ref, sat);
    /* §4.4's yaw rate beyond r_ref, max(0, |r| - |r_ref|), Q27 */
    *r_over = rfe_fix_max(0, rfe_fix_sub(rfe_fix_abs(in->yaw_rate, sat), a_ref, sat));
    r_err = rfe_fix_abs(rfe_fix_sub(in->yaw_rate, r_ref, sat), sat);
    r_tol = rfe_fix_add(p->lin_r_tol, rfe_fix_mul(p->lin_r_rel, a_ref, 30u, sat), sat);
    /* RESET exactly when the yaw rate is off r_ref: the decision below takes that */
    act = rfe_vel_on_ref((r_err <= r_tol) ? 1 : 0, (obs->r_on_ref >= p->lin_dwell) ? 1 : 0);
    if (act == RFE_VEL_ON_REF_RESET) {
        *on_ref = 0;
    } else if (act == RFE_VEL_ON_REF_ADD) {
        *on_ref = rfe_fix_min(rfe_fix_add(obs->r_on_ref, in->dt, sat), p->lin_dwell);
    } else {
        *on_ref = obs->r_on_ref;
    }
    ay_abs = rfe_fix_abs(in->ay, sat);
    on = rfe_vel_linear_range((p->sd_vy_lin > 0) ? 1 : 0, (act != RFE_VEL_ON_REF_RESET) ? 1 : 0,
                              (ay_abs <= p->lin_ay_max) ? 1 : 0,
                              (ay_abs <= p->lin_ay_steady) ? 1 : 0,
                              (*on_ref >= p->lin_dwell) ? 1 : 0);
    *lin_floor = rfe_vel_lin_floor(on, (*on_ref >= p->lin_dwell) ? 1 : 0);
    return on;
}

/* §4.2b the linear range's update: vy_lin = vx ((Lr delta) / L - ay / (cy g)): Lr delta Q29
 * over L into Q29, cy g (Q24 Q24) in Q20, ay Q24 over it into Q29, times vx Q23 into Q23.
 * L > 0, cy > 0 and g > 0 after the parameter checks, so no division fails; a quotient
 * beyond its format saturates, counted. */
static rfe_status_t linear_update_q31(rfe_kf2_q31_t *k, const rfe_velocity_q31_t *obs,
                                      const rfe_velocity_input_q31_t *in, rfe_fix_t vx,
                                      uint32_t *sat)
{
    rfe_kf2_meas_q31_t m;
    const rfe_fix_t len = rfe_fix_add(obs->veh.Lf, obs->veh.Lr, sat);
    const rfe_fix_t cg = rfe_fix_mul(obs->tyre.cy, obs->veh.g, 28u, sat);
    rfe_fix_t a = 0;
    rfe_fix_t b = 0;
    rfe_status_t s;
    s = rfe_fix_div(rfe_fix_mul(obs->veh.Lr, in->delta, 29u, sat), len, 29, &a, sat);
    if (s == RFE_OK) {
        s = rfe_fix_div(in->ay, cg, 25, &b, sat);
    }
    (void)s; /* every divisor is positive (above) */
    m.h0 = RFE_VEL_Q31_ONE;
    m.h1 = 0;
    m.qh0 = RFE_VEL_Q31_QONE;
    m.qh1 = RFE_VEL_Q31_QONE;
    m.qz = RFE_VEL_Q31_QV;
    m.nu = rfe_fix_sub(rfe_fix_mul(vx, rfe_fix_sub(a, b, sat), 29u, sat), k->x[0], sat);
    m.r = rfe_vel_var_q31(obs->p.sd_vy_lin, sat);
    return rfe_kf2_update_q31(k, &m, sat);
}

rfe_status_t rfe_vel_lateral_step_q31(rfe_kf2_q31_t *f, rfe_fix_t *on_ref,
                                      const rfe_velocity_q31_t *obs,
                                      const rfe_velocity_input_q31_t *in, rfe_fix_t vx,
                                      const rfe_velocity_mu_q31_t *mu, uint32_t *flags,
                                      uint32_t *sat)
{
    const rfe_velocity_params_q31_t *p = &obs->p;
    rfe_kf2_q31_t k;
    rfe_kf2_meas_q31_t m;
    rfe_fix_t t_ref = 0; /* below v_lat_min the time on r_ref restarts */
    rfe_fix_t r_over = 0; /* §4.4 the yaw rate beyond r_ref, Q27 (0 below v_lat_min) */
    uint32_t fl = 0u;
    uint32_t cnt = 0u;
    const rfe_fix_t dt = in->dt;
    /* ay - r vx: r Q27 vx Q23 -> Q24 */
    const rfe_fix_t a_kin = rfe_fix_sub(in->ay, rfe_fix_mul(in->yaw_rate, vx, 26u, &cnt), &cnt);
    const int64_t q00 = rfe_vel_dt_var_q31(dt, p->sd_ay, &cnt);
    const int64_t q11 = rfe_vel_scale_q31(rfe_vel_var_q31(p->q_by, &cnt), dt, 30u, &cnt);
    rfe_status_t st;
    k = *f;
    st = rfe_kf2_predict_q31(&k, -dt, rfe_fix_mul(dt, a_kin, 31u, &cnt), q00, q11, 0, &cnt);
    if (st != RFE_OK) {
        return st;
    }
    if (vx >= p->v_lat_min) {
        rfe_meas_lateral_q31_t z;
        const rfe_fix_t vy_pred = k.x[0];
        int lin_floor = 0;
        const int lin = linear_range_q31(obs, in, vx, &t_ref, &lin_floor, &r_over, &cnt);
        /* §4.2 the model's rows on the steps of phase 1 (every lat_every-th step) */
        const int due = rfe_vel_model_due(obs->started);
        if (due != 0) {
            st = model_q31(obs, in, vx, vy_pred, lin_floor, mu, &z, &fl, &cnt);
        }
        if ((st == RFE_OK) && (due != 0)) {
            ay_row_q31(p, in, &z, &m, &cnt);
            st = rfe_kf2_update_q31(&k, &m, &cnt);
            fl |= RFE_VEL_FLAG_VY_MODEL;
        }
        if ((st == RFE_OK) && (due != 0) && (p->sd_model_rdot > 0)) {
            /* sequential update (on when sd_model_rdot > 0): the yaw row after the lateral
             * one, on the vy it left */
            rdot_row_q31(obs, &z, vy_pred, k.x[0], &m, &cnt);
            st = rfe_kf2_update_q31(&k, &m, &cnt);
        }
        if ((st == RFE_OK) && (lin != 0)) {
            st = linear_update_q31(&k, obs, in, vx, &cnt);
            fl |= RFE_VEL_FLAG_VY_LINEAR;
        }
    } else {
        /* §4.3 low speed: the rear axle rolls without side slip, vy = Lr r (Q29 Q27 -> Q23) */
        m.h0 = RFE_VEL_Q31_ONE;
        m.h1 = 0;
        m.qh0 = RFE_VEL_Q31_QONE;
        m.qh1 = RFE_VEL_Q31_QONE;
        m.qz = RFE_VEL_Q31_QV;
        m.nu = rfe_fix_sub(rfe_fix_mul(obs->veh.Lr, in->yaw_rate, 33u, &cnt), k.x[0], &cnt);
        m.r = rfe_vel_var_q31(p->sd_lowspeed, &cnt);
        st = rfe_kf2_update_q31(&k, &m, &cnt);
        fl |= RFE_VEL_FLAG_VY_LOWSPEED;
    }
    if (st == RFE_OK) {
        /* §4.4 no sideslip accelerates for long: ay - r vx = b_y + v-dot_y, v-dot_y as noise
         * (larger while the yaw rate changes, and while the car yaws beyond r_ref): Q24 +
         * Q24 Q24 -> Q24, + Q24 Q27 -> Q24 (shift 27); vydot_rerr <= 100 keeps the last term
         * within Q24 up to a yaw error of 1.28 rad/s, beyond it saturates, counted */
        const rfe_fix_t sv = rfe_fix_add(
            rfe_fix_add(p->sd_vydot,
                        rfe_fix_mul(p->vydot_rdot, rfe_fix_abs(obs->yaw.x[1], &cnt), 24u, &cnt),
                        &cnt),
            rfe_fix_mul(p->vydot_rerr, r_over, 27u, &cnt), &cnt);
        m.h0 = 0;
        m.h1 = RFE_VEL_Q31_ONE;
        m.qh0 = RFE_VEL_Q31_QB;
        m.qh1 = RFE_VEL_Q31_QONE;
        m.qz = RFE_VEL_Q31_QB;
        m.nu = rfe_fix_sub(a_kin, k.x[1], &cnt);
        m.r = rfe_vel_var_q31(sv, &cnt);
        st = rfe_kf2_update_q31(&k, &m, &cnt);
    }
    if (st == RFE_OK) {
        *f = k;
        *on_ref = t_ref;
        *flags |= fl;
        rfe_q31_sat_add(sat, cnt);
    }
    return st;
}
