/**
 * @file log_timing.c
 * @brief Sample periods of a sensor log (log_timing.h).
 */
#include "log_timing.h"

#include <math.h>
#include <stdlib.h>

#include "rfe/common.h"
#include "text_io.h"

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x > y) - (x < y);
}

int rfe_log_period(const rfe_sensor_log_t *log, rfe_log_period_t *out)
{
    double *d;
    size_t n;
    size_t i;
    if (log->n_rows < 2u) {
        return -1;
    }
    n = log->n_rows - 1u;
    d = rfe_xrealloc(NULL, n, sizeof *d);
    for (i = 0u; i < n; ++i) {
        d[i] = log->rows[i + 1u].t - log->rows[i].t;
    }
    qsort(d, n, sizeof *d, cmp_double);
    /* The lower median for an even count: one of the periods itself, never an average. */
    out->median = d[(n - 1u) / 2u];
    out->min = d[0];
    out->max = d[n - 1u];
    out->n = n;
    free(d);
    return 0;
}

size_t rfe_log_gaps(const rfe_sensor_log_t *log, double limit)
{
    size_t gaps = 0u;
    size_t i;
    for (i = 1u; i < log->n_rows; ++i) {
        gaps += ((log->rows[i].t - log->rows[i - 1u].t) > limit) ? 1u : 0u;
    }
    return gaps;
}

double rfe_log_gap_limit(double dt)
{
    return (double)RFE_GAP_PERIODS * dt * (1.0 + ldexp(1.0, -RFE_GAP_STAMP_SHIFT));
}

uint32_t rfe_log_missed(double period, double dt)
{
    double k;
    if (!(dt > 0.0) || !(period > rfe_log_gap_limit(dt))) {
        return 0u;
    }
    k = floor((period / dt) + 0.5) - 1.0; /* >= 1: period > 2 dt */
    return (k >= (double)UINT32_MAX) ? UINT32_MAX : (uint32_t)k;
}
