/**
 * @file metrics.h
 * @brief Accuracy of friction estimates against the truth columns of a simulated log.
 *
 * The one definition of every figure: mu_replay prints it, writes it as JSON, and the
 * README table script reads that JSON. Per wheel and for the four-wheel mean ("the mean
 * series": mean estimate against mean truth). Definitions, with e = estimate - truth:
 *
 *  - settled samples: t >= t[0] + settle_start, and not within settle_after_change seconds
 *    after a change of the truth (for the mean: a change of any wheel's truth), i.e. a
 *    change at t_c excludes t_c <= t < t_c + settle_after_change. A "change" is
 *    |truth[k] - truth[k-1]| > change_min (absorbs round-off in written logs).
 *    Every statistic below except t_converge / reconverge is over settled samples only.
 *  - rmse, max_abs (max |e|), max_rel (max |e| / truth, skipping truth <= 0).
 *  - t_converge: from t[0], or from the last truth change if there is one, until
 *    |e| <= converge_tol holds at every later sample to the end; negative = never (the
 *    last sample is outside the tolerance).
 *  - valid: a sample is valid for a wheel when its valid flag is nonzero (the estimate log
 *    writes 0/1); for the mean series when all four wheels are valid.
 *    n_valid: settled valid samples; frac_valid = n_valid / n_settled;
 *    rmse_valid: RMSE over the settled valid samples (NaN when there are none).
 *  - consistency: share of settled samples with |e| <= consistency_k * sd (default k = 2:
 *    an honest Gaussian filter scores about 95 %). sd is the estimate's standard deviation;
 *    for the mean series sd_mean = sqrt(sd_fl^2 + sd_fr^2 + sd_rl^2 + sd_rr^2) / 4, the sd
 *    of the mean if the four wheels' errors were independent. (The estimate log holds only
 *    the diagonal, so the cross-covariances are unknown; with positively correlated errors
 *    the true sd of the mean is larger, up to the mean of the four sd, so the mean's
 *    consistency is the stricter reading.) A NaN e or sd counts as inconsistent.
 *  - reconverge: for each truth change at sample c (as above; for the mean any wheel's),
 *    the segment runs from c up to the next change (exclusive) or the end; the time to
 *    re-converge is t[j] - t[c] where j is the first sample of the segment from which
 *    |e| <= converge_tol holds to the segment's end (0 when it holds from c on). A change
 *    whose segment ends outside the tolerance never re-converges.
 *    n_changes: number of changes; n_reconverged: how many re-converged;
 *    reconverge = the maximum over changes, NaN when n_changes == 0 or when
 *    n_reconverged < n_changes (some change never re-converged).
 *  - excitation (only when the log has the truth utilisation columns util_fl..util_rr):
 *    a sample is excited for a wheel when util >= excite_util (default 0.5); for the mean
 *    series when any wheel is excited. n_excited: settled excited samples;
 *    frac_valid_excited: share of them flagged valid (NaN when n_excited == 0);
 *    rmse_excited_valid: RMSE over the settled excited valid samples (NaN when none).
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
    double converge_tol;         /**< |error| bound for (re)convergence, default 0.05 */
    double change_min;           /**< smallest truth step that counts as a change, default 1e-9 */
    double consistency_k;        /**< consistent: |error| <= consistency_k * sd, default 2 */
    double excite_util;          /**< excited: true utilisation >= excite_util, default 0.5 */
} rfe_metrics_config_t;

/** The defaults above. */
rfe_metrics_config_t rfe_metrics_config_default(void);

/** Index of the mean series in rfe_metric_series (the wheels are 0..RFE_WHEELS-1). */
#define RFE_METRICS_MEAN ((size_t)RFE_WHEELS)

/**
 * The columns of one run, n samples each: times (increasing), and per wheel the truth,
 * the estimate, its sd and valid flag, and optionally the true utilisation. A series
 * needs the columns of its wheels (all four for the mean); util is all four or none.
 */
typedef struct {
    const double *t;
    size_t n;
    const double *truth[RFE_WHEELS];
    const double *est[RFE_WHEELS];
    const double *sd[RFE_WHEELS];
    const unsigned char *valid[RFE_WHEELS];
    const double *util[RFE_WHEELS];  /**< all NULL when the log has no util columns */
} rfe_metrics_input_t;

/** Accuracy of one series (definitions above). Doubles are NaN where undefined. */
typedef struct {
    size_t n_settled;       /**< samples the error statistics use */
    double rmse;
    double max_abs;         /**< max |error| */
    double max_rel;         /**< max |error| / truth */
    double t_converge;      /**< [s] time to converge, < 0 = never */
    size_t n_valid;         /**< settled samples flagged valid */
    double rmse_valid;      /**< RMSE over settled valid samples */
    double max_abs_valid;   /**< max |error| over settled valid samples: the worst case when valid */
    double frac_valid;      /**< n_valid / n_settled */
    double consistency;     /**< share of settled samples with |error| <= k sd */
    double consistency_valid; /**< the same share among the settled valid samples */
    size_t n_changes;       /**< truth changes */
    size_t n_reconverged;   /**< changes after which the estimate re-converged */
    double reconverge;      /**< [s] max time to re-converge over the changes */
    int has_util;           /**< the excitation figures are defined (util columns given) */
    size_t n_excited;       /**< settled excited samples */
    double frac_valid_excited; /**< share of settled excited samples flagged valid */
    double rmse_excited_valid; /**< RMSE over settled excited valid samples */
} rfe_metric_t;

/** Accuracy of a run: per wheel (fl, fr, rl, rr) and of the four-wheel mean. */
typedef struct {
    rfe_metrics_config_t cfg;
    rfe_metric_t wheel[RFE_WHEELS];
    rfe_metric_t mean;
} rfe_metrics_t;

/**
 * Accuracy of one series: wheel @p series (0..3), or RFE_METRICS_MEAN.
 * @return 0, or -1 when n == 0, a pointer the series needs is NULL, util is neither all
 *         four nor none (for the wheel: that wheel's column decides), or series > 4.
 */
RFE_NODISCARD int rfe_metric_series(const rfe_metrics_input_t *in, size_t series,
                                    const rfe_metrics_config_t *cfg, rfe_metric_t *out);

/**
 * Accuracy per wheel and of the mean. @return 0, or -1 as rfe_metric_series (every
 * column of all four wheels is needed).
 */
RFE_NODISCARD int rfe_metrics_compute(const rfe_metrics_input_t *in,
                                      const rfe_metrics_config_t *cfg, rfe_metrics_t *out);

/**
 * Writes @p m as a JSON object: {"config": {...}, "fl": {...}, ..., "mean": {...}}.
 * config: settle_start_s, settle_after_change_s, converge_tol, change_min, consistency_k,
 * excite_util. Each series: n_settled, rmse, max_abs_err, max_rel_err, t_converge_s,
 * n_valid, rmse_valid, frac_valid, consistency, n_changes, n_reconverged, reconverge_s,
 * n_excited, frac_valid_excited, rmse_excited_valid. null where undefined (NaN, "never",
 * and the three excitation keys when the log has no util columns). Shares are fractions
 * (0..1), not percent. @p indent spaces precede nested lines.
 */
void rfe_metrics_write_json(FILE *f, const rfe_metrics_t *m, int indent);

/** Prints the compact accuracy table (one line per wheel and the mean). */
void rfe_metrics_print_table(FILE *f, const rfe_metrics_t *m);

#endif /* RFE_HOST_METRICS_H */
