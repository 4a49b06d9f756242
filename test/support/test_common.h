/**
 * @file test_common.h
 * @brief Small helpers shared by the floating-point library tests.
 */
#ifndef RFE_TEST_COMMON_H
#define RFE_TEST_COMMON_H

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include <cmocka.h>

#include "rfe/types.h"

/** Where the shared test vectors live (copied from shared/vectors by `make vectors`). */
#define TEST_VECTORS_DIR "test/vectors"

/** |got - want| <= abs_tol + rel_tol * |want|, with a message naming what was compared. */
#define assert_close(got, want, abs_tol, rel_tol, what)                                        \
    do {                                                                                       \
        const double g_ = (double)(got);                                                       \
        const double w_ = (double)(want);                                                      \
        const double lim_ = (abs_tol) + (rel_tol)*fabs(w_);                                    \
        if (!(fabs(g_ - w_) <= lim_)) {                                                        \
            fail_msg("%s: got %.17g want %.17g (|diff| %.3g > %.3g)", (what), g_, w_,          \
                     fabs(g_ - w_), lim_);                                                     \
        }                                                                                      \
    } while (0)

/* Fails with a readable message when !(value <= tol). Build with -DTOL_MEASURE to print
 * every measured value relative to its tolerance instead (to re-derive the "seen" figures
 * quoted next to the tolerances: pipe through `sort -t'|' -k1,1 -k2,2g` and take the
 * maximum per label). */
#if defined(TOL_MEASURE)
#define ASSERT_LE(value, tol, what)                                                       \
    do {                                                                                   \
        const double t_ = (double)(tol);                                                   \
        fprintf(stderr, "%s|%.3e\n", (what), (double)(value) / ((t_ > 0.0) ? t_ : 1.0));   \
    } while (0)
#else
#define ASSERT_LE(value, tol, what)                                                       \
    do {                                                                                   \
        const double v_ = (double)(value);                                                 \
        const double t_ = (double)(tol);                                                   \
        if (!(v_ <= t_)) {                                                                 \
            print_error("%s: %.6e > tolerance %.6e\n", (what), v_, t_);                    \
            fail();                                                                        \
        }                                                                                  \
    } while (0)
#endif

#endif /* RFE_TEST_COMMON_H */
