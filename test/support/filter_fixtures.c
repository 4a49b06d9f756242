/**
 * @file filter_fixtures.c
 * @brief Test support: cubature-point expectations and overflowing models
 *        (see filter_fixtures.h).
 */
#include "filter_fixtures.h"

#include <math.h>
#include <stdint.h>

#define NM ((size_t)RFE_N_MAX)

exp_point_t expected_pts[2u * NM];

void fill_expected_points(const rfe_real_t *x, const rfe_real_t *M, size_t n, double tol)
{
    const double r = sqrt((double)n);
    size_t k;
    size_t i;
    for (k = 0u; k < (2u * n); ++k) {
        const size_t j = k % n;
        const double sgn = (k < n) ? 1.0 : -1.0;
        expected_pts[k].n = n;
        expected_pts[k].tol = tol;
        for (i = 0u; i < n; ++i) {
            const double d = r * (double)M[(i * NM) + j];
            expected_pts[k].v[i] = (double)x[i] + (sgn * d);
            expected_pts[k].scale[i] = fabs((double)x[i]) + fabs(d) + DBL_MIN;
        }
    }
}

int check_point(const LargestIntegralType value, const LargestIntegralType check_data)
{
    const rfe_real_t *x = (const rfe_real_t *)(uintptr_t)value;
    const exp_point_t *e = (const exp_point_t *)(uintptr_t)check_data;
    size_t i;
    for (i = 0u; i < e->n; ++i) {
        if (!(fabs((double)x[i] - e->v[i]) <= (e->tol * e->scale[i]))) {
            print_error("cubature point %ld, element %zu: got %.17g, expected %.17g\n",
                        (long)(e - expected_pts), i, (double)x[i], e->v[i]);
            return 0;
        }
    }
    return 1;
}

rfe_status_t huge_process(void *ctx, const rfe_real_t *x, rfe_real_t *x_next, size_t n)
{
    size_t i;
    (void)ctx;
    (void)x;
    for (i = 0u; i < n; ++i) {
        x_next[i] = (rfe_real_t)0.9 * REAL_BIG;
    }
    return RFE_OK;
}

rfe_status_t huge_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n, size_t m)
{
    size_t i;
    (void)ctx;
    (void)x;
    (void)n;
    for (i = 0u; i < m; ++i) {
        z[i] = (rfe_real_t)0.9 * REAL_BIG;
    }
    return RFE_OK;
}
