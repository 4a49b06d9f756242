/* Must be rejected: a libc call (rand) that the libgcc-only link cannot resolve. */
#include "nofloat_fixture.h"

int rand(void);

int32_t nofloat_fixture_noise(void)
{
    return (int32_t)rand();
}
