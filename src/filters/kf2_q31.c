/**
 * @file kf2_q31.c
 * @brief The two-state Kalman filter in fixed point (rfe/component/kf2_q31.h). Integer
 *        operations only.
 */
#include "rfe/component/kf2_q31.h"

#include "rfe/component/fxmath.h"

#include "numerics/internal_q31.h"
#include "numerics/xf_q31.h"

/* The formats of a filter: both states in Q0..Q31, the transition's shift in [1, 62] (its
 * upper end holds by itself: q1 + qf - q0 <= 31 + 31 - 0). */
static int formats_ok_q31(unsigned int q0, unsigned int q1, unsigned int qf)
{
    const int s = ((int)q1 + (int)qf) - (int)q0;
    return (q0 <= 31u) && (q1 <= 31u) && (qf <= 31u) && (s >= 1);
}

/* A covariance entry clamped to +-RFE_KF2_Q31_PMAX (counted). */
static int64_t clamp_p_q31(int64_t v, uint32_t *sat)
{
    int64_t r = v;
    if (v > RFE_KF2_Q31_PMAX) {
        rfe_fix_count_sat(sat);
        r = RFE_KF2_Q31_PMAX;
    } else if (v < -RFE_KF2_Q31_PMAX) {
        rfe_fix_count_sat(sat);
        r = -RFE_KF2_Q31_PMAX;
    } else {
        /* inside the bound */
    }
    return r;
}

/* floor(t / 2^n + 1/2) = rfe_fix_shr64_round(t, n) for |t| < 2^62 and 1 <= n <= 31, formed as
 * floor((t + 2^(n-1)) / 2^n) (no overflow: |t + 2^(n-1)| < 2^63) in offset binary (u = t +
 * 2^(n-1) + 2^63 in [0, 2^64)) with the 32-bit halves shifted by n < 32, which the Cortex-M
 * does in a few instructions where the general 64-bit shift of any count took ~40. The same
 * integer (an identity, no rounding of its own; test_kf2_q31.c checks mul_p_q31 against the
 * exact product). */
static int64_t shr_round_small_q31(int64_t t, unsigned int n)
{
    const uint32_t half = (uint32_t)1u << (n - 1u);
    const uint64_t u = ((uint64_t)t + (uint64_t)half) + ((uint64_t)1 << 63);
    const uint32_t uh = (uint32_t)(u >> 32);
    const uint32_t ul = (uint32_t)u;
    const uint32_t rl = (ul >> n) | (uh << (32u - n));
    const uint32_t rh = uh >> n;
    const uint32_t oh = (uint32_t)0x80000000u >> n; /* 2^63 / 2^n = oh 2^32 */
    const uint64_t q = ((uint64_t)rh << 32) | (uint64_t)rl; /* floor(u / 2^n) < 2^63 */
    return (int64_t)q - (int64_t)((uint64_t)oh << 32);
}

/* round(v c / 2^s) (half up) for |v| <= PMAX, any int32 c, 1 <= s <= 62, clamped to +-PMAX
 * (counted). The exact product is split as rfe_q31_mul64x32 splits it: v = vh 2^32 + vl
 * (|vh| <= 2^29, 0 <= vl < 2^32), b = vl c = bh 2^32 + bl (0 <= bl < 2^32), v c = t 2^32 + bl
 * with t = vh c + bh, |t| < 2^61. b is formed from the unsigned 32 x 32 product vl |c|' (c's
 * pattern as uint32, c + 2^32 when c < 0): vl c = vl c' - vl 2^32 [c < 0], so bl is its low
 * word and bh its high word minus vl when c < 0 (one umull and one smull on the Cortex-M where
 * the int64 products took four multiplications). For s >= 33 the result is round(t /
 * 2^(s - 32)), below 2^60 (shr_round_small_q31). For s <= 32, with k = 32 - s in [0, 31], it
 * is t 2^k + lo, lo = floor((bl + 2^(s-1)) / 2^s) in [0, 2^k]; PMAX = 2^61 is a multiple of
 * 2^k, so t > PMAX / 2^k gives a result >= PMAX + 2^k (beyond it) and t < -PMAX / 2^k - 1 one
 * <= -PMAX - 2^k (beyond it), and otherwise |t 2^k| <= PMAX + 2^k and the result is formed
 * exactly and clamped. The same integers and counts as the bit-length bounds this function
 * first decided by (test_kf2_q31.c checks the function against the exact product), without
 * them: the observer's three filters take ~60 of these products a step. */
static int64_t mul_p_q31(int64_t v, rfe_fix_t c, unsigned int s, uint32_t *sat)
{
    uint32_t hw;
    int64_t hw64;
    int32_t vh;
    uint32_t vl;
    uint64_t bu;
    int64_t bh;
    int64_t t;
    uint32_t bl;
    int64_t r;
    if ((v == 0) || (c == 0)) {
        /* half the observer's products are by an h1 of 0 */
        return 0;
    }
    /* vh = floor(v / 2^32), |vh| <= 2^29: the high word in offset binary, then the offset */
    hw = (uint32_t)((uint64_t)v >> 32) ^ (uint32_t)0x80000000u;
    hw64 = (int64_t)hw;
    vh = (int32_t)(hw64 - INT64_C(2147483648));
    vl = (uint32_t)((uint64_t)v & (uint64_t)0xFFFFFFFFu);
    bu = (uint64_t)vl * (uint64_t)(uint32_t)c;
    bh = (int64_t)(bu >> 32);
    if (c < 0) {
        bh -= (int64_t)vl;
    }
    t = ((int64_t)vh * (int64_t)c) + bh;
    bl = (uint32_t)bu;
    if (s >= 33u) {
        r = shr_round_small_q31(t, s - 32u);
    } else {
        const unsigned int k = 32u - s;
        const uint64_t lim_u = (uint64_t)RFE_KF2_Q31_PMAX >> k;
        const int64_t lim = (int64_t)lim_u; /* PMAX / 2^k */
        if (t > lim) {
            r = RFE_KF2_Q31_PMAX + 1;
        } else if (t < (-lim - 1)) {
            r = -RFE_KF2_Q31_PMAX - 1;
        } else {
            /* lo = floor((floor(bl / 2^(s-1)) + 1) / 2) in 32 bits; 2^k as a 32-bit factor */
            const unsigned int s1 = s - 1u;
            const uint32_t blh = bl >> s1;
            const uint32_t lo = (blh >> 1) + (blh & 1u);
            const uint32_t p2 = (uint32_t)1u << k;
            r = (t * (int64_t)p2) + (int64_t)lo;
        }
    }
    return clamp_p_q31(r, sat);
}

/* The ratio a / b (b > 0) as m 2^-e: |m| <= 2^30 with 29 significant bits at least. */
typedef struct {
    rfe_fix_t m;
    int e;
} ratio_q31_t;

/* v != 0 as m 2^e with |m| in [2^29, 2^30] (m exact when e <= 0, rounded half up when
 * e > 0); v = 0 gives m = 0. |v| <= PMAX. */
static void normalise_q31(int64_t v, rfe_fix_t *m, int *e)
{
    const int len = (int)rfe_q31_bitlen64(rfe_q31_mag64_any(v));
    const int sh = len - 30;
    if (sh > 0) {
        /* 1 <= sh <= 32 and |v| < 2^len = 2^(30 + sh) (|v| <= PMAX = 2^61, len <= 62):
         * rfe_xf_round's range, rfe_fix_shr64_round's integer in 32-bit operations */
        *m = rfe_xf_round(v, (unsigned int)sh);
    } else {
        *m = (rfe_fix_t)(v * rfe_q31_pow2((unsigned int)(-sh)));
    }
    *e = sh;
}

/* a / b for b > 0 given normalised (normalise_q31: mb in [2^29, 2^30], b = mb 2^eb): both
 * gains of an update share S, so S is normalised once for the two. */
static ratio_q31_t ratio_q31(int64_t a, rfe_fix_t mb, int eb)
{
    ratio_q31_t r = {0, 0};
    rfe_fix_t ma;
    int ea;
    normalise_q31(a, &ma, &ea);
    if (ma != 0) {
        /* |ma / mb| <= 2 (mb >= 2^29): rfe_fix_div(ma, mb, 29)'s integer, no saturation
         * (floor(|ma| 2^30 / mb) <= 2^31 < 2^32), without its checks; mb > 0 as b > 0 */
        const uint32_t am = (ma < 0) ? (uint32_t)(-ma) : (uint32_t)ma;
        const int32_t q = (int32_t)rfe_q31_div_round_mag(am, (uint32_t)mb, 29u);
        r.m = (ma < 0) ? -q : q;
        r.e = (29 + eb) - ea;
    }
    return r;
}

/* round(v a / b) for the ratio r = a / b and |v| <= PMAX, clamped to +-PMAX. A ratio below
 * 2^-32 (e > 62) pre-rounds v (one more rounding of at most 1/2 result LSB); a ratio above
 * 2^28 (e < 1) scales the product up, saturating. */
static int64_t apply_ratio_q31(ratio_q31_t r, int64_t v, uint32_t *sat)
{
    int64_t y;
    if (r.e > 62) {
        const int pre = r.e - 62;
        const int64_t vr = rfe_fix_shr64_round(v, (unsigned int)pre);
        y = mul_p_q31(vr, r.m, 62u, sat);
    } else if (r.e >= 1) {
        y = mul_p_q31(v, r.m, (unsigned int)r.e, sat);
    } else {
        const int up_bits = 1 - r.e;
        const unsigned int up = (unsigned int)up_bits;
        const int64_t y1 = mul_p_q31(v, r.m, 1u, sat);
        if (y1 == 0) {
            y = 0;
        } else if ((up >= 61u) || (rfe_q31_mag64_any(y1) > ((uint64_t)RFE_KF2_Q31_PMAX >> up))) {
            rfe_fix_count_sat(sat);
            y = (y1 < 0) ? -RFE_KF2_Q31_PMAX : RFE_KF2_Q31_PMAX;
        } else {
            y = y1 * rfe_q31_pow2(up);
        }
    }
    return y;
}

rfe_status_t rfe_kf2_init_q31(rfe_kf2_q31_t *f, unsigned int q0, unsigned int q1,
                              unsigned int qf, rfe_fix_t x0, rfe_fix_t x1, rfe_fix_t sd0,
                              rfe_fix_t sd1)
{
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if ((formats_ok_q31(q0, q1, qf) == 0) || (sd0 < 0) || (sd1 < 0)) {
        return RFE_ERR_RANGE;
    }
    f->q0 = q0;
    f->q1 = q1;
    f->qf = qf;
    f->x[0] = x0;
    f->x[1] = x1;
    f->p00 = (int64_t)sd0 * (int64_t)sd0; /* < 2^62: Q(2 q0) */
    f->p01 = 0;
    f->p11 = (int64_t)sd1 * (int64_t)sd1;
    /* sd^2 < 2^62 may exceed PMAX = 2^61 (sd > 2^30.5 LSB): clamp, uncounted (no sat
     * counter here; such an sd is beyond every format's use) */
    if (f->p00 > RFE_KF2_Q31_PMAX) {
        f->p00 = RFE_KF2_Q31_PMAX;
    }
    if (f->p11 > RFE_KF2_Q31_PMAX) {
        f->p11 = RFE_KF2_Q31_PMAX;
    }
    return RFE_OK;
}

/* A noise term within +-PMAX. */
static int noise_ok_q31(int64_t q) { return (q >= -RFE_KF2_Q31_PMAX) && (q <= RFE_KF2_Q31_PMAX); }

rfe_status_t rfe_kf2_predict_q31(rfe_kf2_q31_t *f, rfe_fix_t f01, rfe_fix_t u, int64_t q00,
                                 int64_t q11, int64_t q01, uint32_t *sat)
{
    uint32_t cnt = 0u;
    uint32_t cnt1 = 0u;
    unsigned int s;
    int64_t t;
    int64_t fp01;
    int64_t p00;
    int64_t p01;
    int64_t x0;
    if ((f == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((formats_ok_q31(f->q0, f->q1, f->qf) == 0) || (noise_ok_q31(q00) == 0) ||
        (noise_ok_q31(q11) == 0) || (noise_ok_q31(q01) == 0)) {
        return RFE_ERR_RANGE;
    }
    s = (f->q1 + f->qf) - f->q0;
    /* x0 + f01 x1 + u: |f01 x1| <= 2^62, the sum of three such terms fits int64 */
    x0 = ((int64_t)f->x[0] + rfe_fix_shr64_round((int64_t)f01 * (int64_t)f->x[1], s)) +
         (int64_t)u;
    /* f01 p11 in Q(q0 + q1); p00 + 2 f01 p01 + f01 (f01 p11) + q00; p01 + f01 p11 + q01 */
    t = mul_p_q31(f->p11, f01, s, &cnt);
    /* f01 p01 once, added twice (its saturation counted twice, as two products would be) */
    fp01 = mul_p_q31(f->p01, f01, s, &cnt1);
    rfe_q31_sat_add(&cnt, cnt1);
    rfe_q31_sat_add(&cnt, cnt1);
    p00 = clamp_p_q31(f->p00 + fp01, &cnt);
    p00 = clamp_p_q31(p00 + fp01, &cnt);
    p00 = clamp_p_q31(p00 + mul_p_q31(t, f01, s, &cnt), &cnt);
    p00 = clamp_p_q31(p00 + q00, &cnt);
    p01 = clamp_p_q31(clamp_p_q31(f->p01 + t, &cnt) + q01, &cnt);
    f->x[0] = rfe_fix_sat32(x0, &cnt);
    f->p00 = p00;
    f->p01 = p01;
    f->p11 = clamp_p_q31(f->p11 + q11, &cnt);
    rfe_q31_sat_add(sat, cnt);
    return RFE_OK;
}

/* The measurement's formats: the shifts of h0 x0 and h1 x1 into Q(qz) within [1, 62] (the
 * upper end holds by itself once every format is within Q0..Q31: 31 + 31 - 0). */
static int meas_ok_q31(const rfe_kf2_q31_t *f, const rfe_kf2_meas_q31_t *m)
{
    const int s0 = ((int)f->q0 + (int)m->qh0) - (int)m->qz;
    const int s1 = ((int)f->q1 + (int)m->qh1) - (int)m->qz;
    return (formats_ok_q31(f->q0, f->q1, f->qf) != 0) && (m->qz <= 31u) && (m->qh0 <= 31u) &&
           (m->qh1 <= 31u) && (s0 >= 1) && (s1 >= 1) &&
           (m->r >= 0) && (m->r <= RFE_KF2_Q31_PMAX);
}

/* v h / 2^s for an H entry h: mul_p_q31's integer, without its product where h is exactly 1
 * in its format (h = 2^s, which an int32 h can be only for s <= 30): v 2^s / 2^s is v
 * exactly, no rounding, and mul_p_q31's clamp is clamp_p_q31's (for |v| <= PMAX, the
 * filter's entries, v itself, nothing counted). Every row of the velocity observer but the
 * model's two observes its state with such an h (docs/OBSERVER.md: the wheel reference, the
 * offsets' row, the linear range, low speed, the differentiator). */
static int64_t mul_h_q31(int64_t v, rfe_fix_t h, unsigned int s, uint32_t *cnt)
{
    int64_t r;
    if ((int64_t)h == rfe_q31_pow2(s)) {
        r = clamp_p_q31(v, cnt);
    } else {
        r = mul_p_q31(v, h, s, cnt);
    }
    return r;
}

/* P H^T (ph0 in Q(q0 + qz), ph1 in Q(q1 + qz)) and H P H^T (Q(2 qz)), each sum clamped to
 * +-PMAX (counted). Where one of h0, h1 is 0 (every row of the velocity observer: a state
 * observed alone), its products are 0 (mul_p_q31, uncounted) and each sum is its other
 * product, already within +-PMAX (mul_p_q31 clamps), which the clamp leaves as it is: those
 * products and clamps are skipped, the same integers and counts. */
static void pht_q31(const rfe_kf2_q31_t *f, const rfe_kf2_meas_q31_t *m, unsigned int s0,
                    unsigned int s1, int64_t *ph0, int64_t *ph1, int64_t *hph, uint32_t *cnt)
{
    if (m->h1 == 0) {
        *ph0 = mul_h_q31(f->p00, m->h0, s0, cnt);
        *ph1 = mul_h_q31(f->p01, m->h0, s0, cnt);
        *hph = mul_h_q31(*ph0, m->h0, s0, cnt);
    } else if (m->h0 == 0) {
        *ph0 = mul_h_q31(f->p01, m->h1, s1, cnt);
        *ph1 = mul_h_q31(f->p11, m->h1, s1, cnt);
        *hph = mul_h_q31(*ph1, m->h1, s1, cnt);
    } else {
        *ph0 = clamp_p_q31(mul_p_q31(f->p00, m->h0, s0, cnt) + mul_p_q31(f->p01, m->h1, s1, cnt),
                           cnt);
        *ph1 = clamp_p_q31(mul_p_q31(f->p01, m->h0, s0, cnt) + mul_p_q31(f->p11, m->h1, s1, cnt),
                           cnt);
        *hph = clamp_p_q31(mul_p_q31(*ph0, m->h0, s0, cnt) + mul_p_q31(*ph1, m->h1, s1, cnt),
                           cnt);
    }
}

rfe_status_t rfe_kf2_update_q31(rfe_kf2_q31_t *f, const rfe_kf2_meas_q31_t *m, uint32_t *sat)
{
    uint32_t cnt = 0u;
    unsigned int s0;
    unsigned int s1;
    int64_t ph0;
    int64_t ph1;
    int64_t s;
    ratio_q31_t k0;
    ratio_q31_t k1;
    rfe_fix_t ms;
    int es;
    if ((f == NULL) || (m == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if (meas_ok_q31(f, m) == 0) {
        return RFE_ERR_RANGE;
    }
    s0 = (f->q0 + m->qh0) - m->qz;
    s1 = (f->q1 + m->qh1) - m->qz;
    pht_q31(f, m, s0, s1, &ph0, &ph1, &s, &cnt);
    s = clamp_p_q31(s + m->r, &cnt);
    if (s <= 0) {
        return RFE_ERR_NOT_POSITIVE_DEFINITE;
    }
    /* K_i nu and K_i ph_j in the states' formats are (ph_i / S) times nu and ph_j as
     * integers: the formats cancel (x_i: Q(q_i + qz) / Q(2 qz) * Q(qz) = Q(q_i)) */
    normalise_q31(s, &ms, &es);
    k0 = ratio_q31(ph0, ms, es);
    k1 = ratio_q31(ph1, ms, es);
    f->x[0] = rfe_fix_sat32((int64_t)f->x[0] + apply_ratio_q31(k0, (int64_t)m->nu, &cnt), &cnt);
    f->x[1] = rfe_fix_sat32((int64_t)f->x[1] + apply_ratio_q31(k1, (int64_t)m->nu, &cnt), &cnt);
    f->p00 = clamp_p_q31(f->p00 - apply_ratio_q31(k0, ph0, &cnt), &cnt);
    f->p01 = clamp_p_q31(f->p01 - apply_ratio_q31(k0, ph1, &cnt), &cnt);
    f->p11 = clamp_p_q31(f->p11 - apply_ratio_q31(k1, ph1, &cnt), &cnt);
    rfe_q31_sat_add(sat, cnt);
    return RFE_OK;
}

rfe_status_t rfe_kf2_scale_q31(int64_t v, rfe_fix_t c, unsigned int s, int64_t *out,
                               uint32_t *sat)
{
    if ((out == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((v > RFE_KF2_Q31_PMAX) || (v < -RFE_KF2_Q31_PMAX) || (s < 1u) || (s > 62u)) {
        return RFE_ERR_RANGE;
    }
    *out = mul_p_q31(v, c, s, sat);
    return RFE_OK;
}
