/**
 * @file aux_input.h
 * @brief The samples of the mass and grade estimator and of the tyre identifier taken from
 *        a sensor log row, in the including unit's rfe_real_t: shared by the PIL data
 *        generator (pil_gen --estimator mass_grade|tyre_id, float) and the host benchmark of
 *        the two (bench/bench_aux.c, float and double), so the target, the host program and
 *        the benchmark step on the same inputs.
 *
 * Mass and grade: the speed (omega_fl + omega_fr + omega_rl + omega_rr) / 4 * R in double
 * and in that order, the period from the time stamps in double, torque, ax and the optional
 * brake, pressure and gear the log has: what replay_real.c's mass_grade_input gives
 * mu_replay (MASS_GRADE.md §1; the replay's checks of non-finite or huge gear cells are
 * not repeated: the bundled logs have none); in fixed point the replay's own conversion
 * (rfe_replay_mass_grade_input_q31, linked from replay_q31.o). Tyre identifier: dt, delta, vx, yaw rate, ay,
 * ax of the row, as bench/tyre_id_cost.c and the soak feed it (TYRE_ID.md §1).
 */
#ifndef RFE_HOST_PIL_AUX_INPUT_H
#define RFE_HOST_PIL_AUX_INPUT_H

#include <math.h>
#include <string.h>

#include "host/csv_log.h"
#include "host/fixed_conv.h"
#include "host/replay_q31.h"
#include "rfe/mass_grade.h"
#include "rfe/mass_grade_q31.h"
#include "rfe/tyre_id.h"

static inline void rfe_aux_mg_input(const rfe_sensor_log_t *log, size_t i, double R,
                                    rfe_mass_grade_input_t *in)
{
    const rfe_sensor_row_t *row = &log->rows[i];
    const double v = ((((row->omega[RFE_FL] + row->omega[RFE_FR]) + row->omega[RFE_RL]) +
                       row->omega[RFE_RR]) /
                      4.0) *
                     R;
    memset(in, 0, sizeof *in);
    in->dt = (i > 0u) ? (rfe_real_t)(row->t - log->rows[i - 1u].t) : (rfe_real_t)0.0;
    in->v = (rfe_real_t)v;
    in->torque = (rfe_real_t)row->drive_torque;
    in->ax = (rfe_real_t)row->ax;
    in->p_brake = log->has_brake_pressure ? (rfe_real_t)row->brake_pressure : (rfe_real_t)0.0;
    in->gear = log->has_gear ? (int32_t)floor(row->gear + 0.5) : 0; /* the nearest gear */
    in->brake = (log->has_brake && (row->brake >= 0.5)) ? 1u : 0u;
    in->ay = (rfe_real_t)row->ay; /* the curve pause's input, as the replay hands it over */
    in->has = RFE_MG_HAS_AX | RFE_MG_HAS_AY | (log->has_brake_pressure ? RFE_MG_HAS_PRESSURE : 0u) |
              (log->has_brake ? RFE_MG_HAS_BRAKE : 0u) | (log->has_gear ? RFE_MG_HAS_GEAR : 0u);
}

/* The same sample in the fixed-point twin's formats (rfe/mass_grade_q31.h): the fixed-point
 * replay's conversion (rfe_replay_mass_grade_input_q31: each value of the double computation
 * above rounded by rfe_fix_from_double, the pressure in MPa), the period since the previous
 * row; the saturations counted in *sat. Its status is not returned: the replay's checks of
 * bad cells never fire on the bundled logs (an input it refuses would be all zero). */
static inline void rfe_aux_mg_input_q31(const rfe_sensor_log_t *log, size_t i, double R,
                                        rfe_mass_grade_input_q31_t *in, uint32_t *sat)
{
    const rfe_status_t st = rfe_replay_mass_grade_input_q31(
        log, &log->rows[i], (i > 0u) ? &log->rows[i - 1u].t : NULL, R, in, sat);
    (void)st; /* RFE_OK on every bundled log */
}

static inline void rfe_aux_tid_sample(const rfe_sensor_log_t *log, size_t i,
                                      rfe_tyre_id_sample_t *s)
{
    const rfe_sensor_row_t *row = &log->rows[i];
    s->dt = (i > 0u) ? (rfe_real_t)(row->t - log->rows[i - 1u].t) : (rfe_real_t)0.0;
    s->delta = (rfe_real_t)row->delta;
    s->vx = (rfe_real_t)row->vx;
    s->yaw_rate = (rfe_real_t)row->yaw_rate;
    s->ay = (rfe_real_t)row->ay;
    s->ax = (rfe_real_t)row->ax;
}

#endif /* RFE_HOST_PIL_AUX_INPUT_H */
