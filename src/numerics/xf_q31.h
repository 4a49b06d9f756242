/**
 * @file xf_q31.h
 * @brief Private: numbers as a 30-bit integer mantissa and a power of two, m 2^e (block
 *        floating point in integers), for the few fixed-point computations whose
 *        intermediate values span too many decades for one Q format: the lateral rows'
 *        derivatives of the measurement model (meas_q31.c, tyre_q31.c; docs/OBSERVER.md
 *        §4.2, docs/FIXED_POINT.md "Observer"). Integer operations only (no float, no libm).
 *
 * A value is normalised: m = 0 (e = 0), or 2^29 <= |m| <= 2^30. Each operation rounds its
 * exact integer result once, half up, to 30 significant bits: a relative error <= 2^-30 per
 * operation (a sum rounds to 2^-30 of its result, at most 2^-29 of its larger operand: a
 * cancellation keeps that absolute error, it is not amplified beyond it). No operation overflows:
 * products of two mantissas are < 2^61, sums are formed at the larger operand's exponent
 * minus 31 (< 2^62), quotients rounded as rfe_fix_div rounds them (< 2^31). The
 * exponent is an int: the values met (forces, their derivatives, ratios of lengths) stay
 * within 2^+-200, far inside its range.
 */
#ifndef RFE_XF_Q31_H
#define RFE_XF_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/component/fxmath.h"
#include "rfe/fixed.h"
#include "numerics/internal_q31.h"

/** A function kept out of line: the few rfe_xf_t helpers whose inlined copies (each with
 *  rfe_xf_make's normalisation) cost more flash than their calls cost time (tyre_q31.c), and
 *  the few functions of the tyre and input derivatives kept out of line for flash or so that
 *  their frames leave the deepest stack path (tyre_q31.c, meas_q31.c). */
#if defined(__GNUC__)
/* MISRA-DEV-02: a GNU attribute (Rule 1.2, language extension), only under __GNUC__ */
#define RFE_XF_OUTLINE __attribute__((noinline))
#else
#define RFE_XF_OUTLINE
#endif

/** m 2^e, normalised (see the file comment). */
typedef struct {
    int32_t m; /**< mantissa: 0 or 2^29 <= |m| <= 2^30 */
    int e;     /**< exponent */
} rfe_xf_t;

/** floor(v / 2^sh + 1/2) for 1 <= sh <= 33 and |v| < 2^(30 + sh) (sh = the bit length of |v|
 *  minus 30): rfe_fix_shr64_round(v, sh)'s integer, in [-2^30, 2^30], formed in 32 bits.
 *  f = floor(v / 2^(sh - 1)) is in [-2^31, 2^31): its two's-complement pattern is bits sh - 1
 *  .. sh + 30 of v's (a logical shift of the pattern by sh - 1 <= 32 gives them), and
 *  floor((f + 1) / 2) is the result. With w = f + 2^31 in [0, 2^32) (the pattern's top bit
 *  flipped), floor((w + 1) / 2) = (w >> 1) + (w & 1) (no overflow) is the result plus 2^30.
 *  rfe_xf_make normalises every product, sum and quotient of the observer's derivative pass
 *  this way: about 10 instructions on the Cortex-M4 where the 64-bit rounding took 30. */
static inline int32_t rfe_xf_round(int64_t v, unsigned int sh)
{
    const unsigned int s1 = sh - 1u;
    const uint32_t f = (uint32_t)rfe_fix_ushr64((uint64_t)v, s1);
    const uint32_t w = f ^ (uint32_t)0x80000000u;
    const uint32_t h = (w >> 1) + (w & 1u); /* result + 2^30, in [0, 2^31] */
    return (int32_t)((int64_t)h - (int64_t)0x40000000);
}

/** v 2^e (|v| < 2^63) normalised: rounded to 30 significant bits (half up), exact below. */
#if RFE_FIX_SHIFT64_W32
rfe_xf_t rfe_xf_make(int64_t v, int e);
#endif
#if (!RFE_FIX_SHIFT64_W32) || RFE_Q31_SHARED_HERE
RFE_Q31_SHARED rfe_xf_t rfe_xf_make(int64_t v, int e)
{
    rfe_xf_t r;
    r.m = 0;
    r.e = 0;
    if (v != 0) {
        const unsigned int len = rfe_q31_bitlen64(rfe_q31_mag64(v));
        if (len > 30u) {
            const unsigned int sh = len - 30u;
            r.m = rfe_xf_round(v, sh);
            r.e = e + (int)sh;
        } else {
            /* |v| < 2^len: |v| 2^sh < 2^30 fits int32 (sh <= 29) */
            const unsigned int sh = 30u - len;
            const uint32_t pu = (uint32_t)1u << sh; /* 32-bit: no libgcc shift */
            const int32_t p = (int32_t)pu;
            r.m = (int32_t)v * p;
            r.e = e - (int)sh;
        }
    }
    return r;
}
#endif

/** The fixed-point value v in Q(q). */
static inline rfe_xf_t rfe_xf_of(int32_t v, int q) { return rfe_xf_make((int64_t)v, -q); }

/** a b. */
static inline rfe_xf_t rfe_xf_mul(rfe_xf_t a, rfe_xf_t b)
{
    return rfe_xf_make((int64_t)a.m * (int64_t)b.m, a.e + b.e);
}

/** -a. */
static inline rfe_xf_t rfe_xf_neg(rfe_xf_t a)
{
    rfe_xf_t r = a;
    r.m = -a.m;
    return r;
}

/** a's mantissa at exponent base (base <= a.e - 0 and a.e - base <= 31): exact when the shift
 *  is to the left, rounded half up when base is above a.e (then a is the smaller operand). */
static inline int64_t rfe_xf_at(rfe_xf_t a, int base)
{
    const int s = a.e - base;
    int64_t v;
    if (s >= 0) {
        v = (int64_t)a.m * rfe_q31_pow2((unsigned int)s);
    } else {
        v = rfe_fix_shr64_round((int64_t)a.m, (unsigned int)(-s));
    }
    return v;
}

/** a + b: both mantissas at the larger exponent minus 31 (|.| <= 2^61 each), the sum
 *  normalised. With hi the operand of the larger exponent and d = hi.e - lo.e: for d <= 31
 *  that sum is exactly (hi.m 2^d + lo.m) 2^(31 - d), and rfe_xf_make gives a value and its
 *  power-of-two multiple the same mantissa, so the sum is formed at lo's exponent, one
 *  multiplication and one addition (|.| < 2^62) instead of two alignments (the same bits:
 *  test_xf_q31.c checks it against the two alignments). For d > 31 lo is rounded to hi's
 *  exponent minus 31 first (rfe_xf_at), as before. */
static inline rfe_xf_t rfe_xf_add(rfe_xf_t a, rfe_xf_t b)
{
    rfe_xf_t r;
    if (a.m == 0) {
        r = b;
    } else if (b.m == 0) {
        r = a;
    } else {
        const rfe_xf_t hi = (a.e >= b.e) ? a : b;
        const rfe_xf_t lo = (a.e >= b.e) ? b : a;
        const int d = hi.e - lo.e;
        if (d <= 31) {
            r = rfe_xf_make(((int64_t)hi.m * rfe_q31_pow2((unsigned int)d)) + (int64_t)lo.m,
                            lo.e);
        } else {
            const int base = hi.e - 31;
            r = rfe_xf_make(rfe_xf_at(hi, base) + rfe_xf_at(lo, base), base);
        }
    }
    return r;
}

/** The number of terms rfe_xf_sum adds. */
#define RFE_XF_SUM_MAX 8u

/** The sum of the RFE_XF_SUM_MAX terms t[] (0 for an unused one), rounded once: every term at
 *  base = the largest exponent minus 28 (exact for a term within 28 of it: |m| 2^(e - base) <=
 *  2^58; rounded half up, 1/2 unit of 2^base, for one further below), the integer sum (<= 8
 *  2^58 = 2^61, no overflow) normalised. Error: <= 2^-30 of the result plus 8 2^(base - 1) <=
 *  2^-55 of the largest term (which is >= 2^(29 + 28 + base)), where seven pairwise
 *  rfe_xf_add would round each partial sum (2^-29 of its larger operand each). All terms 0: 0. */
static inline rfe_xf_t rfe_xf_sum(const rfe_xf_t t[RFE_XF_SUM_MAX])
{
    int emax = 0;
    int any = 0;
    int64_t acc = 0;
    size_t i;
    for (i = 0u; i < RFE_XF_SUM_MAX; ++i) {
        if ((t[i].m != 0) && ((any == 0) || (t[i].e > emax))) {
            emax = t[i].e;
            any = 1;
        }
    }
    for (i = 0u; i < RFE_XF_SUM_MAX; ++i) {
        if (t[i].m != 0) {
            const int s = t[i].e - (emax - 28);
            if (s >= 0) {
                acc += (int64_t)t[i].m * rfe_q31_pow2((unsigned int)s);
            } else {
                acc += rfe_fix_shr64_round((int64_t)t[i].m, (unsigned int)(-s));
            }
        }
    }
    return rfe_xf_make(acc, emax - 28);
}

/** a - b. */
static inline rfe_xf_t rfe_xf_sub(rfe_xf_t a, rfe_xf_t b) { return rfe_xf_add(a, rfe_xf_neg(b)); }

/** a / b for b != 0 (b = 0 gives 0: no caller divides by 0): the quotient of the mantissas
 *  at shift 30 when |a.m| < |b.m|, else 29, so that 2^29 <= |q| <= 2^30 (30 bits), rounded
 *  half up on the magnitude: rfe_fix_div(a.m, b.m, shift)'s integer, formed here without its
 *  argument checks and saturation (the observer divides ~60 times a step, and the checks
 *  cost more than the division on the Cortex-M4). q2 = floor(|a.m| 2^(shift + 1) / |b.m|) <
 *  2^32: with shift 29, |a.m| <= 2^30 and |b.m| >= 2^29; with 30, |a.m| < |b.m|; so it is
 *  rfe_q31_udiv64_32's (|b.m| < 2^31). */
#if RFE_FIX_SHIFT64_W32
rfe_xf_t rfe_xf_div(rfe_xf_t a, rfe_xf_t b);
#endif
#if (!RFE_FIX_SHIFT64_W32) || RFE_Q31_SHARED_HERE
RFE_Q31_SHARED rfe_xf_t rfe_xf_div(rfe_xf_t a, rfe_xf_t b)
{
    rfe_xf_t r;
    r.m = 0;
    r.e = 0;
    if (b.m != 0) {
        const uint64_t ma = (a.m < 0) ? (uint64_t)(-(int64_t)a.m) : (uint64_t)a.m;
        const uint64_t mb = (b.m < 0) ? (uint64_t)(-(int64_t)b.m) : (uint64_t)b.m;
        unsigned int sh = 29u;
        int64_t q;
        if (ma < mb) {
            sh = 30u;
        }
        q = (int64_t)rfe_q31_div_round_mag((uint32_t)ma, (uint32_t)mb, sh);
        if ((a.m < 0) != (b.m < 0)) {
            q = -q;
        }
        r = rfe_xf_make(q, (a.e - b.e) - (int)sh);
    }
    return r;
}
#endif

/** sqrt(a) for a >= 0 (the floor root of the mantissa at an even exponent, 31 bits or more). */
static inline rfe_xf_t rfe_xf_sqrt(rfe_xf_t a)
{
    rfe_xf_t r;
    r.m = 0;
    r.e = 0;
    if (a.m > 0) {
        /* (e - s) even, s in {32, 33}: m 2^s < 2^64 */
        unsigned int s = 32u;
        uint32_t root = 0u;
        rfe_status_t st;
        if ((a.e % 2) != 0) {
            s = 33u;
        }
        st = rfe_fix_isqrt64((uint64_t)a.m << s, &root);
        (void)st;
        r = rfe_xf_make((int64_t)root, (a.e - (int)s) / 2);
    }
    return r;
}

/** -1, 0 or 1: the sign of v. */
static inline int rfe_q31_sign(int32_t v)
{
    int r = 0;
    if (v > 0) {
        r = 1;
    } else if (v < 0) {
        r = -1;
    } else {
        /* 0 */
    }
    return r;
}

/** -1, 0 or 1: the sign of a. */
static inline int rfe_xf_sign(rfe_xf_t a) { return rfe_q31_sign(a.m); }

/** a in Q(q), rounded half up, saturated to int32 (counted in *sat). */
static inline rfe_fix_t rfe_xf_to_fix(rfe_xf_t a, int q, uint32_t *sat)
{
    const int s = a.e + q;
    int64_t v;
    if (a.m == 0) {
        v = 0;
    } else if (s > 31) {
        v = (a.m > 0) ? INT64_MAX : -INT64_MAX; /* |a| 2^q >= 2^60: saturates */
    } else {
        v = rfe_xf_at(a, -q);
    }
    return rfe_fix_sat32(v, sat);
}

#endif /* RFE_XF_Q31_H */
