/**
 * @file replay_mem.c
 * @brief The in-memory replay's blocks of rows (replay_mem.h): columns to rows by the
 *        reader's rules, the replay core of the run's precision, rows to the caller's array.
 *        The set-up is mu_replay's own (rfe_mu_replay_open, mu_replay.c).
 */
#include "replay_mem.h"

#include <stdlib.h>
#include <string.h>

/* The estimate log's columns (DATA.md "Estimate log"), in est_values' order. */
static const char *const k_mem_cols[RFE_MEM_COLS] = {
    "t",         "mu_fl",     "mu_fr",     "mu_rl",    "mu_rr",     "sd_fl",       "sd_fr",
    "sd_rl",     "sd_rr",     "valid_fl",  "valid_fr", "valid_rl",  "valid_rr",    "status",
    "vx_est",    "vy_est",    "beta_est",  "yaw_acc_est", "sd_vx",  "sd_vy",       "sd_beta",
    "mass_est",  "sd_mass",   "grade_est", "sd_grade", "mg_status", "mass_used", "grade_walk",
    "mu_id_f",   "mu_id_r",   "sd_mu_id_f", "sd_mu_id_r", "B_f",    "C_f",         "D_f",
    "E_f",       "B_r",       "C_r",       "D_r",      "E_r",       "tid_status",  "tid_flags",
    "cy_used",   "shape_Cy_used", "shape_Ey_used", "r_model_rel_used", "mg_mismatch"};

const char *rfe_replay_mem_col(size_t i)
{
    return (i < RFE_MEM_COLS) ? k_mem_cols[i] : NULL;
}

size_t rfe_replay_mem_state_size(int real)
{
    return (real == (int)RFE_MEM_FLOAT)    ? rfe_replay_state_size_f32()
           : (real == (int)RFE_MEM_DOUBLE) ? rfe_replay_state_size_f64()
           : (real == (int)RFE_MEM_Q31)    ? rfe_replay_state_size_q31()
                                           : 0u;
}

/* One estimate row as RFE_MEM_COLS values (k_mem_cols' order; the observer's, the mass and
 * grade estimator's and the tyre identifier's as the row holds them, 0 when they did not
 * run). */
static void est_values(const rfe_est_row_t *e, double *v)
{
    size_t w;
    v[0] = e->t;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        v[1u + w] = e->mu[w];
        v[5u + w] = e->sd[w];
        v[9u + w] = (double)e->valid[w];
    }
    v[13] = (double)e->status;
    v[14] = e->vx;
    v[15] = e->vy;
    v[16] = e->beta;
    v[17] = e->yaw_acc;
    v[18] = e->sd_vx;
    v[19] = e->sd_vy;
    v[20] = e->sd_beta;
    v[21] = e->mass;
    v[22] = e->sd_mass;
    v[23] = e->grade;
    v[24] = e->sd_grade;
    v[25] = (double)e->mg_status;
    v[26] = e->mass_used;
    v[27] = (double)e->grade_walk;
    v[28] = e->mu_id[0];
    v[29] = e->mu_id[1];
    v[30] = e->sd_mu_id[0];
    v[31] = e->sd_mu_id[1];
    for (w = 0u; w < 2u; ++w) {
        v[32u + 4u * w] = e->mf_B[w];
        v[33u + 4u * w] = e->mf_C[w];
        v[34u + 4u * w] = e->mf_D[w];
        v[35u + 4u * w] = e->mf_E[w];
    }
    v[40] = (double)e->tid_status;
    v[41] = (double)e->tid_flags;
    v[42] = e->cy_used;
    v[43] = e->shape_Cy_used;
    v[44] = e->shape_Ey_used;
    v[45] = e->r_model_rel_used;
    v[46] = (double)e->mg_mismatch;
}

/* Whether @p log has the columns of the first block (the replay state knows only those). */
static int same_columns(const rfe_sensor_log_t *a, const rfe_sensor_log_t *b)
{
    return (a->has_velocity == b->has_velocity) && (a->has_pressure == b->has_pressure) &&
           (a->has_torque == b->has_torque) && (a->has_grade == b->has_grade) &&
           (a->has_drive_torque == b->has_drive_torque) && (a->has_brake == b->has_brake) &&
           (a->has_brake_pressure == b->has_brake_pressure) && (a->has_gear == b->has_gear) &&
           (a->has_swa == b->has_swa) && (a->omega_linear == b->omega_linear);
}

/* The block's rows in the library's terms, as mu_replay's prepare_log makes them (R and
 * obs_steer_ratio were checked at the open: 0 then, -1 only for a set changed since). */
static int convert_block(const rfe_replay_mem_t *m, rfe_sensor_log_t *log)
{
    int rc = 0;
    if (log->omega_linear != 0) {
        rc = rfe_sensor_log_wheel_radius(log, m->ps.value[RFE_PK_R]);
    }
    if ((rc == 0) && (log->has_swa != 0) && (m->observer == 0)) {
        rc = rfe_sensor_log_steer_ratio(log, m->ps.obs[RFE_PK_obs_steer_ratio - RFE_PK_OBS_FIRST]);
    }
    return rc;
}

/* The replay core of the run's precision on the block's rows. */
static rfe_status_t feed_rows(rfe_replay_mem_t *m, const rfe_sensor_log_t *log,
                              rfe_est_row_t *rows)
{
    if (m->real == (int)RFE_MEM_Q31) {
        return rfe_replay_feed_q31(m->q31, log->rows, log->n_rows, rows, NULL);
    }
    return (m->real == (int)RFE_MEM_DOUBLE) ? rfe_replay_feed_f64(m->f64, log->rows, log->n_rows, rows)
                                            : rfe_replay_feed_f32(m->f32, log->rows, log->n_rows, rows);
}

int rfe_replay_mem_feed(rfe_replay_mem_t *m, const rfe_kv_t *meta, size_t n_meta,
                        const rfe_column_t *cols, size_t n_cols, size_t n_rows, double *out,
                        rfe_io_error_t *err)
{
    rfe_sensor_log_t log;
    rfe_est_row_t *rows;
    rfe_status_t st;
    size_t i;
    int rc;
    if ((m == NULL) || (cols == NULL) || (out == NULL) || (err == NULL)) {
        return (int)RFE_ERR_NULL;
    }
    if (m->ready == 0) {
        return (int)RFE_ERR_NOT_INITIALISED;
    }
    rc = rfe_sensor_log_from_columns(m->name, meta, n_meta, cols, n_cols, n_rows, &m->ro, &log, err);
    if (rc != 0) {
        return (rc > 0) ? rc : RFE_MEM_INPUT;
    }
    if (!same_columns(&m->shape, &log)) {
        rfe_io_error_set(err, m->name, 0u, 0u, "%s",
                         "these samples have other columns than the first ones (a run keeps "
                         "the columns it started with)");
        rfe_sensor_log_free(&log);
        return RFE_MEM_INPUT;
    }
    if ((m->have_last != 0) && !(log.rows[0].t > m->t_last)) {
        /* the reader's rule across blocks, before any row steps */
        rfe_io_error_set(err, m->name, 1u, 0u,
                         "column 't': time not increasing (%.17g after %.17g)", log.rows[0].t,
                         m->t_last);
        rfe_sensor_log_free(&log);
        return RFE_MEM_INPUT;
    }
    if (convert_block(m, &log) != 0) {
        rfe_io_error_set(err, m->name, 0u, 0u, "%s", "R or obs_steer_ratio is not a positive number");
        rfe_sensor_log_free(&log);
        return RFE_MEM_INPUT;
    }
    rows = rfe_xrealloc(NULL, log.n_rows, sizeof *rows);
    memset(rows, 0, log.n_rows * sizeof *rows);
    st = feed_rows(m, &log, rows);
    for (i = 0u; (st == RFE_OK) && (i < log.n_rows); ++i) {
        est_values(&rows[i], &out[i * RFE_MEM_COLS]);
    }
    if ((st == RFE_OK) && (log.n_rows > 0u)) {
        m->t_last = log.rows[log.n_rows - 1u].t;
        m->have_last = 1;
    }
    free(rows);
    rfe_sensor_log_free(&log);
    return (int)st;
}

int rfe_replay_mem_stats(const rfe_replay_mem_t *m, rfe_replay_q31_stats_t *stats)
{
    rfe_status_t st;
    if ((m == NULL) || (stats == NULL)) {
        return (int)RFE_ERR_NULL;
    }
    if (m->ready == 0) {
        return (int)RFE_ERR_NOT_INITIALISED;
    }
    memset(stats, 0, sizeof *stats);
    if (m->real == (int)RFE_MEM_Q31) {
        st = rfe_replay_get_stats_q31(m->q31, stats);
    } else {
        st = (m->real == (int)RFE_MEM_DOUBLE) ? rfe_replay_get_stats_f64(m->f64, &stats->base)
                                              : rfe_replay_get_stats_f32(m->f32, &stats->base);
    }
    return (int)st;
}
