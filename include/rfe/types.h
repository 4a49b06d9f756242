/**
 * @file types.h
 * @brief Shared types of the rfe (road-friction estimator) library: status codes,
 *        the floating-point real type, wheel indices, and the sensor sample.
 *
 * Build switch: the floating-point variant is compiled for float32 by default (firmware)
 * or for double with -DRFE_REAL_DOUBLE (host build, compared against the float64
 * reference). Public functions carry the precision in their name (`_f32` / `_f64`) so
 * both builds can be linked into one host program; the fixed-point twin uses `_q31`.
 */
#ifndef RFE_TYPES_H
#define RFE_TYPES_H

#include <stddef.h>
#include <stdint.h>

#if defined(RFE_REAL_DOUBLE)
typedef double rfe_real_t;
/** Appends the precision suffix to a public function name. */
/* cppcheck-suppress misra-c2012-20.10 ; MISRA-DEV-01: ## builds the precision suffix */
#define RFE_FN(name) name##_f64
#else
typedef float rfe_real_t;
/* cppcheck-suppress misra-c2012-20.10 ; MISRA-DEV-01: ## builds the precision suffix */
#define RFE_FN(name) name##_f32
#endif

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
    RFE_ERR_FIRST = 16,
    RFE_ERR_NULL = 16,              /**< a required pointer is NULL */
    RFE_ERR_NONFINITE = 17,         /**< an input is NaN or infinite */
    RFE_ERR_RANGE = 18,             /**< an input is outside its documented limits */
    RFE_ERR_PARAM = 19,             /**< a parameter is invalid (see rfe_params_validate) */
    RFE_ERR_SIZE = 20,              /**< a dimension exceeds the compile-time maxima */
    RFE_ERR_NOT_POSITIVE_DEFINITE = 21, /**< Cholesky / triangular factor failed */
    RFE_ERR_NOT_INITIALISED = 22    /**< state used before a successful init */
} rfe_status_t;

/** Wheel order everywhere (MODEL.md §1). */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum { RFE_FL = 0, RFE_FR = 1, RFE_RL = 2, RFE_RR = 3, RFE_WHEELS = 4 };

/** Number of measurements of the friction estimator: ax, ay, yaw acceleration. */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum { RFE_MEAS = 3 };

/** One sensor sample (DATA.md sensor log), SI units, ISO 8855 body axes. */
typedef struct {
    rfe_real_t delta;      /**< front road-wheel steer angle [rad] */
    rfe_real_t vx;         /**< CoG velocity, body x [m/s] */
    rfe_real_t vy;         /**< CoG velocity, body y [m/s] */
    rfe_real_t yaw_rate;   /**< r [rad/s] */
    rfe_real_t yaw_acc;    /**< r-dot [rad/s^2] (measurement) */
    rfe_real_t ax;         /**< CoG acceleration, body x [m/s^2] (measurement and load input) */
    rfe_real_t ay;         /**< CoG acceleration, body y [m/s^2] (measurement and load input) */
    rfe_real_t omega[RFE_WHEELS]; /**< wheel spin speeds [rad/s], order fl fr rl rr */
} rfe_sample_t;

/** True when the status is an error (the call changed nothing). */
static inline int rfe_status_is_error(rfe_status_t s) { return (int)s >= (int)RFE_ERR_FIRST; }

/** Short human-readable name of a status code (never NULL). Inline because it does not
 *  depend on the number type: one definition serves the _f32, _f64 and _q31 libraries. */
static inline const char *rfe_status_str(rfe_status_t s)
{
    const char *name;
    switch (s) {
    case RFE_OK: name = "ok"; break;
    case RFE_PROJECTED: name = "projected onto [mu_min, mu_max]"; break;
    case RFE_NO_UPDATE_LOW_SPEED: name = "no update: speed below v_est_min"; break;
    case RFE_HELD_NOT_OBSERVABLE: name = "held: not observable"; break;
    case RFE_ERR_NULL: name = "null pointer"; break;
    case RFE_ERR_NONFINITE: name = "non-finite input"; break;
    case RFE_ERR_RANGE: name = "input out of range"; break;
    case RFE_ERR_PARAM: name = "invalid parameter"; break;
    case RFE_ERR_SIZE: name = "dimension exceeds compile-time maximum"; break;
    case RFE_ERR_NOT_POSITIVE_DEFINITE: name = "matrix not positive definite"; break;
    case RFE_ERR_NOT_INITIALISED: name = "not initialised"; break;
    default: name = "unknown status"; break;
    }
    return name;
}

#endif /* RFE_TYPES_H */
