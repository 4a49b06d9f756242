/**
 * @file cubature.h
 * @brief Private cubature-rule helpers shared by the SCKF and the CKF (MODEL.md §6).
 *
 * Points are stored one per row (2n rows, ld RFE_N_MAX); measurements likewise (ld RFE_M_MAX).
 */
#ifndef RFE_CUBATURE_H
#define RFE_CUBATURE_H

#include "rfe/component/sckf.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_cub_points                rfe_cub_points_f64
#define rfe_cub_propagate             rfe_cub_propagate_f64
#define rfe_cub_measure               rfe_cub_measure_f64
#define rfe_cub_mean                  rfe_cub_mean_f64
#define rfe_cub_hold_random_walk_mean rfe_cub_hold_random_walk_mean_f64
#define rfe_cub_correct               rfe_cub_correct_f64
#define rfe_cub_dims_ok               rfe_cub_dims_ok_f64
#else
#define rfe_cub_points                rfe_cub_points_f32
#define rfe_cub_propagate             rfe_cub_propagate_f32
#define rfe_cub_measure               rfe_cub_measure_f32
#define rfe_cub_mean                  rfe_cub_mean_f32
#define rfe_cub_hold_random_walk_mean rfe_cub_hold_random_walk_mean_f32
#define rfe_cub_correct               rfe_cub_correct_f32
#define rfe_cub_dims_ok               rfe_cub_dims_ok_f32
#endif

/** X_j = x + sqrt(n) F e_j and X_{n+j} = x - sqrt(n) F e_j (F: lower factor; F and the
 *  points, one per row, both with row stride ld: RFE_N_MAX in the generic filters). */
void rfe_cub_points(const rfe_real_t *x, const rfe_real_t *F, size_t n, size_t ld,
                    rfe_real_t *pts);

/** X*_j = f(X_j) in place for all 2n points; NULL f is the identity. Checks finiteness. */
rfe_status_t rfe_cub_propagate(rfe_real_t *pts, size_t n, rfe_process_fn_t process,
                               void *ctx, rfe_real_t *tmp);

/** Z_j = h(X_j) for all 2n points into zpts. Checks finiteness. */
rfe_status_t rfe_cub_measure(const rfe_real_t *pts, size_t n, size_t m,
                             rfe_measure_fn_t measure, void *ctx, rfe_real_t *zpts);

/** Mean of the 2n rows (cols values each, row stride ld). */
void rfe_cub_mean(const rfe_real_t *rows, size_t n, size_t cols, size_t ld,
                  rfe_real_t *mean);

/**
 * For the random walk (process == NULL) replaces the points' average by x itself: the points
 * are symmetric about x, and their average differs only by rounding, which over many held
 * steps walks the mean (even outside [mu_min, mu_max]). Any other process: no change.
 */
void rfe_cub_hold_random_walk_mean(const rfe_real_t *x, size_t n,
                                   rfe_process_fn_t process, rfe_real_t *mean);

/**
 * x_new = x + K (y - z), with the gain given transposed (Kt: m x n, row stride ld;
 * RFE_N_MAX in the generic filters).
 * @return RFE_OK, or RFE_ERR_NONFINITE when a huge innovation overflowed (x_new unusable).
 */
rfe_status_t rfe_cub_correct(const rfe_real_t *x, const rfe_real_t *Kt,
                             const rfe_real_t *y, const rfe_real_t *zhat, size_t n,
                             size_t m, size_t ld, rfe_real_t *x_new);

/** True when the filter dimensions are within 1..RFE_N_MAX and 1..RFE_M_MAX. */
int rfe_cub_dims_ok(size_t n, size_t m);

#endif /* RFE_CUBATURE_H */
