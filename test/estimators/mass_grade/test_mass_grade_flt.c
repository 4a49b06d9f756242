/**
 * @file test_mass_grade_flt.c
 * @brief The mass and grade estimator's interface (rfe/mass_grade.h) and its behaviour on
 *        cases whose answer is known without the reference: parameters and presets, every
 *        argument check with the state untouched, the start and restart, the pause logic
 *        (MASS_GRADE.md §4.2), the adaptation (§4.4), the square-root form's failures, the
 *        unscented filter equal to the Kalman filter on a linear problem, and the square-root
 *        form staying positive definite in float32 where the textbook form failed.
 *
 * Tolerances. TOL_EXACT: the same operations as the code under test on the same numbers,
 * so equal up to the one rounding a differently grouped expression in the test may add (2
 * ulp of the number type). TOL_KF: the linear problem, see test_ukf_is_the_kalman_filter.
 */
#include "test_common.h"

#include <stdlib.h>
#include <string.h>

#include "estimators/mass_grade/mass_grade_internal.h"
#include "estimators/mass_grade/mass_grade_logic.h"
#include "kalman_ref.h"
#include "mg_logs.h"
#include "table.h"
#include "rfe/component/params_conv.h"
#include "rfe/mass_grade.h"

#if defined(RFE_REAL_DOUBLE)
#define TOL_EXACT 4.5e-16
#else
#define TOL_EXACT 2.4e-7
#endif

#define DT 0.02

#if defined(RFE_REAL_DOUBLE)
#define HUGE_REAL 1e308
#else
#define HUGE_REAL 3e38f
#endif

static rfe_mass_grade_params_t prm;
static rfe_mass_grade_t mg;

static void setup_with(uint32_t adaptive, uint32_t use_ax)
{
    assert_int_equal(rfe_mass_grade_params_default(&prm), RFE_OK);
    prm.adaptive = adaptive;
    prm.use_ax = use_ax;
    /* the fixed grade walk (§4.7 off; on in the default): these tests check the steps'
     * arithmetic against q_theta; the walk's own tests below turn it on */
    prm.q_theta_hi = (rfe_real_t)0.0;
    assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
}

/* A car cruising at v with some torque and the accelerometer reading a flat road. */
static rfe_mass_grade_input_t cruise(rfe_real_t v, rfe_real_t dt)
{
    rfe_mass_grade_input_t in;
    memset(&in, 0, sizeof(in));
    in.dt = dt;
    in.v = v;
    in.torque = (rfe_real_t)300.0;
    in.ax = (rfe_real_t)0.1;
    in.has = RFE_MG_HAS_AX;
    return in;
}

static rfe_status_t step(const rfe_mass_grade_input_t *in, rfe_mass_grade_estimate_t *e)
{
    return rfe_mass_grade_step(&mg, in, e);
}

/* P = S S^T of the state's factor, in double (each product of two entries exact in double
 * for a float32 S; rounded to 1e-16 in the double build). */
static void cov_of_factor(const rfe_real_t *S, double P[9])
{
    size_t i;
    size_t j;
    size_t k;
    for (i = 0u; i < 3u; ++i) {
        for (j = 0u; j < 3u; ++j) {
            double acc = 0.0;
            for (k = 0u; k < 3u; ++k) {
                acc += (double)S[(i * 3u) + k] * (double)S[(j * 3u) + k];
            }
            P[(i * 3u) + j] = acc;
        }
    }
}

/* REQ-MG-003 */
static void test_params_presets_and_validation(void **state)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_t q;
    (void)state;
    assert_int_equal(rfe_mass_grade_params_default(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_params_preset(NULL, RFE_MG_CAR, RFE_MG_SEED), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_params_validate(NULL), RFE_ERR_NULL);
    /* the default is the car's recommended preset: the plain UKF with the ax row */
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    assert_int_equal(rfe_mass_grade_params_preset(&q, RFE_MG_CAR, RFE_MG_RECOMMENDED), RFE_OK);
    assert_memory_equal(&p, &q, sizeof(p));
    assert_int_equal(p.adaptive, 0u);
    assert_int_equal(p.use_ax, 1u);
    assert_true(p.pause_grade == (rfe_real_t)RFE_MG_PAUSE_GRADE_BRAKE); /* §6: the brake bit */
    assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK);
    /* every preset valid; an unknown vehicle or configuration refused, p untouched */
    assert_int_equal(rfe_mass_grade_params_preset(&q, RFE_MG_TRUCK, RFE_MG_SEED), RFE_OK);
    assert_int_equal(rfe_mass_grade_params_validate(&q), RFE_OK);
    assert_int_equal(q.adaptive, 1u);
    assert_true(q.pause_grade == (rfe_real_t)0.0); /* the seed's pauses hold */
    assert_true(q.m_rot == (rfe_real_t)0.0);
    assert_true(q.m0 == (rfe_real_t)4000.0);
    p = q;
    assert_int_equal(rfe_mass_grade_params_preset(&q, (rfe_mg_vehicle_t)2, RFE_MG_SEED),
                     RFE_ERR_PARAM);
    assert_int_equal(rfe_mass_grade_params_preset(&q, RFE_MG_CAR, (rfe_mg_config_t)2),
                     RFE_ERR_PARAM);
    assert_memory_equal(&p, &q, sizeof(p));
}

/* One broken value per rule of MASS_GRADE.md §6. */
static void expect_bad(void (*breaker)(rfe_mass_grade_params_t *), const char *what)
{
    rfe_mass_grade_params_t p;
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    breaker(&p);
    if (rfe_mass_grade_params_validate(&p) != RFE_ERR_PARAM) {
        fail_msg("%s accepted", what);
    }
}
static void b_r(rfe_mass_grade_params_t *p) { p->R = (rfe_real_t)0.0; }
static void b_rv(rfe_mass_grade_params_t *p) { p->r_v = (rfe_real_t)NAN; }
static void b_fc(rfe_mass_grade_params_t *p) { p->fc = (rfe_real_t)-0.01; }
static void b_beta(rfe_mass_grade_params_t *p) { p->ut_beta = (rfe_real_t)INFINITY; }
static void b_adaptive(rfe_mass_grade_params_t *p) { p->adaptive = 2u; }
static void b_use_ax(rfe_mass_grade_params_t *p) { p->use_ax = 2u; }
static void b_m0_low(rfe_mass_grade_params_t *p) { p->m0 = p->m_min; }
static void b_m0_high(rfe_mass_grade_params_t *p) { p->m0 = p->m_max; }
static void b_m_max(rfe_mass_grade_params_t *p) { p->m_max = (rfe_real_t)NAN; }
static void b_theta0(rfe_mass_grade_params_t *p) { p->theta0 = p->theta_max; }
static void b_theta0_nan(rfe_mass_grade_params_t *p) { p->theta0 = (rfe_real_t)NAN; }
static void b_theta_max(rfe_mass_grade_params_t *p) { p->theta_max = (rfe_real_t)1.5; }
static void b_kappa(rfe_mass_grade_params_t *p) { p->ut_kappa = (rfe_real_t)-3.0; }
static void b_kappa_nan(rfe_mass_grade_params_t *p) { p->ut_kappa = (rfe_real_t)NAN; }
static void b_alpha_huge(rfe_mass_grade_params_t *p) { p->ut_alpha = (rfe_real_t)1e300; }
static void b_slip(rfe_mass_grade_params_t *p) { p->slip_max = (rfe_real_t)-0.01; }
static void b_slip_nan(rfe_mass_grade_params_t *p) { p->slip_max = (rfe_real_t)NAN; }
static void b_ay_max(rfe_mass_grade_params_t *p) { p->ay_max = (rfe_real_t)-0.5; }
static void b_t_curve_nan(rfe_mass_grade_params_t *p) { p->t_curve = (rfe_real_t)NAN; }
static void b_pg_big(rfe_mass_grade_params_t *p) { p->pause_grade = (rfe_real_t)8.0; }
static void b_pg_frac(rfe_mass_grade_params_t *p) { p->pause_grade = (rfe_real_t)2.5; }
static void b_pg_neg(rfe_mass_grade_params_t *p) { p->pause_grade = (rfe_real_t)-1.0; }
static void b_pg_nan(rfe_mass_grade_params_t *p) { p->pause_grade = (rfe_real_t)NAN; }
static void b_pgs_neg(rfe_mass_grade_params_t *p) { p->pause_grade_slip = (rfe_real_t)-0.01; }
static void b_pgs_big(rfe_mass_grade_params_t *p) { p->pause_grade_slip = (rfe_real_t)1.0625; }
static void b_pgs_nan(rfe_mass_grade_params_t *p) { p->pause_grade_slip = (rfe_real_t)NAN; }
static void b_pgs_inf(rfe_mass_grade_params_t *p) { p->pause_grade_slip = (rfe_real_t)INFINITY; }
static void b_pgd_neg(rfe_mass_grade_params_t *p) { p->pause_grade_dv = (rfe_real_t)-0.01; }
static void b_pgd_big(rfe_mass_grade_params_t *p) { p->pause_grade_dv = (rfe_real_t)10.0625; }
static void b_pgd_nan(rfe_mass_grade_params_t *p) { p->pause_grade_dv = (rfe_real_t)NAN; }
static void b_pgd_inf(rfe_mass_grade_params_t *p) { p->pause_grade_dv = (rfe_real_t)INFINITY; }
static void b_stop(rfe_mass_grade_params_t *p)
{
    p->adaptive = 1u;
    p->mv_stop = (p->q_mv0 * p->q_mv0) / (p->q_mc * p->q_mc); /* ends before it starts */
}

/* REQ-MG-003 */
static void test_params_rules(void **state)
{
    rfe_mass_grade_params_t p;
    (void)state;
    expect_bad(b_r, "R = 0");
    expect_bad(b_rv, "r_v NaN");
    expect_bad(b_fc, "fc < 0");
    expect_bad(b_beta, "beta Inf");
    expect_bad(b_adaptive, "adaptive 2");
    expect_bad(b_use_ax, "use_ax 2");
    expect_bad(b_m0_low, "m0 = m_min");
    expect_bad(b_m0_high, "m0 = m_max");
    expect_bad(b_m_max, "m_max NaN");
    expect_bad(b_theta0, "|theta0| = theta_max");
    expect_bad(b_theta0_nan, "theta0 NaN");
    expect_bad(b_theta_max, "theta_max = 1.5");
    expect_bad(b_kappa, "n + lambda = 0");
    expect_bad(b_kappa_nan, "kappa NaN");
    expect_bad(b_alpha_huge, "alpha^2 overflowing");
    expect_bad(b_stop, "adaptation ending before it starts");
    expect_bad(b_slip, "slip_max < 0");
    expect_bad(b_slip_nan, "slip_max NaN");
    expect_bad(b_ay_max, "ay_max < 0");
    expect_bad(b_t_curve_nan, "t_curve NaN");
    expect_bad(b_pg_big, "pause_grade 8");
    expect_bad(b_pg_frac, "pause_grade 2.5");
    expect_bad(b_pg_neg, "pause_grade -1");
    expect_bad(b_pg_nan, "pause_grade NaN");
    expect_bad(b_pgs_neg, "pause_grade_slip < 0");
    expect_bad(b_pgs_big, "pause_grade_slip > 1");
    expect_bad(b_pgs_nan, "pause_grade_slip NaN");
    expect_bad(b_pgs_inf, "pause_grade_slip Inf");
    expect_bad(b_pgd_neg, "pause_grade_dv < 0");
    expect_bad(b_pgd_big, "pause_grade_dv > 10");
    expect_bad(b_pgd_nan, "pause_grade_dv NaN");
    expect_bad(b_pgd_inf, "pause_grade_dv Inf");
    /* the change test's speed: 0.2 m/s by default, its limits 0 (no test) and 10 accepted */
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    assert_true(p.pause_grade_dv == (rfe_real_t)0.2);
    p.pause_grade_dv = (rfe_real_t)0.0;
    assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK);
    p.pause_grade_dv = (rfe_real_t)10.0;
    assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK);
    /* the ABS gate's slip: 0.05 by default, its limits 0 (no gate) and 1 accepted */
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    assert_true(p.pause_grade_slip == (rfe_real_t)0.05);
    p.pause_grade_slip = (rfe_real_t)0.0;
    assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK);
    p.pause_grade_slip = (rfe_real_t)1.0;
    assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK);
    /* every bit sum 0..7, with the accelerometer or without it (then inert:
     * test_pause_grade_inert_without_ax) */
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    assert_true(p.pause_grade == (rfe_real_t)1.0); /* the brake bit by default */
    p.pause_grade = (rfe_real_t)7.0;
    assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK);
    p.use_ax = 0u;
    assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK);
    /* the same stop threshold is fine in the plain UKF, which never adapts */
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    b_stop(&p);
    p.adaptive = 0u;
    assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK);
}

/* REQ-MG-004 */
static void test_init_get_restart_arguments(void **state)
{
    rfe_mass_grade_t m;
    rfe_mass_grade_t copy;
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_params_t bad;
    (void)state;
    setup_with(0u, 1u);
    memset(&m, 0x5A, sizeof(m));
    copy = m;
    assert_int_equal(rfe_mass_grade_init(NULL, &prm), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_init(&m, NULL), RFE_ERR_NULL);
    bad = prm;
    bad.r_v = (rfe_real_t)-1.0;
    assert_int_equal(rfe_mass_grade_init(&m, &bad), RFE_ERR_PARAM);
    /* another caller's layout or number type: refused, nothing written */
    assert_int_equal((rfe_mass_grade_init)(&m, &prm, sizeof(m) + 8u, RFE_CONFIG_REAL),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_mass_grade_init)(&m, &prm, sizeof(m), RFE_CONFIG_REAL ^ 3u),
                     RFE_ERR_ABI);
    assert_memory_equal(&m, &copy, sizeof(m));
    /* not initialised (no magic word) */
    assert_int_equal(rfe_mass_grade_get(&m, &e), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_mass_grade_restart(&m), RFE_ERR_NOT_INITIALISED);
    {
        const rfe_mass_grade_input_t in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        assert_int_equal(rfe_mass_grade_step(&m, &in, &e), RFE_ERR_NOT_INITIALISED);
        assert_int_equal(rfe_mass_grade_step(NULL, &in, &e), RFE_ERR_NULL);
        assert_int_equal(rfe_mass_grade_step(&mg, NULL, &e), RFE_ERR_NULL);
        assert_int_equal(rfe_mass_grade_step(&mg, &in, NULL), RFE_ERR_NULL);
    }
    assert_memory_equal(&m, &copy, sizeof(m));
    assert_int_equal(rfe_mass_grade_get(NULL, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_get(&mg, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_restart(NULL), RFE_ERR_NULL);
    /* before any sample: every value 0, the status RFE_OK of init */
    assert_int_equal(rfe_mass_grade_get(&mg, &e), RFE_OK);
    assert_true((e.mass == (rfe_real_t)0.0) && (e.sd_mass == (rfe_real_t)0.0));
}

/* Every refused sample: its status, the estimator bit for bit as before, the previous
 * estimate out with that status. */
static void expect_refused(rfe_mass_grade_input_t in, rfe_status_t want)
{
    rfe_mass_grade_t before = mg;
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t last;
    assert_int_equal(rfe_mass_grade_get(&mg, &last), RFE_OK);
    assert_int_equal(step(&in, &e), want);
    assert_memory_equal(&mg, &before, sizeof(mg));
    assert_int_equal(e.status, want);
    assert_true((e.mass == last.mass) && (e.grade == last.grade) && (e.sd_mass == last.sd_mass));
}

/* REQ-MG-004 */
static void test_refused_samples_leave_the_state_untouched(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    int k;
    (void)state;
    setup_with(1u, 1u);
    /* before the first sample an error gives zeros, never a NaN */
    in = cruise((rfe_real_t)NAN, (rfe_real_t)0.0);
    assert_int_equal(step(&in, &e), RFE_ERR_NONFINITE);
    assert_true((e.mass == (rfe_real_t)0.0) && (e.status == RFE_ERR_NONFINITE));
    for (k = 0; k < 5; ++k) {
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        assert_false(rfe_status_is_error(step(&in, &e)));
    }
    in = cruise((rfe_real_t)NAN, (rfe_real_t)DT);
    expect_refused(in, RFE_ERR_NONFINITE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)INFINITY);
    expect_refused(in, RFE_ERR_NONFINITE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.torque = (rfe_real_t)-INFINITY;
    expect_refused(in, RFE_ERR_NONFINITE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.ax = (rfe_real_t)NAN;
    expect_refused(in, RFE_ERR_NONFINITE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.p_brake = (rfe_real_t)NAN;
    in.has |= RFE_MG_HAS_PRESSURE;
    expect_refused(in, RFE_ERR_NONFINITE);
    in = cruise((rfe_real_t)101.0, (rfe_real_t)DT); /* |v| > RFE_LIMIT_VX */
    expect_refused(in, RFE_ERR_RANGE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.torque = (rfe_real_t)-1.01e5; /* |T| > RFE_LIMIT_DRIVE_TORQUE */
    expect_refused(in, RFE_ERR_RANGE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.ax = (rfe_real_t)51.0; /* |ax| > RFE_LIMIT_ACC */
    expect_refused(in, RFE_ERR_RANGE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.has = 64u | RFE_MG_HAS_AX; /* an unknown bit */
    expect_refused(in, RFE_ERR_RANGE);
    /* the ground speed vx: checked as v is, when given */
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.has |= RFE_MG_HAS_VX;
    in.vx = (rfe_real_t)NAN;
    expect_refused(in, RFE_ERR_NONFINITE);
    in.vx = (rfe_real_t)-INFINITY;
    expect_refused(in, RFE_ERR_NONFINITE);
    in.vx = (rfe_real_t)-101.0; /* |vx| > RFE_LIMIT_VX */
    expect_refused(in, RFE_ERR_RANGE);
    in.has = RFE_MG_HAS_AX; /* not given: not read */
    assert_int_equal(step(&in, &e), RFE_OK);
    /* the lateral acceleration ay: checked as ax is, when given */
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.has |= RFE_MG_HAS_AY;
    in.ay = (rfe_real_t)NAN;
    expect_refused(in, RFE_ERR_NONFINITE);
    in.ay = (rfe_real_t)-51.0; /* |ay| > RFE_LIMIT_ACC */
    expect_refused(in, RFE_ERR_RANGE);
    in.has = RFE_MG_HAS_AX; /* not given: not read */
    assert_int_equal(step(&in, &e), RFE_OK);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.has = 0u; /* the ax row needs ax */
    expect_refused(in, RFE_ERR_RANGE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)0.0); /* time not moving */
    expect_refused(in, RFE_ERR_RANGE);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)-DT);
    expect_refused(in, RFE_ERR_RANGE);
    /* an ax out of range counts only when given (speed-only filter, no ax bit) */
    setup_with(1u, 0u);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)0.0);
    in.ax = (rfe_real_t)NAN;
    in.has = 0u;
    assert_int_equal(step(&in, &e), RFE_OK);
}

/* REQ-MG-005 */
static void test_start_and_restart(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t fresh;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t other;
    int k;
    (void)state;
    setup_with(1u, 1u);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)123.0); /* the first sample's dt is ignored */
    assert_int_equal(step(&in, &e), RFE_OK);
    /* §4.1: x = [v, m0, theta0], P diagonal, q_mv = q_mv0^2 */
    assert_true(e.mass == prm.m0);
    assert_true(e.grade == prm.theta0);
    assert_true(e.v == (rfe_real_t)20.0);
    assert_close(e.sd_mass, prm.sd_m0, 0.0, TOL_EXACT, "sd_mass at the start");
    assert_close(e.sd_grade, prm.sd_theta0, 0.0, TOL_EXACT, "sd_grade at the start");
    assert_close(e.q_mv, prm.q_mv0 * prm.q_mv0, 0.0, TOL_EXACT, "q_mv at the start");
    for (k = 0; k < 100; ++k) {
        in = cruise((rfe_real_t)20.0 + (rfe_real_t)0.01 * (rfe_real_t)k, (rfe_real_t)DT);
        assert_int_equal(step(&in, &e), RFE_OK);
    }
    assert_true(e.mass != prm.m0); /* it learned */
    other = mg;
    /* a period longer than dt_max starts afresh, as does a restart: both equal the first
     * step of a fresh estimator on the same sample */
    in = cruise((rfe_real_t)25.0, prm.dt_max * (rfe_real_t)1.5);
    assert_int_equal(step(&in, &e), RFE_OK);
    mg = other;
    assert_int_equal(rfe_mass_grade_restart(&mg), RFE_OK);
    assert_int_equal(rfe_mass_grade_get(&mg, &fresh), RFE_OK);
    assert_true(fresh.mass != prm.m0); /* the last estimate stays until the next sample */
    in.dt = (rfe_real_t)DT;
    assert_int_equal(step(&in, &fresh), RFE_OK);
    assert_memory_equal(&e, &fresh, sizeof(e));
    other = mg;
    assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
    assert_int_equal(step(&in, &fresh), RFE_OK);
    assert_memory_equal(&e, &fresh, sizeof(e));
    assert_memory_equal(&mg, &other, sizeof(mg));
}

/* REQ-MG-006 */
static void test_brake_holds_mass_and_grade(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t before;
    rfe_mass_grade_input_t in;
    double P[9];
    double p33;
    int k;
    (void)state;
    setup_with(0u, 1u);
    for (k = 0; k < 50; ++k) {
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        assert_int_equal(step(&in, &before), RFE_OK);
    }
    /* the pedal: held (§4.2): M, theta and P_MM kept, P_thth += q_theta^2 dt, v restarts at
     * the measured speed with variance r_v^2, uncorrelated */
    cov_of_factor(mg.S, P);
    p33 = P[8];
    in = cruise((rfe_real_t)19.0, (rfe_real_t)DT);
    in.brake = 1u;
    in.has |= RFE_MG_HAS_BRAKE;
    in.torque = (rfe_real_t)-2000.0; /* would teach the mass a lot, were it used */
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((e.mass == before.mass) && (e.grade == before.grade) &&
                (e.sd_mass == before.sd_mass));
    /* P_thth from the 2 x 4 triangularisation: the norm of a 4-element row and one
     * reflection of the mass row, a few roundings of the type: 8 TOL_EXACT */
    cov_of_factor(mg.S, P);
    assert_close(P[8], p33 + (double)(prm.q_theta * prm.q_theta) * DT, 0.0, 8.0 * TOL_EXACT,
                 "P_thth grows by its random walk");
    assert_true(e.v == (rfe_real_t)19.0);
    assert_true((mg.S[1] == (rfe_real_t)0.0) && (mg.S[2] == (rfe_real_t)0.0) &&
                (mg.S[3] == (rfe_real_t)0.0) && (mg.S[6] == (rfe_real_t)0.0)); /* v uncorrelated */
    assert_close(e.sd_v, prm.r_v, 0.0, TOL_EXACT, "sd_v restarts at r_v");
    /* released: held t_brake = 1 s = 50 periods after the last braked sample (the 50th,
     * exactly t_brake later, is the first free one), then updates */
    for (k = 1; k <= 50; ++k) {
        in = cruise((rfe_real_t)19.0, (rfe_real_t)DT);
        assert_int_equal(step(&in, &e), (k < 50) ? RFE_MG_PAUSED_BRAKE : RFE_OK);
    }
    assert_true(e.mass != before.mass);
    /* the pressure alone: on above p_brake_on, not at it */
    in = cruise((rfe_real_t)19.0, (rfe_real_t)DT);
    in.has |= RFE_MG_HAS_PRESSURE;
    in.p_brake = prm.p_brake_on;
    assert_int_equal(step(&in, &e), RFE_OK);
    in.p_brake = prm.p_brake_on * (rfe_real_t)1.01;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    /* a pedal flag of 0 is no brake */
    setup_with(0u, 1u);
    in = cruise((rfe_real_t)19.0, (rfe_real_t)DT);
    in.has |= RFE_MG_HAS_BRAKE;
    assert_int_equal(step(&in, &e), RFE_OK);
}

/* A slipping sample: the wheels' speed v runs ahead of the ground speed vx while the drive
 * torque is large; a model taking T / r as the car's force would learn a lighter car. */
static rfe_mass_grade_input_t slipping(rfe_real_t v, rfe_real_t vx)
{
    rfe_mass_grade_input_t in = cruise(v, (rfe_real_t)DT);
    in.torque = (rfe_real_t)3000.0;
    in.ax = (rfe_real_t)0.5;
    in.vx = vx;
    in.has |= RFE_MG_HAS_VX;
    return in;
}

/* REQ-MG-006 the slip pause (§4.2 step 3): held as a brake pause holds; the threshold
 * slip_max max(|vx|, v_min) strict; its precedence; slip_max = 0 and no vx never pause. */
static void test_slip_holds_mass_and_grade(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t before;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t learning;
    double P[9];
    double p33;
    int k;
    (void)state;
    setup_with(0u, 1u);
    for (k = 0; k < 50; ++k) {
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        in.vx = (rfe_real_t)20.0; /* given, no slip: updates */
        in.has |= RFE_MG_HAS_VX;
        assert_int_equal(step(&in, &before), RFE_OK);
    }
    learning = mg;
    cov_of_factor(mg.S, P);
    p33 = P[8];
    /* 2 m/s of slip at 20 m/s (0.1 > 0.05): held, 50 samples of full torque teach nothing;
     * M, theta and sd_M kept, P_thth += q_theta^2 dt each (8 TOL_EXACT: the brake test's) */
    for (k = 0; k < 50; ++k) {
        in = slipping((rfe_real_t)22.0, (rfe_real_t)20.0);
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SLIP);
        assert_true((e.mass == before.mass) && (e.grade == before.grade) &&
                    (e.sd_mass == before.sd_mass));
    }
    cov_of_factor(mg.S, P);
    assert_close(P[8], p33 + 50.0 * (double)(prm.q_theta * prm.q_theta) * DT, 0.0,
                 8.0 * 50.0 * TOL_EXACT, "P_thth grows by its random walk");
    assert_true(e.v == (rfe_real_t)22.0); /* v restarts at the measured (wheels') speed */
    assert_close(e.sd_v, prm.r_v, 0.0, TOL_EXACT, "sd_v restarts at r_v");
    /* the same samples without vx update and move the mass: what the pause keeps out */
    mg = learning;
    for (k = 0; k < 50; ++k) {
        in = slipping((rfe_real_t)22.0, (rfe_real_t)20.0);
        in.has &= ~RFE_MG_HAS_VX;
        assert_int_equal(step(&in, &e), RFE_OK);
    }
    assert_true(fabs((double)(e.mass - before.mass)) > 10.0);
    /* slip_max = 0: no slip pause */
    mg = learning;
    mg.p.slip_max = (rfe_real_t)0.0;
    in = slipping((rfe_real_t)22.0, (rfe_real_t)20.0);
    assert_int_equal(step(&in, &e), RFE_OK);
    /* the threshold, exact in binary: slip_max 1/8 of vx = 16 is 2 m/s; at it updated,
     * beyond it held; either sign of the slip (a braked wheel locking: v below vx) */
    mg = learning;
    mg.p.slip_max = (rfe_real_t)0.125;
    in = slipping((rfe_real_t)18.0, (rfe_real_t)16.0);
    assert_int_equal(step(&in, &e), RFE_OK);
    in = slipping((rfe_real_t)18.5, (rfe_real_t)16.0);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SLIP);
    in = slipping((rfe_real_t)13.5, (rfe_real_t)16.0);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SLIP);
    /* below v_min the reference is v_min (3 m/s: 0.375 m/s), and the slip comes before the
     * low speed: 0.5 m/s of slip at vx = 1 is held as slip, 0.25 as low speed */
    in = slipping((rfe_real_t)1.5, (rfe_real_t)1.0);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SLIP);
    in = slipping((rfe_real_t)1.25, (rfe_real_t)1.0);
    assert_int_equal(step(&in, &e), RFE_NO_UPDATE_LOW_SPEED);
    /* the brake and the shift come before the slip */
    in = slipping((rfe_real_t)22.0, (rfe_real_t)16.0);
    in.brake = 1u;
    in.has |= RFE_MG_HAS_BRAKE;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    mg = learning;
    in = slipping((rfe_real_t)22.0, (rfe_real_t)16.0);
    in.has |= RFE_MG_HAS_GEAR;
    in.gear = 2;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SLIP); /* the first gear: no change */
    in.gear = 3;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SHIFT);
    /* a start on a slipping sample starts and reports the pause, as on a braked one */
    setup_with(0u, 1u);
    in = slipping((rfe_real_t)22.0, (rfe_real_t)20.0);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SLIP);
    assert_true(e.mass == prm.m0);
}

/* A cornering sample at 20 m/s: full torque, ay given. */
static rfe_mass_grade_input_t cornering(rfe_real_t ay)
{
    rfe_mass_grade_input_t in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.torque = (rfe_real_t)3000.0;
    in.ax = (rfe_real_t)0.5;
    in.ay = ay;
    in.has |= RFE_MG_HAS_AY;
    return in;
}

/* REQ-MG-006 the curve pause (§4.2 step 4): |ay| > ay_max held as a brake pause holds, and
 * t_curve after the last such sample (the brake's half-period rule); the threshold strict;
 * after the slip, before the low speed; ay_max = 0 (the default) and no ay never pause. */
static void test_curve_holds_mass_and_grade(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t before;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t learning;
    int k;
    (void)state;
    setup_with(0u, 1u);
    assert_true(prm.ay_max == (rfe_real_t)0.0); /* off by default */
    mg.p.ay_max = (rfe_real_t)1.0;
    mg.p.t_curve = (rfe_real_t)0.1; /* 5 periods */
    for (k = 0; k < 50; ++k) {
        in = cornering((rfe_real_t)0.0); /* given, straight: updates */
        assert_int_equal(step(&in, &before), RFE_OK);
    }
    learning = mg;
    for (k = 0; k < 30; ++k) {
        in = cornering((rfe_real_t)-1.5);
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_CURVE);
        assert_true((e.mass == before.mass) && (e.grade == before.grade) &&
                    (e.sd_mass == before.sd_mass));
    }
    /* 0.08 ... 0.02 s left exceed half a period (0.01 s): held; then 0: updated */
    for (k = 0; k < 4; ++k) {
        in = cornering((rfe_real_t)0.0);
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_CURVE);
        assert_true(e.mass == before.mass);
    }
    in = cornering((rfe_real_t)0.0);
    assert_int_equal(step(&in, &e), RFE_OK);
    /* the same samples without ay update and move the mass: what the pause keeps out */
    mg = learning;
    for (k = 0; k < 30; ++k) {
        in = cornering((rfe_real_t)-1.5);
        in.has &= ~RFE_MG_HAS_AY;
        assert_int_equal(step(&in, &e), RFE_OK);
    }
    assert_true(fabs((double)(e.mass - before.mass)) > 10.0);
    /* ay_max = 0: no curve pause */
    mg = learning;
    mg.p.ay_max = (rfe_real_t)0.0;
    in = cornering((rfe_real_t)-1.5);
    assert_int_equal(step(&in, &e), RFE_OK);
    /* the threshold, exact in binary, no delay: at it updated, beyond it held */
    mg = learning;
    mg.p.t_curve = (rfe_real_t)0.0;
    in = cornering((rfe_real_t)1.0);
    assert_int_equal(step(&in, &e), RFE_OK);
    in = cornering((rfe_real_t)1.0625);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_CURVE);
    in = cornering((rfe_real_t)0.0);
    assert_int_equal(step(&in, &e), RFE_OK);
    /* before the low speed, after the slip */
    in = cornering((rfe_real_t)2.0);
    in.v = (rfe_real_t)1.0;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_CURVE);
    in = cornering((rfe_real_t)2.0);
    in.vx = (rfe_real_t)16.0;
    in.has |= RFE_MG_HAS_VX;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SLIP);
}

/* A braked sample on a 0.05 rad climb decelerating at 2 m/s^2 (ax = v-dot + g sin theta),
 * k periods after the brake went on at 20 m/s. */
#define PG_THETA 0.05
static rfe_mass_grade_input_t braking_on_grade(int k)
{
    rfe_mass_grade_input_t in = cruise((rfe_real_t)(20.0 - (2.0 * DT * (double)k)), (rfe_real_t)DT);
    in.torque = (rfe_real_t)-2000.0;
    in.ax = (rfe_real_t)(-2.0 + (9.81 * sin(PG_THETA)));
    in.brake = 1u;
    in.has |= RFE_MG_HAS_BRAKE;
    return in;
}

/* The state after 50 updates on a level cruise with the accelerometer, pause_grade @p pg,
 * the change test off (pause_grade_dv 0: each pause learns from its second sample, the mode
 * these tests are about; test_change_test runs it on). */
static void pause_grade_setup(rfe_real_t pg)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    int k;
    setup_with(0u, 1u);
    mg.p.pause_grade = pg;
    mg.p.pause_grade_dv = (rfe_real_t)0.0;
    for (k = 0; k < 50; ++k) {
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        assert_int_equal(step(&in, &e), RFE_OK);
    }
}

/* REQ-MG-006 the grade from ax in a pause (§4.2, pause_grade): braking on a 0.05 rad climb
 * with the brake bit set, the first braked sample holds (v was correlated with M) and every
 * later one keeps M, sd_mass and S's mass row bit for bit while the grade runs to the truth;
 * the same samples with pause_grade 0 keep the grade bit for bit. The grade's error after
 * 2 s must be under a tenth of where it was: the data are exact, so only the random walk
 * q_theta and the speed noise r_v limit it, and the kinematic model's residual grows as
 * g dtheta t (0.05 m/s, one r_v, after 0.1 s at an error of 0.05 rad); measured 38 -> 1.9
 * mrad in float and double (the estimate still converging: half the bound). */
static void test_pause_grade_learns_grade_holds_mass(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t first;
    rfe_mass_grade_input_t in;
    rfe_real_t row_m[4];
    double err0;
    int k;
    (void)state;
    pause_grade_setup((rfe_real_t)RFE_MG_PAUSE_GRADE_BRAKE);
    in = braking_on_grade(0);
    assert_int_equal(step(&in, &first), RFE_MG_PAUSED_BRAKE);
    assert_true(mg.S[3] == (rfe_real_t)0.0); /* the hold: v uncorrelated with M */
    row_m[0] = mg.S[4];
    row_m[1] = mg.S[5];
    row_m[2] = mg.S[7];
    row_m[3] = mg.x[1];
    err0 = fabs((double)first.grade - PG_THETA);
    assert_true(err0 > 0.02);
    for (k = 1; k <= 100; ++k) {
        in = braking_on_grade(k);
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
        assert_true((e.mass == first.mass) && (e.sd_mass == first.sd_mass));
        assert_true((mg.S[3] == (rfe_real_t)0.0) && (mg.S[4] == row_m[0]) &&
                    (mg.S[5] == row_m[1]) && (mg.S[7] == row_m[2]) && (mg.x[1] == row_m[3]));
    }
    printf("grade from ax while braking: error %.3g rad -> %.3g rad\n", err0,
           fabs((double)e.grade - PG_THETA));
    assert_true(fabs((double)e.grade - PG_THETA) < (0.1 * err0));
    assert_true(e.sd_grade < first.sd_grade); /* it learned */
    /* off: the same samples hold the grade bit for bit */
    pause_grade_setup((rfe_real_t)0.0);
    in = braking_on_grade(0);
    assert_int_equal(step(&in, &first), RFE_MG_PAUSED_BRAKE);
    for (k = 1; k <= 100; ++k) {
        in = braking_on_grade(k);
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
        assert_true((e.grade == first.grade) && (e.mass == first.mass));
    }
}

/* REQ-MG-006 rfe_mg_pause_grade_bits: without the accelerometer row (use_ax 0) the bits of
 * pause_grade are inert, not refused (the recommended preset's brake bit under a file that
 * sets use_ax 0): braking on the 0.05 rad climb with every bit and the change test off holds
 * the grade bit for bit through 2 s, as with pause_grade 0, and no sample reads ax (the
 * samples carry none). */
static void test_pause_grade_inert_without_ax(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t first;
    rfe_mass_grade_input_t in;
    int k;
    (void)state;
    setup_with(0u, 0u);
    mg.p.pause_grade = (rfe_real_t)RFE_MG_PAUSE_GRADE_ALL;
    mg.p.pause_grade_dv = (rfe_real_t)0.0;
    for (k = 0; k < 50; ++k) {
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        in.has &= ~RFE_MG_HAS_AX;
        assert_int_equal(step(&in, &e), RFE_OK);
    }
    for (k = 0; k <= 100; ++k) {
        in = braking_on_grade(k);
        in.has &= ~RFE_MG_HAS_AX;
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
        if (k == 0) {
            first = e;
        }
        assert_true((e.grade == first.grade) && (e.mass == first.mass));
        assert_true((mg.x[0] == in.v) && (mg.S[0] == mg.p.r_v)); /* the hold */
    }
}

/* One paused sample after a hold, from the state @p from: 1 when it moved the grade. */
static int pause_moves_grade(const rfe_mass_grade_t *from, const rfe_mass_grade_input_t *in,
                             rfe_status_t expect)
{
    rfe_mass_grade_estimate_t e;
    const rfe_real_t grade = from->x[2];
    mg = *from;
    assert_int_equal(step(in, &e), expect);
    assert_true(e.mass == from->x[1]);
    return (e.grade != grade) ? 1 : 0;
}

/* REQ-MG-006 rfe_mg_grade_in_pause (MC/DC): each pause kind learns the grade with its own
 * bit and holds without it (the other two bits set); the slip and the low-speed pauses hold
 * with every bit set; v still correlated with M (the first sample after an update) holds. */
static void test_pause_grade_decision(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t held;
    rfe_mass_grade_t learning;
    (void)state;
    pause_grade_setup((rfe_real_t)RFE_MG_PAUSE_GRADE_ALL);
    learning = mg;
    in = braking_on_grade(0);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    assert_true(e.grade == learning.x[2]); /* v_free 0: the hold */
    held = mg;                             /* S_Mv = 0 from here */
    in = braking_on_grade(1);
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_BRAKE), 1);
    held.p.pause_grade = (rfe_real_t)(RFE_MG_PAUSE_GRADE_SHIFT | RFE_MG_PAUSE_GRADE_CURVE);
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_BRAKE), 0);
    /* the shift: a new gear */
    in = braking_on_grade(1);
    in.has = (in.has & ~RFE_MG_HAS_BRAKE) | RFE_MG_HAS_GEAR;
    in.gear = 3;
    held.has_gear = 1u;
    held.gear = 2;
    held.brake_left = (rfe_real_t)0.0;
    held.p.pause_grade = (rfe_real_t)RFE_MG_PAUSE_GRADE_SHIFT;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_SHIFT), 1);
    held.p.pause_grade = (rfe_real_t)(RFE_MG_PAUSE_GRADE_BRAKE | RFE_MG_PAUSE_GRADE_CURVE);
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_SHIFT), 0);
    /* the curve */
    in = cornering((rfe_real_t)2.0);
    held.gear = 3;
    held.p.ay_max = (rfe_real_t)1.0;
    held.p.pause_grade = (rfe_real_t)RFE_MG_PAUSE_GRADE_CURVE;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_CURVE), 1);
    held.p.pause_grade = (rfe_real_t)(RFE_MG_PAUSE_GRADE_BRAKE | RFE_MG_PAUSE_GRADE_SHIFT);
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_CURVE), 0);
    /* the slip and the low speed: held with every bit */
    held.p.pause_grade = (rfe_real_t)RFE_MG_PAUSE_GRADE_ALL;
    in = slipping((rfe_real_t)22.0, (rfe_real_t)20.0);
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_SLIP), 0);
    in = cruise((rfe_real_t)1.0, (rfe_real_t)DT);
    in.ax = (rfe_real_t)0.5;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_NO_UPDATE_LOW_SPEED), 0);
}

/* REQ-MG-006 v uncorrelated with M (rfe_mg_v_free, MC/DC of its two conditions, and the
 * decision of rfe_mg_grade_in_pause reading it): decided from what the last accepted sample
 * did, never from the value of S_Mv (an update's S_Mv rounds to 0 in the Q31 twin's Q14 mass
 * row and not in double: FIXED_POINT.md "Mass and grade"). After an update (a step, status
 * 0: v_free 0) the next braked sample holds even with S_Mv forced to exactly 0; after a
 * paused sample (a step, status not 0: v_free 1) it learns; after a start on a sample that is
 * not paused (status 0, but a start: v_free 1) it learns too, as after a start on a braked
 * sample. */
static void test_v_free_decision(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t after_update;
    rfe_mass_grade_t from;
    (void)state;
    pause_grade_setup((rfe_real_t)RFE_MG_PAUSE_GRADE_BRAKE);
    /* (step, status 0): v_free 0, whatever S_Mv */
    assert_int_equal(mg.v_free, 0u);
    assert_true(mg.S[3] != (rfe_real_t)0.0); /* the cruise's updates correlate v with M */
    after_update = mg;
    after_update.S[3] = (rfe_real_t)0.0; /* what the Q31 twin's rounding can leave */
    in = braking_on_grade(0);
    assert_int_equal(pause_moves_grade(&after_update, &in, RFE_MG_PAUSED_BRAKE), 0);
    assert_true((mg.x[0] == in.v) && (mg.S[0] == mg.p.r_v)); /* the hold */
    /* (step, status paused): v_free 1, the next braked sample learns */
    assert_int_equal(mg.v_free, 1u);
    from = mg;
    in = braking_on_grade(1);
    assert_int_equal(pause_moves_grade(&from, &in, RFE_MG_PAUSED_BRAKE), 1);
    assert_int_equal(mg.v_free, 1u);
    /* (start, status 0): v_free 1 */
    assert_int_equal(rfe_mass_grade_restart(&mg), RFE_OK);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    assert_int_equal(mg.v_free, 1u);
    from = mg;
    in = braking_on_grade(0);
    assert_int_equal(pause_moves_grade(&from, &in, RFE_MG_PAUSED_BRAKE), 1);
    /* (start, status paused): v_free 1 */
    assert_int_equal(rfe_mass_grade_restart(&mg), RFE_OK);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    assert_int_equal(mg.v_free, 1u);
    from = mg;
    in = braking_on_grade(1);
    assert_int_equal(pause_moves_grade(&from, &in, RFE_MG_PAUSED_BRAKE), 1);
}

/* A braked sample on the 0.05 rad climb of braking_on_grade(k) with the car's ground speed
 * vx given and the wheels @p slip behind it: v = (1 - slip) vx (ABS: the wheels cycle
 * between locking and spinning up again). */
static rfe_mass_grade_input_t braking_slipping(int k, double slip)
{
    rfe_mass_grade_input_t in = braking_on_grade(k);
    in.vx = in.v;
    in.v = (rfe_real_t)((1.0 - slip) * (double)in.vx);
    in.has |= RFE_MG_HAS_VX;
    return in;
}

/* ABS-like cycling: 6 samples at 12 % slip, 4 at 1 %, over and over (the wheels' mean slip
 * passes below the gate's 5 % in every cycle, as the ABS logs' does). */
static double abs_cycle(int k)
{
    return ((k % 10) < 6) ? 0.12 : 0.01;
}

/* REQ-MG-006 the ABS gate of the grade from ax (§4.2, pause_grade_slip): with the brake bit
 * set, a brake pause whose wheels cycle as under ABS holds from its first slipping sample to
 * its end, bit for bit as with the bit off (x, S and every estimate), because the latch set
 * there stays through the samples whose slip falls back under the gate; without the gate
 * (pause_grade_slip = 0) the same samples swing the grade (each spin-up of the wheels, 2.2 m/s
 * in one period, read as acceleration, each relock as deceleration): its worst error over
 * the pause exceeds twice the held grade's (which a learning of the true grade could only
 * lower; measured 0.096 against 0.038 rad in float and double). On a steady brake (1 % slip, under the gate) the gate
 * changes nothing: bit for bit the run without it, which learns the grade (its error after
 * 2 s under a tenth of the start's, test_pause_grade_learns_grade_holds_mass's bound). */
static void test_abs_gate_holds_cycling_wheels(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t off[101];
    rfe_mass_grade_estimate_t ungated;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t start;
    rfe_mass_grade_t bit_off;
    double err0;
    double worst = 0.0;
    int k;
    (void)state;
    pause_grade_setup((rfe_real_t)RFE_MG_PAUSE_GRADE_BRAKE);
    assert_true(mg.p.pause_grade_slip == (rfe_real_t)0.05); /* the default gate */
    start = mg;
    /* the bit off: the hold of every sample */
    mg.p.pause_grade = (rfe_real_t)0.0;
    for (k = 0; k <= 100; ++k) {
        in = braking_slipping(k, abs_cycle(k));
        assert_int_equal(step(&in, &off[k]), RFE_MG_PAUSED_BRAKE);
    }
    bit_off = mg;
    /* the bit on, gated: the same, bit for bit */
    mg = start;
    for (k = 0; k <= 100; ++k) {
        in = braking_slipping(k, abs_cycle(k));
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
        assert_int_equal(mg.slip_latched, 1u);
        assert_memory_equal(&e, &off[k], sizeof(e));
    }
    assert_memory_equal(mg.x, bit_off.x, sizeof(mg.x));
    assert_memory_equal(mg.S, bit_off.S, sizeof(mg.S));
    /* the bit on, no gate: the cycling wheels drive the grade away */
    mg = start;
    mg.p.pause_grade_slip = (rfe_real_t)0.0;
    for (k = 0; k <= 100; ++k) {
        in = braking_slipping(k, abs_cycle(k));
        assert_int_equal(step(&in, &ungated), RFE_MG_PAUSED_BRAKE);
        assert_int_equal(mg.slip_latched, 0u);
        worst = fmax(worst, fabs((double)ungated.grade - PG_THETA));
    }
    err0 = fabs((double)off[100].grade - PG_THETA); /* the held grade's error, constant */
    printf("ABS cycling, brake bit: worst grade error %.3g rad without the gate, %.3g held\n",
           worst, err0);
    assert_true(worst > (2.0 * err0));
    /* a steady brake at 1 % slip: the gate never acts, the grade is learned */
    mg = start;
    for (k = 0; k <= 200; ++k) {
        in = braking_slipping(k, 0.01);
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
        assert_int_equal(mg.slip_latched, 0u);
        if (k == 0) {
            off[0] = e;
        }
    }
    bit_off = mg;
    mg = start;
    mg.p.pause_grade_slip = (rfe_real_t)0.0;
    for (k = 0; k <= 200; ++k) {
        in = braking_slipping(k, 0.01);
        assert_int_equal(step(&in, &ungated), RFE_MG_PAUSED_BRAKE);
    }
    assert_memory_equal(&ungated, &e, sizeof(e));
    assert_memory_equal(mg.S, bit_off.S, sizeof(mg.S));
    err0 = fabs((double)off[0].grade - PG_THETA);
    assert_true(fabs((double)e.grade - PG_THETA) < (0.1 * err0));
}

/* REQ-MG-006 the ABS gate's latch (rfe_mg_slip_latch, MC/DC with rfe_mg_slipping and the new
 * condition of rfe_mg_grade_in_pause): from a held brake pause (S_Mv = 0, the latch clear),
 * one braked sample at a time: slipping beyond the gate sets the latch and holds; each of
 * "vx given", "gate on" and "beyond" alone false leaves it clear and learns; the threshold
 * pause_grade_slip max(|vx|, v_min) strict (exact in binary: 0.0625 of 16 m/s = 1 m/s; at it
 * learned, one step of v below held), either sign; the latch already set holds a sample that
 * does not slip (the rest of the pause); a sample that is not paused clears it even while
 * the wheels slip; a start clears it. */
static void test_abs_gate_decision(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t held;
    (void)state;
    pause_grade_setup((rfe_real_t)RFE_MG_PAUSE_GRADE_BRAKE);
    in = braking_on_grade(0);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE); /* the hold: S_Mv = 0 from here */
    held = mg;
    held.p.pause_grade_slip = (rfe_real_t)0.0625;
    assert_int_equal(held.slip_latched, 0u);
    /* beyond: latched, held */
    in = braking_on_grade(1);
    in.vx = (rfe_real_t)16.0;
    in.v = (rfe_real_t)14.875; /* 1.125 m/s behind */
    in.has |= RFE_MG_HAS_VX;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_BRAKE), 0);
    assert_int_equal(mg.slip_latched, 1u);
    /* ahead as far: the same */
    in.v = (rfe_real_t)17.125;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_BRAKE), 0);
    assert_int_equal(mg.slip_latched, 1u);
    /* vx not given: learned */
    in.has &= ~RFE_MG_HAS_VX;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_BRAKE), 1);
    assert_int_equal(mg.slip_latched, 0u);
    in.has |= RFE_MG_HAS_VX;
    /* at the threshold (1 m/s behind): learned */
    in.v = (rfe_real_t)15.0;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_BRAKE), 1);
    assert_int_equal(mg.slip_latched, 0u);
    /* the gate off: learned */
    in.v = (rfe_real_t)14.875;
    held.p.pause_grade_slip = (rfe_real_t)0.0;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_BRAKE), 1);
    assert_int_equal(mg.slip_latched, 0u);
    /* already latched: a sample at no slip holds and keeps the latch */
    held.p.pause_grade_slip = (rfe_real_t)0.0625;
    held.slip_latched = 1u;
    in.v = in.vx;
    assert_int_equal(pause_moves_grade(&held, &in, RFE_MG_PAUSED_BRAKE), 0);
    assert_int_equal(mg.slip_latched, 1u);
    /* a sample that is not paused (the brake released, its delay over) clears the latch
     * even while the wheels slip beyond the gate (below the slip pause: slip_max off) */
    held.brake_left = (rfe_real_t)0.0;
    held.p.slip_max = (rfe_real_t)0.0;
    in = cruise((rfe_real_t)14.875, (rfe_real_t)DT);
    in.vx = (rfe_real_t)16.0;
    in.has |= RFE_MG_HAS_VX;
    mg = held;
    assert_int_equal(step(&in, &e), RFE_OK);
    assert_int_equal(mg.slip_latched, 0u);
    /* a start clears it: its sample, not paused, leaves it clear */
    mg = held;
    assert_int_equal(rfe_mass_grade_restart(&mg), RFE_OK);
    in.v = in.vx;
    assert_int_equal(step(&in, &e), RFE_OK);
    assert_int_equal(mg.slip_latched, 0u);
    /* a start on a braked sample whose wheels slip sets it at once */
    mg = held;
    assert_int_equal(rfe_mass_grade_restart(&mg), RFE_OK);
    in = braking_on_grade(1);
    in.vx = (rfe_real_t)16.0;
    in.v = (rfe_real_t)14.875;
    in.has |= RFE_MG_HAS_VX;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    assert_int_equal(mg.slip_latched, 1u);
}

/* REQ-MG-003 a bad ABS gate refused by the init, the estimator untouched (bit for bit). */
static void test_abs_gate_bad_param_leaves_state(void **state)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_t before;
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    (void)state;
    setup_with(0u, 1u);
    assert_int_equal(step(&in, &e), RFE_OK);
    before = mg;
    p = prm;
    p.pause_grade_slip = (rfe_real_t)1.5;
    assert_int_equal(rfe_mass_grade_init(&mg, &p), RFE_ERR_PARAM);
    assert_memory_equal(&mg, &before, sizeof(mg));
    p.pause_grade_slip = (rfe_real_t)-0.5;
    assert_int_equal(rfe_mass_grade_init(&mg, &p), RFE_ERR_PARAM);
    assert_memory_equal(&mg, &before, sizeof(mg));
    p = prm; /* the change test's speed likewise */
    p.pause_grade_dv = (rfe_real_t)10.5;
    assert_int_equal(rfe_mass_grade_init(&mg, &p), RFE_ERR_PARAM);
    assert_memory_equal(&mg, &before, sizeof(mg));
}

/* The change test's residual of braking_on_grade's samples 1..k (the first, 0, holds after
 * an update and clears the test) against a held grade @p theta, in double from the samples'
 * definition: sum of (v_j - v_(j-1)) - DT (ax - g sin theta); the first k at which it
 * leaves @p dv. */
static int expected_trip(double theta, double dv)
{
    const double ax = -2.0 + (9.81 * sin(PG_THETA));
    double d = 0.0;
    int k;
    for (k = 1; k < 1000; ++k) {
        d += (-2.0 * DT) - (DT * (ax - (9.81 * sin(theta))));
        if (fabs(d) > dv) {
            return k;
        }
    }
    return -1;
}

/* REQ-MG-006 the change test of the grade from ax in a pause (§4.2, pause_grade_dv, 0.2 m/s
 * by default; rfe_mg_change_tripped and rfe_mg_change_sums, MC/DC): braking on the 0.05 rad
 * climb with the brake bit. (a) The held grade right (set to the truth): the residual stays
 * at rounding level, every sample holds, the grade bit for bit the held one (no learning
 * noise added). (b) The held grade wrong (the cruise's, 0.012 rad: 0.038 rad off): the
 * samples hold until the residual, g (0.05 - 0.012) = 0.37 m/s^2 times t, passes 0.2 m/s
 * (expected_trip: sample 27 at DT 0.02 s; one sample either side allowed for the float32
 * sum's rounding, whose growth per sample, 7.5e-3 m/s, is 10^4 times its rounding; the
 * range asserted on expected_trip only guards the scene), then the test stays tripped
 * and the grade is learned to under a tenth of its error (the learning mode's bound,
 * test_pause_grade_learns_grade_holds_mass) within 2 s. (c) The test's speed is vx where
 * given: wheels 0.3 m/s behind a right vx (a slip onset of 1.5 %, under the ABS gate) hold,
 * the same wheels without vx trip at once. (d) pause_grade_dv 0: learned from the first
 * eligible sample. (e) A sample that is not paused clears the test. */
static void test_change_test(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t start;
    rfe_real_t held;
    double err0;
    int trip;
    int k;
    (void)state;
    pause_grade_setup((rfe_real_t)RFE_MG_PAUSE_GRADE_BRAKE);
    mg.p.pause_grade_dv = prm.pause_grade_dv;
    assert_true(mg.p.pause_grade_dv == (rfe_real_t)0.2); /* the default */
    start = mg;
    /* (a) the held grade right */
    mg.x[2] = (rfe_real_t)PG_THETA;
    for (k = 0; k <= 200; ++k) {
        in = braking_on_grade(k);
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
        assert_true(e.grade == (rfe_real_t)PG_THETA);
        assert_int_equal(mg.chg_on, 0u);
    }
    assert_true(fabs((double)mg.chg_d) < 1e-3);
    /* (b) the held grade wrong */
    mg = start;
    held = start.x[2];
    trip = expected_trip((double)held, 0.2);
    assert_true((trip > 20) && (trip < 35));
    err0 = fabs((double)held - PG_THETA);
    for (k = 0; k <= 250; ++k) {
        in = braking_on_grade(k);
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
        if (k < (trip - 1)) {
            assert_true((e.grade == held) && (mg.chg_on == 0u));
        }
        if (k > trip) {
            assert_int_equal(mg.chg_on, 1u);
        }
    }
    printf("change test: held grade error %.3g rad, tripped near sample %d, error after the "
           "pause %.3g rad\n", err0, trip, fabs((double)e.grade - PG_THETA));
    assert_true(fabs((double)e.grade - PG_THETA) < (0.1 * err0));
    /* (e) a sample that is not paused clears it */
    mg.brake_left = (rfe_real_t)0.0;
    in = cruise((rfe_real_t)15.0, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    assert_true((mg.chg_on == 0u) && (mg.chg_d == (rfe_real_t)0.0));
    /* (c) vx: the wheels 0.3 m/s behind a right vx hold; without vx they trip at once */
    mg = start;
    mg.x[2] = (rfe_real_t)PG_THETA;
    for (k = 0; k <= 100; ++k) {
        in = braking_on_grade(k);
        in.vx = in.v;
        in.v = (k == 0) ? in.v : (in.v - (rfe_real_t)0.3);
        in.has |= RFE_MG_HAS_VX;
        assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
        assert_true((e.grade == (rfe_real_t)PG_THETA) && (mg.chg_on == 0u));
        assert_int_equal(mg.slip_latched, 0u);
    }
    mg = start;
    mg.x[2] = (rfe_real_t)PG_THETA;
    in = braking_on_grade(0);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    in = braking_on_grade(1);
    in.v -= (rfe_real_t)0.3;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.chg_on == 1u) && (e.grade != (rfe_real_t)PG_THETA));
    /* (d) no test: the first eligible sample learns */
    mg = start;
    mg.p.pause_grade_dv = (rfe_real_t)0.0;
    in = braking_on_grade(0);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    assert_true(e.grade == held); /* after an update: the hold */
    in = braking_on_grade(1);
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.chg_on == 1u) && (e.grade != held));
}

/* REQ-MG-006 */
static void test_shift_and_low_speed_hold(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    int k;
    (void)state;
    setup_with(0u, 1u);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.has |= RFE_MG_HAS_GEAR;
    in.gear = 2;
    assert_int_equal(step(&in, &e), RFE_OK); /* the first gear given is no change */
    assert_int_equal(step(&in, &e), RFE_OK);
    in.gear = 3;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SHIFT);
    for (k = 1; k <= 50; ++k) {
        assert_int_equal(step(&in, &e), (k < 50) ? RFE_MG_PAUSED_SHIFT : RFE_OK);
    }
    /* a sample without a gear changes nothing; the next gear is compared with the last */
    in.has = RFE_MG_HAS_AX;
    assert_int_equal(step(&in, &e), RFE_OK);
    in.has |= RFE_MG_HAS_GEAR;
    assert_int_equal(step(&in, &e), RFE_OK);
    /* precedence: brake before shift before low speed */
    in.gear = 4;
    in.v = (rfe_real_t)1.0;
    in.brake = 1u;
    in.has |= RFE_MG_HAS_BRAKE;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    setup_with(0u, 1u);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.has |= RFE_MG_HAS_GEAR;
    in.gear = 1;
    assert_int_equal(step(&in, &e), RFE_OK);
    in.gear = 2;
    in.v = (rfe_real_t)1.0;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SHIFT);
    /* a gear that first appears after the start is no change either */
    setup_with(0u, 1u);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    in.has |= RFE_MG_HAS_GEAR;
    in.gear = 3;
    assert_int_equal(step(&in, &e), RFE_OK);
    in.gear = 4;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_SHIFT);
    /* below v_min: held with status 2; at v_min: updated */
    setup_with(0u, 1u);
    in = cruise(prm.v_min * (rfe_real_t)0.99, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_NO_UPDATE_LOW_SPEED); /* also on the first sample */
    assert_true(e.mass == prm.m0);
    assert_int_equal(step(&in, &e), RFE_NO_UPDATE_LOW_SPEED);
    assert_true(e.mass == prm.m0);
    in.v = prm.v_min;
    assert_int_equal(step(&in, &e), RFE_OK);
}

/* REQ-MG-007 */
static void test_adaptation_as_specified(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t plain;
    rfe_mass_grade_t before;
    double d;
    double qs;
    double lam;
    double Pm[9];
    double Pp[9];
    int k;
    (void)state;
    setup_with(1u, 0u);
    prm.t_adapt = (rfe_real_t)0.0; /* every step */
    assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
    for (k = 0; k < 3; ++k) {
        in = cruise((rfe_real_t)20.0 + (rfe_real_t)0.02 * (rfe_real_t)k, (rfe_real_t)DT);
        assert_int_equal(step(&in, &e), RFE_OK);
    }
    /* the same step without the adaptation (its q_mv still in Q) is the posterior the
     * adaptation scales: lambda_u = 1/2 |q_s - D| / (q_s + D), q_s = q_mv dt,
     * D = (M - M_a)^2; q_mv, P_MM and the mass row scale by lambda_u (P_MM once) */
    before = mg;
    plain = mg;
    plain.p.adaptive = 0u;
    in = cruise((rfe_real_t)20.1, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    assert_int_equal(rfe_mass_grade_step(&plain, &in, &e), RFE_OK);
    d = ((double)plain.x[1] - (double)before.m_adapt) * ((double)plain.x[1] - (double)before.m_adapt);
    qs = (double)before.q_mv * DT;
    lam = 0.5 * fabs(qs - d) / (qs + d);
    assert_true((lam >= 0.0) && (lam <= 0.5));
    assert_close(mg.q_mv, lam * (double)before.q_mv, 0.0, 1e3 * TOL_EXACT, "q_mv");
    /* P' = S' S'^T of the 3 x 4 triangularisation against lambda_u times plain's P (D from
     * the rounded posterior mass: 1e3 TOL_EXACT, as the textbook form's scaling was); the
     * entries off the mass row unchanged up to the reflections' roundings (scaled by the
     * elements' sds sqrt(P_ii P_jj): 8 TOL_EXACT) */
    cov_of_factor(mg.S, Pm);
    cov_of_factor(plain.S, Pp);
    assert_close(Pm[4], lam * Pp[4], 0.0, 1e3 * TOL_EXACT, "P_MM");
    assert_close(Pm[1], lam * Pp[1], 0.0, 1e3 * TOL_EXACT, "P_vM");
    assert_close(Pm[5], lam * Pp[5], 1e3 * TOL_EXACT * sqrt(Pp[4] * Pp[8]), 0.0, "P_Mth");
    assert_close(Pm[0], Pp[0], 8.0 * TOL_EXACT * Pp[0], 0.0, "P_vv");
    assert_close(Pm[8], Pp[8], 8.0 * TOL_EXACT * Pp[8], 0.0, "P_thth");
    assert_close(Pm[2], Pp[2], 8.0 * TOL_EXACT * sqrt(Pp[0] * Pp[8]), 0.0, "P_vth");
    assert_true(mg.m_adapt == mg.x[1]);
    /* the end: q_mv at most mv_stop q_mc^2 after the shrink becomes 0, for good */
    mg.q_mv = prm.mv_stop * (prm.q_mc * prm.q_mc) * (rfe_real_t)1.9;
    in = cruise((rfe_real_t)20.12, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    assert_true(e.q_mv == (rfe_real_t)0.0);
    before = mg;
    in = cruise((rfe_real_t)20.14, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    assert_true((e.q_mv == (rfe_real_t)0.0) && (mg.m_adapt == before.m_adapt));
    /* q_s and D both 0 (q_mv underflowed, the mass did not move): lambda_u = 1/2, its
     * limit, not 0/0 */
    mg.p.mv_stop = (rfe_real_t)0.0;
    mg.q_mv = (rfe_real_t)1e-40;
    mg.adapt_elapsed = (rfe_real_t)-DT; /* the period's sum is 0 after this step's dt */
    mg.p.t_adapt = (rfe_real_t)-1.0;
    mg.m_adapt = (rfe_real_t)-1.0;      /* replaced below by the posterior mass */
    before = mg;
    plain = mg;
    plain.p.adaptive = 0u;
    in = cruise((rfe_real_t)20.16, (rfe_real_t)DT);
    assert_int_equal(rfe_mass_grade_step(&plain, &in, &e), RFE_OK);
    mg.m_adapt = plain.x[1]; /* D = 0 */
    assert_int_equal(step(&in, &e), RFE_OK);
    cov_of_factor(mg.S, Pm);
    cov_of_factor(plain.S, Pp);
    assert_close(Pm[4], 0.5 * Pp[4], 0.0, 8.0 * TOL_EXACT, "P_MM halved");
    assert_true(mg.q_mv == (rfe_real_t)0.5 * (rfe_real_t)1e-40);
    (void)before;
}

/* REQ-MG-007 */
static void test_adaptation_period(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_real_t q0;
    int k;
    (void)state;
    setup_with(1u, 0u); /* t_adapt = 1 s: the 50th update at 50 Hz adapts */
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    q0 = e.q_mv;
    for (k = 1; k <= 50; ++k) {
        in = cruise((rfe_real_t)20.0 + (rfe_real_t)0.01 * (rfe_real_t)k, (rfe_real_t)DT);
        assert_int_equal(step(&in, &e), RFE_OK);
        if (k < 50) {
            assert_true(e.q_mv == q0);
        }
    }
    assert_true(e.q_mv <= (rfe_real_t)0.5 * q0);
    /* a hold restarts the period */
    in.brake = 1u;
    in.has |= RFE_MG_HAS_BRAKE;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    assert_true(mg.adapt_elapsed == (rfe_real_t)0.0);
    assert_true(mg.m_adapt == e.mass);
}

/* REQ-MG-008 */
static void test_factorisation_failures_leave_the_state_untouched(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t before;
    int k;
    (void)state;
    setup_with(0u, 1u);
    for (k = 0; k < 3; ++k) {
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        assert_int_equal(step(&in, &e), RFE_OK);
    }
    /* a factor holding a NaN (a corrupted state): its points are not finite, the
     * triangularisation refuses them */
    mg.S[4] = (rfe_real_t)NAN;
    before = mg;
    assert_int_equal(step(&in, &e), RFE_ERR_NONFINITE);
    assert_memory_equal(&mg, &before, sizeof(mg));
    /* a factor whose points overflow the model: an error, never a NaN */
    setup_with(0u, 1u);
    assert_int_equal(step(&in, &e), RFE_OK);
    mg.S[4] = HUGE_REAL; /* sqrt(n + lambda) S_MM overflows: points at +-Inf kg */
    before = mg;
    assert_int_equal(step(&in, &e), RFE_ERR_NONFINITE);
    assert_memory_equal(&mg, &before, sizeof(mg));
    /* a negative centre weight (alpha < 1) is a downdate of the factor: -1e6 leaves the
     * predicted P indefinite, the downdate fails */
    setup_with(0u, 1u);
    assert_int_equal(step(&in, &e), RFE_OK);
    mg.wc0 = (rfe_real_t)-1e6;
    mg.sqrt_wc0 = (rfe_real_t)1e3;
    before = mg;
    assert_int_equal(step(&in, &e), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_memory_equal(&mg, &before, sizeof(mg));
}

/* REQ-MG-008: an update whose factorisations succeed but whose mean overflows is refused.
 * A factor (set by hand: a corrupted state) correlating the mass with the speed by a
 * quarter of the largest real and a speed innovation of 10 m/s: the speed row's gain moves
 * the mass by about ten times S_Mv, past the largest real, while every factorisation meets
 * finite entries; the update refuses the non-finite mean (mass_grade_flt.c update). The
 * step's check of the outputs' sds would refuse this case too (the huge S_Mv leaves sd_mass
 * past the square root of the largest real): the mean's check is the one that does not
 * depend on that. */
static void test_update_overflowing_the_mean_refused(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t before;
    (void)state;
    setup_with(0u, 0u);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    in.has = 0u; /* the speed row only */
    assert_int_equal(step(&in, &e), RFE_OK);
    mg.S[0] = (rfe_real_t)1.0;
    mg.S[3] = (rfe_real_t)(HUGE_REAL / 4.0); /* S_Mv */
    before = mg;
    in.v = (rfe_real_t)30.0;
    assert_int_equal(step(&in, &e), RFE_ERR_NONFINITE);
    assert_memory_equal(&mg, &before, sizeof(mg));
}

/* REQ-MG-008. Found by fuzz_mass_grade_f32: valid parameters (finite, > 0) whose squares
 * overflow the number type made the start report sd_v = Inf with status 0. A start or a hold
 * that overflows is now refused like an update that does. */
static void test_start_and_hold_overflow_refused(void **state)
{
    /* the square of OVER_SQ overflows the type (sqrt(REAL_MAX) is 1.8e19 / 1.3e154) */
#if defined(RFE_REAL_DOUBLE)
    const rfe_real_t over_sq = (rfe_real_t)1e160;
#else
    const rfe_real_t over_sq = (rfe_real_t)1e30f;
#endif
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_estimate_t e0;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t before;
    int k;
    (void)state;
    /* the start: P_vv = r_v^2, P_MM = sd_m0^2, P_thth = sd_theta0^2, q_mv = q_mv0^2 */
    for (k = 0; k < 4; ++k) {
        memset(&prm, 0, sizeof(prm));
        assert_int_equal(rfe_mass_grade_params_default(&prm), RFE_OK);
        prm.adaptive = 1u;
        if (k == 0) {
            prm.r_v = over_sq;
        } else if (k == 1) {
            prm.sd_m0 = over_sq;
        } else if (k == 2) {
            prm.sd_theta0 = over_sq;
        } else {
            prm.q_mv0 = over_sq;
        }
        assert_int_equal(rfe_mass_grade_params_validate(&prm), RFE_OK);
        memset(&mg, 0, sizeof(mg));
        assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
        assert_int_equal(rfe_mass_grade_get(&mg, &e0), RFE_OK);
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        before = mg;
        assert_int_equal(step(&in, &e), RFE_ERR_NONFINITE);
        assert_memory_equal(&mg, &before, sizeof(mg));
        assert_int_equal(e.status, RFE_ERR_NONFINITE);
        assert_true(e.mass == e0.mass && e.sd_v == e0.sd_v && e.sd_mass == e0.sd_mass);
    }
    /* the hold: P_thth grows by q_theta^2 dt at every held sample */
    memset(&prm, 0, sizeof(prm));
    assert_int_equal(rfe_mass_grade_params_default(&prm), RFE_OK);
    prm.q_theta = over_sq;
    prm.q_theta_hi = (rfe_real_t)0.0; /* §4.7 off: q_theta_hi >= q_theta is a rule */
    memset(&mg, 0, sizeof(mg));
    assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    in.has |= RFE_MG_HAS_BRAKE;
    in.brake = 1u;
    before = mg;
    assert_int_equal(step(&in, &e), RFE_ERR_NONFINITE);
    assert_memory_equal(&mg, &before, sizeof(mg));
    assert_true(isfinite((double)e.sd_grade));
    /* the update: a speed noise whose factor's square overflows in the speed row's rotation
     * (sqrt(S_00^2 + r_v^2) = Inf would scale S's column 0 to 0 and report sd_v = 0 with
     * status 0): refused */
    memset(&prm, 0, sizeof(prm));
    assert_int_equal(rfe_mass_grade_params_default(&prm), RFE_OK);
    prm.q_v = over_sq;
    prm.use_ax = 0u; /* the speed row alone (with ax the points' drag overflows first) */
    memset(&mg, 0, sizeof(mg));
    assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK);
    before = mg;
    assert_int_equal(step(&in, &e), RFE_ERR_NONFINITE);
    assert_memory_equal(&mg, &before, sizeof(mg));
    assert_true(e.sd_v == prm.r_v);
}

/* REQ-MG-008. Found by fuzz_mass_grade_f32: with a rolling radius of 4.5e-12 m (valid: > 0)
 * the torque term T/r spreads the predicted speeds by ~1e10 m/s, and the textbook form's
 * P- - K S K^T left P_vv = -2.7e8 with status 0 (sd_v reported 0). The square-root form
 * cannot lose a variance: every accepted update leaves a factor with a nonnegative diagonal
 * (P = S S^T), and a refused one leaves the estimator untouched. */
static void test_update_losing_a_variance_refused(void **state)
{
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t before;
    rfe_status_t st;
    int k;
    (void)state;
    memset(&prm, 0, sizeof(prm));
    assert_int_equal(rfe_mass_grade_params_preset(&prm, RFE_MG_TRUCK, RFE_MG_SEED), RFE_OK);
    prm.R = (rfe_real_t)4.5e-12;
    memset(&mg, 0, sizeof(mg));
    assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
    memset(&in, 0, sizeof(in));
    in.dt = (rfe_real_t)0.2;
    in.v = (rfe_real_t)11.6;
    in.torque = (rfe_real_t)-3.125;
    assert_int_equal(step(&in, &e), RFE_OK);
    for (k = 0; k < 20; ++k) {
        in.v = (rfe_real_t)(11.6 - 0.01 * k);
        before = mg;
        st = step(&in, &e);
        if (st == RFE_OK) {
            /* an accepted update: a factor with a nonnegative diagonal, finite sds */
            assert_true(mg.S[0] >= 0 && mg.S[4] >= 0 && mg.S[8] >= 0);
            assert_true(isfinite((double)e.sd_v) && isfinite((double)e.sd_mass));
        } else {
            assert_true(st == RFE_ERR_NOT_POSITIVE_DEFINITE || st == RFE_ERR_NONFINITE);
            assert_memory_equal(&mg, &before, sizeof(mg));
        }
    }
}

/* REQ-MG-008 */
static void test_innovation_covariance_not_positive(void **state)
{
    /* alpha 1, beta 2, kappa 0 (§3) and their roots */
    const rfe_mg_weights_t w = {(rfe_real_t)0.0, (rfe_real_t)2.0, (rfe_real_t)(1.0 / 6.0),
                                (rfe_real_t)1.4142135623730951, (rfe_real_t)0.408248290463863,
                                (rfe_real_t)1.7320508075688772};
    const rfe_mg_weights_t wneg = {(rfe_real_t)0.0, (rfe_real_t)-1e6, (rfe_real_t)(1.0 / 6.0),
                                   (rfe_real_t)1e3, (rfe_real_t)0.408248290463863,
                                   (rfe_real_t)1.7320508075688772};
    rfe_real_t chi[RFE_MG_PTS * RFE_MG_N] = {(rfe_real_t)0.0};
    rfe_real_t Z[RFE_MG_PTS] = {(rfe_real_t)0.0};
    const rfe_real_t r[RFE_MG_Z_MAX] = {(rfe_real_t)0.0, (rfe_real_t)0.0};
    const rfe_real_t y[RFE_MG_Z_MAX] = {(rfe_real_t)1.0, (rfe_real_t)1.0};
    rfe_real_t x[RFE_MG_N] = {(rfe_real_t)1.0, (rfe_real_t)2.0, (rfe_real_t)3.0};
    rfe_real_t S[RFE_MG_N * RFE_MG_N] = {(rfe_real_t)0.0};
    rfe_real_t x0[RFE_MG_N];
    rfe_real_t S0[RFE_MG_N * RFE_MG_N];
    rfe_real_t e_ax = (rfe_real_t)7.0;
    size_t i;
    (void)state;
    memcpy(x0, x, sizeof(x));
    memcpy(S0, S, sizeof(S));
    /* no noise and every point measures the same: the speed row's innovation sd
     * sqrt(S_00^2 + r_v^2) = 0, and the ax row's (its array's first row all 0) */
    assert_int_equal(rfe_mg_correct_speed(r[0], y[0], x, S), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_mg_correct(chi, Z, &w, r, y, x, S, &e_ax), RFE_ERR_NOT_POSITIVE_DEFINITE);
    /* the ax row's points spread, its centre weight -1e6: the downdate by 1e3 (Z_0 - z)
     * leaves the innovation variance negative */
    for (i = 0u; i < (size_t)RFE_MG_PTS; ++i) {
        Z[i] = (rfe_real_t)i;
    }
    assert_int_equal(rfe_mg_correct(chi, Z, &wneg, r, y, x, S, &e_ax), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_memory_equal(x, x0, sizeof(x));
    assert_memory_equal(S, S0, sizeof(S));
    assert_true(e_ax == (rfe_real_t)7.0); /* §4.8's innovation is written only on success */
}

/* REQ-MG-008. The failure the square-root form avoids (MASS_GRADE_RESULTS.md "Why the
 * square-root form", make mass-grade-textbook): car_flat_cruise's cruise (from row 1500, 30 s
 * at constant speed) played four times back to back, 600 s without excitation, with the
 * process noise 1/1000 to 1/40 000 of the preset's (q_mc = 1e-3 kg/sqrt(s), q_theta = 1e-7
 * rad/sqrt(s), q_v = 1e-6 m/s/sqrt(s), the Q31 twin's test_square_root_form_stays_definite).
 * The speed then fixes one combination of M and theta, so P's (M, theta) block tends to
 * singular: the textbook form in float32 lost definiteness at step 10,774 (UKF + ax) and
 * 15,719 (UKF) and stayed frozen (status 21). The square-root form must run every step to the
 * end, in both builds, with P = S S^T positive definite (its Cholesky in double succeeds:
 * S's diagonal > 0 is the same statement) and the mass's sd no larger than at the start
 * (P_MM <= sd_m0^2 + q_mc^2 t = 500^2 + 6e-4 kg^2: with this noise the filter can only learn). */
static void test_square_root_form_stays_definite(void **state)
{
    static const uint32_t use_ax[2] = {1u, 0u};
    test_table_t log;
    size_t c;
    (void)state;
    memset(&log, 0, sizeof(log));
    assert_int_equal(test_table_load("scenarios/mass_grade/car_flat_cruise.csv", &log), 0);
    assert_true(log.n_rows > 1600u);
    for (c = 0u; c < 2u; ++c) {
        size_t steps = 0u;
        int rep;
        assert_int_equal(rfe_mass_grade_params_default(&prm), RFE_OK);
        prm.adaptive = 0u;
        prm.use_ax = use_ax[c];
        prm.q_mc = (rfe_real_t)1e-3;
        prm.q_theta = (rfe_real_t)1e-7;
        prm.q_v = (rfe_real_t)1e-6;
        assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
        for (rep = 0; rep < 4; ++rep) {
            size_t k;
            for (k = 1500u; k < log.n_rows; ++k) {
                rfe_mass_grade_input_t in;
                rfe_mass_grade_estimate_t e;
                rfe_status_t st;
                mg_input_of(&log, k, (double)prm.R, &in);
                if (k == 1500u) { /* the seam: the log's own period, the speed continuous */
                    in.dt = (rfe_real_t)(test_table_get(&log, 1u, "t") -
                                         test_table_get(&log, 0u, "t"));
                }
                st = step(&in, &e);
                if (st != RFE_OK) {
                    fail_msg("use_ax %u: status %d at step %zu", (unsigned)use_ax[c], (int)st,
                             steps);
                }
                assert_true((mg.S[0] > 0) && (mg.S[4] > 0) && (mg.S[8] > 0));
                assert_true(e.sd_mass <= prm.sd_m0 * (rfe_real_t)1.000001);
                ++steps;
            }
        }
        assert_true(steps > 30000u); /* every step of the 600 s ran */
    }
    test_table_free(&log);
}

/* A sigma point through the linear f(x) = F x. */
static void linear_f(const double F[][RFE_N_MAX], const rfe_real_t *in, rfe_real_t *out)
{
    size_t r;
    size_t c;
    for (r = 0u; r < 3u; ++r) {
        double s = 0.0;
        for (c = 0u; c < 3u; ++c) {
            s += F[r][c] * (double)in[c];
        }
        out[r] = (rfe_real_t)s;
    }
}

/* REQ-MG-009 */
static void test_ukf_is_the_kalman_filter_on_a_linear_problem(void **state)
{
    /* The unscented transform propagates mean and covariance exactly through a linear map
     * (the points match the first two moments, and chi_0 - mean = 0 so the beta term adds
     * nothing): with linear f and h the UKF is the Kalman filter. The problem looks like the
     * estimator's (speed, mass in kg, grade in rad: a speed that falls with the mass and
     * the grade), with the ax row's measurement a linear mix of the three. 40 steps, each
     * compared, the UKF's P = S S^T formed in double. Tolerance TOL_KF relative to each
     * element's scale sqrt(P_ii P_jj) (x: sqrt P_ii): double, the textbook filter (Joseph
     * form) and the square-root UKF differ in rounding only, ~1e-13 after 40 steps of O(10)
     * operations on condition ~1e8 -> 1e-10 (seen 1.9e-13); float32: the UKF's rounding of
     * 6e-8 on a factor with entries up to 500 and a correlation between the mass and the
     * speed near 1 (condition ~1e8 of P, 1e4 of S): ~1e3 ulp of the scale -> 1e-3 (seen
     * 1.2e-4; the textbook form's P- - K S K^T showed 3.1e-4). */
#if defined(RFE_REAL_DOUBLE)
    const double tol_kf = 1e-10;
#else
    const double tol_kf = 1e-3;
#endif
    static const double F[RFE_N_MAX][RFE_N_MAX] = {
        {1.0, -1e-5, -0.2}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
    static const double H[RFE_N_MAX][RFE_N_MAX] = {{1.0, 0.0, 0.0}, {0.0, 2e-4, 9.81}};
    /* alpha 1, beta 2, kappa 0 (§3) and their roots */
    const rfe_mg_weights_t w = {(rfe_real_t)0.0, (rfe_real_t)2.0, (rfe_real_t)(1.0 / 6.0),
                                (rfe_real_t)1.4142135623730951, (rfe_real_t)0.408248290463863,
                                (rfe_real_t)1.7320508075688772};
    const double q[3] = {4e-4 * DT, 1.0 * DT, 1.6e-5 * DT};
    const double r2[2] = {0.0025, 0.01};
    kf_ref_t ref;
    rfe_real_t x[RFE_MG_N] = {(rfe_real_t)20.0, (rfe_real_t)1500.0, (rfe_real_t)0.0};
    rfe_real_t S[RFE_MG_N * RFE_MG_N] = {(rfe_real_t)0.0};
    double P[9];
    double xt[3] = {20.0, 2000.0, 0.03};
    size_t i;
    size_t j;
    int k;
    (void)state;
    memset(&ref, 0, sizeof(ref));
    ref.n = 3u;
    ref.m = 2u;
    S[0] = (rfe_real_t)0.05;
    S[4] = (rfe_real_t)500.0;
    S[8] = (rfe_real_t)0.05;
    for (i = 0u; i < 3u; ++i) {
        ref.x[i] = (double)x[i];
        ref.P[i][i] = (double)S[(i * 3u) + i] * (double)S[(i * 3u) + i];
        ref.Q[i][i] = q[i];
    }
    ref.R[0][0] = r2[0];
    ref.R[1][1] = r2[1];
    for (k = 0; k < 40; ++k) {
        rfe_real_t chi[RFE_MG_PTS * RFE_MG_N];
        rfe_real_t X[RFE_MG_PTS * RFE_MG_N];
        rfe_real_t Z[RFE_MG_PTS];
        rfe_real_t e_ax = (rfe_real_t)0.0;
        rfe_real_t sq[RFE_MG_N] = {(rfe_real_t)sqrt(q[0]), (rfe_real_t)sqrt(q[1]),
                                   (rfe_real_t)sqrt(q[2])};
        rfe_real_t rr[RFE_MG_Z_MAX] = {(rfe_real_t)sqrt(r2[0]), (rfe_real_t)sqrt(r2[1])};
        rfe_real_t y[RFE_MG_Z_MAX];
        const size_t nz = (k % 2 == 0) ? 2u : 1u; /* the 2-row update and the speed row alone */
        double xn[3];
        /* a deterministic "truth" with a wobble, measured */
        for (i = 0u; i < 3u; ++i) {
            xn[i] = F[i][0] * xt[0] + F[i][1] * xt[1] + F[i][2] * xt[2];
        }
        memcpy(xt, xn, sizeof(xn));
        y[0] = (rfe_real_t)(xt[0] + 0.03 * sin(0.7 * k));
        y[1] = (rfe_real_t)(H[1][1] * xt[1] + H[1][2] * xt[2] + 0.05 * cos(1.3 * k));
        /* the UKF: points through f, moments, new points through h, correction */
        rfe_mg_sigma_points(x, S, w.sqrt_c, chi);
        for (i = 0u; i < (size_t)RFE_MG_PTS; ++i) {
            linear_f(F, &chi[i * 3u], &X[i * 3u]);
        }
        assert_int_equal(rfe_mg_predict(X, &w, sq, x, S), RFE_OK);
        rfe_mg_sigma_points(x, S, w.sqrt_c, chi);
        for (i = 0u; i < (size_t)RFE_MG_PTS; ++i) {
            const rfe_real_t *c = &chi[i * 3u];
            Z[i] = (rfe_real_t)(H[1][1] * (double)c[1] + H[1][2] * (double)c[2]); /* the ax row */
        }
        if (nz == 2u) {
            assert_int_equal(rfe_mg_correct(chi, Z, &w, rr, y, x, S, &e_ax), RFE_OK);
        } else {
            assert_int_equal(rfe_mg_correct_speed(rr[0], y[0], x, S), RFE_OK);
        }
        cov_of_factor(S, P);
        /* the Kalman filter */
        ref.m = nz;
        kf_ref_predict(&ref, F);
        kf_ref_update(&ref, H, y);
        for (i = 0u; i < 3u; ++i) {
            char what[64];
            snprintf(what, sizeof(what), "x[%zu] step %d", i, k);
            assert_close(x[i], ref.x[i], tol_kf * sqrt(ref.P[i][i]), 0.0, what);
            for (j = 0u; j < 3u; ++j) {
                snprintf(what, sizeof(what), "P[%zu][%zu] step %d", i, j, k);
                assert_close(P[(i * 3u) + j], ref.P[i][j],
                             tol_kf * sqrt(ref.P[i][i] * ref.P[j][j]), 0.0, what);
            }
        }
    }
    /* it learned something: the mass's sd fell by more than half */
    assert_true(ref.P[1][1] < 0.25 * 250000.0);
}

/* The conversion to the fixed-point twin's formats from this build's reals
 * (rfe/component/params_conv.h): each value times 2^q rounded (values of the car preset
 * exact in float as in double: integers, halves, powers of two times small integers, or
 * rounded to within 1 LSB), the pressure in MPa; a value beyond its format refused
 * (RFE_ERR_RANGE), an invalid set (RFE_ERR_PARAM), NULL; the output untouched on error. */
/* REQ-MG-010 */
static void test_params_to_q31(void **state)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_params_q31_t before;
    (void)state;
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_OK);
    assert_int_equal(q.m0, (rfe_fix_t)(1830 * 16384));   /* Q14 */
    assert_int_equal(q.sd_m0, (rfe_fix_t)(500 * 16384));
    assert_int_equal(q.theta_max, (rfe_fix_t)((double)p.theta_max * 536870912.0 + 0.5)); /* Q29 */
    assert_int_equal(q.dt_max, (rfe_fix_t)1073741824);   /* 1 s, Q30 */
    assert_int_equal(q.ut_beta, (rfe_fix_t)(2 << 28));   /* Q28 */
    assert_true(labs((long)q.p_brake_on - 3355443L) <= 1L); /* 0.1 MPa, Q25 */
    assert_true(labs((long)q.slip_max - 53687091L) <= 1L);  /* 0.05, Q30 */
    assert_int_equal(q.use_ax, p.use_ax);
    memset(&q, 0x5A, sizeof q);
    before = q;
    p.m_max = (rfe_real_t)200000.0; /* beyond Q14's 131072 kg */
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_ERR_RANGE);
    p.m_max = (rfe_real_t)-1.0;
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_ERR_PARAM);
    assert_memory_equal(&q, &before, sizeof q);
    assert_int_equal(rfe_mass_grade_params_to_q31(NULL, &q), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, NULL), RFE_ERR_NULL);
}

/* §4.8 the model-mismatch monitor on a rigid model: mass and grade known to 1e-3 kg and
 * 1e-6 rad (their sd and walks that small), a cruise at 20 m/s whose torque is exactly the
 * model's resistances at m0 on a level road, so the model predicts ax = 0 (the drag's
 * curvature over the points' sd_v ~ 0.05 m/s adds ~5e-7 m/s^2). With the accelerometer
 * reading a bias b the ax row's innovation is b and its sd s = sqrt(r_ax^2 + P_zz), P_zz /
 * r_ax^2 < 1e-5 (the points' spread in z: dz/dv ~ 0.008 s^-1 times sd_v), and the update
 * barely moves the state (gain ~ P_xz / s^2 ~ 1e-5 on v, ~1e-8 on M), so the normalised
 * innovation stays e0 = b / r_ax to a relative 1e-4. The EMA over k updates is then
 * e0 (1 - (1 - a)^k), a = dt / mm_tau = 0.002; with e0 = 2 mm_e (b = 0.06, r_ax 0.1, mm_e
 * 0.3) it crosses mm_e at k* = ln(1/2) / ln(1 - a) = 346.2: the first flagged update is the
 * 347th (sample 347: sample 0 starts the filter). At k = 346 and 347 the EMA is 0.29980 and
 * 0.30040, 2.0e-4 and 4.0e-4 from mm_e, twice the 1e-4 x 0.6 the innovation's deviation
 * and float's rounding (350 steps of 6e-8) can move it; the test allows one sample either
 * way all the same (clear through 345, set from 348) and checks the EMA against the closed
 * form within 1e-3 of e0 on every sample. */
static void mismatch_drive(rfe_real_t bias, int monitor_on, int steps, int *first_flag,
                           double *worst_dev, double *largest)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_input_t in;
    rfe_mass_grade_estimate_t e;
    const double dt = DT;
    const double v = 20.0;
    double f;
    int k;
    memset(&p, 0, sizeof(p)); /* the double struct's padding: zeroed before filling */
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    p.sd_m0 = (rfe_real_t)1e-3;
    p.q_mc = (rfe_real_t)1e-3;
    p.sd_theta0 = (rfe_real_t)1e-6;
    p.q_theta = (rfe_real_t)1e-6;
    p.q_theta_hi = (rfe_real_t)0.0;
    p.pause_grade = (rfe_real_t)0.0;
    if (monitor_on == 0) {
        p.mm_e = (rfe_real_t)0.0; /* §4.8: mm_e 0 switches the flag off, the EMA still runs */
    }
    assert_int_equal(rfe_mass_grade_init(&mg, &p), RFE_OK);
    f = (double)p.fc + ((double)p.fr * v);
    memset(&in, 0, sizeof(in));
    in.v = (rfe_real_t)v;
    in.torque = (rfe_real_t)((double)p.R * (((double)p.m0 * (double)p.g * f) +
                                            (0.5 * (double)p.rho * (double)p.cd *
                                             (double)p.area * v * v)));
    in.has = RFE_MG_HAS_AX;
    *first_flag = -1;
    *worst_dev = 0.0;
    *largest = 0.0;
    for (k = 0; k < steps; ++k) {
        const double e0 = (double)bias / (double)p.r_ax;
        const double want = e0 * (1.0 - pow(1.0 - (dt / (double)p.mm_tau), (double)k));
        in.dt = (rfe_real_t)dt;
        /* a zero-mean dither of +-r_ax on the unbiased drive, a bias alone on the other */
        in.ax = (bias == (rfe_real_t)0.0) ? (rfe_real_t)(((k % 2) == 0) ? 0.1 : -0.1) : bias;
        assert_int_equal(rfe_mass_grade_step(&mg, &in, &e), RFE_OK);
        if ((e.mismatch != 0u) && (*first_flag < 0)) {
            *first_flag = k;
        }
        if (bias != (rfe_real_t)0.0) {
            *worst_dev = fmax(*worst_dev, fabs((double)e.e_ax - want) / e0);
        }
        *largest = fmax(*largest, fabs((double)e.e_ax));
        /* the flag is the EMA against mm_e, on every sample, while the monitor is on */
        assert_int_equal(e.mismatch, ((monitor_on != 0) && (fabs((double)e.e_ax) > (double)p.mm_e))
                                         ? 1u : 0u);
    }
}

/* REQ-MG-003 */
static void test_mismatch_flag_after_the_derived_time(void **state)
{
    int first = 0;
    double dev = 0.0;
    double largest = 0.0;
    (void)state;
    mismatch_drive((rfe_real_t)0.06, 1, 600, &first, &dev, &largest);
    assert_true((first >= 346) && (first <= 348));
    assert_true(dev < 1e-3); /* the closed form e0 (1 - (1 - a)^k), header comment */
    /* after 599 updates 0.6 (1 - 0.998^599) = 0.4192; dev bounds the rest */
    assert_true(fabs(largest - 0.4192) < 1e-3);
    /* unbiased (ax dithering +-r_ax about the prediction 0): the EMA of e_k = +-1 stays
     * within a / (2 - a) ~ 1e-3 of 0 (plus the start's 0.002 step), far below mm_e */
    mismatch_drive((rfe_real_t)0.0, 1, 2000, &first, &dev, &largest);
    assert_int_equal(first, -1);
    assert_true(largest < 0.01);
    /* the monitor off (mm_e 0): the same biased drive, whose EMA runs past 0.3 as above, never
     * flags; the EMA itself is the same closed form (it is reported, only the flag is off) */
    mismatch_drive((rfe_real_t)0.06, 0, 600, &first, &dev, &largest);
    assert_int_equal(first, -1);
    assert_true(dev < 1e-3);
    assert_true(fabs(largest - 0.4192) < 1e-3);
}

/* §4.8 the monitor's parameters: mm_tau in [dt_max, 60], mm_e in [0, 100], finite; a
 * refused init leaves the estimator untouched; 0 (off) never flags. */
static void mismatch_expect(rfe_real_t tau, rfe_real_t thr, rfe_status_t want, const char *what)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_t before;
    memset(&p, 0, sizeof(p));
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    p.mm_tau = tau;
    p.mm_e = thr;
    if (rfe_mass_grade_params_validate(&p) != want) {
        fail_msg("mismatch parameters: %s", what);
    }
    memset(&mg, 0x5A, sizeof(mg));
    before = mg;
    if (want != RFE_OK) {
        assert_int_equal(rfe_mass_grade_init(&mg, &p), RFE_ERR_PARAM);
        assert_memory_equal(&mg, &before, sizeof(mg));
    }
}

/* REQ-MG-003 */
static void test_mismatch_params_rules(void **state)
{
    const rfe_real_t ten = (rfe_real_t)10.0;
    const rfe_real_t thr = (rfe_real_t)0.3;
    rfe_mass_grade_params_t p;
    (void)state;
    memset(&p, 0, sizeof(p));
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    assert_true((p.mm_tau == ten) && (p.mm_e == thr)); /* on by default, §6's values */
    mismatch_expect((rfe_real_t)1.0, thr, RFE_OK, "tau = dt_max");
    mismatch_expect((rfe_real_t)60.0, thr, RFE_OK, "tau = 60");
    mismatch_expect((rfe_real_t)0.999, thr, RFE_ERR_PARAM, "tau < dt_max");
    mismatch_expect((rfe_real_t)60.01, thr, RFE_ERR_PARAM, "tau > 60");
    mismatch_expect((rfe_real_t)NAN, thr, RFE_ERR_PARAM, "tau NaN");
    mismatch_expect(ten, (rfe_real_t)0.0, RFE_OK, "e 0 (off)");
    mismatch_expect(ten, (rfe_real_t)100.0, RFE_OK, "e 100");
    mismatch_expect(ten, (rfe_real_t)-0.1, RFE_ERR_PARAM, "e < 0");
    mismatch_expect(ten, (rfe_real_t)100.5, RFE_ERR_PARAM, "e > 100");
    mismatch_expect(ten, (rfe_real_t)NAN, RFE_ERR_PARAM, "e NaN");
    mismatch_expect(ten, (rfe_real_t)INFINITY, RFE_ERR_PARAM, "e Inf");
    assert_int_equal(rfe_mg_mismatch(0, 1), 0u); /* off: never, however far the EMA */
    assert_int_equal(rfe_mg_mismatch(1, 0), 0u);
    assert_int_equal(rfe_mg_mismatch(1, 1), 1u);
}

/* §4.7 the two-level walk's parameters: each bound accepted at it and refused beyond it on
 * both sides, NaN and Inf refused, with the estimator untouched by a refused init. */
static void walk_expect(rfe_real_t hi, rfe_real_t on, rfe_real_t off, rfe_real_t tau,
                        rfe_real_t avg, rfe_status_t want, const char *what)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_t before;
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    p.q_theta_hi = hi;
    p.theta_rate_on = on;
    p.theta_rate_off = off;
    p.theta_rate_tau = tau;
    p.theta_rate_avg = avg;
    if (rfe_mass_grade_params_validate(&p) != want) {
        fail_msg("walk parameters: %s", what);
    }
    memset(&mg, 0x5A, sizeof(mg));
    before = mg;
    if (want != RFE_OK) {
        assert_int_equal(rfe_mass_grade_init(&mg, &p), RFE_ERR_PARAM);
        assert_memory_equal(&mg, &before, sizeof(mg));
    }
}

/* REQ-MG-003 */
static void test_walk_params_rules(void **state)
{
    const rfe_real_t on = (rfe_real_t)0.002;
    const rfe_real_t off = (rfe_real_t)0.001;
    const rfe_real_t one = (rfe_real_t)1.0; /* dt_max, the time constants' lower bound */
    const rfe_real_t three = (rfe_real_t)3.0;
    rfe_mass_grade_params_t p;
    (void)state;
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    assert_true((p.q_theta_hi == (rfe_real_t)0.008) && (p.theta_rate_on == on) &&
                (p.theta_rate_off == off) && (p.theta_rate_tau == one) &&
                (p.theta_rate_avg == three)); /* on by default (the recommended preset), §6's values */
    {
        rfe_mass_grade_params_t seed;
        assert_int_equal(rfe_mass_grade_params_preset(&seed, RFE_MG_TRUCK, RFE_MG_SEED), RFE_OK);
        assert_true(seed.q_theta_hi == (rfe_real_t)0.0); /* the seed's preset: off */
    }
    assert_true(p.q_theta == (rfe_real_t)0.004);
    /* q_theta_hi: 0 (off) or in [q_theta, 0.1] */
    walk_expect((rfe_real_t)0.0, on, off, one, three, RFE_OK, "hi 0");
    walk_expect((rfe_real_t)0.004, on, off, one, three, RFE_OK, "hi = q_theta");
    walk_expect((rfe_real_t)0.1, on, off, one, three, RFE_OK, "hi = 0.1");
    walk_expect((rfe_real_t)0.0039, on, off, one, three, RFE_ERR_PARAM, "hi < q_theta");
    walk_expect((rfe_real_t)0.1001, on, off, one, three, RFE_ERR_PARAM, "hi > 0.1");
    walk_expect((rfe_real_t)-0.008, on, off, one, three, RFE_ERR_PARAM, "hi < 0");
    walk_expect((rfe_real_t)NAN, on, off, one, three, RFE_ERR_PARAM, "hi NaN");
    walk_expect((rfe_real_t)INFINITY, on, off, one, three, RFE_ERR_PARAM, "hi Inf");
    /* 0 < off <= on <= 0.1 (checked with the walk off too: a preset stays switchable) */
    walk_expect((rfe_real_t)0.0, on, on, one, three, RFE_OK, "off = on");
    walk_expect((rfe_real_t)0.0, (rfe_real_t)0.1, off, one, three, RFE_OK, "on = 0.1");
    walk_expect((rfe_real_t)0.0, (rfe_real_t)0.1001, off, one, three, RFE_ERR_PARAM, "on > 0.1");
    walk_expect((rfe_real_t)0.0, on, (rfe_real_t)0.0021, one, three, RFE_ERR_PARAM, "off > on");
    walk_expect((rfe_real_t)0.0, on, (rfe_real_t)0.0, one, three, RFE_ERR_PARAM, "off = 0");
    walk_expect((rfe_real_t)0.0, on, (rfe_real_t)-0.001, one, three, RFE_ERR_PARAM, "off < 0");
    walk_expect((rfe_real_t)0.0, (rfe_real_t)NAN, off, one, three, RFE_ERR_PARAM, "on NaN");
    walk_expect((rfe_real_t)0.0, on, (rfe_real_t)NAN, one, three, RFE_ERR_PARAM, "off NaN");
    /* tau, avg in [dt_max, 60] */
    walk_expect((rfe_real_t)0.008, on, off, one, one, RFE_OK, "tau = avg = dt_max");
    walk_expect((rfe_real_t)0.008, on, off, (rfe_real_t)60.0, (rfe_real_t)60.0, RFE_OK, "60 s");
    walk_expect((rfe_real_t)0.008, on, off, (rfe_real_t)0.999, three, RFE_ERR_PARAM, "tau < dt_max");
    walk_expect((rfe_real_t)0.008, on, off, (rfe_real_t)60.01, three, RFE_ERR_PARAM, "tau > 60");
    walk_expect((rfe_real_t)0.008, on, off, one, (rfe_real_t)0.999, RFE_ERR_PARAM, "avg < dt_max");
    walk_expect((rfe_real_t)0.008, on, off, one, (rfe_real_t)60.01, RFE_ERR_PARAM, "avg > 60");
    walk_expect((rfe_real_t)0.008, on, off, (rfe_real_t)NAN, three, RFE_ERR_PARAM, "tau NaN");
    walk_expect((rfe_real_t)0.008, on, off, one, (rfe_real_t)INFINITY, RFE_ERR_PARAM, "avg Inf");
}

/* §4.7 the level's hysteresis (rfe_mg_walk_level), the whole truth table: tight loosens only
 * above on^2, loose tightens only below off^2, in between each stays. */
static void test_walk_level_truth_table(void **state)
{
    (void)state;
    /* (level, above_on, below_off) -> level */
    assert_int_equal(rfe_mg_walk_level(0u, 0, 0), 0u);
    assert_int_equal(rfe_mg_walk_level(0u, 0, 1), 0u);
    assert_int_equal(rfe_mg_walk_level(0u, 1, 0), 1u);
    assert_int_equal(rfe_mg_walk_level(0u, 1, 1), 1u); /* on^2 < s < off^2: not with off <= on */
    assert_int_equal(rfe_mg_walk_level(1u, 0, 0), 1u);
    assert_int_equal(rfe_mg_walk_level(1u, 0, 1), 0u);
    assert_int_equal(rfe_mg_walk_level(1u, 1, 0), 1u);
    assert_int_equal(rfe_mg_walk_level(1u, 1, 1), 0u);
}

/* A hold (the brake pedal, pause_grade 0) after the current state: P_thth must grow by
 * q^2 dt with q the level's density (§4.2, §4.7); the tolerance as in
 * test_brake_holds_mass_and_grade (8 TOL_EXACT: a 2 x 4 triangularisation). */
static void walk_hold_grows_by(rfe_real_t q, const char *what)
{
    rfe_mass_grade_t keep = mg;
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    double P[9];
    double p33;
    cov_of_factor(mg.S, P);
    p33 = P[8];
    in.brake = 1u;
    in.has |= RFE_MG_HAS_BRAKE;
    assert_int_equal(step(&in, &e), RFE_MG_PAUSED_BRAKE);
    cov_of_factor(mg.S, P);
    assert_close(P[8], p33 + ((double)q * (double)q) * DT, 0.0, 8.0 * TOL_EXACT, what);
    mg = keep;
}

/* REQ-MG-004 §4.7 on a drive whose accelerometer says the grade climbs 0.1 rad in 2 s and then
 * stays: the level loosens while the grade estimate moves (its rate ~0.05 rad/s, 25 times
 * on) and tightens once it has settled (s decays below off^2 within 60 s: e^-20 of its
 * peak); each time the next hold's grade variance grows by the level's q^2 dt; r and s
 * follow the spec's recursion on the estimated grades, replayed here in double (the same
 * operations, so only the test's double against the type's roundings: 1e-12 in double;
 * 1e-5 rad/s in float32, 100 ulp of the 0.05 rad/s peak rate for the 3000 steps' roundings). */
static void test_walk_loosens_while_the_grade_moves(void **state)
{
    const double tol = (sizeof(rfe_real_t) == 8u) ? 1e-12 : 1e-5;
    rfe_mass_grade_estimate_t e;
    rfe_mass_grade_input_t in;
    double th_prev;
    double r = 0.0;
    double s = 0.0;
    int loose_seen = 0;
    int k;
    (void)state;
    setup_with(0u, 1u);
    prm.q_theta_hi = (rfe_real_t)0.008;
    prm.pause_grade = (rfe_real_t)0.0;
    assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
    in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
    assert_int_equal(step(&in, &e), RFE_OK); /* the start: r = s = 0, tight */
    th_prev = (double)e.grade;
    assert_true((mg.wq_hi == 0u) && (mg.wq_rate == (rfe_real_t)0.0));
    walk_hold_grows_by(prm.q_theta, "tight at the start: q_theta");
    for (k = 1; k < 3000; ++k) {
        const double th = (k < 100) ? (0.001 * (double)k) : 0.1;
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        in.ax = (rfe_real_t)(0.1 + (9.81 * sin(th)));
        assert_int_equal(step(&in, &e), RFE_OK);
        r += (((double)e.grade - th_prev) / 1.0) - ((DT / 1.0) * r);
        s += (DT / 3.0) * ((r * r) - s);
        th_prev = (double)e.grade;
        assert_close((double)mg.wq_rate, r, tol, 0.0, "the grade rate's low-pass");
        assert_close((double)mg.wq_ms, s, tol * tol + tol * fabs(r), 0.0, "its mean square");
        if (k == 150) {
            assert_true(s > 0.002 * 0.002);
            assert_int_equal(mg.wq_hi, 1u);
            walk_hold_grows_by(prm.q_theta_hi, "loose while the grade moves: q_theta_hi");
            loose_seen = 1;
        }
    }
    assert_true(loose_seen != 0);
    assert_true(s < 0.001 * 0.001);
    assert_int_equal(mg.wq_hi, 0u);
    walk_hold_grows_by(prm.q_theta, "tight once it settled: q_theta");
}

/* §4.7 with q_theta_hi = q_theta the level switches but q_theta does not: every estimate
 * bit for bit the walk off's, so the statistic touches nothing else. */
static void test_walk_equal_levels_change_nothing(void **state)
{
    rfe_mass_grade_t off;
    rfe_mass_grade_estimate_t e0;
    rfe_mass_grade_estimate_t e1;
    rfe_mass_grade_input_t in;
    uint32_t switched = 0u;
    int k;
    (void)state;
    setup_with(0u, 1u);
    off = mg;
    prm.q_theta_hi = prm.q_theta;
    assert_int_equal(rfe_mass_grade_init(&mg, &prm), RFE_OK);
    for (k = 0; k < 500; ++k) {
        in = cruise((rfe_real_t)20.0, (rfe_real_t)DT);
        in.ax = (rfe_real_t)(0.1 + (9.81 * sin(0.001 * (double)((k < 100) ? k : 100))));
        in.brake = ((k % 97) == 50) ? 1u : 0u;
        in.has |= RFE_MG_HAS_BRAKE;
        assert_int_equal(rfe_mass_grade_step(&off, &in, &e0), rfe_mass_grade_step(&mg, &in, &e1));
        assert_memory_equal(&e0, &e1, sizeof(e0));
        switched |= mg.wq_hi;
    }
    assert_int_equal(switched, 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_presets_and_validation),
        cmocka_unit_test(test_params_rules),
        cmocka_unit_test(test_params_to_q31),
        cmocka_unit_test(test_init_get_restart_arguments),
        cmocka_unit_test(test_refused_samples_leave_the_state_untouched),
        cmocka_unit_test(test_start_and_restart),
        cmocka_unit_test(test_brake_holds_mass_and_grade),
        cmocka_unit_test(test_shift_and_low_speed_hold),
        cmocka_unit_test(test_slip_holds_mass_and_grade),
        cmocka_unit_test(test_curve_holds_mass_and_grade),
        cmocka_unit_test(test_pause_grade_learns_grade_holds_mass),
        cmocka_unit_test(test_pause_grade_decision),
        cmocka_unit_test(test_abs_gate_holds_cycling_wheels),
        cmocka_unit_test(test_abs_gate_decision),
        cmocka_unit_test(test_v_free_decision),
        cmocka_unit_test(test_abs_gate_bad_param_leaves_state),
        cmocka_unit_test(test_change_test),
        cmocka_unit_test(test_pause_grade_inert_without_ax),
        cmocka_unit_test(test_adaptation_as_specified),
        cmocka_unit_test(test_adaptation_period),
        cmocka_unit_test(test_factorisation_failures_leave_the_state_untouched),
        cmocka_unit_test(test_update_overflowing_the_mean_refused),
        cmocka_unit_test(test_start_and_hold_overflow_refused),
        cmocka_unit_test(test_update_losing_a_variance_refused),
        cmocka_unit_test(test_innovation_covariance_not_positive),
        cmocka_unit_test(test_ukf_is_the_kalman_filter_on_a_linear_problem),
        cmocka_unit_test(test_square_root_form_stays_definite),
        cmocka_unit_test(test_walk_params_rules),
        cmocka_unit_test(test_mismatch_flag_after_the_derived_time),
        cmocka_unit_test(test_mismatch_params_rules),
        cmocka_unit_test(test_walk_level_truth_table),
        cmocka_unit_test(test_walk_loosens_while_the_grade_moves),
        cmocka_unit_test(test_walk_equal_levels_change_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
