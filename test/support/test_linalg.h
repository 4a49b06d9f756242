/**
 * @file test_linalg.h
 * @brief Test support: small dense linear algebra in double, for the reference
 *        computations of the filter tests. Matrices are double[k][RFE_N_MAX] (row i,
 *        column j at [i][j]); only the leading k x k block is read or written.
 */
#ifndef RFE_TEST_LINALG_H
#define RFE_TEST_LINALG_H

#include <stddef.h>

#include "rfe/config.h"

/** Cholesky of the k x k SPD matrix A into L (lower, zeros above the diagonal); 0 on
 *  success, -1 when a pivot is not > 0. */
int chol_d(const double A[][RFE_N_MAX], size_t k, double L[][RFE_N_MAX]);

/** K (n x m) = B S^-1 for SPD S (m x m) and B (n x m): K^T = S^-1 B^T by Cholesky, forward
 *  then back substitution one row of K at a time. The Cholesky must succeed (cmocka
 *  assertion). */
void right_solve_spd(const double S[][RFE_N_MAX], size_t m, const double B[][RFE_N_MAX],
                     size_t n, double K[][RFE_N_MAX]);

#endif /* RFE_TEST_LINALG_H */
