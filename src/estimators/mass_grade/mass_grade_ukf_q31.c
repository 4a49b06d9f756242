/**
 * @file mass_grade_ukf_q31.c
 * @brief The unscented Kalman filter of the mass and grade estimator in integers, square-root
 *        form (docs/MASS_GRADE.md §3, §4.3 steps 1-7; docs/FIXED_POINT.md "Mass and grade"),
 *        without its model. The covariance steps are triangularisations (rfe_qr_tria_q31),
 *        the gain a triangular solve (rfe_qr_solve_lower_q31): P = S S^T is positive
 *        semidefinite by construction, where P- - K S K^T in Q31 is not (FIXED_POINT.md).
 *
 * Accumulators: a deviation of two values of one format is int64 (< 2^32); a weighted
 * deviation w (X_i - X_0) is formed exactly in int64 (w < 2^30, so < 2^62) and summed
 * saturating (rfe_fix_add64); a root weight times a deviation is exactly rounded by
 * rfe_q31_mul64x32 and saturated to int32 (counted).
 */
#include "estimators/mass_grade/mass_grade_internal_q31.h"

#include "rfe/component/qr_q31.h"
#include "numerics/internal_q31.h"

#define N ((size_t)RFE_MG_N_Q31)
#define PTS ((size_t)RFE_MG_PTS_Q31)
#define ZM ((size_t)RFE_MG_Z_MAX_Q31)
/* Columns of the predict array (7 points, 3 noise columns) and the largest correct array
 * (7 points, 2 noise columns). */
#define PRED_COLS (PTS + N)
#define CORR_COLS (PTS + ZM)
/* The whitened innovation Sz \ (y - z): Q24 (+-128 sd), as the library's SCKF. */
#define Q_WHITE 24u

void rfe_mg_sigma_points_q31(const rfe_fix_t x[RFE_MG_N_Q31],
                             const rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], rfe_fix_t sqrt_c,
                             rfe_fix_t chi[RFE_MG_PTS_Q31 * RFE_MG_N_Q31], uint32_t *sat)
{
    size_t i;
    size_t r;
    for (r = 0u; r < N; ++r) {
        chi[r] = x[r];
    }
    for (i = 0u; i < N; ++i) {
        for (r = 0u; r < N; ++r) {
            /* d = sqrt(c) S[r, i]: Q29 times row r's format, exactly rounded (< 2^33) */
            const rfe_fix_t d = rfe_fix_mul(S[(r * N) + i], sqrt_c, 29u, sat);
            chi[((1u + i) * N) + r] = rfe_fix_add(x[r], d, sat);
            chi[((1u + N + i) * N) + r] = rfe_fix_sub(x[r], d, sat);
        }
    }
}

/* The weighted mean m_r = X_0r + round(sum_{i>=1} w_i (X_ir - X_0r)), over k coordinates
 * of the rows of width ld. */
static void mean_of_q31(const rfe_fix_t *X, size_t ld, size_t k, rfe_fix_t wi, rfe_fix_t *m,
                        uint32_t *sat)
{
    size_t i;
    size_t r;
    for (r = 0u; r < k; ++r) {
        int64_t acc = 0;
        for (i = 1u; i < PTS; ++i) {
            const int64_t dev = (int64_t)X[(i * ld) + r] - (int64_t)X[r];
            acc = rfe_fix_add64(acc, dev * (int64_t)wi, sat); /* |w_i| < 2^29: < 2^62 */
        }
        m[r] = rfe_fix_add(X[r], rfe_fix_narrow(acc, 30u, sat), sat);
    }
}

/* Column i of the centred array: sqrt(w_c,i) (X_ir - m_r) for the k coordinates, into
 * rows row0.. of A (width lda). */
static void centred_q31(const rfe_fix_t *X, size_t ld, size_t k, const rfe_fix_t *m,
                        const rfe_mg_weights_q31_t *w, rfe_fix_t *A, size_t row0, size_t lda,
                        uint32_t *sat)
{
    size_t i;
    size_t r;
    for (i = 0u; i < PTS; ++i) {
        const rfe_fix_t sw = (i == 0u) ? w->sqrt_wc0 : w->sqrt_wi;
        for (r = 0u; r < k; ++r) {
            const int64_t dev = (int64_t)X[(i * ld) + r] - (int64_t)m[r]; /* < 2^32 */
            A[((row0 + r) * lda) + i] = rfe_fix_sat32(rfe_q31_mul64x32(dev, (int64_t)sw, 30u), sat);
        }
    }
}

rfe_status_t rfe_mg_predict_q31(const rfe_fix_t X[RFE_MG_PTS_Q31 * RFE_MG_N_Q31],
                                const rfe_mg_weights_q31_t *w, const rfe_fix_t sq[RFE_MG_N_Q31],
                                rfe_fix_t xm[RFE_MG_N_Q31],
                                rfe_fix_t Sm[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat)
{
    rfe_fix_t A[N * PRED_COLS] = {0};
    size_t r;
    rfe_status_t st;
    mean_of_q31(X, N, N, w->wi, xm, sat);            /* eq. 10 */
    centred_q31(X, N, N, xm, w, A, 0u, PRED_COLS, sat);
    for (r = 0u; r < N; ++r) {
        A[(r * PRED_COLS) + PTS + r] = sq[r];         /* + Q (eq. 11) */
    }
    st = rfe_qr_tria_q31(A, N, PRED_COLS, PRED_COLS, sat);
    if (st == RFE_OK) {
        for (r = 0u; r < N; ++r) {
            size_t c;
            for (c = 0u; c < N; ++c) {
                Sm[(r * N) + c] = A[(r * PRED_COLS) + c];
            }
        }
    }
    return st;
}

rfe_status_t rfe_mg_correct_q31(const rfe_fix_t chi[RFE_MG_PTS_Q31 * RFE_MG_N_Q31],
                                const rfe_fix_t Z[RFE_MG_PTS_Q31 * RFE_MG_Z_MAX_Q31], size_t nz,
                                const rfe_mg_weights_q31_t *w,
                                const rfe_fix_t r[RFE_MG_Z_MAX_Q31],
                                const rfe_fix_t y[RFE_MG_Z_MAX_Q31], rfe_fix_t x[RFE_MG_N_Q31],
                                rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat)
{
    rfe_fix_t A[(ZM + N) * CORR_COLS] = {0};
    rfe_fix_t zm[RFE_MG_Z_MAX_Q31];
    rfe_fix_t e[RFE_MG_Z_MAX_Q31];
    uint32_t s = 0u;
    size_t b;
    size_t i;
    size_t c;
    rfe_status_t st;
    mean_of_q31(Z, ZM, nz, w->wi, zm, &s);                /* eq. 17 */
    centred_q31(Z, ZM, nz, zm, w, A, 0u, CORR_COLS, &s);   /* rows of Zc */
    centred_q31(chi, N, N, x, w, A, nz, CORR_COLS, &s);    /* rows of Xc */
    for (b = 0u; b < nz; ++b) {
        A[(b * CORR_COLS) + PTS + b] = r[b];               /* + R (eq. 18) */
        e[b] = rfe_fix_sub(y[b], zm[b], &s);
    }
    /* [[Zc, R^1/2], [Xc, 0]] -> [[Sz, 0], [G, S+]] (eqs. 18-21) */
    st = rfe_qr_tria_q31(A, nz + N, PTS + nz, CORR_COLS, &s);
    if (st == RFE_OK) {
        /* the whitened innovation Sz \ (y - z), Q24 */
        st = rfe_qr_solve_lower_q31(A, nz, CORR_COLS, e, 1u, 1u, (int)Q_WHITE, &s);
    }
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0u; i < N; ++i) {
        /* x = x- + G e: G's row in state i's format times Q24 */
        int64_t acc = 0;
        for (b = 0u; b < nz; ++b) {
            acc = rfe_fix_add64(acc, (int64_t)A[((nz + i) * CORR_COLS) + b] * (int64_t)e[b], &s);
        }
        x[i] = rfe_fix_add(x[i], rfe_fix_narrow(acc, Q_WHITE, &s), &s);
        for (c = 0u; c < N; ++c) {
            S[(i * N) + c] = A[((nz + i) * CORR_COLS) + nz + c];
        }
    }
    rfe_q31_sat_add(sat, s);
    return RFE_OK;
}
