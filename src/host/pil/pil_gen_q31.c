/**
 * @file pil_gen_q31.c
 * @brief Host part of the PIL data generator (firmware/pil/pil_gen.c) that needs the double
 *        library: the fixed-point parameters exactly as `mu_replay --real q31` derives them
 *        (src/host/replay_q31.c: rfe_replay_params_f64, then rfe_params_to_q31_f64) and the
 *        samples rounded to the Q formats with rfe_fix_from_double (the same conversions).
 *
 * Compiled as a double translation unit (-DRFE_REAL_DOUBLE), so its rfe_params_t is the
 * double struct; pil_gen.c (float) calls it through pil_gen_q31.h.
 */
#if !defined(RFE_REAL_DOUBLE)
#define RFE_REAL_DOUBLE 1
#endif

#include "pil_gen_q31.h"

#include "host/replay_real.h"
#include "host/fixed_conv.h"
#include "rfe/component/params_conv.h"

rfe_status_t pil_gen_params_q31(const rfe_param_set_t *ps, rfe_params_q31_t *q)
{
    rfe_params_t p;
    rfe_status_t st = rfe_replay_params_f64(ps, &p, NULL);
    if (st == RFE_OK) {
        st = rfe_params_to_q31_f64(&p, q);
    }
    return st;
}

uint32_t pil_gen_sample_q31(const rfe_sensor_row_t *row, rfe_sample_q31_t *s)
{
    uint32_t sat = 0u;
    size_t w;
    s->delta = rfe_fix_from_double(row->delta, RFE_FIX_Q_ANGLE, &sat);
    s->vx = rfe_fix_from_double(row->vx, RFE_FIX_Q_SPEED, &sat);
    s->vy = rfe_fix_from_double(row->vy, RFE_FIX_Q_SPEED, &sat);
    s->yaw_rate = rfe_fix_from_double(row->yaw_rate, RFE_FIX_Q_YAWRATE, &sat);
    s->yaw_acc = rfe_fix_from_double(row->yaw_acc, RFE_FIX_Q_ACC, &sat);
    s->ax = rfe_fix_from_double(row->ax, RFE_FIX_Q_ACC, &sat);
    s->ay = rfe_fix_from_double(row->ay, RFE_FIX_Q_ACC, &sat);
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        s->omega[w] = rfe_fix_from_double(row->omega[w], RFE_FIX_Q_OMEGA, &sat);
    }
    return sat;
}
