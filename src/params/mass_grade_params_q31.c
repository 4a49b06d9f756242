/**
 * @file mass_grade_params_q31.c
 * @brief The mass and grade estimator's fixed-point parameters (rfe/mass_grade_params_q31.h):
 *        the unscented weights in integers and the validation on the Q values
 *        (docs/MASS_GRADE.md §6, docs/FIXED_POINT.md "Mass and grade").
 */
#include "rfe/mass_grade_params_q31.h"

#include "rfe/component/fxmath.h"
#include "numerics/internal_q31.h"
#include "numerics/xf_q31.h"

/* 3 (the state's size n) in Q28 and in Q27; 1 in Q30; 1.5 rad in Q29 (the grade bound's
 * limit, MASS_GRADE.md §6). */
#define N_Q28 ((int64_t)805306368)
#define N_Q27 ((int64_t)402653184)
#define ONE_Q27 ((int64_t)134217728)
#define HALF_Q27 ((rfe_fix_t)67108864)
#define ONE_Q30 ((int64_t)1073741824)
#define LIMIT_THETA_Q29 ((rfe_fix_t)805306368)
/* c < 16 in Q56: 2^60. */
#define C_MAX_Q56 ((int64_t)1152921504606846976)

/* §3 the spread c = n + lambda = alpha^2 (n + kappa) in Q27, with alpha^2 in Q28: alpha^2
 * exact in Q56 (|alpha| < 8), rounded to Q28; the product exact in Q56 once it is known to
 * be < 2^60 (c < 16). RFE_ERR_PARAM outside (1, 16). */
static rfe_status_t spread_q31(const rfe_mass_grade_params_q31_t *p, int64_t *a2, rfe_fix_t *c27)
{
    const int64_t sq = rfe_fix_shr64_round((int64_t)p->ut_alpha * (int64_t)p->ut_alpha, 28u);
    const int64_t k3 = N_Q28 + (int64_t)p->ut_kappa; /* n + kappa, Q28, |.| < 2^32 */
    int64_t c56;
    if ((sq <= 0) || (k3 <= 0) || (k3 > (C_MAX_Q56 / sq))) {
        return RFE_ERR_PARAM;
    }
    c56 = sq * k3;
    if (c56 >= C_MAX_Q56) {
        return RFE_ERR_PARAM;
    }
    *c27 = (rfe_fix_t)rfe_fix_shr64_round(c56, 29u); /* < 2^31 */
    *a2 = sq;
    return ((int64_t)*c27 > ONE_Q27) ? RFE_OK : RFE_ERR_PARAM; /* c <= 1: w_m,0 <= -2 */
}

rfe_status_t rfe_mass_grade_weights_q31(const rfe_mass_grade_params_q31_t *p,
                                        rfe_mg_weights_q31_t *w)
{
    int64_t a2 = 0;
    int64_t wc0;
    rfe_fix_t c27 = 0;
    rfe_mg_weights_q31_t t = {0};
    uint32_t sat = 0u;
    rfe_status_t st;
    if ((p == NULL) || (w == NULL)) {
        return RFE_ERR_NULL;
    }
    st = spread_q31(p, &a2, &c27);
    /* w_m,0 = (c - n) / c, w_i = (1/2) / c: exactly rounded quotients, Q27 / Q27 -> Q30 */
    if (st == RFE_OK) {
        st = rfe_fix_div((rfe_fix_t)((int64_t)c27 - N_Q27), c27, 30, &t.wm0, &sat);
    }
    if (st == RFE_OK) {
        st = rfe_fix_div(HALF_Q27, c27, 30, &t.wi, &sat);
    }
    /* w_c,0 = w_m,0 + 1 - alpha^2 + beta, Q30 in int64 (every term < 2^36); below 4 by more
     * than 1 LSB, so that its Q29 rounding below fits an int32 */
    wc0 = (((int64_t)t.wm0 + ONE_Q30) - (a2 * 4)) + ((int64_t)p->ut_beta * 4);
    if ((st != RFE_OK) || (wc0 < 0) || (wc0 >= ((4 * ONE_Q30) - 1))) {
        return RFE_ERR_PARAM;
    }
    /* the roots: w_c,0 rounded to Q29 (< 2^31), sqrt to Q30; w_i in Q30; c Q27 -> Q29 */
    st = rfe_fix_sqrt((rfe_fix_t)rfe_fix_shr64_round(wc0, 1u), 29u, 30u, &t.sqrt_wc0, &sat);
    if (st == RFE_OK) {
        st = rfe_fix_sqrt(t.wi, 30u, 30u, &t.sqrt_wi, &sat);
    }
    if (st == RFE_OK) {
        st = rfe_fix_sqrt(c27, 27u, 29u, &t.sqrt_c, &sat);
    }
    if ((st != RFE_OK) || (sat != 0u)) {
        return RFE_ERR_PARAM; /* a root at the top of its format: outside the domain */
    }
    *w = t;
    return RFE_OK;
}

/* §6 the values that must be > 0. */
static int positive_fields_ok_q31(const rfe_mass_grade_params_q31_t *p)
{
    const rfe_fix_t v[14] = {p->R,     p->g,        p->m0,      p->sd_m0,   p->sd_theta0,
                             p->q_v,   p->q_mc,     p->q_theta, p->r_v,     p->r_ax,
                             p->ut_alpha, p->m_min, p->theta_max, p->dt_max};
    size_t i;
    for (i = 0u; i < 14u; ++i) {
        if (v[i] <= 0) {
            return 0;
        }
    }
    return 1;
}

/* §6 the values that must be >= 0. */
static int non_negative_fields_ok_q31(const rfe_mass_grade_params_q31_t *p)
{
    const rfe_fix_t v[19] = {p->fc,      p->fr,      p->rho,     p->cd,      p->area,
                             p->m_rot,   p->q_mv0,   p->t_adapt, p->mv_stop, p->v_min,
                             p->t_brake, p->t_shift, p->p_brake_on, p->slip_max,
                             p->ay_max,  p->t_curve, p->ut_beta, p->pause_grade_slip,
                             p->pause_grade_dv};
    size_t i;
    for (i = 0u; i < 19u; ++i) {
        if (v[i] < 0) {
            return 0;
        }
    }
    return 1;
}

/* §6 the relations between values, as the float twin's relations_ok. mv_stop q_mc^2 <
 * q_mv0^2 is compared in rfe_xf_t (numerics/xf_q31.h: the squares exact in Q28, the product
 * rounded to 2^-30 relative), so a pair within ~1e-9 of equality may be decided otherwise
 * than in double; no other range restriction. */
static int relations_ok_q31(const rfe_mass_grade_params_q31_t *p)
{
    rfe_mg_weights_q31_t w;
    uint32_t sat = 0u;
    if ((p->m_min >= p->m0) || (p->m0 >= p->m_max)) {
        return 0;
    }
    if ((rfe_fix_abs(p->theta0, &sat) >= p->theta_max) || (p->theta_max >= LIMIT_THETA_Q29)) {
        return 0;
    }
    if ((int64_t)p->pause_grade_slip > ONE_Q30) { /* a slip ratio (>= 0: above) */
        return 0;
    }
    if ((int64_t)p->pause_grade_dv > ((int64_t)RFE_MG_PAUSE_GRADE_DV_MAX_MS * 16777216)) { /* Q24 */
        return 0; /* m/s (>= 0: above) */
    }
    if (rfe_mass_grade_weights_q31(p, &w) != RFE_OK) {
        return 0;
    }
    if (p->adaptive == 1u) {
        const rfe_xf_t qmc2 = rfe_xf_make((int64_t)p->q_mc * (int64_t)p->q_mc, -28);
        const rfe_xf_t qmv2 = rfe_xf_make((int64_t)p->q_mv0 * (int64_t)p->q_mv0, -28);
        const rfe_xf_t stop = rfe_xf_mul(rfe_xf_of(p->mv_stop, RFE_MG_Q_COEF), qmc2);
        if (rfe_xf_sign(rfe_xf_sub(stop, qmv2)) >= 0) {
            return 0;
        }
    }
    return 1;
}

/* §4.7 the two-level walk, as the float twin's walk_ok on the Q values: q_theta_hi (Q29) 0
 * or in [q_theta, 0.1]; 0 < theta_rate_off <= theta_rate_on <= 0.1 (Q30); theta_rate_tau,
 * theta_rate_avg (Q24) in [dt_max, 60] s, compared with dt_max (Q30) exactly in Q30, so
 * that dt <= dt_max <= tau and dt/tau <= 1 fits Q30 on every step that is not a start. */
static int walk_ok_q31(const rfe_mass_grade_params_q31_t *p)
{
    const int64_t max_q29 = (int64_t)RFE_MG_WALK_MAX_MILLI * (INT64_C(1) << 29); /* x 1000 */
    const int64_t max_q30 = (int64_t)RFE_MG_WALK_MAX_MILLI * (INT64_C(1) << 30);
    const rfe_fix_t taus[2] = {p->theta_rate_tau, p->theta_rate_avg};
    int ok = 1;
    size_t i;
    if ((p->q_theta_hi != 0) &&
        ((p->q_theta_hi < p->q_theta) || (((int64_t)p->q_theta_hi * 1000) > max_q29))) {
        ok = 0;
    }
    if ((p->theta_rate_off <= 0) || (p->theta_rate_off > p->theta_rate_on) ||
        (((int64_t)p->theta_rate_on * 1000) > max_q30)) {
        ok = 0;
    }
    for (i = 0u; i < 2u; ++i) {
        if ((((int64_t)taus[i] * 64) < (int64_t)p->dt_max) ||
            ((int64_t)taus[i] > ((int64_t)RFE_MG_WALK_TAU_MAX_S * 16777216))) { /* Q24 */
            ok = 0;
        }
    }
    return ok;
}

/* §4.8 the mismatch monitor, as the float twin's mismatch_ok on the Q values: mm_tau (Q24)
 * in [dt_max, 60] s, compared with dt_max (Q30) exactly in Q30 (dt/tau <= 1 fits Q30 on
 * every update); mm_e (Q24) in [0, 100]. */
static int mismatch_ok_q31(const rfe_mass_grade_params_q31_t *p)
{
    return ((((int64_t)p->mm_tau * 64) >= (int64_t)p->dt_max) &&
            ((int64_t)p->mm_tau <= ((int64_t)RFE_MG_WALK_TAU_MAX_S * 16777216)) && (p->mm_e >= 0) &&
            ((int64_t)p->mm_e <= ((int64_t)RFE_MG_MM_E_MAX * 16777216))) /* Q24 */
               ? 1
               : 0;
}

rfe_status_t rfe_mass_grade_params_validate_q31(const rfe_mass_grade_params_q31_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    if ((p->adaptive > 1u) || (p->use_ax > 1u) || (p->pause_grade > RFE_MG_PAUSE_GRADE_ALL)) {
        return RFE_ERR_PARAM;
    }
    if ((positive_fields_ok_q31(p) == 0) || (non_negative_fields_ok_q31(p) == 0) ||
        (relations_ok_q31(p) == 0) || (walk_ok_q31(p) == 0) || (mismatch_ok_q31(p) == 0)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}
