/**
 * @file tyre_internal.h
 * @brief Private split of the absolute-mode Dugoff evaluation of tyre_flt.c for the
 *        measurement model (meas_flt.c): the terms that do not depend on the friction, once
 *        per sample, and the rest at each friction value. Not installed.
 *
 * rfe_tyre_dugoff_abs is exactly rfe_tyre_dugoff_pre followed by rfe_tyre_dugoff_abs_pre
 * (the same operations in the same order), so a caller that keeps the terms gets the same
 * bits and the same statuses.
 */
#ifndef RFE_TYRE_INTERNAL_H
#define RFE_TYRE_INTERNAL_H

#include <stddef.h>

#include "rfe/params.h"
#include "rfe/component/tyre.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_tyre_dugoff_pre     rfe_tyre_dugoff_pre_f64
#define rfe_tyre_dugoff_abs_pre rfe_tyre_dugoff_abs_pre_f64
#define rfe_tyre_wheel_kin      rfe_tyre_wheel_kin_f64
#define rfe_tyre_wheel_kappa    rfe_tyre_wheel_kappa_f64
#define rfe_tyre_dugoff_pre_tan rfe_tyre_dugoff_pre_tan_f64
#define rfe_tyre_norm_pre       rfe_tyre_norm_pre_f64
#define rfe_tyre_pre_jac        rfe_tyre_pre_jac_f64
#define rfe_tyre_magic_basis    rfe_tyre_magic_basis_f64
#define rfe_tyre_kinematics_cs  rfe_tyre_kinematics_cs_f64
#else
#define rfe_tyre_dugoff_pre     rfe_tyre_dugoff_pre_f32
#define rfe_tyre_dugoff_abs_pre rfe_tyre_dugoff_abs_pre_f32
#define rfe_tyre_wheel_kin      rfe_tyre_wheel_kin_f32
#define rfe_tyre_wheel_kappa    rfe_tyre_wheel_kappa_f32
#define rfe_tyre_dugoff_pre_tan rfe_tyre_dugoff_pre_tan_f32
#define rfe_tyre_norm_pre       rfe_tyre_norm_pre_f32
#define rfe_tyre_pre_jac        rfe_tyre_pre_jac_f32
#define rfe_tyre_magic_basis    rfe_tyre_magic_basis_f32
#define rfe_tyre_kinematics_cs  rfe_tyre_kinematics_cs_f32
#endif

/** rfe_tyre_kinematics with the cos and sin of u->delta it computed (@p cos_delta,
 *  @p sin_delta): the same checks, values and statuses; @p kin and both written only on RFE_OK
 *  (the measurement model's set-up takes them instead of computing them again, issue 16). */
RFE_NODISCARD rfe_status_t rfe_tyre_kinematics_cs(const rfe_vehicle_t *veh,
                                                 const rfe_tyre_params_t *tp,
                                                 const rfe_sample_t *u, rfe_wheel_kin_t *kin,
                                                 rfe_real_t *cos_delta, rfe_real_t *sin_delta);

/** The friction-independent terms of rfe_tyre_dugoff_abs(tp, kappa, alpha, ., vwx, ...)
 *  (and, when tp->mode is RFE_TYRE_MAGIC, the direction cosines ux, uy of rfe_tyre_magic_abs)
 *  (no checks: non-finite inputs give non-finite terms, which the second part then rejects
 *  through its checks of the same inputs). */
void rfe_tyre_dugoff_pre(const rfe_tyre_params_t *tp, rfe_real_t kappa, rfe_real_t alpha,
                         rfe_real_t vwx, rfe_dugoff_pre_t *pre);

/** rfe_tyre_dugoff_abs(tp, kappa, alpha, fz, vwx, mu, fx, fy) (rfe_tyre_magic_abs when
 *  tp->mode is RFE_TYRE_MAGIC) with @p pre = rfe_tyre_dugoff_pre(tp, kappa, alpha, vwx): the
 *  same checks in the same order, the same forces. */
RFE_NODISCARD rfe_status_t rfe_tyre_dugoff_abs_pre(
    const rfe_tyre_params_t *tp, const rfe_dugoff_pre_t *pre, rfe_real_t kappa,
    rfe_real_t alpha, rfe_real_t fz, rfe_real_t vwx, rfe_real_t mu, rfe_real_t *fx,
    rfe_real_t *fy);

/** Wheel @p i's vwx, alpha and kappa for sample @p u, with c, s = cos, sin of u->delta
 *  (ignored for the rear wheels), as rfe_tyre_kinematics computes them (no checks). */
void rfe_tyre_wheel_kin(const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
                        const rfe_sample_t *u, rfe_real_t c, rfe_real_t s, size_t i,
                        rfe_real_t *vwx, rfe_real_t *alpha, rfe_real_t *kappa);

/** A wheel's kappa from its spin speed @p omega and vwx, as rfe_tyre_kinematics computes it. */
rfe_real_t rfe_tyre_wheel_kappa(const rfe_vehicle_t *veh, const rfe_tyre_params_t *tp,
                                rfe_real_t omega, rfe_real_t vwx);

/** rfe_tyre_dugoff_pre with tan of the clamped slip angle given (a previous pre's tan_a). */
void rfe_tyre_dugoff_pre_tan(const rfe_tyre_params_t *tp, rfe_real_t kappa,
                             rfe_real_t tan_a, rfe_real_t vwx, rfe_dugoff_pre_t *pre);

/* ---- the forces' derivatives (the observer's lateral rows, docs/OBSERVER.md §4.2) ---------- */

/** A change of one wheel's tyre inputs per unit of the variable differentiated by: of the
 *  clipped kappa, of tan of the clamped slip angle and of vwx. */
typedef struct {
    rfe_real_t k;     /**< d kappa */
    rfe_real_t tan_a; /**< d tan(alpha) */
    rfe_real_t vwx;   /**< d v_wx */
} rfe_slip_dir_t;

/** One wheel's forces (wheel axes) at its friction and their first derivatives. */
typedef struct {
    rfe_real_t fx;  /**< Fx at mu (paper mode: mu F0x) */
    rfe_real_t fy;  /**< Fy at mu (paper mode: mu F0y) */
    rfe_real_t dfx; /**< dFx along the input change rfe_slip_dir_t */
    rfe_real_t dfy; /**< dFy along the input change */
    rfe_real_t mfx; /**< dFx / d mu (paper mode: F0x; 0 where mu <= 0 in the others) */
    rfe_real_t mfy; /**< dFy / d mu */
} rfe_tyre_jac_t;

/** Paper mode's friction-independent terms of rfe_tyre_dugoff_norm(tp, kappa, alpha, ., vwx):
 *  rfe_tyre_dugoff_pre with the normalised stiffnesses Cx_n, Cy_n (ux, uy 0). */
void rfe_tyre_norm_pre(const rfe_tyre_params_t *tp, rfe_real_t kappa, rfe_real_t alpha,
                       rfe_real_t vwx, rfe_dugoff_pre_t *pre);

/** The forces of tp->mode's curve at friction @p mu (paper: mu F0 from @p pre of
 *  rfe_tyre_norm_pre; absolute, magic: as rfe_tyre_dugoff_abs_pre from @p pre of
 *  rfe_tyre_dugoff_pre, the same operations, so the same bits) and, analytically, their
 *  derivatives along the input change @p d and by mu (docs/OBSERVER.md §4.2: the Dugoff
 *  factor piecewise in L, the Magic Formula shape through the atan values of its own
 *  evaluation and one cosine per direction). Checks and statuses as rfe_tyre_dugoff_abs_pre.
 *  No derivative is checked for finiteness (the caller's sums are). */
RFE_NODISCARD rfe_status_t rfe_tyre_pre_jac(const rfe_tyre_params_t *tp,
                                           const rfe_dugoff_pre_t *pre, rfe_real_t kappa,
                                           rfe_real_t alpha, rfe_real_t fz, rfe_real_t vwx,
                                           rfe_real_t mu, const rfe_slip_dir_t *d,
                                           rfe_tyre_jac_t *out);

/** Magic Formula mode: rfe_tyre_pre_jac along a unit change of kappa (out[0]) and of tan
 *  alpha (out[1]) (d = (1, 0, 0), (0, 1, 0)), bit for bit, with the two curves (an atan2, a
 *  sine and a cosine each) evaluated once for both directions (the step noise's input
 *  derivatives, meas_flt.c; the twin of rfe_tyre_magic_basis_q31). Checks and statuses as
 *  rfe_tyre_pre_jac. */
RFE_NODISCARD rfe_status_t rfe_tyre_magic_basis(const rfe_tyre_params_t *tp,
                                               const rfe_dugoff_pre_t *pre, rfe_real_t kappa,
                                               rfe_real_t alpha, rfe_real_t fz, rfe_real_t vwx,
                                               rfe_real_t mu, rfe_tyre_jac_t out[2]);
#endif /* RFE_TYRE_INTERNAL_H */
