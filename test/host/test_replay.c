/**
 * @file test_replay.c
 * @brief Tests of the replay core (double build, as linked into the host tests): presets
 *        taken from the library, parameter conversion, rejected rows, parameter diagnosis;
 *        and the fixed-point observer replay (replay_q31.h, the q31 library linked too).
 *
 * The float twin runs through mu_replay in test_cli.sh. Tests of the replay mechanics start
 * from the paper preset, whose values are fixed (the default preset may change).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_q31.h"
#include "replay_real.h"
#include "rfe/component/params_conv.h"
#include "rfe/config.h"
#include "rfe/pipeline_q31.h"
#include "rfe/friction.h"
#include "rfe/mass_grade.h"
#include "rfe/mass_grade_q31.h"
#include "rfe/params.h"
#include "rfe/pipeline.h"
#include "rfe/tyre_id.h"
#include "rfe/velocity.h"
#include "test_light.h"

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
    /* obs_lat_every: an integer 1..8 (0 and 9 integers refused by validation, 2.5 and -1 as
     * no integer at all); a valid one reaches the member */
    for (i = 0u; i < sizeof not_a_mask / sizeof not_a_mask[0]; ++i) {
        ps.obs[(size_t)RFE_PK_obs_lat_every - RFE_PK_OBS_FIRST] =
            (not_a_mask[i] == 16.0) ? 9.0 : not_a_mask[i];
        assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, &bad), RFE_ERR_PARAM);
        assert_int_equal(bad, RFE_PK_obs_lat_every);
    }
    ps.obs[(size_t)RFE_PK_obs_lat_every - RFE_PK_OBS_FIRST] = 3.0;
    assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, &bad), RFE_OK);
    assert_int_equal(vp.lat_every, 3u);
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


/* ------------------------------------------------------------ the fixed-point observer run */

/* REQ-CLI-004 REQ-CLI-005 */
static void test_rfe_replay_run_observer_q31_checks_its_arguments(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_q31_stats_t st;
    size_t bad = 0u;
    size_t i;
    (void)state;
    make_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_replay_run_observer_q31(NULL, &log, out, &st, NULL, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_run_observer_q31(&ps, NULL, out, &st, NULL, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, NULL, &st, NULL, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, NULL, NULL, NULL), RFE_ERR_NULL);
    {
        rfe_params_q31_t pq;
        assert_int_equal(rfe_replay_params_q31(NULL, &pq, NULL), RFE_ERR_NULL);
        assert_int_equal(rfe_replay_params_q31(&ps, NULL, NULL), RFE_ERR_NULL);
        {
            rfe_velocity_params_q31_t vq;
            assert_int_equal(rfe_replay_observer_params_q31(NULL, &pq, &vq, NULL), RFE_ERR_NULL);
            assert_int_equal(rfe_replay_observer_params_q31(&ps, &pq, NULL, NULL), RFE_ERR_NULL);
            assert_int_equal(rfe_replay_observer_params_q31(&ps, &pq, &vq, NULL), RFE_OK);
        }
    }
    /* an invalid value: diagnosed as in the double run (the double path comes first) */
    ps.value[RFE_PK_mu0] = 2.0;
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mu0);
    assert_int_equal(st.base.n_steps, 0);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.obs[(size_t)RFE_PK_obs_steer_ratio - RFE_PK_OBS_FIRST] = 0.0;
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_obs_steer_ratio);
    /* valid, but beyond its Q format: 1e5 N m > 2^16 N m (Q15) for the observer's key, and
     * 40000 kg > 2^15 kg (Q16) for the friction estimator's */
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.obs[(size_t)RFE_PK_obs_torque_on - RFE_PK_OBS_FIRST] = 1e5;
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_RANGE);
    assert_int_equal(bad, RFE_PK_obs_torque_on);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.value[RFE_PK_m] = 40000.0;
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_RANGE);
    assert_int_equal(bad, RFE_PK_m);
    /* only a combination beyond its format: dt 1e-4 s and tau_v 30 s each fit, but the
     * input filter's gain dt / (tau_v + dt) = 3.3e-6 has fewer than the 16 significant bits
     * of Q30 its conversion demands (2^30 3.3e-6 = 3579 LSB) */
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.value[RFE_PK_dt] = 1e-4;
    ps.value[RFE_PK_tau_v] = 30.0;
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_RANGE);
    assert_int_equal(bad, RFE_PK_NONE);
    /* wheel speeds still km/h: refused; a steering-wheel angle: the observer takes it */
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    log.omega_linear = 1;
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, NULL), RFE_ERR_RANGE);
    log.omega_linear = 0;
    log.has_swa = 1;
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, NULL), RFE_OK);
    assert_int_equal(st.base.n_steps, log.n_rows);
    for (i = 0u; i < log.n_rows; ++i) {
        assert_int_equal(out[i].has_velocity, 1);
        assert_true(out[i].t == log.rows[i].t);
    }
}

/* The Q31 parameters of @p ps by the documented path (double, then the converters). */
static void q31_params_of(const rfe_param_set_t *ps, rfe_params_q31_t *pq,
                          rfe_velocity_params_q31_t *vq)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    assert_int_equal(rfe_replay_params_f64(ps, &p, NULL), RFE_OK);
    assert_int_equal(rfe_replay_velocity_params_f64(ps, &vp, NULL), RFE_OK);
    assert_int_equal(rfe_params_to_q31_f64(&p, pq), RFE_OK);
    assert_int_equal(rfe_velocity_params_to_q31_f64(&vp, vq), RFE_OK);
}

/* x * 2^q rounded to nearest, ties up (what the replay documents), in the format's range. */
static rfe_fix_t q_of(double x, int q)
{
    const double y = floor(ldexp(x, q) + 0.5);
    assert_true(fabs(y) <= 2147483647.0); /* the rows below stay inside every format */
    return (rfe_fix_t)y;
}

#define N_ESC 8u

/* An ESC log in a turn with every optional column (pressures, torques, grade, the
 * steering-wheel angle; delta 0, as the reader leaves it) where each decides: braking on the
 * pressures alone (rows 0-3, ax 0), then driving on the front torques alone (rows 4-7). */
static void make_esc_log(rfe_sensor_log_t *log, rfe_sensor_row_t rows[N_ESC])
{
    size_t i;
    size_t w;
    memset(log, 0, sizeof *log);
    memset(rows, 0, N_ESC * sizeof rows[0]);
    for (i = 0u; i < N_ESC; ++i) {
        rows[i].t = 0.01 * (double)i;
        rows[i].swa = 0.8 + 0.01 * (double)i;
        rows[i].yaw_rate = 0.1;
        rows[i].ay = 2.0;
        rows[i].grade = 0.02;
        for (w = 0u; w < RFE_WHEELS; ++w) {
            rows[i].omega[w] = (20.0 + 0.1 * (double)w) / 0.325;
            rows[i].p_brake[w] = (i < 4u) ? 1.5 + 0.1 * (double)w : 0.0;
            rows[i].torque[w] = ((i >= 4u) && (w < 2u)) ? 300.0 : 0.0;
        }
    }
    log->rows = rows;
    log->n_rows = N_ESC;
    log->has_pressure = 1;
    log->has_torque = 1;
    log->has_grade = 1;
    log->has_swa = 1;
}

/* Every row of the replay is the fixed-point pipeline's step on the row's Q values (rounded
 * by q_of, its period the time stamps' difference), every output the Q value exactly (an
 * integer after scaling back by 2^q). */
/* REQ-CLI-005 */
static void test_rfe_replay_run_observer_q31_is_the_pipeline_bit_for_bit(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ESC];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ESC];
    rfe_replay_q31_stats_t st;
    uint32_t row_sat[N_ESC];
    uint32_t flags[N_ESC];
    rfe_params_q31_t pq;
    rfe_velocity_params_q31_t vq;
    static rfe_pipeline_q31_t pl;
    size_t i;
    size_t w;
    (void)state;
    make_esc_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    memset(row_sat, 0xff, sizeof row_sat);
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, row_sat, NULL), RFE_OK);
    q31_params_of(&ps, &pq, &vq);
    memset(&pl, 0, sizeof pl);
    assert_int_equal(rfe_pipeline_init_q31(&pl, &pq, &vq), RFE_OK);
    for (i = 0u; i < N_ESC; ++i) {
        const rfe_sensor_row_t *r = &rows[i];
        rfe_velocity_input_q31_t in;
        rfe_pipeline_out_q31_t o;
        rfe_status_t s;
        memset(&in, 0, sizeof in);
        in.dt = q_of((i > 0u) ? r->t - rows[i - 1u].t : 0.0, 30);
        in.delta = q_of(r->delta, 29);
        in.steer_wheel = q_of(r->swa, 26);
        in.yaw_rate = q_of(r->yaw_rate, 27);
        in.ax = q_of(r->ax, 24);
        in.ay = q_of(r->ay, 24);
        in.grade = q_of(r->grade, 29);
        for (w = 0u; w < RFE_WHEELS; ++w) {
            in.omega[w] = q_of(r->omega[w], 22);
            in.p_brake[w] = q_of(r->p_brake[w], 25);
            in.torque[w] = q_of(r->torque[w], 15);
        }
        in.has = RFE_VEL_HAS_PRESSURE | RFE_VEL_HAS_TORQUE | RFE_VEL_HAS_STEER_WHEEL;
        s = rfe_pipeline_step_q31(&pl, &in, &o);
        assert_false(rfe_status_is_error(s));
        assert_int_equal(out[i].status, (int)s);
        assert_int_equal(out[i].has_velocity, 1);
        assert_true(out[i].t == r->t);
        for (w = 0u; w < RFE_WHEELS; ++w) {
            assert_true(ldexp(out[i].mu[w], 29) == (double)o.friction.mu[w]);
            assert_true(ldexp(out[i].sd[w], 30) == (double)o.friction.sd[w]);
            assert_int_equal(out[i].valid[w], o.friction.valid[w]);
        }
        assert_true(ldexp(out[i].vx, 23) == (double)o.velocity.vx);
        assert_true(ldexp(out[i].vy, 23) == (double)o.velocity.vy);
        assert_true(ldexp(out[i].beta, 29) == (double)o.velocity.beta);
        assert_true(ldexp(out[i].yaw_acc, 24) == (double)o.velocity.yaw_acc);
        assert_true(ldexp(out[i].sd_vx, 23) == (double)o.velocity.sd_vx);
        assert_true(ldexp(out[i].sd_vy, 23) == (double)o.velocity.sd_vy);
        assert_true(ldexp(out[i].sd_beta, 29) == (double)o.velocity.sd_beta);
        assert_int_equal(row_sat[i], o.velocity.sat + o.friction.sat);
        flags[i] = o.velocity.flags;
    }
    /* each optional input decided something, so a replay that dropped one would differ
     * above: braking on the pressures, driving on the torques, and the road-wheel angle from
     * the steering wheel through the default ratio 16, within 1 LSB of Q29 (the Q26 rounding
     * of the angle, 2^-27 rad / 16 = 0.25 LSB, and the division's 0.5 LSB) */
    assert_true((flags[3] & RFE_VEL_FLAG_BRAKING) != 0u);
    assert_true((flags[N_ESC - 1u] & RFE_VEL_FLAG_DRIVING) != 0u);
    assert_true(labs((long)pl.velocity.last.delta - (long)q_of(0.87 / 16.0, 29)) <= 1L);
    assert_int_equal(st.base.n_steps, N_ESC);
    assert_int_equal(st.input_sat, 0u);
}

/* A value beyond its Q format saturates and is counted (every format holds its limit: ax
 * 200 m/s^2 > 128 m/s^2 of Q24; a 3 s gap > 2 s of Q30), and the run goes on: the ax row is
 * rejected, logged with its status, not valid, the previous estimates kept; the gap's period
 * saturates at 2 s, still beyond obs_dt_max, so the observer starts afresh there (vx from the
 * wheels: 0.95 x 20 m/s) and the friction estimator makes round(2 s / 0.01 s) - 1 = 199
 * time updates (rfe/pipeline_q31.h); both are counted. */
/* REQ-CLI-003 REQ-CLI-005 REQ-OBS-023 */
static void test_rfe_replay_run_observer_q31_counts_saturation_and_goes_on(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out[N_ROWS];
    rfe_replay_q31_stats_t st;
    size_t w;
    size_t i;
    (void)state;
    make_log(&log, rows);
    rows[1].ax = 200.0;
    for (i = 3u; i < N_ROWS; ++i) {
        rows[i].t += 3.0;
    }
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, NULL), RFE_OK);
    assert_int_equal(st.base.n_steps, N_ROWS);
    assert_int_equal(st.input_sat, 2u);
    assert_int_equal(st.input_sat_rows, 2u);
    assert_int_equal(out[1].status, RFE_ERR_RANGE);
    assert_false(rfe_status_is_error((rfe_status_t)out[2].status));
    assert_false(rfe_status_is_error((rfe_status_t)out[3].status));
    assert_int_equal(st.base.status_count[RFE_ERR_RANGE], 1u);
    assert_int_equal(count_sum(&st.base), N_ROWS);
    assert_int_equal(st.base.n_gaps, 1u);
    assert_int_equal(st.base.n_skipped, 199u);
    assert_int_equal(st.base.n_restarts, 1u);
    for (w = 0u; w < RFE_WHEELS; ++w) {
        assert_int_equal(out[1].valid[w], 0u);
        assert_true(out[1].mu[w] == out[0].mu[w]);
    }
    assert_true(out[1].vx == out[0].vx);
    assert_true(fabs(out[3].vx - (0.95 * 20.0)) < 1e-3); /* the wheels (Q22 omega: < 1e-5) */
    assert_int_equal(out[3].has_velocity, 1);
}

/* The fixed-point run agrees with the double observer run on a recorded car's log (km/h
 * wheel speeds, the steering-wheel angle, no vx columns) and on a simulated lane change with
 * pressures and torques, within REQ-FXP-016's bounds of the pipeline twins (mu 0.005 where
 * both are valid; vx 1e-4 m/s, vy 5e-4 m/s: test_pipeline_q31.c), statuses and valid flags
 * equal (the samples' decisions are far from their thresholds on these logs; measured on the
 * lane change through mu_replay: every flag equal, |dmu| 1.9e-6, |dvx| 1.0e-6 m/s). A wrong
 * conversion (a format, the period, a missing column) is off by orders of magnitude more. */
/* REQ-CLI-005 */
static void test_rfe_replay_run_observer_q31_agrees_with_double(void **state)
{
    static const char *const LOGS[] = {DATA "car_format_small.csv",
                                       "scenarios/observer/dlc_mu09.csv"};
    size_t k;
    (void)state;
    for (k = 0u; k < sizeof LOGS / sizeof LOGS[0]; ++k) {
        rfe_sensor_log_t log;
        rfe_param_set_t ps;
        rfe_io_error_t err;
        rfe_replay_stats_t sd;
        rfe_replay_q31_stats_t sq;
        rfe_est_row_t *od;
        rfe_est_row_t *oq;
        size_t i;
        size_t w;
        size_t n_valid = 0u;
        memset(&log, 0, sizeof log);
        if (rfe_sensor_log_read(LOGS[k], &log, &err) != 0) {
            fail_msg("%s:%zu: %s", err.file, err.line, err.msg);
        }
        assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
        assert_int_equal(rfe_param_set_apply_meta(&ps, &log, LOGS[k], &err), 0);
        if (log.omega_linear != 0) { /* as mu_replay: km/h through R */
            assert_int_equal(rfe_sensor_log_wheel_radius(&log, ps.value[RFE_PK_R]), 0);
        }
        od = calloc(log.n_rows, sizeof *od);
        oq = calloc(log.n_rows, sizeof *oq);
        assert_non_null(od);
        assert_non_null(oq);
        assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, od, &sd, NULL), RFE_OK);
        assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, oq, &sq, NULL, NULL), RFE_OK);
        assert_int_equal(sq.input_sat, 0u);
        assert_int_equal(sq.est_sat, 0u);
        for (i = 0u; i < log.n_rows; ++i) {
            assert_int_equal(oq[i].status, od[i].status);
            assert_true(fabs(oq[i].vx - od[i].vx) <= 1e-4);
            assert_true(fabs(oq[i].vy - od[i].vy) <= 5e-4);
            for (w = 0u; w < RFE_WHEELS; ++w) {
                assert_int_equal(oq[i].valid[w], od[i].valid[w]);
                if (oq[i].valid[w] != 0u) {
                    assert_true(fabs(oq[i].mu[w] - od[i].mu[w]) <= 0.005);
                    ++n_valid;
                }
            }
        }
        /* the lane change settles: the comparison saw valid estimates */
        assert_true((k == 0u) || (n_valid > 1000u));
        free(od);
        free(oq);
        rfe_sensor_log_free(&log);
    }
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

/* ------------------------------------------------------------ mass and grade */

/* The set's mg_* keys are the library's preset of the vehicle and config, each value exactly
 * (read through the key table's member column), origins the preset; the default set's are
 * the car's recommended preset's. NULL or an unknown vehicle or config: -1, nothing changed. */
/* REQ-PARF-004 */
static void check_mg_set_equals_library(const rfe_param_set_t *ps, rfe_mg_vehicle_t vehicle,
                                        rfe_mg_config_t config)
{
    rfe_mass_grade_params_t p;
    assert_int_equal(rfe_mass_grade_params_preset_f64(&p, vehicle, config), RFE_OK);
    assert_int_equal(ps->mg_vehicle, vehicle);
    assert_int_equal(ps->mg_config, config);
    assert_true(ps->mg[RFE_PK_mg_adaptive - RFE_PK_MG_FIRST] == (double)p.adaptive);
    assert_true(ps->mg[RFE_PK_mg_use_ax - RFE_PK_MG_FIRST] == (double)p.use_ax);
#define CHECK_MG_(key, member, unit, doc)                                                    \
    if (!(ps->mg[(size_t)RFE_PK_##key - RFE_PK_MG_FIRST] == p.member)) {                     \
        fail_msg("config %d, key %s: set %.17g, library %.17g", (int)config, #key,          \
                 ps->mg[(size_t)RFE_PK_##key - RFE_PK_MG_FIRST], p.member);                  \
    }                                                                                        \
    assert_null(ps->origin[RFE_PK_##key].file);
    RFE_MG_KEYS(CHECK_MG_)
#undef CHECK_MG_
}

/* REQ-CLI-007 */
static void test_rfe_param_set_mass_grade_is_the_library_preset(void **state)
{
    rfe_param_set_t ps;
    rfe_param_set_t before;
    (void)state;
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    check_mg_set_equals_library(&ps, RFE_MG_CAR, RFE_MG_RECOMMENDED);
    assert_int_equal(ps.mass_grade, 0); /* a preset never runs it */
    assert_int_equal(rfe_param_set_mass_grade_f64(&ps, RFE_MG_CAR, RFE_MG_SEED), 0);
    check_mg_set_equals_library(&ps, RFE_MG_CAR, RFE_MG_SEED);
    assert_true(ps.mg[RFE_PK_mg_adaptive - RFE_PK_MG_FIRST] == 1.0);
    /* the truck (mu_replay --mass-grade-vehicle truck): its own values, e.g. m0 and C_d */
    assert_int_equal(rfe_param_set_mass_grade_f64(&ps, RFE_MG_TRUCK, RFE_MG_RECOMMENDED), 0);
    check_mg_set_equals_library(&ps, RFE_MG_TRUCK, RFE_MG_RECOMMENDED);
    assert_true(ps.mg[RFE_PK_mg_cd - RFE_PK_MG_FIRST] == 0.6); /* MASS_GRADE.md §6 */
    assert_int_equal(rfe_param_set_mass_grade_f64(NULL, RFE_MG_CAR, RFE_MG_SEED), -1);
    memcpy(&before, &ps, sizeof ps);
    assert_int_equal(rfe_param_set_mass_grade_f64(&ps, RFE_MG_CAR, (rfe_mg_config_t)7), -1);
    assert_memory_equal(&ps, &before, sizeof ps);
    assert_int_equal(rfe_param_set_mass_grade_f64(&ps, (rfe_mg_vehicle_t)7, RFE_MG_SEED), -1);
    assert_memory_equal(&ps, &before, sizeof ps);
}

/* Every mg_* key reaches its member (each nonzero value times 1.5 stays valid: the masses stay
 * ordered, n + lambda > 0, theta_max < 1.5), R and g come from the vehicle keys, and the key
 * that alone fails is named; a combination names none. */
/* REQ-CLI-007 */
static void test_rfe_replay_mass_grade_params_keys_and_diagnosis(void **state)
{
    rfe_param_set_t ps;
    rfe_mass_grade_params_t def;
    rfe_mass_grade_params_t mp;
    size_t bad = 0u;
    (void)state;
    memset(&def, 0, sizeof def);
    memset(&mp, 0, sizeof mp);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_mass_grade_params_default_f64(&def), RFE_OK);
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, &bad), RFE_OK);
    assert_int_equal(bad, RFE_PK_NONE);
    assert_memory_equal(&mp, &def, sizeof mp);
    /* pause_grade, an integer (the brake bit 1 by default), times 3 instead: brake + shift;
     * dt_max times 0.5 (the walk's time constants, 1 s and 3 s, must stay >= it, §4.7) */
#define MG_FACTOR_(key)                                                                      \
    ((RFE_PK_##key == RFE_PK_mg_pause_grade) ? 3.0 : ((RFE_PK_##key == RFE_PK_mg_dt_max) ? 0.5 : 1.5))
#define CHECK_MG_(key, member, unit, doc)                                                    \
    ps.mg[(size_t)RFE_PK_##key - RFE_PK_MG_FIRST] = def.member * MG_FACTOR_(key);            \
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, NULL), RFE_OK);              \
    if (!(mp.member == def.member * MG_FACTOR_(key))) {                                      \
        fail_msg("key %s did not reach its member", #key);                                   \
    }                                                                                        \
    ps.mg[(size_t)RFE_PK_##key - RFE_PK_MG_FIRST] = def.member;
    RFE_MG_KEYS(CHECK_MG_)
#undef CHECK_MG_
#undef MG_FACTOR_
    ps.value[RFE_PK_R] = 0.45;
    ps.value[RFE_PK_g] = 9.8;
    ps.mg[RFE_PK_mg_adaptive - RFE_PK_MG_FIRST] = 1.0;
    ps.mg[RFE_PK_mg_use_ax - RFE_PK_MG_FIRST] = 0.0;
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, NULL), RFE_OK);
    assert_true((mp.R == 0.45) && (mp.g == 9.8) && (mp.adaptive == 1u) && (mp.use_ax == 0u));
    ps.mg[RFE_PK_mg_use_ax - RFE_PK_MG_FIRST] = 0.5; /* not a switch */
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mg_use_ax);
    ps.mg[RFE_PK_mg_use_ax - RFE_PK_MG_FIRST] = 1.0;
    ps.mg[RFE_PK_mg_m0 - RFE_PK_MG_FIRST] = -5.0;
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mg_m0);
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, NULL), RFE_ERR_PARAM);
    ps.mg[RFE_PK_mg_m0 - RFE_PK_MG_FIRST] = 5000.0; /* valid alone, as is m_max 4000 */
    ps.mg[RFE_PK_mg_m_max - RFE_PK_MG_FIRST] = 4000.0;
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_NONE);
    assert_int_equal(rfe_replay_mass_grade_params_f64(NULL, &mp, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, NULL, NULL), RFE_ERR_NULL);
}

#define N_MG 40u

/* A drive on a 3 % climb at ~20 m/s, 50 Hz: torque and ax as the car's model gives them, so
 * the estimator's grade moves away from its start of 0 sample by sample. */
static void make_mg_log(rfe_sensor_log_t *log, rfe_sensor_row_t rows[N_MG])
{
    size_t i;
    size_t w;
    memset(log, 0, sizeof *log);
    memset(rows, 0, N_MG * sizeof rows[0]);
    for (i = 0u; i < N_MG; ++i) {
        const double v = 20.0 + 0.01 * (double)i;
        rows[i].t = 0.02 * (double)i;
        rows[i].vx = v;
        rows[i].ax = 0.5 + 9.81 * sin(0.03);
        rows[i].drive_torque = 0.325 * (1875.0 * 0.5 + 1830.0 * 9.81 * (0.03 + 0.01));
        rows[i].gear = 3.0;
        rows[i].brake = 0.0;
        rows[i].brake_pressure = 0.0;
        for (w = 0u; w < RFE_WHEELS; ++w) {
            rows[i].omega[w] = v / 0.325;
        }
    }
    log->rows = rows;
    log->n_rows = N_MG;
    log->has_drive_torque = 1;
    log->has_gear = 1;
    log->has_brake = 1;
    log->has_brake_pressure = 1;
}

/* Behind the observer, each sample first steps the mass and grade estimator, then the
 * pipeline with that sample's estimated grade (the current step's, not the previous one's):
 * the replay equals this loop bit for bit. A measured grade column wins. The estimate is the
 * same with measured velocities (its speed is the wheels'). */
/* REQ-CLI-007 */
static void test_rfe_replay_run_observer_takes_the_current_estimated_grade(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    static rfe_est_row_t meas[N_MG];
    rfe_replay_stats_t st;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_mass_grade_params_t mp;
    static rfe_pipeline_t pl;
    static rfe_mass_grade_t mg;
    size_t i;
    size_t moved = 0u;
    (void)state;
    make_mg_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(rfe_replay_params_f64(&ps, &p, NULL), RFE_OK);
    assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, NULL), RFE_OK);
    assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, NULL), RFE_OK);
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
    assert_int_equal(rfe_mass_grade_init(&mg, &mp), RFE_OK);
    for (i = 0u; i < N_MG; ++i) {
        rfe_mass_grade_input_t mi;
        rfe_mass_grade_estimate_t e;
        rfe_velocity_input_t in;
        rfe_pipeline_out_t o;
        memset(&mi, 0, sizeof mi);
        mi.dt = (i > 0u) ? rows[i].t - rows[i - 1u].t : 0.0;
        mi.v = ((((rows[i].omega[0] + rows[i].omega[1]) + rows[i].omega[2]) + rows[i].omega[3]) / 4.0) *
               0.325;
        mi.torque = rows[i].drive_torque;
        mi.ax = rows[i].ax;
        mi.gear = 3;
        mi.has = RFE_MG_HAS_AX | RFE_MG_HAS_BRAKE | RFE_MG_HAS_PRESSURE | RFE_MG_HAS_GEAR;
        assert_int_equal(rfe_mass_grade_step(&mg, &mi, &e), RFE_OK);
        rfe_replay_esc_input_f64(&log, i, (i > 0u) ? i - 1u : SIZE_MAX, &in);
        in.grade = e.grade;
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
        assert_int_equal(out[i].has_mass_grade, 1);
        assert_int_equal(out[i].mg_status, RFE_OK);
        assert_true((out[i].mass == e.mass) && (out[i].sd_mass == e.sd_mass));
        assert_true((out[i].grade == e.grade) && (out[i].sd_grade == e.sd_grade));
        assert_true((out[i].vx == o.velocity.vx) && (out[i].sd_vx == o.velocity.sd_vx));
        assert_true(out[i].mu[0] == o.friction.mu[0]);
        moved += ((i > 0u) && (out[i].grade != out[i - 1u].grade)) ? 1u : 0u;
    }
    /* the grade changes from each sample to the next, so the previous sample's would differ */
    assert_int_equal(moved, N_MG - 1u);
    assert_int_equal(st.mg_status_count[RFE_OK], N_MG);
    /* the measured grade column wins over the estimate: the observer as with grade 0 */
    log.has_grade = 1;
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, meas, &st, NULL), RFE_OK);
    ps.mass_grade = 0;
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, NULL), RFE_OK);
    for (i = 0u; i < N_MG; ++i) {
        assert_true(meas[i].vx == out[i].vx);
        assert_int_equal(out[i].has_mass_grade, 0);
        assert_int_equal(meas[i].has_mass_grade, 1);
    }
    /* measured velocities: the same mass and grade (rows copied from the observer run) */
    ps.mass_grade = 1;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    for (i = 0u; i < N_MG; ++i) {
        assert_int_equal(out[i].has_velocity, 0);
        assert_true((out[i].mass == meas[i].mass) && (out[i].grade == meas[i].grade));
        assert_true((out[i].sd_mass == meas[i].sd_mass) && (out[i].sd_grade == meas[i].sd_grade));
    }
    /* no drive_torque: not run, whatever the set says */
    log.has_drive_torque = 0;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(out[0].has_mass_grade, 0);
    assert_int_equal(st.mg_status_count[RFE_OK], 0u);
}

/* An invalid mass and grade parameter refuses the run before any row, naming the key; a
 * brake or gear cell the library's integers cannot hold refuses only that sample (the
 * estimate held; the friction side goes on). */
/* REQ-CLI-007 */
static void test_rfe_replay_mass_grade_refusals(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    rfe_replay_stats_t st;
    size_t bad = 0u;
    (void)state;
    make_mg_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    ps.mg[RFE_PK_mg_sd_m0 - RFE_PK_MG_FIRST] = 0.0;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mg_sd_m0);
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mg_sd_m0);
    ps.mg[RFE_PK_mg_sd_m0 - RFE_PK_MG_FIRST] = 500.0;
    rows[1].gear = NAN;
    rows[2].gear = -2e6;
    rows[3].brake = INFINITY;
    rows[4].gear = 2.6; /* the nearest gear, 3: no change, no pause */
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(out[1].mg_status, RFE_ERR_NONFINITE);
    assert_int_equal(out[2].mg_status, RFE_ERR_RANGE);
    assert_int_equal(out[3].mg_status, RFE_ERR_NONFINITE);
    assert_int_equal(out[4].mg_status, RFE_OK);
    assert_true((out[3].mass == out[0].mass) && (out[3].grade == out[0].grade));
    assert_false(rfe_status_is_error((rfe_status_t)out[2].status));
    assert_int_equal(st.mg_status_count[RFE_ERR_NONFINITE], 2u);
}

/* make_mg_log with the front wheels 3 % faster than the body: a drive slip, so the friction
 * estimator's ax row carries information and its mu depends on the mass it is given. */
static void make_mg_slip_log(rfe_sensor_log_t *log, rfe_sensor_row_t rows[N_MG])
{
    size_t i;
    make_mg_log(log, rows);
    for (i = 0u; i < N_MG; ++i) {
        rows[i].omega[RFE_FL] *= 1.03;
        rows[i].omega[RFE_FR] *= 1.03;
    }
}

/* The mass and grade input of row @p i of make_mg_log's rows, written out as the replay
 * builds it (MASS_GRADE.md §10). */
static void mg_input_of(const rfe_sensor_row_t *rows, size_t i, rfe_mass_grade_input_t *mi)
{
    memset(mi, 0, sizeof *mi);
    mi->dt = (i > 0u) ? rows[i].t - rows[i - 1u].t : 0.0;
    mi->v = ((((rows[i].omega[0] + rows[i].omega[1]) + rows[i].omega[2]) + rows[i].omega[3]) / 4.0) *
            0.325;
    mi->torque = rows[i].drive_torque;
    mi->ax = rows[i].ax;
    mi->gear = 3;
    mi->has = RFE_MG_HAS_AX | RFE_MG_HAS_BRAKE | RFE_MG_HAS_PRESSURE | RFE_MG_HAS_GEAR;
}

/* The feed rule, written out: an update (status RFE_OK) whose sd is within rel of its mass. */
static int feed_due(rfe_status_t st, const rfe_mass_grade_estimate_t *e, double rel)
{
    return (st == RFE_OK) && (rel > 0.0) && ((double)e->sd_mass <= rel * (double)e->mass);
}

/* The replay's friction columns (and mass_used) equal a hand-written loop over the library,
 * without the excitation gate (mg_feed_excitation = 0; the gate is the next tests'):
 * each sample the mass and grade step, then the feed rule on that step's estimate, then the
 * friction step (measured velocities: rfe_friction_set_mass; behind the observer:
 * rfe_pipeline_set_mass), bit for bit. mg_feed_sd_rel is set between two samples' sd_mass /
 * mass_est, so the samples before it keep the parameter m (the sd rule) and each one after
 * takes its own sample's mass_est: the mass changes from sample to sample, so a feed of the
 * previous sample's mass gives other bits, and so does a feed that ignores the sd rule. The
 * feed shows in mu (the run without it differs). */
/* REQ-CLI-007 */
static void test_rfe_replay_feeds_the_current_mass_by_the_sd_rule(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    static rfe_est_row_t nofeed[N_MG];
    rfe_replay_stats_t st;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_mass_grade_params_t mp;
    static rfe_pipeline_t pl;
    static rfe_friction_t est;
    static rfe_mass_grade_t mg;
    double rel;
    int observer;
    (void)state;
    make_mg_slip_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    ps.value[RFE_PK_dt] = 0.02; /* the log's period: no gaps */
    ps.mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST] = 0.0; /* the sd rule alone: no gate */
    for (observer = 0; observer <= 1; ++observer) {
        size_t i;
        size_t n_fed = 0u;
        size_t differs = 0u;
        rfe_real_t m_used;
        rfe_status_t (*run)(const rfe_param_set_t *, const rfe_sensor_log_t *, rfe_est_row_t *,
                            rfe_replay_stats_t *, size_t *) =
            observer ? rfe_replay_run_observer_f64 : rfe_replay_run_f64;
        ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = 0.0;
        assert_int_equal(run(&ps, &log, nofeed, &st, NULL), RFE_OK);
        assert_int_equal(st.n_mass_fed, 0u);
        /* between samples N_MG / 2 - 1 and N_MG / 2 (sd_mass / mass_est falls as it learns) */
        rel = nofeed[N_MG / 2u].sd_mass / nofeed[N_MG / 2u].mass;
        assert_true(nofeed[N_MG / 2u - 1u].sd_mass > rel * nofeed[N_MG / 2u - 1u].mass);
        ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = rel;
        assert_int_equal(run(&ps, &log, out, &st, NULL), RFE_OK);
        assert_int_equal(rfe_replay_params_f64(&ps, &p, NULL), RFE_OK);
        assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, NULL), RFE_OK);
        assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, NULL), RFE_OK);
        assert_int_equal(rfe_mass_grade_init(&mg, &mp), RFE_OK);
        if (observer) {
            assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
        } else {
            assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
        }
        m_used = p.vehicle.m;
        for (i = 0u; i < N_MG; ++i) {
            rfe_mass_grade_input_t mi;
            rfe_mass_grade_estimate_t e;
            rfe_estimate_t fe;
            rfe_status_t mst;
            size_t w;
            mg_input_of(rows, i, &mi);
            mst = rfe_mass_grade_step(&mg, &mi, &e);
            assert_int_equal(mst, RFE_OK);
            if (feed_due(mst, &e, rel)) {
                assert_int_equal(observer ? rfe_pipeline_set_mass(&pl, e.mass)
                                          : rfe_friction_set_mass(&est, e.mass),
                                 RFE_OK);
                m_used = e.mass;
                ++n_fed;
            }
            if (observer) {
                rfe_velocity_input_t in;
                rfe_pipeline_out_t o;
                rfe_replay_esc_input_f64(&log, i, (i > 0u) ? i - 1u : SIZE_MAX, &in);
                in.grade = e.grade;
                assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
                fe = o.friction;
                assert_true(out[i].vx == o.velocity.vx);
            } else {
                rfe_sample_t s;
                rfe_replay_sample_from_row_f64(&rows[i], &s);
                assert_false(rfe_status_is_error(rfe_friction_step(&est, &s, &fe)));
            }
            for (w = 0u; w < RFE_WHEELS; ++w) {
                assert_true((out[i].mu[w] == fe.mu[w]) && (out[i].sd[w] == fe.sd[w]));
                assert_int_equal(out[i].valid[w], fe.valid[w]);
                differs += (out[i].mu[w] != nofeed[i].mu[w]) ? 1u : 0u;
            }
            assert_int_equal(out[i].status, fe.status);
            assert_true(out[i].mass_used == m_used);
            /* before the rule trusts the estimate: the parameter m, not a mass_est */
            assert_true((i >= N_MG / 2u) ? (out[i].mass_used == out[i].mass)
                                         : (out[i].mass_used == p.vehicle.m));
            assert_true(nofeed[i].mass_used == p.vehicle.m);
        }
        assert_int_equal(n_fed, N_MG - N_MG / 2u);
        assert_int_equal(st.n_mass_fed, n_fed);
        assert_true(st.mass_used_last == out[N_MG - 1u].mass);
        /* the mass moves each sample, so the previous sample's would differ */
        assert_true(out[N_MG - 1u].mass != out[N_MG - 2u].mass);
        assert_true(differs > 0u);
    }
}

/* mg_feed_sd_rel = 0 never feeds: the friction columns equal those of a run without the mass
 * and grade estimator (--mass-grade off), bit for bit, in both paths. Behind the observer the
 * log has a grade column, so the estimated grade does not reach it either (that is the other
 * way the estimator acts, tested above). */
/* REQ-CLI-007 */
static void test_rfe_replay_feed_off_is_mass_grade_off(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t on[N_MG];
    static rfe_est_row_t off[N_MG];
    rfe_replay_stats_t st;
    int observer;
    (void)state;
    make_mg_slip_log(&log, rows);
    log.has_grade = 1; /* every row's grade 0 */
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_true(ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] == RFE_MG_FEED_SD_REL_DEFAULT);
    ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = 0.0;
    ps.value[RFE_PK_dt] = 0.02;
    for (observer = 0; observer <= 1; ++observer) {
        size_t i;
        size_t w;
        rfe_status_t (*run)(const rfe_param_set_t *, const rfe_sensor_log_t *, rfe_est_row_t *,
                            rfe_replay_stats_t *, size_t *) =
            observer ? rfe_replay_run_observer_f64 : rfe_replay_run_f64;
        ps.mass_grade = 1;
        assert_int_equal(run(&ps, &log, on, &st, NULL), RFE_OK);
        assert_int_equal(st.n_mass_fed, 0u);
        ps.mass_grade = 0;
        assert_int_equal(run(&ps, &log, off, &st, NULL), RFE_OK);
        for (i = 0u; i < N_MG; ++i) {
            assert_int_equal(on[i].has_mass_grade, 1);
            assert_int_equal(off[i].has_mass_grade, 0);
            for (w = 0u; w < RFE_WHEELS; ++w) {
                assert_true((on[i].mu[w] == off[i].mu[w]) && (on[i].sd[w] == off[i].sd[w]));
                assert_int_equal(on[i].valid[w], off[i].valid[w]);
            }
            assert_int_equal(on[i].status, off[i].status);
            assert_true((on[i].vx == off[i].vx) && (on[i].vy == off[i].vy));
        }
    }
    /* a negative value is refused before any row, naming the key */
    {
        size_t bad = 0u;
        ps.mass_grade = 1;
        ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = -0.01;
        assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, &bad), RFE_ERR_PARAM);
        assert_int_equal(bad, RFE_PK_mg_feed_sd_rel);
    }
}

/* make_mg_log's rows 0 .. 39 with the rows from GATE_RESTART on 1.5 s later: a period beyond
 * mg_dt_max (1 s), so the mass and grade estimator starts afresh there (MASS_GRADE.md §4.1). */
#define GATE_RESTART 20u
/* One run of the mass feed's tests on path @p path: 0 double, 1 double behind the observer,
 * 2 q31, 3 q31 behind the observer; the run must succeed; its statistics (q31: the base). */
static rfe_replay_stats_t mg_feed_run_path(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                           rfe_est_row_t *out, int path)
{
    rfe_replay_stats_t st;
    rfe_replay_q31_stats_t sq;
    if (path < 2) {
        assert_int_equal((path == 0) ? rfe_replay_run_f64(ps, log, out, &st, NULL)
                                     : rfe_replay_run_observer_f64(ps, log, out, &st, NULL),
                         RFE_OK);
        return st;
    }
    assert_int_equal((path == 2) ? rfe_replay_run_q31(ps, log, out, &sq, NULL, NULL)
                                 : rfe_replay_run_observer_q31(ps, log, out, &sq, NULL, NULL),
                     RFE_OK);
    return sq.base;
}

/* Each of the two mg_feed_* keys @p k1, @p k2 set to -0.1, NaN and infinity: the double and the
 * q31 replay refuse the run before any row, naming that key; the key is restored after. */
static void mg_feed_keys_refused(rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                 rfe_est_row_t *out, size_t k1, size_t k2)
{
    const double bad_values[3] = {-0.1, NAN, INFINITY};
    rfe_replay_stats_t st;
    rfe_replay_q31_stats_t sq;
    size_t i;
    for (i = 0u; i < 6u; ++i) {
        const size_t k = (i < 3u) ? k1 : k2;
        const double keep = ps->mg[k - RFE_PK_MG_FIRST];
        size_t bad = 0u;
        ps->mg[k - RFE_PK_MG_FIRST] = bad_values[i % 3u];
        assert_int_equal(rfe_replay_run_f64(ps, log, out, &st, &bad), RFE_ERR_PARAM);
        assert_int_equal(bad, k);
        bad = 0u;
        assert_int_equal(rfe_replay_run_q31(ps, log, out, &sq, NULL, &bad), RFE_ERR_PARAM);
        assert_int_equal(bad, k);
        ps->mg[k - RFE_PK_MG_FIRST] = keep;
    }
}

/* Updates after a start the gate needs: the excitation key is set to GATE_OPEN - 0.5 updates'
 * worth of |ax| dt, so it opens at the GATE_OPEN-th update after the start (the sums of
 * GATE_OPEN - 1 and GATE_OPEN equal terms differ from that key by half a term, far more than
 * their rounding, a few 1e-16 relative). */
#define GATE_OPEN 10u

/* The gate of the mass feed (mg_feed_excitation, mg_feed_ax_min; MASS_GRADE.md §10), in
 * double, q31 and behind the observer alike: with the sd rule passing every update
 * (mg_feed_sd_rel = 1: sd_mass <= mass_est from the start, mg_sd_m0 500 kg on 1830 kg) the
 * friction estimator keeps the parameter m until the GATE_OPEN-th update after the start
 * (|ax| dt summed from the second sample: every sample is an update, the constant ax of
 * make_mg_log, 0.794 m/s^2, over 0.02 s), takes each sample's mass_est from there, keeps the
 * last one through the restart at GATE_RESTART (the sum starts again from 0 there) until the
 * GATE_OPEN-th update after it, and takes each again from there. Written out from the rule,
 * not from the replay; a gate that is not reset at the restart feeds rows 20 .. 29, one that
 * is not there feeds rows 0 .. 9. Every arithmetic opens it at the same row (the sum is of
 * the log's double values). With mg_feed_ax_min above |ax| nothing counts and nothing is fed;
 * a negative, NaN or infinite key is refused before any row, naming it. */
/* REQ-CLI-007 */
static void test_rfe_replay_gate_holds_the_feed_until_the_excitation(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    rfe_replay_stats_t st;
    rfe_replay_q31_stats_t sq;
    const double ax = 0.5 + 9.81 * sin(0.03); /* make_mg_log's */
    size_t i;
    int path;
    (void)state;
    make_mg_log(&log, rows);
    for (i = GATE_RESTART; i < N_MG; ++i) {
        rows[i].t += 1.5;
    }
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_true(ps.mg[RFE_PK_mg_dt_max - RFE_PK_MG_FIRST] < 1.5 + 0.02);
    assert_true(ps.mg[RFE_PK_mg_feed_ax_min - RFE_PK_MG_FIRST] <= ax);
    ps.mass_grade = 1;
    ps.value[RFE_PK_dt] = 0.02;
    ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = 1.0;
    ps.mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST] = ((double)GATE_OPEN - 0.5) * 0.02 * ax;
    for (path = 0; path < 4; ++path) { /* double, double observer, q31, q31 observer */
        const double m = ps.value[RFE_PK_m];
        size_t n_fed = 0u;
        double exc_end;
        st = mg_feed_run_path(&ps, &log, out, path);
        assert_int_equal(st.mg_status_count[RFE_OK], N_MG); /* every sample an update */
        for (i = 0u; i < N_MG; ++i) {
            const int after_restart = (i >= GATE_RESTART) ? 1 : 0;
            const size_t since = after_restart ? i - GATE_RESTART : i; /* updates after the start */
            if (since >= GATE_OPEN) {
                assert_true(out[i].mass_used == out[i].mass); /* fed this sample's */
                ++n_fed;
            } else if (after_restart) {
                assert_true(out[i].mass_used == out[GATE_RESTART - 1u].mass); /* the last fed */
            } else {
                assert_true(out[i].mass_used == m); /* the parameter m */
            }
        }
        assert_int_equal(st.n_mass_fed, n_fed);
        assert_int_equal(n_fed, 2u * (GATE_RESTART - GATE_OPEN)); /* 10 + 10 */
        /* the restart's mass differs from the one held, so holding shows */
        assert_true(out[GATE_RESTART].mass != out[GATE_RESTART - 1u].mass);
        /* the sum at the end: the N_MG - GATE_RESTART - 1 updates after the restart's start;
         * that many roundings of a few 1e-16 relative each, so 1e-13 relative */
        exc_end = (double)(N_MG - GATE_RESTART - 1u) * 0.02 * ax;
        assert_true(fabs(st.mg_excitation - exc_end) <= 1e-13 * exc_end);
    }
    /* mg_feed_ax_min above |ax|: nothing counts, nothing fed */
    ps.mg[RFE_PK_mg_feed_ax_min - RFE_PK_MG_FIRST] = ax + 0.01;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(st.n_mass_fed, 0u);
    assert_true(st.mg_excitation == 0.0);
    assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &sq, NULL, NULL), RFE_OK);
    assert_int_equal(sq.base.n_mass_fed, 0u);
    ps.mg[RFE_PK_mg_feed_ax_min - RFE_PK_MG_FIRST] = RFE_MG_FEED_AX_MIN_DEFAULT;
    mg_feed_keys_refused(&ps, &log, out, RFE_PK_mg_feed_excitation, RFE_PK_mg_feed_ax_min);
}

/* make_mg_log's rows whose wheels are 10 % faster than the car (measured vx = their speed /
 * 1.1: a slip of 0.1 over mg_feed_slip_max's 0.05), SLIP_FROM .. SLIP_TO - 1. */
#define SLIP_FROM 15u
#define SLIP_TO 20u

/* The slip tests' log and parameters: make_mg_log's rows with a measured vx (vy = 0, yaw_acc =
 * 0) equal to the wheels' speed, except rows SLIP_FROM .. SLIP_TO - 1, where the wheels run 1.1
 * times vx (a slip of 0.1); the default preset with the mass and grade estimator at the log's
 * 50 Hz, the feed's sd rule passing every update, no band, and the excitation gate opening at
 * row GATE_OPEN. */
static void make_slip_log(rfe_sensor_log_t *log, rfe_sensor_row_t *rows, rfe_param_set_t *ps)
{
    const double ax = 0.5 + 9.81 * sin(0.03); /* make_mg_log's */
    size_t i;
    make_mg_log(log, rows);
    assert_int_equal(rfe_param_set_preset_f64(ps, RFE_PRESET_DEFAULT), 0);
    log->has_velocity = 1;
    for (i = 0u; i < N_MG; ++i) {
        const double v_w = rows[i].omega[0] * ps->value[RFE_PK_R]; /* the wheels' speed */
        rows[i].vx = ((i >= SLIP_FROM) && (i < SLIP_TO)) ? v_w / 1.1 : v_w;
    }
    ps->mass_grade = 1;
    ps->value[RFE_PK_dt] = 0.02;
    ps->mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = 1.0;
    ps->mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST] = 0.0;
    ps->mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST] = ((double)GATE_OPEN - 0.5) * 0.02 * ax;
}

/* The feed's wheel-slip hold (mg_feed_slip_max; MASS_GRADE.md §10), in double, q31 and behind
 * the observer with the log's measured vx: the wheels' speeds are the same on every row (so
 * is the mass and grade estimate), only the car's vx says that rows SLIP_FROM .. SLIP_TO - 1
 * slip. With the gate of the test above (open at the GATE_OPEN-th update after its sum
 * starts) and the sd rule passing every update, the friction estimator takes each row's mass
 * from row GATE_OPEN to SLIP_FROM - 1, keeps row SLIP_FROM - 1's through the slip (each of
 * those updates counted in n_feed_slip), and, the slip having emptied the sum, keeps it
 * until the GATE_OPEN-th update after the slip, then takes each row's again. Written out from
 * the rule; a hold that does not empty the sum feeds from row SLIP_TO, no hold feeds the slip
 * rows. mg_feed_slip_max = 0 feeds every row from GATE_OPEN on. A negative, NaN or infinite
 * mg_feed_slip_max or mg_feed_band is refused before any row, naming it. The filter's own
 * slip pause (mg_slip_max, which the log's measured vx would trigger on the same rows: the
 * next test) is off here, so that the slip rows are updates, as they are behind the observer
 * without a measured vx, where this hold is the only slip guard. */
/* REQ-CLI-007 */
static void test_rfe_replay_slip_holds_the_feed_and_empties_the_gate(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    rfe_replay_stats_t st;
    size_t i;
    int path;
    (void)state;
    make_slip_log(&log, rows, &ps);
    /* on the slip rows |v_w - vx| / vx = (1.1 - 1) = 0.1, twice the default key */
    assert_true(ps.mg[RFE_PK_mg_feed_slip_max - RFE_PK_MG_FIRST] == 0.05);
    ps.mg[RFE_PK_mg_slip_max - RFE_PK_MG_FIRST] = 0.0; /* the filter's pause off */
    for (path = 0; path < 4; ++path) { /* double, double observer, q31, q31 observer */
        const double m = ps.value[RFE_PK_m];
        size_t n_fed = 0u;
        st = mg_feed_run_path(&ps, &log, out, path);
        assert_int_equal(st.mg_status_count[RFE_OK], N_MG); /* every sample an update */
        for (i = 0u; i < N_MG; ++i) {
            if (((i >= GATE_OPEN) && (i < SLIP_FROM)) || (i >= SLIP_TO - 1u + GATE_OPEN)) {
                assert_true(out[i].mass_used == out[i].mass); /* fed this sample's */
                ++n_fed;
            } else if (i >= SLIP_FROM) {
                assert_true(out[i].mass_used == out[SLIP_FROM - 1u].mass); /* the last fed */
            } else {
                assert_true(out[i].mass_used == m); /* the parameter m */
            }
        }
        /* the held mass differs from the rows' own, so holding shows */
        assert_true(out[SLIP_FROM].mass != out[SLIP_FROM - 1u].mass);
        assert_int_equal(st.n_mass_fed, n_fed);
        assert_int_equal(n_fed, (SLIP_FROM - GATE_OPEN) + (N_MG - (SLIP_TO - 1u + GATE_OPEN)));
        assert_int_equal(st.n_feed_slip, SLIP_TO - SLIP_FROM);
        assert_int_equal(st.n_feed_band, 0u);
    }
    /* no slip hold: every row from GATE_OPEN on fed */
    ps.mg[RFE_PK_mg_feed_slip_max - RFE_PK_MG_FIRST] = 0.0;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(st.n_mass_fed, N_MG - GATE_OPEN);
    assert_int_equal(st.n_feed_slip, 0u);
    ps.mg[RFE_PK_mg_feed_slip_max - RFE_PK_MG_FIRST] = RFE_MG_FEED_SLIP_MAX_DEFAULT;
    mg_feed_keys_refused(&ps, &log, out, RFE_PK_mg_feed_slip_max, RFE_PK_mg_feed_band);
}

/* The filter's own slip pause through the replay (mg_slip_max; MASS_GRADE.md §4.2, §10 "The
 * slip pause"): on the previous test's log, whose measured vx says rows SLIP_FROM .. SLIP_TO -
 * 1 slip by 0.1, the replay hands the row's vx to the estimator in double, q31 and behind the
 * observer (a measured vx is handed whichever velocity path runs), so exactly those rows are
 * held with status 7: mass and grade kept at row SLIP_FROM - 1's. No update slips, so the
 * feed's hold counts none and the gate's sum is not emptied: the feed (gate open at
 * GATE_OPEN, sd rule passing every update) takes each update's mass from GATE_OPEN on, keeps
 * the held one through the slip, and takes row SLIP_TO's at once (the mass there learned
 * without the slip). Fails without the replay handing vx (the slip rows would be updates). */
/* REQ-CLI-007 */
static void test_rfe_replay_slip_pauses_the_filter(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    rfe_replay_stats_t st;
    size_t i;
    int path;
    (void)state;
    make_slip_log(&log, rows, &ps);
    /* 0.1 of slip, twice the default; the others' 0 (the wheels' speed is the row's vx) */
    assert_true(ps.mg[RFE_PK_mg_slip_max - RFE_PK_MG_FIRST] == 0.05);
    for (path = 0; path < 4; ++path) { /* double, double observer, q31, q31 observer */
        size_t n_fed = 0u;
        st = mg_feed_run_path(&ps, &log, out, path);
        assert_int_equal(st.mg_status_count[RFE_MG_PAUSED_SLIP], SLIP_TO - SLIP_FROM);
        assert_int_equal(st.mg_status_count[RFE_OK], N_MG - (SLIP_TO - SLIP_FROM));
        for (i = 0u; i < N_MG; ++i) {
            const int slip = ((i >= SLIP_FROM) && (i < SLIP_TO)) ? 1 : 0;
            assert_int_equal(out[i].mg_status, slip ? (int)RFE_MG_PAUSED_SLIP : (int)RFE_OK);
            if (slip) {
                assert_true(out[i].mass == out[SLIP_FROM - 1u].mass); /* held */
                assert_true(out[i].grade == out[SLIP_FROM - 1u].grade);
                assert_true(out[i].mass_used == out[SLIP_FROM - 1u].mass); /* the last fed */
            } else if (i >= GATE_OPEN) {
                assert_true(out[i].mass_used == out[i].mass); /* fed this sample's */
                ++n_fed;
            } else {
                assert_true(out[i].mass_used == ps.value[RFE_PK_m]);
            }
        }
        /* the first update after the slip moves the mass, and is fed at once */
        assert_true(out[SLIP_TO].mass != out[SLIP_FROM - 1u].mass);
        assert_int_equal(st.n_mass_fed, n_fed);
        assert_int_equal(n_fed, N_MG - GATE_OPEN - (SLIP_TO - SLIP_FROM));
        assert_int_equal(st.n_feed_slip, 0u);
    }
}

/* The filter's curve pause through the replay (mg_ay_max; MASS_GRADE.md §4.2, §10 "The curve
 * pause"): make_mg_log's drive with |ay| = 2 m/s^2 on rows SLIP_FROM .. SLIP_TO - 1 and 0
 * elsewhere, mg_ay_max = 1 and mg_t_curve = 0: the replay hands every row's ay to the
 * estimator in double, q31 and behind the observer, so exactly those rows are held with status
 * 8, mass and grade kept at row SLIP_FROM - 1's, and the next row updates. With the default
 * mg_ay_max = 0 no row is held. Fails without the replay handing ay (no row held). */
/* REQ-CLI-007 */
static void test_rfe_replay_curve_pauses_the_filter(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    rfe_replay_stats_t st;
    size_t i;
    int path;
    (void)state;
    make_mg_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    ps.value[RFE_PK_dt] = 0.02;
    for (i = 0u; i < N_MG; ++i) {
        rows[i].ay = ((i >= SLIP_FROM) && (i < SLIP_TO)) ? 2.0 : 0.0;
    }
    assert_true(ps.mg[RFE_PK_mg_ay_max - RFE_PK_MG_FIRST] == 0.0); /* off by default */
    for (path = 0; path < 4; ++path) { /* double, double observer, q31, q31 observer */
        st = mg_feed_run_path(&ps, &log, out, path);
        assert_int_equal(st.mg_status_count[RFE_MG_PAUSED_CURVE], 0u);
    }
    ps.mg[RFE_PK_mg_ay_max - RFE_PK_MG_FIRST] = 1.0;
    ps.mg[RFE_PK_mg_t_curve - RFE_PK_MG_FIRST] = 0.0;
    for (path = 0; path < 4; ++path) {
        st = mg_feed_run_path(&ps, &log, out, path);
        assert_int_equal(st.mg_status_count[RFE_MG_PAUSED_CURVE], SLIP_TO - SLIP_FROM);
        for (i = SLIP_FROM; i < SLIP_TO; ++i) {
            assert_int_equal(out[i].mg_status, (int)RFE_MG_PAUSED_CURVE);
            assert_true(out[i].mass == out[SLIP_FROM - 1u].mass); /* held */
            assert_true(out[i].grade == out[SLIP_FROM - 1u].grade);
        }
        assert_int_equal(out[SLIP_TO].mg_status, (int)RFE_OK);
        assert_true(out[SLIP_TO].mass != out[SLIP_FROM - 1u].mass);
    }
}

/* A bad measured vx reaches the mass and grade estimator as its slip reference, which refuses
 * that sample as it refuses its other inputs (MASS_GRADE.md §10 "The slip pause"): in double
 * and q31, a NaN vx cell gives mg_status 17, a vx beyond 100 m/s 18 (q31: beyond Q24's 128
 * m/s it saturates, then is refused as beyond the limit), the estimate held there; the rows
 * around update. */
/* REQ-CLI-007 */
static void test_rfe_replay_mass_grade_bad_vx_refused(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    rfe_replay_stats_t st;
    rfe_replay_q31_stats_t sq;
    size_t i;
    int path;
    (void)state;
    make_mg_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    ps.value[RFE_PK_dt] = 0.02;
    log.has_velocity = 1;
    for (i = 0u; i < N_MG; ++i) {
        rows[i].vx = rows[i].omega[0] * ps.value[RFE_PK_R]; /* no slip */
    }
    rows[3].vx = NAN;
    rows[5].vx = 150.0;
    for (path = 0; path < 2; ++path) {
        if (path == 0) {
            assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
        } else {
            assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &sq, NULL, NULL), RFE_OK);
            st = sq.base;
        }
        assert_int_equal(out[3].mg_status, RFE_ERR_NONFINITE);
        assert_int_equal(out[5].mg_status, RFE_ERR_RANGE);
        assert_true((out[3].mass == out[2].mass) && (out[3].grade == out[2].grade));
        assert_true((out[5].mass == out[4].mass) && (out[5].grade == out[4].grade));
        assert_int_equal(st.mg_status_count[RFE_OK], N_MG - 2u);
    }
}

/* The feed's band around the parameter m (mg_feed_band; MASS_GRADE.md §10), in double and
 * q31, measured velocities and behind the observer: with the sd rule passing every update
 * and no gate, each row's mass is fed exactly when |mass_est - m| <= mg_feed_band * m, else
 * the last fed (at first m) is kept and the row counted in n_feed_band. The band is set
 * between the smallest and the largest |mass_est - m| / m of the run (from a run with no
 * band), so both branches occur; written out from the rule on the rows' own values. A band
 * below every deviation feeds nothing (all N_MG rows refused), 0 feeds every row. */
/* REQ-CLI-007 */
static void test_rfe_replay_band_refuses_a_mass_far_from_m(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    rfe_replay_stats_t st;
    double dev_min = INFINITY;
    double dev_max = 0.0;
    double m;
    size_t i;
    int path;
    (void)state;
    make_mg_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    ps.value[RFE_PK_dt] = 0.02;
    ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = 1.0;
    ps.mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST] = 0.0; /* no gate */
    ps.mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST] = 0.0;
    /* m a quarter above the estimator's start (mg_m0, the first rows' mass): every row's
     * mass then differs from m, so a band can lie below all of them */
    ps.value[RFE_PK_m] = 1.25 * ps.mg[RFE_PK_mg_m0 - RFE_PK_MG_FIRST];
    m = ps.value[RFE_PK_m];
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(st.n_mass_fed, N_MG); /* band 0: every update fed */
    for (i = 0u; i < N_MG; ++i) {
        const double d = fabs(out[i].mass - m) / m;
        dev_min = (d < dev_min) ? d : dev_min;
        dev_max = (d > dev_max) ? d : dev_max;
    }
    assert_true((dev_min > 0.0) && (dev_min < dev_max)); /* the band can split the rows */
    ps.mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST] = 0.5 * (dev_min + dev_max);
    for (path = 0; path < 4; ++path) { /* double, double observer, q31, q31 observer */
        const double band = ps.mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST];
        double last = m;
        size_t n_fed = 0u;
        size_t n_refused = 0u;
        st = mg_feed_run_path(&ps, &log, out, path);
        assert_int_equal(st.mg_status_count[RFE_OK], N_MG);
        for (i = 0u; i < N_MG; ++i) {
            if (fabs(out[i].mass - m) <= band * m) {
                last = out[i].mass;
                ++n_fed;
            } else {
                ++n_refused;
            }
            assert_true(out[i].mass_used == last);
        }
        assert_true((n_fed > 0u) && (n_refused > 0u)); /* both branches ran */
        assert_int_equal(st.n_mass_fed, n_fed);
        assert_int_equal(st.n_feed_band, n_refused);
        assert_int_equal(st.n_feed_slip, 0u);
    }
    /* a band below every deviation: nothing fed, every update refused and counted */
    ps.mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST] = 0.5 * dev_min;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(st.n_mass_fed, 0u);
    assert_int_equal(st.n_feed_band, N_MG);
    assert_true(out[N_MG - 1u].mass_used == m);
}

/* ------------------------------------------------------------ mass and grade in q31 */

/* A bundled mass and grade log with gear shifts (50 Hz; shifts at 5, 11, 19, 30 s): its
 * first MGQ_ROWS rows, MGQ_LIGHT_ROWS in light mode (test_light.h: under valgrind). Light:
 * 6 s, the first shift's pause (status 6) at 5 s and the feed from row ~230 inside, so each
 * count asserted below can fail either way; full: 30 s, three shifts. */
#define MGQ_LOG "scenarios/mass_grade/car_gear_shift.csv"
#define MGQ_ROWS 1500u
#define MGQ_LIGHT_ROWS 300u

/* The log (its metadata applied to @p ps over the default preset, the estimator on) and, for
 * the measured path, velocities made up in memory: vx the rear wheels' speed times R, vy and
 * the yaw acceleration 0 (the comparison below is bit for bit, not about accuracy). */
static void mgq_log_read(rfe_sensor_log_t *log, rfe_param_set_t *ps)
{
    rfe_io_error_t err;
    size_t i;
    memset(log, 0, sizeof *log);
    assert_int_equal(rfe_sensor_log_read(MGQ_LOG, log, &err), 0);
    assert_int_equal(log->has_drive_torque, 1);
    assert_int_equal(log->has_grade, 0); /* the observer takes the estimated grade */
    assert_true(log->n_rows > MGQ_ROWS);
    log->n_rows = rfe_test_light() ? MGQ_LIGHT_ROWS : MGQ_ROWS;
    assert_int_equal(rfe_param_set_preset_f64(ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_param_set_apply_meta(ps, log, MGQ_LOG, &err), 0);
    assert_true(ps->value[RFE_PK_dt] == 0.02); /* the log's period: no gaps */
    ps->mass_grade = 1;
    for (i = 0u; i < log->n_rows; ++i) {
        log->rows[i].vx = 0.5 * (log->rows[i].omega[RFE_RL] + log->rows[i].omega[RFE_RR]) *
                          ps->value[RFE_PK_R];
    }
}

/* The fixed-point mass and grade sample of row @p i, written out from MASS_GRADE.md §10 and
 * the Q formats of mass_grade_q31.h (q_of: rounded to nearest, ties up): the wheels' mean
 * speed times R, the period since @p t_last (NULL: the first sample), the pressure in MPa,
 * the nearest gear, brake pressed at >= 0.5, every column's bit. */
static void mgq_input_of(const rfe_sensor_row_t *row, const double *t_last, double R,
                         rfe_mass_grade_input_q31_t *mi)
{
    memset(mi, 0, sizeof *mi);
    mi->dt = q_of((t_last != NULL) ? row->t - *t_last : 0.0, 30);
    mi->v = q_of(((((row->omega[0] + row->omega[1]) + row->omega[2]) + row->omega[3]) / 4.0) * R, 24);
    mi->torque = q_of(row->drive_torque, 14);
    mi->ax = q_of(row->ax, 24);
    mi->p_brake = q_of(row->brake_pressure * 1e-6, 25);
    mi->gear = (int32_t)floor(row->gear + 0.5);
    mi->brake = (row->brake >= 0.5) ? 1u : 0u;
    mi->has = RFE_MG_HAS_AX | RFE_MG_HAS_PRESSURE | RFE_MG_HAS_BRAKE | RFE_MG_HAS_GEAR;
}

/* --real q31 runs the mass and grade estimator's fixed-point twin as the float replay runs
 * the float one: the replay equals a hand-written loop over the Q31 library API bit for bit
 * (measured velocities and behind the observer): each sample the mass and grade step on the
 * sample written out above (its columns the Q values: mass, sd Q14, grade, sd Q29), then the
 * feed rule on that step's values (an update with sd_mass <= mg_feed_sd_rel * mass_est) giving
 * the friction estimator that mass in its Q16 (rfe_friction_set_mass_q31, behind the observer
 * rfe_pipeline_set_mass_q31), then the friction (pipeline) step, behind the observer with
 * that sample's estimated grade. With mg_feed_sd_rel = 0 the friction estimator keeps the
 * parameter m and the mass and grade estimate is the same (one way). On this log the friction
 * estimator is held (not observable) over the light rows, so whether the fed mass changes
 * its estimate is the next test's, on a log with drive slip. */
/* REQ-CLI-007 */
static void test_rfe_replay_q31_mass_grade_is_the_library_loop(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_est_row_t *out;
    rfe_est_row_t *nofeed;
    rfe_replay_q31_stats_t st;
    rfe_mass_grade_params_t mp;
    rfe_mass_grade_params_q31_t mq;
    rfe_params_q31_t pq;
    rfe_velocity_params_q31_t vq;
    static rfe_mass_grade_q31_t mg;
    static rfe_pipeline_q31_t pl;
    static rfe_friction_q31_t est;
    int observer;
    (void)state;
    mgq_log_read(&log, &ps);
    out = calloc(log.n_rows, sizeof *out);
    nofeed = calloc(log.n_rows, sizeof *nofeed);
    assert_non_null(out);
    assert_non_null(nofeed);
    assert_int_equal(RFE_MG_Q_TH, RFE_FIX_Q_ANGLE); /* the grade goes to the observer as is */
    assert_int_equal(RFE_MG_Q_M + 2, RFE_FIX_Q_MASS); /* the mass to the friction estimator */
    for (observer = 0; observer <= 1; ++observer) {
        const double rel = ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST];
        const double need = ps.mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST];
        const double ax_min = ps.mg[RFE_PK_mg_feed_ax_min - RFE_PK_MG_FIRST];
        double excitation = 0.0;
        size_t i;
        size_t n_fed = 0u;
        size_t n_held = 0u;
        size_t n_ok = 0u;
        size_t n_shift = 0u;
        double t_last = 0.0;
        int have_last = 0;
        rfe_fix_t m_used;
        rfe_status_t (*run)(const rfe_param_set_t *, const rfe_sensor_log_t *, rfe_est_row_t *,
                            rfe_replay_q31_stats_t *, uint32_t *, size_t *) =
            observer ? rfe_replay_run_observer_q31 : rfe_replay_run_q31;
        assert_true(rel == RFE_MG_FEED_SD_REL_DEFAULT);
        assert_true((need == RFE_MG_FEED_EXCITATION_DEFAULT) && (ax_min == RFE_MG_FEED_AX_MIN_DEFAULT));
        assert_int_equal(run(&ps, &log, out, &st, NULL, NULL), RFE_OK);
        assert_int_equal(rfe_replay_mass_grade_params_f64(&ps, &mp, NULL), RFE_OK);
        assert_int_equal(rfe_mass_grade_params_to_q31_f64(&mp, &mq), RFE_OK);
        assert_int_equal(rfe_mass_grade_init_q31(&mg, &mq), RFE_OK);
        q31_params_of(&ps, &pq, &vq);
        if (observer) {
            assert_int_equal(rfe_pipeline_init_q31(&pl, &pq, &vq), RFE_OK);
        } else {
            assert_int_equal(rfe_friction_init_q31(&est, &pq), RFE_OK);
        }
        m_used = pq.vehicle.m;
        for (i = 0u; i < log.n_rows; ++i) {
            const rfe_sensor_row_t *row = &log.rows[i];
            rfe_mass_grade_input_q31_t mi;
            rfe_mass_grade_estimate_q31_t e;
            rfe_estimate_q31_t fe;
            rfe_status_t mst;
            size_t w;
            mgq_input_of(row, have_last ? &t_last : NULL, mp.R, &mi);
            mst = rfe_mass_grade_step_q31(&mg, &mi, &e);
            assert_false(rfe_status_is_error(mst)); /* every sample taken (or paused) */
            /* the gate: |ax| dt over the updates after the first sample (no gaps: the only
             * start), those with |ax| >= mg_feed_ax_min */
            if (have_last && (mst == RFE_OK) && (fabs(row->ax) >= ax_min)) {
                excitation += fabs(row->ax) * (row->t - t_last);
            }
            t_last = row->t;
            have_last = 1;
            n_ok += (mst == RFE_OK) ? 1u : 0u;
            n_shift += (mst == RFE_MG_PAUSED_SHIFT) ? 1u : 0u;
            assert_int_equal(out[i].has_mass_grade, 1);
            assert_int_equal(out[i].mg_status, mst);
            assert_true(out[i].mass == ldexp((double)e.mass, -14));
            assert_true(out[i].sd_mass == ldexp((double)e.sd_mass, -14));
            assert_true(out[i].grade == ldexp((double)e.grade, -29));
            assert_true(out[i].sd_grade == ldexp((double)e.sd_grade, -29));
            if ((mst == RFE_OK) &&
                (ldexp((double)e.sd_mass, -14) <= rel * ldexp((double)e.mass, -14)) &&
                (excitation < need)) {
                ++n_held; /* the sd rule alone would feed it */
            } else if ((mst == RFE_OK) &&
                (ldexp((double)e.sd_mass, -14) <= rel * ldexp((double)e.mass, -14))) {
                m_used = e.mass * 4; /* Q14 -> Q16, exact below 32768 kg */
                assert_int_equal(observer ? rfe_pipeline_set_mass_q31(&pl, m_used)
                                          : rfe_friction_set_mass_q31(&est, m_used),
                                 RFE_OK);
                ++n_fed;
            }
            assert_true(out[i].mass_used == ldexp((double)m_used, -16));
            if (observer) {
                rfe_velocity_input_q31_t in;
                rfe_pipeline_out_q31_t o;
                (void)rfe_replay_esc_input_q31(&log, i, (i > 0u) ? i - 1u : SIZE_MAX, &in);
                in.grade = e.grade; /* this sample's estimate, no grade column */
                assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pl, &in, &o)));
                fe = o.friction;
                assert_true(out[i].vx == ldexp((double)o.velocity.vx, -(int)RFE_FIX_Q_SPEED));
            } else {
                rfe_sample_q31_t s;
                assert_int_equal(rfe_replay_sample_q31(row, &s), 0u);
                assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &fe)));
            }
            for (w = 0u; w < RFE_WHEELS; ++w) {
                assert_true(out[i].mu[w] == ldexp((double)fe.mu[w], -(int)RFE_FIX_Q_MU));
                assert_true(out[i].sd[w] == ldexp((double)fe.sd[w], -(int)RFE_FIX_Q_SD));
                assert_int_equal(out[i].valid[w], fe.valid[w]);
            }
            assert_int_equal(out[i].status, fe.status);
        }
        /* the rule both ways: the first samples (sd_mass ~27 % of the mass) are not fed; the
         * gate holds some the sd rule passes (this log's |ax| reaches 1 m/s after its sd_mass
         * 2 %: MASS_GRADE_RESULTS.md, 1.6 -> 2.2 s), so a replay without it fails above */
        assert_true((n_fed > 0u) && (n_fed < n_ok));
        assert_true(n_held > 0u);
        assert_true(st.base.mg_excitation == excitation);
        assert_true(n_shift > 0u);
        assert_int_equal(st.base.n_mass_fed, n_fed);
        assert_int_equal(st.base.mg_status_count[RFE_OK], n_ok);
        assert_int_equal(st.base.mg_status_count[RFE_MG_PAUSED_SHIFT], n_shift);
        assert_true(st.base.mass_used_last == out[log.n_rows - 1u].mass_used);
        assert_int_equal(st.est_sat + st.input_sat, 0u);
        /* without the feed: the parameter m throughout, the same estimate (one way) */
        ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = 0.0;
        assert_int_equal(run(&ps, &log, nofeed, &st, NULL, NULL), RFE_OK);
        ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = rel;
        assert_int_equal(st.base.n_mass_fed, 0u);
        for (i = 0u; i < log.n_rows; ++i) {
            assert_true(nofeed[i].mass_used == ldexp((double)pq.vehicle.m, -16));
            assert_true(nofeed[i].mass == out[i].mass);
        }
    }
    free(out);
    free(nofeed);
    rfe_sensor_log_free(&log);
}

/* The fed mass reaches the fixed-point friction estimator's model: on the drive-slip log (its
 * ax row informative, so mu depends on the mass) with mg_feed_sd_rel between two samples'
 * sd_mass / mass_est (as the float test, without the gate), the rows before the first feed equal those of the
 * run without the feed bit for bit and later ones differ, measured and behind the observer
 * (there the log has a grade column, so the estimated grade does not reach the observer and
 * the mass alone makes the difference). */
/* REQ-CLI-007 */
static void test_rfe_replay_q31_fed_mass_reaches_the_friction_estimator(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    static rfe_est_row_t nofeed[N_MG];
    rfe_replay_q31_stats_t st;
    int observer;
    (void)state;
    make_mg_slip_log(&log, rows);
    log.has_grade = 1; /* every row's grade 0 */
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    ps.value[RFE_PK_dt] = 0.02;
    ps.mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST] = 0.0; /* the sd rule alone: no gate */
    for (observer = 0; observer <= 1; ++observer) {
        size_t i;
        size_t w;
        size_t differs = 0u;
        rfe_status_t (*run)(const rfe_param_set_t *, const rfe_sensor_log_t *, rfe_est_row_t *,
                            rfe_replay_q31_stats_t *, uint32_t *, size_t *) =
            observer ? rfe_replay_run_observer_q31 : rfe_replay_run_q31;
        ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = 0.0;
        assert_int_equal(run(&ps, &log, nofeed, &st, NULL, NULL), RFE_OK);
        ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = nofeed[N_MG / 2u].sd_mass / nofeed[N_MG / 2u].mass;
        assert_true(nofeed[N_MG / 2u - 1u].sd_mass >
                    ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] * nofeed[N_MG / 2u - 1u].mass);
        assert_int_equal(run(&ps, &log, out, &st, NULL, NULL), RFE_OK);
        assert_int_equal(st.base.n_mass_fed, N_MG - N_MG / 2u);
        for (i = 0u; i < N_MG; ++i) {
            size_t d = 0u;
            for (w = 0u; w < RFE_WHEELS; ++w) {
                d += ((out[i].mu[w] != nofeed[i].mu[w]) || (out[i].sd[w] != nofeed[i].sd[w])) ? 1u : 0u;
            }
            if (i < N_MG / 2u) {
                assert_int_equal(d, 0u);
                assert_true(out[i].mass_used == nofeed[i].mass_used);
            } else {
                assert_true(out[i].mass_used == out[i].mass);
            }
            differs += d;
        }
        assert_true(differs > 0u);
    }
}

/* The refusals of the fixed-point mass and grade run: a parameter the double path refuses is
 * named as in double; one beyond its Q format (mg_m_max 2e5 kg > Q14's 131072; g 40 m/s^2
 * > Q26's 32, which the friction estimator's Q24 holds) is RFE_ERR_RANGE naming it, and a
 * combination (each key alone refused by the validation) names none; a set the float accepts outside the fixed-point domain
 * (mg_ut_alpha 0.5: n + lambda = 0.75) is RFE_ERR_PARAM from the init, no key blamed. A cell
 * the sample cannot hold refuses that sample alone: the brake and gear cells as in double
 * (17, 18), a NaN torque or ax (no Q value: 17, as the float library), the estimate held,
 * the friction side going on. A mass beyond the friction estimator's Q16 (>= 32768 kg) is
 * not fed (its mass stays the parameter m). */
/* REQ-CLI-007 */
static void test_rfe_replay_q31_mass_grade_refusals(void **state)
{
    double g0;
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_MG];
    rfe_param_set_t ps;
    static rfe_est_row_t out[N_MG];
    rfe_replay_q31_stats_t st;
    size_t bad = 0u;
    size_t i;
    (void)state;
    make_mg_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    ps.mg[RFE_PK_mg_sd_m0 - RFE_PK_MG_FIRST] = 0.0;
    assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_mg_sd_m0);
    ps.mg[RFE_PK_mg_sd_m0 - RFE_PK_MG_FIRST] = 500.0;
    ps.mg[RFE_PK_mg_m_max - RFE_PK_MG_FIRST] = 2e5;
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_RANGE);
    assert_int_equal(bad, RFE_PK_mg_m_max);
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st.base, NULL), RFE_OK); /* double: fine */
    ps.mg[RFE_PK_mg_m_max - RFE_PK_MG_FIRST] = 4000.0;
    g0 = ps.value[RFE_PK_g];
    ps.value[RFE_PK_g] = 40.0; /* the friction estimator's Q24 holds it, the estimator's Q26 not */
    assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_RANGE);
    assert_int_equal(bad, RFE_PK_g);
    ps.mass_grade = 0;
    assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &st, NULL, NULL), RFE_OK);
    ps.mass_grade = 1;
    ps.value[RFE_PK_g] = g0;
    /* the AUKF's mv_stop beyond Q24 (+-128), valid only with a larger q_mv0: no key alone */
    assert_int_equal(rfe_param_set_mass_grade_f64(&ps, RFE_MG_CAR, RFE_MG_SEED), 0);
    ps.mg[RFE_PK_mg_mv_stop - RFE_PK_MG_FIRST] = 2e5;
    ps.mg[RFE_PK_mg_q_mv0 - RFE_PK_MG_FIRST] = 1e5;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st.base, NULL), RFE_OK);
    assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_RANGE);
    assert_int_equal(bad, RFE_PK_NONE);
    assert_int_equal(rfe_param_set_mass_grade_f64(&ps, RFE_MG_CAR, RFE_MG_RECOMMENDED), 0);
    ps.mg[RFE_PK_mg_ut_alpha - RFE_PK_MG_FIRST] = 0.5;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st.base, NULL), RFE_OK);
    bad = 0u;
    assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &st, NULL, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_NONE);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.mass_grade = 1;
    rows[1].gear = NAN;
    rows[2].gear = -2e6;
    rows[3].brake = INFINITY;
    rows[4].drive_torque = NAN;
    rows[5].ax = NAN; /* an input of the friction side too: the row's bad bit, as read */
    rows[5].bad = 1u << RFE_CELL_NONFINITE;
    rows[6].gear = 2.6; /* the nearest gear, 3: no change, no pause */
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, out, &st, NULL, NULL), RFE_OK);
    assert_int_equal(out[1].mg_status, RFE_ERR_NONFINITE);
    assert_int_equal(out[2].mg_status, RFE_ERR_RANGE);
    assert_int_equal(out[3].mg_status, RFE_ERR_NONFINITE);
    assert_int_equal(out[4].mg_status, RFE_ERR_NONFINITE);
    assert_int_equal(out[5].mg_status, RFE_ERR_NONFINITE);
    assert_int_equal(out[6].mg_status, RFE_OK);
    for (i = 1u; i <= 5u; ++i) {
        assert_true((out[i].mass == out[0].mass) && (out[i].grade == out[0].grade));
        assert_true(out[i].sd_mass == out[0].sd_mass);
    }
    assert_true(out[6].sd_mass < out[0].sd_mass); /* it learns again */
    assert_false(rfe_status_is_error((rfe_status_t)out[4].status));
    assert_int_equal(out[5].status, RFE_ERR_NONFINITE);
    assert_int_equal(st.base.mg_status_count[RFE_ERR_NONFINITE], 4u);
    assert_int_equal(st.input_sat, 0u); /* a NaN is refused, not rounded to 0 */
    /* a truck's mass: beyond Q16, never fed, though every update passes the rule */
    make_mg_log(&log, rows);
    ps.value[RFE_PK_dt] = 0.02;
    ps.mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = 1.0;
    ps.mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST] = 0.0; /* every update: no gate */
    /* no band: 40 t is far outside m's, and the band would refuse it before the Q16 check */
    ps.mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST] = 0.0;
    ps.mg[RFE_PK_mg_m0 - RFE_PK_MG_FIRST] = 40000.0;
    ps.mg[RFE_PK_mg_m_min - RFE_PK_MG_FIRST] = 33000.0;
    ps.mg[RFE_PK_mg_m_max - RFE_PK_MG_FIRST] = 60000.0;
    assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &st, NULL, NULL), RFE_OK);
    assert_int_equal(st.base.mg_status_count[RFE_OK], N_MG);
    assert_int_equal(st.base.n_mass_fed, 0u);
    assert_int_equal(st.base.n_feed_band, 0u); /* due every time: the Q16 check refused it */
    for (i = 0u; i < N_MG; ++i) {
        assert_true(out[i].mass >= 32768.0);
        assert_true(out[i].mass_used == ps.value[RFE_PK_m]);
    }
    /* the same with a car's mass: fed at every sample */
    ps.mg[RFE_PK_mg_m0 - RFE_PK_MG_FIRST] = 1830.0;
    ps.mg[RFE_PK_mg_m_min - RFE_PK_MG_FIRST] = 500.0;
    ps.mg[RFE_PK_mg_m_max - RFE_PK_MG_FIRST] = 4000.0;
    assert_int_equal(rfe_replay_run_q31(&ps, &log, out, &st, NULL, NULL), RFE_OK);
    assert_int_equal(st.base.n_mass_fed, N_MG);
}

/* The per-log state: rows stepped one by one (the same state, begun once) give the whole-log
 * run's rows and counters, in double and in q31, measured and behind the observer; a step
 * refused (time not after the last row's) changes nothing. REQ-CLI-003 */
static void test_rfe_replay_state_steps_as_the_run(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_io_error_t err;
    rfe_est_row_t run[3];
    rfe_est_row_t one[3];
    rfe_replay_stats_t st_run;
    rfe_replay_stats_t st_one;
    rfe_replay_q31_stats_t q_run;
    rfe_replay_q31_stats_t q_one;
    struct rfe_replay_state_f64 *s = calloc(1u, rfe_replay_state_size_f64());
    rfe_replay_q31_state_t *q = calloc(1u, rfe_replay_state_size_q31());
    size_t i;
    int observer;
    (void)state;
    assert_non_null(s);
    assert_non_null(q);
    assert_int_equal(rfe_sensor_log_read(DATA "good_esc.csv", &log, &err), 0);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    for (observer = 0; observer <= 1; ++observer) {
        /* the fields a step does not write (vx .. of a measuring run) equal too */
        memset(run, 0, sizeof run);
        memset(one, 0, sizeof one);
        assert_int_equal(observer ? rfe_replay_run_observer_f64(&ps, &log, run, &st_run, NULL)
                                  : rfe_replay_run_f64(&ps, &log, run, &st_run, NULL),
                         RFE_OK);
        assert_int_equal(rfe_replay_begin_f64(s, &ps, &log, observer, NULL), RFE_OK);
        for (i = 0u; i < log.n_rows; ++i) {
            assert_int_equal(rfe_replay_step_f64(s, &log.rows[i], &one[i]), RFE_OK);
            if (i == 1u) { /* the same row again: refused, nothing changed */
                rfe_est_row_t again = one[i];
                assert_int_equal(rfe_replay_step_f64(s, &log.rows[i], &again), RFE_ERR_RANGE);
                assert_memory_equal(&again, &one[i], sizeof again);
            }
            assert_true(one[i].mu[RFE_FL] == run[i].mu[RFE_FL]);
            assert_true(one[i].sd[RFE_RR] == run[i].sd[RFE_RR]);
            assert_true(one[i].vx == run[i].vx);
            assert_int_equal(one[i].status, run[i].status);
        }
        assert_int_equal(rfe_replay_get_stats_f64(s, &st_one), RFE_OK);
        assert_memory_equal(&st_one, &st_run, sizeof st_one);
        memset(run, 0, sizeof run);
        memset(one, 0, sizeof one);
        assert_int_equal(observer ? rfe_replay_run_observer_q31(&ps, &log, run, &q_run, NULL, NULL)
                                  : rfe_replay_run_q31(&ps, &log, run, &q_run, NULL, NULL),
                         RFE_OK);
        assert_int_equal(rfe_replay_begin_q31(q, &ps, &log, observer, NULL), RFE_OK);
        assert_int_equal(rfe_replay_feed_q31(q, log.rows, 1u, one, NULL), RFE_OK);
        assert_int_equal(rfe_replay_step_q31(q, &log.rows[0], &one[1], NULL), RFE_ERR_RANGE);
        assert_int_equal(rfe_replay_feed_q31(q, &log.rows[1], log.n_rows - 1u, &one[1], NULL),
                         RFE_OK);
        for (i = 0u; i < log.n_rows; ++i) {
            assert_true(one[i].mu[RFE_FL] == run[i].mu[RFE_FL]);
            assert_true(one[i].vx == run[i].vx);
            assert_int_equal(one[i].status, run[i].status);
        }
        assert_int_equal(rfe_replay_get_stats_q31(q, &q_one), RFE_OK);
        assert_memory_equal(&q_one, &q_run, sizeof q_one);
    }
    rfe_sensor_log_free(&log);
    free(s);
    free(q);
}

/* The state's entries validate their inputs: NULL, a step before a successful begin, wheel
 * speeds not in rad/s (the state untouched). REQ-CLI-003 */
static void test_rfe_replay_state_refusals(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_row_t rows[N_ROWS];
    rfe_param_set_t ps;
    rfe_est_row_t out;
    rfe_replay_stats_t st;
    rfe_replay_q31_stats_t qst;
    struct rfe_replay_state_f64 *s = calloc(1u, rfe_replay_state_size_f64());
    rfe_replay_q31_state_t *q = calloc(1u, rfe_replay_state_size_q31());
    (void)state;
    assert_non_null(s);
    assert_non_null(q);
    make_log(&log, rows);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_PAPER), 0);
    assert_int_equal(rfe_replay_step_f64(s, &rows[0], &out), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_replay_step_q31(q, &rows[0], &out, NULL), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_replay_begin_f64(NULL, &ps, &log, 0, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_begin_q31(q, &ps, NULL, 0, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_step_f64(s, NULL, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_step_q31(q, &rows[0], NULL, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_feed_f64(s, NULL, 1u, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_feed_q31(q, rows, 1u, NULL, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_get_stats_f64(s, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_get_stats_q31(NULL, &qst), RFE_ERR_NULL);
    log.omega_linear = 1;
    assert_int_equal(rfe_replay_begin_f64(s, &ps, &log, 1, NULL), RFE_ERR_RANGE);
    assert_int_equal(rfe_replay_begin_q31(q, &ps, &log, 0, NULL), RFE_ERR_RANGE);
    assert_int_equal(rfe_replay_step_f64(s, &rows[0], &out), RFE_ERR_NOT_INITIALISED);
    log.omega_linear = 0;
    assert_int_equal(rfe_replay_begin_f64(s, &ps, &log, 0, NULL), RFE_OK);
    assert_int_equal(rfe_replay_feed_f64(s, rows, N_ROWS, (rfe_est_row_t[N_ROWS]){0}), RFE_OK);
    assert_int_equal(rfe_replay_get_stats_f64(s, &st), RFE_OK);
    assert_int_equal(st.n_steps, N_ROWS);
    free(s);
    free(q);
}

/* The ESC sample of log row i for tools that step the observer themselves (the PIL data
 * generator, the soak): the period since row prev (none: prev >= i, dt 0), the optional
 * columns the log has, and in q31 those values rounded to their Q formats. REQ-CLI-003 */
static void test_rfe_replay_esc_input_of_a_log_row(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t q;
    uint32_t sat;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_esc.csv", &log, &err), 0);
    rfe_replay_esc_input_f64(&log, 2u, 1u, &in);
    assert_true(in.dt == log.rows[2].t - log.rows[1].t);
    assert_true(in.omega[RFE_FL] == log.rows[2].omega[RFE_FL]);
    assert_true(in.p_brake[RFE_RR] == log.rows[2].p_brake[RFE_RR]);
    assert_int_equal(in.has, RFE_VEL_HAS_PRESSURE);
    rfe_replay_esc_input_f64(&log, 0u, SIZE_MAX, &in);
    assert_true(in.dt == 0.0);
    sat = rfe_replay_esc_input_q31(&log, 2u, 1u, &q);
    assert_int_equal(sat, 0);
    /* 0.01 s in the period's Q format, rounded to nearest */
    assert_int_equal(q.dt, (int32_t)lround(ldexp(log.rows[2].t - log.rows[1].t, RFE_FIX_Q_DT)));
    assert_int_equal(q.has, RFE_VEL_HAS_PRESSURE);
    rfe_sensor_log_free(&log);
}

/* ------------------------------------------------------------ tyre identifier */

/* The set's tid_* keys are the library's defaults, each value exactly (read through the key
 * table's member column), the seed RFE_TID_SEED_DEFAULT, origins the preset; a preset never
 * runs the identifier. NULL: -1. */
/* REQ-CLI-008 */
static void test_rfe_param_set_tyre_id_is_the_library_default(void **state)
{
    rfe_param_set_t ps;
    rfe_tyre_id_params_t p;
    (void)state;
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_tyre_id_params_default_f64(&p), RFE_OK);
    assert_int_equal(ps.tyre_id, 0);
    assert_true(ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST] == (double)p.filter);
    assert_true(ps.tid[RFE_PK_tid_resample - RFE_PK_TID_FIRST] == (double)p.resample);
    assert_true(ps.tid[RFE_PK_tid_substeps - RFE_PK_TID_FIRST] == (double)p.substeps);
    assert_true(ps.tid[RFE_PK_tid_seed - RFE_PK_TID_FIRST] == 1.0); /* TYRE_ID.md §2 */
    assert_true(ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] == 0.0); /* not fed */
#define CHECK_TID_(key, member, unit, doc)                                                   \
    if (!(ps.tid[(size_t)RFE_PK_##key - RFE_PK_TID_FIRST] == p.member)) {                    \
        fail_msg("key %s: set %.17g, library %.17g", #key,                                   \
                 ps.tid[(size_t)RFE_PK_##key - RFE_PK_TID_FIRST], p.member);                 \
    }                                                                                        \
    assert_null(ps.origin[RFE_PK_##key].file);
    RFE_TID_KEYS(CHECK_TID_)
#undef CHECK_TID_
    assert_int_equal(rfe_param_set_tyre_id_f64(NULL), -1);
}

/* Every real tid_* key reaches its member (each value times 1.5 stays valid: the bounds stay
 * ordered, neff_frac 0.5 <= 1), the words and tid_substeps theirs, tid_seed the seed; the key
 * that alone fails is named (a value its member cannot hold, or one the library refuses); a
 * combination names none. */
/* REQ-CLI-008 */
static void test_rfe_replay_tyre_id_params_keys_and_diagnosis(void **state)
{
    rfe_param_set_t ps;
    rfe_tyre_id_params_t def;
    rfe_tyre_id_params_t tp;
    uint64_t seed = 0u;
    size_t bad = 0u;
    (void)state;
    memset(&def, 0, sizeof def);
    memset(&tp, 0, sizeof tp);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_int_equal(rfe_tyre_id_params_default_f64(&def), RFE_OK);
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, &bad), RFE_OK);
    assert_int_equal(bad, RFE_PK_NONE);
    assert_memory_equal(&tp, &def, sizeof tp);
    assert_true(seed == 1u);
#define CHECK_TID_(key, member, unit, doc)                                                   \
    ps.tid[(size_t)RFE_PK_##key - RFE_PK_TID_FIRST] = def.member * 1.5;                      \
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, NULL), RFE_OK);          \
    if (!(tp.member == def.member * 1.5)) {                                                  \
        fail_msg("key %s did not reach its member", #key);                                   \
    }                                                                                        \
    ps.tid[(size_t)RFE_PK_##key - RFE_PK_TID_FIRST] = def.member;
    RFE_TID_KEYS(CHECK_TID_)
#undef CHECK_TID_
    ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST] = (double)RFE_TID_SIR;
    ps.tid[RFE_PK_tid_resample - RFE_PK_TID_FIRST] = (double)RFE_TID_SYSTEMATIC;
    ps.tid[RFE_PK_tid_substeps - RFE_PK_TID_FIRST] = 4.0;
    ps.tid[RFE_PK_tid_seed - RFE_PK_TID_FIRST] = 9007199254740992.0; /* 2^53, the largest */
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, NULL), RFE_OK);
    assert_true((tp.filter == RFE_TID_SIR) && (tp.resample == RFE_TID_SYSTEMATIC));
    assert_true((tp.substeps == 4u) && (seed == ((uint64_t)1u << 53)));
    ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST] = (double)RFE_TID_SCKF; /* TYRE_ID.md §15 */
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, NULL), RFE_OK);
    assert_true(tp.filter == RFE_TID_SCKF);
    /* one bad key at a time, each named */
    {
        static const struct {
            size_t key;
            double bad;
            double good;
        } cases[] = {
            {RFE_PK_tid_filter, 3.0, 2.0},        /* no rfe_tid_filter_t (2: sckf) */
            {RFE_PK_tid_filter, 1.5, 0.0},
            {RFE_PK_tid_resample, 0.5, 1.0},      /* no rfe_tid_resample_t */
            {RFE_PK_tid_substeps, 2.5, 1.0},      /* not an integer */
            {RFE_PK_tid_substeps, 0.0, 1.0},      /* an integer the library refuses */
            {RFE_PK_tid_substeps, 5e9, 1.0},      /* beyond a uint32_t */
            {RFE_PK_tid_seed, -1.0, 7.0},         /* not 0 .. 2^53 */
            {RFE_PK_tid_seed, 9007199254740994.0, 7.0},
            {RFE_PK_tid_seed, 1.5, 7.0},
            {RFE_PK_tid_sd_r, 0.0, 0.01},         /* rfe_tyre_id_params_validate: > 0 */
            {RFE_PK_tid_neff_frac, 1.5, 0.5},     /* in [0, 1] */
            {RFE_PK_tid_ellipse, 0.5, 1.0},       /* the friction ellipse: 0 or 1 */
            {RFE_PK_tid_fx_front, 1.5, 0.625},    /* in [0, 1] */
            {RFE_PK_tid_ell_min, 0.0, 0.1},       /* in (0, 1] */
            {RFE_PK_tid_ell_ax_min, -0.1, 0.6},   /* in [0, 20] m/s^2 */
            {RFE_PK_tid_delta_q, -0.1, 0.05},     /* the steering-angle filter: >= 0 */
            {RFE_PK_tid_delta_state_q, -0.1, 0.0}, /* delta as the SCKF's state: >= 0 */
        };
        size_t c;
        for (c = 0u; c < sizeof cases / sizeof cases[0]; ++c) {
            ps.tid[cases[c].key - RFE_PK_TID_FIRST] = cases[c].bad;
            assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, &bad), RFE_ERR_PARAM);
            assert_int_equal(bad, cases[c].key);
            ps.tid[cases[c].key - RFE_PK_TID_FIRST] = cases[c].good;
        }
    }
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, NULL), RFE_OK);
    assert_true(seed == 7u);
    /* tid_delta_state_q passed through (TYRE_ID.md §15.7); with tid_delta_q > 0 (0.05 above)
     * both valid alone, refused together: no key to blame */
    ps.tid[RFE_PK_tid_delta_q - RFE_PK_TID_FIRST] = 0.0;
    ps.tid[RFE_PK_tid_delta_state_q - RFE_PK_TID_FIRST] = 0.04;
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, NULL), RFE_OK);
    assert_true(tp.delta_state_q == 0.04 && tp.delta_q == 0.0);
    ps.tid[RFE_PK_tid_delta_q - RFE_PK_TID_FIRST] = 0.05;
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_NONE);
    ps.tid[RFE_PK_tid_delta_state_q - RFE_PK_TID_FIRST] = 0.0;
    /* each valid alone (0.1 < 1.0 < 1.3, 0.1 < 0.9), not together: no key to blame */
    ps.tid[RFE_PK_tid_mu_lo - RFE_PK_TID_FIRST] = 1.0;
    ps.tid[RFE_PK_tid_mu_hi - RFE_PK_TID_FIRST] = 0.9;
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_NONE);
    assert_int_equal(rfe_replay_tyre_id_params_f64(NULL, &tp, &seed, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, NULL, &seed, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, NULL, NULL), RFE_ERR_NULL);
}

/* The sine-steer log of the tyre identification scenarios (TYRE_ID.md §8): 10 s at 100 Hz,
 * the steering excites the lateral curve, so the particles move and resample. */
#define TID_LOG "scenarios/tyre_id/tid_sine_steer.csv"
/* Light mode (test_light.h: under valgrind, ~45x slower) walks the log's first 200 rows: the
 * particles resample from row 2, the feed of the tests below first changes the curve at row
 * 133 and has changed it 68 times by row 200 (of 199 updates), so every assertion keeps its
 * both outcomes possible; the refusal test's gap moves from row 500 to row 150. */
#define TID_LIGHT_ROWS 200u

/* The tyre identification log, its first TID_LIGHT_ROWS rows in light mode. */
static void tid_log_read(rfe_sensor_log_t *log)
{
    rfe_io_error_t err;
    memset(log, 0, sizeof *log);
    assert_int_equal(rfe_sensor_log_read(TID_LOG, log, &err), 0);
    assert_true(log->n_rows > TID_LIGHT_ROWS);
    if (rfe_test_light()) {
        log->n_rows = TID_LIGHT_ROWS;
    }
}

/* The replay's tyre identifier columns of row @p i equal the library's estimate @p e with
 * status @p st, bit for bit. */
static void check_tid_row(const rfe_est_row_t *row, const rfe_tyre_id_estimate_t *e,
                          rfe_status_t st)
{
    assert_int_equal(row->has_tyre_id, 1);
    assert_int_equal(row->tid_status, st);
    assert_int_equal(row->tid_flags, rfe_status_is_error(st) ? 0u : e->flags);
    assert_true(row->mu_id[0] == e->mean[RFE_TID_OUT_MU_F]);
    assert_true(row->mu_id[1] == e->mean[RFE_TID_OUT_MU_R]);
    assert_true(row->sd_mu_id[0] == e->sd[RFE_TID_OUT_MU_F]);
    assert_true(row->sd_mu_id[1] == e->sd[RFE_TID_OUT_MU_R]);
    assert_true((row->mf_B[0] == e->mean[RFE_TID_OUT_B_F]) && (row->mf_B[1] == e->mean[RFE_TID_OUT_B_R]));
    assert_true((row->mf_C[0] == e->mean[RFE_TID_OUT_C_F]) && (row->mf_C[1] == e->mean[RFE_TID_OUT_C_R]));
    assert_true((row->mf_D[0] == e->mean[RFE_TID_OUT_D_F]) && (row->mf_D[1] == e->mean[RFE_TID_OUT_D_R]));
    assert_true((row->mf_E[0] == e->mean[RFE_TID_OUT_E_F]) && (row->mf_E[1] == e->mean[RFE_TID_OUT_E_R]));
}

/* The replay's tyre identifier equals a hand-written loop over the library, bit for bit:
 * with measured velocities each sample's log vx and delta, behind the observer (after the
 * pipeline's step) the observer's vx and the road-wheel angle it used; the period is the
 * difference of the time stamps. The friction and observer columns are those of the run
 * without it (it takes nothing of them and gives nothing). The two runs differ (the observer's
 * vx is not the log's), and the estimate moves (the particles resample), so a replay that fed
 * the wrong vx or did not step would fail. */
/* REQ-CLI-008 */
static void test_rfe_replay_tyre_id_is_the_library_loop(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_replay_stats_t st;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_tyre_id_params_t tp;
    uint64_t seed = 0u;
    static rfe_pipeline_t pl;
    static rfe_tyre_id_t tid;
    rfe_est_row_t *on;
    rfe_est_row_t *off;
    rfe_est_row_t *meas;
    int observer;
    size_t differs = 0u;
    (void)state;
    tid_log_read(&log);
    on = calloc(log.n_rows, sizeof *on);
    off = calloc(log.n_rows, sizeof *off);
    meas = calloc(log.n_rows, sizeof *meas);
    assert_non_null(on);
    assert_non_null(off);
    assert_non_null(meas);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.value[RFE_PK_dt] = 0.01; /* the log's period */
    for (observer = 0; observer <= 1; ++observer) {
        rfe_status_t (*run)(const rfe_param_set_t *, const rfe_sensor_log_t *, rfe_est_row_t *,
                            rfe_replay_stats_t *, size_t *) =
            observer ? rfe_replay_run_observer_f64 : rfe_replay_run_f64;
        size_t i;
        size_t w;
        ps.tyre_id = 0;
        assert_int_equal(run(&ps, &log, off, &st, NULL), RFE_OK);
        ps.tyre_id = 1;
        assert_int_equal(run(&ps, &log, on, &st, NULL), RFE_OK);
        assert_int_equal(rfe_replay_params_f64(&ps, &p, NULL), RFE_OK);
        assert_int_equal(rfe_replay_velocity_params_f64(&ps, &vp, NULL), RFE_OK);
        assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, NULL), RFE_OK);
        assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
        assert_int_equal(rfe_tyre_id_init(&tid, &tp, &p, seed), RFE_OK);
        for (i = 0u; i < log.n_rows; ++i) {
            const rfe_sensor_row_t *row = &log.rows[i];
            rfe_tyre_id_sample_t s;
            rfe_tyre_id_estimate_t e;
            rfe_status_t sst;
            s.dt = (i > 0u) ? row->t - log.rows[i - 1u].t : 0.0;
            s.delta = row->delta;
            s.vx = row->vx;
            s.yaw_rate = row->yaw_rate;
            s.ay = row->ay;
            s.ax = row->ax;
            if (observer) {
                rfe_velocity_input_t in;
                rfe_pipeline_out_t o;
                rfe_replay_esc_input_f64(&log, i, (i > 0u) ? i - 1u : SIZE_MAX, &in);
                assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
                s.vx = o.velocity.vx;
                s.delta = o.velocity.delta;
            }
            sst = rfe_tyre_id_step(&tid, &s, &e);
            assert_int_equal(sst, RFE_OK);
            check_tid_row(&on[i], &e, sst);
            assert_int_equal(off[i].has_tyre_id, 0);
            for (w = 0u; w < RFE_WHEELS; ++w) {
                assert_true((on[i].mu[w] == off[i].mu[w]) && (on[i].sd[w] == off[i].sd[w]));
                assert_int_equal(on[i].valid[w], off[i].valid[w]);
            }
            assert_int_equal(on[i].status, off[i].status);
            assert_true((on[i].vx == off[i].vx) && (on[i].sd_beta == off[i].sd_beta));
            if (observer) {
                differs += (on[i].mu_id[0] != meas[i].mu_id[0]) ? 1u : 0u;
            } else {
                meas[i] = on[i];
            }
        }
        /* the counters are the rows' */
        assert_int_equal(st.tid_status_count[RFE_OK], log.n_rows);
        assert_int_equal(st.tid_flag_count[3], 1u);                 /* first */
        assert_int_equal(st.tid_flag_count[0], log.n_rows - 1u);    /* updated: every other */
        assert_true(st.tid_flag_count[1] > 0u);                     /* resampled */
        assert_int_equal(st.tid_restarts, 0u);
        assert_true(on[log.n_rows - 1u].mu_id[0] != on[0].mu_id[0]);
    }
    assert_true(differs > 0u);
    free(meas);
    free(off);
    free(on);
    rfe_sensor_log_free(&log);
}

/* A sample the identifier refuses (a NaN ay) holds its estimate with the library's status and
 * no flags, and the next period runs from the last accepted sample; a period beyond
 * tid_dt_max starts it afresh (the prior drawn again: flag first), counted; behind the
 * observer a sample the pipeline refuses (a NaN wheel speed) is not stepped and holds the
 * estimate with the pipeline's status. An invalid tid_* key or a prior outside its bounds
 * refuses the run before any row. */
/* REQ-CLI-008 */
static void test_rfe_replay_tyre_id_refusals_and_restart(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_replay_stats_t st;
    rfe_est_row_t *out;
    size_t i;
    size_t bad = 0u;
    const size_t gap = rfe_test_light() ? 150u : 500u; /* within the light rows */
    (void)state;
    tid_log_read(&log);
    out = calloc(log.n_rows, sizeof *out);
    assert_non_null(out);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.value[RFE_PK_dt] = 0.01;
    ps.tyre_id = 1;
    log.rows[100].ay = NAN;
    for (i = gap; i < log.n_rows; ++i) {
        log.rows[i].t += 0.5; /* a gap of 0.51 s before row gap */
    }
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_int_equal(out[100].tid_status, RFE_ERR_NONFINITE);
    assert_int_equal(out[100].tid_flags, 0u);
    assert_true((out[100].mu_id[0] == out[99].mu_id[0]) && (out[100].mf_D[1] == out[99].mf_D[1]));
    assert_int_equal(out[101].tid_status, RFE_OK); /* 0.02 s since row 99: accepted */
    {
        /* rows 0 .. 101 by hand, row 100 skipped: row 101's period is 0.02 s, from row 99 */
        static rfe_tyre_id_t tid;
        rfe_params_t p;
        rfe_tyre_id_params_t tp;
        uint64_t seed = 0u;
        rfe_tyre_id_estimate_t e;
        size_t prev = 0u;
        assert_int_equal(rfe_replay_params_f64(&ps, &p, NULL), RFE_OK);
        assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, NULL), RFE_OK);
        assert_int_equal(rfe_tyre_id_init(&tid, &tp, &p, seed), RFE_OK);
        for (i = 0u; i <= 101u; ++i) {
            const rfe_sensor_row_t *row = &log.rows[i];
            const rfe_tyre_id_sample_t s = {(i > 0u) ? row->t - log.rows[prev].t : 0.0, row->delta,
                                            row->vx, row->yaw_rate, row->ay, row->ax};
            if (i == 100u) {
                continue;
            }
            assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
            prev = i;
        }
        check_tid_row(&out[101], &e, RFE_OK);
    }
    assert_int_equal(out[gap].tid_flags, RFE_TID_FIRST);
    assert_int_equal(out[gap + 1u].tid_flags & RFE_TID_UPDATED, RFE_TID_UPDATED);
    assert_int_equal(st.tid_restarts, 1u);
    assert_int_equal(st.tid_flag_count[3], 2u); /* first: row 0 and row gap */
    assert_int_equal(st.tid_status_count[RFE_ERR_NONFINITE], 1u);
    /* behind the observer: the pipeline refuses row 120 (and row 100: the observer takes ay) */
    log.rows[120].omega[RFE_RL] = NAN;
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, NULL), RFE_OK);
    assert_true(rfe_status_is_error((rfe_status_t)out[120].status));
    assert_int_equal(out[120].tid_status, out[120].status);
    assert_true(out[120].mu_id[0] == out[119].mu_id[0]);
    assert_int_equal(out[121].tid_status, RFE_OK);
    assert_int_equal(out[100].tid_status, out[100].status);
    /* an invalid key: named, before any row; a prior mean outside its bounds: no key alone */
    ps.tid[RFE_PK_tid_sd_ay - RFE_PK_TID_FIRST] = -0.2;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_tid_sd_ay);
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_tid_sd_ay);
    ps.tid[RFE_PK_tid_sd_ay - RFE_PK_TID_FIRST] = 0.2;
    ps.tid[RFE_PK_tid_C_hi - RFE_PK_TID_FIRST] = 1.2; /* shape_Cy 1.3 outside [1, 1.2] */
    assert_int_equal(rfe_replay_run_f64(&ps, &log, out, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_NONE);
    free(out);
    rfe_sensor_log_free(&log);
}


/* The feed rule written out (TYRE_ID.md §14): after an update with status RFE_OK whose summed
 * cornering stiffness has a relative sd (the axles' sds combined as independent) of at most
 * @p feed, the load-weighted curve and r_model_rel = sqrt(r^2 + rel^2). */
static int feed_curve(const rfe_tyre_id_t *tid, const rfe_tyre_id_estimate_t *e, rfe_status_t st,
                      double feed, double r, double v[4])
{
    const double ff = tid->c.fz0[0];
    const double fr = tid->c.fz0[1];
    const double k = e->mean[RFE_TID_OUT_K_F] + e->mean[RFE_TID_OUT_K_R];
    const double rel = sqrt(e->sd[RFE_TID_OUT_K_F] * e->sd[RFE_TID_OUT_K_F] +
                            e->sd[RFE_TID_OUT_K_R] * e->sd[RFE_TID_OUT_K_R]) / k;
    if (!((st == RFE_OK) && ((e->flags & RFE_TID_UPDATED) != 0u) && (rel <= feed))) {
        return 0;
    }
    v[0] = k / (ff + fr);
    v[1] = (ff * e->mean[RFE_TID_OUT_C_F] + fr * e->mean[RFE_TID_OUT_C_R]) / (ff + fr);
    v[2] = (ff * e->mean[RFE_TID_OUT_E_F] + fr * e->mean[RFE_TID_OUT_E_R]) / (ff + fr);
    v[3] = sqrt(r * r + rel * rel);
    return 1;
}

/* The friction estimator's evidence that its curve is wrong, written out (TYRE_ID.md §14):
 * the period since the previous row added while the sample's status is 1 or 4. */
static double evidence_after(double t_wrong, const rfe_sensor_log_t *log, size_t i,
                             rfe_status_t fst)
{
    const int wrong = (fst == RFE_PROJECTED) || (fst == RFE_MODEL_MISMATCH);
    return ((i > 0u) && wrong) ? t_wrong + (log->rows[i].t - log->rows[i - 1u].t) : t_wrong;
}

/* The replay of @p log with the feed at tid_feed_sd_rel 0.05 and tid_feed_evidence
 * @p evidence (s) against a hand-written loop over the library, bit for bit: each sample the
 * friction step, then the identifier's, then the evidence, hold (no feed after a sample whose
 * |ax| exceeds tid_feed_ax_max, its default 0.5 m/s^2) and feed rules on that step's
 * estimate and rfe_friction_set_lateral_tyre, so the next sample's step takes the curve
 * (cy_used .. r_model_rel_used: the curve of each sample's step). Returns the samples fed
 * (the replay's count, checked against the loop's), *differs the samples whose friction
 * estimate differs from the run without the feed, *t_first the evidence when the first curve
 * was fed (-1: none). */
static size_t feed_loop_check(rfe_sensor_log_t *log, double evidence, size_t *differs,
                              double *t_first)
{
    rfe_param_set_t ps;
    rfe_replay_stats_t st;
    rfe_params_t p;
    rfe_tyre_id_params_t tp;
    uint64_t seed = 0u;
    static rfe_friction_t est;
    static rfe_tyre_id_t tid;
    rfe_est_row_t *on = calloc(log->n_rows, sizeof *on);
    rfe_est_row_t *off = calloc(log->n_rows, sizeof *off);
    double t_wrong = 0.0;
    double ax_max;
    size_t i;
    size_t n_fed = 0u;
    assert_non_null(on);
    assert_non_null(off);
    *differs = 0u;
    *t_first = -1.0;
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.value[RFE_PK_dt] = 0.01;
    assert_int_equal(rfe_replay_run_f64(&ps, log, off, &st, NULL), RFE_OK);
    ps.tyre_id = 1;
    ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = 0.05;
    ps.tid[RFE_PK_tid_feed_evidence - RFE_PK_TID_FIRST] = evidence;
    ax_max = ps.tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST];
    assert_true(ax_max == 0.5); /* the preset's hold (TYRE_ID.md §14) */
    assert_int_equal(rfe_replay_run_f64(&ps, log, on, &st, NULL), RFE_OK);
    assert_int_equal(rfe_replay_params_f64(&ps, &p, NULL), RFE_OK);
    assert_int_equal(rfe_replay_tyre_id_params_f64(&ps, &tp, &seed, NULL), RFE_OK);
    memset(&est, 0, sizeof est);
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &p, seed), RFE_OK);
    for (i = 0u; i < log->n_rows; ++i) {
        const rfe_sensor_row_t *row = &log->rows[i];
        rfe_sample_t smp;
        rfe_estimate_t fe;
        rfe_tyre_id_estimate_t e;
        rfe_status_t fst;
        rfe_status_t tst;
        double v[4];
        const rfe_tyre_id_sample_t ts = {(i > 0u) ? row->t - log->rows[i - 1u].t : 0.0, row->delta,
                                         row->vx, row->yaw_rate, row->ay, row->ax};
        assert_int_equal(on[i].has_tyre_feed, 1);
        assert_true((on[i].cy_used == est.params.tyre.cy) &&
                    (on[i].shape_Cy_used == est.params.tyre.shape_Cy) &&
                    (on[i].shape_Ey_used == est.params.tyre.shape_Ey) &&
                    (on[i].r_model_rel_used == est.params.filter.r_model_rel));
        rfe_replay_sample_from_row(row, &smp);
        fst = rfe_friction_step(&est, &smp, &fe);
        assert_int_equal(on[i].status, fst);
        assert_true((on[i].mu[0] == fe.mu[0]) && (on[i].sd[0] == fe.sd[0]) &&
                    (on[i].mu[3] == fe.mu[3]) && (on[i].sd[3] == fe.sd[3]));
        *differs += ((on[i].mu[0] != off[i].mu[0]) || (on[i].sd[0] != off[i].sd[0])) ? 1u : 0u;
        t_wrong = evidence_after(t_wrong, log, i, fst);
        tst = rfe_tyre_id_step(&tid, &ts, &e);
        check_tid_row(&on[i], &e, tst);
        if ((t_wrong >= evidence) && (fabs(row->ax) <= ax_max) &&
            (feed_curve(&tid, &e, tst, 0.05, p.filter.r_model_rel, v) != 0)) {
            assert_int_equal(rfe_friction_set_lateral_tyre(&est, v[0], v[1], v[2], v[3]), RFE_OK);
            *t_first = (n_fed == 0u) ? t_wrong : *t_first;
            ++n_fed;
        }
    }
    assert_int_equal(st.n_tyre_fed, n_fed);
    free(off);
    free(on);
    return n_fed;
}

/* With tid_feed_sd_rel > 0 (and no evidence asked for) the replay is the library loop
 * (feed_loop_check); 0.05 lies within the spread of the log's relative sds, so some updates
 * feed and some do not, and the estimate differs from the run without the feed. Behind the
 * observer (no pipeline setter) and negative, the key is refused before any row, named. */
/* REQ-CLI-008 */
static void test_rfe_replay_tyre_feed_is_the_library_loop(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_replay_stats_t st;
    rfe_est_row_t *on;
    size_t n_fed;
    size_t differs = 0u;
    size_t bad = 0u;
    double t_first;
    (void)state;
    tid_log_read(&log);
    n_fed = feed_loop_check(&log, 0.0, &differs, &t_first);
    assert_true((n_fed > 0u) && (n_fed < log.n_rows - 1u));
    assert_true(differs > 0u);
    on = calloc(log.n_rows, sizeof *on);
    assert_non_null(on);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    ps.value[RFE_PK_dt] = 0.01;
    ps.tyre_id = 1;
    ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = 0.05;
    /* refused before any row, naming the key */
    assert_int_equal(rfe_replay_run_observer_f64(&ps, &log, on, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_tid_feed_sd_rel);
    ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = -0.05;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_tid_feed_sd_rel);
    ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = INFINITY;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_tid_feed_sd_rel);
    ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = 0.05;
    ps.tid[RFE_PK_tid_feed_evidence - RFE_PK_TID_FIRST] = -0.25;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_tid_feed_evidence);
    ps.tid[RFE_PK_tid_feed_evidence - RFE_PK_TID_FIRST] = NAN;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, &bad), RFE_ERR_PARAM);
    assert_int_equal(bad, RFE_PK_tid_feed_evidence);
    free(on);
    rfe_sensor_log_free(&log);
}

/* With tid_feed_evidence > 0 the feed waits for the friction estimator's own evidence that
 * its curve is wrong, and the replay is still the library loop (feed_loop_check). On the
 * wrong-tyre-data log (true cy -30 %, C +30 %: the estimator reports mismatch and bound
 * statuses) with 0.25 s asked for, the first curve is fed once the evidence reached 0.25 s
 * and some are fed; on the sine steer, whose estimator reports neither in the rows read
 * (checked through the loop: no feed with any evidence asked for), nothing is fed and the
 * estimate is the unfed run's. Light mode: the first 400 rows of the wrong-tyre log (the
 * first curve is fed at row 159 in double). */
/* REQ-CLI-008 */
static void test_rfe_replay_tyre_feed_waits_for_evidence(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    size_t n_fed;
    size_t differs = 0u;
    double t_first;
    (void)state;
    memset(&log, 0, sizeof log);
    assert_int_equal(rfe_sensor_log_read("scenarios/wrong_tyre_data.mf.csv", &log, &err), 0);
    if (rfe_test_light()) {
        log.n_rows = (log.n_rows < 400u) ? log.n_rows : 400u;
    }
    n_fed = feed_loop_check(&log, 0.25, &differs, &t_first);
    assert_true(n_fed > 0u);
    assert_true(t_first >= 0.25);
    assert_true(differs > 0u);
    rfe_sensor_log_free(&log);
    tid_log_read(&log);
    n_fed = feed_loop_check(&log, 1e-9, &differs, &t_first);
    assert_int_equal(n_fed, 0u);
    assert_int_equal(differs, 0u);
    rfe_sensor_log_free(&log);
}

/* Curve changes of a fed run @p on of @p log: *after_ax the rows whose curve (cy_used ..
 * r_model_rel_used, the curve of that row's step) differs from the previous row's although
 * the previous row's |ax| exceeded @p ax_max (a curve fed after a braking sample), *other the
 * other changes. */
static void curve_changes(const rfe_sensor_log_t *log, const rfe_est_row_t *on, double ax_max,
                          size_t *after_ax, size_t *other)
{
    size_t i;
    *after_ax = 0u;
    *other = 0u;
    for (i = 1u; i < log->n_rows; ++i) {
        const int changed = (on[i].cy_used != on[i - 1u].cy_used) ||
                            (on[i].shape_Cy_used != on[i - 1u].shape_Cy_used) ||
                            (on[i].shape_Ey_used != on[i - 1u].shape_Ey_used) ||
                            (on[i].r_model_rel_used != on[i - 1u].r_model_rel_used);
        if (changed && (fabs(log->rows[i - 1u].ax) > ax_max)) {
            ++*after_ax;
        } else if (changed) {
            ++*other;
        }
    }
}

/* tid_feed_ax_max (TYRE_ID.md §14): no curve is fed after a sample whose |ax| exceeds it, so
 * the friction estimator keeps its curve through a braking. On brake_in_turn.mf (a steady
 * turn, then about 2.5 m/s^2 of braking from 2.1 s to 6.2 s) with the sigma-point filter at
 * tid_feed_sd_rel 0.05: without the hold (0) the curve identified under braking is fed after
 * braking samples (which the check below must see, or it could not fail); with the preset's
 * 0.5 m/s^2 never, while it still changes after the unbraked samples, and fewer samples are
 * fed. Negative or not finite, the key is refused before any row, named. Light mode: the
 * first 700 rows (braking from row 210 to 620: at 0.05 this filter's first curve is fed
 * under braking, so the unbraked changes come after it). */
/* REQ-CLI-008 */
static void test_rfe_replay_tyre_feed_holds_under_braking(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    rfe_param_set_t ps;
    rfe_replay_stats_t st;
    rfe_est_row_t *on;
    size_t after_ax = 0u;
    size_t other = 0u;
    size_t fed_free;
    size_t bad = 0u;
    const double bad_values[3] = {-0.5, NAN, INFINITY};
    int k;
    (void)state;
    memset(&log, 0, sizeof log);
    assert_int_equal(rfe_sensor_log_read("scenarios/brake_in_turn.mf.csv", &log, &err), 0);
    if (rfe_test_light()) {
        log.n_rows = (log.n_rows < 700u) ? log.n_rows : 700u;
    }
    on = calloc(log.n_rows, sizeof *on);
    assert_non_null(on);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_true(ps.tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST] == RFE_TID_FEED_AX_MAX_DEFAULT);
    ps.value[RFE_PK_dt] = 0.01;
    ps.tyre_id = 1;
    ps.tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST] = (double)RFE_TID_SCKF;
    ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = 0.05;
    ps.tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST] = 0.0; /* no hold */
    assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, NULL), RFE_OK);
    curve_changes(&log, on, 0.5, &after_ax, &other);
    assert_true(after_ax > 0u);
    fed_free = st.n_tyre_fed;
    ps.tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST] = 0.5;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, NULL), RFE_OK);
    curve_changes(&log, on, 0.5, &after_ax, &other);
    assert_int_equal(after_ax, 0u);
    assert_true(other > 0u);
    assert_true((st.n_tyre_fed > 0u) && (st.n_tyre_fed < fed_free));
    for (k = 0; k < 3; ++k) {
        ps.tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST] = bad_values[k];
        bad = 0u;
        assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, &bad), RFE_ERR_PARAM);
        assert_int_equal(bad, RFE_PK_tid_feed_ax_max);
    }
    free(on);
    rfe_sensor_log_free(&log);
}

/* The rows of @p log whose ay differs from @p base's (the fault's spikes), at most @p max
 * into @p rows; their count. */
static size_t spike_rows(const rfe_sensor_log_t *log, const rfe_sensor_log_t *base, size_t *rows,
                         size_t max)
{
    size_t i;
    size_t n = 0u;
    for (i = 0u; (i < log->n_rows) && (n < max); ++i) {
        if (log->rows[i].ay != base->rows[i].ay) {
            rows[n] = i;
            ++n;
        }
    }
    return n;
}

/* 1 when row @p i's curve (cy_used .. r_model_rel_used) is row @p j's. */
static int same_curve(const rfe_est_row_t *on, size_t i, size_t j)
{
    return (on[i].cy_used == on[j].cy_used) && (on[i].shape_Cy_used == on[j].shape_Cy_used) &&
           (on[i].shape_Ey_used == on[j].shape_Ey_used) &&
           (on[i].r_model_rel_used == on[j].r_model_rel_used);
}

/* tid_feed_refresh and tid_feed_outlier_k (MONITOR.md §7), the APF's curve at tid_feed_sd_rel
 * 0.1. On the sine steer with single-sample ay spikes of 5 m/s^2 (the fault log; its spikes
 * found against the clean log it was made from, not by the rule): with the key 0 a curve is
 * fed within a second after the first spike (the check below must see it, or it could not
 * fail); with 1 s the first spike (5 m/s^2 = 25 tid_sd_ay from any tyre force) sets the
 * friction estimator's model error back to the set's r_model_rel before that sample's step
 * (its r_model_rel_used), and no curve is fed in the next 100 rows (a second of samples: the
 * refresh needs a second of excited ones, and an updated curve shows on the row after its
 * feed), and the first curve fed after it is fed where |ay| < 1 m/s^2 (its resumption, away
 * from the limit). On the split-mu hard brake (ABS braking from 1 s to 5 s, the driver counter-steering,
 * then coasting with |ay| below 1 m/s^2) the curve learnt under braking is fed after it
 * without the key and never with it. Negative or not finite, both keys are refused before any
 * row, named. Light mode: the first 300 rows of the sine steer (its first spike at row 177),
 * the brake not run. */
/* REQ-CLI-008 */
static void test_rfe_replay_tyre_feed_refresh_after_taint(void **state)
{
    rfe_sensor_log_t log;
    rfe_sensor_log_t base;
    rfe_io_error_t err;
    rfe_param_set_t ps;
    rfe_replay_stats_t st;
    rfe_est_row_t *on;
    size_t spikes[8];
    size_t n_spikes;
    size_t i;
    size_t s0;
    size_t bad = 0u;
    int changed = 0;
    const double bad_values[3] = {-1.0, NAN, INFINITY};
    int k;
    (void)state;
    memset(&log, 0, sizeof log);
    memset(&base, 0, sizeof base);
    assert_int_equal(rfe_sensor_log_read("scenarios/faults/spike_ay.sine_steer_low_mu.mf.csv",
                                         &log, &err), 0);
    assert_int_equal(rfe_sensor_log_read("scenarios/sine_steer_low_mu.mf.csv", &base, &err), 0);
    assert_int_equal(log.n_rows, base.n_rows);
    if (rfe_test_light()) {
        log.n_rows = (log.n_rows < 300u) ? log.n_rows : 300u;
    }
    n_spikes = spike_rows(&log, &base, spikes, 8u);
    assert_true(n_spikes >= 1u);
    s0 = spikes[0];
    assert_true(s0 + 101u <= log.n_rows);
    on = calloc(log.n_rows, sizeof *on);
    assert_non_null(on);
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    assert_true(ps.tid[RFE_PK_tid_feed_refresh - RFE_PK_TID_FIRST] == 0.0); /* off */
    ps.value[RFE_PK_dt] = 0.01;
    ps.tyre_id = 1;
    ps.tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = 0.1;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, NULL), RFE_OK);
    assert_int_equal(st.n_tyre_reset, 0u);
    for (i = s0 + 1u; i <= s0 + 100u; ++i) {
        changed |= (same_curve(on, i, s0) == 0) ? 1 : 0;
    }
    assert_true(changed); /* without the key a curve is fed after the spike */
    assert_true(on[s0].r_model_rel_used != ps.value[RFE_PK_r_model_rel]);
    ps.tid[RFE_PK_tid_feed_refresh - RFE_PK_TID_FIRST] = 1.0;
    assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, NULL), RFE_OK);
    assert_true(st.n_tyre_reset >= 1u);
    assert_true(st.n_tyre_fed > 0u);
    /* the set's r_model_rel, rounded to the build's real as the estimator holds it */
    assert_true(on[s0].r_model_rel_used == (double)(rfe_real_t)ps.value[RFE_PK_r_model_rel]);
    assert_true(on[s0 - 1u].r_model_rel_used != on[s0].r_model_rel_used);
    for (i = s0 + 1u; i <= s0 + 100u; ++i) {
        assert_true(same_curve(on, i, s0));
    }
    /* the first curve fed after the taint (it shows on the row after its feed) was fed at a
     * sample with |ay| below 5 tid_sd_ay = 1 m/s^2; the refresh itself ends on a sample with
     * |ay| >= 1 m/s^2, so a feed at the taint's end would fail this */
    i = s0 + 101u;
    while ((i < log.n_rows) && same_curve(on, i, s0)) {
        ++i;
    }
    assert_true(rfe_test_light() || (i < log.n_rows)); /* the whole log resumes the feed */
    if (i < log.n_rows) {
        assert_true(fabs(log.rows[i - 1u].ay) < 1.0);
    }
    for (k = 0; k < 6; ++k) {
        const size_t key = (k < 3) ? (size_t)RFE_PK_tid_feed_refresh
                                   : (size_t)RFE_PK_tid_feed_outlier_k;
        rfe_param_set_t b = ps;
        b.tid[key - RFE_PK_TID_FIRST] = bad_values[k % 3];
        bad = 0u;
        assert_int_equal(rfe_replay_run_f64(&b, &log, on, &st, &bad), RFE_ERR_PARAM);
        assert_int_equal(bad, key);
    }
    free(on);
    rfe_sensor_log_free(&base);
    rfe_sensor_log_free(&log);
    if (!rfe_test_light()) {
        assert_int_equal(rfe_sensor_log_read("scenarios/split_mu_hard_brake.nf.csv", &log, &err),
                         0);
        on = calloc(log.n_rows, sizeof *on);
        assert_non_null(on);
        ps.tid[RFE_PK_tid_feed_refresh - RFE_PK_TID_FIRST] = 0.0;
        assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, NULL), RFE_OK);
        assert_true(st.n_tyre_fed > 0u); /* the braking's curve, fed after it */
        ps.tid[RFE_PK_tid_feed_refresh - RFE_PK_TID_FIRST] = 1.0;
        assert_int_equal(rfe_replay_run_f64(&ps, &log, on, &st, NULL), RFE_OK);
        assert_int_equal(st.n_tyre_fed, 0u);
        free(on);
        rfe_sensor_log_free(&log);
    }
}

/* The identifier's state is the replay state's: two states stepped row by row in turn (one
 * measuring with the curve fed, one behind the observer with the other filter and seed) give
 * each its whole-log run's rows and counters, bit for bit, so nothing of a run lives outside
 * its state. */
/* REQ-CLI-008 REQ-CLI-003 */
static void test_rfe_replay_tyre_id_state_steps_as_the_run(void **state)
{
    rfe_sensor_log_t log;
    rfe_param_set_t ps[2];
    rfe_replay_stats_t st_run[2];
    rfe_replay_stats_t st_one;
    struct rfe_replay_state_f64 *s[2];
    rfe_est_row_t *run[2];
    rfe_est_row_t *one[2];
    size_t i;
    int k;
    (void)state;
    tid_log_read(&log);
    for (k = 0; k < 2; ++k) {
        s[k] = calloc(1u, rfe_replay_state_size_f64());
        run[k] = calloc(log.n_rows, sizeof *run[k]);
        one[k] = calloc(log.n_rows, sizeof *one[k]);
        assert_non_null(s[k]);
        assert_non_null(run[k]);
        assert_non_null(one[k]);
        assert_int_equal(rfe_param_set_preset_f64(&ps[k], RFE_PRESET_DEFAULT), 0);
        ps[k].value[RFE_PK_dt] = 0.01;
        ps[k].tyre_id = 1;
    }
    ps[0].tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = 0.05;
    ps[1].tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST] = (double)RFE_TID_SIR;
    ps[1].tid[RFE_PK_tid_seed - RFE_PK_TID_FIRST] = 7.0;
    assert_int_equal(rfe_replay_run_f64(&ps[0], &log, run[0], &st_run[0], NULL), RFE_OK);
    assert_int_equal(rfe_replay_run_observer_f64(&ps[1], &log, run[1], &st_run[1], NULL), RFE_OK);
    assert_int_equal(rfe_replay_begin_f64(s[0], &ps[0], &log, 0, NULL), RFE_OK);
    assert_int_equal(rfe_replay_begin_f64(s[1], &ps[1], &log, 1, NULL), RFE_OK);
    for (i = 0u; i < log.n_rows; ++i) {
        for (k = 0; k < 2; ++k) {
            assert_int_equal(rfe_replay_step_f64(s[k], &log.rows[i], &one[k][i]), RFE_OK);
        }
    }
    assert_true(st_run[0].n_tyre_fed > 0u); /* the feed acted */
    for (k = 0; k < 2; ++k) {
        for (i = 0u; i < log.n_rows; ++i) {
            const rfe_est_row_t *a = &one[k][i];
            const rfe_est_row_t *b = &run[k][i];
            assert_int_equal(a->has_tyre_id, 1);
            assert_int_equal(a->has_tyre_feed, (k == 0) ? 1 : 0);
            assert_memory_equal(a->mu, b->mu, sizeof a->mu);
            assert_memory_equal(a->mu_id, b->mu_id, sizeof a->mu_id);
            assert_memory_equal(a->sd_mu_id, b->sd_mu_id, sizeof a->sd_mu_id);
            assert_memory_equal(a->mf_D, b->mf_D, sizeof a->mf_D);
            assert_true((a->vx == b->vx) && (a->cy_used == b->cy_used) &&
                        (a->r_model_rel_used == b->r_model_rel_used));
            assert_int_equal(a->tid_status, b->tid_status);
            assert_int_equal(a->tid_flags, b->tid_flags);
        }
        assert_int_equal(rfe_replay_get_stats_f64(s[k], &st_one), RFE_OK);
        assert_memory_equal(&st_one, &st_run[k], sizeof st_one);
        free(one[k]);
        free(run[k]);
        free(s[k]);
    }
    /* behind the observer the feed is refused at the start, naming the key; no step then */
    {
        struct rfe_replay_state_f64 *t = calloc(1u, rfe_replay_state_size_f64());
        rfe_est_row_t out;
        size_t bad = 0u;
        assert_non_null(t);
        assert_int_equal(rfe_replay_begin_f64(t, &ps[0], &log, 1, &bad), RFE_ERR_PARAM);
        assert_int_equal(bad, RFE_PK_tid_feed_sd_rel);
        assert_int_equal(rfe_replay_step_f64(t, &log.rows[0], &out), RFE_ERR_NOT_INITIALISED);
        free(t);
    }
    rfe_sensor_log_free(&log);
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
        cmocka_unit_test(test_rfe_replay_run_observer_q31_checks_its_arguments),
        cmocka_unit_test(test_rfe_replay_run_observer_q31_is_the_pipeline_bit_for_bit),
        cmocka_unit_test(test_rfe_replay_run_observer_q31_counts_saturation_and_goes_on),
        cmocka_unit_test(test_rfe_replay_run_observer_q31_agrees_with_double),
        cmocka_unit_test(test_rfe_replay_status_slot_bounds),
        cmocka_unit_test(test_rfe_param_set_mass_grade_is_the_library_preset),
        cmocka_unit_test(test_rfe_replay_mass_grade_params_keys_and_diagnosis),
        cmocka_unit_test(test_rfe_replay_run_observer_takes_the_current_estimated_grade),
        cmocka_unit_test(test_rfe_replay_mass_grade_refusals),
        cmocka_unit_test(test_rfe_replay_feeds_the_current_mass_by_the_sd_rule),
        cmocka_unit_test(test_rfe_replay_feed_off_is_mass_grade_off),
        cmocka_unit_test(test_rfe_replay_gate_holds_the_feed_until_the_excitation),
        cmocka_unit_test(test_rfe_replay_slip_holds_the_feed_and_empties_the_gate),
        cmocka_unit_test(test_rfe_replay_slip_pauses_the_filter),
        cmocka_unit_test(test_rfe_replay_curve_pauses_the_filter),
        cmocka_unit_test(test_rfe_replay_mass_grade_bad_vx_refused),
        cmocka_unit_test(test_rfe_replay_band_refuses_a_mass_far_from_m),
        cmocka_unit_test(test_rfe_replay_q31_mass_grade_is_the_library_loop),
        cmocka_unit_test(test_rfe_replay_q31_fed_mass_reaches_the_friction_estimator),
        cmocka_unit_test(test_rfe_replay_q31_mass_grade_refusals),
        cmocka_unit_test(test_rfe_replay_state_steps_as_the_run),
        cmocka_unit_test(test_rfe_replay_state_refusals),
        cmocka_unit_test(test_rfe_replay_esc_input_of_a_log_row),
        cmocka_unit_test(test_rfe_param_set_tyre_id_is_the_library_default),
        cmocka_unit_test(test_rfe_replay_tyre_id_params_keys_and_diagnosis),
        cmocka_unit_test(test_rfe_replay_tyre_id_is_the_library_loop),
        cmocka_unit_test(test_rfe_replay_tyre_id_refusals_and_restart),
        cmocka_unit_test(test_rfe_replay_tyre_feed_is_the_library_loop),
        cmocka_unit_test(test_rfe_replay_tyre_feed_waits_for_evidence),
        cmocka_unit_test(test_rfe_replay_tyre_feed_holds_under_braking),
        cmocka_unit_test(test_rfe_replay_tyre_feed_refresh_after_taint),
        cmocka_unit_test(test_rfe_replay_tyre_id_state_steps_as_the_run),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
