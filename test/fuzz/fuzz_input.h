/**
 * @file fuzz_input.h
 * @brief Decoding of libFuzzer bytes into an estimator configuration and a sequence of
 *        sensor samples, in double, independent of the number type under test (so a _q31
 *        harness decodes exactly the same inputs and converts them to its own sample type).
 *
 * Format (every read past the end yields 0, so every byte string is a valid input):
 *   byte 0   configuration: bit 0 preset (0 paper, 1 default); bit 1 CKF (paper preset
 *            only); bit 2 toggles the tyre mode (paper <-> absolute); bits 3-4 the initial
 *            estimate mu0: the preset's, mu_min, mu_max, 0.3.
 *   then records, each starting with an op byte, op % 4:
 *     0  a new sample: 11 values (delta, vx, vy, yaw_rate, yaw_acc, ax, ay, omega fl..rr);
 *     1  the current sample again, (op >> 2) + 1 times (1..64 steps);
 *     2  one field (next byte % 11) of the current sample set to a new value, one step; with
 *        a gap callback (fz_run_gaps) and that byte >= 128 instead a gap: 4 bytes, the
 *        number of periods missed before the next sample (any uint32, 0 included);
 *     3  a ramp: a target sample (11 values), then (op >> 2) + 1 steps interpolating
 *        linearly from the current sample to it (smooth runs, e.g. braking to standstill).
 *   a value starts with a class byte c, c % 8:
 *     0, 1, 2  uniform in +-limit x {1, 0.1, 0.01}[c % 8] from 2 bytes (limit of config.h);
 *     3        a special value (next byte % FZ_N_SPECIAL): 0, -0, +-limit, just beyond
 *              +-limit, NaN, +-Inf, +-1e30, +-DBL_MAX, +-DBL_TRUE_MIN, +-1e-30, 0.5 x limit;
 *     4        float32 bit pattern (4 bytes): any float, NaN and Inf included;
 *     5        float64 bit pattern (8 bytes);
 *     6, 7     near a plausible driving state (braking at 20 m/s) plus a signed byte step.
 * At most FZ_MAX_STEPS steps per input.
 */
#ifndef RFE_FUZZ_INPUT_H
#define RFE_FUZZ_INPUT_H

#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "rfe/config.h"

#define FZ_FIELDS 11
#define FZ_MAX_STEPS 20000
#define FZ_N_SPECIAL 24

typedef struct {
    const uint8_t *p;
    size_t n;
} fz_reader_t;

/** Decoded configuration (byte 0). */
typedef struct {
    int preset_default; /**< 0 paper, 1 default */
    int ckf;            /**< 1: CKF with the paper preset; with the default preset, the
                             model-validity monitor off (mon_enable = 0; the preset has it on) */
    int toggle_tyre;    /**< 1: the other tyre mode */
    int mu0_choice;     /**< 0 preset, 1 mu_min, 2 mu_max, 3 0.3 */
} fz_config_t;

static const double FZ_LIMIT[FZ_FIELDS] = {
    RFE_LIMIT_DELTA,   RFE_LIMIT_VX,  RFE_LIMIT_VY,    RFE_LIMIT_YAW_RATE,
    RFE_LIMIT_YAW_ACC, RFE_LIMIT_ACC, RFE_LIMIT_ACC,   RFE_LIMIT_OMEGA,
    RFE_LIMIT_OMEGA,   RFE_LIMIT_OMEGA, RFE_LIMIT_OMEGA};
static const double FZ_NOMINAL[FZ_FIELDS] = {0.0,  20.0, 0.0,  0.0,  0.0, -2.0,
                                             0.0,  58.0, 58.0, 58.0, 58.0};
static const double FZ_STEP[FZ_FIELDS] = {0.005, 0.2, 0.05, 0.01, 0.05, 0.1,
                                          0.1,   0.5, 0.5,  0.5,  0.5};

static inline uint8_t fz_u8(fz_reader_t *r)
{
    uint8_t v = 0;
    if (r->n > 0) {
        v = *r->p;
        ++r->p;
        --r->n;
    }
    return v;
}

static inline uint64_t fz_bytes(fz_reader_t *r, int k)
{
    uint64_t v = 0;
    int i;
    for (i = 0; i < k; ++i) {
        v |= (uint64_t)fz_u8(r) << (8 * i);
    }
    return v;
}

/* The next 4 bytes as a float's bits, any of them (NaNs, subnormals, infinities). */
static inline double fz_raw_float(fz_reader_t *r)
{
    const uint32_t bits = (uint32_t)fz_bytes(r, 4);
    float f;
    memcpy(&f, &bits, sizeof f);
    return (double)f;
}

/* The next 8 bytes as a double's bits. */
static inline double fz_raw_double(fz_reader_t *r)
{
    const uint64_t bits = fz_bytes(r, 8);
    double d;
    memcpy(&d, &bits, sizeof d);
    return d;
}

static inline fz_config_t fz_config(fz_reader_t *r)
{
    const uint8_t b = fz_u8(r);
    fz_config_t c;
    c.preset_default = b & 1;
    c.ckf = (b >> 1) & 1;
    c.toggle_tyre = (b >> 2) & 1;
    c.mu0_choice = (b >> 3) & 3;
    return c;
}

static inline double fz_special(int field, int idx)
{
    const double lim = FZ_LIMIT[field];
    switch (idx % FZ_N_SPECIAL) {
    case 0: return 0.0;
    case 1: return -0.0;
    case 2: return lim;
    case 3: return -lim;
    case 4: return lim * (1.0 + 1e-6);
    case 5: return -lim * (1.0 + 1e-6);
    case 6: return NAN;
    case 7: return INFINITY;
    case 8: return -INFINITY;
    case 9: return 1e30;
    case 10: return -1e30;
    case 11: return DBL_MAX;
    case 12: return -DBL_MAX;
    case 13: return 4.9406564584124654e-324;
    case 14: return -4.9406564584124654e-324;
    case 15: return 1e-30;
    case 16: return -1e-30;
    case 17: return 0.5 * lim;
    case 18: return -0.5 * lim;
    case 19: return FLT_MIN;
    case 20: return (double)FLT_MAX;
    case 21: return 1e-3;
    case 22: return -1e-3;
    default: return lim * 0.999999;
    }
}

static inline double fz_value(fz_reader_t *r, int field)
{
    const uint8_t c = fz_u8(r);
    switch (c % 8) {
    case 0:
    case 1:
    case 2: {
        static const double scale[3] = {1.0, 0.1, 0.01};
        const double u = (double)fz_bytes(r, 2) / 32767.5 - 1.0;
        return u * FZ_LIMIT[field] * scale[c % 8];
    }
    case 3:
        return fz_special(field, fz_u8(r));
    case 4:
        return fz_raw_float(r);
    case 5:
        return fz_raw_double(r);
    default:
        return FZ_NOMINAL[field] + (double)(int8_t)fz_u8(r) * FZ_STEP[field];
    }
}

/** A sample as 11 doubles in the field order of the format. */
typedef struct {
    double v[FZ_FIELDS];
} fz_sample_t;

static inline void fz_read_sample(fz_reader_t *r, fz_sample_t *s)
{
    int f;
    for (f = 0; f < FZ_FIELDS; ++f) {
        s->v[f] = fz_value(r, f);
    }
}

/** Calls step(ctx, sample) for every step the input describes and gap(ctx, missed) for
 *  every gap (gap NULL: none); stops when either returns nonzero, at the end of the input,
 *  or after FZ_MAX_STEPS. Returns the number of steps. */
typedef int (*fz_step_fn_t)(void *ctx, const fz_sample_t *s);
typedef int (*fz_gap_fn_t)(void *ctx, uint32_t missed);

static inline long fz_run_gaps(fz_reader_t *r, fz_step_fn_t step, fz_gap_fn_t gap, void *ctx)
{
    fz_sample_t cur;
    long steps = 0;
    int f;
    for (f = 0; f < FZ_FIELDS; ++f) {
        cur.v[f] = FZ_NOMINAL[f];
    }
    while (r->n > 0 && steps < FZ_MAX_STEPS) {
        const uint8_t op = fz_u8(r);
        const int count = (op >> 2) + 1;
        int k;
        switch (op % 4) {
        case 0:
            fz_read_sample(r, &cur);
            if (step(ctx, &cur) != 0) {
                return steps;
            }
            ++steps;
            break;
        case 1:
            for (k = 0; k < count && steps < FZ_MAX_STEPS; ++k, ++steps) {
                if (step(ctx, &cur) != 0) {
                    return steps;
                }
            }
            break;
        case 2: {
            const uint8_t fb = fz_u8(r);
            const int fld = fb % FZ_FIELDS;
            if ((fb >= 128u) && (gap != NULL)) {
                if (gap(ctx, (uint32_t)fz_bytes(r, 4)) != 0) {
                    return steps;
                }
                break;
            }
            cur.v[fld] = fz_value(r, fld);
            if (step(ctx, &cur) != 0) {
                return steps;
            }
            ++steps;
            break;
        }
        default: {
            fz_sample_t from = cur, to;
            fz_read_sample(r, &to);
            for (k = 1; k <= count && steps < FZ_MAX_STEPS; ++k, ++steps) {
                const double a = (double)k / (double)count;
                for (f = 0; f < FZ_FIELDS; ++f) {
                    /* a non-finite end point is taken as is (no NaN from inf - inf) */
                    cur.v[f] = (isfinite(from.v[f]) && isfinite(to.v[f]))
                                   ? from.v[f] + a * (to.v[f] - from.v[f])
                                   : to.v[f];
                }
                if (step(ctx, &cur) != 0) {
                    return steps;
                }
            }
            break;
        }
        }
    }
    return steps;
}

/** fz_run_gaps without gaps (the velocity harnesses). */
static inline long fz_run(fz_reader_t *r, fz_step_fn_t step, void *ctx)
{
    return fz_run_gaps(r, step, NULL, ctx);
}

#endif /* RFE_FUZZ_INPUT_H */
