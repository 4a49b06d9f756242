/**
 * @file harness.h
 * @brief The benchmark harness shared by bench_flt.c (float, double) and bench_q31.c.
 *
 * A case is a function run once per sample of a sensor log (k = 0 .. N-1) after a prepare
 * step that is not measured. Two modes:
 *   bench_X --log FILE [--reps R] [--only CASE]   host time: R passes over the log, each
 *                        pass timed with clock_gettime(CLOCK_MONOTONIC); per call the pass
 *                        time / N; one JSON line per case with the median, min and max;
 *   bench_X --log FILE --count CASE                one pass inside bench_region() only, for
 *                        valgrind --tool=callgrind --toggle-collect=bench_region (the
 *                        instructions of that pass, divided by N by the caller).
 *   bench_X --list                                 the case names.
 * A case may name a baseline case (restoring the filter state before the call), which the
 * caller subtracts.
 * Host code: not part of the library, never linked into firmware.
 */
#ifndef RFE_BENCH_HARNESS_H
#define RFE_BENCH_HARNESS_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
    const char *name;      /**< e.g. "step.paper.sckf.paper", "qr.tria.4x12" */
    const char *baseline;  /**< case to subtract (state restore only), or NULL */
    void (*prepare)(void); /**< unmeasured set-up before each pass, or NULL */
    void (*run)(size_t k); /**< the measured call for sample k */
} bench_case_t;

/* Defined by the flavour file. */
extern const bench_case_t bench_cases[];
extern const size_t bench_n_cases;
extern const char *const bench_flavour;
/* Reads the log and prepares everything; returns the number of samples N (0: failed). */
size_t bench_setup(const char *log_path);

/* Keeps the optimiser from dropping results. */
extern volatile uint32_t bench_sink;

#define BENCH_MAX_REPS 2001

volatile uint32_t bench_sink;

/* The measured pass: its own symbol, so callgrind can collect it alone. */
__attribute__((noinline)) void bench_region(const bench_case_t *c, size_t n);
__attribute__((noinline)) void bench_region(const bench_case_t *c, size_t n)
{
    size_t k;
    for (k = 0u; k < n; ++k) {
        c->run(k);
    }
}

static double bench_now_ns(void)
{
    struct timespec ts;
    (void)clock_gettime(CLOCK_MONOTONIC, &ts);
    return ((double)ts.tv_sec * 1e9) + (double)ts.tv_nsec;
}

static int bench_cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a;
    const double y = *(const double *)b;
    return (x > y) - (x < y);
}

static const bench_case_t *bench_find(const char *name)
{
    size_t i;
    for (i = 0u; i < bench_n_cases; ++i) {
        if (strcmp(bench_cases[i].name, name) == 0) {
            return &bench_cases[i];
        }
    }
    return NULL;
}

static void bench_time_case(const bench_case_t *c, size_t n, int reps)
{
    static double per_call[BENCH_MAX_REPS];
    int r;
    if (c->prepare != NULL) { /* warm-up pass (caches, branch predictors) */
        c->prepare();
    }
    bench_region(c, n);
    for (r = 0; r < reps; ++r) {
        double t0;
        double t1;
        if (c->prepare != NULL) {
            c->prepare();
        }
        t0 = bench_now_ns();
        bench_region(c, n);
        t1 = bench_now_ns();
        per_call[r] = (t1 - t0) / (double)n;
    }
    qsort(per_call, (size_t)reps, sizeof per_call[0], bench_cmp_double);
    printf("{\"flavour\": \"%s\", \"case\": \"%s\", \"baseline\": %s%s%s, \"calls\": %zu, "
           "\"reps\": %d, \"median_ns\": %.2f, \"min_ns\": %.2f, \"max_ns\": %.2f}\n",
           bench_flavour, c->name, (c->baseline != NULL) ? "\"" : "",
           (c->baseline != NULL) ? c->baseline : "null", (c->baseline != NULL) ? "\"" : "", n,
           reps, per_call[reps / 2], per_call[0], per_call[reps - 1]);
    fflush(stdout);
}

int main(int argc, char **argv)
{
    const char *log_path = NULL;
    const char *only = NULL;
    const char *count = NULL;
    int reps = 51;
    int list = 0;
    int i;
    size_t n;
    for (i = 1; i < argc; ++i) {
        if ((strcmp(argv[i], "--log") == 0) && (i + 1 < argc)) {
            log_path = argv[++i];
        } else if ((strcmp(argv[i], "--reps") == 0) && (i + 1 < argc)) {
            reps = atoi(argv[++i]);
        } else if ((strcmp(argv[i], "--only") == 0) && (i + 1 < argc)) {
            only = argv[++i];
        } else if ((strcmp(argv[i], "--count") == 0) && (i + 1 < argc)) {
            count = argv[++i];
        } else if (strcmp(argv[i], "--list") == 0) {
            list = 1;
        } else {
            fprintf(stderr, "usage: %s --log FILE [--reps R] [--only CASE] [--count CASE] [--list]\n",
                    argv[0]);
            return 2;
        }
    }
    if (list != 0) {
        size_t c;
        for (c = 0u; c < bench_n_cases; ++c) {
            printf("%s %s\n", bench_cases[c].name,
                   (bench_cases[c].baseline != NULL) ? bench_cases[c].baseline : "-");
        }
        return 0;
    }
    if ((log_path == NULL) || (reps < 1) || (reps > BENCH_MAX_REPS)) {
        fprintf(stderr, "%s: --log FILE required, 1 <= reps <= %d\n", argv[0], BENCH_MAX_REPS);
        return 2;
    }
    n = bench_setup(log_path);
    if (n == 0u) {
        return 1;
    }
    if (count != NULL) {
        const bench_case_t *c = bench_find(count);
        if (c == NULL) {
            fprintf(stderr, "%s: no case '%s'\n", argv[0], count);
            return 2;
        }
        if (c->prepare != NULL) {
            c->prepare();
        }
        bench_region(c, n);
        printf("{\"flavour\": \"%s\", \"case\": \"%s\", \"calls\": %zu}\n", bench_flavour, c->name, n);
        return 0;
    }
    {
        size_t c;
        for (c = 0u; c < bench_n_cases; ++c) {
            if ((only == NULL) || (strcmp(only, bench_cases[c].name) == 0)) {
                bench_time_case(&bench_cases[c], n, reps);
            }
        }
    }
    return 0;
}

#endif /* RFE_BENCH_HARNESS_H */
