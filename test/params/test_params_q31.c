/**
 * @file test_params_q31.c
 * @brief The fixed-point parameters (rfe/params_q31.h) and the converter (rfe/component/params_conv.h):
 *        the integer preset tables equal the converted double presets bit for bit, the
 *        converter rounds to nearest and rejects what does not fit, the validation accepts
 *        every converted valid parameter set and rejects each invalid field and each stale
 *        derived constant.
 *
 * Bounds: conversion is exact rounding, so |q - x 2^Q| <= 0.5 for every field (checked). The
 * validation's consistency tolerance is 2^-13 relative + 2 LSB (params_q31.h); a converted
 * set passes because the converter's rounding of at most five 16-bit-or-larger base fields
 * per constant gives <= 5 2^-17 relative, and a base field changed by 0.1 % fails.
 */
#include "test_common.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "host/fixed_conv.h"
#include "rfe/component/fxmath.h"
#include "rfe/params.h"
#include "rfe/component/params_conv.h"
#include "rfe/params_q31.h"
#include "test_rng.h"

/* Every int32 field with its Q format and its real value in rfe_params_t (derived: NAN). */
#define Q31_FIELDS(X)                                                                            \
    X(vehicle.m, 16, p->vehicle.m)                                                               \
    X(vehicle.Lf, 29, p->vehicle.Lf)                                                             \
    X(vehicle.Lr, 29, p->vehicle.Lr)                                                             \
    X(vehicle.Bf, 29, p->vehicle.Bf)                                                             \
    X(vehicle.Br, 29, p->vehicle.Br)                                                             \
    X(vehicle.R, 29, p->vehicle.R)                                                               \
    X(vehicle.J, 12, p->vehicle.J)                                                               \
    X(vehicle.hg, 29, p->vehicle.hg)                                                             \
    X(vehicle.g, 24, p->vehicle.g)                                                               \
    X(vehicle.yf, 29, p->vehicle.Bf / 2)                                                         \
    X(vehicle.yr, 29, p->vehicle.Br / 2)                                                         \
    X(vehicle.inv_m, 38, 1.0 / p->vehicle.m)                                                     \
    X(vehicle.lf_J, 38, p->vehicle.Lf / p->vehicle.J)                                            \
    X(vehicle.lr_J, 38, p->vehicle.Lr / p->vehicle.J)                                            \
    X(vehicle.yf_J, 38, p->vehicle.Bf / 2 / p->vehicle.J)                                        \
    X(vehicle.yr_J, 38, p->vehicle.Br / 2 / p->vehicle.J)                                        \
    X(vehicle.fz_static_f, 15, MG * p->vehicle.Lr / (2 * LA))                                    \
    X(vehicle.fz_static_r, 15, MG * p->vehicle.Lf / (2 * LA))                                    \
    X(vehicle.k_pitch, 20, MH / (2 * LA))                                                        \
    X(vehicle.k_roll_f, 20, MH * p->vehicle.Lr / (LA * p->vehicle.Bf))                           \
    X(vehicle.k_roll_r, 20, MH * p->vehicle.Lf / (LA * p->vehicle.Br))                           \
    X(tyre.Cx_n, 24, p->tyre.Cx_n)                                                               \
    X(tyre.Cy_n, 24, p->tyre.Cy_n)                                                               \
    X(tyre.cx, 24, p->tyre.cx)                                                                   \
    X(tyre.cy, 24, p->tyre.cy)                                                                   \
    X(tyre.eps, 32, p->tyre.eps)                                                                 \
    X(tyre.v_min, 23, p->tyre.v_min)                                                             \
    X(tyre.alpha_max, 29, p->tyre.alpha_max)                                                     \
    X(tyre.shape_Cx, 24, p->tyre.shape_Cx)                                                       \
    X(tyre.shape_Ex, 24, p->tyre.shape_Ex)                                                       \
    X(tyre.shape_Cy, 24, p->tyre.shape_Cy)                                                       \
    X(tyre.shape_Ey, 24, p->tyre.shape_Ey)                                                       \
    X(filter.mu0, 29, p->filter.mu0)                                                             \
    X(filter.sd0, 30, p->filter.sd0)                                                             \
    X(filter.q_mu, 30, p->filter.q_mu)                                                           \
    X(filter.r_ax, 24, p->filter.r_ax)                                                           \
    X(filter.r_ay, 24, p->filter.r_ay)                                                           \
    X(filter.r_yaw_acc, 24, p->filter.r_yaw_acc)                                                 \
    X(filter.mu_min, 29, p->filter.mu_min)                                                       \
    X(filter.mu_max, 29, p->filter.mu_max)                                                       \
    X(filter.v_est_min, 23, p->filter.v_est_min)                                                 \
    X(filter.sd0_common, 30, p->filter.sd0_common)                                               \
    X(filter.q_common, 30, p->filter.q_common)                                                   \
    X(filter.dt, 30, p->filter.dt)                                                               \
    X(filter.tau_v, 26, p->filter.tau_v)                                                         \
    X(filter.sd_in_delta, 29, p->filter.sd_in_delta)                                             \
    X(filter.sd_in_vx, 23, p->filter.sd_in_vx)                                                   \
    X(filter.sd_in_vy, 23, p->filter.sd_in_vy)                                                   \
    X(filter.sd_in_yaw_rate, 27, p->filter.sd_in_yaw_rate)                                       \
    X(filter.sd_in_omega, 22, p->filter.sd_in_omega)                                             \
    X(filter.r_model_rel, 30, p->filter.r_model_rel)                                             \
    X(filter.info_min, 10, p->filter.info_min)                                                   \
    X(filter.sd_max, 30, p->filter.sd_max)                                                       \
    X(filter.sd_floor_rel, 30, p->filter.sd_floor_rel)                                           \
    X(filter.sd_valid, 30, p->filter.sd_valid)                                                   \
    X(filter.rear_hold_k, 24, p->filter.rear_hold_k)                                             \
    X(filter.jump_hold_k, 24, p->filter.jump_hold_k)                                             \
    X(filter.jump_hold_len, 27, p->filter.jump_hold_len)                                         \
    X(filter.stale_omega, 22, p->filter.stale_omega)                                             \
    X(filter.yaw_check, 27, p->filter.yaw_check)                                                 \
    X(filter.valid_bound_k, 24, p->filter.valid_bound_k)                                         \
    X(filter.b_v, 30, p->filter.dt / (p->filter.tau_v + p->filter.dt))

#define MG (p->vehicle.m * p->vehicle.g)
#define MH (p->vehicle.m * p->vehicle.hg)
#define LA (p->vehicle.Lf + p->vehicle.Lr)

/* Fails unless every field of a equals b's (and the enums). */
static void assert_same(const rfe_params_q31_t *a, const rfe_params_q31_t *b, const char *what)
{
#define SAME_(f, q, x)                                                                          \
    if (a->f != b->f) {                                                                         \
        fail_msg("%s: field %s: %ld != %ld", what, #f, (long)a->f, (long)b->f);                 \
    }
    Q31_FIELDS(SAME_)
#undef SAME_
    assert_int_equal(a->tyre.mode, b->tyre.mode);
    assert_int_equal(a->filter.kind, b->filter.kind);
    assert_int_equal(a->filter.structure, b->filter.structure);
}

/* Every field is the real value rounded to nearest: |q - x 2^Q| <= 0.5. */
static void assert_rounded(const rfe_params_t *p, const rfe_params_q31_t *q)
{
#define ROUND_(f, qf, x)                                                                        \
    if (!(fabs((double)q->f - ldexp((double)(x), qf)) <= 0.5)) {                                \
        fail_msg("field %s: %ld is not round(%.17g 2^%d)", #f, (long)q->f, (double)(x), qf);    \
    }
    Q31_FIELDS(ROUND_)
#undef ROUND_
}

/* REQ: the integer preset tables equal the converted double presets bit for bit, are exactly
 * rounded, and validate: the paper preset in paper tyre mode, the default preset in magic tyre
 * mode with info_min 25, both with the Magic Formula shape factors 1.65, 0, 1.3, 0. */
/* REQ-PARAMS-004 REQ-PARAMS-001 */
static void test_params_q31_presets_equal_converted(void **state)
{
    rfe_params_t p;
    rfe_params_q31_t tab, conv;
    (void)state;
    assert_int_equal(rfe_params_paper_f64(&p), RFE_OK);
    memset(&conv, 0, sizeof(conv));
    assert_int_equal(rfe_params_to_q31_f64(&p, &conv), RFE_OK);
    assert_int_equal(rfe_params_paper_q31(&tab), RFE_OK);
    assert_same(&tab, &conv, "paper");
    assert_rounded(&p, &conv);
    assert_int_equal(rfe_params_validate_q31(&tab), RFE_OK);
    assert_int_equal(tab.tyre.mode, RFE_TYRE_PAPER);
    assert_int_equal(tab.tyre.shape_Cx, 27682406); /* 1.65 2^24 = 27682406.4 */
    assert_int_equal(tab.tyre.shape_Ex, 0);
    assert_int_equal(tab.tyre.shape_Cy, 21810381); /* 1.3 2^24 = 21810380.8 */
    assert_int_equal(tab.tyre.shape_Ey, 0);

    assert_int_equal(rfe_params_default_f64(&p), RFE_OK);
    assert_int_equal(rfe_params_to_q31_f64(&p, &conv), RFE_OK);
    assert_int_equal(rfe_params_default_q31(&tab), RFE_OK);
    assert_same(&tab, &conv, "default");
    assert_rounded(&p, &conv);
    assert_int_equal(rfe_params_validate_q31(&tab), RFE_OK);
    assert_int_equal(tab.tyre.mode, RFE_TYRE_MAGIC);
    assert_int_equal(tab.filter.structure, RFE_STRUCT_SIDES);
    assert_int_equal(tab.filter.info_min, 25 << 10);
    assert_int_equal(tab.tyre.shape_Cx, 27682406);
    assert_int_equal(tab.tyre.shape_Cy, 21810381);

    assert_int_equal(rfe_params_paper_q31(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_params_default_q31(NULL), RFE_ERR_NULL);
}

static double uni(double a, double b) { return a + (b - a) * 0.5 * (rng_uniform() + 1.0); }

/* A random valid parameter set: passenger cars to light trucks. */
static void random_params(rfe_params_t *p)
{
    assert_int_equal(rfe_params_default_f64(p), RFE_OK);
    p->vehicle.m = uni(400, 4000);
    p->vehicle.Lf = uni(0.8, 2.5);
    p->vehicle.Lr = uni(0.8, 2.5);
    p->vehicle.Bf = uni(1.2, 2.2);
    p->vehicle.Br = uni(1.2, 2.2);
    p->vehicle.R = uni(0.2, 0.6);
    p->vehicle.J = uni(300, 20000);
    p->vehicle.hg = (rng_uniform() < -0.9) ? 0.0 : uni(0.3, 1.2);
    p->vehicle.g = uni(9.78, 9.83);
    p->tyre.Cx_n = uni(5, 60);
    p->tyre.Cy_n = uni(5, 60);
    p->tyre.cx = uni(5, 60);
    p->tyre.cy = uni(5, 60);
    p->tyre.eps = uni(0, 0.05);
    p->tyre.v_min = uni(0.1, 2);
    p->tyre.alpha_max = uni(0.5, 1.49);
    p->tyre.shape_Cx = uni(1.01, 1.99);
    p->tyre.shape_Cy = uni(1.01, 1.99);
    p->tyre.shape_Ex = (rng_uniform() < 0.0) ? 0.0 : uni(-4.0, 0.99);
    p->tyre.shape_Ey = (rng_uniform() < 0.0) ? 0.0 : uni(-4.0, 0.99);
    p->tyre.mode = (rng_uniform() < -0.3) ? RFE_TYRE_ABSOLUTE : RFE_TYRE_MAGIC;
    p->filter.dt = uni(0.001, 0.1);
    p->filter.tau_v = (rng_uniform() < -0.5) ? 0.0 : uni(0.01, 10);
    p->filter.info_min = uni(0, 1e4);
}

/* True when some field of p does not fit its Q format (the converter's RANGE cases that
 * random_params can produce: a large, tall, short vehicle's load-transfer coefficient). */
static int some_field_too_large(const rfe_params_t *p)
{
    int big = 0;
#define BIG_(f, qf, x) big |= (fabs(ldexp((double)(x), qf)) >= 2147483647.5);
    Q31_FIELDS(BIG_)
#undef BIG_
    return big;
}

/* REQ: every converted valid parameter set validates (2000 random vehicles, tyres and filter
 * timings), is exactly rounded, and changing a base field by 0.1 % without its derived
 * constants is rejected as inconsistent; a set the converter rejects has a field beyond its
 * format. */
/* REQ-PARAMS-004 */
static void test_params_q31_converted_sets_validate(void **state)
{
    int n, n_hg = 0, n_range = 0;
    (void)state;
    rng_seed(0xCA12ull);
    for (n = 0; n < 2000; ++n) {
        rfe_params_t p;
        rfe_params_q31_t q, t;
        rfe_status_t st;
        random_params(&p);
        assert_int_equal(rfe_params_validate_f64(&p), RFE_OK);
        st = rfe_params_to_q31_f64(&p, &q);
        if (st == RFE_ERR_RANGE) {
            assert_true(some_field_too_large(&p));
            ++n_range;
            continue;
        }
        assert_int_equal(st, RFE_OK);
        assert_rounded(&p, &q);
        assert_int_equal(rfe_params_validate_q31(&q), RFE_OK);
        /* stale derived constants: each base field 0.1 % off */
        t = q;
        t.vehicle.m += t.vehicle.m / 1000;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        t = q;
        t.vehicle.Lf += t.vehicle.Lf / 1000;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        t = q;
        t.vehicle.Lr -= t.vehicle.Lr / 1000;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        t = q;
        t.vehicle.Bf += t.vehicle.Bf / 1000;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        t = q;
        t.vehicle.Br -= t.vehicle.Br / 1000;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        t = q;
        t.vehicle.J += t.vehicle.J / 1000;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        t = q;
        t.vehicle.g -= t.vehicle.g / 1000;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        t = q;
        t.filter.dt += t.filter.dt / 1000;
        assert_int_equal(rfe_params_validate_q31(&t),
                         (q.filter.tau_v == 0) ? RFE_OK : RFE_ERR_PARAM); /* b_v = 1 either way */
        if (q.vehicle.hg > 0) {
            t = q;
            t.vehicle.hg += t.vehicle.hg / 1000;
            assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
            ++n_hg;
        }
        if (q.filter.tau_v > 0) {
            t = q;
            t.filter.tau_v += t.filter.tau_v / 1000;
            assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        }
    }
    printf("random parameter sets: 2000, %d beyond a format (load transfer > 2048 kg)\n",
           n_range);
    assert_true(n_range < 200);
    assert_true(n_hg > 1500);
}

/* REQ: each derived constant off by more than the tolerance (2^-12 relative) is rejected, one
 * off by its own rounding (1 LSB) is accepted. */
/* REQ-PARAMS-004 */
static void test_params_q31_derived_consistency(void **state)
{
    rfe_params_q31_t q, t;
    int32_t *const fields[] = {
        &t.vehicle.yf,      &t.vehicle.yr,          &t.vehicle.inv_m,       &t.vehicle.lf_J,
        &t.vehicle.lr_J,    &t.vehicle.yf_J,        &t.vehicle.yr_J,        &t.vehicle.fz_static_f,
        &t.vehicle.fz_static_r, &t.vehicle.k_pitch, &t.vehicle.k_roll_f,    &t.vehicle.k_roll_r,
        &t.filter.b_v};
    size_t i;
    (void)state;
    assert_int_equal(rfe_params_default_q31(&q), RFE_OK);
    for (i = 0; i < sizeof(fields) / sizeof(fields[0]); ++i) {
        t = q;
        *fields[i] += 1;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_OK);
        t = q;
        *fields[i] -= 1;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_OK);
        t = q;
        *fields[i] += *fields[i] / 4096;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
        t = q;
        *fields[i] -= *fields[i] / 4096;
        assert_int_equal(rfe_params_validate_q31(&t), RFE_ERR_PARAM);
    }
}

/* REQ: each field outside its range is rejected (the checks of rfe_params_validate on the Q
 * values, the 16-significant-bit rule, alpha_max < 1.5 rad, the tyre mode, the Magic Formula
 * shape factors 1 < C < 2, -4 <= E < 1 in every mode, the CKF subset). */
/* REQ-PARAMS-002 */
static void test_params_q31_validate_rejects(void **state)
{
    rfe_params_q31_t q, t;
    (void)state;
    assert_int_equal(rfe_params_validate_q31(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_params_default_q31(&q), RFE_OK);
#define REJECT_(stmt)                                                                           \
    do {                                                                                        \
        t = q;                                                                                  \
        stmt;                                                                                   \
        if (rfe_params_validate_q31(&t) != RFE_ERR_PARAM) {                                     \
            fail_msg("accepted: %s", #stmt);                                                    \
        }                                                                                       \
    } while (0)
    /* vehicle base fields */
    REJECT_(t.vehicle.m = 0);
    REJECT_(t.vehicle.m = 65535); /* 1 kg - 1 LSB: fewer than 16 significant bits */
    REJECT_(t.vehicle.Lf = -t.vehicle.Lf);
    REJECT_(t.vehicle.Lr = 0);
    REJECT_(t.vehicle.Bf = 0);
    REJECT_(t.vehicle.Br = -1);
    REJECT_(t.vehicle.R = 0);
    REJECT_(t.vehicle.J = 0);
    REJECT_(t.vehicle.J = 1000);
    REJECT_(t.vehicle.hg = -1);
    REJECT_(t.vehicle.hg = 1000);
    REJECT_(t.vehicle.g = 0);
    REJECT_(t.vehicle.g = 100);
    REJECT_(t.vehicle.Lf = 100);
    REJECT_(t.vehicle.Lr = 100);
    REJECT_(t.vehicle.Bf = 100);
    REJECT_(t.vehicle.Br = 100);
    /* derived: sign and significance */
    REJECT_(t.vehicle.yf = 0);
    REJECT_(t.vehicle.yr = 0);
    REJECT_(t.vehicle.inv_m = 0);
    REJECT_(t.vehicle.lf_J = 0);
    REJECT_(t.vehicle.lr_J = 0);
    REJECT_(t.vehicle.yf_J = 0);
    REJECT_(t.vehicle.yr_J = 0);
    REJECT_(t.vehicle.fz_static_f = 0);
    REJECT_(t.vehicle.fz_static_r = 0);
    REJECT_(t.vehicle.k_pitch = -1);
    REJECT_(t.vehicle.k_roll_f = -1);
    REJECT_(t.vehicle.k_roll_r = -1);
    REJECT_(t.vehicle.yf = 100);
    REJECT_(t.vehicle.yr = 100);
    REJECT_(t.vehicle.inv_m = 100);
    REJECT_(t.vehicle.lf_J = 100);
    REJECT_(t.vehicle.lr_J = 100);
    REJECT_(t.vehicle.yf_J = 100);
    REJECT_(t.vehicle.yr_J = 100);
    REJECT_(t.vehicle.fz_static_f = 100);
    REJECT_(t.vehicle.fz_static_r = 100);
    REJECT_(t.vehicle.k_pitch = 100);
    REJECT_(t.vehicle.k_roll_f = 100);
    REJECT_(t.vehicle.k_roll_r = 100);
    /* hg = 0 needs zero load transfer */
    REJECT_(t.vehicle.hg = 0);
    t = q;
    t.vehicle.hg = 0;
    t.vehicle.k_pitch = t.vehicle.k_roll_f = t.vehicle.k_roll_r = 0;
    assert_int_equal(rfe_params_validate_q31(&t), RFE_OK);
    /* a derived constant whose recomputation does not fit its format */
    REJECT_(t.vehicle.m = 65536; t.vehicle.inv_m = INT32_MAX); /* 1/(1 kg) is 2^38 in Q38 */
    /* tyre */
    REJECT_(t.tyre.mode = (rfe_tyre_mode_t)3);
    REJECT_(t.tyre.mode = (rfe_tyre_mode_t)-1);
    REJECT_(t.tyre.Cx_n = 0);
    REJECT_(t.tyre.Cy_n = 0);
    REJECT_(t.tyre.cx = -1);
    REJECT_(t.tyre.cy = 0);
    REJECT_(t.tyre.eps = -1);
    REJECT_(t.tyre.v_min = 0);
    REJECT_(t.tyre.alpha_max = 0);
    REJECT_(t.tyre.alpha_max = RFE_FIX_TAN_LIMIT_Q29);
    /* the Magic Formula shape factors: 1 < C < 2, -4 <= E < 1 (Q24), one rejection per bound
     * and key */
    REJECT_(t.tyre.shape_Cx = 1 << 24);
    REJECT_(t.tyre.shape_Cx = 2 << 24);
    REJECT_(t.tyre.shape_Ex = -(4 << 24) - 1);
    REJECT_(t.tyre.shape_Ex = 1 << 24);
    REJECT_(t.tyre.shape_Cy = 1 << 24);
    REJECT_(t.tyre.shape_Cy = 2 << 24);
    REJECT_(t.tyre.shape_Ey = -(4 << 24) - 1);
    REJECT_(t.tyre.shape_Ey = 1 << 24);
    /* in every mode (the shape is tyre data, checked also where it is not used) */
    REJECT_(t.tyre.mode = RFE_TYRE_PAPER; t.tyre.shape_Cx = 0);
    REJECT_(t.tyre.mode = RFE_TYRE_ABSOLUTE; t.tyre.shape_Ey = 1 << 24);
    t = q;
    t.tyre.shape_Cx = (1 << 24) + 1; /* the bounds themselves, or 1 LSB inside */
    t.tyre.shape_Ex = -(4 << 24);
    t.tyre.shape_Cy = (2 << 24) - 1;
    t.tyre.shape_Ey = (1 << 24) - 1;
    assert_int_equal(rfe_params_validate_q31(&t), RFE_OK);
    t.tyre.mode = RFE_TYRE_ABSOLUTE;
    assert_int_equal(rfe_params_validate_q31(&t), RFE_OK);
    t = q;
    t.tyre.alpha_max = RFE_FIX_TAN_LIMIT_Q29 - 1;
    t.tyre.eps = 0;
    t.tyre.mode = RFE_TYRE_PAPER;
    assert_int_equal(rfe_params_validate_q31(&t), RFE_OK);
    /* filter */
    REJECT_(t.filter.kind = (rfe_filter_kind_t)5);
    REJECT_(t.filter.structure = (rfe_structure_t)5);
    REJECT_(t.filter.sd0 = 0);
    REJECT_(t.filter.q_mu = 0);
    REJECT_(t.filter.r_ax = 0);
    REJECT_(t.filter.r_ay = 0);
    REJECT_(t.filter.r_yaw_acc = 0);
    REJECT_(t.filter.mu_min = -1);
    REJECT_(t.filter.mu_max = 0);
    REJECT_(t.filter.mu_min = t.filter.mu_max);
    REJECT_(t.filter.mu0 = t.filter.mu_min - 1);
    REJECT_(t.filter.mu0 = t.filter.mu_max + 1);
    REJECT_(t.filter.v_est_min = -1);
    REJECT_(t.filter.sd0_common = -1);
    REJECT_(t.filter.q_common = -1);
    REJECT_(t.filter.dt = 0);
    REJECT_(t.filter.dt = 1000);
    REJECT_(t.filter.tau_v = -1);
    REJECT_(t.filter.tau_v = 1000);
    REJECT_(t.filter.sd_in_delta = -1);
    REJECT_(t.filter.sd_in_vx = -1);
    REJECT_(t.filter.sd_in_vy = -1);
    REJECT_(t.filter.sd_in_yaw_rate = -1);
    REJECT_(t.filter.sd_in_omega = -1);
    REJECT_(t.filter.r_model_rel = -1);
    REJECT_(t.filter.info_min = -1);
    REJECT_(t.filter.sd_max = -1);
    REJECT_(t.filter.sd_floor_rel = -1);
    REJECT_(t.filter.sd_valid = -1);
    REJECT_(t.filter.rear_hold_k = -1);
    REJECT_(t.filter.jump_hold_k = -1);
    REJECT_(t.filter.jump_hold_len = -1);
    REJECT_(t.filter.b_v = 0);
    REJECT_(t.filter.b_v = 100);
    REJECT_(t.filter.b_v = RFE_FIX_ONE(30) + 1);
    /* the CKF subset: the default preset's additions are not allowed */
    REJECT_(t.filter.kind = RFE_FILTER_CKF);
    assert_int_equal(rfe_params_paper_q31(&q), RFE_OK);
    q.filter.kind = RFE_FILTER_CKF;
    q.tyre.mode = RFE_TYRE_ABSOLUTE;
    q.filter.sd_valid = 1000;
    assert_int_equal(rfe_params_validate_q31(&q), RFE_OK);
    REJECT_(t.filter.structure = RFE_STRUCT_SIDES);
    REJECT_(t.filter.sd0_common = 1);
    REJECT_(t.filter.q_common = 1);
    REJECT_(t.filter.tau_v = 65536; t.filter.b_v = 978213192); /* tau_v 1/1024 s, b_v consistent */
    REJECT_(t.filter.sd_in_delta = 1);
    REJECT_(t.filter.sd_in_vx = 1);
    REJECT_(t.filter.sd_in_vy = 1);
    REJECT_(t.filter.sd_in_yaw_rate = 1);
    REJECT_(t.filter.sd_in_omega = 1);
    REJECT_(t.filter.r_model_rel = 1);
    REJECT_(t.filter.info_min = 1);
    REJECT_(t.filter.sd_max = 1);
    REJECT_(t.filter.sd_floor_rel = 1);
    REJECT_(t.monitor.enable = 1u); /* the monitor reads the SCKF's innovations */
    /* the monitor's constants */
    assert_int_equal(rfe_monitor_params_validate_q31(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_params_default_q31(&q), RFE_OK);
    q.monitor.enable = 1u;
    assert_int_equal(rfe_params_validate_q31(&q), RFE_OK);
    REJECT_(t.monitor.enable = 2u);
    REJECT_(t.monitor.inflate = 2u);
    REJECT_(t.monitor.hold_steps = 0x80000000u);
    REJECT_(t.monitor.warmup_steps = 0x80000000u);
    REJECT_(t.monitor.l_d = 0);
    REJECT_(t.monitor.l_d = 65535); /* 2^-14 - 1 LSB: fewer than 16 significant bits */
    REJECT_(t.monitor.l_m = RFE_FIX_ONE(30));
    REJECT_(t.monitor.z_d_clear = 0);
    REJECT_(t.monitor.z_d_clear = t.monitor.z_d_fire);
    REJECT_(t.monitor.z_d_fire = RFE_FIX_MON_Z_MAX + 1);
    REJECT_(t.monitor.z_m_clear = -1);
    REJECT_(t.monitor.z_m_fire = t.monitor.z_m_clear);
    REJECT_(t.monitor.z_m_fire = RFE_FIX_MON_Z_MAX + 1);
#undef REJECT_
}

#define SENT ((int32_t)0x5A5A5A5A)

/* REQ: the converter: NULL -> RFE_ERR_NULL, an invalid real parameter set -> RFE_ERR_PARAM, a
 * value that does not fit its format (too large, a nonzero value rounding to 0, fewer than 16
 * significant bits where required, a derived constant out of range, alpha_max rounding to
 * 1.5 rad, a shape factor rounding onto an open bound, a monitor weight below 2^-14 or a
 * quantile above 8) -> RFE_ERR_RANGE; the output untouched on every error; the shape factors
 * and the monitor's constants converted at their bounds. */
/* REQ-PARAMS-004 REQ-MON-009 */
static void test_params_q31_converter_errors(void **state)
{
    rfe_params_t p0, p;
    rfe_params_q31_t q, q0;
    (void)state;
    assert_int_equal(rfe_params_default_f64(&p0), RFE_OK);
    memset(&q, 0x5A, sizeof(q));
    q0 = q;
    assert_int_equal(rfe_params_to_q31_f64(NULL, &q), RFE_ERR_NULL);
    assert_int_equal(rfe_params_to_q31_f64(&p0, NULL), RFE_ERR_NULL);
#define CONV_(stmt, expect)                                                                     \
    do {                                                                                        \
        p = p0;                                                                                 \
        stmt;                                                                                   \
        if (rfe_params_to_q31_f64(&p, &q) != (expect)) {                                        \
            fail_msg("%s: not %s", #stmt, #expect);                                             \
        }                                                                                       \
        assert_memory_equal(&q, &q0, sizeof(q));                                                \
    } while (0)
    CONV_(p.vehicle.m = -1.0, RFE_ERR_PARAM);
    CONV_(p.vehicle.m = NAN, RFE_ERR_PARAM);
    CONV_(p.tyre.alpha_max = 1.6, RFE_ERR_PARAM);
    CONV_(p.vehicle.m = 40000.0, RFE_ERR_RANGE);             /* beyond Q16 */
    CONV_(p.vehicle.m = 100.0, RFE_ERR_RANGE);               /* 1/m beyond Q38 */
    CONV_(p.vehicle.hg = 1e-5, RFE_ERR_RANGE);               /* 5369 LSB < 2^16 */
    CONV_(p.filter.q_mu = 1e-12, RFE_ERR_RANGE);             /* nonzero, rounds to 0 */
    CONV_(p.filter.sd_in_vx = 1e-9, RFE_ERR_RANGE);          /* "on" must not become "off" */
    CONV_(p.filter.tau_v = 1e-4, RFE_ERR_RANGE);             /* 6711 LSB < 2^16 */
    CONV_(p.filter.info_min = 3e6, RFE_ERR_RANGE);           /* beyond Q10 */
    CONV_(p.tyre.alpha_max = 1.5 - 1e-12, RFE_ERR_RANGE);    /* rounds to 1.5 rad */
    CONV_(p.tyre.eps = 0.6, RFE_ERR_RANGE);                  /* beyond Q32 */
    CONV_(p.tyre.shape_Cx = 1.0, RFE_ERR_PARAM);             /* 1 < C < 2 */
    CONV_(p.tyre.shape_Ey = 1.0, RFE_ERR_PARAM);             /* E < 1 */
    CONV_(p.tyre.shape_Cx = 1.0 + 1e-9, RFE_ERR_RANGE);      /* rounds to C = 1 */
    CONV_(p.tyre.shape_Cy = 2.0 - 1e-9, RFE_ERR_RANGE);      /* rounds to C = 2 */
    CONV_(p.tyre.shape_Ex = 1.0 - 1e-9, RFE_ERR_RANGE);      /* rounds to E = 1 */
    CONV_(p.tyre.shape_Ey = 1.0 - 1e-9, RFE_ERR_RANGE);      /* rounds to E = 1 */
    CONV_(p.tyre.shape_Ey = 1e-12, RFE_ERR_RANGE);           /* nonzero, rounds to 0 */
    CONV_(p.vehicle.J = 1e6, RFE_ERR_RANGE);                 /* beyond Q12 */
    CONV_(p.vehicle.hg = 3.9; p.vehicle.m = 9000.0, RFE_ERR_RANGE); /* k_roll beyond Q20 */
    CONV_(p.vehicle.m = 30000.0, RFE_ERR_RANGE);             /* static load beyond Q15 */
    CONV_(p.monitor.tau_nis = 200.0, RFE_ERR_RANGE);         /* l = 5.0e-5 < 2^-14 */
    CONV_(p.monitor.tau_mean = 200.0, RFE_ERR_RANGE);        /* the same for the means */
    CONV_(p.monitor.p_fire = 1e-15, RFE_ERR_RANGE);          /* z(1 - 5e-16) = 8.03 > 8 */
    CONV_(p.monitor.p_fire = 4e-15, RFE_ERR_RANGE);          /* z_d 7.86, z_m = z(1 - p / 12) 8.08 */
    CONV_(p.monitor.p_fire = 1e-17, RFE_ERR_RANGE);          /* 1 - p / 2 rounds to 1 */
    CONV_(p.monitor.enable = 1.0; p.filter.kind = RFE_FILTER_CKF; p.filter.structure =
              RFE_STRUCT_WHEELS, RFE_ERR_PARAM);             /* the monitor needs the SCKF */
#undef CONV_
    /* the edges that fit */
    p = p0;
    p.tyre.alpha_max = 1.4999999;
    p.vehicle.hg = 0.0;
    p.filter.tau_v = 0.0;
    p.vehicle.m = 128.5;
    p.tyre.shape_Cx = 1.0 + ldexp(1.0, -24);
    p.tyre.shape_Cy = 2.0 - ldexp(1.0, -24);
    p.tyre.shape_Ex = -4.0;
    p.tyre.shape_Ey = 1.0 - ldexp(1.0, -24);
    assert_int_equal(rfe_params_to_q31_f64(&p, &q), RFE_OK);
    assert_int_equal(q.tyre.shape_Cx, (1 << 24) + 1);
    assert_int_equal(q.tyre.shape_Cy, (2 << 24) - 1);
    assert_int_equal(q.tyre.shape_Ex, -(4 << 24));
    assert_int_equal(q.tyre.shape_Ey, (1 << 24) - 1);
    assert_int_equal(q.vehicle.k_pitch, 0);
    assert_int_equal(q.filter.b_v, RFE_FIX_ONE(30));
    assert_int_equal(rfe_params_validate_q31(&q), RFE_OK);
    /* the monitor on, at its smallest weight and largest quantile that fit */
    p = p0;
    p.monitor.enable = 1.0;
    p.monitor.tau_nis = 163.0;  /* l = 0.01 / 163.01 = 6.13e-5 >= 2^-14 = 6.10e-5 */
    p.monitor.p_fire = 1.2e-14; /* z(1 - p / 12) = z(1 - 1e-15) = 7.94 */
    p.monitor.inflate = 0.0;
    assert_int_equal(rfe_params_to_q31_f64(&p, &q), RFE_OK);
    assert_int_equal(q.monitor.enable, 1u);
    assert_int_equal(q.monitor.inflate, 0u);
    assert_true(q.monitor.l_d >= (1 << 16));
    assert_true(q.monitor.z_d_fire <= RFE_FIX_MON_Z_MAX);
    assert_int_equal(rfe_params_validate_q31(&q), RFE_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params_q31_presets_equal_converted),
        cmocka_unit_test(test_params_q31_converted_sets_validate),
        cmocka_unit_test(test_params_q31_derived_consistency),
        cmocka_unit_test(test_params_q31_validate_rejects),
        cmocka_unit_test(test_params_q31_converter_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
