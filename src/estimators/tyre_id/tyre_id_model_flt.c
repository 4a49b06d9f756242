/**
 * @file tyre_id_model_flt.c
 * @brief The tyre identifier's model (docs/TYRE_ID.md §3-4) and likelihood (§5.1), one
 *        particle at a time, each operation in the page's order.
 */
#include "estimators/tyre_id/tyre_id_internal.h"
#include "numerics/internal.h"

/* The slip angle clipped to [-a_max, a_max]; a NaN stays NaN (as the reference's
 * minimum/maximum), so a diverged particle gets no finite likelihood. */
static rfe_real_t clip_slip(rfe_real_t a, rfe_real_t a_max)
{
    rfe_real_t y = a;
    if (a < -a_max) {
        y = -a_max;
    } else if (a > a_max) {
        y = a_max;
    } else {
        /* inside, or NaN */
    }
    return y;
}

/* §3.1 t = tan(alpha) of the front and rear axle at (vy, r) and inputs u. */
static void slips(const rfe_tyre_id_t *tid, rfe_real_t vy, rfe_real_t r,
                  const rfe_tid_input_t *u, rfe_real_t *t_f, rfe_real_t *t_r)
{
    const rfe_real_t a_f = u->delta - RFE_ATAN2(vy + (tid->c.Lf * r), u->vx);
    const rfe_real_t a_r = -RFE_ATAN2(vy - (tid->c.Lr * r), u->vx);
    *t_f = RFE_TAN(clip_slip(a_f, tid->c.alpha_max));
    *t_r = RFE_TAN(clip_slip(a_r, tid->c.alpha_max));
}

/* §4 B = K / (C D) of the axle whose parameters start at th. */
static rfe_real_t b_of(const rfe_real_t *th)
{
    return th[2] / (th[1] * th[0]);
}

/* §3.2 F = D sin(C atan(x - E (x - atan x))), x = B t, for the axle's (D, C, K, E) at th;
 * with a non-NULL slope also dF/dalpha =
 * ((((D C) cos(C phi)) / (1 + psi psi)) ((1 - E) + E / (1 + x x))) (B (1 + t t)). */
static rfe_real_t mf(const rfe_real_t *th, rfe_real_t t, rfe_real_t *slope)
{
    const rfe_real_t d = th[0];
    const rfe_real_t c = th[1];
    const rfe_real_t e = th[3];
    const rfe_real_t b = b_of(th);
    const rfe_real_t x = b * t;
    const rfe_real_t psi = x - (e * (x - RFE_ATAN(x)));
    const rfe_real_t cphi = c * RFE_ATAN(psi);
    if (slope != NULL) {
        const rfe_real_t dpsi = (RFE_R(1.0) - e) + (e / (RFE_R(1.0) + (x * x)));
        *slope = ((((d * c) * RFE_COS(cphi)) / (RFE_R(1.0) + (psi * psi))) * dpsi) *
                 (b * (RFE_R(1.0) + (t * t)));
    }
    return d * RFE_SIN(cphi);
}

/* §3.5 the factor of one axle's pure-slip force at ax: lam sqrt(1 - min(rho rho, u_max)),
 * rho = (kxm ax) / (lam D), with lam = Fz / Fz0 of that axle (§3.4) and D its peak at the
 * static load; a NaN rho stays NaN (as the reference's minimum). */
static rfe_real_t axle_scale(rfe_real_t lam, rfe_real_t kxm, rfe_real_t ax, rfe_real_t d,
                             rfe_real_t u_max)
{
    const rfe_real_t rho = (kxm * ax) / (lam * d);
    rfe_real_t u = rho * rho;
    if (u > u_max) {
        u = u_max;
    }
    return lam * RFE_SQRT(RFE_R(1.0) - u);
}

/* §3.5 the factors (s_f, s_r) of the axle forces of parameters th at ax: 1 and 1 without the
 * ellipse (the caller then leaves the forces as they are, so the lateral-only model stays bit
 * for bit). Below the dead band ell_ax_min ax is taken as 0: lam = Fz0 / Fz0 = 1 and rho = 0,
 * so each factor is exactly 1. Returns 1 when the ellipse is on. */
static int scales(const rfe_tyre_id_t *tid, const rfe_real_t *th, rfe_real_t ax,
                  rfe_real_t *s_f, rfe_real_t *s_r)
{
    const rfe_tid_consts_t *c = &tid->c;
    int on = 0;
    *s_f = RFE_R(1.0);
    *s_r = RFE_R(1.0);
    if (tid->p.ellipse != RFE_R(0.0)) {
        const rfe_real_t a = (RFE_FABS(ax) < tid->p.ell_ax_min) ? RFE_R(0.0) : ax;
        /* lam_f = (Fz0_f - G a) / Fz0_f, lam_r = (Fz0_r + G a) / Fz0_r */
        const rfe_real_t lam_f = (c->fz0[0] - (c->gx * a)) / c->fz0[0];
        const rfe_real_t lam_r = (c->fz0[1] + (c->gx * a)) / c->fz0[1];
        *s_f = axle_scale(lam_f, c->kxm[0], a, th[0], c->u_max);
        *s_r = axle_scale(lam_r, c->kxm[1], a, th[RFE_TID_D_R - RFE_TID_STATES], c->u_max);
        on = 1;
    }
    return on;
}

void rfe_tid_mu_loads(const rfe_tyre_id_t *tid, rfe_real_t ax, rfe_real_t fz[2])
{
    if (tid->p.ellipse != RFE_R(0.0)) {
        fz[0] = tid->c.fz0[0];
        fz[1] = tid->c.fz0[1];
    } else {
        fz[0] = tid->c.fz0[0] - (tid->c.gx * ax);
        fz[1] = tid->c.fz0[1] + (tid->c.gx * ax);
    }
}

void rfe_tid_forces(const rfe_tyre_id_t *tid, const rfe_real_t x[RFE_TID_DIM],
                    const rfe_tid_input_t *u, rfe_real_t *fy_f, rfe_real_t *fy_r)
{
    rfe_real_t t_f;
    rfe_real_t t_r;
    rfe_real_t s_f;
    rfe_real_t s_r;
    slips(tid, x[RFE_TID_VY], x[RFE_TID_R], u, &t_f, &t_r);
    *fy_f = mf(&x[RFE_TID_D_F], t_f, NULL);
    *fy_r = mf(&x[RFE_TID_D_R], t_r, NULL);
    if (scales(tid, &x[RFE_TID_D_F], u->ax, &s_f, &s_r) != 0) {
        *fy_f = *fy_f * s_f;
        *fy_r = *fy_r * s_r;
    }
}

/* §3.3 (vy', r') = (ay - r vx, (Lf F_c - Lr F_r) / J), ay = (F_c + F_r) / m, F_c = F_f cos d. */
static void rhs(const rfe_tyre_id_t *tid, const rfe_real_t x[RFE_TID_DIM], rfe_real_t vy,
                rfe_real_t r, const rfe_tid_input_t *u, rfe_real_t d[RFE_TID_STATES])
{
    rfe_real_t t_f;
    rfe_real_t t_r;
    rfe_real_t ff;
    rfe_real_t fyc;
    rfe_real_t fr;
    rfe_real_t s_f;
    rfe_real_t s_r;
    slips(tid, vy, r, u, &t_f, &t_r);
    ff = mf(&x[RFE_TID_D_F], t_f, NULL);
    fr = mf(&x[RFE_TID_D_R], t_r, NULL);
    if (scales(tid, &x[RFE_TID_D_F], u->ax, &s_f, &s_r) != 0) {
        ff = ff * s_f;
        fr = fr * s_r;
    }
    fyc = ff * u->cd;
    d[0] = ((fyc + fr) / tid->c.m) - (r * u->vx);
    d[1] = ((tid->c.Lf * fyc) - (tid->c.Lr * fr)) / tid->c.J;
}

rfe_tid_input_t rfe_tid_mean_input(const rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp)
{
    const rfe_real_t d_bar = RFE_R(0.5) * (tid->prev_delta + smp->delta);
    rfe_tid_input_t ub;
    ub.delta = d_bar;
    ub.cd = RFE_COS(d_bar);
    ub.sd = RFE_R(0.0); /* not used by the dynamics */
    ub.vx = RFE_R(0.5) * (tid->prev_vx + smp->vx);
    ub.ax = RFE_R(0.5) * (tid->prev_ax + smp->ax);
    return ub;
}

void rfe_tid_rk4(const rfe_tyre_id_t *tid, const rfe_real_t x[RFE_TID_DIM],
                 const rfe_tid_input_t *u, rfe_real_t h, rfe_real_t out[RFE_TID_STATES])
{
    const rfe_real_t hs = h / (rfe_real_t)tid->p.substeps;
    const rfe_real_t h2 = RFE_R(0.5) * hs;
    const rfe_real_t h6 = hs / RFE_R(6.0);
    rfe_real_t a = x[RFE_TID_VY];
    rfe_real_t b = x[RFE_TID_R];
    uint32_t n;
    for (n = 0u; n < tid->p.substeps; ++n) {
        rfe_real_t k1[RFE_TID_STATES];
        rfe_real_t k2[RFE_TID_STATES];
        rfe_real_t k3[RFE_TID_STATES];
        rfe_real_t k4[RFE_TID_STATES];
        /* k1 = f(x), k2 = f(x + h2 k1), k3 = f(x + h2 k2), k4 = f(x + hs k3) */
        rhs(tid, x, a, b, u, k1);
        rhs(tid, x, a + (h2 * k1[0]), b + (h2 * k1[1]), u, k2);
        rhs(tid, x, a + (h2 * k2[0]), b + (h2 * k2[1]), u, k3);
        rhs(tid, x, a + (hs * k3[0]), b + (hs * k3[1]), u, k4);
        /* x <- x + h6 (((k1 + 2 k2) + 2 k3) + k4) */
        a = a + (h6 * (((k1[0] + (RFE_R(2.0) * k2[0])) + (RFE_R(2.0) * k3[0])) + k4[0]));
        b = b + (h6 * (((k1[1] + (RFE_R(2.0) * k2[1])) + (RFE_R(2.0) * k3[1])) + k4[1]));
    }
    out[0] = a;
    out[1] = b;
}

void rfe_tid_ay(const rfe_tyre_id_t *tid, rfe_real_t vy, rfe_real_t r, const rfe_real_t *th,
                const rfe_tid_input_t *u, rfe_real_t *ay_p, rfe_real_t *g, rfe_real_t *fy)
{
    rfe_real_t t_f;
    rfe_real_t t_r;
    rfe_real_t slope = RFE_R(0.0);
    rfe_real_t f;
    rfe_real_t fr;
    rfe_real_t s_f;
    rfe_real_t s_r;
    slips(tid, vy, r, u, &t_f, &t_r);
    f = mf(&th[0], t_f, (g != NULL) ? &slope : NULL);
    fr = mf(&th[RFE_TID_D_R - RFE_TID_STATES], t_r, NULL);
    if (scales(tid, th, u->ax, &s_f, &s_r) != 0) {
        f = f * s_f;
        slope = slope * s_f;
        fr = fr * s_r;
    }
    /* ay_p = ((F_f c) + F_r) / m,  g = d ay_p / d delta = ((dF_f/dalpha c) - (F_f s)) / m */
    *ay_p = ((f * u->cd) + fr) / tid->c.m;
    if (g != NULL) {
        *g = ((slope * u->cd) - (f * u->sd)) / tid->c.m;
    }
    /* the axle forces, the values rfe_tid_forces gives at the same states and inputs (the
     * same operations: mf's force does not depend on whether it also gives the slope) */
    if (fy != NULL) {
        fy[0] = f;
        fy[1] = fr;
    }
}

rfe_real_t rfe_tid_loglik(const rfe_tyre_id_t *tid, rfe_real_t vy, rfe_real_t r,
                          const rfe_real_t *th, const rfe_tid_input_t *u, rfe_real_t yaw_rate,
                          rfe_real_t ay, rfe_real_t *fy)
{
    const rfe_tyre_id_params_t *p = &tid->p;
    rfe_real_t ay_p;
    rfe_real_t g;
    rfe_real_t gs;
    rfe_real_t v;
    rfe_real_t e1;
    rfe_real_t e2;
    rfe_real_t ll;
    rfe_tid_ay(tid, vy, r, th, u, &ay_p, &g, fy);
    gs = g * tid->sd_delta;
    v = (p->sd_ay * p->sd_ay) + (gs * gs);
    e1 = (yaw_rate - r) / p->sd_r;
    e2 = ay - ay_p;
    /* l = -0.5 (e1 e1 + (e2 e2) / v) - 0.5 log v */
    ll = (RFE_R(-0.5) * ((e1 * e1) + ((e2 * e2) / v))) - (RFE_R(0.5) * RFE_LOG(v));
    /* a diverged particle weighs 0: a non-finite l, or an infinite vy (its slip angles and
     * forces stay finite, so l would not show it) */
    return ((rfe_is_finite(ll) != 0) && (rfe_is_finite(vy) != 0)) ? ll : -(rfe_real_t)INFINITY;
}
