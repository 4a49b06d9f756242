/**
 * @file test_abi_mismatch_flt.c
 * @brief The ABI guard (rfe/config.h RFE_CONFIG_*): this file is compiled with other maxima
 *        (-DRFE_N_MAX=4 -DRFE_M_MAX=3, the README's firmware build) and linked against the
 *        float library built with the defaults, as an application that links a prebuilt
 *        librfe.a. Each init must refuse with RFE_ERR_ABI and write nothing: not the state,
 *        not the bytes after it (where a library with larger maxima would write). The
 *        estimator inits and the component inits whose state depends on the maxima or the
 *        number type (rfe/component/: sckf, ckf, kf2, conditioner, monitor).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "rfe/component/ckf.h"
#include "rfe/component/conditioner.h"
#include "rfe/component/kf2.h"
#include "rfe/component/monitor.h"
#include "rfe/component/sckf.h"
#include "rfe/pipeline.h"

#if RFE_N_MAX != 4 || RFE_M_MAX != 3
#error "test_abi_mismatch_flt.c must be compiled with -DRFE_N_MAX=4 -DRFE_M_MAX=3"
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
        rfe_friction_t est;
        unsigned char after[GUARD];
    } box;
    rfe_params_t p;
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&box, (int)PATTERN, sizeof box);
    assert_int_equal(rfe_friction_init(&box.est, &p), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    /* by its full name too (firmware/example/main.c calls it so) */
    assert_int_equal(rfe_friction_init_f32(&box.est, &p), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
}

/* REQ-ABI-001 */
static void test_velocity_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_velocity_t obs;
        unsigned char after[GUARD];
    } box;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    memset(&box, (int)PATTERN, sizeof box);
    /* the observer's layout does not depend on the maxima: the configuration word says it */
    assert_int_equal(rfe_velocity_init(&box.obs, &vp, &p), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
}

/* REQ-ABI-001 */
static void test_pipeline_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_pipeline_t pl;
        unsigned char after[GUARD];
    } box;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    memset(&box, (int)PATTERN, sizeof box);
    assert_int_equal(rfe_pipeline_init(&box.pl, &p, &vp), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    assert_string_equal(rfe_status_str(RFE_ERR_ABI), "caller built with other maxima or number type");
}

/* A prior for the cubature filters at n = 4, m = 3 (valid in either layout): x0 = 0.8, the
 * factors and covariances diagonal. */
static void prior(rfe_real_t x0[4], rfe_real_t A[16], rfe_real_t B[16], rfe_real_t C[9])
{
    size_t i;
    memset(A, 0, 16u * sizeof(rfe_real_t));
    memset(B, 0, 16u * sizeof(rfe_real_t));
    memset(C, 0, 9u * sizeof(rfe_real_t));
    for (i = 0u; i < 4u; ++i) {
        x0[i] = (rfe_real_t)0.8;
        A[(i * 4u) + i] = (rfe_real_t)0.1;
        B[(i * 4u) + i] = (rfe_real_t)0.01;
    }
    for (i = 0u; i < 3u; ++i) {
        C[(i * 3u) + i] = (rfe_real_t)0.5;
    }
}

/* The audit's case: rfe_sckf_init, then a predict, from a caller with other maxima. The init
 * refuses; the predict finds no initialised filter; nothing is written either time. */
/* REQ-ABI-001 */
static void test_sckf_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_sckf_t f;
        unsigned char after[GUARD];
    } box;
    rfe_real_t x0[4], S0[16], SQ[16], SR[9];
    (void)state;
    prior(x0, S0, SQ, SR);
    memset(&box, (int)PATTERN, sizeof box);
    assert_int_equal(rfe_sckf_init(&box.f, 4u, 3u, x0, S0, SQ, SR), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    assert_int_equal(rfe_sckf_init_f32(&box.f, 4u, 3u, x0, S0, SQ, SR), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    assert_int_equal(rfe_sckf_predict(&box.f, NULL, NULL), RFE_ERR_NOT_INITIALISED);
    assert_true(untouched(&box, sizeof box));
}

/* REQ-ABI-001 */
static void test_ckf_init_refuses_other_maxima(void **state)
{
    static struct {
        rfe_ckf_t f;
        unsigned char after[GUARD];
    } box;
    rfe_real_t x0[4], P0[16], Q[16], R[9];
    (void)state;
    prior(x0, P0, Q, R);
    memset(&box, (int)PATTERN, sizeof box);
    assert_int_equal(rfe_ckf_init(&box.f, 4u, 3u, x0, P0, Q, R), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    assert_int_equal(rfe_ckf_init_f32(&box.f, 4u, 3u, x0, P0, Q, R), RFE_ERR_ABI);
    assert_true(untouched(&box, sizeof box));
    assert_int_equal(rfe_ckf_predict(&box.f, NULL, NULL), RFE_ERR_NOT_INITIALISED);
    assert_true(untouched(&box, sizeof box));
}

/* The small components' layouts depend on the number type, not on the maxima: the
 * configuration word, which carries both, says the caller was built otherwise. */
/* REQ-ABI-001 */
static void test_small_component_inits_refuse_other_configuration(void **state)
{
    static struct {
        rfe_kf2_t f;
        unsigned char after[GUARD];
    } kf;
    static struct {
        rfe_conditioner_t c;
        unsigned char after[GUARD];
    } cond;
    static struct {
        rfe_monitor_t m;
        unsigned char after[GUARD];
    } mon;
    rfe_params_t p;
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&kf, (int)PATTERN, sizeof kf);
    memset(&cond, (int)PATTERN, sizeof cond);
    memset(&mon, (int)PATTERN, sizeof mon);
    assert_int_equal(rfe_kf2_init(&kf.f, 1.0f, 2.0f, 0.5f, 3.0f), RFE_ERR_ABI);
    assert_int_equal(rfe_kf2_init_f32(&kf.f, 1.0f, 2.0f, 0.5f, 3.0f), RFE_ERR_ABI);
    assert_true(untouched(&kf, sizeof kf));
    assert_int_equal(rfe_conditioner_init(&cond.c), RFE_ERR_ABI);
    assert_int_equal(rfe_conditioner_init_f32(&cond.c), RFE_ERR_ABI);
    assert_true(untouched(&cond, sizeof cond));
    assert_int_equal(rfe_monitor_init(&mon.m, &p.monitor, p.filter.dt), RFE_ERR_ABI);
    assert_int_equal(rfe_monitor_init_f32(&mon.m, &p.monitor, p.filter.dt), RFE_ERR_ABI);
    assert_true(untouched(&mon, sizeof mon));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_friction_init_refuses_other_maxima),
        cmocka_unit_test(test_velocity_init_refuses_other_maxima),
        cmocka_unit_test(test_pipeline_init_refuses_other_maxima),
        cmocka_unit_test(test_sckf_init_refuses_other_maxima),
        cmocka_unit_test(test_ckf_init_refuses_other_maxima),
        cmocka_unit_test(test_small_component_inits_refuse_other_configuration),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
