/**
 * @file sckf_flt.c
 * @brief Square-root cubature Kalman filter (MODEL.md §6).
 *
 * Every step computes into scratch and commits x and S only when everything succeeded,
 * so an error leaves the filter exactly as it was.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_SCKF_IMPL
#include "rfe/component/sckf.h"

#include "rfe/component/qr.h"

#include "filters/cubature.h"
#include "numerics/internal.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)
#define TC RFE_TRIA_COLS_SZ

/* The update's helpers inlined into update_body, and update_body into update_core once with
 * the firmware's sizes (n = 4, m = 3) as constants and once with run-time sizes (issue 21). */
#if defined(__GNUC__)
/* MISRA-DEV-02: a GNU attribute (Rule 1.2, language extension), only under __GNUC__ */
#define SCKF_INLINE __attribute__((always_inline)) inline
#else
#define SCKF_INLINE inline
#endif

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

/* Accepts a step: the candidate mean (w.xn) and factor (Tria output in w.A) become the state.
 * Only S's lower triangle is written: its upper triangle is zero from the init (copy_lower)
 * on, and nothing writes it (issue 21: zeroing it again cost a memset call per row). */
static SCKF_INLINE void commit(rfe_sckf_t *f, size_t n)
{
    size_t i;
    size_t j;
    /* Column by column, the mean in the same loop: a strided copy stays inline, where a
     * contiguous copy is compiled into a memmove call (~45 instructions for a few elements
     * on the Cortex-M4F). */
    for (j = 0u; j < n; ++j) {
        f->x[j] = f->w.xn[j];
        for (i = j; i < n; ++i) {
            f->S[(i * NM) + j] = f->w.A[(i * TC) + j];
        }
    }
}

rfe_status_t rfe_sckf_init(rfe_sckf_t *f, size_t n, size_t m, const rfe_real_t *x0,
                           const rfe_real_t *S0, const rfe_real_t *SQ,
                           const rfe_real_t *SR, size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    size_t i;
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*f)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if ((f == NULL) || (x0 == NULL) || (S0 == NULL) || (SQ == NULL) || (SR == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_cub_dims_ok(n, m) == 0) {
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

/* Time update through the cubature points (any process f): X_j = S xi_j + x, X*_j = f(X_j),
 * x- = mean X*_j, and the Tria input [(X*_j - x-)/sqrt(2n), S_Q] (n x 3n) into w->A. */
static rfe_status_t predict_points(rfe_sckf_t *f, rfe_process_fn_t process, void *ctx)
{
    rfe_cub_scratch_t *w = &f->w;
    const size_t n = f->n;
    const rfe_real_t inv_sqrt_2n = RFE_R(1.0) / RFE_SQRT(RFE_R(2.0) * (rfe_real_t)n);
    size_t i;
    size_t j;
    rfe_status_t st;
    rfe_cub_points(f->x, f->S, n, NM, w->pts);
    st = rfe_cub_propagate(w->pts, n, process, ctx, w->xn);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_mean(w->pts, n, n, NM, w->xn);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < (2u * n); ++j) {
            w->A[(i * TC) + j] = (w->pts[(j * NM) + i] - w->xn[i]) * inv_sqrt_2n;
        }
        for (j = 0u; j < n; ++j) {
            w->A[(i * TC) + (2u * n) + j] = f->SQ[(i * NM) + j];
        }
    }
    return RFE_OK;
}

/* Time update of the random walk f(x) = x: its points X_j = x +- sqrt(n) S e_j are
 * symmetric about x, so x- = x exactly, and the centred points +-sqrt(n) S e_j / sqrt(2n)
 * = +-S e_j / sqrt(2) contribute exactly S S^T: S- = Tria([S, S_Q]) (n x 2n) needs no
 * cubature points; k steps at once: Tria([S, sqrt(k) S_Q]) (c = sqrt(k), 1 for one step:
 * bit for bit the one-step product). The Tria input into w->A, x- = x into w->xn. */
static SCKF_INLINE void predict_random_walk(rfe_sckf_t *f, rfe_real_t c, size_t n)
{
    rfe_cub_scratch_t *w = &f->w;
    size_t i;
    size_t j;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            w->A[(i * TC) + j] = f->S[(i * NM) + j];
            w->A[(i * TC) + n + j] = c * f->SQ[(i * NM) + j];
        }
    }
    rfe_cub_hold_random_walk_mean(f->x, n, NULL, w->xn);
}

rfe_status_t rfe_sckf_predict(rfe_sckf_t *f, rfe_process_fn_t process, void *ctx)
{
    size_t n;
    rfe_status_t st;

    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    n = f->n;
    /* S- = Tria([(X*_1 - x-, ..., X*_2n - x-)/sqrt(2n), S_Q]); for the random walk
     * S- = Tria([S, S_Q]). */
    if (process == NULL) {
        /* n = 4 (the firmware's) as a constant: unrolled (issue 21), the same result */
        if (n == 4u) {
            predict_random_walk(f, RFE_R(1.0), 4u);
        } else {
            predict_random_walk(f, RFE_R(1.0), n);
        }
        st = rfe_qr_tria_pair(f->w.A, n, TC); /* S and S_Q lower-triangular */
    } else {
        st = predict_points(f, process, ctx);
        if (st == RFE_OK) {
            st = rfe_qr_tria_lt(f->w.A, n, 3u * n, TC); /* S_Q lower-triangular */
        }
    }
    if (st != RFE_OK) {
        return st;
    }
    if (n == 4u) {
        commit(f, 4u);
    } else {
        commit(f, n);
    }
    return RFE_OK;
}

rfe_status_t rfe_sckf_predict_steps(rfe_sckf_t *f, uint32_t k)
{
    rfe_status_t st;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (k == 0u) {
        return RFE_OK;
    }
    predict_random_walk(f, RFE_SQRT((rfe_real_t)k), f->n);
    st = rfe_qr_tria_pair(f->w.A, f->n, TC); /* S and S_Q triangular */
    if (st != RFE_OK) {
        return st;
    }
    commit(f, f->n);
    return RFE_OK;
}

/* Xc = (X_j - x-)/sqrt(2n) into B (n x 2n) and Zc = (Z_j - z)/sqrt(2n) in place in zpts. */
static SCKF_INLINE void centre_points(rfe_sckf_t *f, size_t n, size_t m)
{
    rfe_cub_scratch_t *w = &f->w;
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

/* Zc = H S- and Xc = S- (k = n columns; issue 21) for a linear h(x) = H x: z = h(x-) and
 * Zc e_j = h(S- e_j), n + 1 evaluations. The third-degree rule is exact for a linear h, and
 * the 2n centred points (X_j - x-)/sqrt(2n) = [S-, -S-]/sqrt(2) (Zc likewise) have the same
 * products Xc Xc^T = S- S-^T, Zc Zc^T = H P H^T, Xc Zc^T = P H^T as these n columns, so every
 * later step is the same algebra on k = n columns (docs/ESTIMATOR.md "The linear update").
 * The columns of S- as points in w->pts (S-'s upper triangle is 0: copy_lower, commit), x-
 * after them. */
static SCKF_INLINE rfe_status_t centre_linear(rfe_sckf_t *f, rfe_measure_fn_t measure,
                                              void *ctx, size_t n, size_t m)
{
    rfe_cub_scratch_t *w = &f->w;
    size_t i;
    size_t j;
    for (j = 0u; j < n; ++j) {
        for (i = 0u; i < n; ++i) {
            w->pts[(j * NM) + i] = f->S[(i * NM) + j];
            w->B[(i * TC) + j] = f->S[(i * NM) + j];
        }
        w->pts[(n * NM) + j] = f->x[j];
    }
    /* h at the n + 1 points, each output checked as rfe_cub_measure checks the rule's (which
     * keeps its 2n, so the generic path's code is unchanged) */
    for (j = 0u; j <= n; ++j) {
        rfe_real_t *z = &w->zpts[j * MM];
        const rfe_status_t st = measure(ctx, &w->pts[j * NM], z, n, m);
        if (st != RFE_OK) {
            return st;
        }
        if (!rfe_all_finite(z, m)) {
            return RFE_ERR_NONFINITE;
        }
    }
    for (i = 0u; i < m; ++i) {
        w->zhat[i] = w->zpts[(n * MM) + i];
    }
    return RFE_OK;
}

/* P_xz[i][r] = sum_j Xc[i][j] Zc[r][j] over the k centred columns (w->B, w->zpts). One
 * definition for the gain and the information, so both use the same sums in the same order. */
static SCKF_INLINE rfe_real_t pxz_element(const rfe_cub_scratch_t *w, size_t r, size_t i, size_t k)
{
    rfe_real_t acc = RFE_R(0.0);
    size_t j;
    for (j = 0u; j < k; ++j) {
        acc += w->zpts[(j * MM) + r] * w->B[(i * TC) + j];
    }
    return acc;
}

/* S_zz = Tria([Zc, S_R]) into w->Szz (needs the k centred columns; uses w->A). */
static SCKF_INLINE rfe_status_t innovation_factor(rfe_sckf_t *f, const rfe_real_t *SR, size_t k,
                                                  size_t m)
{
    rfe_cub_scratch_t *w = &f->w;
    size_t j;
    size_t r;
    rfe_status_t st;
    for (r = 0u; r < m; ++r) {
        for (j = 0u; j < k; ++j) {
            w->A[(r * TC) + j] = w->zpts[(j * MM) + r];
        }
        for (j = 0u; j < m; ++j) {
            w->A[(r * TC) + k + j] = SR[(r * MM) + j];
        }
    }
    st = rfe_qr_tria_lt(w->A, m, k + m, TC); /* S_R triangular */
    if (st == RFE_OK) {
        /* S_zz with its upper part: Tria leaves zeros right of the diagonal (rfe_qr_tria),
         * so a plain copy (no separate zeroing, issue 21), column by column (commit). */
        for (j = 0u; j < m; ++j) {
            for (r = 0u; r < m; ++r) {
                w->Szz[(r * MM) + j] = w->A[(r * TC) + j];
            }
        }
    }
    return st;
}

/* The innovation of the predicted points into *o: y - z_hat, S_zz (w->Szz, which the caller
 * has computed) with its upper part 0, diag(Zc Zc^T). */
static SCKF_INLINE void innovation_out(const rfe_sckf_t *f, const rfe_real_t *y,
                                      rfe_sckf_innov_t *o, size_t k, size_t m)
{
    const rfe_cub_scratch_t *w = &f->w;
    size_t j;
    size_t r;
    /* All of *o is written (0 beyond m): the caller keeps it in its state, which must be
     * fully defined to be copied and compared. Each element once (issue 21: zeroing first
     * cost memset calls); w->Szz's upper part is 0 (innovation_factor). */
    for (r = 0u; r < MM; ++r) {
        rfe_real_t nu = RFE_R(0.0);
        rfe_real_t acc = RFE_R(0.0);
        if (r < m) {
            nu = y[r] - w->zhat[r];
            for (j = 0u; j < k; ++j) {
                acc += w->zpts[(j * MM) + r] * w->zpts[(j * MM) + r];
            }
        }
        o->nu[r] = nu;
        o->zz[r] = acc;
        for (j = 0u; j < MM; ++j) {
            o->Szz[(r * MM) + j] = ((r < m) && (j < m)) ? w->Szz[(r * MM) + j] : RFE_R(0.0);
        }
    }
}

/* S_zz = Tria([Zc, S_R]) into w->Szz; then K^T = S_zz^-T (S_zz^-1 P_xz^T), P_xz = Xc Zc^T.
 * SR: this step's lower-triangular S_R, ld RFE_M_MAX. */
static SCKF_INLINE rfe_status_t gain(rfe_sckf_t *f, const rfe_real_t *SR, size_t n, size_t m,
                                     size_t k)
{
    rfe_cub_scratch_t *w = &f->w;
    size_t i;
    size_t r;
    rfe_status_t st;

    st = innovation_factor(f, SR, k, m);
    if (st != RFE_OK) {
        return st;
    }
    /* P_xz^T (m x n). */
    for (r = 0u; r < m; ++r) {
        for (i = 0u; i < n; ++i) {
            w->Kt[(r * NM) + i] = pxz_element(w, r, i, k);
        }
    }
    /* K = (P_xz / S_zz^T) / S_zz: two triangular solves, never an inverse. */
    st = rfe_qr_solve_lower(w->Szz, m, MM, w->Kt, n, NM);
    if (st == RFE_OK) {
        st = rfe_qr_solve_lower_t(w->Szz, m, MM, w->Kt, n, NM);
    }
    return st;
}

/* P_xz (n x m) = Xc Zc^T into w->A (ld TC): the same sums, in the same order, as the gain's
 * P_xz^T. */
static SCKF_INLINE void cross_covariance(rfe_sckf_t *f, size_t n, size_t m, size_t k)
{
    rfe_cub_scratch_t *w = &f->w;
    size_t i;
    size_t r;
    for (r = 0u; r < m; ++r) {
        for (i = 0u; i < n; ++i) {
            w->A[(i * TC) + r] = pxz_element(w, r, i, k);
        }
    }
}

/* docs/ESTIMATOR.md step 5: I_k = sum_r W_rk^2, W = S_R \ J, J^T = S-^T \ (S- \ P_zx^T).
 * Needs the centred points (w->B, w->zpts); uses w->A and w->Kt as scratch. */
static SCKF_INLINE rfe_status_t information(rfe_sckf_t *f, const rfe_real_t *SR,
                                             rfe_real_t *info, size_t n, size_t m, size_t k)
{
    rfe_cub_scratch_t *w = &f->w;
    size_t i;
    size_t r;
    rfe_status_t st;

    cross_covariance(f, n, m, k);
    /* J^T (n x m) = S-^T \ (S- \ P_xz): statistical linearisation, no inverse of S- S-^T. */
    st = rfe_qr_solve_lower(f->S, n, NM, w->A, m, TC);
    if (st == RFE_OK) {
        st = rfe_qr_solve_lower_t(f->S, n, NM, w->A, m, TC);
    }
    if (st != RFE_OK) {
        return st;
    }
    /* W (m x n) = S_R \ J, J transposed into w->Kt. */
    for (r = 0u; r < m; ++r) {
        for (i = 0u; i < n; ++i) {
            w->Kt[(r * NM) + i] = w->A[(i * TC) + r];
        }
    }
    st = rfe_qr_solve_lower(SR, m, MM, w->Kt, n, NM);
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0u; i < n; ++i) {
        rfe_real_t acc = RFE_R(0.0);
        for (r = 0u; r < m; ++r) {
            acc += w->Kt[(r * NM) + i] * w->Kt[(r * NM) + i];
        }
        info[i] = acc;
    }
    /* An overflow (absurd prior or model) must not pass as "no information". */
    return rfe_all_finite(info, n) ? RFE_OK : RFE_ERR_NONFINITE;
}

/* docs/ESTIMATOR.md steps 5-6: the step's information into info (n) and the gate: *held = 1
 * when info_min > 0 and no state reaches it. Needs the centred points. */
static SCKF_INLINE rfe_status_t gate(rfe_sckf_t *f, const rfe_real_t *SR, rfe_real_t info_min,
                                     rfe_real_t *info, int *held, size_t n, size_t m, size_t k)
{
    const rfe_status_t st = information(f, SR, info, n, m, k);
    *held = 0;
    if (st == RFE_OK) {
        rfe_real_t most = RFE_R(0.0);
        size_t i;
        for (i = 0u; i < n; ++i) {
            most = rfe_max(most, info[i]);
        }
        if ((info_min > RFE_R(0.0)) && (most < info_min)) {
            *held = 1;
        }
    }
    return st;
}

/* Row i of Xc - K Zc (k values) into w->A: element by element the subtractions of
 * K[i][r] Zc[r][j] for r = 0, 1, ... in that order, from Xc[i][j] in a register (issue 21:
 * copying the row first was compiled into a memmove call). */
static SCKF_INLINE void posterior_points_row(rfe_sckf_t *f, size_t i, size_t k, size_t m)
{
    rfe_cub_scratch_t *w = &f->w;
    size_t j;
    size_t r;
    for (j = 0u; j < k; ++j) {
        rfe_real_t acc = w->B[(i * TC) + j];
        for (r = 0u; r < m; ++r) {
            acc -= w->Kt[(r * NM) + i] * w->zpts[(j * MM) + r];
        }
        w->A[(i * TC) + j] = acc;
    }
}

/* [Xc - K Zc, K S_R] (n x (k + m)) into w->A: the Tria input of the posterior factor.
 * Needs the k centred columns (w->B, w->zpts) and the gain (w->Kt). */
static SCKF_INLINE void posterior_tria_input(rfe_sckf_t *f, const rfe_real_t *SR, size_t n,
                                             size_t m, size_t k)
{
    rfe_cub_scratch_t *w = &f->w;
    size_t i;
    size_t j;
    size_t r;
    for (i = 0u; i < n; ++i) {
        posterior_points_row(f, i, k, m);
        for (j = 0u; j < m; ++j) {
            rfe_real_t acc = RFE_R(0.0);
            for (r = j; r < m; ++r) { /* S_R is lower-triangular */
                acc += w->Kt[(r * NM) + i] * SR[(r * MM) + j];
            }
            w->A[(i * TC) + k + j] = acc;
        }
    }
}

/* The measurement update of MODEL.md §6 with S_R = SR (ld RFE_M_MAX), gated on the
 * information when info_min > 0 (docs/ESTIMATOR.md steps 5-6), on k centred columns: the
 * 2n cubature points (k = 2n, any h) or the n columns of S- (k = n, h linear: centre_linear).
 * Writes info (n) when want_info; *updated = 0 when held. Commits x and S only when
 * everything succeeded. */
static SCKF_INLINE rfe_status_t update_body(rfe_sckf_t *f, rfe_measure_fn_t measure, void *ctx,
                                            const rfe_real_t *y, const rfe_real_t *SR,
                                            rfe_real_t info_min, int want_info, rfe_real_t *info,
                                            rfe_sckf_innov_t *innov, int *updated, size_t n,
                                            size_t m, size_t k)
{
    rfe_cub_scratch_t *w = &f->w;
    rfe_status_t st;

    if (k == n) {
        st = centre_linear(f, measure, ctx, n, m);
    } else {
        /* X_j = S- xi_j + x-;  Z_j = h(X_j, u);  z = mean_j Z_j. */
        rfe_cub_points(f->x, f->S, n, NM, w->pts);
        st = rfe_cub_measure(w->pts, n, m, measure, ctx, w->zpts);
        if (st == RFE_OK) {
            rfe_cub_mean(w->zpts, n, m, MM, w->zhat);
            centre_points(f, n, m);
        }
    }
    if (st != RFE_OK) {
        return st;
    }
    if ((want_info != 0) || (info_min > RFE_R(0.0))) {
        int held = 0;
        st = gate(f, SR, info_min, info, &held, n, m, k);
        if (st != RFE_OK) {
            return st;
        }
        if (held != 0) {
            /* held: not observable; x-, S- stay (S_zz computed only for the innovation) */
            if (innov != NULL) {
                st = innovation_factor(f, SR, k, m);
                if (st != RFE_OK) {
                    return st;
                }
                innovation_out(f, y, innov, k, m);
            }
            *updated = 0;
            return RFE_OK;
        }
    }
    st = gain(f, SR, n, m, k);
    if (st != RFE_OK) {
        return st;
    }
    if (innov != NULL) {
        innovation_out(f, y, innov, k, m); /* before the update: the predicted points' */
    }
    /* x = x- + K (y - z); a huge innovation that overflows commits nothing. */
    st = rfe_cub_correct(f->x, w->Kt, y, w->zhat, n, m, NM, w->xn);
    if (st != RFE_OK) {
        return st;
    }
    /* S = Tria([Xc - K Zc, K S_R]). */
    posterior_tria_input(f, SR, n, m, k);
    st = rfe_qr_tria(w->A, n, k + m, TC);
    if (st != RFE_OK) {
        return st;
    }
    commit(f, n);
    *updated = 1;
    return RFE_OK;
}

/* update_body with the firmware's sizes n = 4 states, m = 3 measurements and the 2n = 8
 * points as constants, so the compiler unrolls its short loops (issue 21), or with the
 * filter's run-time sizes; the same operations in the same order either way, so the same
 * results bit for bit. linear != 0: h is linear (k = n columns, centre_linear), run-time
 * sizes only: a third unrolled copy linked 68,076 B on the Cortex-M4F (budget 65,536 B). */
static rfe_status_t update_core(rfe_sckf_t *f, rfe_measure_fn_t measure, void *ctx,
                                const rfe_real_t *y, const rfe_real_t *SR, rfe_real_t info_min,
                                int want_info, rfe_real_t *info, rfe_sckf_innov_t *innov,
                                int *updated, int linear)
{
    rfe_status_t st;
    if ((f->n == 4u) && (f->m == 3u) && (linear == 0)) {
        st = update_body(f, measure, ctx, y, SR, info_min, want_info, info, innov, updated, 4u,
                         3u, 8u);
    } else {
        st = update_body(f, measure, ctx, y, SR, info_min, want_info, info, innov, updated,
                         f->n, f->m, (linear != 0) ? f->n : (2u * f->n));
    }
    return st;
}

/* Common argument checks of the measurement updates. */
static rfe_status_t check_update(const rfe_sckf_t *f, rfe_measure_fn_t measure,
                                 const rfe_real_t *y)
{
    if ((f == NULL) || (measure == NULL) || (y == NULL)) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    return rfe_all_finite(y, f->m) ? RFE_OK : RFE_ERR_NONFINITE;
}

rfe_status_t rfe_sckf_update(rfe_sckf_t *f, rfe_measure_fn_t measure, void *ctx,
                             const rfe_real_t *y)
{
    rfe_real_t info[RFE_N_MAX];
    int updated = 0;
    const rfe_status_t st = check_update(f, measure, y);
    if (st != RFE_OK) {
        return st;
    }
    return update_core(f, measure, ctx, y, f->SR, RFE_R(0.0), 0, info, NULL, &updated, 0);
}

/* rfe_sckf_update_ex (linear 0) and rfe_sckf_update_linear (linear 1): the checks, the step's
 * S_R and the outputs once in the source, inlined into both (a call between them cost the
 * Cortex-M4F's default step ~20 instructions; it has the flash, the M0+ build has no float). */
static SCKF_INLINE rfe_status_t update_ex_common(rfe_sckf_t *f, rfe_measure_fn_t measure, void *ctx,
                                     const rfe_real_t *y, const rfe_real_t *SR,
                                     rfe_real_t info_min, rfe_real_t *info_out,
                                     rfe_sckf_innov_t *innov_out, int *updated, int linear)
{
    rfe_sckf_innov_t innov;
    rfe_real_t SRl[RFE_M_MAX * RFE_M_MAX];
    rfe_real_t info[RFE_N_MAX];
    const rfe_real_t *sr;
    int upd = 0;
    rfe_status_t st = check_update(f, measure, y);

    if ((st == RFE_OK) && (updated == NULL)) {
        st = RFE_ERR_NULL;
    }
    if (st != RFE_OK) {
        return st;
    }
    if (!rfe_is_finite(info_min)) {
        return RFE_ERR_NONFINITE;
    }
    sr = f->SR;
    if (SR != NULL) {
        if (!rfe_lower_finite(SR, f->m, f->m)) {
            return RFE_ERR_NONFINITE;
        }
        copy_lower(SR, f->m, f->m, SRl, MM);
        sr = SRl;
    }
    st = update_core(f, measure, ctx, y, sr, info_min, (info_out != NULL) ? 1 : 0, info,
                     (innov_out != NULL) ? &innov : NULL, &upd, linear);
    if (st != RFE_OK) {
        return st;
    }
    if (innov_out != NULL) {
        *innov_out = innov;
    }
    if (info_out != NULL) {
        size_t i;
        for (i = 0u; i < f->n; ++i) {
            info_out[i] = info[i];
        }
    }
    *updated = upd;
    return RFE_OK;
}

rfe_status_t rfe_sckf_update_ex(rfe_sckf_t *f, rfe_measure_fn_t measure, void *ctx,
                                const rfe_real_t *y, const rfe_real_t *SR,
                                rfe_real_t info_min, rfe_real_t *info_out,
                                rfe_sckf_innov_t *innov_out, int *updated)
{
    return update_ex_common(f, measure, ctx, y, SR, info_min, info_out, innov_out, updated, 0);
}

rfe_status_t rfe_sckf_update_linear(rfe_sckf_t *f, rfe_measure_fn_t measure, void *ctx,
                                    const rfe_real_t *y, const rfe_real_t *SR,
                                    rfe_real_t info_min, rfe_real_t *info_out,
                                    rfe_sckf_innov_t *innov_out, int *updated)
{
    return update_ex_common(f, measure, ctx, y, SR, info_min, info_out, innov_out, updated, 1);
}

rfe_status_t rfe_sckf_scale(rfe_sckf_t *f, rfe_real_t c)
{
    rfe_real_t *cand;
    size_t i;
    size_t j;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (!rfe_is_finite(c) || !(c > RFE_R(0.0))) {
        return RFE_ERR_RANGE;
    }
    /* Candidate c S in the Tria scratch (lower triangle, ld TC), committed when finite. */
    cand = f->w.A;
    for (i = 0u; i < f->n; ++i) {
        for (j = 0u; j <= i; ++j) {
            cand[(i * TC) + j] = c * f->S[(i * NM) + j];
        }
        if (!rfe_all_finite(&cand[i * TC], i + 1u)) {
            return RFE_ERR_NONFINITE;
        }
    }
    for (i = 0u; i < f->n; ++i) {
        for (j = 0u; j <= i; ++j) {
            f->S[(i * NM) + j] = cand[(i * TC) + j];
        }
    }
    return RFE_OK;
}

rfe_status_t rfe_sckf_get(const rfe_sckf_t *f, rfe_real_t *x, rfe_real_t *sd)
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

/* generated by scripts/codegen/twins.py from filter_clamp: do not edit; make twins */
rfe_status_t rfe_sckf_clamp(rfe_sckf_t *f, rfe_real_t lo, rfe_real_t hi, int *clamped)
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
/* end generated */
