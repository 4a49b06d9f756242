/**
 * @file fuzz_real.h
 * @brief The float/double harnesses' decoded double -> rfe_real_t, as a sensor driver would
 *        convert: out of range becomes +-Inf (a plain cast would be undefined behaviour);
 *        and the two checks every harness's invariants use.
 *        The build's number type decides: float, or double with -DRFE_REAL_DOUBLE.
 */
#ifndef RFE_FUZZ_REAL_H
#define RFE_FUZZ_REAL_H

#include <float.h>
#include <math.h>

#include "rfe/types.h"

#if defined(RFE_REAL_DOUBLE)
#define FZ_REAL_MAX DBL_MAX
#define FZ_BUILD "double"
#else
#define FZ_REAL_MAX FLT_MAX
#define FZ_BUILD "float"
#endif

static inline rfe_real_t fz_to_real(double d)
{
    if (isnan(d)) {
        return (rfe_real_t)NAN;
    }
    if (d > (double)FZ_REAL_MAX) {
        return (rfe_real_t)INFINITY;
    }
    if (d < -(double)FZ_REAL_MAX) {
        return (rfe_real_t)-INFINITY;
    }
    return (rfe_real_t)d;
}

/* 1 when x is finite (the invariants' check of every estimate). */
static inline int finite(rfe_real_t x)
{
    return isfinite((double)x);
}

/* |x| beyond the limit @p lim of config.h, the limit rounded to the build's type. */
static inline int beyond(rfe_real_t x, double lim)
{
    const rfe_real_t l = (rfe_real_t)lim;
    return (x > l) || (x < -l);
}

#endif /* RFE_FUZZ_REAL_H */
