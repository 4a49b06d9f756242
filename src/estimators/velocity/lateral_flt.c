/**
 * @file lateral_flt.c
 * @brief The lateral filter [vy, b_y] (docs/OBSERVER.md §4): ay - r vx integrated, held by
 *        the friction estimator's own measurement model (rfe/component/meas.h) at its last
 *        friction, which the measured ay bounds from below: its lateral acceleration against
 *        the measured ay, its yaw acceleration against the differentiator's.
 */
#include "estimators/velocity/velocity_internal.h"

#include "rfe/component/meas.h"

#include "estimators/velocity/velocity_logic.h"

#include "numerics/internal.h"

/* The model's rows ay and r-dot of h(mu, u) at vy and their derivatives by vy and by the
 * friction in the direction of its sd (§4.2), from one set-up at vy. */
static rfe_status_t model_rows(const rfe_velocity_t *obs, const rfe_velocity_input_t *in,
                               rfe_real_t vx, rfe_real_t vy, const rfe_real_t mu[RFE_WHEELS],
                               const rfe_real_t sd[RFE_WHEELS], rfe_meas_lateral_t *rows)
{
    rfe_meas_t h;
    rfe_sample_t u;
    size_t i;
    rfe_status_t st;
    u.delta = in->delta;
    u.vx = vx;
    u.vy = vy;
    u.yaw_rate = in->yaw_rate;
    u.yaw_acc = RFE_R(0.0); /* not used by the model */
    u.ax = in->ax;
    u.ay = in->ay;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        u.omega[i] = in->omega[i];
    }
    st = rfe_meas_setup(&h, &obs->veh, &obs->tyre, &u);
    if (st == RFE_OK) {
        st = rfe_meas_lateral_jac(&h, &obs->veh, &obs->tyre, &u, mu, sd, rows);
    }
    return st;
}

/* The model's friction (§4.2): the input or the default, raised to what the measured ay
 * proves, (1 + mu_margin) |ay| / g, and in a steady turn of the linear range (@p lin_floor) to
 * at least lin_mu_gain |ay| / g; and its sd. Returns 1 when the bound raised a wheel. */
static int model_friction(const rfe_velocity_params_t *p, rfe_real_t g, rfe_real_t ay,
                          int lin_floor, const rfe_velocity_mu_t *in, rfe_real_t mu[RFE_WHEELS],
                          rfe_real_t sd_mu[RFE_WHEELS])
{
    const rfe_real_t margin = RFE_R(1.0) + p->mu_margin;
    const rfe_real_t gain = (lin_floor != 0) ? rfe_max(margin, p->lin_mu_gain) : margin;
    const rfe_real_t mu_low = (gain * RFE_FABS(ay)) / g;
    int raised = 0;
    size_t i;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        const rfe_real_t m = (in != NULL) ? in->mu[i] : p->mu_default;
        if (m < mu_low) {
            raised = 1;
        }
        mu[i] = rfe_max(m, mu_low);
        sd_mu[i] = (in != NULL) ? in->sd[i] : p->sd_mu_default;
    }
    return raised;
}

rfe_real_t rfe_vel_sd_vy_floor(const rfe_velocity_t *obs, const rfe_velocity_input_t *in,
                               rfe_real_t vx, const rfe_velocity_mu_t *mu)
{
    rfe_real_t m[RFE_WHEELS];
    rfe_real_t sd[RFE_WHEELS];
    rfe_real_t rel = RFE_R(0.0);
    const rfe_real_t g = obs->veh.g;
    size_t i;
    /* the margin's bound only (lin_floor 0): the friction the output floor scales by */
    (void)model_friction(&obs->p, g, in->ay, 0, mu, m, sd);
    for (i = 0u; i < RFE_WHEELS; ++i) {
        if (m[i] > RFE_R(0.0)) {
            rel = rfe_max(rel, sd[i] / m[i]);
        }
    }
    /* the linear model's slip part of vy, vx ay / (cy g) (cy, g > 0: parameter checks) */
    return RFE_FABS((obs->p.vy_out_floor_mu * ((vx * in->ay) / (obs->tyre.cy * g))) * rel);
}

/* §4.2b the linear range, decided before the model's update (its friction floor depends on
 * it): where the yaw rate is the neutral single-track model's (r_ref = vx (delta / L)) and
 * |ay| moderate (or, in a steady turn, the yaw rate on r_ref for lin_dwell, below the higher
 * cap). @p on_ref: the time r has stayed on r_ref, updated; @p lin_floor: 1 when taken in a
 * steady turn (rfe_vel_lin_floor); @p r_over: §4.4's yaw rate beyond r_ref,
 * max(0, |r| - |r_ref|). Returns 1 when taken. */
static int linear_range(const rfe_velocity_t *obs, const rfe_velocity_input_t *in, rfe_real_t vx,
                        rfe_real_t *on_ref, int *lin_floor, rfe_real_t *r_over)
{
    const rfe_velocity_params_t *p = &obs->p;
    const rfe_real_t len = obs->veh.Lf + obs->veh.Lr;
    const rfe_real_t r_ref = vx * (in->delta / len);
    const rfe_real_t a_ref = RFE_FABS(r_ref);
    const rfe_real_t r_tol = p->lin_r_tol + (p->lin_r_rel * a_ref);
    /* RESET exactly when the yaw rate is off r_ref: the decision below takes that */
    const rfe_vel_on_ref_t a = rfe_vel_on_ref((RFE_FABS(in->yaw_rate - r_ref) <= r_tol) ? 1 : 0,
                                              (obs->r_on_ref >= p->lin_dwell) ? 1 : 0);
    int on;
    *r_over = rfe_max(RFE_R(0.0), RFE_FABS(in->yaw_rate) - a_ref);
    if (a == RFE_VEL_ON_REF_RESET) {
        *on_ref = RFE_R(0.0);
    } else if (a == RFE_VEL_ON_REF_ADD) {
        *on_ref = rfe_min(obs->r_on_ref + in->dt, p->lin_dwell);
    } else {
        *on_ref = obs->r_on_ref;
    }
    on = rfe_vel_linear_range((p->sd_vy_lin > RFE_R(0.0)) ? 1 : 0,
                              (a != RFE_VEL_ON_REF_RESET) ? 1 : 0,
                              (RFE_FABS(in->ay) <= p->lin_ay_max) ? 1 : 0,
                              (RFE_FABS(in->ay) <= p->lin_ay_steady) ? 1 : 0,
                              (*on_ref >= p->lin_dwell) ? 1 : 0);
    *lin_floor = rfe_vel_lin_floor(on, (*on_ref >= p->lin_dwell) ? 1 : 0);
    return on;
}

/* §4.2b the linear range's update: vy = vx (Lr delta / L - ay / (cy g)), the linear model's,
 * with sd sd_vy_lin. */
static rfe_status_t linear_update(rfe_kf2_t *k, const rfe_velocity_t *obs,
                                  const rfe_velocity_input_t *in, rfe_real_t vx)
{
    const rfe_velocity_params_t *p = &obs->p;
    const rfe_real_t len = obs->veh.Lf + obs->veh.Lr;
    const rfe_real_t vy_lin =
        vx * (((obs->veh.Lr * in->delta) / len) - (in->ay / (obs->tyre.cy * obs->veh.g)));
    return rfe_kf2_update(k, RFE_R(1.0), RFE_R(0.0), vy_lin - k->x[0],
                          p->sd_vy_lin * p->sd_vy_lin);
}

/* §4.2 a model row's variance @p r at lat_every @p n: r / n when n > 1 (an update every n-th
 * step at r / n carries the information per second of one every step at r); r itself at
 * n = 1 (no arithmetic: bit for bit the every-step filter). */
static rfe_real_t rate_var(rfe_real_t r, uint32_t n)
{
    return (n > 1u) ? (r / (rfe_real_t)n) : r;
}

/* §4.2 the model's update at the prediction (the lateral row, then the yaw row when on) with
 * the friction the measured ay bounds (@p lin_floor: the steady turn's floor). */
static rfe_status_t model_update(rfe_kf2_t *k, const rfe_velocity_t *obs,
                                 const rfe_velocity_input_t *in, rfe_real_t vx, int lin_floor,
                                 const rfe_velocity_mu_t *mu, uint32_t *fl)
{
    const rfe_velocity_params_t *p = &obs->p;
    rfe_real_t m[RFE_WHEELS];
    rfe_real_t m_sd[RFE_WHEELS];
    rfe_meas_lateral_t z;
    const rfe_real_t vy_pred = k->x[0];
    rfe_status_t st;
    if (model_friction(p, obs->veh.g, in->ay, lin_floor, mu, m, m_sd) != 0) {
        *fl |= RFE_VEL_FLAG_MU_RAISED;
    }
    st = model_rows(obs, in, vx, vy_pred, m, m_sd, &z);
    if (st == RFE_OK) {
        /* H = d ay / d vy, the friction's error to first order: (d ay / d mu) . sd */
        const rfe_real_t h0 = z.d_vy[0];
        const rfe_real_t e_mu = z.d_mu[0];
        const rfe_real_t rel = p->model_ay_rel * in->ay;
        const rfe_real_t r = rate_var(
            ((p->sd_model_ay * p->sd_model_ay) + (rel * rel)) + (e_mu * e_mu), p->lat_every);
        st = rfe_kf2_update(k, h0, RFE_R(0.0), in->ay - z.z[0], r);
        *fl |= RFE_VEL_FLAG_VY_MODEL;
    }
    if ((st == RFE_OK) && (p->sd_model_rdot > RFE_R(0.0))) {
        /* §4.2 the yaw moment balance (on when sd_model_rdot > 0): the differentiator's
         * r-dot against the model's, at the same linearisation point vy_pred (sequential
         * update: the innovation is taken at the vy the lateral row left) */
        const rfe_real_t h1 = z.d_vy[1];
        const rfe_real_t e_mu = z.d_mu[1];
        const rfe_real_t r = rate_var(
            ((p->sd_model_rdot * p->sd_model_rdot) + (e_mu * e_mu)) + obs->yaw.p11,
            p->lat_every);
        st = rfe_kf2_update(k, h1, RFE_R(0.0),
                            obs->yaw.x[1] - (z.z[1] + (h1 * (k->x[0] - vy_pred))), r);
    }
    return st;
}

rfe_status_t rfe_vel_lateral_step(rfe_kf2_t *f, rfe_real_t *on_ref, const rfe_velocity_t *obs,
                                  const rfe_velocity_input_t *in, rfe_real_t vx,
                                  const rfe_velocity_mu_t *mu, uint32_t *flags)
{
    const rfe_velocity_params_t *p = &obs->p;
    rfe_kf2_t k;
    rfe_real_t t_ref = RFE_R(0.0); /* below v_lat_min the time on r_ref restarts */
    rfe_real_t r_over = RFE_R(0.0); /* §4.4 the yaw rate beyond r_ref (0 below v_lat_min) */
    uint32_t fl = 0u;
    const rfe_real_t dt = in->dt;
    const rfe_real_t sy = dt * p->sd_ay;
    rfe_status_t st;
    k = *f;
    st = rfe_kf2_predict(&k, -dt, dt * (in->ay - (in->yaw_rate * vx)), sy * sy,
                                      (p->q_by * p->q_by) * dt, RFE_R(0.0));
    if (st != RFE_OK) {
        return st;
    }
    if (vx >= p->v_lat_min) {
        int lin_floor = 0;
        const int lin = linear_range(obs, in, vx, &t_ref, &lin_floor, &r_over);
        /* §4.2 the model's rows on the steps of phase 1 (every lat_every-th step) */
        if (rfe_vel_model_due(obs->started) != 0) {
            st = model_update(&k, obs, in, vx, lin_floor, mu, &fl);
        }
        if ((st == RFE_OK) && (lin != 0)) {
            st = linear_update(&k, obs, in, vx);
            fl |= RFE_VEL_FLAG_VY_LINEAR;
        }
    } else {
        /* §4.3 low speed: the rear axle rolls without side slip, vy = Lr r */
        st = rfe_kf2_update(&k, RFE_R(1.0), RFE_R(0.0), (obs->veh.Lr * in->yaw_rate) - k.x[0],
                            p->sd_lowspeed * p->sd_lowspeed);
        fl |= RFE_VEL_FLAG_VY_LOWSPEED;
    }
    if (st == RFE_OK) {
        /* §4.4 no sideslip accelerates for long: ay - r vx = b_y + v-dot_y, with v-dot_y as
         * noise (larger while the yaw rate changes, and while the car yaws beyond the
         * neutral-steer reference: sliding out), holds b_y where the model cannot (a
         * saturated tyre tells nothing of vy) */
        const rfe_real_t sv = (p->sd_vydot + (p->vydot_rdot * RFE_FABS(obs->yaw.x[1]))) +
                              (p->vydot_rerr * r_over);
        st = rfe_kf2_update(&k, RFE_R(0.0), RFE_R(1.0),
                            (in->ay - (in->yaw_rate * vx)) - k.x[1], sv * sv);
    }
    if (st == RFE_OK) {
        *f = k;
        *on_ref = t_ref;
        *flags |= fl;
    }
    return st;
}
