/**
 * @file test_qr_bound_q31.c
 * @brief The bound that lets Tria's reflected elements skip saturation (qr_q31.c
 *        sub_round_c): every element Tria computes is a - round(p / 2^30) with
 *        |a - round(p / 2^30)| < 2^30 + 5 (derived in qr_q31.c). This file includes
 *        qr_q31.c with RFE_QR_BOUND_HOOK defined, so every call of the library's own
 *        sub_round_c reports its operands and result here, and checks it for bit and bound:
 *        the result equals the exact int64 a - shr64_round(p, 30) (the saturating form it
 *        replaced, which never saturates under the bound) and its magnitude is below 2^30 + 5.
 *
 * Inputs: rfe_qr_tria_q31 and rfe_qr_tria_lt_q31 on every size up to RFE_N_MAX rows and
 * RFE_TRIA_COLS_MAX columns, with entries at the int32 extremes (INT32_MIN, INT32_MAX, equal
 * and opposite rows, one huge entry among tiny ones, rank-deficient copies) and random
 * entries of random magnitude per row (1 to 31 bits), 20,000 matrices.
 *
 * Outside test/numerics/ (mk/lib.mk's TEST_DIRS) on purpose, as the other tests here: it
 * compiles qr_q31.c with the hook, a form the library never has; `make test-c` runs it.
 */
#include "test_common.h"

#include <stdint.h>

static void bound_hook(int32_t a, int64_t p, int64_t r);
#define RFE_QR_BOUND_HOOK(a, p, r) bound_hook((a), (p), (r))

#include "numerics/qr_q31.c"

/* the derived bound: |result| < 2^30 + 5 */
#define BOUND ((INT64_C(1) << 30) + 5)

static unsigned long n_calls;
static int64_t max_mag;

static void bound_hook(int32_t a, int64_t p, int64_t r)
{
    const int64_t want = (int64_t)a - rfe_fix_shr64_round(p, 30u); /* exact: |p| < 2^62 */
    const int64_t mag = (want < 0) ? -want : want;
    assert_true((p < (INT64_C(1) << 62)) && (p > -(INT64_C(1) << 62)));
    if (r != want) {
        fail_msg("sub_round_c(%ld, %lld) = %lld, want %lld", (long)a, (long long)p,
                 (long long)r, (long long)want);
    }
    if (mag >= BOUND) {
        fail_msg("reflected element %lld beyond the bound 2^30 + 5", (long long)want);
    }
    if (mag > max_mag) {
        max_mag = mag;
    }
    ++n_calls;
}

/* splitmix64 (Steele, Lea, Flood 2014) */
static uint64_t mix_state;

static uint64_t rand_u64(void)
{
    uint64_t z = (mix_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

#define NR RFE_N_MAX
#define NC RFE_TRIA_COLS_MAX

static int32_t buf[NR * NC];

/* An entry of kind k: the extremes, or random of at most bits bits. */
static int32_t entry(unsigned int kind, unsigned int bits)
{
    const uint64_t r = rand_u64();
    int32_t v;
    switch (kind) {
    case 0u:
        v = INT32_MIN;
        break;
    case 1u:
        v = INT32_MAX;
        break;
    case 2u:
        v = ((r & 1u) != 0u) ? INT32_MIN : INT32_MAX;
        break;
    default: {
        const int64_t m = (int64_t)((r >> 1) & ((UINT64_C(1) << bits) - 1u));
        v = (int32_t)(((r & 1u) != 0u) ? -m : m);
        break;
    }
    }
    return v;
}

/* One matrix: rows x cols, each row of a random kind and magnitude, some rows copies or
 * negated copies of an earlier one (rank-deficient, equal and opposite). */
static void fill(size_t rows, size_t cols)
{
    size_t i;
    size_t j;
    for (i = 0u; i < rows; ++i) {
        const uint64_t r = rand_u64();
        const unsigned int kind = (unsigned int)(r % 8u);
        const unsigned int bits = 1u + (unsigned int)((r >> 8) % 31u);
        const size_t big = (size_t)((r >> 16) % cols);
        for (j = 0u; j < cols; ++j) {
            buf[(i * cols) + j] = entry((kind < 3u) ? kind : 3u, bits);
        }
        if ((kind == 3u) && (i > 0u)) { /* a copy, or a negated one, of the row above */
            const int neg = ((r >> 24) & 1u) != 0u;
            for (j = 0u; j < cols; ++j) {
                const int32_t v = buf[((i - 1u) * cols) + j];
                buf[(i * cols) + j] = (neg && (v != INT32_MIN)) ? -v : v;
            }
        }
        if (kind == 4u) { /* one huge entry among tiny ones */
            for (j = 0u; j < cols; ++j) {
                buf[(i * cols) + j] = entry(3u, 2u);
            }
            buf[(i * cols) + big] = entry(2u, 31u);
        }
    }
}

static void test_tria_bound(void **state)
{
    unsigned int it;
    (void)state;
    mix_state = 0xB0C0DE21ull;
    n_calls = 0u;
    max_mag = 0;
    for (it = 0u; it < 20000u; ++it) {
        const uint64_t r = rand_u64();
        const size_t rows = 1u + (size_t)(r % NR);
        const size_t cols = rows + (size_t)((r >> 8) % ((NC - rows) + 1u));
        uint32_t sat = 0u;
        fill(rows, cols);
        if (((r >> 20) & 1u) != 0u) {
            assert_int_equal(rfe_qr_tria_q31(buf, rows, cols, cols, &sat), RFE_OK);
        } else {
            /* the lower-triangular form reads the right rows x rows block as triangular:
             * zero above its diagonal */
            size_t i;
            size_t j;
            for (i = 0u; i < rows; ++i) {
                for (j = (cols - rows) + i + 1u; j < cols; ++j) {
                    buf[(i * cols) + j] = 0;
                }
            }
            assert_int_equal(rfe_qr_tria_lt_q31(buf, rows, cols, cols, &sat), RFE_OK);
        }
    }
    print_message("%lu reflected elements, largest |value| %lld (bound 2^30 + 5 = %lld)\n",
                  n_calls, (long long)max_mag, (long long)BOUND);
    assert_true(n_calls > 1000000u); /* the hook ran: the check is not empty */
    assert_true(max_mag > (INT64_C(1) << 29)); /* and reached the bound's scale */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tria_bound),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
