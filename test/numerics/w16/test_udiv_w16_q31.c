/**
 * @file test_udiv_w16_q31.c
 * @brief The Cortex-M0+ form of the 64-by-32 division in 16-bit digits (internal_q31.h
 *        rfe_q31_udiv64_32_digits, whose dividend is normalised in 32-bit words where
 *        RFE_FIX_MUL64_W16 = 1), run on the host: this file sets RFE_FIX_MUL64_W16 to 1 and
 *        includes internal_q31.h itself, so the division checked is the library's own code in
 *        the form the Thumb-1 build compiles (test_xf_q31.c checks the other cores' form).
 *
 * Every quotient must equal the 64-bit division's n / d bit for bit (no tolerance), for d >= 1
 * and n < d 2^32 (the division's precondition). Operands: for every divisor bit length 1 .. 32
 * (every normalising shift 31 .. 0) its smallest and largest divisor, one with the low half
 * all ones, and random ones, each with the dividends 0, 1, the largest (d 2^32 - 1), exact
 * multiples q d and their neighbours q d +- 1 (remainder 0, 1 and d - 1), and random
 * dividends below d 2^32; 300,000 cases in all.
 *
 * Built outside test/numerics/ (mk/lib.mk's TEST_DIRS) on purpose: it compiles a library
 * header in another form than the library's, so the coverage and MC/DC runs leave it out;
 * `make test-c` runs it (Makefile, W16_TESTS).
 */
#define RFE_FIX_MUL64_W16 1

#include "test_common.h"

#include <stdint.h>

#include "numerics/internal_q31.h"

#include "splitmix64.h"

static unsigned long n_checked;

/* One case: the digits' quotient against n / d. */
static void check(uint64_t n, uint32_t d)
{
    const uint64_t want = n / (uint64_t)d;
    const uint32_t got = rfe_q31_udiv64_32_digits(n, d);
    assert_true(want < ((uint64_t)1 << 32)); /* the precondition n < d 2^32 */
    if ((uint64_t)got != want) {
        fail_msg("udiv64_32_digits(%llu, %lu) = %lu, want %llu", (unsigned long long)n,
                 (unsigned long)d, (unsigned long)got, (unsigned long long)want);
    }
    ++n_checked;
}

/* REQ-FXP-001 */
static void test_udiv_w16(void **state)
{
    unsigned int len;
    unsigned int k;
    (void)state;
    mix_state = 0x5EED0018ull;
    n_checked = 0u;
    for (len = 1u; len <= 32u; ++len) {
        const uint64_t top = (uint64_t)1 << (len - 1u);
        for (k = 0u; k < 2000u; ++k) {
            uint32_t d;
            uint64_t q;
            uint64_t n;
            if (k == 0u) {
                d = (uint32_t)top;
            } else if (k == 1u) {
                d = (uint32_t)((top - 1u) | top);
            } else if ((k == 2u) && (len > 16u)) {
                d = (uint32_t)(top | 0xFFFFu);
            } else {
                d = (uint32_t)(top | (rand_u64() & (top - 1u)));
            }
            check(0u, d);
            check(1u, d);
            check(((uint64_t)d << 32) - 1u, d);
            q = rand_u64() >> 32; /* < 2^32 */
            n = q * (uint64_t)d;
            check(n, d);
            if (n > 0u) {
                check(n - 1u, d);
            }
            if ((n + 1u) < ((uint64_t)d << 32)) {
                check(n + 1u, d);
            }
            check(rand_u64() % ((uint64_t)d << 32), d);
        }
    }
    assert_true(n_checked > 300000u);
    print_message("%lu divisions\n", n_checked);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_udiv_w16),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
