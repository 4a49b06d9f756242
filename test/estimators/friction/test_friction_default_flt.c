/**
 * @file test_friction_default_flt.c
 * @brief The observability-aware estimator of docs/ESTIMATOR.md (the default preset): input
 *        conditioning, step noise S_R, information gate, sd bounds, sides structure,
 *        validity by sd, parameter validation of every new key, rollback with the input
 *        filter active. The paper preset is pinned by test_friction_flt.c and the goldens.
 *
 * Tolerances.
 * - Complementary filter (hand-derived values): a handful of roundings on values ~20:
 *   double 1e-12 absolute, float32 4e-5 (3 ulp of 20 per step, two steps).
 * - S_R S_R^T against R0 + sum g g^T formed here in double from g = sd dh/du computed by
 *   rfe_meas_input_jac called here (tested itself in test_meas_flt.c): the same function
 *   calls give the same g; what remains is Tria's rounding on a 3 x 11 matrix: double 1e-12,
 *   float32 1e-5, relative to max |R|.
 * - Bounds: c S is one rounding per element, so sd after scaling is sd_max (or the floor)
 *   to a few eps, and the correlation is kept to a few eps of its value.
 */
#include "test_common.h"

#include <float.h>
#include <string.h>

#include "rfe/component/step_noise.h"
#include "rfe/friction.h"
#include "rfe/component/meas.h"
#include "rfe/component/obsmat.h"

#if defined(RFE_REAL_DOUBLE)
#define TOL_CF 1e-12
#define TOL_SR 1e-12
#define EPS_R DBL_EPSILON
#define HUGE_SD0 1e160 /* squares overflow double */
#else
#define TOL_CF 4e-5
#define TOL_SR 1e-5
#define EPS_R ((double)FLT_EPSILON)
#define HUGE_SD0 1e20 /* squares overflow float */
#endif

static rfe_params_t dflt; /* rfe_params_default */
static rfe_params_t paper; /* rfe_params_paper */

static int setup(void **state)
{
    (void)state;
    if ((rfe_params_default(&dflt) != RFE_OK) || (rfe_params_paper(&paper) != RFE_OK)) {
        return -1;
    }
    return 0;
}

/* Straight driving at vx with longitudinal slip s on every wheel (omega R = vx (1 + s)). */
static rfe_sample_t straight_sample(double vx, double slip_left, double slip_right)
{
    rfe_sample_t u;
    memset(&u, 0, sizeof u);
    u.vx = (rfe_real_t)vx;
    u.omega[RFE_FL] = (rfe_real_t)(vx * (1.0 + slip_left) / 0.325);
    u.omega[RFE_RL] = (rfe_real_t)(vx * (1.0 + slip_left) / 0.325);
    u.omega[RFE_FR] = (rfe_real_t)(vx * (1.0 + slip_right) / 0.325);
    u.omega[RFE_RR] = (rfe_real_t)(vx * (1.0 + slip_right) / 0.325);
    return u;
}

/* y = h(mu, u) of the absolute model, iterating the loads (ax, ay enter them). */
static void model_match(const rfe_params_t *p, rfe_sample_t *u, const rfe_real_t mu[4])
{
    static const rfe_real_t ones[4] = {1, 1, 1, 1};
    rfe_wheel_kin_t kin;
    rfe_real_t fx[4], fy[4], H[12], y[3];
    int k;
    for (k = 0; k < 8; ++k) {
        assert_int_equal(rfe_tyre_kinematics(&p->vehicle, &p->tyre, u, &kin), RFE_OK);
        assert_int_equal(rfe_tyre_forces_abs(&p->tyre, &kin, mu, fx, fy), RFE_OK);
        assert_int_equal(rfe_obsmat_build(&p->vehicle, u->delta, fx, fy, H), RFE_OK);
        assert_int_equal(rfe_obsmat_apply(H, ones, y), RFE_OK);
        u->ax = y[0];
        u->ay = y[1];
        u->yaw_acc = y[2];
    }
}

/* Correlation P_01 / sqrt(P_00 P_11) of the SCKF's first two states. */
static double correlation(const rfe_sckf_t *f)
{
    const double s00 = (double)f->S[0];
    const double s10 = (double)f->S[RFE_N_MAX];
    const double s11 = (double)f->S[RFE_N_MAX + 1];
    return (s00 * s10) / sqrt((s00 * s00) * ((s10 * s10) + (s11 * s11)));
}

/* ---- step 1: complementary filter ------------------------------------------------------ */

/* REQ: docs/ESTIMATOR.md step 1 on a hand-derived example. dt = 0.01, tau_v = 0.09, so
 * b = 0.1. Sample 1 (vx 20, vy 0.5) initialises. Sample 2 (ax -2, ay 1, r 0.2, vx 19.9,
 * vy 0.4): px = 20 + 0.01 (-2 + 0.2 * 0.5) = 19.981, py = 0.5 + 0.01 (1 - 0.2 * 20) = 0.47,
 * vx = 0.9 * 19.981 + 0.1 * 19.9 = 19.9729, vy = 0.9 * 0.47 + 0.1 * 0.4 = 0.463.
 * Sample 3 (all zero but vx 20): vx = 0.9 * 19.9729 + 2 = 19.97561, vy = 0.9 * 0.463 = 0.4167. */
/* REQ-COND-001 */
static void test_rfe_conditioner_hand_example(void **state)
{
    rfe_conditioner_t c;
    rfe_sample_t u, out;
    const rfe_real_t dt = (rfe_real_t)0.01, tau = (rfe_real_t)0.09;
    (void)state;
    assert_int_equal(rfe_conditioner_init(&c), RFE_OK);
    memset(&u, 0, sizeof u);
    u.vx = 20;
    u.vy = (rfe_real_t)0.5;
    u.ax = 7; /* not used at the first sample */
    u.omega[2] = 3;
    assert_int_equal(rfe_conditioner_step(&c, dt, tau, &u, &out), RFE_OK);
    assert_true(out.vx == u.vx && out.vy == u.vy && out.ax == u.ax && out.omega[2] == u.omega[2]);
    assert_int_equal(c.started, 1);
    u.vx = (rfe_real_t)19.9;
    u.vy = (rfe_real_t)0.4;
    u.ax = -2;
    u.ay = 1;
    u.yaw_rate = (rfe_real_t)0.2;
    assert_int_equal(rfe_conditioner_step(&c, dt, tau, &u, &out), RFE_OK);
    assert_close(out.vx, 19.9729, TOL_CF, 0.0, "vx after step 2");
    assert_close(out.vy, 0.463, TOL_CF, 0.0, "vy after step 2");
    assert_close(c.vx, 19.9729, TOL_CF, 0.0, "state vx");
    assert_true(out.ax == u.ax && out.yaw_rate == u.yaw_rate); /* everything else copied */
    memset(&u, 0, sizeof u);
    u.vx = 20;
    /* out may alias in */
    assert_int_equal(rfe_conditioner_step(&c, dt, tau, &u, &u), RFE_OK);
    assert_close(u.vx, 19.97561, TOL_CF, 0.0, "vx after step 3");
    assert_close(u.vy, 0.4167, TOL_CF, 0.0, "vy after step 3");
}

/* REQ: tau_v = 0 is off (sample passes, state untouched); errors change nothing. */
/* REQ-COND-002 REQ-ABI-001 */
static void test_rfe_conditioner_off_and_errors(void **state)
{
    rfe_conditioner_t c, copy, blank;
    rfe_sample_t u, out, out_copy;
    (void)state;
    assert_int_equal(rfe_conditioner_init(NULL), RFE_ERR_NULL);
    /* as the wrapper would call it from a caller compiled otherwise: another size of the
     * state, another configuration word (RFE_ERR_ABI, nothing written) */
    memset(&c, 0x5A, sizeof c);
    copy = c;
    assert_int_equal((rfe_conditioner_init)(&c, sizeof c + 8u, RFE_CONFIG_REAL), RFE_ERR_ABI);
    assert_int_equal((rfe_conditioner_init)(&c, sizeof c, RFE_CONFIG_REAL ^ 3u), RFE_ERR_ABI);
    assert_int_equal((rfe_conditioner_init)(&c, sizeof c, RFE_CONFIG_REAL ^ (1u << 16u)),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_conditioner_init)(NULL, sizeof c, RFE_CONFIG_REAL ^ 3u), RFE_ERR_ABI);
    assert_memory_equal(&c, &copy, sizeof c);
    assert_int_equal(rfe_conditioner_init(&c), RFE_OK);
    memset(&u, 0, sizeof u);
    u.vx = 10;
    u.vy = 1;
    copy = c;
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)0.01, 0, &u, &out), RFE_OK);
    assert_memory_equal(&out, &u, sizeof u);
    assert_memory_equal(&c, &copy, sizeof c);
    memset(&out, 0x5A, sizeof out);
    out_copy = out;
    assert_int_equal(rfe_conditioner_step(NULL, (rfe_real_t)0.01, 1, &u, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)0.01, 1, NULL, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)0.01, 1, &u, NULL), RFE_ERR_NULL);
    memset(&blank, 0, sizeof blank);
    assert_int_equal(rfe_conditioner_step(&blank, (rfe_real_t)0.01, 1, &u, &out), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_conditioner_step(&c, 0, 1, &u, &out), RFE_ERR_PARAM);
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)NAN, 1, &u, &out), RFE_ERR_PARAM);
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)0.01, -1, &u, &out), RFE_ERR_PARAM);
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)0.01, (rfe_real_t)INFINITY, &u, &out),
                     RFE_ERR_PARAM);
    u.yaw_rate = (rfe_real_t)NAN;
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)0.01, 1, &u, &out), RFE_ERR_NONFINITE);
    u.yaw_rate = 0;
    u.vy = (rfe_real_t)INFINITY;
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)0.01, 1, &u, &out), RFE_ERR_NONFINITE);
    assert_memory_equal(&c, &copy, sizeof c);
    assert_memory_equal(&out, &out_copy, sizeof out);
    /* A finite sample whose prediction overflows. */
#if defined(RFE_REAL_DOUBLE)
    u.vx = (rfe_real_t)(0.9 * DBL_MAX);
#else
    u.vx = (rfe_real_t)(0.9 * FLT_MAX);
#endif
    u.vy = 0;
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)0.01, 1, &u, &out), RFE_OK);
    copy = c;
    u.ax = u.vx;
    assert_int_equal(rfe_conditioner_step(&c, 1, 1, &u, &out), RFE_ERR_NONFINITE);
    assert_memory_equal(&c, &copy, sizeof c);
}

/* REQ: the estimator uses the filtered vx everywhere, including the low-speed test: a
 * measured vx that drops below v_est_min for one sample (a glitch) is smoothed away. */
/* REQ-EST-011 */
static void test_rfe_friction_uses_filtered_speed(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    rfe_sample_t u = straight_sample(20.0, 0.0, 0.0);
    rfe_status_t st;
    (void)state;
    assert_int_equal(rfe_friction_init(&est, &dflt), RFE_OK);
    assert_int_equal(est.cond.started, 0);
    st = rfe_friction_step(&est, &u, &out);
    assert_int_equal(st, RFE_HELD_NOT_OBSERVABLE); /* zero slip: no information */
    assert_true(est.cond.vx == u.vx);
    u.vx = 1; /* glitch */
    st = rfe_friction_step(&est, &u, &out);
    assert_false(rfe_status_is_error(st));
    assert_true(st != RFE_NO_UPDATE_LOW_SPEED); /* the filtered vx is ~19.4 */
    assert_close(est.cond.vx, 20.0 - (19.0 * 0.01 / 0.31), 1e-4, 0.0, "filtered vx");
    /* The paper preset uses the measured vx. */
    assert_int_equal(rfe_friction_init(&est, &paper), RFE_OK);
    assert_int_equal(rfe_friction_step(&est, &u, &out), RFE_NO_UPDATE_LOW_SPEED);
}

/* ---- step 4: step noise S_R ------------------------------------------------------------ */

/* h(mu, u) straight from the tyre and obsmat functions (not through meas.h), in double. */
static void h_direct(const rfe_params_t *p, const rfe_sample_t *u, const rfe_real_t mu[4], double z[3])
{
    static const rfe_real_t ones[4] = {1, 1, 1, 1};
    rfe_wheel_kin_t kin;
    rfe_real_t fx[4], fy[4], H[12], y[3];
    size_t r;
    assert_int_equal(rfe_tyre_kinematics(&p->vehicle, &p->tyre, u, &kin), RFE_OK);
    if (p->tyre.mode == RFE_TYRE_PAPER) {
        assert_int_equal(rfe_tyre_forces_norm(&p->tyre, &kin, fx, fy), RFE_OK);
        assert_int_equal(rfe_obsmat_build(&p->vehicle, u->delta, fx, fy, H), RFE_OK);
        assert_int_equal(rfe_obsmat_apply(H, mu, y), RFE_OK);
    } else {
        assert_int_equal(rfe_tyre_forces_abs(&p->tyre, &kin, mu, fx, fy), RFE_OK);
        assert_int_equal(rfe_obsmat_build(&p->vehicle, u->delta, fx, fy, H), RFE_OK);
        assert_int_equal(rfe_obsmat_apply(H, ones, y), RFE_OK);
    }
    for (r = 0; r < 3; ++r) {
        z[r] = (double)y[r];
    }
}

/* R0 + sum_j g_j g_j^T with g_j = sd_j dh/du_j (docs/ESTIMATOR.md step 4), in double: g_j
 * from rfe_meas_input_jac called here on a model set up here (the derivative itself is tested
 * against central differences of full set-ups in test_meas_flt.c, REQ-MEAS-004); h0 from the
 * tyre and obsmat functions directly. */
static void r_reference(const rfe_params_t *p, const rfe_sample_t *u, const rfe_real_t mu[4],
                        double R[3][3])
{
    const rfe_filter_params_t *fp = &p->filter;
    const rfe_real_t sd[8] = {fp->sd_in_delta, fp->sd_in_vx, fp->sd_in_vy, fp->sd_in_yaw_rate,
                              fp->sd_in_omega, fp->sd_in_omega, fp->sd_in_omega, fp->sd_in_omega};
    const double r[3] = {fp->r_ax, fp->r_ay, fp->r_yaw_acc};
    rfe_meas_t h;
    rfe_real_t G[3 * 8];
    double h0[3];
    size_t i, j, k;
    h_direct(p, u, mu, h0);
    assert_int_equal(rfe_meas_setup(&h, &p->vehicle, &p->tyre, u), RFE_OK);
    assert_int_equal(rfe_meas_input_jac(&h, &p->vehicle, &p->tyre, u, mu, sd, G), RFE_OK);
    memset(R, 0, 9 * sizeof(double));
    for (i = 0; i < 3; ++i) {
        const double e = (double)fp->r_model_rel * fabs(h0[i]);
        R[i][i] = r[i] * r[i] + e * e;
    }
    for (k = 0; k < 8; ++k) {
        if (!(sd[k] > 0)) {
            continue;
        }
        for (i = 0; i < 3; ++i) {
            for (j = 0; j < 3; ++j) {
                R[i][j] += (double)G[i * 8 + k] * (double)G[j * 8 + k];
            }
        }
    }
}

static void check_sr(const rfe_params_t *p, const rfe_sample_t *u, const rfe_real_t mu[4], const char *what)
{
    rfe_real_t SR[9];
    double R[3][3], scale = 0.0;
    size_t i, j, k;
    char msg[96];
    assert_int_equal(rfe_step_noise_sqrt(p, u, mu, SR), RFE_OK);
    r_reference(p, u, mu, R);
    for (i = 0; i < 3; ++i) {
        scale = fmax(scale, fabs(R[i][i]));
        assert_true(SR[i * 3 + i] > 0); /* non-negative diagonal, full rank */
        for (j = i + 1; j < 3; ++j) {
            assert_true(SR[i * 3 + j] == 0); /* lower-triangular */
        }
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            double acc = 0.0;
            for (k = 0; k < 3; ++k) {
                acc += (double)SR[i * 3 + k] * (double)SR[j * 3 + k];
            }
            snprintf(msg, sizeof msg, "%s: (S_R S_R^T)[%zu][%zu]", what, i, j);
            assert_close(acc, R[i][j], TOL_SR * scale, 0.0, msg);
        }
    }
}

/* REQ: S_R S_R^T = R0 + sum_j g_j g_j^T (docs/ESTIMATOR.md step 4), g_j from
 * rfe_meas_input_jac called here, for the absolute and the paper tyre, on a braking, steered,
 * yawing sample; inputs with sd 0 contribute nothing. */
/* REQ-EIV-001 */
static void test_rfe_step_noise_sqrt_reconstructs_r(void **state)
{
    rfe_params_t p = dflt;
    rfe_sample_t u = straight_sample(18.0, -0.06, -0.03);
    const rfe_real_t mu[4] = {(rfe_real_t)0.7, (rfe_real_t)0.4, (rfe_real_t)0.7, (rfe_real_t)0.4};
    (void)state;
    u.delta = (rfe_real_t)0.04;
    u.vy = (rfe_real_t)0.3;
    u.yaw_rate = (rfe_real_t)0.15;
    model_match(&p, &u, mu);
    check_sr(&p, &u, mu, "absolute, default");
    p.filter.sd_in_vy = 0; /* a column fewer */
    p.filter.sd_in_delta = 0;
    check_sr(&p, &u, mu, "absolute, two inputs off");
    p.filter.r_model_rel = 0;
    p.filter.sd_in_omega = (rfe_real_t)0.2;
    check_sr(&p, &u, mu, "absolute, no model error");
    p = dflt;
    p.tyre.mode = RFE_TYRE_PAPER;
    check_sr(&p, &u, mu, "paper tyre");
}

/* REQ: rfe_step_noise_sqrt validates its arguments and leaves SR untouched on error. */
/* REQ-EIV-002 */
static void test_rfe_step_noise_sqrt_errors(void **state)
{
    rfe_params_t p = dflt;
    rfe_sample_t u = straight_sample(18.0, -0.05, -0.05);
    const rfe_real_t mu[4] = {(rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5};
    rfe_real_t bad_mu[4] = {(rfe_real_t)0.5, (rfe_real_t)NAN, (rfe_real_t)0.5, (rfe_real_t)0.5};
    rfe_real_t SR[9], SR_copy[9];
    (void)state;
    memset(SR, 0x3C, sizeof SR);
    memcpy(SR_copy, SR, sizeof SR);
    assert_int_equal(rfe_step_noise_sqrt(NULL, &u, mu, SR), RFE_ERR_NULL);
    assert_int_equal(rfe_step_noise_sqrt(&p, NULL, mu, SR), RFE_ERR_NULL);
    assert_int_equal(rfe_step_noise_sqrt(&p, &u, NULL, SR), RFE_ERR_NULL);
    assert_int_equal(rfe_step_noise_sqrt(&p, &u, mu, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_step_noise_sqrt(&p, &u, bad_mu, SR), RFE_ERR_NONFINITE);
    p.filter.sd_in_vx = -1;
    assert_int_equal(rfe_step_noise_sqrt(&p, &u, mu, SR), RFE_ERR_PARAM);
    p = dflt;
    u.ax = (rfe_real_t)NAN;
    assert_int_equal(rfe_step_noise_sqrt(&p, &u, mu, SR), RFE_ERR_NONFINITE);
    assert_memory_equal(SR, SR_copy, sizeof SR);
}

/* REQ: the measurement model (meas.h) equals H(u) mu in paper mode and the absolute forces'
 * accelerations in absolute mode; bad arguments are rejected. */
/* REQ-MEAS-001 REQ-MEAS-002 */
static void test_rfe_meas_setup_eval(void **state)
{
    rfe_meas_t h, copy;
    rfe_sample_t u = straight_sample(18.0, -0.06, -0.03);
    const rfe_real_t mu[4] = {(rfe_real_t)0.7, (rfe_real_t)0.4, (rfe_real_t)0.6, (rfe_real_t)0.3};
    rfe_real_t z[3];
    double ref[3];
    size_t r;
    int k;
    (void)state;
    /* Zeroed so the padding after h.mode (in double) is defined for the byte comparison
     * below; rfe_meas_setup writes every field but not the padding. */
    memset(&h, 0, sizeof h);
    u.delta = (rfe_real_t)0.03;
    u.yaw_rate = (rfe_real_t)0.1;
    for (k = 0; k < 2; ++k) {
        const rfe_params_t *p = k ? &dflt : &paper;
        assert_int_equal(rfe_meas_setup(&h, &p->vehicle, &p->tyre, &u), RFE_OK);
        assert_int_equal(rfe_meas_eval(&h, &p->vehicle, &p->tyre, mu, z), RFE_OK);
        h_direct(p, &u, mu, ref);
        for (r = 0; r < 3; ++r) {
            assert_true((double)z[r] == ref[r]);
        }
    }
    memcpy(&copy, &h, sizeof h);
    assert_int_equal(rfe_meas_setup(NULL, &dflt.vehicle, &dflt.tyre, &u), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_setup(&h, NULL, &dflt.tyre, &u), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_setup(&h, &dflt.vehicle, NULL, &u), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_setup(&h, &dflt.vehicle, &dflt.tyre, NULL), RFE_ERR_NULL);
    u.vy = (rfe_real_t)NAN;
    assert_int_equal(rfe_meas_setup(&h, &dflt.vehicle, &dflt.tyre, &u), RFE_ERR_NONFINITE);
    assert_int_equal(rfe_meas_setup(&h, &paper.vehicle, &paper.tyre, &u), RFE_ERR_NONFINITE);
    assert_memory_equal(&h, &copy, sizeof h);
    assert_int_equal(rfe_meas_eval(NULL, &dflt.vehicle, &dflt.tyre, mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval(&h, NULL, &dflt.tyre, mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval(&h, &dflt.vehicle, NULL, mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval(&h, &dflt.vehicle, &dflt.tyre, NULL, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval(&h, &dflt.vehicle, &dflt.tyre, mu, NULL), RFE_ERR_NULL);
}

/* ---- steps 5-9: gate, bounds, output --------------------------------------------------- */

/* REQ: cruising (zero slip) carries no information: every step is held (status 3), the mean
 * stays mu0, the sd grows to the sd_max bound and stays there, the estimate is not valid. */
/* REQ-EST-008 */
static void test_rfe_friction_gate_holds_on_cruise(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    rfe_sample_t u = straight_sample(22.0, 0.0, 0.0);
    double sd_prev = 0.0;
    size_t i;
    int k;
    (void)state;
    assert_int_equal(rfe_friction_init(&est, &dflt), RFE_OK);
    assert_int_equal(est.n, 2);
    for (k = 0; k < 200; ++k) {
        assert_int_equal(rfe_friction_step(&est, &u, &out), RFE_HELD_NOT_OBSERVABLE);
        assert_int_equal(out.status, RFE_HELD_NOT_OBSERVABLE);
        for (i = 0; i < 4; ++i) {
            assert_close(out.mu[i], dflt.filter.mu0, 64.0 * EPS_R, 0.0, "held mean");
            assert_true((double)out.sd[i] <= (double)dflt.filter.sd_max * (1.0 + 4.0 * EPS_R));
            assert_int_equal(out.valid[i], 0);
        }
        assert_true((double)out.sd[0] >= sd_prev * (1.0 - 4.0 * EPS_R)); /* grows, never shrinks */
        sd_prev = (double)out.sd[0];
    }
    /* The largest sd lands on sd_max; the other side's differs from it by the rounding its
     * row accumulated (one factor scales both). */
    for (i = 0; i < 4; ++i) {
        assert_close(out.sd[i], dflt.filter.sd_max, 64.0 * EPS_R, 0.0, "sd at the bound");
    }
    assert_string_equal(rfe_status_str(RFE_HELD_NOT_OBSERVABLE), "held: not observable");
    assert_false(rfe_status_is_error(RFE_HELD_NOT_OBSERVABLE));
}

/* REQ: hard braking carries information: the first step updates (status 0 or 1), and a
 * consistent braking sequence (model-matched at mu 0.6, speeds decreasing with ax) converges
 * to 0.6 on every wheel and becomes valid (sd <= sd_valid). */
/* REQ-EST-008 */
static void test_rfe_friction_gate_updates_on_hard_braking(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    const rfe_real_t mu[4] = {(rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6};
    double vx = 25.0;
    rfe_status_t st;
    size_t i;
    int k;
    (void)state;
    assert_int_equal(rfe_friction_init(&est, &dflt), RFE_OK);
    for (k = 0; k < 150; ++k) {
        rfe_sample_t u = straight_sample(vx, -0.12, -0.12);
        model_match(&dflt, &u, mu);
        st = rfe_friction_step(&est, &u, &out);
        if (k == 0) {
            assert_true(st == RFE_OK || st == RFE_PROJECTED);
            assert_true(fabs((double)out.mu[0] - 0.5) > 1e-3); /* the mean moved */
        }
        assert_false(rfe_status_is_error(st));
        vx += (double)u.ax * (double)dflt.filter.dt;
    }
    for (i = 0; i < 4; ++i) {
        assert_close(out.mu[i], 0.6, 0.01, 0.0, "braking mu");
        assert_true(out.sd[i] <= dflt.filter.sd_valid);
        assert_true(out.sd[i] >= dflt.filter.sd_floor_rel * (rfe_real_t)0.59); /* the floor */
        assert_int_equal(out.valid[i], 1);
    }
}

/* REQ: the cap scales the whole S by one factor c = sd_max / max sd_k: the largest sd lands on
 * sd_max, the correlation between the sides is the one without the cap. */
/* REQ-EST-009 */
static void test_rfe_friction_cap_keeps_correlation(void **state)
{
    static rfe_friction_t capped, free_;
    rfe_estimate_t a, b;
    rfe_params_t p = dflt, q;
    rfe_sample_t u = straight_sample(22.0, 0.0, 0.0);
    double ca, cb;
    (void)state;
    p.filter.sd0 = (rfe_real_t)0.2; /* prior sd 0.36 > sd_max 0.32 */
    q = p;
    q.filter.sd_max = 0;
    assert_int_equal(rfe_friction_init(&capped, &p), RFE_OK);
    assert_int_equal(rfe_friction_init(&free_, &q), RFE_OK);
    assert_int_equal(rfe_friction_step(&capped, &u, &a), RFE_HELD_NOT_OBSERVABLE);
    assert_int_equal(rfe_friction_step(&free_, &u, &b), RFE_HELD_NOT_OBSERVABLE);
    assert_true(b.sd[0] > p.filter.sd_max);
    assert_close(a.sd[0], p.filter.sd_max, 4.0 * EPS_R, 0.0, "capped sd");
    assert_close((double)a.sd[1] / (double)b.sd[1], (double)a.sd[0] / (double)b.sd[0], 8.0 * EPS_R, 0.0,
                 "one factor for all");
    ca = correlation(&capped.filter.sckf);
    cb = correlation(&free_.filter.sckf);
    assert_true(cb > 0.5); /* the common mode correlates the sides */
    assert_close(ca, cb, 8.0 * EPS_R, 0.0, "correlation kept");
}

/* REQ: the floor raises sd to sd_floor_rel mu by one factor, correlation kept; with both
 * bounds on, the cap wins (else-if). */
/* REQ-EST-009 */
static void test_rfe_friction_floor_and_priority(void **state)
{
    static rfe_friction_t fl, free_;
    rfe_estimate_t a, b;
    rfe_params_t p = dflt, q;
    rfe_sample_t u = straight_sample(22.0, 0.0, 0.0);
    (void)state;
    p.filter.mu0 = 1; /* floor = sd_floor_rel */
    p.filter.sd0 = (rfe_real_t)0.01;
    p.filter.sd0_common = (rfe_real_t)0.02;
    q = p;
    q.filter.sd_floor_rel = 0;
    assert_int_equal(rfe_friction_init(&fl, &p), RFE_OK);
    assert_int_equal(rfe_friction_init(&free_, &q), RFE_OK);
    assert_int_equal(rfe_friction_step(&fl, &u, &a), RFE_HELD_NOT_OBSERVABLE);
    assert_int_equal(rfe_friction_step(&free_, &u, &b), RFE_HELD_NOT_OBSERVABLE);
    assert_true(b.sd[0] < p.filter.sd_floor_rel);
    assert_close(a.sd[0], p.filter.sd_floor_rel, 4.0 * EPS_R, 0.0, "sd raised to the floor");
    assert_close(correlation(&fl.filter.sckf), correlation(&free_.filter.sckf), 8.0 * EPS_R, 0.0,
                 "correlation kept");
    assert_int_equal(a.valid[0], (a.sd[0] <= p.filter.sd_valid) ? 1 : 0);
    /* Cap below the floor: the cap applies first. */
    p.filter.sd_max = (rfe_real_t)0.05;
    p.filter.sd0 = (rfe_real_t)0.2;
    assert_int_equal(rfe_friction_init(&fl, &p), RFE_OK);
    assert_int_equal(rfe_friction_step(&fl, &u, &a), RFE_HELD_NOT_OBSERVABLE);
    assert_close(a.sd[0], 0.05, 4.0 * EPS_R, 0.0, "cap wins");
    /* Next step: sd 0.05 plus process noise is above the cap again: capped again. */
    assert_int_equal(rfe_friction_step(&fl, &u, &a), RFE_HELD_NOT_OBSERVABLE);
    assert_close(a.sd[0], 0.05, 4.0 * EPS_R, 0.0, "cap wins again");
}

/* REQ: the floor's factor never lifts an sd above sd_max: one side well informed (sd far below
 * its floor), the other near the cap -> c = sd_max / max sd, not f / sd (docs/ESTIMATOR.md
 * step 7; before, reported sd reached 1.0 on split_mu_brake). */
/* REQ-EST-009 */
static void test_rfe_friction_floor_limited_by_cap(void **state)
{
    static rfe_friction_t fl, free_;
    rfe_estimate_t a, b;
    rfe_params_t p = dflt, q;
    rfe_sample_t u = straight_sample(22.0, 0.0, 0.0);
    rfe_real_t *S;
    int k;
    (void)state;
    p.filter.mu0 = 1; /* floor = sd_floor_rel = 0.15 on both sides */
    q = p;
    q.filter.sd_floor_rel = 0;
    q.filter.sd_max = 0;
    assert_int_equal(rfe_friction_init(&fl, &p), RFE_OK);
    assert_int_equal(rfe_friction_init(&free_, &q), RFE_OK);
    /* left side informed (sd 0.01), right side near the cap (sd ~0.30), correlated */
    S = fl.filter.sckf.S;
    S[0] = (rfe_real_t)0.01;
    S[RFE_N_MAX] = (rfe_real_t)0.002;
    S[RFE_N_MAX + 1] = (rfe_real_t)0.30;
    memcpy(free_.filter.sckf.S, S, sizeof fl.filter.sckf.S);
    assert_int_equal(rfe_friction_step(&fl, &u, &a), RFE_HELD_NOT_OBSERVABLE);
    assert_int_equal(rfe_friction_step(&free_, &u, &b), RFE_HELD_NOT_OBSERVABLE);
    assert_true(b.sd[0] < p.filter.sd_floor_rel); /* the floor wants c = 0.15 / 0.01 */
    assert_true(b.sd[1] * (rfe_real_t)1.5 > p.filter.sd_max); /* ... which would break the cap */
    for (k = 0; k < 4; ++k) {
        ASSERT_LE(a.sd[k], (double)p.filter.sd_max * (1.0 + (4.0 * EPS_R)), "sd <= sd_max");
    }
    assert_close(a.sd[1], p.filter.sd_max, 4.0 * EPS_R, 0.0, "the wheel nearest the cap at it");
    assert_true(a.sd[0] > b.sd[0]); /* still lifted towards the floor, by the same factor */
    assert_close((double)a.sd[0] / (double)b.sd[0], (double)a.sd[1] / (double)b.sd[1], 8.0 * EPS_R,
                 0.0, "one factor for all");
    assert_close(correlation(&fl.filter.sckf), correlation(&free_.filter.sckf), 8.0 * EPS_R, 0.0,
                 "correlation kept");
}

/* REQ: structure sides maps fl, rl to the left state and fr, rr to the right one; init gives
 * sd = sqrt(sd0^2 + sd0_common^2) and the exact Cholesky factor of the prior. */
/* REQ-EST-010 */
static void test_rfe_friction_sides_mapping(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    const rfe_real_t mu[4] = {(rfe_real_t)0.8, (rfe_real_t)0.3, (rfe_real_t)0.8, (rfe_real_t)0.3};
    const rfe_sckf_t *f = &est.filter.sckf;
    double p00, p01, p11;
    int k;
    (void)state;
    assert_int_equal(rfe_friction_init(&est, &dflt), RFE_OK);
    assert_int_equal(rfe_friction_get(&est, &out), RFE_OK);
    assert_close(out.sd[0], sqrt(0.1 * 0.1 + 0.3 * 0.3), 4.0 * EPS_R, 0.0, "prior sd");
    p00 = (double)f->S[0] * (double)f->S[0];
    p01 = (double)f->S[0] * (double)f->S[RFE_N_MAX];
    p11 = (double)f->S[RFE_N_MAX] * (double)f->S[RFE_N_MAX] + (double)f->S[RFE_N_MAX + 1] * (double)f->S[RFE_N_MAX + 1];
    assert_close(p00, 0.1, 8.0 * EPS_R, 0.0, "P00 = sd0^2 + sd0_common^2");
    assert_close(p11, 0.1, 8.0 * EPS_R, 0.0, "P11");
    assert_close(p01, 0.09, 8.0 * EPS_R, 0.0, "P01 = sd0_common^2");
    assert_true(f->S[1] == 0);
    for (k = 0; k < 100; ++k) {
        rfe_sample_t u = straight_sample(25.0 - 0.05 * k, -0.1, -0.1);
        model_match(&dflt, &u, mu);
        assert_false(rfe_status_is_error(rfe_friction_step(&est, &u, &out)));
        assert_true(out.mu[RFE_FL] == out.mu[RFE_RL] && out.mu[RFE_FR] == out.mu[RFE_RR]);
        assert_true(out.sd[RFE_FL] == out.sd[RFE_RL] && out.sd[RFE_FR] == out.sd[RFE_RR]);
        /* the same flags, except a rear wheel its side's hold turns off (step 9) */
        assert_int_equal(out.valid[RFE_RL], (est.hold.held[0] != 0u) ? 0u : out.valid[RFE_FL]);
        assert_int_equal(out.valid[RFE_RR], (est.hold.held[1] != 0u) ? 0u : out.valid[RFE_FR]);
    }
    assert_true(out.mu[RFE_FL] > out.mu[RFE_FR] + 0.2); /* split mu seen left vs right */
    /* The same tuning with four states runs and gives per-wheel values. */
    {
        rfe_params_t p = dflt;
        p.filter.structure = RFE_STRUCT_WHEELS;
        assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
        assert_int_equal(est.n, 4);
        for (k = 0; k < 20; ++k) {
            rfe_sample_t u = straight_sample(25.0 - 0.05 * k, -0.1, -0.1);
            model_match(&p, &u, mu);
            assert_false(rfe_status_is_error(rfe_friction_step(&est, &u, &out)));
        }
        assert_true(out.mu[RFE_FL] != out.mu[RFE_RL]);
    }
}

/* REQ: validity: sd_valid > 0 is the sd rule at every status (also for get and at low speed),
 * never on a projection bound; sd_valid = 0 is the paper rule (valid when updated). */
/* REQ-EST-010 */
static void test_rfe_friction_validity_rules(void **state)
{
    static rfe_friction_t est;
    rfe_estimate_t out;
    rfe_params_t p = dflt;
    rfe_sample_t slow = straight_sample(2.0, 0.0, 0.0);
    rfe_sample_t brake = straight_sample(20.0, -0.1, -0.1);
    rfe_sample_t cruise = straight_sample(20.0, 0.0, 0.0);
    const rfe_real_t mu[4] = {(rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6};
    rfe_status_t st;
    (void)state;
    model_match(&dflt, &brake, mu);
    p.filter.sd0 = (rfe_real_t)0.05; /* prior sd 0.07: valid by the sd rule from the start */
    p.filter.sd0_common = (rfe_real_t)0.05;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    assert_int_equal(rfe_friction_get(&est, &out), RFE_OK);
    assert_int_equal(out.valid[0], 1);
    assert_int_equal(rfe_friction_step(&est, &slow, &out), RFE_NO_UPDATE_LOW_SPEED);
    assert_int_equal(out.valid[2], 1);
    /* Never valid on a projection bound (step 9): the same prior at mu_min or mu_max is not
     * valid, a little inside either bound it is (the bound margin off: 0.01 above mu_min is
     * within 3 sd of it; the margin's own tests are test_trust_rules_flt.c's). */
    {
        const rfe_real_t mu0[4] = {p.filter.mu_min, p.filter.mu_max,
                                   p.filter.mu_min + (rfe_real_t)0.01,
                                   p.filter.mu_max - (rfe_real_t)0.01};
        const rfe_real_t keep = p.filter.mu0;
        size_t c;
        p.filter.valid_bound_k = (rfe_real_t)0.0;
        for (c = 0u; c < 4u; ++c) {
            p.filter.mu0 = mu0[c];
            assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
            assert_int_equal(rfe_friction_get(&est, &out), RFE_OK);
            assert_true(out.mu[0] == mu0[c]);
            assert_true(out.sd[0] <= p.filter.sd_valid);
            assert_int_equal(out.valid[0], (c < 2u) ? 0 : 1);
            assert_int_equal(out.valid[3], (c < 2u) ? 0 : 1);
        }
        p.filter.mu0 = keep;
    }
    /* The paper rule with the default tuning: valid only on updating steps. */
    p.filter.sd_valid = 0;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    assert_int_equal(rfe_friction_get(&est, &out), RFE_OK);
    assert_int_equal(out.valid[0], 0);
    st = rfe_friction_step(&est, &brake, &out);
    assert_true(st == RFE_OK || st == RFE_PROJECTED);
    assert_int_equal(out.valid[0], 1);
    assert_int_equal(rfe_friction_step(&est, &cruise, &out), RFE_HELD_NOT_OBSERVABLE);
    assert_int_equal(out.valid[0], 0);
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    assert_int_equal(rfe_friction_step(&est, &slow, &out), RFE_NO_UPDATE_LOW_SPEED);
    assert_int_equal(out.valid[0], 0);
    /* The CKF accepts any sd_valid (an output rule). */
    p = paper;
    p.filter.kind = RFE_FILTER_CKF;
    p.filter.sd_valid = 1;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    assert_int_equal(rfe_friction_step(&est, &slow, &out), RFE_NO_UPDATE_LOW_SPEED);
    assert_int_equal(out.valid[1], 1);
}

/* ---- parameters ------------------------------------------------------------------------ */

/* REQ: both presets validate; every new key is rejected when negative or non-finite
 * (dt also at 0), one rejection per key, and 0 (off) is accepted where allowed. */
/* REQ-PARAMS-002 */
static void test_rfe_params_validate_new_keys(void **state)
{
    rfe_params_t p;
    size_t k;
    rfe_real_t *fields[14];
    (void)state;
    assert_int_equal(rfe_params_validate(&dflt), RFE_OK);
    assert_int_equal(rfe_params_validate(&paper), RFE_OK);
    assert_int_equal(rfe_params_paper(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_params_default(NULL), RFE_ERR_NULL);
    p = dflt;
    fields[0] = &p.filter.sd0_common;
    fields[1] = &p.filter.q_common;
    fields[2] = &p.filter.dt;
    fields[3] = &p.filter.tau_v;
    fields[4] = &p.filter.sd_in_delta;
    fields[5] = &p.filter.sd_in_vx;
    fields[6] = &p.filter.sd_in_vy;
    fields[7] = &p.filter.sd_in_yaw_rate;
    fields[8] = &p.filter.sd_in_omega;
    fields[9] = &p.filter.r_model_rel;
    fields[10] = &p.filter.info_min;
    fields[11] = &p.filter.sd_max;
    fields[12] = &p.filter.sd_floor_rel;
    fields[13] = &p.filter.sd_valid;
    for (k = 0; k < 14; ++k) {
        const rfe_real_t keep = *fields[k];
        char what[32];
        snprintf(what, sizeof what, "field %zu", k);
        *fields[k] = (rfe_real_t)-0.001;
        if (rfe_params_validate(&p) != RFE_ERR_PARAM) {
            fail_msg("%s: negative accepted", what);
        }
        *fields[k] = (rfe_real_t)NAN;
        if (rfe_params_validate(&p) != RFE_ERR_PARAM) {
            fail_msg("%s: NaN accepted", what);
        }
        *fields[k] = (rfe_real_t)INFINITY;
        if (rfe_params_validate(&p) != RFE_ERR_PARAM) {
            fail_msg("%s: Inf accepted", what);
        }
        *fields[k] = 0;
        if (rfe_params_validate(&p) != ((k == 2) ? RFE_ERR_PARAM : RFE_OK)) {
            fail_msg("%s: 0 handled wrongly", what);
        }
        *fields[k] = keep;
    }
    p.filter.structure = (rfe_structure_t)2;
    assert_int_equal(rfe_params_validate(&p), RFE_ERR_PARAM);
    p = dflt;
    p.filter.sd_max = (rfe_real_t)1e-3; /* any positive bound */
    assert_int_equal(rfe_params_validate(&p), RFE_OK);
}

/* REQ: the CKF runs only the paper subset: the paper preset with any tyre, any dt and any
 * sd_valid is accepted; each addition alone is rejected; the default preset is rejected. */
/* REQ-PARAMS-003 */
static void test_rfe_params_validate_ckf_subset(void **state)
{
    rfe_params_t p;
    rfe_real_t *fields[13];
    size_t k;
    (void)state;
    p = paper;
    p.filter.kind = RFE_FILTER_CKF;
    p.tyre.mode = RFE_TYRE_ABSOLUTE;
    p.filter.dt = (rfe_real_t)0.02;
    p.filter.sd_valid = (rfe_real_t)0.1;
    assert_int_equal(rfe_params_validate(&p), RFE_OK);
    fields[0] = &p.filter.sd0_common;
    fields[1] = &p.filter.q_common;
    fields[2] = &p.filter.tau_v;
    fields[3] = &p.filter.sd_in_delta;
    fields[4] = &p.filter.sd_in_vx;
    fields[5] = &p.filter.sd_in_vy;
    fields[6] = &p.filter.sd_in_yaw_rate;
    fields[7] = &p.filter.sd_in_omega;
    fields[8] = &p.filter.r_model_rel;
    fields[9] = &p.filter.info_min;
    fields[10] = &p.filter.sd_max;
    fields[11] = &p.filter.sd_floor_rel;
    fields[12] = &p.filter.sd0; /* control: not an addition, any positive value */
    for (k = 0; k < 13; ++k) {
        const rfe_real_t keep = *fields[k];
        *fields[k] = (rfe_real_t)0.5;
        if (rfe_params_validate(&p) != ((k == 12) ? RFE_OK : RFE_ERR_PARAM)) {
            fail_msg("CKF subset: field %zu", k);
        }
        p.filter.kind = RFE_FILTER_SCKF; /* the same value is fine for the SCKF */
        assert_int_equal(rfe_params_validate(&p), RFE_OK);
        p.filter.kind = RFE_FILTER_CKF;
        *fields[k] = keep;
    }
    p.filter.structure = RFE_STRUCT_SIDES;
    assert_int_equal(rfe_params_validate(&p), RFE_ERR_PARAM);
    p = dflt;
    p.filter.kind = RFE_FILTER_CKF;
    assert_int_equal(rfe_params_validate(&p), RFE_ERR_PARAM);
}

/* REQ: the paper preset has every addition off and its prior is exactly sd0 I (no
 * Cholesky); the default preset has the docs/ESTIMATOR.md values. */
/* REQ-PARAMS-001 */
static void test_rfe_params_presets(void **state)
{
    static rfe_friction_t est;
    size_t i, j;
    (void)state;
    assert_int_equal(paper.filter.structure, RFE_STRUCT_WHEELS);
    assert_int_equal(paper.tyre.mode, RFE_TYRE_PAPER);
    assert_true(paper.filter.sd0_common == 0 && paper.filter.q_common == 0 && paper.filter.tau_v == 0 &&
                paper.filter.sd_in_delta == 0 && paper.filter.sd_in_vx == 0 && paper.filter.sd_in_vy == 0 &&
                paper.filter.sd_in_yaw_rate == 0 && paper.filter.sd_in_omega == 0 &&
                paper.filter.r_model_rel == 0 && paper.filter.info_min == 0 && paper.filter.sd_max == 0 &&
                paper.filter.sd_floor_rel == 0 && paper.filter.sd_valid == 0);
    assert_true(paper.filter.dt == (rfe_real_t)0.01);
    assert_int_equal(dflt.filter.structure, RFE_STRUCT_SIDES);
    assert_int_equal(dflt.tyre.mode, RFE_TYRE_MAGIC);
    assert_true(dflt.tyre.shape_Cx == (rfe_real_t)1.65 && dflt.tyre.shape_Ex == 0 &&
                dflt.tyre.shape_Cy == (rfe_real_t)1.3 && dflt.tyre.shape_Ey == 0);
    assert_true(paper.tyre.shape_Cx == dflt.tyre.shape_Cx && paper.tyre.shape_Ey == dflt.tyre.shape_Ey);
    assert_true(dflt.filter.sd0 == (rfe_real_t)0.1 && dflt.filter.sd0_common == (rfe_real_t)0.3);
    assert_true(dflt.filter.q_mu == (rfe_real_t)0.002 && dflt.filter.q_common == (rfe_real_t)0.006);
    assert_true(dflt.filter.dt == (rfe_real_t)0.01 && dflt.filter.tau_v == (rfe_real_t)0.3);
    assert_true(dflt.filter.sd_in_delta == (rfe_real_t)0.001 && dflt.filter.sd_in_vx == (rfe_real_t)0.01 &&
                dflt.filter.sd_in_vy == (rfe_real_t)0.01 && dflt.filter.sd_in_yaw_rate == (rfe_real_t)0.005 &&
                dflt.filter.sd_in_omega == (rfe_real_t)0.05);
    assert_true(dflt.filter.r_model_rel == (rfe_real_t)0.05 && dflt.filter.info_min == (rfe_real_t)25 &&
                dflt.filter.sd_max == (rfe_real_t)0.32 && dflt.filter.sd_floor_rel == (rfe_real_t)0.15 &&
                dflt.filter.sd_valid == (rfe_real_t)0.15);
    assert_int_equal(rfe_friction_init(&est, &paper), RFE_OK);
    for (i = 0; i < 4; ++i) {
        for (j = 0; j <= i; ++j) {
            assert_true(est.filter.sckf.S[i * RFE_N_MAX + j] == ((i == j) ? paper.filter.sd0 : 0));
            assert_true(est.filter.sckf.SQ[i * RFE_N_MAX + j] == ((i == j) ? paper.filter.q_mu : 0));
        }
    }
}

/* ---- rollback ---------------------------------------------------------------------------- */

/* REQ: a step that fails inside the filter (a prior so large that its cross-covariance
 * overflows) restores the filter and the input filter as they were; the estimator then
 * behaves exactly like a copy taken before the failing step. */
/* REQ-EST-005 */
static void test_rfe_friction_rollback_with_conditioner(void **state)
{
    static rfe_friction_t est, copy;
    rfe_estimate_t out, out_copy;
    rfe_params_t p = dflt;
    rfe_sample_t slow = straight_sample(2.0, 0.0, 0.0);
    rfe_sample_t fast = straight_sample(20.0, -0.1, -0.1);
    rfe_status_t st;
    (void)state;
    p.tyre.mode = RFE_TYRE_PAPER; /* h = H x: huge x, huge z */
    p.filter.sd0 = (rfe_real_t)HUGE_SD0;
    p.filter.sd0_common = 0;      /* S0 = sd0 I: no squares at init */
    p.filter.tau_v = (rfe_real_t)0.001; /* b = 0.91: the fast sample is fast at once */
    p.filter.sd_max = 0;
    p.filter.sd_floor_rel = 0;
    fast.ax = -5;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    slow.ax = (rfe_real_t)-0.5;
    assert_int_equal(rfe_friction_step(&est, &slow, &out), RFE_NO_UPDATE_LOW_SPEED);
    assert_int_equal(rfe_friction_step(&est, &slow, &out), RFE_NO_UPDATE_LOW_SPEED);
    assert_int_equal(est.cond.started, 1);
    assert_true(est.cond.vx != slow.vx); /* the input filter has a state of its own */
    copy = est;
    st = rfe_friction_step(&est, &fast, &out);
    assert_true(rfe_status_is_error(st));
    assert_int_equal(out.status, st);
    assert_int_equal(out.valid[0], 0);
    assert_memory_equal(&est.cond, &copy.cond, sizeof est.cond);
    assert_memory_equal(est.filter.sckf.x, copy.filter.sckf.x, sizeof est.filter.sckf.x);
    assert_memory_equal(est.filter.sckf.S, copy.filter.sckf.S, sizeof est.filter.sckf.S);
    /* The next good step is the same as the copy's. */
    assert_int_equal(rfe_friction_step(&est, &slow, &out), RFE_NO_UPDATE_LOW_SPEED);
    assert_int_equal(rfe_friction_step(&copy, &slow, &out_copy), RFE_NO_UPDATE_LOW_SPEED);
    assert_memory_equal(&est.cond, &copy.cond, sizeof est.cond);
    assert_memory_equal(est.filter.sckf.x, copy.filter.sckf.x, sizeof est.filter.sckf.x);
    assert_memory_equal(est.filter.sckf.S, copy.filter.sckf.S, sizeof est.filter.sckf.S);
    /* A rejected sample touches nothing at all, conditioner included. */
    copy = est;
    fast.vx = (rfe_real_t)NAN;
    assert_int_equal(rfe_friction_step(&est, &fast, &out), RFE_ERR_NONFINITE);
    assert_memory_equal(&est, &copy, sizeof est);
}

/* REQ: a prior whose common-mode part so dominates that its covariance is singular in the
 * working precision (float: sd0_common / sd0 = 1e11; double: 1e17) is refused at init with
 * RFE_ERR_NOT_POSITIVE_DEFINITE (friction.h), the estimator untouched (found by fuzz_csv). */
/* REQ-EST-002 */
static void test_rfe_friction_singular_prior_refused(void **state)
{
    static rfe_friction_t est, copy;
    rfe_params_t p = dflt;
    (void)state;
    p.filter.sd0 = (rfe_real_t)0.1;
#if defined(RFE_REAL_DOUBLE)
    p.filter.sd0_common = (rfe_real_t)1e16;
#else
    p.filter.sd0_common = (rfe_real_t)1e10;
#endif
    memset(&est, 0x5A, sizeof est);
    copy = est;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_memory_equal(&est, &copy, sizeof est);
    p.filter.sd0_common = (rfe_real_t)3.0; /* a ratio of 30 (the default preset: 3) is fine */
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
}

/* REQ: with sd_max on, a prior whose row norms overflow is an error (not a scale to zero). */
/* REQ-EST-009 */
static void test_rfe_friction_bounds_reject_overflowing_sd(void **state)
{
    static rfe_friction_t est, copy;
    rfe_estimate_t out;
    rfe_params_t p = dflt;
    rfe_sample_t slow = straight_sample(2.0, 0.0, 0.0);
    (void)state;
    p.filter.sd0 = (rfe_real_t)HUGE_SD0;
    /* With a common-mode part the prior's Cholesky squares sd0: refused at init, untouched. */
    memset(&est, 0x5A, sizeof est);
    copy = est;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_ERR_NONFINITE);
    assert_memory_equal(&est, &copy, sizeof est);
    p.filter.sd0_common = 0;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    copy = est;
    assert_int_equal(rfe_friction_step(&est, &slow, &out), RFE_ERR_NONFINITE);
    assert_memory_equal(est.filter.sckf.S, copy.filter.sckf.S, sizeof est.filter.sckf.S);
    assert_memory_equal(&est.cond, &copy.cond, sizeof est.cond);
}

/* (M M^T)_ij in double of a factor M with ld RFE_N_MAX (the SCKF's S: P; its S_Q: Q). */
static double outer_ij(const rfe_real_t *M, size_t i, size_t j)
{
    double acc = 0.0;
    size_t k;
    for (k = 0u; k < (size_t)RFE_N_MAX; ++k) {
        acc += (double)M[(i * RFE_N_MAX) + k] * (double)M[(j * RFE_N_MAX) + k];
    }
    return acc;
}

/* REQ: a gap (rfe_friction_skip, ESTIMATOR.md "Gaps"): missed = 0 changes nothing; with the
 * sd bounds off, P = P0 + k Q (the random walk's k time updates; TOL_CF relative: one Tria
 * of a 2n-column array) and the mean held bit for bit; a gap of any length ends at the
 * prior's variance (default: not valid); the input filter restarts and the next sample
 * seeds it; the paper CKF's P grows by k Q; NULL, an uninitialised estimator and a failing
 * filter (a factor made non-finite by hand) are refused with the estimator untouched. */
/* REQ-EST-015 */
static void test_rfe_friction_skip(void **state)
{
    static rfe_friction_t est;
    static rfe_friction_t copy;
    rfe_params_t p = dflt;
    rfe_estimate_t out;
    rfe_sample_t brake = straight_sample(20.0, -0.1, -0.1);
    const rfe_real_t mu[4] = {(rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6};
    double p0[2][2];
    size_t i;
    size_t j;
    int k;
    (void)state;
    model_match(&dflt, &brake, mu);
    p.filter.sd_max = 0; /* bounds off: the exact random walk */
    p.filter.sd_floor_rel = 0;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    for (k = 0; k < 30; ++k) {
        assert_false(rfe_status_is_error(rfe_friction_step(&est, &brake, &out)));
    }
    copy = est;
    assert_int_equal(rfe_friction_skip(&est, 0u), RFE_OK);
    assert_memory_equal(est.filter.sckf.S, copy.filter.sckf.S, sizeof est.filter.sckf.S);
    assert_int_equal(est.cond.started, 1u);
    for (i = 0u; i < 2u; ++i) {
        for (j = 0u; j < 2u; ++j) {
            p0[i][j] = outer_ij(est.filter.sckf.S, i, j);
        }
    }
    assert_int_equal(rfe_friction_skip(&est, 50u), RFE_OK);
    assert_memory_equal(est.filter.sckf.x, copy.filter.sckf.x, sizeof est.filter.sckf.x);
    for (i = 0u; i < 2u; ++i) {
        for (j = 0u; j < 2u; ++j) {
            const double want = p0[i][j] + (50.0 * outer_ij(est.filter.sckf.SQ, i, j));
            assert_close(outer_ij(est.filter.sckf.S, i, j), want, TOL_CF, 0.0, "P + k Q");
        }
    }
    assert_int_equal(est.cond.started, 0u); /* restarted: the next sample seeds it */
    assert_false(rfe_status_is_error(rfe_friction_step(&est, &brake, &out)));
    assert_true(est.cond.vx == brake.vx);

    /* a gap of any length stops where a state's variance reaches the prior's (sd0^2 +
     * sd0_common^2), within one period's Q_ii below it (the count is floored; 16 eps: the
     * sums of squares); a second gap then adds nothing; the default preset: not valid */
    for (k = 0; k < 3; ++k) {
        const rfe_params_t *base = (k == 0) ? &dflt : &paper;
        const double prior = ((double)base->filter.sd0 * (double)base->filter.sd0) +
                             ((double)base->filter.sd0_common * (double)base->filter.sd0_common);
        const double q = ((double)base->filter.q_mu * (double)base->filter.q_mu) +
                         ((double)base->filter.q_common * (double)base->filter.q_common);
        rfe_estimate_t again;
        p = *base;
        p.filter.kind = (k == 2) ? RFE_FILTER_CKF : RFE_FILTER_SCKF;
        assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
        for (i = 0u; i < 30u; ++i) {
            assert_false(rfe_status_is_error(rfe_friction_step(&est, &brake, &out)));
        }
        assert_int_equal(rfe_friction_skip(&est, UINT32_MAX), RFE_OK);
        assert_int_equal(rfe_friction_get(&est, &out), RFE_OK);
        {
            double top = 0.0; /* the state that limits the count */
            for (i = 0u; i < 4u; ++i) {
                const double var = (double)out.sd[i] * (double)out.sd[i];
                ASSERT_LE(var, prior * (1.0 + (16.0 * EPS_R)), "at most the prior's variance");
                top = fmax(top, var);
                assert_true((k != 0) || (out.valid[i] == 0));
            }
            ASSERT_LE(prior - top, (q * (1.0 + (16.0 * EPS_R))) + (16.0 * EPS_R * prior),
                      "the limiting state within one period of it");
        }
        assert_int_equal(rfe_friction_skip(&est, UINT32_MAX), RFE_OK);
        assert_int_equal(rfe_friction_get(&est, &again), RFE_OK);
        assert_memory_equal(again.sd, out.sd, sizeof out.sd);
    }

    /* the paper CKF: P + k Q */
    p = paper;
    p.filter.kind = RFE_FILTER_CKF;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    for (i = 0u; i < 30u; ++i) { /* below the prior's variance first: room for the gap */
        assert_false(rfe_status_is_error(rfe_friction_step(&est, &brake, &out)));
    }
    copy = est;
    assert_int_equal(rfe_friction_skip(&est, 9u), RFE_OK);
    assert_close(est.filter.ckf.P[0], copy.filter.ckf.P[0] + (9.0 * (double)est.filter.ckf.Q[0]),
                 4.0 * EPS_R, 0.0, "CKF P + k Q");

    /* refused, untouched */
    assert_int_equal(rfe_friction_skip(NULL, 1u), RFE_ERR_NULL);
    memset(&copy, 0, sizeof copy);
    assert_int_equal(rfe_friction_skip(&copy, 1u), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_friction_init(&est, &dflt), RFE_OK);
    est.filter.sckf.S[0] = (rfe_real_t)INFINITY; /* a corrupted factor: Tria refuses it */
    copy = est;
    assert_int_equal(rfe_friction_skip(&est, 3u), RFE_ERR_NONFINITE);
    assert_memory_equal(est.filter.sckf.S, copy.filter.sckf.S, sizeof est.filter.sckf.S);
    assert_memory_equal(&est.cond, &copy.cond, sizeof est.cond);
}

/* REQ: the periods a gap misses (rfe_friction_missed, rfe/common.h): none up to 2 dt (jitter,
 * one dropped sample; widened by 2^-20 for the stamps' rounding), else round(period / dt) - 1,
 * capped at UINT32_MAX; a period not finite or negative is refused with the output untouched.
 * The expected counts are worked out by hand from the rule at dt = 0.01 s (the default). */
/* REQ-EST-015 */
static void test_rfe_friction_missed(void **state)
{
    static rfe_friction_t est;
    static rfe_friction_t blank;
    const struct {
        double period;
        uint32_t want;
    } cases[] = {
        {0.0, 0u}, {0.01, 0u}, {0.0199, 0u}, {0.02, 0u}, /* 2 periods: still jitter */
        {0.02 * (1.0 + 1e-4), 1u},                         /* beyond the stamps' rounding */
        {0.0305, 2u}, {0.0349, 2u}, {0.0351, 3u}, {0.05, 4u}, {0.48, 47u}, {2.0, 199u},
        {1e12, UINT32_MAX}, {1e30, UINT32_MAX},
    };
    uint32_t missed = 7u;
    size_t i;
    (void)state;
    assert_int_equal(rfe_friction_init(&est, &dflt), RFE_OK);
    for (i = 0u; i < sizeof cases / sizeof cases[0]; ++i) {
        assert_int_equal(rfe_friction_missed(&est, (rfe_real_t)cases[i].period, &missed), RFE_OK);
        if (missed != cases[i].want) {
            fail_msg("period %g: %u missed, want %u", cases[i].period, (unsigned)missed,
                     (unsigned)cases[i].want);
        }
    }
    missed = 7u;
    assert_int_equal(rfe_friction_missed(&est, (rfe_real_t)NAN, &missed), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_missed(&est, (rfe_real_t)INFINITY, &missed), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_missed(&est, (rfe_real_t)-0.01, &missed), RFE_ERR_RANGE);
    assert_int_equal(missed, 7u);
    assert_int_equal(rfe_friction_missed(NULL, (rfe_real_t)0.5, &missed), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_missed(&est, (rfe_real_t)0.5, NULL), RFE_ERR_NULL);
    memset(&blank, 0, sizeof blank);
    assert_int_equal(rfe_friction_missed(&blank, (rfe_real_t)0.5, &missed), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(missed, 7u);
}

/* The filter's mean and factor, the input filter and the monitor of two estimators agree bit
 * for bit (their backups may differ: they hold the state before different calls). */
static void assert_same_filter(const rfe_friction_t *a, const rfe_friction_t *b)
{
    assert_memory_equal(a->filter.sckf.x, b->filter.sckf.x, sizeof a->filter.sckf.x);
    assert_memory_equal(a->filter.sckf.S, b->filter.sckf.S, sizeof a->filter.sckf.S);
    assert_memory_equal(&a->cond, &b->cond, sizeof a->cond);
    assert_memory_equal(&a->mon, &b->mon, sizeof a->mon);
}

/* REQ: one step after a gap (rfe_friction_step_after) is rfe_friction_skip then
 * rfe_friction_step, bit for bit, in the default preset and the paper CKF; a rejected sample
 * (NaN) or a failing filter (a factor made non-finite by hand) after a gap leaves the
 * estimator as it was before the gap's time updates too; NULL and an uninitialised
 * estimator are refused. */
/* REQ-EST-015 */
static void test_rfe_friction_step_after(void **state)
{
    static rfe_friction_t a;
    static rfe_friction_t b;
    static rfe_friction_t before;
    rfe_estimate_t oa;
    rfe_estimate_t ob;
    rfe_params_t p = dflt;
    rfe_sample_t brake = straight_sample(20.0, -0.1, -0.1);
    rfe_sample_t bad;
    const rfe_real_t mu[4] = {(rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6, (rfe_real_t)0.6};
    int k;
    int cfg;
    (void)state;
    model_match(&dflt, &brake, mu);
    for (cfg = 0; cfg < 2; ++cfg) {
        p = (cfg == 0) ? dflt : paper;
        p.filter.kind = (cfg == 0) ? RFE_FILTER_SCKF : RFE_FILTER_CKF;
        assert_int_equal(rfe_friction_init(&a, &p), RFE_OK);
        for (k = 0; k < 30; ++k) {
            assert_false(rfe_status_is_error(rfe_friction_step(&a, &brake, &oa)));
        }
        b = a;
        assert_int_equal(rfe_friction_skip(&b, 12u), RFE_OK);
        assert_int_equal(rfe_friction_step(&b, &brake, &ob), rfe_friction_step_after(&a, 12u, &brake, &oa));
        assert_memory_equal(&oa, &ob, sizeof oa);
        if (cfg == 0) {
            assert_same_filter(&a, &b);
        } else {
            assert_memory_equal(a.filter.ckf.x, b.filter.ckf.x, sizeof a.filter.ckf.x);
            assert_memory_equal(a.filter.ckf.P, b.filter.ckf.P, sizeof a.filter.ckf.P);
        }
        /* missed = 0: rfe_friction_step itself */
        b = a;
        assert_int_equal(rfe_friction_step(&b, &brake, &ob), rfe_friction_step_after(&a, 0u, &brake, &oa));
        assert_memory_equal(&oa, &ob, sizeof oa);
    }

    /* a rejected sample after a gap: nothing changed, the gap's time updates included */
    assert_int_equal(rfe_friction_init(&a, &dflt), RFE_OK);
    for (k = 0; k < 30; ++k) {
        assert_false(rfe_status_is_error(rfe_friction_step(&a, &brake, &oa)));
    }
    before = a;
    bad = brake;
    bad.ax = (rfe_real_t)NAN;
    assert_int_equal(rfe_friction_step_after(&a, 40u, &bad, &oa), RFE_ERR_NONFINITE);
    assert_memory_equal(&a, &before, sizeof a);
    /* a filter that fails in the gap's time updates: undone */
    a.filter.sckf.S[0] = (rfe_real_t)INFINITY;
    before = a;
    assert_int_equal(rfe_friction_step_after(&a, 40u, &brake, &oa), RFE_ERR_NONFINITE);
    assert_same_filter(&a, &before);
    assert_int_equal(oa.status, RFE_ERR_NONFINITE);

    assert_int_equal(rfe_friction_step_after(NULL, 1u, &brake, &oa), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_step_after(&a, 1u, NULL, &oa), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_step_after(&a, 1u, &brake, NULL), RFE_ERR_NULL);
    memset(&b, 0, sizeof b);
    assert_int_equal(rfe_friction_step_after(&b, 1u, &brake, &oa), RFE_ERR_NOT_INITIALISED);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_conditioner_hand_example),
        cmocka_unit_test(test_rfe_conditioner_off_and_errors),
        cmocka_unit_test(test_rfe_friction_uses_filtered_speed),
        cmocka_unit_test(test_rfe_step_noise_sqrt_reconstructs_r),
        cmocka_unit_test(test_rfe_step_noise_sqrt_errors),
        cmocka_unit_test(test_rfe_meas_setup_eval),
        cmocka_unit_test(test_rfe_friction_gate_holds_on_cruise),
        cmocka_unit_test(test_rfe_friction_gate_updates_on_hard_braking),
        cmocka_unit_test(test_rfe_friction_cap_keeps_correlation),
        cmocka_unit_test(test_rfe_friction_floor_and_priority),
        cmocka_unit_test(test_rfe_friction_floor_limited_by_cap),
        cmocka_unit_test(test_rfe_friction_sides_mapping),
        cmocka_unit_test(test_rfe_friction_validity_rules),
        cmocka_unit_test(test_rfe_params_validate_new_keys),
        cmocka_unit_test(test_rfe_params_validate_ckf_subset),
        cmocka_unit_test(test_rfe_params_presets),
        cmocka_unit_test(test_rfe_friction_rollback_with_conditioner),
        cmocka_unit_test(test_rfe_friction_bounds_reject_overflowing_sd),
        cmocka_unit_test(test_rfe_friction_singular_prior_refused),
        cmocka_unit_test(test_rfe_friction_skip),
        cmocka_unit_test(test_rfe_friction_missed),
        cmocka_unit_test(test_rfe_friction_step_after),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
