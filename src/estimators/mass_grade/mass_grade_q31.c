/**
 * @file mass_grade_q31.c
 * @brief Fixed-point twin of mass_grade_flt.c (docs/MASS_GRADE.md, docs/FIXED_POINT.md "Mass
 *        and grade"): input checks, the start, the pause logic (§4.2, its decisions shared:
 *        mass_grade_logic.h), the longitudinal model (§1-2) through the square-root unscented
 *        filter (mass_grade_ukf_q31.c, §4.3), the projection and the adaptation (§4.4).
 *
 * The model v-dot = (T/r - M g ((f_c + f_r v) cos theta + sin theta) - rho C_d S v^2 / 2) /
 * (M + m_rot) spans forces from 1e-2 N (f_r v) to 1e6 N (M g): it is evaluated in rfe_xf_t
 * (numerics/xf_q31.h: a 30-bit mantissa and a power of two, each operation rounded to 2^-30
 * relative), sin and cos by rfe_q31_sincos_q29 (6.2e-10), and rounded once to Q24.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_MASS_GRADE_Q31_IMPL
#include "rfe/mass_grade_q31.h"

#include "rfe/component/fxmath.h"
#include "rfe/component/qr_q31.h"
#include "estimators/mass_grade/mass_grade_internal_q31.h"
#include "estimators/mass_grade/mass_grade_logic.h"
#include "numerics/fxmath_internal_q31.h"
#include "numerics/internal_q31.h"
#include "numerics/xf_q31.h"

#define N ((size_t)RFE_MG_N_Q31)
#define PTS ((size_t)RFE_MG_PTS_Q31)
/* The times t_brake, t_shift, t_adapt (Q24) in the timers' Q30: 2^6. */
#define TIME_TO_DT 64
/* 1/2 in Q30. */
#define HALF_Q30 ((rfe_fix_t)536870912)
/* 1 in Q30: slip_max's unit, which |v - vx| (Q24) is scaled by to compare in Q54 */
#define ONE_Q30_64 ((int64_t)1073741824)

rfe_status_t rfe_mass_grade_init_q31(rfe_mass_grade_q31_t *mg, const rfe_mass_grade_params_q31_t *p,
                                     size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    rfe_mg_weights_q31_t w;
    if ((size != sizeof(*mg)) || (config != RFE_CONFIG_Q31)) {
        return RFE_ERR_ABI;
    }
    if ((mg == NULL) || (p == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((rfe_mass_grade_params_validate_q31(p) != RFE_OK) ||
        (rfe_mass_grade_weights_q31(p, &w) != RFE_OK)) {
        return RFE_ERR_PARAM;
    }
    *mg = (rfe_mass_grade_q31_t){0};
    mg->p = *p;
    mg->wm0 = w.wm0;
    mg->wi = w.wi;
    mg->sqrt_wc0 = w.sqrt_wc0;
    mg->sqrt_wi = w.sqrt_wi;
    mg->sqrt_c = w.sqrt_c;
    mg->magic = RFE_MAGIC_MG_Q31;
    return RFE_OK;
}

/* §4.1 the sample's checks: inside the limits, ax when the row needs it, a period after the
 * first sample. */
static rfe_status_t check_torque_sample_q31(const rfe_mass_grade_q31_t *mg,
                                            const rfe_mass_grade_input_q31_t *in)
{
    uint32_t sat = 0u; /* |INT32_MIN| saturates to INT32_MAX, beyond every limit */
    if ((rfe_mg_has_status(in->has, mg->p.use_ax) != RFE_OK) ||
        (rfe_fix_abs(in->v, &sat) > RFE_MG_LIMIT_V_Q31) ||
        (rfe_fix_abs(in->torque, &sat) > RFE_MG_LIMIT_TORQUE_Q31)) {
        return RFE_ERR_RANGE;
    }
    if (((in->has & RFE_MG_HAS_AX) != 0u) && (rfe_fix_abs(in->ax, &sat) > RFE_MG_LIMIT_AX_Q31)) {
        return RFE_ERR_RANGE;
    }
    if (((in->has & RFE_MG_HAS_VX) != 0u) && (rfe_fix_abs(in->vx, &sat) > RFE_MG_LIMIT_V_Q31)) {
        return RFE_ERR_RANGE;
    }
    if (((in->has & RFE_MG_HAS_AY) != 0u) && (rfe_fix_abs(in->ay, &sat) > RFE_MG_LIMIT_AX_Q31)) {
        return RFE_ERR_RANGE;
    }
    if ((mg->started != 0u) && (in->dt <= 0)) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* The model's terms that do not depend on the point, in rfe_xf_t: formed once per set of
 * points (the same operations, in the same order, as for each point). */
typedef struct {
    rfe_xf_t fc;     /* f_c */
    rfe_xf_t fr;     /* f_r */
    rfe_xf_t g;      /* g */
    rfe_xf_t drag;   /* ((1/2 rho) C_d) S */
    rfe_xf_t thrust; /* T / r */
} model_q31_t;

/* §1 the point-independent terms at the torque T (Q14). */
static void model_of_q31(const rfe_mass_grade_params_q31_t *p, rfe_fix_t torque, model_q31_t *k)
{
    k->fc = rfe_xf_of(p->fc, RFE_MG_Q_FC);
    k->fr = rfe_xf_of(p->fr, RFE_MG_Q_FR);
    k->g = rfe_xf_of(p->g, RFE_MG_Q_G);
    k->drag = rfe_xf_mul(rfe_xf_mul(rfe_xf_make((int64_t)p->rho, -(RFE_MG_Q_COEF + 1)),
                                    rfe_xf_of(p->cd, RFE_MG_Q_COEF)),
                         rfe_xf_of(p->area, RFE_MG_Q_COEF));
    k->thrust = rfe_xf_div(rfe_xf_of(torque, RFE_MG_Q_TORQUE), rfe_xf_of(p->R, RFE_MG_Q_R));
}

/* §1 v-dot of the point pt = [v Q24, M Q14, theta Q29], M clamped to [m_min, m_max], in the
 * page's grouping: (T/r - (M g) ((f_c + f_r v) cos theta + sin theta) - ((1/2 rho C_d S) v) v)
 * / (M + m_rot); @p sin_th receives sin theta (Q30) for the ax row. */
static rfe_xf_t accel_q31(const rfe_mass_grade_params_q31_t *p, const model_q31_t *k,
                          const rfe_fix_t *pt, rfe_fix_t *sin_th)
{
    const rfe_fix_t m = rfe_fix_clamp(pt[1], p->m_min, p->m_max);
    const rfe_xf_t v = rfe_xf_of(pt[0], RFE_MG_Q_V);
    int32_t s = 0;
    int32_t c = 0;
    rfe_xf_t f;
    rfe_xf_t force;
    rfe_q31_sincos_q29(pt[2], &s, &c);
    *sin_th = s;
    /* f = f_c + f_r v; (f cos theta + sin theta) */
    f = rfe_xf_add(k->fc, rfe_xf_mul(k->fr, v));
    f = rfe_xf_add(rfe_xf_mul(f, rfe_xf_of(c, 30)), rfe_xf_of(s, 30));
    /* force = T / r - (M g) k - drag */
    force = rfe_xf_sub(k->thrust, rfe_xf_mul(rfe_xf_mul(rfe_xf_of(m, RFE_MG_Q_M), k->g), f));
    force = rfe_xf_sub(force, rfe_xf_mul(rfe_xf_mul(k->drag, v), v));
    /* / (M + m_rot): the sum exact in Q14 (int64) */
    return rfe_xf_div(force, rfe_xf_make((int64_t)m + (int64_t)p->m_rot, -RFE_MG_Q_M));
}

/* §4.2 the change test's speed: the car's vx where given, else the wheels' v (Q24). */
static rfe_fix_t test_speed_q31(const rfe_mass_grade_input_q31_t *in)
{
    return ((in->has & RFE_MG_HAS_VX) != 0u) ? in->vx : in->v;
}

/* §4.1 (re)start at the sample: x = [v, m0, theta0], S = diag(r_v, sd_m0, sd_theta0), the
 * adaptation armed (q_mv = q_mv0^2, exact in Q28). */
static void start_filter_q31(rfe_mass_grade_q31_t *o, const rfe_mass_grade_input_q31_t *in)
{
    size_t i;
    for (i = 0u; i < (N * N); ++i) {
        o->S[i] = 0;
    }
    o->x[0] = in->v;
    o->x[1] = o->p.m0;
    o->x[2] = o->p.theta0;
    o->S[0] = o->p.r_v;
    o->S[4] = o->p.sd_m0;
    o->S[8] = o->p.sd_theta0;
    o->q_mv = (o->p.adaptive == 1u) ? ((int64_t)o->p.q_mv0 * (int64_t)o->p.q_mv0) : 0;
    o->adapt_elapsed = 0;
    o->m_adapt = o->x[1];
    o->brake_left = 0;
    o->shift_left = 0;
    o->curve_left = 0;
    o->has_gear = in->has & RFE_MG_HAS_GEAR;
    o->gear = in->gear;
    o->slip_latched = 0u;
    o->chg_on = 0u;
    o->chg_d = 0;
    o->u_prev = test_speed_q31(in);
    o->wq_rate = 0; /* §4.7 the walk tight, its rate and mean square 0 */
    o->wq_ms = 0;
    o->wq_hi = 0u;
    o->mm_e = 0; /* §4.8 the monitor's EMA starts at 0 */
}

/* §4.7 the grade's random walk density for this sample, Q29: q_theta_hi while the
 * two-level walk is loose, else q_theta. */
static rfe_fix_t q_theta_now_q31(const rfe_mass_grade_q31_t *o)
{
    return (o->wq_hi != 0u) ? o->p.q_theta_hi : o->p.q_theta;
}

/* §4.7 as the float twin's walk_level (the walk on; @p th_prev the grade before the step):
 * d = theta - theta_prev (Q29), d/tau and dt/tau,
 * dt/avg in Q30 by exactly rounded divisions (tau, avg Q24 >= dt_max >= dt: the ratios
 * <= 1), r (Q30) += d/tau - (dt/tau) r, s (Q30) += (dt/avg) (r^2 - s), each product
 * rounded; on^2, off^2 in Q30 (>= 1 LSB: on, off >= 2^-15 rad/s give >= 1; smaller ones
 * compare against 0). r and s saturate (counted) beyond +-2, where s > on^2 already. */
static void walk_level_q31(rfe_mass_grade_q31_t *o, rfe_fix_t th_prev, rfe_fix_t dt,
                           uint32_t *sat)
{
    const rfe_fix_t d = rfe_fix_sub(o->x[2], th_prev, sat);
    rfe_fix_t dr = 0;
    rfe_fix_t kr = 0;
    rfe_fix_t ks = 0;
    rfe_fix_t r2;
    rfe_status_t st = rfe_fix_div(d, o->p.theta_rate_tau, 25, &dr, sat); /* Q29/Q24 */
    if (st == RFE_OK) {
        st = rfe_fix_div(dt, o->p.theta_rate_tau, 24, &kr, sat); /* Q30/Q24 -> Q30 */
    }
    if (st == RFE_OK) {
        st = rfe_fix_div(dt, o->p.theta_rate_avg, 24, &ks, sat);
    }
    (void)st; /* tau, avg > 0 (validated), shifts in range: RFE_OK */
    o->wq_rate = rfe_fix_add(o->wq_rate,
                             rfe_fix_sub(dr, rfe_fix_mul(kr, o->wq_rate, 30u, sat), sat), sat);
    r2 = rfe_fix_mul(o->wq_rate, o->wq_rate, 30u, sat);
    o->wq_ms = rfe_fix_add(o->wq_ms,
                           rfe_fix_mul(ks, rfe_fix_sub(r2, o->wq_ms, sat), 30u, sat), sat);
    o->wq_hi = rfe_mg_walk_level(
        o->wq_hi,
        (o->wq_ms > rfe_fix_mul(o->p.theta_rate_on, o->p.theta_rate_on, 30u, sat)) ? 1 : 0,
        (o->wq_ms < rfe_fix_mul(o->p.theta_rate_off, o->p.theta_rate_off, 30u, sat)) ? 1 : 0);
}

/* §4.2 step 3 the slip test's comparison, |v - vx| > ratio max(|vx|, v_min), read only
 * with vx given: in int64, exact (|v - vx| < 2^32 in Q24; the ratio Q30 times the Q24
 * reference < 2^62 against |v - vx| in Q54), so it decides as the real comparison on the Q
 * values; ratio slip_max for the slip pause, pause_grade_slip for the ABS gate. */
static int slip_beyond_q31(const rfe_mass_grade_params_q31_t *p,
                           const rfe_mass_grade_input_q31_t *in, rfe_fix_t ratio)
{
    int beyond = 0;
    if ((in->has & RFE_MG_HAS_VX) != 0u) {
        const int64_t vx = (int64_t)in->vx;
        const int64_t avx = (vx < 0) ? -vx : vx;
        const int64_t ref = (avx > (int64_t)p->v_min) ? avx : (int64_t)p->v_min;
        const int64_t d = (int64_t)in->v - vx;
        const int64_t ad = (d < 0) ? -d : d;
        if ((ad * ONE_Q30_64) > ((int64_t)ratio * ref)) {
            beyond = 1;
        }
    }
    return beyond;
}

/* §4.2 steps 0 and 4 for the curve on its Q30 timer: |ay| and ay_max both Q24, compared
 * exactly (read only when given); 1 when held: cornering now or 2 left > dt. */
static int curve_held_q31(rfe_mass_grade_q31_t *o, const rfe_mass_grade_input_q31_t *in,
                          int64_t dt64)
{
    uint32_t sat = 0u; /* |INT32_MIN| saturates to INT32_MAX: beyond every ay_max */
    int beyond = 0;
    int cornering;
    if (((in->has & RFE_MG_HAS_AY) != 0u) && (rfe_fix_abs(in->ay, &sat) > o->p.ay_max)) {
        beyond = 1;
    }
    cornering = rfe_mg_cornering(in->has, (o->p.ay_max > 0) ? 1 : 0, beyond);
    o->curve_left = (o->curve_left > dt64) ? (o->curve_left - dt64) : 0;
    if (cornering != 0) {
        o->curve_left = (int64_t)o->p.t_curve * TIME_TO_DT;
    }
    return ((cornering != 0) || ((2 * o->curve_left) > dt64)) ? 1 : 0;
}

/* §4.2 the pause logic on Q30 timers counting down by dt (0 on a start); a delay ends where
 * less than half a period of it is left (2 left > dt, exact in integers). */
static rfe_status_t pause_status_q31(rfe_mass_grade_q31_t *o, const rfe_mass_grade_input_q31_t *in,
                                     rfe_fix_t dt)
{
    const int64_t dt64 = (int64_t)dt;
    int above = 0;
    int brake;
    int curve;
    rfe_status_t status;
    if (((in->has & RFE_MG_HAS_PRESSURE) != 0u) && (in->p_brake > o->p.p_brake_on)) {
        above = 1;
    }
    brake = rfe_mg_braking(in->has, in->brake, above);
    o->brake_left = (o->brake_left > dt64) ? (o->brake_left - dt64) : 0;
    o->shift_left = (o->shift_left > dt64) ? (o->shift_left - dt64) : 0;
    if (brake != 0) {
        o->brake_left = (int64_t)o->p.t_brake * TIME_TO_DT;
    }
    if (rfe_mg_gear_changed(in->has, o->has_gear, in->gear, o->gear) != 0) {
        o->shift_left = (int64_t)o->p.t_shift * TIME_TO_DT;
    }
    if ((in->has & RFE_MG_HAS_GEAR) != 0u) {
        o->gear = in->gear;
        o->has_gear = 1u;
    }
    curve = curve_held_q31(o, in, dt64);
    status = rfe_mg_pause_status(brake, ((2 * o->brake_left) > dt64) ? 1 : 0,
                                 ((2 * o->shift_left) > dt64) ? 1 : 0,
                                 rfe_mg_slipping(in->has, (o->p.slip_max > 0) ? 1 : 0,
                                                 slip_beyond_q31(&o->p, in, o->p.slip_max)),
                                 curve, (in->v < o->p.v_min) ? 1 : 0);
    /* the ABS gate (pause_grade_slip) */
    o->slip_latched =
        rfe_mg_slip_latch(status, o->slip_latched,
                          rfe_mg_slipping(in->has, (o->p.pause_grade_slip > 0) ? 1 : 0,
                                          slip_beyond_q31(&o->p, in, o->p.pause_grade_slip)));
    return status;
}

/* sqrt(dt) in Q30 (dt > 0, Q30: never saturates). */
static rfe_fix_t sqrt_dt_q31(rfe_fix_t dt, uint32_t *sat)
{
    rfe_fix_t r = 0;
    const rfe_status_t st = rfe_fix_sqrt(dt, 30u, 30u, &r, sat);
    (void)st; /* dt > 0 in Q30: inside its domain */
    return r;
}

/* §4.2 the hold: M, theta kept; P_thth += q_theta^2 dt; v restarts at the measured speed,
 * uncorrelated: S = [[r_v, 0, 0], [0, T]], T T^T = S_23 S_23^T + diag(0, q_theta^2 dt) by a
 * 2 x 4 triangularisation of the mass and grade rows with the noise column. */
static rfe_status_t hold_q31(rfe_mass_grade_q31_t *o, const rfe_mass_grade_input_q31_t *in,
                             rfe_fix_t dt, uint32_t *sat)
{
    rfe_fix_t A[8] = {0};
    rfe_status_t st;
    A[0] = o->S[3];
    A[1] = o->S[4];
    A[4] = o->S[6];
    A[5] = o->S[7];
    A[6] = o->S[8];
    A[7] = rfe_fix_mul(q_theta_now_q31(o), sqrt_dt_q31(dt, sat), 30u, sat);
    st = rfe_qr_tria_q31(A, 2u, 4u, 4u, sat);
    if (st == RFE_OK) {
        o->x[0] = in->v;
        o->S[0] = o->p.r_v;
        o->S[1] = 0;
        o->S[2] = 0;
        o->S[3] = 0;
        o->S[4] = A[0];
        o->S[5] = 0;
        o->S[6] = 0;
        o->S[7] = A[4];
        o->S[8] = A[5];
        o->adapt_elapsed = 0;
        o->m_adapt = o->x[1];
    }
    return st;
}

/* §4.2 the grade from ax in a pause (pause_grade), as the float twin's grade_from_ax: M and
 * S's mass row untouched; the kinematic model v-dot = a_x - g sin theta on S's columns 0
 * (v, Q24) and 2 (theta, Q29) by the 2 x 4 triangularisation [[S_vv - gc S_theta,v,
 * -gc S_theta,theta, q_v', 0], [S_theta,v, S_theta,theta, 0, q_theta sqrt(dt)]] (each row in
 * its state's format), gc = g cos(theta) dt in Q26 and g sin(theta) in Q24 (exactly rounded
 * products: fixed-point multiplications only, so that the model's rfe_xf_t helpers stay
 * inlined where the update needs them), q_v' = |(q_v sqrt(dt), r_ax dt)| exactly rounded;
 * then the speed row (rfe_mg_correct_speed_q31). */
static rfe_status_t grade_from_ax_q31(rfe_mass_grade_q31_t *o, const rfe_mass_grade_input_q31_t *in,
                                      rfe_fix_t dt, uint32_t *sat)
{
    rfe_fix_t A[8] = {0};
    rfe_fix_t x[RFE_MG_N_Q31];
    rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31];
    rfe_fix_t q[2];
    int32_t s = 0;
    int32_t c = 0;
    const rfe_fix_t sdt = sqrt_dt_q31(dt, sat);
    rfe_fix_t gc;
    rfe_status_t st;
    rfe_q31_sincos_q29(o->x[2], &s, &c);
    gc = rfe_fix_mul(rfe_fix_mul(o->p.g, c, 30u, sat), dt, 30u, sat); /* Q26 */
    A[0] = rfe_fix_sub(o->S[0], rfe_fix_mul(gc, o->S[6], 31u, sat), sat);  /* Q26 Q29 -> Q24 */
    A[1] = rfe_fix_sub(0, rfe_fix_mul(gc, o->S[8], 31u, sat), sat);
    q[0] = rfe_fix_mul(o->p.q_v, sdt, 30u, sat);
    q[1] = rfe_fix_mul(o->p.r_ax, dt, 30u, sat);
    st = rfe_fix_norm(q, 2u, &A[2], sat);
    A[4] = o->S[6];
    A[5] = o->S[8];
    A[7] = rfe_fix_mul(q_theta_now_q31(o), sdt, 30u, sat);
    if (st == RFE_OK) {
        st = rfe_qr_tria_q31(A, 2u, 4u, 4u, sat);
    }
    if (st == RFE_OK) {
        /* a_x - g sin theta in Q24 (Q26 Q30 -> Q24), times dt (Q30) */
        const rfe_fix_t acc = rfe_fix_sub(in->ax, rfe_fix_mul(o->p.g, s, 32u, sat), sat);
        size_t i;
        for (i = 0u; i < (N * N); ++i) {
            S[i] = o->S[i];
        }
        x[0] = rfe_fix_add(o->x[0], rfe_fix_mul(acc, dt, 30u, sat), sat);
        x[1] = o->x[1];
        x[2] = o->x[2];
        S[0] = A[0];
        S[6] = A[4];
        S[8] = A[5];
        st = rfe_mg_correct_speed_q31(o->p.r_v, in->v, x, S, sat);
    }
    if (st == RFE_OK) {
        o->x[0] = x[0];
        o->x[2] = rfe_fix_clamp(x[2], -o->p.theta_max, o->p.theta_max);
        o->S[0] = S[0];
        o->S[6] = S[6];
        o->S[8] = S[8];
        o->adapt_elapsed = 0;
        o->m_adapt = o->x[1];
    }
    return st;
}

/* §4.2 the change test (pause_grade_dv) on a sample that may learn the grade, as the float
 * twin's change_seen: d += (u - u_prev) - dt (ax - g sin theta) in Q24 (int64: |d| stays
 * within pause_grade_dv <= 10 m/s plus one sample's increment), the product and g sin theta
 * rounded as in grade_from_ax_q31; 1 when the sample learns. */
static int change_seen_q31(rfe_mass_grade_q31_t *o, const rfe_mass_grade_input_q31_t *in,
                           uint32_t *sat)
{
    int test_on = 0;
    int beyond = 0;
    if (o->p.pause_grade_dv > 0) {
        test_on = 1;
    }
    if (rfe_mg_change_sums(test_on, o->chg_on) != 0) {
        int32_t s = 0;
        int32_t c = 0;
        rfe_fix_t acc;
        int64_t ad;
        rfe_q31_sincos_q29(o->x[2], &s, &c);
        acc = rfe_fix_sub(in->ax, rfe_fix_mul(o->p.g, s, 32u, sat), sat); /* Q24 */
        o->chg_d += ((int64_t)test_speed_q31(in) - (int64_t)o->u_prev) -
                    (int64_t)rfe_fix_mul(acc, in->dt, 30u, sat);
        ad = (o->chg_d < 0) ? -o->chg_d : o->chg_d;
        if (ad > (int64_t)o->p.pause_grade_dv) {
            beyond = 1;
        }
    }
    o->chg_on = rfe_mg_change_tripped(test_on, o->chg_on, beyond);
    return (o->chg_on != 0u) ? 1 : 0;
}

/* §4.2 a paused sample: the grade from ax where pause_grade sets the pause's bit, v is
 * uncorrelated with M (the last accepted sample a start or a paused one, v_free: not a
 * test of S_Mv = 0, which an update's Q14 mass row can reach by rounding alone), the ABS
 * gate's latch is clear and the change test saw the held grade contradicted, else the hold;
 * a sample that may not learn clears the change test. */
static rfe_status_t paused_q31(rfe_mass_grade_q31_t *o, const rfe_mass_grade_input_q31_t *in,
                               rfe_status_t status, uint32_t *sat)
{
    rfe_status_t st;
    int learn = 0;
    if (rfe_mg_grade_in_pause(status, rfe_mg_pause_grade_bits(o->p.pause_grade, o->p.use_ax),
                              o->v_free, o->slip_latched) != 0) {
        learn = change_seen_q31(o, in, sat);
    } else {
        o->chg_on = 0u;
        o->chg_d = 0;
    }
    if (learn != 0) {
        st = grade_from_ax_q31(o, in, in->dt, sat);
    } else {
        st = hold_q31(o, in, in->dt, sat);
    }
    return st;
}

/* The adaptation's stop: q_mv <= mv_stop q_mc^2 (in rfe_xf_t: the square exact, the product
 * and the comparison to 2^-30 relative). */
static int adaptation_over_q31(const rfe_mass_grade_q31_t *o)
{
    const rfe_xf_t qmc2 = rfe_xf_make((int64_t)o->p.q_mc * (int64_t)o->p.q_mc, -RFE_MG_Q_QMV);
    const rfe_xf_t stop = rfe_xf_mul(rfe_xf_of(o->p.mv_stop, RFE_MG_Q_COEF), qmc2);
    return (rfe_xf_sign(rfe_xf_sub(rfe_xf_make(o->q_mv, -RFE_MG_Q_QMV), stop)) <= 0) ? 1 : 0;
}

/* §4.4 eqs. 22-25 once per adaptation period: lambda_u = 1/2 |q_s - D| / (q_s + D) (in
 * rfe_xf_t, then Q30) scales q_mv; P's mass row and column by lambda_u and P_MM once:
 * P' = D P D + (lambda - lambda^2) P_MM e2 e2^T, D = diag(1, lambda, 1), in square-root
 * form S' = Tria([D S, sqrt(lambda - lambda^2) |S row M| e2]). */
static rfe_status_t adapt_q31(rfe_mass_grade_q31_t *o, rfe_fix_t dt, uint32_t *sat)
{
    rfe_fix_t A[12] = {0};
    rfe_fix_t lam = HALF_Q30; /* 1/2, the limit at D = 0 */
    rfe_fix_t sd_m = 0;
    rfe_xf_t qs;
    rfe_xf_t d;
    int64_t dm;
    int64_t l2;
    uint64_t e;
    rfe_status_t st;
    o->adapt_elapsed += (int64_t)dt;
    /* the period ends within half a sample period of t_adapt: 2 tau >= 2 t_adapt - dt */
    if ((2 * o->adapt_elapsed) < (((2 * (int64_t)o->p.t_adapt) * TIME_TO_DT) - (int64_t)dt)) {
        return RFE_OK;
    }
    dm = (int64_t)o->x[1] - (int64_t)o->m_adapt;
    d = rfe_xf_make(dm * dm, -RFE_MG_Q_QMV);                     /* (M_t - M_a)^2, Q28 */
    qs = rfe_xf_mul(rfe_xf_make(o->q_mv, -RFE_MG_Q_QMV),
                    rfe_xf_make(o->adapt_elapsed, -RFE_MG_Q_DT)); /* q_mv tau, kg^2 */
    if (rfe_xf_sign(rfe_xf_add(qs, d)) > 0) {
        rfe_xf_t num = rfe_xf_sub(qs, d);
        if (rfe_xf_sign(num) < 0) {
            num = rfe_xf_neg(num);
        }
        lam = rfe_xf_to_fix(rfe_xf_div(rfe_xf_make((int64_t)num.m, num.e - 1), rfe_xf_add(qs, d)),
                            30, sat);
    }
    o->q_mv = rfe_q31_mul64x32(o->q_mv, (int64_t)lam, 30u);
    /* sqrt(lambda - lambda^2): exact in Q60, exactly rounded to Q30 */
    l2 = ((int64_t)lam * rfe_q31_pow2(30u)) - ((int64_t)lam * (int64_t)lam); /* >= 0 */
    e = rfe_q31_sqrt_round((uint64_t)l2);
    st = rfe_fix_norm(&o->S[3], 2u, &sd_m, sat);
    A[0] = o->S[0];
    A[4] = rfe_fix_mul(o->S[3], lam, 30u, sat);
    A[5] = rfe_fix_mul(o->S[4], lam, 30u, sat);
    A[7] = rfe_fix_mul(sd_m, (rfe_fix_t)e, 30u, sat);
    A[8] = o->S[6];
    A[9] = o->S[7];
    A[10] = o->S[8];
    if (st == RFE_OK) {
        st = rfe_qr_tria_q31(A, N, 4u, 4u, sat);
    }
    if (st == RFE_OK) {
        size_t r;
        size_t c;
        for (r = 0u; r < N; ++r) {
            for (c = 0u; c < N; ++c) {
                o->S[(r * N) + c] = A[(r * 4u) + c];
            }
        }
        if (adaptation_over_q31(o) != 0) {
            o->q_mv = 0; /* q_22 has converged to q_mc^2: the AUKF is the UKF now */
        }
        o->adapt_elapsed = 0;
        o->m_adapt = o->x[1];
    }
    return st;
}

/* §4.3 steps 1-2: the points of (x, S) through f(x) = [v + dt v-dot(T_prev), M, theta]; Q's
 * roots q_v sqrt(dt), sqrt(q_mc^2 + q_mv) sqrt(dt), q_theta sqrt(dt). */
static rfe_status_t time_update_q31(const rfe_mass_grade_q31_t *o, rfe_fix_t dt,
                                    rfe_fix_t xm[RFE_MG_N_Q31],
                                    rfe_fix_t Sm[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat)
{
    const rfe_mg_weights_q31_t w = {o->wm0, o->wi, o->sqrt_wc0, o->sqrt_wi, o->sqrt_c};
    const rfe_xf_t xdt = rfe_xf_of(dt, RFE_MG_Q_DT);
    const rfe_fix_t sdt = sqrt_dt_q31(dt, sat);
    rfe_fix_t chi[RFE_MG_PTS_Q31 * RFE_MG_N_Q31];
    rfe_fix_t sq[RFE_MG_N_Q31];
    int64_t qm2;
    uint64_t qm;
    size_t i;
    model_q31_t k;
    model_of_q31(&o->p, o->torque_prev, &k);
    rfe_mg_sigma_points_q31(o->x, o->S, o->sqrt_c, chi, sat);
    for (i = 0u; i < PTS; ++i) {
        rfe_fix_t *pt = &chi[i * N];
        rfe_fix_t s = 0;
        const rfe_xf_t a = accel_q31(&o->p, &k, pt, &s);
        pt[0] = rfe_fix_add(pt[0], rfe_xf_to_fix(rfe_xf_mul(xdt, a), RFE_MG_Q_V, sat), sat);
    }
    qm2 = rfe_fix_add64((int64_t)o->p.q_mc * (int64_t)o->p.q_mc, o->q_mv, sat); /* Q28 */
    qm = rfe_q31_sqrt_round((uint64_t)qm2);                                       /* Q14 */
    sq[0] = rfe_fix_mul(o->p.q_v, sdt, 30u, sat);
    sq[1] = rfe_fix_sat32(rfe_fix_shr64_round((int64_t)qm * (int64_t)sdt, 30u), sat);
    sq[2] = rfe_fix_mul(q_theta_now_q31(o), sdt, 30u, sat);
    return rfe_mg_predict_q31(chi, &w, sq, xm, Sm, sat);
}

/* §4.3 steps 3-7: the speed row alone (rfe_mg_correct_speed_q31: linear in the state, it
 * needs no sigma points); with the ax row, new points of (x-, S-) and their z_ax = v-dot(T) +
 * g sin theta, then the ax row and the speed row (rfe_mg_correct_q31). */
static rfe_status_t measurement_update_q31(const rfe_mass_grade_q31_t *o,
                                           const rfe_mass_grade_input_q31_t *in,
                                           rfe_fix_t x[RFE_MG_N_Q31],
                                           rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat,
                                           rfe_fix_t *e_ax)
{
    rfe_status_t st;
    if (o->p.use_ax == 1u) {
        const rfe_mg_weights_q31_t w = {o->wm0, o->wi, o->sqrt_wc0, o->sqrt_wi, o->sqrt_c};
        const rfe_fix_t r[RFE_MG_Z_MAX_Q31] = {o->p.r_v, o->p.r_ax};
        const rfe_fix_t y[RFE_MG_Z_MAX_Q31] = {in->v, in->ax};
        rfe_fix_t chi[RFE_MG_PTS_Q31 * RFE_MG_N_Q31];
        rfe_fix_t Z[RFE_MG_PTS_Q31];
        model_q31_t k;
        size_t i;
        model_of_q31(&o->p, in->torque, &k);
        rfe_mg_sigma_points_q31(x, S, o->sqrt_c, chi, sat);
        for (i = 0u; i < PTS; ++i) {
            rfe_fix_t s = 0;
            const rfe_xf_t a = accel_q31(&o->p, &k, &chi[i * N], &s);
            const rfe_xf_t gs = rfe_xf_mul(k.g, rfe_xf_of(s, 30));
            Z[i] = rfe_xf_to_fix(rfe_xf_add(a, gs), RFE_MG_Q_V, sat);
        }
        st = rfe_mg_correct_q31(chi, Z, &w, r, y, x, S, sat, e_ax);
    } else {
        st = rfe_mg_correct_speed_q31(o->p.r_v, in->v, x, S, sat);
    }
    return st;
}

/* §4.8 the mismatch monitor's EMA of the ax row's normalised innovation e (Q24): k = dt/tau
 * in Q30 (<= 1: mm_tau >= dt_max >= dt) by an exactly rounded division, then m += k (e - m),
 * the product rounded (each step's error at most 1/2 LSB of the division times |e - m| plus
 * 1/2 LSB of Q24 from the product, so the EMA stays within a few LSB of the real recursion's
 * on the same e: FIXED_POINT.md). e - m saturates (counted) only beyond +-128. */
static void mismatch_ema_q31(rfe_mass_grade_q31_t *o, rfe_fix_t e, rfe_fix_t dt, uint32_t *sat)
{
    rfe_fix_t k = 0;
    const rfe_status_t st = rfe_fix_div(dt, o->p.mm_tau, 24, &k, sat); /* Q30/Q24 -> Q30 */
    (void)st; /* tau > 0 (validated), the shift in range: RFE_OK */
    o->mm_e = rfe_fix_add(o->mm_e, rfe_fix_mul(k, rfe_fix_sub(e, o->mm_e, sat), 30u, sat), sat);
}

/* §4.3 one filter step, the projection of the mean and the adaptation; o is the caller's
 * copy, so an error leaves the estimator untouched. */
static rfe_status_t update_q31(rfe_mass_grade_q31_t *o, const rfe_mass_grade_input_q31_t *in,
                               rfe_fix_t dt, uint32_t *sat)
{
    rfe_fix_t x[RFE_MG_N_Q31];
    rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31];
    rfe_fix_t e = 0;
    rfe_status_t st = time_update_q31(o, dt, x, S, sat);
    if (st == RFE_OK) {
        st = measurement_update_q31(o, in, x, S, sat, &e);
    }
    if (st == RFE_OK) {
        size_t i;
        x[1] = rfe_fix_clamp(x[1], o->p.m_min, o->p.m_max); /* step 8 */
        x[2] = rfe_fix_clamp(x[2], -o->p.theta_max, o->p.theta_max);
        for (i = 0u; i < N; ++i) {
            o->x[i] = x[i];
        }
        for (i = 0u; i < (N * N); ++i) {
            o->S[i] = S[i];
        }
        if (o->p.use_ax == 1u) {
            mismatch_ema_q31(o, e, dt, sat);
        }
        if ((o->p.adaptive == 1u) && (o->q_mv > 0)) {
            st = adapt_q31(o, dt, sat);
        }
    }
    return st;
}

/* §1 the outputs: the state, the sd as the norms of S's rows (exactly rounded). */
static void estimate_of_q31(const rfe_mass_grade_q31_t *o, rfe_status_t status, uint32_t step_sat,
                            rfe_mass_grade_estimate_q31_t *e)
{
    uint32_t sat = 0u; /* a row norm fits its format: |S row| <= the largest sd, never counted */
    rfe_status_t st = rfe_fix_norm(&o->S[3], 2u, &e->sd_mass, &sat);
    if (st == RFE_OK) {
        st = rfe_fix_norm(&o->S[6], 3u, &e->sd_grade, &sat);
    }
    (void)st; /* non-NULL arguments */
    e->mass = o->x[1];
    e->grade = o->x[2];
    e->v = o->x[0];
    e->sd_v = rfe_fix_abs(o->S[0], &sat);
    e->q_mv = o->q_mv;
    e->e_ax = o->mm_e;
    e->mismatch = rfe_mg_mismatch((o->p.mm_e > 0) ? 1 : 0,
                                  (rfe_fix_abs(o->mm_e, &sat) > o->p.mm_e) ? 1 : 0);
    e->sat = step_sat;
    e->status = status;
}

rfe_status_t rfe_mass_grade_step_q31(rfe_mass_grade_q31_t *mg, const rfe_mass_grade_input_q31_t *in,
                                     rfe_mass_grade_estimate_q31_t *out)
{
    rfe_mass_grade_q31_t o;
    uint32_t sat = 0u;
    rfe_status_t st;
    rfe_status_t status = RFE_OK;
    rfe_mg_plan_t plan = RFE_MG_PLAN_STEP;
    if ((mg == NULL) || (in == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mg->magic != RFE_MAGIC_MG_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    st = check_torque_sample_q31(mg, in);
    o = *mg; /* work on a copy: an error leaves the estimator as it was */
    if ((st == RFE_OK) &&
        (rfe_mg_plan(o.started, (in->dt > o.p.dt_max) ? 1 : 0) == RFE_MG_PLAN_START)) {
        start_filter_q31(&o, in); /* §4.1: a first sample or a gap the model cannot bridge */
        plan = RFE_MG_PLAN_START;
        status = pause_status_q31(&o, in, 0);
    } else if (st == RFE_OK) {
        status = pause_status_q31(&o, in, in->dt);
        if (status == RFE_OK) {
            o.chg_on = 0u; /* an update: no pause, the change test cleared */
            o.chg_d = 0;
            st = update_q31(&o, in, in->dt, &sat);
        } else {
            st = paused_q31(&o, in, status, &sat);
        }
    } else {
        /* the checks failed: nothing to compute */
    }
    if (st != RFE_OK) {
        *out = mg->last;
        out->status = st;
        return st;
    }
    o.started = 1u;
    o.torque_prev = in->torque;
    o.v_free = rfe_mg_v_free(plan, status);
    o.u_prev = test_speed_q31(in);
    if ((plan != RFE_MG_PLAN_START) && (o.p.q_theta_hi != 0)) {
        walk_level_q31(&o, mg->x[2], in->dt, &sat);
    }
    rfe_q31_sat_add(&o.sat, sat);
    estimate_of_q31(&o, status, sat, &o.last);
    *mg = o;
    *out = o.last;
    return status;
}

rfe_status_t rfe_mass_grade_restart_q31(rfe_mass_grade_q31_t *mg)
{
    if (mg == NULL) {
        return RFE_ERR_NULL;
    }
    if (mg->magic != RFE_MAGIC_MG_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    mg->started = 0u; /* the next accepted sample starts afresh (§4.1) */
    return RFE_OK;
}

rfe_status_t rfe_mass_grade_get_q31(const rfe_mass_grade_q31_t *mg,
                                    rfe_mass_grade_estimate_q31_t *out)
{
    if ((mg == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mg->magic != RFE_MAGIC_MG_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    *out = mg->last;
    return RFE_OK;
}
