/**
 * @file test_trust_rules_q31.c
 * @brief Issue 17's two trust rules in the fixed-point estimator (docs/ESTIMATOR.md steps 0b
 *        and 9, docs/MONITOR.md §9): test_trust_rules_flt.c's checks on the Q31 twin.
 *
 * The samples and parameters are those of mu_replay --real q31 (rfe_replay_sample_q31,
 * rfe_replay_params_q31). The stale rule is recomputed in double from the Q22 speeds (exact:
 * every Q22 value and difference below 2^31 LSB is a double), so every row is compared. The
 * yaw-rate check is recomputed in double from the Q27 yaw rates and Q24 yaw accelerations; the
 * library rounds its prediction to Q27 once (half an LSB, 3.7e-9 rad/s), and a replaced value
 * predicts the next, so the accepted values are compared to 2 LSB (1.5e-8 rad/s): the spikes
 * are isolated, so no chain of replacements adds more. The estimator on the spiky log must
 * equal the estimator without the check on the log with the library's replacements, bit for
 * bit; the clean logs are unchanged bit for bit; synthetic samples take each condition both
 * ways.
 */
#include "test_common.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_q31.h"
#include "replay_real.h"
#include "rfe/friction_q31.h"

#define SCEN "scenarios"
#define FREEZE_PATH SCEN "/faults/freeze_omega_fl.hard_brake_low_mu.mf.csv"
#define SPIKE_PATH SCEN "/faults/spike_yaw_rate.sine_steer_low_mu.mf.csv"
#define CLEAN_BRAKE SCEN "/hard_brake_low_mu.mf.csv"
#define CLEAN_SINE SCEN "/sine_steer_low_mu.mf.csv"
#define N_SPIKES 8 /* the fault log's single-sample yaw-rate spikes (MONITOR.md §8) */
#define YAW_TOL (2.0 / 134217728.0) /* 2 LSB of Q27 (above) */
#define Q22(x) ((rfe_fix_t)((x) * 4194304.0))
#define Q27(x) ((rfe_fix_t)((x) * 134217728.0))
#define Q24(x) ((rfe_fix_t)((x) * 16777216.0))
#define Q29(x) ((rfe_fix_t)((x) * 536870912.0))
#define Q30(x) ((rfe_fix_t)((x) * 1073741824.0))

typedef struct {
    rfe_estimate_q31_t *e;
    uint8_t *stale;
    rfe_fix_t *yaw;
    size_t n;
} run_t;

static void load(const char *path, rfe_sensor_log_t *log, rfe_params_q31_t *p)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(log, 0, sizeof *log);
    if (rfe_sensor_log_read(path, log, &err) != 0) {
        fail_msg("%s:%zu:%zu: %s", err.file, err.line, err.col, err.msg);
    }
    assert_int_equal(rfe_param_set_preset_f64(&ps, RFE_PRESET_DEFAULT), 0);
    if (rfe_param_set_apply_meta(&ps, log, path, &err) != 0) {
        fail_msg("%s: %s", path, err.msg);
    }
    assert_int_equal(rfe_replay_params_q31(&ps, p, NULL), RFE_OK);
}

static void run(const rfe_sensor_log_t *log, const rfe_params_q31_t *p, run_t *r)
{
    static rfe_friction_q31_t est;
    size_t i;
    r->n = log->n_rows;
    r->e = calloc(r->n, sizeof *r->e);
    r->stale = calloc(r->n, 1);
    r->yaw = calloc(r->n, sizeof *r->yaw);
    assert_non_null(r->e);
    assert_non_null(r->stale);
    assert_non_null(r->yaw);
    assert_int_equal(rfe_friction_init_q31(&est, p), RFE_OK);
    for (i = 0; i < r->n; ++i) {
        rfe_sample_q31_t s;
        assert_int_equal(rfe_replay_sample_q31(&log->rows[i], &s), 0u);
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &r->e[i])));
        r->stale[i] = est.hold.stale;
        r->yaw[i] = est.hold.yaw_rate;
    }
}

static void run_free(run_t *r)
{
    free(r->e);
    free(r->stale);
    free(r->yaw);
}

static double median3(double a, double b, double c)
{
    double v[3] = {a, b, c};
    size_t i, j;
    for (i = 0; i < 3; ++i) {
        for (j = i + 1; j < 3; ++j) {
            if (v[j] < v[i]) {
                const double t = v[i];
                v[i] = v[j];
                v[j] = t;
            }
        }
    }
    return v[1];
}

/* REQ: as test_trust_rules_flt.c's, in fixed point: a frozen wheel speed clears every flag
 * exactly where the stale rule says so; mu and sd bit for bit those without the rule. */
/* REQ-EST-020 REQ-EST-021 REQ-FXP-010 */
static void test_q31_stale_wheel_clears_every_flag(void **state)
{
    rfe_sensor_log_t log;
    rfe_params_q31_t on, off;
    run_t a, b;
    double prev[4] = {0.0, 0.0, 0.0, 0.0}, ref[4] = {0.0, 0.0, 0.0, 0.0};
    const double lsb = 1.0 / 4194304.0;
    size_t i, w, n_stale = 0, n_cleared = 0;
    (void)state;
    load(FREEZE_PATH, &log, &on);
    assert_int_equal(on.filter.stale_omega, Q22(0.25));
    off = on;
    off.filter.stale_omega = 0;
    run(&log, &on, &a);
    run(&log, &off, &b);
    for (i = 0; i < log.n_rows; ++i) {
        rfe_sample_q31_t s;
        uint8_t want = 0;
        assert_int_equal(rfe_replay_sample_q31(&log.rows[i], &s), 0u);
        for (w = 0; w < 4; ++w) {
            const double om = (double)s.omega[w] * lsb;
            const double others = median3((double)s.omega[(w + 1) % 4] * lsb,
                                          (double)s.omega[(w + 2) % 4] * lsb,
                                          (double)s.omega[(w + 3) % 4] * lsb);
            if (om != prev[w] || om == 0.0) {
                ref[w] = others;
            } else {
                want |= (uint8_t)(fabs(others - ref[w]) > 0.25);
            }
            prev[w] = om;
        }
        assert_memory_equal(a.e[i].mu, b.e[i].mu, sizeof a.e[i].mu);
        assert_memory_equal(a.e[i].sd, b.e[i].sd, sizeof a.e[i].sd);
        assert_int_equal(a.stale[i], want);
        assert_int_equal(b.stale[i], 0);
        if (a.e[i].status == RFE_MODEL_MISMATCH) {
            assert_int_equal(b.e[i].status, RFE_MODEL_MISMATCH);
        }
        for (w = 0; w < 4; ++w) {
            assert_int_equal(a.e[i].valid[w], want ? 0 : b.e[i].valid[w]);
            n_cleared += (size_t)(want && b.e[i].valid[w]);
        }
        n_stale += want;
    }
    printf("  q31: %zu rows stale, %zu valid flags cleared\n", n_stale, n_cleared);
    assert_true(n_stale > 0);
    assert_true(n_cleared > 0);
    run_free(&a);
    run_free(&b);
    rfe_sensor_log_free(&log);
}

static void clean_unchanged(const char *path)
{
    rfe_sensor_log_t log;
    rfe_params_q31_t on, off;
    run_t a, b;
    size_t i;
    load(path, &log, &on);
    off = on;
    off.filter.stale_omega = 0;
    off.filter.yaw_check = 0;
    run(&log, &on, &a);
    run(&log, &off, &b);
    for (i = 0; i < log.n_rows; ++i) {
        rfe_sample_q31_t s;
        assert_int_equal(rfe_replay_sample_q31(&log.rows[i], &s), 0u);
        assert_memory_equal(&a.e[i], &b.e[i], sizeof a.e[i]);
        assert_int_equal(a.stale[i], 0);
        assert_int_equal(a.yaw[i], s.yaw_rate);
    }
    run_free(&a);
    run_free(&b);
    rfe_sensor_log_free(&log);
}

/* REQ: on clean logs the two rules change nothing in fixed point, bit for bit. */
/* REQ-EST-020 REQ-EST-021 REQ-FXP-010 */
static void test_q31_clean_logs_unchanged(void **state)
{
    (void)state;
    clean_unchanged(CLEAN_BRAKE);
    clean_unchanged(CLEAN_SINE);
}

/* REQ: the fixed-point yaw-rate check replaces the spikes, and only them, by the prediction; the
 * estimate equals the one without the check on the log with those samples replaced. */
/* REQ-EST-020 REQ-EST-021 REQ-FXP-010 */
static void test_q31_yaw_check_replaces_the_spikes(void **state)
{
    rfe_sensor_log_t log, fixed;
    rfe_params_q31_t on, off;
    run_t a, b;
    double prev = 0.0, prev_acc = 0.0;
    int checked = 0; /* the check restarts after a replaced sample */
    size_t i, n_rep = 0;
    (void)state;
    load(SPIKE_PATH, &log, &on);
    assert_int_equal(on.filter.yaw_check, 13421773); /* 0.1 rad/s, Q27 */
    assert_int_equal(on.filter.dt, 10737418);        /* 0.01 s, Q30 */
    run(&log, &on, &a);
    load(SPIKE_PATH, &fixed, &off);
    off.filter.yaw_check = 0;
    for (i = 0; i < log.n_rows; ++i) {
        rfe_sample_q31_t s;
        double r;
        const double got = (double)a.yaw[i] / 134217728.0;
        assert_int_equal(rfe_replay_sample_q31(&log.rows[i], &s), 0u);
        r = (double)s.yaw_rate / 134217728.0;
        if (checked) {
            const double acc = ((double)s.yaw_acc + prev_acc) / 16777216.0;
            const double pred = prev + (10737418.0 / 1073741824.0) * 0.5 * acc;
            if (fabs(r - pred) > 0.1) {
                r = pred;
                checked = 0;
                ++n_rep;
                assert_true(a.yaw[i] != s.yaw_rate);
                /* the library's value, as a row the replay rounds back to it exactly */
                fixed.rows[i].yaw_rate = got;
            } else {
                assert_int_equal(a.yaw[i], s.yaw_rate);
            }
        } else {
            assert_int_equal(a.yaw[i], s.yaw_rate); /* the first, or after a replacement */
            checked = 1;
        }
        assert_close(got, r, YAW_TOL, 0.0, "accepted yaw rate");
        prev = r;
        prev_acc = (double)s.yaw_acc;
    }
    printf("  q31: %zu yaw-rate samples replaced\n", n_rep);
    assert_int_equal(n_rep, N_SPIKES);
    run(&fixed, &off, &b);
    for (i = 0; i < log.n_rows; ++i) {
        assert_memory_equal(&a.e[i], &b.e[i], sizeof a.e[i]);
    }
    run_free(&a);
    run_free(&b);
    rfe_sensor_log_free(&log);
    rfe_sensor_log_free(&fixed);
}

/* A steady synthetic sample: 20 m/s straight, every wheel at w (Q22). */
static rfe_sample_q31_t cruise_q31(rfe_fix_t w)
{
    rfe_sample_q31_t s;
    size_t i;
    memset(&s, 0, sizeof s);
    s.vx = (rfe_fix_t)(20 * 8388608); /* Q23 */
    for (i = 0; i < 4; ++i) {
        s.omega[i] = w;
    }
    return s;
}

/* REQ: the stale rule's conditions in fixed point (test_trust_rules_flt.c's). */
/* REQ-EST-020 REQ-EST-021 REQ-FXP-010 */
static void test_q31_stale_wheel_conditions(void **state)
{
    static rfe_friction_q31_t est;
    rfe_params_q31_t p;
    rfe_estimate_q31_t e;
    rfe_sample_q31_t s;
    int k;
    (void)state;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    assert_int_equal(p.filter.stale_omega, Q22(0.25));
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    for (k = 0; k < 20; ++k) {
        s = cruise_q31(Q22(60.0));
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
        assert_int_equal(est.hold.stale, 0);
    }
    for (k = 0; k <= 8; ++k) {
        s = cruise_q31(Q22(60.0) - k * Q22(0.0625));
        s.omega[RFE_FL] = Q22(60.0);
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
        assert_int_equal(est.hold.stale, (k >= 5) ? 1 : 0); /* 0.25 exactly is not more */
        if (k >= 5) {
            assert_int_equal(e.valid[0] | e.valid[1] | e.valid[2] | e.valid[3], 0);
        }
    }
    s = cruise_q31(Q22(59.0));
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.stale, 0);
    for (k = 0; k <= 8; ++k) {
        s = cruise_q31(Q22(58.0) - k * Q22(0.0625));
        s.omega[RFE_FL] = 0;
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
        assert_int_equal(est.hold.stale, 0);
    }
    p.filter.stale_omega = 0;
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    for (k = 0; k <= 8; ++k) {
        s = cruise_q31(Q22(60.0) - k * Q22(0.0625));
        s.omega[RFE_FL] = Q22(60.0);
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
        assert_int_equal(est.hold.stale, 0);
    }
}

/* REQ: the yaw-rate check's conditions in fixed point (test_trust_rules_flt.c's), and a
 * prediction beyond Q27's range saturated and counted. */
/* REQ-EST-020 REQ-EST-021 REQ-FXP-010 */
static void test_q31_yaw_check_conditions(void **state)
{
    static rfe_friction_q31_t est, before;
    rfe_params_q31_t p;
    rfe_estimate_q31_t e;
    rfe_sample_q31_t s = cruise_q31(Q22(61.5));
    (void)state;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    p.filter.yaw_check = Q27(0.125);
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    s.yaw_rate = Q27(0.5);
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, Q27(0.5));
    s.yaw_rate = Q27(0.625); /* exactly 0.125 away: kept */
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, Q27(0.625));
    s.yaw_rate = Q27(0.875); /* 0.25 away: the prediction */
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, Q27(0.625));
    assert_int_equal(est.hold.yaw_on, 0);
    s.yaw_rate = Q27(0.875); /* the departure persists: accepted, the check restarts */
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, Q27(0.875));
    /* trapezoid: dt (2 + 0) / 2 = dt rad/s: dt Q30 = 10737418 -> Q27 10737418 / 8 rounded */
    s.yaw_acc = (rfe_fix_t)(2 * 16777216);
    s.yaw_rate = Q27(1.5);
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, Q27(0.875) + 1342177);
    s.yaw_acc = 0;
    before = est;
    s.ax = (rfe_fix_t)(60 * 16777216); /* beyond RFE_LIMIT_ACC */
    assert_int_equal(rfe_friction_step_q31(&est, &s, &e), RFE_ERR_RANGE);
    assert_memory_equal(&est, &before, sizeof est);
    s.ax = 0;
    assert_int_equal(rfe_friction_skip_q31(&est, 5u), RFE_OK);
    s.yaw_rate = Q27(1.5);
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, Q27(1.5));
    s.yaw_rate = Q27(-1.0);
    assert_false(rfe_status_is_error(rfe_friction_step_after_q31(&est, 3u, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, Q27(-1.0));
    /* a prediction beyond +-16 rad/s (dt 1.5 s, yaw accelerations 100 rad/s^2): saturated */
    p.filter.yaw_check = Q27(0.125);
    p.filter.dt = (rfe_fix_t)(1.5 * 1073741824.0);
    p.filter.tau_v = 0; /* b_v = 1 (dt / (0 + dt)), valid at any dt */
    p.filter.b_v = (rfe_fix_t)1073741824;
    p.monitor.enable = 0u; /* its constants belong to dt 0.01 s */
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    s.yaw_acc = (rfe_fix_t)(100 * 16777216);
    s.yaw_rate = Q27(9.0);
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    s.yaw_rate = Q27(9.5);
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, RFE_FIX_MAX);
    assert_true(e.sat > 0u);
    /* off: a jump is accepted */
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    p.filter.yaw_check = 0;
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    s = cruise_q31(Q22(61.5));
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    s.yaw_rate = Q27(2.0);
    assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &s, &e)));
    assert_int_equal(est.hold.yaw_rate, Q27(2.0));
}

/* REQ: the fixed-point parameters: 0 in the paper preset, limits (0 to 500 rad/s Q22 and 10
 * rad/s Q27), an invalid one refused with RFE_ERR_PARAM, the estimator untouched. */
/* REQ-EST-020 REQ-EST-021 REQ-FXP-010 */
static void test_q31_trust_rule_params(void **state)
{
    static rfe_friction_q31_t est, before;
    rfe_params_q31_t p, q;
    (void)state;
    assert_int_equal(rfe_params_paper_q31(&p), RFE_OK);
    assert_int_equal(p.filter.stale_omega, 0);
    assert_int_equal(p.filter.yaw_check, 0);
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    q = p;
    q.filter.stale_omega = (rfe_fix_t)(500 * 4194304);
    q.filter.yaw_check = Q27(10.0);
    assert_int_equal(rfe_params_validate_q31(&q), RFE_OK);
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    before = est;
#define REJECT_(field, value)                                                                   \
    q = p;                                                                                      \
    q.filter.field = (value);                                                                   \
    assert_int_equal(rfe_params_validate_q31(&q), RFE_ERR_PARAM);                               \
    assert_int_equal(rfe_friction_init_q31(&est, &q), RFE_ERR_PARAM);                           \
    assert_memory_equal(&est, &before, sizeof est)
    REJECT_(stale_omega, -1);
    REJECT_(stale_omega, (rfe_fix_t)(500 * 4194304) + 1);
    REJECT_(yaw_check, -1);
    REJECT_(yaw_check, Q27(10.0) + 1);
#undef REJECT_
}

/* test_trust_rules_flt.c's hand example in Q formats (every value exact): mu_min 0.125 (Q29),
 * sd0 0.0625 (Q30) with no common part, so the sd is sd0 exactly; k = 3 (Q24) puts the margin
 * at 0.3125. */
static uint8_t margin_valid_q31(rfe_fix_t mu0, rfe_fix_t k, int wheel)
{
    static rfe_friction_q31_t est;
    rfe_params_q31_t p;
    rfe_estimate_q31_t e;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    p.filter.mu_min = Q29(0.125);
    p.filter.sd0 = Q30(0.0625);
    p.filter.sd0_common = 0;
    p.filter.mu0 = mu0;
    p.filter.valid_bound_k = k;
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    assert_int_equal(rfe_friction_get_q31(&est, &e), RFE_OK);
    assert_int_equal(e.sd[wheel], Q30(0.0625));
    assert_int_equal(e.mu[wheel], mu0);
    return e.valid[wheel];
}

/* REQ: the bound margin in fixed point: valid only at least valid_bound_k sd above mu_min, at
 * exactly k sd valid (the compare in Q54 is exact), k = 0 today's rule. */
/* REQ-EST-022 REQ-FXP-010 */
static void test_q31_bound_margin_hand_example(void **state)
{
    const rfe_fix_t below = Q29(0.3125) - 1; /* one LSB of Q29 below the margin */
    int w;
    (void)state;
    for (w = 0; w < 4; ++w) {
        assert_int_equal(margin_valid_q31(Q29(0.3125), Q24(3.0), w), 1);
        assert_int_equal(margin_valid_q31(below, Q24(3.0), w), 0);
        assert_int_equal(margin_valid_q31(Q29(0.1875), Q24(3.0), w), 0);
        assert_int_equal(margin_valid_q31(Q29(0.1875), Q24(1.0), w), 1);
        assert_int_equal(margin_valid_q31(below, 0, w), 1);
        assert_int_equal(margin_valid_q31(Q29(0.1875), 0, w), 1);
        assert_int_equal(margin_valid_q31(Q29(0.125), 0, w), 0); /* on the bound: never */
    }
}

/* REQ: as test_trust_rules_flt.c's on the noise-free low-mu hard brake, in fixed point: mu and
 * sd bit for bit as without the margin, the flags cleared exactly where mu - mu_min < 3 sd
 * (recomputed in double from the Q29 and Q30 integers: exact, so every row is compared). */
/* REQ-EST-022 REQ-FXP-010 */
static void test_q31_bound_margin_on_a_log(void **state)
{
    rfe_sensor_log_t log;
    rfe_params_q31_t p, off;
    run_t a, b;
    size_t i, w, cleared = 0;
    (void)state;
    load(SCEN "/hard_brake_low_mu.nf.csv", &log, &p);
    assert_int_equal(p.filter.valid_bound_k, Q24(3.0)); /* on in the default preset */
    off = p;
    off.filter.valid_bound_k = 0;
    run(&log, &p, &a);
    run(&log, &off, &b);
    for (i = 0; i < a.n; ++i) {
        assert_memory_equal(a.e[i].mu, b.e[i].mu, sizeof a.e[i].mu);
        assert_memory_equal(a.e[i].sd, b.e[i].sd, sizeof a.e[i].sd);
        for (w = 0; w < 4; ++w) {
            const double m = ((double)b.e[i].mu[w] - (double)p.filter.mu_min) / 536870912.0;
            const double k_sd = 3.0 * (double)b.e[i].sd[w] / 1073741824.0;
            assert_int_equal(a.e[i].valid[w], (b.e[i].valid[w] != 0u) && (m >= k_sd));
            cleared += (size_t)((b.e[i].valid[w] != 0u) && (a.e[i].valid[w] == 0u));
        }
    }
    assert_true(cleared > 0u); /* the rule acts on this log */
    run_free(&a);
    run_free(&b);
    rfe_sensor_log_free(&log);
}

/* REQ: valid_bound_k in fixed point: 3 sd (Q24) in the default preset, 0 in the paper preset,
 * [0, 10] sd; an invalid one refused with RFE_ERR_PARAM, the estimator untouched. */
/* REQ-EST-022 REQ-FXP-010 */
static void test_q31_bound_margin_params(void **state)
{
    static rfe_friction_q31_t est, before;
    rfe_params_q31_t p, q;
    (void)state;
    assert_int_equal(rfe_params_paper_q31(&p), RFE_OK);
    assert_int_equal(p.filter.valid_bound_k, 0);
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    assert_int_equal(p.filter.valid_bound_k, Q24(3.0));
    q = p;
    q.filter.valid_bound_k = Q24(10.0);
    assert_int_equal(rfe_params_validate_q31(&q), RFE_OK);
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    before = est;
#define REJECT_(value)                                                                          \
    q = p;                                                                                      \
    q.filter.valid_bound_k = (value);                                                           \
    assert_int_equal(rfe_params_validate_q31(&q), RFE_ERR_PARAM);                               \
    assert_int_equal(rfe_friction_init_q31(&est, &q), RFE_ERR_PARAM);                           \
    assert_memory_equal(&est, &before, sizeof est)
    REJECT_(-1);
    REJECT_(Q24(10.0) + 1);
#undef REJECT_
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_q31_stale_wheel_clears_every_flag),
        cmocka_unit_test(test_q31_clean_logs_unchanged),
        cmocka_unit_test(test_q31_yaw_check_replaces_the_spikes),
        cmocka_unit_test(test_q31_stale_wheel_conditions),
        cmocka_unit_test(test_q31_yaw_check_conditions),
        cmocka_unit_test(test_q31_trust_rule_params),
        cmocka_unit_test(test_q31_bound_margin_hand_example),
        cmocka_unit_test(test_q31_bound_margin_on_a_log),
        cmocka_unit_test(test_q31_bound_margin_params),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
