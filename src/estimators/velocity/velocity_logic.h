/**
 * @file velocity_logic.h
 * @brief Private, shared by both number types (the observer's *_flt.c and *_q31.c; no real
 *        type in it): the observer's decisions that are not arithmetic. Each twin makes the
 *        comparisons on its own numbers and hands their outcomes (0 or 1, or a wheel mask)
 *        here; what follows from them lives once. Not installed.
 *
 *  - the step plan (§3.0): the first accepted sample initialises, every later one runs the
 *    filters in the order yaw rate, longitudinal, lateral;
 *  - the driving state (§3.4) from the deceleration / acceleration tests, the pressures and
 *    the torques;
 *  - the wheel votes (§3.5): which plausible wheel is free-rolling, and which reference the
 *    longitudinal filter takes;
 *  - the re-acquisition of the wheels and the drift while braking unchecked (§3.5);
 *  - the time the yaw rate has stayed on its neutral reference, and whether the lateral
 *    filter takes the linear range's vy (§4.2b);
 *  - whether the reported sd(vy) has its floor (§5, vy_out_floor_mu);
 *  - the flags each decision sets (§5).
 */
#ifndef RFE_VELOCITY_LOGIC_H
#define RFE_VELOCITY_LOGIC_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"
#include "rfe/velocity_bits.h"

/** §3.0 what a step does: initialise the filters, or run them. */
typedef enum {
    RFE_VEL_PLAN_START = 0,  /**< first accepted sample: every filter initialised from it */
    RFE_VEL_PLAN_FILTERS = 1 /**< later samples: yaw rate, then longitudinal, then lateral */
} rfe_vel_plan_t;

/** The filters a later sample runs, in their order (§3.1): the yaw-rate differentiator
 *  first (the lateral filter's kinematic noise uses its r-dot of the previous step), then
 *  the longitudinal filter (on the lateral filter's previous vy), then the lateral filter
 *  (at this step's vx). */
typedef enum {
    RFE_VEL_STAGE_YAW = 0,
    RFE_VEL_STAGE_LONGITUDINAL = 1,
    RFE_VEL_STAGE_LATERAL = 2,
    RFE_VEL_STAGES = 3
} rfe_vel_stage_t;

/** Stage @p k (0 .. RFE_VEL_STAGES - 1) of a later sample, in the order above. */
static inline rfe_vel_stage_t rfe_vel_stage(size_t k)
{
    static const rfe_vel_stage_t order[RFE_VEL_STAGES] = {
        RFE_VEL_STAGE_YAW, RFE_VEL_STAGE_LONGITUDINAL, RFE_VEL_STAGE_LATERAL};
    return order[k];
}

/** §3.0 the plan of a step from the observer's `started`. */
static inline rfe_vel_plan_t rfe_vel_plan(uint32_t started)
{
    return (started == 0u) ? RFE_VEL_PLAN_START : RFE_VEL_PLAN_FILTERS;
}

/** §4.2 the lateral model's rate: `started` is 0 before the first accepted sample and
 *  afterwards the phase of this step, 1 .. lat_every; the model's rows are evaluated on the
 *  steps of phase 1 (every step when lat_every is 1). */
static inline int rfe_vel_model_due(uint32_t started)
{
    return (started == 1u) ? 1 : 0;
}

/** §4.2 `started` after an accepted step: 1 after the first sample (its next step evaluates
 *  the model), else the next phase, back to 1 after @p lat_every (>= 1) steps. */
static inline uint32_t rfe_vel_next_phase(rfe_vel_plan_t plan, uint32_t started,
                                          uint32_t lat_every)
{
    return ((plan == RFE_VEL_PLAN_START) || (started >= lat_every)) ? 1u : (started + 1u);
}

/** The driven-wheel bit of wheel @p i (fl, fr, rl, rr: the RFE_DRIVEN_* order). */
static inline uint32_t rfe_vel_wheel_bit(size_t i)
{
    return (uint32_t)1u << i;
}

/** The outcomes of the driving-state comparisons of one sample (§3.4). */
typedef struct {
    int decelerating;       /**< a_net < -ax_brake_on (a_net: ax - g sin grade - b_x) */
    int accelerating;       /**< a_net > ax_drive_on */
    uint32_t pressure_mask; /**< bit i: p_brake[i] > p_brake_on */
    uint32_t torque_mask;   /**< bit i: torque[i] > torque_on */
    int turning;            /**< ay_turn > 0 and |ay| >= ay_turn */
} rfe_vel_drive_tests_t;

/** The driving state (§3.4). */
typedef struct {
    int decelerating; /**< 1: a_net < -ax_brake_on (the test's outcome) */
    int braking;     /**< 1: braking */
    int driving;     /**< 1: driving (never together with braking) */
    uint32_t driven; /**< the wheels driven this step (RFE_DRIVEN_* bits) */
    int turning;     /**< 1: in a turn and not braking (b_x's walk is q_bx_turn; rolling,
                          the driven wheels are not free) */
} rfe_vel_drive_state_t;

/** §3.4 braking when decelerating or (pressures given) a wheel's pressure is above its
 *  threshold; driving when not braking and accelerating, or (torques given) when not
 *  braking and a wheel's torque is above its threshold, which then also names the driven
 *  wheels (else the parameters' @p driven); turning when in a turn and not braking. */
static inline rfe_vel_drive_state_t rfe_vel_drive_state(const rfe_vel_drive_tests_t *t,
                                                        uint32_t has, uint32_t driven)
{
    rfe_vel_drive_state_t s;
    s.decelerating = t->decelerating;
    s.braking = 0;
    s.driving = 0;
    s.driven = driven;
    s.turning = 0;
    if ((t->decelerating != 0) ||
        (((has & RFE_VEL_HAS_PRESSURE) != 0u) && (t->pressure_mask != 0u))) {
        s.braking = 1;
    }
    if ((has & RFE_VEL_HAS_TORQUE) != 0u) {
        s.driven = t->torque_mask;
        if ((s.braking == 0) && (s.driven != 0u)) {
            s.driving = 1;
        }
    } else if ((s.braking == 0) && (t->accelerating != 0)) {
        s.driving = 1;
    } else {
        /* rolling or braking */
    }
    if ((s.braking == 0) && (t->turning != 0)) {
        s.turning = 1;
    }
    return s;
}

/** §5 the driving-state flag. */
static inline uint32_t rfe_vel_drive_flags(const rfe_vel_drive_state_t *s)
{
    uint32_t fl = 0u;
    if (s->braking != 0) {
        fl = RFE_VEL_FLAG_BRAKING;
    } else if (s->driving != 0) {
        fl = RFE_VEL_FLAG_DRIVING;
    } else {
        /* rolling */
    }
    return fl;
}

/** §3.5 a plausible wheel @p i measures vx (free-rolling): nothing is braked, and wheel i
 *  is not a driven one, or nothing is driven and the car is not in a turn (in a turn the
 *  driven wheels carry its drag with ax near 0: not free although rolling). */
static inline int rfe_vel_wheel_is_free(const rfe_vel_drive_state_t *s, size_t i)
{
    return ((s->braking == 0) &&
            (((s->driving == 0) && (s->turning == 0)) ||
             ((s->driven & rfe_vel_wheel_bit(i)) == 0u))) ? 1 : 0;
}

/** §3.5 the reference the longitudinal filter takes. */
typedef enum {
    RFE_VEL_REF_NONE = 0,     /**< no correction this step */
    RFE_VEL_REF_FREE_MEAN = 1, /**< the mean of the free-rolling wheels (variance / count) */
    RFE_VEL_REF_BRAKED_HI = 2, /**< braking: the fastest plausible wheel, a lower bound */
    RFE_VEL_REF_DRIVEN_LO = 3, /**< driving: the slowest plausible wheel, an upper bound */
    RFE_VEL_REF_REACQUIRE = 4  /**< every wheel outside the gate but in agreement: their
                                    mean, the prediction's variance re-inflated */
} rfe_vel_ref_t;

/** §3.5 which reference: the free wheels' mean when there is one; else, braking, the
 *  fastest plausible wheel when it is above the prediction (a braked wheel turns slower
 *  than it rolls); else, driving, the slowest when it is below (a driven wheel turns
 *  faster). @p hi_above: the fastest plausible wheel > vx_pred; @p lo_below: the slowest
 *  < vx_pred (both meaningless, and unused, when @p n_ok is 0). */
static inline rfe_vel_ref_t rfe_vel_reference(size_t n_free, size_t n_ok,
                                              const rfe_vel_drive_state_t *s, int hi_above,
                                              int lo_below)
{
    rfe_vel_ref_t r = RFE_VEL_REF_NONE;
    if (n_free > 0u) {
        r = RFE_VEL_REF_FREE_MEAN;
    } else if ((n_ok > 0u) && (s->braking != 0) && (hi_above != 0)) {
        r = RFE_VEL_REF_BRAKED_HI;
    } else if ((n_ok > 0u) && (s->braking == 0) && (s->driving != 0) && (lo_below != 0)) {
        r = RFE_VEL_REF_DRIVEN_LO;
    } else {
        /* no trustworthy wheel this step */
    }
    return r;
}

/** §3.5 re-acquisition when the gated wheels gave no reference (@p ref NONE): the gate
 *  guards against one wheel that slips, not against a prediction that drifted away from
 *  all of them. Taken when the car rolls (neither braking nor driving) and the wheels agree
 *  (@p agree: max - min <= k_agree sd_w), or when it stands (@p standing: every wheel below
 *  v_stand) without decelerating or driving (the brake may be held). */
static inline rfe_vel_ref_t rfe_vel_reacquire(rfe_vel_ref_t ref, int agree, int standing,
                                              const rfe_vel_drive_state_t *s)
{
    rfe_vel_ref_t r = ref;
    if ((ref == RFE_VEL_REF_NONE) && (s->driving == 0)) {
        if (((s->braking == 0) && (agree != 0)) ||
            ((standing != 0) && (s->decelerating == 0))) {
            r = RFE_VEL_REF_REACQUIRE;
        }
    }
    return r;
}

/** §3.5 braking and no wheel corrected vx this step: vx integrates ax, whose error while
 *  braking (pitch, scale) is more than its offset's: the variance grows by q_vx_brake^2 dt. */
static inline int rfe_vel_brake_drift(rfe_vel_ref_t ref, const rfe_vel_drive_state_t *s)
{
    return ((ref == RFE_VEL_REF_NONE) && (s->braking != 0)) ? 1 : 0;
}

/** §4.2b what the time the yaw rate has stayed on its reference does this step. */
typedef enum {
    RFE_VEL_ON_REF_RESET = 0, /**< r is off r_ref (or vx below v_lat_min): back to 0 */
    RFE_VEL_ON_REF_ADD = 1,   /**< r on r_ref: plus this period, held at lin_dwell */
    RFE_VEL_ON_REF_HOLD = 2   /**< r on r_ref and the time has reached lin_dwell: kept */
} rfe_vel_on_ref_t;

/** §4.2b the time on r_ref: reset when the yaw rate is off it (@p yaw_linear 0), kept once
 *  it has reached lin_dwell (@p reached: time >= lin_dwell; the sum stays bounded), else
 *  grown by the period. */
static inline rfe_vel_on_ref_t rfe_vel_on_ref(int yaw_linear, int reached)
{
    rfe_vel_on_ref_t a = RFE_VEL_ON_REF_RESET;
    if ((yaw_linear != 0) && (reached != 0)) {
        a = RFE_VEL_ON_REF_HOLD;
    } else if (yaw_linear != 0) {
        a = RFE_VEL_ON_REF_ADD;
    } else {
        /* off the reference */
    }
    return a;
}

/** §4.2b the linear range's update of vy: on (@p on: sd_vy_lin > 0), the yaw rate near the
 *  neutral reference (@p yaw_linear: |r - r_ref| <= lin_r_tol + lin_r_rel |r_ref|) and the
 *  lateral acceleration moderate (@p ay_moderate: |ay| <= lin_ay_max), or in a steady turn
 *  below the higher cap (@p ay_steady: |ay| <= lin_ay_steady, and @p dwelled: the yaw rate
 *  has stayed on r_ref for lin_dwell, this step included). */
static inline int rfe_vel_linear_range(int on, int yaw_linear, int ay_moderate, int ay_steady,
                                       int dwelled)
{
    return ((on != 0) && (yaw_linear != 0) &&
            ((ay_moderate != 0) || ((ay_steady != 0) && (dwelled != 0)))) ? 1 : 0;
}

/** §4.2 the steady turn's friction floor: the linear range is taken this step (@p linear)
 *  and the yaw rate has stayed on r_ref for lin_dwell (@p dwelled): the tyres are in their
 *  linear range, so the model's friction is at least lin_mu_gain |ay| / g. */
static inline int rfe_vel_lin_floor(int linear, int dwelled)
{
    return ((linear != 0) && (dwelled != 0)) ? 1 : 0;
}

/** §5 the reported sd(vy)'s floor applies on a later sample (@p plan: not the first, which
 *  only initialises), when it is on (@p on: vy_out_floor_mu > 0) and vx is at least
 *  v_lat_min (@p lateral: the lateral model's speed range, where the slip part it scales
 *  exists). */
static inline int rfe_vel_out_floor_due(rfe_vel_plan_t plan, int on, int lateral)
{
    return ((plan == RFE_VEL_PLAN_FILTERS) && (on != 0) && (lateral != 0)) ? 1 : 0;
}

#endif /* RFE_VELOCITY_LOGIC_H */
