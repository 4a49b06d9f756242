/**
 * @file log_timing.h
 * @brief The sample period of a sensor log from its time stamps, host only. A recorded car's
 *        log runs at 50 Hz or 100 Hz with jittering stamps; the friction estimator's input
 *        filter needs the nominal period (key dt), the observer steps with each real one.
 */
#ifndef RFE_HOST_LOG_TIMING_H
#define RFE_HOST_LOG_TIMING_H

#include <stddef.h>
#include <stdint.h>

#include "csv_log.h"

/** The periods t[i] - t[i-1] of a log. */
typedef struct {
    double median; /**< the nominal period [s]: robust to jitter and to a few gaps */
    double min;    /**< shortest [s] */
    double max;    /**< longest [s] */
    size_t n;      /**< number of periods (rows - 1) */
} rfe_log_period_t;

/**
 * The periods of @p log (time strictly increasing, as the reader guarantees).
 * @return 0, or -1 when the log has fewer than two rows (@p out then untouched).
 */
int rfe_log_period(const rfe_sensor_log_t *log, rfe_log_period_t *out);

/** Number of periods longer than @p limit [s] (gaps in the recording). */
size_t rfe_log_gaps(const rfe_sensor_log_t *log, double limit);

/**
 * The longest period at the nominal @p dt [s] that is not a gap (rfe/common.h
 * RFE_GAP_PERIODS, RFE_GAP_STAMP_SHIFT, the library's rule): 2 dt, widened by the time
 * stamps' own rounding (2^-20 relative: a log's decimal stamps differ from exact multiples
 * of dt by ~1e-15 s; real jitter is 1e3 times larger), so one dropped sample (a period of
 * 2 dt) is jitter, not a gap.
 */
double rfe_log_gap_limit(double dt);

/**
 * The sample periods missing in a period of @p period [s] at the nominal @p dt [s]: 0 up to
 * rfe_log_gap_limit (jitter), else round(period / dt) - 1, at most UINT32_MAX (what
 * rfe_friction_skip is given before the sample that ends the gap). 0 when dt <= 0.
 */
uint32_t rfe_log_missed(double period, double dt);

#endif /* RFE_HOST_LOG_TIMING_H */
