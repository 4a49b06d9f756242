/**
 * @file test_philox_flt.c
 * @brief The random stream of the tyre identifier (docs/TYRE_ID.md §6): Philox4x64-10
 *        against the Random123 known answers, and the stream's words, uniforms and normals
 *        against the reference (scenarios/golden/tyre_id/stream.csv, written by
 *        scripts/reference/philox.py through `make tyre-id-goldens`).
 *
 * Tolerances.
 * - Words: integers, exactly, in both builds.
 * - Double build: the uniform is exact arithmetic on the word (((w >> 12) + 0.5) 2^-52) and
 *   the normal the same libm calls in the same order as the reference's libm backend: both
 *   exactly (bit for bit).
 * - Float build: the uniform keeps the top 23 bits, ((w >> 41) + 0.5) 2^-23, so it differs
 *   from the double's by at most 2^-24 (the dropped bits and the different centring, each
 *   below half a float step); checked exactly against that formula evaluated in double too.
 *   The normal rho cos(th) (or sin) moves with u_b by at most 2 pi rho |du_b| <= 2 pi rho
 *   2^-24 and with u_a by |d rho| = |du_a| / (u_a rho) <= 2^-24 / (u_a rho); the float libm
 *   calls and products add a few float ulps of rho (4e-7 absolute in th = 2 pi u_b before the
 *   cosine): bound 2 pi rho 2^-24 + 2^-24 / (u_a rho) + 2e-6 rho, per normal.
 */
#include "test_common.h"

#include <stdint.h>
#include <string.h>

#include "rfe/component/philox.h"
#include "table.h"

#define STREAM_GOLDEN "scenarios/golden/tyre_id/stream.csv"

/* Random123 tests/kat_vectors, the three philox4x64 10-round lines (the same the reference's
 * test_tyre_id.py pins NumPy and its plain-integer rounds to). */
static const uint64_t KAT[3][10] = {
    {0u, 0u, 0u, 0u, 0u, 0u, 0x16554d9eca36314cu, 0xdb20fe9d672d0fdcu, 0xd7e772cee186176bu,
     0x7e68b68aec7ba23bu},
    {UINT64_MAX, UINT64_MAX, UINT64_MAX, UINT64_MAX, UINT64_MAX, UINT64_MAX,
     0x87b092c3013fe90bu, 0x438c3c67be8d0224u, 0x9cc7d7c69cd777b6u, 0xa09caebf594f0ba0u},
    {0x243f6a8885a308d3u, 0x13198a2e03707344u, 0xa4093822299f31d0u, 0x082efa98ec4e6c89u,
     0x452821e638d01377u, 0xbe5466cf34e90c6cu, 0xa528f45403e61d95u, 0x38c72dbd566e9788u,
     0xa5a1610e72fd18b5u, 0x57bd43b5e52b7fe6u},
};

/* REQ-TID-001 */
static void test_block_matches_random123_known_answers(void **state)
{
    size_t i;
    (void)state;
    for (i = 0u; i < 3u; ++i) {
        uint64_t out[4];
        assert_int_equal(rfe_philox_block(&KAT[i][0], &KAT[i][4], out), RFE_OK);
        assert_true(out[0] == KAT[i][6]);
        assert_true(out[1] == KAT[i][7]);
        assert_true(out[2] == KAT[i][8]);
        assert_true(out[3] == KAT[i][9]);
    }
}

static uint64_t u64(double hi, double lo)
{
    return (((uint64_t)hi) << 32) | (uint64_t)lo;
}

/* REQ-TID-001 */
static void test_stream_matches_reference(void **state)
{
    test_table_t g;
    size_t k;
    (void)state;
    memset(&g, 0, sizeof(g));
    assert_int_equal(test_table_load(STREAM_GOLDEN, &g), 0);
    assert_true(g.n_rows >= 30u);
    for (k = 0u; k < g.n_rows; ++k) {
        const uint64_t seed = u64(test_table_get(&g, k, "seed_hi"), test_table_get(&g, k, "seed_lo"));
        const uint64_t c1 = u64(test_table_get(&g, k, "c1_hi"), test_table_get(&g, k, "c1_lo"));
        const uint64_t c2 = (uint64_t)test_table_get(&g, k, "c2");
        const uint64_t n = (uint64_t)test_table_get(&g, k, "n");
        const uint64_t want = u64(test_table_get(&g, k, "w_hi"), test_table_get(&g, k, "w_lo"));
        const double u_ref = test_table_get(&g, k, "uniform");
        const double z_ref = test_table_get(&g, k, "normal");
        rfe_philox_t s;
        uint64_t w = 0u;
        rfe_real_t u = 0;
        rfe_real_t z[2];
        char what[96];
        snprintf(what, sizeof(what), "stream row %zu", k);
        assert_int_equal(rfe_philox_stream(&s, seed, c1, c2), RFE_OK);
        assert_int_equal(rfe_philox_word(&s, n, &w), RFE_OK);
        assert_true(w == want);
        assert_int_equal(rfe_philox_uniform(&s, n, &u), RFE_OK);
        assert_int_equal(rfe_philox_normal_pair(&s, n / 2u, z), RFE_OK);
#if defined(RFE_REAL_DOUBLE)
        assert_true(u == u_ref);
        assert_true(z[n % 2u] == z_ref);
#else
        {
            /* the float formula evaluated exactly in double, and its distance to the double's */
            const double u_f = ((double)(w >> 41) + 0.5) * 1.1920928955078125e-07;
            uint64_t wa = 0u;
            double ua;
            double rho;
            assert_true((double)u == u_f);
            assert_close(u, u_ref, 5.9604644775390625e-08, 0.0, what); /* 2^-24 */
            assert_int_equal(rfe_philox_word(&s, 2u * (n / 2u), &wa), RFE_OK);
            ua = ((double)(wa >> 12) + 0.5) * 2.220446049250313e-16;
            rho = sqrt(-2.0 * log(ua));
            assert_close(z[n % 2u], z_ref,
                         6.283185307179586 * rho * 5.96e-8 + 5.96e-8 / (ua * rho) + 2e-6 * rho,
                         0.0, what);
        }
#endif
    }
    test_table_free(&g);
}

/* REQ-TID-001: the stream caches one block; reading words out of order must give the same
 * words as in order, and uniforms lie strictly inside (0, 1). */
static void test_words_out_of_order_and_uniform_range(void **state)
{
    rfe_philox_t s;
    uint64_t fwd[12];
    uint64_t w = 0u;
    size_t i;
    (void)state;
    assert_int_equal(rfe_philox_stream(&s, 99u, 5u, 2u), RFE_OK);
    for (i = 0u; i < 12u; ++i) {
        assert_int_equal(rfe_philox_word(&s, (uint64_t)i, &fwd[i]), RFE_OK);
    }
    for (i = 12u; i > 0u; --i) {
        assert_int_equal(rfe_philox_word(&s, (uint64_t)(i - 1u), &w), RFE_OK);
        assert_true(w == fwd[i - 1u]);
    }
    {
        /* block 1 of the same counter, computed directly */
        const uint64_t ctr[4] = {1u, 5u, 2u, 0u};
        const uint64_t key[2] = {99u, 0u};
        uint64_t out[4];
        assert_int_equal(rfe_philox_block(ctr, key, out), RFE_OK);
        assert_true(out[0] == fwd[4]);
        assert_true(out[3] == fwd[7]);
    }
    for (i = 0u; i < 400u; ++i) {
        rfe_real_t u = 0;
        assert_int_equal(rfe_philox_uniform(&s, (uint64_t)i, &u), RFE_OK);
        assert_true((u > 0) && (u < 1));
    }
}

/* REQ-TID-001 */
static void test_null_arguments(void **state)
{
    rfe_philox_t s;
    uint64_t w = 0u;
    uint64_t out[4];
    rfe_real_t u = 0;
    rfe_real_t z[2];
    (void)state;
    assert_int_equal(rfe_philox_block(NULL, KAT[0], out), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_block(KAT[0], NULL, out), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_block(KAT[0], KAT[0], NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_stream(NULL, 1u, 0u, 0u), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_stream(&s, 1u, 0u, 0u), RFE_OK);
    assert_int_equal(rfe_philox_word(NULL, 0u, &w), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_word(&s, 0u, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_uniform(&s, 0u, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_uniform(NULL, 0u, &u), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_normal_pair(NULL, 0u, z), RFE_ERR_NULL);
    assert_int_equal(rfe_philox_normal_pair(&s, 0u, NULL), RFE_ERR_NULL);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_block_matches_random123_known_answers),
        cmocka_unit_test(test_stream_matches_reference),
        cmocka_unit_test(test_words_out_of_order_and_uniform_range),
        cmocka_unit_test(test_null_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
