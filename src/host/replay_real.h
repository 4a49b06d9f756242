/**
 * @file replay_real.h
 * @brief Runs the estimator over a whole sensor log, in float or double.
 *
 * replay_real.c is compiled twice (float, and -DRFE_REAL_DOUBLE); its public names carry
 * the precision suffix (the block below), so both are declared here explicitly and one
 * program can call either. Everything here is doubles in, doubles out.
 */
#ifndef RFE_HOST_REPLAY_REAL_H
#define RFE_HOST_REPLAY_REAL_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "csv_log.h"
#include "param_file.h"
#include "rfe/mass_grade.h"
#include "rfe/mass_grade_params.h"
#include "rfe/params.h"
#include "rfe/tyre_id_params.h"
#include "rfe/types.h"
#include "rfe/velocity.h"
#include "rfe/velocity_params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_replay_run             rfe_replay_run_f64
#define rfe_replay_run_observer    rfe_replay_run_observer_f64
#define rfe_replay_sample_from_row rfe_replay_sample_from_row_f64
#define rfe_replay_esc_input       rfe_replay_esc_input_f64
#define rfe_replay_esc_input_row   rfe_replay_esc_input_row_f64
#define rfe_replay_mass_grade_input_row rfe_replay_mass_grade_input_row_f64
#define rfe_replay_state           rfe_replay_state_f64
#define rfe_replay_state_size      rfe_replay_state_size_f64
#define rfe_replay_begin           rfe_replay_begin_f64
#define rfe_replay_step            rfe_replay_step_f64
#define rfe_replay_feed            rfe_replay_feed_f64
#define rfe_replay_get_stats       rfe_replay_get_stats_f64
#define rfe_param_set_preset       rfe_param_set_preset_f64
#define rfe_replay_params          rfe_replay_params_f64
#define rfe_replay_velocity_params rfe_replay_velocity_params_f64
#define rfe_replay_preset_fn       rfe_replay_preset_fn_f64
#define rfe_param_set_mass_grade   rfe_param_set_mass_grade_f64
#define rfe_replay_mass_grade_params rfe_replay_mass_grade_params_f64
#define rfe_replay_tyre_id_params  rfe_replay_tyre_id_params_f64
#define rfe_param_set_tyre_id      rfe_param_set_tyre_id_f64
#else
#define rfe_replay_run             rfe_replay_run_f32
#define rfe_replay_run_observer    rfe_replay_run_observer_f32
#define rfe_replay_sample_from_row rfe_replay_sample_from_row_f32
#define rfe_replay_esc_input       rfe_replay_esc_input_f32
#define rfe_replay_esc_input_row   rfe_replay_esc_input_row_f32
#define rfe_replay_mass_grade_input_row rfe_replay_mass_grade_input_row_f32
#define rfe_replay_state           rfe_replay_state_f32
#define rfe_replay_state_size      rfe_replay_state_size_f32
#define rfe_replay_begin           rfe_replay_begin_f32
#define rfe_replay_step            rfe_replay_step_f32
#define rfe_replay_feed            rfe_replay_feed_f32
#define rfe_replay_get_stats       rfe_replay_get_stats_f32
#define rfe_param_set_preset       rfe_param_set_preset_f32
#define rfe_replay_params          rfe_replay_params_f32
#define rfe_replay_velocity_params rfe_replay_velocity_params_f32
#define rfe_replay_preset_fn       rfe_replay_preset_fn_f32
#define rfe_param_set_mass_grade   rfe_param_set_mass_grade_f32
#define rfe_replay_mass_grade_params rfe_replay_mass_grade_params_f32
#define rfe_replay_tyre_id_params  rfe_replay_tyre_id_params_f32
#define rfe_param_set_tyre_id      rfe_param_set_tyre_id_f32
#endif

/** Status codes counted individually (0 .. RFE_REPLAY_STATUS_SLOTS-2); the last slot is
 *  "any other value". */
#define RFE_REPLAY_STATUS_SLOTS 32

/** The tyre identifier's status bits counted (RFE_TID_UPDATED 1 .. RFE_TID_LOST 16). */
#define RFE_REPLAY_TID_FLAGS 5u

/** Per-run counters. */
typedef struct {
    size_t n_steps;
    size_t status_count[RFE_REPLAY_STATUS_SLOTS];  /**< index = rfe_status_t value */
    size_t n_gaps;      /**< periods longer than 2 dt (rfe_log_missed; behind the observer:
                             the pipeline's rfe_friction_missed) */
    uint64_t n_skipped; /**< the sample periods they miss, time-updated by rfe_friction_skip
                             (behind the observer: the pipeline's out.missed) */
    size_t n_restarts;  /**< behind the observer: samples it started afresh at (a period
                             beyond obs_dt_max, the pipeline's out.restarted) */
    size_t mg_status_count[RFE_REPLAY_STATUS_SLOTS]; /**< the mass and grade estimator's
                                                          statuses (when it ran) */
    size_t n_mass_fed;     /**< samples whose mass_est the friction estimator took
                                (mg_feed_sd_rel, MASS_GRADE.md §10) */
    double mass_used_last; /**< the friction estimator's mass at the last sample [kg] (when
                                the mass and grade estimator ran) */
    double mg_excitation;  /**< the feed gate's excitation at the last sample [m/s] (its
                                sum since the estimator's last start, mg_feed_excitation) */
    size_t n_feed_slip;    /**< updates the wheel slip kept from the feed (mg_feed_slip_max) */
    size_t n_feed_band;    /**< samples due but refused: mass_est outside the band around the
                                parameter m (mg_feed_band) */
    size_t n_feed_mismatch; /**< samples due but held: the estimator's model-mismatch flag
                                 set (MASS_GRADE.md §4.8, mg_mm_e) */
    size_t tid_status_count[RFE_REPLAY_STATUS_SLOTS]; /**< the tyre identifier's statuses
                                                           (when it ran) */
    size_t tid_flag_count[RFE_REPLAY_TID_FLAGS]; /**< samples with each of its RFE_TID_* bits,
                                                      bit b at index b (updated, resampled,
                                                      held, first, lost) */
    size_t tid_restarts;   /**< samples it started afresh at: a period beyond tid_dt_max
                                since its last accepted one (the prior drawn again) */
    size_t n_tyre_fed;     /**< samples whose identified lateral curve the friction estimator
                                took (tid_feed_sd_rel, TYRE_ID.md §14) */
    size_t n_tyre_reset;   /**< implausible samples that set the friction estimator's model
                                error back to the set's (tid_feed_outlier_k, MONITOR.md §7) */
} rfe_replay_stats_t;

/** A gear cell beyond +-this is refused (status 18): the library's gear is an int32_t. */
#define RFE_REPLAY_GEAR_MAX 1e6

/** Slot of @p status in rfe_replay_stats_t.status_count (inline: this header is shared by
 *  both precisions, so no out-of-line precision-independent code lives in replay_real.c). */
static inline size_t rfe_replay_status_slot(int status)
{
    return ((status >= 0) && (status < RFE_REPLAY_STATUS_SLOTS - 1)) ? (size_t)status
                                                                    : (size_t)(RFE_REPLAY_STATUS_SLOTS - 1);
}

/**
 * The per-log state of a replay, one precision's (the struct tag is rfe_replay_state_f32 or
 * _f64; its members are private to replay_real.c): the friction estimator, or the pipeline
 * of the observer feeding it, the mass and grade estimator, the tyre identifier, which
 * columns the log has, the time of the previous row and of the last accepted one (the
 * periods), the counters. The
 * caller owns it, so runs need no heap and several may run side by side (one state each):
 * rfe_replay_begin, then rfe_replay_step per row (or rfe_replay_feed per block of rows).
 * rfe_replay_run and rfe_replay_run_observer are that over a whole log, with a state of
 * their own.
 */
struct rfe_replay_state_f32;
struct rfe_replay_state_f64;
/** The state of the including translation unit's precision. */
typedef struct rfe_replay_state rfe_replay_state_t;

/** sizeof the state, for a caller that allocates it without its definition (Python). */
size_t rfe_replay_state_size_f32(void);
/** Double-precision twin of rfe_replay_state_size_f32. */
size_t rfe_replay_state_size_f64(void);

/**
 * Starts a replay in @p st: the parameters of @p ps converted (as rfe_replay_run), the
 * friction estimator (@p observer 0: measured velocities) or the pipeline (@p observer 1),
 * when ps->mass_grade is set and @p log has drive_torque the mass and grade estimator, and
 * when ps->tyre_id is set the tyre identifier initialised (tid_feed_sd_rel > 0 behind the
 * observer: RFE_ERR_PARAM naming it); @p log gives which columns the log has (its rows are
 * not read).
 * @param bad_key as rfe_replay_run (may be NULL).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE (wheel speeds not in rad/s, or a steering-wheel
 *         angle without the observer: @p st untouched); RFE_ERR_PARAM or an init's error
 *         (then rfe_replay_step refuses with RFE_ERR_NOT_INITIALISED).
 */
RFE_NODISCARD rfe_status_t rfe_replay_begin_f32(struct rfe_replay_state_f32 *st,
                                                const rfe_param_set_t *ps,
                                                const rfe_sensor_log_t *log, int observer,
                                                size_t *bad_key);
/** Double-precision twin of rfe_replay_begin_f32. */
RFE_NODISCARD rfe_status_t rfe_replay_begin_f64(struct rfe_replay_state_f64 *st,
                                                const rfe_param_set_t *ps,
                                                const rfe_sensor_log_t *log, int observer,
                                                size_t *bad_key);

/**
 * One row of the log: its estimate row into @p out, as rfe_replay_run writes it (a row the
 * library rejects: the held estimate, valid 0, its error status in out->status).
 * @return RFE_OK (whatever the row's own status); RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED (no
 *         successful rfe_replay_begin); RFE_ERR_RANGE when row->t does not exceed the
 *         previous row's (state and @p out untouched).
 */
RFE_NODISCARD rfe_status_t rfe_replay_step_f32(struct rfe_replay_state_f32 *st,
                                               const rfe_sensor_row_t *row, rfe_est_row_t *out);
/** Double-precision twin of rfe_replay_step_f32. */
RFE_NODISCARD rfe_status_t rfe_replay_step_f64(struct rfe_replay_state_f64 *st,
                                               const rfe_sensor_row_t *row, rfe_est_row_t *out);

/**
 * rfe_replay_step on @p n rows in order (the replay's one loop: a whole log and the Python
 * package's blocks of samples both go through it).
 * @return RFE_OK, or the first step's error (the rows before it stepped).
 */
RFE_NODISCARD rfe_status_t rfe_replay_feed_f32(struct rfe_replay_state_f32 *st,
                                               const rfe_sensor_row_t *rows, size_t n,
                                               rfe_est_row_t *out);
/** Double-precision twin of rfe_replay_feed_f32. */
RFE_NODISCARD rfe_status_t rfe_replay_feed_f64(struct rfe_replay_state_f64 *st,
                                               const rfe_sensor_row_t *rows, size_t n,
                                               rfe_est_row_t *out);

/** The counters of the rows stepped so far. @return RFE_OK or RFE_ERR_NULL. */
RFE_NODISCARD rfe_status_t rfe_replay_get_stats_f32(const struct rfe_replay_state_f32 *st,
                                                    rfe_replay_stats_t *stats);
/** Double-precision twin of rfe_replay_get_stats_f32. */
RFE_NODISCARD rfe_status_t rfe_replay_get_stats_f64(const struct rfe_replay_state_f64 *st,
                                                    rfe_replay_stats_t *stats);

/**
 * Converts the parameter set, initialises the estimator and steps it on every row of
 * @p log, writing one estimate row per input row into @p out (log->n_rows entries). A row
 * the library rejects gets the unchanged previous estimate, valid = 0 and its error status,
 * and the run goes on.
 * The library parameters start from ps->preset (so a library field without a key follows
 * the preset), then every key of the set is applied.
 * @param bad_key on RFE_ERR_PARAM: RFE_PK_FILTER when the set is valid except that the CKF
 *        runs only the paper subset (filter = ckf with an addition of docs/ESTIMATOR.md on);
 *        else the first key that alone makes the library's rfe_params_validate fail
 *        (starting from the library preset), or RFE_PK_NONE when only a combination does
 *        (e.g. mu_min >= mu_max); may be NULL.
 * @return RFE_OK, or RFE_ERR_PARAM for an unknown ps->preset, or the rfe_friction_init
 *         error (nothing written then).
 */
RFE_NODISCARD rfe_status_t rfe_replay_run_f32(const rfe_param_set_t *ps,
                                              const rfe_sensor_log_t *log, rfe_est_row_t *out,
                                              rfe_replay_stats_t *stats, size_t *bad_key);
/** Double-precision twin of rfe_replay_run_f32. */
RFE_NODISCARD rfe_status_t rfe_replay_run_f64(const rfe_param_set_t *ps,
                                              const rfe_sensor_log_t *log, rfe_est_row_t *out,
                                              rfe_replay_stats_t *stats, size_t *bad_key);

/**
 * As rfe_replay_run, on the sensors of a production car: the composed pipeline
 * (rfe/pipeline.h, docs/OBSERVER.md) estimates vx, vy and the yaw acceleration from the
 * log's steer, yaw rate, ax, ay and wheel speeds (and its brake pressures, drive torques
 * and grade when the log has them), with the observer's default parameters, and feeds
 * the friction estimator; measured vx, vy, yaw_acc columns are ignored. The period of
 * each step is the time since the last accepted row (rfe/pipeline.h: a rejected sample
 * changes nothing, so its period belongs to the next). Each row gets the observer's
 * estimate too (has_velocity = 1); gaps and restarts are counted in @p stats.
 */
RFE_NODISCARD rfe_status_t rfe_replay_run_observer_f32(const rfe_param_set_t *ps,
                                                       const rfe_sensor_log_t *log,
                                                       rfe_est_row_t *out,
                                                       rfe_replay_stats_t *stats,
                                                       size_t *bad_key);
/** Double-precision twin of rfe_replay_run_observer_f32. */
RFE_NODISCARD rfe_status_t rfe_replay_run_observer_f64(const rfe_param_set_t *ps,
                                                       const rfe_sensor_log_t *log,
                                                       rfe_est_row_t *out,
                                                       rfe_replay_stats_t *stats,
                                                       size_t *bad_key);

/** The library sample of a log row (each field rounded to the build's real type), as the
 *  replay steps it; for tests and tools that step the estimator themselves. */
void rfe_replay_sample_from_row(const rfe_sensor_row_t *row, rfe_sample_t *s);

/** The ESC sample of log row @p i as rfe_replay_run_observer steps it (the period since row
 *  @p prev, the last accepted sample, from the time stamps' difference in double; 0 when
 *  @p prev >= @p i: none yet; then each field rounded to the build's real type); for tools
 *  that step the observer themselves (the PIL data generator, the soak: @p prev = i - 1). */
void rfe_replay_esc_input(const rfe_sensor_log_t *log, size_t i, size_t prev,
                          rfe_velocity_input_t *in);

/** The ESC sample of @p row of a log with the columns of @p log (its rows unused), the period
 *  since @p t_prev (the last accepted sample's time; NULL: none yet); rfe_replay_esc_input is
 *  this on log row @p i, and the fixed-point replay (a double translation unit) rounds the
 *  _f64 one's. */
void rfe_replay_esc_input_row(const rfe_sensor_log_t *log, const rfe_sensor_row_t *row,
                              const double *t_prev, rfe_velocity_input_t *in);

/**
 * The mass and grade sample of @p row of a log with the columns of @p log (its rows unused),
 * as the replay steps it (MASS_GRADE.md §10): the speed (omega_fl + omega_fr + omega_rl +
 * omega_rr) / 4 * @p R in double and in that order, the period since @p t_prev (the last
 * sample the estimator accepted; NULL: none yet), drive_torque, ax, and the optional brake
 * (pressed at >= 0.5), brake_pressure [Pa] and gear (the nearest) the log has, and the
 * log's measured vx as the ground speed of the slip pause (RFE_MG_HAS_VX; only a measured
 * one: MASS_GRADE.md §10 "The slip pause"); each value
 * rounded to the build's real type. The fixed-point replay (a double translation unit) rounds
 * the _f64 one's (rfe_replay_mass_grade_input_q31).
 * @return RFE_OK, or the status of a row whose brake or gear cell the library's integer
 *         inputs cannot hold: RFE_ERR_NONFINITE (not finite), RFE_ERR_RANGE (a gear beyond
 *         +-RFE_REPLAY_GEAR_MAX); the sample is not to be stepped then.
 */
RFE_NODISCARD rfe_status_t rfe_replay_mass_grade_input_row(const rfe_sensor_log_t *log,
                                                           const rfe_sensor_row_t *row,
                                                           const double *t_prev, double R,
                                                           rfe_mass_grade_input_t *in);

/**
 * The excitation gate of the mass feed (MASS_GRADE.md §10): the longitudinal excitation
 * since the mass and grade estimator's last start (the first accepted sample, or a period
 * beyond mg_dt_max), the sum of |ax| dt over its updates (mg_status RFE_OK) whose |ax| >=
 * mg_feed_ax_min, from the log's ax and times in double: the same in every replay (float,
 * double, q31). ax is the accelerometer's specific force, v' + g sin(theta): the inertia and
 * the grade force, which identify the mass; a steady cruise, whose mass is seen only through
 * the rolling and drag resistances the model may not match, adds nothing. With it the feed's
 * two plausibility checks: the wheel-slip hold (mg_feed_slip_max: an update whose wheels'
 * speed departs from the car's is not fed and empties the sum) and the band around the
 * parameter m (mg_feed_band).
 */
typedef struct {
    double need;       /**< key mg_feed_excitation [m/s]; 0: no gate */
    double ax_min;     /**< key mg_feed_ax_min [m/s^2] */
    double excitation; /**< the sum so far [m/s] */
    double slip_max;   /**< key mg_feed_slip_max [1]; 0: no slip hold */
    double band;       /**< key mg_feed_band [1]; 0: no band */
    double m_param;    /**< key m [kg]: the band's centre */
    double v_floor;    /**< key mg_v_min [m/s]: the slip's smallest denominator */
    double vx_ref;     /**< the car's speed the slip is taken against [m/s] (have_vx_ref):
                            the log's measured vx, else the observer's of the previous sample */
    int have_vx_ref;   /**< vx_ref is set */
    int slipping;      /**< the last step was an update whose slip exceeded slip_max */
} rfe_replay_mass_gate_t;

/** What rfe_replay_mass_feed_due says of a row. */
typedef enum {
    RFE_REPLAY_FEED_NONE = 0, /**< not due: no update, not confident or the gate closed */
    RFE_REPLAY_FEED_DUE = 1,  /**< due: feed mass_est */
    RFE_REPLAY_FEED_SLIP = 2, /**< an update held by the slip (mg_feed_slip_max) */
    RFE_REPLAY_FEED_BAND = 3, /**< due by the sd rule and the gate, refused: mass_est outside
                                   the band around m (mg_feed_band) */
    RFE_REPLAY_FEED_MISMATCH = 4 /**< due by the sd rule and the gate, held: the estimator's
                                      model-mismatch flag is set (MASS_GRADE.md §4.8) */
} rfe_replay_feed_t;

/** The gate of a run from @p ps's keys, nothing summed, no reference speed yet. */
static inline rfe_replay_mass_gate_t rfe_replay_mass_gate_of(const rfe_param_set_t *ps)
{
    rfe_replay_mass_gate_t g;
    g.need = ps->mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST];
    g.ax_min = ps->mg[RFE_PK_mg_feed_ax_min - RFE_PK_MG_FIRST];
    g.excitation = 0.0;
    g.slip_max = ps->mg[RFE_PK_mg_feed_slip_max - RFE_PK_MG_FIRST];
    g.band = ps->mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST];
    g.m_param = ps->value[RFE_PK_m];
    g.v_floor = ps->mg[RFE_PK_mg_v_min - RFE_PK_MG_FIRST];
    g.vx_ref = 0.0;
    g.have_vx_ref = 0;
    g.slipping = 0;
    return g;
}

/** The car's speed @p vx [m/s] the next rows' slip is taken against. */
static inline void rfe_replay_mass_gate_vx(rfe_replay_mass_gate_t *g, double vx)
{
    g->vx_ref = vx;
    g->have_vx_ref = 1;
}

/**
 * 1 when @p row's wheels slip beyond the gate's slip_max: |v_w - vx| > slip_max max(|vx|,
 * v_floor), v_w = (omega_fl + omega_fr + omega_rl + omega_rr) / 4 R [m/s] in double (the
 * estimator's speed, §10), vx the gate's reference; 0 without a reference, with slip_max 0
 * or a wheel speed not finite (that row the estimator refuses).
 */
static inline int rfe_replay_mass_gate_slips(const rfe_replay_mass_gate_t *g,
                                             const rfe_sensor_row_t *row, double R)
{
    const double v_w = (row->omega[0] + row->omega[1] + row->omega[2] + row->omega[3]) / 4.0 * R;
    const double den = (fabs(g->vx_ref) > g->v_floor) ? fabs(g->vx_ref) : g->v_floor;
    return ((g->have_vx_ref != 0) && (g->slip_max > 0.0) && isfinite(v_w) &&
            (fabs(v_w - g->vx_ref) > g->slip_max * den))
               ? 1
               : 0;
}

/**
 * After each mass and grade step: @p start 1 when the step started the filter afresh (the
 * library's rule: not started yet or a period beyond mg_dt_max; the caller tests it in the
 * step's own arithmetic before the step), @p status the step's, @p ax [m/s^2] the row's,
 * @p dt [s] the row's time since the estimator's last accepted one (ignored on a start),
 * @p slips rfe_replay_mass_gate_slips of the row. A start empties the sum; an update that
 * slips empties it too (the excitation must be seen again without slip) and marks the row;
 * an update with |ax| >= ax_min and dt > 0 adds |ax| dt; a pause, hold or refused row adds
 * nothing (a refused row cannot be a start: the caller passes 0).
 */
static inline void rfe_replay_mass_gate_step(rfe_replay_mass_gate_t *g, int start, int status,
                                             double ax, double dt, int slips)
{
    g->slipping = ((status == (int)RFE_OK) && (slips != 0)) ? 1 : 0;
    if ((start != 0) || (g->slipping != 0)) {
        g->excitation = 0.0;
    } else if ((status == (int)RFE_OK) && (fabs(ax) >= g->ax_min) && (dt > 0.0)) {
        g->excitation += fabs(ax) * dt;
    } else {
        /* no update, or too little |ax| to count */
    }
}

/**
 * The mass feed rule of the replay (MASS_GRADE.md §10), on a row whose mass and grade columns
 * this sample's step wrote: RFE_REPLAY_FEED_DUE when that step is an update (mg_status
 * RFE_OK: not paused, held or refused) that did not slip, with sd_mass <= @p rel * mass_est,
 * compared in double on the row's values, the gate @p g open (need 0, or its excitation,
 * this step's included, >= need) and mass_est within the band (band 0, or |mass_est -
 * m_param| <= band m_param); RFE_REPLAY_FEED_SLIP for an update that slipped,
 * RFE_REPLAY_FEED_MISMATCH for one due while the step's mismatch flag is set (§4.8: held,
 * the friction estimator keeps its last mass), RFE_REPLAY_FEED_BAND for one due but outside
 * the band, else RFE_REPLAY_FEED_NONE; never due
 * with @p rel = 0 (key mg_feed_sd_rel). The one rule of every replay (float, double, q31).
 */
static inline rfe_replay_feed_t rfe_replay_mass_feed_due(double rel,
                                                         const rfe_replay_mass_gate_t *g,
                                                         const rfe_est_row_t *out)
{
    rfe_replay_feed_t f = RFE_REPLAY_FEED_NONE;
    if ((out->mg_status != (int)RFE_OK) || !(rel > 0.0)) {
        f = RFE_REPLAY_FEED_NONE;
    } else if (g->slipping != 0) {
        f = RFE_REPLAY_FEED_SLIP;
    } else if (!(out->sd_mass <= rel * out->mass) ||
               !((g->need <= 0.0) || (g->excitation >= g->need))) {
        f = RFE_REPLAY_FEED_NONE;
    } else if (out->mg_mismatch != 0) {
        f = RFE_REPLAY_FEED_MISMATCH;
    } else if ((g->band > 0.0) && !(fabs(out->mass - g->m_param) <= g->band * g->m_param)) {
        f = RFE_REPLAY_FEED_BAND;
    } else {
        f = RFE_REPLAY_FEED_DUE;
    }
    return f;
}

/** Counts @p f in @p stats (the samples the slip held and the band refused). */
static inline void rfe_replay_mass_feed_count(rfe_replay_feed_t f, rfe_replay_stats_t *stats)
{
    stats->n_feed_slip += (f == RFE_REPLAY_FEED_SLIP) ? 1u : 0u;
    stats->n_feed_band += (f == RFE_REPLAY_FEED_BAND) ? 1u : 0u;
    stats->n_feed_mismatch += (f == RFE_REPLAY_FEED_MISMATCH) ? 1u : 0u;
}

/**
 * Fills @p ps from the library's preset @p preset (every key of the table, tyre, filter;
 * origins NULL = "the preset"; ps->preset recorded). The values are the library's, so the
 * library stays the one source of preset values:
 *  - _f64 copies rfe_params_default_f64 / rfe_params_paper_f64: exactly the library's
 *    decimal values. mu_replay always uses this one (both libraries are linked into it).
 *  - _f32 copies the float library's values widened to double (0.325f, not 0.325): exact
 *    for a float run (they convert back to the same floats), for programs that link only
 *    the float library.
 * @return 0, or -1 (ps untouched) when ps is NULL or preset is not an rfe_preset_t value.
 */
int rfe_param_set_preset_f32(rfe_param_set_t *ps, rfe_preset_t preset);
/** Double-precision twin of rfe_param_set_preset_f32 (see there). */
int rfe_param_set_preset_f64(rfe_param_set_t *ps, rfe_preset_t preset);

/**
 * The default preset, from the library of the including translation unit's precision
 * (_f64 where RFE_REAL_DOUBLE is defined, else _f32). Inline because that choice
 * is the caller's: a test linked against one library gets that library's values.
 * Precision-independent host code (mu_replay.c) calls rfe_param_set_preset_f64 instead.
 */
static inline void rfe_param_set_default(rfe_param_set_t *ps)
{
    (void)rfe_param_set_preset(ps, RFE_PRESET_DEFAULT); /* cannot fail: valid preset */
}

/**
 * The library parameters of @p ps (ps->preset, then every key, as rfe_replay_run converts
 * them), validated with rfe_params_validate. Its short name is the twin of the
 * including TU's precision (rfe_params_t is that precision's struct). The fixed-point replay
 * (replay_q31.c) starts from the _f64 one.
 * @param bad_key on RFE_ERR_PARAM: as rfe_replay_run; else RFE_PK_NONE; may be NULL.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (unknown preset or invalid set).
 */
RFE_NODISCARD rfe_status_t rfe_replay_params(const rfe_param_set_t *ps, rfe_params_t *p,
                                            size_t *bad_key);

/**
 * The observer's parameters of the set (its obs_* keys over rfe_velocity_params_default),
 * validated.
 * @param[out] bad_key  when not NULL: the obs_* key whose value alone fails validation (or
 *                      is not an integer 0..15 for obs_driven, 0..255 for obs_lat_every), else RFE_PK_NONE.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_replay_velocity_params(const rfe_param_set_t *ps,
                                                     rfe_velocity_params_t *vp,
                                                     size_t *bad_key);

/**
 * Fills the set's mass and grade keys (mg_*) from the library's preset of @p vehicle and
 * @p config (rfe_mass_grade_params_preset; origins: the preset) and records both; R and g
 * stay the vehicle keys'. rfe_param_set_preset does it with RFE_MG_CAR, RFE_MG_RECOMMENDED.
 * @return 0, or -1 (nothing changed) when ps is NULL or vehicle or config is not one of its
 *         enum's values.
 */
int rfe_param_set_mass_grade_f32(rfe_param_set_t *ps, rfe_mg_vehicle_t vehicle,
                                 rfe_mg_config_t config);
/** Double-precision twin of rfe_param_set_mass_grade_f32 (mu_replay uses this one). */
int rfe_param_set_mass_grade_f64(rfe_param_set_t *ps, rfe_mg_vehicle_t vehicle,
                                 rfe_mg_config_t config);

/**
 * The mass and grade estimator's parameters of the set: the library's preset of
 * ps->mg_vehicle and ps->mg_config, then R, g and every mg_* key, validated (rfe_mass_grade_params_validate).
 * The replays run the estimator with them when ps->mass_grade is set and the log has
 * drive_torque: the estimate rows then carry mass_est .. mg_status, and behind the observer
 * the estimated grade of each sample is the observer's grade input when the log has no
 * grade column.
 * @param[out] bad_key  when not NULL: the key (R, g or mg_*) whose value alone fails (or is
 *                      not 0 or 1 for mg_adaptive, mg_use_ax), else RFE_PK_NONE.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_replay_mass_grade_params(const rfe_param_set_t *ps,
                                                       rfe_mass_grade_params_t *mp,
                                                       size_t *bad_key);

/**
 * Fills the set's tyre identifier keys (tid_*) from rfe_tyre_id_params_default and tid_seed
 * from RFE_TID_SEED_DEFAULT (origins: the preset); rfe_param_set_preset does it. The vehicle
 * and the prior's tyre data stay the friction estimator's keys.
 * @return 0, or -1 (nothing changed) when ps is NULL.
 */
int rfe_param_set_tyre_id_f32(rfe_param_set_t *ps);
/** Double-precision twin of rfe_param_set_tyre_id_f32 (mu_replay uses this one). */
int rfe_param_set_tyre_id_f64(rfe_param_set_t *ps);

/**
 * The tyre identifier's parameters of the set (rfe_tyre_id_params_default, then every tid_*
 * key but tid_seed), validated with rfe_tyre_id_params_validate, and its seed. The replays
 * run the identifier with them and the friction estimator's vehicle and tyre data
 * (rfe_tyre_id_init) when ps->tyre_id is set: each sample after the friction step, on the
 * log's delta, yaw_rate, ay, ax and the vx of that step (the log's vx with measured
 * velocities; behind the observer its vx and the road-wheel angle it used); the estimate rows
 * then carry mu_id_f .. tid_flags.
 * @param[out] seed     the stream's seed (tid_seed).
 * @param[out] bad_key  when not NULL: the tid_* key whose value alone fails (tid_substeps not
 *                      an integer, tid_seed not an integer 0 .. 2^53, or a value
 *                      rfe_tyre_id_params_validate refuses), else RFE_PK_NONE.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_replay_tyre_id_params(const rfe_param_set_t *ps,
                                                    rfe_tyre_id_params_t *tp, uint64_t *seed,
                                                    size_t *bad_key);

/** A library preset function of the including TU's precision (rfe_params_default_fXX, ...). */
typedef rfe_status_t (*rfe_replay_preset_fn_t)(rfe_params_t *p);

/**
 * The library function behind @p preset (the one mapping from rfe_preset_t to the library,
 * used by rfe_param_set_preset and by the replay's conversion), or NULL for a value that is
 * not an rfe_preset_t. Its short name is the twin of the including TU's precision.
 */
rfe_replay_preset_fn_t rfe_replay_preset_fn(rfe_preset_t preset);

#endif /* RFE_HOST_REPLAY_REAL_H */
