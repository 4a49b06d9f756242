/**
 * @file longitudinal_q31.c
 * @brief The longitudinal filter [vx Q23, b_x Q24] in fixed point (docs/OBSERVER.md
 *        §3.3-3.5; twin of longitudinal_flt.c): ax integrated, corrected by the wheels that
 *        can be trusted. The decisions are velocity_logic.h's, shared with the float twin.
 */
#include "estimators/velocity/velocity_internal_q31.h"
#include "estimators/velocity/velocity_logic.h"

#include "rfe/component/fxmath.h"

#include "numerics/fxmath_internal_q31.h"
#include "numerics/internal_q31.h"

/* Wheel positions (MODEL.md §2), Q29: the twin of models/vehicle.h's rfe_wheel_positions. */
static void wheel_positions_q31(const rfe_vehicle_q31_t *veh, rfe_fix_t px[RFE_WHEELS],
                                rfe_fix_t py[RFE_WHEELS])
{
    px[RFE_FL] = veh->Lf;
    px[RFE_FR] = veh->Lf;
    px[RFE_RL] = -veh->Lr;
    px[RFE_RR] = -veh->Lr;
    py[RFE_FL] = veh->yf;
    py[RFE_FR] = -veh->yf;
    py[RFE_RL] = veh->yr;
    py[RFE_RR] = -veh->yr;
}

void rfe_vel_wheel_refs_q31(const rfe_vehicle_q31_t *veh, const rfe_velocity_input_q31_t *in,
                            rfe_fix_t vy, rfe_fix_t refs[RFE_WHEELS], uint32_t *sat)
{
    rfe_fix_t px[RFE_WHEELS];
    rfe_fix_t py[RFE_WHEELS];
    rfe_fix_t sd = 0;
    rfe_fix_t cd = RFE_FIX_ONE(30);
    size_t i;
    rfe_q31_sincos_q29(in->delta, &sd, &cd); /* every int32 angle */
    wheel_positions_q31(veh, px, py);
    for (i = 0u; i < RFE_WHEELS; ++i) {
        /* omega Q22 R Q29 -> Q23; r Q27 x Q29 -> Q23 */
        rfe_fix_t v = rfe_fix_mul(in->omega[i], veh->R, 28u, sat);
        if (i < 2u) {
            const rfe_fix_t lat = rfe_fix_add(vy, rfe_fix_mul(in->yaw_rate, px[i], 33u, sat), sat);
            const rfe_fix_t num = rfe_fix_sub(v, rfe_fix_mul(lat, sd, 30u, sat), sat);
            /* cos(delta) >= cos(1 rad) > 0 after the input check: the division is defined */
            const rfe_status_t sd_st = rfe_fix_div(num, cd, 30, &v, sat);
            (void)sd_st;
        }
        refs[i] = rfe_fix_add(v, rfe_fix_mul(in->yaw_rate, py[i], 33u, sat), sat);
    }
}

/* §3.4 the driving state: the comparisons here, what follows from them in
 * velocity_logic.h. */
static rfe_vel_drive_state_t driving_state_q31(const rfe_velocity_params_q31_t *p,
                                               const rfe_velocity_input_q31_t *in,
                                               rfe_fix_t a_net, uint32_t *sat)
{
    rfe_vel_drive_tests_t t = {0, 0, 0u, 0u, 0};
    size_t i;
    if ((p->ay_turn > 0) && (rfe_fix_abs(in->ay, sat) >= p->ay_turn)) {
        t.turning = 1;
    }
    if (a_net < -p->ax_brake_on) {
        t.decelerating = 1;
    }
    if (a_net > p->ax_drive_on) {
        t.accelerating = 1;
    }
    for (i = 0u; i < RFE_WHEELS; ++i) {
        if (in->p_brake[i] > p->p_brake_on) {
            t.pressure_mask |= rfe_vel_wheel_bit(i);
        }
        if (in->torque[i] > p->torque_on) {
            t.torque_mask |= rfe_vel_wheel_bit(i);
        }
    }
    return rfe_vel_drive_state(&t, in->has, p->driven);
}

/* §3.5 what the plausible wheels say (Q23; the sum in int64). */
typedef struct {
    int64_t sum;
    size_t n_free;
    rfe_fix_t hi;
    rfe_fix_t lo;
    size_t n_ok;
} wheel_vote_q31_t;

static wheel_vote_q31_t wheel_votes_q31(const rfe_fix_t refs[RFE_WHEELS], rfe_fix_t vx_pred,
                                        rfe_fix_t gate, const rfe_vel_drive_state_t *ds)
{
    wheel_vote_q31_t w = {0, 0u, 0, 0, 0u};
    size_t i;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        const int64_t d = (int64_t)refs[i] - (int64_t)vx_pred;
        if (((d < 0) ? -d : d) <= (int64_t)gate) {
            if (rfe_vel_wheel_is_free(ds, i) != 0) {
                w.sum += (int64_t)refs[i];
                ++w.n_free;
            }
            w.hi = (w.n_ok == 0u) ? refs[i] : rfe_fix_max(w.hi, refs[i]);
            w.lo = (w.n_ok == 0u) ? refs[i] : rfe_fix_min(w.lo, refs[i]);
            ++w.n_ok;
        }
    }
    return w;
}

/* §3.5 every wheel, gated or not: their sum (int64), the fastest and the slowest, for the
 * re-acquisition. */
typedef struct {
    int64_t sum;
    rfe_fix_t hi;
    rfe_fix_t lo;
} wheel_spread_q31_t;

static wheel_spread_q31_t wheel_spread_q31(const rfe_fix_t refs[RFE_WHEELS])
{
    wheel_spread_q31_t a = {(int64_t)refs[0], refs[0], refs[0]};
    size_t i;
    for (i = 1u; i < RFE_WHEELS; ++i) {
        a.sum += (int64_t)refs[i];
        a.hi = rfe_fix_max(a.hi, refs[i]);
        a.lo = rfe_fix_min(a.lo, refs[i]);
    }
    return a;
}

/* §3.5 which reference (the choice in velocity_logic.h); the spread in int64. */
static rfe_vel_ref_t reference_kind_q31(const rfe_velocity_params_q31_t *p,
                                        const wheel_vote_q31_t *w, const wheel_spread_q31_t *a,
                                        rfe_fix_t vx_pred, const rfe_vel_drive_state_t *ds,
                                        rfe_fix_t sd_w, uint32_t *sat)
{
    const rfe_vel_ref_t ref = rfe_vel_reference(w->n_free, w->n_ok, ds,
                                                (w->hi > vx_pred) ? 1 : 0,
                                                (w->lo < vx_pred) ? 1 : 0);
    /* k_agree Q24 sd_w Q23 -> Q23 */
    const rfe_fix_t bound = rfe_fix_mul(p->k_agree, sd_w, 24u, sat);
    const int64_t spread = (int64_t)a->hi - (int64_t)a->lo;
    return rfe_vel_reacquire(ref, (spread <= (int64_t)bound) ? 1 : 0,
                             (a->hi < p->v_stand) ? 1 : 0, ds);
}

/* §3.5 the wheel reference z (Q23) and its variance *r (Q46) for @p ref; a re-acquisition
 * also re-inflates the prediction's variance (*p00, Q46) by the innovation squared. */
static void wheel_reference_q31(rfe_vel_ref_t ref, const wheel_vote_q31_t *w,
                                const wheel_spread_q31_t *a, rfe_fix_t vx_pred, rfe_fix_t sd_w,
                                rfe_fix_t *z, int64_t *r, int64_t *p00, uint32_t *sat)
{
    *r = rfe_vel_var_q31(sd_w, sat);
    if (ref == RFE_VEL_REF_FREE_MEAN) {
        const int64_t n = (int64_t)w->n_free; /* 1 .. 4 */
        *z = rfe_q31_div_round(w->sum, (rfe_fix_t)n, sat);
        *r = (*r + (n / 2)) / n; /* r >= 0: rounded to nearest */
    } else if (ref == RFE_VEL_REF_BRAKED_HI) {
        *z = w->hi;
    } else if (ref == RFE_VEL_REF_DRIVEN_LO) {
        *z = w->lo;
    } else if (ref == RFE_VEL_REF_REACQUIRE) {
        const int64_t n = (int64_t)RFE_WHEELS;
        *z = rfe_q31_div_round(a->sum, (rfe_fix_t)n, sat);
        *r = (*r + (n / 2)) / n;
        *p00 = rfe_vel_pmax_q31(
            rfe_fix_add64(*p00, rfe_vel_var_q31(rfe_fix_sub(*z, vx_pred, sat), sat), sat), sat);
    } else {
        /* none */
    }
}

/* The tyres' longitudinal push ax - g sin(grade), Q24 (the step adds r vy_prev). A grade of 0
 * (the input's default when the car does not know it) has the sine 0 that rfe_q31_sincos_q29
 * gives for it (test_velocity_q31.c checks that integer), so the two sines of that call are
 * skipped. */
static rfe_fix_t lon_acc_q31(const rfe_vehicle_q31_t *veh, const rfe_velocity_input_q31_t *in,
                             uint32_t *sat)
{
    rfe_fix_t sg = 0;
    rfe_fix_t cg = 0;
    if (in->grade != 0) {
        rfe_q31_sincos_q29(in->grade, &sg, &cg); /* every int32 angle */
    }
    return rfe_fix_sub(in->ax, rfe_fix_mul(veh->g, sg, 30u, sat), sat);
}

rfe_status_t rfe_vel_longitudinal_step_q31(rfe_kf2_q31_t *f, const rfe_velocity_params_q31_t *p,
                                           const rfe_vehicle_q31_t *veh,
                                           const rfe_velocity_input_q31_t *in,
                                           rfe_fix_t vy_prev, uint32_t *flags, uint32_t *sat)
{
    rfe_kf2_q31_t k;
    rfe_fix_t refs[RFE_WHEELS];
    rfe_kf2_meas_q31_t m;
    rfe_vel_drive_state_t ds;
    uint32_t fl;
    uint32_t cnt = 0u;
    const rfe_fix_t dt = in->dt;
    /* §3.4 the driving state takes a_lon, the tyres' push: r vy moves vx without a brake or
     * a drive torque (a car that slides out) */
    const rfe_fix_t a_lon = lon_acc_q31(veh, in, &cnt);
    const rfe_fix_t a = rfe_fix_add(a_lon, rfe_fix_mul(in->yaw_rate, vy_prev, 26u, &cnt), &cnt);
    const int64_t q00 = rfe_vel_dt_var_q31(dt, p->sd_ax, &cnt);
    int64_t q11;
    rfe_status_t st;
    k = *f;
    /* the predict keeps b_x: the driving state (and with it b_x's walk) from it first */
    ds = driving_state_q31(p, in, rfe_fix_sub(a_lon, k.x[1], &cnt), &cnt);
    q11 = rfe_vel_scale_q31(rfe_vel_var_q31((ds.turning != 0) ? p->q_bx_turn : p->q_bx, &cnt),
                            dt, 30u, &cnt);
    /* f01 = -dt; u = dt a: Q30 Q24 -> Q23 */
    st = rfe_kf2_predict_q31(&k, -dt, rfe_fix_mul(dt, a, 31u, &cnt), q00, q11, 0, &cnt);
    if (st != RFE_OK) {
        return st;
    }
    fl = rfe_vel_drive_flags(&ds);
    rfe_vel_wheel_refs_q31(veh, in, vy_prev, refs, &cnt);
    {
        const rfe_fix_t vx_pred = k.x[0];
        const rfe_fix_t sd_w = rfe_fix_add(
            p->sd_wheel, rfe_fix_mul(p->sd_wheel_rel, rfe_fix_abs(vx_pred, &cnt), 30u, &cnt),
            &cnt);
        /* sqrt(p00 + sd_w^2): Q46 -> Q23, the root of an int64 below 2^62 */
        const int64_t v_gate = rfe_fix_add64(k.p00, rfe_vel_var_q31(sd_w, &cnt), &cnt);
        const uint64_t root = rfe_q31_sqrt_round((v_gate > 0) ? (uint64_t)v_gate : 0u);
        const rfe_fix_t sd_gate = rfe_fix_sat32((int64_t)root, &cnt);
        const rfe_fix_t gate = rfe_fix_mul(p->k_gate, sd_gate, 24u, &cnt);
        const wheel_vote_q31_t w = wheel_votes_q31(refs, vx_pred, gate, &ds);
        const wheel_spread_q31_t all = wheel_spread_q31(refs);
        const rfe_vel_ref_t ref = reference_kind_q31(p, &w, &all, vx_pred, &ds, sd_w, &cnt);
        rfe_fix_t z = 0;
        wheel_reference_q31(ref, &w, &all, vx_pred, sd_w, &z, &m.r, &k.p00, &cnt);
        if (ref != RFE_VEL_REF_NONE) {
            m.h0 = RFE_VEL_Q31_ONE;
            m.h1 = 0;
            m.qh0 = RFE_VEL_Q31_QONE;
            m.qh1 = RFE_VEL_Q31_QONE;
            m.qz = RFE_VEL_Q31_QV;
            m.nu = rfe_fix_sub(z, vx_pred, &cnt);
            st = rfe_kf2_update_q31(&k, &m, &cnt);
            fl |= RFE_VEL_FLAG_VX_WHEEL;
        } else if (rfe_vel_brake_drift(ref, &ds) != 0) {
            /* q_vx_brake^2 Q46, times dt Q30 */
            k.p00 = rfe_vel_pmax_q31(
                rfe_fix_add64(k.p00,
                              rfe_vel_scale_q31(rfe_vel_var_q31(p->q_vx_brake, &cnt), dt, 30u,
                                                &cnt),
                              &cnt),
                &cnt);
        } else {
            /* rolling or driving without a wheel: the prediction's own variance */
        }
    }
    if (st == RFE_OK) {
        if (k.x[0] < 0) {
            k.x[0] = 0; /* forward driving only */
        }
        *f = k;
        *flags |= fl;
        rfe_q31_sat_add(sat, cnt);
    }
    return st;
}
