/**
 * @file mg_run_q31.c
 * @brief Runs the library's fixed-point mass and grade estimator (the square-root form,
 *        docs/FIXED_POINT.md "Mass and grade") over a log and prints mg_run_common.h's
 *        summary: P = S S^T is positive definite exactly when every diagonal entry of the
 *        lower factor S is > 0, checked each step; sat is the state's saturation count.
 */
#include <string.h>

#include "fixed_conv.h"
#include "mg_logs.h"
#include "mg_run_common.h"
#include "rfe/component/params_conv.h"
#include "rfe/mass_grade.h"
#include "rfe/mass_grade_q31.h"
#include "table.h"

int main(int argc, char **argv)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_params_q31_t q;
    rfe_mass_grade_q31_t mg;
    test_table_t log;
    char config[64] = "";
    mg_run_t r;
    size_t k;
    memset(&r, 0, sizeof(r));
    r.first21 = -1;
    r.first_npd = -1;
    if (argc != 3) {
        return mg_run_usage(argv[0]);
    }
    if ((mg_read_params(argv[1], &p, config, sizeof(config)) != 0) ||
        (test_table_load(argv[2], &log) != 0)) {
        fprintf(stderr, "%s: cannot read %s or %s\n", argv[0], argv[1], argv[2]);
        return 1;
    }
    if ((rfe_mass_grade_params_to_q31(&p, &q) != RFE_OK) ||
        (rfe_mass_grade_init_q31(&mg, &q) != RFE_OK)) {
        fprintf(stderr, "%s: parameters refused\n", argv[0]);
        return 1;
    }
    for (k = 0u; k < log.n_rows; ++k) {
        rfe_mass_grade_input_t in;
        rfe_mass_grade_input_q31_t inq;
        rfe_mass_grade_estimate_q31_t e;
        rfe_status_t st;
        uint32_t sat = 0u;
        mg_input_of(&log, k, p.R, &in);
        memset(&inq, 0, sizeof(inq));
        inq.dt = rfe_fix_from_double(in.dt, RFE_MG_Q_DT, &sat);
        inq.v = rfe_fix_from_double(in.v, RFE_MG_Q_V, &sat);
        inq.torque = rfe_fix_from_double(in.torque, RFE_MG_Q_TORQUE, &sat);
        inq.p_brake = rfe_fix_from_double(in.p_brake * 1e-6, RFE_MG_Q_PRESSURE, &sat);
        inq.ax = rfe_fix_from_double(in.ax, RFE_MG_Q_V, &sat);
        inq.gear = in.gear;
        inq.brake = in.brake;
        inq.has = in.has;
        st = rfe_mass_grade_step_q31(&mg, &inq, &e);
        mg_run_note(&r, k, (int)st,
                    (mg.started == 0u) || ((mg.S[0] > 0) && (mg.S[4] > 0) && (mg.S[8] > 0)),
                    rfe_fix_to_double(e.mass, RFE_MG_Q_M), rfe_fix_to_double(e.sd_mass, RFE_MG_Q_M));
        r.sat += sat;
    }
    r.sat += mg.sat;
    mg_run_print(&r);
    test_table_free(&log);
    return 0;
}
