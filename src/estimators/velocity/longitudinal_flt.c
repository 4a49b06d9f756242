/**
 * @file longitudinal_flt.c
 * @brief The longitudinal filter [vx, b_x] (docs/OBSERVER.md §3.3-3.5): ax integrated,
 *        corrected by the wheels that can be trusted: free-rolling wheels measure vx, a
 *        braked wheel bounds it from below, a driven wheel from above.
 */
#include "estimators/velocity/velocity_internal.h"

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

/* One bit per wheel, fl fr rl rr (the RFE_DRIVEN_* order). */
static const uint32_t wheel_bit[RFE_WHEELS] = {RFE_DRIVEN_FL, RFE_DRIVEN_FR, RFE_DRIVEN_RL,
                                               RFE_DRIVEN_RR};

/* §3.4 the driving state: sets *braking, *driving (0 or 1) and the driven-wheel mask. */
static void driving_state(const rfe_velocity_params_t *p, const rfe_velocity_input_t *in,
                          rfe_real_t a_net, int *braking, int *driving, uint32_t *driven)
{
    size_t i;
    int brake = 0;
    int drive = 0;
    uint32_t mask = p->driven;
    if (a_net < -p->ax_brake_on) {
        brake = 1;
    }
    if ((in->has & RFE_VEL_HAS_PRESSURE) != 0u) {
        for (i = 0u; i < RFE_WHEELS; ++i) {
            if (in->p_brake[i] > p->p_brake_on) {
                brake = 1;
            }
        }
    }
    if ((brake == 0) && (a_net > p->ax_drive_on)) {
        drive = 1;
    }
    if ((in->has & RFE_VEL_HAS_TORQUE) != 0u) {
        mask = 0u;
        for (i = 0u; i < RFE_WHEELS; ++i) {
            if (in->torque[i] > p->torque_on) {
                mask |= wheel_bit[i];
            }
        }
        drive = 0;
        if ((brake == 0) && (mask != 0u)) {
            drive = 1;
        }
    }
    *braking = brake;
    *driving = drive;
    *driven = mask;
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
                                rfe_real_t gate, int braking, int driving, uint32_t driven)
{
    wheel_vote_t w = {RFE_R(0.0), 0u, RFE_R(0.0), RFE_R(0.0), 0u};
    size_t i;
    for (i = 0u; i < RFE_WHEELS; ++i) {
        if (RFE_FABS(refs[i] - vx_pred) <= gate) {
            if ((braking == 0) && ((driving == 0) || ((driven & wheel_bit[i]) == 0u))) {
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

/* §3.5 the wheel reference z and its variance *r; 0 when there is none this step. */
static int wheel_reference(const wheel_vote_t *w, rfe_real_t vx_pred, int braking, int driving,
                           rfe_real_t sd_w, rfe_real_t *z, rfe_real_t *r)
{
    *r = sd_w * sd_w;
    if (w->n_free > 0u) {
        *z = w->sum / (rfe_real_t)w->n_free;
        *r = *r / (rfe_real_t)w->n_free;
        return 1;
    }
    if ((w->n_ok > 0u) && (braking != 0) && (w->hi > vx_pred)) {
        *z = w->hi; /* a braked wheel turns slower than it rolls: a lower bound */
        return 1;
    }
    if ((w->n_ok > 0u) && (braking == 0) && (driving != 0) && (w->lo < vx_pred)) {
        *z = w->lo; /* a driven wheel turns faster: an upper bound */
        return 1;
    }
    return 0;
}

rfe_status_t rfe_vel_longitudinal_step(rfe_kf2_t *f, const rfe_velocity_params_t *p,
                                       const rfe_vehicle_t *veh, const rfe_velocity_input_t *in,
                                       rfe_real_t vy_prev, uint32_t *flags)
{
    rfe_kf2_t k;
    rfe_real_t refs[RFE_WHEELS];
    rfe_real_t z = RFE_R(0.0);
    rfe_real_t r = RFE_R(0.0);
    int braking;
    int driving;
    uint32_t driven;
    uint32_t fl = 0u;
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
    driving_state(p, in, a - k.x[1], &braking, &driving, &driven);
    if (braking != 0) {
        fl |= RFE_VEL_FLAG_BRAKING;
    } else if (driving != 0) {
        fl |= RFE_VEL_FLAG_DRIVING;
    } else {
        /* rolling */
    }
    rfe_vel_wheel_refs(veh, in, vy_prev, refs);
    {
        const rfe_real_t vx_pred = k.x[0];
        const rfe_real_t sd_w = p->sd_wheel + (p->sd_wheel_rel * RFE_FABS(vx_pred));
        const rfe_real_t gate = p->k_gate * RFE_SQRT(k.p00 + (sd_w * sd_w));
        const wheel_vote_t w = wheel_votes(refs, vx_pred, gate, braking, driving, driven);
        if (wheel_reference(&w, vx_pred, braking, driving, sd_w, &z, &r) != 0) {
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
