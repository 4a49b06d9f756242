/**
 * @file sckf_flt.c
 * @brief Square-root cubature Kalman filter (MODEL.md §6).
 *
 * Every step computes into scratch and commits x and S only when everything succeeded,
 * so an error leaves the filter exactly as it was.
 */
#include "rfe/sckf.h"

#include "rfe/qr.h"

#include "cubature.h"
#include "internal.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)
#define TC ((size_t)RFE_TRIA_COLS_MAX)

/* Copies the lower triangle of a k x k matrix (src stride lds) into dst (stride ldd),
 * zeroing dst's upper triangle. */
static void copy_lower(const rfe_real_t *src, size_t lds, size_t k, rfe_real_t *dst, size_t ldd)
{
    size_t i;
    size_t j;
    for (i = 0u; i < k; ++i) {
        for (j = 0u; j < k; ++j) {
            dst[(i * ldd) + j] = (j <= i) ? src[(i * lds) + j] : RFE_R(0.0);
        }
    }
}

/* Accepts a step: the candidate mean (w.xn) and factor (Tria output in w.A) become the state. */
static void commit(rfe_sckf_t *f)
{
    size_t i;
    for (i = 0u; i < f->n; ++i) {
        f->x[i] = f->w.xn[i];
    }
    copy_lower(f->w.A, TC, f->n, f->S, NM);
}

rfe_status_t RFE_FN(rfe_sckf_init)(rfe_sckf_t *f, size_t n, size_t m, const rfe_real_t *x0,
                                   const rfe_real_t *S0, const rfe_real_t *SQ,
                                   const rfe_real_t *SR)
{
    size_t i;
    if ((f == NULL) || (x0 == NULL) || (S0 == NULL) || (SQ == NULL) || (SR == NULL)) {
        return RFE_ERR_NULL;
    }
    if (RFE_FN(rfe_cub_dims_ok)(n, m) == 0) {
        return RFE_ERR_SIZE;
    }
    if (!rfe_all_finite(x0, n) || !rfe_lower_finite(S0, n, n) || !rfe_lower_finite(SQ, n, n) ||
        !rfe_lower_finite(SR, m, m)) {
        return RFE_ERR_NONFINITE;
    }
    f->n = n;
    f->m = m;
    for (i = 0u; i < n; ++i) {
        f->x[i] = x0[i];
    }
    copy_lower(S0, n, n, f->S, NM);
    copy_lower(SQ, n, n, f->SQ, NM);
    copy_lower(SR, m, m, f->SR, MM);
    f->magic = RFE_MAGIC_SCKF;
    return RFE_OK;
}

rfe_status_t RFE_FN(rfe_sckf_predict)(rfe_sckf_t *f, rfe_process_fn_t process, void *ctx)
{
    rfe_cub_scratch_t *w;
    rfe_real_t inv_sqrt_2n;
    size_t n;
    size_t i;
    size_t j;
    rfe_status_t st;

    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    w = &f->w;
    n = f->n;
    /* X_j = S xi_j + x;  X*_j = f(X_j);  x- = mean_j X*_j. */
    RFE_FN(rfe_cub_points)(f->x, f->S, n, w->pts);
    st = RFE_FN(rfe_cub_propagate)(w->pts, n, process, ctx, w->xn);
    if (st != RFE_OK) {
        return st;
    }
    RFE_FN(rfe_cub_mean)(w->pts, n, n, NM, w->xn);
    /* S- = Tria([(X*_1 - x-, ..., X*_2n - x-)/sqrt(2n), S_Q]). */
    inv_sqrt_2n = RFE_R(1.0) / RFE_SQRT(RFE_R(2.0) * (rfe_real_t)n);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < (2u * n); ++j) {
            w->A[(i * TC) + j] = (w->pts[(j * NM) + i] - w->xn[i]) * inv_sqrt_2n;
        }
        for (j = 0u; j < n; ++j) {
            w->A[(i * TC) + (2u * n) + j] = f->SQ[(i * NM) + j];
        }
    }
    st = RFE_FN(rfe_qr_tria)(w->A, n, 3u * n, TC);
    if (st != RFE_OK) {
        return st;
    }
    commit(f);
    return RFE_OK;
}

/* Xc = (X_j - x-)/sqrt(2n) into B (n x 2n) and Zc = (Z_j - z)/sqrt(2n) in place in zpts. */
static void centre_points(rfe_sckf_t *f)
{
    rfe_cub_scratch_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    const rfe_real_t inv_sqrt_2n = RFE_R(1.0) / RFE_SQRT(RFE_R(2.0) * (rfe_real_t)n);
    size_t i;
    size_t j;
    for (j = 0u; j < (2u * n); ++j) {
        for (i = 0u; i < n; ++i) {
            w->B[(i * TC) + j] = (w->pts[(j * NM) + i] - f->x[i]) * inv_sqrt_2n;
        }
        for (i = 0u; i < m; ++i) {
            w->zpts[(j * MM) + i] = (w->zpts[(j * MM) + i] - w->zhat[i]) * inv_sqrt_2n;
        }
    }
}

/* S_zz = Tria([Zc, S_R]) into w->Szz; then K^T = S_zz^-T (S_zz^-1 P_xz^T), P_xz = Xc Zc^T. */
static rfe_status_t gain(rfe_sckf_t *f)
{
    rfe_cub_scratch_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    size_t i;
    size_t j;
    size_t r;
    rfe_status_t st;

    for (r = 0u; r < m; ++r) {
        for (j = 0u; j < (2u * n); ++j) {
            w->A[(r * TC) + j] = w->zpts[(j * MM) + r];
        }
        for (j = 0u; j < m; ++j) {
            w->A[(r * TC) + (2u * n) + j] = f->SR[(r * MM) + j];
        }
    }
    st = RFE_FN(rfe_qr_tria)(w->A, m, (2u * n) + m, TC);
    if (st != RFE_OK) {
        return st;
    }
    copy_lower(w->A, TC, m, w->Szz, MM);
    /* P_xz^T (m x n): row r, column i = sum_j Zc[r][j] Xc[i][j]. */
    for (r = 0u; r < m; ++r) {
        for (i = 0u; i < n; ++i) {
            rfe_real_t acc = RFE_R(0.0);
            for (j = 0u; j < (2u * n); ++j) {
                acc += w->zpts[(j * MM) + r] * w->B[(i * TC) + j];
            }
            w->Kt[(r * NM) + i] = acc;
        }
    }
    /* K = (P_xz / S_zz^T) / S_zz: two triangular solves, never an inverse. */
    st = RFE_FN(rfe_qr_solve_lower)(w->Szz, m, MM, w->Kt, n, NM);
    if (st == RFE_OK) {
        st = RFE_FN(rfe_qr_solve_lower_t)(w->Szz, m, MM, w->Kt, n, NM);
    }
    return st;
}

rfe_status_t RFE_FN(rfe_sckf_update)(rfe_sckf_t *f, rfe_measure_fn_t measure, void *ctx,
                                     const rfe_real_t *y)
{
    rfe_cub_scratch_t *w;
    size_t n;
    size_t m;
    size_t i;
    size_t j;
    size_t r;
    rfe_status_t st;

    if ((f == NULL) || (measure == NULL) || (y == NULL)) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    w = &f->w;
    n = f->n;
    m = f->m;
    if (!rfe_all_finite(y, m)) {
        return RFE_ERR_NONFINITE;
    }
    /* X_j = S- xi_j + x-;  Z_j = h(X_j, u);  z = mean_j Z_j. */
    RFE_FN(rfe_cub_points)(f->x, f->S, n, w->pts);
    st = RFE_FN(rfe_cub_measure)(w->pts, n, m, measure, ctx, w->zpts);
    if (st != RFE_OK) {
        return st;
    }
    RFE_FN(rfe_cub_mean)(w->zpts, n, m, MM, w->zhat);
    centre_points(f);
    st = gain(f);
    if (st != RFE_OK) {
        return st;
    }
    /* x = x- + K (y - z); a huge innovation that overflows commits nothing. */
    st = RFE_FN(rfe_cub_correct)(f->x, w->Kt, y, w->zhat, n, m, w->xn);
    if (st != RFE_OK) {
        return st;
    }
    /* S = Tria([Xc - K Zc, K S_R]). */
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < (2u * n); ++j) {
            rfe_real_t acc = w->B[(i * TC) + j];
            for (r = 0u; r < m; ++r) {
                acc -= w->Kt[(r * NM) + i] * w->zpts[(j * MM) + r];
            }
            w->A[(i * TC) + j] = acc;
        }
        for (j = 0u; j < m; ++j) {
            rfe_real_t acc = RFE_R(0.0);
            for (r = j; r < m; ++r) { /* S_R is lower-triangular */
                acc += w->Kt[(r * NM) + i] * f->SR[(r * MM) + j];
            }
            w->A[(i * TC) + (2u * n) + j] = acc;
        }
    }
    st = RFE_FN(rfe_qr_tria)(w->A, n, (2u * n) + m, TC);
    if (st != RFE_OK) {
        return st;
    }
    commit(f);
    return RFE_OK;
}

rfe_status_t RFE_FN(rfe_sckf_get)(const rfe_sckf_t *f, rfe_real_t *x, rfe_real_t *sd)
{
    size_t i;
    size_t j;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    for (i = 0u; i < f->n; ++i) {
        if (x != NULL) {
            x[i] = f->x[i];
        }
        if (sd != NULL) {
            /* sd_i = sqrt((S S^T)_ii) = norm of row i of S. */
            rfe_real_t ss = RFE_R(0.0);
            for (j = 0u; j <= i; ++j) {
                ss += f->S[(i * NM) + j] * f->S[(i * NM) + j];
            }
            sd[i] = RFE_SQRT(ss);
        }
    }
    return RFE_OK;
}

rfe_status_t RFE_FN(rfe_sckf_clamp)(rfe_sckf_t *f, rfe_real_t lo, rfe_real_t hi, int *clamped)
{
    if ((f == NULL) || (clamped == NULL)) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (!rfe_is_finite(lo) || !rfe_is_finite(hi) || !(lo <= hi)) {
        return RFE_ERR_RANGE;
    }
    *clamped = rfe_clamp_vec(f->x, f->n, lo, hi);
    return RFE_OK;
}
