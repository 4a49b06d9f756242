/**
 * @file pil_gen_q31.h
 * @brief Fixed-point half of the PIL data generator (host only, see pil_gen_q31.c).
 */
#ifndef PIL_GEN_Q31_H
#define PIL_GEN_Q31_H

#include <stdint.h>

#include "host/csv_log.h"
#include "host/param_file.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre_q31.h"

/** The parameters of `mu_replay --real q31` for @p ps (RFE_OK or the conversion's error). */
rfe_status_t pil_gen_params_q31(const rfe_param_set_t *ps, rfe_params_q31_t *q);

/** One sensor row in the Q formats of rfe_sample_q31_t; returns the saturation count. */
uint32_t pil_gen_sample_q31(const rfe_sensor_row_t *row, rfe_sample_q31_t *s);

#endif /* PIL_GEN_Q31_H */
