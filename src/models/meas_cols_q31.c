/**
 * @file meas_cols_q31.c
 * @brief The fixed-point input columns' per-wheel rows and columns (rfe_meas_input_jac_q31,
 *        meas_q31.c; docs/ESTIMATOR.md step 4, docs/FIXED_POINT.md "Analytic input
 *        derivatives"): each wheel's body rows per unit change of its velocity in integers
 *        and each input's column from them. A unit of its own so that the compiler cannot
 *        fold their locals into rfe_meas_input_jac_q31's frame, which sits on the step
 *        noise's deepest call path (the tyre derivatives below it). Integer operations only.
 */
#include "models/meas_cols_internal_q31.h"

#include "models/meas_inputs.h"

/* 1.0 in Q30, 2^30 (1 - kappa at no slip). */
#define ONE_Q30 ((int32_t)0x40000000)

/* The Q format of each input (RFE_IN_*) of the sample: its sd's too. */
static int input_q_q31(size_t j)
{
    int q = (int)RFE_FIX_Q_OMEGA;
    if (j == (size_t)RFE_IN_DELTA) {
        q = (int)RFE_FIX_Q_ANGLE;
    } else if ((j == (size_t)RFE_IN_VX) || (j == (size_t)RFE_IN_VY)) {
        q = (int)RFE_FIX_Q_SPEED;
    } else if (j == (size_t)RFE_IN_YAW_RATE) {
        q = (int)RFE_FIX_Q_YAWRATE;
    } else {
        /* a wheel speed */
    }
    return q;
}

/* A value m 2^e of the input columns' per-wheel chain, |m| <= 2^30 (m = 0: the value 0). */
typedef struct {
    int64_t m;
    int e;
} qv_q31_t;

/* v[0..n-1] 2^*e (|v| < 2^62) brought to 30 bits together: the shift s = (bit length of the
 * largest |v|) - 30 when positive, each rounded half up (1/2 unit: <= 2^-30 of the largest),
 * |v| <= 2^30 after it, *e += s. */
static void norm30_q31(int64_t *v, size_t n, int *e)
{
    uint64_t big = 0u;
    unsigned int len;
    size_t k;
    for (k = 0u; k < n; ++k) {
        const uint64_t a = rfe_q31_mag64(v[k]);
        big = (a > big) ? a : big;
    }
    len = rfe_q31_bitlen64(big);
    if (len > 30u) {
        const unsigned int sh = len - 30u;
        for (k = 0u; k < n; ++k) {
            v[k] = rfe_fix_shr64_round(v[k], sh);
        }
        *e += (int)sh;
    }
}

/* Wheel i's slips' changes per unit change of its velocity (v_wx, v_wy, omega R), the chain
 * of meas_flt.c input_direction written per unit of each speed: tan(alpha) by v_wx (tx) and
 * v_wy (ty), kappa by v_wx (kx) and omega R (kr); zero where the slip is clamped. Two
 * quotients per wheel, 1 / |v_wx| (|v_wx| Q23) and 1 / den, den = max(|omega R|, |v_wx|,
 * v_min) (Q51, as the kinematics form it, vy_direction_q31), each one rfe_xf_t division (a
 * mantissa in [2^29, 2^30], 2^-30 relative: 1 / |v_wx| has no fixed range); the numerators are
 * plain Q: -1, -t sgn(v_wx) (tan_a Q26, |.| < 2^31), -(1 + own_x) and 1 - own_r (Q30, <= 2^31,
 * |kappa| < 1); each product with the quotient's mantissa < 2^61, exact, brought to 30 bits
 * (norm30_q31: 2^-30 relative). */
typedef struct {
    qv_q31_t tx;
    qv_q31_t ty;
    qv_q31_t kx;
    qv_q31_t kr;
} slip_sens_q31_t;

/* num (|.| <= 2^31) times the quotient q, at 30 bits. */
static qv_q31_t sens_q31(int64_t num, rfe_xf_t q, int qnum)
{
    qv_q31_t r;
    r.m = rfe_fix_mul_m31(num, (int64_t)q.m);
    r.e = q.e - qnum;
    norm30_q31(&r.m, 1u, &r.e);
    return r;
}

static void slip_sens_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                          const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u, size_t i,
                          int32_t tan_a, slip_sens_q31_t *ss)
{
    const int32_t vwx = h->kin.vwx[i];
    const int32_t kappa = h->kin.kappa[i];
    const int sv = rfe_q31_sign(vwx);
    const rfe_xf_t one = rfe_xf_make(1, 0);
    const qv_q31_t zero = {0, 0};
    ss->tx = zero;
    ss->ty = zero;
    ss->kx = zero;
    ss->kr = zero;
    if ((rfe_q31_within(h->kin.alpha[i], tp->alpha_max - 1) != 0) && (vwx != 0)) {
        /* d tan(alpha) = -(d v_wy + t sgn(v_wx) d v_wx) / |v_wx| */
        const rfe_xf_t iv =
            rfe_xf_div(one, rfe_xf_of((vwx < 0) ? -vwx : vwx, (int)RFE_FIX_Q_SPEED));
        ss->ty = sens_q31(-1, iv, 0);
        ss->tx = sens_q31((sv > 0) ? -(int64_t)tan_a : (int64_t)tan_a, iv, 26);
    }
    if (rfe_q31_within(kappa, ONE_Q30 - 1) != 0) {
        /* d kappa = (d(omega R) (1 - [den = |omega R|] kappa sgn(omega R))
         *            - d v_wx (1 + [den = |v_wx|] kappa sgn(v_wx))) / den, the speeds in Q51 */
        const int64_t vr = rfe_fix_mul32x32(u->omega[i], veh->R);
        const uint64_t avr = rfe_q31_mag64(vr);
        const uint64_t avx = (uint64_t)((vwx < 0) ? -(int64_t)vwx : (int64_t)vwx) << 28;
        const uint64_t vmin = (uint64_t)tp->v_min << 28;
        const uint64_t big = (avr > avx) ? avr : avx;
        const rfe_xf_t id =
            rfe_xf_div(one, rfe_xf_make((int64_t)((big > vmin) ? big : vmin), -51));
        int64_t own_x = 0;
        int64_t own_r = 0;
        if ((avx > avr) && (avx > vmin)) {
            own_x = (sv > 0) ? (int64_t)kappa : -(int64_t)kappa;
        }
        if ((avr >= avx) && (avr > vmin)) {
            own_r = (vr > 0) ? (int64_t)kappa : -(int64_t)kappa;
        }
        ss->kr = sens_q31((int64_t)ONE_Q30 - own_r, id, 30);
        ss->kx = sens_q31(-((int64_t)ONE_Q30 + own_x), id, 30);
    }
}

/* The body rows (ax, ay, r-dot) of a force pair (wheel axes) by the Q36 map b (lat_map_q36:
 * the ax row is (fx c - fy s) / m = fx b->ay - fy b->ax): both mantissas at the larger exponent
 * E (rfe_xf_at: the smaller one rounded half up, 1/2 unit = 2^-31 of the larger force),
 * |(mx, my)| <= 2^30.5, each row a sum of two exact products < |(mx, my)| |(a, b)| < 2^30.5
 * 2^29.5 = 2^60 (|(ax, ay)| = 1 / m, |(rx, ry)| = |(x_i, y_i)| / J, both < 2^-6.5, < 2^29.5
 * in Q36), at E - 36, then brought to 30 bits together (norm30_q31); all 0 (m 0) when both
 * forces are 0. */
static void body_part_q31(const lat_q36_t *b, rfe_xf_t fx, rfe_xf_t fy, int64_t m[3], int *e)
{
    m[0] = 0;
    m[1] = 0;
    m[2] = 0;
    *e = 0;
    if ((fx.m != 0) || (fy.m != 0)) {
        int ef = (fx.m != 0) ? fx.e : fy.e;
        int64_t mx;
        int64_t my;
        if ((fy.m != 0) && (fy.e > ef)) {
            ef = fy.e;
        }
        mx = rfe_xf_at(fx, ef);
        my = rfe_xf_at(fy, ef);
        m[0] = rfe_fix_mul_m31(mx, (int64_t)b->ay) - rfe_fix_mul_m31(my, (int64_t)b->ax);
        m[1] = rfe_fix_mul_m31(mx, (int64_t)b->ax) + rfe_fix_mul_m31(my, (int64_t)b->ay);
        m[2] = rfe_fix_mul_m31(mx, (int64_t)b->rx) + rfe_fix_mul_m31(my, (int64_t)b->ry);
        *e = ef - 36;
        norm30_q31(m, 3u, e);
    }
}


/* sum of the n terms t[k] 2^x[k] (each |.| <= 2^60; terms 0 skipped) at the largest exponent
 * of the nonzero ones, *e (a smaller one rounded half up there, 1/2 unit): |sum| < 3 2^60 for
 * n <= 3, exact but for those roundings. 0 (e = 0) when all are 0. */
static int64_t aligned_sum_q31(const int64_t *t, const int *x, size_t n, int *e)
{
    int emax = 0;
    int any = 0;
    int64_t sum = 0;
    size_t k;
    for (k = 0u; k < n; ++k) {
        if ((t[k] != 0) && ((any == 0) || (x[k] > emax))) {
            emax = x[k];
            any = 1;
        }
    }
    for (k = 0u; k < n; ++k) {
        if (t[k] != 0) {
            const int d = emax - x[k];
            sum += rfe_fix_shr64_round(t[k], (unsigned int)d);
        }
    }
    *e = emax;
    return sum;
}

/* wc's rows per unit velocity change from the nine values v[k] 2^x[k] (|v| < 2^62): base = the
 * top bit position of the largest (max of x + bit length) - 27, each value at it (rounded half
 * up when shifted down, 1/2 unit <= 2^-27 of the largest |v 2^x|, whose top bit is at base +
 * 26 or above; shifted up exactly otherwise: x + bit length <= base + 27 keeps it below 2^27),
 * |wm| <= 2^27. */
static void wheel_block_q31(const int64_t v[9], const int x[9], wheel_cols_q31_t *wc)
{
    int top = 0;
    int any = 0;
    size_t k;
    for (k = 0u; k < 9u; ++k) {
        if (v[k] != 0) {
            const int t = x[k] + (int)rfe_q31_bitlen64(rfe_q31_mag64(v[k]));
            if ((any == 0) || (t > top)) {
                top = t;
                any = 1;
            }
        }
    }
    for (k = 0u; k < 9u; ++k) {
        const int sh = (top - 27) - x[k];
        wc->wm[k] = 0;
        if ((v[k] != 0) && (sh > 0)) {
            wc->wm[k] = (int32_t)rfe_fix_shr64_round(v[k], (unsigned int)sh);
        } else if (v[k] != 0) {
            wc->wm[k] = (int32_t)(v[k] * rfe_q31_pow2((unsigned int)(-sh)));
        } else {
            /* 0 */
        }
    }
    wc->base = top - 27;
    wc->any = any;
}

/* Wheel i's body rows per unit change of its velocity: by v_wx (k = 0..2), v_wy (3..5) and
 * omega R (6..8): the rows of each slip's force derivative (fj, body_part_q31: B_k, B_t, B_v at
 * 30 bits) times the slips' sensitivities (slip_sens_q31, 30 bits), the chain of meas_flt.c
 * input_direction and wheel_input_sums formed once per wheel instead of once per input:
 *   v_wx: B_k kx + B_t tx + B_v,  v_wy: B_t ty,  omega R: B_k kr,
 * each product of two 30-bit mantissas exact (<= 2^60), the v_wx row's three terms (B_v as
 * B_v 2^30 at its exponent - 30) summed at the largest exponent (aligned_sum_q31, < 2^61.6),
 * then all nine at one exponent (wheel_block_q31). */
void rfe_meas_wheel_rows_q31(const rfe_meas_q31_t *h, const rfe_vehicle_q31_t *veh,
                             const rfe_tyre_params_q31_t *tp, const rfe_sample_q31_t *u, size_t i,
                             int32_t tan_a, const lat_q36_t *bm, const rfe_tyre_jac_q31_t fj[3],
                             wheel_cols_q31_t *wc)
{
    slip_sens_q31_t sens;
    const slip_sens_q31_t *ss = &sens;
    int64_t bk[3];
    int64_t bt[3];
    int64_t bv[3];
    int ek = 0;
    int et = 0;
    int ev = 0;
    int64_t v[9];
    int x[9];
    size_t r;
    slip_sens_q31(h, veh, tp, u, i, tan_a, &sens);
    body_part_q31(bm, fj[0].dfx, fj[0].dfy, bk, &ek);
    body_part_q31(bm, fj[1].dfx, fj[1].dfy, bt, &et);
    body_part_q31(bm, fj[2].dfx, fj[2].dfy, bv, &ev);
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        int64_t t[3];
        int xt[3];
        t[0] = bk[r] * ss->kx.m;
        xt[0] = ek + ss->kx.e;
        t[1] = bt[r] * ss->tx.m;
        xt[1] = et + ss->tx.e;
        t[2] = bv[r] * rfe_q31_pow2(30u);
        xt[2] = ev - 30;
        v[r] = aligned_sum_q31(t, xt, 3u, &x[r]);
        v[3u + r] = bt[r] * ss->ty.m;
        x[3u + r] = et + ss->ty.e;
        v[6u + r] = bk[r] * ss->kr.m;
        x[6u + r] = ek + ss->kr.e;
    }
    wheel_block_q31(v, x, wc);
}

void rfe_meas_turn_rows_q31(const lat_q36_t *bm, rfe_xf_t fx, rfe_xf_t fy, wheel_cols_q31_t *wc)
{
    int64_t ft[3];
    size_t r;
    body_part_q31(bm, fx, fy, ft, &wc->fte);
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        wc->ftm[r] = (int32_t)ft[r]; /* <= 2^30 (norm30_q31) */
    }
}

/* Input j's change of wheel i's velocity (d v_wx, d v_wy, d(omega R)) per unit, integers in
 * Q(returned), |.| < 2^31 (meas_flt.c input_change): vx, vy, r move the body velocity (dbx,
 * dby) = (1, 0), (0, 1), (-y_i, x_i), rotated into wheel axes by c, s (Q30): (c, -s) and (s,
 * c) in Q30, r's in Q28 (lengths Q29 x Q30 = Q59, a sum of two exact, < 2^62, rounded by 31:
 * |.| <= |(x_i, y_i)| < 4 sqrt 2 m, < 2^30.5); delta turns the wheel velocity, (v_wy, -v_wx) in
 * Q21 (vw); the wheel's own speed moves omega R by R (Q29). */
static int input_change_q31(const rfe_vehicle_q31_t *veh, size_t j, size_t i, int32_t c,
                            int32_t s, const int32_t vw[2], int32_t dv[3])
{
    int q = 30;
    dv[0] = 0;
    dv[1] = 0;
    dv[2] = 0;
    if (j == (size_t)RFE_IN_DELTA) {
        dv[0] = vw[1];
        dv[1] = -vw[0];
        q = 21;
    } else if (j >= (size_t)RFE_IN_OMEGA) {
        dv[2] = veh->R;
        q = (int)RFE_FIX_Q_LEN;
    } else if (j == (size_t)RFE_IN_VX) {
        dv[0] = c;
        dv[1] = -s;
    } else if (j == (size_t)RFE_IN_VY) {
        dv[0] = s;
        dv[1] = c;
    } else {
        const int64_t x = (i < (size_t)RFE_RL) ? (int64_t)veh->Lf : -(int64_t)veh->Lr;
        const int64_t yy = (i < (size_t)RFE_RL) ? (int64_t)veh->yf : (int64_t)veh->yr;
        const int64_t y = ((i == (size_t)RFE_FL) || (i == (size_t)RFE_RL)) ? yy : -yy;
        dv[0] = (int32_t)rfe_fix_shr64_round(
            rfe_fix_mul_m31(x, (int64_t)s) - rfe_fix_mul_m31(y, (int64_t)c), 31u);
        dv[1] = (int32_t)rfe_fix_shr64_round(
            rfe_fix_mul_m31(x, (int64_t)c) + rfe_fix_mul_m31(y, (int64_t)s), 31u);
        q = 28;
    }
    return q;
}

/* sum 2^e times sd (Q(qsd), > 0) in Q24, rounded half up, saturating (counted in *count): sum
 * (|.| < 2^63) rounded to 31 bits first (2^-31 relative), its product with sd (< 2^62)
 * rounded once more (rfe_meas_q24_of_scaled_q31). */
static rfe_fix_t scaled_entry_q31(int64_t sum, int e, rfe_fix_t sd, int qsd, uint32_t *count)
{
    const unsigned int len = rfe_q31_bitlen64(rfe_q31_mag64(sum));
    const unsigned int sh = (len > 31u) ? (unsigned int)(len - 31u) : 0u;
    const int64_t p = rfe_fix_mul_m31(rfe_fix_shr64_round(sum, sh), (int64_t)sd); /* <= 2^31 */
    return rfe_meas_q24_of_scaled_q31(p, ((e + (int)sh) - qsd) + 24, count);
}

/* Row r of input j's column over the wheels it reaches: each wheel's rows times the input's
 * change of its velocity (input_change_q31, Q(q)), three exact products (|.| <= 3 2^27 2^31 <
 * 2^60), at the exponent base - q; for delta also the turned forces' rows (mantissa <= 2^30).
 * All terms are brought to the largest of their exponents, E (for the forces' terms their
 * exponent - 30; a smaller term rounded half up, 1/2 unit of 2^E: the W terms' units are 2^-27
 * of each wheel's largest row entry times the unit of the velocity change), and summed exactly
 * (at most four wheels and two turned forces, each < 2^60: < 2^63): the sum is returned, E in
 * *e. */
static int64_t column_row_q31(const wheel_cols_q31_t wc[RFE_WHEELS], const int32_t *dv,
                              const int reach[RFE_WHEELS], int q, int delta, size_t r, int *e)
{
    int64_t term[2u * (size_t)RFE_WHEELS];
    int ex[2u * (size_t)RFE_WHEELS];
    int emax = 0;
    int any = 0;
    int64_t sum = 0;
    size_t n = 0u;
    size_t i;
    size_t k;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        if ((reach[i] != 0) && (wc[i].any != 0)) {
            const int32_t *d = &dv[3u * i];
            term[n] = rfe_fix_mul32x32(wc[i].wm[r], d[0]) +
                      rfe_fix_mul32x32(wc[i].wm[3u + r], d[1]) +
                      rfe_fix_mul32x32(wc[i].wm[6u + r], d[2]);
            ex[n] = wc[i].base - q;
            ++n;
        }
        if ((reach[i] != 0) && (delta != 0) && (wc[i].ftm[r] != 0)) {
            term[n] = (int64_t)wc[i].ftm[r] * rfe_q31_pow2(30u);
            ex[n] = wc[i].fte - 30;
            ++n;
        }
    }
    for (k = 0u; k < n; ++k) {
        if ((any == 0) || (ex[k] > emax)) {
            emax = ex[k];
            any = 1;
        }
    }
    for (k = 0u; k < n; ++k) {
        const int d = emax - ex[k];
        sum += rfe_fix_shr64_round(term[k], (unsigned int)d);
    }
    *e = emax;
    return sum;
}

/* Input j's column (G[r RFE_INPUTS + j], Q24): sd_j (in input j's format) times dh/du_j, each
 * row rounded once, saturating (counted in *count); 0 for sd_j <= 0. */
void rfe_meas_input_column_q31(const wheel_cols_q31_t wc[RFE_WHEELS],
                               const rfe_vehicle_q31_t *veh, size_t j, rfe_fix_t sdj,
                               rfe_fix_t G[(size_t)RFE_MEAS * (size_t)RFE_INPUTS], uint32_t *count)
{
    int32_t dv[3u * (size_t)RFE_WHEELS];
    int reach[RFE_WHEELS];
    int q = 30;
    int delta = 0;
    size_t i;
    size_t r;
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        G[(r * (size_t)RFE_INPUTS) + j] = 0;
    }
    if (sdj <= 0) {
        return;
    }
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        reach[i] = rfe_input_reaches(j, i);
        if (reach[i] != 0) {
            q = input_change_q31(veh, j, i, wc[i].c, wc[i].s, wc[i].vw, &dv[3u * i]);
        }
    }
    if (j == (size_t)RFE_IN_DELTA) {
        delta = 1;
    }
    for (r = 0u; r < (size_t)RFE_MEAS; ++r) {
        int e = 0;
        const int64_t sum = column_row_q31(wc, dv, reach, q, delta, r, &e);
        G[(r * (size_t)RFE_INPUTS) + j] = scaled_entry_q31(sum, e, sdj, input_q_q31(j), count);
    }
}
