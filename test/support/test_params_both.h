/**
 * @file test_params_both.h
 * @brief The double and the fixed-point parameters of one run, derived as mu_replay derives
 *        them (`--real double` and `--real q31`): the preset, a log's metadata, then the
 *        conversions rfe_params_to_q31_f64 / rfe_velocity_params_to_q31_f64. For the
 *        back-to-back tests of the fixed-point observer and pipeline (built as double).
 *        Include after test_common.h (cmocka).
 */
#ifndef RFE_TEST_PARAMS_BOTH_H
#define RFE_TEST_PARAMS_BOTH_H

#include <string.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/component/params_conv.h"
#include "rfe/params_q31.h"
#include "rfe/velocity_params_q31.h"

typedef struct {
    rfe_params_t pd;
    rfe_velocity_params_t vd;
    rfe_params_q31_t pq;
    rfe_velocity_params_q31_t vq;
} both_t;

/* The defaults, or those of @p log's metadata when it is not NULL. */
static inline void params_of(const rfe_sensor_log_t *log, both_t *b)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(b, 0, sizeof(*b)); /* the estimators copy them, padding included */
    rfe_param_set_default(&ps);
    if (log != NULL) {
        assert_int_equal(rfe_param_set_apply_meta(&ps, log, "log", &err), 0);
    }
    assert_int_equal(rfe_replay_params(&ps, &b->pd, NULL), RFE_OK);
    assert_int_equal(rfe_replay_velocity_params(&ps, &b->vd, NULL), RFE_OK);
    assert_int_equal(rfe_params_to_q31_f64(&b->pd, &b->pq), RFE_OK);
    assert_int_equal(rfe_velocity_params_to_q31_f64(&b->vd, &b->vq), RFE_OK);
}

#endif /* RFE_TEST_PARAMS_BOTH_H */
