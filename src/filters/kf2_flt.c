/**
 * @file kf2_flt.c
 * @brief The two-state Kalman filter (rfe/component/kf2.h).
 */
/* This file defines the init: its header's wrapper macro stays out (MISRA-DEV-08). */
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: read by the header's #if */
#define RFE_KF2_IMPL
#include "rfe/component/kf2.h"

#include "numerics/internal.h"

rfe_status_t rfe_kf2_init(rfe_kf2_t *f, rfe_real_t x0, rfe_real_t x1, rfe_real_t sd0,
                          rfe_real_t sd1, size_t size, uint32_t config)
/* cppcheck-suppress misra-c2012-5.5 ; MISRA-DEV-08: the function its wrapper macro calls */
{
    const rfe_real_t v[4] = {x0, x1, sd0, sd1};
    /* A caller built with other maxima or another number type lays the state out
     * differently: nothing may be written (RFE_ERR_ABI, rfe/common.h). */
    if ((size != sizeof(*f)) || (config != RFE_CONFIG_REAL)) {
        return RFE_ERR_ABI;
    }
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (!rfe_all_finite(v, 4u)) {
        return RFE_ERR_NONFINITE;
    }
    if ((sd0 < RFE_R(0.0)) || (sd1 < RFE_R(0.0))) {
        return RFE_ERR_RANGE;
    }
    f->x[0] = x0;
    f->x[1] = x1;
    f->p00 = sd0 * sd0;
    f->p01 = RFE_R(0.0);
    f->p11 = sd1 * sd1;
    return RFE_OK;
}

rfe_status_t rfe_kf2_predict(rfe_kf2_t *f, rfe_real_t f01, rfe_real_t u, rfe_real_t q00,
                             rfe_real_t q11, rfe_real_t q01)
{
    rfe_real_t n[5];
    const rfe_real_t a[5] = {f01, u, q00, q11, q01};
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (!rfe_all_finite(a, 5u)) {
        return RFE_ERR_NONFINITE;
    }
    n[0] = f->x[0] + (f01 * f->x[1]) + u;
    n[1] = f->x[1];
    n[2] = f->p00 + (RFE_R(2.0) * f01 * f->p01) + (f01 * f01 * f->p11) + q00;
    n[3] = f->p01 + (f01 * f->p11) + q01;
    n[4] = f->p11 + q11;
    if (!rfe_all_finite(n, 5u)) {
        return RFE_ERR_NONFINITE;
    }
    f->x[0] = n[0];
    f->x[1] = n[1];
    f->p00 = n[2];
    f->p01 = n[3];
    f->p11 = n[4];
    return RFE_OK;
}

rfe_status_t rfe_kf2_update(rfe_kf2_t *f, rfe_real_t h0, rfe_real_t h1, rfe_real_t nu,
                            rfe_real_t r)
{
    rfe_real_t n[5];
    rfe_real_t ph0;
    rfe_real_t ph1;
    rfe_real_t s;
    rfe_real_t k0;
    rfe_real_t k1;
    const rfe_real_t a[4] = {h0, h1, nu, r};
    if (f == NULL) {
        return RFE_ERR_NULL;
    }
    if (!rfe_all_finite(a, 4u)) {
        return RFE_ERR_NONFINITE;
    }
    if (r < RFE_R(0.0)) {
        return RFE_ERR_RANGE;
    }
    ph0 = (f->p00 * h0) + (f->p01 * h1);
    ph1 = (f->p01 * h0) + (f->p11 * h1);
    s = (h0 * ph0) + (h1 * ph1) + r;
    if (!rfe_is_finite(s)) {
        return RFE_ERR_NONFINITE;
    }
    if (!(s > RFE_R(0.0))) {
        return RFE_ERR_NOT_POSITIVE_DEFINITE;
    }
    k0 = ph0 / s;
    k1 = ph1 / s;
    n[0] = f->x[0] + (k0 * nu);
    n[1] = f->x[1] + (k1 * nu);
    n[2] = f->p00 - (k0 * k0 * s);
    n[3] = f->p01 - (k0 * k1 * s);
    n[4] = f->p11 - (k1 * k1 * s);
    if (!rfe_all_finite(n, 5u)) {
        return RFE_ERR_NONFINITE;
    }
    f->x[0] = n[0];
    f->x[1] = n[1];
    f->p00 = n[2];
    f->p01 = n[3];
    f->p11 = n[4];
    return RFE_OK;
}
