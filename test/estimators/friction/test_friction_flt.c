/**
 * @file test_friction_flt.c
 * @brief The friction estimator (MODEL.md §5-6): single SCKF steps against the independent
 *        vectors, input validation, untouched state on error, low speed, projection.
 *
 * Tolerances. Double: the step vectors come from an independent float64 implementation
 * (numpy QR); one step differs only by rounding: 1e-9. Float32: one step of the filter
 * works on H entries ~1..10 and innovations ~1 with relative rounding 6e-8 through two
 * Tria() and two solves (condition of S_zz ~ 1e2): 2e-4 absolute on x and S.
 */
#include "test_common.h"

#include <string.h>

#include "rfe/friction.h"
#include "rfe/component/obsmat.h"
#include "rfe/component/qr.h"
#include "table.h"

#if defined(RFE_REAL_DOUBLE)
#define TOL_STEP 1e-9
#define HUGE_SD0 1e160 /* squares overflow double */
#else
#define TOL_STEP 2e-4
#define HUGE_SD0 1e20 /* squares overflow float (max 3.4e38) */
#endif

static const char *const WHEEL[4] = {"fl", "fr", "rl", "rr"};

static rfe_params_t params;

static int setup(void **state)
{
    (void)state;
    /* The paper preset: these tests pin MODEL.md §6 (the default preset is tested in
     * test_friction_default_flt.c). */
    return rfe_params_paper(&params) == RFE_OK ? 0 : -1;
}

/* A plausible braking sample at 20 m/s. */
static rfe_sample_t braking_sample(void)
{
    rfe_sample_t u;
    size_t i;
    memset(&u, 0, sizeof(u));
    u.vx = 20;
    u.ax = -3;
    u.ay = (rfe_real_t)0.2;
    u.yaw_acc = (rfe_real_t)0.01;
    u.delta = (rfe_real_t)0.01;
    for (i = 0; i < 4; ++i) {
        u.omega[i] = (rfe_real_t)(20.0 * 0.97 / 0.325);
    }
    return u;
}

struct paper_ctx {
    rfe_real_t H[12];
};

static rfe_status_t measure_H(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n, size_t m)
{
    (void)n;
    (void)m;
    return rfe_obsmat_apply(((struct paper_ctx *)ctx)->H, x, z);
}

/* REQ: one SCKF step of the paper configuration equals the independent vectors
 * (tyre -> H -> predict -> update -> projection), including the projected flag. */
/* REQ-EST-001 */
static void test_rfe_sckf_step_matches_vectors(void **state)
{
    test_table_t v;
    size_t r, i, j;
    char name[32], what[96];
    (void)state;
    assert_int_equal(test_table_load(TEST_VECTORS_DIR "/sckf_step_vectors.csv", &v), 0);
    assert_true(v.n_rows >= 10);
    for (r = 0; r < v.n_rows; ++r) {
        rfe_sample_t u;
        rfe_wheel_kin_t kin;
        rfe_real_t f0x[4], f0y[4], x0[4], S0[16], SQ[16] = {0}, SR[9] = {0}, y[3], x1[4];
        struct paper_ctx ctx;
        rfe_sckf_t f;
        int clamped = -1;
        memset(&u, 0, sizeof(u));
        u.delta = (rfe_real_t)test_table_get(&v, r, "delta");
        u.vx = (rfe_real_t)test_table_get(&v, r, "vx");
        u.vy = (rfe_real_t)test_table_get(&v, r, "vy");
        u.yaw_rate = (rfe_real_t)test_table_get(&v, r, "yaw_rate");
        u.ax = (rfe_real_t)test_table_get(&v, r, "ax");
        u.ay = (rfe_real_t)test_table_get(&v, r, "ay");
        for (i = 0; i < 4; ++i) {
            snprintf(name, sizeof(name), "omega_%s", WHEEL[i]);
            u.omega[i] = (rfe_real_t)test_table_get(&v, r, name);
            snprintf(name, sizeof(name), "x0_%s", WHEEL[i]);
            x0[i] = (rfe_real_t)test_table_get(&v, r, name);
            SQ[i * 4 + i] = params.filter.q_mu;
            for (j = 0; j < 4; ++j) {
                snprintf(name, sizeof(name), "S0_%zu%zu", i + 1, j + 1);
                S0[i * 4 + j] = (rfe_real_t)test_table_get(&v, r, name);
            }
        }
        y[0] = (rfe_real_t)test_table_get(&v, r, "y_ax");
        y[1] = (rfe_real_t)test_table_get(&v, r, "y_ay");
        y[2] = (rfe_real_t)test_table_get(&v, r, "y_yaw_acc");
        SR[0] = params.filter.r_ax;
        SR[4] = params.filter.r_ay;
        SR[8] = params.filter.r_yaw_acc;
        assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &u, &kin), RFE_OK);
        assert_int_equal(rfe_tyre_forces_norm(&params.tyre, &kin, f0x, f0y), RFE_OK);
        assert_int_equal(rfe_obsmat_build(&params.vehicle, u.delta, f0x, f0y, ctx.H), RFE_OK);
        assert_int_equal(rfe_sckf_init(&f, 4, 3, x0, S0, SQ, SR), RFE_OK);
        assert_int_equal(rfe_sckf_predict(&f, NULL, NULL), RFE_OK);
        assert_int_equal(rfe_sckf_update(&f, measure_H, &ctx, y), RFE_OK);
        assert_int_equal(rfe_sckf_clamp(&f, params.filter.mu_min, params.filter.mu_max,
                                                &clamped), RFE_OK);
        assert_int_equal(clamped, (int)test_table_get(&v, r, "projected"));
        assert_int_equal(rfe_sckf_get(&f, x1, NULL), RFE_OK);
        for (i = 0; i < 4; ++i) {
            snprintf(name, sizeof(name), "x1_%s", WHEEL[i]);
            snprintf(what, sizeof(what), "case %zu %s", r, name);
            assert_close(x1[i], test_table_get(&v, r, name), TOL_STEP, 0.0, what);
            for (j = 0; j < 4; ++j) {
                snprintf(name, sizeof(name), "S1_%zu%zu", i + 1, j + 1);
                snprintf(what, sizeof(what), "case %zu %s", r, name);
                assert_close(f.S[i * RFE_N_MAX + j], test_table_get(&v, r, name), TOL_STEP, 0.0, what);
            }
        }
    }
    test_table_free(&v);
}

/* REQ: init validates parameters; a rejected init leaves the estimator untouched. */
/* REQ-EST-002 REQ-EST-003 REQ-PARAMS-002 */
static void test_rfe_friction_init_rejects_bad_params(void **state)
{
    static rfe_friction_t est, copy;
    rfe_params_t p = params;
    (void)state;
    memset(&est, 0xA5, sizeof(est));
    copy = est;
    p.vehicle.m = -1;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_ERR_PARAM);
    p = params;
    p.filter.mu_min = (rfe_real_t)1.3; /* above mu_max */
    assert_int_equal(rfe_friction_init(&est, &p), RFE_ERR_PARAM);
    p = params;
    p.tyre.alpha_max = (rfe_real_t)1.6; /* tan would blow up near pi/2 */
    assert_int_equal(rfe_friction_init(&est, &p), RFE_ERR_PARAM);
    p = params;
    p.filter.q_mu = (rfe_real_t)NAN;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_ERR_PARAM);
    p = params;
    p.filter.kind = (rfe_filter_kind_t)7;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_ERR_PARAM);
    assert_int_equal(rfe_friction_init(NULL, &params), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_init(&est, NULL), RFE_ERR_NULL);
    assert_memory_equal(&est, &copy, sizeof(est));
    assert_int_equal(rfe_params_validate(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_params_default(NULL), RFE_ERR_NULL);
}

/* REQ: the initial estimate is mu0 with sd0 on every wheel, for both filters. */
/* REQ-EST-002 */
static void test_rfe_friction_init_sets_prior(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    rfe_params_t p = params;
    int k;
    size_t i;
    (void)state;
    for (k = 0; k < 2; ++k) {
        p.filter.kind = k ? RFE_FILTER_CKF : RFE_FILTER_SCKF;
        assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
        assert_int_equal(rfe_friction_get(&est, &out), RFE_OK);
        for (i = 0; i < 4; ++i) {
            assert_close(out.mu[i], params.filter.mu0, 1e-7, 0.0, "mu0");
            assert_close(out.sd[i], params.filter.sd0, 1e-7, 0.0, "sd0");
            assert_int_equal(out.valid[i], 0);
        }
    }
}

/* REQ: step/get before init, or with NULL arguments, are rejected. */
/* REQ-EST-003 */
static void test_rfe_friction_step_requires_init(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    rfe_sample_t u = braking_sample();
    (void)state;
    memset(&est, 0, sizeof(est));
    assert_int_equal(rfe_friction_step(&est, &u, &out), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_friction_get(&est, &out), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_friction_step(NULL, &u, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_step(&est, NULL, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_step(&est, &u, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_get(NULL, &out), RFE_ERR_NULL);
}

/* REQ: a NaN/Inf or out-of-range sample returns a distinct status, leaves the whole
 * estimator untouched, reports the previous estimate as not valid; the next good sample
 * continues normally. */
/* REQ-EST-004 REQ-EST-005 */
static void test_rfe_friction_step_bad_sample_leaves_state(void **state)
{
    static rfe_friction_t est, copy;
    rfe_estimate_t out;
    rfe_sample_t good = braking_sample(), bad;
    int k;
    (void)state;
    for (k = 0; k < 2; ++k) {
        rfe_params_t p = params;
        p.filter.kind = k ? RFE_FILTER_CKF : RFE_FILTER_SCKF;
        assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
        assert_false(rfe_status_is_error(rfe_friction_step(&est, &good, &out)));
        copy = est;
        bad = good;
        bad.ax = (rfe_real_t)NAN;
        assert_int_equal(rfe_friction_step(&est, &bad, &out), RFE_ERR_NONFINITE);
        assert_memory_equal(&est, &copy, sizeof(est));
        assert_int_equal(out.status, RFE_ERR_NONFINITE);
        assert_int_equal(out.valid[0], 0);
        bad = good;
        bad.yaw_acc = (rfe_real_t)-INFINITY;
        assert_int_equal(rfe_friction_step(&est, &bad, &out), RFE_ERR_NONFINITE);
        bad = good;
        bad.omega[2] = (rfe_real_t)(RFE_LIMIT_OMEGA * 1.01);
        assert_int_equal(rfe_friction_step(&est, &bad, &out), RFE_ERR_RANGE);
        bad = good;
        bad.delta = (rfe_real_t)(RFE_LIMIT_DELTA * 1.01);
        assert_int_equal(rfe_friction_step(&est, &bad, &out), RFE_ERR_RANGE);
        bad = good;
        bad.vx = (rfe_real_t)(-RFE_LIMIT_VX * 1.01);
        assert_int_equal(rfe_friction_step(&est, &bad, &out), RFE_ERR_RANGE);
        bad = good;
        bad.ay = (rfe_real_t)(RFE_LIMIT_ACC * 1.01);
        assert_int_equal(rfe_friction_step(&est, &bad, &out), RFE_ERR_RANGE);
        assert_memory_equal(&est, &copy, sizeof(est));
        assert_false(rfe_status_is_error(rfe_friction_step(&est, &good, &out)));
        assert_int_equal(out.valid[3], 1);
    }
}

/* REQ: below v_est_min only the time update runs: mean held, variance grows by q_mu^2. */
/* REQ-EST-006 */
static void test_rfe_friction_step_low_speed_time_update_only(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    rfe_sample_t u = braking_sample();
    size_t i;
    (void)state;
    u.vx = (rfe_real_t)(params.filter.v_est_min * 0.5);
    assert_int_equal(rfe_friction_init(&est, &params), RFE_OK);
    assert_int_equal(rfe_friction_step(&est, &u, &out), RFE_NO_UPDATE_LOW_SPEED);
    for (i = 0; i < 4; ++i) {
        const double sd0 = params.filter.sd0, q = params.filter.q_mu;
        assert_close(out.mu[i], params.filter.mu0, 1e-6, 0.0, "held mean");
        assert_close(out.sd[i], sqrt(sd0 * sd0 + q * q), 1e-6, 0.0, "sd grows");
        assert_int_equal(out.valid[i], 0);
    }
    u.vx = -5; /* reversing: also no update */
    assert_int_equal(rfe_friction_step(&est, &u, &out), RFE_NO_UPDATE_LOW_SPEED);
}

/* REQ: a measurement that implies friction above mu_max is projected onto the bound. */
/* REQ-EST-007 */
static void test_rfe_friction_step_projects_onto_bounds(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    rfe_sample_t u = braking_sample();
    rfe_status_t st = RFE_OK;
    int k, seen = 0;
    size_t i;
    (void)state;
    u.ax = -40; /* 4 g of braking with ~3 % slip: mu far above 1.2 */
    assert_int_equal(rfe_friction_init(&est, &params), RFE_OK);
    for (k = 0; k < 50; ++k) {
        st = rfe_friction_step(&est, &u, &out);
        assert_false(rfe_status_is_error(st));
        seen |= (st == RFE_PROJECTED);
    }
    assert_true(seen);
    for (i = 0; i < 4; ++i) {
        assert_true(out.mu[i] <= params.filter.mu_max && out.mu[i] >= params.filter.mu_min);
    }
    assert_int_equal(out.valid[0], 1);
}

/* REQ: absolute tyre mode runs the measurement at every cubature point; on a model-matched
 * sample (y generated from the absolute model at mu = 0.6 on a heavily braked, steered car)
 * the four-wheel mean converges towards 0.6. */
/* REQ-EST-012 */
static void test_rfe_friction_absolute_mode_converges(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    rfe_params_t p = params;
    rfe_sample_t u = braking_sample();
    rfe_wheel_kin_t kin;
    rfe_real_t fx[4], fy[4], H[12], y[3];
    const rfe_real_t mu[4] = {(rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6};
    const rfe_real_t ones[4] = {1, 1, 1, 1};
    double mean = 0.0;
    size_t i;
    int k;
    (void)state;
    p.tyre.mode = RFE_TYRE_ABSOLUTE;
    u.delta = (rfe_real_t)0.05;
    for (i = 0; i < 4; ++i) {
        u.omega[i] = (rfe_real_t)(20.0 * 0.85 / 0.325); /* 15 % slip: near saturation */
    }
    for (k = 0; k < 3; ++k) { /* loads depend on ax, ay: iterate to the model-matched point */
        assert_int_equal(rfe_tyre_kinematics(&p.vehicle, &p.tyre, &u, &kin), RFE_OK);
        assert_int_equal(rfe_tyre_forces_abs(&p.tyre, &kin, mu, fx, fy), RFE_OK);
        assert_int_equal(rfe_obsmat_build(&p.vehicle, u.delta, fx, fy, H), RFE_OK);
        assert_int_equal(rfe_obsmat_apply(H, ones, y), RFE_OK);
        u.ax = y[0];
        u.ay = y[1];
        u.yaw_acc = y[2];
    }
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    for (k = 0; k < 300; ++k) {
        assert_false(rfe_status_is_error(rfe_friction_step(&est, &u, &out)));
    }
    for (i = 0; i < 4; ++i) {
        mean += out.mu[i] / 4.0;
    }
    /* Loads were iterated 3 times only, so the sample is model-matched to ~1 %. */
    assert_close(mean, 0.6, 0.03, 0.0, "absolute-mode mean mu");
}

/* REQ: a numerical failure inside the filter (a prior so large its squares overflow)
 * returns an error and restores the filter as it was before the step. */
/* REQ-EST-013 REQ-EST-005 */
static void test_rfe_friction_step_numeric_failure_rolls_back(void **state)
{
    static rfe_friction_t est, copy;
    rfe_estimate_t out;
    rfe_params_t p = params;
    rfe_sample_t u = braking_sample();
    rfe_status_t st;
    (void)state;
    p.filter.sd0 = (rfe_real_t)HUGE_SD0;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    copy = est;
    st = rfe_friction_step(&est, &u, &out);
    assert_true(rfe_status_is_error(st));
    assert_memory_equal(est.filter.sckf.x, copy.filter.sckf.x, sizeof(copy.filter.sckf.x));
    assert_memory_equal(est.filter.sckf.S, copy.filter.sckf.S, sizeof(copy.filter.sckf.S));
    assert_int_equal(out.status, st);
    assert_true(isfinite(out.mu[0]));
}

/* REQ: every status has a name. */
/* REQ-EST-014 */
static void test_rfe_status_str_names_every_code(void **state)
{
    int s;
    (void)state;
    for (s = 0; s < 32; ++s) {
        assert_non_null(rfe_status_str((rfe_status_t)s));
    }
    assert_string_equal(rfe_status_str(RFE_OK), "ok");
    assert_string_equal(rfe_status_str((rfe_status_t)99), "unknown status");
    assert_true(rfe_status_is_error(RFE_ERR_NULL));
    assert_false(rfe_status_is_error(RFE_PROJECTED));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_sckf_step_matches_vectors),
        cmocka_unit_test(test_rfe_friction_init_rejects_bad_params),
        cmocka_unit_test(test_rfe_friction_init_sets_prior),
        cmocka_unit_test(test_rfe_friction_step_requires_init),
        cmocka_unit_test(test_rfe_friction_step_bad_sample_leaves_state),
        cmocka_unit_test(test_rfe_friction_step_low_speed_time_update_only),
        cmocka_unit_test(test_rfe_friction_step_projects_onto_bounds),
        cmocka_unit_test(test_rfe_friction_absolute_mode_converges),
        cmocka_unit_test(test_rfe_friction_step_numeric_failure_rolls_back),
        cmocka_unit_test(test_rfe_status_str_names_every_code),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
