/**
 * @file test_pipeline_loop_flt.c
 * @brief The friction loop of the composed pipeline (OBSERVER.md §6 "The loop") closed on a
 *        friction step while cornering: it does not run away (float and double).
 *
 * The loop: each step the observer's model row uses the friction estimator's previous
 * estimate and sd (raised to what the measured ay proves), and the friction estimator runs
 * on the observer's vx, vy, r-dot with their sd. The log (scenarios/observer_loop/
 * turn_mu_step, make observer-loop-scenarios): the circle_r60 turn (ay ~ 4 m/s^2) on mu 0.9,
 * 0.5 from t ~ 10 s, 0.9 again from t ~ 20 s, with both truth tyres; the pipeline runs on the
 * production sensors only (no vx, vy, r-dot; the brake pressures and drive torques the log
 * has), default preset and observer parameters: the samples and parameters of
 * `mu_replay --velocity observer`.
 *
 * What is asserted, each bound from issue 16's targets or the observer's own parameters:
 * - every step succeeds and every output and sd is finite; the lateral filter's sd(vy)
 *   (sd_vy_filter) stays in (0, obs_sd_vy0]: the observer never knows less than at its
 *   start (the reported sd(vy) carries §5's floor, obs_vy_out_floor_mu 4 by default, whose
 *   point is to exceed the filter's where the friction is unobserved: not bounded here);
 * - no runaway: |vy| never exceeds the largest |vy| the car has, widened by the 0.3 deg
 *   target at the log's speed (max vx tan 0.3 deg = 0.08 m/s);
 * - after the step back to mu 0.9 (|ay| < 0.5 mu g: the 0.3 deg target applies), |beta
 *   error| <= 0.3 deg from LOOP_T_CONV = 3 s on, to the end of the log (8 s);
 * - the Magic Formula truth (whose stiffness does not scale with mu): |beta error| <= 1.0 deg
 *   (the at-the-limit target, taken as a maximum) everywhere and RMS <= 0.3 deg.
 * Negative control: the same Dugoff run with the linear range's vy row off (obs_sd_vy_lin
 * = 0, the safeguard of §4.2b) runs away after the step up, past both bounds.
 *
 * Not asserted (a measured limitation, OBSERVER.md §6 "The loop"): on the Dugoff truth,
 * whose cornering stiffness scales with mu like the paper tyre's mu F0, the steady turn on
 * mu 0.5 leaves the loop at a consistent wrong point: ay fixes only the product of the
 * friction and the slip angle, and kinematics do not see a constant vy, so the friction
 * estimator reads its bound 1.2 from the observer's small vy and the observer keeps the
 * high-friction vy: beta 3.6 deg off (measured) with sd(vy) ~ 0.02 m/s, bounded and not
 * growing. Float and double agree to ~1e-5 m/s here, far inside every bound.
 */
#include "test_common.h"

#include <math.h>
#include <string.h>

#include "csv_log.h"
#include "loop_check.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/pipeline.h"

/* The preset, the log's metadata and the observer defaults, as mu_replay derives them. */
static void params_of(const rfe_sensor_log_t *log, rfe_params_t *p, rfe_velocity_params_t *vp)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(p, 0, sizeof *p); /* the estimators copy them, padding included */
    memset(vp, 0, sizeof *vp);
    rfe_param_set_default(&ps);
    assert_int_equal(rfe_param_set_apply_meta(&ps, log, "log", &err), 0);
    assert_int_equal(rfe_replay_params(&ps, p, NULL), RFE_OK);
    assert_int_equal(rfe_replay_velocity_params(&ps, vp, NULL), RFE_OK);
}

/* The run of @p name with the preset, the log's metadata and the observer defaults, as
 * mu_replay derives them; @p sd_vy_lin >= 0 replaces obs_sd_vy_lin (negative: keep). */
static void run(const char *name, double sd_vy_lin, loop_run_t *r, loop_stats_t *s,
                double *sd_vy0)
{
    static rfe_pipeline_t pl;
    rfe_sensor_log_t log;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    size_t k;
    loop_read(name, &log, r);
    params_of(&log, &p, &vp);
    if (sd_vy_lin >= 0.0) {
        vp.sd_vy_lin = (rfe_real_t)sd_vy_lin;
        vp.ay_turn = 0.0f; /* the negative control: the turn rule off too (see below) */
    }
    *sd_vy0 = (double)vp.sd_vy0;
    memset(&pl, 0, sizeof pl);
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
    for (k = 0u; k < log.n_rows; ++k) {
        rfe_velocity_input_t in;
        rfe_pipeline_out_t o;
        rfe_replay_esc_input(&log, k, (k > 0u) ? k - 1u : 0u, &in); /* mu_replay's sample */
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
        r->vy[k] = (double)o.velocity.vy;
        r->beta[k] = (double)o.velocity.beta;
        r->sd_vy[k] = (double)pl.velocity.sd_vy_filter; /* the filter's: the runaway bound */
        r->sd_beta[k] = (double)o.velocity.sd_beta;
        assert_true(isfinite((double)o.velocity.sd_vy) &&
                    (o.velocity.sd_vy >= pl.velocity.sd_vy_filter)); /* the floor only raises */
    }
    rfe_sensor_log_free(&log);
    *s = loop_stats(r);
    loop_print(name, r, s);
}

static loop_run_t lr; /* 10 arrays of 4000 doubles: not on the stack */

/* The Dugoff run of test_the_loop_does_not_run_away_dugoff twice side by side, the
 * reported sd(vy)'s floor off (obs_vy_out_floor_mu 0) and at @p k (OBSERVER.md
 * §5): every friction estimate and vx, vy, beta, sd(vx) equal bit for bit (the floor is on
 * the report only, the friction estimator's vy input noise is the filter's own sd, so the
 * closed loop is unchanged by construction); off, the reported sd(vy) is the filter's; on,
 * it is at least that. @p r gets the run with the floor. */
static void run_floor(const char *name, double k_floor, loop_run_t *r)
{
    static rfe_pipeline_t off;
    static rfe_pipeline_t on;
    rfe_sensor_log_t log;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    size_t k;
    size_t floored = 0u;
    loop_read(name, &log, r);
    params_of(&log, &p, &vp);
    assert_true(vp.vy_out_floor_mu == (rfe_real_t)4.0); /* 4 by default (OBSERVER.md §2) */
    memset(&off, 0, sizeof off);
    memset(&on, 0, sizeof on);
    vp.vy_out_floor_mu = (rfe_real_t)0.0; /* off */
    assert_int_equal(rfe_pipeline_init(&off, &p, &vp), RFE_OK);
    vp.vy_out_floor_mu = (rfe_real_t)k_floor;
    assert_int_equal(rfe_pipeline_init(&on, &p, &vp), RFE_OK);
    for (k = 0u; k < log.n_rows; ++k) {
        rfe_velocity_input_t in;
        rfe_pipeline_out_t a;
        rfe_pipeline_out_t b;
        rfe_replay_esc_input(&log, k, (k > 0u) ? k - 1u : 0u, &in);
        assert_false(rfe_status_is_error(rfe_pipeline_step(&off, &in, &a)));
        assert_false(rfe_status_is_error(rfe_pipeline_step(&on, &in, &b)));
        assert_memory_equal(&a.friction, &b.friction, sizeof(a.friction));
        assert_memory_equal(&off.friction, &on.friction, sizeof(off.friction));
        assert_true((a.velocity.vx == b.velocity.vx) && (a.velocity.vy == b.velocity.vy) &&
                    (a.velocity.beta == b.velocity.beta) &&
                    (a.velocity.sd_vx == b.velocity.sd_vx));
        assert_true(a.velocity.sd_vy == off.velocity.sd_vy_filter);
        assert_true(on.velocity.sd_vy_filter == off.velocity.sd_vy_filter);
        assert_true(b.velocity.sd_vy >= a.velocity.sd_vy);
        floored += (b.velocity.sd_vy > a.velocity.sd_vy) ? 1u : 0u;
        r->vy[k] = (double)b.velocity.vy;
        r->beta[k] = (double)b.velocity.beta;
        r->sd_vy[k] = (double)b.velocity.sd_vy;
        r->sd_beta[k] = (double)b.velocity.sd_beta;
    }
    loop_assert_floor_count(k_floor, floored);
    rfe_sensor_log_free(&log);
}

/* REQ-OBS-025: issue 17, never confidently wrong. On the Dugoff truth's mu 0.5 phase the loop
 * stays at a wrong point (beta 3.5 deg off, OBSERVER.md §6) with sd(beta) 0.07 deg: every
 * sample beyond 2 sd without the floor (measured 100 %; asserted > 90 %, so the check below
 * can fail); with obs_vy_out_floor_mu 4 at most a consistent Gaussian's 4.55 % (the study
 * measured 0 %), and the loop itself unchanged (run_floor). */
static void test_the_output_floor_makes_the_mu_step_honest(void **state)
{
    (void)state;
    loop_assert_floor_honest(run_floor, &lr, "");
}

/* REQ-OBS-024 */
static void test_the_loop_does_not_run_away_dugoff(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.csv", -1.0, &lr, &s, &sd_vy0);
    loop_assert_no_runaway(&s, sd_vy0);
}

/* REQ-OBS-024 */
static void test_the_loop_does_not_run_away_magic_formula(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.mf.csv", -1.0, &lr, &s, &sd_vy0);
    loop_assert_no_runaway(&s, sd_vy0);
    loop_assert_beta_targets(&s);
}

/* REQ-OBS-024: the checks can fail. Without the linear range's vy row the loop has nothing
 * that pulls vy back once the friction input is wrong: after the step up vy drifts on
 * (measured: to 1.20 m/s against a true 0.04, 4.2 deg off at the end, sd(vy) 0.37). The
 * control runs with the longitudinal turn rule off (obs_ay_turn 0, REQ-OBS-028): with it on
 * the same run stays within every bound (measured 2026-12-07: max |vy| 0.391 m/s against
 * 1.098, settled 1.84 s after the step up), so the control would not show that the checks
 * can fail. */
static void test_without_the_linear_row_the_loop_runs_away(void **state)
{
    loop_stats_t s;
    double sd_vy0;
    (void)state;
    run("turn_mu_step.csv", 0.0, &lr, &s, &sd_vy0);
    loop_assert_runs_away(&s, sd_vy0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_the_loop_does_not_run_away_dugoff),
        cmocka_unit_test(test_the_loop_does_not_run_away_magic_formula),
        cmocka_unit_test(test_without_the_linear_row_the_loop_runs_away),
        cmocka_unit_test(test_the_output_floor_makes_the_mu_step_honest),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
