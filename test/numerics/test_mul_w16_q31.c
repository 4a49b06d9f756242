/**
 * @file test_mul_w16_q31.c
 * @brief The Cortex-M0+'s 32 x 32 -> 64 multiplies from 16-bit partial products (rfe/fixed.h:
 *        rfe_fix_mul32x32, rfe_fix_umul32x32, rfe_fix_mul_m31, and rfe_q31_mul64x32 built on
 *        them), run here on the host: this file sets RFE_FIX_MUL64_W16 to 1 before the
 *        headers, so every helper below takes the form the Thumb-1 build takes.
 *
 * Every result must equal the exact product bit for bit (no tolerance): the int64 / uint64
 * product of the operands, and for rfe_q31_mul64x32 the 128-bit product rounded half up
 * (GCC's and Clang's __int128 where the host has it). Operands: every pair of a set of edge
 * values (0, +-1, the 16-bit half boundaries, +-(2^31 - 1), -2^31, +-2^31 for the int64
 * forms) and random pairs, uniform and with a log-uniform magnitude. Also rfe_q31_div_round
 * (internal_q31.h), whose quotient comes from 32-bit divisions where it fits 32 bits, against
 * the 64-bit division.
 */
#define RFE_FIX_MUL64_W16 1

#include "test_common.h"

#include <stdint.h>

#include "rfe/fixed.h"
#include "numerics/internal_q31.h"
#include "rfe/component/fxmath.h"
#include "test_light.h"
#include "test_rng.h"

/* Light mode (valgrind): every 10th random pair. */
#define LIGHT_STEP ((int)rfe_test_stride(10u))

static uint32_t rand_u32(void) { return (uint32_t)floor(ldexp(rng_uniform(), 32)); }

/* A random int32 with a log-uniform magnitude (bit length 0 .. 31) and a random sign. */
static int32_t rand_i32_log(void)
{
    const unsigned int bits = rand_u32() % 32u;
    const uint32_t m = (bits == 0u) ? 0u : (rand_u32() >> (32u - bits));
    return ((rand_u32() & 1u) != 0u) ? -(int32_t)m : (int32_t)m;
}

static const int64_t edge[] = {0,
                               1,
                               -1,
                               2,
                               -2,
                               0x7FFF,
                               -0x7FFF,
                               0x8000,
                               -0x8000,
                               0xFFFF,
                               -0xFFFF,
                               0x10000,
                               -0x10000,
                               0x10001,
                               -0x10001,
                               0x7FFF8000,
                               -0x7FFF8000,
                               0x7FFFFFFE,
                               0x40000000,
                               -0x40000000,
                               0x55555555,
                               -0x55555555,
                               INT32_MAX,
                               -INT32_MAX,
                               INT32_MIN,
                               (int64_t)1 << 31}; /* the last: rfe_fix_mul_m31 only */
#define N_EDGE (sizeof edge / sizeof edge[0])

/* REQ-FXP-001 */
static void test_mul32x32_edges(void **state)
{
    size_t i;
    size_t j;
    (void)state;
    for (i = 0u; i < N_EDGE; ++i) {
        for (j = 0u; j < N_EDGE; ++j) {
            const int64_t a = edge[i];
            const int64_t b = edge[j];
            assert_true(rfe_fix_mul_m31(a, b) == a * b);
            if ((i < (N_EDGE - 1u)) && (j < (N_EDGE - 1u))) {
                const int32_t a32 = (int32_t)a;
                const int32_t b32 = (int32_t)b;
                const uint32_t ua = (uint32_t)a32;
                const uint32_t ub = (uint32_t)b32;
                assert_true(rfe_fix_mul32x32(a32, b32) == a * b);
                assert_true(rfe_fix_mul32x32_w16(a32, b32) == a * b);
                /* the unsigned form over the whole uint32 range (the patterns of the edges) */
                assert_true(rfe_fix_umul32x32(ua, ub) == (uint64_t)ua * (uint64_t)ub);
            }
        }
    }
    assert_true(rfe_fix_umul32x32(UINT32_MAX, UINT32_MAX) == (uint64_t)UINT32_MAX * UINT32_MAX);
    assert_true(rfe_fix_umul31_w16(0x80000000u, 0x80000000u) == ((uint64_t)1 << 62));
}

/* REQ-FXP-001 */
static void test_mul32x32_random(void **state)
{
    int k;
    (void)state;
    rng_seed(2112u);
    for (k = 0; k < 400000; k += LIGHT_STEP) {
        const int32_t a = ((k & 2) != 0) ? rand_i32_log() : (int32_t)rand_u32();
        const int32_t b = ((k & 4) != 0) ? rand_i32_log() : (int32_t)rand_u32();
        const uint32_t ua = rand_u32();
        const uint32_t ub = ((k & 8) != 0) ? (uint32_t)rand_i32_log() : rand_u32();
        assert_true(rfe_fix_mul32x32(a, b) == (int64_t)a * (int64_t)b);
        assert_true(rfe_fix_umul32x32(ua, ub) == (uint64_t)ua * (uint64_t)ub);
        assert_true(rfe_fix_mul_m31((int64_t)a, (int64_t)b) == (int64_t)a * (int64_t)b);
    }
}

/* round(num / den), ties away from zero, saturated to +-INT32_MAX with a count: the 64-bit
 * division on the magnitude */
static int32_t ref_div_round(int64_t num, int32_t den, uint32_t *sat)
{
    const uint64_t mag = (num < 0) ? ((uint64_t)(-(num + 1)) + 1u) : (uint64_t)num;
    const uint64_t d = (uint64_t)den;
    uint64_t q = (mag / d) + (((2u * (mag % d)) >= d) ? 1u : 0u);
    if (q > (uint64_t)INT32_MAX) {
        q = (uint64_t)INT32_MAX;
        ++*sat;
    }
    return (num < 0) ? -(int32_t)q : (int32_t)q;
}

/* rfe_q31_div_round's 32-bit quotient (where it fits: |num| < den 2^32) and its 64-bit
 * fallback against the 64-bit division: every result and every saturation count equal, at
 * the edges (ties, quotients around 2^31 and 2^32, INT64_MIN) and on random operands. */
/* REQ-FXP-001 */
static void test_div_round_paths(void **state)
{
    static const int64_t nums[] = {0, 1, -1, 2, -3, 5, -5, INT32_MAX, INT32_MIN,
                                   ((int64_t)1 << 32) - 1, (int64_t)1 << 32, -((int64_t)1 << 32),
                                   ((int64_t)1 << 62) + 12345, INT64_MAX, INT64_MIN,
                                   -INT64_MAX};
    static const int32_t dens[] = {1, 2, 3, 7, 0xFFFF, 0x10000, 0x7FFFFFFE, INT32_MAX};
    int k;
    size_t i;
    size_t j;
    (void)state;
    for (i = 0u; i < sizeof nums / sizeof nums[0]; ++i) {
        for (j = 0u; j < sizeof dens / sizeof dens[0]; ++j) {
            uint32_t sat = 0u;
            uint32_t want_sat = 0u;
            const int32_t want = ref_div_round(nums[i], dens[j], &want_sat);
            assert_int_equal(rfe_q31_div_round(nums[i], dens[j], &sat), want);
            assert_int_equal(sat, want_sat);
        }
    }
    rng_seed(2114u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        const unsigned int bits = rand_u32() % 64u;
        const uint64_t m = (((uint64_t)rand_u32() << 32) | rand_u32()) >> (63u - bits) >> 1;
        const int64_t num = ((k & 1) != 0) ? -(int64_t)m : (int64_t)m;
        const int32_t den = (int32_t)(1u + ((rand_u32() >> (rand_u32() % 32u)) & 0x7FFFFFFEu));
        uint32_t sat = 0u;
        uint32_t want_sat = 0u;
        const int32_t want = ref_div_round(num, den, &want_sat);
        assert_int_equal(rfe_q31_div_round(num, den, &sat), want);
        assert_int_equal(sat, want_sat);
    }
}

/* rfe_q31_div_round_by (the reciprocal of an invariant divisor, Moller-Granlund) against the
 * 64-bit division: every result and count equal, at the edges above, at the ties and their
 * neighbours (num = q den + floor(den / 2) + {-1, 0, 1}, where the rounding turns) for
 * quotients up to and around 2^31 and 2^32, and on random operands. */
/* REQ-FXP-001 */
static void check_div_by(int64_t num, int32_t den, const rfe_q31_recip_t *r)
{
    uint32_t sat = 0u;
    uint32_t want_sat = 0u;
    const int32_t want = ref_div_round(num, den, &want_sat);
    assert_int_equal(rfe_q31_div_round_by(num, r, &sat), want);
    assert_int_equal(sat, want_sat);
}

static void test_div_round_by(void **state)
{
    static const int64_t nums[] = {0, 1, -1, 2, -3, 5, -5, INT32_MAX, INT32_MIN,
                                   ((int64_t)1 << 32) - 1, (int64_t)1 << 32, -((int64_t)1 << 32),
                                   ((int64_t)1 << 62) + 12345, INT64_MAX, INT64_MIN,
                                   -INT64_MAX};
    static const int32_t dens[] = {1, 2, 3, 7, 0xFFFF, 0x10000, 0x40000000, 0x7FFFFFFE,
                                   INT32_MAX};
    static const uint64_t quots[] = {0u, 1u, 2u, 0x7FFFFFFEu, 0x7FFFFFFFu, 0x80000000u,
                                     0xFFFFFFFEu, 0xFFFFFFFFu};
    int k;
    size_t i;
    size_t j;
    (void)state;
    for (j = 0u; j < sizeof dens / sizeof dens[0]; ++j) {
        rfe_q31_recip_t r;
        rfe_q31_recip_init(&r, dens[j]);
        for (i = 0u; i < sizeof nums / sizeof nums[0]; ++i) {
            check_div_by(nums[i], dens[j], &r);
        }
        for (i = 0u; i < sizeof quots / sizeof quots[0]; ++i) {
            const uint64_t base = (quots[i] * (uint64_t)dens[j]) + ((uint64_t)dens[j] / 2u);
            int64_t t;
            for (t = -1; t <= 1; ++t) {
                const int64_t num = (int64_t)base + t;
                if (num >= 0) {
                    check_div_by(num, dens[j], &r);
                    check_div_by(-num, dens[j], &r);
                }
            }
        }
    }
    rng_seed(2115u);
    for (k = 0; k < 400000; k += LIGHT_STEP) {
        const unsigned int bits = rand_u32() % 64u;
        const uint64_t m = (((uint64_t)rand_u32() << 32) | rand_u32()) >> (63u - bits) >> 1;
        const int64_t num = ((k & 1) != 0) ? -(int64_t)m : (int64_t)m;
        const int32_t den = (int32_t)(1u + ((rand_u32() >> (rand_u32() % 32u)) & 0x7FFFFFFEu));
        rfe_q31_recip_t r;
        rfe_q31_recip_init(&r, den);
        check_div_by(num, den, &r);
    }
}

/* The tyre model's shared-divisor quotients (tyre_q31.c div2_q30): rfe_fix_div(a, b, 30) and
 * rfe_q31_div_round_by(a 2^30, reciprocal of b) must be the same integer for every int32 a and
 * b > 0, saturation included (both round a 2^30 / b to nearest, ties away from zero, into the
 * symmetric int32 range): the edges and 200,000 random pairs of random lengths. */
/* REQ-FXP-001 */
static void check_div30(int32_t a, int32_t b)
{
    rfe_q31_recip_t r;
    int32_t want = 0;
    uint32_t sat_div = 0u;
    uint32_t sat_by = 0u;
    assert_int_equal(rfe_fix_div(a, b, 30, &want, &sat_div), RFE_OK);
    rfe_q31_recip_init(&r, b);
    assert_int_equal(rfe_q31_div_round_by((int64_t)a * ((int64_t)1 << 30), &r, &sat_by), want);
    assert_int_equal(sat_by, sat_div);
}

static void test_div30_by_recip(void **state)
{
    static const int32_t as[] = {0, 1, -1, 3, -3, 0x3FFFFFFF, 0x40000000, -0x40000000,
                                 INT32_MAX, INT32_MIN, INT32_MIN + 1};
    static const int32_t bs[] = {1, 2, 3, 0x3FFFFFFF, 0x40000000, 0x40000001, 0x5A827999,
                                 INT32_MAX};
    size_t i;
    size_t j;
    int k;
    (void)state;
    for (i = 0u; i < sizeof as / sizeof as[0]; ++i) {
        for (j = 0u; j < sizeof bs / sizeof bs[0]; ++j) {
            check_div30(as[i], bs[j]);
        }
    }
    rng_seed(2116u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        const int32_t a = (int32_t)(rand_u32() >> (rand_u32() % 32u)) * (((k & 1) != 0) ? -1 : 1);
        const int32_t b = (int32_t)(1u + ((rand_u32() >> (rand_u32() % 32u)) & 0x7FFFFFFEu));
        check_div30(a, b);
    }
}

#if defined(__SIZEOF_INT128__)
__extension__ typedef __int128 i128_t;

/* floor((v c + 2^(s-1)) / 2^s) in 128 bits, without shifting a negative value */
static int64_t ref_mul64x32(int64_t v, int64_t c, unsigned int s)
{
    const i128_t p = ((i128_t)v * (i128_t)c) + ((i128_t)1 << (s - 1u));
    const i128_t d = (i128_t)1 << s;
    const i128_t q = (p >= 0) ? (p / d) : -((-p + d - 1) / d);
    return (int64_t)q;
}

/* rfe_q31_mul64x32's M0+ form (its products from rfe_fix_umul32x32 and rfe_fix_mul_m31)
 * against the 128-bit product, within its preconditions (|v| < 2^62, |c| <= 2^31, the result
 * below 2^62). */
/* REQ-FXP-001 */
static void test_mul64x32_w16(void **state)
{
    static const int64_t cs[] = {0, 1, -1, 0x7FFF, 0x10000, -0x10001, INT32_MAX, -INT32_MAX,
                                 INT32_MIN, (int64_t)1 << 31};
    int k;
    size_t i;
    (void)state;
    for (i = 0u; i < sizeof cs / sizeof cs[0]; ++i) {
        unsigned int s;
        for (s = 31u; s <= 62u; ++s) {
            const int64_t vmax = ((int64_t)1 << 62) - 1;
            assert_true(rfe_q31_mul64x32(vmax, cs[i], s) == ref_mul64x32(vmax, cs[i], s));
            assert_true(rfe_q31_mul64x32(-vmax, cs[i], s) == ref_mul64x32(-vmax, cs[i], s));
            assert_true(rfe_q31_mul64x32(-1, cs[i], s) == ref_mul64x32(-1, cs[i], s));
            assert_true(rfe_q31_mul64x32(0xFFFFFFFF, cs[i], s) == ref_mul64x32(0xFFFFFFFF, cs[i], s));
        }
    }
    rng_seed(2113u);
    for (k = 0; k < 200000; k += LIGHT_STEP) {
        /* |v| < 2^62 with a random bit length, c any int32 or +-2^31; s >= 31 keeps the
         * result below 2^62 (|v c| < 2^93) */
        const unsigned int bits = rand_u32() % 63u;
        const uint64_t m = (((uint64_t)rand_u32() << 32) | rand_u32()) >> (64u - (bits + 1u));
        const int64_t v = ((k & 1) != 0) ? -(int64_t)(m >> 1) : (int64_t)(m >> 1);
        const int64_t c = ((k % 97) == 0) ? (((k & 2) != 0) ? INT32_MIN : ((int64_t)1 << 31))
                                          : (int64_t)(int32_t)rand_u32();
        const unsigned int s = 31u + (rand_u32() % 32u);
        assert_true(rfe_q31_mul64x32(v, c, s) == ref_mul64x32(v, c, s));
    }
}
#endif

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mul32x32_edges),
        cmocka_unit_test(test_mul32x32_random),
        cmocka_unit_test(test_div_round_paths),
        cmocka_unit_test(test_div_round_by),
        cmocka_unit_test(test_div30_by_recip),
#if defined(__SIZEOF_INT128__)
        cmocka_unit_test(test_mul64x32_w16),
#endif
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
