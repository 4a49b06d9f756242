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

/** Longest synthetic series below. */
#define MAXN 16u

static void assert_near(double got, double want)
{
    if (!(fabs(got - want) <= TOL)) {
        fail_msg("got %.17g, want %.17g", got, want);
    }
}

/* Placeholders for the tests of the error figures, which do not look at sd / valid. */
static const double k_sd1[MAXN] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
static const unsigned char k_valid1[MAXN] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1};

/* One-wheel input: wheel fl gets the columns, the others stay NULL (a wheel series needs
 * only its own). sd / valid NULL = the placeholders above; util NULL = no util columns. */
static rfe_metrics_input_t input1(const double *t, const double *truth, const double *est,
                                  const double *sd, const unsigned char *valid,
                                  const double *util, size_t n)
{
    rfe_metrics_input_t in;
    assert_true(n <= MAXN);
    memset(&in, 0, sizeof in);
    in.t = t;
    in.n = n;
    in.truth[RFE_FL] = truth;
    in.est[RFE_FL] = est;
    in.sd[RFE_FL] = (sd != NULL) ? sd : k_sd1;
    in.valid[RFE_FL] = (valid != NULL) ? valid : k_valid1;
    in.util[RFE_FL] = util;
    return in;
}

/* The old one-series call: error figures of fl. */
static int series1(const double *t, const double *truth, const double *est, size_t n,
                   const rfe_metrics_config_t *cfg, rfe_metric_t *m)
{
    rfe_metrics_input_t in = input1(t, truth, est, NULL, NULL, NULL, n);
    return rfe_metric_series(&in, RFE_FL, cfg, m);
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
/* REQ-MET-001 */
static void test_rfe_metric_series_constant_truth(void **state)
{
    const double t[] = {0.0, 0.5, 1.0, 1.5, 2.0};
    const double truth[] = {0.5, 0.5, 0.5, 0.5, 0.5};
    const double est[] = {0.9, 0.6, 0.52, 0.47, 0.51};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(series1(t, truth, est, 5u, &cfg, &m), 0);
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
/* REQ-MET-001 */
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
    assert_int_equal(series1(t, truth, est, 13u, &cfg, &m), 0);
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
/* REQ-MET-001 */
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
    assert_int_equal(series1(t, truth, est, 13u, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 13);
    assert_near(m.max_abs, 0.5);
    assert_near(m.max_rel, 0.5 / 0.3);
    assert_near(m.t_converge, 0.25);
}

/* Last sample outside the tolerance: never converges (negative). */
/* REQ-MET-001 */
static void test_rfe_metric_series_never_converges(void **state)
{
    const double t[] = {0.0, 1.0, 2.0};
    const double truth[] = {0.4, 0.4, 0.4};
    const double est[] = {0.4, 0.4, 0.5}; /* last error 0.1 > 0.05 */
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(series1(t, truth, est, 3u, &cfg, &m), 0);
    assert_true(m.t_converge < 0.0);
    assert_near(m.max_abs, 0.1);
}

/* Within tolerance from the first sample: converged at once (0 s). */
/* REQ-MET-001 */
static void test_rfe_metric_series_converged_from_start(void **state)
{
    const double t[] = {0.0, 1.0, 2.0};
    const double truth[] = {0.4, 0.4, 0.4};
    const double est[] = {0.42, 0.39, 0.4};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(series1(t, truth, est, 3u, &cfg, &m), 0);
    assert_near(m.t_converge, 0.0);
}

/* A log shorter than settle_start has no settled sample: statistics NaN, count 0. */
/* REQ-MET-001 */
static void test_rfe_metric_series_no_settled_samples(void **state)
{
    const double t[] = {0.0, 0.5};
    const double truth[] = {0.4, 0.4};
    const double est[] = {0.4, 0.4};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(series1(t, truth, est, 2u, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 0);
    assert_true(isnan(m.rmse));
    assert_true(isnan(m.max_abs));
    assert_true(isnan(m.max_rel));
}

/* A NaN estimate must not disappear: RMSE and max become NaN, and it never converges. */
/* REQ-MET-001 */
static void test_rfe_metric_series_nan_estimate(void **state)
{
    const double t[] = {0.0, 1.0, 2.0};
    const double truth[] = {0.4, 0.4, 0.4};
    const double est[] = {0.4, 0.4, (double)NAN};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(series1(t, truth, est, 3u, &cfg, &m), 0);
    assert_true(isnan(m.rmse));
    assert_true(isnan(m.max_abs));
    assert_true(m.t_converge < 0.0);
}

/* Truth <= 0 has no relative error: skipped, NaN when nothing is left. */
/* REQ-MET-001 */
static void test_rfe_metric_series_zero_truth_no_relative_error(void **state)
{
    const double t[] = {1.0, 2.0};
    const double truth[] = {0.0, 0.0};
    const double est[] = {0.01, 0.02};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    cfg.settle_start = 0.0;
    assert_int_equal(series1(t, truth, est, 2u, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 2);
    assert_near(m.max_abs, 0.02);
    assert_true(isnan(m.max_rel));
}

/* REQ-MET-001 */
static void test_rfe_metric_series_rejects_empty_and_null(void **state)
{
    const double x[] = {0.0};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_input_t in = input1(x, x, x, NULL, NULL, NULL, 1u);
    rfe_metric_t m;
    (void)state;
    assert_int_equal(series1(x, x, x, 0u, &cfg, &m), -1);
    assert_int_equal(series1(x, x, x, 1u, NULL, &m), -1);
    assert_int_equal(rfe_metric_series(NULL, RFE_FL, &cfg, &m), -1);
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, NULL), -1);
    assert_int_equal(rfe_metric_series(&in, RFE_METRICS_MEAN + 1u, &cfg, &m), -1);
    assert_int_equal(rfe_metric_series(&in, RFE_FR, &cfg, &m), -1);          /* fr: no columns */
    assert_int_equal(rfe_metric_series(&in, RFE_METRICS_MEAN, &cfg, &m), -1); /* needs all four */
    in.t = NULL;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), -1);
    in = input1(x, x, x, NULL, NULL, NULL, 1u);
    in.sd[RFE_FL] = NULL;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), -1);
    in = input1(x, x, x, NULL, NULL, NULL, 1u);
    in.valid[RFE_FL] = NULL;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), -1);
    in = input1(x, NULL, x, NULL, NULL, NULL, 1u);
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), -1);
    in = input1(x, x, NULL, NULL, NULL, NULL, 1u);
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), -1);
}

/* ------------------------------------------------------------ valid, consistency */

/*
 * Series A (constant truth 0.5, dt = 0.5 s) with valid flags and sd:
 *   k     : 0     1     2      3      4
 *   t     : 0     0.5   1.0    1.5    2.0
 *   error : 0.4   0.1   0.02  -0.03   0.01
 *   valid : 1     1     0      1      1
 *   sd    : 0.1   0.1   0.005  0.02   0.004
 * Settled: k = 2, 3, 4 (n_settled 3).
 *   valid among them: k = 3, 4 -> n_valid 2, frac_valid 2/3,
 *   rmse_valid = sqrt((0.03^2 + 0.01^2)/2) = sqrt(10e-4/2) = sqrt(5e-4).
 *   consistency, k = 2: |e| <= 2 sd?  k2: 0.02 <= 0.01 no; k3: 0.03 <= 0.04 yes;
 *   k4: 0.01 <= 0.008 no -> 1/3. The unsettled k = 0, 1 do not count.
 *   With consistency_k = 3: k2: 0.02 <= 0.015 no; k3 yes; k4: 0.01 <= 0.012 yes -> 2/3.
 *   Among the valid k = 3, 4: max_abs_valid 0.03 (the larger error k = 0 is not settled, k = 2
 *   not valid); consistency_valid 1/2 (k3 yes, k4 no), with consistency_k = 3: 2/2.
 */
/* REQ-MET-001 */
static void test_rfe_metric_series_valid_and_consistency(void **state)
{
    const double t[] = {0.0, 0.5, 1.0, 1.5, 2.0};
    const double truth[] = {0.5, 0.5, 0.5, 0.5, 0.5};
    const double est[] = {0.9, 0.6, 0.52, 0.47, 0.51};
    const double sd[] = {0.1, 0.1, 0.005, 0.02, 0.004};
    const unsigned char valid[] = {1, 1, 0, 1, 1};
    rfe_metrics_input_t in = input1(t, truth, est, sd, valid, NULL, 5u);
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_near(cfg.consistency_k, 2.0);
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 3);
    assert_int_equal(m.n_valid, 2);
    assert_near(m.frac_valid, 2.0 / 3.0);
    assert_near(m.rmse_valid, sqrt(5e-4));
    assert_near(m.rmse, sqrt(14e-4 / 3.0)); /* unchanged: all settled samples */
    assert_near(m.consistency, 1.0 / 3.0);
    assert_near(m.max_abs_valid, 0.03);
    assert_near(m.consistency_valid, 0.5);
    cfg.consistency_k = 3.0;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), 0);
    assert_near(m.consistency, 2.0 / 3.0);
    assert_near(m.consistency_valid, 1.0);
}

/*
 * Edges of the definitions (settle_start 0, every sample settled, truth 0.5):
 *   est   : 0.75   0.5    0.5   0.625
 *   error : 0.25   0      0     0.125      (exact binary fractions)
 *   sd    : 0.125  0      NaN   0.0625
 *   valid : 0      0      0     0
 * consistency (k = 2): 0.25 <= 0.25 yes (the bound is inclusive); 0 <= 0 yes; NaN sd no;
 *   0.125 <= 0.125 yes -> 3/4. No valid sample: n_valid 0, frac_valid 0, rmse_valid NaN.
 */
/* REQ-MET-001 */
static void test_rfe_metric_series_consistency_bound_and_no_valid(void **state)
{
    const double t[] = {0.0, 1.0, 2.0, 3.0};
    const double truth[] = {0.5, 0.5, 0.5, 0.5};
    const double est[] = {0.75, 0.5, 0.5, 0.625};
    const double sd[] = {0.125, 0.0, (double)NAN, 0.0625};
    const unsigned char valid[] = {0, 0, 0, 0};
    rfe_metrics_input_t in = input1(t, truth, est, sd, valid, NULL, 4u);
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    cfg.settle_start = 0.0;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 4);
    assert_near(m.consistency, 0.75);
    assert_int_equal(m.n_valid, 0);
    assert_near(m.frac_valid, 0.0);
    assert_true(isnan(m.rmse_valid));
    assert_true(isnan(m.max_abs_valid));     /* no worst case without a valid sample */
    assert_true(isnan(m.consistency_valid));
}

/* No settled sample: the shares are undefined (NaN), not 0. */
/* REQ-MET-001 */
static void test_rfe_metric_series_no_settled_shares_nan(void **state)
{
    const double t[] = {0.0, 0.5};
    const double truth[] = {0.4, 0.4};
    rfe_metric_t m;
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    (void)state;
    assert_int_equal(series1(t, truth, truth, 2u, &cfg, &m), 0);
    assert_int_equal(m.n_valid, 0);
    assert_true(isnan(m.frac_valid));
    assert_true(isnan(m.consistency));
    assert_true(isnan(m.rmse_valid));
}

/* ------------------------------------------------------------ re-convergence */

/*
 * Two truth changes, dt = 0.25 s, 13 samples (tol 0.05):
 *   k     : 0-3   4    5    6     7     8     9     10    11   12
 *   t     : 0-.75 1.0  1.25 1.5   1.75  2.0   2.25  2.5   2.75 3.0
 *   truth : 0.8   0.3  0.3  0.3   0.3   0.3   0.6   0.6   0.6  0.6
 *   est   : 0.8   0.8  0.4  0.32  0.36  0.31  0.3   0.64  0.6  0.61
 *   error : 0     .5   .1   .02   .06   .01   -.3   .04   0    .01
 * Changes at k = 4 and k = 9 (n_changes 2).
 *   Segment k = 4..8: last outside k = 7 (0.06) -> t[8] - t[4] = 2.0 - 1.0 = 1.0 s.
 *   Segment k = 9..12: last outside k = 9 -> t[10] - t[9] = 0.25 s.
 *   reconverge = max = 1.0 s, n_reconverged 2. (t_converge, from the last change: 0.25 s.)
 * Variant: est[8] = 0.36 (error .06): segment 1 ends outside -> it never re-converges:
 *   n_reconverged 1, reconverge NaN (the max is undefined); t_converge still 0.25 s.
 */
/* REQ-MET-001 */
static void test_rfe_metric_series_reconverge_two_changes(void **state)
{
    double t[13];
    const double truth[13] = {0.8, 0.8, 0.8, 0.8, 0.3, 0.3, 0.3, 0.3, 0.3, 0.6, 0.6, 0.6, 0.6};
    double est[13] = {0.8, 0.8, 0.8, 0.8, 0.8, 0.4, 0.32, 0.36, 0.31, 0.3, 0.64, 0.6, 0.61};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    size_t k;
    (void)state;
    for (k = 0u; k < 13u; ++k) {
        t[k] = 0.25 * (double)k;
    }
    assert_int_equal(series1(t, truth, est, 13u, &cfg, &m), 0);
    assert_int_equal(m.n_changes, 2);
    assert_int_equal(m.n_reconverged, 2);
    assert_near(m.reconverge, 1.0);
    assert_near(m.t_converge, 0.25);
    est[8] = 0.36;
    assert_int_equal(series1(t, truth, est, 13u, &cfg, &m), 0);
    assert_int_equal(m.n_changes, 2);
    assert_int_equal(m.n_reconverged, 1);
    assert_true(isnan(m.reconverge));
    assert_near(m.t_converge, 0.25);
}

/*
 * One change (k = 2), estimate inside the tolerance from the change on: re-converged at once
 * (0 s). With converge_tol = 0.005 the error 0.01 at the end is outside: never (NaN), which
 * shows the knob is used. Without a change (constant truth): n_changes 0, reconverge NaN.
 *   t     : 0    1    2    3    4
 *   truth : 0.4  0.4  0.6  0.6  0.6
 *   est   : 0.4  0.4  0.6  0.59 0.61   errors 0 0 0 -0.01 0.01
 */
/* REQ-MET-001 */
static void test_rfe_metric_series_reconverge_at_once_never_and_no_change(void **state)
{
    const double t[] = {0.0, 1.0, 2.0, 3.0, 4.0};
    const double truth[] = {0.4, 0.4, 0.6, 0.6, 0.6};
    const double est[] = {0.4, 0.4, 0.6, 0.59, 0.61};
    const double flat[] = {0.6, 0.6, 0.6, 0.6, 0.6};
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_int_equal(series1(t, truth, est, 5u, &cfg, &m), 0);
    assert_int_equal(m.n_changes, 1);
    assert_int_equal(m.n_reconverged, 1);
    assert_near(m.reconverge, 0.0);
    cfg.converge_tol = 0.005;
    assert_int_equal(series1(t, truth, est, 5u, &cfg, &m), 0);
    assert_int_equal(m.n_changes, 1);
    assert_int_equal(m.n_reconverged, 0);
    assert_true(isnan(m.reconverge));
    cfg = rfe_metrics_config_default();
    assert_int_equal(series1(t, flat, est, 5u, &cfg, &m), 0);
    assert_int_equal(m.n_changes, 0);
    assert_int_equal(m.n_reconverged, 0);
    assert_true(isnan(m.reconverge));
}

/* ------------------------------------------------------------ excitation */

/*
 * One wheel with util (settle_start 0, every sample settled; excite_util 0.5):
 *   k     : 0     1     2     3     4
 *   util  : 0.7   0.5   0.49  0.9   NaN
 *   valid : 1     0     1     1     1
 *   error : 0.02  0.3   0.1  -0.04  0
 * Excited (util >= 0.5; NaN is not): k = 0, 1, 3 -> n_excited 3; valid among them k = 0, 3
 *   -> frac_valid_excited 2/3, rmse_excited_valid = sqrt((4e-4 + 16e-4)/2) = sqrt(1e-3).
 * With excite_util = 0.95 nothing is excited: n_excited 0, both figures NaN.
 * Without util columns the figures are not defined: has_util 0.
 */
/* REQ-MET-001 */
static void test_rfe_metric_series_excited(void **state)
{
    const double t[] = {0.0, 1.0, 2.0, 3.0, 4.0};
    const double truth[] = {0.5, 0.5, 0.5, 0.5, 0.5};
    const double est[] = {0.52, 0.8, 0.6, 0.46, 0.5};
    const double util[] = {0.7, 0.5, 0.49, 0.9, (double)NAN};
    const unsigned char valid[] = {1, 0, 1, 1, 1};
    rfe_metrics_input_t in = input1(t, truth, est, NULL, valid, util, 5u);
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metric_t m;
    (void)state;
    assert_near(cfg.excite_util, 0.5);
    cfg.settle_start = 0.0;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), 0);
    assert_int_equal(m.has_util, 1);
    assert_int_equal(m.n_settled, 5);
    assert_int_equal(m.n_excited, 3);
    assert_near(m.frac_valid_excited, 2.0 / 3.0);
    assert_near(m.rmse_excited_valid, sqrt(1e-3));
    cfg.excite_util = 0.95;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), 0);
    assert_int_equal(m.n_excited, 0);
    assert_true(isnan(m.frac_valid_excited));
    assert_true(isnan(m.rmse_excited_valid));
    in.util[RFE_FL] = NULL;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), 0);
    assert_int_equal(m.has_util, 0);
    assert_int_equal(m.n_excited, 0);
}

/* Excited samples before settling do not count (the figures are over settled samples). */
/* REQ-MET-001 */
static void test_rfe_metric_series_excited_only_settled(void **state)
{
    const double t[] = {0.0, 0.5, 1.0};
    const double truth[] = {0.5, 0.5, 0.5};
    const double util[] = {0.9, 0.9, 0.1};
    rfe_metrics_input_t in = input1(t, truth, truth, NULL, NULL, util, 3u);
    rfe_metrics_config_t cfg = rfe_metrics_config_default(); /* settled: t >= 1.0 */
    rfe_metric_t m;
    (void)state;
    assert_int_equal(rfe_metric_series(&in, RFE_FL, &cfg, &m), 0);
    assert_int_equal(m.n_settled, 1);
    assert_int_equal(m.n_excited, 0);
    assert_true(isnan(m.frac_valid_excited));
}

/* ------------------------------------------------------------ four wheels and the mean */

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
/* REQ-MET-001 */
static void test_rfe_metrics_compute_wheels_and_mean(void **state)
{
    const double t[6] = {0.0, 0.5, 1.0, 1.5, 2.0, 2.5};
    const double tfl[6] = {0.4, 0.4, 0.4, 0.8, 0.8, 0.8};
    const double efl[6] = {0.4, 0.4, 0.42, 0.5, 0.7, 0.8};
    const double c04[6] = {0.4, 0.4, 0.4, 0.4, 0.4, 0.4};
    rfe_metrics_input_t in;
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    size_t w;
    (void)state;
    memset(&in, 0, sizeof in);
    in.t = t;
    in.n = 6u;
    for (w = 0u; w < RFE_WHEELS; ++w) {
        in.truth[w] = (w == RFE_FL) ? tfl : c04;
        in.est[w] = (w == RFE_FL) ? efl : c04;
        in.sd[w] = k_sd1;
        in.valid[w] = k_valid1;
    }
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
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

/*
 * The mean series' own definitions (settle_start 0, constant truth 0.5, dt = 1 s):
 *   k              : 0     1      2      3
 *   est fl         : 0.5   0.6    0.54   0.5    (fr, rl, rr: 0.5, error 0)
 *   err fl         : 0     0.1    0.04   0
 *   mean err       : 0     0.025  0.01   0
 *   sd (all four)  : 0.05  0.02   0.03   0.05
 *   sd_mean = sqrt(4 sd^2)/4 = sd/2 : 0.025 0.01 0.015 0.025
 *   valid fl       : 1     1      1      0
 *   valid fr       : 1     0      1      1      (rl, rr: always 1)
 *   util fl        : 0.6   0.1    0.1    0.1
 *   util fr        : 0.1   0.5    0.1    0.1
 *   util rl        : 0.1   0.1    0.1    0.1
 *   util rr        : 0.1   0.1    0.1    0.49
 * consistency (k = 2):
 *   fl: |e| <= 2 sd: 0<=0.1 y, 0.1<=0.04 n, 0.04<=0.06 y, 0<=0.1 y -> 3/4.
 *   mean: |e| <= 2 sd_mean: 0<=0.05 y, 0.025<=0.02 n, 0.01<=0.03 y, 0<=0.05 y -> 3/4.
 *   (With the mean of the four sd instead, k = 1 would pass: 0.025 <= 0.04 -> 4/4; the
 *   figure distinguishes the two definitions.)
 * valid: fl k = 0, 1, 2 -> n_valid 3, rmse_valid = sqrt((0 + 0.01 + 0.0016)/3);
 *   mean (all four valid): k = 0, 2 -> n_valid 2, frac 1/2, rmse_valid = sqrt(1e-4/2).
 * excited (util >= 0.5): fl k = 0; fr k = 1 (inclusive); rl none; rr none (0.49).
 *   fl: n_excited 1, valid -> frac 1, rmse_excited_valid = 0 (error 0 at k = 0).
 *   fr: n_excited 1, fr invalid at k = 1 -> frac 0, rmse_excited_valid NaN.
 *   rl: n_excited 0 -> both NaN.
 *   mean (any wheel excited): k = 0, 1 -> n_excited 2; all valid only at k = 0 -> frac 1/2,
 *   rmse_excited_valid = 0.
 *   excite_util = 0.45: rr's 0.49 counts, mean excited k = 0, 1, 3 (fl invalid at 3) -> 1/3.
 */
/* REQ-MET-001 */
static void test_rfe_metrics_compute_mean_valid_consistency_excited(void **state)
{
    const double t[4] = {0.0, 1.0, 2.0, 3.0};
    const double truth[4] = {0.5, 0.5, 0.5, 0.5};
    const double efl[4] = {0.5, 0.6, 0.54, 0.5};
    const double sd[4] = {0.05, 0.02, 0.03, 0.05};
    const unsigned char vfl[4] = {1, 1, 1, 0};
    const unsigned char vfr[4] = {1, 0, 1, 1};
    const unsigned char v1[4] = {1, 1, 1, 1};
    const double ufl[4] = {0.6, 0.1, 0.1, 0.1};
    const double ufr[4] = {0.1, 0.5, 0.1, 0.1};
    const double url[4] = {0.1, 0.1, 0.1, 0.1};
    const double urr[4] = {0.1, 0.1, 0.1, 0.49};
    rfe_metrics_input_t in;
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    size_t w;
    (void)state;
    memset(&in, 0, sizeof in);
    in.t = t;
    in.n = 4u;
    for (w = 0u; w < RFE_WHEELS; ++w) {
        in.truth[w] = truth;
        in.est[w] = (w == RFE_FL) ? efl : truth;
        in.sd[w] = sd;
        in.valid[w] = (w == RFE_FL) ? vfl : ((w == RFE_FR) ? vfr : v1);
    }
    in.util[RFE_FL] = ufl;
    in.util[RFE_FR] = ufr;
    in.util[RFE_RL] = url;
    in.util[RFE_RR] = urr;
    cfg.settle_start = 0.0;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
    assert_near(m.wheel[RFE_FL].consistency, 0.75);
    assert_near(m.mean.consistency, 0.75);
    assert_near(m.wheel[RFE_FR].consistency, 1.0);
    assert_int_equal(m.wheel[RFE_FL].n_valid, 3);
    assert_near(m.wheel[RFE_FL].rmse_valid, sqrt(0.0116 / 3.0));
    assert_int_equal(m.mean.n_valid, 2);
    assert_near(m.mean.frac_valid, 0.5);
    assert_near(m.mean.rmse_valid, sqrt(1e-4 / 2.0));
    assert_int_equal(m.wheel[RFE_FL].n_excited, 1);
    assert_near(m.wheel[RFE_FL].frac_valid_excited, 1.0);
    assert_near(m.wheel[RFE_FL].rmse_excited_valid, 0.0);
    assert_int_equal(m.wheel[RFE_FR].n_excited, 1);
    assert_near(m.wheel[RFE_FR].frac_valid_excited, 0.0);
    assert_true(isnan(m.wheel[RFE_FR].rmse_excited_valid));
    assert_int_equal(m.wheel[RFE_RL].n_excited, 0);
    assert_true(isnan(m.wheel[RFE_RL].frac_valid_excited));
    assert_int_equal(m.mean.has_util, 1);
    assert_int_equal(m.mean.n_excited, 2);
    assert_near(m.mean.frac_valid_excited, 0.5);
    assert_near(m.mean.rmse_excited_valid, 0.0);
    cfg.excite_util = 0.45;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
    assert_int_equal(m.mean.n_excited, 3);
    assert_near(m.mean.frac_valid_excited, 1.0 / 3.0);
    assert_int_equal(m.wheel[RFE_RR].n_excited, 1);
}

/*
 * Re-convergence of the mean: a change of any wheel's truth is a change of the mean.
 * dt = 1 s; fl steps 0.4 -> 0.8 at k = 2, rl at k = 4; fr, rr 0.4 with perfect estimates.
 *   k         : 0    1    2     3     4     5
 *   truth fl  : 0.4  0.4  0.8   0.8   0.8   0.8
 *   est fl    : 0.4  0.4  0.4   0.8   0.8   0.8     err fl: 0 0 -0.4 0 0 0
 *   truth rl  : 0.4  0.4  0.4   0.4   0.8   0.8
 *   est rl    = truth rl                              err rl: 0
 *   mean err  : 0    0    -0.1  0     0     0
 * fl: one change (k = 2), segment k = 2..5, last outside k = 2 -> t[3] - t[2] = 1 s.
 * rl: one change (k = 4), inside from the change on -> 0 s.  fr: no change -> NaN.
 * mean: changes at k = 2 and 4 (n_changes 2). Segment 2..3: last outside k = 2 -> 1 s;
 *   segment 4..5: 0 s. reconverge = 1 s.
 * Variant est fl[3] = 0.5 (err fl -0.3, mean err -0.075): fl's segment 2..5 has its last
 *   outside at k = 3 -> t[4] - t[2] = 2 s; the mean's segment 2..3 ends outside -> never:
 *   n_reconverged 1 of 2, reconverge NaN.
 */
/* REQ-MET-001 */
static void test_rfe_metrics_compute_mean_reconverge_any_wheel_change(void **state)
{
    const double t[6] = {0.0, 1.0, 2.0, 3.0, 4.0, 5.0};
    const double tfl[6] = {0.4, 0.4, 0.8, 0.8, 0.8, 0.8};
    double efl[6] = {0.4, 0.4, 0.4, 0.8, 0.8, 0.8};
    const double trl[6] = {0.4, 0.4, 0.4, 0.4, 0.8, 0.8};
    const double c04[6] = {0.4, 0.4, 0.4, 0.4, 0.4, 0.4};
    rfe_metrics_input_t in;
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    size_t w;
    (void)state;
    memset(&in, 0, sizeof in);
    in.t = t;
    in.n = 6u;
    for (w = 0u; w < RFE_WHEELS; ++w) {
        in.truth[w] = c04;
        in.est[w] = c04;
        in.sd[w] = k_sd1;
        in.valid[w] = k_valid1;
    }
    in.truth[RFE_FL] = tfl;
    in.est[RFE_FL] = efl;
    in.truth[RFE_RL] = trl;
    in.est[RFE_RL] = trl;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
    assert_int_equal(m.wheel[RFE_FL].n_changes, 1);
    assert_near(m.wheel[RFE_FL].reconverge, 1.0);
    assert_int_equal(m.wheel[RFE_RL].n_changes, 1);
    assert_near(m.wheel[RFE_RL].reconverge, 0.0);
    assert_int_equal(m.wheel[RFE_FR].n_changes, 0);
    assert_true(isnan(m.wheel[RFE_FR].reconverge));
    assert_int_equal(m.mean.n_changes, 2);
    assert_int_equal(m.mean.n_reconverged, 2);
    assert_near(m.mean.reconverge, 1.0);
    efl[3] = 0.5;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
    assert_near(m.wheel[RFE_FL].reconverge, 2.0);
    assert_int_equal(m.mean.n_changes, 2);
    assert_int_equal(m.mean.n_reconverged, 1);
    assert_true(isnan(m.mean.reconverge));
}

/* REQ-MET-001 */
static void test_rfe_metrics_compute_rejects_bad_input(void **state)
{
    const double x[1] = {0.0};
    const unsigned char v[1] = {1};
    rfe_metrics_input_t in;
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    size_t w;
    (void)state;
    memset(&in, 0, sizeof in);
    in.t = x;
    in.n = 1u;
    for (w = 0u; w < RFE_WHEELS; ++w) {
        in.truth[w] = x;
        in.est[w] = x;
        in.sd[w] = x;
        in.valid[w] = v;
    }
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
    assert_int_equal(rfe_metrics_compute(NULL, &cfg, &m), -1);
    assert_int_equal(rfe_metrics_compute(&in, NULL, &m), -1);
    assert_int_equal(rfe_metrics_compute(&in, &cfg, NULL), -1);
    in.util[RFE_FL] = x; /* util of only some wheels: all or none */
    in.util[RFE_FR] = x;
    in.util[RFE_RL] = x;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), -1);
    in.util[RFE_RR] = x;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
    in.valid[RFE_RR] = NULL;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), -1);
    in.valid[RFE_RR] = v;
    in.n = 0u;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), -1);
}

/* ------------------------------------------------------------ output */

/* Writes @p m through a memory stream (JSON or table); returns the text (free it). */
static char *render(const rfe_metrics_t *m, int json)
{
    char *buf = NULL;
    size_t len = 0u;
    FILE *f = open_memstream(&buf, &len);
    assert_non_null(f);
    if (json) {
        rfe_metrics_write_json(f, m, 0);
    } else {
        rfe_metrics_print_table(f, m);
    }
    fclose(f);
    return buf;
}

/* JSON: numbers where defined, null for NaN, "never" and absent util. Table: "n/a",
 * "never", "-" (no change). */
/* REQ-MET-002 */
static void test_rfe_metrics_write_json_and_table(void **state)
{
    const double t[3] = {0.0, 1.0, 2.0};
    const double tr[3] = {0.4, 0.4, 0.4};
    const double ok[3] = {0.4, 0.4, 0.41};
    const double bad[3] = {0.4, 0.4, 0.6};
    const double sd[3] = {0.1, 0.1, 0.1};
    const unsigned char v[3] = {1, 1, 0};
    rfe_metrics_input_t in;
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    char *buf;
    size_t w;
    (void)state;
    memset(&in, 0, sizeof in);
    in.t = t;
    in.n = 3u;
    for (w = 0u; w < RFE_WHEELS; ++w) {
        in.truth[w] = tr;
        in.est[w] = (w == RFE_FR) ? bad : ok;
        in.sd[w] = sd;
        in.valid[w] = v;
    }
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
    m.wheel[RFE_RR].n_settled = 0u; /* pretend: undefined statistics */
    m.wheel[RFE_RR].rmse = (double)NAN;
    m.wheel[RFE_RR].max_rel = (double)NAN;
    buf = render(&m, 1);
    assert_non_null(strstr(buf, "\"converge_tol\": 0.05"));
    assert_non_null(strstr(buf, "\"consistency_k\": 2, \"excite_util\": 0.5}"));
    assert_non_null(strstr(buf, "\"fl\": {\"n_settled\": 2, \"rmse\": "));
    assert_non_null(strstr(buf, "\"fr\": {\"n_settled\": 2, \"rmse\": "));
    assert_non_null(strstr(buf, "\"t_converge_s\": null, ")); /* fr never converges */
    assert_non_null(strstr(buf, "\"rr\": {\"n_settled\": 0, \"rmse\": null"));
    /* fl: settled k = 1, 2; valid only k = 1 (error 0: worst case 0, consistent); consistent
     * both (0.01 <= 0.2). */
    assert_non_null(strstr(buf, "\"n_valid\": 1, \"rmse_valid\": 0, \"max_abs_err_valid\": 0, "
                                "\"frac_valid\": 0.5, \"consistency\": 1, "
                                "\"consistency_valid\": 1, \"n_changes\": 0, \"n_reconverged\": 0, "
                                "\"reconverge_s\": null, \"n_excited\": null, "
                                "\"frac_valid_excited\": null, \"rmse_excited_valid\": null}"));
    assert_non_null(strstr(buf, "\"mean\": {"));
    assert_int_equal(buf[strlen(buf) - 1u], '}');
    free(buf);
    buf = render(&m, 0);
    assert_non_null(strstr(buf, "never"));
    assert_non_null(strstr(buf, "n/a"));
    assert_non_null(strstr(buf, "\nwheel "));
    assert_non_null(strstr(buf, "rmse_v"));
    assert_non_null(strstr(buf, "cons%"));
    assert_non_null(strstr(buf, "reconv"));
    assert_null(strstr(buf, "exc_val")); /* no util columns: no excitation column */
    assert_non_null(strstr(buf, "\nmean "));
    free(buf);
}

/* With util: JSON has numbers for the excitation keys, the table the exc_val column. A
 * change that never re-converges prints "never" in reconv. */
/* REQ-MET-002 */
static void test_rfe_metrics_write_json_and_table_with_util(void **state)
{
    const double t[3] = {0.0, 1.0, 2.0};
    const double tr[3] = {0.4, 0.4, 0.8};
    const double est[3] = {0.4, 0.4, 0.4};
    const double sd[3] = {0.1, 0.1, 0.1};
    const unsigned char v[3] = {1, 1, 1};
    const double util[3] = {0.9, 0.9, 0.9};
    rfe_metrics_input_t in;
    rfe_metrics_config_t cfg = rfe_metrics_config_default();
    rfe_metrics_t m;
    char *buf;
    size_t w;
    (void)state;
    memset(&in, 0, sizeof in);
    in.t = t;
    in.n = 3u;
    for (w = 0u; w < RFE_WHEELS; ++w) {
        in.truth[w] = tr;
        in.est[w] = est;
        in.sd[w] = sd;
        in.valid[w] = v;
        in.util[w] = util;
    }
    cfg.settle_start = 0.0;
    cfg.settle_after_change = 0.0;
    assert_int_equal(rfe_metrics_compute(&in, &cfg, &m), 0);
    buf = render(&m, 1);
    /* Every sample settled and excited and valid; errors 0, 0, -0.4. */
    assert_non_null(strstr(buf, "\"n_changes\": 1, \"n_reconverged\": 0, \"reconverge_s\": null, "
                                "\"n_excited\": 3, \"frac_valid_excited\": 1, "
                                "\"rmse_excited_valid\": "));
    free(buf);
    buf = render(&m, 0);
    assert_non_null(strstr(buf, "exc_val"));
    assert_non_null(strstr(buf, "util >= 0.5"));
    assert_non_null(strstr(buf, "  never"));
    assert_non_null(strstr(buf, "100.0%"));
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
        cmocka_unit_test(test_rfe_metric_series_valid_and_consistency),
        cmocka_unit_test(test_rfe_metric_series_consistency_bound_and_no_valid),
        cmocka_unit_test(test_rfe_metric_series_no_settled_shares_nan),
        cmocka_unit_test(test_rfe_metric_series_reconverge_two_changes),
        cmocka_unit_test(test_rfe_metric_series_reconverge_at_once_never_and_no_change),
        cmocka_unit_test(test_rfe_metric_series_excited),
        cmocka_unit_test(test_rfe_metric_series_excited_only_settled),
        cmocka_unit_test(test_rfe_metrics_compute_wheels_and_mean),
        cmocka_unit_test(test_rfe_metrics_compute_mean_valid_consistency_excited),
        cmocka_unit_test(test_rfe_metrics_compute_mean_reconverge_any_wheel_change),
        cmocka_unit_test(test_rfe_metrics_compute_rejects_bad_input),
        cmocka_unit_test(test_rfe_metrics_write_json_and_table),
        cmocka_unit_test(test_rfe_metrics_write_json_and_table_with_util),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
