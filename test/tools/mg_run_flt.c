/**
 * @file mg_run_flt.c
 * @brief Runs the library's mass and grade estimator (float build: the square-root form of
 *        MASS_GRADE.md §3-4, the state carrying the lower factor S of P) over a log and prints
 *        mg_run_common.h's summary; each step's P = S S^T is formed in double (each product
 *        of two float entries exact, the sums rounded to 1e-16) and checked for positive
 *        definiteness by a Cholesky in double.
 */
#include <string.h>

#include "mg_logs.h"
#include "mg_run_common.h"
#include "rfe/mass_grade.h"
#include "table.h"

static int pd3(const rfe_real_t *Sr)
{
    double a[9];
    double L[9] = {0};
    int i;
    int j;
    int k;
    for (i = 0; i < 9; ++i) {
        if (!isfinite((double)Sr[i])) {
            return 0;
        }
    }
    for (i = 0; i < 3; ++i) {
        for (j = 0; j < 3; ++j) {
            double s = 0.0;
            for (k = 0; k < 3; ++k) {
                s += (double)Sr[(i * 3) + k] * (double)Sr[(j * 3) + k]; /* P = S S^T */
            }
            a[(i * 3) + j] = s;
        }
    }
    for (j = 0; j < 3; ++j) {
        double d = a[(j * 3) + j];
        for (k = 0; k < j; ++k) {
            d -= L[(j * 3) + k] * L[(j * 3) + k];
        }
        if (!(d > 0.0)) {
            return 0;
        }
        L[(j * 3) + j] = sqrt(d);
        for (i = j + 1; i < 3; ++i) {
            double s = a[(i * 3) + j];
            for (k = 0; k < j; ++k) {
                s -= L[(i * 3) + k] * L[(j * 3) + k];
            }
            L[(i * 3) + j] = s / L[(j * 3) + j];
        }
    }
    return 1;
}

int main(int argc, char **argv)
{
    rfe_mass_grade_params_t p;
    rfe_mass_grade_t mg;
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
    if (rfe_mass_grade_init(&mg, &p) != RFE_OK) {
        fprintf(stderr, "%s: parameters refused\n", argv[0]);
        return 1;
    }
    for (k = 0u; k < log.n_rows; ++k) {
        rfe_mass_grade_input_t in;
        rfe_mass_grade_estimate_t e;
        rfe_status_t st;
        mg_input_of(&log, k, (double)p.R, &in);
        st = rfe_mass_grade_step(&mg, &in, &e);
        mg_run_note(&r, k, (int)st, (mg.started == 0u) || pd3(mg.S), (double)e.mass,
                    (double)e.sd_mass);
    }
    mg_run_print(&r);
    test_table_free(&log);
    return 0;
}
