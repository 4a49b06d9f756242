/**
 * @file test_sckf_dot_w16_q31.c
 * @brief The Cortex-M0+ form of the SCKF update's exact sums (sckf_q31.c dot_exact_w16, the
 *        sum modulo 2^64 in 32-bit words from 16-bit partial products, compiled where
 *        RFE_FIX_MUL64_W16 = 1), run on the host: this file sets RFE_FIX_MUL64_W16 to 1 and
 *        includes sckf_q31.c itself, so the sum checked is the library's own code in the form
 *        the Thumb-1 build compiles (test_sckf_sums_q31.c checks the bound that selects the
 *        exact path, in the library's host form).
 *
 * Every sum must equal the plain one bit for bit (no tolerance): acc + sum_k a_k b_k of the
 * int64 products, summed in unsigned __int128 (GCC's and Clang's) so that no partial sum can
 * overflow the reference; the form's precondition is a result inside int64 (sums_fit_q31's
 * exact path keeps even every partial sum there), so the cases whose result leaves int64 are
 * counted and skipped. Where the reference's partial sums stay in int64 the plain int64 sum
 * term by term is checked too. Operands: edge cases (the int32 extremes in every sign
 * combination, the sums 2^62 and -2^62 of one product, results at +-(2^63 - 1)), and 300,000
 * pseudo-random cases: lengths 0 .. 24 (RFE_TRIA_COLS_MAX), the update's strides (1, NM, TC),
 * entries at the extremes or of random bit length and sign, a random int64 acc or 0, through
 * dot_q31's exact path as the update calls it.
 *
 * Built outside test/numerics/ (mk/lib.mk's TEST_DIRS) on purpose: it compiles sckf_q31.c in
 * another form than the library's, so the coverage and MC/DC runs, which read src/ through
 * every test binary, leave it out; `make test-c` runs it (Makefile, W16_TESTS).
 */
#define RFE_FIX_MUL64_W16 1

#include "test_common.h"

#include <stdint.h>

#include "filters/sckf_q31.c"

#include "splitmix64.h"

#define LEN_MAX 24u
#define ST_MAX ((size_t)RFE_TRIA_COLS_SZ)

static unsigned long n_checked;
static unsigned long n_skipped;
static unsigned long n_plain; /* also checked against the term-by-term int64 sum */

/* One case: dot_exact_w16 and dot_q31's exact path against the int128 sum (no tolerance). */
static void check(int64_t acc, const int32_t *a, size_t sa, const int32_t *b, size_t sb,
                  size_t len)
{
    __int128 want = acc;
    int in64 = 1; /* every partial sum inside int64 */
    int64_t plain = acc;
    uint32_t count = 0u;
    size_t k;
    for (k = 0u; k < len; ++k) {
        const int64_t p = (int64_t)a[k * sa] * (int64_t)b[k * sb]; /* |p| <= 2^62 */
        want += p;
        if ((want > INT64_MAX) || (want < INT64_MIN)) {
            in64 = 0;
        }
    }
    if ((want > INT64_MAX) || (want < INT64_MIN)) {
        ++n_skipped; /* outside the form's precondition */
        return;
    }
    if (dot_exact_w16(acc, a, sa, b, sb, len) != (int64_t)want) {
        fail_msg("dot_exact_w16: len %zu, acc %lld: %lld, want %lld", len, (long long)acc,
                 (long long)dot_exact_w16(acc, a, sa, b, sb, len), (long long)want);
    }
    assert_true(dot_q31(acc, a, sa, b, sb, len, 1, &count) == (int64_t)want);
    assert_int_equal(count, 0u); /* the exact path never counts */
    if (in64 != 0) {
        for (k = 0u; k < len; ++k) {
            plain += (int64_t)a[k * sa] * (int64_t)b[k * sb];
        }
        assert_true(plain == (int64_t)want);
        ++n_plain;
    }
    ++n_checked;
}

/* An int32: an extreme, or random of at most bits bits with a random sign. */
static int32_t rand_entry(unsigned int bits)
{
    const uint64_t r = rand_u64();
    const unsigned int kind = (unsigned int)(r % 8u);
    int32_t x;
    if (kind == 0u) {
        x = INT32_MIN;
    } else if (kind == 1u) {
        x = INT32_MAX;
    } else if (kind == 2u) {
        x = -INT32_MAX;
    } else {
        const int64_t m = (int64_t)((r >> 8) & ((UINT64_C(1) << bits) - 1u));
        x = (int32_t)(((r & 0x10u) != 0u) ? -m : m);
    }
    return x;
}

static void test_dot_w16_edges(void **state)
{
    static const int32_t ext[] = {INT32_MIN, -INT32_MAX, -65536, -65535, -32768, -1, 0, 1,
                                  32767,     32768,      65535,  65536,  INT32_MAX};
    const size_t n_ext = sizeof(ext) / sizeof(ext[0]);
    int32_t a[2];
    int32_t b[2];
    size_t i;
    size_t j;
    (void)state;
    n_checked = 0u;
    /* one product of every pair of edge values, after acc = 0 and acc at +-(2^63 - 2^62 - 1) */
    for (i = 0u; i < n_ext; ++i) {
        for (j = 0u; j < n_ext; ++j) {
            a[0] = ext[i];
            b[0] = ext[j];
            check(0, a, 1u, b, 1u, 1u);
            check(INT64_MAX - (INT64_C(1) << 62), a, 1u, b, 1u, 1u);
            check(-(INT64_MAX - (INT64_C(1) << 62)), a, 1u, b, 1u, 1u);
        }
    }
    /* 2 (-2^31)^2 = 2^63 leaves int64 (skipped); with acc = -1 it is INT64_MAX exactly */
    a[0] = INT32_MIN;
    a[1] = INT32_MIN;
    b[0] = INT32_MIN;
    b[1] = INT32_MIN;
    check(-1, a, 1u, b, 1u, 2u);
    assert_int_equal(n_skipped, 0u); /* every case above is inside int64 */
    check(0, a, 1u, b, 1u, 2u);
    assert_int_equal(n_skipped, 1u);
    /* 2 (-2^31)(2^31 - 1) = -2^63 + 2^32: inside; with acc = -2^32 exactly INT64_MIN */
    b[0] = INT32_MAX;
    b[1] = INT32_MAX;
    check(0, a, 1u, b, 1u, 2u);
    check(-(INT64_C(1) << 32), a, 1u, b, 1u, 2u);
    /* the empty sum */
    check(INT64_MIN, a, 1u, b, 1u, 0u);
    check(INT64_MAX, a, 1u, b, 1u, 0u);
    assert_true(n_checked == (3u * n_ext * n_ext) + 5u);
}

static void test_dot_w16_random(void **state)
{
    static const size_t strides[] = {1u, (size_t)RFE_N_MAX, ST_MAX};
    static int32_t a[LEN_MAX * ST_MAX];
    static int32_t b[LEN_MAX * ST_MAX];
    unsigned int it;
    (void)state;
    mix_state = 0xD07B16u;
    n_checked = 0u;
    n_skipped = 0u;
    n_plain = 0u;
    for (it = 0u; it < 300000u; ++it) {
        const uint64_t r = rand_u64();
        const size_t len = (size_t)(r % (LEN_MAX + 1u));
        const size_t sa = strides[(r >> 8) % 3u];
        const size_t sb = strides[(r >> 12) % 3u];
        const unsigned int bits_a = 1u + (unsigned int)((r >> 16) % 31u);
        const unsigned int bits_b = 1u + (unsigned int)((r >> 24) % 31u);
        const int64_t acc = (((r >> 32) & 3u) == 0u) ? 0 : (int64_t)(rand_u64() >> 2) -
                                                                  (INT64_C(1) << 61);
        size_t k;
        for (k = 0u; k < len; ++k) {
            a[k * sa] = rand_entry(bits_a);
            b[k * sb] = rand_entry(bits_b);
        }
        check(acc, a, sa, b, sb, len);
    }
    print_message("dot_exact_w16: %lu sums checked (%lu also term by term in int64), %lu "
                  "outside int64 skipped\n",
                  n_checked, n_plain, n_skipped);
    /* most cases are inside the precondition, and some partial sums leave int64 on the way */
    assert_true(n_checked > 250000u);
    assert_true(n_plain > 200000u);
    assert_true(n_checked > n_plain);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dot_w16_edges),
        cmocka_unit_test(test_dot_w16_random),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
