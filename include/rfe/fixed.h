/**
 * @file fixed.h
 * @brief Fixed-point conventions of the `_q31` variant and its saturating integer
 *        primitives (docs/FIXED_POINT.md).
 *
 * Storage. Every fixed-point quantity is an `rfe_fix_t`: an int32 whose Q format (the number
 * n of fractional bits, "Qn": the stored integer v means v / 2^n) is stated where it is used
 * (a struct member's comment, a parameter's documentation, a `RFE_FIX_Q_*` constant).
 * Intermediates are int64; products of two int32 need at most 62 bits plus sign.
 *
 * Rounding. Right shifts that drop bits round half up (toward +infinity): floor(v / 2^s + 1/2).
 * Functions evaluated on magnitudes (division, square roots, norms, trigonometry; fxmath.h)
 * round their magnitude to nearest with ties away from zero, so they are exactly odd- or
 * even-symmetric.
 *
 * Saturation. Results that do not fit an int32 saturate symmetrically to
 * [RFE_FIX_MIN, RFE_FIX_MAX] = [-INT32_MAX, INT32_MAX] (INT32_MIN is never produced, so a
 * result can always be negated) and increment the caller's saturation counter `*sat`
 * (itself saturating at UINT32_MAX). The helpers below require a non-NULL `sat`; they
 * never return an error. INT32_MIN is accepted as an input everywhere.
 *
 * Defined behaviour only. No signed overflow (int64 intermediates, explicit range checks),
 * no left shift of a negative value (left shifts are multiplications by 2^s in int64 after a
 * range check), and no right shift of a negative value (implementation-defined in C99): an
 * arithmetic right shift is computed in offset binary,
 *   floor(a / 2^s) = ((uint64)a + 2^63) >> s  -  2^63 >> s,
 * where the unsigned conversion and shift are fully defined and, for s >= 1, the shifted
 * value is below 2^63 so the conversion back to int64 is exact. Integer operations only:
 * the results are bit-identical on every platform.
 *
 * This header uses only <stdint.h>; host-side conversions to and from real numbers are in
 * host/fixed_conv.h, which library sources must never include.
 */
#ifndef RFE_FIXED_H
#define RFE_FIXED_H

#include <stdint.h>

/** A fixed-point value: int32 with the Q format stated where it is used. */
typedef int32_t rfe_fix_t;

/** Largest and smallest saturated results (symmetric range). */
#define RFE_FIX_MAX INT32_MAX
#define RFE_FIX_MIN (-INT32_MAX)

/** 1.0 in Qn as an int32 (0 <= n <= 30). */
#define RFE_FIX_ONE(n) ((rfe_fix_t)((uint32_t)1u << (n)))

/* Q formats of the integer math functions (fxmath.h). */
#define RFE_FIX_Q_ANGLE 29u /**< angles [rad]: Q29, range +-4 rad, LSB 1.86e-9 rad */
#define RFE_FIX_Q_TRIG 30u  /**< sin, cos: Q30, range +-2, LSB 9.31e-10 */
#define RFE_FIX_Q_TAN 26u   /**< tan: Q26, range +-32, LSB 1.49e-8 */

/* Angle constants in Q29 (rounded to nearest), for the application: the library's CORDIC
 * works with its own Q61 constants (fxmath_q31.c) and uses none of them. */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-07: public API constant, for the application */
#define RFE_FIX_PI_Q29 ((rfe_fix_t)1686629713) /**< pi (exact value ...713.065) */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-07: public API constant, for the application */
#define RFE_FIX_HALF_PI_Q29 ((rfe_fix_t)843314857) /**< pi / 2 */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-07: public API constant, for the application */
#define RFE_FIX_QUARTER_PI_Q29 ((rfe_fix_t)421657428) /**< pi / 4 */

/** Counts one saturation event (the counter itself stops at UINT32_MAX). */
static inline void rfe_fix_count_sat(uint32_t *sat)
{
    if (*sat < UINT32_MAX) {
        ++*sat;
    }
}

/** int64 -> int32, saturating to [RFE_FIX_MIN, RFE_FIX_MAX]; counts a clamp in *sat. */
static inline rfe_fix_t rfe_fix_sat32(int64_t v, uint32_t *sat)
{
    rfe_fix_t r;
    if (v > (int64_t)RFE_FIX_MAX) {
        rfe_fix_count_sat(sat);
        r = RFE_FIX_MAX;
    } else if (v < (int64_t)RFE_FIX_MIN) {
        rfe_fix_count_sat(sat);
        r = RFE_FIX_MIN;
    } else {
        r = (rfe_fix_t)v;
    }
    return r;
}

/** Saturating a + b (any common Q format). */
static inline rfe_fix_t rfe_fix_add(rfe_fix_t a, rfe_fix_t b, uint32_t *sat)
{
    return rfe_fix_sat32((int64_t)a + (int64_t)b, sat);
}

/** Saturating a - b (any common Q format). */
static inline rfe_fix_t rfe_fix_sub(rfe_fix_t a, rfe_fix_t b, uint32_t *sat)
{
    return rfe_fix_sat32((int64_t)a - (int64_t)b, sat);
}

/** Saturating -a (only INT32_MIN saturates, to INT32_MAX). */
static inline rfe_fix_t rfe_fix_neg(rfe_fix_t a, uint32_t *sat)
{
    return rfe_fix_sat32(-(int64_t)a, sat);
}

/** Saturating |a| (only INT32_MIN saturates, to INT32_MAX). */
static inline rfe_fix_t rfe_fix_abs(rfe_fix_t a, uint32_t *sat)
{
    return (a < 0) ? rfe_fix_neg(a, sat) : a;
}

/** Smaller / larger of a and b; a clamped to [lo, hi] (lo <= hi; same Q format). */
static inline rfe_fix_t rfe_fix_min(rfe_fix_t a, rfe_fix_t b) { return (a < b) ? a : b; }
static inline rfe_fix_t rfe_fix_max(rfe_fix_t a, rfe_fix_t b) { return (a > b) ? a : b; }
static inline rfe_fix_t rfe_fix_clamp(rfe_fix_t a, rfe_fix_t lo, rfe_fix_t hi)
{
    return rfe_fix_min(rfe_fix_max(a, lo), hi);
}

/*
 * Where the core has no 64-bit shift and the compiler calls the C library for one (Thumb-1:
 * the Cortex-M0+, where every variable int64 shift is a call to libgcc's __aeabi_llsr or
 * __aeabi_llsl, ~20 instructions with the call), the two shifts below work on the 32-bit
 * halves instead (rfe_fix_shr64_floor_w32, rfe_fix_bit64_w32). The same integers on every
 * core (test_fxmath_q31.c checks the halves against the int64 forms on the host at every
 * shift; make pil checks the Cortex-M0+ image against the host bit for bit).
 */
#if defined(__arm__) && !defined(__thumb2__)
#define RFE_FIX_SHIFT64_W32 1
#else
#define RFE_FIX_SHIFT64_W32 0
#endif

/*
 * The Cortex-M0+ (Thumb-1) multiplies 32 x 32 -> 32 bits only (MULS), so GCC calls libgcc's
 * general 64 x 64 multiply (__aeabi_lmul, ~41 instructions with the call) for every int64
 * product, even of two widened int32. Where RFE_FIX_MUL64_W16 (Thumb-1 only)
 * rfe_fix_mul32x32 forms such a product from four 16 x 16 -> 32 partial products instead
 * (rfe_fix_mul32x32_w16, inlined: ~30 instructions). The same integer on every core
 * (test_fxmath_q31.c checks the halves against the int64 product on the host; make pil checks
 * the Cortex-M0+ image against the host bit for bit).
 */
#ifndef RFE_FIX_MUL64_W16 /* a host test sets it to 1 to run the Cortex-M0+ forms */
#define RFE_FIX_MUL64_W16 RFE_FIX_SHIFT64_W32
#endif

/* -Os keeps a helper of this size out of line, and a call costs what it saves. */
#if defined(__GNUC__)
/* MISRA-DEV-02: a GNU attribute (Rule 1.2, language extension), only under __GNUC__ */
#define RFE_FIX_INLINE_ALWAYS __attribute__((always_inline)) inline
#else
#define RFE_FIX_INLINE_ALWAYS inline
#endif

/** ma mb exactly for ma, mb <= 2^31, from 32-bit operations only: in 16-bit halves,
 *  ma = ah 2^16 + al, mb = bh 2^16 + bl (ah, bh <= 2^15; al, bl < 2^16),
 *    ma mb = ah bh 2^32 + (al bh + ah bl) 2^16 + al bl,
 *  every partial product below 2^32 and al bh + ah bl <= 2 * 2^15 (2^16 - 1) < 2^32 too, so
 *  the middle sum needs no carry word; the product is <= 2^62. */
static RFE_FIX_INLINE_ALWAYS uint64_t rfe_fix_umul31_w16(uint32_t ma, uint32_t mb)
{
    const uint32_t al = ma & 0xFFFFu;
    const uint32_t ah = ma >> 16;
    const uint32_t bl = mb & 0xFFFFu;
    const uint32_t bh = mb >> 16;
    const uint32_t mid = (al * bh) + (ah * bl);
    const uint32_t hh = ah * bh;
    const uint32_t ll = al * bl;
    const uint64_t hl = ((uint64_t)hh << 32) | (uint64_t)ll;
    return hl + ((uint64_t)mid << 16);
}

/** a b exactly for |a|, |b| <= 2^31 (int64 holding them), from 32-bit operations only: the
 *  magnitudes (their low words negated in uint32, exact up to 2^31) by rfe_fix_umul31_w16,
 *  <= 2^62 so the conversion to int64 is exact, then the sign of a b. */
static RFE_FIX_INLINE_ALWAYS int64_t rfe_fix_mul_m31_w16(int64_t a, int64_t b)
{
    const uint32_t ua = (uint32_t)a; /* modulo 2^32 */
    const uint32_t ub = (uint32_t)b;
    const uint32_t na = 0u - ua;
    const uint32_t nb = 0u - ub;
    const uint32_t ma = (a < 0) ? na : ua;
    const uint32_t mb = (b < 0) ? nb : ub;
    const int64_t r = (int64_t)rfe_fix_umul31_w16(ma, mb);
    return ((a < 0) != (b < 0)) ? -r : r;
}

/** a b for two int32 from 32-bit operations only (rfe_fix_mul_m31_w16). */
static RFE_FIX_INLINE_ALWAYS int64_t rfe_fix_mul32x32_w16(int32_t a, int32_t b)
{
    return rfe_fix_mul_m31_w16((int64_t)a, (int64_t)b);
}

/** a b exactly for any uint32 a, b (< 2^64), in 16-bit halves as rfe_fix_mul32x32_w16, but
 *  al bh + ah bl can reach 2^33 here: its carry is the bit 2^48 of the product. */
static RFE_FIX_INLINE_ALWAYS uint64_t rfe_fix_umul32x32_w16(uint32_t a, uint32_t b)
{
    const uint32_t al = a & 0xFFFFu;
    const uint32_t ah = a >> 16;
    const uint32_t bl = b & 0xFFFFu;
    const uint32_t bh = b >> 16;
    const uint32_t m1 = al * bh;
    const uint32_t mid = m1 + (ah * bl); /* modulo 2^32 */
    const uint64_t carry = (mid < m1) ? ((uint64_t)1 << 48) : 0u;
    const uint32_t hh = ah * bh;
    const uint32_t ll = al * bl;
    const uint64_t hl = ((uint64_t)hh << 32) | (uint64_t)ll;
    return (hl + ((uint64_t)mid << 16)) + carry;
}

/** (uint64)a * (uint64)b: as rfe_fix_mul32x32 for unsigned operands. */
static RFE_FIX_INLINE_ALWAYS uint64_t rfe_fix_umul32x32(uint32_t a, uint32_t b)
{
#if RFE_FIX_MUL64_W16
    return rfe_fix_umul32x32_w16(a, b);
#else
    return (uint64_t)a * (uint64_t)b;
#endif
}

/** a b for int64 a, b of magnitude <= 2^31 (a product <= 2^62): as rfe_fix_mul32x32, for
 *  the values just outside int32 (2^31, a difference or a negation of two int32). */
static RFE_FIX_INLINE_ALWAYS int64_t rfe_fix_mul_m31(int64_t a, int64_t b)
{
#if RFE_FIX_MUL64_W16
    return rfe_fix_mul_m31_w16(a, b);
#else
    return a * b;
#endif
}

/** (int64)a * (int64)b: the 16-bit partial products where RFE_FIX_MUL64_W16, else the int64
 *  product (one SMULL on the Cortex-M3/M4). */
static RFE_FIX_INLINE_ALWAYS int64_t rfe_fix_mul32x32(int32_t a, int32_t b)
{
#if RFE_FIX_MUL64_W16
    return rfe_fix_mul32x32_w16(a, b);
#else
    return (int64_t)a * (int64_t)b;
#endif
}

/** u >> s for 0 <= s <= 63 from the 32-bit halves (no libgcc call); rfe_fix_ushr64 takes it
 *  where RFE_FIX_SHIFT64_W32, else the int64 shift: the same integer (test_fxmath_q31.c
 *  checks the halves on the host). */
static inline uint64_t rfe_fix_ushr64_w32(uint64_t u, unsigned int s)
{
    const uint32_t hi = (uint32_t)(u >> 32);
    const uint32_t lo = (uint32_t)u;
    uint64_t r;
    if (s == 0u) {
        r = u;
    } else if (s < 32u) {
        const uint32_t rl = (lo >> s) | (hi << (32u - s));
        const uint32_t rh = hi >> s;
        r = ((uint64_t)rh << 32) | (uint64_t)rl;
    } else {
        const uint32_t rl = hi >> ((s - 32u) & 31u);
        r = (uint64_t)rl;
    }
    return r;
}

static inline uint64_t rfe_fix_ushr64(uint64_t u, unsigned int s)
{
#if RFE_FIX_SHIFT64_W32
    return rfe_fix_ushr64_w32(u, s);
#else
    return u >> s;
#endif
}

/** floor(a / 2^s) for 1 <= s <= 63 in 32-bit halves: the offset-binary form below, with
 *  u = (uint64)a + 2^63 (a's pattern with its top bit flipped) shifted word by word and
 *  2^(63 - s) taken off the word that holds it. s < 32: u >> s = rh 2^32 + rl with
 *  rh = hi >> s < 2^(32 - s) <= 2^31, so rh 2^32 + rl < 2^63 converts exactly, and
 *  2^(63 - s) = oh 2^32 with oh = 2^(31 - s); s >= 32: u >> s = hi >> (s - 32) < 2^32 and
 *  2^(63 - s) <= 2^31. */
static inline int64_t rfe_fix_shr64_floor_w32(int64_t a, unsigned int s)
{
    const uint64_t u = (uint64_t)a ^ ((uint64_t)1 << 63);
    const uint32_t hi = (uint32_t)(u >> 32);
    const uint32_t lo = (uint32_t)u;
    int64_t r;
    if (s < 32u) {
        const uint32_t rl = (lo >> s) | (hi << (32u - s));
        const uint32_t rh = hi >> s;
        const uint32_t oh = 1u << (31u - s);
        const uint64_t rw = ((uint64_t)rh << 32) | (uint64_t)rl; /* < 2^63 */
        const uint64_t ow = (uint64_t)oh << 32;
        r = (int64_t)rw - (int64_t)ow;
    } else {
        const unsigned int s32 = (s - 32u) & 31u; /* s <= 63 */
        const uint32_t rl = hi >> s32;
        const uint32_t o = 0x80000000u >> s32;
        r = (int64_t)rl - (int64_t)o;
    }
    return r;
}

/** Bit s of a's two's-complement pattern (0 <= s <= 63), from the word that holds it. */
static inline uint32_t rfe_fix_bit64_w32(int64_t a, unsigned int s)
{
    const uint64_t u = (uint64_t)a;
    const uint32_t w = (s < 32u) ? (uint32_t)u : (uint32_t)(u >> 32);
    return (w >> (s & 31u)) & 1u;
}

/** floor(a / 2^s): the arithmetic right shift, for every a and every s (s >= 64 gives
 *  -1 for a < 0, else 0). Offset-binary evaluation: no implementation-defined shift. */
static inline int64_t rfe_fix_shr64_floor(int64_t a, unsigned int s)
{
    int64_t r;
    if (s == 0u) {
        r = a;
    } else if (s >= 64u) {
        r = (a < 0) ? INT64_C(-1) : INT64_C(0);
    } else {
#if RFE_FIX_SHIFT64_W32
        r = rfe_fix_shr64_floor_w32(a, s);
#else
        const uint64_t off = (uint64_t)1 << 63;
        const uint64_t u = ((uint64_t)a + off) >> s; /* < 2^63: converts exactly */
        const uint64_t o = off >> s;
        r = (int64_t)u - (int64_t)o;
#endif
    }
    return r;
}

/** floor(a / 2^s + 1/2): right shift rounding half up, for every a and s (never overflows:
 *  it is floor(a / 2^s) plus bit s-1 of a's two's-complement pattern). */
static inline int64_t rfe_fix_shr64_round(int64_t a, unsigned int s)
{
    int64_t r;
    if (s == 0u) {
        r = a;
    } else if (s >= 64u) {
        r = 0; /* |a| / 2^s <= 1/2, and -1/2 rounds up to 0 */
    } else {
        const unsigned int s1 = s - 1u;
#if RFE_FIX_SHIFT64_W32
        const uint32_t half_bit = rfe_fix_bit64_w32(a, s1);
#else
        const uint64_t half_bit = ((uint64_t)a >> s1) & 1u;
#endif
        r = rfe_fix_shr64_floor(a, s) + (int64_t)half_bit;
    }
    return r;
}

/** int32 right shift rounding half up (never saturates): floor(a / 2^s) plus bit s-1 of a,
 *  the integer of rfe_fix_shr64_round((int64_t)a, s), in 32-bit operations (the int64 form's
 *  variable 64-bit shift cost ~40 instructions on the Cortex-M4). With the offset-binary
 *  u = a + 2^31 (in [0, 2^32)), floor(a / 2^s) = floor(u / 2^s) - 2^(31 - s) for s <= 31
 *  (2^s divides 2^31); both terms and the sum are within int32. s >= 32: |a| / 2^s <= 1/2,
 *  and -1/2 rounds up to 0. */
static inline rfe_fix_t rfe_fix_shr_round(rfe_fix_t a, unsigned int s)
{
    rfe_fix_t r;
    if (s == 0u) {
        r = a;
    } else if (s >= 32u) {
        r = 0;
    } else {
        const uint32_t ua = (uint32_t)a;
        const uint32_t off = (uint32_t)1u << 31;
        const uint32_t u = ua ^ off; /* a + 2^31 */
        const uint32_t half_bit = (ua >> (s - 1u)) & 1u;
        const uint32_t q = u >> s;   /* < 2^31 */
        const uint32_t o = off >> s; /* 2^(31 - s) */
        r = ((rfe_fix_t)q - (rfe_fix_t)o) + (rfe_fix_t)half_bit;
    }
    return r;
}

/** Saturating a * 2^s (s >= 0): a multiplication in int64, never a shift of a negative. */
static inline rfe_fix_t rfe_fix_shl(rfe_fix_t a, unsigned int s, uint32_t *sat)
{
    rfe_fix_t r;
    if (a == 0) {
        r = 0;
    } else if (s > 31u) {
        rfe_fix_count_sat(sat);
        r = (a < 0) ? RFE_FIX_MIN : RFE_FIX_MAX;
    } else {
        const uint64_t p2 = (uint64_t)1 << s; /* <= 2^31: |a| 2^s <= 2^62 */
        r = rfe_fix_sat32((int64_t)a * (int64_t)p2, sat);
    }
    return r;
}

/** Converts a from Q(q_from) to Q(q_to) (0 <= q <= 63): a left shift saturates, a right
 *  shift rounds half up. */
static inline rfe_fix_t rfe_fix_rescale(rfe_fix_t a, unsigned int q_from, unsigned int q_to,
                                        uint32_t *sat)
{
    return (q_to >= q_from) ? rfe_fix_shl(a, q_to - q_from, sat)
                            : rfe_fix_shr_round(a, q_from - q_to);
}

/** Rounds an int64 accumulator down by s bits (half up) and saturates it to int32. */
static inline rfe_fix_t rfe_fix_narrow(int64_t v, unsigned int s, uint32_t *sat)
{
    return rfe_fix_sat32(rfe_fix_shr64_round(v, s), sat);
}

/** Saturating product round(a * b / 2^s): a in Qa, b in Qb gives Q(a + b - s). The exact
 *  product (|a b| <= 2^62) is formed in int64 and rounded half up. */
static inline rfe_fix_t rfe_fix_mul(rfe_fix_t a, rfe_fix_t b, unsigned int s, uint32_t *sat)
{
    return rfe_fix_narrow((int64_t)a * (int64_t)b, s, sat);
}

/** Saturating int64 a + b, to [-INT64_MAX, INT64_MAX], always inlined: for the few hot
 *  accumulations whose calls cost more than the copy (the SCKF update's sums on the
 *  Cortex-M0+, where -Os keeps rfe_fix_add64 out of line). */
static RFE_FIX_INLINE_ALWAYS int64_t rfe_fix_add64_hot(int64_t a, int64_t b, uint32_t *sat)
{
    int64_t r;
    if ((b > 0) && (a > (INT64_MAX - b))) {
        rfe_fix_count_sat(sat);
        r = INT64_MAX;
    } else if ((b < 0) && (a < (-INT64_MAX - b))) {
        rfe_fix_count_sat(sat);
        r = -INT64_MAX;
    } else {
        r = a + b;
        if (r < -INT64_MAX) { /* INT64_MIN: keep the range symmetric */
            rfe_fix_count_sat(sat);
            r = -INT64_MAX;
        }
    }
    return r;
}

/** Saturating int64 a + b, to [-INT64_MAX, INT64_MAX] (for long accumulations). */
static inline int64_t rfe_fix_add64(int64_t a, int64_t b, uint32_t *sat)
{
    return rfe_fix_add64_hot(a, b, sat);
}

#endif /* RFE_FIXED_H */
