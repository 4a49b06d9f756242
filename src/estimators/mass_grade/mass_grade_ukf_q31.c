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
 * saturating (rfe_fix_add64); a root weight times a deviation is exact in int64 (< 2^63),
 * rounded half up and saturated to int32 (rfe_fix_narrow, counted).
 */
#include "estimators/mass_grade/mass_grade_internal_q31.h"

#include "rfe/component/qr_q31.h"
#include "numerics/internal_q31.h"

#define N ((size_t)RFE_MG_N_Q31)
#define PTS ((size_t)RFE_MG_PTS_Q31)
/* Columns of the predict array (7 points, 3 noise columns) and of the ax row's array (7
 * points, its noise column). */
#define PRED_COLS (PTS + N)
#define CORR_COLS (PTS + 1u)
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
            /* |dev| <= 2^32 - 2, 0 <= sw < 2^31: the product < 2^63, exact */
            const int64_t dev = (int64_t)X[(i * ld) + r] - (int64_t)m[r];
            A[((row0 + r) * lda) + i] = rfe_fix_narrow(dev * (int64_t)sw, 30u, sat);
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

/* One scalar measurement in square-root form: the array [[zc, r], [xc, 0]] (row 0 the
 * measurement's deviations, rows 1-3 the state's, over @p cols columns with the noise r in
 * the last) is triangularised to [[s, 0], [g, S+]] (s^2 = the innovation variance, g s =
 * P_xz, S+ S+^T = P- - P_xz P_xz^T / s^2), then x += g (y - z) / s, the whitened innovation
 * (y - z) / s in Q24 by the exactly rounded solve, also into @p e_out. A (4 x cols, width
 * lda) is overwritten. */
static rfe_status_t scalar_update_q31(rfe_fix_t *A, size_t cols, size_t lda, rfe_fix_t innov,
                                      rfe_fix_t x[RFE_MG_N_Q31],
                                      rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat,
                                      rfe_fix_t *e_out)
{
    rfe_fix_t e = innov;
    rfe_status_t st = rfe_qr_tria_q31(A, 1u + N, cols, lda, sat);
    if (st == RFE_OK) {
        st = rfe_qr_solve_lower_q31(A, 1u, lda, &e, 1u, 1u, (int)Q_WHITE, sat);
    }
    if (st == RFE_OK) {
        size_t i;
        for (i = 0u; i < N; ++i) {
            size_t c;
            /* x = x- + g e: g's entry in state i's format times Q24 */
            x[i] = rfe_fix_add(x[i], rfe_fix_mul(A[(1u + i) * lda], e, Q_WHITE, sat), sat);
            for (c = 0u; c < N; ++c) {
                S[(i * N) + c] = A[((1u + i) * lda) + 1u + c];
            }
        }
        *e_out = e;
    }
    return st;
}

/* The speed row, linear in the state (z = v, so H S = [S_00, 0, 0]): the array
 * [[S_00, 0, 0, r_v], [S, 0]] has two nonzero entries in its first row, so its
 * triangularisation is one Givens rotation of S's first column with the column (r_v, 0):
 * s = |(S_00, r_v)| (the innovation sd, exactly rounded: rfe_fix_norm), g = (S_00 / s)
 * S[:, 0] (= P_xz / s), and S+ = S with its first column scaled by r_v / s, already lower
 * triangular with a nonnegative diagonal (S+ S+^T = P - P_xz P_xz^T / s^2). Then x += g (y -
 * v) / s, the whitened innovation in Q24. The ratios in Q30 (<= 1) by exactly rounded
 * divisions. Every check comes before the first write, and the saturations are counted into
 * @p sat only on success, so an error leaves x, S and the count untouched. */
rfe_status_t rfe_mg_correct_speed_q31(rfe_fix_t r_v, rfe_fix_t y, rfe_fix_t x[RFE_MG_N_Q31],
                                      rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat)
{
    const rfe_fix_t col[2] = {S[0], r_v};
    uint32_t k = 0u;
    const rfe_fix_t innov = rfe_fix_sub(y, x[0], &k);
    rfe_fix_t s = 0;
    rfe_fix_t cs = 0;
    rfe_fix_t sn = 0;
    rfe_fix_t e = 0;
    /* non-NULL arguments: the norm cannot fail, and s stays 0 if it did */
    rfe_status_t st = rfe_fix_norm(col, 2u, &s, &k);
    if (s <= 0) {
        st = RFE_ERR_NOT_POSITIVE_DEFINITE; /* r_v > 0: never through the public API */
    }
    if (st == RFE_OK) {
        st = rfe_fix_div(S[0], s, 30, &cs, &k);  /* S_00 / s, Q30 */
    }
    if (st == RFE_OK) {
        st = rfe_fix_div(r_v, s, 30, &sn, &k);   /* r_v / s, Q30 */
    }
    if (st == RFE_OK) {
        st = rfe_fix_div(innov, s, (int)Q_WHITE, &e, &k); /* (y - v) / s, Q24 */
    }
    if (st == RFE_OK) {
        size_t i;
        for (i = 0u; i < N; ++i) {
            const rfe_fix_t g = rfe_fix_mul(S[i * N], cs, 30u, &k);
            x[i] = rfe_fix_add(x[i], rfe_fix_mul(g, e, Q_WHITE, &k), &k);
            S[i * N] = rfe_fix_mul(S[i * N], sn, 30u, &k);
        }
        rfe_q31_sat_add(sat, k);
    }
    return st;
}

rfe_status_t rfe_mg_correct_q31(const rfe_fix_t chi[RFE_MG_PTS_Q31 * RFE_MG_N_Q31],
                                const rfe_fix_t Z[RFE_MG_PTS_Q31], const rfe_mg_weights_q31_t *w,
                                const rfe_fix_t r[RFE_MG_Z_MAX_Q31],
                                const rfe_fix_t y[RFE_MG_Z_MAX_Q31], rfe_fix_t x[RFE_MG_N_Q31],
                                rfe_fix_t S[RFE_MG_N_Q31 * RFE_MG_N_Q31], uint32_t *sat,
                                rfe_fix_t *e_ax)
{
    rfe_fix_t en = 0;
    rfe_fix_t xn[RFE_MG_N_Q31];
    rfe_fix_t Sn[RFE_MG_N_Q31 * RFE_MG_N_Q31];
    /* the ax row by the points: [[Zc, r_ax], [Xc, 0]], 4 x 8 (eqs. 17-21) */
    rfe_fix_t A[(1u + N) * CORR_COLS] = {0};
    rfe_fix_t zm = 0;
    uint32_t s = 0u;
    size_t i;
    rfe_status_t st;
    for (i = 0u; i < N; ++i) {
        xn[i] = x[i];
    }
    for (i = 0u; i < (N * N); ++i) {
        Sn[i] = S[i];
    }
    mean_of_q31(Z, 1u, 1u, w->wi, &zm, &s);                    /* eq. 17 */
    centred_q31(Z, 1u, 1u, &zm, w, A, 0u, PTS + 1u, &s);        /* row of Zc */
    centred_q31(chi, N, N, xn, w, A, 1u, PTS + 1u, &s);         /* rows of Xc */
    A[PTS] = r[1];
    st = scalar_update_q31(A, PTS + 1u, PTS + 1u, rfe_fix_sub(y[1], zm, &s), xn, Sn, &s, &en);
    if (st == RFE_OK) {
        st = rfe_mg_correct_speed_q31(r[0], y[0], xn, Sn, &s);
    }
    if (st != RFE_OK) {
        return st;
    }
    for (i = 0u; i < N; ++i) {
        x[i] = xn[i];
    }
    for (i = 0u; i < (N * N); ++i) {
        S[i] = Sn[i];
    }
    *e_ax = en;
    rfe_q31_sat_add(sat, s);
    return RFE_OK;
}
