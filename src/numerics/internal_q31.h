/**
 * @file internal_q31.h
 * @brief Private helpers shared by the fixed-point library sources (src/<module>_q31.c;
 *        not installed). Integer operations only; includes no libc header beyond the
 *        freestanding <stddef.h> and <stdint.h>, so the Cortex-M0+ build (make check-nofloat)
 *        can compile it.
 *
 * Each module's helpers sit in their own named section below.
 */
#ifndef RFE_INTERNAL_Q31_H
#define RFE_INTERNAL_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/config.h"
#include "rfe/fixed.h"
#include "rfe/component/fxmath.h"

#include "numerics/sizes.h" /* RFE_TRIA_COLS_SZ */

/* ==== Section: every module ================================================================ */

/** Magic words marking an initialised fixed-point state (distinct from the float twins'). */
#define RFE_MAGIC_EST_Q31 0x45513331u /* "EQ31" */
#define RFE_MAGIC_VEL_Q31 0x56513331u /* "VQ31" */
#define RFE_MAGIC_MON_Q31 0x4D513331u /* "MQ31" */

/** 1 when |v| <= lim (lim >= 0), without forming |v| (INT32_MIN is a valid input), else 0. */
static inline int rfe_q31_within(rfe_fix_t v, rfe_fix_t lim)
{
    return ((v <= lim) && (v >= -lim)) ? 1 : 0;
}

/** Projects v[0..k) onto [lo, hi] (lo <= hi); returns 1 if any element moved. The twin of
 *  numerics/internal.h's rfe_clamp_vec, so that the filters' mean projection
 *  (rfe_sckf_clamp_q31, rfe_ckf_clamp_q31) is the float one's sequence on Q values. */
static inline int rfe_clamp_vec_q31(rfe_fix_t *v, size_t k, rfe_fix_t lo, rfe_fix_t hi)
{
    size_t i;
    int moved = 0;
    for (i = 0u; i < k; ++i) {
        if ((v[i] < lo) || (v[i] > hi)) {
            v[i] = rfe_fix_clamp(v[i], lo, hi);
            moved = 1;
        }
    }
    return moved;
}

/** 2^s as an int64 multiplier (0 <= s <= 62): a left shift is a multiplication by it (no
 *  shift of a signed value). */
static inline int64_t rfe_q31_pow2(unsigned int s)
{
    const uint64_t p = (uint64_t)1 << s;
    return (int64_t)p;
}

/* ==== Section: measurement model (tyre_q31.c, obsmat_q31.c, meas_q31.c) ==================== */

/**
 * round(v * c / 2^s) (half up) of an int64 and a 32-bit factor, exactly, although the product
 * needs up to 93 bits. Preconditions (the callers prove them): |v| < 2^62, |c| <= 2^31,
 * 1 <= s <= 62, and the result below 2^62 in magnitude.
 *
 * With v = vh 2^32 + vl (vh = floor(v / 2^32), |vh| <= 2^30; 0 <= vl < 2^32):
 *   a = vh c, |a| <= 2^61;   b = vl c, |b| <= (2^32 - 1) 2^31 < 2^63;
 *   b = bh 2^32 + bl (0 <= bl < 2^32), so v c = t 2^32 + bl with t = a + bh, |t| < 2^62.
 * Then, for integer t and 0 <= bl / 2^32 < 1,
 *   s >= 33: floor((t 2^32 + bl + 2^(s-1)) / 2^s) = floor((t + 2^(s-33)) / 2^(s-32))
 *            = rfe_fix_shr64_round(t, s - 32);
 *   s <= 32: t 2^(32-s) + floor((bl + 2^(s-1)) / 2^s)   (bl + 2^(s-1) < 2^33: no overflow).
 */
static inline int64_t rfe_q31_mul64x32(int64_t v, int64_t c, unsigned int s)
{
    const uint64_t low32 = (uint64_t)0xFFFFFFFFu;
    const int64_t vh = rfe_fix_shr64_floor(v, 32u);
    const uint64_t vl_u = (uint64_t)v & low32;
    const int64_t vl = (int64_t)vl_u;
    const int64_t a = vh * c;
    const int64_t b = vl * c;
    const int64_t bh = rfe_fix_shr64_floor(b, 32u);
    const uint64_t bl = (uint64_t)b & low32;
    const int64_t t = a + bh;
    int64_t r;

    if (s >= 33u) {
        r = rfe_fix_shr64_round(t, s - 32u);
    } else {
        const unsigned int s1 = s - 1u;
        const uint64_t half = (uint64_t)1 << s1;
        const uint64_t lo = (bl + half) >> s;
        r = (t * rfe_q31_pow2(32u - s)) + (int64_t)lo;
    }
    return r;
}

/** |v| as uint64 (exact for every int64 above INT64_MIN; the callers' values are < 2^63).
 *  For the full int64 range see rfe_q31_mag64_any (cubature_q31.h). */
static inline uint64_t rfe_q31_mag64(int64_t v)
{
    return (v < 0) ? (uint64_t)(-v) : (uint64_t)v;
}

/** The bit length of a 32-bit m: the smallest len with m < 2^len (0 for m = 0), by halving
 *  the search range in 32-bit operations (five tests; the Cortex-M0+ has no 64-bit shift). */
static inline unsigned int rfe_q31_bitlen32(uint32_t m)
{
    uint32_t v = m;
    unsigned int len = 0u;
    if ((v >> 16) != 0u) {
        v >>= 16;
        len += 16u;
    }
    if ((v >> 8) != 0u) {
        v >>= 8;
        len += 8u;
    }
    if ((v >> 4) != 0u) {
        v >>= 4;
        len += 4u;
    }
    if ((v >> 2) != 0u) {
        v >>= 2;
        len += 2u;
    }
    if ((v >> 1) != 0u) {
        v >>= 1;
        len += 1u;
    }
    return len + (unsigned int)v; /* v is now 0 (m = 0) or 1 */
}

/** The bit length of a 64-bit m (0 for m = 0): the high word's plus 32, else the low word's. */
static inline unsigned int rfe_q31_bitlen64(uint64_t m)
{
    const uint32_t hi = (uint32_t)(m >> 32);
    return (hi != 0u) ? (32u + rfe_q31_bitlen32(hi)) : rfe_q31_bitlen32((uint32_t)m);
}

/**
 * The smallest right shift s that brings a magnitude m below 2^bits: m < 2^(bits + s). A value
 * with magnitude <= m rounded by that shift (half up) then has magnitude <= 2^bits, and keeps
 * at least bits significant bits when s > 0 (relative rounding error <= 2^-bits).
 */
static inline unsigned int rfe_q31_norm_shift(uint64_t m, unsigned int bits)
{
    const unsigned int len = rfe_q31_bitlen64(m);
    unsigned int s = 0u;
    if (len > bits) {
        s = len - bits;
    }
    return s;
}

/** v (|v| < 2^63) rounded down by s bits (half up) to an int32: the caller guarantees it fits
 *  (|v| < 2^(30 + s) after rfe_q31_norm_shift(., 30)). */
static inline int32_t rfe_q31_shr_to32(int64_t v, unsigned int s)
{
    return (int32_t)rfe_fix_shr64_round(v, s);
}

/** Adds a function's saturation count to the caller's counter, which stops at UINT32_MAX. */
static inline void rfe_q31_sat_add(uint32_t *sat, uint32_t count)
{
    *sat = (*sat > (UINT32_MAX - count)) ? UINT32_MAX : (*sat + count);
}

/* ==== Section: linear algebra and the cubature filters (qr_q31.c, chol_q31.c, sckf_q31.c,
 * ckf_q31.c) ================================================================================ */

/** |v| as uint64 for every int64 (2^63 for INT64_MIN; internal_q31.h's rfe_q31_mag64 needs
 *  v > INT64_MIN). */
static inline uint64_t rfe_q31_mag64_any(int64_t v)
{
    return (v < 0) ? ((uint64_t)(-(v + 1)) + 1u) : (uint64_t)v;
}

/** round(num / den) for den > 0, ties away from zero (exactly rounded on the magnitude, so
 *  odd in num), saturating to the symmetric int32 range with a count in *sat. */
static inline rfe_fix_t rfe_q31_div_round(int64_t num, rfe_fix_t den, uint32_t *sat)
{
    const uint64_t d = (uint64_t)den;
    const uint64_t mag = rfe_q31_mag64_any(num);
    uint64_t q = mag / d;
    int64_t r;
    if ((2u * (mag % d)) >= d) { /* mag % d < 2^31: no overflow */
        q += 1u;
    }
    if (q > (uint64_t)RFE_FIX_MAX) {
        rfe_fix_count_sat(sat);
        q = (uint64_t)RFE_FIX_MAX;
    }
    r = (int64_t)q;
    return (rfe_fix_t)((num < 0) ? -r : r);
}

/** round(sqrt(x)) for every uint64 (<= 2^32): floor root r from rfe_fix_isqrt64, plus one
 *  exactly when x - r^2 > r (sqrt(x) is never a half-integer). */
static inline uint64_t rfe_q31_sqrt_round(uint64_t x)
{
    uint32_t r32 = 0u;
    uint64_t r;
    /* rfe_fix_isqrt64 fails only for a NULL root pointer; r32 is never NULL. */
    const rfe_status_t st = rfe_fix_isqrt64(x, &r32);
    (void)st;
    r = (uint64_t)r32;
    if ((x - (r * r)) > r) { /* r^2 <= x < 2^64 */
        r += 1u;
    }
    return r;
}

#endif /* RFE_INTERNAL_Q31_H */
