/**
 * @file monitor_q31.c
 * @brief Model-validity monitor on int32 Q values (the twin of monitor_flt.c,
 *        docs/MONITOR.md §2): normalisation, averages, thresholds from the false-alarm
 *        probability, hysteresis (monitor_logic.h). Integer operations only.
 *
 * The thresholds of D (monitor_flt.c's Pearson match) rewritten for integers: with
 * K2 = sum_r s_r^2 + l' w_r^2 and K3 = sum_r s_r^3 + l3 w_r^3 (s_r = c_r + w_r l', w_r =
 * 1 - c_r; the float's k2 = 2 K2, k3 = 8 K3), the matched a + b chi2(nu) has
 * b nu = K2^2 / K3 and 2 / (9 nu) = A = (2/9) rho^2, rho = K3 / K2^(3/2) <= 1, so the
 * Wilson-Hilferty threshold a + b nu max(0, 1 - A + z sqrt A)^3 is
 *   m + (K2^2 / K3) (max(0, 1 - A + z sqrt A)^3 - 1),   sqrt A = (sqrt 2 / 3) rho.
 * K2 and K3 are sums of at most six terms of Q62 products (exact to 2^-62 each), kept in Q60;
 * rho and B = K2^2 / K3 come from the 30-bit quotients y = K3 / K2 and B = K2 / y, with
 * relative errors of about 2^-30 / y (y >= 2 l / 3: 2^-24 at the default weight).
 */
#include "rfe/component/monitor_q31.h"

#include "rfe/component/fxmath.h"
#include "rfe/component/qr_q31.h"

#include "estimators/friction/monitor_logic.h"
#include "numerics/internal_q31.h"

#define MC ((size_t)RFE_MEAS)
#define QE RFE_MON_Q31_QE /* w, e, M [sd] */
#define QD RFE_MON_Q31_QD /* d, D, D's thresholds */
#define QC RFE_MON_Q31_QC /* shares, weights */
#define QF RFE_MON_Q31_QF /* inflation factor */
#define QN 24u            /* nu, S_zz (RFE_FIX_Q_ACC), quantiles (RFE_FIX_Q_MON_Z) */
#define QT 28u            /* 1 - A + z sqrt A and its cube (<= 4.8 and 108: below 2^31, 2^35) */
#define ONE_C UINT32_C(1073741824)     /* 1 in Q30 */
#define ONE_C_FIX ((rfe_fix_t)1073741824) /* the same as rfe_fix_t */
#define ONE_D ((rfe_fix_t)65536)          /* 1 in Q16 */
#define ONE_T INT64_C(268435456)          /* 1 in Q28 */
#define MASK_C UINT64_C(0x3FFFFFFF)       /* the low 30 bits */

/* The inflation divides by m through its reciprocal (rfe_monitor_inflation_q31). */
/* cppcheck-suppress misra-c2012-2.3 ; MISRA-DEV-04: static assertion, never used by design */
typedef char rfe_assert_monitor_q31_three_channels[(RFE_MEAS == 3) ? 1 : -1];

/* sqrt(2) / 3 in Q30, rounded (0.47140452079103168...). */
#define SQRT2_OVER_3_Q30 UINT64_C(506166750)

/* floor(a b / 2^30) for a <= 2^62, b <= 2^31: a split at bit 30, each part's product below
 * 2^63, the sum below 2^63 + 2^31. */
static uint64_t umul_shr30(uint64_t a, uint32_t b)
{
    const uint64_t hi = (a >> QC) * (uint64_t)b;
    const uint64_t lo = ((a & MASK_C) * (uint64_t)b) >> QC;
    return hi + lo;
}

/* l' = l / (2 - l), Q30, rounded (l in (0, 1): the quotient is in (0, 1)). */
static rfe_fix_t weight_squares(rfe_fix_t l)
{
    const uint64_t den = ((uint64_t)2u << QC) - (uint64_t)l;
    const uint64_t num = (uint64_t)l << QC;
    const uint64_t q = (num + (den >> 1)) / den;
    return (rfe_fix_t)q;
}

/* l3 / l'^2 = (2 - l)^2 / (3 - 3 l + l^2), Q30, rounded (in (1, 4/3] for l in (0, 1)). */
static rfe_fix_t weight_cubes(rfe_fix_t l)
{
    const uint64_t two_minus = ((uint64_t)2u << QC) - (uint64_t)l;     /* < 2^31 */
    const uint64_t l2 = ((uint64_t)l * (uint64_t)l) >> QC;             /* Q30 */
    const uint64_t den = ((uint64_t)3u << QC) - (3u * (uint64_t)l) + l2; /* in (1, 3], Q30 */
    const uint64_t num = two_minus * two_minus;                        /* Q60, < 2^62 */
    const uint64_t q = (num + (den >> 1)) / den;
    return (rfe_fix_t)q;
}

rfe_status_t rfe_monitor_init_q31(rfe_monitor_q31_t *mon, const rfe_monitor_params_q31_t *p)
{
    rfe_monitor_q31_t m;
    size_t r;
    if ((mon == NULL) || (p == NULL)) {
        return RFE_ERR_NULL;
    }
    if (rfe_monitor_params_validate_q31(p) != RFE_OK) {
        return RFE_ERR_PARAM;
    }
    m.hold_steps = p->hold_steps;
    m.warmup_steps = p->warmup_steps;
    m.inflate = (p->inflate != 0u) ? 1u : 0u; /* validated: 0 or 1 */
    m.l_d = p->l_d;
    m.l_m = p->l_m;
    m.lp_d = weight_squares(p->l_d);
    m.lp_m = weight_squares(p->l_m);
    m.r3_d = weight_cubes(p->l_d);
    m.z_d_fire = p->z_d_fire;
    m.z_d_clear = p->z_d_clear;
    m.z_m_fire = p->z_m_fire;
    m.z_m_clear = p->z_m_clear;
    m.seen = 0u;
    m.hold = 0u;
    m.started = 0u;
    m.spare[0] = 0u;
    m.spare[1] = 0u;
    m.fired = 0u;
    m.D = (rfe_fix_t)RFE_MEAS * ONE_D;
    for (r = 0u; r < MC; ++r) {
        m.M[r] = 0;
        m.C[r] = 0;
    }
    m.magic = RFE_MAGIC_MON_Q31;
    *mon = m;
    return RFE_OK;
}

/* The cumulant sums K2, K3 (Q60) and each channel's mean thresholds at the clipped shares
 * c (Q30): sigma_r = sqrt(c_r + w_r l'_m), |M_r| against z sigma_r (Q20). */
static void channel_sums(const rfe_monitor_q31_t *m, const rfe_fix_t c[RFE_MEAS],
                         uint64_t *K2, uint64_t *K3, rfe_monitor_limits_q31_t *out)
{
    const uint32_t lp = (uint32_t)m->lp_d;
    size_t r;
    uint32_t scratch = 0u; /* sigma <= 1 and z sigma <= 8: nothing saturates */
    *K2 = 0u;
    *K3 = 0u;
    for (r = 0u; r < MC; ++r) {
        const uint32_t cr = (uint32_t)rfe_fix_clamp(c[r], 0, ONE_C_FIX);
        const uint32_t w = ONE_C - cr;
        const uint32_t s = cr + (uint32_t)(((uint64_t)w * (uint64_t)lp) >> QC);
        const uint64_t s2 = ((uint64_t)s * (uint64_t)s) << 2; /* Q62 */
        const uint64_t w2 = ((uint64_t)w * (uint64_t)w) << 2; /* Q62 */
        const uint64_t w3l3 = umul_shr30(umul_shr30(umul_shr30(umul_shr30(w2, w), lp), lp),
                                         (uint32_t)m->r3_d);
        const uint32_t v = cr + (uint32_t)(((uint64_t)w * (uint64_t)(uint32_t)m->lp_m) >> QC);
        rfe_fix_t sig = 0;
        rfe_status_t st;
        *K2 += (s2 + umul_shr30(w2, lp)) >> 2;
        *K3 += (umul_shr30(s2, s) + w3l3) >> 2;
        st = rfe_fix_sqrt((rfe_fix_t)v, QC, QC, &sig, &scratch); /* v >= 0: cannot fail */
        (void)st;
        out->m_fire[r] = rfe_fix_mul(m->z_m_fire, sig, QN + QC - QE, &scratch);
        out->m_clear[r] = rfe_fix_mul(m->z_m_clear, sig, QN + QC - QE, &scratch);
    }
}

/* m + B (max(0, 1 - A + z sqrt A)^3 - 1) in Q16 (sqrt A, A in Q30; B in Q24; z in Q24). */
static rfe_fix_t nis_threshold(uint64_t sqA, uint64_t A, uint64_t B, rfe_fix_t z)
{
    uint32_t scratch = 0u; /* below 3 + 128 * 108 < 2^15: nothing saturates */
    const uint64_t zsu = ((uint64_t)z * sqA) >> (QN + QC - QT); /* z sqrt A, Q28 */
    const uint64_t au = A >> (QC - QT);                          /* A, Q28 */
    const int64_t t = (ONE_T - (int64_t)au) + (int64_t)zsu;
    const int64_t tp = (t > 0) ? t : 0;
    const int64_t t2 = (tp * tp) / ONE_T; /* tp >= 0: the quotient is the floor */
    const int64_t g = ((t2 * tp) / ONE_T) - ONE_T; /* Q28, >= -1 */
    const int64_t bg = rfe_fix_shr64_round((int64_t)B * rfe_fix_shr64_round(g, QT - QN),
                                           QN + QN - QD);
    return rfe_fix_sat32(((int64_t)RFE_MEAS * (int64_t)ONE_D) + bg, &scratch);
}

/* The thresholds of D and of each |M_r| at the clipped shares c, into *out. */
static void limits_core(const rfe_monitor_q31_t *m, const rfe_fix_t c[RFE_MEAS],
                        rfe_monitor_limits_q31_t *out)
{
    uint64_t K2;
    uint64_t K3;
    uint64_t k2;
    uint64_t y;
    uint64_t rho;
    uint64_t sqA;
    uint64_t A;
    uint64_t B;
    uint32_t r2 = 0u;
    rfe_status_t st;
    channel_sums(m, c, &K2, &K3, out);
    /* K2 >= 3 l' >= 2^-15 and K3 / K2 >= 2 l / 3 >= 2^-15: every divisor below is >= 1 */
    k2 = K2 >> QC;                          /* Q30 */
    y = K3 / k2;                            /* K3 / K2, Q30, <= 1 */
    st = rfe_fix_isqrt64(K2, &r2);          /* sqrt K2, Q30 (non-NULL: cannot fail) */
    (void)st;
    rho = (y << QC) / (uint64_t)r2;         /* K3 / K2^(3/2), Q30 */
    sqA = (rho * SQRT2_OVER_3_Q30) >> QC;   /* Q30, <= 0.4715 */
    A = (sqA * sqA) >> QC;                  /* Q30 */
    B = K2 / (y << (QC - QN));              /* K2^2 / K3, Q24 (<= m) */
    out->d_fire = nis_threshold(sqA, A, B, m->z_d_fire);
    out->d_clear = nis_threshold(sqA, A, B, m->z_d_clear);
}

rfe_status_t rfe_monitor_limits_q31(const rfe_monitor_q31_t *mon, const rfe_fix_t c[RFE_MEAS],
                                    rfe_monitor_limits_q31_t *out)
{
    if ((mon == NULL) || (c == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mon->magic != RFE_MAGIC_MON_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    limits_core(mon, c, out);
    return RFE_OK;
}

/* The share c = clip(pers / S_rr, 0, 1) in Q30, both Q48 (RFE_MON_Q31_QP): shifted right
 * together until S_rr fits 31 bits (then S_rr >= 2^30, so each shift's truncation moves the
 * ratio by < 2^-30 relative), then one rounded division (half an LSB of Q30). Exact ranges:
 * neither saturates, whatever the variance (issue 21: a Q24 pers saturated at 128). */
static rfe_fix_t persistent_share(uint64_t pers, uint64_t srr, uint32_t *count)
{
    rfe_fix_t c = ONE_C_FIX;
    if (pers == 0u) {
        c = 0;
    } else if (pers < srr) {
        const unsigned int len = rfe_q31_bitlen64(srr);
        unsigned int s = 0u;
        if (len > 31u) {
            s = len - 31u;
        }
        /* srr >> s in [2^30, 2^31) or srr itself (> pers >= 1): > 0, so it cannot fail */
        const uint64_t num = pers >> s;
        const uint64_t den = srr >> s;
        rfe_status_t st = rfe_fix_div((rfe_fix_t)num, (rfe_fix_t)den, (int)QC, &c, count);
        (void)st;
    } else {
        /* at least the whole variance: share 1 */
    }
    return c;
}

/* d = |S_zz \ nu|^2 (Q16), e_r = nu_r / sqrt(S_rr) (Q20), c_r = clip(pers_r / S_rr, 0, 1)
 * (Q30); saturations into *count. */
static rfe_status_t normalise_innovation_q31(const rfe_fix_t nu[RFE_MEAS],
                                  const rfe_fix_t Szz[RFE_MEAS * RFE_MEAS],
                                  const uint64_t pers[RFE_MEAS], rfe_fix_t *d,
                                  rfe_fix_t e[RFE_MEAS], rfe_fix_t c[RFE_MEAS], uint32_t *count)
{
    rfe_fix_t w[RFE_MEAS];
    uint64_t acc = 0u;
    size_t r;
    size_t j;
    rfe_status_t st;
    for (r = 0u; r < MC; ++r) {
        w[r] = nu[r];
    }
    /* Q24 \ Q24 into Q20: shift = 20 - 24 + 24 */
    st = rfe_qr_solve_lower_q31(Szz, MC, MC, w, 1u, 1u, (int)QE, count);
    if (st != RFE_OK) {
        return st;
    }
    for (r = 0u; r < MC; ++r) {
        const uint64_t wr = (uint64_t)rfe_q31_mag64((int64_t)w[r]);
        uint64_t srr = 0u;
        uint32_t sd = 0u;
        acc += wr * wr; /* each < 2^62: the sum of three fits */
        for (j = 0u; j <= r; ++j) {
            const uint64_t a = (uint64_t)rfe_q31_mag64((int64_t)Szz[(r * MC) + j]);
            srr += a * a; /* Q48, < 3 2^62 */
        }
        st = rfe_fix_isqrt64(srr, &sd); /* >= S_rr's diagonal > 0 (the solve checked it) */
        (void)st;
        st = rfe_fix_div(nu[r], (sd > (uint32_t)RFE_FIX_MAX) ? RFE_FIX_MAX : (rfe_fix_t)sd,
                         (int)QE, &e[r], count); /* Q24 / Q24 into Q20; sd >= 1 */
        (void)st;
        c[r] = persistent_share(pers[r], srr, count);
    }
    /* Q40 rounded to Q16, saturated (counted) beyond 32768 */
    *d = rfe_fix_narrow((int64_t)(acc >> 1), (2u * QE) - QD - 1u, count);
    return RFE_OK;
}

/* x + l (target - x), the product rounded (l in Q30; x, target in one format). */
static rfe_fix_t ewma(rfe_fix_t x, rfe_fix_t target, rfe_fix_t l)
{
    const int64_t step = rfe_fix_shr64_round(((int64_t)target - (int64_t)x) * (int64_t)l, QC);
    return (rfe_fix_t)((int64_t)x + step); /* between x and target: fits */
}

/* The averages and the hysteresis of one counted step into the copy *m. */
static void advance_q31(rfe_monitor_q31_t *m, rfe_fix_t d, const rfe_fix_t e[RFE_MEAS],
                        const rfe_fix_t c[RFE_MEAS])
{
    rfe_monitor_limits_q31_t lim;
    int over = 0;
    int under = 0;
    size_t r;
    if (m->started == 0u) {
        for (r = 0u; r < MC; ++r) {
            m->C[r] = c[r];
        }
        m->started = 1u;
    }
    m->D = ewma(m->D, d, m->l_d);
    for (r = 0u; r < MC; ++r) {
        m->M[r] = ewma(m->M[r], e[r], m->l_m);
        m->C[r] = ewma(m->C[r], c[r], m->l_m);
    }
    limits_core(m, m->C, &lim);
    if (m->D > lim.d_fire) {
        over = 1;
    }
    if (m->D < lim.d_clear) {
        under = 1;
    }
    for (r = 0u; r < MC; ++r) {
        const int64_t a = (int64_t)rfe_q31_mag64((int64_t)m->M[r]);
        if (a > (int64_t)lim.m_fire[r]) {
            over = 1;
        }
        if (!(a < (int64_t)lim.m_clear[r])) {
            under = 0;
        }
    }
    rfe_monitor_hysteresis(&m->fired, &m->hold, m->hold_steps, over, under);
}

rfe_status_t rfe_monitor_step_q31(rfe_monitor_q31_t *mon, const rfe_fix_t nu[RFE_MEAS],
                                  const rfe_fix_t Szz[RFE_MEAS * RFE_MEAS],
                                  const uint64_t pers[RFE_MEAS], uint32_t *fired,
                                  uint32_t *sat)
{
    rfe_monitor_q31_t m;
    uint32_t count = 0u;
    rfe_status_t st = RFE_OK;
    if ((mon == NULL) || (nu == NULL) || (Szz == NULL) || (pers == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mon->magic != RFE_MAGIC_MON_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    m = *mon;
    m.seen = rfe_monitor_count_seen(m.seen);
    if (m.seen > m.warmup_steps) {
        rfe_fix_t d = 0;
        rfe_fix_t e[RFE_MEAS];
        rfe_fix_t c[RFE_MEAS];
        st = normalise_innovation_q31(nu, Szz, pers, &d, e, c, &count);
        if (st == RFE_OK) {
            advance_q31(&m, d, e, c);
        }
    }
    if (st != RFE_OK) {
        return st;
    }
    *mon = m;
    rfe_q31_sat_add(sat, count);
    if (fired != NULL) {
        *fired = m.fired;
    }
    return RFE_OK;
}

rfe_status_t rfe_monitor_inflation_q31(const rfe_monitor_q31_t *mon, rfe_fix_t *c)
{
    rfe_fix_t f = RFE_MON_Q31_ONE_F;
    if ((mon == NULL) || (c == NULL)) {
        return RFE_ERR_NULL;
    }
    if (mon->magic != RFE_MAGIC_MON_Q31) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if ((mon->fired != 0u) && (mon->inflate != 0u)) {
        /* D / m (D >= 0) by the reciprocal of m = 3, floor(2^32 / 3): within 1 LSB of the
         * floor of the quotient, and no division helper on the Cortex-M0+ */
        const uint64_t prod = (uint64_t)(uint32_t)mon->D * UINT64_C(1431655765);
        const uint32_t ratio = (uint32_t)(prod >> 32);
        if (ratio > (uint32_t)ONE_D) {
            uint32_t scratch = 0u; /* sqrt(32768 / 3) < 128: nothing saturates */
            rfe_status_t st = rfe_fix_sqrt((rfe_fix_t)ratio, QD, QF, &f, &scratch);
            (void)st;
        }
    }
    *c = f;
    return RFE_OK;
}
