/* Must be rejected: including <math.h>. The Cortex-M0+ build is freestanding (-nostdinc:
 * only GCC's own headers, even where newlib is installed), so this does not compile. */
#include <math.h>

#include "nofloat_fixture.h"

int32_t nofloat_fixture_floor(int32_t x)
{
    return (int32_t)floor(x);
}
