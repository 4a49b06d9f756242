/**
 * @file test_monitor_flt.c
 * @brief The model-validity monitor (rfe/component/monitor.h, docs/MONITOR.md §2): the normal
 *        quantile, the thresholds against the reference's table, the warm-up, the averages,
 *        fire / hold / clear and the sd inflation, input validation with the state untouched;
 *        the monitor's parameters in rfe_params_validate and the status rule of
 *        friction_logic.h; the estimator with the monitor on.
 *
 * Tolerances.
 * - Normal quantile against published values (Abramowitz & Stegun table 26.5 / scipy's
 *   ndtri, 16 digits): Acklam's approximation is within 1.15e-9 relative; double 2e-9 relative,
 *   float32 adds its rounding over ~12 Horner operations and a log: 2e-6 relative.
 * - Thresholds against docs/MONITOR.md's table (written by the float64 reference with scipy's
 *   exact normal quantiles, 3 decimals): 5e-4 for the table's rounding plus the quantile's
 *   1.15e-9 relative (a threshold of ~18 moves by < 1e-7): 6e-4 absolute; float32 adds ~1e-5
 *   (a dozen operations on values ~20 at 6e-8 relative): 6e-4 still holds.
 * - The averages: one multiply-add each on values ~3: double 1e-14, float32 1e-6.
 */
#include "test_common.h"

#include <math.h>
#include <string.h>

#include "rfe/component/monitor.h"
#include "rfe/friction.h"

#include "estimators/friction/friction_logic.h"

#if defined(RFE_REAL_DOUBLE)
#define TOL_Z_REL 2e-9
#define TOL_AVG 1e-14
#else
#define TOL_Z_REL 2e-6
#define TOL_AVG 1e-6
#endif
#define TOL_TABLE 6e-4

static rfe_monitor_params_t defaults(void)
{
    rfe_params_t p;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    return p.monitor;
}

static rfe_monitor_t started(void)
{
    rfe_monitor_t m;
    const rfe_monitor_params_t mp = defaults();
    assert_int_equal(rfe_monitor_init(&m, &mp, (rfe_real_t)0.01), RFE_OK);
    return m;
}

/* REQ: the normal quantile matches published values in both tails and the centre, is odd
 * about 1/2, and rejects probabilities outside (0, 1). */
/* REQ-MON-007 */
static void test_normal_quantile(void **state)
{
    /* z(q) for q = 0.5, 0.975, 1 - 5e-4, 1e-3, 1 - 1e-3 / 12 (16 digits, scipy.special.ndtri) */
    static const double q[5] = {0.5, 0.975, 0.9995, 0.001, 1.0 - (0.001 / 12.0)};
    static const double want[5] = {0.0, 1.959963984540054, 3.290526731491926,
                                   -3.090232306167813, 3.764823649533926};
    rfe_real_t z = (rfe_real_t)7.0;
    size_t i;
    (void)state;
    for (i = 0; i < 5; ++i) {
        /* float32 cannot hold q exactly: its rounding moves z by |dq| / phi(z), which is
         * added (1 % margin) to the method's tolerance (0 in double) */
        const double dq = fabs(q[i] - (double)(rfe_real_t)q[i]);
        const double phi = exp(-0.5 * want[i] * want[i]) / 2.5066282746310002;
        assert_int_equal(rfe_normal_quantile((rfe_real_t)q[i], &z), RFE_OK);
        assert_close((double)z, want[i], 1e-12 + (1.01 * dq / phi), TOL_Z_REL,
                     "normal quantile");
    }
    for (i = 1; i < 30; ++i) {
        rfe_real_t lo;
        rfe_real_t hi;
        const double qq = 0.0005 + (0.0165 * (double)i); /* across both region edges */
        assert_int_equal(rfe_normal_quantile((rfe_real_t)qq, &lo), RFE_OK);
        assert_int_equal(rfe_normal_quantile((rfe_real_t)(1.0 - qq), &hi), RFE_OK);
        assert_close((double)lo, -(double)hi, 1e-6, 1e-5, "z(q) = -z(1 - q)");
    }
    z = (rfe_real_t)7.0;
    assert_int_equal(rfe_normal_quantile((rfe_real_t)0.0, &z), RFE_ERR_RANGE);
    assert_int_equal(rfe_normal_quantile((rfe_real_t)1.0, &z), RFE_ERR_RANGE);
    assert_int_equal(rfe_normal_quantile((rfe_real_t)NAN, &z), RFE_ERR_RANGE);
    assert_true(z == (rfe_real_t)7.0);
    assert_int_equal(rfe_normal_quantile((rfe_real_t)0.5, NULL), RFE_ERR_NULL);
}

/* REQ: the fire and clear thresholds at the defaults equal docs/MONITOR.md's table (the
 * float64 reference with exact quantiles), for persistent shares 0 .. 1; shares outside
 * [0, 1] are clipped. */
/* REQ-MON-008 */
static void test_limits_match_reference_table(void **state)
{
    /* c, D_fire, D_clear, M_fire, M_clear (docs/MONITOR.md "Thresholds at the defaults") */
    static const double t[6][5] = {{0.0, 3.894, 3.417, 0.375, 0.238},
                                   {0.1, 4.619, 3.635, 1.242, 0.790},
                                   {0.3, 7.601, 4.495, 2.086, 1.326},
                                   {0.5, 10.625, 5.421, 2.675, 1.701},
                                   {0.8, 15.133, 6.830, 3.372, 2.144},
                                   {1.0, 18.130, 7.775, 3.765, 2.394}};
    const rfe_monitor_t m = started();
    rfe_monitor_limits_t lim;
    rfe_monitor_limits_t clipped;
    size_t i;
    size_t r;
    (void)state;
    assert_int_equal(m.hold_steps, 50u);    /* 0.5 s / 0.01 s, float's 50.0000007 too */
    assert_int_equal(m.warmup_steps, 100u); /* 1 s / 0.01 s */
    for (i = 0; i < 6; ++i) {
        const rfe_real_t c[RFE_MEAS] = {(rfe_real_t)t[i][0], (rfe_real_t)t[i][0],
                                        (rfe_real_t)t[i][0]};
        assert_int_equal(rfe_monitor_limits(&m, c, &lim), RFE_OK);
        assert_close((double)lim.d_fire, t[i][1], TOL_TABLE, 0.0, "D_fire");
        assert_close((double)lim.d_clear, t[i][2], TOL_TABLE, 0.0, "D_clear");
        for (r = 0; r < RFE_MEAS; ++r) {
            assert_close((double)lim.m_fire[r], t[i][3], TOL_TABLE, 0.0, "M_fire");
            assert_close((double)lim.m_clear[r], t[i][4], TOL_TABLE, 0.0, "M_clear");
        }
    }
    {
        const rfe_real_t out[RFE_MEAS] = {(rfe_real_t)-0.5, (rfe_real_t)2.0, (rfe_real_t)1.0};
        const rfe_real_t in[RFE_MEAS] = {(rfe_real_t)0.0, (rfe_real_t)1.0, (rfe_real_t)1.0};
        assert_int_equal(rfe_monitor_limits(&m, out, &clipped), RFE_OK);
        assert_int_equal(rfe_monitor_limits(&m, in, &lim), RFE_OK);
        assert_memory_equal(&clipped, &lim, sizeof(lim));
    }
}

/* REQ: the warm-up only counts; after it D, M, C are exponential averages of the NIS, the
 * normalised innovations and the persistent shares, with C starting at the first share. */
/* REQ-MON-008 */
static void test_warmup_and_averages(void **state)
{
    rfe_monitor_t m = started();
    const rfe_real_t Szz[RFE_MEAS * RFE_MEAS] = {2, 0, 0, 0, 1, 0, 0, 0, 1};
    const rfe_real_t nu[RFE_MEAS] = {1, 0.5, -0.25};
    const rfe_real_t pers[RFE_MEAS] = {2, 0.5, 0};
    uint32_t fired = 9u;
    double D;
    double M0;
    double ld;
    double lm;
    uint32_t k;
    (void)state;
    for (k = 0u; k < m.warmup_steps; ++k) {
        assert_int_equal(rfe_monitor_step(&m, nu, Szz, pers, &fired), RFE_OK);
    }
    assert_true(m.D == (rfe_real_t)3.0);
    assert_true(m.M[0] == (rfe_real_t)0.0);
    assert_int_equal(m.started, 0u);
    assert_int_equal(fired, 0u);
    ld = (double)m.l_d;
    lm = (double)m.l_m;
    assert_close(ld, 0.01 / 0.51, 1e-15, TOL_AVG, "l_d = dt / (tau + dt)");
    assert_int_equal(rfe_monitor_step(&m, nu, Szz, pers, &fired), RFE_OK);
    /* w = (1/2, 1/2, -1/4): d = 0.5625; e = (1/2, 1/2, -1/4) (S_rr = 4, 1, 1); c = (1/2, 1/2, 0) */
    D = ((1.0 - ld) * 3.0) + (ld * 0.5625);
    M0 = lm * 0.5;
    assert_close((double)m.D, D, TOL_AVG, 0.0, "D after the first counted step");
    assert_close((double)m.M[0], M0, TOL_AVG, 0.0, "M_ax");
    assert_close((double)m.M[2], -lm * 0.25, TOL_AVG, 0.0, "M_yaw");
    assert_close((double)m.C[0], 0.5, TOL_AVG, 0.0, "C starts at the first share");
    assert_close((double)m.C[2], 0.0, TOL_AVG, 0.0, "C_yaw");
    assert_int_equal(rfe_monitor_step(&m, nu, Szz, pers, NULL), RFE_OK);
    assert_close((double)m.D, ((1.0 - ld) * D) + (ld * 0.5625), TOL_AVG, 0.0, "D, second step");
    assert_close((double)m.M[0], ((1.0 - lm) * M0) + (lm * 0.5), TOL_AVG, 0.0, "M, second step");
}

/* REQ: innovations far beyond their covariance fire the monitor; it stays fired for at least
 * the hold time after the last exceedance and clears once the statistics are below the clear
 * thresholds; the sd factor is sqrt(max(1, D / 3)) while fired (with inflate) and 1 otherwise. */
/* REQ-MON-008 */
static void test_fire_hold_clear_inflation(void **state)
{
    rfe_monitor_t m = started();
    rfe_monitor_t no_inflate;
    rfe_monitor_params_t mp = defaults();
    const rfe_real_t Szz[RFE_MEAS * RFE_MEAS] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const rfe_real_t big[RFE_MEAS] = {4, -4, 4};
    const rfe_real_t zero[RFE_MEAS] = {0, 0, 0};
    uint32_t fired = 0u;
    uint32_t k;
    uint32_t first = 0u;
    uint32_t cleared = 0u;
    rfe_real_t c = (rfe_real_t)0.0;
    (void)state;
    mp.inflate = (rfe_real_t)0.0;
    assert_int_equal(rfe_monitor_init(&no_inflate, &mp, (rfe_real_t)0.01), RFE_OK);
    for (k = 0u; k < m.warmup_steps; ++k) {
        assert_int_equal(rfe_monitor_step(&m, zero, Szz, zero, &fired), RFE_OK);
        assert_int_equal(rfe_monitor_step(&no_inflate, zero, Szz, zero, NULL), RFE_OK);
    }
    assert_int_equal(rfe_monitor_inflation(&m, &c), RFE_OK);
    assert_true(c == (rfe_real_t)1.0);
    /* NIS 48 per step against D_fire 3.9 (white, c = 0): D passes it within a few steps */
    for (k = 1u; (k <= 20u) && (fired == 0u); ++k) {
        assert_int_equal(rfe_monitor_step(&m, big, Szz, zero, &fired), RFE_OK);
        assert_int_equal(rfe_monitor_step(&no_inflate, big, Szz, zero, NULL), RFE_OK);
        first = k;
    }
    assert_int_equal(fired, 1u);
    assert_true(first <= 5u); /* D_k = 3 + (48 - 3)(1 - (1 - l)^k) > 3.9 from k = 2 */
    assert_int_equal(rfe_monitor_inflation(&m, &c), RFE_OK);
    assert_close((double)c, sqrt((double)m.D / 3.0), TOL_AVG, 1e-6, "inflation");
    assert_true(c > (rfe_real_t)1.0);
    assert_int_equal(rfe_monitor_inflation(&no_inflate, &c), RFE_OK);
    assert_true(c == (rfe_real_t)1.0); /* inflate = 0: sd untouched */
    /* quiet innovations: held at least hold_steps, then cleared when D and M are low */
    for (k = 1u; k <= 2000u; ++k) {
        assert_int_equal(rfe_monitor_step(&m, zero, Szz, zero, &fired), RFE_OK);
        if (fired == 0u) {
            cleared = k;
            break;
        }
    }
    assert_true(cleared >= m.hold_steps);
    assert_true(cleared > 0u);
    assert_int_equal(rfe_monitor_inflation(&m, &c), RFE_OK);
    assert_true(c == (rfe_real_t)1.0);
}

/* REQ: bad arguments give a distinct status and leave the monitor untouched: NULL, not
 * initialised, non-finite innovation / factor / share, a zero diagonal; bad parameters are
 * rejected by init and by rfe_params_validate, which also refuses the monitor on the CKF. */
/* REQ-MON-009 */
static void test_bad_input_untouched(void **state)
{
    rfe_monitor_t m = started();
    rfe_monitor_t before;
    rfe_monitor_t blank;
    rfe_monitor_params_t mp = defaults();
    rfe_params_t p;
    const rfe_real_t Szz[RFE_MEAS * RFE_MEAS] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    const rfe_real_t sing[RFE_MEAS * RFE_MEAS] = {1, 0, 0, 0, 0, 0, 0, 0, 1};
    const rfe_real_t nu[RFE_MEAS] = {1, 1, 1};
    const rfe_real_t bad[RFE_MEAS] = {1, (rfe_real_t)NAN, 1};
    rfe_real_t c;
    (void)state;
    memset(&blank, 0, sizeof(blank));
    m.seen = m.warmup_steps; /* the next step is counted */
    before = m;
    assert_int_equal(rfe_monitor_step(NULL, nu, Szz, nu, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step(&m, NULL, Szz, nu, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step(&m, nu, NULL, nu, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step(&m, nu, Szz, NULL, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step(&blank, nu, Szz, nu, NULL), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_monitor_step(&m, bad, Szz, nu, NULL), RFE_ERR_NONFINITE);
    assert_int_equal(rfe_monitor_step(&m, nu, Szz, bad, NULL), RFE_ERR_NONFINITE);
    {
        /* a non-finite factor below the diagonal is refused; above it (unread) it is not */
        rfe_real_t lo[RFE_MEAS * RFE_MEAS] = {1, 0, 0, (rfe_real_t)NAN, 1, 0, 0, 0, 1};
        rfe_monitor_t up = m;
        assert_int_equal(rfe_monitor_step(&m, nu, lo, nu, NULL), RFE_ERR_NONFINITE);
        lo[3] = (rfe_real_t)0.0;
        lo[1] = (rfe_real_t)NAN;
        assert_int_equal(rfe_monitor_step(&up, nu, lo, nu, NULL), RFE_OK);
    }
    assert_int_equal(rfe_monitor_step(&m, nu, sing, nu, NULL), RFE_ERR_NOT_POSITIVE_DEFINITE);
    {
        const rfe_real_t huge[RFE_MEAS] = {(rfe_real_t)1e30, 1, 1};
        const rfe_real_t tiny[RFE_MEAS * RFE_MEAS] = {(rfe_real_t)1e-30, 0, 0, 0, 1, 0, 0, 0, 1};
#if defined(RFE_REAL_DOUBLE)
        const rfe_real_t h2[RFE_MEAS] = {(rfe_real_t)1e200, 1, 1};
        const rfe_real_t t2[RFE_MEAS * RFE_MEAS] = {(rfe_real_t)1e-200, 0, 0, 0, 1, 0, 0, 0, 1};
        (void)huge;
        (void)tiny;
        assert_int_equal(rfe_monitor_step(&m, h2, t2, nu, NULL), RFE_ERR_NONFINITE);
#else
        assert_int_equal(rfe_monitor_step(&m, huge, tiny, nu, NULL), RFE_ERR_NONFINITE);
#endif
    }
    assert_memory_equal(&m, &before, sizeof(m));
    assert_int_equal(rfe_monitor_inflation(NULL, &c), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_inflation(&m, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_inflation(&blank, &c), RFE_ERR_NOT_INITIALISED);
    {
        rfe_monitor_limits_t lim;
        assert_int_equal(rfe_monitor_limits(NULL, nu, &lim), RFE_ERR_NULL);
        assert_int_equal(rfe_monitor_limits(&m, NULL, &lim), RFE_ERR_NULL);
        assert_int_equal(rfe_monitor_limits(&m, nu, NULL), RFE_ERR_NULL);
        assert_int_equal(rfe_monitor_limits(&blank, nu, &lim), RFE_ERR_NOT_INITIALISED);
        assert_int_equal(rfe_monitor_limits(&m, bad, &lim), RFE_ERR_NONFINITE);
    }
    /* init: each bad parameter, NULL, a bad dt; the target untouched */
    {
        struct {
            rfe_real_t *field;
            rfe_real_t value;
        } cases[] = {{&mp.enable, (rfe_real_t)0.5},   {&mp.inflate, (rfe_real_t)2.0},
                     {&mp.tau_nis, (rfe_real_t)0.0},  {&mp.tau_mean, (rfe_real_t)-1.0},
                     {&mp.p_fire, (rfe_real_t)0.0},   {&mp.p_fire, (rfe_real_t)0.2},
                     {&mp.p_clear, (rfe_real_t)1.0},  {&mp.hold, (rfe_real_t)-0.1},
                     {&mp.warmup, (rfe_real_t)INFINITY}, {&mp.hold, (rfe_real_t)1e9},
                     {&mp.tau_nis, (rfe_real_t)NAN}};
        size_t i;
        for (i = 0; i < sizeof(cases) / sizeof(cases[0]); ++i) {
            const rfe_real_t keep = *cases[i].field;
            rfe_monitor_t t = blank;
            *cases[i].field = cases[i].value;
            assert_int_equal(rfe_monitor_init(&t, &mp, (rfe_real_t)0.01), RFE_ERR_PARAM);
            assert_memory_equal(&t, &blank, sizeof(t));
            assert_int_equal(rfe_monitor_params_validate(&mp, (rfe_real_t)0.01), RFE_ERR_PARAM);
            assert_int_equal(rfe_params_default(&p), RFE_OK);
            p.monitor = mp;
            assert_int_equal(rfe_params_validate(&p), RFE_ERR_PARAM);
            *cases[i].field = keep;
        }
        /* a probability too small for the real type: 1 - p rounds to 1 */
        mp.p_fire = (rfe_real_t)1e-30;
        assert_int_equal(rfe_monitor_init(&m, &mp, (rfe_real_t)0.01), RFE_ERR_PARAM);
        mp = defaults();
        assert_int_equal(rfe_monitor_init(&m, &mp, (rfe_real_t)0.0), RFE_ERR_PARAM);
        assert_int_equal(rfe_monitor_init(NULL, &mp, (rfe_real_t)0.01), RFE_ERR_NULL);
        assert_int_equal(rfe_monitor_init(&m, NULL, (rfe_real_t)0.01), RFE_ERR_NULL);
        {
            rfe_monitor_consts_t k;
            assert_int_equal(rfe_monitor_consts(NULL, (rfe_real_t)0.01, &k), RFE_ERR_NULL);
            assert_int_equal(rfe_monitor_consts(&mp, (rfe_real_t)0.01, NULL), RFE_ERR_NULL);
            assert_int_equal(rfe_monitor_consts(&mp, (rfe_real_t)0.01, &k), RFE_OK);
            assert_int_equal(k.hold_steps, m.hold_steps);
        }
        assert_int_equal(rfe_monitor_params_validate(NULL, (rfe_real_t)0.01), RFE_ERR_NULL);
        assert_memory_equal(&m, &before, sizeof(m));
    }
    /* the monitor reads the SCKF's innovations: on with the CKF is refused */
    assert_int_equal(rfe_params_paper(&p), RFE_OK);
    p.filter.kind = RFE_FILTER_CKF;
    p.monitor.enable = (rfe_real_t)1.0;
    assert_int_equal(rfe_params_validate(&p), RFE_ERR_PARAM);
    p.filter.kind = RFE_FILTER_SCKF;
    assert_int_equal(rfe_params_validate(&p), RFE_OK);
}

/* REQ: while fired, an updated step and a held step that would be valid report
 * RFE_MODEL_MISMATCH; a held step with every flag 0, low speed and errors keep their status;
 * the verdict applies to the steps that evaluated the model. */
/* The init as its wrapper would call it from a caller compiled otherwise (another size of
 * the state, another configuration word) writes nothing; through the wrapper it is accepted. */
/* REQ-ABI-001 */
static void test_init_refuses_other_layout_or_word(void **state)
{
    rfe_monitor_t m;
    rfe_monitor_t before;
    const rfe_monitor_params_t mp = defaults();
    const rfe_real_t dt = (rfe_real_t)0.01;
    (void)state;
    memset(&m, 0x5A, sizeof m);
    before = m;
    assert_int_equal((rfe_monitor_init)(&m, &mp, dt, sizeof m - 4u, RFE_CONFIG_REAL),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_monitor_init)(&m, &mp, dt, sizeof m, RFE_CONFIG_REAL ^ 3u),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_monitor_init)(&m, &mp, dt, sizeof m, RFE_CONFIG_REAL ^ (1u << 8u)),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_monitor_init)(NULL, NULL, dt, sizeof m, RFE_CONFIG_REAL ^ 3u),
                     RFE_ERR_ABI);
    assert_memory_equal(&m, &before, sizeof m);
    assert_int_equal(rfe_monitor_init(&m, &mp, dt), RFE_OK);
    assert_int_equal(m.fired, 0);
}

/* REQ-MON-010 */
static void test_status_rule(void **state)
{
    (void)state;
    assert_int_equal(rfe_friction_monitor_status(RFE_OK, 0), RFE_MODEL_MISMATCH);
    assert_int_equal(rfe_friction_monitor_status(RFE_PROJECTED, 1), RFE_MODEL_MISMATCH);
    assert_int_equal(rfe_friction_monitor_status(RFE_HELD_NOT_OBSERVABLE, 1),
                     RFE_MODEL_MISMATCH);
    assert_int_equal(rfe_friction_monitor_status(RFE_HELD_NOT_OBSERVABLE, 0),
                     RFE_HELD_NOT_OBSERVABLE);
    assert_int_equal(rfe_friction_monitor_applies(RFE_OK), 1);
    assert_int_equal(rfe_friction_monitor_applies(RFE_PROJECTED), 1);
    assert_int_equal(rfe_friction_monitor_applies(RFE_HELD_NOT_OBSERVABLE), 1);
    assert_int_equal(rfe_friction_monitor_applies(RFE_NO_UPDATE_LOW_SPEED), 0);
    assert_int_equal(rfe_friction_monitor_applies(RFE_ERR_RANGE), 0);
    assert_int_equal(rfe_status_is_error(RFE_MODEL_MISMATCH), 0);
    assert_string_equal(rfe_status_str(RFE_MODEL_MISMATCH),
                        "model mismatch: the innovations contradict the model");
}

/* REQ: with the monitor on, an accelerometer offset while cruising (a fault no friction
 * explains) ends in RFE_MODEL_MISMATCH with every flag 0 and the sd inflated; with it off the
 * same samples are reported as the estimator computes them. */
/* REQ-MON-010 */
static void test_estimator_reports_mismatch(void **state)
{
    rfe_params_t p;
    rfe_friction_t on;
    rfe_friction_t off;
    rfe_estimate_t e_on;
    rfe_estimate_t e_off;
    rfe_sample_t u;
    size_t k;
    size_t w;
    int mismatch = 0;
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    assert_true(p.monitor.enable == (rfe_real_t)1.0); /* on in the default preset */
    p.monitor.enable = (rfe_real_t)0.0;
    assert_int_equal(rfe_friction_init(&off, &p), RFE_OK);
    p.monitor.enable = (rfe_real_t)1.0;
    assert_int_equal(rfe_friction_init(&on, &p), RFE_OK);
    memset(&u, 0, sizeof(u));
    u.vx = (rfe_real_t)20.0;
    for (w = 0; w < RFE_WHEELS; ++w) {
        u.omega[w] = (rfe_real_t)(20.0 / 0.325);
    }
    u.ax = (rfe_real_t)0.8; /* rolling freely, yet 0.8 m/s^2 measured: no mu explains it */
    for (k = 0; k < 400; ++k) {
        const rfe_status_t s_on = rfe_friction_step(&on, &u, &e_on);
        const rfe_status_t s_off = rfe_friction_step(&off, &u, &e_off);
        assert_false(rfe_status_is_error(s_on));
        assert_int_equal(s_on, e_on.status);
        for (w = 0; w < RFE_WHEELS; ++w) {
            assert_true(e_on.mu[w] == e_off.mu[w]); /* the monitor never feeds back */
        }
        if (s_on == RFE_MODEL_MISMATCH) {
            mismatch = 1;
            for (w = 0; w < RFE_WHEELS; ++w) {
                assert_int_equal(e_on.valid[w], 0u);
                assert_true(e_on.sd[w] >= e_off.sd[w]);
            }
            assert_true(s_off != RFE_NO_UPDATE_LOW_SPEED);
        } else {
            assert_int_equal(s_on, s_off);
        }
    }
    assert_int_equal(mismatch, 1);
    assert_int_equal(e_on.status, RFE_MODEL_MISMATCH);
    assert_true(on.mon.fired == 1u);
}

/* One phase of samples: speed, wheel slip (omega = (1 + slip) vx / R), ax. */
static rfe_sample_t phase_sample(double vx, double slip, double ax)
{
    rfe_sample_t u;
    size_t w;
    memset(&u, 0, sizeof(u));
    u.vx = (rfe_real_t)vx;
    u.ax = (rfe_real_t)ax;
    for (w = 0; w < RFE_WHEELS; ++w) {
        u.omega[w] = (rfe_real_t)((1.0 + slip) * vx / 0.325);
    }
    return u;
}

/* REQ: while fired, every kind of step maps as specified: updated (0) and projected (1) steps
 * and held steps (3) with a flag 1 report RFE_MODEL_MISMATCH, a held step with every flag 0
 * keeps 3 and low speed keeps 2; the estimate underneath (mu) is the monitor-off one. With
 * no warm-up a large ax offset fires the monitor at once, while the prior's sd still holds
 * every flag 0 (held, not valid); then the offset's projected updates, crawling (low
 * speed), braking (updated and held with the flags set); each kind must occur while fired. */
/* REQ-MON-010 */
static void test_estimator_status_while_fired(void **state)
{
    static const double phases[6][4] = {
        /* steps, vx [m/s], slip, ax [m/s^2] */
        {300.0, 20.0, 0.0, 3.0},     /* the offset: fires at once, held at the prior's sd */
        {300.0, 1.0, 0.0, 0.8},      /* crawling: low speed */
        {300.0, 20.0, 0.0, 0.8},     /* the offset again */
        {60.0, 20.0, -0.05, -3.0},   /* braking: updated, then held with the flags set */
        {100.0, 20.0, 0.0, 0.0},     /* cruising: projected updates */
        {0.0, 0.0, 0.0, 0.0}};
    rfe_params_t p;
    rfe_friction_t on;
    rfe_friction_t off;
    unsigned seen[5] = {0u, 0u, 0u, 0u, 0u}; /* while fired: s_off 0, 1, 2, 3 valid, 3 not */
    rfe_estimate_t last_on;
    size_t ph;
    (void)state;
    memset(&last_on, 0, sizeof last_on);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    assert_true(p.monitor.enable == (rfe_real_t)1.0); /* on in the default preset */
    p.monitor.enable = (rfe_real_t)0.0;
    assert_int_equal(rfe_friction_init(&off, &p), RFE_OK);
    p.monitor.enable = (rfe_real_t)1.0;
    p.monitor.warmup = (rfe_real_t)0.0; /* judged from the first step: fires while the prior holds */
    assert_int_equal(rfe_friction_init(&on, &p), RFE_OK);
    for (ph = 0; phases[ph][0] > 0.0; ++ph) {
        const rfe_sample_t u = phase_sample(phases[ph][1], phases[ph][2], phases[ph][3]);
        int k;
        for (k = 0; k < (int)phases[ph][0]; ++k) {
            rfe_estimate_t e_on;
            rfe_estimate_t e_off;
            const rfe_status_t s_on = rfe_friction_step(&on, &u, &e_on);
            const rfe_status_t s_off = rfe_friction_step(&off, &u, &e_off);
            const int any = (e_off.valid[0] | e_off.valid[1] | e_off.valid[2] | e_off.valid[3]) != 0u;
            rfe_status_t want = s_off;
            size_t w;
            for (w = 0; w < RFE_WHEELS; ++w) {
                assert_true(e_on.mu[w] == e_off.mu[w]);
            }
            last_on = e_on;
            if (on.mon.fired == 0u) {
                assert_int_equal(s_on, s_off);
                continue;
            }
            for (w = 0; w < RFE_WHEELS; ++w) { /* every step while fired: inflated, no flag */
                assert_int_equal(e_on.valid[w], 0u);
                assert_true(e_on.sd[w] >= e_off.sd[w]);
            }
            if ((s_off == RFE_OK) || (s_off == RFE_PROJECTED) ||
                ((s_off == RFE_HELD_NOT_OBSERVABLE) && any)) {
                want = RFE_MODEL_MISMATCH;
            }
            assert_int_equal(s_on, want);
            if (s_off == RFE_HELD_NOT_OBSERVABLE) {
                seen[any ? 3 : 4]++;
            } else if ((unsigned)s_off < 3u) {
                seen[(unsigned)s_off]++;
            }
        }
    }
    printf("  while fired: %u updated, %u projected, %u low speed, %u held valid, %u held\n",
           seen[0], seen[1], seen[2], seen[3], seen[4]);
    for (ph = 0; ph < 5; ++ph) {
        assert_true(seen[ph] > 0u);
    }
    /* a rejected sample while fired reports the previous estimate (inflated sd) */
    assert_int_equal(on.mon.fired, 1u);
    {
        rfe_sample_t bad = phase_sample(20.0, 0.0, 0.0);
        rfe_estimate_t e;
        bad.vx = (rfe_real_t)1e3;
        assert_int_equal(rfe_friction_step(&on, &bad, &e), RFE_ERR_RANGE);
        assert_memory_equal(e.mu, last_on.mu, sizeof e.mu);
        assert_memory_equal(e.sd, last_on.sd, sizeof e.sd);
        /* get reports what the step did: no flag, the inflated sd */
        assert_int_equal(rfe_friction_get(&on, &e), RFE_OK);
        assert_memory_equal(e.mu, last_on.mu, sizeof e.mu);
        assert_memory_equal(e.sd, last_on.sd, sizeof e.sd);
        assert_memory_equal(e.valid, last_on.valid, sizeof e.valid);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normal_quantile),
        cmocka_unit_test(test_limits_match_reference_table),
        cmocka_unit_test(test_warmup_and_averages),
        cmocka_unit_test(test_fire_hold_clear_inflation),
        cmocka_unit_test(test_bad_input_untouched),
        cmocka_unit_test(test_init_refuses_other_layout_or_word),
        cmocka_unit_test(test_status_rule),
        cmocka_unit_test(test_estimator_reports_mismatch),
        cmocka_unit_test(test_estimator_status_while_fired),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
