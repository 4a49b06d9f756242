/**
 * @file tyre_id_weights_flt.c
 * @brief The tyre identifier's weights and resampling (docs/TYRE_ID.md §5.1, §5.3-5.5):
 *        log-sum-exp, N_eff, the parent search, multinomial and systematic draws, the stable
 *        order by weight and the reflection into the bounds.
 */
#include "estimators/tyre_id/tyre_id_internal.h"
#include "numerics/internal.h"

int rfe_tid_normalise(const rfe_real_t *l, size_t n, rfe_real_t *w, rfe_real_t *lw)
{
    rfe_real_t mx = l[0];
    rfe_real_t s = RFE_R(0.0);
    rfe_real_t log_s;
    int nan_seen = 0;
    size_t i;
    for (i = 0u; i < n; ++i) {
        if (isnan(l[i]) != 0) {
            nan_seen = 1;
        } else if (l[i] > mx) {
            mx = l[i];
        } else {
            /* below the maximum so far */
        }
    }
    /* M = max l: every particle impossible (M = -inf), or a weight that is no number */
    if ((nan_seen != 0) || !rfe_is_finite(mx)) {
        return 0;
    }
    /* e_i = exp(l_i - M), S = e_0 + e_1 + ... (S >= 1: the maximum's term is 1) */
    for (i = 0u; i < n; ++i) {
        w[i] = RFE_EXP(l[i] - mx);
        s += w[i];
    }
    log_s = RFE_LOG(s);
    for (i = 0u; i < n; ++i) {
        if (lw != NULL) {
            lw[i] = (l[i] - mx) - log_s;
        }
        w[i] = w[i] / s;
    }
    return 1;
}

rfe_real_t rfe_tid_neff(const rfe_real_t *w, size_t n)
{
    rfe_real_t s = RFE_R(0.0);
    size_t i;
    for (i = 0u; i < n; ++i) {
        s += w[i] * w[i];
    }
    return RFE_R(1.0) / s;
}

void rfe_tid_cumsum(const rfe_real_t *w, size_t n, rfe_real_t *cum)
{
    rfe_real_t s = RFE_R(0.0);
    size_t i;
    for (i = 0u; i < n; ++i) {
        s += w[i];
        cum[i] = s;
    }
}

size_t rfe_tid_search(const rfe_real_t *cum, size_t n, rfe_real_t x)
{
    /* bisection for the first cum[i] > x (cum is non-decreasing) */
    size_t lo = 0u;
    size_t hi = n;
    while (lo < hi) {
        const size_t mid = lo + ((hi - lo) / 2u);
        if (cum[mid] > x) {
            hi = mid;
        } else {
            lo = mid + 1u;
        }
    }
    return (lo < n) ? lo : (n - 1u);
}

/* Uniform n of the identifier's own stream (non-NULL: the call cannot fail). */
static rfe_real_t uniform(rfe_philox_t *s, uint64_t n)
{
    rfe_real_t u = RFE_R(0.5);
    const rfe_status_t st = rfe_philox_uniform(s, n, &u);
    (void)st; /* fails only for NULL arguments, which these are not */
    return u;
}

void rfe_tid_draw(const rfe_real_t *cum, size_t n, rfe_philox_t *s, rfe_tid_resample_t scheme,
                  size_t m, uint16_t *idx)
{
    const rfe_real_t total = cum[n - 1u];
    size_t j;
    if (scheme == RFE_TID_SYSTEMATIC) {
        /* x_j = (j + u_0) (S / m) */
        const rfe_real_t step = total / (rfe_real_t)m;
        const rfe_real_t u0 = uniform(s, 0u);
        for (j = 0u; j < m; ++j) {
            idx[j] = (uint16_t)rfe_tid_search(cum, n, ((rfe_real_t)j + u0) * step);
        }
    } else {
        /* x_j = u_j S */
        for (j = 0u; j < m; ++j) {
            idx[j] = (uint16_t)rfe_tid_search(cum, n, uniform(s, (uint64_t)j) * total);
        }
    }
}

static size_t smaller(size_t a, size_t b)
{
    return (a < b) ? a : b;
}

/* One pass of the bottom-up merge: runs of `width` from src merged into dst, the left run
 * first on equal weights (stable). */
static void merge_pass(const rfe_real_t *w, size_t n, size_t width, const uint16_t *src,
                       uint16_t *dst)
{
    size_t lo;
    for (lo = 0u; lo < n; lo += (2u * width)) {
        const size_t mid = smaller(lo + width, n);
        const size_t end = smaller(mid + width, n);
        size_t a = lo;
        size_t b = mid;
        size_t k;
        for (k = lo; k < end; ++k) {
            if ((a < mid) && ((b >= end) || (w[src[a]] >= w[src[b]]))) {
                dst[k] = src[a];
                ++a;
            } else {
                dst[k] = src[b];
                ++b;
            }
        }
    }
}

void rfe_tid_order(const rfe_real_t *w, size_t n, uint16_t *order, uint16_t *tmp)
{
    size_t width;
    size_t i;
    int in_order = 1; /* which buffer holds the runs */
    for (i = 0u; i < n; ++i) {
        order[i] = (uint16_t)i;
    }
    for (width = 1u; width < n; width *= 2u) {
        if (in_order != 0) {
            merge_pass(w, n, width, order, tmp);
        } else {
            merge_pass(w, n, width, tmp, order);
        }
        in_order = 1 - in_order;
    }
    if (in_order == 0) {
        for (i = 0u; i < n; ++i) {
            order[i] = tmp[i];
        }
    }
}

rfe_real_t rfe_tid_reflect(rfe_real_t x, rfe_real_t lo, rfe_real_t hi)
{
    /* y = x < lo ? lo + (lo - x) : x;  y = y > hi ? hi - (y - hi) : y;  min(max(y, lo), hi) */
    rfe_real_t y = (x < lo) ? (lo + (lo - x)) : x;
    y = (y > hi) ? (hi - (y - hi)) : y;
    return rfe_clamp(y, lo, hi);
}
