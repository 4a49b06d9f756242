/**
 * @file fixed_conv.h
 * @brief HOST ONLY: conversions between double and the Q formats of rfe/fixed.h, for tests,
 *        tools and the host side of back-to-back comparisons.
 *
 * Never include this header from a library source (src/<module>_q31.c): the fixed-point library
 * is built for targets without a floating-point unit and must not pull in any soft-float
 * helper or libm symbol. Link with -lm.
 */
#ifndef RFE_FIXED_CONV_H
#define RFE_FIXED_CONV_H

#include <math.h>
#include <stdint.h>

#include "numerics/round_half_up.h"
#include "rfe/fixed.h"

/** x * 2^q rounded to nearest (ties up, like the library's shifts), saturating to
 *  [RFE_FIX_MIN, RFE_FIX_MAX] with a count in *sat; NaN gives 0 and counts. 0 <= q <= 62. */
static inline int32_t rfe_fix_from_double(double x, unsigned int q, uint32_t *sat)
{
    const double y = ldexp(x, (int)q);
    int32_t r;
    if (isnan(y)) {
        rfe_fix_count_sat(sat);
        r = 0;
    } else if (y >= (double)RFE_FIX_MAX + 0.5) {
        rfe_fix_count_sat(sat);
        r = RFE_FIX_MAX;
    } else if (y < (double)RFE_FIX_MIN - 0.5) {
        rfe_fix_count_sat(sat);
        r = RFE_FIX_MIN;
    } else {
        r = (int32_t)rfe_round_half_up(y);
    }
    return r;
}

/** v / 2^q as a double (exact for every int32 and q). */
static inline double rfe_fix_to_double(int32_t v, unsigned int q)
{
    return ldexp((double)v, -(int)q);
}

/** v / 2^q for an int64 intermediate (exact when |v| < 2^53). */
static inline double rfe_fix64_to_double(int64_t v, unsigned int q)
{
    return ldexp((double)v, -(int)q);
}

#endif /* RFE_FIXED_CONV_H */
