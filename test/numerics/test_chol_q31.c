/**
 * @file test_chol_q31.c
 * @brief The fixed-point Cholesky factorisation (rfe_chol_factor_q31) against exact integer
 *        references and back to back against its double twin (rfe_chol_factor_f64).
 *
 * Bounds. Every pivot d_j = P_jj 2^up - sum L_jk^2 and numerator P_ij 2^up - sum L_ik L_jk is
 * exact in int64 (Q(2 q_l), up = 2 q_l - q_p), L_jj = round(sqrt(d_j)) and
 * L_ij = round(numerator / L_jj) are exactly rounded. Hence, in units of Q(2 q_l), with the
 * exact products of the computed L:
 *   (L L^T - P 2^up)_ij = delta L_jj, |delta| <= 1/2            (i > j),
 *   (L L^T - P 2^up)_jj = L_jj^2 - d_j, |.| <= 2 (1/2) sqrt(d_j) + 1/4 <= L_jj + 3/4,
 * checked exactly (int128) — the factor is the exact factor of a matrix within rounding of
 * P. Against the double twin the entries differ by the propagation of those roundings,
 * bounded to first order column by column (LSB of Q(q_l), from the computed L):
 *   D_jj = 1/2 + sum_{k<j} |L_jk| D_jk / L_jj,
 *   D_ij = 1/2 + (sum_{k<j} (|L_ik| D_jk + |L_jk| D_ik) + |L_ij| D_jj) / L_jj,
 * asserted as |L_q - L_f| <= 2 D_ij (the factor 2 covers the second-order terms) plus the
 * double twin's own error (1e-12 relative). Rows with tiny variances next to large ones make
 * D large (a small L_jj divides); the measured worst case is printed relative to it.
 * Random inputs come from the fixed-seed generator (test_rng.h): deterministic.
 */
#include "test_common.h"

#include <stdint.h>
#include <string.h>

#include "rfe/component/chol.h"
#include "rfe/component/chol_q31.h"
#include "host/fixed_conv.h"
#include "test_rng.h"

typedef __int128 i128;

#define NM ((size_t)RFE_N_MAX)
#define AT(M, ld, i, j) ((M)[((i) * (ld)) + (j)])

static double worst_off;   /* max |E_ij| / (L_jj / 2), i > j */
static double worst_diag;  /* max |E_jj| / (L_jj + 3/4) */
static double worst_twin;  /* max |L_q - L_f| / (2 D_ij) */
static double worst_lsb;   /* max |L_q - L_f| in LSB */

/* Random SPD P (n x n, ld ldp) in Q(qp): P = M M^T with M lower, diagonal in [0.5, 1] times a
 * row scale 10^(-3u) (variances over six orders of magnitude) and off-diagonal entries
 * +-0.3 of the row scale; scaled so that max |P_ij| <= 0.9 of the format's range. The upper
 * triangle is filled with garbage (never read). */
static void make_spd(int32_t *P, size_t n, size_t ldp, unsigned qp)
{
    double M[RFE_N_MAX][RFE_N_MAX];
    double Pd[RFE_N_MAX][RFE_N_MAX];
    double sc[RFE_N_MAX];
    double big = 0.0;
    double range = ldexp(1.0, 31 - (int)qp);
    uint32_t s = 0u;
    size_t i;
    size_t j;
    size_t k;
    for (i = 0u; i < n; ++i) {
        sc[i] = pow(10.0, -3.0 * 0.5 * (rng_uniform() + 1.0));
        for (j = 0u; j <= i; ++j) {
            M[i][j] = (j == i) ? ((0.75 + (0.25 * rng_uniform())) * sc[i])
                               : (0.3 * rng_uniform() * sc[i]);
        }
    }
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            double acc = 0.0;
            for (k = 0u; k <= ((i < j) ? i : j); ++k) {
                acc += M[i][k] * M[j][k];
            }
            Pd[i][j] = acc;
            big = fmax(big, fabs(acc));
        }
    }
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < ldp; ++j) {
            AT(P, ldp, i, j) = (j <= i) ? rfe_fix_from_double(Pd[i][j] * 0.9 * range / big, qp, &s)
                                        : (int32_t)0x6B6B6B6B;
        }
    }
    assert_int_equal(s, 0u);
}

static void check_factor(const int32_t *P, size_t n, size_t ldp, unsigned qp, unsigned ql,
                         uint64_t seed)
{
    static int32_t L[NM * (NM + 1u)];
    static double Pf[NM * NM];
    static double Lf[NM * NM];
    double D[RFE_N_MAX][RFE_N_MAX];
    const size_t ldl = n + 1u;
    const unsigned up = (2u * ql) - qp;
    uint32_t sat = 3u;
    size_t i;
    size_t j;
    size_t k;
    (void)seed;
    for (i = 0u; i < (NM * (NM + 1u)); ++i) {
        L[i] = 0x13579BDF;
    }
    assert_int_equal(rfe_chol_factor_q31(P, n, ldp, L, ldl, qp, ql, &sat), RFE_OK);
    assert_int_equal(sat, 3u); /* |L_ij| <= sqrt(P_ii): nothing can saturate */
    for (i = 0u; i < n; ++i) {
        assert_true(AT(L, ldl, i, i) > 0);
        for (j = i + 1u; j < n; ++j) {
            assert_int_equal(AT(L, ldl, i, j), 0);
        }
        assert_int_equal(AT(L, ldl, i, n), 0x13579BDF); /* padding column untouched */
        for (j = 0u; j <= i; ++j) {
            i128 acc = -((i128)AT(P, ldp, i, j) * ((i128)1 << up));
            double e;
            for (k = 0u; k <= j; ++k) {
                acc += (i128)AT(L, ldl, i, k) * AT(L, ldl, j, k);
            }
            e = fabs((double)acc);
            if (i == j) {
                ASSERT_LE(e, (double)AT(L, ldl, j, j) + 0.75, "|(L L^T - P)_jj|");
                worst_diag = fmax(worst_diag, e / ((double)AT(L, ldl, j, j) + 0.75));
            } else {
                ASSERT_LE(e, 0.5 * (double)AT(L, ldl, j, j), "|(L L^T - P)_ij|");
                worst_off = fmax(worst_off, e / (0.5 * (double)AT(L, ldl, j, j)));
            }
        }
    }
    /* the double twin on the same (dequantised) matrix */
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            AT(Pf, n, i, j) = rfe_fix_to_double(AT(P, ldp, (i > j) ? i : j, (i > j) ? j : i), qp);
        }
    }
    assert_int_equal(rfe_chol_factor_f64(Pf, n, n, Lf, n), RFE_OK);
    for (j = 0u; j < n; ++j) {
        const double ljj = (double)AT(L, ldl, j, j);
        double acc = 0.0;
        for (k = 0u; k < j; ++k) {
            acc += fabs((double)AT(L, ldl, j, k)) * D[j][k];
        }
        D[j][j] = 0.5 + (acc / ljj);
        for (i = j + 1u; i < n; ++i) {
            acc = fabs((double)AT(L, ldl, i, j)) * D[j][j];
            for (k = 0u; k < j; ++k) {
                acc += (fabs((double)AT(L, ldl, i, k)) * D[j][k]) +
                       (fabs((double)AT(L, ldl, j, k)) * D[i][k]);
            }
            D[i][j] = 0.5 + (acc / ljj);
        }
    }
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j <= i; ++j) {
            const double ref = ldexp(AT(Lf, n, i, j), (int)ql);
            const double d = fabs((double)AT(L, ldl, i, j) - ref);
            const double tol = (2.0 * D[i][j]) + (1e-12 * fabs(ref));
            ASSERT_LE(d, tol, "L vs double twin (LSB)");
            worst_twin = fmax(worst_twin, d / tol);
            worst_lsb = fmax(worst_lsb, d);
        }
    }
}

/* The formats the CKF uses (P Q31 -> L Q30, Pzz Q24 -> Lz Q24) and others. */
static const unsigned formats[][2] = {{31u, 30u}, {24u, 24u}, {30u, 30u}, {30u, 15u},
                                      {16u, 16u}, {28u, 20u}, {0u, 0u},   {0u, 15u}};

/* REQ-FXP-004 REQ-CHOL-001 */
static void test_rfe_chol_factor_q31_random_spd(void **state)
{
    static int32_t P[NM * (NM + 2u)];
    size_t f;
    size_t n;
    int rep;
    (void)state;
    rng_seed(501u);
    for (f = 0u; f < (sizeof formats / sizeof formats[0]); ++f) {
        for (n = 1u; n <= NM; ++n) {
            for (rep = 0; rep < 40; ++rep) {
                const size_t ldp = n + (size_t)(rep % 3);
                make_spd(P, n, ldp, formats[f][0]);
                check_factor(P, n, ldp, formats[f][0], formats[f][1], 0u);
            }
        }
    }
    printf("  [chol] worst |E_ij| %.3g of L_jj/2, |E_jj| %.3g of L_jj + 3/4; worst |L - L_f64| "
           "%.3g of 2 D_ij (%.3g LSB)\n", worst_off, worst_diag, worst_twin, worst_lsb);
}

/* Integer matrices (Q0) with an exact factor: P = M M^T for integer M with positive
 * diagonal gives L = M exactly when every division is exact — checked on a known case. */
/* REQ-FXP-004 REQ-CHOL-001 */
static void test_rfe_chol_factor_q31_exact_integer(void **state)
{
    /* M = [2 0 0; 1 3 0; -2 1 4] -> P = [4 2 -4; 2 10 1; -4 1 21] */
    static const int32_t P[9] = {4, 2, -4, 2, 10, 1, -4, 1, 21};
    static const int32_t M[9] = {2, 0, 0, 1, 3, 0, -2, 1, 4};
    int32_t L[9];
    int32_t L8[9];
    static const int32_t M8[9] = {512, 0, 0, 256, 768, 0, -512, 256, 1024};
    uint32_t sat = 0u;
    (void)state;
    assert_int_equal(rfe_chol_factor_q31(P, 3u, 3u, L, 3u, 0u, 0u, &sat), RFE_OK);
    assert_memory_equal(L, M, sizeof M);
    /* the same in Q0 -> Q8 (up = 16) */
    assert_int_equal(rfe_chol_factor_q31(P, 3u, 3u, L8, 3u, 0u, 8u, &sat), RFE_OK);
    assert_memory_equal(L8, M8, sizeof M8);
    assert_int_equal(sat, 0u);
}

/* Pivots <= 0 fail with RFE_ERR_NOT_POSITIVE_DEFINITE and leave *sat alone, also when an
 * intermediate saturated on the way. */
/* REQ-CHOL-002 */
static void test_rfe_chol_factor_q31_not_positive_definite(void **state)
{
    static const int32_t indefinite[4] = {1 << 20, 2 << 20, 2 << 20, 1 << 20};
    static const int32_t singular[4] = {4, 4, 4, 4};        /* d_1 = 4 - 2^2 = 0 exactly */
    static const int32_t negative[9] = {1, 0, 0, 0, -1, 0, 0, 0, 1};
    static const int32_t zero[4] = {0, 0, 0, 0};
    /* L_10 = 2^30 2^31 / 2^15.5 saturates, then d_1 < 0 */
    static const int32_t huge_off[4] = {1, 0, 1 << 30, 1 << 30};
    int32_t L[9];
    uint32_t sat = 11u;
    (void)state;
    assert_int_equal(rfe_chol_factor_q31(indefinite, 2u, 2u, L, 2u, 30u, 30u, &sat),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor_q31(singular, 2u, 2u, L, 2u, 0u, 0u, &sat),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor_q31(negative, 3u, 3u, L, 3u, 31u, 30u, &sat),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor_q31(zero, 2u, 2u, L, 2u, 24u, 24u, &sat),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(rfe_chol_factor_q31(huge_off, 2u, 2u, L, 2u, 31u, 31u, &sat),
                     RFE_ERR_NOT_POSITIVE_DEFINITE);
    assert_int_equal(sat, 11u);
}

/* REQ-CHOL-003 */
static void test_rfe_chol_factor_q31_errors(void **state)
{
    static const int32_t P[4] = {1 << 20, 0, 0, 1 << 20};
    int32_t L[4] = {7, 7, 7, 7};
    static const int32_t L7[4] = {7, 7, 7, 7};
    /* q_p, q_l: out of range or 2 q_l - q_p outside [0, 31] */
    static const unsigned bad[][2] = {{32u, 30u}, {30u, 32u}, {31u, 15u}, {0u, 16u}, {20u, 9u}};
    uint32_t sat = 5u;
    size_t c;
    (void)state;
    assert_int_equal(rfe_chol_factor_q31(NULL, 2u, 2u, L, 2u, 20u, 20u, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_chol_factor_q31(P, 2u, 2u, NULL, 2u, 20u, 20u, &sat), RFE_ERR_NULL);
    assert_int_equal(rfe_chol_factor_q31(P, 2u, 2u, L, 2u, 20u, 20u, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_chol_factor_q31(P, 0u, 2u, L, 2u, 20u, 20u, &sat), RFE_ERR_SIZE);
    assert_int_equal(rfe_chol_factor_q31(P, NM + 1u, NM + 1u, L, NM + 1u, 20u, 20u, &sat),
                     RFE_ERR_SIZE);
    assert_int_equal(rfe_chol_factor_q31(P, 2u, 1u, L, 2u, 20u, 20u, &sat), RFE_ERR_SIZE);
    assert_int_equal(rfe_chol_factor_q31(P, 2u, 2u, L, 1u, 20u, 20u, &sat), RFE_ERR_SIZE);
    for (c = 0u; c < (sizeof bad / sizeof bad[0]); ++c) {
        assert_int_equal(rfe_chol_factor_q31(P, 2u, 2u, L, 2u, bad[c][0], bad[c][1], &sat),
                         RFE_ERR_RANGE);
    }
    assert_memory_equal(L, L7, sizeof L7);
    assert_int_equal(sat, 5u);
}

/* Same input, same bits (pinned hash of a seeded batch; integer-only inputs). */
#define PINNED_HASH 0x4a51a0f1fd7803a4ull

static uint64_t batch_hash(void)
{
    static int32_t P[NM * NM];
    static int32_t L[NM * NM];
    uint64_t h = 1469598103934665603ull;
    uint64_t x = 0x2545F4914F6CDD1Dull;
    uint32_t sat = 0u;
    size_t n;
    size_t i;
    size_t j;
    size_t k;
    for (n = 1u; n <= NM; ++n) {
        int32_t M[NM][NM];
        for (i = 0u; i < n; ++i) {
            for (j = 0u; j <= i; ++j) {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                M[i][j] = (j == i) ? (int32_t)(4096u + (uint32_t)(x % 4096u))
                                   : ((int32_t)(x % 2048u) - 1024);
            }
        }
        for (i = 0u; i < n; ++i) {
            for (j = 0u; j < n; ++j) {
                int64_t acc = 0;
                for (k = 0u; k <= ((i < j) ? i : j); ++k) {
                    acc += (int64_t)M[i][k] * M[j][k];
                }
                AT(P, n, i, j) = (int32_t)acc; /* < 2^31: n 8192^2 */
            }
        }
        assert_int_equal(rfe_chol_factor_q31(P, n, n, L, n, 7u, 17u, &sat), RFE_OK);
        for (i = 0u; i < (n * n); ++i) {
            uint32_t u = (uint32_t)L[i];
            int b;
            for (b = 0; b < 4; ++b) {
                h ^= (uint64_t)(u & 0xFFu);
                h *= 1099511628211ull;
                u >>= 8;
            }
        }
    }
    return h;
}

/* REQ-FXP-007 */
static void test_rfe_chol_factor_q31_deterministic(void **state)
{
    const uint64_t h1 = batch_hash();
    (void)state;
    printf("  [determinism] batch hash 0x%016llx\n", (unsigned long long)h1);
    assert_true(h1 == batch_hash());
    assert_true(h1 == PINNED_HASH);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_chol_factor_q31_random_spd),
        cmocka_unit_test(test_rfe_chol_factor_q31_exact_integer),
        cmocka_unit_test(test_rfe_chol_factor_q31_not_positive_definite),
        cmocka_unit_test(test_rfe_chol_factor_q31_errors),
        cmocka_unit_test(test_rfe_chol_factor_q31_deterministic),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
