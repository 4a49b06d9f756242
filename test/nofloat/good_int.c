/* Must be accepted: integer-only code that needs libgcc's integer helpers on Cortex-M0+
 * (no divide instruction, no 64-bit multiply, no CLZ): __aeabi_idiv, __aeabi_uidivmod,
 * __aeabi_ldivmod, __aeabi_uldivmod, __aeabi_lmul, __clzsi2, and a struct copy that GCC may
 * turn into memcpy. */
#include "nofloat_fixture.h"

typedef struct {
    int32_t v[16];
} nofloat_fixture_block_t;

int64_t nofloat_fixture_div64(int64_t n, int64_t d)
{
    return (d == 0) ? 0 : (n / d + n % d);
}

uint64_t nofloat_fixture_udiv64(uint64_t n, uint64_t d)
{
    return (d == 0u) ? 0u : n / d;
}

int32_t nofloat_fixture_div32(int32_t n, int32_t d)
{
    return (d == 0) ? 0 : n / d;
}

uint32_t nofloat_fixture_mod32(uint32_t n, uint32_t d)
{
    return (d == 0u) ? 0u : n % d;
}

int64_t nofloat_fixture_mul64(int64_t a, int64_t b)
{
    return (int64_t)((uint64_t)a * (uint64_t)b);
}

uint64_t nofloat_fixture_shifts(uint64_t x, unsigned int s)
{
    const unsigned int k = s & 63u;
    return (x << k) ^ (x >> k);
}

int nofloat_fixture_clz(uint32_t x)
{
    return (x == 0u) ? 32 : __builtin_clz(x);
}

void nofloat_fixture_copy(nofloat_fixture_block_t *dst, const nofloat_fixture_block_t *src)
{
    *dst = *src;
}
