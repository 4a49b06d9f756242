/**
 * @file tyre_internal_q31.h
 * @brief Private per-wheel pieces of the fixed-point tyre model (tyre_q31.c), for the
 *        measurement model (meas_q31.c; the step noise reaches them only through its
 *        public rfe_meas_nominal_q31 / rfe_meas_eval_perturbed_q31): one wheel's
 *        kinematics, the load-scaled tyre evaluation (absolute Dugoff or Magic Formula) split
 *        into its friction-independent part and the rest. Not installed; integer operations
 *        only (no libc header beyond <stdint.h> and <stddef.h>, no <math.h>).
 *
 * Twin of tyre_internal.h, name for name: rfe_tyre_wheel_kin_q31, rfe_tyre_wheel_kappa_q31,
 * rfe_tyre_dugoff_pre_q31, rfe_tyre_dugoff_pre_tan_q31 and rfe_tyre_dugoff_abs_pre_q31 (the
 * curve of tp->mode at mu from the friction-independent terms). The float
 * rfe_tyre_dugoff_abs_pre also checks its arguments at every call; the fixed-point one checks
 * none, because the fixed-point evaluation has no per-value checks (no NaN or infinity: it
 * saturates and counts instead), so the parameter checks (rfe_tyre_dugoff_params_ok_q31,
 * rfe_tyre_abs_params_ok_q31) are made once per set of parameters. rfe_tyre_kinematics_ex_q31 exists only here because it returns the per-wheel
 * saturation counts, a fixed-point concept (the float set-up computes cos/sin of delta
 * itself).
 *
 * These are exactly the operations of rfe_tyre_kinematics_q31, rfe_tyre_dugoff_abs_q31 and
 * rfe_tyre_magic_abs_q31 (which are built from them), so a caller that combines them as those
 * functions do gets the same bits. They check no argument: the callers pass valid pointers, a wheel index below
 * RFE_WHEELS and parameters that passed the public functions' checks.
 */
#ifndef RFE_TYRE_INTERNAL_Q31_H
#define RFE_TYRE_INTERNAL_Q31_H

#include <stddef.h>
#include <stdint.h>

#include "rfe/fixed.h"
#include "rfe/params_q31.h"
#include "rfe/component/tyre_q31.h"
#include "numerics/xf_q31.h"

/** What rfe_tyre_kinematics_ex_q31 gives beyond rfe_wheel_kin_q31_t. */
typedef struct {
    rfe_fix_t cos_delta;          /**< cos of the sample's steer angle, Q30 */
    rfe_fix_t sin_delta;          /**< sin of the sample's steer angle, Q30 */
    uint32_t sat_vwx[RFE_WHEELS]; /**< saturations of each wheel's vwx (0 or 1) */
    uint32_t sat_fz[RFE_WHEELS];  /**< saturations of each wheel's load (0 or 1) */
} rfe_tyre_kin_extra_q31_t;

/** rfe_tyre_kinematics_q31 without the NULL checks, with the saturations per wheel and
 *  cos/sin of delta. @return RFE_OK; RFE_ERR_PARAM (v_min, alpha_max) with nothing written. */
rfe_status_t rfe_tyre_kinematics_ex_q31(const rfe_vehicle_q31_t *veh,
                                        const rfe_tyre_params_q31_t *tp,
                                        const rfe_sample_q31_t *u, rfe_wheel_kin_q31_t *kin,
                                        rfe_tyre_kin_extra_q31_t *extra);

/** Wheel @p i's vwx (Q23, a saturation counted in *sat), alpha and kappa for sample @p u,
 *  with c, s = cos, sin of u->delta (Q30; ignored for the rear wheels). */
void rfe_tyre_wheel_kin_q31(const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
                            const rfe_sample_q31_t *u, int32_t c, int32_t s, size_t i,
                            rfe_fix_t *vwx, rfe_fix_t *alpha, rfe_fix_t *kappa, uint32_t *sat);

/** Wheel @p i's kappa alone (as rfe_tyre_wheel_kin_q31 computes it). */
rfe_fix_t rfe_tyre_wheel_kappa_q31(const rfe_vehicle_q31_t *veh, const rfe_tyre_params_q31_t *tp,
                                   const rfe_sample_q31_t *u, int32_t c, int32_t s, size_t i);

/** The friction-independent part of rfe_tyre_dugoff_abs_q31(tp, kappa, alpha, ., vwx, ...),
 *  which is also that of rfe_tyre_magic_abs_q31 (it depends on neither the mode nor the shape
 *  factors), except that for a Magic Formula @p tp (tp->mode == RFE_TYRE_MAGIC) E and 1 - |k|
 *  (pre->e, pre->omk), which only the Dugoff curve reads, are not formed (left 0): such a pre
 *  serves Magic Formula evaluations only (meas_q31.c pre_matches_q31). */
void rfe_tyre_dugoff_pre_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa, rfe_fix_t alpha,
                             rfe_fix_t vwx, rfe_dugoff_pre_q31_t *pre);

/** The same with tan of the clamped slip angle given (Q26, a previous pre's tan_a); E and
 *  1 - |k| as above. */
void rfe_tyre_dugoff_pre_tan_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa,
                                 rfe_fix_t tan_a, rfe_fix_t vwx, rfe_dugoff_pre_q31_t *pre);

/** 1 when rfe_tyre_dugoff_abs_q31 accepts the parameters (alpha_max, eps), else 0. */
int rfe_tyre_dugoff_params_ok_q31(const rfe_tyre_params_q31_t *tp);

/** The forces Fx, Fy (Q15) of tp->mode's load-scaled curve at friction @p mu (Q29; mu < 0
 *  evaluated as 0) and load @p fz (Q15, >= 0) from @p pre (of rfe_tyre_dugoff_pre_q31 at tp):
 *  the Magic Formula in magic mode, the load-scaled Dugoff otherwise, as
 *  rfe_tyre_forces_abs_q31 chooses (the same operations as rfe_tyre_magic_abs_q31 /
 *  rfe_tyre_dugoff_abs_q31 after their checks); one count in *sat per clamped force. @p tp must pass
 *  rfe_tyre_abs_params_ok_q31. The twin of tyre_internal.h's rfe_tyre_dugoff_abs_pre. */
void rfe_tyre_dugoff_abs_pre_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                                 rfe_fix_t mu, rfe_fix_t fz, rfe_fix_t *fx, rfe_fix_t *fy,
                                 uint32_t *sat);

/** 1 when rfe_tyre_forces_abs_q31 accepts the parameters in tp's mode (alpha_max, eps; in
 *  magic mode also the shape factors), else 0. */
int rfe_tyre_abs_params_ok_q31(const rfe_tyre_params_q31_t *tp);

/* ---- the forces' derivatives (the observer's lateral rows, docs/OBSERVER.md §4.2) ---------- */

/** A change of one wheel's tyre inputs per unit of vy (tyre_internal.h's rfe_slip_dir_t), real
 *  values in rfe_xf_t: of the clipped kappa [s/m], of tan alpha [s/m], of v_wx [1]. */
typedef struct {
    rfe_xf_t k;     /**< d kappa */
    rfe_xf_t tan_a; /**< d tan(alpha) */
    rfe_xf_t vwx;   /**< d v_wx */
} rfe_slip_dir_q31_t;

/** One wheel's force derivatives (real values in rfe_xf_t, wheel axes). */
typedef struct {
    rfe_xf_t dfx; /**< dFx along the input change [N per unit of the change's variable] */
    rfe_xf_t dfy; /**< dFy along the input change */
    rfe_xf_t mfx; /**< dFx / d mu [N] (paper mode: F0x; 0 where mu <= 0 in the others) */
    rfe_xf_t mfy; /**< dFy / d mu [N] */
} rfe_tyre_jac_q31_t;

/** Paper mode's friction-independent terms (rfe_tyre_dugoff_pre_q31 with Cx_n, Cy_n). */
void rfe_tyre_norm_pre_q31(const rfe_tyre_params_q31_t *tp, rfe_fix_t kappa, rfe_fix_t alpha,
                           rfe_fix_t vwx, rfe_dugoff_pre_q31_t *pre);

/** The twin of tyre_internal.h's rfe_tyre_pre_jac: the derivatives of tp->mode's forces at
 *  friction @p mu (Q29) and load @p fz (Q15) along @p d and by mu, from @p pre (paper:
 *  rfe_tyre_norm_pre_q31; the others: rfe_tyre_dugoff_pre_q31) and the clipped kappa (Q30) and
 *  v_wx (Q23) it was made of; the float formulas in rfe_xf_t (2^-30 relative per operation).
 *  @p tp must pass rfe_tyre_abs_params_ok_q31 (paper mode: its Dugoff checks). */
void rfe_tyre_pre_jac_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                          rfe_fix_t kappa, rfe_fix_t vwx, rfe_fix_t fz, rfe_fix_t mu,
                          const rfe_slip_dir_q31_t *d, rfe_tyre_jac_q31_t *out);

/** rfe_tyre_pre_jac_q31 for paper and absolute (Dugoff) mode only, bit for bit: the step
 *  noise's input derivatives (meas_q31.c wheel_basis_q31) call it for those modes, so a build
 *  that links them does not link the Magic Formula's directional derivative
 *  (rfe_tyre_magic_pre_jac_q31) through rfe_tyre_pre_jac_q31's other branch. */
void rfe_tyre_dugoff_pre_jac_q31(const rfe_tyre_params_q31_t *tp,
                                 const rfe_dugoff_pre_q31_t *pre, rfe_fix_t kappa,
                                 rfe_fix_t vwx, rfe_fix_t fz, rfe_fix_t mu,
                                 const rfe_slip_dir_q31_t *d, rfe_tyre_jac_q31_t *out);

/** Magic Formula mode (tp passed rfe_tyre_abs_params_ok_q31): the forces Fx, Fy (Q15) of
 *  rfe_tyre_dugoff_abs_pre_q31 and the derivatives of rfe_tyre_pre_jac_q31 at friction @p mu
 *  (Q29) and load @p fz (Q15, >= 0) from @p pre (rfe_tyre_dugoff_pre_q31), bit for bit, with
 *  each direction's two atan2 and sine evaluated once for both (the observer's lateral rows);
 *  one count in *sat per clamped force. */
void rfe_tyre_magic_pre_jac_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                                rfe_fix_t fz, rfe_fix_t mu, const rfe_slip_dir_q31_t *d,
                                rfe_fix_t *fx, rfe_fix_t *fy, uint32_t *sat,
                                rfe_tyre_jac_q31_t *out);

/** Magic Formula mode (tp passed rfe_tyre_abs_params_ok_q31): the forces Fx, Fy (Q15) of
 *  rfe_tyre_magic_pre_jac_q31 and the derivatives it gives along a unit change of kappa
 *  (out[0]) and of tan alpha (out[1]), bit for bit, with the curves (per direction two atan2 and
 *  a sine) and their derivative factors evaluated once for both (the step noise's input
 *  derivatives, meas_q31.c); one count in *sat per clamped force. */
void rfe_tyre_magic_basis_q31(const rfe_tyre_params_q31_t *tp, const rfe_dugoff_pre_q31_t *pre,
                              rfe_fix_t fz, rfe_fix_t mu, rfe_fix_t *fx, rfe_fix_t *fy,
                              uint32_t *sat, rfe_tyre_jac_q31_t out[2]);

#endif /* RFE_TYRE_INTERNAL_Q31_H */
