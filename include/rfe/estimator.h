/**
 * @file estimator.h
 * @brief The friction estimator: one sensor sample in, four mu estimates out.
 *
 * Composition of the modules, one hop each: sample -> kinematics, loads, slips (tyre) ->
 * normalised forces (tyre) -> H (obsmat) -> SCKF or CKF (sckf/ckf, qr) -> estimate.
 * The caller owns the rfe_estimator_t (no heap); init it once, then step at the sample
 * rate. A rejected sample returns an error status and leaves the estimator untouched.
 */
#ifndef RFE_ESTIMATOR_H
#define RFE_ESTIMATOR_H

#include "rfe/ckf.h"
#include "rfe/params.h"
#include "rfe/sckf.h"
#include "rfe/tyre.h"

/** Output of one step (one row of the DATA.md estimate log). */
typedef struct {
    rfe_real_t mu[RFE_WHEELS];    /**< estimated friction per wheel */
    rfe_real_t sd[RFE_WHEELS];    /**< its standard deviation */
    uint8_t valid[RFE_WHEELS];    /**< 1 when this step updated the wheel's estimate from data */
    rfe_status_t status;          /**< status of the step (same as the return value) */
} rfe_estimate_t;

/** Estimator state (caller-owned; fields are read-only for the caller). */
typedef struct {
    uint32_t magic;
    rfe_params_t params;
    rfe_wheel_kin_t kin;              /**< kinematics of the sample being processed */
    rfe_real_t H[RFE_MEAS * RFE_WHEELS]; /**< paper mode: H(u) of that sample */
    rfe_real_t delta;                 /**< steer angle of that sample */
    rfe_real_t backup_x[RFE_N_MAX];   /**< filter mean before the step (restored on error) */
    rfe_real_t backup_S[RFE_N_MAX * RFE_N_MAX]; /**< its S (SCKF) or P (CKF) */
    union {
        rfe_sckf_t sckf;
        rfe_ckf_t ckf;
    } filter;                          /**< params.filter.kind says which is live */
} rfe_estimator_t;

/**
 * Validates @p params (rfe_params_validate) and initialises: x0 = mu0 on every wheel,
 * S0 = sd0 I, S_Q = q_mu I, S_R = diag(r_ax, r_ay, r_yaw_acc).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (estimator then untouched).
 */
RFE_NODISCARD rfe_status_t RFE_FN(rfe_estimator_init)(rfe_estimator_t *est,
                                                     const rfe_params_t *params);

/**
 * One step: time update, then (if vx >= v_est_min) the measurement update with
 * y = [ax, ay, yaw_acc], then projection onto [mu_min, mu_max].
 * @p out receives the posterior (or, on error, the unchanged previous estimate with
 * valid = 0 and the error status).
 * @return RFE_OK, RFE_PROJECTED, RFE_NO_UPDATE_LOW_SPEED; errors: RFE_ERR_NULL,
 *         RFE_ERR_NOT_INITIALISED, RFE_ERR_NONFINITE, RFE_ERR_RANGE (see config.h limits),
 *         RFE_ERR_NOT_POSITIVE_DEFINITE (CKF only).
 */
RFE_NODISCARD rfe_status_t RFE_FN(rfe_estimator_step)(rfe_estimator_t *est,
                                                     const rfe_sample_t *sample,
                                                     rfe_estimate_t *out);

/** Current estimate without stepping (status RFE_OK, valid = 0). */
RFE_NODISCARD rfe_status_t RFE_FN(rfe_estimator_get)(const rfe_estimator_t *est,
                                                    rfe_estimate_t *out);

#endif /* RFE_ESTIMATOR_H */
