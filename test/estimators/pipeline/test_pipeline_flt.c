/**
 * @file test_pipeline_flt.c
 * @brief The composed entry (rfe/pipeline.h) and the friction estimator's per-step input
 *        noise: statuses, the untouched state on error, and that each step hands the
 *        observer's estimate and sd to the friction estimator.
 */
#include "test_common.h"

#include <string.h>

#include "rfe/pipeline.h"

static rfe_velocity_input_t rolling(const rfe_params_t *p, rfe_real_t v, rfe_real_t dt)
{
    rfe_velocity_input_t in;
    size_t i;
    memset(&in, 0, sizeof(in));
    in.dt = dt;
    for (i = 0u; i < 4u; ++i) {
        in.omega[i] = v / p->vehicle.R;
    }
    return in;
}

static void test_set_input_noise(void **state)
{
    rfe_params_t p;
    rfe_friction_t est;
    rfe_friction_t before;
    (void)state;
    memset(&p, 0, sizeof p); /* the estimators copy it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&est, 0, sizeof(est));
    assert_int_equal(rfe_friction_set_input_noise(NULL, 0.1f, 0.1f, 0.1f), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_set_input_noise(&est, 0.1f, 0.1f, 0.1f),
                     RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    memcpy(&before, &est, sizeof before); /* bytes, padding included (not a member copy) */
    assert_int_equal(rfe_friction_set_input_noise(&est, -0.1f, 0.1f, 0.1f), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise(&est, 0.1f, (rfe_real_t)NAN, 0.1f),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise(&est, 0.1f, 0.1f, 0.0f), RFE_ERR_RANGE);
    assert_memory_equal(&est, &before, sizeof(est));
    assert_int_equal(rfe_friction_set_input_noise(&est, 0.2f, 0.3f, 0.4f), RFE_OK);
    assert_close(est.params.filter.sd_in_vx, 0.2, 1e-7, 0.0, "sd_in_vx");
    assert_close(est.params.filter.sd_in_vy, 0.3, 1e-7, 0.0, "sd_in_vy");
    assert_close(est.params.filter.r_yaw_acc, 0.4, 1e-7, 0.0, "r_yaw_acc");
}

/* REQ-OBS-007 */
static void test_pipeline_steps_both_estimators(void **state)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_t pl;
    rfe_pipeline_out_t o;
    rfe_velocity_input_t in;
    size_t k;
    (void)state;
    memset(&p, 0, sizeof p); /* the estimators copy it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&vp, 0, sizeof vp);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    assert_int_equal(rfe_pipeline_init(NULL, &p, &vp), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_init(&pl, NULL, &vp), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_init(&pl, &p, NULL), RFE_ERR_NULL);
    vp.driven = 0u;
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_ERR_PARAM);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
    for (k = 0u; k < 100u; ++k) {
        in = rolling(&p, 20.0f, (k == 0u) ? 0.0f : 0.01f);
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    }
    /* the friction estimator ran on the observer's vx (straight rolling: no excitation, so
     * its estimate is held), with the observer's sd as its input noise */
    assert_close(o.velocity.vx, 20.0, 1e-3, 0.0, "vx");
    assert_close(pl.friction.params.filter.sd_in_vx, o.velocity.sd_vx, 0.0, 0.0, "sd_in_vx");
    assert_close(pl.friction.params.filter.sd_in_vy, o.velocity.sd_vy, 0.0, 0.0, "sd_in_vy");
    assert_close(pl.friction.params.filter.r_yaw_acc,
                 sqrt((double)p.filter.r_yaw_acc * p.filter.r_yaw_acc +
                      (double)o.velocity.sd_yaw_acc * o.velocity.sd_yaw_acc),
                 1e-6, 1e-6, "r_yaw_acc");
    assert_memory_equal(&pl.last, &o.friction, sizeof(o.friction));
}

/* REQ-OBS-007 */
static void test_an_error_leaves_the_pipeline_untouched(void **state)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_t pl;
    rfe_pipeline_t before;
    rfe_pipeline_out_t o;
    rfe_velocity_input_t in;
    (void)state;
    memset(&p, 0, sizeof p); /* the estimators copy it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&vp, 0, sizeof vp);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    memset(&pl, 0, sizeof pl); /* padding and scratch defined, so whole-struct compares are */
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
    in = rolling(&p, 20.0f, 0.0f);
    assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    memcpy(&before, &pl, sizeof before); /* bytes, padding included (not a member copy) */
    assert_int_equal(rfe_pipeline_step(NULL, &in, &o), RFE_ERR_NULL);
    in = rolling(&p, 20.0f, 0.01f);
    in.ax = (rfe_real_t)NAN; /* the observer rejects it */
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_NONFINITE);
    assert_memory_equal(&pl, &before, sizeof(pl));
    /* the observer accepts a sample that the friction estimator rejects: a wheel speed
     * beyond the friction estimator's limit is within the observer's too, so use an
     * uninitialised friction estimator instead */
    pl.friction.magic = 0u;
    memcpy(&before, &pl, sizeof before); /* bytes, padding included (not a member copy) */
    in = rolling(&p, 20.0f, 0.01f);
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_NOT_INITIALISED);
    assert_memory_equal(&pl, &before, sizeof(pl));
}

/* REQ-ABI-001 */
static void test_inits_refuse_other_layout_or_word(void **state)
{
    /* Each init called as its wrapper would be from a caller compiled otherwise: another
     * size of the state, or another configuration word (maxima, number type). */
    static rfe_pipeline_t pl, pl0;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    const uint32_t other = RFE_CONFIG_REAL ^ 3u; /* float <-> double, or the q31 word */
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    memset(&pl, 0x5A, sizeof pl);
    pl0 = pl;
    assert_int_equal((rfe_friction_init)(&pl.friction, &p, sizeof pl.friction - 8u, RFE_CONFIG_REAL), RFE_ERR_ABI);
    assert_int_equal((rfe_friction_init)(&pl.friction, &p, sizeof pl.friction, other), RFE_ERR_ABI);
    assert_int_equal((rfe_velocity_init)(&pl.velocity, &vp, &p, sizeof pl.velocity + 8u, RFE_CONFIG_REAL), RFE_ERR_ABI);
    assert_int_equal((rfe_velocity_init)(&pl.velocity, &vp, &p, sizeof pl.velocity, other), RFE_ERR_ABI);
    assert_int_equal((rfe_pipeline_init)(&pl, &p, &vp, sizeof pl - 8u, RFE_CONFIG_REAL), RFE_ERR_ABI);
    assert_int_equal((rfe_pipeline_init)(&pl, &p, &vp, sizeof pl, other), RFE_ERR_ABI);
    assert_memory_equal(&pl, &pl0, sizeof pl);
    /* and through the wrappers, this file's own layout: accepted */
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inits_refuse_other_layout_or_word),
        cmocka_unit_test(test_set_input_noise),
        cmocka_unit_test(test_pipeline_steps_both_estimators),
        cmocka_unit_test(test_an_error_leaves_the_pipeline_untouched),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
