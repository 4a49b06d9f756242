/* Structural self-test fixture: a stack frame sized at run time without a VLA (alloca). */
#include <stddef.h>

double fixture_sum(const double *v, size_t n);

double fixture_sum(const double *v, size_t n)
{
    double *tmp = (double *)__builtin_alloca(n * sizeof(double));
    double acc = 0.0;
    size_t i;
    for (i = 0u; i < n; ++i) {
        tmp[i] = v[i];
        acc += tmp[i];
    }
    return acc;
}
