/**
 * @file metrics.c
 * @brief Accuracy metrics (definitions in metrics.h).
 *
 * One code path serves a single wheel and the four-wheel mean: a series is the average of
 * `width` columns (width 1 = one wheel, width 4 = the mean), and a truth change of any of
 * its columns is a change of the series.
 */
#include "metrics.h"

#include <math.h>

#include "text_io.h"

/** NaN as a double (NAN is a float constant; -Wdouble-promotion). */
#define NAN_D ((double)NAN)

/** A series: value at sample k = mean over `width` columns. */
typedef struct {
    const double *const *truth;
    const double *const *est;
    size_t width;
} series_t;

static const char *const k_wheel_names[RFE_WHEELS] = {"fl", "fr", "rl", "rr"};

static double col_mean(const double *const *cols, size_t width, size_t k);
static int truth_changed(const series_t *s, size_t k, double change_min);
static double max_nan(double m, double a);
static void error_stats(const double *t, size_t n, const series_t *s,
                        const rfe_metrics_config_t *cfg, rfe_metric_t *out);
static double converge_time(const double *t, size_t n, const series_t *s,
                            const rfe_metrics_config_t *cfg);
static void series_metrics(const double *t, size_t n, const series_t *s,
                           const rfe_metrics_config_t *cfg, rfe_metric_t *out);
static void write_series_json(FILE *f, const char *name, const rfe_metric_t *m, int indent,
                              int last);
static void print_row(FILE *f, const char *name, const rfe_metric_t *m);

rfe_metrics_config_t rfe_metrics_config_default(void)
{
    rfe_metrics_config_t c;
    c.settle_start = 1.0;
    c.settle_after_change = 0.5;
    c.converge_tol = 0.05;
    c.change_min = 1e-9;
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

/* RMSE, max |e|, max |e|/truth over the settled samples. */
static void error_stats(const double *t, size_t n, const series_t *s,
                        const rfe_metrics_config_t *cfg, rfe_metric_t *out)
{
    const double t_settle = t[0] + cfg->settle_start;
    double t_change = 0.0;
    int seen_change = 0;
    double sum_sq = 0.0;
    size_t n_rel = 0u;
    size_t k;
    out->n_settled = 0u;
    out->max_abs = 0.0;
    out->max_rel = 0.0;
    for (k = 0u; k < n; ++k) {
        double truth = col_mean(s->truth, s->width, k);
        double e = col_mean(s->est, s->width, k) - truth;
        if ((k > 0u) && truth_changed(s, k, cfg->change_min)) {
            t_change = t[k];
            seen_change = 1;
        }
        if ((t[k] < t_settle) || (seen_change && (t[k] < t_change + cfg->settle_after_change))) {
            continue;
        }
        ++out->n_settled;
        sum_sq += e * e;
        out->max_abs = max_nan(out->max_abs, fabs(e));
        if (truth > 0.0) {
            ++n_rel;
            out->max_rel = max_nan(out->max_rel, fabs(e) / truth);
        }
    }
    out->rmse = (out->n_settled > 0u) ? sqrt(sum_sq / (double)out->n_settled) : NAN_D;
    out->max_abs = (out->n_settled > 0u) ? out->max_abs : NAN_D;
    out->max_rel = (n_rel > 0u) ? out->max_rel : NAN_D;
}

/* Time from the reference (start, or last truth change) until |e| <= tol for good. */
static double converge_time(const double *t, size_t n, const series_t *s,
                            const rfe_metrics_config_t *cfg)
{
    size_t ref = 0u;
    size_t last_bad = n; /* n = none */
    size_t k;
    for (k = 1u; k < n; ++k) {
        if (truth_changed(s, k, cfg->change_min)) {
            ref = k;
        }
    }
    for (k = ref; k < n; ++k) {
        double e = col_mean(s->est, s->width, k) - col_mean(s->truth, s->width, k);
        if (!(fabs(e) <= cfg->converge_tol)) { /* written so that NaN is "outside" */
            last_bad = k;
        }
    }
    if (last_bad == n) {
        return 0.0;
    }
    if (last_bad == n - 1u) {
        return -1.0;
    }
    return t[last_bad + 1u] - t[ref];
}

static void series_metrics(const double *t, size_t n, const series_t *s,
                           const rfe_metrics_config_t *cfg, rfe_metric_t *out)
{
    error_stats(t, n, s, cfg, out);
    out->t_converge = converge_time(t, n, s, cfg);
}

int rfe_metric_series(const double *t, const double *truth, const double *est, size_t n,
                      const rfe_metrics_config_t *cfg, rfe_metric_t *out)
{
    series_t s;
    if ((t == NULL) || (truth == NULL) || (est == NULL) || (cfg == NULL) || (out == NULL) ||
        (n == 0u)) {
        return -1;
    }
    s.truth = &truth;
    s.est = &est;
    s.width = 1u;
    series_metrics(t, n, &s, cfg, out);
    return 0;
}

int rfe_metrics_compute(const double *t, const double *const truth[RFE_WHEELS],
                        const double *const est[RFE_WHEELS], size_t n,
                        const rfe_metrics_config_t *cfg, rfe_metrics_t *out)
{
    series_t s;
    size_t w;
    if ((t == NULL) || (truth == NULL) || (est == NULL) || (cfg == NULL) || (out == NULL) ||
        (n == 0u)) {
        return -1;
    }
    out->cfg = *cfg;
    s.width = 1u;
    for (w = 0u; w < RFE_WHEELS; ++w) {
        s.truth = &truth[w];
        s.est = &est[w];
        series_metrics(t, n, &s, cfg, &out->wheel[w]);
    }
    s.truth = truth;
    s.est = est;
    s.width = RFE_WHEELS;
    series_metrics(t, n, &s, cfg, &out->mean);
    return 0;
}

/* ------------------------------------------------------------ output */

static void write_series_json(FILE *f, const char *name, const rfe_metric_t *m, int indent,
                              int last)
{
    fprintf(f, "%*s\"%s\": {\"n_settled\": %zu, \"rmse\": ", indent + 2, "", name, m->n_settled);
    rfe_json_write_number(f, m->rmse);
    fputs(", \"max_abs_err\": ", f);
    rfe_json_write_number(f, m->max_abs);
    fputs(", \"max_rel_err\": ", f);
    rfe_json_write_number(f, m->max_rel);
    fputs(", \"t_converge_s\": ", f);
    rfe_json_write_number(f, (m->t_converge >= 0.0) ? m->t_converge : NAN_D);
    fprintf(f, "}%s\n", last ? "" : ",");
}

void rfe_metrics_write_json(FILE *f, const rfe_metrics_t *m, int indent)
{
    size_t w;
    fputs("{\n", f);
    fprintf(f, "%*s\"config\": {\"settle_start_s\": ", indent + 2, "");
    rfe_json_write_number(f, m->cfg.settle_start);
    fputs(", \"settle_after_change_s\": ", f);
    rfe_json_write_number(f, m->cfg.settle_after_change);
    fputs(", \"converge_tol\": ", f);
    rfe_json_write_number(f, m->cfg.converge_tol);
    fputs(", \"change_min\": ", f);
    rfe_json_write_number(f, m->cfg.change_min);
    fputs("},\n", f);
    for (w = 0u; w < RFE_WHEELS; ++w) {
        write_series_json(f, k_wheel_names[w], &m->wheel[w], indent, 0);
    }
    write_series_json(f, "mean", &m->mean, indent, 1);
    fprintf(f, "%*s}", indent, "");
}

/* One table line; "n/a" for undefined values, "never" for no convergence. */
static void print_row(FILE *f, const char *name, const rfe_metric_t *m)
{
    fprintf(f, "%-6s", name);
    if (m->n_settled > 0u) {
        fprintf(f, " %9.4f %9.4f", m->rmse, m->max_abs);
    } else {
        fprintf(f, " %9s %9s", "n/a", "n/a");
    }
    if (isnan(m->max_rel)) {
        fprintf(f, " %9s", "n/a");
    } else {
        fprintf(f, " %8.2f%%", 100.0 * m->max_rel);
    }
    if (m->t_converge >= 0.0) {
        fprintf(f, " %10.3f", m->t_converge);
    } else {
        fprintf(f, " %10s", "never");
    }
    fprintf(f, " %8zu\n", m->n_settled);
}

void rfe_metrics_print_table(FILE *f, const rfe_metrics_t *m)
{
    size_t w;
    fprintf(f, "accuracy: settled = t >= t0 + %g s and >= %g s after a truth change; "
               "converged = |err| <= %g to the end\n",
            m->cfg.settle_start, m->cfg.settle_after_change, m->cfg.converge_tol);
    fprintf(f, "%-6s %9s %9s %9s %10s %8s\n", "wheel", "rmse", "max_err", "max_rel", "t_conv[s]",
            "settled");
    for (w = 0u; w < RFE_WHEELS; ++w) {
        print_row(f, k_wheel_names[w], &m->wheel[w]);
    }
    print_row(f, "mean", &m->mean);
}
