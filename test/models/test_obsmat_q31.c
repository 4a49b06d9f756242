/**
 * @file test_obsmat_q31.c
 * @brief The fixed-point observation matrix (rfe/component/obsmat_q31.h) back to back against the double
 *        twin (rfe/component/obsmat.h, _f64): random forces and steer angles over the whole Q15 range,
 *        the paper-mode H of every sample of every bundled log, h = H x against an exact
 *        integer reference; determinism, saturation counting, argument checks.
 *
 * Setup: q31 with the converted default preset, double with the original one; both get the
 * same inputs (Q values converted exactly). LSBn = 2^-n; TRIG = 6.16e-10 (sin/cos, rfe_q31_sincos_q29: q31_trig_bounds.h).
 *
 * Bounds (obsmat_q31.c: the body-axis forces Fbx = Fx c - Fy s, Fby are exact int64 products
 * of the Q30 cos/sin; each entry is rounded once, row 3 after two Q30 roundings):
 *  - the rotation: |dFbx|, |dFby| <= TRIG (|Fx| + |Fy|) on the front wheels, 0 on the rear;
 *  - rows 1, 2: 0.5 LSB24 + dFb / m + |Fb| d(1/m), d(1/m) the actual rounding of inv_m (Q38);
 *  - row 3: 0.5 LSB24 + 2^-30 + (|x_i| dFby + |y_i| dFbx) / J + |Fby| d(x_i/J)
 *    + |Fbx| d(y_i/J);
 *  - plus 1e-15 relative for the double reference.
 * h = H x: every y_r is the exactly rounded sum of the exact Q53 products (error <= 0.5 LSB24),
 * checked bit for bit against a 128-bit integer reference, and within 0.5 LSB24 + 4 2^-53
 * sum |H x| of the double twin on the same values.
 * The measured worst cases are printed (docs/FIXED_POINT.md quotes them).
 */
#include "test_common.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "q31_rows.h"
#include "test_light.h"
#include "host/fixed_conv.h"
#include "rfe/component/obsmat.h"
#include "rfe/component/obsmat_q31.h"
#include "rfe/component/params_conv.h"
#include "rfe/component/tyre_q31.h"
#include "q31_trig_bounds.h"
#include "test_rng.h"

#define TRIG Q31B_TRIG
#define LSB(q) ldexp(1.0, -(q))
#define HMAX (2147483647.0 / 16777216.0) /* largest Q24 value */

static const char *const SCENARIO[19] = {
    "accel_low_mu",       "brake_in_turn",      "cruise",          "hard_brake_high_mu",
    "hard_brake_low_mu",  "mu_step_hard_brake", "paper_high_mu_brake", "paper_low_mu_brake",
    "paper_mu_step",      "sine_steer_high_mu", "sine_steer_low_mu", "split_mu_brake",
    "split_mu_hard_brake",
    /* issue 17 */
    "double_lane_change_high_mu", "double_lane_change_low_mu", "ramp_steer_high_mu",
    "ramp_steer_low_mu", "brake_in_turn_low_mu", "wrong_tyre_data"};
static const char *const VARIANT[3] = {"", ".mf", ".nf"};

static rfe_params_t pd;
static rfe_params_q31_t pq;

typedef struct {
    const char *name;
    double max_abs, max_rel, max_ratio;
    long n;
} worst_t;

static worst_t w_h12 = {"H rows 1-2", 0, 0, 0, 0};
static worst_t w_h3 = {"H row 3", 0, 0, 0, 0};
static worst_t w_y = {"y = H x", 0, 0, 0, 0};

static void reset(worst_t *w) { w->max_abs = w->max_rel = w->max_ratio = 0.0, w->n = 0; }

static void track(worst_t *w, double got, double want, double bound, const char *ctx)
{
    const double err = fabs(got - want);
    w->max_abs = fmax(w->max_abs, err);
    if (fabs(want) >= 0.01) {
        w->max_rel = fmax(w->max_rel, err / fabs(want));
    }
    w->max_ratio = fmax(w->max_ratio, err / bound);
    ++w->n;
    if (!(err <= bound)) {
        fail_msg("%s %s: q31 %.17g double %.17g |diff| %.3e > bound %.3e", w->name, ctx, got,
                 want, err, bound);
    }
}

static void report(const worst_t *w)
{
    printf("  %-12s n=%-8ld max |err| %.3e (%.3f LSB24)  max rel %.3e (|ref| >= 0.01)  max "
           "err/bound %.3f\n",
           w->name, w->n, w->max_abs, w->max_abs / LSB(24), w->max_rel, w->max_ratio);
}

static int32_t toq(double x, int q)
{
    uint32_t s = 0u;
    return rfe_fix_from_double(x, (unsigned)q, &s);
}
static double fromq(int32_t v, int q) { return rfe_fix_to_double(v, (unsigned)q); }

static int setup(void **state)
{
    (void)state;
    return (rfe_params_default_f64(&pd) == RFE_OK && rfe_params_to_q31_f64(&pd, &pq) == RFE_OK)
               ? 0
               : -1;
}

/* Bounds of the 12 entries for the (double) forces and steer angle; see the file comment. */
static void h_bounds(double delta, const double fx[4], const double fy[4], double b[12])
{
    const rfe_vehicle_t *v = &pd.vehicle;
    const double px[4] = {v->Lf, v->Lf, -v->Lr, -v->Lr};
    const double py[4] = {v->Bf / 2, -v->Bf / 2, v->Br / 2, -v->Br / 2};
    const double pxJ[4] = {fromq(pq.vehicle.lf_J, 38), fromq(pq.vehicle.lf_J, 38),
                           -fromq(pq.vehicle.lr_J, 38), -fromq(pq.vehicle.lr_J, 38)};
    const double pyJ[4] = {fromq(pq.vehicle.yf_J, 38), -fromq(pq.vehicle.yf_J, 38),
                           fromq(pq.vehicle.yr_J, 38), -fromq(pq.vehicle.yr_J, 38)};
    const double dinv = fabs(fromq(pq.vehicle.inv_m, 38) - 1.0 / v->m);
    size_t i;
    for (i = 0; i < 4; ++i) {
        const double d = (i < 2) ? delta : 0.0;
        const double fbx = fabs(fx[i] * cos(d) - fy[i] * sin(d));
        const double fby = fabs(fx[i] * sin(d) + fy[i] * cos(d));
        const double dfb = (i < 2) ? TRIG * (fabs(fx[i]) + fabs(fy[i])) : 0.0;
        const double rel = 1e-15 * (fabs(fx[i]) + fabs(fy[i]));
        b[i] = 0.5 * LSB(24) + dfb / v->m + fbx * dinv + rel;
        b[4 + i] = 0.5 * LSB(24) + dfb / v->m + fby * dinv + rel;
        b[8 + i] = 0.5 * LSB(24) + LSB(30) + (fabs(px[i]) + fabs(py[i])) * dfb / v->J +
                   fby * fabs(pxJ[i] - px[i] / v->J) + fbx * fabs(pyJ[i] - py[i] / v->J) + rel;
    }
}

/* Builds H both ways from Q forces and checks every entry. */
static void check_build(int32_t dq, const int32_t fxq[4], const int32_t fyq[4], const char *ctx)
{
    rfe_fix_t Hq[RFE_H_Q31_SIZE];
    double Hd[RFE_H_SIZE], fx[4], fy[4], b[12];
    uint32_t sat = 0u;
    size_t i;
    char what[200];
    for (i = 0; i < 4; ++i) {
        fx[i] = fromq(fxq[i], 15);
        fy[i] = fromq(fyq[i], 15);
    }
    assert_int_equal(rfe_obsmat_build_q31(&pq.vehicle, dq, fxq, fyq, Hq, &sat), RFE_OK);
    assert_int_equal(rfe_obsmat_build_f64(&pd.vehicle, fromq(dq, 29), fx, fy, Hd), RFE_OK);
    assert_int_equal(sat, 0u);
    h_bounds(fromq(dq, 29), fx, fy, b);
    for (i = 0; i < 12; ++i) {
        snprintf(what, sizeof(what), "%s entry %zu", ctx, i);
        track((i < 8) ? &w_h12 : &w_h3, fromq(Hq[i], 24), Hd[i], b[i], what);
    }
}

static double uni(double a, double b) { return a + (b - a) * 0.5 * (rng_uniform() + 1.0); }

/* REQ: >= 1e5 random force sets over the whole Q15 range and steer angles over +-1 rad (and
 * over the whole Q29 range): H within the derived bounds. */
/* REQ-FXP-003 REQ-OBSMAT-001 */
static void test_obsmat_q31_build_random(void **state)
{
    int n;
    char ctx[64];
    (void)state;
    reset(&w_h12);
    reset(&w_h3);
    rng_seed(0x0B5E7ull);
    for (n = 0; n < 100000; ++n) {
        int32_t fxq[4], fyq[4], dq;
        size_t i;
        const double scale = (n % 2) ? 65535.0 : 8000.0;
        for (i = 0; i < 4; ++i) {
            fxq[i] = toq(uni(-scale, scale), 15);
            fyq[i] = toq(uni(-scale, scale), 15);
        }
        dq = (n % 10) ? toq(uni(-1.0, 1.0), 29) : (int32_t)floor(ldexp(rng_uniform(), 31));
        snprintf(ctx, sizeof(ctx), "random %d", n);
        check_build(dq, fxq, fyq, ctx);
    }
    printf("random force sets: 100000\n");
    report(&w_h12);
    report(&w_h3);
}

/* REQ: the paper-mode H(u) of every sample of every bundled log (the q31 kinematics and
 * normalised forces, the same Q forces to both twins): within the bounds. */
/* REQ-FXP-003 REQ-OBSMAT-001 */
static void test_obsmat_q31_build_scenarios(void **state)
{
    size_t s, v, r, n = 0;
    rfe_params_q31_t pap;
    (void)state;
    reset(&w_h12);
    reset(&w_h3);
    assert_int_equal(rfe_params_paper_q31(&pap), RFE_OK);
    for (s = 0; s < 19; ++s) {
        /* light mode (valgrind): the noisy variant only, every 10th row (each row is checked
         * on its own; the light run still reaches every line and branch the full one does) */
        for (v = 0; v < 3; v += rfe_test_stride(3u)) {
            char path[256], ctx[300];
            rfe_sensor_log_t log;
            rfe_io_error_t err;
            memset(&log, 0, sizeof(log));
            snprintf(path, sizeof(path), "scenarios/%s%s.csv", SCENARIO[s], VARIANT[v]);
            if (rfe_sensor_log_read(path, &log, &err) != 0) {
                fail_msg("%s:%zu: %s", path, err.line, err.msg);
            }
            for (r = 0; r < log.n_rows; r += rfe_test_stride(10u)) {
                const rfe_sensor_row_t *row = &log.rows[r];
                rfe_sample_q31_t u;
                rfe_wheel_kin_q31_t kin;
                rfe_fix_t f0x[4], f0y[4];
                uint32_t sat = 0u;
                q31_sample_from_row(row, &u);
                assert_int_equal(rfe_tyre_kinematics_q31(&pap.vehicle, &pap.tyre, &u, &kin, &sat),
                                 RFE_OK);
                assert_int_equal(rfe_tyre_forces_norm_q31(&pap.tyre, &kin, f0x, f0y, &sat),
                                 RFE_OK);
                snprintf(ctx, sizeof(ctx), "%s row %zu", path, r);
                check_build(u.delta, f0x, f0y, ctx);
                ++n;
            }
            rfe_sensor_log_free(&log);
        }
    }
    printf("scenario samples: %zu (57 logs)\n", n);
    report(&w_h12);
    report(&w_h3);
}

#if defined(__SIZEOF_INT128__)
/* Exact reference of y_r = round_half_up(sum H x / 2^29), saturated, in 128-bit integers. */
static int32_t ref_apply_row(const int32_t *h, const int32_t *x, uint32_t *count)
{
    __int128 s = 0;
    __int128 q;
    size_t i;
    for (i = 0; i < 4; ++i) {
        s += (__int128)h[i] * (__int128)x[i];
    }
    s += ((__int128)1 << 28);
    /* floor division by 2^29 */
    q = s / ((__int128)1 << 29);
    if ((q * ((__int128)1 << 29)) > s) {
        q -= 1;
    }
    if (q > INT32_MAX) {
        ++*count;
        return INT32_MAX;
    }
    if (q < -INT32_MAX) {
        ++*count;
        return -INT32_MAX;
    }
    return (int32_t)q;
}
#endif

/* REQ: h = H x is exactly rounded (bit for bit against an exact integer reference, including
 * the saturation count), and within 0.5 LSB24 of the double twin, for H and x over their
 * whole formats. */
/* REQ-FXP-003 REQ-OBSMAT-002 */
static void test_obsmat_q31_apply(void **state)
{
    int n;
    char ctx[64];
    (void)state;
    reset(&w_y);
    rng_seed(0xA991ull);
    for (n = 0; n < 100000; ++n) {
        int32_t Hq[12], xq[4], yq[3];
        double Hd[12], xd[4], yd[3];
        uint32_t sat = 0u, ref_sat = 0u;
        size_t i, r;
        const int wide = (n % 4 == 0);
        for (i = 0; i < 12; ++i) {
            /* the wide quarter with both signs (every second draw of it negated) */
            Hq[i] = wide ? (int32_t)floor(ldexp(rng_uniform(), 31)) * ((n % 8 == 0) ? -1 : 1)
                         : toq(uni(-20, 20), 24);
            Hd[i] = fromq(Hq[i], 24);
        }
        for (i = 0; i < 4; ++i) {
            xq[i] = wide ? (int32_t)floor(ldexp(rng_uniform(), 31)) * ((i % 2u == 0u) ? -1 : 1)
                         : toq(uni(-0.5, 1.5), 29);
            xd[i] = fromq(xq[i], 29);
        }
        assert_int_equal(rfe_obsmat_apply_q31(Hq, xq, yq, &sat), RFE_OK);
        assert_int_equal(rfe_obsmat_apply_f64(Hd, xd, yd), RFE_OK);
        for (r = 0; r < 3; ++r) {
            double mag = 0.0;
#if defined(__SIZEOF_INT128__)
            assert_int_equal(yq[r], ref_apply_row(&Hq[4 * r], xq, &ref_sat));
#endif
            for (i = 0; i < 4; ++i) {
                mag += fabs(Hd[4 * r + i] * xd[i]);
            }
            if (fabs(yd[r]) < HMAX - 1.0) {
                snprintf(ctx, sizeof(ctx), "random %d row %zu", n, r);
                track(&w_y, fromq(yq[r], 24), yd[r], 0.5 * LSB(24) + 4.0 * ldexp(mag, -53), ctx);
            } else if (fabs(yd[r]) > HMAX + 1.0) {
                assert_int_equal(abs(yq[r]), INT32_MAX); /* saturated */
            }
        }
#if defined(__SIZEOF_INT128__)
        assert_int_equal(sat, ref_sat);
#endif
    }
#if defined(__SIZEOF_INT128__)
    {
        /* the extremes: four products of 2^62 (a sum of 2^64), of -2^62 + 2^31, and mixed */
        static const int32_t ext[3] = {INT32_MIN, INT32_MAX, -INT32_MAX};
        size_t a;
        size_t b;
        for (a = 0u; a < 3u; ++a) {
            for (b = 0u; b < 3u; ++b) {
                int32_t He[12], xe[4], ye[3];
                uint32_t sat = 0u, ref_sat = 0u;
                size_t i;
                for (i = 0; i < 12; ++i) {
                    He[i] = (i % 4u == 3u) ? ext[b] : ext[a];
                }
                for (i = 0; i < 4; ++i) {
                    xe[i] = ext[(a + i) % 3u];
                }
                assert_int_equal(rfe_obsmat_apply_q31(He, xe, ye, &sat), RFE_OK);
                for (i = 0; i < 3; ++i) {
                    assert_int_equal(ye[i], ref_apply_row(&He[4 * i], xe, &ref_sat));
                }
                assert_int_equal(sat, ref_sat);
            }
        }
    }
#endif
    printf("random H x: 100000 (a quarter over the whole int32 range)\n");
    report(&w_y);
}

/* REQ: identical inputs give identical outputs. */
/* REQ-FXP-007 */
static void test_obsmat_q31_deterministic(void **state)
{
    int n;
    (void)state;
    rng_seed(5u);
    for (n = 0; n < 1000; ++n) {
        int32_t fx[4], fy[4], x[4], H1[12], H2[12], y1[3], y2[3];
        const int32_t d = toq(uni(-1, 1), 29);
        uint32_t s1 = 0u, s2 = 0u;
        size_t i;
        for (i = 0; i < 4; ++i) {
            fx[i] = toq(uni(-65535, 65535), 15);
            fy[i] = toq(uni(-65535, 65535), 15);
            x[i] = toq(uni(-4, 4), 29);
        }
        assert_int_equal(rfe_obsmat_build_q31(&pq.vehicle, d, fx, fy, H1, &s1), RFE_OK);
        assert_int_equal(rfe_obsmat_build_q31(&pq.vehicle, d, fx, fy, H2, &s2), RFE_OK);
        assert_memory_equal(H1, H2, sizeof(H1));
        assert_int_equal(rfe_obsmat_apply_q31(H1, x, y1, &s1), RFE_OK);
        assert_int_equal(rfe_obsmat_apply_q31(H2, x, y2, &s2), RFE_OK);
        assert_memory_equal(y1, y2, sizeof(y1));
        assert_int_equal(s1, s2);
    }
}

/* REQ: the counter grows by exactly the number of clamped entries: a light vehicle (m =
 * 200 kg, J = 300 kg m^2: |H| up to 460 m/s^2 per mu) with forces up to 65 kN clamps some
 * entries, each counted once; the counter stops at UINT32_MAX. */
/* REQ-FXP-008 */
static void test_obsmat_q31_saturation(void **state)
{
    rfe_params_t lp = pd;
    rfe_params_q31_t lq;
    int n, n_sat = 0;
    (void)state;
    lp.vehicle.m = 200.0;
    lp.vehicle.J = 300.0;
    assert_int_equal(rfe_params_to_q31_f64(&lp, &lq), RFE_OK);
    rng_seed(99u);
    for (n = 0; n < 5000; ++n) {
        int32_t fxq[4], fyq[4], Hq[12];
        double fx[4], fy[4], Hd[12];
        const int32_t dq = toq(uni(-1, 1), 29);
        uint32_t sat = 0u, expect = 0u, railed = 0u;
        int ambiguous = 0;
        size_t i;
        for (i = 0; i < 4; ++i) {
            fxq[i] = toq(uni(-65535, 65535), 15);
            fyq[i] = toq(uni(-65535, 65535), 15);
            fx[i] = fromq(fxq[i], 15);
            fy[i] = fromq(fyq[i], 15);
        }
        assert_int_equal(rfe_obsmat_build_q31(&lq.vehicle, dq, fxq, fyq, Hq, &sat), RFE_OK);
        assert_int_equal(rfe_obsmat_build_f64(&lp.vehicle, fromq(dq, 29), fx, fy, Hd), RFE_OK);
        for (i = 0; i < 12; ++i) {
            /* 1e-5 covers the bound of every entry of this vehicle (<= 2e-6: the rotation
             * TRIG 131070 N / 200 kg, 1/m and y/J rounded to Q38, 0.5 LSB24) five times */
            if (fabs(Hd[i]) > HMAX + 1e-5) {
                ++expect;
                assert_int_equal(Hq[i], (Hd[i] > 0) ? RFE_FIX_MAX : RFE_FIX_MIN);
            } else if (fabs(Hd[i]) >= HMAX - 1e-5) {
                ambiguous = 1;
            } else {
                assert_true(fabs(fromq(Hq[i], 24) - Hd[i]) < 1e-5);
            }
            railed += (abs(Hq[i]) == INT32_MAX) ? 1u : 0u;
        }
        if (!ambiguous) {
            assert_int_equal(sat, expect);
        }
        assert_true(sat <= railed);
        n_sat += (sat > 0u) ? 1 : 0;
    }
    printf("saturation: %d of 5000 light-vehicle force sets clamp an entry\n", n_sat);
    assert_true(n_sat > 500);
    {
        int32_t H[12], x[4], y[3];
        uint32_t sat = UINT32_MAX - 1u;
        size_t i;
        for (i = 0; i < 12; ++i) {
            H[i] = toq(127.0, 24);
        }
        for (i = 0; i < 4; ++i) {
            x[i] = toq(3.9, 29);
        }
        assert_int_equal(rfe_obsmat_apply_q31(H, x, y, &sat), RFE_OK);
        assert_int_equal(sat, UINT32_MAX);
        sat = 0u;
        assert_int_equal(rfe_obsmat_apply_q31(H, x, y, &sat), RFE_OK);
        assert_int_equal(sat, 3u);
        assert_int_equal(y[0], RFE_FIX_MAX);
        x[0] = toq(-3.9, 29);
        x[1] = toq(-3.9, 29);
        x[2] = toq(-3.9, 29);
        H[8] = toq(-127.0, 24);
        sat = 0u;
        assert_int_equal(rfe_obsmat_apply_q31(H, x, y, &sat), RFE_OK);
        assert_int_equal(sat, 2u); /* rows 1, 2: 127 (-7.8) = -991; row 3: exactly 0 */
        assert_int_equal(y[0], RFE_FIX_MIN);
        assert_true(abs(y[2]) < INT32_MAX);
        sat = UINT32_MAX;
        {
            int32_t fx[4] = {INT32_MAX, INT32_MAX, INT32_MAX, INT32_MAX};
            int32_t Hq[12];
            assert_int_equal(rfe_obsmat_build_q31(&lq.vehicle, 0, fx, fx, Hq, &sat), RFE_OK);
            assert_int_equal(sat, UINT32_MAX);
        }
    }
}

#define SENT ((int32_t)0x5A5A5A5A)

/* REQ: NULL -> RFE_ERR_NULL with outputs and counter untouched; every int32 input is in the
 * domain (no error for any value). */
/* REQ-OBSMAT-004 */
static void test_obsmat_q31_argument_checks(void **state)
{
    int32_t f[4] = {1, 2, 3, 4}, H[12], x[4] = {0, 0, 0, 0}, y[3];
    uint32_t sat = 3u;
    size_t i;
    (void)state;
    for (i = 0; i < 12; ++i) {
        H[i] = SENT;
    }
    y[0] = y[1] = y[2] = SENT;
    assert_int_equal(rfe_obsmat_build_q31(NULL, 0, f, f, H, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build_q31(&pq.vehicle, 0, NULL, f, H, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build_q31(&pq.vehicle, 0, f, NULL, H, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build_q31(&pq.vehicle, 0, f, f, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_build_q31(&pq.vehicle, 0, f, f, H, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_apply_q31(NULL, x, y, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_apply_q31(H, NULL, y, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_apply_q31(H, x, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_obsmat_apply_q31(H, x, y, NULL), RFE_ERR_NULL);
    for (i = 0; i < 12; ++i) {
        assert_int_equal(H[i], SENT);
    }
    assert_int_equal(y[0], SENT);
    assert_int_equal(sat, 3u);
    /* the int32 extremes: no error, and nothing saturates for the default vehicle */
    {
        static const int32_t ext[5] = {INT32_MIN, -INT32_MAX, -1, 0, INT32_MAX};
        int c;
        for (c = 0; c < 625; ++c) {
            const int32_t fx[4] = {ext[c % 5], ext[(c / 5) % 5], ext[(c / 25) % 5],
                                   ext[(c / 125) % 5]};
            sat = 0u;
            assert_int_equal(rfe_obsmat_build_q31(&pq.vehicle, ext[c % 5], fx, fx, H, &sat),
                             RFE_OK);
            assert_int_equal(sat, 0u);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_obsmat_q31_build_random),
        cmocka_unit_test(test_obsmat_q31_build_scenarios),
        cmocka_unit_test(test_obsmat_q31_apply),
        cmocka_unit_test(test_obsmat_q31_deterministic),
        cmocka_unit_test(test_obsmat_q31_saturation),
        cmocka_unit_test(test_obsmat_q31_argument_checks),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
