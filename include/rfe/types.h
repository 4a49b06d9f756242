/**
 * @file types.h
 * @brief Types of the floating-point library (float or double): the real type and the
 *        sensor sample. What every number type shares (status codes, wheel indices) is
 *        rfe/common.h's, which this includes.
 *
 * Build switch: the floating-point variant is compiled for float32 by default (firmware)
 * or for double with -DRFE_REAL_DOUBLE (host build, compared against the float64
 * reference). Public functions carry the precision in their name (`_f32` / `_f64`) so
 * both builds can be linked into one host program; the fixed-point twin uses `_q31`.
 * Each header maps its functions' short names to the full ones in a block at its top
 * (`#define rfe_sckf_init rfe_sckf_init_f32`), so every full name is written out once
 * and a grep for it finds that header.
 */
#ifndef RFE_TYPES_H
#define RFE_TYPES_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"

#if defined(RFE_REAL_DOUBLE)
typedef double rfe_real_t;
#else
typedef float rfe_real_t;
#endif

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

#endif /* RFE_TYPES_H */
