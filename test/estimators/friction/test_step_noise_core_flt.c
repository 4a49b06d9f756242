/**
 * @file test_step_noise_core_flt.c
 * @brief The step noise's internal entry rfe_step_noise_sqrt_core
 *        (src/estimators/friction/step_noise_internal.h; the estimator's, for a model already
 *        set up at the sample: nominal terms of the wheels an input does not reach reused)
 *        against the public rfe_step_noise_sqrt and against a reference built here from the
 *        public measurement model exactly as docs/ESTIMATOR.md step 4 writes it (a full set-up,
 *        h at u, the public input derivative rfe_meas_input_jac), bit for bit and status for status, in
 *        absolute and paper tyre mode, with every input switched on or off, and the statuses
 *        when a perturbed input, a perturbed wheel's kinematics or the nominal model is not
 *        finite. The pieces it is built on are tested with their modules:
 *        test/models/test_tyre_internal_flt.c (the tyre's split), test/models/test_meas_flt.c
 *        (the cached measurement terms).
 * Inputs from a fixed-seed generator (test_draws.h) over and beyond the input limits.
 */
#include "test_light.h"
#include "test_common.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "rfe/component/step_noise.h"
#include "rfe/component/meas.h"
#include "rfe/params.h"
#include "rfe/component/qr.h"

#include "estimators/friction/step_noise_internal.h"
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
        assert_int_equal(rfe_step_noise_sqrt_core(&p, &h, &u, mu, S2, NULL), e1);
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
    /* g_j = sd_j dh/du_j (docs/ESTIMATOR.md step 4) from the public derivative on a set-up
     * of its own (rfe_meas_input_jac is tested against central differences in
     * test_meas_flt.c) */
    {
        rfe_meas_t hs;
        rfe_real_t G[3 * 8];
        st = rfe_meas_setup(&hs, &p->vehicle, &p->tyre, u);
        if (st == RFE_OK) {
            st = rfe_meas_input_jac(&hs, &p->vehicle, &p->tyre, u, mu, sd, G);
        }
        if (st != RFE_OK) {
            return st;
        }
        for (j = 0; j < 8; ++j) {
            if (!(sd[j] > RFE_R(0.0))) {
                continue;
            }
            for (i = 0; i < 3; ++i) {
                A[i * 11u + cols] = G[i * 8u + j];
            }
            ++cols;
        }
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
        assert_int_equal(rfe_step_noise_sqrt_core(p, &h, u, mu, S3, NULL), e1);
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
    /* Since issue 21 no perturbed sample is formed (g_j = sd_j dh/du_j, analytic): a huge vx
     * with the wheels at rest holds every kappa at its clamp (-1, derivative 0) and, with
     * vy = r = delta = 0, every tan(alpha) at 0 with derivatives vy / vx^2 = 0 and x_i / vx,
     * y_i / vx of ~1e-308 (double; ~1e-38 float32): a huge sd_vx or sd_r times them is finite,
     * so the step noise is RFE_OK where the central differences' u + sd e_j overflowed. */
    p.filter.sd_in_vx = (rfe_real_t)T_BIG;
    assert_int_equal(check_three(&p, &u, mu), RFE_OK);
    p.filter.sd_in_vx = RFE_R(0.0);
    p.filter.sd_in_yaw_rate = (rfe_real_t)T_BIG;
    assert_int_equal(check_three(&p, &u, mu), RFE_OK);
    /* the nominal model already overflows: the nominal forces' check */
    u.vy = (rfe_real_t)T_HUGE;
    u.delta = RFE_R(0.7);
    assert_int_equal(check_three(&p, &u, mu), RFE_ERR_NONFINITE);
    /* the same two in paper tyre mode */
    p.tyre.mode = RFE_TYRE_PAPER;
    u.vy = RFE_R(0.0);
    u.delta = RFE_R(0.0);
    assert_int_equal(check_three(&p, &u, mu), RFE_OK);
    p.filter.sd_in_yaw_rate = RFE_R(0.0);
    p.filter.sd_in_vx = (rfe_real_t)T_BIG;
    assert_int_equal(check_three(&p, &u, mu), RFE_OK);
    /* a huge sd times a derivative of magnitude >= 1: the derivative's finiteness check
     * (rfe_meas_input_jac); the steer angle's derivative of the lateral acceleration on a
     * drawn sample is of the order of the tyres' cornering stiffness over the mass, >> 1 */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    draw_sample(&u, mu, 1);
    p.filter.sd_in_delta = (rfe_real_t)T_HUGE;
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
        assert_int_equal(rfe_step_noise_sqrt_core(&p, &h, &u, mu, S, NULL), RFE_ERR_NONFINITE);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_step_noise_core),
        cmocka_unit_test(test_step_noise_reference),
        cmocka_unit_test(test_step_noise_overflow),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
