/**
 * @file replay_q31.h
 * @brief Runs the fixed-point estimator (rfe_friction_*_q31), or the fixed-point pipeline
 *        (rfe_pipeline_*_q31: the velocity observer feeding it), over a whole sensor log: the
 *        `--real q31` of mu_replay. Doubles in, doubles out, like replay_real.h.
 *
 * The parameters take the double path of rfe_replay_run_f64 (the preset's exact decimals,
 * then every key; rfe_params_validate_f64) and are then converted with rfe_params_to_q31_f64
 * (rounded to nearest). Each sample is converted with rfe_fix_from_double (rounded to
 * nearest, ties up) into the formats of rfe_sample_q31_t; a value beyond its format
 * saturates and is counted (the estimator then rejects the sample: every format holds its
 * config.h limit). The estimate is converted back exactly (rfe_fix_to_double: mu Q29,
 * sd Q30), so an estimate log written with the shortest round-trip format holds the Q values
 * bit for bit.
 *
 * The observer run takes the observer's parameters the same way (rfe_replay_velocity_params_f64,
 * then rfe_velocity_params_to_q31_f64), builds each ESC sample as rfe_replay_run_observer_f64
 * does (the period from the time stamps' difference in double), rounds every value as above
 * into the formats of rfe_velocity_input_q31_t, and converts the observer's estimate back
 * exactly too (vx, vy, sd Q23; beta, sd_beta Q29; yaw acceleration Q24).
 *
 * The mass and grade estimator (MASS_GRADE.md §10) runs as in the float and double replay:
 * when the set says so (ps->mass_grade) and the log has drive_torque, each sample steps the
 * fixed-point twin (rfe_mass_grade_*_q31) first, on its parameters by the double path
 * (rfe_replay_mass_grade_params_f64, then rfe_mass_grade_params_to_q31_f64) and the sample of
 * rfe_replay_mass_grade_input_q31; its estimate goes back exactly (mass, sd_mass Q14; grade,
 * sd_grade Q29); then the feed rule (rfe_replay_mass_feed_due) gives the friction estimator
 * that mass (rfe_friction_set_mass_q31, behind the observer rfe_pipeline_set_mass_q31; Q14 to
 * Q16, exact), and behind the observer without a grade column the observer takes that
 * sample's estimated grade. Its saturations count with the estimator's and the input's.
 */
#ifndef RFE_HOST_REPLAY_Q31_H
#define RFE_HOST_REPLAY_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/component/tyre_q31.h"
#include "rfe/mass_grade_q31.h"
#include "rfe/params_q31.h"
#include "rfe/velocity_q31.h"
#include "rfe/types.h"

/** Per-run counters of a fixed-point run. */
typedef struct {
    rfe_replay_stats_t base;  /**< steps and status counts, as the float/double runs */
    uint64_t input_sat;       /**< values saturated converting the samples to Q formats */
    size_t input_sat_rows;    /**< rows with at least one such value */
    uint64_t est_sat;         /**< sum of the estimator's per-step saturation counts */
    uint32_t est_sat_max;     /**< the largest per-step count */
    size_t est_sat_rows;      /**< steps with a nonzero count */
} rfe_replay_q31_stats_t;

/**
 * The fixed-point twin of rfe_replay_run_f64: parameters as described above, one estimate row
 * per input row (a rejected row: the unchanged previous estimate, valid = 0, its error
 * status), and the saturation counters.
 * @param row_sat per-row saturation count of the estimator (log->n_rows entries; the mass
 *        and grade estimator's included when it runs), or NULL
 * @param bad_key on RFE_ERR_PARAM as rfe_replay_run_f64; on RFE_ERR_RANGE the key that alone
 *        (starting from the preset) does not fit its Q format (an mg_* key: from the set's
 *        mass and grade preset), or RFE_PK_NONE when none does alone or the estimator's prior
 *        does not fit (rfe_friction_init_q31); may be NULL.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (also a mass and grade set outside the
 *         fixed-point domain: rfe_mass_grade_init_q31); RFE_ERR_RANGE (rfe_params_to_q31_f64,
 *         rfe_mass_grade_params_to_q31_f64 or rfe_friction_init_q31); the init's other errors
 *         (nothing written then).
 */
RFE_NODISCARD rfe_status_t rfe_replay_run_q31(const rfe_param_set_t *ps,
                                              const rfe_sensor_log_t *log, rfe_est_row_t *out,
                                              rfe_replay_q31_stats_t *stats, uint32_t *row_sat,
                                              size_t *bad_key);

/**
 * The fixed-point parameters of @p ps as rfe_replay_run_q31 derives them (the one place
 * they are derived: mu_replay --real q31, the PIL data generator and the soak runner):
 * rfe_replay_params_f64, then rfe_params_to_q31_f64.
 * @param bad_key on RFE_ERR_PARAM as rfe_replay_params_f64; may be NULL.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; RFE_ERR_RANGE (a value outside its Q format).
 */
RFE_NODISCARD rfe_status_t rfe_replay_params_q31(const rfe_param_set_t *ps, rfe_params_q31_t *q,
                                                 size_t *bad_key);

/**
 * The fixed-point parameters of an observer run as rfe_replay_run_observer_q31 derives them
 * (the one place: mu_replay --real q31 --velocity observer and the PIL data generator): the
 * friction estimator's as rfe_replay_params_q31, then the observer's (its obs_* keys over
 * rfe_velocity_params_default_f64: rfe_replay_velocity_params_f64, then
 * rfe_velocity_params_to_q31_f64).
 * @param bad_key on RFE_ERR_PARAM the key rejected (as rfe_replay_run_observer_f64); may be
 *        NULL.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; RFE_ERR_RANGE (a value outside its Q format).
 */
RFE_NODISCARD rfe_status_t rfe_replay_observer_params_q31(const rfe_param_set_t *ps,
                                                          rfe_params_q31_t *q,
                                                          rfe_velocity_params_q31_t *vq,
                                                          size_t *bad_key);

/**
 * One sensor row in the Q formats of rfe_sample_q31_t, as rfe_replay_run_q31 steps it
 * (rfe_fix_from_double: rounded to nearest, saturated).
 * @return the number of values that saturated.
 */
uint32_t rfe_replay_sample_q31(const rfe_sensor_row_t *row, rfe_sample_q31_t *s);

/**
 * The ESC sample of log row @p i in the Q formats of rfe_velocity_input_q31_t, as
 * rfe_replay_run_observer_q31 steps it: rfe_replay_esc_input_f64's sample (the period since
 * row @p prev, the last accepted one, in double; the optional columns when the log has them, else 0)
 * with each value rounded by rfe_fix_from_double, its RFE_VEL_HAS_* bits as they are; for
 * tools that step the fixed-point observer themselves.
 * @return the number of values that saturated.
 */
uint32_t rfe_replay_esc_input_q31(const rfe_sensor_log_t *log, size_t i, size_t prev,
                                  rfe_velocity_input_q31_t *in);

/**
 * The mass and grade sample of @p row in the Q formats of rfe_mass_grade_input_q31_t, as the
 * fixed-point replay steps it: rfe_replay_mass_grade_input_row_f64's sample (the wheels'
 * speed times @p R and the period since @p t_prev, the last sample the estimator accepted,
 * in double; its checks of the brake and gear cells) with each value rounded by
 * rfe_fix_from_double (the brake pressure from Pa to MPa); the gear, brake and RFE_MG_HAS_*
 * bits as they are. The one conversion of the replay and the PIL data generator
 * (host/pil/aux_input.h).
 * @param sat  the saturations of the rounding are added to it.
 * @return RFE_OK; the double sample's status; RFE_ERR_NONFINITE for a value the float library
 *         checks (dt, v, torque, ax, the pressure with RFE_MG_HAS_PRESSURE and vx with
 *         RFE_MG_HAS_VX) that is not finite (it has no Q value: refused as the float library refuses it). @p in is all
 *         zero unless RFE_OK.
 */
RFE_NODISCARD rfe_status_t rfe_replay_mass_grade_input_q31(const rfe_sensor_log_t *log,
                                                           const rfe_sensor_row_t *row,
                                                           const double *t_prev, double R,
                                                           rfe_mass_grade_input_q31_t *in,
                                                           uint32_t *sat);

/**
 * The fixed-point twin of rfe_replay_run_observer_f64 (the parameters, samples and estimates
 * as described above): one row per input row with the observer's estimate (has_velocity = 1);
 * a rejected row gets the unchanged previous estimates, valid = 0, its error status.
 * The estimator's saturation count of a step is the observer's plus the friction
 * estimator's (rfe_velocity_estimate_q31_t.sat + rfe_estimate_q31_t.sat).
 * @param row_sat as rfe_replay_run_q31
 * @param bad_key on RFE_ERR_PARAM as rfe_replay_run_observer_f64; on RFE_ERR_RANGE the key
 *        (an obs_* key included) that alone does not fit its Q format, or RFE_PK_NONE; may be
 *        NULL.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM; RFE_ERR_RANGE (wheel speeds not in rad/s, a
 *         conversion, or rfe_pipeline_init_q31); the init's other errors (nothing written
 *         then).
 */
RFE_NODISCARD rfe_status_t rfe_replay_run_observer_q31(const rfe_param_set_t *ps,
                                                       const rfe_sensor_log_t *log,
                                                       rfe_est_row_t *out,
                                                       rfe_replay_q31_stats_t *stats,
                                                       uint32_t *row_sat, size_t *bad_key);

/**
 * The per-log state of a fixed-point replay (members private to replay_q31.c), as
 * rfe_replay_state_t of replay_real.h: the caller owns it; rfe_replay_begin_q31, then
 * rfe_replay_step_q31 per row; rfe_replay_run_q31 and rfe_replay_run_observer_q31 are that
 * over a whole log.
 */
typedef struct rfe_replay_q31_state rfe_replay_q31_state_t;

/** sizeof the state, for a caller that allocates it without its definition (Python). */
size_t rfe_replay_state_size_q31(void);

/**
 * Starts a fixed-point replay in @p st: the parameters as rfe_replay_run_q31 (@p observer 0)
 * or rfe_replay_run_observer_q31 (1) derives them, the estimator or pipeline initialised;
 * @p log gives which columns the log has (its rows are not read).
 * @return as those runs (RFE_ERR_NULL, RFE_ERR_RANGE with @p st untouched for the units;
 *         else the parameters' or init's error, after which steps are refused).
 */
RFE_NODISCARD rfe_status_t rfe_replay_begin_q31(rfe_replay_q31_state_t *st,
                                                const rfe_param_set_t *ps,
                                                const rfe_sensor_log_t *log, int observer,
                                                size_t *bad_key);

/**
 * One row: its estimate row into @p out as rfe_replay_run_q31 writes it; @p sat (may be
 * NULL) the step's saturation count.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_RANGE when row->t does not
 *         exceed the previous row's (state untouched).
 */
RFE_NODISCARD rfe_status_t rfe_replay_step_q31(rfe_replay_q31_state_t *st,
                                               const rfe_sensor_row_t *row, rfe_est_row_t *out,
                                               uint32_t *sat);

/** rfe_replay_step_q31 on @p n rows in order (the replay's one loop); @p row_sat per row or
 *  NULL. @return RFE_OK, or the first step's error. */
RFE_NODISCARD rfe_status_t rfe_replay_feed_q31(rfe_replay_q31_state_t *st,
                                               const rfe_sensor_row_t *rows, size_t n,
                                               rfe_est_row_t *out, uint32_t *row_sat);

/** The counters of the rows stepped so far. @return RFE_OK or RFE_ERR_NULL. */
RFE_NODISCARD rfe_status_t rfe_replay_get_stats_q31(const rfe_replay_q31_state_t *st,
                                                    rfe_replay_q31_stats_t *stats);

#endif /* RFE_HOST_REPLAY_Q31_H */
