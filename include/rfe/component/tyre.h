/**
 * @file tyre.h
 * @brief Wheel kinematics, vertical loads, slips (MODEL.md §3), the Dugoff tyre (§4) and the
 *        load-scaled Magic Formula tyre (docs/ESTIMATOR.md).
 *
 * Pure functions: no state. All inputs in SI units, wheel order fl, fr, rl, rr.
 * Singularity-free at zero slip (S -> 0), locked wheel (|kappa| -> 1) and standstill.
 */
#ifndef RFE_TYRE_H
#define RFE_TYRE_H

#include "rfe/params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_tyre_kinematics  rfe_tyre_kinematics_f64
#define rfe_tyre_dugoff_norm rfe_tyre_dugoff_norm_f64
#define rfe_tyre_dugoff_abs  rfe_tyre_dugoff_abs_f64
#define rfe_tyre_magic_abs   rfe_tyre_magic_abs_f64
#define rfe_tyre_forces_norm rfe_tyre_forces_norm_f64
#define rfe_tyre_forces_abs  rfe_tyre_forces_abs_f64
#else
#define rfe_tyre_kinematics  rfe_tyre_kinematics_f32
#define rfe_tyre_dugoff_norm rfe_tyre_dugoff_norm_f32
#define rfe_tyre_dugoff_abs  rfe_tyre_dugoff_abs_f32
#define rfe_tyre_magic_abs   rfe_tyre_magic_abs_f32
#define rfe_tyre_forces_norm rfe_tyre_forces_norm_f32
#define rfe_tyre_forces_abs  rfe_tyre_forces_abs_f32
#endif

/**
 * The friction-independent part of one wheel's load-scaled tyre evaluation (absolute Dugoff,
 * MODEL.md §4, or Magic Formula, docs/ESTIMATOR.md), which rfe_meas_setup computes once per
 * sample so that each cubature point only does the friction-dependent rest (fields read-only
 * for the caller).
 */
typedef struct {
    rfe_real_t tan_a; /**< tan of the clamped slip angle */
    rfe_real_t k;     /**< kappa clipped to [-1, 1] */
    rfe_real_t s;     /**< S = |(cx k, cy tan a)| */
    rfe_real_t e;     /**< E = max(0, 1 - eps |vwx| sqrt(k^2 + tan^2 a)) */
    rfe_real_t omk;   /**< 1 - |k| */
    rfe_real_t ux;    /**< cx k / S (magic mode; 0 when S = 0 or in the Dugoff modes) */
    rfe_real_t uy;    /**< cy tan a / S (magic mode; 0 when S = 0 or in the Dugoff modes) */
} rfe_dugoff_pre_t;

/** Per-wheel quantities derived from one sample: the inputs u of the tyre model. */
typedef struct {
    rfe_real_t kappa[RFE_WHEELS]; /**< longitudinal slip, clipped to [-1, 1] */
    rfe_real_t alpha[RFE_WHEELS]; /**< slip angle [rad], bounded to |alpha| <= alpha_max */
    rfe_real_t fz[RFE_WHEELS];    /**< vertical load [N], >= 0 */
    rfe_real_t vwx[RFE_WHEELS];   /**< wheel-centre speed along the wheel x axis [m/s] */
} rfe_wheel_kin_t;

/**
 * MODEL.md §3: wheel-centre velocities, slip angles, longitudinal slips and quasi-static
 * loads from one sample. Uses delta, vx, vy, yaw_rate, ax, ay, omega of @p u.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE if a used input is NaN/Inf.
 */
RFE_NODISCARD rfe_status_t rfe_tyre_kinematics(const rfe_vehicle_t *veh,
                                              const rfe_tyre_params_t *tp,
                                              const rfe_sample_t *u,
                                              rfe_wheel_kin_t *kin);

/**
 * MODEL.md §4, paper mode, one wheel: normalised forces in wheel axes, F = mu * F0.
 *   S = sqrt((Cx_n k)^2 + (Cy_n tan a)^2),  L = (1-|k|) E / (2S),  f(L) = L(2-L) or 1,
 *   F0x = Fz Cx_n k f(L)/(1-|k|),  F0y = Fz Cy_n tan(a) f(L)/(1-|k|),
 *   E = max(0, 1 - eps |vwx| sqrt(k^2 + tan^2 a)).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NONFINITE; RFE_ERR_RANGE if fz < 0.
 */
RFE_NODISCARD rfe_status_t rfe_tyre_dugoff_norm(const rfe_tyre_params_t *tp,
                                               rfe_real_t kappa, rfe_real_t alpha,
                                               rfe_real_t fz, rfe_real_t vwx,
                                               rfe_real_t *f0x, rfe_real_t *f0y);

/**
 * MODEL.md §4, absolute (load-scaled) mode, one wheel: forces in wheel axes at friction mu,
 * Cx = cx Fz, Cy = cy Fz, L = mu (1-|k|) E / (2 sqrt(cx^2 k^2 + cy^2 tan^2 a)).
 * Nonlinear in mu; mu < 0 is evaluated as mu = 0 (a cubature point may fall there).
 */
RFE_NODISCARD rfe_status_t rfe_tyre_dugoff_abs(const rfe_tyre_params_t *tp,
                                              rfe_real_t kappa, rfe_real_t alpha,
                                              rfe_real_t fz, rfe_real_t vwx, rfe_real_t mu,
                                              rfe_real_t *fx, rfe_real_t *fy);

/**
 * Load-scaled Magic Formula (docs/ESTIMATOR.md "The Magic Formula tyre"), one wheel: forces
 * in wheel axes at friction mu, with the slip stiffnesses cx Fz, cy Fz of the absolute mode
 * and the shape factors shape_Cx, shape_Ex, shape_Cy, shape_Ey of @p tp:
 *   s = |(cx k, cy tan a)|, m = max(mu, 0), per direction d: a = atan2(s, m C_d),
 *   G_d = sin(C_d atan2(s - E_d (s - m C_d a), m C_d)),  F_d = Fz m G_d (c_d slip_d) / s.
 * |F| <= m Fz; zero force at zero slip and at mu <= 0 (a cubature point may fall there).
 * Arguments and statuses as rfe_tyre_dugoff_abs (vwx is checked but not used).
 */
RFE_NODISCARD rfe_status_t rfe_tyre_magic_abs(const rfe_tyre_params_t *tp,
                                             rfe_real_t kappa, rfe_real_t alpha,
                                             rfe_real_t fz, rfe_real_t vwx, rfe_real_t mu,
                                             rfe_real_t *fx, rfe_real_t *fy);

/** Four-wheel paper-mode forces F0x, F0y (wheel axes) from the kinematics. */
RFE_NODISCARD rfe_status_t rfe_tyre_forces_norm(const rfe_tyre_params_t *tp,
                                               const rfe_wheel_kin_t *kin,
                                               rfe_real_t f0x[RFE_WHEELS],
                                               rfe_real_t f0y[RFE_WHEELS]);

/** Four-wheel load-scaled forces Fx, Fy (wheel axes) at per-wheel friction mu: the Magic
 *  Formula when tp->mode is RFE_TYRE_MAGIC, the absolute Dugoff otherwise. */
RFE_NODISCARD rfe_status_t rfe_tyre_forces_abs(const rfe_tyre_params_t *tp,
                                              const rfe_wheel_kin_t *kin,
                                              const rfe_real_t mu[RFE_WHEELS],
                                              rfe_real_t fx[RFE_WHEELS],
                                              rfe_real_t fy[RFE_WHEELS]);

#endif /* RFE_TYRE_H */
