/**
 * @file tyre_id_sckf_flt.c
 * @brief The tyre identifier's third filter (docs/TYRE_ID.md §15): the augmented-state
 *        square-root cubature Kalman filter over (vy, r) and the eight Magic Formula
 *        parameters. The cubature rule is the library's (filters/cubature.h: the points, their
 *        means, the correction), the square roots its Tria and triangular solves
 *        (rfe/component/qr.h), the model the particle filters' (tyre_id_model_flt.c) point by
 *        point. Deterministic: no random stream.
 */
#include "estimators/tyre_id/tyre_id_internal.h"
#include "filters/cubature.h"
#include "numerics/internal.h"
#include "rfe/component/qr.h"

#define NX ((size_t)RFE_TID_DIM)        /* state dimension n = 10 */
#define NP ((size_t)RFE_TID_CUB)        /* cubature points 2n = 20 */
#define NZ ((size_t)RFE_TID_MEAS)       /* measurements (yaw rate, ay) */
#define NS ((size_t)RFE_TID_STATES)     /* vy, r */
#define NPAR ((size_t)RFE_TID_PAR)      /* the parameters */
#define TC ((size_t)RFE_TID_TRIA_COLS)  /* ld of A: [points | S_Q] */
#define ZC (NP + NZ)                    /* ld of Z: [Zc | S_R] */
#define NQ 5u                           /* the point-wise outputs: beta, Fy_f, Fy_r, B_f, B_r */

/* The state, the points and Tria's bound agree (config.h RFE_TID_SCKF_N sizes Tria). */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_tid_sckf_dim[((RFE_TID_DIM == RFE_TID_SCKF_N) &&
                                      (RFE_TID_CUB == (2 * RFE_TID_DIM)) &&
                                      (RFE_TID_TRIA_COLS == (RFE_TID_CUB + RFE_TID_DIM)) &&
                                      (RFE_TID_TRIA_COLS <= RFE_TRIA_COLS_LIMIT))
                                         ? 1
                                         : -1];

/* §15.3 a point's columns with its parameters clipped into [lo, hi] (where it enters §3). */
static void clipped(const rfe_tyre_id_t *t, const rfe_real_t *pt, rfe_real_t out[RFE_TID_DIM])
{
    size_t e;
    out[RFE_TID_VY] = pt[RFE_TID_VY];
    out[RFE_TID_R] = pt[RFE_TID_R];
    for (e = 0u; e < NPAR; ++e) {
        out[NS + e] = rfe_clamp(pt[NS + e], t->c.lo[e], t->c.hi[e]);
    }
}

/* §15.3 the projection: the mean's parameters clipped into [lo, hi]; S unchanged. */
static void sckf_project(const rfe_tyre_id_t *t, rfe_real_t x[RFE_TID_DIM])
{
    size_t e;
    for (e = 0u; e < NPAR; ++e) {
        x[NS + e] = rfe_clamp(x[NS + e], t->c.lo[e], t->c.hi[e]);
    }
}

void rfe_tid_sckf_prior(rfe_tyre_id_t *tid, rfe_real_t r_meas)
{
    rfe_tid_sckf_t *k = &tid->sk;
    size_t i;
    for (i = 0u; i < (NX * NX); ++i) {
        k->S[i] = RFE_R(0.0);
    }
    k->x[RFE_TID_VY] = RFE_R(0.0);
    k->x[RFE_TID_R] = r_meas;
    k->S[0] = tid->p.sd0_vy;
    k->S[NX + 1u] = tid->p.sd0_r;
    for (i = 0u; i < NPAR; ++i) {
        k->x[NS + i] = tid->c.mean0[i];
        k->S[((NS + i) * NX) + NS + i] = tid->c.sd0[i];
    }
}

/* Column j of the centred points (X_j - x) / sqrt(2n) into column j of M (row stride ld). */
static void sckf_centred(const rfe_real_t *pts, const rfe_real_t *x, rfe_real_t s2n, rfe_real_t *M,
                         size_t ld)
{
    size_t i;
    size_t j;
    for (i = 0u; i < NX; ++i) {
        for (j = 0u; j < NP; ++j) {
            M[(i * ld) + j] = (pts[(j * NX) + i] - x[i]) / s2n;
        }
    }
}

/* S = the lower triangle of Tria's output A (rows NX, ld lda). */
static void take_lower(rfe_tid_sckf_t *k, size_t lda)
{
    size_t i;
    size_t j;
    for (i = 0u; i < NX; ++i) {
        for (j = 0u; j < NX; ++j) {
            k->S[(i * NX) + j] = (j <= i) ? k->A[(i * lda) + j] : RFE_R(0.0);
        }
    }
}

/* The end of both updates: S = the lower triangle of Tria(A) over its first @p cols columns,
 * x = x_new projected onto the bounds (§15.3, §15.4); RFE_ERR_NONFINITE when Tria fails. */
static rfe_status_t factor_and_commit(rfe_tyre_id_t *t, size_t cols)
{
    rfe_tid_sckf_t *k = &t->sk;
    size_t i;
    if (rfe_qr_tria(k->A, NX, cols, TC) != RFE_OK) {
        return RFE_ERR_NONFINITE;
    }
    take_lower(k, TC);
    for (i = 0u; i < NX; ++i) {
        k->x[i] = k->xn[i];
    }
    sckf_project(t, k->x);
    return RFE_OK;
}

/* §15.3 time update: the points through RK4 at the period's mean inputs (parameters clipped,
 * a random walk), x- = their mean, S- = Tria([(X*_j - x-) / sqrt(2n), S_Q]), projected. */
static rfe_status_t sckf_time_update(rfe_tyre_id_t *t, const rfe_tyre_id_sample_t *smp,
                                rfe_real_t s2n)
{
    rfe_tid_sckf_t *k = &t->sk;
    const rfe_real_t sq = RFE_SQRT(smp->dt);
    const rfe_tid_input_t ub = rfe_tid_mean_input(t, smp);
    size_t i;
    size_t j;
    rfe_cub_points(k->x, k->S, NX, NX, k->pts);
    for (j = 0u; j < NP; ++j) {
        rfe_real_t xc[RFE_TID_DIM];
        clipped(t, &k->pts[j * NX], xc);
        rfe_tid_rk4(t, xc, &ub, smp->dt, &k->pts[j * NX]); /* vy, r; parameters kept */
    }
    rfe_cub_mean(k->pts, NX, NX, NX, k->xn);
    for (i = 0u; i < (NX * TC); ++i) {
        k->A[i] = RFE_R(0.0);
    }
    sckf_centred(k->pts, k->xn, s2n, k->A, TC);
    /* S_Q = diag(q_vy s, q_r s, q s), s = sqrt(h) (§4.3) */
    k->A[NP] = t->p.q_vy * sq;
    k->A[TC + NP + 1u] = t->p.q_r * sq;
    for (i = 0u; i < NPAR; ++i) {
        k->A[((NS + i) * TC) + NP + NS + i] = t->c.q[i] * sq;
    }
    return factor_and_commit(t, TC);
}

/* §15.3 S_R's diagonal: sd_r and sqrt(sd_ay^2 + (g sd_delta)^2), g = d ay / d delta at the
 * predicted mean (parameters clipped) at the sample's inputs; sd_delta the steering-angle
 * filter's posterior sd with it on (§4.4). */
static void meas_noise(rfe_tyre_id_t *t, const rfe_tid_input_t *u)
{
    rfe_tid_sckf_t *k = &t->sk;
    rfe_real_t xc[RFE_TID_DIM];
    rfe_real_t ay;
    rfe_real_t g;
    rfe_real_t gs;
    clipped(t, k->x, xc);
    rfe_tid_ay(t, xc[RFE_TID_VY], xc[RFE_TID_R], &xc[NS], u, &ay, &g, NULL);
    gs = g * t->sd_delta;
    k->sr[0] = t->p.sd_r;
    k->sr[1] = RFE_SQRT((t->p.sd_ay * t->p.sd_ay) + (gs * gs));
}

/* Zc = (Z_j - z) / sqrt(2n) into the first NP columns of M (NZ rows, ld ZC). */
static void centred_z(const rfe_tid_sckf_t *k, rfe_real_t s2n, rfe_real_t *M)
{
    size_t r;
    size_t j;
    for (r = 0u; r < NZ; ++r) {
        for (j = 0u; j < NP; ++j) {
            M[(r * ZC) + j] = (k->zp[(j * NZ) + r] - k->zhat[r]) / s2n;
        }
    }
}

/* §15.3 the gain K = (P_xz / S_zz^T) / S_zz, transposed into k->Kt, with S_zz =
 * Tria([Zc, S_R]) and P_xz = Xc Zc^T (Xc in k->A, ld TC). */
static rfe_status_t sckf_gain(rfe_tid_sckf_t *k, rfe_real_t s2n)
{
    size_t r;
    size_t i;
    size_t j;
    for (i = 0u; i < (NZ * ZC); ++i) {
        k->Z[i] = RFE_R(0.0);
    }
    centred_z(k, s2n, k->Z);
    for (r = 0u; r < NZ; ++r) {
        for (i = 0u; i < NX; ++i) {
            rfe_real_t acc = RFE_R(0.0);
            for (j = 0u; j < NP; ++j) {
                acc += k->A[(i * TC) + j] * k->Z[(r * ZC) + j];
            }
            k->Kt[(r * NX) + i] = acc; /* P_xz^T */
        }
        k->Z[(r * ZC) + NP + r] = k->sr[r];
    }
    if (rfe_qr_tria(k->Z, NZ, ZC, ZC) != RFE_OK) {
        return RFE_ERR_NONFINITE;
    }
    /* S_zz W^T = P_xz^T, then S_zz^T K^T = W^T: two triangular solves, no inverse */
    if ((rfe_qr_solve_lower(k->Z, NZ, ZC, k->Kt, NX, NX) != RFE_OK) ||
        (rfe_qr_solve_lower_t(k->Z, NZ, ZC, k->Kt, NX, NX) != RFE_OK)) {
        return RFE_ERR_NONFINITE;
    }
    return RFE_OK;
}

/* §15.3 measurement update on (r_m, ay_m): the points of (x-, S-), Z_j = (r_j, ay_p(X_j)),
 * x = x- + K (y - z), S = Tria([Xc - K Zc, K S_R]), projected. */
static rfe_status_t meas_update(rfe_tyre_id_t *t, const rfe_tyre_id_sample_t *smp,
                                const rfe_tid_input_t *u, rfe_real_t s2n)
{
    rfe_tid_sckf_t *k = &t->sk;
    const rfe_real_t y[RFE_TID_MEAS] = {smp->yaw_rate, smp->ay};
    rfe_real_t zc[RFE_TID_MEAS * (RFE_TID_CUB + RFE_TID_MEAS)];
    size_t i;
    size_t j;
    meas_noise(t, u);
    rfe_cub_points(k->x, k->S, NX, NX, k->pts);
    for (j = 0u; j < NP; ++j) {
        rfe_real_t xc[RFE_TID_DIM];
        clipped(t, &k->pts[j * NX], xc);
        k->zp[j * NZ] = xc[RFE_TID_R];
        rfe_tid_ay(t, xc[RFE_TID_VY], xc[RFE_TID_R], &xc[NS], u, &k->zp[(j * NZ) + 1u], NULL,
                   NULL);
    }
    rfe_cub_mean(k->zp, NX, NZ, NZ, k->zhat);
    for (i = 0u; i < (NX * TC); ++i) {
        k->A[i] = RFE_R(0.0);
    }
    sckf_centred(k->pts, k->x, s2n, k->A, TC);
    if (sckf_gain(k, s2n) != RFE_OK) {
        return RFE_ERR_NONFINITE;
    }
    if (rfe_cub_correct(k->x, k->Kt, y, k->zhat, NX, NZ, NX, k->xn) != RFE_OK) {
        return RFE_ERR_NONFINITE;
    }
    /* [Xc - K Zc | K S_R]: Zc again (Tria overwrote it) */
    centred_z(k, s2n, zc);
    for (i = 0u; i < NX; ++i) {
        for (j = 0u; j < NP; ++j) {
            const rfe_real_t kz = (k->Kt[i] * zc[j]) + (k->Kt[NX + i] * zc[ZC + j]);
            k->A[(i * TC) + j] -= kz;
        }
        k->A[(i * TC) + NP] = k->Kt[i] * k->sr[0];
        k->A[(i * TC) + NP + 1u] = k->Kt[NX + i] * k->sr[1];
    }
    return factor_and_commit(t, ZC);
}

uint32_t rfe_tid_sckf_step(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp,
                           const rfe_tid_input_t *u)
{
    const rfe_real_t s2n = RFE_SQRT(RFE_R(2.0) * (rfe_real_t)NX);
    rfe_tid_sckf_t *k = &tid->sk;
    rfe_status_t st = sckf_time_update(tid, smp, s2n);
    if (st == RFE_OK) {
        st = meas_update(tid, smp, u, s2n);
    }
    if ((st != RFE_OK) || (rfe_all_finite(k->x, NX) == 0) ||
        (rfe_all_finite(k->S, NX * NX) == 0)) {
        rfe_tid_sckf_prior(tid, smp->yaw_rate); /* §15.3 lost: the prior at this sample */
        return RFE_TID_LOST;
    }
    return RFE_TID_UPDATED;
}

/* sqrt(w ((v_0 - m)^2 + (v_1 - m)^2 + ...)) over n values of stride st, in order; when that
 * overflows (a spread beyond the square root of the type's range: vehicle data scaled far
 * beyond a car's, as the particle filters' rescaled_sd) the same with every term divided by
 * the largest magnitude first. */
static rfe_real_t spread(const rfe_real_t *v, size_t n, size_t st, rfe_real_t m, rfe_real_t w)
{
    rfe_real_t acc = RFE_R(0.0);
    rfe_real_t r;
    size_t j;
    for (j = 0u; j < n; ++j) {
        const rfe_real_t d = v[j * st] - m;
        acc += d * d;
    }
    r = RFE_SQRT(acc * w);
    if (rfe_is_finite(r) == 0) {
        rfe_real_t big = RFE_FABS(m);
        for (j = 0u; j < n; ++j) {
            big = rfe_max(big, RFE_FABS(v[j * st]));
        }
        if ((big > RFE_R(0.0)) && (rfe_is_finite(big) != 0)) {
            acc = RFE_R(0.0);
            for (j = 0u; j < n; ++j) {
                const rfe_real_t d = (v[j * st] / big) - (m / big);
                acc += d * d;
            }
            r = big * RFE_SQRT(acc * w);
        }
    }
    return r;
}

void rfe_tid_sckf_estimate(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp,
                           const rfe_tid_input_t *u, uint32_t flags)
{
    static const size_t OUT_Q[NQ] = {RFE_TID_OUT_BETA, RFE_TID_OUT_FY_F, RFE_TID_OUT_FY_R,
                                     RFE_TID_OUT_B_F, RFE_TID_OUT_B_R};
    rfe_tid_sckf_t *k = &tid->sk;
    rfe_tyre_id_estimate_t *e = &tid->last;
    const rfe_real_t w = RFE_R(1.0) / (rfe_real_t)NP;
    rfe_real_t fz[2];
    rfe_real_t qm[NQ];
    size_t i;
    size_t j;
    /* beta, the forces and B: mean and sd over the points of (x, S), parameters clipped;
     * one row of k->A per point (ld NQ) */
    rfe_cub_points(k->x, k->S, NX, NX, k->pts);
    for (j = 0u; j < NP; ++j) {
        rfe_real_t xc[RFE_TID_DIM];
        rfe_real_t *q = &k->A[j * NQ];
        clipped(tid, &k->pts[j * NX], xc);
        q[0] = RFE_ATAN2(xc[RFE_TID_VY], smp->vx);
        rfe_tid_forces(tid, xc, u, &q[1], &q[2]);
        q[3] = xc[RFE_TID_K_F] / (xc[RFE_TID_C_F] * xc[RFE_TID_D_F]);
        q[4] = xc[RFE_TID_K_R] / (xc[RFE_TID_C_R] * xc[RFE_TID_D_R]);
    }
    rfe_cub_mean(k->A, NX, NQ, NQ, qm);
    for (i = 0u; i < NQ; ++i) {
        e->mean[OUT_Q[i]] = qm[i];
        e->sd[OUT_Q[i]] = spread(&k->A[i], NP, NQ, qm[i], w);
    }
    /* the states and parameters: x and the row norms of S (the output of column i: vy, r,
     * then the parameters in order) */
    for (i = 0u; i < NX; ++i) {
        static const size_t OUT_X[RFE_TID_DIM] = {
            RFE_TID_OUT_VY,  RFE_TID_OUT_R,   RFE_TID_OUT_D_F, RFE_TID_OUT_C_F, RFE_TID_OUT_K_F,
            RFE_TID_OUT_E_F, RFE_TID_OUT_D_R, RFE_TID_OUT_C_R, RFE_TID_OUT_K_R, RFE_TID_OUT_E_R};
        const size_t o = OUT_X[i];
        e->mean[o] = k->x[i];
        e->sd[o] = spread(&k->S[i * NX], i + 1u, 1u, RFE_R(0.0), RFE_R(1.0));
    }
    /* mu = D / Fz (§3.4, §3.5), its sd sd(D) / Fz */
    rfe_tid_mu_loads(tid, smp->ax, fz);
    e->mean[RFE_TID_OUT_MU_F] = k->x[RFE_TID_D_F] / fz[0];
    e->sd[RFE_TID_OUT_MU_F] = e->sd[RFE_TID_OUT_D_F] / fz[0];
    e->mean[RFE_TID_OUT_MU_R] = k->x[RFE_TID_D_R] / fz[1];
    e->sd[RFE_TID_OUT_MU_R] = e->sd[RFE_TID_OUT_D_R] / fz[1];
    e->n_eff = (rfe_real_t)NAN; /* no particles */
    e->flags = flags;
    e->status = RFE_OK;
}
