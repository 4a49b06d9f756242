/**
 * @file fuzz_csv.c
 * @brief libFuzzer harness for the CLI's input readers on arbitrary bytes: the sensor-log
 *        reader (src/host/csv_log.c) with the metadata -> parameter path and a short float
 *        replay (what mu_replay does with a log), the parameter-file reader
 *        (src/host/param_file.c), and the strict number parser (text_io.c).
 *
 * Byte 0 selects the target (% 3): 0 sensor log, 1 parameter file, 2 number parser; the
 * rest is the file's content (read through fmemopen, as from disk).
 * Checked (abort on violation, so libFuzzer keeps the input):
 *  - sensor log: accepted -> at least one row, t strictly increasing, every needed field
 *    finite, metadata keys non-NULL; rejected -> a non-empty one-line message, 1-based
 *    line; the metadata applied to the default preset either succeeds or fails with a
 *    message; then the float replay of the first REPLAY_ROWS rows either refuses the
 *    parameters at init (RFE_ERR_PARAM, RFE_ERR_NONFINITE) or gives a status for every row,
 *    finite mu in [mu_min, mu_max] (to 1e-6 relative: the bounds are rounded to float) and
 *    finite sd > 0 (the estimator behind the CLI on whatever the reader lets through);
 *  - parameter file: accepted -> every numeric value finite; rejected -> a message;
 *  - number parser: RFE_NUM_OK only with a finite result.
 * ASan/UBSan and LeakSanitizer catch memory errors and leaks of the readers.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_real.h"
#include "text_io.h"

#define REPLAY_ROWS 64

static void violation(const char *what)
{
    fprintf(stderr, "fuzz_csv: %s\n", what);
    abort();
}

static void check_error(const rfe_io_error_t *err)
{
    if (err->msg[0] == '\0' || strchr(err->msg, '\n') != NULL) {
        violation("error message empty or not one line");
    }
}

static void sensor_log(const uint8_t *data, size_t size)
{
    FILE *f = fmemopen((void *)(uintptr_t)data, size, "r");
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    size_t i;
    int w;
    if (f == NULL) {
        return;
    }
    memset(&err, 0, sizeof err);
    if (rfe_sensor_log_read_stream(f, "fuzz.csv", &log, &err) != 0) {
        fclose(f);
        check_error(&err);
        if (log.n_rows != 0 || log.rows != NULL || log.meta != NULL) {
            violation("a rejected log was not left empty");
        }
        return;
    }
    fclose(f);
    if (log.n_rows == 0) {
        violation("accepted log without rows");
    }
    for (i = 0; i < log.n_rows; ++i) {
        const rfe_sensor_row_t *r = &log.rows[i];
        const double v[8] = {r->t, r->delta, r->vx, r->vy, r->yaw_rate, r->yaw_acc, r->ax, r->ay};
        for (w = 0; w < 8; ++w) {
            if (!isfinite(v[w])) {
                violation("accepted log with a non-finite field");
            }
        }
        for (w = 0; w < 4; ++w) {
            if (!isfinite(r->omega[w])) {
                violation("accepted log with a non-finite wheel speed");
            }
        }
        if (i > 0 && !(r->t > log.rows[i - 1].t)) {
            violation("accepted log with t not strictly increasing");
        }
    }
    for (i = 0; i < log.n_meta; ++i) {
        if (log.meta[i].key == NULL || log.meta[i].value == NULL) {
            violation("metadata entry without key or value");
        }
    }
    {
        rfe_param_set_t ps;
        rfe_io_error_t perr;
        if (rfe_param_set_preset_f32(&ps, RFE_PRESET_DEFAULT) != 0) {
            violation("preset");
        }
        memset(&perr, 0, sizeof perr);
        if (rfe_param_set_apply_meta(&ps, &log, "fuzz.csv", &perr) != 0) {
            check_error(&perr);
        } else {
            rfe_sensor_log_t head = log;
            rfe_est_row_t out[REPLAY_ROWS];
            rfe_replay_stats_t stats;
            size_t bad_key;
            rfe_status_t st;
            const double lo = ps.value[RFE_PK_mu_min], hi = ps.value[RFE_PK_mu_max];
            head.n_rows = log.n_rows < REPLAY_ROWS ? log.n_rows : REPLAY_ROWS;
            st = rfe_replay_run_f32(&ps, &head, out, &stats, &bad_key);
            if (st == RFE_OK) {
                for (i = 0; i < head.n_rows; ++i) {
                    for (w = 0; w < 4; ++w) {
                        if (!isfinite(out[i].mu[w]) || !isfinite(out[i].sd[w]) ||
                            !(out[i].sd[w] > 0.0) ||
                            out[i].mu[w] < lo - 1e-6 * fmax(1.0, fabs(lo)) ||
                            out[i].mu[w] > hi + 1e-6 * fmax(1.0, fabs(hi))) {
                            fprintf(stderr, "fuzz_csv: row %zu wheel %d: mu %.17g sd %.17g, "
                                            "bounds [%.17g, %.17g]\n", i, w, out[i].mu[w],
                                    out[i].sd[w], lo, hi);
                            violation("replay output not finite or mu out of bounds");
                        }
                    }
                }
                if (stats.n_steps != head.n_rows) {
                    violation("replay step count");
                }
            } else if (st != RFE_ERR_PARAM && st != RFE_ERR_NONFINITE &&
                       st != RFE_ERR_NOT_POSITIVE_DEFINITE) {
                /* friction.h: init fails with RFE_ERR_PARAM, RFE_ERR_NONFINITE when a prior
                 * with a common-mode part overflows, or RFE_ERR_NOT_POSITIVE_DEFINITE when it
                 * is singular in the working precision (sd0_common >> sd0) */
                violation("replay failed with a status other than PARAM / NONFINITE");
            }
        }
    }
    rfe_sensor_log_free(&log);
}

static void param_file(const uint8_t *data, size_t size)
{
    FILE *f = fmemopen((void *)(uintptr_t)data, size, "r");
    rfe_param_set_t ps;
    rfe_io_error_t err;
    size_t k;
    if (f == NULL) {
        return;
    }
    if (rfe_param_set_preset_f32(&ps, RFE_PRESET_PAPER) != 0) {
        violation("preset");
    }
    memset(&err, 0, sizeof err);
    if (rfe_param_set_apply_stream(&ps, f, "fuzz.par", &err) != 0) {
        check_error(&err);
    } else {
        for (k = 0; k < RFE_PK_NUMERIC; ++k) {
            if (!isfinite(ps.value[k])) {
                violation("accepted parameter file with a non-finite value");
            }
        }
    }
    fclose(f);
}

static void number(const uint8_t *data, size_t size)
{
    char buf[256];
    double x = 0.0;
    const size_t n = size < sizeof buf - 1 ? size : sizeof buf - 1;
    memcpy(buf, data, n);
    buf[n] = '\0';
    if (rfe_text_parse_double(buf, &x) == RFE_NUM_OK && !isfinite(x)) {
        violation("number parser accepted a non-finite value");
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2) { /* fmemopen needs a non-empty buffer */
        return 0;
    }
    switch (data[0] % 3) {
    case 0:
        sensor_log(data + 1, size - 1);
        break;
    case 1:
        param_file(data + 1, size - 1);
        break;
    default:
        number(data + 1, size - 1);
        break;
    }
    return 0;
}
