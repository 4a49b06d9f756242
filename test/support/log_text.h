/**
 * @file log_text.h
 * @brief Host tests: a sensor log read from text through a temporary file (the same stream
 *        code as a real file), named "mem.csv" in messages.
 */
#ifndef RFE_TEST_LOG_TEXT_H
#define RFE_TEST_LOG_TEXT_H

#include <stdio.h>
#include <string.h>

#include "csv_log.h"

static inline int read_log_text(const char *text, rfe_sensor_log_t *log, rfe_io_error_t *err)
{
    FILE *f = tmpfile();
    int rc;
    assert_non_null(f);
    assert_int_equal(fwrite(text, 1u, strlen(text), f), strlen(text));
    rewind(f);
    rc = rfe_sensor_log_read_stream(f, "mem.csv", log, err);
    fclose(f);
    return rc;
}

#endif /* RFE_TEST_LOG_TEXT_H */
