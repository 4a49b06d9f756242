/**
 * @file test_velocity_logic.c
 * @brief The observer's decisions that both twins share (src/estimators/velocity/
 *        velocity_logic.h), over every combination of their inputs: which wheel reference the
 *        longitudinal filter takes (§3.5), when it re-acquires the wheels, when vx's variance
 *        grows while braking. The observer tests reach only the combinations a car produces;
 *        here each rule is held to its statement in docs/OBSERVER.md §3.5, written out below
 *        as the expected value, so every condition is shown to act on its own (MC/DC).
 * No tolerances: the results are enums and flags.
 */
#include "test_common.h"

#include "estimators/velocity/velocity_logic.h"

/* Every driving state a step can have, and the two the observer never produces (braking and
 * driving together), which the rules must still answer as written. */
static rfe_vel_drive_state_t state(int decelerating, int braking, int driving)
{
    rfe_vel_drive_state_t s;
    s.decelerating = decelerating;
    s.braking = braking;
    s.driving = driving;
    s.driven = RFE_DRIVEN_FL | RFE_DRIVEN_FR;
    return s;
}

/* REQ: §3.5 the reference: the free wheels' mean when there is one; else, braking, the
 * fastest plausible wheel when it is above the prediction; else, driving and not braking,
 * the slowest when it is below; else none. */
/* REQ-OBS-004 */
static void test_reference_every_combination(void **state_)
{
    size_t n_free;
    size_t n_ok;
    int dec;
    int brk;
    int drv;
    int hi;
    int lo;
    (void)state_;
    for (n_free = 0u; n_free <= 1u; ++n_free) {
        for (n_ok = 0u; n_ok <= 1u; ++n_ok) {
            for (brk = 0; brk <= 1; ++brk) {
                for (drv = 0; drv <= 1; ++drv) {
                    for (hi = 0; hi <= 1; ++hi) {
                        for (lo = 0; lo <= 1; ++lo) {
                            for (dec = 0; dec <= 1; ++dec) {
                                const rfe_vel_drive_state_t s = state(dec, brk, drv);
                                rfe_vel_ref_t want = RFE_VEL_REF_NONE;
                                if (n_free > 0u) {
                                    want = RFE_VEL_REF_FREE_MEAN;
                                } else if ((n_ok > 0u) && brk && hi) {
                                    want = RFE_VEL_REF_BRAKED_HI;
                                } else if ((n_ok > 0u) && !brk && drv && lo) {
                                    want = RFE_VEL_REF_DRIVEN_LO;
                                }
                                assert_int_equal(rfe_vel_reference(n_free, n_ok, &s, hi, lo),
                                                 want);
                            }
                        }
                    }
                }
            }
        }
    }
}

/* REQ: §3.5 re-acquisition: only when the gated wheels gave no reference and the car does
 * not drive; then when it rolls (not braking) with the wheels in agreement, or stands
 * without decelerating (the brake may be held). Braked wheels in agreement are not taken:
 * they turn slower than the car moves. */
/* REQ-OBS-010 */
static void test_reacquire_every_combination(void **state_)
{
    int r;
    int agree;
    int standing;
    int dec;
    int brk;
    int drv;
    (void)state_;
    for (r = (int)RFE_VEL_REF_NONE; r <= (int)RFE_VEL_REF_DRIVEN_LO; ++r) {
        for (agree = 0; agree <= 1; ++agree) {
            for (standing = 0; standing <= 1; ++standing) {
                for (dec = 0; dec <= 1; ++dec) {
                    for (brk = 0; brk <= 1; ++brk) {
                        for (drv = 0; drv <= 1; ++drv) {
                            const rfe_vel_drive_state_t s = state(dec, brk, drv);
                            const rfe_vel_ref_t ref = (rfe_vel_ref_t)r;
                            const int rolling_in_agreement = !brk && agree;
                            const int parked = standing && !dec;
                            const rfe_vel_ref_t want =
                                ((ref == RFE_VEL_REF_NONE) && !drv &&
                                 (rolling_in_agreement || parked))
                                    ? RFE_VEL_REF_REACQUIRE
                                    : ref;
                            assert_int_equal(rfe_vel_reacquire(ref, agree, standing, &s), want);
                        }
                    }
                }
            }
        }
    }
    {
        /* the named cases: braked wheels in agreement, moving: not taken; parked with the
         * brake held: taken; driving: never */
        const rfe_vel_drive_state_t braked = state(1, 1, 0);
        const rfe_vel_drive_state_t held = state(0, 1, 0);
        const rfe_vel_drive_state_t driven = state(0, 0, 1);
        assert_int_equal(rfe_vel_reacquire(RFE_VEL_REF_NONE, 1, 0, &braked), RFE_VEL_REF_NONE);
        assert_int_equal(rfe_vel_reacquire(RFE_VEL_REF_NONE, 1, 1, &held),
                         RFE_VEL_REF_REACQUIRE);
        assert_int_equal(rfe_vel_reacquire(RFE_VEL_REF_NONE, 1, 1, &driven), RFE_VEL_REF_NONE);
    }
}

/* REQ: §3.5 vx's variance grows (q_vx_brake) exactly on a braking step without a wheel
 * reference. */
/* REQ-OBS-010 */
static void test_brake_drift_every_combination(void **state_)
{
    int r;
    int dec;
    int brk;
    int drv;
    (void)state_;
    for (r = (int)RFE_VEL_REF_NONE; r <= (int)RFE_VEL_REF_REACQUIRE; ++r) {
        for (dec = 0; dec <= 1; ++dec) {
            for (brk = 0; brk <= 1; ++brk) {
                for (drv = 0; drv <= 1; ++drv) {
                    const rfe_vel_drive_state_t s = state(dec, brk, drv);
                    const int want = (((rfe_vel_ref_t)r == RFE_VEL_REF_NONE) && brk) ? 1 : 0;
                    assert_int_equal(rfe_vel_brake_drift((rfe_vel_ref_t)r, &s), want);
                }
            }
        }
    }
}

/* REQ-OBS-011 REQ-OBS-012 */
static void test_linear_range_every_combination(void **state)
{
    /* §4.2b: taken only when on and the yaw rate linear, and ay moderate or, in a steady
     * turn (the yaw rate on r_ref for lin_dwell), below the higher cap (the truth table) */
    int on, yaw, ay, ays, dw;
    (void)state;
    for (on = 0; on <= 1; ++on) {
        for (yaw = 0; yaw <= 1; ++yaw) {
            for (ay = 0; ay <= 1; ++ay) {
                for (ays = 0; ays <= 1; ++ays) {
                    for (dw = 0; dw <= 1; ++dw) {
                        assert_int_equal(rfe_vel_linear_range(on, yaw, ay, ays, dw),
                                         (on && yaw && (ay || (ays && dw))) ? 1 : 0);
                    }
                }
            }
        }
    }
}

/* REQ-OBS-012 */
static void test_time_on_reference_every_combination(void **state)
{
    /* §4.2b: off r_ref the time restarts; on it, it grows until it has reached lin_dwell,
     * then it is kept */
    (void)state;
    assert_int_equal(rfe_vel_on_ref(0, 0), RFE_VEL_ON_REF_RESET);
    assert_int_equal(rfe_vel_on_ref(0, 1), RFE_VEL_ON_REF_RESET);
    assert_int_equal(rfe_vel_on_ref(1, 0), RFE_VEL_ON_REF_ADD);
    assert_int_equal(rfe_vel_on_ref(1, 1), RFE_VEL_ON_REF_HOLD);
}

/* REQ-OBS-012 */
static void test_steady_turn_floor_every_combination(void **state)
{
    /* §4.2: the friction floor only where the linear range is taken and the yaw rate has
     * stayed on r_ref for lin_dwell */
    (void)state;
    assert_int_equal(rfe_vel_lin_floor(0, 0), 0);
    assert_int_equal(rfe_vel_lin_floor(0, 1), 0);
    assert_int_equal(rfe_vel_lin_floor(1, 0), 0);
    assert_int_equal(rfe_vel_lin_floor(1, 1), 1);
}

/* REQ: §4.2 the model's rate: due on phase 1 only; the next phase is 1 after a first sample
 * or once the phase has reached lat_every, else one more (each condition alone decides). */
static void test_model_rate_every_combination(void **state)
{
    uint32_t every;
    uint32_t started;
    (void)state;
    assert_int_equal(rfe_vel_model_due(0u), 0);
    assert_int_equal(rfe_vel_model_due(1u), 1);
    assert_int_equal(rfe_vel_model_due(2u), 0);
    for (every = 1u; every <= RFE_VEL_LAT_EVERY_MAX; ++every) {
        for (started = 0u; started <= every; ++started) {
            const uint32_t next = (started >= every) ? 1u : (started + 1u);
            assert_int_equal(rfe_vel_next_phase(RFE_VEL_PLAN_START, started, every), 1u);
            assert_int_equal(rfe_vel_next_phase(RFE_VEL_PLAN_FILTERS, started, every), next);
        }
    }
    /* a full cycle of lat_every 3 from the first sample: 1, 2, 3, 1, ... */
    assert_int_equal(rfe_vel_next_phase(RFE_VEL_PLAN_FILTERS, 3u, 3u), 1u);
    assert_int_equal(rfe_vel_next_phase(RFE_VEL_PLAN_FILTERS, 2u, 3u), 3u);
}

/* §5 the reported sd(vy)'s floor: only on a later sample, when on and at vx >= v_lat_min */
static void test_output_floor_every_combination(void **state)
{
    int on;
    int lateral;
    (void)state;
    for (on = 0; on <= 1; ++on) {
        for (lateral = 0; lateral <= 1; ++lateral) {
            assert_int_equal(rfe_vel_out_floor_due(RFE_VEL_PLAN_START, on, lateral), 0);
            assert_int_equal(rfe_vel_out_floor_due(RFE_VEL_PLAN_FILTERS, on, lateral),
                             ((on != 0) && (lateral != 0)) ? 1 : 0);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_reference_every_combination),
        cmocka_unit_test(test_reacquire_every_combination),
        cmocka_unit_test(test_brake_drift_every_combination),
        cmocka_unit_test(test_linear_range_every_combination),
        cmocka_unit_test(test_time_on_reference_every_combination),
        cmocka_unit_test(test_steady_turn_floor_every_combination),
        cmocka_unit_test(test_model_rate_every_combination),
        cmocka_unit_test(test_output_floor_every_combination),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
