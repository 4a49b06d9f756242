/**
 * @file cubature_q31.h
 * @brief Private helpers of the fixed-point cubature filters (sckf_q31.c, ckf_q31.c): the
 *        third-degree cubature rule on Q29 points. The exactly rounded integer division and
 *        square root they share with the linear algebra are numerics/internal_q31.h's.
 *
 * Points are stored one per row (2n rows, ld RFE_N_MAX, Q29); measurements likewise
 * (ld RFE_M_MAX, Q24). Integer operations only; no <math.h> (not internal.h).
 */
#ifndef RFE_CUBATURE_Q31_H
#define RFE_CUBATURE_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/fixed.h"
#include "rfe/component/fxmath.h"
#include "rfe/component/sckf_q31.h"

#include "numerics/internal_q31.h" /* rfe_q31_pow2, RFE_TRIA_COLS_SZ, rfe_q31_div_round */

/** Magic words marking an initialised fixed-point state struct (distinct from the float
 *  filters' so that a struct of the other kind is never taken for initialised). */
#define RFE_MAGIC_SCKF_Q31 0x53513331u /* "SQ31" */
#define RFE_MAGIC_CKF_Q31 0x43513331u  /* "CQ31" */

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

/** rfe_cub_centre_q31 of the 2n points' values v[j ldv] (j = 0 .. 2n-1) about one mean into
 *  out[j ldo] (out may be v with ldo = ldv): the same integers, in one call per state or
 *  measurement row instead of one per value. The constant is looked up once, and the
 *  product |v - mean| (< 2^32) times 1/sqrt(2n) (< 2^31) is formed from the magnitudes as
 *  one 32 x 32 -> 64 multiply (rfe_fix_umul32x32: 16-bit halves on the Cortex-M0+) with
 *  the sign applied after; below 2^63, so it is the int64 product exactly. */
void rfe_cub_centre_vec_q31(const rfe_fix_t *v, size_t ldv, rfe_fix_t mean, size_t n,
                            unsigned int q_in, unsigned int q_out, rfe_fix_t *out, size_t ldo,
                            uint32_t *sat);

/** True when the filter dimensions are within 1..RFE_N_MAX and 1..RFE_M_MAX (and within
 *  the 8 states the cubature constants are tabulated for). */
int rfe_cub_dims_ok_q31(size_t n, size_t m);

#endif /* RFE_CUBATURE_Q31_H */
