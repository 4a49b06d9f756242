/**
 * @file test_vehicle_mass_flt.c
 * @brief The vehicle mass set at run time (rfe_params_set_mass, rfe_friction_set_mass,
 *        rfe_pipeline_set_mass):
 *        statuses and the untouched state on error, and that a mass set after init acts
 *        exactly as the same mass given to init (the estimator keeps nothing derived from it).
 */
#include "test_common.h"

#include <string.h>

#include "rfe/friction.h"
#include "rfe/pipeline.h"

/* A braking sample at 20 m/s with 4 % slip: the tyre loads and h both use the mass. */
static rfe_sample_t braking(size_t k)
{
    rfe_sample_t u;
    size_t w;
    memset(&u, 0, sizeof u);
    u.vx = (rfe_real_t)20.0;
    u.ax = (rfe_real_t)(-4.0 - (0.01 * (double)(k % 7u)));
    for (w = 0u; w < 4u; ++w) {
        u.omega[w] = (rfe_real_t)(20.0 * 0.96 / 0.325);
    }
    return u;
}

static void init_default(rfe_friction_t *est, rfe_params_t *p, rfe_real_t m)
{
    memset(p, 0, sizeof *p); /* the estimator copies it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(p), RFE_OK);
    p->vehicle.m = m;
    memset(est, 0, sizeof *est);
    assert_int_equal(rfe_friction_init(est, p), RFE_OK);
}

/* REQ-EST-017 */
static void test_params_set_mass(void **state)
{
    rfe_params_t p;
    rfe_params_t before;
    (void)state;
    memset(&p, 0, sizeof p);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    assert_int_equal(rfe_params_set_mass(NULL, (rfe_real_t)1500.0), RFE_ERR_NULL);
    memcpy(&before, &p, sizeof before);
    assert_int_equal(rfe_params_set_mass(&p, (rfe_real_t)0.0), RFE_ERR_PARAM);
    assert_int_equal(rfe_params_set_mass(&p, (rfe_real_t)-1500.0), RFE_ERR_PARAM);
    assert_int_equal(rfe_params_set_mass(&p, (rfe_real_t)NAN), RFE_ERR_PARAM);
    assert_int_equal(rfe_params_set_mass(&p, (rfe_real_t)INFINITY), RFE_ERR_PARAM);
    assert_memory_equal(&p, &before, sizeof p);
    /* a set that is invalid elsewhere is refused whatever the mass, untouched */
    p.vehicle.J = (rfe_real_t)-1.0;
    memcpy(&before, &p, sizeof before);
    assert_int_equal(rfe_params_set_mass(&p, (rfe_real_t)1500.0), RFE_ERR_PARAM);
    assert_memory_equal(&p, &before, sizeof p);
    p.vehicle.J = (rfe_real_t)3000.0;
    assert_int_equal(rfe_params_set_mass(&p, (rfe_real_t)1500.0), RFE_OK);
    assert_true(p.vehicle.m == (rfe_real_t)1500.0);
}

/* REQ-EST-017 */
static void test_friction_set_mass_statuses(void **state)
{
    rfe_params_t p;
    rfe_friction_t est;
    rfe_friction_t before;
    (void)state;
    assert_int_equal(rfe_friction_set_mass(NULL, (rfe_real_t)1500.0), RFE_ERR_NULL);
    memset(&est, 0, sizeof est);
    assert_int_equal(rfe_friction_set_mass(&est, (rfe_real_t)1500.0), RFE_ERR_NOT_INITIALISED);
    init_default(&est, &p, (rfe_real_t)1830.0);
    memcpy(&before, &est, sizeof before); /* bytes, padding included */
    assert_int_equal(rfe_friction_set_mass(&est, (rfe_real_t)NAN), RFE_ERR_NONFINITE);
    assert_int_equal(rfe_friction_set_mass(&est, (rfe_real_t)-INFINITY), RFE_ERR_NONFINITE);
    assert_int_equal(rfe_friction_set_mass(&est, (rfe_real_t)0.0), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_mass(&est, (rfe_real_t)-1.0), RFE_ERR_RANGE);
    assert_memory_equal(&est, &before, sizeof est);
    assert_int_equal(rfe_friction_set_mass(&est, (rfe_real_t)1500.0), RFE_OK);
    assert_true(est.params.vehicle.m == (rfe_real_t)1500.0);
}

/* A mass set at run time acts as the same mass given to init, bit for bit, from the start
 * and after steps taken with another mass; the mass is a parameter, so the steps before the
 * change are the old mass's. Setting the mass the estimator already has changes nothing. */
/* REQ-EST-017 */
static void test_friction_set_mass_acts_as_init(void **state)
{
    rfe_params_t p;
    rfe_friction_t a; /* init 1830 kg, set to 1500 kg after K steps */
    rfe_friction_t b; /* init 1500 kg, its state before the change from run c */
    rfe_friction_t c; /* init 1830 kg, never set */
    rfe_estimate_t ea;
    rfe_estimate_t eb;
    rfe_estimate_t ec;
    size_t k;
    const size_t K = 150u;
    int differs = 0;
    (void)state;
    memset(&ea, 0, sizeof ea); /* compared as bytes below */
    memset(&eb, 0, sizeof eb);
    memset(&ec, 0, sizeof ec);
    init_default(&a, &p, (rfe_real_t)1830.0);
    init_default(&c, &p, (rfe_real_t)1830.0);
    for (k = 0u; k < K; ++k) {
        const rfe_sample_t u = braking(k);
        assert_false(rfe_status_is_error(rfe_friction_step(&a, &u, &ea)));
        assert_false(rfe_status_is_error(rfe_friction_step(&c, &u, &ec)));
    }
    assert_int_equal(rfe_friction_set_mass(&c, (rfe_real_t)1830.0), RFE_OK);
    assert_memory_equal(&a, &c, sizeof a); /* the same mass again: nothing changed */
    /* b: the state a has now, with the parameters of an init at 1500 kg */
    init_default(&b, &p, (rfe_real_t)1500.0);
    {
        const rfe_params_t pb = b.params;
        memcpy(&b, &a, sizeof b);
        b.params = pb;
    }
    assert_int_equal(rfe_friction_set_mass(&a, (rfe_real_t)1500.0), RFE_OK);
    assert_memory_equal(&a, &b, sizeof a);
    for (k = K; k < (2u * K); ++k) {
        const rfe_sample_t u = braking(k);
        assert_false(rfe_status_is_error(rfe_friction_step(&a, &u, &ea)));
        assert_false(rfe_status_is_error(rfe_friction_step(&b, &u, &eb)));
        assert_false(rfe_status_is_error(rfe_friction_step(&c, &u, &ec)));
        assert_memory_equal(&ea, &eb, sizeof ea);
        differs |= (memcmp(&ea.mu, &ec.mu, sizeof ea.mu) != 0) ? 1 : 0;
    }
    assert_true(differs); /* and the mass reaches the model: 1500 kg is not 1830 kg */
}

/* An ESC sample: braking at about 20 m/s, the wheels 4 % slower, a little steering. */
static rfe_velocity_input_t esc(const rfe_params_t *p, size_t k)
{
    rfe_velocity_input_t in;
    size_t w;
    memset(&in, 0, sizeof in);
    in.dt = (rfe_real_t)0.01;
    in.delta = (rfe_real_t)0.01;
    in.ax = (rfe_real_t)(-4.0 - (0.01 * (double)(k % 7u)));
    in.yaw_rate = (rfe_real_t)0.05;
    for (w = 0u; w < 4u; ++w) {
        in.omega[w] = (rfe_real_t)((20.0 - (0.04 * (double)k)) * 0.96) / p->vehicle.R;
    }
    return in;
}

static void pipeline_at(rfe_pipeline_t *pl, rfe_real_t m)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    memset(&p, 0, sizeof p);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    p.vehicle.m = m;
    memset(&vp, 0, sizeof vp);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    memset(pl, 0, sizeof *pl); /* padding defined: compared as bytes */
    assert_int_equal(rfe_pipeline_init(pl, &p, &vp), RFE_OK);
}

/* Both estimators take the mass: the pipeline set to 1500 kg after K steps equals, from then
 * on, the same state with the parameters of an init at 1500 kg. */
/* REQ-EST-017 */
static void test_pipeline_set_mass(void **state)
{
    static rfe_pipeline_t a;
    static rfe_pipeline_t b;
    static rfe_pipeline_t before;
    rfe_pipeline_out_t oa;
    rfe_pipeline_out_t ob;
    rfe_params_t p;
    size_t k;
    const size_t K = 100u;
    (void)state;
    memset(&p, 0, sizeof p);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&oa, 0, sizeof oa);
    memset(&ob, 0, sizeof ob);
    assert_int_equal(rfe_pipeline_set_mass(NULL, (rfe_real_t)1500.0), RFE_ERR_NULL);
    memset(&a, 0, sizeof a);
    assert_int_equal(rfe_pipeline_set_mass(&a, (rfe_real_t)1500.0), RFE_ERR_NOT_INITIALISED);
    pipeline_at(&a, (rfe_real_t)1830.0);
    for (k = 0u; k < K; ++k) {
        const rfe_velocity_input_t in = esc(&p, k);
        assert_false(rfe_status_is_error(rfe_pipeline_step(&a, &in, &oa)));
    }
    memcpy(&before, &a, sizeof before);
    assert_int_equal(rfe_pipeline_set_mass(&a, (rfe_real_t)NAN), RFE_ERR_NONFINITE);
    assert_int_equal(rfe_pipeline_set_mass(&a, (rfe_real_t)-1.0), RFE_ERR_RANGE);
    assert_memory_equal(&a, &before, sizeof a);
    pipeline_at(&b, (rfe_real_t)1500.0);
    {
        /* the vehicle of an init at 1500 kg; the rest (the input noise the steps set) a's */
        const rfe_vehicle_t fb = b.friction.params.vehicle;
        const rfe_vehicle_t vb = b.velocity.veh;
        memcpy(&b, &a, sizeof b);
        b.friction.params.vehicle = fb;
        b.velocity.veh = vb;
    }
    assert_int_equal(rfe_pipeline_set_mass(&a, (rfe_real_t)1500.0), RFE_OK);
    assert_memory_equal(&a, &b, sizeof a);
    for (k = K; k < (2u * K); ++k) {
        const rfe_velocity_input_t in = esc(&p, k);
        assert_false(rfe_status_is_error(rfe_pipeline_step(&a, &in, &oa)));
        assert_false(rfe_status_is_error(rfe_pipeline_step(&b, &in, &ob)));
        assert_memory_equal(&oa, &ob, sizeof oa);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_set_mass),
        cmocka_unit_test(test_friction_set_mass_statuses),
        cmocka_unit_test(test_friction_set_mass_acts_as_init),
        cmocka_unit_test(test_pipeline_set_mass),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
