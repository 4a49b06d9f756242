/**
 * @file test_golden_q31.c
 * @brief The fixed-point estimator against its own goldens, bit for bit: every value of
 *        scenarios/golden/<stem>.<config>.q31.csv (written by `make goldens-q31`, i.e.
 *        `mu_replay --real q31`) must be reproduced exactly, so any change to the integer
 *        arithmetic is seen.
 *
 * Why an exact comparison is possible: the q31 library uses integer operations only, in a fixed
 * order (bit-identical on every platform and build: this test runs in the optimised, the
 * -O0 coverage and the ASan/UBSan builds and under valgrind); mu (Q29) and sd (Q30) convert
 * exactly to double (rfe_fix_to_double), and the estimate log writes each double in the
 * shortest form that reads back as the same double (RFE_NUMFMT_DOUBLE), so reading the golden
 * gives the Q value's double exactly. Compared: t, mu, sd, valid, status of every row, and the
 * saturation counts of the golden's metadata (all 0 on these logs).
 *
 * The run here takes the same path as mu_replay: the library preset (double), the log's
 * metadata, then --filter / --tyre; rfe_replay_run_q31 (src/host/replay_q31.c). The four
 * configurations are those of the float goldens on the noisy logs: paper.sckf, paper.ckf,
 * absolute.sckf (paper preset, absolute tyre) and default.sckf.
 */
#include "test_common.h"

#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_q31.h"
#include "replay_real.h"
#include "table.h"
#include "test_light.h"

#define GOLDEN_DIR "scenarios/golden"
#define SCENARIO_DIR "scenarios"

static const char *const STEMS[] = {
    "accel_low_mu",        "brake_in_turn",      "cruise",
    "hard_brake_high_mu",  "hard_brake_low_mu",  "mu_step_hard_brake",
    "paper_high_mu_brake", "paper_low_mu_brake", "paper_mu_step",
    "sine_steer_high_mu",  "sine_steer_low_mu",  "split_mu_brake",
    "split_mu_hard_brake",
    /* issue 17's scenarios */
    "double_lane_change_high_mu", "double_lane_change_low_mu", "ramp_steer_high_mu",
    "ramp_steer_low_mu",   "brake_in_turn_low_mu", "wrong_tyre_data"};
#define N_STEMS (sizeof STEMS / sizeof STEMS[0])

static const char *const WHEEL[4] = {"fl", "fr", "rl", "rr"};

typedef struct {
    const char *tag;       /* file tag */
    rfe_preset_t preset;   /* --preset */
    int set_filter;        /* --filter given */
    rfe_filter_kind_t kind;
    int set_tyre;          /* --tyre given */
    rfe_tyre_mode_t tyre;
} config_t;

static const config_t CONFIGS[] = {
    {"paper.sckf", RFE_PRESET_PAPER, 1, RFE_FILTER_SCKF, 0, RFE_TYRE_PAPER},
    {"paper.ckf", RFE_PRESET_PAPER, 1, RFE_FILTER_CKF, 0, RFE_TYRE_PAPER},
    {"absolute.sckf", RFE_PRESET_PAPER, 0, RFE_FILTER_SCKF, 1, RFE_TYRE_ABSOLUTE},
    {"default.sckf", RFE_PRESET_DEFAULT, 0, RFE_FILTER_SCKF, 0, RFE_TYRE_ABSOLUTE},
};

/* The value of metadata line `# key = value` of a CSV file as an unsigned integer; fails the
 * test when the line is missing. */
static unsigned long long meta_uint(const char *path, const char *key)
{
    char line[512];
    const size_t kl = strlen(key);
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    while (fgets(line, sizeof line, f) != NULL && line[0] == '#') {
        if (strncmp(line + 2, key, kl) == 0 && strncmp(line + 2 + kl, " = ", 3) == 0) {
            fclose(f);
            return strtoull(line + 2 + kl + 3, NULL, 10);
        }
    }
    fclose(f);
    fail_msg("%s: no metadata line '%s'", path, key);
    return 0;
}

/* One golden: returns the number of values compared. */
static size_t check_golden(const char *stem, const config_t *c)
{
    char sensor[512];
    char golden[512];
    rfe_sensor_log_t log;
    rfe_param_set_t ps;
    rfe_io_error_t err;
    rfe_replay_q31_stats_t stats;
    rfe_est_row_t *rows;
    test_table_t g;
    size_t r;
    size_t w;
    size_t n = 0;
    snprintf(sensor, sizeof sensor, SCENARIO_DIR "/%s.csv", stem);
    snprintf(golden, sizeof golden, GOLDEN_DIR "/%s.%s.q31.csv", stem, c->tag);
    memset(&log, 0, sizeof log);
    if (rfe_sensor_log_read(sensor, &log, &err) != 0) {
        fail_msg("%s:%zu:%zu: %s", err.file, err.line, err.col, err.msg);
    }
    assert_int_equal(rfe_param_set_preset_f64(&ps, c->preset), 0);
    if (rfe_param_set_apply_meta(&ps, &log, sensor, &err) != 0) {
        fail_msg("%s: %s", sensor, err.msg);
    }
    if (c->set_filter) {
        ps.filter = c->kind;
    }
    if (c->set_tyre) {
        ps.tyre = c->tyre;
    }
    rows = calloc(log.n_rows, sizeof *rows);
    assert_non_null(rows);
    assert_int_equal(rfe_replay_run_q31(&ps, &log, rows, &stats, NULL, NULL), RFE_OK);
    if (test_table_load(golden, &g) != 0) {
        fail_msg("missing or unreadable golden %s (make goldens-q31)", golden);
    }
    assert_int_equal(g.n_rows, log.n_rows);
    for (r = 0; r < log.n_rows; ++r) {
        char name[16];
        if (rows[r].t != test_table_get(&g, r, "t")) {
            fail_msg("%s row %zu: t", golden, r);
        }
        for (w = 0; w < 4; ++w) {
            double want;
            snprintf(name, sizeof name, "mu_%s", WHEEL[w]);
            want = test_table_get(&g, r, name);
            if (rows[r].mu[w] != want) {
                fail_msg("%s row %zu: mu_%s %.17g, golden %.17g (not bit-exact)", golden, r,
                         WHEEL[w], rows[r].mu[w], want);
            }
            snprintf(name, sizeof name, "sd_%s", WHEEL[w]);
            want = test_table_get(&g, r, name);
            if (rows[r].sd[w] != want) {
                fail_msg("%s row %zu: sd_%s %.17g, golden %.17g (not bit-exact)", golden, r,
                         WHEEL[w], rows[r].sd[w], want);
            }
            snprintf(name, sizeof name, "valid_%s", WHEEL[w]);
            if ((double)rows[r].valid[w] != test_table_get(&g, r, name)) {
                fail_msg("%s row %zu: valid_%s", golden, r, WHEEL[w]);
            }
            n += 3;
        }
        if ((double)rows[r].status != test_table_get(&g, r, "status")) {
            fail_msg("%s row %zu: status %d, golden %g", golden, r, rows[r].status,
                     test_table_get(&g, r, "status"));
        }
        n += 2;
    }
    assert_true(meta_uint(golden, "saturation_estimator_total") == stats.est_sat);
    assert_true(meta_uint(golden, "saturation_input_values") == stats.input_sat);
    test_table_free(&g);
    free(rows);
    rfe_sensor_log_free(&log);
    return n;
}

/* REQ: the q31 estimator reproduces its goldens bit for bit on every noisy scenario log in
 * every configuration of the float goldens. */
/* REQ-FXP-009 */
static void test_rfe_friction_q31_matches_goldens(void **state)
{
    size_t s;
    size_t c;
    size_t values = 0;
    size_t files = 0;
    (void)state;
    for (c = 0; c < sizeof CONFIGS / sizeof CONFIGS[0]; ++c) {
        for (s = 0; s < N_STEMS; s += rfe_test_stride(5u)) { /* light mode (valgrind): every 5th */
            values += check_golden(STEMS[s], &CONFIGS[c]);
            ++files;
        }
    }
    printf("  %zu q31 goldens, %zu values, every one bit-exact\n", files, values);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_friction_q31_matches_goldens),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
