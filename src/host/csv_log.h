/**
 * @file csv_log.h
 * @brief Sensor-log reader and estimate-log writer (docs DATA.md), host only.
 *
 * Format: `# key = value` metadata lines, then one header row of column names, then one row
 * per sample. Columns are looked up by name (any order; extra columns are ignored and not
 * parsed). Fields may be padded with blanks. Every needed field must be a finite decimal
 * number; anything else is an error that names file, line and column (field index and name),
 * unless the caller keeps the bad cells of the estimator's inputs (rfe_sensor_log_read_cells).
 *
 * A recorded car's log declares its own units, scales and column names in the metadata
 * (DATA.md "Units, scales and names of a recorded log"): `unit_<column>` (deg, km/h, rpm,
 * g, bar, ms, ...), `scale_<column>`, `offset_<column>` and `column_<column> = <its header
 * name>`. The reader converts every value to SI as it reads: SI = factor(unit) * (scale *
 * value + offset).
 */
#ifndef RFE_HOST_CSV_LOG_H
#define RFE_HOST_CSV_LOG_H

#include <stddef.h>
#include <stdio.h>

#include "rfe/types.h"
#include "text_io.h"

/** One `# key = value` metadata line of a sensor log (strings owned by the log). */
typedef struct {
    char *key;
    char *value;
    size_t line;  /**< 1-based line in the file, for messages */
} rfe_meta_entry_t;

/** One sensor sample as read (DATA.md sensor log), doubles whatever the build precision. */
typedef struct {
    double t, delta, vx, vy, yaw_rate, yaw_acc, ax, ay; /**< vx, vy, yaw_acc: 0 unless has_velocity;
                                                             delta 0 when has_swa */
    double swa;                  /**< steering-wheel angle [rad]; only when has_swa */
    double omega[RFE_WHEELS];    /**< omega_fl .. omega_rr */
    double p_brake[RFE_WHEELS];  /**< p_fl .. p_rr [MPa]; only when has_pressure */
    double torque[RFE_WHEELS];   /**< torque_fl .. torque_rr [N m]; only when has_torque */
    double grade;                /**< known road grade [rad]; only when has_grade (else 0) */
    double mu_true[RFE_WHEELS];  /**< mu_fl .. mu_rr; only meaningful when has_truth */
    double util_true[RFE_WHEELS]; /**< util_fl .. util_rr (true friction utilisation
                                       sqrt(Fx^2 + Fy^2) / (mu Fz)); only when has_util */
    double drive_torque;         /**< total drive torque at the wheels [N m]; only when
                                      has_drive_torque (the mass and grade estimator's input) */
    double brake;                /**< brake pedal, 0 released / 1 pressed; only when has_brake */
    double brake_pressure;       /**< driver's brake pressure [Pa]; only when has_brake_pressure */
    double gear;                 /**< engaged gear; only when has_gear */
    double mass_true;            /**< vehicle mass [kg] (truth); only when has_mass_true */
    double grade_true;           /**< road grade [rad], uphill positive (truth); only when
                                      has_grade_true */
    unsigned bad;                /**< bit (1 << rfe_cell_cause_t) per kind of bad cell this row
                                      holds (RFE_CELLS_KEEP; 0 = every value finite) */
} rfe_sensor_row_t;

/** Why a cell of an estimator input holds no finite number. With RFE_CELLS_KEEP such a cell
 *  is read as NaN or +-Inf, so the row goes to the library as it is and is rejected there
 *  (RFE_ERR_NONFINITE) with the estimate held. */
typedef enum {
    RFE_CELL_EMPTY = 0,     /**< nothing but blanks: read as NaN */
    RFE_CELL_NONFINITE = 1, /**< nan / inf text: read as NaN or +-Inf */
    RFE_CELL_RANGE = 2,     /**< beyond a double, as written or once in SI units: +-Inf */
    RFE_CELL_CAUSES = 3
} rfe_cell_cause_t;

/** What the reader does with a bad cell (rfe_cell_cause_t) of an estimator input. */
typedef enum {
    RFE_CELLS_STRICT = 0, /**< an error naming file, line and column (mu_replay --strict) */
    RFE_CELLS_KEEP = 1    /**< kept as NaN / +-Inf and counted (mu_replay's default) */
} rfe_cells_t;

/** Which input columns the run uses (rfe_read_opts_t.inputs), as mu_replay's --velocity:
 *  a bad cell of a column the run does not use is not counted with the others (it cannot
 *  reject a row) but apart, as ignored (bad_ignored). */
typedef enum {
    RFE_INPUTS_ALL = 0,      /**< every estimator input (the plain readers) */
    RFE_INPUTS_MEASURED = 1, /**< measured velocities: vx, vy, yaw_acc needed (named among the
                                  missing columns when others are missing too; alone, the read
                                  succeeds with has_velocity 0 for the caller to say why);
                                  p_*, torque_*, grade unused */
    RFE_INPUTS_OBSERVER = 2, /**< the velocity observer: vx, vy, yaw_acc unused */
    RFE_INPUTS_AUTO = 3      /**< MEASURED when the log has vx, vy, yaw_acc, else OBSERVER */
} rfe_inputs_t;

/** Options of rfe_sensor_log_read_opts (zero-initialised: strict, every input used). */
typedef struct {
    rfe_cells_t cells;   /**< what a bad cell of an estimator input is */
    rfe_inputs_t inputs; /**< which input columns the run uses */
    int mass_grade_off;  /**< nonzero: the mass and grade columns (drive_torque, brake,
                              brake_pressure, gear, mass_true, grade_true) are read as extra
                              columns (not parsed), as they always are in a log without
                              drive_torque */
} rfe_read_opts_t;

/** A whole sensor log in memory. Zero-initialise, read, then rfe_sensor_log_free. */
typedef struct {
    rfe_meta_entry_t *meta;
    size_t n_meta;
    rfe_sensor_row_t *rows;
    size_t n_rows;
    int has_truth;  /**< 1 when all four mu_* truth columns are present */
    int has_util;   /**< 1 when all four util_* truth columns are present */
    int has_velocity; /**< 1 when vx, vy, yaw_acc are present (a test car's sensors) */
    int has_pressure; /**< 1 when the four p_* brake pressures are present */
    int has_torque;   /**< 1 when the four torque_* drive torques are present */
    int has_grade;    /**< 1 when the grade column is present */
    int has_drive_torque;   /**< 1 when drive_torque is present (and not mass_grade_off): the
                                 mass and grade columns below are read */
    int has_brake;          /**< 1 when brake is present (with drive_torque) */
    int has_brake_pressure; /**< 1 when brake_pressure is present (with drive_torque) */
    int has_gear;           /**< 1 when gear is present (with drive_torque) */
    int has_mass_true;      /**< 1 when mass_true is present (with drive_torque) */
    int has_grade_true;     /**< 1 when grade_true is present (with drive_torque) */
    int drive_torque_ignored; /**< 1 when drive_torque is present but mass_grade_off left the
                                   mass and grade columns out */
    int has_swa;      /**< 1 while the steering angle is the steering wheel's (swa) and delta is
                           not filled (rfe_sensor_log_steer_ratio fills it) */
    int omega_linear; /**< 1 while omega_* hold circumferential speeds [m/s] (a unit_omega_* of
                           km/h, m/s, mph): rfe_sensor_log_wheel_radius makes them rad/s */
    size_t bad_cells[RFE_CELL_CAUSES]; /**< kept bad cells per cause (RFE_CELLS_KEEP) */
    size_t bad_rows;       /**< rows holding at least one of them */
    size_t bad_first_line; /**< line and column (1-based) of the first one; 0 when none */
    size_t bad_first_col;
    size_t bad_ignored;    /**< kept bad cells of columns the run does not use (rfe_inputs_t):
                                read as NaN / +-Inf too, in no count above, no row's bad bits */
    size_t bad_ignored_first_line; /**< line and column of the first of those; 0 when none */
    size_t bad_ignored_first_col;
    const char *unused_cols; /**< the log's input columns the run does not use ("vx, vy,
                                  yaw_acc"), static text; NULL when it uses all it has */
} rfe_sensor_log_t;

/**
 * Reads @p path into @p log, every value in SI. Rejected: no header, missing required
 * columns (every missing column of every rule in one message, in the order of DATA.md's
 * table), neither or both of delta and swa, a unit_/scale_/offset_/column_ key naming no
 * column, a unit that is not one of its column's quantity, a scale of 0, only some of
 * the columns of an optional group (each all or none: vx, vy, yaw_acc; p_fl..p_rr;
 * torque_fl..torque_rr; the truth groups mu_fl..mu_rr, util_fl..util_rr),
 * duplicate column names, a wrong field count, a field that is not
 * a finite decimal number, time not strictly increasing, no data rows.
 * @return 0, or -1 with @p err filled (log then empty; err->file points to @p path).
 */
RFE_NODISCARD int rfe_sensor_log_read(const char *path, rfe_sensor_log_t *log,
                                      rfe_io_error_t *err);

/** As rfe_sensor_log_read, from an open stream; @p name is used in messages. */
RFE_NODISCARD int rfe_sensor_log_read_stream(FILE *f, const char *name, rfe_sensor_log_t *log,
                                             rfe_io_error_t *err);

/**
 * As rfe_sensor_log_read, with the bad cells of the estimator's inputs (every column but t
 * and the truth columns mu_*, util_*) handled as @p cells says: RFE_CELLS_STRICT is
 * rfe_sensor_log_read; RFE_CELLS_KEEP reads an empty, nan/inf or out-of-range cell as NaN or
 * +-Inf and counts it (bad_cells, bad_rows, bad_first_line/col; the row's bad bits). Text
 * that is not a number ('0.1x') stays an error: it is a broken file, not a sample.
 */
RFE_NODISCARD int rfe_sensor_log_read_cells(const char *path, rfe_cells_t cells,
                                            rfe_sensor_log_t *log, rfe_io_error_t *err);

/** As rfe_sensor_log_read_cells, from an open stream; @p name is used in messages. */
RFE_NODISCARD int rfe_sensor_log_read_stream_cells(FILE *f, const char *name, rfe_cells_t cells,
                                                   rfe_sensor_log_t *log, rfe_io_error_t *err);

/**
 * As rfe_sensor_log_read_cells, with @p opts: the bad cells as opts->cells says, and the
 * columns of opts->inputs needed (the missing ones named with all others in one message)
 * and the bad cells of the unused ones counted apart (bad_ignored).
 */
RFE_NODISCARD int rfe_sensor_log_read_opts(const char *path, const rfe_read_opts_t *opts,
                                           rfe_sensor_log_t *log, rfe_io_error_t *err);

/** As rfe_sensor_log_read_opts, from an open stream; @p name is used in messages. */
RFE_NODISCARD int rfe_sensor_log_read_stream_opts(FILE *f, const char *name,
                                                  const rfe_read_opts_t *opts,
                                                  rfe_sensor_log_t *log, rfe_io_error_t *err);

/** A metadata pair (strings not owned): written to an estimate log, or a log in memory's. */
typedef struct {
    const char *key;
    const char *value;
} rfe_kv_t;

/** One column of a log in memory: its header name and its n_rows values (NULL: a column
 *  whose cells are no numbers, an error when it names an input). */
typedef struct {
    const char *name;
    const double *values;
} rfe_column_t;

/**
 * As rfe_sensor_log_read_opts, from columns in memory instead of a file: the metadata pairs
 * (each trimmed, as a `# key = value` line), the column names (the header) and their values
 * go through the reader's own rules (column names and groups, unit_, scale_, offset_,
 * column_ metadata, bad cells as opts->cells says, time increasing), so the log equals the
 * one read from these columns written as a CSV with every double in its shortest round-trip
 * text. A NaN or +-Inf value is such a CSV's nan/inf cell. Messages name @p name, and as the
 * "line" a pair's index (metadata) or a row's (data), 1-based.
 * @return 0; RFE_ERR_NONFINITE with @p err filled for a bad cell refused (an empty, nan/inf
 *         or out-of-range cell with RFE_CELLS_STRICT, or of t or a truth column: what the
 *         estimator would reject with that status); else -1 with @p err filled (log then
 *         empty; nothing filled when an argument is NULL).
 */
RFE_NODISCARD int rfe_sensor_log_from_columns(const char *name, const rfe_kv_t *meta,
                                              size_t n_meta, const rfe_column_t *cols,
                                              size_t n_cols, size_t n_rows,
                                              const rfe_read_opts_t *opts, rfe_sensor_log_t *log,
                                              rfe_io_error_t *err);

/** Name of a cell cause ("empty", "nan/inf", "out of range"). */
const char *rfe_cell_cause_str(rfe_cell_cause_t c);

/** Frees everything the log owns and zeroes it (safe on a zeroed or freed log). */
void rfe_sensor_log_free(rfe_sensor_log_t *log);

/** The columns a log has without its rows and its metadata (pointers NULL, counts 0): the
 *  shape a replay keeps to read later blocks of the same log. Owns nothing. */
rfe_sensor_log_t rfe_sensor_log_shape(const rfe_sensor_log_t *log);

/**
 * Turns circumferential wheel speeds [m/s] into spin speeds [rad/s] with the effective
 * rolling radius @p R [m] (the vehicle parameter R), once; a log in rad/s is untouched.
 * @return 0, or -1 when @p R is not a positive finite number (log then untouched).
 */
RFE_NODISCARD int rfe_sensor_log_wheel_radius(rfe_sensor_log_t *log, double R);

/**
 * Fills delta = swa / @p ratio in every row of a log that gives the steering-wheel angle
 * and clears has_swa, for the runs that take the road-wheel angle; a log with delta is
 * untouched.
 * @return 0, or -1 when @p ratio is not a positive finite number (log then untouched).
 */
RFE_NODISCARD int rfe_sensor_log_steer_ratio(rfe_sensor_log_t *log, double ratio);

/** Value of metadata @p key, or NULL (the last one when repeated). */
const char *rfe_sensor_log_meta(const rfe_sensor_log_t *log, const char *key);

/** One row of the DATA.md estimate log, as doubles. */
typedef struct {
    double t;
    double mu[RFE_WHEELS];
    double sd[RFE_WHEELS];
    unsigned char valid[RFE_WHEELS];
    int status;  /**< rfe_status_t of that step */
    int has_velocity; /**< 1 when the velocity observer ran: the fields below are written */
    double vx, vy, beta, yaw_acc, sd_vx, sd_vy, sd_beta; /**< the observer's estimate */
    int has_mass_grade; /**< 1 when the mass and grade estimator ran: the fields below are
                             written (mass_est, sd_mass, grade_est, sd_grade, mg_status) */
    double mass, sd_mass, grade, sd_grade; /**< its estimate [kg], [rad] */
    int mg_status;      /**< rfe_status_t of its step */
    double mass_used;   /**< the friction estimator's mass at this sample [kg] (mg_feed_sd_rel:
                             the last mass_est fed, else the parameter m) */
    int grade_walk;     /**< the grade walk's level after this step (MASS_GRADE.md §4.7): 1 loose
                             (mg_q_theta_hi), 0 tight (mg_q_theta; always with the walk off) */
    int mg_mismatch;    /**< the model-mismatch flag after this step (MASS_GRADE.md §4.8): 1 the
                             ax row's EMA beyond mg_mm_e (the feed holds), else 0 */
    int has_tyre_id;    /**< 1 when the tyre identifier ran: the fields below are written
                             (mu_id_f .. E_r, tid_status, tid_flags; DATA.md "Estimate log") */
    double mu_id[2];    /**< mu = D / Fz of the front [0] and rear [1] axle [1] */
    double sd_mu_id[2]; /**< their sd [1] */
    double mf_B[2], mf_C[2], mf_D[2], mf_E[2]; /**< the Magic Formula per axle: B [1/rad], C,
                                                    D [N], E (weighted means) */
    int tid_status;     /**< rfe_status_t of its step */
    unsigned tid_flags; /**< its RFE_TID_* bits (rfe/tyre_id.h) */
    int has_tyre_feed;  /**< 1 when the identified curve is fed (tid_feed_sd_rel > 0): the
                             friction estimator's curve of this sample's step is written */
    double cy_used, shape_Cy_used, shape_Ey_used, r_model_rel_used; /**< [1/rad], 1, 1, 1 */
} rfe_est_row_t;

/** Number format of estimate-log values. */
typedef enum {
    RFE_NUMFMT_DOUBLE = 0,  /**< shortest text that reads back as the same double */
    RFE_NUMFMT_FLOAT = 1    /**< %.9g: reads back as the same float (float32 runs) */
} rfe_numfmt_t;

/**
 * Writes the estimate log: `# key = value` lines (control characters in values become
 * '?', so each stays one line), the header, one row per estimate.
 * @return 0, or -1 with @p err filled (open, write or close failed).
 */
RFE_NODISCARD int rfe_estimate_log_write(const char *path, const rfe_kv_t *meta, size_t n_meta,
                                         const rfe_est_row_t *rows, size_t n_rows,
                                         rfe_numfmt_t fmt, rfe_io_error_t *err);

/** As rfe_estimate_log_write, to an open stream (not closed); returns -1 on a write error. */
RFE_NODISCARD int rfe_estimate_log_write_stream(FILE *f, const rfe_kv_t *meta, size_t n_meta,
                                                const rfe_est_row_t *rows, size_t n_rows,
                                                rfe_numfmt_t fmt);

#endif /* RFE_HOST_CSV_LOG_H */
