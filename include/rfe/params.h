/**
 * @file params.h
 * @brief Run-time parameters: vehicle, tyre, filter (MODEL.md §2, DATA.md parameter keys).
 *
 * Nothing in the algorithms is a literal: every number comes from these structs. Defaults
 * are the MODEL.md §2 values; each field names its DATA.md key.
 */
#ifndef RFE_PARAMS_H
#define RFE_PARAMS_H

#include "rfe/types.h"

/** Vehicle geometry and mass (MODEL.md §2). */
typedef struct {
    rfe_real_t m;   /**< key m: mass [kg], default 1830 */
    rfe_real_t Lf;  /**< key Lf: CoG to front axle [m], default 1.40 */
    rfe_real_t Lr;  /**< key Lr: CoG to rear axle [m], default 1.65 */
    rfe_real_t Bf;  /**< key Bf: front track [m], default 1.60 */
    rfe_real_t Br;  /**< key Br: rear track [m], default 1.60 */
    rfe_real_t R;   /**< key R: effective rolling radius [m], default 0.325 */
    rfe_real_t J;   /**< key J: yaw moment of inertia [kg m^2], default 3234 */
    rfe_real_t hg;  /**< key hg: CoG height [m], default 0.54 */
    rfe_real_t g;   /**< key g: gravity [m/s^2], default 9.81 */
} rfe_vehicle_t;

/** Which Dugoff form the measurement model uses (MODEL.md §4). */
typedef enum {
    RFE_TYRE_PAPER = 0,    /**< normalised: F = mu * F0(u), stiffness ∝ mu*Fz; h = H(u) x */
    RFE_TYRE_ABSOLUTE = 1  /**< load-scaled: Cx = cx*Fz, Cy = cy*Fz; h nonlinear in mu */
} rfe_tyre_mode_t;

/** Dugoff tyre and slip-computation parameters (MODEL.md §3-4). */
typedef struct {
    rfe_tyre_mode_t mode; /**< key tyre (paper|absolute), default paper */
    rfe_real_t Cx_n;      /**< key Cx_n: normalised longitudinal stiffness [1], default 20 */
    rfe_real_t Cy_n;      /**< key Cy_n: normalised cornering stiffness [1/rad], default 15 */
    rfe_real_t cx;        /**< key cx: longitudinal stiffness per unit Fz, absolute mode, default 20 */
    rfe_real_t cy;        /**< key cy: cornering stiffness per unit Fz, absolute mode [1/rad], default 15 */
    rfe_real_t eps;       /**< key eps: Dugoff velocity-reduction factor [s/m], default 0.015 */
    rfe_real_t v_min;     /**< key v_min: slip denominator guard [m/s], default 0.5 */
    rfe_real_t alpha_max; /**< key alpha_max: slip-angle bound [rad], default 1.4, must be < pi/2 */
} rfe_tyre_params_t;

/** Which filter runs the estimator (MODEL.md §6). */
typedef enum {
    RFE_FILTER_SCKF = 0,  /**< square-root cubature Kalman filter (the paper's method) */
    RFE_FILTER_CKF = 1    /**< full-covariance cubature Kalman filter (the paper's baseline) */
} rfe_filter_kind_t;

/** Filter tuning (MODEL.md §6, DATA.md). */
typedef struct {
    rfe_filter_kind_t kind; /**< key filter (sckf|ckf), default sckf */
    rfe_real_t mu0;       /**< key mu0: initial estimate on every wheel, default 0.5 */
    rfe_real_t sd0;       /**< key sd0: initial standard deviation, S0 = sd0*I, default 0.3 */
    rfe_real_t q_mu;      /**< key q_mu: process-noise sd per step, S_Q = q_mu*I, default 0.003 */
    rfe_real_t r_ax;      /**< key r_ax: ax measurement-noise sd [m/s^2], default 0.05 */
    rfe_real_t r_ay;      /**< key r_ay: ay measurement-noise sd [m/s^2], default 0.05 */
    rfe_real_t r_yaw_acc; /**< key r_yaw_acc: yaw-acceleration noise sd [rad/s^2], default 0.05 */
    rfe_real_t mu_min;    /**< key mu_min: lower projection bound, default 0.05 */
    rfe_real_t mu_max;    /**< key mu_max: upper projection bound, default 1.2 */
    rfe_real_t v_est_min; /**< key v_est_min: below this vx no measurement update [m/s], default 3.0 */
} rfe_filter_params_t;

/** Everything the friction estimator needs. */
typedef struct {
    rfe_vehicle_t vehicle;
    rfe_tyre_params_t tyre;
    rfe_filter_params_t filter;
} rfe_params_t;

/** Fills @p p with the library's default configuration (today: the paper configuration). */
RFE_NODISCARD rfe_status_t RFE_FN(rfe_params_default)(rfe_params_t *p);

/**
 * Fills @p p with the paper configuration (MODEL.md §2, §6): four independent mu, normalised
 * tyre, x0 = 0.5, S0 = 0.3 I, S_Q = 0.003 I, S_R = 0.05 I. Kept as the reference baseline.
 */
RFE_NODISCARD rfe_status_t RFE_FN(rfe_params_paper)(rfe_params_t *p);

/**
 * Checks every field: finite, positive where physical (m, L, B, R, J, g, stiffnesses,
 * noise sds), hg >= 0, eps >= 0, 0 < alpha_max < 1.5, 0 <= mu_min < mu_max, mu0 within
 * [mu_min, mu_max], v_est_min >= 0, enums in range. Returns RFE_OK or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t RFE_FN(rfe_params_validate)(const rfe_params_t *p);

#endif /* RFE_PARAMS_H */
