/* Must be rejected: including <math.h>. The Cortex-M0+ build is freestanding (no libc
 * headers), so this does not compile; were newlib's headers installed, the floor() call
 * would be caught as a libm function instead. */
#include <math.h>

#include "nofloat_fixture.h"

int32_t nofloat_fixture_floor(int32_t x)
{
    return (int32_t)floor(x);
}
