/**
 * @file test_meas_flt.c
 * @brief The measurement model (src/models/meas_flt.c), bit for bit and status for status:
 *  - at a perturbed input (rfe_meas_nominal, rfe_meas_eval_perturbed; the step noise's model
 *    evaluations, docs/ESTIMATOR.md step 4) against a full rfe_meas_setup + rfe_meas_eval at
 *    the perturbed sample, in every tyre mode and for every input, and their argument checks;
 *  - rfe_meas_eval with the terms cached by rfe_meas_setup, against the chain
 *    rfe_tyre_forces_abs -> rfe_obsmat_build -> rfe_obsmat_apply(H, ones), also when eval is
 *    given other tyre parameters than the set-up (the cached terms are then not used).
 * Inputs from a fixed-seed generator (test_draws.h), some beyond the limits.
 */
#include "test_light.h"
#include "test_common.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "rfe/component/meas.h"
#include "rfe/component/obsmat.h"
#include "rfe/params.h"
#include "rfe/component/tyre.h"

#include "test_draws.h"

#define N_CASES 4000         /* perturbed-input cases */
#define N_CACHED_CASES 20000 /* cached-terms cases */
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
    for (n = 0; n < N_CACHED_CASES; n += (int)rfe_test_stride(10u)) {
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
        assert_memory_equal(z1, z2, sizeof(z1));
        other.cx = (rfe_real_t)draw_uniform(0.0, 60.0);
        other.cy = (rfe_real_t)draw_uniform(0.0, 60.0);
        other.eps = (n % 2) ? (rfe_real_t)NAN : (rfe_real_t)draw_uniform(0.0, 0.05);
        assert_int_equal(rfe_meas_eval(&h, &p.vehicle, &other, mu, z1),
                         chain(&h, &p.vehicle, &other, mu, z2));
        assert_memory_equal(z1, z2, sizeof(z1));
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
        assert_memory_equal(z1, z2, sizeof(z1));
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
        assert_memory_equal(z1, z2, sizeof(z1));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_meas_perturbed),
        cmocka_unit_test(test_meas_perturbed_args),
        cmocka_unit_test(test_meas_cached),
        cmocka_unit_test(test_meas_cached_each_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
