/**
 * @file test_draws.h
 * @brief Test support: the fixed-seed xorshift64 generator (shifts 13, 7, 17) that the
 *        randomised model and step-noise tests draw their cases from, and the draws of the
 *        build tree's real type built on it (uniform values, values with specials, a driving
 *        sample). One state per test program: each test seeds it first, so it runs the same
 *        cases whatever ran before. The fixed-point draws on the same generator are in
 *        test_draws_q31.h (header only: the float tests do not link the q31 library).
 *        test_rng.h is a different generator (xorshift64*) with its own state.
 */
#ifndef RFE_TEST_DRAWS_H
#define RFE_TEST_DRAWS_H

#include <stdint.h>

#include "rfe/types.h"

/** Restarts the sequence at s (a zero seed, on which xorshift stays at zero, is replaced by a
 *  fixed non-zero one). */
void draw_seed(uint64_t s);

/** The next 64 random bits (one xorshift64 step). */
uint64_t draw_u64(void);

/** Uniform in [a, b] (53 bits of one draw_u64). */
double draw_uniform(double a, double b);

/** Mostly uniform in [-typ, typ]; one in 32 each 0, +-1e30 (sign from a further draw),
 *  +infinity, NaN. */
rfe_real_t draw_special(double typ);

/** A driving sample and four friction values: every field uniform over its typical range
 *  (vx -5 .. 60 m/s, wheel speeds 0.7 .. 1.1 of vx over a 0.3 m radius, mu -0.5 .. 1.6), the
 *  rest of *u zero. With finite == 0 also vx, one wheel speed and one mu replaced by
 *  draw_special values (possibly huge, infinite or NaN). */
void draw_sample(rfe_sample_t *u, rfe_real_t mu[4], int finite);

#endif /* RFE_TEST_DRAWS_H */
