/* Must be rejected: float arithmetic (soft-float helpers __aeabi_fmul, __aeabi_fadd) and the
 * token `float` in the source. */
#include "nofloat_fixture.h"

float nofloat_fixture_scale(float a, float b)
{
    return a * b + 1.0f;
}
