/**
 * @file test_tyre_magic_q31.c
 * @brief The fixed-point Magic Formula tyre (rfe_tyre_magic_abs_q31, the magic mode of
 *        rfe_tyre_forces_abs_q31, rfe_tyre_dugoff_abs_pre_q31) against the formula of
 *        docs/ESTIMATOR.md "The Magic Formula tyre" evaluated in double here, and against the
 *        double twin rfe_tyre_magic_abs_f64 on every bundled log; its properties (zero force
 *        at zero slip and at mu <= 0, |F| <= mu Fz, left/right mirror), the dispatch of the
 *        four-wheel function, saturation counting, determinism, argument checks.
 *
 * Setup. The double reference gets the Q values of the inputs and of the parameters (cx, cy,
 * alpha_max, the shape factors) converted exactly, so every difference is an error of the
 * integer evaluation (no parameter rounding). U = 2^-29 (1 LSB29), LSB15 = 2^-15 N.
 * Per direction d with C = shape_Cd, E = shape_Ed, m = max(mu, 0), s = |(cx k, cy t)|,
 * x = s / (m C), T(x) = x - E (x - atan x), theta = atan2(s, m C), b = atan T(tan theta),
 * G = sin(C b), psi(s) = m G, F_d = Fz psi(s) v_d / s (v = (cx k, cy t)).
 *
 * Two constants of the curve (for 1 < C < 2, -4 <= E < 1):
 *  - K_E, a bound of |psi'(s)| = |cos phi| T'(x) / (1 + T^2) and of psi(s) / s (its mean):
 *    E >= 0: T' <= 1, so K_E = 1; E < 0: T >= x and T' = 1 + |E| w with w = x^2 / (1 + x^2),
 *    so T' / (1 + T^2) <= (1 + |E| w)(1 - w) <= (1 - E)^2 / (-4 E) for E <= -1, 1 above.
 *    The Jacobian of F(v) = Fz psi_d(|v|) v_d / |v| then has every entry <= Fz K_E (the
 *    mixed one is Fz (v_x v_y / r^2)(psi' - psi / r), the diagonal a convex combination of
 *    psi' and psi / r).
 *  - K_b, a bound of db / dtheta = (1 + (1 - E) t^2) / (1 + T(t)^2), t = tan theta:
 *    E >= 0: T >= (1 - E) t, so K_b = 1 / (1 - E); E < 0: T >= t, so K_b = 1 - E. (As
 *    E -> 1 the curve is ill-conditioned in the slip ratio itself: K_b = 2^24 at the largest
 *    Q24 value below 1; the bound says so honestly.)
 *
 * Error of the integer evaluation (tyre_q31.c) given its inputs S (Q(qs)), u (Q30):
 *  - first angle: the pair (S, m C) scaled to 30 bits, the larger >= 2^29: 0.71 U; atan2 in
 *    Q31 by rfe_q31_atan2_quad1 (fxmath_internal_q31.h, the Magic Formula's short CORDIC):
 *    e_at = 5.2 2^-32 = 1.211e-9 rad (0.65 U);
 *  - second angle (E != 0): K_b 0.71 U (the first pair's rounding, through the curve),
 *    |E| e_at (z carries E x da), 0.5 U (z rounded in Q(W + 24): 0.5 2^-24 over
 *    |(x, z)| >= 32 units), 0.71 U (the second pair), e_at (atan2); for E = 0, b = a;
 *    so e_b = K_b 0.71 U + e_at + [E != 0] (|E| e_at + 1.21 U);
 *  - G: phi = C b is exact (Q24 x Q31 = Q55), and rfe_q31_sin_q55 is within e_sin = 6.15e-10
 *    (0.66 LSB30, 0.33 U): |d sin| <= C e_b + e_sin = e_G;
 *  - w = m G rounded to Q29 (0.5 U): Fz (1 + 2^-30)(m e_G + 0.5 U) in the force (|u| <= 1);
 *  - the Dugoff set-up's S and u (shared): the components rounded to 30 bits (0.71 ulp_s),
 *    S exactly rounded (0.5 ulp_s), C1 k rounded to Q50 (0.5 2^-50): eps_S <= 1.71 ulp_s,
 *    ulp_s = 2^-qs. When S >= 2^29 ulp_s (the set-up shifted): eps_S / S <= 1.71 U, so
 *    |psi(S) - psi(s)| <= m C K_b 0.5 (eps_S / S) (dtheta / d ln s <= 1/2) <= 0.88 m C K_b U
 *    and |u_q - u| <= 2 eps_S / S + 2^-31 (quotients exactly rounded in Q30), times
 *    psi <= m: 3.75 m U. When ulp_s = 2^-50 (no shift): |dpsi| <= K_E 1.71 2^-50 and
 *    psi |du| <= K_E s 2.71 2^-50 / S + m 2^-31 <= 7.35 K_E 2^-50 + 0.25 m U. Both cases:
 *    Fz (m (0.88 C K_b + 3.75) U + 10 K_E 2^-50);
 *  - the force rounded once to Q15: 0.5 LSB15.
 * Against the exact tan(alpha) the Q26 tangent (rfe_q31_tan_q29, q31_trig_bounds.h: TAN(a) =
 * 2^-27 + 6.16e-10 (1 + |tan a|) / (cos a - 6.16e-10)) adds Fz K_E cy TAN(a).
 * So, per direction,
 *   B_d = 0.5 LSB15 + Fz [K_E cy TAN(a)] + Fz (1 + 2^-30)(m e_G + 0.5 U)
 *         + Fz (m (0.88 C K_b + 3.75) U + 10 K_E 2^-50) + 1e-14 Fz m (the reference's own
 *         double rounding).
 * For the default tyre (cx = 20, cy = 15, C = 1.65 / 1.3, E = 0) at mu = 1, Fz = 5 kN, above
 * the output rounding: 6.7e-4 N (22 LSB15) against the exact tangent, dominated by the
 * tangent's format (5.9e-4 N) as in the Dugoff tyre; 7.7e-5 N (2.5 LSB15) at the Q26 tangent,
 * of which the angles, the sine and the rounding of w are 2.9e-5 N (3.0e-5 N with the 40-step
 * CORDIC of rfe_fix_atan2 / rfe_fix_sincos and phi rounded to Q29, before the short routines).
 *
 * Saturation: a force beyond +-65536 N clamps and counts once; the count must be between the
 * number of outputs whose double value is beyond the range by more than the bound and the
 * number beyond it minus the bound. The measured worst cases are printed (docs/FIXED_POINT.md
 * quotes them).
 */
#include "test_light.h"
#include "test_common.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "q31_rows.h"
#include "rfe/config.h"
#include "host/fixed_conv.h"
#include "rfe/component/fxmath.h"
#include "rfe/component/params_conv.h"
#include "rfe/component/tyre.h"
#include "rfe/component/tyre_q31.h"
#include "numerics/fxmath_internal_q31.h"
#include "numerics/internal_q31.h"
#include "q31_trig_bounds.h"
#include "test_rng.h"
#include "models/tyre_internal_q31.h"

#define U_ ldexp(1.0, -29)
#define EAT (5.2 * ldexp(1.0, -32)) /* rfe_q31_atan2_quad1 [rad] */
#define ESIN 6.15e-10               /* rfe_q31_sin_q55 */
#define LSB15 ldexp(1.0, -15)
#define FMAX_N (2147483647.0 / 32768.0) /* largest Q15 force [N] */
#define ONE24 (1 << 24)
#define SENT ((int32_t)0x5A5A5A5A)

static rfe_params_q31_t pq;     /* default preset, q31 (magic mode) */
static rfe_params_t pd;         /* default preset, double */

/* ---- conversions -------------------------------------------------------------------------- */

static int32_t toq(double x, int q)
{
    uint32_t s = 0u;
    return rfe_fix_from_double(x, (unsigned)q, &s);
}
static double fromq(int32_t v, int q) { return rfe_fix_to_double(v, (unsigned)q); }

/* ---- the reference and the bound ---------------------------------------------------------- */

/* The tyre parameters of a q31 set as doubles (exact). */
typedef struct {
    double cx, cy, amax, C[2], E[2];
} mtp_t;

static mtp_t mtp_of(const rfe_tyre_params_q31_t *tp)
{
    mtp_t t;
    t.cx = fromq(tp->cx, 24);
    t.cy = fromq(tp->cy, 24);
    t.amax = fromq(tp->alpha_max, 29);
    t.C[0] = fromq(tp->shape_Cx, 24);
    t.E[0] = fromq(tp->shape_Ex, 24);
    t.C[1] = fromq(tp->shape_Cy, 24);
    t.E[1] = fromq(tp->shape_Ey, 24);
    return t;
}

/* docs/ESTIMATOR.md "The Magic Formula tyre" in double. tq: the tangent to use (NAN: the exact
 * tan of the clamped alpha). */
static void ref_forces(const mtp_t *t, double kappa, double alpha, double fz, double mu,
                       double tq, double F[2])
{
    const double k = fmin(fmax(kappa, -1.0), 1.0);
    const double a = fmin(fmax(alpha, -t->amax), t->amax);
    const double tt = isnan(tq) ? tan(a) : tq;
    const double v[2] = {t->cx * k, t->cy * tt};
    const double s = hypot(v[0], v[1]);
    const double m = fmax(mu, 0.0);
    int d;
    for (d = 0; d < 2; ++d) {
        if (s == 0.0 || m == 0.0) {
            F[d] = 0.0;
        } else {
            const double mc = m * t->C[d];
            const double a1 = atan2(s, mc);
            const double G = sin(t->C[d] * atan2(s - t->E[d] * (s - mc * a1), mc));
            F[d] = fz * m * G * (v[d] / s);
        }
    }
}

static double k_e(double E) { return (E < -1.0) ? (1.0 - E) * (1.0 - E) / (-4.0 * E) : 1.0; }
static double k_b(double E) { return (E < 0.0) ? 1.0 - E : 1.0 / (1.0 - E); }

/* The bound of direction d (file comment); exact_tan: against tan(alpha) (else at the Q26
 * tangent). */
/* tan_err: the Q26 tangent's error against the exact one (q31b_tan of the clamped angle), or 0
 * against the Q26 tangent itself. */
static double magic_bound(const mtp_t *t, int d, double fz, double mu, double tan_err)
{
    const double m = fmax(mu, 0.0);
    const double C = t->C[d], E = t->E[d];
    const double KE = k_e(E), Kb = k_b(E);
    const double eb = Kb * 0.71 * U_ + EAT + ((E != 0.0) ? fabs(E) * EAT + 1.21 * U_ : 0.0);
    const double eG = C * eb + ESIN;
    double b = 0.5 * LSB15 + fz * (1.0 + ldexp(1.0, -30)) * (m * eG + 0.5 * U_) +
               fz * (m * (0.88 * C * Kb + 3.75) * U_ + 10.0 * KE * ldexp(1.0, -50)) + 1e-14 * fz * m;
    return b + fz * KE * t->cy * tan_err;
}

/* ---- worst-case tracking ---------------------------------------------------------------- */

/* max_ratio: err / bound; max_inner: (err - 0.5 LSB15) / (bound - 0.5 LSB15), the part of
 * the bound above the final rounding (which alone reaches 1 on tiny loads). */
typedef struct {
    const char *name;
    double max_abs, max_ratio, max_inner, max_rel;
    long n;
    char where[200];
} worst_t;

static worst_t w_exact = {"magic vs formula, exact tan", 0, 0, 0, 0, 0, {0}};
static worst_t w_qtan = {"magic vs formula, Q26 tan", 0, 0, 0, 0, 0, {0}};
static worst_t w_twin = {"magic vs double twin (logs)", 0, 0, 0, 0, 0, {0}};

static void reset(worst_t *w)
{
    w->max_abs = w->max_ratio = w->max_inner = w->max_rel = 0.0;
    w->n = 0;
    w->where[0] = '\0';
}

static void report(const worst_t *w)
{
    printf("  %-28s n=%-7ld max |err| %.3e N (%.1f LSB15), rel %.2e (|F| >= 100 N); "
           "err/bound %.3f, above the output rounding %.3f\n",
           w->name, w->n, w->max_abs, w->max_abs / LSB15, w->max_rel, w->max_ratio, w->max_inner);
    if (getenv("RFE_TEST_VERBOSE") != NULL) {
        printf("      worst (err - rounding)/(bound - rounding) at %s\n", w->where);
    }
}

/* One force against its reference: in range, or (beyond the Q15 range) saturated. Returns the
 * number of saturations this output may (bit 0) and must (bit 1) have. */
static unsigned check_force(worst_t *w, int32_t got_q, double want, double bound,
                            const char *ctx)
{
    const double got = fromq(got_q, 15);
    if (fabs(want) >= FMAX_N + bound) {
        if (got_q != ((want > 0) ? INT32_MAX : -INT32_MAX)) {
            fail_msg("%s %s: %.9g beyond the range but got %.9g", w->name, ctx, want, got);
        }
        return 3u;
    }
    {
        const double clamped = fmin(fmax(want, -FMAX_N), FMAX_N);
        const double err = fabs(got - clamped);
        if (err > w->max_abs) {
            w->max_abs = err;
        }
        if (fabs(want) >= 100.0 && err / fabs(want) > w->max_rel) {
            w->max_rel = err / fabs(want);
        }
        if ((err - 0.5 * LSB15) / (bound - 0.5 * LSB15) > w->max_inner) {
            w->max_inner = (err - 0.5 * LSB15) / (bound - 0.5 * LSB15);
            snprintf(w->where, sizeof(w->where), "%s (q31 %.9g, double %.9g, bound %.3g)", ctx,
                     got, want, bound);
        }
        if (err / bound > w->max_ratio) {
            w->max_ratio = err / bound;
        }
        ++w->n;
        if (!(err <= bound)) {
            fail_msg("%s %s: q31 %.17g double %.17g |diff| %.3e > bound %.3e", w->name, ctx, got,
                     want, err, bound);
        }
    }
    return (fabs(want) > FMAX_N - bound) ? 1u : 0u;
}

/* The q31 tangent the tyre uses for alpha (Q29) clamped to +-alpha_max, as a double. */
static double q_tan(const rfe_tyre_params_q31_t *tp, int32_t alpha)
{
    const int32_t a = (alpha > tp->alpha_max) ? tp->alpha_max
                                              : ((alpha < -tp->alpha_max) ? -tp->alpha_max : alpha);
    return fromq(rfe_q31_tan_q29(a), 26);
}

/* One wheel case through rfe_tyre_magic_abs_q31 against the formula (exact and Q26 tangent),
 * the saturation count checked; also the properties that hold bit for bit. Outputs the q31
 * forces. */
static void check_case(const rfe_tyre_params_q31_t *tp, int32_t kappa, int32_t alpha, int32_t fz,
                       int32_t mu, int32_t out[2])
{
    const mtp_t t = mtp_of(tp);
    const double k = fromq(kappa, 30), a = fromq(alpha, 29), f = fromq(fz, 15), m = fromq(mu, 29);
    const double a_err = q31b_tan(fmin(fabs(a), fromq(tp->alpha_max, 29)));
    double Fe[2], Fq[2];
    int32_t fq[2] = {SENT, SENT};
    uint32_t sat = 0u;
    unsigned may = 0u, must = 0u;
    char ctx[200];
    int d;
    assert_int_equal(rfe_tyre_magic_abs_q31(tp, kappa, alpha, fz, 0, mu, &fq[0], &fq[1], &sat),
                     RFE_OK);
    ref_forces(&t, k, a, f, m, NAN, Fe);
    ref_forces(&t, k, a, f, m, q_tan(tp, alpha), Fq);
    for (d = 0; d < 2; ++d) {
        unsigned r;
        snprintf(ctx, sizeof(ctx), "%s k %.6g a %.6g fz %.6g mu %.6g C %.8g E %.8g", d ? "Fy" : "Fx",
                 k, a, f, m, t.C[d], t.E[d]);
        r = check_force(&w_exact, fq[d], Fe[d], magic_bound(&t, d, f, m, a_err), ctx);
        (void)check_force(&w_qtan, fq[d], Fq[d], magic_bound(&t, d, f, m, 0.0), ctx);
        may += r & 1u;
        must += (r >> 1) & 1u;
        /* |F_d| <= m Fz exactly (w <= m, |u_d| <= 1), plus the final rounding */
        if (!(fabs(fromq(fq[d], 15)) <= fmax(m, 0.0) * f + 0.5 * LSB15)) {
            fail_msg("%s: |F| %.9g > mu Fz %.9g", ctx, fromq(fq[d], 15), fmax(m, 0.0) * f);
        }
    }
    if (sat < must || sat > may) {
        fail_msg("k %.6g a %.6g fz %.6g mu %.6g: %u saturations, expected %u..%u", k, a, f, m,
                 sat, must, may);
    }
    /* and the vector: |F| <= mu Fz (1 + 2^-28) + 1 LSB15 */
    assert_true(hypot(fromq(fq[0], 15), fromq(fq[1], 15)) <=
                fmax(m, 0.0) * f * (1.0 + ldexp(1.0, -28)) + LSB15);
    /* zero at zero slip and at mu <= 0, bit for bit */
    if (mu <= 0 || (kappa == 0 && alpha == 0)) {
        assert_int_equal(fq[0], 0);
        assert_int_equal(fq[1], 0);
    }
    out[0] = fq[0];
    out[1] = fq[1];
}

/* Tyre parameters: the default's with the given shape factors (Q24) and stiffnesses. */
static rfe_tyre_params_q31_t tyre_with(int32_t Cx, int32_t Ex, int32_t Cy, int32_t Ey)
{
    rfe_tyre_params_q31_t tp = pq.tyre;
    tp.shape_Cx = Cx;
    tp.shape_Ex = Ex;
    tp.shape_Cy = Cy;
    tp.shape_Ey = Ey;
    return tp;
}

static int setup(void **state)
{
    (void)state;
    if (rfe_params_default_f64(&pd) != RFE_OK || rfe_params_to_q31_f64(&pd, &pq) != RFE_OK) {
        return -1;
    }
    return 0;
}

/* ---- the grid ------------------------------------------------------------------------------- */

/* The shape factors: the default, each at its bounds (1 < C < 2: 1 + 1 LSB, 2 - 1 LSB;
 * -4 <= E < 1: -4, 1 - 1 LSB), the simulator's E = -1 and between. */
static const int32_t SHAPES[][4] = {
    {27682406, 0, 21810381, 0},                               /* default 1.65, 0, 1.3, 0 */
    {ONE24 + 1, 0, 2 * ONE24 - 1, 0},                         /* C at its bounds */
    {2 * ONE24 - 1, -4 * ONE24, ONE24 + 1, ONE24 - 1},        /* E at its bounds */
    {ONE24 + 1, ONE24 - 1, 2 * ONE24 - 1, -4 * ONE24},        /* both, crossed */
    {27682406, -ONE24, 21810381, -ONE24},                     /* E = -1 (simulator's E_y) */
    {27682406, ONE24 / 2, 21810381, -2 * ONE24},              /* E = 0.5, -2 */
    {25165824, 15938355, 30198989, -52428800},                /* 1.5, 0.95, 1.8, -3.125 */
};

/* REQ: the q31 Magic Formula forces agree with the formula evaluated in double over a grid of
 * kappa (beyond the clip), alpha (beyond alpha_max), mu (below 0, 0, 1 LSB, tiny, 1.2, up to
 * 3.99), loads (0 to 40 kN, saturating at high mu) and shape factors at their bounds, within
 * the derived bound (exact tangent and Q26 tangent); |F| <= mu Fz; zero force at zero slip and
 * at mu <= 0; saturations counted. */
/* REQ-TYRE-007 REQ-FXP-003 REQ-FXP-008 */
static void test_magic_q31_grid(void **state)
{
    static const double KAPPA[] = {0.0,   1e-9,  -1e-9, 1e-6,  -3e-5, 1e-3, -0.003, 0.02,
                                   -0.05, 0.1,   -0.2,  0.35,  -0.6,  0.9,  -1.0,   1.0,
                                   1.7,   -3.0};
    static const double ALPHA[] = {0.0,  1e-8,  -1e-6, 0.003, -0.01, 0.04, -0.08,
                                   0.15, -0.3, 0.6,   -0.9,  1.2,   -1.4, 1.45};
    static const double MU[] = {-0.5, -1e-9, 0.0, 1.9e-9, 1e-6, 1e-3, 0.05, 0.3,
                                0.8,  1.2,   2.0, 3.99};
    static const double FZ[] = {0.0, 3.1e-5, 100.0, 4000.0, 12000.0, 40000.0};
    size_t s, i, j, l, f;
    long n = 0;
    (void)state;
    reset(&w_exact);
    reset(&w_qtan);
    for (s = 0; s < sizeof(SHAPES) / sizeof(SHAPES[0]); ++s) {
        const rfe_tyre_params_q31_t tp = tyre_with(SHAPES[s][0], SHAPES[s][1], SHAPES[s][2],
                                                   SHAPES[s][3]);
        for (i = 0; i < sizeof(KAPPA) / sizeof(KAPPA[0]); ++i) {
            for (j = 0; j < sizeof(ALPHA) / sizeof(ALPHA[0]); j += rfe_test_stride(3u)) {
                for (l = 0; l < sizeof(MU) / sizeof(MU[0]); ++l) {
                    for (f = 0; f < sizeof(FZ) / sizeof(FZ[0]); ++f) {
                        int32_t out[2];
                        check_case(&tp, toq(KAPPA[i], 30), toq(ALPHA[j], 29), toq(FZ[f], 15),
                                   toq(MU[l], 29), out);
                        ++n;
                    }
                }
            }
        }
    }
    printf("grid: %ld wheel cases (%zu shape sets)\n", n, sizeof(SHAPES) / sizeof(SHAPES[0]));
    report(&w_exact);
    report(&w_qtan);
}

static double uni(double a, double b) { return a + (b - a) * 0.5 * (rng_uniform() + 1.0); }

/* A value with a log-uniform magnitude in [1e-6 a, a] and a random sign. */
static double logu(double a)
{
    const double m = a * pow(10.0, uni(-6.0, 0.0));
    return (rng_uniform() < 0.0) ? -m : m;
}

/* REQ: 1e5 random single-wheel cases: stiffnesses 1..60, shape factors anywhere in their
 * domain, kappa and alpha uniform and log-uniform (beyond the clips), mu in [-0.5, 3.9],
 * loads up to 60 kN: within the derived bound. */
/* REQ-TYRE-007 REQ-FXP-003 */
static void test_magic_q31_random(void **state)
{
    int n;
    const int N = rfe_test_light() ? 10000 : 100000;
    (void)state;
    reset(&w_exact);
    reset(&w_qtan);
    rng_seed(0x3A61Cull);
    for (n = 0; n < N; ++n) {
        rfe_tyre_params_q31_t tp = pq.tyre;
        const int kind = n % 4;
        int32_t out[2];
        double k, a;
        tp.cx = toq(uni(1.0, 60.0), 24);
        tp.cy = toq(uni(1.0, 60.0), 24);
        tp.alpha_max = toq(uni(0.2, 1.49), 29);
        tp.shape_Cx = ONE24 + 1 + (int32_t)((ONE24 - 2) * 0.5 * (rng_uniform() + 1.0));
        tp.shape_Cy = ONE24 + 1 + (int32_t)((ONE24 - 2) * 0.5 * (rng_uniform() + 1.0));
        tp.shape_Ex = (kind == 0) ? 0 : toq(uni(-4.0, 0.99), 24);
        tp.shape_Ey = (kind == 0) ? 0 : toq(uni(-4.0, 0.99), 24);
        if (kind == 1) {
            k = logu(1.0);
            a = logu(1.5);
        } else {
            k = uni(-1.2, 1.2);
            a = uni(-1.6, 1.6);
        }
        check_case(&tp, toq(k, 30), toq(a, 29), toq(uni(0.0, 60000.0), 15),
                   toq((kind == 2) ? logu(1.0) : uni(-0.5, 3.9), 29), out);
    }
    printf("random: %d wheel cases\n", N);
    report(&w_exact);
    report(&w_qtan);
}

/* ---- the bundled logs against the double twin ----------------------------------------------- */

static const char *const SCENARIO[19] = {
    "accel_low_mu",       "brake_in_turn",      "cruise",          "hard_brake_high_mu",
    "hard_brake_low_mu",  "mu_step_hard_brake", "paper_high_mu_brake", "paper_low_mu_brake",
    "paper_mu_step",      "sine_steer_high_mu", "sine_steer_low_mu", "split_mu_brake",
    "split_mu_hard_brake",
    /* issue 17 */
    "double_lane_change_high_mu", "double_lane_change_low_mu", "ramp_steer_high_mu",
    "ramp_steer_low_mu", "brake_in_turn_low_mu", "wrong_tyre_data"};
static const char *const VARIANT[3] = {"", ".mf", ".nf"};

/* REQ: on every sample of every bundled log (19 scenarios x 3 truth variants), at the log's
 * true mu and at mu = 0.2 and 1.0, the four-wheel q31 forces in magic mode (from the q31
 * kinematics) agree with the double twin rfe_tyre_magic_abs_f64 on the same inputs and
 * parameter values within the derived bound. */
/* REQ-FXP-003 REQ-TYRE-007 */
static void test_magic_q31_scenarios_twin(void **state)
{
    rfe_tyre_params_t td = pd.tyre; /* the q31 values as doubles: no parameter rounding */
    const mtp_t t = mtp_of(&pq.tyre);
    size_t s, v, r, n_rows = 0;
    (void)state;
    reset(&w_twin);
    assert_int_equal(pq.tyre.mode, RFE_TYRE_MAGIC);
    td.cx = t.cx;
    td.cy = t.cy;
    td.alpha_max = t.amax;
    td.shape_Cx = t.C[0];
    td.shape_Ex = t.E[0];
    td.shape_Cy = t.C[1];
    td.shape_Ey = t.E[1];
    for (s = 0; s < 19; ++s) {
        for (v = 0; v < 3; v += rfe_test_stride(3u)) {
            char path[256], ctx[300];
            rfe_sensor_log_t log;
            rfe_io_error_t err;
            memset(&log, 0, sizeof(log));
            snprintf(path, sizeof(path), "scenarios/%s%s.csv", SCENARIO[s], VARIANT[v]);
            if (rfe_sensor_log_read(path, &log, &err) != 0) {
                fail_msg("%s:%zu: %s", path, err.line, err.msg);
            }
            /* light mode (valgrind): every 10th row (each row is checked on its own) */
            for (r = 0; r < log.n_rows; r += rfe_test_stride(10u)) {
                const rfe_sensor_row_t *row = &log.rows[r];
                rfe_sample_q31_t uq;
                rfe_wheel_kin_q31_t kq;
                uint32_t sat = 0u;
                size_t i, c;
                q31_sample_from_row(row, &uq);
                assert_int_equal(rfe_tyre_kinematics_q31(&pq.vehicle, &pq.tyre, &uq, &kq, &sat),
                                 RFE_OK);
                for (c = 0; c < 3; ++c) {
                    rfe_fix_t muq[4], fx[4], fy[4];
                    for (i = 0; i < 4; ++i) {
                        muq[i] = toq((c == 0) ? row->mu_true[i] : ((c == 1) ? 0.2 : 1.0), 29);
                    }
                    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &kq, muq, fx, fy, &sat),
                                     RFE_OK);
                    for (i = 0; i < 4; ++i) {
                        const double k = fromq(kq.kappa[i], 30), a = fromq(kq.alpha[i], 29);
                        const double fz = fromq(kq.fz[i], 15), m = fromq(muq[i], 29);
                        double F[2];
                        assert_int_equal(rfe_tyre_magic_abs_f64(&td, k, a, fz,
                                                                fromq(kq.vwx[i], 23), m, &F[0],
                                                                &F[1]),
                                         RFE_OK);
                        snprintf(ctx, sizeof(ctx), "%s row %zu wheel %zu mu %.3f", path, r, i, m);
                        (void)check_force(&w_twin, fx[i], F[0], magic_bound(&t, 0, fz, m, q31b_tan(fmin(fabs(a), td.alpha_max))), ctx);
                        (void)check_force(&w_twin, fy[i], F[1], magic_bound(&t, 1, fz, m, q31b_tan(fmin(fabs(a), td.alpha_max))), ctx);
                    }
                }
                assert_int_equal(sat, 0u);
            }
            n_rows += log.n_rows;
            rfe_sensor_log_free(&log);
        }
    }
    printf("logs: %zu samples x 4 wheels x 3 friction values\n", n_rows);
    report(&w_twin);
}

/* ---- properties ------------------------------------------------------------------------------ */

/* REQ: left/right mirror: alpha -> -alpha gives (Fx, -Fy), kappa -> -kappa gives (-Fx, Fy),
 * within the sum of the two cases' bounds at the Q26 tangent (the double reference is exactly
 * symmetric: tan is exactly odd); most cases bit for bit (only a tie of a half-up rounding of
 * a negative value can break the symmetry). */
/* REQ-TYRE-005 REQ-TYRE-007 */
static void test_magic_q31_mirror(void **state)
{
    int n;
    long exact = 0, total = 0;
    (void)state;
    rng_seed(0x31EEull);
    for (n = 0; n < 20000; n += (int)rfe_test_stride(10u)) {
        const size_t si = (size_t)n % (sizeof(SHAPES) / sizeof(SHAPES[0]));
        const rfe_tyre_params_q31_t tp = tyre_with(SHAPES[si][0], SHAPES[si][1], SHAPES[si][2],
                                                   SHAPES[si][3]);
        const mtp_t t = mtp_of(&tp);
        const int32_t k = toq(uni(-1.0, 1.0), 30), a = toq(uni(-1.4, 1.4), 29);
        const int32_t fz = toq(uni(0.0, 20000.0), 15), mu = toq(uni(0.0, 1.5), 29);
        const double m = fromq(mu, 29), f = fromq(fz, 15);
        int32_t p[2], q[2], r[2];
        uint32_t sat = 0u;
        assert_int_equal(rfe_tyre_magic_abs_q31(&tp, k, a, fz, 0, mu, &p[0], &p[1], &sat), RFE_OK);
        assert_int_equal(rfe_tyre_magic_abs_q31(&tp, k, -a, fz, 0, mu, &q[0], &q[1], &sat), RFE_OK);
        assert_int_equal(rfe_tyre_magic_abs_q31(&tp, -k, a, fz, 0, mu, &r[0], &r[1], &sat), RFE_OK);
        assert_true(fabs(fromq(q[0], 15) - fromq(p[0], 15)) <= 2.0 * magic_bound(&t, 0, f, m, 0.0));
        assert_true(fabs(fromq(q[1], 15) + fromq(p[1], 15)) <= 2.0 * magic_bound(&t, 1, f, m, 0.0));
        assert_true(fabs(fromq(r[0], 15) + fromq(p[0], 15)) <= 2.0 * magic_bound(&t, 0, f, m, 0.0));
        assert_true(fabs(fromq(r[1], 15) - fromq(p[1], 15)) <= 2.0 * magic_bound(&t, 1, f, m, 0.0));
        exact += (q[0] == p[0] && q[1] == -p[1] && r[0] == -p[0] && r[1] == p[1]) ? 1 : 0;
        ++total;
        assert_int_equal(sat, 0u);
    }
    printf("mirror: %ld of %ld cases bit for bit\n", exact, total);
    assert_true(exact * 10 >= total * 9);
}

/* White box: the argument z of the second atan2 in tyre_q31.c's magic_g_q31 for the x
 * direction (longitudinal slip kappa, alpha = 0), before its clamp at 0, computed as there:
 * the Dugoff set-up's S, the pair (S, m C) scaled to 30 bits, a = rfe_q31_atan2_quad1 and
 * z = (1 - E) yn + E xn a. */
static int64_t second_angle_arg(const rfe_tyre_params_q31_t *tp, int32_t kappa, int32_t mu)
{
    rfe_dugoff_pre_q31_t pre;
    int64_t mc, xn, yn;
    unsigned d, lx, ly;
    int l, e;
    uint32_t a;
    rfe_tyre_dugoff_pre_q31(tp, kappa, 0, 0, &pre);
    mc = (int64_t)mu * tp->shape_Cx;
    d = 53u - pre.qs;
    lx = rfe_q31_bitlen64((uint64_t)mc);
    ly = rfe_q31_bitlen64((uint64_t)pre.s) + d;
    l = (int)((lx > ly) ? lx : ly);
    xn = (l > 30) ? rfe_fix_shr64_round(mc, (unsigned)(l - 30)) : mc * ((int64_t)1 << (30 - l));
    e = (int)d + 30 - l;
    yn = (e >= 0) ? (int64_t)pre.s * ((int64_t)1 << e) : rfe_fix_shr64_round(pre.s, (unsigned)-e);
    a = rfe_q31_atan2_quad1((uint32_t)yn, (uint32_t)xn);
    return ((int64_t)ONE24 - tp->shape_Ex) * yn + rfe_q31_mul64x32(xn * (int64_t)a, tp->shape_Ex, 31u);
}

/* REQ: the shape of the curve: zero force at zero slip and at mu <= 0 for any shape; at zero
 * slip the slope is cx Fz (cy Fz) for every mu > 0; the pure-slip peak is mu Fz (C atan = pi/2
 * reached at some slip) and the force never exceeds it; the rounding of a pushing the second
 * atan2's argument below 0 (E < 0, slip a few LSB of m C) is clamped to a zero force, not a
 * force against the slip (cases that do clamp are checked to exist). */
/* REQ-TYRE-007 REQ-FXP-003 */
static void test_magic_q31_curve_properties(void **state)
{
    const rfe_tyre_params_q31_t tp = pq.tyre;
    const int32_t fz = toq(5000.0, 15);
    double peak = 0.0;
    int32_t fx = SENT, fy = SENT;
    uint32_t sat = 0u;
    int i;
    (void)state;
    /* zero slip, any mu; any slip, mu <= 0 */
    assert_int_equal(rfe_tyre_magic_abs_q31(&tp, 0, 0, fz, 0, toq(1.0, 29), &fx, &fy, &sat), RFE_OK);
    assert_int_equal(fx, 0);
    assert_int_equal(fy, 0);
    assert_int_equal(rfe_tyre_magic_abs_q31(&tp, toq(0.1, 30), toq(0.1, 29), fz, 0, 0, &fx, &fy,
                                            &sat),
                     RFE_OK);
    assert_int_equal(fx, 0);
    assert_int_equal(fy, 0);
    assert_int_equal(rfe_tyre_magic_abs_q31(&tp, toq(0.1, 30), toq(0.1, 29), fz, 0, -5, &fx, &fy,
                                            &sat),
                     RFE_OK);
    assert_int_equal(fx, 0);
    assert_int_equal(fy, 0);
    /* slope at zero slip: F ~ cx Fz k for k -> 0, at mu 0.1 and 1 */
    for (i = 0; i < 2; ++i) {
        const double mu = (i == 0) ? 0.1 : 1.0;
        const double k = 1e-5;
        assert_int_equal(rfe_tyre_magic_abs_q31(&tp, toq(k, 30), 0, fz, 0, toq(mu, 29), &fx, &fy,
                                                &sat),
                         RFE_OK);
        assert_close(fromq(fx, 15), fromq(tp.cx, 24) * 5000.0 * k, 1e-3, 2e-3, "slope x");
        assert_int_equal(rfe_tyre_magic_abs_q31(&tp, 0, toq(k, 29), fz, 0, toq(mu, 29), &fx, &fy,
                                                &sat),
                         RFE_OK);
        assert_close(fromq(fy, 15), fromq(tp.cy, 24) * 5000.0 * tan(fromq(toq(k, 29), 29)),
                     1e-3, 2e-3, "slope y");
    }
    /* pure longitudinal slip: the peak is mu Fz (within 1e-6 relative) */
    for (i = 1; i <= 1000; ++i) {
        const int32_t k = (int32_t)((int64_t)i * (1 << 30) / 1000);
        assert_int_equal(rfe_tyre_magic_abs_q31(&tp, k, 0, fz, 0, toq(0.8, 29), &fx, &fy, &sat),
                         RFE_OK);
        assert_int_equal(fy, 0);
        peak = fmax(peak, fromq(fx, 15));
        assert_true(fromq(fx, 15) <= 0.8 * 5000.0 + LSB15);
    }
    assert_close(peak, 0.8 * 5000.0, 0.0, 2e-5, "peak");
    assert_int_equal(sat, 0u);
    /* the clamp of the second angle: E = -4, the smallest slips, mu where m C is just above a
     * power of two (the pair's x just above 2^29, y = 1 or 2 units: the Q31 rounding of a can
     * take z below 0) and mu = 3.99; second_angle_arg (white box) says which cases clamp */
    {
        static const double MUC[3] = {2.005, 2.025, 3.99};
        rfe_tyre_params_q31_t te = tyre_with(2 * ONE24 - 1, -4 * ONE24, 2 * ONE24 - 1, -4 * ONE24);
        int hit = 0, clamped = 0, j;
        te.cx = 8 * ONE24;
        for (j = 0; j < 3; ++j) {
            for (i = 1; i <= 64; ++i) {
                int32_t out[2];
                const int32_t mu = toq(MUC[j], 29);
                check_case(&te, i, 0, toq(40000.0, 15), mu, out);
                assert_true(out[0] >= 0);
                hit += (out[0] == 0) ? 1 : 0;
                if (second_angle_arg(&te, i, mu) < 0) {
                    assert_int_equal(out[0], 0); /* b = 0: G = 0 */
                    ++clamped;
                }
            }
        }
        printf("second-angle clamp: %d of 192 tiny-slip cases clamped, %d give zero force\n",
               clamped, hit);
        assert_true(clamped > 0);
    }
}

/* REQ: rfe_tyre_forces_abs_q31 dispatches on the mode: magic -> rfe_tyre_magic_abs_q31,
 * absolute and paper -> rfe_tyre_dugoff_abs_q31, bit for bit with the same count; the internal
 * per-point piece on the shared set-up (rfe_tyre_dugoff_abs_pre_q31, either mode) is
 * the public functions' bits; shape factors matter only in magic mode. */
/* REQ-TYRE-007 REQ-FXP-007 */
static void test_magic_q31_dispatch(void **state)
{
    static const rfe_tyre_mode_t MODES[3] = {RFE_TYRE_MAGIC, RFE_TYRE_ABSOLUTE, RFE_TYRE_PAPER};
    int n;
    (void)state;
    rng_seed(0xD15Full);
    for (n = 0; n < 3000; n += (int)rfe_test_stride(10u)) {
        rfe_tyre_params_q31_t tp = pq.tyre;
        rfe_wheel_kin_q31_t kin;
        rfe_fix_t mu[4], fx[4], fy[4];
        uint32_t sat = 0u, sum = 0u;
        size_t i;
        tp.mode = MODES[n % 3];
        tp.shape_Ex = (n % 2) ? toq(-1.5, 24) : 0;
        for (i = 0; i < 4; ++i) {
            kin.kappa[i] = toq(uni(-1.1, 1.1), 30);
            kin.alpha[i] = toq(uni(-1.5, 1.5), 29);
            kin.fz[i] = toq(uni(0.0, 40000.0), 15);
            kin.vwx[i] = toq(uni(-50.0, 50.0), 23);
            mu[i] = toq(uni(-0.3, 3.0), 29);
        }
        assert_int_equal(rfe_tyre_forces_abs_q31(&tp, &kin, mu, fx, fy, &sat), RFE_OK);
        for (i = 0; i < 4; ++i) {
            rfe_fix_t a = 0, b = 0, c = 0, d = 0;
            uint32_t s1 = 0u, s2 = 0u;
            rfe_dugoff_pre_q31_t pre;
            if (tp.mode == RFE_TYRE_MAGIC) {
                assert_int_equal(rfe_tyre_magic_abs_q31(&tp, kin.kappa[i], kin.alpha[i], kin.fz[i],
                                                        kin.vwx[i], mu[i], &a, &b, &s1),
                                 RFE_OK);
            } else {
                assert_int_equal(rfe_tyre_dugoff_abs_q31(&tp, kin.kappa[i], kin.alpha[i],
                                                         kin.fz[i], kin.vwx[i], mu[i], &a, &b,
                                                         &s1),
                                 RFE_OK);
            }
            assert_int_equal(a, fx[i]);
            assert_int_equal(b, fy[i]);
            sum += s1;
            rfe_tyre_dugoff_pre_q31(&tp, kin.kappa[i], kin.alpha[i], kin.vwx[i], &pre);
            rfe_tyre_dugoff_abs_pre_q31(&tp, &pre, mu[i], kin.fz[i], &c, &d, &s2);
            assert_int_equal(c, a);
            assert_int_equal(d, b);
            assert_int_equal(s2, s1);
        }
        assert_int_equal(sat, sum);
    }
    /* the parameter check of the load-scaled modes */
    {
        rfe_tyre_params_q31_t tp = pq.tyre;
        assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 1);
        tp.shape_Cy = ONE24;
        assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 0);
        tp.mode = RFE_TYRE_ABSOLUTE; /* the Dugoff curve does not use the shape */
        assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 1);
        tp.eps = -1;
        assert_int_equal(rfe_tyre_abs_params_ok_q31(&tp), 0);
    }
}

/* REQ: identical inputs give identical forces and counts. */
/* REQ-FXP-007 */
static void test_magic_q31_deterministic(void **state)
{
    int n;
    (void)state;
    rng_seed(0xDE7ull);
    for (n = 0; n < 2000; ++n) {
        const int32_t k = toq(uni(-1.2, 1.2), 30), a = toq(uni(-1.6, 1.6), 29);
        const int32_t fz = toq(uni(0.0, 60000.0), 15), mu = toq(uni(-0.5, 3.9), 29);
        const rfe_tyre_params_q31_t tp = tyre_with(SHAPES[n % 7][0], SHAPES[n % 7][1],
                                                   SHAPES[n % 7][2], SHAPES[n % 7][3]);
        int32_t p[2], q[2];
        uint32_t s1 = 0u, s2 = 0u;
        assert_int_equal(rfe_tyre_magic_abs_q31(&tp, k, a, fz, 0, mu, &p[0], &p[1], &s1), RFE_OK);
        assert_int_equal(rfe_tyre_magic_abs_q31(&tp, k, a, fz, 0, mu, &q[0], &q[1], &s2), RFE_OK);
        assert_memory_equal(p, q, sizeof(p));
        assert_int_equal(s1, s2);
    }
}

/* REQ: NULL -> RFE_ERR_NULL; alpha_max, eps or a shape factor outside its domain
 * (1 < C < 2, -4 <= E < 1, each bound of each direction) -> RFE_ERR_PARAM (before the load's
 * RFE_ERR_RANGE), fz < 0 -> RFE_ERR_RANGE; the outputs and the counter untouched on every
 * error; the largest and smallest valid shape factors are accepted. Four wheels in magic mode:
 * a bad shape or a bad load leaves every output untouched. */
/* REQ-TYRE-006 REQ-TYRE-007 */
static void test_magic_q31_argument_checks(void **state)
{
    rfe_tyre_params_q31_t bad;
    rfe_wheel_kin_q31_t kin;
    rfe_fix_t a = SENT, b = SENT, fa[4], fb[4], mu[4] = {0, 1 << 28, 1 << 29, 3 << 29};
    uint32_t sat = 9u;
    size_t i;
    (void)state;
    assert_int_equal(rfe_tyre_magic_abs_q31(NULL, 0, 0, 0, 0, 0, &a, &b, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_abs_q31(&pq.tyre, 0, 0, 0, 0, 0, NULL, &b, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_abs_q31(&pq.tyre, 0, 0, 0, 0, 0, &a, NULL, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_abs_q31(&pq.tyre, 0, 0, 0, 0, 0, &a, &b, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_tyre_magic_abs_q31(&pq.tyre, 0, 0, -1, 0, 0, &a, &b, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_tyre_magic_abs_q31(&pq.tyre, 0, 0, INT32_MIN, 0, 0, &a, &b, &sat),
                     RFE_ERR_RANGE);
#define BAD_(stmt)                                                                              \
    do {                                                                                        \
        bad = pq.tyre;                                                                          \
        stmt;                                                                                   \
        if (rfe_tyre_magic_abs_q31(&bad, 1 << 20, 1 << 20, -1, 0, 1 << 29, &a, &b, &sat) !=     \
            RFE_ERR_PARAM) {                                                                    \
            fail_msg("accepted: %s", #stmt);                                                    \
        }                                                                                       \
    } while (0)
    BAD_(bad.alpha_max = 0);
    BAD_(bad.alpha_max = RFE_FIX_TAN_LIMIT_Q29);
    BAD_(bad.eps = -1);
    BAD_(bad.shape_Cx = ONE24);
    BAD_(bad.shape_Cx = 2 * ONE24);
    BAD_(bad.shape_Ex = -4 * ONE24 - 1);
    BAD_(bad.shape_Ex = ONE24);
    BAD_(bad.shape_Cy = ONE24);
    BAD_(bad.shape_Cy = 2 * ONE24);
    BAD_(bad.shape_Ey = -4 * ONE24 - 1);
    BAD_(bad.shape_Ey = ONE24);
#undef BAD_
    assert_int_equal(a, SENT);
    assert_int_equal(b, SENT);
    assert_int_equal(sat, 9u);
    /* the extreme valid shapes */
    bad = tyre_with(ONE24 + 1, -4 * ONE24, 2 * ONE24 - 1, ONE24 - 1);
    assert_int_equal(rfe_tyre_magic_abs_q31(&bad, 1 << 28, 1 << 27, 1 << 28, 0, 1 << 29, &a, &b,
                                            &sat),
                     RFE_OK);
    /* the Dugoff functions ignore the shape factors */
    bad = pq.tyre;
    bad.shape_Cx = 0;
    assert_int_equal(rfe_tyre_dugoff_abs_q31(&bad, 1 << 28, 1 << 27, 1 << 28, 0, 1 << 29, &a, &b,
                                             &sat),
                     RFE_OK);
    /* four wheels */
    sat = 9u;
    for (i = 0; i < 4; ++i) {
        kin.kappa[i] = 1 << 26;
        kin.alpha[i] = 1 << 25;
        kin.fz[i] = 5000 << 15;
        kin.vwx[i] = 20 << 23;
        fa[i] = fb[i] = SENT;
    }
    bad = pq.tyre;
    bad.shape_Ey = ONE24;
    assert_int_equal(rfe_tyre_forces_abs_q31(&bad, &kin, mu, fa, fb, &sat), RFE_ERR_PARAM);
    bad.mode = RFE_TYRE_ABSOLUTE;
    assert_int_equal(rfe_tyre_forces_abs_q31(&bad, &kin, mu, fa, fb, &sat), RFE_OK);
    for (i = 0; i < 4; ++i) {
        fa[i] = fb[i] = SENT;
    }
    kin.fz[3] = -1;
    assert_int_equal(rfe_tyre_forces_abs_q31(&pq.tyre, &kin, mu, fa, fb, &sat), RFE_ERR_RANGE);
    assert_int_equal(rfe_tyre_forces_abs_q31(NULL, &kin, mu, fa, fb, &sat), RFE_ERR_NULL);
    for (i = 0; i < 4; ++i) {
        assert_int_equal(fa[i], SENT);
        assert_int_equal(fb[i], SENT);
    }
    assert_int_equal(sat, 9u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_magic_q31_grid),
        cmocka_unit_test(test_magic_q31_random),
        cmocka_unit_test(test_magic_q31_scenarios_twin),
        cmocka_unit_test(test_magic_q31_mirror),
        cmocka_unit_test(test_magic_q31_curve_properties),
        cmocka_unit_test(test_magic_q31_dispatch),
        cmocka_unit_test(test_magic_q31_deterministic),
        cmocka_unit_test(test_magic_q31_argument_checks),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
