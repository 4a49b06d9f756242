/**
 * @file params_flt.c
 * @brief Default parameters (MODEL.md §2, DATA.md) and their validation.
 */
#include "rfe/params.h"

#include "internal.h"

rfe_status_t RFE_FN(rfe_params_default)(rfe_params_t *p)
{
    return RFE_FN(rfe_params_paper)(p);
}

rfe_status_t RFE_FN(rfe_params_paper)(rfe_params_t *p)
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

static int tyre_ok(const rfe_tyre_params_t *t)
{
    /* alpha_max < 1.5 rad keeps tan(alpha) bounded (MODEL.md §4: |alpha| < 1.4). */
    return ((t->mode == RFE_TYRE_PAPER) || (t->mode == RFE_TYRE_ABSOLUTE)) && is_pos(t->Cx_n) &&
           is_pos(t->Cy_n) && is_pos(t->cx) && is_pos(t->cy) && is_nonneg(t->eps) &&
           is_pos(t->v_min) && is_pos(t->alpha_max) && (t->alpha_max < RFE_R(1.5));
}

static int filter_ok(const rfe_filter_params_t *f)
{
    return ((f->kind == RFE_FILTER_SCKF) || (f->kind == RFE_FILTER_CKF)) && is_pos(f->sd0) &&
           is_pos(f->q_mu) && is_pos(f->r_ax) && is_pos(f->r_ay) && is_pos(f->r_yaw_acc) &&
           is_nonneg(f->mu_min) && is_pos(f->mu_max) && (f->mu_min < f->mu_max) &&
           rfe_is_finite(f->mu0) && (f->mu0 >= f->mu_min) && (f->mu0 <= f->mu_max) &&
           is_nonneg(f->v_est_min);
}

rfe_status_t RFE_FN(rfe_params_validate)(const rfe_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    if (!vehicle_ok(&p->vehicle) || !tyre_ok(&p->tyre) || !filter_ok(&p->filter)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}
