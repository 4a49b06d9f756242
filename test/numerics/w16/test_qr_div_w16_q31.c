/**
 * @file test_qr_div_w16_q31.c
 * @brief The Cortex-M0+ form of Tria's division (qr_q31.c div_shl32, two 16-bit digits of
 *        Knuth's long division in 32-bit words, compiled where RFE_FIX_MUL64_W16 = 1), run on
 *        the host: this file sets RFE_FIX_MUL64_W16 to 1 and includes qr_q31.c itself, so the
 *        division checked is the library's own code in the form the Thumb-1 build compiles
 *        (test_qr_q31.c checks a bit-by-bit copy and the other cores' form,
 *        rfe_q31_div_shl32_round).
 *
 * Every quotient must equal the exact one bit for bit (no tolerance): floor(n 2^32 / d) from
 * the unsigned __int128 division (GCC's and Clang's), rounded half up on its last bit, for
 * d >= 1, d < 2^63 and n < d 2^31 (the division's precondition, qr_q31.c). Operands: edge
 * cases (n = 0; d = 1 and the powers of two, where the quotient is an exact shift; the
 * largest n = d 2^31 - 1 for every divisor length; d at its maximum, 2^63 - 1, and at Tria's,
 * v.v < 2^62; exact ties of the rounding), 300,000 pseudo-random pairs with a divisor of
 * every length 1 .. 63 and a dividend of every length up to its bound, and 80,000 built to
 * take the M0+ digits' add-back (the digit estimate one too large after Knuth's test).
 *
 * Built outside test/numerics/ (mk/lib.mk's TEST_DIRS) on purpose: it compiles qr_q31.c in
 * another form than the library's, so the coverage and MC/DC runs, which read src/ through
 * every test binary, leave it out; `make test-c` runs it (Makefile, W16_TESTS).
 */
#define RFE_FIX_MUL64_W16 1

#include "test_common.h"

#include <stdint.h>

#include "numerics/qr_q31.c"

#include "splitmix64.h"

/* A random uint64 of exactly len bits (1 <= len <= 64). */
static uint64_t rand_len(unsigned int len)
{
    const uint64_t top = (uint64_t)1 << (len - 1u);
    return top | (rand_u64() & (top - 1u));
}

static unsigned int n_checked;

/* One case: the int128 quotient floor(n 2^32 / d), rounded half up on its last bit, against
 * the M0+ form of div_shl32 and against the other cores' form (exact: no tolerance). */
static void check(uint64_t n, uint64_t d)
{
    const unsigned __int128 q = (((unsigned __int128)n) << 32) / d;
    uint64_t want;
    assert_true((d >= 1u) && (d < ((uint64_t)1 << 63)));
    assert_true(q < ((unsigned __int128)1 << 63)); /* the precondition n < d 2^31 */
    want = (uint64_t)((q + 1u) >> 1);
    if (div_shl32(n, d) != want) {
        fail_msg("div_shl32(%llu, %llu) = %llu, want %llu", (unsigned long long)n,
                 (unsigned long long)d, (unsigned long long)div_shl32(n, d),
                 (unsigned long long)want);
    }
    assert_true(rfe_q31_div_shl32_round(n, d) == want);
    ++n_checked;
}

/* The largest dividend below d 2^31 (n is 64 bits wide: all of them from d >= 2^33 on). */
static uint64_t n_max(uint64_t d)
{
    return (d >= ((uint64_t)1 << 33)) ? UINT64_MAX : ((d << 31) - 1u);
}

/* REQ-FXP-001 */
static void test_div_shl32_w16_edges(void **state)
{
    const uint64_t d_max = ((uint64_t)1 << 63) - 1u; /* the division's largest divisor */
    const uint64_t vtv_max = ((uint64_t)1 << 62) - 1u; /* Tria's: v.v < 2^62 (qr_q31.c) */
    const uint64_t ds[] = {1u, 2u, 3u, 0xFFFFFFFFu, (uint64_t)1 << 32, ((uint64_t)1 << 32) + 1u,
                           (uint64_t)1 << 33, vtv_max, (uint64_t)1 << 62, d_max};
    unsigned int i;
    unsigned int s;
    (void)state;
    n_checked = 0u;
    /* d = 1 scaled: d = 2^s, where n 2^32 / d is a shift (rounded half up below 2^-1) */
    for (s = 0u; s < 63u; ++s) {
        const uint64_t d = (uint64_t)1 << s;
        check(0u, d);
        check(1u, d);
        check(d - 1u, d);
        check(d, d);
        check(n_max(d), d);
        check(n_max(d) >> 1, d);
    }
    /* n = 0, n = d 2^31 - 1 (the largest quotient, 2^62 - 1 rounded) and their neighbours,
     * for the largest divisor of every length and the listed ones */
    for (s = 1u; s <= 63u; ++s) {
        const uint64_t d = (s == 63u) ? d_max : (((uint64_t)1 << s) - 1u);
        check(0u, d);
        check(n_max(d), d);
        check(n_max(d) - 1u, d);
    }
    for (i = 0u; i < (sizeof ds / sizeof ds[0]); ++i) {
        check(0u, ds[i]);
        check(1u, ds[i]);
        check(ds[i] - 1u, ds[i]);
        check(ds[i], ds[i]);
        check(ds[i] + 1u, ds[i]);
        check(n_max(ds[i]), ds[i]);
    }
    /* exact ties: d = 2^33 and n odd make n 2^32 / d an odd multiple of 1/2 */
    for (i = 0u; i < 64u; ++i) {
        check(((uint64_t)i << 1) | 1u, (uint64_t)1 << 33);
        check(UINT64_MAX - ((uint64_t)i << 1), (uint64_t)1 << 33);
    }
    print_message("edges: %u divisions\n", n_checked);
}

/* REQ-FXP-001 */
static void test_div_shl32_w16_random(void **state)
{
    unsigned int k;
    (void)state;
    mix_state = 0x5EED0016ull;
    n_checked = 0u;
    for (k = 0u; k < 300000u; ++k) {
        const unsigned int dlen = 1u + (k % 63u);
        const uint64_t d = rand_len(dlen);
        const unsigned int nbound = ((dlen + 31u) < 64u) ? (dlen + 31u) : 64u;
        const unsigned int nlen = 1u + ((k / 63u) % nbound);
        uint64_t n = rand_len(nlen);
        if ((nlen == (dlen + 31u)) && (n > n_max(d))) {
            n -= (uint64_t)1 << (nlen - 1u); /* of that length the bound may cut: one shorter */
        }
        check(n, d);
    }
    /* Tria's operands: |a.v| < 2^61 over v.v in [2^58, 2^62), 2 |a.v| < 2 v.v (|c| < 4) */
    for (k = 0u; k < 20000u; ++k) {
        const uint64_t vtv = rand_len(59u + (k % 4u));
        const uint64_t dot = rand_len(1u + (k % 61u));
        check((dot < (vtv << 1)) ? dot : ((vtv << 1) - 1u), vtv);
    }
    /* the M0+ digits' add-back (q^ one too large after Knuth's test, which sees the top 32
     * bits of d: ~2 / 2^16 of random digits): d = dt 2^31 + 2^31 - 1 (bit 62 the top, so
     * d 2^s = d) and n = q dt 2^15 for a digit q, which that test finds divisible by q while
     * q d exceeds n 2^16 (by q (2^31 - 1)): the first digit is q - 1, after the add-back */
    for (k = 0u; k < 40000u; ++k) {
        const uint64_t dt = ((uint64_t)1 << 31) | (rand_u64() & 0x7FFFFFFFu);
        const uint64_t q = ((uint64_t)1 << 15) | (rand_u64() & 0x7FFFu);
        const uint64_t d = (dt << 31) | 0x7FFFFFFFu;
        check((q * dt) << 15, d);
        check(((q * dt) << 15) | (rand_u64() & 0x7FFFu), d);
    }
    print_message("random: %u divisions\n", n_checked);
}

/* sub_round_c's 32-bit-word form against the int64 form it replaces, sat32(a -
 * shr64_round(p, 30)): the same value wherever that form does not saturate (the only inputs
 * Tria gives it: qr_q31.c derives |result| < 2^30 + 5, test_qr_bound_q31.c checks it), for
 * every a of a set of edges and random a, and p of magnitude below 2^62 (Tria's bound on
 * c v_j) around the rounding ties and up to the int32 limits. The saturating cases are
 * skipped (counted, so that the check cannot pass empty). */
static void test_sub_round_c_w16(void **state)
{
    static const rfe_fix_t as[] = {0, 1, -1, RFE_FIX_MAX, RFE_FIX_MIN, 0x40000000, -0x40000000};
    static const int64_t ps[] = {0, 1, -1, (INT64_C(1) << 29), -(INT64_C(1) << 29),
                                 (INT64_C(1) << 29) - 1, -(INT64_C(1) << 29) + 1,
                                 (INT64_C(3) << 29), -(INT64_C(3) << 29),
                                 (INT64_C(1) << 62) - 1, -(INT64_C(1) << 62) + 1,
                                 (INT64_C(1) << 61), -(INT64_C(1) << 61),
                                 (INT64_C(0x7FFFFFFF) << 30), -(INT64_C(0x7FFFFFFF) << 30),
                                 (INT64_C(0x80000000) << 30) - (INT64_C(1) << 29),
                                 -(INT64_C(0x80000000) << 30) + (INT64_C(1) << 29),
                                 (INT64_C(1) << 32) - (INT64_C(1) << 29),
                                 -(INT64_C(1) << 32) - (INT64_C(1) << 29)};
    size_t i;
    size_t j;
    int k;
    unsigned int n_fit = 0u;
    (void)state;
    for (i = 0u; i < sizeof as / sizeof as[0]; ++i) {
        for (j = 0u; j < sizeof ps / sizeof ps[0]; ++j) {
            uint32_t want_sat = 0u;
            const rfe_fix_t want =
                rfe_fix_sat32((int64_t)as[i] - rfe_fix_shr64_round(ps[j], 30u), &want_sat);
            if (want_sat == 0u) {
                assert_int_equal(sub_round_c(as[i], ps[j]), want);
                ++n_fit;
            }
        }
    }
    mix_state = 0x5AB0C0DEull;
    for (k = 0; k < 400000; ++k) {
        const uint64_t r = rand_u64();
        const unsigned int len = 1u + (unsigned int)(r % 62u);
        const int64_t m = (int64_t)(rand_u64() >> (64u - len));
        const int64_t p = ((r >> 8) & 1u) ? -m : m;
        const rfe_fix_t a = (rfe_fix_t)(int32_t)(uint32_t)(rand_u64() >> 33) *
                            (((r >> 9) & 1u) ? -1 : 1);
        uint32_t want_sat = 0u;
        const rfe_fix_t want = rfe_fix_sat32((int64_t)a - rfe_fix_shr64_round(p, 30u), &want_sat);
        if (want_sat == 0u) {
            assert_int_equal(sub_round_c(a, p), want);
            ++n_fit;
        }
    }
    /* most random pairs fit (|p| / 2^30 below 2^31 for lengths up to ~61 bits) */
    assert_true(n_fit > 200000u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_div_shl32_w16_edges),
        cmocka_unit_test(test_div_shl32_w16_random),
        cmocka_unit_test(test_sub_round_c_w16),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
