/**
 * @file ckf_q31.c
 * @brief Full-covariance cubature Kalman filter on int32 Q values, the paper's baseline
 *        (the twin of ckf_flt.c, MODEL.md §6).
 *
 * Deliberately the textbook form (P = P- - K Pzz K^T, no symmetrisation or Joseph form), as
 * the float twin: it is the comparison the paper makes, here in fixed point. The moment sums
 * are practically exact in int64 (products of two Q values rounded 4 bits below their exact
 * format, Q54 for P), so the cancellation in sum w X X^T - x x^T costs only the rounding of
 * the mean x (0.5 LSB of Q29, i.e. up to 2 |x| 2^-30 in P: ~5 LSB of Q31 for mu ~ 1.2) and
 * the final rounding to Q31.
 *
 * Every step computes into scratch and commits x, P and the saturation count only when
 * everything succeeded.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_CKF_Q31_IMPL
#include "rfe/component/ckf_q31.h"

#include "rfe/component/chol_q31.h"
#include "rfe/component/qr_q31.h"

#include "filters/cubature_q31.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)
#define TC RFE_TRIA_COLS_SZ

/* Internal formats (fractional bits; docs/FIXED_POINT.md "Linear algebra and filters"). */
#define QL 30u   /* chol(P): standard deviations, as S of the SCKF */
#define QLZ 24u  /* chol(Pzz) [m/s^2] */
#define QPXZ 30u /* P_xz, Lz \ P_xz^T and K Pzz [mu m/s^2], +-2 */
#define QK 26u   /* the gain K [mu per m/s^2], +-32 */

static void copy_square_q31(const rfe_fix_t *src, size_t lds, size_t k, rfe_fix_t *dst, size_t ldd)
{
    size_t i;
    size_t j;
    for (i = 0u; i < k; ++i) {
        for (j = 0u; j < k; ++j) {
            dst[(i * ldd) + j] = src[(i * lds) + j];
        }
    }
}

rfe_status_t rfe_ckf_init_q31(rfe_ckf_q31_t *f, size_t n, size_t m, const rfe_fix_t *x0,
                              const rfe_fix_t *P0, const rfe_fix_t *Q, const rfe_fix_t *R,
                              size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    size_t i;
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*f)) || (config != RFE_CONFIG_Q31)) {
        return RFE_ERR_ABI;
    }
    if ((f == NULL) || (x0 == NULL) || (P0 == NULL) || (Q == NULL) || (R == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_cub_dims_ok_q31(n, m) == 0) {
        return RFE_ERR_SIZE;
    }
    f->n = n;
    f->m = m;
    for (i = 0u; i < n; ++i) {
        f->x[i] = x0[i];
    }
    copy_square_q31(P0, n, n, f->P, NM);
    copy_square_q31(Q, n, n, f->Q, NM);
    copy_square_q31(R, m, m, f->R, MM);
    f->sat = 0u;
    f->magic = RFE_MAGIC_CKF_Q31;
    return RFE_OK;
}

/* round(num / den) for 1 <= den <= 16, ties away from zero, in int64 (no saturation). */
static int64_t div_round64(int64_t num, size_t den)
{
    const uint64_t d = (uint64_t)den;
    const uint64_t mag = rfe_q31_mag64_any(num);
    uint64_t q = mag / d;
    int64_t r;
    if ((2u * (mag % d)) >= d) {
        q += 1u;
    }
    r = (int64_t)q; /* num >= -INT64_MAX (rfe_fix_add64): q < 2^63 */
    return (num < 0) ? -r : r;
}

/* Guard bits of the moment sums: 2n <= 16 products of at most 2^62 each are pre-shifted by
 * 4 bits, so their sum stays below 2^62 for every int32 input. */
#define MOMENT_GUARD 4u

/* Second moment about the mean: out = sum_j w a_j b_j^T - abar bbar^T (the paper's form),
 * w = 1/(2n). a rows: na values (stride lda, Q(qa)), b rows: nb values (stride ldb, Q(qb)),
 * 2n rows each; out in Q(qa + qb - shift), shift >= MOMENT_GUARD. The products are formed
 * exactly and rounded to Q(qa + qb - 4) (2^-(qa + qb - 3) each, far below the output LSB),
 * summed exactly, divided by 2n with one rounding; one final rounding. */
static void cross_moment_q31(const rfe_fix_t *a, size_t lda, const rfe_fix_t *abar, size_t na,
                             const rfe_fix_t *b, size_t ldb, const rfe_fix_t *bbar, size_t nb,
                             size_t n, rfe_fix_t *out, size_t ldo, unsigned int shift,
                             uint32_t *count)
{
    size_t i;
    size_t k;
    size_t j;
    for (i = 0u; i < na; ++i) {
        for (k = 0u; k < nb; ++k) {
            int64_t acc = 0;
            for (j = 0u; j < (2u * n); ++j) {
                acc = rfe_fix_add64(acc,
                                    rfe_fix_shr64_round((int64_t)a[(j * lda) + i] *
                                                            (int64_t)b[(j * ldb) + k],
                                                        MOMENT_GUARD),
                                    count);
            }
            acc = rfe_fix_add64(div_round64(acc, 2u * n),
                                -rfe_fix_shr64_round((int64_t)abar[i] * (int64_t)bbar[k],
                                                     MOMENT_GUARD),
                                count);
            out[(i * ldo) + k] = rfe_fix_narrow(acc, shift - MOMENT_GUARD, count);
        }
    }
}

rfe_status_t rfe_ckf_predict_q31(rfe_ckf_q31_t *f, rfe_process_fn_q31_t process, void *ctx)
{
    rfe_cub_scratch_q31_t *w;
    uint32_t count = 0u;
    size_t n;
    size_t i;
    size_t j;
    rfe_status_t st;

    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    w = &f->w;
    n = f->n;
    /* X_j = chol(P) xi_j + x (chol(P) in w.A);  X*_j = f(X_j);  x- = mean X*_j. */
    st = rfe_chol_factor_q31(f->P, n, NM, w->A, NM, RFE_Q31_QP, QL, &count);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_points_q31(f->x, w->A, n, w->pts, &count);
    st = rfe_cub_propagate_q31(w->pts, n, process, ctx, w->xn);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_mean_q31(w->pts, n, n, NM, w->xn);
    /* P- = sum_j w X*_j X*_j^T - x- x-^T + Q: Q29 Q29 = Q58 -> Q31, into w.B. */
    cross_moment_q31(w->pts, NM, w->xn, n, w->pts, NM, w->xn, n, n, w->B, NM,
                     (2u * RFE_Q31_QX) - RFE_Q31_QP, &count);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            w->B[(i * NM) + j] = rfe_fix_add(w->B[(i * NM) + j], f->Q[(i * NM) + j], &count);
        }
    }
    /* The moment above needs the points' own mean; the committed x- of a random walk is x. */
    rfe_cub_hold_random_walk_mean_q31(f->x, n, process, w->xn);
    for (i = 0u; i < n; ++i) {
        f->x[i] = w->xn[i];
    }
    copy_square_q31(w->B, NM, n, f->P, NM);
    rfe_q31_sat_add(&f->sat, count);
    return RFE_OK;
}

rfe_status_t rfe_ckf_predict_steps_q31(rfe_ckf_q31_t *f, uint32_t k)
{
    uint32_t count = 0u;
    size_t n;
    size_t i;
    size_t j;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    n = f->n;
    /* P- = P + k Q: |k Q_ij| < 2^63 exactly in int64, then saturating to Q31; x- = x. */
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            const int64_t kq = (int64_t)f->Q[(i * NM) + j] * (int64_t)k;
            f->P[(i * NM) + j] =
                rfe_fix_add(f->P[(i * NM) + j], rfe_fix_narrow(kq, 0u, &count), &count);
        }
    }
    rfe_q31_sat_add(&f->sat, count);
    return RFE_OK;
}

/* The candidate covariance P = P- - K Pzz K^T into w.B (gain transposed in w.Kt, Q26; Pzz
 * in w.Szz, Q24): T = K Pzz (n x m, Q30, in w.A), then P- - T K^T in Q(30 + 26) -> Q31. */
static void posterior_covariance_q31(rfe_ckf_q31_t *f, uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    size_t i;
    size_t j;
    size_t r;
    size_t s;
    for (i = 0u; i < n; ++i) {
        for (s = 0u; s < m; ++s) {
            int64_t acc = 0;
            for (r = 0u; r < m; ++r) {
                const int64_t kp = (int64_t)w->Kt[(r * NM) + i] * (int64_t)w->Szz[(r * MM) + s];
                acc = rfe_fix_add64(acc, kp, count);
            }
            w->A[(i * TC) + s] = rfe_fix_narrow(acc, (QK + RFE_Q31_QR) - QPXZ, count);
        }
    }
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            int64_t acc = 0;
            for (s = 0u; s < m; ++s) {
                acc = rfe_fix_add64(acc, (int64_t)w->A[(i * TC) + s] * (int64_t)w->Kt[(s * NM) + j],
                                    count);
            }
            w->B[(i * NM) + j] = rfe_fix_sub(f->P[(i * NM) + j],
                                              rfe_fix_narrow(acc, (QPXZ + QK) - RFE_Q31_QP, count),
                                              count);
        }
    }
}

/* K^T = Lz^-T (Lz^-1 Pxz^T) in w.Kt, Lz = chol(Pzz) (Pzz in w.Szz, Pxz^T in w.Kt). */
static rfe_status_t ckf_gain(rfe_ckf_q31_t *f, uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    rfe_status_t st = rfe_chol_factor_q31(w->Szz, m, MM, w->Lz, MM, RFE_Q31_QR, QLZ, count);
    if (st == RFE_OK) {
        /* Q30 by Q24 into Q30 (mu) */
        st = rfe_qr_solve_lower_q31(w->Lz, m, MM, w->Kt, n, NM, (int)QPXZ - (int)QPXZ + (int)QLZ,
                                    count);
    }
    if (st == RFE_OK) {
        /* Q30 by Q24 into Q26 (mu per m/s^2) */
        st = rfe_qr_solve_lower_t_q31(w->Lz, m, MM, w->Kt, n, NM, (int)QK - (int)QPXZ + (int)QLZ,
                                      count);
    }
    return st;
}

rfe_status_t rfe_ckf_update_q31(rfe_ckf_q31_t *f, rfe_measure_fn_q31_t measure, void *ctx,
                                const rfe_fix_t *y)
{
    rfe_cub_scratch_q31_t *w;
    uint32_t count = 0u;
    size_t n;
    size_t m;
    size_t i;
    size_t r;
    rfe_status_t st;

    if ((f == NULL) || (measure == NULL) || (y == NULL)) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    w = &f->w;
    n = f->n;
    m = f->m;
    /* X_j = chol(P-) xi_j + x- (chol(P-) in w.A);  Z_j = h(X_j);  z = mean Z_j. */
    st = rfe_chol_factor_q31(f->P, n, NM, w->A, NM, RFE_Q31_QP, QL, &count);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_points_q31(f->x, w->A, n, w->pts, &count);
    st = rfe_cub_measure_q31(w->pts, n, m, measure, ctx, w->zpts);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_mean_q31(w->zpts, n, m, MM, w->zhat);
    /* Pzz = sum w Z Z^T - z z^T + R (Q24 Q24 = Q48 -> Q24);
     * Pxz^T = sum w Z X^T - z x-^T (m x n, Q24 Q29 = Q53 -> Q30). */
    cross_moment_q31(w->zpts, MM, w->zhat, m, w->zpts, MM, w->zhat, m, n, w->Szz, MM,
                     (2u * RFE_Q31_QZ) - RFE_Q31_QR, &count);
    for (r = 0u; r < m; ++r) {
        for (i = 0u; i < m; ++i) {
            w->Szz[(r * MM) + i] = rfe_fix_add(w->Szz[(r * MM) + i], f->R[(r * MM) + i], &count);
        }
    }
    cross_moment_q31(w->zpts, MM, w->zhat, m, w->pts, NM, f->x, n, n, w->Kt, NM,
                     (RFE_Q31_QZ + RFE_Q31_QX) - QPXZ, &count);
    /* K = Pxz Pzz^-1 via Pzz = Lz Lz^T: K^T = Lz^-T (Lz^-1 Pxz^T). */
    st = ckf_gain(f, &count);
    if (st != RFE_OK) {
        return st;
    }
    /* x = x- + K (y - z): Q26 Q24 = Q50 -> Q29. */
    for (r = 0u; r < m; ++r) {
        w->Lz[r] = rfe_fix_sub(y[r], w->zhat[r], &count); /* Lz no longer needed */
    }
    for (i = 0u; i < n; ++i) {
        int64_t acc = (int64_t)f->x[i] * rfe_q31_pow2((QK + RFE_Q31_QZ) - RFE_Q31_QX);
        for (r = 0u; r < m; ++r) {
            acc = rfe_fix_add64(acc, (int64_t)w->Kt[(r * NM) + i] * (int64_t)w->Lz[r], &count);
        }
        w->xn[i] = rfe_fix_narrow(acc, (QK + RFE_Q31_QZ) - RFE_Q31_QX, &count);
    }
    /* P = P- - K Pzz K^T. */
    posterior_covariance_q31(f, &count);
    for (i = 0u; i < n; ++i) {
        f->x[i] = w->xn[i];
    }
    copy_square_q31(w->B, NM, n, f->P, NM);
    rfe_q31_sat_add(&f->sat, count);
    return RFE_OK;
}

rfe_status_t rfe_ckf_get_q31(const rfe_ckf_q31_t *f, rfe_fix_t *x, rfe_fix_t *sd)
{
    uint32_t never = 0u; /* sqrt of a Q31 value into Q30 is below 1: never saturates */
    size_t i;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    for (i = 0u; i < f->n; ++i) {
        if (x != NULL) {
            x[i] = f->x[i];
        }
        if (sd != NULL) {
            /* A negative diagonal (P no longer positive semi-definite) reports sd 0. */
            rfe_fix_t v = 0;
            const rfe_fix_t var = rfe_fix_max(f->P[(i * NM) + i], 0);
            const rfe_status_t st = rfe_fix_sqrt(var, RFE_Q31_QP, RFE_Q31_QS, &v, &never);
            (void)st; /* the arguments are always in the domain */
            sd[i] = v;
        }
    }
    return RFE_OK;
}

/* generated by scripts/codegen/twins.py from filter_clamp: do not edit; make twins */
rfe_status_t rfe_ckf_clamp_q31(rfe_ckf_q31_t *f, rfe_fix_t lo, rfe_fix_t hi, int *clamped)
{
    if ((f == NULL) || (clamped == NULL)) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_CKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (lo > hi) { /* every Q value is finite */
        return RFE_ERR_RANGE;
    }
    *clamped = rfe_clamp_vec_q31(f->x, f->n, lo, hi);
    return RFE_OK;
}
/* end generated */
