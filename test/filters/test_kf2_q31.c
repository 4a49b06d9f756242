/**
 * @file test_kf2_q31.c
 * @brief The fixed-point two-state Kalman filter (rfe_kf2_*_q31) back to back against the
 *        double twin (rfe_kf2_*_f64), and its argument checks, saturation counts and
 *        untouched state on every error.
 *
 * How the two are fed. Each case draws a real state, covariance and step, rounds them to
 * the Q formats, and gives the double filter the exact values of those integers: the
 * difference is the fixed-point arithmetic alone (the double's own rounding, ~1e-16
 * relative, is covered by DBL_REL below).
 *
 * Bounds (real units; LSB(q) = 2^-q).
 *  - Predict: x0 one rounding of f01 x1 (0.5 LSB(q0)); p01 one of f01 p11 (0.5
 *    LSB(q0 + q1)); p00 three roundings (2 f01 p01 as two products, f01 (f01 p11)) of 0.5
 *    LSB(2 q0) and the error of f01 p11 carried by f01: 1.5 LSB(2 q0) + 0.5 |f01|
 *    LSB(q0 + q1); p11 exact.
 *  - Update: ph_i = (P H^T)_i is two exactly rounded products (1 LSB(q_i + qz)); S three
 *    more (h0 ph0, h1 ph1 and their errors carried by |h|): e_S = |h0| e_ph0 + |h1| e_ph1 +
 *    1 LSB(2 qz). The gain ph_i / S is a 30-bit ratio: operands normalised to [2^29, 2^30]
 *    (2^-30 relative each) and the Q29 quotient (<= 2^-29 relative): 2^-28 in all. So
 *    |dx_i| <= |K_i nu| (2^-28 + e_ph_i / |ph_i| + e_S / S) + 1 LSB(q_i) (the applied
 *    product's rounding, and a pre-rounding for ratios below 2^-32), and
 *    |dp_ij| <= |ph_i ph_j / S| (2^-28 + e_ph_i/|ph_i| + e_ph_j/|ph_j| + e_S/S) + 1
 *    LSB(q_i + q_j), evaluated per case from the double's values.
 */
#include "test_common.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "host/fixed_conv.h"
#include "rfe/component/kf2.h"
#include "rfe/component/kf2_q31.h"
#include "test_rng.h"

#define N_RANDOM 4000
#define DBL_REL 1e-14 /* the double twin's own rounding on O(1e2) sums of a few terms */
#define GAIN_REL (1.0 / 268435456.0) /* 2^-28: the ratio's relative error */

/* The observer's three filters (docs/FIXED_POINT.md "Observer"): q0, q1, qf. */
typedef struct {
    unsigned int q0, q1, qf;
    double sd0_max, sd1_max, x0_max, x1_max; /* the real ranges drawn */
} fmt_case_t;

static const fmt_case_t FMTS[] = {
    {27u, 24u, 30u, 0.05, 3.0, 3.0, 20.0},   /* yaw: [r Q27, r-dot Q24], f01 = dt */
    {23u, 24u, 30u, 1.0, 0.3, 60.0, 2.0},    /* longitudinal: [vx Q23, b_x Q24], f01 = -dt */
    {23u, 24u, 30u, 0.3, 0.3, 10.0, 2.0},    /* lateral: [vy Q23, b_y Q24], f01 = -dt */
};

static double lsb(unsigned int q) { return ldexp(1.0, -(int)q); }

static int64_t var_q(double v, unsigned int q) { return (int64_t)llround(ldexp(v, (int)q)); }

/* The q31 filter's state as the double filter (exact: the integers are below 2^53 or their
 * rounding to double is far below the bounds). */
static void to_double(const rfe_kf2_q31_t *f, rfe_kf2_t *d)
{
    d->x[0] = rfe_fix_to_double(f->x[0], f->q0);
    d->x[1] = rfe_fix_to_double(f->x[1], f->q1);
    d->p00 = rfe_fix64_to_double(f->p00, 2u * f->q0);
    d->p01 = rfe_fix64_to_double(f->p01, f->q0 + f->q1);
    d->p11 = rfe_fix64_to_double(f->p11, 2u * f->q1);
}

/* A random state of format @p c: sds up to the maxima (down to 1e-4 of them), a
 * correlation in (-0.9, 0.9). */
static void random_state(const fmt_case_t *c, rfe_kf2_q31_t *f)
{
    uint32_t sat = 0u;
    const double s0 = c->sd0_max * pow(10.0, -2.0 * (rng_uniform() + 1.0));
    const double s1 = c->sd1_max * pow(10.0, -2.0 * (rng_uniform() + 1.0));
    const double rho = 0.9 * rng_uniform();
    assert_int_equal(rfe_kf2_init_q31(f, c->q0, c->q1, c->qf,
                                      rfe_fix_from_double(c->x0_max * rng_uniform(), c->q0, &sat),
                                      rfe_fix_from_double(c->x1_max * rng_uniform(), c->q1, &sat),
                                      0, 0),
                     RFE_OK);
    f->p00 = var_q(s0 * s0, 2u * c->q0);
    f->p11 = var_q(s1 * s1, 2u * c->q1);
    f->p01 = var_q(rho * s0 * s1, c->q0 + c->q1);
    assert_int_equal(sat, 0u);
}

static void check_predict(const fmt_case_t *c)
{
    rfe_kf2_q31_t f;
    rfe_kf2_t d;
    uint32_t sat = 0u;
    const double dt = 0.001 + 0.099 * 0.5 * (rng_uniform() + 1.0);
    const double f01 = (rng_uniform() < 0.0) ? -dt : dt;
    const rfe_fix_t f01q = rfe_fix_from_double(f01, c->qf, &sat);
    const rfe_fix_t uq = rfe_fix_from_double(dt * 5.0 * rng_uniform(), c->q0, &sat);
    const int64_t q00 = var_q(pow(dt * 0.05, 2.0), 2u * c->q0);
    const int64_t q11 = var_q(0.25 * dt, 2u * c->q1);
    const int64_t q01 = var_q(0.125 * dt * dt * rng_uniform(), c->q0 + c->q1);
    double b00, b01, b0;
    random_state(c, &f);
    to_double(&f, &d);
    assert_int_equal(rfe_kf2_predict(&d, rfe_fix_to_double(f01q, c->qf),
                                         rfe_fix_to_double(uq, c->q0),
                                         rfe_fix64_to_double(q00, 2u * c->q0),
                                         rfe_fix64_to_double(q11, 2u * c->q1),
                                         rfe_fix64_to_double(q01, c->q0 + c->q1)),
                     RFE_OK);
    assert_int_equal(rfe_kf2_predict_q31(&f, f01q, uq, q00, q11, q01, &sat), RFE_OK);
    assert_int_equal(sat, 0u);
    b0 = 0.5 * lsb(c->q0) + DBL_REL * fabs(d.x[0]);
    b01 = 0.5 * lsb(c->q0 + c->q1) + DBL_REL * fabs(d.p01);
    b00 = 1.5 * lsb(2u * c->q0) + 0.5 * fabs(f01) * lsb(c->q0 + c->q1) + DBL_REL * d.p00;
    ASSERT_LE(fabs(rfe_fix_to_double(f.x[0], c->q0) - d.x[0]), b0, "predict x0");
    ASSERT_LE(fabs(rfe_fix_to_double(f.x[1], c->q1) - d.x[1]), 0.0, "predict x1");
    ASSERT_LE(fabs(rfe_fix64_to_double(f.p00, 2u * c->q0) - d.p00), b00, "predict p00");
    ASSERT_LE(fabs(rfe_fix64_to_double(f.p01, c->q0 + c->q1) - d.p01), b01, "predict p01");
    ASSERT_LE(fabs(rfe_fix64_to_double(f.p11, 2u * c->q1) - d.p11), DBL_REL * d.p11,
              "predict p11");
}

/* One update of @p f (format already set) with @p m, against the double twin. */
static void check_update(rfe_kf2_q31_t *f, const rfe_kf2_meas_q31_t *m)
{
    rfe_kf2_t d;
    rfe_kf2_t d0;
    uint32_t sat = 0u;
    const double h0 = rfe_fix_to_double(m->h0, m->qh0);
    const double h1 = rfe_fix_to_double(m->h1, m->qh1);
    const double nu = rfe_fix_to_double(m->nu, m->qz);
    const double r = rfe_fix64_to_double(m->r, 2u * m->qz);
    double ph[2], S, eph[2], eS, rel[2];
    int i;
    to_double(f, &d);
    d0 = d;
    assert_int_equal(rfe_kf2_update(&d, h0, h1, nu, r), RFE_OK);
    assert_int_equal(rfe_kf2_update_q31(f, m, &sat), RFE_OK);
    assert_int_equal(sat, 0u);
    ph[0] = d0.p00 * h0 + d0.p01 * h1;
    ph[1] = d0.p01 * h0 + d0.p11 * h1;
    S = h0 * ph[0] + h1 * ph[1] + r;
    eph[0] = lsb(f->q0 + m->qz);
    eph[1] = lsb(f->q1 + m->qz);
    eS = fabs(h0) * eph[0] + fabs(h1) * eph[1] + lsb(2u * m->qz);
    for (i = 0; i < 2; ++i) {
        rel[i] = GAIN_REL + ((ph[i] != 0.0) ? eph[i] / fabs(ph[i]) : 0.0) + eS / S + DBL_REL;
    }
    ASSERT_LE(fabs(rfe_fix_to_double(f->x[0], f->q0) - d.x[0]),
              fabs(ph[0] / S * nu) * rel[0] + lsb(f->q0) + DBL_REL * fabs(d.x[0]), "update x0");
    ASSERT_LE(fabs(rfe_fix_to_double(f->x[1], f->q1) - d.x[1]),
              fabs(ph[1] / S * nu) * rel[1] + lsb(f->q1) + DBL_REL * fabs(d.x[1]), "update x1");
    ASSERT_LE(fabs(rfe_fix64_to_double(f->p00, 2u * f->q0) - d.p00),
              fabs(ph[0] * ph[0] / S) * (2.0 * rel[0]) + lsb(2u * f->q0) + DBL_REL * d0.p00,
              "update p00");
    ASSERT_LE(fabs(rfe_fix64_to_double(f->p01, f->q0 + f->q1) - d.p01),
              fabs(ph[0] * ph[1] / S) * (rel[0] + rel[1]) + lsb(f->q0 + f->q1) +
                  DBL_REL * fabs(d0.p01),
              "update p01");
    ASSERT_LE(fabs(rfe_fix64_to_double(f->p11, 2u * f->q1) - d.p11),
              fabs(ph[1] * ph[1] / S) * (2.0 * rel[1]) + lsb(2u * f->q1) + DBL_REL * d0.p11,
              "update p11");
}

/* REQ-FXP-013 */
static void test_predict_matches_double(void **state)
{
    int k;
    (void)state;
    rng_seed(11u);
    for (k = 0; k < N_RANDOM; ++k) {
        check_predict(&FMTS[(size_t)k % 3u]);
    }
}

/* REQ-FXP-013 */
static void test_update_matches_double(void **state)
{
    int k;
    uint32_t sat = 0u;
    (void)state;
    rng_seed(12u);
    for (k = 0; k < N_RANDOM; ++k) {
        const fmt_case_t *c = &FMTS[(size_t)k % 3u];
        rfe_kf2_q31_t f;
        rfe_kf2_meas_q31_t m;
        random_state(c, &f);
        switch (k % 4) {
        case 0: /* a direct measurement of x0 (wheel reference, yaw rate, low-speed vy) */
            m = (rfe_kf2_meas_q31_t){RFE_FIX_ONE(30), 0, 30u, 30u, c->q0,
                                     rfe_fix_from_double(c->sd0_max * rng_uniform(), c->q0, &sat),
                                     var_q(pow(0.05 * c->sd0_max, 2.0), 2u * c->q0)};
            break;
        case 1: /* the lateral model: z = ay (Q24), h0 = d ay / d vy in Q24 */
            m = (rfe_kf2_meas_q31_t){rfe_fix_from_double(-60.0 * (rng_uniform() + 1.0), 24u,
                                                         &sat),
                                     0, 24u, 24u, 24u,
                                     rfe_fix_from_double(2.0 * rng_uniform(), 24u, &sat),
                                     var_q(0.3 * 0.3 + 0.1 * rng_uniform() + 0.1, 48u)};
            break;
        case 2: /* the kinematic row: z = b_y (Q24), H = [0, 1] */
            m = (rfe_kf2_meas_q31_t){0, RFE_FIX_ONE(30), 24u, 30u, 24u,
                                     rfe_fix_from_double(3.0 * rng_uniform(), 24u, &sat),
                                     var_q(1.0 + 100.0 * (rng_uniform() + 1.0), 48u)};
            break;
        default: /* a general row on both states */
            m = (rfe_kf2_meas_q31_t){rfe_fix_from_double(rng_uniform(), 28u, &sat),
                                     rfe_fix_from_double(rng_uniform(), 28u, &sat), 28u, 28u,
                                     24u, rfe_fix_from_double(rng_uniform(), 24u, &sat),
                                     var_q(0.01 * (rng_uniform() + 1.1), 48u)};
            break;
        }
        check_update(&f, &m);
    }
    assert_int_equal(sat, 0u);
}

/* REQ-FXP-013: gains far below 2^-32 and above 2^28 (in the integers' units) take the
 * pre-rounded and the scaled-up path; both stay within the same bound. */
static void test_extreme_gains_match_double(void **state)
{
    rfe_kf2_q31_t f;
    rfe_kf2_meas_q31_t m;
    (void)state;
    /* tiny: var(x0) of 1e-12 against a noise of 1e2 m^2/s^2 */
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 30u, 0, 0, 0, 0), RFE_OK);
    f.p00 = var_q(1e-12, 46u);
    f.p11 = var_q(1e-4, 48u);
    f.p01 = var_q(1e-9, 47u);
    m = (rfe_kf2_meas_q31_t){RFE_FIX_ONE(30), 0, 30u, 30u, 23u, RFE_FIX_ONE(23),
                             var_q(100.0, 46u)};
    check_update(&f, &m);
    /* large: var(x0) at the bound, H = 2^-31 and r = 1 LSB, so ph0 / S ~ 2^29 in the
     * integers' units (the bound is loose here: S is two LSB, e_S / S ~ 1/2) */
    assert_int_equal(rfe_kf2_init_q31(&f, 31u, 31u, 1u, 0, 0, 0, 0), RFE_OK);
    f.p00 = RFE_KF2_Q31_PMAX;
    m = (rfe_kf2_meas_q31_t){1, 0, 31u, 31u, 31u, 1, 1};
    check_update(&f, &m);
}

/* REQ-FXP-013 */
static void test_init(void **state)
{
    rfe_kf2_q31_t f;
    rfe_kf2_q31_t before;
    (void)state;
    memset(&f, 0, sizeof f); /* its tail padding defined, so whole-struct compares see bytes */
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 30u, 100, -7, 1000, 3), RFE_OK);
    assert_int_equal(f.x[0], 100);
    assert_int_equal(f.x[1], -7);
    assert_true(f.p00 == 1000000);
    assert_true(f.p01 == 0);
    assert_true(f.p11 == 9);
    assert_int_equal((int)f.q0, 23);
    assert_int_equal((int)f.q1, 24);
    assert_int_equal((int)f.qf, 30);
    /* sd^2 beyond the covariance bound 2^61 is clamped */
    assert_int_equal(rfe_kf2_init_q31(&f, 31u, 31u, 1u, 0, 0, INT32_MAX, INT32_MAX), RFE_OK);
    assert_true(f.p00 == RFE_KF2_Q31_PMAX);
    assert_true(f.p11 == RFE_KF2_Q31_PMAX);
    memcpy(&before, &f, sizeof before); /* bytes, padding included (not a member copy) */
    assert_int_equal(rfe_kf2_init_q31(NULL, 23u, 24u, 30u, 0, 0, 0, 0), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 30u, 0, 0, -1, 0), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 30u, 0, 0, 0, -1), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_init_q31(&f, 32u, 24u, 30u, 0, 0, 0, 0), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 32u, 30u, 0, 0, 0, 0), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 32u, 0, 0, 0, 0), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_init_q31(&f, 31u, 0u, 0u, 0, 0, 0, 0), RFE_ERR_RANGE); /* shift < 1 */
    assert_int_equal(rfe_kf2_init_q31(&f, 0u, 31u, 31u, 0, 0, 0, 0), RFE_OK); /* shift 62 */
    assert_int_equal((int)f.q0, 0);
}

/* REQ-FXP-013 */
static void test_errors_leave_the_filter_untouched(void **state)
{
    rfe_kf2_q31_t f;
    rfe_kf2_q31_t before;
    rfe_kf2_meas_q31_t m = {RFE_FIX_ONE(30), 0, 30u, 30u, 23u, 100, 1000};
    rfe_kf2_meas_q31_t bad;
    uint32_t sat = 5u;
    (void)state;
    memset(&f, 0, sizeof f);
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 30u, 1, 2, 1000, 1000), RFE_OK);
    memcpy(&before, &f, sizeof before);
    assert_int_equal(rfe_kf2_predict_q31(NULL, 1, 0, 0, 0, 0, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_predict_q31(&f, 1, 0, 0, 0, 0, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_predict_q31(&f, 1, 0, RFE_KF2_Q31_PMAX + 1, 0, 0, &sat),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_predict_q31(&f, 1, 0, 0, -RFE_KF2_Q31_PMAX - 1, 0, &sat),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_predict_q31(&f, 1, 0, 0, 0, RFE_KF2_Q31_PMAX + 1, &sat),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_update_q31(NULL, &m, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_update_q31(&f, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_update_q31(&f, &m, NULL), RFE_ERR_NULL);
    bad = m;
    bad.r = -1;
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_RANGE);
    bad = m;
    bad.r = RFE_KF2_Q31_PMAX + 1;
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_RANGE);
    bad = m;
    bad.qz = 32u;
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_RANGE);
    bad = m;
    bad.qh0 = 32u;
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_RANGE);
    bad = m;
    bad.qh1 = 32u;
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_RANGE);
    bad = m;
    bad.qh0 = 0u; /* shift 23 + 0 - 23 = 0 */
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_RANGE);
    bad = m;
    bad.qh1 = 0u;
    bad.qz = 30u; /* shift 24 + 0 - 30 < 1 */
    bad.qh0 = 30u;
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_RANGE);
    bad = m;
    bad.qz = 0u;  /* shift 23 + 30 - 0 = 53 fine; 24 + 31 - 0 = 55 fine; make s0 > 62 */
    bad.qh0 = 31u;
    f.q0 = 31u;   /* 31 + 31 - 0 = 62 ok; the corrupted format below is not */
    f.q1 = 0u;
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_RANGE); /* q1 + qf - q0 < 1 */
    assert_int_equal(rfe_kf2_predict_q31(&f, 1, 0, 0, 0, 0, &sat), RFE_ERR_RANGE);
    memcpy(&f, &before, sizeof f);
    bad = m;
    bad.h0 = 0;
    bad.r = 0; /* S = 0 */
    assert_int_equal(rfe_kf2_update_q31(&f, &bad, &sat), RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_memory_equal(&f, &before, sizeof(f));
    assert_int_equal(sat, 5u);
}

/* REQ-FXP-013: every clamp is counted, and the clamped values are the bounds. */
static void test_saturation_is_counted(void **state)
{
    rfe_kf2_q31_t f;
    uint32_t sat = 0u;
    rfe_kf2_meas_q31_t m = {RFE_FIX_ONE(30), 0, 30u, 30u, 23u, INT32_MAX, 0};
    (void)state;
    /* a state driven beyond int32 by the input */
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 30u, INT32_MAX - 10, 0, 0, 0), RFE_OK);
    assert_int_equal(rfe_kf2_predict_q31(&f, 0, 100, 0, 0, 0, &sat), RFE_OK);
    assert_int_equal(f.x[0], INT32_MAX);
    assert_int_equal(sat, 1u);
    /* a covariance driven beyond the bound: p11 = PMAX, f01 large (every product of it and
     * of t saturates), q11 added on top */
    sat = 0u;
    assert_int_equal(rfe_kf2_init_q31(&f, 1u, 1u, 31u, 0, 0, 0, INT32_MAX), RFE_OK);
    f.p01 = -RFE_KF2_Q31_PMAX;
    assert_int_equal(rfe_kf2_predict_q31(&f, INT32_MAX, 0, 0, RFE_KF2_Q31_PMAX,
                                         -RFE_KF2_Q31_PMAX, &sat),
                     RFE_OK);
    assert_true(f.p11 == RFE_KF2_Q31_PMAX);
    assert_true(f.p01 == -RFE_KF2_Q31_PMAX);
    assert_true(sat >= 3u);
    /* an update with the gain 1 towards an innovation beyond the state's range */
    sat = 0u;
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 30u, INT32_MAX - 5, 0, 1 << 20, 0), RFE_OK);
    assert_int_equal(rfe_kf2_update_q31(&f, &m, &sat), RFE_OK);
    assert_int_equal(f.x[0], INT32_MAX);
    assert_int_equal(sat, 1u);
    /* a gain scaled up beyond the covariance bound: var(x0) = 2^61 LSB and H such that S
     * is 1 LSB, so ph0 / S reaches its Cauchy-Schwarz limit sqrt(p00 / S) = 2^30.5 in the
     * integers' units, times the largest innovation */
    sat = 0u;
    assert_int_equal(rfe_kf2_init_q31(&f, 31u, 31u, 1u, 0, 0, 0, 0), RFE_OK);
    f.p00 = RFE_KF2_Q31_PMAX;
    m = (rfe_kf2_meas_q31_t){1518500250, 0, 30u, 30u, 0u, INT32_MAX, 0};
    assert_int_equal(rfe_kf2_update_q31(&f, &m, &sat), RFE_OK);
    assert_int_equal(f.x[0], INT32_MAX);
    assert_true(sat >= 2u);
    /* products of a covariance and f01 beyond the bound by far (2^69) and by a little
     * (2^63, decided on the product rounded by two more bits) */
    sat = 0u;
    assert_int_equal(rfe_kf2_init_q31(&f, 1u, 1u, 1u, 0, 0, 0, 0), RFE_OK);
    f.p11 = (int64_t)1 << 40;
    assert_int_equal(rfe_kf2_predict_q31(&f, 1 << 30, 0, 0, 0, 0, &sat), RFE_OK);
    assert_true(f.p01 == RFE_KF2_Q31_PMAX);
    assert_true(sat >= 1u);
    sat = 0u;
    assert_int_equal(rfe_kf2_init_q31(&f, 1u, 1u, 1u, 0, 0, 0, 0), RFE_OK);
    f.p11 = ((int64_t)1 << 33) - 1;
    assert_int_equal(rfe_kf2_predict_q31(&f, -INT32_MAX, 0, 0, 0, 0, &sat), RFE_OK);
    assert_true(f.p01 == -RFE_KF2_Q31_PMAX);
    assert_true(sat >= 1u);
    /* the counter itself stops at UINT32_MAX */
    sat = UINT32_MAX;
    assert_int_equal(rfe_kf2_init_q31(&f, 23u, 24u, 30u, INT32_MAX - 10, 0, 0, 0), RFE_OK);
    assert_int_equal(rfe_kf2_predict_q31(&f, 0, 100, 0, 0, 0, &sat), RFE_OK);
    assert_int_equal(sat, UINT32_MAX);
}

/* REQ-FXP-013: the public covariance product: exactly rounded, clamped and counted, its
 * arguments checked. */
static void test_scale(void **state)
{
    int64_t y = 7;
    uint32_t sat = 0u;
    (void)state;
    assert_int_equal(rfe_kf2_scale_q31(3, 5, 1u, &y, &sat), RFE_OK);
    assert_true(y == 8); /* 15 / 2 = 7.5 rounds half up */
    assert_int_equal(rfe_kf2_scale_q31(-3, 5, 1u, &y, &sat), RFE_OK);
    assert_true(y == -7); /* -7.5 rounds half up */
    assert_int_equal(sat, 0u);
    assert_int_equal(rfe_kf2_scale_q31(RFE_KF2_Q31_PMAX, INT32_MAX, 1u, &y, &sat), RFE_OK);
    assert_true(y == RFE_KF2_Q31_PMAX);
    assert_int_equal(sat, 1u);
    y = 7;
    assert_int_equal(rfe_kf2_scale_q31(1, 1, 1u, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_scale_q31(1, 1, 1u, &y, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_kf2_scale_q31(RFE_KF2_Q31_PMAX + 1, 1, 1u, &y, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_scale_q31(-RFE_KF2_Q31_PMAX - 1, 1, 1u, &y, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_scale_q31(1, 1, 0u, &y, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_kf2_scale_q31(1, 1, 63u, &y, &sat), RFE_ERR_RANGE);
    assert_true(y == 7);
    assert_int_equal(sat, 1u);
}

typedef __int128 i128; /* the exact product (GNU C; tests only) */

/* clamp(floor(v c / 2^s + 1/2), +-PMAX) from the exact 93-bit product, and whether it clamped:
 * the definition the covariance product must meet. */
static int64_t scale_exact(int64_t v, int32_t c, unsigned int s, int *clamped)
{
    const i128 p = (i128)v * (i128)c;
    const i128 one = 1;
    const i128 half = one << (s - 1u);
    const i128 q = (p + half) >> s; /* GCC's >> on a negative i128 is the floor */
    *clamped = 1;
    if (q > (i128)RFE_KF2_Q31_PMAX) {
        return RFE_KF2_Q31_PMAX;
    }
    if (q < -(i128)RFE_KF2_Q31_PMAX) {
        return -RFE_KF2_Q31_PMAX;
    }
    *clamped = 0;
    return (int64_t)q;
}

/* REQ-FXP-013: the covariance product (rfe_kf2_scale_q31, the filters' mul_p_q31) is the
 * exactly rounded product clamped to +-PMAX with one count per clamp, for every shift 1 .. 62:
 * on random v and c of every magnitude and sign, and on the products that land on PMAX, one
 * LSB beyond it and one inside (either sign), where the clamp's decision is made from the high
 * word of the product alone for shifts up to 32. */
static void test_scale_exact(void **state)
{
    unsigned int s;
    int n;
    (void)state;
    rng_seed(0x5CA1Eull);
    for (s = 1u; s <= 62u; ++s) {
        for (n = 0; n < 400; ++n) {
            const int ev = (int)(rng_uniform() * 31.0) + 31; /* |v| up to 2^61 */
            const int ec = (int)(rng_uniform() * 16.0) + 16;
            int64_t v = (int64_t)(rng_uniform() * ldexp(1.0, ev));
            int32_t c = (int32_t)(rng_uniform() * ldexp(1.0, ec));
            int64_t y = 0;
            int clamped = 0;
            uint32_t sat = 0u;
            int64_t want;
            if (((n % 5) == 0) && (c != 0)) {
                /* v c / 2^s at +-PMAX: v = trunc(PMAX 2^s / c) + (-2 .. 2), when it fits */
                const i128 vv = ((i128)RFE_KF2_Q31_PMAX << s) / (i128)c;
                if ((vv < (i128)RFE_KF2_Q31_PMAX) && (vv > -(i128)RFE_KF2_Q31_PMAX)) {
                    v = ((int64_t)vv + (int64_t)((n / 5) % 5)) - 2;
                }
            }
            if (v > RFE_KF2_Q31_PMAX) {
                v = RFE_KF2_Q31_PMAX;
            } else if (v < -RFE_KF2_Q31_PMAX) {
                v = -RFE_KF2_Q31_PMAX;
            } else {
                /* inside */
            }
            if ((n % 3) == 1) {
                c = (c == INT32_MIN) ? INT32_MAX : -c;
            }
            if (n == 1) {
                c = INT32_MIN;
            }
            want = scale_exact(v, c, s, &clamped);
            assert_int_equal(rfe_kf2_scale_q31(v, c, s, &y, &sat), RFE_OK);
            assert_true(y == want);
            assert_int_equal(sat, (unsigned int)clamped);
        }
    }
}

/* REQ-FXP-013: an update skips the covariance product by an H entry of exactly 1 in its
 * format (h = 2^s, s <= 30, kf2_q31.c mul_h_q31) and takes the entry itself, which is the
 * integer the product gives: v 2^s / 2^s rounded is v, for every |v| <= PMAX (the filter's
 * entries), counting nothing. Checked against the product routine (rfe_kf2_scale_q31) at
 * every such s, at the ends of the range and at random magnitudes of both signs. */
static void test_a_unit_h_entry_is_the_product(void **state)
{
    unsigned int s;
    int n;
    (void)state;
    rng_seed(0x0117ull);
    for (s = 1u; s <= 30u; ++s) {
        const rfe_fix_t h = (rfe_fix_t)(INT32_C(1) << s);
        for (n = 0; n < 200; ++n) {
            const int ev = (int)(0.5 * (rng_uniform() + 1.0) * 61.0); /* |v| up to 2^61 */
            int64_t v = (int64_t)(rng_uniform() * ldexp(1.0, ev));
            int64_t y = 0;
            uint32_t sat = 0u;
            if (n == 0) {
                v = RFE_KF2_Q31_PMAX;
            } else if (n == 1) {
                v = -RFE_KF2_Q31_PMAX;
            } else if (n == 2) {
                v = 0;
            } else if ((v > RFE_KF2_Q31_PMAX) || (v < -RFE_KF2_Q31_PMAX)) {
                v = v / 2;
            } else {
                /* drawn inside the range */
            }
            assert_int_equal(rfe_kf2_scale_q31(v, h, s, &y, &sat), RFE_OK);
            assert_true(y == v);
            assert_int_equal(sat, 0u);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_predict_matches_double),
        cmocka_unit_test(test_update_matches_double),
        cmocka_unit_test(test_extreme_gains_match_double),
        cmocka_unit_test(test_init),
        cmocka_unit_test(test_errors_leave_the_filter_untouched),
        cmocka_unit_test(test_saturation_is_counted),
        cmocka_unit_test(test_scale),
        cmocka_unit_test(test_scale_exact),
        cmocka_unit_test(test_a_unit_h_entry_is_the_product),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
