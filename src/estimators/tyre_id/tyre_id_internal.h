/**
 * @file tyre_id_internal.h
 * @brief The tyre identifier's parts (docs/TYRE_ID.md), one module each: the single-track
 *        model with the Magic Formula per axle, its RK4 step and the likelihood
 *        (tyre_id_model_flt.c, §3-4, §5.1); the weights and the resampling
 *        (tyre_id_weights_flt.c, §5.1, §5.3-5.5). tyre_id_flt.c composes them. Every sum over
 *        particles runs in particle order and every expression is rounded as the page
 *        parenthesises it (§9): the double build is the reference's twin bit for bit.
 */
#ifndef RFE_TYRE_ID_INTERNAL_H
#define RFE_TYRE_ID_INTERNAL_H

#include "rfe/tyre_id.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_tid_forces    rfe_tid_forces_f64
#define rfe_tid_mu_loads  rfe_tid_mu_loads_f64
#define rfe_tid_rk4       rfe_tid_rk4_f64
#define rfe_tid_mean_input rfe_tid_mean_input_f64
#define rfe_tid_loglik    rfe_tid_loglik_f64
#define rfe_tid_ay        rfe_tid_ay_f64
#define rfe_tid_sckf_prior rfe_tid_sckf_prior_f64
#define rfe_tid_sckf_step rfe_tid_sckf_step_f64
#define rfe_tid_sckf_estimate rfe_tid_sckf_estimate_f64
#define rfe_tid_normalise rfe_tid_normalise_f64
#define rfe_tid_neff      rfe_tid_neff_f64
#define rfe_tid_cumsum    rfe_tid_cumsum_f64
#define rfe_tid_search    rfe_tid_search_f64
#define rfe_tid_draw      rfe_tid_draw_f64
#define rfe_tid_order     rfe_tid_order_f64
#define rfe_tid_reflect   rfe_tid_reflect_f64
#else
#define rfe_tid_forces    rfe_tid_forces_f32
#define rfe_tid_mu_loads  rfe_tid_mu_loads_f32
#define rfe_tid_rk4       rfe_tid_rk4_f32
#define rfe_tid_mean_input rfe_tid_mean_input_f32
#define rfe_tid_loglik    rfe_tid_loglik_f32
#define rfe_tid_ay        rfe_tid_ay_f32
#define rfe_tid_sckf_prior rfe_tid_sckf_prior_f32
#define rfe_tid_sckf_step rfe_tid_sckf_step_f32
#define rfe_tid_sckf_estimate rfe_tid_sckf_estimate_f32
#define rfe_tid_normalise rfe_tid_normalise_f32
#define rfe_tid_neff      rfe_tid_neff_f32
#define rfe_tid_cumsum    rfe_tid_cumsum_f32
#define rfe_tid_search    rfe_tid_search_f32
#define rfe_tid_draw      rfe_tid_draw_f32
#define rfe_tid_order     rfe_tid_order_f32
#define rfe_tid_reflect   rfe_tid_reflect_f32
#endif

/** The inputs of one evaluation of the model: delta, cos(delta), sin(delta), vx, ax (read
 *  with the ellipse of §3.5 only). */
typedef struct {
    rfe_real_t delta;
    rfe_real_t cd;
    rfe_real_t sd;
    rfe_real_t vx;
    rfe_real_t ax;
} rfe_tid_input_t;

/** §3.4 the loads of mu = D / Fz at @p ax into @p fz: the axle loads at ax; with the ellipse
 *  of §3.5 the static loads (D is then the peak at the static load). */
void rfe_tid_mu_loads(const rfe_tyre_id_t *tid, rfe_real_t ax, rfe_real_t fz[2]);

/** §3.1-3.2 the axle lateral forces of particle @p x (its columns) at inputs @p u. */
void rfe_tid_forces(const rfe_tyre_id_t *tid, const rfe_real_t x[RFE_TID_DIM],
                    const rfe_tid_input_t *u, rfe_real_t *fy_f, rfe_real_t *fy_r);

/** §4.1 the inputs the RK4 step holds over the period before sample @p smp: the means of the
 *  previous sample's and this sample's delta, vx and ax, cos of the mean delta (sin unused). */
rfe_tid_input_t rfe_tid_mean_input(const rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp);

/** §4.1 the noise-free step of (vy, r) of particle @p x over @p h: substeps RK4 steps with
 *  the inputs @p u held and the parameters fixed. */
void rfe_tid_rk4(const rfe_tyre_id_t *tid, const rfe_real_t x[RFE_TID_DIM],
                 const rfe_tid_input_t *u, rfe_real_t h, rfe_real_t out[RFE_TID_STATES]);

/** §5.1 the log-likelihood of (yaw_rate, ay) for states (vy, r) and the parameters @p th
 *  (RFE_TID_PAR of them) at the sample's inputs @p u; -infinity when it is not finite. When
 *  @p fy is not NULL, the axle forces of rfe_tid_ay into fy[0], fy[1]. */
rfe_real_t rfe_tid_loglik(const rfe_tyre_id_t *tid, rfe_real_t vy, rfe_real_t r,
                          const rfe_real_t *th, const rfe_tid_input_t *u, rfe_real_t yaw_rate,
                          rfe_real_t ay, rfe_real_t *fy);

/** §5.1 the predicted lateral acceleration ay_p = ((F_f c) + F_r) / m of states (vy, r) and
 *  parameters @p th at inputs @p u, and (when @p g is not NULL) its slope in delta,
 *  g = ((dF_f/dalpha c) - (F_f s)) / m; (when @p fy is not NULL) the axle forces F_f, F_r
 *  (§3.2, with §3.5's factors), bit for bit what rfe_tid_forces gives for the same particle. */
void rfe_tid_ay(const rfe_tyre_id_t *tid, rfe_real_t vy, rfe_real_t r, const rfe_real_t *th,
                const rfe_tid_input_t *u, rfe_real_t *ay_p, rfe_real_t *g, rfe_real_t *fy);
/** §15.2 the sigma-point filter's prior: x = (0, r_m, mean0), S = diag(sd0); with
 *  delta_state_q > 0 (§15.7) delta_m appended to x, sd_delta to S's diagonal. */
void rfe_tid_sckf_prior(rfe_tyre_id_t *tid, rfe_real_t r_meas, rfe_real_t delta_meas);
/** §15.3 the sigma-point filter's step over the sample @p smp (inputs @p u): its flags
 *  (UPDATED, or LOST when the prior was set again). */
uint32_t rfe_tid_sckf_step(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp,
                           const rfe_tid_input_t *u);
/** §15.4 the sigma-point filter's outputs at the sample's inputs into tid->last. */
void rfe_tid_sckf_estimate(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *smp,
                           const rfe_tid_input_t *u, uint32_t flags);
/** §5.1 log-sum-exp: w_i = exp(l_i - M) / S, and (when @p lw is not NULL; it may be @p l)
 *  lw_i = (l_i - M) - log S. Returns 0, writing nothing, when no weight is positive and
 *  finite (the maximum M is -infinity, +infinity or NaN), else 1. */
int rfe_tid_normalise(const rfe_real_t *l, size_t n, rfe_real_t *w, rfe_real_t *lw);

/** §5.1 N_eff = 1 / (w_0 w_0 + w_1 w_1 + ...), in that order. */
rfe_real_t rfe_tid_neff(const rfe_real_t *w, size_t n);

/** §5.3 C_i = w_0 + ... + w_i, in that order. */
void rfe_tid_cumsum(const rfe_real_t *w, size_t n, rfe_real_t *cum);

/** §5.3 the smallest i with x < cum[i], n - 1 if none. */
size_t rfe_tid_search(const rfe_real_t *cum, size_t n, rfe_real_t x);

/** §5.3 @p m parents from the cumulative weights @p cum (n of them) into @p idx, with the
 *  uniforms of stream @p s: multinomial (uniform j for parent j) or systematic (uniform 0). */
void rfe_tid_draw(const rfe_real_t *cum, size_t n, rfe_philox_t *s, rfe_tid_resample_t scheme,
                  size_t m, uint16_t *idx);

/** §5.4 @p order = the particles by descending weight, ties by ascending index (a stable
 *  bottom-up merge sort; @p tmp is its second buffer, n entries). */
void rfe_tid_order(const rfe_real_t *w, size_t n, uint16_t *order, uint16_t *tmp);

/** §5.5 reflect into [lo, hi]: one reflection at each bound, then a clip. */
rfe_real_t rfe_tid_reflect(rfe_real_t x, rfe_real_t lo, rfe_real_t hi);

#endif /* RFE_TYRE_ID_INTERNAL_H */
