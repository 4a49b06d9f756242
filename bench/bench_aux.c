/**
 * @file bench_aux.c
 * @brief Host cost per step of the mass and grade estimator and the tyre identifier
 *        (make bench, docs/BENCHMARKS.md "Other estimators"), in the build's precision (float,
 *        or double with -DRFE_REAL_DOUBLE):
 *
 *   bench_aux_{f32,f64} --case mg_ukf|mg_aukf|tid --log LOG.csv [--rows N] [--reps R]
 *
 * The samples are host/pil/aux_input.h's (those of the PIL images, make pil-aux) and the
 * parameters as pil_gen derives them: mass and grade from the car preset (recommended: UKF
 * + ax; seed: the AUKF on speed and torque) with the log's metadata; the tyre identifier's
 * vehicle from the default preset and the metadata, its own defaults, seed 1, RFE_TID_N
 * particles. The first N rows (0: all) are stepped R times, each pass from a fresh init
 * (not timed); prints "ns_per_step <mean over the passes> <fastest pass> <median pass> steps <N>". The step
 * calls run inside bench_aux_region, so valgrind --tool=callgrind
 * --toggle-collect=bench_aux_region counts only them.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "host/csv_log.h"
#include "host/param_file.h"
#include "host/pil/aux_input.h"
#include "host/replay_real.h"

static rfe_mass_grade_t g_mg;
static rfe_tyre_id_t g_tid;
static rfe_mass_grade_input_t *g_mg_in;
static rfe_tyre_id_sample_t *g_tid_in;
volatile rfe_real_t bench_aux_sink;

__attribute__((noinline)) int bench_aux_region(int tid, size_t n);
__attribute__((noinline)) int bench_aux_region(int tid, size_t n)
{
    size_t k;
    for (k = 0u; k < n; ++k) {
        if (tid) {
            rfe_tyre_id_estimate_t e;
            if (rfe_tyre_id_step(&g_tid, &g_tid_in[k], &e) != RFE_OK) {
                return -1;
            }
            bench_aux_sink = e.mean[0];
        } else {
            rfe_mass_grade_estimate_t e;
            if (rfe_status_is_error(rfe_mass_grade_step(&g_mg, &g_mg_in[k], &e))) {
                return -1;
            }
            bench_aux_sink = e.mass;
        }
    }
    return 0;
}

static double now_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return ((double)ts.tv_sec * 1e9) + (double)ts.tv_nsec;
}

static int cmp_double(const void *x, const void *y)
{
    const double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

int main(int argc, char **argv)
{
    const char *c = NULL, *path = NULL;
    size_t rows = 0u, i;
    int reps = 5, r, a, tid;
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    rfe_param_set_t ps;
    rfe_mass_grade_params_t mp;
    rfe_params_t vp;
    rfe_tyre_id_params_t tp;
    double sum = 0.0, best = 1e300, *pass;
    for (a = 1; a + 1 < argc; a += 2) {
        if (strcmp(argv[a], "--case") == 0) { c = argv[a + 1]; }
        else if (strcmp(argv[a], "--log") == 0) { path = argv[a + 1]; }
        else if (strcmp(argv[a], "--rows") == 0) { rows = (size_t)strtoul(argv[a + 1], NULL, 10); }
        else if (strcmp(argv[a], "--reps") == 0) { reps = atoi(argv[a + 1]); }
    }
    if (c == NULL || path == NULL || reps < 1 ||
        (strcmp(c, "mg_ukf") != 0 && strcmp(c, "mg_aukf") != 0 && strcmp(c, "tid") != 0)) {
        fprintf(stderr, "usage: %s --case mg_ukf|mg_aukf|tid --log LOG.csv [--rows N] [--reps R]\n", argv[0]);
        return 2;
    }
    tid = strcmp(c, "tid") == 0;
    memset(&log, 0, sizeof log);
    if (rfe_sensor_log_read(path, &log, &err) != 0) {
        fprintf(stderr, "%s: %s:%zu: %s\n", argv[0], path, err.line, err.msg);
        return 1;
    }
    if (rows == 0u || rows > log.n_rows) {
        rows = log.n_rows;
    }
    (void)rfe_param_set_preset(&ps, RFE_PRESET_DEFAULT);
    if (!tid) {
        (void)rfe_param_set_mass_grade(&ps, RFE_MG_CAR, strcmp(c, "mg_aukf") == 0 ? RFE_MG_SEED : RFE_MG_RECOMMENDED);
    }
    if (rfe_param_set_apply_meta(&ps, &log, path, &err) != 0 ||
        (tid ? (rfe_replay_params(&ps, &vp, NULL) != RFE_OK || rfe_tyre_id_params_default(&tp) != RFE_OK)
             : (!log.has_drive_torque || rfe_replay_mass_grade_params(&ps, &mp, NULL) != RFE_OK))) {
        fprintf(stderr, "%s: %s: the parameters are rejected\n", argv[0], path);
        return 1;
    }
    g_mg_in = calloc(rows, sizeof *g_mg_in);
    g_tid_in = calloc(rows, sizeof *g_tid_in);
    pass = calloc((size_t)reps, sizeof *pass);
    if (g_mg_in == NULL || g_tid_in == NULL || pass == NULL) {
        return 1;
    }
    for (i = 0u; i < rows; ++i) {
        rfe_aux_mg_input(&log, i, (double)mp.R, &g_mg_in[i]);
        rfe_aux_tid_sample(&log, i, &g_tid_in[i]);
    }
    for (r = 0; r < reps; ++r) {
        double t0, t;
        if (tid ? rfe_tyre_id_init(&g_tid, &tp, &vp, 1u) != RFE_OK : rfe_mass_grade_init(&g_mg, &mp) != RFE_OK) {
            return 1;
        }
        t0 = now_ns();
        if (bench_aux_region(tid, rows) != 0) {
            fprintf(stderr, "%s: a step failed\n", argv[0]);
            return 1;
        }
        t = (now_ns() - t0) / (double)rows;
        sum += t;
        best = t < best ? t : best;
        pass[r] = t;
    }
    qsort(pass, (size_t)reps, sizeof *pass, cmp_double);
    printf("ns_per_step %.1f %.1f %.1f steps %zu\n", sum / reps, best, pass[reps / 2], rows);
    free(pass);
    free(g_mg_in);
    free(g_tid_in);
    rfe_sensor_log_free(&log);
    return 0;
}
