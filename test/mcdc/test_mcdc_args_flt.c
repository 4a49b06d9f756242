/**
 * @file test_mcdc_args_flt.c
 * @brief MC/DC of the argument checks: one bad argument at a time.
 *
 * The library's checks are decisions of several conditions, `(a == NULL) || (b == NULL) ||
 * …` or `!finite(x) || !finite(y) || …`. The module tests reject a bad argument, but often
 * the first one only, which leaves the other conditions without an independence pair (make
 * mcdc, build/mcdc/gaps.md). Here every argument is made bad on its own, all others valid,
 * so each condition alone flips the decision: each call must return the documented error and
 * leave every output (and the state) bit-for-bit untouched; the all-valid call, the other
 * half of each pair, must succeed. The parameter validator gets the same treatment field by
 * field, and the estimator's "errors in variables on?" decision one input-noise key at a time
 * (each alone must change the step's sd). Last, the parameter converter to Q formats in this
 * build's precision (the q31 tests call only the double one): its four outcomes.
 *
 * No tolerances: statuses are exact and "untouched" is compared with memcmp.
 */
#include "test_common.h"

#include <float.h>
#include <string.h>

#include "rfe/component/ckf.h"
#include "rfe/component/conditioner.h"
#include "rfe/component/step_noise.h"
#include "rfe/friction.h"
#include "rfe/component/obsmat.h"
#include "rfe/params.h"
#include "rfe/component/params_conv.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre.h"

#if defined(RFE_REAL_DOUBLE)
#define REAL_BIG DBL_MAX
#else
#define REAL_BIG FLT_MAX
#endif

static rfe_params_t paper; /* rfe_params_paper */
static rfe_params_t dflt;  /* rfe_params_default */

static int setup(void **state)
{
    (void)state;
    if ((rfe_params_paper(&paper) != RFE_OK) || (rfe_params_default(&dflt) != RFE_OK)) {
        return -1;
    }
    return 0;
}

static rfe_real_t nan_r(void) { return (rfe_real_t)NAN; }

/* A gentle braking sample at 20 m/s, slight steer (every slip and angle nonzero). */
static rfe_sample_t good_sample(void)
{
    rfe_sample_t u;
    memset(&u, 0, sizeof u);
    u.delta = (rfe_real_t)0.02;
    u.vx = (rfe_real_t)20.0;
    u.vy = (rfe_real_t)0.1;
    u.yaw_rate = (rfe_real_t)0.05;
    u.yaw_acc = (rfe_real_t)0.01;
    u.ax = (rfe_real_t)-2.0;
    u.ay = (rfe_real_t)1.0;
    u.omega[RFE_FL] = (rfe_real_t)(20.0 * 0.97 / 0.325);
    u.omega[RFE_FR] = (rfe_real_t)(20.0 * 0.98 / 0.325);
    u.omega[RFE_RL] = (rfe_real_t)(20.0 * 0.985 / 0.325);
    u.omega[RFE_RR] = (rfe_real_t)(20.0 * 0.99 / 0.325);
    return u;
}

/* Kinematics of the good sample (asserted to succeed). */
static rfe_wheel_kin_t good_kin(void)
{
    rfe_sample_t u = good_sample();
    rfe_wheel_kin_t kin;
    assert_int_equal(rfe_tyre_kinematics(&paper.vehicle, &paper.tyre, &u, &kin), RFE_OK);
    return kin;
}

/* REQ-TYRE-006 */
static void test_mcdc_tyre_kinematics_each_argument(void **state)
{
    const rfe_sample_t good = good_sample();
    rfe_wheel_kin_t kin, before;
    rfe_sample_t u;
    size_t f;
    (void)state;
    memset(&kin, 0x5a, sizeof kin);
    before = kin;
    assert_int_equal(rfe_tyre_kinematics(NULL, &paper.tyre, &good, &kin), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_kinematics(&paper.vehicle, NULL, &good, &kin), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_kinematics(&paper.vehicle, &paper.tyre, NULL, &kin), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_kinematics(&paper.vehicle, &paper.tyre, &good, NULL), RFE_ERR_NULL);
    assert_memory_equal(&kin, &before, sizeof kin);
    /* every field of the sample non-finite on its own: delta, vx, vy, yaw_rate, yaw_acc (not
     * an input of the kinematics: accepted), ax, ay, omega[0..3] */
    for (f = 0u; f < 7u + (size_t)RFE_WHEELS; ++f) {
        rfe_real_t *field[7 + RFE_WHEELS];
        u = good;
        field[0] = &u.delta;
        field[1] = &u.vx;
        field[2] = &u.vy;
        field[3] = &u.yaw_rate;
        field[4] = &u.yaw_acc;
        field[5] = &u.ax;
        field[6] = &u.ay;
        field[7] = &u.omega[0];
        field[8] = &u.omega[1];
        field[9] = &u.omega[2];
        field[10] = &u.omega[3];
        *field[f] = nan_r();
        if (f == 4u) {
            assert_int_equal(rfe_tyre_kinematics(&paper.vehicle, &paper.tyre, &u, &kin), RFE_OK);
            memset(&kin, 0x5a, sizeof kin);
        } else {
            assert_int_equal(rfe_tyre_kinematics(&paper.vehicle, &paper.tyre, &u, &kin),
                             RFE_ERR_NONFINITE);
            assert_memory_equal(&kin, &before, sizeof kin);
        }
    }
    assert_int_equal(rfe_tyre_kinematics(&paper.vehicle, &paper.tyre, &good, &kin), RFE_OK);
}

/* REQ-TYRE-006 */
static void test_mcdc_tyre_dugoff_each_argument(void **state)
{
    const rfe_wheel_kin_t k = good_kin();
    const rfe_real_t ka = k.kappa[0], al = k.alpha[0], fz = k.fz[0], vw = k.vwx[0];
    const rfe_real_t n = nan_r();
    rfe_real_t a = (rfe_real_t)7, b = (rfe_real_t)8;
    int mode;
    (void)state;
    for (mode = 0; mode < 2; ++mode) {
        /* the two single-wheel functions share the checks (check_wheel) */
#define DUG(tp, k_, a_, f_, v_, o1, o2)                                                        \
    ((mode == 0) ? rfe_tyre_dugoff_norm((tp), (k_), (a_), (f_), (v_), (o1), (o2))      \
                 : rfe_tyre_dugoff_abs((tp), (k_), (a_), (f_), (v_), (rfe_real_t)0.5, (o1), (o2)))
        assert_int_equal(DUG(NULL, ka, al, fz, vw, &a, &b), RFE_ERR_NULL);
        assert_int_equal(DUG(&paper.tyre, ka, al, fz, vw, NULL, &b), RFE_ERR_NULL);
        assert_int_equal(DUG(&paper.tyre, ka, al, fz, vw, &a, NULL), RFE_ERR_NULL);
        assert_int_equal(DUG(&paper.tyre, n, al, fz, vw, &a, &b), RFE_ERR_NONFINITE);
        assert_int_equal(DUG(&paper.tyre, ka, n, fz, vw, &a, &b), RFE_ERR_NONFINITE);
        assert_int_equal(DUG(&paper.tyre, ka, al, n, vw, &a, &b), RFE_ERR_NONFINITE);
        assert_int_equal(DUG(&paper.tyre, ka, al, fz, n, &a, &b), RFE_ERR_NONFINITE);
        assert_true((a == (rfe_real_t)7) && (b == (rfe_real_t)8));
        assert_int_equal(DUG(&paper.tyre, ka, al, fz, vw, &a, &b), RFE_OK);
        a = (rfe_real_t)7;
        b = (rfe_real_t)8;
#undef DUG
    }
}

/* REQ-TYRE-006 */
static void test_mcdc_tyre_forces_each_argument(void **state)
{
    const rfe_wheel_kin_t k = good_kin();
    const rfe_real_t mu[RFE_WHEELS] = {(rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5};
    rfe_real_t fx[RFE_WHEELS], fy[RFE_WHEELS], bx[RFE_WHEELS], by[RFE_WHEELS];
    (void)state;
    memset(fx, 0x5a, sizeof fx);
    memset(fy, 0x5a, sizeof fy);
    memcpy(bx, fx, sizeof fx);
    memcpy(by, fy, sizeof fy);
    assert_int_equal(rfe_tyre_forces_norm(&paper.tyre, NULL, fx, fy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_norm(&paper.tyre, &k, NULL, fy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_norm(&paper.tyre, &k, fx, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs(&paper.tyre, NULL, mu, fx, fy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs(&paper.tyre, &k, NULL, fx, fy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs(&paper.tyre, &k, mu, NULL, fy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs(&paper.tyre, &k, mu, fx, NULL), RFE_ERR_NULL);
    assert_memory_equal(fx, bx, sizeof fx);
    assert_memory_equal(fy, by, sizeof fy);
    assert_int_equal(rfe_tyre_forces_norm(&paper.tyre, &k, fx, fy), RFE_OK);
    assert_int_equal(rfe_tyre_forces_abs(&paper.tyre, &k, mu, fx, fy), RFE_OK);
}

/* REQ-OBSMAT-004 */
static void test_mcdc_obsmat_each_argument(void **state)
{
    const rfe_wheel_kin_t k = good_kin();
    rfe_real_t fx[RFE_WHEELS], fy[RFE_WHEELS], H[RFE_H_SIZE], Hb[RFE_H_SIZE];
    rfe_real_t x[RFE_WHEELS] = {(rfe_real_t)0.5, (rfe_real_t)0.6, (rfe_real_t)0.7, (rfe_real_t)0.8};
    rfe_real_t y[RFE_MEAS], yb[RFE_MEAS];
    size_t i;
    (void)state;
    assert_int_equal(rfe_tyre_forces_norm(&paper.tyre, &k, fx, fy), RFE_OK);
    memset(H, 0x5a, sizeof H);
    memcpy(Hb, H, sizeof H);
    assert_int_equal(rfe_obsmat_build(NULL, (rfe_real_t)0.02, fx, fy, H), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build(&paper.vehicle, (rfe_real_t)0.02, NULL, fy, H), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build(&paper.vehicle, (rfe_real_t)0.02, fx, NULL, H), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build(&paper.vehicle, (rfe_real_t)0.02, fx, fy, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build(&paper.vehicle, nan_r(), fx, fy, H), RFE_ERR_NONFINITE);
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        const rfe_real_t keep_x = fx[i], keep_y = fy[i];
        fx[i] = nan_r();
        assert_int_equal(rfe_obsmat_build(&paper.vehicle, (rfe_real_t)0.02, fx, fy, H), RFE_ERR_NONFINITE);
        fx[i] = keep_x;
        fy[i] = nan_r();
        assert_int_equal(rfe_obsmat_build(&paper.vehicle, (rfe_real_t)0.02, fx, fy, H), RFE_ERR_NONFINITE);
        fy[i] = keep_y;
    }
    assert_memory_equal(H, Hb, sizeof H);
    assert_int_equal(rfe_obsmat_build(&paper.vehicle, (rfe_real_t)0.02, fx, fy, H), RFE_OK);

    memset(y, 0x5a, sizeof y);
    memcpy(yb, y, sizeof y);
    assert_int_equal(rfe_obsmat_apply(NULL, x, y), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_apply(H, NULL, y), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_apply(H, x, NULL), RFE_ERR_NULL);
    memcpy(Hb, H, sizeof H);
    H[5] = nan_r();
    assert_int_equal(rfe_obsmat_apply(H, x, y), RFE_ERR_NONFINITE);
    memcpy(H, Hb, sizeof H);
    x[2] = nan_r();
    assert_int_equal(rfe_obsmat_apply(H, x, y), RFE_ERR_NONFINITE);
    assert_memory_equal(y, yb, sizeof y);
    x[2] = (rfe_real_t)0.7;
    assert_int_equal(rfe_obsmat_apply(H, x, y), RFE_OK);
}

/* REQ-COND-002 */
static void test_mcdc_conditioner_each_input(void **state)
{
    const rfe_sample_t good = good_sample();
    const rfe_real_t dt = (rfe_real_t)0.01, tau = (rfe_real_t)0.3;
    rfe_conditioner_t c, cb;
    rfe_sample_t u, out, ob;
    size_t f;
    (void)state;
    assert_int_equal(rfe_conditioner_init(&c), RFE_OK);
    assert_int_equal(rfe_conditioner_step(&c, dt, tau, &good, &out), RFE_OK); /* started */
    memcpy(&cb, &c, sizeof c);
    memset(&out, 0x5a, sizeof out);
    ob = out;
    /* each input the filter reads, non-finite on its own: vx, vy, ax, ay, yaw_rate */
    for (f = 0u; f < 5u; ++f) {
        u = good;
        switch (f) {
        case 0u: u.vx = nan_r(); break;
        case 1u: u.vy = nan_r(); break;
        case 2u: u.ax = nan_r(); break;
        case 3u: u.ay = nan_r(); break;
        default: u.yaw_rate = nan_r(); break;
        }
        assert_int_equal(rfe_conditioner_step(&c, dt, tau, &u, &out), RFE_ERR_NONFINITE);
        assert_memory_equal(&c, &cb, sizeof c);
        assert_memory_equal(&out, &ob, sizeof out);
    }
    /* finite inputs whose blend overflows in one component only: ay at the type's maximum
     * with dt = 2 s makes py = v̂y + dt·ay infinite while vx stays finite (and vice versa
     * with ax); nothing may change */
    u = good;
    u.ay = (rfe_real_t)REAL_BIG;
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)2.0, tau, &u, &out), RFE_ERR_NONFINITE);
    u = good;
    u.ax = (rfe_real_t)REAL_BIG;
    assert_int_equal(rfe_conditioner_step(&c, (rfe_real_t)2.0, tau, &u, &out), RFE_ERR_NONFINITE);
    assert_memory_equal(&c, &cb, sizeof c);
    assert_memory_equal(&out, &ob, sizeof out);
    assert_int_equal(rfe_conditioner_step(&c, dt, tau, &good, &out), RFE_OK);
}

/* REQ-CKF-004 */
static void test_mcdc_ckf_clamp_each_bound(void **state)
{
    rfe_ckf_t f, fb;
    const rfe_real_t x0[1] = {(rfe_real_t)2.0}, P0[1] = {(rfe_real_t)1.0};
    const rfe_real_t Q[1] = {(rfe_real_t)0.1}, R[1] = {(rfe_real_t)0.1};
    int clamped = 7;
    (void)state;
    memset(&f, 0, sizeof f); /* every byte defined, so the arrays can be compared whole */
    assert_int_equal(rfe_ckf_init(&f, 1u, 1u, x0, P0, Q, R), RFE_OK);
    memcpy(&fb, &f, sizeof f);
    assert_int_equal(rfe_ckf_clamp(&f, nan_r(), (rfe_real_t)1.0, &clamped), RFE_ERR_RANGE);
    assert_int_equal(rfe_ckf_clamp(&f, (rfe_real_t)0.0, nan_r(), &clamped), RFE_ERR_RANGE);
    assert_int_equal(rfe_ckf_clamp(&f, (rfe_real_t)0.0, (rfe_real_t)INFINITY, &clamped), RFE_ERR_RANGE);
    assert_int_equal(rfe_ckf_clamp(&f, (rfe_real_t)1.0, (rfe_real_t)0.5, &clamped), RFE_ERR_RANGE);
    assert_int_equal(clamped, 7);
    /* the state, not the scratch (uninitialised between calls) */
    assert_memory_equal(f.x, fb.x, sizeof f.x);
    assert_memory_equal(f.P, fb.P, sizeof f.P);
    assert_int_equal(rfe_ckf_clamp(&f, (rfe_real_t)0.0, (rfe_real_t)1.0, &clamped), RFE_OK);
    assert_int_equal(clamped, 1);
}

/* REQ-EST-003 */
static void test_mcdc_estimator_get_each_argument(void **state)
{
    rfe_friction_t est;
    rfe_estimate_t out, ob;
    (void)state;
    assert_int_equal(rfe_friction_init(&est, &paper), RFE_OK);
    memset(&out, 0x5a, sizeof out);
    ob = out;
    assert_int_equal(rfe_friction_get(NULL, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_get(&est, NULL), RFE_ERR_NULL);
    assert_memory_equal(&out, &ob, sizeof out);
    assert_int_equal(rfe_friction_get(&est, &out), RFE_OK);
}

/* One parameter changed from a valid set must make rfe_params_validate fail (what). */
static void expect_param_rejected(const rfe_params_t *p, const char *what)
{
    if (rfe_params_validate(p) != RFE_ERR_PARAM) {
        fail_msg("rfe_params_validate accepted %s", what);
    }
}

#define REJECT(field, value)                                                                   \
    do {                                                                                       \
        rfe_params_t p_ = base;                                                                \
        p_.field = (value);                                                                    \
        expect_param_rejected(&p_, #field " = " #value);                                       \
    } while (0)

/* REQ-PARAMS-002 */
static void test_mcdc_params_each_field(void **state)
{
    const rfe_real_t n = nan_r(), z = (rfe_real_t)0.0, neg = (rfe_real_t)-1.0;
    int which;
    (void)state;
    for (which = 0; which < 2; ++which) {
        const rfe_params_t base = (which == 0) ? paper : dflt;
        assert_int_equal(rfe_params_validate(&base), RFE_OK);
        /* vehicle: positive (zero and NaN: both conditions of is_pos), hg non-negative */
        REJECT(vehicle.m, z);      REJECT(vehicle.m, n);
        REJECT(vehicle.Lf, z);     REJECT(vehicle.Lf, n);
        REJECT(vehicle.Lr, z);     REJECT(vehicle.Lr, n);
        REJECT(vehicle.Bf, z);     REJECT(vehicle.Br, z);
        REJECT(vehicle.R, z);      REJECT(vehicle.J, z);
        REJECT(vehicle.hg, neg);   REJECT(vehicle.hg, n);
        REJECT(vehicle.g, z);
        /* tyre */
        REJECT(tyre.mode, (rfe_tyre_mode_t)3);
        /* Magic Formula shapes: 1 < C < 2, -4 <= E < 1 (each bound, NaN) */
        REJECT(tyre.shape_Cx, (rfe_real_t)1.0); REJECT(tyre.shape_Cx, (rfe_real_t)2.0);
        REJECT(tyre.shape_Cx, n);
        REJECT(tyre.shape_Ex, (rfe_real_t)1.0); REJECT(tyre.shape_Ex, (rfe_real_t)-4.5);
        REJECT(tyre.shape_Ex, n);
        REJECT(tyre.shape_Cy, (rfe_real_t)1.0); REJECT(tyre.shape_Cy, (rfe_real_t)2.0);
        REJECT(tyre.shape_Cy, n);
        REJECT(tyre.shape_Ey, (rfe_real_t)1.0); REJECT(tyre.shape_Ey, (rfe_real_t)-4.5);
        REJECT(tyre.shape_Ey, n);
        REJECT(tyre.Cx_n, z);      REJECT(tyre.Cy_n, z);
        REJECT(tyre.cx, z);        REJECT(tyre.cy, z);
        REJECT(tyre.eps, neg);     REJECT(tyre.v_min, z);
        REJECT(tyre.alpha_max, z); REJECT(tyre.alpha_max, (rfe_real_t)1.5);
        /* filter: enums, noise */
        REJECT(filter.kind, (rfe_filter_kind_t)2);
        REJECT(filter.structure, (rfe_structure_t)2);
        REJECT(filter.sd0, z);     REJECT(filter.q_mu, z);
        REJECT(filter.r_ax, z);    REJECT(filter.r_ay, z);
        REJECT(filter.r_yaw_acc, z);
        /* filter: bounds */
        REJECT(filter.mu_min, neg);
        REJECT(filter.mu_min, n);
        REJECT(filter.mu_max, z);
        REJECT(filter.mu_max, (rfe_real_t)0.04); /* below mu_min = 0.05 */
        REJECT(filter.mu0, n);
        REJECT(filter.mu0, (rfe_real_t)0.01);    /* below mu_min */
        REJECT(filter.mu0, (rfe_real_t)1.3);     /* above mu_max */
        REJECT(filter.v_est_min, neg);
    }
    /* the other tyre modes are accepted (each condition of the mode check), and the shape
     * bounds are inclusive where documented (E = -4) */
    {
        rfe_params_t p = paper;
        p.tyre.mode = RFE_TYRE_ABSOLUTE;
        assert_int_equal(rfe_params_validate(&p), RFE_OK);
        p.tyre.mode = RFE_TYRE_MAGIC;
        assert_int_equal(rfe_params_validate(&p), RFE_OK);
        p.tyre.shape_Ex = (rfe_real_t)-4.0;
        p.tyre.shape_Ey = (rfe_real_t)-4.0;
        assert_int_equal(rfe_params_validate(&p), RFE_OK);
        p.tyre.mode = RFE_TYRE_ABSOLUTE;
        p.filter.structure = RFE_STRUCT_SIDES;
        assert_int_equal(rfe_params_validate(&p), RFE_OK);
    }
}

/* The paper preset's sd after 20 steps on the good sample with the given parameters. */
static void run_sd(const rfe_params_t *p, rfe_real_t sd[RFE_WHEELS])
{
    rfe_friction_t est;
    rfe_estimate_t out;
    const rfe_sample_t u = good_sample();
    int k;
    assert_int_equal(rfe_friction_init(&est, p), RFE_OK);
    for (k = 0; k < 20; ++k) {
        assert_false(rfe_status_is_error(rfe_friction_step(&est, &u, &out)));
    }
    memcpy(sd, out.sd, sizeof out.sd);
}

/* REQ-EIV-001 */
static void test_mcdc_estimator_each_input_noise_switches_step_noise_on(void **state)
{
    rfe_real_t sd_off[RFE_WHEELS], sd_on[RFE_WHEELS];
    int which;
    (void)state;
    run_sd(&paper, sd_off); /* every addition off: S_R is the diagonal */
    for (which = 0; which < 6; ++which) {
        rfe_params_t p = paper;
        int w, differs = 0;
        switch (which) {
        case 0: p.filter.r_model_rel = (rfe_real_t)0.05; break;
        case 1: p.filter.sd_in_delta = (rfe_real_t)0.01; break;
        case 2: p.filter.sd_in_vx = (rfe_real_t)0.05; break;
        case 3: p.filter.sd_in_vy = (rfe_real_t)0.05; break;
        case 4: p.filter.sd_in_yaw_rate = (rfe_real_t)0.02; break;
        default: p.filter.sd_in_omega = (rfe_real_t)0.2; break;
        }
        assert_int_equal(rfe_params_validate(&p), RFE_OK);
        run_sd(&p, sd_on);
        /* a larger S_R means less information per step: the sd of some wheel must end
         * higher than with S_R diagonal (strictly: the noise added is far above rounding) */
        for (w = 0; w < RFE_WHEELS; ++w) {
            if (sd_on[w] > sd_off[w]) {
                differs = 1;
            }
        }
        if (!differs) {
            fail_msg("input-noise key %d alone did not raise any sd (errors in variables off?)", which);
        }
    }
}

/* REQ-PARAMS-004 */
static void test_mcdc_params_to_q31_this_precision(void **state)
{
    rfe_params_t p;
    rfe_params_q31_t q, q0;
    (void)state;
    memset(&q, 0x5a, sizeof q);
    q0 = q;
    assert_int_equal(rfe_params_to_q31(NULL, &q), RFE_ERR_NULL);
    assert_int_equal(rfe_params_to_q31(&paper, NULL), RFE_ERR_NULL);
    p = paper;
    p.vehicle.m = (rfe_real_t)-1.0; /* invalid: rfe_params_validate fails first */
    assert_int_equal(rfe_params_to_q31(&p, &q), RFE_ERR_PARAM);
    p = paper;
    p.vehicle.m = (rfe_real_t)40000.0; /* valid, but beyond its Q16 format */
    assert_int_equal(rfe_params_to_q31(&p, &q), RFE_ERR_RANGE);
    assert_memory_equal(&q, &q0, sizeof q);
    /* the paper preset converts, and the values exact in both precisions convert exactly:
     * mu0 = 0.5 (Q29), m = 1830 kg (Q16), the enums (validation of the result in Q is
     * test_params_q31's: the q31 library is not linked here) */
    assert_int_equal(rfe_params_to_q31(&paper, &q), RFE_OK);
    assert_int_equal(q.filter.mu0, (rfe_fix_t)(1 << 28));
    assert_int_equal(q.vehicle.m, (rfe_fix_t)(1830 << 16));
    assert_int_equal((int)q.filter.kind, (int)paper.filter.kind);
    assert_int_equal((int)q.tyre.mode, (int)paper.tyre.mode);
}

/* REQ-EIV-002 */
static void test_mcdc_step_noise_failures_leave_sr_untouched(void **state)
{
    const rfe_real_t mu[RFE_WHEELS] = {(rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5, (rfe_real_t)0.5};
    rfe_real_t SR[RFE_MEAS * RFE_MEAS], SRb[RFE_MEAS * RFE_MEAS];
    rfe_sample_t u;
    rfe_params_t p;
    (void)state;
    memset(SR, 0x5a, sizeof SR);
    memcpy(SRb, SR, sizeof SR);
    /* the sample itself non-finite: the measurement model at u fails */
    u = good_sample();
    u.vx = nan_r();
    assert_int_equal(rfe_step_noise_sqrt(&dflt, &u, mu, SR), RFE_ERR_NONFINITE);
    /* finite sample, but sd_in_delta times the steer derivative of ay (~ the front cornering
     * stiffness over the mass, >> 1 per rad) overflows: the input derivative's check fails
     * (since issue 21 no perturbed sample u + sd e_j is formed) */
    u = good_sample();
    p = dflt;
    p.filter.sd_in_delta = (rfe_real_t)REAL_BIG;
    assert_int_equal(rfe_params_validate(&p), RFE_OK);
    assert_int_equal(rfe_step_noise_sqrt(&p, &u, mu, SR), RFE_ERR_NONFINITE);
    /* a valid but huge sensor noise: r_ax^2 overflows in S_R0, Tria rejects the block */
    u = good_sample();
    p = dflt;
    p.filter.r_ax = (rfe_real_t)(REAL_BIG / 4);
    assert_int_equal(rfe_params_validate(&p), RFE_OK);
    assert_int_equal(rfe_step_noise_sqrt(&p, &u, mu, SR), RFE_ERR_NONFINITE);
    assert_memory_equal(SR, SRb, sizeof SR);
    /* and the good call succeeds */
    assert_int_equal(rfe_step_noise_sqrt(&dflt, &u, mu, SR), RFE_OK);
}

/* REQ-EST-005 REQ-COND-002 */
static void test_mcdc_estimator_conditioner_overflow_rolls_back(void **state)
{
    /* the default preset with a (valid) huge sample period: the input filter's prediction
     * v̂x + dt·(ax + r·v̂y) overflows on the second sample, so the step fails before its time
     * update result is used (the low-speed test is not reached) and everything is restored */
    rfe_params_t p = dflt;
    rfe_friction_t est;
    rfe_estimate_t out, prev;
    rfe_sample_t u = good_sample();
    (void)state;
    p.filter.dt = (rfe_real_t)(REAL_BIG / 4);
    assert_int_equal(rfe_params_validate(&p), RFE_OK);
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    assert_false(rfe_status_is_error(rfe_friction_step(&est, &u, &out)));
    assert_int_equal(rfe_friction_get(&est, &prev), RFE_OK);
    u.ax = (rfe_real_t)-8.0;
    assert_int_equal(rfe_friction_step(&est, &u, &out), RFE_ERR_NONFINITE);
    assert_memory_equal(out.mu, prev.mu, sizeof out.mu);
    assert_memory_equal(out.sd, prev.sd, sizeof out.sd);
    assert_true((out.valid[0] == 0u) && (out.valid[1] == 0u) && (out.valid[2] == 0u) && (out.valid[3] == 0u));
    assert_int_equal(rfe_friction_get(&est, &out), RFE_OK);
    assert_memory_equal(out.mu, prev.mu, sizeof out.mu);
    assert_memory_equal(out.sd, prev.sd, sizeof out.sd);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mcdc_tyre_kinematics_each_argument),
        cmocka_unit_test(test_mcdc_tyre_dugoff_each_argument),
        cmocka_unit_test(test_mcdc_tyre_forces_each_argument),
        cmocka_unit_test(test_mcdc_obsmat_each_argument),
        cmocka_unit_test(test_mcdc_conditioner_each_input),
        cmocka_unit_test(test_mcdc_ckf_clamp_each_bound),
        cmocka_unit_test(test_mcdc_estimator_get_each_argument),
        cmocka_unit_test(test_mcdc_params_each_field),
        cmocka_unit_test(test_mcdc_estimator_each_input_noise_switches_step_noise_on),
        cmocka_unit_test(test_mcdc_params_to_q31_this_precision),
        cmocka_unit_test(test_mcdc_step_noise_failures_leave_sr_untouched),
        cmocka_unit_test(test_mcdc_estimator_conditioner_overflow_rolls_back),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
