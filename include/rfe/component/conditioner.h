/**
 * @file conditioner.h
 * @brief Input conditioning (docs/ESTIMATOR.md step 1): a complementary filter for the
 *        speeds vx, vy, integrating the accelerometer at high frequency and following the
 *        measured speeds at low frequency.
 *
 * State v_x, v_y (caller-owned rfe_conditioner_t), set to the measured vx, vy at the first
 * sample it accepts. Afterwards, with b = dt / (tau_v + dt) and the sample's ax, ay, r:
 *   px = v_x + dt (ax + r v_y),   py = v_y + dt (ay - r v_x)   (the old v_x, v_y in both)
 *   v_x = (1 - b) px + b vx_measured,   v_y = (1 - b) py + b vy_measured.
 * tau_v = 0 switches the filter off: the sample passes through and the state is not touched.
 */
#ifndef RFE_CONDITIONER_H
#define RFE_CONDITIONER_H

#include "rfe/config.h"
#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_conditioner_init rfe_conditioner_init_f64
#define rfe_conditioner_step rfe_conditioner_step_f64
#else
#define rfe_conditioner_init rfe_conditioner_init_f32
#define rfe_conditioner_step rfe_conditioner_step_f32
#endif

/** Complementary-filter state (caller-owned; fields read-only for the caller). */
typedef struct {
    uint32_t magic;   /**< set by init; guards use before init */
    uint32_t started; /**< 0 until the first accepted sample */
    rfe_real_t vx;    /**< filtered vx [m/s] (valid when started) */
    rfe_real_t vy;    /**< filtered vy [m/s] (valid when started) */
} rfe_conditioner_t;

/**
 * Resets the filter: the next accepted sample initialises it.
 * @param[out] c  the filter; written only on RFE_OK.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_ABI (below; nothing written).
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library (the state's layout depends on the number type).
 */
RFE_NODISCARD rfe_status_t rfe_conditioner_init(rfe_conditioner_t *c, size_t size,
                                               uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_CONDITIONER_IMPL), where the name is the function's own. */
#if !defined(RFE_CONDITIONER_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_conditioner_init_f64(c) \
    rfe_conditioner_init_f64((c), sizeof(rfe_conditioner_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_conditioner_init_f32(c) \
    rfe_conditioner_init_f32((c), sizeof(rfe_conditioner_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * One sample: updates the state (when tau_v > 0) and writes the conditioned sample to
 * @p out: a copy of @p in with vx, vy replaced by the filtered speeds. @p out may be @p in.
 * @param dt    sample period [s], finite and > 0
 * @param tau_v time constant [s], finite and >= 0; 0 = off (out = in, state untouched)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_PARAM (dt, tau_v);
 *         RFE_ERR_NONFINITE (vx, vy, ax, ay, yaw_rate of @p in, or an overflowing result).
 *         On error the state and @p out are untouched.
 */
RFE_NODISCARD rfe_status_t rfe_conditioner_step(rfe_conditioner_t *c, rfe_real_t dt,
                                               rfe_real_t tau_v, const rfe_sample_t *in,
                                               rfe_sample_t *out);

#endif /* RFE_CONDITIONER_H */
