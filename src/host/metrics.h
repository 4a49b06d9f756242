/**
 * @file metrics.h
 * @brief Accuracy of friction estimates against the truth columns of a simulated log.
 *
 * Per wheel and for the four-wheel mean (mean estimate against mean truth):
 *  - settled samples: t >= t[0] + settle_start, and not within settle_after_change seconds
 *    after a change of the truth (for the mean: a change of any wheel's truth), i.e. a
 *    change at t_c excludes t_c <= t < t_c + settle_after_change;
 *  - RMSE, max |error| and max |error| / truth over the settled samples (relative error
 *    skips samples whose truth is <= 0);
 *  - time to converge: from t[0], or from the last truth change if there is one, until
 *    |error| <= converge_tol holds at every later sample to the end of the log; negative
 *    when it never does (the last sample is outside the tolerance).
 * A "change" is |truth[k] - truth[k-1]| > change_min (absorbs round-off in written logs).
 * NaN estimates count as outside every tolerance and make RMSE / max NaN.
 */
#ifndef RFE_HOST_METRICS_H
#define RFE_HOST_METRICS_H

#include <stddef.h>
#include <stdio.h>

#include "rfe/types.h"

/** Knobs of the accuracy definition (no literals in the loops). */
typedef struct {
    double settle_start;         /**< [s] ignore the start of the log, default 1.0 */
    double settle_after_change;  /**< [s] ignore after each truth change, default 0.5 */
    double converge_tol;         /**< |error| bound for convergence, default 0.05 */
    double change_min;           /**< smallest truth step that counts as a change, default 1e-9 */
} rfe_metrics_config_t;

/** The defaults above. */
rfe_metrics_config_t rfe_metrics_config_default(void);

/** Accuracy of one series. Values are NaN when undefined (no settled sample). */
typedef struct {
    size_t n_settled;     /**< samples the error statistics use */
    double rmse;
    double max_abs;       /**< max |error| */
    double max_rel;       /**< max |error| / truth */
    double t_converge;    /**< [s] time to converge, < 0 = never */
} rfe_metric_t;

/** Accuracy of a run: per wheel (fl, fr, rl, rr) and of the four-wheel mean. */
typedef struct {
    rfe_metrics_config_t cfg;
    rfe_metric_t wheel[RFE_WHEELS];
    rfe_metric_t mean;
} rfe_metrics_t;

/**
 * Accuracy of one estimate series @p est against @p truth at times @p t (n samples, t
 * increasing). @return 0, or -1 when n == 0 or a pointer is NULL.
 */
RFE_NODISCARD int rfe_metric_series(const double *t, const double *truth, const double *est,
                                    size_t n, const rfe_metrics_config_t *cfg, rfe_metric_t *out);

/**
 * Accuracy per wheel and of the mean. truth[w] and est[w] are the columns of wheel w.
 * @return 0, or -1 when n == 0 or a pointer is NULL.
 */
RFE_NODISCARD int rfe_metrics_compute(const double *t, const double *const truth[RFE_WHEELS],
                                      const double *const est[RFE_WHEELS], size_t n,
                                      const rfe_metrics_config_t *cfg, rfe_metrics_t *out);

/**
 * Writes @p m as a JSON object: {"config": {...}, "fl": {...}, ..., "mean": {...}}; each
 * series has n_settled, rmse, max_abs_err, max_rel_err, t_converge_s (null = never / n.a.).
 * @p indent spaces precede nested lines.
 */
void rfe_metrics_write_json(FILE *f, const rfe_metrics_t *m, int indent);

/** Prints the compact accuracy table (one line per wheel and the mean). */
void rfe_metrics_print_table(FILE *f, const rfe_metrics_t *m);

#endif /* RFE_HOST_METRICS_H */
