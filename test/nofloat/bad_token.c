/* Must be rejected although it generates no floating-point code: the token `double` in the
 * source (no float or double anywhere in a fixed-point translation unit). Only the source
 * scan can see it. */
#include "nofloat_fixture.h"

size_t nofloat_fixture_real_size(void)
{
    return sizeof(double);
}
