/**
 * @file test_mcdc_bounds_q31.c
 * @brief MC/DC of the fixed-point estimator's sd bounds and of its "errors in variables on?"
 *        decision (docs/ESTIMATOR.md steps 4 and 7, docs/FIXED_POINT.md "Estimator"): each
 *        condition on its own (make mcdc, build/mcdc/gaps.md). The twin of
 *        test_mcdc_bounds_flt.c and of the last test of test_mcdc_args_flt.c.
 *
 * - Floor only (sd_max = 0, sd_floor_rel = 0.5, paper preset): after every unprojected update
 *   each wheel's sd ≥ sd_floor_rel · μ, and the floor binds on some step (with the cap off it
 *   must not be limited by it).
 * - Cap only (sd_max = 0.2, sd_floor_rel = 0): every sd ≤ sd_max; a step where no sd is above
 *   the cap gives bit for bit what the same state gives with both bounds off.
 * - Each input-noise key (r_model_rel, sd_in_delta, …, sd_in_omega) alone switches the step
 *   noise on: the sd after 20 steps ends above the one with every key 0 (paper tyre), or
 *   differs from it (load-scaled Magic Formula tyre, whose step noise reuses the set-up's
 *   per-wheel terms as the absolute Dugoff's; h is nonlinear in mu, so a larger S_R also
 *   moves the mean and with it the information, and the sd may end lower).
 * - A floor factor beyond the Q24 range of c (sd_floor_rel μ / sd > 128: a very precise
 *   sensor, r = 1e-4 m/s², collapses the sd in one update) saturates at 128, counted in the
 *   step's `sat`; the sd is then lifted by 128, still below its floor.
 *
 * Tolerance REL = 1e-5: c is Q24 (6e-8) and sd Q30 (9e-10 on ~0.1, 1e-8 relative); the
 * floor's f_k is exact in Q59 (FIXED_POINT.md), so a few LSB is far below 1e-5.
 */
#include "test_common.h"

#include <stdint.h>
#include <string.h>

#include "rfe/friction.h"
#include "rfe/friction_q31.h"
#include "host/fixed_conv.h"
#include "rfe/params.h"
#include "rfe/component/params_conv.h"

#define REL 1e-5

static rfe_params_t paper; /* double preset, converted per test */

static int setup(void **state)
{
    (void)state;
    return (rfe_params_paper_f64(&paper) == RFE_OK) ? 0 : -1;
}

static rfe_params_q31_t to_q(const rfe_params_t *pd)
{
    rfe_params_q31_t q;
    assert_int_equal(rfe_params_to_q31_f64(pd, &q), RFE_OK);
    return q;
}

/* Straight braking at 20 m/s, 4 % slip, 4 m/s^2 (the sample of test_mcdc_bounds_flt.c);
 * with delta != 0 also a slight turn (vy, yaw rate, ay), so every input-noise key matters. */
static rfe_sample_q31_t braking(double delta)
{
    rfe_sample_q31_t q;
    uint32_t sat = 0;
    size_t w;
    memset(&q, 0, sizeof q);
    q.delta = rfe_fix_from_double(delta, RFE_FIX_Q_ANGLE, &sat);
    q.vx = rfe_fix_from_double(20.0, RFE_FIX_Q_SPEED, &sat);
    q.ax = rfe_fix_from_double(-4.0, RFE_FIX_Q_ACC, &sat);
    if (delta != 0.0) {
        q.vy = rfe_fix_from_double(0.1, RFE_FIX_Q_SPEED, &sat);
        q.yaw_rate = rfe_fix_from_double(0.05, RFE_FIX_Q_YAWRATE, &sat);
        q.ay = rfe_fix_from_double(0.5, RFE_FIX_Q_ACC, &sat);
    }
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        q.omega[w] = rfe_fix_from_double(20.0 * 0.96 / 0.325, RFE_FIX_Q_OMEGA, &sat);
    }
    assert_int_equal(sat, 0);
    return q;
}

static double mu_d(rfe_fix_t v) { return rfe_fix_to_double(v, RFE_FIX_Q_MU); }
static double sd_d(rfe_fix_t v) { return rfe_fix_to_double(v, RFE_FIX_Q_SD); }

/* REQ-EST-009 REQ-FXP-006 */
static void test_mcdc_q31_floor_without_cap(void **state)
{
    rfe_params_t pd = paper;
    rfe_params_q31_t p;
    rfe_friction_q31_t est;
    rfe_estimate_q31_t out;
    const rfe_sample_q31_t u = braking(0.0);
    int k, binding = 0, checked = 0;
    (void)state;
    pd.filter.sd_max = 0.0;
    pd.filter.sd_floor_rel = 0.5;
    p = to_q(&pd);
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    for (k = 0; k < 200; ++k) {
        const rfe_status_t st = rfe_friction_step_q31(&est, &u, &out);
        double lo = 1e300;
        size_t w;
        assert_false(rfe_status_is_error(st));
        if (st != RFE_OK) {
            continue;
        }
        ++checked;
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            const double f = 0.5 * fmax(mu_d(out.mu[w]), 0.0);
            if (!(sd_d(out.sd[w]) >= f * (1.0 - REL))) {
                fail_msg("step %d wheel %zu: sd %.9g below its floor %.9g", k, w, sd_d(out.sd[w]), f);
            }
            if (f > 0.0) {
                lo = fmin(lo, sd_d(out.sd[w]) / f);
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

/* REQ-EST-009 REQ-FXP-006 */
static void test_mcdc_q31_cap_without_floor(void **state)
{
    rfe_params_t pd = paper;
    rfe_params_q31_t p;
    rfe_friction_q31_t est, twin;
    rfe_estimate_q31_t out, out_twin;
    const rfe_sample_q31_t u = braking(0.0);
    int k, capped = 0, free_steps = 0;
    (void)state;
    pd.filter.sd_max = 0.2;
    pd.filter.sd_floor_rel = 0.0;
    p = to_q(&pd);
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    for (k = 0; k < 200; ++k) {
        size_t w;
        double hi = 0.0;
        memcpy(&twin, &est, sizeof est);
        twin.params.filter.sd_max = 0;
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&twin, &u, &out_twin)));
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &u, &out)));
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            if (!(sd_d(out.sd[w]) <= 0.2 * (1.0 + REL))) {
                fail_msg("step %d wheel %zu: sd %.9g above the cap 0.2", k, w, sd_d(out.sd[w]));
            }
            hi = fmax(hi, sd_d(out_twin.sd[w]));
        }
        if (hi > 0.2) {
            ++capped;
        } else {
            ++free_steps;
            assert_memory_equal(out.mu, out_twin.mu, sizeof out.mu);
            assert_memory_equal(out.sd, out_twin.sd, sizeof out.sd);
        }
    }
    assert_true(capped > 0);
    assert_true(free_steps > 0);
}

/* The sd of each wheel after 20 steps. */
static void run_sd(const rfe_params_t *pd, double sd[RFE_WHEELS])
{
    const rfe_params_q31_t p = to_q(pd);
    const rfe_sample_q31_t u = braking(0.02);
    rfe_friction_q31_t est;
    rfe_estimate_q31_t out;
    size_t w;
    int k;
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    for (k = 0; k < 20; ++k) {
        assert_false(rfe_status_is_error(rfe_friction_step_q31(&est, &u, &out)));
    }
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        sd[w] = sd_d(out.sd[w]);
    }
}

/* REQ-EIV-001 REQ-FXP-006 */
static void test_mcdc_q31_each_input_noise_switches_step_noise_on(void **state)
{
    double sd_off[RFE_WHEELS], sd_on[RFE_WHEELS];
    int which;
    (void)state;
    run_sd(&paper, sd_off);
    for (which = 0; which < 12; ++which) {
        rfe_params_t pd = paper;
        int w, differs = 0;
        if (which == 6) {
            /* the same with the Magic Formula tyre */
            rfe_params_t pm = paper;
            pm.tyre.mode = RFE_TYRE_MAGIC;
            run_sd(&pm, sd_off);
        }
        if (which >= 6) {
            pd.tyre.mode = RFE_TYRE_MAGIC;
        }
        switch (which % 6) {
        case 0: pd.filter.r_model_rel = 0.05; break;
        case 1: pd.filter.sd_in_delta = 0.01; break;
        case 2: pd.filter.sd_in_vx = 0.05; break;
        case 3: pd.filter.sd_in_vy = 0.05; break;
        case 4: pd.filter.sd_in_yaw_rate = 0.02; break;
        default: pd.filter.sd_in_omega = 0.2; break;
        }
        run_sd(&pd, sd_on);
        for (w = 0; w < RFE_WHEELS; ++w) {
            /* paper tyre (h linear in mu): a larger S_R only raises the sd; magic tyre: the
             * mean, and with it the curve's information, moves too, so only "differs" */
            if ((sd_on[w] > sd_off[w]) || ((which >= 6) && (sd_on[w] != sd_off[w]))) {
                differs = 1;
            }
        }
        if (!differs) {
            fail_msg("input-noise key %d alone did not raise any sd (errors in variables off?)", which);
        }
    }
}

/* REQ-EST-009 REQ-FXP-008 */
static void test_mcdc_q31_floor_factor_saturates(void **state)
{
    rfe_params_t pd = paper;
    rfe_params_q31_t p;
    rfe_friction_q31_t est;
    rfe_estimate_q31_t out;
    const rfe_sample_q31_t u = braking(0.02);
    rfe_status_t st;
    size_t w;
    int below = 0;
    (void)state;
    pd.filter.structure = RFE_STRUCT_SIDES;
    pd.filter.sd_max = 0.0;
    pd.filter.sd_floor_rel = 1.5;
    pd.filter.r_ax = 1e-4;
    pd.filter.r_ay = 1e-4;
    pd.filter.r_yaw_acc = 1e-4;
    p = to_q(&pd);
    assert_int_equal(rfe_friction_init_q31(&est, &p), RFE_OK);
    st = rfe_friction_step_q31(&est, &u, &out);
    assert_false(rfe_status_is_error(st));
    assert_true(out.sat >= 1u);
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        below += (sd_d(out.sd[w]) < 1.5 * mu_d(out.mu[w])) ? 1 : 0;
    }
    printf("floor factor beyond Q24: %u saturation(s) in the step, %d of 4 sds left below the "
           "floor\n",
           out.sat, below);
    assert_true(below > 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mcdc_q31_floor_without_cap),
        cmocka_unit_test(test_mcdc_q31_cap_without_floor),
        cmocka_unit_test(test_mcdc_q31_each_input_noise_switches_step_noise_on),
        cmocka_unit_test(test_mcdc_q31_floor_factor_saturates),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
