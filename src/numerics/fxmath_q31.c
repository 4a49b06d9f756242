/**
 * @file fxmath_q31.c
 * @brief Integer math of the fixed-point variant (rfe/component/fxmath.h): square roots, norm,
 *        division, CORDIC atan2 / sincos / tan; and the shorter atan2 and sine of the Magic
 *        Formula tyre (fxmath_internal_q31.h). Integer operations only.
 */
/* the one definition of the helpers internal_q31.h shares out of line (RFE_Q31_SHARED) */
#define RFE_Q31_SHARED_HERE 1

#include "rfe/component/fxmath.h"

#include "numerics/fxmath_internal_q31.h"
#include "numerics/internal_q31.h"
#include "numerics/xf_q31.h"

/* ---- shared helpers ------------------------------------------------------------------- */

#if !(defined(__GNUC__) && (!defined(__arm__) || defined(__ARM_FEATURE_CLZ)))
/* rfe_q31_bitlen32's byte table (internal_q31.h): entry v is the bit length of v. One copy
 * for every object that takes the bit length (the Cortex-M0+: no count-leading-zeros). */
const uint8_t rfe_q31_bitlen8[256] = {
    0u, 1u, 2u, 2u, 3u, 3u, 3u, 3u, 4u, 4u, 4u, 4u, 4u, 4u, 4u, 4u,
    5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u, 5u,
    6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u,
    6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u, 6u,
    7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u,
    7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u,
    7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u,
    7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u, 7u,
    8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u,
    8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u,
    8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u,
    8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u,
    8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u,
    8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u,
    8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u,
    8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u, 8u};
#endif

/* |v| of an int32 as uint64 (2^31 for INT32_MIN, no overflow). */
static uint64_t mag32(rfe_fix_t v)
{
    return (v < 0) ? (uint64_t)(-(int64_t)v) : (uint64_t)v;
}

/* floor(sqrt(y)) of a 32-bit value and the remainder y - root^2, digit by digit in 32-bit
 * arithmetic: two bits of y per step from b, the largest power of 4 not above y, 16 steps at
 * most, additions and shifts only. At the step with b = 4^k, r holds the root's bits above
 * bit k, floor(sqrt(y)) >> (k + 1), times 4^(k+1); that is below 2^31, so r + b < 2^32. */
static uint32_t isqrt32_rem(uint32_t y, uint32_t *rem)
{
#if defined(__arm__) && defined(__ARM_FEATURE_IDIV)
    /* the core divides in one instruction (Cortex-M3, M4): Newton steps, the same root */
    const uint32_t root = rfe_q31_isqrt32_newton(y);
    *rem = y - (root * root);
    return root;
#else
    uint32_t r = 0u;
    uint32_t rm = y;
    uint32_t b = 0u;

    if (y != 0u) {
        b = (uint32_t)1 << ((rfe_q31_bitlen64(y) - 1u) & ~1u);
    }
    while (b != 0u) {
        if (rm >= (r + b)) {
            rm -= r + b;
            r = (r >> 1) + b;
        } else {
            r >>= 1;
        }
        b >>= 2;
    }
    *rem = rm;
    return r;
#endif
}

/* floor(sqrt(x)) and the remainder x - root^2 (<= 2 root) of any uint64. Below 2^32: the
 * 32-bit digit-by-digit root. Above: with y = floor(x / 2^sh) < 2^32 (sh even, so y keeps 31
 * or 32 bits, y >= 2^30), r0 = floor(sqrt(y)) >= 2^15 and r = (r0 + 1) 2^h (h = sh / 2 <= 16)
 * > sqrt(x) >= r0 2^h, so e = r - sqrt(x) <= 2^h; then one integer Newton step
 * r1 = floor((r + floor(x / r)) / 2). It is >= floor(sqrt(x)) (AM-GM), and below the exact
 * step (r + x / r) / 2 = sqrt(x) + e^2 / (2 r) <= sqrt(x) + 2^(2h) / (2 r0 2^h) <= sqrt(x) +
 * 2^(h - 16) <= sqrt(x) + 1, so r1 is floor(sqrt(x)) or one more: one product and
 * comparison (r1 = 2^32 is one more: floor(sqrt(x)) < 2^32) leave floor(sqrt(x)) exactly,
 * the integer the Newton steps repeated until r^2 <= x gave (one division where they took
 * one or two). r + x/r <= 2^33 (x/r <= sqrt(x) < 2^32); r = 2^32 only at the start (r0 =
 * 2^16 - 1, h = 16), where x / r is x / 2^32. */
#if RFE_FIX_MUL64_W16
/* The Cortex-M0+ (RFE_FIX_MUL64_W16: no divider, no 32 x 32 -> 64 multiply): the part above
 * 2^32 of isqrt_rem by one step of Zimmermann's Karatsuba square root (P. Zimmermann,
 * "Karatsuba square root", INRIA RR-3805, 1999; Brent and Zimmermann, "Modern Computer
 * Arithmetic", algorithm 1.12) instead of the Newton step: the same root and remainder with
 * one 32-bit division of a quotient <= 2^16 where the Newton step took a 64-by-32 division
 * (two 32-bit ones) and a 64-bit product. With sh, h, y as in isqrt_rem (y >= 2^30),
 * b = 2^h <= 2^16 and x = y b^2 + a1 b + a0 (a1, a0 < b): s' = floor(sqrt(y)) in
 * [2^15, 2^16), r' = y - s'^2 <= 2 s', q = floor(N / (2 s')) with N = r' b + a1 and u = N -
 * 2 s' q < 2 s'; then s = s' b + q and r = u b + a0 - q^2 satisfy s^2 + r = x identically.
 * Bounds (b <= 2 s'): q <= N / (2 s') <= b + (b - 1) / (2 s') < b + 1, so q <= b; r <= u b +
 * a0 < 2 s' b <= 2 s, so (s + 1)^2 > x; r >= -q^2 >= -b^2 >= -2 s' b > -(2 s - 1), so
 * (s - 1)^2 <= x. Hence s = floor(sqrt(x)) when r >= 0, else s - 1 with remainder r + 2 s - 1
 * (the one correction). Widths: floor(N / 2) = r' 2^(h - 1) + floor(a1 / 2) <= (2^17 - 2)
 * 2^15 + 2^15 - 1 < 2^32 and floor(N / (2 s')) = floor(floor(N / 2) / s'), u = 2 (floor(N /
 * 2) - q s') + (a1 mod 2); s <= 2^32, u b + a0 < 2^33, q^2 <= 2^32 (q = 2^16 only with
 * b = 2^16: its square is 2^32, the 32-bit product's wrapped 0 plus the high word).
 * test/numerics/w16/test_isqrt_w16_q31.c checks it against the exact root. */
static uint64_t isqrt_rem_hi(uint64_t x, uint64_t *rem)
{
    /* in 32-bit words, without libgcc's 64-bit shifts: x = xh 2^32 + xl with xh >= 1 */
    const uint32_t xh = (uint32_t)(x >> 32);
    const uint32_t xl = (uint32_t)x;
    const unsigned int sh = (rfe_q31_bitlen32(xh) + 1u) & ~1u; /* even, 2..32 */
    const unsigned int h = sh / 2u;                              /* 1..16 */
    const uint32_t y = (sh == 32u) ? xh : ((xh << (32u - sh)) | (xl >> sh));
    const uint32_t low = xl & (0xFFFFFFFFu >> (32u - sh)); /* x mod b^2 */
    const uint32_t a1 = low >> h;
    const uint32_t a0 = low & (0xFFFFFFFFu >> (32u - h));
    uint32_t r1 = 0u;
    const uint32_t s1 = isqrt32_rem(y, &r1);
    const uint32_t nh = (r1 << (h - 1u)) + (a1 >> 1); /* floor(N / 2) */
    const uint32_t q = nh / s1;
    const uint32_t u = ((nh - (q * s1)) << 1) + (a1 & 1u);
    const uint32_t q_hi = q >> 16;  /* 1 only for q = 2^16 */
    const uint32_t q_sq = q * q;    /* q^2 modulo 2^32 */
    const uint64_t q2 = ((uint64_t)q_hi << 32) | (uint64_t)q_sq;
    /* u b < 2^33 as its two words; s' b < 2^32 */
    const uint32_t ub_hi = u >> (32u - h);
    const uint32_t ub_lo = u << h;
    const uint64_t t = (((uint64_t)ub_hi << 32) | (uint64_t)ub_lo) + (uint64_t)a0;
    const uint32_t s1b = s1 << h;
    uint64_t s = (uint64_t)s1b + (uint64_t)q;
    if (t < q2) {
        *rem = ((t + (s << 1)) - 1u) - q2;
        s -= 1u;
    } else {
        *rem = t - q2;
    }
    return s;
}
#endif

static uint64_t isqrt_rem(uint64_t x, uint64_t *rem)
{
    uint64_t r;

    if ((x >> 32) == 0u) {
        uint32_t rm32 = 0u;
        r = isqrt32_rem((uint32_t)x, &rm32);
        *rem = rm32;
    } else {
#if RFE_FIX_MUL64_W16
        r = isqrt_rem_hi(x, rem);
#else
        const unsigned int sh = (rfe_q31_bitlen64(x) - 31u) & ~1u;
        const unsigned int half = sh / 2u;
        const uint32_t y = (uint32_t)(x >> sh);
        uint32_t rm32 = 0u;
        uint64_t r0;
        uint64_t xr;
        uint64_t sq;
        r0 = isqrt32_rem(y, &rm32);
        r = (r0 + 1u) << half;
        xr = ((r >> 32) == 0u) ? (uint64_t)rfe_q31_udiv64_32(x, (uint32_t)r) : (x >> 32);
        r = (r + xr) >> 1;
        /* r^2 modulo 2^64 (0 for r = 2^32); one less: (r - 1)^2 = r^2 - 2 r + 1, also modulo
         * 2^64 (intended: exact once r - 1 < 2^32), so one product either way */
        sq = r * r;
        if (((r >> 32) != 0u) || (sq > x)) {
            sq = (sq - (r << 1)) + 1u;
            r -= 1u;
        }
        *rem = x - sq;
#endif
    }
    return r;
}

/* Rounded root of the integer n: round(sqrt(n)) = r + 1 exactly when n - r^2 > r (sqrt(n)
 * is never a half-integer). Result <= 2^32. */
static uint64_t sqrt_round(uint64_t n)
{
    uint64_t rem;
    uint64_t r = isqrt_rem(n, &rem);
    if (rem > r) {
        r += 1u;
    }
    return r;
}


/* 2^32 - 1: a doubled quotient from here on rounds beyond INT32_MAX. */
#define LIM2 ((((uint64_t)1) << 32) - 1u)

/* floor(n 2^bits / d) for d in [1, 2^63], or a value >= LIM2 when that is >= LIM2 = 2^32 - 1:
 * long division, the integer part, then the quotient bits one by one (shifts and
 * subtractions), the remainder staying below d; a partial quotient only grows, so the
 * division stops as soon as one reaches LIM2 (which also keeps every partial quotient below
 * 2^33). It gives exactly floor(n 2^i / d) for the bits i consumed so far. Its one caller is
 * div_round_mag's last case, reached only by rfe_fix_tan's 61-bit sine over a cosine above
 * 2^56: the int32 operands of rfe_fix_div take the single-division cases before it (a faster
 * form for d <= 2^56, k bits per division, had no caller left once those cases took every
 * rfe_fix_div shift, and was removed). */
static uint64_t div_bits(uint64_t n, uint64_t d, unsigned int bits)
{
    uint64_t quo = n / d;
    uint64_t rem = n % d;
    unsigned int left = bits;

    while ((quo < LIM2) && (left > 0u)) {
        quo <<= 1;
        rem <<= 1;
        if (rem >= d) {
            rem -= d;
            quo += 1u;
        }
        --left;
    }
    return quo;
}

/* div_round_mag for both magnitudes below 2^32 and 0 <= e <= 31: q2 = floor(n 2^(e+1) / d)
 * by one rfe_q31_udiv64_32 once the quotient is known to be below 2^32, else LIM2 (too
 * large). rfe_fix_div's common call takes it directly (inline: the call to div_round_mag
 * and its 64-bit argument tests cost about as much as the division's own arithmetic on the
 * Cortex-M4); div_round_mag's own first case is this. */
static inline int div_round_mag32(uint32_t n, uint32_t d, unsigned int e, uint64_t *q)
{
    const unsigned int e1 = e + 1u;
    const uint64_t ne = (uint64_t)n << e1; /* < 2^64: n < 2^32, e + 1 <= 32 */
    uint64_t q2 = LIM2;                          /* the quotient is 2^32 or more */
    int over = 1;
    if ((ne >> 32) < (uint64_t)d) {
        q2 = (uint64_t)rfe_q31_udiv64_32(ne, d);
    }
    if (q2 < LIM2) {
        *q = (q2 + 1u) >> 1;
        over = 0;
    }
    return over;
}

/* round(n * 2^e / d) for d in [1, 2^63], to nearest with ties up (on the magnitude, i.e.
 * away from zero): with q2 = floor(n * 2^(e+1) / d), the result is
 * (q2 + 1) >> 1 = floor(n * 2^e / d + 1/2). It exceeds INT32_MAX exactly when
 * q2 >= 2^32 - 1 (returns 1, *q unset). When n, d < 2^32 and e + 1 <= 32, n 2^(e+1) < 2^64
 * and q2 is one integer division (the common case: int32 operands; rfe_q31_udiv64_32 once
 * the quotient is known to be below 2^32, else it is at least LIM2); else div_bits. */
static int div_round_mag(uint64_t n, uint64_t d, unsigned int e, uint64_t *q)
{
    const unsigned int e1 = e + 1u;
    int over = 1;

    if (((n >> 32) == 0u) && ((d >> 32) == 0u) && (e1 <= 32u)) {
        over = div_round_mag32((uint32_t)n, (uint32_t)d, e, q);
    } else if (((n >> 32) == 0u) && ((d >> 32) == 0u) && (e1 <= 63u)) {
        /* n, d < 2^32 and e + 1 in [33, 63] (rfe_fix_div's shift above 31): q2 < 2^32 needs
         * n 2^(e+1) < d 2^32 < 2^64, so a dividend beyond 64 bits (bitlen(n) + e + 1 > 64)
         * means q2 >= 2^32: too large, as div_bits finds it; else one rfe_q31_udiv64_32 as
         * in div_round_mag32 (where div_bits took three or four 64-bit divisions, libgcc's
         * __aeabi_uldivmod on Arm). The same q2 where it is below 2^32. */
        if ((rfe_q31_bitlen64(n) + e1) <= 64u) {
            const uint64_t ne = n << e1;
            if ((ne >> 32) < d) {
                const uint64_t q2 = (uint64_t)rfe_q31_udiv64_32(ne, (uint32_t)d);
                if (q2 < LIM2) {
                    *q = (q2 + 1u) >> 1;
                    over = 0;
                }
            }
        }
    } else if (((n >> 32) == 0u) && ((d >> 32) != 0u) && (e1 == 1u)) {
        /* n < 2^32 <= d (rfe_fix_div's negative shift with |b| 2^-shift >= 2^32): n / d < 1,
         * so floor(n / d + 1/2) is 1 where 2 n >= d, else 0 (2 n < 2^33: no overflow) */
        *q = 0u;
        if ((n << 1) >= d) {
            *q = 1u;
        }
        over = 0;
    } else {
        const uint64_t q2 = div_bits(n, d, e1);
        if (q2 < LIM2) {
            *q = (q2 + 1u) >> 1;
            over = 0;
        }
    }
    return over;
}

/* Applies the sign to a magnitude that fits int32 (m <= INT32_MAX). */
static rfe_fix_t signed32(uint64_t m, int neg)
{
    const rfe_fix_t v = (rfe_fix_t)m;
    return (neg != 0) ? -v : v;
}

/* ---- square roots and norm -------------------------------------------------------------- */

rfe_status_t rfe_fix_isqrt64(uint64_t x, uint32_t *root)
{
    uint64_t rem;

    if (root == NULL) {
        return RFE_ERR_NULL;
    }
    *root = (uint32_t)isqrt_rem(x, &rem);
    return RFE_OK;
}

/* round(sqrt(N)) > INT32_MAX exactly when N > (2^31 - 1/2)^2 - 1/4 = 2^62 - 2^31. */
#define SQRT_SAT_ABOVE (((uint64_t)1 << 62) - ((uint64_t)1 << 31))

rfe_status_t rfe_fix_sqrt(rfe_fix_t x, unsigned int q_in, unsigned int q_out, rfe_fix_t *root,
                          uint32_t *sat)
{
    const uint64_t ux = mag32(x); /* used only when x >= 0 */
    uint64_t r;
    int e;

    if ((root == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((x < 0) || (q_in > 31u) || (q_out > 31u)) {
        return RFE_ERR_RANGE;
    }
    /* root = sqrt(x * 2^e) with e = 2 q_out - q_in in [-31, 62]. */
    e = (2 * (int)q_out) - (int)q_in;
    if (e >= 0) {
        /* x * 2^e > T  <=>  x > floor(T / 2^e): decided before the product could overflow. */
        if (ux > (SQRT_SAT_ABOVE >> (unsigned int)e)) {
            rfe_fix_count_sat(sat);
            *root = RFE_FIX_MAX;
            return RFE_OK;
        }
        r = sqrt_round(ux << (unsigned int)e);
    } else {
        /* sqrt(x / 2^k) = sqrt(x * 2^m) / 2^h with m = k mod 2, h = (k + m) / 2 >= 1, and
         * round(y / 2^h) = (floor(y) + 2^(h-1)) >> h exactly for real y >= 0. */
        const unsigned int k = (unsigned int)(-e);
        const unsigned int m = k & 1u;
        const unsigned int h = (k + m) / 2u;
        const unsigned int h1 = h - 1u;
        const uint64_t half = (uint64_t)1 << h1;
        uint64_t rem;
        r = isqrt_rem(ux << m, &rem) + half;
        r >>= h;
    }
    *root = (rfe_fix_t)r;
    return RFE_OK;
}

rfe_status_t rfe_fix_norm(const rfe_fix_t *v, size_t n, rfe_fix_t *norm, uint32_t *sat)
{
    uint64_t ss = 0u;
    size_t i;

    if ((v == NULL) || (norm == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    /* Exact sum of squares: each term <= 2^62 and the sum stays <= SQRT_SAT_ABOVE < 2^62
     * before every addition (or we stop), so it never exceeds 2^63. */
    for (i = 0u; i < n; ++i) {
        const uint64_t m = mag32(v[i]);
        ss += m * m;
        if (ss > SQRT_SAT_ABOVE) {
            rfe_fix_count_sat(sat);
            *norm = RFE_FIX_MAX;
            return RFE_OK;
        }
    }
    *norm = (rfe_fix_t)sqrt_round(ss);
    return RFE_OK;
}

/* ---- division --------------------------------------------------------------------------- */

rfe_status_t rfe_fix_div(rfe_fix_t a, rfe_fix_t b, int shift, rfe_fix_t *q, uint32_t *sat)
{
    uint64_t m = 0u;
    int over = 0;
    int neg = 0;

    if ((q == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((b == 0) || (shift < -62) || (shift > 62)) {
        return RFE_ERR_RANGE;
    }
    if ((a < 0) != (b < 0)) {
        neg = 1;
    }
    if (shift >= 0) {
        if (shift <= 31) {
            over = div_round_mag32((uint32_t)mag32(a), (uint32_t)mag32(b), (unsigned int)shift,
                                   &m);
        } else {
            over = div_round_mag(mag32(a), mag32(b), (unsigned int)shift, &m);
        }
    } else if (shift >= -32) {
        /* divisor |b| 2^-shift <= 2^63 */
        over = div_round_mag(mag32(a), mag32(b) << (unsigned int)(-shift), 0u, &m);
    } else {
        m = 0u; /* |a / b| 2^shift <= 2^31 2^-33 = 1/4 rounds to 0 */
    }
    if (over != 0) {
        rfe_fix_count_sat(sat);
        *q = (neg != 0) ? RFE_FIX_MIN : RFE_FIX_MAX;
    } else {
        *q = signed32(m, neg);
    }
    return RFE_OK;
}

/* ---- CORDIC ------------------------------------------------------------------------------ */

/* Iterations of both CORDIC modes; the residual angle after them is <= atan(2^-39) = 1.8e-12
 * rad, 0.001 LSB of Q29. */
#define CORDIC_N 40u

/* atan(2^-i) in Q61, rounded to nearest (computed with 60 significant digits). */
static const int64_t cordic_atan_q61[CORDIC_N] = {
    INT64_C(1811004864519280711), INT64_C(1069098597953152948), INT64_C(564882337777596249),
    INT64_C(286743094836456889),  INT64_C(143927976672616092),  INT64_C(72034151524184357),
    INT64_C(36025865417378411),   INT64_C(18014032019027246),   INT64_C(9007153442175927),
    INT64_C(4503593900760542),    INT64_C(2251799097857775),    INT64_C(1125899817364151),
    INT64_C(562949942236502),     INT64_C(281474975312555),     INT64_C(140737488180565),
    INT64_C(70368744155819),      INT64_C(35184372086101),      INT64_C(17592186044075),
    INT64_C(8796093022165),       INT64_C(4398046511099),       INT64_C(2199023255551),
    INT64_C(1099511627776),       INT64_C(549755813888),        INT64_C(274877906944),
    INT64_C(137438953472),        INT64_C(68719476736),         INT64_C(34359738368),
    INT64_C(17179869184),         INT64_C(8589934592),          INT64_C(4294967296),
    INT64_C(2147483648),          INT64_C(1073741824),          INT64_C(536870912),
    INT64_C(268435456),           INT64_C(134217728),           INT64_C(67108864),
    INT64_C(33554432),            INT64_C(16777216),            INT64_C(8388608),
    INT64_C(4194304)};

/* 1 / K in Q61, K = prod_{i<40} sqrt(1 + 2^-2i) = 1.64676025812106564836... */
#define CORDIC_INV_K_Q61 INT64_C(1400229935014726477)
/* pi and pi/2 in Q61, rounded to nearest. */
#define PI_Q61 UINT64_C(7244019458077122842)
#define HALF_PI_Q61 UINT64_C(3622009729038561421)

/* floor(a / 2^s) for 1 <= s <= 63, given o = 2^(63 - s): rfe_fix_shr64_floor's offset-binary
 * shift, floor(a / 2^s) = ((a + 2^63) >> s) - (2^63 >> s), without its range checks and with
 * 2^63 >> s carried by the CORDIC loops (halved each iteration). */
static int64_t floor_shr_o(int64_t a, unsigned int s, uint64_t o)
{
    const uint64_t off = (uint64_t)1 << 63;
    const uint64_t u = ((uint64_t)a + off) >> s; /* < 2^63: converts exactly */
    return (int64_t)u - (int64_t)o;
}

/* Vectoring mode: the angle atan(y / x) in Q61 of a first-quadrant vector x >= 0, y >= 0,
 * max(x, y) in [2^59, 2^60). |(x, y)| grows by K < 1.65 at most, so |x|, |y| < 2^62.
 * x stays positive; y changes sign and is shifted with the defined floor shift. */
static uint64_t cordic_vector(int64_t x0, int64_t y0)
{
    int64_t x = x0;
    int64_t y = y0;
    int64_t z = 0;
    uint64_t o = (uint64_t)1 << 63; /* 2^63 >> i */
    unsigned int i;

    for (i = 0u; (i < CORDIC_N) && (y != 0); ++i) {
        const int64_t xs = (i == 0u) ? x : floor_shr_o(x, i, o);
        const int64_t ys = (i == 0u) ? y : floor_shr_o(y, i, o);
        if (y > 0) {
            x += ys;
            y -= xs;
            z += cordic_atan_q61[i];
        } else {
            x -= ys;
            y += xs;
            z -= cordic_atan_q61[i];
        }
        o >>= 1;
    }
    /* From a first-quadrant start z stays within [-2^-39, pi/2 + 2^-39] rad. */
    return (z > 0) ? (uint64_t)z : 0u;
}

/* Rotation mode: (cos z, sin z) in Q61 for |z| <= pi/2 (z in Q61), starting from
 * (1/K, 0); every intermediate vector has length <= 1 (plus rounding), so |x|, |y| < 2^62. */
static void cordic_rotate(int64_t z0, int64_t *c, int64_t *s)
{
    int64_t x = CORDIC_INV_K_Q61;
    int64_t y = 0;
    int64_t z = z0;
    uint64_t o = (uint64_t)1 << 63; /* 2^63 >> i */
    unsigned int i;

    for (i = 0u; i < CORDIC_N; ++i) {
        const int64_t xs = (i == 0u) ? x : floor_shr_o(x, i, o);
        const int64_t ys = (i == 0u) ? y : floor_shr_o(y, i, o);
        if (z >= 0) {
            x -= ys;
            y += xs;
            z -= cordic_atan_q61[i];
        } else {
            x += ys;
            y -= xs;
            z += cordic_atan_q61[i];
        }
        o >>= 1;
    }
    *c = x;
    *s = y;
}

/* Q61 magnitude -> Q(61 - s), rounded half up, for a non-negative value below 2^63 - 2^s. */
static uint64_t round_down_mag(uint64_t m, unsigned int s)
{
    const unsigned int s1 = s - 1u;
    const uint64_t half = (uint64_t)1 << s1;
    return (m + half) >> s;
}

/* v rounded from Q61 to Q30 on its magnitude (v is a CORDIC output, |v| < 2^62). */
static rfe_fix_t q61_to_trig(int64_t v)
{
    const uint64_t m = (v < 0) ? (uint64_t)(-v) : (uint64_t)v;
    return signed32(round_down_mag(m, 61u - RFE_FIX_Q_TRIG), (v < 0) ? 1 : 0);
}

rfe_status_t rfe_fix_atan2(rfe_fix_t y, rfe_fix_t x, rfe_fix_t *angle)
{
    uint64_t ax;
    uint64_t ay;
    uint64_t big;
    uint64_t th;
    uint64_t xn;
    uint64_t yn;
    unsigned int len;
    unsigned int sh;

    if (angle == NULL) {
        return RFE_ERR_NULL;
    }
    ax = mag32(x);
    ay = mag32(y);
    if ((ax == 0u) && (ay == 0u)) {
        *angle = 0;
        return RFE_OK;
    }
    /* Exact normalisation: scale both by 2^sh so that max(|x|, |y|) lies in [2^59, 2^60). */
    big = (ax > ay) ? ax : ay;
    len = rfe_q31_bitlen64(big);
    sh = 60u - len; /* len <= 32 */
    xn = ax << sh;
    yn = ay << sh;
    th = cordic_vector((int64_t)xn, (int64_t)yn);
    /* Quadrant: x < 0 mirrors to pi - theta (>= pi/2 - 2^-39 rad, so no wrap). */
    if (x < 0) {
        th = PI_Q61 - th;
    }
    *angle = signed32(round_down_mag(th, 61u - RFE_FIX_Q_ANGLE), (y < 0) ? 1 : 0);
    return RFE_OK;
}

/* The unrounded Q61 cosine and sine of a Q29 angle reduced to |z| <= pi/2, computed on |a|
 * and mirrored (sin odd, cos even, so the results are exactly symmetric). */
static void sincos_q61(rfe_fix_t a, int64_t *c, int64_t *s)
{
    const uint64_t am = mag32(a) << (61u - RFE_FIX_Q_ANGLE); /* |a| in Q61, <= 2^63 */
    int64_t cz;
    int64_t sz;
    int flip = 0;
    int64_t z;

    if (am > HALF_PI_Q61) {
        /* |a| in (pi/2, 4]: sin a = sin(pi - a), cos a = -cos(pi - a), |pi - a| <= pi/2. */
        flip = 1;
        z = (am <= PI_Q61) ? (int64_t)(PI_Q61 - am) : -(int64_t)(am - PI_Q61);
    } else {
        z = (int64_t)am;
    }
    cordic_rotate(z, &cz, &sz);
    *c = (flip != 0) ? -cz : cz;
    *s = (a < 0) ? -sz : sz;
}

rfe_status_t rfe_fix_sincos(rfe_fix_t angle, rfe_fix_t *s, rfe_fix_t *c)
{
    int64_t c61;
    int64_t s61;

    if ((s == NULL) || (c == NULL)) {
        return RFE_ERR_NULL;
    }
    if (angle == 0) {
        /* what the CORDIC rounds to at 0 (a road's grade is mostly 0): its 40 steps saved */
        *s = 0;
        *c = (rfe_fix_t)1073741824; /* 2^30: 1 in Q30 (RFE_FIX_Q_TRIG) */
        return RFE_OK;
    }
    sincos_q61(angle, &c61, &s61);
    *s = q61_to_trig(s61);
    *c = q61_to_trig(c61);
    return RFE_OK;
}

rfe_status_t rfe_fix_tan(rfe_fix_t angle, rfe_fix_t *t)
{
    int64_t c61;
    int64_t s61;
    uint64_t m = 0u;

    if (t == NULL) {
        return RFE_ERR_NULL;
    }
    if ((angle > RFE_FIX_TAN_LIMIT_Q29) || (angle < -RFE_FIX_TAN_LIMIT_Q29)) {
        return RFE_ERR_RANGE;
    }
    if (angle == 0) {
        *t = 0; /* what the CORDIC's quotient rounds to at 0 (below): its 40 steps saved */
        return RFE_OK;
    }
    /* |angle| <= 1.5 rad: cos >= 0.0707, so c61 >= 1.6e17 > 0 and s / c <= 14.2 (Q26 fits). */
    /* (sin can come out as -1e-12 instead of 0 at angle 0; its magnitude then rounds to 0.)
     * The quotient is <= 14.2 * 2^26, so the division cannot report an overflow. */
    sincos_q61((angle < 0) ? -angle : angle, &c61, &s61);
    (void)div_round_mag((s61 < 0) ? (uint64_t)(-s61) : (uint64_t)s61, (uint64_t)c61,
                        RFE_FIX_Q_TAN, &m);
    *t = signed32(m, (angle < 0) ? 1 : 0);
    return RFE_OK;
}

/* ---- the Magic Formula's atan2 and sine (fxmath_internal_q31.h) ---------------------------------
 * Both are built for the ~2^-30 the curve needs, in 32-bit arithmetic wherever the 40-step
 * int64 CORDIC above spends its time (on the Cortex-M0+ every 64-bit shift is a libgcc call). */

/* rfe_q31_atan2_quad1 takes the CORDIC steps i = 1 .. 11; the division then delivers the
 * digits 2^-11 .. 2^-33 of the residual ratio: the leading one and 22 more. */
/* The leading digit 2^-11 in Q33, and the marker bit after the 22 further digits. */
#define QA_LEAD 4194304u
/* The marker of the step bits after the 10 steps i = 2 .. 11 (2^10). */
#define QA_CPOS 1024u
/* The larger input is scaled to [QA_X_MIN, 2^30] (2^29). */
#define QA_X_MIN 536870912u

/*
 * The division digits 2^-12 .. 2^-33 of rfe_q31_atan2_quad1 summed in units of 2^-33: the
 * non-restoring steps W <- 2 W - sigma x (sigma = +1 for W >= 0, else -1), 22 of them, from
 * W_0 = w in [-x, x) (x > 0; the leading digit leaves it there, see below): the sum is
 * D = sum_j sigma_j 2^(21-j) (j = 0 .. 21), odd. Each step keeps W in [-x, x), and
 * W_22 = 2^22 W_0 - D x, so D x is in (2^22 W_0 - x, 2^22 W_0 + x]: D is the one odd integer
 * there, 2 floor(2^21 W_0 / x) + 1 (|.| <= 2^22 + 1). Where the core divides in one
 * instruction (__ARM_FEATURE_IDIV, the Cortex-M3 and M4; the host) that floor is one division
 * (rfe_q31_udiv64_32, on the magnitude: 2^21 |W_0| < 2^32 x; for W_0 < 0 the floor is minus
 * the ceiling of the magnitude's quotient): ~40 instructions on the Cortex-M4 instead of
 * ~130 for the steps. Without a divider (the Cortex-M0+) the 22 steps stay, a shift and an
 * addition each, cheaper there than a 64-bit division by calls. The same integer either way
 * (test_fxmath_q31.c checks rfe_q31_atan2_quad1 against its step-by-step form, and PIL on
 * each core against the host).
 */
static int32_t qa_digits(int32_t w, int32_t x)
{
#if defined(__arm__) && !defined(__ARM_FEATURE_IDIV)
    int32_t ww = w;
    uint32_t dpos = 1u; /* a marker bit, then sigma_j = +1 as a 1 */
    while (dpos < QA_LEAD) {
        dpos += dpos;
        if (ww >= 0) {
            ww = (ww - x) + ww;
            dpos += 1u;
        } else {
            ww = (ww + x) + ww;
        }
    }
    {
        /* with the +1s as bits B (marker 2^22 taken off): 2 B - (2^22 - 1) */
        const uint32_t db = dpos - QA_LEAD; /* < 2^22 */
        return ((2 * (int32_t)db) + 1) - (int32_t)QA_LEAD;
    }
#else
    const uint32_t ux = (uint32_t)x;
    int32_t f;
    if (w >= 0) {
        const uint32_t uw = (uint32_t)w;
        const uint64_t n = (uint64_t)uw << 21;
        f = (int32_t)rfe_q31_udiv64_32(n, ux);
    } else {
        const int32_t mw = -w; /* w >= -x > -2^31 */
        const uint32_t uw = (uint32_t)mw;
        const uint64_t xm1 = (uint64_t)ux - 1u;
        const uint64_t n = ((uint64_t)uw << 21) + xm1;
        f = -(int32_t)rfe_q31_udiv64_32(n, ux);
    }
    return (2 * f) + 1;
#endif
}

/* 2^-i - atan(2^-i) in Q38, i = 2 .. 11, rounded to nearest (2^-36.8 of rounding in all;
 * the sum of the entries, 1583063625, fits int32). */
#define QA_CORR_2 1380254570
#define QA_CORR_3 177297749
#define QA_CORR_4 22317338
#define QA_CORR_5 2794565
#define QA_CORR_6 349474
#define QA_CORR_7 43689
#define QA_CORR_8 5461
#define QA_CORR_9 683
#define QA_CORR_10 85
#define QA_CORR_11 11

/* qa_step inlined at its ten calls (each with its constants) on every core, -Os too. */
#if defined(__GNUC__)
/* MISRA-DEV-02: a GNU attribute (Rule 1.2, language extension), only under __GNUC__ */
#define QA_INLINE __attribute__((always_inline)) inline
#else
#define QA_INLINE inline
#endif

/* The CORDIC state of rfe_q31_atan2_quad1 between its steps i = 2 .. 11 (below). */
typedef struct {
    int32_t w;     /* W = y 2^(i-1) */
    int32_t xx;    /* x */
    uint32_t cpos; /* a marker bit, then sigma_i = +1 as a 1 */
    int32_t corr;  /* sum sigma_i (2^-i - atan 2^-i), Q38 */
} qa_state_t;

/* One CORDIC step i (s1 = 2i - 2, c = 2^-i - atan 2^-i in Q38) of rfe_q31_atan2_quad1:
 * W <- 2 W - sigma x, x += round(|W| / 2^(s1 + 1)) = floor((floor(|W| / 2^s1) + 1) / 2). The
 * ten steps are written out with their constants (no loop counter, no table walk): the same
 * integers as the loop over the table they replace. */
static QA_INLINE void qa_step(qa_state_t *q, unsigned int s1, int32_t c)
{
    const int32_t w = q->w;
    uint32_t m;
    q->cpos += q->cpos;
    if (w >= 0) {
        m = (uint32_t)w;
        q->w = (w - q->xx) + w;
        q->cpos += 1u;
        q->corr += c;
    } else {
        m = (uint32_t)(-w);
        q->w = (w + q->xx) + w;
        q->corr -= c;
    }
    q->xx += (int32_t)(((m >> s1) + 1u) >> 1);
}

/*
 * atan2(y, x), 0 <= x, y <= 2^30, in Q31.
 *
 * Octant: with a = max(x, y), b = min(x, y) the angle t = atan(b / a) is in [0, pi/4] and the
 * result t or pi/2 - t (b = 0: t = 0 exactly). Both are scaled by 2^sh (exact) so that
 * a in [2^29, 2^30].
 *
 * CORDIC steps i = 1 .. 11 (no step 0: sum_{i>=1} atan 2^-i = 0.958 > pi/4), vectoring mode,
 * sigma = sign(y), y carried as W = y 2^(i-1), so that
 *   W <- 2 W - sigma x (exact),  x <- x + |W| 2^-(2i-1) (rounded half up),  z += sigma atan 2^-i.
 * Step 1 has sigma = +1 (W = b > 0). The angle is summed as atan(1/2) (Q61) plus, for
 * i = 2 .. 11, the digits sigma 2^-i (an integer in Q11) minus sigma (2^-i - atan 2^-i) (Q38,
 * table above): 2^-36.8 of table rounding. From t in [0, pi/4] the residual angle
 * phi_(i+1) of the exact iteration obeys |phi_2| <= atan(1/2) and |phi_(i+1)| <= atan(2^-i)
 * (atan 2^-(i-1) <= 2 atan 2^-i), so |y_(i+1)| <= 2^-i x_(i+1) and |W| <= x; the rounding of x
 * moves the angle by < 2^-29 rad, which loosens this to |W| <= x (1 + 2^-18). x only grows,
 * to K' |(a, b)| <= 1.1645 sqrt(2) 2^30 < 2^30.72 (K' = prod_{i>=1} sqrt(1 + 2^-2i)), so x
 * and W, and W -+ x (|.| <= max(|W|, x)), fit int32.
 *
 * Error of the rounding of x: a change e (|e| <= 1/2) of x after step i is a vector error
 * (e, 0) that the later steps rotate onto the residual direction, whose angle to it is
 * phi_(i+1), and scale by prod_{j>i} k_j: the angle moves by at most
 *   sum_i (1/2) |phi_(i+1)| / (prod_{j<=i} k_j |(a, b)|) <= (1/2) 0.8729 2^-29 = 3.49 2^-32 rad
 * (|phi_(i+1)| <= sum_{j>i} atan 2^-j, the sum evaluated numerically; |(a, b)| >= 2^29).
 *
 * Division: after step 11 the remaining angle is atan(q), q = y_12 / x_12 = 2^-11 W / x with
 * |W| <= x (1 + 2^-18). The digits sigma_j 2^-j, j = 11 .. 33, come from non-restoring
 * division: the leading one W <- W - sigma x (|W| <= x afterwards, as |W| <= 2 x), then
 * W <- 2 W - sigma x, which keeps |W| <= x exactly; the remainder is <= 2^-33. atan q and q
 * differ by <= |q|^3 / 3 <= 2^-34.58. The digits are summed in Q33 (|.| < 2^23).
 *
 * Total: 3.49 2^-32 + 2^-33 + 2^-34.58 + 2^-36.8 + 2^-62 (atan(1/2), pi/2) < 4.2 2^-32
 * before, 5.2 2^-32 = 1.211e-9 rad after the final rounding (2^-32, Q61 -> Q31). Range: for
 * b >= 1 the angle t >= atan(2^-30) > 3.99 2^-32 (a <= 2^30), so the unrounded t is above
 * -0.21 2^-32 and rounds to >= 0 (b = 0: t = 0 exactly); pi/2 - t is then below
 * pi/2 + 0.21 2^-32 and rounds to at most round(pi/2 2^31) = 3373259426 (pi/2 2^31 =
 * 3373259426.13). So no clamp is needed: the result is within [0, pi/2].
 */
uint32_t rfe_q31_atan2_quad1(uint32_t y, uint32_t x)
{
    const uint32_t a = (y > x) ? y : x;
    const uint32_t b = (y > x) ? x : y;
    int64_t z = 0; /* t, Q61 */

    if (b != 0u) {
        unsigned int sh = 0u;
        qa_state_t st;
        uint32_t cpos;         /* a marker bit, then sigma_i = +1 as a 1, i = 2 .. 11 */
        int32_t corr;          /* sum sigma_i (2^-i - atan 2^-i), i = 2 .. 11, Q38 */
        int32_t lead;          /* the leading division digit 2^-11, Q33 */
        int32_t steps;         /* sum sigma_i 2^-i, i = 2 .. 11, Q11 */
        int32_t digits;        /* sum sigma_j 2^-j, j = 11 .. 33, Q33 */
        int32_t xx;
        int32_t w;

        if (a < QA_X_MIN) {
            sh = 30u - rfe_q31_bitlen32(a); /* a >= 1: bit length 1 .. 29 */
        }
        {
            const uint32_t an = a << sh; /* [2^29, 2^30] */
            const uint32_t bn = b << sh; /* W_1 = y > 0: sigma_1 = +1 */
            xx = (int32_t)an;
            w = (int32_t)bn;
        }
        {
            const uint32_t m = (uint32_t)w;
            w = (w - xx) + w;
            xx += (int32_t)((m + 1u) >> 1);
        }
        st.w = w;
        st.xx = xx;
        st.cpos = 1u;
        st.corr = 0;
        /* steps i = 2 .. 11, written out (qa_step): constant shifts and corrections, no
         * loop counter or table walk */
        qa_step(&st, 2u, QA_CORR_2);
        qa_step(&st, 4u, QA_CORR_3);
        qa_step(&st, 6u, QA_CORR_4);
        qa_step(&st, 8u, QA_CORR_5);
        qa_step(&st, 10u, QA_CORR_6);
        qa_step(&st, 12u, QA_CORR_7);
        qa_step(&st, 14u, QA_CORR_8);
        qa_step(&st, 16u, QA_CORR_9);
        qa_step(&st, 18u, QA_CORR_10);
        qa_step(&st, 20u, QA_CORR_11);
        w = st.w;
        xx = st.xx;
        cpos = st.cpos;
        corr = st.corr;
        /* The leading digit 2^-11, then 2^-12 .. 2^-33 (qa_digits) */
        if (w >= 0) {
            w -= xx;
            lead = (int32_t)QA_LEAD;
        } else {
            w += xx;
            lead = -(int32_t)QA_LEAD;
        }
        digits = lead + qa_digits(w, xx);
        /* sum sigma 2^-k over n digits with the +1s as bits B (marker 2^n taken off):
         * 2 B - (2^n - 1), in units of the last digit: the steps' in Q11 (|.| < 2^10) */
        {
            const uint32_t cb = cpos - QA_CPOS; /* < 2^10 */
            steps = ((2 * (int32_t)cb) + 1) - (int32_t)QA_CPOS;
        }
        /* t = atan(1/2) + steps 2^-11 - corr 2^-38 + digits 2^-33, in Q61 */
        z = ((cordic_atan_q61[1] + ((int64_t)steps * rfe_q31_pow2(50u))) -
             ((int64_t)corr * rfe_q31_pow2(23u))) +
            ((int64_t)digits * rfe_q31_pow2(28u));
    }
    if (y > x) {
        z = (int64_t)HALF_PI_Q61 - z;
    }
    /* z > -2^29 (see above), < pi/2 2^61 + 2^28: rounded to Q31, within [0, 3373259426] */
    z += rfe_q31_pow2(29u);
    return (uint32_t)((uint64_t)z >> 30);
}

/* Entries of the sine and cosine tables of rfe_q31_sin_q55 (k = 0 .. 50). */
#define SIN_TAB_N 51u
/* pi and pi/2 in Q55, rounded to nearest (pi 2^55 = ...044.41, so pi/2 is exactly half). */
#define PI_Q55 INT64_C(113187804032455044)
#define HALF_PI_Q55 INT64_C(56593902016227522)
/* 2^18 / 6 and 2^16 / 24, rounded (1/6 + 1.27e-6 and 1/24 + 5.1e-6). */
#define INV6_Q18 43691u
#define INV24_Q16 2731

/* floor(v / 2^s + 1/2) for |v| <= 2^30 and 1 <= s <= 29, in 32-bit offset binary: v + 2^30
 * (modulo 2^32, intended) is the non-negative value v + 2^30 <= 2^31, the rounding bit
 * 2^(s-1) <= 2^28 keeps it below 2^32, and the shifted offset is taken off after the shift. */
static int32_t rshr32(int32_t v, unsigned int s)
{
    const uint32_t off = (uint32_t)1 << 30;
    const unsigned int s1 = s - 1u;
    const uint32_t u = (((uint32_t)v + off) + ((uint32_t)1 << s1)) >> s;
    const uint32_t offs = off >> s;
    return (int32_t)u - (int32_t)offs;
}

/* floor(v / 2^s + 1/2) for |v| <= 2^61 and 1 <= s <= 61, as rshr32 with the offset 2^62. */
static int64_t rshr64(int64_t v, unsigned int s)
{
    const uint64_t off = (uint64_t)1 << 62;
    const unsigned int s1 = s - 1u;
    const uint64_t u = (((uint64_t)v + off) + ((uint64_t)1 << s1)) >> s;
    const uint64_t offs = off >> s;
    return (int64_t)u - (int64_t)offs;
}

/*
 * sin(phi), phi in Q55 within [0, pi], in Q30.
 *
 * p = phi or pi - phi, in [0, pi/2] (pi rounded by 2^-56); k = round(32 p) in [0, 50],
 * d = p - k/32 with |d| <= 2^-6, rounded to Q36 (|d| <= 2^30, error 2^-37). With S, C the
 * table's sin, cos of k/32:
 *   sin(k/32 + d) = S + d (C + d (-S/2 + d (-C/6 + d S/24))) + R,  |R| <= d^5/120 <= 2^-36.9.
 * Horner from the inside (error bounds of each level in brackets):
 *   u3 = -C/6 + d S/24, Q31, in 32-bit products: C/6 from C rounded to Q16 (2^-17 / 6) times
 *        1/6 in Q18 (1.27e-6), d S from d in Q20 and S in Q16 rounded to Q24 (2^-20.4), times
 *        1/24 in Q16 (5.1e-6 2^-6): [2^-18.5];
 *   u2 = -S/2 + d u3, Q31: 64-bit product rounded (2^-32), S/2 rounded (2^-32): [2^-24.5];
 *   u1 = C + d u2, Q31 in int64 (C = 1 at k = 0): C's table rounding 2^-32, the product's
 *        2^-32, d 2^-24.5: [2^-29.7];
 *   G = S + d u1, Q62: S's table rounding 2^-33, d u1 to 2^-63, d 2^-29.7: [2^-33 + 2^-35.7].
 * Total before the final rounding: 2^-33 + 2^-35.7 + 2^-37 (d rounded, slope <= 1) + 2^-36.9
 * (R) < 2^-32.64 (1.28 2^-33), so -2^-32.64 < G < 1 + 2^-32.64, and G rounded to Q30 (half
 * up) is within [0, 2^30]; error <= 2^-31 + 2^-32.64 = 0.66 LSB30 = 6.15e-10.
 */
int32_t rfe_q31_sin_q55(int64_t phi)
{
    /* sin(k / 32) in Q32 (all below 2^32: k / 32 <= 1.5625 < pi/2) and cos(k / 32) in Q31
     * (<= 2^31), k = 0 .. 50, rounded to nearest (computed with 60 significant digits). */
    static const uint32_t sin_tab_q32[SIN_TAB_N] = {
        0u,          134195884u,  268260727u,  402063619u,  535473903u,  668361305u,  800596063u,
        932049054u,  1062591914u, 1192097171u, 1320438366u, 1447490175u, 1573128534u, 1697230760u,
        1819675669u, 1940343695u, 2059117009u, 2175879630u, 2290517542u, 2402918802u, 2512973652u,
        2620574627u, 2725616654u, 2827997164u, 2927616182u, 3024376433u, 3118183431u, 3208945576u,
        3296574240u, 3380983856u, 3462091998u, 3539819466u, 3614090360u, 3684832157u, 3751975777u,
        3815455657u, 3875209809u, 3931179884u, 3983311229u, 4031552938u, 4075857905u, 4116182865u,
        4152488442u, 4184739185u, 4212903601u, 4236954188u, 4256867461u, 4272623976u, 4284208345u,
        4291609258u, 4294819488u};
    static const uint32_t cos_tab_q31[SIN_TAB_N] = {
        2147483648u, 2146435157u, 2143290709u, 2138053374u, 2130728266u, 2121322538u, 2109845374u,
        2096307983u, 2080723582u, 2063107390u, 2043476608u, 2021850407u, 1998249902u, 1972698141u,
        1945220073u, 1915842531u, 1884594201u, 1851505597u, 1816609030u, 1779938574u, 1741530038u,
        1701420928u, 1659650409u, 1616259270u, 1571289881u, 1524786154u, 1476793500u, 1427358781u,
        1376530271u, 1324357603u, 1270891722u, 1216184836u, 1160290367u, 1103262894u, 1045158103u,
        986032733u,  925944519u,  864952136u,  803115142u,  740493919u,  677149617u,  613144090u,
        548539838u,  483399946u,  417788022u,  351768135u,  285404752u,  218762677u,  151906984u,
        84902956u,   17816022u};
    const int64_t p = (phi > HALF_PI_Q55) ? (PI_Q55 - phi) : phi;
    const uint32_t k = (uint32_t)(((uint64_t)p + ((uint64_t)1 << 49)) >> 50); /* <= 50 */
    const int64_t d55 = p - (int64_t)((uint64_t)k << 50); /* in [-2^49, 2^49) */
    const int32_t d = (int32_t)rshr64(d55, 19u);          /* Q36, |d| <= 2^30 */
    const uint32_t s = sin_tab_q32[k];
    const uint32_t c = cos_tab_q31[k];
    /* C/6 in Q34: (C rounded to Q16, <= 2^16) times 1/6 in Q18: < 2^31.5, uint32 */
    const uint32_t c6 = ((c + ((uint32_t)1 << 14)) >> 15) * INV6_Q18;
    /* d S in Q24: (d in Q20, |.| <= 2^14) (S in Q16, < 2^16) < 2^30, rounded by 12 bits */
    const int32_t ds = rshr32(rshr32(d, 16u) * (int32_t)(s >> 16), 12u);
    /* u3 = -C/6 + d S/24, Q31 (|ds| 1/24 in Q40: < 2^29.4) */
    const int32_t u3 = rshr32(ds * INV24_Q16, 9u) - (int32_t)((c6 + 4u) >> 3);
    /* u2 = -S/2 + d u3, Q31 (S + 2 < 2^32: S <= 2^32 - 147808) */
    const int32_t u2 =
        (int32_t)rshr64(rfe_fix_mul32x32(d, u3), 36u) - (int32_t)((s + 2u) >> 2);
    /* u1 = C + d u2, Q31, <= 2^31 */
    const int64_t u1 = (int64_t)c + rshr64(rfe_fix_mul32x32(d, u2), 36u);
    /* G = S + d u1, Q62 (|d u1| <= 2^61 in Q67) */
    const int64_t g = (int64_t)((uint64_t)s << 30) + rshr64(rfe_fix_mul_m31((int64_t)d, u1), 5u);

    /* g + 2^31 > 0 (G > -2^-32.64): rounded to Q30 */
    return (int32_t)(((uint64_t)g + ((uint64_t)1 << 31)) >> 32);
}

/* ---- the rounded division of the linear algebra and the filters (internal_q31.h) ---------- */

/* The two rounded divisions' common tail: the rounded magnitude q saturated to RFE_FIX_MAX
 * (counted) and signed by num (ties away from zero: odd in num). */
static rfe_fix_t div_signed_sat(uint64_t q, int64_t num, uint32_t *sat)
{
    uint64_t qs = q;
    int64_t r;
    if (qs > (uint64_t)RFE_FIX_MAX) {
        rfe_fix_count_sat(sat);
        qs = (uint64_t)RFE_FIX_MAX;
    }
    r = (int64_t)qs;
    return (rfe_fix_t)((num < 0) ? -r : r);
}

/** round(num / den) for den > 0, ties away from zero (exactly rounded on the magnitude, so
 *  odd in num), saturating to the symmetric int32 range with a count in *sat. The quotient
 *  floor(|num| / den) by rfe_q31_udiv64_32 (the Cortex-M's two 32-bit divisions instead of
 *  libgcc's 64-bit __udivmoddi4) where it fits 32 bits, |num| < den 2^32, i.e. the high word
 *  of |num| below den; the remainder |num| - q den < den < 2^31 is then the low word's
 *  difference modulo 2^32. A larger quotient saturates either way. */
rfe_fix_t rfe_q31_div_round(int64_t num, rfe_fix_t den, uint32_t *sat)
{
    const uint32_t d32 = (uint32_t)den;
    const uint64_t d = (uint64_t)den;
    const uint64_t mag = rfe_q31_mag64_any(num);
    uint64_t q;
    uint64_t rem;
    if ((mag >> 32) < d) {
        const uint32_t q32 = rfe_q31_udiv64_32(mag, d32);
        const uint32_t rem32 = (uint32_t)mag - (q32 * d32); /* < den: exact modulo 2^32 */
        q = (uint64_t)q32;
        rem = (uint64_t)rem32;
    } else {
        q = mag / d;
        rem = mag % d;
    }
    if ((2u * rem) >= d) { /* rem < 2^31: no overflow */
        q += 1u;
    }
    return div_signed_sat(q, num, sat);
}

void rfe_q31_recip_init(rfe_q31_recip_t *r, rfe_fix_t den)
{
    const uint32_t d32 = (uint32_t)den; /* den > 0 */
    const uint32_t s = 32u - rfe_q31_bitlen32(d32);
    const uint32_t d = d32 << s;
    /* floor((2^64 - 1) / d) - 2^32 = floor(((2^32 - 1 - d) 2^32 + 2^32 - 1) / d): the high
     * word ~d is below d (d >= 2^31), so the quotient fits 32 bits */
    const uint32_t nd = ~d;
    const uint64_t top = (uint64_t)nd << 32;
    r->den = d32;
    r->d = d;
    r->s = s;
    r->v = rfe_q31_udiv64_32(top | (uint64_t)0xFFFFFFFFu, d);
}

/* mag = |num| < den 2^32: u = mag 2^s < d 2^32 (u1 < d), so Moller-Granlund's algorithm 4
 * gives q = floor(u / d) = floor(mag / den) and the remainder R = (mag mod den) 2^s: the
 * candidate q1 = (high word of v u1 + u) + 1 is q, q + 1 or (rarely) q - 1, the first test
 * (R > low word) takes one off, the second (R >= d) adds one. Rounded half up on the
 * magnitude as rfe_q31_div_round (2 rem >= den <=> R >= d - R), then saturated. A quotient
 * of 2^32 or more (mag >> 32 >= den) saturates there too, and does here without dividing. */
rfe_fix_t rfe_q31_div_round_by(int64_t num, const rfe_q31_recip_t *r, uint32_t *sat)
{
    const uint64_t mag = rfe_q31_mag64_any(num);
    const uint32_t hi = (uint32_t)(mag >> 32);
    const uint32_t lo = (uint32_t)mag;
    uint64_t q;
    if (hi >= r->den) {
        q = (uint64_t)1 << 32;
    } else {
        const uint32_t u1 = (r->s == 0u) ? hi : ((hi << r->s) | (lo >> (32u - r->s)));
        const uint32_t u0 = lo << r->s;
        const uint64_t p = rfe_fix_umul32x32(r->v, u1) + ((((uint64_t)u1) << 32) | u0);
        uint32_t q1 = (uint32_t)(p >> 32) + 1u;
        uint32_t rem = u0 - (q1 * r->d);
        if (rem > (uint32_t)p) {
            q1 -= 1u;
            rem += r->d;
        }
        if (rem >= r->d) {
            q1 += 1u;
            rem -= r->d;
        }
        q = (uint64_t)q1;
        if (rem >= (r->d - rem)) {
            q += 1u;
        }
    }
    return div_signed_sat(q, num, sat);
}

/* ---- the estimators' angle functions (fxmath_internal_q31.h) ------------------------------ */

/* pi in Q31, round(pi 2^31) = round(6746518852.26). */
#define PI_Q31 INT64_C(6746518852)

/*
 * atan2(y, x) in Q29 over the whole plane, from rfe_q31_atan2_quad1 on the magnitudes.
 * Scaling: the magnitudes (|.| <= 2^62) are brought by one common shift to <= 2^30 (exact when
 * both are already; otherwise each is rounded by <= 1/2 with the larger >= 2^29, which turns
 * the vector by <= (sqrt(2)/2) 2^-29 = 1.317e-9 rad). The first-quadrant angle a (Q31, error
 * <= 1.211e-9 rad) is mirrored to pi - a for x < 0 (pi in Q31, 0.26 2^-31 off), rounded half up
 * to Q29 (<= 2^-30 = 9.31e-10) and signed by y. Total <= 1.317e-9 + 1.211e-9 + 9.31e-10 +
 * 1.3e-10 = 3.59e-9 rad (1.93 LSB of Q29); 2.27e-9 when both |x|, |y| <= 2^30. The result is in
 * [-round(pi 2^29), round(pi 2^29)]; (0, 0) -> 0, (0, x < 0) -> +pi.
 */
int32_t rfe_q31_atan2_q29(int64_t y, int64_t x)
{
    const uint64_t mx = rfe_q31_mag64(x);
    const uint64_t my = rfe_q31_mag64(y);
    const unsigned int sh = rfe_q31_norm_shift((mx > my) ? mx : my, 30u);
    const uint32_t xs = (uint32_t)rfe_q31_shr_to32((int64_t)mx, sh); /* <= 2^30 */
    const uint32_t ys = (uint32_t)rfe_q31_shr_to32((int64_t)my, sh);
    int64_t a = (int64_t)rfe_q31_atan2_quad1(ys, xs); /* Q31, [0, pi/2] */

    if (x < 0) {
        a = PI_Q31 - a;
    }
    a = (a + 2) / 4; /* a >= 0: half up to Q29, <= round(pi 2^29) */
    return (int32_t)((y < 0) ? -a : a);
}

/*
 * sin and cos of every int32 angle in Q29 (|a| <= 4 rad), in Q30, from rfe_q31_sin_q55 on
 * [0, pi]: with p = |a| in Q55 (exact),
 *   sin p = sin_q55(p) for p <= pi, else -sin_q55(p - pi)  (p - pi <= 0.86 rad);
 *   cos p = sin_q55(pi/2 - p) for p <= pi/2, else -sin_q55(p - pi/2)  (<= 2.43 rad <= pi);
 * then sin takes the sign of a. pi and pi/2 in Q55 are 2^-56 off. Error <= 6.15e-10 + 2^-56
 * < 6.16e-10 (0.66 LSB of Q30) each.
 */
void rfe_q31_sincos_q29(int32_t a, int32_t *s, int32_t *c)
{
    const int64_t p = ((a < 0) ? -(int64_t)a : (int64_t)a) * rfe_q31_pow2(26u); /* Q55, <= 2^57 */
    const int32_t sm = (p <= PI_Q55) ? rfe_q31_sin_q55(p) : -rfe_q31_sin_q55(p - PI_Q55);

    *c = (p <= HALF_PI_Q55) ? rfe_q31_sin_q55(HALF_PI_Q55 - p)
                            : -rfe_q31_sin_q55(p - HALF_PI_Q55);
    *s = (a < 0) ? -sm : sm;
}

/*
 * tan(a) in Q26 for |a| <= 1.5 rad (Q29): s / c of the Q30 sine and cosine of |a| (each off by
 * eps <= 6.16e-10, c >= cos 1.5 - eps > 0), exactly rounded (rfe_q31_div_round), signed by a.
 * With s = sin + e1, c = cos + e2: s/c - tan = (e1 - tan e2) / c, so the error is
 *   <= 2^-27 + eps (1 + |tan a|) / (cos a - eps),
 * 8.1e-9 (0.54 LSB) at 0, 9.7e-9 at 0.9 rad, 3.2e-8 at 1.4 rad (tan 5.8), 1.39e-7 at 1.5 rad
 * (tan 14.1); half a step of the Q29 input moves tan by (1 + tan^2) 2^-30, about as much
 * (3.2e-8 at 1.4 rad, 1.86e-7 at 1.5 rad). |tan| <= 14.11 < 2^4: no saturation.
 */
int32_t rfe_q31_tan_q29(int32_t a)
{
    const int64_t p = ((a < 0) ? -(int64_t)a : (int64_t)a) * rfe_q31_pow2(26u); /* Q55 */
    const int32_t s = rfe_q31_sin_q55(p);
    const int32_t c = rfe_q31_sin_q55(HALF_PI_Q55 - p); /* >= 75.9e6 for |a| <= 1.5 rad */
    uint32_t scratch = 0u;
    const int32_t t = rfe_q31_div_round((int64_t)s * rfe_q31_pow2(26u), c, &scratch);

    return (a < 0) ? -t : t;
}
