/**
 * @file test_csv_log.c
 * @brief Tests of the sensor-log reader, the estimate-log writer and the text helpers.
 *
 * Run from the repository root (fixtures under test/host/data/). Error positions are
 * checked exactly: LINE and COL are 1-based, COL of a CSV error is the field index.
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
#include <unistd.h>

#include "csv_log.h"
#include "log_text.h"
#include "text_io.h"

#define DATA "test/host/data/"

#define HDR "t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
#define ROW0 "0,0,20,0,0,0,-2,0,60,60,60,60\n"
/* The inputs of a production car's log (no vx, vy, yaw_acc), without the line end. */
#define HDR_NOVEL "t,delta,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr"
#define ROW1 "0.01,0,19.98,0,0,0,-2,0,59.9,59.9,59.9,59.9\n"

/* ------------------------------------------------------------ reading: valid input */

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_shuffled_columns_with_extra(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_small.csv", &log, &err), 0);
    assert_int_equal(log.n_rows, 3);
    assert_int_equal(log.has_truth, 1);
    /* Row 2 has blanks around fields; row 3 an exponent and an empty extra field. */
    assert_true(log.rows[1].t == 0.01);
    assert_true(log.rows[1].ay == 0.2);
    assert_true(log.rows[2].vx == 19.95);
    assert_true(log.rows[2].ay == -0.3);
    assert_true(log.rows[0].delta == 0.001);
    assert_true(log.rows[0].yaw_rate == 0.02);
    assert_true(log.rows[0].yaw_acc == 0.03);
    assert_true(log.rows[0].ax == -2.5);
    assert_true(log.rows[0].vy == 0.01);
    assert_true(log.rows[0].omega[RFE_FL] == 61.5);
    assert_true(log.rows[0].omega[RFE_RR] == 61.8);
    assert_true(log.rows[0].mu_true[RFE_FL] == 0.8);
    assert_true(log.rows[0].mu_true[RFE_RL] == 0.82);
    assert_true(log.rows[0].mu_true[RFE_RR] == 0.85);
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_metadata_collected(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_small.csv", &log, &err), 0);
    /* The '#' line without '=' is a comment, not metadata. */
    assert_int_equal(log.n_meta, 4);
    assert_string_equal(rfe_sensor_log_meta(&log, "scenario"), "unit_test");
    assert_string_equal(rfe_sensor_log_meta(&log, "mu0"), "0.6");
    assert_string_equal(rfe_sensor_log_meta(&log, "tyre"), "absolute");
    assert_null(rfe_sensor_log_meta(&log, "dt"));
    assert_int_equal(log.meta[2].line, 5);
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_without_truth(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_notruth.csv", &log, &err), 0);
    assert_int_equal(log.has_truth, 0);
    assert_int_equal(log.n_rows, 3);
    assert_int_equal(log.n_meta, 0);
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_crlf_bom_and_trailing_blank_lines(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("\xEF\xBB\xBFt,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,"
                               "omega_fr,omega_rl,omega_rr\r\n0,0,20,0,0,0,-2,0,60,60,60,60.5\r\n\r\n\n",
                               &log, &err),
                     0);
    assert_int_equal(log.n_rows, 1);
    assert_true(log.rows[0].omega[RFE_RR] == 60.5);
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_very_long_number_not_truncated(void **state)
{
    /* 200000 leading zeros then "1.5": a fixed-size line buffer would cut it. */
    const size_t zeros = 200000u;
    size_t n = strlen(HDR) + zeros + 64u;
    char *text = malloc(n);
    char *p;
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_non_null(text);
    p = text + sprintf(text, "%s0,0,", HDR);
    memset(p, '0', zeros);
    p += zeros;
    strcpy(p, "1.5,0,0,0,-2,0,60,60,60,60\n");
    assert_int_equal(read_log_text(text, &log, &err), 0);
    assert_true(log.rows[0].vx == 1.5);
    rfe_sensor_log_free(&log);
    free(text);
}

/* ------------------------------------------------------------ reading: errors */

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_missing_column(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "missing_column.csv", &log, &err), -1);
    assert_string_equal(err.file, DATA "missing_column.csv");
    assert_int_equal(err.line, 2);
    assert_int_equal(err.col, 0);
    /* vx, vy, yaw_acc are optional together (a production car has none of them) */
    assert_non_null(strstr(err.msg, "velocity column 'vy' missing (give all of vx, vy, yaw_acc or none)"));
    assert_null(log.rows);
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_missing_required_column(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    memset(&log, 0, sizeof log);
    assert_int_equal(read_log_text("t,delta,yaw_rate,ax,omega_fl,omega_fr,omega_rl,omega_rr\n"
                               "0,0,0,0,60,60,60,60\n", &log, &err), -1);
    assert_non_null(strstr(err.msg, "missing column 'ay'"));
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_production_car_log(void **state)
{
    /* no vx, vy, yaw_acc; brake pressures; a partial pressure group is rejected */
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    memset(&log, 0, sizeof log);
    assert_int_equal(rfe_sensor_log_read(DATA "good_esc.csv", &log, &err), 0);
    assert_int_equal(log.n_rows, 3);
    assert_int_equal(log.has_velocity, 0);
    assert_int_equal(log.has_pressure, 1);
    assert_int_equal(log.has_torque, 0);
    assert_int_equal(log.has_grade, 0);
    assert_true(log.rows[1].p_brake[2] == 0.3);
    assert_true(log.rows[1].omega[0] == 59.94);
    assert_true(log.rows[1].vx == 0.0);
    rfe_sensor_log_free(&log);
    assert_int_equal(read_log_text("t,delta,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr,p_fl\n"
                               "0,0,0,0,0,60,60,60,60,1\n", &log, &err), -1);
    /* every missing member of the group named, not only the first */
    assert_string_equal(err.msg, "pressure columns 'p_fr', 'p_rl', 'p_rr' missing (give all of "
                                 "p_fl, p_fr, p_rl, p_rr or none)");
    assert_int_equal(read_log_text("t,delta,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr,grade,"
                               "torque_fl,torque_fr,torque_rl,torque_rr\n"
                               "0,0,0,0,0,60,60,60,60,0.05,100,100,0,0\n", &log, &err), 0);
    assert_int_equal(log.has_torque, 1);
    assert_int_equal(log.has_grade, 1);
    assert_true(log.rows[0].grade == 0.05);
    assert_true(log.rows[0].torque[1] == 100.0);
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_bad_number_position(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "bad_number.csv", &log, &err), -1);
    assert_int_equal(err.line, 4);
    assert_int_equal(err.col, 3);
    assert_non_null(strstr(err.msg, "column 'vx'"));
    assert_non_null(strstr(err.msg, "'19.9x'"));
    assert_int_equal(log.n_rows, 0);
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_wrong_column_count(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "wrong_count.csv", &log, &err), -1);
    assert_int_equal(err.line, 3);
    assert_int_equal(err.col, 12); /* first missing field */
    assert_non_null(strstr(err.msg, "11 fields, header has 12"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_too_many_fields(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text(HDR ROW0 "0.01,0,19.98,0,0,0,-2,0,59.9,59.9,59.9,59.9,7\n", &log,
                               &err),
                     -1);
    assert_int_equal(err.line, 3);
    assert_int_equal(err.col, 13); /* first extra field */
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_empty_file(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "empty.csv", &log, &err), -1);
    assert_int_equal(err.line, 0);
    assert_non_null(strstr(err.msg, "empty file"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_only_metadata_no_header(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("# dt = 0.01\n\n", &log, &err), -1);
    assert_non_null(strstr(err.msg, "no header row"));
    assert_int_equal(log.n_meta, 0); /* freed on error */
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_nan_text_rejected(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "nan_value.csv", &log, &err), -1);
    assert_int_equal(err.line, 3);
    assert_int_equal(err.col, 7);
    assert_non_null(strstr(err.msg, "column 'ax'"));
    assert_non_null(strstr(err.msg, "nan"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_inf_text_rejected(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text(HDR "0,0,20,0,0,0,-2,0,60,60,60,-Infinity\n", &log, &err), -1);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.col, 12);
    assert_non_null(strstr(err.msg, "finite"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_empty_field_rejected(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text(HDR "0,0,20,0,,0,-2,0,60,60,60,60\n", &log, &err), -1);
    assert_int_equal(err.col, 5);
    assert_non_null(strstr(err.msg, "column 'yaw_rate': empty field"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_overflow_rejected(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text(HDR "0,0,1e999,0,0,0,-2,0,60,60,60,60\n", &log, &err), -1);
    assert_int_equal(err.col, 3);
    assert_non_null(strstr(err.msg, "out of range"));
}

/* Reads @p text with RFE_CELLS_KEEP (the stream code of a real file). */
static int read_keep(const char *text, rfe_sensor_log_t *log, rfe_io_error_t *err)
{
    FILE *f = tmpfile();
    int rc;
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1u, strlen(text), f), strlen(text));
    rewind(f);
    rc = rfe_sensor_log_read_stream_cells(f, "mem.csv", RFE_CELLS_KEEP, log, err);
    fclose(f);
    return rc;
}

/* Reads @p text with @p opts (rfe_sensor_log_read_stream_opts). */
static int read_opts_text(const char *text, rfe_cells_t cells, rfe_inputs_t inputs,
                          rfe_sensor_log_t *log, rfe_io_error_t *err)
{
    rfe_read_opts_t opts;
    FILE *f = tmpfile();
    int rc;
    opts.cells = cells;
    opts.inputs = inputs;
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1u, strlen(text), f), strlen(text));
    rewind(f);
    rc = rfe_sensor_log_read_stream_opts(f, "mem.csv", &opts, log, err);
    fclose(f);
    return rc;
}

/* A log missing columns of several rules names every one of them in one message, in
 * DATA.md's order: required inputs, the steering angle, each optional group given in part
 * (its rule after its last missing column), with column_ aliases. */
/* REQ-CLI-001 REQ-CSV-002 */
static void test_rfe_sensor_log_read_every_missing_column(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    memset(&log, 0, sizeof log);
    assert_int_equal(read_log_text("# column_p_rl = BrkRL\n"
                                   "t,yaw_rate,ay,omega_fl,omega_fr,omega_rl,p_fl,p_rr,util_fl\n"
                                   "0,0,0,60,60,60,1,1,0.1\n", &log, &err), -1);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.col, 0);
    assert_string_equal(err.msg,
                        "missing columns 'delta' (the road-wheel angle) or 'swa' (the "
                        "steering-wheel angle, with obs_steer_ratio), 'ax', 'omega_rr', "
                        "'util_fr', 'util_rl', 'util_rr' (truth: give all of util_fl, util_fr, "
                        "util_rl, util_rr or none), 'p_fr', 'p_rl' (named 'BrkRL' by its "
                        "column_p_rl metadata) (pressure: give all of p_fl, p_fr, p_rl, p_rr or "
                        "none)");
    assert_null(log.rows);
    /* one group alone keeps its message, every missing member named */
    assert_int_equal(read_log_text(HDR_NOVEL ",torque_fl,torque_rr\n0,0,0,0,0,60,60,60,60,1,1\n",
                                   &log, &err), -1);
    assert_string_equal(err.msg, "torque columns 'torque_fr', 'torque_rl' missing (give all of "
                                 "torque_fl, torque_fr, torque_rl, torque_rr or none)");
    /* measured velocities: named with the others; alone, the caller's to say */
    assert_int_equal(read_opts_text("t,delta,yaw_rate,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
                                    "0,0,0,0,60,60,60,60\n", RFE_CELLS_STRICT,
                                    RFE_INPUTS_MEASURED, &log, &err), -1);
    assert_string_equal(err.msg, "missing columns 'vx', 'vy', 'yaw_acc' (velocity: measured "
                                 "velocities need all of vx, vy, yaw_acc), 'ax'");
    assert_int_equal(read_opts_text(HDR_NOVEL "\n0,0,0,0,0,60,60,60,60\n", RFE_CELLS_STRICT,
                                    RFE_INPUTS_OBSERVER, &log, &err), 0);
    rfe_sensor_log_free(&log);
    assert_int_equal(read_opts_text(HDR_NOVEL "\n0,0,0,0,0,60,60,60,60\n", RFE_CELLS_STRICT,
                                    RFE_INPUTS_MEASURED, &log, &err), 0);
    assert_int_equal(log.has_velocity, 0);
    rfe_sensor_log_free(&log);
    assert_int_equal(read_opts_text("t,delta,vx,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
                                    "0,0,20,0,0,0,60,60,60,60\n", RFE_CELLS_STRICT,
                                    RFE_INPUTS_MEASURED, &log, &err), -1);
    assert_string_equal(err.msg, "velocity columns 'vy', 'yaw_acc' missing (measured velocities "
                                 "need all of vx, vy, yaw_acc)");
    {
        /* a list longer than a message (four 300-character aliases) is cut with "..." */
        static const char *const cols[4] = {"omega_fl", "omega_fr", "omega_rl", "omega_rr"};
        char text[2048];
        char alias[301];
        size_t used = 0u;
        size_t i;
        memset(alias, 'W', 300u);
        alias[300] = '\0';
        for (i = 0u; i < 4u; ++i) {
            used += (size_t)snprintf(text + used, sizeof text - used, "# column_%s = %s%zu\n",
                                     cols[i], alias, i);
        }
        (void)snprintf(text + used, sizeof text - used, HDR "0,0,20,0,0,0,0,0,60,60,60,60\n");
        assert_int_equal(read_log_text(text, &log, &err), -1);
        assert_non_null(strstr(err.msg, "missing columns 'omega_fl' (named 'WWW"));
        assert_non_null(strstr(err.msg, "..."));
        assert_true(strlen(err.msg) < sizeof err.msg - 1u);
    }
}

/* The bad cells of the input columns a run does not use (rfe_inputs_t) are read as NaN too
 * but counted apart (bad_ignored): they reject no row (no bad bits), so bad_cells and
 * bad_rows are those of the cells the estimator gets. */
/* REQ-CSV-007 */
static void test_rfe_sensor_log_read_cells_unused_columns(void **state)
{
    static const char text[] = HDR "0,0,nan,0,0,0,-2,0,60,60,60,60\n"
                                   "0.01,0,20,,0,0,nan,0,60,60,60,60\n"
                                   "0.02,0,20,0,0,inf,-2,0,60,60,60,60\n";
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    memset(&log, 0, sizeof log);
    assert_int_equal(read_opts_text(text, RFE_CELLS_KEEP, RFE_INPUTS_OBSERVER, &log, &err), 0);
    assert_true(isnan(log.rows[0].vx));
    assert_int_equal(log.rows[0].bad, 0u);
    assert_int_equal(log.rows[1].bad, 1u << RFE_CELL_NONFINITE); /* ax: used */
    assert_int_equal(log.rows[2].bad, 0u);
    assert_int_equal(log.bad_cells[RFE_CELL_EMPTY], 0);
    assert_int_equal(log.bad_cells[RFE_CELL_NONFINITE], 1);
    assert_int_equal(log.bad_rows, 1);
    assert_int_equal(log.bad_first_line, 3);
    assert_int_equal(log.bad_first_col, 7);
    assert_int_equal(log.bad_ignored, 3);
    assert_int_equal(log.bad_ignored_first_line, 2);
    assert_int_equal(log.bad_ignored_first_col, 3);
    assert_string_equal(log.unused_cols, "vx, vy, yaw_acc");
    rfe_sensor_log_free(&log);
    /* the same log measured (auto: it has vx, vy, yaw_acc): every cell counted */
    assert_int_equal(read_opts_text(text, RFE_CELLS_KEEP, RFE_INPUTS_AUTO, &log, &err), 0);
    assert_int_equal(log.bad_rows, 3);
    assert_int_equal(log.bad_ignored, 0);
    assert_null(log.unused_cols);
    rfe_sensor_log_free(&log);
    /* measured velocities: the brake pressures are not used */
    assert_int_equal(read_opts_text("t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,"
                                    "omega_rl,omega_rr,p_fl,p_fr,p_rl,p_rr\n"
                                    "0,0,20,0,0,0,-2,0,60,60,60,60,nan,0,0,0\n",
                                    RFE_CELLS_KEEP, RFE_INPUTS_AUTO, &log, &err), 0);
    assert_int_equal(log.bad_rows, 0);
    assert_int_equal(log.rows[0].bad, 0u);
    assert_int_equal(log.bad_ignored, 1);
    assert_string_equal(log.unused_cols, "p_*");
    rfe_sensor_log_free(&log);
    /* the plain reader: every input used */
    assert_int_equal(read_keep(text, &log, &err), 0);
    assert_int_equal(log.bad_rows, 3);
    assert_int_equal(log.bad_ignored, 0);
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-007 */
static void test_rfe_sensor_log_read_cells_keep_bad_inputs(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    /* row 2: ax nan and omega_rr empty; row 3 clean; row 4: vx -inf and ay 1e999;
     * row 5: delta 1e308 deg overflows in SI (x pi/180 fits, x 1e9 does not: scale) */
    assert_int_equal(read_keep("# scale_delta = 1e9\n" HDR
                               "0,0,20,0,0,0,nan,0,60,60,60,\n"
                               ROW1
                               "0.02,0,-inf,0,0,0,-2,1e999,60,60,60,60\n"
                               "0.03,1e308,20,0,0,0,-2,0,60,60,60,60\n", &log, &err), 0);
    assert_int_equal(log.n_rows, 4);
    assert_true(isnan(log.rows[0].ax));
    assert_true(isnan(log.rows[0].omega[RFE_RR]));
    assert_int_equal(log.rows[0].bad, (1u << RFE_CELL_EMPTY) | (1u << RFE_CELL_NONFINITE));
    assert_int_equal(log.rows[1].bad, 0u);
    assert_true(isinf(log.rows[2].vx) && (log.rows[2].vx < 0.0));
    assert_true(isinf(log.rows[2].ay) && (log.rows[2].ay > 0.0));
    assert_int_equal(log.rows[2].bad, (1u << RFE_CELL_NONFINITE) | (1u << RFE_CELL_RANGE));
    assert_true(isinf(log.rows[3].delta));
    assert_int_equal(log.rows[3].bad, 1u << RFE_CELL_RANGE);
    assert_int_equal(log.bad_cells[RFE_CELL_EMPTY], 1);
    assert_int_equal(log.bad_cells[RFE_CELL_NONFINITE], 2);
    assert_int_equal(log.bad_cells[RFE_CELL_RANGE], 2);
    assert_int_equal(log.bad_rows, 3);
    assert_int_equal(log.bad_first_line, 3); /* line 3, the first data row; ax = field 7 */
    assert_int_equal(log.bad_first_col, 7);
    assert_string_equal(rfe_cell_cause_str(RFE_CELL_RANGE), "out of range");
    assert_string_equal(rfe_cell_cause_str(RFE_CELL_EMPTY), "empty");
    assert_string_equal(rfe_cell_cause_str(RFE_CELL_NONFINITE), "nan/inf");
    assert_string_equal(rfe_cell_cause_str(RFE_CELL_CAUSES), "?");
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-007 */
static void test_rfe_sensor_log_read_cells_keep_still_rejects(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    /* text that is no number is a broken file, not a sample */
    assert_int_equal(read_keep(HDR "0,0,20,0,0,0,-2x,0,60,60,60,60\n", &log, &err), -1);
    assert_int_equal(err.col, 7);
    assert_non_null(strstr(err.msg, "not a decimal number"));
    /* the time stamp orders the rows: never kept */
    assert_int_equal(read_keep(HDR ROW0 "nan,0,20,0,0,0,-2,0,60,60,60,60\n", &log, &err), -1);
    assert_int_equal(err.col, 1);
    assert_int_equal(read_keep(HDR ",0,20,0,0,0,-2,0,60,60,60,60\n", &log, &err), -1);
    /* truth never reaches the estimator: a bad truth cell stays an error */
    assert_int_equal(read_keep("t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,"
                               "omega_rr,mu_fl,mu_fr,mu_rl,mu_rr\n"
                               "0,0,20,0,0,0,-2,0,60,60,60,60,0.5,nan,0.5,0.5\n", &log, &err), -1);
    assert_int_equal(err.col, 14);
    /* and strict mode is the plain reader */
    assert_int_equal(read_log_text(HDR "0,0,20,0,0,0,nan,0,60,60,60,60\n", &log, &err), -1);
}

/* REQ-CSV-001 REQ-CSV-002 */
static void test_rfe_sensor_log_read_partial_truth(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "partial_truth.csv", &log, &err), -1);
    assert_int_equal(err.line, 1);
    assert_non_null(strstr(err.msg, "'mu_rr' missing"));
}

/* util_fl..util_rr: a second optional truth group, parsed like mu_* (any column order). */
/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_util_columns_parsed(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_util.csv", &log, &err), 0);
    assert_int_equal(log.n_rows, 3);
    assert_int_equal(log.has_truth, 1);
    assert_int_equal(log.has_util, 1);
    assert_true(log.rows[0].util_true[RFE_FL] == 0.25);
    assert_true(log.rows[0].util_true[RFE_FR] == 0.5);
    assert_true(log.rows[0].util_true[RFE_RL] == 0.125);
    assert_true(log.rows[0].util_true[RFE_RR] == 0.05);
    assert_true(log.rows[1].util_true[RFE_FL] == 0.75);
    assert_true(log.rows[1].util_true[RFE_FR] == 0.1); /* "1e-1" */
    assert_true(log.rows[2].util_true[RFE_RR] == 0.07);
    assert_true(log.rows[2].mu_true[RFE_RR] == 0.8);
    rfe_sensor_log_free(&log);
}

/* Without util columns: has_util 0 (good_small has mu_* only). */
/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_no_util_columns(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "good_small.csv", &log, &err), 0);
    assert_int_equal(log.has_truth, 1);
    assert_int_equal(log.has_util, 0);
    rfe_sensor_log_free(&log);
}

/* The two truth groups are independent: util without mu is accepted. */
/* REQ-CSV-001 REQ-CSV-002 */
static void test_rfe_sensor_log_read_util_without_mu(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,"
                               "omega_rr,util_fl,util_fr,util_rl,util_rr\n"
                               "0,0,20,0,0,0,-2,0,60,60,60,60,0.1,0.2,0.3,0.4\n",
                               &log, &err),
                     0);
    assert_int_equal(log.has_truth, 0);
    assert_int_equal(log.has_util, 1);
    assert_true(log.rows[0].util_true[RFE_RR] == 0.4);
    rfe_sensor_log_free(&log);
}

/* Only some util columns: all or none, the first missing one named, header line. */
/* REQ-CSV-001 REQ-CSV-002 */
static void test_rfe_sensor_log_read_partial_util(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("# dt = 0.01\n"
                               "t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,"
                               "omega_rr,util_fl,util_rl,util_rr\n"
                               "0,0,20,0,0,0,-2,0,60,60,60,60,0.1,0.3,0.4\n",
                               &log, &err),
                     -1);
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.msg, "'util_fr' missing"));
    assert_non_null(strstr(err.msg, "util_fl, util_fr, util_rl, util_rr"));
    assert_int_equal(log.n_rows, 0);
}

/* A util field is a needed field: a non-number is an error at its position. */
/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_bad_util_value(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,"
                               "omega_rr,util_fl,util_fr,util_rl,util_rr\n"
                               "0,0,20,0,0,0,-2,0,60,60,60,60,0.1,high,0.3,0.4\n",
                               &log, &err),
                     -1);
    assert_int_equal(err.line, 2);
    assert_int_equal(err.col, 14);
    assert_non_null(strstr(err.msg, "column 'util_fr'"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_time_not_increasing(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "time_backwards.csv", &log, &err), -1);
    assert_int_equal(err.line, 4);
    assert_int_equal(err.col, 1);
    assert_non_null(strstr(err.msg, "time not increasing"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_header_only(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "header_only.csv", &log, &err), -1);
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.msg, "no data rows"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_duplicate_column(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,"
                               "omega_rr,vx\n",
                               &log, &err),
                     -1);
    assert_int_equal(err.line, 1);
    assert_int_equal(err.col, 13);
    assert_non_null(strstr(err.msg, "duplicate column 'vx' (also column 3)"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_empty_column_name(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("t,,delta\n", &log, &err), -1);
    assert_int_equal(err.col, 2);
    assert_non_null(strstr(err.msg, "empty column name"));
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_blank_line_between_rows(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text(HDR ROW0 "\n" ROW1, &log, &err), -1);
    assert_int_equal(err.line, 3);
    assert_non_null(strstr(err.msg, "empty line"));
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_comment_after_header(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text(HDR ROW0 "# late = 1\n" ROW1, &log, &err), -1);
    assert_int_equal(err.line, 3);
    assert_non_null(strstr(err.msg, "after the header"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_nul_byte(void **state)
{
    static const char text[] = HDR "0,0,20\0,0,0,0,-2,0,60,60,60,60\n";
    FILE *f = tmpfile();
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1u, sizeof text - 1u, f), sizeof text - 1u);
    rewind(f);
    assert_int_equal(rfe_sensor_log_read_stream(f, "nul.csv", &log, &err), -1);
    fclose(f);
    assert_int_equal(err.line, 2);
    assert_non_null(strstr(err.msg, "NUL"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_nonexistent_file(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(rfe_sensor_log_read(DATA "does_not_exist.csv", &log, &err), -1);
    assert_int_equal(err.line, 0);
    assert_non_null(strstr(err.msg, "cannot open"));
}

/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_long_bad_field_quoted_short(void **state)
{
    /* The message quotes at most 40 characters of a huge bad field: still one short line. */
    const size_t big = 100000u;
    char *text = malloc(strlen(HDR) + big + 64u);
    char *p;
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_non_null(text);
    p = text + sprintf(text, "%s0,0,", HDR);
    memset(p, 'x', big);
    strcpy(p + big, ",0,0,0,-2,0,60,60,60,60\n");
    assert_int_equal(read_log_text(text, &log, &err), -1);
    assert_int_equal(err.col, 3);
    assert_non_null(strstr(err.msg, "...'"));
    assert_true(strlen(err.msg) < 120u);
    free(text);
}


/* REQ-CSV-002 */
static void test_rfe_sensor_log_read_directory_is_read_error(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    /* fopen() of a directory succeeds on Linux; the first read fails (EISDIR). */
    assert_int_equal(rfe_sensor_log_read(DATA, &log, &err), -1);
    assert_int_equal(err.line, 1);
    assert_non_null(strstr(err.msg, "read error"));
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_metadata_without_key_ignored(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("#  = orphan value\n# k = v = w\n" HDR ROW0, &log, &err), 0);
    assert_int_equal(log.n_meta, 1);
    assert_string_equal(log.meta[0].key, "k");
    assert_string_equal(log.meta[0].value, "v = w"); /* split at the first '=' only */
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-001 */
static void test_rfe_sensor_log_read_many_rows_grow(void **state)
{
    /* 1000 rows: the row array grows several times; every value lands in its row. */
    const size_t n = 1000u;
    char *text = malloc(strlen(HDR) + n * 64u);
    char *p;
    size_t i;
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_non_null(text);
    p = text + sprintf(text, "%s", HDR);
    for (i = 0u; i < n; ++i) {
        p += sprintf(p, "%zu,0,%zu,0,0,0,-2,0,60,60,60,60\n", i, 2u * i);
    }
    assert_int_equal(read_log_text(text, &log, &err), 0);
    assert_int_equal(log.n_rows, n);
    assert_true(log.rows[999].t == 999.0);
    assert_true(log.rows[999].vx == 1998.0);
    assert_true(log.rows[17].vx == 34.0);
    rfe_sensor_log_free(&log);
    free(text);
}

/* REQ-CSV-003 */
static void test_rfe_estimate_log_write_full_disk(void **state)
{
    rfe_est_row_t row;
    rfe_io_error_t err;
    FILE *probe = fopen("/dev/full", "w");
    (void)state;
    if (probe == NULL) {
        skip(); /* not Linux */
    }
    fclose(probe);
    memset(&row, 0, sizeof row);
    /* /dev/full accepts open and buffered writes; the flush at fclose fails (ENOSPC). */
    assert_int_equal(rfe_estimate_log_write("/dev/full", NULL, 0u, &row, 1u, RFE_NUMFMT_DOUBLE,
                                            &err),
                     -1);
    assert_non_null(strstr(err.msg, "write failed"));
}

/* ------------------------------------------------------------ writing */

/* REQ-CSV-003 */
static void test_rfe_estimate_log_write_round_trips_doubles(void **state)
{
    rfe_est_row_t rows[2];
    rfe_kv_t meta[2] = {{"generator", "test"}, {"input", "a\nb.csv"}};
    char *buf = NULL;
    size_t len = 0u;
    FILE *f = open_memstream(&buf, &len);
    double v[5];
    char *line;
    (void)state;
    memset(rows, 0, sizeof rows);
    rows[0].t = 0.1;
    rows[0].mu[0] = 0.1 + 0.2; /* needs 17 digits */
    rows[0].mu[3] = 1.0 / 3.0;
    rows[0].sd[1] = 0.003;
    rows[0].valid[2] = 1u;
    rows[1].t = 0.2;
    rows[1].status = 18;
    assert_non_null(f);
    assert_int_equal(rfe_estimate_log_write_stream(f, meta, 2u, rows, 2u, RFE_NUMFMT_DOUBLE), 0);
    fclose(f);
    /* The newline in the metadata value became '?': one line per key. */
    assert_non_null(strstr(buf, "# generator = test\n# input = a?b.csv\n"));
    assert_non_null(strstr(buf, "\nt,mu_fl,mu_fr,mu_rl,mu_rr,sd_fl,sd_fr,sd_rl,sd_rr,valid_fl,"
                                "valid_fr,valid_rl,valid_rr,status\n"));
    line = strstr(buf, "status\n") + 7;
    assert_int_equal(sscanf(line, "%lf,%lf,%*f,%*f,%lf,%*f,%lf", &v[0], &v[1], &v[2], &v[3]), 4);
    assert_true(v[0] == 0.1);
    assert_true(v[1] == 0.1 + 0.2);
    assert_true(v[2] == 1.0 / 3.0);
    assert_true(v[3] == 0.003); /* sd_fr, written as "0.003" */
    assert_non_null(strstr(line, ",0.003,"));
    assert_non_null(strstr(line, ",0,0,1,0,0\n0.2,"));
    assert_non_null(strstr(line, ",0,0,0,0,18\n"));
    free(buf);
}

/* REQ-CSV-003 */
static void test_rfe_estimate_log_write_float_format_round_trips_floats(void **state)
{
    rfe_est_row_t row;
    char *buf = NULL;
    size_t len = 0u;
    FILE *f = open_memstream(&buf, &len);
    const float x = 0.1f;
    float back;
    char *line;
    (void)state;
    memset(&row, 0, sizeof row);
    row.mu[0] = (double)x;
    assert_non_null(f);
    assert_int_equal(rfe_estimate_log_write_stream(f, NULL, 0u, &row, 1u, RFE_NUMFMT_FLOAT), 0);
    fclose(f);
    line = strchr(buf, '\n') + 1;
    assert_int_equal(sscanf(line, "%*f,%f", &back), 1);
    assert_true(back == x);
    assert_non_null(strstr(line, "0.100000001")); /* 9 digits, not 17 */
    free(buf);
}

/* REQ-CSV-003 */
static void test_rfe_estimate_log_write_unwritable_path(void **state)
{
    rfe_est_row_t row;
    rfe_io_error_t err;
    (void)state;
    memset(&row, 0, sizeof row);
    assert_int_equal(rfe_estimate_log_write("/nonexistent_dir/x.csv", NULL, 0u, &row, 1u,
                                            RFE_NUMFMT_DOUBLE, &err),
                     -1);
    assert_non_null(strstr(err.msg, "cannot open for writing"));
}

/* REQ-CSV-003 */
static void test_rfe_estimate_log_write_file_then_read_text(void **state)
{
    char path[] = "/tmp/rfe_test_estimate_XXXXXX";
    int fd = mkstemp(path);
    rfe_est_row_t row;
    rfe_io_error_t err;
    char text[512];
    FILE *f;
    size_t n;
    (void)state;
    assert_true(fd >= 0);
    close(fd);
    memset(&row, 0, sizeof row);
    row.t = 1.5;
    row.mu[0] = 0.25;
    assert_int_equal(rfe_estimate_log_write(path, NULL, 0u, &row, 1u, RFE_NUMFMT_DOUBLE, &err), 0);
    f = fopen(path, "r");
    assert_non_null(f);
    n = fread(text, 1u, sizeof text - 1u, f);
    text[n] = '\0';
    fclose(f);
    remove(path);
    assert_non_null(strstr(text, "\n1.5,0.25,0,0,0,0,0,0,0,0,0,0,0,0\n"));
}

/* ------------------------------------------------------------ text helpers */

/* REQ-CSV-004 */
static void test_rfe_text_parse_double_accepts_decimal_forms(void **state)
{
    static const struct {
        const char *text;
        double value;
    } ok[] = {{"1", 1.0},       {"-1.5e-3", -1.5e-3}, {".5", 0.5},   {"5.", 5.0},
              {" 2 ", 2.0},     {"+3E2", 300.0},      {"1e-400", 0.0}, {"0001.25", 1.25}};
    size_t i;
    (void)state;
    for (i = 0u; i < sizeof ok / sizeof ok[0]; ++i) {
        double v = -99.0;
        assert_int_equal(rfe_text_parse_double(ok[i].text, &v), RFE_NUM_OK);
        assert_true(v == ok[i].value);
    }
}

/* REQ-CSV-004 */
static void test_rfe_text_parse_double_rejects_non_decimal(void **state)
{
    static const struct {
        const char *text;
        rfe_num_status_t why;
    } bad[] = {{"", RFE_NUM_EMPTY},        {"  ", RFE_NUM_EMPTY},      {"1e", RFE_NUM_SYNTAX},
               {"0x10", RFE_NUM_SYNTAX},   {"1.0x", RFE_NUM_SYNTAX},   {"nan", RFE_NUM_NONFINITE},
               {"-inf", RFE_NUM_NONFINITE}, {"NaN", RFE_NUM_NONFINITE}, {"1e999", RFE_NUM_OVERFLOW},
               {"1 2", RFE_NUM_SYNTAX},    {"++1", RFE_NUM_SYNTAX},    {".", RFE_NUM_SYNTAX},
               {"-", RFE_NUM_SYNTAX},      {"1e+", RFE_NUM_SYNTAX}};
    size_t i;
    (void)state;
    for (i = 0u; i < sizeof bad / sizeof bad[0]; ++i) {
        double v = -99.0;
        assert_int_equal(rfe_text_parse_double(bad[i].text, &v), bad[i].why);
        assert_true(v == -99.0); /* untouched on error */
    }
}

/* REQ-CSV-004 */
static void test_rfe_text_format_double_shortest_round_trip(void **state)
{
    char buf[RFE_NUM_BUF];
    (void)state;
    rfe_text_format_double(buf, 0.003);
    assert_string_equal(buf, "0.003");
    rfe_text_format_double(buf, 0.1 + 0.2);
    assert_string_equal(buf, "0.30000000000000004");
    rfe_text_format_double(buf, 1830.0);
    assert_string_equal(buf, "1830");
    rfe_text_format_double(buf, -1e-300);
    assert_true(strtod(buf, NULL) == -1e-300);
    rfe_text_format_double(buf, (double)NAN);
    assert_string_equal(buf, "nan");
}

/* REQ-CSV-002 */
static void test_rfe_io_error_print_one_line(void **state)
{
    rfe_io_error_t err;
    char *buf = NULL;
    size_t len = 0u;
    FILE *f = open_memstream(&buf, &len);
    (void)state;
    assert_non_null(f);
    rfe_io_error_set(&err, "a.csv", 4u, 3u, "column '%s': bad", "vx");
    rfe_io_error_print(f, "mu_replay", &err);
    rfe_io_error_set(&err, "b.csv", 7u, 0u, "no col");
    rfe_io_error_print(f, "mu_replay", &err);
    rfe_io_error_set(&err, "new\nline.csv", 0u, 5u, "whole file\tmsg");
    rfe_io_error_print(f, "mu_replay", &err);
    fclose(f);
    assert_string_equal(buf, "mu_replay: a.csv:4:3: column 'vx': bad\n"
                             "mu_replay: b.csv:7: no col\n"
                             "mu_replay: new?line.csv: whole file?msg\n");
    free(buf);
}

/* REQ-CSV-002 */
static void test_rfe_text_quote_marks_cut(void **state)
{
    char q[8];
    (void)state;
    rfe_text_quote(q, sizeof q, "abcdefgh", 4u);
    assert_string_equal(q, "abcd...");
    rfe_text_quote(q, sizeof q, "a\tb", 4u);
    assert_string_equal(q, "a?b");
    /* max too big for the buffer: cut to fit, never overrun. */
    rfe_text_quote(q, sizeof q, "abcdefgh", 100u);
    assert_string_equal(q, "abcd...");
}

/* REQ-CSV-002 */
static void test_rfe_num_status_str_every_value(void **state)
{
    (void)state;
    assert_string_equal(rfe_num_status_str(RFE_NUM_OK), "ok");
    assert_string_equal(rfe_num_status_str(RFE_NUM_EMPTY), "empty field");
    assert_non_null(strstr(rfe_num_status_str(RFE_NUM_OVERFLOW), "range"));
    assert_string_equal(rfe_num_status_str((rfe_num_status_t)99), "invalid number");
}

/* REQ-MET-002 */
static void test_rfe_json_write_string_escapes(void **state)
{
    char *buf = NULL;
    size_t len = 0u;
    FILE *f = open_memstream(&buf, &len);
    (void)state;
    assert_non_null(f);
    rfe_json_write_string(f, "a\"b\\c\nd");
    fputc(' ', f);
    rfe_json_write_number(f, 0.25);
    fputc(' ', f);
    rfe_json_write_number(f, (double)INFINITY);
    fclose(f);
    assert_string_equal(buf, "\"a\\\"b\\\\c\\u000ad\" 0.25 null");
    free(buf);
}

/* REQ-CSV-001 */
static void test_rfe_xrealloc_zero_size_not_null(void **state)
{
    void *p;
    char *s;
    (void)state;
    p = rfe_xrealloc(NULL, 0u, 8u);
    assert_non_null(p);
    free(p);
    s = rfe_xstrdup("abc");
    assert_string_equal(s, "abc");
    free(s);
}

/* ---------------------------------------------------------------- from columns in memory */

#define MEM_MAX_COLS 64u
#define MEM_MAX_ROWS 64u
#define MEM_MAX_META 32u
#define MEM_LINE 4096u

/** A small CSV parsed by this test on its own (strtok, strchr, strtod; no unit conversion): the
 *  raw columns and metadata pairs rfe_sensor_log_from_columns takes. */
typedef struct {
    char meta_text[MEM_MAX_META][2][256];
    rfe_kv_t meta[MEM_MAX_META];
    size_t n_meta;
    char names[MEM_MAX_COLS][64];
    double values[MEM_MAX_COLS][MEM_MAX_ROWS];
    rfe_column_t cols[MEM_MAX_COLS];
    size_t n_cols;
    size_t n_rows;
} mem_log_t;

static char *trim(char *s)
{
    char *e;
    while ((*s == ' ') || (*s == '\t')) {
        ++s;
    }
    e = s + strlen(s);
    while ((e > s) && ((e[-1] == ' ') || (e[-1] == '\n') || (e[-1] == '\r') || (e[-1] == '\t'))) {
        *--e = '\0';
    }
    return s;
}

static void mem_log_load(const char *path, mem_log_t *m)
{
    char line[MEM_LINE];
    FILE *f = fopen(path, "r");
    int header = 0;
    assert_non_null(f);
    memset(m, 0, sizeof *m);
    while (fgets(line, sizeof line, f) != NULL) {
        if (trim(line)[0] == '\0') {
            continue; /* a blank line */
        }
        if (line[0] == '#') {
            char *eq = strchr(line, '=');
            if (eq == NULL) {
                continue; /* a comment */
            }
            *eq = '\0';
            (void)snprintf(m->meta_text[m->n_meta][0], 256, "%s", trim(line + 1));
            (void)snprintf(m->meta_text[m->n_meta][1], 256, "%s", trim(eq + 1));
            m->meta[m->n_meta].key = m->meta_text[m->n_meta][0];
            m->meta[m->n_meta].value = m->meta_text[m->n_meta][1];
            ++m->n_meta;
        } else if (!header) {
            char *tok = strtok(line, ",");
            for (; tok != NULL; tok = strtok(NULL, ",")) {
                (void)snprintf(m->names[m->n_cols], 64, "%s", trim(tok));
                ++m->n_cols;
            }
            header = 1;
        } else {
            char *p = line;
            size_t j = 0u;
            for (;;) { /* fields may be empty (strtok would skip them) */
                char *comma = strchr(p, ',');
                m->values[j++][m->n_rows] = strtod(p, NULL);
                if (comma == NULL) {
                    break;
                }
                p = comma + 1;
            }
            assert_int_equal(j, m->n_cols);
            ++m->n_rows;
        }
    }
    (void)fclose(f);
    for (size_t j = 0u; j < m->n_cols; ++j) {
        m->cols[j].name = m->names[j];
        m->cols[j].values = m->values[j];
    }
}

/* Every value of two logs' rows the same, bit for bit, and the same columns. */
static void assert_same_log(const rfe_sensor_log_t *a, const rfe_sensor_log_t *b)
{
    assert_int_equal(a->n_rows, b->n_rows);
    assert_int_equal(a->omega_linear, b->omega_linear);
    assert_int_equal(a->has_swa, b->has_swa);
    assert_int_equal(a->has_velocity, b->has_velocity);
    assert_int_equal(a->has_truth, b->has_truth);
    assert_int_equal(a->bad_rows, b->bad_rows);
    for (size_t i = 0u; i < a->n_rows; ++i) {
        assert_memory_equal(&a->rows[i], &b->rows[i], offsetof(rfe_sensor_row_t, bad));
        assert_int_equal(a->rows[i].bad, b->rows[i].bad);
    }
}

/* The columns of a car logger's file (units, scales, names in the metadata) give the log the
 * reader makes of the file: the same rules, the same SI values. REQ-CLI-003 */
static void test_rfe_sensor_log_from_columns_equals_file(void **state)
{
    static mem_log_t m;
    rfe_sensor_log_t a;
    rfe_sensor_log_t b;
    rfe_io_error_t err;
    rfe_read_opts_t ro;
    (void)state;
    memset(&ro, 0, sizeof ro);
    ro.cells = RFE_CELLS_KEEP;
    ro.inputs = RFE_INPUTS_AUTO;
    mem_log_load(DATA "car_format_small.csv", &m);
    assert_int_equal(rfe_sensor_log_read_opts(DATA "car_format_small.csv", &ro, &a, &err), 0);
    assert_int_equal(rfe_sensor_log_from_columns("mem", m.meta, m.n_meta, m.cols, m.n_cols,
                                                 m.n_rows, &ro, &b, &err), 0);
    assert_int_equal(a.omega_linear, 1); /* the units were applied: km/h wheel speeds */
    assert_same_log(&a, &b);
    assert_string_equal(rfe_sensor_log_meta(&b, "obs_steer_ratio"), "16");
    rfe_sensor_log_free(&a);
    rfe_sensor_log_free(&b);
    mem_log_load(DATA "good_small.csv", &m);
    assert_int_equal(rfe_sensor_log_read_opts(DATA "good_small.csv", &ro, &a, &err), 0);
    assert_int_equal(rfe_sensor_log_from_columns("mem", m.meta, m.n_meta, m.cols, m.n_cols,
                                                 m.n_rows, &ro, &b, &err), 0);
    assert_same_log(&a, &b);
    rfe_sensor_log_free(&a);
    rfe_sensor_log_free(&b);
}

/* A NaN value is a CSV's nan cell: kept and counted (row rejected later), or, strict, the
 * error RFE_ERR_NONFINITE at its row and column; a text column naming an input, no rows,
 * time not increasing, NULL arguments: -1. REQ-CLI-003 */
static void test_rfe_sensor_log_from_columns_errors(void **state)
{
    static mem_log_t m;
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    rfe_read_opts_t ro;
    size_t ax = 0u;
    (void)state;
    memset(&ro, 0, sizeof ro);
    mem_log_load(DATA "good_small.csv", &m);
    while (strcmp(m.names[ax], "ax") != 0) {
        ++ax;
    }
    m.values[ax][1] = (double)NAN;
    ro.cells = RFE_CELLS_KEEP;
    assert_int_equal(rfe_sensor_log_from_columns("mem", m.meta, m.n_meta, m.cols, m.n_cols,
                                                 m.n_rows, &ro, &log, &err), 0);
    assert_int_equal(log.bad_rows, 1);
    assert_int_equal(log.bad_cells[RFE_CELL_NONFINITE], 1);
    assert_true(isnan(log.rows[1].ax));
    rfe_sensor_log_free(&log);
    ro.cells = RFE_CELLS_STRICT;
    assert_int_equal(rfe_sensor_log_from_columns("mem", m.meta, m.n_meta, m.cols, m.n_cols,
                                                 m.n_rows, &ro, &log, &err), RFE_ERR_NONFINITE);
    assert_int_equal(err.line, 2); /* the row, 1-based */
    assert_int_equal(err.col, ax + 1u);
    assert_int_equal(log.n_rows, 0);
    m.values[ax][1] = 0.0;
    m.cols[ax].values = NULL; /* a column of text */
    assert_int_equal(rfe_sensor_log_from_columns("mem", m.meta, m.n_meta, m.cols, m.n_cols,
                                                 m.n_rows, &ro, &log, &err), -1);
    assert_non_null(strstr(err.msg, "column 'ax'"));
    m.cols[ax].values = m.values[ax];
    assert_int_equal(rfe_sensor_log_from_columns("mem", m.meta, m.n_meta, m.cols, m.n_cols, 0u,
                                                 &ro, &log, &err), -1);
    assert_non_null(strstr(err.msg, "no data rows"));
    assert_string_equal(m.names[1], "t"); /* good_small.csv: ay, t, ... */
    m.values[1][1] = m.values[1][0];      /* time not increasing at row 2 */
    assert_int_equal(rfe_sensor_log_from_columns("mem", m.meta, m.n_meta, m.cols, m.n_cols,
                                                 m.n_rows, &ro, &log, &err), -1);
    assert_non_null(strstr(err.msg, "time not increasing"));
    assert_int_equal(rfe_sensor_log_from_columns(NULL, m.meta, m.n_meta, m.cols, m.n_cols,
                                                 m.n_rows, &ro, &log, &err), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_sensor_log_read_shuffled_columns_with_extra),
        cmocka_unit_test(test_rfe_sensor_log_read_metadata_collected),
        cmocka_unit_test(test_rfe_sensor_log_read_without_truth),
        cmocka_unit_test(test_rfe_sensor_log_read_crlf_bom_and_trailing_blank_lines),
        cmocka_unit_test(test_rfe_sensor_log_read_very_long_number_not_truncated),
        cmocka_unit_test(test_rfe_sensor_log_read_missing_column),
        cmocka_unit_test(test_rfe_sensor_log_read_missing_required_column),
        cmocka_unit_test(test_rfe_sensor_log_read_every_missing_column),
        cmocka_unit_test(test_rfe_sensor_log_read_production_car_log),
        cmocka_unit_test(test_rfe_sensor_log_read_bad_number_position),
        cmocka_unit_test(test_rfe_sensor_log_read_wrong_column_count),
        cmocka_unit_test(test_rfe_sensor_log_read_too_many_fields),
        cmocka_unit_test(test_rfe_sensor_log_read_empty_file),
        cmocka_unit_test(test_rfe_sensor_log_read_only_metadata_no_header),
        cmocka_unit_test(test_rfe_sensor_log_read_nan_text_rejected),
        cmocka_unit_test(test_rfe_sensor_log_read_inf_text_rejected),
        cmocka_unit_test(test_rfe_sensor_log_read_empty_field_rejected),
        cmocka_unit_test(test_rfe_sensor_log_read_overflow_rejected),
        cmocka_unit_test(test_rfe_sensor_log_read_cells_keep_bad_inputs),
        cmocka_unit_test(test_rfe_sensor_log_read_cells_unused_columns),
        cmocka_unit_test(test_rfe_sensor_log_read_cells_keep_still_rejects),
        cmocka_unit_test(test_rfe_sensor_log_read_partial_truth),
        cmocka_unit_test(test_rfe_sensor_log_read_util_columns_parsed),
        cmocka_unit_test(test_rfe_sensor_log_read_no_util_columns),
        cmocka_unit_test(test_rfe_sensor_log_read_util_without_mu),
        cmocka_unit_test(test_rfe_sensor_log_read_partial_util),
        cmocka_unit_test(test_rfe_sensor_log_read_bad_util_value),
        cmocka_unit_test(test_rfe_sensor_log_read_time_not_increasing),
        cmocka_unit_test(test_rfe_sensor_log_read_header_only),
        cmocka_unit_test(test_rfe_sensor_log_read_duplicate_column),
        cmocka_unit_test(test_rfe_sensor_log_read_empty_column_name),
        cmocka_unit_test(test_rfe_sensor_log_read_blank_line_between_rows),
        cmocka_unit_test(test_rfe_sensor_log_read_comment_after_header),
        cmocka_unit_test(test_rfe_sensor_log_read_nul_byte),
        cmocka_unit_test(test_rfe_sensor_log_read_nonexistent_file),
        cmocka_unit_test(test_rfe_sensor_log_read_long_bad_field_quoted_short),
        cmocka_unit_test(test_rfe_sensor_log_read_directory_is_read_error),
        cmocka_unit_test(test_rfe_sensor_log_read_metadata_without_key_ignored),
        cmocka_unit_test(test_rfe_sensor_log_read_many_rows_grow),
        cmocka_unit_test(test_rfe_estimate_log_write_full_disk),
        cmocka_unit_test(test_rfe_estimate_log_write_round_trips_doubles),
        cmocka_unit_test(test_rfe_estimate_log_write_float_format_round_trips_floats),
        cmocka_unit_test(test_rfe_estimate_log_write_unwritable_path),
        cmocka_unit_test(test_rfe_estimate_log_write_file_then_read_text),
        cmocka_unit_test(test_rfe_text_parse_double_accepts_decimal_forms),
        cmocka_unit_test(test_rfe_text_parse_double_rejects_non_decimal),
        cmocka_unit_test(test_rfe_text_format_double_shortest_round_trip),
        cmocka_unit_test(test_rfe_io_error_print_one_line),
        cmocka_unit_test(test_rfe_text_quote_marks_cut),
        cmocka_unit_test(test_rfe_num_status_str_every_value),
        cmocka_unit_test(test_rfe_json_write_string_escapes),
        cmocka_unit_test(test_rfe_xrealloc_zero_size_not_null),
        cmocka_unit_test(test_rfe_sensor_log_from_columns_equals_file),
        cmocka_unit_test(test_rfe_sensor_log_from_columns_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
