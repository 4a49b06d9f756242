/**
 * @file test_meas_flt.c
 * @brief The measurement model (src/models/meas_flt.c), bit for bit and status for status:
 *  - at a perturbed input (rfe_meas_nominal, rfe_meas_eval_perturbed; the step noise's model
 *    evaluations, docs/ESTIMATOR.md step 4) against a full rfe_meas_setup + rfe_meas_eval at
 *    the perturbed sample, in every tyre mode and for every input, and their argument checks;
 *  - rfe_meas_eval with the terms cached by rfe_meas_setup, against the chain
 *    rfe_tyre_forces_abs -> rfe_obsmat_build -> rfe_obsmat_apply(H, ones), also when eval is
 *    given other tyre parameters than the set-up (the cached terms are then not used);
 *  - the lateral rows' analytic derivatives (rfe_meas_lateral_jac, docs/OBSERVER.md §4.2)
 *    and the derivatives by every input (rfe_meas_input_jac, for the step noise, docs/ESTIMATOR.md
 *    step 4) against central differences of full set-ups and evaluations, in every tyre mode.
 * Inputs from a fixed-seed generator (test_draws.h), some beyond the limits.
 */
#include "test_light.h"
#include "test_common.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "rfe/component/meas.h"
#include "rfe/component/obsmat.h"
#include "rfe/params.h"
#include "rfe/component/tyre.h"

#include "models/meas_internal.h"
#include "test_draws.h"

/* The largest finite real of the build (float or double). */
#if defined(RFE_REAL_DOUBLE)
#define HUGE_REAL ((rfe_real_t)DBL_MAX)
#else
#define HUGE_REAL ((rfe_real_t)FLT_MAX)
#endif

#define N_CASES 4000         /* perturbed-input cases */
#define N_CACHED_CASES 20000 /* cached-terms cases */
#define N_JAC_CASES 6000     /* derivative cases (2000 per tyre mode) */

/* The derivatives' tolerance. A central difference D(h) = (f(x + h) - f(x - h)) / 2h differs
 * from f' by its truncation h^2 f''' / 6 + ... and its rounding <= 2 EPS_F max|f| / h. The
 * truncation is estimated from the same function: D(2h) - D(h) = 3 h^2 f''' / 6 + O(h^4), so
 * |D(h) - f'| <= |D(2h) - D(h)| / 3 (1 + o(1)) + rounding; the bound below takes the whole
 * difference D(2h) - D(h) (three times the estimate: margin for the O(h^4) terms), the
 * rounding of the evaluations (8 EPS_F over h of the rows' term scale, term_scale) and a
 * relative floor REL_FLOOR |f'| for the analytic side's own rounding. Where a clamp or branch of the model (alpha_max, the
 * kappa clip, L = 1, E = 0, mu = 0, den's max) lies within 2h the difference is not a
 * derivative: D(2h) - D(h) is then large and so is the bound, and such cases are counted; at
 * least MIN_TIGHT of the cases must have a bound below TIGHT relative (the test is not
 * vacuous). A smooth function's differences shrink as h^2: D(4h) - D(2h) = 4 (D(2h) - D(h));
 * a kink within 4h breaks that ratio, and a kink nearer than h, where the central differences
 * of both steps are the same mean of the two sides' slopes, leaves the one-sided differences'
 * gap F - B the jump whatever the step, where a smooth function's grows as h (F(2h) - B(2h)
 * = 2 (F(h) - B(h))). Such cases (a few in a thousand) are not compared but counted
 * (at most MAX_KINKED of them); a kink too small to be told from the rounding by that test
 * moves D(h) by at most half the gap F(h) - B(h) it leaves (the derivative's jump times the
 * share of the step beyond it), which the bound adds (in a smooth stretch that gap is h f'',
 * which sets TIGHT). Double: h = 1e-4 (m/s for vy, unit sd steps for mu), float: h = 1e-2. */
#if defined(RFE_REAL_DOUBLE)
#define JAC_H 1e-4
#define EPS_F 2.3e-16
#define REL_FLOOR 1e-9
#define TIGHT 1e-4
#else
#define JAC_H 1e-2
#define EPS_F 1.2e-7
#define REL_FLOOR 1e-4
#define TIGHT 1e-2
#endif
#define MIN_TIGHT 0.9
#define MAX_KINKED 0.01
/* test_meas_input_jac, float32 only: the analytic derivative's own rounding, relative to the
 * rows' term scale (its ~30 chained operations carry terms up to that scale into a sum that
 * may cancel; measured: 6 % of a yaw-row derivative of 0.008 at delta 0.48 rad, paper tyre),
 * and the speed below which the differences are not compared: the step noise runs from
 * v_est_min (3 m/s, ESTIMATOR.md step 3) up, and below it a float32 central difference of
 * 1e-2 m/s is not a derivative (measured at 0.2-2.7 m/s: 9 % off, converging linearly in the
 * step; the double build compares every speed). */
#if defined(RFE_REAL_DOUBLE)
#define TERM_REL 0.0
#define JAC_V_MIN 0.0
#define MIN_TIGHT_IN 0.9 /* measured 0.96 */
#else
#define TERM_REL 1e-3
#define JAC_V_MIN 3.0
#define MIN_TIGHT_IN 0.7 /* measured 0.75: TERM_REL is most of the bound of small derivatives */
#endif
#define RFE_R(x) ((rfe_real_t)(x))

/* u with input j changed by d, as a caller would write it. */
static rfe_sample_t perturb(const rfe_sample_t *u, size_t j, rfe_real_t d)
{
    rfe_sample_t up = *u;
    switch (j) {
    case RFE_IN_DELTA: up.delta += d; break;
    case RFE_IN_VX: up.vx += d; break;
    case RFE_IN_VY: up.vy += d; break;
    case RFE_IN_YAW_RATE: up.yaw_rate += d; break;
    default: up.omega[j - RFE_IN_OMEGA] += d; break;
    }
    return up;
}

static const rfe_tyre_mode_t MODES[3] = {RFE_TYRE_PAPER, RFE_TYRE_ABSOLUTE, RFE_TYRE_MAGIC};

/* REQ: the model at u + d e_j from the set-up model at u (nominal terms of the wheels input j
 * does not reach reused) is the full set-up and evaluation at u + d e_j, bits and statuses,
 * for every input and tyre mode, including perturbations that overflow the input; the
 * nominal z is rfe_meas_eval's. */
/* REQ-MEAS-001 */
static void test_meas_perturbed(void **state)
{
    int n;
    int n_case = 0; /* cases walked, so the light mode's stride keeps every kind */
    long compared = 0;
    long failed = 0;
    (void)state;
    draw_seed(0x9E3779B97F4A7C15ull);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        ++n_case;
        rfe_params_t p;
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_meas_t h;
        rfe_meas_terms_t nom;
        rfe_real_t z0[3];
        rfe_real_t ze[3];
        size_t j;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        p.tyre.mode = MODES[n % 3];
        draw_sample(&u, mu, 1);
        if (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK) {
            continue;
        }
        {
            const rfe_status_t st = rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, &nom, z0);
            assert_int_equal(st, rfe_meas_eval(&h, &p.vehicle, &p.tyre, mu, ze));
            if (st != RFE_OK) {
                continue;
            }
            assert_memory_equal(z0, ze, sizeof(z0));
        }
        for (j = 0; j < (size_t)RFE_INPUTS; ++j) {
            /* a small step, a large one, and (every 16th case) an infinite one */
            const double mag = ((n_case % 2) == 0) ? 1e-2 : 0.3;
            const rfe_real_t dm = ((n_case % 16) == 5) ? (rfe_real_t)INFINITY : (rfe_real_t)mag;
            const rfe_real_t d = ((draw_u64() & 1u) != 0u) ? dm : -dm;
            const rfe_sample_t up = perturb(&u, j, d);
            rfe_meas_t hp;
            rfe_real_t zg[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
            rfe_real_t zw[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
            rfe_status_t want = rfe_meas_setup(&hp, &p.vehicle, &p.tyre, &up);
            const rfe_status_t got =
                rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, j, d, mu, zg);
            if (want == RFE_OK) {
                want = rfe_meas_eval(&hp, &p.vehicle, &p.tyre, mu, zw);
            }
            assert_int_equal(got, want);
            assert_memory_equal(zg, zw, sizeof(zg)); /* on an error both untouched */
            ++compared;
            failed += (got != RFE_OK) ? 1 : 0;
        }
    }
    print_message("meas perturbed: %ld evaluations bit-identical, %ld of them errors\n",
                  compared, failed);
    assert_true(compared > 1000);
    assert_true(failed > 0); /* the error statuses were exercised */
}

/* REQ: bad arguments are rejected with a status and nothing written; paper mode leaves the
 * nominal terms untouched. */
/* REQ-MEAS-002 */
static void test_meas_perturbed_args(void **state)
{
    rfe_params_t p;
    rfe_sample_t u;
    rfe_real_t mu[4];
    rfe_meas_t h;
    rfe_meas_terms_t nom;
    rfe_meas_terms_t nom0;
    rfe_real_t z[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
    const rfe_real_t z7[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
    (void)state;
    draw_seed(0x1234567ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    p.tyre.mode = RFE_TYRE_ABSOLUTE;
    draw_sample(&u, mu, 1);
    u.vx = RFE_R(20.0);
    assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
    assert_int_equal(rfe_meas_nominal(NULL, &p.vehicle, &p.tyre, mu, &nom, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, NULL, &p.tyre, mu, &nom, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, NULL, mu, &nom, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, NULL, &nom, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, NULL, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, &nom, NULL), RFE_ERR_NULL);
    assert_memory_equal(z, z7, sizeof(z));
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, &nom, z), RFE_OK);
    z[0] = z[1] = z[2] = RFE_R(7.0);
    assert_int_equal(rfe_meas_eval_perturbed(NULL, &p.vehicle, &p.tyre, &nom, &u, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, NULL, &p.tyre, &nom, &u, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, NULL, &nom, &u, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, NULL, &u, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, NULL, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, 0u, RFE_R(0.1), NULL, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, 0u, RFE_R(0.1), mu, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, (size_t)RFE_INPUTS, RFE_R(0.1), mu, z), RFE_ERR_PARAM);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, RFE_IN_VX, (rfe_real_t)NAN, mu, z), RFE_ERR_NONFINITE);
    assert_memory_equal(z, z7, sizeof(z));
    /* a non-finite friction at a wheel the input reaches: the tyre's check fails the call,
     * z untouched (since issue 21 the step noise no longer perturbs, so this is its test) */
    {
        rfe_real_t mu_bad[4];
        memcpy(mu_bad, mu, sizeof(mu_bad));
        mu_bad[2] = (rfe_real_t)NAN;
        assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, RFE_IN_VX, RFE_R(0.1), mu_bad, z), RFE_ERR_NONFINITE);
        assert_memory_equal(z, z7, sizeof(z));
    }
    /* paper mode: z as rfe_meas_eval, the terms untouched */
    p.tyre.mode = RFE_TYRE_PAPER;
    assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
    memset(&nom, 0x5A, sizeof(nom));
    nom0 = nom;
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, &nom, z), RFE_OK);
    assert_memory_equal(&nom, &nom0, sizeof(nom));
}

/* The absolute-mode chain of the public functions at tyre parameters tp. */
static rfe_status_t chain(const rfe_meas_t *h, const rfe_vehicle_t *veh,
                          const rfe_tyre_params_t *tp, const rfe_real_t mu[4], rfe_real_t z[3])
{
    static const rfe_real_t ones[4] = {RFE_R(1.0), RFE_R(1.0), RFE_R(1.0), RFE_R(1.0)};
    rfe_real_t fx[4];
    rfe_real_t fy[4];
    rfe_real_t H[RFE_H_SIZE];
    rfe_status_t st = rfe_tyre_forces_abs(tp, &h->kin, mu, fx, fy);
    if (st == RFE_OK) {
        st = rfe_obsmat_build(veh, h->delta, fx, fy, H);
    }
    if (st == RFE_OK) {
        st = rfe_obsmat_apply(H, ones, z);
    }
    return st;
}

/* REQ: eval with the cached terms is the public chain (forces, H, H ones), bits and
 * statuses, also for other tyre parameters than the set-up's. */
/* REQ-MEAS-001 */
static void test_meas_cached(void **state)
{
    rfe_params_t p;
    int n;
    (void)state;
    draw_seed(0x3EA5C0ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    for (n = 0; n < N_CACHED_CASES; n += (int)rfe_test_stride(10u)) {
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_meas_t h;
        rfe_tyre_params_t other = p.tyre;
        rfe_real_t z1[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
        rfe_real_t z2[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
        draw_sample(&u, mu, ((n % 4) != 0) ? 1 : 0);
        if (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK) {
            continue;
        }
        assert_int_equal(rfe_meas_eval(&h, &p.vehicle, &p.tyre, mu, z1),
                         chain(&h, &p.vehicle, &p.tyre, mu, z2));
        assert_memory_equal(z1, z2, sizeof(z1));
        other.cx = (rfe_real_t)draw_uniform(0.0, 60.0);
        other.cy = (rfe_real_t)draw_uniform(0.0, 60.0);
        other.eps = (n % 2) ? (rfe_real_t)NAN : (rfe_real_t)draw_uniform(0.0, 0.05);
        assert_int_equal(rfe_meas_eval(&h, &p.vehicle, &other, mu, z1),
                         chain(&h, &p.vehicle, &other, mu, z2));
        assert_memory_equal(z1, z2, sizeof(z1));
    }
}

/* REQ: the cached terms are used only for the set-up's own tyre: changing any one of the
 * mode (magic <-> absolute Dugoff), cx, cy, eps, alpha_max alone makes eval recompute them,
 * giving the public chain's bits. */
/* REQ-MEAS-001 */
static void test_meas_cached_each_field(void **state)
{
    rfe_params_t p;
    rfe_sample_t u;
    rfe_real_t mu[4];
    rfe_meas_t h;
    int f;
    (void)state;
    draw_seed(0xF1E1Dull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    do {
        draw_sample(&u, mu, 1);
    } while (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK);
    for (f = 0; f < 5; ++f) {
        rfe_tyre_params_t other = p.tyre;
        rfe_real_t z1[3];
        rfe_real_t z2[3];
        if (f == 4) {
            other.mode = RFE_TYRE_ABSOLUTE;
        } else if (f == 0) {
            other.cx *= RFE_R(1.5);
        } else if (f == 1) {
            other.cy *= RFE_R(1.5);
        } else if (f == 2) {
            other.eps += RFE_R(0.01);
        } else {
            other.alpha_max *= RFE_R(0.5);
        }
        assert_int_equal(rfe_meas_eval(&h, &p.vehicle, &other, mu, z1),
                         chain(&h, &p.vehicle, &other, mu, z2));
        assert_memory_equal(z1, z2, sizeof(z1));
    }
    /* set up for the absolute Dugoff (no direction cosines cached), evaluated as magic */
    {
        rfe_tyre_params_t dug = p.tyre;
        rfe_meas_t h2;
        rfe_real_t z1[3];
        rfe_real_t z2[3];
        dug.mode = RFE_TYRE_ABSOLUTE;
        assert_int_equal(rfe_meas_setup(&h2, &p.vehicle, &dug, &u), RFE_OK);
        assert_int_equal(rfe_meas_eval(&h2, &p.vehicle, &p.tyre, mu, z1),
                         chain(&h2, &p.vehicle, &p.tyre, mu, z2));
        assert_memory_equal(z1, z2, sizeof(z1));
    }
}

/* Rows ay, r-dot of h(mu, u) at u with vy moved by dvy and mu moved by t dmu: a full set-up
 * and evaluation. */
static rfe_status_t rows_at(const rfe_params_t *p, const rfe_sample_t *u, double dvy,
                            const rfe_real_t mu[4], const rfe_real_t dmu[4], double t,
                            double z[2])
{
    rfe_sample_t up = *u;
    rfe_real_t m[4];
    rfe_real_t zz[3];
    rfe_meas_t h;
    size_t i;
    rfe_status_t st;
    up.vy = (rfe_real_t)((double)u->vy + dvy);
    for (i = 0u; i < 4u; ++i) {
        m[i] = (rfe_real_t)((double)mu[i] + (t * (double)dmu[i]));
    }
    st = rfe_meas_setup(&h, &p->vehicle, &p->tyre, &up);
    if (st == RFE_OK) {
        st = rfe_meas_eval(&h, &p->vehicle, &p->tyre, m, zz);
    }
    z[0] = (double)zz[1];
    z[1] = (double)zz[2];
    return st;
}

/* Central differences D(h), D(2h), D(4h) of the two rows by vy (which = 0) or by mu along dmu
 * (which = 1) in d[0..2], the one-sided differences' gaps F(h) - B(h), F(2h) - B(2h) in
 * gap[0..1]; 0 when an evaluation failed. */
static int central(const rfe_params_t *p, const rfe_sample_t *u, const rfe_real_t mu[4],
                   const rfe_real_t dmu[4], int which, double d[3][2], double gap[2][2])
{
    double z[7][2];
    int k;
    int r;
    for (k = 0; k < 7; ++k) {
        /* +h, -h, +2h, -2h, +4h, -4h, 0 */
        const double st =
            (k == 6) ? 0.0 : (double)(1 << (k / 2)) * (((k % 2) == 0) ? JAC_H : -JAC_H);
        const double dv = (which == 0) ? st : 0.0;
        const double dm = (which == 0) ? 0.0 : st;
        if (rows_at(p, u, dv, mu, dmu, dm, z[k]) != RFE_OK) {
            return 0;
        }
    }
    for (r = 0; r < 2; ++r) {
        for (k = 0; k < 3; ++k) {
            d[k][r] = (z[2 * k][r] - z[(2 * k) + 1][r]) / (2.0 * JAC_H * (double)(1 << k));
        }
        for (k = 0; k < 2; ++k) {
            gap[k][r] = ((z[2 * k][r] - z[6][r]) - (z[6][r] - z[(2 * k) + 1][r])) /
                        (JAC_H * (double)(1 << k));
        }
    }
    return 1;
}

/* The rounding scale of each row: a wheel's force is at most |mu| Fz (every tyre mode) on the
 * stencil (|mu| + 4h dmu), its terms at most that over m (ay) and times |(x_i, y_i)| / J
 * (r-dot); the rows' rounding is a few EPS_F of the sum of the terms' magnitudes. */
static void term_scale(const rfe_params_t *p, const rfe_meas_t *h, const rfe_real_t mu[4],
                       const rfe_real_t dmu[4], double scale[2])
{
    const double x[4] = {p->vehicle.Lf, p->vehicle.Lf, -p->vehicle.Lr, -p->vehicle.Lr};
    const double y[4] = {p->vehicle.Bf / 2.0, p->vehicle.Bf / 2.0, p->vehicle.Br / 2.0,
                         p->vehicle.Br / 2.0};
    int i;
    scale[0] = 0.0;
    scale[1] = 0.0;
    for (i = 0; i < 4; ++i) {
        const double f = (fabs((double)mu[i]) + (4.0 * JAC_H * (double)dmu[i])) *
                         (double)h->kin.fz[i];
        scale[0] += f / (double)p->vehicle.m;
        scale[1] += f * sqrt((x[i] * x[i]) + (y[i] * y[i])) / (double)p->vehicle.J;
    }
}

/* REQ: the lateral rows' derivatives by vy and by the friction along dmu are the model's
 * (central differences of full set-ups and evaluations within their truncation and rounding
 * error), in every tyre mode, and the rows are rfe_meas_eval's bit for bit. */
/* REQ-MEAS-003 */
static void test_meas_lateral_jac(void **state)
{
    long checked = 0;
    long tight = 0;
    long kinked = 0;
    long worse[3] = {0, 0, 0};
    double worst = 0.0;
    int n;
    (void)state;
    draw_seed(0xD1FFEull);
    for (n = 0; n < N_JAC_CASES; n += (int)rfe_test_stride(10u)) {
        rfe_params_t p;
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_real_t dmu[4];
        rfe_real_t ze[3];
        rfe_meas_t h;
        rfe_meas_lateral_t out;
        size_t i;
        int which;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        p.tyre.mode = MODES[n % 3];
        draw_sample(&u, mu, 1);
        for (i = 0u; i < 4u; ++i) {
            dmu[i] = (rfe_real_t)draw_uniform(0.0, 0.5);
        }
        if ((n % 50) < 3) {
            /* no slip at all (S = 0 on every wheel: the limits of the derivatives) */
            u.delta = RFE_R(0.0);
            u.vy = RFE_R(0.0);
            u.yaw_rate = RFE_R(0.0);
            for (i = 0u; i < 4u; ++i) {
                u.omega[i] = RFE_R(20.0) / p.vehicle.R;
            }
            u.vx = u.omega[0] * p.vehicle.R;
        }
        if (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK) {
            continue;
        }
        assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, &p.tyre, &u, mu, dmu, &out),
                         rfe_meas_eval(&h, &p.vehicle, &p.tyre, mu, ze));
        assert_memory_equal(out.z, &ze[1], sizeof(out.z));
        for (which = 0; which < 2; ++which) {
            const rfe_real_t *an = (which == 0) ? out.d_vy : out.d_mu;
            double d[3][2];
            double gap[2][2];
            double sc[2];
            int r;
            if (central(&p, &u, mu, dmu, which, d, gap) == 0) {
                continue;
            }
            term_scale(&p, &h, mu, dmu, sc);
            for (r = 0; r < 2; ++r) {
                const double a = (double)an[r];
                const double noise = 8.0 * EPS_F * sc[r] / JAC_H;
                const double d12 = fabs(d[1][r] - d[0][r]);
                const double g1 = fabs(gap[0][r]);
                const double tol = d12 + (0.5 * g1) + noise + (REL_FLOOR * fabs(a));
                const double err = fabs(a - d[0][r]);
                if (((d12 > (2.0 * noise)) && (fabs(d[2][r] - d[1][r]) < (2.0 * d12))) ||
                    ((g1 > (4.0 * noise)) && (fabs(gap[1][r]) < (1.5 * g1)))) {
                    ++kinked; /* not smooth within 4h */
                    continue;
                }
                if (err > tol) {
                    print_message("case %d mode %d %s row %d: analytic %.12g, difference "
                                  "%.12g (2h: %.12g), bound %.3g\n",
                                  n, (int)p.tyre.mode, (which == 0) ? "d/dvy" : "d/dmu", r,
                                  a, d[0][r], d[1][r], tol);
                    print_message("  u: delta %.17g vx %.17g vy %.17g r %.17g ax %.17g ay %.17g "
                                  "omega %.17g %.17g %.17g %.17g mu %.17g %.17g %.17g %.17g "
                                  "dmu %.17g %.17g %.17g %.17g\n",
                                  (double)u.delta, (double)u.vx, (double)u.vy,
                                  (double)u.yaw_rate, (double)u.ax, (double)u.ay,
                                  (double)u.omega[0], (double)u.omega[1], (double)u.omega[2],
                                  (double)u.omega[3], (double)mu[0], (double)mu[1],
                                  (double)mu[2], (double)mu[3], (double)dmu[0], (double)dmu[1],
                                  (double)dmu[2], (double)dmu[3]);
                    ++worse[n % 3];
                }
                if (tol <= (TIGHT * fmax(fabs(a), 1.0))) {
                    ++tight;
                }
                worst = fmax(worst, err / fmax(fabs(a), 1.0));
                ++checked;
            }
        }
    }
    print_message("meas lateral jac: %ld derivatives against central differences, %ld with a "
                  "tight bound, worst error %.3g (relative to max(|f'|, 1)); %ld not smooth "
                  "within 4h, not compared\n",
                  checked, tight, worst, kinked);
    assert_int_equal(worse[0], 0);
    assert_int_equal(worse[1], 0);
    assert_int_equal(worse[2], 0);
    assert_true(checked > 1000);
    assert_true((double)tight >= (MIN_TIGHT * (double)checked));
    assert_true((double)kinked <= (MAX_KINKED * (double)(checked + kinked)));
}

/* REQ: the derivatives with tyre parameters other than the set-up's recompute the cached terms
 * (the same derivatives as a set-up with those parameters); bad arguments and non-finite friction
 * or directions are rejected with rfe_meas_eval's statuses, nothing written. */
/* REQ-MEAS-002 */
/* REQ-MEAS-003 */
static void test_meas_lateral_jac_args(void **state)
{
    rfe_params_t p;
    rfe_sample_t u;
    rfe_real_t mu[4];
    rfe_real_t dmu[4] = {RFE_R(0.1), RFE_R(0.1), RFE_R(0.2), RFE_R(0.2)};
    rfe_meas_t h;
    rfe_meas_lateral_t out;
    rfe_meas_lateral_t out0;
    int m;
    (void)state;
    draw_seed(0xA1B2C3ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    draw_sample(&u, mu, 1);
    u.vx = RFE_R(20.0);
    for (m = 0; m < 3; ++m) {
        rfe_tyre_params_t other = p.tyre;
        rfe_meas_t h2;
        rfe_meas_lateral_t o2;
        rfe_real_t bad[4];
        p.tyre.mode = MODES[m];
        other.mode = MODES[m];
        other.cy *= RFE_R(1.3);
        other.Cy_n *= RFE_R(1.3);
        assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
        assert_int_equal(rfe_meas_setup(&h2, &p.vehicle, &other, &u), RFE_OK);
        assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, &other, &u, mu, dmu, &out),
                         RFE_OK);
        assert_int_equal(rfe_meas_lateral_jac(&h2, &p.vehicle, &other, &u, mu, dmu, &o2),
                         RFE_OK);
        /* paper mode's rows are H(u) mu of the set-up, as rfe_meas_eval's */
        if (MODES[m] != RFE_TYRE_PAPER) {
            assert_memory_equal(out.z, o2.z, sizeof(out.z));
        }
        assert_memory_equal(out.d_vy, o2.d_vy, sizeof(out.d_vy));
        assert_memory_equal(out.d_mu, o2.d_mu, sizeof(out.d_mu));
        memset(&out, 0x5A, sizeof(out));
        out0 = out;
        memcpy(bad, mu, sizeof(bad));
        bad[2] = (rfe_real_t)NAN;
        assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, &p.tyre, &u, bad, dmu, &out),
                         RFE_ERR_NONFINITE);
        memcpy(bad, dmu, sizeof(bad));
        bad[1] = (rfe_real_t)INFINITY;
        assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, &p.tyre, &u, mu, bad, &out),
                         RFE_ERR_NONFINITE);
        assert_memory_equal(&out, &out0, sizeof(out));
    }
    assert_int_equal(rfe_meas_lateral_jac(NULL, &p.vehicle, &p.tyre, &u, mu, dmu, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac(&h, NULL, &p.tyre, &u, mu, dmu, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, NULL, &u, mu, dmu, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, &p.tyre, NULL, mu, dmu, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, &p.tyre, &u, NULL, dmu, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, &p.tyre, &u, mu, NULL, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac(&h, &p.vehicle, &p.tyre, &u, mu, dmu, NULL), RFE_ERR_NULL);
    assert_memory_equal(&out, &out0, sizeof(out));
}

/* ---- the derivatives by the inputs (rfe_meas_input_jac, docs/ESTIMATOR.md step 4) ----------- */

/* h(mu, u + d e_j): a full set-up and evaluation (all three rows). */
static rfe_status_t rows3_at(const rfe_params_t *p, const rfe_sample_t *u, size_t j, double d,
                             const rfe_real_t mu[4], double z[3])
{
    rfe_sample_t up = *u;
    rfe_real_t *slot = &up.delta;
    rfe_real_t zz[3];
    rfe_meas_t h;
    rfe_status_t st;
    int r;
    switch (j) {
    case RFE_IN_DELTA: slot = &up.delta; break;
    case RFE_IN_VX: slot = &up.vx; break;
    case RFE_IN_VY: slot = &up.vy; break;
    case RFE_IN_YAW_RATE: slot = &up.yaw_rate; break;
    default: slot = &up.omega[j - RFE_IN_OMEGA]; break;
    }
    *slot = (rfe_real_t)((double)*slot + d);
    st = rfe_meas_setup(&h, &p->vehicle, &p->tyre, &up);
    if (st == RFE_OK) {
        st = rfe_meas_eval(&h, &p->vehicle, &p->tyre, mu, zz);
    }
    for (r = 0; r < 3; ++r) {
        z[r] = (double)zz[r];
    }
    return st;
}

/* The step of input j's differences: JAC_H in its unit (m/s, rad/s), a tenth of it for delta
 * (rad), whose slip angles' curves bend on a scale ten times shorter than the speeds'. */
static double input_step(size_t j)
{
    return (j == (size_t)RFE_IN_DELTA) ? (0.1 * JAC_H) : JAC_H;
}

/* central()'s differences for input j, all three rows: D(h), D(2h), D(4h) in d, the one-sided
 * gaps in gap, h = input_step(j); 0 when an evaluation failed. */
static int central3(const rfe_params_t *p, const rfe_sample_t *u, const rfe_real_t mu[4],
                    size_t j, double d[3][3], double gap[2][3])
{
    const double hj = input_step(j);
    double z[7][3];
    int k;
    int r;
    for (k = 0; k < 7; ++k) {
        const double st =
            (k == 6) ? 0.0 : (double)(1 << (k / 2)) * (((k % 2) == 0) ? hj : -hj);
        if (rows3_at(p, u, j, st, mu, z[k]) != RFE_OK) {
            return 0;
        }
    }
    for (r = 0; r < 3; ++r) {
        for (k = 0; k < 3; ++k) {
            d[k][r] = (z[2 * k][r] - z[(2 * k) + 1][r]) / (2.0 * hj * (double)(1 << k));
        }
        for (k = 0; k < 2; ++k) {
            gap[k][r] = ((z[2 * k][r] - z[6][r]) - (z[6][r] - z[(2 * k) + 1][r])) /
                        (hj * (double)(1 << k));
        }
    }
    return 1;
}

/* One of the operating points of test_meas_input_jac: every 50 cases, a free-rolling sample
 * (no slip: S = 0), a locked wheel (kappa clipped at -1: saturated, its slip derivative 0), a
 * wheel spinning (kappa +0.6, far beyond the curves' peaks), a drift (|alpha| beyond
 * alpha_max on the rear wheels: the clamp) and a hard turn at low friction (the forces on the
 * saturated part of the curves: Dugoff's L < 1, the Magic Formula past its peak); the rest
 * random (test_draws.h). */
static void input_jac_point(const rfe_params_t *p, int n, rfe_sample_t *u, rfe_real_t mu[4])
{
    const int c = n % 50;
    size_t i;
    draw_sample(u, mu, 1);
    if (c < 5) {
        u->delta = RFE_R(0.0);
        u->vy = RFE_R(0.0);
        u->yaw_rate = RFE_R(0.0);
        u->vx = RFE_R(20.0);
        for (i = 0u; i < 4u; ++i) {
            u->omega[i] = u->vx / p->vehicle.R;
        }
    }
    if (c == 1) {
        u->omega[2] = RFE_R(0.0); /* locked */
        u->delta = RFE_R(0.05);
    } else if (c == 2) {
        u->omega[1] = RFE_R(2.5) * u->vx / p->vehicle.R; /* spinning: kappa 0.6 */
        u->delta = RFE_R(0.05);
    } else if (c == 3) {
        u->vy = RFE_R(-20.0); /* drift: the rear slip angles beyond alpha_max */
        u->yaw_rate = RFE_R(0.3);
    } else if (c == 4) {
        u->delta = RFE_R(0.12); /* hard turn on mu 0.2 */
        u->vy = RFE_R(-1.5);
        u->yaw_rate = RFE_R(0.5);
        u->omega[0] = RFE_R(0.9) * u->vx / p->vehicle.R;
        for (i = 0u; i < 4u; ++i) {
            mu[i] = RFE_R(0.2);
        }
    } else {
        /* random */
    }
}

/* REQ: the derivatives of h by the inputs are the model's (central differences of full set-ups
 * and evaluations within their truncation and rounding error, the tolerance of
 * test_meas_lateral_jac), for every input and row, in every tyre mode (paper, absolute Dugoff,
 * Magic Formula), on random samples and on free-rolling, locked, spinning, drifting and
 * saturated ones; each column scaled by its sd. */
/* REQ-MEAS-004 */
static void test_meas_input_jac(void **state)
{
    long checked = 0;
    long tight = 0;
    long kinked = 0;
    long worse[3] = {0, 0, 0};
    double worst = 0.0;
    int n;
    (void)state;
    draw_seed(0x1A9E7ull);
    /* light mode: a stride prime to input_jac_point's 50 kinds and to the 3 modes, so the
     * light subset holds every kind in its share (10 took the free-rolling kind, whose zero
     * slips are kinks, in 1 case of 5, and with it the not-smooth share above MAX_KINKED) */
    for (n = 0; n < N_JAC_CASES; n += (int)rfe_test_stride(11u)) {
        rfe_params_t p;
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_real_t sd[RFE_INPUTS];
        rfe_real_t G[3 * RFE_INPUTS];
        rfe_meas_t h;
        size_t j;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        p.tyre.mode = MODES[n % 3];
        input_jac_point(&p, n, &u, mu);
        for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
            sd[j] = (j == (size_t)RFE_IN_VY) ? RFE_R(0.5) : RFE_R(1.0);
        }
        if ((fabs((double)u.vx) < JAC_V_MIN) ||
            (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK)) {
            continue;
        }
        if (rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, sd, G) != RFE_OK) {
            continue;
        }
        for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
            double d[3][3];
            double gap[2][3];
            double sc[2];
            int r;
            if (central3(&p, &u, mu, j, d, gap) == 0) {
                continue;
            }
            {
                const rfe_real_t zero[4] = {RFE_R(0.0), RFE_R(0.0), RFE_R(0.0), RFE_R(0.0)};
                term_scale(&p, &h, mu, zero, sc); /* ax's terms are at most ay's scale */
            }
            for (r = 0; r < 3; ++r) {
                const double a = (double)G[((size_t)r * RFE_INPUTS) + j] / (double)sd[j];
                const double noise = 8.0 * EPS_F * sc[(r == 2) ? 1 : 0] / input_step(j);
                const double d12 = fabs(d[1][r] - d[0][r]);
                const double g1 = fabs(gap[0][r]);
                /* 2 d12, not d12: a kink of the second derivative within the stencil (kappa's
                 * den switching speeds at kappa = 0, Dugoff's L = 1: C1 points) leaves
                 * D(h) - f' ~ c h, so D(2h) - D(h) ~ c h is the error itself, not 3 times it;
                 * measured at low speed, where such a point is within 4h: float32 errors up to
                 * 0.9 d12 */
                const double tol = (2.0 * d12) + (0.5 * g1) + noise + (REL_FLOOR * fabs(a)) +
                                   (TERM_REL * sc[(r == 2) ? 1 : 0]);
                const double err = fabs(a - d[0][r]);
                if (((d12 > (2.0 * noise)) && (fabs(d[2][r] - d[1][r]) < (2.0 * d12))) ||
                    ((g1 > (4.0 * noise)) && (fabs(gap[1][r]) < (1.5 * g1)))) {
                    ++kinked; /* not smooth within 4h */
                    continue;
                }
                if (err > tol) {
                    print_message("case %d mode %d input %zu row %d: analytic %.12g, difference "
                                  "%.12g (2h: %.12g), bound %.3g\n",
                                  n, (int)p.tyre.mode, j, r, a, d[0][r], d[1][r], tol);
                    ++worse[n % 3];
                }
                if (tol <= (TIGHT * fmax(fabs(a), 1.0))) {
                    ++tight;
                }
                worst = fmax(worst, err / fmax(fabs(a), 1.0));
                ++checked;
            }
        }
    }
    print_message("meas input jac: %ld derivatives against central differences, %ld with a "
                  "tight bound, worst error %.3g (relative to max(|f'|, 1)); %ld not smooth "
                  "within 4h, not compared\n",
                  checked, tight, worst, kinked);
    assert_int_equal(worse[0], 0);
    assert_int_equal(worse[1], 0);
    assert_int_equal(worse[2], 0);
    assert_true(checked > 1000);
    assert_true((double)tight >= (MIN_TIGHT_IN * (double)checked));
    assert_true((double)kinked <= (MAX_KINKED * (double)(checked + kinked)));
}

/* REQ: rfe_meas_input_jac rejects bad arguments and a non-finite friction with
 * rfe_meas_eval's statuses, G untouched; a column's scale multiplies it (sd 0: a zero column);
 * other tyre parameters than the set-up's give a set-up's with them. */
/* REQ-MEAS-004 */
static void test_meas_input_jac_args(void **state)
{
    rfe_params_t p;
    rfe_sample_t u;
    rfe_real_t mu[4];
    rfe_real_t sd[RFE_INPUTS];
    rfe_real_t G[3 * RFE_INPUTS];
    rfe_real_t G2[3 * RFE_INPUTS];
    rfe_real_t G0[3 * RFE_INPUTS];
    rfe_meas_t h;
    size_t j;
    int m;
    (void)state;
    draw_seed(0x5EED5ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    draw_sample(&u, mu, 1);
    u.vx = RFE_R(20.0);
    u.delta = RFE_R(0.05);
    for (m = 0; m < 3; ++m) {
        rfe_tyre_params_t other = p.tyre;
        rfe_meas_t h2;
        rfe_real_t bad[4];
        p.tyre.mode = MODES[m];
        other.mode = MODES[m];
        other.cy *= RFE_R(1.3);
        other.Cy_n *= RFE_R(1.3);
        for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
            sd[j] = RFE_R(1.0);
        }
        assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
        assert_int_equal(rfe_meas_setup(&h2, &p.vehicle, &other, &u), RFE_OK);
        assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &other, &u, mu, sd, G), RFE_OK);
        assert_int_equal(rfe_meas_input_jac(&h2, &p.vehicle, &other, &u, mu, sd, G2), RFE_OK);
        assert_memory_equal(G, G2, sizeof(G));
        /* an input that does not reach any wheel's slip cannot exist, and every column of a
         * steered, moving sample is nonzero somewhere; a scale multiplies its column */
        assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, sd, G), RFE_OK);
        sd[RFE_IN_VX] = RFE_R(0.0);
        sd[RFE_IN_DELTA] = RFE_R(0.5);
        assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, sd, G2), RFE_OK);
        for (j = 0u; j < 3u; ++j) {
            assert_true(G2[(j * RFE_INPUTS) + RFE_IN_VX] == RFE_R(0.0));
            assert_true(G2[(j * RFE_INPUTS) + RFE_IN_DELTA] ==
                        RFE_R(0.5) * G[(j * RFE_INPUTS) + RFE_IN_DELTA]);
            assert_memory_equal(&G2[(j * RFE_INPUTS) + RFE_IN_VY],
                                &G[(j * RFE_INPUTS) + RFE_IN_VY],
                                (RFE_INPUTS - RFE_IN_VY) * sizeof(rfe_real_t));
        }
        memset(G, 0x5A, sizeof(G));
        memcpy(G0, G, sizeof(G));
        memcpy(bad, mu, sizeof(bad));
        bad[2] = (rfe_real_t)NAN;
        assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, &u, bad, sd, G),
                         RFE_ERR_NONFINITE);
        assert_memory_equal(G, G0, sizeof(G));
        /* finite arguments whose product is not: the largest real as every column's scale.
         * A steered sample with its wheels rolling at the body's speed has derivatives beyond
         * 1 in magnitude (ay by delta is of the order of an axle's cornering stiffness over
         * the mass, ~1e2 m/s^2 per rad), so a scaled entry overflows: RFE_ERR_NONFINITE, G
         * untouched. */
        {
            rfe_sample_t rolling = u;
            rfe_meas_t hr;
            for (j = 0u; j < (size_t)RFE_WHEELS; ++j) {
                rolling.omega[j] = rolling.vx / p.vehicle.R;
            }
            for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
                sd[j] = HUGE_REAL;
            }
            assert_int_equal(rfe_meas_setup(&hr, &p.vehicle, &p.tyre, &rolling), RFE_OK);
            assert_int_equal(rfe_meas_input_jac(&hr, &p.vehicle, &p.tyre, &rolling, mu, sd, G),
                             RFE_ERR_NONFINITE);
            assert_memory_equal(G, G0, sizeof(G));
        }
    }
    assert_int_equal(rfe_meas_input_jac(NULL, &p.vehicle, &p.tyre, &u, mu, sd, G), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac(&h, NULL, &p.tyre, &u, mu, sd, G), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, NULL, &u, mu, sd, G), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, NULL, mu, sd, G), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, &u, NULL, sd, G), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, NULL, G), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, sd, NULL), RFE_ERR_NULL);
    assert_memory_equal(G, G0, sizeof(G));
}

/* REQ: rfe_meas_input_jac of a car at rest (the function takes any speed; the step noise does
 * not call it yet): every wheel's v_wx = 0, so no slip angle's tangent term (the division by
 * |v_wx| is not formed) and the slip's over v_min; every entry finite, the column of vy (which
 * reaches the slips only through the tangents) 0. */
/* REQ-MEAS-004 */
static void test_meas_input_jac_at_rest(void **state)
{
    rfe_params_t p;
    rfe_sample_t u;
    rfe_real_t mu[4] = {RFE_R(0.8), RFE_R(0.8), RFE_R(0.8), RFE_R(0.8)};
    rfe_real_t sd[RFE_INPUTS];
    rfe_real_t G[3 * RFE_INPUTS];
    rfe_meas_t h;
    size_t j;
    int m;
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&u, 0, sizeof(u));
    for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
        sd[j] = RFE_R(1.0);
    }
    for (m = 0; m < 3; ++m) {
        p.tyre.mode = MODES[m];
        assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
        assert_int_equal(rfe_meas_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, sd, G), RFE_OK);
        for (j = 0u; j < (3u * (size_t)RFE_INPUTS); ++j) {
            assert_true(isfinite((double)G[j]));
        }
        for (j = 0u; j < 3u; ++j) {
            assert_true(G[(j * RFE_INPUTS) + RFE_IN_VY] == RFE_R(0.0));
        }
    }
}

/* REQ: rfe_meas_nominal_input_jac is rfe_meas_nominal followed by rfe_meas_input_jac, bit for
 * bit and status for status (z and G written only on RFE_OK), in every tyre mode, with the
 * set-up's tyre parameters (the load-scaled modes' one evaluation of the forces) and with
 * others (the two calls), on the operating points of test_meas_input_jac and with a
 * non-finite friction; NULL arguments rejected. */
/* REQ-MEAS-004 */
static void test_meas_nominal_input_jac(void **state)
{
    int n;
    int fast = 0;
    (void)state;
    draw_seed(0x0E1A7ull);
    for (n = 0; n < 600; n += (int)rfe_test_stride(7u)) {
        rfe_params_t p;
        rfe_tyre_params_t other;
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_real_t sd[RFE_INPUTS];
        rfe_meas_t h;
        rfe_meas_terms_t nom;
        size_t j;
        int k;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        p.tyre.mode = MODES[n % 3];
        input_jac_point(&p, n, &u, mu);
        for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
            sd[j] = (j == (size_t)RFE_IN_VY) ? RFE_R(0.5) : RFE_R(1.0);
        }
        if ((n % 7) == 6) {
            mu[n % 4] = (rfe_real_t)NAN; /* the wheels' checks: the same first failure */
        }
        other = p.tyre;
        other.cy *= RFE_R(1.3);
        other.Cy_n *= RFE_R(1.3);
        if (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK) {
            continue;
        }
        for (k = 0; k < 2; ++k) {
            const rfe_tyre_params_t *tp = (k == 0) ? &p.tyre : &other;
            rfe_real_t z[3];
            rfe_real_t z2[3];
            rfe_real_t G[3 * RFE_INPUTS];
            rfe_real_t G2[3 * RFE_INPUTS];
            rfe_status_t want = rfe_meas_nominal(&h, &p.vehicle, tp, mu, &nom, z);
            rfe_status_t got;
            if (want == RFE_OK) {
                want = rfe_meas_input_jac(&h, &p.vehicle, tp, &u, mu, sd, G);
            }
            memset(z2, 0x5A, sizeof(z2));
            memset(G2, 0x5A, sizeof(G2));
            got = rfe_meas_nominal_input_jac(&h, &p.vehicle, tp, &u, mu, sd, z2, G2);
            assert_int_equal(got, want);
            if (want == RFE_OK) {
                assert_memory_equal(z2, z, sizeof(z));
                assert_memory_equal(G2, G, sizeof(G));
                fast += ((k == 0) && (p.tyre.mode != RFE_TYRE_PAPER)) ? 1 : 0;
            } else {
                memset(z, 0x5A, sizeof(z));
                memset(G, 0x5A, sizeof(G));
                assert_memory_equal(z2, z, sizeof(z));
                assert_memory_equal(G2, G, sizeof(G));
            }
        }
    }
    assert_true(fast >= 5); /* the one-evaluation path was compared */
    {
        rfe_params_t p;
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_real_t sd[RFE_INPUTS] = {0};
        rfe_real_t z[3];
        rfe_real_t G[3 * RFE_INPUTS];
        rfe_meas_t h;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        draw_sample(&u, mu, 1);
        u.vx = RFE_R(20.0);
        assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
        assert_int_equal(rfe_meas_nominal_input_jac(NULL, &p.vehicle, &p.tyre, &u, mu, sd, z, G),
                         RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac(&h, NULL, &p.tyre, &u, mu, sd, z, G),
                         RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac(&h, &p.vehicle, NULL, &u, mu, sd, z, G),
                         RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac(&h, &p.vehicle, &p.tyre, NULL, mu, sd, z, G),
                         RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac(&h, &p.vehicle, &p.tyre, &u, NULL, sd, z, G),
                         RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, NULL, z, G),
                         RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, sd, NULL, G),
                         RFE_ERR_NULL);
        assert_int_equal(rfe_meas_nominal_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, sd, z, NULL),
                         RFE_ERR_NULL);
    }
}

/* REQ: the forces rfe_meas_nominal_input_jac keeps in h change none of rfe_meas_eval's
 * results or statuses (bit for bit against the same model without them): at the kept friction,
 * with some wheels moved off it, with -0 for +0, with another Magic Formula shape (each of
 * the four alone) or stiffness (not kept for those), with a NaN friction; rfe_meas_setup drops them. */
/* REQ-MEAS-004 */
static void test_meas_kept_forces(void **state)
{
    int n;
    int kept = 0;
    (void)state;
    draw_seed(0x6E3Full);
    for (n = 0; n < 600; n += (int)rfe_test_stride(7u)) {
        rfe_params_t p;
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_real_t sd[RFE_INPUTS];
        rfe_real_t z0[3];
        rfe_real_t G[3 * RFE_INPUTS];
        rfe_meas_t h;
        rfe_meas_t plain;
        size_t j;
        int k;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        p.tyre.mode = MODES[n % 3];
        input_jac_point(&p, n, &u, mu);
        for (j = 0u; j < (size_t)RFE_INPUTS; ++j) {
            sd[j] = RFE_R(1.0);
        }
        if (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK) {
            continue;
        }
        plain = h;
        assert_int_equal(h.memo_valid, 0);
        if (rfe_meas_nominal_input_jac(&h, &p.vehicle, &p.tyre, &u, mu, sd, z0, G) != RFE_OK) {
            continue;
        }
        kept += h.memo_valid;
        for (k = 0; k < 9; ++k) {
            rfe_tyre_params_t tp = p.tyre;
            rfe_real_t m2[4];
            rfe_real_t z[3];
            rfe_real_t z2[3];
            rfe_status_t a;
            rfe_status_t b;
            memcpy(m2, mu, sizeof(m2));
            if (k == 1) {
                m2[n % 4] += RFE_R(0.05); /* one wheel off the kept friction */
            } else if (k == 2) {
                m2[0] = RFE_R(0.0);
                m2[1] = -RFE_R(0.0); /* -0 and +0 */
            } else if (k == 3) {
                tp.shape_Cx = RFE_R(1.5); /* another shape: not kept for it */
            } else if (k == 4) {
                tp.cy *= RFE_R(1.2); /* another stiffness: not kept for it */
            } else if (k == 5) {
                m2[n % 4] = (rfe_real_t)NAN;
            } else if (k == 6) {
                tp.shape_Ex = RFE_R(0.2); /* each other shape alone (default Ex, Ey 0, Cy 1.3) */
            } else if (k == 7) {
                tp.shape_Cy = RFE_R(1.5);
            } else if (k == 8) {
                tp.shape_Ey = RFE_R(0.2);
            } else {
                /* the kept friction */
            }
            memset(z, 0x5A, sizeof(z));
            memset(z2, 0x5A, sizeof(z2));
            a = rfe_meas_eval(&h, &p.vehicle, &tp, m2, z);
            b = rfe_meas_eval(&plain, &p.vehicle, &tp, m2, z2);
            assert_int_equal(a, b);
            assert_memory_equal(z, z2, sizeof(z));
        }
        assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
        assert_int_equal(h.memo_valid, 0);
    }
    assert_true(kept >= 5); /* forces were kept (load-scaled modes) and compared */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_meas_perturbed),
        cmocka_unit_test(test_meas_perturbed_args),
        cmocka_unit_test(test_meas_cached),
        cmocka_unit_test(test_meas_cached_each_field),
        cmocka_unit_test(test_meas_lateral_jac),
        cmocka_unit_test(test_meas_input_jac),
        cmocka_unit_test(test_meas_input_jac_args),
        cmocka_unit_test(test_meas_input_jac_at_rest),
        cmocka_unit_test(test_meas_nominal_input_jac),
        cmocka_unit_test(test_meas_kept_forces),
        cmocka_unit_test(test_meas_lateral_jac_args),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
