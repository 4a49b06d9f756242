/**
 * @file mass_grade_ukf_flt.c
 * @brief The unscented Kalman filter of the mass and grade estimator in the square-root form
 *        (docs/MASS_GRADE.md §3, §4.3 steps 1-7) on n = 3 states and one or two
 *        measurements, without its model. The covariance steps are triangularisations
 *        (rfe_qr_tria, the library's Householder Tria): P = S S^T is positive semidefinite
 *        by construction, where P- - K S K^T in float32 is not (MASS_GRADE.md §9 "Float32
 *        and positive definiteness"). The steps are the Q31 twin's (mass_grade_ukf_q31.c);
 *        each sum runs in the reference's order (scripts/reference/mass_grade.py, form
 *        "sqrt"), so the double build follows it operation for operation.
 */
#include "estimators/mass_grade/mass_grade_internal.h"

#include "rfe/component/qr.h"
#include "numerics/internal.h"

#define N ((size_t)RFE_MG_N)
#define PTS ((size_t)RFE_MG_PTS)
/* Columns of the predict array (7 points, 3 noise columns) and of the ax row's array (7
 * points, its noise column). */
#define PRED_COLS (PTS + N)
#define CORR_COLS (PTS + 1u)

void rfe_mg_sigma_points(const rfe_real_t x[RFE_MG_N], const rfe_real_t S[RFE_MG_N * RFE_MG_N],
                         rfe_real_t sqrt_c, rfe_real_t chi[RFE_MG_PTS * RFE_MG_N])
{
    size_t i;
    size_t r;
    for (r = 0u; r < N; ++r) {
        chi[r] = x[r];
    }
    for (i = 0u; i < N; ++i) {
        for (r = 0u; r < N; ++r) {
            const rfe_real_t d = sqrt_c * S[(r * N) + i];
            chi[((1u + i) * N) + r] = x[r] + d;     /* chi_i = x + d_i */
            chi[((1u + N + i) * N) + r] = x[r] - d; /* chi_{n+i} = x - d_i */
        }
    }
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
    for (i = 0u; i < PTS; ++i) {
        const rfe_real_t wm = (i == 0u) ? w->wm0 : w->wi;
        for (r = 0u; r < k; ++r) {
            m[r] += wm * X[(i * ld) + r];
        }
    }
}

/* Columns 0..6 of the centred array: sqrt(w_c,i) (X_ir - m_r) for the k coordinates, into
 * rows row0.. of A (width lda); the centre's column 0 when w_c,0 < 0 (its downdate). */
static void centred(const rfe_real_t *X, size_t ld, size_t k, const rfe_real_t *m,
                    const rfe_mg_weights_t *w, rfe_real_t *A, size_t row0, size_t lda)
{
    size_t i;
    size_t r;
    for (i = 0u; i < PTS; ++i) {
        rfe_real_t sw = w->sqrt_wi;
        if (i == 0u) {
            sw = (w->wc0 < RFE_R(0.0)) ? RFE_R(0.0) : w->sqrt_wc0;
        }
        for (r = 0u; r < k; ++r) {
            A[((row0 + r) * lda) + i] = sw * (X[(i * ld) + r] - m[r]);
        }
    }
}

/* The rank-one downdate L' L'^T = L L^T - v v^T of the lower k x k L (width ld, nonnegative
 * diagonal), v overwritten, by hyperbolic rotations column by column: r = sqrt((L_jj - v_j)
 * (L_jj + v_j)), c = r / L_jj, s = v_j / L_jj; L_jj = r, L_ij = (L_ij - s v_i) / c, v_i =
 * c v_i - s L_ij (i > j). A zero column with v_j = 0 is skipped (a state known exactly).
 * RFE_ERR_NOT_POSITIVE_DEFINITE when the difference is not positive definite (L partly
 * written). */
static rfe_status_t downdate(rfe_real_t *L, size_t k, size_t ld, rfe_real_t *v)
{
    size_t i;
    size_t j;
    for (j = 0u; j < k; ++j) {
        const rfe_real_t ljj = L[(j * ld) + j];
        const rfe_real_t r2 = (ljj - v[j]) * (ljj + v[j]);
        if (!(r2 > RFE_R(0.0))) {
            if ((ljj != RFE_R(0.0)) || (v[j] != RFE_R(0.0))) {
                return RFE_ERR_NOT_POSITIVE_DEFINITE;
            }
        } else {
            const rfe_real_t rr = RFE_SQRT(r2);
            const rfe_real_t c = rr / ljj;
            const rfe_real_t s = v[j] / ljj;
            L[(j * ld) + j] = rr;
            for (i = j + 1u; i < k; ++i) {
                L[(i * ld) + j] = (L[(i * ld) + j] - (s * v[i])) / c;
                v[i] = (c * v[i]) - (s * L[(i * ld) + j]);
            }
        }
    }
    return RFE_OK;
}

rfe_status_t rfe_mg_predict(const rfe_real_t X[RFE_MG_PTS * RFE_MG_N], const rfe_mg_weights_t *w,
                            const rfe_real_t sq[RFE_MG_N], rfe_real_t xm[RFE_MG_N],
                            rfe_real_t Sm[RFE_MG_N * RFE_MG_N])
{
    rfe_real_t A[N * PRED_COLS] = {0};
    size_t r;
    size_t c;
    rfe_status_t st;
    mean_of(X, N, N, w, xm); /* eq. 10 */
    centred(X, N, N, xm, w, A, 0u, PRED_COLS);
    for (r = 0u; r < N; ++r) {
        A[(r * PRED_COLS) + PTS + r] = sq[r]; /* + Q (eq. 11) */
    }
    st = rfe_qr_tria(A, N, PRED_COLS, PRED_COLS);
    if ((st == RFE_OK) && (w->wc0 < RFE_R(0.0))) {
        rfe_real_t v[RFE_MG_N];
        for (r = 0u; r < N; ++r) {
            v[r] = w->sqrt_wc0 * (X[r] - xm[r]);
        }
        st = downdate(A, N, PRED_COLS, v);
    }
    for (r = 0u; r < N; ++r) {
        for (c = 0u; c < N; ++c) {
            Sm[(r * N) + c] = (c <= r) ? A[(r * PRED_COLS) + c] : RFE_R(0.0);
        }
    }
    return st;
}

/* The ax row (eqs. 17-21): [[Zc, r_ax], [Xc, 0]] (4 x 8) triangularised to [[s, 0], [g, S+]]
 * (s^2 the innovation variance, g s = P_xz, S+ S+^T = P- - P_xz P_xz^T / s^2), then x += g
 * (y - z) / s. */
static rfe_status_t ax_update(const rfe_real_t *chi, const rfe_real_t *Z,
                              const rfe_mg_weights_t *w, rfe_real_t r_ax, rfe_real_t y,
                              rfe_real_t *x, rfe_real_t *S, rfe_real_t *e_ax)
{
    rfe_real_t A[(1u + N) * CORR_COLS] = {0};
    rfe_real_t zm = RFE_R(0.0);
    size_t i;
    rfe_status_t st;
    mean_of(Z, 1u, 1u, w, &zm);                  /* eq. 17 */
    centred(Z, 1u, 1u, &zm, w, A, 0u, CORR_COLS); /* row of Zc */
    centred(chi, N, N, x, w, A, 1u, CORR_COLS);   /* rows of Xc */
    A[PTS] = r_ax;
    st = rfe_qr_tria(A, 1u + N, CORR_COLS, CORR_COLS);
    if ((st == RFE_OK) && (w->wc0 < RFE_R(0.0))) {
        rfe_real_t v[RFE_MG_N + 1];
        v[0] = w->sqrt_wc0 * (Z[0] - zm);
        for (i = 0u; i < N; ++i) {
            v[1u + i] = w->sqrt_wc0 * (chi[i] - x[i]);
        }
        st = downdate(A, 1u + N, CORR_COLS, v);
    }
    if ((st == RFE_OK) && !(A[0] > RFE_R(0.0))) {
        st = RFE_ERR_NOT_POSITIVE_DEFINITE; /* every point measures the same, r_ax = 0 */
    }
    if (st == RFE_OK) {
        const rfe_real_t e = (y - zm) / A[0]; /* the whitened innovation */
        *e_ax = e;
        for (i = 0u; i < N; ++i) {
            size_t c;
            x[i] += A[(1u + i) * CORR_COLS] * e;
            for (c = 0u; c < N; ++c) {
                S[(i * N) + c] = A[((1u + i) * CORR_COLS) + 1u + c];
            }
        }
    }
    return st;
}

/* The speed row, linear in the state (z = v, so H S = [S_00, 0, 0]): the array
 * [[S_00, 0, 0, r_v], [S, 0]] triangularises by one Givens rotation of S's column 0 with
 * (r_v, 0): s = sqrt(S_00^2 + r_v^2), g = (S_00 / s) S[:, 0] (= P_xz / s), S+ = S with its
 * column 0 scaled by r_v / s (lower triangular with a nonnegative diagonal already). Every
 * check comes before the first write, so an error leaves x and S untouched. */
rfe_status_t rfe_mg_correct_speed(rfe_real_t r_v, rfe_real_t y, rfe_real_t x[RFE_MG_N],
                                  rfe_real_t S[RFE_MG_N * RFE_MG_N])
{
    const rfe_real_t s = RFE_SQRT((S[0] * S[0]) + (r_v * r_v));
    const rfe_real_t innov = y - x[0];
    rfe_real_t cs;
    rfe_real_t sn;
    rfe_real_t e;
    size_t i;
    if (!(s > RFE_R(0.0))) {
        return RFE_ERR_NOT_POSITIVE_DEFINITE; /* r_v > 0: never through the public API */
    }
    if (!rfe_is_finite(s)) {
        return RFE_ERR_NONFINITE; /* S_00^2 overflowed: the rotation would zero column 0 */
    }
    cs = S[0] / s;
    sn = r_v / s;
    e = innov / s;
    for (i = 0u; i < N; ++i) {
        const rfe_real_t g = S[i * N] * cs;
        x[i] += g * e;
        S[i * N] *= sn;
    }
    return RFE_OK;
}

rfe_status_t rfe_mg_correct(const rfe_real_t chi[RFE_MG_PTS * RFE_MG_N],
                            const rfe_real_t Z[RFE_MG_PTS], const rfe_mg_weights_t *w,
                            const rfe_real_t r[RFE_MG_Z_MAX], const rfe_real_t y[RFE_MG_Z_MAX],
                            rfe_real_t x[RFE_MG_N], rfe_real_t S[RFE_MG_N * RFE_MG_N],
                            rfe_real_t *e_ax)
{
    rfe_real_t en = RFE_R(0.0);
    rfe_real_t xn[RFE_MG_N];
    rfe_real_t Sn[RFE_MG_N * RFE_MG_N];
    size_t i;
    rfe_status_t st;
    for (i = 0u; i < N; ++i) {
        xn[i] = x[i];
    }
    for (i = 0u; i < (N * N); ++i) {
        Sn[i] = S[i];
    }
    st = ax_update(chi, Z, w, r[1], y[1], xn, Sn, &en);
    if (st == RFE_OK) {
        st = rfe_mg_correct_speed(r[0], y[0], xn, Sn);
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
    return RFE_OK;
}
