/**
 * @file monitor_flt.c
 * @brief Model-validity monitor on the innovations (docs/MONITOR.md §2): normalisation,
 *        averages, thresholds from the false-alarm probability, hysteresis.
 */
#include "rfe/component/monitor.h"

#include "rfe/component/qr.h"

#include "numerics/internal.h"

#define MC ((size_t)RFE_MEAS)

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

rfe_status_t rfe_monitor_init(rfe_monitor_t *mon, const rfe_monitor_params_t *p, rfe_real_t dt)
{
    rfe_monitor_t m;
    const rfe_real_t ch = RFE_R(RFE_MEAS);
    size_t r;
    rfe_status_t st;
    if ((mon == NULL) || (p == NULL)) {
        return RFE_ERR_NULL;
    }
    st = rfe_monitor_params_validate(p, dt);
    if (st != RFE_OK) {
        return st;
    }
    m.hold_steps = steps_of(p->hold, dt);
    m.warmup_steps = steps_of(p->warmup, dt);
    m.l_d = dt / (p->tau_nis + dt);
    m.l_m = dt / (p->tau_mean + dt);
    /* a probability too small for the real type rounds 1 - p to 1: RFE_ERR_PARAM */
    st = rfe_normal_quantile(RFE_R(1.0) - (p->p_fire / RFE_R(2.0)), &m.z_d_fire);
    if (st == RFE_OK) {
        st = rfe_normal_quantile(RFE_R(1.0) - (p->p_clear / RFE_R(2.0)), &m.z_d_clear);
    }
    if (st == RFE_OK) {
        st = rfe_normal_quantile(RFE_R(1.0) - (p->p_fire / (RFE_R(4.0) * ch)), &m.z_m_fire);
    }
    if (st == RFE_OK) {
        st = rfe_normal_quantile(RFE_R(1.0) - (p->p_clear / (RFE_R(4.0) * ch)), &m.z_m_clear);
    }
    if (st != RFE_OK) {
        return RFE_ERR_PARAM;
    }
    m.seen = 0u;
    m.hold = 0u;
    m.started = 0u;
    m.fired = 0u;
    m.D = ch;
    for (r = 0u; r < MC; ++r) {
        m.M[r] = RFE_R(0.0);
        m.C[r] = RFE_R(0.0);
    }
    m.inflate = 0u;
    if (p->inflate != RFE_R(0.0)) {
        m.inflate = 1u;
    }
    m.magic = RFE_MAGIC_MON;
    *mon = m;
    return RFE_OK;
}

/* Wilson-Hilferty chi-square quantile at the normal quantile z: nu max(0, 1 - a + z sqrt a)^3,
 * a = 2 / (9 nu). */
static rfe_real_t chi2_quantile(rfe_real_t nu, rfe_real_t z)
{
    const rfe_real_t a = RFE_R(2.0) / (RFE_R(9.0) * nu);
    const rfe_real_t b = rfe_max(RFE_R(1.0) - a + (z * RFE_SQRT(a)), RFE_R(0.0));
    return nu * b * b * b;
}

/* cppcheck-suppress misra-c2012-8.7 ; MISRA-DEV-06: public API, called by the application */
rfe_status_t rfe_monitor_limits(const rfe_monitor_t *mon, const rfe_real_t c[RFE_MEAS],
                                rfe_monitor_limits_t *out)
{
    rfe_real_t k2 = RFE_R(0.0);
    rfe_real_t k3 = RFE_R(0.0);
    rfe_real_t lp;
    rfe_real_t l3;
    rfe_real_t lpm;
    rfe_real_t om;
    rfe_real_t b;
    rfe_real_t nu;
    rfe_real_t a;
    size_t r;
    if ((mon == NULL) || (c == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mon->magic != RFE_MAGIC_MON) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (!rfe_all_finite(c, MC)) {
        return RFE_ERR_NONFINITE;
    }
    /* the sums of the weights' squares and cubes: l' = l / (2 - l), l3 = l^3 / (1 - (1 - l)^3) */
    lp = mon->l_d / (RFE_R(2.0) - mon->l_d);
    om = RFE_R(1.0) - mon->l_d;
    l3 = (mon->l_d * mon->l_d * mon->l_d) / (RFE_R(1.0) - (om * om * om));
    lpm = mon->l_m / (RFE_R(2.0) - mon->l_m);
    for (r = 0u; r < MC; ++r) {
        const rfe_real_t cr = rfe_clamp(c[r], RFE_R(0.0), RFE_R(1.0));
        const rfe_real_t w = RFE_R(1.0) - cr;
        const rfe_real_t s = cr + (w * lp);
        k2 += (RFE_R(2.0) * s * s) + (RFE_R(2.0) * lp * w * w);
        k3 += (RFE_R(8.0) * s * s * s) + (RFE_R(8.0) * l3 * w * w * w);
        {
            const rfe_real_t sig = RFE_SQRT(cr + (w * lpm));
            out->m_fire[r] = mon->z_m_fire * sig;
            out->m_clear[r] = mon->z_m_clear * sig;
        }
    }
    /* D ~ a + b chi2(nu), the first three cumulants matched (Pearson) */
    b = k3 / (RFE_R(4.0) * k2);
    nu = (RFE_R(8.0) * k2 * k2 * k2) / (k3 * k3);
    a = RFE_R(RFE_MEAS) - (b * nu);
    out->d_fire = a + (b * chi2_quantile(nu, mon->z_d_fire));
    out->d_clear = a + (b * chi2_quantile(nu, mon->z_d_clear));
    return RFE_OK;
}

/* d = |S_zz \ nu|^2, e_r = nu_r / sqrt(S_rr), c_r = clip(pers_r / S_rr, 0, 1). */
static rfe_status_t normalise(const rfe_real_t nu[RFE_MEAS],
                              const rfe_real_t Szz[RFE_MEAS * RFE_MEAS],
                              const rfe_real_t pers[RFE_MEAS], rfe_real_t *d,
                              rfe_real_t e[RFE_MEAS], rfe_real_t c[RFE_MEAS])
{
    rfe_real_t w[RFE_MEAS];
    rfe_real_t acc = RFE_R(0.0);
    size_t r;
    size_t j;
    rfe_status_t st;
    for (r = 0u; r < MC; ++r) {
        w[r] = nu[r];
    }
    st = rfe_qr_solve_lower(Szz, MC, MC, w, 1u, 1u);
    if (st != RFE_OK) {
        return st;
    }
    for (r = 0u; r < MC; ++r) {
        rfe_real_t srr = RFE_R(0.0);
        for (j = 0u; j <= r; ++j) {
            srr += Szz[(r * MC) + j] * Szz[(r * MC) + j];
        }
        acc += w[r] * w[r];
        e[r] = nu[r] / RFE_SQRT(srr);
        c[r] = rfe_clamp(pers[r] / srr, RFE_R(0.0), RFE_R(1.0));
    }
    *d = acc;
    return RFE_OK;
}

/* The hysteresis after the averages moved (docs/MONITOR.md §2 item 6). */
static void hysteresis(rfe_monitor_t *m, const rfe_monitor_limits_t *lim)
{
    int over = 0;
    int under = 0;
    size_t r;
    if (m->D > lim->d_fire) {
        over = 1;
    }
    if (m->D < lim->d_clear) {
        under = 1;
    }
    for (r = 0u; r < MC; ++r) {
        const rfe_real_t a = RFE_FABS(m->M[r]);
        if (a > lim->m_fire[r]) {
            over = 1;
        }
        if (!(a < lim->m_clear[r])) {
            under = 0;
        }
    }
    if (over != 0) {
        m->fired = 1u;
        m->hold = m->hold_steps;
    } else if (m->fired != 0u) {
        m->hold = (m->hold > 0u) ? (m->hold - 1u) : 0u;
        if ((m->hold == 0u) && (under != 0)) {
            m->fired = 0u;
        }
    } else {
        /* not fired, nothing exceeded: nothing changes */
    }
}

/* The averages and the hysteresis of one counted step into the copy *m (from d, e, c). */
static rfe_status_t advance(rfe_monitor_t *m, rfe_real_t d, const rfe_real_t e[RFE_MEAS],
                            const rfe_real_t c[RFE_MEAS])
{
    rfe_monitor_limits_t lim;
    size_t r;
    rfe_status_t st;
    if (m->started == 0u) {
        for (r = 0u; r < MC; ++r) {
            m->C[r] = c[r];
        }
        m->started = 1u;
    }
    m->D = ((RFE_R(1.0) - m->l_d) * m->D) + (m->l_d * d);
    for (r = 0u; r < MC; ++r) {
        m->M[r] = ((RFE_R(1.0) - m->l_m) * m->M[r]) + (m->l_m * e[r]);
        m->C[r] = ((RFE_R(1.0) - m->l_m) * m->C[r]) + (m->l_m * c[r]);
    }
    if (!rfe_is_finite(m->D) || !rfe_all_finite(m->M, MC)) {
        return RFE_ERR_NONFINITE; /* an innovation so large its square overflows */
    }
    st = rfe_monitor_limits(m, m->C, &lim);
    if (st == RFE_OK) {
        hysteresis(m, &lim);
    }
    return st;
}

rfe_status_t rfe_monitor_step(rfe_monitor_t *mon, const rfe_real_t nu[RFE_MEAS],
                              const rfe_real_t Szz[RFE_MEAS * RFE_MEAS],
                              const rfe_real_t pers[RFE_MEAS], uint32_t *fired)
{
    rfe_monitor_t m;
    rfe_status_t st = RFE_OK;
    if ((mon == NULL) || (nu == NULL) || (Szz == NULL) || (pers == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mon->magic != RFE_MAGIC_MON) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (!rfe_all_finite(nu, MC) || !rfe_lower_finite(Szz, MC, MC) || !rfe_all_finite(pers, MC)) {
        return RFE_ERR_NONFINITE;
    }
    m = *mon;
    if (m.seen < UINT32_MAX) {
        ++m.seen;
    }
    if (m.seen > m.warmup_steps) {
        rfe_real_t d;
        rfe_real_t e[RFE_MEAS];
        rfe_real_t c[RFE_MEAS];
        st = normalise(nu, Szz, pers, &d, e, c);
        if (st == RFE_OK) {
            st = advance(&m, d, e, c);
        }
    }
    if (st != RFE_OK) {
        return st;
    }
    *mon = m;
    if (fired != NULL) {
        *fired = m.fired;
    }
    return RFE_OK;
}

rfe_status_t rfe_monitor_inflation(const rfe_monitor_t *mon, rfe_real_t *c)
{
    if ((mon == NULL) || (c == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mon->magic != RFE_MAGIC_MON) {
        return RFE_ERR_NOT_INITIALISED;
    }
    *c = ((mon->fired != 0u) && (mon->inflate != 0u))
             ? RFE_SQRT(rfe_max(RFE_R(1.0), mon->D / RFE_R(RFE_MEAS)))
             : RFE_R(1.0);
    return RFE_OK;
}
