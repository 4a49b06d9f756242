/**
 * @file test_replay_mem.c
 * @brief Tests of the in-memory replay (replay_mem.h: rfe_mu_replay_open in mu_replay.c,
 *        rfe_replay_mem_feed): columns in memory against mu_replay's own main on the file
 *        (rfe_mu_replay_main, main renamed as the Python package builds it), in float,
 *        double and q31; blocks of rows against one block; the error codes.
 *
 * The expected values come from the file path: the CSV reader, the CLI's set-up and the
 * estimate-log writer (doubles as their shortest round-trip text, read back with strtod by
 * test_table: exact), so every comparison is exact. A float run's log holds %.9g text, which
 * rounds back to the same float: compared as floats.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "replay_mem.h"
#include "table.h"
#include "test_light.h"

int rfe_mu_replay_main(int argc, char **argv);

#define DATA "test/host/data/"
#define MAX_COLS 40u

/** A sensor log's columns in memory, column-major, from test_table (its own parser). */
typedef struct {
    test_table_t t;
    double *values; /**< n_cols x n_rows */
    rfe_column_t cols[MAX_COLS];
} mem_cols_t;

static void mem_cols_load(const char *path, mem_cols_t *m)
{
    size_t i;
    size_t j;
    assert_int_equal(test_table_load(path, &m->t), 0);
    assert_true(m->t.n_cols <= MAX_COLS);
    m->values = calloc(m->t.n_cols * m->t.n_rows + 1u, sizeof *m->values);
    assert_non_null(m->values);
    for (j = 0u; j < m->t.n_cols; ++j) {
        for (i = 0u; i < m->t.n_rows; ++i) {
            m->values[j * m->t.n_rows + i] = m->t.values[i * m->t.n_cols + j];
        }
        m->cols[j].name = m->t.names[j];
        m->cols[j].values = &m->values[j * m->t.n_rows];
    }
}

static void mem_cols_free(mem_cols_t *m)
{
    free(m->values);
    test_table_free(&m->t);
}

/* mu_replay ARGS --in PATH --out a temporary file: its estimate log as a table. */
static void cli_estimates(const char *path, const char *real, const char *extra,
                          test_table_t *est)
{
    char out[] = "test_replay_mem_XXXXXX";
    const int fd = mkstemp(out);
    char *argv[12];
    int argc = 0;
    assert_true(fd >= 0);
    (void)close(fd);
    argv[argc++] = "mu_replay";
    argv[argc++] = "--in";
    argv[argc++] = (char *)(uintptr_t)path;
    argv[argc++] = "--out";
    argv[argc++] = out;
    argv[argc++] = "--real";
    argv[argc++] = (char *)(uintptr_t)real;
    argv[argc++] = "--quiet";
    if (extra != NULL) {
        argv[argc++] = (char *)(uintptr_t)extra;
    }
    argv[argc] = NULL;
    assert_int_equal(rfe_mu_replay_main(argc, argv), 0);
    assert_int_equal(test_table_load(out, est), 0);
    (void)unlink(out);
}

/* A run in memory of @p m's columns (with @p meta) as `mu_replay --real REAL [EXTRA]`,
 * its rows fed in blocks of @p block; the output rows (RFE_MEM_COLS each) into @p out. */
static int mem_run(const mem_cols_t *m, const rfe_kv_t *meta, size_t n_meta, const char *real,
                   const char *extra, size_t block, double *out, rfe_replay_mem_t *mem,
                   void **state, rfe_io_error_t *err)
{
    char *argv[10];
    int argc = 0;
    int rc;
    size_t i;
    const int r = (strcmp(real, "q31") == 0) ? (int)RFE_MEM_Q31
                  : (strcmp(real, "double") == 0) ? (int)RFE_MEM_DOUBLE : (int)RFE_MEM_FLOAT;
    *state = calloc(1u, rfe_replay_mem_state_size(r) + 1u);
    assert_non_null(*state);
    argv[argc++] = "mu_replay";
    argv[argc++] = "--in";
    argv[argc++] = "memory";
    argv[argc++] = "--out";
    argv[argc++] = "-";
    argv[argc++] = "--real";
    argv[argc++] = (char *)(uintptr_t)real;
    if (extra != NULL) {
        argv[argc++] = (char *)(uintptr_t)extra;
    }
    argv[argc] = NULL;
    rc = rfe_mu_replay_open(mem, argc, argv, NULL, meta, n_meta, m->cols, m->t.n_cols,
                            m->t.n_rows, *state, err);
    for (i = 0u; (rc == 0) && (i < m->t.n_rows); i += block) {
        rfe_column_t cols[MAX_COLS];
        const size_t n = (m->t.n_rows - i < block) ? m->t.n_rows - i : block;
        size_t j;
        for (j = 0u; j < m->t.n_cols; ++j) {
            cols[j].name = m->cols[j].name;
            cols[j].values = m->cols[j].values + i;
        }
        rc = rfe_replay_mem_feed(mem, meta, n_meta, cols, m->t.n_cols, n, out + i * RFE_MEM_COLS,
                                 err);
    }
    return rc;
}

/* Every column of the CLI's estimate log equals the in-memory value of the same name. */
static void assert_equals_cli(const test_table_t *est, const double *out, int is_float)
{
    size_t i;
    size_t j;
    size_t k;
    for (j = 0u; j < est->n_cols; ++j) {
        for (k = 0u; (k < RFE_MEM_COLS) && (rfe_replay_mem_col(k) != NULL); ++k) {
            if (strcmp(rfe_replay_mem_col(k), est->names[j]) == 0) {
                break;
            }
        }
        assert_non_null(rfe_replay_mem_col(k));
        for (i = 0u; i < est->n_rows; ++i) {
            const double want = est->values[i * est->n_cols + j];
            const double got = out[i * RFE_MEM_COLS + k];
            if (is_float && (k > 0u)) { /* t is the input's double in every run */
                assert_true((float)got == (float)want);
                assert_true((double)(float)got == got);
            } else {
                assert_memory_equal(&got, &want, sizeof got);
            }
        }
    }
}

/* The columns of a measuring log and of an observer log with brake pressures, run in memory
 * in float, double and q31, equal mu_replay's estimate log of the file; fed in blocks of 2
 * rows they equal one block. REQ-CLI-003 */
static void test_rfe_replay_mem_equals_mu_replay(void **state)
{
    static const char *const logs[2] = {DATA "good_small.csv", DATA "good_esc.csv"};
    static const char *const reals[3] = {"float", "double", "q31"};
    /* the metadata of the two files, as its own `# key = value` lines give it */
    static const rfe_kv_t meta_small[3] = {{"scenario", "unit_test"}, {"mu0", "0.6"},
                                           {"tyre", "absolute"}};
    static const rfe_kv_t meta_esc[1] = {{"dt", "0.01"}};
    size_t l;
    size_t r;
    (void)state;
    for (l = 0u; l < 2u; ++l) {
        mem_cols_t m;
        mem_cols_load(logs[l], &m);
        for (r = 0u; r < 3u; ++r) {
            test_table_t est;
            rfe_replay_mem_t mem;
            rfe_replay_mem_t mem2;
            rfe_io_error_t err;
            rfe_replay_q31_stats_t st;
            void *s1;
            void *s2;
            double *out = calloc(m.t.n_rows * RFE_MEM_COLS, sizeof *out);
            double *out2 = calloc(m.t.n_rows * RFE_MEM_COLS, sizeof *out2);
            const rfe_kv_t *meta = (l == 0u) ? meta_small : meta_esc;
            const size_t n_meta = (l == 0u) ? 3u : 1u;
            assert_non_null(out);
            assert_non_null(out2);
            cli_estimates(logs[l], reals[r], NULL, &est);
            assert_int_equal(mem_run(&m, meta, n_meta, reals[r], NULL, m.t.n_rows, out, &mem,
                                     &s1, &err), 0);
            assert_int_equal(est.n_rows, m.t.n_rows);
            assert_equals_cli(&est, out, r == 0u);
            assert_int_equal(mem.observer, (l == 1u) ? 1 : 0);
            assert_int_equal(rfe_replay_mem_stats(&mem, &st), 0);
            assert_int_equal(st.base.n_steps, m.t.n_rows);
            assert_int_equal(mem_run(&m, meta, n_meta, reals[r], NULL, 2u, out2, &mem2, &s2,
                                     &err), 0);
            assert_memory_equal(out, out2, m.t.n_rows * RFE_MEM_COLS * sizeof *out);
            test_table_free(&est);
            free(out);
            free(out2);
            free(s1);
            free(s2);
        }
        mem_cols_free(&m);
    }
}

/* The codes: a usage error, an invalid parameter (status 19, the message naming where it came
 * from), --help, a malformed block, other columns, time not increasing, feeding an unopened
 * run, NULL arguments. REQ-CLI-003 */
static void test_rfe_replay_mem_errors(void **state)
{
    static const rfe_kv_t meta[1] = {{"dt", "0.01"}};
    static const rfe_kv_t bad_mu0[2] = {{"dt", "0.01"}, {"mu0", "-3"}};
    mem_cols_t m;
    rfe_replay_mem_t mem;
    rfe_replay_q31_stats_t st;
    rfe_io_error_t err;
    double out[4 * RFE_MEM_COLS];
    void *s;
    /* params_good.par: filter = ckf, which runs with the paper preset */
    char *argv[] = {"mu_replay", "--in", "memory", "--out", "-", "--params",
                    DATA "params_good.par", "--preset", "paper", NULL};
    (void)state;
    mem_cols_load(DATA "good_esc.csv", &m);
    assert_int_equal(mem_run(&m, meta, 1u, "q32", NULL, 4u, out, &mem, &s, &err), RFE_MEM_USAGE);
    assert_non_null(strstr(err.msg, "--real must be"));
    free(s);
    assert_int_equal(mem_run(&m, bad_mu0, 2u, "double", NULL, 4u, out, &mem, &s, &err),
                     RFE_ERR_PARAM);
    assert_non_null(strstr(err.msg, "invalid parameter mu0"));
    assert_int_equal(err.line, 2); /* the metadata pair, 1-based */
    assert_int_equal(rfe_replay_mem_feed(&mem, meta, 1u, m.cols, m.t.n_cols, 1u, out, &err),
                     RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_replay_mem_stats(&mem, &st), RFE_ERR_NOT_INITIALISED);
    free(s);
    assert_int_equal(mem_run(&m, meta, 1u, "double", "--help", 4u, out, &mem, &s, &err),
                     RFE_MEM_USAGE);
    free(s);
    assert_int_equal(mem_run(&m, meta, 1u, "double", NULL, 4u, out, &mem, &s, &err), 0);
    /* the same rows again: time not after the last row's; nothing stepped */
    assert_int_equal(rfe_replay_mem_feed(&mem, meta, 1u, m.cols, m.t.n_cols, 1u, out, &err),
                     RFE_MEM_INPUT);
    assert_non_null(strstr(err.msg, "time not increasing"));
    assert_int_equal(rfe_replay_mem_feed(&mem, meta, 1u, m.cols, m.t.n_cols - 4u, 1u, out, &err),
                     RFE_MEM_INPUT); /* without p_fl .. p_rr: other columns */
    assert_non_null(strstr(err.msg, "other columns"));
    assert_int_equal(rfe_replay_mem_feed(&mem, meta, 1u, m.cols, 1u, 1u, out, &err),
                     RFE_MEM_INPUT); /* t alone: missing columns */
    assert_int_equal(rfe_replay_mem_stats(&mem, &st), 0);
    assert_int_equal(st.base.n_steps, m.t.n_rows);
    assert_int_equal(rfe_replay_mem_feed(NULL, meta, 1u, m.cols, m.t.n_cols, 1u, out, &err),
                     RFE_ERR_NULL);
    assert_int_equal(rfe_replay_mem_stats(NULL, &st), RFE_ERR_NULL);
    assert_int_equal(rfe_mu_replay_open(&mem, 9, argv, NULL, meta, 1u, m.cols, m.t.n_cols,
                                        m.t.n_rows, NULL, &err), RFE_ERR_NULL);
    free(s);
    s = calloc(1u, rfe_replay_mem_state_size((int)RFE_MEM_FLOAT));
    assert_non_null(s);
    /* a parameter file and parameter text: the text after the file */
    assert_int_equal(rfe_mu_replay_open(&mem, 9, argv, "mu0 = 0.55\n", meta, 1u, m.cols,
                                        m.t.n_cols, m.t.n_rows, s, &err), 0);
    assert_true(mem.ps.value[RFE_PK_mu0] == 0.55);
    assert_int_equal(mem.dt_given, 1);
    assert_int_equal(rfe_mu_replay_open(&mem, 9, argv, "mu0 = x\n", meta, 1u, m.cols,
                                        m.t.n_cols, m.t.n_rows, s, &err), RFE_MEM_INPUT);
    assert_string_equal(err.file, "params");
    assert_int_equal(rfe_mu_replay_open(&mem, 9, argv, "", meta, 1u, m.cols, m.t.n_cols,
                                        m.t.n_rows, s, &err), 0); /* no lines: the file's */
    assert_true(mem.ps.value[RFE_PK_mu0] == 0.7);
    assert_int_equal(rfe_mu_replay_open(&mem, 9, argv, NULL, meta, 1u, m.cols, 1u, m.t.n_rows,
                                        s, &err), RFE_MEM_INPUT); /* t alone */
    assert_non_null(strstr(err.msg, "missing column"));
    assert_int_equal(rfe_replay_mem_state_size(3), 0);
    assert_null(rfe_replay_mem_col(RFE_MEM_COLS));
    free(s);
    mem_cols_free(&m);
}

/** A file's `# key = value` metadata (trimmed), as the reader keeps it. */
typedef struct {
    char text[64][2][256];
    rfe_kv_t kv[64];
    size_t n;
} mem_meta_t;

static char *trim_text(char *s)
{
    char *e = s + strlen(s);
    while ((*s == ' ') || (*s == '\t')) {
        ++s;
    }
    while ((e > s) && ((e[-1] == ' ') || (e[-1] == '\n') || (e[-1] == '\r'))) {
        *--e = '\0';
    }
    return s;
}

static void mem_meta_load(const char *path, mem_meta_t *m)
{
    char line[512];
    FILE *f = fopen(path, "r");
    assert_non_null(f);
    m->n = 0u;
    while ((fgets(line, sizeof line, f) != NULL) && (line[0] == '#')) {
        char *eq = strchr(line, '=');
        if (eq == NULL) {
            continue;
        }
        *eq = '\0';
        assert_true(m->n < 64u);
        (void)snprintf(m->text[m->n][0], 256, "%s", trim_text(line + 1));
        (void)snprintf(m->text[m->n][1], 256, "%s", trim_text(eq + 1));
        m->kv[m->n].key = m->text[m->n][0];
        m->kv[m->n].value = m->text[m->n][1];
        ++m->n;
    }
    (void)fclose(f);
}

/* A car logger's columns in its own units and names (km/h wheel speeds through R, the
 * steering-wheel angle: the observer) run in memory equal mu_replay on the file, in blocks
 * too. REQ-CLI-003 */
static void test_rfe_replay_mem_car_units_equal_mu_replay(void **state)
{
    static mem_meta_t meta;
    mem_cols_t m;
    test_table_t est;
    rfe_replay_mem_t mem;
    rfe_io_error_t err;
    void *s;
    double *out;
    (void)state;
    mem_cols_load(DATA "car_format_small.csv", &m);
    mem_meta_load(DATA "car_format_small.csv", &meta);
    out = calloc(m.t.n_rows * RFE_MEM_COLS, sizeof *out);
    assert_non_null(out);
    cli_estimates(DATA "car_format_small.csv", "double", NULL, &est);
    assert_int_equal(mem_run(&m, meta.kv, meta.n, "double", NULL, 3u, out, &mem, &s, &err), 0);
    assert_int_equal(mem.observer, 1);
    assert_equals_cli(&est, out, 0);
    test_table_free(&est);
    free(out);
    free(s);
    mem_cols_free(&m);
}

/* A measuring log's steering-wheel angle with its ratio (obs_steer_ratio = 2) runs as the
 * same log with delta = swa / 2 (both exact: a doubling and a halving). REQ-CLI-003 */
static void test_rfe_replay_mem_steer_ratio_as_delta(void **state)
{
    static const rfe_kv_t meta[3] = {{"mu0", "0.6"}, {"tyre", "absolute"}, {"dt", "0.01"}};
    static const rfe_kv_t meta_swa[4] = {{"mu0", "0.6"}, {"tyre", "absolute"}, {"dt", "0.01"},
                                         {"obs_steer_ratio", "2"}};
    mem_cols_t m;
    rfe_replay_mem_t mem;
    rfe_io_error_t err;
    void *s1;
    void *s2;
    size_t j;
    size_t i;
    double *a;
    double *b;
    (void)state;
    mem_cols_load(DATA "good_small.csv", &m);
    a = calloc(m.t.n_rows * RFE_MEM_COLS, sizeof *a);
    b = calloc(m.t.n_rows * RFE_MEM_COLS, sizeof *b);
    assert_non_null(a);
    assert_non_null(b);
    assert_int_equal(mem_run(&m, meta, 3u, "double", NULL, m.t.n_rows, a, &mem, &s1, &err), 0);
    for (j = 0u; strcmp(m.cols[j].name, "delta") != 0; ++j) {
    }
    m.cols[j].name = "swa";
    for (i = 0u; i < m.t.n_rows; ++i) {
        m.values[j * m.t.n_rows + i] *= 2.0;
    }
    assert_int_equal(mem_run(&m, meta_swa, 4u, "double", NULL, 2u, b, &mem, &s2, &err), 0);
    assert_int_equal(mem.observer, 0);
    assert_memory_equal(a, b, m.t.n_rows * RFE_MEM_COLS * sizeof *a);
    free(a);
    free(b);
    free(s1);
    free(s2);
    mem_cols_free(&m);
}

/* A copy of the log at @p path with its metadata, header and first @p n rows, in the file
 * @p tmpl (a mkstemp template, filled in); returns tmpl. */
static const char *log_prefix(const char *path, size_t n, char *tmpl)
{
    char line[1024];
    size_t rows = 0u;
    int header = 0;
    FILE *in = fopen(path, "r");
    const int fd = mkstemp(tmpl);
    FILE *out = (fd >= 0) ? fdopen(fd, "w") : NULL;
    assert_non_null(in);
    assert_non_null(out);
    while ((rows < n) && (fgets(line, sizeof line, in) != NULL)) {
        assert_non_null(strchr(line, '\n')); /* whole lines */
        if ((line[0] != '#') && header) {
            ++rows;
        }
        header |= (line[0] != '#') ? 1 : 0;
        assert_true(fputs(line, out) >= 0);
    }
    assert_int_equal(rows, n);
    (void)fclose(in);
    assert_int_equal(fclose(out), 0);
    return tmpl;
}

/* The tyre identifier in memory (--tyre-id=apf, a tyre identification log with its metadata,
 * in blocks): every column of mu_replay's estimate log, mu_id_f .. tid_flags included, equals
 * the in-memory value, in float and double; the run says it ran (no feed without
 * tid_feed_sd_rel). With --real q31 it is refused as mu_replay refuses it. REQ-CLI-008 */
static void test_rfe_replay_mem_tyre_id_equals_mu_replay(void **state)
{
    static const char *const full = "scenarios/tyre_id/tid_sine_steer.csv";
    char prefix[] = "test_replay_mem_tid_XXXXXX";
    /* light mode (under valgrind, ~45x slower): the log's first 200 of 1000 rows, which
     * resample from row 2 (test_replay.c's TID_LIGHT_ROWS) */
    const char *const log = rfe_test_light() ? log_prefix(full, 200u, prefix) : full;
    static const char *const reals[2] = {"float", "double"};
    static mem_meta_t meta;
    mem_cols_t m;
    rfe_replay_mem_t mem;
    rfe_io_error_t err;
    void *s;
    size_t r;
    size_t j;
    (void)state;
    mem_cols_load(log, &m);
    mem_meta_load(log, &meta);
    for (r = 0u; r < 2u; ++r) {
        test_table_t est;
        int has_mu_id = 0;
        double *out = calloc(m.t.n_rows * RFE_MEM_COLS, sizeof *out);
        assert_non_null(out);
        cli_estimates(log, reals[r], "--tyre-id=apf", &est);
        for (j = 0u; j < est.n_cols; ++j) {
            has_mu_id |= (strcmp(est.names[j], "mu_id_f") == 0) ? 1 : 0;
        }
        assert_true(has_mu_id);
        assert_int_equal(mem_run(&m, meta.kv, meta.n, reals[r], "--tyre-id=apf", 250u, out, &mem,
                                 &s, &err), 0);
        assert_int_equal(mem.tyre_id, 1);
        assert_int_equal(mem.tyre_feed, 0);
        assert_equals_cli(&est, out, r == 0u);
        test_table_free(&est);
        free(out);
        free(s);
    }
    {
        double out[RFE_MEM_COLS];
        assert_int_equal(mem_run(&m, meta.kv, meta.n, "q31", "--tyre-id=apf", 1u, out, &mem, &s,
                                 &err),
                         RFE_MEM_USAGE);
        free(s);
    }
    mem_cols_free(&m);
    if (log != full) {
        (void)unlink(prefix);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_replay_mem_equals_mu_replay),
        cmocka_unit_test(test_rfe_replay_mem_errors),
        cmocka_unit_test(test_rfe_replay_mem_car_units_equal_mu_replay),
        cmocka_unit_test(test_rfe_replay_mem_steer_ratio_as_delta),
        cmocka_unit_test(test_rfe_replay_mem_tyre_id_equals_mu_replay),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
