/* Must be rejected although neither `float` nor `double` appears: the floating constant 0.5
 * makes this double arithmetic (__aeabi_i2d, __aeabi_dmul, __aeabi_d2iz). Only the symbol
 * check can see it. */
#include "nofloat_fixture.h"

int32_t nofloat_fixture_half(int32_t x)
{
    return (int32_t)(x * 0.5);
}
