/**
 * @file mg_logs.h
 * @brief The mass and grade tests' readers (include after test_common.h and table.h): the
 *        parameters a golden's metadata records (scenarios/golden/mass_grade/) and sample k
 *        of a mass and grade log (scenarios/mass_grade/) as the reference builds it.
 */
#ifndef RFE_TEST_MG_LOGS_H
#define RFE_TEST_MG_LOGS_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rfe/mass_grade.h"
#include "table.h"

/* The parameter keys a golden's metadata records and the field each sets. */
typedef struct {
    const char *key;
    rfe_real_t *field;
} key_field_t;

static inline int mg_read_params(const char *path, rfe_mass_grade_params_t *p, char *config, size_t len)
{
    key_field_t map[] = {
        {"R", &p->R},           {"g", &p->g},               {"mg_fc", &p->fc},
        {"mg_fr", &p->fr},      {"mg_rho", &p->rho},        {"mg_cd", &p->cd},
        {"mg_area", &p->area},  {"mg_m_rot", &p->m_rot},    {"mg_m0", &p->m0},
        {"mg_theta0", &p->theta0}, {"mg_sd_m0", &p->sd_m0}, {"mg_sd_theta0", &p->sd_theta0},
        {"mg_q_v", &p->q_v},    {"mg_q_mc", &p->q_mc},      {"mg_q_mv0", &p->q_mv0},
        {"mg_q_theta", &p->q_theta}, {"mg_r_v", &p->r_v},   {"mg_r_ax", &p->r_ax},
        {"mg_ut_alpha", &p->ut_alpha}, {"mg_ut_beta", &p->ut_beta},
        {"mg_ut_kappa", &p->ut_kappa}, {"mg_t_adapt", &p->t_adapt},
        {"mg_mv_stop", &p->mv_stop}, {"mg_v_min", &p->v_min}, {"mg_t_brake", &p->t_brake},
        {"mg_t_shift", &p->t_shift}, {"mg_p_brake_on", &p->p_brake_on},
        {"mg_slip_max", &p->slip_max}, {"mg_ay_max", &p->ay_max}, {"mg_t_curve", &p->t_curve},
        {"mg_pause_grade", &p->pause_grade}, {"mg_pause_grade_slip", &p->pause_grade_slip},
        {"mg_pause_grade_dv", &p->pause_grade_dv},
        {"mg_m_min", &p->m_min}, {"mg_m_max", &p->m_max}, {"mg_theta_max", &p->theta_max},
        {"mg_dt_max", &p->dt_max},
        {"mg_q_theta_hi", &p->q_theta_hi}, {"mg_theta_rate_on", &p->theta_rate_on},
        {"mg_theta_rate_off", &p->theta_rate_off}, {"mg_theta_rate_tau", &p->theta_rate_tau},
        {"mg_theta_rate_avg", &p->theta_rate_avg},
        {"mg_mm_tau", &p->mm_tau}, {"mg_mm_e", &p->mm_e},
    };
    const size_t n_map = sizeof(map) / sizeof(map[0]);
    size_t found = 0u;
    char line[256];
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        return -1;
    }
    memset(p, 0, sizeof(*p));
    while ((fgets(line, sizeof(line), f) != NULL) && (line[0] == '#')) {
        char key[64];
        char val[128];
        size_t i;
        if (sscanf(line, "# %63s = %127s", key, val) != 2) {
            continue;
        }
        if (strcmp(key, "config") == 0) {
            snprintf(config, len, "%s", val);
        } else if (strcmp(key, "mg_adaptive") == 0) {
            p->adaptive = (strtod(val, NULL) == 1.0) ? 1u : 0u;
            ++found;
        } else if (strcmp(key, "mg_use_ax") == 0) {
            p->use_ax = (strtod(val, NULL) == 1.0) ? 1u : 0u;
            ++found;
        } else {
            for (i = 0u; i < n_map; ++i) {
                if (strcmp(key, map[i].key) == 0) {
                    *map[i].field = (rfe_real_t)strtod(val, NULL);
                    ++found;
                }
            }
        }
    }
    fclose(f);
    return (found == n_map + 2u) ? 0 : -1;
}

/* Sample k of the log: the speed from the four wheels (MASS_GRADE.md §1, in double and in
 * the reference's order), the period from the time stamps in double, every optional input
 * the log has (the reference hands them all over; ax too when the row is off). */
static inline void mg_input_of(const test_table_t *log, size_t k, double R, rfe_mass_grade_input_t *in)
{
    const double v = ((((test_table_get(log, k, "omega_fl") + test_table_get(log, k, "omega_fr")) +
                        test_table_get(log, k, "omega_rl")) +
                       test_table_get(log, k, "omega_rr")) /
                      4.0) *
                     R;
    memset(in, 0, sizeof(*in));
    in->dt = (k > 0u) ? (rfe_real_t)(test_table_get(log, k, "t") - test_table_get(log, k - 1u, "t"))
                      : (rfe_real_t)0.0;
    in->v = (rfe_real_t)v;
    in->torque = (rfe_real_t)test_table_get(log, k, "drive_torque");
    in->ax = (rfe_real_t)test_table_get(log, k, "ax");
    in->p_brake = (rfe_real_t)test_table_get(log, k, "brake_pressure");
    in->gear = (int32_t)test_table_get(log, k, "gear");
    in->brake = (test_table_get(log, k, "brake") >= 0.5) ? 1u : 0u;
    in->has = RFE_MG_HAS_BRAKE | RFE_MG_HAS_PRESSURE | RFE_MG_HAS_GEAR | RFE_MG_HAS_AX;
}

#endif /* RFE_TEST_MG_LOGS_H */
