/**
 * @file mass_grade_flt.c
 * @brief The mass and road-grade estimator (docs/MASS_GRADE.md): input checks, the start,
 *        the pause logic (§4.2, its decisions shared with the Q31 twin: mass_grade_logic.h),
 *        the longitudinal model (§1-2) through the square-root unscented filter
 *        (mass_grade_ukf_flt.c, §4.3), the projection and the adaptation (§4.4). The state
 *        carries the lower factor S of P = S S^T; the start, the hold and the adaptation
 *        write S (each covariance step a triangularisation, rfe_qr_tria): the steps of
 *        mass_grade_q31.c.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_MASS_GRADE_IMPL
#include "rfe/mass_grade.h"

#include "rfe/component/qr.h"
#include "estimators/mass_grade/mass_grade_internal.h"
#include "estimators/mass_grade/mass_grade_logic.h"
#include "numerics/internal.h"

#define N ((size_t)RFE_MG_N)

rfe_status_t rfe_mass_grade_init(rfe_mass_grade_t *mg, const rfe_mass_grade_params_t *p,
                                 size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    const rfe_real_t n = (rfe_real_t)RFE_MG_N;
    rfe_real_t lam;
    rfe_real_t c;
    /* A caller built with another number type lays the state out differently: nothing may
     * be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*mg)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if ((mg == NULL) || (p == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_mass_grade_params_validate(p) != RFE_OK) {
        return RFE_ERR_PARAM;
    }
    *mg = (rfe_mass_grade_t){0};
    mg->p = *p;
    /* §3 lambda = alpha^2 (n + kappa) - n and the weights (eq. 14 corrected, §8 C4) */
    lam = ((p->ut_alpha * p->ut_alpha) * (n + p->ut_kappa)) - n;
    c = n + lam;
    mg->wm0 = lam / c;
    mg->wc0 = (lam / c) + ((RFE_R(1.0) - (p->ut_alpha * p->ut_alpha)) + p->ut_beta);
    mg->wi = RFE_R(1.0) / (RFE_R(2.0) * c);
    mg->sqrt_wc0 = RFE_SQRT(RFE_FABS(mg->wc0)); /* a negative w_c,0 is a downdate (§4.6) */
    mg->sqrt_wi = RFE_SQRT(mg->wi);
    mg->sqrt_c = RFE_SQRT(c);
    mg->magic = RFE_MAGIC_MG;
    return RFE_OK;
}

/* §4.1 every value the sample carries finite. */
static int sample_values_finite(const rfe_mass_grade_input_t *in)
{
    const rfe_real_t v[3] = {in->dt, in->v, in->torque};
    if (rfe_all_finite(v, 3u) == 0) {
        return 0;
    }
    if (((in->has & RFE_MG_HAS_PRESSURE) != 0u) && !rfe_is_finite(in->p_brake)) {
        return 0;
    }
    if (((in->has & RFE_MG_HAS_VX) != 0u) && !rfe_is_finite(in->vx)) {
        return 0;
    }
    if (((in->has & RFE_MG_HAS_AY) != 0u) && !rfe_is_finite(in->ay)) {
        return 0;
    }
    return (((in->has & RFE_MG_HAS_AX) == 0u) || rfe_is_finite(in->ax)) ? 1 : 0;
}

/* §4.1 the sample's checks: finite, inside the limits, ax when the row needs it, a period
 * after the first sample. */
static rfe_status_t check_torque_sample(const rfe_mass_grade_t *mg,
                                       const rfe_mass_grade_input_t *in)
{
    if (sample_values_finite(in) == 0) {
        return RFE_ERR_NONFINITE;
    }
    if ((rfe_mg_has_status(in->has, mg->p.use_ax) != RFE_OK) ||
        (RFE_FABS(in->v) > RFE_R(RFE_LIMIT_VX)) ||
        (RFE_FABS(in->torque) > RFE_R(RFE_LIMIT_DRIVE_TORQUE))) {
        return RFE_ERR_RANGE;
    }
    if (((in->has & RFE_MG_HAS_AX) != 0u) && (RFE_FABS(in->ax) > RFE_R(RFE_LIMIT_ACC))) {
        return RFE_ERR_RANGE;
    }
    if (((in->has & RFE_MG_HAS_VX) != 0u) && (RFE_FABS(in->vx) > RFE_R(RFE_LIMIT_VX))) {
        return RFE_ERR_RANGE;
    }
    if (((in->has & RFE_MG_HAS_AY) != 0u) && (RFE_FABS(in->ay) > RFE_R(RFE_LIMIT_ACC))) {
        return RFE_ERR_RANGE;
    }
    if ((mg->started != 0u) && !(in->dt > RFE_R(0.0))) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* §1 v-dot = (T/r - M g ((f_c + f_r v) cos theta + sin theta) - rho C_d S v^2 / 2)
 * / (M + m_rot), M clamped to [m_min, m_max] (a sigma point may leave them). */
static rfe_real_t accel(const rfe_mass_grade_params_t *p, const rfe_real_t *x, rfe_real_t torque)
{
    const rfe_real_t v = x[0];
    const rfe_real_t m = rfe_clamp(x[1], p->m_min, p->m_max);
    const rfe_real_t f = p->fc + (p->fr * v);
    const rfe_real_t drag = ((((RFE_R(0.5) * p->rho) * p->cd) * p->area) * v) * v;
    const rfe_real_t force = ((torque / p->R) -
                              ((m * p->g) * ((f * RFE_COS(x[2])) + RFE_SIN(x[2])))) - drag;
    return force / (m + p->m_rot);
}

/* §4.2 the change test's speed: the car's vx where given, else the wheels' v. */
static rfe_real_t test_speed(const rfe_mass_grade_input_t *in)
{
    return ((in->has & RFE_MG_HAS_VX) != 0u) ? in->vx : in->v;
}

/* §4.1 (re)start at the sample: x = [v, m0, theta0], S = diag(r_v, sd_m0, sd_theta0), the
 * adaptation armed. */
static void start_filter(rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in)
{
    size_t i;
    for (i = 0u; i < (N * N); ++i) {
        o->S[i] = RFE_R(0.0);
    }
    o->x[0] = in->v;
    o->x[1] = o->p.m0;
    o->x[2] = o->p.theta0;
    o->S[0] = o->p.r_v;
    o->S[4] = o->p.sd_m0;
    o->S[8] = o->p.sd_theta0;
    o->q_mv = (o->p.adaptive == 1u) ? (o->p.q_mv0 * o->p.q_mv0) : RFE_R(0.0);
    o->adapt_elapsed = RFE_R(0.0);
    o->m_adapt = o->x[1];
    o->brake_left = RFE_R(0.0);
    o->shift_left = RFE_R(0.0);
    o->curve_left = RFE_R(0.0);
    o->has_gear = in->has & RFE_MG_HAS_GEAR;
    o->gear = in->gear;
    o->slip_latched = 0u;
    o->chg_on = 0u;
    o->chg_d = RFE_R(0.0);
    o->u_prev = test_speed(in);
    o->wq_rate = RFE_R(0.0); /* §4.7 the walk tight, its rate and mean square 0 */
    o->wq_ms = RFE_R(0.0);
    o->wq_hi = 0u;
    o->mm_e = RFE_R(0.0); /* §4.8 the monitor's EMA starts at 0 */
}

/* §4.7 the grade's random walk density for this sample: q_theta_hi while the two-level
 * walk is loose, else q_theta. */
static rfe_real_t q_theta_now(const rfe_mass_grade_t *o)
{
    return (o->wq_hi != 0u) ? o->p.q_theta_hi : o->p.q_theta;
}

/* §4.7 after an accepted sample that is not a start, the walk on (q_theta_hi > 0):
 * d = theta - theta_prev (@p th_prev: the grade of the state before the step, i.e. at the
 * last accepted sample, which an error leaves as it was), r += d/tau - (dt/tau) r,
 * s += (dt/avg) (r^2 - s), then the level by the hysteresis (rfe_mg_walk_level) against
 * on^2 and off^2. */
static void walk_level(rfe_mass_grade_t *o, rfe_real_t th_prev, rfe_real_t dt)
{
    const rfe_real_t d = o->x[2] - th_prev;
    const rfe_real_t tau = o->p.theta_rate_tau;
    const rfe_real_t avg = o->p.theta_rate_avg;
    const rfe_real_t on = o->p.theta_rate_on;
    const rfe_real_t off = o->p.theta_rate_off;
    o->wq_rate += (d / tau) - ((dt / tau) * o->wq_rate);
    o->wq_ms += (dt / avg) * ((o->wq_rate * o->wq_rate) - o->wq_ms);
    o->wq_hi = rfe_mg_walk_level(o->wq_hi, (o->wq_ms > (on * on)) ? 1 : 0,
                                 (o->wq_ms < (off * off)) ? 1 : 0);
}

/* §4.2 step 3 the slip test's comparison, |v - vx| > ratio max(|vx|, v_min), read only
 * with vx given (its outcome counts only then, rfe_mg_slipping): ratio slip_max for the slip
 * pause, pause_grade_slip for the ABS gate of the grade from ax. */
static int slip_beyond(const rfe_mass_grade_params_t *p, const rfe_mass_grade_input_t *in,
                       rfe_real_t ratio)
{
    int beyond = 0;
    if ((in->has & RFE_MG_HAS_VX) != 0u) {
        const rfe_real_t ref = rfe_max(RFE_FABS(in->vx), p->v_min);
        if (RFE_FABS(in->v - in->vx) > (ratio * ref)) {
            beyond = 1;
        }
    }
    return beyond;
}

/* §4.2 steps 0 and 4 for the curve: its delay counts down, a sample with |ay| over ay_max
 * (read only when given: its outcome counts only then) restarts it; 1 when held: cornering
 * now or more than half a period of the delay left. */
static int curve_held(rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in, rfe_real_t dt)
{
    int beyond = 0;
    int cornering;
    if (((in->has & RFE_MG_HAS_AY) != 0u) && (RFE_FABS(in->ay) > o->p.ay_max)) {
        beyond = 1;
    }
    cornering = rfe_mg_cornering(in->has, (o->p.ay_max > RFE_R(0.0)) ? 1 : 0, beyond);
    o->curve_left = rfe_max(o->curve_left - dt, RFE_R(0.0));
    if (cornering != 0) {
        o->curve_left = o->p.t_curve;
    }
    return ((cornering != 0) || (o->curve_left > (RFE_R(0.5) * dt))) ? 1 : 0;
}

/* §4.2 the pause logic; the delays count down by the period dt (0 on a start), so they stay
 * as exact as the period in float32 however long the drive; a delay ends at the sample where
 * less than half a period of it is left, so a delay of whole periods holds the same samples
 * in float and double whatever the rounding of the periods' sum. */
static rfe_status_t pause_status(rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in,
                                 rfe_real_t dt)
{
    int above = 0;
    int brake;
    int curve;
    rfe_status_t status;
    /* §4.2 step 1: the pedal flag, or the pressure above p_brake_on (read only when given) */
    if (((in->has & RFE_MG_HAS_PRESSURE) != 0u) && (in->p_brake > o->p.p_brake_on)) {
        above = 1;
    }
    brake = rfe_mg_braking(in->has, in->brake, above);
    o->brake_left = rfe_max(o->brake_left - dt, RFE_R(0.0));
    o->shift_left = rfe_max(o->shift_left - dt, RFE_R(0.0));
    if (brake != 0) {
        o->brake_left = o->p.t_brake;
    }
    if (rfe_mg_gear_changed(in->has, o->has_gear, in->gear, o->gear) != 0) {
        o->shift_left = o->p.t_shift;
    }
    if ((in->has & RFE_MG_HAS_GEAR) != 0u) {
        o->gear = in->gear;
        o->has_gear = 1u;
    }
    curve = curve_held(o, in, dt);
    status = rfe_mg_pause_status(
        brake, (o->brake_left > (RFE_R(0.5) * dt)) ? 1 : 0,
        (o->shift_left > (RFE_R(0.5) * dt)) ? 1 : 0,
        rfe_mg_slipping(in->has, (o->p.slip_max > RFE_R(0.0)) ? 1 : 0,
                        slip_beyond(&o->p, in, o->p.slip_max)),
        curve, (in->v < o->p.v_min) ? 1 : 0);
    /* the ABS gate (pause_grade_slip) */
    o->slip_latched = rfe_mg_slip_latch(
        status, o->slip_latched,
        rfe_mg_slipping(in->has, (o->p.pause_grade_slip > RFE_R(0.0)) ? 1 : 0,
                        slip_beyond(&o->p, in, o->p.pause_grade_slip)));
    return status;
}

/* §4.2 the hold: M, theta kept; P_thth += q_theta^2 dt; v restarts at the measured speed,
 * uncorrelated: S = [[r_v, 0, 0], [0, T]], T T^T = S_23 S_23^T + diag(0, q_theta^2 dt) by a
 * 2 x 4 triangularisation of the mass and grade rows with the noise column; the adaptation's
 * clock restarts at the held mass. */
static rfe_status_t hold(rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in, rfe_real_t dt)
{
    rfe_real_t A[8] = {0};
    rfe_status_t st;
    A[0] = o->S[3];
    A[1] = o->S[4];
    A[4] = o->S[6];
    A[5] = o->S[7];
    A[6] = o->S[8];
    A[7] = q_theta_now(o) * RFE_SQRT(dt);
    st = rfe_qr_tria(A, 2u, 4u, 4u);
    if (st == RFE_OK) {
        o->x[0] = in->v;
        o->S[0] = o->p.r_v;
        o->S[1] = RFE_R(0.0);
        o->S[2] = RFE_R(0.0);
        o->S[3] = RFE_R(0.0);
        o->S[4] = A[0];
        o->S[5] = RFE_R(0.0);
        o->S[6] = RFE_R(0.0);
        o->S[7] = A[4];
        o->S[8] = A[5];
        o->adapt_elapsed = RFE_R(0.0);
        o->m_adapt = o->x[1];
    }
    return st;
}

/* §4.2 the grade from ax in a pause (pause_grade): M and S's mass row untouched (P_MM,
 * P_Mv = 0, P_Mtheta kept), v and theta run the kinematic model v-dot = a_x - g sin theta,
 * ax its input, on S's columns 0 and 2 (theta given the held M: S_theta,M kept): the EKF
 * time update [L 0] = Tria([F L, diag(q_v', q_theta sqrt(dt))]), F = [[1, -g cos(theta) dt],
 * [0, 1]], L = [[S_vv, 0], [S_theta,v, S_theta,theta]], q_v'^2 = q_v^2 dt + (r_ax dt)^2; then
 * the speed row (rfe_mg_correct_speed: S's mass row, 0 in column 0, keeps its mean and its S
 * row bit for bit); theta projected onto its bound; the adaptation's clock restarts as in the
 * hold. */
static rfe_status_t grade_from_ax(rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in,
                                  rfe_real_t dt)
{
    rfe_real_t A[8] = {0};
    rfe_real_t x[RFE_MG_N];
    rfe_real_t S[RFE_MG_N * RFE_MG_N];
    const rfe_real_t gc = (o->p.g * RFE_COS(o->x[2])) * dt;
    const rfe_real_t rax = o->p.r_ax * dt;
    rfe_status_t st;
    A[0] = o->S[0] - (gc * o->S[6]);
    A[1] = -gc * o->S[8];
    A[2] = RFE_SQRT(((o->p.q_v * o->p.q_v) * dt) + (rax * rax));
    A[4] = o->S[6];
    A[5] = o->S[8];
    A[7] = q_theta_now(o) * RFE_SQRT(dt);
    st = rfe_qr_tria(A, 2u, 4u, 4u);
    if (st == RFE_OK) {
        size_t i;
        for (i = 0u; i < (N * N); ++i) {
            S[i] = o->S[i];
        }
        x[0] = o->x[0] + (dt * (in->ax - (o->p.g * RFE_SIN(o->x[2]))));
        x[1] = o->x[1];
        x[2] = o->x[2];
        S[0] = A[0];
        S[6] = A[4];
        S[8] = A[5];
        st = rfe_mg_correct_speed(o->p.r_v, in->v, x, S);
    }
    if ((st == RFE_OK) && (rfe_all_finite(x, N) == 0)) {
        st = RFE_ERR_NONFINITE;
    }
    if (st == RFE_OK) {
        o->x[0] = x[0];
        o->x[2] = rfe_clamp(x[2], -o->p.theta_max, o->p.theta_max);
        o->S[0] = S[0];
        o->S[6] = S[6];
        o->S[8] = S[8];
        o->adapt_elapsed = RFE_R(0.0);
        o->m_adapt = o->x[1];
    }
    return st;
}

/* §4.2 the change test (pause_grade_dv) on a sample that may learn the grade: the residual
 * of the held grade d += (u - u_prev) - dt (ax - g sin theta) while not tripped; 1 when the
 * sample learns (rfe_mg_change_tripped). */
static int change_seen(rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in)
{
    int test_on = 0;
    int beyond = 0;
    if (o->p.pause_grade_dv > RFE_R(0.0)) {
        test_on = 1;
    }
    if (rfe_mg_change_sums(test_on, o->chg_on) != 0) {
        o->chg_d += (test_speed(in) - o->u_prev) -
                    (in->dt * (in->ax - (o->p.g * RFE_SIN(o->x[2]))));
        if (RFE_FABS(o->chg_d) > o->p.pause_grade_dv) {
            beyond = 1;
        }
    }
    o->chg_on = rfe_mg_change_tripped(test_on, o->chg_on, beyond);
    return (o->chg_on != 0u) ? 1 : 0;
}

/* §4.2 a paused sample: the grade from ax where pause_grade sets the pause's bit, v is
 * uncorrelated with M (the last accepted sample a start or a paused one, v_free; then
 * S_Mv = 0 in every number type), the wheels have not slipped in this pause (the ABS
 * gate's latch clear) and the change test saw the held grade contradicted, else the hold;
 * a sample that may not learn clears the change test. */
static rfe_status_t paused(rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in,
                           rfe_status_t status)
{
    rfe_status_t st;
    int learn = 0;
    if (rfe_mg_grade_in_pause(status,
                              rfe_mg_pause_grade_bits((uint32_t)o->p.pause_grade, o->p.use_ax),
                              o->v_free, o->slip_latched) != 0) {
        learn = change_seen(o, in);
    } else {
        o->chg_on = 0u;
        o->chg_d = RFE_R(0.0);
    }
    if (learn != 0) {
        st = grade_from_ax(o, in, in->dt);
    } else {
        st = hold(o, in, in->dt);
    }
    return st;
}

/* §4.4 eqs. 22-25 once per adaptation period: lambda_u = 1/2 |q_s - D| / (q_s + D) scales
 * q_mv; P's mass row and column by lambda_u and P_MM once: P' = D P D + (lambda - lambda^2)
 * P_MM e2 e2^T, D = diag(1, lambda, 1), in square-root form S' = Tria([D S, sqrt(lambda -
 * lambda^2) |S row M| e2]); the adaptation ends at the stop threshold. */
static rfe_status_t adapt(rfe_mass_grade_t *o, rfe_real_t dt)
{
    rfe_real_t A[12] = {0};
    rfe_real_t d;
    rfe_real_t qs;
    rfe_real_t lam;
    rfe_real_t sd_m;
    rfe_status_t st;
    o->adapt_elapsed += dt;
    if (o->adapt_elapsed < (o->p.t_adapt - (RFE_R(0.5) * dt))) {
        return RFE_OK; /* the period ends within half a sample period of t_adapt, as the delays */
    }
    d = (o->x[1] - o->m_adapt) * (o->x[1] - o->m_adapt); /* (M_t - M_a)^2 */
    qs = o->q_mv * o->adapt_elapsed;                      /* q_mv over the period, kg^2 */
    /* 1/2, the limit at D = 0, where q_s underflowed to 0 */
    lam = ((qs + d) > RFE_R(0.0)) ? ((RFE_R(0.5) * RFE_FABS(qs - d)) / (qs + d)) : RFE_R(0.5);
    o->q_mv *= lam;
    sd_m = RFE_SQRT((o->S[3] * o->S[3]) + (o->S[4] * o->S[4])); /* |S row M| = sqrt(P_MM) */
    A[0] = o->S[0];
    A[4] = lam * o->S[3];
    A[5] = lam * o->S[4];
    A[7] = RFE_SQRT(lam - (lam * lam)) * sd_m; /* lambda in [0, 1/2]: lambda - lambda^2 >= 0 */
    A[8] = o->S[6];
    A[9] = o->S[7];
    A[10] = o->S[8];
    st = rfe_qr_tria(A, N, 4u, 4u);
    if (st == RFE_OK) {
        size_t r;
        size_t c;
        for (r = 0u; r < N; ++r) {
            for (c = 0u; c < N; ++c) {
                o->S[(r * N) + c] = (c <= r) ? A[(r * 4u) + c] : RFE_R(0.0);
            }
        }
        if (o->q_mv <= (o->p.mv_stop * (o->p.q_mc * o->p.q_mc))) {
            o->q_mv = RFE_R(0.0); /* q_22 has converged to q_mc^2: the AUKF is the UKF now */
        }
        o->adapt_elapsed = RFE_R(0.0);
        o->m_adapt = o->x[1];
    }
    return st;
}

/* §4.3 steps 1-2: the points of (x, S) through f(x) = [v + dt v-dot(T_prev), M, theta]; Q's
 * roots q_v sqrt(dt), sqrt(q_mc^2 + q_mv) sqrt(dt), q_theta sqrt(dt). */
static rfe_status_t time_update(const rfe_mass_grade_t *o, rfe_real_t dt, rfe_real_t xm[RFE_MG_N],
                                rfe_real_t Sm[RFE_MG_N * RFE_MG_N])
{
    const rfe_mg_weights_t w = {o->wm0, o->wc0, o->wi, o->sqrt_wc0, o->sqrt_wi, o->sqrt_c};
    const rfe_real_t sdt = RFE_SQRT(dt);
    rfe_real_t chi[RFE_MG_PTS * RFE_MG_N];
    rfe_real_t sq[RFE_MG_N];
    size_t i;
    rfe_mg_sigma_points(o->x, o->S, o->sqrt_c, chi);
    for (i = 0u; i < (size_t)RFE_MG_PTS; ++i) {
        rfe_real_t *pt = &chi[i * N];
        pt[0] += dt * accel(&o->p, pt, o->torque_prev);
    }
    sq[0] = o->p.q_v * sdt;
    sq[1] = RFE_SQRT((o->p.q_mc * o->p.q_mc) + o->q_mv) * sdt;
    sq[2] = q_theta_now(o) * sdt;
    return rfe_mg_predict(chi, &w, sq, xm, Sm);
}

/* §4.3 steps 3-7: the speed row alone (rfe_mg_correct_speed: linear in the state, it needs
 * no sigma points); with the ax row, new points of (x-, S-) and their z_ax = v-dot(T) +
 * g sin theta, then the ax row and the speed row (rfe_mg_correct). */
static rfe_status_t measurement_update(const rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in,
                                       rfe_real_t x[RFE_MG_N], rfe_real_t S[RFE_MG_N * RFE_MG_N],
                                       rfe_real_t *e_ax)
{
    rfe_status_t st;
    if (o->p.use_ax == 1u) {
        const rfe_mg_weights_t w = {o->wm0, o->wc0, o->wi, o->sqrt_wc0, o->sqrt_wi, o->sqrt_c};
        const rfe_real_t r[RFE_MG_Z_MAX] = {o->p.r_v, o->p.r_ax};
        const rfe_real_t y[RFE_MG_Z_MAX] = {in->v, in->ax};
        rfe_real_t chi[RFE_MG_PTS * RFE_MG_N];
        rfe_real_t Z[RFE_MG_PTS];
        size_t i;
        rfe_mg_sigma_points(x, S, o->sqrt_c, chi);
        for (i = 0u; i < (size_t)RFE_MG_PTS; ++i) {
            const rfe_real_t *pt = &chi[i * N];
            Z[i] = accel(&o->p, pt, in->torque) + (o->p.g * RFE_SIN(pt[2]));
        }
        st = rfe_mg_correct(chi, Z, &w, r, y, x, S, e_ax);
    } else {
        st = rfe_mg_correct_speed(o->p.r_v, in->v, x, S);
    }
    return st;
}

/* §4.3 one filter step, the projection of the mean and the adaptation; o is the caller's
 * copy, so an error leaves the estimator untouched. */
static rfe_status_t update(rfe_mass_grade_t *o, const rfe_mass_grade_input_t *in, rfe_real_t dt)
{
    rfe_real_t x[RFE_MG_N];
    rfe_real_t S[RFE_MG_N * RFE_MG_N];
    rfe_real_t e = RFE_R(0.0);
    rfe_status_t st = time_update(o, dt, x, S);
    if (st == RFE_OK) {
        st = measurement_update(o, in, x, S, &e);
    }
    if ((st == RFE_OK) && ((rfe_all_finite(x, N) == 0) || (rfe_all_finite(S, N * N) == 0))) {
        st = RFE_ERR_NONFINITE; /* an overflow is refused: never a NaN out */
    }
    if (st == RFE_OK) {
        size_t i;
        x[1] = rfe_clamp(x[1], o->p.m_min, o->p.m_max); /* step 8 */
        x[2] = rfe_clamp(x[2], -o->p.theta_max, o->p.theta_max);
        for (i = 0u; i < N; ++i) {
            o->x[i] = x[i];
        }
        for (i = 0u; i < (N * N); ++i) {
            o->S[i] = S[i];
        }
        if (o->p.use_ax == 1u) {
            /* §4.8 the mismatch monitor's EMA of the ax row's normalised innovation; dt/tau
             * <= 1 (mm_tau >= dt_max >= dt) */
            o->mm_e += (dt / o->p.mm_tau) * (e - o->mm_e);
        }
        if ((o->p.adaptive == 1u) && (o->q_mv > RFE_R(0.0))) {
            st = adapt(o, dt);
        }
    }
    return st;
}

/* §4.1 the state after a start, a hold, an update or an adaptation: S, q_mv and the sds
 * finite. Valid parameters may still overflow a square (q_mv0 = 1e30 in float: q_mv0^2 =
 * Inf; a row of S whose norm, the sd, overflows). x needs no check: a start takes the
 * sample's checked v and the parameters' m0 and theta0, a hold keeps M and theta and takes
 * the checked v, an update checked it. */
static int state_finite(const rfe_mass_grade_t *o, const rfe_mass_grade_estimate_t *e)
{
    const rfe_real_t sd[3] = {e->sd_v, e->sd_mass, e->sd_grade};
    return ((rfe_all_finite(o->S, N * N) != 0) && (rfe_is_finite(o->q_mv) != 0) &&
            (rfe_all_finite(sd, 3u) != 0))
               ? 1
               : 0;
}

/* §1 the outputs: the state, the sd as the norms of S's rows (sqrt of P's diagonal). */
static void estimate_of(const rfe_mass_grade_t *o, rfe_status_t status,
                        rfe_mass_grade_estimate_t *e)
{
    e->mass = o->x[1];
    e->sd_mass = RFE_SQRT((o->S[3] * o->S[3]) + (o->S[4] * o->S[4]));
    e->grade = o->x[2];
    e->sd_grade = RFE_SQRT(((o->S[6] * o->S[6]) + (o->S[7] * o->S[7])) + (o->S[8] * o->S[8]));
    e->v = o->x[0];
    e->sd_v = RFE_SQRT(o->S[0] * o->S[0]); /* |S_00|, overflowing as the other rows do */
    e->q_mv = o->q_mv;
    e->e_ax = o->mm_e;
    e->mismatch = rfe_mg_mismatch((o->p.mm_e > RFE_R(0.0)) ? 1 : 0,
                                  (RFE_FABS(o->mm_e) > o->p.mm_e) ? 1 : 0);
    e->status = status;
}

rfe_status_t rfe_mass_grade_step(rfe_mass_grade_t *mg, const rfe_mass_grade_input_t *in,
                                 rfe_mass_grade_estimate_t *out)
{
    rfe_mass_grade_t o;
    rfe_status_t st;
    rfe_status_t status = RFE_OK;
    rfe_mg_plan_t plan = RFE_MG_PLAN_STEP;
    if ((mg == NULL) || (in == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mg->magic != RFE_MAGIC_MG) {
        return RFE_ERR_NOT_INITIALISED;
    }
    st = check_torque_sample(mg, in);
    o = *mg; /* work on a copy: an error leaves the estimator as it was */
    if ((st == RFE_OK) &&
        (rfe_mg_plan(o.started, (in->dt > o.p.dt_max) ? 1 : 0) == RFE_MG_PLAN_START)) {
        start_filter(&o, in); /* §4.1: a first sample or a gap the model cannot bridge */
        plan = RFE_MG_PLAN_START;
        status = pause_status(&o, in, RFE_R(0.0));
    } else if (st == RFE_OK) {
        status = pause_status(&o, in, in->dt);
        if (status == RFE_OK) {
        o.chg_on = 0u; /* an update: no pause, the change test cleared */
        o.chg_d = RFE_R(0.0);
        st = update(&o, in, in->dt);
    } else {
        st = paused(&o, in, status);
    }
    } else {
        /* the checks failed: nothing to compute */
    }
    if (st == RFE_OK) {
        /* into the copy's own estimate, not a local: its padding (double build) is then the
         * state's, zeroed by init, and never the stack's */
        estimate_of(&o, status, &o.last);
        if (state_finite(&o, &o.last) == 0) {
            st = RFE_ERR_NONFINITE; /* an overflow (e.g. q_mv0^2): never a NaN out */
        }
    }
    if (st != RFE_OK) {
        *out = mg->last;
        out->status = st;
        return st;
    }
    o.started = 1u;
    o.torque_prev = in->torque;
    o.v_free = rfe_mg_v_free(plan, status);
    o.u_prev = test_speed(in);
    if ((plan != RFE_MG_PLAN_START) && (o.p.q_theta_hi != RFE_R(0.0))) {
        walk_level(&o, mg->x[2], in->dt);
    }
    *mg = o;
    *out = o.last;
    return status;
}

rfe_status_t rfe_mass_grade_restart(rfe_mass_grade_t *mg)
{
    if (mg == NULL) {
        return RFE_ERR_NULL;
    }
    if (mg->magic != RFE_MAGIC_MG) {
        return RFE_ERR_NOT_INITIALISED;
    }
    mg->started = 0u; /* the next accepted sample starts afresh (§4.1) */
    return RFE_OK;
}

rfe_status_t rfe_mass_grade_get(const rfe_mass_grade_t *mg, rfe_mass_grade_estimate_t *out)
{
    if ((mg == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mg->magic != RFE_MAGIC_MG) {
        return RFE_ERR_NOT_INITIALISED;
    }
    *out = mg->last;
    return RFE_OK;
}
