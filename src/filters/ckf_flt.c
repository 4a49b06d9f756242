/**
 * @file ckf_flt.c
 * @brief Full-covariance cubature Kalman filter, the paper's baseline (MODEL.md §6).
 *
 * Deliberately the textbook form (P = P- - K Pzz K^T, no symmetrisation or Joseph form):
 * it is the comparison the paper makes, and its finite-precision failure is the point.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_CKF_IMPL
#include "rfe/component/ckf.h"

#include "rfe/component/chol.h"
#include "rfe/component/qr.h"

#include "filters/cubature.h"
#include "numerics/internal.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)

static void copy_square(const rfe_real_t *src, size_t lds, size_t k, rfe_real_t *dst, size_t ldd)
{
    size_t i;
    size_t j;
    for (i = 0u; i < k; ++i) {
        for (j = 0u; j < k; ++j) {
            dst[(i * ldd) + j] = src[(i * lds) + j];
        }
    }
}

rfe_status_t rfe_ckf_init(rfe_ckf_t *f, size_t n, size_t m, const rfe_real_t *x0,
                          const rfe_real_t *P0, const rfe_real_t *Q, const rfe_real_t *R,
                          size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    size_t i;
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*f)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if ((f == NULL) || (x0 == NULL) || (P0 == NULL) || (Q == NULL) || (R == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_cub_dims_ok(n, m) == 0) {
        return RFE_ERR_SIZE;
    }
    if (!rfe_all_finite(x0, n) || !rfe_all_finite(P0, n * n) || !rfe_all_finite(Q, n * n) ||
        !rfe_all_finite(R, m * m)) {
        return RFE_ERR_NONFINITE;
    }
    f->n = n;
    f->m = m;
    for (i = 0u; i < n; ++i) {
        f->x[i] = x0[i];
    }
    copy_square(P0, n, n, f->P, NM);
    copy_square(Q, n, n, f->Q, NM);
    copy_square(R, m, m, f->R, MM);
    f->magic = RFE_MAGIC_CKF;
    return RFE_OK;
}

/* Second moment about the mean: out = sum_j w a_j b_j^T - abar bbar^T (the paper's form).
 * a rows: na values (stride lda), b rows: nb values (stride ldb), 2n rows each. */
static void cross_moment(const rfe_real_t *a, size_t lda, const rfe_real_t *abar, size_t na,
                         const rfe_real_t *b, size_t ldb, const rfe_real_t *bbar, size_t nb,
                         size_t n, rfe_real_t *out, size_t ldo)
{
    const rfe_real_t w = RFE_R(1.0) / (RFE_R(2.0) * (rfe_real_t)n);
    size_t i;
    size_t k;
    size_t j;
    for (i = 0u; i < na; ++i) {
        for (k = 0u; k < nb; ++k) {
            rfe_real_t acc = RFE_R(0.0);
            for (j = 0u; j < (2u * n); ++j) {
                acc += a[(j * lda) + i] * b[(j * ldb) + k];
            }
            out[(i * ldo) + k] = (w * acc) - (abar[i] * bbar[k]);
        }
    }
}

rfe_status_t rfe_ckf_predict(rfe_ckf_t *f, rfe_process_fn_t process, void *ctx)
{
    rfe_cub_scratch_t *w;
    size_t n;
    size_t i;
    size_t j;
    rfe_status_t st;

    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    w = &f->w;
    n = f->n;
    /* X_j = chol(P) xi_j + x;  X*_j = f(X_j);  x- = mean X*_j. */
    st = rfe_chol_factor(f->P, n, NM, f->L, NM);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_points(f->x, f->L, n, NM, w->pts);
    st = rfe_cub_propagate(w->pts, n, process, ctx, w->xn);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_mean(w->pts, n, n, NM, w->xn);
    /* P- = sum_j w X*_j X*_j^T - x- x-^T + Q. */
    cross_moment(w->pts, NM, w->xn, n, w->pts, NM, w->xn, n, n, f->Pn, NM);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            f->Pn[(i * NM) + j] += f->Q[(i * NM) + j];
        }
    }
    /* The moment above needs the points' own mean; the committed x- of a random walk is x. */
    rfe_cub_hold_random_walk_mean(f->x, n, process, w->xn);
    if (!rfe_all_finite(w->xn, n) || !rfe_lower_finite(f->Pn, n, NM)) {
        return RFE_ERR_NONFINITE; /* overflow in the propagated points: commit nothing */
    }
    for (i = 0u; i < n; ++i) {
        f->x[i] = w->xn[i];
    }
    copy_square(f->Pn, NM, n, f->P, NM);
    return RFE_OK;
}

rfe_status_t rfe_ckf_predict_steps(rfe_ckf_t *f, uint32_t k)
{
    const rfe_real_t c = (rfe_real_t)k;
    size_t n;
    size_t i;
    size_t j;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    n = f->n;
    /* P- = P + k Q into Pn first: an overflow commits nothing. x- = x (random walk). */
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            f->Pn[(i * NM) + j] = f->P[(i * NM) + j] + (c * f->Q[(i * NM) + j]);
        }
    }
    if (!rfe_lower_finite(f->Pn, n, NM)) {
        return RFE_ERR_NONFINITE;
    }
    copy_square(f->Pn, NM, n, f->P, NM);
    return RFE_OK;
}

/* dst (k x k, stride ld) += src (k x k, stride ld). */
static void add_square(const rfe_real_t *src, size_t k, size_t ld, rfe_real_t *dst)
{
    size_t r;
    size_t s;
    for (r = 0u; r < k; ++r) {
        for (s = 0u; s < k; ++s) {
            dst[(r * ld) + s] += src[(r * ld) + s];
        }
    }
}

/* The candidate covariance P = P- - K Pzz K^T into f->Pn (gain transposed in w.Kt, Pzz in
 * w.Szz). */
static void posterior_covariance(rfe_ckf_t *f)
{
    const rfe_cub_scratch_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    size_t i;
    size_t j;
    size_t r;
    size_t s;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            rfe_real_t acc = RFE_R(0.0);
            for (r = 0u; r < m; ++r) {
                for (s = 0u; s < m; ++s) {
                    acc += w->Kt[(r * NM) + i] * w->Szz[(r * MM) + s] * w->Kt[(s * NM) + j];
                }
            }
            f->Pn[(i * NM) + j] = f->P[(i * NM) + j] - acc;
        }
    }
}

rfe_status_t rfe_ckf_update(rfe_ckf_t *f, rfe_measure_fn_t measure, void *ctx,
                            const rfe_real_t *y)
{
    rfe_cub_scratch_t *w;
    size_t n;
    size_t m;
    size_t i;
    rfe_status_t st;

    if ((f == NULL) || (measure == NULL) || (y == NULL)) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    w = &f->w;
    n = f->n;
    m = f->m;
    if (!rfe_all_finite(y, m)) {
        return RFE_ERR_NONFINITE;
    }
    /* X_j = chol(P-) xi_j + x-;  Z_j = h(X_j);  z = mean Z_j. */
    st = rfe_chol_factor(f->P, n, NM, f->L, NM);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_points(f->x, f->L, n, NM, w->pts);
    st = rfe_cub_measure(w->pts, n, m, measure, ctx, w->zpts);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_mean(w->zpts, n, m, MM, w->zhat);
    /* Pzz = sum w Z Z^T - z z^T + R;  Pxz^T = sum w Z X^T - z x-^T (m x n). */
    cross_moment(w->zpts, MM, w->zhat, m, w->zpts, MM, w->zhat, m, n, w->Szz, MM);
    add_square(f->R, m, MM, w->Szz);
    cross_moment(w->zpts, MM, w->zhat, m, w->pts, NM, f->x, n, n, w->Kt, NM);
    /* K = Pxz Pzz^-1 via Pzz = Lz Lz^T: K^T = Lz^-T (Lz^-1 Pxz^T). */
    st = rfe_chol_factor(w->Szz, m, MM, w->Lz, MM);
    if (st == RFE_OK) {
        st = rfe_qr_solve_lower(w->Lz, m, MM, w->Kt, n, NM);
    }
    if (st == RFE_OK) {
        st = rfe_qr_solve_lower_t(w->Lz, m, MM, w->Kt, n, NM);
    }
    if (st != RFE_OK) {
        return st;
    }
    /* x = x- + K (y - z). */
    st = rfe_cub_correct(f->x, w->Kt, y, w->zhat, n, m, NM, w->xn);
    if (st != RFE_OK) {
        return st;
    }
    /* P = P- - K Pzz K^T. */
    posterior_covariance(f);
    for (i = 0u; i < n; ++i) {
        f->x[i] = w->xn[i];
    }
    copy_square(f->Pn, NM, n, f->P, NM);
    return RFE_OK;
}

rfe_status_t rfe_ckf_get(const rfe_ckf_t *f, rfe_real_t *x, rfe_real_t *sd)
{
    size_t i;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    for (i = 0u; i < f->n; ++i) {
        if (x != NULL) {
            x[i] = f->x[i];
        }
        if (sd != NULL) {
            /* A negative diagonal (P no longer positive semi-definite) reports sd 0. */
            sd[i] = RFE_SQRT(rfe_max(f->P[(i * NM) + i], RFE_R(0.0)));
        }
    }
    return RFE_OK;
}

/* generated by scripts/codegen/twins.py from filter_clamp: do not edit; make twins */
rfe_status_t rfe_ckf_clamp(rfe_ckf_t *f, rfe_real_t lo, rfe_real_t hi, int *clamped)
{
    if ((f == NULL) || (clamped == NULL)) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (!rfe_is_finite(lo) || !rfe_is_finite(hi) || !(lo <= hi)) {
        return RFE_ERR_RANGE;
    }
    *clamped = rfe_clamp_vec(f->x, f->n, lo, hi);
    return RFE_OK;
}
/* end generated */
