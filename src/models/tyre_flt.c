/**
 * @file tyre_flt.c
 * @brief Wheel kinematics, loads, slips (MODEL.md §3), the Dugoff tyre (§4) and the
 *        load-scaled Magic Formula tyre (docs/ESTIMATOR.md).
 */
#include "rfe/component/tyre.h"

#include "numerics/internal.h"
#include "models/vehicle.h"
#include "models/tyre_internal.h"

/* Quasi-static loads (MODEL.md §3), clamped at >= 0; ay > 0 unloads the left wheels. */
static void vertical_loads(const rfe_vehicle_t *veh, rfe_real_t ax, rfe_real_t ay,
                           rfe_real_t fz[RFE_WHEELS])
{
    const rfe_real_t La = veh->Lf + veh->Lr;
    const rfe_real_t mg = veh->m * veh->g;
    const rfe_real_t front_static = mg * veh->Lr / (RFE_R(2.0) * La);
    const rfe_real_t rear_static = mg * veh->Lf / (RFE_R(2.0) * La);
    const rfe_real_t pitch = veh->m * ax * veh->hg / (RFE_R(2.0) * La);
    const rfe_real_t roll_f = veh->m * ay * veh->hg * veh->Lr / (La * veh->Bf);
    const rfe_real_t roll_r = veh->m * ay * veh->hg * veh->Lf / (La * veh->Br);

    fz[RFE_FL] = rfe_max(front_static - pitch - roll_f, RFE_R(0.0));
    fz[RFE_FR] = rfe_max(front_static - pitch + roll_f, RFE_R(0.0));
    fz[RFE_RL] = rfe_max(rear_static + pitch - roll_r, RFE_R(0.0));
    fz[RFE_RR] = rfe_max(rear_static + pitch + roll_r, RFE_R(0.0));
}

/* kappa = (omega R - v_wx) / max(|omega R|, |v_wx|, v_min), clipped to [-1, 1]. */
static inline rfe_real_t wheel_kappa(const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
                                     rfe_real_t omega, rfe_real_t vwx)
{
    const rfe_real_t vr = omega * veh->R;
    const rfe_real_t den = rfe_max(rfe_max(RFE_FABS(vr), RFE_FABS(vwx)), tp->v_min);
    return rfe_clamp((vr - vwx) / den, RFE_R(-1.0), RFE_R(1.0));
}

/* Wheel i at position (px, py) of sample u, c, s = cos, sin of u->delta: vwx, alpha, kappa. */
static inline void wheel_kin(const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
                             const rfe_sample_t *u, rfe_real_t c, rfe_real_t s, size_t i,
                             rfe_real_t px, rfe_real_t py, rfe_real_t *vwx_out,
                             rfe_real_t *alpha_out, rfe_real_t *kappa_out)
{
    /* Only the front wheels steer. */
    const rfe_real_t ci = (i < (size_t)RFE_RL) ? c : RFE_R(1.0);
    const rfe_real_t si = (i < (size_t)RFE_RL) ? s : RFE_R(0.0);
    /* v_i = (vx - r y_i, vy + r x_i), rotated into wheel axes. */
    const rfe_real_t vbx = u->vx - (u->yaw_rate * py);
    const rfe_real_t vby = u->vy + (u->yaw_rate * px);
    const rfe_real_t vwx = (vbx * ci) + (vby * si);
    const rfe_real_t vwy = (-vbx * si) + (vby * ci);
    /* alpha = -atan2(v_wy, |v_wx|), bounded so tan(alpha) stays finite. */
    const rfe_real_t alpha = -RFE_ATAN2(vwy, RFE_FABS(vwx));

    *vwx_out = vwx;
    *alpha_out = rfe_clamp(alpha, -tp->alpha_max, tp->alpha_max);
    *kappa_out = wheel_kappa(veh, tp, u->omega[i], vwx);
}

rfe_status_t rfe_tyre_kinematics_cs(const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
                                    const rfe_sample_t *u, rfe_wheel_kin_t *kin,
                                    rfe_real_t *cos_delta, rfe_real_t *sin_delta)
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    rfe_real_t c;
    rfe_real_t s;
    size_t i;

    if ((veh == NULL) || (tp == NULL) || (u == NULL) || (kin == NULL)) {
        return RFE_ERR_NULL;
    }
    {
        const rfe_real_t v[6] = {u->delta, u->vx, u->vy, u->yaw_rate, u->ax, u->ay};
        if (!rfe_all_finite(v, 6u) || !rfe_all_finite(u->omega, RFE_WHEELS)) {
            return RFE_ERR_NONFINITE;
        }
    }
    /* nothing fails below the checks: *kin is written only on RFE_OK */
    rfe_wheel_positions(veh, px, py);
    c = RFE_COS(u->delta);
    s = RFE_SIN(u->delta);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        wheel_kin(veh, tp, u, c, s, i, px[i], py[i], &kin->vwx[i], &kin->alpha[i],
                  &kin->kappa[i]);
    }
    vertical_loads(veh, u->ax, u->ay, kin->fz);
    *cos_delta = c;
    *sin_delta = s;
    return RFE_OK;
}

rfe_status_t rfe_tyre_kinematics(const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
                                 const rfe_sample_t *u, rfe_wheel_kin_t *kin)
{
    rfe_real_t c;
    rfe_real_t s;
    return rfe_tyre_kinematics_cs(veh, tp, u, kin, &c, &s);
}

/* Shared Dugoff core (MODEL.md §4). Returns g = f(L)/(1-|kappa|) computed without dividing
 * two small numbers, for L = mu_scale (1-|kappa|) E / (2 S):
 *   S = 0        -> f = 1 and kappa = 0, so g = 1 (forces are 0 anyway);
 *   L < 1        -> g = mu_scale E (2 - L) / (2 S)   (finite as |kappa| -> 1);
 *   L >= 1       -> g = 1 / (1 - |kappa|)            (then 1 - |kappa| >= 2S/(mu_scale E) > 0).
 * mu_scale = 1 in paper mode, mu in absolute mode. Split in two: dugoff_terms computes the
 * terms that do not depend on mu_scale (kept in pre->k, tan_a, s, e, omk), dugoff_g the rest;
 * together the same operations in the same order as one evaluation. */
static void dugoff_terms(rfe_real_t kappa, rfe_real_t tan_a, rfe_real_t Cx, rfe_real_t Cy,
                       rfe_real_t eps, rfe_real_t vwx, rfe_dugoff_pre_t *pre)
{
    const rfe_real_t ak = RFE_FABS(kappa);
    const rfe_real_t S =
        RFE_SQRT(((Cx * kappa) * (Cx * kappa)) + ((Cy * tan_a) * (Cy * tan_a)));
    const rfe_real_t slip = RFE_SQRT((kappa * kappa) + (tan_a * tan_a));
    /* E = 1 - eps |v_wx| sqrt(k^2 + tan^2 a), clamped at >= 0 (negative above ~67 m/s). */
    pre->e = rfe_max(RFE_R(1.0) - ((eps * RFE_FABS(vwx)) * slip), RFE_R(0.0));
    pre->k = kappa;
    pre->tan_a = tan_a;
    pre->s = S;
    pre->omk = RFE_R(1.0) - ak;
    pre->ux = RFE_R(0.0);
    pre->uy = RFE_R(0.0);
}

/* Magic mode: the direction cosines of the normalised slip, (cx k, cy tan a) / S (0 at S = 0,
 * where the force is 0). Computed once per sample, so a cubature point divides nothing. */
static void magic_terms(rfe_real_t Cx, rfe_real_t Cy, rfe_dugoff_pre_t *pre)
{
    if (pre->s > RFE_R(0.0)) {
        pre->ux = (Cx * pre->k) / pre->s;
        pre->uy = (Cy * pre->tan_a) / pre->s;
    }
}

/* b = atan(y), y = x - E (x - a), as atan2(n, m C), n = s - E (s - m C a) (*n_out); at E = 0
 * (both directions of the default tyre) n is s exactly (E times a finite value is a signed
 * zero), so b is a, bit for bit, without the second atan2 (as the fixed-point twin). */
static rfe_real_t magic_inner(rfe_real_t s, rfe_real_t mc, rfe_real_t E, rfe_real_t a,
                              rfe_real_t *n_out)
{
    rfe_real_t b = a;
    *n_out = s;
    if (E != RFE_R(0.0)) {
        *n_out = s - (E * (s - (mc * a)));
        b = RFE_ATAN2(*n_out, mc);
    }
    return b;
}

/* G = sin(C atan(x - E (x - atan x))), x = s / (m C), written with atan2 (no division, and
 * atan2(s, 0) = pi/2 as m -> 0): docs/ESTIMATOR.md "The Magic Formula tyre". */
static rfe_real_t magic_shape(rfe_real_t s, rfe_real_t m, rfe_real_t C, rfe_real_t E)
{
    const rfe_real_t mc = m * C;
    rfe_real_t n;
    const rfe_real_t b = magic_inner(s, mc, E, RFE_ATAN2(s, mc), &n);
    return RFE_SIN(C * b);
}

/* Forces at friction mu from the friction-independent terms (ux, uy set by magic_terms). */
static void magic_at_mu(const rfe_tyre_params_t *tp, const rfe_dugoff_pre_t *pre, rfe_real_t fz,
                        rfe_real_t mu, rfe_real_t *fx, rfe_real_t *fy)
{
    /* A cubature point may put mu below 0: evaluate it at mu = 0 (zero force). */
    const rfe_real_t m = rfe_max(mu, RFE_R(0.0));
    const rfe_real_t fm = fz * m;
    *fx = fm * magic_shape(pre->s, m, tp->shape_Cx, tp->shape_Ex) * pre->ux;
    *fy = fm * magic_shape(pre->s, m, tp->shape_Cy, tp->shape_Ey) * pre->uy;
}

static rfe_real_t dugoff_g(const rfe_dugoff_pre_t *pre, rfe_real_t mu_scale)
{
    const rfe_real_t S = pre->s;
    const rfe_real_t E = pre->e;
    rfe_real_t g;

    if (S <= RFE_R(0.0)) {
        g = RFE_R(1.0);
    } else {
        const rfe_real_t L = mu_scale * pre->omk * E / (RFE_R(2.0) * S);
        if (L < RFE_R(1.0)) {
            g = mu_scale * E * (RFE_R(2.0) - L) / (RFE_R(2.0) * S);
        } else {
            g = RFE_R(1.0) / pre->omk;
        }
    }
    return g;
}

/* One evaluation of both parts, written out (the same operations in the same order as
 * dugoff_terms then dugoff_g, without the struct in between: the public single-wheel
 * functions and the paper mode's set-up keep their cost). */
static rfe_real_t dugoff_factor(rfe_real_t kappa, rfe_real_t tan_a, rfe_real_t Cx, rfe_real_t Cy,
                                rfe_real_t eps, rfe_real_t vwx, rfe_real_t mu_scale)
{
    const rfe_real_t ak = RFE_FABS(kappa);
    const rfe_real_t S =
        RFE_SQRT(((Cx * kappa) * (Cx * kappa)) + ((Cy * tan_a) * (Cy * tan_a)));
    const rfe_real_t slip = RFE_SQRT((kappa * kappa) + (tan_a * tan_a));
    const rfe_real_t E = rfe_max(RFE_R(1.0) - ((eps * RFE_FABS(vwx)) * slip), RFE_R(0.0));
    rfe_real_t g;

    if (S <= RFE_R(0.0)) {
        g = RFE_R(1.0);
    } else {
        const rfe_real_t L = mu_scale * (RFE_R(1.0) - ak) * E / (RFE_R(2.0) * S);
        if (L < RFE_R(1.0)) {
            g = mu_scale * E * (RFE_R(2.0) - L) / (RFE_R(2.0) * S);
        } else {
            g = RFE_R(1.0) / (RFE_R(1.0) - ak);
        }
    }
    return g;
}

/* Common argument checks of the single-wheel tyre functions. */
static rfe_status_t check_wheel(const rfe_tyre_params_t *tp, rfe_real_t kappa, rfe_real_t alpha,
                                rfe_real_t fz, rfe_real_t vwx, const rfe_real_t *o1,
                                const rfe_real_t *o2)
{
    if ((tp == NULL) || (o1 == NULL) || (o2 == NULL)) {
        return RFE_ERR_NULL;
    }
    {
        /* one test of the four (rfe_all_finite; issue 16: ~20 calls a pipeline step) */
        const rfe_real_t v[4] = {kappa, alpha, fz, vwx};
        if (!rfe_all_finite(v, 4u)) {
            return RFE_ERR_NONFINITE;
        }
    }
    if (fz < RFE_R(0.0)) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_tyre_dugoff_norm(const rfe_tyre_params_t *tp, rfe_real_t kappa,
                                  rfe_real_t alpha, rfe_real_t fz, rfe_real_t vwx,
                                  rfe_real_t *f0x, rfe_real_t *f0y)
{
    rfe_real_t k;
    rfe_real_t ta;
    rfe_real_t g;
    const rfe_status_t st = check_wheel(tp, kappa, alpha, fz, vwx, f0x, f0y);

    if (st != RFE_OK) {
        return st;
    }
    k = rfe_clamp(kappa, RFE_R(-1.0), RFE_R(1.0));
    ta = RFE_TAN(rfe_clamp(alpha, -tp->alpha_max, tp->alpha_max));
    g = dugoff_factor(k, ta, tp->Cx_n, tp->Cy_n, tp->eps, vwx, RFE_R(1.0));
    /* F0x = Fz Cx_n k f(L)/(1-|k|), F0y = Fz Cy_n tan(a) f(L)/(1-|k|). */
    *f0x = fz * tp->Cx_n * k * g;
    *f0y = fz * tp->Cy_n * ta * g;
    return RFE_OK;
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_tyre_dugoff_abs(const rfe_tyre_params_t *tp, rfe_real_t kappa,
                                 rfe_real_t alpha, rfe_real_t fz, rfe_real_t vwx,
                                 rfe_real_t mu, rfe_real_t *fx, rfe_real_t *fy)
{
    rfe_real_t k;
    rfe_real_t ta;
    rfe_real_t g;
    const rfe_status_t st = check_wheel(tp, kappa, alpha, fz, vwx, fx, fy);

    if (st != RFE_OK) {
        return st;
    }
    if (!rfe_is_finite(mu)) {
        return RFE_ERR_NONFINITE;
    }
    k = rfe_clamp(kappa, RFE_R(-1.0), RFE_R(1.0));
    ta = RFE_TAN(rfe_clamp(alpha, -tp->alpha_max, tp->alpha_max));
    /* A cubature point may put mu below 0: evaluate it at mu = 0 (MODEL.md §4). */
    g = dugoff_factor(k, ta, tp->cx, tp->cy, tp->eps, vwx, rfe_max(mu, RFE_R(0.0)));
    /* Fx = cx Fz k f(L)/(1-|k|), Fy = cy Fz tan(a) f(L)/(1-|k|). */
    *fx = fz * tp->cx * k * g;
    *fy = fz * tp->cy * ta * g;
    return RFE_OK;
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_tyre_magic_abs(const rfe_tyre_params_t *tp, rfe_real_t kappa,
                                rfe_real_t alpha, rfe_real_t fz, rfe_real_t vwx,
                                rfe_real_t mu, rfe_real_t *fx, rfe_real_t *fy)
{
    rfe_dugoff_pre_t pre;
    const rfe_status_t st = check_wheel(tp, kappa, alpha, fz, vwx, fx, fy);

    if (st != RFE_OK) {
        return st;
    }
    if (!rfe_is_finite(mu)) {
        return RFE_ERR_NONFINITE;
    }
    dugoff_terms(rfe_clamp(kappa, RFE_R(-1.0), RFE_R(1.0)),
                 RFE_TAN(rfe_clamp(alpha, -tp->alpha_max, tp->alpha_max)), tp->cx, tp->cy,
                 tp->eps, vwx, &pre);
    magic_terms(tp->cx, tp->cy, &pre);
    magic_at_mu(tp, &pre, fz, mu, fx, fy);
    return RFE_OK;
}

rfe_status_t rfe_tyre_forces_norm(const rfe_tyre_params_t *tp, const rfe_wheel_kin_t *kin,
                                  rfe_real_t f0x[RFE_WHEELS], rfe_real_t f0y[RFE_WHEELS])
{
    rfe_real_t fx[RFE_WHEELS];
    rfe_real_t fy[RFE_WHEELS];
    size_t i;

    if ((kin == NULL) || (f0x == NULL) || (f0y == NULL)) {
        return RFE_ERR_NULL;
    }
    /* Compute all four first so an error leaves the outputs untouched. */
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        const rfe_status_t st = rfe_tyre_dugoff_norm(tp, kin->kappa[i], kin->alpha[i],
                                                    kin->fz[i], kin->vwx[i], &fx[i],
                                                    &fy[i]);
        if (st != RFE_OK) {
            return st;
        }
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        f0x[i] = fx[i];
        f0y[i] = fy[i];
    }
    return RFE_OK;
}

rfe_status_t rfe_tyre_forces_abs(const rfe_tyre_params_t *tp, const rfe_wheel_kin_t *kin,
                                 const rfe_real_t mu[RFE_WHEELS],
                                 rfe_real_t fx[RFE_WHEELS], rfe_real_t fy[RFE_WHEELS])
{
    rfe_real_t tx[RFE_WHEELS];
    rfe_real_t ty[RFE_WHEELS];
    size_t i;

    if ((tp == NULL) || (kin == NULL) || (mu == NULL) || (fx == NULL) || (fy == NULL)) {
        return RFE_ERR_NULL;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        const rfe_status_t st =
            (tp->mode == RFE_TYRE_MAGIC)
                ? rfe_tyre_magic_abs(tp, kin->kappa[i], kin->alpha[i], kin->fz[i],
                                     kin->vwx[i], mu[i], &tx[i], &ty[i])
                : rfe_tyre_dugoff_abs(tp, kin->kappa[i], kin->alpha[i], kin->fz[i],
                                      kin->vwx[i], mu[i], &tx[i], &ty[i]);
        if (st != RFE_OK) {
            return st;
        }
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        fx[i] = tx[i];
        fy[i] = ty[i];
    }
    return RFE_OK;
}

/* ---- internal API (tyre_internal.h) ---------------------------------------------------- */

void rfe_tyre_dugoff_pre(const rfe_tyre_params_t *tp, rfe_real_t kappa, rfe_real_t alpha,
                         rfe_real_t vwx, rfe_dugoff_pre_t *pre)
{
    const rfe_real_t k = rfe_clamp(kappa, RFE_R(-1.0), RFE_R(1.0));
    const rfe_real_t ta = RFE_TAN(rfe_clamp(alpha, -tp->alpha_max, tp->alpha_max));
    dugoff_terms(k, ta, tp->cx, tp->cy, tp->eps, vwx, pre);
    if (tp->mode == RFE_TYRE_MAGIC) {
        magic_terms(tp->cx, tp->cy, pre);
    }
}

rfe_status_t rfe_tyre_dugoff_abs_pre(const rfe_tyre_params_t *tp,
                                     const rfe_dugoff_pre_t *pre, rfe_real_t kappa,
                                     rfe_real_t alpha, rfe_real_t fz, rfe_real_t vwx,
                                     rfe_real_t mu, rfe_real_t *fx, rfe_real_t *fy)
{
    rfe_real_t g;
    const rfe_status_t st = check_wheel(tp, kappa, alpha, fz, vwx, fx, fy);

    if (st != RFE_OK) {
        return st;
    }
    if (!rfe_is_finite(mu)) {
        return RFE_ERR_NONFINITE;
    }
    if (tp->mode == RFE_TYRE_MAGIC) {
        magic_at_mu(tp, pre, fz, mu, fx, fy); /* as rfe_tyre_magic_abs */
        return RFE_OK;
    }
    /* A cubature point may put mu below 0: evaluate it at mu = 0 (MODEL.md §4). */
    g = dugoff_g(pre, rfe_max(mu, RFE_R(0.0)));
    /* Fx = cx Fz k f(L)/(1-|k|), Fy = cy Fz tan(a) f(L)/(1-|k|), as rfe_tyre_dugoff_abs. */
    *fx = fz * tp->cx * pre->k * g;
    *fy = fz * tp->cy * pre->tan_a * g;
    return RFE_OK;
}

void rfe_tyre_wheel_kin(const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
                        const rfe_sample_t *u, rfe_real_t c, rfe_real_t s, size_t i,
                        rfe_real_t *vwx, rfe_real_t *alpha, rfe_real_t *kappa)
{
    rfe_real_t px[RFE_WHEELS];
    rfe_real_t py[RFE_WHEELS];
    rfe_wheel_positions(veh, px, py);
    wheel_kin(veh, tp, u, c, s, i, px[i], py[i], vwx, alpha, kappa);
}

rfe_real_t rfe_tyre_wheel_kappa(const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
                                rfe_real_t omega, rfe_real_t vwx)
{
    return wheel_kappa(veh, tp, omega, vwx);
}

void rfe_tyre_dugoff_pre_tan(const rfe_tyre_params_t *tp, rfe_real_t kappa,
                             rfe_real_t tan_a, rfe_real_t vwx, rfe_dugoff_pre_t *pre)
{
    const rfe_real_t k = rfe_clamp(kappa, RFE_R(-1.0), RFE_R(1.0));
    dugoff_terms(k, tan_a, tp->cx, tp->cy, tp->eps, vwx, pre);
    if (tp->mode == RFE_TYRE_MAGIC) {
        magic_terms(tp->cx, tp->cy, pre);
    }
}

/* ---- the forces' derivatives (docs/OBSERVER.md §4.2) ------------------------------------- */

void rfe_tyre_norm_pre(const rfe_tyre_params_t *tp, rfe_real_t kappa, rfe_real_t alpha,
                       rfe_real_t vwx, rfe_dugoff_pre_t *pre)
{
    const rfe_real_t k = rfe_clamp(kappa, RFE_R(-1.0), RFE_R(1.0));
    const rfe_real_t ta = RFE_TAN(rfe_clamp(alpha, -tp->alpha_max, tp->alpha_max));
    dugoff_terms(k, ta, tp->Cx_n, tp->Cy_n, tp->eps, vwx, pre);
}

/* dE along d: E = max(0, 1 - eps |vwx| sqrt(k^2 + tan^2 a)) has
 * dE = -eps (sgn(vwx) d_vwx |(k, t)| + |vwx| (k dk + t dt) / |(k, t)|) where E > 0, else 0
 * (the clamp; (k, t) != 0 since S > 0 at the only call). */
static rfe_real_t dugoff_de(const rfe_dugoff_pre_t *pre, rfe_real_t eps, rfe_real_t vwx,
                            const rfe_slip_dir_t *d)
{
    rfe_real_t de = RFE_R(0.0);
    if (pre->e > RFE_R(0.0)) {
        const rfe_real_t slip = RFE_SQRT((pre->k * pre->k) + (pre->tan_a * pre->tan_a));
        const rfe_real_t dslip = ((pre->k * d->k) + (pre->tan_a * d->tan_a)) / slip;
        de = -eps * (((rfe_sgn(vwx) * d->vwx) * slip) + (RFE_FABS(vwx) * dslip));
    }
    return de;
}

/* The Dugoff factor g = dugoff_g(pre, mu_s) (S > 0) differentiated: along d (*dg) and by the
 * friction scale mu_s (*dg_mu). With q = mu_s / (2 S), L = q (1 - |k|) E:
 *   L < 1:  g = q E (2 - L): dq = -q dS / S, dL = (dq (1 - |k|) - q sgn(k) dk) E + q (1 - |k|) dE,
 *           dg = (dq E + q dE) (2 - L) - q E dL,  dg/dmu_s = E (1 - L) / S;
 *   L >= 1: g = 1 / (1 - |k|): dg = sgn(k) dk / (1 - |k|)^2, dg/dmu_s = 0;
 * dS = (c1^2 k dk + c2^2 tan a dt) / S. */
static void dugoff_g_jac(const rfe_dugoff_pre_t *pre, rfe_real_t c1, rfe_real_t c2,
                         rfe_real_t eps, rfe_real_t vwx, rfe_real_t mu_s,
                         const rfe_slip_dir_t *d, rfe_real_t *dg, rfe_real_t *dg_mu)
{
    const rfe_real_t S = pre->s;
    const rfe_real_t E = pre->e;
    const rfe_real_t L = mu_s * pre->omk * E / (RFE_R(2.0) * S);
    if (L < RFE_R(1.0)) {
        const rfe_real_t q = mu_s / (RFE_R(2.0) * S);
        const rfe_real_t ds =
            (((c1 * pre->k) * (c1 * d->k)) + ((c2 * pre->tan_a) * (c2 * d->tan_a))) / S;
        const rfe_real_t de = dugoff_de(pre, eps, vwx, d);
        const rfe_real_t dq = -q * ds / S;
        const rfe_real_t dl =
            (((dq * pre->omk) - (q * (rfe_sgn(pre->k) * d->k))) * E) + ((q * pre->omk) * de);
        *dg = (((dq * E) + (q * de)) * (RFE_R(2.0) - L)) - ((q * E) * dl);
        *dg_mu = E * (RFE_R(1.0) - L) / S;
    } else {
        *dg = (rfe_sgn(pre->k) * d->k) / (pre->omk * pre->omk);
        *dg_mu = RFE_R(0.0);
    }
}

/* Dugoff forces F = fz (c1 k, c2 tan a) g at the friction scale mu_s and their derivatives
 * (along d; by mu_s): dF = fz (c1 (dk g + k dg), c2 (dt g + t dg)), dF/dmu_s = fz (c1 k, c2 t)
 * dg/dmu_s. S = 0 (no slip): the limit S -> 0, dg = dg/dmu_s = 0 and g = 1 (L -> infinity)
 * where mu_s > 0, g = 0 at mu_s = 0 (no force at any slip). */
static void dugoff_jac(const rfe_dugoff_pre_t *pre, rfe_real_t c1, rfe_real_t c2,
                       rfe_real_t eps, rfe_real_t vwx, rfe_real_t mu_s, rfe_real_t fz,
                       const rfe_slip_dir_t *d, rfe_tyre_jac_t *o)
{
    const rfe_real_t g = dugoff_g(pre, mu_s);
    rfe_real_t g_d = g;
    rfe_real_t dg = RFE_R(0.0);
    rfe_real_t dg_mu = RFE_R(0.0);
    if (pre->s > RFE_R(0.0)) {
        dugoff_g_jac(pre, c1, c2, eps, vwx, mu_s, d, &dg, &dg_mu);
    } else if (!(mu_s > RFE_R(0.0))) {
        g_d = RFE_R(0.0);
    } else {
        /* g = 1 */
    }
    /* as rfe_tyre_dugoff_abs_pre / rfe_tyre_dugoff_norm: the same products, the same bits */
    o->fx = fz * c1 * pre->k * g;
    o->fy = fz * c2 * pre->tan_a * g;
    o->dfx = (fz * c1) * ((d->k * g_d) + (pre->k * dg));
    o->dfy = (fz * c2) * ((d->tan_a * g_d) + (pre->tan_a * dg));
    o->mfx = (fz * c1) * (pre->k * dg_mu);
    o->mfy = (fz * c2) * (pre->tan_a * dg_mu);
}

/* The Magic Formula shape G of magic_shape (the same operations) and dG/ds, from its own atan
 * values a = atan(x), b = atan(y) (x = s / (m C), y = x - E (x - a)) and one cosine:
 *   dG/dx = cos(C b) C (1 - E + E / (1 + x^2)) / (1 + y^2),  dG/ds = dG/dx / (m C),
 * written with n = s - E (s - m C a) = m C y as
 *   dG/ds = cos(C b) C (1 - E + E (mC)^2 / ((mC)^2 + s^2)) mC / ((mC)^2 + n^2)   (m C > 0; 0
 * at m = 0, where the force is 0 whatever the slip). */
static rfe_real_t magic_shape_jac(rfe_real_t s, rfe_real_t m, rfe_real_t C, rfe_real_t E,
                                  rfe_real_t *g_s)
{
    const rfe_real_t mc = m * C;
    rfe_real_t n;
    const rfe_real_t phi = C * magic_inner(s, mc, E, RFE_ATAN2(s, mc), &n);
    *g_s = RFE_R(0.0);
    if (mc > RFE_R(0.0)) {
        const rfe_real_t mc2 = mc * mc;
        const rfe_real_t shape = (RFE_R(1.0) - E) + ((E * mc2) / (mc2 + (s * s)));
        *g_s = ((RFE_COS(phi) * C) * shape) * (mc / (mc2 + (n * n)));
    }
    return RFE_SIN(phi);
}

/* Magic Formula forces F = fz m G(s) u (magic_at_mu's operations) and their derivatives, m =
 * max(mu, 0) > 0: ds = ux cx dk + uy cy dt, du = ((cx dk, cy dt) - u ds) / s,
 * dF = fz m (G_s ds u + G du); dF/dmu = fz u (G - s G_s) (x dG/dx = s G_s). At s = 0 (u = 0)
 * the force is linear in the slip: dF = fz m G_s (cx dk, cy dt), dF/dmu = 0. m = 0: every
 * derivative 0 (no force at any slip). */
typedef struct {
    rfe_real_t m;  /* max(mu, 0) */
    rfe_real_t gx; /* G of the x direction's curve */
    rfe_real_t gxs; /* its dG/ds */
    rfe_real_t gy;
    rfe_real_t gys;
} magic_curves_t;

/* The two curves of magic_jac at friction mu: they do not depend on the direction d. */
static void magic_curves(const rfe_tyre_params_t *tp, const rfe_dugoff_pre_t *pre, rfe_real_t mu,
                         magic_curves_t *g)
{
    g->m = rfe_max(mu, RFE_R(0.0));
    g->gx = magic_shape_jac(pre->s, g->m, tp->shape_Cx, tp->shape_Ex, &g->gxs);
    g->gy = magic_shape_jac(pre->s, g->m, tp->shape_Cy, tp->shape_Ey, &g->gys);
}

/* magic_jac from the curves g of magic_curves (the same operations). */
static void magic_jac_of(const rfe_tyre_params_t *tp, const rfe_dugoff_pre_t *pre, rfe_real_t fz,
                         const magic_curves_t *g, const rfe_slip_dir_t *d, rfe_tyre_jac_t *o)
{
    const rfe_real_t m = g->m;
    const rfe_real_t fm = fz * m;
    const rfe_real_t s = pre->s;
    const rfe_real_t gxs = g->gxs;
    const rfe_real_t gys = g->gys;
    const rfe_real_t gx = g->gx;
    const rfe_real_t gy = g->gy;
    const rfe_real_t cdk = tp->cx * d->k;
    const rfe_real_t cdt = tp->cy * d->tan_a;
    o->fx = fm * gx * pre->ux;
    o->fy = fm * gy * pre->uy;
    o->mfx = RFE_R(0.0);
    o->mfy = RFE_R(0.0);
    if (s > RFE_R(0.0)) {
        const rfe_real_t ds = (pre->ux * cdk) + (pre->uy * cdt);
        const rfe_real_t dux = (cdk - (pre->ux * ds)) / s;
        const rfe_real_t duy = (cdt - (pre->uy * ds)) / s;
        o->dfx = fm * (((gxs * ds) * pre->ux) + (gx * dux));
        o->dfy = fm * (((gys * ds) * pre->uy) + (gy * duy));
        if (m > RFE_R(0.0)) {
            o->mfx = (fz * pre->ux) * (gx - (s * gxs));
            o->mfy = (fz * pre->uy) * (gy - (s * gys));
        }
    } else {
        o->dfx = fm * (gxs * cdk);
        o->dfy = fm * (gys * cdt);
    }
}

static void magic_jac(const rfe_tyre_params_t *tp, const rfe_dugoff_pre_t *pre, rfe_real_t fz,
                      rfe_real_t mu, const rfe_slip_dir_t *d, rfe_tyre_jac_t *o)
{
    magic_curves_t g;
    magic_curves(tp, pre, mu, &g);
    magic_jac_of(tp, pre, fz, &g, d, o);
}

rfe_status_t rfe_tyre_pre_jac(const rfe_tyre_params_t *tp, const rfe_dugoff_pre_t *pre,
                              rfe_real_t kappa, rfe_real_t alpha, rfe_real_t fz, rfe_real_t vwx,
                              rfe_real_t mu, const rfe_slip_dir_t *d, rfe_tyre_jac_t *out)
{
    rfe_status_t st = RFE_ERR_NULL;
    if ((pre != NULL) && (d != NULL) && (out != NULL)) {
        st = check_wheel(tp, kappa, alpha, fz, vwx, &out->fx, &out->fy);
    }
    if (st != RFE_OK) {
        return st;
    }
    if (!rfe_is_finite(mu)) {
        return RFE_ERR_NONFINITE;
    }
    if (tp->mode == RFE_TYRE_MAGIC) {
        magic_jac(tp, pre, fz, mu, d, out);
    } else if (tp->mode == RFE_TYRE_PAPER) {
        /* F = mu F0: dF = mu dF0, dF/dmu = F0 */
        rfe_tyre_jac_t f0;
        dugoff_jac(pre, tp->Cx_n, tp->Cy_n, tp->eps, vwx, RFE_R(1.0), fz, d, &f0);
        out->fx = mu * f0.fx;
        out->fy = mu * f0.fy;
        out->dfx = mu * f0.dfx;
        out->dfy = mu * f0.dfy;
        out->mfx = f0.fx;
        out->mfy = f0.fy;
    } else {
        /* mu < 0 is evaluated at 0 (MODEL.md §4), where nothing depends on mu */
        dugoff_jac(pre, tp->cx, tp->cy, tp->eps, vwx, rfe_max(mu, RFE_R(0.0)), fz, d, out);
        if (mu <= RFE_R(0.0)) {
            out->mfx = RFE_R(0.0);
            out->mfy = RFE_R(0.0);
        }
    }
    return RFE_OK;
}

rfe_status_t rfe_tyre_magic_basis(const rfe_tyre_params_t *tp, const rfe_dugoff_pre_t *pre,
                                  rfe_real_t kappa, rfe_real_t alpha, rfe_real_t fz,
                                  rfe_real_t vwx, rfe_real_t mu, rfe_tyre_jac_t out[2])
{
    rfe_status_t st = RFE_ERR_NULL;
    if ((pre != NULL) && (out != NULL)) {
        st = check_wheel(tp, kappa, alpha, fz, vwx, &out[0].fx, &out[0].fy);
    }
    if (st != RFE_OK) {
        return st;
    }
    if (!rfe_is_finite(mu)) {
        return RFE_ERR_NONFINITE;
    }
    {
        /* the unit changes of kappa and of tan(alpha), as wheel_basis (meas_flt.c) forms them */
        const rfe_slip_dir_t ek = {RFE_R(1.0), RFE_R(0.0), RFE_R(0.0)};
        const rfe_slip_dir_t et = {RFE_R(0.0), RFE_R(1.0), RFE_R(0.0)};
        magic_curves_t g;
        magic_curves(tp, pre, mu, &g);
        magic_jac_of(tp, pre, fz, &g, &ek, &out[0]);
        magic_jac_of(tp, pre, fz, &g, &et, &out[1]);
    }
    return RFE_OK;
}
