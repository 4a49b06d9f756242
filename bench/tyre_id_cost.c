/**
 * @file tyre_id_cost.c
 * @brief Host cost per step of the tyre identifier (docs/TYRE_ID_RESULTS.md "Cost of the C
 *        library"): every sample of one tyre-identification log through rfe_tyre_id_step, the
 *        wall time per step (the fastest of `reps` passes), at the particle count the
 *        program was compiled with. The particle count is a compile-time constant, so each
 *        count is its own build of the identifier's sources:
 *
 *   for n in 64 256 1024; do
 *     gcc -std=c99 -O2 -D_POSIX_C_SOURCE=200809L -DRFE_TID_N=$n -Iinclude -Isrc -Isrc/host \
 *       bench/tyre_id_cost.c \
 *       src/numerics/philox_flt.c src/params/tyre_id_params_flt.c src/estimators/tyre_id/*.c \
 *       build/f32/hostlib.a build/f32/librfe.a -lm -o build/tid_cost_$n
 *     build/tid_cost_$n scenarios/tyre_id/tid_ramp_steer_high_mu.csv 5
 *   done
 *
 * A third argument names the filter (apf, the default, sir or sckf): the sigma-point filter
 * of TYRE_ID.md §15 needs no particles, so its own build is -DRFE_TID_N=2 (the smallest state),
 *   build/tid_cost_2 scenarios/tyre_id/tid_ramp_steer_high_mu.csv 5 sckf
 *
 * and the instructions per step with
 *   valgrind --tool=callgrind --toggle-collect='rfe_tyre_id_step_f32' build/tid_cost_$n <log> 1
 * (the total Ir over the log's samples). Not part of `make bench` (it would need one library
 * per particle count); the figures on the results page were measured once this way.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "csv_log.h"
#include "rfe/tyre_id.h"

static rfe_tyre_id_t tid;

static double now_s(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int main(int argc, char **argv)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    rfe_params_t veh;
    rfe_tyre_id_params_t tp;
    double best = 1e30;
    int reps = (argc > 2) ? atoi(argv[2]) : 3;
    int r;
    memset(&log, 0, sizeof(log));
    if ((argc < 2) || (rfe_sensor_log_read(argv[1], &log, &err) != 0)) {
        fprintf(stderr, "usage: %s <tyre-id log> [reps]\n", argv[0]);
        return 2;
    }
    if ((rfe_params_default(&veh) != RFE_OK) || (rfe_tyre_id_params_default(&tp) != RFE_OK)) {
        return 1;
    }
    if (argc > 3) {
        tp.filter = (strcmp(argv[3], "sckf") == 0)  ? RFE_TID_SCKF
                    : (strcmp(argv[3], "sir") == 0) ? RFE_TID_SIR
                                                    : RFE_TID_APF;
    }
    for (r = 0; r < reps; ++r) {
        double t0;
        double t1;
        size_t k;
        if (rfe_tyre_id_init(&tid, &tp, &veh, 1u) != RFE_OK) {
            return 1;
        }
        t0 = now_s();
        for (k = 0u; k < log.n_rows; ++k) {
            const rfe_sensor_row_t *row = &log.rows[k];
            rfe_tyre_id_sample_t s;
            rfe_tyre_id_estimate_t e;
            s.dt = (k > 0u) ? (rfe_real_t)(row->t - log.rows[k - 1u].t) : (rfe_real_t)0;
            s.delta = (rfe_real_t)row->delta;
            s.vx = (rfe_real_t)row->vx;
            s.yaw_rate = (rfe_real_t)row->yaw_rate;
            s.ay = (rfe_real_t)row->ay;
            s.ax = (rfe_real_t)row->ax;
            if (rfe_tyre_id_step(&tid, &s, &e) != RFE_OK) {
                return 1;
            }
        }
        t1 = now_s();
        if ((t1 - t0) < best) {
            best = t1 - t0;
        }
    }
    printf("filter %d, N = %d, %zu steps, %.1f us per step (fastest of %d), state %zu bytes\n",
           (int)tp.filter, RFE_TID_N, log.n_rows, 1e6 * best / (double)log.n_rows, reps,
           sizeof(rfe_tyre_id_t));
    rfe_sensor_log_free(&log);
    return 0;
}
