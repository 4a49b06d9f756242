/**
 * @file splitmix64.h
 * @brief Test support: splitmix64 (Steele, Lea, Flood 2014), the full-period 64-bit sequence
 *        the w16 tests (test/numerics/w16/) draw their integers from. Header-only, one state per
 *        test program: each program includes it once and seeds mix_state before a sweep, so a
 *        run is deterministic.
 */
#ifndef RFE_TEST_SPLITMIX64_H
#define RFE_TEST_SPLITMIX64_H

#include <stdint.h>

static uint64_t mix_state;

static uint64_t rand_u64(void)
{
    uint64_t z = (mix_state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

#endif /* RFE_TEST_SPLITMIX64_H */
