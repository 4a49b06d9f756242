/**
 * @file cubature_q31.h
 * @brief Private helpers of the fixed-point linear algebra and cubature filters (qr_q31.c,
 *        chol_q31.c, sckf_q31.c, ckf_q31.c): the third-degree cubature rule on Q29 points
 *        and the exactly rounded integer division and square root they share.
 *
 * Points are stored one per row (2n rows, ld RFE_N_MAX, Q29); measurements likewise
 * (ld RFE_M_MAX, Q24). Integer operations only; no <math.h> (not internal.h). The helpers
 * shared with every module (rfe_q31_pow2) are internal_q31.h's.
 */
#ifndef RFE_CUBATURE_Q31_H
#define RFE_CUBATURE_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/fixed.h"
#include "rfe/fxmath.h"
#include "rfe/sckf_q31.h"

#include "internal_q31.h" /* rfe_q31_pow2 */

/** RFE_TRIA_COLS_MAX as a size_t, built from casts of the single constants (as
 *  RFE_TRIA_COLS_SZ of the float sources' internal.h, which q31 sources cannot include). */
#define RFE_Q31_TRIA_COLS                                                                      \
    ((2u * (size_t)RFE_N_MAX) +                                                                \
     (((size_t)RFE_N_MAX > (size_t)RFE_M_MAX) ? (size_t)RFE_N_MAX : (size_t)RFE_M_MAX))

/** Magic words marking an initialised fixed-point state struct (distinct from the float
 *  filters' so that a struct of the other kind is never taken for initialised). */
#define RFE_MAGIC_SCKF_Q31 0x53513331u /* "SQ31" */
#define RFE_MAGIC_CKF_Q31 0x43513331u  /* "CQ31" */

/** |v| as uint64 for every int64 (2^63 for INT64_MIN; internal_q31.h's rfe_q31_mag64 needs
 *  v > INT64_MIN). */
static inline uint64_t rfe_q31_mag64_any(int64_t v)
{
    return (v < 0) ? ((uint64_t)(-(v + 1)) + 1u) : (uint64_t)v;
}

/** Adds count saturation events to *sat (saturating at UINT32_MAX, like rfe_fix_count_sat). */
static inline void rfe_q31_add_count(uint32_t *sat, uint32_t count)
{
    *sat = (*sat > (UINT32_MAX - count)) ? UINT32_MAX : (*sat + count);
}

/** round(num / den) for den > 0, ties away from zero (exactly rounded on the magnitude, so
 *  odd in num), saturating to the symmetric int32 range with a count in *sat. */
static inline rfe_fix_t rfe_q31_div_round(int64_t num, rfe_fix_t den, uint32_t *sat)
{
    const uint64_t d = (uint64_t)den;
    const uint64_t mag = rfe_q31_mag64_any(num);
    uint64_t q = mag / d;
    int64_t r;
    if ((2u * (mag % d)) >= d) { /* mag % d < 2^31: no overflow */
        q += 1u;
    }
    if (q > (uint64_t)RFE_FIX_MAX) {
        rfe_fix_count_sat(sat);
        q = (uint64_t)RFE_FIX_MAX;
    }
    r = (int64_t)q;
    return (rfe_fix_t)((num < 0) ? -r : r);
}

/** round(sqrt(x)) for every uint64 (<= 2^32): floor root r from rfe_fix_isqrt64, plus one
 *  exactly when x - r^2 > r (sqrt(x) is never a half-integer). */
static inline uint64_t rfe_q31_sqrt_round(uint64_t x)
{
    uint32_t r32 = 0u;
    uint64_t r;
    /* rfe_fix_isqrt64 fails only for a NULL root pointer; r32 is never NULL. */
    const rfe_status_t st = rfe_fix_isqrt64(x, &r32);
    (void)st;
    r = (uint64_t)r32;
    if ((x - (r * r)) > r) { /* r^2 <= x < 2^64 */
        r += 1u;
    }
    return r;
}

/** X_j = x + sqrt(n) F e_j and X_{n+j} = x - sqrt(n) F e_j (F: lower factor, ld RFE_N_MAX,
 *  Q30; x and the points Q29). sqrt(n) is a Q30 constant rounded to nearest; each offset
 *  is rounded once (error <= 0.5 LSB of Q29 + |F_ij| 2^-31), each point saturates
 *  (counted) outside +-4. */
void rfe_cub_points_q31(const rfe_fix_t *x, const rfe_fix_t *F, size_t n, rfe_fix_t *pts,
                        uint32_t *sat);

/** X*_j = f(X_j) in place for all 2n points; NULL f is the identity. */
rfe_status_t rfe_cub_propagate_q31(rfe_fix_t *pts, size_t n, rfe_process_fn_q31_t process,
                                   void *ctx, rfe_fix_t *tmp);

/** Z_j = h(X_j) for all 2n points into zpts. */
rfe_status_t rfe_cub_measure_q31(const rfe_fix_t *pts, size_t n, size_t m,
                                 rfe_measure_fn_q31_t measure, void *ctx, rfe_fix_t *zpts);

/** Mean of the 2n rows (cols values each, row stride ld): the exact int64 sum divided by
 *  2n, rounded to nearest (ties away from zero); never saturates. */
void rfe_cub_mean_q31(const rfe_fix_t *rows, size_t n, size_t cols, size_t ld,
                      rfe_fix_t *mean);

/** For the random walk (process == NULL) replaces the points' average by x itself (they
 *  differ only where points saturated); any other process: no change. */
void rfe_cub_hold_random_walk_mean_q31(const rfe_fix_t *x, size_t n,
                                       rfe_process_fn_q31_t process, rfe_fix_t *mean);

/** Centred, weighted deviation (v - mean) / sqrt(2n): v, mean in Q(q_in), the result in
 *  Q(q_out), q_out <= q_in + 1. 1/sqrt(2n) is a Q31 constant rounded to nearest; one
 *  rounding (half up) of the exact product; saturates (counted). */
rfe_fix_t rfe_cub_centre_q31(rfe_fix_t v, rfe_fix_t mean, size_t n, unsigned int q_in,
                             unsigned int q_out, uint32_t *sat);

/** True when the filter dimensions are within 1..RFE_N_MAX and 1..RFE_M_MAX (and within
 *  the 8 states the cubature constants are tabulated for). */
int rfe_cub_dims_ok_q31(size_t n, size_t m);

#endif /* RFE_CUBATURE_Q31_H */
