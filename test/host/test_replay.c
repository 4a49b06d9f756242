/**
 * @file test_replay.c
 * @brief Tests of the replay core (double build, as linked into the host tests): presets
 *        taken from the library, parameter conversion, rejected rows, parameter diagnosis.
 *
 * The float twin runs through mu_replay in test_cli.sh. Tests of the replay mechanics start
 * from the paper preset, whose values are fixed (the default preset may change).
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
#include "rfe/friction.h"
#include "rfe/params.h"
#include "rfe/velocity.h"

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

/* Each preset name maps to its library function (a swap would show here even while the
 * two presets have equal values). */
/* REQ-CLI-002 */
static void test_rfe_replay_preset_fn_maps_to_library(void **state)
{
    (void)state;
    assert_true(rfe_replay_preset_fn_f64(RFE_PRESET_DEFAULT) == rfe_params_default_f64);
    assert_true(rfe_replay_preset_fn_f64(RFE_PRESET_PAPER) == rfe_params_paper_f64);
    assert_null(rfe_replay_preset_fn_f64((rfe_preset_t)7));
}

/* Every key of the table equals the library's field exactly (read through the table's
 * member column, independently of the replay's offset table), for both presets. */
static void check_set_equals_library(rfe_preset_t preset, rfe_status_t (*lib)(rfe_params_t *))
{
    rfe_param_set_t ps;
    rfe_params_t p;
    size_t k;
    memset(&ps, 0xA5, sizeof ps);
    assert_int_equal(rfe_param_set_preset_f64(&ps, preset), 0);
    assert_int_equal(lib(&p), RFE_OK);
    assert_int_equal(ps.preset, preset);
#define CHECK_KEY_(key, member, unit, doc)                                                   \
    if (!(ps.value[RFE_PK_##key] == p.member)) {                                             \
        fail_msg("preset %s, key %s: set %.17g, library %.17g", rfe_preset_str(preset), #key, \
                 ps.value[RFE_PK_##key], p.member);                                          \
    }
    RFE_PARAM_KEYS(CHECK_KEY_)
#undef CHECK_KEY_
    assert_int_equal(ps.tyre, p.tyre.mode);
    assert_int_equal(ps.filter, p.filter.kind);
    assert_int_equal(ps.structure, p.filter.structure);
    for (k = 0u; k < (size_t)RFE_PK_COUNT; ++k) {
        assert_null(ps.origin[k].file); /* "the preset" */
        assert_int_equal(ps.origin[k].line, 0);
    }
}

/* REQ-CLI-002 REQ-PARAMS-001 */
static void test_rfe_param_set_preset_values_are_the_library_s(void **state)
{
    (void)state;
    check_set_equals_library(RFE_PRESET_DEFAULT, rfe_params_default_f64);
    check_set_equals_library(RFE_PRESET_PAPER, rfe_params_paper_f64);
}

/* rfe_param_set_default (inline; double here) is the default preset. */
/* REQ-CLI-002 */
static void test_rfe_param_set_default_is_default_preset(void **state)
{
    rfe_param_set_t a;
    rfe_param_set_t b;
    (void)state;
    memset(&a, 0, sizeof a);
    memset(&b, 0xFF, sizeof b);
    rfe_param_set_default(&b);
    assert_int_equal(rfe_param_set_preset_f64(&a, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(b.preset, RFE_PRESET_DEFAULT);
    assert_memory_equal(&a, &b, sizeof a);
}

/* REQ-CLI-002 */
static void test_rfe_param_set_preset_rejects_null_and_unknown(void **state)
{
    rfe_param_set_t ps;
    rfe_param_set_t before;
    (void)state;
    assert_int_equal(rfe_param_set_preset_f64(NULL, RFE_PRESET_PAPER), -1);
    memset(&ps, 0x5A, sizeof ps);
    before = ps;
    assert_int_equal(rfe_param_set_preset_f64(&ps, (rfe_preset_t)7), -1);
    assert_memory_equal(&ps, &before, sizeof ps); /* untouched */
}

/* The replay of a preset's set gives exactly what the estimator initialised by the library
 * function of that preset gives (the conversion loses nothing in double). */
static void check_replay_equals_library(rfe_preset_t preset, rfe_status_t (*lib)(rfe_params_t *),
                                        const rfe_sensor_log_t *log)
{
    rfe_param_set_t ps;
    rfe_params_t p;
    rfe_friction_t est;
    rfe_estimate_t e;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    size_t i;
    size_t w;
    assert_int_equal(rfe_param_set_preset_f64(&ps, preset), 0);
    assert_int_equal(rfe_replay_run_f64(&ps, log, out, &st, NULL), RFE_OK);
    assert_int_equal(lib(&p), RFE_OK);
    assert_int_equal(rfe_friction_init_f64(&est, &p), RFE_OK);
    for (i = 0u; i < log->n_rows; ++i) {
        rfe_sample_t s;
        memset(&s, 0, sizeof s);
        s.vx = log->rows[i].vx;
        s.ax = log->rows[i].ax;
        for (w = 0u; w < RFE_WHEELS; ++w) {
            s.omega[w] = log->rows[i].omega[w];
        }
        assert_int_equal(rfe_friction_step_f64(&est, &s, &e), out[i].status);
        for (w = 0u; w < RFE_WHEELS; ++w) {
            assert_true(out[i].mu[w] == e.mu[w]);
            assert_true(out[i].sd[w] == e.sd[w]);
        }
    }
}

/* REQ-CLI-002 REQ-CLI-003 */
static void test_rfe_replay_run_presets_as_library(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    (void)state;
    make_log(&log, rows);
    check_replay_equals_library(RFE_PRESET_DEFAULT, rfe_params_default_f64, &log);
    check_replay_equals_library(RFE_PRESET_PAPER, rfe_params_paper_f64, &log);
}

/* A set whose preset is not an rfe_preset_t: init refused, no key blamed. */
/* REQ-CLI-002 */
static void test_rfe_replay_run_unknown_preset(void **state)
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
    ps.preset = (rfe_preset_t)7;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_NONE);
    assert_int_equal(st.n_steps, 0);
}

/* REQ-CLI-003 */
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
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_PAPER), 0);
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

/* REQ-CLI-003 */
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
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_PAPER), 0);
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

/* REQ-CLI-003 */
static void test_rfe_replay_run_both_filters_and_tyres(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    (void)state;
    make_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_PAPER), 0);
    ps.filter = RFE_FILTER_CKF;
    ps.tyre = RFE_TYRE_ABSOLUTE;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_false(rfe_status_is_error((rfe_status_t)out[N_ROWS - 1u].status));
    assert_int_equal(st.n_steps, N_ROWS);
}

/* REQ-CLI-004 */
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
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_PAPER), 0);
    ps.value[RFE_PK_mu0] = 2.0; /* above mu_max = 1.2 */
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mu0);
    assert_int_equal(st.n_steps, 0);
}

/* REQ-CLI-004 */
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
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_PAPER), 0);
    /* Each alone is valid against the defaults; together mu0 < mu_min. */
    ps.value[RFE_PK_mu_min] = 0.45;
    ps.value[RFE_PK_mu0] = 0.4;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_NONE);
}

/* The CKF runs only the paper subset: asking for it on the default preset (or adding one of
 * docs/ESTIMATOR.md's additions to the paper preset) is blamed on the filter key. */
/* REQ-CLI-004 */
static void test_rfe_replay_run_ckf_outside_paper_subset_blames_filter(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    size_t bad = 0u;
    (void)state;
    make_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.filter = RFE_FILTER_CKF;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_FILTER);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_PAPER), 0);
    ps.filter = RFE_FILTER_CKF;
    ps.structure = RFE_STRUCT_SIDES;
    bad = 0u;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_FILTER);
    /* A key invalid on its own is still blamed, CKF or not. */
    ps.structure = RFE_STRUCT_WHEELS;
    ps.value[RFE_PK_sd_max] = -1.0;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_sd_max);
    /* The structure word key reaches the library. */
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.structure = RFE_STRUCT_WHEELS;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    ps.structure = (rfe_structure_t)7;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_STRUCTURE);
}

/* REQ-CLI-003 */
static void test_rfe_replay_run_null_arguments(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    (void)state;
    make_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_PAPER), 0);
    assert_int_equal(rfe_replay_run_f64(NULL, &log, out, &st, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_run_f64(&ps, &log, NULL, &st, NULL), RFE_ERR_NULL);
}

/* REQ-CLI-004 */
static void test_rfe_replay_run_observer_checks_its_arguments(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    size_t bad = 0u;
    size_t i;
    (void)state;
    make_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_replay_run_observer_f64(NULL, &log, out, &st, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_run_observer_f64(&ps, NULL, out, &st, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, NULL, &st, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, NULL, NULL), RFE_ERR_NULL);
    ps.value[RFE_PK_mu0] = 2.0; /* above mu_max: the set is diagnosed as for rfe_replay_run */
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mu0);
    assert_int_equal(st.n_steps, 0);
    /* a valid set runs every row and writes the observer's estimate into each */
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(st.n_steps, log.n_rows);
    for (i = 0u; i < log.n_rows; ++i) {
        assert_int_equal(out[i].has_velocity, 1);
        assert_true(out[i].t == log.rows[i].t);
    }
}

/* The observer's keys start from rfe_velocity_params_default and reach rfe_velocity_params_t
 * member by member (each default times 1.5 stays valid: every default is > 0 and dt_max
 * 0.15 s is still within 1 s). */
/* REQ-PARF-004 */
static void test_rfe_replay_velocity_params_keys_reach_members(void **state)
{
    rfe_param_set_t ps;
    rfe_velocity_params_t def;
    rfe_velocity_params_t vp;
    size_t bad = 0u;
    (void)state;
    /* zeroed first: the padding after the uint32_t driven stays defined for the compare */
    memset(&def, 0, sizeof def);
    memset(&vp, 0, sizeof vp);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_velocity_params_default_f64(&def), RFE_OK);
    assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, &bad), RFE_OK);
    assert_int_equal(bad, RFE_PK_NONE);
    assert_memory_equal(&vp, &def, sizeof vp);
#define CHECK_OBS_(key, member, unit, doc)                                                   \
    ps.obs[(size_t)RFE_PK_##key - RFE_PK_OBS_FIRST] = def.member * 1.5;                \
    assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, NULL), RFE_OK);                \
    if (!(vp.member == def.member * 1.5)) {                                           \
        fail_msg("key %s did not reach its member", #key);                                   \
    }                                                                                        \
    ps.obs[(size_t)RFE_PK_##key - RFE_PK_OBS_FIRST] = def.member;
    RFE_OBS_KEYS(CHECK_OBS_)
#undef CHECK_OBS_
    ps.obs[0] = 12.0; /* rear drive */
    assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, NULL), RFE_OK);
    assert_int_equal(vp.driven, RFE_DRIVEN_RL | RFE_DRIVEN_RR);
}

/* REQ-PARF-004 */
static void test_rfe_replay_velocity_params_names_the_bad_key(void **state)
{
    rfe_param_set_t ps;
    rfe_velocity_params_t vp;
    size_t bad = 0u;
    static const double not_a_mask[] = {0.0, 2.5, 16.0, -1.0};
    size_t i;
    (void)state;
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_replay_velocity_params_f64(NULL, &vp, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_velocity_params_f64(&ps, NULL, NULL), RFE_ERR_NULL);
    /* 0 is an integer but no wheel driven: validation; the rest are not masks at all. */
    for (i = 0u; i < sizeof not_a_mask / sizeof not_a_mask[0]; ++i) {
        ps.obs[0] = not_a_mask[i];
        assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, &bad), RFE_ERR_PARAM);
        assert_int_equal(bad, RFE_PK_obs_driven);
    }
    ps.obs[0] = 3.0;
    ps.obs[(size_t)RFE_PK_obs_steer_ratio - RFE_PK_OBS_FIRST] = 0.0;
    assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_obs_steer_ratio);
    ps.obs[(size_t)RFE_PK_obs_steer_ratio - RFE_PK_OBS_FIRST] = 16.0;
    ps.obs[(size_t)RFE_PK_obs_dt_max - RFE_PK_OBS_FIRST] = 0.0005; /* below dt_min */
    assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_obs_dt_max);
}

/* A log still in km/h wheel speeds or steering-wheel angles is refused, never run as if
 * it were rad/s and road-wheel angles; the observer takes the steering-wheel angle itself. */
/* REQ-CSV-005 */
static void test_rfe_replay_refuses_unconverted_logs(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_stats_t st;
    (void)state;
    make_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    log.omega_linear = 1;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_ERR_RANGE);
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, NULL), RFE_ERR_RANGE);
    log.omega_linear = 0;
    log.has_swa = 1;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_ERR_RANGE);
    assert_int_equal(st.n_steps, 0);
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(st.n_steps, log.n_rows);
}

/* REQ-CLI-003 */
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
        cmocka_unit_test(test_rfe_replay_preset_fn_maps_to_library),
        cmocka_unit_test(test_rfe_param_set_preset_values_are_the_library_s),
        cmocka_unit_test(test_rfe_param_set_default_is_default_preset),
        cmocka_unit_test(test_rfe_param_set_preset_rejects_null_and_unknown),
        cmocka_unit_test(test_rfe_replay_run_presets_as_library),
        cmocka_unit_test(test_rfe_replay_run_unknown_preset),
        cmocka_unit_test(test_rfe_replay_run_file_every_row),
        cmocka_unit_test(test_rfe_replay_run_rejected_row_logged_and_run_continues),
        cmocka_unit_test(test_rfe_replay_run_both_filters_and_tyres),
        cmocka_unit_test(test_rfe_replay_run_invalid_key_diagnosed),
        cmocka_unit_test(test_rfe_replay_run_invalid_combination_not_blamed_on_one_key),
        cmocka_unit_test(test_rfe_replay_run_ckf_outside_paper_subset_blames_filter),
        cmocka_unit_test(test_rfe_replay_run_null_arguments),
        cmocka_unit_test(test_rfe_replay_run_observer_checks_its_arguments),
        cmocka_unit_test(test_rfe_replay_velocity_params_keys_reach_members),
        cmocka_unit_test(test_rfe_replay_velocity_params_names_the_bad_key),
        cmocka_unit_test(test_rfe_replay_refuses_unconverted_logs),
        cmocka_unit_test(test_rfe_replay_status_slot_bounds),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
