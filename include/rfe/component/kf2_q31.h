/**
 * @file kf2_q31.h
 * @brief Fixed-point twin of rfe/component/kf2.h: the two-state linear Kalman filter of the
 *        velocity observer (docs/OBSERVER.md §3-4, docs/FIXED_POINT.md "Observer").
 *
 * The states are int32 in the Q formats q0, q1 the filter is initialised with; the
 * covariance is int64, p00 in Q(2 q0), p01 in Q(q0 + q1), p11 in Q(2 q1), so the small
 * variances of a settled filter (1e-8 and below) keep their precision. The transition's
 * f01 is given in Q(qf): f01 x1 lands in the format of x0 after a shift of q1 + qf - q0.
 *
 * Arithmetic. Every product of a covariance and an int32 factor is exactly rounded
 * (rfe_q31_mul64x32); the gain is the ratio ph_i / S of two int64, carried as a 30-bit
 * mantissa and a power of two (relative error <= 2^-29), and the update uses
 * P <- P - (P H^T) (P H^T)^T / S, so K and S never need a format of their own.
 * Saturation (rfe/fixed.h): a state clamps to +-INT32_MAX, a covariance entry to
 * +-RFE_KF2_Q31_PMAX; each clamp counts one in `*sat`. Saturation is not an error. On an
 * error the filter and `*sat` are untouched.
 */
#ifndef RFE_KF2_Q31_H
#define RFE_KF2_Q31_H

#include <stdint.h>

#include "rfe/common.h"
#include "rfe/fixed.h"

/** Bound of every covariance entry (2^61): keeps each product with an int32 below 2^93
 *  and each sum of two entries inside int64. */
#define RFE_KF2_Q31_PMAX ((int64_t)2305843009213693952)

/** Two-state filter (caller-owned; plain data, copy it to keep a snapshot). */
typedef struct {
    rfe_fix_t x[2];      /**< mean: x0 in Q(q0), x1 in Q(q1) */
    int64_t p00;         /**< var(x0), Q(2 q0) */
    int64_t p01;         /**< cov(x0, x1), Q(q0 + q1) */
    int64_t p11;         /**< var(x1), Q(2 q1) */
    unsigned int q0;     /**< Q format of x0 */
    unsigned int q1;     /**< Q format of x1 */
    unsigned int qf;     /**< Q format of the transition's f01 */
} rfe_kf2_q31_t;

/** One scalar measurement z = h0 x0 + h1 x1 (+ noise) for rfe_kf2_update_q31. */
typedef struct {
    rfe_fix_t h0;        /**< H's first entry, Q(qh0): h0 x0 lands in Q(qz) after a
                              shift of q0 + qh0 - qz */
    rfe_fix_t h1;        /**< H's second entry, Q(qh1) */
    unsigned int qh0;    /**< Q format of h0 */
    unsigned int qh1;    /**< Q format of h1 */
    unsigned int qz;     /**< Q format of the measurement */
    rfe_fix_t nu;        /**< the innovation z - H x, Q(qz) */
    int64_t r;           /**< noise variance, Q(2 qz), >= 0 */
} rfe_kf2_meas_q31_t;

/**
 * Sets the formats, x = [x0, x1], P = diag(sd0^2, sd1^2).
 * @param[out] f         the filter.
 * @param[in]  q0, q1    Q formats of the states, <= 31.
 * @param[in]  qf        Q format of f01, with 1 <= q1 + qf - q0 <= 62.
 * @param[in]  x0, x1    the initial mean, Q(q0), Q(q1).
 * @param[in]  sd0, sd1  the initial sds, Q(q0), Q(q1), >= 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE (a negative sd, a format outside its range).
 * @note No ABI guard (RFE_ERR_ABI, rfe/config.h): unlike the float twin's, this state is
 *       fixed-width integers only, laid out alike whatever the caller's maxima.
 */
RFE_NODISCARD rfe_status_t rfe_kf2_init_q31(rfe_kf2_q31_t *f, unsigned int q0, unsigned int q1,
                                            unsigned int qf, rfe_fix_t x0, rfe_fix_t x1,
                                            rfe_fix_t sd0, rfe_fix_t sd1);

/**
 * Time update x <- F x + [u, 0], P <- F P F^T + Q with F = [[1, f01], [0, 1]],
 * Q = [[q00, q01], [q01, q11]] (kf2.h).
 * @param[in,out] f    the filter (rfe_kf2_init_q31).
 * @param[in]     f01  Q(qf).
 * @param[in]     u    Q(q0).
 * @param[in]     q00  Q(2 q0), q11 Q(2 q1), q01 Q(q0 + q1); each within +-RFE_KF2_Q31_PMAX.
 * @param[in,out] sat  saturation counter.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE (a noise term beyond RFE_KF2_Q31_PMAX, or
 *         formats that rfe_kf2_init_q31 would reject).
 */
RFE_NODISCARD rfe_status_t rfe_kf2_predict_q31(rfe_kf2_q31_t *f, rfe_fix_t f01, rfe_fix_t u,
                                               int64_t q00, int64_t q11, int64_t q01,
                                               uint32_t *sat);

/**
 * Scalar measurement update (kf2.h): S = H P H^T + r, x <- x + P H^T nu / S,
 * P <- P - P H^T H P / S.
 * @param[in,out] f    the filter.
 * @param[in]     m    the measurement: shifts q0 + qh0 - qz and q1 + qh1 - qz within
 *                     [1, 62], qz <= 31, 0 <= r <= RFE_KF2_Q31_PMAX.
 * @param[in,out] sat  saturation counter.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE (formats, r); RFE_ERR_NOT_POSITIVE_DEFINITE
 *         (S <= 0).
 */
RFE_NODISCARD rfe_status_t rfe_kf2_update_q31(rfe_kf2_q31_t *f, const rfe_kf2_meas_q31_t *m,
                                              uint32_t *sat);

/**
 * The filter's covariance product, for the callers' noise terms: *out = round(v c / 2^s),
 * exactly rounded, clamped to +-RFE_KF2_Q31_PMAX (counted in *sat).
 * @param[in]     v    |v| <= RFE_KF2_Q31_PMAX.
 * @param[in]     c    any int32.
 * @param[in]     s    1 <= s <= 62.
 * @param[out]    out  the product.
 * @param[in,out] sat  saturation counter.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE (v or s outside their ranges; nothing written).
 */
RFE_NODISCARD rfe_status_t rfe_kf2_scale_q31(int64_t v, rfe_fix_t c, unsigned int s,
                                             int64_t *out, uint32_t *sat);

#endif /* RFE_KF2_Q31_H */
