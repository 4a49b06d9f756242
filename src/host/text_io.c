/**
 * @file text_io.c
 * @brief Host-only text helpers: error record, unbounded line reading, strict decimal
 *        parsing, round-trip number formatting, JSON literals.
 */
#include "text_io.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

static const char *skip_digits(const char *p, size_t *count);
static int starts_with_nonfinite_word(const char *p);
static void print_sanitised(FILE *f, const char *s);

void rfe_io_error_set(rfe_io_error_t *err, const char *file, size_t line, size_t col,
                      const char *fmt, ...)
{
    va_list ap;
    err->file = file;
    err->line = line;
    err->col = col;
    va_start(ap, fmt);
    (void)vsnprintf(err->msg, sizeof err->msg, fmt, ap);
    va_end(ap);
}

void rfe_io_error_print(FILE *f, const char *prog, const rfe_io_error_t *err)
{
    fprintf(f, "%s: ", prog);
    print_sanitised(f, (err->file != NULL) ? err->file : "?");
    if (err->line > 0u) {
        fprintf(f, ":%zu", err->line);
        if (err->col > 0u) {
            fprintf(f, ":%zu", err->col);
        }
    }
    fputs(": ", f);
    print_sanitised(f, err->msg);
    fputc('\n', f);
}

/* A file name may hold a newline; the message must stay one line. */
static void print_sanitised(FILE *f, const char *s)
{
    for (; *s != '\0'; ++s) {
        fputc(iscntrl((unsigned char)*s) ? '?' : *s, f);
    }
}

/* Advances over decimal digits, counting them. */
static const char *skip_digits(const char *p, size_t *count)
{
    while (isdigit((unsigned char)*p)) {
        ++p;
        ++*count;
    }
    return p;
}

/* "nan", "inf", "infinity" in any case: strtod would take them, a sensor log must not. */
static int starts_with_nonfinite_word(const char *p)
{
    char w[4];
    size_t i;
    for (i = 0u; (i < 3u) && (p[i] != '\0'); ++i) {
        w[i] = (char)tolower((unsigned char)p[i]);
    }
    w[i] = '\0';
    return (strcmp(w, "nan") == 0) || (strcmp(w, "inf") == 0);
}

rfe_num_status_t rfe_text_parse_double(const char *text, double *out)
{
    const char *p = text;
    size_t mant = 0u;
    size_t expo = 0u;
    double v;
    while ((*p == ' ') || (*p == '\t')) {
        ++p;
    }
    if (*p == '\0') {
        return RFE_NUM_EMPTY;
    }
    /* Grammar check first, so strtod never sees hex, nan or trailing text. */
    if ((*p == '+') || (*p == '-')) {
        ++p;
    }
    if (starts_with_nonfinite_word(p)) {
        return RFE_NUM_NONFINITE;
    }
    p = skip_digits(p, &mant);
    if (*p == '.') {
        p = skip_digits(p + 1, &mant);
    }
    if (mant == 0u) {
        return RFE_NUM_SYNTAX;
    }
    if ((*p == 'e') || (*p == 'E')) {
        ++p;
        if ((*p == '+') || (*p == '-')) {
            ++p;
        }
        p = skip_digits(p, &expo);
        if (expo == 0u) {
            return RFE_NUM_SYNTAX;
        }
    }
    while ((*p == ' ') || (*p == '\t')) {
        ++p;
    }
    if (*p != '\0') {
        return RFE_NUM_SYNTAX;
    }
    errno = 0;
    v = strtod(text, NULL);
    if (isinf(v)) {
        return RFE_NUM_OVERFLOW; /* ERANGE overflow; underflow gives a finite value */
    }
    *out = v;
    return RFE_NUM_OK;
}

const char *rfe_num_status_str(rfe_num_status_t s)
{
    switch (s) {
    case RFE_NUM_OK: return "ok";
    case RFE_NUM_EMPTY: return "empty field";
    case RFE_NUM_NONFINITE: return "nan/inf is not allowed (values must be finite numbers)";
    case RFE_NUM_SYNTAX: return "not a decimal number";
    case RFE_NUM_OVERFLOW: return "number out of range of a double";
    default: return "invalid number";
    }
}

int rfe_text_read_line(FILE *f, char **buf, size_t *cap, size_t *len)
{
    ssize_t n;
    size_t un;
    errno = 0;
    n = getline(buf, cap, f);
    if (n < 0) {
        return ferror(f) ? -1 : 0;
    }
    un = (size_t)n;
    /* getline counts bytes, strlen stops at NUL: they differ when the line holds one. */
    if (strlen(*buf) != un) {
        return -2;
    }
    if ((un > 0u) && ((*buf)[un - 1u] == '\n')) {
        (*buf)[--un] = '\0';
    }
    if ((un > 0u) && ((*buf)[un - 1u] == '\r')) {
        (*buf)[--un] = '\0';
    }
    *len = un;
    return 1;
}

void *rfe_xrealloc(void *p, size_t n, size_t size)
{
    void *q = NULL;
    if ((size == 0u) || (n <= SIZE_MAX / size)) {
        q = realloc(p, (n * size > 0u) ? n * size : 1u);
    }
    if (q == NULL) { /* GCOVR_EXCL_START: needs exhausted memory */
        fprintf(stderr, "mu_replay: out of memory (%zu x %zu bytes)\n", n, size);
        exit(1);
    } /* GCOVR_EXCL_STOP */
    return q;
}

char *rfe_xstrdup(const char *s)
{
    size_t n = strlen(s) + 1u;
    return memcpy(rfe_xrealloc(NULL, n, 1u), s, n);
}

char *rfe_text_trim(char *s)
{
    size_t n;
    while ((*s == ' ') || (*s == '\t')) {
        ++s;
    }
    n = strlen(s);
    while ((n > 0u) && ((s[n - 1u] == ' ') || (s[n - 1u] == '\t'))) {
        s[--n] = '\0';
    }
    return s;
}

void rfe_text_quote(char *dst, size_t dst_size, const char *s, size_t max)
{
    /* Room for "..." and the NUL even when the caller's max is too big (dst_size >= 4). */
    const size_t lim = (max + 4u <= dst_size) ? max : dst_size - 4u;
    size_t i;
    for (i = 0u; (i < lim) && (s[i] != '\0'); ++i) {
        dst[i] = iscntrl((unsigned char)s[i]) ? '?' : s[i];
    }
    if (s[i] != '\0') {
        memcpy(&dst[i], "...", 3u);
        i += 3u;
    }
    dst[i] = '\0';
}

void rfe_text_format_double(char buf[RFE_NUM_BUF], double x)
{
    int digits;
    if (!isfinite(x)) {
        (void)snprintf(buf, RFE_NUM_BUF, "%s", isnan(x) ? "nan" : ((x > 0.0) ? "inf" : "-inf"));
        return;
    }
    for (digits = 15; digits < 17; ++digits) {
        (void)snprintf(buf, RFE_NUM_BUF, "%.*g", digits, x);
        if (strtod(buf, NULL) == x) {
            return;
        }
    }
    (void)snprintf(buf, RFE_NUM_BUF, "%.17g", x);
}

void rfe_text_format_float(char buf[RFE_NUM_BUF], double x)
{
    (void)snprintf(buf, RFE_NUM_BUF, "%.9g", x);
}

void rfe_json_write_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s != '\0'; ++s) {
        unsigned char c = (unsigned char)*s;
        if ((c == '"') || (c == '\\')) {
            fputc('\\', f);
            fputc((int)c, f);
        } else if (c < 0x20u) {
            fprintf(f, "\\u%04x", (unsigned)c);
        } else {
            fputc((int)c, f);
        }
    }
    fputc('"', f);
}

void rfe_json_write_number(FILE *f, double x)
{
    char buf[RFE_NUM_BUF];
    if (!isfinite(x)) {
        fputs("null", f);
        return;
    }
    rfe_text_format_double(buf, x);
    fputs(buf, f);
}
