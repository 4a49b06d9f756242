/**
 * @file test_qr_bound_q31.c
 * @brief The bound that lets Tria's reflected elements skip saturation (qr_q31.c
 *        sub_round_c): every element a reflection computes is a - round(c v_j / 2^30) with
 *        |a - round(c v_j / 2^30)| < 2^30 + 5 (derived in qr_q31.c). This file includes
 *        qr_q31.c and runs Tria's reduction itself, reflection by reflection, with the
 *        library's own static steps (tail_shift, scale_tail, reflect); before each reflection
 *        it keeps a copy of the normalised rows and recomputes every reflected element in
 *        int64 from it, in the saturating form sub_round_c replaced (sat32(a -
 *        shr64_round(c v_j, 30)), with c from the same exact dot product and division). Each
 *        must be below the bound and equal to reflect's (no tolerance: the same integer).
 *        Before each reflection after the first, every tail's sum of squares must be below
 *        2^61 and tail_shift's one-limb sum (normed) equal to the two-limb one.
 *
 * Inputs: every size up to RFE_N_MAX rows and RFE_TRIA_COLS_MAX columns, dense, with entries
 * at the int32 extremes (INT32_MIN, INT32_MAX, equal and opposite rows, one huge entry among
 * tiny ones, rank-deficient copies) and random entries of random magnitude per row (1 to 31
 * bits), 20,000 matrices.
 *
 * Outside test/numerics/ (mk/lib.mk's TEST_DIRS) as the other tests here: it includes a
 * library source; `make test-c` runs it.
 */
#include "test_common.h"

#include <stdint.h>
#include <string.h>

#include "numerics/qr_q31.c"

/* the derived bound: |result| < 2^30 + 5 */
#define BOUND ((INT64_C(1) << 30) + 5)

static unsigned long n_checked;
static int64_t max_mag;
static uint64_t max_ss; /* the largest one-limb sum of squares of a tail (k >= 1) */

#include "splitmix64.h"

static int32_t buf[RFE_N_MAX * RFE_TRIA_COLS_MAX];

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

#define NR RFE_N_MAX
#define NC RFE_TRIA_COLS_MAX

/* The dense reduction of tria_core_q31 (tri = 0), with every reflection's elements checked. */
static void reduce_checked(size_t rows, size_t cols)
{
    static int32_t before[NR * NC];
    int nonzero[NR] = {0};
    size_t k;
    size_t i;
    size_t j;
    for (k = 0u; k < rows; ++k) {
        const size_t len = cols - k;
        for (i = k; i < rows; ++i) {
            int s = 0;
            uint64_t ss = 0u;
            if (k != 0u) {
                /* tail_shift's one-limb sum (normed, every reflection after the first):
                 * below 2^61 and equal to the two-limb sum, as derived in qr_q31.c */
                uint64_t hi = 0u;
                const uint64_t lo = tail_squares(&buf[(i * cols) + k], len, &hi);
                assert_true(hi == 0u);
                assert_true(lo < (UINT64_C(1) << 61));
                assert_true(tail_squares_normed(&buf[(i * cols) + k], len) == lo);
                if (lo > max_ss) {
                    max_ss = lo;
                }
            }
            nonzero[i] = tail_shift(&buf[(i * cols) + k], len, k, &s, &ss);
            if (nonzero[i] != 0) {
                scale_tail(&buf[(i * cols) + k], len, s);
            }
        }
        if (nonzero[k] == 0) {
            continue;
        }
        memcpy(before, buf, sizeof before);
        (void)reflect(buf, rows, cols, k, len, 0u, nonzero);
        {
            const int32_t *x = &before[(k * cols) + k];
            uint64_t ss = 0u;
            uint64_t x0sq;
            int64_t norm;
            int64_t v0;
            uint64_t vtv;
            for (j = 0u; j < len; ++j) {
                ss += (uint64_t)((int64_t)x[j] * x[j]);
            }
            x0sq = (uint64_t)((int64_t)x[0] * x[0]);
            if (ss == x0sq) {
                continue; /* reflect leaves the rows alone */
            }
            norm = (int64_t)rfe_q31_sqrt_round(ss);
            v0 = (x[0] < 0) ? ((int64_t)x[0] - norm) : ((int64_t)x[0] + norm);
            vtv = (ss - x0sq) + ((uint64_t)(v0 < 0 ? -v0 : v0) * (uint64_t)(v0 < 0 ? -v0 : v0));
            for (i = k + 1u; i < rows; ++i) {
                const int32_t *a = &before[(i * cols) + k];
                int64_t dot = (int64_t)a[0] * v0;
                int64_t c;
                uint64_t cm;
                if (nonzero[i] == 0) {
                    continue;
                }
                for (j = 1u; j < len; ++j) {
                    dot += (int64_t)a[j] * x[j];
                }
                cm = rfe_q31_div_shl32_round((uint64_t)(dot < 0 ? -dot : dot), vtv);
                c = (dot < 0) ? -(int64_t)cm : (int64_t)cm;
                for (j = 0u; j < len; ++j) {
                    const int64_t p = c * ((j == 0u) ? v0 : (int64_t)x[j]);
                    const int64_t want = (int64_t)a[j] - rfe_fix_shr64_round(p, 30u);
                    const int64_t mag = (want < 0) ? -want : want;
                    assert_true((p < (INT64_C(1) << 62)) && (p > -(INT64_C(1) << 62)));
                    if (mag >= BOUND) {
                        fail_msg("reflected element %lld beyond the bound 2^30 + 5",
                                 (long long)want);
                    }
                    assert_int_equal(buf[(i * cols) + k + j], want);
                    if (mag > max_mag) {
                        max_mag = mag;
                    }
                    ++n_checked;
                }
            }
        }
    }
}

static void test_tria_bound(void **state)
{
    unsigned int it;
    (void)state;
    mix_state = 0xB0C0DE21ull;
    n_checked = 0u;
    max_mag = 0;
    max_ss = 0u;
    for (it = 0u; it < 20000u; ++it) {
        const uint64_t r = rand_u64();
        const size_t rows = 1u + (size_t)(r % NR);
        const size_t cols = rows + (size_t)((r >> 8) % ((NC - rows) + 1u));
        fill(rows, cols);
        reduce_checked(rows, cols);
    }
    print_message("%lu reflected elements, largest |value| %lld (bound 2^30 + 5 = %lld)\n",
                  n_checked, (long long)max_mag, (long long)BOUND);
    assert_true(n_checked > 1000000u); /* the check is not empty */
    assert_true(max_mag > (INT64_C(1) << 29)); /* and reached the bound's scale */
    print_message("largest sum of squares of a tail after a reflection %.6f 2^60 (bound 2^61)\n",
                  (double)max_ss / (double)(UINT64_C(1) << 60));
    assert_true(max_ss >= (UINT64_C(1) << 58)); /* the sums reached the normalised scale */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tria_bound),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
