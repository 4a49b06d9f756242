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

#endif /* RFE_TEST_COMMON_H */
