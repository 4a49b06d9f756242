/* Must be rejected: a libm call (sqrt), plus the int <-> double conversions around it. No
 * libc headers exist for the target, so the prototype is written out. */
#include "nofloat_fixture.h"

double sqrt(double x);

int32_t nofloat_fixture_isqrt(int32_t v)
{
    return (int32_t)sqrt((double)v);
}
