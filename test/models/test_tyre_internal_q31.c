/**
 * @file test_tyre_internal_q31.c
 * @brief The fixed-point tyre model's internal split (src/models/tyre_internal_q31.h) behind
 *        the cheaper fixed-point step, against the public functions it replaces, bit for bit,
 *        saturation counts included: one wheel's kinematics and kappa alone against
 *        rfe_tyre_kinematics_q31 (and its variant with the extra terms), the load-scaled tyre
 *        evaluation (absolute Dugoff and Magic Formula) split into its friction-independent
 *        part and the rest against rfe_tyre_dugoff_abs_q31 and rfe_tyre_magic_abs_q31; the
 *        Dugoff parameter check.
 * Inputs: integer samples from a fixed-seed generator (test_draws_q31.h) over the typical
 * range, the int32 extremes and rolling wheels, tyre parameters varied around the preset's.
 * In valgrind's light mode every tenth case (every path is still taken).
 */
#include "test_light.h"
#include "test_common.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "rfe/fixed.h"
#include "rfe/component/fxmath.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre_q31.h"

#include "models/tyre_internal.h"
#include "models/tyre_internal_q31.h"
#include "numerics/fxmath_internal_q31.h"
#include "test_draws_q31.h"

#define N_CASES 20000

static rfe_params_q31_t preset(void)
{
    rfe_params_q31_t p;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    return p;
}

/* REQ: one wheel's kinematics and the split Dugoff and Magic Formula evaluations are
 * rfe_tyre_kinematics_q31's, rfe_tyre_dugoff_abs_q31's and rfe_tyre_magic_abs_q31's bits and
 * counts. */
/* REQ-FXP-007 REQ-FXP-008 */
static void test_tyre_internal_q31(void **state)
{
    rfe_params_q31_t p = preset();
    int n;
    (void)state;
    draw_seed(0x7E1EC0DEull);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        rfe_sample_q31_t u;
        rfe_fix_t mu[4];
        rfe_wheel_kin_q31_t kin;
        rfe_wheel_kin_q31_t kin_ex;
        rfe_tyre_kin_extra_q31_t extra;
        rfe_fix_t s = 0;
        rfe_fix_t c = 0;
        uint32_t sat = 0u;
        uint32_t sum = 0u;
        size_t i;
        p = preset();
        if ((n % 3) == 1) {
            draw_tyre_q31(&p.tyre);
        }
        draw_sample_q31(&p, &u, mu, n);
        assert_int_equal(rfe_tyre_kinematics_q31(&p.vehicle, &p.tyre, &u, &kin, &sat), RFE_OK);
        assert_int_equal(rfe_tyre_kinematics_ex_q31(&p.vehicle, &p.tyre, &u, &kin_ex, &extra),
                         RFE_OK);
        assert_memory_equal(&kin, &kin_ex, sizeof(kin));
        rfe_q31_sincos_q29(u.delta, &s, &c);
        assert_int_equal(extra.cos_delta, c);
        assert_int_equal(extra.sin_delta, s);
        for (i = 0; i < 4; ++i) {
            rfe_fix_t vwx = 0;
            rfe_fix_t alpha = 0;
            rfe_fix_t kappa = 0;
            rfe_fix_t fx = 0;
            rfe_fix_t fy = 0;
            rfe_fix_t gx = 0;
            rfe_fix_t gy = 0;
            uint32_t cw = 0u;
            uint32_t c1 = 0u;
            uint32_t c2 = 0u;
            rfe_dugoff_pre_q31_t pre;
            rfe_dugoff_pre_q31_t pre_t;
            sum += extra.sat_vwx[i] + extra.sat_fz[i];
            rfe_tyre_wheel_kin_q31(&p.vehicle, &p.tyre, &u, c, s, i, &vwx, &alpha, &kappa, &cw);
            assert_int_equal(vwx, kin.vwx[i]);
            assert_int_equal(alpha, kin.alpha[i]);
            assert_int_equal(kappa, kin.kappa[i]);
            assert_int_equal(cw, extra.sat_vwx[i]);
            assert_int_equal(rfe_tyre_wheel_kappa_q31(&p.vehicle, &p.tyre, &u, c, s, i),
                             kin.kappa[i]);
            assert_int_equal(rfe_tyre_dugoff_abs_q31(&p.tyre, kin.kappa[i], kin.alpha[i],
                                                     kin.fz[i], kin.vwx[i], mu[i], &fx, &fy,
                                                     &c1),
                             RFE_OK);
            {
                /* the terms of an absolute (Dugoff) tyre, which serve both load-scaled modes */
                rfe_tyre_params_q31_t td = p.tyre;
                td.mode = RFE_TYRE_ABSOLUTE;
                rfe_tyre_dugoff_pre_q31(&td, kin.kappa[i], kin.alpha[i], kin.vwx[i], &pre);
                rfe_tyre_dugoff_abs_pre_q31(&td, &pre, mu[i], kin.fz[i], &gx, &gy, &c2);
                rfe_tyre_dugoff_pre_tan_q31(&td, kin.kappa[i], pre.tan_a, kin.vwx[i], &pre_t);
            }
            assert_int_equal(gx, fx);
            assert_int_equal(gy, fy);
            assert_int_equal(c2, c1);
            assert_memory_equal(&pre_t, &pre, sizeof(pre));
            {
                /* a Magic Formula tyre's terms: the same but without E and 1 - |k| (0), which
                 * only the Dugoff curve reads; the Magic Formula's forces from them below */
                rfe_tyre_params_q31_t tm = p.tyre;
                rfe_dugoff_pre_q31_t pre_m;
                tm.mode = RFE_TYRE_MAGIC;
                rfe_tyre_dugoff_pre_q31(&tm, kin.kappa[i], kin.alpha[i], kin.vwx[i], &pre_m);
                assert_int_equal(pre_m.tan_a, pre.tan_a);
                assert_int_equal(pre_m.s, pre.s);
                assert_int_equal(pre_m.qs, pre.qs);
                assert_int_equal(pre_m.ux, pre.ux);
                assert_int_equal(pre_m.uy, pre.uy);
                assert_int_equal(pre_m.e, 0);
                assert_int_equal(pre_m.omk, 0);
                rfe_tyre_dugoff_pre_tan_q31(&tm, kin.kappa[i], pre.tan_a, kin.vwx[i], &pre_t);
                assert_memory_equal(&pre_t, &pre_m, sizeof(pre_m));
                c1 = c2 = 0u;
                assert_int_equal(rfe_tyre_magic_abs_q31(&tm, kin.kappa[i], kin.alpha[i],
                                                        kin.fz[i], kin.vwx[i], mu[i], &fx, &fy,
                                                        &c1),
                                 RFE_OK);
                rfe_tyre_dugoff_abs_pre_q31(&tm, &pre_m, mu[i], kin.fz[i], &gx, &gy, &c2);
                assert_int_equal(gx, fx);
                assert_int_equal(gy, fy);
                assert_int_equal(c2, c1);
            }
            /* the Magic Formula on the absolute tyre's terms */
            c1 = c2 = 0u;
            assert_int_equal(rfe_tyre_magic_abs_q31(&p.tyre, kin.kappa[i], kin.alpha[i],
                                                    kin.fz[i], kin.vwx[i], mu[i], &fx, &fy,
                                                    &c1),
                             RFE_OK);
            {
                rfe_tyre_params_q31_t tm = p.tyre;
                tm.mode = RFE_TYRE_MAGIC;
                rfe_tyre_dugoff_abs_pre_q31(&tm, &pre, mu[i], kin.fz[i], &gx, &gy, &c2);
            }
            assert_int_equal(gx, fx);
            assert_int_equal(gy, fy);
            assert_int_equal(c2, c1);
            /* the mode's curve by rfe_tyre_dugoff_abs_pre_q31: the public function of that
             * mode's bits and counts, in both load-scaled modes */
            {
                rfe_tyre_params_q31_t tp = p.tyre;
                size_t mode;
                for (mode = 0u; mode < 2u; ++mode) {
                    uint32_t c3 = 0u;
                    uint32_t c4 = 0u;
                    tp.mode = (mode == 0u) ? RFE_TYRE_MAGIC : RFE_TYRE_ABSOLUTE;
                    assert_int_equal((mode == 0u)
                                         ? rfe_tyre_magic_abs_q31(&tp, kin.kappa[i], kin.alpha[i],
                                                                  kin.fz[i], kin.vwx[i], mu[i],
                                                                  &fx, &fy, &c3)
                                         : rfe_tyre_dugoff_abs_q31(&tp, kin.kappa[i], kin.alpha[i],
                                                                   kin.fz[i], kin.vwx[i], mu[i],
                                                                   &fx, &fy, &c3),
                                     RFE_OK);
                    rfe_tyre_dugoff_abs_pre_q31(&tp, &pre, mu[i], kin.fz[i], &gx, &gy, &c4);
                    assert_int_equal(gx, fx);
                    assert_int_equal(gy, fy);
                    assert_int_equal(c4, c3);
                }
            }
        }
        assert_int_equal(sum, sat);
    }
    {
        rfe_tyre_params_q31_t bad = p.tyre;
        assert_int_equal(rfe_tyre_dugoff_params_ok_q31(&p.tyre), 1);
        bad.shape_Cx = 0; /* the Dugoff check does not look at the shape */
        assert_int_equal(rfe_tyre_dugoff_params_ok_q31(&bad), 1);
        bad = p.tyre;
        bad.eps = -1;
        assert_int_equal(rfe_tyre_dugoff_params_ok_q31(&bad), 0);
        bad = p.tyre;
        bad.alpha_max = 0;
        assert_int_equal(rfe_tyre_dugoff_params_ok_q31(&bad), 0);
        bad = p.tyre;
        bad.v_min = 0;
        {
            rfe_wheel_kin_q31_t kin;
            rfe_tyre_kin_extra_q31_t extra;
            rfe_sample_q31_t u;
            memset(&u, 0, sizeof(u));
            assert_int_equal(rfe_tyre_kinematics_ex_q31(&p.vehicle, &bad, &u, &kin, &extra),
                             RFE_ERR_PARAM);
        }
    }
}

/* The real value of an rfe_xf_t (m 2^e). */
static double xf_value(rfe_xf_t a) { return ldexp((double)a.m, a.e); }

/* The derivative direction the tests ask for (3 2^-7 along kappa, -5 2^-6 along tan alpha,
 * 2^-1 along v_wx: mixed signs, exact in both twins), in q31 (d) and in double (dd). */
static void slip_dirs(rfe_slip_dir_q31_t *d, rfe_slip_dir_t *dd)
{
    d->k = rfe_xf_make(3, -7);
    d->tan_a = rfe_xf_make(-5, -6);
    d->vwx = rfe_xf_make(1, -1);
    if (dd != NULL) {
        dd->k = xf_value(d->k);
        dd->tan_a = xf_value(d->tan_a);
        dd->vwx = xf_value(d->vwx);
    }
}

/* The four derivatives of the q31 result o (got) and of the double twin's od (want) in one
 * order: dFx, dFy, dFx/dmu, dFy/dmu. */
static void jac_values(const rfe_tyre_jac_q31_t *o, const rfe_tyre_jac_t *od, double got[4],
                       double want[4])
{
    got[0] = xf_value(o->dfx);
    got[1] = xf_value(o->dfy);
    got[2] = xf_value(o->mfx);
    got[3] = xf_value(o->mfy);
    want[0] = od->dfx;
    want[1] = od->dfy;
    want[2] = od->mfx;
    want[3] = od->mfy;
}

/* The double twin's set-up read exactly from the q31 one (s in Q(qs); ux, uy, E and 1 - |k| in
 * Q30; tan a in Q26) and from the Q30 kappa kq it was built from, so the double code runs on the
 * very values the q31 code does; the fields the q31 set-up has not, 0. */
static void dugoff_pre_f64(const rfe_dugoff_pre_q31_t *pre, rfe_fix_t kq, rfe_dugoff_pre_t *pd)
{
    memset(pd, 0, sizeof *pd);
    pd->s = ldexp((double)pre->s, -(int)pre->qs);
    pd->ux = ldexp((double)pre->ux, -30);
    pd->uy = ldexp((double)pre->uy, -30);
    pd->e = ldexp((double)pre->e, -30);
    pd->omk = ldexp((double)pre->omk, -30);
    pd->k = ldexp((double)kq, -30);
    pd->tan_a = ldexp((double)pre->tan_a, -26);
}

/* REQ: at no slip (kappa = 0, alpha = 0: S = 0) the absolute Dugoff tyre's derivatives are the
 * linear tyre's (dFy = Fz cy d tan(alpha), dFx = Fz cx d kappa, no dependence on mu) when
 * mu > 0, and zero at mu = 0 and below (no friction: no force at any slip, so none changes). The
 * expectation is the tyre's linear limit (MODEL.md §4), not the code's formula; tolerance: the
 * three products each round to 2^-30 relative (rfe_xf_t) after the inputs' own rounding (Fz and
 * cy exact in Q15 / Q24 here, the direction exact in rfe_xf_t): 4 2^-30 < 1e-8 relative. */
/* REQ-MEAS-003 REQ-FXP-003 */
static void test_tyre_pre_jac_no_slip_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_tyre_params_q31_t tp = p.tyre;
    rfe_dugoff_pre_q31_t pre;
    rfe_slip_dir_q31_t d;
    const rfe_fix_t vwx = (rfe_fix_t)(20 * (1 << 23)); /* 20 m/s, Q23 */
    const rfe_fix_t fz = (rfe_fix_t)(4000 * (1 << 15)); /* 4000 N, Q15 */
    const rfe_fix_t mus[3] = {(rfe_fix_t)(1 << 28), 0, -(rfe_fix_t)(1 << 27)}; /* 0.5, 0, -0.25 */
    size_t j;
    (void)state;
    tp.mode = RFE_TYRE_ABSOLUTE;
    d.k = rfe_xf_make(1, -6);     /* d kappa / d vy = 2^-6 s/m: exact */
    d.tan_a = rfe_xf_make(1, -4); /* d tan(alpha) / d vy = 2^-4 s/m (1 / 16 m/s): exact */
    d.vwx = rfe_xf_make(0, 0);
    rfe_tyre_dugoff_pre_q31(&tp, 0, 0, vwx, &pre);
    assert_int_equal(pre.s, 0); /* the case under test: no slip */
    for (j = 0u; j < 3u; ++j) {
        rfe_tyre_jac_q31_t o;
        rfe_tyre_pre_jac_q31(&tp, &pre, 0, vwx, fz, mus[j], &d, &o);
        if (mus[j] > 0) {
            const double wy = 4000.0 * ldexp((double)tp.cy, -RFE_FIX_Q_STIFF) / 16.0;
            const double wx = 4000.0 * ldexp((double)tp.cx, -RFE_FIX_Q_STIFF) / 64.0;
            assert_true(fabs(xf_value(o.dfy) - wy) <= (1e-8 * wy));
            assert_true(fabs(xf_value(o.dfx) - wx) <= (1e-8 * wx));
        } else {
            assert_int_equal(o.dfy.m, 0);
            assert_int_equal(o.dfx.m, 0);
        }
        assert_int_equal(o.mfx.m, 0); /* no slip: the force (0) does not depend on mu */
        assert_int_equal(o.mfy.m, 0);
    }
}

/* The same xf value: mantissa and exponent. */
static void assert_xf_equal(rfe_xf_t a, rfe_xf_t b)
{
    assert_int_equal(a.m, b.m);
    assert_int_equal(a.e, b.e);
}

/* The same four derivatives, bit for bit. */
static void assert_jac_equal(const rfe_tyre_jac_q31_t *a, const rfe_tyre_jac_q31_t *b)
{
    assert_xf_equal(a->dfx, b->dfx);
    assert_xf_equal(a->dfy, b->dfy);
    assert_xf_equal(a->mfx, b->mfx);
    assert_xf_equal(a->mfy, b->mfy);
}

/* rfe_tyre_magic_basis_q31 at (pre, fz, mu) against rfe_tyre_pre_jac_q31 along a unit change
 * of kappa and of tan alpha, and the forces fx, fy and count sat of rfe_tyre_dugoff_abs_pre_q31,
 * bit for bit. */
static void basis_equal(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                        rfe_fix_t kappa, rfe_fix_t vwx, rfe_fix_t fz, rfe_fix_t mu, rfe_fix_t fx,
                        rfe_fix_t fy, uint32_t sat)
{
    rfe_tyre_jac_q31_t ob[2];
    rfe_fix_t fxb = 3;
    rfe_fix_t fyb = 3;
    uint32_t sb = 0u;
    size_t e;
    rfe_tyre_magic_basis_q31(tp, pre, fz, mu, &fxb, &fyb, &sb, ob);
    assert_int_equal(fx, fxb);
    assert_int_equal(fy, fyb);
    assert_int_equal(sat, sb);
    for (e = 0u; e < 2u; ++e) {
        rfe_slip_dir_q31_t u;
        rfe_tyre_jac_q31_t o;
        u.k = rfe_xf_make((e == 0u) ? 1 : 0, 0);
        u.tan_a = rfe_xf_make((e == 1u) ? 1 : 0, 0);
        u.vwx = rfe_xf_make(0, 0);
        rfe_tyre_pre_jac_q31(tp, pre, kappa, vwx, fz, mu, &u, &o);
        assert_jac_equal(&o, &ob[e]);
    }
}

/* REQ: the Magic Formula's forces and derivatives from one evaluation of each direction's
 * curve (rfe_tyre_magic_pre_jac_q31, the observer's lateral rows) are those of the two
 * separate functions (rfe_tyre_dugoff_abs_pre_q31, rfe_tyre_pre_jac_q31), bit for bit, with
 * the same saturation count: across slips, no slip (S = 0), friction above, at and below 0,
 * and loads that saturate the forces. The same for rfe_tyre_magic_basis_q31 (the step noise's
 * input derivatives): its forces and its derivatives along a unit change of kappa and of tan
 * alpha are rfe_tyre_pre_jac_q31's along those two directions, bit for bit. */
/* REQ-MEAS-003 REQ-FXP-003 */
static void test_tyre_magic_pre_jac_fused_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_tyre_params_q31_t tp = p.tyre;
    const rfe_fix_t kappas[5] = {0, (rfe_fix_t)(1 << 24), -(rfe_fix_t)(1 << 27),
                                 (rfe_fix_t)(3 << 28), -(rfe_fix_t)(1 << 30)};
    const rfe_fix_t alphas[4] = {0, (rfe_fix_t)(1 << 22), -(rfe_fix_t)(1 << 25),
                                 (rfe_fix_t)(5 << 26)};
    const rfe_fix_t mus[4] = {(rfe_fix_t)(1 << 28), (rfe_fix_t)(3 << 28), 0,
                              -(rfe_fix_t)(1 << 27)};
    const rfe_fix_t fzs[2] = {(rfe_fix_t)(4000 * (1 << 15)), RFE_FIX_MAX};
    const rfe_fix_t vwx = (rfe_fix_t)(20 * (1 << 23));
    rfe_slip_dir_q31_t d;
    size_t a;
    size_t b;
    size_t j;
    size_t k;
    (void)state;
    tp.mode = RFE_TYRE_MAGIC;
    assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 1);
    slip_dirs(&d, NULL);
    for (a = 0u; a < 5u; ++a) {
        for (b = 0u; b < 4u; ++b) {
            rfe_dugoff_pre_q31_t pre;
            rfe_tyre_dugoff_pre_q31(&tp, kappas[a], alphas[b], vwx, &pre);
            for (j = 0u; j < 4u; ++j) {
                for (k = 0u; k < 2u; ++k) {
                    rfe_tyre_jac_q31_t o1;
                    rfe_tyre_jac_q31_t o2;
                    rfe_fix_t fx1 = 1;
                    rfe_fix_t fy1 = 1;
                    rfe_fix_t fx2 = 2;
                    rfe_fix_t fy2 = 2;
                    uint32_t s1 = 0u;
                    uint32_t s2 = 0u;
                    rfe_tyre_dugoff_abs_pre_q31(&tp, &pre, mus[j], fzs[k], &fx1, &fy1, &s1);
                    rfe_tyre_pre_jac_q31(&tp, &pre, kappas[a], vwx, fzs[k], mus[j], &d, &o1);
                    rfe_tyre_magic_pre_jac_q31(&tp, &pre, fzs[k], mus[j], &d, &fx2, &fy2, &s2,
                                               &o2);
                    assert_int_equal(fx1, fx2);
                    assert_int_equal(fy1, fy2);
                    assert_int_equal(s1, s2);
                    assert_jac_equal(&o1, &o2);
                    basis_equal(&tp, &pre, kappas[a], vwx, fzs[k], mus[j], fx1, fy1, s1);
                }
            }
        }
    }
}

/* ---- the Magic Formula's derivatives against the double twin --------------------------------
 * Bound (tyre_q31.c magic_g_over_s_q31, magic_shape_jac_q31). Both twins take the same S, ux,
 * uy, tan a (the q31 set-up's, converted exactly), m, fz, shape factors and direction, so they
 * differ only by the q31 curve's angles and sine and the derivative's own roundings:
 *   - the angles: a within 0.71 LSB29 + 1.211e-9 = 2.53e-9 rad, b the same plus E times a's
 *     error, |E| <= 4: db <= 5 2.53e-9 = 1.27e-8; C b (C < 2) within 2.53e-8; G = sin(C b) and
 *     cos(C b) within 2.53e-8 + 6.2e-10 = 2.6e-8 (DG);
 *   - m G / s = G m / S within DG / (C x) + 10 2^-30 (x = s / (m C) >= 2^-8 there, C > 1):
 *     <= 2^8 DG + 1e-8 = 6.7e-6; the series below 2^-8 within x^4 + 10 2^-30 < 1e-8: E_GOS;
 *   - m dG/ds = cos(C b) d cos^2 b, d = 1 - E sin^2 a in (0, 5]: 5 DG (cos) + |E| 2 (6.2e-10 +
 *     2.53e-9) (d) + 5 1.27e-8 (cos^2 b moves with b: slope <= 1) + 5 2^-28 + 3 2^-31
 *     (roundings: cos^2 b's from the pair and its division, magic_shape_jac_q31)
 *     = 1.3e-7 + 2.5e-8 + 6.4e-8 + 2.0e-8 < 2.6e-7: E_GS;
 *   - G - s dG/ds = G - C cos(C b) d w, w = s p / (p^2 + n^2) <= 1 / (2 (1 - E)) for E > 0, <= 1/2
 *     for E <= 0 (OBSERVER.md's w; here E <= 0.6: w <= 1.25): DG + C (5 w DG + w 2.5e-8 + 5 2 w
 *     1.27e-8 (w moves with b: relative slope <= 2)) + C 5 w 2^-28 + 2^-30 (roundings: w's
 *     from the pair and its division, the product's) < 2.6e-8 + 2 (1.6e-7 + 3.1e-8 + 1.6e-7)
 *     + 4.8e-8 < 8.0e-7: E_GMS;
 * so |dF err| <= fz (|c d| E_GOS + |u ds| (E_GS + E_GOS)) and |dF/dmu err| <= fz |u| E_GMS, plus
 * 2^-27 of the terms for the rfe_xf_t products and sums that combine them (about 8 roundings
 * of 2^-30). */
#define E_GOS 6.7e-6
#define E_GS 2.6e-7
#define E_GMS 8.0e-7

/* REQ: the Magic Formula forces' derivatives by a slip direction and by the friction
 * (rfe_tyre_pre_jac_q31, magic mode) are the double twin's within the bound above, across
 * slips from the series' range to locked wheels, small and large friction and shape factors
 * with E below, at and above 0; the worst error over its bound printed. */
/* REQ-MEAS-003 REQ-FXP-003 */
static void test_tyre_magic_jac_vs_f64_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_tyre_params_q31_t tp = p.tyre;
    rfe_tyre_params_t td;
    const rfe_fix_t kappas[6] = {0, (rfe_fix_t)(1 << 14), (rfe_fix_t)(1 << 24),
                                 -(rfe_fix_t)(1 << 27), (rfe_fix_t)(3 << 28),
                                 -(rfe_fix_t)(1 << 30)};
    const rfe_fix_t alphas[5] = {0, (rfe_fix_t)(1 << 12), (rfe_fix_t)(1 << 22),
                                 -(rfe_fix_t)(1 << 25), (rfe_fix_t)(5 << 26)};
    /* mu 0.01, 0.3, 1.2 (Q29) */
    const rfe_fix_t mus[3] = {(rfe_fix_t)5368709, (rfe_fix_t)161061274, (rfe_fix_t)644245094};
    /* E (Q24): -3.5, 0, 0.6 */
    const rfe_fix_t es[3] = {-(rfe_fix_t)58720256, 0, (rfe_fix_t)10066330};
    const rfe_fix_t fz = (rfe_fix_t)(4000 * (1 << 15));
    const rfe_fix_t vwx = (rfe_fix_t)(20 * (1 << 23));
    rfe_slip_dir_q31_t d;
    rfe_slip_dir_t dd;
    double worst = 0.0;
    long compared = 0;
    size_t a;
    size_t b;
    size_t j;
    size_t e;
    (void)state;
    tp.mode = RFE_TYRE_MAGIC;
    slip_dirs(&d, &dd);
    memset(&td, 0, sizeof td);
    td.mode = RFE_TYRE_MAGIC;
    td.cx = ldexp((double)tp.cx, -RFE_FIX_Q_STIFF);
    td.cy = ldexp((double)tp.cy, -RFE_FIX_Q_STIFF);
    td.shape_Cx = ldexp((double)tp.shape_Cx, -RFE_FIX_Q_STIFF);
    td.shape_Cy = ldexp((double)tp.shape_Cy, -RFE_FIX_Q_STIFF);
    td.alpha_max = ldexp((double)tp.alpha_max, -29);
    for (e = 0u; e < 3u; ++e) {
        tp.shape_Ex = es[e];
        tp.shape_Ey = es[2u - e];
        td.shape_Ex = ldexp((double)tp.shape_Ex, -RFE_FIX_Q_STIFF);
        td.shape_Ey = ldexp((double)tp.shape_Ey, -RFE_FIX_Q_STIFF);
        assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 1);
        for (a = 0u; a < 6u; ++a) {
            for (b = 0u; b < 5u; ++b) {
                rfe_dugoff_pre_q31_t pre;
                rfe_dugoff_pre_t pd;
                double ds;
                rfe_tyre_dugoff_pre_q31(&tp, kappas[a], alphas[b], vwx, &pre);
                memset(&pd, 0, sizeof pd);
                pd.s = ldexp((double)pre.s, -(int)pre.qs);
                pd.ux = ldexp((double)pre.ux, -30);
                pd.uy = ldexp((double)pre.uy, -30);
                pd.tan_a = ldexp((double)pre.tan_a, -26);
                ds = (pd.ux * td.cx * dd.k) + (pd.uy * td.cy * dd.tan_a);
                for (j = 0u; j < 3u; ++j) {
                    const double fzd = ldexp((double)fz, -15);
                    const double cd[2] = {td.cx * dd.k, td.cy * dd.tan_a};
                    const double u[2] = {pd.ux, pd.uy};
                    rfe_tyre_jac_q31_t o;
                    rfe_tyre_jac_t od;
                    double got[4];
                    double want[4];
                    size_t r;
                    rfe_tyre_pre_jac_q31(&tp, &pre, kappas[a], vwx, fz, mus[j], &d, &o);
                    assert_int_equal(rfe_tyre_pre_jac_f64(&td, &pd, ldexp((double)kappas[a], -30),
                                                          ldexp((double)alphas[b], -29), fzd,
                                                          ldexp((double)vwx, -23),
                                                          ldexp((double)mus[j], -29), &dd, &od),
                                     RFE_OK);
                    jac_values(&o, &od, got, want);
                    for (r = 0u; r < 4u; ++r) {
                        const size_t c = r % 2u;
                        const double terms = (r < 2u)
                                                 ? (fzd * ((fabs(cd[c]) * E_GOS) +
                                                           (fabs(u[c] * ds) * (E_GS + E_GOS))))
                                                 : (fzd * fabs(u[c]) * E_GMS);
                        const double bound = terms + (ldexp(1.0, -27) * (fabs(want[r]) +
                                                      (fzd * (fabs(cd[c]) + fabs(u[c] * ds)))));
                        const double err = fabs(got[r] - want[r]);
                        if (err > bound) {
                            printf("E %zu kappa %zu alpha %zu mu %zu out %zu: q31 %.12g f64 %.12g "
                                   "bound %.3g\n", e, a, b, j, r, got[r], want[r], bound);
                        }
                        assert_true(err <= bound);
                        worst = fmax(worst, err / bound);
                        ++compared;
                    }
                }
            }
        }
    }
    printf("magic jac q31 vs f64: %ld values compared, worst |error| / bound %.3g\n", compared,
           worst);
}

/* ---- the Dugoff derivative (plain Q30 coefficients) against the double twin ---------------
 * tyre_q31.c's dugoff_jac_q31 writes, for L < 1, dF = fz (h (b_k dk + b_t dt) + mu (1 - L) u dE)
 * with h = mu E / S the only rfe_xf_t quotient and the b, mu (1 - L) u, dF/dmu = fz E (1 - L) u
 * and the forces fz w u as Q30 integers; dE (dugoff_de_q31) from the slip's cosines in Q30. The
 * expectation is tyre_flt.c's dugoff_jac in double (the g = w / S form: q = mu / (2 S), dq, dL,
 * dg; not the code's u form) from the same set-up (s, ux, uy, E, 1 - |k|, k, tan a taken exactly
 * from the q31 set-up). Bound per value, from the code's comments: the b within 2^-28 (|c1| +
 * |c2| + 1), h within 2^-29 relative, L (dugoff_l30: two 30-bit roundings and a Q30 quotient)
 * within 2^-27, which moves b by 2^-27 (|c1| + |c2| + 1) and mu (1 - L) by 4 2^-27; the
 * cosines within 2^-28 (dE within 2^-27 of eps (slip |dv| + |vwx| (|dk| + |dt|)) = de_s); the
 * 30-bit rfe_xf_t steps 2^-27 relative of the result:
 *   B = fz (2^-25 h (|c1| + |c2| + 1)(|dk| + |dt|) + 2^-24 (mu + 1) de_s) + 2^-27 |want|
 * and for dF/dmu (and paper mode's F0) fz 2^-25 (mu + 1); for L >= 1 (g = 1 / (1 - |k|),
 * relative 2^-29 per rfe_xf_t step) fz 2^-25 (|c1| |dk| g + |c1 k dk| g^2 + |c2| (|dt| g +
 * |t dk| g^2)). Points with |L - 1| < 2^-20 (either branch) are skipped. Stiffness from the
 * preset's down to 0.05 (h up to mu / (0.05 |k|)), slips to a locked wheel (1 - |k| = 2^-10),
 * eps 0 to 0.45, both signs of v_wx, friction 0.01 to 1.2 in absolute and paper mode. Fails
 * when a coefficient's formula is off (checked once: b_xk's sgn(k) term with the wrong sign). */
static double dugoff_bound(const rfe_dugoff_pre_t *pd, double c1, double c2, double eps,
                           double vwx, double mu, double fzd, const rfe_slip_dir_t *dd, size_t r,
                           double want)
{
    const double L = mu * pd->omk * pd->e / (2.0 * pd->s);
    const double cs = fabs(c1) + fabs(c2) + 1.0;
    const double dkt = fabs(dd->k) + fabs(dd->tan_a);
    const double slip = sqrt((pd->k * pd->k) + (pd->tan_a * pd->tan_a));
    const double de_s = eps * ((slip * fabs(dd->vwx)) + (fabs(vwx) * dkt));
    double b = ldexp(fzd, -25) * (mu + 1.0);
    if (pd->s <= 0.0) {
        b = ldexp(fzd, -25) * cs * dkt;
    } else if ((L < 1.0) && (r < 2u)) {
        const double h = mu * pd->e / pd->s;
        b = fzd * ((ldexp(h, -25) * cs * dkt) + (ldexp(mu + 1.0, -24) * de_s));
    } else if (L >= 1.0) {
        const double g = 1.0 / pd->omk;
        b += ldexp(fzd, -25) * ((fabs(c1 * dd->k) * g) + (fabs(c1 * pd->k * dd->k) * g * g) +
                                (fabs(c2) * ((fabs(dd->tan_a) * g) +
                                             (fabs(pd->tan_a * dd->k) * g * g))));
    } else {
        /* dF/dmu at L < 1: fz 2^-25 (mu + 1) */
    }
    return b + ldexp(fabs(want), -27);
}

/* REQ: the Dugoff forces' derivatives (absolute and paper mode) are the double twin's within
 * the bound above, across slips, stiffness, eps, v_wx and friction. */
/* REQ-MEAS-003 REQ-FXP-003 */
static void test_tyre_dugoff_jac_vs_f64_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_tyre_params_q31_t tp = p.tyre;
    rfe_tyre_params_t td;
    const rfe_fix_t kappas[7] = {0, (rfe_fix_t)(1 << 12), (rfe_fix_t)(1 << 22),
                                 -(rfe_fix_t)(1 << 27), (rfe_fix_t)(3 << 28),
                                 -(rfe_fix_t)((1 << 30) - (1 << 20)), (rfe_fix_t)(1 << 30)};
    const rfe_fix_t alphas[5] = {0, (rfe_fix_t)(1 << 12), (rfe_fix_t)(1 << 22),
                                 -(rfe_fix_t)(1 << 25), (rfe_fix_t)(5 << 26)};
    /* mu 0.01, 0.3, 1.2 (Q29) */
    const rfe_fix_t mus[3] = {(rfe_fix_t)5368709, (rfe_fix_t)161061274, (rfe_fix_t)644245094};
    /* eps 0, the preset's, 0.45 (Q32) */
    const rfe_fix_t epss[3] = {0, tp.eps, (rfe_fix_t)1932735283};
    /* v_wx 20 m/s and -3 m/s (Q23) */
    const rfe_fix_t vwxs[2] = {(rfe_fix_t)(20 * (1 << 23)), -(rfe_fix_t)(3 * (1 << 23))};
    /* the preset's stiffness and 0.05 (Q24) */
    const rfe_fix_t stiff[2] = {0, (rfe_fix_t)838861};
    const rfe_fix_t fz = (rfe_fix_t)(4000 * (1 << 15));
    const double fzd = 4000.0;
    rfe_slip_dir_q31_t d;
    rfe_slip_dir_t dd;
    double worst = 0.0;
    long compared = 0;
    size_t mode;
    (void)state;
    slip_dirs(&d, &dd);
    for (mode = 0u; mode < 2u; ++mode) {
        size_t ic;
        /* 12 cases: stiffness (2) x eps (3) x v_wx (2) */
        for (ic = 0u; ic < 12u; ++ic) {
            const size_t is = ic % 2u;
            const size_t ie = (ic / 2u) % 3u;
            const size_t iv = ic / 6u;
            size_t a;
            tp = p.tyre;
            tp.mode = (mode == 0u) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_PAPER;
            tp.eps = epss[ie];
            if (stiff[is] != 0) {
                tp.cx = stiff[is];
                tp.Cx_n = stiff[is];
            }
            memset(&td, 0, sizeof td);
            td.mode = tp.mode;
            td.cx = ldexp((double)tp.cx, -RFE_FIX_Q_STIFF);
            td.cy = ldexp((double)tp.cy, -RFE_FIX_Q_STIFF);
            td.Cx_n = ldexp((double)tp.Cx_n, -RFE_FIX_Q_STIFF);
            td.Cy_n = ldexp((double)tp.Cy_n, -RFE_FIX_Q_STIFF);
            td.eps = ldexp((double)tp.eps, -RFE_FIX_Q_EPS);
            td.alpha_max = ldexp((double)tp.alpha_max, -29);
            assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 1);
            for (a = 0u; a < 35u; ++a) {
                const rfe_fix_t kq = kappas[a / 5u];
                const rfe_fix_t aq = alphas[a % 5u];
                const rfe_fix_t vwx = vwxs[iv];
                const double c1 = (mode == 0u) ? td.cx : td.Cx_n;
                const double c2 = (mode == 0u) ? td.cy : td.Cy_n;
                rfe_dugoff_pre_q31_t pre;
                rfe_dugoff_pre_t pd;
                size_t j;
                if (mode == 0u) {
                    rfe_tyre_dugoff_pre_q31(&tp, kq, aq, vwx, &pre);
                } else {
                    rfe_tyre_norm_pre_q31(&tp, kq, aq, vwx, &pre);
                }
                dugoff_pre_f64(&pre, kq, &pd);
                for (j = 0u; j < 3u; ++j) {
                    const double mud = ldexp((double)mus[j], -29);
                    const double mus_d = (mode == 0u) ? mud : 1.0;
                    const double L = mus_d * pd.omk * pd.e / (2.0 * pd.s);
                    rfe_tyre_jac_q31_t o;
                    rfe_tyre_jac_t od;
                    double got[4];
                    double want[4];
                    size_t r;
                    if ((pd.s > 0.0) && (fabs(L - 1.0) < ldexp(1.0, -20))) {
                        continue; /* the branch may differ by the rounding of L */
                    }
                    rfe_tyre_pre_jac_q31(&tp, &pre, kq, vwx, fz, mus[j], &d, &o);
                    assert_int_equal(rfe_tyre_pre_jac_f64(&td, &pd, pd.k,
                                                          ldexp((double)aq, -29), fzd,
                                                          ldexp((double)vwx, -23), mud, &dd,
                                                          &od),
                                     RFE_OK);
                    jac_values(&o, &od, got, want);
                    for (r = 0u; r < 4u; ++r) {
                        /* paper mode: dF = mu dF0 (one more 2^-30 step), F0 at mu_s = 1 */
                        const double scale = ((mode == 1u) && (r < 2u)) ? mud : 1.0;
                        const double bound =
                            scale * dugoff_bound(&pd, c1, c2, td.eps, ldexp((double)vwx, -23),
                                                 mus_d, fzd, &dd, r, want[r] / scale);
                        const double err = fabs(got[r] - want[r]);
                        if (err > bound) {
                            printf("mode %zu case %zu slip %zu mu %zu out %zu: q31 %.12g f64 "
                                   "%.12g bound %.3g\n", mode, ic, a, j, r, got[r], want[r],
                                   bound);
                        }
                        assert_true(err <= bound);
                        worst = fmax(worst, err / bound);
                        ++compared;
                    }
                }
            }
        }
    }
    printf("dugoff jac q31 vs f64: %ld values compared, worst |error| / bound %.3g\n", compared,
           worst);
}

/* ---- the Dugoff derivative's two rfe_xf_t branches against the double twin ----------------
 * dugoff_jac_q31 keeps two branches in rfe_xf_t: L >= 1 (S > 0: g = 1 / (1 - |k|), no range
 * as the wheel locks) and S = 0 (no slip: g = 1 for mu > 0, 0 at mu = 0). The points below are
 * chosen in them (small slips on a soft tyre: L = mu (1 - |k|) E / (2 S) >> 1; a wheel near
 * lock, 1 - |k| down to 2^-10, so g up to 2^10; and k = t = 0), checked in double from the same
 * set-up, and the test counts them: it fails if fewer points than built take a branch. The
 * expectation is tyre_flt.c's dugoff_jac in double (dugoff_g's g = 1 / (1 - |k|), dg = sgn(k)
 * dk / (1 - |k|)^2; S = 0: g = 1 or 0, dg = 0) from the same set-up values. Bound, counting the
 * rfe_xf_t roundings (each 2^-30 relative, half an LSB of a mantissa >= 2^29) in the branch's
 * code: fz c (fz in Q15 and c in Q24 each to 30 bits, their product: 3); g0 = 1 / (1 - |k|)
 * (the quotient: 1; 1 - |k| and k are exact Q30); dv g0: 2; g1 = sgn(k) dk g0^2: 2 + 1 + 1 = 4,
 * k g1 (tan a Q26 to 30 bits, the product): 6; their sum: 1 of |dv g0| + |k g1|; the product by
 * fz c: 3 + 1; paper mode's mu dF0: 1. At most 12 2^-30 < 2^-26.4 of
 *   T = fz |c1| (|dk| g + |k dk| g^2)   (dFx; dFy with |c2|, |dt| and |t|; paper mode mu T),
 * so B = 2^-26 T (the double's own rounding, ~2^-50 relative, far below). dF/dmu is 0 in both
 * (absolute mode: exactly); paper mode's dF/dmu = F0 = fz c k g: 3 + 1 + 1 + 1 roundings, B =
 * 2^-27 |fz c k g|. At S = 0: dF = fz c d (4 roundings, with paper mode's mu 5), B = 2^-27
 * fz |c| |d| (paper mode mu times it), and at mu = 0 (absolute) 0 exactly; F0 = 0 exactly. */
static void dugoff_branch_check(const rfe_tyre_params_q31_t *tp, const rfe_tyre_params_t *td,
                                rfe_fix_t kq, rfe_fix_t aq, rfe_fix_t vwx, rfe_fix_t mu,
                                const rfe_slip_dir_q31_t *d, const rfe_slip_dir_t *dd,
                                size_t *n_l1, size_t *n_s0, double *worst)
{
    const rfe_fix_t fz = (rfe_fix_t)(4000 * (1 << 15));
    const double fzd = 4000.0;
    const int paper = (tp->mode == RFE_TYRE_PAPER) ? 1 : 0;
    const double c[2] = {(paper != 0) ? td->Cx_n : td->cx, (paper != 0) ? td->Cy_n : td->cy};
    const double dv[2] = {dd->k, dd->tan_a};
    const double mud = ldexp((double)mu, -29);
    const double mus = (paper != 0) ? 1.0 : mud;
    const double dscale = (paper != 0) ? mud : 1.0; /* paper mode: dF = mu dF0 */
    rfe_dugoff_pre_q31_t pre;
    rfe_dugoff_pre_t pd;
    rfe_tyre_jac_q31_t o;
    rfe_tyre_jac_t od;
    double g;
    double kt[2];
    double got[4];
    double want[4];
    double bound[4];
    size_t r;
    if (paper != 0) {
        rfe_tyre_norm_pre_q31(tp, kq, aq, vwx, &pre);
    } else {
        rfe_tyre_dugoff_pre_q31(tp, kq, aq, vwx, &pre);
    }
    dugoff_pre_f64(&pre, kq, &pd);
    kt[0] = pd.k;
    kt[1] = pd.tan_a;
    if (pd.s > 0.0) {
        const double L = mus * pd.omk * pd.e / (2.0 * pd.s);
        if (L < 1.0 + ldexp(1.0, -20)) {
            return; /* not this test's branch (or too near L = 1 to know which) */
        }
        ++*n_l1;
        g = 1.0 / pd.omk;
        for (r = 0u; r < 2u; ++r) {
            const double t = fzd * fabs(c[r]) * ((fabs(dv[r]) * g) + (fabs(kt[r] * dd->k) * g * g));
            bound[r] = ldexp(t * dscale, -26);
            bound[2u + r] = ldexp(fzd * fabs(c[r] * kt[r]) * g, -27);
        }
    } else {
        ++*n_s0;
        for (r = 0u; r < 2u; ++r) {
            bound[r] = ldexp(fzd * fabs(c[r] * dv[r]) * dscale, -27);
            bound[2u + r] = 0.0;
        }
    }
    rfe_tyre_pre_jac_q31(tp, &pre, kq, vwx, fz, mu, d, &o);
    assert_int_equal(rfe_tyre_pre_jac_f64(td, &pd, pd.k, ldexp((double)aq, -29), fzd,
                                          ldexp((double)vwx, -23), mud, dd, &od),
                     RFE_OK);
    got[0] = xf_value(o.dfx);
    got[1] = xf_value(o.dfy);
    got[2] = xf_value(o.mfx);
    got[3] = xf_value(o.mfy);
    want[0] = od.dfx;
    want[1] = od.dfy;
    want[2] = od.mfx;
    want[3] = od.mfy;
    for (r = 0u; r < 4u; ++r) {
        const double err = fabs(got[r] - want[r]);
        if (err > bound[r]) {
            printf("mode %d kappa %ld alpha %ld mu %ld out %zu: q31 %.12g f64 %.12g bound %.3g\n",
                   (int)tp->mode, (long)kq, (long)aq, (long)mu, r, got[r], want[r], bound[r]);
        }
        assert_true(err <= bound[r]);
        if (bound[r] > 0.0) {
            *worst = fmax(*worst, err / bound[r]);
        }
    }
}

/* REQ: the Dugoff forces' derivatives in their L >= 1 and S = 0 branches (absolute and paper
 * mode) are the double twin's within the bound above. */
/* REQ-MEAS-003 REQ-FXP-003 */
static void test_tyre_dugoff_jac_l1_s0_vs_f64_q31(void **state)
{
    const rfe_params_q31_t p = preset();
    /* small slips and a wheel near lock (Q30: 2^-18, -2^-12, 2^-8, 1 - 2^-10; 0) */
    const rfe_fix_t kappas[5] = {0, (rfe_fix_t)(1 << 12), -(rfe_fix_t)(1 << 18),
                                 (rfe_fix_t)(1 << 22), (rfe_fix_t)((1 << 30) - (1 << 20))};
    /* small slip angles (Q29 rad: 0, 2^-17, -2^-10) */
    const rfe_fix_t alphas[3] = {0, (rfe_fix_t)(1 << 12), -(rfe_fix_t)(1 << 19)};
    /* mu 0, 0.3, 1.2 (Q29) */
    const rfe_fix_t mus[3] = {0, (rfe_fix_t)161061274, (rfe_fix_t)644245094};
    /* v_wx 20 m/s and -3 m/s (Q23) */
    const rfe_fix_t vwxs[2] = {(rfe_fix_t)(20 * (1 << 23)), -(rfe_fix_t)(3 * (1 << 23))};
    /* eps 0 and 0.45 (Q32); stiffness: the preset's and 0.05 (Q24) */
    const rfe_fix_t epss[2] = {0, (rfe_fix_t)1932735283};
    const rfe_fix_t stiff[2] = {0, (rfe_fix_t)838861};
    rfe_slip_dir_q31_t d;
    rfe_slip_dir_t dd;
    size_t n_l1 = 0u;
    size_t n_s0 = 0u;
    double worst = 0.0;
    size_t n;
    (void)state;
    slip_dirs(&d, &dd);
    /* mode (2) x stiffness (2) x eps (2) x v_wx (2) x kappa (5) x alpha (3) x mu (3) */
    for (n = 0u; n < 720u; ++n) {
        rfe_tyre_params_q31_t tp = p.tyre;
        rfe_tyre_params_t td;
        const size_t im = n % 2u;
        const size_t is = (n / 2u) % 2u;
        const size_t ie = (n / 4u) % 2u;
        const size_t iv = (n / 8u) % 2u;
        const size_t ik = (n / 16u) % 5u;
        const size_t ia = (n / 80u) % 3u;
        const size_t ju = n / 240u;
        tp.mode = (im == 0u) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_PAPER;
        tp.eps = epss[ie];
        if (stiff[is] != 0) {
            tp.cx = stiff[is];
            tp.cy = stiff[is];
            tp.Cx_n = stiff[is];
            tp.Cy_n = stiff[is];
        }
        assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 1);
        memset(&td, 0, sizeof td);
        td.mode = tp.mode;
        td.cx = ldexp((double)tp.cx, -RFE_FIX_Q_STIFF);
        td.cy = ldexp((double)tp.cy, -RFE_FIX_Q_STIFF);
        td.Cx_n = ldexp((double)tp.Cx_n, -RFE_FIX_Q_STIFF);
        td.Cy_n = ldexp((double)tp.Cy_n, -RFE_FIX_Q_STIFF);
        td.eps = ldexp((double)tp.eps, -RFE_FIX_Q_EPS);
        td.alpha_max = ldexp((double)tp.alpha_max, -29);
        dugoff_branch_check(&tp, &td, kappas[ik], alphas[ia], vwxs[iv], mus[ju], &d, &dd, &n_l1,
                            &n_s0, &worst);
    }
    printf("dugoff jac q31 vs f64, L >= 1: %zu points, S = 0: %zu points, worst |error| / bound "
           "%.3g\n", n_l1, n_s0, worst);
    assert_true(n_l1 >= 100u);
    assert_true(n_s0 == 48u); /* k = t = 0: 2 modes x 2 stiffness x 2 eps x 2 v_wx x 3 mu */
}

/* ---- the Magic Formula derivative's factors in Q30 against the formulas in double ----------
 * tyre_q31.c computes, per direction, m G / s (magic_g_over_s_q31), m dG/ds and G - s dG/ds
 * (magic_shape_jac_q31) as Q30 integers and combines them (magic_dfs_q31) into
 *   dFx = fz (Pxk cx dk + Pxt cy dt),  dFy = fz (Pyk cx dk + Pyt cy dt),  dFx/dmu = fz ux gms_x,
 * Pxk = gos_x + (gs_x - gos_x) ux^2, Pxt = (gs_x - gos_x) ux uy (y alike with uy^2). The unit
 * directions (dk, dt) = (1, 0) and (0, 1) give each coefficient alone: Pxk = dFx / (fz cx) and
 * so on, and gms = dF/dmu / (fz u); the division by the exact fz cx (fz u) adds nothing, the
 * rfe_xf_t steps that carry the coefficient out (a rounding to 30 bits of fz P, one product,
 * the sum with an exact 0) are 2 2^-30 relative. The expectation is the formulas written out in
 * double from the same s, ux, uy, m, C, E (p = m C, a = atan2(s, p), n = s - E (s - p a),
 * b = atan2(n, p), G = sin(C b), dn/ds = 1 - E + E p^2 / (p^2 + s^2), db/ds = p dn/ds /
 * (p^2 + n^2), dG/ds = C cos(C b) db/ds), not the code's angle form. Bound per value:
 *   - the q31 curve's angles (test_tyre_magic_jac_vs_f64_q31 above): G and cos(C b) within
 *     DG = 2.6e-8, b within 1.27e-8;
 *   - gos: above x = s / (m C) = 2^-8 the quotient, DG / (C x) + 2^-30 (Q29 quotient, its
 *     numerator's rounding); below, the series' x^4 + 4 2^-30 (x within 2^-30, x^2, C^2 / 6, the
 *     division by 6: magic_g_over_s_q31); within 2^-20 of the line both (either branch);
 *   - gs: E_GS (above; with cos^2 b's 2^-28 from the pair and the one division, 2.45e-7);
 *   - gms: DG + C w (5 DG + 2.5e-8 + 10 1.27e-8 + 5.2e-8) + 2^-30, w = s p / (p^2 + n^2);
 *   - the coefficients: their factors' errors times ux^2 <= 1 (or |ux uy|), the rounding of
 *     u^2 to Q30 (2^-31 times |gs - gos| <= 10), gs - gos rounded to Q27 (2^-28 times u^2 <= 1)
 *     and gos and the product rounded to Q28 (2^-29 each): magic_dfs_q31;
 * each plus 2^-28 relative for the rfe_xf_t steps. Shape factors at the domain's edges (C 1.05
 * and 1.95, E -4 and 0.95, where w's bound is 2^4 and the quotient keeps 26 bits) and the
 * preset's; slips from the series' range to a locked wheel, friction 0.01 to 1.2. Fails when a
 * factor's formula, shift or rounding is off (checked with cos^2 b's exponent off by one and
 * with the series' 6 as 3). */
#define DG_ANGLE 2.6e-8
#define DB_ANGLE 1.27e-8

static double magic_w_f64(double s, double m, double C, double E)
{
    const double p = m * C;
    const double a = atan2(s, p);
    const double n = s - (E * (s - (p * a)));
    return (s * p) / ((p * p) + (n * n));
}

/* gos, gs, gms of one direction in double (the formulas above). */
static void magic_factors_f64(double s, double m, double C, double E, double f[3])
{
    const double p = m * C;
    const double a = atan2(s, p);
    const double n = s - (E * (s - (p * a)));
    const double b = atan2(n, p);
    const double G = sin(C * b);
    const double dn = (1.0 - E) + ((E * p * p) / ((p * p) + (s * s)));
    const double dgds = C * cos(C * b) * p * dn / ((p * p) + (n * n));
    f[0] = m * G / s;
    f[1] = m * dgds;
    f[2] = G - (s * dgds);
}

static double gos_bound(double s, double m, double C)
{
    const double x = s / (m * C);
    const double line = ldexp(1.0, -8);
    double b = 0.0;
    if (x < (line * (1.0 + ldexp(1.0, -20)))) {
        b += (x * x * x * x) + ldexp(4.0, -30);
    }
    if (x > (line * (1.0 - ldexp(1.0, -20)))) {
        b += (DG_ANGLE / (C * x)) + ldexp(1.0, -30);
    }
    return b;
}

/* REQ: the Magic Formula derivative's bounded factors (m G / s, m dG/ds, G - s dG/ds, Q30
 * integers) and their combination with the direction cosines are the formulas' in double
 * within the bound above, across shape factors at the domain's edges, slips and friction. */
/* REQ-MEAS-003 REQ-FXP-003 */
static void test_tyre_magic_factors_vs_f64_q31(void **state)
{
    rfe_params_q31_t p = preset();
    rfe_tyre_params_q31_t tp = p.tyre;
    const rfe_fix_t kappas[7] = {(rfe_fix_t)(1 << 12), (rfe_fix_t)(1 << 18),
                                 -(rfe_fix_t)(1 << 24), (rfe_fix_t)(1 << 27),
                                 -(rfe_fix_t)(3 << 28), (rfe_fix_t)(1 << 30), 0};
    const rfe_fix_t alphas[6] = {0, (rfe_fix_t)(1 << 10), -(rfe_fix_t)(1 << 20),
                                 (rfe_fix_t)(1 << 25), -(rfe_fix_t)(5 << 26),
                                 (rfe_fix_t)(1 << 29)};
    /* mu 0.01, 0.3, 1.2 (Q29) */
    const rfe_fix_t mus[3] = {(rfe_fix_t)5368709, (rfe_fix_t)161061274, (rfe_fix_t)644245094};
    /* C (Q24): 1.05, the preset's x, 1.95; E (Q24): -4, 0, 0.95 */
    const rfe_fix_t cs[3] = {(rfe_fix_t)17616077, tp.shape_Cx, (rfe_fix_t)32715571};
    const rfe_fix_t es[3] = {-(rfe_fix_t)67108864, 0, (rfe_fix_t)15938355};
    const rfe_fix_t fz = (rfe_fix_t)(4000 * (1 << 15));
    const rfe_fix_t vwx = (rfe_fix_t)(20 * (1 << 23));
    const double fzd = 4000.0;
    const double cxd = ldexp((double)tp.cx, -RFE_FIX_Q_STIFF);
    const double cyd = ldexp((double)tp.cy, -RFE_FIX_Q_STIFF);
    rfe_slip_dir_q31_t dk;
    rfe_slip_dir_q31_t dt;
    double worst = 0.0;
    long compared = 0;
    size_t ic;
    size_t ie;
    size_t a;
    size_t b;
    size_t j;
    (void)state;
    tp.mode = RFE_TYRE_MAGIC;
    dk.k = rfe_xf_make(1, 0);
    dk.tan_a = rfe_xf_make(0, 0);
    dk.vwx = rfe_xf_make(0, 0);
    dt = dk;
    dt.k = rfe_xf_make(0, 0);
    dt.tan_a = rfe_xf_make(1, 0);
    for (ic = 0u; ic < 3u; ++ic) {
        for (ie = 0u; ie < 3u; ++ie) {
            tp.shape_Cx = cs[ic];
            tp.shape_Cy = cs[2u - ic];
            tp.shape_Ex = es[ie];
            tp.shape_Ey = es[(ie + 1u) % 3u];
            assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 1);
            for (a = 0u; a < 7u; ++a) {
                for (b = 0u; b < 6u; ++b) {
                    rfe_dugoff_pre_q31_t pre;
                    double s;
                    double u[2];
                    rfe_tyre_dugoff_pre_q31(&tp, kappas[a], alphas[b], vwx, &pre);
                    if (pre.s == 0) {
                        continue; /* no curve: test_tyre_pre_jac_no_slip_q31's case */
                    }
                    s = ldexp((double)pre.s, -(int)pre.qs);
                    u[0] = ldexp((double)pre.ux, -30);
                    u[1] = ldexp((double)pre.uy, -30);
                    for (j = 0u; j < 3u; ++j) {
                        const double m = ldexp((double)mus[j], -29);
                        const double C[2] = {ldexp((double)tp.shape_Cx, -24),
                                             ldexp((double)tp.shape_Cy, -24)};
                        const double E[2] = {ldexp((double)tp.shape_Ex, -24),
                                             ldexp((double)tp.shape_Ey, -24)};
                        rfe_tyre_jac_q31_t ok;
                        rfe_tyre_jac_q31_t ot;
                        double got[6];
                        double want[6];
                        double bound[6];
                        size_t r;
                        size_t c;
                        rfe_tyre_pre_jac_q31(&tp, &pre, kappas[a], vwx, fz, mus[j], &dk, &ok);
                        rfe_tyre_pre_jac_q31(&tp, &pre, kappas[a], vwx, fz, mus[j], &dt, &ot);
                        got[0] = xf_value(ok.dfx) / (fzd * cxd); /* Pxk */
                        got[1] = xf_value(ot.dfx) / (fzd * cyd); /* Pxt */
                        got[2] = xf_value(ok.dfy) / (fzd * cxd); /* Pyk */
                        got[3] = xf_value(ot.dfy) / (fzd * cyd); /* Pyt */
                        got[4] = (u[0] != 0.0) ? (xf_value(ok.mfx) / (fzd * u[0])) : 0.0;
                        got[5] = (u[1] != 0.0) ? (xf_value(ok.mfy) / (fzd * u[1])) : 0.0;
                        for (c = 0u; c < 2u; ++c) {
                            double f[3];
                            const double uu = u[c] * u[c];
                            const double uxy = u[0] * u[1];
                            const double eg = gos_bound(s, m, C[c]);
                            const double w = magic_w_f64(s, m, C[c], E[c]);
                            double dd;
                            magic_factors_f64(s, m, C[c], E[c], f);
                            dd = f[1] - f[0];
                            /* Pck (c = x) / Pct (c = y): gos + dd u_c^2; the other: dd ux uy */
                            want[(2u * c) + c] = f[0] + (dd * uu);
                            bound[(2u * c) + c] = (eg * (1.0 - uu)) + (E_GS * uu) +
                                                  (10.0 * ldexp(1.0, -31)) +
                                                  ldexp(1.0, -28) + ldexp(2.0, -29);
                            want[(2u * c) + (1u - c)] = dd * uxy;
                            bound[(2u * c) + (1u - c)] = ((eg + E_GS) * fabs(uxy)) +
                                                         (10.0 * ldexp(1.0, -31)) +
                                                         ldexp(1.0, -28) + ldexp(1.0, -29);
                            want[4u + c] = (u[c] != 0.0) ? f[2] : 0.0;
                            bound[4u + c] =
                                DG_ANGLE +
                                (C[c] * w *
                                 ((5.0 * DG_ANGLE) + 2.5e-8 + (10.0 * DB_ANGLE) + 5.2e-8)) +
                                ldexp(1.0, -30);
                        }
                        for (r = 0u; r < 6u; ++r) {
                            const double bd = bound[r] + (ldexp(1.0, -28) * fabs(want[r]));
                            const double err = fabs(got[r] - want[r]);
                            if (err > bd) {
                                printf("C %zu E %zu kappa %zu alpha %zu mu %zu value %zu: q31 "
                                       "%.12g f64 %.12g bound %.3g\n",
                                       ic, ie, a, b, j, r, got[r], want[r], bd);
                            }
                            assert_true(err <= bd);
                            worst = fmax(worst, err / bd);
                            ++compared;
                        }
                    }
                }
            }
        }
    }
    printf("magic factors q31 vs f64: %ld values compared, worst |error| / bound %.3g\n",
           compared, worst);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_tyre_internal_q31),
        cmocka_unit_test(test_tyre_pre_jac_no_slip_q31),
        cmocka_unit_test(test_tyre_magic_pre_jac_fused_q31),
        cmocka_unit_test(test_tyre_magic_jac_vs_f64_q31),
        cmocka_unit_test(test_tyre_magic_factors_vs_f64_q31),
        cmocka_unit_test(test_tyre_dugoff_jac_vs_f64_q31),
        cmocka_unit_test(test_tyre_dugoff_jac_l1_s0_vs_f64_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
