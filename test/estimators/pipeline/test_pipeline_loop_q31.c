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
        r->sd_vy[k] = rfe_fix_to_double(o.velocity.sd_vy, 23u);
        r->sd_beta[k] = rfe_fix_to_double(o.velocity.sd_beta, 29u);
    }
    assert_int_equal(sat, 0u);
    rfe_sensor_log_free(&log);
    *s = loop_stats(r);
    loop_print(name, r, s);
}

static loop_run_t lr; /* 9 arrays of 4000 doubles: not on the stack */

static void assert_no_runaway(const loop_stats_t *s, double sd_vy0)
{
    assert_true(s->finite);
    assert_true(s->min_sd_vy > 0.0);
    ASSERT_LE(s->max_sd_vy, sd_vy0, "sd(vy) <= obs_sd_vy0");
    ASSERT_LE(s->max_vy, s->vy_bound, "max |vy| <= max |vy_true| + vx tan 0.3 deg");
    ASSERT_LE(s->t_settle, LOOP_T_CONV, "settled after the step up [s]");
}

/* REQ-OBS-024 */
static void test_the_loop_does_not_run_away_dugoff_q31(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.csv", -1.0, &lr, &s, &sd_vy0);
    assert_no_runaway(&s, sd_vy0);
}

/* REQ-OBS-024 */
static void test_the_loop_does_not_run_away_magic_formula_q31(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.mf.csv", -1.0, &lr, &s, &sd_vy0);
    assert_no_runaway(&s, sd_vy0);
    ASSERT_LE(s.max_err_deg, LOOP_BETA_LIMIT_DEG, "max |beta error| [deg]");
    ASSERT_LE(s.rms_err_deg, LOOP_BETA_LIN_DEG, "RMS beta error [deg]");
}

/* REQ-OBS-024: the checks can fail (test_pipeline_loop_flt.c's control, in fixed point) */
static void test_without_the_linear_row_the_loop_runs_away_q31(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.csv", 0.0, &lr, &s, &sd_vy0);
    assert_true(s.max_vy > s.vy_bound);
    assert_true(s.max_sd_vy > sd_vy0);
    assert_true(s.t_settle > LOOP_T_CONV);
    assert_true(s.end_err_deg > LOOP_BETA_LIMIT_DEG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_loop_does_not_run_away_dugoff_q31),
        cmocka_unit_test(test_the_loop_does_not_run_away_magic_formula_q31),
        cmocka_unit_test(test_without_the_linear_row_the_loop_runs_away_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
