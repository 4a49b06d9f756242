/**
 * @file test_sckf_sums_q31.c
 * @brief The bound that lets the SCKF update's two hot sums skip saturation (sckf_q31.c
 *        sums_fit_q31, dot_q31): the gain G^T = W Xc^T (2n products, limit 2^63) and the
 *        posterior Tria input [Xc, 0] 2^30 - G W (m products after a term below 2^61, limit
 *        2^62). sums_fit_q31 says "exact" when terms 2^(bits of max|a| + bits of max|b|)
 *        stays within 2^limit; then every partial sum is below 2^limit in magnitude, the
 *        saturating accumulation it replaces (rfe_fix_add64_hot, the former form) neither
 *        saturates nor counts, and the plain int64 sum is the same integer.
 *
 * This file includes sckf_q31.c and calls its own static helpers. For every case it
 *  - recomputes the sum of the products' magnitudes in uint64 with an overflow check: where
 *    sums_fit_q31 said exact it must stay below 2^limit (the bound itself);
 *  - runs the former saturating accumulation (rfe_fix_add64_hot, term by term, with its count)
 *    and compares dot_q31's integer and count with it, in the exact and the saturating path,
 *    and for the posterior the -(-acc + sum) form against acc - sum (no tolerance: the same
 *    integer, the same count).
 * Inputs: lengths 1..24 (RFE_TRIA_COLS_MAX), entries at the int32 extremes and of random bit
 * length per vector (1 to 32 bits), 200,000 cases per sum, so that both paths and saturating
 * sums occur (asserted).
 *
 * Outside test/numerics/ (mk/lib.mk's TEST_DIRS) as the other tests here: it includes a
 * library source; `make test-c` runs it.
 */
#include "test_common.h"

#include <stdint.h>

#include "filters/sckf_q31.c"

#define LEN_MAX 24u

#include "splitmix64.h"

/* A vector of len entries, stride st: the extremes, or random of at most bits bits. */
static void fill(int32_t *v, size_t len, size_t st)
{
    const uint64_t r0 = rand_u64();
    const unsigned int kind = (unsigned int)(r0 % 6u);
    const unsigned int bits = 1u + (unsigned int)((r0 >> 8) % 31u);
    size_t k;
    for (k = 0u; k < len; ++k) {
        const uint64_t r = rand_u64();
        int32_t x;
        if (kind == 0u) {
            x = INT32_MIN;
        } else if (kind == 1u) {
            x = ((r & 1u) != 0u) ? INT32_MIN : INT32_MAX;
        } else {
            const int64_t m = (int64_t)((r >> 1) & ((UINT64_C(1) << bits) - 1u));
            x = (int32_t)(((r & 1u) != 0u) ? -m : m);
        }
        v[k * st] = x;
    }
}

static uint64_t mag64(int64_t p)
{
    return (p < 0) ? (0u - (uint64_t)p) : (uint64_t)p;
}

/* sum_k |a_k b_k| (+ |acc|), 0 when it reaches 2^64 (flagged in *over) */
static uint64_t mag_sum(int64_t acc, const int32_t *a, size_t sa, const int32_t *b, size_t sb,
                        size_t len, int *over)
{
    uint64_t s = mag64(acc);
    size_t k;
    *over = 0;
    for (k = 0u; k < len; ++k) {
        const uint64_t t = mag64((int64_t)a[k * sa] * (int64_t)b[k * sb]);
        if ((s + t) < s) {
            *over = 1;
        }
        s += t;
    }
    return s;
}

static unsigned long n_exact[2];
static unsigned long n_sat_path[2];
static unsigned long n_saturated[2];

/* One case of either sum: len products of a (stride sa) and b (stride sb) after acc (posterior:
 * subtracted, acc = Xc 2^30; gain: added, acc = 0), the rows' magnitudes taken over the two
 * vectors as sckf_q31.c takes them over the matrices. */
static void check_case(int posterior, int64_t acc, const int32_t *a, size_t sa, const int32_t *b,
                       size_t sb, size_t len)
{
    const unsigned int limit = (posterior != 0) ? 62u : 63u;
    const int exact = sums_fit_q31(mag_bits_q31(a, len, 1u, sa) + mag_bits_q31(b, len, 1u, sb),
                                   len, limit);
    uint32_t want_count = 0u;
    uint32_t got_count = 0u;
    int64_t want = acc;
    int64_t got;
    int over = 0;
    size_t k;
    const uint64_t ms = mag_sum(0, a, sa, b, sb, len, &over);
    if (exact != 0) {
        /* the bound: the products' magnitudes sum below 2^limit */
        assert_int_equal(over, 0);
        assert_true(ms < (UINT64_C(1) << limit));
        ++n_exact[posterior];
    } else {
        ++n_sat_path[posterior];
    }
    /* the former form, term by term */
    for (k = 0u; k < len; ++k) {
        const int64_t p = (int64_t)a[k * sa] * (int64_t)b[k * sb];
        want = rfe_fix_add64_hot(want, (posterior != 0) ? -p : p, &want_count);
    }
    if (posterior != 0) {
        got = -dot_q31(-acc, a, sa, b, sb, len, exact, &got_count);
    } else {
        got = dot_q31(acc, a, sa, b, sb, len, exact, &got_count);
    }
    assert_true(got == want);
    assert_int_equal(got_count, want_count);
    if (want_count != 0u) {
        ++n_saturated[posterior];
        assert_int_equal(exact, 0); /* the exact path never meets a saturating sum */
    }
    /* and the exact path agrees with the former form wherever it is taken */
    if (exact != 0) {
        uint32_t c2 = 0u;
        const int64_t sat_path = (posterior != 0) ? -dot_q31(-acc, a, sa, b, sb, len, 0, &c2)
                                                  : dot_q31(acc, a, sa, b, sb, len, 0, &c2);
        assert_true(sat_path == got);
        assert_int_equal(c2, 0u);
    }
}

static void run(int posterior)
{
    static int32_t a[LEN_MAX * RFE_N_MAX];
    static int32_t b[LEN_MAX * RFE_TRIA_COLS_SZ];
    unsigned int it;
    for (it = 0u; it < 200000u; ++it) {
        const uint64_t r = rand_u64();
        const size_t len = 1u + (size_t)(r % LEN_MAX);
        /* the posterior's strides (G^T column: NM, W column: TC), the gain's 1 */
        const size_t sa = (posterior != 0) ? (size_t)RFE_N_MAX : 1u;
        const size_t sb = (posterior != 0) ? (size_t)RFE_TRIA_COLS_SZ : 1u;
        int64_t acc = 0;
        fill(a, len, sa);
        fill(b, len, sb);
        if (posterior != 0) { /* Xc_ij 2^30, |Xc_ij| <= 2^31 */
            int32_t x = 0;
            fill(&x, 1u, 1u);
            acc = (int64_t)x * (INT64_C(1) << 30);
        }
        check_case(posterior, acc, a, sa, b, sb, len);
    }
    print_message("%s: %lu exact, %lu saturating path (%lu sums saturated)\n",
                  (posterior != 0) ? "posterior" : "gain", n_exact[posterior],
                  n_sat_path[posterior], n_saturated[posterior]);
    /* both paths and saturating sums were met */
    assert_true(n_exact[posterior] > 10000u);
    assert_true(n_sat_path[posterior] > 10000u);
    assert_true(n_saturated[posterior] > 100u);
}

static void test_gain_sums(void **state)
{
    (void)state;
    mix_state = 0x5C4F5u;
    run(0);
}

static void test_posterior_sums(void **state)
{
    (void)state;
    mix_state = 0x9057u;
    run(1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gain_sums),
        cmocka_unit_test(test_posterior_sums),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
