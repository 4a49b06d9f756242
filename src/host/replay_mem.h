/**
 * @file replay_mem.h
 * @brief A replay over columns in memory, the Python package's Estimator.run and .step: set
 *        up as mu_replay sets up a run (its options, the log's metadata, the parameter
 *        precedence, the checks: rfe_mu_replay_open, in mu_replay.c), then the replay core
 *        (rfe_replay_feed_*) on blocks of rows, the estimates into the caller's array.
 *
 * Nothing is printed and nothing is global: the caller owns the rfe_replay_mem_t and the
 * precision's replay state, so runs go side by side in threads. Errors come back as a code:
 * a library status (rfe_status_t, > 0), RFE_MEM_INPUT (malformed input, mu_replay's exit 1
 * without a library status) or RFE_MEM_USAGE (an option mu_replay refuses, its exit 2), with
 * the message in an rfe_io_error_t.
 */
#ifndef RFE_HOST_REPLAY_MEM_H
#define RFE_HOST_REPLAY_MEM_H

#include <stddef.h>

#include "csv_log.h"
#include "param_file.h"
#include "replay_q31.h"

/** Malformed input: mu_replay would exit 1, and no library status says why. */
#define RFE_MEM_INPUT (-1)
/** An option mu_replay refuses (its exit status 2). */
#define RFE_MEM_USAGE (-2)
/** Values per estimate row in rfe_replay_mem_feed's output (rfe_replay_mem_col names them). */
#define RFE_MEM_COLS 47u

/** The number type of a run (mu_replay --real). */
typedef enum { RFE_MEM_FLOAT = 0, RFE_MEM_DOUBLE = 1, RFE_MEM_Q31 = 2 } rfe_mem_real_t;

/** A run set up by rfe_mu_replay_open. Zero it, open, then feed blocks of rows. */
typedef struct {
    rfe_param_set_t ps;     /**< the run's parameters, resolved as mu_replay resolves them */
    rfe_read_opts_t ro;     /**< how a block's columns are read (--strict, --velocity, ...) */
    rfe_sensor_log_t shape; /**< the first block's columns (has_*; no rows, no metadata) */
    char name[64];          /**< the --in name, for messages (a copy) */
    int real;               /**< rfe_mem_real_t */
    int observer;           /**< the velocity observer runs */
    int mass_grade;         /**< the mass and grade estimator runs */
    int tyre_id;            /**< the tyre identifier runs (--tyre-id apf|sir) */
    int tyre_feed;          /**< its curve is fed to the friction estimator (tid_feed_sd_rel) */
    int dt_given;           /**< dt came from the metadata or the parameters, not the stamps */
    int preset_vehicle;     /**< a vehicle key came from no file: the preset's value stands */
    struct rfe_replay_state_f32 *f32; /**< the state of the run's precision (the caller's) */
    struct rfe_replay_state_f64 *f64;
    rfe_replay_q31_state_t *q31;
    double t_last;          /**< the last row fed's time (have_last): a block starts after it */
    int have_last;
    int ready;              /**< open succeeded */
} rfe_replay_mem_t;

/** Bytes of the replay state of @p real (rfe_mem_real_t; 0 for another value). */
size_t rfe_replay_mem_state_size(int real);

/**
 * Sets up @p m as `mu_replay ARGV` sets up its run on the first block of columns (the options
 * --in NAME --out ANY [--preset ...] as the CLI takes them; --in names the columns in
 * messages), @p params_text (NULL, or `key = value` lines) applied where a --params file
 * is; dt from the block's time stamps when no file gives it; then starts the replay state in
 * @p state (rfe_replay_mem_state_size bytes, aligned as a double; the caller's) for the
 * run's precision. Steps nothing: feed the block (rfe_replay_mem_feed) next.
 * @return 0; RFE_MEM_USAGE; RFE_MEM_INPUT; a library status (a bad cell with --strict:
 *         RFE_ERR_NONFINITE; the start's RFE_ERR_PARAM, RFE_ERR_RANGE, ...); RFE_ERR_NULL
 *         (@p err untouched). @p err holds the message of every error but RFE_ERR_NULL.
 */
int rfe_mu_replay_open(rfe_replay_mem_t *m, int argc, char **argv, const char *params_text,
                       const rfe_kv_t *meta, size_t n_meta, const rfe_column_t *cols,
                       size_t n_cols, size_t n_rows, void *state, rfe_io_error_t *err);

/**
 * Steps the run on a block of @p n_rows rows (the columns and metadata read as at the open,
 * the wheel speeds and steering-wheel angle converted as mu_replay converts them; the same
 * columns as the first block), writing RFE_MEM_COLS values per row into @p out (row-major;
 * valid_*, status, mg_status, tid_status, tid_flags as exact small integers).
 * @return 0; RFE_MEM_INPUT (a malformed block, other columns than the first block's, time
 *         not after the last row's: nothing stepped); RFE_ERR_NONFINITE (a bad cell with
 *         --strict); RFE_ERR_NOT_INITIALISED (not opened); RFE_ERR_NULL.
 */
int rfe_replay_mem_feed(rfe_replay_mem_t *m, const rfe_kv_t *meta, size_t n_meta,
                        const rfe_column_t *cols, size_t n_cols, size_t n_rows, double *out,
                        rfe_io_error_t *err);

/** The counters of the rows fed so far (the base counters of a float or double run; the
 *  saturation counters too for q31). @return 0, RFE_ERR_NULL or RFE_ERR_NOT_INITIALISED. */
int rfe_replay_mem_stats(const rfe_replay_mem_t *m, rfe_replay_q31_stats_t *stats);

/** The estimate-log name of output value @p i (< RFE_MEM_COLS), or NULL. */
const char *rfe_replay_mem_col(size_t i);

#endif /* RFE_HOST_REPLAY_MEM_H */
