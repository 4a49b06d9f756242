/**
 * @file test_tyre_id_flt.c
 * @brief The tyre identifier's API, weights and resampling (docs/TYRE_ID.md): parameters,
 *        argument checks (the state untouched, memcmp), log-sum-exp with extreme
 *        log-likelihoods, the parent search and both draws on hand-derived weights, the
 *        order by weight, the reflection, the bounds after every step of a log, the
 *        status bits (FIRST, HELD, UPDATED, RESAMPLED, LOST) and the spread on straight
 *        driving. Agreement with the reference: test_tyre_id_golden_flt.c.
 *
 * Tolerances.
 * - Hand-derived weights (log-sum-exp): w = 1 / (1 + e) and e / (1 + e) for log weights 1
 *   apart, a few float ulps of rounding in exp, the sum and the division: 1e-6 relative in
 *   float, 1e-14 in double.
 * - The friction ellipse (§3.5) against its formula evaluated here in double: the library
 *   multiplies each cubature point's force by the same factor (every point has the prior's
 *   D when its sd is 0) and averages 20 points, a few roundings of the float or double
 *   format each; the factor itself is a handful of operations: TOL_ELL 1e-5 relative in float
 *   (~80 float ulps), 1e-12 in double.
 * - Everything else is exact: indices, orders, the reflection's hand cases (each is one
 *   subtraction of values exact in binary), bounds (the reflection ends with a clip onto
 *   [lo, hi], so no rounding may cross them).
 */
#include "test_common.h"

#include <stdlib.h>
#include <stddef.h>
#include <string.h>

#include "csv_log.h"
#include "estimators/tyre_id/tyre_id_internal.h"
#include "rfe/tyre_id.h"

#if defined(RFE_REAL_DOUBLE)
#define TOL_W 1e-14
#define TOL_ELL 1e-12
#define TOL_CLIP 1e-12
#define SD_R_OVERFLOW 1e-160 /* (1e-3 / sd_r)^2 overflows the double */
#else
#define TOL_W 1e-6
#define TOL_ELL 1e-5
#define TOL_CLIP 1e-5
#define SD_R_OVERFLOW 1e-30  /* (1e-3 / sd_r)^2 overflows the float */
#endif

static rfe_tyre_id_t tid;    /* off the stack: tens of kB */
static rfe_tyre_id_t before; /* a copy for the untouched checks */

static void setup_defaults(rfe_params_t *veh, rfe_tyre_id_params_t *tp)
{
    /* zeroed first: the double build's parameter struct has 4 bytes of padding after its
     * 32-bit fields, which init copies into the state with the rest; the state comparisons
     * (memcmp) then read defined bytes (valgrind) */
    memset(veh, 0, sizeof(*veh));
    memset(tp, 0, sizeof(*tp));
    assert_int_equal(rfe_params_default(veh), RFE_OK);
    assert_int_equal(rfe_tyre_id_params_default(tp), RFE_OK);
}

static rfe_tyre_id_sample_t sample(rfe_real_t dt, rfe_real_t delta, rfe_real_t vx, rfe_real_t r,
                                   rfe_real_t ay)
{
    rfe_tyre_id_sample_t s;
    s.dt = dt;
    s.delta = delta;
    s.vx = vx;
    s.yaw_rate = r;
    s.ay = ay;
    s.ax = 0;
    return s;
}

/* REQ-TID-007 */
static void test_params_defaults_and_validation(void **state)
{
    rfe_tyre_id_params_t p;
    rfe_tyre_id_params_t q;
    rfe_real_t *reals[] = {&q.v_min, &q.dt_max, &q.sd_r, &q.sd_ay, &q.sd_delta, &q.q_vy,
                           &q.q_r, &q.q_mu, &q.q_C, &q.q_cy, &q.q_E, &q.sd0_mu, &q.sd0_C,
                           &q.sd0_E, &q.sd0_cy_rel, &q.sd0_vy, &q.sd0_r, &q.rough_k,
                           &q.delta_q, &q.delta_state_q, &q.mu0, &q.neff_frac, &q.mu_lo, &q.mu_hi, &q.C_lo, &q.C_hi,
                           &q.cy_lo, &q.cy_hi, &q.E_lo, &q.E_hi};
    size_t i;
    (void)state;
    assert_int_equal(rfe_tyre_id_params_default(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_id_params_validate(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_id_params_default(&p), RFE_OK);
    /* TYRE_ID.md §2 */
    assert_int_equal(p.filter, RFE_TID_APF);
    assert_int_equal(p.resample, RFE_TID_MULTINOMIAL);
    assert_int_equal(p.substeps, 1u);
    assert_true(p.v_min == (rfe_real_t)5.0 && p.sd_r == (rfe_real_t)0.01);
    assert_true(p.sd_ay == (rfe_real_t)0.2 && p.sd_delta == (rfe_real_t)0.001);
    assert_true(p.q_cy == (rfe_real_t)0.3 && p.mu0 == (rfe_real_t)0.7);
    assert_true(p.cy_lo == (rfe_real_t)4.0 && p.cy_hi == (rfe_real_t)40.0);
    assert_true(p.E_lo == (rfe_real_t)-3.0 && p.E_hi == (rfe_real_t)0.95);
    assert_true(p.neff_frac == (rfe_real_t)(1.0 / 3.0) && p.rough_k == (rfe_real_t)0.2);
    assert_true(p.delta_q == (rfe_real_t)0.0); /* the steering-angle filter off (§4.4) */
    assert_true(p.delta_state_q == (rfe_real_t)0.0); /* delta not a state (§15.7) */
    assert_int_equal(rfe_tyre_id_params_validate(&p), RFE_OK);
    /* every real field non-finite */
    for (i = 0u; i < sizeof(reals) / sizeof(reals[0]); ++i) {
        q = p;
        *reals[i] = (rfe_real_t)NAN;
        assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
        q = p;
        *reals[i] = (rfe_real_t)INFINITY;
        assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    }
    /* the first four must be > 0, the next sixteen >= 0 */
    for (i = 0u; i < 20u; ++i) {
        q = p;
        *reals[i] = (rfe_real_t)-1e-3;
        assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
        q = p;
        *reals[i] = 0;
        assert_int_equal(rfe_tyre_id_params_validate(&q), (i < 4u) ? RFE_ERR_PARAM : RFE_OK);
    }
    /* §15.7 delta as a state and §4.4's steering-angle filter: each alone, never both */
    q = p;
    q.delta_state_q = (rfe_real_t)0.04;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_OK);
    q.delta_q = (rfe_real_t)0.05;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q.delta_state_q = 0;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_OK);
    q = p;
    q.neff_frac = (rfe_real_t)1.5;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.neff_frac = (rfe_real_t)-0.1;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.C_lo = q.C_hi; /* lo < hi */
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.E_hi = q.E_lo - 1;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.mu_lo = 0; /* D > 0 */
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.C_lo = 0;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.cy_lo = 0;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.E_lo = -10; /* E may be negative */
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_OK);
    q = p;
    q.filter = RFE_TID_SCKF; /* the sigma-point filter of §15 */
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_OK);
    q.filter = (rfe_tid_filter_t)3;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.resample = (rfe_tid_resample_t)2;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q = p;
    q.substeps = 0u;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q.substeps = (uint32_t)RFE_TID_SUBSTEPS_MAX + 1u;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
    q.substeps = (uint32_t)RFE_TID_SUBSTEPS_MAX;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_OK);
}

/* Each of @p n bad values of the key at @p offset (an rfe_real_t of the parameters), the
 * ellipse on and the other keys at @p tp's, is refused by the validation and by an init of the
 * file's tid. */
static void ellipse_key_refused(const rfe_params_t *veh, const rfe_tyre_id_params_t *tp,
                                size_t offset, const rfe_real_t *bad, size_t n)
{
    size_t i;
    for (i = 0u; i < n; ++i) {
        rfe_tyre_id_params_t q = *tp;
        q.ellipse = 1;
        memcpy((unsigned char *)&q + offset, &bad[i], sizeof(rfe_real_t));
        assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_ERR_PARAM);
        assert_int_equal(rfe_tyre_id_init(&tid, &q, veh, 1u), RFE_ERR_PARAM);
    }
}

/* REQ-TID-007 REQ-TID-009: the friction ellipse's keys (§2, §3.5): defaults, ranges, and an
 * init refused for each leaves the state as it was. */
static void test_ellipse_params(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_params_t q;
    const rfe_real_t bad_switch[] = {(rfe_real_t)0.5, -1, 2, (rfe_real_t)NAN, (rfe_real_t)INFINITY};
    const rfe_real_t bad_share[] = {(rfe_real_t)-0.01, (rfe_real_t)1.01, (rfe_real_t)NAN};
    const rfe_real_t bad_floor[] = {0, (rfe_real_t)-0.1, (rfe_real_t)1.01, (rfe_real_t)NAN};
    const rfe_real_t bad_band[] = {(rfe_real_t)-0.01, (rfe_real_t)20.01, (rfe_real_t)NAN,
                                   (rfe_real_t)INFINITY};
    (void)state;
    setup_defaults(&veh, &tp);
    assert_true(tp.ellipse == 0 && tp.fx_front == (rfe_real_t)0.625 &&
                tp.ell_min == (rfe_real_t)0.1 && tp.ell_ax_min == (rfe_real_t)0.6);
    memset(&tid, 0x5A, sizeof(tid));
    before = tid;
    ellipse_key_refused(&veh, &tp, offsetof(rfe_tyre_id_params_t, ellipse), bad_switch,
                        sizeof(bad_switch) / sizeof(bad_switch[0]));
    ellipse_key_refused(&veh, &tp, offsetof(rfe_tyre_id_params_t, fx_front), bad_share,
                        sizeof(bad_share) / sizeof(bad_share[0]));
    ellipse_key_refused(&veh, &tp, offsetof(rfe_tyre_id_params_t, ell_min), bad_floor,
                        sizeof(bad_floor) / sizeof(bad_floor[0]));
    ellipse_key_refused(&veh, &tp, offsetof(rfe_tyre_id_params_t, ell_ax_min), bad_band,
                        sizeof(bad_band) / sizeof(bad_band[0]));
    assert_memory_equal(&tid, &before, sizeof(tid));
    /* the ends of each range are valid */
    q = tp;
    q.ellipse = 1;
    q.fx_front = 0;
    q.ell_min = 1;
    q.ell_ax_min = 0;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_OK);
    q.fx_front = 1;
    q.ell_ax_min = 20;
    assert_int_equal(rfe_tyre_id_params_validate(&q), RFE_OK);
}


/* §3.5 the factor of an axle's pure-slip force, from the page, in double: lam sqrt(1 -
 * min(rho^2, 1 - ell_min^2)), rho = (share m ax) / (lam D), lam = load / static load. */
static double ellipse_factor(double fz0, double load, double share_m, double ax, double d,
                             double ell_min)
{
    const double lam = load / fz0;
    const double rho = (share_m * ax) / (lam * d);
    return lam * sqrt(1.0 - fmin(rho * rho, 1.0 - ell_min * ell_min));
}

/* Both axles (front, rear) at @p ax for the vehicle @p veh and the keys @p tp, with D = mu0
 * Fz0: the static loads @p fz0, the loads @p load under ax's load transfer (m hg / L ax off the
 * front, onto the rear) and the factors @p k of ellipse_factor. */
static void axle_factors(const rfe_params_t *veh, const rfe_tyre_id_params_t *tp, double ax,
                         double fz0[2], double load[2], double k[2])
{
    const double m = (double)veh->vehicle.m;
    const double la = (double)veh->vehicle.Lf + (double)veh->vehicle.Lr;
    const double g_x = m * (double)veh->vehicle.hg / la;
    const double share[2] = {(double)tp->fx_front, 1.0 - (double)tp->fx_front};
    size_t a;
    fz0[0] = m * (double)veh->vehicle.g * (double)veh->vehicle.Lr / la;
    fz0[1] = m * (double)veh->vehicle.g * (double)veh->vehicle.Lf / la;
    load[0] = fz0[0] - g_x * ax;
    load[1] = fz0[1] + g_x * ax;
    for (a = 0u; a < 2u; ++a) {
        k[a] = ellipse_factor(fz0[a], load[a], share[a] * m, ax, (double)tp->mu0 * fz0[a],
                              (double)tp->ell_min);
    }
}

/* REQ-TID-009: with tid_ellipse = 1 each axle's force is its pure-slip force times the
 * factor of §3.5 (at ax 0 exactly 1; braking moderately: the load and the ellipse; braking
 * hard: the floor ell_min), and mu = D / Fz0 (the static load); with 0, mu = D / Fz at ax.
 * The sigma-point filter's first sample (its prior, no update), with the prior's sd of D 0
 * so that every cubature point has D = mu0 Fz0: the forces of the two runs differ by the
 * factor alone. */
static void test_ellipse_scales_the_axle_forces(void **state)
{
    static rfe_tyre_id_t off;
    const rfe_real_t axs[3] = {0, -3, -9};
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_params_t tp_on;
    rfe_tyre_id_estimate_t e_on;
    rfe_tyre_id_estimate_t e_off;
    size_t i;
    (void)state;
    setup_defaults(&veh, &tp);
    tp.filter = RFE_TID_SCKF;
    tp.sd0_mu = 0;
    tp_on = tp;
    tp_on.ellipse = 1;
    for (i = 0u; i < 3u; ++i) {
        rfe_tyre_id_sample_t s = sample(0, (rfe_real_t)0.02, 20, (rfe_real_t)0.05, 1);
        const double mu0 = (double)tp.mu0;
        double fz0[2];
        double load[2];
        double k[2];
        double k_f;
        double k_r;
        axle_factors(&veh, &tp, (double)axs[i], fz0, load, k);
        k_f = k[0];
        k_r = k[1];
        s.ax = axs[i];
        assert_int_equal(rfe_tyre_id_init(&off, &tp, &veh, 1u), RFE_OK);
        assert_int_equal(rfe_tyre_id_init(&tid, &tp_on, &veh, 1u), RFE_OK);
        assert_int_equal(rfe_tyre_id_step(&off, &s, &e_off), RFE_OK);
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e_on), RFE_OK);
        assert_int_equal(e_on.flags, RFE_TID_FIRST);
        if (i == 0u) {
            assert_true(e_on.mean[RFE_TID_OUT_FY_F] == e_off.mean[RFE_TID_OUT_FY_F]);
            assert_true(e_on.mean[RFE_TID_OUT_FY_R] == e_off.mean[RFE_TID_OUT_FY_R]);
        } else if (i == 1u) {
            /* braking at 3 m/s^2, inside the floor: the rear (its load falls) loses more than
             * the front (its load rises) */
            assert_true(k_r > 0.5 && k_r < k_f && k_f < 1.0);
        } else {
            /* at 9 m/s^2 the rear's share of m ax exceeds its peak: the floor, lam ell_min */
            assert_true(fabs(k_r / (load[1] / fz0[1]) - (double)tp.ell_min) < 1e-12);
        }
        assert_close(e_on.mean[RFE_TID_OUT_FY_F], k_f * (double)e_off.mean[RFE_TID_OUT_FY_F],
                     0.0, TOL_ELL, "Fy_f");
        assert_close(e_on.mean[RFE_TID_OUT_FY_R], k_r * (double)e_off.mean[RFE_TID_OUT_FY_R],
                     0.0, TOL_ELL, "Fy_r");
        /* mu = D / Fz0 with the ellipse (D the peak at the static load), D / Fz at ax off */
        assert_close(e_on.mean[RFE_TID_OUT_MU_F], mu0, 0.0, TOL_ELL, "mu_f on");
        assert_close(e_on.mean[RFE_TID_OUT_MU_R], mu0, 0.0, TOL_ELL, "mu_r on");
        assert_close(e_off.mean[RFE_TID_OUT_MU_F], mu0 * fz0[0] / load[0], 0.0, TOL_ELL,
                     "mu_f off");
        assert_close(e_off.mean[RFE_TID_OUT_MU_R], mu0 * fz0[1] / load[1], 0.0, TOL_ELL,
                     "mu_r off");
    }
}

/* REQ-TID-009: the ellipse's dead band (§3.5): below tid_ell_ax_min ax is taken as 0, so each
 * axle's force is the lateral-only model's bit for bit (the factor is exactly 1: lam = Fz0 /
 * Fz0, rho = 0); at and above it, and at every ax with the band 0, the factor of §3.5 (an
 * ax inside the default band moves the forces by the load: |1 - lam| = G |ax| / Fz0, 1.3 %
 * of the front's at 0.4 m/s^2, far above TOL_ELL). The sigma-point filter's first sample as
 * in test_ellipse_scales_the_axle_forces (every point has D = mu0 Fz0). The ax probed are
 * placed from the band the defaults give (rfe_tyre_id_params_default, the one source; the
 * defaults test pins its value), not from a copy of it: 2/3 of it either way (inside), the
 * band itself (its edge), 5/3 of it (beyond). */
static void test_ellipse_dead_band(void **state)
{
    static rfe_tyre_id_t off;
    rfe_real_t axs[4];
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_params_t tp_band;
    rfe_tyre_id_params_t tp_none;
    rfe_tyre_id_estimate_t e_off;
    rfe_tyre_id_estimate_t e_band;
    rfe_tyre_id_estimate_t e_none;
    static rfe_tyre_id_t none;
    size_t i;
    (void)state;
    setup_defaults(&veh, &tp);
    assert_true(tp.ell_ax_min > 0); /* a band to probe: inside, on its edge, beyond */
    axs[0] = (rfe_real_t)(-(2.0 / 3.0) * (double)tp.ell_ax_min);
    axs[1] = -axs[0];
    axs[2] = -tp.ell_ax_min; /* exactly the key: |ax| < band is false */
    axs[3] = (rfe_real_t)(-(5.0 / 3.0) * (double)tp.ell_ax_min);
    tp.filter = RFE_TID_SCKF;
    tp.sd0_mu = 0;
    tp_band = tp;
    tp_band.ellipse = 1;     /* the default band */
    tp_none = tp_band;
    tp_none.ell_ax_min = 0;  /* no band: the ellipse as first built */
    for (i = 0u; i < 4u; ++i) {
        rfe_tyre_id_sample_t s = sample(0, (rfe_real_t)0.02, 20, (rfe_real_t)0.05, 1);
        double fz0[2];
        double load[2];
        double k[2];
        double k_f;
        double k_r;
        axle_factors(&veh, &tp, (double)axs[i], fz0, load, k);
        k_f = k[0];
        k_r = k[1];
        s.ax = axs[i];
        assert_int_equal(rfe_tyre_id_init(&off, &tp, &veh, 1u), RFE_OK);
        assert_int_equal(rfe_tyre_id_init(&tid, &tp_band, &veh, 1u), RFE_OK);
        assert_int_equal(rfe_tyre_id_init(&none, &tp_none, &veh, 1u), RFE_OK);
        assert_int_equal(rfe_tyre_id_step(&off, &s, &e_off), RFE_OK);
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e_band), RFE_OK);
        assert_int_equal(rfe_tyre_id_step(&none, &s, &e_none), RFE_OK);
        /* without the band the factor acts at every ax, and it is not 1 here */
        assert_true(fabs(k_f - 1.0) > 1e-3 && fabs(k_r - 1.0) > 1e-3);
        assert_close(e_none.mean[RFE_TID_OUT_FY_F], k_f * (double)e_off.mean[RFE_TID_OUT_FY_F],
                     0.0, TOL_ELL, "Fy_f none");
        assert_close(e_none.mean[RFE_TID_OUT_FY_R], k_r * (double)e_off.mean[RFE_TID_OUT_FY_R],
                     0.0, TOL_ELL, "Fy_r none");
        if (i < 2u) {
            /* inside the band: the lateral-only forces, bit for bit */
            assert_true(e_band.mean[RFE_TID_OUT_FY_F] == e_off.mean[RFE_TID_OUT_FY_F]);
            assert_true(e_band.mean[RFE_TID_OUT_FY_R] == e_off.mean[RFE_TID_OUT_FY_R]);
        } else {
            /* on its edge (|ax| < band is false) and beyond: as without the band */
            assert_true(e_band.mean[RFE_TID_OUT_FY_F] == e_none.mean[RFE_TID_OUT_FY_F]);
            assert_true(e_band.mean[RFE_TID_OUT_FY_R] == e_none.mean[RFE_TID_OUT_FY_R]);
        }
    }
}

/* REQ-TID-003: the init writes nothing when it refuses. */
static void test_init_refusals_write_nothing(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_params_t bad;
    rfe_params_t bad_veh;
    (void)state;
    setup_defaults(&veh, &tp);
    memset(&tid, 0xA5, sizeof(tid));
    before = tid;
    assert_int_equal((rfe_tyre_id_init)(&tid, &tp, &veh, 1u, sizeof(tid) - 1u, RFE_CONFIG_REAL),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_tyre_id_init)(&tid, &tp, &veh, 1u, sizeof(tid), RFE_CONFIG_REAL ^ 3u),
                     RFE_ERR_ABI);
    assert_int_equal(rfe_tyre_id_init(NULL, &tp, &veh, 1u), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_id_init(&tid, NULL, &veh, 1u), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, NULL, 1u), RFE_ERR_NULL);
    bad = tp;
    bad.sd_r = 0;
    assert_int_equal(rfe_tyre_id_init(&tid, &bad, &veh, 1u), RFE_ERR_PARAM);
    bad_veh = veh;
    bad_veh.vehicle.m = -1;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &bad_veh, 1u), RFE_ERR_PARAM);
    /* a prior mean outside its bounds: the tyre data's C below C_lo, then cy above cy_hi */
    bad = tp;
    bad.C_lo = (rfe_real_t)1.5;
    assert_int_equal(rfe_tyre_id_init(&tid, &bad, &veh, 1u), RFE_ERR_PARAM);
    bad = tp;
    bad.cy_hi = (rfe_real_t)10.0;
    assert_int_equal(rfe_tyre_id_init(&tid, &bad, &veh, 1u), RFE_ERR_PARAM);
    /* delta as the SCKF's state (§15.7) with the steering-angle filter (§4.4), or negative */
    bad = tp;
    bad.delta_state_q = (rfe_real_t)0.04;
    bad.delta_q = (rfe_real_t)0.05;
    assert_int_equal(rfe_tyre_id_init(&tid, &bad, &veh, 1u), RFE_ERR_PARAM);
    bad = tp;
    bad.delta_state_q = (rfe_real_t)-0.04;
    assert_int_equal(rfe_tyre_id_init(&tid, &bad, &veh, 1u), RFE_ERR_PARAM);
    assert_memory_equal(&tid, &before, sizeof(tid));
    /* the memory statement of rfe/config.h: 26 reals and three 16-bit indices per particle,
     * the sigma-point filter's 928 reals (rfe_tid_sckf_t, sized for n = 11 since
     * delta_state_q, TYRE_ID.md §15.7: 11 + 121 + 242 + 66 + 363 + 75 + 33 + 11 + 3 + 3) and
     * less than 1.5 kB besides (the parameters, 37 reals, the constants and the last estimate) */
    assert_int_equal(sizeof(rfe_tid_sckf_t), 928u * sizeof(rfe_real_t));
    assert_true(sizeof(rfe_tyre_id_t) >= (size_t)RFE_TID_N * (26u * sizeof(rfe_real_t) + 6u) +
                                             sizeof(rfe_tid_sckf_t));
    assert_true(sizeof(rfe_tyre_id_t) < (size_t)RFE_TID_N * (26u * sizeof(rfe_real_t) + 6u) +
                                            sizeof(rfe_tid_sckf_t) + 1536u);
}

/* REQ-TID-003: every refused step of filter f leaves the state bit for bit as it was and
 * returns the previous estimate with the error status. */
static void step_refusals(rfe_tid_filter_t f)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_estimate_t last;
    rfe_tyre_id_sample_t s = sample(0, (rfe_real_t)0.01, 20, (rfe_real_t)0.02, (rfe_real_t)0.5);
    rfe_tyre_id_sample_t b;
    rfe_real_t *field[6];
    size_t i;
    setup_defaults(&veh, &tp);
    tp.filter = f;
    memset(&tid, 0, sizeof(tid));
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_tyre_id_get(&tid, &e), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 3u), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    s.dt = (rfe_real_t)0.01;
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    last = e;
    before = tid;
    assert_int_equal(rfe_tyre_id_step(NULL, &s, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_id_step(&tid, NULL, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_id_get(NULL, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_id_get(&tid, NULL), RFE_ERR_NULL);
    field[0] = &b.dt;
    field[1] = &b.delta;
    field[2] = &b.vx;
    field[3] = &b.yaw_rate;
    field[4] = &b.ay;
    field[5] = &b.ax;
    for (i = 0u; i < 6u; ++i) {
        b = s;
        *field[i] = (rfe_real_t)NAN;
        assert_int_equal(rfe_tyre_id_step(&tid, &b, &e), RFE_ERR_NONFINITE);
        assert_int_equal(e.status, RFE_ERR_NONFINITE);
        assert_memory_equal(e.mean, last.mean, sizeof(e.mean));
        b = s;
        *field[i] = (rfe_real_t)-INFINITY;
        assert_int_equal(rfe_tyre_id_step(&tid, &b, &e), RFE_ERR_NONFINITE);
        if (i > 0u) {
            /* beyond config.h's limits */
            b = s;
            *field[i] = (rfe_real_t)(-1e3);
            assert_int_equal(rfe_tyre_id_step(&tid, &b, &e), RFE_ERR_RANGE);
            assert_int_equal(e.status, RFE_ERR_RANGE);
        }
    }
    /* the period: 0, negative, beyond dt_max */
    b = s;
    b.dt = 0;
    assert_int_equal(rfe_tyre_id_step(&tid, &b, &e), RFE_ERR_RANGE);
    b.dt = (rfe_real_t)-0.01;
    assert_int_equal(rfe_tyre_id_step(&tid, &b, &e), RFE_ERR_RANGE);
    b.dt = tp.dt_max * (rfe_real_t)1.01;
    assert_int_equal(rfe_tyre_id_step(&tid, &b, &e), RFE_ERR_RANGE);
    /* an ax within the limits that lifts an axle: braking lifts the rear (ax < -g Lf / hg,
     * about -25 m/s^2), accelerating the front (ax > g Lr / hg, about 30 m/s^2) */
    b = s;
    b.ax = (rfe_real_t)-26.0;
    assert_int_equal(rfe_tyre_id_step(&tid, &b, &e), RFE_ERR_RANGE);
    b.ax = (rfe_real_t)31.0;
    assert_int_equal(rfe_tyre_id_step(&tid, &b, &e), RFE_ERR_RANGE);
    assert_memory_equal(&tid, &before, sizeof(tid));
    assert_int_equal(rfe_tyre_id_get(&tid, &e), RFE_OK);
    assert_memory_equal(&e, &last, sizeof(e));
}

/* REQ-TID-003 */
static void test_step_refusals_leave_the_state_untouched(void **state)
{
    (void)state;
    step_refusals(RFE_TID_APF);
}

/* REQ-TID-003: the same for the sigma-point filter (§15), whose state is tid.sk. */
static void test_sckf_step_refusals_leave_the_state_untouched(void **state)
{
    (void)state;
    step_refusals(RFE_TID_SCKF);
}

/* REQ-TID-004 */
static void test_log_sum_exp_with_extreme_log_likelihoods(void **state)
{
    const rfe_real_t ninf = -(rfe_real_t)INFINITY;
    /* 1e6 below the exponent range; -1e6 + 1 is exact in float */
    rfe_real_t l[3] = {(rfe_real_t)-1e6, (rfe_real_t)(-1e6 + 1.0), ninf};
    rfe_real_t w[4];
    rfe_real_t lw[3];
    const double e1 = exp(1.0);
    (void)state;
    assert_int_equal(rfe_tid_normalise(l, 3u, w, lw), 1);
    assert_close(w[0], 1.0 / (1.0 + e1), 0.0, TOL_W, "w0");
    assert_close(w[1], e1 / (1.0 + e1), 0.0, TOL_W, "w1");
    assert_true(w[2] == 0);
    assert_close(lw[1], -log1p(1.0 / e1), TOL_W, 0.0, "lw1"); /* -log S with S = 1 + 1/e */
    assert_true(lw[2] == ninf);
    assert_close(rfe_tid_neff(w, 3u), 1.0 / ((1.0 + e1 * e1) / ((1.0 + e1) * (1.0 + e1))), 0.0,
                 TOL_W, "neff");
    /* in place: lw may be l */
    assert_int_equal(rfe_tid_normalise(l, 3u, w, l), 1);
    assert_close(l[0], -1.0 - log1p(1.0 / e1), TOL_W, 0.0, "in place");
    {
        /* one finite weight among impossible ones takes all the weight */
        rfe_real_t one[4] = {ninf, ninf, (rfe_real_t)-3e38, ninf};
        assert_int_equal(rfe_tid_normalise(one, 4u, w, NULL), 1);
        assert_true(w[0] == 0 && w[1] == 0 && w[2] == 1 && w[3] == 0);
    }
    {
        /* every weight impossible, a NaN, a +inf: nothing normalised, nothing written */
        rfe_real_t none[3] = {ninf, ninf, ninf};
        rfe_real_t nan1[3] = {0, (rfe_real_t)NAN, 0};
        rfe_real_t nan0[3] = {(rfe_real_t)NAN, 0, 0};
        rfe_real_t pinf[3] = {0, (rfe_real_t)INFINITY, 0};
        rfe_real_t keep[3] = {7, 7, 7};
        assert_int_equal(rfe_tid_normalise(none, 3u, keep, NULL), 0);
        assert_int_equal(rfe_tid_normalise(nan1, 3u, keep, NULL), 0);
        assert_int_equal(rfe_tid_normalise(nan0, 3u, keep, NULL), 0);
        assert_int_equal(rfe_tid_normalise(pinf, 3u, keep, NULL), 0);
        assert_true(keep[0] == 7 && keep[1] == 7 && keep[2] == 7);
    }
}

/* The smallest i with x < cum[i] (n - 1 if none), by a plain scan: the definition of §5.3,
 * independent of the library's bisection. */
static size_t scan(const rfe_real_t *cum, size_t n, rfe_real_t x)
{
    size_t i;
    for (i = 0u; i < n; ++i) {
        if (x < cum[i]) {
            return i;
        }
    }
    return n - 1u;
}

/* REQ-TID-005 */
static void test_parent_search_and_draws_on_hand_weights(void **state)
{
    /* weights 1/8, 0, 3/8, 1/2 (exact in binary): cumulative 1/8, 1/8, 1/2, 1 */
    const rfe_real_t w[4] = {(rfe_real_t)0.125, 0, (rfe_real_t)0.375, (rfe_real_t)0.5};
    rfe_real_t cum[4];
    uint16_t idx[64];
    rfe_philox_t s;
    size_t j;
    (void)state;
    rfe_tid_cumsum(w, 4u, cum);
    assert_true(cum[0] == (rfe_real_t)0.125 && cum[1] == (rfe_real_t)0.125);
    assert_true(cum[2] == (rfe_real_t)0.5 && cum[3] == 1);
    assert_int_equal(rfe_tid_search(cum, 4u, (rfe_real_t)0.05), 0u);
    /* on the boundary C_0 = C_1 = 1/8 the next particle of positive weight: 2, never 1 */
    assert_int_equal(rfe_tid_search(cum, 4u, (rfe_real_t)0.125), 2u);
    assert_int_equal(rfe_tid_search(cum, 4u, (rfe_real_t)0.3), 2u);
    assert_int_equal(rfe_tid_search(cum, 4u, (rfe_real_t)0.5), 3u);
    assert_int_equal(rfe_tid_search(cum, 4u, (rfe_real_t)0.99), 3u);
    /* at or past S: the guard for rounding, N - 1 */
    assert_int_equal(rfe_tid_search(cum, 4u, 1), 3u);
    assert_int_equal(rfe_tid_search(cum, 4u, 2), 3u);
    assert_int_equal(rfe_tid_search(cum, 4u, 0), 0u);
    /* multinomial: parent j of uniform j, u_j S, S = 1 */
    assert_int_equal(rfe_philox_stream(&s, 11u, 4u, 2u), RFE_OK);
    rfe_tid_draw(cum, 4u, &s, RFE_TID_MULTINOMIAL, 64u, idx);
    {
        size_t count[4] = {0u, 0u, 0u, 0u};
        for (j = 0u; j < 64u; ++j) {
            rfe_real_t u = 0;
            assert_int_equal(rfe_philox_uniform(&s, (uint64_t)j, &u), RFE_OK);
            assert_int_equal(idx[j], scan(cum, 4u, u * cum[3]));
            ++count[idx[j]];
        }
        assert_int_equal(count[1], 0u); /* zero weight: never a parent */
        assert_true(count[3] > count[0]);
    }
    /* systematic with 4 positions (j + u0) / 4: one in [0, 1/4) (0 below 1/8, else 2), one in
     * [1/4, 1/2): 2, two in [1/2, 1): 3 */
    rfe_tid_draw(cum, 4u, &s, RFE_TID_SYSTEMATIC, 4u, idx);
    {
        rfe_real_t u0 = 0;
        assert_int_equal(rfe_philox_uniform(&s, 0u, &u0), RFE_OK);
        assert_int_equal(idx[0], (u0 < (rfe_real_t)0.5) ? 0u : 2u);
        assert_int_equal(idx[1], 2u);
        assert_int_equal(idx[2], 3u);
        assert_int_equal(idx[3], 3u);
    }
    {
        /* even weights, systematic: every particle exactly once, in order */
        const rfe_real_t even[5] = {(rfe_real_t)0.2, (rfe_real_t)0.2, (rfe_real_t)0.2,
                                    (rfe_real_t)0.2, (rfe_real_t)0.2};
        rfe_real_t c5[5];
        rfe_tid_cumsum(even, 5u, c5);
        rfe_tid_draw(c5, 5u, &s, RFE_TID_SYSTEMATIC, 5u, idx);
        for (j = 0u; j < 5u; ++j) {
            assert_int_equal(idx[j], j);
        }
    }
}

/* REQ-TID-005 */
static void test_order_by_weight_is_stable(void **state)
{
    const rfe_real_t w[7] = {1, 3, 3, 2, 1, 3, 0};
    const uint16_t want[7] = {1, 2, 5, 3, 0, 4, 6}; /* descending, ties by index */
    uint16_t order[7];
    uint16_t tmp[7];
    size_t i;
    (void)state;
    rfe_tid_order(w, 7u, order, tmp);
    for (i = 0u; i < 7u; ++i) {
        assert_int_equal(order[i], want[i]);
    }
    {
        /* a power-of-two length (the runs end in the other buffer) and one element */
        const rfe_real_t w4[4] = {(rfe_real_t)0.1, (rfe_real_t)0.4, (rfe_real_t)0.1,
                                  (rfe_real_t)0.4};
        const uint16_t want4[4] = {1, 3, 0, 2};
        rfe_tid_order(w4, 4u, order, tmp);
        for (i = 0u; i < 4u; ++i) {
            assert_int_equal(order[i], want4[i]);
        }
        rfe_tid_order(w4, 1u, order, tmp);
        assert_int_equal(order[0], 0u);
    }
}

/* REQ-TID-006 */
static void test_reflect_hand_cases(void **state)
{
    (void)state;
    assert_true(rfe_tid_reflect((rfe_real_t)0.5, 0, 1) == (rfe_real_t)0.5);
    assert_true(rfe_tid_reflect((rfe_real_t)-0.25, 0, 1) == (rfe_real_t)0.25);
    assert_true(rfe_tid_reflect((rfe_real_t)1.25, 0, 1) == (rfe_real_t)0.75);
    assert_true(rfe_tid_reflect(0, 0, 1) == 0);
    assert_true(rfe_tid_reflect(1, 0, 1) == 1);
    /* wider than the interval: reflected at lo to 2.5, at hi to -0.5, clipped to lo */
    assert_true(rfe_tid_reflect((rfe_real_t)-2.5, 0, 1) == 0);
    /* above: reflected at hi to -1.5, clipped to lo */
    assert_true(rfe_tid_reflect((rfe_real_t)3.5, 0, 1) == 0);
    assert_true(rfe_tid_reflect((rfe_real_t)-3.5, -3, (rfe_real_t)0.95) == (rfe_real_t)-2.5);
}

static void check_bounds_and_finite(const rfe_tyre_id_t *t, const rfe_tyre_id_estimate_t *e,
                                    size_t k)
{
    const size_t n = (t->p.filter == RFE_TID_SCKF) ? 1u : (size_t)RFE_TID_N;
    size_t i;
    size_t j;
    for (i = 0u; i < n; ++i) {
        /* the particles, or the sigma-point filter's mean (§15.3: projected after each update;
         * its parameter outputs are this mean, checked below) */
        const rfe_real_t *x = (t->p.filter == RFE_TID_SCKF) ? t->sk.x : t->x[i];
        for (j = 0u; j < (size_t)RFE_TID_PAR; ++j) {
            const rfe_real_t v = x[RFE_TID_STATES + j];
            if (!(v >= t->c.lo[j]) || !(v <= t->c.hi[j])) {
                fail_msg("sample %zu particle %zu parameter %zu: %g outside [%g, %g]", k, i, j,
                         (double)v, (double)t->c.lo[j], (double)t->c.hi[j]);
            }
        }
    }
    for (j = 0u; j < (size_t)RFE_TID_OUTPUTS; ++j) {
        assert_true(isfinite(e->mean[j]) && isfinite(e->sd[j]));
    }
    if (t->p.filter == RFE_TID_SCKF) {
        for (j = 0u; j < (size_t)RFE_TID_PAR; ++j) {
            assert_true(e->mean[RFE_TID_OUT_D_F + j] == t->sk.x[RFE_TID_STATES + j]);
        }
        assert_true(isnan(e->n_eff)); /* no particles (§15.4) */
    } else {
        assert_true(e->n_eff >= (rfe_real_t)0.99 && e->n_eff <= (rfe_real_t)RFE_TID_N * 1.01f);
    }
}

/* Runs `count` samples of a tyre-identification log from `first`, checking the bounds and the
 * outputs after every step; returns the OR of the status bits and the smallest sd of mu. */
static uint32_t run_log(const char *name, size_t first, size_t count, rfe_tid_filter_t f,
                        rfe_tid_resample_t scheme, rfe_real_t *min_sd_mu)
{
    char path[256];
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    uint32_t seen = 0u;
    size_t k;
    memset(&log, 0, sizeof(log));
    snprintf(path, sizeof(path), "scenarios/tyre_id/%s.csv", name);
    assert_int_equal(rfe_sensor_log_read(path, &log, &err), 0);
    assert_true(log.n_rows >= first + count);
    setup_defaults(&veh, &tp);
    tp.filter = f;
    tp.resample = scheme;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 5u), RFE_OK);
    *min_sd_mu = (rfe_real_t)1e9;
    for (k = first; k < first + count; ++k) {
        const rfe_sensor_row_t *r = &log.rows[k];
        rfe_tyre_id_sample_t s;
        rfe_tyre_id_estimate_t e;
        s.dt = (k > first) ? (rfe_real_t)(r->t - log.rows[k - 1u].t) : (rfe_real_t)0;
        s.delta = (rfe_real_t)r->delta;
        s.vx = (rfe_real_t)r->vx;
        s.yaw_rate = (rfe_real_t)r->yaw_rate;
        s.ay = (rfe_real_t)r->ay;
        s.ax = (rfe_real_t)r->ax;
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
        check_bounds_and_finite(&tid, &e, k);
        seen |= e.flags;
        if (e.sd[RFE_TID_OUT_MU_F] < *min_sd_mu) {
            *min_sd_mu = e.sd[RFE_TID_OUT_MU_F];
        }
        if (e.sd[RFE_TID_OUT_MU_R] < *min_sd_mu) {
            *min_sd_mu = e.sd[RFE_TID_OUT_MU_R];
        }
    }
    rfe_sensor_log_free(&log);
    return seen;
}

/* REQ-TID-006 REQ-TID-008: the ramp steer from the start to the limit (4 s to 7 s of it is
 * where the front axle saturates), with both filters. */
static void test_bounds_hold_on_a_ramp_to_the_limit(void **state)
{
    rfe_real_t sd_mu;
    uint32_t seen;
    (void)state;
    seen = run_log("tid_ramp_steer_high_mu", 400u, 300u, RFE_TID_APF, RFE_TID_MULTINOMIAL,
                   &sd_mu);
    assert_true((seen & RFE_TID_FIRST) != 0u);
    assert_true((seen & RFE_TID_UPDATED) != 0u);
    assert_true((seen & RFE_TID_RESAMPLED) != 0u);
    assert_true((seen & (RFE_TID_HELD | RFE_TID_LOST)) == 0u);
    seen = run_log("tid_ramp_steer_high_mu", 400u, 150u, RFE_TID_SIR, RFE_TID_SYSTEMATIC, &sd_mu);
    assert_true((seen & RFE_TID_RESAMPLED) != 0u);
}

/* REQ-TID-008: straight driving identifies no peak: the spread of mu from D stays at the
 * prior's (0.3; at least 0.2 per axle over the first second, TYRE_ID_RESULTS.md). */
static void test_straight_driving_keeps_the_spread_of_mu(void **state)
{
    rfe_real_t sd_mu;
    (void)state;
    (void)run_log("tid_straight", 0u, 100u, RFE_TID_APF, RFE_TID_MULTINOMIAL, &sd_mu);
    assert_true(sd_mu >= (rfe_real_t)0.2);
}

/* REQ-TID-008: below v_min nothing changes but the stored inputs. */
static void test_held_below_v_min(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_sample_t s = sample(0, (rfe_real_t)0.02, 20, (rfe_real_t)0.05, 1);
    (void)state;
    setup_defaults(&veh, &tp);
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 9u), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_FIRST);
    assert_true(e.n_eff == (rfe_real_t)RFE_TID_N); /* even weights */
    before = tid;
    s.dt = (rfe_real_t)0.01;
    s.vx = tp.v_min * (rfe_real_t)0.9;
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_HELD);
    assert_memory_equal(tid.x, before.x, sizeof(tid.x));
    assert_memory_equal(tid.logw, before.logw, sizeof(tid.logw));
    assert_true(tid.k == before.k + 1u);
    /* the previous vx was below v_min: held once more, then it steps */
    s.vx = 20;
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_HELD);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_true((e.flags & RFE_TID_UPDATED) != 0u);
}

/* Runs first-sample-at-rest then a sample whose yaw rate (r_next) the particles cannot
 * explain at sd_r = SD_R_OVERFLOW; returns the flags of the second step. */
static uint32_t lost_case(rfe_tid_filter_t f, rfe_real_t r_next)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_sample_t s = sample(0, 0, 20, 0, 0);
    size_t j;
    setup_defaults(&veh, &tp);
    tp.filter = f;
    tp.sd_r = (rfe_real_t)SD_R_OVERFLOW;
    tp.sd0_vy = 0; /* every particle at vy = 0, r = 0: no force, no motion */
    tp.sd0_r = 0;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 2u), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    s.dt = (rfe_real_t)0.01;
    s.yaw_rate = r_next;
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    for (j = 0u; j < (size_t)RFE_TID_OUTPUTS; ++j) {
        assert_true(isfinite(e.mean[j]) && isfinite(e.sd[j]));
    }
    assert_true(e.n_eff == (rfe_real_t)RFE_TID_N); /* the prior again: even weights */
    return e.flags;
}

/* REQ-TID-004 REQ-TID-008: every particle impossible: the prior is drawn again (LOST),
 * at the APF's first stage (r_m 0.01 away from every auxiliary point), at its second stage
 * (r_m = 0 = every auxiliary point, but the process noise moves each r by ~1e-3) and in
 * the bootstrap filter. */
static void test_lost_draws_the_prior_again(void **state)
{
    (void)state;
    assert_int_equal(lost_case(RFE_TID_APF, (rfe_real_t)0.01), RFE_TID_LOST);
    assert_int_equal(lost_case(RFE_TID_APF, 0), RFE_TID_LOST);
    assert_int_equal(lost_case(RFE_TID_SIR, 0), RFE_TID_LOST);
}

/* REQ-TID-002: the step of §4.1 with two RK4 substeps runs and stays within the bounds
 * (its agreement with the reference is that of one substep of half the period). */
static void test_substeps(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_sample_t s = sample(0, (rfe_real_t)0.02, 20, (rfe_real_t)0.05, 1);
    rfe_real_t one[RFE_TID_STATES];
    rfe_real_t two[RFE_TID_STATES];
    rfe_real_t half[RFE_TID_STATES];
    rfe_real_t xh[RFE_TID_DIM];
    rfe_tid_input_t u;
    size_t j;
    (void)state;
    setup_defaults(&veh, &tp);
    tp.substeps = 2u;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 4u), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    u.delta = (rfe_real_t)0.02;
    u.cd = (rfe_real_t)cos(0.02);
    u.sd = 0;
    u.vx = 20;
    /* two substeps of h/2 = one substep of h/2 applied twice */
    rfe_tid_rk4(&tid, tid.x[0], &u, (rfe_real_t)0.02, two);
    tid.p.substeps = 1u;
    rfe_tid_rk4(&tid, tid.x[0], &u, (rfe_real_t)0.01, half);
    memcpy(xh, tid.x[0], sizeof(xh));
    xh[RFE_TID_VY] = half[0];
    xh[RFE_TID_R] = half[1];
    rfe_tid_rk4(&tid, xh, &u, (rfe_real_t)0.01, one);
    assert_true(one[0] == two[0] && one[1] == two[1]);
    tid.p.substeps = 2u;
    s.dt = (rfe_real_t)0.01;
    for (j = 0u; j < 5u; ++j) {
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
        check_bounds_and_finite(&tid, &e, j);
    }
}

/* F = D sin(C atan(x - E (x - atan x))), x = B tan(alpha), B = K / (C D): §3.2 in double. */
static double mf_ref(const rfe_real_t *th, double alpha)
{
    const double d = th[0];
    const double c = th[1];
    const double b = (double)th[2] / (c * d);
    const double e = th[3];
    const double x = b * tan(alpha);
    return d * sin(c * atan(x - e * (x - atan(x))));
}

/* REQ-TID-006: a slip angle beyond alpha_max (a particle sliding sideways) is clipped to
 * +-alpha_max before the curve, on both axles, both signs. Tolerance: the float build's
 * tan, atan and sin at tan(1.4) = 5.8 and B t ~ 100 round to a few float ulps of D:
 * 1e-5 D; the double build 1e-12 D. */
static void test_slip_beyond_alpha_max_is_clipped(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_real_t x[RFE_TID_DIM];
    rfe_tid_input_t u;
    rfe_real_t ff;
    rfe_real_t fr;
    double sign;
    (void)state;
    setup_defaults(&veh, &tp);
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    memset(x, 0, sizeof(x));
    memcpy(&x[RFE_TID_STATES], tid.c.mean0, sizeof(tid.c.mean0));
    u.delta = 0;
    u.cd = 1;
    u.sd = 0;
    u.vx = 1;
    for (sign = -1.0; sign <= 1.0; sign += 2.0) {
        const double a = -sign * (double)veh.tyre.alpha_max; /* alpha = -atan2(vy, vx) */
        x[RFE_TID_VY] = (rfe_real_t)(sign * 1000.0);
        rfe_tid_forces(&tid, x, &u, &ff, &fr);
        assert_close(ff, mf_ref(&x[RFE_TID_D_F], a), TOL_CLIP * tid.c.mean0[0], 0.0, "front");
        assert_close(fr, mf_ref(&x[RFE_TID_D_R], a), TOL_CLIP * tid.c.mean0[4], 0.0, "rear");
    }
}

/* REQ-TID-003. Found by fuzz_tyre_id_f32: a vehicle the parameter checks accept (every value
 * finite and > 0) whose axle load times mu_lo underflows gave D the bounds [0, 0], and B =
 * K / (C D) = 0 / 0 out. Init now refuses constants it cannot use, writing nothing. */
static void test_init_refuses_unusable_derived_bounds(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    (void)state;
    setup_defaults(&veh, &tp);
#if defined(RFE_REAL_DOUBLE)
    veh.vehicle.m = (rfe_real_t)1e-305; /* (m g) Lf = 1e-324: 0 */
#else
    veh.vehicle.m = (rfe_real_t)1.83e-27; /* (m g) Lf = 2.5e-47: 0 */
#endif
    veh.vehicle.Lf = (rfe_real_t)1.4e-20;
    assert_int_equal(rfe_params_validate(&veh), RFE_OK);
    assert_int_equal(rfe_tyre_id_params_validate(&tp), RFE_OK);
    memset(&tid, 0xA5, sizeof(tid));
    before = tid;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_ERR_PARAM);
    assert_memory_equal(&tid, &before, sizeof(tid));
    /* the other end: a mass whose axle load times cy_hi overflows (K's upper bound +Inf) */
    setup_defaults(&veh, &tp);
#if defined(RFE_REAL_DOUBLE)
    veh.vehicle.m = (rfe_real_t)1e307;
#else
    veh.vehicle.m = (rfe_real_t)1e37f;
#endif
    assert_int_equal(rfe_params_validate(&veh), RFE_OK);
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_ERR_PARAM);
    assert_memory_equal(&tid, &before, sizeof(tid));
}

/* Init refuses each kind of unusable derived constant on its own (consts_usable): an axle
 * load that overflows, a walk or a prior spread that overflows while the bounds are finite, a
 * front C D bound that underflows to 0 while the rear's is fine, and a rear K / (C D) that
 * overflows while the front's is finite. Every vehicle and parameter set here passes its own
 * checks. */
/* REQ-TID-003 */
static void test_init_refuses_each_unusable_constant(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
#if defined(RFE_REAL_DOUBLE)
    const rfe_real_t huge = (rfe_real_t)1e308;
    const rfe_real_t big_m = (rfe_real_t)1e307;   /* m g finite, 40 m g not */
    const rfe_real_t short_lr = (rfe_real_t)1e-300;
    const rfe_real_t tiny_m = (rfe_real_t)1e-30;  /* m g Lr / L * mu_lo underflows to 0 */
#else
    const rfe_real_t huge = (rfe_real_t)3e38f;
    const rfe_real_t big_m = (rfe_real_t)1e37f;
    const rfe_real_t short_lr = (rfe_real_t)1e-30f;
    const rfe_real_t tiny_m = (rfe_real_t)1e-20f;
#endif
    size_t k;
    (void)state;
    memset(&tid, 0xA5, sizeof(tid));
    before = tid;
    for (k = 0u; k < 5u; ++k) {
        setup_defaults(&veh, &tp);
        if (k == 0u) {
            veh.vehicle.m = huge; /* m g = Inf: the axle loads themselves */
        } else if (k == 1u) {
            tp.q_cy = huge; /* the walk of K = q_cy Fz overflows; its bounds do not */
        } else if (k == 2u) {
            tp.sd0_mu = huge; /* the prior spread of D overflows */
        } else if (k == 3u) {
            veh.vehicle.m = tiny_m; /* the front axle's load underflows: C D's bound 0 */
            veh.vehicle.Lr = short_lr;
        } else {
            veh.vehicle.m = big_m; /* the rear axle's K bound overflows, the front's not */
            veh.vehicle.Lr = short_lr;
        }
        assert_int_equal(rfe_params_validate(&veh), RFE_OK);
        assert_int_equal(rfe_tyre_id_params_validate(&tp), RFE_OK);
        if (rfe_tyre_id_init(&tid, &tp, &veh, 1u) != RFE_ERR_PARAM) {
            fail_msg("case %zu: init accepted", k);
        }
        assert_memory_equal(&tid, &before, sizeof(tid));
    }
}

/* REQ-TID-004. Found by fuzz_tyre_id_f32: with a mass of 1.8e23 kg (valid) the spread of D
 * and K passes the square root of the float's range, and the sds came out +Inf with status
 * 0. They are now the same sums over values scaled by the largest first: finite. */
static void test_huge_vehicle_gives_finite_sds(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_sample_t s;
    int k;
    int i;
    (void)state;
    setup_defaults(&veh, &tp);
#if defined(RFE_REAL_DOUBLE)
    veh.vehicle.m = (rfe_real_t)1.83e155;
#else
    veh.vehicle.m = (rfe_real_t)1.83e23;
#endif
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    for (k = 0; k < 5; ++k) {
        s = sample((rfe_real_t)0.02, (rfe_real_t)0.01, (rfe_real_t)11.6, 0, 0);
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
        for (i = 0; i < RFE_TID_OUTPUTS; ++i) {
            assert_true(isfinite((double)e.mean[i]));
            assert_true(isfinite((double)e.sd[i]) && e.sd[i] >= 0);
        }
        if (k == 0) {
            /* the prior's spread of D, 0.3 Fz0 (reflected into its bounds): not 0, not Inf */
            assert_true(e.sd[RFE_TID_OUT_D_F] > 0.05 * tid.c.fz0[0]);
        }
    }
}

/* REQ-TID-004: the sigma-point filter (§15) with the same huge vehicle: the prior's sd of D
 * (0.3 Fz0, about 5e23 N in float) is a row norm of S whose plain sum of squares overflows;
 * the spread is the same sum over the row scaled by its largest entry first, so on the first
 * sample (S = diag(sd0)) it is sd0 exactly and not +Inf; every later output finite. In the
 * float build each update's corrected mean x + K (y - z) overflows (rfe_cub_correct refuses
 * it; the posterior Tria would refuse it next), so those steps are LOST with the prior, whose
 * outputs are finite too; the double build updates. */
static void test_sckf_huge_vehicle_gives_finite_sds(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_sample_t s;
    int k;
    int i;
    (void)state;
    setup_defaults(&veh, &tp);
    tp.filter = RFE_TID_SCKF;
#if defined(RFE_REAL_DOUBLE)
    veh.vehicle.m = (rfe_real_t)1.83e155;
#else
    veh.vehicle.m = (rfe_real_t)1.83e23;
#endif
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    assert_false(isfinite((double)(tid.c.sd0[0] * tid.c.sd0[0]))); /* the plain sum overflows */
    for (k = 0; k < 5; ++k) {
        s = sample((k > 0) ? (rfe_real_t)0.02 : 0, (rfe_real_t)0.01, (rfe_real_t)11.6, 0, 0);
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
        for (i = 0; i < RFE_TID_OUTPUTS; ++i) {
            assert_true(isfinite((double)e.mean[i]));
            assert_true(isfinite((double)e.sd[i]) && e.sd[i] >= 0);
        }
        if (k == 0) {
            assert_int_equal(e.flags, RFE_TID_FIRST);
            assert_true(e.sd[RFE_TID_OUT_D_F] == tid.c.sd0[0]);
            assert_true(e.sd[RFE_TID_OUT_D_R] == tid.c.sd0[4]);
        }
    }
}

/* The SCKF's step just reported LOST alone (§15.3): the prior of §15.2 is set at this sample,
 * vy = 0, r = the sample's @p r, each parameter's mean0 with its sd0, every output finite. */
static void assert_lost_at_prior(const rfe_tyre_id_estimate_t *e, rfe_real_t r)
{
    size_t j;
    assert_int_equal(e->flags, RFE_TID_LOST);
    assert_true(tid.sk.x[RFE_TID_VY] == 0 && tid.sk.x[RFE_TID_R] == r);
    for (j = 0u; j < (size_t)RFE_TID_PAR; ++j) {
        const size_t d = (size_t)RFE_TID_STATES + j;
        assert_true(tid.sk.x[d] == tid.c.mean0[j]);
        assert_true(tid.sk.S[(d * (size_t)RFE_TID_DIM) + d] == tid.c.sd0[j]);
    }
    for (j = 0u; j < (size_t)RFE_TID_OUTPUTS; ++j) {
        assert_true(isfinite(e->mean[j]) && isfinite(e->sd[j]));
    }
}

/* REQ-TID-004 REQ-TID-008: a valid sd_ay (> 0, no upper bound) whose square overflows makes
 * S_R's second entry +Inf, so the innovation factor's Tria refuses (the first of the update's
 * checks to meet it; the posterior Tria, whose K S_R holds it too, would refuse as well): the
 * update is lost (§15.3), the step reports LOST with the prior at the sample, every output
 * finite. */
static void test_sckf_overflowing_ay_noise_is_lost(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_sample_t s = sample(0, (rfe_real_t)0.02, 20, (rfe_real_t)0.05, 1);
    (void)state;
    setup_defaults(&veh, &tp);
    tp.filter = RFE_TID_SCKF;
#if defined(RFE_REAL_DOUBLE)
    tp.sd_ay = (rfe_real_t)1e160;
#else
    tp.sd_ay = (rfe_real_t)1e20;
#endif
    assert_int_equal(rfe_tyre_id_params_validate(&tp), RFE_OK);
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_FIRST);
    s.dt = (rfe_real_t)0.01;
    s.yaw_rate = (rfe_real_t)0.07;
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_lost_at_prior(&e, (rfe_real_t)0.07);
}

/* REQ-TID-004: a particle with an infinite vy weighs 0 (its slip angles, forces and so its
 * l would stay finite, and its vy would turn every mean it enters into Inf or NaN). */
static void test_infinite_vy_weighs_zero(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tid_input_t u;
    rfe_real_t ll;
    (void)state;
    setup_defaults(&veh, &tp);
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    u.delta = 0;
    u.cd = 1;
    u.sd = 0;
    u.vx = 10;
    ll = rfe_tid_loglik(&tid, 0, 0, tid.c.mean0, &u, 0, 0, NULL);
    assert_true(isfinite((double)ll));
    ll = rfe_tid_loglik(&tid, (rfe_real_t)INFINITY, 0, tid.c.mean0, &u, 0, 0, NULL);
    assert_true(isinf((double)ll) && ll < 0);
    ll = rfe_tid_loglik(&tid, -(rfe_real_t)INFINITY, 0, tid.c.mean0, &u, 0, 0, NULL);
    assert_true(isinf((double)ll) && ll < 0);
}

/* REQ-TID-006 REQ-TID-008: the sigma-point filter (§15) on the ramp steer to the limit: its
 * mean inside the bounds after every step (the projection), the outputs finite, never LOST
 * nor RESAMPLED; on straight driving the spread of mu stays at least the prior's 0.2 (D is
 * not identified; its sd grows by the walk, TYRE_ID_RESULTS.md). */
static void test_sckf_bounds_hold_and_straight_keeps_the_spread(void **state)
{
    rfe_real_t sd_mu;
    uint32_t seen;
    (void)state;
    seen = run_log("tid_ramp_steer_high_mu", 400u, 300u, RFE_TID_SCKF, RFE_TID_MULTINOMIAL,
                   &sd_mu);
    assert_true((seen & RFE_TID_FIRST) != 0u);
    assert_true((seen & RFE_TID_UPDATED) != 0u);
    assert_true((seen & (RFE_TID_RESAMPLED | RFE_TID_HELD | RFE_TID_LOST)) == 0u);
    (void)run_log("tid_straight", 0u, 100u, RFE_TID_SCKF, RFE_TID_MULTINOMIAL, &sd_mu);
    assert_true(sd_mu >= (rfe_real_t)0.2);
}

/* REQ-TID-002: the steering-angle filter of §4.4 (delta_q > 0) against the same Kalman filter
 * written here in matrix form in double (P = F P F^T + Q, K = P H^T / (H P H^T + R),
 * x = F x + K (z - H F x), P = (I - K H) P): the library's scalar recurrences are another
 * arrangement of the same algebra, so the two agree to rounding. The filter is stable (its
 * error dynamics (I - K H) F contract), so rounding is damped rather than summed: a few ulps
 * per step of some ten operations, TOL_DF relative to the quantity plus the sensor's sd
 * (1e-5 in float, ~80 ulps; 1e-12 in double). The posterior sd must fall below the sensor's
 * (p00 = p00- R / (p00- + R) < R whatever p00-), and the identifier read the filtered delta:
 * its estimate differs from a run on the same samples with the filter off. With delta_q 0
 * the filter's state stays zero and the steering noise is sd_delta exactly. */
static void test_delta_filter_is_a_kalman_filter(void **state)
{
#if defined(RFE_REAL_DOUBLE)
    const double tol = 1e-12;
#else
    const double tol = 1e-5;
#endif
    const double q = 0.05;
    const double h = 0.01;
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_estimate_t e_off;
    double x[2] = {0.0, 0.0};
    double P[2][2] = {{0.0, 0.0}, {0.0, 0.0}};
    double rv;
    size_t k;
    (void)state;
    setup_defaults(&veh, &tp);
    tp.filter = RFE_TID_SCKF;
    tp.delta_q = (rfe_real_t)q;
    rv = (double)tp.sd_delta * (double)tp.sd_delta;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    for (k = 0u; k < 300u; ++k) {
        /* a ramp with a deterministic jitter of the sensor's size */
        const rfe_real_t d = (rfe_real_t)((0.0001 * (double)k) + (0.001 * sin(1.7 * (double)k)));
        const rfe_real_t r = (rfe_real_t)(20.0 * (0.0001 * (double)k) / 3.05);
        const rfe_tyre_id_sample_t s = sample((k == 0u) ? 0 : (rfe_real_t)h, d, 20, r, 20 * r);
        double z = (double)d;
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
        if (k == 0u) {
            x[0] = z;
            x[1] = 0.0;
            P[0][0] = rv;
        } else {
            const double F[2][2] = {{1.0, h}, {0.0, 1.0}};
            const double Q[2][2] = {{q * q * h * h * h / 3.0, q * q * h * h / 2.0},
                                    {q * q * h * h / 2.0, q * q * h}};
            double FP[2][2];
            double Pm[2][2];
            double xm[2];
            double K[2];
            double sv;
            size_t i;
            size_t j;
            for (i = 0u; i < 2u; ++i) {
                for (j = 0u; j < 2u; ++j) {
                    FP[i][j] = (F[i][0] * P[0][j]) + (F[i][1] * P[1][j]);
                }
            }
            for (i = 0u; i < 2u; ++i) {
                for (j = 0u; j < 2u; ++j) {
                    Pm[i][j] = (FP[i][0] * F[j][0]) + (FP[i][1] * F[j][1]) + Q[i][j];
                }
            }
            xm[0] = x[0] + (h * x[1]);
            xm[1] = x[1];
            sv = Pm[0][0] + rv;
            K[0] = Pm[0][0] / sv;
            K[1] = Pm[1][0] / sv;
            x[0] = xm[0] + (K[0] * (z - xm[0]));
            x[1] = xm[1] + (K[1] * (z - xm[0]));
            for (i = 0u; i < 2u; ++i) {
                for (j = 0u; j < 2u; ++j) {
                    P[i][j] = Pm[i][j] - (K[i] * Pm[0][j]);
                }
            }
        }
        assert_close(tid.dlt[0], x[0], tol * ((double)tp.sd_delta), tol, "delta");
        assert_close(tid.dlt[1], x[1], tol * ((double)tp.sd_delta / h), tol, "delta rate");
        assert_close(tid.sd_delta, sqrt(P[0][0]), tol * (double)tp.sd_delta, tol, "sd");
        if (k > 0u) {
            assert_true(tid.sd_delta < tp.sd_delta);
        }
    }
    /* off: the same samples, the steering-angle filter's state stays zero */
    tp.delta_q = 0;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    for (k = 0u; k < 300u; ++k) {
        const rfe_real_t d = (rfe_real_t)((0.0001 * (double)k) + (0.001 * sin(1.7 * (double)k)));
        const rfe_real_t r = (rfe_real_t)(20.0 * (0.0001 * (double)k) / 3.05);
        const rfe_tyre_id_sample_t s = sample((k == 0u) ? 0 : (rfe_real_t)h, d, 20, r, 20 * r);
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e_off), RFE_OK);
    }
    assert_true(tid.sd_delta == tp.sd_delta);
    assert_true(tid.dlt[0] == 0 && tid.dlt[1] == 0 && tid.dlt[2] == 0);
    assert_true(e.mean[RFE_TID_OUT_K_F] != e_off.mean[RFE_TID_OUT_K_F]);
}

/* REQ-TID-002: the prior of §15.2 exactly: x = (0, r_m, mean0), S = diag(sd0); the outputs of
 * the parameters are x and the row norms of a diagonal S, sqrt(s * s) = s exactly (correctly
 * rounded square and root, no underflow); mu = D / Fz0 at ax = 0. Then a held step (vx below
 * v_min) leaves x and S bit for bit, and the filter is deterministic: a second init and the
 * same samples give the same state bit for bit. */
static void test_sckf_prior_held_and_deterministic(void **state)
{
    static rfe_tyre_id_t again;
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_estimate_t e2;
    rfe_tyre_id_sample_t s = sample(0, (rfe_real_t)0.02, 20, (rfe_real_t)0.05, 1);
    size_t j;
    size_t k;
    (void)state;
    setup_defaults(&veh, &tp);
    tp.filter = RFE_TID_SCKF;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 9u), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_FIRST);
    assert_true(e.mean[RFE_TID_OUT_VY] == 0 && e.sd[RFE_TID_OUT_VY] == tp.sd0_vy);
    assert_true(e.mean[RFE_TID_OUT_R] == (rfe_real_t)0.05 && e.sd[RFE_TID_OUT_R] == tp.sd0_r);
    for (j = 0u; j < (size_t)RFE_TID_PAR; ++j) {
        assert_true(e.mean[RFE_TID_OUT_D_F + j] == tid.c.mean0[j]);
        assert_true(e.sd[RFE_TID_OUT_D_F + j] == tid.c.sd0[j]);
    }
    assert_true(e.mean[RFE_TID_OUT_MU_F] == tid.c.mean0[0] / tid.c.fz0[0]);
    assert_true(e.sd[RFE_TID_OUT_MU_R] == tid.c.sd0[4] / tid.c.fz0[1]);
    before = tid;
    s.dt = (rfe_real_t)0.01;
    s.vx = tp.v_min * (rfe_real_t)0.9;
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_HELD);
    assert_memory_equal(tid.sk.x, before.sk.x, sizeof(tid.sk.x));
    assert_memory_equal(tid.sk.S, before.sk.S, sizeof(tid.sk.S));
    /* determinism: two inits, 50 steering samples each */
    setup_defaults(&veh, &tp);
    tp.filter = RFE_TID_SCKF;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    assert_int_equal(rfe_tyre_id_init(&again, &tp, &veh, 2u), RFE_OK); /* seed unused */
    for (k = 0u; k < 50u; ++k) {
        s = sample((k > 0u) ? (rfe_real_t)0.01 : 0, (rfe_real_t)(0.001 * (double)k), 20,
                   (rfe_real_t)(0.002 * (double)k), (rfe_real_t)(0.04 * (double)k));
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
        assert_int_equal(rfe_tyre_id_step(&again, &s, &e2), RFE_OK);
        assert_memory_equal(e.mean, e2.mean, sizeof(e.mean));
        assert_memory_equal(e.sd, e2.sd, sizeof(e.sd));
    }
    assert_memory_equal(&tid.sk, &again.sk, sizeof(tid.sk));
    assert_true((e.flags & RFE_TID_UPDATED) != 0u);
}

/* REQ-TID-004 REQ-TID-008: §15.3 lost: a mean that is not finite (set by hand here: no
 * finite input reaches it) makes the step's Tria refuse; the step reports LOST alone and sets
 * the prior of §15.2 at this sample (x = (0, r_m, mean0), S = diag(sd0)) exactly, every output
 * finite; the next step updates from it. */
static void test_sckf_lost_sets_the_prior_again(void **state)
{
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_sample_t s = sample(0, (rfe_real_t)0.02, 20, (rfe_real_t)0.05, 1);
    (void)state;
    setup_defaults(&veh, &tp);
    tp.filter = RFE_TID_SCKF;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    tid.sk.x[RFE_TID_VY] = (rfe_real_t)NAN;
    s.dt = (rfe_real_t)0.01;
    s.yaw_rate = (rfe_real_t)0.07;
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_lost_at_prior(&e, (rfe_real_t)0.07);
    assert_true(tid.sk.S[0] == tp.sd0_vy && tid.sk.S[RFE_TID_DIM + 1] == tp.sd0_r);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_UPDATED);
}

/* §15.7 the prior with delta as a state (n = 11): x = (0, r_m, mean0, delta_m), S = diag(sd0,
 * sd_delta) with row stride 11. */
static void assert_dstate_prior(const rfe_tyre_id_params_t *tp, rfe_real_t r, rfe_real_t d)
{
    const size_t n = (size_t)RFE_TID_SCKF_DIM;
    size_t i;
    size_t j;
    assert_true(tid.sk.x[RFE_TID_VY] == 0 && tid.sk.x[RFE_TID_R] == r);
    assert_true(tid.sk.x[RFE_TID_DELTA] == d);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            rfe_real_t want = 0;
            if (i == j) {
                want = (i == 0u)                    ? tp->sd0_vy
                       : (i == 1u)                  ? tp->sd0_r
                       : (i == (size_t)RFE_TID_DELTA) ? tp->sd_delta
                                                    : tid.c.sd0[i - (size_t)RFE_TID_STATES];
            }
            assert_true(tid.sk.S[(i * n) + j] == want);
        }
    }
    for (j = 0u; j < (size_t)RFE_TID_PAR; ++j) {
        assert_true(tid.sk.x[(size_t)RFE_TID_STATES + j] == tid.c.mean0[j]);
    }
}

/* REQ-TID-002: the steering angle as the sigma-point filter's state (delta_state_q > 0,
 * TYRE_ID.md §15.7). The first sample sets the prior with delta_m and the sensor's sd (the
 * outputs those of the prior without it: delta is no output, S diagonal); an update puts the
 * sensor's sd in S_R's third entry and sd_ay in its second exactly (§15.3's slope term, which
 * makes it sqrt(sd_ay^2 + (g sd_delta)^2) > sd_ay on a turn, skipped), keeps delta's estimate
 * within three of its sds of the measured delta on a constant steer (measured with sd
 * sd_delta, a walk of 0.04 rad/sqrt(s): the posterior mean sits near the measurements), and
 * gives other estimates than the filter without it; a lost step sets the prior with this
 * sample's delta. */
static void test_sckf_delta_state(void **state)
{
    static rfe_tyre_id_t off;
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    rfe_tyre_id_params_t tp_off;
    rfe_tyre_id_estimate_t e;
    rfe_tyre_id_estimate_t e_off;
    const rfe_real_t d = (rfe_real_t)0.02;
    rfe_tyre_id_sample_t s = sample(0, d, 20, (rfe_real_t)0.12, (rfe_real_t)2.4);
    size_t k;
    size_t o;
    (void)state;
    setup_defaults(&veh, &tp);
    tp.filter = RFE_TID_SCKF;
    tp_off = tp;
    tp.delta_state_q = (rfe_real_t)0.04;
    assert_int_equal(rfe_tyre_id_init(&tid, &tp, &veh, 1u), RFE_OK);
    assert_int_equal(rfe_tyre_id_init(&off, &tp_off, &veh, 1u), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(rfe_tyre_id_step(&off, &s, &e_off), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_FIRST);
    assert_dstate_prior(&tp, s.yaw_rate, d);
    for (o = 0u; o < (size_t)RFE_TID_OUTPUTS; ++o) {
        if ((o != RFE_TID_OUT_BETA) && (o != RFE_TID_OUT_FY_F) && (o != RFE_TID_OUT_FY_R) &&
            (o != RFE_TID_OUT_B_F) && (o != RFE_TID_OUT_B_R)) {
            assert_true(e.mean[o] == e_off.mean[o] && e.sd[o] == e_off.sd[o]);
        }
    }
    s.dt = (rfe_real_t)0.01;
    for (k = 0u; k < 100u; ++k) {
        assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
        assert_int_equal(rfe_tyre_id_step(&off, &s, &e_off), RFE_OK);
        assert_int_equal(e.flags, RFE_TID_UPDATED);
        assert_true(tid.sk.sr[0] == tp.sd_r && tid.sk.sr[1] == tp.sd_ay);
        assert_true(tid.sk.sr[2] == tp.sd_delta);
        assert_true(off.sk.sr[1] > tp.sd_ay); /* the slope term, off: a turn, g != 0 */
    }
    {
        const size_t n = (size_t)RFE_TID_SCKF_DIM;
        const rfe_real_t *row = &tid.sk.S[(size_t)RFE_TID_DELTA * n];
        double v = 0.0;
        for (k = 0u; k < n; ++k) {
            v += (double)row[k] * (double)row[k];
        }
        assert_true(fabs((double)tid.sk.x[RFE_TID_DELTA] - (double)d) <= 3.0 * sqrt(v));
        assert_true(sqrt(v) < (double)tp.sd_delta); /* measured 100 times: narrower */
    }
    assert_true(e.mean[RFE_TID_OUT_K_F] != e_off.mean[RFE_TID_OUT_K_F]);
    /* lost (§15.3): the prior again, at this sample's yaw rate and delta */
    tid.sk.x[RFE_TID_VY] = (rfe_real_t)NAN;
    s.yaw_rate = (rfe_real_t)0.07;
    s.delta = (rfe_real_t)0.03;
    assert_int_equal(rfe_tyre_id_step(&tid, &s, &e), RFE_OK);
    assert_int_equal(e.flags, RFE_TID_LOST);
    assert_dstate_prior(&tp, (rfe_real_t)0.07, (rfe_real_t)0.03);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_defaults_and_validation),
        cmocka_unit_test(test_sckf_delta_state),
        cmocka_unit_test(test_ellipse_params),
        cmocka_unit_test(test_ellipse_dead_band),
        cmocka_unit_test(test_ellipse_scales_the_axle_forces),
        cmocka_unit_test(test_init_refusals_write_nothing),
        cmocka_unit_test(test_step_refusals_leave_the_state_untouched),
        cmocka_unit_test(test_sckf_step_refusals_leave_the_state_untouched),
        cmocka_unit_test(test_sckf_bounds_hold_and_straight_keeps_the_spread),
        cmocka_unit_test(test_sckf_prior_held_and_deterministic),
        cmocka_unit_test(test_sckf_lost_sets_the_prior_again),
        cmocka_unit_test(test_delta_filter_is_a_kalman_filter),
        cmocka_unit_test(test_log_sum_exp_with_extreme_log_likelihoods),
        cmocka_unit_test(test_parent_search_and_draws_on_hand_weights),
        cmocka_unit_test(test_order_by_weight_is_stable),
        cmocka_unit_test(test_reflect_hand_cases),
        cmocka_unit_test(test_bounds_hold_on_a_ramp_to_the_limit),
        cmocka_unit_test(test_straight_driving_keeps_the_spread_of_mu),
        cmocka_unit_test(test_held_below_v_min),
        cmocka_unit_test(test_lost_draws_the_prior_again),
        cmocka_unit_test(test_substeps),
        cmocka_unit_test(test_slip_beyond_alpha_max_is_clipped),
        cmocka_unit_test(test_init_refuses_unusable_derived_bounds),
        cmocka_unit_test(test_init_refuses_each_unusable_constant),
        cmocka_unit_test(test_huge_vehicle_gives_finite_sds),
        cmocka_unit_test(test_infinite_vy_weighs_zero),
        cmocka_unit_test(test_sckf_huge_vehicle_gives_finite_sds),
        cmocka_unit_test(test_sckf_overflowing_ay_noise_is_lost),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
