/**
 * @file test_guard.h
 * @brief Test support for the matrix-kernel tests (QR, Cholesky): buffers are pre-set to a
 *        guard value so that writes outside the documented output are caught, and padding
 *        columns between the used width and the leading dimension carry their own marker.
 */
#ifndef RFE_TEST_GUARD_H
#define RFE_TEST_GUARD_H

#include <stddef.h>

#include "rfe/types.h"

#define GUARD_N 8u                         /* guard words after every output buffer */
#define GUARD_VAL ((rfe_real_t)-7777.25)   /* exactly representable in both precisions */
#define PAD_VAL ((rfe_real_t)4321.5)       /* padding columns between the width and ld */

/* Element (i, j) of the row-major matrix M with leading dimension ld. */
#define AT(M, ld, i, j) ((M)[((i) * (ld)) + (j)])

/* Sets buf[0 .. count) to GUARD_VAL. */
static inline void guard_fill(rfe_real_t *buf, size_t count)
{
    size_t i;
    for (i = 0u; i < count; ++i) {
        buf[i] = GUARD_VAL;
    }
}

#endif /* RFE_TEST_GUARD_H */
