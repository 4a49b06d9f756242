/**
 * @file test_mcdc_host.c
 * @brief Host code paths the CLI and replay tests do not reach (make coverage,
 *        docs/COVERAGE_JUSTIFICATION.md): the NULL checks of rfe_replay_params.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>

#include "param_file.h"
#include "replay_real.h"
#include "rfe/params.h"

/* REQ-CLI-004 */
static void test_mcdc_replay_params_null_arguments(void **state)
{
    rfe_param_set_t ps;
    rfe_params_t p, before;
    size_t bad = 12345u;
    (void)state;
    assert_int_equal(rfe_param_set_preset(&ps, RFE_PRESET_PAPER), 0);
    memset(&p, 0x5a, sizeof p);
    before = p;
    assert_int_equal(rfe_replay_params(NULL, &p, &bad), RFE_ERR_NULL);
    assert_int_equal(rfe_replay_params(&ps, NULL, &bad), RFE_ERR_NULL);
    assert_memory_equal(&p, &before, sizeof p);
    assert_int_equal(bad, 12345u); /* untouched on an error */
    assert_int_equal(rfe_replay_params(&ps, &p, &bad), RFE_OK);
    assert_int_equal(bad, (size_t)RFE_PK_NONE);
    assert_int_equal(rfe_params_validate(&p), RFE_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mcdc_replay_params_null_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
