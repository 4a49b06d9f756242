/* Structural self-test fixture: a variable-length array. */
#include <stddef.h>

double fixture_sum(const double *v, size_t n);

double fixture_sum(const double *v, size_t n)
{
    double tmp[n];
    double acc = 0.0;
    size_t i;
    for (i = 0u; i < n; ++i) {
        tmp[i] = v[i];
        acc += tmp[i];
    }
    return acc;
}
