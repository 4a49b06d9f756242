/**
 * @file internal.h
 * @brief Private helpers shared by the floating-point library sources (not installed).
 *
 * Literals and libm calls go through these macros so that the float32 build never
 * promotes to double (-Wdouble-promotion) and the double build never truncates.
 */
#ifndef RFE_INTERNAL_H
#define RFE_INTERNAL_H

#include <float.h>
#include <math.h>

#include "rfe/config.h"
#include "rfe/types.h"

#include "numerics/sizes.h" /* RFE_TRIA_COLS_SZ */

/** A literal in the build's real type. */
#define RFE_R(x) ((rfe_real_t)(x))

/*
 * atan2 of the float32 build (the double build keeps libm's, the reference's twin to 1e-9).
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

#if defined(RFE_REAL_DOUBLE)
#define RFE_SQRT(x) sqrt(x)
#define RFE_FABS(x) fabs(x)
#define RFE_ATAN2(y, x) atan2((y), (x))
#define RFE_SIN(x) sin(x)
#define RFE_COS(x) cos(x)
#define RFE_TAN(x) tan(x)
#define RFE_FREXP(x, e) frexp((x), (e))
#define RFE_LDEXP(x, e) ldexp((x), (e))
#define RFE_LOG(x) log(x)
#define RFE_EXP(x) exp(x)
#define RFE_ERFC(x) erfc(x)
#define RFE_CEIL(x) ceil(x)
#define RFE_ATAN(x) atan(x)
#define RFE_POW(x, y) pow((x), (y))
#else
#define RFE_SQRT(x) sqrtf(x)
#define RFE_FABS(x) fabsf(x)
#define RFE_ATAN2(y, x) rfe_atan2_f32((y), (x))
#define RFE_SIN(x) sinf(x)
#define RFE_COS(x) cosf(x)
#define RFE_TAN(x) tanf(x)
#define RFE_FREXP(x, e) frexpf((x), (e))
#define RFE_LDEXP(x, e) ldexpf((x), (e))
#define RFE_LOG(x) logf(x)
#define RFE_EXP(x) expf(x)
#define RFE_ERFC(x) erfcf(x)
#define RFE_CEIL(x) ceilf(x)
#define RFE_ATAN(x) atanf(x)
#define RFE_POW(x, y) powf((x), (y))
#endif

/** Magic words marking an initialised state struct (guards use before init). */
#define RFE_MAGIC_SCKF 0x53434B46u /* "SCKF" */
#define RFE_MAGIC_CKF 0x434B4620u  /* "CKF " */
#define RFE_MAGIC_EST 0x45535431u  /* "EST1" */
#define RFE_MAGIC_COND 0x434F4E44u /* "COND" */
#define RFE_MAGIC_VEL 0x56454C31u  /* "VEL1" */
#define RFE_MAGIC_MON 0x4D4F4E31u  /* "MON1" */
#define RFE_MAGIC_TID 0x54494431u  /* "TID1" */
#define RFE_MAGIC_MG 0x4D475231u   /* "MGR1" */

/** True when x is neither NaN nor infinite. */
static inline int rfe_is_finite(rfe_real_t x) { return isfinite(x) ? 1 : 0; }

/* A 0/1 parameter (a flag carried as a real in the parameter structs) is set. */
static inline int rfe_flag_on(rfe_real_t f) { return (f != RFE_R(0.0)) ? 1 : 0; }

/** True when all k values are finite. */
static inline int rfe_all_finite(const rfe_real_t *v, size_t k)
{
    size_t i;
    for (i = 0u; i < k; ++i) {
        if (!isfinite(v[i])) {
            return 0;
        }
    }
    return 1;
}

/** True when the lower triangle of the k x k matrix M (row stride ld) is finite. */
static inline int rfe_lower_finite(const rfe_real_t *M, size_t k, size_t ld)
{
    size_t i;
    for (i = 0u; i < k; ++i) {
        if (!rfe_all_finite(&M[i * ld], i + 1u)) {
            return 0;
        }
    }
    return 1;
}

static inline rfe_real_t rfe_max(rfe_real_t a, rfe_real_t b) { return (a > b) ? a : b; }
static inline rfe_real_t rfe_min(rfe_real_t a, rfe_real_t b) { return (a < b) ? a : b; }
static inline rfe_real_t rfe_clamp(rfe_real_t x, rfe_real_t lo, rfe_real_t hi)
{
    return rfe_min(rfe_max(x, lo), hi);
}
/** -1, 0 or 1: the derivative of |x|, taken as 0 at 0. */
static inline rfe_real_t rfe_sgn(rfe_real_t x)
{
    rfe_real_t r = (rfe_real_t)0;
    if (x > (rfe_real_t)0) {
        r = (rfe_real_t)1;
    } else if (x < (rfe_real_t)0) {
        r = (rfe_real_t)-1;
    } else {
        /* 0 (also NaN, which the callers' sums then reject) */
    }
    return r;
}

/* generated by scripts/codegen/twins.py from numerics_clamp_vec: do not edit; make twins */
/* Projects v[0..k) onto [lo, hi] (lo <= hi); returns 1 if any element moved. The filters'
 * mean projection (rfe_sckf_clamp, rfe_ckf_clamp), one sequence for both types. */
static inline int rfe_clamp_vec(rfe_real_t *v, size_t k, rfe_real_t lo, rfe_real_t hi)
{
    size_t i;
    int moved = 0;
    for (i = 0u; i < k; ++i) {
        if ((v[i] < lo) || (v[i] > hi)) {
            v[i] = rfe_clamp(v[i], lo, hi);
            moved = 1;
        }
    }
    return moved;
}
/* end generated */

#endif /* RFE_INTERNAL_H */
