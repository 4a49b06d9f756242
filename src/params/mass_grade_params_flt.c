/**
 * @file mass_grade_params_flt.c
 * @brief The mass and grade estimator's presets and validation (docs/MASS_GRADE.md §6).
 */
#include "rfe/mass_grade_params.h"

#include "numerics/internal.h"

/* The state's size n = 3 ([v, M, theta], rfe/mass_grade.h RFE_MG_N, a layer above) in the
 * unscented transform's lambda (§3). */
#define MG_N RFE_R(3.0)

/* §6 the car's values and the recommended configuration. */
static void car(rfe_mass_grade_params_t *p)
{
    p->R = RFE_R(0.325);
    p->g = RFE_R(9.81);
    p->fc = RFE_R(0.010);
    p->fr = RFE_R(0.00015);
    p->rho = RFE_R(1.2);
    p->cd = RFE_R(0.30);
    p->area = RFE_R(2.2);
    p->m_rot = RFE_R(45.4);
    p->m0 = RFE_R(1830.0);
    p->theta0 = RFE_R(0.0);
    p->sd_m0 = RFE_R(500.0);
    p->sd_theta0 = RFE_R(0.05);
    p->q_v = RFE_R(0.02);
    p->q_mc = RFE_R(1.0);
    p->q_mv0 = RFE_R(300.0);
    p->q_theta = RFE_R(0.004);
    p->r_v = RFE_R(0.05);
    p->r_ax = RFE_R(0.1);
    p->ut_alpha = RFE_R(1.0);
    p->ut_beta = RFE_R(2.0);
    p->ut_kappa = RFE_R(0.0);
    p->adaptive = 0u;
    p->use_ax = 1u;
    p->t_adapt = RFE_R(1.0);
    p->mv_stop = RFE_R(0.001);
    p->v_min = RFE_R(3.0);
    p->t_brake = RFE_R(1.0);
    p->t_shift = RFE_R(1.0);
    p->p_brake_on = RFE_R(1.0e5);
    p->slip_max = RFE_R(0.05);
    p->ay_max = RFE_R(0.0);
    p->t_curve = RFE_R(1.0);
    p->pause_grade = (rfe_real_t)RFE_MG_PAUSE_GRADE_BRAKE; /* the brake bit (§4.2) */
    p->pause_grade_slip = RFE_R(0.05);
    p->pause_grade_dv = RFE_R(0.2);
    p->m_min = RFE_R(300.0);
    p->m_max = RFE_R(60000.0);
    p->theta_max = RFE_R(0.35);
    p->dt_max = RFE_R(1.0);
    p->q_theta_hi = RFE_R(0.008); /* §4.7 the two-level walk on (MASS_GRADE_RESULTS.md
                                   * "The grade's two-level walk"); the seed's preset: off */
    p->theta_rate_on = RFE_R(0.002);
    p->theta_rate_off = RFE_R(0.001);
    p->theta_rate_tau = RFE_R(1.0);
    p->theta_rate_avg = RFE_R(3.0);
    p->mm_tau = RFE_R(10.0); /* §4.8 issue 19's 10 s */
    p->mm_e = RFE_R(0.3);    /* §4.8 2 x the clean logs' largest |EMA| (MASS_GRADE_RESULTS.md
                              * "A model-mismatch monitor on the ax row") */
}

/* §6 the truck column: the values that differ from the car's. */
static void truck(rfe_mass_grade_params_t *p)
{
    p->R = RFE_R(0.45);
    p->fc = RFE_R(0.0065);
    p->fr = RFE_R(0.00005);
    p->cd = RFE_R(0.60);
    p->area = RFE_R(6.0);
    p->m_rot = RFE_R(158.0);
    p->m0 = RFE_R(4000.0);
    p->sd_m0 = RFE_R(2000.0);
    p->q_mc = RFE_R(3.0);
    p->q_mv0 = RFE_R(1000.0);
}

rfe_status_t rfe_mass_grade_params_default(rfe_mass_grade_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    car(p);
    return RFE_OK;
}

rfe_status_t rfe_mass_grade_params_preset(rfe_mass_grade_params_t *p, rfe_mg_vehicle_t vehicle,
                                          rfe_mg_config_t config)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    if (((vehicle != RFE_MG_CAR) && (vehicle != RFE_MG_TRUCK)) ||
        ((config != RFE_MG_RECOMMENDED) && (config != RFE_MG_SEED))) {
        return RFE_ERR_PARAM;
    }
    car(p);
    if (vehicle == RFE_MG_TRUCK) {
        truck(p);
    }
    if (config == RFE_MG_SEED) {
        /* §6 the seed's configuration: its AUKF on speed and torque, adapted every
         * iteration (its period is not stated), its model without rotating parts */
        p->adaptive = 1u;
        p->use_ax = 0u;
        p->m_rot = RFE_R(0.0);
        p->t_adapt = RFE_R(0.0);
        p->pause_grade = RFE_R(0.0); /* the seed's pauses hold (inert without ax anyway) */
        p->q_theta_hi = RFE_R(0.0);  /* the seed's fixed grade walk (§4.7 off) */
    }
    return RFE_OK;
}

/* §6 the values that must be finite and > 0. */
static int positive_fields_ok(const rfe_mass_grade_params_t *p)
{
    const rfe_real_t v[14] = {p->R,    p->g,        p->m0,    p->sd_m0,    p->sd_theta0,
                              p->q_v,  p->q_mc,     p->q_theta, p->r_v,    p->r_ax,
                              p->ut_alpha, p->m_min, p->theta_max, p->dt_max};
    size_t i;
    for (i = 0u; i < 14u; ++i) {
        if (!rfe_is_finite(v[i]) || !(v[i] > RFE_R(0.0))) {
            return 0;
        }
    }
    return 1;
}

/* §6 the values that must be finite and >= 0. */
static int non_negative_fields_ok(const rfe_mass_grade_params_t *p)
{
    const rfe_real_t v[19] = {p->fc,      p->fr,      p->rho,     p->cd,      p->area,
                              p->m_rot,   p->q_mv0,   p->t_adapt, p->mv_stop, p->v_min,
                              p->t_brake, p->t_shift, p->p_brake_on, p->slip_max,
                              p->ay_max,  p->t_curve, p->ut_beta, p->pause_grade_slip,
                              p->pause_grade_dv};
    size_t i;
    for (i = 0u; i < 19u; ++i) {
        if (!rfe_is_finite(v[i]) || !(v[i] >= RFE_R(0.0))) {
            return 0;
        }
    }
    return 1;
}

/* §6 the relations between values: the bounds around the start, the points' spread and an
 * adaptation that has something to adapt. */
static int relations_ok(const rfe_mass_grade_params_t *p)
{
    const rfe_real_t a2 = p->ut_alpha * p->ut_alpha;
    const rfe_real_t c = a2 * (MG_N + p->ut_kappa); /* n + lambda = alpha^2 (n + kappa) */
    if (!rfe_is_finite(p->theta0) || !rfe_is_finite(p->ut_kappa) || !rfe_is_finite(p->m_max)) {
        return 0;
    }
    if (!(p->m_min < p->m0) || !(p->m0 < p->m_max)) {
        return 0;
    }
    if (!(RFE_FABS(p->theta0) < p->theta_max) || !(p->theta_max < RFE_R(1.5))) {
        return 0;
    }
    if (!(p->pause_grade_slip <= RFE_R(1.0))) { /* a slip ratio (finite, >= 0: above) */
        return 0;
    }
    if (!(p->pause_grade_dv <= (rfe_real_t)RFE_MG_PAUSE_GRADE_DV_MAX_MS)) { /* m/s (finite, >= 0: above) */
        return 0;
    }
    if (!(c > RFE_R(0.0)) || !rfe_is_finite(c)) {
        return 0;
    }
    if ((p->adaptive == 1u) && !((p->mv_stop * (p->q_mc * p->q_mc)) < (p->q_mv0 * p->q_mv0))) {
        return 0;
    }
    return 1;
}

/* §4.7 the two-level walk: every value finite; q_theta_hi 0 (off) or in [q_theta, 0.1];
 * 0 < theta_rate_off <= theta_rate_on <= 0.1; theta_rate_tau, theta_rate_avg in
 * [dt_max, 60] (so dt/tau <= 1 on every step that is not a start). */
static int walk_ok(const rfe_mass_grade_params_t *p)
{
    const rfe_real_t hi_max = (rfe_real_t)RFE_MG_WALK_MAX_MILLI / RFE_R(1000.0); /* 0.1 */
    const rfe_real_t tau_max = (rfe_real_t)RFE_MG_WALK_TAU_MAX_S;
    const rfe_real_t v[5] = {p->q_theta_hi, p->theta_rate_on, p->theta_rate_off,
                             p->theta_rate_tau, p->theta_rate_avg};
    int ok = 1;
    size_t i;
    for (i = 0u; i < 5u; ++i) {
        if (!rfe_is_finite(v[i])) {
            ok = 0;
        }
    }
    if ((p->q_theta_hi != RFE_R(0.0)) &&
        (!(p->q_theta <= p->q_theta_hi) || !(p->q_theta_hi <= hi_max))) {
        ok = 0;
    }
    if (!(p->theta_rate_off > RFE_R(0.0)) || !(p->theta_rate_off <= p->theta_rate_on) ||
        !(p->theta_rate_on <= hi_max)) {
        ok = 0;
    }
    for (i = 3u; i < 5u; ++i) {
        if (!(p->dt_max <= v[i]) || !(v[i] <= tau_max)) {
            ok = 0;
        }
    }
    return ok;
}

/* §4.8 the mismatch monitor: mm_tau in [dt_max, 60] (so dt/tau <= 1 on every update),
 * 0 <= mm_e <= 100; both finite (a NaN fails every comparison). */
static int mismatch_ok(const rfe_mass_grade_params_t *p)
{
    return ((p->dt_max <= p->mm_tau) && (p->mm_tau <= (rfe_real_t)RFE_MG_WALK_TAU_MAX_S) &&
            (p->mm_e >= RFE_R(0.0)) && (p->mm_e <= (rfe_real_t)RFE_MG_MM_E_MAX))
               ? 1
               : 0;
}

/* §6 pause_grade: one of the integers 0..7 (a sum of the bits 1 brake, 2 shift, 4 curve);
 * without use_ax its bits are inert (rfe_mg_pause_grade_bits), not refused. */
static int pause_grade_ok(const rfe_mass_grade_params_t *p)
{
    int ok = 0;
    uint32_t i;
    for (i = 0u; i <= RFE_MG_PAUSE_GRADE_ALL; ++i) {
        if (p->pause_grade == (rfe_real_t)i) {
            ok = 1;
        }
    }
    return ok;
}

rfe_status_t rfe_mass_grade_params_validate(const rfe_mass_grade_params_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    if ((p->adaptive > 1u) || (p->use_ax > 1u) || (pause_grade_ok(p) == 0)) {
        return RFE_ERR_PARAM;
    }
    if ((positive_fields_ok(p) == 0) || (non_negative_fields_ok(p) == 0) || (relations_ok(p) == 0) ||
        (walk_ok(p) == 0) || (mismatch_ok(p) == 0)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}
