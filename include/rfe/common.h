/**
 * @file common.h
 * @brief What the float, double and fixed-point (_q31) libraries share: status codes and
 *        their names, wheel indices, the estimator's measurement count. No number type:
 *        the fixed-point build includes this, never rfe/types.h.
 */
#ifndef RFE_COMMON_H
#define RFE_COMMON_H

/** Results that must be checked. */
#if defined(__GNUC__)
/* MISRA-DEV-02: a GNU attribute (Rule 1.2, language extension), only under __GNUC__ */
#define RFE_NODISCARD __attribute__((warn_unused_result))
#else
#define RFE_NODISCARD
#endif

/**
 * One status enum for the whole library. Values below RFE_ERR_FIRST are information
 * about a successful call; from RFE_ERR_FIRST on they are errors, and the call left its
 * state and outputs untouched.
 */
typedef enum {
    RFE_OK = 0,                     /**< success */
    RFE_PROJECTED = 1,              /**< estimate projected onto [mu_min, mu_max] */
    RFE_NO_UPDATE_LOW_SPEED = 2,    /**< vx < v_est_min: time update only */
    RFE_HELD_NOT_OBSERVABLE = 3,    /**< the step's information about the state is below the
                                         threshold (info_min): time update only */
    RFE_MODEL_MISMATCH = 4,         /**< the model-validity monitor is fired: the innovations
                                         contradict the model, nothing is valid (MONITOR.md) */
    RFE_MG_PAUSED_BRAKE = 5,        /**< mass and grade: the brake is on, or was less than
                                         t_brake ago: held (MASS_GRADE.md §4.2) */
    RFE_MG_PAUSED_SHIFT = 6,        /**< mass and grade: less than t_shift since a gear
                                         change: held (MASS_GRADE.md §4.2) */
    RFE_MG_PAUSED_SLIP = 7,         /**< mass and grade: the wheels' speed departs from the
                                         given ground speed by more than slip_max: held
                                         (MASS_GRADE.md §4.2) */
    RFE_MG_PAUSED_CURVE = 8,        /**< mass and grade: |ay| above ay_max, or was less than
                                         t_curve ago: held (MASS_GRADE.md §4.2) */
    RFE_ERR_FIRST = 16,
    RFE_ERR_NULL = 16,              /**< a required pointer is NULL */
    RFE_ERR_NONFINITE = 17,         /**< an input is NaN or infinite */
    RFE_ERR_RANGE = 18,             /**< an input is outside its documented limits */
    RFE_ERR_PARAM = 19,             /**< a parameter is invalid (see rfe_params_validate) */
    RFE_ERR_SIZE = 20,              /**< a dimension exceeds the compile-time maxima */
    RFE_ERR_NOT_POSITIVE_DEFINITE = 21, /**< Cholesky / triangular factor failed */
    RFE_ERR_NOT_INITIALISED = 22,   /**< state used before a successful init */
    RFE_ERR_ABI = 23                /**< init: the caller was compiled with other maxima or
                                         another number type (rfe/config.h RFE_CONFIG_*) */
} rfe_status_t;

/** Wheel order everywhere (MODEL.md §1). */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum { RFE_FL = 0, RFE_FR = 1, RFE_RL = 2, RFE_RR = 3, RFE_WHEELS = 4 };

/** Number of measurements of the friction estimator: ax, ay, yaw acceleration. */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum { RFE_MEAS = 3 };

/** The inputs of a sample that the step noise perturbs and rfe_meas_eval_perturbed (and its
 *  fixed-point twin) evaluates the model at, in that order: the steer angle, the body
 *  velocities, the yaw rate, then the wheel speed of wheel w as input RFE_IN_OMEGA + w.
 *  ax and ay are never perturbed: the loads stay nominal. */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum {
    RFE_IN_DELTA = 0,
    RFE_IN_VX = 1,
    RFE_IN_VY = 2,
    RFE_IN_YAW_RATE = 3,
    RFE_IN_OMEGA = 4,
    RFE_INPUTS = 8
};

/** A gap in the data (docs/ESTIMATOR.md "Gaps"): a sample period longer than
 *  RFE_GAP_PERIODS nominal periods dt, the limit widened by 2^-RFE_GAP_STAMP_SHIFT of itself
 *  for the time stamps' own rounding (a period of exactly two dt, one dropped sample, is
 *  jitter). It misses round(period / dt) - 1 periods. The library (rfe_friction_missed and
 *  its twin), mu_replay and the reference use this one rule. */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum { RFE_GAP_PERIODS = 2, RFE_GAP_STAMP_SHIFT = 20 };

/** True when the status is an error (the call changed nothing). */
static inline int rfe_status_is_error(rfe_status_t s) { return (int)s >= (int)RFE_ERR_FIRST; }

/** Short human-readable name of a status code (never NULL). Inline because it does not
 *  depend on the number type: one definition serves the _f32, _f64 and _q31 libraries. A
 *  table per range of codes (information 0-8, errors 16-23), so that a new status adds a
 *  name and not a branch. */
static inline const char *rfe_status_str(rfe_status_t s)
{
    static const char *const info[9] = {
        "ok",                                                   /* RFE_OK */
        "projected onto [mu_min, mu_max]",                      /* RFE_PROJECTED */
        "no update: speed below v_est_min",                     /* RFE_NO_UPDATE_LOW_SPEED */
        "held: not observable",                                 /* RFE_HELD_NOT_OBSERVABLE */
        "model mismatch: the innovations contradict the model", /* RFE_MODEL_MISMATCH */
        "held: braking",                                        /* RFE_MG_PAUSED_BRAKE */
        "held: gear shift",                                     /* RFE_MG_PAUSED_SHIFT */
        "held: wheel slip",                                     /* RFE_MG_PAUSED_SLIP */
        "held: cornering"                                       /* RFE_MG_PAUSED_CURVE */
    };
    static const char *const err[8] = {
        "null pointer",                                  /* RFE_ERR_NULL */
        "non-finite input",                              /* RFE_ERR_NONFINITE */
        "input out of range",                            /* RFE_ERR_RANGE */
        "invalid parameter",                             /* RFE_ERR_PARAM */
        "dimension exceeds compile-time maximum",        /* RFE_ERR_SIZE */
        "matrix not positive definite",                  /* RFE_ERR_NOT_POSITIVE_DEFINITE */
        "not initialised",                               /* RFE_ERR_NOT_INITIALISED */
        "caller built with other maxima or number type"  /* RFE_ERR_ABI */
    };
    const int c = (int)s;
    const char *name = "unknown status";
    if ((c >= (int)RFE_OK) && (c <= (int)RFE_MG_PAUSED_CURVE)) {
        name = info[c];
    } else if ((c >= (int)RFE_ERR_FIRST) && (c <= (int)RFE_ERR_ABI)) {
        name = err[c - (int)RFE_ERR_FIRST];
    } else {
        /* not a status of this library */
    }
    return name;
}

#endif /* RFE_COMMON_H */
