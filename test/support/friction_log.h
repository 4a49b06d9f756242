/**
 * @file friction_log.h
 * @brief The friction estimator's set-up on a bundled log, as mu_replay makes it: the log read,
 *        the default preset, the log's metadata, then rfe_replay_params. Shared by the tests
 *        that run the estimator on logs in the real type of their build (test_holds_flt.c,
 *        test_trust_rules_flt.c; float32 and double). Include after test_common.h (cmocka).
 */
#ifndef RFE_TEST_FRICTION_LOG_H
#define RFE_TEST_FRICTION_LOG_H

#include <string.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/params.h"

/* Reads @p path into @p log (free it with rfe_sensor_log_free) and fills @p p for it; any
 * error fails the test. @p p is zeroed first: the double build's rfe_params_t has padding
 * (4 bytes after tyre.mode), which the estimator's init copies into its state, and a
 * whole-state comparison must read defined bytes only (valgrind). */
static inline void friction_log_load(const char *path, rfe_sensor_log_t *log, rfe_params_t *p)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(log, 0, sizeof *log);
    memset(p, 0, sizeof *p);
    if (rfe_sensor_log_read(path, log, &err) != 0) {
        fail_msg("%s:%zu:%zu: %s", err.file, err.line, err.col, err.msg);
    }
    assert_int_equal(rfe_param_set_preset(&ps, RFE_PRESET_DEFAULT), 0);
    if (rfe_param_set_apply_meta(&ps, log, path, &err) != 0) {
        fail_msg("%s: %s", path, err.msg);
    }
    assert_int_equal(rfe_replay_params(&ps, p, NULL), RFE_OK);
}

#endif /* RFE_TEST_FRICTION_LOG_H */
