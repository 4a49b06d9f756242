/**
 * @file test_mcdc_meas_flt.c
 * @brief rfe_meas_eval's non-finite paths in both tyre modes (make coverage / make mcdc):
 *        a non-finite μ in paper mode, and an acceleration sum that overflows in absolute
 *        mode (finite forces, a yaw inertia at the bottom of the normal range). Each must
 *        return RFE_ERR_NONFINITE and leave z untouched; the same call with sane values
 *        succeeds. No tolerances (statuses and memcmp).
 */
#include "test_common.h"

#include <float.h>
#include <string.h>

#include "rfe/component/meas.h"
#include "rfe/params.h"

#if defined(RFE_REAL_DOUBLE)
#define REAL_TINY DBL_MIN
#else
#define REAL_TINY FLT_MIN
#endif

static rfe_params_t paper;

static int setup(void **state)
{
    (void)state;
    return (rfe_params_paper(&paper) == RFE_OK) ? 0 : -1;
}

static rfe_sample_t braking_turn(void)
{
    rfe_sample_t u;
    size_t w;
    memset(&u, 0, sizeof u);
    u.delta = (rfe_real_t)0.03;
    u.vx = (rfe_real_t)20.0;
    u.yaw_rate = (rfe_real_t)0.1;
    u.ax = (rfe_real_t)-3.0;
    u.ay = (rfe_real_t)2.0;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        u.omega[w] = (rfe_real_t)(20.0 * 0.96 / 0.325);
    }
    return u;
}

/* REQ-MEAS-002 */
static void test_mcdc_meas_eval_nonfinite_mu_paper(void **state)
{
    const rfe_sample_t u = braking_turn();
    rfe_meas_t h;
    rfe_real_t mu[RFE_WHEELS] = {(rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5};
    rfe_real_t z[RFE_MEAS], zb[RFE_MEAS];
    size_t w;
    (void)state;
    assert_int_equal(paper.tyre.mode, RFE_TYRE_PAPER);
    assert_int_equal(rfe_meas_setup(&h, &paper.vehicle, &paper.tyre, &u), RFE_OK);
    memset(z, 0x5a, sizeof z);
    memcpy(zb, z, sizeof z);
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        mu[w] = (rfe_real_t)NAN;
        assert_int_equal(rfe_meas_eval(&h, &paper.vehicle, &paper.tyre, mu, z), RFE_ERR_NONFINITE);
        mu[w] = (rfe_real_t)INFINITY;
        assert_int_equal(rfe_meas_eval(&h, &paper.vehicle, &paper.tyre, mu, z), RFE_ERR_NONFINITE);
        mu[w] = (rfe_real_t)0.5;
    }
    assert_memory_equal(z, zb, sizeof z);
    assert_int_equal(rfe_meas_eval(&h, &paper.vehicle, &paper.tyre, mu, z), RFE_OK);
}

/* REQ-MEAS-002 */
static void test_mcdc_meas_eval_overflowing_sum_absolute(void **state)
{
    const rfe_sample_t u = braking_turn();
    const rfe_real_t mu[RFE_WHEELS] = {(rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5};
    rfe_params_t p = paper;
    rfe_vehicle_t tiny_j;
    rfe_meas_t h;
    rfe_real_t z[RFE_MEAS], zb[RFE_MEAS];
    (void)state;
    p.tyre.mode = RFE_TYRE_ABSOLUTE;
    assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
    /* the yaw moment (~1e3 N m) over J = the smallest normal number overflows */
    tiny_j = p.vehicle;
    tiny_j.J = (rfe_real_t)REAL_TINY;
    memset(z, 0x5a, sizeof z);
    memcpy(zb, z, sizeof z);
    assert_int_equal(rfe_meas_eval(&h, &tiny_j, &p.tyre, mu, z), RFE_ERR_NONFINITE);
    assert_memory_equal(z, zb, sizeof z);
    assert_int_equal(rfe_meas_eval(&h, &p.vehicle, &p.tyre, mu, z), RFE_OK);
    assert_true(isfinite((double)z[0]) && isfinite((double)z[1]) && isfinite((double)z[2]));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mcdc_meas_eval_nonfinite_mu_paper),
        cmocka_unit_test(test_mcdc_meas_eval_overflowing_sum_absolute),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
