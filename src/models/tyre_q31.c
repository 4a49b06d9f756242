/**
 * @file tyre_q31.c
 * @brief Fixed-point twin of tyre_flt.c: wheel kinematics, loads, slips (MODEL.md §3) and the
 *        Dugoff tyre (§4). Integer operations only (rfe/component/tyre_q31.h).
 *
 * Internal formats (docs/FIXED_POINT.md, "Tyre, kinematics and observation matrix"):
 *  - body and wheel-centre velocities: int64 Q51 (range 2^12 m/s). vx 2^28 is exact,
 *    r y_i (Q27 x Q29 = Q56) is rounded once to Q51 (2^-52 m/s), omega R (Q22 x Q29) is exactly
 *    Q51, and the rotation by delta rounds each product once (rfe_q31_mul64x32);
 *  - loads: int64 Q43 sums of the static load (Q15 2^28) and k a (Q20 x Q24 = Q44, one
 *    rounding), so one rounding to Q15 at the end;
 *  - Dugoff: mantissa/exponent pairs with 30 significant bits (block floating point in
 *    integers) for S, sqrt(k^2 + tan^2 a), eps |vwx| and mu (1 - |k|) E, because their ranges
 *    span many decades (S from 0 to 1800); E, L and the direction cosines C k / S, C tan a / S
 *    in Q30; the force magnitude w in Q29; the forces Fz w u rounded once to Q15;
 *  - Magic Formula (docs/ESTIMATOR.md "The Magic Formula tyre"): the Dugoff set-up's S and
 *    direction cosines, then per direction the pair (S, m C) in one common format with 30
 *    significant bits (only their ratio matters), the two atan2 (Q31, the short 32-bit
 *    CORDIC of fxmath_internal_q31.h), phi = C b (Q55, exact), G = sin phi (Q30, table and
 *    polynomial, fxmath_internal_q31.h), the magnitude w = m G (Q29) and the forces Fz w u
 *    rounded once to Q15.
 */
#include "rfe/component/tyre_q31.h"

#include "rfe/component/fxmath.h"

#include "numerics/fxmath_internal_q31.h"
#include "numerics/internal_q31.h"
#include "numerics/xf_q31.h"
#include "models/tyre_internal_q31.h"

/* Internal velocity format: Q51, and the shift from the sample's speed format to it. */
#define QV 51u
#define QV_SPEED (QV - (unsigned int)RFE_FIX_Q_SPEED)
/* 1/2 in Q30 as uint64: the rounding bit of a shift by 30. */
#define HALF_Q30 ((uint64_t)1 << 29)
/* 1.0 in Q30, 2^30 (kappa, E, L, direction cosines). */
#define ONE_Q30 ((int32_t)0x40000000)
/* The slip arithmetic below holds kappa in Q30 (ONE_Q30, the Q59 = Q29 x Q30 of mu (1 - |k|)). */
#if RFE_FIX_Q_KAPPA != 30
#error "tyre_q31.c computes kappa in Q30: keep RFE_FIX_Q_KAPPA (params_q31.h) at 30"
#endif

/* ---- fxmath calls whose arguments are valid by construction -------------------------------
 * Each fxmath function fails only for a NULL pointer or an argument outside its domain; the
 * wrappers below are called with local outputs and with arguments proven inside the domain at
 * each call site, so the status is always RFE_OK and is not propagated. */

/* round(a 2^shift / b): b != 0 and shift in [-62, 62] at every call. */
static int32_t div_q(int32_t a, int32_t b, int shift, uint32_t *sat)
{
    int32_t q = 0;
    const rfe_status_t st = rfe_fix_div(a, b, shift, &q, sat);
    (void)st;
    return q;
}

/* round(a 2^30 / b) and round(c 2^30 / b) (div_q(., b, 30)'s integers; 0 for b <= 0, where
 * div_q's rfe_fix_div fails and leaves its 0): one reciprocal of b for both
 * (rfe_q31_recip_init, then rfe_q31_div_round_by: rfe_q31_div_round's integer, round(num / b)
 * ties away from zero, saturated to the symmetric int32 range as rfe_fix_div's), where the
 * two divisions took a 64-by-32 division each (issue 21; test_fxmath_q31.c checks the
 * equality). */
static void div2_q30(int32_t a, int32_t c, int32_t b, int32_t *qa, int32_t *qc)
{
    *qa = 0;
    *qc = 0;
    if (b > 0) {
        rfe_q31_recip_t r;
        uint32_t scratch = 0u;
        rfe_q31_recip_init(&r, b);
        *qa = rfe_q31_div_round_by((int64_t)a * rfe_q31_pow2(30u), &r, &scratch);
        *qc = rfe_q31_div_round_by((int64_t)c * rfe_q31_pow2(30u), &r, &scratch);
    }
}

/* |(x, y)|, exactly rounded. */
static int32_t norm2(int32_t x, int32_t y, uint32_t *sat)
{
    int32_t v[2];
    int32_t r = 0;
    rfe_status_t st;
    v[0] = x;
    v[1] = y;
    st = rfe_fix_norm(v, 2u, &r, sat);
    (void)st;
    return r;
}

/* tan(angle), Q26: |angle| <= alpha_max < 1.5 rad at the only call (the domain of
 * rfe_q31_tan_q29, whose ~2^-27 the tyre curves need, not the CORDIC's 2^-40). */
static int32_t tan_q(int32_t angle)
{
    return rfe_q31_tan_q29(angle);
}

/* ---- parameter checks ------------------------------------------------------------------- */

static int alpha_max_ok(const rfe_tyre_params_q31_t *tp)
{
    return (tp->alpha_max > 0) && (tp->alpha_max < RFE_FIX_TAN_LIMIT_Q29);
}

/* ---- kinematics (MODEL.md §3) ----------------------------------------------------------- */

/* alpha = -atan2(v_wy, |v_wx|) of the Q51 wheel-centre velocity, clamped to +-alpha_max.
 * rfe_q31_atan2_q29 scales both components by one common power of two, so the angle keeps its
 * accuracy (<= 3.59e-9 rad) at any speed. */
static int32_t slip_angle(int64_t vwx, int64_t vwy, int32_t alpha_max)
{
    const int32_t a = rfe_q31_atan2_q29(vwy, (int64_t)rfe_q31_mag64(vwx)); /* |.| < 2^61 */

    /* |a| <= pi/2 in Q29 (x >= 0), so the negation cannot overflow. */
    return rfe_fix_clamp(-a, -alpha_max, alpha_max);
}

/* kappa = (omega R - v_wx) / max(|omega R|, |v_wx|, v_min), clipped to [-1, 1], Q30.
 * Q51 operands: |omega R| <= 2^62 (Q22 x Q29), |v_wx| < 2^61, so num fits int64; den >= v_min
 * > 0. Inside the clip |num| < den: both are scaled by one shift to den <= 2^30, and the
 * exactly rounded quotient is <= 2^30 (no saturation). */
static int32_t long_slip(int32_t omega, int32_t R, int64_t vwx, int32_t v_min)
{
    const int64_t vr = rfe_fix_mul32x32(omega, R);
    const int64_t num = vr - vwx;
    const uint64_t mvr = rfe_q31_mag64(vr);
    const uint64_t mvx = rfe_q31_mag64(vwx);
    const uint64_t mv = (uint64_t)v_min << QV_SPEED;
    uint64_t den = (mvr > mvx) ? mvr : mvx;
    int32_t k;

    den = (den > mv) ? den : mv;
    if (num >= (int64_t)den) {
        k = ONE_Q30;
    } else if (num <= -(int64_t)den) {
        k = -ONE_Q30;
    } else {
        const unsigned int sh = rfe_q31_norm_shift(den, 30u);
        const int32_t nm = rfe_q31_shr_to32(num, sh);
        const int32_t dm = rfe_q31_shr_to32((int64_t)den, sh);
        uint32_t scratch = 0u;
        k = div_q(nm, dm, 30, &scratch); /* dm >= 2^27 > 0; |nm| <= dm: no saturation */
    }
    return k;
}

/* Quasi-static loads (MODEL.md §3), clamped at >= 0, in int64 Q43:
 *   static: fz_static (Q15) 2^28, |.| < 2^59;
 *   pitch = k_pitch ax, roll = k_roll ay: Q20 x Q24 = Q44 (< 2^62), rounded to Q43 (< 2^61);
 * so every sum is below 2^59 + 2^62 < 2^63. One rounding to Q15, saturating (counted per
 * wheel in cnt[i]). */
static void vertical_loads_q31(const rfe_vehicle_q31_t *veh, int32_t ax, int32_t ay,
                               int32_t fz[RFE_WHEELS], uint32_t cnt[RFE_WHEELS])
{
    const int64_t fs_f = (int64_t)veh->fz_static_f * rfe_q31_pow2(28u);
    const int64_t fs_r = (int64_t)veh->fz_static_r * rfe_q31_pow2(28u);
    const int64_t pitch = rfe_fix_shr64_round(rfe_fix_mul32x32(veh->k_pitch, ax), 1u);
    const int64_t roll_f = rfe_fix_shr64_round(rfe_fix_mul32x32(veh->k_roll_f, ay), 1u);
    const int64_t roll_r = rfe_fix_shr64_round(rfe_fix_mul32x32(veh->k_roll_r, ay), 1u);
    int64_t v[RFE_WHEELS];
    size_t i;

    /* ay > 0 unloads the left wheels; ax > 0 loads the rear. */
    v[RFE_FL] = fs_f - pitch - roll_f;
    v[RFE_FR] = fs_f - pitch + roll_f;
    v[RFE_RL] = fs_r + pitch - roll_r;
    v[RFE_RR] = fs_r + pitch + roll_r;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        cnt[i] = 0u;
        fz[i] = rfe_fix_narrow((v[i] > 0) ? v[i] : 0, 28u, &cnt[i]);
    }
}

/* Wheel i's centre velocity in wheel axes, int64 Q51 (c, s: cos and sin of delta, Q30; only
 * the front wheels steer). Wheel positions (MODEL.md §1), Q29: front x = Lf, rear x = -Lr,
 * left y = +B/2. */
static void wheel_velocity(const rfe_vehicle_q31_t *veh, const rfe_sample_q31_t *u, int32_t c,
                           int32_t s, size_t i, int64_t *vwx_out, int64_t *vwy_out)
{
    const int64_t px = (i < (size_t)RFE_RL) ? (int64_t)veh->Lf : -(int64_t)veh->Lr;
    const int64_t y = (i < (size_t)RFE_RL) ? (int64_t)veh->yf : (int64_t)veh->yr;
    const int64_t py = ((i == (size_t)RFE_FL) || (i == (size_t)RFE_RL)) ? y : -y;
    const int32_t ci = (i < (size_t)RFE_RL) ? c : ONE_Q30;
    const int32_t si = (i < (size_t)RFE_RL) ? s : 0;
    /* v_i = (vx - r y_i, vy + r x_i) in Q51: |vx 2^28| <= 2^59, |r y| (Q56) <= 2^62
     * becomes <= 2^57 in Q51, so |vb| < 2^59.4. */
    const int64_t vbx = ((int64_t)u->vx * rfe_q31_pow2(QV_SPEED)) -
                        rfe_fix_shr64_round(rfe_fix_mul_m31((int64_t)u->yaw_rate, py), 5u);
    const int64_t vby = ((int64_t)u->vy * rfe_q31_pow2(QV_SPEED)) +
                        rfe_fix_shr64_round(rfe_fix_mul_m31((int64_t)u->yaw_rate, px), 5u);
    /* Rotated into wheel axes: |vb c|, |vb s| < 2^59.4 each (|c|, |s| <= 1), sums < 2^60.4. */
    *vwx_out = rfe_q31_mul64x32(vbx, ci, 30u) + rfe_q31_mul64x32(vby, si, 30u);
    *vwy_out = rfe_q31_mul64x32(vby, ci, 30u) - rfe_q31_mul64x32(vbx, si, 30u);
}

void rfe_tyre_wheel_kin_q31(const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
                            const rfe_sample_q31_t *u, int32_t c, int32_t s, size_t i,
                            rfe_fix_t *vwx, rfe_fix_t *alpha, rfe_fix_t *kappa, uint32_t *sat)
{
    int64_t vx51 = 0;
    int64_t vy51 = 0;
    wheel_velocity(veh, u, c, s, i, &vx51, &vy51);
    *vwx = rfe_fix_narrow(vx51, QV_SPEED, sat);
    *alpha = slip_angle(vx51, vy51, tp->alpha_max);
    *kappa = long_slip(u->omega[i], veh->R, vx51, tp->v_min);
}

rfe_fix_t rfe_tyre_wheel_kappa_q31(const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
                                   const rfe_sample_q31_t *u, int32_t c, int32_t s, size_t i)
{
    int64_t vx51 = 0;
    int64_t vy51 = 0;
    wheel_velocity(veh, u, c, s, i, &vx51, &vy51);
    return long_slip(u->omega[i], veh->R, vx51, tp->v_min);
}

rfe_status_t rfe_tyre_kinematics_ex_q31(const rfe_vehicle_q31_t *veh,
                                        const rfe_tyre_params_q31_t *tp,
                                        const rfe_sample_q31_t *u, rfe_wheel_kin_q31_t *kin,
                                        rfe_tyre_kin_extra_q31_t *extra)
{
    int32_t c = 0;
    int32_t s = 0;
    size_t i;

    if ((tp->v_min <= 0) || !alpha_max_ok(tp)) {
        return RFE_ERR_PARAM;
    }
    {
        rfe_q31_sincos_q29(u->delta, &s, &c); /* every angle */
    }
    /* nothing fails below the check: *kin is written in place (issue 21: no copy of it) */
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        extra->sat_vwx[i] = 0u;
        rfe_tyre_wheel_kin_q31(veh, tp, u, c, s, i, &kin->vwx[i], &kin->alpha[i], &kin->kappa[i],
                               &extra->sat_vwx[i]);
    }
    vertical_loads_q31(veh, u->ax, u->ay, kin->fz, extra->sat_fz);
    extra->cos_delta = c;
    extra->sin_delta = s;
    return RFE_OK;
}

rfe_status_t rfe_tyre_kinematics_q31(const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
                                     const rfe_sample_q31_t *u, rfe_wheel_kin_q31_t *kin,
                                     uint32_t *sat)
{
    rfe_tyre_kin_extra_q31_t extra;
    uint32_t count = 0u;
    rfe_status_t st;
    size_t i;

    if ((veh == NULL) || (tp == NULL) || (u == NULL) || (kin == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_tyre_kinematics_ex_q31(veh, tp, u, kin, &extra);
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        count += extra.sat_vwx[i] + extra.sat_fz[i]; /* at most 2 each */
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

/* ---- Dugoff tyre (MODEL.md §4) ---------------------------------------------------------- */

/* A positive quantity as mant 2^-q with |mant| <= 2^30 (block floating point). */
typedef struct {
    int32_t mant;
    unsigned int q;
} bfp_t;

/* v (0 <= v < 2^63) in Q(q) to 30 bits: relative rounding error <= 2^-30. The callers keep
 * q - shift >= 0 (commented at each call). */
static inline bfp_t bfp_make(int64_t v, unsigned int q)
{
    const unsigned int sh = rfe_q31_norm_shift((uint64_t)v, 30u);
    bfp_t r;
    r.mant = rfe_q31_shr_to32(v, sh);
    r.q = q - sh;
    return r;
}

/* E = max(0, 1 - eps |vwx| sqrt(k^2 + tan^2 a)) in Q30 (eps >= 0, so E <= 1).
 * slip = |(k, tan a)|: k Q30 and tan a Q26 brought to Q30 (|.| < 2^34) are scaled by one
 * shift (<= 4) to <= 2^30 and normed exactly: slip in Q(30 - sh) >= Q26, <= 2^30.5.
 * ev = eps |vwx|: Q32 x Q23 = Q55, < 2^62, to 30 bits: Q(55 - sh) >= Q23.
 * P = ev slip < 2^61 in Q(q_ev + q_slip) >= Q49; rounded to Q30 (shift in [19, 55]). */
static int32_t dugoff_e(int32_t k, int32_t t, int32_t eps, int32_t vwx)
{
    const int64_t t30 = (int64_t)t * 16;
    const uint64_t mk = rfe_q31_mag64(k);
    const uint64_t mt = rfe_q31_mag64(t30);
    const unsigned int sh = rfe_q31_norm_shift((mk > mt) ? mk : mt, 30u);
    uint32_t scratch = 0u;
    /* both <= 2^30, so the norm <= 2^30.5 never saturates */
    const int32_t slip =
        norm2(rfe_q31_shr_to32(k, sh), rfe_q31_shr_to32(t30, sh), &scratch);
    bfp_t ev;
    int64_t p30;

    ev = bfp_make(rfe_fix_mul_m31((int64_t)eps, (int64_t)rfe_q31_mag64(vwx)), 55u);
    p30 = rfe_fix_shr64_round(rfe_fix_mul32x32(ev.mant, slip), (ev.q + (30u - sh)) - 30u);
    return (p30 >= (int64_t)ONE_Q30) ? 0 : (ONE_Q30 - (int32_t)p30);
}

/*
 * Dugoff forces of one wheel, without a singularity (MODEL.md §4; the float code's g = f(L)/(1-|k|)):
 * with S = |(C1 k, C2 tan a)|, the direction cosines ux = C1 k / S, uy = C2 tan a / S and
 *   L < 1:  F = Fz u mu E (1 - L/2)        (= Fz C k g with g = mu E (2 - L) / (2 S))
 *   L >= 1: F = Fz u S / (1 - |k|)         (= Fz C k g with g = 1 / (1 - |k|))
 *   S = 0:  F = 0                          (the float code's g = 1 with C k = C tan a = 0)
 * where L = mu (1 - |k|) E / (2 S), mu = 1 in paper mode. The magnitude w (the brackets) is
 * <= mu < 4 (L < 1) or <= mu E / 2 (L >= 1, since then S <= mu (1 - |k|) E / 2): Q29. The
 * forces are the only values that can exceed their range (counted in *sat).
 * Inputs: k Q30 in [-1, 1], t = tan a Q26, C1, C2 Q24, eps Q32 >= 0, vwx Q23, mu Q29 >= 0,
 * fz Q15 >= 0.
 *
 * Split in two: dugoff_pre computes everything that does not depend on mu and fz (S, the
 * direction cosines, E, 1 - |k|), dugoff_at_mu the rest, so that a caller evaluating one
 * wheel at several mu (the cubature points) computes the first part once. Together they are
 * the same operations in the same order as one evaluation.
 */
static void dugoff_pre_e(int32_t k, int32_t t, int32_t c1, int32_t c2, int32_t eps,
                         int32_t vwx, int with_e, rfe_dugoff_pre_q31_t *pre)
{
    /* S: C1 k is Q54 (|.| <= 2^61), rounded to Q50; C2 tan a is Q50 (< 2^61). One common
     * shift brings both to <= 2^30 (S in Q(50 - sh), sh <= 31); the norm is exact. */
    const int64_t a50 = rfe_fix_shr64_round(rfe_fix_mul32x32(c1, k), 4u);
    const int64_t b50 = rfe_fix_mul32x32(c2, t);
    const uint64_t ma = rfe_q31_mag64(a50);
    const uint64_t mb = rfe_q31_mag64(b50);
    const unsigned int sh = rfe_q31_norm_shift((ma > mb) ? ma : mb, 30u);
    const int32_t ca = rfe_q31_shr_to32(a50, sh);
    const int32_t cb = rfe_q31_shr_to32(b50, sh);
    uint32_t scratch = 0u;
    const int32_t S = norm2(ca, cb, &scratch); /* <= 2^30.5: never saturates */

    pre->tan_a = t;
    pre->s = S;
    pre->qs = 50u - sh;
    pre->ux = 0;
    pre->uy = 0;
    pre->e = 0;
    pre->omk = 0;
    if (S != 0) {
        /* |comp| <= S: the quotients are <= 2^30 in Q30 (no saturation). */
        div2_q30(ca, cb, S, &pre->ux, &pre->uy); /* S > 0: a norm, not 0 */
        if (with_e != 0) {
            pre->e = dugoff_e(k, t, eps, vwx);
            pre->omk = ONE_Q30 - ((k < 0) ? -k : k); /* 1 - |k| in [0, 1], Q30 */
        }
    }
}

/* dugoff_pre_e with E and 1 - |k| (every Dugoff evaluation). */
static void dugoff_pre(int32_t k, int32_t t, int32_t c1, int32_t c2, int32_t eps, int32_t vwx,
                       rfe_dugoff_pre_q31_t *pre)
{
    dugoff_pre_e(k, t, c1, c2, eps, vwx, 1, pre);
}

/* 1 when the friction-independent terms for tp need E and 1 - |k|: every mode but the Magic
 * Formula, whose forces and derivatives read only tan_a, s, qs, ux and uy. */
static int pre_needs_e(const rfe_tyre_params_q31_t *tp)
{
    return (tp->mode != RFE_TYRE_MAGIC) ? 1 : 0;
}

/* L = mu (1 - |k|) E / (2 S) in Q30 (S > 0, mu Q29 >= 0): N = mu (1 - |k|) E: Q29 x Q30 = Q59
 * (< 2^61) to 30 bits (Q >= 28), times E (Q30) to 30 bits again: Q(qn) in [28, 89]. Then
 * L = N / (2 S): shift = 30 - qn + qs - 1 in [-41, 51]. A quotient beyond the int32 range
 * (L >= 2) saturates in the scratch counter: only L >= 1 is used then. 0 where N = 0. */
static int32_t dugoff_l30(const rfe_dugoff_pre_q31_t *pre, int32_t mu)
{
    uint32_t scratch = 0u;
    int32_t l30 = 0;
    const bfp_t n1 = bfp_make(rfe_fix_mul32x32(mu, pre->omk), 59u);
    const bfp_t n = bfp_make(rfe_fix_mul32x32(n1.mant, pre->e), n1.q + 30u);
    if (n.mant > 0) {
        l30 = div_q(n.mant, pre->s, (29 - (int)n.q) + (int)pre->qs, &scratch);
    }
    return l30;
}

static void dugoff_at_mu(const rfe_dugoff_pre_q31_t *pre, int32_t mu, int32_t fz, int32_t *fx,
                         int32_t *fy, uint32_t *sat)
{
    const int32_t S = pre->s;
    const unsigned int qs = (unsigned int)pre->qs;
    const int32_t e30 = pre->e;
    const int32_t omk = pre->omk;
    uint32_t scratch = 0u;
    int32_t l30;
    int64_t w;

    if (S == 0) {
        *fx = 0; /* k = 0 and tan a = 0 (C1, C2 != 0) or no stiffness: no force */
        *fy = 0;
        return;
    }
    l30 = dugoff_l30(pre, mu);
    if (l30 >= ONE_Q30) {
        /* L >= 1: w = S / (1 - |k|) in Q29, shift 59 - qs in [9, 40]; here N > 0, so
         * 1 - |k| > 0, and w <= mu E / 2 (1 + 2^-28) < 2: no saturation. */
        w = div_q(S, omk, 59 - (int)qs, &scratch);
    } else {
        /* L < 1: w = mu E (1 - L/2) = (mu E, Q59 < 2^61) (2^31 - L30, Q31 <= 2^31) / 2^61,
         * <= mu (E <= 1): Q29. */
        w = rfe_q31_mul64x32((int64_t)mu * (int64_t)e30, (int64_t)RFE_FIX_MAX + 1 - l30, 61u);
    }
    /* F = Fz w u: (Fz w, Q44, < 2^62) u (Q30) / 2^59 -> Q15, one rounding; |F| < 2^33. */
    *fx = rfe_fix_sat32(rfe_q31_mul64x32((int64_t)fz * w, pre->ux, 59u), sat);
    *fy = rfe_fix_sat32(rfe_q31_mul64x32((int64_t)fz * w, pre->uy, 59u), sat);
}

/* One evaluation: both parts. */
static void dugoff_core(int32_t k, int32_t t, int32_t c1, int32_t c2, int32_t eps, int32_t vwx,
                        int32_t mu, int32_t fz, int32_t *fx, int32_t *fy, uint32_t *sat)
{
    rfe_dugoff_pre_q31_t pre;
    dugoff_pre(k, t, c1, c2, eps, vwx, &pre);
    dugoff_at_mu(&pre, mu, fz, fx, fy, sat);
}

/* ---- Magic Formula tyre (docs/ESTIMATOR.md "The Magic Formula tyre") ------------------------
 * Per direction d with C = shape_Cd, E = shape_Ed and m = max(mu, 0):
 *   a = atan2(s, m C),  phi = C atan2(s - E (s - m C a), m C),  G = sin phi,  F = Fz m G u
 * with s = S and u = (ux, uy) of the Dugoff set-up (dugoff_pre: the same friction-independent
 * terms serve both curves). Both atan2 are of a pair in one format, so only the ratio of
 * s and m C matters: the pair is brought to 30 significant bits by one power of two (exact
 * when scaling up), which keeps the angle to 0.71 LSB29 whatever s and m are (m -> 0 gives
 * a = pi/2, no overflow, no division). The curve needs ~2^-30, so the angles and the sine
 * are the short 32-bit routines of fxmath_internal_q31.h (rfe_q31_atan2_quad1,
 * rfe_q31_sin_q55), not the 40-step int64 CORDIC of rfe_fix_atan2 / rfe_fix_sincos (which
 * the kinematics keep). With 1 < C < 2 and -4 <= E < 1 (checked):
 *   - 0 <= a <= pi/2, and z = s - E (s - m C a) = (1 - E) s + E m C a >= 0 (clamped there
 *     against the rounding of a), so 0 <= b <= pi/2, 0 <= phi = C b < pi, 0 <= G <= 1;
 *   - w = m G <= m < 4 (Q29) and |F| <= Fz m (saturating, counted, as the Dugoff forces).
 * Error (derived in test/models/test_tyre_magic_q31.c and docs/FIXED_POINT.md): the angles within
 * 0.71 LSB29 (pair rounding) + 1.211e-9 rad (0.65 LSB29, rfe_q31_atan2_quad1) each, the second
 * one also carrying the first's error times E and the sensitivity of the curve to the slip
 * ratio; phi = C b exact; the sine within 6.15e-10 (0.66 LSB30); no intermediate saturates. */

/* 1 when the shape factors are inside the domain the arithmetic below is proven for:
 * 1 < C < 2 and -4 <= E < 1 (Q24), both directions. */
static int magic_shape_ok(const rfe_tyre_params_q31_t *tp)
{
    const int32_t one = RFE_FIX_ONE(RFE_FIX_Q_STIFF);
    return (tp->shape_Cx > one) && (tp->shape_Cx < (2 * one)) && (tp->shape_Ex >= (-4 * one)) &&
           (tp->shape_Ex < one) && (tp->shape_Cy > one) && (tp->shape_Cy < (2 * one)) &&
           (tp->shape_Ey >= (-4 * one)) && (tp->shape_Ey < one);
}

/* v 2^e (0 <= v < 2^62), rounded half up when e < 0 (the callers keep e >= -35 and the result
 * <= 2^30): a shift of the non-negative value, no multiplication (on the Cortex-M0+ a 64-bit
 * product is a libgcc call). */
static int32_t scale_pow2(int64_t v, int e)
{
    const uint64_t u = (uint64_t)v;
    uint64_t r;
    if (e >= 0) {
        r = u << (unsigned int)e;
    } else {
        r = rfe_q31_ushr64_round(u, (unsigned int)(-e));
    }
    return (int32_t)r;
}

/* G = sin(C atan2(s - E (s - m C a), m C)), a = atan2(s, m C), in Q30 (0 <= G <= 1), for
 * S > 0 in Q(qs) (< 2^31, qs in [19, 50]: dugoff_pre's shift is <= 31), m in Q29
 * (0 < m < 2^31), C and E Q24 within magic_shape_ok.
 *   m C: Q29 x Q24 = Q53, exact, in (0, 2^56). S in Q53 would be S 2^(53 - qs) (53 - qs in
 *   [3, 34]): with l the larger bit length of the two in Q53 (<= 65), both are scaled by
 *   2^(30 - l): xn, yn <= 2^30, the larger >= 2^29 (the other exact or rounded, 0.5 unit), so
 *   never both 0: rfe_q31_atan2_quad1's domain. a in Q31, <= round(pi/2 2^31) = 3373259426.
 *   Second angle (E != 0): z = (1 - E) yn + E xn a in Q(W + 24) (W the pair's format):
 *   (2^24 - E) yn < 5 2^24 2^30 = 2^56.4; xn a < 2^30 2^31.65 = 2^61.65 (< 2^62), times E
 *   (|E| <= 2^26) over 2^31: < 2^56.7 (rfe_q31_mul64x32's preconditions), so |z| < 2^57.6;
 *   z and xn 2^24 (< 2^55) are brought below 2^30 by one more shift (z >= 2^29 when xn = 0).
 *   phi = C b: Q24 x Q31 = Q55, exact, <= (2^25 - 1) 3373259426 < round(pi 2^55): the sine's
 *   domain [0, pi]. */
/* The pair of the first atan2 and what the derivatives take from it (magic_shape_jac_q31): xn,
 * yn (m C and s scaled by one power of two, <= 2^30, the larger >= 2^29), a = atan2(yn, xn)
 * (Q31) and z, n = s - E (s - m C a) in the pair's units times 2^24 (z >= 0). */
typedef struct {
    int64_t z;
    int32_t xn;
    int32_t yn;
    uint32_t a;
} magic_pair_q31_t;

/* phi = C b of the shape below (Q55) and the pair *pr (above), from the two atan2 (the same
 * operations as magic_shape_q31). */
static int64_t magic_phi_q31(int32_t S, unsigned int qs, int32_t m, int32_t C, int32_t E,
                             magic_pair_q31_t *pr)
{
    const int64_t mc = rfe_fix_mul32x32(m, C);
    const unsigned int d = 53u - qs;
    const unsigned int lx = rfe_q31_bitlen64((uint64_t)mc);
    const unsigned int ly = rfe_q31_bitlen32((uint32_t)S) + d;
    const int l = (int)((lx > ly) ? lx : ly);
    const int32_t xn = scale_pow2(mc, 30 - l);
    const int32_t yn = scale_pow2((int64_t)S, ((int)d + 30) - l);
    uint32_t b = rfe_q31_atan2_quad1((uint32_t)yn, (uint32_t)xn); /* a, Q31, in [0, pi/2] */

    /* n = s when E = 0 */
    pr->z = (int64_t)yn * rfe_q31_pow2(24u);
    pr->xn = xn;
    pr->yn = yn;
    pr->a = b;

    if (E != 0) {
        const int64_t x24 = (int64_t)xn * rfe_q31_pow2(24u);
        int64_t z = rfe_fix_mul_m31((int64_t)RFE_FIX_ONE(RFE_FIX_Q_STIFF) - (int64_t)E, yn) +
                    rfe_q31_mul64x32((int64_t)xn * (int64_t)b, (int64_t)E, 31u);
        unsigned int sh;
        /* z >= 0 exactly; only the rounding of a (E < 0, yn of a few units) can take it
         * below */
        z = (z > 0) ? z : 0;
        sh = rfe_q31_norm_shift((uint64_t)((z > x24) ? z : x24), 30u);
        b = rfe_q31_atan2_quad1((uint32_t)rfe_q31_shr_to32(z, sh),
                                (uint32_t)rfe_q31_shr_to32(x24, sh));
        pr->z = z;
    }
    /* phi = C b in Q55, within the sine's domain */
    return (int64_t)C * (int64_t)b;
}

static int32_t magic_shape_q31(int32_t S, unsigned int qs, int32_t m, int32_t C, int32_t E)
{
    magic_pair_q31_t pr;
    return rfe_q31_sin_q55(magic_phi_q31(S, qs, m, C, E, &pr));
}

/* Magic Formula forces at m = max(mu, 0) (Q29, >= 0) and load fz (Q15, >= 0) from the
 * friction-independent terms pre (S, qs, ux, uy): F = Fz w u with w = m G in Q29 (<= m),
 * (Fz w, Q44, < 2^62) u (Q30) / 2^59 -> Q15, one rounding, as the Dugoff forces; |F| < 2^33
 * before the (counted) clamp. S = 0 (no slip) or m = 0: F = 0. */
static void magic_forces_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                             int32_t m, int32_t fz, int32_t *fx, int32_t *fy, uint32_t *sat)
{
    int64_t px;
    int64_t py;
    uint64_t wx;
    uint64_t wy;
    if ((pre->s == 0) || (m == 0)) {
        *fx = 0;
        *fy = 0;
        return;
    }
    /* w = m G rounded to Q29 (<= m): m G >= 0, so the rounding is a shift of the product */
    px = rfe_fix_mul32x32(m, magic_shape_q31(pre->s, pre->qs, m, tp->shape_Cx, tp->shape_Ex));
    py = rfe_fix_mul32x32(m, magic_shape_q31(pre->s, pre->qs, m, tp->shape_Cy, tp->shape_Ey));
    wx = ((uint64_t)px + HALF_Q30) >> 30;
    wy = ((uint64_t)py + HALF_Q30) >> 30;
    *fx = rfe_fix_sat32(rfe_q31_mul64x32(rfe_fix_mul_m31(fz, (int64_t)wx), pre->ux, 59u), sat);
    *fy = rfe_fix_sat32(rfe_q31_mul64x32(rfe_fix_mul_m31(fz, (int64_t)wy), pre->uy, 59u), sat);
}

/* Common checks of the single-wheel functions (the float check_wheel, plus the parameters;
 * magic != 0: also the shape factors). */
static rfe_status_t check_wheel_q31(const rfe_tyre_params_q31_t *tp, int32_t fz, const int32_t *o1,
                                    const int32_t *o2, const uint32_t *sat, int magic)
{
    if ((tp == NULL) || (o1 == NULL) || (o2 == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (!alpha_max_ok(tp) || (tp->eps < 0) || ((magic != 0) && !magic_shape_ok(tp))) {
        return RFE_ERR_PARAM;
    }
    if (fz < 0) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* Clip kappa to [-1, 1] and tan of alpha clamped to +-alpha_max (Q26). */
static void slip_inputs(const rfe_tyre_params_q31_t *tp, int32_t kappa, int32_t alpha,
                        int32_t *k, int32_t *t)
{
    *k = rfe_fix_clamp(kappa, -ONE_Q30, ONE_Q30);
    /* |alpha| <= alpha_max < 1.5 rad: inside tan's domain. */
    *t = tan_q(rfe_fix_clamp(alpha, -tp->alpha_max, tp->alpha_max));
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_tyre_dugoff_norm_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa,
                                      rfe_fix_t alpha, rfe_fix_t fz, rfe_fix_t vwx, rfe_fix_t *f0x,
                                      rfe_fix_t *f0y, uint32_t *sat)
{
    int32_t k;
    int32_t t;
    const rfe_status_t st = check_wheel_q31(tp, fz, f0x, f0y, sat, 0);

    if (st != RFE_OK) {
        return st;
    }
    slip_inputs(tp, kappa, alpha, &k, &t);
    dugoff_core(k, t, tp->Cx_n, tp->Cy_n, tp->eps, vwx, RFE_FIX_ONE(RFE_FIX_Q_MU), fz, f0x, f0y,
                sat);
    return RFE_OK;
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_tyre_dugoff_abs_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa,
                                     rfe_fix_t alpha, rfe_fix_t fz, rfe_fix_t vwx, rfe_fix_t mu,
                                     rfe_fix_t *fx, rfe_fix_t *fy, uint32_t *sat)
{
    int32_t k;
    int32_t t;
    const rfe_status_t st = check_wheel_q31(tp, fz, fx, fy, sat, 0);

    if (st != RFE_OK) {
        return st;
    }
    slip_inputs(tp, kappa, alpha, &k, &t);
    /* A cubature point may put mu below 0: evaluate it at mu = 0 (MODEL.md §4). */
    dugoff_core(k, t, tp->cx, tp->cy, tp->eps, vwx, (mu > 0) ? mu : 0, fz, fx, fy, sat);
    return RFE_OK;
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_tyre_magic_abs_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa,
                                    rfe_fix_t alpha, rfe_fix_t fz, rfe_fix_t vwx, rfe_fix_t mu,
                                    rfe_fix_t *fx, rfe_fix_t *fy, uint32_t *sat)
{
    rfe_dugoff_pre_q31_t pre;
    int32_t k;
    int32_t t;
    const rfe_status_t st = check_wheel_q31(tp, fz, fx, fy, sat, 1);

    if (st != RFE_OK) {
        return st;
    }
    slip_inputs(tp, kappa, alpha, &k, &t);
    dugoff_pre(k, t, tp->cx, tp->cy, tp->eps, vwx, &pre);
    /* A cubature point may put mu below 0: evaluate it at mu = 0 (zero force). */
    magic_forces_q31(tp, &pre, (mu > 0) ? mu : 0, fz, fx, fy, sat);
    return RFE_OK;
}

rfe_status_t rfe_tyre_forces_norm_q31(const rfe_tyre_params_q31_t *tp,
                                      const rfe_wheel_kin_q31_t *kin, rfe_fix_t f0x[RFE_WHEELS],
                                      rfe_fix_t f0y[RFE_WHEELS], uint32_t *sat)
{
    rfe_fix_t fx[RFE_WHEELS];
    rfe_fix_t fy[RFE_WHEELS];
    uint32_t count = 0u;
    size_t i;

    if ((kin == NULL) || (f0x == NULL) || (f0y == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    /* Compute all four first so an error leaves the outputs untouched. */
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        const rfe_status_t st = rfe_tyre_dugoff_norm_q31(tp, kin->kappa[i], kin->alpha[i],
                                                         kin->fz[i], kin->vwx[i], &fx[i],
                                                         &fy[i], &count);
        if (st != RFE_OK) {
            return st;
        }
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        f0x[i] = fx[i];
        f0y[i] = fy[i];
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

rfe_status_t rfe_tyre_forces_abs_q31(const rfe_tyre_params_q31_t *tp,
                                     const rfe_wheel_kin_q31_t *kin,
                                     const rfe_fix_t mu[RFE_WHEELS], rfe_fix_t fx[RFE_WHEELS],
                                     rfe_fix_t fy[RFE_WHEELS], uint32_t *sat)
{
    rfe_fix_t tx[RFE_WHEELS];
    rfe_fix_t ty[RFE_WHEELS];
    uint32_t count = 0u;
    size_t i;

    if ((tp == NULL) || (kin == NULL) || (mu == NULL) || (fx == NULL) || (fy == NULL) ||
        (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        const rfe_status_t st =
            (tp->mode == RFE_TYRE_MAGIC)
                ? rfe_tyre_magic_abs_q31(tp, kin->kappa[i], kin->alpha[i], kin->fz[i],
                                         kin->vwx[i], mu[i], &tx[i], &ty[i], &count)
                : rfe_tyre_dugoff_abs_q31(tp, kin->kappa[i], kin->alpha[i], kin->fz[i],
                                          kin->vwx[i], mu[i], &tx[i], &ty[i], &count);
        if (st != RFE_OK) {
            return st;
        }
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        fx[i] = tx[i];
        fy[i] = ty[i];
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

/* ---- internal API (tyre_internal_q31.h) ------------------------------------------------- */

void rfe_tyre_dugoff_pre_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa, rfe_fix_t alpha,
                             rfe_fix_t vwx, rfe_dugoff_pre_q31_t *pre)
{
    int32_t k;
    int32_t t;
    slip_inputs(tp, kappa, alpha, &k, &t);
    dugoff_pre_e(k, t, tp->cx, tp->cy, tp->eps, vwx, pre_needs_e(tp), pre);
}

void rfe_tyre_dugoff_pre_tan_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa,
                                 rfe_fix_t tan_a, rfe_fix_t vwx, rfe_dugoff_pre_q31_t *pre)
{
    const int32_t k = rfe_fix_clamp(kappa, -ONE_Q30, ONE_Q30);
    dugoff_pre_e(k, tan_a, tp->cx, tp->cy, tp->eps, vwx, pre_needs_e(tp), pre);
}

/* The rest of rfe_tyre_dugoff_abs_q31 from pre: Fx, Fy at mu (mu < 0 as 0) and fz. */
static void dugoff_mu_q31(const rfe_dugoff_pre_q31_t *pre, rfe_fix_t mu, rfe_fix_t fz,
                          rfe_fix_t *fx, rfe_fix_t *fy, uint32_t *sat)
{
    /* A cubature point may put mu below 0: evaluate it at mu = 0 (MODEL.md §4). */
    dugoff_at_mu(pre, (mu > 0) ? mu : 0, fz, fx, fy, sat);
}

int rfe_tyre_dugoff_params_ok_q31(const rfe_tyre_params_q31_t *tp)
{
    return (alpha_max_ok(tp) && (tp->eps >= 0)) ? 1 : 0;
}

/* The rest of rfe_tyre_magic_abs_q31 from pre: Fx, Fy with tp's shape at mu (mu < 0 as 0). */
static void magic_mu_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                         rfe_fix_t mu, rfe_fix_t fz, rfe_fix_t *fx, rfe_fix_t *fy,
                         uint32_t *sat)
{
    /* A cubature point may put mu below 0: evaluate it at mu = 0 (zero force). */
    magic_forces_q31(tp, pre, (mu > 0) ? mu : 0, fz, fx, fy, sat);
}

void rfe_tyre_dugoff_abs_pre_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                                 rfe_fix_t mu, rfe_fix_t fz, rfe_fix_t *fx, rfe_fix_t *fy,
                                 uint32_t *sat)
{
    if (tp->mode == RFE_TYRE_MAGIC) {
        magic_mu_q31(tp, pre, mu, fz, fx, fy, sat);
    } else {
        dugoff_mu_q31(pre, mu, fz, fx, fy, sat);
    }
}

int rfe_tyre_abs_params_ok_q31(const rfe_tyre_params_q31_t *tp)
{
    return ((rfe_tyre_dugoff_params_ok_q31(tp) != 0) &&
            ((tp->mode != RFE_TYRE_MAGIC) || (magic_shape_ok(tp) != 0)))
               ? 1
               : 0;
}

/* ---- the forces' derivatives (docs/OBSERVER.md §4.2, FIXED_POINT.md "Observer") ------------
 * The float twin's formulas (tyre_flt.c) operation for operation in rfe_xf_t (xf_q31.h: 30
 * significant bits and a power of two per value), because a derivative's terms span many
 * decades (q = mu / (2 S) from 1e-3 to 1e6, dS/S, 1/|v_wx|). The set-up's Q formats enter
 * exactly; every operation rounds once to 2^-30 relative. */

void rfe_tyre_norm_pre_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa, rfe_fix_t alpha,
                           rfe_fix_t vwx, rfe_dugoff_pre_q31_t *pre)
{
    int32_t k;
    int32_t t;
    slip_inputs(tp, kappa, alpha, &k, &t);
    dugoff_pre(k, t, tp->Cx_n, tp->Cy_n, tp->eps, vwx, pre);
}

/* a b and a b + c d, out of line (RFE_XF_OUTLINE): one copy for the Dugoff derivative's
 * products and sums (dugoff_de_q31, both branches of dugoff_jac_q31; tyre_xf_mul also for the
 * Magic Formula derivative's S = 0 branch, off the curve's path), where every inlined
 * rfe_xf_t product or sum was another copy of rfe_xf_make's normalisation. The same
 * operations in the same order: the same bits. Measured (make firmware-libs, make pil):
 * dugoff_jac_q31 7,288 -> 4,684 B on the Cortex-M4 (-O2), and the observer's step did not
 * slow (the calls replace as many inlined copies). */
RFE_XF_OUTLINE static rfe_xf_t tyre_xf_mul(rfe_xf_t a, rfe_xf_t b) { return rfe_xf_mul(a, b); }

RFE_XF_OUTLINE static rfe_xf_t tyre_xf_dot(rfe_xf_t a, rfe_xf_t b, rfe_xf_t c, rfe_xf_t d)
{
    return rfe_xf_add(rfe_xf_mul(a, b), rfe_xf_mul(c, d));
}

/* sgn(s) a for s in {-1, 0, 1}. */
static rfe_xf_t xf_signed(int s, rfe_xf_t a)
{
    rfe_xf_t r = rfe_xf_make(0, 0);
    if (s > 0) {
        r = a;
    } else if (s < 0) {
        r = rfe_xf_neg(a);
    } else {
        /* 0 */
    }
    return r;
}

/* dE along d (tyre_flt.c dugoff_de) where E > 0, else 0, with (k, t) != 0 (S > 0):
 *   dE = -(eps |(k, t)|) sgn(vwx) d_vwx - (eps |vwx|) (ck dk + ct dt),
 * (ck, ct) = (k, t) / |(k, t)| the cosines of the slip, |.| <= 1. In plain integers, no
 * rfe_xf_t square root or quotient: |k| (Q30) and |t| as Q30 (< 2^35) are brought to 30
 * significant bits by one power of two 2^l (exact when l >= 0; l >= -5 rounds each to 2^-30
 * of the larger), n = |(kn, tn)| in [2^29, 2^30.5] exactly rounded (relative 2^-31), the
 * cosines kn / n, tn / n in Q30 (<= 2^30: no saturation) within 2^-31 + 2^-29 + 2^-31 < 2^-28
 * of the exact ones. eps |(k, t)| = eps n 2^-l: Q32 x Q(30 + l), < 2^31 2^30.5 < 2^62, exact in
 * rfe_xf_t; eps |vwx|: Q32 x Q23 = Q55, < 2^62, exact. Three rfe_xf_t products and two sums
 * with d (real values), as before; the change is within 2^-27 relative of the former
 * rfe_xf_t chain (30-bit roundings in both). Out of line (RFE_XF_OUTLINE), called by
 * rfe_tyre_dugoff_pre_jac_q31: its divisions' stack is beside dugoff_jac_q31's frame, not
 * below it. */
RFE_XF_OUTLINE static rfe_xf_t dugoff_de_q31(const rfe_dugoff_pre_q31_t *pre, int32_t kq,
                                             int32_t eps, int32_t vwx,
                                             const rfe_slip_dir_q31_t *d)
{
    rfe_xf_t de = rfe_xf_make(0, 0);
    if (pre->e > 0) {
        const int64_t t30 = (int64_t)pre->tan_a * 16;
        const uint64_t mk = rfe_q31_mag64(kq);
        const uint64_t mt = rfe_q31_mag64(t30);
        const int l = 30 - (int)rfe_q31_bitlen64((mk > mt) ? mk : mt);
        const int32_t kn = scale_pow2((int64_t)mk, l);
        const int32_t tn = scale_pow2((int64_t)mt, l);
        uint32_t scratch = 0u;
        const int32_t n = norm2(kn, tn, &scratch); /* <= 2^30.5: never saturates */
        int32_t ck = 0;
        int32_t ct = 0;
        div2_q30((kq < 0) ? -kn : kn, (t30 < 0) ? -tn : tn, n, &ck, &ct);
        const rfe_xf_t dsl = tyre_xf_dot(rfe_xf_of(ck, 30), d->k, rfe_xf_of(ct, 30), d->tan_a);
        const rfe_xf_t es = rfe_xf_make((int64_t)eps * (int64_t)n, -(62 + l));
        const rfe_xf_t ev = rfe_xf_make((int64_t)eps * (int64_t)rfe_q31_mag64(vwx), -55);
        const rfe_xf_t inner = tyre_xf_dot(es, xf_signed(rfe_q31_sign(vwx), d->vwx), ev, dsl);
        de = rfe_xf_neg(inner);
    }
    return de;
}

/* Round a product to Q30: v / 2^sh, half up. */
static int64_t q30_of(int64_t v, unsigned int sh) { return rfe_fix_shr64_round(v, sh); }

/* dF, dF/dmu and the forces at mu of the Dugoff forces for S > 0 and L < 1 (tyre_flt.c
 * dugoff_jac's g = w / S), in the form F = Fz w u of dugoff_at_mu (w = mu E (1 - L/2),
 * u = (ux, uy) = (C1 k, C2 t) / S, L from dugoff_l30, the forces' own branch):
 *   dF = Fz (h (b_k dk + b_t dt) + mu (1 - L) u dE),   dF/dmu = Fz E (1 - L) u,
 * h = mu E / S, dE from dugoff_de_q31 (the caller's, de), and per direction (x with C1 = c1,
 * y with c2)
 *   b_xk = ((1 - L/2) - (1 - L) ux^2) c1 + sgn(k) ux mu E / 4,   b_xt = -(1 - L) ux uy c2,
 *   b_yk = sgn(k) uy mu E / 4 - (1 - L) ux uy c1,               b_yt = ((1 - L/2) - (1 - L) uy^2) c2
 * (from du = (cd - u (u . cd)) / S, cd = (c1 dk, c2 dt), and dw = mu (1 - L) dE
 * + (mu E)^2 / (4 S) sgn(k) dk + mu E L / 2 (u . cd) / S). Only h spans decades (L < 1 gives
 * h < 2 / (1 - |k|), and S >= |c1 k|: up to mu / |c1| for |k| -> 1): one rfe_xf_t quotient.
 * Everything else is plain Q30 in int64 with derived bounds: 1 - L, 1 - L/2, |ux|, |uy| <= 1
 * (Q30 <= 2^30), mu E < 4 (Q59 < 2^61, Q30 < 2^32), |c| < 128 (Q24); each 32 x 32 product
 * < 2^62 rounded to Q30 (2^-31 each): (1 - L) u u within 3 2^-31, times c within 2^-22.4
 * (2^-29.4 of |c|); mu E / 4 u within 2^-30; |b| < 2^8.1 (Q30 < 2^38.1). mu (1 - L) u: Q30
 * < 2^32 within 2^-30. The b enter rfe_xf_t rounded to 30 bits (2^-30 relative); per
 * direction (one loop; tyre_xf_mul, tyre_xf_dot out of line) 7 rfe_xf_t products with the
 * real change d, h, dE and fz, where the former rfe_xf_t chain had about 40 in all. Outputs:
 * df = dF, mf = dF/dmu, f0 = F (paper mode's dF/dmu). */
static void dugoff_jac_lt1_q31(const rfe_dugoff_pre_q31_t *pre, int32_t kq, int32_t c1q,
                               int32_t c2q, int32_t m, int32_t l30, rfe_xf_t de, rfe_xf_t fzx,
                               const rfe_slip_dir_q31_t *d, rfe_xf_t df[2], rfe_xf_t mf[2],
                               rfe_xf_t f0[2])
{
    const int64_t u[2] = {pre->ux, pre->uy};
    const int64_t c[2] = {c1q, c2q};
    const int64_t oml = (int64_t)ONE_Q30 - (int64_t)l30;                 /* 1 - L, (0, 2^30] */
    const int64_t omh = (int64_t)ONE_Q30 - ((int64_t)l30 / 2);           /* 1 - L/2 */
    const int64_t me = (int64_t)m * (int64_t)pre->e;                     /* mu E, Q59 < 2^61 */
    const int64_t me30 = q30_of(me, 29u);                                /* < 2^32 */
    const int64_t ouxy = q30_of(q30_of(oml * u[0], 30u) * u[1], 30u);    /* (1 - L) ux uy */
    const int64_t sk = (int64_t)rfe_q31_sign(kq);
    const int64_t mo = q30_of((int64_t)m * oml, 29u);                   /* mu (1 - L), < 2^32 */
    const int64_t w30 = q30_of(me30 * omh, 30u);                         /* w, Q30 < 2^32 */
    const int64_t eo = q30_of((int64_t)pre->e * oml, 30u);               /* E (1 - L) <= 1 */
    const rfe_xf_t h = rfe_xf_div(rfe_xf_make(me, -59), rfe_xf_of(pre->s, (int)pre->qs));
    size_t i;
    for (i = 0u; i < 2u; ++i) {
        /* direction i: b_k, b_t of the comment above; (1 - L) u_i^2 as (1 - L) u_i, then u_i */
        const int64_t ouii = q30_of(q30_of(oml * u[i], 30u) * u[i], 30u);
        const int64_t diag = q30_of((omh - ouii) * c[i], 24u);
        const int64_t off = q30_of(ouxy * c[1u - i], 24u);
        const int64_t mei = sk * q30_of(me30 * u[i], 32u);               /* sgn(k) u_i mu E / 4 */
        int64_t bk = mei - off;
        int64_t bt = diag;
        rfe_xf_t dd;
        if (i == 0u) {
            bk = diag + mei;
            bt = -off;
        }
        dd = tyre_xf_dot(rfe_xf_make(bk, -30), d->k, rfe_xf_make(bt, -30), d->tan_a);
        df[i] = tyre_xf_mul(fzx, tyre_xf_dot(h, dd, rfe_xf_make(q30_of(mo * u[i], 30u), -30), de));
        mf[i] = tyre_xf_mul(fzx, rfe_xf_make(q30_of(eo * u[i], 30u), -30));
        f0[i] = tyre_xf_mul(fzx, rfe_xf_make(q30_of(w30 * u[i], 30u), -30));
    }
}

/* dugoff_jac_q31 where L >= 1 or S = 0: dF/dmu = 0 and g = 1 / (1 - |k|), dg = sgn(k) dk g^2
 * (L >= 1), or g = 1, dg = 0 at S = 0 (the limit S -> 0, L -> infinity; 0 at m = 0: no force
 * at any slip). Its rfe_xf_t products and sums out of line (tyre_xf_mul, tyre_xf_dot). */
static void dugoff_jac_ge1_q31(const rfe_dugoff_pre_q31_t *pre, int32_t kq, int32_t c1q,
                               int32_t c2q, int32_t m, rfe_xf_t fzx,
                               const rfe_slip_dir_q31_t *d, rfe_xf_t df[2], rfe_xf_t mf[2],
                               rfe_xf_t f0[2])
{
    const int32_t cq[2] = {c1q, c2q};
    const int32_t ktq[2] = {kq, pre->tan_a};
    const int ktf[2] = {30, 26};
    rfe_xf_t dv[2];
    rfe_xf_t g0 = rfe_xf_make((m > 0) ? 1 : 0, 0);
    rfe_xf_t g1 = rfe_xf_make(0, 0);
    size_t i;
    dv[0] = d->k;
    dv[1] = d->tan_a;
    if (pre->s > 0) {
        g0 = rfe_xf_div(rfe_xf_make(1, 0), rfe_xf_of(pre->omk, 30));
        g1 = tyre_xf_mul(xf_signed(rfe_q31_sign(kq), d->k), tyre_xf_mul(g0, g0));
    }
    for (i = 0u; i < 2u; ++i) {
        const rfe_xf_t kt = rfe_xf_of(ktq[i], ktf[i]);
        const rfe_xf_t fc = tyre_xf_mul(fzx, rfe_xf_of(cq[i], (int)RFE_FIX_Q_STIFF));
        f0[i] = tyre_xf_mul(fc, tyre_xf_mul(kt, g0));
        df[i] = tyre_xf_mul(fc, tyre_xf_dot(dv[i], g0, kt, g1));
        mf[i] = rfe_xf_make(0, 0);
    }
}

/* Dugoff forces fz (c1 k, c2 t) g and their derivatives (tyre_flt.c dugoff_jac) at mu = m
 * (Q29, >= 0; paper mode: 1) with l30 = L (dugoff_l30; 1 where S = 0) and, where L < 1, de = dE
 * along d (dugoff_de_q31); f0[0..1]: the forces. L < 1 (S > 0): dugoff_jac_lt1_q31, else
 * dugoff_jac_ge1_q31. Out of line, and L and dE formed by the caller, so their divisions are
 * not on the stack below this frame. */
RFE_XF_OUTLINE static void dugoff_jac_q31(const rfe_dugoff_pre_q31_t *pre, int32_t kq,
                                          int32_t c1q, int32_t c2q, int32_t m, int32_t l30,
                                          rfe_xf_t de, int32_t fz, const rfe_slip_dir_q31_t *d,
                                          rfe_tyre_jac_q31_t *o, rfe_xf_t f0[2])
{
    const rfe_xf_t fzx = rfe_xf_of(fz, 15);
    rfe_xf_t df[2];
    rfe_xf_t mf[2];
    if (l30 < ONE_Q30) {
        dugoff_jac_lt1_q31(pre, kq, c1q, c2q, m, l30, de, fzx, d, df, mf, f0);
    } else {
        dugoff_jac_ge1_q31(pre, kq, c1q, c2q, m, fzx, d, df, mf, f0);
    }
    o->dfx = df[0];
    o->dfy = df[1];
    o->mfx = mf[0];
    o->mfy = mf[1];
}

/* pi/2 in Q55, round(pi/2 2^55). */
#define HALF_PI_Q55 ((int64_t)56593902016227522)

/* Below x = s / (m C) = 2^-MAGIC_SERIES_BITS, m G / s is its series (magic_g_over_s_q31). */
#define MAGIC_SERIES_BITS 8

/* One direction's curve at m > 0, S > 0 (magic_phi_q31): phi (Q55), the pair of its atan2 and
 * G = sin phi (Q30), which the forces and their derivatives share. */
typedef struct {
    int64_t phi;
    magic_pair_q31_t pr;
    int32_t g;
} magic_dir_q31_t;

static void magic_dir_q31(const rfe_dugoff_pre_q31_t *pre, int32_t m, int32_t C, int32_t E,
                          magic_dir_q31_t *dir)
{
    dir->phi = magic_phi_q31(pre->s, (unsigned int)pre->qs, m, C, E, &dir->pr);
    dir->g = rfe_q31_sin_q55(dir->phi);
}

/* cos(C b) d in Q30 (int64) from c30 = cos(C b) (Q30) and d = dn/ds = 1 - E sin^2 a in Q30,
 * (0, 5 2^30], from a (Q31) and E (Q24) (magic_shape_jac_q31 below: the product Q60, |.| <= 5
 * 2^60, rounded to Q30); E = 0 (the preset's curves): d = 1, so c30 itself, without the sine
 * and the product. */
static int64_t magic_cos_dn_q31(int32_t c30, int32_t Eq, uint32_t a)
{
    int64_t cd = c30;
    if (Eq != 0) {
        const int64_t sa = rfe_q31_sin_q55((int64_t)a * rfe_q31_pow2(24u));
        const int64_t sa2 = rfe_fix_shr64_round(sa * sa, 30u);
        const int64_t d = (int64_t)ONE_Q30 - rfe_fix_shr64_round((int64_t)Eq * sa2, 24u);
        cd = rfe_fix_shr64_round((int64_t)c30 * d, 30u);
    }
    return cd;
}

/* round(v 2^e / dh) (half up) where the quotient is below 2^32 (rfe_q31_udiv64_32's domain)
 * and, for e >= 0, v 2^e + dh / 2 < 2^64 (the left shift exact); for e < 0, v is rounded by -e
 * bits first (1/2 unit). Its callers: magic_shape_jac_q31's cos^2 b and w (dh in [2^30, 2^31),
 * v 2^e / dh < 2^31, so v 2^e < 2^62; the first rounding 2^-31 of the quotient's unit) and
 * magic_g_over_s_q31's m G / S (dh = S): one copy of the rounded division for the three. */
RFE_XF_OUTLINE static uint32_t magic_ratio_q31(uint64_t v, int e, uint32_t dh)
{
    uint64_t n;
    if (e >= 0) {
        n = v << (unsigned int)e;
    } else {
        n = rfe_q31_ushr64_round(v, (unsigned int)(-e));
    }
    return rfe_q31_udiv64_32(n + (uint64_t)(dh >> 1), dh);
}

/* m G / s of one direction (S > 0, m > 0) in Q30, in [0, 5 2^30] (m G / s = sin(C b) / (C x)
 * with x = s / (m C): sin(C b) <= C b and b <= atan((1 + |E|) x) <= 5 x). G (Q30) holds 30 bits
 * of its value only where it is not small, so below x = 2^-MAGIC_SERIES_BITS (read from the
 * atan2's pair: yn 2^8 < xn; either side of the line is accurate) the series
 * m G / s = 1 - c2 x^2, c2 = (1 + E) / 3 + C^2 / 6 (atan and sin to third order: relative error
 * < x^4 < 2.4e-10) replaces the quotient (G >= C x / 2 > 2^-9 above it: 2^-21 relative, and
 * better as x grows).
 *   Series: x = yn / xn in Q38 (xn >= 2^29 there, yn within 1/2: x within 2^-30 + 2^-30 x),
 *   rounded (q2 = yn 2^39 / xn < 2^31); x^2 to Q46 (<= 2^30, 2^-47); 6 c2 = 2 (1 + E) + C^2
 *   in Q24 (C^2 rounded from Q48, 2^-25; |.| <= 8 2^24); 6 c2 x^2 (Q70, < 2^57) to Q30
 *   (< 2^17, int32), divided by 6 (truncated, < 2^-30). Error <= 2 x (2^-30) 1.4 + 3 2^-30 <
 *   4 2^-30 plus the series' x^4.
 *   Quotient: m G (Q29 x Q30 = Q59, exact, < 2^61) over S (Q(qs)) is the value in Q29:
 *   n = m G 2^(qs - 30) (exact for qs >= 30: n = q S < 5.1 2^29 2^31 < 2^63; for qs < 30 S
 *   >= 2^29 and n is m G rounded by 30 - qs bits, <= 1/2 unit: 2^-30 LSB29 of the quotient),
 *   rounded, q < 5.1 2^29 < 2^32 (rfe_q31_udiv64_32's domain); in Q30 2 q, within 2^-30. */
static int64_t magic_g_over_s_q31(const rfe_dugoff_pre_q31_t *pre, int32_t m, int32_t Cq,
                                  int32_t Eq, const magic_dir_q31_t *dir)
{
    int64_t r;
    if (((int64_t)dir->pr.yn * rfe_q31_pow2((unsigned int)MAGIC_SERIES_BITS)) <
        (int64_t)dir->pr.xn) {
        const int64_t x = (int64_t)rfe_q31_div_round_mag((uint32_t)dir->pr.yn,
                                                         (uint32_t)dir->pr.xn, 38u);
        const int64_t x2 = rfe_fix_shr64_round(x * x, 30u);
        const int64_t cc = rfe_fix_shr64_round((int64_t)Cq * (int64_t)Cq, 24u);
        const int64_t c6 = (2 * ((int64_t)RFE_FIX_ONE(RFE_FIX_Q_STIFF) + (int64_t)Eq)) + cc;
        const int32_t t = (int32_t)rfe_fix_shr64_round(c6 * x2, 40u);
        const int32_t t6 = t / 6;
        r = (int64_t)ONE_Q30 - (int64_t)t6;
    } else {
        /* n = m G 2^(qs - 30) rounded over S, as above */
        const uint64_t mg = (uint64_t)rfe_fix_mul32x32(m, dir->g);
        r = 2 * (int64_t)magic_ratio_q31(mg, (int)pre->qs - 30, (uint32_t)pre->s);
    }
    return r;
}

/* The bits W of w = s p / (p^2 + n^2)'s bound 2^W for the curvature E (Q24, E < 1): w <= 1/2
 * for E <= 0 (n >= s there: E (s - p a) <= 0, a <= s / p) and w <= 1 / (2 (1 - E)) for E > 0
 * (n >= (1 - E) s; p^2 + n^2 >= 2 p n); with t = 1 - E in Q24 (>= 1), W = 0 where t >= 2^23,
 * else 24 - bitlen(t) (2^(W + 1) t >= 2^24, so 1 / (2 (1 - E)) <= 2^W; W <= 23). */
static unsigned int magic_w_bits(int32_t Eq)
{
    const int32_t tq = RFE_FIX_ONE(RFE_FIX_Q_STIFF) - Eq; /* (0, 5 2^24] */
    const uint32_t t = (uint32_t)tq;
    unsigned int w = 0u;
    if (t < ((uint32_t)1 << 23)) {
        w = 24u - rfe_q31_bitlen32(t);
    }
    return w;
}

/* m dG/ds and G - s dG/ds of one direction in Q30 (int64), S > 0, m > 0 (tyre_flt.c
 * magic_shape_jac's dG/ds, written in the curve's angles). With p = m C, n = s - E (s - p a),
 * tan a = s / p, tan b = n / p:
 *   dn/ds = 1 - E + E p^2 / (p^2 + s^2) = 1 - E sin^2 a = d,   db/ds = cos^2 b d / p,
 *   m dG/ds = m cos(C b) C db/ds = cos(C b) d cos^2 b            (|.| <= 5: d in (0, 5]),
 *   s dG/ds = C cos(C b) d w,   w = s p / (p^2 + n^2) (= tan a cos^2 b, <= 2^W: magic_w_bits).
 * In integers:
 *   sin a: rfe_q31_sin_q55 of a (Q31 to Q55, in [0, pi/2]), Q30; sin^2 a Q30; E sin^2 a (Q24 x
 *   Q30, |.| <= 2^56) rounded to Q30, d = 1 - E sin^2 a in Q30, (0, 5 2^30] (int64);
 *   cos(C b) d: Q60, |.| <= 5 2^60 < 2^63, rounded to Q30 (cd; E = 0: cos(C b) itself,
 *   magic_cos_dn_q31);
 *   cos^2 b and w from the pair (p = xn, s = yn, n = z / 2^24 in its units): x24 = xn 2^24
 *   (<= 2^54) and z (< 2^58, >= 0) brought to <= 2^30 by one shift sh (the larger of xs, zs >=
 *   2^29: xn or yn >= 2^29 and z >= (1 - E) yn 2^24 with 1 - E >= 2^-24; all non-negative, so
 *   the unsigned rounding shift and 32 x 32 products), D = xs^2 + zs^2 in
 *   [2^58, 2^61] exact, p^2 + n^2 = D 2^(2 sh - 48) to 2^-29 relative (the two roundings); D
 *   truncated to 31 bits, dh = D / 2^k (k in [28, 31], 2^-30 relative), and with the exact
 *   numerators (<= 2^60) cos^2 b = xn^2 2^(78 - 2 sh - k) / dh in Q30 and w = yn xn 2^(78 - 2
 *   sh - k - W) / dh in Q(30 - W), each one rounded division (magic_ratio_q31; quotients <=
 *   2^30 (1 + 2^-27));
 *   m dG/ds = cd cos^2 b (Q60, < 5 2^60) rounded to Q30;
 *   s dG/ds = (C cd: Q54, < 2^58) w rounded to Q30 (rfe_q31_mul64x32, shift 54 - W in [31,
 *   54], result < 10 2^23 2^30 < 2^57), G - s dG/ds in Q30 (int64).
 * Error: sin a within 6.2e-10 (rfe_q31_sin_q55) and cos(C b) within 6.2e-10, the roundings to
 * Q30 (2^-31 each, times |E| <= 4 and d <= 5); cos^2 b within 2^-29 (p^2 + n^2) + 2^-30 (dh)
 * + 2^-31 (the division) < 2^-28, so m dG/ds within 5 (2 6.2e-10 + 4 2^-31) + 5 2^-31 + 5
 * 2^-28 + 2^-31 < 2.6e-8, and s dG/ds within C w (the same) plus 2^-31 < 5.2e-8 w + 2^-31,
 * absolute, at the computed angles (the angles' own errors move the derivative as they move
 * the forces, test_tyre_internal_q31.c's bound). */
static void magic_shape_jac_q31(const magic_dir_q31_t *dir, int32_t Cq, int32_t Eq,
                                int64_t *m_gs, int64_t *gms)
{
    const int64_t phi = dir->phi;
    const int32_t c30 = (phi <= HALF_PI_Q55) ? rfe_q31_sin_q55(HALF_PI_Q55 - phi)
                                             : -rfe_q31_sin_q55(phi - HALF_PI_Q55);
    const int64_t cd = magic_cos_dn_q31(c30, Eq, dir->pr.a);
    const uint32_t xn = (uint32_t)dir->pr.xn;
    const uint64_t x24 = (uint64_t)xn << 24;
    const uint64_t z = (uint64_t)dir->pr.z;
    const unsigned int sh = rfe_q31_norm_shift((z > x24) ? z : x24, 30u);
    const uint32_t xs = (uint32_t)rfe_q31_ushr64_round(x24, sh);
    const uint32_t zs = (uint32_t)rfe_q31_ushr64_round(z, sh);
    const uint64_t dd = rfe_fix_umul32x32(xs, xs) + rfe_fix_umul32x32(zs, zs);
    const unsigned int k = rfe_q31_bitlen64(dd) - 31u;
    const uint32_t dh = (uint32_t)(dd >> k);
    const unsigned int wb = magic_w_bits(Eq);
    const int e = 78 - ((2 * (int)sh) + (int)k);
    const int64_t cb2 = (int64_t)magic_ratio_q31(rfe_fix_umul32x32(xn, xn), e, dh);
    const int64_t w =
        (int64_t)magic_ratio_q31(rfe_fix_umul32x32((uint32_t)dir->pr.yn, xn), e - (int)wb, dh);
    *m_gs = rfe_fix_shr64_round(cd * cb2, 30u);
    *gms = (int64_t)dir->g - rfe_q31_mul64x32((int64_t)Cq * cd, w, 54u - wb);
}

/* One direction's bounded factors (Q30, int64): m G / s in [0, 5 2^30], m dG/ds in [-5 2^30,
 * 5 2^30] and G - s dG/ds (|.| < 2^57). */
typedef struct {
    int64_t gos;
    int64_t gs;
    int64_t gms;
} magic_terms_q31_t;

/* fz (p1 c1 + p2 c2) in rfe_xf_t for fz (Q15, >= 0) and p1, p2 in Q28 (int32, |.| <= 5 2^28
 * (1 + 2^-20)): fz p exact (Q43, < 2^62), the two products and the sum rounded once each
 * (2^-30 relative, the sum 2^-29 of the larger term). */
static rfe_xf_t magic_lin_q31(int32_t fz, int32_t p1, rfe_xf_t c1, int32_t p2, rfe_xf_t c2)
{
    const int64_t a = rfe_fix_mul32x32(fz, p1);
    const int64_t b = rfe_fix_mul32x32(fz, p2);
    return rfe_xf_add(rfe_xf_mul(rfe_xf_make(a, -43), c1), rfe_xf_mul(rfe_xf_make(b, -43), c2));
}

/* Both directions' dF and dF/dmu (S > 0, m > 0) from their factors tx, ty (Q30). With
 * ds = ux cdk + uy cdt (cdk = cx dk, cdt = cy dt), one direction's
 *   dF = fz ((m G / s) cd + (m G_s - m G / s) u ds),   dF/dmu = fz u (G - s G_s),
 * so with dx = m G_s - m G / s of x and dy of y (|.| <= 10):
 *   dFx = fz ((gos_x + dx ux^2) cdk + dx ux uy cdt),  dFy = fz (dy ux uy cdk + (gos_y + dy uy^2) cdt),
 * the four coefficients in Q28 (int32) from 32 x 32 products: ux^2, ux uy, uy^2 rounded to Q30
 * (2^-31 each, <= 2^30), d rounded to Q27 (2^-28, |.| < 2^30.4), gos to Q28 (2^-29), d u^2
 * (Q57, < 2^61) rounded to Q28 (2^-29): within 10 2^-31 + 2^-28 + 2^-28 of the exact
 * combination of the Q30 factors. Each coefficient is a convex combination of gos and gs
 * (|.| <= 5) or dx ux uy (|ux uy| <= 1/2 + 2^-30): |.| <= 5 (1 + 2^-20) < 2^31 / 2^28,
 * magic_lin_q31's domain. fz u (Q45, < 2^61) and G - s G_s (Q30) enter rfe_xf_t exactly or
 * rounded to 30 bits, and one product. Where the set-up held the factors and the change ds in
 * rfe_xf_t before: no reciprocal of S, two products instead of ten per direction. The
 * coefficients and dF/dmu do not depend on the change: formed once for the n changes
 * (cdk, cdt) = (cd[2 b], cd[2 b + 1]) of o[b] (the input derivative's two; the observer's one). */
static void magic_dfs_q31(const rfe_dugoff_pre_q31_t *pre, int32_t fz, const rfe_xf_t *cd,
                          size_t n, const magic_terms_q31_t *tx, const magic_terms_q31_t *ty,
                          rfe_tyre_jac_q31_t *o)
{
    const int64_t ux = pre->ux;
    const int64_t uy = pre->uy;
    /* every factor below fits int32 (the bounds above), so each product is one 32 x 32 */
    const int32_t uxx = (int32_t)rfe_fix_shr64_round(rfe_fix_mul_m31(ux, ux), 30u);
    const int32_t uxy = (int32_t)rfe_fix_shr64_round(rfe_fix_mul_m31(ux, uy), 30u);
    const int32_t uyy = (int32_t)rfe_fix_shr64_round(rfe_fix_mul_m31(uy, uy), 30u);
    const int32_t dx = (int32_t)rfe_fix_shr64_round(tx->gs - tx->gos, 3u);
    const int32_t dy = (int32_t)rfe_fix_shr64_round(ty->gs - ty->gos, 3u);
    const int32_t gx = (int32_t)rfe_fix_shr64_round(tx->gos, 2u);
    const int32_t gy = (int32_t)rfe_fix_shr64_round(ty->gos, 2u);
    const int32_t pxk = gx + (int32_t)rfe_fix_shr64_round(rfe_fix_mul32x32(dx, uxx), 29u);
    const int32_t pxt = (int32_t)rfe_fix_shr64_round(rfe_fix_mul32x32(dx, uxy), 29u);
    const int32_t pyk = (int32_t)rfe_fix_shr64_round(rfe_fix_mul32x32(dy, uxy), 29u);
    const int32_t pyt = gy + (int32_t)rfe_fix_shr64_round(rfe_fix_mul32x32(dy, uyy), 29u);
    const rfe_xf_t mfx = rfe_xf_mul(rfe_xf_make(rfe_fix_mul_m31(fz, ux), -45), rfe_xf_make(tx->gms, -30));
    const rfe_xf_t mfy = rfe_xf_mul(rfe_xf_make(rfe_fix_mul_m31(fz, uy), -45), rfe_xf_make(ty->gms, -30));
    size_t b;
    for (b = 0u; b < n; ++b) {
        o[b].dfx = magic_lin_q31(fz, pxk, cd[2u * b], pxt, cd[(2u * b) + 1u]);
        o[b].dfy = magic_lin_q31(fz, pyk, cd[2u * b], pyt, cd[(2u * b) + 1u]);
        o[b].mfx = mfx;
        o[b].mfy = mfy;
    }
}

/* One direction's factors (S > 0, m > 0). */
static void magic_terms_q31(const rfe_dugoff_pre_q31_t *pre, int32_t m, int32_t Cq, int32_t Eq,
                            const magic_dir_q31_t *dir, magic_terms_q31_t *t)
{
    t->gos = magic_g_over_s_q31(pre, m, Cq, Eq, dir);
    magic_shape_jac_q31(dir, Cq, Eq, &t->gs, &t->gms);
}

/* Magic Formula forces' derivatives (tyre_flt.c magic_jac) at m = max(mu, 0) (Q29) along the
 * n slip changes (cx dk, cy dt) = (cd[2 b], cd[2 b + 1]) of o[b]: m = 0: all 0; S = 0: dF = fz (cx dk, cy dt)
 * (the limit fz m G_s(0) = fz), dF/dmu = 0; else each direction's factors and magic_dfs_q31's
 * coefficients, formed once for all n changes, and its two sums per change. */
static void magic_jac_q31(const rfe_dugoff_pre_q31_t *pre, int32_t m, int32_t fz,
                          const rfe_tyre_params_q31_t *tp, const rfe_xf_t *cd, size_t n,
                          const magic_dir_q31_t dir[2], rfe_tyre_jac_q31_t *o)
{
    if ((m > 0) && (pre->s != 0)) {
        magic_terms_q31_t tx;
        magic_terms_q31_t ty;
        magic_terms_q31(pre, m, tp->shape_Cx, tp->shape_Ex, &dir[0], &tx);
        magic_terms_q31(pre, m, tp->shape_Cy, tp->shape_Ey, &dir[1], &ty);
        magic_dfs_q31(pre, fz, cd, n, &tx, &ty, o);
    } else {
        const rfe_xf_t zero = rfe_xf_make(0, 0);
        const rfe_xf_t fzx = rfe_xf_of(fz, 15);
        size_t b;
        for (b = 0u; b < n; ++b) {
            o[b].dfx = zero;
            o[b].dfy = zero;
            o[b].mfx = zero;
            o[b].mfy = zero;
            if (m > 0) {
                /* S = 0 (no slip): out of line (tyre_xf_mul), off the curve's path */
                o[b].dfx = tyre_xf_mul(fzx, cd[2u * b]);
                o[b].dfy = tyre_xf_mul(fzx, cd[(2u * b) + 1u]);
            }
        }
    }
}

/* (cx dk, cy dt) of the slip change d (magic_jac_q31's cd). */
static void magic_cd_q31(const rfe_tyre_params_q31_t *tp, const rfe_slip_dir_q31_t *d,
                         rfe_xf_t cd[2])
{
    cd[0] = rfe_xf_mul(rfe_xf_of(tp->cx, (int)RFE_FIX_Q_STIFF), d->k);
    cd[1] = rfe_xf_mul(rfe_xf_of(tp->cy, (int)RFE_FIX_Q_STIFF), d->tan_a);
}

/* Both directions' curves at m (Q29, >= 0), where the forces and derivatives use them (S > 0,
 * m > 0); else zeros, unused. */
static void magic_dirs_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                           int32_t m, magic_dir_q31_t dir[2])
{
    if ((pre->s != 0) && (m > 0)) {
        magic_dir_q31(pre, m, tp->shape_Cx, tp->shape_Ex, &dir[0]);
        magic_dir_q31(pre, m, tp->shape_Cy, tp->shape_Ey, &dir[1]);
    } else {
        size_t k;
        /* field by field: a struct copy of zeros is a memset call on the Cortex-M */
        for (k = 0u; k < 2u; ++k) {
            dir[k].phi = 0;
            dir[k].pr.z = 0;
            dir[k].pr.xn = 0;
            dir[k].pr.yn = 0;
            dir[k].pr.a = 0u;
            dir[k].g = 0;
        }
    }
}

/* magic_forces_q31 with its two sines from dir (the curves at m = max(mu, 0)). */
static void magic_dir_forces_q31(const rfe_dugoff_pre_q31_t *pre, int32_t m, rfe_fix_t fz,
                                 const magic_dir_q31_t dir[2], rfe_fix_t *fx, rfe_fix_t *fy,
                                 uint32_t *sat)
{
    *fx = 0;
    *fy = 0;
    if ((pre->s != 0) && (m != 0)) {
        const int64_t px = rfe_fix_mul32x32(m, dir[0].g);
        const int64_t py = rfe_fix_mul32x32(m, dir[1].g);
        const uint64_t wx = ((uint64_t)px + HALF_Q30) >> 30;
        const uint64_t wy = ((uint64_t)py + HALF_Q30) >> 30;
        *fx = rfe_fix_sat32(rfe_q31_mul64x32(rfe_fix_mul_m31(fz, (int64_t)wx), pre->ux, 59u), sat);
        *fy = rfe_fix_sat32(rfe_q31_mul64x32(rfe_fix_mul_m31(fz, (int64_t)wy), pre->uy, 59u), sat);
    }
}

void rfe_tyre_magic_pre_jac_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                                rfe_fix_t fz, rfe_fix_t mu, const rfe_slip_dir_q31_t *d,
                                rfe_fix_t *fx, rfe_fix_t *fy, uint32_t *sat,
                                rfe_tyre_jac_q31_t *out)
{
    const int32_t m = (mu > 0) ? mu : 0;
    magic_dir_q31_t dir[2];
    rfe_xf_t cd[2];
    magic_dirs_q31(tp, pre, m, dir);
    magic_dir_forces_q31(pre, m, fz, dir, fx, fy, sat);
    magic_cd_q31(tp, d, cd);
    magic_jac_q31(pre, m, fz, tp, cd, 1u, dir, out);
}

void rfe_tyre_magic_basis_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                              rfe_fix_t fz, rfe_fix_t mu, rfe_fix_t *fx, rfe_fix_t *fy,
                              uint32_t *sat, rfe_tyre_jac_q31_t out[2])
{
    const int32_t m = (mu > 0) ? mu : 0;
    const rfe_xf_t zero = rfe_xf_make(0, 0);
    magic_dir_q31_t dir[2];
    rfe_xf_t cd[4];
    /* unit d kappa: (cx, 0); unit d tan(alpha): (0, cy), as magic_cd_q31 forms them (a
     * product by 1 is exact in rfe_xf_t, by 0 is 0) */
    cd[0] = rfe_xf_of(tp->cx, (int)RFE_FIX_Q_STIFF);
    cd[1] = zero;
    cd[2] = zero;
    cd[3] = rfe_xf_of(tp->cy, (int)RFE_FIX_Q_STIFF);
    magic_dirs_q31(tp, pre, m, dir);
    magic_dir_forces_q31(pre, m, fz, dir, fx, fy, sat);
    magic_jac_q31(pre, m, fz, tp, cd, 2u, dir, out);
}

void rfe_tyre_dugoff_pre_jac_q31(const rfe_tyre_params_q31_t *tp,
                                 const rfe_dugoff_pre_q31_t *pre, rfe_fix_t kappa,
                                 rfe_fix_t vwx, rfe_fix_t fz, rfe_fix_t mu,
                                 const rfe_slip_dir_q31_t *d, rfe_tyre_jac_q31_t *out)
{
    const int32_t k = rfe_fix_clamp(kappa, -ONE_Q30, ONE_Q30);
    /* paper mode: F = mu F0, F0 at mu = 1 with the normalised stiffnesses; the others at
     * max(mu, 0) (mu < 0 is evaluated at 0, MODEL.md §4, where nothing depends on mu) */
    const int32_t mpos = (mu > 0) ? mu : 0;
    const int32_t m = (tp->mode == RFE_TYRE_PAPER) ? RFE_FIX_ONE(RFE_FIX_Q_MU) : mpos;
    const int32_t c1 = (tp->mode == RFE_TYRE_PAPER) ? tp->Cx_n : tp->cx;
    const int32_t c2 = (tp->mode == RFE_TYRE_PAPER) ? tp->Cy_n : tp->cy;
    /* L and dE here, not in dugoff_jac_q31: their divisions' stack sits below this small
     * frame (dE only where L < 1, its only use) */
    const int32_t l30 = (pre->s > 0) ? dugoff_l30(pre, m) : ONE_Q30;
    const rfe_xf_t de =
        (l30 < ONE_Q30) ? dugoff_de_q31(pre, k, tp->eps, vwx, d) : rfe_xf_make(0, 0);
    rfe_xf_t f0[2];
    dugoff_jac_q31(pre, k, c1, c2, m, l30, de, fz, d, out, f0);
    if (tp->mode == RFE_TYRE_PAPER) {
        /* dF = mu dF0, dF/dmu = F0 */
        const rfe_xf_t mux = rfe_xf_of(mu, (int)RFE_FIX_Q_MU);
        out->dfx = rfe_xf_mul(mux, out->dfx);
        out->dfy = rfe_xf_mul(mux, out->dfy);
        out->mfx = f0[0];
        out->mfy = f0[1];
    } else if (m == 0) {
        out->mfx = rfe_xf_make(0, 0);
        out->mfy = rfe_xf_make(0, 0);
    } else {
        /* dF/dmu from dugoff_jac_q31 */
    }
}

void rfe_tyre_pre_jac_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                          rfe_fix_t kappa, rfe_fix_t vwx, rfe_fix_t fz, rfe_fix_t mu,
                          const rfe_slip_dir_q31_t *d, rfe_tyre_jac_q31_t *out)
{
    if (tp->mode == RFE_TYRE_MAGIC) {
        /* rfe_tyre_magic_pre_jac_q31's derivatives (the same calls), its forces unused: out of
         * line, its frame is not on the Dugoff path's stack */
        rfe_fix_t fx = 0;
        rfe_fix_t fy = 0;
        uint32_t scratch = 0u;
        rfe_tyre_magic_pre_jac_q31(tp, pre, fz, mu, d, &fx, &fy, &scratch, out);
    } else {
        rfe_tyre_dugoff_pre_jac_q31(tp, pre, kappa, vwx, fz, mu, d, out);
    }
}
