/**
 * @file friction_logic.h
 * @brief What the friction estimator's twins (friction_flt.c, friction_q31.c) decide alike,
 *        whatever their arithmetic (docs/ESTIMATOR.md): the map T from wheels to states, the
 *        step's status and the per-wheel valid flag. Written once, so the twins cannot drift.
 */
#ifndef RFE_FRICTION_LOGIC_H
#define RFE_FRICTION_LOGIC_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"
#include "rfe/modes.h"

/* State index of wheel w: the map T. wheels: T = I; sides: fl, rl on the left state 0,
 * fr, rr on the right state 1. */
static inline size_t rfe_friction_state_index(rfe_structure_t structure, size_t w)
{
    if (structure == RFE_STRUCT_SIDES) {
        return ((w == (size_t)RFE_FL) || (w == (size_t)RFE_RL)) ? 0u : 1u;
    }
    return w;
}

/* 1 for the inputs the conditioner low-passes (ESTIMATOR.md step 1: vx, vy): their error
 * persists over tau_v, so the model monitor counts their step-noise columns as persistent
 * (docs/MONITOR.md §1). */
static inline int rfe_input_low_passed(size_t j)
{
    return ((j == (size_t)RFE_IN_VX) || (j == (size_t)RFE_IN_VY)) ? 1 : 0;
}

/* The status of a step that raised no error (steps 3, 6, 8): no measurement below v_est_min,
 * held when the gate kept the update out, projected when step 8 moved the mean. */
static inline rfe_status_t rfe_friction_step_status(int measured, int updated, int clamped)
{
    rfe_status_t s = RFE_NO_UPDATE_LOW_SPEED;
    if (measured != 0) {
        s = (updated != 0) ? RFE_OK : RFE_HELD_NOT_OBSERVABLE;
    }
    if ((updated != 0) && (clamped != 0)) {
        s = RFE_PROJECTED;
    }
    return s;
}

/* The status of a step while the model-validity monitor is fired, for a status its verdict
 * applies to (0, 1, 3: rfe_friction_monitor_applies; docs/MONITOR.md §2 item 7): updated
 * steps and a held one that would be valid (a flag 1) report the mismatch; a held step with
 * every flag 0 keeps "not observable" (the status says why the estimate is not valid). */
static inline rfe_status_t rfe_friction_monitor_status(rfe_status_t st, int any_valid)
{
    rfe_status_t out = RFE_MODEL_MISMATCH;
    if ((st == RFE_HELD_NOT_OBSERVABLE) && (any_valid == 0)) {
        out = st;
    }
    return out;
}

/* 1 when the monitor's verdict applies to a step of status st (it evaluated the model: 0, 1,
 * 3; docs/MONITOR.md §2 item 7). */
static inline int rfe_friction_monitor_applies(rfe_status_t st)
{
    return ((st == RFE_OK) || (st == RFE_PROJECTED) || (st == RFE_HELD_NOT_OBSERVABLE)) ? 1 : 0;
}

/* Step 9's sd rule for one wheel (sd_ok: sd_valid > 0 and sd <= sd_valid; inside: the mean
 * strictly between mu_min and mu_max; above: the bound margin, mu - mu_min >= valid_bound_k sd,
 * always 1 when valid_bound_k = 0). A mean on a bound was put there by the projection
 * (step 8): the data asked for a friction outside the physical range, so the filter's sd
 * does not describe the error there; nor does it near the lower bound, where the projection
 * has cut off the Gaussian claim's lower tail (docs/ESTIMATOR.md step 9, MONITOR.md §10). */
static inline uint8_t rfe_friction_by_sd(uint8_t sd_ok, uint8_t inside, uint8_t above)
{
    return ((sd_ok != 0u) && (inside != 0u) && (above != 0u)) ? 1u : 0u;
}

/* Step 9's valid flag of one wheel after a step with status st: never after an error; by the
 * sd (by_sd, computed from the estimate) when the sd rule is on (sd_valid > 0); else the
 * paper's rule, valid when this step updated the estimate from data. */
static inline uint8_t rfe_friction_valid(rfe_status_t st, int sd_rule, uint8_t by_sd)
{
    if (rfe_status_is_error(st) != 0) {
        return 0u;
    }
    if (sd_rule != 0) {
        return by_sd;
    }
    return ((st == RFE_OK) || (st == RFE_PROJECTED)) ? 1u : 0u;
}

/* Step 9's holds, the bits of a side's held flags: its rear wheels hold (RFE_HOLD_REAR), or
 * both its wheels hold after a jump (RFE_HOLD_JUMP). */
#define RFE_HOLD_REAR 1u
#define RFE_HOLD_JUMP 2u

/* Step 9's holds: a wheel of a side held after a jump, or a rear wheel (RL, RR) of a side whose
 * rear hold is on, is not valid; every other flag as it was. */
static inline uint8_t rfe_friction_held_valid(size_t w, uint8_t held, uint8_t valid)
{
    const uint8_t rear = ((w >= (size_t)RFE_RL) && ((held & RFE_HOLD_REAR) != 0u)) ? 1u : 0u;
    return ((rear != 0u) || ((held & RFE_HOLD_JUMP) != 0u)) ? 0u : valid;
}

/* Step 0b, the yaw-rate input check (docs/ESTIMATOR.md): it checks a sample when it is on
 * (yaw_check > 0) and has a sample accepted as it was to predict from (yaw_on: 0 at init and
 * after a replaced sample) with no gap since (periods 0: a gap restarts it, like the
 * conditioner). */
static inline int rfe_friction_yaw_checked(int on, uint8_t yaw_on, uint32_t periods)
{
    return ((on != 0) && (yaw_on != 0u) && (periods == 0u)) ? 1 : 0;
}

/* Step 9's stale-wheel-speed rule for one wheel (docs/ESTIMATOR.md; stale_omega > 0): its
 * reference (the median of the other three) restarts when its speed changed (same 0) or reads
 * exactly 0 (a wheel at rest or locked: a state of the car, not of the sensor); else the wheel
 * is stale when the others' median moved by more than stale_omega since (moved). */
#define RFE_STALE_RESTART 1u
#define RFE_STALE_STALE 2u
static inline uint8_t rfe_friction_stale_wheel(int same, int zero, int moved)
{
    uint8_t out = 0u;
    if ((same == 0) || (zero != 0)) {
        out = RFE_STALE_RESTART;
    } else if (moved != 0) {
        out = RFE_STALE_STALE;
    } else {
        /* unchanged, the others still: nothing */
    }
    return out;
}

/* Step 9's flag of a wheel while a wheel speed is stale: 0 on every wheel (the shared road
 * state carries one wheel's error to the other side, docs/MONITOR.md §8); else as it was. */
static inline uint8_t rfe_friction_stale_valid(uint8_t stale, uint8_t valid)
{
    return (stale != 0u) ? 0u : valid;
}

/* Periods of a gap added to those pending, saturating (far beyond any wheelbase's distance). */
static inline uint32_t rfe_friction_periods_add(uint32_t pending, uint32_t missed)
{
    return (missed > (UINT32_MAX - pending)) ? UINT32_MAX : (pending + missed);
}

#endif /* RFE_FRICTION_LOGIC_H */
