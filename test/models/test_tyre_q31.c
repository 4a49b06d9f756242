/**
 * @file test_tyre_q31.c
 * @brief The fixed-point kinematics and Dugoff tyre (rfe/component/tyre_q31.h) back to back against the
 *        double twin (rfe/component/tyre.h, _f64): every bundled scenario log, >= 1e5 random inputs over
 *        the documented limits (config.h) and the edges; determinism, saturation counting,
 *        argument checks. (The Magic Formula tyre: test_tyre_magic_q31.c.)
 *
 * Setup. The q31 functions get the converted presets (rfe_params_to_q31_f64; the default
 * preset with its tyre mode set to absolute, so that the load-scaled forces are the
 * Dugoff ones); the double
 * functions the original double presets and the same inputs (each Q input converted exactly to
 * double). So every difference is an error of the fixed-point evaluation: the rounding of the
 * parameters to their Q formats (the test measures each constant's actual rounding d(.) from the
 * two structs) and of the integer arithmetic. LSBn = 2^-n.
 *
 * Bounds (first order; the second-order terms are below 1e-13 of the values and are covered
 * by rounding each constant up). Primitive errors (q31_trig_bounds.h: fxmath_internal_q31.h,
 * measured by test_fxmath_q31): sin/cos 6.16e-10 (TRIG), atan2 2.27e-9 (ATAN2), tan at the
 * angle a: 2^-27 + TRIG (1 + |tan a|) / (cos a - TRIG) (TAN(a)).
 *
 * Kinematics (tyre_q31.c keeps the body / wheel velocities in int64 Q51):
 *  - wheel velocity error dv = TRIG (|vbx| + |vby|) (front wheels: the rotation by delta)
 *    + |r| (dx_i + dy_i) (positions rounded to Q29) + 2^-50 (four Q51 roundings of 2^-52);
 *  - vwx: 0.5 LSB23 (output rounding) + dv;
 *  - alpha = -atan2(v_wy, |v_wx|): ATAN2 + 0.71 LSB29 (both components rounded to 30 bits,
 *    magnitude >= 2^29: |d| <= 0.5 sqrt 2 / 2^29 rad) + sqrt(2) TRIG (front: the rotation turns
 *    the vector by at most that) + (dv without the trig term) / |v_w| + d(alpha_max) (clamp);
 *  - kappa = num / den: (1 + |kappa|) (|omega| dR + dv + d(v_min)) / den + 3 LSB30 (num and
 *    den rounded to 30 bits with den >= 2^29: <= 2 LSB30; exactly rounded quotient: 0.5 LSB30;
 *    0.5 LSB30 for the second order);
 *  - fz: 0.5 LSB15 (output) + 2^-43 (three Q43 roundings) + d(fz_static) + |ax| d(k_pitch)
 *    + |ay| d(k_roll).
 *
 * Dugoff (one wheel, the same Q inputs to both; mu_e = 1 in paper mode, max(mu, 0) else;
 * C1, C2 = Cx, Cy of the mode; G = 2 + mu_e / C1; v = |vwx|):
 *  - the tan of the Q26 format: |dF/dtan| <= Fz (2 C2 G + mu_e eps v) (derivation: with
 *    S = |(C1 k, C2 t)|, g = F/(Fz C k), and L < 1: g <= mu E / S <= G because S > mu (1-|k|)
 *    E / 2 and S >= C1 |k|; each of the three terms of d(C t g)/dt is bounded by C2 G or by
 *    mu eps v; L >= 1: C2 / (1 - |k|) <= C2 (1 + mu / (2 C1)) <= C2 G), times
 *    dt = TAN(alpha) + (1 + t^2) d(alpha_max) when alpha is clamped;
 *  - the integer evaluation (tyre_q31.c): direction cosines C k / S, C t / S within 4 2^-30;
 *    E within 4 2^-30 plus the eps rounding d(eps) v slip (while eps v slip < 2); the magnitude
 *    w = mu E (1 - L/2) within (8.5 mu_e + 1) 2^-30 + 1.5 mu_e dE (L >= 1: smaller); so
 *    Fz ((12.5 mu_e + 1) 2^-30 + 1.5 mu_e d(eps) v slip);
 *  - the stiffness rounding: 2 (dC1 / C1 + dC2 / C2) |F|; the final rounding 0.5 LSB15.
 * So |Fq - Fd| <= 0.5 LSB15 + rel |F| + k_z Fz, where the Fz term is the tan format's: a small
 * force at a large load carries the absolute error of tan alpha times the load's stiffness.
 * For the default presets (C = 20, 15, both exact in Q24; mu <= 1.2; v <= 150 m/s; alpha not
 * clamped) k_z ~ 5.2e-7, so the bound at Fz = 5 kN is ~2.6e-3 N + 1e-12 |F|; the test
 * evaluates it per case.
 *
 * Saturation: outputs beyond +-65536 N (Q15) clamp and count once each; the check compares
 * the count with the outputs whose double value is beyond the range by more than the bound.
 * The measured worst cases are printed (docs/FIXED_POINT.md quotes them).
 */
#include "test_light.h"
#include "test_common.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "rfe/config.h"
#include "host/fixed_conv.h"
#include "rfe/component/fxmath.h"
#include "rfe/component/params_conv.h"
#include "rfe/component/tyre.h"
#include "rfe/component/tyre_q31.h"
#include "q31_trig_bounds.h"
#include "test_rng.h"

#define TRIG Q31B_TRIG
#define ATAN2 Q31B_ATAN2
#define TAN(a) q31b_tan(a)
#define LSB(q) ldexp(1.0, -(q))
#define FMAX_N (2147483647.0 / 32768.0) /* largest Q15 force [N] */

#define N_RANDOM_SAMPLES 100000
#define N_RANDOM_WHEEL 120000

static const char *const WHEEL[4] = {"fl", "fr", "rl", "rr"};

/* The 19 bundled scenarios, each as model truth, Magic-Formula truth and noise-free. */
static const char *const SCENARIO[19] = {
    "accel_low_mu",       "brake_in_turn",      "cruise",          "hard_brake_high_mu",
    "hard_brake_low_mu",  "mu_step_hard_brake", "paper_high_mu_brake", "paper_low_mu_brake",
    "paper_mu_step",      "sine_steer_high_mu", "sine_steer_low_mu", "split_mu_brake",
    "split_mu_hard_brake",
    /* issue 17 */
    "double_lane_change_high_mu", "double_lane_change_low_mu", "ramp_steer_high_mu",
    "ramp_steer_low_mu", "brake_in_turn_low_mu", "wrong_tyre_data"};
static const char *const VARIANT[3] = {"", ".mf", ".nf"};

static rfe_params_t pd;     /* default preset in absolute tyre mode, double */
static rfe_params_t pd_pap; /* paper preset, double */
static rfe_params_q31_t pq;
static rfe_params_q31_t pq_pap;

/* Actual rounding of each constant (q value minus double value). */
static struct {
    double x[4], y[4]; /* wheel positions */
    double R, v_min, alpha_max, eps, Cx_n, Cy_n, cx, cy, fs_f, fs_r, kp, krf, krr;
} dp;

/* ---- worst-case tracking ---------------------------------------------------------------- */

typedef struct {
    const char *name;
    double lsb;       /* output LSB, for printing in LSB */
    double rel_floor; /* relative errors are reported where |ref| >= this */
    double max_abs, max_rel, max_ratio;
    long n;
    char where[160]; /* the case of the largest err/bound */
} worst_t;

static void track(worst_t *w, double got, double want, double bound, const char *ctx)
{
    const double err = fabs(got - want);
    if (err > w->max_abs) {
        w->max_abs = err;
    }
    if (fabs(want) >= w->rel_floor && err / fabs(want) > w->max_rel) {
        w->max_rel = err / fabs(want);
    }
    if (err / bound > w->max_ratio) {
        w->max_ratio = err / bound;
        snprintf(w->where, sizeof(w->where), "%s (q31 %.9g, double %.9g, bound %.3g)", ctx, got,
                 want, bound);
    }
    ++w->n;
    if (!(err <= bound)) {
        fail_msg("%s %s: q31 %.17g double %.17g |diff| %.3e > bound %.3e", w->name, ctx, got,
                 want, err, bound);
    }
}

static void reset(worst_t *w)
{
    w->max_abs = w->max_rel = w->max_ratio = 0.0;
    w->n = 0;
}

static void report(const worst_t *w)
{
    printf("  %-22s n=%-8ld max |err| %.3e (%.3f LSB)  max rel %.3e (|ref| >= %g)  max err/bound "
           "%.3f\n",
           w->name, w->n, w->max_abs, w->max_abs / w->lsb, w->max_rel, w->rel_floor,
           w->max_ratio);
    if (getenv("RFE_TEST_VERBOSE") != NULL) {
        printf("      worst err/bound at %s\n", w->where);
    }
}

/* ---- conversions -------------------------------------------------------------------------- */

static int32_t toq(double x, int q)
{
    uint32_t s = 0u;
    return rfe_fix_from_double(x, (unsigned)q, &s);
}
static double fromq(int32_t v, int q) { return rfe_fix_to_double(v, (unsigned)q); }

/* A sample in Q, and the same values in double. */
static void make_sample(double delta, double vx, double vy, double r, double ax, double ay,
                        const double om[4], rfe_sample_q31_t *uq, rfe_sample_t *ud)
{
    size_t i;
    memset(uq, 0, sizeof(*uq));
    memset(ud, 0, sizeof(*ud));
    uq->delta = toq(delta, 29);
    uq->vx = toq(vx, 23);
    uq->vy = toq(vy, 23);
    uq->yaw_rate = toq(r, 27);
    uq->ax = toq(ax, 24);
    uq->ay = toq(ay, 24);
    ud->delta = fromq(uq->delta, 29);
    ud->vx = fromq(uq->vx, 23);
    ud->vy = fromq(uq->vy, 23);
    ud->yaw_rate = fromq(uq->yaw_rate, 27);
    ud->ax = fromq(uq->ax, 24);
    ud->ay = fromq(uq->ay, 24);
    for (i = 0; i < 4; ++i) {
        uq->omega[i] = toq(om[i], 22);
        ud->omega[i] = fromq(uq->omega[i], 22);
    }
}

static int setup(void **state)
{
    (void)state;
    if (rfe_params_default_f64(&pd) != RFE_OK || rfe_params_paper_f64(&pd_pap) != RFE_OK) {
        return -1;
    }
    /* The Dugoff tyre in both of its modes here (the default preset's magic mode has its own
     * test, test_tyre_magic_q31.c): the load-scaled comparisons use the absolute mode. */
    pd.tyre.mode = RFE_TYRE_ABSOLUTE;
    if (rfe_params_to_q31_f64(&pd, &pq) != RFE_OK ||
        rfe_params_to_q31_f64(&pd_pap, &pq_pap) != RFE_OK) {
        return -1;
    }
    dp.x[0] = dp.x[1] = fabs(fromq(pq.vehicle.Lf, 29) - pd.vehicle.Lf);
    dp.x[2] = dp.x[3] = fabs(fromq(pq.vehicle.Lr, 29) - pd.vehicle.Lr);
    dp.y[0] = dp.y[1] = fabs(fromq(pq.vehicle.yf, 29) - 0.5 * pd.vehicle.Bf);
    dp.y[2] = dp.y[3] = fabs(fromq(pq.vehicle.yr, 29) - 0.5 * pd.vehicle.Br);
    dp.R = fabs(fromq(pq.vehicle.R, 29) - pd.vehicle.R);
    dp.v_min = fabs(fromq(pq.tyre.v_min, 23) - pd.tyre.v_min);
    dp.alpha_max = fabs(fromq(pq.tyre.alpha_max, 29) - pd.tyre.alpha_max);
    dp.eps = fabs(fromq(pq.tyre.eps, 32) - pd.tyre.eps);
    dp.Cx_n = fabs(fromq(pq.tyre.Cx_n, 24) - pd.tyre.Cx_n);
    dp.Cy_n = fabs(fromq(pq.tyre.Cy_n, 24) - pd.tyre.Cy_n);
    dp.cx = fabs(fromq(pq.tyre.cx, 24) - pd.tyre.cx);
    dp.cy = fabs(fromq(pq.tyre.cy, 24) - pd.tyre.cy);
    {
        const rfe_vehicle_t *v = &pd.vehicle;
        const double La = v->Lf + v->Lr;
        dp.fs_f = fabs(fromq(pq.vehicle.fz_static_f, 15) - v->m * v->g * v->Lr / (2 * La));
        dp.fs_r = fabs(fromq(pq.vehicle.fz_static_r, 15) - v->m * v->g * v->Lf / (2 * La));
        dp.kp = fabs(fromq(pq.vehicle.k_pitch, 20) - v->m * v->hg / (2 * La));
        dp.krf = fabs(fromq(pq.vehicle.k_roll_f, 20) - v->m * v->hg * v->Lr / (La * v->Bf));
        dp.krr = fabs(fromq(pq.vehicle.k_roll_r, 20) - v->m * v->hg * v->Lf / (La * v->Br));
    }
    return 0;
}

/* ---- the derived bounds --------------------------------------------------------------------- */

typedef struct {
    double vwx, alpha, kappa, fz;
} kin_bound_t;

/* Bounds of the kinematics of wheel i for the (double) sample u; see the file comment. */
static kin_bound_t kin_bounds(const rfe_sample_t *u, size_t i, double kappa_d)
{
    const rfe_vehicle_t *v = &pd.vehicle;
    const double px[4] = {v->Lf, v->Lf, -v->Lr, -v->Lr};
    const double py[4] = {v->Bf / 2, -v->Bf / 2, v->Br / 2, -v->Br / 2};
    const double d = (i < 2) ? u->delta : 0.0;
    const double vbx = u->vx - u->yaw_rate * py[i];
    const double vby = u->vy + u->yaw_rate * px[i];
    const double vwx = vbx * cos(d) + vby * sin(d);
    const double vwy = -vbx * sin(d) + vby * cos(d);
    const double vr = u->omega[i] * v->R;
    const double den = fmax(fmax(fabs(vr), fabs(vwx)), pd.tyre.v_min);
    const double dpos = fabs(u->yaw_rate) * (dp.x[i] + dp.y[i]) + ldexp(1.0, -50);
    const double dtrig = (i < 2) ? TRIG * (fabs(vbx) + fabs(vby)) : 0.0;
    const double vw = hypot(vwx, vwy);
    const double ax = fabs(u->ax), ay = fabs(u->ay);
    kin_bound_t b;

    b.vwx = 0.5 * LSB(23) + dtrig + dpos + 1e-15 * (fabs(vbx) + fabs(vby));
    b.alpha = ATAN2 + 0.71 * LSB(29) + ((i < 2) ? sqrt(2.0) * TRIG : 0.0) + dp.alpha_max +
              ((vw > 0.0) ? dpos / vw : 0.0) + 1e-15;
    b.kappa = (1.0 + fabs(kappa_d)) * (fabs(u->omega[i]) * dp.R + dtrig + dpos + dp.v_min) / den +
              3.0 * LSB(30);
    b.fz = 0.5 * LSB(15) + ldexp(1.0, -43) + ((i < 2) ? dp.fs_f : dp.fs_r) + ax * dp.kp +
           ay * ((i < 2) ? dp.krf : dp.krr) + 1e-12 * 1e4;
    return b;
}

/* Bound of one Dugoff force for the (double) inputs; see the file comment. F is the double
 * force. paper: mode. */
static double dugoff_bound(int paper, double kappa, double alpha, double fz, double vwx,
                           double mu, double F)
{
    const rfe_tyre_params_t *t = &pd.tyre;
    const double C1 = paper ? t->Cx_n : t->cx;
    const double C2 = paper ? t->Cy_n : t->cy;
    const double dC = 2.0 * (paper ? (dp.Cx_n / C1 + dp.Cy_n / C2) : (dp.cx / C1 + dp.cy / C2));
    const double mue = paper ? 1.0 : fmax(mu, 0.0);
    const double amax = fmin(t->alpha_max, fromq(pq.tyre.alpha_max, 29));
    const double ac = fmin(fmax(alpha, -t->alpha_max), t->alpha_max);
    const double k = fmin(fmax(kappa, -1.0), 1.0);
    const double tn = tan(ac);
    const double slip = hypot(k, tn);
    const double v = fabs(vwx);
    const double P = t->eps * v * slip;
    const double dE = (P < 2.0) ? dp.eps * v * slip : 0.0;
    const double G = 2.0 + mue / C1;
    double dt = TAN(ac);
    if (fabs(alpha) >= amax - LSB(29)) {
        dt += (1.0 + tn * tn) * dp.alpha_max;
    }
    return 0.5 * LSB(15) + (dC + 1e-12) * fabs(F) +
           fz * ((12.5 * mue + 1.0) * ldexp(1.0, -30) + 1.5 * mue * dE +
                 (2.0 * C2 * G + mue * t->eps * v) * dt);
}

/* ---- kinematics ---------------------------------------------------------------------------- */

static worst_t w_vwx = {"kin vwx [m/s]", 1.0 / 8388608.0, 0.1, 0, 0, 0, 0, {0}};
static worst_t w_alpha = {"kin alpha [rad]", 1.0 / 536870912.0, 1e-3, 0, 0, 0, 0, {0}};
static worst_t w_kappa = {"kin kappa", 1.0 / 1073741824.0, 1e-3, 0, 0, 0, 0, {0}};
static worst_t w_fz = {"kin fz [N]", 1.0 / 32768.0, 100.0, 0, 0, 0, 0, {0}};
static worst_t w_f0 = {"F0x, F0y paper [N]", 1.0 / 32768.0, 100.0, 0, 0, 0, 0, {0}};
static worst_t w_fabs = {"Fx, Fy absolute [N]", 1.0 / 32768.0, 100.0, 0, 0, 0, 0, {0}};

static void reset_all(void)
{
    reset(&w_vwx);
    reset(&w_alpha);
    reset(&w_kappa);
    reset(&w_fz);
    reset(&w_f0);
    reset(&w_fabs);
}

static void report_all(void)
{
    report(&w_vwx);
    report(&w_alpha);
    report(&w_kappa);
    report(&w_fz);
    report(&w_f0);
    report(&w_fabs);
}

/* Runs both kinematics on one sample, checks the bounds, returns both results. */
static void check_kinematics(const rfe_sample_q31_t *uq, const rfe_sample_t *ud,
                             rfe_wheel_kin_q31_t *kq, rfe_wheel_kin_t *kd, const char *ctx)
{
    uint32_t sat = 0u;
    size_t i;
    char what[200];
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, uq, kq, &sat), RFE_OK);
    assert_int_equal(rfe_tyre_kinematics_f64(&pd.vehicle, &pd.tyre, ud, kd), RFE_OK);
    assert_int_equal(sat, 0u); /* within the documented limits nothing saturates */
    for (i = 0; i < 4; ++i) {
        const kin_bound_t b = kin_bounds(ud, i, kd->kappa[i]);
        snprintf(what, sizeof(what), "%s wheel %s", ctx, WHEEL[i]);
        track(&w_vwx, fromq(kq->vwx[i], 23), kd->vwx[i], b.vwx, what);
        track(&w_alpha, fromq(kq->alpha[i], 29), kd->alpha[i], b.alpha, what);
        track(&w_kappa, fromq(kq->kappa[i], 30), kd->kappa[i], b.kappa, what);
        track(&w_fz, fromq(kq->fz[i], 15), kd->fz[i], b.fz, what);
    }
}

/* Both tyre modes on the q31 kinematics of one sample (the double tyre gets the same Q
 * inputs), at friction mu per wheel. */
static void check_forces(const rfe_wheel_kin_q31_t *kq, const double mu[4], const char *ctx)
{
    rfe_fix_t fxq[4], fyq[4], muq[4];
    uint32_t sat = 0u;
    size_t i;
    char what[200];
    for (i = 0; i < 4; ++i) {
        muq[i] = toq(mu[i], 29);
    }
    assert_int_equal(rfe_tyre_forces_norm_q31(&pq_pap.tyre, kq, fxq, fyq, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        const double k = fromq(kq->kappa[i], 30), a = fromq(kq->alpha[i], 29);
        const double fz = fromq(kq->fz[i], 15), v = fromq(kq->vwx[i], 23);
        double fx, fy;
        assert_int_equal(rfe_tyre_dugoff_norm_f64(&pd_pap.tyre, k, a, fz, v, &fx, &fy), RFE_OK);
        snprintf(what, sizeof(what), "%s norm wheel %s", ctx, WHEEL[i]);
        track(&w_f0, fromq(fxq[i], 15), fx, dugoff_bound(1, k, a, fz, v, 1.0, fx), what);
        track(&w_f0, fromq(fyq[i], 15), fy, dugoff_bound(1, k, a, fz, v, 1.0, fy), what);
    }
    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, kq, muq, fxq, fyq, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        const double k = fromq(kq->kappa[i], 30), a = fromq(kq->alpha[i], 29);
        const double fz = fromq(kq->fz[i], 15), v = fromq(kq->vwx[i], 23);
        const double m = fromq(muq[i], 29);
        double fx, fy;
        assert_int_equal(rfe_tyre_dugoff_abs_f64(&pd.tyre, k, a, fz, v, m, &fx, &fy), RFE_OK);
        snprintf(what, sizeof(what), "%s abs wheel %s mu %.3f", ctx, WHEEL[i], m);
        track(&w_fabs, fromq(fxq[i], 15), fx, dugoff_bound(0, k, a, fz, v, m, fx), what);
        track(&w_fabs, fromq(fyq[i], 15), fy, dugoff_bound(0, k, a, fz, v, m, fy), what);
    }
    assert_int_equal(sat, 0u);
}

/* REQ: on every sample of every bundled log (19 scenarios x 3 truth variants) the q31
 * kinematics and both tyre modes (at the log's true mu) agree with the double twin within the
 * derived bounds. */
/* REQ-FXP-003 */
static void test_tyre_q31_scenarios(void **state)
{
    size_t s, v, r, n_logs = 0, n_rows = 0;
    (void)state;
    reset_all();
    for (s = 0; s < 19; ++s) {
        for (v = 0; v < 3; v += rfe_test_stride(3u)) { /* light mode: the noisy variant only */
            char path[256], ctx[300];
            rfe_sensor_log_t log;
            rfe_io_error_t err;
            memset(&log, 0, sizeof(log));
            snprintf(path, sizeof(path), "scenarios/%s%s.csv", SCENARIO[s], VARIANT[v]);
            if (rfe_sensor_log_read(path, &log, &err) != 0) {
                fail_msg("%s:%zu: %s", path, err.line, err.msg);
            }
            assert_true(log.has_truth);
            /* light mode (valgrind): every 10th row (each row is checked on its own) */
            for (r = 0; r < log.n_rows; r += rfe_test_stride(10u)) {
                const rfe_sensor_row_t *row = &log.rows[r];
                rfe_sample_q31_t uq;
                rfe_sample_t ud;
                rfe_wheel_kin_q31_t kq;
                rfe_wheel_kin_t kd;
                make_sample(row->delta, row->vx, row->vy, row->yaw_rate, row->ax, row->ay,
                            row->omega, &uq, &ud);
                snprintf(ctx, sizeof(ctx), "%s row %zu", path, r);
                check_kinematics(&uq, &ud, &kq, &kd, ctx);
                check_forces(&kq, row->mu_true, ctx);
            }
            n_rows += log.n_rows;
            ++n_logs;
            rfe_sensor_log_free(&log);
        }
    }
    assert_int_equal(n_logs, rfe_test_light() ? 19 : 57); /* light: one variant of 19 */
    printf("scenario logs: %zu logs, %zu samples, 4 wheels each\n", n_logs, n_rows);
    report_all();
}

static double uni(double a, double b) { return a + (b - a) * 0.5 * (rng_uniform() + 1.0); }

/* A value with a log-uniform magnitude in [1e-6 a, a] and a random sign. */
static double logu(double a)
{
    const double m = a * pow(10.0, uni(-6.0, 0.0));
    return (rng_uniform() < 0.0) ? -m : m;
}

/* REQ: >= 1e5 random samples over the input limits of config.h (uniform, near-rolling wheels
 * and log-uniform magnitudes), with the tyre at random mu in [-0.5, 1.2]: within the bounds. */
/* REQ-FXP-003 */
static void test_tyre_q31_random(void **state)
{
    int n;
    char ctx[64];
    (void)state;
    reset_all();
    rng_seed(0x51A7E5EEDull);
    for (n = 0; n < N_RANDOM_SAMPLES; n += (int)rfe_test_stride(10u)) {
        double om[4], mu[4], delta, vx, vy, r, ax, ay;
        size_t i;
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        rfe_wheel_kin_q31_t kq;
        rfe_wheel_kin_t kd;
        switch (n % 3) {
        case 0: /* uniform over the limits */
            delta = uni(-RFE_LIMIT_DELTA, RFE_LIMIT_DELTA);
            vx = uni(-RFE_LIMIT_VX, RFE_LIMIT_VX);
            vy = uni(-RFE_LIMIT_VY, RFE_LIMIT_VY);
            r = uni(-RFE_LIMIT_YAW_RATE, RFE_LIMIT_YAW_RATE);
            ax = uni(-RFE_LIMIT_ACC, RFE_LIMIT_ACC);
            ay = uni(-RFE_LIMIT_ACC, RFE_LIMIT_ACC);
            for (i = 0; i < 4; ++i) {
                om[i] = uni(-RFE_LIMIT_OMEGA, RFE_LIMIT_OMEGA);
            }
            break;
        case 1: /* driving: wheels near rolling, small slip angles */
            delta = uni(-0.3, 0.3);
            vx = uni(0.0, 60.0);
            vy = uni(-2.0, 2.0);
            r = uni(-1.0, 1.0);
            ax = uni(-10.0, 10.0);
            ay = uni(-10.0, 10.0);
            for (i = 0; i < 4; ++i) {
                om[i] = vx * (1.0 + uni(-0.3, 0.1)) / pd.vehicle.R;
            }
            break;
        default: /* magnitudes over six decades */
            delta = logu(RFE_LIMIT_DELTA);
            vx = logu(RFE_LIMIT_VX);
            vy = logu(RFE_LIMIT_VY);
            r = logu(RFE_LIMIT_YAW_RATE);
            ax = logu(RFE_LIMIT_ACC);
            ay = logu(RFE_LIMIT_ACC);
            for (i = 0; i < 4; ++i) {
                om[i] = logu(RFE_LIMIT_OMEGA);
            }
            break;
        }
        for (i = 0; i < 4; ++i) {
            mu[i] = uni(-0.5, 1.2);
        }
        make_sample(delta, vx, vy, r, ax, ay, om, &uq, &ud);
        snprintf(ctx, sizeof(ctx), "random sample %d", n);
        check_kinematics(&uq, &ud, &kq, &kd, ctx);
        check_forces(&kq, mu, ctx);
    }
    printf("random samples: %d (x 4 wheels)\n", N_RANDOM_SAMPLES);
    report_all();
}

/* REQ: the edges: standstill, zero slip, locked and spinning wheels, slip angles at
 * alpha_max, loads clipped at 0, reversing; exact where the model is exact. */
/* REQ-FXP-003 REQ-TYRE-001 REQ-TYRE-004 */
static void test_tyre_q31_kinematics_edges(void **state)
{
    static const double zero[4] = {0, 0, 0, 0};
    rfe_sample_q31_t uq;
    rfe_sample_t ud;
    rfe_wheel_kin_q31_t kq;
    rfe_wheel_kin_t kd;
    size_t i;
    double om[4];
    (void)state;

    /* Standstill: everything 0, the v_min guard keeps kappa at 0. */
    make_sample(0, 0, 0, 0, 0, 0, zero, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "standstill");
    for (i = 0; i < 4; ++i) {
        assert_int_equal(kq.kappa[i], 0);
        assert_int_equal(kq.alpha[i], 0);
        assert_int_equal(kq.vwx[i], 0);
        assert_true(kq.fz[i] > 0);
    }
    /* Locked wheels while moving: kappa = -1 exactly; driving from standstill: +1. */
    make_sample(0.1, 20, 0.5, 0.2, -8, 1, zero, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "locked");
    for (i = 0; i < 4; ++i) {
        assert_int_equal(kq.kappa[i], -RFE_FIX_ONE(30));
    }
    for (i = 0; i < 4; ++i) {
        om[i] = 30.0;
    }
    make_sample(0, 0, 0, 0, 3, 0, om, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "spinning from standstill");
    for (i = 0; i < 4; ++i) {
        assert_int_equal(kq.kappa[i], RFE_FIX_ONE(30));
    }
    /* Zero slip: straight, no yaw, omega R = vx (exact in Q: omega = vx / R chosen so that
     * omega_q R_q equals vx_q to within the Q51 resolution). */
    for (i = 0; i < 4; ++i) {
        om[i] = 25.0 / pd.vehicle.R;
    }
    make_sample(0, 25, 0, 0, 0, 0, om, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "zero slip");
    for (i = 0; i < 4; ++i) {
        assert_true(abs(kq.kappa[i]) <= 64); /* |kappa| <= 6e-8: R's rounding only */
        assert_int_equal(kq.alpha[i], 0);
    }
    /* Sideways: |alpha| clamped to alpha_max exactly. */
    make_sample(0, 0.05, 40, 0, 0, 0, zero, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "sideways");
    for (i = 0; i < 4; ++i) {
        assert_int_equal(kq.alpha[i], -pq.tyre.alpha_max);
    }
    make_sample(0, 0.05, -40, 0, 0, 0, zero, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "sideways right");
    for (i = 0; i < 4; ++i) {
        assert_int_equal(kq.alpha[i], pq.tyre.alpha_max);
    }
    /* Hard braking and cornering at the limits: loads clipped at exactly 0. */
    make_sample(0, 30, 0, 0, RFE_LIMIT_ACC, RFE_LIMIT_ACC, zero, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "load clip");
    assert_int_equal(kq.fz[RFE_FL], 0);
    assert_true(kq.fz[RFE_RR] > 0);
    make_sample(0, 30, 0, 0, -RFE_LIMIT_ACC, -RFE_LIMIT_ACC, zero, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "load clip 2");
    assert_int_equal(kq.fz[RFE_RR], 0);
    /* Reversing straight: alpha = 0 (|v_wx| in atan2), vwx < 0. */
    for (i = 0; i < 4; ++i) {
        om[i] = -10.0 / pd.vehicle.R;
    }
    make_sample(0, -10, 0, 0, 0, 0, om, &uq, &ud);
    check_kinematics(&uq, &ud, &kq, &kd, "reversing");
    for (i = 0; i < 4; ++i) {
        assert_int_equal(kq.alpha[i], 0);
        assert_true(kq.vwx[i] < 0);
    }
    /* Every limit at once, all sign combinations. */
    {
        int c;
        for (c = 0; c < 128; ++c) {
            const double sg[7] = {(c & 1) ? 1 : -1, (c & 2) ? 1 : -1, (c & 4) ? 1 : -1,
                                  (c & 8) ? 1 : -1, (c & 16) ? 1 : -1, (c & 32) ? 1 : -1,
                                  (c & 64) ? 1 : -1};
            for (i = 0; i < 4; ++i) {
                om[i] = sg[6] * RFE_LIMIT_OMEGA * ((i & 1) ? 1.0 : 0.0);
            }
            make_sample(sg[0] * RFE_LIMIT_DELTA, sg[1] * RFE_LIMIT_VX, sg[2] * RFE_LIMIT_VY,
                        sg[3] * RFE_LIMIT_YAW_RATE, sg[4] * RFE_LIMIT_ACC,
                        sg[5] * RFE_LIMIT_ACC, om, &uq, &ud);
            check_kinematics(&uq, &ud, &kq, &kd, "limits");
        }
    }
}

/* One wheel, both modes, one case: checks the bounds (and returns the q31 forces). */
static void check_wheel(double kappa, double alpha, double fz, double vwx, double mu,
                        int32_t out[4], const char *ctx)
{
    const int32_t kq = toq(kappa, 30), aq = toq(alpha, 29), fq = toq(fz, 15);
    const int32_t vq = toq(vwx, 23), mq = toq(mu, 29);
    const double k = fromq(kq, 30), a = fromq(aq, 29), f = fromq(fq, 15), v = fromq(vq, 23);
    const double m = fromq(mq, 29);
    double fx, fy;
    uint32_t sat = 0u;
    assert_int_equal(rfe_tyre_dugoff_norm_q31(&pq_pap.tyre, kq, aq, fq, vq, &out[0], &out[1], &sat),
                     RFE_OK);
    assert_int_equal(rfe_tyre_dugoff_norm_f64(&pd_pap.tyre, k, a, f, v, &fx, &fy), RFE_OK);
    track(&w_f0, fromq(out[0], 15), fx, dugoff_bound(1, k, a, f, v, 1.0, fx), ctx);
    track(&w_f0, fromq(out[1], 15), fy, dugoff_bound(1, k, a, f, v, 1.0, fy), ctx);
    assert_int_equal(rfe_tyre_dugoff_abs_q31(&pq.tyre, kq, aq, fq, vq, mq, &out[2], &out[3], &sat),
                     RFE_OK);
    assert_int_equal(rfe_tyre_dugoff_abs_f64(&pd.tyre, k, a, f, v, m, &fx, &fy), RFE_OK);
    track(&w_fabs, fromq(out[2], 15), fx, dugoff_bound(0, k, a, f, v, m, fx), ctx);
    track(&w_fabs, fromq(out[3], 15), fy, dugoff_bound(0, k, a, f, v, m, fy), ctx);
    assert_int_equal(sat, 0u);
}

/* REQ: >= 1e5 random single-wheel cases over the whole input domain of the Dugoff functions
 * (kappa beyond the clip, alpha beyond alpha_max, loads up to 30 kN, |vwx| up to 150 m/s,
 * mu in [-0.5, 1.2] and up to 3.9 for cubature points) and the edges: within the bounds. */
/* REQ-FXP-003 REQ-TYRE-002 REQ-TYRE-003 REQ-TYRE-004 */
static void test_tyre_q31_dugoff_random_and_edges(void **state)
{
    int n;
    int32_t o[4];
    char ctx[64];
    (void)state;
    reset_all();
    rng_seed(0xD060FFull);
    for (n = 0; n < N_RANDOM_WHEEL; n += (int)rfe_test_stride(10u)) {
        const double kappa = (n % 2) ? uni(-1.2, 1.2) : logu(1.0);
        const double alpha = (n % 3) ? uni(-1.5, 1.5) : logu(1.0);
        const double mu = (n % 5) ? uni(-0.5, 1.2) : uni(1.2, 3.9);
        /* |F| <= mu Fz: keep the forces inside Q15 here (saturation has its own test) */
        const double fz = uni(0.0, fmin(30000.0, 60000.0 / fmax(mu, 1.0)));
        const double vwx = uni(-150.0, 150.0);
        snprintf(ctx, sizeof(ctx), "random wheel %d", n);
        check_wheel(kappa, alpha, fz, vwx, mu, o, ctx);
    }
    /* Zero slip: no force at all. */
    check_wheel(0, 0, 5000, 30, 0.8, o, "zero slip");
    assert_true(o[0] == 0 && o[1] == 0 && o[2] == 0 && o[3] == 0);
    /* No load, mu <= 0: no force. */
    check_wheel(-0.3, 0.2, 0, 30, 0.8, o, "no load");
    assert_true(o[0] == 0 && o[1] == 0 && o[2] == 0 && o[3] == 0);
    check_wheel(-0.3, 0.2, 5000, 30, -0.2, o, "mu < 0");
    assert_true(o[2] == 0 && o[3] == 0);
    check_wheel(-0.3, 0.2, 5000, 30, 0.0, o, "mu = 0");
    assert_true(o[2] == 0 && o[3] == 0);
    /* Locked wheel, pure slip and combined, and beyond the clip (same result as at -1). */
    {
        int32_t p[4];
        check_wheel(-1.0, 0.0, 5000, 30, 0.8, o, "locked");
        assert_true(o[0] < 0 && o[1] == 0);
        check_wheel(-1.7, 0.0, 5000, 30, 0.8, p, "beyond locked");
        assert_memory_equal(o, p, sizeof(o));
        check_wheel(1.0, 0.3, 5000, 30, 0.8, o, "spinning");
        check_wheel(2.0, 0.3, 5000, 30, 0.8, p, "beyond spinning");
        assert_memory_equal(o, p, sizeof(o));
        /* alpha at and beyond alpha_max */
        check_wheel(0.05, 1.4, 5000, 30, 0.8, o, "alpha_max");
        check_wheel(0.05, 1.49, 5000, 30, 0.8, p, "beyond alpha_max");
        assert_memory_equal(o, p, sizeof(o));
        check_wheel(0.05, -1.4, 5000, 30, 0.8, o, "-alpha_max");
    }
    /* The velocity reduction at its clamp (E = 0) and just inside. */
    check_wheel(-0.9, 1.3, 5000, 150, 0.8, o, "E = 0");
    assert_true(o[0] == 0 && o[1] == 0 && o[2] == 0 && o[3] == 0);
    check_wheel(-0.9, 0.0, 5000, 73, 0.8, o, "E small");
    /* Tiny slips (L >= 1, linear region) and the smallest representable ones. */
    check_wheel(1e-9, 0.0, 5000, 30, 0.8, o, "1 LSB kappa");
    check_wheel(0.0, 2e-9, 5000, 30, 0.8, o, "1 LSB alpha");
    check_wheel(-1e-4, 1e-4, 65000, 30, 0.01, o, "tiny slip, large load, small mu");
    printf("random wheels: %d (both modes)\n", N_RANDOM_WHEEL);
    report(&w_f0);
    report(&w_fabs);
}

/* ---- determinism, saturation ------------------------------------------------------------- */

/* REQ: the same inputs give bit-identical outputs (and saturation counts) on repeated calls. */
/* REQ-FXP-007 */
static void test_tyre_q31_deterministic(void **state)
{
    int n;
    (void)state;
    rng_seed(77u);
    for (n = 0; n < 2000; ++n) {
        double om[4];
        size_t i;
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        rfe_wheel_kin_q31_t k1, k2;
        rfe_fix_t f1[4][4], f2[4][4], mu[4];
        uint32_t s1 = 0u, s2 = 0u;
        for (i = 0; i < 4; ++i) {
            om[i] = uni(-RFE_LIMIT_OMEGA, RFE_LIMIT_OMEGA);
            mu[i] = toq(uni(-0.5, 3.9), 29);
        }
        make_sample(uni(-1, 1), uni(-100, 100), uni(-50, 50), uni(-10, 10), uni(-50, 50),
                    uni(-50, 50), om, &uq, &ud);
        memset(&k1, 0x11, sizeof(k1));
        memset(&k2, 0x22, sizeof(k2));
        assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &uq, &k1, &s1), RFE_OK);
        assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &uq, &k2, &s2), RFE_OK);
        assert_memory_equal(&k1, &k2, sizeof(k1));
        assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, &k1, f1[0], f1[1], &s1), RFE_OK);
        assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, &k2, f2[0], f2[1], &s2), RFE_OK);
        assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &k1, mu, f1[2], f1[3], &s1), RFE_OK);
        assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &k2, mu, f2[2], f2[3], &s2), RFE_OK);
        assert_memory_equal(f1, f2, sizeof(f1));
        assert_int_equal(s1, s2);
    }
}

/* Number of values v[0..n) at the rail. */
static uint32_t n_railed(const int32_t *v, size_t n)
{
    uint32_t c = 0u;
    size_t i;
    for (i = 0; i < n; ++i) {
        c += (v[i] == RFE_FIX_MAX || v[i] == RFE_FIX_MIN) ? 1u : 0u;
    }
    return c;
}

/* REQ: the saturation counter grows by exactly the number of clamped outputs: loads and
 * wheel speeds beyond their formats (inputs beyond config.h), forces beyond 65536 N (large mu
 * at a large load); at the rail the value is the clamped one, and the counter itself stops at
 * UINT32_MAX. */
/* REQ-FXP-008 */
static void test_tyre_q31_saturation(void **state)
{
    rfe_sample_q31_t uq;
    rfe_sample_t ud;
    rfe_wheel_kin_q31_t kq;
    rfe_fix_t fx, fy;
    uint32_t sat = 5u;
    double om[4] = {0, 0, 0, 0};
    int n, n_sat_cases = 0;
    (void)state;

    /* ax = -127, ay = 127 m/s^2 (beyond config.h, inside Q24): the front-right load
     * 4856 - 162 ax + 334.1 ay = 67864 N > 65536 N saturates; fl and rl clip at 0 and rr is
     * 19550 N: exactly one count. */
    make_sample(0, 10, 0, 0, -127.0, 127.0, om, &uq, &ud);
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &uq, &kq, &sat), RFE_OK);
    assert_int_equal(sat, 5u + 1u);
    assert_int_equal(kq.fz[RFE_FR], RFE_FIX_MAX);
    assert_int_equal(n_railed(kq.fz, 4), 1u);
    /* vx = 255 m/s, r = 15.9 rad/s: the right wheels see 255 + 15.9 * 0.8 > 256 m/s. */
    make_sample(0, 255.0, 0, 15.9, 0, 0, om, &uq, &ud);
    sat = 0u;
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &uq, &kq, &sat), RFE_OK);
    assert_int_equal(sat, 2u);
    assert_int_equal(kq.vwx[RFE_FR], RFE_FIX_MAX);
    assert_int_equal(kq.vwx[RFE_RR], RFE_FIX_MAX);
    assert_int_equal(n_railed(kq.vwx, 4), 2u);
    /* Absolute mode at mu = 3.9 and 60 kN: |F| up to mu Fz = 234 kN. The count must equal the
     * number of outputs whose double value is beyond the range by more than the bound; near
     * the boundary (within the bound) either is allowed, and counted consistently. */
    rng_seed(4242u);
    for (n = 0; n < 20000; ++n) {
        const double k = uni(-1, 1), a = uni(-1.4, 1.4), f = uni(10000, 65535);
        const double v = uni(-60, 60), m = uni(0.5, 3.99);
        const int32_t kq1 = toq(k, 30), aq1 = toq(a, 29), fq1 = toq(f, 15), vq1 = toq(v, 23);
        const int32_t mq1 = toq(m, 29);
        double fxd, fyd;
        const double *fd[2] = {&fxd, &fyd};
        const int32_t *fqv[2] = {&fx, &fy};
        uint32_t expect = 0u;
        int j, ambiguous = 0;
        sat = 0u;
        assert_int_equal(rfe_tyre_dugoff_abs_q31(&pq.tyre, kq1, aq1, fq1, vq1, mq1, &fx, &fy,
                                                 &sat),
                         RFE_OK);
        assert_int_equal(rfe_tyre_dugoff_abs_f64(&pd.tyre, fromq(kq1, 30), fromq(aq1, 29),
                                                 fromq(fq1, 15), fromq(vq1, 23), fromq(mq1, 29),
                                                 &fxd, &fyd),
                         RFE_OK);
        for (j = 0; j < 2; ++j) {
            const double b = dugoff_bound(0, fromq(kq1, 30), fromq(aq1, 29), fromq(fq1, 15),
                                          fromq(vq1, 23), fromq(mq1, 29), *fd[j]);
            if (fabs(*fd[j]) > FMAX_N + b) {
                ++expect;
                assert_int_equal(*fqv[j], (*fd[j] > 0) ? RFE_FIX_MAX : RFE_FIX_MIN);
            } else if (fabs(*fd[j]) >= FMAX_N - b) {
                ambiguous = 1;
            } else {
                assert_true(abs(*fqv[j]) < RFE_FIX_MAX);
            }
        }
        if (!ambiguous) {
            assert_int_equal(sat, expect);
        }
        assert_int_equal(sat, n_railed(&fx, 1) + n_railed(&fy, 1));
        n_sat_cases += (sat > 0u) ? 1 : 0;
    }
    printf("saturation: %d of 20000 high-mu, high-load cases clamp at least one force\n",
           n_sat_cases);
    assert_true(n_sat_cases > 1000);
    /* The counter stops at UINT32_MAX. */
    sat = UINT32_MAX - 1u;
    make_sample(0, 10, 0, 0, -127.0, 127.0, om, &uq, &ud);
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &uq, &kq, &sat), RFE_OK);
    assert_int_equal(sat, UINT32_MAX);
    {
        rfe_wheel_kin_q31_t k4;
        rfe_fix_t mu[4], ax4[4], ay4[4];
        size_t i;
        for (i = 0; i < 4; ++i) {
            k4.kappa[i] = toq(-0.2, 30);
            k4.alpha[i] = toq(0.1, 29);
            k4.fz[i] = toq(65000, 15);
            k4.vwx[i] = toq(20, 23);
            mu[i] = toq(3.9, 29);
        }
        sat = 0u;
        assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &k4, mu, ax4, ay4, &sat), RFE_OK);
        assert_int_equal(sat, n_railed(ax4, 4) + n_railed(ay4, 4));
        assert_true(sat >= 4u);
        sat = UINT32_MAX - 2u;
        assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &k4, mu, ax4, ay4, &sat), RFE_OK);
        assert_int_equal(sat, UINT32_MAX);
        sat = UINT32_MAX;
        assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, &k4, ax4, ay4, &sat), RFE_OK);
        assert_int_equal(sat, UINT32_MAX);
    }
}

/* Expected saturation count of outputs q[0..n) (Q15 or Q23 at rail `lim`) against their
 * double values d with error bounds b: an output beyond the range by more than its bound must
 * be clamped and counted, one inside by more than its bound must not; in between (within the
 * bound of the edge) either is correct. Returns the count, or -1 when any is ambiguous, and
 * checks the values. */
static long expected_sat(const int32_t *q, const double *d, const double *b, size_t n,
                         double lim)
{
    long c = 0;
    size_t i;
    for (i = 0; i < n; ++i) {
        if (fabs(d[i]) > lim + b[i]) {
            assert_int_equal(q[i], (d[i] > 0) ? RFE_FIX_MAX : RFE_FIX_MIN);
            ++c;
        } else if (fabs(d[i]) >= lim - b[i]) {
            return -1;
        } else {
            assert_true(q[i] != RFE_FIX_MAX && q[i] != RFE_FIX_MIN);
        }
    }
    return c;
}

/* REQ: every int32 input is in the domain: the extremes of every format run without
 * undefined behaviour (the sanitizer build checks), the clips hold, the results are within
 * the bounds where they fit, and the counter counts exactly the clamped outputs. */
/* REQ-FXP-003 REQ-FXP-008 */
static void test_tyre_q31_int32_extremes(void **state)
{
    static const int32_t ext[5] = {INT32_MIN, -INT32_MAX, -1, 0, INT32_MAX};
    int c, n_exact = 0;
    (void)state;
    for (c = 0; c < 5 * 5 * 5 * 5 * 5; ++c) {
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        rfe_wheel_kin_q31_t kq;
        rfe_wheel_kin_t kd;
        uint32_t sat = 0u;
        double dv[8], bv[8], dz[8];
        int32_t qv[8];
        long e1, e2;
        size_t i;
        uq.delta = ext[c % 5];
        uq.vx = ext[(c / 5) % 5];
        uq.vy = ext[(c / 25) % 5];
        uq.yaw_rate = ext[(c / 125) % 5];
        uq.ax = ext[(c / 625) % 5];
        uq.ay = ext[(c / 5) % 5];
        uq.yaw_acc = 0;
        for (i = 0; i < 4; ++i) {
            uq.omega[i] = ext[(c + (int)i) % 5];
        }
        ud.delta = fromq(uq.delta, 29);
        ud.vx = fromq(uq.vx, 23);
        ud.vy = fromq(uq.vy, 23);
        ud.yaw_rate = fromq(uq.yaw_rate, 27);
        ud.ax = fromq(uq.ax, 24);
        ud.ay = fromq(uq.ay, 24);
        ud.yaw_acc = 0;
        for (i = 0; i < 4; ++i) {
            ud.omega[i] = fromq(uq.omega[i], 22);
        }
        assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &uq, &kq, &sat), RFE_OK);
        assert_int_equal(rfe_tyre_kinematics_f64(&pd.vehicle, &pd.tyre, &ud, &kd), RFE_OK);
        for (i = 0; i < 4; ++i) {
            const kin_bound_t b = kin_bounds(&ud, i, kd.kappa[i]);
            assert_true(fabs(fromq(kq.kappa[i], 30) - kd.kappa[i]) <= b.kappa);
            assert_true(fabs(fromq(kq.alpha[i], 29) - kd.alpha[i]) <= b.alpha);
            assert_true(kq.fz[i] >= 0);
            qv[i] = kq.fz[i];
            dv[i] = kd.fz[i];
            bv[i] = b.fz;
            qv[4 + i] = kq.vwx[i];
            dv[4 + i] = kd.vwx[i];
            bv[4 + i] = b.vwx;
        }
        e1 = expected_sat(qv, dv, bv, 4, FMAX_N);
        e2 = expected_sat(qv + 4, dv + 4, bv + 4, 4, 2147483647.0 / 8388608.0);
        for (i = 0; i < 8; ++i) {
            dz[i] = fabs(fromq(qv[i], (i < 4) ? 15 : 23) - dv[i]);
            if (qv[i] != RFE_FIX_MAX && qv[i] != RFE_FIX_MIN) {
                assert_true(dz[i] <= bv[i]); /* inside the range: the bound holds */
            }
        }
        if (e1 >= 0 && e2 >= 0) {
            assert_int_equal(sat, (uint32_t)(e1 + e2));
            ++n_exact;
        }
        assert_true(sat <= n_railed(qv, 8));
    }
    /* Single wheel: every kappa, alpha, vwx extreme at the largest load, mu extremes. */
    for (c = 0; c < 5 * 5 * 5 * 5; ++c) {
        const int32_t k = ext[c % 5], a = ext[(c / 5) % 5], v = ext[(c / 25) % 5];
        const int32_t m = ext[(c / 125) % 5];
        const double kd1 = fromq(k, 30), ad = fromq(a, 29), vd = fromq(v, 23), md = fromq(m, 29);
        const double fzd = fromq(INT32_MAX, 15);
        uint32_t sat = 0u;
        int32_t q[2];
        double d[2], b[2];
        long e;
        assert_int_equal(rfe_tyre_dugoff_abs_q31(&pq.tyre, k, a, INT32_MAX, v, m, &q[0], &q[1],
                                                 &sat),
                         RFE_OK);
        assert_int_equal(rfe_tyre_dugoff_abs_f64(&pd.tyre, kd1, ad, fzd, vd, md, &d[0], &d[1]),
                         RFE_OK);
        b[0] = dugoff_bound(0, kd1, ad, fzd, vd, md, d[0]);
        b[1] = dugoff_bound(0, kd1, ad, fzd, vd, md, d[1]);
        e = expected_sat(q, d, b, 2, FMAX_N);
        if (e >= 0) {
            assert_int_equal(sat, (uint32_t)e);
            ++n_exact;
        }
        assert_true(sat <= n_railed(q, 2));
        sat = 0u;
        assert_int_equal(rfe_tyre_dugoff_norm_q31(&pq.tyre, k, a, INT32_MAX, v, &q[0], &q[1],
                                                  &sat),
                         RFE_OK);
        assert_int_equal(rfe_tyre_dugoff_norm_f64(&pd.tyre, kd1, ad, fzd, vd, &d[0], &d[1]),
                         RFE_OK);
        b[0] = dugoff_bound(1, kd1, ad, fzd, vd, 1.0, d[0]);
        b[1] = dugoff_bound(1, kd1, ad, fzd, vd, 1.0, d[1]);
        e = expected_sat(q, d, b, 2, FMAX_N);
        if (e >= 0) {
            assert_int_equal(sat, (uint32_t)e);
            ++n_exact;
        }
        assert_true(sat <= n_railed(q, 2));
    }
    printf("int32 extremes: %d cases with an unambiguous expected saturation count, all exact\n",
           n_exact);
    assert_true(n_exact > 3000);
}

/* ---- argument checks ------------------------------------------------------------------------ */

#define SENT ((int32_t)0x5A5A5A5A)

/* REQ: NULL -> RFE_ERR_NULL, invalid tyre parameters -> RFE_ERR_PARAM, fz < 0 ->
 * RFE_ERR_RANGE; outputs and the counter untouched on every error. */
/* REQ-TYRE-006 */
static void test_tyre_q31_argument_checks(void **state)
{
    rfe_sample_q31_t u;
    rfe_wheel_kin_q31_t k, kin_ok;
    rfe_tyre_params_q31_t bad;
    rfe_fix_t a = SENT, b = SENT, fa[4], fb[4], mu[4] = {0, 0, 0, 0};
    uint32_t sat = 9u;
    size_t i;
    (void)state;
    memset(&u, 0, sizeof(u));
    u.vx = toq(10, 23);
    memset(&k, 0x5A, sizeof(k));
    /* kinematics */
    assert_int_equal(rfe_tyre_kinematics_q31(NULL, &pq.tyre, &u, &k, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, NULL, &u, &k, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, NULL, &k, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &u, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &u, &k, NULL), RFE_ERR_NULL);
    bad = pq.tyre;
    bad.v_min = 0;
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &bad, &u, &k, &sat), RFE_ERR_PARAM);
    bad = pq.tyre;
    bad.alpha_max = 0;
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &bad, &u, &k, &sat), RFE_ERR_PARAM);
    bad.alpha_max = RFE_FIX_TAN_LIMIT_Q29;
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &bad, &u, &k, &sat), RFE_ERR_PARAM);
    assert_int_equal(k.kappa[0], SENT);
    assert_int_equal(k.fz[3], SENT);
    assert_int_equal(sat, 9u);
    bad.alpha_max = RFE_FIX_TAN_LIMIT_Q29 - 1; /* the largest valid bound */
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &bad, &u, &k, &sat), RFE_OK);

    /* single wheel */
    assert_int_equal(rfe_tyre_dugoff_norm_q31(NULL, 0, 0, 0, 0, &a, &b, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_dugoff_norm_q31(&pq.tyre, 0, 0, 0, 0, NULL, &b, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_dugoff_norm_q31(&pq.tyre, 0, 0, 0, 0, &a, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_dugoff_norm_q31(&pq.tyre, 0, 0, 0, 0, &a, &b, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_dugoff_abs_q31(NULL, 0, 0, 0, 0, 0, &a, &b, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_dugoff_abs_q31(&pq.tyre, 0, 0, 0, 0, 0, NULL, &b, &sat),
                     RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_dugoff_norm_q31(&pq.tyre, 0, 0, -1, 0, &a, &b, &sat),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_tyre_dugoff_abs_q31(&pq.tyre, 0, 0, INT32_MIN, 0, 0, &a, &b, &sat),
                     RFE_ERR_RANGE);
    bad = pq.tyre;
    bad.eps = -1;
    assert_int_equal(rfe_tyre_dugoff_abs_q31(&bad, 0, 0, 100, 0, 0, &a, &b, &sat),
                     RFE_ERR_PARAM);
    bad = pq.tyre;
    bad.alpha_max = -5;
    assert_int_equal(rfe_tyre_dugoff_norm_q31(&bad, 0, 0, 100, 0, &a, &b, &sat),
                     RFE_ERR_PARAM);
    assert_int_equal(a, SENT);
    assert_int_equal(b, SENT);
    assert_int_equal(sat, 9u);

    /* four wheels: an error in wheel 3 leaves all outputs untouched */
    assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &u, &kin_ok, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        fa[i] = SENT;
        fb[i] = SENT;
    }
    k = kin_ok;
    k.fz[3] = -1;
    assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, &k, fa, fb, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &k, mu, fa, fb, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_tyre_forces_norm_q31(NULL, &kin_ok, fa, fb, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs_q31(NULL, &kin_ok, mu, fa, fb, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, NULL, fa, fb, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, &kin_ok, NULL, fb, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, &kin_ok, fa, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, &kin_ok, fa, fb, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, NULL, mu, fa, fb, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &kin_ok, NULL, fa, fb, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &kin_ok, mu, NULL, fb, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &kin_ok, mu, fa, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &kin_ok, mu, fa, fb, NULL), RFE_ERR_NULL);
    for (i = 0; i < 4; ++i) {
        assert_int_equal(fa[i], SENT);
        assert_int_equal(fb[i], SENT);
    }
    assert_int_equal(sat, 9u);
    /* and the four-wheel functions equal the single-wheel ones bit for bit */
    assert_int_equal(rfe_tyre_forces_norm_q31(&pq.tyre, &kin_ok, fa, fb, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        assert_int_equal(rfe_tyre_dugoff_norm_q31(&pq.tyre, kin_ok.kappa[i], kin_ok.alpha[i],
                                                  kin_ok.fz[i], kin_ok.vwx[i], &a, &b, &sat),
                         RFE_OK);
        assert_int_equal(a, fa[i]);
        assert_int_equal(b, fb[i]);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tyre_q31_kinematics_edges),
        cmocka_unit_test(test_tyre_q31_dugoff_random_and_edges),
        cmocka_unit_test(test_tyre_q31_random),
        cmocka_unit_test(test_tyre_q31_scenarios),
        cmocka_unit_test(test_tyre_q31_deterministic),
        cmocka_unit_test(test_tyre_q31_saturation),
        cmocka_unit_test(test_tyre_q31_int32_extremes),
        cmocka_unit_test(test_tyre_q31_argument_checks),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
