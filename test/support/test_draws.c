/**
 * @file test_draws.c
 * @brief Test support: the xorshift64 generator and the real-typed draws (see test_draws.h).
 *        Compiled per build tree, so rfe_real_t is that tree's real type.
 */
#include "test_draws.h"

#include <math.h>
#include <string.h>

static uint64_t draw_state = 0x9E3779B97F4A7C15ull;

void draw_seed(uint64_t s) { draw_state = (s != 0u) ? s : 0x9E3779B97F4A7C15ull; }

uint64_t draw_u64(void)
{
    draw_state ^= draw_state << 13;
    draw_state ^= draw_state >> 7;
    draw_state ^= draw_state << 17;
    return draw_state;
}

double draw_uniform(double a, double b)
{
    return a + (b - a) * ((double)(draw_u64() >> 11) / 9007199254740992.0);
}

rfe_real_t draw_special(double typ)
{
    const unsigned int k = (unsigned int)(draw_u64() % 32u);
    if (k == 0u) {
        return (rfe_real_t)0.0;
    }
    if (k == 1u) {
        return (rfe_real_t)(((draw_u64() & 1u) != 0u) ? 1e30 : -1e30);
    }
    if (k == 2u) {
        return (rfe_real_t)INFINITY;
    }
    if (k == 3u) {
        return (rfe_real_t)NAN;
    }
    return (rfe_real_t)draw_uniform(-typ, typ);
}

void draw_sample(rfe_sample_t *u, rfe_real_t mu[4], int finite)
{
    size_t i;
    memset(u, 0, sizeof(*u));
    u->delta = (rfe_real_t)draw_uniform(-0.5, 0.5);
    u->vx = (rfe_real_t)draw_uniform(-5.0, 60.0);
    u->vy = (rfe_real_t)draw_uniform(-3.0, 3.0);
    u->yaw_rate = (rfe_real_t)draw_uniform(-1.0, 1.0);
    u->yaw_acc = (rfe_real_t)draw_uniform(-3.0, 3.0);
    u->ax = (rfe_real_t)draw_uniform(-12.0, 12.0);
    u->ay = (rfe_real_t)draw_uniform(-12.0, 12.0);
    for (i = 0; i < 4; ++i) {
        u->omega[i] = (rfe_real_t)((double)u->vx * draw_uniform(0.7, 1.1) / 0.3);
        mu[i] = (rfe_real_t)draw_uniform(-0.5, 1.6);
    }
    if (finite == 0) {
        u->vx = draw_special(3e38);
        u->omega[draw_u64() % 4u] = draw_special(1e3);
        mu[draw_u64() % 4u] = draw_special(2.0);
    }
}
