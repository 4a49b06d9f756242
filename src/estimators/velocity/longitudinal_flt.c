/**
 * @file longitudinal_flt.c
 * @brief The longitudinal filter [vx, b_x] (docs/OBSERVER.md §3.3-3.5): ax integrated,
 *        corrected by the wheels that can be trusted: free-rolling wheels measure vx, a
 *        braked wheel bounds it from below, a driven wheel from above.
 */
#include "estimators/velocity/velocity_internal.h"
#include "estimators/velocity/velocity_logic.h"

#include "models/vehicle.h"
#include "numerics/internal.h"

void rfe_vel_wheel_refs(const rfe_vehicle_t *veh, const rfe_velocity_input_t *in, rfe_real_t vy,
                        rfe_real_t refs[RFE_WHEELS])
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    const rfe_real_t sd = RFE_SIN(in->delta);
    const rfe_real_t cd = RFE_COS(in->delta);
    size_t i;
    rfe_wheel_positions(veh, px, py);
    for (i = 0u; i < RFE_WHEELS; ++i) {
        const rfe_real_t v_w = in->omega[i] * veh->R;
        const rfe_real_t s = (i < 2u) ? sd : RFE_R(0.0);
        const rfe_real_t c = (i < 2u) ? cd : RFE_R(1.0);
        refs[i] = ((v_w - ((vy + (in->yaw_rate * px[i])) * s)) / c) + (in->yaw_rate * py[i]);
    }
}

/* §3.4 the driving state: the comparisons here, what follows from them in
 * velocity_logic.h. */
static rfe_vel_drive_state_t driving_state(const rfe_velocity_params_t *p,
                                           const rfe_velocity_input_t *in, rfe_real_t a_net)
{
    rfe_vel_drive_tests_t t = {0, 0, 0u, 0u, 0};
    size_t i;
    if ((p->ay_turn > RFE_R(0.0)) && (RFE_FABS(in->ay) >= p->ay_turn)) {
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

/* §3.5 what the plausible wheels say: the free ones' sum and count, the fastest and the
 * slowest of all plausible ones and their count. */
typedef struct {
    rfe_real_t sum;
    size_t n_free;
    rfe_real_t hi;
    rfe_real_t lo;
    size_t n_ok;
} wheel_vote_t;

static wheel_vote_t wheel_votes(const rfe_real_t refs[RFE_WHEELS], rfe_real_t vx_pred,
                                rfe_real_t gate, const rfe_vel_drive_state_t *ds)
{
    wheel_vote_t w = {RFE_R(0.0), 0u, RFE_R(0.0), RFE_R(0.0), 0u};
    size_t i;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        if (RFE_FABS(refs[i] - vx_pred) <= gate) {
            if (rfe_vel_wheel_is_free(ds, i) != 0) {
                w.sum += refs[i];
                ++w.n_free;
            }
            w.hi = (w.n_ok == 0u) ? refs[i] : rfe_max(w.hi, refs[i]);
            w.lo = (w.n_ok == 0u) ? refs[i] : rfe_min(w.lo, refs[i]);
            ++w.n_ok;
        }
    }
    return w;
}

/* §3.5 every wheel, gated or not: their sum, the fastest and the slowest, for the
 * re-acquisition. */
typedef struct {
    rfe_real_t sum;
    rfe_real_t hi;
    rfe_real_t lo;
} wheel_spread_t;

static wheel_spread_t wheel_spread(const rfe_real_t refs[RFE_WHEELS])
{
    wheel_spread_t a = {refs[0], refs[0], refs[0]};
    size_t i;
    for (i = 1u; i < RFE_WHEELS; ++i) {
        a.sum += refs[i];
        a.hi = rfe_max(a.hi, refs[i]);
        a.lo = rfe_min(a.lo, refs[i]);
    }
    return a;
}

/* §3.5 which reference (the choice in velocity_logic.h). */
static rfe_vel_ref_t reference_kind(const rfe_velocity_params_t *p, const wheel_vote_t *w,
                                    const wheel_spread_t *a, rfe_real_t vx_pred,
                                    const rfe_vel_drive_state_t *ds, rfe_real_t sd_w)
{
    const rfe_vel_ref_t ref = rfe_vel_reference(w->n_free, w->n_ok, ds,
                                                (w->hi > vx_pred) ? 1 : 0,
                                                (w->lo < vx_pred) ? 1 : 0);
    return rfe_vel_reacquire(ref, ((a->hi - a->lo) <= (p->k_agree * sd_w)) ? 1 : 0,
                             (a->hi < p->v_stand) ? 1 : 0, ds);
}

/* §3.5 the wheel reference z and its variance *r for @p ref; a re-acquisition also
 * re-inflates the prediction's variance by the innovation squared (*p00). */
static void wheel_reference(rfe_vel_ref_t ref, const wheel_vote_t *w, const wheel_spread_t *a,
                            rfe_real_t vx_pred, rfe_real_t sd_w, rfe_real_t *z, rfe_real_t *r,
                            rfe_real_t *p00)
{
    *r = sd_w * sd_w;
    if (ref == RFE_VEL_REF_FREE_MEAN) {
        *z = w->sum / (rfe_real_t)w->n_free;
        *r = *r / (rfe_real_t)w->n_free;
    } else if (ref == RFE_VEL_REF_BRAKED_HI) {
        *z = w->hi;
    } else if (ref == RFE_VEL_REF_DRIVEN_LO) {
        *z = w->lo;
    } else if (ref == RFE_VEL_REF_REACQUIRE) {
        *z = a->sum / (rfe_real_t)RFE_WHEELS;
        *r = *r / (rfe_real_t)RFE_WHEELS;
        *p00 += (*z - vx_pred) * (*z - vx_pred);
    } else {
        /* none */
    }
}

rfe_status_t rfe_vel_longitudinal_step(rfe_kf2_t *f, const rfe_velocity_params_t *p,
                                       const rfe_vehicle_t *veh, const rfe_velocity_input_t *in,
                                       rfe_real_t vy_prev, uint32_t *flags)
{
    rfe_kf2_t k;
    rfe_real_t refs[RFE_WHEELS];
    rfe_real_t z = RFE_R(0.0);
    rfe_real_t r = RFE_R(0.0);
    rfe_vel_drive_state_t ds;
    uint32_t fl;
    const rfe_real_t dt = in->dt;
    /* §3.4 the driving state takes a_lon, the tyres' push: r vy moves vx without a brake or
     * a drive torque (a car that slides out) */
    const rfe_real_t a_lon = in->ax - (veh->g * RFE_SIN(in->grade));
    const rfe_real_t a = a_lon + (in->yaw_rate * vy_prev);
    const rfe_real_t sx = dt * p->sd_ax;
    rfe_status_t st;
    rfe_real_t q;
    k = *f;
    /* the predict keeps b_x: the driving state (and with it b_x's walk) from it first */
    ds = driving_state(p, in, a_lon - k.x[1]);
    q = (ds.turning != 0) ? p->q_bx_turn : p->q_bx;
    st = rfe_kf2_predict(&k, -dt, dt * a, sx * sx, (q * q) * dt, RFE_R(0.0));
    if (st != RFE_OK) {
        return st;
    }
    fl = rfe_vel_drive_flags(&ds);
    rfe_vel_wheel_refs(veh, in, vy_prev, refs);
    {
        const rfe_real_t vx_pred = k.x[0];
        const rfe_real_t sd_w = p->sd_wheel + (p->sd_wheel_rel * RFE_FABS(vx_pred));
        const rfe_real_t gate = p->k_gate * RFE_SQRT(k.p00 + (sd_w * sd_w));
        const wheel_vote_t w = wheel_votes(refs, vx_pred, gate, &ds);
        const wheel_spread_t all = wheel_spread(refs);
        const rfe_vel_ref_t ref = reference_kind(p, &w, &all, vx_pred, &ds, sd_w);
        wheel_reference(ref, &w, &all, vx_pred, sd_w, &z, &r, &k.p00);
        if (ref != RFE_VEL_REF_NONE) {
            st = rfe_kf2_update(&k, RFE_R(1.0), RFE_R(0.0), z - vx_pred, r);
            fl |= RFE_VEL_FLAG_VX_WHEEL;
        } else if (rfe_vel_brake_drift(ref, &ds) != 0) {
            k.p00 += (p->q_vx_brake * p->q_vx_brake) * dt;
        } else {
            /* rolling or driving without a wheel: the prediction's own variance */
        }
    }
    if (st == RFE_OK) {
        if (k.x[0] < RFE_R(0.0)) {
            k.x[0] = RFE_R(0.0); /* forward driving only */
        }
        *f = k;
        *flags |= fl;
    }
    return st;
}
