/* Must be rejected: a double division (soft-float helper __aeabi_ddiv). */
#include "nofloat_fixture.h"

double nofloat_fixture_ratio(double num, double den)
{
    return num / den;
}
