/**
 * @file mass_grade_ukf_flt.c
 * @brief The unscented Kalman filter of the mass and grade estimator (docs/MASS_GRADE.md
 *        §3, §4.3 steps 1-7) on n = 3 states and one or two measurements, without its
 *        model. Each sum runs in the page's order, so the double build follows the
 *        reference (scripts/reference/mass_grade.py) operation for operation.
 */
#include "estimators/mass_grade/mass_grade_internal.h"

#include "numerics/internal.h"

#define N ((size_t)RFE_MG_N)
#define ZM ((size_t)RFE_MG_Z_MAX)

/* §3 the weight of point i: the centre's or the others'. */
static rfe_real_t weight(rfe_real_t w0, rfe_real_t wi, size_t i)
{
    return (i == 0u) ? w0 : wi;
}

/* §3 the lower Cholesky factor L of the 3 x 3 A (L L^T = A), column by column; a zero pivot
 * leaves its column 0 (a state known exactly). */
static rfe_status_t cholesky3(const rfe_real_t A[RFE_MG_N * RFE_MG_N],
                              rfe_real_t L[RFE_MG_N * RFE_MG_N])
{
    size_t i;
    size_t j;
    size_t k;
    for (i = 0u; i < (N * N); ++i) {
        L[i] = RFE_R(0.0);
    }
    for (j = 0u; j < N; ++j) {
        rfe_real_t d = A[(j * N) + j];
        for (k = 0u; k < j; ++k) {
            d -= L[(j * N) + k] * L[(j * N) + k];
        }
        if (d < RFE_R(0.0)) {
            return RFE_ERR_NOT_POSITIVE_DEFINITE;
        }
        if (d > RFE_R(0.0)) {
            L[(j * N) + j] = RFE_SQRT(d);
            for (i = j + 1u; i < N; ++i) {
                rfe_real_t s = A[(i * N) + j];
                for (k = 0u; k < j; ++k) {
                    s -= L[(i * N) + k] * L[(j * N) + k];
                }
                L[(i * N) + j] = s / L[(j * N) + j];
            }
        }
    }
    return RFE_OK;
}

rfe_status_t rfe_mg_sigma_points(const rfe_real_t x[RFE_MG_N],
                                 const rfe_real_t P[RFE_MG_N * RFE_MG_N], rfe_real_t c,
                                 rfe_real_t chi[RFE_MG_PTS * RFE_MG_N])
{
    rfe_real_t A[RFE_MG_N * RFE_MG_N];
    rfe_real_t L[RFE_MG_N * RFE_MG_N];
    size_t i;
    size_t r;
    rfe_status_t st;
    for (i = 0u; i < (N * N); ++i) {
        A[i] = c * P[i]; /* A = (n + lambda) P */
    }
    st = cholesky3(A, L);
    if (st != RFE_OK) {
        return st;
    }
    for (r = 0u; r < N; ++r) {
        chi[r] = x[r];
    }
    for (i = 0u; i < N; ++i) {
        for (r = 0u; r < N; ++r) {
            chi[((1u + i) * N) + r] = x[r] + L[(r * N) + i];     /* chi_i = x + L[:, i-1] */
            chi[((1u + N + i) * N) + r] = x[r] - L[(r * N) + i]; /* chi_{n+i} = x - L[:, i-1] */
        }
    }
    return RFE_OK;
}

/* x-bar = sum_i w_m,i X_i over the points' rows of width @p ld, k of them used. */
static void mean_of(const rfe_real_t *X, size_t ld, size_t k, const rfe_mg_weights_t *w,
                    rfe_real_t *m)
{
    size_t i;
    size_t r;
    for (r = 0u; r < k; ++r) {
        m[r] = RFE_R(0.0);
    }
    for (i = 0u; i < (size_t)RFE_MG_PTS; ++i) {
        const rfe_real_t wm = weight(w->wm0, w->wi, i);
        for (r = 0u; r < k; ++r) {
            m[r] += wm * X[(i * ld) + r];
        }
    }
}

/* cov(A, B) = sum_i w_c,i (A_i - am)(B_i - bm)^T, each element accumulated over i; A's rows
 * ka of width lda, B's kb of width ldb; out is ka x kb, row-major with width kb. */
static void cov_of(const rfe_real_t *A, size_t lda, size_t ka, const rfe_real_t *am,
                   const rfe_real_t *B, size_t ldb, size_t kb, const rfe_real_t *bm,
                   const rfe_mg_weights_t *w, rfe_real_t *out)
{
    size_t i;
    size_t r;
    size_t c;
    for (r = 0u; r < (ka * kb); ++r) {
        out[r] = RFE_R(0.0);
    }
    for (i = 0u; i < (size_t)RFE_MG_PTS; ++i) {
        const rfe_real_t wc = weight(w->wc0, w->wi, i);
        for (r = 0u; r < ka; ++r) {
            const rfe_real_t da = A[(i * lda) + r] - am[r];
            for (c = 0u; c < kb; ++c) {
                out[(r * kb) + c] += (wc * da) * (B[(i * ldb) + c] - bm[c]);
            }
        }
    }
}

void rfe_mg_predict(const rfe_real_t X[RFE_MG_PTS * RFE_MG_N], const rfe_mg_weights_t *w,
                    const rfe_real_t q[RFE_MG_N], rfe_real_t xm[RFE_MG_N],
                    rfe_real_t Pm[RFE_MG_N * RFE_MG_N])
{
    size_t r;
    mean_of(X, N, N, w, xm);
    cov_of(X, N, N, xm, X, N, N, xm, w, Pm);
    for (r = 0u; r < N; ++r) {
        Pm[(r * N) + r] += q[r]; /* P- = cov(X, X) + Q */
    }
}

/* S^-1 of the nz x nz S (row-major, width nz): 1/s, or the adjugate over the determinant.
 * Not positive definite (a weight w_c,0 < 0 can make it so): an error. */
static rfe_status_t inverse_of(const rfe_real_t *S, size_t nz, rfe_real_t *Si)
{
    if (nz == 1u) {
        if (!(S[0] > RFE_R(0.0))) {
            return RFE_ERR_NOT_POSITIVE_DEFINITE;
        }
        Si[0] = RFE_R(1.0) / S[0];
    } else {
        const rfe_real_t det = (S[0] * S[3]) - (S[1] * S[2]);
        if (!(S[0] > RFE_R(0.0)) || !(det > RFE_R(0.0))) {
            return RFE_ERR_NOT_POSITIVE_DEFINITE;
        }
        Si[0] = S[3] / det;
        Si[1] = -S[1] / det;
        Si[2] = -S[2] / det;
        Si[3] = S[0] / det;
    }
    return RFE_OK;
}

/* K = P_xz S^-1 (N x nz, width nz): K_rb = sum_a P_xz,ra S^-1_ab, a ascending. */
static void gain_of(const rfe_real_t *Pxz, const rfe_real_t *Si, size_t nz, rfe_real_t *K)
{
    size_t r;
    size_t a;
    size_t b;
    for (r = 0u; r < N; ++r) {
        for (b = 0u; b < nz; ++b) {
            rfe_real_t s = RFE_R(0.0);
            for (a = 0u; a < nz; ++a) {
                s += Pxz[(r * nz) + a] * Si[(a * nz) + b];
            }
            K[(r * nz) + b] = s;
        }
    }
}

/* x = x- + K (y - z); P = P- - K S K^T, the upper triangle computed and mirrored. */
static void apply_gain(const rfe_real_t *K, const rfe_real_t *S, size_t nz,
                       const rfe_real_t *innov, rfe_real_t *x, rfe_real_t *P)
{
    rfe_real_t KS[RFE_MG_N * RFE_MG_Z_MAX];
    size_t r;
    size_t c;
    size_t b;
    for (r = 0u; r < N; ++r) {
        rfe_real_t s = RFE_R(0.0);
        for (b = 0u; b < nz; ++b) {
            s += K[(r * nz) + b] * innov[b];
        }
        x[r] += s;
        for (c = 0u; c < nz; ++c) {
            rfe_real_t t = RFE_R(0.0);
            for (b = 0u; b < nz; ++b) {
                t += K[(r * nz) + b] * S[(b * nz) + c];
            }
            KS[(r * nz) + c] = t;
        }
    }
    for (r = 0u; r < N; ++r) {
        for (c = r; c < N; ++c) {
            rfe_real_t s = RFE_R(0.0);
            for (b = 0u; b < nz; ++b) {
                s += KS[(r * nz) + b] * K[(c * nz) + b];
            }
            P[(r * N) + c] -= s;
            P[(c * N) + r] = P[(r * N) + c];
        }
    }
}

rfe_status_t rfe_mg_correct(const rfe_real_t chi[RFE_MG_PTS * RFE_MG_N],
                            const rfe_real_t Z[RFE_MG_PTS * RFE_MG_Z_MAX], size_t nz,
                            const rfe_mg_weights_t *w, const rfe_real_t r2[RFE_MG_Z_MAX],
                            const rfe_real_t y[RFE_MG_Z_MAX], rfe_real_t x[RFE_MG_N],
                            rfe_real_t P[RFE_MG_N * RFE_MG_N])
{
    rfe_real_t zm[RFE_MG_Z_MAX];
    rfe_real_t S[RFE_MG_Z_MAX * RFE_MG_Z_MAX];
    rfe_real_t Si[RFE_MG_Z_MAX * RFE_MG_Z_MAX];
    rfe_real_t Pxz[RFE_MG_N * RFE_MG_Z_MAX];
    rfe_real_t innov[RFE_MG_Z_MAX];
    size_t b;
    rfe_status_t st;
    mean_of(Z, ZM, nz, w, zm);                     /* eq. 17 */
    cov_of(Z, ZM, nz, zm, Z, ZM, nz, zm, w, S);    /* eq. 18 */
    for (b = 0u; b < nz; ++b) {
        S[(b * nz) + b] += r2[b];
        innov[b] = y[b] - zm[b];
    }
    cov_of(chi, N, N, x, Z, ZM, nz, zm, w, Pxz);   /* eq. 19 */
    st = inverse_of(S, nz, Si);
    if (st == RFE_OK) {
        rfe_real_t K[RFE_MG_N * RFE_MG_Z_MAX];
        gain_of(Pxz, Si, nz, K);                   /* eq. 19 */
        apply_gain(K, S, nz, innov, x, P);         /* eqs. 20-21 */
    }
    return st;
}
