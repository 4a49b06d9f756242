/**
 * @file chol_flt.c
 * @brief Cholesky factorisation for the CKF baseline.
 */
#include "rfe/component/chol.h"

#include "numerics/internal.h"

#define AT(M, ld, i, j) ((M)[((i) * (ld)) + (j)])

rfe_status_t rfe_chol_factor(const rfe_real_t *P, size_t n, size_t ldp, rfe_real_t *L,
                             size_t ldl)
{
    size_t i;
    size_t j;
    size_t k;

    if ((P == NULL) || (L == NULL)) {
        return RFE_ERR_NULL;
    }
    if ((n == 0u) || (n > (size_t)RFE_N_MAX) || (ldp < n) || (ldl < n)) {
        return RFE_ERR_SIZE;
    }
    for (i = 0u; i < n; ++i) {
        if (!rfe_all_finite(&AT(P, ldp, i, 0u), i + 1u)) {
            return RFE_ERR_NONFINITE;
        }
    }
    /* L_jj = sqrt(P_jj - sum_k L_jk^2),  L_ij = (P_ij - sum_k L_ik L_jk) / L_jj. */
    for (j = 0u; j < n; ++j) {
        rfe_real_t d = AT(P, ldp, j, j);
        for (k = 0u; k < j; ++k) {
            d -= AT(L, ldl, j, k) * AT(L, ldl, j, k);
        }
        if (!(d > RFE_R(0.0))) {
            return RFE_ERR_NOT_POSITIVE_DEFINITE;
        }
        AT(L, ldl, j, j) = RFE_SQRT(d);
        for (i = j + 1u; i < n; ++i) {
            rfe_real_t s = AT(P, ldp, i, j);
            for (k = 0u; k < j; ++k) {
                s -= AT(L, ldl, i, k) * AT(L, ldl, j, k);
            }
            AT(L, ldl, i, j) = s / AT(L, ldl, j, j);
        }
        for (k = j + 1u; k < n; ++k) {
            AT(L, ldl, j, k) = RFE_R(0.0);
        }
    }
    return RFE_OK;
}
