/**
 * @file test_lateral_tyre_flt.c
 * @brief The lateral tyre curve set at run time (rfe_params_set_lateral_tyre,
 *        rfe_friction_set_lateral_tyre): statuses and the untouched state on error, and that a
 *        curve set after init acts exactly as the same curve given to init (the estimator
 *        keeps nothing derived from it).
 */
#include "test_common.h"

#include <string.h>

#include "rfe/friction.h"

/* A steady corner at 20 m/s on the default car: ay 3 m/s^2, r = ay / vx, the body sliding
 * outwards (vy -0.3 m/s), a little steer; the lateral rows carry the curve's information. */
static rfe_sample_t cornering(size_t k)
{
    rfe_sample_t u;
    size_t w;
    memset(&u, 0, sizeof u);
    u.vx = (rfe_real_t)20.0;
    u.vy = (rfe_real_t)-0.3;
    u.delta = (rfe_real_t)(0.035 + (0.0005 * (double)(k % 5u)));
    u.yaw_rate = (rfe_real_t)0.15;
    u.ay = (rfe_real_t)3.0;
    for (w = 0u; w < 4u; ++w) {
        u.omega[w] = (rfe_real_t)(20.0 / 0.325);
    }
    return u;
}

static void init_with(rfe_friction_t *est, rfe_params_t *p, rfe_real_t cy, rfe_real_t C,
                      rfe_real_t E, rfe_real_t r_model_rel)
{
    memset(p, 0, sizeof *p); /* the estimator copies it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(p), RFE_OK);
    p->tyre.cy = cy;
    p->tyre.shape_Cy = C;
    p->tyre.shape_Ey = E;
    p->filter.r_model_rel = r_model_rel;
    memset(est, 0, sizeof *est);
    assert_int_equal(rfe_friction_init(est, p), RFE_OK);
}

/* REQ-EST-019 */
static void test_params_set_lateral_tyre(void **state)
{
    /* each row one value the validation refuses (DATA.md: cy > 0, 1 < C < 2, -4 <= E < 1,
     * r_model_rel >= 0), the others valid */
    static const double bad[][4] = {
        {0.0, 1.5, 0.3, 0.08},  {-12.0, 1.5, 0.3, 0.08}, {12.0, 1.0, 0.3, 0.08},
        {12.0, 2.0, 0.3, 0.08}, {12.0, 1.5, 1.0, 0.08},  {12.0, 1.5, -4.5, 0.08},
        {12.0, 1.5, 0.3, -0.01},
    };
    rfe_params_t p;
    rfe_params_t before;
    size_t i;
    (void)state;
    memset(&p, 0, sizeof p);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    assert_int_equal(rfe_params_set_lateral_tyre(NULL, (rfe_real_t)12.0, (rfe_real_t)1.5,
                                                 (rfe_real_t)0.3, (rfe_real_t)0.08),
                     RFE_ERR_NULL);
    memcpy(&before, &p, sizeof before);
    for (i = 0u; i < sizeof bad / sizeof bad[0]; ++i) {
        assert_int_equal(rfe_params_set_lateral_tyre(&p, (rfe_real_t)bad[i][0], (rfe_real_t)bad[i][1],
                                                     (rfe_real_t)bad[i][2], (rfe_real_t)bad[i][3]),
                         RFE_ERR_PARAM);
        assert_memory_equal(&p, &before, sizeof p);
    }
    assert_int_equal(rfe_params_set_lateral_tyre(&p, (rfe_real_t)NAN, (rfe_real_t)1.5,
                                                 (rfe_real_t)0.3, (rfe_real_t)0.08),
                     RFE_ERR_PARAM);
    assert_memory_equal(&p, &before, sizeof p);
    /* a set that is invalid elsewhere is refused whatever the curve, untouched */
    p.vehicle.J = (rfe_real_t)-1.0;
    memcpy(&before, &p, sizeof before);
    assert_int_equal(rfe_params_set_lateral_tyre(&p, (rfe_real_t)12.0, (rfe_real_t)1.5,
                                                 (rfe_real_t)0.3, (rfe_real_t)0.08),
                     RFE_ERR_PARAM);
    assert_memory_equal(&p, &before, sizeof p);
    p.vehicle.J = (rfe_real_t)3000.0;
    assert_int_equal(rfe_params_set_lateral_tyre(&p, (rfe_real_t)12.0, (rfe_real_t)1.5,
                                                 (rfe_real_t)0.3, (rfe_real_t)0.08),
                     RFE_OK);
    assert_true((p.tyre.cy == (rfe_real_t)12.0) && (p.tyre.shape_Cy == (rfe_real_t)1.5) &&
                (p.tyre.shape_Ey == (rfe_real_t)0.3) && (p.filter.r_model_rel == (rfe_real_t)0.08));
}

/* REQ-EST-019 */
static void test_friction_set_lateral_tyre_statuses(void **state)
{
    rfe_params_t p;
    rfe_friction_t est;
    rfe_friction_t before;
    const rfe_real_t ok[4] = {(rfe_real_t)12.0, (rfe_real_t)1.5, (rfe_real_t)0.3, (rfe_real_t)0.08};
    size_t i;
    (void)state;
    assert_int_equal(rfe_friction_set_lateral_tyre(NULL, ok[0], ok[1], ok[2], ok[3]), RFE_ERR_NULL);
    memset(&est, 0, sizeof est);
    assert_int_equal(rfe_friction_set_lateral_tyre(&est, ok[0], ok[1], ok[2], ok[3]),
                     RFE_ERR_NOT_INITIALISED);
    init_with(&est, &p, (rfe_real_t)15.0, (rfe_real_t)1.3, (rfe_real_t)0.0, (rfe_real_t)0.05);
    memcpy(&before, &est, sizeof before); /* bytes, padding included */
    for (i = 0u; i < 4u; ++i) {
        /* each argument not finite, the others valid */
        rfe_real_t v[4] = {ok[0], ok[1], ok[2], ok[3]};
        v[i] = (rfe_real_t)NAN;
        assert_int_equal(rfe_friction_set_lateral_tyre(&est, v[0], v[1], v[2], v[3]), RFE_ERR_NONFINITE);
        v[i] = (rfe_real_t)INFINITY;
        assert_int_equal(rfe_friction_set_lateral_tyre(&est, v[0], v[1], v[2], v[3]), RFE_ERR_NONFINITE);
    }
    assert_int_equal(rfe_friction_set_lateral_tyre(&est, (rfe_real_t)-1.0, ok[1], ok[2], ok[3]),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_lateral_tyre(&est, ok[0], (rfe_real_t)2.5, ok[2], ok[3]),
                     RFE_ERR_RANGE);
    assert_memory_equal(&est, &before, sizeof est);
    assert_int_equal(rfe_friction_set_lateral_tyre(&est, ok[0], ok[1], ok[2], ok[3]), RFE_OK);
    assert_true((est.params.tyre.cy == ok[0]) && (est.params.tyre.shape_Cy == ok[1]) &&
                (est.params.tyre.shape_Ey == ok[2]) && (est.params.filter.r_model_rel == ok[3]));
}

/* A curve set at run time acts as the same curve given to init, bit for bit, after steps taken
 * with another; the steps before the change are the old curve's. Setting the curve the
 * estimator already has changes nothing; the new curve reaches the estimate. */
/* REQ-EST-019 */
static void test_friction_set_lateral_tyre_acts_as_init(void **state)
{
    rfe_params_t p;
    rfe_friction_t a; /* init with the default curve, set to the new one after K steps */
    rfe_friction_t b; /* init with the new curve, its state before the change from run a */
    rfe_friction_t c; /* init with the default curve, never set */
    rfe_estimate_t ea;
    rfe_estimate_t eb;
    rfe_estimate_t ec;
    size_t k;
    const size_t K = 150u;
    int differs = 0;
    rfe_real_t cy0;
    rfe_real_t C0;
    rfe_real_t E0;
    rfe_real_t r0;
    (void)state;
    memset(&ea, 0, sizeof ea); /* compared as bytes below */
    memset(&eb, 0, sizeof eb);
    memset(&ec, 0, sizeof ec);
    memset(&p, 0, sizeof p);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    cy0 = p.tyre.cy;
    C0 = p.tyre.shape_Cy;
    E0 = p.tyre.shape_Ey;
    r0 = p.filter.r_model_rel;
    init_with(&a, &p, cy0, C0, E0, r0);
    init_with(&c, &p, cy0, C0, E0, r0);
    for (k = 0u; k < K; ++k) {
        const rfe_sample_t u = cornering(k);
        assert_false(rfe_status_is_error(rfe_friction_step(&a, &u, &ea)));
        assert_false(rfe_status_is_error(rfe_friction_step(&c, &u, &ec)));
    }
    assert_int_equal(rfe_friction_set_lateral_tyre(&c, cy0, C0, E0, r0), RFE_OK);
    assert_memory_equal(&a, &c, sizeof a); /* the same curve again: nothing changed */
    init_with(&b, &p, (rfe_real_t)11.0, (rfe_real_t)1.6, (rfe_real_t)0.4, (rfe_real_t)0.09);
    {
        const rfe_params_t pb = b.params;
        memcpy(&b, &a, sizeof b);
        b.params = pb;
    }
    assert_int_equal(rfe_friction_set_lateral_tyre(&a, (rfe_real_t)11.0, (rfe_real_t)1.6,
                                                   (rfe_real_t)0.4, (rfe_real_t)0.09),
                     RFE_OK);
    assert_memory_equal(&a, &b, sizeof a);
    for (k = K; k < (2u * K); ++k) {
        const rfe_sample_t u = cornering(k);
        assert_false(rfe_status_is_error(rfe_friction_step(&a, &u, &ea)));
        assert_false(rfe_status_is_error(rfe_friction_step(&b, &u, &eb)));
        assert_false(rfe_status_is_error(rfe_friction_step(&c, &u, &ec)));
        assert_memory_equal(&ea, &eb, sizeof ea);
        differs |= (memcmp(&ea.sd, &ec.sd, sizeof ea.sd) != 0) ? 1 : 0;
    }
    assert_true(differs); /* and the curve reaches the model */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_set_lateral_tyre),
        cmocka_unit_test(test_friction_set_lateral_tyre_statuses),
        cmocka_unit_test(test_friction_set_lateral_tyre_acts_as_init),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
