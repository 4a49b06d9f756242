/**
 * @file test_rng.c
 * @brief Test support: deterministic random numbers and matrices (see test_rng.h).
 */
#include "test_rng.h"

static uint64_t rng_state = 0x243F6A8885A308D3ull;

void rng_seed(uint64_t s) { rng_state = (s != 0u) ? s : 0x9E3779B97F4A7C15ull; }

double rng_uniform(void)
{
    uint64_t x = rng_state;
    x ^= x >> 12;
    x ^= x << 25;
    x ^= x >> 27;
    rng_state = x;
    return ((double)((x * 0x2545F4914F6CDD1Dull) >> 11) * (2.0 / 9007199254740992.0)) - 1.0;
}

void rand_lower(rfe_real_t *M, size_t k, double d0, double dspan, double off)
{
    size_t i;
    size_t j;
    for (i = 0u; i < k; ++i) {
        for (j = 0u; j < k; ++j) {
            double v = 0.0;
            if (j < i) {
                v = off * rng_uniform();
            } else if (j == i) {
                v = d0 + (0.5 * dspan * (rng_uniform() + 1.0));
            }
            M[(i * k) + j] = (rfe_real_t)v;
        }
    }
}
