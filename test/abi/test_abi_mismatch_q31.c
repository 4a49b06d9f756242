/**
 * @file test_abi_mismatch_q31.c
 * @brief The ABI guard (rfe/config.h RFE_CONFIG_*): this file is compiled with other maxima
 *        (-DRFE_N_MAX=4 -DRFE_M_MAX=3, the README's firmware build) and linked against the
 *        fixed-point library built with the defaults, as an application that links a prebuilt
 *        librfe.a. Each init must refuse with RFE_ERR_ABI and write nothing: not the state,
 *        not the bytes after it (where a library with larger maxima would write). The
 *        estimator inits and the component inits whose state depends on the maxima
 *        (rfe/component/: sckf_q31, ckf_q31); the components whose state is fixed-width
 *        integers whatever the maxima (kf2_q31, conditioner_q31, monitor_q31) have no guard,
 *        and their inits work from this build, writing within their state only.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "rfe/component/ckf_q31.h"
#include "rfe/component/conditioner_q31.h"
#include "rfe/component/kf2_q31.h"
#include "rfe/component/monitor_q31.h"
#include "rfe/component/sckf_q31.h"
#include "rfe/pipeline_q31.h"

#if RFE_N_MAX != 4 || RFE_M_MAX != 3
#error "test_abi_mismatch_q31.c must be compiled with -DRFE_N_MAX=4 -DRFE_M_MAX=3"
#endif

#define PATTERN 0xA5u
#define GUARD 16384u /**< more than any state grows by between the two maxima */

/* True when all @p n bytes of @p p are PATTERN. */
static int untouched(const void *p, size_t n)
{
    const unsigned char *b = (const unsigned char *)p;
    size_t i;
    for (i = 0u; i < n; ++i) {
        if (b[i] != PATTERN) {
            return 0;
        }
    }
    return 1;
}

/* REQ-ABI-001 */
static void test_friction_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_friction_q31_t est;
        unsigned char after[GUARD];
    } box;
    rfe_params_q31_t p;
    (void)state;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    memset(&box, (int)PATTERN, sizeof box);
    assert_int_equal(rfe_friction_init_q31(&box.est, &p), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
}

/* REQ-ABI-001 */
static void test_velocity_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_velocity_q31_t obs;
        unsigned char after[GUARD];
    } box;
    rfe_params_q31_t p;
    rfe_velocity_params_q31_t vp;
    (void)state;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    assert_int_equal(rfe_velocity_params_default_q31(&vp), RFE_OK);
    memset(&box, (int)PATTERN, sizeof box);
    /* the observer's layout does not depend on the maxima: the configuration word says it */
    assert_int_equal(rfe_velocity_init_q31(&box.obs, &vp, &p), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
}

/* REQ-ABI-001 */
static void test_pipeline_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_pipeline_q31_t pl;
        unsigned char after[GUARD];
    } box;
    rfe_params_q31_t p;
    rfe_velocity_params_q31_t vp;
    (void)state;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    assert_int_equal(rfe_velocity_params_default_q31(&vp), RFE_OK);
    memset(&box, (int)PATTERN, sizeof box);
    assert_int_equal(rfe_pipeline_init_q31(&box.pl, &p, &vp), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    assert_string_equal(rfe_status_str(RFE_ERR_ABI), "caller built with other maxima or number type");
}

/* A prior for the cubature filters at n = 4, m = 3 (valid in either layout): x0 = 0.75 (Q29),
 * the factors and covariances diagonal (0.1 in Q30 or Q31, 0.5 in Q24). */
static void prior_q31(rfe_fix_t x0[4], rfe_fix_t A[16], rfe_fix_t B[16], rfe_fix_t C[9])
{
    size_t i;
    memset(A, 0, 16u * sizeof(rfe_fix_t));
    memset(B, 0, 16u * sizeof(rfe_fix_t));
    memset(C, 0, 9u * sizeof(rfe_fix_t));
    for (i = 0u; i < 4u; ++i) {
        x0[i] = (rfe_fix_t)(3 << 27);
        A[(i * 4u) + i] = (rfe_fix_t)(1 << 26);
        B[(i * 4u) + i] = (rfe_fix_t)(1 << 22);
    }
    for (i = 0u; i < 3u; ++i) {
        C[(i * 3u) + i] = (rfe_fix_t)(1 << 23);
    }
}

/* The audit's case (rfe_sckf_init, then a predict) in fixed point. */
/* REQ-ABI-001 */
static void test_sckf_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_sckf_q31_t f;
        unsigned char after[GUARD];
    } box;
    rfe_fix_t x0[4], S0[16], SQ[16], SR[9];
    (void)state;
    prior_q31(x0, S0, SQ, SR);
    memset(&box, (int)PATTERN, sizeof box);
    assert_int_equal(rfe_sckf_init_q31(&box.f, 4u, 3u, x0, S0, SQ, SR), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    assert_int_equal(rfe_sckf_predict_q31(&box.f, NULL, NULL), RFE_ERR_NOT_INITIALISED);
    assert_true(untouched(&box, sizeof box));
}

/* REQ-ABI-001 */
static void test_ckf_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_ckf_q31_t f;
        unsigned char after[GUARD];
    } box;
    rfe_fix_t x0[4], P0[16], Q[16], R[9];
    (void)state;
    prior_q31(x0, P0, Q, R);
    memset(&box, (int)PATTERN, sizeof box);
    assert_int_equal(rfe_ckf_init_q31(&box.f, 4u, 3u, x0, P0, Q, R), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    assert_int_equal(rfe_ckf_predict_q31(&box.f, NULL, NULL), RFE_ERR_NOT_INITIALISED);
    assert_true(untouched(&box, sizeof box));
}

/* The components whose state does not depend on the maxima (nor on a number type: Q31 has
 * one) have no guard: from this build their inits succeed and write within the caller's
 * state only (the same layout in both builds). */
/* REQ-ABI-001 */
static void test_fixed_layout_component_inits_work(void **state)
{
    static struct {
        rfe_kf2_q31_t f;
        unsigned char after[GUARD];
    } kf;
    static struct {
        rfe_conditioner_q31_t c;
        unsigned char after[GUARD];
    } cond;
    static struct {
        rfe_monitor_q31_t m;
        unsigned char after[GUARD];
    } mon;
    rfe_params_q31_t p;
    (void)state;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    memset(&kf, (int)PATTERN, sizeof kf);
    memset(&cond, (int)PATTERN, sizeof cond);
    memset(&mon, (int)PATTERN, sizeof mon);
    assert_int_equal(rfe_kf2_init_q31(&kf.f, 20u, 20u, 20u, 1 << 20, 0, 1 << 19, 1 << 19), RFE_OK);
    assert_true(untouched(kf.after, sizeof kf.after));
    assert_int_equal(kf.f.x[0], 1 << 20);
    assert_int_equal(rfe_conditioner_init_q31(&cond.c), RFE_OK);
    assert_true(untouched(cond.after, sizeof cond.after));
    assert_int_equal(cond.c.started, 0);
    assert_int_equal(rfe_monitor_init_q31(&mon.m, &p.monitor), RFE_OK);
    assert_true(untouched(mon.after, sizeof mon.after));
    assert_int_equal(mon.m.fired, 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_friction_init_refuses_other_maxima),
        cmocka_unit_test(test_velocity_init_refuses_other_maxima),
        cmocka_unit_test(test_pipeline_init_refuses_other_maxima),
        cmocka_unit_test(test_sckf_init_refuses_other_maxima),
        cmocka_unit_test(test_ckf_init_refuses_other_maxima),
        cmocka_unit_test(test_fixed_layout_component_inits_work),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
