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
 *
 * Also the tyre's mode and Magic Formula shape factors (1 < C < 2, -4 <= E < 1, Q24, checked
 * in every mode): each condition of the decision on its own, at the boundary (the value on
 * the bound rejected, one LSB inside accepted), in each of the three modes.
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

/* REQ-PARAMS-002 REQ-FXP-010 */
static void test_mcdc_q31_validate_tyre_mode_and_shape(void **state)
{
    static const rfe_tyre_mode_t MODES[3] = {RFE_TYRE_PAPER, RFE_TYRE_ABSOLUTE, RFE_TYRE_MAGIC};
    const rfe_fix_t one = (rfe_fix_t)1 << 24;
    rfe_params_q31_t p;
    size_t m;
    (void)state;
    for (m = 0; m < 3; ++m) {
        /* each shape factor: on its bound rejected, one LSB inside accepted */
        rfe_fix_t *const field[4] = {&p.tyre.shape_Cx, &p.tyre.shape_Ex, &p.tyre.shape_Cy,
                                     &p.tyre.shape_Ey};
        const rfe_fix_t lo_bad[4] = {one, -4 * one - 1, one, -4 * one - 1};
        const rfe_fix_t lo_ok[4] = {one + 1, -4 * one, one + 1, -4 * one};
        const rfe_fix_t hi_bad[4] = {2 * one, one, 2 * one, one};
        const rfe_fix_t hi_ok[4] = {2 * one - 1, one - 1, 2 * one - 1, one - 1};
        size_t k;
        assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
        p.tyre.mode = MODES[m];
        assert_int_equal(rfe_params_validate_q31(&p), RFE_OK);
        for (k = 0; k < 4; ++k) {
            const rfe_fix_t keep = *field[k];
            *field[k] = lo_bad[k];
            assert_int_equal(rfe_params_validate_q31(&p), RFE_ERR_PARAM);
            *field[k] = lo_ok[k];
            assert_int_equal(rfe_params_validate_q31(&p), RFE_OK);
            *field[k] = hi_bad[k];
            assert_int_equal(rfe_params_validate_q31(&p), RFE_ERR_PARAM);
            *field[k] = hi_ok[k];
            assert_int_equal(rfe_params_validate_q31(&p), RFE_OK);
            *field[k] = keep;
        }
    }
    /* a mode beyond the three */
    p.tyre.mode = (rfe_tyre_mode_t)3;
    assert_int_equal(rfe_params_validate_q31(&p), RFE_ERR_PARAM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mcdc_q31_validate_rejects_derived_beyond_format),
        cmocka_unit_test(test_mcdc_q31_validate_tyre_mode_and_shape),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
