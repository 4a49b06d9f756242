/**
 * @file trig_f32.h
 * @brief The float32 build's atan2, sine, cosine and tangent (private, not installed).
 *
 * numerics/internal.h maps RFE_ATAN2, RFE_SIN, RFE_COS and RFE_TAN to these in the float32
 * build; the double build keeps libm's, the reference's twin to 1e-9. Each is a polynomial of
 * its own after a reduction, cheaper on a Cortex-M4F than newlib's single-precision functions
 * (whose sinf, cosf and tanf reduce through __ieee754_rem_pio2f) at float32's precision:
 * BENCHMARKS.md "What was made faster". An argument the reduction does not cover (infinite,
 * NaN, or beyond the range stated below) goes to libm's function.
 */
#ifndef RFE_TRIG_F32_H
#define RFE_TRIG_F32_H

#include <float.h>
#include <math.h>
#include <stdint.h>

/*
 * atan2 of the float32 build.
 * Reduced to the first octant, t = min(|x|, |y|) / max(|x|, |y|) in [0, 1] (one rounding),
 * atan t = t P(t^2) with the 9 coefficients of scripts/tools/atan_minimax.py (a minimax fit of
 * the relative error, 1.4e-8 in exact arithmetic), then pi/2 - a above the diagonal, pi - a for
 * x < 0 and the sign of y. Measured in float32 against double atan2 (test_atan2_flt.c, which
 * states the bound 4.0e-7 rad, and 3.0e-7 relative below the diagonal for x > 0): newlib's
 * atan2f is within about 2.4e-7 rad, at about 85 instructions on the Cortex-M4F against ~40
 * here. Signed zeros are not distinguished (atan2(-0, x < 0) is +pi); an infinite or NaN
 * input goes to libm's atan2f.
 */
static inline float rfe_atan2_f32(float y, float x)
{
    const float ax = fabsf(x);
    const float ay = fabsf(y);
    const float hi = (ay > ax) ? ay : ax;
    const float lo = (ay > ax) ? ax : ay;
    float a = 0.0f;
    if (!(hi <= FLT_MAX)) {
        return atan2f(y, x);
    }
    if (hi > 0.0f) {
        /* Horner written out (no loop, no table: the constants sit in the literal pool) */
        const float t = lo / hi;
        const float t2 = t * t;
        float p = (0.002903596730902791f * t2) - 0.016283195465803146f;
        p = (p * t2) + 0.04303969442844391f;
        p = (p * t2) - 0.07533705979585648f;
        p = (p * t2) + 0.10654693096876144f;
        p = (p * t2) - 0.14207138121128082f;
        p = (p * t2) + 0.19993054866790771f;
        p = (p * t2) - 0.3333309292793274f;
        a = ((p * t2) * t) + t; /* t P(t^2) with the leading coefficient 1 */
    }
    if (ay > ax) {
        a = 1.57079637f - a; /* above the diagonal; pi/2 rounded to float */
    }
    if (x < 0.0f) {
        a = 3.14159274f - a; /* pi rounded to float */
    }
    return (y < 0.0f) ? -a : a;
}

/*
 * The sine, cosine and tangent share one reduction: k = x 2/pi rounded half away from 0,
 * r = (x - k P1) - k P2 in [-pi/4, pi/4] (to a rounding of x 2/pi), P1 + P2 = pi/2 to 1.7e-13
 * with P1 = 0x3fc90f80 (17 significant bits, so k P1 is exact for |k| <= 127 and x - k P1 is
 * exact by Sterbenz's lemma), the quadrant k mod 4. For |x| <= RFE_TRIG_F32_MAX (|k| <= 127)
 * r is within 2^-24 |r| (its rounding) + 1.1e-10 of x - k pi/2 (127 times the split's 1.7e-13,
 * and the rounding of k P2: 2^-24 of 1.4e-3); beyond it, or not finite, the caller takes libm's
 * function. On r the polynomials of scripts/tools/sincos_minimax.py: sin r = r + r z S(z),
 * cos r = 1 + z C(z), z = r^2, minimax for the relative error (3.8e-9 and 6.4e-11 in exact
 * arithmetic). The bounds against double sin, cos and tan are test_trig_flt.c's.
 */
#define RFE_TRIG_F32_MAX 199.0f /* 127 pi/2 = 199.49: |k| <= 127 */
/* Below it (a float just under pi/4) r = x without the reduction's arithmetic (k = 0): most
 * callers' angles are small (slip angles, steering, the Magic Formula's C atan at moderate
 * slip), where newlib's functions take a short path too. */
#define RFE_TRIG_F32_QUARTER 0.785398f

/* k (|k| <= 127) and r of |x| <= RFE_TRIG_F32_MAX, as described above. */
static inline float rfe_trig_reduce_f32(float x, int32_t *k)
{
    const float kf = (x * 0.636619772f) + ((x < 0.0f) ? -0.5f : 0.5f); /* 2/pi */
    const int32_t kk = (int32_t)kf;                                      /* toward 0 */
    const float kr = (float)kk;
    *k = kk;
    return (x - (kr * 1.57078552f)) - (kr * 1.08043341e-05f); /* P1, P2 */
}

/* sin r and cos r, |r| <= pi/4 (plus a rounding), Horner written out. */
static inline float rfe_sin_poly_f32(float r)
{
    const float z = r * r;
    float p = (-0.000195152825f * z) + 0.00833216030f;
    p = (p * z) - 0.166666552f;
    return ((r * z) * p) + r;
}

static inline float rfe_cos_poly_f32(float r)
{
    const float z = r * r;
    float p = (2.43835675e-05f * z) - 0.00138866820f;
    p = (p * z) + 0.0416666195f;
    p = (p * z) - 0.5f;
    return (z * p) + 1.0f;
}

/* sin(r + q pi/2), q in 0..3: sin r, cos r, -sin r, -cos r. */
static inline float rfe_sin_quadrant_f32(float r, uint32_t q)
{
    const float v = ((q & 1u) == 0u) ? rfe_sin_poly_f32(r) : rfe_cos_poly_f32(r);
    return ((q & 2u) == 0u) ? v : -v;
}

/* sin x = sin(r + k pi/2). */
static inline float rfe_sin_f32(float x)
{
    int32_t k = 0;
    float r;
    if (fabsf(x) < RFE_TRIG_F32_QUARTER) {
        return rfe_sin_poly_f32(x);
    }
    if (!(fabsf(x) <= RFE_TRIG_F32_MAX)) {
        return sinf(x);
    }
    r = rfe_trig_reduce_f32(x, &k);
    return rfe_sin_quadrant_f32(r, (uint32_t)k & 3u);
}

/* cos x = sin(r + (k + 1) pi/2). */
static inline float rfe_cos_f32(float x)
{
    int32_t k = 0;
    float r;
    if (fabsf(x) < RFE_TRIG_F32_QUARTER) {
        return rfe_cos_poly_f32(x);
    }
    if (!(fabsf(x) <= RFE_TRIG_F32_MAX)) {
        return cosf(x);
    }
    r = rfe_trig_reduce_f32(x, &k);
    return rfe_sin_quadrant_f32(r, ((uint32_t)k + 1u) & 3u);
}

/* tan x = sin r / cos r for k even, -cos r / sin r for k odd (r = 0 with k odd is x = k pi/2
 * exactly, which no float is: |r| >= 1.2e-8 there). */
static inline float rfe_tan_f32(float x)
{
    int32_t k = 0;
    float r;
    float s;
    float c;
    float t;
    if (fabsf(x) < RFE_TRIG_F32_QUARTER) {
        return rfe_sin_poly_f32(x) / rfe_cos_poly_f32(x);
    }
    if (!(fabsf(x) <= RFE_TRIG_F32_MAX)) {
        return tanf(x);
    }
    r = rfe_trig_reduce_f32(x, &k);
    s = rfe_sin_poly_f32(r);
    c = rfe_cos_poly_f32(r);
    if (((uint32_t)k & 1u) == 0u) {
        t = s / c;
    } else {
        t = -(c / s); /* the same value as (-c) / s: IEEE division is sign-symmetric */
    }
    return t;
}

#endif /* RFE_TRIG_F32_H */
