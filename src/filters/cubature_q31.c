/**
 * @file cubature_q31.c
 * @brief Third-degree spherical-radial cubature rule on fixed-point values: points,
 *        propagation, means, centring (the twin of cubature_flt.c).
 */
#include "filters/cubature_q31.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)

/* The cubature constants are tabulated for n = 1..8 (rfe_cub_dims_ok_q31 rejects more). */
#define CUB_TABLE_N 8u

/* a b exactly for an int32 a and a uint32 b (|a b| < 2^63): the magnitudes' product as one
 * 32 x 32 -> 64 multiply (rfe_fix_umul32x32: 16-bit halves on the Cortex-M0+, which would
 * call the C library's 64 x 64 multiply for the int64 product), signed after. */
static inline int64_t mul_q31_u32(rfe_fix_t a, uint32_t b)
{
    const uint32_t ua = (uint32_t)a; /* a modulo 2^32 */
    const uint32_t na = 0u - ua;
    const uint32_t ma = (a < 0) ? na : ua; /* |a| <= 2^31 */
    const int64_t p = (int64_t)rfe_fix_umul32x32(ma, b);
    return (a < 0) ? -p : p;
}

void rfe_cub_points_q31(const rfe_fix_t *x, const rfe_fix_t *F, size_t n, rfe_fix_t *pts,
                        uint32_t *sat)
{
    /* sqrt(n) in Q30, n = 1..8, rounded to nearest (50-digit reference values); as uint32,
     * since sqrt(n) >= 2 does not fit an int32 Q30 (all are below 2^32). */
    static const uint32_t sqrt_n_q30[CUB_TABLE_N] = {
        1073741824u, 1518500250u, 1859775393u, 2147483648u,
        2400959709u, 2630119584u, 2840853839u, 3037000500u};
    /* xi_j = +-sqrt(n) e_j, equal weights 1/(2n). |F| <= 2^31, sqrt(n) 2^30 < 2^31.6: the
     * product is below 2^62.6 and exact, formed from the magnitudes as one 32 x 32 -> 64
     * multiply (rfe_fix_umul32x32: 16-bit halves on the Cortex-M0+, which would call the
     * C library's 64 x 64 multiply for the int64 product) and signed after (the same
     * integer); rounded from Q60 to Q29. */
    const uint32_t r = sqrt_n_q30[n - 1u];
    size_t j;
    size_t i;
    for (j = 0u; j < n; ++j) {
        for (i = 0u; i < n; ++i) {
            const rfe_fix_t fij = F[(i * NM) + j];
            const int64_t d = rfe_fix_shr64_round(mul_q31_u32(fij, r), 60u - RFE_Q31_QX);
            pts[(j * NM) + i] = rfe_fix_sat32((int64_t)x[i] + d, sat);
            pts[((n + j) * NM) + i] = rfe_fix_sat32((int64_t)x[i] - d, sat);
        }
    }
}

rfe_status_t rfe_cub_propagate_q31(rfe_fix_t *pts, size_t n, rfe_process_fn_q31_t process,
                                   void *ctx, rfe_fix_t *tmp)
{
    size_t j;
    size_t i;
    if (process == NULL) {
        return RFE_OK; /* random walk: X*_j = X_j */
    }
    for (j = 0u; j < (2u * n); ++j) {
        rfe_fix_t *row = &pts[j * NM];
        const rfe_status_t st = process(ctx, row, tmp, n);
        if (st != RFE_OK) {
            return st;
        }
        for (i = 0u; i < n; ++i) {
            row[i] = tmp[i];
        }
    }
    return RFE_OK;
}

rfe_status_t rfe_cub_measure_q31(const rfe_fix_t *pts, size_t n, size_t m,
                                 rfe_measure_fn_q31_t measure, void *ctx, rfe_fix_t *zpts)
{
    size_t j;
    for (j = 0u; j < (2u * n); ++j) {
        const rfe_status_t st = measure(ctx, &pts[j * NM], &zpts[j * MM], n, m);
        if (st != RFE_OK) {
            return st;
        }
    }
    return RFE_OK;
}

void rfe_cub_mean_q31(const rfe_fix_t *rows, size_t n, size_t cols, size_t ld,
                      rfe_fix_t *mean)
{
    uint32_t unused = 0u; /* |sum| / 2n <= 2^31: never saturates */
    const size_t two_n = 2u * n; /* <= 16 */
    size_t i;
    size_t j;
    for (i = 0u; i < cols; ++i) {
        int64_t acc = 0; /* <= 16 terms of 2^31: exact */
        for (j = 0u; j < two_n; ++j) {
            acc += (int64_t)rows[(j * ld) + i];
        }
        mean[i] = rfe_q31_div_round(acc, (rfe_fix_t)two_n, &unused);
    }
}

void rfe_cub_hold_random_walk_mean_q31(const rfe_fix_t *x, size_t n,
                                       rfe_process_fn_q31_t process, rfe_fix_t *mean)
{
    if (process == NULL) {
        size_t i;
        for (i = 0u; i < n; ++i) {
            mean[i] = x[i];
        }
    }
}

/* 1 / sqrt(2n) in Q31, n = 1..8, rounded to nearest (all < 1, so they fit an int32). */
static const uint32_t inv_sqrt_2n_q31[CUB_TABLE_N] = {
    1518500250u, 1073741824u, 876706528u, 759250125u,
    679093957u,  619925131u,  573939147u, 536870912u};

rfe_fix_t rfe_cub_centre_q31(rfe_fix_t v, rfe_fix_t mean, size_t n, unsigned int q_in,
                             unsigned int q_out, uint32_t *sat)
{
    /* |v - mean| < 2^32 and 1/sqrt(2n) 2^31 <= 2^30.5: the product is below 2^62.5, exact;
     * Q(q_in + 31) -> Q(q_out). */
    const int64_t d = (int64_t)v - (int64_t)mean;
    return rfe_fix_narrow(d * (int64_t)inv_sqrt_2n_q31[n - 1u], (q_in + 31u) - q_out, sat);
}

/* floor(t / 2^s) for s <= 63, or RFE_FIX_MAX + 1u where that exceeds RFE_FIX_MAX (the
 * caller saturates it): from t's 32-bit words with 32-bit shifts (the uint64 shift by a
 * variable s was ~8 instructions on the Cortex-M4 and a libgcc call on the M0+). For s < 32
 * the quotient is below 2^32 exactly when the high word's bits from s up are 0, and is then
 * (lo >> s) | (hi << (32 - s)); for s >= 32 it is hi >> (s - 32). The same integer. */
static uint32_t centre_shr(uint64_t t, unsigned int s)
{
    const uint32_t lo = (uint32_t)t;
    const uint32_t hi = (uint32_t)(t >> 32);
    const uint32_t over = (uint32_t)RFE_FIX_MAX + 1u;
    uint32_t r;
    if (s >= 32u) {
        r = hi >> (s - 32u);
    } else if (s == 0u) {
        r = (hi != 0u) ? over : lo;
    } else if ((hi >> s) != 0u) {
        r = over;
    } else {
        r = (lo >> s) | (hi << (32u - s));
    }
    return (r > (uint32_t)RFE_FIX_MAX) ? over : r;
}

void rfe_cub_centre_vec_q31(const rfe_fix_t *v, size_t ldv, rfe_fix_t mean, size_t n,
                            unsigned int q_in, unsigned int q_out, rfe_fix_t *out, size_t ldo,
                            uint32_t *sat)
{
    const uint32_t c = inv_sqrt_2n_q31[n - 1u];
    const unsigned int s = (q_in + 31u) - q_out;
    const uint32_t um = (uint32_t)mean;
    /* rfe_fix_narrow(+-p, s) on the magnitude p < 2^63 (issue 21: the same integer and
     * count in fewer instructions): round half up is floor((p + 2^(s-1)) / 2^s) for +p and
     * -floor((p + 2^(s-1) - 1) / 2^s) for -p (a tie rounds towards +inf), both sums below
     * 2^64; a magnitude above RFE_FIX_MAX saturates to +-RFE_FIX_MAX (symmetric range). */
    uint64_t half = 0u; /* 2^(s-1), 0 for s = 0 */
    uint64_t tie = 0u;  /* 1 where half is 2^(s-1) */
    size_t j;
    if (s >= 64u) {
        /* |p| / 2^s < 1/2: every value rounds to 0 (rfe_fix_shr64_round) */
        for (j = 0u; j < (2u * n); ++j) {
            out[j * ldo] = 0;
        }
        return;
    }
    if (s > 0u) {
        const unsigned int s1 = s - 1u;
        half = (uint64_t)1 << s1;
        tie = 1u;
    }
    for (j = 0u; j < (2u * n); ++j) {
        const rfe_fix_t vj = v[j * ldv];
        /* |v - mean| as uint32: the difference modulo 2^32 of the larger minus the smaller;
         * its product with c < 2^63, exact */
        const uint32_t uv = (uint32_t)vj;
        uint32_t r;
        rfe_fix_t o;
        if (vj >= mean) {
            const uint32_t up = uv - um;
            r = centre_shr(rfe_fix_umul32x32(up, c) + half, s);
        } else {
            const uint32_t down = um - uv;
            r = centre_shr(rfe_fix_umul32x32(down, c) + (half - tie), s);
        }
        if (r > (uint32_t)RFE_FIX_MAX) {
            rfe_fix_count_sat(sat);
            o = RFE_FIX_MAX;
        } else {
            o = (rfe_fix_t)r;
        }
        out[j * ldo] = (vj >= mean) ? o : -o;
    }
}

int rfe_cub_dims_ok_q31(size_t n, size_t m)
{
    return ((n >= 1u) && (n <= NM) && (n <= CUB_TABLE_N) && (m >= 1u) && (m <= MM)) ? 1 : 0;
}
