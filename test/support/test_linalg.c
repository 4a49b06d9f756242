/**
 * @file test_linalg.c
 * @brief Test support: dense linear algebra in double (see test_linalg.h).
 */
#include "test_linalg.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>

#include <cmocka.h>

#define NM ((size_t)RFE_N_MAX)

int chol_d(const double A[][RFE_N_MAX], size_t k, double L[][RFE_N_MAX])
{
    size_t i;
    size_t j;
    size_t c;
    for (i = 0u; i < k; ++i) {
        for (j = 0u; j < k; ++j) {
            L[i][j] = 0.0;
        }
    }
    for (j = 0u; j < k; ++j) {
        double d = A[j][j];
        for (c = 0u; c < j; ++c) {
            d -= L[j][c] * L[j][c];
        }
        if (!(d > 0.0)) {
            return -1;
        }
        L[j][j] = sqrt(d);
        for (i = j + 1u; i < k; ++i) {
            double s = A[i][j];
            for (c = 0u; c < j; ++c) {
                s -= L[i][c] * L[j][c];
            }
            L[i][j] = s / L[j][j];
        }
    }
    return 0;
}

void right_solve_spd(const double S[][RFE_N_MAX], size_t m, const double B[][RFE_N_MAX],
                     size_t n, double K[][RFE_N_MAX])
{
    double L[NM][NM];
    size_t i;
    size_t j;
    size_t k;
    assert_int_equal(chol_d(S, m, L), 0);
    for (i = 0u; i < n; ++i) {
        double v[NM];
        for (j = 0u; j < m; ++j) {
            double s = B[i][j];
            for (k = 0u; k < j; ++k) {
                s -= L[j][k] * v[k];
            }
            v[j] = s / L[j][j];
        }
        for (j = m; j-- > 0u;) {
            double s = v[j];
            for (k = j + 1u; k < m; ++k) {
                s -= L[k][j] * K[i][k];
            }
            K[i][j] = s / L[j][j];
        }
    }
}
