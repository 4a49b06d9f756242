/**
 * @file test_mass_grade_q31.c
 * @brief The fixed-point mass and grade estimator (rfe_mass_grade_*_q31) and its parameters:
 *        the API contract (input validation, untouched state on every error status), the
 *        conversion and the fixed-point domain of the weights, the square-root form against
 *        the textbook covariance form, and back to back against the double twin (_f64) on
 *        every mass and grade log in every configuration the goldens ran.
 *
 * How the two are fed: the q31 estimator gets the parameters converted by
 * rfe_mass_grade_params_to_q31_f64 and the samples rounded to their formats
 * (rfe_fix_from_double); the double twin gets exactly those values back in double (the
 * parameters and samples dequantised), so the comparison measures the fixed-point
 * arithmetic alone, not the rounding of the inputs.
 *
 * Bounds (TOL_* below; docs/FIXED_POINT.md "Mass and grade" quotes the measured worst cases,
 * printed by this test).
 *  - Per step, the fixed-point filter differs from the double one by (a) the model:
 *    ~20 rfe_xf_t operations of 2^-30 relative and sin/cos within 6.2e-10, so v-dot within
 *    ~3e-8 relative, times dt (0.02 s) and |v-dot| < 5 m/s^2: < 1e-8 m/s in a point's v,
 *    rounded to Q24 (3e-8 m/s); (b) the triangularisations: S S^T of Tria(A) is (A + E)(A +
 *    E)^T with |row i of E| <= 8 rows 2^-29 |a_i| (rfe_qr_tria_q31; rows <= 5: 7.5e-8 of the
 *    row's norm, i.e. of the state's sd), plus half an LSB per entry; (c) the whitened
 *    innovation, the solve's exactly rounded quotients: 1.5 sqrt(2n + m) LSB24 / sd_z (a
 *    relative 1e-6 at sd_z = 0.05 m/s) on the gain's effect, ~1e-6 of the correction; (d)
 *    the weights, exactly rounded to Q30 (5e-10).
 *  - Each is a perturbation of at most eps = 1e-6 of the state's sd per step (c dominates).
 *    The filter carries a perturbation of the mass and the grade forward with weight <= 1
 *    (a random walk learned only as fast as the excitation allows: no contraction can be
 *    assumed on a flat cruise), so over K steps the deviation is at most K eps sd in the
 *    worst case of aligned signs. The longest log has 11 259 steps: 0.0113 sd. The bound
 *    taken: TOL_SD = 0.02 of the filter's own sd (the double's, at that step) plus the
 *    formats' 4 LSB (M: 2.4e-4 kg; theta: 7.5e-9 rad); v: 0.02 sd_v + 4 LSB24.
 *  - The sds: the same perturbations in S (relative, per step; not accumulating: P is
 *    contracted by every measurement update, which forgets a relative error in P at the
 *    filter's rate, and the sd's own quantisation is 0.5 LSB): relative 0.02 plus 4 LSB.
 *  - The AUKF: lambda_u = 1/2 |q_s - D| / (q_s + D) has a relative derivative in D without
 *    bound where D nears q_s (test_mass_grade_golden_flt.c: float32 against double moved
 *    P_MM and q_mv by up to 27 % there), and it multiplies P_MM and q_mv: in the adaptive
 *    configurations sd_mass and q_mv are compared at 50 % relative (the float32 golden
 *    test's bound, for the same reason), the mass at 0.2 sd_mass (its float32 bound).
 *  - Statuses exactly: the pause delays end half a sample period before their length
 *    (MASS_GRADE.md §4.2), and the speed compared with v_min is the same dequantised value
 *    on both sides.
 */
#include "test_common.h"
#include "csv_dir.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fixed_conv.h"
#include "mg_logs.h"
#include "rfe/component/params_conv.h"
#include "rfe/mass_grade.h"
#include "rfe/mass_grade_q31.h"
#include "table.h"
#include "test_light.h"

#include "estimators/mass_grade/mass_grade_internal_q31.h"

#define GOLDEN_DIR "scenarios/golden/mass_grade"
/* light mode: the rows of each log it walks (30 s at 50 Hz: the first excitation, pauses) */
#define MG_LIGHT_ROWS 1500u
#define LOG_DIR "scenarios/mass_grade"
#define MIN_GOLDENS 28 /* 10 logs x 2 presets + 8 other configurations */

#define TOL_SD 0.02       /* share of the filter's sd: mass, grade, v (derivation above) */
#define TOL_SD_AUKF 0.2   /* the mass's share in the adaptive configurations */
#define TOL_REL 0.02      /* sd_v, sd_mass, sd_grade, relative */
#define TOL_REL_AUKF 0.5  /* sd_mass, q_mv in the adaptive configurations */
#define LSB(q) (4.0 * ldexp(1.0, -(q))) /* 4 LSB of Q(q) */

static const unsigned int QV = RFE_MG_Q_V;
static const unsigned int QM = RFE_MG_Q_M;
static const unsigned int QT = RFE_MG_Q_TH;

/* ---- conversions between the two faces ---------------------------------------------- */

/* The q31 parameters back in double (each field exactly its Q value). */
static void dequantise_params(const rfe_mass_grade_params_q31_t *q, rfe_mass_grade_params_t *p)
{
    memset(p, 0, sizeof(*p));
    p->R = rfe_fix_to_double(q->R, RFE_MG_Q_R);
    p->g = rfe_fix_to_double(q->g, RFE_MG_Q_G);
    p->fc = rfe_fix_to_double(q->fc, RFE_MG_Q_FC);
    p->fr = rfe_fix_to_double(q->fr, RFE_MG_Q_FR);
    p->rho = rfe_fix_to_double(q->rho, RFE_MG_Q_COEF);
    p->cd = rfe_fix_to_double(q->cd, RFE_MG_Q_COEF);
    p->area = rfe_fix_to_double(q->area, RFE_MG_Q_COEF);
    p->m_rot = rfe_fix_to_double(q->m_rot, QM);
    p->m0 = rfe_fix_to_double(q->m0, QM);
    p->theta0 = rfe_fix_to_double(q->theta0, QT);
    p->sd_m0 = rfe_fix_to_double(q->sd_m0, QM);
    p->sd_theta0 = rfe_fix_to_double(q->sd_theta0, QT);
    p->q_v = rfe_fix_to_double(q->q_v, QV);
    p->q_mc = rfe_fix_to_double(q->q_mc, QM);
    p->q_mv0 = rfe_fix_to_double(q->q_mv0, QM);
    p->q_theta = rfe_fix_to_double(q->q_theta, QT);
    p->r_v = rfe_fix_to_double(q->r_v, QV);
    p->r_ax = rfe_fix_to_double(q->r_ax, QV);
    p->ut_alpha = rfe_fix_to_double(q->ut_alpha, RFE_MG_Q_UT);
    p->ut_beta = rfe_fix_to_double(q->ut_beta, RFE_MG_Q_UT);
    p->ut_kappa = rfe_fix_to_double(q->ut_kappa, RFE_MG_Q_UT);
    p->adaptive = q->adaptive;
    p->use_ax = q->use_ax;
    p->t_adapt = rfe_fix_to_double(q->t_adapt, RFE_MG_Q_TIME);
    p->mv_stop = rfe_fix_to_double(q->mv_stop, RFE_MG_Q_COEF);
    p->v_min = rfe_fix_to_double(q->v_min, QV);
    p->t_brake = rfe_fix_to_double(q->t_brake, RFE_MG_Q_TIME);
    p->t_shift = rfe_fix_to_double(q->t_shift, RFE_MG_Q_TIME);
    p->p_brake_on = rfe_fix_to_double(q->p_brake_on, RFE_MG_Q_PRESSURE) * 1e6;
    p->slip_max = rfe_fix_to_double(q->slip_max, RFE_MG_Q_FC);
    p->ay_max = rfe_fix_to_double(q->ay_max, QV);
    p->t_curve = rfe_fix_to_double(q->t_curve, RFE_MG_Q_TIME);
    p->pause_grade = (double)q->pause_grade;
    p->pause_grade_slip = rfe_fix_to_double(q->pause_grade_slip, RFE_MG_Q_FC);
    p->pause_grade_dv = rfe_fix_to_double(q->pause_grade_dv, QV);
    p->m_min = rfe_fix_to_double(q->m_min, QM);
    p->m_max = rfe_fix_to_double(q->m_max, QM);
    p->theta_max = rfe_fix_to_double(q->theta_max, QT);
    p->dt_max = rfe_fix_to_double(q->dt_max, RFE_MG_Q_DT);
    p->q_theta_hi = rfe_fix_to_double(q->q_theta_hi, QT);
    p->theta_rate_on = rfe_fix_to_double(q->theta_rate_on, RFE_MG_Q_RATE);
    p->theta_rate_off = rfe_fix_to_double(q->theta_rate_off, RFE_MG_Q_RATE);
    p->theta_rate_tau = rfe_fix_to_double(q->theta_rate_tau, RFE_MG_Q_TIME);
    p->theta_rate_avg = rfe_fix_to_double(q->theta_rate_avg, RFE_MG_Q_TIME);
    p->mm_tau = rfe_fix_to_double(q->mm_tau, RFE_MG_Q_TIME);
    p->mm_e = rfe_fix_to_double(q->mm_e, RFE_MG_Q_E);
}

/* The sample rounded to the Q formats (q) and back (d, what the double twin gets). */
static void quantise_input(const rfe_mass_grade_input_t *in, rfe_mass_grade_input_q31_t *q,
                           rfe_mass_grade_input_t *d)
{
    uint32_t sat = 0u;
    memset(q, 0, sizeof(*q));
    q->dt = rfe_fix_from_double(in->dt, RFE_MG_Q_DT, &sat);
    q->v = rfe_fix_from_double(in->v, QV, &sat);
    q->torque = rfe_fix_from_double(in->torque, RFE_MG_Q_TORQUE, &sat);
    q->p_brake = rfe_fix_from_double(in->p_brake * 1e-6, RFE_MG_Q_PRESSURE, &sat);
    q->ax = rfe_fix_from_double(in->ax, QV, &sat);
    q->vx = rfe_fix_from_double(in->vx, QV, &sat);
    q->ay = rfe_fix_from_double(in->ay, QV, &sat);
    q->gear = in->gear;
    q->brake = in->brake;
    q->has = in->has;
    assert_int_equal(sat, 0u); /* every bundled sample fits its format */
    *d = *in;
    d->dt = rfe_fix_to_double(q->dt, RFE_MG_Q_DT);
    d->v = rfe_fix_to_double(q->v, QV);
    d->torque = rfe_fix_to_double(q->torque, RFE_MG_Q_TORQUE);
    d->p_brake = rfe_fix_to_double(q->p_brake, RFE_MG_Q_PRESSURE) * 1e6;
    d->ax = rfe_fix_to_double(q->ax, QV);
    d->vx = rfe_fix_to_double(q->vx, QV);
}

static void default_q31(rfe_mass_grade_params_q31_t *q)
{
    rfe_mass_grade_params_t p;
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, q), RFE_OK);
}

/* A plausible sample at speed v [m/s] (cruise torque, level road, ax = 0). */
static rfe_mass_grade_input_q31_t cruise_sample(double v)
{
    rfe_mass_grade_input_q31_t in;
    uint32_t sat = 0u;
    memset(&in, 0, sizeof(in));
    in.dt = rfe_fix_from_double(0.01, RFE_MG_Q_DT, &sat);
    in.v = rfe_fix_from_double(v, QV, &sat);
    in.torque = rfe_fix_from_double(150.0, RFE_MG_Q_TORQUE, &sat);
    in.ax = 0;
    in.has = RFE_MG_HAS_AX;
    return in;
}

/* ---- parameters ------------------------------------------------------------------------- */

/* The conversion: each field the value times 2^q, rounded (values of the car preset). */
static void test_params_to_q31_formats(void **state)
{
    rfe_mass_grade_params_q31_t q;
    (void)state;
    default_q31(&q);
    assert_int_equal(q.m0, (rfe_fix_t)(1830 * 16384));             /* 1830 kg, Q14 */
    assert_int_equal(q.sd_m0, (rfe_fix_t)(500 * 16384));           /* 500 kg */
    assert_int_equal(q.R, (rfe_fix_t)llround(0.325 * 268435456.0)); /* Q28 */
    assert_int_equal(q.g, (rfe_fix_t)llround(9.81 * 67108864.0));   /* Q26 */
    assert_int_equal(q.p_brake_on, (rfe_fix_t)llround(0.1 * 33554432.0)); /* 1e5 Pa in MPa, Q25 */
    assert_int_equal(q.dt_max, (rfe_fix_t)1073741824);             /* 1 s, Q30 */
    assert_int_equal(q.t_brake, (rfe_fix_t)16777216);              /* 1 s, Q24 */
    assert_int_equal(q.use_ax, 1u);
    assert_int_equal(q.adaptive, 0u);
    assert_int_equal(rfe_mass_grade_params_validate_q31(&q), RFE_OK);
}

/* Values beyond a format are refused (RFE_ERR_RANGE), q untouched; NULL and invalid sets. */
static void test_params_to_q31_errors(void **state)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_params_q31_t before;
    (void)state;
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    memset(&q, 0x5A, sizeof(q));
    before = q;
    p.m_max = 200000.0; /* beyond Q14's 131072 kg */
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_ERR_RANGE);
    assert_memory_equal(&q, &before, sizeof(q));
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    p.dt_max = 2.5; /* beyond Q30's 2 s (the walk's time constants >= it: valid) */
    p.theta_rate_tau = 3.0;
    p.theta_rate_avg = 3.0;
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_ERR_RANGE);
    p.dt_max = -1.0;
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_ERR_PARAM);
    assert_memory_equal(&q, &before, sizeof(q));
    assert_int_equal(rfe_mass_grade_params_to_q31(NULL, &q), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, NULL), RFE_ERR_NULL);
}

/* The weights of the defaults (alpha 1, beta 2, kappa 0: c = 3, lambda = 0): w_m,0 = 0,
 * w_i = 1/6, w_c,0 = 2, each exactly rounded to Q30 (sqrt(c) to Q29) from exact inputs. */
static void test_weights_of_the_defaults(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mg_weights_q31_t w;
    (void)state;
    default_q31(&q);
    assert_int_equal(rfe_mass_grade_weights_q31(&q, &w), RFE_OK);
    assert_int_equal(w.wm0, 0);
    assert_int_equal(w.wi, (rfe_fix_t)llround(1073741824.0 / 6.0));
    assert_int_equal(w.sqrt_wc0, (rfe_fix_t)llround(sqrt(2.0) * 1073741824.0));
    /* sqrt of the rounded w_i: within 1 LSB of the exact root */
    assert_true(fabs((double)w.sqrt_wi - sqrt(1.0 / 6.0) * 1073741824.0) <= 1.0);
    assert_int_equal(w.sqrt_c, (rfe_fix_t)llround(sqrt(3.0) * 536870912.0));
    assert_int_equal(rfe_mass_grade_weights_q31(NULL, &w), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_weights_q31(&q, NULL), RFE_ERR_NULL);
}

/* The fixed-point domain: sets the float twin accepts but Q31 refuses (c <= 1: w_m,0 <= -2;
 * c >= 16; w_c,0 < 0, whose root the square-root form needs), and a set just inside. */
/* REQ-MG-010 */
static void test_weights_domain(void **state)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mg_weights_q31_t w;
    static const struct {
        double alpha;
        double beta;
        double kappa;
        rfe_status_t want;
    } cases[] = {
        {0.5, 2.0, 0.0, RFE_ERR_PARAM},  /* c = 0.75 */
        {0.57, 2.0, 0.0, RFE_ERR_PARAM}, /* c = 0.9747 */
        {0.6, 2.0, 0.0, RFE_OK},         /* c = 1.08 */
        {2.3, 5.0, 0.0, RFE_OK},         /* c = 15.87, w_c,0 = 1.52 */
        {2.3, 2.0, 0.0, RFE_ERR_PARAM},  /* w_c,0 = 0.811 + 1 - 5.29 + 2 = -1.48 */
        {2.31, 2.0, 0.0, RFE_ERR_PARAM}, /* c = 16.008 */
        {1.2, 0.0, 0.0, RFE_ERR_PARAM},  /* c = 4.32: w_c,0 = 1.32/4.32 + 1 - 1.44 = -0.134 */
        {1.2, 0.2, 0.0, RFE_OK},         /* w_c,0 = 0.0656 */
        {1.0, 2.0, 1.0, RFE_OK},         /* c = 4 */
        {2.0, 2.0, 1.0, RFE_ERR_PARAM},  /* c = 16 exactly: alpha^2 (n + kappa) = 2^60 in Q56 */
        {1.0, 4.0, 0.0, RFE_ERR_PARAM},  /* w_c,0 = 4 */
        {1.0, 3.9, 0.0, RFE_OK},         /* w_c,0 = 3.9 */
    };
    size_t i;
    (void)state;
    for (i = 0u; i < sizeof(cases) / sizeof(cases[0]); ++i) {
        assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
        p.ut_alpha = cases[i].alpha;
        p.ut_beta = cases[i].beta;
        p.ut_kappa = cases[i].kappa;
        assert_int_equal(rfe_mass_grade_params_validate(&p), RFE_OK); /* the float accepts */
        assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_OK);
        assert_int_equal(rfe_mass_grade_weights_q31(&q, &w), cases[i].want);
        assert_int_equal(rfe_mass_grade_params_validate_q31(&q), cases[i].want);
        assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), cases[i].want);
        if (cases[i].want == RFE_OK) {
            /* w_m,0 against double on the Q28 alpha and kappa the integers see: alpha^2
             * rounded to Q28 (2^-29) and c to Q27 (2^-28) move c by dc <= (3 + kappa) 2^-29 +
             * 2^-28, w_m,0 = 1 - 3/c by 3/c^2 dc, plus its own rounding (0.5 LSB30) */
            const double a = rfe_fix_to_double(q.ut_alpha, RFE_MG_Q_UT);
            const double k3 = 3.0 + rfe_fix_to_double(q.ut_kappa, RFE_MG_Q_UT);
            const double c = (a * a) * k3;
            const double dc = (k3 * ldexp(1.0, -29)) + ldexp(1.0, -28);
            const double tol = ((3.0 / (c * c)) * dc * 1073741824.0) + 0.5;
            assert_true(fabs((double)w.wm0 - (1.0 - 3.0 / c) * 1073741824.0) <= tol);
            assert_true(fabs((double)w.wi - (0.5 / c) * 1073741824.0) <= ((0.5 / (c * c)) * dc * 1073741824.0) + 0.5);
        }
    }
    /* the weights alone (callable without the validation): alpha rounding to 0 in alpha^2,
     * n + kappa <= 0 */
    default_q31(&q);
    q.ut_alpha = 1; /* 2^-28: alpha^2 rounds to 0 in Q28 */
    assert_int_equal(rfe_mass_grade_weights_q31(&q, &w), RFE_ERR_PARAM);
    default_q31(&q);
    q.ut_kappa = -(3 << 28); /* n + kappa = 0 */
    assert_int_equal(rfe_mass_grade_weights_q31(&q, &w), RFE_ERR_PARAM);
}

/* Each field's check on the Q values: a nonpositive value where > 0 is needed, a negative
 * one where >= 0, the relations, the switches. */
/* REQ-MG-010 */
static void test_validate_q31(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_params_q31_t t;
    (void)state;
    default_q31(&q);
    assert_int_equal(rfe_mass_grade_params_validate_q31(NULL), RFE_ERR_NULL);
    t = q; t.R = 0;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.dt_max = -1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.fr = -1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.p_brake_on = -1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.slip_max = -1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.slip_max = 0; /* 0: no slip pause */
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    t = q; t.ay_max = -1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.t_curve = -1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.pause_grade = 7u; /* every bit, with use_ax */
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    t = q; t.pause_grade = 8u;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.pause_grade = 1u; t.use_ax = 0u; /* inert without ax, not refused */
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    t = q; t.pause_grade = 0u; t.use_ax = 0u;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    /* the ABS gate's slip in [0, 1] (Q30) */
    t = q; t.pause_grade_slip = -1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.pause_grade_slip = (1 << 30) + 1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.pause_grade_slip = 1 << 30;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    t = q; t.pause_grade_slip = 0; /* 0: no gate */
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    /* the change test's speed in [0, 10] m/s (Q24) */
    t = q; t.pause_grade_dv = -1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.pause_grade_dv = (10 << 24) + 1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.pause_grade_dv = 10 << 24;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    t = q; t.pause_grade_dv = 0; /* 0: no test */
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    t = q; t.adaptive = 2u;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.use_ax = 2u;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.m0 = t.m_min;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.m0 = t.m_max;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.theta0 = -t.theta_max;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t = q; t.theta_max = (rfe_fix_t)805306368; /* 1.5 rad */
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    /* the AUKF: mv_stop q_mc^2 < q_mv0^2; equality refused, just below accepted */
    t = q; t.adaptive = 1u; t.q_mc = 1 << 14; t.mv_stop = 1 << 24; t.q_mv0 = 1 << 14;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_ERR_PARAM);
    t.q_mv0 = (1 << 14) + 1;
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
    t.adaptive = 0u; t.q_mv0 = 0; /* the UKF ignores q_mv0 */
    assert_int_equal(rfe_mass_grade_params_validate_q31(&t), RFE_OK);
}

/* ---- the API contract ------------------------------------------------------------------- */

/* REQ-MG-010 */
static void test_init_errors(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_q31_t before;
    (void)state;
    default_q31(&q);
    memset(&mg, 0x3C, sizeof(mg));
    before = mg;
    assert_int_equal(rfe_mass_grade_init_q31(NULL, &q), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_init_q31(&mg, NULL), RFE_ERR_NULL);
    q.R = -1;
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_ERR_PARAM);
    default_q31(&q);
    /* the wrapper's size and configuration word checked: another layout is refused */
    assert_int_equal((rfe_mass_grade_init_q31)(&mg, &q, sizeof(mg) - 4u, RFE_CONFIG_Q31),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_mass_grade_init_q31)(&mg, &q, sizeof(mg), RFE_CONFIG_REAL),
                     RFE_ERR_ABI);
    assert_memory_equal(&mg, &before, sizeof(mg));
}

/* Every error status leaves the state as it was and returns the previous estimate. */
/* REQ-MG-010 */
static void test_step_errors_leave_state(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_q31_t before;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    rfe_mass_grade_input_q31_t bad;
    int k;
    (void)state;
    default_q31(&q);
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    assert_int_equal(rfe_mass_grade_get_q31(&mg, &e), RFE_OK);
    assert_int_equal(e.mass, 0); /* before the first sample every value is 0 */
    for (k = 0; k < 50; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    before = mg;
    assert_int_equal(rfe_mass_grade_step_q31(NULL, &in, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, NULL, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, NULL), RFE_ERR_NULL);
    bad = in; bad.v = RFE_MG_LIMIT_V_Q31 + 1;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    assert_int_equal(e.status, RFE_ERR_RANGE);
    assert_int_equal(e.mass, before.last.mass);
    bad = in; bad.v = INT32_MIN;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    bad = in; bad.torque = -RFE_MG_LIMIT_TORQUE_Q31 - 1;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    bad = in; bad.ax = RFE_MG_LIMIT_AX_Q31 + 1;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    bad = in; bad.has = 0u; /* no ax while use_ax */
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    bad = in; bad.has = RFE_MG_HAS_AX | 64u; /* an unknown bit */
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    bad = in; bad.has |= RFE_MG_HAS_VX; bad.vx = -RFE_MG_LIMIT_V_Q31 - 1; /* |vx| > 100 m/s */
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    assert_int_equal(e.status, RFE_ERR_RANGE);
    bad.vx = INT32_MIN;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    bad = in; bad.has |= RFE_MG_HAS_AY; bad.ay = RFE_MG_LIMIT_AX_Q31 + 1; /* |ay| > 50 m/s^2 */
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    bad.ay = INT32_MIN;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    bad = in; bad.dt = 0;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &bad, &e), RFE_ERR_RANGE);
    assert_memory_equal(&mg, &before, sizeof(mg));
    /* speed only: an ax not given is not checked, however large */
    {
        rfe_mass_grade_params_t p;
        rfe_mass_grade_params_q31_t q0;
        rfe_mass_grade_q31_t m0;
        rfe_mass_grade_input_q31_t s0 = in;
        assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
        p.use_ax = 0u;
        assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q0), RFE_OK);
        assert_int_equal(rfe_mass_grade_init_q31(&m0, &q0), RFE_OK);
        s0.has = 0u;
        s0.ax = INT32_MAX;
        assert_int_equal(rfe_mass_grade_step_q31(&m0, &s0, &e), RFE_OK);
        s0.has = RFE_MG_HAS_AX; /* given: checked */
        assert_int_equal(rfe_mass_grade_step_q31(&m0, &s0, &e), RFE_ERR_RANGE);
    }
    /* at the limits exactly: accepted */
    bad = in; bad.v = RFE_MG_LIMIT_V_Q31; bad.ax = -RFE_MG_LIMIT_AX_Q31;
    assert_false(rfe_status_is_error(rfe_mass_grade_step_q31(&mg, &bad, &e)));
    /* not initialised */
    memset(&mg, 0, sizeof(mg));
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_mass_grade_get_q31(&mg, &e), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_mass_grade_restart_q31(&mg), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_mass_grade_get_q31(NULL, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_get_q31(&mg, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_mass_grade_restart_q31(NULL), RFE_ERR_NULL);
}

/* The start (§4.1): the first sample gives x = [v, m0, theta0], sd = (r_v, sd_m0,
 * sd_theta0) exactly; a restart and a period beyond dt_max start again. */
/* REQ-MG-010 */
static void test_start_and_restart(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    int k;
    (void)state;
    default_q31(&q);
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    assert_int_equal(e.v, in.v);
    assert_int_equal(e.mass, q.m0);
    assert_int_equal(e.grade, q.theta0);
    assert_int_equal(e.sd_v, q.r_v);
    assert_int_equal(e.sd_mass, q.sd_m0);
    assert_int_equal(e.sd_grade, q.sd_theta0);
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    assert_true(e.sd_mass < q.sd_m0); /* it learned */
    assert_int_equal(rfe_mass_grade_restart_q31(&mg), RFE_OK);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    assert_int_equal(e.sd_mass, q.sd_m0);
    for (k = 0; k < 10; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    in.dt = q.dt_max + 1;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    assert_int_equal(e.sd_mass, q.sd_m0);
    assert_int_equal(e.mass, q.m0);
}

/* The pauses (§4.2) with the statuses of the float twin: brake flag, pressure, its delay,
 * a gear change, low speed; a hold keeps M and theta and restarts v at the measurement. */
/* REQ-MG-010 */
static void test_pauses(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_estimate_q31_t held;
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    rfe_mass_grade_input_q31_t b;
    int k;
    (void)state;
    default_q31(&q);
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    held = e;
    b = in;
    b.has |= RFE_MG_HAS_BRAKE;
    b.brake = 1u;
    b.v = in.v - 1000;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &b, &e), RFE_MG_PAUSED_BRAKE);
    assert_int_equal(e.mass, held.mass);
    assert_int_equal(e.grade, held.grade);
    assert_int_equal(e.v, b.v);       /* v restarts at the measurement */
    assert_int_equal(e.sd_v, q.r_v);  /* with sd r_v */
    assert_int_equal(e.sd_mass, held.sd_mass);
    assert_true(e.sd_grade > held.sd_grade); /* the grade's walk */
    /* t_brake = 1 s of 0.01 s periods: held while more than half a period is left, i.e.
     * the 99 samples after the braked one; the 100th updates */
    for (k = 0; k < 99; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_MG_PAUSED_BRAKE);
    }
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    /* the pressure above p_brake_on; at it exactly not */
    b = in;
    b.has |= RFE_MG_HAS_PRESSURE;
    b.p_brake = q.p_brake_on;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &b, &e), RFE_OK);
    b.p_brake = q.p_brake_on + 1;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &b, &e), RFE_MG_PAUSED_BRAKE);
    for (k = 0; k < 99; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_MG_PAUSED_BRAKE);
    }
    /* a gear change: the shift delay */
    b = in;
    b.has |= RFE_MG_HAS_GEAR;
    b.gear = 3;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &b, &e), RFE_OK); /* the first gear given */
    b.gear = 4;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &b, &e), RFE_MG_PAUSED_SHIFT);
    for (k = 0; k < 99; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &b, &e), RFE_MG_PAUSED_SHIFT);
    }
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &b, &e), RFE_OK);
    /* low speed */
    b = cruise_sample(2.0);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &b, &e), RFE_NO_UPDATE_LOW_SPEED);
}

/* The slip pause (§4.2 step 3): the float twin's status, held as the brake holds; the
 * threshold slip_max max(|vx|, v_min) to the LSB: thr = floor(slip_max ref / 2^30) LSB24 of
 * slip is no slip, one LSB more is (the comparison is exact in int64). */
/* REQ-MG-006 */
static void test_slip_pause_q31(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_q31_t learning;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_estimate_q31_t held;
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    rfe_mass_grade_input_q31_t s;
    uint32_t sat = 0u;
    int64_t thr;
    int k;
    (void)state;
    default_q31(&q);
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    in.vx = in.v; /* given, no slip */
    in.has |= RFE_MG_HAS_VX;
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    held = e;
    learning = mg;
    s = in;
    s.torque = rfe_fix_from_double(3000.0, RFE_MG_Q_TORQUE, &sat); /* spinning the wheels */
    s.v = in.v + rfe_fix_from_double(2.0, QV, &sat);
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_SLIP);
        assert_int_equal(e.mass, held.mass);
        assert_int_equal(e.grade, held.grade);
        assert_int_equal(e.sd_mass, held.sd_mass);
    }
    assert_int_equal(e.v, s.v); /* v restarts at the measurement, sd r_v */
    assert_int_equal(e.sd_v, q.r_v);
    /* the same samples without vx: learned (what the pause keeps out) */
    mg = learning;
    s.has &= ~RFE_MG_HAS_VX;
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    }
    assert_true(e.mass != held.mass);
    /* the threshold to the LSB at vx = 20 m/s (above v_min) */
    mg = learning;
    thr = ((int64_t)q.slip_max * (int64_t)in.vx) / 1073741824;
    s = in;
    s.v = (rfe_fix_t)((int64_t)in.vx + thr);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    s.v = (rfe_fix_t)((int64_t)in.vx + thr + 1);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_SLIP);
    s.v = (rfe_fix_t)((int64_t)in.vx - thr - 1); /* either sign */
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_SLIP);
    /* slip_max = 0: none */
    mg = learning;
    mg.p.slip_max = 0;
    s.v = in.vx + rfe_fix_from_double(2.0, QV, &sat);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    assert_int_equal(sat, 0u);
}

/* The curve pause (§4.2 step 4): the float twin's statuses, held as the brake holds; |ay|
 * against ay_max exact in Q24 (ay_max itself updates, one LSB more holds, either sign); the
 * delay t_curve in Q30 periods; ay_max = 0 (the default) or no ay: none. */
/* REQ-MG-006 */
static void test_curve_pause_q31(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_q31_t learning;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_estimate_q31_t held;
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    rfe_mass_grade_input_q31_t s;
    uint32_t sat = 0u;
    int k;
    (void)state;
    default_q31(&q);
    assert_int_equal(q.ay_max, 0); /* off by default */
    q.ay_max = rfe_fix_from_double(1.0, QV, &sat);
    q.t_curve = rfe_fix_from_double(0.05, RFE_MG_Q_TIME, &sat); /* 5 periods of 0.01 s */
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    in.has |= RFE_MG_HAS_AY; /* given, straight */
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    held = e;
    learning = mg;
    s = in;
    s.torque = rfe_fix_from_double(3000.0, RFE_MG_Q_TORQUE, &sat);
    s.ay = rfe_fix_from_double(-1.5, QV, &sat);
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_CURVE);
        assert_int_equal(e.mass, held.mass);
        assert_int_equal(e.grade, held.grade);
        assert_int_equal(e.sd_mass, held.sd_mass);
    }
    /* the delay: 0.04 ... 0.01 s left exceed half a period: held; then 0: updated (t_curve
     * in Q24 is 0.05 within 2^-24 s, under half a period from whole periods) */
    s.ay = 0;
    for (k = 0; k < 4; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_CURVE);
    }
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    /* the same samples without ay: learned */
    mg = learning;
    s.ay = rfe_fix_from_double(-1.5, QV, &sat);
    s.has &= ~RFE_MG_HAS_AY;
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    }
    assert_true(e.mass != held.mass);
    /* the threshold to the LSB, no delay */
    mg = learning;
    mg.p.t_curve = 0;
    s = in;
    s.ay = q.ay_max;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    s.ay = q.ay_max + 1;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_CURVE);
    s.ay = -q.ay_max - 1;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_CURVE);
    s.ay = -q.ay_max;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    /* ay_max = 0: none */
    mg = learning;
    mg.p.ay_max = 0;
    s.ay = rfe_fix_from_double(-1.5, QV, &sat);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    assert_int_equal(sat, 0u);
}

/* REQ-MG-006 the grade from ax in a pause (§4.2, pause_grade) in the twin: braking on a
 * 0.05 rad climb (v-dot = -2 m/s^2, ax = v-dot + g sin theta), the first braked sample holds
 * and every later one keeps M, sd_mass and S's mass row bit for bit while the grade runs to
 * the truth (under a tenth of its error after 2 s, here 200 periods of 0.01 s: the float
 * twins' bound and reason, test_pause_grade_learns_grade_holds_mass); the brake bit unset:
 * held bit for bit; no saturation. The twin against double on the same pauses: the
 * pause_grade goldens in test_every_log_against_double. */
static void test_pause_grade_q31(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_q31_t learning;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_estimate_q31_t first;
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    rfe_mass_grade_input_q31_t s;
    rfe_fix_t row[4];
    uint32_t sat = 0u;
    double err0;
    double err;
    int pass;
    int k;
    (void)state;
    default_q31(&q);
    assert_int_equal(q.pause_grade, RFE_MG_PAUSE_GRADE_BRAKE); /* the brake bit by default */
    q.pause_grade = RFE_MG_PAUSE_GRADE_BRAKE;
    q.pause_grade_dv = 0; /* the learning mode itself: test_change_test_q31 runs the test */
    q.q_theta_hi = 0; /* the fixed grade walk (§4.7 off), as the float twin's test: learning
                       * moves the grade, which would loosen the walk and widen sd_grade */
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    learning = mg;
    for (pass = 0; pass < 2; ++pass) {
        mg = learning;
        mg.p.pause_grade = (pass == 0) ? RFE_MG_PAUSE_GRADE_BRAKE
                                       : (RFE_MG_PAUSE_GRADE_SHIFT | RFE_MG_PAUSE_GRADE_CURVE);
        for (k = 0; k <= 200; ++k) {
            s = in;
            s.v = rfe_fix_from_double(20.0 - (0.02 * (double)k), QV, &sat);
            s.torque = rfe_fix_from_double(-2000.0, RFE_MG_Q_TORQUE, &sat);
            s.ax = rfe_fix_from_double(-2.0 + (9.81 * sin(0.05)), QV, &sat);
            s.brake = 1u;
            s.has |= RFE_MG_HAS_BRAKE;
            assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
            assert_int_equal(e.sat, 0u);
            if (k == 0) {
                first = e;
                assert_int_equal(mg.S[3], 0); /* the hold: v uncorrelated with M */
                row[0] = mg.S[4];
                row[1] = mg.S[5];
                row[2] = mg.S[7];
                row[3] = mg.x[1];
            }
            assert_int_equal(e.mass, first.mass);
            assert_int_equal(e.sd_mass, first.sd_mass);
            assert_true((mg.S[3] == 0) && (mg.S[4] == row[0]) && (mg.S[5] == row[1]) &&
                        (mg.S[7] == row[2]) && (mg.x[1] == row[3]));
            if (pass == 1) {
                assert_int_equal(e.grade, first.grade);
            }
        }
        err0 = fabs(rfe_fix_to_double(first.grade, QT) - 0.05);
        err = fabs(rfe_fix_to_double(e.grade, QT) - 0.05);
        if (pass == 0) {
            printf("q31 grade from ax while braking: error %.3g rad -> %.3g rad\n", err0, err);
            assert_true((err0 > 0.02) && (err < (0.1 * err0)));
            assert_true(e.sd_grade < first.sd_grade);
        }
    }
    assert_int_equal(sat, 0u);
}

/* Braked sample k on the 0.05 rad climb of test_pause_grade_q31 with the ground speed vx
 * given and the wheels' speed (1 - slip) vx. */
static rfe_mass_grade_input_q31_t braking_slipping_q31(int k, double slip)
{
    rfe_mass_grade_input_q31_t s = cruise_sample(20.0);
    const double vx = 20.0 - (0.02 * (double)k);
    uint32_t sat = 0u;
    s.vx = rfe_fix_from_double(vx, QV, &sat);
    s.v = rfe_fix_from_double((1.0 - slip) * vx, QV, &sat);
    s.torque = rfe_fix_from_double(-2000.0, RFE_MG_Q_TORQUE, &sat);
    s.ax = rfe_fix_from_double(-2.0 + (9.81 * sin(0.05)), QV, &sat);
    s.brake = 1u;
    s.has |= RFE_MG_HAS_BRAKE | RFE_MG_HAS_VX;
    assert_int_equal(sat, 0u);
    return s;
}

/* REQ-MG-006 the ABS gate (§4.2, pause_grade_slip) in the twin, as the float twin's
 * test_abs_gate_holds_cycling_wheels and test_abs_gate_decision: ABS-like cycling (6 samples
 * at 12 % slip, 4 at 1 %) with the brake bit and the default gate holds bit for bit as with
 * the bit off; a steady brake at 1 % learns bit for bit as without the gate; the gate's
 * comparison exact in int64 on the Q values (the threshold to the LSB, either sign); vx not
 * given or the gate 0: learned; the latch kept through a non-slipping paused sample, cleared
 * by an update; a bad gate refused by the init with the state untouched. */
static void test_abs_gate_q31(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_params_q31_t bad;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_q31_t start;
    rfe_mass_grade_q31_t held;
    rfe_mass_grade_q31_t before;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_estimate_q31_t off[101];
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    rfe_mass_grade_input_q31_t s;
    uint32_t sat = 0u;
    int64_t thr;
    int k;
    (void)state;
    default_q31(&q);
    assert_int_equal(q.pause_grade_slip, rfe_fix_from_double(0.05, RFE_MG_Q_FC, &sat));
    q.pause_grade = RFE_MG_PAUSE_GRADE_BRAKE;
    q.pause_grade_dv = 0; /* the gate alone: test_change_test_q31 runs the change test */
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    start = mg;
    /* cycling: the bit off, then on with the gate: the same bit for bit */
    mg.p.pause_grade = 0u;
    for (k = 0; k <= 100; ++k) {
        s = braking_slipping_q31(k, ((k % 10) < 6) ? 0.12 : 0.01);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &off[k]), RFE_MG_PAUSED_BRAKE);
    }
    mg = start;
    for (k = 0; k <= 100; ++k) {
        s = braking_slipping_q31(k, ((k % 10) < 6) ? 0.12 : 0.01);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
        assert_int_equal(mg.slip_latched, 1u);
        assert_memory_equal(&e, &off[k], sizeof(e));
    }
    /* the same without the gate: the grade leaves the held one */
    mg = start;
    mg.p.pause_grade_slip = 0;
    for (k = 0; k <= 100; ++k) {
        s = braking_slipping_q31(k, ((k % 10) < 6) ? 0.12 : 0.01);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    }
    assert_true(e.grade != off[100].grade);
    /* a steady brake at 1 %: the gate never acts */
    mg = start;
    for (k = 0; k <= 100; ++k) {
        s = braking_slipping_q31(k, 0.01);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &off[k]), RFE_MG_PAUSED_BRAKE);
        assert_int_equal(mg.slip_latched, 0u);
    }
    mg = start;
    mg.p.pause_grade_slip = 0;
    for (k = 0; k <= 100; ++k) {
        s = braking_slipping_q31(k, 0.01);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
        assert_memory_equal(&e, &off[k], sizeof(e));
    }
    assert_true(e.grade != off[0].grade); /* learned */
    /* the decision, one braked sample after a hold (S_Mv = 0) */
    mg = start;
    s = braking_slipping_q31(0, 0.0);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    held = mg;
    s = braking_slipping_q31(1, 0.0);
    thr = ((int64_t)q.pause_grade_slip * (int64_t)s.vx) / 1073741824; /* vx > v_min */
    s.v = (rfe_fix_t)((int64_t)s.vx - thr); /* at the threshold: learned */
    mg = held;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.slip_latched == 0u) && (e.grade != held.last.grade));
    s.v = (rfe_fix_t)((int64_t)s.vx - thr - 1); /* one LSB beyond: held */
    mg = held;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.slip_latched == 1u) && (e.grade == held.last.grade));
    s.v = (rfe_fix_t)((int64_t)s.vx + thr + 1); /* either sign */
    mg = held;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.slip_latched == 1u) && (e.grade == held.last.grade));
    s.has &= ~RFE_MG_HAS_VX; /* vx not given: learned */
    mg = held;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.slip_latched == 0u) && (e.grade != held.last.grade));
    s.has |= RFE_MG_HAS_VX; /* the gate off: learned */
    mg = held;
    mg.p.pause_grade_slip = 0;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.slip_latched == 0u) && (e.grade != held.last.grade));
    mg = held; /* latched: a sample at no slip holds */
    mg.slip_latched = 1u;
    s.v = s.vx;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.slip_latched == 1u) && (e.grade == held.last.grade));
    mg.brake_left = 0; /* an update clears it, the wheels slipping (slip pause off) */
    mg.p.slip_max = 0;
    s = in;
    s.vx = in.v + rfe_fix_from_double(2.0, QV, &sat);
    s.has |= RFE_MG_HAS_VX;
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_OK);
    assert_int_equal(mg.slip_latched, 0u);
    /* a bad gate: refused, the state untouched */
    before = mg;
    bad = q;
    bad.pause_grade_slip = (1 << 30) + 1;
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &bad), RFE_ERR_PARAM);
    assert_memory_equal(&mg, &before, sizeof(mg));
    assert_int_equal(sat, 0u);
}

/* Braked sample k (0.01 s apart from 20 m/s at 2 m/s^2) on the 0.05 rad climb of
 * test_pause_grade_q31, the wheels @p behind m/s behind the car (from k = 1) and vx given
 * when @p with_vx. */
static rfe_mass_grade_input_q31_t braking_q31(int k, double behind, int with_vx)
{
    rfe_mass_grade_input_q31_t s = cruise_sample(20.0);
    const double vx = 20.0 - (0.02 * (double)k);
    uint32_t sat = 0u;
    s.vx = rfe_fix_from_double(vx, QV, &sat);
    s.v = rfe_fix_from_double((k == 0) ? vx : (vx - behind), QV, &sat);
    s.torque = rfe_fix_from_double(-2000.0, RFE_MG_Q_TORQUE, &sat);
    s.ax = rfe_fix_from_double(-2.0 + (9.81 * sin(0.05)), QV, &sat);
    s.brake = 1u;
    s.has |= RFE_MG_HAS_BRAKE | ((with_vx != 0) ? RFE_MG_HAS_VX : 0u);
    assert_int_equal(sat, 0u);
    return s;
}

/* REQ-MG-006 the change test (§4.2, pause_grade_dv) in the twin, as the float twin's
 * test_change_test: the default 0.2 m/s in Q24; the held grade set to the truth holds bit for
 * bit through 2 s of braking (its residual within 100 LSB of Q24: only the rounding of g sin
 * theta and of the products, 1/2 LSB each per sample, 200 samples); the held grade of the
 * level cruise (0.05 rad off) holds until the residual, g sin(0.05) t = 0.49 m/s^2 t, passes
 * 0.2 m/s (0.41 s: sample 42 at 0.01 s, computed in double from the samples; one sample
 * either side for the Q24 rounding, the residual growing 4.9e-3 m/s a sample, 8e4 LSB) and
 * then learns to under a tenth of its error by the end (2 s; measured 3.2 mrad of 50); wheels
 * 0.3 m/s behind a right vx hold, without vx they trip at once; 0: learned at once; an update
 * clears it. */
static void test_change_test_q31(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_q31_t start;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    rfe_mass_grade_input_q31_t s;
    uint32_t sat = 0u;
    rfe_fix_t held;
    rfe_fix_t truth;
    double err0;
    double d = 0.0;
    int trip = -1;
    int k;
    (void)state;
    default_q31(&q);
    assert_int_equal(q.pause_grade_dv, rfe_fix_from_double(0.2, QV, &sat));
    q.pause_grade = RFE_MG_PAUSE_GRADE_BRAKE;
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    for (k = 0; k < 100; ++k) {
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    }
    start = mg;
    held = start.x[2];
    truth = rfe_fix_from_double(0.05, QT, &sat);
    /* the held grade right */
    mg.x[2] = truth;
    for (k = 0; k <= 200; ++k) {
        s = braking_q31(k, 0.0, 0);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
        assert_true((e.grade == truth) && (mg.chg_on == 0u));
    }
    assert_true(llabs(mg.chg_d) < 100);
    /* the held grade wrong: the trip expected from the samples' definition, in double */
    for (k = 1; k < 1000; ++k) {
        d += -0.02 - (0.01 * ((-2.0 + (9.81 * sin(0.05))) -
                               (9.81 * sin(rfe_fix_to_double(held, QT)))));
        if (fabs(d) > 0.2) {
            trip = k;
            break;
        }
    }
    assert_true((trip > 40) && (trip < 70));
    err0 = fabs(rfe_fix_to_double(held, QT) - 0.05);
    mg = start;
    for (k = 0; k <= 200; ++k) {
        s = braking_q31(k, 0.0, 0);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
        if (k < (trip - 1)) {
            assert_true((e.grade == held) && (mg.chg_on == 0u));
        }
        if (k > trip) {
            assert_int_equal(mg.chg_on, 1u);
        }
    }
    printf("q31 change test: held grade error %.3g rad, trip near sample %d, then %.3g rad\n",
           err0, trip, fabs(rfe_fix_to_double(e.grade, QT) - 0.05));
    assert_true(fabs(rfe_fix_to_double(e.grade, QT) - 0.05) < (0.1 * err0));
    mg.brake_left = 0; /* an update clears it */
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
    assert_true((mg.chg_on == 0u) && (mg.chg_d == 0));
    /* the test's speed: vx where given */
    mg = start;
    mg.x[2] = truth;
    for (k = 0; k <= 100; ++k) {
        s = braking_q31(k, 0.3, 1);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
        assert_true((e.grade == truth) && (mg.chg_on == 0u) && (mg.slip_latched == 0u));
    }
    mg = start;
    mg.x[2] = truth;
    s = braking_q31(0, 0.3, 0);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    s = braking_q31(1, 0.3, 0);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.chg_on == 1u) && (e.grade != truth));
    /* no test: the first eligible sample learns */
    mg = start;
    mg.p.pause_grade_dv = 0;
    s = braking_q31(0, 0.0, 0);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    s = braking_q31(1, 0.0, 0);
    assert_int_equal(rfe_mass_grade_step_q31(&mg, &s, &e), RFE_MG_PAUSED_BRAKE);
    assert_true((mg.chg_on == 1u) && (e.grade != held));
    assert_int_equal(sat, 0u);
}

/* The speed row refuses a zero innovation sd (r_v = 0 and a zero factor: not positive
 * definite), leaving x and S untouched, alone and after an ax row that succeeded (its points
 * all measure the same, so the ax row leaves S's v row 0); the public API cannot reach it
 * (r_v > 0). */
/* REQ-MG-010 */
static void test_correct_zero_innovation_sd(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mg_weights_q31_t w;
    rfe_fix_t chi[RFE_MG_PTS_Q31 * RFE_MG_N_Q31];
    const rfe_fix_t Z[RFE_MG_PTS_Q31] = {0};
    const rfe_fix_t r[RFE_MG_Z_MAX_Q31] = {0, 1 << 20}; /* r_v = 0, r_ax = 1/16 m/s^2 */
    const rfe_fix_t y[RFE_MG_Z_MAX_Q31] = {1 << 24, 1 << 22};
    rfe_fix_t x[RFE_MG_N_Q31] = {20 << 24, 1800 << 14, 0};
    rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31] = {0, 0, 0, 0, 100 << 14, 0, 0, 0, 1 << 20};
    rfe_fix_t x0[RFE_MG_N_Q31];
    rfe_fix_t S0[RFE_MG_N_Q31 * RFE_MG_N_Q31];
    rfe_fix_t e_ax = 77;
    uint32_t sat = 0u;
    (void)state;
    default_q31(&q);
    assert_int_equal(rfe_mass_grade_weights_q31(&q, &w), RFE_OK);
    rfe_mg_sigma_points_q31(x, S, w.sqrt_c, chi, &sat);
    assert_int_equal(sat, 0u);
    memcpy(x0, x, sizeof x);
    memcpy(S0, S, sizeof S);
    assert_int_equal(rfe_mg_correct_speed_q31(r[0], y[0], x, S, &sat),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_mg_correct_q31(chi, Z, &w, r, y, x, S, &sat, &e_ax),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_memory_equal(x, x0, sizeof x);
    assert_memory_equal(S, S0, sizeof S);
    assert_int_equal(e_ax, 77); /* §4.8's innovation is written only on success */
    assert_int_equal(sat, 0u);
    /* the same ax row succeeds: with r_v > 0 the whole correction does */
    {
        const rfe_fix_t r1[RFE_MG_Z_MAX_Q31] = {1 << 20, 1 << 20};
        uint32_t sat1 = 0u;
        assert_int_equal(rfe_mg_correct_q31(chi, Z, &w, r1, y, x, S, &sat1, &e_ax), RFE_OK);
    }
}

/* ---- the square-root form against the textbook form -------------------------------------- */

/* The linear random-walk filter where the UKF is the Kalman filter: v measured, M and
 * theta unobserved random walks coupled to v only through the model. With the model's
 * v-dot the points' v moves with M and theta, so the filter correlates them; the check
 * here is the invariant the square-root form guarantees and the textbook one does not:
 * over a long run with a tiny process noise, P = S S^T stays positive semidefinite (every
 * factor diagonal >= 0 and the sds nonnegative and finite by construction), every step
 * updates (never RFE_ERR_NOT_POSITIVE_DEFINITE), and the mass's sd keeps decreasing
 * monotonically under constant excitation. */
/* REQ-MG-010 */
static void test_square_root_form_stays_definite(void **state)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    rfe_mass_grade_estimate_q31_t e;
    rfe_mass_grade_input_q31_t in = cruise_sample(20.0);
    rfe_fix_t sd_prev = INT32_MAX;
    int k;
    (void)state;
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    p.q_mc = 1e-3;    /* 16 LSB of Q14: the mass almost a constant */
    p.q_theta = 1e-7; /* 54 LSB of Q29 */
    p.q_v = 1e-6;     /* 17 LSB of Q24 */
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_OK);
    assert_int_equal(rfe_mass_grade_init_q31(&mg, &q), RFE_OK);
    for (k = 0; k < 20000; ++k) {
        /* a torque that alternates every second: the mass is excited throughout */
        in.torque = (((k / 100) % 2) == 0) ? (300 << 14) : (100 << 14);
        assert_int_equal(rfe_mass_grade_step_q31(&mg, &in, &e), RFE_OK);
        assert_true(mg.S[0] >= 0);
        assert_true(mg.S[4] >= 0);
        assert_true(mg.S[8] >= 0);
        if ((k > 0) && ((k % 1000) == 0)) {
            assert_true(e.sd_mass <= sd_prev);
            sd_prev = e.sd_mass;
        }
    }
    assert_int_equal(mg.sat, 0u);
}

/* ---- back to back against the double twin ---------------------------------------------- */

static double worst_mass_sd;  /* |dM| / sd_M, the largest */
static double worst_grade_sd; /* |dtheta| / sd_theta */
static double worst_v_sd;     /* |dv| / sd_v */
static double worst_sd_rel;   /* the sds, relative (UKF configurations) */
static double worst_mass_kg;
static double worst_grade_rad;
static double worst_mass_sd_aukf; /* |dM| / sd_M in the adaptive configurations */
static double worst_rel_aukf;     /* sd_mass and q_mv, relative, adaptive */
/* What a textbook covariance form in int32 would face (the double twin's P = S S^T, every
 * update): the range of each variance and the smallest normalised determinant det P / (P11
 * P22 P33) (1 for uncorrelated states; near 0 where P is near singular). */
static double var_min[3] = {1e300, 1e300, 1e300};
static double var_max[3];
static double det_norm_min = 1.0;
static size_t n_steps; /* steps compared */

static void track_textbook(const rfe_mass_grade_t *md)
{
    double P[9];
    size_t r;
    size_t c;
    size_t k;
    for (r = 0u; r < 3u; ++r) {
        for (c = 0u; c < 3u; ++c) {
            double acc = 0.0;
            for (k = 0u; k < 3u; ++k) {
                acc += md->S[(r * 3u) + k] * md->S[(c * 3u) + k];
            }
            P[(r * 3u) + c] = acc;
        }
    }
    const double det = P[0] * (P[4] * P[8] - P[5] * P[7]) - P[1] * (P[3] * P[8] - P[5] * P[6]) +
                       P[2] * (P[3] * P[7] - P[4] * P[6]);
    size_t i;
    for (i = 0u; i < 3u; ++i) {
        const double v = P[i * 4u];
        var_min[i] = (v < var_min[i]) ? v : var_min[i];
        var_max[i] = (v > var_max[i]) ? v : var_max[i];
    }
    if ((det / (P[0] * P[4] * P[8])) < det_norm_min) {
        det_norm_min = det / (P[0] * P[4] * P[8]);
    }
}

static void track(double *worst, double value)
{
    if (value > *worst) {
        *worst = value;
    }
}

/* With slip_mode set, compare_one gives both twins the log's vx_true as the ground speed vx,
 * and 0.9 of it on rows [SLIP_FROM, SLIP_TO) (the wheels 11 % ahead: beyond slip_max 0.05),
 * counting the samples the slip paused. */
#define SLIP_FROM 500u
#define SLIP_TO 1000u
static int slip_mode;
static size_t n_slip_paused;
/* With abs_mode set, compare_one gives both twins vx_true as the ground speed and 1.1 times
 * it on the braked rows (the wheels 9 % behind: beyond the ABS gate's 0.05), counting the
 * steps whose latch is set (the same in both twins, checked at every step). */
static int abs_mode;
static size_t n_abs_latched;
static size_t n_chg_on; /* steps whose change test (pause_grade_dv) is tripped, both twins */
/* With walk_mode set, compare_one turns the grade's two-level walk on (q_theta_hi 0.008
 * rad/sqrt(s), §4.7) in both twins, counting the steps loose in the Q31 one and those whose
 * level differs between the twins (each compares its own s with on^2, off^2). */
static int walk_mode;
static size_t n_walk_hi;
static size_t n_walk_diff;

/* §4.7 the walk's level is a threshold decision on s, the grade rate's mean square, which
 * the Q31 twin carries in Q30 (LSB 9.3e-10 rad^2/s^2: 2.3e-4 of on^2 = 4e-6 at the presets'
 * 0.002 rad/s), rounded at every update, besides the twins' difference in the grade
 * increments it averages. Where the twins' levels differ, the Q31's s must be within
 * WALK_NEAR_Q31 of the threshold (on^2 or off^2) it decided on: a switch moved by that
 * rounding, not a different s (printed as "walk: ... s within ... of a threshold").
 * Its scale: s = r^2 averaged, r the grade's increments low-passed over tau_r, so a
 * difference dtheta between the twins' grades that builds up over tau_r moves r by
 * dtheta / tau_r and s by 2 dtheta / (tau_r on) relative at the threshold: 1.8e-3 with the
 * worst dtheta of every log (1.8e-6 rad, printed below) and the presets' 1 s, 0.002 rad/s;
 * measured 1.6e-3 at worst (4 samples over every log and configuration). The bound 5e-3 is that
 * scale with a factor of about 3 (the sign and timing of dtheta's build-up are not bounded
 * tighter than its size).
 * Then the Q31 twin takes the double's level (wq_hi, caller-owned state) for its next
 * sample, so the bounds above, which are the arithmetic's, keep holding on every later
 * sample; a moved switch runs one sample's time update with the other process noise, which
 * moves sd_grade by up to 7 % until the filter forgets it (~1 s; test_mass_grade_golden_flt.c,
 * the same rule for float32 against the reference). */
#define WALK_NEAR_Q31 5e-3
static double worst_walk_near;

static void walk_follow_double(rfe_mass_grade_q31_t *mq, const rfe_mass_grade_t *md,
                               const rfe_mass_grade_params_t *p, const char *what)
{
    const double s = rfe_fix_to_double(mq->wq_ms, 30u);
    const double on2 = p->theta_rate_on * p->theta_rate_on;
    const double off2 = p->theta_rate_off * p->theta_rate_off;
    const double near = fmin(fabs(s - on2) / on2, fabs(s - off2) / off2);
    track(&worst_walk_near, near);
    if (near > WALK_NEAR_Q31) {
        fail_msg("%s: walk level %u, the double's %u, s %.9g not near a threshold", what,
                 (unsigned)mq->wq_hi, (unsigned)md->wq_hi, s);
    }
    mq->wq_hi = md->wq_hi;
    ++n_walk_diff;
}

static void compare_one(const char *name)
{
    char golden_path[512];
    char log_path[512];
    char config[64] = "";
    char log_name[256];
    test_table_t log;
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_t pd;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_t md;
    rfe_mass_grade_q31_t mq;
    size_t k;
    const char *dot = strchr(name, '.');
    double tol_mass;
    double tol_rel;
    memset(&log, 0, sizeof(log));
    assert_non_null(dot);
    snprintf(golden_path, sizeof(golden_path), "%s/%s", GOLDEN_DIR, name);
    snprintf(log_name, sizeof(log_name), "%.*s", (int)(dot - name), name);
    snprintf(log_path, sizeof(log_path), "%s/%s.csv", LOG_DIR, log_name);
    assert_int_equal(mg_read_params(golden_path, &p, config, sizeof(config)), 0);
    assert_int_equal(test_table_load(log_path, &log), 0);
    if (walk_mode != 0) {
        p.q_theta_hi = 0.008;
    }
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_OK);
    dequantise_params(&q, &pd);
    assert_int_equal(rfe_mass_grade_init(&md, &pd), RFE_OK);
    assert_int_equal(rfe_mass_grade_init_q31(&mq, &q), RFE_OK);
    tol_mass = (p.adaptive == 1u) ? TOL_SD_AUKF : TOL_SD;
    tol_rel = (p.adaptive == 1u) ? TOL_REL_AUKF : TOL_REL;
    /* light mode (test_light.h: under valgrind, ~45x slower): the first MG_LIGHT_ROWS rows of
     * each log, each step still checked against the double one (a prefix of a causal filter's
     * run is the run of the prefix); the full logs run natively, under ASan and in coverage */
    if (rfe_test_light() && (log.n_rows > MG_LIGHT_ROWS)) {
        log.n_rows = MG_LIGHT_ROWS;
    }
    for (k = 0u; k < log.n_rows; ++k) {
        rfe_mass_grade_input_t in;
        rfe_mass_grade_input_t ind;
        rfe_mass_grade_input_q31_t inq;
        rfe_mass_grade_estimate_t ed;
        rfe_mass_grade_estimate_q31_t eq;
        char what[160];
        rfe_status_t sd_st;
        rfe_status_t sq_st;
        double d;
        mg_input_of(&log, k, p.R, &in);
        if (slip_mode != 0) {
            const double vx = test_table_get(&log, k, "vx_true");
            in.vx = ((k >= SLIP_FROM) && (k < SLIP_TO)) ? 0.9 * vx : vx;
            in.has |= RFE_MG_HAS_VX;
        }
        if (abs_mode != 0) {
            const double vx = test_table_get(&log, k, "vx_true");
            in.vx = (test_table_get(&log, k, "brake") >= 0.5) ? 1.1 * vx : vx;
            in.has |= RFE_MG_HAS_VX;
        }
        quantise_input(&in, &inq, &ind);
        sd_st = rfe_mass_grade_step(&md, &ind, &ed);
        sq_st = rfe_mass_grade_step_q31(&mq, &inq, &eq);
        snprintf(what, sizeof(what), "%s row %zu", name, k);
        assert_false(rfe_status_is_error(sd_st));
        assert_int_equal(sq_st, sd_st);
        n_slip_paused += (sd_st == RFE_MG_PAUSED_SLIP) ? 1u : 0u;
        assert_int_equal(mq.slip_latched, md.slip_latched);
        assert_int_equal(mq.chg_on, md.chg_on); /* the change test decides alike */
        n_chg_on += mq.chg_on;
        n_walk_hi += mq.wq_hi;
        if (mq.wq_hi != md.wq_hi) {
            walk_follow_double(&mq, &md, &p, what);
        }
        n_abs_latched += mq.slip_latched;
        ++n_steps;
        assert_int_equal(eq.sat, 0u);
        d = fabs(rfe_fix_to_double(eq.mass, QM) - ed.mass);
        track(&worst_mass_kg, d);
        if (p.adaptive == 0u) {
            track(&worst_mass_sd, d / ed.sd_mass);
        } else {
            track(&worst_mass_sd_aukf, d / ed.sd_mass);
            track(&worst_rel_aukf, fabs(rfe_fix_to_double(eq.sd_mass, QM) / ed.sd_mass - 1.0));
            if (ed.q_mv > 0.0) {
                track(&worst_rel_aukf,
                      fabs(rfe_fix64_to_double(eq.q_mv, RFE_MG_Q_QMV) / ed.q_mv - 1.0));
            }
        }
        if (sd_st == RFE_OK) {
            track_textbook(&md);
        }
        assert_close(rfe_fix_to_double(eq.mass, QM), ed.mass, tol_mass * ed.sd_mass + LSB(QM),
                     0.0, what);
        d = fabs(rfe_fix_to_double(eq.grade, QT) - ed.grade);
        track(&worst_grade_rad, d);
        track(&worst_grade_sd, d / ed.sd_grade);
        assert_close(rfe_fix_to_double(eq.grade, QT), ed.grade, TOL_SD * ed.sd_grade + LSB(QT),
                     0.0, what);
        d = fabs(rfe_fix_to_double(eq.v, QV) - ed.v);
        track(&worst_v_sd, d / ed.sd_v);
        assert_close(rfe_fix_to_double(eq.v, QV), ed.v, TOL_SD * ed.sd_v + LSB(QV), 0.0, what);
        assert_close(rfe_fix_to_double(eq.sd_v, QV), ed.sd_v, LSB(QV), TOL_REL, what);
        assert_close(rfe_fix_to_double(eq.sd_grade, QT), ed.sd_grade, LSB(QT), TOL_REL, what);
        assert_close(rfe_fix_to_double(eq.sd_mass, QM), ed.sd_mass, LSB(QM), tol_rel, what);
        assert_close(rfe_fix64_to_double(eq.q_mv, RFE_MG_Q_QMV), ed.q_mv, LSB(RFE_MG_Q_QMV),
                     tol_rel, what);
        if (p.adaptive == 0u) {
            track(&worst_sd_rel, fabs(rfe_fix_to_double(eq.sd_mass, QM) / ed.sd_mass - 1.0));
            track(&worst_sd_rel, fabs(rfe_fix_to_double(eq.sd_grade, QT) / ed.sd_grade - 1.0));
            track(&worst_sd_rel, fabs(rfe_fix_to_double(eq.sd_v, QV) / ed.sd_v - 1.0));
        }
    }
    test_table_free(&log);
}

/* The slip pause back to back (REQ-MG-006): on car_hilly_road in both presets with the
 * ground speed given and 500 rows of slip, the same statuses step by step (the slip
 * compared exactly in int64 on the Q values, in double on the same values dequantised) and
 * the estimates within the bounds above (a hold is a smaller step than an update: the same
 * triangularisation, no model, no gain). */
static void test_slip_pause_against_double(void **state)
{
    (void)state;
    slip_mode = 1;
    n_slip_paused = 0u;
    compare_one("car_hilly_road.recommended.csv");
    compare_one("car_hilly_road.seed.csv");
    slip_mode = 0;
    printf("q31 vs double with the slip pause: %zu samples paused by slip\n", n_slip_paused);
    /* every row of the window in both runs, unless a brake or shift pause came first */
    assert_true(n_slip_paused > 0u);
    assert_true(n_slip_paused <= 2u * (SLIP_TO - SLIP_FROM));
}

/* The ABS gate back to back (REQ-MG-006): car_stop_and_go with the brake and shift bits
 * (its pause_grade golden's parameters, the gate at its default 0.05) and the wheels 9 %
 * behind the ground speed on every braked row: the same statuses and latch step by step (the
 * gate compared exactly in int64 on the Q values, in double on the same values dequantised)
 * and the estimates within the bounds above (the latched samples hold, a smaller step than
 * the learning the golden already compares). */
static void test_abs_gate_against_double(void **state)
{
    (void)state;
    abs_mode = 1;
    n_abs_latched = 0u;
    compare_one("car_stop_and_go.pause_grade.csv");
    abs_mode = 0;
    printf("q31 vs double with the ABS gate: %zu steps latched\n", n_abs_latched);
    assert_true(n_abs_latched > 0u);
}

/* The two-level walk back to back (§4.7): the hilly road and the crest with q_theta_hi
 * 0.008 (the recommended preset's since the walk is on there; walk_mode sets it anyway, so
 * the test keeps its meaning if the preset changes), every step within the bounds above (the Q31 twin's r and
 * s in Q30, its d/tau, dt/tau, dt/avg by rounded divisions); the walk loosens on them, and
 * the twins' levels may differ only on the few steps where s crosses a threshold within the
 * twins' difference in the grade. */
static void test_walk_against_double(void **state)
{
    (void)state;
    walk_mode = 1;
    n_walk_hi = 0u;
    n_walk_diff = 0u;
    compare_one("car_hilly_road.recommended.csv");
    compare_one("car_long_curve_crest.recommended.csv");
    walk_mode = 0;
    printf("q31 vs double with the two-level walk: %zu steps loose, %zu with the level differing"
           " (walk: s within %.2g of a threshold there, worst of every run so far)\n",
           n_walk_hi, n_walk_diff, worst_walk_near);
    assert_true(n_walk_hi > 0u);
    assert_true(n_walk_diff * 100u < n_walk_hi); /* under 1 % of the loose steps */
}

/* §4.7 the walk's parameters on the Q values: each bound accepted at it and refused one LSB
 * beyond (the float twin's test_walk_params_rules on the real values). */
static void test_walk_params_rules_q31(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_params_q31_t b;
    (void)state;
    default_q31(&q);
    assert_int_equal(q.q_theta_hi, 4294967); /* on by default: 0.008 rad/sqrt(s) in Q29, rounded */
    assert_int_equal(rfe_mass_grade_params_validate_q31(&q), RFE_OK);
#define WALK_Q_(field, value, want)                                                          \
    b = q;                                                                                   \
    b.field = (value);                                                                       \
    assert_int_equal(rfe_mass_grade_params_validate_q31(&b), (want));
    WALK_Q_(q_theta_hi, q.q_theta, RFE_OK)
    WALK_Q_(q_theta_hi, q.q_theta - 1, RFE_ERR_PARAM)
    WALK_Q_(q_theta_hi, 53687091, RFE_OK)           /* 0.1 rad/sqrt(s) in Q29, rounded down */
    WALK_Q_(q_theta_hi, 53687092, RFE_ERR_PARAM)
    WALK_Q_(q_theta_hi, -q.q_theta, RFE_ERR_PARAM)
    WALK_Q_(theta_rate_on, 107374182, RFE_OK)       /* 0.1 rad/s in Q30, rounded down */
    WALK_Q_(theta_rate_on, 107374183, RFE_ERR_PARAM)
    WALK_Q_(theta_rate_off, q.theta_rate_on, RFE_OK)
    WALK_Q_(theta_rate_off, q.theta_rate_on + 1, RFE_ERR_PARAM)
    WALK_Q_(theta_rate_off, 0, RFE_ERR_PARAM)
    WALK_Q_(theta_rate_off, -1, RFE_ERR_PARAM)
    WALK_Q_(theta_rate_tau, q.dt_max / 64, RFE_OK)  /* dt_max 1 s: Q30 over 2^6 is Q24 */
    WALK_Q_(theta_rate_tau, (q.dt_max / 64) - 1, RFE_ERR_PARAM)
    WALK_Q_(theta_rate_tau, 60 * 16777216, RFE_OK)
    WALK_Q_(theta_rate_tau, (60 * 16777216) + 1, RFE_ERR_PARAM)
    WALK_Q_(theta_rate_avg, q.dt_max / 64, RFE_OK)
    WALK_Q_(theta_rate_avg, (q.dt_max / 64) - 1, RFE_ERR_PARAM)
    WALK_Q_(theta_rate_avg, 60 * 16777216, RFE_OK)
    WALK_Q_(theta_rate_avg, (60 * 16777216) + 1, RFE_ERR_PARAM)
#undef WALK_Q_
}

/* §4.8 the mismatch monitor in Q31 on the float twin's rigid drive
 * (test_mismatch_flag_after_the_derived_time, the derivation there): the model's ax 0, the
 * accelerometer's bias 0.06 m/s^2 = 2 mm_e r_ax, so the EMA e0 (1 - (1 - a)^k), e0 = 0.6,
 * a = dt / mm_tau = 0.002, crosses mm_e = 0.3 at the 347th update. The Q31 EMA's own error:
 * k = dt/tau in Q30 (rounded: relative 2e-7) and each step's product rounded to 1/2 LSB of
 * Q24 (3e-8), over 350 steps < 2e-5 absolute, against the crossing's margins 2e-4 and 4e-4
 * either side; one sample allowed either way all the same. */
static void mismatch_drive_q31(double bias, int monitor_on, int steps, int *first_flag,
                               double *worst_dev)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t m;
    rfe_mass_grade_input_q31_t in;
    rfe_mass_grade_estimate_q31_t e;
    uint32_t sat = 0u;
    const double v = 20.0;
    double f;
    int k;
    memset(&p, 0, sizeof(p));
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    p.sd_m0 = 1e-3;
    p.q_mc = 1e-3;
    p.sd_theta0 = 1e-6;
    p.q_theta = 1e-6;
    p.q_theta_hi = 0.0;
    p.pause_grade = 0.0;
    if (monitor_on == 0) {
        p.mm_e = 0.0; /* §4.8: mm_e 0 switches the flag off, the EMA still runs */
    }
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_OK);
    assert_int_equal(rfe_mass_grade_init_q31(&m, &q), RFE_OK);
    f = (double)p.fc + ((double)p.fr * v);
    memset(&in, 0, sizeof(in));
    in.dt = rfe_fix_from_double(0.02, RFE_MG_Q_DT, &sat);
    in.v = rfe_fix_from_double(v, QV, &sat);
    in.torque = rfe_fix_from_double(
        (double)p.R * (((double)p.m0 * (double)p.g * f) +
                       (0.5 * (double)p.rho * (double)p.cd * (double)p.area * v * v)),
        RFE_MG_Q_TORQUE, &sat);
    in.has = RFE_MG_HAS_AX;
    assert_int_equal(sat, 0u);
    *first_flag = -1;
    *worst_dev = 0.0;
    for (k = 0; k < steps; ++k) {
        const double e0 = bias / (double)p.r_ax;
        const double want = e0 * (1.0 - pow(1.0 - (0.02 / (double)p.mm_tau), (double)k));
        const double ax = (bias == 0.0) ? (((k % 2) == 0) ? 0.1 : -0.1) : bias;
        double ema;
        in.ax = rfe_fix_from_double(ax, QV, &sat);
        assert_int_equal(rfe_mass_grade_step_q31(&m, &in, &e), RFE_OK);
        ema = rfe_fix_to_double(e.e_ax, RFE_MG_Q_E);
        if ((e.mismatch != 0u) && (*first_flag < 0)) {
            *first_flag = k;
        }
        *worst_dev = fmax(*worst_dev, (bias == 0.0) ? fabs(ema) : (fabs(ema - want) / e0));
        assert_int_equal(e.mismatch,
                         ((monitor_on != 0) && ((e.e_ax > q.mm_e) || (e.e_ax < -q.mm_e))) ? 1u
                                                                                      : 0u);
    }
}

/* REQ-MG-010 */
static void test_mismatch_flag_q31(void **state)
{
    int first = 0;
    double dev = 0.0;
    (void)state;
    mismatch_drive_q31(0.06, 1, 600, &first, &dev);
    assert_true((first >= 346) && (first <= 348));
    assert_true(dev < 1e-3); /* the closed form, relative to e0 */
    /* unbiased: the EMA of +-1 stays within ~1e-3 of 0 (the float twin's bound) */
    mismatch_drive_q31(0.0, 1, 2000, &first, &dev);
    assert_int_equal(first, -1);
    assert_true(dev < 0.01);
    /* the monitor off (mm_e 0): the biased drive's EMA follows the same closed form past 0.3
     * and never flags */
    mismatch_drive_q31(0.06, 0, 600, &first, &dev);
    assert_int_equal(first, -1);
    assert_true(dev < 1e-3);
}

/* REQ-MG-010 §4.8's parameters in Q24: mm_tau in [dt_max, 60] s (dt_max compared in Q30),
 * mm_e in [0, 100]; each bound accepted at it and refused one LSB beyond. */
static void test_mismatch_params_q31(void **state)
{
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_params_q31_t b;
    rfe_mass_grade_q31_t m;
    rfe_mass_grade_q31_t before;
    (void)state;
    default_q31(&q);
    assert_int_equal(q.mm_tau, 10 * 16777216);
    assert_int_equal(q.mm_e, 5033165); /* 0.3 in Q24, rounded */
#define MM_Q_(field, value, want)                                                            \
    b = q;                                                                                   \
    b.field = (value);                                                                       \
    assert_int_equal(rfe_mass_grade_params_validate_q31(&b), (want));
    MM_Q_(mm_tau, q.dt_max / 64, RFE_OK)
    MM_Q_(mm_tau, (q.dt_max / 64) - 1, RFE_ERR_PARAM)
    MM_Q_(mm_tau, 60 * 16777216, RFE_OK)
    MM_Q_(mm_tau, (60 * 16777216) + 1, RFE_ERR_PARAM)
    MM_Q_(mm_e, 0, RFE_OK)
    MM_Q_(mm_e, -1, RFE_ERR_PARAM)
    MM_Q_(mm_e, 100 * 16777216, RFE_OK)
    MM_Q_(mm_e, (100 * 16777216) + 1, RFE_ERR_PARAM)
#undef MM_Q_
    /* a refused init leaves the estimator untouched */
    b = q;
    b.mm_e = -1;
    memset(&m, 0x5A, sizeof(m));
    before = m;
    assert_int_equal(rfe_mass_grade_init_q31(&m, &b), RFE_ERR_PARAM);
    assert_memory_equal(&m, &before, sizeof(m));
}

/* Whether the last step held (§4.2 the hold: v restarts at the measured speed, S_vv = r_v)
 * rather than learned the grade from ax (v the filter's, S_vv = r_v S'_vv / |(S'_vv, r_v)|
 * < r_v) or updated. */
static int held_q31(const rfe_mass_grade_q31_t *m, const rfe_mass_grade_input_q31_t *in)
{
    return ((m->x[0] == in->v) && (m->S[0] == m->p.r_v)) ? 1 : 0;
}

static int held_dbl(const rfe_mass_grade_t *m, const rfe_mass_grade_input_t *in)
{
    return ((m->x[0] == in->v) && (m->S[0] == m->p.r_v)) ? 1 : 0;
}

/* REQ-MG-006, REQ-MG-011 the grade from ax in a pause, back to back on a noise-free braked
 * input with no drive torque (as the ABS logs abs_brake_mu02.nf / mu09.nf: the mass never
 * excited, so an update's S_Mv is below the Q14 mass row's LSB and rounds to 0 in the twin
 * while double keeps it): the recommended preset with the simulator's resistances (fc, fr,
 * rho 0, as mass_pause_grade_study.py runs those logs) and the brake bit, 100 Hz; 1 s
 * coasting at 100 km/h, 3 s braked at 5 m/s^2 (ax = -5 exactly, v following it), 1 s released
 * at constant speed, 1 s braked again. At every step the same status, the same v_free and
 * the same decision, held or learned (held_q31/held_dbl); the first braked sample of each
 * pause holds in both (it follows an update: v was correlated with M, MASS_GRADE.md §4.2) and
 * the rest learn. The twins decided from S_Mv == 0 before: Q31 learned from the first braked
 * sample and parted from double (FIXED_POINT.md "Mass and grade"). */
static void test_pause_grade_decision_against_double(void **state)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_t pd;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_t md;
    rfe_mass_grade_q31_t mq;
    double v = 27.75;
    int k;
    int was_paused = 0;
    size_t n_learned = 0u;
    size_t n_first_held = 0u;
    (void)state;
    assert_int_equal(rfe_mass_grade_params_default(&p), RFE_OK);
    p.adaptive = 0u;
    p.use_ax = 1u;
    p.fc = 0.0;
    p.fr = 0.0;
    p.rho = 0.0;
    p.pause_grade = (double)RFE_MG_PAUSE_GRADE_BRAKE;
    p.pause_grade_dv = 0.0; /* v_free's decision alone (the change test: compare_one) */
    assert_int_equal(rfe_mass_grade_params_to_q31(&p, &q), RFE_OK);
    dequantise_params(&q, &pd);
    assert_int_equal(rfe_mass_grade_init(&md, &pd), RFE_OK);
    assert_int_equal(rfe_mass_grade_init_q31(&mq, &q), RFE_OK);
    for (k = 0; k < 600; ++k) {
        rfe_mass_grade_input_t in;
        rfe_mass_grade_input_t ind;
        rfe_mass_grade_input_q31_t inq;
        rfe_mass_grade_estimate_t ed;
        rfe_mass_grade_estimate_q31_t eq;
        rfe_status_t sd_st;
        rfe_status_t sq_st;
        const int braked = ((k >= 100) && (k < 400)) || (k >= 500);
        memset(&in, 0, sizeof(in));
        in.dt = 0.01;
        in.v = v;
        in.torque = 0.0; /* no drive torque */
        in.ax = braked ? -5.0 : 0.0;
        in.brake = braked ? 1u : 0u;
        in.has = RFE_MG_HAS_AX | RFE_MG_HAS_BRAKE;
        quantise_input(&in, &inq, &ind);
        sd_st = rfe_mass_grade_step(&md, &ind, &ed);
        sq_st = rfe_mass_grade_step_q31(&mq, &inq, &eq);
        assert_false(rfe_status_is_error(sd_st));
        assert_int_equal(sq_st, sd_st);
        assert_int_equal(mq.v_free, md.v_free);
        assert_int_equal(held_q31(&mq, &inq), held_dbl(&md, &ind));
        if ((k > 0) && (sd_st == RFE_MG_PAUSED_BRAKE)) {
            if (was_paused == 0) {
                assert_int_equal(held_dbl(&md, &ind), 1); /* after an update: the hold */
                ++n_first_held;
            } else {
                assert_int_equal(held_dbl(&md, &ind), 0); /* then learned */
                ++n_learned;
            }
        }
        was_paused = (sd_st != RFE_OK) ? 1 : 0;
        if (braked) {
            v -= 0.05; /* 5 m/s^2 over 0.01 s (both twins get the same quantised v) */
        }
    }
    printf("q31 vs double, brake pauses without drive torque: %zu first samples held, %zu "
           "learned, the same decision at every step\n", n_first_held, n_learned);
    assert_int_equal(n_first_held, 2u);
    assert_true(n_learned > 0u);
}

/* REQ-MG-011 */
static void test_every_log_against_double(void **state)
{
    (void)state;
    n_walk_diff = 0u;
    assert_true(test_each_csv(GOLDEN_DIR, compare_one) >= MIN_GOLDENS);
    printf("%zu steps with the change test tripped in both twins\n", n_chg_on);
    printf("walk: %zu samples with the twins' levels differing, s within %.2g of a threshold "
           "there (worst)\n", n_walk_diff, worst_walk_near);
    printf("%zu steps; q31 vs double, every log and configuration: mass %.3g kg (UKF %.3g sd_mass), "
           "grade %.3g rad (%.3g sd_grade), v %.3g sd_v, UKF sds %.3g relative\n",
           n_steps, worst_mass_kg, worst_mass_sd, worst_grade_rad, worst_grade_sd, worst_v_sd,
           worst_sd_rel);
    printf("q31 vs double, AUKF: mass %.3g sd_mass, sd_mass and q_mv %.3g relative\n",
           worst_mass_sd_aukf, worst_rel_aukf);
    printf("double P over every update: var v [%.3g, %.3g], var M [%.3g, %.3g], var theta "
           "[%.3g, %.3g]; min det P / (P11 P22 P33) %.3g\n",
           var_min[0], var_max[0], var_min[1], var_max[1], var_min[2], var_max[2], det_norm_min);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_to_q31_formats),
        cmocka_unit_test(test_params_to_q31_errors),
        cmocka_unit_test(test_weights_of_the_defaults),
        cmocka_unit_test(test_weights_domain),
        cmocka_unit_test(test_validate_q31),
        cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_slip_pause_q31),
        cmocka_unit_test(test_curve_pause_q31),
        cmocka_unit_test(test_pause_grade_q31),
        cmocka_unit_test(test_abs_gate_q31),
        cmocka_unit_test(test_change_test_q31),
        cmocka_unit_test(test_abs_gate_against_double),
        cmocka_unit_test(test_pause_grade_decision_against_double),
        cmocka_unit_test(test_slip_pause_against_double),
        cmocka_unit_test(test_step_errors_leave_state),
        cmocka_unit_test(test_start_and_restart),
        cmocka_unit_test(test_pauses),
        cmocka_unit_test(test_correct_zero_innovation_sd),
        cmocka_unit_test(test_square_root_form_stays_definite),
        cmocka_unit_test(test_every_log_against_double),
        cmocka_unit_test(test_walk_against_double),
        cmocka_unit_test(test_walk_params_rules_q31),
        cmocka_unit_test(test_mismatch_flag_q31),
        cmocka_unit_test(test_mismatch_params_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
