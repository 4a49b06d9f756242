/**
 * @file text_io.h
 * @brief Host-only text helpers shared by the CSV and parameter readers: the one-line error
 *        record, line reading without length limits, strict decimal parsing, and number
 *        formatting that round-trips.
 *
 * Never linked into firmware (uses stdio and malloc).
 */
#ifndef RFE_HOST_TEXT_IO_H
#define RFE_HOST_TEXT_IO_H

#include <stddef.h>
#include <stdio.h>

#include "rfe/types.h"

/** Longest error message kept (the message is ours; file names are not copied): room for
 *  every missing column of a log, column_ aliases included (csv_log.c cuts a longer list
 *  with "..."). */
#define RFE_IO_MSG_MAX 1024

/**
 * Where and why reading failed. Printed as ONE line `FILE:LINE:COL: msg`; LINE and COL are
 * 1-based and 0 when they do not apply. In a CSV file COL is the field index, in a parameter
 * file the character position of the offending text.
 */
typedef struct {
    const char *file;           /**< name used in messages; not owned, must outlive the error */
    size_t line;                /**< 1-based line, 0 = the whole file */
    size_t col;                 /**< 1-based column, 0 = the whole line */
    char msg[RFE_IO_MSG_MAX];   /**< what is wrong, one line */
} rfe_io_error_t;

/** Fills @p err with a printf-style message. */
#if defined(__GNUC__)
__attribute__((format(printf, 5, 6)))
#endif
void rfe_io_error_set(rfe_io_error_t *err, const char *file, size_t line, size_t col,
                      const char *fmt, ...);

/** Prints `PROG: FILE:LINE:COL: msg` (or shorter when line/col are 0) as one line. */
void rfe_io_error_print(FILE *f, const char *prog, const rfe_io_error_t *err);

/** Reason a field is not a number, for rfe_text_parse_double. */
typedef enum {
    RFE_NUM_OK = 0,
    RFE_NUM_EMPTY,      /**< nothing but blanks */
    RFE_NUM_NONFINITE,  /**< nan / inf text */
    RFE_NUM_SYNTAX,     /**< not a decimal number, or trailing characters */
    RFE_NUM_OVERFLOW    /**< a decimal number too large for a double */
} rfe_num_status_t;

/**
 * Parses @p text as a decimal number `[+-]digits[.digits][(e|E)[+-]digits]` (what Python and
 * C print). Hex floats, nan, inf and trailing characters are rejected so that a typo never
 * becomes a value. Underflow to a subnormal or zero is accepted.
 */
RFE_NODISCARD rfe_num_status_t rfe_text_parse_double(const char *text, double *out);

/** Short message for a rfe_num_status_t ("empty field", ...). */
const char *rfe_num_status_str(rfe_num_status_t s);

/**
 * Reads one line of any length into *buf (grown with realloc, caller frees), without the
 * line end ("\n" or "\r\n"). Returns 1 for a line, 0 at end of file, -1 on a read error,
 * -2 when the line holds a NUL byte.
 */
RFE_NODISCARD int rfe_text_read_line(FILE *f, char **buf, size_t *cap, size_t *len);

/**
 * realloc of @p n elements of @p size bytes that never returns NULL: on overflow of n*size or
 * when memory is exhausted it prints `mu_replay: out of memory` and exits with status 1.
 * Host tools only: this is why no reader has an out-of-memory error path of its own.
 */
void *rfe_xrealloc(void *p, size_t n, size_t size);

/** strdup through rfe_xrealloc (never NULL). */
char *rfe_xstrdup(const char *s);

/** Strips leading and trailing blanks (space, tab) in place; returns the new start. */
char *rfe_text_trim(char *s);

/**
 * Copies at most @p max characters of @p s into @p dst for quoting in a one-line message:
 * control characters become '?', and "..." marks a cut. Fewer than @p max characters are
 * kept when @p dst_size < max + 4; @p dst_size must be at least 4.
 */
void rfe_text_quote(char *dst, size_t dst_size, const char *s, size_t max);

/** Buffer size that holds any number rfe_text_format_double writes. */
#define RFE_NUM_BUF 32

/**
 * Shortest of "%.15g", "%.16g", "%.17g" that reads back as exactly @p x (so a double
 * round-trips like %.17g, but 0.003 stays "0.003"). Non-finite values print as nan/inf.
 */
void rfe_text_format_double(char buf[RFE_NUM_BUF], double x);

/** "%.9g": enough to round-trip any float stored in a double. */
void rfe_text_format_float(char buf[RFE_NUM_BUF], double x);

/** Writes @p s as a JSON string literal (quotes and escapes). */
void rfe_json_write_string(FILE *f, const char *s);

/** Writes @p x as a JSON number, or null when it is not finite (JSON has no NaN). */
void rfe_json_write_number(FILE *f, double x);

#endif /* RFE_HOST_TEXT_IO_H */
