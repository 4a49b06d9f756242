/**
 * @file soak.c
 * @brief The soak run: a long simulated drive (scripts/data/soak_drive.py) through every variant
 *        of the estimator (float, double and, built with -DSOAK_Q31, the fixed-point one) in
 *        the paper preset (SCKF, CKF) and the default preset, then through the composed
 *        pipeline (velocity observer + friction estimator, float, double and with -DSOAK_Q31
 *        fixed point), the
 *        invariants checked at every step; prints a summary (for q31 also the saturation
 *        counts, for the pipeline the observer's vx, vy against the log) and writes it as
 *        JSON.
 *
 *     build/soak/soak --in DRIVE.csv [--json SUMMARY.json] [--tid-from S] [--tid-to S]
 *
 * Then the mass and grade estimator (float, double; the recommended and the seed's
 * configuration) over the whole drive and the tyre identifier (float, double; APF) over the
 * rows with S_from <= t < S_to (default: all), each with its invariants at every step
 * (test/soak/soak_run_aux.c).
 *
 * Exit status 0 when no step of any run broke an invariant and no row inside the input
 * limits was refused; 1 otherwise (the first violation of each run is printed); 2 on a
 * usage or input error.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "soak.h"

typedef int (*soak_fn_t)(const rfe_sensor_log_t *, const char *, const soak_cfg_t *,
                         soak_result_t *);

static const struct {
    const char *name;
    soak_fn_t run;
} VARIANTS[] = {
    {"float", soak_run_f32},
    {"double", soak_run_f64},
#if defined(SOAK_Q31)
    {"q31", soak_run_q31},
#endif
};

static const soak_cfg_t CFGS[] = {
    {"paper.sckf", 0, 0},
    {"paper.ckf", 0, 1},
    {"default.sckf", 1, 0},
};

/* The composed pipeline: the observer needs no measured vx, vy, yaw_acc (a production car). */
static const struct {
    const char *name;
    soak_fn_t run;
} PIPELINES[] = {
    {"float", soak_run_pipeline_f32},
    {"double", soak_run_pipeline_f64},
#if defined(SOAK_Q31)
    {"q31", soak_run_pipeline_q31},
#endif
};
static const soak_cfg_t PIPELINE_CFG = {"pipeline", 1, 0};

/* The mass and grade estimator and the tyre identifier (soak_run_aux.c). */
typedef int (*soak_aux_fn_t)(const rfe_sensor_log_t *, const char *, const soak_aux_cfg_t *,
                             soak_aux_result_t *);
static const struct {
    const char *variant;
    const char *what;
    soak_aux_fn_t run;
    int seed_config;
    const char *cfg;
} AUX[] = {
    {"float", "mass_grade", soak_run_mass_grade_f32, 0, "car.recommended"},
    {"double", "mass_grade", soak_run_mass_grade_f64, 0, "car.recommended"},
    {"float", "mass_grade", soak_run_mass_grade_f32, 1, "car.seed"},
    {"double", "mass_grade", soak_run_mass_grade_f64, 1, "car.seed"},
#if defined(SOAK_Q31)
    {"q31", "mass_grade", soak_run_mass_grade_q31, 0, "car.recommended"},
    {"q31", "mass_grade", soak_run_mass_grade_q31, 1, "car.seed"},
#endif
    {"float", "tyre_id", soak_run_tyre_id_f32, 0, "apf"},
    {"double", "tyre_id", soak_run_tyre_id_f64, 0, "apf"},
};
#define N_AUX (sizeof AUX / sizeof AUX[0])

#define N_VARIANTS (sizeof VARIANTS / sizeof VARIANTS[0])
#define N_PIPELINES (sizeof PIPELINES / sizeof PIPELINES[0])
#define N_CFGS (sizeof CFGS / sizeof CFGS[0])

int main(int argc, char **argv)
{
    const char *in = NULL, *json = NULL;
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    soak_result_t res[N_VARIANTS][N_CFGS];
    soak_result_t res_pl[N_PIPELINES];
    soak_aux_result_t res_aux[N_AUX];
    double tid_from = -INFINITY, tid_to = INFINITY;
    size_t v, c;
    int i, failed = 0;
    FILE *jf = NULL;
    for (i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--in") == 0 && i + 1 < argc) {
            in = argv[++i];
        } else if (strcmp(argv[i], "--json") == 0 && i + 1 < argc) {
            json = argv[++i];
        } else if (strcmp(argv[i], "--tid-from") == 0 && i + 1 < argc) {
            tid_from = atof(argv[++i]);
        } else if (strcmp(argv[i], "--tid-to") == 0 && i + 1 < argc) {
            tid_to = atof(argv[++i]);
        } else {
            fprintf(stderr, "usage: soak --in DRIVE.csv [--json SUMMARY.json] [--tid-from S] "
                            "[--tid-to S]\n");
            return 2;
        }
    }
    if (in == NULL) {
        fprintf(stderr, "usage: soak --in DRIVE.csv [--json SUMMARY.json]\n");
        return 2;
    }
    memset(&log, 0, sizeof(log));
    if (rfe_sensor_log_read(in, &log, &err) != 0) {
        rfe_io_error_print(stderr, "soak", &err);
        return 2;
    }
    printf("soak: %s: %zu steps (%.1f simulated minutes), invariants at every step\n", in,
           log.n_rows, (double)log.n_rows * 0.01 / 60.0);
    printf("%-7s %-13s %8s %6s %7s %7s %8s %6s %6s %12s %13s %6s %8s %6s %6s %6s %9s\n",
           "variant", "config", "steps", "ok%", "proj", "at_bnd", "low_spd%", "held%", "err",
           "mu min..max", "sd min..max", "sd>cap", "valid%", "rmse_v", "cons_v", "us/st",
           "sat_steps");
    for (v = 0; v < N_VARIANTS; ++v) {
        for (c = 0; c < N_CFGS; ++c) {
            soak_result_t *r = &res[v][c];
            double n;
            if (VARIANTS[v].run(&log, in, &CFGS[c], r) != 0) {
                rfe_sensor_log_free(&log);
                return 2;
            }
            n = (double)(r->steps ? r->steps : 1);
            printf("%-7s %-13s %8ld %5.1f%% %7ld %7ld %7.1f%% %5.1f%% %6ld %5.3f..%5.3f "
                   "%6.4f..%5.3f %6ld %7.1f%% %6.3f %5.1f%% %6.1f %9ld\n",
                   VARIANTS[v].name, CFGS[c].name, r->steps,
                   100.0 * (double)(r->status[0] + r->status[1]) / n, r->projected, r->at_bound,
                   100.0 * (double)r->status[2] / n, 100.0 * (double)r->status[3] / n,
                   r->steps - r->status[0] - r->status[1] - r->status[2] - r->status[3],
                   r->mu_lo, r->mu_hi, r->sd_lo, r->sd_hi, r->sd_over_cap,
                   100.0 * (double)r->n_valid / (4.0 * n), r->rmse_valid,
                   100.0 * r->consistent_valid, r->us_per_step, r->sat_steps);
            if (r->violations > 0) {
                printf("  FAILED: %ld step(s) broke an invariant; first at step %ld, %s\n",
                       r->violations, r->first_violation_step, r->first_violation);
                failed = 1;
            }
        }
    }
    printf("%-7s %-13s %8s %6s %6s %12s %13s %8s %6s %6s %8s %7s %6s %7s %8s %7s %7s %6s\n",
           "variant", "config", "steps", "ok%", "err", "mu min..max", "sd min..max", "valid%",
           "rmse_v", "cons_v", "vx_rmse", "vx_max", "vx>1", "vx_2sd", "vy_rmse", "vy_max",
           "vy_2sd", "us/st");
    for (v = 0; v < N_PIPELINES; ++v) {
        soak_result_t *r = &res_pl[v];
        double n;
        if (PIPELINES[v].run(&log, in, &PIPELINE_CFG, r) != 0) {
            rfe_sensor_log_free(&log);
            return 2;
        }
        n = (double)(r->steps ? r->steps : 1);
        printf("%-7s %-13s %8ld %5.1f%% %6ld %5.3f..%5.3f %6.4f..%5.3f %7.1f%% %6.3f %5.1f%% "
               "%8.3f %7.3f %5.1f%% %6.1f%% %8.3f %7.3f %6.1f%% %6.1f\n",
               PIPELINES[v].name, PIPELINE_CFG.name, r->steps,
               100.0 * (double)(r->status[0] + r->status[1]) / n, r->failed_valid, r->mu_lo,
               r->mu_hi, r->sd_lo, r->sd_hi, 100.0 * (double)r->n_valid / (4.0 * n),
               r->rmse_valid, 100.0 * r->consistent_valid, r->obs_rmse_vx, r->obs_max_err_vx,
               100.0 * r->obs_far_vx, 100.0 * r->obs_cons_vx, r->obs_rmse_vy, r->obs_max_err_vy, 100.0 * r->obs_cons_vy,
               r->us_per_step);
        if (r->violations > 0) {
            printf("  FAILED: %ld step(s) broke an invariant; first at step %ld, %s\n",
                   r->violations, r->first_violation_step, r->first_violation);
            failed = 1;
        }
    }
    printf("%-7s %-10s %-15s %8s %6s %6s %6s %6s %8s %8s %17s %17s %17s %7s\n", "variant",
           "estimator", "config", "steps", "ok%", "held%", "upd%", "resmp%", "lost", "err",
           "mass|mu_f min..max", "grade|neff min..max", "final mass|K_f (sd)", "us/st");
    for (v = 0; v < N_AUX; ++v) {
        soak_aux_result_t *r = &res_aux[v];
        soak_aux_cfg_t cfg;
        double n;
        long errors = 0;
        int s;
        cfg.name = AUX[v].cfg;
        cfg.seed_config = AUX[v].seed_config;
        cfg.from = tid_from;
        cfg.to = tid_to;
        if (AUX[v].run(&log, in, &cfg, r) != 0) {
            rfe_sensor_log_free(&log);
            return 2;
        }
        for (s = 16; s < SOAK_STATUS_SLOTS; ++s) {
            errors += r->status[s];
        }
        n = (double)(r->steps ? r->steps : 1);
        printf("%-7s %-10s %-15s %8ld %5.1f%% %5.1f%% %5.1f%% %5.1f%% %8ld %8ld %8.4g..%-8.4g "
               "%8.4g..%-8.4g %9.5g (%.3g) %7.1f\n",
               AUX[v].variant, AUX[v].what, AUX[v].cfg, r->steps,
               100.0 * (double)r->status[0] / n,
               100.0 * (strcmp(AUX[v].what, "tyre_id") == 0
                            ? (double)r->held
                            : (double)(r->status[2] + r->status[5] + r->status[6])) / n,
               100.0 * (double)r->updated / n, 100.0 * (double)r->resampled / n, r->lost, errors,
               r->lo, r->hi, r->lo2, r->hi2, r->final, r->final_sd, r->us_per_step);
        if (r->violations > 0) {
            printf("  FAILED: %ld step(s) broke an invariant; first at step %ld, %s\n",
                   r->violations, r->first_violation_step, r->first_violation);
            failed = 1;
        }
    }
    if (json != NULL && (jf = fopen(json, "w")) != NULL) {
        fprintf(jf, "{\n \"input\": \"%s\",\n \"steps\": %zu,\n \"runs\": [\n", in, log.n_rows);
        for (v = 0; v < N_VARIANTS; ++v) {
            for (c = 0; c < N_CFGS; ++c) {
                const soak_result_t *r = &res[v][c];
                int s;
                fprintf(jf, "  {\"variant\": \"%s\", \"config\": \"%s\", \"steps\": %ld, "
                            "\"statuses\": {",
                        VARIANTS[v].name, CFGS[c].name, r->steps);
                for (s = 0, i = 0; s < SOAK_STATUS_SLOTS; ++s) {
                    if (r->status[s] != 0) {
                        fprintf(jf, "%s\"%d\": %ld", i++ ? ", " : "", s, r->status[s]);
                    }
                }
                fprintf(jf, "}, \"projected\": %ld, \"at_bound\": %ld, \"sd_over_cap\": %ld, "
                            "\"rejected\": %ld, \"failed_valid\": %ld, \"violations\": %ld, "
                            "\"mu_min\": %.9g, \"mu_max\": %.9g, \"sd_min\": %.9g, "
                            "\"sd_max\": %.9g, \"valid_share\": %.6f, \"rmse_valid\": %.6f, "
                            "\"max_err_valid\": %.6f, \"consistent_valid\": %.6f, "
                            "\"us_per_step\": %.3f, \"input_sat_rows\": %ld, "
                            "\"sat_steps\": %ld, \"sat_total\": %llu, \"sat_max\": %lu}%s\n",
                        r->projected, r->at_bound, r->sd_over_cap, r->rejected, r->failed_valid,
                        r->violations, r->mu_lo, r->mu_hi, r->sd_lo, r->sd_hi,
                        (double)r->n_valid / (4.0 * (double)(r->steps ? r->steps : 1)),
                        r->rmse_valid, r->max_err_valid, r->consistent_valid, r->us_per_step,
                        r->input_sat_rows, r->sat_steps, r->sat_total, r->sat_max,
                        (v + 1 == N_VARIANTS && c + 1 == N_CFGS) ? "" : ",");
            }
        }
        fprintf(jf, " ],\n \"pipeline_runs\": [\n");
        for (v = 0; v < N_PIPELINES; ++v) {
            const soak_result_t *r = &res_pl[v];
            fprintf(jf, "  {\"variant\": \"%s\", \"config\": \"%s\", \"steps\": %ld, "
                        "\"failed\": %ld, \"violations\": %ld, \"projected\": %ld, "
                        "\"mu_min\": %.9g, \"mu_max\": %.9g, \"sd_min\": %.9g, \"sd_max\": %.9g, "
                        "\"valid_share\": %.6f, \"rmse_valid\": %.6f, \"consistent_valid\": %.6f, "
                        "\"observer_steps\": %ld, \"vx_rmse\": %.6f, \"vx_max_err\": %.6f, "
                        "\"vx_within_2sd\": %.6f, \"vx_far_1ms\": %.6f, \"vy_rmse\": %.6f, \"vy_max_err\": %.6f, \"vy_within_2sd\": %.6f, "
                        "\"us_per_step\": %.3f, \"input_sat_rows\": %ld, \"sat_steps\": %ld, "
                        "\"sat_total\": %llu, \"sat_max\": %lu}%s\n",
                    PIPELINES[v].name, PIPELINE_CFG.name, r->steps, r->failed_valid,
                    r->violations, r->projected, r->mu_lo, r->mu_hi, r->sd_lo, r->sd_hi,
                    (double)r->n_valid / (4.0 * (double)(r->steps ? r->steps : 1)),
                    r->rmse_valid, r->consistent_valid, r->obs_steps, r->obs_rmse_vx,
                    r->obs_max_err_vx, r->obs_cons_vx, r->obs_far_vx, r->obs_rmse_vy, r->obs_max_err_vy, r->obs_cons_vy,
                    r->us_per_step, r->input_sat_rows, r->sat_steps, r->sat_total, r->sat_max,
                    v + 1 == N_PIPELINES ? "" : ",");
        }
        fprintf(jf, " ],\n \"aux_runs\": [\n");
        for (v = 0; v < N_AUX; ++v) {
            const soak_aux_result_t *r = &res_aux[v];
            int s;
            fprintf(jf, "  {\"variant\": \"%s\", \"estimator\": \"%s\", \"config\": \"%s\", "
                        "\"steps\": %ld, \"statuses\": {",
                    AUX[v].variant, AUX[v].what, AUX[v].cfg, r->steps);
            for (s = 0, i = 0; s < SOAK_STATUS_SLOTS; ++s) {
                if (r->status[s] != 0) {
                    fprintf(jf, "%s\"%d\": %ld", i++ ? ", " : "", s, r->status[s]);
                }
            }
            fprintf(jf, "}, \"updated\": %ld, \"held\": %ld, \"resampled\": %ld, \"lost\": %ld, "
                        "\"violations\": %ld, \"lo\": %.9g, \"hi\": %.9g, \"lo2\": %.9g, "
                        "\"hi2\": %.9g, \"final\": %.9g, \"final_sd\": %.9g, \"truth\": %.9g, "
                        "\"us_per_step\": %.3f}%s\n",
                    r->updated, r->held, r->resampled, r->lost, r->violations, r->lo, r->hi,
                    r->lo2, r->hi2, r->final, r->final_sd, r->truth, r->us_per_step,
                    v + 1 == N_AUX ? "" : ",");
        }
        fprintf(jf, " ]\n}\n");
        fclose(jf);
    }
    rfe_sensor_log_free(&log);
    printf("soak: %s\n", failed ? "FAILED (an invariant broke, see above)"
                                : "every invariant held at every step of every run");
    return failed;
}
