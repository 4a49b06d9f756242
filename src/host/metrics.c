/**
 * @file metrics.c
 * @brief Accuracy metrics (definitions in metrics.h).
 *
 * One code path serves a single wheel and the four-wheel mean: a series is the average of
 * `width` columns (width 1 = one wheel, width 4 = the mean); a truth change of any of its
 * columns is a change of the series, it is valid when all its columns are, excited when any
 * is, and its sd is sqrt(sum sd^2) / width.
 */
#include "metrics.h"

#include <math.h>

#include "text_io.h"

/** NaN as a double (NAN is a float constant; -Wdouble-promotion). */
#define NAN_D ((double)NAN)

/** A series: value at sample k = mean over `width` columns (sd: see series_sd). */
typedef struct {
    const double *const *truth;
    const double *const *est;
    const double *const *sd;
    const unsigned char *const *valid;
    const double *const *util; /* NULL: no util columns */
    size_t width;
} series_t;

/** Running sums of one set of samples (for an RMSE). */
typedef struct {
    size_t n;
    double sum_sq;
} sq_sum_t;

static const char *const k_wheel_names[RFE_WHEELS] = {"fl", "fr", "rl", "rr"};

static double col_mean(const double *const *cols, size_t width, size_t k);
static double series_sd(const series_t *s, size_t k);
static int series_valid(const series_t *s, size_t k);
static int series_excited(const series_t *s, size_t k, double excite_util);
static int truth_changed(const series_t *s, size_t k, double change_min);
static double max_nan(double m, double a);
static void sq_add(sq_sum_t *acc, double e);
static double sq_rmse(const sq_sum_t *acc);
static double share(size_t part, size_t whole);
static void error_stats(const double *t, size_t n, const series_t *s,
                        const rfe_metrics_config_t *cfg, rfe_metric_t *out);
static size_t last_outside(size_t from, size_t to, const series_t *s, double tol);
static double converge_time(const double *t, size_t n, const series_t *s,
                            const rfe_metrics_config_t *cfg);
static void reconverge_stats(const double *t, size_t n, const series_t *s,
                             const rfe_metrics_config_t *cfg, rfe_metric_t *out);
static int columns_given(const rfe_metrics_input_t *in, size_t first, size_t width);
static void series_of(const rfe_metrics_input_t *in, size_t first, size_t width, series_t *s);
static void json_key(FILE *f, const char *key, double v);
static void write_series_json(FILE *f, const char *name, const rfe_metric_t *m, int indent,
                              int last);
static void print_value(FILE *f, double v, const char *fmt, double scale, const char *undef);
static void print_row(FILE *f, const char *name, const rfe_metric_t *m, int with_util);

rfe_metrics_config_t rfe_metrics_config_default(void)
{
    rfe_metrics_config_t c;
    c.settle_start = 1.0;
    c.settle_after_change = 0.5;
    c.converge_tol = 0.05;
    c.change_min = 1e-9;
    c.consistency_k = 2.0;
    c.excite_util = 0.5;
    return c;
}

static double col_mean(const double *const *cols, size_t width, size_t k)
{
    double s = 0.0;
    size_t c;
    for (c = 0u; c < width; ++c) {
        s += cols[c][k];
    }
    return s / (double)width;
}

/* sd of the series: one wheel's sd; for the mean sqrt(sum sd_i^2) / width, the sd of the
 * mean of independent errors (metrics.h). */
static double series_sd(const series_t *s, size_t k)
{
    double ss = 0.0;
    size_t c;
    for (c = 0u; c < s->width; ++c) {
        ss += s->sd[c][k] * s->sd[c][k];
    }
    return sqrt(ss) / (double)s->width;
}

/* Valid when every column of the series is flagged valid. */
static int series_valid(const series_t *s, size_t k)
{
    size_t c;
    for (c = 0u; c < s->width; ++c) {
        if (s->valid[c][k] == 0u) {
            return 0;
        }
    }
    return 1;
}

/* Excited when any column's utilisation reaches the threshold (NaN: not excited). */
static int series_excited(const series_t *s, size_t k, double excite_util)
{
    size_t c;
    for (c = 0u; c < s->width; ++c) {
        if (s->util[c][k] >= excite_util) {
            return 1;
        }
    }
    return 0;
}

/* Sample k (>= 1) starts a new truth value in any column of the series. */
static int truth_changed(const series_t *s, size_t k, double change_min)
{
    size_t c;
    for (c = 0u; c < s->width; ++c) {
        if (fabs(s->truth[c][k] - s->truth[c][k - 1u]) > change_min) {
            return 1;
        }
    }
    return 0;
}

/* max that keeps a NaN once seen (a NaN estimate must not vanish from the report). */
static double max_nan(double m, double a)
{
    return (isnan(a) || (a > m)) ? a : m;
}

static void sq_add(sq_sum_t *acc, double e)
{
    ++acc->n;
    acc->sum_sq += e * e;
}

static double sq_rmse(const sq_sum_t *acc)
{
    return (acc->n > 0u) ? sqrt(acc->sum_sq / (double)acc->n) : NAN_D;
}

static double share(size_t part, size_t whole)
{
    return (whole > 0u) ? (double)part / (double)whole : NAN_D;
}

/* Every statistic over the settled samples: all, valid, consistent, excited. */
static void error_stats(const double *t, size_t n, const series_t *s,
                        const rfe_metrics_config_t *cfg, rfe_metric_t *out)
{
    const double t_settle = t[0] + cfg->settle_start;
    double t_change = 0.0;
    int seen_change = 0;
    sq_sum_t all = {0u, 0.0};
    sq_sum_t valid = {0u, 0.0};
    sq_sum_t exc_valid = {0u, 0.0};
    size_t n_rel = 0u;
    size_t n_consistent = 0u;
    size_t n_consistent_valid = 0u;
    size_t k;
    out->max_abs = 0.0;
    out->max_abs_valid = 0.0;
    out->max_rel = 0.0;
    out->n_excited = 0u;
    for (k = 0u; k < n; ++k) {
        double truth = col_mean(s->truth, s->width, k);
        double e = col_mean(s->est, s->width, k) - truth;
        int is_valid;
        size_t consistent;
        if ((k > 0u) && truth_changed(s, k, cfg->change_min)) {
            t_change = t[k];
            seen_change = 1;
        }
        if ((t[k] < t_settle) || (seen_change && (t[k] < t_change + cfg->settle_after_change))) {
            continue;
        }
        sq_add(&all, e);
        out->max_abs = max_nan(out->max_abs, fabs(e));
        if (truth > 0.0) {
            ++n_rel;
            out->max_rel = max_nan(out->max_rel, fabs(e) / truth);
        }
        /* Written so that a NaN error or sd is inconsistent. */
        consistent = (fabs(e) <= cfg->consistency_k * series_sd(s, k)) ? 1u : 0u;
        n_consistent += consistent;
        is_valid = series_valid(s, k);
        if (is_valid) {
            sq_add(&valid, e);
            out->max_abs_valid = max_nan(out->max_abs_valid, fabs(e));
            n_consistent_valid += consistent;
        }
        if ((s->util != NULL) && series_excited(s, k, cfg->excite_util)) {
            ++out->n_excited;
            if (is_valid) {
                sq_add(&exc_valid, e);
            }
        }
    }
    out->n_settled = all.n;
    out->rmse = sq_rmse(&all);
    out->max_abs = (all.n > 0u) ? out->max_abs : NAN_D;
    out->max_rel = (n_rel > 0u) ? out->max_rel : NAN_D;
    out->n_valid = valid.n;
    out->rmse_valid = sq_rmse(&valid);
    out->max_abs_valid = (valid.n > 0u) ? out->max_abs_valid : NAN_D;
    out->frac_valid = share(valid.n, all.n);
    out->consistency = share(n_consistent, all.n);
    out->consistency_valid = share(n_consistent_valid, valid.n);
    out->has_util = (s->util != NULL) ? 1 : 0;
    out->frac_valid_excited = share(exc_valid.n, out->n_excited);
    out->rmse_excited_valid = sq_rmse(&exc_valid);
}

/* Last k in [from, to) with |e| > tol (NaN counts as outside), or `to` when none. */
static size_t last_outside(size_t from, size_t to, const series_t *s, double tol)
{
    size_t last = to;
    size_t k;
    for (k = from; k < to; ++k) {
        double e = col_mean(s->est, s->width, k) - col_mean(s->truth, s->width, k);
        if (!(fabs(e) <= tol)) { /* written so that NaN is "outside" */
            last = k;
        }
    }
    return last;
}

/* Time from the reference (start, or last truth change) until |e| <= tol for good. */
static double converge_time(const double *t, size_t n, const series_t *s,
                            const rfe_metrics_config_t *cfg)
{
    size_t ref = 0u;
    size_t last_bad;
    size_t k;
    for (k = 1u; k < n; ++k) {
        if (truth_changed(s, k, cfg->change_min)) {
            ref = k;
        }
    }
    last_bad = last_outside(ref, n, s, cfg->converge_tol);
    if (last_bad == n) {
        return 0.0;
    }
    if (last_bad == n - 1u) {
        return -1.0;
    }
    return t[last_bad + 1u] - t[ref];
}

/* Per change: time until |e| <= tol holds to the next change (or the end); the maximum. */
static void reconverge_stats(const double *t, size_t n, const series_t *s,
                             const rfe_metrics_config_t *cfg, rfe_metric_t *out)
{
    size_t c = 0u; /* start of the current segment; 0 = before the first change */
    size_t k;
    double worst = 0.0;
    out->n_changes = 0u;
    out->n_reconverged = 0u;
    for (k = 1u; k <= n; ++k) {
        size_t bad;
        if ((k < n) && !truth_changed(s, k, cfg->change_min)) {
            continue;
        }
        if (c > 0u) { /* close the segment [c, k) that a change opened */
            bad = last_outside(c, k, s, cfg->converge_tol);
            if (bad == k) {
                ++out->n_reconverged; /* inside from the change on: 0 s */
            } else if (bad + 1u < k) {
                ++out->n_reconverged;
                worst = fmax(worst, t[bad + 1u] - t[c]);
            }
        }
        if (k < n) {
            ++out->n_changes;
            c = k;
        }
    }
    out->reconverge =
        ((out->n_changes > 0u) && (out->n_reconverged == out->n_changes)) ? worst : NAN_D;
}

/* Pointers the series [first, first + width) needs; util all or none. */
static int columns_given(const rfe_metrics_input_t *in, size_t first, size_t width)
{
    size_t n_util = 0u;
    size_t c;
    if ((in->t == NULL) || (in->n == 0u)) {
        return 0;
    }
    for (c = first; c < first + width; ++c) {
        if ((in->truth[c] == NULL) || (in->est[c] == NULL) || (in->sd[c] == NULL) ||
            (in->valid[c] == NULL)) {
            return 0;
        }
        n_util += (in->util[c] != NULL) ? 1u : 0u;
    }
    return (n_util == 0u) || (n_util == width);
}

static void series_of(const rfe_metrics_input_t *in, size_t first, size_t width, series_t *s)
{
    s->truth = &in->truth[first];
    s->est = &in->est[first];
    s->sd = &in->sd[first];
    s->valid = &in->valid[first];
    s->util = (in->util[first] != NULL) ? &in->util[first] : NULL;
    s->width = width;
}

int rfe_metric_series(const rfe_metrics_input_t *in, size_t series,
                      const rfe_metrics_config_t *cfg, rfe_metric_t *out)
{
    const size_t first = (series == RFE_METRICS_MEAN) ? 0u : series;
    const size_t width = (series == RFE_METRICS_MEAN) ? (size_t)RFE_WHEELS : 1u;
    series_t s;
    if ((in == NULL) || (cfg == NULL) || (out == NULL) || (series > RFE_METRICS_MEAN) ||
        !columns_given(in, first, width)) {
        return -1;
    }
    series_of(in, first, width, &s);
    error_stats(in->t, in->n, &s, cfg, out);
    out->t_converge = converge_time(in->t, in->n, &s, cfg);
    reconverge_stats(in->t, in->n, &s, cfg, out);
    return 0;
}

int rfe_metrics_compute(const rfe_metrics_input_t *in, const rfe_metrics_config_t *cfg,
                        rfe_metrics_t *out)
{
    int rc;
    size_t w;
    /* The mean needs every column: checking it first leaves out untouched on -1. */
    if ((in == NULL) || (cfg == NULL) || (out == NULL) || !columns_given(in, 0u, RFE_WHEELS)) {
        return -1;
    }
    out->cfg = *cfg;
    rc = rfe_metric_series(in, RFE_METRICS_MEAN, cfg, &out->mean);
    for (w = 0u; w < RFE_WHEELS; ++w) {
        rc |= rfe_metric_series(in, w, cfg, &out->wheel[w]); /* 0: checked above */
    }
    return rc;
}

/* ------------------------------------------------------------ output */

static void json_key(FILE *f, const char *key, double v)
{
    fprintf(f, ", \"%s\": ", key);
    rfe_json_write_number(f, v);
}

static void write_series_json(FILE *f, const char *name, const rfe_metric_t *m, int indent,
                              int last)
{
    fprintf(f, "%*s\"%s\": {\"n_settled\": %zu", indent + 2, "", name, m->n_settled);
    json_key(f, "rmse", m->rmse);
    json_key(f, "max_abs_err", m->max_abs);
    json_key(f, "max_rel_err", m->max_rel);
    json_key(f, "t_converge_s", (m->t_converge >= 0.0) ? m->t_converge : NAN_D);
    fprintf(f, ", \"n_valid\": %zu", m->n_valid);
    json_key(f, "rmse_valid", m->rmse_valid);
    json_key(f, "max_abs_err_valid", m->max_abs_valid);
    json_key(f, "frac_valid", m->frac_valid);
    json_key(f, "consistency", m->consistency);
    json_key(f, "consistency_valid", m->consistency_valid);
    fprintf(f, ", \"n_changes\": %zu, \"n_reconverged\": %zu", m->n_changes, m->n_reconverged);
    json_key(f, "reconverge_s", m->reconverge);
    if (m->has_util) {
        fprintf(f, ", \"n_excited\": %zu", m->n_excited);
    } else {
        fputs(", \"n_excited\": null", f);
    }
    json_key(f, "frac_valid_excited", m->has_util ? m->frac_valid_excited : NAN_D);
    json_key(f, "rmse_excited_valid", m->has_util ? m->rmse_excited_valid : NAN_D);
    fprintf(f, "}%s\n", last ? "" : ",");
}

void rfe_metrics_write_json(FILE *f, const rfe_metrics_t *m, int indent)
{
    size_t w;
    fputs("{\n", f);
    fprintf(f, "%*s\"config\": {\"settle_start_s\": ", indent + 2, "");
    rfe_json_write_number(f, m->cfg.settle_start);
    json_key(f, "settle_after_change_s", m->cfg.settle_after_change);
    json_key(f, "converge_tol", m->cfg.converge_tol);
    json_key(f, "change_min", m->cfg.change_min);
    json_key(f, "consistency_k", m->cfg.consistency_k);
    json_key(f, "excite_util", m->cfg.excite_util);
    fputs("},\n", f);
    for (w = 0u; w < RFE_WHEELS; ++w) {
        write_series_json(f, k_wheel_names[w], &m->wheel[w], indent, 0);
    }
    write_series_json(f, "mean", &m->mean, indent, 1);
    fprintf(f, "%*s}", indent, "");
}

/* One right-aligned cell of CELL_W characters after a blank: v * scale with @p fmt (of that
 * width), or @p undef when NaN. */
#define CELL_W 7
static void print_value(FILE *f, double v, const char *fmt, double scale, const char *undef)
{
    if (isnan(v)) {
        fprintf(f, " %*s", CELL_W, undef);
    } else {
        fputc(' ', f);
        fprintf(f, fmt, v * scale);
    }
}

/* One table line; "n/a" for undefined values, "never" for no (re)convergence, "-" for
 * "no truth change". */
static void print_row(FILE *f, const char *name, const rfe_metric_t *m, int with_util)
{
    const int never_reconverged = (m->n_changes > 0u) && (m->n_reconverged < m->n_changes);
    fprintf(f, "%-6s", name);
    print_value(f, m->rmse, "%7.4f", 1.0, "n/a");
    print_value(f, m->max_abs, "%7.4f", 1.0, "n/a");
    print_value(f, m->rmse_valid, "%7.4f", 1.0, "n/a");
    print_value(f, m->frac_valid, "%6.1f%%", 100.0, "n/a");
    print_value(f, m->consistency, "%6.1f%%", 100.0, "n/a");
    print_value(f, (m->t_converge >= 0.0) ? m->t_converge : NAN_D, "%7.3f", 1.0, "never");
    print_value(f, m->reconverge, "%7.3f", 1.0, never_reconverged ? "never" : "-");
    if (with_util) {
        print_value(f, m->frac_valid_excited, "%6.1f%%", 100.0, "n/a");
        fprintf(f, " %*zu", CELL_W, m->n_excited);
    }
    fprintf(f, " %*zu\n", CELL_W, m->n_settled);
}

void rfe_metrics_print_table(FILE *f, const rfe_metrics_t *m)
{
    const int with_util = m->mean.has_util;
    size_t w;
    fprintf(f, "accuracy over settled samples (t >= t0 + %g s, >= %g s after a truth change);"
               " times in s\n",
            m->cfg.settle_start, m->cfg.settle_after_change);
    fprintf(f, "t_conv: |err| <= %g from then to the end; reconv: the same up to the next "
               "change, worst change\n",
            m->cfg.converge_tol);
    fprintf(f, "valid%%: flagged valid; rmse_v: rmse where valid; cons%%: |err| <= %g sd",
            m->cfg.consistency_k);
    if (with_util) {
        fprintf(f, "; exc_val: valid%% where util >= %g", m->cfg.excite_util);
    }
    fputc('\n', f);
    fprintf(f, "%-6s %*s %*s %*s %*s %*s %*s %*s", "wheel", CELL_W, "rmse", CELL_W, "max_err",
            CELL_W, "rmse_v", CELL_W, "valid%", CELL_W, "cons%", CELL_W, "t_conv", CELL_W,
            "reconv");
    if (with_util) {
        fprintf(f, " %*s %*s", CELL_W, "exc_val", CELL_W, "n_exc");
    }
    fprintf(f, " %*s\n", CELL_W, "settled");
    for (w = 0u; w < RFE_WHEELS; ++w) {
        print_row(f, k_wheel_names[w], &m->wheel[w], with_util);
    }
    print_row(f, "mean", &m->mean, with_util);
}
