/**
 * @file cubature_flt.c
 * @brief Third-degree spherical-radial cubature rule: points, propagation, means.
 */
#include "filters/cubature.h"

#include "numerics/internal.h"

/* The point, mean and correction loops inlined into their functions once with the firmware's
 * n = 4 states (m = 3 measurements) as constants, so the compiler unrolls them (issue 21), and once with run-time n;
 * the same operations in the same order, so the same results bit for bit. */
#if defined(__GNUC__)
/* MISRA-DEV-02: a GNU attribute (Rule 1.2, language extension), only under __GNUC__ */
#define CUB_INLINE __attribute__((always_inline)) inline
#else
#define CUB_INLINE inline
#endif

static CUB_INLINE void points_body(const rfe_real_t *x, const rfe_real_t *F, size_t n,
                                   size_t ld, rfe_real_t *pts)
{
    /* xi_j = +-sqrt(n) e_j, equal weights 1/(2n). */
    const rfe_real_t r = RFE_SQRT((rfe_real_t)n);
    size_t j;
    size_t i;
    for (j = 0u; j < n; ++j) {
        for (i = 0u; i < n; ++i) {
            const rfe_real_t d = r * F[(i * ld) + j];
            pts[(j * ld) + i] = x[i] + d;
            pts[((n + j) * ld) + i] = x[i] - d;
        }
    }
}

void rfe_cub_points(const rfe_real_t *x, const rfe_real_t *F, size_t n, size_t ld,
                    rfe_real_t *pts)
{
    if (n == 4u) {
        points_body(x, F, 4u, ld, pts);
    } else {
        points_body(x, F, n, ld, pts);
    }
}

rfe_status_t rfe_cub_propagate(rfe_real_t *pts, size_t n, rfe_process_fn_t process,
                               void *ctx, rfe_real_t *tmp)
{
    size_t j;
    size_t i;
    if (process == NULL) {
        return RFE_OK; /* random walk: X*_j = X_j */
    }
    for (j = 0u; j < (2u * n); ++j) {
        rfe_real_t *row = &pts[j * (size_t)RFE_N_MAX];
        const rfe_status_t st = process(ctx, row, tmp, n);
        if (st != RFE_OK) {
            return st;
        }
        if (!rfe_all_finite(tmp, n)) {
            return RFE_ERR_NONFINITE;
        }
        for (i = 0u; i < n; ++i) {
            row[i] = tmp[i];
        }
    }
    return RFE_OK;
}

rfe_status_t rfe_cub_measure(const rfe_real_t *pts, size_t n, size_t m,
                             rfe_measure_fn_t measure, void *ctx, rfe_real_t *zpts)
{
    size_t j;
    for (j = 0u; j < (2u * n); ++j) {
        rfe_real_t *z = &zpts[j * (size_t)RFE_M_MAX];
        const rfe_status_t st = measure(ctx, &pts[j * (size_t)RFE_N_MAX], z, n, m);
        if (st != RFE_OK) {
            return st;
        }
        if (!rfe_all_finite(z, m)) {
            return RFE_ERR_NONFINITE;
        }
    }
    return RFE_OK;
}

static CUB_INLINE void mean_body(const rfe_real_t *rows, size_t n, size_t cols, size_t ld,
                                 rfe_real_t *mean)
{
    const rfe_real_t w = RFE_R(1.0) / (RFE_R(2.0) * (rfe_real_t)n);
    size_t i;
    size_t j;
    for (i = 0u; i < cols; ++i) {
        rfe_real_t acc = RFE_R(0.0);
        for (j = 0u; j < (2u * n); ++j) {
            acc += rows[(j * ld) + i];
        }
        mean[i] = acc * w;
    }
}

void rfe_cub_mean(const rfe_real_t *rows, size_t n, size_t cols, size_t ld,
                  rfe_real_t *mean)
{
    if ((n == 4u) && (cols == 3u)) {
        mean_body(rows, 4u, 3u, ld, mean);
    } else {
        mean_body(rows, n, cols, ld, mean);
    }
}

void rfe_cub_hold_random_walk_mean(const rfe_real_t *x, size_t n,
                                   rfe_process_fn_t process, rfe_real_t *mean)
{
    if (process == NULL) {
        size_t i;
        for (i = 0u; i < n; ++i) {
            mean[i] = x[i];
        }
    }
}

static CUB_INLINE void correct_body(const rfe_real_t *x, const rfe_real_t *Kt,
                                    const rfe_real_t *y, const rfe_real_t *zhat, size_t n,
                                    size_t m, size_t ld, rfe_real_t *x_new)
{
    size_t i;
    size_t r;
    for (i = 0u; i < n; ++i) {
        rfe_real_t acc = x[i];
        for (r = 0u; r < m; ++r) {
            acc += Kt[(r * ld) + i] * (y[r] - zhat[r]);
        }
        x_new[i] = acc;
    }
}

rfe_status_t rfe_cub_correct(const rfe_real_t *x, const rfe_real_t *Kt,
                             const rfe_real_t *y, const rfe_real_t *zhat, size_t n,
                             size_t m, size_t ld, rfe_real_t *x_new)
{
    if ((n == 4u) && (m == 3u)) {
        correct_body(x, Kt, y, zhat, 4u, 3u, ld, x_new);
    } else {
        correct_body(x, Kt, y, zhat, n, m, ld, x_new);
    }
    return rfe_all_finite(x_new, n) ? RFE_OK : RFE_ERR_NONFINITE;
}

int rfe_cub_dims_ok(size_t n, size_t m)
{
    return (n >= 1u) && (n <= (size_t)RFE_N_MAX) && (m >= 1u) && (m <= (size_t)RFE_M_MAX);
}
