/**
 * @file test_rng.h
 * @brief Test support: the fixed-seed xorshift64* generator every randomised unit test
 *        draws from (one state per test program, so a run is deterministic), and the random
 *        matrices built from it.
 */
#ifndef RFE_TEST_RNG_H
#define RFE_TEST_RNG_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/types.h"

/** Restarts the sequence (a zero seed is replaced by a fixed non-zero one). Until the first
 *  call the generator runs from 0x243F6A8885A308D3. */
void rng_seed(uint64_t s);

/** Next value, uniform in [-1, 1) (xorshift64*, 53 bits). */
double rng_uniform(void);

/** Random lower-triangular k x k matrix M (ld k), zeros above the diagonal: diagonal in
 *  [d0, d0 + dspan], off-diagonal rng_uniform() * off; drawn row by row, left to right. */
void rand_lower(rfe_real_t *M, size_t k, double d0, double dspan, double off);

#endif /* RFE_TEST_RNG_H */
