/**
 * @file test_mcdc_params_q31.c
 * @brief MC/DC of rfe_params_validate_q31's recomputation of the derived constants
 *        (docs/FIXED_POINT.md "Estimator", make mcdc): a base value whose derived constant
 *        lands just above the top of its Q format must be rejected.
 *
 * The paper preset in Q with the mass m = 100 kg (Q16, fits): 1/m = 0.01 does not fit the
 * Q38 format of the derived 1/m (range 2^-7 = 0.0078), by less than a factor 2^2, so the
 * recomputed reference is formed and found above INT32_MAX (not rejected earlier by its
 * shift). The same value through the double converter is RFE_ERR_RANGE
 * (test_params_q31_converter_errors); here the base field is set directly in Q, as firmware
 * with its own calibration tool could. No tolerances: statuses only.
 */
#include "test_common.h"

#include <stdint.h>
#include <string.h>

#include "rfe/params_q31.h"

/* REQ-PARAMS-004 REQ-FXP-010 */
static void test_mcdc_q31_validate_rejects_derived_beyond_format(void **state)
{
    rfe_params_q31_t p;
    (void)state;
    assert_int_equal(rfe_params_paper_q31(&p), RFE_OK);
    assert_int_equal(rfe_params_validate_q31(&p), RFE_OK);
    p.vehicle.m = (rfe_fix_t)(100 << 16);
    assert_int_not_equal(rfe_params_validate_q31(&p), RFE_OK);
    /* a mass whose 1/m fits (128.5 kg, the converter test's edge) with the stored 1/m left
     * as it was is rejected too: the stored constant no longer agrees */
    p.vehicle.m = (rfe_fix_t)(257 << 15);
    assert_int_not_equal(rfe_params_validate_q31(&p), RFE_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mcdc_q31_validate_rejects_derived_beyond_format),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
