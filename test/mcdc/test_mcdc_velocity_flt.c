/**
 * @file test_mcdc_velocity_flt.c
 * @brief MC/DC of the velocity observer's and the pipeline's checks and decisions: one bad
 *        input, one bad parameter, one NULL argument at a time (test_mcdc_args_flt.c does the
 *        same for the friction estimator).
 *
 * The checks are decisions of several conditions (`!finite(a) || !finite(b) || ...`,
 * `|x| > limit || |y| > limit || ...`); the module tests reject a bad value, often the first
 * one only, which leaves the other conditions without an independence pair (make mcdc,
 * build/mcdc/gaps.md). Here each value is made bad on its own, everything else valid, so that
 * condition alone flips the decision: the call returns the documented error and leaves the
 * state bit for bit untouched; the all-valid call, the other half of each pair, succeeds.
 * Then the driving-state decision with a drive-torque input (braked, no torque, torque) and
 * the input-noise setter's finiteness checks with +-infinity (which, unlike NaN, fails
 * only the finiteness condition of each pair) and its sign checks with finite negatives, and
 * the conversion of the observer's parameters to Q formats with each NULL argument.
 *
 * No tolerances: statuses and flags are exact, "untouched" is compared with memcmp.
 */
#include "test_common.h"

#include <string.h>

#include "rfe/component/params_conv.h"
#include "rfe/config.h"
#include "rfe/friction.h"
#include "rfe/pipeline.h"
#include "rfe/velocity.h"
#include "rfe/velocity_params_q31.h"

static rfe_params_t veh;
static rfe_velocity_params_t vpar;

static int setup(void **state)
{
    (void)state;
    if ((rfe_params_default(&veh) != RFE_OK) || (rfe_velocity_params_default(&vpar) != RFE_OK)) {
        return -1;
    }
    return 0;
}

/* Straight running at 20 m/s, every wheel rolling, every optional input given and quiet. */
static rfe_velocity_input_t good_input(void)
{
    rfe_velocity_input_t in;
    size_t i;
    memset(&in, 0, sizeof in);
    in.dt = (rfe_real_t)0.01;
    in.delta = (rfe_real_t)0.01;
    for (i = 0u; i < 4u; ++i) {
        in.omega[i] = (rfe_real_t)20.0 / veh.vehicle.R;
    }
    in.has = RFE_VEL_HAS_PRESSURE | RFE_VEL_HAS_TORQUE;
    return in;
}

static rfe_velocity_mu_t good_mu(void)
{
    rfe_velocity_mu_t m;
    size_t i;
    for (i = 0u; i < 4u; ++i) {
        m.mu[i] = (rfe_real_t)0.9;
        m.sd[i] = (rfe_real_t)0.05;
    }
    return m;
}

/* An observer past its first sample (so the period check is on). */
static void started(rfe_velocity_t *obs)
{
    rfe_velocity_estimate_t e;
    const rfe_velocity_input_t in = good_input();
    memset(obs, 0, sizeof *obs);
    assert_int_equal(rfe_velocity_init(obs, &vpar, &veh), RFE_OK);
    assert_int_equal(rfe_velocity_step(obs, &in, NULL, &e), RFE_OK);
}

/* One step with @p in and @p mu must return @p want; on an error the observer is untouched. */
static void expect_step(const rfe_velocity_input_t *in, const rfe_velocity_mu_t *mu,
                        rfe_status_t want)
{
    rfe_velocity_t obs;
    rfe_velocity_t before;
    rfe_velocity_estimate_t e;
    started(&obs);
    before = obs;
    assert_int_equal(rfe_velocity_step(&obs, in, mu, &e), want);
    if (want != RFE_OK) {
        assert_memory_equal(&obs, &before, sizeof obs);
        assert_int_equal(e.status, want);
    }
}

/* REQ: every positive parameter alone at +infinity or NaN, and dt_min, dt_max alone at
 * +infinity, are rejected (the finiteness condition on its own). */
/* REQ-OBS-003 */
static void test_params_one_at_a_time(void **state)
{
    static const rfe_real_t bad[2] = {(rfe_real_t)INFINITY, (rfe_real_t)NAN};
    size_t f;
    size_t b;
    (void)state;
    assert_int_equal(rfe_velocity_params_validate(&vpar), RFE_OK);
    for (f = 0u; f < 11u; ++f) {
        for (b = 0u; b < 2u; ++b) {
            rfe_velocity_params_t p = vpar;
            rfe_real_t *const field[11] = {&p.q_jerk,      &p.sd_r,       &p.sd_ax,
                                           &p.sd_ay,       &p.v_lat_min,  &p.sd_lowspeed,
                                           &p.mu_default,  &p.sd_vydot,   &p.steer_ratio,
                                           &p.dt_min,      &p.dt_max};
            *field[f] = bad[b];
            assert_int_equal(rfe_velocity_params_validate(&p), RFE_ERR_PARAM);
        }
    }
    {
        rfe_velocity_params_t p = vpar; /* finite, not positive: the sign condition alone */
        p.dt_min = (rfe_real_t)0.0;
        assert_int_equal(rfe_velocity_params_validate(&p), RFE_ERR_PARAM);
    }
}

/* REQ: the conversion to Q formats rejects each NULL argument alone and leaves the output
 * untouched. */
/* REQ-FXP-015 */
static void test_params_to_q31_null_one_at_a_time(void **state)
{
    rfe_velocity_params_q31_t q;
    rfe_velocity_params_q31_t before;
    (void)state;
    memset(&q, 0x5A, sizeof q);
    before = q;
    assert_int_equal(rfe_velocity_params_to_q31(NULL, &q), RFE_ERR_NULL);
    assert_memory_equal(&q, &before, sizeof q);
    assert_int_equal(rfe_velocity_params_to_q31(&vpar, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_params_to_q31(&vpar, &q), RFE_OK);
}

/* REQ: a non-finite wheel speed, brake pressure or drive torque alone is RFE_ERR_NONFINITE,
 * and the observer is untouched. */
/* REQ-OBS-003 */
static void test_nonfinite_wheel_inputs_one_at_a_time(void **state)
{
    size_t k;
    size_t w;
    (void)state;
    {
        const rfe_velocity_input_t in = good_input();
        const rfe_velocity_mu_t mu = good_mu();
        expect_step(&in, &mu, RFE_OK);
    }
    for (k = 0u; k < 3u; ++k) {
        for (w = 0u; w < 4u; ++w) {
            rfe_velocity_input_t in = good_input();
            rfe_real_t *const v[3] = {&in.omega[w], &in.p_brake[w], &in.torque[w]};
            *v[k] = (rfe_real_t)NAN;
            expect_step(&in, NULL, RFE_ERR_NONFINITE);
        }
    }
}

/* REQ: each scalar input, each wheel's speed, pressure and torque, a friction below 0 or
 * above 2 and a negative sd, each alone beyond its limit, is RFE_ERR_RANGE, and the observer
 * is untouched. */
/* REQ-OBS-003 */
static void test_limits_one_at_a_time(void **state)
{
    const rfe_real_t lim_scalar[5] = {(rfe_real_t)RFE_LIMIT_DELTA, (rfe_real_t)RFE_LIMIT_YAW_RATE,
                                      (rfe_real_t)RFE_LIMIT_ACC, (rfe_real_t)RFE_LIMIT_ACC,
                                      (rfe_real_t)RFE_LIMIT_GRADE};
    const rfe_real_t lim_wheel[3] = {(rfe_real_t)RFE_LIMIT_OMEGA, (rfe_real_t)RFE_LIMIT_PRESSURE,
                                     (rfe_real_t)RFE_LIMIT_TORQUE};
    const rfe_real_t beyond = (rfe_real_t)1.01; /* 1 % past the limit: beyond it in float too */
    size_t k;
    size_t w;
    (void)state;
    for (k = 0u; k < 5u; ++k) {
        rfe_velocity_input_t in = good_input();
        rfe_real_t *const v[5] = {&in.delta, &in.yaw_rate, &in.ax, &in.ay, &in.grade};
        *v[k] = -beyond * lim_scalar[k];
        expect_step(&in, NULL, RFE_ERR_RANGE);
    }
    for (k = 0u; k < 3u; ++k) {
        for (w = 0u; w < 4u; ++w) {
            rfe_velocity_input_t in = good_input();
            rfe_real_t *const v[3] = {&in.omega[w], &in.p_brake[w], &in.torque[w]};
            *v[k] = beyond * lim_wheel[k];
            expect_step(&in, NULL, RFE_ERR_RANGE);
        }
    }
    for (k = 0u; k < 3u; ++k) {
        const rfe_velocity_input_t in = good_input();
        rfe_velocity_mu_t mu = good_mu();
        if (k == 0u) {
            mu.mu[1] = (rfe_real_t)-0.01;
        } else if (k == 1u) {
            mu.mu[2] = (rfe_real_t)2.01;
        } else {
            mu.sd[3] = (rfe_real_t)-0.01;
        }
        expect_step(&in, &mu, RFE_ERR_RANGE);
    }
}

/* The flags of the second step on @p in (the first one starts the filters). */
static uint32_t flags_of(const rfe_velocity_input_t *in)
{
    rfe_velocity_t obs;
    rfe_velocity_estimate_t e;
    started(&obs);
    assert_int_equal(rfe_velocity_step(&obs, in, NULL, &e), RFE_OK);
    return e.flags & (RFE_VEL_FLAG_BRAKING | RFE_VEL_FLAG_DRIVING);
}

/* REQ: with a drive-torque input the car drives when a wheel's torque exceeds torque_on and
 * it does not brake: torque with brake pressure is braking, no torque is rolling, torque
 * alone is driving (each condition of the decision on its own). */
/* REQ-OBS-004 */
static void test_driving_state_by_torque(void **state)
{
    rfe_velocity_input_t in = good_input();
    (void)state;
    assert_int_equal(flags_of(&in), 0u); /* no torque, no pressure: rolling */
    in.torque[2] = (rfe_real_t)2.0 * vpar.torque_on;
    assert_int_equal(flags_of(&in), RFE_VEL_FLAG_DRIVING);
    in.p_brake[0] = (rfe_real_t)2.0 * vpar.p_brake_on;
    assert_int_equal(flags_of(&in), RFE_VEL_FLAG_BRAKING);
}

/* REQ: the pipeline's step rejects each NULL argument alone with RFE_ERR_NULL. */
/* REQ-OBS-007 */
static void test_pipeline_null_one_at_a_time(void **state)
{
    static rfe_pipeline_t pl;
    rfe_pipeline_out_t out;
    const rfe_velocity_input_t in = good_input();
    (void)state;
    assert_int_equal(rfe_pipeline_init(&pl, &veh, &vpar), RFE_OK);
    assert_int_equal(rfe_pipeline_step(NULL, &in, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_step(&pl, NULL, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_step(&pl, &in, NULL), RFE_ERR_NULL);
    /* the valid call: no error (the first step may hold the estimate: not observable) */
    assert_int_equal(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &out)), 0);
}

/* REQ: the input-noise setter rejects each of its three values alone at +infinity (the
 * finiteness condition on its own; -infinity also fails the sign condition). */
/* REQ-EIV-002 */
static void test_input_noise_infinite_one_at_a_time(void **state)
{
    static rfe_friction_t est;
    const rfe_real_t inf = (rfe_real_t)INFINITY;
    const rfe_real_t ok = (rfe_real_t)0.1;
    (void)state;
    assert_int_equal(rfe_friction_init(&est, &veh), RFE_OK);
    assert_int_equal(rfe_friction_set_input_noise(&est, ok, ok, ok), RFE_OK);
    assert_int_equal(rfe_friction_set_input_noise(&est, inf, ok, ok), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise(&est, ok, inf, ok), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise(&est, ok, ok, inf), RFE_ERR_RANGE);
    /* finite and negative (r_yaw_acc: zero): the sign conditions alone */
    assert_int_equal(rfe_friction_set_input_noise(&est, -ok, ok, ok), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise(&est, ok, -ok, ok), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise(&est, ok, ok, (rfe_real_t)0.0), RFE_ERR_RANGE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_one_at_a_time),
        cmocka_unit_test(test_params_to_q31_null_one_at_a_time),
        cmocka_unit_test(test_nonfinite_wheel_inputs_one_at_a_time),
        cmocka_unit_test(test_limits_one_at_a_time),
        cmocka_unit_test(test_driving_state_by_torque),
        cmocka_unit_test(test_pipeline_null_one_at_a_time),
        cmocka_unit_test(test_input_noise_infinite_one_at_a_time),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
