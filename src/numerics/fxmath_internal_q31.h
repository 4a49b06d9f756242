/**
 * @file fxmath_internal_q31.h
 * @brief Private integer math of fxmath_q31.c for the fixed-point estimators: a
 *        first-quadrant atan2 and the sine of an angle in [0, pi] (the Magic Formula tyre), and
 *        built on them the atan2, sin/cos and tan of the kinematics and the observer, all for
 *        the ~2^-30 those need rather than the 2^-40 of rfe_fix_atan2 / rfe_fix_sincos /
 *        rfe_fix_tan (rfe/component/fxmath.h), whose behaviour and bounds they leave
 *        untouched. Not installed; integer operations only (no libc header beyond <stdint.h>).
 *
 * Their loops run in 32-bit arithmetic (on the Cortex-M0+ every 64-bit shift or product is a
 * libgcc call; the 40-step int64 CORDIC costs ~4 k instructions there per call):
 *  - rfe_q31_atan2_quad1: 11 CORDIC steps in vectoring mode with y carried as W = y 2^(i-1)
 *    (so the y update W <- 2 W - sigma x is exact and only x is rounded), then the ratio of
 *    the residual vector by 23 exact non-restoring division steps, whose digits are the
 *    remaining angle (atan q = q within q^3/3 once |q| <= 2^-11);
 *  - rfe_q31_sin_q55: sin(k/32 + d) = sin(k/32) cos d + cos(k/32) sin d from a 51-entry table
 *    and a fourth-order Taylor polynomial in |d| <= 2^-6 (Horner, three 64-bit products).
 * The error bounds below are derived at the definitions (fxmath_q31.c) and checked against
 * libm in test/numerics/test_fxmath_q31.c, which prints the measured worst cases (docs/FIXED_POINT.md).
 * They check no argument: the caller keeps them in their domain (outside it the value is
 * unspecified, never undefined behaviour).
 */
#ifndef RFE_FXMATH_INTERNAL_Q31_H
#define RFE_FXMATH_INTERNAL_Q31_H

#include <stdint.h>

/**
 * atan2(y, x) for 0 <= x, y <= 2^30 (both in one scale), in Q31 radians within
 * [0, round(pi/2 2^31)] = [0, 3373259426]; atan2(0, x) = 0 (also for x = 0) and
 * atan2(y > 0, 0) = 3373259426 exactly. Error <= 5.2 2^-32 = 1.211e-9 rad (0.65 LSB of Q29):
 * 2^-32 final rounding, 3.49 2^-32 from the rounding of x in the CORDIC steps, 2^-33 division
 * remainder, 2^-34.6 from atan q ~ q, 2^-36.8 table.
 */
uint32_t rfe_q31_atan2_quad1(uint32_t y, uint32_t x);

/**
 * sin(phi) in Q30, within [0, 2^30], for phi in Q55 with 0 <= phi <= round(pi 2^55) =
 * 113187804032455044. Error <= 2^-31 + 2^-32.64 = 6.15e-10 (0.66 LSB of Q30): the final
 * rounding, 2^-33 table, the rest below 2^-35.
 */
int32_t rfe_q31_sin_q55(int64_t phi);

/**
 * atan2(y, x) in Q29 radians within [-round(pi 2^29), round(pi 2^29)] for |x|, |y| <= 2^62 (one
 * scale): (0, 0) -> 0, (0, x < 0) -> +pi. Error <= 3.59e-9 rad (1.93 LSB of Q29); <= 2.27e-9
 * when |x|, |y| <= 2^30 (no scaling): the scaling to 30 bits, rfe_q31_atan2_quad1, the
 * rounding to Q29.
 */
int32_t rfe_q31_atan2_q29(int64_t y, int64_t x);

/**
 * sin and cos of an angle in Q29 (every int32, |a| <= 4 rad), in Q30 within [-2^30, 2^30].
 * Error <= 6.16e-10 each (0.66 LSB of Q30): rfe_q31_sin_q55 after an exact reduction to [0, pi].
 */
void rfe_q31_sincos_q29(int32_t a, int32_t *s, int32_t *c);

/**
 * tan(a) in Q26 for |a| <= 1.5 rad (Q29, RFE_FIX_TAN_LIMIT_Q29), within +-14.11. Error
 * <= 2^-27 + 6.16e-10 (1 + |tan a|) / (cos a - 6.16e-10): 0.54 LSB at 0, 2.15 LSB at 1.4 rad,
 * 9.3 LSB at 1.5 rad (where half a step of the Q29 input moves tan by 12.5 LSB).
 */
int32_t rfe_q31_tan_q29(int32_t a);

#endif /* RFE_FXMATH_INTERNAL_Q31_H */
