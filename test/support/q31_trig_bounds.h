/**
 * @file q31_trig_bounds.h
 * @brief The stated worst-case errors of the fixed-point angle functions the estimators use
 *        (src/numerics/fxmath_internal_q31.h; derived at their definitions in fxmath_q31.c and
 *        checked against libm by test/numerics/test_fxmath_q31.c), for the tests that bound a
 *        fixed-point model against its double twin. One place, so a change of a primitive
 *        changes every bound built on it.
 */
#ifndef RFE_TEST_Q31_TRIG_BOUNDS_H
#define RFE_TEST_Q31_TRIG_BOUNDS_H

#include <math.h>

/** rfe_q31_sincos_q29: sin and cos, each [1]. */
#define Q31B_TRIG 6.16e-10
/** rfe_q31_atan2_q29 with |x|, |y| <= 2^30 [rad]: rfe_q31_atan2_quad1 (1.211e-9), the rounding
 *  to Q29 (2^-30) and pi in Q31 (1.3e-10); the scaling of larger inputs to 30 bits
 *  ((sqrt 2 / 2) 2^-29) is the caller's term. */
#define Q31B_ATAN2 2.27e-9

/** rfe_q31_tan_q29 at the angle a (|a| <= 1.5 rad) [1]: the Q26 rounding and the quotient of
 *  a sine and a cosine each off by Q31B_TRIG; increasing in |a|, so a bound at the largest
 *  angle a caller can reach holds for all smaller ones. */
static inline double q31b_tan(double a)
{
    const double m = fabs(a);
    return ldexp(1.0, -27) + Q31B_TRIG * (1.0 + tan(m)) / (cos(m) - Q31B_TRIG);
}

#endif /* RFE_TEST_Q31_TRIG_BOUNDS_H */
