/**
 * @file philox_flt.c
 * @brief Philox4x64-10 and the uniforms and normals of its words (docs/TYRE_ID.md §6).
 */
#include "rfe/component/philox.h"

#include "numerics/internal.h"

/* The Philox4x64 round multipliers and the Weyl increments of the key (Salmon et al.). */
#define PHILOX_M0 0xD2E7470EE14C6C93u
#define PHILOX_M1 0xCA5A826395121157u
#define PHILOX_W0 0x9E3779B97F4A7C15u
#define PHILOX_W1 0xBB67AE8584CAA73Bu
#define PHILOX_ROUNDS 10u
#define LOW32 0xFFFFFFFFu

/* The double nearest 2 pi (TYRE_ID.md §6.2), in the build's type. */
#define TWO_PI_R RFE_R(6.283185307179586)

#if defined(RFE_REAL_DOUBLE)
#define UNIFORM_SHIFT 12u              /* the top 52 bits */
#define UNIFORM_SCALE 2.220446049250313e-16 /* 2^-52 */
#else
#define UNIFORM_SHIFT 41u              /* the top 23 bits */
#define UNIFORM_SCALE 1.1920928955078125e-07 /* 2^-23 */
#endif

/* hi:lo = a b, the exact 128-bit product, schoolbook on 32-bit limbs with the carries
 * folded in as it goes: each partial sum is x y + c (+ d) with x, y, c, d < 2^32, at most
 * (2^32 - 1)^2 + 2 (2^32 - 1) = 2^64 - 1, so none overflows 64 bits. Four 32 x 32 -> 64 bit
 * multiplies, each with its additions a multiply-accumulate on a 32-bit core (UMAAL on the
 * Cortex-M4). a b = t0_lo + 2^32 t2_lo + 2^64 (a1 b1 + t1_hi + t2_hi). */
static void mul128(uint64_t a, uint64_t b, uint64_t *hi, uint64_t *lo)
{
    const uint32_t a0 = (uint32_t)(a & LOW32);
    const uint32_t a1 = (uint32_t)(a >> 32u);
    const uint32_t b0 = (uint32_t)(b & LOW32);
    const uint32_t b1 = (uint32_t)(b >> 32u);
    const uint64_t t0 = (uint64_t)a0 * (uint64_t)b0;
    const uint32_t c0 = (uint32_t)(t0 >> 32u);
    const uint64_t t1 = ((uint64_t)a1 * (uint64_t)b0) + (uint64_t)c0;
    const uint32_t t1_lo = (uint32_t)(t1 & LOW32);
    const uint32_t t1_hi = (uint32_t)(t1 >> 32u);
    const uint64_t t2 = ((uint64_t)a0 * (uint64_t)b1) + (uint64_t)t1_lo;
    const uint32_t t2_hi = (uint32_t)(t2 >> 32u);
    *lo = (t2 << 32u) | (t0 & LOW32);
    *hi = (((uint64_t)a1 * (uint64_t)b1) + (uint64_t)t1_hi) + (uint64_t)t2_hi;
}

/* One block (the public entry checks the pointers). */
static void block(const uint64_t ctr[RFE_PHILOX_WORDS], const uint64_t key[2],
                  uint64_t out[RFE_PHILOX_WORDS])
{
    uint64_t c0 = ctr[0];
    uint64_t c1 = ctr[1];
    uint64_t c2 = ctr[2];
    uint64_t c3 = ctr[3];
    uint64_t k0 = key[0];
    uint64_t k1 = key[1];
    uint32_t r;
    /* round: (hi(M1 c2) ^ c1 ^ k0, lo(M1 c2), hi(M0 c0) ^ c3 ^ k1, lo(M0 c0)); the key
     * grows by the Weyl increments before every round but the first */
    for (r = 0u; r < PHILOX_ROUNDS; ++r) {
        uint64_t h0;
        uint64_t l0;
        uint64_t h1;
        uint64_t l1;
        if (r > 0u) {
            k0 += PHILOX_W0;
            k1 += PHILOX_W1;
        }
        mul128(PHILOX_M0, c0, &h0, &l0);
        mul128(PHILOX_M1, c2, &h1, &l1);
        c0 = (h1 ^ c1) ^ k0;
        c1 = l1;
        c2 = (h0 ^ c3) ^ k1;
        c3 = l0;
    }
    out[0] = c0;
    out[1] = c1;
    out[2] = c2;
    out[3] = c3;
}

rfe_status_t rfe_philox_block(const uint64_t ctr[RFE_PHILOX_WORDS], const uint64_t key[2],
                              uint64_t out[RFE_PHILOX_WORDS])
{
    if ((ctr == NULL) || (key == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    block(ctr, key, out);
    return RFE_OK;
}

rfe_status_t rfe_philox_stream(rfe_philox_t *s, uint64_t seed, uint64_t c1, uint64_t c2)
{
    if (s == NULL) {
        return RFE_ERR_NULL;
    }
    s->key[0] = seed;
    s->key[1] = 0u;
    s->c1 = c1;
    s->c2 = c2;
    s->block = 0u;
    s->w[0] = 0u;
    s->w[1] = 0u;
    s->w[2] = 0u;
    s->w[3] = 0u;
    s->cached = 0u;
    return RFE_OK;
}

rfe_status_t rfe_philox_word(rfe_philox_t *s, uint64_t n, uint64_t *w)
{
    const uint64_t j = n / (uint64_t)RFE_PHILOX_WORDS;
    if ((s == NULL) || (w == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((s->cached == 0u) || (s->block != j)) {
        const uint64_t ctr[RFE_PHILOX_WORDS] = {j, s->c1, s->c2, 0u};
        block(ctr, s->key, s->w);
        s->block = j;
        s->cached = 1u;
    }
    *w = s->w[n % (uint64_t)RFE_PHILOX_WORDS];
    return RFE_OK;
}

/* u = ((w >> shift) + 0.5) 2^-bits: the top bits, centred, exact in the type. */
static rfe_real_t uniform_of(uint64_t w)
{
    const uint64_t top = w >> UNIFORM_SHIFT;
    return ((rfe_real_t)top + RFE_R(0.5)) * RFE_R(UNIFORM_SCALE);
}

rfe_status_t rfe_philox_uniform(rfe_philox_t *s, uint64_t n, rfe_real_t *u)
{
    uint64_t w = 0u;
    rfe_status_t st;
    if (u == NULL) {
        return RFE_ERR_NULL;
    }
    st = rfe_philox_word(s, n, &w);
    if (st == RFE_OK) {
        *u = uniform_of(w);
    }
    return st;
}

rfe_status_t rfe_philox_normal_pair(rfe_philox_t *s, uint64_t p, rfe_real_t z[2])
{
    uint64_t wa = 0u;
    uint64_t wb = 0u;
    rfe_status_t st;
    if ((s == NULL) || (z == NULL)) {
        return RFE_ERR_NULL;
    }
    /* words 2p and 2p + 1 lie in one block (blocks start at multiples of 4) */
    st = rfe_philox_word(s, 2u * p, &wa);
    if (st == RFE_OK) {
        st = rfe_philox_word(s, (2u * p) + 1u, &wb);
    }
    if (st == RFE_OK) {
        /* rho = sqrt(-2 log u_a), th = TWO_PI u_b */
        const rfe_real_t rho = RFE_SQRT(RFE_R(-2.0) * RFE_LOG(uniform_of(wa)));
        const rfe_real_t th = TWO_PI_R * uniform_of(wb);
        z[0] = rho * RFE_COS(th);
        z[1] = rho * RFE_SIN(th);
    }
    return st;
}
