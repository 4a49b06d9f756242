/**
 * @file kalman_ref.c
 * @brief Test support: textbook Kalman filter in double (see kalman_ref.h).
 */
#include "kalman_ref.h"

#include <string.h>

#include "test_linalg.h"

#define NM ((size_t)RFE_N_MAX)
#define MM ((size_t)RFE_M_MAX)

/* R, Sz and K are stored in RFE_N_MAX-sized arrays. */
typedef char kf_ref_m_fits_in_n[(RFE_M_MAX <= RFE_N_MAX) ? 1 : -1];

void kf_ref_predict(kf_ref_t *r, const double F_in[][RFE_N_MAX])
{
    const size_t n = r->n;
    double F[NM][NM];
    double FP[NM][NM];
    double xn[NM];
    size_t i;
    size_t j;
    size_t k;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            F[i][j] = (F_in != NULL) ? F_in[i][j] : ((i == j) ? 1.0 : 0.0);
        }
    }
    for (i = 0u; i < n; ++i) {
        xn[i] = 0.0;
        for (k = 0u; k < n; ++k) {
            xn[i] += F[i][k] * r->x[k];
        }
        for (j = 0u; j < n; ++j) {
            FP[i][j] = 0.0;
            for (k = 0u; k < n; ++k) {
                FP[i][j] += F[i][k] * r->P[k][j];
            }
        }
    }
    for (i = 0u; i < n; ++i) {
        r->x[i] = xn[i];
        for (j = 0u; j < n; ++j) {
            double acc = r->Q[i][j];
            for (k = 0u; k < n; ++k) {
                acc += FP[i][k] * F[j][k];
            }
            r->P[i][j] = acc;
        }
    }
}

void kf_ref_update(kf_ref_t *r, const double H[][RFE_N_MAX], const rfe_real_t *y)
{
    const size_t n = r->n;
    const size_t m = r->m;
    double PHt[NM][NM];
    double Sz[NM][NM];
    double K[NM][NM];
    double A[NM][NM];
    double AP[NM][NM];
    double Pn[NM][NM];
    double innov[MM];
    size_t i;
    size_t j;
    size_t k;
    size_t s;
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < m; ++j) {
            PHt[i][j] = 0.0;
            for (k = 0u; k < n; ++k) {
                PHt[i][j] += r->P[i][k] * H[j][k];
            }
        }
    }
    for (i = 0u; i < m; ++i) {
        double hx = 0.0;
        for (k = 0u; k < n; ++k) {
            hx += H[i][k] * r->x[k];
        }
        innov[i] = (double)y[i] - hx;
        for (j = 0u; j < m; ++j) {
            Sz[i][j] = r->R[i][j];
            for (k = 0u; k < n; ++k) {
                Sz[i][j] += H[i][k] * PHt[k][j];
            }
        }
    }
    right_solve_spd(Sz, m, PHt, n, K);
    for (i = 0u; i < n; ++i) {
        for (k = 0u; k < m; ++k) {
            r->x[i] += K[i][k] * innov[k];
        }
        for (j = 0u; j < n; ++j) {
            A[i][j] = (i == j) ? 1.0 : 0.0;
            for (k = 0u; k < m; ++k) {
                A[i][j] -= K[i][k] * H[k][j];
            }
        }
    }
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            AP[i][j] = 0.0;
            for (k = 0u; k < n; ++k) {
                AP[i][j] += A[i][k] * r->P[k][j];
            }
        }
    }
    for (i = 0u; i < n; ++i) {
        for (j = 0u; j < n; ++j) {
            double acc = 0.0;
            for (k = 0u; k < n; ++k) {
                acc += AP[i][k] * A[j][k];
            }
            for (k = 0u; k < m; ++k) {
                for (s = 0u; s < m; ++s) {
                    acc += K[i][k] * r->R[k][s] * K[j][s];
                }
            }
            Pn[i][j] = acc;
        }
    }
    memcpy(r->P, Pn, sizeof Pn);
}
