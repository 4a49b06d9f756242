/**
 * @file test_tyre_flt.c
 * @brief Kinematics, loads, slips (MODEL.md §3) and Dugoff tyre (§4) of the float variant.
 *
 * Tolerances. Double: the shared vectors come from an independent float64 implementation,
 * so agreement is limited by rounding only: 1e-9 relative (MODEL.md asks ~1e-9).
 * Float32: inputs are rounded to float (relative 6e-8); slip is a difference of speeds
 * ~30 m/s divided by a speed, so kappa/alpha carry ~1e-6 absolute error, and a force
 * Fz*C*kappa (Fz ~ 6e3 N, C = 20) then ~0.1 N; near the Dugoff knee the force's slope
 * d(F)/d(kappa) ~ Fz*C amplifies it the same way. Bounds: slips 2e-6, loads 1e-5 rel,
 * forces 1e-4 rel + 0.5 N, H entries (forces / m or J) 1e-4 rel + 5e-4.
 */
#include "test_common.h"

#include <string.h>

#include "rfe/component/obsmat.h"
#include "rfe/params.h"
#include "rfe/component/tyre.h"
#include "table.h"

#if defined(RFE_REAL_DOUBLE)
#define TOL_SLIP_ABS 1e-12
#define TOL_REL 1e-9
#define TOL_FORCE_ABS 1e-8
#define TOL_H_ABS 1e-12
#else
#define TOL_SLIP_ABS 2e-6
#define TOL_REL 1e-4
#define TOL_FORCE_ABS 0.5
#define TOL_H_ABS 5e-4
#endif

#if defined(RFE_REAL_DOUBLE)
#define RFE_TAN_TEST(x) tan(x)
#else
#define RFE_TAN_TEST(x) tanf((float)(x))
#endif

static const char *const WHEEL[4] = {"fl", "fr", "rl", "rr"};

static test_table_t vectors;
static rfe_params_t params;

static int setup(void **state)
{
    (void)state;
    if (rfe_params_default(&params) != RFE_OK) {
        return -1;
    }
    return test_table_load(TEST_VECTORS_DIR "/model_vectors.csv", &vectors);
}

static int teardown(void **state)
{
    (void)state;
    test_table_free(&vectors);
    return 0;
}

static rfe_sample_t sample_from_row(size_t row)
{
    rfe_sample_t u;
    size_t i;
    char name[32];
    memset(&u, 0, sizeof(u));
    u.delta = (rfe_real_t)test_table_get(&vectors, row, "delta");
    u.vx = (rfe_real_t)test_table_get(&vectors, row, "vx");
    u.vy = (rfe_real_t)test_table_get(&vectors, row, "vy");
    u.yaw_rate = (rfe_real_t)test_table_get(&vectors, row, "yaw_rate");
    u.ax = (rfe_real_t)test_table_get(&vectors, row, "ax");
    u.ay = (rfe_real_t)test_table_get(&vectors, row, "ay");
    for (i = 0; i < 4; ++i) {
        snprintf(name, sizeof(name), "omega_%s", WHEEL[i]);
        u.omega[i] = (rfe_real_t)test_table_get(&vectors, row, name);
    }
    return u;
}

static double col(size_t row, const char *prefix, size_t wheel)
{
    char name[80];
    snprintf(name, sizeof(name), "%s_%s", prefix, WHEEL[wheel]);
    return test_table_get(&vectors, row, name);
}

/* REQ: MODEL.md §3 slips, slip angles (after the bound) and loads equal the vectors. */
/* REQ-TYRE-001 */
static void test_rfe_tyre_kinematics_matches_vectors(void **state)
{
    size_t r, i;
    char what[128];
    (void)state;
    assert_true(vectors.n_rows >= 70);
    for (r = 0; r < vectors.n_rows; ++r) {
        rfe_sample_t u = sample_from_row(r);
        rfe_wheel_kin_t kin;
        assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &u, &kin),
                         RFE_OK);
        for (i = 0; i < 4; ++i) {
            snprintf(what, sizeof(what), "row %zu kappa_%s", r, WHEEL[i]);
            assert_close(kin.kappa[i], col(r, "kappa", i), TOL_SLIP_ABS, TOL_REL, what);
            snprintf(what, sizeof(what), "row %zu alpha_%s", r, WHEEL[i]);
            assert_close(kin.alpha[i], col(r, "alpha", i), TOL_SLIP_ABS, TOL_REL, what);
            snprintf(what, sizeof(what), "row %zu fz_%s", r, WHEEL[i]);
            assert_close(kin.fz[i], col(r, "fz", i), TOL_FORCE_ABS, TOL_REL, what);
        }
    }
}

/* REQ: MODEL.md §4 normalised forces F0x, F0y and §5 H equal the vectors. */
/* REQ-TYRE-002 */
static void test_rfe_tyre_forces_norm_matches_vectors(void **state)
{
    size_t r, i, k;
    char what[128];
    (void)state;
    for (r = 0; r < vectors.n_rows; ++r) {
        rfe_sample_t u = sample_from_row(r);
        rfe_wheel_kin_t kin;
        rfe_real_t f0x[4], f0y[4], H[12];
        assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &u, &kin),
                         RFE_OK);
        assert_int_equal(rfe_tyre_forces_norm(&params.tyre, &kin, f0x, f0y), RFE_OK);
        for (i = 0; i < 4; ++i) {
            snprintf(what, sizeof(what), "row %zu f0x_%s", r, WHEEL[i]);
            assert_close(f0x[i], col(r, "f0x", i), TOL_FORCE_ABS, TOL_REL, what);
            snprintf(what, sizeof(what), "row %zu f0y_%s", r, WHEEL[i]);
            assert_close(f0y[i], col(r, "f0y", i), TOL_FORCE_ABS, TOL_REL, what);
        }
        assert_int_equal(rfe_obsmat_build(&params.vehicle, u.delta, f0x, f0y, H), RFE_OK);
        for (k = 0; k < 12; ++k) {
            char name[8];
            snprintf(name, sizeof(name), "H%zu%zu", k / 4 + 1, k % 4 + 1);
            snprintf(what, sizeof(what), "row %zu %s", r, name);
            assert_close(H[k], test_table_get(&vectors, r, name), TOL_H_ABS, TOL_REL, what);
        }
    }
}

/* REQ: MODEL.md §4 load-scaled absolute forces at mu 0.3 and 0.8 equal the vectors. */
/* REQ-TYRE-003 */
static void test_rfe_tyre_forces_abs_matches_vectors(void **state)
{
    static const struct {
        double mu;
        const char *tag;
    } cases[2] = {{0.3, "mu03"}, {0.8, "mu08"}};
    size_t r, i, c;
    char what[160], name[48];
    (void)state;
    for (r = 0; r < vectors.n_rows; ++r) {
        rfe_sample_t u = sample_from_row(r);
        rfe_wheel_kin_t kin;
        rfe_tyre_params_t tp = params.tyre;
        tp.mode = RFE_TYRE_ABSOLUTE; /* the vectors hold the absolute Dugoff */
        assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &tp, &u, &kin),
                         RFE_OK);
        for (c = 0; c < 2; ++c) {
            const rfe_real_t mu[4] = {(rfe_real_t)cases[c].mu, (rfe_real_t)cases[c].mu,
                                      (rfe_real_t)cases[c].mu, (rfe_real_t)cases[c].mu};
            rfe_real_t fx[4], fy[4];
            assert_int_equal(rfe_tyre_forces_abs(&tp, &kin, mu, fx, fy), RFE_OK);
            for (i = 0; i < 4; ++i) {
                snprintf(name, sizeof(name), "fx_abs_%s", cases[c].tag);
                snprintf(what, sizeof(what), "row %zu %s_%s", r, name, WHEEL[i]);
                assert_close(fx[i], col(r, name, i), TOL_FORCE_ABS, TOL_REL, what);
                snprintf(name, sizeof(name), "fy_abs_%s", cases[c].tag);
                snprintf(what, sizeof(what), "row %zu %s_%s", r, name, WHEEL[i]);
                assert_close(fy[i], col(r, name, i), TOL_FORCE_ABS, TOL_REL, what);
            }
        }
    }
}

/* Textbook Dugoff (MODEL.md §4 as written, dividing by 1 - |kappa|): an evaluation path
 * independent of the library's rearranged, singularity-free form. */
static void dugoff_textbook(double k, double a, double fz, double v, double Cx, double Cy,
                            double eps, double mu, double *fx, double *fy)
{
    const double ta = tan(a);
    const double S = sqrt(Cx * Cx * k * k + Cy * Cy * ta * ta);
    double E = 1.0 - eps * fabs(v) * sqrt(k * k + ta * ta);
    double L, f;
    E = E > 0.0 ? E : 0.0;
    L = mu * (1.0 - fabs(k)) * E / (2.0 * S);
    f = L < 1.0 ? L * (2.0 - L) : 1.0;
    *fx = fz * Cx * k / (1.0 - fabs(k)) * f;
    *fy = fz * Cy * ta / (1.0 - fabs(k)) * f;
}

/* REQ: paper-mode Dugoff equals the textbook formula over a grid away from singular points. */
/* REQ-TYRE-002 */
static void test_rfe_tyre_dugoff_norm_matches_textbook_grid(void **state)
{
    double k, a;
    (void)state;
    for (k = -0.95; k <= 0.95; k += 0.0731) {
        for (a = -1.3; a <= 1.3; a += 0.117) {
            double ex, ey;
            rfe_real_t fx, fy;
            dugoff_textbook(k, a, 4321.0, 23.0, 20.0, 15.0, 0.015, 1.0, &ex, &ey);
            assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, (rfe_real_t)k,
                                                          (rfe_real_t)a, (rfe_real_t)4321.0,
                                                          (rfe_real_t)23.0, &fx, &fy),
                             RFE_OK);
            assert_close(fx, ex, TOL_FORCE_ABS, TOL_REL * 100.0, "fx grid");
            assert_close(fy, ey, TOL_FORCE_ABS, TOL_REL * 100.0, "fy grid");
        }
    }
}

/* REQ: in the linear region (L >= 1) F0x = Fz Cx kappa / (1 - |kappa|) exactly.
 * kappa = -0.01, alpha = 0, v = 20: S = 0.2, E = 1 - 0.015*20*0.01 = 0.997,
 * L = 0.99*0.997/0.4 = 2.47 >= 1, so F0x = 4000*20*(-0.01)/0.99 = -808.0808... */
/* REQ-TYRE-002 */
static void test_rfe_tyre_dugoff_norm_linear_region_hand_value(void **state)
{
    rfe_real_t fx, fy;
    (void)state;
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, (rfe_real_t)-0.01, 0,
                                                  (rfe_real_t)4000.0, (rfe_real_t)20.0, &fx,
                                                  &fy),
                     RFE_OK);
    assert_close(fx, -4000.0 * 20.0 * 0.01 / 0.99, TOL_FORCE_ABS, TOL_REL, "F0x linear");
    assert_close(fy, 0.0, TOL_FORCE_ABS, 0.0, "F0y");
}

/* REQ: locked wheel kappa = -1, alpha = 0: f(L)/(1-|k|) -> E/S with S = Cx, so
 * F0x = -Fz E = -Fz (1 - eps v); finite and continuous from kappa -> -1. */
/* REQ-TYRE-004 */
static void test_rfe_tyre_dugoff_norm_locked_wheel_finite(void **state)
{
    rfe_real_t fx, fy, fx_near, fy_near;
    const double want = -5000.0 * (1.0 - 0.015 * 20.0);
    (void)state;
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, (rfe_real_t)-1.0, 0,
                                                  (rfe_real_t)5000.0, (rfe_real_t)20.0, &fx, &fy),
                     RFE_OK);
    assert_close(fx, want, TOL_FORCE_ABS, TOL_REL, "locked F0x");
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, (rfe_real_t)-0.99999, 0,
                                                  (rfe_real_t)5000.0, (rfe_real_t)20.0, &fx_near,
                                                  &fy_near),
                     RFE_OK);
    assert_close(fx_near, want, 1.0, 1e-3, "near-locked F0x continuous");
    /* Beyond -1 the slip is clipped to -1. */
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, (rfe_real_t)-3.0, 0,
                                                  (rfe_real_t)5000.0, (rfe_real_t)20.0, &fx_near,
                                                  &fy_near),
                     RFE_OK);
    assert_close(fx_near, want, TOL_FORCE_ABS, TOL_REL, "clipped kappa");
}

/* REQ: zero slip and standstill give zero force, no NaN. */
/* REQ-TYRE-004 */
static void test_rfe_tyre_zero_slip_and_standstill(void **state)
{
    rfe_sample_t u;
    rfe_wheel_kin_t kin;
    rfe_real_t f0x[4], f0y[4];
    size_t i;
    (void)state;
    memset(&u, 0, sizeof(u)); /* standing still, nothing turning */
    assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &u, &kin), RFE_OK);
    assert_int_equal(rfe_tyre_forces_norm(&params.tyre, &kin, f0x, f0y), RFE_OK);
    for (i = 0; i < 4; ++i) {
        assert_true(kin.kappa[i] == 0 && kin.alpha[i] == 0);
        assert_true(f0x[i] == 0 && f0y[i] == 0);
        assert_true(kin.fz[i] > 0);
    }
    /* Creeping wheel spin at standstill: den = v_min keeps kappa finite and clipped. */
    u.omega[0] = (rfe_real_t)1.0;
    assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &u, &kin), RFE_OK);
    assert_close(kin.kappa[0], 0.325 / 0.5, TOL_SLIP_ABS, TOL_REL, "kappa with v_min guard");
}

/* REQ: the mirrored manoeuvre gives mirrored slips, loads and forces (left/right symmetry). */
/* REQ-TYRE-005 */
static void test_rfe_tyre_left_right_symmetry(void **state)
{
    static const size_t mirror[4] = {1, 0, 3, 2};
    size_t r, i;
    (void)state;
    for (r = 0; r < vectors.n_rows; r += 5) {
        rfe_sample_t u = sample_from_row(r), m = u;
        rfe_wheel_kin_t ku, km;
        rfe_real_t ux[4], uy[4], mx[4], my[4];
        m.delta = -u.delta;
        m.vy = -u.vy;
        m.yaw_rate = -u.yaw_rate;
        m.ay = -u.ay;
        for (i = 0; i < 4; ++i) {
            m.omega[i] = u.omega[mirror[i]];
        }
        assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &u, &ku), RFE_OK);
        assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &m, &km), RFE_OK);
        assert_int_equal(rfe_tyre_forces_norm(&params.tyre, &ku, ux, uy), RFE_OK);
        assert_int_equal(rfe_tyre_forces_norm(&params.tyre, &km, mx, my), RFE_OK);
        for (i = 0; i < 4; ++i) {
            const size_t j = mirror[i];
            assert_close(km.kappa[i], ku.kappa[j], TOL_SLIP_ABS, TOL_REL, "mirrored kappa");
            assert_close(km.alpha[i], -ku.alpha[j], TOL_SLIP_ABS, TOL_REL, "mirrored alpha");
            assert_close(km.fz[i], ku.fz[j], TOL_FORCE_ABS, TOL_REL, "mirrored fz");
            assert_close(mx[i], ux[j], TOL_FORCE_ABS, TOL_REL, "mirrored F0x");
            assert_close(my[i], -uy[j], TOL_FORCE_ABS, TOL_REL, "mirrored F0y");
        }
    }
}

/* REQ: above ~67 m/s of slip speed the eps factor is clamped at 0: zero force, not a
 * reversed one; huge slip angles are bounded by alpha_max. */
/* REQ-TYRE-004 */
static void test_rfe_tyre_eps_clamp_and_alpha_bound(void **state)
{
    rfe_real_t fx, fy, fx2, fy2;
    rfe_sample_t u;
    rfe_wheel_kin_t kin;
    (void)state;
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, (rfe_real_t)-1.0, 0,
                                                  (rfe_real_t)5000.0, (rfe_real_t)90.0, &fx, &fy),
                     RFE_OK);
    assert_true(fx == 0 && fy == 0);
    /* alpha beyond the bound behaves like alpha at the bound. */
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, 0, (rfe_real_t)1.5,
                                                  (rfe_real_t)5000.0, (rfe_real_t)5.0, &fx, &fy),
                     RFE_OK);
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, 0, params.tyre.alpha_max,
                                                  (rfe_real_t)5000.0, (rfe_real_t)5.0, &fx2, &fy2),
                     RFE_OK);
    assert_true(fx == fx2 && fy == fy2 && isfinite(fy));
    /* Pure sideways sliding: |alpha| = pi/2 before the bound. */
    memset(&u, 0, sizeof(u));
    u.vy = (rfe_real_t)10.0;
    assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &u, &kin), RFE_OK);
    assert_close(kin.alpha[0], -params.tyre.alpha_max, 0.0, 0.0, "alpha bounded");
}

/* REQ: absolute mode: mu < 0 evaluates as mu = 0 (zero force); at small slip the force does
 * not depend on mu (L >= 1); it saturates at mu Fz in pure slip for large slip. */
/* REQ-TYRE-003 */
static void test_rfe_tyre_dugoff_abs_mu_behaviour(void **state)
{
    rfe_real_t fx_a, fy_a, fx_b, fy_b;
    (void)state;
    assert_int_equal(rfe_tyre_dugoff_abs(&params.tyre, (rfe_real_t)-0.2, (rfe_real_t)0.1,
                                                 (rfe_real_t)4000.0, (rfe_real_t)20.0,
                                                 (rfe_real_t)-0.3, &fx_a, &fy_a),
                     RFE_OK);
    assert_true(fx_a == 0 && fy_a == 0);
    assert_int_equal(rfe_tyre_dugoff_abs(&params.tyre, (rfe_real_t)-0.005, 0,
                                                 (rfe_real_t)4000.0, (rfe_real_t)20.0,
                                                 (rfe_real_t)0.8, &fx_a, &fy_a),
                     RFE_OK);
    assert_int_equal(rfe_tyre_dugoff_abs(&params.tyre, (rfe_real_t)-0.005, 0,
                                                 (rfe_real_t)4000.0, (rfe_real_t)20.0,
                                                 (rfe_real_t)1.1, &fx_b, &fy_b),
                     RFE_OK);
    assert_close(fx_a, fx_b, TOL_FORCE_ABS, TOL_REL, "low slip independent of mu");
    assert_close(fx_a, -4000.0 * 20.0 * 0.005 / 0.995, TOL_FORCE_ABS, TOL_REL, "linear abs force");
    /* Deep slip at low speed: |F| approaches mu Fz (Dugoff saturation), never above it. */
    assert_int_equal(rfe_tyre_dugoff_abs(&params.tyre, (rfe_real_t)-0.9, 0,
                                                 (rfe_real_t)4000.0, (rfe_real_t)0.0,
                                                 (rfe_real_t)0.4, &fx_a, &fy_a),
                     RFE_OK);
    assert_true(fx_a < 0 && -fx_a <= 0.4 * 4000.0 * 1.0001 && -fx_a > 0.4 * 4000.0 * 0.9);
}

/* REQ: invalid inputs give distinct statuses and leave outputs untouched. */
/* REQ-TYRE-006 */
static void test_rfe_tyre_rejects_bad_input(void **state)
{
    rfe_real_t fx = 7, fy = 7;
    rfe_sample_t u;
    rfe_wheel_kin_t kin;
    rfe_real_t mu[4] = {1, 1, 1, 1}, ox[4] = {7, 7, 7, 7}, oy[4] = {7, 7, 7, 7};
    (void)state;
    assert_int_equal(rfe_tyre_dugoff_norm(NULL, 0, 0, 1, 1, &fx, &fy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, 0, 0, 1, 1, NULL, &fy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, (rfe_real_t)NAN, 0, 1, 1, &fx, &fy),
                     RFE_ERR_NONFINITE);
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, 0, (rfe_real_t)INFINITY, 1, 1, &fx, &fy),
                     RFE_ERR_NONFINITE);
    assert_int_equal(rfe_tyre_dugoff_norm(&params.tyre, 0, 0, -1, 1, &fx, &fy), RFE_ERR_RANGE);
    assert_int_equal(rfe_tyre_dugoff_abs(&params.tyre, 0, 0, 1, 1, (rfe_real_t)NAN, &fx, &fy),
                     RFE_ERR_NONFINITE);
    assert_int_equal(rfe_tyre_dugoff_abs(&params.tyre, 0, 0, -1, 1, 1, &fx, &fy), RFE_ERR_RANGE);
    assert_true(fx == 7 && fy == 7);
    memset(&u, 0, sizeof(u));
    u.omega[3] = (rfe_real_t)NAN;
    assert_int_equal(rfe_tyre_kinematics(&params.vehicle, &params.tyre, &u, &kin),
                     RFE_ERR_NONFINITE);
    assert_int_equal(rfe_tyre_kinematics(NULL, &params.tyre, &u, &kin), RFE_ERR_NULL);
    memset(&kin, 0, sizeof(kin));
    kin.fz[2] = -1; /* a negative load is out of range for the four-wheel helpers too */
    assert_int_equal(rfe_tyre_forces_norm(&params.tyre, &kin, ox, oy), RFE_ERR_RANGE);
    assert_int_equal(rfe_tyre_forces_abs(&params.tyre, &kin, mu, ox, oy), RFE_ERR_RANGE);
    assert_true(ox[0] == 7 && oy[3] == 7);
    assert_int_equal(rfe_tyre_forces_norm(&params.tyre, NULL, ox, oy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs(&params.tyre, &kin, NULL, ox, oy), RFE_ERR_NULL);
}

/* Magic mode at one point (mode set on a copy of the preset's tyre). */
static void magic(rfe_real_t kappa, rfe_real_t alpha, rfe_real_t fz, rfe_real_t mu, rfe_real_t *fx,
                  rfe_real_t *fy)
{
    rfe_tyre_params_t tp = params.tyre;
    tp.mode = RFE_TYRE_MAGIC;
    assert_int_equal(rfe_tyre_magic_abs(&tp, kappa, alpha, fz, (rfe_real_t)20.0, mu, fx, fy),
                     RFE_OK);
}

/* REQ: the load-scaled Magic Formula: slope cx Fz / cy Fz at zero slip for every mu, pure-slip
 * peak mu Fz (scanned), |F| <= mu Fz, zero at zero slip and at mu <= 0, odd in the slips.
 * Tolerances: the slope from a finite difference at 1e-5 slip (curvature term ~ rho^2 ~ 1e-6
 * relative at mu 0.2) plus float rounding of a sin/atan2 chain (~1e-6 relative): 1e-4 rel;
 * the scanned peak at 1e-4 slip steps misses the top by < (1e-4 * cx / mu)^2 ~ 1e-4 rel. */
/* REQ-TYRE-007 */
static void test_rfe_tyre_magic_abs_shape(void **state)
{
    const rfe_real_t fz = (rfe_real_t)4321.0;
    const rfe_real_t mus[3] = {(rfe_real_t)0.2, (rfe_real_t)0.5, (rfe_real_t)1.1};
    rfe_real_t fx, fy, fx2, fy2;
    size_t m;
    (void)state;
    for (m = 0u; m < 3u; ++m) {
        const rfe_real_t mu = mus[m];
        rfe_real_t peak = 0;
        int j;
        magic((rfe_real_t)1e-5, 0, fz, mu, &fx, &fy);
        assert_close(fx / (fz * (rfe_real_t)1e-5), params.tyre.cx, 0, 1e-4, "slope x");
        assert_true(fy == 0);
        magic(0, (rfe_real_t)1e-5, fz, mu, &fx, &fy);
        assert_close(fy / (fz * (rfe_real_t)RFE_TAN_TEST(1e-5)), params.tyre.cy, 0, 1e-4, "slope y");
        for (j = 1; j <= 10000; ++j) {
            magic((rfe_real_t)j * (rfe_real_t)1e-4, 0, fz, mu, &fx, &fy);
            assert_true(fx <= mu * fz * (rfe_real_t)1.000001);
            peak = (fx > peak) ? fx : peak;
        }
        assert_close(peak, mu * fz, 0, 1e-4, "peak mu Fz");
        /* combined slip stays within the friction circle */
        magic((rfe_real_t)-0.3, (rfe_real_t)0.4, fz, mu, &fx, &fy);
        assert_true(fx < 0 && fy > 0 && (fx * fx + fy * fy) <= (mu * fz) * (mu * fz) * (rfe_real_t)1.00001);
        magic((rfe_real_t)0.3, (rfe_real_t)-0.4, fz, mu, &fx2, &fy2);
        assert_true(fx2 == -fx && fy2 == -fy);
    }
    magic(0, 0, fz, (rfe_real_t)0.8, &fx, &fy);
    assert_true(fx == 0 && fy == 0);
    magic((rfe_real_t)0.1, (rfe_real_t)0.1, fz, 0, &fx, &fy);
    assert_true(fx == 0 && fy == 0);
    magic((rfe_real_t)0.1, (rfe_real_t)0.1, fz, (rfe_real_t)-0.2, &fx, &fy);
    assert_true(fx == 0 && fy == 0);
    /* the absolute Dugoff and the Magic Formula share the slope at zero slip only: at 40 %
     * of the friction Dugoff is still linear, the Magic Formula already bends (5 % less) */
    {
        rfe_real_t dx, dy;
        assert_int_equal(rfe_tyre_dugoff_abs(&params.tyre, (rfe_real_t)0.01, 0, fz,
                                                     (rfe_real_t)20.0, (rfe_real_t)0.5, &dx, &dy),
                         RFE_OK);
        magic((rfe_real_t)0.01, 0, fz, (rfe_real_t)0.5, &fx, &fy);
        assert_true(fx < dx * (rfe_real_t)0.99);
    }
}

/* REQ: the Magic Formula with a curvature E != 0 (the default tyre has E = 0 in both
 * directions, where the library skips the curve's second atan2): pure longitudinal and pure
 * lateral slip against the formula written out in double, F = mu Fz sin(C atan(x - E (x -
 * atan x))), x = s / (mu C), s = cx |kappa| (cy |tan alpha|), with the slip's sign. Tolerance
 * relative to mu Fz: double 1e-12 (a dozen roundings of 1e-16 through sin and atan, whose
 * derivatives are <= 1, times C E <= 3); float32 2e-6 (the same chain in float32, 6e-8 per
 * operation and ~2.6e-7 for the float32 atan2 and sine, times C (1 + |E|) <= 4.2: ~1.5e-6). */
/* REQ-TYRE-007 */
static void test_rfe_tyre_magic_abs_curvature(void **state)
{
    const double Es[4] = {-1.5, -0.5, 0.5, 0.9};
    const double slips[5] = {-0.4, -0.05, 0.01, 0.08, 0.6};
    const double fz = 4321.0;
    const double mu = 0.7;
#if defined(RFE_REAL_DOUBLE)
    const double tol = 1e-12;
#else
    const double tol = 2e-6;
#endif
    size_t e;
    size_t k;
    (void)state;
    for (e = 0u; e < 4u; ++e) {
        rfe_tyre_params_t tp = params.tyre;
        tp.mode = RFE_TYRE_MAGIC;
        tp.shape_Ex = (rfe_real_t)Es[e];
        tp.shape_Ey = (rfe_real_t)Es[e];
        for (k = 0u; k < 5u; ++k) {
            const double kap = (double)(rfe_real_t)slips[k];
            const double alp = (double)(rfe_real_t)(0.5 * slips[k]);
            const double sx = (double)tp.cx * fabs(kap);
            const double sy = (double)tp.cy * fabs(tan(alp));
            const double Cx = (double)tp.shape_Cx;
            const double Cy = (double)tp.shape_Cy;
            const double E = (double)(rfe_real_t)Es[e];
            const double xx = sx / (mu * Cx);
            const double xy = sy / (mu * Cy);
            const double wx = mu * fz * sin(Cx * atan(xx - E * (xx - atan(xx)))) * (kap < 0 ? -1 : 1);
            const double wy = mu * fz * sin(Cy * atan(xy - E * (xy - atan(xy)))) * (alp < 0 ? -1 : 1);
            rfe_real_t fx;
            rfe_real_t fy;
            assert_int_equal(rfe_tyre_magic_abs(&tp, (rfe_real_t)kap, 0, (rfe_real_t)fz,
                                                (rfe_real_t)20.0, (rfe_real_t)mu, &fx, &fy),
                             RFE_OK);
            assert_close(fx, wx, tol * mu * fz, 0, "Fx with E != 0");
            assert_true(fy == 0);
            assert_int_equal(rfe_tyre_magic_abs(&tp, 0, (rfe_real_t)alp, (rfe_real_t)fz,
                                                (rfe_real_t)20.0, (rfe_real_t)mu, &fx, &fy),
                             RFE_OK);
            assert_close(fy, wy, tol * mu * fz, 0, "Fy with E != 0");
        }
    }
}

/* REQ: the four-wheel helper dispatches on the mode; the magic function checks its arguments
 * like the Dugoff one and leaves the outputs untouched on an error. */
/* REQ-TYRE-007 REQ-TYRE-006 */
static void test_rfe_tyre_magic_dispatch_and_checks(void **state)
{
    rfe_tyre_params_t tp = params.tyre;
    rfe_wheel_kin_t kin;
    rfe_real_t mu[4] = {(rfe_real_t)0.3, (rfe_real_t)0.6, (rfe_real_t)0.9, (rfe_real_t)1.2};
    rfe_real_t fx[4], fy[4], ex, ey, fx1 = 7, fy1 = 7;
    size_t i;
    (void)state;
    tp.mode = RFE_TYRE_MAGIC;
    for (i = 0u; i < 4u; ++i) {
        kin.kappa[i] = (rfe_real_t)(-0.02 * (double)(i + 1u));
        kin.alpha[i] = (rfe_real_t)(0.03 * (double)i);
        kin.fz[i] = (rfe_real_t)(3000.0 + 500.0 * (double)i);
        kin.vwx[i] = (rfe_real_t)15.0;
    }
    assert_int_equal(rfe_tyre_forces_abs(&tp, &kin, mu, fx, fy), RFE_OK);
    for (i = 0u; i < 4u; ++i) {
        assert_int_equal(rfe_tyre_magic_abs(&tp, kin.kappa[i], kin.alpha[i], kin.fz[i],
                                                    kin.vwx[i], mu[i], &ex, &ey),
                         RFE_OK);
        assert_true(fx[i] == ex && fy[i] == ey);
    }
    assert_int_equal(rfe_tyre_forces_abs(NULL, &kin, mu, fx, fy), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_abs(NULL, 0, 0, 1, 1, 1, &fx1, &fy1), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_abs(&tp, 0, 0, 1, 1, 1, NULL, &fy1), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_abs(&tp, (rfe_real_t)NAN, 0, 1, 1, 1, &fx1, &fy1),
                     RFE_ERR_NONFINITE);
    assert_int_equal(rfe_tyre_magic_abs(&tp, 0, 0, 1, 1, (rfe_real_t)INFINITY, &fx1, &fy1),
                     RFE_ERR_NONFINITE);
    assert_int_equal(rfe_tyre_magic_abs(&tp, 0, 0, -1, 1, 1, &fx1, &fy1), RFE_ERR_RANGE);
    assert_true(fx1 == 7 && fy1 == 7);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_tyre_kinematics_matches_vectors),
        cmocka_unit_test(test_rfe_tyre_forces_norm_matches_vectors),
        cmocka_unit_test(test_rfe_tyre_forces_abs_matches_vectors),
        cmocka_unit_test(test_rfe_tyre_dugoff_norm_matches_textbook_grid),
        cmocka_unit_test(test_rfe_tyre_dugoff_norm_linear_region_hand_value),
        cmocka_unit_test(test_rfe_tyre_dugoff_norm_locked_wheel_finite),
        cmocka_unit_test(test_rfe_tyre_zero_slip_and_standstill),
        cmocka_unit_test(test_rfe_tyre_left_right_symmetry),
        cmocka_unit_test(test_rfe_tyre_eps_clamp_and_alpha_bound),
        cmocka_unit_test(test_rfe_tyre_dugoff_abs_mu_behaviour),
        cmocka_unit_test(test_rfe_tyre_rejects_bad_input),
        cmocka_unit_test(test_rfe_tyre_magic_abs_shape),
        cmocka_unit_test(test_rfe_tyre_magic_abs_curvature),
        cmocka_unit_test(test_rfe_tyre_magic_dispatch_and_checks),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
