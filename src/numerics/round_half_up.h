/**
 * @file round_half_up.h
 * @brief The one rounding rule from double to an integer of a Q format: to nearest, ties
 *        up (towards +inf), the same rule as the fixed-point library's rounding shifts.
 *
 * Used by the float library's parameter conversion (params_conv_flt.c) and the host's
 * sample and reference conversions (src/host/fixed_conv.h), so a value converted on
 * either side is the same integer. Double arithmetic: never included by a *_q31 file.
 */
#ifndef RFE_ROUND_HALF_UP_H
#define RFE_ROUND_HALF_UP_H

#include <math.h>

/** floor(y + 1/2) for a finite y, without the double rounding of y + 0.5 (y - floor(y) is
 *  exact, so 0.49999999999999994 stays 0). */
static inline double rfe_round_half_up(double y)
{
    double f = floor(y);
    if ((y - f) >= 0.5) {
        f += 1.0;
    }
    return f;
}

#endif /* RFE_ROUND_HALF_UP_H */
