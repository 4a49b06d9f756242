/**
 * @file monitor_q31.h
 * @brief Fixed-point twin of rfe/component/monitor.h: the model-validity monitor on the SCKF's
 *        innovations (docs/MONITOR.md §2) in integer arithmetic. The same statistics, the same
 *        thresholds (Pearson's three-cumulant match with the Wilson-Hilferty quantile, the
 *        channel means against z sigma) and the same hysteresis (monitor_logic.h, shared);
 *        the normal quantiles and step counts come precomputed in rfe_monitor_params_q31_t
 *        (rfe_params_to_q31), since the integer library has no inverse normal.
 *
 * Formats (fractional bits): innovations nu and S_zz in Q24 (RFE_FIX_Q_ACC, [m/s^2,
 * rad/s^2]); the persistent diagonal, a sum of their squares, in Q48 as uint64
 * (RFE_MON_Q31_QP: every square of two Q24 values, exactly); the whitened innovation w = S_zz \ nu,
 * the normalised innovations e and their means M in Q20 [sd] (+-2048 sd); the NIS d and its
 * average D in Q16 (+-32768); the persistent shares c and their averages C in Q30; the
 * thresholds of D in Q16 and of |M| in Q20; the inflation factor in Q24. A value beyond its
 * format saturates and is counted (rfe/fixed.h), as everywhere in the fixed-point library.
 *
 * Accuracy against the double twin (derived in monitor_q31.c, checked in
 * test/estimators/friction/test_monitor_q31.c): the averages carry the rounding of one
 * update per step, a dead band of 0.5 / l LSB (l the weight: 25 LSB at l = 1/51); the
 * thresholds of D are within ~1e-5 relative at the default weights (the ratios K3 / K2 and
 * K2 / (K3 / K2) are formed from 30-bit quotients; ~2^-14 relative at the smallest weight
 * 2^-14). A decision near a threshold can therefore differ from the double's by a step.
 * Integer operations only: bit-identical on every platform.
 */
#ifndef RFE_MONITOR_Q31_H
#define RFE_MONITOR_Q31_H

#include <stdint.h>

#include "rfe/fixed.h"
#include "rfe/params_q31.h"

/** Fractional bits of the whitened and normalised innovations and their means [sd]. */
#define RFE_MON_Q31_QE 20u
/** Fractional bits of the NIS d, its average D and D's thresholds. */
#define RFE_MON_Q31_QD 16u
/** Fractional bits of the persistent shares, their averages and the derived weights. */
#define RFE_MON_Q31_QC 30u
/** Fractional bits of the inflation factor of rfe_monitor_inflation_q31. */
#define RFE_MON_Q31_QF 24u
/** Fractional bits of the persistent diagonal (uint64; [(m/s^2)^2, (rad/s^2)^2]): the
 *  squares of Q24 values exactly, with the range of S_zz's own squares (up to 2^16). */
#define RFE_MON_Q31_QP 48u
/** 1 in the inflation factor's format (the factor of a monitor that is not fired). */
#define RFE_MON_Q31_ONE_F ((rfe_fix_t)16777216)

/** Monitor state (caller-owned; fields read-only for the caller). 32-bit words only: no
 *  padding, so whole-state copies and comparisons see defined bytes only. */
typedef struct {
    uint32_t magic;        /**< set by init; guards use before init */
    uint32_t hold_steps;   /**< the parameters' hold_steps */
    uint32_t warmup_steps; /**< the parameters' warmup_steps */
    uint32_t seen;         /**< steps seen (saturates): the warm-up counts them */
    uint32_t hold;         /**< hold counter while fired */
    uint32_t fired;        /**< 1: the data contradict the model */
    uint8_t started;       /**< 0 until the first counted step set C */
    uint8_t inflate;       /**< 1: rfe_monitor_inflation_q31 gives sqrt(max(1, D / m)) (the
                                two flags share one word: the friction state's 2 KiB budget) */
    uint8_t spare[2];      /**< 0 (set by init): the flags' word filled, so no padding */
    rfe_fix_t l_d;         /**< EWMA weight of D, Q30 */
    rfe_fix_t l_m;         /**< EWMA weight of M and C, Q30 */
    rfe_fix_t lp_d;        /**< l' = l_d / (2 - l_d): the sum of the weights' squares, Q30 */
    rfe_fix_t lp_m;        /**< l_m / (2 - l_m), Q30 */
    rfe_fix_t r3_d;        /**< l3 / l'^2 = (2 - l_d)^2 / (3 - 3 l_d + l_d^2), l3 the sum of
                                the weights' cubes, Q30 (in (1, 4/3]) */
    rfe_fix_t z_d_fire;    /**< quantiles as the parameters', Q24 */
    rfe_fix_t z_d_clear;
    rfe_fix_t z_m_fire;
    rfe_fix_t z_m_clear;
    rfe_fix_t D;           /**< NIS average, Q16 */
    rfe_fix_t M[RFE_MEAS]; /**< innovation means, normalised, per channel, Q20 */
    rfe_fix_t C[RFE_MEAS]; /**< persistent shares, averaged, per channel, Q30 */
} rfe_monitor_q31_t;

/** The thresholds at given averaged persistent shares (rfe_monitor_limits_q31). */
typedef struct {
    rfe_fix_t d_fire;             /**< D above this fires, Q16 */
    rfe_fix_t d_clear;            /**< D below this may clear, Q16 */
    rfe_fix_t m_fire[RFE_MEAS];   /**< |M_r| above this fires, Q20 */
    rfe_fix_t m_clear[RFE_MEAS];  /**< |M_r| below this may clear, Q20 */
} rfe_monitor_limits_q31_t;

/**
 * Initialises the monitor from its integer parameters: D = m, M = 0, C = 0, not fired; the
 * weights' derived sums (l', l3 / l'^2) computed here.
 * @param[out] mon  written only on RFE_OK
 * @param[in]  p    within the ranges of rfe_monitor_params_q31_t (rfe_monitor_params_validate_q31;
 *                  enable is the caller's: it is not read)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM.
 * @note No ABI guard (RFE_ERR_ABI, rfe/config.h): unlike the float twin's, this state is
 *       fixed-width integers only, laid out alike whatever the caller's maxima.
 */
RFE_NODISCARD rfe_status_t rfe_monitor_init_q31(rfe_monitor_q31_t *mon,
                                               const rfe_monitor_params_q31_t *p);

/**
 * One step with an innovation (rfe_monitor_step's twin).
 * @param[in] nu    the innovation y - z_hat (RFE_MEAS values, Q24)
 * @param[in] Szz   lower factor of its covariance (RFE_MEAS x RFE_MEAS, row-major, ld
 *                  RFE_MEAS, Q24; only the lower triangle is read), positive diagonal
 * @param[in] pers  the diagonal of the persistent part of S_zz S_zz^T (RFE_MEAS values,
 *                  Q48 as uint64, RFE_MON_Q31_QP; each share is clipped to [0, 1])
 * @param[out] fired 1 when the monitor is fired after this step, else 0 (may be NULL)
 * @param[in,out] sat saturation counter (required): the step's saturations are added on RFE_OK
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NOT_POSITIVE_DEFINITE (a
 *         diagonal entry of Szz not > 0). On error the state and *sat are untouched.
 */
RFE_NODISCARD rfe_status_t rfe_monitor_step_q31(rfe_monitor_q31_t *mon,
                                               const rfe_fix_t nu[RFE_MEAS],
                                               const rfe_fix_t Szz[RFE_MEAS * RFE_MEAS],
                                               const uint64_t pers[RFE_MEAS], uint32_t *fired,
                                               uint32_t *sat);

/**
 * The factor for the reported sd (Q24): sqrt(max(1, D / m)) while fired and inflate = 1,
 * else 1.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_monitor_inflation_q31(const rfe_monitor_q31_t *mon, rfe_fix_t *c);

/**
 * The fire and clear thresholds at persistent shares @p c (Q30, each clipped to [0, 1]),
 * with @p mon's weights and quantiles (docs/MONITOR.md §2 items 4-5).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_monitor_limits_q31(const rfe_monitor_q31_t *mon,
                                                 const rfe_fix_t c[RFE_MEAS],
                                                 rfe_monitor_limits_q31_t *out);

#endif /* RFE_MONITOR_Q31_H */
