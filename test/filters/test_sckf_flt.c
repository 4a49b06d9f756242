/**
 * @file test_sckf_flt.c
 * @brief Unit tests of the generic square-root cubature Kalman filter (rfe_sckf_*,
 *        MODEL.md §6). Built twice: float32 and double.
 *
 * (a) On a linear-Gaussian model the SCKF is exact: its mean and S S^T must equal a
 *     textbook Kalman filter in double with explicit matrices (kalman_ref.h).
 * (b) cmocka mocks of the model callbacks check the 2n cubature points (values, order,
 *     context pointer, dimensions) and that a callback error or NaN leaves the state alone.
 * (c) Argument, size, initialisation and range errors.
 * (d) After every step S is lower-triangular with a non-negative diagonal.
 * Random inputs come from the fixed-seed xorshift generator (test_rng.h, deterministic).
 */
#include "test_common.h"

#include <float.h>
#include <stdint.h>
#include <string.h>

#include "filter_fixtures.h"
#include "kalman_ref.h"
#include "rfe/component/sckf.h"
#include "test_rng.h"

/* ---- tolerances ------------------------------------------------------------------------
 * Errors are relative: mean error / max(1, |x_ref|_inf), covariance error / max|P_ref|. */
#if defined(RFE_REAL_DOUBLE)
/* double: a few Tria + triangular solves per step, eps 2.2e-16 * cond ~ 1e2, 6 steps of a
 * contracting filter -> far under the 1e-10 the spec asks for (seen 1.5e-14). */
#define TOL_KF 1e-10
/* double: a cubature point is x + sqrt(n) S_ij, rounded twice: 2 eps relative to
 * |x| + sqrt(n) |S_ij|, with margin -> 4 eps. */
#define TOL_POINT (4.0 * DBL_EPSILON)
#else
/* float32: each step re-rounds x and S to float (eps 1.2e-7) and the gain amplifies by
 * cond(S_zz) ~ 10..100; over 6 steps the float filter tracks the double reference to
 * a few 1e-6 (seen 2.8e-6) -> 2e-5. */
#define TOL_KF 2e-5
/* float32: as for double, 4 eps of float. */
#define TOL_POINT (4.0 * (double)FLT_EPSILON)
#endif

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)
#define STEPS 6

/* ---- the linear-Gaussian test problem --------------------------------------------------- */

/* Model callbacks' context: x_next = F x, z = H x (evaluated in double, rounded). */
typedef struct {
    size_t n;
    size_t m;
    rfe_real_t F[NM * NM]; /* ld NM */
    rfe_real_t H[MM * NM]; /* ld NM */
} lin_model_t;

static rfe_status_t lin_process(void *ctx, const rfe_real_t *x, rfe_real_t *x_next, size_t n)
{
    const lin_model_t *mdl = (const lin_model_t *)ctx;
    size_t i;
    size_t j;
    for (i = 0u; i < n; ++i) {
        double acc = 0.0;
        for (j = 0u; j < n; ++j) {
            acc += (double)mdl->F[(i * NM) + j] * (double)x[j];
        }
        x_next[i] = (rfe_real_t)acc;
    }
    return RFE_OK;
}

static rfe_status_t lin_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n, size_t m)
{
    const lin_model_t *mdl = (const lin_model_t *)ctx;
    size_t r;
    size_t j;
    for (r = 0u; r < m; ++r) {
        double acc = 0.0;
        for (j = 0u; j < n; ++j) {
            acc += (double)mdl->H[(r * NM) + j] * (double)x[j];
        }
        z[r] = (rfe_real_t)acc;
    }
    return RFE_OK;
}

/* Everything needed to initialise the filter and its reference. Matrices given to
 * rfe_sckf_init are row-major with ld = columns (n or m). */
typedef struct {
    size_t n;
    size_t m;
    lin_model_t mdl;
    rfe_real_t x0[NM];
    rfe_real_t S0[NM * NM];
    rfe_real_t SQ[NM * NM];
    rfe_real_t SR[MM * MM];
} problem_t;

static void make_problem(problem_t *p, size_t n, size_t m, uint64_t seed)
{
    size_t i;
    size_t j;
    memset(p, 0, sizeof *p);
    rng_seed(seed);
    p->n = n;
    p->m = m;
    p->mdl.n = n;
    p->mdl.m = m;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            p->mdl.F[(i * NM) + j] = (rfe_real_t)(((i == j) ? 0.9 : 0.0) + (0.15 * rng_uniform()));
        }
    }
    for (i = 0u; i < m; ++i) {
        for (j = 0u; j < n; ++j) {
            p->mdl.H[(i * NM) + j] = (rfe_real_t)rng_uniform();
        }
    }
    for (i = 0u; i < n; ++i) {
        p->x0[i] = (rfe_real_t)rng_uniform();
    }
    rand_lower(p->S0, n, 0.5, 0.5, 0.3);
    rand_lower(p->SQ, n, 0.05, 0.1, 0.03);
    rand_lower(p->SR, m, 0.2, 0.2, 0.05);
}

/* ---- the reference: textbook Kalman filter in double (kalman_ref.h) --------------------- */

/* M M^T of a k x k lower factor stored with ld k. */
static void outer_lower(const rfe_real_t *M, size_t k, double out[][NM])
{
    size_t i;
    size_t j;
    size_t c;
    for (i = 0u; i < k; ++i) {
        for (j = 0u; j < k; ++j) {
            double acc = 0.0;
            for (c = 0u; c <= ((i < j) ? i : j); ++c) {
                acc += (double)M[(i * k) + c] * (double)M[(j * k) + c];
            }
            out[i][j] = acc;
        }
    }
}

static void ref_init(kf_ref_t *r, const problem_t *p)
{
    double tmp[NM][NM];
    size_t i;
    size_t j;
    memset(r, 0, sizeof *r);
    r->n = p->n;
    r->m = p->m;
    for (i = 0u; i < p->n; ++i) {
        r->x[i] = (double)p->x0[i];
    }
    outer_lower(p->S0, p->n, r->P);
    outer_lower(p->SQ, p->n, r->Q);
    outer_lower(p->SR, p->m, tmp);
    for (i = 0u; i < p->m; ++i) {
        for (j = 0u; j < p->m; ++j) {
            r->R[i][j] = tmp[i][j];
        }
    }
}

/* x- = F x,  P- = F P F^T + Q  (mdl NULL: F = identity). */
static void ref_predict(kf_ref_t *r, const lin_model_t *mdl)
{
    double F[NM][NM];
    size_t i;
    size_t j;
    if (mdl == NULL) {
        kf_ref_predict(r, NULL);
        return;
    }
    for (i = 0u; i < r->n; ++i) {
        for (j = 0u; j < r->n; ++j) {
            F[i][j] = (double)mdl->F[(i * NM) + j];
        }
    }
    kf_ref_predict(r, F);
}

/* Kalman update with the model's H (see kf_ref_update). */
static void ref_update(kf_ref_t *r, const lin_model_t *mdl, const rfe_real_t *y)
{
    double H[MM][NM];
    size_t i;
    size_t j;
    for (i = 0u; i < r->m; ++i) {
        for (j = 0u; j < r->n; ++j) {
            H[i][j] = (double)mdl->H[(i * NM) + j];
        }
    }
    kf_ref_update(r, H, y);
}

/* ---- comparisons and invariants --------------------------------------------------------- */

static void assert_matches_ref(const rfe_sckf_t *f, const kf_ref_t *r, const char *when)
{
    const size_t n = r->n;
    double xs = 1.0;
    double ps = 0.0;
    double ex = 0.0;
    double ep = 0.0;
    size_t i;
    size_t j;
    size_t k;
    for (i = 0u; i < n; ++i) {
        xs = fmax(xs, fabs(r->x[i]));
        for (j = 0u; j < n; ++j) {
            ps = fmax(ps, fabs(r->P[i][j]));
        }
    }
    for (i = 0u; i < n; ++i) {
        ex = fmax(ex, fabs((double)f->x[i] - r->x[i]));
        for (j = 0u; j < n; ++j) {
            double acc = 0.0;
            for (k = 0u; k < n; ++k) {
                acc += (double)f->S[(i * NM) + k] * (double)f->S[(j * NM) + k];
            }
            ep = fmax(ep, fabs(acc - r->P[i][j]));
        }
    }
    if (!((ex / xs) <= TOL_KF) || !((ep / ps) <= TOL_KF)) {
        print_error("after %s: n=%zu m=%zu\n", when, n, r->m);
    }
    ASSERT_LE(ex / xs, TOL_KF, "SCKF mean vs Kalman filter");
    ASSERT_LE(ep / ps, TOL_KF, "SCKF S S^T vs Kalman filter");
}

/* (d) S lower-triangular (exact zeros above the diagonal) with non-negative diagonal. */
static void assert_s_invariants(const rfe_sckf_t *f)
{
    size_t i;
    size_t j;
    for (i = 0u; i < f->n; ++i) {
        assert_true(f->S[(i * NM) + i] >= (rfe_real_t)0.0);
        assert_true(isfinite(f->S[(i * NM) + i]));
        for (j = i + 1u; j < f->n; ++j) {
            assert_true(f->S[(i * NM) + j] == (rfe_real_t)0.0);
        }
    }
}

static void init_filter(rfe_sckf_t *f, const problem_t *p)
{
    memset(f, 0, sizeof *f);
    assert_int_equal(rfe_sckf_init(f, p->n, p->m, p->x0, p->S0, p->SQ, p->SR), RFE_OK);
}

/* Byte image of the state without the scratch member w. */
#define STATE_BYTES offsetof(rfe_sckf_t, w)

/* ---- (a) linear-Gaussian: SCKF = Kalman filter ------------------------------------------ */

static void run_linear(size_t n, size_t m, int random_walk, uint64_t seed)
{
    static problem_t p;
    static rfe_sckf_t f;
    static kf_ref_t r;
    rfe_real_t y[MM];
    int step;
    size_t i;
    make_problem(&p, n, m, seed);
    init_filter(&f, &p);
    ref_init(&r, &p);
    assert_matches_ref(&f, &r, "init");
    for (step = 0; step < STEPS; ++step) {
        if (random_walk != 0) {
            assert_int_equal(rfe_sckf_predict(&f, NULL, &p.mdl), RFE_OK);
            ref_predict(&r, NULL);
        } else {
            assert_int_equal(rfe_sckf_predict(&f, lin_process, &p.mdl), RFE_OK);
            ref_predict(&r, &p.mdl);
        }
        assert_s_invariants(&f);
        assert_matches_ref(&f, &r, "predict");
        for (i = 0u; i < m; ++i) {
            y[i] = (rfe_real_t)(2.0 * rng_uniform());
        }
        assert_int_equal(rfe_sckf_update(&f, lin_measure, &p.mdl, y), RFE_OK);
        ref_update(&r, &p.mdl, y);
        assert_s_invariants(&f);
        assert_matches_ref(&f, &r, "update");
    }
}

/* REQ-SCKF-001 */
static void test_rfe_sckf_linear_matches_kalman_n4(void **state)
{
    size_t m;
    (void)state;
    for (m = 1u; m <= MM; ++m) {
        run_linear(4u, m, 0, 200u + m);
    }
}

/* REQ-SCKF-001 */
static void test_rfe_sckf_linear_matches_kalman_n8(void **state)
{
    size_t m;
    (void)state;
    for (m = 1u; m <= MM; ++m) {
        run_linear(NM, m, 0, 300u + m);
    }
}

/* REQ-SCKF-001 REQ-SCKF-002 */
static void test_rfe_sckf_random_walk_matches_kalman(void **state)
{
    size_t m;
    (void)state;
    for (m = 1u; m <= MM; ++m) {
        run_linear(4u, m, 1, 400u + m);
        run_linear(NM, m, 1, 500u + m);
    }
}

/* A run of time updates alone (the estimator's held steps) must not move the random walk's
 * mean by a single bit: averaging the symmetric points used to add rounding that walked x
 * (out of [mu_min, mu_max] in a long hold). The sd still grows. */
/* REQ-SCKF-002 */
static void test_rfe_sckf_random_walk_hold_keeps_mean_exactly(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    rfe_real_t x[NM];
    rfe_real_t sd0[NM];
    rfe_real_t sd[NM];
    size_t k;
    (void)state;
    make_problem(&p, 4u, 3u, 4242u);
    p.x0[0] = (rfe_real_t)0.05; /* values whose sums with the point offsets round */
    p.x0[1] = (rfe_real_t)0.1;
    p.x0[2] = (rfe_real_t)0.3;
    p.x0[3] = (rfe_real_t)1.2;
    assert_int_equal(rfe_sckf_init(&f, 4u, 3u, p.x0, p.S0, p.SQ, p.SR), RFE_OK);
    assert_int_equal(rfe_sckf_get(&f, NULL, sd0), RFE_OK);
    for (k = 0u; k < 2000u; ++k) {
        assert_int_equal(rfe_sckf_predict(&f, NULL, NULL), RFE_OK);
        assert_int_equal(rfe_sckf_get(&f, x, sd), RFE_OK);
        assert_memory_equal(x, p.x0, 4u * sizeof x[0]);
    }
    for (k = 0u; k < 4u; ++k) {
        assert_true(sd[k] > sd0[k]);
    }
}

/* Small dimensions too: n = 1..3 against every m. */
/* REQ-SCKF-001 */
static void test_rfe_sckf_linear_matches_kalman_small_n(void **state)
{
    size_t n;
    size_t m;
    (void)state;
    for (n = 1u; n <= 3u; ++n) {
        for (m = 1u; m <= MM; ++m) {
            run_linear(n, m, 0, 600u + (10u * n) + m);
        }
    }
}

/* ---- (b) mocked callbacks --------------------------------------------------------------- */

enum { MOCK_OK = 0, MOCK_FAIL = 1, MOCK_NAN = 2 };
#define MOCK_ERR_STATUS RFE_ERR_PARAM /* a status the filter never produces itself here */

static rfe_status_t mock_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n, size_t m)
{
    int mode;
    function_called();
    check_expected_ptr(ctx);
    check_expected(n);
    check_expected(m);
    check_expected_ptr(x);
    mode = (int)mock();
    (void)lin_measure(ctx, x, z, n, m);
    if (mode == MOCK_NAN) {
        z[m - 1u] = (rfe_real_t)NAN;
    }
    return (mode == MOCK_FAIL) ? MOCK_ERR_STATUS : RFE_OK;
}

static rfe_status_t mock_process(void *ctx, const rfe_real_t *x, rfe_real_t *x_next, size_t n)
{
    int mode;
    function_called();
    check_expected_ptr(ctx);
    check_expected(n);
    check_expected_ptr(x);
    mode = (int)mock();
    (void)lin_process(ctx, x, x_next, n);
    if (mode == MOCK_NAN) {
        x_next[0] = (rfe_real_t)NAN;
    }
    return (mode == MOCK_FAIL) ? MOCK_ERR_STATUS : RFE_OK;
}

/* Queues the expectations of one update: exactly 2n calls, in order, the last one
 * behaving as last_mode. */
static void expect_measure_calls(const rfe_sckf_t *f, void *ctx, int last_mode)
{
    const size_t n = f->n;
    size_t k;
    fill_expected_points(f->x, f->S, f->n, TOL_POINT);
    expect_function_calls(mock_measure, (int)(2u * n));
    for (k = 0u; k < (2u * n); ++k) {
        expect_value(mock_measure, ctx, (uintptr_t)ctx);
        expect_value(mock_measure, n, n);
        expect_value(mock_measure, m, f->m);
        expect_check(mock_measure, x, check_point, (uintptr_t)&expected_pts[k]);
        will_return(mock_measure, (k == ((2u * n) - 1u)) ? last_mode : MOCK_OK);
    }
}

static void expect_process_calls(const rfe_sckf_t *f, void *ctx, int last_mode)
{
    const size_t n = f->n;
    size_t k;
    fill_expected_points(f->x, f->S, f->n, TOL_POINT);
    expect_function_calls(mock_process, (int)(2u * n));
    for (k = 0u; k < (2u * n); ++k) {
        expect_value(mock_process, ctx, (uintptr_t)ctx);
        expect_value(mock_process, n, n);
        expect_check(mock_process, x, check_point, (uintptr_t)&expected_pts[k]);
        will_return(mock_process, (k == ((2u * n) - 1u)) ? last_mode : MOCK_OK);
    }
}

/* REQ-CUB-001 */
static void test_rfe_sckf_update_evaluates_cubature_points(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static kf_ref_t r;
    rfe_real_t y[MM];
    size_t n;
    size_t i;
    (void)state;
    for (n = 1u; n <= NM; n += 3u) { /* n = 1, 4, 7 */
        const size_t m = (n < MM) ? n : 3u;
        make_problem(&p, n, m, 700u + n);
        init_filter(&f, &p);
        ref_init(&r, &p);
        assert_int_equal(rfe_sckf_predict(&f, lin_process, &p.mdl), RFE_OK);
        ref_predict(&r, &p.mdl);
        for (i = 0u; i < m; ++i) {
            y[i] = (rfe_real_t)rng_uniform();
        }
        expect_measure_calls(&f, &p.mdl, MOCK_OK);
        assert_int_equal(rfe_sckf_update(&f, mock_measure, &p.mdl, y), RFE_OK);
        /* the mocked model is the linear one: the result is still the Kalman filter's */
        ref_update(&r, &p.mdl, y);
        assert_matches_ref(&f, &r, "mocked update");
    }
}

/* REQ-CUB-001 */
static void test_rfe_sckf_predict_evaluates_cubature_points(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static kf_ref_t r;
    size_t n;
    (void)state;
    for (n = 2u; n <= NM; n += 3u) { /* n = 2, 5, 8 */
        make_problem(&p, n, 2u, 800u + n);
        init_filter(&f, &p);
        ref_init(&r, &p);
        expect_process_calls(&f, &p.mdl, MOCK_OK);
        assert_int_equal(rfe_sckf_predict(&f, mock_process, &p.mdl), RFE_OK);
        ref_predict(&r, &p.mdl);
        assert_matches_ref(&f, &r, "mocked predict");
    }
}

/* A callback error (status or NaN output) at the very last cubature point, after the
 * filter has done all the other work: the status comes back and x, S are as before. */
static void update_fault_untouched(int mode, rfe_status_t expected)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    rfe_real_t y[MM] = {0};
    make_problem(&p, 4u, 3u, 900u + (uint64_t)mode);
    init_filter(&f, &p);
    assert_int_equal(rfe_sckf_predict(&f, lin_process, &p.mdl), RFE_OK);
    y[0] = (rfe_real_t)0.5;
    memcpy(before, &f, STATE_BYTES);
    expect_measure_calls(&f, &p.mdl, mode);
    assert_int_equal(rfe_sckf_update(&f, mock_measure, &p.mdl, y), expected);
    assert_memory_equal(before, &f, STATE_BYTES);
    /* and the filter still works afterwards */
    assert_int_equal(rfe_sckf_update(&f, lin_measure, &p.mdl, y), RFE_OK);
}

static void predict_fault_untouched(int mode, rfe_status_t expected)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    make_problem(&p, 4u, 3u, 950u + (uint64_t)mode);
    init_filter(&f, &p);
    memcpy(before, &f, STATE_BYTES);
    expect_process_calls(&f, &p.mdl, mode);
    assert_int_equal(rfe_sckf_predict(&f, mock_process, &p.mdl), expected);
    assert_memory_equal(before, &f, STATE_BYTES);
    assert_int_equal(rfe_sckf_predict(&f, lin_process, &p.mdl), RFE_OK);
}

/* REQ-SCKF-007 */
static void test_rfe_sckf_update_callback_error_untouched(void **state)
{
    (void)state;
    update_fault_untouched(MOCK_FAIL, MOCK_ERR_STATUS);
}

/* REQ-SCKF-007 */
static void test_rfe_sckf_update_callback_nan_untouched(void **state)
{
    (void)state;
    update_fault_untouched(MOCK_NAN, RFE_ERR_NONFINITE);
}

/* REQ-SCKF-007 */
static void test_rfe_sckf_predict_callback_error_untouched(void **state)
{
    (void)state;
    predict_fault_untouched(MOCK_FAIL, MOCK_ERR_STATUS);
}

/* REQ-SCKF-007 */
static void test_rfe_sckf_predict_callback_nan_untouched(void **state)
{
    (void)state;
    predict_fault_untouched(MOCK_NAN, RFE_ERR_NONFINITE);
}

/* An error at the first point is returned as well (whether or not the remaining points
 * are evaluated is not specified, so a plain callback counts instead of a strict mock). */
static int fail_first_calls;
static rfe_status_t fail_first_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n,
                                       size_t m)
{
    ++fail_first_calls;
    (void)lin_measure(ctx, x, z, n, m);
    return (fail_first_calls == 1) ? RFE_ERR_RANGE : RFE_OK;
}

/* REQ-SCKF-007 */
static void test_rfe_sckf_update_callback_error_first_point_untouched(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    rfe_real_t y[MM] = {0};
    (void)state;
    make_problem(&p, NM, MM, 990u);
    init_filter(&f, &p);
    memcpy(before, &f, STATE_BYTES);
    fail_first_calls = 0;
    assert_int_equal(rfe_sckf_update(&f, fail_first_measure, &p.mdl, y), RFE_ERR_RANGE);
    assert_true(fail_first_calls >= 1);
    assert_memory_equal(before, &f, STATE_BYTES);
}

/* Zero innovation covariance: h constant and S_R = 0 make S_zz = 0, the gain undefined. */
/* REQ-SCKF-007 */
static void test_rfe_sckf_update_singular_innovation_untouched(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    rfe_real_t y[MM] = {0};
    (void)state;
    make_problem(&p, 4u, 2u, 991u);
    memset(p.mdl.H, 0, sizeof p.mdl.H);
    memset(p.SR, 0, sizeof p.SR);
    init_filter(&f, &p);
    memcpy(before, &f, STATE_BYTES);
    assert_int_equal(rfe_sckf_update(&f, lin_measure, &p.mdl, y),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_memory_equal(before, &f, STATE_BYTES);
}

/* Finite but huge model outputs (huge_process, huge_measure: filter_fixtures.h, 0.9 of the
 * largest rfe_real_t at every point): their mean overflows, so Tria sees Inf. The step must
 * fail and leave the state alone. */
/* REQ-SCKF-007 */
static void test_rfe_sckf_predict_overflow_untouched(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    (void)state;
    make_problem(&p, 4u, 3u, 992u);
    init_filter(&f, &p);
    memcpy(before, &f, STATE_BYTES);
    assert_int_equal(rfe_sckf_predict(&f, huge_process, NULL), RFE_ERR_NONFINITE);
    assert_memory_equal(before, &f, STATE_BYTES);
}

/* REQ-SCKF-007 */
static void test_rfe_sckf_update_measure_overflow_untouched(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    rfe_real_t y[MM] = {0};
    (void)state;
    make_problem(&p, 4u, 3u, 993u);
    init_filter(&f, &p);
    memcpy(before, &f, STATE_BYTES);
    assert_int_equal(rfe_sckf_update(&f, huge_measure, NULL, y), RFE_ERR_NONFINITE);
    assert_memory_equal(before, &f, STATE_BYTES);
}

/* A finite y whose correction overflows the mean: n = m = 1, h(x) = 0.01 x, S_R = 1e-3
 * give K ~ 99, and y = MAX / 2 makes x = x- + K (y - z) = Inf. The update must not report
 * success with a non-finite mean (the CKF checks exactly this: ckf_flt.c, "x = x- + K (y - z)"
 * is followed by a finiteness check); expected RFE_ERR_NONFINITE with the state untouched. */
/* REQ-SCKF-007 */
static void test_rfe_sckf_update_mean_overflow_untouched(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    rfe_real_t y[MM] = {0};
    rfe_status_t st;
    (void)state;
    make_problem(&p, 1u, 1u, 994u);
    p.mdl.H[0] = (rfe_real_t)0.01;
    p.x0[0] = (rfe_real_t)0.5;
    p.S0[0] = (rfe_real_t)1.0;
    p.SR[0] = (rfe_real_t)1e-3;
    init_filter(&f, &p);
    memcpy(before, &f, STATE_BYTES);
    y[0] = (rfe_real_t)0.5 * REAL_BIG;
    st = rfe_sckf_update(&f, lin_measure, &p.mdl, y);
    if (st == RFE_OK) {
        if (!isfinite(f.x[0])) {
            print_error("rfe_sckf_update returned RFE_OK with x = %g for finite y = %g\n",
                        (double)f.x[0], (double)y[0]);
            fail();
        }
    } else {
        assert_int_equal(st, RFE_ERR_NONFINITE);
        assert_memory_equal(before, &f, STATE_BYTES);
    }
}

/* ---- (c) errors ------------------------------------------------------------------------- */

/* REQ-SCKF-008 */
static void test_rfe_sckf_init_null(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static rfe_sckf_t ref;
    (void)state;
    make_problem(&p, 4u, 3u, 1001u);
    memset(&f, 0xA5, sizeof f);
    memcpy(&ref, &f, sizeof f);
    assert_int_equal(rfe_sckf_init(NULL, 4u, 3u, p.x0, p.S0, p.SQ, p.SR), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_init(&f, 4u, 3u, NULL, p.S0, p.SQ, p.SR), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_init(&f, 4u, 3u, p.x0, NULL, p.SQ, p.SR), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_init(&f, 4u, 3u, p.x0, p.S0, NULL, p.SR), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_init(&f, 4u, 3u, p.x0, p.S0, p.SQ, NULL), RFE_ERR_NULL);
    assert_memory_equal(&f, &ref, sizeof f);
}

/* The init as its wrapper would call it from a caller compiled otherwise (another size of
 * the state, another configuration word: maxima, number type) writes nothing; through the
 * wrapper, this file's own layout, it is accepted. */
/* REQ-ABI-001 */
static void test_rfe_sckf_init_refuses_other_layout_or_word(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static rfe_sckf_t ref;
    const uint32_t other_type = RFE_CONFIG_REAL ^ 3u;         /* float <-> double */
    const uint32_t other_max = RFE_CONFIG_REAL ^ (1u << 16u); /* another RFE_N_MAX */
    (void)state;
    make_problem(&p, 4u, 3u, 1005u);
    memset(&f, 0xA5, sizeof f);
    memcpy(&ref, &f, sizeof f);
    assert_int_equal((rfe_sckf_init)(&f, 4u, 3u, p.x0, p.S0, p.SQ, p.SR, sizeof f - 8u,
                                     RFE_CONFIG_REAL), RFE_ERR_ABI);
    assert_int_equal((rfe_sckf_init)(&f, 4u, 3u, p.x0, p.S0, p.SQ, p.SR, sizeof f, other_type),
                     RFE_ERR_ABI);
    assert_int_equal((rfe_sckf_init)(&f, 4u, 3u, p.x0, p.S0, p.SQ, p.SR, sizeof f, other_max),
                     RFE_ERR_ABI);
    /* refused before anything else is looked at */
    assert_int_equal((rfe_sckf_init)(NULL, 4u, 3u, NULL, NULL, NULL, NULL, sizeof f, other_type),
                     RFE_ERR_ABI);
    assert_memory_equal(&f, &ref, sizeof f);
    assert_int_equal(rfe_sckf_init(&f, 4u, 3u, p.x0, p.S0, p.SQ, p.SR), RFE_OK);
    assert_int_equal(rfe_sckf_predict(&f, NULL, NULL), RFE_OK);
}

/* REQ-SCKF-008 */
static void test_rfe_sckf_init_size_errors(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static rfe_sckf_t ref;
    static rfe_real_t big[(NM + 1u) * (NM + 1u)];
    static const size_t cases[][2] = {{0u, 3u}, {NM + 1u, 3u}, {4u, 0u}, {4u, MM + 1u}};
    size_t c;
    size_t i;
    (void)state;
    make_problem(&p, 4u, 3u, 1002u);
    for (i = 0u; i < ((NM + 1u) * (NM + 1u)); ++i) {
        big[i] = (rfe_real_t)((i % (NM + 2u)) == 0u); /* identity at any size */
    }
    memset(&f, 0xA5, sizeof f);
    memcpy(&ref, &f, sizeof f);
    for (c = 0u; c < (sizeof cases / sizeof cases[0]); ++c) {
        assert_int_equal(rfe_sckf_init(&f, cases[c][0], cases[c][1], big, big, big, big),
                         RFE_ERR_SIZE);
        assert_memory_equal(&f, &ref, sizeof f);
    }
}

/* REQ-SCKF-008 */
static void test_rfe_sckf_init_nonfinite(void **state)
{
    static problem_t p;
    static problem_t bad;
    static rfe_sckf_t f;
    static rfe_sckf_t ref;
    const rfe_real_t vals[2] = {(rfe_real_t)NAN, (rfe_real_t)INFINITY};
    size_t v;
    int which;
    (void)state;
    make_problem(&p, 4u, 3u, 1003u);
    memset(&f, 0xA5, sizeof f);
    memcpy(&ref, &f, sizeof f);
    for (v = 0u; v < 2u; ++v) {
        for (which = 0; which < 4; ++which) {
            bad = p;
            switch (which) {
            case 0: bad.x0[3] = vals[v]; break;
            case 1: bad.S0[(2u * 4u) + 1u] = vals[v]; break; /* lower triangle */
            case 2: bad.SQ[(3u * 4u) + 3u] = vals[v]; break;
            default: bad.SR[(2u * 3u) + 0u] = vals[v]; break;
            }
            assert_int_equal(rfe_sckf_init(&f, 4u, 3u, bad.x0, bad.S0, bad.SQ, bad.SR),
                             RFE_ERR_NONFINITE);
            assert_memory_equal(&f, &ref, sizeof f);
        }
    }
}

/* "Only the lower triangles of S0, SQ, SR are read": finite garbage above the diagonal
 * changes nothing (the stored factors are lower-triangular and the steps agree). */
/* REQ-SCKF-008 */
static void test_rfe_sckf_init_ignores_upper_triangles(void **state)
{
    static problem_t p;
    static problem_t g;
    static rfe_sckf_t f1;
    static rfe_sckf_t f2;
    rfe_real_t y[MM] = {(rfe_real_t)0.3, (rfe_real_t)-0.2, (rfe_real_t)0.1};
    size_t i;
    size_t j;
    (void)state;
    make_problem(&p, 4u, 3u, 1004u);
    g = p;
    for (i = 0u; i < 4u; ++i) {
        for (j = i + 1u; j < 4u; ++j) {
            g.S0[(i * 4u) + j] = (rfe_real_t)7.0;
            g.SQ[(i * 4u) + j] = (rfe_real_t)-3.0;
            if (j < 3u) {
                g.SR[(i * 3u) + j] = (rfe_real_t)5.0;
            }
        }
    }
    init_filter(&f1, &p);
    init_filter(&f2, &g);
    assert_memory_equal(&f1, &f2, STATE_BYTES);
    assert_int_equal(rfe_sckf_predict(&f1, lin_process, &p.mdl), RFE_OK);
    assert_int_equal(rfe_sckf_predict(&f2, lin_process, &g.mdl), RFE_OK);
    assert_int_equal(rfe_sckf_update(&f1, lin_measure, &p.mdl, y), RFE_OK);
    assert_int_equal(rfe_sckf_update(&f2, lin_measure, &g.mdl, y), RFE_OK);
    assert_memory_equal(f1.x, f2.x, sizeof f1.x);
    assert_memory_equal(f1.S, f2.S, sizeof f1.S);
}

/* Same promise with a NaN above the diagonal: an entry that is not read cannot make the
 * call fail. */
/* REQ-SCKF-008 */
static void test_rfe_sckf_init_nonfinite_upper_triangle_ignored(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static rfe_sckf_t ref;
    int which;
    (void)state;
    for (which = 0; which < 3; ++which) {
        make_problem(&p, 4u, 3u, 1005u);
        init_filter(&ref, &p);
        switch (which) {
        case 0: p.S0[(0u * 4u) + 3u] = (rfe_real_t)NAN; break;
        case 1: p.SQ[(1u * 4u) + 2u] = (rfe_real_t)NAN; break;
        default: p.SR[(0u * 3u) + 1u] = (rfe_real_t)NAN; break;
        }
        memset(&f, 0, sizeof f);
        if (rfe_sckf_init(&f, 4u, 3u, p.x0, p.S0, p.SQ, p.SR) != RFE_OK) {
            print_error("rfe_sckf_init rejected a NaN in the strict upper triangle of %s, "
                        "which sckf.h says is not read\n",
                        (which == 0) ? "S0" : ((which == 1) ? "SQ" : "SR"));
            fail();
        }
        assert_memory_equal(&f, &ref, STATE_BYTES);
    }
}

/* REQ-SCKF-008 */
static void test_rfe_sckf_use_before_init(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static rfe_sckf_t ref;
    rfe_real_t y[MM] = {0};
    rfe_real_t x[NM];
    rfe_real_t sd[NM];
    int clamped = 7;
    (void)state;
    make_problem(&p, 4u, 3u, 1006u);
    memset(&f, 0, sizeof f);
    memcpy(&ref, &f, sizeof f);
    assert_int_equal(rfe_sckf_predict(&f, lin_process, &p.mdl), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_sckf_predict(&f, NULL, NULL), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_sckf_update(&f, lin_measure, &p.mdl, y),
                     RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_sckf_get(&f, x, sd), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_sckf_clamp(&f, (rfe_real_t)0.0, (rfe_real_t)1.0, &clamped),
                     RFE_ERR_NOT_INITIALISED);
    assert_int_equal(clamped, 7);
    assert_memory_equal(&f, &ref, sizeof f);
    /* a failed init does not make the state usable */
    assert_int_equal(rfe_sckf_init(&f, 0u, 3u, p.x0, p.S0, p.SQ, p.SR), RFE_ERR_SIZE);
    assert_int_equal(rfe_sckf_predict(&f, NULL, NULL), RFE_ERR_NOT_INITIALISED);
}

/* REQ-SCKF-008 */
static void test_rfe_sckf_null_args(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    rfe_real_t y[MM] = {0};
    rfe_real_t x[NM];
    int clamped = 7;
    (void)state;
    make_problem(&p, 4u, 3u, 1007u);
    init_filter(&f, &p);
    memcpy(before, &f, STATE_BYTES);
    assert_int_equal(rfe_sckf_predict(NULL, lin_process, &p.mdl), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_update(NULL, lin_measure, &p.mdl, y), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_update(&f, NULL, &p.mdl, y), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_update(&f, lin_measure, &p.mdl, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_get(NULL, x, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_clamp(NULL, (rfe_real_t)0.0, (rfe_real_t)1.0, &clamped),
                     RFE_ERR_NULL);
    assert_int_equal(rfe_sckf_clamp(&f, (rfe_real_t)0.0, (rfe_real_t)1.0, NULL),
                     RFE_ERR_NULL);
    assert_int_equal(clamped, 7);
    assert_memory_equal(before, &f, STATE_BYTES);
}

/* REQ-SCKF-007 */
static void test_rfe_sckf_update_nonfinite_y_untouched(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    const rfe_real_t bad[3] = {(rfe_real_t)NAN, (rfe_real_t)INFINITY, (rfe_real_t)-INFINITY};
    rfe_real_t y[MM];
    size_t b;
    size_t k;
    (void)state;
    make_problem(&p, 4u, 3u, 1008u);
    init_filter(&f, &p);
    assert_int_equal(rfe_sckf_predict(&f, lin_process, &p.mdl), RFE_OK);
    memcpy(before, &f, STATE_BYTES);
    for (b = 0u; b < 3u; ++b) {
        for (k = 0u; k < 3u; ++k) {
            y[0] = (rfe_real_t)0.1;
            y[1] = (rfe_real_t)0.2;
            y[2] = (rfe_real_t)0.3;
            y[k] = bad[b];
            assert_int_equal(rfe_sckf_update(&f, lin_measure, &p.mdl, y),
                             RFE_ERR_NONFINITE);
            assert_memory_equal(before, &f, STATE_BYTES);
        }
    }
}

/* REQ-SCKF-006 */
static void test_rfe_sckf_clamp_range_errors(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    static unsigned char before[STATE_BYTES];
    int clamped = 7;
    (void)state;
    make_problem(&p, 4u, 3u, 1009u);
    init_filter(&f, &p);
    memcpy(before, &f, STATE_BYTES);
    assert_int_equal(rfe_sckf_clamp(&f, (rfe_real_t)1.0, (rfe_real_t)0.5, &clamped),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_sckf_clamp(&f, (rfe_real_t)NAN, (rfe_real_t)1.0, &clamped),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_sckf_clamp(&f, (rfe_real_t)0.0, (rfe_real_t)NAN, &clamped),
                     RFE_ERR_RANGE);
    assert_int_equal(clamped, 7);
    assert_memory_equal(before, &f, STATE_BYTES);
}

/* REQ-SCKF-006 */
static void test_rfe_sckf_clamp_projects_mean(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    rfe_real_t S_before[NM * NM];
    rfe_real_t x_before[NM];
    int clamped = 7;
    size_t i;
    (void)state;
    make_problem(&p, 4u, 3u, 1010u);
    p.x0[0] = (rfe_real_t)-0.5;
    p.x0[1] = (rfe_real_t)0.25;
    p.x0[2] = (rfe_real_t)2.0;
    p.x0[3] = (rfe_real_t)1.2;
    init_filter(&f, &p);
    memcpy(S_before, f.S, sizeof S_before);
    /* inside: nothing moves */
    memcpy(x_before, f.x, sizeof x_before);
    assert_int_equal(rfe_sckf_clamp(&f, (rfe_real_t)-1.0, (rfe_real_t)2.0, &clamped),
                     RFE_OK);
    assert_int_equal(clamped, 0);
    assert_memory_equal(x_before, f.x, sizeof x_before);
    /* [0.05, 1.2]: -0.5 -> 0.05, 2.0 -> 1.2, the others stay (1.2 is on the bound) */
    assert_int_equal(rfe_sckf_clamp(&f, (rfe_real_t)0.05, (rfe_real_t)1.2, &clamped),
                     RFE_OK);
    assert_int_equal(clamped, 1);
    assert_true(f.x[0] == (rfe_real_t)0.05);
    assert_true(f.x[1] == (rfe_real_t)0.25);
    assert_true(f.x[2] == (rfe_real_t)1.2);
    assert_true(f.x[3] == (rfe_real_t)1.2);
    assert_memory_equal(S_before, f.S, sizeof S_before);
    /* lo == hi is a valid (degenerate) interval */
    assert_int_equal(rfe_sckf_clamp(&f, (rfe_real_t)0.5, (rfe_real_t)0.5, &clamped),
                     RFE_OK);
    assert_int_equal(clamped, 1);
    for (i = 0u; i < 4u; ++i) {
        assert_true(f.x[i] == (rfe_real_t)0.5);
    }
}

/* REQ-SCKF-008 */
static void test_rfe_sckf_get_outputs(void **state)
{
    static problem_t p;
    static rfe_sckf_t f;
    rfe_real_t x[NM];
    rfe_real_t sd[NM];
    rfe_real_t x2[NM];
    rfe_real_t sd2[NM];
    size_t i;
    size_t k;
    (void)state;
    make_problem(&p, 5u, 2u, 1011u);
    init_filter(&f, &p);
    assert_int_equal(rfe_sckf_predict(&f, lin_process, &p.mdl), RFE_OK);
    assert_int_equal(rfe_sckf_get(&f, x, sd), RFE_OK);
    for (i = 0u; i < 5u; ++i) {
        double pii = 0.0;
        for (k = 0u; k <= i; ++k) {
            pii += (double)f.S[(i * NM) + k] * (double)f.S[(i * NM) + k];
        }
        assert_true(x[i] == f.x[i]);
        ASSERT_LE(fabs((double)sd[i] - sqrt(pii)), 4.0 * TOL_POINT * sqrt(pii), "sd");
    }
    assert_int_equal(rfe_sckf_get(&f, x2, NULL), RFE_OK);
    assert_memory_equal(x, x2, 5u * sizeof x[0]);
    assert_int_equal(rfe_sckf_get(&f, NULL, sd2), RFE_OK);
    assert_memory_equal(sd, sd2, 5u * sizeof sd[0]);
    assert_int_equal(rfe_sckf_get(&f, NULL, NULL), RFE_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_sckf_linear_matches_kalman_n4),
        cmocka_unit_test(test_rfe_sckf_linear_matches_kalman_n8),
        cmocka_unit_test(test_rfe_sckf_random_walk_matches_kalman),
        cmocka_unit_test(test_rfe_sckf_random_walk_hold_keeps_mean_exactly),
        cmocka_unit_test(test_rfe_sckf_linear_matches_kalman_small_n),
        cmocka_unit_test(test_rfe_sckf_update_evaluates_cubature_points),
        cmocka_unit_test(test_rfe_sckf_predict_evaluates_cubature_points),
        cmocka_unit_test(test_rfe_sckf_update_callback_error_untouched),
        cmocka_unit_test(test_rfe_sckf_update_callback_nan_untouched),
        cmocka_unit_test(test_rfe_sckf_predict_callback_error_untouched),
        cmocka_unit_test(test_rfe_sckf_predict_callback_nan_untouched),
        cmocka_unit_test(test_rfe_sckf_update_callback_error_first_point_untouched),
        cmocka_unit_test(test_rfe_sckf_update_singular_innovation_untouched),
        cmocka_unit_test(test_rfe_sckf_predict_overflow_untouched),
        cmocka_unit_test(test_rfe_sckf_update_measure_overflow_untouched),
        cmocka_unit_test(test_rfe_sckf_update_mean_overflow_untouched),
        cmocka_unit_test(test_rfe_sckf_init_null),
        cmocka_unit_test(test_rfe_sckf_init_refuses_other_layout_or_word),
        cmocka_unit_test(test_rfe_sckf_init_size_errors),
        cmocka_unit_test(test_rfe_sckf_init_nonfinite),
        cmocka_unit_test(test_rfe_sckf_init_ignores_upper_triangles),
        cmocka_unit_test(test_rfe_sckf_init_nonfinite_upper_triangle_ignored),
        cmocka_unit_test(test_rfe_sckf_use_before_init),
        cmocka_unit_test(test_rfe_sckf_null_args),
        cmocka_unit_test(test_rfe_sckf_update_nonfinite_y_untouched),
        cmocka_unit_test(test_rfe_sckf_clamp_range_errors),
        cmocka_unit_test(test_rfe_sckf_clamp_projects_mean),
        cmocka_unit_test(test_rfe_sckf_get_outputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
