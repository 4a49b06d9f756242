/**
 * @file test_draws_q31.h
 * @brief Test support: the fixed-point draws of the randomised model and step-noise tests, on
 *        the generator of test_draws.h (same state, same stream). Header only, static inline,
 *        types and fields only and no q31 library call: the float tests, which do not link
 *        the q31 library, compile the test support too.
 */
#ifndef RFE_TEST_DRAWS_Q31_H
#define RFE_TEST_DRAWS_Q31_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "rfe/component/tyre_q31.h"
#include "rfe/params_q31.h"
#include "test_draws.h"

/** Mostly within +-typical, one in 16 each any int32, an int32 extreme or 0. */
static inline int32_t draw_special_q31(int32_t typical)
{
    const uint64_t r = draw_u64();
    const unsigned int k = (unsigned int)(r % 16u);
    if (k == 0u) {
        return (int32_t)(uint32_t)(draw_u64() >> 32);
    }
    if (k == 1u) {
        return ((r & 16u) != 0u) ? INT32_MAX : INT32_MIN;
    }
    if (k == 2u) {
        return 0;
    }
    return (int32_t)((int64_t)(draw_u64() % (2u * (uint64_t)typical + 1u)) - typical);
}

/** A sample and four friction values, every field draw_special_q31 around its typical range
 *  (so also the int32 extremes); every fourth case (n % 4 == 0) rolling wheels instead:
 *  vx 0 .. 40 m/s, omega = vx / R plus a little slip, mu 0 .. 2. Uses p's wheel radius. */
static inline void draw_sample_q31(const rfe_params_q31_t *p, rfe_sample_q31_t *u, rfe_fix_t mu[4],
                                   int n)
{
    size_t i;
    memset(u, 0, sizeof(*u));
    u->delta = draw_special_q31(1 << 29);
    u->vx = draw_special_q31(40 << 23);
    u->vy = draw_special_q31(5 << 23);
    u->yaw_rate = draw_special_q31(1 << 27);
    u->yaw_acc = draw_special_q31(1 << 24);
    u->ax = draw_special_q31(10 << 24);
    u->ay = draw_special_q31(10 << 24);
    for (i = 0; i < 4; ++i) {
        u->omega[i] = draw_special_q31(100 << 22);
        mu[i] = draw_special_q31(1 << 30);
    }
    if ((n % 4) == 0) {
        /* rolling wheels: omega = vx / R plus a little slip, realistic mu */
        u->vx = (int32_t)(draw_u64() % (40u << 23));
        u->delta = (int32_t)(draw_u64() % (1u << 28)) - (1 << 27);
        for (i = 0; i < 4; ++i) {
            /* in int64, saturated: draw_special_q31() may return an int32 extreme */
            const int64_t w = ((((int64_t)u->vx) << 6) / (p->vehicle.R >> 20)) +
                              (int64_t)draw_special_q31(1 << 20);
            u->omega[i] = (int32_t)((w > INT32_MAX) ? INT32_MAX : ((w < INT32_MIN) ? INT32_MIN : w));
            mu[i] = (int32_t)(draw_u64() % (1u << 30));
        }
    }
}

/** Tyre parameters varied around the preset's (stiffness 0 .. 60, eps 0 .. 0.25, the Magic
 *  Formula shape factors anywhere in 1 < C < 2, -4 <= E < 1). */
static inline void draw_tyre_q31(rfe_tyre_params_q31_t *tp)
{
    tp->cx = (int32_t)(draw_u64() % (60u << 24));
    tp->cy = (int32_t)(draw_u64() % (60u << 24));
    tp->eps = ((draw_u64() % 4u) == 0u) ? 0 : (int32_t)(draw_u64() % (1u << 30));
    tp->shape_Cx = (1 << 24) + 1 + (int32_t)(draw_u64() % ((1u << 24) - 1u));
    tp->shape_Cy = (1 << 24) + 1 + (int32_t)(draw_u64() % ((1u << 24) - 1u));
    tp->shape_Ex = ((draw_u64() % 2u) == 0u) ? 0 : (int32_t)(draw_u64() % (5u << 24)) - (4 << 24);
    tp->shape_Ey = ((draw_u64() % 2u) == 0u) ? 0 : (int32_t)(draw_u64() % (5u << 24)) - (4 << 24);
}

#endif /* RFE_TEST_DRAWS_Q31_H */
