/**
 * @file test_metrics.c
 * @brief Tests of the accuracy metrics on small synthetic series, expected values derived
 *        by hand in the comments.
 *
 * Tolerance: TOL = 1e-12 absolute. Every expected value is a short exact decimal expression
 * evaluated in double; the metric code sums at most a dozen squares, so its rounding error
 * is a few ulp of numbers below 1, far below TOL.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "metrics.h"

#define TOL 1e-12

static void assert_near(double got, double want)
{
    if (!(fabs(got - want) <= TOL)) {
        fail_msg("got %.17g, want %.17g", got, want);
    }
}

/*
 * Series A: constant truth 0.5, dt = 0.5 s, no truth change.
 *   t    : 0    0.5  1.0   1.5   2.0
 *   est  : 0.9  0.6  0.52  0.47  0.51
 *   error: 0.4  0.1  0.02 -0.03  0.01
 * Settled (t >= 0 + 1.0): the last three. RMSE = sqrt((4e-4 + 9e-4 + 1e-4)/3) = sqrt(14e-4/3);
 * max |e| = 0.03; max rel = 0.03/0.5 = 0.06. Converge (tol 0.05): last sample outside is
 * t = 0.5, so from t = 1.0: 1.0 - 0 = 1.0 s.
 */
static void test_rfe_metric_series_constant_truth(void **state)
{
    const double t[] = {0.0, 0.5, 1.0, 1.5, 2.0};
    const double truth[] = {0.5, 0.5, 0.5, 0.5, 0.5};
    const double est[] = {0.9, 0.6, 0.52, 0.47, 0.51};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(rfe_metric_series(t, truth, est, 5u, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 3);
    assert_near(m.rmse, sqrt(14e-4 / 3.0));
    assert_near(m.max_abs, 0.03);
    assert_near(m.max_rel, 0.06);
    assert_near(m.t_converge, 1.0);
}

/*
 * Series B: truth 0.8 until t = 2.0, then 0.3 (change at k = 8); dt = 0.25 s, 13 samples.
 *   k      : 0-3  4     5     6    7     8    9    10    11    12
 *   t      : ..   1.0   1.25  1.5  1.75  2.0  2.25 2.5   2.75  3.0
 *   truth  : 0.8  0.8   0.8   0.8  0.8   0.3  0.3  0.3   0.3   0.3
 *   est    : 0.5  0.78  0.82  0.80 0.79  0.8  0.5  0.34  0.28  0.31
 *   error  : -.3  -.02  .02   0    -.01  .5   .2   .04   -.02  .01
 * Settled: t >= 1.0 and not in [2.0, 2.5): k = 4..7 and 10..12 (7 samples).
 *   sum of squares = (4 + 4 + 0 + 1 + 16 + 4 + 1) e-4 = 30e-4; RMSE = sqrt(30e-4/7).
 *   max |e| = 0.04 (k = 10); max rel = 0.04/0.3.
 * Converge: from the change (k = 8, t = 2.0): errors .5 .2 .04 -.02 .01; the last outside is
 *   k = 9, so t[10] - t[8] = 0.5 s.
 */
static void test_rfe_metric_series_truth_step(void **state)
{
    double t[13];
    const double truth[13] = {0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.3, 0.3, 0.3, 0.3, 0.3};
    const double est[13] = {0.5, 0.5, 0.5, 0.5, 0.78, 0.82, 0.80, 0.79, 0.8, 0.5, 0.34, 0.28, 0.31};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    size_t k;
    (void)state;
    for (k = 0u; k < 13u; ++k) {
        t[k] = 0.25 * (double)k;
    }
    assert_int_equal(rfe_metric_series(t, truth, est, 13u, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 7);
    assert_near(m.rmse, sqrt(30e-4 / 7.0));
    assert_near(m.max_abs, 0.04);
    assert_near(m.max_rel, 0.04 / 0.3);
    assert_near(m.t_converge, 0.5);
}

/*
 * Same data as series B, configuration changed: settle_start = 0, settle_after_change = 0,
 * converge_tol = 0.25. Now every sample is settled (13); max |e| = 0.5 (k = 8, the step);
 * convergence from k = 8: only |0.5| > 0.25, so t[9] - t[8] = 0.25 s. Shows the knobs are
 * used rather than literals.
 */
static void test_rfe_metric_series_config_is_used(void **state)
{
    double t[13];
    const double truth[13] = {0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.8, 0.3, 0.3, 0.3, 0.3, 0.3};
    const double est[13] = {0.5, 0.5, 0.5, 0.5, 0.78, 0.82, 0.80, 0.79, 0.8, 0.5, 0.34, 0.28, 0.31};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    size_t k;
    (void)state;
    for (k = 0u; k < 13u; ++k) {
        t[k] = 0.25 * (double)k;
    }
    cfg.settle_start = 0.0;
    cfg.settle_after_change = 0.0;
    cfg.converge_tol = 0.25;
    assert_int_equal(rfe_metric_series(t, truth, est, 13u, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 13);
    assert_near(m.max_abs, 0.5);
    assert_near(m.max_rel, 0.5 / 0.3);
    assert_near(m.t_converge, 0.25);
}

/* Last sample outside the tolerance: never converges (negative). */
static void test_rfe_metric_series_never_converges(void **state)
{
    const double t[] = {0.0, 1.0, 2.0};
    const double truth[] = {0.4, 0.4, 0.4};
    const double est[] = {0.4, 0.4, 0.5}; /* last error 0.1 > 0.05 */
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(rfe_metric_series(t, truth, est, 3u, &cfg, &m), 0);
    assert_true(m.t_converge < 0.0);
    assert_near(m.max_abs, 0.1);
}

/* Within tolerance from the first sample: converged at once (0 s). */
static void test_rfe_metric_series_converged_from_start(void **state)
{
    const double t[] = {0.0, 1.0, 2.0};
    const double truth[] = {0.4, 0.4, 0.4};
    const double est[] = {0.42, 0.39, 0.4};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(rfe_metric_series(t, truth, est, 3u, &cfg, &m), 0);
    assert_near(m.t_converge, 0.0);
}

/* A log shorter than settle_start has no settled sample: statistics NaN, count 0. */
static void test_rfe_metric_series_no_settled_samples(void **state)
{
    const double t[] = {0.0, 0.5};
    const double truth[] = {0.4, 0.4};
    const double est[] = {0.4, 0.4};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(rfe_metric_series(t, truth, est, 2u, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 0);
    assert_true(isnan(m.rmse));
    assert_true(isnan(m.max_abs));
    assert_true(isnan(m.max_rel));
}

/* A NaN estimate must not disappear: RMSE and max become NaN, and it never converges. */
static void test_rfe_metric_series_nan_estimate(void **state)
{
    const double t[] = {0.0, 1.0, 2.0};
    const double truth[] = {0.4, 0.4, 0.4};
    const double est[] = {0.4, 0.4, (double)NAN};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(rfe_metric_series(t, truth, est, 3u, &cfg, &m), 0);
    assert_true(isnan(m.rmse));
    assert_true(isnan(m.max_abs));
    assert_true(m.t_converge < 0.0);
}

/* Truth <= 0 has no relative error: skipped, NaN when nothing is left. */
static void test_rfe_metric_series_zero_truth_no_relative_error(void **state)
{
    const double t[] = {1.0, 2.0};
    const double truth[] = {0.0, 0.0};
    const double est[] = {0.01, 0.02};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    cfg.settle_start = 0.0;
    assert_int_equal(rfe_metric_series(t, truth, est, 2u, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 2);
    assert_near(m.max_abs, 0.02);
    assert_true(isnan(m.max_rel));
}

static void test_rfe_metric_series_rejects_empty_and_null(void **state)
{
    const double x[] = {0.0};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(rfe_metric_series(x, x, x, 0u, &cfg, &m), -1);
    assert_int_equal(rfe_metric_series(NULL, x, x, 1u, &cfg, &m), -1);
    assert_int_equal(rfe_metric_series(x, x, x, 1u, NULL, &m), -1);
}

/*
 * Four wheels, dt = 0.5 s, 6 samples; fl's truth steps 0.4 -> 0.8 at t = 1.5 (k = 3), the
 * others stay 0.4 with perfect estimates.
 *   t        : 0    0.5  1.0   1.5    2.0    2.5
 *   truth fl : 0.4  0.4  0.4   0.8    0.8    0.8
 *   est fl   : 0.4  0.4  0.42  0.5    0.7    0.8
 *   err fl   : 0    0    0.02  -0.3   -0.1   0
 *   mean tru : 0.4  0.4  0.4   0.5    0.5    0.5
 *   mean est : 0.4  0.4  0.405 0.425  0.475  0.5
 *   mean err : 0    0    0.005 -0.075 -0.025 0
 * fl: settled k = 2, 4, 5 (k = 3 is within 0.5 s of the change; t = 2.0 = 1.5 + 0.5 is not):
 *   RMSE = sqrt((4e-4 + 1e-2 + 0)/3); max |e| = 0.1; max rel = max(0.02/0.4, 0.1/0.8) = 0.125;
 *   converge from k = 3: last outside k = 4, so t[5] - t[3] = 1.0 s.
 * mean: the change of fl is a change of the mean; settled k = 2, 4, 5:
 *   RMSE = sqrt((25e-6 + 625e-6 + 0)/3); max |e| = 0.025; max rel = max(0.005/0.4,
 *   0.025/0.5) = 0.05; converge from k = 3: last outside k = 3, so t[4] - t[3] = 0.5 s.
 * fr: error 0 everywhere: RMSE 0, settled k = 2..5 (4 samples, no change on fr), converge 0.
 */
static void test_rfe_metrics_compute_wheels_and_mean(void **state)
{
    const double t[6] = {0.0, 0.5, 1.0, 1.5, 2.0, 2.5};
    const double tfl[6] = {0.4, 0.4, 0.4, 0.8, 0.8, 0.8};
    const double efl[6] = {0.4, 0.4, 0.42, 0.5, 0.7, 0.8};
    const double c04[6] = {0.4, 0.4, 0.4, 0.4, 0.4, 0.4};
    const double *const truth[RFE_WHEELS] = {tfl, c04, c04, c04};
    const double *const est[RFE_WHEELS] = {efl, c04, c04, c04};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    (void)state;
    assert_int_equal(rfe_metrics_compute(t, truth, est, 6u, &cfg, &m), 0);
    assert_int_equal(m.wheel[RFE_FL].n_settled, 3);
    assert_near(m.wheel[RFE_FL].rmse, sqrt((4e-4 + 1e-2) / 3.0));
    assert_near(m.wheel[RFE_FL].max_abs, 0.1);
    assert_near(m.wheel[RFE_FL].max_rel, 0.125);
    assert_near(m.wheel[RFE_FL].t_converge, 1.0);
    assert_int_equal(m.mean.n_settled, 3);
    assert_near(m.mean.rmse, sqrt((25e-6 + 625e-6) / 3.0));
    assert_near(m.mean.max_abs, 0.025);
    assert_near(m.mean.max_rel, 0.05);
    assert_near(m.mean.t_converge, 0.5);
    assert_int_equal(m.wheel[RFE_FR].n_settled, 4);
    assert_near(m.wheel[RFE_FR].rmse, 0.0);
    assert_near(m.wheel[RFE_FR].t_converge, 0.0);
    assert_near(m.cfg.converge_tol, 0.05);
}

static void test_rfe_metrics_compute_rejects_empty(void **state)
{
    const double x[1] = {0.0};
    const double *const cols[RFE_WHEELS] = {x, x, x, x};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    (void)state;
    assert_int_equal(rfe_metrics_compute(x, cols, cols, 0u, &cfg, &m), -1);
    assert_int_equal(rfe_metrics_compute(x, NULL, cols, 1u, &cfg, &m), -1);
}

/* JSON: numbers where defined, null for NaN and for "never". Table: "n/a" and "never". */
static void test_rfe_metrics_write_json_and_table(void **state)
{
    const double t[3] = {0.0, 1.0, 2.0};
    const double tr[3] = {0.4, 0.4, 0.4};
    const double ok[3] = {0.4, 0.4, 0.41};
    const double bad[3] = {0.4, 0.4, 0.6};
    const double *const truth[RFE_WHEELS] = {tr, tr, tr, tr};
    const double *const est[RFE_WHEELS] = {ok, bad, ok, ok};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    char *buf = NULL;
    size_t len = 0u;
    FILE *f;
    (void)state;
    assert_int_equal(rfe_metrics_compute(t, truth, est, 3u, &cfg, &m), 0);
    m.wheel[RFE_RR].n_settled = 0u; /* pretend: undefined statistics */
    m.wheel[RFE_RR].rmse = (double)NAN;
    m.wheel[RFE_RR].max_rel = (double)NAN;
    f = open_memstream(&buf, &len);
    assert_non_null(f);
    rfe_metrics_write_json(f, &m, 0);
    fclose(f);
    assert_non_null(strstr(buf, "\"converge_tol\": 0.05"));
    assert_non_null(strstr(buf, "\"fl\": {\"n_settled\": 2, \"rmse\": "));
    assert_non_null(strstr(buf, "\"fr\": {\"n_settled\": 2, \"rmse\": "));
    assert_non_null(strstr(buf, "\"t_converge_s\": null}")); /* fr never converges */
    assert_non_null(strstr(buf, "\"rr\": {\"n_settled\": 0, \"rmse\": null"));
    assert_non_null(strstr(buf, "\"mean\": {"));
    assert_int_equal(buf[strlen(buf) - 1u], '}');
    free(buf);
    buf = NULL;
    f = open_memstream(&buf, &len);
    assert_non_null(f);
    rfe_metrics_print_table(f, &m);
    fclose(f);
    assert_non_null(strstr(buf, "never"));
    assert_non_null(strstr(buf, "n/a"));
    assert_non_null(strstr(buf, "\nmean "));
    free(buf);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_metric_series_constant_truth),
        cmocka_unit_test(test_rfe_metric_series_truth_step),
        cmocka_unit_test(test_rfe_metric_series_config_is_used),
        cmocka_unit_test(test_rfe_metric_series_never_converges),
        cmocka_unit_test(test_rfe_metric_series_converged_from_start),
        cmocka_unit_test(test_rfe_metric_series_no_settled_samples),
        cmocka_unit_test(test_rfe_metric_series_nan_estimate),
        cmocka_unit_test(test_rfe_metric_series_zero_truth_no_relative_error),
        cmocka_unit_test(test_rfe_metric_series_rejects_empty_and_null),
        cmocka_unit_test(test_rfe_metrics_compute_wheels_and_mean),
        cmocka_unit_test(test_rfe_metrics_compute_rejects_empty),
        cmocka_unit_test(test_rfe_metrics_write_json_and_table),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
