/**
 * @file param_file.c
 * @brief Parameter set as doubles: key table, parameter files, sensor-log metadata (the
 *        preset values come from the library, see replay_real.c).
 *
 * Everything is driven by the RFE_PARAM_KEYS table in param_file.h, plus the three word keys
 * (tyre, filter, structure) appended here.
 */
#include "param_file.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/** Longest piece of file text quoted in a message. */
#define QUOTE_MAX 40u

static const rfe_param_info_t k_info[RFE_PK_COUNT] = {
#define RFE_PK_INFO_(key, member, unit, doc) {#key, unit, doc},
    RFE_PARAM_KEYS(RFE_PK_INFO_)
    {"tyre", "-", "tyre model: paper (normalised Dugoff), absolute (load-scaled Dugoff) or magic (load-scaled Magic Formula)"},
    {"filter", "-", "filter: sckf (square-root cubature) or ckf (full covariance)"},
    {"structure", "-", "state: wheels (four independent mu) or sides (mu_left, mu_right)"},
    {"obs_driven", "-", "driven wheels, a bit mask fl 1, fr 2, rl 4, rr 8 (3 front, 12 rear, 15 all)"},
    {"obs_lat_every", "-", "the lateral model's rows every obs_lat_every-th step (an integer 1 .. 8; 8 by default, 1 every step)"},
    RFE_OBS_KEYS(RFE_PK_INFO_)
    {"mg_adaptive", "-", "mass and grade: 1 the seed's adaptive UKF (AUKF), 0 the plain UKF"},
    {"mg_use_ax", "-", "mass and grade: 1 the accelerometer row, 0 speed and torque only"},
    {"mg_feed_sd_rel", "1", "replay: feed mass_est to the friction estimator after an update with sd_mass <= this * mass_est (0 = never)"},
    {"mg_feed_excitation", "m/s", "replay: feed mass_est only once the sum of |ax| dt over the estimator's updates with |ax| >= mg_feed_ax_min since its start reaches this (0 = no gate)"},
    {"mg_feed_ax_min", "m/s^2", "replay: the smallest |ax| counted by mg_feed_excitation"},
    {"mg_feed_slip_max", "1", "replay: an update whose |v_wheels - vx| / max(|vx|, mg_v_min) exceeds this is not fed and empties the excitation sum (0 = no slip hold)"},
    {"mg_feed_band", "1", "replay: feed mass_est only when |mass_est - m| <= this * m; refusals counted (0 = no band)"},
    RFE_MG_KEYS(RFE_PK_INFO_)
    {"tid_filter", "-", "tyre identifier: apf (the auxiliary particle filter), sir (the bootstrap filter) or sckf (the augmented-state sigma-point filter)"},
    {"tid_resample", "-", "tyre identifier: how parents are drawn, multinomial or systematic"},
    {"tid_substeps", "-", "tyre identifier: RK4 steps per sample period (an integer)"},
    {"tid_seed", "-", "tyre identifier: seed of its random stream (an integer 0 .. 2^53)"},
    {"tid_feed_sd_rel", "1", "replay: feed the identified lateral curve to the friction estimator after an update with sd(K) <= this * K (0 = never)"},
    {"tid_feed_evidence", "s", "replay: feed only once the friction estimator has spent this long (summed) at a mu bound or in model mismatch (0 = from the start)"},
    {"tid_feed_ax_max", "m/s^2", "replay: feed no curve after a sample whose |ax| exceeds this, braking or driving (0 = no hold)"},
    {"tid_feed_refresh", "s", "replay: after a held or implausible sample feed no curve until the identifier has updated on this long of untainted samples with |ay| >= tid_feed_outlier_k * tid_sd_ay, then first at a sample with |ay| below it (0 = off)"},
    {"tid_feed_outlier_k", "1", "replay: with tid_feed_refresh > 0, a sample whose |ay| is more than this * tid_sd_ay from the identifier's last estimate is implausible; the first resets the estimator's r_model_rel (0 = no test)"},
    RFE_TID_KEYS(RFE_PK_INFO_)
#undef RFE_PK_INFO_
};

static const char *const k_tyre_words[] = {"paper", "absolute", "magic"}; /* rfe_tyre_mode_t order */
static const char *const k_filter_words[] = {"sckf", "ckf"};         /* rfe_filter_kind_t order */
static const char *const k_structure_words[] = {"wheels", "sides"};  /* rfe_structure_t order */
static const char *const k_preset_words[] = {"default", "paper"};    /* rfe_preset_t order */
static const char *const k_tid_filter_words[] = {"apf", "sir", "sckf"}; /* rfe_tid_filter_t order */
static const char *const k_tid_resample_words[] = {"multinomial", "systematic"}; /* rfe_tid_resample_t */

static int word_index(const char *s, const char *const *words, size_t n);
static int takes_word(size_t k);
static rfe_num_status_t tid_word(rfe_param_set_t *ps, size_t k, const char *value);
static int apply_line(rfe_param_set_t *ps, char *line, const char *name, size_t line_no,
                      size_t first_seen[RFE_PK_COUNT], rfe_io_error_t *err);
static int report_unknown_key(const char *key, const char *name, size_t line_no, size_t col,
                              rfe_io_error_t *err);

const rfe_param_info_t *rfe_param_info(size_t k)
{
    return (k < (size_t)RFE_PK_COUNT) ? &k_info[k] : NULL;
}

size_t rfe_param_find(const char *name)
{
    size_t k;
    for (k = 0u; k < (size_t)RFE_PK_COUNT; ++k) {
        if (strcmp(k_info[k].key, name) == 0) {
            return k;
        }
    }
    return RFE_PK_NONE;
}

void rfe_param_format(const rfe_param_set_t *ps, size_t k, char buf[RFE_NUM_BUF])
{
    if (k < RFE_PK_NUMERIC) {
        rfe_text_format_double(buf, ps->value[k]);
    } else if (rfe_param_is_obs(k) != 0) {
        rfe_text_format_double(buf, ps->obs[k - RFE_PK_OBS_FIRST]);
    } else if (rfe_param_is_mg(k) != 0) {
        rfe_text_format_double(buf, ps->mg[k - RFE_PK_MG_FIRST]);
    } else if (k == (size_t)RFE_PK_tid_filter) {
        (void)snprintf(buf, RFE_NUM_BUF, "%s",
                       rfe_tid_filter_str((rfe_tid_filter_t)ps->tid[k - RFE_PK_TID_FIRST]));
    } else if (k == (size_t)RFE_PK_tid_resample) {
        (void)snprintf(buf, RFE_NUM_BUF, "%s",
                       rfe_tid_resample_str((rfe_tid_resample_t)ps->tid[k - RFE_PK_TID_FIRST]));
    } else if (rfe_param_is_tid(k) != 0) {
        rfe_text_format_double(buf, ps->tid[k - RFE_PK_TID_FIRST]);
    } else {
        const char *w = (k == (size_t)RFE_PK_TYRE)     ? rfe_tyre_mode_str(ps->tyre)
                        : (k == (size_t)RFE_PK_FILTER) ? rfe_filter_kind_str(ps->filter)
                                                       : rfe_structure_str(ps->structure);
        (void)snprintf(buf, RFE_NUM_BUF, "%s", w);
    }
}

rfe_num_status_t rfe_param_set_text(rfe_param_set_t *ps, size_t k, const char *value)
{
    double v = 0.0;
    rfe_num_status_t st;
    if (k == (size_t)RFE_PK_TYRE) {
        return (rfe_tyre_mode_parse(value, &ps->tyre) == 0) ? RFE_NUM_OK : RFE_NUM_SYNTAX;
    }
    if (k == (size_t)RFE_PK_FILTER) {
        return (rfe_filter_kind_parse(value, &ps->filter) == 0) ? RFE_NUM_OK : RFE_NUM_SYNTAX;
    }
    if (k == (size_t)RFE_PK_STRUCTURE) {
        return (rfe_structure_parse(value, &ps->structure) == 0) ? RFE_NUM_OK : RFE_NUM_SYNTAX;
    }
    if (rfe_param_is_tid_word(k) != 0) {
        return tid_word(ps, k, value);
    }
    if ((k >= (size_t)RFE_PK_COUNT) || (rfe_param_is_word(k) != 0)) {
        return RFE_NUM_SYNTAX;
    }
    st = rfe_text_parse_double(value, &v);
    if ((st == RFE_NUM_OK) && (k < RFE_PK_NUMERIC)) {
        ps->value[k] = v;
    } else if ((st == RFE_NUM_OK) && (rfe_param_is_obs(k) != 0)) {
        ps->obs[k - RFE_PK_OBS_FIRST] = v;
    } else if ((st == RFE_NUM_OK) && (rfe_param_is_mg(k) != 0)) {
        ps->mg[k - RFE_PK_MG_FIRST] = v;
    } else if (st == RFE_NUM_OK) {
        ps->tid[k - RFE_PK_TID_FIRST] = v;
    } else {
        /* st names what is wrong with the text */
    }
    return st;
}

/* 1 when key @p k takes a word, not a number: tyre, filter, structure, tid_filter,
 * tid_resample. */
static int takes_word(size_t k)
{
    return (rfe_param_is_word(k) != 0) || (rfe_param_is_tid_word(k) != 0);
}

/* tid_filter or tid_resample from its word, stored as the enum's value. */
static rfe_num_status_t tid_word(rfe_param_set_t *ps, size_t k, const char *value)
{
    rfe_tid_filter_t f;
    rfe_tid_resample_t r;
    double *slot = &ps->tid[k - RFE_PK_TID_FIRST];
    if (k == (size_t)RFE_PK_tid_filter) {
        if (rfe_tid_filter_parse(value, &f) != 0) {
            return RFE_NUM_SYNTAX;
        }
        *slot = (double)f;
    } else {
        if (rfe_tid_resample_parse(value, &r) != 0) {
            return RFE_NUM_SYNTAX;
        }
        *slot = (double)r;
    }
    return RFE_NUM_OK;
}

/* ------------------------------------------------------------ parameter files */

int rfe_param_set_apply_file(rfe_param_set_t *ps, const char *path, rfe_io_error_t *err)
{
    FILE *f = fopen(path, "r");
    int rc;
    if (f == NULL) {
        rfe_io_error_set(err, path, 0u, 0u, "cannot open: %s", strerror(errno));
        return -1;
    }
    rc = rfe_param_set_apply_stream(ps, f, path, err);
    (void)fclose(f); /* read-only */
    return rc;
}

int rfe_param_set_apply_stream(rfe_param_set_t *ps, FILE *f, const char *name,
                               rfe_io_error_t *err)
{
    size_t first_seen[RFE_PK_COUNT] = {0u}; /* line where each key was set, to catch repeats */
    char *buf = NULL;
    size_t cap = 0u;
    size_t len = 0u;
    size_t line_no = 0u;
    int rc;
    while ((rc = rfe_text_read_line(f, &buf, &cap, &len)) == 1) {
        ++line_no;
        if (apply_line(ps, buf, name, line_no, first_seen, err) != 0) {
            free(buf);
            return -1;
        }
    }
    free(buf);
    if (rc == -2) {
        rfe_io_error_set(err, name, line_no + 1u, 0u, "line contains a NUL byte");
        return -1;
    }
    if (rc < 0) {
        rfe_io_error_set(err, name, line_no + 1u, 0u, "read error: %s", strerror(errno));
        return -1;
    }
    return 0;
}

/* One `key = value` line (comments already possible anywhere after '#'). */
static int apply_line(rfe_param_set_t *ps, char *line, const char *name, size_t line_no,
                      size_t first_seen[RFE_PK_COUNT], rfe_io_error_t *err)
{
    char q[QUOTE_MAX + 4u];
    char *hash = strchr(line, '#');
    char *body;
    char *eq;
    char *key;
    char *value;
    size_t k;
    rfe_num_status_t st;
    if (hash != NULL) {
        *hash = '\0';
    }
    body = rfe_text_trim(line);
    if (*body == '\0') {
        return 0;
    }
    eq = strchr(body, '=');
    if (eq == NULL) {
        rfe_text_quote(q, sizeof q, body, QUOTE_MAX);
        rfe_io_error_set(err, name, line_no, (size_t)(body - line) + 1u,
                         "expected 'key = value', got '%s'", q);
        return -1;
    }
    *eq = '\0';
    key = rfe_text_trim(body);
    value = rfe_text_trim(eq + 1);
    if (*key == '\0') {
        rfe_io_error_set(err, name, line_no, (size_t)(eq - line) + 1u, "missing key before '='");
        return -1;
    }
    k = rfe_param_find(key);
    if (k == RFE_PK_NONE) {
        return report_unknown_key(key, name, line_no, (size_t)(key - line) + 1u, err);
    }
    if (first_seen[k] != 0u) {
        rfe_io_error_set(err, name, line_no, (size_t)(key - line) + 1u,
                         "parameter '%s' given twice (first at line %zu)", k_info[k].key,
                         first_seen[k]);
        return -1;
    }
    st = rfe_param_set_text(ps, k, value);
    if (st != RFE_NUM_OK) {
        rfe_text_quote(q, sizeof q, value, QUOTE_MAX);
        rfe_io_error_set(err, name, line_no, (size_t)(value - line) + 1u, "value of '%s': %s: '%s'",
                         k_info[k].key,
                         takes_word(k) ? "not one of the allowed words"
                                               : rfe_num_status_str(st),
                         q);
        return -1;
    }
    first_seen[k] = line_no;
    ps->origin[k].file = name;
    ps->origin[k].line = line_no;
    return 0;
}

/* Unknown keys are errors in a parameter file; a case-only typo gets a hint. */
static int report_unknown_key(const char *key, const char *name, size_t line_no, size_t col,
                              rfe_io_error_t *err)
{
    char q[QUOTE_MAX + 4u];
    size_t k;
    rfe_text_quote(q, sizeof q, key, QUOTE_MAX);
    for (k = 0u; k < (size_t)RFE_PK_COUNT; ++k) {
        if (strcasecmp(k_info[k].key, key) == 0) {
            rfe_io_error_set(err, name, line_no, col, "unknown parameter key '%s' (did you mean '%s'?)",
                             q, k_info[k].key);
            return -1;
        }
    }
    rfe_io_error_set(err, name, line_no, col, "unknown parameter key '%s'", q);
    return -1;
}

/* ------------------------------------------------------------ log metadata */

int rfe_param_set_apply_meta(rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                             const char *log_name, rfe_io_error_t *err)
{
    char q[QUOTE_MAX + 4u];
    size_t i;
    for (i = 0u; i < log->n_meta; ++i) {
        const rfe_meta_entry_t *e = &log->meta[i];
        size_t k = rfe_param_find(e->key);
        rfe_num_status_t st;
        if (k == RFE_PK_NONE) {
            continue; /* scenario, seed, noise_*: information, not parameters */
        }
        st = rfe_param_set_text(ps, k, e->value);
        if (st != RFE_NUM_OK) {
            rfe_text_quote(q, sizeof q, e->value, QUOTE_MAX);
            rfe_io_error_set(err, log_name, e->line, 0u, "metadata '%s': %s: '%s'", e->key,
                             takes_word(k) ? "not one of the allowed words"
                                                   : rfe_num_status_str(st),
                             q);
            return -1;
        }
        ps->origin[k].file = log_name;
        ps->origin[k].line = e->line;
    }
    return 0;
}

/* ------------------------------------------------------------ word keys */

static int word_index(const char *s, const char *const *words, size_t n)
{
    size_t i;
    for (i = 0u; i < n; ++i) {
        if (strcmp(s, words[i]) == 0) {
            return (int)i;
        }
    }
    return -1;
}

const char *rfe_tyre_mode_str(rfe_tyre_mode_t m)
{
    return ((unsigned)m < 3u) ? k_tyre_words[m] : "?";
}

const char *rfe_filter_kind_str(rfe_filter_kind_t k)
{
    return ((unsigned)k < 2u) ? k_filter_words[k] : "?";
}

int rfe_tyre_mode_parse(const char *s, rfe_tyre_mode_t *out)
{
    int i = word_index(s, k_tyre_words, 3u);
    if (i < 0) {
        return -1;
    }
    {
        static const rfe_tyre_mode_t modes[] = {RFE_TYRE_PAPER, RFE_TYRE_ABSOLUTE, RFE_TYRE_MAGIC};
        *out = modes[i];
    }
    return 0;
}

int rfe_filter_kind_parse(const char *s, rfe_filter_kind_t *out)
{
    int i = word_index(s, k_filter_words, 2u);
    if (i < 0) {
        return -1;
    }
    *out = (i == 0) ? RFE_FILTER_SCKF : RFE_FILTER_CKF;
    return 0;
}

const char *rfe_structure_str(rfe_structure_t s)
{
    return ((unsigned)s < 2u) ? k_structure_words[s] : "?";
}

int rfe_structure_parse(const char *s, rfe_structure_t *out)
{
    int i = word_index(s, k_structure_words, 2u);
    if (i < 0) {
        return -1;
    }
    *out = (i == 0) ? RFE_STRUCT_WHEELS : RFE_STRUCT_SIDES;
    return 0;
}

const char *rfe_preset_str(rfe_preset_t p)
{
    return ((unsigned)p < 2u) ? k_preset_words[p] : "?";
}

int rfe_preset_parse(const char *s, rfe_preset_t *out)
{
    int i = word_index(s, k_preset_words, 2u);
    if (i < 0) {
        return -1;
    }
    *out = (i == 0) ? RFE_PRESET_DEFAULT : RFE_PRESET_PAPER;
    return 0;
}

const char *rfe_tid_filter_str(rfe_tid_filter_t f)
{
    return ((unsigned)f < 3u) ? k_tid_filter_words[f] : "?";
}

const char *rfe_tid_resample_str(rfe_tid_resample_t r)
{
    return ((unsigned)r < 2u) ? k_tid_resample_words[r] : "?";
}

int rfe_tid_filter_parse(const char *s, rfe_tid_filter_t *out)
{
    int i = word_index(s, k_tid_filter_words, 3u);
    if (i < 0) {
        return -1;
    }
    *out = (i == 0) ? RFE_TID_APF : ((i == 1) ? RFE_TID_SIR : RFE_TID_SCKF);
    return 0;
}

int rfe_tid_resample_parse(const char *s, rfe_tid_resample_t *out)
{
    int i = word_index(s, k_tid_resample_words, 2u);
    if (i < 0) {
        return -1;
    }
    *out = (i == 0) ? RFE_TID_MULTINOMIAL : RFE_TID_SYSTEMATIC;
    return 0;
}
