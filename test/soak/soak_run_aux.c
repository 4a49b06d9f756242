/**
 * @file soak_run_aux.c
 * @brief The soak of the two estimators beside the friction estimator, in the number type of
 *        the build (float, or double with -DRFE_REAL_DOUBLE): the mass and grade estimator
 *        (docs/MASS_GRADE.md) and the tyre identifier (docs/TYRE_ID.md) over the soak drive,
 *        their invariants checked at every step. It exists because every estimator must meet
 *        what the friction estimator meets, the soak included.
 *
 * What each is fed, from the drive's rows (DATA.md columns; the drive is flat, grade 0):
 *  - mass and grade: v = R (omega_fl + omega_fr + omega_rl + omega_rr) / 4 (MASS_GRADE.md §1);
 *    ax; dt from the time stamps. The drive has no drive_torque column (the simulator's
 *    torques are inputs it does not log), so the runner derives the torque at the wheels
 *    from the drive's own longitudinal dynamics, with the log's mass m and radius R and the
 *    estimator's own resistance and rotating-mass values (a car that matches its model):
 *    F_k = (m + m_rot) dvx/dt + m g (f_c + f_r vx_k) + rho C_d S vx_k^2 / 2, dvx/dt the
 *    log's vx differenced over +-0.25 s (DV_HALF: its sensor noise), the force the model
 *    (§1) needs for the drive's acceleration. Where F_k < -0.1 m g (a deceleration no engine
 *    braking gives) the car is braking: the brake flag is set and the torque is 0 (the
 *    brake's force is not on the bus, §4.2); else T_k = R F_k. So the estimator should find
 *    about the log's m and a grade of 0; the invariants do not depend on it.
 *  - tyre identifier: dt, delta, vx (the log's, as a test car's sensor or the observer
 *    gives it), yaw rate, ay, ax; the vehicle and tyre data from the log's metadata on the
 *    default preset (as mu_replay), the identifier's defaults, seed 1, RFE_TID_N particles;
 *    only the rows with from <= t < to (the identifier costs ~9 200 instructions per
 *    particle and step: make soak-short runs a stretch, make soak the whole drive).
 *
 * Invariants at every step: no error on a row inside the limits (every row of the drive);
 * the estimate finite, every sd >= 0; mass and grade: the mass in [m_min, m_max], |grade| <=
 * theta_max, q_mv >= 0, the state x and P finite with a non-negative diagonal; tyre
 * identifier: known flags, exactly one of FIRST, HELD, UPDATED, LOST (RESAMPLED only with
 * UPDATED), n_eff in [1, N], every
 * particle's parameters inside their bounds exactly and the means of D, C, K, E inside them
 * to the rounding of a weighted sum, every log weight <= 0 and never NaN.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "param_file.h"
#include "replay_real.h"
#include "rfe/mass_grade.h"
#include "rfe/tyre_id.h"
#if defined(RFE_REAL_DOUBLE) && defined(SOAK_Q31)
#include "fixed_conv.h"
#include "rfe/component/params_conv.h"
#include "rfe/mass_grade_q31.h"
#endif
#include "soak.h"

#if defined(RFE_REAL_DOUBLE)
#define AUX_MEAN_TOL (4.0 * RFE_TID_N * 1.1102230246251565e-16)
#else
#define AUX_MEAN_TOL (4.0 * RFE_TID_N * 5.9604645e-08)
#endif

static void aux_violation(soak_aux_result_t *res, size_t i, double t, const char *why)
{
    if (res->violations++ == 0) {
        res->first_violation_step = (long)i;
        snprintf(res->first_violation, sizeof(res->first_violation), "t = %.2f s: %s", t, why);
    }
}

static int fin(rfe_real_t x)
{
    return isfinite((double)x);
}


/* Half the window of the speed's derivative [rows]: the log's vx carries sensor noise
 * (~0.05 m/s), which a one-row difference would turn into +-5 m/s^2 at 100 Hz; over +-0.25 s
 * it is ~0.1 m/s^2. */
#define DV_HALF 25u

/* The derived torque at row i and whether the car brakes there (see the file comment). */
static void torque_of(const rfe_sensor_log_t *log, size_t i, const rfe_mass_grade_params_t *mp,
                      double m, double *torque, int *brake)
{
    const size_t j0 = (i > DV_HALF) ? i - DV_HALF : 0u;
    const size_t j1 = (i + DV_HALF < log->n_rows) ? i + DV_HALF : log->n_rows - 1u;
    const rfe_sensor_row_t *a = &log->rows[j0];
    const rfe_sensor_row_t *b = &log->rows[j1];
    const double v = log->rows[i].vx;
    const double g = (double)mp->g;
    const double f = (m + (double)mp->m_rot) * (b->vx - a->vx) / (b->t - a->t) +
                     m * g * ((double)mp->fc + (double)mp->fr * v) +
                     0.5 * (double)mp->rho * (double)mp->cd * (double)mp->area * v * v;
    *brake = f < -0.1 * m * g;
    *torque = *brake ? 0.0 : (double)mp->R * f;
}

/* Sample i of the log for the estimator: the wheels' mean speed, the derived torque and
 * brake, ax. */
static void mg_sample(const rfe_sensor_log_t *log, size_t i, const rfe_mass_grade_params_t *mp,
                      double m, rfe_mass_grade_input_t *u)
{
    const rfe_sensor_row_t *row = &log->rows[i];
    double torque;
    int brake;
    memset(u, 0, sizeof(*u));
    torque_of(log, i, mp, m, &torque, &brake);
    u->dt = (rfe_real_t)((i > 0) ? row->t - log->rows[i - 1].t : 0.0);
    u->v = (rfe_real_t)((double)mp->R *
                        (((row->omega[0] + row->omega[1]) + row->omega[2]) + row->omega[3]) / 4.0);
    u->torque = (rfe_real_t)torque;
    u->ax = (rfe_real_t)row->ax;
    u->brake = brake ? 1u : 0u;
    u->has = RFE_MG_HAS_AX | RFE_MG_HAS_BRAKE;
}

static void check_mg(const rfe_mass_grade_t *mg, const rfe_mass_grade_estimate_t *e, char *why,
                     size_t n_why)
{
    const rfe_mass_grade_params_t *p = &mg->p;
    const rfe_real_t v[7] = {e->mass, e->sd_mass, e->grade, e->sd_grade, e->v, e->sd_v, e->q_mv};
    rfe_mass_grade_estimate_t got;
    int k;
    why[0] = '\0';
    for (k = 0; k < 7; ++k) {
        if (!fin(v[k])) {
            snprintf(why, n_why, "a non-finite estimate");
            return;
        }
    }
    for (k = 0; k < RFE_MG_N * RFE_MG_N; ++k) {
        if (!fin(mg->S[k]) || (k < RFE_MG_N && !fin(mg->x[k]))) {
            snprintf(why, n_why, "a non-finite state");
            return;
        }
    }
    if (e->sd_mass < 0 || e->sd_grade < 0 || e->sd_v < 0 || e->q_mv < 0 || mg->S[0] < 0 ||
        mg->S[4] < 0 || mg->S[8] < 0) {
        snprintf(why, n_why, "a negative sd, factor diagonal or q_mv");
    } else if (e->mass < p->m_min || e->mass > p->m_max) {
        snprintf(why, n_why, "mass %.6g outside [m_min, m_max]", (double)e->mass);
    } else if (e->grade < -p->theta_max || e->grade > p->theta_max) {
        snprintf(why, n_why, "|grade| %.6g beyond theta_max", (double)e->grade);
    } else if (rfe_mass_grade_get(mg, &got) != RFE_OK || got.mass != e->mass ||
               got.grade != e->grade || got.status != e->status) {
        snprintf(why, n_why, "get does not return the last estimate");
    }
}

/* The mass and grade runs' start, float and fixed point alike: the result emptied, the
 * configuration's preset with the log's R and g, and the log's mass m. 0, or -1 (said on
 * stderr) without parameters or a vx column. */
static int mg_setup(const rfe_sensor_log_t *log, const char *log_name, const soak_aux_cfg_t *cfg,
                    soak_aux_result_t *res, rfe_mass_grade_params_t *mp, double *m)
{
    rfe_params_t veh;
    memset(res, 0, sizeof(*res));
    res->first_violation_step = -1;
    res->lo = res->lo2 = INFINITY;
    res->hi = res->hi2 = -INFINITY;
    memset(mp, 0, sizeof(*mp));
    if (soak_params_of(log, log_name, RFE_PRESET_DEFAULT, &veh) != 0 ||
        rfe_mass_grade_params_preset(mp, RFE_MG_CAR,
                                     cfg->seed_config ? RFE_MG_SEED : RFE_MG_RECOMMENDED) != RFE_OK ||
        log->n_rows < 2 || !log->has_velocity) {
        fprintf(stderr, "soak: mass and grade %s: no parameters or no vx column\n", cfg->name);
        return -1;
    }
    mp->R = veh.vehicle.R;
    mp->g = veh.vehicle.g;
    *m = (double)veh.vehicle.m;
    return 0;
}

/* A mass and grade step counted by its status; an error inside the limits is a violation.
 * 1 when the step failed (nothing more to check). */
static int mg_counted(soak_aux_result_t *res, size_t i, double t, rfe_status_t st)
{
    char why[SOAK_WHY];
    ++res->steps;
    ++res->status[(st >= 0 && st < SOAK_STATUS_SLOTS) ? st : SOAK_STATUS_SLOTS - 1];
    if (!rfe_status_is_error(st)) {
        return 0;
    }
    snprintf(why, sizeof(why), "a row inside the limits failed with status %d (%s)", (int)st,
             rfe_status_str(st));
    aux_violation(res, i, t, why);
    return 1;
}

/* After a successful step: its invariant check's verdict (why, empty when it held) and the
 * ranges and the end of the mass [kg], the grade [rad] and the mass's sd, float or Q31 alike. */
static void mg_tracked(soak_aux_result_t *res, size_t i, double t, const char *why, double mass,
                       double grade, double sd_mass)
{
    if (why[0] != '\0') {
        aux_violation(res, i, t, why);
    }
    res->lo = fmin(res->lo, mass);
    res->hi = fmax(res->hi, mass);
    res->lo2 = fmin(res->lo2, grade);
    res->hi2 = fmax(res->hi2, grade);
    res->final = mass;
    res->final_sd = sd_mass;
}

int soak_run_mass_grade(const rfe_sensor_log_t *log, const char *log_name,
                        const soak_aux_cfg_t *cfg, soak_aux_result_t *res)
{
    static rfe_mass_grade_t mg;
    rfe_mass_grade_params_t mp;
    double m;
    size_t i;
    clock_t c0;
    if (mg_setup(log, log_name, cfg, res, &mp, &m) != 0) {
        return -1;
    }
    memset(&mg, 0, sizeof(mg));
    if (rfe_mass_grade_init(&mg, &mp) != RFE_OK) {
        fprintf(stderr, "soak: mass and grade %s: init failed\n", cfg->name);
        return -1;
    }
    res->truth = m;
    c0 = clock();
    for (i = 0; i < log->n_rows; ++i) {
        const rfe_sensor_row_t *row = &log->rows[i];
        rfe_mass_grade_input_t u;
        rfe_mass_grade_estimate_t e;
        rfe_status_t st;
        char why[SOAK_WHY];
        mg_sample(log, i, &mp, m, &u);
        st = rfe_mass_grade_step(&mg, &u, &e);
        if (mg_counted(res, i, row->t, st) != 0) {
            continue;
        }
        check_mg(&mg, &e, why, sizeof(why));
        mg_tracked(res, i, row->t, why, (double)e.mass, (double)e.grade, (double)e.sd_mass);
    }
    res->us_per_step = 1e6 * (double)(clock() - c0) / CLOCKS_PER_SEC /
                       (double)(res->steps ? res->steps : 1);
    return 0;
}

#if defined(RFE_REAL_DOUBLE) && defined(SOAK_Q31)
/* The fixed-point twin on the same samples rounded to their formats (rfe_fix_from_double;
 * a saturated sample is counted as a violation: the drive stays inside every format). */
static void check_mg_q31(const rfe_mass_grade_q31_t *mg, const rfe_mass_grade_estimate_q31_t *e,
                         char *why, size_t n_why)
{
    const rfe_mass_grade_params_q31_t *p = &mg->p;
    rfe_mass_grade_estimate_q31_t got;
    why[0] = '\0';
    if (e->sd_mass < 0 || e->sd_grade < 0 || e->sd_v < 0 || e->q_mv < 0 || mg->S[0] < 0 ||
        mg->S[4] < 0 || mg->S[8] < 0) {
        snprintf(why, n_why, "a negative sd, factor diagonal or q_mv");
    } else if (e->mass < p->m_min || e->mass > p->m_max) {
        snprintf(why, n_why, "mass %ld (Q14) outside [m_min, m_max]", (long)e->mass);
    } else if (e->grade < -p->theta_max || e->grade > p->theta_max) {
        snprintf(why, n_why, "|grade| %ld (Q29) beyond theta_max", (long)e->grade);
    } else if (e->sat != 0u) {
        snprintf(why, n_why, "%lu saturations in a step", (unsigned long)e->sat);
    } else if (rfe_mass_grade_get_q31(mg, &got) != RFE_OK ||
               memcmp(&got, e, sizeof(got)) != 0) {
        snprintf(why, n_why, "get does not return the last estimate");
    }
}

int soak_run_mass_grade_q31(const rfe_sensor_log_t *log, const char *log_name,
                            const soak_aux_cfg_t *cfg, soak_aux_result_t *res)
{
    static rfe_mass_grade_q31_t mg;
    rfe_mass_grade_params_t mp;
    rfe_mass_grade_params_q31_t q;
    double m;
    size_t i;
    clock_t c0;
    if (mg_setup(log, log_name, cfg, res, &mp, &m) != 0) {
        return -1;
    }
    memset(&mg, 0, sizeof(mg));
    if (rfe_mass_grade_params_to_q31(&mp, &q) != RFE_OK || rfe_mass_grade_init_q31(&mg, &q) != RFE_OK) {
        fprintf(stderr, "soak: mass and grade %s (q31): init failed\n", cfg->name);
        return -1;
    }
    res->truth = m;
    c0 = clock();
    for (i = 0; i < log->n_rows; ++i) {
        const rfe_sensor_row_t *row = &log->rows[i];
        rfe_mass_grade_input_t u;
        rfe_mass_grade_input_q31_t uq;
        rfe_mass_grade_estimate_q31_t e;
        rfe_status_t st;
        uint32_t sat = 0u;
        char why[SOAK_WHY];
        mg_sample(log, i, &mp, m, &u);
        memset(&uq, 0, sizeof(uq));
        uq.dt = rfe_fix_from_double(u.dt, RFE_MG_Q_DT, &sat);
        uq.v = rfe_fix_from_double(u.v, RFE_MG_Q_V, &sat);
        uq.torque = rfe_fix_from_double(u.torque, RFE_MG_Q_TORQUE, &sat);
        uq.ax = rfe_fix_from_double(u.ax, RFE_MG_Q_V, &sat);
        uq.brake = u.brake;
        uq.has = u.has;
        st = rfe_mass_grade_step_q31(&mg, &uq, &e);
        if (sat != 0u) {
            aux_violation(res, i, row->t, "a sample beyond its Q format");
        }
        if (mg_counted(res, i, row->t, st) != 0) {
            continue;
        }
        check_mg_q31(&mg, &e, why, sizeof(why));
        mg_tracked(res, i, row->t, why, rfe_fix_to_double(e.mass, RFE_MG_Q_M),
                   rfe_fix_to_double(e.grade, RFE_MG_Q_TH), rfe_fix_to_double(e.sd_mass, RFE_MG_Q_M));
    }
    res->us_per_step = 1e6 * (double)(clock() - c0) / CLOCKS_PER_SEC /
                       (double)(res->steps ? res->steps : 1);
    return 0;
}
#endif

static void check_tid(const rfe_tyre_id_t *t, const rfe_tyre_id_estimate_t *e, char *why,
                      size_t n_why)
{
    static const int out_of_par[RFE_TID_PAR] = {RFE_TID_OUT_D_F, RFE_TID_OUT_C_F,
                                                RFE_TID_OUT_K_F, RFE_TID_OUT_E_F,
                                                RFE_TID_OUT_D_R, RFE_TID_OUT_C_R,
                                                RFE_TID_OUT_K_R, RFE_TID_OUT_E_R};
    const uint32_t known = RFE_TID_UPDATED | RFE_TID_RESAMPLED | RFE_TID_HELD | RFE_TID_FIRST |
                           RFE_TID_LOST;
    const uint32_t phase =
        e->flags & (RFE_TID_FIRST | RFE_TID_HELD | RFE_TID_UPDATED | RFE_TID_LOST);
    int i;
    int j;
    why[0] = '\0';
    if ((e->flags & ~known) != 0u ||
        (phase != RFE_TID_FIRST && phase != RFE_TID_HELD && phase != RFE_TID_UPDATED &&
         phase != RFE_TID_LOST) ||
        (phase != RFE_TID_UPDATED && (e->flags & RFE_TID_RESAMPLED) != 0u)) {
        snprintf(why, n_why, "flags %#x", (unsigned)e->flags);
        return;
    }
    for (i = 0; i < RFE_TID_OUTPUTS; ++i) {
        if (!fin(e->mean[i]) || !fin(e->sd[i]) || e->sd[i] < 0) {
            snprintf(why, n_why, "output %d: mean %g sd %g", i, (double)e->mean[i],
                     (double)e->sd[i]);
            return;
        }
    }
    if (!fin(e->n_eff) || (double)e->n_eff < 1.0 - AUX_MEAN_TOL ||
        (double)e->n_eff > RFE_TID_N * (1.0 + AUX_MEAN_TOL)) {
        snprintf(why, n_why, "n_eff %g outside [1, N]", (double)e->n_eff);
        return;
    }
    for (j = 0; j < RFE_TID_PAR; ++j) {
        const double lo = (double)t->c.lo[j];
        const double hi = (double)t->c.hi[j];
        const double tol = AUX_MEAN_TOL * fmax(fabs(lo), fabs(hi));
        const double mean = (double)e->mean[out_of_par[j]];
        if (mean < lo - tol || mean > hi + tol) {
            snprintf(why, n_why, "the mean of parameter %d, %g, outside [%g, %g]", j, mean, lo, hi);
            return;
        }
    }
    for (i = 0; i < RFE_TID_N; ++i) {
        if (isnan((double)t->logw[i]) || t->logw[i] > 0) {
            snprintf(why, n_why, "log weight %d is %g", i, (double)t->logw[i]);
            return;
        }
        for (j = 0; j < RFE_TID_PAR; ++j) {
            const rfe_real_t x = t->x[i][RFE_TID_STATES + j];
            if (!(x >= t->c.lo[j] && x <= t->c.hi[j])) {
                snprintf(why, n_why, "particle %d's parameter %d outside its bounds", i, j);
                return;
            }
        }
    }
}

int soak_run_tyre_id(const rfe_sensor_log_t *log, const char *log_name,
                     const soak_aux_cfg_t *cfg, soak_aux_result_t *res)
{
    static rfe_tyre_id_t tid;
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    size_t i;
    size_t prev = 0;
    int started = 0;
    clock_t c0;
    memset(res, 0, sizeof(*res));
    res->first_violation_step = -1;
    res->lo = res->lo2 = INFINITY;
    res->hi = res->hi2 = -INFINITY;
    memset(&tp, 0, sizeof(tp));
    if (soak_params_of(log, log_name, RFE_PRESET_DEFAULT, &veh) != 0 || rfe_tyre_id_params_default(&tp) != RFE_OK ||
        !log->has_velocity) {
        fprintf(stderr, "soak: tyre identifier %s: no parameters or no vx column\n", cfg->name);
        return -1;
    }
    tp.filter = cfg->seed_config ? RFE_TID_SIR : RFE_TID_APF;
    memset(&tid, 0, sizeof(tid));
    if (rfe_tyre_id_init(&tid, &tp, &veh, 1u) != RFE_OK) {
        fprintf(stderr, "soak: tyre identifier %s: init failed\n", cfg->name);
        return -1;
    }
    c0 = clock();
    for (i = 0; i < log->n_rows; ++i) {
        const rfe_sensor_row_t *row = &log->rows[i];
        rfe_tyre_id_sample_t s;
        rfe_tyre_id_estimate_t e;
        rfe_status_t st;
        char why[SOAK_WHY];
        if (row->t < cfg->from || row->t >= cfg->to) {
            continue;
        }
        memset(&s, 0, sizeof(s));
        s.dt = (rfe_real_t)(started ? row->t - log->rows[prev].t : 0.0);
        s.delta = (rfe_real_t)row->delta;
        s.vx = (rfe_real_t)row->vx;
        s.yaw_rate = (rfe_real_t)row->yaw_rate;
        s.ay = (rfe_real_t)row->ay;
        s.ax = (rfe_real_t)row->ax;
        st = rfe_tyre_id_step(&tid, &s, &e);
        prev = i;
        ++res->steps;
        ++res->status[(st >= 0 && st < SOAK_STATUS_SLOTS) ? st : SOAK_STATUS_SLOTS - 1];
        if (st != RFE_OK) {
            snprintf(why, sizeof(why), "a row inside the limits failed with status %d (%s)",
                     (int)st, rfe_status_str(st));
            aux_violation(res, i, row->t, why);
            continue;
        }
        started = 1;
        res->updated += (e.flags & RFE_TID_UPDATED) != 0u;
        res->held += (e.flags & RFE_TID_HELD) != 0u;
        res->resampled += (e.flags & RFE_TID_RESAMPLED) != 0u;
        res->lost += (e.flags & RFE_TID_LOST) != 0u;
        check_tid(&tid, &e, why, sizeof(why));
        if (why[0] != '\0') {
            aux_violation(res, i, row->t, why);
        }
        res->lo = fmin(res->lo, (double)e.mean[RFE_TID_OUT_MU_F]);
        res->hi = fmax(res->hi, (double)e.mean[RFE_TID_OUT_MU_F]);
        res->lo2 = fmin(res->lo2, (double)e.n_eff);
        res->hi2 = fmax(res->hi2, (double)e.n_eff);
        res->final = (double)e.mean[RFE_TID_OUT_K_F];
        res->final_sd = (double)e.sd[RFE_TID_OUT_K_F];
    }
    res->us_per_step = 1e6 * (double)(clock() - c0) / CLOCKS_PER_SEC /
                       (double)(res->steps ? res->steps : 1);
    return 0;
}
