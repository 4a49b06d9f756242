/**
 * @file fuzz_params.h
 * @brief Decoding of libFuzzer bytes into a parameter struct for the harnesses of the mass
 *        and grade estimator and the tyre identifier: the preset as it is, the preset with a
 *        few fields perturbed, or every field garbage. Exists so that both harnesses feed
 *        their inits the same classes of bad parameters (the step harnesses of the friction
 *        estimator and the observer only pick among presets).
 *
 * Format (every read past the end yields 0, fuzz_input.h):
 *   a mode byte m, m % 4:
 *     0, 3  the preset unchanged;
 *     1     a count byte k, then (k % 8) + 1 perturbations: a field byte (index % number of
 *           fields; the real fields first, then the integer ones) and its new value;
 *     2     every field a new value, in order.
 *   a real field's new value from its preset value x0 and a class byte c, c % 8:
 *     0  x0 * 2^(s / 16), s a signed byte (a factor 1/256 .. 256);
 *     1  x0 * (1 + s / 128);
 *     2  -x0;
 *     3  a special value (fz_special with limit max(|x0|, 1)): 0, -0, +-limit, NaN, +-Inf,
 *        +-1e30, +-DBL_MAX, subnormals, ...;
 *     4  a float32 bit pattern; 5  a float64 bit pattern;
 *     6  0;
 *     7  x0 * 10^(e - 20), e = byte % 41.
 *   an integer field's new value from a byte b: b % 4 = 0, 1, 2 that value; 3 four raw bytes.
 */
#ifndef RFE_FUZZ_PARAMS_H
#define RFE_FUZZ_PARAMS_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "fuzz_input.h"
#include "fuzz_real.h"

/** The fields of a parameter struct, by address. */
typedef struct {
    rfe_real_t *const *real;
    size_t n_real;
    uint32_t *const *u32;
    size_t n_u32;
} fzp_fields_t;

static inline double fzp_real_value(fz_reader_t *r, double x0)
{
    const uint8_t c = fz_u8(r);
    switch (c % 8) {
    case 0:
        return x0 * pow(2.0, (double)(int8_t)fz_u8(r) / 16.0);
    case 1:
        return x0 * (1.0 + (double)(int8_t)fz_u8(r) / 128.0);
    case 2:
        return -x0;
    case 3: {
        /* fz_special on a field whose limit is |x0|: reuse the delta slot's table by scaling */
        const double lim = fmax(fabs(x0), 1.0);
        return fz_special(0, fz_u8(r)) * lim / FZ_LIMIT[0];
    }
    case 4:
        return fz_raw_float(r);
    case 5:
        return fz_raw_double(r);
    case 6:
        return 0.0;
    default:
        return x0 * pow(10.0, (double)(fz_u8(r) % 41) - 20.0);
    }
}

static inline uint32_t fzp_u32_value(fz_reader_t *r)
{
    const uint8_t b = fz_u8(r);
    return ((b % 4) == 3) ? (uint32_t)fz_bytes(r, 4) : (uint32_t)(b % 4);
}

static inline void fzp_set(fz_reader_t *r, const fzp_fields_t *f, size_t idx)
{
    if (idx < f->n_real) {
        rfe_real_t *x = f->real[idx];
        *x = fz_to_real(fzp_real_value(r, (double)*x));
    } else {
        *f->u32[idx - f->n_real] = fzp_u32_value(r);
    }
}

/** Applies the mode byte and what follows to the fields (filled with the preset before);
 *  returns the mode (0 unchanged, 1 perturbed, 2 garbage). */
static inline int fzp_decode(fz_reader_t *r, const fzp_fields_t *f)
{
    const int mode = fz_u8(r) % 4;
    const size_t n = f->n_real + f->n_u32;
    size_t i;
    if (mode == 1) {
        const int k = (fz_u8(r) % 8) + 1;
        int j;
        for (j = 0; j < k; ++j) {
            fzp_set(r, f, (size_t)fz_u8(r) % n);
        }
        return 1;
    }
    if (mode == 2) {
        for (i = 0; i < n; ++i) {
            fzp_set(r, f, i);
        }
        return 2;
    }
    return 0;
}

#endif /* RFE_FUZZ_PARAMS_H */
