/**
 * @file mass_grade_logic.h
 * @brief Private, shared by both number types (mass_grade_flt.c and mass_grade_q31.c; no
 *        real type in it): the mass and grade estimator's decisions that are not
 *        arithmetic (docs/MASS_GRADE.md §4.1, §4.2). Each twin makes the comparisons on its
 *        own numbers and hands their outcomes (0 or 1) here. Not installed.
 */
#ifndef RFE_MASS_GRADE_LOGIC_H
#define RFE_MASS_GRADE_LOGIC_H

#include <stdint.h>

#include "rfe/common.h"
#include "rfe/mass_grade_bits.h"

/** What a step that passed the checks does (§4.1). */
typedef enum {
    RFE_MG_PLAN_START = 0, /**< the first sample, or a period beyond dt_max: (re)start */
    RFE_MG_PLAN_STEP = 1   /**< the pause logic, then a hold or the filter's update */
} rfe_mg_plan_t;

/** §4.1 the plan from `started` and whether the period exceeds dt_max. */
static inline rfe_mg_plan_t rfe_mg_plan(uint32_t started, int dt_beyond_max)
{
    return ((started == 0u) || (dt_beyond_max != 0)) ? RFE_MG_PLAN_START : RFE_MG_PLAN_STEP;
}

/** §4.1 the sample's `has` bits and the accelerometer the row needs: RFE_OK, or
 *  RFE_ERR_RANGE for an unknown bit or a missing ax while use_ax (the value checks are each
 *  twin's). */
static inline rfe_status_t rfe_mg_has_status(uint32_t has, uint32_t use_ax)
{
    rfe_status_t st = RFE_OK;
    /* an unknown bit; no ax while the accelerometer option needs it in every sample */
    if (((has & ~RFE_MG_HAS_ALL) != 0u) || (((has & RFE_MG_HAS_AX) == 0u) && (use_ax == 1u))) {
        st = RFE_ERR_RANGE;
    }
    return st;
}

/** §4.2 step 1: braking = the pedal flag given and pressed, or the pressure given and above
 *  p_brake_on (@p pressure_above: that comparison's outcome). */
static inline int rfe_mg_braking(uint32_t has, uint32_t brake, int pressure_above)
{
    return ((((has & RFE_MG_HAS_BRAKE) != 0u) && (brake != 0u)) ||
            (((has & RFE_MG_HAS_PRESSURE) != 0u) && (pressure_above != 0)))
               ? 1
               : 0;
}

/** §4.2 step 2: a gear given that differs from the last given one starts the shift delay. */
static inline int rfe_mg_gear_changed(uint32_t has, uint32_t has_gear, int32_t gear,
                                      int32_t last_gear)
{
    return (((has & RFE_MG_HAS_GEAR) != 0u) && (has_gear != 0u) && (gear != last_gear)) ? 1 : 0;
}

/** §4.2 step 3: slipping = the ground speed vx given, the slip pause on (slip_max > 0) and
 *  |v - vx| > slip_max max(|vx|, v_min) (@p beyond: that comparison's outcome). */
static inline int rfe_mg_slipping(uint32_t has, int slip_on, int beyond)
{
    return (((has & RFE_MG_HAS_VX) != 0u) && (slip_on != 0) && (beyond != 0)) ? 1 : 0;
}

/** §4.2 step 4: cornering = ay given, the curve pause on (ay_max > 0) and |ay| > ay_max
 *  (@p beyond: that comparison's outcome). */
static inline int rfe_mg_cornering(uint32_t has, int curve_on, int beyond)
{
    return (((has & RFE_MG_HAS_AY) != 0u) && (curve_on != 0) && (beyond != 0)) ? 1 : 0;
}

/** §4.2 step 5: the status from braking, the delays left beyond half a period, the slip, the
 *  curve (cornering now or its delay left beyond half a period) and the low speed, in that
 *  order. */
static inline rfe_status_t rfe_mg_pause_status(int brake, int brake_pending, int shift_pending,
                                               int slip, int curve, int low_speed)
{
    rfe_status_t st = RFE_OK;
    if ((brake != 0) || (brake_pending != 0)) {
        st = RFE_MG_PAUSED_BRAKE;
    } else if (shift_pending != 0) {
        st = RFE_MG_PAUSED_SHIFT;
    } else if (slip != 0) {
        st = RFE_MG_PAUSED_SLIP;
    } else if (curve != 0) {
        st = RFE_MG_PAUSED_CURVE;
    } else if (low_speed != 0) {
        st = RFE_NO_UPDATE_LOW_SPEED;
    } else {
        /* update */
    }
    return st;
}

/** §4.2 the ABS gate's latch after a sample of status @p status: set at a paused sample
 *  whose wheels slip (@p slipping: rfe_mg_slipping with pause_grade_slip), kept (@p latched,
 *  its value before the sample) through the rest of the pause, cleared (0) by a sample that
 *  is not paused. A start clears it before its sample is tested. */
static inline uint32_t rfe_mg_slip_latch(rfe_status_t status, uint32_t latched, int slipping)
{
    return ((status != RFE_OK) && ((latched != 0u) || (slipping != 0))) ? 1u : 0u;
}

/** §4.2 v uncorrelated with M after an accepted sample: after a start (@p plan
 *  RFE_MG_PLAN_START: S diagonal) or a paused sample (@p status not RFE_OK: the hold sets
 *  S_Mv = 0, the grade from ax runs only from S_Mv = 0 and keeps S's mass row), 1; after the
 *  filter's update (status RFE_OK), 0, whatever S_Mv it left. Decided from what the sample
 *  did, not by testing S_Mv == 0, because an update's S_Mv rounds to 0 in one number type and
 *  not in another (the Q14 mass row of the Q31 twin: FIXED_POINT.md "Mass and grade"), so
 *  the twins would take different pauses' first samples for learned ones. */
static inline uint32_t rfe_mg_v_free(rfe_mg_plan_t plan, rfe_status_t status)
{
    return ((plan == RFE_MG_PLAN_START) || (status != RFE_OK)) ? 1u : 0u;
}

/** §4.2 the bits of pause_grade that act: all of @p pause_grade with the accelerometer row
 *  (@p use_ax 1), none without it (the grade from ax needs ax on every sample; a preset's
 *  bits over use_ax 0 are valid and inert). */
static inline uint32_t rfe_mg_pause_grade_bits(uint32_t pause_grade, uint32_t use_ax)
{
    return (use_ax == 1u) ? pause_grade : 0u;
}

/** §4.2 the pause kind: in a pause @p status whose bit (RFE_MG_PAUSE_GRADE_*) is set in
 *  @p pause_grade, with v uncorrelated with M (@p v_free: rfe_mg_v_free of the previous
 *  accepted sample, i.e. it was a start or a paused sample, not an update) and the ABS gate's
 *  latch clear (@p slip_latched == 0, rfe_mg_slip_latch), the grade keeps being learned from
 *  ax with M held (1); else the hold (0). So the first sample of a pause that follows an
 *  update holds, the next ones learn, and once the wheels slipped beyond pause_grade_slip the
 *  rest of the pause holds. */
static inline int rfe_mg_grade_in_pause(rfe_status_t status, uint32_t pause_grade,
                                        uint32_t v_free, uint32_t slip_latched)
{
    uint32_t bit = 0u;
    if (status == RFE_MG_PAUSED_BRAKE) {
        bit = RFE_MG_PAUSE_GRADE_BRAKE;
    } else if (status == RFE_MG_PAUSED_SHIFT) {
        bit = RFE_MG_PAUSE_GRADE_SHIFT;
    } else if (status == RFE_MG_PAUSED_CURVE) {
        bit = RFE_MG_PAUSE_GRADE_CURVE;
    } else {
        /* the slip pause (v is the wheels', not the car's) and the low speed: the hold */
    }
    return (((pause_grade & bit) != 0u) && (v_free != 0u) && (slip_latched == 0u)) ? 1 : 0;
}

/** §4.2 the change test of a pause that may learn the grade (rfe_mg_grade_in_pause 1): with
 *  the test off (@p test_on 0: pause_grade_dv 0) it learns at once; else once the residual of
 *  the held grade has left pause_grade_dv (@p beyond: |d| > pause_grade_dv, d the sum over
 *  the pause of du - dt (ax - g sin theta), computed by the twin only while not tripped) or
 *  the test tripped earlier in this pause (@p tripped). Returns the test's new state, 1: the
 *  sample learns, and so does the rest of the pause; a sample that may not learn clears it
 *  (the twins: the residual to 0 with it). */
static inline uint32_t rfe_mg_change_tripped(int test_on, uint32_t tripped, int beyond)
{
    return ((test_on == 0) || (tripped != 0u) || (beyond != 0)) ? 1u : 0u;
}

/** §4.2 the change test runs its sum on this sample: the test on (@p test_on) and not yet
 *  tripped in this pause (@p tripped 0). */
static inline int rfe_mg_change_sums(int test_on, uint32_t tripped)
{
    return ((test_on != 0) && (tripped == 0u)) ? 1 : 0;
}

/** §4.8 the model-mismatch flag: the monitor on (@p on: mm_e > 0) and the EMA of the ax row's
 *  normalised innovation beyond it (@p beyond: |EMA| > mm_e), 1; else 0. */
static inline uint32_t rfe_mg_mismatch(int on, int beyond)
{
    return ((on != 0) && (beyond != 0)) ? 1u : 0u;
}

/** §4.7 the grade's two-level walk, its level after an accepted sample that is not a start:
 *  loose (1: q_theta_hi) once the grade rate's mean square exceeds theta_rate_on^2
 *  (@p above_on), tight (0: q_theta) again once it falls below theta_rate_off^2
 *  (@p below_off), else as it was (@p loose): hysteresis. */
static inline uint32_t rfe_mg_walk_level(uint32_t loose, int above_on, int below_off)
{
    uint32_t level = loose;
    if (loose != 0u) {
        if (below_off != 0) {
            level = 0u;
        }
    } else if (above_on != 0) {
        level = 1u;
    } else {
        /* tight, and s not above on^2: stays tight */
    }
    return level;
}

#endif /* RFE_MASS_GRADE_LOGIC_H */
