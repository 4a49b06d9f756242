/**
 * @file test_step_noise_core_flt.c
 * @brief The internal pieces behind the cheaper float/double step (src/models/tyre_internal.h,
 *        src/estimators/friction/step_noise_internal.h) against the public functions they replace, bit for bit and
 *        status for status:
 *  - the absolute-mode Dugoff evaluation split into its friction-independent part and the
 *    rest, against rfe_tyre_dugoff_abs (finite, non-finite and out-of-range inputs);
 *  - rfe_meas_eval with the terms cached by rfe_meas_setup, against the chain
 *    rfe_tyre_forces_abs -> rfe_obsmat_build -> rfe_obsmat_apply(H, ones), also when eval is
 *    given other tyre parameters than the set-up (the cached terms are then not used);
 *  - the step noise's internal entry rfe_step_noise_sqrt_core (the estimator's, for a model
 *    already set up at the sample: nominal terms of the wheels an input does not reach
 *    reused) against the public rfe_step_noise_sqrt and against a reference built here from
 *    the public measurement model exactly as docs/ESTIMATOR.md step 4 writes it (a full
 *    set-up and evaluation at u and at u +- sd_j e_j), in absolute and paper tyre mode, with
 *    every input switched on or off, and the statuses when a perturbed input, a perturbed
 *    wheel's kinematics or the nominal model is not finite.
 * Inputs from a fixed-seed generator (test_draws.h) over and beyond the input limits.
 */
#include "test_light.h"
#include "test_common.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "rfe/component/step_noise.h"
#include "rfe/component/meas.h"
#include "rfe/component/obsmat.h"
#include "rfe/params.h"
#include "rfe/component/qr.h"
#include "rfe/component/tyre.h"

#include "estimators/friction/step_noise_internal.h"
#include "models/tyre_internal.h"
#include "test_draws.h"

#define N_CASES 20000
#define RFE_R(x) ((rfe_real_t)(x))
#if defined(RFE_REAL_DOUBLE)
#define T_SQRT sqrt
#define T_FABS fabs
#define T_HUGE 1.7e308
#define T_BIG 1e308
#define T_TINY 1e-306
#else
#define T_SQRT sqrtf
#define T_FABS fabsf
#define T_HUGE 3.35e38
#define T_BIG 1e38
#define T_TINY 1e-37
#endif

static void bits_equal(const rfe_real_t *a, const rfe_real_t *b, size_t n)
{
    assert_memory_equal(a, b, n * sizeof(rfe_real_t));
}

/* REQ: the split evaluation of a load-scaled tyre is the public function's (Dugoff:
 * rfe_tyre_dugoff_abs, magic: rfe_tyre_magic_abs), bits and statuses. */
/* REQ-TYRE-003 REQ-TYRE-007 */
static void test_dugoff_split(void **state)
{
    rfe_params_t p;
    int n;
    (void)state;
    draw_seed(0xD06FF5ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        const rfe_real_t kappa = draw_special(1.2);
        const rfe_real_t alpha = draw_special(0.6);
        const rfe_real_t fz = draw_special(9000.0);
        const rfe_real_t vwx = draw_special(60.0);
        const rfe_real_t mu = draw_special(2.0);
        rfe_real_t f1[2] = {RFE_R(7.0), RFE_R(7.0)};
        rfe_real_t f2[2] = {RFE_R(7.0), RFE_R(7.0)};
        rfe_dugoff_pre_t pre;
        rfe_tyre_params_t tp = p.tyre;
        if ((n % 3) == 1) {
            tp.cx = (rfe_real_t)draw_uniform(0.0, 60.0);
            tp.cy = (rfe_real_t)draw_uniform(0.0, 60.0);
            tp.eps = (rfe_real_t)draw_uniform(0.0, 0.05);
        }
        tp.mode = (((n / (int)rfe_test_stride(10u)) % 2) == 0) ? RFE_TYRE_MAGIC : RFE_TYRE_ABSOLUTE;
        rfe_tyre_dugoff_pre(&tp, kappa, alpha, vwx, &pre);
        assert_int_equal(rfe_tyre_dugoff_abs_pre(&tp, &pre, kappa, alpha, fz, vwx, mu,
                                                         &f2[0], &f2[1]),
                         (tp.mode == RFE_TYRE_MAGIC)
                             ? rfe_tyre_magic_abs(&tp, kappa, alpha, fz, vwx, mu, &f1[0],
                                                  &f1[1])
                             : rfe_tyre_dugoff_abs(&tp, kappa, alpha, fz, vwx, mu, &f1[0],
                                                   &f1[1]));
        bits_equal(f1, f2, 2u);
    }
    {
        rfe_dugoff_pre_t pre;
        rfe_real_t f[2];
        rfe_tyre_dugoff_pre(&p.tyre, RFE_R(0.1), RFE_R(0.0), RFE_R(20.0), &pre);
        assert_int_equal(rfe_tyre_dugoff_abs_pre(NULL, &pre, RFE_R(0.1), RFE_R(0.0),
                                                         RFE_R(1.0), RFE_R(20.0), RFE_R(1.0),
                                                         &f[0], &f[1]),
                         RFE_ERR_NULL);
    }
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
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
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
        bits_equal(z1, z2, 3u);
        other.cx = (rfe_real_t)draw_uniform(0.0, 60.0);
        other.cy = (rfe_real_t)draw_uniform(0.0, 60.0);
        other.eps = (n % 2) ? (rfe_real_t)NAN : (rfe_real_t)draw_uniform(0.0, 0.05);
        assert_int_equal(rfe_meas_eval(&h, &p.vehicle, &other, mu, z1),
                         chain(&h, &p.vehicle, &other, mu, z2));
        bits_equal(z1, z2, 3u);
    }
}

/* REQ: the estimator's step-noise entry is the public function's S_R and status for a model
 * set up at the sample, in absolute and paper tyre mode. */
/* REQ-EIV-001 */
static void test_step_noise_core(void **state)
{
    int n;
    long ok = 0;
    long failed = 0;
    (void)state;
    draw_seed(0xE1FC0BEull);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        rfe_params_t p;
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_meas_t h;
        rfe_real_t S1[9];
        rfe_real_t S2[9];
        rfe_status_t e1;
        size_t i;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        if ((n % 5) == 2) {
            p.filter.sd_in_delta = (rfe_real_t)draw_uniform(0.0, 0.02);
            p.filter.sd_in_vx = (n % 2) ? RFE_R(0.0) : (rfe_real_t)draw_uniform(0.0, 0.3);
            p.filter.sd_in_omega = (rfe_real_t)draw_uniform(0.0, 0.5);
            p.filter.sd_in_vy = ((n % 4) == 3) ? RFE_R(0.0) : p.filter.sd_in_vy;
        }
        if ((n % 7) == 3) {
            p.tyre.mode = RFE_TYRE_PAPER;
        }
        draw_sample(&u, mu, ((n % 4) != 0) ? 1 : 0);
        for (i = 0; i < 9; ++i) {
            S1[i] = S2[i] = RFE_R(7.0);
        }
        e1 = rfe_step_noise_sqrt(&p, &u, mu, S1);
        if (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK) {
            assert_true(e1 != RFE_OK);
            continue;
        }
        assert_int_equal(rfe_step_noise_sqrt_core(&p, &h, &u, mu, S2), e1);
        bits_equal(S1, S2, 9u);
        ok += (e1 == RFE_OK) ? 1 : 0;
        failed += (e1 != RFE_OK) ? 1 : 0;
    }
    printf("step noise: %ld equal results, %ld equal errors\n", ok, failed);
    assert_true(ok > 100);
    assert_true(failed > 10);
}

/* ---- reference: docs/ESTIMATOR.md step 4 with the public measurement model -------------- */

static rfe_status_t ref_h(const rfe_params_t *p, const rfe_sample_t *u, const rfe_real_t mu[4],
                          rfe_real_t z[3])
{
    rfe_meas_t h;
    rfe_status_t st = rfe_meas_setup(&h, &p->vehicle, &p->tyre, u);
    if (st == RFE_OK) {
        st = rfe_meas_eval(&h, &p->vehicle, &p->tyre, mu, z);
    }
    return st;
}

static rfe_real_t *slot(rfe_sample_t *u, size_t j)
{
    rfe_real_t *const s[8] = {&u->delta,    &u->vx,       &u->vy,       &u->yaw_rate,
                              &u->omega[0], &u->omega[1], &u->omega[2], &u->omega[3]};
    return s[j];
}

static rfe_status_t ref_step_noise(const rfe_params_t *p, const rfe_sample_t *u, const rfe_real_t mu[4],
                            rfe_real_t SR[9])
{
    const rfe_filter_params_t *fp = &p->filter;
    const rfe_real_t sd[8] = {fp->sd_in_delta,    fp->sd_in_vx,    fp->sd_in_vy,
                              fp->sd_in_yaw_rate, fp->sd_in_omega, fp->sd_in_omega,
                              fp->sd_in_omega,    fp->sd_in_omega};
    const rfe_real_t r[3] = {fp->r_ax, fp->r_ay, fp->r_yaw_acc};
    rfe_real_t A[3 * 11];
    rfe_real_t h0[3];
    size_t cols = 3u;
    size_t i;
    size_t j;
    rfe_status_t st = ref_h(p, u, mu, h0);
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0; i < 3; ++i) {
        const rfe_real_t e = fp->r_model_rel * T_FABS(h0[i]);
        for (j = 0; j < 3; ++j) {
            A[i * 11u + j] = (i == j) ? T_SQRT((r[i] * r[i]) + (e * e)) : RFE_R(0.0);
        }
    }
    for (j = 0; j < 8; ++j) {
        rfe_sample_t up = *u;
        rfe_sample_t um = *u;
        rfe_real_t zp[3];
        rfe_real_t zm[3];
        if (!(sd[j] > RFE_R(0.0))) {
            continue;
        }
        *slot(&up, j) += sd[j];
        *slot(&um, j) -= sd[j];
        st = ref_h(p, &up, mu, zp);
        if (st == RFE_OK) {
            st = ref_h(p, &um, mu, zm);
        }
        if (st != RFE_OK) {
            return st;
        }
        for (i = 0; i < 3; ++i) {
            A[i * 11u + cols] = (zp[i] - zm[i]) / RFE_R(2.0);
        }
        ++cols;
    }
    st = rfe_qr_tria(A, 3u, cols, 11u);
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            SR[i * 3u + j] = (j <= i) ? A[i * 11u + j] : RFE_R(0.0);
        }
    }
    return RFE_OK;
}

/* The public function, the internal entry (after a set-up) and the reference agree. */
static rfe_status_t check_three(const rfe_params_t *p, const rfe_sample_t *u,
                                const rfe_real_t mu[4])
{
    rfe_real_t S1[9];
    rfe_real_t S2[9];
    rfe_real_t S3[9];
    rfe_meas_t h;
    rfe_status_t e1;
    size_t i;
    for (i = 0; i < 9; ++i) {
        S1[i] = S2[i] = S3[i] = RFE_R(7.0);
    }
    e1 = rfe_step_noise_sqrt(p, u, mu, S1);
    assert_int_equal(ref_step_noise(p, u, mu, S2), e1);
    bits_equal(S1, S2, 9u);
    if (rfe_meas_setup(&h, &p->vehicle, &p->tyre, u) == RFE_OK) {
        assert_int_equal(rfe_step_noise_sqrt_core(p, &h, u, mu, S3), e1);
        bits_equal(S1, S3, 9u);
    }
    return e1;
}

/* REQ: the step noise with the nominal terms reused is the reference's S_R, bit for bit,
 * and its status, on random samples (absolute and paper tyre, inputs on and off). */
/* REQ-EIV-001 */
static void test_step_noise_reference(void **state)
{
    int n;
    long ok = 0;
    (void)state;
    draw_seed(0xA5A5F00Dull);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        rfe_params_t p;
        rfe_sample_t u;
        rfe_real_t mu[4];
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        if ((n % 5) == 2) {
            p.filter.sd_in_delta = (rfe_real_t)draw_uniform(0.0, 0.02);
            p.filter.sd_in_vx = (n % 2) ? RFE_R(0.0) : (rfe_real_t)draw_uniform(0.0, 0.3);
            p.filter.sd_in_omega = (rfe_real_t)draw_uniform(0.0, 0.5);
            p.filter.sd_in_yaw_rate = ((n % 4) == 3) ? RFE_R(0.0) : p.filter.sd_in_yaw_rate;
        }
        if ((n % 7) == 3) {
            p.tyre.mode = RFE_TYRE_PAPER;
        }
        draw_sample(&u, mu, ((n % 4) != 0) ? 1 : 0);
        ok += (check_three(&p, &u, mu) == RFE_OK) ? 1 : 0;
    }
    printf("step noise vs reference: %ld of %d cases RFE_OK\n", ok, N_CASES);
    assert_true(ok > 100);
}

/* REQ: the statuses where a perturbed input overflows, a perturbed wheel's kinematics
 * overflow, or the nominal model is not finite; the internal entry's status for a NaN mu. */
/* REQ-EIV-002 */
static void test_step_noise_overflow(void **state)
{
    rfe_params_t p;
    rfe_sample_t u;
    rfe_real_t mu[4];
    rfe_meas_t h;
    rfe_real_t S[9];
    size_t i;
    (void)state;
    draw_seed(0x0FF0ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    draw_sample(&u, mu, 1);
    u.delta = RFE_R(0.0);
    u.vy = RFE_R(0.0);
    u.yaw_rate = RFE_R(0.0);
    u.vx = (rfe_real_t)T_HUGE;
    for (i = 0; i < 4; ++i) {
        u.omega[i] = RFE_R(0.0);
    }
    /* vx + sd_vx overflows: the set-up's check of the perturbed sample */
    p.filter.sd_in_vx = (rfe_real_t)T_BIG;
    assert_int_equal(check_three(&p, &u, mu), RFE_ERR_NONFINITE);
    /* r + sd_r finite, but the right wheels' vx - r y overflows: the tyre's check */
    p.filter.sd_in_vx = RFE_R(0.0);
    p.filter.sd_in_yaw_rate = (rfe_real_t)T_BIG;
    assert_int_equal(check_three(&p, &u, mu), RFE_ERR_NONFINITE);
    /* the nominal model already overflows: the nominal forces' check */
    u.vy = (rfe_real_t)T_HUGE;
    u.delta = RFE_R(0.7);
    assert_int_equal(check_three(&p, &u, mu), RFE_ERR_NONFINITE);
    /* the same two in paper tyre mode (full evaluations) */
    p.tyre.mode = RFE_TYRE_PAPER;
    u.vy = RFE_R(0.0);
    u.delta = RFE_R(0.0);
    assert_int_equal(check_three(&p, &u, mu), RFE_ERR_NONFINITE);
    p.filter.sd_in_yaw_rate = RFE_R(0.0);
    p.filter.sd_in_vx = (rfe_real_t)T_BIG;
    assert_int_equal(check_three(&p, &u, mu), RFE_ERR_NONFINITE);
    /* finite forces whose yaw acceleration overflows (a tiny inertia): the sums' check */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    draw_sample(&u, mu, 1);
    p.vehicle.J = (rfe_real_t)T_TINY;
    assert_int_equal(check_three(&p, &u, mu), RFE_ERR_NONFINITE);
    /* the internal entry with a NaN mu: the evaluation's check (absolute and paper mode) */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    draw_sample(&u, mu, 1);
    mu[2] = (rfe_real_t)NAN;
    for (i = 0; i < 2; ++i) {
        if (i == 1u) {
            p.tyre.mode = RFE_TYRE_PAPER;
        }
        assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
        assert_int_equal(rfe_step_noise_sqrt_core(&p, &h, &u, mu, S), RFE_ERR_NONFINITE);
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
        bits_equal(z1, z2, 3u);
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
        bits_equal(z1, z2, 3u);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dugoff_split),
        cmocka_unit_test(test_meas_cached),
        cmocka_unit_test(test_meas_cached_each_field),
        cmocka_unit_test(test_step_noise_core),
        cmocka_unit_test(test_step_noise_reference),
        cmocka_unit_test(test_step_noise_overflow),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
