/**
 * @file test_sckf_gate_flt.c
 * @brief Unit tests of the SCKF additions for docs/ESTIMATOR.md: rfe_sckf_update_ex (a
 *        step-specific S_R, the Fisher information by statistical linearisation, the
 *        information gate) and rfe_sckf_scale (step 7). Built twice: float32 and double.
 *
 * (a) update_ex with the filter's own S_R and no gate is rfe_sckf_update bit for bit (also
 *     while it computes the information on the side); with a step S_R it is bit for bit the
 *     update of a filter whose own S_R is that factor.
 * (b) On a linear model h = H x the statistical linearisation is exact (J = H), so the
 *     information must equal diag(H^T R^-1 H), R = S_R S_R^T, computed here independently
 *     in double (Cholesky of R, not the filter's triangular solves).
 * (c) The gate: threshold just below max_k I_k updates (the same bits as no gate), just above
 *     holds (x, S exactly the predicted ones); errors leave state and outputs untouched.
 * (d) rfe_sckf_scale multiplies S by c exactly, keeps x and the correlations, and rejects a
 *     bad c or an overflowing product without touching S.
 * Random problems come from the fixed-seed generator (test_rng.h, deterministic).
 */
#include "test_common.h"

#include <float.h>
#include <stdint.h>
#include <string.h>

#include "filter_fixtures.h"
#include "rfe/component/sckf.h"
#include "test_linalg.h"
#include "test_rng.h"

/* ---- tolerances ------------------------------------------------------------------------
 * Information, relative to max_k I_k of the reference.
 * double: cubature points, two triangular solves with S- (cond ~ 10) and one with S_R
 *   (cond ~ 10) on values ~1: a few eps * cond^2 -> 1e-10 (seen 1.4e-15).
 * float32: the same chain in float: the centred points carry ~eps |x| / |S| relative error,
 *   the solves amplify by cond(S-)^2 cond(S_R) ~ 1e2..1e3: ~1e-5 worst case -> 1e-4
 *   (seen 7.4e-7). */
#if defined(RFE_REAL_DOUBLE)
#define TOL_INFO 1e-10
#define TINY_SR 1e-160 /* 1/TINY^2 overflows double */
#else
#define TOL_INFO 1e-4
#define TINY_SR 1e-25 /* 1/TINY^2 overflows float */
#endif

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)

/* ---- a linear problem: x_next = x (random walk), z = H x -------------------------------- */

typedef struct {
    size_t n;
    size_t m;
    rfe_real_t H[MM * NM]; /* ld NM */
} lin_h_t;

static rfe_status_t lin_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n, size_t m)
{
    const lin_h_t *h = (const lin_h_t *)ctx;
    size_t r;
    size_t j;
    for (r = 0u; r < m; ++r) {
        double acc = 0.0;
        for (j = 0u; j < n; ++j) {
            acc += (double)h->H[(r * NM) + j] * (double)x[j];
        }
        z[r] = (rfe_real_t)acc;
    }
    return RFE_OK;
}

/* A nonlinear model (cubic in x_0): the gate must work with any h. */
static rfe_status_t cubic_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n,
                                  size_t m)
{
    size_t r;
    (void)ctx;
    for (r = 0u; r < m; ++r) {
        z[r] = x[0] * x[0] * x[0] + (rfe_real_t)r * x[n - 1u];
    }
    return RFE_OK;
}

typedef struct {
    size_t n;
    size_t m;
    lin_h_t h;
    rfe_real_t x0[NM];
    rfe_real_t S0[NM * NM]; /* ld n */
    rfe_real_t SQ[NM * NM]; /* ld n */
    rfe_real_t SR[MM * MM]; /* ld m: the filter's own S_R */
    rfe_real_t SR2[MM * MM]; /* ld m: a step S_R */
    rfe_real_t y[MM];
} problem_t;

static void make_problem(problem_t *p, size_t n, size_t m, uint64_t seed)
{
    size_t i;
    size_t j;
    memset(p, 0, sizeof *p);
    rng_seed(seed);
    p->n = n;
    p->m = m;
    p->h.n = n;
    p->h.m = m;
    for (i = 0u; i < m; ++i) {
        for (j = 0u; j < n; ++j) {
            p->h.H[(i * NM) + j] = (rfe_real_t)rng_uniform();
        }
        p->y[i] = (rfe_real_t)rng_uniform();
    }
    for (i = 0u; i < n; ++i) {
        p->x0[i] = (rfe_real_t)rng_uniform();
    }
    rand_lower(p->S0, n, 0.5, 0.5, 0.3);
    rand_lower(p->SQ, n, 0.05, 0.1, 0.03);
    rand_lower(p->SR, m, 0.2, 0.2, 0.05);
    rand_lower(p->SR2, m, 0.3, 0.3, 0.1);
}

static void init_filter(rfe_sckf_t *f, const problem_t *p, const rfe_real_t *SR)
{
    memset(f, 0, sizeof *f);
    assert_int_equal(rfe_sckf_init(f, p->n, p->m, p->x0, p->S0, p->SQ, SR), RFE_OK);
    assert_int_equal(rfe_sckf_predict(f, NULL, NULL), RFE_OK);
}

/* The state a step may change: mean and factor, bit for bit. */
static void assert_same_state(const rfe_sckf_t *a, const rfe_sckf_t *b)
{
    assert_memory_equal(a->x, b->x, sizeof a->x);
    assert_memory_equal(a->S, b->S, sizeof a->S);
}

/* diag(H^T R^-1 H), R = SR SR^T (SR ld m), in double by a Cholesky solve. */
static void ref_information(const problem_t *p, const rfe_real_t *SR, double *info)
{
    double R[NM][NM];
    double Ht[NM][NM];
    double K[NM][NM];
    size_t i;
    size_t j;
    size_t c;
    memset(R, 0, sizeof R);
    for (i = 0u; i < p->m; ++i) {
        for (j = 0u; j < p->m; ++j) {
            double acc = 0.0;
            for (c = 0u; c < p->m; ++c) {
                const double a = (c <= i) ? (double)SR[(i * p->m) + c] : 0.0;
                const double b = (c <= j) ? (double)SR[(j * p->m) + c] : 0.0;
                acc += a * b;
            }
            R[i][j] = acc;
        }
    }
    for (i = 0u; i < p->n; ++i) {
        for (j = 0u; j < p->m; ++j) {
            Ht[i][j] = (double)p->h.H[(j * NM) + i];
        }
    }
    right_solve_spd(R, p->m, Ht, p->n, K); /* K = H^T R^-1 (n x m) */
    for (i = 0u; i < p->n; ++i) {
        double acc = 0.0;
        for (c = 0u; c < p->m; ++c) {
            acc += K[i][c] * (double)p->h.H[(c * NM) + i];
        }
        info[i] = acc;
    }
}

static double max_of(const rfe_real_t *v, size_t k)
{
    double best = 0.0;
    size_t i;
    for (i = 0u; i < k; ++i) {
        best = ((double)v[i] > best) ? (double)v[i] : best;
    }
    return best;
}

/* Every (n, m) the maxima allow, a few seeds each. */
#define FOR_EACH_PROBLEM(p, body)                                                           \
    do {                                                                                    \
        size_t n_;                                                                          \
        size_t m_;                                                                          \
        uint64_t s_;                                                                        \
        for (n_ = 1u; n_ <= NM; ++n_) {                                                     \
            for (m_ = 1u; m_ <= MM; ++m_) {                                                 \
                for (s_ = 1u; s_ <= 3u; ++s_) {                                             \
                    make_problem(&(p), n_, m_, (n_ * 100u) + (m_ * 10u) + s_);              \
                    body                                                                    \
                }                                                                           \
            }                                                                               \
        }                                                                                   \
    } while (0)

/* REQ: with the filter's S_R (NULL or passed explicitly) and no gate, update_ex is
 * rfe_sckf_update bit for bit, also when it reports the information on the side. */
/* REQ-SCKF-004 */
static void test_rfe_sckf_update_ex_equals_update_bitwise(void **state)
{
    static rfe_sckf_t a, b, c, d;
    problem_t p;
    (void)state;
    FOR_EACH_PROBLEM(p, {
        rfe_real_t info[NM];
        int upd = -1;
        int k;
        init_filter(&a, &p, p.SR);
        b = a;
        c = a;
        d = a;
        for (k = 0; k < 3; ++k) {
            assert_int_equal(rfe_sckf_update(&a, lin_measure, &p.h, p.y), RFE_OK);
            assert_int_equal(rfe_sckf_update_ex(&b, lin_measure, &p.h, p.y, NULL,
                                                        (rfe_real_t)0, NULL, NULL, &upd), RFE_OK);
            assert_int_equal(upd, 1);
            assert_int_equal(rfe_sckf_update_ex(&c, lin_measure, &p.h, p.y, p.SR,
                                                        (rfe_real_t)-1, info, NULL, &upd), RFE_OK);
            assert_int_equal(upd, 1);
            assert_int_equal(rfe_sckf_update_ex(&d, cubic_measure, NULL, p.y, NULL,
                                                        (rfe_real_t)0, info, NULL, &upd), RFE_OK);
            assert_same_state(&a, &b);
            assert_same_state(&a, &c);
            assert_int_equal(rfe_sckf_predict(&a, NULL, NULL), RFE_OK);
            assert_int_equal(rfe_sckf_predict(&b, NULL, NULL), RFE_OK);
            assert_int_equal(rfe_sckf_predict(&c, NULL, NULL), RFE_OK);
            assert_int_equal(rfe_sckf_predict(&d, NULL, NULL), RFE_OK);
        }
    });
}

/* REQ: a step S_R replaces the filter's S_R for that step only: the same bits as a filter
 * whose own S_R is the step factor; the filter's S_R is not changed. */
/* REQ-SCKF-004 */
static void test_rfe_sckf_update_ex_step_sr_replaces_filter_sr(void **state)
{
    static rfe_sckf_t a, b;
    problem_t p;
    (void)state;
    FOR_EACH_PROBLEM(p, {
        rfe_real_t SR_before[MM * MM];
        int upd = -1;
        init_filter(&a, &p, p.SR);
        init_filter(&b, &p, p.SR2);
        memcpy(SR_before, a.SR, sizeof SR_before);
        assert_int_equal(rfe_sckf_update_ex(&a, lin_measure, &p.h, p.y, p.SR2,
                                                    (rfe_real_t)0, NULL, NULL, &upd), RFE_OK);
        assert_int_equal(rfe_sckf_update(&b, lin_measure, &p.h, p.y), RFE_OK);
        assert_same_state(&a, &b);
        assert_memory_equal(a.SR, SR_before, sizeof SR_before);
    });
}

/* |a - b| <= tol max(1, |b|) element by element. */
static void assert_near_vec(const rfe_real_t *a, const rfe_real_t *b, size_t k, double tol)
{
    size_t i;
    for (i = 0u; i < k; ++i) {
        const double mag = fabs((double)b[i]);
        assert_true(fabs((double)a[i] - (double)b[i]) <= (tol * ((mag > 1.0) ? mag : 1.0)));
    }
}

/* REQ (issue 21): on a linear h = H x, rfe_sckf_update_linear (the n columns Xc = S-,
 * Zc = H S-) gives the update of the 2n cubature points (rfe_sckf_update_ex): the same x, S,
 * information and innovation (nu, S_zz, diag(Zc Zc^T)), within rounding, on every (n, m) with
 * a step S_R. Both compute the same exact quantities (Xc Xc^T, Zc Zc^T and Xc Zc^T are equal,
 * docs/ESTIMATOR.md "The linear update"); their roundings differ: the points' x- +- sqrt(n)
 * S- e_j and their centring against the direct columns, then the same Tria and solves
 * (cond(S-), cond(S_zz) ~ 10 on values ~ 1): a few eps cond^2 per element. double: 1e-11
 * (eps 2.2e-16 x 1e2 x a 1e2 margin for the chain's ~50 operations); float32: 1e-4 (eps
 * 1.2e-7 x 1e2 x 10). The generic path itself is unchanged: the default preset's goldens
 * (test_golden_flt.c, test_golden_q31.c bit for bit) hold it. */
/* REQ-SCKF-004 */
static void test_rfe_sckf_update_linear_equals_points(void **state)
{
#if defined(RFE_REAL_DOUBLE)
    const double tol = 1e-11;
#else
    const double tol = 1e-4;
#endif
    problem_t p;
    (void)state;
    FOR_EACH_PROBLEM(p, {
        static rfe_sckf_t a;
        static rfe_sckf_t b;
        rfe_real_t info_a[RFE_N_MAX];
        rfe_real_t info_b[RFE_N_MAX];
        rfe_sckf_innov_t ia;
        rfe_sckf_innov_t ib;
        int ua = 0;
        int ub = 0;
        double most = 0.0;
        size_t i;
        init_filter(&a, &p, p.SR);
        init_filter(&b, &p, p.SR);
        assert_int_equal(rfe_sckf_update_ex(&a, lin_measure, &p.h, p.y, p.SR2, 0, info_a, &ia,
                                            &ua),
                         RFE_OK);
        assert_int_equal(rfe_sckf_update_linear(&b, lin_measure, &p.h, p.y, p.SR2, 0, info_b,
                                                &ib, &ub),
                         RFE_OK);
        assert_int_equal(ua, 1);
        assert_int_equal(ub, 1);
        assert_near_vec(b.x, a.x, p.n, tol);
        assert_near_vec(b.S, a.S, NM * NM, tol);
        assert_near_vec(ib.nu, ia.nu, MM, tol);
        assert_near_vec(ib.Szz, ia.Szz, MM * MM, tol);
        assert_near_vec(ib.zz, ia.zz, MM, tol);
        /* the information relative to its largest (TOL_INFO's derivation) */
        most = max_of(info_a, p.n);
        for (i = 0u; i < p.n; ++i) {
            assert_true(fabs((double)info_b[i] - (double)info_a[i]) <= (TOL_INFO * most));
        }
    });
}

/* h = H x, then a non-finite output at the last point (x-, the linear form's fifth). */
static int nan_calls;
static rfe_status_t nan_last_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n,
                                     size_t m)
{
    const rfe_status_t st = lin_measure(ctx, x, z, n, m);
    ++nan_calls;
    if (nan_calls == (int)(n + 1u)) {
        z[m - 1u] = (rfe_real_t)NAN;
    }
    return st;
}

/* h = H x, then an error status from the callback at its second call (the linear form's
 * second column). */
static int fail_calls;
static rfe_status_t fail_second_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n,
                                        size_t m)
{
    ++fail_calls;
    return (fail_calls == 2) ? RFE_ERR_RANGE : lin_measure(ctx, x, z, n, m);
}

/* REQ: the linear entry checks its arguments as update_ex does, refuses a non-finite output
 * of h (RFE_ERR_NONFINITE) and passes on the callback's own error status at once; on every
 * error the state and *updated stay as they were. */
/* REQ-SCKF-004 */
static void test_rfe_sckf_update_linear_errors_untouched(void **state)
{
    static rfe_sckf_t f;
    static rfe_sckf_t copy;
    problem_t p;
    rfe_real_t info[RFE_N_MAX];
    int upd = -1;
    (void)state;
    make_problem(&p, 4u, 3u, 77u);
    init_filter(&f, &p, p.SR);
    copy = f;
    assert_int_equal(rfe_sckf_update_linear(NULL, lin_measure, &p.h, p.y, NULL, 0, info, NULL,
                                            &upd),
                     RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_update_linear(&f, NULL, &p.h, p.y, NULL, 0, info, NULL, &upd),
                     RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_update_linear(&f, lin_measure, &p.h, p.y, NULL, 0, info, NULL,
                                            NULL),
                     RFE_ERR_NULL);
    nan_calls = 0;
    assert_int_equal(rfe_sckf_update_linear(&f, nan_last_measure, &p.h, p.y, NULL, 0, info,
                                            NULL, &upd),
                     RFE_ERR_NONFINITE);
    assert_int_equal(nan_calls, 5);
    assert_int_equal(upd, -1);
    assert_same_state(&f, &copy);
    fail_calls = 0;
    assert_int_equal(rfe_sckf_update_linear(&f, fail_second_measure, &p.h, p.y, NULL, 0, info,
                                            NULL, &upd),
                     RFE_ERR_RANGE);
    assert_int_equal(fail_calls, 2); /* no evaluation after the failing one */
    assert_int_equal(upd, -1);
    assert_same_state(&f, &copy);
    /* and it still works */
    assert_int_equal(rfe_sckf_update_linear(&f, lin_measure, &p.h, p.y, NULL, 0, info, NULL,
                                            &upd),
                     RFE_OK);
    assert_int_equal(upd, 1);
}

/* REQ: on a linear model the information is diag(H^T R^-1 H) with R = S_R S_R^T of the
 * step S_R (statistical linearisation is exact there), independent of the prior. */
/* REQ-SCKF-004 */
static void test_rfe_sckf_update_ex_information_linear_model(void **state)
{
    static rfe_sckf_t f;
    problem_t p;
    (void)state;
    FOR_EACH_PROBLEM(p, {
        rfe_real_t info[NM];
        double ref[NM];
        double scale = 0.0;
        int upd = -1;
        size_t i;
        char what[64];
        init_filter(&f, &p, p.SR);
        assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, p.y, p.SR2,
                                                    (rfe_real_t)0, info, NULL, &upd), RFE_OK);
        ref_information(&p, p.SR2, ref);
        for (i = 0u; i < p.n; ++i) {
            scale = (ref[i] > scale) ? ref[i] : scale;
        }
        for (i = 0u; i < p.n; ++i) {
            snprintf(what, sizeof what, "n %zu m %zu info[%zu]", p.n, p.m, i);
            ASSERT_LE(fabs((double)info[i] - ref[i]) / scale, TOL_INFO, what);
        }
    });
}

/* REQ: max_k I_k >= info_min updates (the same bits as without the gate); below, the step is
 * held: x, S stay the predicted ones, *updated = 0, the information is still reported. */
/* REQ-SCKF-004 */
static void test_rfe_sckf_update_ex_gate_threshold(void **state)
{
    static rfe_sckf_t probe, pred, a, b;
    problem_t p;
    (void)state;
    FOR_EACH_PROBLEM(p, {
        rfe_real_t info[NM];
        rfe_real_t info_held[NM];
        rfe_real_t most;
        int upd = -1;
        init_filter(&pred, &p, p.SR);
        probe = pred;
        assert_int_equal(rfe_sckf_update_ex(&probe, lin_measure, &p.h, p.y, p.SR2,
                                                    (rfe_real_t)0, info, NULL, &upd), RFE_OK);
        most = (rfe_real_t)max_of(info, p.n);
        assert_true(most > 0);
        /* Just below the largest information: updates, same bits as the ungated step. */
        a = pred;
        assert_int_equal(rfe_sckf_update_ex(&a, lin_measure, &p.h, p.y, p.SR2,
                                                    most * (rfe_real_t)0.999, NULL, NULL, &upd), RFE_OK);
        assert_int_equal(upd, 1);
        assert_same_state(&a, &probe);
        /* Equal to it: updates (the gate holds only below info_min). */
        a = pred;
        assert_int_equal(rfe_sckf_update_ex(&a, lin_measure, &p.h, p.y, p.SR2, most,
                                                    NULL, NULL, &upd), RFE_OK);
        assert_int_equal(upd, 1);
        /* Just above: held. */
        b = pred;
        upd = -1;
        assert_int_equal(rfe_sckf_update_ex(&b, lin_measure, &p.h, p.y, p.SR2,
                                                    most * (rfe_real_t)1.001, info_held, NULL, &upd),
                         RFE_OK);
        assert_int_equal(upd, 0);
        assert_same_state(&b, &pred);
        assert_memory_equal(info_held, info, p.n * sizeof info[0]);
    });
}

/* REQ: the gate works on a nonlinear model too: a state the measurement does not depend on
 * near the mean carries little information (cubic at x_0 = 0 with a tiny spread). */
/* REQ-SCKF-004 */
static void test_rfe_sckf_update_ex_gate_nonlinear(void **state)
{
    static rfe_sckf_t f, pred;
    const rfe_real_t x0[1] = {0};
    const rfe_real_t S0[1] = {(rfe_real_t)0.01};
    const rfe_real_t SQ[1] = {(rfe_real_t)0.001};
    const rfe_real_t SR[1] = {(rfe_real_t)0.1};
    const rfe_real_t y[1] = {(rfe_real_t)0.5};
    rfe_real_t info[1];
    int upd = -1;
    (void)state;
    assert_int_equal(rfe_sckf_init(&f, 1, 1, x0, S0, SQ, SR), RFE_OK);
    assert_int_equal(rfe_sckf_predict(&f, NULL, NULL), RFE_OK);
    pred = f;
    /* z = x^3: J = E[x^4]/E[x^2] ~ S^2 = 1e-4, so I ~ (1e-4 / 0.1)^2 = 1e-6. */
    assert_int_equal(rfe_sckf_update_ex(&f, cubic_measure, NULL, y, NULL, (rfe_real_t)1e-3,
                                                info, NULL, &upd), RFE_OK);
    assert_int_equal(upd, 0);
    assert_true(info[0] > 0 && info[0] < (rfe_real_t)1e-5);
    assert_same_state(&f, &pred);
}

/* REQ: bad arguments are rejected and change nothing (state, info_out, updated). */
/* REQ-SCKF-004 REQ-SCKF-008 */
static void test_rfe_sckf_update_ex_argument_errors(void **state)
{
    static rfe_sckf_t f, copy, blank;
    problem_t p;
    rfe_real_t info[NM];
    rfe_real_t info_copy[NM];
    rfe_real_t SRbad[MM * MM];
    rfe_real_t ybad[MM];
    int upd = -7;
    size_t i;
    (void)state;
    make_problem(&p, 3u, 2u, 42u);
    init_filter(&f, &p, p.SR);
    copy = f;
    for (i = 0u; i < NM; ++i) {
        info[i] = (rfe_real_t)-3;
    }
    memcpy(info_copy, info, sizeof info);
    assert_int_equal(rfe_sckf_update_ex(NULL, lin_measure, &p.h, p.y, NULL, 0, info, NULL, &upd), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_update_ex(&f, NULL, &p.h, p.y, NULL, 0, info, NULL, &upd), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, NULL, NULL, 0, info, NULL, &upd), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, p.y, NULL, 0, info, NULL, NULL), RFE_ERR_NULL);
    memset(&blank, 0, sizeof blank);
    assert_int_equal(rfe_sckf_update_ex(&blank, lin_measure, &p.h, p.y, NULL, 0, info, NULL, &upd),
                     RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, p.y, NULL, (rfe_real_t)NAN,
                                                info, NULL, &upd), RFE_ERR_NONFINITE);
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, p.y, NULL,
                                                (rfe_real_t)INFINITY, info, NULL, &upd), RFE_ERR_NONFINITE);
    memcpy(ybad, p.y, sizeof ybad);
    ybad[1] = (rfe_real_t)NAN;
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, ybad, NULL, 0, info, NULL, &upd),
                     RFE_ERR_NONFINITE);
    memcpy(SRbad, p.SR2, sizeof SRbad);
    SRbad[2] = (rfe_real_t)INFINITY; /* (1,0): lower triangle */
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, p.y, SRbad, 0, info, NULL, &upd),
                     RFE_ERR_NONFINITE);
    /* The upper triangle is not read. */
    memcpy(SRbad, p.SR2, sizeof SRbad);
    SRbad[1] = (rfe_real_t)NAN;
    copy = f;
    {
        static rfe_sckf_t g;
        g = f;
        assert_int_equal(rfe_sckf_update_ex(&g, lin_measure, &p.h, p.y, SRbad, 0, NULL, NULL, &upd),
                         RFE_OK);
        assert_int_equal(rfe_sckf_update_ex(&copy, lin_measure, &p.h, p.y, p.SR2, 0, NULL, NULL, &upd),
                         RFE_OK);
        assert_same_state(&g, &copy);
    }
    copy = f;
    upd = -7;
    /* A zero diagonal in S_R: the information cannot be formed (the update alone could). */
    memcpy(SRbad, p.SR2, sizeof SRbad);
    SRbad[3] = 0; /* (1,1) */
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, p.y, SRbad, (rfe_real_t)1,
                                                info, NULL, &upd), RFE_ERR_NOT_POSITIVE_DEFINITE);
    /* An information that overflows is an error, not "no information". */
    memcpy(SRbad, p.SR2, sizeof SRbad);
    SRbad[0] = (rfe_real_t)TINY_SR;
    SRbad[2] = 0;
    SRbad[3] = (rfe_real_t)TINY_SR;
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, p.y, SRbad, (rfe_real_t)1,
                                                info, NULL, &upd), RFE_ERR_NONFINITE);
    /* Measurements whose mean overflows. */
    assert_int_equal(rfe_sckf_update_ex(&f, huge_measure, NULL, p.y, NULL, (rfe_real_t)1,
                                                info, NULL, &upd), RFE_ERR_NONFINITE);
    assert_same_state(&f, &copy);
    assert_memory_equal(info, info_copy, sizeof info);
    assert_int_equal(upd, -7);
}

/* REQ: a zero diagonal in S- (a singular prior) makes the information fail, state kept. */
/* REQ-SCKF-007 */
static void test_rfe_sckf_update_ex_singular_prior(void **state)
{
    static rfe_sckf_t f, copy;
    const rfe_real_t x0[2] = {0, 0};
    const rfe_real_t S0[4] = {1, 0, 1, 0}; /* rank 1 */
    const rfe_real_t SQ[4] = {0, 0, 0, 0};
    const rfe_real_t SR[1] = {1};
    const rfe_real_t y[1] = {1};
    lin_h_t h;
    rfe_real_t info[2];
    int upd = -1;
    (void)state;
    memset(&h, 0, sizeof h);
    h.n = 2;
    h.m = 1;
    h.H[0] = 1;
    h.H[1] = 2;
    assert_int_equal(rfe_sckf_init(&f, 2, 1, x0, S0, SQ, SR), RFE_OK);
    copy = f;
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &h, y, NULL, (rfe_real_t)1, info, NULL, &upd),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_same_state(&f, &copy);
    /* Without the information the (rank-deficient) update itself still runs. */
    assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &h, y, NULL, 0, NULL, NULL, &upd), RFE_OK);
    assert_int_equal(upd, 1);
}

/* REQ: rfe_sckf_scale multiplies every element of S by c (exactly one rounding each), keeps x
 * and the correlation P_01 / sqrt(P_00 P_11). */
/* REQ-SCKF-005 */
static void test_rfe_sckf_scale_multiplies_factor(void **state)
{
    static rfe_sckf_t f, before;
    problem_t p;
    rfe_real_t sd0[NM];
    rfe_real_t sd1[NM];
    const rfe_real_t c = (rfe_real_t)0.37;
    size_t i;
    size_t j;
    double P0[3];
    double P1[3];
    (void)state;
    make_problem(&p, (NM >= 4u) ? 4u : NM, 2u, 7u);
    init_filter(&f, &p, p.SR);
    before = f;
    assert_int_equal(rfe_sckf_scale(&f, c), RFE_OK);
    assert_memory_equal(f.x, before.x, sizeof f.x);
    for (i = 0u; i < p.n; ++i) {
        for (j = 0u; j <= i; ++j) {
            const rfe_real_t want = c * before.S[(i * NM) + j];
            assert_true(f.S[(i * NM) + j] == want);
        }
    }
    assert_int_equal(rfe_sckf_get(&before, NULL, sd0), RFE_OK);
    assert_int_equal(rfe_sckf_get(&f, NULL, sd1), RFE_OK);
    for (i = 0u; i < p.n; ++i) {
        assert_close(sd1[i], (double)c * (double)sd0[i], 0.0, 4.0 * (double)FLT_EPSILON, "sd scaled");
    }
    /* P_00, P_11, P_01 from the first two rows. */
    P0[0] = (double)before.S[0] * (double)before.S[0];
    P0[1] = (double)before.S[NM] * (double)before.S[NM] + (double)before.S[NM + 1u] * (double)before.S[NM + 1u];
    P0[2] = (double)before.S[0] * (double)before.S[NM];
    P1[0] = (double)f.S[0] * (double)f.S[0];
    P1[1] = (double)f.S[NM] * (double)f.S[NM] + (double)f.S[NM + 1u] * (double)f.S[NM + 1u];
    P1[2] = (double)f.S[0] * (double)f.S[NM];
    assert_close(P1[2] / sqrt(P1[0] * P1[1]), P0[2] / sqrt(P0[0] * P0[1]), 1e-6, 0.0, "correlation");
}

/* REQ: a bad factor or an overflowing product is rejected, S untouched. */
/* REQ-SCKF-005 */
static void test_rfe_sckf_scale_errors(void **state)
{
    static rfe_sckf_t f, copy, blank;
    const rfe_real_t x0[2] = {1, 2};
    const rfe_real_t S0[4] = {2, 0, (rfe_real_t)0.5, 3}; /* elements > 1: c = max overflows */
    const rfe_real_t SQ[4] = {(rfe_real_t)0.1, 0, 0, (rfe_real_t)0.1};
    const rfe_real_t SR[1] = {1};
    (void)state;
    assert_int_equal(rfe_sckf_init(&f, 2, 1, x0, S0, SQ, SR), RFE_OK);
    copy = f;
    assert_int_equal(rfe_sckf_scale(NULL, 1), RFE_ERR_NULL);
    memset(&blank, 0, sizeof blank);
    assert_int_equal(rfe_sckf_scale(&blank, 1), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_sckf_scale(&f, 0), RFE_ERR_RANGE);
    assert_int_equal(rfe_sckf_scale(&f, -1), RFE_ERR_RANGE);
    assert_int_equal(rfe_sckf_scale(&f, (rfe_real_t)NAN), RFE_ERR_RANGE);
    assert_int_equal(rfe_sckf_scale(&f, (rfe_real_t)INFINITY), RFE_ERR_RANGE);
    assert_int_equal(rfe_sckf_scale(&f, REAL_BIG), RFE_ERR_NONFINITE);
    assert_same_state(&f, &copy);
    assert_int_equal(rfe_sckf_scale(&f, 1), RFE_OK);
    assert_same_state(&f, &copy);
}

/* REQ: the innovation output (the monitor's input) on a linear model: nu = y - H x- with x-
 * the predicted mean (the cubature mean of a linear map is exact), and the whole struct
 * written: every entry beyond m and S_zz's upper part 0 (the estimator keeps it in its
 * state, copied and compared whole; the output is filled with 0x5A bytes before). Bound on
 * nu: lin_measure rounds each point's output once to rfe_real_t and the filter averages 2n
 * of them, so at most ~(2n + 1) roundings of size eps * scale, scale = 1 + sum_j |H_rj|
 * (|x_j| + sum_k |S_jk|) (x, S predicted) bounding |z| at every point; 4 (2 N_MAX + 1) eps * scale covers it
 * with a factor 4 of margin. */
/* REQ-SCKF-004 REQ-MON-005 */
static void test_rfe_sckf_update_ex_innovation_output(void **state)
{
    static rfe_sckf_t f;
    problem_t p;
#if defined(RFE_REAL_DOUBLE)
    const double eps = DBL_EPSILON;
#else
    const double eps = (double)FLT_EPSILON;
#endif
    (void)state;
    FOR_EACH_PROBLEM(p, {
        rfe_sckf_innov_t in;
        rfe_real_t xp[NM];
        rfe_real_t Sp[NM * NM];
        int upd = -1;
        size_t r;
        size_t j;
        size_t k;
        char what[64];
        init_filter(&f, &p, p.SR);
        memcpy(xp, f.x, sizeof xp); /* the predicted mean and factor */
        memcpy(Sp, f.S, sizeof Sp);
        memset(&in, 0x5A, sizeof in);
        assert_int_equal(rfe_sckf_update_ex(&f, lin_measure, &p.h, p.y, p.SR2, (rfe_real_t)0,
                                            NULL, &in, &upd), RFE_OK);
        for (r = 0u; r < MM; ++r) {
            double hx = 0.0;
            double scale = 1.0;
            if (r >= p.m) {
                assert_true((in.nu[r] == (rfe_real_t)0) && (in.zz[r] == (rfe_real_t)0));
            } else {
                for (j = 0u; j < p.n; ++j) {
                    double row = fabs((double)xp[j]);
                    for (k = 0u; k <= j; ++k) {
                        row += fabs((double)Sp[(j * NM) + k]);
                    }
                    hx += (double)p.h.H[(r * NM) + j] * (double)xp[j];
                    scale += fabs((double)p.h.H[(r * NM) + j]) * row;
                }
                snprintf(what, sizeof what, "n %zu m %zu nu[%zu]", p.n, p.m, r);
                ASSERT_LE(fabs((double)in.nu[r] - ((double)p.y[r] - hx)),
                          4.0 * ((2.0 * (double)NM) + 1.0) * eps * scale, what);
            }
            for (j = 0u; j < MM; ++j) {
                assert_true(((r < p.m) && (j <= r)) || (in.Szz[(r * MM) + j] == (rfe_real_t)0));
            }
        }
    });
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_sckf_update_ex_equals_update_bitwise),
        cmocka_unit_test(test_rfe_sckf_update_ex_step_sr_replaces_filter_sr),
        cmocka_unit_test(test_rfe_sckf_update_ex_information_linear_model),
        cmocka_unit_test(test_rfe_sckf_update_linear_equals_points),
        cmocka_unit_test(test_rfe_sckf_update_linear_errors_untouched),
        cmocka_unit_test(test_rfe_sckf_update_ex_gate_threshold),
        cmocka_unit_test(test_rfe_sckf_update_ex_gate_nonlinear),
        cmocka_unit_test(test_rfe_sckf_update_ex_argument_errors),
        cmocka_unit_test(test_rfe_sckf_update_ex_singular_prior),
        cmocka_unit_test(test_rfe_sckf_update_ex_innovation_output),
        cmocka_unit_test(test_rfe_sckf_scale_multiplies_factor),
        cmocka_unit_test(test_rfe_sckf_scale_errors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
