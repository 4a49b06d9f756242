/**
 * @file replay_real.h
 * @brief Runs the estimator over a whole sensor log, in float or double.
 *
 * replay_real.c is compiled twice (float, and -DRFE_REAL_DOUBLE); its public names carry
 * the precision suffix through RFE_FN(), so both are declared here explicitly and one
 * program can call either. Everything here is doubles in, doubles out.
 */
#ifndef RFE_HOST_REPLAY_REAL_H
#define RFE_HOST_REPLAY_REAL_H

#include <stddef.h>

#include "csv_log.h"
#include "param_file.h"
#include "rfe/types.h"

/** Status codes counted individually (0 .. RFE_REPLAY_STATUS_SLOTS-2); the last slot is
 *  "any other value". */
#define RFE_REPLAY_STATUS_SLOTS 32

/** Per-run counters. */
typedef struct {
    size_t n_steps;
    size_t status_count[RFE_REPLAY_STATUS_SLOTS];  /**< index = rfe_status_t value */
} rfe_replay_stats_t;

/** Slot of @p status in rfe_replay_stats_t.status_count (inline: this header is shared by
 *  both precisions, so no out-of-line precision-independent code lives in replay_real.c). */
static inline size_t rfe_replay_status_slot(int status)
{
    return ((status >= 0) && (status < RFE_REPLAY_STATUS_SLOTS - 1)) ? (size_t)status
                                                                    : (size_t)(RFE_REPLAY_STATUS_SLOTS - 1);
}

/**
 * Converts the parameter set, initialises the estimator and steps it on every row of
 * @p log, writing one estimate row per input row into @p out (log->n_rows entries). A row
 * the library rejects gets the unchanged previous estimate, valid = 0 and its error status,
 * and the run goes on.
 * @param bad_key on RFE_ERR_PARAM: the first key that alone makes the library's
 *        rfe_params_validate fail (starting from the library defaults), or RFE_PK_NONE
 *        when only a combination does (e.g. mu_min >= mu_max); may be NULL.
 * @return RFE_OK, or the rfe_estimator_init error (nothing written then).
 */
RFE_NODISCARD rfe_status_t rfe_replay_run_f32(const rfe_param_set_t *ps,
                                              const rfe_sensor_log_t *log, rfe_est_row_t *out,
                                              rfe_replay_stats_t *stats, size_t *bad_key);
/** Double-precision twin of rfe_replay_run_f32. */
RFE_NODISCARD rfe_status_t rfe_replay_run_f64(const rfe_param_set_t *ps,
                                              const rfe_sensor_log_t *log, rfe_est_row_t *out,
                                              rfe_replay_stats_t *stats, size_t *bad_key);

/**
 * Checks that the defaults of the key table (param_file.h) equal the library's double
 * rfe_params_default exactly (the table is double, so double is the exact comparison).
 * @return RFE_PK_NONE when all agree, else the index of the first key that differs
 *         (RFE_PK_TYRE when tyre or filter differ). Defined in the double object only.
 */
size_t rfe_replay_check_defaults_f64(void);

#endif /* RFE_HOST_REPLAY_REAL_H */
