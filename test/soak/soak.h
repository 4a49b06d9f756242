/**
 * @file soak.h
 * @brief The soak runner (test/soak/): one variant of the estimator over a long sensor log,
 *        every invariant checked at every step (test/support/invariants.h), a summary.
 *
 * soak_run.c is compiled once per number type and defines soak_run_f32 / soak_run_f64
 * (as soak_run, named below); soak_run_pipeline.c likewise runs the composed pipeline
 * (observer + friction estimator); soak_run_q31.c and soak_run_pipeline_q31.c run the fixed-point estimator and pipeline;
 * soak_run_aux.c (float, double) the mass and grade estimator and the tyre identifier; soak.c reads the log once and
 * calls each variant for each configuration.
 */
#ifndef RFE_SOAK_H
#define RFE_SOAK_H

#include <stddef.h>

#include "csv_log.h"
#include "param_file.h"

#define SOAK_STATUS_SLOTS 32
#define SOAK_WHY 200

/** A configuration: library preset and filter. */
typedef struct {
    const char *name;   /**< "paper.sckf", "paper.ckf", "default.sckf" */
    int preset_default; /**< 0 rfe_params_paper, 1 rfe_params_default */
    int ckf;            /**< 1: the CKF (paper preset only) */
} soak_cfg_t;

/** What one run saw. Shares are over (row, wheel) pairs. */
typedef struct {
    long steps;
    long status[SOAK_STATUS_SLOTS];   /**< count per status code */
    long rejected;                    /**< rows outside the input limits (expected errors) */
    long failed_valid;                /**< errors on rows inside the limits */
    long projected;                   /**< steps with status RFE_PROJECTED (saturation) */
    long at_bound;                    /**< wheel-steps with mu exactly at mu_min or mu_max */
    long sd_over_cap;                 /**< wheel-steps with sd > sd_max (beyond 1e-5 relative) */
    long violations;                  /**< steps breaking an invariant */
    long first_violation_step;        /**< -1 if none */
    char first_violation[SOAK_WHY];
    double mu_lo, mu_hi, sd_lo, sd_hi;
    long n_valid;                     /**< wheel-steps reported valid */
    double rmse_valid;                /**< against the log's truth, where valid */
    double max_err_valid;
    double consistent_valid;          /**< share of valid wheel-steps with |err| <= 2 sd */
    double us_per_step;               /**< wall time per step */
    /* fixed point only (0 for float and double) */
    long input_sat_rows;              /**< rows with a value saturated converting to Q */
    long sat_steps;                   /**< steps whose estimate reports saturations */
    unsigned long long sat_total;     /**< sum of the per-step saturation counts */
    unsigned long sat_max;            /**< the largest per-step count */
    /* the composed pipeline only (0 otherwise): the observer against the log's vx, vy where
     * vx >= v_lat_min */
    long obs_steps;                   /**< accepted steps compared */
    double obs_rmse_vx, obs_max_err_vx, obs_cons_vx; /**< cons: share within 2 sd */
    double obs_far_vx;                /**< share of the steps with vx more than 1 m/s off */
    double obs_rmse_vy, obs_max_err_vy, obs_cons_vy;
} soak_result_t;

/** Runs the configuration over the whole log; 0, or -1 when init fails (message on stderr). */
/* soak_run.c's short name: the twin of the including translation unit's precision. */
#if defined(RFE_REAL_DOUBLE)
#define soak_run soak_run_f64
#define soak_run_pipeline soak_run_pipeline_f64
#else
#define soak_run soak_run_f32
#define soak_run_pipeline soak_run_pipeline_f32
#endif

int soak_run_f32(const rfe_sensor_log_t *log, const char *log_name, const soak_cfg_t *cfg,
                 soak_result_t *res);
int soak_run_f64(const rfe_sensor_log_t *log, const char *log_name, const soak_cfg_t *cfg,
                 soak_result_t *res);
/** The composed pipeline (soak_run_pipeline.c, float and double), the default preset with
 *  the observer's parameters of the log (cfg names the run only). */
int soak_run_pipeline_f32(const rfe_sensor_log_t *log, const char *log_name, const soak_cfg_t *cfg,
                          soak_result_t *res);
int soak_run_pipeline_f64(const rfe_sensor_log_t *log, const char *log_name, const soak_cfg_t *cfg,
                          soak_result_t *res);
/** The fixed-point estimator (soak_run_q31.c): parameters through the double path and
 *  rfe_params_to_q31_f64, samples rounded to the Q formats (as mu_replay --real q31). */
int soak_run_q31(const rfe_sensor_log_t *log, const char *log_name, const soak_cfg_t *cfg,
                 soak_result_t *res);
/** The fixed-point composed pipeline (soak_run_pipeline_q31.c): parameters and ESC samples as
 *  mu_replay --real q31 --velocity observer derives them. */
int soak_run_pipeline_q31(const rfe_sensor_log_t *log, const char *log_name,
                          const soak_cfg_t *cfg, soak_result_t *res);

/** A run of the mass and grade estimator or the tyre identifier (soak_run_aux.c). */
typedef struct {
    const char *name;   /**< "car.recommended", "car.seed"; "apf", "sir" */
    int seed_config;    /**< mass and grade: the seed's configuration (AUKF, speed only);
                             tyre identifier: the bootstrap filter (else the APF) */
    double from, to;    /**< the tyre identifier steps the rows with from <= t < to [s] */
} soak_aux_cfg_t;

/** What one such run saw. */
typedef struct {
    long steps;
    long status[SOAK_STATUS_SLOTS];
    long updated, held, resampled, lost; /**< tyre identifier: steps with each flag */
    long violations;
    long first_violation_step;
    char first_violation[SOAK_WHY];
    double lo, hi;          /**< mass [kg] / the tyre identifier's mu_f mean */
    double lo2, hi2;        /**< grade [rad] / n_eff */
    double final, final_sd; /**< the last mass and its sd / the last K_f and its sd */
    double truth;           /**< the log's mass (mass and grade) */
    double us_per_step;
} soak_aux_result_t;

#if defined(RFE_REAL_DOUBLE)
#define soak_params_of soak_params_of_f64
#else
#define soak_params_of soak_params_of_f32
#endif
/** The library preset's parameters with the log's metadata applied, as mu_replay forms them
 *  (soak_run.c; the struct zeroed first, padding included: states are compared with memcmp);
 *  0, or -1 with a message on stderr. */
int soak_params_of_f32(const rfe_sensor_log_t *log, const char *name, rfe_preset_t preset,
                       rfe_params_t *p);
int soak_params_of_f64(const rfe_sensor_log_t *log, const char *name, rfe_preset_t preset,
                       rfe_params_t *p);

#if defined(RFE_REAL_DOUBLE)
#define soak_run_mass_grade soak_run_mass_grade_f64
#define soak_run_tyre_id soak_run_tyre_id_f64
#else
#define soak_run_mass_grade soak_run_mass_grade_f32
#define soak_run_tyre_id soak_run_tyre_id_f32
#endif
/** The mass and grade estimator over the log, the torque derived from its dynamics
 *  (soak_run_aux.c); 0, or -1 when it cannot start (message on stderr). */
int soak_run_mass_grade_f32(const rfe_sensor_log_t *log, const char *log_name,
                            const soak_aux_cfg_t *cfg, soak_aux_result_t *res);
int soak_run_mass_grade_f64(const rfe_sensor_log_t *log, const char *log_name,
                            const soak_aux_cfg_t *cfg, soak_aux_result_t *res);
/** The fixed-point twin on the same samples rounded to their formats (soak_run_aux.c's
 *  double unit, with SOAK_Q31). */
int soak_run_mass_grade_q31(const rfe_sensor_log_t *log, const char *log_name,
                            const soak_aux_cfg_t *cfg, soak_aux_result_t *res);
/** The tyre identifier over the rows of [cfg->from, cfg->to). */
int soak_run_tyre_id_f32(const rfe_sensor_log_t *log, const char *log_name,
                         const soak_aux_cfg_t *cfg, soak_aux_result_t *res);
int soak_run_tyre_id_f64(const rfe_sensor_log_t *log, const char *log_name,
                         const soak_aux_cfg_t *cfg, soak_aux_result_t *res);

#endif /* RFE_SOAK_H */
