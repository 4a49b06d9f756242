/**
 * @file fxmath.h
 * @brief Integer math of the fixed-point variant: square roots, vector norm, division,
 *        atan2, sin/cos, tan (docs/FIXED_POINT.md). Integer operations only.
 *
 * Conventions of rfe/fixed.h: int32 values in a stated Q format, int64 intermediates,
 * symmetric saturation to +-INT32_MAX counted in `*sat`. Every function validates its
 * arguments first: a NULL pointer gives RFE_ERR_NULL and an argument outside the documented
 * domain RFE_ERR_RANGE, and then no output (nor `*sat`) is written. Saturation is not an
 * error: the call returns RFE_OK with the saturated value and one count added to `*sat`.
 *
 * The stated error bounds are properties of the algorithms (derived at each function) and
 * are checked against libm in test/numerics/test_fxmath_q31.c, which also prints the measured
 * worst cases quoted in docs/FIXED_POINT.md. These functions have no real-number twin, so
 * their names carry the `rfe_fix_` prefix instead of a `_q31` suffix.
 */
#ifndef RFE_FXMATH_H
#define RFE_FXMATH_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/common.h"
#include "rfe/fixed.h"

/** |angle| limit of rfe_fix_tan: 1.5 rad in Q29 (the tyre's alpha_max must be < 1.5). */
#define RFE_FIX_TAN_LIMIT_Q29 ((rfe_fix_t)805306368)

/**
 * floor(sqrt(x)), exact for every uint64 x (digit-by-digit, 32 steps, no multiplication).
 * @return RFE_OK; RFE_ERR_NULL if root is NULL.
 */
RFE_NODISCARD rfe_status_t rfe_fix_isqrt64(uint64_t x, uint32_t *root);

/**
 * Square root with a change of format: x in Q(q_in), x >= 0, the root in Q(q_out),
 * i.e. round(sqrt(x * 2^(2 q_out - q_in))), exactly rounded (error <= 0.5 LSB of Q(q_out);
 * ties, possible only when 2 q_out < q_in, away from zero). Same format in and out
 * (q_in = q_out = q) never saturates; a large 2 q_out - q_in may, to INT32_MAX (counted).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE if x < 0 or q_in or q_out > 31.
 */
RFE_NODISCARD rfe_status_t rfe_fix_sqrt(rfe_fix_t x, unsigned int q_in, unsigned int q_out,
                                        rfe_fix_t *root, uint32_t *sat);

/**
 * Euclidean norm of v[0 .. n) in the Q format of v: round(sqrt(sum v_i^2)), exactly rounded
 * (error <= 0.5 LSB; no tie is possible). The sum of squares is exact in uint64 (no
 * pre-scaling, no precision lost for small vectors); the norm saturates to INT32_MAX
 * (counted) only when it rounds above INT32_MAX. n = 0 gives 0. Any n; |v_i| = 2^31 allowed.
 * @return RFE_OK; RFE_ERR_NULL if v, norm or sat is NULL.
 */
RFE_NODISCARD rfe_status_t rfe_fix_norm(const rfe_fix_t *v, size_t n, rfe_fix_t *norm,
                                        uint32_t *sat);

/**
 * Division q = round(a * 2^shift / b), exactly rounded (error <= 0.5 LSB; ties away from
 * zero). For a in Q(qa), b in Q(qb) and the quotient wanted in Q(qq): shift = qq - qa + qb.
 * Saturates to +-INT32_MAX (counted) when the quotient rounds beyond the int32 range.
 * The reciprocal of b in Q(qb) into Q(qq) is rfe_fix_div(1, b, qq + qb, ...).
 * @return RFE_OK; RFE_ERR_NULL if q or sat is NULL; RFE_ERR_RANGE if b == 0 or shift is
 *         outside [-62, 62].
 */
RFE_NODISCARD rfe_status_t rfe_fix_div(rfe_fix_t a, rfe_fix_t b, int shift, rfe_fix_t *q,
                                       uint32_t *sat);

/**
 * atan2(y, x) [rad] in Q29 (RFE_FIX_Q_ANGLE), in [-pi, pi]; y and x in any common Q format.
 * Every int32 pair is in the domain: atan2(0, 0) = 0, atan2(0, x < 0) = +pi (no signed
 * zero), exactly odd in y. Integer CORDIC (vectoring mode, 40 iterations) in int64 after an
 * exact power-of-two normalisation of (x, y), so small inputs lose nothing.
 * Error <= 0.5 LSB (final rounding) + 2e-12 rad (CORDIC residual atan(2^-39)) + 1e-15 rad
 * (int64 truncation), stated as 9.4e-10 rad (0.505 LSB of Q29).
 * @return RFE_OK; RFE_ERR_NULL if angle is NULL.
 */
RFE_NODISCARD rfe_status_t rfe_fix_atan2(rfe_fix_t y, rfe_fix_t x, rfe_fix_t *angle);

/**
 * sin and cos of angle [rad, Q29]; every int32 angle (|angle| <= 4 rad) is in the domain.
 * Results in Q30 (RFE_FIX_Q_TRIG), within [-2^30, 2^30]; sin is exactly odd, cos exactly
 * even. Integer CORDIC (rotation mode, 40 iterations, int64 Q61) after reduction to
 * [-pi/2, pi/2] with a Q61 pi. Error <= 0.5 LSB (final rounding) + 2e-12 (residual angle)
 * + 1e-15, stated as 4.7e-10 absolute (0.505 LSB of Q30).
 * @return RFE_OK; RFE_ERR_NULL if s or c is NULL.
 */
RFE_NODISCARD rfe_status_t rfe_fix_sincos(rfe_fix_t angle, rfe_fix_t *s, rfe_fix_t *c);

/**
 * tan(angle), angle [rad] in Q29 with |angle| <= RFE_FIX_TAN_LIMIT_Q29 (1.5 rad, tan = 14.1),
 * result in Q26 (RFE_FIX_Q_TAN, range +-32), exactly odd. The unrounded Q61 sine and cosine
 * of the CORDIC are divided with exact rounding. Error <= 0.5 LSB + 2e-12 * (1 + tan^2),
 * stated as 7.9e-9 absolute (0.53 LSB of Q26) over the whole domain.
 * @return RFE_OK; RFE_ERR_NULL if t is NULL; RFE_ERR_RANGE if |angle| > 1.5 rad.
 */
RFE_NODISCARD rfe_status_t rfe_fix_tan(rfe_fix_t angle, rfe_fix_t *t);

#endif /* RFE_FXMATH_H */
