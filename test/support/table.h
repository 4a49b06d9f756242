/**
 * @file table.h
 * @brief Test support: a whole numeric CSV (test vectors, golden estimate logs) in memory,
 *        columns looked up by name. Non-numeric fields (e.g. a case label) read as NaN.
 */
#ifndef RFE_TEST_TABLE_H
#define RFE_TEST_TABLE_H

#include <stddef.h>

typedef struct {
    char **names;     /**< column names */
    size_t n_cols;
    double *values;   /**< row-major n_rows x n_cols */
    size_t n_rows;
} test_table_t;

/** Loads @p path ('#' lines before the header are skipped). Returns 0 or -1 (message on stderr). */
int test_table_load(const char *path, test_table_t *t);

/** Index of column @p name, or -1. */
int test_table_col(const test_table_t *t, const char *name);

/** Value at (row, column name); aborts the test program if the column does not exist. */
double test_table_get(const test_table_t *t, size_t row, const char *name);

void test_table_free(test_table_t *t);

#endif /* RFE_TEST_TABLE_H */
