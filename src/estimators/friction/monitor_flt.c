/**
 * @file monitor_flt.c
 * @brief Model-validity monitor on the innovations (docs/MONITOR.md §2): normalisation,
 *        averages, thresholds from the false-alarm probability, hysteresis.
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_MONITOR_IMPL
#include "rfe/component/monitor.h"

#include "rfe/component/qr.h"

#include "estimators/friction/monitor_logic.h"
#include "numerics/internal.h"

#define MC ((size_t)RFE_MEAS)

rfe_status_t rfe_monitor_init(rfe_monitor_t *mon, const rfe_monitor_params_t *p, rfe_real_t dt,
                              size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    rfe_monitor_t m;
    rfe_monitor_consts_t k;
    size_t r;
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*mon)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if ((mon == NULL) || (p == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_monitor_consts(p, dt, &k) != RFE_OK) {
        return RFE_ERR_PARAM;
    }
    m.hold_steps = k.hold_steps;
    m.warmup_steps = k.warmup_steps;
    m.l_d = k.l_d;
    m.l_m = k.l_m;
    m.z_d_fire = k.z_d_fire;
    m.z_d_clear = k.z_d_clear;
    m.z_m_fire = k.z_m_fire;
    m.z_m_clear = k.z_m_clear;
    m.seen = 0u;
    m.hold = 0u;
    m.started = 0u;
    m.fired = 0u;
    m.D = RFE_R(RFE_MEAS);
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
    rfe_monitor_hysteresis(&m->fired, &m->hold, m->hold_steps, over, under);
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
    m.seen = rfe_monitor_count_seen(m.seen);
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
