/**
 * @file test_monitor_q31.c
 * @brief The fixed-point model-validity monitor (rfe/component/monitor_q31.h) back to back
 *        with its double twin (monitor_flt.c built for double): the thresholds over a grid of
 *        persistent shares and weights, the averages and decisions over long random
 *        innovation streams, the inflation, the share's edge cases, saturation, input
 *        validation with the state untouched; and the estimator with the monitor on.
 *
 * Tolerances (derived in monitor_q31.c's header and measured; the measured worst cases are
 * printed):
 * - D's thresholds: relative error ~2^-30 / y of the quotient y = K3 / K2 (Q30) plus
 *   2^-30 / rho and the Q16 rounding 2^-17 / 3; y >= l / 3: at the default weight (1/51,
 *   y >= 6.5e-3) 2e-7 relative + 1 LSB of Q16 (1.5e-5); at the smallest weight 2^-14
 *   (y >= 2^-15.6) 5e-5 relative. Bounds used: 2e-6 + 2 LSB at the default and at
 *   l >= 1/501, 1e-4 at l = 2^-14.
 * - The means' thresholds: z (Q24, rounded by the converter: 3e-8 relative) times
 *   sqrt(c + w l') in Q30 and the Q20 rounding: 1e-7 relative + 1 LSB of Q20 (1e-6).
 * - The averages over a stream: each update rounds to half an LSB and the average forgets
 *   errors at rate l, so the accumulated error stays below 0.5 LSB / l plus the input's
 *   rounding: D (Q16) 25 LSB + the NIS's own rounding (w in Q20: 3 x 2 x 10 sd x 2^-21 =
 *   3e-5 absolute): 1e-3 absolute for D ~ 3 .. 50; M (Q20) 25 LSB + e's 2^-21: 5e-5 sd.
 * - Decisions: the statistics differ from the double's by the above, so a decision can
 *   differ only on steps where a statistic lies within that distance of its threshold; the
 *   streams below cross thresholds a few times per thousand steps: >= 99 % of steps agree,
 *   and every disagreement is such a near-threshold step (checked).
 */
#include "test_common.h"

#include <math.h>
#include <string.h>

#include "fixed_conv.h"
#include "rfe/component/monitor.h"
#include "rfe/component/monitor_q31.h"
#include "rfe/component/params_conv.h"
#include "rfe/params.h"
#include "rfe/params_q31.h"

#define QE RFE_MON_Q31_QE
#define QD RFE_MON_Q31_QD
#define QC RFE_MON_Q31_QC
#define QF RFE_MON_Q31_QF
#define QN 24u

static void both_defaults(rfe_monitor_params_t *mp, rfe_monitor_params_q31_t *mq,
                          double tau_nis, double tau_mean)
{
    rfe_params_t p;
    rfe_params_q31_t q;
    assert_int_equal(rfe_params_default_f64(&p), RFE_OK);
    p.monitor.tau_nis = tau_nis;
    p.monitor.tau_mean = tau_mean;
    assert_int_equal(rfe_params_to_q31_f64(&p, &q), RFE_OK);
    *mp = p.monitor;
    *mq = q.monitor;
}

static void both_started(rfe_monitor_t *md, rfe_monitor_q31_t *mq, double tau_nis,
                         double tau_mean)
{
    rfe_monitor_params_t pd;
    rfe_monitor_params_q31_t pq;
    both_defaults(&pd, &pq, tau_nis, tau_mean);
    assert_int_equal(rfe_monitor_init_f64(md, &pd, 0.01), RFE_OK);
    assert_int_equal(rfe_monitor_init_q31(mq, &pq), RFE_OK);
}

static double q2d(rfe_fix_t v, unsigned int q) { return rfe_fix_to_double(v, q); }

/* REQ: the integer thresholds equal the double's within their derived bounds over a grid
 * of persistent shares (every combination of 0, 1e-3, 0.05, 0.3, 0.7, 0.99, 1 and values
 * outside [0, 1], which are clipped) and over the weights from the smallest that fits
 * (2^-14) to 1/2. */
/* REQ-MON-011 */
static void test_limits_match_double(void **state)
{
    static const double shares[9] = {-0.5, 0.0, 1e-3, 0.05, 0.3, 0.7, 0.99, 1.0, 1.5};
    static const double taus[4] = {0.5, 0.01, 5.0, 163.0};
    double worst_d[4] = {0, 0, 0, 0};
    double worst_m = 0.0;
    size_t t;
    (void)state;
    for (t = 0; t < 4; ++t) {
        rfe_monitor_t md;
        rfe_monitor_q31_t mq;
        /* relative bound of D's thresholds at this weight (header) and 2 LSB of Q16 */
        const double rel = (taus[t] > 100.0) ? 1e-4 : 2e-6;
        size_t a;
        size_t b;
        size_t c;
        both_started(&md, &mq, taus[t], taus[t]);
        for (a = 0; a < 9; ++a) {
            for (b = 0; b < 9; ++b) {
                for (c = 0; c < 9; ++c) {
                    const double cs[3] = {shares[a], shares[b], shares[c]};
                    rfe_real_t cd[3];
                    rfe_fix_t cq[3];
                    rfe_monitor_limits_t ld;
                    rfe_monitor_limits_q31_t lq;
                    uint32_t sat = 0u;
                    size_t r;
                    for (r = 0; r < 3; ++r) {
                        cd[r] = cs[r];
                        cq[r] = rfe_fix_from_double(cs[r], QC, &sat);
                        cd[r] = q2d(cq[r], QC); /* the same share in both */
                    }
                    assert_int_equal(rfe_monitor_limits_f64(&md, cd, &ld), RFE_OK);
                    assert_int_equal(rfe_monitor_limits_q31(&mq, cq, &lq), RFE_OK);
                    assert_close(q2d(lq.d_fire, QD), ld.d_fire, 2.0 / 65536.0, rel, "d_fire");
                    assert_close(q2d(lq.d_clear, QD), ld.d_clear, 2.0 / 65536.0, rel,
                                 "d_clear");
                    worst_d[t] = fmax(worst_d[t], fabs(q2d(lq.d_fire, QD) - ld.d_fire) /
                                                      ld.d_fire);
                    for (r = 0; r < 3; ++r) {
                        assert_close(q2d(lq.m_fire[r], QE), ld.m_fire[r], 1e-6, 1e-7,
                                     "m_fire");
                        assert_close(q2d(lq.m_clear[r], QE), ld.m_clear[r], 1e-6, 1e-7,
                                     "m_clear");
                        worst_m = fmax(worst_m, fabs(q2d(lq.m_fire[r], QE) - ld.m_fire[r]));
                    }
                }
            }
        }
    }
    printf("  worst relative |d_fire| error at tau 0.5, 0.01, 5, 163 s: %.3g %.3g %.3g %.3g; "
           "worst |m_fire| error %.3g sd\n",
           worst_d[0], worst_d[1], worst_d[2], worst_d[3], worst_m);
}

/* A deterministic generator (64-bit LCG, top bits) of uniform doubles in (0, 1). */
static double uniform(uint64_t *s)
{
    *s = (*s * 6364136223846793005ULL) + 1442695040888963407ULL;
    return ((double)(*s >> 11) + 0.5) / 9007199254740992.0;
}

static double gauss(uint64_t *s)
{
    const double u = uniform(s);
    const double v = uniform(s);
    return sqrt(-2.0 * log(u)) * cos(6.283185307179586 * v);
}

/* One step of both monitors on the same (Q24-representable) input. */
static void step_both(rfe_monitor_t *md, rfe_monitor_q31_t *mq, const double nu[3],
                      const double S[9], const double pers[3], uint32_t *fd, uint32_t *fq,
                      uint32_t *sat)
{
    rfe_real_t nd[3];
    rfe_real_t Sd[9];
    rfe_real_t pd[3];
    rfe_fix_t nq[3];
    rfe_fix_t Sq[9];
    uint64_t pq[3];
    uint32_t conv = 0u;
    size_t i;
    for (i = 0; i < 3; ++i) {
        nq[i] = rfe_fix_from_double(nu[i], QN, &conv);
        /* pers >= 0 here, in Q48 (RFE_MON_Q31_QP); 2^48 and the rounded value exact in double */
        pq[i] = (uint64_t)llround(pers[i] * 281474976710656.0);
        nd[i] = q2d(nq[i], QN);
        pd[i] = (rfe_real_t)((double)pq[i] / 281474976710656.0);
    }
    for (i = 0; i < 9; ++i) {
        Sq[i] = rfe_fix_from_double(S[i], QN, &conv);
        Sd[i] = q2d(Sq[i], QN);
    }
    assert_int_equal(conv, 0u);
    assert_int_equal(rfe_monitor_step_f64(md, nd, Sd, pd, fd), RFE_OK);
    assert_int_equal(rfe_monitor_step_q31(mq, nq, Sq, pq, fq, sat), RFE_OK);
}

/* 1 when a statistic of the double monitor lies within the averages' bound of a threshold
 * that decides (a decision may then differ). */
static int near_threshold(const rfe_monitor_t *md)
{
    rfe_monitor_limits_t l;
    int near = 0;
    size_t r;
    assert_int_equal(rfe_monitor_limits_f64(md, md->C, &l), RFE_OK);
    if ((fabs(md->D - l.d_fire) < 2e-3) || (fabs(md->D - l.d_clear) < 2e-3)) {
        near = 1;
    }
    for (r = 0; r < 3; ++r) {
        if ((fabs(fabs(md->M[r]) - l.m_fire[r]) < 1e-4) ||
            (fabs(fabs(md->M[r]) - l.m_clear[r]) < 1e-4)) {
            near = 1;
        }
    }
    return near;
}

/* REQ: over long innovation streams (white with a correlated factor and a persistent share,
 * then a variance excess, a bias on one channel, and back), the integer monitor's averages
 * stay within their derived bounds of the double's and its decisions agree on >= 99 % of
 * steps, every disagreement at a near-threshold step; nothing saturates. */
/* REQ-MON-011 */
static void test_stream_matches_double(void **state)
{
    static const double S[9] = {0.06, 0, 0, 0.02, 0.08, 0, -0.01, 0.03, 0.12};
    static const double pers[3] = {0.0009, 0.002, 0.0};
    rfe_monitor_t md;
    rfe_monitor_q31_t mq;
    uint64_t seed = 12345u;
    uint32_t sat = 0u;
    size_t agree = 0;
    size_t fired_steps = 0;
    size_t k;
    const size_t n = 20000;
    double worst_D = 0.0;
    double worst_M = 0.0;
    (void)state;
    both_started(&md, &mq, 0.5, 0.5);
    for (k = 0; k < n; ++k) {
        /* phases of 2000 steps: model-matched, variance x 2, bias 0.05 on ay, matched */
        const size_t phase = (k / 2000u) % 5u;
        const double scale = (phase == 1u) ? 2.0 : 1.0;
        const double bias = (phase == 3u) ? 0.05 : 0.0;
        double g[3];
        double nu[3];
        uint32_t fd = 0u;
        uint32_t fq = 0u;
        size_t r;
        size_t j;
        for (r = 0; r < 3; ++r) {
            g[r] = gauss(&seed);
        }
        for (r = 0; r < 3; ++r) {
            nu[r] = (r == 1u) ? bias : 0.0;
            for (j = 0; j <= r; ++j) {
                nu[r] += scale * S[(r * 3) + j] * g[j];
            }
        }
        step_both(&md, &mq, nu, S, pers, &fd, &fq, &sat);
        fired_steps += fd;
        if (fd == fq) {
            ++agree;
        } else if (!near_threshold(&md)) {
            fail_msg("step %zu: decisions differ (double %u, q31 %u) away from a threshold", k,
                     (unsigned)fd, (unsigned)fq);
        }
        worst_D = fmax(worst_D, fabs(q2d(mq.D, QD) - md.D));
        for (r = 0; r < 3; ++r) {
            worst_M = fmax(worst_M, fabs(q2d(mq.M[r], QE) - md.M[r]));
        }
    }
    printf("  %zu steps, %zu fired (double); decisions agree on %zu; worst |dD| %.3g, "
           "|dM| %.3g sd\n",
           n, fired_steps, agree, worst_D, worst_M);
    ASSERT_LE(worst_D, 1e-3, "D");
    ASSERT_LE(worst_M, 5e-5, "M");
    assert_true((double)agree >= 0.99 * (double)n);
    assert_true(fired_steps > 1000u); /* the excess and the bias phases fire */
    assert_true(fired_steps < n / 2u);
    assert_int_equal(sat, 0u);
    assert_int_equal(mq.seen, (uint32_t)n);
}

/* REQ: the warm-up only counts; the first counted step sets C; the count of steps seen
 * saturates at UINT32_MAX; the sd factor is sqrt(max(1, D / 3)) (Q24) while fired with
 * inflate, else exactly 1. */
/* REQ-MON-011 */
static void test_warmup_inflation_seen(void **state)
{
    static const double S[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const double big[3] = {4, -4, 4};
    static const double small[3] = {0.5, 0.5, 0.5};
    static const double zero[3] = {0, 0, 0};
    rfe_monitor_t md;
    rfe_monitor_q31_t mq;
    rfe_monitor_q31_t noinf;
    rfe_monitor_params_t pd;
    rfe_monitor_params_q31_t pq;
    uint32_t fd = 0u;
    uint32_t fq = 0u;
    uint32_t sat = 0u;
    rfe_fix_t c = 0;
    uint32_t k;
    (void)state;
    both_defaults(&pd, &pq, 0.5, 0.5);
    pq.inflate = 0u;
    assert_int_equal(rfe_monitor_init_q31(&noinf, &pq), RFE_OK);
    both_started(&md, &mq, 0.5, 0.5);
    for (k = 0u; k < mq.warmup_steps; ++k) {
        step_both(&md, &mq, big, S, zero, &fd, &fq, &sat);
    }
    assert_int_equal(mq.D, 3 << QD); /* counted only */
    assert_int_equal(mq.started, 0u);
    assert_int_equal(rfe_monitor_inflation_q31(&mq, &c), RFE_OK);
    assert_int_equal(c, RFE_FIX_ONE(QF));
    for (k = 0u; (k < 20u) && (fq == 0u); ++k) {
        step_both(&md, &mq, big, S, small, &fd, &fq, &sat);
    }
    assert_int_equal(fq, 1u);
    assert_int_equal(fd, 1u);
    assert_int_equal(mq.started, 1u);
    assert_int_equal(rfe_monitor_inflation_q31(&mq, &c), RFE_OK);
    /* sqrt in Q24 of D / 3 (Q16): 2^-25 relative rounding of the root + D's 1e-3 */
    assert_close(q2d(c, QF), sqrt(md.D / 3.0), 1e-4, 1e-6, "inflation");
    assert_true(c > RFE_FIX_ONE(QF));
    /* fired with inflate = 0: exactly 1 */
    noinf.fired = 1u;
    assert_int_equal(rfe_monitor_inflation_q31(&noinf, &c), RFE_OK);
    assert_int_equal(c, RFE_FIX_ONE(QF));
    /* fired with D below m: 1 */
    noinf.inflate = 1u;
    noinf.D = 2 << QD;
    assert_int_equal(rfe_monitor_inflation_q31(&noinf, &c), RFE_OK);
    assert_int_equal(c, RFE_FIX_ONE(QF));
    /* quiet innovations clear it after the hold */
    for (k = 1u; k <= 2000u; ++k) {
        step_both(&md, &mq, zero, S, zero, &fd, &fq, &sat);
        assert_int_equal(fq, fd);
        if (fq == 0u) {
            break;
        }
    }
    assert_true(k >= mq.hold_steps);
    assert_int_equal(fq, 0u);
    /* the count of steps seen saturates */
    mq.seen = UINT32_MAX;
    step_both(&md, &mq, zero, S, zero, &fd, &fq, &sat);
    assert_int_equal(mq.seen, UINT32_MAX);
    assert_int_equal(sat, 0u);
}

/* REQ: the persistent share (pers and S_rr in Q48) is 0 for pers 0, 1 for pers >= the
 * variance, else pers / S_rr to the Q30 LSB, with no saturation also where the variance is
 * far beyond Q24's 128 (issue 21: a Q24 pers saturated there) or only 2^20 LSB (no shift);
 * an innovation far beyond its covariance saturates the NIS and the normalised innovation,
 * and both are counted. */
/* REQ-MON-011 */
static void test_shares_and_saturation(void **state)
{
    rfe_monitor_t md;
    rfe_monitor_q31_t mq;
    rfe_monitor_q31_t mq2;
    rfe_monitor_q31_t before;
    const rfe_fix_t one = RFE_FIX_ONE(QN);
    /* S_rr = 10^4, 1 and 2^-28 (m/s^2)^2: 10^4 2^48, 2^48 and 2^20 in Q48 */
    const rfe_fix_t Sq[9] = {100 * one, 0, 0, 0, one, 0, 0, 0, 1024};
    const rfe_fix_t S1[9] = {one, 0, 0, 0, one, 0, 0, 0, 1}; /* S_33 = 1 LSB */
    const rfe_fix_t nu0[3] = {0, 0, 0};
    /* exact halves (Q30: 2^29) where S_rr needs the shift and where it does not, and a
     * pers twice the variance (share 1) */
    const uint64_t pers[3] = {UINT64_C(5000) << 48, UINT64_C(2) << 48, UINT64_C(1) << 19};
    /* shares 0 (pers 0), a third (to the rounded Q30 LSB), 1 (pers = S_rr = 1 LSB^2) */
    const uint64_t pers2[3] = {0u, (UINT64_C(1) << 48) / 3u, 1u};
    const rfe_fix_t huge[3] = {RFE_FIX_MAX, 0, RFE_FIX_MAX};
    uint32_t sat = 0u;
    uint32_t k;
    (void)state;
    both_started(&md, &mq, 0.5, 0.5);
    mq.warmup_steps = 0u;
    mq2 = mq;
    assert_int_equal(rfe_monitor_step_q31(&mq, nu0, Sq, pers, NULL, &sat), RFE_OK);
    assert_int_equal(mq.C[0], RFE_FIX_ONE(QC) / 2); /* S_rr beyond Q24's range: exact 1/2 */
    assert_int_equal(mq.C[1], RFE_FIX_ONE(QC));     /* pers > variance: 1 */
    assert_int_equal(mq.C[2], RFE_FIX_ONE(QC) / 2); /* S_rr < 2^31, no shift: exact 1/2 */
    assert_int_equal(rfe_monitor_step_q31(&mq2, nu0, S1, pers2, NULL, &sat), RFE_OK);
    assert_int_equal(mq2.C[0], 0);                                   /* pers 0: share 0 */
    assert_int_equal(mq2.C[1], (rfe_fix_t)((RFE_FIX_ONE(QC) + 1) / 3)); /* 357913941.33 */
    assert_int_equal(mq2.C[2], RFE_FIX_ONE(QC));                     /* pers = S_rr: 1 */
    assert_int_equal(sat, 0u);
    /* a huge innovation over a 1-LSB sd: w and e beyond Q20, the NIS beyond Q16 */
    before = mq;
    assert_int_equal(rfe_monitor_step_q31(&mq, huge, S1, pers2, NULL, &sat), RFE_OK);
    assert_true(sat >= 3u);
    assert_true(mq.D > before.D);
    for (k = 0u; k < 2000u; ++k) {
        assert_int_equal(rfe_monitor_step_q31(&mq, huge, S1, pers2, NULL, &sat), RFE_OK);
    }
    assert_true(mq.D > (RFE_FIX_MAX - (RFE_FIX_MAX / 100))); /* pinned near the top */
    assert_int_equal(mq.fired, 1u);
}

/* REQ: bad arguments give a distinct status and leave the monitor and the counter untouched
 * (NULL, not initialised, a diagonal of S_zz that is not > 0); init refuses NULL and
 * parameters outside their ranges. */
/* REQ-MON-012 */
static void test_bad_input_untouched(void **state)
{
    rfe_monitor_t md;
    rfe_monitor_q31_t m;
    rfe_monitor_q31_t before;
    rfe_monitor_q31_t blank;
    rfe_monitor_params_t pd;
    rfe_monitor_params_q31_t pq;
    rfe_monitor_limits_q31_t lim;
    const rfe_fix_t one = RFE_FIX_ONE(QN);
    const rfe_fix_t S[9] = {one, 0, 0, 0, one, 0, 0, 0, one};
    const rfe_fix_t Sbad[9] = {one, 0, 0, 0, 0, 0, 0, 0, one};
    const rfe_fix_t Sneg[9] = {one, 0, 0, 0, -one, 0, 0, 0, one};
    const rfe_fix_t v[3] = {one, one, one};
    const uint64_t pv[3] = {1u, 1u, 1u}; /* persistent diagonal (Q48) */
    rfe_fix_t c = 7;
    uint32_t fired = 5u;
    uint32_t sat = 9u;
    (void)state;
    both_defaults(&pd, &pq, 0.5, 0.5);
    both_started(&md, &m, 0.5, 0.5);
    m.warmup_steps = 0u;
    before = m;
    memset(&blank, 0, sizeof blank);
    assert_int_equal(rfe_monitor_init_q31(NULL, &pq), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_init_q31(&blank, NULL), RFE_ERR_NULL);
    pq.l_d = 0;
    assert_int_equal(rfe_monitor_init_q31(&blank, &pq), RFE_ERR_PARAM);
    assert_int_equal(blank.magic, 0u);
    assert_int_equal(rfe_monitor_step_q31(NULL, v, S, pv, &fired, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step_q31(&m, NULL, S, pv, &fired, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step_q31(&m, v, NULL, pv, &fired, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step_q31(&m, v, S, NULL, &fired, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step_q31(&m, v, S, pv, &fired, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_step_q31(&blank, v, S, pv, &fired, &sat),
                     RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_monitor_step_q31(&m, v, Sbad, pv, &fired, &sat),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_monitor_step_q31(&m, v, Sneg, pv, &fired, &sat),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_memory_equal(&m, &before, sizeof m);
    assert_int_equal(fired, 5u);
    assert_int_equal(sat, 9u);
    assert_int_equal(rfe_monitor_inflation_q31(NULL, &c), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_inflation_q31(&m, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_inflation_q31(&blank, &c), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(c, 7);
    assert_int_equal(rfe_monitor_limits_q31(NULL, v, &lim), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_limits_q31(&m, NULL, &lim), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_limits_q31(&m, v, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_monitor_limits_q31(&blank, v, &lim), RFE_ERR_NOT_INITIALISED);
    /* in the warm-up nothing is read but the pointers: a bad factor is not an error there */
    m.warmup_steps = 5u;
    m.seen = 0u;
    assert_int_equal(rfe_monitor_step_q31(&m, v, Sbad, pv, NULL, &sat), RFE_OK);
    assert_int_equal(m.seen, 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_limits_match_double),
        cmocka_unit_test(test_stream_matches_double),
        cmocka_unit_test(test_warmup_inflation_seen),
        cmocka_unit_test(test_shares_and_saturation),
        cmocka_unit_test(test_bad_input_untouched),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
