/**
 * @file q31_rows.h
 * @brief A sensor-log row as a fixed-point sample, each value rounded to its format (the
 *        module tests' conversion; the replay's own is rfe_replay_run_q31's). Test support.
 */
#ifndef RFE_TEST_Q31_ROWS_H
#define RFE_TEST_Q31_ROWS_H

#include <stdint.h>
#include <string.h>

#include "csv_log.h"
#include "host/fixed_conv.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre_q31.h"

/** @p x rounded to Q @p q (a value beyond the format saturates; the count is not kept). */
static inline int32_t q31_rows_toq(double x, unsigned int q)
{
    uint32_t s = 0u;
    return rfe_fix_from_double(x, q, &s);
}

/** Every input field of @p row in the formats of rfe_sample_q31_t. */
static inline void q31_sample_from_row(const rfe_sensor_row_t *row, rfe_sample_q31_t *u)
{
    size_t i;
    memset(u, 0, sizeof(*u));
    u->delta = q31_rows_toq(row->delta, RFE_FIX_Q_ANGLE);
    u->vx = q31_rows_toq(row->vx, RFE_FIX_Q_SPEED);
    u->vy = q31_rows_toq(row->vy, RFE_FIX_Q_SPEED);
    u->yaw_rate = q31_rows_toq(row->yaw_rate, RFE_FIX_Q_YAWRATE);
    u->yaw_acc = q31_rows_toq(row->yaw_acc, RFE_FIX_Q_ACC);
    u->ax = q31_rows_toq(row->ax, RFE_FIX_Q_ACC);
    u->ay = q31_rows_toq(row->ay, RFE_FIX_Q_ACC);
    for (i = 0; i < 4u; ++i) {
        u->omega[i] = q31_rows_toq(row->omega[i], RFE_FIX_Q_OMEGA);
    }
}

#endif /* RFE_TEST_Q31_ROWS_H */
