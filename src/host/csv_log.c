/**
 * @file csv_log.c
 * @brief Sensor-log reader and estimate-log writer (DATA.md), host only.
 *
 * The reader is line-oriented: metadata and blank lines until the header, then data rows.
 * Columns are found by name through one table (k_cols), so a new input column is one line.
 */
#include "csv_log.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "log_units.h"

/** Column roles: required input, or one of the optional groups (each all or none): true
 *  friction, true friction utilisation, measured velocities (a test car), brake
 *  pressures, drive torques, the known grade; the steering pair; the mass and grade
 *  estimator's columns and their truth (each on its own). */
typedef enum {
    COL_INPUT = 0,
    COL_MU = 1,
    COL_UTIL = 2,
    COL_VEL = 3,
    COL_PRES = 4,
    COL_TORQ = 5,
    COL_GRADE = 6,
    COL_STEER = 7, /**< delta or swa: exactly one of them */
    COL_MG = 8,    /**< an input of the mass and grade estimator, each optional on its own;
                        read only with drive_torque (and not mass_grade_off) */
    COL_MG_TRUTH = 9, /**< its truth, each optional on its own, read as COL_MG */
    COL_KINDS = 10
} col_kind_t;

/** A sensor-log column: its DATA.md name, where its value goes in a row, its role and its
 *  physical quantity (which unit_<name> words it accepts). */
typedef struct {
    const char *name;
    size_t offset;
    col_kind_t kind;
    rfe_dim_t dim;
} col_spec_t;

#define ROW_OFF(member) offsetof(rfe_sensor_row_t, member)

static const col_spec_t k_cols[] = {
    {"t", ROW_OFF(t), COL_INPUT, RFE_DIM_TIME},
    {"delta", ROW_OFF(delta), COL_STEER, RFE_DIM_ANGLE},
    {"swa", ROW_OFF(swa), COL_STEER, RFE_DIM_ANGLE},
    {"vx", ROW_OFF(vx), COL_VEL, RFE_DIM_SPEED},
    {"vy", ROW_OFF(vy), COL_VEL, RFE_DIM_SPEED},
    {"yaw_rate", ROW_OFF(yaw_rate), COL_INPUT, RFE_DIM_RATE},
    {"yaw_acc", ROW_OFF(yaw_acc), COL_VEL, RFE_DIM_ANG_ACC},
    {"ax", ROW_OFF(ax), COL_INPUT, RFE_DIM_ACC},
    {"ay", ROW_OFF(ay), COL_INPUT, RFE_DIM_ACC},
    {"omega_fl", ROW_OFF(omega[RFE_FL]), COL_INPUT, RFE_DIM_WHEEL},
    {"omega_fr", ROW_OFF(omega[RFE_FR]), COL_INPUT, RFE_DIM_WHEEL},
    {"omega_rl", ROW_OFF(omega[RFE_RL]), COL_INPUT, RFE_DIM_WHEEL},
    {"omega_rr", ROW_OFF(omega[RFE_RR]), COL_INPUT, RFE_DIM_WHEEL},
    {"mu_fl", ROW_OFF(mu_true[RFE_FL]), COL_MU, RFE_DIM_NONE},
    {"mu_fr", ROW_OFF(mu_true[RFE_FR]), COL_MU, RFE_DIM_NONE},
    {"mu_rl", ROW_OFF(mu_true[RFE_RL]), COL_MU, RFE_DIM_NONE},
    {"mu_rr", ROW_OFF(mu_true[RFE_RR]), COL_MU, RFE_DIM_NONE},
    {"util_fl", ROW_OFF(util_true[RFE_FL]), COL_UTIL, RFE_DIM_NONE},
    {"util_fr", ROW_OFF(util_true[RFE_FR]), COL_UTIL, RFE_DIM_NONE},
    {"util_rl", ROW_OFF(util_true[RFE_RL]), COL_UTIL, RFE_DIM_NONE},
    {"util_rr", ROW_OFF(util_true[RFE_RR]), COL_UTIL, RFE_DIM_NONE},
    {"p_fl", ROW_OFF(p_brake[RFE_FL]), COL_PRES, RFE_DIM_PRESSURE},
    {"p_fr", ROW_OFF(p_brake[RFE_FR]), COL_PRES, RFE_DIM_PRESSURE},
    {"p_rl", ROW_OFF(p_brake[RFE_RL]), COL_PRES, RFE_DIM_PRESSURE},
    {"p_rr", ROW_OFF(p_brake[RFE_RR]), COL_PRES, RFE_DIM_PRESSURE},
    {"torque_fl", ROW_OFF(torque[RFE_FL]), COL_TORQ, RFE_DIM_TORQUE},
    {"torque_fr", ROW_OFF(torque[RFE_FR]), COL_TORQ, RFE_DIM_TORQUE},
    {"torque_rl", ROW_OFF(torque[RFE_RL]), COL_TORQ, RFE_DIM_TORQUE},
    {"torque_rr", ROW_OFF(torque[RFE_RR]), COL_TORQ, RFE_DIM_TORQUE},
    {"grade", ROW_OFF(grade), COL_GRADE, RFE_DIM_ANGLE},
    {"drive_torque", ROW_OFF(drive_torque), COL_MG, RFE_DIM_TORQUE},
    {"brake", ROW_OFF(brake), COL_MG, RFE_DIM_NONE},
    {"brake_pressure", ROW_OFF(brake_pressure), COL_MG, RFE_DIM_PRESSURE_PA},
    {"gear", ROW_OFF(gear), COL_MG, RFE_DIM_NONE},
    {"mass_true", ROW_OFF(mass_true), COL_MG_TRUTH, RFE_DIM_MASS},
    {"grade_true", ROW_OFF(grade_true), COL_MG_TRUTH, RFE_DIM_ANGLE},
};
#define N_COLS (sizeof k_cols / sizeof k_cols[0])

/** "No column" marker in the field -> column map. */
#define NO_COL SIZE_MAX

/** Longest piece of file text quoted in a message. */
#define QUOTE_MAX 40u

/** Reading state: the stream, the current line and the header's layout. */
typedef struct {
    FILE *f;
    const char *name;
    rfe_io_error_t *err;
    char *buf;
    size_t cap;
    size_t len;
    size_t line;          /**< number of the line in buf */
    size_t header_line;
    size_t n_fields;      /**< fields per row (header width) */
    size_t t_field;       /**< field index of column t */
    size_t *field_col;    /**< per field: index into k_cols, or NO_COL (ignored column) */
    const char *want[N_COLS]; /**< header name of each column (its name, or column_<name>) */
    double col_a[N_COLS];     /**< per column: SI value = col_a * text + col_b (unit_, scale_, */
    double col_b[N_COLS];     /**< offset_ metadata) */
    char **fields;        /**< n_fields pointers into buf, reused per row */
    rfe_read_opts_t opts; /**< what a bad cell is, which input columns the run uses */
    unsigned char unused[N_COLS]; /**< 1: an input column the run does not use */
    size_t rows_cap;
    size_t meta_cap;
    int bad_cell;         /**< the error is a bad cell refused (not text that is no number) */
} reader_t;

static int next_line(reader_t *r);
static int read_preamble(reader_t *r, rfe_sensor_log_t *log);
static void add_meta(reader_t *r, rfe_sensor_log_t *log);
static size_t split_fields(char *line, char **fields, size_t max);
static int parse_header(reader_t *r, rfe_sensor_log_t *log);
static int check_column_meta(reader_t *r, const rfe_sensor_log_t *log);
static int column_meta(reader_t *r, rfe_sensor_log_t *log, size_t k);
static int meta_number(reader_t *r, const rfe_sensor_log_t *log, const char *key, double *v);
static int map_header_fields(reader_t *r, size_t n);
static int check_columns(reader_t *r, rfe_sensor_log_t *log);
static int read_rows(reader_t *r, rfe_sensor_log_t *log);
static int parse_row(reader_t *r, rfe_sensor_log_t *log);
static void *grow(void *arr, size_t *cap, size_t elem, size_t need);
static void write_sanitised(FILE *f, const char *s);

/* ---------------------------------------------------------------- reading */

int rfe_sensor_log_read(const char *path, rfe_sensor_log_t *log, rfe_io_error_t *err)
{
    return rfe_sensor_log_read_cells(path, RFE_CELLS_STRICT, log, err);
}

int rfe_sensor_log_read_stream(FILE *f, const char *name, rfe_sensor_log_t *log,
                               rfe_io_error_t *err)
{
    return rfe_sensor_log_read_stream_cells(f, name, RFE_CELLS_STRICT, log, err);
}

const char *rfe_cell_cause_str(rfe_cell_cause_t c)
{
    switch (c) {
    case RFE_CELL_EMPTY: return "empty";
    case RFE_CELL_NONFINITE: return "nan/inf";
    case RFE_CELL_RANGE: return "out of range";
    default: return "?";
    }
}

int rfe_sensor_log_read_cells(const char *path, rfe_cells_t cells, rfe_sensor_log_t *log,
                              rfe_io_error_t *err)
{
    rfe_read_opts_t opts;
    memset(&opts, 0, sizeof opts); /* every option not set here off (mass_grade_off 0) */
    opts.cells = cells;
    opts.inputs = RFE_INPUTS_ALL;
    return rfe_sensor_log_read_opts(path, &opts, log, err);
}

int rfe_sensor_log_read_stream_cells(FILE *f, const char *name, rfe_cells_t cells,
                                     rfe_sensor_log_t *log, rfe_io_error_t *err)
{
    rfe_read_opts_t opts;
    memset(&opts, 0, sizeof opts); /* every option not set here off (mass_grade_off 0) */
    opts.cells = cells;
    opts.inputs = RFE_INPUTS_ALL;
    return rfe_sensor_log_read_stream_opts(f, name, &opts, log, err);
}

int rfe_sensor_log_read_opts(const char *path, const rfe_read_opts_t *opts,
                             rfe_sensor_log_t *log, rfe_io_error_t *err)
{
    FILE *f;
    int rc;
    memset(log, 0, sizeof *log);
    f = fopen(path, "r");
    if (f == NULL) {
        rfe_io_error_set(err, path, 0u, 0u, "cannot open: %s", strerror(errno));
        return -1;
    }
    rc = rfe_sensor_log_read_stream_opts(f, path, opts, log, err);
    (void)fclose(f); /* read-only: nothing to lose on close */
    return rc;
}

int rfe_sensor_log_read_stream_opts(FILE *f, const char *name, const rfe_read_opts_t *opts,
                                    rfe_sensor_log_t *log, rfe_io_error_t *err)
{
    reader_t r;
    int rc;
    memset(&r, 0, sizeof r);
    memset(log, 0, sizeof *log);
    r.opts = *opts;
    r.f = f;
    r.name = name;
    r.err = err;
    rc = read_preamble(&r, log);
    if (rc == 0) {
        rc = parse_header(&r, log);
    }
    if (rc == 0) {
        rc = read_rows(&r, log);
    }
    free(r.buf);
    free(r.field_col);
    free(r.fields);
    if (rc != 0) {
        rfe_sensor_log_free(log);
    }
    return rc;
}

void rfe_sensor_log_free(rfe_sensor_log_t *log)
{
    size_t i;
    for (i = 0u; i < log->n_meta; ++i) {
        free(log->meta[i].key);
        free(log->meta[i].value);
    }
    free(log->meta);
    free(log->rows);
    memset(log, 0, sizeof *log);
}

rfe_sensor_log_t rfe_sensor_log_shape(const rfe_sensor_log_t *log)
{
    rfe_sensor_log_t shape = *log;
    shape.rows = NULL;
    shape.n_rows = 0u;
    shape.meta = NULL;
    shape.n_meta = 0u;
    return shape;
}

int rfe_sensor_log_wheel_radius(rfe_sensor_log_t *log, double R)
{
    size_t i;
    size_t w;
    if (!(isfinite(R) && (R > 0.0))) {
        return -1;
    }
    if (log->omega_linear == 0) {
        return 0;
    }
    for (i = 0u; i < log->n_rows; ++i) {
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            log->rows[i].omega[w] /= R;
        }
    }
    log->omega_linear = 0;
    return 0;
}

int rfe_sensor_log_steer_ratio(rfe_sensor_log_t *log, double ratio)
{
    size_t i;
    if (!(isfinite(ratio) && (ratio > 0.0))) {
        return -1;
    }
    for (i = 0u; (log->has_swa != 0) && (i < log->n_rows); ++i) {
        log->rows[i].delta = log->rows[i].swa / ratio;
    }
    log->has_swa = 0;
    return 0;
}

const char *rfe_sensor_log_meta(const rfe_sensor_log_t *log, const char *key)
{
    const char *v = NULL;
    size_t i;
    for (i = 0u; i < log->n_meta; ++i) {
        if (strcmp(log->meta[i].key, key) == 0) {
            v = log->meta[i].value;
        }
    }
    return v;
}

/* Reads the next line into r->buf. 1 = line, 0 = end of file, -1 = error (reported). */
static int next_line(reader_t *r)
{
    int rc = rfe_text_read_line(r->f, &r->buf, &r->cap, &r->len);
    if (rc == 1) {
        ++r->line;
        /* A UTF-8 byte-order mark (spreadsheet export) is not part of the first name. */
        if ((r->line == 1u) && (strncmp(r->buf, "\xEF\xBB\xBF", 3u) == 0)) {
            memmove(r->buf, r->buf + 3, r->len - 2u);
            r->len -= 3u;
        }
        return 1;
    }
    if (rc == 0) {
        return 0;
    }
    if (rc == -2) {
        rfe_io_error_set(r->err, r->name, r->line + 1u, 0u,
                         "line contains a NUL byte (not a text CSV file?)");
    } else {
        rfe_io_error_set(r->err, r->name, r->line + 1u, 0u, "read error: %s", strerror(errno));
    }
    return -1;
}

/* Metadata and blank lines up to the header; leaves the header line in r->buf. */
static int read_preamble(reader_t *r, rfe_sensor_log_t *log)
{
    for (;;) {
        int rc = next_line(r);
        const char *s;
        if (rc <= 0) {
            if (rc == 0) {
                rfe_io_error_set(r->err, r->name, 0u, 0u,
                                 (r->line == 0u) ? "empty file (no header row)" : "no header row");
            }
            return -1;
        }
        s = r->buf + strspn(r->buf, " \t");
        if (*s == '\0') {
            continue;
        }
        if (*s != '#') {
            r->header_line = r->line;
            return 0;
        }
        add_meta(r, log);
    }
}

/* Stores a `# key = value` line; a '#' line without '=' is a plain comment. */
static void add_meta(reader_t *r, rfe_sensor_log_t *log)
{
    char *body = strchr(r->buf, '#') + 1;
    char *eq = strchr(body, '=');
    char *key;
    rfe_meta_entry_t *e;
    if (eq == NULL) {
        return;
    }
    *eq = '\0';
    key = rfe_text_trim(body);
    if (*key == '\0') {
        return; /* "# = x" names nothing */
    }
    log->meta = grow(log->meta, &r->meta_cap, sizeof *log->meta, log->n_meta + 1u);
    e = &log->meta[log->n_meta++];
    e->key = rfe_xstrdup(key);
    e->value = rfe_xstrdup(rfe_text_trim(eq + 1));
    e->line = r->line;
}

/* Splits at commas in place; returns the number of fields (may exceed max, then only the
 * first max are stored). */
static size_t split_fields(char *line, char **fields, size_t max)
{
    size_t n = 0u;
    char *p = line;
    for (;;) {
        char *comma = strchr(p, ',');
        if (comma != NULL) {
            *comma = '\0';
        }
        if (n < max) {
            fields[n] = rfe_text_trim(p);
        }
        ++n;
        if (comma == NULL) {
            return n;
        }
        p = comma + 1;
    }
}

static int parse_header(reader_t *r, rfe_sensor_log_t *log)
{
    size_t n = 1u;
    size_t k;
    const char *p;
    for (p = r->buf; *p != '\0'; ++p) {
        n += (*p == ',') ? 1u : 0u;
    }
    r->n_fields = n;
    r->field_col = rfe_xrealloc(NULL, n, sizeof *r->field_col);
    r->fields = rfe_xrealloc(NULL, n, sizeof *r->fields);
    (void)split_fields(r->buf, r->fields, n);
    if (check_column_meta(r, log) != 0) {
        return -1;
    }
    for (k = 0u; k < N_COLS; ++k) {
        if (column_meta(r, log, k) != 0) {
            return -1;
        }
    }
    if (map_header_fields(r, n) != 0) {
        return -1;
    }
    return check_columns(r, log);
}

/** Metadata prefixes that describe a column (DATA.md "Units, scales and names"). */
static const char *const k_col_prefix[] = {"unit_", "scale_", "offset_", "column_"};
#define N_COL_PREFIX (sizeof k_col_prefix / sizeof k_col_prefix[0])

/* Index of the column named @p name in k_cols, or NO_COL. */
static size_t find_col(const char *name)
{
    size_t k;
    for (k = 0u; k < N_COLS; ++k) {
        if (strcmp(k_cols[k].name, name) == 0) {
            return k;
        }
    }
    return NO_COL;
}

/* Every unit_X, scale_X, offset_X, column_X key names a column of k_cols: a typo
 * ("unit_yawrate") would otherwise leave a column in the wrong unit without a word. */
static int check_column_meta(reader_t *r, const rfe_sensor_log_t *log)
{
    char q[QUOTE_MAX + 4u];
    size_t i;
    size_t j;
    for (i = 0u; i < log->n_meta; ++i) {
        const char *key = log->meta[i].key;
        for (j = 0u; j < N_COL_PREFIX; ++j) {
            const size_t len = strlen(k_col_prefix[j]);
            if ((strncmp(key, k_col_prefix[j], len) == 0) && (find_col(key + len) == NO_COL)) {
                rfe_text_quote(q, sizeof q, key, QUOTE_MAX);
                rfe_io_error_set(r->err, r->name, log->meta[i].line, 0u,
                                 "metadata '%s': '%s' is not a sensor-log column (DATA.md)", q,
                                 key + len);
                return -1;
            }
        }
    }
    return 0;
}

/* Line of metadata @p key (the last one, the one rfe_sensor_log_meta returns), 0 if none. */
static size_t meta_line(const rfe_sensor_log_t *log, const char *key)
{
    size_t line = 0u;
    size_t i;
    for (i = 0u; i < log->n_meta; ++i) {
        line = (strcmp(log->meta[i].key, key) == 0) ? log->meta[i].line : line;
    }
    return line;
}

/* Metadata @p key as a finite number into @p v (untouched when absent); -1 if malformed. */
static int meta_number(reader_t *r, const rfe_sensor_log_t *log, const char *key, double *v)
{
    char q[QUOTE_MAX + 4u];
    const char *text = rfe_sensor_log_meta(log, key);
    rfe_num_status_t st;
    if (text == NULL) {
        return 0;
    }
    st = rfe_text_parse_double(text, v);
    if (st == RFE_NUM_OK) {
        return 0;
    }
    rfe_text_quote(q, sizeof q, text, QUOTE_MAX);
    rfe_io_error_set(r->err, r->name, meta_line(log, key), 0u, "metadata '%s': %s: '%s'", key,
                     rfe_num_status_str(st), q);
    return -1;
}

/* Column k's header name and its conversion to SI from unit_, scale_, offset_, column_
 * metadata: SI = factor(unit) * (scale * text + offset). Wheel speeds given as a speed
 * (km/h) are kept in m/s and flagged (log->omega_linear) for rfe_sensor_log_wheel_radius. */
static int column_meta(reader_t *r, rfe_sensor_log_t *log, size_t k)
{
    char key[64];
    char q[QUOTE_MAX + 4u];
    const col_spec_t *c = &k_cols[k];
    const char *unit;
    const char *alias;
    double factor = 1.0;
    double scale = 1.0;
    double offset = 0.0;
    int linear = 0;
    (void)snprintf(key, sizeof key, "column_%s", c->name);
    alias = rfe_sensor_log_meta(log, key);
    r->want[k] = ((alias != NULL) && (alias[0] != '\0')) ? alias : c->name;
    (void)snprintf(key, sizeof key, "unit_%s", c->name);
    unit = rfe_sensor_log_meta(log, key);
    if ((unit != NULL) && (rfe_unit_factor(c->dim, unit, &factor, &linear) != 0)) {
        rfe_text_quote(q, sizeof q, unit, QUOTE_MAX);
        rfe_io_error_set(r->err, r->name, meta_line(log, key), 0u,
                         "metadata '%s': '%s' is not a unit of column '%s' (one of: %s)", key, q,
                         c->name, rfe_unit_words(c->dim));
        return -1;
    }
    (void)snprintf(key, sizeof key, "scale_%s", c->name);
    if (meta_number(r, log, key, &scale) != 0) {
        return -1;
    }
    if (scale == 0.0) {
        rfe_io_error_set(r->err, r->name, meta_line(log, key), 0u,
                         "metadata '%s': a scale of 0 erases the column", key);
        return -1;
    }
    (void)snprintf(key, sizeof key, "offset_%s", c->name);
    if (meta_number(r, log, key, &offset) != 0) {
        return -1;
    }
    r->col_a[k] = factor * scale;
    r->col_b[k] = factor * offset;
    if (c->dim == RFE_DIM_WHEEL) {
        if ((k != find_col("omega_fl")) && (linear != log->omega_linear)) {
            rfe_io_error_set(r->err, r->name, r->header_line, 0u,
                             "metadata: the wheel speeds mix spin (rad/s, rpm) and "
                             "circumferential (km/h, m/s) units; give all four in one kind");
            return -1;
        }
        log->omega_linear = linear;
    }
    return 0;
}

/* Names -> k_cols indices; rejects empty and duplicate names. */
static int map_header_fields(reader_t *r, size_t n)
{
    char q[QUOTE_MAX + 4u];
    size_t j;
    size_t k;
    for (j = 0u; j < n; ++j) {
        r->field_col[j] = NO_COL;
        if (r->fields[j][0] == '\0') {
            rfe_io_error_set(r->err, r->name, r->line, j + 1u, "empty column name in header");
            return -1;
        }
        for (k = 0u; k < j; ++k) {
            if (strcmp(r->fields[k], r->fields[j]) == 0) {
                rfe_text_quote(q, sizeof q, r->fields[j], QUOTE_MAX);
                rfe_io_error_set(r->err, r->name, r->line, j + 1u,
                                 "duplicate column '%s' (also column %zu)", q, k + 1u);
                return -1;
            }
        }
        for (k = 0u; k < N_COLS; ++k) {
            if (strcmp(r->want[k], r->fields[j]) == 0) {
                if (r->field_col[j] != NO_COL) {
                    rfe_text_quote(q, sizeof q, r->fields[j], QUOTE_MAX);
                    rfe_io_error_set(r->err, r->name, r->line, j + 1u,
                                     "column '%s' is named for both '%s' and '%s' (column_ "
                                     "metadata)", q, k_cols[r->field_col[j]].name, k_cols[k].name);
                    return -1;
                }
                r->field_col[j] = k;
                r->t_field = (k == 0u) ? j : r->t_field; /* k_cols[0] is t */
            }
        }
    }
    return 0;
}

/* The word of each optional group in messages ("velocity column 'vy' missing"). */
static const char *const k_group_word[COL_KINDS] = {"", "truth", "truth", "velocity",
                                                    "pressure", "torque", "grade", "", "", ""};

/* Appends @p s to the message list; what does not fit is cut to "..." (then *used = cap). */
static void list_add(char *list, size_t cap, size_t *used, const char *s)
{
    const size_t n = strlen(s);
    if (*used >= cap) {
        return;
    }
    if (*used + n + 4u > cap) { /* room for "..." and the NUL */
        (void)snprintf(list + *used, cap - *used, "...");
        *used = cap;
        return;
    }
    memcpy(list + *used, s, n + 1u);
    *used += n;
}

/* Whether column @p k must be in the header: a required input; delta, standing for the
 * steering pair, when neither delta nor swa is; a member of an optional group (each all or
 * none) of which some column is there; of the velocity group, when the run measures
 * velocities (RFE_INPUTS_MEASURED). */
static int col_needed(const reader_t *r, size_t k, const size_t *n_present)
{
    const col_kind_t g = k_cols[k].kind;
    if (g == COL_STEER) {
        return (n_present[COL_STEER] == 0u) && (k_cols[k].offset == ROW_OFF(delta));
    }
    if ((g == COL_MG) || (g == COL_MG_TRUTH)) {
        return 0; /* each optional on its own */
    }
    return (g == COL_INPUT) || (n_present[g] != 0u) ||
           ((g == COL_VEL) && (r->opts.inputs == RFE_INPUTS_MEASURED));
}

/* The rule a missing member of group @p g breaks (groups: "give all of ... or none"). */
static const char *group_rule(const reader_t *r, col_kind_t g)
{
    static const char *const rule[COL_KINDS] = {
        "", "give all of mu_fl, mu_fr, mu_rl, mu_rr or none",
        "give all of util_fl, util_fr, util_rl, util_rr or none",
        "give all of vx, vy, yaw_acc or none", "give all of p_fl, p_fr, p_rl, p_rr or none",
        "give all of torque_fl, torque_fr, torque_rl, torque_rr or none", "", "", "", ""};
    return ((g == COL_VEL) && (r->opts.inputs == RFE_INPUTS_MEASURED))
               ? "measured velocities need all of vx, vy, yaw_acc"
               : rule[g];
}

/* One missing column as the message names it: 'name', its column_ alias when the metadata
 * gave one, the steering pair's choice, and after the last missing member of an optional
 * group the group's rule (@p rule; NULL: none). */
static void missing_item(const reader_t *r, size_t k, const char *rule, char *item, size_t cap)
{
    int w;
    if (k_cols[k].kind == COL_STEER) {
        (void)snprintf(item, cap, "'delta' (the road-wheel angle) or 'swa' (the steering-wheel "
                                  "angle, with obs_steer_ratio)");
        return;
    }
    w = (r->want[k] != k_cols[k].name)
            ? snprintf(item, cap, "'%s' (named '%s' by its column_%s metadata)", k_cols[k].name,
                       r->want[k], k_cols[k].name)
            : snprintf(item, cap, "'%s'", k_cols[k].name);
    if ((rule != NULL) && (w > 0) && ((size_t)w < cap)) {
        (void)snprintf(item + w, cap - (size_t)w, " (%s: %s)", k_group_word[k_cols[k].kind], rule);
    }
}

/* Every column the header lacks, of every rule (required inputs, the steering angle, the
 * optional groups given in part, the velocities a measuring run needs), all in one message
 * in k_cols' order (DATA.md's table); 0 when none. The message of one group given in part
 * alone is "<group> column(s) ... missing (<rule>)". Measured velocities asked for and none
 * given, alone: 0 (has_velocity stays 0 and the caller says why it needs them). */
static int missing_columns(reader_t *r, const size_t *present, const size_t *n_present)
{
    char list[RFE_IO_MSG_MAX - 64u]; /* room for the words around it */
    char item[RFE_IO_MSG_MAX];
    size_t last[COL_KINDS];
    size_t used = 0u;
    size_t n = 0u;
    size_t n_kinds = 0u;
    col_kind_t g1 = COL_INPUT;
    int one_group;
    size_t k;
    for (k = 0u; k < (size_t)COL_KINDS; ++k) {
        last[k] = NO_COL;
    }
    for (k = 0u; k < N_COLS; ++k) {
        const col_kind_t g = k_cols[k].kind;
        if ((present[k] == 0u) && col_needed(r, k, n_present)) {
            n_kinds += (last[g] == NO_COL) ? 1u : 0u;
            g1 = (n == 0u) ? g : g1;
            last[g] = k;
            ++n;
        }
    }
    if ((n == 0u) || ((n_kinds == 1u) && (g1 == COL_VEL) && (n_present[COL_VEL] == 0u))) {
        return 0;
    }
    /* one optional group given in part, and nothing else: that group's own message */
    one_group = (n_kinds == 1u) && (g1 != COL_INPUT) && (g1 != COL_STEER);
    list[0] = '\0';
    for (k = 0u; k < N_COLS; ++k) {
        const col_kind_t g = k_cols[k].kind;
        if ((present[k] == 0u) && col_needed(r, k, n_present)) {
            const int rule = !one_group && (g != COL_INPUT) && (g != COL_STEER) && (last[g] == k);
            missing_item(r, k, rule ? group_rule(r, g) : NULL, item, sizeof item);
            list_add(list, sizeof list, &used, (used > 0u) ? ", " : "");
            list_add(list, sizeof list, &used, item);
        }
    }
    if (one_group) {
        rfe_io_error_set(r->err, r->name, r->line, 0u, "%s column%s %s missing (%s)", k_group_word[g1],
                         (n > 1u) ? "s" : "", list, group_rule(r, g1));
    } else {
        rfe_io_error_set(r->err, r->name, r->line, 0u, "missing column%s %s", (n > 1u) ? "s" : "",
                         list);
    }
    return -1;
}

/* The optional inputs a measuring run does not use that a log has, by has_pressure
 * + 2 has_torque + 4 has_grade (rfe_sensor_log_t.unused_cols). */
static const char *const k_esc_cols[8] = {NULL,          "p_*",           "torque_*",
                                          "p_*, torque_*", "grade",       "p_*, grade",
                                          "torque_*, grade", "p_*, torque_*, grade"};

/* The input columns the run does not use (rfe_inputs_t), once the groups given are known;
 * unused_cols names those of them the log has. */
static void mark_unused(reader_t *r, rfe_sensor_log_t *log)
{
    const rfe_inputs_t in = (r->opts.inputs != RFE_INPUTS_AUTO)
                                ? r->opts.inputs
                                : (log->has_velocity ? RFE_INPUTS_MEASURED : RFE_INPUTS_OBSERVER);
    size_t k;
    for (k = 0u; k < N_COLS; ++k) {
        const col_kind_t g = k_cols[k].kind;
        r->unused[k] = (unsigned char)(((in == RFE_INPUTS_OBSERVER) && (g == COL_VEL)) ||
                                       ((in == RFE_INPUTS_MEASURED) &&
                                        ((g == COL_PRES) || (g == COL_TORQ) || (g == COL_GRADE))));
    }
    log->unused_cols =
        ((in == RFE_INPUTS_OBSERVER) && log->has_velocity)
            ? "vx, vy, yaw_acc"
            : ((in == RFE_INPUTS_MEASURED)
                   ? k_esc_cols[(log->has_pressure ? 1 : 0) + (log->has_torque ? 2 : 0) +
                                (log->has_grade ? 4 : 0)]
                   : NULL);
}

/* The mass and grade estimator's columns are read only when the log has drive_torque and the
 * run does not turn the estimator off: else they are extra columns, neither parsed nor
 * counted, so such a log reads exactly as before they existed. Sets the has_* flags. */
static void mass_grade_columns(reader_t *r, rfe_sensor_log_t *log, size_t *present)
{
    const int given = present[find_col("drive_torque")] != 0u;
    const int on = given && (r->opts.mass_grade_off == 0);
    size_t j;
    for (j = 0u; j < r->n_fields; ++j) {
        const size_t k = r->field_col[j];
        if ((k != NO_COL) && ((k_cols[k].kind == COL_MG) || (k_cols[k].kind == COL_MG_TRUTH)) &&
            !on) {
            r->field_col[j] = NO_COL;
            present[k] = 0u;
        }
    }
    log->has_drive_torque = on ? 1 : 0;
    log->drive_torque_ignored = (given && !on) ? 1 : 0;
    log->has_brake = (present[find_col("brake")] != 0u) ? 1 : 0;
    log->has_brake_pressure = (present[find_col("brake_pressure")] != 0u) ? 1 : 0;
    log->has_gear = (present[find_col("gear")] != 0u) ? 1 : 0;
    log->has_mass_true = (present[find_col("mass_true")] != 0u) ? 1 : 0;
    log->has_grade_true = (present[find_col("grade_true")] != 0u) ? 1 : 0;
}

/* Every needed column present (missing_columns), not both delta and swa; the groups given. */
static int check_columns(reader_t *r, rfe_sensor_log_t *log)
{
    size_t present[N_COLS] = {0u};
    size_t n_present[COL_KINDS] = {0u};
    size_t j;
    size_t k;
    for (j = 0u; j < r->n_fields; ++j) {
        if (r->field_col[j] != NO_COL) {
            present[r->field_col[j]] = 1u;
        }
    }
    mass_grade_columns(r, log, present);
    for (k = 0u; k < N_COLS; ++k) {
        n_present[k_cols[k].kind] += present[k];
    }
    if (missing_columns(r, present, n_present) != 0) {
        return -1;
    }
    if (n_present[COL_STEER] > 1u) {
        rfe_io_error_set(r->err, r->name, r->line, 0u, "%s",
                         "both 'delta' and 'swa' given: keep one steering angle");
        return -1;
    }
    log->has_truth = (n_present[COL_MU] != 0u) ? 1 : 0;
    log->has_util = (n_present[COL_UTIL] != 0u) ? 1 : 0;
    log->has_velocity = (n_present[COL_VEL] != 0u) ? 1 : 0;
    log->has_pressure = (n_present[COL_PRES] != 0u) ? 1 : 0;
    log->has_torque = (n_present[COL_TORQ] != 0u) ? 1 : 0;
    log->has_grade = (n_present[COL_GRADE] != 0u) ? 1 : 0;
    log->has_swa = present[find_col("swa")] != 0u ? 1 : 0;
    mark_unused(r, log);
    return 0;
}

/* Data rows to the end. A blank line is tolerated only at the end of the file. */
static int read_rows(reader_t *r, rfe_sensor_log_t *log)
{
    size_t blank_line = 0u;
    int rc;
    while ((rc = next_line(r)) == 1) {
        const char *s = r->buf + strspn(r->buf, " \t");
        if (*s == '\0') {
            blank_line = (blank_line == 0u) ? r->line : blank_line;
            continue;
        }
        if (blank_line != 0u) {
            rfe_io_error_set(r->err, r->name, blank_line, 0u, "empty line between data rows");
            return -1;
        }
        if (*s == '#') {
            rfe_io_error_set(r->err, r->name, r->line, 0u,
                             "'#' line after the header (metadata must come before it)");
            return -1;
        }
        if (parse_row(r, log) != 0) {
            return -1;
        }
    }
    if (rc < 0) {
        return -1;
    }
    if (log->n_rows == 0u) {
        rfe_io_error_set(r->err, r->name, r->header_line, 0u, "no data rows after the header");
        return -1;
    }
    return 0;
}

/* A bad cell (parse status @p st, or RFE_NUM_OK for a value that left the doubles in SI
 * units) of column @p c: kept as NaN / +-Inf in *v when the reader keeps bad cells and the
 * column is an estimator input (not t, not truth); returns its cause, or -1 (an error).
 * *v holds the cell's own value (nan, inf, -inf as written; +-Inf beyond the doubles). */
static int keep_cell(const reader_t *r, const col_spec_t *c, rfe_num_status_t st, double *v)
{
    const int input = (c->kind != COL_MU) && (c->kind != COL_UTIL) && (c->kind != COL_MG_TRUTH) &&
                      (c->offset != ROW_OFF(t));
    if ((r->opts.cells != RFE_CELLS_KEEP) || !input || (st == RFE_NUM_SYNTAX)) {
        return -1;
    }
    if (st == RFE_NUM_EMPTY) {
        *v = (double)NAN;
        return (int)RFE_CELL_EMPTY;
    }
    return (st == RFE_NUM_NONFINITE) ? (int)RFE_CELL_NONFINITE : (int)RFE_CELL_RANGE;
}

/* Counts a kept bad cell of @p cause at field @p j of the current line into row and log. */
static void count_bad_cell(const reader_t *r, rfe_sensor_log_t *log, rfe_sensor_row_t *row,
                           int cause, size_t j)
{
    if (row->bad == 0u) {
        ++log->bad_rows;
    }
    if (log->bad_first_line == 0u) {
        log->bad_first_line = r->line;
        log->bad_first_col = j + 1u;
    }
    row->bad |= 1u << (unsigned)cause;
    ++log->bad_cells[cause];
}

/* Counts a kept bad cell at field @p j of a column the run does not use: apart, so that it
 * rejects no row (its value, NaN / +-Inf, reaches no estimator). */
static void count_ignored_cell(const reader_t *r, rfe_sensor_log_t *log, size_t j)
{
    if (log->bad_ignored_first_line == 0u) {
        log->bad_ignored_first_line = r->line;
        log->bad_ignored_first_col = j + 1u;
    }
    ++log->bad_ignored;
}

/* Field @p j of the current row into @p row: @p v as read (parse status @p st; the cell's own
 * value when it is not finite), converted to SI; a bad cell kept and counted, or an error
 * quoting @p text. The one rule for a cell, whether it came as text or as a double. */
static int store_cell(reader_t *r, rfe_sensor_log_t *log, rfe_sensor_row_t *row, size_t j,
                      rfe_num_status_t st, double v, const char *text)
{
    char q[QUOTE_MAX + 4u];
    const col_spec_t *c = &k_cols[r->field_col[j]];
    if (st == RFE_NUM_OK) {
        v = r->col_a[r->field_col[j]] * v + r->col_b[r->field_col[j]];
    }
    if ((st != RFE_NUM_OK) || !isfinite(v)) {
        const int cause = keep_cell(r, c, st, &v);
        if (cause < 0) {
            r->bad_cell = (st != RFE_NUM_SYNTAX) ? 1 : 0;
            rfe_text_quote(q, sizeof q, text, QUOTE_MAX);
            if (st != RFE_NUM_OK) {
                rfe_io_error_set(r->err, r->name, r->line, j + 1u, "column '%s': %s: '%s'",
                                 c->name, rfe_num_status_str(st), q);
            } else {
                rfe_io_error_set(r->err, r->name, r->line, j + 1u,
                                 "column '%s': out of range in SI units: '%s'", c->name, q);
            }
            return -1;
        }
        if (r->unused[r->field_col[j]] != 0u) {
            count_ignored_cell(r, log, j);
        } else {
            count_bad_cell(r, log, row, cause, j);
        }
    }
    memcpy((char *)row + c->offset, &v, sizeof v);
    return 0;
}

/* Appends @p row, its time after the last row's. */
static int append_row(reader_t *r, rfe_sensor_log_t *log, const rfe_sensor_row_t *row)
{
    if ((log->n_rows > 0u) && !(row->t > log->rows[log->n_rows - 1u].t)) {
        rfe_io_error_set(r->err, r->name, r->line, r->t_field + 1u,
                         "column 't': time not increasing (%.17g after %.17g)", row->t,
                         log->rows[log->n_rows - 1u].t);
        return -1;
    }
    log->rows = grow(log->rows, &r->rows_cap, sizeof *row, log->n_rows + 1u);
    log->rows[log->n_rows++] = *row;
    return 0;
}

/* One data row: field count, every needed field a finite number (or a kept bad cell), time
 * increasing. */
static int parse_row(reader_t *r, rfe_sensor_log_t *log)
{
    rfe_sensor_row_t row;
    size_t n = split_fields(r->buf, r->fields, r->n_fields);
    size_t j;
    memset(&row, 0, sizeof row);
    if (n != r->n_fields) {
        /* COL = the first field that is missing or extra. */
        rfe_io_error_set(r->err, r->name, r->line, ((n < r->n_fields) ? n : r->n_fields) + 1u,
                         "wrong column count: %zu fields, header has %zu", n, r->n_fields);
        return -1;
    }
    for (j = 0u; j < n; ++j) {
        double v = 0.0;
        rfe_num_status_t st;
        if (r->field_col[j] == NO_COL) {
            continue; /* extra columns are ignored, not parsed */
        }
        st = rfe_text_parse_double(r->fields[j], &v);
        if ((st == RFE_NUM_NONFINITE) || (st == RFE_NUM_OVERFLOW)) {
            /* the text's own value: nan, inf, -inf (the grammar check let only those words
             * by), or +-HUGE_VAL, the infinity of the written sign */
            v = strtod(r->fields[j], NULL);
        }
        if (store_cell(r, log, &row, j, st, v, r->fields[j]) != 0) {
            return -1;
        }
    }
    return append_row(r, log, &row);
}

/* ------------------------------------------------------- from columns in memory */

/* The metadata pairs as the reader keeps `# key = value` lines (trimmed copies; "line" the
 * pair's index, 1-based). */
static void columns_meta(rfe_sensor_log_t *log, reader_t *r, const rfe_kv_t *meta, size_t n)
{
    size_t i;
    for (i = 0u; i < n; ++i) {
        char *key = rfe_xstrdup(meta[i].key);
        char *value = rfe_xstrdup(meta[i].value);
        const char *k = rfe_text_trim(key);
        if (*k != '\0') {
            rfe_meta_entry_t *e;
            log->meta = grow(log->meta, &r->meta_cap, sizeof *log->meta, log->n_meta + 1u);
            e = &log->meta[log->n_meta++];
            e->key = rfe_xstrdup(k);
            e->value = rfe_xstrdup(rfe_text_trim(value));
            e->line = i + 1u;
        }
        free(key);
        free(value);
    }
}

/* The rows of the columns: row i's cells as a text row's, "line" i + 1. A column without
 * values (not numbers) that names an input is an error, as text that is no number. */
static int columns_rows(reader_t *r, rfe_sensor_log_t *log, const rfe_column_t *cols,
                        size_t n_rows)
{
    size_t i;
    size_t j;
    for (i = 0u; i < n_rows; ++i) {
        rfe_sensor_row_t row;
        memset(&row, 0, sizeof row);
        r->line = i + 1u;
        for (j = 0u; j < r->n_fields; ++j) {
            char text[RFE_NUM_BUF];
            const double x = (cols[j].values != NULL) ? cols[j].values[i] : (double)NAN;
            const rfe_num_status_t st = (cols[j].values == NULL) ? RFE_NUM_SYNTAX
                                        : isfinite(x)             ? RFE_NUM_OK
                                                                  : RFE_NUM_NONFINITE;
            if (r->field_col[j] == NO_COL) {
                continue; /* extra columns are ignored */
            }
            rfe_text_format_double(text, x);
            if (store_cell(r, log, &row, j, st, x, (cols[j].values != NULL) ? text : "(not a number)") != 0) {
                return -1;
            }
        }
        if (append_row(r, log, &row) != 0) {
            return -1;
        }
    }
    if (n_rows == 0u) {
        rfe_io_error_set(r->err, r->name, 0u, 0u, "no data rows");
        return -1;
    }
    return 0;
}

int rfe_sensor_log_from_columns(const char *name, const rfe_kv_t *meta, size_t n_meta,
                                const rfe_column_t *cols, size_t n_cols, size_t n_rows,
                                const rfe_read_opts_t *opts, rfe_sensor_log_t *log,
                                rfe_io_error_t *err)
{
    reader_t r;
    int rc = 0;
    size_t j;
    if ((name == NULL) || ((meta == NULL) && (n_meta > 0u)) || (cols == NULL) ||
        (opts == NULL) || (log == NULL) || (err == NULL)) {
        return -1;
    }
    memset(&r, 0, sizeof r);
    memset(log, 0, sizeof *log);
    r.opts = *opts;
    r.name = name;
    r.err = err;
    columns_meta(log, &r, meta, n_meta);
    r.n_fields = n_cols;
    r.field_col = rfe_xrealloc(NULL, n_cols + 1u, sizeof *r.field_col);
    r.fields = rfe_xrealloc(NULL, n_cols + 1u, sizeof *r.fields);
    for (j = 0u; j < n_cols; ++j) {
        r.fields[j] = rfe_xstrdup((cols[j].name != NULL) ? cols[j].name : "");
    }
    rc = check_column_meta(&r, log);
    for (j = 0u; (rc == 0) && (j < N_COLS); ++j) {
        rc = column_meta(&r, log, j);
    }
    if (rc == 0) {
        rc = map_header_fields(&r, n_cols);
    }
    if (rc == 0) {
        rc = check_columns(&r, log);
    }
    if (rc == 0) {
        rc = columns_rows(&r, log, cols, n_rows);
    }
    for (j = 0u; j < n_cols; ++j) {
        free(r.fields[j]);
    }
    free(r.field_col);
    free(r.fields);
    if (rc != 0) {
        rfe_sensor_log_free(log);
    }
    return ((rc != 0) && (r.bad_cell != 0)) ? (int)RFE_ERR_NONFINITE : rc;
}

/* Room for @p need elements, doubling the capacity (amortised O(1) appends). */
static void *grow(void *arr, size_t *cap, size_t elem, size_t need)
{
    if (need <= *cap) {
        return arr;
    }
    /* need is at most *cap + 1; 2 * *cap cannot wrap: *cap * elem bytes already exist. */
    *cap = (*cap < 16u) ? 16u : 2u * *cap;
    return rfe_xrealloc(arr, *cap, elem);
}

/* ---------------------------------------------------------------- writing */

static const char *const k_est_header =
    "t,mu_fl,mu_fr,mu_rl,mu_rr,sd_fl,sd_fr,sd_rl,sd_rr,valid_fl,valid_fr,valid_rl,valid_rr,status";
/* The velocity observer's columns, written when it ran (DATA.md "Estimate log"). */
static const char *const k_est_velocity_header =
    ",vx_est,vy_est,beta_est,yaw_acc_est,sd_vx,sd_vy,sd_beta";
/* The mass and grade estimator's columns, written when it ran (DATA.md "Estimate log"). */
static const char *const k_est_mass_grade_header = ",mass_est,sd_mass,grade_est,sd_grade,mg_status,mass_used,grade_walk,mg_mismatch";
/* The tyre identifier's columns, written when it ran (DATA.md "Estimate log"; names fixed by
 * issue 20). */
static const char *const k_est_tyre_id_header =
    ",mu_id_f,mu_id_r,sd_mu_id_f,sd_mu_id_r,B_f,C_f,D_f,E_f,B_r,C_r,D_r,E_r,tid_status,tid_flags";
/* The friction estimator's lateral curve, written when the identified one is fed. */
static const char *const k_est_tyre_feed_header = ",cy_used,shape_Cy_used,shape_Ey_used,r_model_rel_used";

/* Metadata value on one line: control characters (a newline in a file name) become '?'. */
static void write_sanitised(FILE *f, const char *s)
{
    for (; *s != '\0'; ++s) {
        fputc(((unsigned char)*s < 0x20u) ? '?' : *s, f);
    }
}

int rfe_estimate_log_write_stream(FILE *f, const rfe_kv_t *meta, size_t n_meta,
                                  const rfe_est_row_t *rows, size_t n_rows, rfe_numfmt_t fmt)
{
    void (*format)(char *, double) =
        (fmt == RFE_NUMFMT_FLOAT) ? rfe_text_format_float : rfe_text_format_double;
    char num[RFE_NUM_BUF];
    size_t i;
    size_t w;
    for (i = 0u; i < n_meta; ++i) {
        fputs("# ", f);
        write_sanitised(f, meta[i].key);
        fputs(" = ", f);
        write_sanitised(f, meta[i].value);
        fputc('\n', f);
    }
    fprintf(f, "%s%s%s%s%s\n", k_est_header,
            ((n_rows > 0u) && (rows[0].has_velocity != 0)) ? k_est_velocity_header : "",
            ((n_rows > 0u) && (rows[0].has_mass_grade != 0)) ? k_est_mass_grade_header : "",
            ((n_rows > 0u) && (rows[0].has_tyre_id != 0)) ? k_est_tyre_id_header : "",
            ((n_rows > 0u) && (rows[0].has_tyre_feed != 0)) ? k_est_tyre_feed_header : "");
    for (i = 0u; i < n_rows; ++i) {
        const rfe_est_row_t *e = &rows[i];
        /* t is the input time, copied exactly whatever the run precision. */
        rfe_text_format_double(num, e->t);
        fputs(num, f);
        for (w = 0u; w < RFE_WHEELS; ++w) {
            format(num, e->mu[w]);
            fprintf(f, ",%s", num);
        }
        for (w = 0u; w < RFE_WHEELS; ++w) {
            format(num, e->sd[w]);
            fprintf(f, ",%s", num);
        }
        for (w = 0u; w < RFE_WHEELS; ++w) {
            fprintf(f, ",%u", (unsigned)e->valid[w]);
        }
        fprintf(f, ",%d", e->status);
        if (rows[0].has_velocity != 0) {
            const double v[7] = {e->vx, e->vy, e->beta, e->yaw_acc, e->sd_vx, e->sd_vy, e->sd_beta};
            for (w = 0u; w < 7u; ++w) {
                format(num, v[w]);
                fprintf(f, ",%s", num);
            }
        }
        if (rows[0].has_mass_grade != 0) {
            const double m[4] = {e->mass, e->sd_mass, e->grade, e->sd_grade};
            for (w = 0u; w < 4u; ++w) {
                format(num, m[w]);
                fprintf(f, ",%s", num);
            }
            fprintf(f, ",%d", e->mg_status);
            format(num, e->mass_used);
            fprintf(f, ",%s,%d,%d", num, e->grade_walk, e->mg_mismatch);
        }
        if (rows[0].has_tyre_id != 0) {
            const double v[12] = {e->mu_id[0], e->mu_id[1], e->sd_mu_id[0], e->sd_mu_id[1],
                                  e->mf_B[0],  e->mf_C[0],  e->mf_D[0],     e->mf_E[0],
                                  e->mf_B[1],  e->mf_C[1],  e->mf_D[1],     e->mf_E[1]};
            for (w = 0u; w < 12u; ++w) {
                format(num, v[w]);
                fprintf(f, ",%s", num);
            }
            fprintf(f, ",%d,%u", e->tid_status, e->tid_flags);
        }
        if (rows[0].has_tyre_feed != 0) {
            const double c[4] = {e->cy_used, e->shape_Cy_used, e->shape_Ey_used, e->r_model_rel_used};
            for (w = 0u; w < 4u; ++w) {
                format(num, c[w]);
                fprintf(f, ",%s", num);
            }
        }
        fputc('\n', f);
    }
    return ferror(f) ? -1 : 0;
}

int rfe_estimate_log_write(const char *path, const rfe_kv_t *meta, size_t n_meta,
                           const rfe_est_row_t *rows, size_t n_rows, rfe_numfmt_t fmt,
                           rfe_io_error_t *err)
{
    FILE *f = fopen(path, "w");
    int rc;
    if (f == NULL) {
        rfe_io_error_set(err, path, 0u, 0u, "cannot open for writing: %s", strerror(errno));
        return -1;
    }
    rc = rfe_estimate_log_write_stream(f, meta, n_meta, rows, n_rows, fmt);
    errno = 0;
    /* fclose flushes: a full disk shows up here, not in fprintf. */
    if ((fclose(f) != 0) || (rc != 0)) {
        rfe_io_error_set(err, path, 0u, 0u, "write failed: %s",
                         (errno != 0) ? strerror(errno) : "I/O error");
        return -1;
    }
    return 0;
}
