/**
 * @file test_pipeline_loop_q31.c
 * @brief The friction loop of the fixed-point composed pipeline (rfe_pipeline_step_q31,
 *        OBSERVER.md §6 "The loop") closed on a friction step while cornering: it does not
 *        run away.
 *
 * The run, the log and the bounds of test_pipeline_loop_flt.c (loop_check.h), on the
 * samples and parameters of `mu_replay --velocity observer --real q31`: the double sample
 * rounded to the Q formats (rfe_replay_esc_input_q31), the converted parameters
 * (test_params_both.h). The outputs are converted back to double (vy, sd(vy) Q23; beta,
 * sd(beta) Q29) before the checks, whose bounds (0.08 m/s, 0.3 deg, 3 s) are far above the
 * fixed-point twin's distance from the double one (test_pipeline_q31.c: 5e-4 m/s on vy), so
 * the double build's bounds hold unchanged; no value saturates.
 */
#include "test_common.h"

#include <math.h>
#include <string.h>

#include "csv_log.h"
#include "host/fixed_conv.h"
#include "loop_check.h"
#include "replay_q31.h"
#include "rfe/pipeline_q31.h"
#include "test_params_both.h"

/* The run of @p name; @p sd_vy_lin >= 0 replaces obs_sd_vy_lin (negative: keep). */
static void run(const char *name, double sd_vy_lin, loop_run_t *r, loop_stats_t *s,
                double *sd_vy0)
{
    static rfe_pipeline_q31_t pl;
    rfe_sensor_log_t log;
    both_t b;
    size_t k;
    uint32_t sat = 0u;
    loop_read(name, &log, r);
    if (sd_vy_lin >= 0.0) {
        rfe_param_set_t ps;
        rfe_io_error_t err;
        memset(&b, 0, sizeof b);
        rfe_param_set_default(&ps);
        assert_int_equal(rfe_param_set_apply_meta(&ps, &log, "log", &err), 0);
        assert_int_equal(rfe_replay_params(&ps, &b.pd, NULL), RFE_OK);
        assert_int_equal(rfe_replay_velocity_params(&ps, &b.vd, NULL), RFE_OK);
        b.vd.sd_vy_lin = sd_vy_lin;
        b.vd.ay_turn = 0.0; /* the negative control: the turn rule off too (flt's test) */
        assert_int_equal(rfe_params_to_q31_f64(&b.pd, &b.pq), RFE_OK);
        assert_int_equal(rfe_velocity_params_to_q31_f64(&b.vd, &b.vq), RFE_OK);
    } else {
        params_of(&log, &b);
    }
    *sd_vy0 = rfe_fix_to_double(b.vq.sd_vy0, 23u);
    memset(&pl, 0, sizeof pl);
    assert_int_equal(rfe_pipeline_init_q31(&pl, &b.pq, &b.vq), RFE_OK);
    for (k = 0u; k < log.n_rows; ++k) {
        rfe_velocity_input_q31_t in;
        rfe_pipeline_out_q31_t o;
        sat += rfe_replay_esc_input_q31(&log, k, (k > 0u) ? k - 1u : 0u, &in);
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pl, &in, &o)));
        assert_int_equal(o.velocity.sat, 0u);
        assert_int_equal(o.friction.sat, 0u);
        r->vy[k] = rfe_fix_to_double(o.velocity.vy, 23u);
        r->beta[k] = rfe_fix_to_double(o.velocity.beta, 29u);
        /* the filter's sd(vy): the runaway bound (test_pipeline_loop_flt.c) */
        r->sd_vy[k] = rfe_fix_to_double(pl.velocity.sd_vy_filter, 23u);
        r->sd_beta[k] = rfe_fix_to_double(o.velocity.sd_beta, 29u);
        assert_true(o.velocity.sd_vy >= pl.velocity.sd_vy_filter); /* the floor only raises */
    }
    assert_int_equal(sat, 0u);
    rfe_sensor_log_free(&log);
    *s = loop_stats(r);
    loop_print(name, r, s);
}

static loop_run_t lr; /* 10 arrays of 4000 doubles: not on the stack */

/* REQ-OBS-024 */
static void test_the_loop_does_not_run_away_dugoff_q31(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.csv", -1.0, &lr, &s, &sd_vy0);
    loop_assert_no_runaway(&s, sd_vy0);
}

/* REQ-OBS-024 */
static void test_the_loop_does_not_run_away_magic_formula_q31(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.mf.csv", -1.0, &lr, &s, &sd_vy0);
    loop_assert_no_runaway(&s, sd_vy0);
    loop_assert_beta_targets(&s);
}

/* REQ-OBS-024: the checks can fail (test_pipeline_loop_flt.c's control, in fixed point) */
static void test_without_the_linear_row_the_loop_runs_away_q31(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.csv", 0.0, &lr, &s, &sd_vy0);
    loop_assert_runs_away(&s, sd_vy0);
}

/* The Dugoff run of test_the_loop_does_not_run_away_dugoff_q31 twice side by side, the
 * reported sd(vy)'s floor off (obs_vy_out_floor_mu 0) and at @p k (Q24,
 * OBSERVER.md §5): test_pipeline_loop_flt.c's run_floor in fixed point (the friction
 * estimates and vx, vy, beta, sd(vx) equal bit for bit; off, the reported sd(vy) is the
 * filter's). @p r gets the run with the floor. */
static void run_floor(const char *name, double k_floor, loop_run_t *r)
{
    static rfe_pipeline_q31_t off;
    static rfe_pipeline_q31_t on;
    rfe_sensor_log_t log;
    both_t b;
    rfe_velocity_params_q31_t vq_on;
    size_t k;
    size_t floored = 0u;
    uint32_t sat = 0u;
    loop_read(name, &log, r);
    params_of(&log, &b);
    assert_int_equal(b.vq.vy_out_floor_mu, RFE_FIX_ONE(26)); /* 4 (Q24) by default */
    b.vd.vy_out_floor_mu = 0.0; /* off */
    assert_int_equal(rfe_velocity_params_to_q31_f64(&b.vd, &b.vq), RFE_OK);
    assert_int_equal(b.vq.vy_out_floor_mu, 0);
    b.vd.vy_out_floor_mu = k_floor;
    vq_on = b.vq;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&b.vd, &vq_on), RFE_OK);
    memset(&off, 0, sizeof off);
    memset(&on, 0, sizeof on);
    assert_int_equal(rfe_pipeline_init_q31(&off, &b.pq, &b.vq), RFE_OK);
    assert_int_equal(rfe_pipeline_init_q31(&on, &b.pq, &vq_on), RFE_OK);
    for (k = 0u; k < log.n_rows; ++k) {
        rfe_velocity_input_q31_t in;
        rfe_pipeline_out_q31_t a;
        rfe_pipeline_out_q31_t o;
        sat += rfe_replay_esc_input_q31(&log, k, (k > 0u) ? k - 1u : 0u, &in);
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&off, &in, &a)));
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&on, &in, &o)));
        assert_int_equal(o.velocity.sat, 0u);
        assert_memory_equal(&a.friction, &o.friction, sizeof(a.friction));
        assert_memory_equal(&off.friction, &on.friction, sizeof(off.friction));
        assert_true((a.velocity.vx == o.velocity.vx) && (a.velocity.vy == o.velocity.vy) &&
                    (a.velocity.beta == o.velocity.beta) &&
                    (a.velocity.sd_vx == o.velocity.sd_vx));
        assert_int_equal(a.velocity.sd_vy, off.velocity.sd_vy_filter);
        assert_int_equal(on.velocity.sd_vy_filter, off.velocity.sd_vy_filter);
        assert_true(o.velocity.sd_vy >= a.velocity.sd_vy);
        floored += (o.velocity.sd_vy > a.velocity.sd_vy) ? 1u : 0u;
        r->vy[k] = rfe_fix_to_double(o.velocity.vy, 23u);
        r->beta[k] = rfe_fix_to_double(o.velocity.beta, 29u);
        r->sd_vy[k] = rfe_fix_to_double(o.velocity.sd_vy, 23u);
        r->sd_beta[k] = rfe_fix_to_double(o.velocity.sd_beta, 29u);
    }
    assert_int_equal(sat, 0u);
    loop_assert_floor_count(k_floor, floored);
    rfe_sensor_log_free(&log);
}

/* REQ-OBS-025: test_pipeline_loop_flt.c's test_the_output_floor_makes_the_mu_step_honest in
 * fixed point: on the Dugoff truth's mu 0.5 phase more than 90 % of the samples beyond 2
 * sd(beta) without the floor, at most a consistent Gaussian's 4.55 % with
 * obs_vy_out_floor_mu 4 (the floor's Q31 path is within 1e-6 m/s of its closed form,
 * test_velocity_q31.c, so the double build's figures hold), the loop unchanged. */
static void test_the_output_floor_makes_the_mu_step_honest_q31(void **state)
{
    (void)state;
    loop_assert_floor_honest(run_floor, &lr, "q31 ");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_loop_does_not_run_away_dugoff_q31),
        cmocka_unit_test(test_the_loop_does_not_run_away_magic_formula_q31),
        cmocka_unit_test(test_without_the_linear_row_the_loop_runs_away_q31),
        cmocka_unit_test(test_the_output_floor_makes_the_mu_step_honest_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
