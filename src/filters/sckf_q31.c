/**
 * @file sckf_q31.c
 * @brief Square-root cubature Kalman filter on int32 Q values (the twin of sckf_flt.c,
 *        MODEL.md §6, docs/ESTIMATOR.md steps 5-7).
 *
 * Every step computes into scratch and commits x, S and the saturation count only when
 * everything succeeded, so an error leaves the filter exactly as it was.
 *
 * The measurement update is the float twin's algebra in whitened form, chosen because every
 * intermediate then has a range known in advance (what a fixed-point format needs):
 * Xc, Zc have k columns: the 2n centred cubature points, or for a linear h the n columns
 * Xc = S-, Zc = H S- (rfe_sckf_update_linear_q31; the same products Xc Xc^T, Zc Zc^T, Xc Zc^T,
 * so every bound below, on W W^T and on row norms, holds for both):
 *  - W = S_zz \ [Zc, S_R] (m x (k + m)): S_zz S_zz^T = Zc Zc^T + S_R S_R^T, so W W^T = I,
 *    every |W_rj| <= 1 (Q30, format QW);
 *  - G = [Xc 0] W^T = P_xz S_zz^-T = K S_zz (n x m): |G_ir| <= |row i of Xc| = sd_i (Q30);
 *  - e = S_zz \ (y - z): the innovation in units of its own sd (Q24, format QE; an innovation
 *    beyond 128 sd saturates, counted);
 *  - x = x- + G e = x- + K (y - z);  S = Tria([Xc, 0] - G W) = Tria([Xc - K Zc, K S_R]).
 * The information of update_ex (docs/ESTIMATOR.md step 5) is the float twin's sequence of
 * solves with the first one moved onto Xc: S- \ P_xz = (S- \ Xc) Zc^T, U = S- \ Xc (Q30,
 * ~ +-1/sqrt(2) e_k; I for the linear form), then J^T = S-^T \ (U Zc^T) (Q20, format QJ),
 * S_R \ J (Q16, format QV), I_k in Q10.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_SCKF_Q31_IMPL
#include "rfe/component/sckf_q31.h"

#include "rfe/component/qr_q31.h"

#include "filters/cubature_q31.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)
#define TC RFE_TRIA_COLS_SZ

/* Internal formats (fractional bits; docs/FIXED_POINT.md "Linear algebra and filters"). */
#define QW 30u /* U = S- \ Xc, W = S_zz \ [Zc, S_R], G = [Xc 0] W^T: dimensionless / mu */
#define QE 24u /* whitened innovation S_zz \ (y - z) [sd] */
#define QJ 20u /* statistical linearisation J [m/s^2 per mu], +-2048 */
#define QV 16u /* S_R \ J [1/mu], +-32768 */

/* Copies the lower triangle of a k x k matrix (src stride lds) into dst (stride ldd),
 * zeroing dst's upper triangle. */
static void copy_lower_q31(const rfe_fix_t *src, size_t lds, size_t k, rfe_fix_t *dst, size_t ldd)
{
    size_t i;
    size_t j;
    for (i = 0u; i < k; ++i) {
        for (j = 0u; j < k; ++j) {
            dst[(i * ldd) + j] = (j <= i) ? src[(i * lds) + j] : 0;
        }
    }
}

/* The OR of the magnitudes |M_ij| (i < rows, j < cols, stride ld; |INT32_MIN| = 2^31 as a
 * uint32): its bit length is that of the largest |M_ij|. */
static uint32_t mag_or_q31(const rfe_fix_t *M, size_t rows, size_t cols, size_t ld)
{
    uint32_t any = 0u;
    size_t i;
    size_t j;
    for (i = 0u; i < rows; ++i) {
        for (j = 0u; j < cols; ++j) {
            const rfe_fix_t v = M[(i * ld) + j];
            const uint32_t uv = (uint32_t)v;
            const uint32_t nv = 0u - uv;
            const uint32_t mv = ((uv >> 31) != 0u) ? nv : uv; /* v < 0: its sign bit */
            any |= mv;
        }
    }
    return any;
}

/* The bit length of the largest |M_ij| (mag_or_q31's). */
static unsigned int mag_bits_q31(const rfe_fix_t *M, size_t rows, size_t cols, size_t ld)
{
    return rfe_q31_bitlen32(mag_or_q31(M, rows, cols, ld));
}

/* 1 when terms products of magnitudes below 2^bits (the two factors' bit lengths summed) sum
 * below 2^limit: terms 2^bits <= 2^(bitlen(terms) + bits). Then every partial sum of such
 * products is inside int64 (limit <= 63) and a saturating accumulation would neither
 * saturate nor count: the plain int64 sum is the same integer (docs/FIXED_POINT.md "The SCKF
 * update's unsaturated sums"; test_sckf_sums_q31.c). */
static int sums_fit_q31(unsigned int bits, size_t terms, unsigned int limit)
{
    return ((bits + rfe_q31_bitlen32((uint32_t)terms)) <= limit) ? 1 : 0;
}

#if RFE_FIX_MUL64_W16
/* The exact sum acc + sum_k a_k b_k (|result| < 2^63, sums_fit_q31) where the core has no
 * 32 x 32 -> 64 multiply (Thumb-1), modulo 2^64 (exact, the result fitting int64) in 32-bit
 * words hi:lo. With ua = a mod 2^32, a = ua - 2^32 [a < 0], so a b = ua ub - 2^32 ([b < 0] ua
 * + [a < 0] ub) modulo 2^64: a correction of the high word only. ua ub = ah bh 2^32 +
 * (al bh + ah bl) 2^16 + al bl in 16-bit halves: al bl adds to lo (its carry to hi), ah bh to
 * hi, the middle products to a word mid whose carries are 2^48 = 2^16 on hi, and mid 2^16
 * once at the end. Eight live words, so the Thumb-1 core's registers hold the loop (~30
 * instructions a product on the Cortex-M0+ against ~60 for the signed 64-bit product and sum
 * term by term); the same integer (test/numerics/w16/test_sckf_sums_q31.c). */
static int64_t dot_exact_w16(int64_t acc, const rfe_fix_t *a, size_t sa, const rfe_fix_t *b,
                             size_t sb, size_t len)
{
    const uint64_t u = (uint64_t)acc; /* modulo 2^64 */
    uint32_t lo = (uint32_t)u;
    uint32_t hi = (uint32_t)(u >> 32);
    uint32_t mid = 0u;
    uint64_t s;
    uint64_t below; /* s - 2^63 */
    const rfe_fix_t *pa = a;
    const rfe_fix_t *pb = b;
    size_t k;
    for (k = len; k != 0u; --k) {
        const uint32_t ua = (uint32_t)*pa;
        const uint32_t ub = (uint32_t)*pb;
        const uint32_t ll = (ua & 0xFFFFu) * (ub & 0xFFFFu);
        const uint32_t m1 = (ua & 0xFFFFu) * (ub >> 16);
        const uint32_t m2 = (ua >> 16) * (ub & 0xFFFFu);
        lo += ll;
        hi += (ua >> 16) * (ub >> 16);
        hi -= ((0u - (ub >> 31)) & ua) + ((0u - (ua >> 31)) & ub);
        if (lo < ll) {
            hi += 1u;
        }
        mid += m1;
        if (mid < m1) {
            hi += 0x10000u;
        }
        mid += m2;
        if (mid < m2) {
            hi += 0x10000u;
        }
        pa = &pa[sa];
        pb = &pb[sb];
    }
    s = (((uint64_t)hi << 32) | (uint64_t)lo) + ((uint64_t)mid << 16);
    /* back to int64 (s >= 2^63 stands for s - 2^64: s - 2^63 converts exactly, then less
     * 2^63 in int64, down to INT64_MIN without overflow) */
    below = s - ((uint64_t)1 << 63);
    return ((s >> 63) != 0u) ? (((int64_t)below - INT64_MAX) - 1) : (int64_t)s;
}
#endif

/* acc + sum_k a[k sa] b[k sb] (k < len): plain int64 sums where exact (sums_fit_q31 said no
 * partial sum can leave int64), else saturating (counted), the same integers either way. */
static int64_t dot_q31(int64_t acc, const rfe_fix_t *a, size_t sa, const rfe_fix_t *b,
                       size_t sb, size_t len, int exact, uint32_t *count)
{
    int64_t s = acc;
    size_t k;
    if (exact != 0) {
#if RFE_FIX_MUL64_W16
        s = dot_exact_w16(acc, a, sa, b, sb, len);
#else
        for (k = 0u; k < len; ++k) {
            s += rfe_fix_mul32x32(a[k * sa], b[k * sb]);
        }
#endif
    } else {
        for (k = 0u; k < len; ++k) {
            s = rfe_fix_add64(s, rfe_fix_mul32x32(a[k * sa], b[k * sb]), count);
        }
    }
    return s;
}

/* Accepts a step: the candidate mean (w.xn) and factor (Tria output in M, ld TC) become the
 * state, and the step's saturation events are added to the counter. */
static void commit_q31(rfe_sckf_q31_t *f, const rfe_fix_t *M, uint32_t count)
{
    size_t i;
    for (i = 0u; i < f->n; ++i) {
        f->x[i] = f->w.xn[i];
    }
    copy_lower_q31(M, TC, f->n, f->S, NM);
    rfe_q31_sat_add(&f->sat, count);
}

rfe_status_t rfe_sckf_init_q31(rfe_sckf_q31_t *f, size_t n, size_t m, const rfe_fix_t *x0,
                               const rfe_fix_t *S0, const rfe_fix_t *SQ, const rfe_fix_t *SR,
                               size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    size_t i;
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*f)) || (config != RFE_CONFIG_Q31)) {
        return RFE_ERR_ABI;
    }
    if ((f == NULL) || (x0 == NULL) || (S0 == NULL) || (SQ == NULL) || (SR == NULL)) {
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
    copy_lower_q31(S0, n, n, f->S, NM);
    copy_lower_q31(SQ, n, n, f->SQ, NM);
    copy_lower_q31(SR, m, m, f->SR, MM);
    f->sat = 0u;
    f->magic = RFE_MAGIC_SCKF_Q31;
    return RFE_OK;
}

/* The random walk's predict from the factor, once the caller has put its right block B
 * (n x n, lower-triangular: S_Q, or sqrt(k) S_Q) into columns n..2n-1 of w->A: S- =
 * Tria([S, B]) (rfe_qr_tria_pair_q31: S and B triangular), x- = x, committed with the
 * caller's saturation count. */
static rfe_status_t walk_commit_q31(rfe_sckf_q31_t *f, uint32_t count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    uint32_t cnt = count;
    size_t i;
    size_t j;
    rfe_status_t st;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) { /* with S's zeros: Tria reads them */
            w->A[(i * TC) + j] = f->S[(i * NM) + j];
        }
        w->xn[i] = f->x[i];
    }
    st = rfe_qr_tria_pair_q31(w->A, n, TC, &cnt);
    if (st != RFE_OK) {
        return st;
    }
    commit_q31(f, w->A, cnt);
    return RFE_OK;
}

/* The random walk: X*_j = X_j = x +- sqrt(n) S e_j, so x- = x and the centred points are
 * [S, -S] / sqrt(2) with [S, -S] [S, -S]^T / 2 = S S^T: S- = Tria([S, S_Q]) (n x 2n) from the
 * factor itself, without rounding the points to Q29 and the deviations to Q30
 * (docs/FIXED_POINT.md "The random walk's predict from the factor itself"). */
static rfe_status_t predict_walk_q31(rfe_sckf_q31_t *f)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    size_t i;
    size_t j;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j <= i; ++j) {
            w->A[(i * TC) + n + j] = f->SQ[(i * NM) + j];
        }
    }
    return walk_commit_q31(f, 0u);
}

rfe_status_t rfe_sckf_predict_q31(rfe_sckf_q31_t *f, rfe_process_fn_q31_t process, void *ctx)
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
    if (f->magic != RFE_MAGIC_SCKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    w = &f->w;
    n = f->n;
    if (process == NULL) {
        return predict_walk_q31(f);
    }
    /* X_j = S xi_j + x;  X*_j = f(X_j);  x- = mean_j X*_j. */
    rfe_cub_points_q31(f->x, f->S, n, w->pts, &count);
    st = rfe_cub_propagate_q31(w->pts, n, process, ctx, w->xn);
    if (st != RFE_OK) {
        return st;
    }
    rfe_cub_mean_q31(w->pts, n, n, NM, w->xn);
    /* S- = Tria([(X*_1 - x-, ..., X*_2n - x-)/sqrt(2n), S_Q]): Q29 deviations -> Q30. */
    for (i = 0u; i < n; ++i) {
        rfe_cub_centre_vec_q31(&w->pts[i], NM, w->xn[i], n, RFE_Q31_QX, RFE_Q31_QS,
                               &w->A[i * TC], 1u, &count);
        for (j = 0u; j < n; ++j) {
            w->A[(i * TC) + (2u * n) + j] = f->SQ[(i * NM) + j];
        }
    }
    st = rfe_qr_tria_lt_q31(w->A, n, 3u * n, TC, &count); /* S_Q triangular */
    if (st != RFE_OK) {
        return st;
    }
    commit_q31(f, w->A, count);
    return RFE_OK;
}

rfe_status_t rfe_sckf_predict_steps_q31(rfe_sckf_q31_t *f, uint32_t k)
{
    rfe_cub_scratch_q31_t *w;
    uint32_t count = 0u;
    uint64_t root;
    size_t n;
    size_t i;
    size_t j;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (k == 0u) {
        return RFE_OK;
    }
    w = &f->w;
    n = f->n;
    /* sqrt(k) in Q16 (<= 2^32); |SQ_ij sqrt(k)| < 2^63 in int64, rounded once to Q30. The
     * random walk's points are symmetric about x: S- = Tria([S, sqrt(k) S_Q]), x- = x. */
    root = rfe_q31_sqrt_round(((uint64_t)k) << 32u);
    for (i = 0u; i < n; ++i) {
        /* Q30 holds sd < 2: no more than sqrt(k) sd(S_Q row) = 1 (root <= 2^46 / |row|) */
        rfe_fix_t qn = 0;
        uint32_t unused = 0u;
        const rfe_status_t nst = rfe_fix_norm(&f->SQ[i * NM], i + 1u, &qn, &unused);
        (void)nst; /* fails only for NULL arguments, which these are not */
        if ((qn > 0) && (root > (((uint64_t)1u << 46u) / (uint64_t)qn))) {
            root = ((uint64_t)1u << 46u) / (uint64_t)qn;
        }
    }
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j <= i; ++j) {
            const int64_t prod = (int64_t)f->SQ[(i * NM) + j] * (int64_t)root;
            w->A[(i * TC) + n + j] = rfe_fix_narrow(prod, 16u, &count);
        }
    }
    return walk_commit_q31(f, count);
}

/* Xc = (X_j - x-)/sqrt(2n) into B (n x 2n, Q30) and Zc = (Z_j - z)/sqrt(2n) in place in
 * zpts (Q24). */
static void centre_points_q31(rfe_sckf_q31_t *f, uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    size_t i;
    for (i = 0u; i < n; ++i) {
        rfe_cub_centre_vec_q31(&w->pts[i], NM, f->x[i], n, RFE_Q31_QX, RFE_Q31_QS,
                               &w->B[i * TC], 1u, count);
    }
    for (i = 0u; i < m; ++i) {
        rfe_cub_centre_vec_q31(&w->zpts[i], MM, w->zhat[i], n, RFE_Q31_QZ, RFE_Q31_QZ,
                               &w->zpts[i], MM, count);
    }
}

/* The linear form (sckf_flt.c's centre_linear; issue 21): z = h(x-), Xc = S- (n x n, Q30:
 * the factor itself, exact) into B, Zc = [h(S- e_1) .. h(S- e_n)] (Q24) in zpts: the columns
 * of S- rounded to Q29 as the callback's points (|S_ij| < 2 fits Q29's range of 4). The
 * entries of Zc are sqrt(2) times the generic ones ((Z_j - z)/sqrt(2n) = +-H S- e_j/sqrt(2))
 * with the same row norms sqrt((H P H^T)_rr) (Zc Zc^T = H P H^T either way), and each is
 * an output of h, in Q24's range like any Z_j; the bounds the update relies on are on row
 * norms and on W W^T = I, |G_ir| <= sd_i (the file's head), which hold as they did. */
static rfe_status_t centre_linear_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure,
                                      void *ctx)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    size_t i;
    size_t j;
    for (j = 0u; j < n; ++j) {
        for (i = 0u; i < n; ++i) {
            const rfe_fix_t s = f->S[(i * NM) + j];
            w->pts[(j * NM) + i] = rfe_fix_shr_round(s, RFE_Q31_QS - RFE_Q31_QX);
            w->B[(i * TC) + j] = s;
        }
        w->pts[(n * NM) + j] = f->x[j];
    }
    /* h at the n + 1 points (rfe_cub_measure_q31 keeps the rule's 2n: the generic code is
     * unchanged) */
    for (j = 0u; j <= n; ++j) {
        const rfe_status_t st = measure(ctx, &w->pts[j * NM], &w->zpts[j * MM], n, f->m);
        if (st != RFE_OK) {
            return st;
        }
    }
    for (i = 0u; i < f->m; ++i) {
        w->zhat[i] = w->zpts[(n * MM) + i];
    }
    return RFE_OK;
}

/* z, Xc (w->B) and Zc (w->zpts): the 2n centred cubature points (linear 0: X_j = S- xi_j + x-,
 * Z_j = h(X_j, u), z = mean_j Z_j), or the linear form's n columns (centre_linear_q31). */
static rfe_status_t centre_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure, void *ctx,
                               int linear, uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    rfe_status_t st;
    if (linear != 0) {
        st = centre_linear_q31(f, measure, ctx);
    } else {
        rfe_cub_points_q31(f->x, f->S, f->n, w->pts, count);
        st = rfe_cub_measure_q31(w->pts, f->n, f->m, measure, ctx, w->zpts);
        if (st == RFE_OK) {
            rfe_cub_mean_q31(w->zpts, f->n, f->m, MM, w->zhat);
            centre_points_q31(f, count);
        }
    }
    return st;
}

/* [Zc, S_R] (m x (k + m), Q24) into w->A (k: the centred columns, 2n or n). */
static void innovation_array(rfe_sckf_q31_t *f, const rfe_fix_t *SR, size_t k)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t m = f->m;
    size_t j;
    size_t r;
    for (r = 0u; r < m; ++r) {
        for (j = 0u; j < k; ++j) {
            w->A[(r * TC) + j] = w->zpts[(j * MM) + r];
        }
        for (j = 0u; j < m; ++j) {
            w->A[(r * TC) + k + j] = SR[(r * MM) + j];
        }
    }
}

/* S_zz = Tria([Zc, S_R]) into w->Szz (Q24); W = S_zz \ [Zc, S_R] into w->A (m rows, Q30);
 * the whitened gain G = Xc Y^T (Y: the first k columns of W) transposed into w->Kt (m x n,
 * Q30). SR: this step's lower-triangular S_R, ld RFE_M_MAX. */
/* S_zz = Tria([Zc, S_R]) into w->Szz (Q24; needs the k centred columns, uses w->A). */
static rfe_status_t innovation_factor_q31(rfe_sckf_q31_t *f, const rfe_fix_t *SR, size_t k,
                                          uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    rfe_status_t st;
    innovation_array(f, SR, k);
    st = rfe_qr_tria_lt_q31(w->A, f->m, k + f->m, TC, count); /* S_R triangular */
    if (st == RFE_OK) {
        copy_lower_q31(w->A, TC, f->m, w->Szz, MM);
    }
    return st;
}

/* The innovation of the predicted points into *o (sckf_flt.c's innovation_out): y - z_hat,
 * S_zz (w->Szz, computed by the caller) with its upper part 0, diag(Zc Zc^T) (Q48 -> Q24). */
static void innovation_out_q31(const rfe_sckf_q31_t *f, const rfe_fix_t *y,
                               rfe_sckf_innov_q31_t *o, size_t k, uint32_t *count)
{
    const rfe_cub_scratch_q31_t *w = &f->w;
    const size_t m = f->m;
    size_t j;
    size_t r;
    /* All of *o is written (0 beyond m): the caller keeps it in its state, which must be
     * fully defined to be copied and compared. */
    for (r = 0u; r < MM; ++r) {
        o->nu[r] = 0;
        o->zz[r] = 0;
        for (j = 0u; j < MM; ++j) {
            o->Szz[(r * MM) + j] = 0;
        }
    }
    for (r = 0u; r < m; ++r) {
        int64_t acc = 0;
        o->nu[r] = rfe_fix_sub(y[r], w->zhat[r], count);
        for (j = 0u; j < k; ++j) {
            const int64_t z = (int64_t)w->zpts[(j * MM) + r];
            acc = rfe_fix_add64(acc, z * z, count);
        }
        o->zz[r] = rfe_fix_narrow(acc, RFE_Q31_QZ, count);
        for (j = 0u; j <= r; ++j) {
            o->Szz[(r * MM) + j] = w->Szz[(r * MM) + j];
        }
    }
}

/* *w_or: mag_or_q31 of W's first k columns (posterior_tria_input_q31 reuses it; W stays in
 * w->A until then). */
static rfe_status_t gain_q31(rfe_sckf_q31_t *f, const rfe_fix_t *SR, size_t k, uint32_t *w_or,
                             uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    size_t i;
    size_t r;
    int exact;
    rfe_status_t st;

    st = innovation_factor_q31(f, SR, k, count);
    if (st != RFE_OK) {
        return st;
    }
    /* W = S_zz \ [Zc, S_R]: Q24 by Q24 into Q30, shift = 30 - 24 + 24. */
    innovation_array(f, SR, k);
    st = rfe_qr_solve_lower_q31(w->Szz, m, MM, w->A, k + m, TC,
                                (int)QW - (int)RFE_Q31_QZ + (int)RFE_Q31_QZ, count);
    if (st != RFE_OK) {
        return st;
    }
    /* G^T[r][i] = sum_j W[r][j] Xc[i][j]: Q30 Q30 = Q60 -> Q30. Unsaturated where k terms
     * of the largest magnitudes cannot reach 2^63 (sums_fit_q31; the same integers). */
    *w_or = mag_or_q31(w->A, m, k, TC);
    exact = sums_fit_q31(rfe_q31_bitlen32(*w_or) + mag_bits_q31(w->B, n, k, TC), k, 63u);
    for (r = 0u; r < m; ++r) {
        for (i = 0u; i < n; ++i) {
            const int64_t acc = dot_q31(0, &w->A[r * TC], 1u, &w->B[i * TC], 1u, k, exact,
                                        count);
            w->Kt[(r * NM) + i] = rfe_fix_narrow(acc, RFE_Q31_QS, count); /* Q(QW + QS) -> QW */
        }
    }
    return RFE_OK;
}

/* x = x- + G (S_zz \ (y - z)) into w->xn (needs w->Szz, w->Kt). */
static rfe_status_t correct(rfe_sckf_q31_t *f, const rfe_fix_t *y, uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    rfe_fix_t e[RFE_M_MAX];
    size_t i;
    size_t r;
    rfe_status_t st;

    for (r = 0u; r < m; ++r) {
        e[r] = rfe_fix_sub(y[r], w->zhat[r], count);
    }
    /* e = S_zz \ (y - z): Q24 by Q24 into Q24. */
    st = rfe_qr_solve_lower_q31(w->Szz, m, MM, e, 1u, 1u,
                                (int)QE - (int)RFE_Q31_QZ + (int)RFE_Q31_QZ, count);
    if (st != RFE_OK) {
        return st;
    }
    /* x_i + sum_r G_ir e_r in Q(30 + 24) = Q54, rounded to Q29. */
    for (i = 0u; i < n; ++i) {
        int64_t acc = (int64_t)f->x[i] * rfe_q31_pow2((QW + QE) - RFE_Q31_QX);
        for (r = 0u; r < m; ++r) {
            acc = rfe_fix_add64(acc, rfe_fix_mul32x32(w->Kt[(r * NM) + i], e[r]), count);
        }
        w->xn[i] = rfe_fix_narrow(acc, (QW + QE) - RFE_Q31_QX, count);
    }
    return RFE_OK;
}

/* [Xc, 0] - G W (n x (k + m), Q30) in place of Xc in w->B: the Tria input of the posterior
 * factor, [Xc - K Zc, K S_R]. Needs W (w->A), G^T (w->Kt) and gain_q31's w_or. */
static void posterior_tria_input_q31(rfe_sckf_q31_t *f, size_t k, uint32_t w_or,
                                     uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    size_t i;
    size_t j;
    /* |Xc_ij 2^30| <= 2^61: unsaturated where m terms of the largest magnitudes stay below
     * 2^62 (the sum then below 2^61 + 2^62 < 2^63; sums_fit_q31; the same integers) */
    const uint32_t a_or = w_or | mag_or_q31(&w->A[k], m, m, TC); /* all of W */
    const int exact = sums_fit_q31(mag_bits_q31(w->Kt, m, n, NM) + rfe_q31_bitlen32(a_or), m,
                                   62u);
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < (k + m); ++j) {
            int64_t acc = (j < k)
                              ? ((int64_t)w->B[(i * TC) + j] * rfe_q31_pow2(QW))
                              : 0;
            /* acc - sum_r G_ir W_rj as -(-acc + sum): the saturation is odd-symmetric
             * ([-INT64_MAX, INT64_MAX]), so the same integers and count */
            acc = -dot_q31(-acc, &w->Kt[i], NM, &w->A[j], TC, m, exact, count);
            w->B[(i * TC) + j] = rfe_fix_narrow(acc, QW, count);
        }
    }
}

/* S- \ P_xz = U Zc^T (n x m) into columns k.. of w->A, U = S- \ Xc in its first k columns:
 * Q30 Q24 = Q54 -> Q24. */
static void project_innovations(rfe_sckf_q31_t *f, size_t k, uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    size_t i;
    size_t j;
    size_t r;
    for (i = 0u; i < n; ++i) {
        const rfe_fix_t *u = &w->A[i * TC];
        for (r = 0u; r < f->m; ++r) {
            int64_t acc = 0;
            for (j = 0u; j < k; ++j) {
                acc = rfe_fix_add64_hot(acc, rfe_fix_mul32x32(u[j], w->zpts[(j * MM) + r]), count);
            }
            w->A[(i * TC) + k + r] = rfe_fix_narrow(acc, QW, count);
        }
    }
}

/* I_k = sum_r V_rk^2 from V (m x n, Q16) in w->Kt: Q32 -> Q10, saturating (counted) above
 * 2.1e6 1/mu^2. */
static void sum_squares(const rfe_sckf_q31_t *f, rfe_fix_t *info, uint32_t *count)
{
    size_t i;
    size_t r;
    for (i = 0u; i < f->n; ++i) {
        int64_t acc = 0;
        for (r = 0u; r < f->m; ++r) {
            const int64_t v = (int64_t)f->w.Kt[(r * NM) + i];
            acc = rfe_fix_add64(acc, v * v, count);
        }
        info[i] = rfe_fix_narrow(acc, (2u * QV) - RFE_Q31_QI, count);
    }
}

/* docs/ESTIMATOR.md step 5: I_k = sum_r V_rk^2, V = S_R \ J, J^T = S-^T \ (U Zc^T),
 * U = S- \ Xc. Needs the centred points (w->B, w->zpts); uses w->A and w->Kt as scratch.
 * info in Q10. */
static rfe_status_t information_q31(rfe_sckf_q31_t *f, const rfe_fix_t *SR, rfe_fix_t *info,
                                    size_t k, uint32_t *count)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    size_t i;
    size_t r;
    rfe_status_t st;

    /* U = S- \ Xc (n x k): Q30 by Q30 into Q30 (the linear form's Xc = S-: U = I, entries
     * 0 and 1, inside Q30's range of 2 as the generic +-1/sqrt(2) e_k). */
    for (i = 0u; i < (n * TC); ++i) {
        w->A[i] = w->B[i];
    }
    st = rfe_qr_solve_lower_q31(f->S, n, NM, w->A, k, TC,
                                (int)QW - (int)RFE_Q31_QS + (int)RFE_Q31_QS, count);
    if (st != RFE_OK) {
        return st;
    }
    project_innovations(f, k, count);
    /* J^T = S-^T \ (S- \ P_xz): Q24 by Q30 into Q20 (cannot fail: diag(S-) > 0 was
     * checked by the solve above). */
    st = rfe_qr_solve_lower_t_q31(f->S, n, NM, &w->A[k], m, TC,
                                  (int)QJ - (int)RFE_Q31_QZ + (int)RFE_Q31_QS, count);
    /* V (m x n) = S_R \ J, J transposed into w->Kt: Q20 by Q24 into Q16. */
    for (r = 0u; r < m; ++r) {
        for (i = 0u; i < n; ++i) {
            w->Kt[(r * NM) + i] = w->A[(i * TC) + k + r];
        }
    }
    if (st == RFE_OK) {
        st = rfe_qr_solve_lower_q31(SR, m, MM, w->Kt, n, NM, (int)QV - (int)QJ + (int)RFE_Q31_QZ,
                                    count);
    }
    if (st == RFE_OK) {
        sum_squares(f, info, count);
    }
    return st;
}

/* docs/ESTIMATOR.md steps 5-6: the step's information into info (n, Q10) and the gate:
 * *held = 1 when info_min > 0 and no state reaches it. Needs the centred points. */
static rfe_status_t gate_q31(rfe_sckf_q31_t *f, const rfe_fix_t *SR, rfe_fix_t info_min,
                             rfe_fix_t *info, int *held, size_t k, uint32_t *count)
{
    const rfe_status_t st = information_q31(f, SR, info, k, count);
    *held = 0;
    if (st == RFE_OK) {
        rfe_fix_t most = 0;
        size_t i;
        for (i = 0u; i < f->n; ++i) {
            most = rfe_fix_max(most, info[i]);
        }
        if ((info_min > 0) && (most < info_min)) {
            *held = 1;
        }
    }
    return st;
}

/* The measurement update of MODEL.md §6 with S_R = SR (ld RFE_M_MAX), gated on the
 * information when info_min > 0 (docs/ESTIMATOR.md steps 5-6), on k centred columns: the 2n
 * cubature points (linear 0, any h) or the n columns of S- (linear != 0, h linear:
 * centre_linear_q31). Writes info (n) when want_info; *updated = 0 when held. Commits x, S
 * and the count only when everything succeeded (a held step commits the count of the
 * information alone). */
static rfe_status_t update_core_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure, void *ctx,
                                    const rfe_fix_t *y, const rfe_fix_t *SR, rfe_fix_t info_min,
                                    int want_info, rfe_fix_t *info, rfe_sckf_innov_q31_t *innov,
                                    int *updated, int linear)
{
    rfe_cub_scratch_q31_t *w = &f->w;
    const size_t n = f->n;
    const size_t m = f->m;
    const size_t k = (linear != 0) ? n : (2u * n);
    uint32_t count = 0u;
    uint32_t w_or = 0u; /* gain_q31's mag_or_q31 of W's first k columns */
    rfe_status_t st;

    st = centre_q31(f, measure, ctx, linear, &count);
    if (st != RFE_OK) {
        return st;
    }
    if ((want_info != 0) || (info_min > 0)) {
        int held = 0;
        st = gate_q31(f, SR, info_min, info, &held, k, &count);
        if (st != RFE_OK) {
            return st;
        }
        if (held != 0) {
            /* held: not observable; x-, S- stay (S_zz computed only for the innovation) */
            if (innov != NULL) {
                st = innovation_factor_q31(f, SR, k, &count);
                if (st != RFE_OK) {
                    return st;
                }
                innovation_out_q31(f, y, innov, k, &count);
            }
            rfe_q31_sat_add(&f->sat, count);
            *updated = 0;
            return RFE_OK;
        }
    }
    st = gain_q31(f, SR, k, &w_or, &count);
    if ((st == RFE_OK) && (innov != NULL)) {
        innovation_out_q31(f, y, innov, k, &count); /* before the update: the predicted points' */
    }
    if (st == RFE_OK) {
        st = correct(f, y, &count);
    }
    if (st != RFE_OK) {
        return st;
    }
    /* S = Tria([Xc - K Zc, K S_R]). */
    posterior_tria_input_q31(f, k, w_or, &count);
    st = rfe_qr_tria_q31(w->B, n, k + m, TC, &count);
    if (st != RFE_OK) {
        return st;
    }
    commit_q31(f, w->B, count);
    *updated = 1;
    return RFE_OK;
}

/* Common argument checks of the measurement updates. */
static rfe_status_t check_update_q31(const rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure,
                                     const rfe_fix_t *y)
{
    if ((f == NULL) || (measure == NULL) || (y == NULL)) {
        return RFE_ERR_NULL;
    }
    return (f->magic != RFE_MAGIC_SCKF_Q31) ? RFE_ERR_NOT_INITIALISED : RFE_OK;
}

rfe_status_t rfe_sckf_update_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure, void *ctx,
                                 const rfe_fix_t *y)
{
    rfe_fix_t info[RFE_N_MAX];
    int updated = 0;
    const rfe_status_t st = check_update_q31(f, measure, y);
    if (st != RFE_OK) {
        return st;
    }
    return update_core_q31(f, measure, ctx, y, f->SR, 0, 0, info, NULL, &updated, 0);
}

/* rfe_sckf_update_ex_q31 (linear 0) and rfe_sckf_update_linear_q31 (linear 1): the checks,
 * the step's S_R and the outputs once. */
static rfe_status_t update_ex_common_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure,
                                         void *ctx, const rfe_fix_t *y, const rfe_fix_t *SR,
                                         rfe_fix_t info_min, rfe_fix_t *info_out,
                                         rfe_sckf_innov_q31_t *innov_out, int *updated,
                                         int linear)
{
    rfe_sckf_innov_q31_t innov;
    rfe_fix_t SRl[RFE_M_MAX * RFE_M_MAX];
    rfe_fix_t info[RFE_N_MAX];
    const rfe_fix_t *sr;
    int upd = 0;
    rfe_status_t st = check_update_q31(f, measure, y);

    if ((st == RFE_OK) && (updated == NULL)) {
        st = RFE_ERR_NULL;
    }
    if (st != RFE_OK) {
        return st;
    }
    sr = f->SR;
    if (SR != NULL) {
        copy_lower_q31(SR, f->m, f->m, SRl, MM);
        sr = SRl;
    }
    st = update_core_q31(f, measure, ctx, y, sr, info_min, (info_out != NULL) ? 1 : 0, info,
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

rfe_status_t rfe_sckf_update_ex_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure, void *ctx,
                                    const rfe_fix_t *y, const rfe_fix_t *SR, rfe_fix_t info_min,
                                    rfe_fix_t *info_out, rfe_sckf_innov_q31_t *innov_out,
                                    int *updated)
{
    return update_ex_common_q31(f, measure, ctx, y, SR, info_min, info_out, innov_out, updated,
                                0);
}

rfe_status_t rfe_sckf_update_linear_q31(rfe_sckf_q31_t *f, rfe_measure_fn_q31_t measure,
                                        void *ctx, const rfe_fix_t *y, const rfe_fix_t *SR,
                                        rfe_fix_t info_min, rfe_fix_t *info_out,
                                        rfe_sckf_innov_q31_t *innov_out, int *updated)
{
    return update_ex_common_q31(f, measure, ctx, y, SR, info_min, info_out, innov_out, updated,
                                1);
}

rfe_status_t rfe_sckf_scale_q31(rfe_sckf_q31_t *f, rfe_fix_t c)
{
    uint32_t count = 0u;
    size_t i;
    size_t j;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (c <= 0) {
        return RFE_ERR_RANGE;
    }
    /* c S: Q24 Q30 = Q54 -> Q30, each element rounded once, saturating (counted). */
    for (i = 0u; i < f->n; ++i) {
        for (j = 0u; j <= i; ++j) {
            f->S[(i * NM) + j] = rfe_fix_mul(c, f->S[(i * NM) + j], RFE_Q31_QC, &count);
        }
    }
    rfe_q31_sat_add(&f->sat, count);
    return RFE_OK;
}

rfe_status_t rfe_sckf_get_q31(const rfe_sckf_q31_t *f, rfe_fix_t *x, rfe_fix_t *sd)
{
    uint32_t unreported = 0u; /* f is const: an sd >= 2 is reported as RFE_FIX_MAX only */
    size_t i;
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    for (i = 0u; i < f->n; ++i) {
        if (x != NULL) {
            x[i] = f->x[i];
        }
        if (sd != NULL) {
            /* sd_i = sqrt((S S^T)_ii) = norm of row i of S (exactly rounded, Q30). */
            rfe_fix_t v = 0;
            const rfe_status_t st = rfe_fix_norm(&f->S[i * NM], i + 1u, &v, &unreported);
            (void)st; /* fails only for NULL arguments, which these are not */
            sd[i] = v;
        }
    }
    return RFE_OK;
}

/* generated by scripts/codegen/twins.py from filter_clamp: do not edit; make twins */
rfe_status_t rfe_sckf_clamp_q31(rfe_sckf_q31_t *f, rfe_fix_t lo, rfe_fix_t hi, int *clamped)
{
    if ((f == NULL) || (clamped == NULL)) {
        return RFE_ERR_NULL;
    }
    if (f->magic != RFE_MAGIC_SCKF_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (lo > hi) { /* every Q value is finite */
        return RFE_ERR_RANGE;
    }
    *clamped = rfe_clamp_vec_q31(f->x, f->n, lo, hi);
    return RFE_OK;
}
/* end generated */
