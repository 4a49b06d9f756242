/**
 * @file pil_data.h
 * @brief The generated data of a processor-in-the-loop image (pil_gen.c writes it): the
 *        estimator parameters and the sensor samples, fixed point with PIL_Q31, else float.
 *        With PIL_PIPELINE: the composed pipeline's parameters, the observer's and the ESC
 *        samples (fixed point with PIL_Q31, else float). With PIL_MASS_GRADE (fixed point with
 *        PIL_Q31, else float) or PIL_TYRE_ID (float only): that estimator's parameters and
 *        samples.
 */
#ifndef PIL_DATA_H
#define PIL_DATA_H

#include <stdint.h>

#if defined(PIL_MASS_GRADE) && defined(PIL_Q31)
#include "rfe/mass_grade_q31.h"
extern const rfe_mass_grade_params_q31_t pil_mg_params;
extern const rfe_mass_grade_input_q31_t pil_mg_inputs[];
#elif defined(PIL_MASS_GRADE)
#include "rfe/mass_grade.h"
extern const rfe_mass_grade_params_t pil_mg_params;
extern const rfe_mass_grade_input_t pil_mg_inputs[];
#elif defined(PIL_TYRE_ID)
#include "rfe/tyre_id.h"
extern const rfe_params_t pil_params;
extern const rfe_tyre_id_sample_t pil_tid_samples[];
#elif defined(PIL_PIPELINE) && defined(PIL_Q31)
#include "rfe/pipeline_q31.h"
extern const rfe_params_q31_t pil_params;
extern const rfe_velocity_params_q31_t pil_velocity_params;
extern const rfe_velocity_input_q31_t pil_inputs[];
#elif defined(PIL_PIPELINE)
#include "rfe/pipeline.h"
extern const rfe_params_t pil_params;
extern const rfe_velocity_params_t pil_velocity_params;
extern const rfe_velocity_input_t pil_inputs[];
#elif defined(PIL_Q31)
#include "rfe/friction_q31.h"
extern const rfe_params_q31_t pil_params;
extern const rfe_sample_q31_t pil_samples[];
#else
#include "rfe/friction.h"
extern const rfe_params_t pil_params;
extern const rfe_sample_t pil_samples[];
#endif

/** Number of entries of pil_samples (pil_inputs). */
extern const uint32_t pil_n_samples;

#endif /* PIL_DATA_H */
