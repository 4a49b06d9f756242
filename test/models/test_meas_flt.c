/**
 * @file test_meas_flt.c
 * @brief The measurement model at a perturbed input (rfe_meas_nominal,
 *        rfe_meas_eval_perturbed; the step noise's model evaluations, docs/ESTIMATOR.md
 *        step 4) against a full rfe_meas_setup + rfe_meas_eval at the perturbed sample, bit
 *        for bit and status for status, in every tyre mode and for every input, and their
 *        argument checks. Inputs from a fixed-seed generator (test_draws.h), some beyond the limits.
 */
#include "test_light.h"
#include "test_common.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "rfe/component/meas.h"
#include "rfe/params.h"

#include "test_draws.h"

#define N_CASES 4000
#define RFE_R(x) ((rfe_real_t)(x))

/* u with input j changed by d, as a caller would write it. */
static rfe_sample_t perturb(const rfe_sample_t *u, size_t j, rfe_real_t d)
{
    rfe_sample_t up = *u;
    switch (j) {
    case RFE_IN_DELTA: up.delta += d; break;
    case RFE_IN_VX: up.vx += d; break;
    case RFE_IN_VY: up.vy += d; break;
    case RFE_IN_YAW_RATE: up.yaw_rate += d; break;
    default: up.omega[j - RFE_IN_OMEGA] += d; break;
    }
    return up;
}

static const rfe_tyre_mode_t MODES[3] = {RFE_TYRE_PAPER, RFE_TYRE_ABSOLUTE, RFE_TYRE_MAGIC};

/* REQ: the model at u + d e_j from the set-up model at u (nominal terms of the wheels input j
 * does not reach reused) is the full set-up and evaluation at u + d e_j, bits and statuses,
 * for every input and tyre mode, including perturbations that overflow the input; the
 * nominal z is rfe_meas_eval's. */
/* REQ-MEAS-001 */
static void test_meas_perturbed(void **state)
{
    int n;
    int n_case = 0; /* cases walked, so the light mode's stride keeps every kind */
    long compared = 0;
    long failed = 0;
    (void)state;
    draw_seed(0x9E3779B97F4A7C15ull);
    for (n = 0; n < N_CASES; n += (int)rfe_test_stride(10u)) {
        ++n_case;
        rfe_params_t p;
        rfe_sample_t u;
        rfe_real_t mu[4];
        rfe_meas_t h;
        rfe_meas_terms_t nom;
        rfe_real_t z0[3];
        rfe_real_t ze[3];
        size_t j;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        p.tyre.mode = MODES[n % 3];
        draw_sample(&u, mu, 1);
        if (rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u) != RFE_OK) {
            continue;
        }
        {
            const rfe_status_t st = rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, &nom, z0);
            assert_int_equal(st, rfe_meas_eval(&h, &p.vehicle, &p.tyre, mu, ze));
            if (st != RFE_OK) {
                continue;
            }
            assert_memory_equal(z0, ze, sizeof(z0));
        }
        for (j = 0; j < (size_t)RFE_INPUTS; ++j) {
            /* a small step, a large one, and (every 16th case) an infinite one */
            const double mag = ((n_case % 2) == 0) ? 1e-2 : 0.3;
            const rfe_real_t dm = ((n_case % 16) == 5) ? (rfe_real_t)INFINITY : (rfe_real_t)mag;
            const rfe_real_t d = ((draw_u64() & 1u) != 0u) ? dm : -dm;
            const rfe_sample_t up = perturb(&u, j, d);
            rfe_meas_t hp;
            rfe_real_t zg[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
            rfe_real_t zw[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
            rfe_status_t want = rfe_meas_setup(&hp, &p.vehicle, &p.tyre, &up);
            const rfe_status_t got =
                rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, j, d, mu, zg);
            if (want == RFE_OK) {
                want = rfe_meas_eval(&hp, &p.vehicle, &p.tyre, mu, zw);
            }
            assert_int_equal(got, want);
            assert_memory_equal(zg, zw, sizeof(zg)); /* on an error both untouched */
            ++compared;
            failed += (got != RFE_OK) ? 1 : 0;
        }
    }
    print_message("meas perturbed: %ld evaluations bit-identical, %ld of them errors\n",
                  compared, failed);
    assert_true(compared > 1000);
    assert_true(failed > 0); /* the error statuses were exercised */
}

/* REQ: bad arguments are rejected with a status and nothing written; paper mode leaves the
 * nominal terms untouched. */
/* REQ-MEAS-002 */
static void test_meas_perturbed_args(void **state)
{
    rfe_params_t p;
    rfe_sample_t u;
    rfe_real_t mu[4];
    rfe_meas_t h;
    rfe_meas_terms_t nom;
    rfe_meas_terms_t nom0;
    rfe_real_t z[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
    const rfe_real_t z7[3] = {RFE_R(7.0), RFE_R(7.0), RFE_R(7.0)};
    (void)state;
    draw_seed(0x1234567ull);
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    p.tyre.mode = RFE_TYRE_ABSOLUTE;
    draw_sample(&u, mu, 1);
    u.vx = RFE_R(20.0);
    assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
    assert_int_equal(rfe_meas_nominal(NULL, &p.vehicle, &p.tyre, mu, &nom, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, NULL, &p.tyre, mu, &nom, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, NULL, mu, &nom, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, NULL, &nom, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, NULL, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, &nom, NULL), RFE_ERR_NULL);
    assert_memory_equal(z, z7, sizeof(z));
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, &nom, z), RFE_OK);
    z[0] = z[1] = z[2] = RFE_R(7.0);
    assert_int_equal(rfe_meas_eval_perturbed(NULL, &p.vehicle, &p.tyre, &nom, &u, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, NULL, &p.tyre, &nom, &u, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, NULL, &nom, &u, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, NULL, &u, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, NULL, 0u, RFE_R(0.1), mu, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, 0u, RFE_R(0.1), NULL, z), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, 0u, RFE_R(0.1), mu, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, (size_t)RFE_INPUTS, RFE_R(0.1), mu, z), RFE_ERR_PARAM);
    assert_int_equal(rfe_meas_eval_perturbed(&h, &p.vehicle, &p.tyre, &nom, &u, RFE_IN_VX, (rfe_real_t)NAN, mu, z), RFE_ERR_NONFINITE);
    assert_memory_equal(z, z7, sizeof(z));
    /* paper mode: z as rfe_meas_eval, the terms untouched */
    p.tyre.mode = RFE_TYRE_PAPER;
    assert_int_equal(rfe_meas_setup(&h, &p.vehicle, &p.tyre, &u), RFE_OK);
    memset(&nom, 0x5A, sizeof(nom));
    nom0 = nom;
    assert_int_equal(rfe_meas_nominal(&h, &p.vehicle, &p.tyre, mu, &nom, z), RFE_OK);
    assert_memory_equal(&nom, &nom0, sizeof(nom));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_meas_perturbed),
        cmocka_unit_test(test_meas_perturbed_args),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
