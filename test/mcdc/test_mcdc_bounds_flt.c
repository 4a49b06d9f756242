/**
 * @file test_mcdc_bounds_flt.c
 * @brief MC/DC of the sd bounds (docs/ESTIMATOR.md step 7): the cap and the floor each on
 *        their own, so each condition of "cap on?", "floor on?" and "floor limited by the
 *        cap?" is shown to act alone (make mcdc, build/mcdc/gaps.md).
 *
 * - Floor only (sd_max = 0, sd_floor_rel = 0.5 on the paper preset): after every update that
 *   was not projected, each wheel's sd is at least sd_floor_rel · μ, and on some step the floor
 *   binds (min over wheels of sd / (sd_floor_rel μ) = 1). With the cap off the floor's factor
 *   must not be limited by it (a limit by sd_max = 0 would collapse S to 0).
 * - Cap only (sd_max = 0.2 below the prior's 0.3, sd_floor_rel = 0): every sd ≤ sd_max, and a
 *   step where no sd is above the cap gives bit for bit what the same step gives with both
 *   bounds off (the floor, switched off, must not act).
 *
 * Tolerance REL = 1e-5: after scaling, c·S is one rounding per element and c one division
 * (float32 ε = 1.2e-7, so a few ulp are ~1e-6 relative); the floor's f_k uses x̂ before the
 * projection, so projected steps are not checked.
 */
#include "test_common.h"

#include <string.h>

#include "rfe/friction.h"
#include "rfe/params.h"

#define REL 1e-5

static rfe_params_t paper;

static int setup(void **state)
{
    (void)state;
    return (rfe_params_paper(&paper) == RFE_OK) ? 0 : -1;
}

/* Straight braking at 20 m/s, 4 % slip, 4 m/s^2 (every wheel informative). */
static rfe_sample_t braking(void)
{
    rfe_sample_t u;
    size_t w;
    memset(&u, 0, sizeof u);
    u.vx = (rfe_real_t)20.0;
    u.ax = (rfe_real_t)-4.0;
    u.yaw_acc = (rfe_real_t)0.0;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        u.omega[w] = (rfe_real_t)(20.0 * 0.96 / 0.325);
    }
    return u;
}

/* REQ-EST-009 */
static void test_mcdc_floor_without_cap(void **state)
{
    rfe_params_t p = paper;
    rfe_friction_t est;
    rfe_estimate_t out;
    const rfe_sample_t u = braking();
    int k, binding = 0, checked = 0;
    (void)state;
    p.filter.sd_max = (rfe_real_t)0.0;
    p.filter.sd_floor_rel = (rfe_real_t)0.5;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    for (k = 0; k < 200; ++k) {
        const rfe_status_t st = rfe_friction_step(&est, &u, &out);
        double lo = 1e300;
        size_t w;
        assert_false(rfe_status_is_error(st));
        if (st != RFE_OK) {
            continue;
        }
        ++checked;
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            const double f = 0.5 * fmax((double)out.mu[w], 0.0);
            if (!((double)out.sd[w] >= f * (1.0 - REL))) {
                fail_msg("step %d wheel %zu: sd %.9g below its floor %.9g", k, w, (double)out.sd[w], f);
            }
            if (f > 0.0) {
                lo = fmin(lo, (double)out.sd[w] / f);
            }
        }
        if (lo <= 1.0 + REL) {
            ++binding;
        }
    }
    assert_true(checked > 100);
    if (binding == 0) {
        fail_msg("the floor never bound in %d updates (test does not exercise it)", checked);
    }
}

/* REQ-EST-009 */
static void test_mcdc_cap_without_floor(void **state)
{
    rfe_params_t p = paper;
    rfe_friction_t est, twin;
    rfe_estimate_t out, out_twin;
    const rfe_sample_t u = braking();
    int k, capped = 0, free_steps = 0;
    (void)state;
    p.filter.sd_max = (rfe_real_t)0.2;
    p.filter.sd_floor_rel = (rfe_real_t)0.0;
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    for (k = 0; k < 200; ++k) {
        size_t w;
        double hi = 0.0;
        /* the twin: this state with both bounds off, stepped with the same sample */
        memcpy(&twin, &est, sizeof est);
        twin.params.filter.sd_max = (rfe_real_t)0.0;
        assert_false(rfe_status_is_error(rfe_friction_step(&twin, &u, &out_twin)));
        assert_false(rfe_status_is_error(rfe_friction_step(&est, &u, &out)));
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            if (!((double)out.sd[w] <= 0.2 * (1.0 + REL))) {
                fail_msg("step %d wheel %zu: sd %.9g above the cap 0.2", k, w, (double)out.sd[w]);
            }
            hi = fmax(hi, (double)out_twin.sd[w]);
        }
        if (hi > 0.2) {
            ++capped;
        } else {
            /* no sd above the cap: nothing may scale S (the floor is off) */
            ++free_steps;
            assert_memory_equal(out.mu, out_twin.mu, sizeof out.mu);
            assert_memory_equal(out.sd, out_twin.sd, sizeof out.sd);
        }
    }
    assert_true(capped > 0);
    assert_true(free_steps > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mcdc_floor_without_cap),
        cmocka_unit_test(test_mcdc_cap_without_floor),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
