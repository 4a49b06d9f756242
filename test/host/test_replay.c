/**
 * @file test_replay.c
 * @brief Tests of the replay core (double build, as linked into the host tests): parameter
 *        conversion, default agreement with the library, rejected rows, parameter diagnosis.
 *
 * The float twin runs through mu_replay in test_cli.sh.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/config.h"

#define DATA "test/host/data/"
#define N_ROWS 4u

/* A straight-line braking log in memory: 20 m/s, -3 m/s^2, 5 % slip on every wheel. */
static void make_log(rfe_sensor_log_t *log, rfe_sensor_row_t rows[N_ROWS])
{
    size_t i;
    size_t w;
    memset(log, 0, sizeof *log);
    memset(rows, 0, N_ROWS * sizeof rows[0]);
    for (i = 0u; i < N_ROWS; ++i) {
        rows[i].t = 0.01 * (double)i;
        rows[i].vx = 20.0;
        rows[i].ax = -3.0;
        for (w = 0u; w < RFE_WHEELS; ++w) {
            rows[i].omega[w] = 0.95 * 20.0 / 0.325;
        }
    }
    log->rows = rows;
    log->n_rows = N_ROWS;
}

static size_t count_sum(const rfe_replay_stats_t *s)
{
    size_t i;
    size_t n = 0u;
    for (i = 0u; i < RFE_REPLAY_STATUS_SLOTS; ++i) {
        n += s->status_count[i];
    }
    return n;
}

static void test_rfe_replay_check_defaults_match_library(void **state)
{
    (void)state;
    assert_int_equal(rfe_replay_check_defaults_f64(), RFE_PK_NONE);
}

static void test_rfe_replay_run_file_every_row(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_io_error_t err;
    rfe_est_row_t out[3];
    rfe_replay_stats_t st;
    size_t i;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_notruth.csv", &log, &err), 0);
    rfe_param_set_default(&ps);
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(st.n_steps, 3);
    assert_int_equal(count_sum(&st), 3);
    for (i = 0u; i < 3u; ++i) {
        assert_true(out[i].t == log.rows[i].t);
        assert_false(rfe_status_is_error((rfe_status_t)out[i].status));
        assert_true((out[i].mu[RFE_FL] >= 0.05) && (out[i].mu[RFE_FL] <= 1.2));
        assert_true(out[i].sd[RFE_RR] > 0.0);
    }
    rfe_sensor_log_free(&log);
}

static void test_rfe_replay_run_rejected_row_logged_and_run_continues(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    size_t w;
    (void)state;
    make_log(&log, rows);
    rows[2].vx = 2.0 * RFE_LIMIT_VX; /* implausible: the library rejects it */
    rfe_param_set_default(&ps);
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(out[2].status, RFE_ERR_RANGE);
    for (w = 0u; w < RFE_WHEELS; ++w) {
        assert_int_equal(out[2].valid[w], 0);
        assert_true(out[2].mu[w] == out[1].mu[w]); /* unchanged estimate */
    }
    assert_false(rfe_status_is_error((rfe_status_t)out[3].status));
    assert_int_equal(st.status_count[RFE_ERR_RANGE], 1);
    assert_int_equal(count_sum(&st), N_ROWS);
}

static void test_rfe_replay_run_both_filters_and_tyres(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    (void)state;
    make_log(&log, rows);
    rfe_param_set_default(&ps);
    ps.filter = RFE_FILTER_CKF;
    ps.tyre = RFE_TYRE_ABSOLUTE;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_false(rfe_status_is_error((rfe_status_t)out[N_ROWS - 1u].status));
    assert_int_equal(st.n_steps, N_ROWS);
}

static void test_rfe_replay_run_invalid_key_diagnosed(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    size_t bad = 0u;
    (void)state;
    make_log(&log, rows);
    rfe_param_set_default(&ps);
    ps.value[RFE_PK_mu0] = 2.0; /* above mu_max = 1.2 */
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mu0);
    assert_int_equal(st.n_steps, 0);
}

static void test_rfe_replay_run_invalid_combination_not_blamed_on_one_key(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    size_t bad = 0u;
    (void)state;
    make_log(&log, rows);
    rfe_param_set_default(&ps);
    /* Each alone is valid against the defaults; together mu0 < mu_min. */
    ps.value[RFE_PK_mu_min] = 0.45;
    ps.value[RFE_PK_mu0] = 0.4;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_NONE);
}

static void test_rfe_replay_run_null_arguments(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    (void)state;
    make_log(&log, rows);
    rfe_param_set_default(&ps);
    assert_int_equal(rfe_replay_run_f64(NULL, &log, out, &st, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_run_f64(&ps, &log, NULL, &st, NULL), RFE_ERR_NULL);
}

static void test_rfe_replay_status_slot_bounds(void **state)
{
    (void)state;
    assert_int_equal(rfe_replay_status_slot(0), 0);
    assert_int_equal(rfe_replay_status_slot(RFE_ERR_RANGE), RFE_ERR_RANGE);
    assert_int_equal(rfe_replay_status_slot(-1), RFE_REPLAY_STATUS_SLOTS - 1);
    assert_int_equal(rfe_replay_status_slot(1000), RFE_REPLAY_STATUS_SLOTS - 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_replay_check_defaults_match_library),
        cmocka_unit_test(test_rfe_replay_run_file_every_row),
        cmocka_unit_test(test_rfe_replay_run_rejected_row_logged_and_run_continues),
        cmocka_unit_test(test_rfe_replay_run_both_filters_and_tyres),
        cmocka_unit_test(test_rfe_replay_run_invalid_key_diagnosed),
        cmocka_unit_test(test_rfe_replay_run_invalid_combination_not_blamed_on_one_key),
        cmocka_unit_test(test_rfe_replay_run_null_arguments),
        cmocka_unit_test(test_rfe_replay_status_slot_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
