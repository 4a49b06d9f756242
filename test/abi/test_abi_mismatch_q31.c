/**
 * @file test_abi_mismatch_q31.c
 * @brief The ABI guard (rfe/config.h RFE_CONFIG_*): this file is compiled with other maxima
 *        (-DRFE_N_MAX=4 -DRFE_M_MAX=3, the README's firmware build) and linked against the
 *        fixed-point library built with the defaults, as an application that links a prebuilt
 *        librfe.a. Each init must refuse with RFE_ERR_ABI and write nothing: not the state,
 *        not the bytes after it (where a library with larger maxima would write).
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_friction_init_refuses_other_maxima),
        cmocka_unit_test(test_velocity_init_refuses_other_maxima),
        cmocka_unit_test(test_pipeline_init_refuses_other_maxima),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
