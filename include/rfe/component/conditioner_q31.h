/**
 * @file conditioner_q31.h
 * @brief Fixed-point twin of rfe/component/conditioner.h: the complementary filter for the speeds
 *        vx, vy (docs/ESTIMATOR.md step 1) on int32 Q values (docs/FIXED_POINT.md,
 *        "Estimator").
 *
 * State v_x, v_y (Q23, the format of the sample's speeds), set to the measured vx, vy at the
 * first sample it accepts. Afterwards, with the gain b = dt / (tau_v + dt) (precomputed:
 * rfe_filter_params_q31_t.b_v, so the integer code never divides by a parameter):
 *   px = v_x + dt (ax + r v_y),   py = v_y + dt (ay - r v_x)   (the old v_x, v_y in both)
 *   v_x = (1 - b) px + b vx_measured,   v_y = (1 - b) py + b vy_measured.
 * The products are formed exactly in int64 (wide intermediate formats, Q40 and Q46, see
 * conditioner_q31.c); each new speed is within 0.5 LSB23 + 2^-39 m/s of the exact blend of
 * the Q inputs, and saturates (counted in *sat) only beyond +-256 m/s.
 * tau_v = 0 switches the filter off: the sample passes through and the state is not touched.
 */
#ifndef RFE_CONDITIONER_Q31_H
#define RFE_CONDITIONER_Q31_H

#include <stdint.h>

#include "rfe/common.h"
#include "rfe/fixed.h"
#include "rfe/component/tyre_q31.h"

/** Complementary-filter state (caller-owned; fields read-only for the caller). */
typedef struct {
    uint32_t magic;   /**< set by init; guards use before init */
    uint32_t started; /**< 0 until the first accepted sample */
    rfe_fix_t vx;     /**< filtered vx [m/s], Q23 (valid when started) */
    rfe_fix_t vy;     /**< filtered vy [m/s], Q23 (valid when started) */
} rfe_conditioner_q31_t;

/**
 * Resets the filter: the next accepted sample initialises it.
 * @param[out] c  the filter; written only on RFE_OK.
 * @return RFE_OK; RFE_ERR_NULL.
 * @note No ABI guard (RFE_ERR_ABI, rfe/config.h): unlike the float twin's, this state is
 *       fixed-width integers only, laid out alike whatever the caller's maxima.
 */
RFE_NODISCARD rfe_status_t rfe_conditioner_init_q31(rfe_conditioner_q31_t *c);

/**
 * One sample: updates the state (when tau_v > 0) and writes the conditioned sample to
 * @p out: a copy of @p in with vx, vy replaced by the filtered speeds. @p out may be @p in.
 * The arguments of rfe_conditioner_step plus what fixed point needs: the precomputed gain
 * @p b_v and the saturation counter.
 * @param dt    sample period [s], Q30 (RFE_FIX_Q_DT), > 0
 * @param tau_v time constant [s], Q26 (RFE_FIX_Q_TAU), >= 0; 0 = off (out = in, state
 *              untouched; b_v is then not used)
 * @param b_v   dt / (tau_v + dt), Q30, in (0, 1] (rfe_filter_params_q31_t.b_v)
 * @param sat   saturation counter (required): one count per new speed clamped to Q23
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_PARAM (dt <= 0, tau_v < 0,
 *         b_v outside (0, 1]). On error the state, @p out and *sat are untouched. Every int32
 *         sample is in the domain (there are no non-finite values).
 */
RFE_NODISCARD rfe_status_t rfe_conditioner_step_q31(rfe_conditioner_q31_t *c, rfe_fix_t dt,
                                                    rfe_fix_t tau_v, rfe_fix_t b_v,
                                                    const rfe_sample_q31_t *in,
                                                    rfe_sample_q31_t *out, uint32_t *sat);

#endif /* RFE_CONDITIONER_Q31_H */
