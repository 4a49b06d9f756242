/**
 * @file test_isqrt_w16_q31.c
 * @brief The Cortex-M0+ form of the 64-bit integer square root (fxmath_q31.c isqrt_rem_hi,
 *        one Karatsuba square-root step compiled where RFE_FIX_MUL64_W16 = 1), run on the
 *        host: this file sets RFE_FIX_MUL64_W16 to 1 and includes fxmath_q31.c itself, so the
 *        root checked is the library's own code in the form the Thumb-1 build compiles
 *        (test_fxmath_q31.c checks the library's host form, the Newton step).
 *
 * Every root and remainder must be exact (no tolerance): r = floor(sqrt(x)) is the one integer
 * with r^2 <= x < (r + 1)^2, checked in unsigned __int128 (GCC's and Clang's), and the
 * remainder must be x - r^2; the definition itself, no second square-root algorithm. Operands
 * (x >= 2^32, the form's domain, and below it through isqrt_rem's 32-bit path): the powers of
 * two and their neighbours, every k^2 - 1, k^2, k^2 + 2 k (the largest remainder) around the
 * roots 2^16 .. 2^32 - 1, the largest x, the dividends whose Karatsuba quotient reaches its
 * bound b (y = (s' + 1)^2 - 1 at every split h = 1 .. 16), and 300,000 pseudo-random x of
 * every bit length 33 .. 64 and k^2 + (a random remainder up to 2 k). The correction step
 * (the estimate one too large) must be taken in some of them, counted so that it cannot pass
 * untested.
 *
 * Built outside test/numerics/ (mk/lib.mk's TEST_DIRS) on purpose: it compiles fxmath_q31.c
 * in another form than the library's, so the coverage and MC/DC runs, which read src/
 * through every test binary, leave it out; `make test-c` runs it (Makefile, W16_TESTS).
 */
#define RFE_FIX_MUL64_W16 1

#include "test_common.h"

#include <stdint.h>

#include "numerics/fxmath_q31.c"

#include "splitmix64.h"

static unsigned long n_checked;
static unsigned long n_corrected; /* the Karatsuba estimate s was one too large */

/* One x: isqrt_rem(x) against the definition of the floor root, exactly. */
static void check(uint64_t x)
{
    uint64_t rem = 0u;
    const uint64_t r = isqrt_rem(x, &rem);
    const unsigned __int128 sq = (unsigned __int128)r * r;
    const unsigned __int128 next = (unsigned __int128)(r + 1u) * (r + 1u);
    if ((sq > x) || (next <= x) || (rem != (uint64_t)(x - (uint64_t)sq))) {
        fail_msg("isqrt_rem(%llu) = %llu rem %llu", (unsigned long long)x, (unsigned long long)r,
                 (unsigned long long)rem);
    }
    if (x >= ((uint64_t)1 << 32)) {
        /* the estimate s' b + q exceeds the root exactly when its remainder u b + a0 - q^2 is
         * negative: re-derived here from the definition (s' = floor(sqrt(y)), not the code) */
        const unsigned int len = 64u - (unsigned int)__builtin_clzll(x);
        const unsigned int sh = (len - 31u) & ~1u;
        const unsigned int h = sh / 2u;
        const uint64_t y = x >> sh;
        const uint64_t a1 = (x & ((((uint64_t)1) << sh) - 1u)) >> h;
        uint64_t lo = 0u;       /* lo^2 <= y */
        uint64_t hi = 65536u;   /* hi^2 > y (y < 2^32) */
        uint64_t s1;
        while ((hi - lo) > 1u) { /* bisection on the definition */
            const uint64_t mid = (lo + hi) / 2u;
            if ((mid * mid) <= y) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        s1 = lo;
        {
            const uint64_t q = (((y - (s1 * s1)) << h) + a1) / (s1 << 1);
            if ((((s1 << h) + q)) != r) {
                ++n_corrected;
            }
        }
    }
    ++n_checked;
}

/* A random uint64 of exactly len bits (1 <= len <= 64). */
static uint64_t rand_len(unsigned int len)
{
    const uint64_t top = (uint64_t)1 << (len - 1u);
    return top | (rand_u64() & (top - 1u));
}

/* REQ-FXP-001 */
static void test_isqrt_w16_edges(void **state)
{
    unsigned int n;
    unsigned int h;
    uint64_t k;
    (void)state;
    n_checked = 0u;
    n_corrected = 0u;
    check(0u);
    check(1u);
    check(UINT64_MAX);
    check(UINT64_MAX - 1u);
    check(UINT64_MAX - 0xFFFFFFFFu); /* 2^64 - 2^32: y = 2^32 - 1, q = b = 2^16 */
    for (n = 1u; n < 64u; ++n) {
        const uint64_t p = (uint64_t)1 << n;
        check(p - 1u);
        check(p);
        check(p + 1u);
    }
    /* roots around 2^16 (x around 2^32, both paths), 2^31, 2^32 - 1 */
    for (k = 65000u; k < 66100u; ++k) {
        check((k * k) - 1u);
        check(k * k);
        check((k * k) + (k << 1));
    }
    for (k = 0xFFFFF000u; k <= 0xFFFFFFFFu; ++k) {
        check((k * k) - 1u);
        check(k * k);
        check((k * k) + (k << 1));
    }
    for (k = 0x7FFFF800u; k < 0x80000800u; ++k) {
        check((k * k) - 1u);
        check(k * k);
        check((k * k) + (k << 1));
    }
    /* the Karatsuba quotient at its bound: y = (s' + 1)^2 - 1 (r' = 2 s'), every split h,
     * with the low part x mod b^2 at 0, 1, and its largest */
    for (h = 1u; h <= 16u; ++h) {
        const uint64_t b2 = (uint64_t)1 << (2u * h);
        for (k = 32768u; k <= 65536u; k += 1021u) {
            const uint64_t y = (k * k) - 1u;
            if ((y >= ((uint64_t)1 << 30)) && (y < ((uint64_t)1 << 32))) {
                check(y * b2);
                check((y * b2) + 1u);
                check((y * b2) + (b2 - 1u));
            }
        }
    }
    assert_true(n_corrected > 0u);
    print_message("edges: %lu roots, %lu corrected\n", n_checked, n_corrected);
}

/* REQ-FXP-001 */
static void test_isqrt_w16_random(void **state)
{
    unsigned int i;
    (void)state;
    mix_state = 0x5EED0017ull;
    n_checked = 0u;
    n_corrected = 0u;
    for (i = 0u; i < 200000u; ++i) {
        check(rand_len(33u + (i % 32u)));
    }
    /* near perfect squares: k^2 + a remainder up to its largest, 2 k */
    for (i = 0u; i < 100000u; ++i) {
        const uint64_t k = rand_len(17u + (i % 16u));
        const uint64_t rem = rand_u64() % ((k << 1) + 1u);
        check((k * k) + ((i & 1u) ? rem : (rem & 3u)));
    }
    assert_true(n_corrected > 0u);
    print_message("random: %lu roots, %lu corrected\n", n_checked, n_corrected);
}

/* The public entry in the same form: rfe_fix_isqrt64 and rfe_fix_sqrt's rounding on it. */
/* REQ-FXP-001 */
static void test_isqrt_w16_public(void **state)
{
    uint32_t r = 0u;
    rfe_fix_t root = 0;
    uint32_t sat = 0u;
    (void)state;
    assert_int_equal(rfe_fix_isqrt64(UINT64_MAX, &r), RFE_OK);
    assert_true(r == 0xFFFFFFFFu);
    assert_int_equal(rfe_fix_isqrt64(((uint64_t)1 << 62), &r), RFE_OK);
    assert_true(r == 0x80000000u);
    /* sqrt(1.0 in Q30) in Q30 = 2^30: x 2^30 = 2^60, above 2^32 */
    assert_int_equal(rfe_fix_sqrt((rfe_fix_t)1 << 30, 30u, 30u, &root, &sat), RFE_OK);
    assert_int_equal(root, (rfe_fix_t)1 << 30);
    /* sqrt(2) in Q30, rounded: 1518500249.99...(2^30 sqrt(2) = 1518500249.988) -> 1518500250 */
    assert_int_equal(rfe_fix_sqrt((rfe_fix_t)1 << 29, 28u, 30u, &root, &sat), RFE_OK);
    assert_int_equal(root, 1518500250);
    assert_int_equal(sat, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_isqrt_w16_edges),
        cmocka_unit_test(test_isqrt_w16_random),
        cmocka_unit_test(test_isqrt_w16_public),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
