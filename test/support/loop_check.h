/**
 * @file loop_check.h
 * @brief The friction loop's closed-loop checks (OBSERVER.md §6 "The loop"), shared by the
 *        float/double and the fixed-point tests of the composed pipeline
 *        (test/estimators/pipeline/test_pipeline_loop_*.c): the log of a friction step while
 *        cornering (scenarios/observer_loop/, make observer-loop-scenarios), its truth
 *        columns, and the figures the tests bound, computed in double from the estimates the
 *        run hands over (converted from its number type). Include after test_common.h.
 */
#ifndef RFE_TEST_LOOP_CHECK_H
#define RFE_TEST_LOOP_CHECK_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "csv_log.h"
#include "table.h"

#define LOOP_DIR "scenarios/observer_loop"
#define LOOP_MAX_ROWS 4000u /* the 30 s log at 0.01 s: 3001 rows */

/* Accuracy targets of issue 16 (OBSERVER_RESULTS.md): beta within 0.3 deg while
 * |ay| < 0.5 mu g (this turn: 4.0 m/s^2 < 4.4 on mu 0.9), within 1.0 deg at the limit. */
#define LOOP_BETA_LIN_DEG 0.3
#define LOOP_BETA_LIMIT_DEG 1.0
/* The re-convergence time this test requires after the step back to high friction: 3 s,
 * about 46 m of road at 15.5 m/s (a stated requirement, not a fit: measured 1.8 s) */
#define LOOP_T_CONV 3.0

/* The truth and the estimates of one run, and the friction steps (from the mu_* truth). */
typedef struct {
    size_t n;
    double t[LOOP_MAX_ROWS];
    double vx_true[LOOP_MAX_ROWS];
    double vy_true[LOOP_MAX_ROWS];
    double beta_true[LOOP_MAX_ROWS];
    double vy[LOOP_MAX_ROWS];
    double beta[LOOP_MAX_ROWS];
    double sd_vy[LOOP_MAX_ROWS];
    double sd_beta[LOOP_MAX_ROWS];
    double mu_mean[LOOP_MAX_ROWS]; /* the four wheels' true friction, averaged */
    double t_down; /* the first sample with a wheel on the low friction */
    double t_up;   /* the first sample after it with every wheel back on the high one */
} loop_run_t;

/* What the tests bound. */
typedef struct {
    double max_vy;        /* max |vy estimate| [m/s] */
    double vy_bound;      /* max |vy_true| + max vx_true tan(0.3 deg) [m/s] */
    double max_sd_vy;     /* max sd(vy) [m/s] */
    double min_sd_vy;     /* min sd(vy) [m/s] */
    double max_err_deg;   /* max |beta error| [deg] */
    double rms_err_deg;   /* RMS beta error [deg] */
    double max_err_low;   /* max |beta error| on the low friction [deg] */
    double t_settle;      /* after t_up, the time of the last |beta error| > 0.3 deg, from
                             t_up [s] (0 when none) */
    double end_err_deg;   /* mean |beta error| over the last second [deg] */
    int finite;           /* every estimate and sd finite */
} loop_stats_t;

/* Reads the log @p name of LOOP_DIR and its truth columns into @p r (estimates zeroed). */
static inline void loop_read(const char *name, rfe_sensor_log_t *log, loop_run_t *r)
{
    char path[512];
    rfe_io_error_t err;
    test_table_t tab;
    size_t k;
    int up = 0;
    memset(log, 0, sizeof(*log));
    memset(&tab, 0, sizeof(tab));
    memset(r, 0, sizeof(*r));
    snprintf(path, sizeof(path), "%s/%s", LOOP_DIR, name);
    assert_int_equal(rfe_sensor_log_read(path, log, &err), 0);
    assert_int_equal(test_table_load(path, &tab), 0);
    assert_true(log->has_truth);
    assert_int_equal(tab.n_rows, log->n_rows);
    assert_true(log->n_rows <= LOOP_MAX_ROWS);
    r->n = log->n_rows;
    r->t_down = -1.0;
    r->t_up = -1.0;
    for (k = 0u; k < r->n; ++k) {
        const rfe_sensor_row_t *row = &log->rows[k];
        const double mu_max = fmax(fmax(row->mu_true[0], row->mu_true[1]),
                                   fmax(row->mu_true[2], row->mu_true[3]));
        const double mu_min = fmin(fmin(row->mu_true[0], row->mu_true[1]),
                                   fmin(row->mu_true[2], row->mu_true[3]));
        r->t[k] = row->t;
        r->vx_true[k] = test_table_get(&tab, k, "vx_true");
        r->vy_true[k] = test_table_get(&tab, k, "vy_true");
        r->beta_true[k] = test_table_get(&tab, k, "beta_true");
        r->mu_mean[k] = 0.25 * (((row->mu_true[0] + row->mu_true[1]) + row->mu_true[2]) +
                                row->mu_true[3]);
        if ((r->t_down < 0.0) && (mu_min < log->rows[0].mu_true[0])) {
            r->t_down = row->t;
        }
        if ((r->t_down >= 0.0) && (up == 0) && (mu_max < log->rows[0].mu_true[0])) {
            up = 1; /* every wheel on the low friction: the step up comes after */
        }
        if ((up == 1) && (r->t_up < 0.0) && (mu_min >= log->rows[0].mu_true[0])) {
            r->t_up = row->t;
        }
    }
    assert_true((r->t_down > 0.0) && (r->t_up > r->t_down)); /* the log has both steps */
    test_table_free(&tab);
}

static inline double loop_deg(double rad) { return rad * (180.0 / 3.14159265358979323846); }

static inline loop_stats_t loop_stats(const loop_run_t *r)
{
    loop_stats_t s;
    double max_vy_true = 0.0;
    double max_vx = 0.0;
    double sum2 = 0.0;
    double end_sum = 0.0;
    size_t end_n = 0u;
    size_t k;
    memset(&s, 0, sizeof(s));
    s.min_sd_vy = HUGE_VAL;
    s.finite = 1;
    for (k = 0u; k < r->n; ++k) {
        const double e = fabs(loop_deg(r->beta[k] - r->beta_true[k]));
        if (!(isfinite(r->vy[k]) && isfinite(r->beta[k]) && isfinite(r->sd_vy[k]) &&
              isfinite(r->sd_beta[k]))) {
            s.finite = 0;
        }
        max_vy_true = fmax(max_vy_true, fabs(r->vy_true[k]));
        max_vx = fmax(max_vx, r->vx_true[k]);
        s.max_vy = fmax(s.max_vy, fabs(r->vy[k]));
        s.max_sd_vy = fmax(s.max_sd_vy, r->sd_vy[k]);
        s.min_sd_vy = fmin(s.min_sd_vy, r->sd_vy[k]);
        s.max_err_deg = fmax(s.max_err_deg, e);
        sum2 += e * e;
        if ((r->t[k] >= r->t_down) && (r->t[k] < r->t_up)) {
            s.max_err_low = fmax(s.max_err_low, e);
        }
        if ((r->t[k] >= r->t_up) && (e > LOOP_BETA_LIN_DEG)) {
            s.t_settle = r->t[k] - r->t_up;
        }
        if (r->t[k] > r->t[r->n - 1u] - 1.0) {
            end_sum += e;
            ++end_n;
        }
    }
    s.vy_bound = max_vy_true + max_vx * tan(LOOP_BETA_LIN_DEG * 3.14159265358979323846 / 180.0);
    s.rms_err_deg = sqrt(sum2 / (double)r->n);
    s.end_err_deg = end_sum / (double)end_n;
    return s;
}

/* The mu 0.5 phase of OBSERVER_RESULTS.md "Honest on an unobserved friction" (the study's
 * mask: the wheels' mean true friction below 0.7, between the log's 0.5 and 0.9, and vx_true
 * >= 3 m/s): the share of its samples with |beta error| > 2 sd(beta); @p n: their count. */
static inline double loop_low_beyond_2sd(const loop_run_t *r, size_t *n)
{
    size_t k;
    size_t out = 0u;
    *n = 0u;
    for (k = 0u; k < r->n; ++k) {
        if ((r->mu_mean[k] < 0.7) && (r->vx_true[k] >= 3.0)) {
            ++*n;
            if (fabs(r->beta[k] - r->beta_true[k]) > 2.0 * r->sd_beta[k]) {
                ++out;
            }
        }
    }
    return (*n > 0u) ? (double)out / (double)*n : 0.0;
}

/* A consistent Gaussian estimate leaves 4.55 % of its samples beyond 2 sd (2 (1 - Phi(2))):
 * the most a consistent sd(beta) may leave (the study measured 0 % at obs_vy_out_floor_mu
 * 4; without the floor 100 %). */
#define LOOP_GAUSS_BEYOND_2SD 0.0455

/* After a run_floor of the twins (floor off and at @p k_floor side by side): @p floored samples
 * had a reported sd(vy) above the filter's. On, the floor must have acted (so the run's
 * comparisons could fail); off, the reported sd is the filter's, bit for bit. */
static inline void loop_assert_floor_count(double k_floor, size_t floored)
{
    if (k_floor > 0.0) {
        assert_true(floored > 0u);
    } else {
        assert_int_equal(floored, 0u);
    }
}

/* REQ-OBS-025 on the Dugoff truth's mu 0.5 phase, for a twin's @p run_floor: without the
 * floor more than 90 % of the samples beyond 2 sd(beta) (measured 100 %, so the check can
 * fail), with obs_vy_out_floor_mu 4 at most a consistent Gaussian's LOOP_GAUSS_BEYOND_2SD.
 * @p tag prefixes the printed shares. */
static inline void loop_assert_floor_honest(void (*run_floor)(const char *, double, loop_run_t *),
                                            loop_run_t *r, const char *tag)
{
    size_t n;
    double beyond;
    run_floor("turn_mu_step.csv", 0.0, r);
    beyond = loop_low_beyond_2sd(r, &n);
    printf("%sobs_vy_out_floor_mu 0: %.1f %% of %zu samples beyond 2 sd(beta)\n", tag,
           100.0 * beyond, n);
    assert_true(n > 500u); /* the phase is 10 s at 100 Hz */
    assert_true(beyond > 0.9);
    run_floor("turn_mu_step.csv", 4.0, r);
    beyond = loop_low_beyond_2sd(r, &n);
    printf("%sobs_vy_out_floor_mu 4: %.1f %% of %zu samples beyond 2 sd(beta)\n", tag,
           100.0 * beyond, n);
    ASSERT_LE(beyond, LOOP_GAUSS_BEYOND_2SD, "share beyond 2 sd(beta) on mu 0.5");
}

static inline void loop_print(const char *what, const loop_run_t *r, const loop_stats_t *s)
{
    printf("%s: steps at %.2f / %.2f s; max|vy| %.3f (bound %.3f) m/s, sd_vy %.4f..%.4f m/s, "
           "beta error max %.2f deg (low friction %.2f), RMS %.2f, settled %.2f s after the "
           "step up, last second %.2f deg\n",
           what, r->t_down, r->t_up, s->max_vy, s->vy_bound, s->min_sd_vy, s->max_sd_vy,
           s->max_err_deg, s->max_err_low, s->rms_err_deg, s->t_settle, s->end_err_deg);
}

/* REQ-OBS-024's bounds on a run with the loop's safeguards on: finite estimates, sd(vy)
 * positive and at most its start (@p sd_vy0), |vy| within the car's own plus vx tan 0.3 deg,
 * and settled within LOOP_T_CONV after the step up. */
static inline void loop_assert_no_runaway(const loop_stats_t *s, double sd_vy0)
{
    assert_true(s->finite);
    assert_true(s->min_sd_vy > 0.0);
    ASSERT_LE(s->max_sd_vy, sd_vy0, "sd(vy) <= obs_sd_vy0");
    ASSERT_LE(s->max_vy, s->vy_bound, "max |vy| <= max |vy_true| + vx tan 0.3 deg");
    ASSERT_LE(s->t_settle, LOOP_T_CONV, "settled after the step up [s]");
}

/* The Magic Formula truth's beta targets over the whole run: the limit's for the largest
 * error, the linear range's for the RMS. */
static inline void loop_assert_beta_targets(const loop_stats_t *s)
{
    ASSERT_LE(s->max_err_deg, LOOP_BETA_LIMIT_DEG, "max |beta error| [deg]");
    ASSERT_LE(s->rms_err_deg, LOOP_BETA_LIN_DEG, "RMS beta error [deg]");
}

/* The negative control: without the linear range's vy row every bound of
 * loop_assert_no_runaway fails, and beta ends beyond the limit's target. */
static inline void loop_assert_runs_away(const loop_stats_t *s, double sd_vy0)
{
    assert_true(s->max_vy > s->vy_bound);
    assert_true(s->max_sd_vy > sd_vy0);
    assert_true(s->t_settle > LOOP_T_CONV);
    assert_true(s->end_err_deg > LOOP_BETA_LIMIT_DEG);
}

#endif /* RFE_TEST_LOOP_CHECK_H */
