/**
 * @file test_xf_q31.c
 * @brief The integer mantissa-exponent numbers of src/numerics/xf_q31.h (the fixed-point
 *        derivatives of the measurement model, docs/FIXED_POINT.md "Observer") against
 *        double: each operation within its stated 2^-30 relative rounding (a sum: 2^-29 of its
 *        larger operand), normalised results, and the edge cases (zeros, a division by 0,
 *        square roots at odd and even exponents, conversion to Q formats with rounding and
 *        saturation of both signs), on random operands over 2^+-80 from test_rng.h.
 */
#include "test_common.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "numerics/xf_q31.h"
#include "test_rng.h"

#define N_CASES 20000
/* One rounding to 30 significant bits, half up: <= 2^-30 of the result (2^-29.0 of the
 * normalised mantissa's lowest value); the bound allows that plus the operands' own. */
#define REL 1.0e-9
/* A sum: 2^-30 of its result, which is at most twice the larger operand. */
#define REL_SUM 1.9e-9

static double val(rfe_xf_t a) { return ldexp((double)a.m, a.e); }

static rfe_xf_t draw(void)
{
    const double m = rng_uniform();            /* (-1, 1) */
    const int e = (int)(rng_uniform() * 80.0); /* -80 .. 80 */
    return rfe_xf_make((int64_t)(m * 4.0e18), e - 62);
}

static void normalised(rfe_xf_t a)
{
    if (a.m != 0) {
        const int32_t mag = (a.m < 0) ? -a.m : a.m;
        assert_true((mag >= (1 << 29)) && (mag <= (1 << 30)));
    } else {
        assert_int_equal(a.e, 0);
    }
}

/* REQ: every operation within one rounding of its exact value, normalised (REQ-FXP-002's
 * integer math, here the derivatives' number type). */
/* REQ-FXP-002 REQ-MEAS-003 */
static void test_xf_operations(void **state)
{
    double worst = 0.0;
    int n;
    (void)state;
    rng_seed(0x3F5ull);
    for (n = 0; n < N_CASES; ++n) {
        const rfe_xf_t a = draw();
        const rfe_xf_t b = draw();
        const double va = val(a);
        const double vb = val(b);
        const rfe_xf_t p = rfe_xf_mul(a, b);
        const rfe_xf_t s = rfe_xf_add(a, b);
        const rfe_xf_t d = rfe_xf_sub(a, b);
        const rfe_xf_t q = rfe_xf_div(a, b);
        const rfe_xf_t r = rfe_xf_sqrt((a.m < 0) ? rfe_xf_neg(a) : a);
        const double big = fmax(fabs(va), fabs(vb));
        normalised(p);
        normalised(s);
        normalised(q);
        normalised(r);
        assert_true(fabs(val(p) - (va * vb)) <= REL * fabs(va * vb));
        assert_true(fabs(val(s) - (va + vb)) <= REL_SUM * big);
        assert_true(fabs(val(d) - (va - vb)) <= REL_SUM * big);
        assert_true(fabs(val(q) - (va / vb)) <= REL * fabs(va / vb));
        assert_true(fabs(val(r) - sqrt(fabs(va))) <= REL * sqrt(fabs(va)));
        assert_int_equal(rfe_xf_sign(a), (va > 0.0) ? 1 : -1);
        worst = fmax(worst, fabs(val(p) - (va * vb)) / fabs(va * vb));
    }
    printf("xf: %d cases, worst product error %.3g relative\n", N_CASES, worst);
}

/* REQ: a sum of RFE_XF_SUM_MAX terms, 1 to 8 of them non-zero (the observer's lateral rows over
 * the wheels), is within its stated bound of the exact sum: one rounding of the result (2^-30 of
 * it, REL) plus 8 2^(base - 1) for the terms rounded to base = the largest exponent minus 28, <=
 * 2^-55 of the largest term (a normalised term is >= 2^(29 + e)). The reference is the double sum,
 * whose own error is <= 7 2^-53 of the largest term: the check allows 2^-55 + 2^-50 of the largest
 * term besides REL of the result. Normalised results; all zeros give 0; terms spread over 2^+-80
 * (draw), of both signs, with exact cancellations (a term and its negative) and zeros.
 */
/* REQ-FXP-002 REQ-MEAS-003 */
static void test_xf_sum(void **state)
{
    double worst = 0.0;
    int n;
    (void)state;
    rng_seed(0x5E4ull);
    for (n = 0; n < N_CASES; ++n) {
        rfe_xf_t t[RFE_XF_SUM_MAX];
        const size_t cnt = 1u + ((size_t)n % RFE_XF_SUM_MAX);
        double exact = 0.0;
        double big = 0.0;
        rfe_xf_t r;
        size_t i;
        for (i = 0u; i < RFE_XF_SUM_MAX; ++i) {
            t[i] = rfe_xf_make(0, 0); /* unused terms: 0 */
        }
        for (i = 0u; i < cnt; ++i) {
            t[i] = draw();
            if ((n % 7) == 0) {
                t[i].e = t[0].e + (int)(i % 3u); /* close exponents: long carries */
            }
            if (((n % 5) == 0) && (i == 1u)) {
                t[i] = rfe_xf_neg(t[0]); /* cancellation */
            }
            if (((n % 11) == 0) && (i == 2u)) {
                t[i] = rfe_xf_make(0, 0);
            }
            exact += val(t[i]);
            big = fmax(big, fabs(val(t[i])));
        }
        r = rfe_xf_sum(t);
        normalised(r);
        {
            const double err = fabs(val(r) - exact);
            const double bound = (REL * fabs(exact)) + (ldexp(1.0, -50) * big);
            assert_true(err <= bound);
            worst = fmax(worst, err / bound);
        }
    }
    {
        const rfe_xf_t z[RFE_XF_SUM_MAX] = {{0, 0}, {0, 0}, {0, 0}, {0, 0},
                                            {0, 0}, {0, 0}, {0, 0}, {0, 0}};
        const rfe_xf_t r = rfe_xf_sum(z);
        assert_int_equal(r.m, 0);
        assert_int_equal(r.e, 0);
    }
    printf("xf sum: %d cases, worst error %.3g of its bound\n", N_CASES, worst);
}

/* REQ: zeros, a division by 0 (0, never called so), a sum across many decades, square roots
 * at odd and even exponents, and the conversion to a Q format: rounding, saturation of both
 * signs (counted), and the values too small for the format. */
/* REQ-FXP-001 REQ-FXP-008 REQ-MEAS-003 */
static void test_xf_edges(void **state)
{
    const rfe_xf_t zero = rfe_xf_make(0, 5);
    const rfe_xf_t one = rfe_xf_make(1, 0);
    uint32_t sat = 0u;
    (void)state;
    assert_int_equal(zero.m, 0);
    assert_int_equal(zero.e, 0);
    assert_int_equal(rfe_xf_add(zero, one).m, one.m);
    assert_int_equal(rfe_xf_add(one, zero).m, one.m);
    assert_int_equal(rfe_xf_div(one, zero).m, 0);
    assert_int_equal(rfe_xf_sqrt(zero).m, 0);
    assert_int_equal(rfe_xf_sqrt(rfe_xf_neg(one)).m, 0);
    assert_int_equal(rfe_xf_sign(zero), 0);
    assert_int_equal(rfe_q31_sign(-3), -1);
    /* a sum across 100 decades keeps the larger operand (the smaller rounds away) */
    assert_true(val(rfe_xf_add(one, rfe_xf_make(1, -100))) == 1.0);
    assert_true(val(rfe_xf_add(rfe_xf_make(1, -100), one)) == 1.0);
    assert_true(fabs(val(rfe_xf_sqrt(rfe_xf_make(2, 0))) - sqrt(2.0)) < 1e-9);
    assert_true(fabs(val(rfe_xf_sqrt(rfe_xf_make(8, 0))) - sqrt(8.0)) < 1e-8);
    assert_true(fabs(val(rfe_xf_sqrt(rfe_xf_make(3, -7))) - sqrt(3.0 / 128.0)) < 1e-9);
    /* to Q24: 1.5 exactly, -2.5 LSB rounds half up to -2, tiny to 0, huge saturates */
    assert_int_equal(rfe_xf_to_fix(rfe_xf_make(3, -1), 24, &sat), 3 << 23);
    assert_int_equal(rfe_xf_to_fix(rfe_xf_make(-5, -25), 24, &sat), -2);
    assert_int_equal(rfe_xf_to_fix(rfe_xf_make(1, -90), 24, &sat), 0);
    assert_int_equal(rfe_xf_to_fix(zero, 24, &sat), 0);
    assert_int_equal(sat, 0u);
    assert_int_equal(rfe_xf_to_fix(rfe_xf_make(1, 10), 24, &sat), INT32_MAX);
    assert_int_equal(rfe_xf_to_fix(rfe_xf_make(-1, 40), 24, &sat), -INT32_MAX);
    assert_int_equal(rfe_xf_to_fix(rfe_xf_make(1, 40), 24, &sat), INT32_MAX);
    assert_int_equal(sat, 3u);
    /* the fixed-point value of a Q format, exactly */
    assert_true(val(rfe_xf_of(-12345, 15)) == -12345.0 / 32768.0);
}

/* The quotient is rounded exactly as rfe_fix_div rounds the mantissas' quotient (its integer,
 * half up on the magnitude, at shift 30 when |a.m| < |b.m|, else 29): the same integers the
 * observer had when rfe_xf_div called rfe_fix_div, on random operands of every sign, equal
 * mantissas (the shift's boundary) and the mantissa range's ends (2^29, 2^30). */
static void test_xf_div_as_fix_div(void **state)
{
    const int32_t ends[4] = {1 << 29, (1 << 29) + 1, (1 << 30) - 1, 1 << 30};
    int n;
    (void)state;
    rng_seed(0x51Dull);
    for (n = 0; n < N_CASES + 16; ++n) {
        rfe_xf_t a = draw();
        rfe_xf_t b = draw();
        int32_t q = 0;
        uint32_t sat = 0u;
        int sh;
        rfe_xf_t want;
        rfe_xf_t got;
        if (n >= N_CASES) {
            /* the ends against each other, both signs of a */
            a.m = ((n & 1) != 0) ? -ends[(n / 4) % 4] : ends[(n / 4) % 4];
            b.m = ends[n % 4];
        } else if ((n % 7) == 0) {
            b.m = -a.m; /* equal magnitudes: shift 29 */
        } else {
            /* a.m, b.m as drawn */
        }
        if (b.m == 0) {
            continue; /* draw() gives 0 only for a zero mantissa; a division by 0 is test_xf_edges' */
        }
        sh = (((a.m < 0) ? -(int64_t)a.m : (int64_t)a.m) < ((b.m < 0) ? -(int64_t)b.m : (int64_t)b.m)) ? 30 : 29;
        assert_int_equal(rfe_fix_div(a.m, b.m, sh, &q, &sat), RFE_OK);
        assert_int_equal(sat, 0u);
        want = rfe_xf_make((int64_t)q, (a.e - b.e) - sh);
        got = rfe_xf_div(a, b);
        assert_int_equal(got.m, want.m);
        assert_int_equal(got.e, want.e);
    }
}

/* The normalisation as first written (rfe_fix_shr64_round to 30 bits, a multiplication
 * below): the reference for rfe_xf_make's 32-bit rounding. */
static rfe_xf_t make_ref(int64_t v, int e)
{
    rfe_xf_t r = {0, 0};
    if (v != 0) {
        const uint64_t mag = (v < 0) ? (uint64_t)(-v) : (uint64_t)v;
        unsigned int len = 0u;
        while ((len < 64u) && ((mag >> len) != 0u)) {
            ++len;
        }
        if (len > 30u) {
            r.m = (int32_t)rfe_fix_shr64_round(v, len - 30u);
            r.e = e + (int)(len - 30u);
        } else {
            r.m = (int32_t)(v * (int64_t)((uint64_t)1 << (30u - len)));
            r.e = e - (int)(30u - len);
        }
    }
    return r;
}

/* The sum as first written: both mantissas aligned at the larger exponent minus 31, the
 * smaller rounded half up when it lies more than 31 below (make_ref normalising). */
static rfe_xf_t add_ref(rfe_xf_t a, rfe_xf_t b)
{
    rfe_xf_t r;
    if (a.m == 0) {
        r = b;
    } else if (b.m == 0) {
        r = a;
    } else {
        const int base = ((a.e > b.e) ? a.e : b.e) - 31;
        int64_t v = 0;
        int k;
        for (k = 0; k < 2; ++k) {
            const rfe_xf_t x = (k == 0) ? a : b;
            const int s = x.e - base;
            v += (s >= 0) ? ((int64_t)x.m * (int64_t)((uint64_t)1 << (unsigned int)s))
                          : rfe_fix_shr64_round((int64_t)x.m, (unsigned int)(-s));
        }
        r = make_ref(v, base);
    }
    return r;
}

/* rfe_xf_make's rounding in 32 bits and rfe_xf_add's sum at the smaller operand's exponent
 * (both faster on the Cortex-M4) give the integers of the first forms above, bit for bit:
 * on every bit length 1 .. 63 of either sign with the rounding's tie and its neighbours in
 * the low bits, on random 64-bit values, and on sums of random operands whose exponents
 * differ by 0 .. 40 (both sides of d = 31, where the sum changes form), with equal and
 * opposite mantissas (cancellation to 0 and to few bits) and the mantissa range's ends. */
static void test_xf_make_add_as_before(void **state)
{
    const int32_t ends[4] = {1 << 29, (1 << 29) + 1, (1 << 30) - 1, 1 << 30};
    unsigned int len;
    int n;
    (void)state;
    rng_seed(0xADDull);
    for (len = 1u; len <= 63u; ++len) {
        const uint64_t top = (uint64_t)1 << (len - 1u);
        int k;
        for (k = 0; k < 64; ++k) {
            /* the low bits around the tie 2^(len - 31) of a rounding by len - 30 bits */
            const uint64_t tie = (len > 30u) ? ((uint64_t)1 << (len - 31u)) : 1u;
            const uint64_t low = (k < 8) ? ((tie + (uint64_t)k) - 4u)
                                         : (uint64_t)((rng_uniform() + 1.0) * 4.0e18);
            const uint64_t mag = top | (low & (top - 1u));
            int sgn;
            for (sgn = 0; sgn < 2; ++sgn) {
                const int64_t v = (sgn == 0) ? (int64_t)mag : -(int64_t)mag;
                const rfe_xf_t got = rfe_xf_make(v, 7);
                const rfe_xf_t want = make_ref(v, 7);
                assert_int_equal(got.m, want.m);
                assert_int_equal(got.e, want.e);
            }
        }
    }
    for (n = 0; n < 4 * N_CASES; ++n) {
        rfe_xf_t a = draw();
        rfe_xf_t b = draw();
        rfe_xf_t got;
        rfe_xf_t want;
        b.e = a.e - ((n / 4) % 41); /* d = 0 .. 40 */
        if ((n % 4) == 1) {
            b.m = -a.m;
        } else if ((n % 4) == 2) {
            a.m = ends[(n / 8) % 4];
            b.m = ((n % 8) < 4) ? -ends[(n / 32) % 4] : ends[(n / 32) % 4];
        } else {
            /* as drawn */
        }
        got = rfe_xf_add(a, b);
        want = add_ref(a, b);
        assert_int_equal(got.m, want.m);
        assert_int_equal(got.e, want.e);
        got = rfe_xf_add(b, a);
        assert_int_equal(got.m, want.m);
        assert_int_equal(got.e, want.e);
    }
}

/* The bit length every normalisation above starts from (internal_q31.h: one instruction where
 * the core counts leading zeros, the portable search elsewhere): for every length L, the
 * smallest (2^(L-1)), the largest (2^L - 1) and random values with bit L-1 set and lower bits
 * drawn have length L, which holds by construction; 0 has length 0. */
static void test_bitlen(void **state)
{
    unsigned int len;
    int k;
    (void)state;
    assert_int_equal(rfe_q31_bitlen32(0u), 0);
    assert_int_equal(rfe_q31_bitlen64(0u), 0);
    for (len = 1u; len <= 64u; ++len) {
        const uint64_t top = (uint64_t)1 << (len - 1u);
        const uint64_t low_mask = top - 1u;
        assert_int_equal(rfe_q31_bitlen64(top), len);
        assert_int_equal(rfe_q31_bitlen64(top | low_mask), len);
        if (len <= 32u) {
            assert_int_equal(rfe_q31_bitlen32((uint32_t)top), len);
            assert_int_equal(rfe_q31_bitlen32((uint32_t)(top | low_mask)), len);
        }
        for (k = 0; k < 50; ++k) {
            const uint64_t r = (uint64_t)((rng_uniform() + 1.0) * 9.0e18);
            const uint64_t v = top | (r & low_mask);
            assert_int_equal(rfe_q31_bitlen64(v), len);
            if (len <= 32u) {
                assert_int_equal(rfe_q31_bitlen32((uint32_t)v), len);
            }
        }
    }
}

/* One case of the unsigned rounding shift (0 <= s <= 63): floor(u / 2^s + 1/2) from the
 * quotient and the remainder (q + 1 when the remainder reaches half the divisor; u at s = 0),
 * and for u < 2^63 the signed rfe_fix_shr64_round's integer. */
static void check_ushr(uint64_t u, unsigned int s)
{
    const uint64_t div = (uint64_t)1 << s;
    const uint64_t want =
        (s == 0u) ? u : ((u >> s) + (((u & (div - 1u)) >= (div >> 1)) ? 1u : 0u));
    assert_true(rfe_q31_ushr64_round(u, s) == want);
    if (u < ((uint64_t)1 << 63)) {
        assert_true(rfe_q31_ushr64_round(u, s) == (uint64_t)rfe_fix_shr64_round((int64_t)u, s));
    }
}

/* REQ: the unsigned round-half-up shift (internal_q31.h, the Magic Formula's scalings) is
 * floor(u / 2^s + 1/2) for every shift of its domain 0 .. 63, at the ties (k 2^s +- 2^(s-1)),
 * the largest u (2^64 - 1, where adding 2^(s-1) first would wrap) and random u of every bit
 * length. */
/* REQ-FXP-002 */
static void test_ushr64_round(void **state)
{
    unsigned int s;
    int k;
    (void)state;
    rng_seed(0x5E1Full);
    for (s = 0u; s <= 63u; ++s) {
        check_ushr(0u, s);
        check_ushr(UINT64_MAX, s);
        check_ushr(UINT64_MAX - 1u, s);
        if (s > 0u) {
            const uint64_t half = (uint64_t)1 << (s - 1u);
            check_ushr(half, s);
            check_ushr(half - 1u, s);
            check_ushr((((uint64_t)5) << s) + half, s);
            check_ushr((((uint64_t)5) << s) + half - 1u, s);
        }
        for (k = 0; k < 64; ++k) {
            const uint64_t r = (uint64_t)((rng_uniform() + 1.0) * 9.0e18);
            check_ushr(r >> (unsigned int)k, s);
            check_ushr(~(r >> (unsigned int)k), s);
        }
    }
}

/* One case of the 64-by-32 division: the digits' integer and the dispatcher's are n / d. */
static void check_udiv(uint64_t n, uint32_t d)
{
    const uint64_t want = n / (uint64_t)d;
    assert_true(want < ((uint64_t)1 << 32)); /* the precondition n < d 2^32 */
    assert_true((uint64_t)rfe_q31_udiv64_32_digits(n, d) == want);
    assert_true((uint64_t)rfe_q31_udiv64_32(n, d) == want);
}

/* The 64-by-32 division in 16-bit digits (internal_q31.h, the Cortex-M3 and M4's form of the
 * observer's divisions) is the 64-bit division's integer: for every divisor bit length 1 .. 32
 * its smallest and largest divisor and random ones, with the largest dividend (d 2^32 - 1),
 * the smallest (0), exact multiples and their neighbours, and random dividends; divisors whose
 * low half is all ones or zero (where the digit estimate is 2 too large or exact); and the
 * operands of the observer's division (|a.m| 2^30 or 2^31 over |b.m| in [2^29, 2^30]). */
static void test_udiv64_32(void **state)
{
    unsigned int len;
    int k;
    (void)state;
    rng_seed(0xD1Full);
    for (len = 1u; len <= 32u; ++len) {
        const uint64_t top = (uint64_t)1 << (len - 1u);
        for (k = 0; k < 200; ++k) {
            uint32_t d;
            uint64_t n;
            uint64_t q;
            if (k == 0) {
                d = (uint32_t)top;
            } else if (k == 1) {
                d = (uint32_t)((top - 1u) | top);
            } else if ((k == 2) && (len > 16u)) {
                d = (uint32_t)(top | 0xFFFFu);
            } else {
                d = (uint32_t)(top | ((uint64_t)((rng_uniform() + 1.0) * 2.0e9) & (top - 1u)));
            }
            check_udiv(((uint64_t)d << 32) - 1u, d);
            check_udiv(0u, d);
            q = (uint64_t)((rng_uniform() + 1.0) * 2.1e9) & 0xFFFFFFFFu;
            n = q * (uint64_t)d;
            check_udiv(n, d);
            if (n > 0u) {
                check_udiv(n - 1u, d);
            }
            if ((n + (uint64_t)d - 1u) < ((uint64_t)d << 32)) {
                check_udiv(n + (uint64_t)d - 1u, d);
            }
            n = (uint64_t)((rng_uniform() + 1.0) * 9.0e18) % ((uint64_t)d << 32);
            check_udiv(n, d);
        }
    }
    for (k = 0; k < N_CASES; ++k) {
        const uint64_t ma = (uint64_t)((rng_uniform() + 1.0) * 536870912.0) + 1u; /* (0, 2^30] */
        const uint32_t mb = (uint32_t)((rng_uniform() + 3.0) * 268435456.0); /* [2^29, 2^30) */
        const unsigned int sh1 = (ma < (uint64_t)mb) ? 31u : 30u;
        check_udiv(ma << sh1, mb);
    }
}

/* One case of the Newton root: r^2 <= y < (r + 1)^2, in 64 bits. */
static void check_isqrt32(uint32_t y)
{
    const uint64_t r = (uint64_t)rfe_q31_isqrt32_newton(y);
    assert_true((r * r) <= (uint64_t)y);
    assert_true((uint64_t)y < ((r + 1u) * (r + 1u)));
}

/* The 32-bit Newton root (internal_q31.h; the Cortex-M3 and M4's form of the square roots'
 * leading digits) is floor(sqrt(y)): every y below 2^16 + 1, the squares k^2 of every k up
 * to 2^16 - 1 with their neighbours k^2 - 1 and k^2 + 2k ((k + 1)^2 - 1), both ends of
 * every bit length, and random values. */
static void test_isqrt32_newton(void **state)
{
    uint32_t y;
    uint32_t k;
    unsigned int len;
    int n;
    (void)state;
    for (y = 0u; y <= 65536u; ++y) {
        check_isqrt32(y);
    }
    for (k = 1u; k < 65536u; ++k) {
        check_isqrt32(k * k);
        check_isqrt32((k * k) - 1u);
        check_isqrt32((k * k) + (2u * k));
    }
    for (len = 1u; len <= 32u; ++len) {
        const uint32_t top = (uint32_t)1u << (len - 1u);
        check_isqrt32(top);
        check_isqrt32((top - 1u) | top);
    }
    rng_seed(0x5A7ull);
    for (n = 0; n < N_CASES; ++n) {
        check_isqrt32((uint32_t)((rng_uniform() + 1.0) * 2147483647.0));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_xf_operations),
        cmocka_unit_test(test_xf_sum),
        cmocka_unit_test(test_xf_edges),
        cmocka_unit_test(test_bitlen),
        cmocka_unit_test(test_xf_div_as_fix_div),
        cmocka_unit_test(test_xf_make_add_as_before),
        cmocka_unit_test(test_udiv64_32),
        cmocka_unit_test(test_ushr64_round),
        cmocka_unit_test(test_isqrt32_newton),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
