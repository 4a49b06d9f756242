/**
 * @file filter_fixtures.h
 * @brief Test support shared by the SCKF and CKF tests: the cubature points a mocked model
 *        callback must be called with (a cmocka parameter check), and models whose finite
 *        outputs overflow the filter's moments.
 */
#ifndef RFE_TEST_FILTER_FIXTURES_H
#define RFE_TEST_FILTER_FIXTURES_H

#include <float.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "rfe/config.h"
#include "rfe/types.h"

/** Largest finite rfe_real_t. */
#if defined(RFE_REAL_DOUBLE)
#define REAL_BIG ((rfe_real_t)DBL_MAX)
#else
#define REAL_BIG ((rfe_real_t)FLT_MAX)
#endif

/** One expected cubature point. */
typedef struct {
    size_t n;
    double tol;               /**< allowed |error| per unit of scale */
    double v[RFE_N_MAX];      /**< expected point */
    double scale[RFE_N_MAX];  /**< |x_i| + sqrt(n) |M_ij|: size of the terms that were rounded */
} exp_point_t;

/** The 2n points of the step being checked, in the order the filter must visit them. */
extern exp_point_t expected_pts[2u * RFE_N_MAX];

/** Fills expected_pts[0 .. 2n) with X_j = x + sqrt(n) M e_j (j = 1..n), then
 *  X_{n+j} = x - sqrt(n) M e_j, for the square-root factor M (n x n, ld RFE_N_MAX) of the
 *  covariance; each coordinate may be off by tol * scale. */
void fill_expected_points(const rfe_real_t *x, const rfe_real_t *M, size_t n, double tol);

/** cmocka parameter check (expect_check): the point the filter passed (value) equals the
 *  expected point check_data (an exp_point_t *). */
int check_point(const LargestIntegralType value, const LargestIntegralType check_data);

/** Process / measurement callbacks mapping every point to 0.9 REAL_BIG: finite outputs
 *  whose mean and second moment overflow. */
rfe_status_t huge_process(void *ctx, const rfe_real_t *x, rfe_real_t *x_next, size_t n);
rfe_status_t huge_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n, size_t m);

#endif /* RFE_TEST_FILTER_FIXTURES_H */
