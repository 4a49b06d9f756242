/**
 * @file test_log_units.c
 * @brief Tests of a recorded car's log format: unit words and factors (log_units.c), the
 *        reader's unit_/scale_/offset_/column_ metadata, the steering-wheel angle and
 *        circumferential wheel speeds (csv_log.c), and the sample period (log_timing.c).
 *
 * Expected SI values are written from the unit definitions (1 km/h = 1/3.6 m/s, 1 deg =
 * pi/180 rad, 1 g = 9.80665 m/s^2, 1 bar = 0.1 MPa, 1 rpm = 2 pi/60 rad/s), not from the
 * code's table. Each converted value has two roundings (the factor, the product) and at
 * most two more (scale, offset): compared within 8 ulp relative (REL).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "csv_log.h"
#include "log_text.h"
#include "log_timing.h"
#include "rfe/friction.h"
#include "log_units.h"
#include "text_io.h"

#define PI 3.14159265358979323846
#define REL (8.0 * 2.220446049250313e-16)

static void assert_close(double got, double want)
{
    const double tol = REL * fmax(fabs(want), 1e-300);
    if (!(fabs(got - want) <= tol)) {
        fail_msg("got %.17g, want %.17g (tolerance %.3g)", got, want, tol);
    }
}

/* Reads @p text expecting an error at @p line whose message contains @p part. */
static void assert_read_error(const char *text, size_t line, const char *part)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    memset(&err, 0, sizeof err);
    assert_int_equal(read_log_text(text, &log, &err), -1);
    assert_int_equal(log.n_rows, 0);
    if (strstr(err.msg, part) == NULL) {
        fail_msg("message '%s' lacks '%s'", err.msg, part);
    }
    assert_int_equal(err.line, line);
}

/* A car's log: vendor names, ms, deg (steering wheel), deg/s, g with ay in the SAE sense,
 * km/h wheel speeds, bar, an offset on ax, and a column the library does not read. */
#define CAR_META                                                                          \
    "# column_t = Time\n# unit_t = ms\n"                                                  \
    "# column_swa = SWA\n# unit_swa = deg\n"                                              \
    "# column_yaw_rate = YawRate\n# unit_yaw_rate = deg/s\n"                              \
    "# unit_ax = g\n# offset_ax = -0.01\n"                                                \
    "# unit_ay = g\n# scale_ay = -1\n"                                                    \
    "# unit_omega_fl = km/h\n# unit_omega_fr = km/h\n# unit_omega_rl = km/h\n"            \
    "# unit_omega_rr = km/h\n"                                                            \
    "# unit_p_fl = bar\n# unit_p_fr = bar\n# unit_p_rl = bar\n# unit_p_rr = bar\n"
#define CAR_HDR "Time,SWA,YawRate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr,p_fl,p_fr,p_rl,p_rr,Rpm\n"
#define CAR_ROWS "1000,90,10,0.51,0.2,36,72,90,108,10,20,0,5,2000\n" \
                 "1020,-45,-5,0,-0.1,36,36,36,36,0,0,0,0,2000\n"

/* ------------------------------------------------------------ unit words */

/* REQ-CSV-005 */
static void test_rfe_unit_factor_definitions(void **state)
{
    double f = 0.0;
    int lin = -1;
    (void)state;
    assert_int_equal(rfe_unit_factor(RFE_DIM_SPEED, "km/h", &f, &lin), 0);
    assert_close(f * 3.6, 1.0);
    assert_int_equal(lin, 0);
    assert_int_equal(rfe_unit_factor(RFE_DIM_ANGLE, "deg", &f, &lin), 0);
    assert_close(f, PI / 180.0);
    assert_int_equal(rfe_unit_factor(RFE_DIM_RATE, "rpm", &f, &lin), 0);
    assert_close(f, 2.0 * PI / 60.0);
    assert_int_equal(rfe_unit_factor(RFE_DIM_ACC, "g", &f, &lin), 0);
    assert_close(f, 9.80665);
    assert_int_equal(rfe_unit_factor(RFE_DIM_PRESSURE, "bar", &f, &lin), 0);
    assert_close(f, 0.1);
    assert_int_equal(rfe_unit_factor(RFE_DIM_PRESSURE, "psi", &f, &lin), 0);
    assert_close(f, 0.45359237 * 9.80665 / (0.0254 * 0.0254) * 1e-6); /* lbf/in^2 in MPa */
    assert_int_equal(rfe_unit_factor(RFE_DIM_SPEED, "mph", &f, &lin), 0);
    assert_close(f, 1609.344 / 3600.0);
    assert_int_equal(rfe_unit_factor(RFE_DIM_TIME, "ms", &f, &lin), 0);
    assert_close(f, 1e-3);
    /* A wheel speed: spin units are rad/s, speed units are flagged circumferential. */
    assert_int_equal(rfe_unit_factor(RFE_DIM_WHEEL, "rpm", &f, &lin), 0);
    assert_int_equal(lin, 0);
    assert_int_equal(rfe_unit_factor(RFE_DIM_WHEEL, "km/h", &f, &lin), 0);
    assert_int_equal(lin, 1);
    assert_close(f * 3.6, 1.0);
    /* the mass and grade logs' brake pressure is in Pa (the p_* columns' unit is MPa) */
    assert_int_equal(rfe_unit_factor(RFE_DIM_PRESSURE_PA, "Pa", &f, &lin), 0);
    assert_close(f, 1.0);
    assert_int_equal(rfe_unit_factor(RFE_DIM_PRESSURE_PA, "bar", &f, &lin), 0);
    assert_close(f, 1e5);
    assert_int_equal(rfe_unit_factor(RFE_DIM_PRESSURE_PA, "psi", &f, &lin), 0);
    assert_close(f, 0.45359237 * 9.80665 / (0.0254 * 0.0254)); /* lbf/in^2 in Pa */
    assert_int_equal(rfe_unit_factor(RFE_DIM_MASS, "t", &f, &lin), 0);
    assert_close(f, 1e3);
    assert_int_equal(rfe_unit_factor(RFE_DIM_MASS, "lb", &f, &lin), -1);
    assert_string_equal(rfe_unit_words(RFE_DIM_PRESSURE_PA), "Pa, kPa, bar, MPa, psi");
    assert_string_equal(rfe_unit_words(RFE_DIM_MASS), "kg, t");
}

/* REQ-CSV-005 */
static void test_rfe_unit_factor_wrong_quantity_untouched(void **state)
{
    double f = 7.0;
    int lin = 7;
    (void)state;
    assert_int_equal(rfe_unit_factor(RFE_DIM_ANGLE, "km/h", &f, &lin), -1);
    assert_int_equal(rfe_unit_factor(RFE_DIM_ACC, "deg", &f, &lin), -1);
    assert_int_equal(rfe_unit_factor(RFE_DIM_WHEEL, "g", &f, &lin), -1);
    assert_int_equal(rfe_unit_factor(RFE_DIM_SPEED, "KM/H", &f, &lin), -1); /* case matters */
    assert_true(f == 7.0);
    assert_int_equal(lin, 7);
    assert_non_null(strstr(rfe_unit_words(RFE_DIM_RATE), "deg/s"));
    assert_string_equal(rfe_unit_words((rfe_dim_t)99), "?");
}

/* ------------------------------------------------------------ the reader */

/* REQ-CSV-005 */
static void test_rfe_sensor_log_read_car_units_to_si(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    const rfe_sensor_row_t *r;
    (void)state;
    assert_int_equal(read_log_text(CAR_META CAR_HDR CAR_ROWS, &log, &err), 0);
    assert_int_equal(log.n_rows, 2);
    assert_int_equal(log.has_swa, 1);
    assert_int_equal(log.has_pressure, 1);
    assert_int_equal(log.omega_linear, 1);
    r = &log.rows[0];
    assert_close(r->t, 1.0);
    assert_close(log.rows[1].t, 1.02);
    assert_close(r->swa, PI / 2.0);
    assert_true(r->delta == 0.0); /* not filled until the ratio is known */
    assert_close(r->yaw_rate, 10.0 * PI / 180.0);
    assert_close(r->ax, (0.51 - 0.01) * 9.80665); /* SI = factor * (scale * x + offset) */
    assert_close(r->ay, -0.2 * 9.80665);          /* SAE: positive to the right */
    assert_close(r->omega[RFE_FL], 10.0);         /* 36 km/h, still m/s */
    assert_close(r->omega[RFE_FR], 20.0);
    assert_close(r->omega[RFE_RL], 25.0);
    assert_close(r->omega[RFE_RR], 30.0);
    assert_close(r->p_brake[RFE_FL], 1.0);
    assert_close(r->p_brake[RFE_RR], 0.5);
    /* R = 0.25 m: 10 m/s is 40 rad/s; once. */
    assert_int_equal(rfe_sensor_log_wheel_radius(&log, 0.25), 0);
    assert_int_equal(log.omega_linear, 0);
    assert_close(r->omega[RFE_FL], 40.0);
    assert_int_equal(rfe_sensor_log_wheel_radius(&log, 0.25), 0);
    assert_close(r->omega[RFE_FL], 40.0);
    /* Ratio 15: the road-wheel angle, and the log now reads as one with delta. */
    assert_int_equal(rfe_sensor_log_steer_ratio(&log, 15.0), 0);
    assert_int_equal(log.has_swa, 0);
    assert_close(r->delta, PI / 2.0 / 15.0);
    assert_close(log.rows[1].delta, -PI / 4.0 / 15.0);
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-005 */
static void test_rfe_sensor_log_radius_and_ratio_rejected_untouched(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text(CAR_META CAR_HDR CAR_ROWS, &log, &err), 0);
    assert_int_equal(rfe_sensor_log_wheel_radius(&log, 0.0), -1);
    assert_int_equal(rfe_sensor_log_wheel_radius(&log, NAN), -1);
    assert_int_equal(rfe_sensor_log_steer_ratio(&log, -15.0), -1);
    assert_int_equal(rfe_sensor_log_steer_ratio(&log, INFINITY), -1);
    assert_int_equal(log.omega_linear, 1);
    assert_int_equal(log.has_swa, 1);
    assert_close(log.rows[0].omega[RFE_FL], 10.0);
    assert_true(log.rows[0].delta == 0.0);
    rfe_sensor_log_free(&log);
}

/* REQ-CSV-005 */
static void test_rfe_sensor_log_read_spin_units_need_no_radius(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    assert_int_equal(read_log_text("# unit_omega_fl = rpm\n# unit_omega_fr = rpm\n"
                               "# unit_omega_rl = rpm\n# unit_omega_rr = rpm\n"
                               "# unit_delta = deg\n# unit_yaw_acc = deg/s^2\n"
                               "# unit_vx = km/h\n# unit_vy = mph\n"
                               "t,delta,vx,vy,yaw_rate,yaw_acc,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
                               "0,2,72,1,0,30,0,0,600,600,600,600\n",
                               &log, &err), 0);
    assert_int_equal(log.omega_linear, 0);
    assert_int_equal(log.has_swa, 0);
    assert_close(log.rows[0].omega[RFE_RR], 600.0 * 2.0 * PI / 60.0);
    assert_close(log.rows[0].delta, 2.0 * PI / 180.0);
    assert_close(log.rows[0].yaw_acc, 30.0 * PI / 180.0);
    assert_close(log.rows[0].vx, 20.0);
    assert_close(log.rows[0].vy, 0.44704);
    rfe_sensor_log_free(&log);
}

#define SI_HDR "t,delta,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
#define SI_ROW "0,0,0,0,0,60,60,60,60\n"

/* REQ-CSV-005 */
static void test_rfe_sensor_log_read_column_meta_errors(void **state)
{
    (void)state;
    /* A typo in the column name would leave a column in the wrong unit: an error. */
    assert_read_error("# scenario = x\n# unit_yawrate = deg/s\n" SI_HDR SI_ROW, 2u,
                      "'yawrate' is not a sensor-log column");
    assert_read_error("# column_omega_f = WS\n" SI_HDR SI_ROW, 1u, "is not a sensor-log column");
    assert_read_error("# unit_delta = km/h\n" SI_HDR SI_ROW, 1u, "not a unit of column 'delta'");
    assert_read_error("# unit_ax = m/s/s\n" SI_HDR SI_ROW, 1u, "one of: m/s^2 (m/s2), g");
    assert_read_error("# scale_ay = 0\n" SI_HDR SI_ROW, 1u, "a scale of 0");
    assert_read_error("# x = 1\n# offset_ax = abc\n" SI_HDR SI_ROW, 2u, "metadata 'offset_ax'");
    assert_read_error("# scale_ax = nan\n" SI_HDR SI_ROW, 1u, "metadata 'scale_ax'");
    /* Spin and circumferential wheel units mixed. */
    assert_read_error("# unit_omega_fl = rpm\n# unit_omega_fr = km/h\n" SI_HDR SI_ROW, 3u,
                      "mix spin");
    /* The alias names a column the header does not have. */
    assert_read_error("# column_yaw_rate = Gier\n" SI_HDR SI_ROW, 2u,
                      "missing column 'yaw_rate' (named 'Gier' by its column_yaw_rate");
    /* Two library columns claim one header column. */
    assert_read_error("# column_ax = ay\n" SI_HDR SI_ROW, 2u, "named for both");
    /* A scale can push a finite text out of the doubles. */
    assert_read_error("# scale_ax = 1e300\n" SI_HDR "0,0,0,1e300,0,60,60,60,60\n", 3u,
                      "out of range in SI units");
}

/* REQ-CSV-005 */
static void test_rfe_sensor_log_read_steering_angle_one_of_two(void **state)
{
    (void)state;
    assert_read_error("t,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n0,0,0,0,1,1,1,1\n",
                      1u, "missing column 'delta' (the road-wheel angle) or 'swa'");
    assert_read_error("t,delta,swa,yaw_rate,ax,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
                      "0,0,0,0,0,0,1,1,1,1\n",
                      1u, "both 'delta' and 'swa'");
}

/* REQ-CSV-005 */
static void test_rfe_sensor_log_read_alias_wins_over_own_name(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    (void)state;
    /* column_ax = Ax2: the header's own "ax" is then just an extra column. */
    assert_int_equal(read_log_text("# column_ax = Ax2\n"
                               "t,delta,yaw_rate,ax,Ax2,ay,omega_fl,omega_fr,omega_rl,omega_rr\n"
                               "0,0,0,5,-1.5,0,60,60,60,60\n",
                               &log, &err), 0);
    assert_true(log.rows[0].ax == -1.5);
    rfe_sensor_log_free(&log);
}

/* ------------------------------------------------------------ the sample period */

/* REQ-CSV-006 */
static void test_rfe_log_period_median_of_jittered_stamps(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    rfe_log_period_t per;
    (void)state;
    /* Periods 0.018, 0.022, 0.020, 0.021, 0.150 (a gap): sorted, the lower median of five
     * is the third, 0.021. */
    assert_int_equal(read_log_text(SI_HDR "0,0,0,0,0,1,1,1,1\n0.018,0,0,0,0,1,1,1,1\n"
                                      "0.040,0,0,0,0,1,1,1,1\n0.060,0,0,0,0,1,1,1,1\n"
                                      "0.081,0,0,0,0,1,1,1,1\n0.231,0,0,0,0,1,1,1,1\n",
                               &log, &err), 0);
    assert_int_equal(rfe_log_period(&log, &per), 0);
    assert_int_equal(per.n, 5);
    assert_true(fabs(per.median - 0.021) < 1e-15); /* a difference of two stamps */
    assert_true(fabs(per.min - 0.018) < 1e-15);
    assert_true(fabs(per.max - 0.150) < 1e-15);
    assert_int_equal(rfe_log_gaps(&log, 0.1), 1);
    assert_int_equal(rfe_log_gaps(&log, 0.2), 0);
    rfe_sensor_log_free(&log);
}

/* REQ: the periods a gap misses (rfe_log_missed): none up to 2 dt (jitter; widened by 2^-20
 * relative for the stamps' own rounding, so one dropped sample is not a gap), else
 * round(period / dt) - 1, capped at UINT32_MAX; none for a dt <= 0 or a NaN period. */
/* REQ-CSV-006 REQ-EST-015 */
static void test_rfe_log_missed_periods(void **state)
{
    (void)state;
    assert_int_equal(rfe_log_missed(0.0199, 0.01), 0u);
    assert_int_equal(rfe_log_missed(0.02, 0.01), 0u);    /* 2 periods: still jitter */
    assert_int_equal(rfe_log_missed(0.13 - 0.11, 0.01), 0u); /* 2 periods in decimal stamps */
    assert_int_equal(rfe_log_missed(0.0200001, 0.01), 1u); /* beyond the stamps' rounding */
    assert_int_equal(rfe_log_missed(0.0305, 0.01), 2u);  /* 3.05 periods: 2 missing */
    assert_int_equal(rfe_log_missed(0.0349, 0.01), 2u);
    assert_int_equal(rfe_log_missed(0.0351, 0.01), 3u);
    assert_int_equal(rfe_log_missed(0.31, 0.01), 30u);
    assert_int_equal(rfe_log_missed(1e12, 0.01), UINT32_MAX);
    assert_int_equal(rfe_log_missed(0.5, 0.0), 0u);
    assert_int_equal(rfe_log_missed(0.5, -0.01), 0u);
    assert_int_equal(rfe_log_missed(NAN, 0.01), 0u);
}

/* REQ-CSV-006 */
static void test_rfe_log_period_one_row_has_none(void **state)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    rfe_log_period_t per = {7.0, 7.0, 7.0, 7u};
    (void)state;
    assert_int_equal(read_log_text(SI_HDR SI_ROW, &log, &err), 0);
    assert_int_equal(rfe_log_period(&log, &per), -1);
    assert_true(per.median == 7.0);
    assert_int_equal(per.n, 7);
    assert_int_equal(rfe_log_gaps(&log, 0.0), 0);
    rfe_sensor_log_free(&log);
}

/* REQ: mu_replay's gap rule (rfe_log_missed, double) and the library's (rfe_friction_missed,
 * the double build, which the pipeline uses behind the observer) are one rule: equal counts
 * on a sweep of periods from 0 to 2 s in steps of 1/7 ms, at dt = 0.01 s and 0.02 s, and at
 * the edges (2 dt, just beyond the stamps' rounding, half periods). */
/* REQ-EST-015 REQ-OBS-023 */
static void test_rfe_log_missed_is_the_library_rule(void **state)
{
    static rfe_friction_t est;
    rfe_params_t p;
    const double dts[2] = {0.01, 0.02};
    size_t d;
    int k;
    (void)state;
    for (d = 0u; d < 2u; ++d) {
        const double dt = dts[d];
        const double edges[] = {2.0 * dt, 2.0 * dt * (1.0 + 2e-6), 2.5 * dt, 3.5 * dt, 1e12};
        uint32_t lib = 0u;
        size_t e;
        memset(&p, 0, sizeof p);
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        p.filter.dt = dt;
        assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
        for (k = 0; k < 14000; ++k) {
            const double period = (double)k / 7000.0;
            assert_int_equal(rfe_friction_missed(&est, period, &lib), RFE_OK);
            if (lib != rfe_log_missed(period, dt)) {
                fail_msg("dt %g, period %.9g: library %u, host %u", dt, period, (unsigned)lib,
                         (unsigned)rfe_log_missed(period, dt));
            }
        }
        for (e = 0u; e < sizeof edges / sizeof edges[0]; ++e) {
            assert_int_equal(rfe_friction_missed(&est, edges[e], &lib), RFE_OK);
            assert_int_equal(lib, rfe_log_missed(edges[e], dt));
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_unit_factor_definitions),
        cmocka_unit_test(test_rfe_unit_factor_wrong_quantity_untouched),
        cmocka_unit_test(test_rfe_sensor_log_read_car_units_to_si),
        cmocka_unit_test(test_rfe_sensor_log_radius_and_ratio_rejected_untouched),
        cmocka_unit_test(test_rfe_sensor_log_read_spin_units_need_no_radius),
        cmocka_unit_test(test_rfe_sensor_log_read_column_meta_errors),
        cmocka_unit_test(test_rfe_sensor_log_read_steering_angle_one_of_two),
        cmocka_unit_test(test_rfe_sensor_log_read_alias_wins_over_own_name),
        cmocka_unit_test(test_rfe_log_period_median_of_jittered_stamps),
        cmocka_unit_test(test_rfe_log_period_one_row_has_none),
        cmocka_unit_test(test_rfe_log_missed_periods),
        cmocka_unit_test(test_rfe_log_missed_is_the_library_rule),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
