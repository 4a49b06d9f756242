/**
 * @file test_lateral_tyre_q31.c
 * @brief The fixed-point lateral tyre curve set at run time (rfe_params_set_lateral_tyre_q31,
 *        rfe_friction_set_lateral_tyre_q31): statuses and the untouched state on error, and
 *        that the estimator keeps nothing derived from the curve (a set after init acts as the
 *        same set given to init, bit for bit).
 */
#include "test_common.h"

#include <string.h>

#include "host/fixed_conv.h"
#include "rfe/friction_q31.h"

static rfe_params_q31_t preset(void)
{
    rfe_params_q31_t p;
    memset(&p, 0, sizeof p); /* the estimator copies it, padding included: keep it defined */
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    return p;
}

static rfe_fix_t q(double x, unsigned int fmt)
{
    uint32_t sat = 0u;
    const rfe_fix_t v = rfe_fix_from_double(x, fmt, &sat);
    assert_int_equal(sat, 0u);
    return v;
}

/* The curve of the acts-as-init test: cy 11 /rad, C 1.6, E 0.4, r_model_rel 0.09. */
#define NEW_CY q(11.0, RFE_FIX_Q_STIFF)
#define NEW_C q(1.6, RFE_FIX_Q_STIFF)
#define NEW_E q(0.4, RFE_FIX_Q_STIFF)
#define NEW_R q(0.09, RFE_FIX_Q_SD)

/* REQ-EST-019 */
static void test_params_set_lateral_tyre_q31_refused(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_params_q31_t before;
    (void)state;
    assert_int_equal(rfe_params_set_lateral_tyre_q31(NULL, NEW_CY, NEW_C, NEW_E, NEW_R), RFE_ERR_NULL);
    memcpy(&before, &p, sizeof before);
    /* each one value the validation refuses: cy <= 0, C outside (1, 2), E >= 1, r < 0 */
    assert_int_equal(rfe_params_set_lateral_tyre_q31(&p, 0, NEW_C, NEW_E, NEW_R), RFE_ERR_PARAM);
    assert_int_equal(rfe_params_set_lateral_tyre_q31(&p, NEW_CY, q(1.0, RFE_FIX_Q_STIFF), NEW_E, NEW_R),
                     RFE_ERR_PARAM);
    assert_int_equal(rfe_params_set_lateral_tyre_q31(&p, NEW_CY, q(2.0, RFE_FIX_Q_STIFF), NEW_E, NEW_R),
                     RFE_ERR_PARAM);
    assert_int_equal(rfe_params_set_lateral_tyre_q31(&p, NEW_CY, NEW_C, q(1.0, RFE_FIX_Q_STIFF), NEW_R),
                     RFE_ERR_PARAM);
    assert_int_equal(rfe_params_set_lateral_tyre_q31(&p, NEW_CY, NEW_C, NEW_E, -1), RFE_ERR_PARAM);
    assert_memory_equal(&p, &before, sizeof p);
    /* a set that is invalid elsewhere is refused whatever the curve, untouched */
    p.vehicle.J = -1;
    memcpy(&before, &p, sizeof before);
    assert_int_equal(rfe_params_set_lateral_tyre_q31(&p, NEW_CY, NEW_C, NEW_E, NEW_R), RFE_ERR_PARAM);
    assert_memory_equal(&p, &before, sizeof p);
}

/* A steady corner at 20 m/s (Q formats), as test_lateral_tyre_flt.c's. */
static rfe_sample_q31_t cornering(size_t k)
{
    rfe_sample_q31_t u;
    size_t w;
    memset(&u, 0, sizeof u);
    u.vx = q(20.0, RFE_FIX_Q_SPEED);
    u.vy = q(-0.3, RFE_FIX_Q_SPEED);
    u.delta = q(0.035 + (0.0005 * (double)(k % 5u)), RFE_FIX_Q_ANGLE);
    u.yaw_rate = q(0.15, RFE_FIX_Q_YAWRATE);
    u.ay = q(3.0, RFE_FIX_Q_ACC);
    for (w = 0u; w < 4u; ++w) {
        u.omega[w] = q(20.0 / 0.325, RFE_FIX_Q_OMEGA);
    }
    return u;
}

/* REQ-EST-019 */
static void test_friction_set_lateral_tyre_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_params_q31_t p2;
    rfe_friction_q31_t a; /* set to the new curve after K steps */
    rfe_friction_q31_t b; /* a's state, with the parameters of an init with the new curve */
    rfe_friction_q31_t c; /* never set */
    rfe_friction_q31_t before;
    rfe_estimate_q31_t ea;
    rfe_estimate_q31_t eb;
    rfe_estimate_q31_t ec;
    size_t k;
    const size_t K = 150u;
    int differs = 0;
    (void)state;
    memset(&ea, 0, sizeof ea); /* compared as bytes below */
    memset(&eb, 0, sizeof eb);
    memset(&ec, 0, sizeof ec);
    memset(&a, 0, sizeof a);
    assert_int_equal(rfe_friction_set_lateral_tyre_q31(NULL, NEW_CY, NEW_C, NEW_E, NEW_R), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_set_lateral_tyre_q31(&a, NEW_CY, NEW_C, NEW_E, NEW_R),
                     RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_friction_init_q31(&a, &p), RFE_OK);
    memset(&c, 0, sizeof c);
    assert_int_equal(rfe_friction_init_q31(&c, &p), RFE_OK);
    for (k = 0u; k < K; ++k) {
        const rfe_sample_q31_t u = cornering(k);
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&a, &u, &ea)));
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&c, &u, &ec)));
    }
    memcpy(&before, &a, sizeof before); /* bytes, padding included */
    assert_int_equal(rfe_friction_set_lateral_tyre_q31(&a, -NEW_CY, NEW_C, NEW_E, NEW_R), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_lateral_tyre_q31(&a, NEW_CY, NEW_C, NEW_E, -NEW_R), RFE_ERR_RANGE);
    assert_memory_equal(&a, &before, sizeof a);
    /* b: a's state with the parameters of an init with the new curve */
    p2 = p;
    p2.tyre.cy = NEW_CY;
    p2.tyre.shape_Cy = NEW_C;
    p2.tyre.shape_Ey = NEW_E;
    p2.filter.r_model_rel = NEW_R;
    assert_int_equal(rfe_params_validate_q31(&p2), RFE_OK);
    memcpy(&b, &a, sizeof b);
    b.params = p2;
    assert_int_equal(rfe_friction_set_lateral_tyre_q31(&a, NEW_CY, NEW_C, NEW_E, NEW_R), RFE_OK);
    assert_memory_equal(&a, &b, sizeof a);
    for (k = K; k < (2u * K); ++k) {
        const rfe_sample_q31_t u = cornering(k);
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&a, &u, &ea)));
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&b, &u, &eb)));
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&c, &u, &ec)));
        assert_memory_equal(&ea, &eb, sizeof ea);
        differs |= (memcmp(&ea.sd, &ec.sd, sizeof ea.sd) != 0) ? 1 : 0;
    }
    assert_true(differs); /* the curve reaches the model */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_set_lateral_tyre_q31_refused),
        cmocka_unit_test(test_friction_set_lateral_tyre_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
