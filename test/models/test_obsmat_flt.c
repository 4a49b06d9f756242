/**
 * @file test_obsmat_flt.c
 * @brief Observation matrix H(u) (MODEL.md §5) against its definition.
 *
 * Tolerances. Double: H is linear in the forces, so central differences of an independent
 * rigid-body force/moment sum are exact up to rounding: 1e-9 relative of the column scale.
 * Float32: entries are sums of ~3 products of float values (relative 6e-8 each), so 1e-5
 * relative of the column scale leaves a 100x margin.
 */
#include "test_common.h"

#include <string.h>

#include "rfe/component/obsmat.h"
#include "rfe/params.h"

#if defined(RFE_REAL_DOUBLE)
#define TOL_REL 1e-9
#else
#define TOL_REL 1e-5
#endif

static rfe_params_t params;

static int setup(void **state)
{
    (void)state;
    return rfe_params_default(&params) == RFE_OK ? 0 : -1;
}

/* Independent rigid-body sum (double): each wheel's force (mu_i * F0 in wheel axes)
 * rotated by its steer angle into body axes, accelerations = sum F / m, yaw acceleration =
 * sum (r_i x F_i)_z / J with r_i the wheel position from the CoG. */
static void body_accel(const double mu[4], const double fx[4], const double fy[4], double delta,
                       double out[3])
{
    const double m = params.vehicle.m, J = params.vehicle.J;
    const double px[4] = {params.vehicle.Lf, params.vehicle.Lf, -params.vehicle.Lr, -params.vehicle.Lr};
    const double py[4] = {params.vehicle.Bf / 2, -params.vehicle.Bf / 2, params.vehicle.Br / 2,
                          -params.vehicle.Br / 2};
    size_t i;
    out[0] = out[1] = out[2] = 0.0;
    for (i = 0; i < 4; ++i) {
        const double d = i < 2 ? delta : 0.0;
        const double Fb[2] = {mu[i] * (fx[i] * cos(d) - fy[i] * sin(d)),
                              mu[i] * (fx[i] * sin(d) + fy[i] * cos(d))};
        out[0] += Fb[0] / m;
        out[1] += Fb[1] / m;
        out[2] += (px[i] * Fb[1] - py[i] * Fb[0]) / J;
    }
}

/* REQ: column i of H is d(y)/d(mu_i) of the rigid-body accelerations (finite differences). */
/* REQ-OBSMAT-001 */
static void test_rfe_obsmat_build_equals_finite_differences(void **state)
{
    unsigned seed = 12345u;
    int trial;
    (void)state;
    for (trial = 0; trial < 200; ++trial) {
        double fx[4], fy[4], mu[4], delta, scale;
        rfe_real_t rfx[4], rfy[4], H[12];
        size_t i, r;
        for (i = 0; i < 4; ++i) {
            seed = seed * 1103515245u + 12345u;
            fx[i] = ((double)(seed >> 8) / 16777216.0 - 0.5) * 12000.0;
            seed = seed * 1103515245u + 12345u;
            fy[i] = ((double)(seed >> 8) / 16777216.0 - 0.5) * 12000.0;
            rfx[i] = (rfe_real_t)fx[i];
            rfy[i] = (rfe_real_t)fy[i];
            fx[i] = (double)rfx[i]; /* compare on the values the library saw */
            fy[i] = (double)rfy[i];
            mu[i] = 0.5;
        }
        seed = seed * 1103515245u + 12345u;
        delta = (double)(rfe_real_t)(((double)(seed >> 8) / 16777216.0 - 0.5) * 1.2);
        assert_int_equal(rfe_obsmat_build(&params.vehicle, (rfe_real_t)delta, rfx, rfy, H),
                         RFE_OK);
        for (i = 0; i < 4; ++i) {
            double yp[3], ym[3];
            const double h = 1e-3;
            mu[i] = 0.5 + h;
            body_accel(mu, fx, fy, delta, yp);
            mu[i] = 0.5 - h;
            body_accel(mu, fx, fy, delta, ym);
            mu[i] = 0.5;
            scale = (fabs(fx[i]) + fabs(fy[i])) / params.vehicle.m + 1e-12;
            for (r = 0; r < 3; ++r) {
                const double fd = (yp[r] - ym[r]) / (2 * h);
                assert_close(H[RFE_H_AT(r, i)], fd, TOL_REL * scale * 10.0, 0.0, "H column");
            }
        }
    }
}

/* REQ: h(x, u) = H x. */
/* REQ-OBSMAT-002 */
static void test_rfe_obsmat_apply_is_matrix_product(void **state)
{
    rfe_real_t H[12], x[4] = {(rfe_real_t)0.3, (rfe_real_t)0.9, (rfe_real_t)0.1, (rfe_real_t)1.1};
    rfe_real_t y[3];
    size_t k;
    (void)state;
    for (k = 0; k < 12; ++k) {
        H[k] = (rfe_real_t)((double)k - 5.5);
    }
    assert_int_equal(rfe_obsmat_apply(H, x, y), RFE_OK);
    for (k = 0; k < 3; ++k) {
        const double want = (double)H[4 * k] * x[0] + (double)H[4 * k + 1] * x[1] +
                            (double)H[4 * k + 2] * x[2] + (double)H[4 * k + 3] * x[3];
        assert_close(y[k], want, 1e-6, TOL_REL, "H x");
    }
}

/* REQ: straight driving: the yaw row sees only the left/right difference. */
/* REQ-OBSMAT-003 */
static void test_rfe_obsmat_build_straight_braking_structure(void **state)
{
    const rfe_real_t fx[4] = {-3000, -3000, -2000, -2000}, fy[4] = {0, 0, 0, 0};
    rfe_real_t H[12];
    (void)state;
    assert_int_equal(rfe_obsmat_build(&params.vehicle, 0, fx, fy, H), RFE_OK);
    /* Equal mu left and right: zero yaw moment. */
    assert_close(H[RFE_H_AT(2, 0)] + H[RFE_H_AT(2, 1)], 0.0, 1e-9, 0.0, "front yaw cancels");
    assert_close(H[RFE_H_AT(2, 2)] + H[RFE_H_AT(2, 3)], 0.0, 1e-9, 0.0, "rear yaw cancels");
    /* Braking left wheel (negative Fx at y = +B/2) turns the car left: positive moment. */
    assert_true(H[RFE_H_AT(2, 0)] > 0);
    assert_true(H[RFE_H_AT(1, 0)] == 0 && H[RFE_H_AT(1, 3)] == 0);
    assert_close(H[RFE_H_AT(0, 0)], -3000.0 / params.vehicle.m, 1e-9, TOL_REL, "ax row");
}

/* REQ: bad input gives distinct statuses and no output. */
/* REQ-OBSMAT-004 */
static void test_rfe_obsmat_rejects_bad_input(void **state)
{
    rfe_real_t fx[4] = {1, 2, 3, 4}, fy[4] = {1, 2, 3, 4}, H[12], x[4] = {1, 1, 1, 1}, y[3];
    size_t k;
    (void)state;
    for (k = 0; k < 12; ++k) {
        H[k] = 7;
    }
    assert_int_equal(rfe_obsmat_build(NULL, 0, fx, fy, H), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build(&params.vehicle, (rfe_real_t)NAN, fx, fy, H),
                     RFE_ERR_NONFINITE);
    fy[2] = (rfe_real_t)INFINITY;
    assert_int_equal(rfe_obsmat_build(&params.vehicle, 0, fx, fy, H), RFE_ERR_NONFINITE);
    assert_true(H[0] == 7 && H[11] == 7);
    assert_int_equal(rfe_obsmat_apply(H, NULL, y), RFE_ERR_NULL);
    x[1] = (rfe_real_t)NAN;
    assert_int_equal(rfe_obsmat_apply(H, x, y), RFE_ERR_NONFINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_obsmat_build_equals_finite_differences),
        cmocka_unit_test(test_rfe_obsmat_apply_is_matrix_product),
        cmocka_unit_test(test_rfe_obsmat_build_straight_braking_structure),
        cmocka_unit_test(test_rfe_obsmat_rejects_bad_input),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
