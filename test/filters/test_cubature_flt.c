/**
 * @file test_cubature_flt.c
 * @brief The cubature points, mean and correction (src/filters/cubature_flt.c) with n = 4 states, which
 *        the library computes in copies unrolled for that constant size (issue 21), against the
 *        definitions written out here, and the run-time loops (other n) against the same.
 *
 * Tolerance: none (exact equality). The expected values are the same IEEE operations in the
 * same order on the same rfe_real_t operands: X_j = x + r F e_j, X_{n+j} = x - r F e_j with
 * r = sqrt(n) = 2 (n = 4) or 1 (n = 1), both exact, and the mean as the sum over the points in
 * point order times 1/(2n), the correction x + sum_r K_ir (y_r - z_r) in r order; the builds do not contract a*b + c into a fused multiply-add
 * (-std=c99 sets -ffp-contract=off), so any difference is a bug, not rounding.
 */
#include "test_common.h"

#include "filters/cubature.h"
#include "test_rng.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)

/* Random x (n) and lower-triangular F (n x n, ld NM), values in [-1, 1) + 0.5 on the diagonal. */
static void fill(size_t n, rfe_real_t *x, rfe_real_t *F)
{
    size_t i;
    size_t j;
    for (i = 0u; i < NM; ++i) {
        x[i] = (i < n) ? (rfe_real_t)((2.0 * rng_uniform()) - 1.0) : (rfe_real_t)0.0;
        for (j = 0u; j < NM; ++j) {
            F[(i * NM) + j] = ((i < n) && (j <= i))
                                  ? (rfe_real_t)((2.0 * rng_uniform()) - 1.0 + ((i == j) ? 0.5 : 0.0))
                                  : (rfe_real_t)0.0;
        }
    }
}

static void check_points(size_t n, rfe_real_t r)
{
    rfe_real_t x[RFE_N_MAX];
    rfe_real_t F[RFE_N_MAX * RFE_N_MAX];
    rfe_real_t pts[2 * RFE_N_MAX * RFE_N_MAX];
    size_t i;
    size_t j;
    fill(n, x, F);
    rfe_cub_points(x, F, n, NM, pts);
    for (j = 0u; j < n; ++j) {
        for (i = 0u; i < n; ++i) {
            const rfe_real_t d = r * F[(i * NM) + j];
            assert_true(pts[(j * NM) + i] == (x[i] + d));
            assert_true(pts[((n + j) * NM) + i] == (x[i] - d));
        }
    }
}

/* REQ-SCKF-001 */
static void test_rfe_cub_points_n4_matches_definition(void **state)
{
    int rep;
    (void)state;
    rng_seed(41u);
    for (rep = 0; rep < 20; ++rep) {
        check_points(4u, (rfe_real_t)2.0); /* the unrolled copy: sqrt(4) = 2 exactly */
        check_points(1u, (rfe_real_t)1.0); /* the run-time loops: sqrt(1) = 1 exactly */
    }
}

static void check_mean(size_t n, size_t cols)
{
    rfe_real_t rows[2 * RFE_N_MAX * RFE_M_MAX];
    rfe_real_t mean[RFE_M_MAX];
    const rfe_real_t w = (rfe_real_t)1.0 / ((rfe_real_t)2.0 * (rfe_real_t)n);
    size_t i;
    size_t j;
    for (j = 0u; j < (2u * NM * MM); ++j) {
        rows[j] = (rfe_real_t)((2.0 * rng_uniform()) - 1.0);
    }
    rfe_cub_mean(rows, n, cols, MM, mean);
    for (i = 0u; i < cols; ++i) {
        rfe_real_t acc = (rfe_real_t)0.0;
        for (j = 0u; j < (2u * n); ++j) {
            acc += rows[(j * MM) + i];
        }
        assert_true(mean[i] == (acc * w));
    }
}

/* REQ-SCKF-001 */
static void test_rfe_cub_mean_n4_matches_definition(void **state)
{
    int rep;
    (void)state;
    rng_seed(42u);
    for (rep = 0; rep < 20; ++rep) {
        check_mean(4u, 3u); /* the unrolled copy (n = 4, 3 measurements) */
        check_mean(4u, 2u); /* the run-time loops */
        check_mean(2u, 3u); /* the run-time loops */
    }
}

static void check_correct(size_t n, size_t m)
{
    rfe_real_t x[RFE_N_MAX];
    rfe_real_t Kt[RFE_M_MAX * RFE_N_MAX];
    rfe_real_t y[RFE_M_MAX];
    rfe_real_t zhat[RFE_M_MAX];
    rfe_real_t x_new[RFE_N_MAX];
    size_t i;
    size_t r;
    for (i = 0u; i < NM; ++i) {
        x[i] = (rfe_real_t)((2.0 * rng_uniform()) - 1.0);
    }
    for (r = 0u; r < MM; ++r) {
        y[r] = (rfe_real_t)((2.0 * rng_uniform()) - 1.0);
        zhat[r] = (rfe_real_t)((2.0 * rng_uniform()) - 1.0);
        for (i = 0u; i < NM; ++i) {
            Kt[(r * NM) + i] = (rfe_real_t)((2.0 * rng_uniform()) - 1.0);
        }
    }
    assert_int_equal(rfe_cub_correct(x, Kt, y, zhat, n, m, NM, x_new), RFE_OK);
    for (i = 0u; i < n; ++i) {
        rfe_real_t acc = x[i];
        for (r = 0u; r < m; ++r) {
            acc += Kt[(r * NM) + i] * (y[r] - zhat[r]);
        }
        assert_true(x_new[i] == acc);
    }
}

/* REQ-SCKF-001 */
static void test_rfe_cub_correct_n4_matches_definition(void **state)
{
    int rep;
    (void)state;
    rng_seed(43u);
    for (rep = 0; rep < 20; ++rep) {
        check_correct(4u, 3u); /* the unrolled copy */
        check_correct(4u, 2u); /* the run-time loops */
        check_correct(3u, 3u); /* the run-time loops */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_cub_points_n4_matches_definition),
        cmocka_unit_test(test_rfe_cub_mean_n4_matches_definition),
        cmocka_unit_test(test_rfe_cub_correct_n4_matches_definition),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
