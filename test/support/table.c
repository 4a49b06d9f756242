/**
 * @file table.c
 * @brief Test support: numeric CSV tables (see table.h). Host-only, uses malloc.
 */
#include "table.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "text_io.h"

/* Splits line at commas in place; returns the number of fields (at most max). */
static size_t split(char *line, char **fields, size_t max)
{
    size_t n = 0;
    char *p = line;
    while (n < max) {
        char *c = strchr(p, ',');
        fields[n++] = rfe_text_trim(p);
        if (c == NULL) {
            break;
        }
        *c = '\0';
        p = c + 1;
    }
    return n;
}

int test_table_load(const char *path, test_table_t *t)
{
    enum { MAX_FIELDS = 256 };
    char *fields[MAX_FIELDS];
    char *buf = NULL;
    size_t cap = 0, len = 0, cap_rows = 0;
    int header_done = 0;
    FILE *f = fopen(path, "r");
    memset(t, 0, sizeof(*t));
    if (f == NULL) {
        fprintf(stderr, "table: cannot open %s\n", path);
        return -1;
    }
    while (rfe_text_read_line(f, &buf, &cap, &len) == 1) {
        size_t n, i;
        if (!header_done && (len == 0 || buf[0] == '#')) {
            continue;
        }
        if (len == 0) {
            continue;
        }
        n = split(buf, fields, MAX_FIELDS);
        if (!header_done) {
            t->n_cols = n;
            t->names = calloc(n, sizeof(char *));
            for (i = 0; i < n; ++i) {
                t->names[i] = malloc(strlen(fields[i]) + 1);
                strcpy(t->names[i], fields[i]);
            }
            header_done = 1;
            continue;
        }
        if (n != t->n_cols) {
            fprintf(stderr, "table: %s: row %zu has %zu fields, header %zu\n", path,
                    t->n_rows + 1, n, t->n_cols);
            fclose(f);
            free(buf);
            test_table_free(t);
            return -1;
        }
        if (t->n_rows == cap_rows) {
            cap_rows = cap_rows ? 2 * cap_rows : 1024;
            t->values = realloc(t->values, cap_rows * t->n_cols * sizeof(double));
        }
        for (i = 0; i < n; ++i) {
            double v;
            t->values[t->n_rows * t->n_cols + i] =
                (rfe_text_parse_double(fields[i], &v) == RFE_NUM_OK) ? v : NAN;
        }
        t->n_rows++;
    }
    free(buf);
    fclose(f);
    return header_done ? 0 : -1;
}

int test_table_col(const test_table_t *t, const char *name)
{
    size_t i;
    for (i = 0; i < t->n_cols; ++i) {
        if (strcmp(t->names[i], name) == 0) {
            return (int)i;
        }
    }
    return -1;
}

double test_table_get(const test_table_t *t, size_t row, const char *name)
{
    const int c = test_table_col(t, name);
    if (c < 0 || row >= t->n_rows) {
        fprintf(stderr, "table: no column '%s' or row %zu out of range\n", name, row);
        abort();
    }
    return t->values[row * t->n_cols + (size_t)c];
}

void test_table_free(test_table_t *t)
{
    size_t i;
    for (i = 0; i < t->n_cols; ++i) {
        free(t->names[i]);
    }
    free(t->names);
    free(t->values);
    memset(t, 0, sizeof(*t));
}
