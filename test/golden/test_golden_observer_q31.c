/**
 * @file test_golden_observer_q31.c
 * @brief The fixed-point pipeline (velocity observer and friction estimator, rfe_pipeline_*_q31)
 *        against its own goldens, bit for bit: every value of
 *        scenarios/golden/observer_q31/[car_format.]<stem>.q31.csv (written by
 *        `make observer-goldens-q31`, i.e. `mu_replay --real q31 --velocity observer`) must be
 *        reproduced exactly, so any change to the observer's or the estimator's integer
 *        arithmetic, or to the replay's conversions, is seen.
 *
 * Why an exact comparison is possible (as test_golden_q31.c): the q31 library uses integer
 * operations only, in a fixed order, so it is bit-identical on every platform and build (this
 * test runs in the optimised, the -O0 coverage and the ASan/UBSan builds and under valgrind);
 * every output converts exactly to double (rfe_fix_to_double) and the estimate log writes each
 * double in the shortest form that reads back as the same double, so reading the golden gives
 * the Q value's double exactly. The host's own steps before the Q formats (the decimal
 * reader, the car-format log's unit factors, the period from the time stamps) are IEEE double
 * operations, correctly rounded and so the same on every conforming host. Compared: t, mu, sd,
 * valid, status and the observer's vx, vy, beta, yaw acceleration, sd_vx, sd_vy, sd_beta of
 * every row, and the saturation counts of the golden's metadata (all 0 on these logs).
 *
 * The run here takes mu_replay's path: the default preset (double), the log's metadata, the
 * wheel speeds through R and dt from the time stamps' median where the log asks for it
 * (the car-format log), then rfe_replay_run_observer_q31 (src/host/replay_q31.c). The logs are
 * the Makefile's Q31_OBS_GOLDEN_LOGS; a golden in the folder that this list does not name
 * fails the test, so none goes unchecked. Valgrind's light mode (test_light.h) checks every
 * second log.
 */
#include "test_common.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "log_timing.h"
#include "param_file.h"
#include "replay_q31.h"
#include "replay_real.h"
#include "table.h"
#include "test_light.h"

#define GOLDEN_DIR "scenarios/golden/observer_q31"

typedef struct {
    const char *sensor; /* the sensor log */
    const char *golden; /* its golden's file name in GOLDEN_DIR */
} golden_log_t;

static const golden_log_t LOGS[] = {
    {"scenarios/observer/abs_brake_mu02.csv", "abs_brake_mu02.q31.csv"},
    {"scenarios/observer/abs_brake_split_mu.csv", "abs_brake_split_mu.q31.csv"},
    {"scenarios/observer/dlc_mu035.csv", "dlc_mu035.q31.csv"},
    {"scenarios/observer/sine_dwell_mu09.csv", "sine_dwell_mu09.q31.csv"},
    {"scenarios/observer/traction_rwd_mu03.csv", "traction_rwd_mu03.q31.csv"},
    {"scenarios/observer/hill_known_grade.csv", "hill_known_grade.q31.csv"},
    {"scenarios/observer/creep_stop.csv", "creep_stop.q31.csv"},
    {"scenarios/car_format/dlc_mu035.csv", "car_format.dlc_mu035.q31.csv"},
};
#define N_LOGS (sizeof LOGS / sizeof LOGS[0])

static const char *const WHEEL[4] = {"fl", "fr", "rl", "rr"};

/* The value of metadata line `# key = value` of a CSV file as a string (into buf); fails the
 * test when the line is missing. */
static const char *meta_value(const char *path, const char *key, char *buf, size_t n)
{
    char line[512];
    const size_t kl = strlen(key);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    while (fgets(line, sizeof line, f) != NULL && line[0] == '#') {
        if (strncmp(line + 2, key, kl) == 0 && strncmp(line + 2 + kl, " = ", 3) == 0) {
            fclose(f);
            snprintf(buf, n, "%s", line + 2 + kl + 3);
            buf[strcspn(buf, "\r\n")] = '\0';
            return buf;
        }
    }
    fclose(f);
    fail_msg("%s: no metadata line '%s'", path, key);
    return NULL;
}

static unsigned long long meta_uint(const char *path, const char *key)
{
    char buf[64];
    return strtoull(meta_value(path, key, buf, sizeof buf), NULL, 10);
}

/* The parameters of mu_replay's run on @p log (default preset < metadata; a log of
 * circumferential wheel speeds through R; dt, when not given, the time stamps' median). */
static void replay_setup(const char *sensor, rfe_sensor_log_t *log, rfe_param_set_t *ps)
{
    rfe_io_error_t err;
    rfe_log_period_t per;
    memset(log, 0, sizeof *log);
    if (rfe_sensor_log_read(sensor, log, &err) != 0) {
        fail_msg("%s:%zu:%zu: %s", err.file, err.line, err.col, err.msg);
    }
    assert_int_equal(rfe_param_set_preset_f64(ps, RFE_PRESET_DEFAULT), 0);
    if (rfe_param_set_apply_meta(ps, log, sensor, &err) != 0) {
        fail_msg("%s: %s", sensor, err.msg);
    }
    if (log->omega_linear != 0) {
        assert_int_equal(rfe_sensor_log_wheel_radius(log, ps->value[RFE_PK_R]), 0);
    }
    if ((ps->origin[RFE_PK_dt].file == NULL) && (rfe_log_period(log, &per) == 0)) {
        ps->value[RFE_PK_dt] = per.median;
    }
}

/* Fails unless column @p name of golden row @p r is exactly @p got. */
static void expect_exact(const char *golden, const test_table_t *g, size_t r, const char *name,
                         double got)
{
    const double want = test_table_get(g, r, name);
    if (got != want) {
        fail_msg("%s row %zu: %s %.17g, golden %.17g (not bit-exact)", golden, r, name, got,
                 want);
    }
}

/* One golden: returns the number of values compared. */
static size_t check_golden(const golden_log_t *gl)
{
    char golden[512];
    char buf[64];
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_replay_q31_stats_t stats;
    rfe_est_row_t *rows;
    test_table_t g;
    size_t r;
    size_t w;
    size_t n = 0;
    snprintf(golden, sizeof golden, GOLDEN_DIR "/%s", gl->golden);
    replay_setup(gl->sensor, &log, &ps);
    rows = calloc(log.n_rows, sizeof *rows);
    assert_non_null(rows);
    assert_int_equal(rfe_replay_run_observer_q31(&ps, &log, rows, &stats, NULL, NULL), RFE_OK);
    if (test_table_load(golden, &g) != 0) {
        fail_msg("missing or unreadable golden %s (make observer-goldens-q31)", golden);
    }
    /* a golden of this run: the observer's, in fixed point */
    assert_string_equal(meta_value(golden, "velocity", buf, sizeof buf), "observer");
    assert_string_equal(meta_value(golden, "real", buf, sizeof buf), "q31");
    assert_int_equal(g.n_rows, log.n_rows);
    for (r = 0; r < log.n_rows; ++r) {
        char name[16];
        const rfe_est_row_t *e = &rows[r];
        assert_int_equal(e->has_velocity, 1);
        expect_exact(golden, &g, r, "t", e->t);
        for (w = 0; w < 4; ++w) {
            snprintf(name, sizeof name, "mu_%s", WHEEL[w]);
            expect_exact(golden, &g, r, name, e->mu[w]);
            snprintf(name, sizeof name, "sd_%s", WHEEL[w]);
            expect_exact(golden, &g, r, name, e->sd[w]);
            snprintf(name, sizeof name, "valid_%s", WHEEL[w]);
            expect_exact(golden, &g, r, name, (double)e->valid[w]);
        }
        expect_exact(golden, &g, r, "status", (double)e->status);
        expect_exact(golden, &g, r, "vx_est", e->vx);
        expect_exact(golden, &g, r, "vy_est", e->vy);
        expect_exact(golden, &g, r, "beta_est", e->beta);
        expect_exact(golden, &g, r, "yaw_acc_est", e->yaw_acc);
        expect_exact(golden, &g, r, "sd_vx", e->sd_vx);
        expect_exact(golden, &g, r, "sd_vy", e->sd_vy);
        expect_exact(golden, &g, r, "sd_beta", e->sd_beta);
        n += 4u * 3u + 2u + 7u;
    }
    assert_true(meta_uint(golden, "saturation_estimator_total") == stats.est_sat);
    assert_true(meta_uint(golden, "saturation_input_values") == stats.input_sat);
    test_table_free(&g);
    free(rows);
    rfe_sensor_log_free(&log);
    return n;
}

/* Every *.q31.csv in GOLDEN_DIR is one of LOGS (a golden left out of the list would go
 * unchecked), and every one of LOGS is there. */
static void check_folder_is_the_list(void)
{
    DIR *d = opendir(GOLDEN_DIR);
    struct dirent *e;
    size_t found = 0;
    size_t i;
    if (d == NULL) {
        fail_msg("no folder %s (make observer-goldens-q31)", GOLDEN_DIR);
    }
    while ((e = readdir(d)) != NULL) {
        const size_t len = strlen(e->d_name);
        int listed = 0;
        if ((len <= 8u) || (strcmp(e->d_name + len - 8u, ".q31.csv") != 0)) {
            continue;
        }
        for (i = 0; i < N_LOGS; ++i) {
            listed |= (strcmp(e->d_name, LOGS[i].golden) == 0);
        }
        if (!listed) {
            closedir(d);
            fail_msg("%s/%s is not in this test's list (nor in the Makefile's "
                     "Q31_OBS_GOLDEN_LOGS?)", GOLDEN_DIR, e->d_name);
        }
        ++found;
    }
    closedir(d);
    assert_int_equal(found, N_LOGS);
}

/* REQ: the q31 pipeline reproduces its goldens bit for bit on the observer logs. */
/* REQ-FXP-017 */
static void test_rfe_pipeline_q31_matches_observer_goldens(void **state)
{
    const size_t stride = rfe_test_stride(2u);
    size_t i;
    size_t values = 0;
    size_t files = 0;
    (void)state;
    check_folder_is_the_list();
    for (i = 0; i < N_LOGS; i += stride) {
        values += check_golden(&LOGS[i]);
        ++files;
    }
    printf("  %zu q31 observer goldens, %zu values, every one bit-exact\n", files, values);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_pipeline_q31_matches_observer_goldens),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
