/**
 * @file chol_q31.c
 * @brief Cholesky factorisation on int32 Q values for the CKF baseline (the twin of
 *        chol_flt.c).
 */
#include "rfe/component/chol_q31.h"

#include "numerics/internal_q31.h"

#define AT(M, ld, i, j) ((M)[((i) * (ld)) + (j)])

/* Argument checks (nothing is written before they pass). */
static rfe_status_t check_args(const rfe_fix_t *P, size_t n, size_t ldp, const rfe_fix_t *L,
                               size_t ldl, unsigned int q_p, unsigned int q_l,
                               const uint32_t *sat)
{
    if ((P == NULL) || (L == NULL) || (sat == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((n == 0u) || (n > (size_t)RFE_N_MAX) || (ldp < n) || (ldl < n)) {
        return RFE_ERR_SIZE;
    }
    if ((q_p > 31u) || (q_l > 31u) || ((2u * q_l) < q_p) || (((2u * q_l) - q_p) > 31u)) {
        return RFE_ERR_RANGE;
    }
    return RFE_OK;
}

/* start - sum_{k<j} L_ik L_jk, exact in int64 (each product <= 2^62; saturating, counted,
 * should the sum ever leave the int64 range). */
static int64_t reduce(int64_t start, const rfe_fix_t *L, size_t ldl, size_t i, size_t j,
                      uint32_t *count)
{
    int64_t acc = start;
    size_t k;
    for (k = 0u; k < j; ++k) {
        acc = rfe_fix_add64(acc, -((int64_t)AT(L, ldl, i, k) * (int64_t)AT(L, ldl, j, k)), count);
    }
    return acc;
}

rfe_status_t rfe_chol_factor_q31(const rfe_fix_t *P, size_t n, size_t ldp, rfe_fix_t *L,
                                 size_t ldl, unsigned int q_p, unsigned int q_l, uint32_t *sat)
{
    uint32_t count = 0u;
    int64_t up;
    size_t i;
    size_t j;
    size_t k;
    const rfe_status_t st = check_args(P, n, ldp, L, ldl, q_p, q_l, sat);

    if (st != RFE_OK) {
        return st;
    }
    /* P in Q(q_p) -> Q(2 q_l): times 2^up, |P| 2^up <= 2^62, exact. */
    up = rfe_q31_pow2((2u * q_l) - q_p);
    /* L_jj = sqrt(P_jj - sum_k L_jk^2),  L_ij = (P_ij - sum_k L_ik L_jk) / L_jj. */
    for (j = 0u; j < n; ++j) {
        const int64_t d = reduce((int64_t)AT(P, ldp, j, j) * up, L, ldl, j, j, &count);
        if (d <= 0) {
            return RFE_ERR_NOT_POSITIVE_DEFINITE;
        }
        /* d < 2^63: the root is at most 2^31.5 */
        AT(L, ldl, j, j) = rfe_fix_sat32((int64_t)rfe_q31_sqrt_round((uint64_t)d), &count);
        for (i = j + 1u; i < n; ++i) {
            const int64_t s = reduce((int64_t)AT(P, ldp, i, j) * up, L, ldl, i, j, &count);
            AT(L, ldl, i, j) = rfe_q31_div_round(s, AT(L, ldl, j, j), &count);
        }
        for (k = j + 1u; k < n; ++k) {
            AT(L, ldl, j, k) = 0;
        }
    }
    rfe_q31_sat_add(sat, count);
    return RFE_OK;
}
