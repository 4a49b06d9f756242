/**
 * @file qr_q31.c
 * @brief Householder Tria() and triangular solves on int32 Q values (the twin of qr_flt.c).
 *
 * Tria works row by row on the unreduced part ("tail", columns k..cols-1 at reflection k) of
 * every remaining row, each in its own power-of-two scale: the stored integer w stands for
 * w 2^-e_i LSB of the input format. Before reflection k every tail is rescaled so that its
 * norm lies in [2^29, 2^30) (block scaling), so whatever the magnitude of a row, its
 * remaining part is always carried with ~30 significant bits. Bounds used below, for a tail
 * a of L <= RFE_TRIA_COLS_MAX = 24 elements with |a| < 2^30 (+ a few units of rounding):
 *  - sum of squares of a normalised tail < 2^60 + 2^32: exact in uint64;
 *  - v = x + sign(x0) |x| e0: |v0| <= 2 |x| < 2^31, v.v = 2 |x| (|x| + |x0|) < 2^62;
 *  - a.v: |a.v| <= |a| |v| < 2^61 (every partial sum too, by Cauchy-Schwarz): exact in int64;
 *  - c = 2 a.v / v.v, |c| <= 2 |a| / |v| < 4 (|v| >= |x| >= 2^29): in Q30 below 2^32, and
 *    |c v_j| <= 2 |a|, so the Q30 product c v_j stays below 2^62.
 */
#include "rfe/component/qr_q31.h"

#include "numerics/internal_q31.h"

#define AT(M, ld, i, j) ((M)[((i) * (ld)) + (j)])

/* Target of the block scaling: the norm of every tail in [2^NORM_LO, 2^(NORM_LO + 1)). */
#define NORM_LO 29
/* Fractional bits of the reflection coefficient c. */
#define C_FRAC 30u

/* The sum of squares of t[0..len), exactly in two uint64 limbs (each square <= 2^62, at
 * most 24 of them): the low one returned, carries added to *hi. */
#if RFE_FIX_MUL64_W16
static uint64_t tail_squares(const rfe_fix_t *t, size_t len, uint64_t *hi)
{
    uint64_t lo = 0u;
    size_t j;
    for (j = 0u; j < len; ++j) {
        const uint64_t sq = (uint64_t)rfe_fix_mul32x32(t[j], t[j]); /* <= 2^62 */
        lo += sq;
        if (lo < sq) {
            *hi += 1u;
        }
    }
    return lo;
}
#else
/* Where the core multiplies 32 x 32 -> 64 (not the M0+): summed as s + c 2^63 with
 * s < 2^63: s + sq < 2^63 + 2^62 never wraps, and its top bit moves into c (a shift and a
 * mask a square, where the carry test on the wrapped sum made GCC form each square twice:
 * M4 -340 instructions a paper step; the M0+ form above is the cheaper there, +900); then
 * lo = s + (c mod 2) 2^63 and hi += c / 2, the same two limbs. */
static uint64_t tail_squares(const rfe_fix_t *t, size_t len, uint64_t *hi)
{
    const uint64_t top = ((uint64_t)1) << 63;
    uint64_t s = 0u;
    uint32_t c = 0u; /* at most 24 */
    uint32_t ch;
    uint64_t c0;
    size_t j;
    for (j = 0u; j < len; ++j) {
        s += (uint64_t)rfe_fix_mul32x32(t[j], t[j]); /* <= 2^62 */
        c += (uint32_t)(s >> 63);
        s &= top - 1u;
    }
    ch = c >> 1;
    c0 = (uint64_t)c & 1u;
    *hi += (uint64_t)ch;
    return s | (c0 << 63);
}
#endif

/* The sum of squares of a tail of norm below 2^30 + 11 (normed in tail_shift): below 2^61,
 * one uint64 limb holds it and no partial sum carries. */
static uint64_t tail_squares_normed(const rfe_fix_t *t, size_t len)
{
    uint64_t s = 0u;
    size_t j;
    for (j = 0u; j < len; ++j) {
        s += (uint64_t)rfe_fix_mul32x32(t[j], t[j]); /* <= 2^62 */
    }
    return s;
}

/* Shift s that brings the norm of t[0..len) into [2^29, 2^30): s = 29 - floor(log2 |t|).
 * Returns 0 (and leaves *shift alone) for an all-zero tail. *ss: the low limb of the sum of
 * squares (the whole sum when the returned shift is >= 0:
 * the norm is then below 2^30, the sum below 2^60). At reflection k >= 1 (tria_core_q31) the
 * tail's norm is below 2^30 + 11 and its sum of squares below 2^61, summed in one limb (the
 * same integers): row i's tail there is a part of the tail that reflection k - 1 found
 * normalised (norm below 2^30 + 3, sub_round_c) and then left
 * alone or reflected; the exact reflection keeps the norm, and each computed element is
 * within 1.51 of the exact one (the rounding of c, below 1.01, and of the product, 1/2;
 * sub_round_c), so the norm stays below 2^30 + 3 + 1.51 sqrt(24) < 2^30 + 11
 * (test_qr_bound_q31.c checks the sums against the two-limb form). */
static int tail_shift(const rfe_fix_t *t, size_t len, size_t k, int *shift, uint64_t *ss)
{
    uint64_t hi = 0u;
    const uint64_t lo = (k != 0u) ? tail_squares_normed(t, len) : tail_squares(t, len, &hi);
    unsigned int bits;
    unsigned int half;
    *ss = lo;
    if ((hi == 0u) && (lo == 0u)) {
        return 0;
    }
    /* bit length of the 128-bit sum; floor(log2 sqrt(ss)) = floor((bits - 1) / 2) */
    bits = (hi != 0u) ? (64u + rfe_q31_bitlen64(hi)) : rfe_q31_bitlen64(lo);
    half = (bits - 1u) / 2u;
    *shift = NORM_LO - (int)half;
    return 1;
}

/* t[0..len) *= 2^s: exact for s > 0 (the result is below 2^30 by the choice of s), rounded
 * half up for s < 0. */
static void scale_tail(rfe_fix_t *t, size_t len, int s)
{
    size_t j;
    if (s > 0) {
        /* s <= 29 (the tail's norm is at least each |t[j]| >= 1 and ends below 2^30), and
         * every product is below 2^30: one 32-bit multiplication each, exact */
        const int32_t p2 = (int32_t)rfe_q31_pow2((unsigned int)s);
        for (j = 0u; j < len; ++j) {
            t[j] = t[j] * p2;
        }
    } else if (s < 0) {
        for (j = 0u; j < len; ++j) {
            t[j] = rfe_fix_shr_round(t[j], (unsigned int)(-s));
        }
    } else {
        /* already in range */
    }
}

/* A working value w of scale e (w 2^-e LSB) rounded into the output format, saturating. Every
 * w is an int32 (a tail element, or a diagonal entry: x0 or the norm of a normalised tail,
 * below 2^30 + 3): rounded down in 32-bit operations (rfe_fix_shr_round, which never
 * saturates), the integer the int64 narrowing gave (~30 instructions fewer a call on the
 * Cortex-M4, whose variable 64-bit shift it avoids). */
static rfe_fix_t to_output(rfe_fix_t w, int e, uint32_t *sat)
{
    rfe_fix_t r;
    if (e >= 0) {
        r = rfe_fix_shr_round(w, (unsigned int)e);
    } else {
        r = rfe_fix_shl(w, (unsigned int)(-e), sat);
    }
    return r;
}

#if RFE_FIX_MUL64_W16
#if defined(__GNUC__)
/* MISRA-DEV-02: a GNU attribute (Rule 1.2, language extension), only under __GNUC__ */
#define QR_DIV_OUTLINE __attribute__((noinline))
#else
#define QR_DIV_OUTLINE
#endif
/* One 16-bit digit of the Cortex-M0+'s long division below: q = floor(R 2^16 / D) for
 * R < D, D in [2^62, 2^63) (both as 32-bit words), and R <- R 2^16 - q D. Knuth's algorithm D
 * (TAOCP vol. 2, 4.3.1) in base b = 2^16 with the divisor's top digit vt = floor(D / 2^47) in
 * [2^15, 2^16) (normalised): q^ = floor(ut / vt) of the dividend's top ut = floor(R / 2^31)
 * (< 2^32), lowered while q^ >= b or q^ v2 > b r^ + u2 (v2, u2 the next digits, r^ = ut -
 * q^ vt), at most twice as in rfe_q31_udiv64_32_digits (ut <= vt b + v2, so q^ <= b + 1, and
 * the test stops once r^ reaches b; q^ v2 is formed only below b: < 2^32). After that test q^
 * is q or q + 1 (Knuth, step D3), so T = R 2^16 - q^ D lies in [-D, D), inside int64
 * (D < 2^63): it is formed modulo 2^64 in two words (q^ D from three 32-bit products, q^ <=
 * 2^16: q^ times each 16-bit half of D's low word below 2^32, its high word's only modulo
 * 2^32), and a negative T (the top bit) is the one add-back, q^ - 1. Inlined into
 * div_shl32's loop (the words then stay in registers: 48 B less than a call by pointers). */
static RFE_FIX_INLINE_ALWAYS uint32_t div_digit16(uint32_t *rh, uint32_t *rl, uint32_t dh, uint32_t dl)
{
    const uint32_t base = 65536u;
    const uint32_t vt = dh >> 15;
    const uint32_t v2 = ((dh << 1) | (dl >> 31)) & 0xFFFFu;
    const uint32_t ut = (*rh << 1) | (*rl >> 31);
    const uint32_t u2 = (*rl >> 15) & 0xFFFFu;
    uint32_t q = ut / vt;
    uint32_t rr = ut - (q * vt);
    uint32_t plo;
    uint32_t pmid;
    uint32_t lo;
    uint32_t hi;
    uint32_t tl;
    uint32_t th;
    if ((q >= base) || ((q * v2) > ((base * rr) + u2))) {
        q -= 1u;
        rr += vt;
        if ((rr < base) && ((q >= base) || ((q * v2) > ((base * rr) + u2)))) {
            q -= 1u;
        }
    }
    plo = q * (dl & 0xFFFFu);
    pmid = q * (dl >> 16);
    lo = plo + (pmid << 16);
    hi = ((q * dh) + (pmid >> 16)) + ((lo < plo) ? 1u : 0u);
    tl = *rl << 16;
    th = (*rh << 16) | (*rl >> 16);
    *rl = tl - lo;
    *rh = (th - hi) - ((tl < lo) ? 1u : 0u);
    if ((*rh >> 31) != 0u) { /* T < 0: q^ was one too large */
        const uint32_t sl = *rl + dl;
        *rh = (*rh + dh) + ((sl < dl) ? 1u : 0u);
        *rl = sl;
        q -= 1u;
    }
    return q;
}

/* The Cortex-M0+ (RFE_FIX_MUL64_W16): round(n 2^32 / d) half up for 0 < d < 2^63, n < d 2^31,
 * as rfe_q31_div_shl32_round elsewhere but in 32-bit words, which the Thumb-1 core keeps in
 * its registers: the whole part (Tria's is 0 or 1: |c| < 4; the 64-bit division only where it
 * is not 0), then the 32 bits of floor(r 2^32 / d) (r < d) as two 16-bit digits of the long
 * division by d 2^s in [2^62, 2^63) (div_digit16: one 32-bit division each, ~300
 * instructions a call where the bit-by-bit division it replaced took ~500). The same integer
 * (test/numerics/w16/test_qr_div_w16_q31.c builds this file with RFE_FIX_MUL64_W16 = 1 and
 * checks both forms against the int128 quotient; make pil, bit-identical on the M0+). Out of
 * line: one copy for Tria's one call site, its words in the Thumb-1 core's low registers. */
static QR_DIV_OUTLINE uint64_t div_shl32(uint64_t n, uint64_t d)
{
    uint32_t dh = (uint32_t)(d >> 32);
    uint32_t dl = (uint32_t)d;
    uint32_t q0 = 0u; /* the whole part, below 2^31 (n < d 2^31) */
    uint64_t r = n;
    uint32_t rh;
    uint32_t rl;
    uint32_t q;
    uint32_t half;
    uint32_t odd;
    unsigned int i;
    if (n >= d) {
        q0 = (uint32_t)(n / d);
        r = n % d;
    }
    rh = (uint32_t)(r >> 32);
    rl = (uint32_t)r;
    /* d and r times 2^s, d 2^s in [2^62, 2^63) (d < 2^63), in words: 31 bits at once where
     * d < 2^32 (then r < 2^32 too), then bit by bit (Tria's v.v >= 2^58: four steps at most;
     * no bit length, whose 64-bit form this object then stopped inlining into Tria) */
    if (dh == 0u) {
        dh = dl >> 1;
        dl <<= 31;
        rh = rl >> 1;
        rl <<= 31;
    }
    while ((dh >> 30) == 0u) {
        dh = (dh << 1) | (dl >> 31);
        dl <<= 1;
        rh = (rh << 1) | (rl >> 31);
        rl <<= 1;
    }
    q = 0u;
    for (i = 0u; i < 2u; ++i) {
        q = (q << 16) | div_digit16(&rh, &rl, dh, dl);
    }
    /* (q0 2^32 + q + 1) / 2, floored, without the 33-bit sum */
    half = q >> 1;
    odd = q & 1u;
    return (((uint64_t)q0 << 31) + (uint64_t)half) + (uint64_t)odd;
}
#else
/* Elsewhere one digit of Knuth's long division (internal_q31.h). */
static inline uint64_t div_shl32(uint64_t n, uint64_t d)
{
    return rfe_q31_div_shl32_round(n, d);
}
#endif

/* c x for c = sign(dot) cm and an int32 x (|c x| < 2^62, above). Where the core has no
 * 32 x 32 -> 64 multiply (RFE_FIX_MUL64_W16, fixed.h) and cm < 2^32 (|c| < 4 in Q30; a
 * rounding up to 4 takes the int64 product), the magnitudes' product in 32-bit halves with
 * the sign applied after (cm |x| < 2^63 converts exactly); else the int64 product. The same
 * integer either way. */
static inline int64_t mul_c_x(int64_t dot, uint64_t cm, rfe_fix_t x)
{
    const int64_t c = (dot < 0) ? -(int64_t)cm : (int64_t)cm;
    int64_t r;
#if RFE_FIX_MUL64_W16
    if ((cm >> 32) == 0u) {
        const uint32_t ux = (uint32_t)x;
        const uint32_t nx = 0u - ux;
        const uint32_t mx = (x < 0) ? nx : ux;
        const int64_t p = (int64_t)rfe_fix_umul32x32((uint32_t)cm, mx);
        r = ((dot < 0) != (x < 0)) ? -p : p;
    } else {
        r = c * (int64_t)x;
    }
#else
    r = c * (int64_t)x;
#endif
    return r;
}

/* a - round(p / 2^C_FRAC) (half up) for |p| < 2^62: a reflected element. No saturation is
 * needed, by this bound (|x| the norm of row k's tail, |a| that of row i's, both normalised):
 *  - after scale_tail every tail's norm is below 2^30 + 3 (chosen below 2^30, then each
 *    element rounded by at most 1/2, L <= 24 of them: sqrt(24) / 2 < 3);
 *  - the exact reflection is orthogonal, so every element of the exact result a - c v has
 *    magnitude at most |a - c v| = |a| < 2^30 + 3;
 *  - the computed element differs from it by the rounding of c (at most 2^-31 in Q30 units
 *    of 1, times |v_j| <= |v| <= 2 |x| < 2^31 + 6: below 1.01) and that of the product
 *    (1/2): |result| < 2^30 + 5, far inside int32.
 * So sat32 never bit in the int64 form this replaces (sat32(a - shr64_round(p, 30)), which
 * counted no saturation either), and the difference is exact modulo 2^32: only the low word
 * of round(p / 2^30) = floor((p + 2^29) / 2^30) is needed, (w_lo >> 30) | (w_hi << 2) of
 * w = p + 2^29 (no overflow: |p| < 2^62). The same integer, a quarter of the instructions.
 * test/numerics/w16/test_qr_bound_q31.c checks the bound and the integer on every element
 * of every reflection of Tria's reduction over extreme and random inputs. */
static RFE_FIX_INLINE_ALWAYS rfe_fix_t sub_round_c(rfe_fix_t a, int64_t p)
{
    const int64_t ph = p + rfe_q31_pow2(C_FRAC - 1u);
    const uint64_t w = (uint64_t)ph;
    const uint32_t lo = (uint32_t)w;
    const uint32_t hi = (uint32_t)(w >> 32);
    const uint32_t ql = (lo >> C_FRAC) | (hi << (32u - C_FRAC));
    const uint32_t d = (uint32_t)a - ql; /* the result modulo 2^32 */
    /* its two's-complement value, without an implementation-defined conversion */
    const int64_t wrap = ((d >> 31) != 0u) ? rfe_q31_pow2(32u) : 0;
    const int64_t r = (int64_t)d - wrap;
    return (rfe_fix_t)r;
}

/* a[j] <- a[j] - round(c x[j] / 2^C_FRAC), j < n, c = sign(dot) cm. Where the core has a
 * 32 x 32 -> 64 multiply (not RFE_FIX_MUL64_W16) and |c| < 2^31 (|c| < 2 in Q30, most rows),
 * c is an int32 and each product one SMULL-class multiply (the same integer as mul_c_x's
 * int64 product); else mul_c_x. */
static inline void update_tail(rfe_fix_t *a, const rfe_fix_t *x, size_t n, int64_t dot,
                               uint64_t cm)
{
    size_t j;
#if !RFE_FIX_MUL64_W16
    if ((cm >> 31) == 0u) {
        const rfe_fix_t c32 = (dot < 0) ? -(rfe_fix_t)cm : (rfe_fix_t)cm;
        for (j = 0u; j < n; ++j) {
            a[j] = sub_round_c(a[j], rfe_fix_mul32x32(c32, x[j]));
        }
        return;
    }
#endif
    for (j = 0u; j < n; ++j) {
        a[j] = sub_round_c(a[j], mul_c_x(dot, cm, x[j]));
    }
}

/* Reflection k, on normalised tails: row k's tail x (length len, starting at column k) is
 * mapped onto (-sign(x0) |x|, 0, ..., 0) and every other row i > k with a non-zero tail gets
 * a <- a - c v, c = 2 a.v / v.v, v = x + sign(x0) |x| e0. Returns the unrounded diagonal
 * entry (scale of row k): -sign(x0) |x|, or x0 itself when it is the only non-zero. ssk:
 * |x|^2 (< 2^60 + 2^32 after the normalisation) when the caller knows it, else 0. */
static rfe_fix_t reflect(rfe_fix_t *A, size_t rows, size_t lda, size_t k, size_t len,
                         uint64_t ssk, const int *nonzero)
{
    rfe_fix_t *x = &AT(A, lda, k, k);
    uint64_t ss = ssk;
    uint64_t x0sq;
    int64_t norm;
    int64_t diag;
    int64_t v0;
    uint64_t vtv;
    size_t i;
    size_t j;

    if (ss == 0u) { /* not known to the caller: summed here (a non-zero tail's is > 0) */
        for (j = 0u; j < len; ++j) {
            ss += (uint64_t)rfe_fix_mul32x32(x[j], x[j]); /* each square <= 2^62 */
        }
    }
    x0sq = (uint64_t)rfe_fix_mul32x32(x[0], x[0]);
    if (ss == x0sq) {
        /* Only x0 is non-zero: the reflection would negate column k and the sign fix-up
         * negate it back where x0 > 0; skipping it gives the same factor, exactly (a
         * lower-triangular input is its own Tria up to column signs). */
        return x[0];
    }
    norm = (int64_t)rfe_q31_sqrt_round(ss);
    v0 = (x[0] < 0) ? ((int64_t)x[0] - norm) : ((int64_t)x[0] + norm);
    /* v.v = |x|^2 - x0^2 + v0^2, exact */
    vtv = (ss - x0sq) +
          (rfe_q31_mag64_any(v0) * rfe_q31_mag64_any(v0));
    for (i = k + 1u; i < rows; ++i) {
        if (nonzero[i] != 0) {
            rfe_fix_t *a = &AT(A, lda, i, k);
            int64_t dot = (int64_t)a[0] * v0;
            uint64_t cm;
            int64_t c;
            for (j = 1u; j < len; ++j) {
                dot += rfe_fix_mul32x32(a[j], x[j]);
            }
            /* c in Q30: round(2 a.v 2^30 / v.v), magnitude below 2^32 */
            cm = div_shl32(rfe_q31_mag64_any(dot), vtv); /* C_FRAC + 1 = 31 */
            c = (dot < 0) ? -(int64_t)cm : (int64_t)cm;
            a[0] = sub_round_c(a[0], c * v0);
            update_tail(&a[1], &x[1], len - 1u, dot, cm);
        }
    }
    for (j = 0u; j < len; ++j) {
        x[j] = 0;
    }
    /* norm <= 2^30 + 3 (the normalised tail's, above): an int32 */
    diag = (v0 < 0) ? norm : -norm;
    return (rfe_fix_t)diag;
}

/* Row k's sum of squares ss (tail_shift's, before scale_tail by 2^s) for reflect: scaled up
 * by 2^s exactly, every square by 2^2s (< 2^60 after); 0 where it was scaled down (rounded):
 * reflect sums it again then. */
static uint64_t scaled_squares(uint64_t ss, int s)
{
    uint64_t r = 0u;
    if (s >= 0) {
        const unsigned int s2 = 2u * (unsigned int)s;
        r = ss << s2;
    }
    return r;
}

/* Non-negative diagonal of the lower-triangular rows x rows S in A: flipping a column's sign
 * leaves S S^T unchanged (entries are symmetric-saturated, so negation is exact). The flip is
 * decided on the sign of the unrounded diagonal (flip[k]), so that a diagonal entry that
 * rounds to 0 still gets the column sign of the exact factor. */
static void make_diagonal_nonnegative_q31(rfe_fix_t *A, size_t rows, size_t lda, const int *flip)
{
    size_t i;
    size_t k;
    for (k = 0u; k < rows; ++k) {
        if (flip[k] != 0) {
            for (i = k; i < rows; ++i) {
                AT(A, lda, i, k) = -AT(A, lda, i, k);
            }
        }
    }
}

/* Tria of the checked rows x cols A. tri = 0: a dense A, every row's tail is columns
 * k..cols-1. tri = 1: A = [B, L], L lower-triangular rows x rows (rfe_qr_tria_lt_q31): with
 * t = cols - rows, row i is zero right of column t + i before every reflection (reflection
 * j < k mixes only columns j..t+j, row j's tail), so the tails end there. Every operation
 * of the dense reduction on those zeros is exact (a square or product 0, a scaled 0, an
 * update by c 0 = 0): the shorter tails give the same integers. */
static void tria_core_q31(rfe_fix_t *A, size_t rows, size_t cols, size_t lda, int tri,
                          uint32_t *sat)
{
    int e[RFE_N_MAX] = {0}; /* scale of each row's tail (a fixed-size initialiser: no memset
                             * call, which a loop over the rows became) */
    int nonzero[RFE_N_MAX] = {0}; /* tail of the row not all zero (set before each read) */
    int flip[RFE_N_MAX];    /* unrounded diagonal entry negative */
    uint32_t count = 0u;
    size_t i;
    size_t k;

    /* A^T = Q R  <=>  A Q = R^T = [S 0]: zero each row's tail right of the diagonal. */
    for (k = 0u; k < rows; ++k) {
        uint64_t ssk = 0u; /* sum of squares of row k's normalised tail */
        for (i = k; i < rows; ++i) {
            int s = 0;
            uint64_t ss = 0u;
            rfe_fix_t *t = &AT(A, lda, i, k);
            const size_t len = ((tri != 0) ? ((cols - rows) + i + 1u) : cols) - k;
            nonzero[i] = tail_shift(t, len, k, &s, &ss);
            if (nonzero[i] != 0) {
                scale_tail(t, len, s);
                e[i] += s;
            }
            if (i == k) {
                ssk = scaled_squares(ss, s);
            }
        }
        flip[k] = 0;
        if (nonzero[k] != 0) {
            const size_t len = ((tri != 0) ? ((cols - rows) + k + 1u) : cols) - k;
            const rfe_fix_t diag = reflect(A, rows, lda, k, len, ssk, nonzero);
            AT(A, lda, k, k) = to_output(diag, e[k], &count);
            if (diag < 0) {
                flip[k] = 1;
            }
        }
        /* nonzero[k] == 0: the tail is already zero (rank-deficient input); S(k,k) = 0. */
        for (i = k + 1u; i < rows; ++i) {
            AT(A, lda, i, k) = to_output(AT(A, lda, i, k), e[i], &count);
        }
    }
    make_diagonal_nonnegative_q31(A, rows, lda, flip);
    rfe_q31_sat_add(sat, count);
}

/* The argument checks of both Tria entries. */
static rfe_status_t check_tria_q31(const rfe_fix_t *A, size_t rows, size_t cols, size_t lda,
                                   const uint32_t *sat)
{
    if ((A == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((rows == 0u) || (rows > (size_t)RFE_N_MAX) || (cols < rows) ||
        (cols > RFE_TRIA_COLS_SZ) || (lda < cols)) {
        return RFE_ERR_SIZE;
    }
    return RFE_OK;
}

rfe_status_t rfe_qr_tria_q31(rfe_fix_t *A, size_t rows, size_t cols, size_t lda, uint32_t *sat)
{
    const rfe_status_t st = check_tria_q31(A, rows, cols, lda, sat);
    if (st == RFE_OK) {
        tria_core_q31(A, rows, cols, lda, 0, sat);
    }
    return st;
}

rfe_status_t rfe_qr_tria_lt_q31(rfe_fix_t *A, size_t rows, size_t cols, size_t lda,
                                uint32_t *sat)
{
    const rfe_status_t st = check_tria_q31(A, rows, cols, lda, sat);
    if (st == RFE_OK) {
        tria_core_q31(A, rows, cols, lda, 1, sat);
    }
    return st;
}

rfe_status_t rfe_qr_tria_pair_q31(rfe_fix_t *A, size_t n, size_t lda, uint32_t *sat)
{
    return rfe_qr_tria_lt_q31(A, n, 2u * n, lda, sat);
}

/* Shared checks of the triangular solves; all diagonal entries must be > 0. */
static rfe_status_t check_solve_q31(const rfe_fix_t *L, size_t n, size_t ldl, const rfe_fix_t *B,
                                    size_t ncols, size_t ldb, int shift, const uint32_t *sat)
{
    size_t i;
    if ((L == NULL) || (B == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((n == 0u) || (n > (size_t)RFE_N_MAX) || (ldl < n) || (ncols == 0u) || (ldb < ncols)) {
        return RFE_ERR_SIZE;
    }
    if ((shift < 0) || (shift > 31)) {
        return RFE_ERR_RANGE;
    }
    for (i = 0u; i < n; ++i) {
        if (AT(L, ldl, i, i) <= 0) {
            return RFE_ERR_NOT_POSITIVE_DEFINITE;
        }
    }
    return RFE_OK;
}

/* The reciprocals of the checked diagonal L_ii > 0 (i < n): every column divides by them
 * (rfe_q31_div_round_by, the same integers as rfe_q31_div_round). */
static void diag_recips_q31(const rfe_fix_t *L, size_t n, size_t ldl, rfe_q31_recip_t *rec)
{
    size_t i;
    for (i = 0u; i < n; ++i) {
        rfe_q31_recip_init(&rec[i], AT(L, ldl, i, i));
    }
}

#if RFE_FIX_MUL64_W16
/* The two substitutions in one body (checked arguments): trans = 0, L X = B, x_i for
 * i = 0..n-1 from the L_ij (j < i); trans = 1, L^T X = B, i = n-1..0 from the L_ji (j > i).
 * x_i = (b_i 2^shift - sum_j l_j x_j) / L_ii, the sum in ascending j: the numerator in
 * Q(qx + ql), b_i 2^shift <= 2^62, each product <= 2^62, summed with saturation. One body
 * for both, on the Cortex-M0+ only (RFE_FIX_MUL64_W16): 282 B less of its flash, ~800 more
 * instructions per paper step; elsewhere the two loops below, the same integers. */
static void solve_core_q31(const rfe_fix_t *L, size_t n, size_t ldl, rfe_fix_t *B, size_t ncols,
                           size_t ldb, int shift, int trans, uint32_t *sat)
{
    uint32_t count = 0u;
    rfe_q31_recip_t rec[RFE_N_MAX];
    size_t c;
    size_t u;
    size_t j;
    diag_recips_q31(L, n, ldl, rec);
    for (c = 0u; c < ncols; ++c) {
        for (u = 0u; u < n; ++u) {
            size_t i = u;
            size_t lo = 0u;
            size_t hi = u;
            size_t step = 1u;            /* l_j = l[j step]: L_ij, or L_ji for the transpose */
            const rfe_fix_t *l = &L[u * ldl];
            int64_t acc;
            if (trans != 0) {
                i = (n - 1u) - u;
                lo = i + 1u;
                hi = n;
                step = ldl;
                l = &L[i];
            }
            acc = (int64_t)AT(B, ldb, i, c) * rfe_q31_pow2((unsigned int)shift);
            for (j = lo; j < hi; ++j) {
                acc = rfe_fix_add64(acc, -rfe_fix_mul32x32(l[j * step], AT(B, ldb, j, c)), &count);
            }
            AT(B, ldb, i, c) = rfe_q31_div_round_by(acc, &rec[i], &count);
        }
    }
    rfe_q31_sat_add(sat, count);
}

rfe_status_t rfe_qr_solve_lower_q31(const rfe_fix_t *L, size_t n, size_t ldl, rfe_fix_t *B,
                                    size_t ncols, size_t ldb, int shift, uint32_t *sat)
{
    const rfe_status_t st = check_solve_q31(L, n, ldl, B, ncols, ldb, shift, sat);
    if (st == RFE_OK) {
        solve_core_q31(L, n, ldl, B, ncols, ldb, shift, 0, sat);
    }
    return st;
}

rfe_status_t rfe_qr_solve_lower_t_q31(const rfe_fix_t *L, size_t n, size_t ldl, rfe_fix_t *B,
                                      size_t ncols, size_t ldb, int shift, uint32_t *sat)
{
    const rfe_status_t st = check_solve_q31(L, n, ldl, B, ncols, ldb, shift, sat);
    if (st == RFE_OK) {
        solve_core_q31(L, n, ldl, B, ncols, ldb, shift, 1, sat);
    }
    return st;
}
#else
/* b 2^shift (0 <= shift <= 31) as an int64: one 32 x 32 -> 64 product by p2 = 2^shift as an
 * int32 where that fits (shift <= 30; a Cortex-M3/M4 SMULL, where the int64 product by
 * rfe_q31_pow2 became a variable 64-bit shift, ~10 instructions), else the int64 product. The
 * same integer. */
static inline int64_t scaled_rhs(rfe_fix_t b, int shift, rfe_fix_t p2)
{
    int64_t r;
    if (shift <= 30) {
        r = rfe_fix_mul32x32(b, p2);
    } else {
        r = (int64_t)b * rfe_q31_pow2((unsigned int)shift);
    }
    return r;
}

/* 2^shift as an int32 for scaled_rhs (0 where shift = 31, which does not use it). */
static rfe_fix_t rhs_p2(int shift)
{
    return (shift <= 30) ? (rfe_fix_t)rfe_q31_pow2((unsigned int)shift) : 0;
}

rfe_status_t rfe_qr_solve_lower_q31(const rfe_fix_t *L, size_t n, size_t ldl, rfe_fix_t *B,
                                    size_t ncols, size_t ldb, int shift, uint32_t *sat)
{
    uint32_t count = 0u;
    rfe_q31_recip_t rec[RFE_N_MAX];
    size_t c;
    size_t i;
    size_t j;
    const rfe_status_t st = check_solve_q31(L, n, ldl, B, ncols, ldb, shift, sat);
    rfe_fix_t p2;

    if (st != RFE_OK) {
        return st;
    }
    p2 = rhs_p2(shift);
    diag_recips_q31(L, n, ldl, rec);
    /* x_i = (b_i 2^shift - sum_{j<i} L_ij x_j) / L_ii, column by column; the numerator in
     * Q(qx + ql): b_i 2^shift <= 2^62, each product <= 2^62, summed with saturation. */
    for (c = 0u; c < ncols; ++c) {
        for (i = 0u; i < n; ++i) {
            int64_t acc = scaled_rhs(AT(B, ldb, i, c), shift, p2);
            for (j = 0u; j < i; ++j) {
                acc = rfe_fix_add64(acc, -rfe_fix_mul32x32(AT(L, ldl, i, j), AT(B, ldb, j, c)),
                                    &count);
            }
            AT(B, ldb, i, c) = rfe_q31_div_round_by(acc, &rec[i], &count);
        }
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}

rfe_status_t rfe_qr_solve_lower_t_q31(const rfe_fix_t *L, size_t n, size_t ldl, rfe_fix_t *B,
                                      size_t ncols, size_t ldb, int shift, uint32_t *sat)
{
    uint32_t count = 0u;
    rfe_q31_recip_t rec[RFE_N_MAX];
    size_t c;
    size_t j;
    const rfe_status_t st = check_solve_q31(L, n, ldl, B, ncols, ldb, shift, sat);
    rfe_fix_t p2;

    if (st != RFE_OK) {
        return st;
    }
    p2 = rhs_p2(shift);
    diag_recips_q31(L, n, ldl, rec);
    /* x_i = (b_i 2^shift - sum_{j>i} L_ji x_j) / L_ii, from the last row up. */
    for (c = 0u; c < ncols; ++c) {
        size_t up;
        for (up = 0u; up < n; ++up) {
            const size_t i = n - 1u - up; /* rows n-1 .. 0 */
            int64_t acc = scaled_rhs(AT(B, ldb, i, c), shift, p2);
            for (j = i + 1u; j < n; ++j) {
                acc = rfe_fix_add64(acc, -rfe_fix_mul32x32(AT(L, ldl, j, i), AT(B, ldb, j, c)),
                                    &count);
            }
            AT(B, ldb, i, c) = rfe_q31_div_round_by(acc, &rec[i], &count);
        }
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}
#endif
