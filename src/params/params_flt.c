/**
 * @file params_flt.c
 * @brief The two parameter presets (MODEL.md §2, docs/ESTIMATOR.md) and their validation.
 */
#include "rfe/params.h"

#include "numerics/internal.h"

/* The largest bound margin valid_bound_k [sd] (docs/ESTIMATOR.md step 9): 10 sd is far past any
 * Gaussian tail a valid claim needs, and with sd <= 2 (Q30) keeps k sd within 2^55 in Q54. */
#define VALID_BOUND_K_MAX 10.0

rfe_status_t rfe_params_default(rfe_params_t *p)
{
    /* docs/ESTIMATOR.md, "default preset" column: the paper's vehicle, tyre constants and
     * measurement noise, plus every addition switched on. */
    const rfe_status_t st = rfe_params_paper(p);
    if (st != RFE_OK) {
        return st;
    }
    p->tyre.mode = RFE_TYRE_MAGIC;
    p->filter.structure = RFE_STRUCT_SIDES;
    p->filter.sd0 = RFE_R(0.1);
    p->filter.sd0_common = RFE_R(0.3);
    p->filter.q_mu = RFE_R(0.002);
    p->filter.q_common = RFE_R(0.006);
    p->filter.tau_v = RFE_R(0.3);
    p->filter.sd_in_delta = RFE_R(0.001);
    p->filter.sd_in_vx = RFE_R(0.01);
    p->filter.sd_in_vy = RFE_R(0.01);
    p->filter.sd_in_yaw_rate = RFE_R(0.005);
    p->filter.sd_in_omega = RFE_R(0.05);
    p->filter.r_model_rel = RFE_R(0.05);
    p->filter.info_min = RFE_R(25.0);
    p->filter.sd_max = RFE_R(0.32);
    p->filter.sd_floor_rel = RFE_R(0.15);
    p->filter.sd_valid = RFE_R(0.15);
    p->filter.rear_hold_k = RFE_R(2.0); /* docs/ESTIMATOR.md step 9: the rear wheels' hold */
    p->filter.jump_hold_k = RFE_R(2.0); /* docs/ESTIMATOR.md step 9: the jump hold */
    p->filter.jump_hold_len = RFE_R(1.5);
    p->filter.stale_omega = RFE_R(0.25); /* docs/ESTIMATOR.md step 9: 5 sd_in_omega (MONITOR.md §8) */
    p->filter.yaw_check = RFE_R(0.1);    /* docs/ESTIMATOR.md step 0b (MONITOR.md §8) */
    p->filter.valid_bound_k = RFE_R(3.0); /* docs/ESTIMATOR.md step 9: the bound margin (MONITOR.md §10) */
    p->monitor.enable = RFE_R(1.0); /* docs/MONITOR.md: the model-validity monitor acts */
    return RFE_OK;
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_params_paper(rfe_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    /* MODEL.md §2: the paper's Table 1 plus its stated assumptions. */
    p->vehicle.m = RFE_R(1830.0);
    p->vehicle.Lf = RFE_R(1.40);
    p->vehicle.Lr = RFE_R(1.65);
    p->vehicle.Bf = RFE_R(1.60);
    p->vehicle.Br = RFE_R(1.60);
    p->vehicle.R = RFE_R(0.325);
    p->vehicle.J = RFE_R(3234.0);
    p->vehicle.hg = RFE_R(0.54);
    p->vehicle.g = RFE_R(9.81);

    p->tyre.mode = RFE_TYRE_PAPER;
    p->tyre.Cx_n = RFE_R(20.0);
    p->tyre.Cy_n = RFE_R(15.0);
    p->tyre.cx = RFE_R(20.0);
    p->tyre.cy = RFE_R(15.0);
    p->tyre.eps = RFE_R(0.015);
    p->tyre.v_min = RFE_R(0.5);
    p->tyre.alpha_max = RFE_R(1.4);
    /* Pacejka's typical passenger-car shape factors, neutral curvature (tyre data, used by
     * the magic mode only; docs/ESTIMATOR.md). */
    p->tyre.shape_Cx = RFE_R(1.65);
    p->tyre.shape_Ex = RFE_R(0.0);
    p->tyre.shape_Cy = RFE_R(1.3);
    p->tyre.shape_Ey = RFE_R(0.0);

    /* The paper configuration of the filter (MODEL.md §6). */
    p->filter.kind = RFE_FILTER_SCKF;
    p->filter.mu0 = RFE_R(0.5);
    p->filter.sd0 = RFE_R(0.3);
    p->filter.q_mu = RFE_R(0.003);
    p->filter.r_ax = RFE_R(0.05);
    p->filter.r_ay = RFE_R(0.05);
    p->filter.r_yaw_acc = RFE_R(0.05);
    p->filter.mu_min = RFE_R(0.05);
    p->filter.mu_max = RFE_R(1.2);
    p->filter.v_est_min = RFE_R(3.0);

    /* Every docs/ESTIMATOR.md addition off: the filter is then exactly MODEL.md §6. */
    p->filter.structure = RFE_STRUCT_WHEELS;
    p->filter.sd0_common = RFE_R(0.0);
    p->filter.q_common = RFE_R(0.0);
    p->filter.dt = RFE_R(0.01);
    p->filter.tau_v = RFE_R(0.0);
    p->filter.sd_in_delta = RFE_R(0.0);
    p->filter.sd_in_vx = RFE_R(0.0);
    p->filter.sd_in_vy = RFE_R(0.0);
    p->filter.sd_in_yaw_rate = RFE_R(0.0);
    p->filter.sd_in_omega = RFE_R(0.0);
    p->filter.r_model_rel = RFE_R(0.0);
    p->filter.info_min = RFE_R(0.0);
    p->filter.sd_max = RFE_R(0.0);
    p->filter.sd_floor_rel = RFE_R(0.0);
    p->filter.sd_valid = RFE_R(0.0);
    p->filter.rear_hold_k = RFE_R(0.0);
    p->filter.jump_hold_k = RFE_R(0.0);
    p->filter.jump_hold_len = RFE_R(0.0);
    p->filter.stale_omega = RFE_R(0.0);
    p->filter.yaw_check = RFE_R(0.0);
    p->filter.valid_bound_k = RFE_R(0.0);

    /* docs/MONITOR.md §2 "Parameters": stated probabilities and time scales, not tuned;
     * off in the paper preset (MODEL.md §6 has no monitor), on in the default preset. */
    p->monitor.enable = RFE_R(0.0);
    p->monitor.tau_nis = RFE_R(0.5);
    p->monitor.tau_mean = RFE_R(0.5);
    p->monitor.p_fire = RFE_R(1e-3);
    p->monitor.p_clear = RFE_R(0.1);
    p->monitor.hold = RFE_R(0.5);
    p->monitor.warmup = RFE_R(1.0);
    p->monitor.inflate = RFE_R(1.0);
    return RFE_OK;
}

/* Finite and > 0. */
static int is_pos(rfe_real_t x) { return (rfe_is_finite(x) != 0) && (x > RFE_R(0.0)); }
/* Finite and >= 0. */
static int is_nonneg(rfe_real_t x) { return (rfe_is_finite(x) != 0) && (x >= RFE_R(0.0)); }

static int vehicle_ok(const rfe_vehicle_t *v)
{
    return is_pos(v->m) && is_pos(v->Lf) && is_pos(v->Lr) && is_pos(v->Bf) && is_pos(v->Br) &&
           is_pos(v->R) && is_pos(v->J) && is_nonneg(v->hg) && is_pos(v->g);
}

/* A Magic Formula shape: 1 < C < 2 (a peak, and a positive force beyond it), -4 <= E < 1
 * (the curve rises monotonically to its peak; docs/ESTIMATOR.md). */
static int shape_ok(rfe_real_t C, rfe_real_t E)
{
    return (rfe_is_finite(C) != 0) && (C > RFE_R(1.0)) && (C < RFE_R(2.0)) &&
           (rfe_is_finite(E) != 0) && (E >= RFE_R(-4.0)) && (E < RFE_R(1.0));
}

static int tyre_ok(const rfe_tyre_params_t *t)
{
    /* alpha_max < 1.5 rad keeps tan(alpha) bounded (MODEL.md §4: |alpha| < 1.4). */
    return ((t->mode == RFE_TYRE_PAPER) || (t->mode == RFE_TYRE_ABSOLUTE) ||
            (t->mode == RFE_TYRE_MAGIC)) &&
           is_pos(t->Cx_n) && is_pos(t->Cy_n) && is_pos(t->cx) && is_pos(t->cy) &&
           is_nonneg(t->eps) && is_pos(t->v_min) && is_pos(t->alpha_max) &&
           (t->alpha_max < RFE_R(1.5)) && shape_ok(t->shape_Cx, t->shape_Ex) &&
           shape_ok(t->shape_Cy, t->shape_Ey);
}

/* Enums in range; sd0, q_mu and the measurement noise positive. */
static int filter_kind_noise_ok(const rfe_filter_params_t *f)
{
    return ((f->kind == RFE_FILTER_SCKF) || (f->kind == RFE_FILTER_CKF)) &&
           ((f->structure == RFE_STRUCT_WHEELS) || (f->structure == RFE_STRUCT_SIDES)) &&
           is_pos(f->sd0) && is_pos(f->q_mu) && is_pos(f->r_ax) && is_pos(f->r_ay) &&
           is_pos(f->r_yaw_acc);
}

/* 0 <= mu_min < mu_max, mu0 within them, v_est_min >= 0. */
static int filter_bounds_ok(const rfe_filter_params_t *f)
{
    return is_nonneg(f->mu_min) && is_pos(f->mu_max) && (f->mu_min < f->mu_max) &&
           rfe_is_finite(f->mu0) && (f->mu0 >= f->mu_min) && (f->mu0 <= f->mu_max) &&
           is_nonneg(f->v_est_min);
}

static int filter_ok(const rfe_filter_params_t *f)
{
    return filter_kind_noise_ok(f) && filter_bounds_ok(f);
}

/* The docs/ESTIMATOR.md additions: each finite and >= 0 (0 = off), dt > 0. sd_max is
 * "0 = off, else a positive bound", which is the same test. */
/* Step 9's holds (docs/ESTIMATOR.md): thresholds and the jump hold's length, finite and >= 0;
 * the stale-wheel-speed rule's move (at most RFE_LIMIT_OMEGA) and the yaw-rate check's threshold
 * (at most RFE_LIMIT_YAW_RATE), finite and >= 0: the fixed-point formats hold them; the bound
 * margin valid_bound_k, finite, in [0, VALID_BOUND_K_MAX]. */
static int holds_ok(const rfe_filter_params_t *f)
{
    return is_nonneg(f->rear_hold_k) && is_nonneg(f->jump_hold_k) && is_nonneg(f->jump_hold_len) &&
           is_nonneg(f->stale_omega) && (f->stale_omega <= RFE_R(RFE_LIMIT_OMEGA)) &&
           is_nonneg(f->yaw_check) && (f->yaw_check <= RFE_R(RFE_LIMIT_YAW_RATE)) &&
           is_nonneg(f->valid_bound_k) && (f->valid_bound_k <= RFE_R(VALID_BOUND_K_MAX));
}

static int additions_ok(const rfe_filter_params_t *f)
{
    return is_nonneg(f->sd0_common) && is_nonneg(f->q_common) && is_pos(f->dt) &&
           is_nonneg(f->tau_v) && is_nonneg(f->sd_in_delta) && is_nonneg(f->sd_in_vx) &&
           is_nonneg(f->sd_in_vy) && is_nonneg(f->sd_in_yaw_rate) && is_nonneg(f->sd_in_omega) &&
           is_nonneg(f->r_model_rel) && is_nonneg(f->info_min) && is_nonneg(f->sd_max) &&
           is_nonneg(f->sd_floor_rel) && is_nonneg(f->sd_valid) && holds_ok(f);
}

/* The CKF is the paper's baseline: it runs only what MODEL.md §6 has (four independent mu,
 * diagonal prior and noise, no input filter, no errors in variables, no gate, no bounds).
 * Any tyre, any dt (unused), any sd_valid (an output rule). */
static int ckf_subset_ok(const rfe_filter_params_t *f)
{
    const rfe_real_t zero = RFE_R(0.0);
    return (f->kind != RFE_FILTER_CKF) ||
           ((f->structure == RFE_STRUCT_WHEELS) && (f->sd0_common == zero) &&
            (f->q_common == zero) && (f->tau_v == zero) && (f->sd_in_delta == zero) &&
            (f->sd_in_vx == zero) && (f->sd_in_vy == zero) && (f->sd_in_yaw_rate == zero) &&
            (f->sd_in_omega == zero) && (f->r_model_rel == zero) && (f->info_min == zero) &&
            (f->sd_max == zero) && (f->sd_floor_rel == zero));
}

/* 0 or 1. */
static int is_flag(rfe_real_t x) { return (x == RFE_R(0.0)) || (x == RFE_R(1.0)); }

/* A duration t >= 0 shorter than 2^31 periods dt (a step count fits uint32_t). */
static int is_steps(rfe_real_t t, rfe_real_t dt)
{
    return is_nonneg(t) && ((t / dt) < RFE_R(2147483648.0));
}

rfe_status_t rfe_monitor_params_validate(const rfe_monitor_params_t *mp, rfe_real_t dt)
{
    if (mp == NULL) {
        return RFE_ERR_NULL;
    }
    if (!is_pos(dt) || !is_flag(mp->enable) || !is_flag(mp->inflate) || !is_pos(mp->tau_nis) ||
        !is_pos(mp->tau_mean) || !(mp->p_fire > RFE_R(0.0)) || !(mp->p_fire < mp->p_clear) ||
        !(mp->p_clear < RFE_R(1.0)) || !is_steps(mp->hold, dt) || !is_steps(mp->warmup, dt)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}

rfe_status_t rfe_params_validate(const rfe_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    if (!vehicle_ok(&p->vehicle) || !tyre_ok(&p->tyre) || !filter_ok(&p->filter) ||
        !additions_ok(&p->filter) || !ckf_subset_ok(&p->filter)) {
        return RFE_ERR_PARAM;
    }
    /* the monitor reads the SCKF's innovations: the CKF baseline runs without it */
    if ((p->filter.kind == RFE_FILTER_CKF) && (p->monitor.enable != RFE_R(0.0))) {
        return RFE_ERR_PARAM;
    }
    return rfe_monitor_params_validate(&p->monitor, p->filter.dt);
}

rfe_status_t rfe_params_set_lateral_tyre(rfe_params_t *p, rfe_real_t cy, rfe_real_t shape_Cy,
                                         rfe_real_t shape_Ey, rfe_real_t r_model_rel)
{
    rfe_status_t st = RFE_ERR_NULL;
    if (p != NULL) {
        const rfe_tyre_params_t tyre_was = p->tyre;
        const rfe_real_t r_was = p->filter.r_model_rel;
        p->tyre.cy = cy;
        p->tyre.shape_Cy = shape_Cy;
        p->tyre.shape_Ey = shape_Ey;
        p->filter.r_model_rel = r_model_rel;
        st = rfe_params_validate(p);
        if (st != RFE_OK) {
            p->tyre = tyre_was; /* an invalid result leaves p as it was */
            p->filter.r_model_rel = r_was;
        }
    }
    return st;
}

rfe_status_t rfe_params_set_mass(rfe_params_t *p, rfe_real_t m)
{
    rfe_status_t st = RFE_ERR_NULL;
    if (p != NULL) {
        const rfe_real_t m_was = p->vehicle.m;
        p->vehicle.m = m;
        st = rfe_params_validate(p);
        if (st != RFE_OK) {
            p->vehicle.m = m_was; /* an invalid result leaves p as it was */
        }
    }
    return st;
}
