/**
 * @file test_meas_q31.c
 * @brief The fixed-point measurement model (rfe/component/meas_q31.h) back to back against the double
 *        twin (rfe/component/meas.h, _f64): paper mode h = H(u) mu, absolute mode and magic mode per
 *        friction value, on every sample of every bundled log (at the log's true mu, and in
 *        the load-scaled modes on a mu grid 0, 0.1, ..., 1.2) and on 1e5 random samples over
 *        the input limits; in magic mode also bit for bit against the uncached public chain
 *        (forces, H, H ones); determinism, saturation counting, argument checks. Also the
 *        cached terms (rfe_meas_setup_q31, rfe_meas_nominal_q31) bit for bit against that
 *        chain with the same count, per wheel and summed, for tyre parameters other than the
 *        set-up's too (random integer samples and tyres from test_draws_q31.h, including the
 *        int32 extremes), invalid tyres at set-up and eval, and rfe_fix_div's saturation.
 *
 * Setup: q31 with the converted presets (paper preset for paper mode, default preset with the
 * tyre mode set to absolute for absolute mode, the default preset for magic mode), double with
 * the original ones (magic mode: with the q31 tyre values converted exactly, so the shape
 * factors' rounding does not enter); the same inputs (Q values converted exactly).
 *
 * Bound (composed from the derived bounds of the parts, test_tyre_q31.c and
 * test_obsmat_q31.c, whose derivations are not repeated here). Per wheel i, evaluated at the
 * double kinematics (kappa, alpha, Fz, vwx) with the double force F:
 *  - force error dF_i <= B_dugoff + L_k dkappa + L_a dalpha + mu_e dFz + L_v dvwx, with the
 *    kinematics bounds dkappa, dalpha, dFz, dvwx and the Lipschitz constants of the Dugoff
 *    force (G = 2 + mu_e / C1, t = tan alpha, v = |vwx|; derivation as for the tan bound of
 *    test_tyre_q31.c, with d/dkappa of g = mu E / S - mu^2 (1-|k|) E^2 / (4 S^2)):
 *      L_k = Fz (2 C1 G + 0.75 mu_e G + mu_e eps v),  L_a = Fz (2 C2 G + mu_e eps v)(1 + t^2),
 *      L_v = Fz mu_e eps sqrt(k^2 + t^2),  d|F|/dFz <= mu_e;
 *  - its effect on H's column: (dFx_i + dFy_i) / m (rows 1-2), (|x_i| + |y_i|) / J (row 3);
 *  - plus H's own bound (obsmat) for the double forces.
 * Magic mode: the force bound of test_tyre_magic_q31.c (against the exact tangent), and its
 * Lipschitz constants (derived there: every entry of the Jacobian in (cx k, cy t) is at most
 * Fz K_E, K_E = 1 for E >= -1): L_k = Fz K_E cx, L_a = Fz K_E cy (1 + t^2), d|F|/dFz <= mu_e,
 * nothing through vwx (the curve does not use it).
 * Paper mode: |dz_r| <= 0.5 LSB24 + sum_i |mu_i| dH_ri. Load-scaled modes (z_r = row sum of
 * the H of the forces): |dz_r| <= 0.5 LSB24 + sum_i dH_ri. The first-order terms are
 * evaluated at the double values; the factor 1.001 covers the change of the constants over
 * the error interval (t and Fz move by < 1e-6 relative).
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
#include "rfe/component/meas.h"
#include "rfe/component/meas_q31.h"
#include "rfe/component/fxmath.h"
#include "rfe/component/params_conv.h"
#include "models/tyre_internal_q31.h"
#include "test_draws_q31.h"
#include "q31_trig_bounds.h"
#include "test_rng.h"

#define TRIG Q31B_TRIG
#define ATAN2 Q31B_ATAN2
#define TAN(a) q31b_tan(a)
#define LSB(q) ldexp(1.0, -(q))
#define N_RANDOM 100000
#define N_COLUMN_CASES 20000 /* per-wheel column cases */

static const char *const SCENARIO[19] = {
    "accel_low_mu",       "brake_in_turn",      "cruise",          "hard_brake_high_mu",
    "hard_brake_low_mu",  "mu_step_hard_brake", "paper_high_mu_brake", "paper_low_mu_brake",
    "paper_mu_step",      "sine_steer_high_mu", "sine_steer_low_mu", "split_mu_brake",
    "split_mu_hard_brake",
    /* issue 17 */
    "double_lane_change_high_mu", "double_lane_change_low_mu", "ramp_steer_high_mu",
    "ramp_steer_low_mu", "brake_in_turn_low_mu", "wrong_tyre_data"};
static const char *const VARIANT[3] = {"", ".mf", ".nf"};

static rfe_params_t pd, pd_pap, pd_mag;     /* default (absolute mode), paper, default (magic) */
static rfe_params_q31_t pq, pq_pap, pq_mag;

/* ---- worst cases -------------------------------------------------------------------------- */

typedef struct {
    const char *name;
    double max_abs, max_rel, max_ratio;
    long n;
} worst_t;

static worst_t w_paper = {"z paper", 0, 0, 0, 0};
static worst_t w_abs = {"z absolute", 0, 0, 0, 0};
static worst_t w_mag = {"z magic", 0, 0, 0, 0};

static void reset(worst_t *w) { w->max_abs = w->max_rel = w->max_ratio = 0.0, w->n = 0; }

static void track(worst_t *w, double got, double want, double bound, const char *ctx)
{
    const double err = fabs(got - want);
    w->max_abs = fmax(w->max_abs, err);
    if (fabs(want) >= 0.1) {
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
    printf("  %-10s n=%-8ld max |err| %.3e (%.3f LSB24)  max rel %.3e (|ref| >= 0.1)  max "
           "err/bound %.3f\n",
           w->name, w->n, w->max_abs, w->max_abs / LSB(24), w->max_rel, w->max_ratio);
}

static int32_t toq(double x, int q)
{
    uint32_t s = 0u;
    return rfe_fix_from_double(x, (unsigned)q, &s);
}
static double fromq(int32_t v, int q) { return rfe_fix_to_double(v, (unsigned)q); }

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
    if (rfe_params_default_f64(&pd_mag) != RFE_OK || rfe_params_to_q31_f64(&pd_mag, &pq_mag) != RFE_OK ||
        pq_mag.tyre.mode != RFE_TYRE_MAGIC) {
        return -1;
    }
    /* the magic twin gets the q31 tyre values (exact in double) */
    pd_mag.tyre.cx = fromq(pq_mag.tyre.cx, 24);
    pd_mag.tyre.cy = fromq(pq_mag.tyre.cy, 24);
    pd_mag.tyre.alpha_max = fromq(pq_mag.tyre.alpha_max, 29);
    pd_mag.tyre.shape_Cx = fromq(pq_mag.tyre.shape_Cx, 24);
    pd_mag.tyre.shape_Ex = fromq(pq_mag.tyre.shape_Ex, 24);
    pd_mag.tyre.shape_Cy = fromq(pq_mag.tyre.shape_Cy, 24);
    pd_mag.tyre.shape_Ey = fromq(pq_mag.tyre.shape_Ey, 24);
    if (rfe_params_default_f64(&pd) != RFE_OK) {
        return -1;
    }
    pd.tyre.mode = RFE_TYRE_ABSOLUTE; /* the Dugoff comparisons */
    return (rfe_params_paper_f64(&pd_pap) == RFE_OK && rfe_params_to_q31_f64(&pd, &pq) == RFE_OK &&
            rfe_params_to_q31_f64(&pd_pap, &pq_pap) == RFE_OK)
               ? 0
               : -1;
}

/* ---- the parts' bounds (as derived in test_tyre_q31.c and test_obsmat_q31.c) ------------- */

typedef struct {
    double vwx, alpha, kappa, fz;
} kin_bound_t;

static kin_bound_t kin_bounds(const rfe_sample_t *u, size_t i, double kappa_d)
{
    const rfe_vehicle_t *v = &pd.vehicle;
    const double px[4] = {v->Lf, v->Lf, -v->Lr, -v->Lr};
    const double py[4] = {v->Bf / 2, -v->Bf / 2, v->Br / 2, -v->Br / 2};
    const double qx[4] = {fromq(pq.vehicle.Lf, 29), fromq(pq.vehicle.Lf, 29),
                          -fromq(pq.vehicle.Lr, 29), -fromq(pq.vehicle.Lr, 29)};
    const double qy[4] = {fromq(pq.vehicle.yf, 29), -fromq(pq.vehicle.yf, 29),
                          fromq(pq.vehicle.yr, 29), -fromq(pq.vehicle.yr, 29)};
    const double d = (i < 2) ? u->delta : 0.0;
    const double vbx = u->vx - u->yaw_rate * py[i];
    const double vby = u->vy + u->yaw_rate * px[i];
    const double vwx = vbx * cos(d) + vby * sin(d);
    const double vwy = -vbx * sin(d) + vby * cos(d);
    const double vr = u->omega[i] * v->R;
    const double den = fmax(fmax(fabs(vr), fabs(vwx)), pd.tyre.v_min);
    const double dpos =
        fabs(u->yaw_rate) * (fabs(qx[i] - px[i]) + fabs(qy[i] - py[i])) + ldexp(1.0, -50);
    const double dtrig = (i < 2) ? TRIG * (fabs(vbx) + fabs(vby)) : 0.0;
    const double vw = hypot(vwx, vwy);
    const double La = v->Lf + v->Lr;
    const double mg = v->m * v->g, mh = v->m * v->hg;
    const double dfs = (i < 2) ? fabs(fromq(pq.vehicle.fz_static_f, 15) - mg * v->Lr / (2 * La))
                               : fabs(fromq(pq.vehicle.fz_static_r, 15) - mg * v->Lf / (2 * La));
    const double dkp = fabs(fromq(pq.vehicle.k_pitch, 20) - mh / (2 * La));
    const double dkr = (i < 2) ? fabs(fromq(pq.vehicle.k_roll_f, 20) - mh * v->Lr / (La * v->Bf))
                               : fabs(fromq(pq.vehicle.k_roll_r, 20) - mh * v->Lf / (La * v->Br));
    const double dR = fabs(fromq(pq.vehicle.R, 29) - v->R);
    const double dvmin = fabs(fromq(pq.tyre.v_min, 23) - pd.tyre.v_min);
    const double damax = fabs(fromq(pq.tyre.alpha_max, 29) - pd.tyre.alpha_max);
    kin_bound_t b;
    b.vwx = 0.5 * LSB(23) + dtrig + dpos + 1e-15 * (fabs(vbx) + fabs(vby));
    b.alpha = ATAN2 + 0.71 * LSB(29) + ((i < 2) ? sqrt(2.0) * TRIG : 0.0) + damax +
              ((vw > 0.0) ? dpos / vw : 0.0) + 1e-15;
    b.kappa = (1.0 + fabs(kappa_d)) * (fabs(u->omega[i]) * dR + dtrig + dpos + dvmin) / den +
              3.0 * LSB(30);
    b.fz = 0.5 * LSB(15) + ldexp(1.0, -43) + dfs + fabs(u->ax) * dkp + fabs(u->ay) * dkr +
           1e-12 * 1e4;
    return b;
}

/* Dugoff force bound for the same inputs (both modes share the tyre parameters' values). */
static double dugoff_bound(int paper, double kappa, double alpha, double fz, double vwx,
                           double mu, double F)
{
    const rfe_tyre_params_t *t = &pd.tyre;
    const double C1 = paper ? t->Cx_n : t->cx;
    const double C2 = paper ? t->Cy_n : t->cy;
    const double dC1 = fabs(fromq(paper ? pq.tyre.Cx_n : pq.tyre.cx, 24) - C1);
    const double dC2 = fabs(fromq(paper ? pq.tyre.Cy_n : pq.tyre.cy, 24) - C2);
    const double deps = fabs(fromq(pq.tyre.eps, 32) - t->eps);
    const double damax = fabs(fromq(pq.tyre.alpha_max, 29) - t->alpha_max);
    const double mue = paper ? 1.0 : fmax(mu, 0.0);
    const double amax = fmin(t->alpha_max, fromq(pq.tyre.alpha_max, 29));
    const double ac = fmin(fmax(alpha, -t->alpha_max), t->alpha_max);
    const double k = fmin(fmax(kappa, -1.0), 1.0);
    const double tn = tan(ac);
    const double slip = hypot(k, tn);
    const double v = fabs(vwx);
    const double P = t->eps * v * slip;
    const double dE = (P < 2.0) ? deps * v * slip : 0.0;
    const double G = 2.0 + mue / C1;
    double dt = TAN(ac);
    if (fabs(alpha) >= amax - LSB(29)) {
        dt += (1.0 + tn * tn) * damax;
    }
    return 0.5 * LSB(15) + (2.0 * (dC1 / C1 + dC2 / C2) + 1e-12) * fabs(F) +
           fz * ((12.5 * mue + 1.0) * ldexp(1.0, -30) + 1.5 * mue * dE +
                 (2.0 * C2 * G + mue * t->eps * v) * dt);
}

/* Bound of each force component of wheel i through the kinematics (see the file comment). */
static double force_bound(int paper, const rfe_sample_t *u, const rfe_wheel_kin_t *kd, size_t i,
                          double mu, double F)
{
    const rfe_tyre_params_t *t = &pd.tyre;
    const kin_bound_t kb = kin_bounds(u, i, kd->kappa[i]);
    const double C1 = paper ? t->Cx_n : t->cx;
    const double C2 = paper ? t->Cy_n : t->cy;
    const double mue = paper ? 1.0 : fmax(mu, 0.0);
    const double G = 2.0 + mue / C1;
    const double fz = kd->fz[i] + kb.fz;
    const double v = fabs(kd->vwx[i]) + kb.vwx;
    const double k = fmin(fmax(kd->kappa[i], -1.0), 1.0);
    const double tn = tan(fmin(fabs(kd->alpha[i]) + kb.alpha, t->alpha_max));
    const double Lk = fz * (2.0 * C1 * G + 0.75 * mue * G + mue * t->eps * v);
    const double La = fz * (2.0 * C2 * G + mue * t->eps * v) * (1.0 + tn * tn);
    const double Lv = fz * mue * t->eps * hypot(k, tn);
    return dugoff_bound(paper, kd->kappa[i], kd->alpha[i], fz, kd->vwx[i], mu, F) +
           1.001 * (Lk * kb.kappa + La * kb.alpha + mue * kb.fz + Lv * kb.vwx);
}

/* Magic Formula force bound (test_tyre_magic_q31.c: against the exact tangent, no parameter
 * rounding) through the kinematics' errors, for the magic tyre of pd_mag (E_x, E_y >= -1, so
 * K_E = 1; the default's E = 0 also gives K_b = 1). */
static double magic_force_bound(const rfe_sample_t *u, const rfe_wheel_kin_t *kd, size_t i,
                                double mu, int d)
{
    const rfe_tyre_params_t *t = &pd_mag.tyre;
    const double U = ldexp(1.0, -29);
    const kin_bound_t kb = kin_bounds(u, i, kd->kappa[i]);
    const double C = d ? t->shape_Cy : t->shape_Cx, E = d ? t->shape_Ey : t->shape_Ex;
    const double Kb = (E < 0.0) ? 1.0 - E : 1.0 / (1.0 - E);
    const double m = fmax(mu, 0.0);
    const double fz = kd->fz[i] + kb.fz;
    const double tn = tan(fmin(fabs(kd->alpha[i]) + kb.alpha, t->alpha_max));
    const double eb = Kb * 0.71 * U + 0.505 * U + ((E != 0.0) ? (fabs(E) * 0.505 + 1.21) * U : 0.0);
    const double eG = C * eb + 0.7525 * U;
    const double B = 0.5 * LSB(15) + fz * t->cy * TAN(atan(tn)) + fz * (1.0 + LSB(30)) * (m * eG + 0.5 * U) +
                     fz * (m * (0.88 * C * Kb + 3.75) * U + 10.0 * LSB(50)) + 1e-14 * fz * m;
    return B + 1.001 * (fz * t->cx * kb.kappa + fz * t->cy * (1.0 + tn * tn) * kb.alpha + m * kb.fz);
}

/* Bounds of H's entries from the double forces fx, fy and their error bounds dfx, dfy. */
static void h_bounds(double delta, const double fx[4], const double fy[4], const double dfx[4],
                     const double dfy[4], double b[12])
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
        const double ax = fabs(fx[i]) + dfx[i], ay = fabs(fy[i]) + dfy[i];
        const double fbx = fabs(fx[i] * cos(d) - fy[i] * sin(d)) + dfx[i] + dfy[i];
        const double fby = fabs(fx[i] * sin(d) + fy[i] * cos(d)) + dfx[i] + dfy[i];
        const double dfb = ((i < 2) ? TRIG * (ax + ay) : 0.0) + dfx[i] + dfy[i];
        const double rel = 1e-15 * (ax + ay);
        b[i] = 0.5 * LSB(24) + dfb / v->m + fbx * dinv + rel;
        b[4 + i] = 0.5 * LSB(24) + dfb / v->m + fby * dinv + rel;
        b[8 + i] = 0.5 * LSB(24) + LSB(30) + (fabs(px[i]) + fabs(py[i])) * dfb / v->J +
                   fby * fabs(pxJ[i] - px[i] / v->J) + fbx * fabs(pyJ[i] - py[i] / v->J) + rel;
    }
}

/* ---- the back-to-back check of one sample ------------------------------------------------- */

/* Paper mode at mu and absolute mode at mu and at every mu_grid value (all wheels). */
static void check_sample(const rfe_sample_q31_t *uq, const rfe_sample_t *ud, const double mu[4],
                         int grid, const char *ctx)
{
    rfe_meas_q31_t hq;
    rfe_meas_t hd;
    rfe_wheel_kin_t kd;
    uint32_t sat = 0u;
    double f0x[4], f0y[4], df0x[4], df0y[4], b[12], zd[3];
    rfe_fix_t zq[3], muq[4];
    double mud[4];
    char what[300];
    size_t i, r;
    int g;

    for (i = 0; i < 4; ++i) {
        muq[i] = toq(mu[i], 29);
        mud[i] = fromq(muq[i], 29);
    }
    /* paper mode */
    assert_int_equal(rfe_meas_setup_q31(&hq, &pq_pap.vehicle, &pq_pap.tyre, uq, &sat), RFE_OK);
    assert_int_equal(rfe_meas_setup_f64(&hd, &pd_pap.vehicle, &pd_pap.tyre, ud), RFE_OK);
    assert_int_equal(rfe_meas_eval_q31(&hq, &pq_pap.vehicle, &pq_pap.tyre, muq, zq, &sat), RFE_OK);
    assert_int_equal(rfe_meas_eval_f64(&hd, &pd_pap.vehicle, &pd_pap.tyre, mud, zd), RFE_OK);
    assert_int_equal(sat, 0u);
    kd = hd.kin;
    assert_int_equal(rfe_tyre_forces_norm_f64(&pd_pap.tyre, &kd, f0x, f0y), RFE_OK);
    for (i = 0; i < 4; ++i) {
        df0x[i] = force_bound(1, ud, &kd, i, 1.0, f0x[i]);
        df0y[i] = force_bound(1, ud, &kd, i, 1.0, f0y[i]);
    }
    h_bounds(ud->delta, f0x, f0y, df0x, df0y, b);
    for (r = 0; r < 3; ++r) {
        double bound = 0.5 * LSB(24) + 1e-15 * fabs(zd[r]);
        for (i = 0; i < 4; ++i) {
            bound += fabs(mud[i]) * b[4 * r + i];
        }
        snprintf(what, sizeof(what), "%s paper row %zu", ctx, r);
        track(&w_paper, fromq(zq[r], 24), zd[r], bound, what);
    }
    /* absolute mode */
    assert_int_equal(rfe_meas_setup_q31(&hq, &pq.vehicle, &pq.tyre, uq, &sat), RFE_OK);
    assert_int_equal(rfe_meas_setup_f64(&hd, &pd.vehicle, &pd.tyre, ud), RFE_OK);
    for (g = -1; g < (grid ? 13 : 0); ++g) {
        double m[4], fx[4], fy[4], dfx[4], dfy[4];
        rfe_fix_t mq[4];
        for (i = 0; i < 4; ++i) {
            mq[i] = (g < 0) ? muq[i] : toq(0.1 * g, 29);
            m[i] = fromq(mq[i], 29);
        }
        assert_int_equal(rfe_meas_eval_q31(&hq, &pq.vehicle, &pq.tyre, mq, zq, &sat), RFE_OK);
        assert_int_equal(rfe_meas_eval_f64(&hd, &pd.vehicle, &pd.tyre, m, zd), RFE_OK);
        assert_int_equal(sat, 0u);
        assert_int_equal(rfe_tyre_forces_abs_f64(&pd.tyre, &kd, m, fx, fy), RFE_OK);
        for (i = 0; i < 4; ++i) {
            dfx[i] = force_bound(0, ud, &kd, i, m[i], fx[i]);
            dfy[i] = force_bound(0, ud, &kd, i, m[i], fy[i]);
        }
        h_bounds(ud->delta, fx, fy, dfx, dfy, b);
        for (r = 0; r < 3; ++r) {
            double bound = 0.5 * LSB(24) + 1e-15 * fabs(zd[r]);
            for (i = 0; i < 4; ++i) {
                bound += b[4 * r + i];
            }
            snprintf(what, sizeof(what), "%s absolute mu %s row %zu", ctx,
                     (g < 0) ? "truth" : "grid", r);
            track(&w_abs, fromq(zq[r], 24), zd[r], bound, what);
        }
    }
    /* magic mode: against the double twin, and bit for bit against the uncached chain */
    assert_int_equal(rfe_meas_setup_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, uq, &sat), RFE_OK);
    assert_int_equal(rfe_meas_setup_f64(&hd, &pd_mag.vehicle, &pd_mag.tyre, ud), RFE_OK);
    kd = hd.kin;
    for (g = -1; g < (grid ? 13 : 0); ++g) {
        static const rfe_fix_t ones[4] = {1 << 29, 1 << 29, 1 << 29, 1 << 29};
        double m[4], fx[4], fy[4], dfx[4], dfy[4];
        rfe_fix_t mq[4], cfx[4], cfy[4], Hc[12], zc[3];
        uint32_t csat = 0u;
        for (i = 0; i < 4; ++i) {
            mq[i] = (g < 0) ? muq[i] : toq(0.1 * g, 29);
            m[i] = fromq(mq[i], 29);
        }
        assert_int_equal(rfe_meas_eval_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, mq, zq, &sat),
                         RFE_OK);
        assert_int_equal(rfe_meas_eval_f64(&hd, &pd_mag.vehicle, &pd_mag.tyre, m, zd), RFE_OK);
        assert_int_equal(sat, 0u);
        assert_int_equal(rfe_tyre_forces_abs_q31(&pq_mag.tyre, &hq.kin, mq, cfx, cfy, &csat), RFE_OK);
        assert_int_equal(rfe_obsmat_build_q31(&pq_mag.vehicle, hq.delta, cfx, cfy, Hc, &csat), RFE_OK);
        assert_int_equal(rfe_obsmat_apply_q31(Hc, ones, zc, &csat), RFE_OK);
        assert_memory_equal(zq, zc, sizeof(zc));
        assert_int_equal(csat, 0u);
        assert_int_equal(rfe_tyre_forces_abs_f64(&pd_mag.tyre, &kd, m, fx, fy), RFE_OK);
        for (i = 0; i < 4; ++i) {
            dfx[i] = magic_force_bound(ud, &kd, i, m[i], 0);
            dfy[i] = magic_force_bound(ud, &kd, i, m[i], 1);
        }
        h_bounds(ud->delta, fx, fy, dfx, dfy, b);
        for (r = 0; r < 3; ++r) {
            double bound = 0.5 * LSB(24) + 1e-15 * fabs(zd[r]);
            for (i = 0; i < 4; ++i) {
                bound += b[4 * r + i];
            }
            snprintf(what, sizeof(what), "%s magic mu %s row %zu", ctx,
                     (g < 0) ? "truth" : "grid", r);
            track(&w_mag, fromq(zq[r], 24), zd[r], bound, what);
        }
    }
}

/* REQ: every sample of every bundled log (19 scenarios x 3 truth variants): paper mode at the
 * true mu, absolute and magic mode at the true mu and on the grid mu = 0, 0.1, ..., 1.2,
 * within the composed bounds; magic mode bit for bit the uncached chain. */
/* REQ-FXP-003 REQ-MEAS-001 */
static void test_meas_q31_scenarios(void **state)
{
    size_t s, v, r, n = 0;
    (void)state;
    reset(&w_paper);
    reset(&w_abs);
    reset(&w_mag);
    for (s = 0; s < 19; ++s) {
        /* light mode (valgrind): the noisy variant only */
        for (v = 0; v < 3; v += rfe_test_stride(3u)) {
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
                make_sample(row->delta, row->vx, row->vy, row->yaw_rate, row->ax, row->ay,
                            row->omega, &uq, &ud);
                snprintf(ctx, sizeof(ctx), "%s row %zu", path, r);
                check_sample(&uq, &ud, row->mu_true, 1, ctx);
                ++n;
            }
            rfe_sensor_log_free(&log);
        }
    }
    printf("scenario samples: %zu (57 logs; load-scaled modes at the true mu and 13 grid values)\n",
           n);
    report(&w_paper);
    report(&w_abs);
    report(&w_mag);
}

static double uni(double a, double b) { return a + (b - a) * 0.5 * (rng_uniform() + 1.0); }

/* REQ: 1e5 random samples over the input limits (config.h; uniform and near-rolling), random
 * mu in [-0.5, 1.5] per wheel: within the composed bounds (paper, absolute, magic mode). */
/* REQ-FXP-003 REQ-MEAS-001 */
static void test_meas_q31_random(void **state)
{
    int n;
    char ctx[64];
    (void)state;
    reset(&w_paper);
    reset(&w_abs);
    reset(&w_mag);
    rng_seed(0x3EA5ull);
    for (n = 0; n < N_RANDOM; n += (int)rfe_test_stride(10u)) {
        double om[4], mu[4];
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        size_t i;
        if (n % 2) {
            const double vx = uni(0, 60);
            for (i = 0; i < 4; ++i) {
                om[i] = vx * (1.0 + uni(-0.3, 0.1)) / pd.vehicle.R;
            }
            make_sample(uni(-0.3, 0.3), vx, uni(-2, 2), uni(-1, 1), uni(-10, 10), uni(-10, 10),
                        om, &uq, &ud);
        } else {
            for (i = 0; i < 4; ++i) {
                om[i] = uni(-RFE_LIMIT_OMEGA, RFE_LIMIT_OMEGA);
            }
            make_sample(uni(-RFE_LIMIT_DELTA, RFE_LIMIT_DELTA), uni(-RFE_LIMIT_VX, RFE_LIMIT_VX),
                        uni(-RFE_LIMIT_VY, RFE_LIMIT_VY),
                        uni(-RFE_LIMIT_YAW_RATE, RFE_LIMIT_YAW_RATE),
                        uni(-RFE_LIMIT_ACC, RFE_LIMIT_ACC), uni(-RFE_LIMIT_ACC, RFE_LIMIT_ACC), om,
                        &uq, &ud);
        }
        for (i = 0; i < 4; ++i) {
            mu[i] = uni(-0.5, 1.5);
        }
        snprintf(ctx, sizeof(ctx), "random %d", n);
        check_sample(&uq, &ud, mu, 0, ctx);
    }
    printf("random samples: %d\n", N_RANDOM);
    report(&w_paper);
    report(&w_abs);
    report(&w_mag);
}

/* REQ: identical inputs give identical outputs (model and predictions). */
/* REQ-FXP-007 */
static void test_meas_q31_deterministic(void **state)
{
    int n;
    (void)state;
    rng_seed(11u);
    for (n = 0; n < 1000; ++n) {
        double om[4];
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        rfe_meas_q31_t h1, h2;
        rfe_fix_t mu[4], z1[3], z2[3];
        uint32_t s1 = 0u, s2 = 0u;
        size_t i;
        for (i = 0; i < 4; ++i) {
            om[i] = uni(-RFE_LIMIT_OMEGA, RFE_LIMIT_OMEGA);
            mu[i] = toq(uni(-1, 3.9), 29);
        }
        make_sample(uni(-1, 1), uni(-100, 100), uni(-50, 50), uni(-10, 10), uni(-50, 50),
                    uni(-50, 50), om, &uq, &ud);
        const rfe_tyre_params_q31_t *tp =
            ((n % 3) == 0) ? &pq_pap.tyre : (((n % 3) == 1) ? &pq.tyre : &pq_mag.tyre);
        memset(&h1, 0x11, sizeof(h1));
        memset(&h2, 0x22, sizeof(h2));
        assert_int_equal(rfe_meas_setup_q31(&h1, &pq.vehicle, tp, &uq, &s1), RFE_OK);
        assert_int_equal(rfe_meas_setup_q31(&h2, &pq.vehicle, tp, &uq, &s2), RFE_OK);
        assert_memory_equal(&h1, &h2, sizeof(h1));
        assert_int_equal(rfe_meas_eval_q31(&h1, &pq.vehicle, tp, mu, z1, &s1), RFE_OK);
        assert_int_equal(rfe_meas_eval_q31(&h2, &pq.vehicle, tp, mu, z2, &s2), RFE_OK);
        assert_memory_equal(z1, z2, sizeof(z1));
        assert_int_equal(s1, s2);
    }
}

/* The load-scaled chain of the public functions (forces, H, H ones) at tyre parameters tp (the
 * curve of tp's mode), i.e. rfe_meas_eval_q31 step by step: z, each step's count in part, and
 * their total. */
static uint32_t chain(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                      const rfe_tyre_params_q31_t *tp, const rfe_fix_t mu[4], rfe_fix_t z[3],
                      uint32_t part[3])
{
    static const rfe_fix_t ones[4] = {1 << 29, 1 << 29, 1 << 29, 1 << 29};
    rfe_fix_t fx[4], fy[4], Hf[12];
    part[0] = part[1] = part[2] = 0u;
    assert_int_equal(rfe_tyre_forces_abs_q31(tp, &h->kin, mu, fx, fy, &part[0]), RFE_OK);
    assert_int_equal(rfe_obsmat_build_q31(veh, h->delta, fx, fy, Hf, &part[1]), RFE_OK);
    assert_int_equal(rfe_obsmat_apply_q31(Hf, ones, z, &part[2]), RFE_OK);
    return part[0] + part[1] + part[2];
}

/* REQ: saturation anywhere in the chain is counted, exactly once per clamped value: a light,
 * tall vehicle (m = 200 kg, J = 300 kg m^2, hg = 2.5 m) braking with locked wheels at
 * 1 m/s with ax = -80, ay = 80 m/s^2 at the input puts 20.6 kN on the front-right wheel; at
 * mu = 1 its force (20.3 kN, 101 m/s^2) fits everywhere, at mu = 3.9 it (~79 kN) clamps,
 * then H's entries (> 128 m/s^2) and z. The counts of
 * setup and eval equal the sums of their steps' counts, every step's count equals its number
 * of clamped outputs; at mu = 1 nothing clamps; the counter stops at UINT32_MAX. */
/* REQ-FXP-008 */
static void test_meas_q31_saturation(void **state)
{
    rfe_params_t lp = pd;
    rfe_params_q31_t lq, lq_pap;
    rfe_meas_q31_t h;
    rfe_sample_q31_t uq;
    rfe_sample_t ud;
    rfe_fix_t mu[4], z[3], zc[3];
    const double om[4] = {0, 0, 0, 0};
    uint32_t sat = 0u, part[3];
    size_t i;
    (void)state;
    lp.vehicle.m = 200.0;
    lp.vehicle.J = 300.0;
    lp.vehicle.hg = 2.5;
    assert_int_equal(rfe_params_to_q31_f64(&lp, &lq), RFE_OK);
    lp.tyre.mode = RFE_TYRE_PAPER;
    assert_int_equal(rfe_params_to_q31_f64(&lp, &lq_pap), RFE_OK);
    make_sample(0, 1.0, 0, 0, -80.0, 80.0, om, &uq, &ud);
    assert_int_equal(rfe_meas_setup_q31(&h, &lq.vehicle, &lq.tyre, &uq, &sat), RFE_OK);
    assert_int_equal(sat, 0u); /* the loads fit (fz_fr = 20.6 kN) */
    for (i = 0; i < 4; ++i) {
        mu[i] = toq(1.0, 29);
    }
    assert_int_equal(rfe_meas_eval_q31(&h, &lq.vehicle, &lq.tyre, mu, z, &sat), RFE_OK);
    assert_int_equal(sat, 0u);
    assert_int_equal(chain(&h, &lq.vehicle, &lq.tyre, mu, zc, part), 0u);
    for (i = 0; i < 4; ++i) {
        mu[i] = toq(3.9, 29);
    }
    assert_int_equal(rfe_meas_eval_q31(&h, &lq.vehicle, &lq.tyre, mu, z, &sat), RFE_OK);
    assert_int_equal(sat, chain(&h, &lq.vehicle, &lq.tyre, mu, zc, part));
    assert_memory_equal(z, zc, sizeof(z));
    printf("absolute mode, light tall vehicle, mu 3.9: counts forces %u, H %u, z %u; z = [%g, "
           "%g, %g]\n",
           part[0], part[1], part[2], fromq(z[0], 24), fromq(z[1], 24), fromq(z[2], 24));
    assert_true(part[0] >= 1u && part[1] >= 1u && part[2] >= 1u);
    assert_int_equal(z[0], RFE_FIX_MIN); /* the deceleration clamps at -128 m/s^2 */
    {
        /* each step's count is its number of clamped outputs */
        rfe_fix_t fx[4], fy[4], Hf[12];
        uint32_t c = 0u, railed = 0u;
        assert_int_equal(rfe_tyre_forces_abs_q31(&lq.tyre, &h.kin, mu, fx, fy, &c), RFE_OK);
        for (i = 0; i < 4; ++i) {
            railed += (abs(fx[i]) == INT32_MAX) + (abs(fy[i]) == INT32_MAX);
        }
        assert_int_equal(c, railed);
        c = 0u;
        railed = 0u;
        assert_int_equal(rfe_obsmat_build_q31(&lq.vehicle, h.delta, fx, fy, Hf, &c), RFE_OK);
        for (i = 0; i < 12; ++i) {
            railed += (abs(Hf[i]) == INT32_MAX);
        }
        assert_int_equal(c, railed);
        railed = 0u;
        for (i = 0; i < 3; ++i) {
            railed += (abs(z[i]) == INT32_MAX);
        }
        assert_int_equal(part[2], railed);
    }
    /* paper mode: at ax = -127, ay = 127 the front-right load is 32.4 kN and F0x ~ -Fz, so
     * H(1, fr) ~ -160 m/s^2 clamps; setup counts the clamped H entries */
    make_sample(0, 1.0, 0, 0, -127.0, 127.0, om, &uq, &ud);
    {
        rfe_wheel_kin_q31_t kin;
        rfe_fix_t f0x[4], f0y[4], H[12];
        uint32_t c = 0u, railed = 0u;
        sat = 0u;
        assert_int_equal(rfe_meas_setup_q31(&h, &lq_pap.vehicle, &lq_pap.tyre, &uq, &sat), RFE_OK);
        assert_int_equal(rfe_tyre_kinematics_q31(&lq_pap.vehicle, &lq_pap.tyre, &uq, &kin, &c),
                         RFE_OK);
        assert_int_equal(rfe_tyre_forces_norm_q31(&lq_pap.tyre, &kin, f0x, f0y, &c), RFE_OK);
        assert_int_equal(rfe_obsmat_build_q31(&lq_pap.vehicle, uq.delta, f0x, f0y, H, &c), RFE_OK);
        assert_int_equal(sat, c);
        assert_memory_equal(h.H, H, sizeof(H));
        for (i = 0; i < 12; ++i) {
            railed += (abs(H[i]) == INT32_MAX);
        }
        assert_int_equal(sat, railed);
        assert_true(sat >= 1u);
        printf("paper mode, light tall vehicle: %u clamped H entries\n", sat);
        /* z = H mu clamps per row */
        sat = 0u;
        assert_int_equal(rfe_meas_eval_q31(&h, &lq_pap.vehicle, &lq_pap.tyre, mu, z, &sat), RFE_OK);
        railed = 0u;
        for (i = 0; i < 3; ++i) {
            railed += (abs(z[i]) == INT32_MAX);
        }
        assert_int_equal(sat, railed);
        assert_true(sat >= 1u);
    }
    /* magic mode at mu = 3.9: the same count as the chain (forces ~ 80 kN clamp) */
    {
        rfe_params_t mp = lp;
        rfe_params_q31_t lq_mag;
        mp.tyre.mode = RFE_TYRE_MAGIC;
        assert_int_equal(rfe_params_to_q31_f64(&mp, &lq_mag), RFE_OK);
        make_sample(0, 1.0, 0, 0, -80.0, 80.0, om, &uq, &ud);
        sat = 0u;
        assert_int_equal(rfe_meas_setup_q31(&h, &lq_mag.vehicle, &lq_mag.tyre, &uq, &sat), RFE_OK);
        assert_int_equal(rfe_meas_eval_q31(&h, &lq_mag.vehicle, &lq_mag.tyre, mu, z, &sat), RFE_OK);
        assert_int_equal(sat, chain(&h, &lq_mag.vehicle, &lq_mag.tyre, mu, zc, part));
        assert_memory_equal(z, zc, sizeof(z));
        assert_true(part[0] >= 1u);
        printf("magic mode, light tall vehicle, mu 3.9: counts forces %u, H %u, z %u\n", part[0],
               part[1], part[2]);
    }
    make_sample(0, 1.0, 0, 0, -127.0, 127.0, om, &uq, &ud);
    /* The counter stops at UINT32_MAX, in both modes. */
    sat = UINT32_MAX - 1u;
    assert_int_equal(rfe_meas_eval_q31(&h, &lq_pap.vehicle, &lq_pap.tyre, mu, z, &sat), RFE_OK);
    assert_int_equal(sat, UINT32_MAX);
    assert_int_equal(rfe_meas_setup_q31(&h, &lq.vehicle, &lq.tyre, &uq, &sat), RFE_OK);
    assert_int_equal(rfe_meas_eval_q31(&h, &lq.vehicle, &lq.tyre, mu, z, &sat), RFE_OK);
    assert_int_equal(sat, UINT32_MAX);
    sat = UINT32_MAX - 1u;
    assert_int_equal(rfe_meas_setup_q31(&h, &lq_pap.vehicle, &lq_pap.tyre, &uq, &sat), RFE_OK);
    assert_int_equal(sat, UINT32_MAX);
}

#define SENT ((int32_t)0x5A5A5A5A)

/* REQ: NULL -> RFE_ERR_NULL, invalid tyre parameters or mode -> RFE_ERR_PARAM, the tyre's
 * errors passed on; the model, z and the counter untouched on every error. */
/* REQ-MEAS-002 */
static void test_meas_q31_argument_checks(void **state)
{
    rfe_meas_q31_t h, h0;
    rfe_sample_q31_t u;
    rfe_tyre_params_q31_t bad;
    rfe_fix_t mu[4] = {0, 0, 0, 0}, z[3] = {SENT, SENT, SENT};
    uint32_t sat = 7u;
    (void)state;
    memset(&u, 0, sizeof(u));
    u.vx = toq(20, 23);
    memset(&h, 0x5A, sizeof(h));
    h0 = h;
    assert_int_equal(rfe_meas_setup_q31(NULL, &pq.vehicle, &pq.tyre, &u, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_setup_q31(&h, NULL, &pq.tyre, &u, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_setup_q31(&h, &pq.vehicle, NULL, &u, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_setup_q31(&h, &pq.vehicle, &pq.tyre, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_setup_q31(&h, &pq.vehicle, &pq.tyre, &u, NULL), RFE_ERR_NULL);
    bad = pq.tyre;
    bad.mode = (rfe_tyre_mode_t)7;
    assert_int_equal(rfe_meas_setup_q31(&h, &pq.vehicle, &bad, &u, &sat), RFE_ERR_PARAM);
    bad = pq.tyre;
    bad.v_min = -1;
    assert_int_equal(rfe_meas_setup_q31(&h, &pq.vehicle, &bad, &u, &sat), RFE_ERR_PARAM);
    bad = pq_pap.tyre;
    bad.eps = -1; /* the kinematics accept it, the paper-mode forces do not */
    assert_int_equal(rfe_meas_setup_q31(&h, &pq.vehicle, &bad, &u, &sat), RFE_ERR_PARAM);
    assert_memory_equal(&h, &h0, sizeof(h));
    assert_int_equal(sat, 7u);

    assert_int_equal(rfe_meas_setup_q31(&h, &pq.vehicle, &pq.tyre, &u, &sat), RFE_OK);
    assert_int_equal(rfe_meas_eval_q31(NULL, &pq.vehicle, &pq.tyre, mu, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_q31(&h, NULL, &pq.tyre, mu, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, NULL, mu, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, &pq.tyre, NULL, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, &pq.tyre, mu, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, &pq.tyre, mu, z, NULL), RFE_ERR_NULL);
    /* absolute mode: the tyre's errors (a negative load in the model, invalid parameters) */
    h0 = h;
    h.kin.fz[2] = -5;
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, &pq.tyre, mu, z, &sat), RFE_ERR_RANGE);
    h = h0;
    bad = pq.tyre;
    bad.eps = -1;
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, &bad, mu, z, &sat), RFE_ERR_PARAM);
    assert_int_equal(z[0], SENT);
    assert_int_equal(z[2], SENT);
    assert_int_equal(sat, 7u);
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, &pq.tyre, mu, z, &sat), RFE_OK);
    assert_int_equal(z[0], 0); /* mu = 0 everywhere: no force */
    /* magic mode: set up in it; a shape factor outside its domain at eval -> RFE_ERR_PARAM */
    z[0] = z[1] = z[2] = SENT;
    sat = 7u;
    assert_int_equal(rfe_meas_setup_q31(&h, &pq_mag.vehicle, &pq_mag.tyre, &u, &sat), RFE_OK);
    assert_int_equal(h.mode, RFE_TYRE_MAGIC);
    bad = pq_mag.tyre;
    bad.shape_Ex = 1 << 24;
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, &bad, mu, z, &sat), RFE_ERR_PARAM);
    bad = pq_mag.tyre;
    bad.shape_Cx = 1 << 24;
    assert_int_equal(rfe_meas_eval_q31(&h, &pq.vehicle, &bad, mu, z, &sat), RFE_ERR_PARAM);
    assert_int_equal(z[0], SENT);
    assert_int_equal(sat, 7u);
    assert_int_equal(rfe_meas_eval_q31(&h, &pq_mag.vehicle, &pq_mag.tyre, mu, z, &sat), RFE_OK);
}

/* u with input j changed by d (saturating), as a caller would write it. */
static rfe_sample_q31_t perturb_q31(const rfe_sample_q31_t *u, size_t j, rfe_fix_t d)
{
    rfe_sample_q31_t up = *u;
    uint32_t unused = 0u;
    rfe_fix_t *slot;
    switch (j) {
    case RFE_IN_DELTA: slot = &up.delta; break;
    case RFE_IN_VX: slot = &up.vx; break;
    case RFE_IN_VY: slot = &up.vy; break;
    case RFE_IN_YAW_RATE: slot = &up.yaw_rate; break;
    default: slot = &up.omega[j - RFE_IN_OMEGA]; break;
    }
    *slot = rfe_fix_add(*slot, d, &unused);
    return up;
}

/* REQ: the model at u + d e_j from the set-up model at u (the nominal terms and counts of
 * the wheels input j does not reach reused) is the full set-up and evaluation at u + d e_j:
 * the same integers, statuses and saturation counts (the perturbed input's own saturation
 * included), for every input in paper, absolute and magic mode; the nominal z is
 * rfe_meas_eval_q31's, its count that plus the set-up's kinematics counts. */
/* REQ-FXP-007 REQ-MEAS-001 */
static void test_meas_q31_perturbed(void **state)
{
    int n;
    int n_case = 0; /* cases walked: every 8th saturates, whatever the stride */
    long compared = 0;
    long saturated = 0;
    (void)state;
    rng_seed(0x7E57ull);
    for (n = 0; n < 3000; ++n) {
        const rfe_params_q31_t *p = ((n % 3) == 0) ? &pq_pap : (((n % 3) == 1) ? &pq : &pq_mag);
        ++n_case;
        double om[4];
        rfe_fix_t mu[4];
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        rfe_meas_q31_t h;
        rfe_meas_terms_q31_t nom;
        rfe_fix_t z0[3];
        rfe_fix_t ze[3];
        uint32_t s0 = 0u;
        uint32_t se = 0u;
        uint32_t kin = 0u;
        const double vx = uni(0, 60);
        size_t i;
        size_t j;
        for (i = 0; i < 4; ++i) {
            om[i] = vx * (1.0 + uni(-0.3, 0.1)) / pd.vehicle.R;
            mu[i] = toq(uni(-0.5, 1.5), 29);
        }
        make_sample(uni(-0.3, 0.3), vx, uni(-2, 2), uni(-1, 1), uni(-10, 10), uni(-10, 10), om,
                    &uq, &ud);
        if (rfe_meas_setup_q31(&h, &p->vehicle, &p->tyre, &uq, &s0) != RFE_OK) {
            continue;
        }
        s0 = 0u;
        assert_int_equal(rfe_meas_nominal_q31(&h, &p->vehicle, &p->tyre, mu, &nom, z0, &s0),
                         RFE_OK);
        assert_int_equal(rfe_meas_eval_q31(&h, &p->vehicle, &p->tyre, mu, ze, &se), RFE_OK);
        assert_memory_equal(z0, ze, sizeof(z0));
        if (p->tyre.mode != RFE_TYRE_PAPER) {
            for (i = 0; i < 4; ++i) {
                kin += h.sat_vwx[i] + h.sat_fz[i];
            }
        }
        assert_int_equal(s0, se + kin);
        for (j = 0; j < (size_t)RFE_INPUTS; ++j) {
            /* a small change, and (every 8th case) one that saturates the input */
            const rfe_fix_t d = ((n_case % 8) == 3) ? (rfe_fix_t)0x7FFFFFFF
                                               : (rfe_fix_t)((int32_t)(rng_uniform() * 2e6));
            const rfe_sample_q31_t up = perturb_q31(&uq, j, d);
            rfe_meas_q31_t hp;
            rfe_fix_t zg[3] = {7, 7, 7};
            rfe_fix_t zw[3] = {7, 7, 7};
            uint32_t sg = 0u;
            uint32_t sw = 0u;
            uint32_t sd = 0u;
            rfe_status_t want;
            rfe_status_t got;
            {
                /* the perturbed input's saturation, as the function counts it */
                const rfe_sample_q31_t *base = &uq;
                const rfe_fix_t v[8] = {base->delta, base->vx, base->vy, base->yaw_rate,
                                        base->omega[0], base->omega[1], base->omega[2],
                                        base->omega[3]};
                (void)rfe_fix_add(v[j], d, &sd);
            }
            want = rfe_meas_setup_q31(&hp, &p->vehicle, &p->tyre, &up, &sw);
            if (want == RFE_OK) {
                want = rfe_meas_eval_q31(&hp, &p->vehicle, &p->tyre, mu, zw, &sw);
            }
            got = rfe_meas_eval_perturbed_q31(&h, &p->vehicle, &p->tyre, &nom, &uq, j, d, mu, zg,
                                              &sg);
            assert_int_equal(got, want);
            assert_memory_equal(zg, zw, sizeof(zg));
            if (got == RFE_OK) {
                assert_int_equal(sg, sw + sd);
            } else {
                assert_int_equal(sg, 0u); /* nothing added on an error */
            }
            ++compared;
            saturated += (sg != 0u) ? 1 : 0;
        }
    }
    printf("meas perturbed q31: %ld evaluations identical, %ld with saturations\n", compared,
           saturated);
    assert_true(compared > 1000);
    assert_true(saturated > 0);
}

/* REQ: bad arguments of the perturbed evaluation are rejected with a status, nothing
 * written. */
/* REQ-MEAS-002 */
static void test_meas_q31_perturbed_args(void **state)
{
    const rfe_params_q31_t *p = &pq;
    const double om[4] = {66.0, 66.0, 66.0, 66.0};
    const rfe_fix_t mu[4] = {1 << 29, 1 << 29, 1 << 29, 1 << 29};
    rfe_sample_q31_t uq;
    rfe_sample_t ud;
    rfe_meas_q31_t h;
    rfe_meas_terms_q31_t nom;
    rfe_fix_t z[3] = {7, 7, 7};
    const rfe_fix_t z7[3] = {7, 7, 7};
    uint32_t sat = 0u;
    (void)state;
    make_sample(0.05, 20.0, 0.1, 0.1, -2.0, 1.0, om, &uq, &ud);
    assert_int_equal(rfe_meas_setup_q31(&h, &p->vehicle, &p->tyre, &uq, &sat), RFE_OK);
    sat = 0u;
    assert_int_equal(rfe_meas_nominal_q31(NULL, &p->vehicle, &p->tyre, mu, &nom, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal_q31(&h, NULL, &p->tyre, mu, &nom, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal_q31(&h, &p->vehicle, NULL, mu, &nom, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal_q31(&h, &p->vehicle, &p->tyre, NULL, &nom, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal_q31(&h, &p->vehicle, &p->tyre, mu, NULL, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal_q31(&h, &p->vehicle, &p->tyre, mu, &nom, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal_q31(&h, &p->vehicle, &p->tyre, mu, &nom, z, NULL), RFE_ERR_NULL);
    assert_memory_equal(z, z7, sizeof(z));
    assert_int_equal(rfe_meas_nominal_q31(&h, &p->vehicle, &p->tyre, mu, &nom, z, &sat), RFE_OK);
    z[0] = z[1] = z[2] = 7;
    sat = 0u;
    assert_int_equal(rfe_meas_eval_perturbed_q31(NULL, &p->vehicle, &p->tyre, &nom, &uq, 0u, 1, mu, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed_q31(&h, NULL, &p->tyre, &nom, &uq, 0u, 1, mu, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &p->vehicle, NULL, &nom, &uq, 0u, 1, mu, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &p->vehicle, &p->tyre, NULL, &uq, 0u, 1, mu, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &p->vehicle, &p->tyre, &nom, NULL, 0u, 1, mu, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &p->vehicle, &p->tyre, &nom, &uq, 0u, 1, NULL, z, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &p->vehicle, &p->tyre, &nom, &uq, 0u, 1, mu, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &p->vehicle, &p->tyre, &nom, &uq, 0u, 1, mu, z, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &p->vehicle, &p->tyre, &nom, &uq, (size_t)RFE_INPUTS, 1, mu, z, &sat), RFE_ERR_PARAM);
    assert_memory_equal(z, z7, sizeof(z));
    assert_int_equal(sat, 0u);
    /* paper mode: the perturbed sample's set-up rejects tyre parameters it would reject
     * (v_min <= 0), with nothing written; with the set-up's own parameters it succeeds */
    {
        rfe_tyre_params_q31_t bad = pq_pap.tyre;
        bad.v_min = 0;
        assert_int_equal(rfe_meas_setup_q31(&h, &pq_pap.vehicle, &pq_pap.tyre, &uq, &sat), RFE_OK);
        sat = 0u;
        assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &pq_pap.vehicle, &bad, &nom, &uq, RFE_IN_VX, 1, mu, z, &sat), RFE_ERR_PARAM);
        assert_memory_equal(z, z7, sizeof(z));
        assert_int_equal(sat, 0u);
        assert_int_equal(rfe_meas_eval_perturbed_q31(&h, &pq_pap.vehicle, &pq_pap.tyre, &nom, &uq, RFE_IN_VX, 1, mu, z, &sat), RFE_OK);
    }
}

/* ---- the cached terms against the public chain ------------------------------------------ */

/* The fixed-point default preset (the cached-terms tests start from it). */
static rfe_params_q31_t preset(void)
{
    rfe_params_q31_t p;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    return p;
}

/* REQ: the per-wheel columns and their sums are the load-scaled chain (forces, H, H ones) bit
 * for bit with the same count, in magic and absolute mode; eval with other tyre parameters
 * than the set-up's (stiffness, eps, alpha_max, the other load-scaled mode, other shape
 * factors) gives that chain at the other parameters. */
/* REQ-FXP-007 REQ-FXP-008 */
static void test_meas_columns_q31(void **state)
{
    int n;
    long with_sat = 0;
    (void)state;
    draw_seed(0xC01C01ull);
    for (n = 0; n < N_COLUMN_CASES; ++n) {
        rfe_params_q31_t p = preset();
        rfe_tyre_params_q31_t other;
        rfe_sample_q31_t u;
        rfe_fix_t mu[4];
        rfe_meas_q31_t h;
        rfe_meas_terms_q31_t nom;
        rfe_fix_t z[3];
        rfe_fix_t zc[3];
        uint32_t sat = 0u;
        uint32_t cnt = 0u;
        uint32_t kin_cnt;
        uint32_t part[3];
        size_t i;
        if ((n % 3) == 1) {
            draw_tyre_q31(&p.tyre);
        }
        if ((n % 5) == 2) {
            p.tyre.mode = RFE_TYRE_ABSOLUTE;
        }
        draw_sample_q31(&p, &u, mu, n);
        assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &sat), RFE_OK);
        /* the nominal terms and their sum: the chain's z; the count is the chain's plus the
         * set-up's kinematics counts, which each wheel's terms carry */
        assert_int_equal(rfe_meas_nominal_q31(&h, &p.vehicle, &p.tyre, mu, &nom, z, &cnt),
                         RFE_OK);
        kin_cnt = 0u;
        for (i = 0; i < 4; ++i) {
            kin_cnt += h.sat_vwx[i] + h.sat_fz[i];
        }
        assert_int_equal(chain(&h, &p.vehicle, &p.tyre, mu, zc, part) + kin_cnt, cnt);
        cnt -= kin_cnt;
        assert_memory_equal(z, zc, sizeof(z));
        sat = 0u;
        assert_int_equal(rfe_meas_eval_q31(&h, &p.vehicle, &p.tyre, mu, z, &sat), RFE_OK);
        assert_int_equal(sat, cnt);
        assert_memory_equal(z, zc, sizeof(z));
        with_sat += (cnt != 0u) ? 1 : 0;
        /* other (valid) tyre parameters at eval: the terms are recomputed for them */
        other = p.tyre;
        switch (n % 6) {
        case 0:
            other.cx = other.cx / 2 + 1;
            break;
        case 1:
            other.cy = other.cy / 3 + 1;
            break;
        case 2:
            other.eps = other.eps / 2;
            break;
        case 3:
            other.alpha_max = other.alpha_max / 2;
            break;
        case 4:
            /* the other load-scaled curve on the same cached terms */
            other.mode = (other.mode == RFE_TYRE_MAGIC) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_MAGIC;
            break;
        default:
            /* other shape factors on the same cached terms */
            other.shape_Cx = (1 << 24) + 1 + (int32_t)(draw_u64() % ((1u << 24) - 1u));
            other.shape_Ey = (int32_t)(draw_u64() % (5u << 24)) - (4 << 24);
            break;
        }
        sat = 0u;
        assert_int_equal(rfe_meas_eval_q31(&h, &p.vehicle, &other, mu, z, &sat), RFE_OK);
        assert_int_equal(sat, chain(&h, &p.vehicle, &other, mu, zc, part));
        assert_memory_equal(z, zc, sizeof(z));
    }
    printf("columns: %d cases, %ld with saturations\n", N_COLUMN_CASES, with_sat);
    assert_true(with_sat > 10);
}

/* REQ: a set-up in absolute mode with invalid Dugoff parameters (eps < 0) keeps zero
 * friction-independent terms, and the evaluation rejects the tyre (as the public chain does);
 * in magic mode with a shape factor outside its domain the set-up succeeds (its terms do not
 * depend on the shape) and the evaluation rejects the tyre;
 * rfe_fix_div's long division stops as soon as the quotient must saturate (operands that
 * take the long path: shift + 1 > 32), saturating to INT32_MAX, counted. */
/* REQ-FXP-008 REQ-MEAS-002 */
static void test_meas_pre_invalid_tyre_and_div_saturation_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_sample_q31_t u;
    rfe_fix_t mu[4];
    rfe_fix_t z[3];
    rfe_meas_q31_t h;
    rfe_fix_t q = 0;
    uint32_t sat = 0u;
    size_t i;
    (void)state;
    draw_seed(0xD1CEull);
    draw_sample_q31(&p, &u, mu, 0);
    u.vx = 20 << 23;
    u.delta = 0;
    for (i = 0; i < 4; ++i) {
        u.omega[i] = (int32_t)((((int64_t)u.vx) << 6) / (p.vehicle.R >> 20));
        mu[i] = 1 << 28;
    }
    p.tyre.mode = RFE_TYRE_ABSOLUTE;
    p.tyre.eps = -1;
    assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        const rfe_dugoff_pre_q31_t zero = {0, 0, 0, 0, 0, 0, 0u};
        assert_memory_equal(&h.pre[i], &zero, sizeof zero);
    }
    assert_int_not_equal(rfe_meas_eval_q31(&h, &p.vehicle, &p.tyre, mu, z, &sat), RFE_OK);
    /* magic mode, C = 2 (outside 1 < C < 2) */
    p = preset();
    p.tyre.shape_Cy = 2 << 24;
    sat = 0u;
    assert_int_equal(rfe_meas_setup_q31(&h, &p.vehicle, &p.tyre, &u, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        rfe_dugoff_pre_q31_t fresh;
        rfe_tyre_dugoff_pre_q31(&p.tyre, h.kin.kappa[i], h.kin.alpha[i], h.kin.vwx[i], &fresh);
        assert_memory_equal(&h.pre[i], &fresh, sizeof fresh);
    }
    memset(z, 0x5A, sizeof z);
    assert_int_equal(rfe_meas_eval_q31(&h, &p.vehicle, &p.tyre, mu, z, &sat), RFE_ERR_PARAM);
    assert_int_equal(z[0], 0x5A5A5A5A);
    assert_int_equal(sat, 0u);
    p.tyre.mode = RFE_TYRE_ABSOLUTE; /* the Dugoff curve does not use the shape */
    assert_int_equal(rfe_meas_eval_q31(&h, &p.vehicle, &p.tyre, mu, z, &sat), RFE_OK);
    {
        /* the Magic Formula set-up's terms lack E and 1 - |k|: the Dugoff evaluation forms
         * its own, the integers of an absolute set-up */
        rfe_meas_q31_t ha;
        rfe_fix_t za[3];
        uint32_t sa = 0u;
        assert_int_equal(rfe_meas_setup_q31(&ha, &p.vehicle, &p.tyre, &u, &sa), RFE_OK);
        assert_int_equal(rfe_meas_eval_q31(&ha, &p.vehicle, &p.tyre, mu, za, &sa), RFE_OK);
        assert_memory_equal(za, z, sizeof z);
    }
    /* division: a = INT32_MAX, b = 1, shift 40: 2^71, far beyond int32 */
    sat = 0u;
    assert_int_equal(rfe_fix_div(INT32_MAX, 1, 40, &q, &sat), RFE_OK);
    assert_int_equal(q, INT32_MAX);
    assert_int_equal(sat, 1u);
    sat = 0u;
    assert_int_equal(rfe_fix_div(-INT32_MAX, 3, 35, &q, &sat), RFE_OK);
    assert_int_equal(q, -INT32_MAX);
    assert_int_equal(sat, 1u);
    /* and just inside: 3 * 2^35 / 2^6 = 3 * 2^29 fits exactly */
    sat = 0u;
    assert_int_equal(rfe_fix_div(3, 1 << 6, 35, &q, &sat), RFE_OK);
    assert_int_equal(q, 3 << 29);
    assert_int_equal(sat, 0u);
}

/* ---- the lateral rows' derivatives (rfe_meas_lateral_jac_q31) ------------------------------
 * Bound. The q31 derivatives are the double formulas in rfe_xf_t: each of the ~120 operations
 * of a wheel rounds to 2^-30 relative of its result, and a sum to 2^-29 of its larger
 * operand, so a wheel's derivative errs by at most ~120 2^-29 = 2.2e-7 of the largest term it
 * passes through (the wheel's |dF| / m, |dF| |r_i| / J, |F_mu| sd / m: JAC_SCALE below); the
 * inputs enter rounded (the kinematics: tan alpha within TAN + alpha's 2 LSB29, kappa 1 LSB30,
 * the Magic Formula angles and sine within 2 ATAN2 and TRIG), which moves a derivative by its
 * own sensitivity to them: below 1e-6 relative of the wheel's terms at the slips met (d/dt of
 * dF/dt over dF/dt is < 1/t_min with t_min ~ 1e-3 where the derivative of the shape changes
 * fastest), and the result rounds to Q24 (0.5 LSB, 3e-8). The body map and the sums over the
 * wheels are plain integers (meas_q31.c lat_map_q36, lat_part_q31, lat_row_q31): the map's
 * coefficients in Q36 (1/2 unit = 2^-37 absolute, <= m 2^-37 < 3e-7 of the wheel's term scale
 * |dF| / m for m <= 40 t), a wheel's smaller force at its larger one's exponent (2^-31 of it),
 * the smaller wheels' parts at the largest one's (2^-61 of it), exact sums: well inside the
 * same budget. JAC_REL = 1e-5 of the wheels' term
 * scale is ten times the sum, plus 1 LSB24. Cases whose double state lies within
 * JAC_NEAR of a kink of the derivative (alpha at alpha_max, |kappa| at 1, E at 0, mu at 0: the
 * two twins may take opposite sides) are not compared but counted (<= 1 %). */
#define JAC_REL 1e-5
#define JAC_NEAR 1e-6
#define N_JAC 20000

/* The double twin's kinks within JAC_NEAR (see above). */
static int near_kink(const rfe_meas_t *h, const rfe_params_t *p, const double mu[4])
{
    size_t i;
    for (i = 0; i < 4; ++i) {
        if ((fabs(fabs(h->kin.alpha[i]) - p->tyre.alpha_max) < JAC_NEAR) ||
            (fabs(fabs(h->kin.kappa[i]) - 1.0) < JAC_NEAR) ||
            ((mu[i] != 0.0) && (fabs(mu[i]) < JAC_NEAR)) ||
            ((h->mode != RFE_TYRE_MAGIC) && (h->pre[i].s > 0.0) && (h->pre[i].e < JAC_NEAR))) {
            return 1;
        }
    }
    return 0;
}

/* The wheels' term scale of the derivatives (double): per wheel the magnitude of each
 * derivative's body terms, from a central difference of each wheel's terms alone would be
 * costly; the sum of the rows' derivative magnitudes per wheel is bounded by the friction
 * limit over the speed (|dF/dvy| <= cy Fz / |vwx| (1 + |t|) for every mode and mu, from the
 * linear tyre, the stiffest) and the friction derivative by Fz sd: scale = sum_i Fz_i (cy (1 +
 * |t_i|) / max(|vwx_i|, v_min) + sd_i) (1 / m + |r_i| / J). */
static double jac_scale(const rfe_meas_t *h, const rfe_params_t *p, const double sd[4])
{
    const double x[4] = {p->vehicle.Lf, p->vehicle.Lf, -p->vehicle.Lr, -p->vehicle.Lr};
    const double y[4] = {p->vehicle.Bf / 2, p->vehicle.Bf / 2, p->vehicle.Br / 2,
                         p->vehicle.Br / 2};
    const double c = fmax(p->tyre.cy, p->tyre.Cy_n);
    double sc = 0.0;
    size_t i;
    for (i = 0; i < 4; ++i) {
        const double t = fabs(tan(h->kin.alpha[i]));
        const double f = h->kin.fz[i] * ((c * (1.0 + t) / fmax(fabs(h->kin.vwx[i]), p->tyre.v_min)) + sd[i]);
        sc += f * ((1.0 / p->vehicle.m) + (sqrt((x[i] * x[i]) + (y[i] * y[i])) / p->vehicle.J));
    }
    return sc;
}

/* REQ: the lateral rows' derivatives in fixed point against the double twin within the
 * derived bound (above), in every tyre mode, on driving samples (vx 3 .. 45 m/s, the observer's
 * range), the rows themselves rfe_meas_eval_q31's integers; the worst cases printed. */
/* REQ-MEAS-003 REQ-FXP-003 */
static void test_meas_lateral_jac_q31(void **state)
{
    double worst[3] = {0.0, 0.0, 0.0};
    long compared = 0;
    long kinks = 0;
    int n;
    (void)state;
    rng_seed(0x1A7E2A1ull);
    for (n = 0; n < N_JAC; ++n) {
        const int m = n % 3;
        const rfe_params_t *p = (m == 0) ? &pd_pap : ((m == 1) ? &pd : &pd_mag);
        const rfe_params_q31_t *q = (m == 0) ? &pq_pap : ((m == 1) ? &pq : &pq_mag);
        const double vx = uni(3.0, 45.0);
        double om[4];
        double mu[4];
        double sd[4];
        rfe_fix_t muq[4];
        rfe_fix_t sdq[4];
        rfe_real_t mud[4];
        rfe_real_t sdd[4];
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        rfe_meas_q31_t hq;
        rfe_meas_t hd;
        rfe_meas_lateral_q31_t oq;
        rfe_meas_lateral_t od;
        rfe_fix_t zq[3];
        uint32_t sat = 0u;
        uint32_t sat2 = 0u;
        double sc;
        size_t i;
        int r;
        for (i = 0; i < 4; ++i) {
            om[i] = vx * (1.0 + uni(-0.2, 0.1)) / p->vehicle.R;
            muq[i] = toq(uni(0.05, 1.3), 29);
            sdq[i] = toq(uni(0.0, 0.4), 30);
            mu[i] = fromq(muq[i], 29);
            sd[i] = fromq(sdq[i], 30);
            mud[i] = mu[i];
            sdd[i] = sd[i];
        }
        if ((n % 50) < 3) {
            /* no slip (S = 0), or a slip so small that the shape's series replaces G / s */
            for (i = 0; i < 4; ++i) {
                om[i] = 20.0 / p->vehicle.R;
            }
            make_sample(0.0, 20.0, ((n % 50) == 0) ? 0.0 : 1e-4, 0.0, 0.0, 0.0, om, &uq, &ud);
            if ((n % 50) == 2) {
                muq[1] = 0; /* no friction on one wheel: no force at any slip */
                mu[1] = 0.0;
                mud[1] = 0.0;
            }
        } else {
            if ((n % 2000) == 110) {
                /* a locked front wheel while steering: kappa = -1 exactly in both twins, so no
                 * kappa derivative although the steer angle's sine is not 0 (counted as a kink
                 * case, 10 of them: 0.05 %, 0.5 % with RFE_TEST_LIGHT) */
                om[0] = 0.0;
            }
            make_sample(uni(-0.3, 0.3), vx, uni(-2.5, 2.5), uni(-0.8, 0.8), uni(-9, 5),
                        uni(-9, 9), om, &uq, &ud);
        }
        assert_int_equal(rfe_meas_setup_q31(&hq, &q->vehicle, &q->tyre, &uq, &sat), RFE_OK);
        assert_int_equal(rfe_meas_setup_f64(&hd, &p->vehicle, &p->tyre, &ud), RFE_OK);
        assert_int_equal(rfe_meas_lateral_jac_q31(&hq, &q->vehicle, &q->tyre, &uq, muq, sdq, &oq, &sat), RFE_OK);
        assert_int_equal(rfe_meas_eval_q31(&hq, &q->vehicle, &q->tyre, muq, zq, &sat2), RFE_OK);
        assert_int_equal(oq.z[0], zq[1]);
        assert_int_equal(oq.z[1], zq[2]);
        assert_int_equal(rfe_meas_lateral_jac_f64(&hd, &p->vehicle, &p->tyre, &ud, mud, sdd, &od), RFE_OK);
        if (near_kink(&hd, p, mu) != 0) {
            ++kinks;
            continue;
        }
        sc = jac_scale(&hd, p, sd);
        for (r = 0; r < 2; ++r) {
            const double ev = fabs(fromq(oq.d_vy[r], 24) - od.d_vy[r]);
            const double em = fabs(fromq(oq.d_mu[r], 24) - od.d_mu[r]);
            const double bound = (JAC_REL * sc) + ldexp(1.0, -24);
            if ((ev > bound) || (em > bound)) {
                printf("case %d mode %d row %d: d_vy q31 %.9g f64 %.9g, d_mu q31 %.9g f64 %.9g, "
                       "bound %.3g\n", n, m, r, fromq(oq.d_vy[r], 24), od.d_vy[r],
                       fromq(oq.d_mu[r], 24), od.d_mu[r], bound);
            }
            assert_true(ev <= bound);
            assert_true(em <= bound);
            worst[m] = fmax(worst[m], fmax(ev, em) / bound);
            ++compared;
        }
    }
    printf("lateral jac q31 vs f64: %ld rows compared, %ld cases near a kink skipped; worst "
           "|error| / bound: paper %.3g, absolute %.3g, magic %.3g\n",
           compared, kinks, worst[0], worst[1], worst[2]);
    assert_true((double)kinks <= (0.01 * (double)(compared / 2 + kinks)));
}

/* REQ: at a slip angle beyond its bound (alpha clamped to alpha_max on every wheel: vy / vx
 * = 7 > tan 1.4 = 5.8, far from the clamp's edge, so both twins clamp), the lateral rows'
 * derivatives lose the slip angle's term in both twins and agree within the bound above. */
/* REQ-MEAS-003 REQ-FXP-003 */
static void test_meas_lateral_jac_q31_at_alpha_bound(void **state)
{
    size_t m;
    (void)state;
    for (m = 0; m < 3; ++m) {
        const rfe_params_t *p = (m == 0) ? &pd_pap : ((m == 1) ? &pd : &pd_mag);
        const rfe_params_q31_t *q = (m == 0) ? &pq_pap : ((m == 1) ? &pq : &pq_mag);
        double om[4];
        double sd[4];
        rfe_fix_t muq[4];
        rfe_fix_t sdq[4];
        rfe_real_t mud[4];
        rfe_real_t sdd[4];
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        rfe_meas_q31_t hq;
        rfe_meas_t hd;
        rfe_meas_lateral_q31_t oq;
        rfe_meas_lateral_t od;
        uint32_t sat = 0u;
        size_t i;
        int r;
        for (i = 0; i < 4; ++i) {
            om[i] = 3.0 / p->vehicle.R;
            muq[i] = toq(0.6, 29);
            sdq[i] = toq(0.1, 30);
            mud[i] = fromq(muq[i], 29);
            sd[i] = fromq(sdq[i], 30);
            sdd[i] = sd[i];
        }
        make_sample(0.0, 3.0, 21.0, 0.0, 0.0, 0.0, om, &uq, &ud);
        assert_int_equal(rfe_meas_setup_q31(&hq, &q->vehicle, &q->tyre, &uq, &sat), RFE_OK);
        assert_int_equal(rfe_meas_setup_f64(&hd, &p->vehicle, &p->tyre, &ud), RFE_OK);
        for (i = 0; i < 4; ++i) {
            assert_true(fabs(hd.kin.alpha[i]) >= p->tyre.alpha_max); /* clamped */
            assert_true(rfe_q31_within(hq.kin.alpha[i], q->tyre.alpha_max - 1) == 0);
            assert_true(hq.kin.vwx[i] != 0);
        }
        assert_int_equal(rfe_meas_lateral_jac_q31(&hq, &q->vehicle, &q->tyre, &uq, muq, sdq, &oq,
                                                  &sat), RFE_OK);
        assert_int_equal(rfe_meas_lateral_jac_f64(&hd, &p->vehicle, &p->tyre, &ud, mud, sdd, &od),
                         RFE_OK);
        for (r = 0; r < 2; ++r) {
            const double bound = (JAC_REL * jac_scale(&hd, p, sd)) + ldexp(1.0, -24);
            assert_true(fabs(fromq(oq.d_vy[r], 24) - od.d_vy[r]) <= bound);
            assert_true(fabs(fromq(oq.d_mu[r], 24) - od.d_mu[r]) <= bound);
        }
    }
}

/* REQ: the lateral rows' derivatives reject missing arguments (RFE_ERR_NULL), tyre parameters
 * the tangent or the curve cannot use (RFE_ERR_PARAM: alpha_max, a Magic Formula shape factor
 * out of its domain), nothing written, the counter untouched. */
/* REQ-MEAS-002 REQ-MEAS-003 */
static void test_meas_lateral_jac_q31_args(void **state)
{
    const rfe_params_q31_t *q = &pq_mag;
    rfe_fix_t mu[4] = {1 << 29, 1 << 29, 1 << 29, 1 << 29};
    rfe_fix_t sd[4] = {1 << 28, 1 << 28, 1 << 28, 1 << 28};
    const double om[4] = {66.0, 66.0, 66.0, 66.0};
    rfe_sample_q31_t uq;
    rfe_sample_t ud;
    rfe_meas_q31_t h;
    rfe_meas_lateral_q31_t o;
    rfe_meas_lateral_q31_t o0;
    rfe_tyre_params_q31_t bad = q->tyre;
    uint32_t sat = 0u;
    (void)state;
    make_sample(0.05, 20.0, 0.3, 0.1, 0.0, 2.0, om, &uq, &ud);
    assert_int_equal(rfe_meas_setup_q31(&h, &q->vehicle, &q->tyre, &uq, &sat), RFE_OK);
    memset(&o, 0x5A, sizeof(o));
    o0 = o;
    sat = 0u;
    assert_int_equal(rfe_meas_lateral_jac_q31(NULL, &q->vehicle, &q->tyre, &uq, mu, sd, &o, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, NULL, &q->tyre, &uq, mu, sd, &o, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, NULL, &uq, mu, sd, &o, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, &q->tyre, NULL, mu, sd, &o, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, &q->tyre, &uq, NULL, sd, &o, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, &q->tyre, &uq, mu, NULL, &o, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, &q->tyre, &uq, mu, sd, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, &q->tyre, &uq, mu, sd, &o, NULL), RFE_ERR_NULL);
    bad.alpha_max = 0;
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, &bad, &uq, mu, sd, &o, &sat), RFE_ERR_PARAM);
    bad = q->tyre;
    bad.shape_Cx = 0;
    assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, &bad, &uq, mu, sd, &o, &sat), RFE_ERR_PARAM);
    /* a negative wheel load (a set-up corrupted by hand): refused as rfe_meas_eval_q31
     * refuses it, in the Magic Formula's one-pass path too */
    {
        rfe_meas_q31_t neg = h;
        neg.kin.fz[2] = -5;
        assert_int_equal(rfe_meas_lateral_jac_q31(&neg, &q->vehicle, &q->tyre, &uq, mu, sd, &o, &sat),
                         RFE_ERR_RANGE);
    }
    assert_memory_equal(&o, &o0, sizeof(o));
    assert_int_equal(sat, 0u);
    /* other tyre parameters than the set-up's: the terms are recomputed, as a set-up with them */
    {
        rfe_tyre_params_q31_t other = q->tyre;
        rfe_meas_q31_t h2;
        rfe_meas_lateral_q31_t o2;
        other.cy = other.cy + (other.cy / 4);
        assert_int_equal(rfe_meas_setup_q31(&h2, &q->vehicle, &other, &uq, &sat), RFE_OK);
        assert_int_equal(rfe_meas_lateral_jac_q31(&h, &q->vehicle, &other, &uq, mu, sd, &o, &sat), RFE_OK);
        assert_int_equal(rfe_meas_lateral_jac_q31(&h2, &q->vehicle, &other, &uq, mu, sd, &o2, &sat), RFE_OK);
        assert_memory_equal(&o, &o2, sizeof(o));
    }
}

/* ---- the derivatives by the inputs (rfe_meas_input_jac_q31, for the step noise) -----------
 * Bound: JAC_REL of the input's term scale times its sd, plus 1 LSB24 (the final rounding and
 * the sd's own). Per wheel, the tyre's derivatives along kappa, tan alpha (and v_wx) and the
 * slips' sensitivities to the wheel's velocity are the double formulas in rfe_xf_t (as the
 * lateral rows' above: ~60 operations, 2^-29 each of the largest term passed through; the
 * inputs rounded as the kinematics round them), the rows per unit velocity change rounded to
 * one exponent per wheel (2^-27 of the wheel's largest entry, which the term scale below
 * bounds up to the Magic Formula's slope factor <= 5); each input's change of the wheel's
 * velocity in a Q format (vx, vy: cos, sin Q30; r: lever arms Q28, 2^-29 m; delta: the wheel
 * velocity Q21, 2^-22 m/s, ~1e-7 of |v_w| at the 3 m/s and more drawn here; omega: R exact), the
 * products exact, the wheels' sums aligned (1/2 unit, 2^-27 of the largest wheel's entries
 * times the velocity change's unit), rounded to 31 bits before sd (2^-31): together < 1e-7 of
 * the scale, two orders below JAC_REL, which stays as it was (the Q24 rounding dominates the
 * measured worst ratio). The term scale of input j: per wheel it
 * reaches, its load times the stiffest curve's slope per unit slip (max of cx, cy, Cx_n, Cy_n:
 * the linear tyre, which no mode or friction exceeds), times the slip change per unit input
 * ((1 + |t|) (1 + |kappa|) times the wheel's speed change over max(|vwx|, v_min): 1 for vx and
 * vy, the distance to the CoG for r, R for its wheel speed, the wheel's speed |v_w| for delta),
 * plus for delta the turned force, <= |mu| Fz; mapped by 1/m + |r_i|/J. */
static double input_scale(const rfe_meas_t *h, const rfe_params_t *p, const double mu[4],
                          size_t j)
{
    const double x[4] = {p->vehicle.Lf, p->vehicle.Lf, -p->vehicle.Lr, -p->vehicle.Lr};
    const double y[4] = {p->vehicle.Bf / 2, p->vehicle.Bf / 2, p->vehicle.Br / 2,
                         p->vehicle.Br / 2};
    const double c = fmax(fmax(p->tyre.cx, p->tyre.cy), fmax(p->tyre.Cx_n, p->tyre.Cy_n));
    double sc = 0.0;
    size_t i;
    for (i = 0; i < 4; ++i) {
        const double ri = sqrt((x[i] * x[i]) + (y[i] * y[i]));
        const double t = fabs(tan(h->kin.alpha[i]));
        const double vw = fabs(h->kin.vwx[i]) * (1.0 + t);
        double dv = 0.0;
        double turn = 0.0;
        if ((j == (size_t)RFE_IN_DELTA) && (i < 2u)) {
            dv = vw;
            turn = fabs(mu[i]);
        } else if ((j == (size_t)RFE_IN_VX) || (j == (size_t)RFE_IN_VY)) {
            dv = 1.0;
        } else if (j == (size_t)RFE_IN_YAW_RATE) {
            dv = ri;
        } else if (j == (size_t)RFE_IN_OMEGA + i) {
            dv = p->vehicle.R;
        } else {
            /* not reached */
        }
        sc += h->kin.fz[i] *
              ((c * (1.0 + t) * (1.0 + fabs(h->kin.kappa[i])) * dv /
                fmax(fabs(h->kin.vwx[i]), p->tyre.v_min)) + turn) *
              ((1.0 / p->vehicle.m) + (ri / p->vehicle.J));
    }
    return sc;
}

/* REQ: the input columns sd_j dh/du_j in fixed point against the double twin within the
 * derived bound (above), every input and row, in every tyre mode, on driving samples (vx 3 .. 45
 * m/s: the step noise runs from v_est_min), at no slip, on a locked and a spinning wheel and in
 * hard turns, with a front wheel at mu 0; a column of sd 0 is 0. */
/* REQ-MEAS-004 REQ-FXP-003 */
static void test_meas_input_jac_q31(void **state)
{
    double worst[3] = {0.0, 0.0, 0.0};
    long compared = 0;
    long kinks = 0;
    int n;
    (void)state;
    rng_seed(0x1A9E7Aull);
    for (n = 0; n < N_JAC; ++n) {
        const int m = n % 3;
        const rfe_params_t *p = (m == 0) ? &pd_pap : ((m == 1) ? &pd : &pd_mag);
        const rfe_params_q31_t *q = (m == 0) ? &pq_pap : ((m == 1) ? &pq : &pq_mag);
        const double vx = uni(3.0, 45.0);
        const int qf[8] = {29, 23, 23, 27, 22, 22, 22, 22};
        double om[4];
        double mu[4];
        rfe_fix_t muq[4];
        rfe_real_t mud[4];
        rfe_fix_t sdq[8];
        rfe_real_t sdd[8];
        rfe_fix_t Gq[24];
        rfe_real_t Gd[24];
        rfe_sample_q31_t uq;
        rfe_sample_t ud;
        rfe_meas_q31_t hq;
        rfe_meas_t hd;
        uint32_t sat = 0u;
        size_t i;
        size_t j;
        for (i = 0; i < 4; ++i) {
            om[i] = vx * (1.0 + uni(-0.2, 0.1)) / p->vehicle.R;
            muq[i] = toq(uni(0.05, 1.3), 29);
            mu[i] = fromq(muq[i], 29);
            mud[i] = mu[i];
        }
        if ((n % 50) == 4) {
            /* a front wheel without friction (mu 0: no force, no derivative): the columns skip
             * its rows and, for delta, its turned forces; the other wheels' still compared */
            muq[0] = 0;
            mu[0] = 0.0;
            mud[0] = 0.0;
        }
        for (j = 0; j < 8; ++j) {
            /* sds up to ten times the default preset's; input 2 (vy) off every fourth case */
            const double top[8] = {0.01, 0.1, 0.1, 0.05, 0.5, 0.5, 0.5, 0.5};
            sdq[j] = ((j == 2u) && ((n % 4) == 3)) ? 0 : toq(uni(0.0, top[j]), qf[j]);
            sdd[j] = fromq(sdq[j], qf[j]);
        }
        if ((n % 50) < 3) {
            for (i = 0; i < 4; ++i) {
                om[i] = 20.0 / p->vehicle.R; /* free rolling: no slip */
            }
            if ((n % 50) == 1) {
                om[2] = 0.0; /* locked: kappa -1, saturated */
            } else if ((n % 50) == 2) {
                om[1] = 40.0 / p->vehicle.R; /* spinning: kappa 0.5 */
            } else {
                /* none */
            }
            make_sample(0.05, 20.0, 0.0, 0.0, 0.0, 0.0, om, &uq, &ud);
        } else if ((n % 50) == 3) {
            make_sample(0.12, vx, -0.08 * vx, 9.0 / vx, -2.0, 8.0, om, &uq, &ud); /* hard turn */
        } else {
            make_sample(uni(-0.3, 0.3), vx, uni(-2.5, 2.5), uni(-0.8, 0.8), uni(-9, 5),
                        uni(-9, 9), om, &uq, &ud);
        }
        assert_int_equal(rfe_meas_setup_q31(&hq, &q->vehicle, &q->tyre, &uq, &sat), RFE_OK);
        assert_int_equal(rfe_meas_setup_f64(&hd, &p->vehicle, &p->tyre, &ud), RFE_OK);
        assert_int_equal(rfe_meas_input_jac_q31(&hq, &q->vehicle, &q->tyre, &uq, muq, sdq, Gq, &sat), RFE_OK);
        assert_int_equal(rfe_meas_input_jac_f64(&hd, &p->vehicle, &p->tyre, &ud, mud, sdd, Gd), RFE_OK);
        for (j = 0; j < 8; ++j) {
            if (sdq[j] == 0) {
                assert_int_equal(Gq[j], 0);
                assert_int_equal(Gq[8 + j], 0);
                assert_int_equal(Gq[16 + j], 0);
            }
        }
        /* the locked wheel's kappa is exactly -1 in both twins ((0 - v) / v, clipped): both
         * on the clip's side, compared */
        if (((n % 50) != 1) && (near_kink(&hd, p, mu) != 0)) {
            ++kinks;
            continue;
        }
        for (j = 0; j < 8; ++j) {
            const double bound = (JAC_REL * input_scale(&hd, p, mu, j) * sdd[j]) + ldexp(1.0, -24);
            int r;
            for (r = 0; r < 3; ++r) {
                const double e = fabs(fromq(Gq[(size_t)r * 8u + j], 24) - Gd[(size_t)r * 8u + j]);
                if (e > bound) {
                    printf("case %d mode %d input %zu row %d: q31 %.9g f64 %.9g, bound %.3g\n", n,
                           m, j, r, fromq(Gq[(size_t)r * 8u + j], 24), Gd[(size_t)r * 8u + j],
                           bound);
                }
                assert_true(e <= bound);
                worst[m] = fmax(worst[m], e / bound);
                ++compared;
            }
        }
    }
    printf("input jac q31 vs f64: %ld entries compared, %ld cases near a kink skipped; worst "
           "|error| / bound: paper %.3g, absolute %.3g, magic %.3g\n",
           compared, kinks, worst[0], worst[1], worst[2]);
    assert_true(compared > 10000);
    assert_true((double)kinks <= (0.01 * (double)(compared / 24 + kinks)));
}

/* REQ: rfe_meas_input_jac_q31's argument checks: NULLs, invalid tyre parameters (RFE_ERR_PARAM),
 * nothing written and nothing counted. */
/* REQ-MEAS-004 */
static void test_meas_input_jac_q31_args(void **state)
{
    const double om[4] = {70.0, 70.0, 70.0, 70.0};
    rfe_fix_t muq[4] = {toq(0.8, 29), toq(0.8, 29), toq(0.8, 29), toq(0.8, 29)};
    rfe_fix_t sdq[8] = {toq(0.001, 29), toq(0.01, 23), toq(0.01, 23), toq(0.005, 27),
                        toq(0.05, 22), toq(0.05, 22), toq(0.05, 22), toq(0.05, 22)};
    rfe_fix_t G[24];
    rfe_fix_t G0[24];
    rfe_sample_q31_t uq;
    rfe_sample_t ud;
    rfe_meas_q31_t hq;
    rfe_tyre_params_q31_t bad = pq_mag.tyre;
    uint32_t sat = 0u;
    (void)state;
    make_sample(0.05, 20.0, 0.3, 0.1, -2.0, 3.0, om, &uq, &ud);
    assert_int_equal(rfe_meas_setup_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, &uq, &sat), RFE_OK);
    memset(G, 0x5A, sizeof(G));
    memcpy(G0, G, sizeof(G));
    sat = 0u;
    assert_int_equal(rfe_meas_input_jac_q31(NULL, &pq_mag.vehicle, &pq_mag.tyre, &uq, muq, sdq, G, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac_q31(&hq, NULL, &pq_mag.tyre, &uq, muq, sdq, G, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, NULL, &uq, muq, sdq, G, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, NULL, muq, sdq, G, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, &uq, NULL, sdq, G, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, &uq, muq, NULL, G, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, &uq, muq, sdq, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, &uq, muq, sdq, G, NULL), RFE_ERR_NULL);
    bad.alpha_max = 0; /* the tangents' bound must be positive */
    assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, &bad, &uq, muq, sdq, G, &sat), RFE_ERR_PARAM);
    assert_memory_equal(G, G0, sizeof(G));
    assert_int_equal(sat, 0u);
    assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, &uq, muq, sdq, G, &sat), RFE_OK);
    assert_true(G[0] != G0[0]);
}

/* REQ: rfe_meas_input_jac_q31 at and near standstill (the function itself takes any speed; the
 * step noise does not call it yet): a car at rest (every v_wx = 0: no tangent term, den = v_min
 * for the slip), a slow car whose wheels are below v_min (front |v_wx| > |omega R|, rear
 * |omega R| >= |v_wx|: den = v_min, neither speed's own term), with no steering column
 * (sd_delta = 0: no turned forces); every column finite and that of delta 0. */
/* REQ-MEAS-004 */
static void test_meas_input_jac_q31_slow(void **state)
{
    const double still[4] = {0.0, 0.0, 0.0, 0.0};
    double slow[4];
    rfe_fix_t muq[4] = {toq(0.8, 29), toq(0.8, 29), toq(0.8, 29), toq(0.8, 29)};
    rfe_fix_t sdq[8] = {0, toq(0.01, 23), toq(0.01, 23), toq(0.005, 27),
                        toq(0.05, 22), toq(0.05, 22), toq(0.05, 22), toq(0.05, 22)};
    rfe_fix_t G[24];
    rfe_sample_q31_t uq;
    rfe_sample_t ud;
    rfe_meas_q31_t hq;
    uint32_t sat = 0u;
    int c;
    (void)state;
    slow[0] = 0.1 / pd_mag.vehicle.R; /* front: omega R 0.1 < v_wx 0.2 < v_min 0.5 */
    slow[1] = slow[0];
    slow[2] = 0.3 / pd_mag.vehicle.R; /* rear: v_wx 0.2 <= omega R 0.3 < v_min */
    slow[3] = slow[2];
    for (c = 0; c < 2; ++c) {
        size_t r;
        make_sample(0.0, (c == 0) ? 0.0 : 0.2, 0.0, 0.0, 0.0, 0.0, (c == 0) ? still : slow, &uq,
                    &ud);
        assert_int_equal(rfe_meas_setup_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, &uq, &sat), RFE_OK);
        memset(G, 0x5A, sizeof(G));
        assert_int_equal(rfe_meas_input_jac_q31(&hq, &pq_mag.vehicle, &pq_mag.tyre, &uq, muq, sdq, G, &sat), RFE_OK);
        for (r = 0; r < 3u; ++r) {
            assert_int_equal(G[r * 8u], 0);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_meas_q31_scenarios),
        cmocka_unit_test(test_meas_q31_random),
        cmocka_unit_test(test_meas_q31_deterministic),
        cmocka_unit_test(test_meas_q31_saturation),
        cmocka_unit_test(test_meas_q31_argument_checks),
        cmocka_unit_test(test_meas_q31_perturbed),
        cmocka_unit_test(test_meas_q31_perturbed_args),
        cmocka_unit_test(test_meas_columns_q31),
        cmocka_unit_test(test_meas_pre_invalid_tyre_and_div_saturation_q31),
        cmocka_unit_test(test_meas_lateral_jac_q31),
        cmocka_unit_test(test_meas_input_jac_q31),
        cmocka_unit_test(test_meas_input_jac_q31_args),
        cmocka_unit_test(test_meas_input_jac_q31_slow),
        cmocka_unit_test(test_meas_lateral_jac_q31_at_alpha_bound),
        cmocka_unit_test(test_meas_lateral_jac_q31_args),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
