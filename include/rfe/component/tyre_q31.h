/**
 * @file tyre_q31.h
 * @brief Fixed-point twin of rfe/component/tyre.h: wheel kinematics, loads, slips (MODEL.md §3), the
 *        Dugoff tyre (§4) and the load-scaled Magic Formula tyre (docs/ESTIMATOR.md) on int32
 *        Q values (docs/FIXED_POINT.md, "Tyre, kinematics and observation matrix").
 *
 * Same functions, arguments and structs as the float module, with Q values and a trailing
 * saturation counter: a result beyond its format's range is clamped symmetrically and one
 * count is added to `*sat` per clamped output value (kinematics: vwx and fz; tyre: Fx, Fy).
 * No intermediate value saturates (each range is proven in tyre_q31.c; the Dugoff ratio L is
 * only compared with 1, so its clamp at L >= 2 is not counted), so the count is exactly the
 * number of clamped outputs. Every int32 input is in the domain: there
 * are no non-finite values, and the float module's clip and guards (kappa to [-1, 1],
 * |alpha| <= alpha_max, E >= 0, loads >= 0, the v_min guard) hold for any input.
 * On an error nothing is written (outputs and `*sat` untouched).
 *
 * Parameter checks (the float module has them implicitly, through NaN; here they guard the
 * integer algorithms): v_min > 0 (kinematics: slip denominator), 0 < alpha_max < 1.5 rad
 * (tan's domain), eps >= 0 (keeps E in [0, 1]); the Magic Formula also 1 < shape_C < 2 and
 * -4 <= shape_E < 1 in both directions (rfe_params_validate's rule; it keeps every angle of
 * the curve in [0, pi)); otherwise RFE_ERR_PARAM.
 */
#ifndef RFE_TYRE_Q31_H
#define RFE_TYRE_Q31_H

#include <stdint.h>

#include "rfe/common.h"
#include "rfe/fixed.h"
#include "rfe/params_q31.h"

/** One sensor sample in Q formats (fields of rfe_sample_t). */
typedef struct {
    rfe_fix_t delta;             /**< front road-wheel steer angle [rad], Q29 */
    rfe_fix_t vx;                /**< CoG velocity, body x [m/s], Q23 */
    rfe_fix_t vy;                /**< CoG velocity, body y [m/s], Q23 */
    rfe_fix_t yaw_rate;          /**< r [rad/s], Q27 */
    rfe_fix_t yaw_acc;           /**< r-dot [rad/s^2], Q24 */
    rfe_fix_t ax;                /**< CoG acceleration, body x [m/s^2], Q24 */
    rfe_fix_t ay;                /**< CoG acceleration, body y [m/s^2], Q24 */
    rfe_fix_t omega[RFE_WHEELS]; /**< wheel spin speeds [rad/s], Q22, order fl fr rl rr */
} rfe_sample_q31_t;

/** Per-wheel quantities derived from one sample (fields of rfe_wheel_kin_t). */
typedef struct {
    rfe_fix_t kappa[RFE_WHEELS]; /**< longitudinal slip, Q30, clipped to [-1, 1] */
    rfe_fix_t alpha[RFE_WHEELS]; /**< slip angle [rad], Q29, |alpha| <= alpha_max */
    rfe_fix_t fz[RFE_WHEELS];    /**< vertical load [N], Q15, >= 0 */
    rfe_fix_t vwx[RFE_WHEELS];   /**< wheel-centre speed along the wheel x axis [m/s], Q23 */
} rfe_wheel_kin_q31_t;

/**
 * The friction- and load-independent part of one wheel's load-scaled tyre evaluation
 * (absolute Dugoff, MODEL.md §4, and the Magic Formula, docs/ESTIMATOR.md, which uses s, ux,
 * uy and qs; the same terms for both, independent of the mode and the shape factors), which
 * rfe_meas_setup_q31 computes once per sample so that each cubature point only does the
 * friction-dependent rest (fields read-only for the caller; the internal formats of
 * tyre_q31.c).
 */
typedef struct {
    rfe_fix_t tan_a; /**< tan of the clamped slip angle, Q26 */
    rfe_fix_t s;     /**< S = |(C1 k, C2 tan a)| (30 significant bits), Q(qs) */
    rfe_fix_t ux;    /**< direction cosine C1 k / S, Q30 (0 when S = 0) */
    rfe_fix_t uy;    /**< direction cosine C2 tan a / S, Q30 (0 when S = 0) */
    rfe_fix_t e;     /**< E = max(0, 1 - eps |vwx| sqrt(k^2 + tan^2 a)), Q30 (0 when S = 0) */
    rfe_fix_t omk;   /**< 1 - |k|, Q30 (0 when S = 0) */
    uint32_t qs;     /**< the Q format of s */
} rfe_dugoff_pre_q31_t;

/**
 * MODEL.md §3: wheel-centre velocities, slip angles, longitudinal slips and quasi-static
 * loads from one sample (uses delta, vx, vy, yaw_rate, ax, ay, omega of @p u).
 * Internally the body and wheel-centre velocities are int64 Q51 (exact products, one rounding
 * to 2^-52 m/s each), so alpha and kappa keep their accuracy at any speed (docs).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (v_min <= 0 or alpha_max outside (0, 1.5) rad).
 */
RFE_NODISCARD rfe_status_t rfe_tyre_kinematics_q31(const rfe_vehicle_q31_t *veh,
                                                   const rfe_tyre_params_q31_t *tp,
                                                   const rfe_sample_q31_t *u,
                                                   rfe_wheel_kin_q31_t *kin, uint32_t *sat);

/**
 * MODEL.md §4, paper mode, one wheel: normalised forces F0x, F0y [N, Q15] in wheel axes.
 * |F0| <= Fz, so these never saturate (the counter is still taken, for the shape).
 * @param kappa Q30 (clipped to [-1, 1]); @param alpha Q29 (clamped to +-alpha_max);
 * @param fz Q15, >= 0; @param vwx Q23.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE if fz < 0; RFE_ERR_PARAM (alpha_max, eps).
 */
RFE_NODISCARD rfe_status_t rfe_tyre_dugoff_norm_q31(const rfe_tyre_params_q31_t *tp,
                                                    rfe_fix_t kappa, rfe_fix_t alpha,
                                                    rfe_fix_t fz, rfe_fix_t vwx, rfe_fix_t *f0x,
                                                    rfe_fix_t *f0y, uint32_t *sat);

/**
 * MODEL.md §4, absolute (load-scaled) mode, one wheel: forces Fx, Fy [N, Q15] at friction
 * @p mu (Q29; mu < 0 is evaluated as mu = 0). Arguments as rfe_tyre_dugoff_norm_q31.
 */
RFE_NODISCARD rfe_status_t rfe_tyre_dugoff_abs_q31(const rfe_tyre_params_q31_t *tp,
                                                   rfe_fix_t kappa, rfe_fix_t alpha,
                                                   rfe_fix_t fz, rfe_fix_t vwx, rfe_fix_t mu,
                                                   rfe_fix_t *fx, rfe_fix_t *fy,
                                                   uint32_t *sat);

/**
 * Load-scaled Magic Formula (docs/ESTIMATOR.md "The Magic Formula tyre"), one wheel: forces
 * Fx, Fy [N, Q15] in wheel axes at friction @p mu (Q29; mu < 0 is evaluated as mu = 0, zero
 * force), with the slip stiffnesses cx Fz, cy Fz and the shape factors shape_Cx, shape_Ex,
 * shape_Cy, shape_Ey (Q24) of @p tp:
 *   s = |(cx k, cy tan a)|, m = max(mu, 0), per direction d: a = atan2(s, m C_d),
 *   G_d = sin(C_d atan2(s - E_d (s - m C_d a), m C_d)),  F_d = Fz m G_d (c_d slip_d) / s.
 * |F| <= m Fz (a value beyond Q15 clamps and counts); F = 0 at zero slip and at mu <= 0.
 * Arguments as rfe_tyre_dugoff_abs_q31 (vwx is not used by the curve; eps must still be
 * >= 0, the set-up shared with the Dugoff tyre uses it).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE if fz < 0; RFE_ERR_PARAM (alpha_max, eps, a
 *         shape factor outside 1 < C < 2, -4 <= E < 1).
 */
RFE_NODISCARD rfe_status_t rfe_tyre_magic_abs_q31(const rfe_tyre_params_q31_t *tp,
                                                  rfe_fix_t kappa, rfe_fix_t alpha,
                                                  rfe_fix_t fz, rfe_fix_t vwx, rfe_fix_t mu,
                                                  rfe_fix_t *fx, rfe_fix_t *fy, uint32_t *sat);

/** Four-wheel paper-mode forces F0x, F0y (wheel axes, Q15) from the kinematics. */
RFE_NODISCARD rfe_status_t rfe_tyre_forces_norm_q31(const rfe_tyre_params_q31_t *tp,
                                                    const rfe_wheel_kin_q31_t *kin,
                                                    rfe_fix_t f0x[RFE_WHEELS],
                                                    rfe_fix_t f0y[RFE_WHEELS], uint32_t *sat);

/** Four-wheel load-scaled forces Fx, Fy (wheel axes, Q15) at per-wheel friction mu (Q29): the
 *  Magic Formula (rfe_tyre_magic_abs_q31) when tp->mode is RFE_TYRE_MAGIC, the absolute
 *  Dugoff (rfe_tyre_dugoff_abs_q31) otherwise. */
RFE_NODISCARD rfe_status_t rfe_tyre_forces_abs_q31(const rfe_tyre_params_q31_t *tp,
                                                   const rfe_wheel_kin_q31_t *kin,
                                                   const rfe_fix_t mu[RFE_WHEELS],
                                                   rfe_fix_t fx[RFE_WHEELS],
                                                   rfe_fix_t fy[RFE_WHEELS], uint32_t *sat);

#endif /* RFE_TYRE_Q31_H */
