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
    rfe_vel_drive_tests_t t = {0, 0, 0u, 0u};
    size_t i;
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

/* §3.5 the wheel reference z and its variance *r (the choice in velocity_logic.h); 0 when
 * there is none this step. */
static int wheel_reference(const wheel_vote_t *w, rfe_real_t vx_pred,
                           const rfe_vel_drive_state_t *ds, rfe_real_t sd_w, rfe_real_t *z,
                           rfe_real_t *r)
{
    const rfe_vel_ref_t ref = rfe_vel_reference(w->n_free, w->n_ok, ds,
                                                (w->hi > vx_pred) ? 1 : 0,
                                                (w->lo < vx_pred) ? 1 : 0);
    *r = sd_w * sd_w;
    if (ref == RFE_VEL_REF_FREE_MEAN) {
        *z = w->sum / (rfe_real_t)w->n_free;
        *r = *r / (rfe_real_t)w->n_free;
    } else if (ref == RFE_VEL_REF_BRAKED_HI) {
        *z = w->hi;
    } else if (ref == RFE_VEL_REF_DRIVEN_LO) {
        *z = w->lo;
    } else {
        /* none */
    }
    return (ref != RFE_VEL_REF_NONE) ? 1 : 0;
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
    const rfe_real_t a = (in->ax - (veh->g * RFE_SIN(in->grade))) + (in->yaw_rate * vy_prev);
    const rfe_real_t sx = dt * p->sd_ax;
    rfe_status_t st;
    k = *f;
    st = rfe_kf2_predict(&k, -dt, dt * a, sx * sx, (p->q_bx * p->q_bx) * dt,
                                      RFE_R(0.0));
    if (st != RFE_OK) {
        return st;
    }
    ds = driving_state(p, in, a - k.x[1]);
    fl = rfe_vel_drive_flags(&ds);
    rfe_vel_wheel_refs(veh, in, vy_prev, refs);
    {
        const rfe_real_t vx_pred = k.x[0];
        const rfe_real_t sd_w = p->sd_wheel + (p->sd_wheel_rel * RFE_FABS(vx_pred));
        const rfe_real_t gate = p->k_gate * RFE_SQRT(k.p00 + (sd_w * sd_w));
        const wheel_vote_t w = wheel_votes(refs, vx_pred, gate, &ds);
        if (wheel_reference(&w, vx_pred, &ds, sd_w, &z, &r) != 0) {
            st = rfe_kf2_update(&k, RFE_R(1.0), RFE_R(0.0), z - vx_pred, r);
            fl |= RFE_VEL_FLAG_VX_WHEEL;
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
