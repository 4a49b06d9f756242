/**
 * @file tyre_id_sckf_flt.c
 * @brief The tyre identifier's third filter (docs/TYRE_ID.md §15): the augmented-state
 *        square-root cubature Kalman filter over (vy, r) and the eight Magic Formula
 *        parameters (with delta_state_q > 0 the steering angle too, §15.7). The cubature rule
 *        is the library's (filters/cubature.h: the points, their means, the correction), the square roots its Tria and triangular solves
 *        (rfe/component/qr.h), the model the particle filters' (tyre_id_model_flt.c) point by
 *        point. Deterministic: no random stream.
 */
#include "estimators/tyre_id/tyre_id_internal.h"
#include "filters/cubature.h"
#include "numerics/internal.h"
#include "rfe/component/qr.h"

#define NXP ((size_t)RFE_TID_DIM)      /* a particle's columns: vy, r, the parameters */
#define NS ((size_t)RFE_TID_STATES)     /* vy, r */
#define NPAR ((size_t)RFE_TID_PAR)      /* the parameters */
#define ID ((size_t)RFE_TID_DELTA)      /* delta's row with §15.7 */
#define NQ 5u                           /* the point-wise outputs: beta, Fy_f, Fy_r, B_f, B_r */

/* The state, the points and Tria's bound agree (config.h RFE_TID_SCKF_N sizes Tria). */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_tid_sckf_dim[((RFE_TID_SCKF_DIM == RFE_TID_SCKF_N) &&
                                      (RFE_TID_SCKF_DIM == (RFE_TID_DIM + 1)) &&
                                      (RFE_TID_DELTA == RFE_TID_DIM) &&
                                      (RFE_TID_CUB == (2 * RFE_TID_SCKF_DIM)) &&
                                      (RFE_TID_TRIA_COLS == (RFE_TID_CUB + RFE_TID_SCKF_DIM)) &&
                                      (RFE_TID_TRIA_COLS <= RFE_TRIA_COLS_LIMIT))
                                         ? 1
                                         : -1];

/* The filter's dimensions: n = 10 states and m = 2 measurements (yaw rate, ay), or with
 * delta as a state (delta_state_q > 0, §15.7) n = 11 and m = 3 (and delta); 2n points; the
 * leading dimensions of [points | S_Q] (3n) and of [Zc | S_R] (2n + m). */
typedef struct {
    size_t n;
    size_t np;
    size_t nz;
    size_t tc;
    size_t zc;
    int ds; /* 1: delta is state ID */
} sckf_dims_t;

/* The dimensions at state dimension @p n (10, or 11 with delta). Every function below takes n
 * and derives the rest here: the step calls them with n a constant in each of its two
 * branches, so an optimising compiler can specialise each for its n (fixed loop bounds, as
 * before §15.7, where the n = 10 filter's cost stays). */
static sckf_dims_t dims_n(size_t n)
{
    sckf_dims_t d;
    if (n > NXP) {
        d.ds = 1;
        d.nz = 3u;
    } else {
        d.ds = 0;
        d.nz = 2u;
    }
    d.n = n;
    d.np = 2u * n;
    d.tc = d.np + n;
    d.zc = d.np + d.nz;
    return d;
}

/* The state dimension the parameters ask for: 11 with delta_state_q > 0 (§15.7), else 10. */
static size_t sckf_n(const rfe_tyre_id_t *t)
{
    return (t->p.delta_state_q > RFE_R(0.0)) ? (NXP + 1u) : NXP;
}

/* §15.7 the inputs @p u with delta set to a point's @p delta (and, when @p with_cos, its
 * cosine; sin is read only by the slope, not asked for per point). */
static rfe_tid_input_t at_delta(const rfe_tid_input_t *u, rfe_real_t delta, int with_cos)
{
    rfe_tid_input_t v = *u;
    v.delta = delta;
    v.sd = RFE_R(0.0);
    if (with_cos != 0) {
        v.cd = RFE_COS(delta);
    }
    return v;
}

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
static void sckf_project(const rfe_tyre_id_t *t, rfe_real_t *x)
{
    size_t e;
    for (e = 0u; e < NPAR; ++e) {
        x[NS + e] = rfe_clamp(x[NS + e], t->c.lo[e], t->c.hi[e]);
    }
}

void rfe_tid_sckf_prior(rfe_tyre_id_t *tid, rfe_real_t r_meas, rfe_real_t delta_meas)
{
    const sckf_dims_t d = dims_n(sckf_n(tid));
    rfe_tid_sckf_t *k = &tid->sk;
    size_t i;
    for (i = 0u; i < (d.n * d.n); ++i) {
        k->S[i] = RFE_R(0.0);
    }
    k->x[RFE_TID_VY] = RFE_R(0.0);
    k->x[RFE_TID_R] = r_meas;
    k->S[0] = tid->p.sd0_vy;
    k->S[d.n + 1u] = tid->p.sd0_r;
    for (i = 0u; i < NPAR; ++i) {
        k->x[NS + i] = tid->c.mean0[i];
        k->S[((NS + i) * d.n) + NS + i] = tid->c.sd0[i];
    }
    if (d.ds != 0) {
        /* §15.7 delta starts at the measured one, with the sensor's sd */
        k->x[ID] = delta_meas;
        k->S[(ID * d.n) + ID] = tid->p.sd_delta;
    }
}

/* Column j of the centred points (X_j - x) / sqrt(2n) into column j of M (row stride ld). */
static void sckf_centred(size_t n, const rfe_real_t *pts, const rfe_real_t *x,
                         rfe_real_t s2n, rfe_real_t *M, size_t ld)
{
    const sckf_dims_t dd = dims_n(n);
    const sckf_dims_t *d = &dd;
    size_t i;
    size_t j;
    for (i = 0u; i < d->n; ++i) {
        for (j = 0u; j < d->np; ++j) {
            M[(i * ld) + j] = (pts[(j * d->n) + i] - x[i]) / s2n;
        }
    }
}

/* S = the lower triangle of Tria's output A (n rows, ld lda). */
static void take_lower(rfe_tid_sckf_t *k, size_t n, size_t lda)
{
    size_t i;
    size_t j;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            k->S[(i * n) + j] = (j <= i) ? k->A[(i * lda) + j] : RFE_R(0.0);
        }
    }
}

/* The end of both updates: S = the lower triangle of Tria(A) over its first @p cols columns,
 * x = x_new projected onto the bounds (§15.3, §15.4); RFE_ERR_NONFINITE when Tria fails. */
static rfe_status_t factor_and_commit(rfe_tyre_id_t *t, size_t n, size_t cols)
{
    const sckf_dims_t dd = dims_n(n);
    const sckf_dims_t *d = &dd;
    rfe_tid_sckf_t *k = &t->sk;
    size_t i;
    if (rfe_qr_tria(k->A, d->n, cols, d->tc) != RFE_OK) {
        return RFE_ERR_NONFINITE;
    }
    take_lower(k, d->n, d->tc);
    for (i = 0u; i < d->n; ++i) {
        k->x[i] = k->xn[i];
    }
    sckf_project(t, k->x);
    return RFE_OK;
}

/* §15.3 time update: the points through RK4 at the period's mean inputs (parameters clipped,
 * a random walk; with §15.7 each point at its own delta, a random walk too), x- = their mean,
 * S- = Tria([(X*_j - x-) / sqrt(2n), S_Q]), projected. */
static rfe_status_t sckf_time_update(rfe_tyre_id_t *t, size_t n,
                                     const rfe_tyre_id_sample_t *smp, rfe_real_t s2n)
{
    const sckf_dims_t dd = dims_n(n);
    const sckf_dims_t *d = &dd;
    rfe_tid_sckf_t *k = &t->sk;
    const rfe_real_t sq = RFE_SQRT(smp->dt);
    const rfe_tid_input_t ub = rfe_tid_mean_input(t, smp);
    size_t i;
    size_t j;
    rfe_cub_points(k->x, k->S, d->n, d->n, k->pts);
    for (j = 0u; j < d->np; ++j) {
        rfe_real_t *pt = &k->pts[j * d->n];
        rfe_real_t xc[RFE_TID_DIM];
        clipped(t, pt, xc);
        if (d->ds != 0) {
            const rfe_tid_input_t uj = at_delta(&ub, pt[ID], 1);
            rfe_tid_rk4(t, xc, &uj, smp->dt, pt); /* vy, r; parameters, delta kept */
        } else {
            rfe_tid_rk4(t, xc, &ub, smp->dt, pt); /* vy, r; parameters kept */
        }
    }
    rfe_cub_mean(k->pts, d->n, d->n, d->n, k->xn);
    for (i = 0u; i < (d->n * d->tc); ++i) {
        k->A[i] = RFE_R(0.0);
    }
    sckf_centred(d->n, k->pts, k->xn, s2n, k->A, d->tc);
    /* S_Q = diag(q_vy s, q_r s, q s[, delta_state_q s]), s = sqrt(h) (§4.3, §15.7) */
    k->A[d->np] = t->p.q_vy * sq;
    k->A[d->tc + d->np + 1u] = t->p.q_r * sq;
    for (i = 0u; i < NPAR; ++i) {
        k->A[((NS + i) * d->tc) + d->np + NS + i] = t->c.q[i] * sq;
    }
    if (d->ds != 0) {
        k->A[(ID * d->tc) + d->np + ID] = t->p.delta_state_q * sq;
    }
    return factor_and_commit(t, d->n, d->tc);
}

/* §15.3 S_R's diagonal: sd_r and sqrt(sd_ay^2 + (g sd_delta)^2), g = d ay / d delta at the
 * predicted mean (parameters clipped) at the sample's inputs; sd_delta the steering-angle
 * filter's posterior sd with it on (§4.4). With delta as a state (§15.7) no slope term:
 * sd_r, sd_ay and the steering sensor's sd_delta for its own row. */
static void meas_noise(rfe_tyre_id_t *t, size_t n, const rfe_tid_input_t *u)
{
    const sckf_dims_t dd = dims_n(n);
    const sckf_dims_t *d = &dd;
    rfe_tid_sckf_t *k = &t->sk;
    k->sr[0] = t->p.sd_r;
    if (d->ds != 0) {
        k->sr[1] = t->p.sd_ay;
        k->sr[2] = t->p.sd_delta;
    } else {
        rfe_real_t xc[RFE_TID_DIM];
        rfe_real_t ay;
        rfe_real_t g;
        rfe_real_t gs;
        clipped(t, k->x, xc);
        rfe_tid_ay(t, xc[RFE_TID_VY], xc[RFE_TID_R], &xc[NS], u, &ay, &g, NULL);
        gs = g * t->sd_delta;
        k->sr[1] = RFE_SQRT((t->p.sd_ay * t->p.sd_ay) + (gs * gs));
    }
}

/* Zc = (Z_j - z) / sqrt(2n) into the first 2n columns of M (m rows, ld 2n + m). */
static void centred_z(const rfe_tid_sckf_t *k, size_t n, rfe_real_t s2n,
                      rfe_real_t *M)
{
    const sckf_dims_t dd = dims_n(n);
    const sckf_dims_t *d = &dd;
    size_t r;
    size_t j;
    for (r = 0u; r < d->nz; ++r) {
        for (j = 0u; j < d->np; ++j) {
            M[(r * d->zc) + j] = (k->zp[(j * d->nz) + r] - k->zhat[r]) / s2n;
        }
    }
}

/* §15.3 the gain K = (P_xz / S_zz^T) / S_zz, transposed into k->Kt, with S_zz =
 * Tria([Zc, S_R]) and P_xz = Xc Zc^T (Xc in k->A, ld 3n). */
static rfe_status_t sckf_gain(rfe_tid_sckf_t *k, size_t n, rfe_real_t s2n)
{
    const sckf_dims_t dd = dims_n(n);
    const sckf_dims_t *d = &dd;
    size_t r;
    size_t i;
    size_t j;
    for (i = 0u; i < (d->nz * d->zc); ++i) {
        k->Z[i] = RFE_R(0.0);
    }
    centred_z(k, d->n, s2n, k->Z);
    for (r = 0u; r < d->nz; ++r) {
        for (i = 0u; i < d->n; ++i) {
            rfe_real_t acc = RFE_R(0.0);
            for (j = 0u; j < d->np; ++j) {
                acc += k->A[(i * d->tc) + j] * k->Z[(r * d->zc) + j];
            }
            k->Kt[(r * d->n) + i] = acc; /* P_xz^T */
        }
        k->Z[(r * d->zc) + d->np + r] = k->sr[r];
    }
    if (rfe_qr_tria(k->Z, d->nz, d->zc, d->zc) != RFE_OK) {
        return RFE_ERR_NONFINITE;
    }
    /* S_zz W^T = P_xz^T, then S_zz^T K^T = W^T: two triangular solves, no inverse */
    if ((rfe_qr_solve_lower(k->Z, d->nz, d->zc, k->Kt, d->n, d->n) != RFE_OK) ||
        (rfe_qr_solve_lower_t(k->Z, d->nz, d->zc, k->Kt, d->n, d->n) != RFE_OK)) {
        return RFE_ERR_NONFINITE;
    }
    return RFE_OK;
}

/* §15.3 the points' measurements Z_j = (r_j, ay_p(X_j)) at the sample's inputs; with §15.7
 * ay_p at the point's delta (its cosine too) and delta_j the third. */
static void measure_points(rfe_tyre_id_t *t, size_t n, const rfe_tid_input_t *u)
{
    const sckf_dims_t dd = dims_n(n);
    const sckf_dims_t *d = &dd;
    rfe_tid_sckf_t *k = &t->sk;
    size_t j;
    for (j = 0u; j < d->np; ++j) {
        const rfe_real_t *pt = &k->pts[j * d->n];
        rfe_real_t *z = &k->zp[j * d->nz];
        rfe_real_t xc[RFE_TID_DIM];
        clipped(t, pt, xc);
        z[0] = xc[RFE_TID_R];
        if (d->ds != 0) {
            const rfe_tid_input_t uj = at_delta(u, pt[ID], 1);
            rfe_tid_ay(t, xc[RFE_TID_VY], xc[RFE_TID_R], &xc[NS], &uj, &z[1], NULL, NULL);
            z[2] = pt[ID];
        } else {
            rfe_tid_ay(t, xc[RFE_TID_VY], xc[RFE_TID_R], &xc[NS], u, &z[1], NULL, NULL);
        }
    }
}

/* §15.3 measurement update on (r_m, ay_m[, delta_m]): the points of (x-, S-), their
 * measurements, x = x- + K (y - z), S = Tria([Xc - K Zc, K S_R]), projected. */
static rfe_status_t meas_update(rfe_tyre_id_t *t, size_t n,
                                const rfe_tyre_id_sample_t *smp, const rfe_tid_input_t *u,
                                rfe_real_t s2n)
{
    const sckf_dims_t dd = dims_n(n);
    const sckf_dims_t *d = &dd;
    rfe_tid_sckf_t *k = &t->sk;
    const rfe_real_t y[RFE_TID_MEAS] = {smp->yaw_rate, smp->ay, smp->delta};
    rfe_real_t zc[RFE_TID_MEAS * (RFE_TID_CUB + RFE_TID_MEAS)];
    size_t i;
    size_t j;
    size_t r;
    meas_noise(t, d->n, u);
    rfe_cub_points(k->x, k->S, d->n, d->n, k->pts);
    measure_points(t, d->n, u);
    rfe_cub_mean(k->zp, d->n, d->nz, d->nz, k->zhat);
    for (i = 0u; i < (d->n * d->tc); ++i) {
        k->A[i] = RFE_R(0.0);
    }
    sckf_centred(d->n, k->pts, k->x, s2n, k->A, d->tc);
    if (sckf_gain(k, d->n, s2n) != RFE_OK) {
        return RFE_ERR_NONFINITE;
    }
    if (rfe_cub_correct(k->x, k->Kt, y, k->zhat, d->n, d->nz, d->n, k->xn) != RFE_OK) {
        return RFE_ERR_NONFINITE;
    }
    /* [Xc - K Zc | K S_R]: Zc again (Tria overwrote it); K Zc summed over the rows in order */
    centred_z(k, d->n, s2n, zc);
    for (i = 0u; i < d->n; ++i) {
        for (j = 0u; j < d->np; ++j) {
            rfe_real_t kz = k->Kt[i] * zc[j];
            for (r = 1u; r < d->nz; ++r) {
                kz += k->Kt[(r * d->n) + i] * zc[(r * d->zc) + j];
            }
            k->A[(i * d->tc) + j] -= kz;
        }
        for (r = 0u; r < d->nz; ++r) {
            k->A[(i * d->tc) + d->np + r] = k->Kt[(r * d->n) + i] * k->sr[r];
        }
    }
    return factor_and_commit(t, d->n, d->zc);
}

/* §15.3 the step at state dimension @p n: time update, measurement update; not OK when
 * either failed or left x or S not finite. */
static rfe_status_t sckf_step_n(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp,
                                const rfe_tid_input_t *u, size_t n)
{
    const rfe_real_t s2n = RFE_SQRT(RFE_R(2.0) * (rfe_real_t)n);
    rfe_tid_sckf_t *k = &tid->sk;
    rfe_status_t st = sckf_time_update(tid, n, smp, s2n);
    if (st == RFE_OK) {
        st = meas_update(tid, n, smp, u, s2n);
    }
    if ((st == RFE_OK) &&
        ((rfe_all_finite(k->x, n) == 0) || (rfe_all_finite(k->S, n * n) == 0))) {
        st = RFE_ERR_NONFINITE;
    }
    return st;
}

uint32_t rfe_tid_sckf_step(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp,
                           const rfe_tid_input_t *u)
{
    /* n a constant in each call (dims_n) */
    const rfe_status_t st = (sckf_n(tid) > NXP) ? sckf_step_n(tid, smp, u, NXP + 1u)
                                                : sckf_step_n(tid, smp, u, NXP);
    if (st != RFE_OK) {
        /* §15.3 lost: the prior at this sample */
        rfe_tid_sckf_prior(tid, smp->yaw_rate, smp->delta);
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

/* §15.4 the outputs at state dimension @p n into tid->last. */
static void sckf_estimate_n(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp,
                            const rfe_tid_input_t *u, uint32_t flags, size_t n)
{
    static const size_t OUT_Q[NQ] = {RFE_TID_OUT_BETA, RFE_TID_OUT_FY_F, RFE_TID_OUT_FY_R,
                                     RFE_TID_OUT_B_F, RFE_TID_OUT_B_R};
    const sckf_dims_t d = dims_n(n);
    rfe_tid_sckf_t *k = &tid->sk;
    rfe_tyre_id_estimate_t *e = &tid->last;
    const rfe_real_t w = RFE_R(1.0) / (rfe_real_t)d.np;
    rfe_real_t fz[2];
    rfe_real_t qm[NQ];
    size_t i;
    size_t j;
    /* beta, the forces and B: mean and sd over the points of (x, S), parameters clipped
     * (with §15.7 the forces at the point's delta); one row of k->A per point (ld NQ) */
    rfe_cub_points(k->x, k->S, d.n, d.n, k->pts);
    for (j = 0u; j < d.np; ++j) {
        const rfe_real_t *pt = &k->pts[j * d.n];
        rfe_real_t xc[RFE_TID_DIM];
        rfe_real_t *q = &k->A[j * NQ];
        clipped(tid, pt, xc);
        q[0] = RFE_ATAN2(xc[RFE_TID_VY], smp->vx);
        if (d.ds != 0) {
            const rfe_tid_input_t uj = at_delta(u, pt[ID], 0);
            rfe_tid_forces(tid, xc, &uj, &q[1], &q[2]);
        } else {
            rfe_tid_forces(tid, xc, u, &q[1], &q[2]);
        }
        q[3] = xc[RFE_TID_K_F] / (xc[RFE_TID_C_F] * xc[RFE_TID_D_F]);
        q[4] = xc[RFE_TID_K_R] / (xc[RFE_TID_C_R] * xc[RFE_TID_D_R]);
    }
    rfe_cub_mean(k->A, d.n, NQ, NQ, qm);
    for (i = 0u; i < NQ; ++i) {
        e->mean[OUT_Q[i]] = qm[i];
        e->sd[OUT_Q[i]] = spread(&k->A[i], d.np, NQ, qm[i], w);
    }
    /* the states and parameters: x and the row norms of S (the output of column i: vy, r,
     * then the parameters in order; delta, last, is no output) */
    for (i = 0u; i < NXP; ++i) {
        static const size_t OUT_X[RFE_TID_DIM] = {
            RFE_TID_OUT_VY,  RFE_TID_OUT_R,   RFE_TID_OUT_D_F, RFE_TID_OUT_C_F, RFE_TID_OUT_K_F,
            RFE_TID_OUT_E_F, RFE_TID_OUT_D_R, RFE_TID_OUT_C_R, RFE_TID_OUT_K_R, RFE_TID_OUT_E_R};
        const size_t o = OUT_X[i];
        e->mean[o] = k->x[i];
        e->sd[o] = spread(&k->S[i * d.n], i + 1u, 1u, RFE_R(0.0), RFE_R(1.0));
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

void rfe_tid_sckf_estimate(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp,
                           const rfe_tid_input_t *u, uint32_t flags)
{
    /* n a constant in each call (dims_n) */
    if (sckf_n(tid) > NXP) {
        sckf_estimate_n(tid, smp, u, flags, NXP + 1u);
    } else {
        sckf_estimate_n(tid, smp, u, flags, NXP);
    }
}
