/* Must be rejected: an int -> float conversion by a cast (soft-float helper __aeabi_i2f). */
#include "nofloat_fixture.h"

float nofloat_fixture_to_real(int32_t x)
{
    return (float)x;
}
