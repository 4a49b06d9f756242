/**
 * @file csv_dir.h
 * @brief The golden tests' walk over a folder of CSV files: fn(name) for each *.csv in it.
 *        Include after test_common.h (cmocka).
 */
#ifndef RFE_TEST_CSV_DIR_H
#define RFE_TEST_CSV_DIR_H

#include <dirent.h>
#include <string.h>

/* Calls fn(name) for every file of dir whose name ends in ".csv" (in readdir's order);
 * returns how many. The folder must exist. */
static inline int test_each_csv(const char *dir, void (*fn)(const char *name))
{
    DIR *d = opendir(dir);
    struct dirent *e;
    int n = 0;
    assert_non_null(d);
    while ((e = readdir(d)) != NULL) {
        const size_t len = strlen(e->d_name);
        if ((len > 4u) && (strcmp(e->d_name + len - 4u, ".csv") == 0)) {
            fn(e->d_name);
            ++n;
        }
    }
    closedir(d);
    return n;
}

#endif /* RFE_TEST_CSV_DIR_H */
