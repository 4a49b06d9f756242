/**
 * @file monitor_consts_flt.c
 * @brief The model-validity monitor's constants from its parameters (rfe/params.h,
 *        docs/MONITOR.md §2): the normal quantile, the EWMA weights and the step counts. In
 *        the parameter layer, so that the monitor (float and double) and the conversion to
 *        the fixed-point constants (params_conv_flt.c) compute them once, the same way.
 */
#include "rfe/params.h"

#include "numerics/internal.h"

/* Acklam's rational approximation of the normal quantile (P. J. Acklam, "An algorithm for
 * computing the inverse normal cumulative distribution function", 2003; relative error
 * < 1.15e-9): the central region's and the tails' coefficients live in lower_quantile and
 * tail_quantile; the tails' edge: */
#define ACK_TAIL RFE_R(0.02425)

/* Relative slack of the step counts: a duration within 1e-6 of a whole number of periods
 * is that number (hold / dt = 0.5 / 0.01 is 50.0000007 in float; 1e-6 is ~8 float ulps). */
#define STEPS_SLACK RFE_R(1e-6)

/* Horner evaluation of sum_k c[k] x^(n-1-k). */
static rfe_real_t horner(const rfe_real_t *c, size_t n, rfe_real_t x)
{
    rfe_real_t acc = RFE_R(0.0);
    size_t k;
    for (k = 0u; k < n; ++k) {
        acc = (acc * x) + c[k];
    }
    return acc;
}

/* sqrt(2 pi), the normal density's normaliser. */
#define SQRT_2PI RFE_R(2.5066282746310002)

/* The lower tail's quantile at q < ACK_TAIL, from s = sqrt(-2 ln q). */
static rfe_real_t tail_quantile(rfe_real_t q)
{
    static const rfe_real_t ACK_C[6] = {
        RFE_R(-7.784894002430293e-03), RFE_R(-3.223964580411365e-01),
        RFE_R(-2.400758277161838e+00), RFE_R(-2.549732539343734e+00),
        RFE_R(4.374664141464968e+00), RFE_R(2.938163982698783e+00)};
    static const rfe_real_t ACK_D[4] = {
        RFE_R(7.784695709041462e-03), RFE_R(3.224671290700398e-01), RFE_R(2.445134137142996e+00),
        RFE_R(3.754408661907416e+00)};
    const rfe_real_t s = RFE_SQRT(RFE_R(-2.0) * RFE_LOG(q));
    return horner(ACK_C, 6u, s) / ((horner(ACK_D, 4u, s) * s) + RFE_R(1.0));
}

/* Acklam's approximation at p <= 1/2 (the lower half), then one Halley step on
 * Phi(z) - p = erfc(-z / sqrt 2) / 2 - p: the rational's cancellation costs the float build
 * ~1e-4 relative in the centre, the step restores the working precision (Acklam's paper). */
static rfe_real_t lower_quantile(rfe_real_t p)
{
    static const rfe_real_t ACK_A[6] = {
        RFE_R(-3.969683028665376e+01), RFE_R(2.209460984245205e+02),
        RFE_R(-2.759285104469687e+02), RFE_R(1.383577518672690e+02),
        RFE_R(-3.066479806614716e+01), RFE_R(2.506628277459239e+00)};
    static const rfe_real_t ACK_B[5] = {
        RFE_R(-5.447609879822406e+01), RFE_R(1.615858368580409e+02),
        RFE_R(-1.556989798598866e+02), RFE_R(6.680131188771972e+01), RFE_R(-1.328068155288572e+01)};
    rfe_real_t z;
    rfe_real_t e;
    rfe_real_t u;
    if (p < ACK_TAIL) {
        z = tail_quantile(p);
    } else {
        const rfe_real_t c = p - RFE_R(0.5);
        const rfe_real_t r = c * c;
        z = (horner(ACK_A, 6u, r) * c) / ((horner(ACK_B, 5u, r) * r) + RFE_R(1.0));
    }
    e = (RFE_R(0.5) * RFE_ERFC(-z / RFE_SQRT(RFE_R(2.0)))) - p;
    u = e * SQRT_2PI * RFE_EXP((z * z) / RFE_R(2.0));
    return z - (u / (RFE_R(1.0) + ((z * u) / RFE_R(2.0))));
}

rfe_status_t rfe_normal_quantile(rfe_real_t q, rfe_real_t *z)
{
    if (z == NULL) {
        return RFE_ERR_NULL;
    }
    if (!rfe_is_finite(q) || !(q > RFE_R(0.0)) || !(q < RFE_R(1.0))) {
        return RFE_ERR_RANGE;
    }
    /* z(q) = -z(1 - q): the upper half from the lower, 1 - q exact for q >= 1/2 (Sterbenz) */
    *z = (q > RFE_R(0.5)) ? -lower_quantile(RFE_R(1.0) - q) : lower_quantile(q);
    return RFE_OK;
}

/* ceil(t / dt) with STEPS_SLACK (t / dt < 2^31: rfe_monitor_params_validate). */
static uint32_t steps_of(rfe_real_t t, rfe_real_t dt)
{
    return (uint32_t)RFE_CEIL((t / dt) * (RFE_R(1.0) - STEPS_SLACK));
}


rfe_status_t rfe_monitor_consts(const rfe_monitor_params_t *mp, rfe_real_t dt,
                                rfe_monitor_consts_t *out)
{
    rfe_monitor_consts_t k;
    const rfe_real_t ch = RFE_R(RFE_MEAS);
    rfe_status_t st;
    if ((mp == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_monitor_params_validate(mp, dt);
    if (st != RFE_OK) {
        return st;
    }
    k.hold_steps = steps_of(mp->hold, dt);
    k.warmup_steps = steps_of(mp->warmup, dt);
    k.l_d = dt / (mp->tau_nis + dt);
    k.l_m = dt / (mp->tau_mean + dt);
    /* a probability too small for the real type rounds 1 - p to 1: RFE_ERR_PARAM */
    st = rfe_normal_quantile(RFE_R(1.0) - (mp->p_fire / RFE_R(2.0)), &k.z_d_fire);
    if (st == RFE_OK) {
        st = rfe_normal_quantile(RFE_R(1.0) - (mp->p_clear / RFE_R(2.0)), &k.z_d_clear);
    }
    if (st == RFE_OK) {
        st = rfe_normal_quantile(RFE_R(1.0) - (mp->p_fire / (RFE_R(4.0) * ch)), &k.z_m_fire);
    }
    if (st == RFE_OK) {
        st = rfe_normal_quantile(RFE_R(1.0) - (mp->p_clear / (RFE_R(4.0) * ch)), &k.z_m_clear);
    }
    if (st != RFE_OK) {
        return RFE_ERR_PARAM;
    }
    *out = k;
    return RFE_OK;
}
