/**
 * @file mg_run_common.h
 * @brief Shared by the mass and grade run drivers (mg_run_flt.c, mg_run_q31.c; used by
 *        scripts/tools/mass_grade_textbook.py, docs/MASS_GRADE_RESULTS.md "Why the square-root
 *        form"): the command line and the one-line summary of a run.
 */
#ifndef RFE_TEST_MG_RUN_COMMON_H
#define RFE_TEST_MG_RUN_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* What a run counts: steps, status 21 (RFE_ERR_NOT_POSITIVE_DEFINITE) and the first one,
 * the steps after the start whose stored covariance is not positive definite and the first,
 * the steps with a non-finite estimate; the estimate at the end. */
typedef struct {
    size_t steps, n21, npd, nonfinite;
    long first21, first_npd;
    double mass, sd_mass;
    unsigned long sat;
} mg_run_t;

static void mg_run_note(mg_run_t *r, size_t k, int status, int pd, double mass, double sd)
{
    ++r->steps;
    if (status == 21) {
        if (r->n21++ == 0u) {
            r->first21 = (long)k;
        }
    }
    if (!pd) {
        if (r->npd++ == 0u) {
            r->first_npd = (long)k;
        }
    }
    if (!isfinite(mass) || !isfinite(sd)) {
        ++r->nonfinite;
    }
    r->mass = mass;
    r->sd_mass = sd;
}

static void mg_run_print(const mg_run_t *r)
{
    printf("steps=%zu n21=%zu first21=%ld npd=%zu first_npd=%ld nonfinite=%zu mass=%.17g "
           "sd_mass=%.17g sat=%lu\n",
           r->steps, r->n21, r->first21, r->npd, r->first_npd, r->nonfinite, r->mass, r->sd_mass,
           r->sat);
}

static int mg_run_usage(const char *argv0)
{
    fprintf(stderr, "usage: %s PARAMS LOG\n  PARAMS: '# key = value' lines of every mg_* key, R "
                    "and g (a golden's metadata); LOG: a mass and grade log\n", argv0);
    return 2;
}

#endif /* RFE_TEST_MG_RUN_COMMON_H */
