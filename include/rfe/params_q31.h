/**
 * @file params_q31.h
 * @brief Run-time parameters of the fixed-point variant: the fields of rfe_params_t
 *        (params.h) as int32 Q values, plus the derived constants the integer code needs
 *        precomputed (docs/FIXED_POINT.md, "Tyre, kinematics and observation matrix").
 *
 * Every field states its unit, its Q format (the number of fractional bits: the stored
 * integer v means v / 2^Q) and the range that format gives. The algorithms never use a
 * literal: the vehicle and tyre constants and the derived constants below are all they use.
 *
 * The derived constants (1/m, x_i/J, y_i/J, half tracks, static loads, load-transfer
 * coefficients, the input-filter gain) are redundant: they must agree with the base fields.
 * rfe_params_to_q31_f32/_f64 (rfe/component/params_conv.h, host or float build) computes them from
 * the real-valued parameters; rfe_params_validate_q31 recomputes each from the Q base fields
 * and rejects a struct whose derived constant is off by more than 2^-13 relative (a stale
 * constant after a base field was changed by more than ~0.01 %).
 *
 * The enums (tyre mode, filter kind, structure) are rfe/modes.h's, which both number types
 * share; the float parameters of rfe/params.h are never included here.
 */
#ifndef RFE_PARAMS_Q31_H
#define RFE_PARAMS_Q31_H

#include <stdint.h>

#include "rfe/common.h"
#include "rfe/fixed.h"
#include "rfe/modes.h"

/* ---- Q formats of the measurement model (docs/FIXED_POINT.md) -------------------------- */
#define RFE_FIX_Q_MU 29      /**< friction mu, mu0, mu_min, mu_max: Q29, +-4 */
#define RFE_FIX_Q_SD 30      /**< sd of mu (S, sd0, q_mu, ...), dimensionless ratios: Q30, +-2 */
#define RFE_FIX_Q_SPEED 23   /**< speeds [m/s]: Q23, +-256 */
#define RFE_FIX_Q_OMEGA 22   /**< wheel spin speeds [rad/s]: Q22, +-512 */
#define RFE_FIX_Q_YAWRATE 27 /**< yaw rate [rad/s]: Q27, +-16 */
#define RFE_FIX_Q_KAPPA 30   /**< longitudinal slip: Q30, +-2 */
#define RFE_FIX_Q_FORCE 15   /**< loads and tyre forces [N]: Q15, +-65536 */
#define RFE_FIX_Q_ACC 24     /**< accelerations, h, H entries [m/s^2, rad/s^2]: Q24, +-128 */
#define RFE_FIX_Q_LEN 29     /**< lengths Lf, Lr, Bf, Br, R, hg and half tracks [m]: Q29, +-4 */
#define RFE_FIX_Q_MASS 16    /**< mass m [kg]: Q16, +-32768 */
#define RFE_FIX_Q_INERTIA 12 /**< yaw inertia J [kg m^2]: Q12, +-524288 */
#define RFE_FIX_Q_STIFF 24   /**< stiffnesses Cx_n, Cy_n, cx, cy [1, 1/rad]: Q24, +-128 */
#define RFE_FIX_Q_EPS 32     /**< Dugoff eps [s/m]: Q32, +-0.5 */
#define RFE_FIX_Q_INV 38     /**< 1/m [1/kg], x/J, y/J [1/(kg m)]: Q38, +-2^-7 */
#define RFE_FIX_Q_KLOAD 20   /**< load-transfer coefficients [kg]: Q20, +-2048 */
#define RFE_FIX_Q_DT 30      /**< sample period dt [s]: Q30, +-2 */
#define RFE_FIX_Q_TAU 26     /**< time constant tau_v [s]: Q26, +-32 */
/** Fisher information info_min [1/mu^2]: Q10, +-2.1e6 (the SCKF's RFE_Q31_QI, sckf_q31.h) */
#define RFE_FIX_Q_INFO 10
/** The rear wheels' hold threshold rear_hold_k [sd]: Q24, +-128 */
#define RFE_FIX_Q_HOLD 24
/** The jump hold's distance jump_hold_len [m]: Q27, +-16 (the hold's distances, friction_q31.h) */
#define RFE_FIX_Q_HOLD_LEN 27
/** The bound margin valid_bound_k [sd]: Q24, +-128 (docs/ESTIMATOR.md step 9) */
#define RFE_FIX_Q_BOUND_K 24

/** Vehicle geometry and mass (MODEL.md §2) with the derived constants of the loads (§3) and
 *  of H (§5). Field names and meaning as rfe_vehicle_t. */
typedef struct {
    rfe_fix_t m;   /**< mass [kg], Q16 */
    rfe_fix_t Lf;  /**< CoG to front axle [m], Q29 */
    rfe_fix_t Lr;  /**< CoG to rear axle [m], Q29 */
    rfe_fix_t Bf;  /**< front track [m], Q29 */
    rfe_fix_t Br;  /**< rear track [m], Q29 */
    rfe_fix_t R;   /**< effective rolling radius [m], Q29 */
    rfe_fix_t J;   /**< yaw moment of inertia [kg m^2], Q12 */
    rfe_fix_t hg;  /**< CoG height [m], Q29 */
    rfe_fix_t g;   /**< gravity [m/s^2], Q24 */
    /* Derived (rfe_params_to_q31 computes them; rfe_params_validate_q31 checks them). */
    rfe_fix_t yf;          /**< Bf / 2, left-wheel y of the front axle [m], Q29 */
    rfe_fix_t yr;          /**< Br / 2 [m], Q29 */
    rfe_fix_t inv_m;       /**< 1 / m [1/kg], Q38 (m >= 128 kg) */
    rfe_fix_t lf_J;        /**< Lf / J [1/(kg m)], Q38 */
    rfe_fix_t lr_J;        /**< Lr / J [1/(kg m)], Q38 */
    rfe_fix_t yf_J;        /**< Bf / (2 J) [1/(kg m)], Q38 */
    rfe_fix_t yr_J;        /**< Br / (2 J) [1/(kg m)], Q38 */
    rfe_fix_t fz_static_f; /**< m g Lr / (2 La): static load of a front wheel [N], Q15 */
    rfe_fix_t fz_static_r; /**< m g Lf / (2 La): static load of a rear wheel [N], Q15 */
    rfe_fix_t k_pitch;     /**< m hg / (2 La): load per unit ax on each wheel [kg], Q20 */
    rfe_fix_t k_roll_f;    /**< m hg Lr / (La Bf): load per unit ay, front wheel [kg], Q20 */
    rfe_fix_t k_roll_r;    /**< m hg Lf / (La Br): load per unit ay, rear wheel [kg], Q20 */
} rfe_vehicle_q31_t;

/** Dugoff tyre and slip parameters (MODEL.md §3-4); fields as rfe_tyre_params_t. */
typedef struct {
    rfe_tyre_mode_t mode; /**< paper (normalised) or absolute (load-scaled) Dugoff, or magic */
    rfe_fix_t Cx_n;       /**< normalised longitudinal stiffness [1], Q24 */
    rfe_fix_t Cy_n;       /**< normalised cornering stiffness [1/rad], Q24 */
    rfe_fix_t cx;         /**< longitudinal stiffness per unit Fz [1], Q24 */
    rfe_fix_t cy;         /**< cornering stiffness per unit Fz [1/rad], Q24 */
    rfe_fix_t eps;        /**< Dugoff velocity-reduction factor [s/m], Q32 */
    rfe_fix_t v_min;      /**< slip denominator guard [m/s], Q23 */
    rfe_fix_t alpha_max;  /**< slip-angle bound [rad], Q29, < 1.5 rad */
    rfe_fix_t shape_Cx;   /**< Magic Formula shape factor C, longitudinal [1], Q24, 1 < C < 2 */
    rfe_fix_t shape_Ex;   /**< Magic Formula curvature factor E, longitudinal [1], Q24, -4 <= E < 1 */
    rfe_fix_t shape_Cy;   /**< Magic Formula shape factor C, lateral [1], Q24, 1 < C < 2 */
    rfe_fix_t shape_Ey;   /**< Magic Formula curvature factor E, lateral [1], Q24, -4 <= E < 1 */
} rfe_tyre_params_q31_t;

/** Filter tuning (MODEL.md §6, docs/ESTIMATOR.md); fields as rfe_filter_params_t. The
 *  input noise sds use the format of their signal. */
typedef struct {
    rfe_filter_kind_t kind;     /**< sckf | ckf */
    rfe_structure_t structure;  /**< wheels | sides */
    rfe_fix_t mu0;            /**< initial estimate, Q29 */
    rfe_fix_t sd0;            /**< prior sd, differential part, Q30 */
    rfe_fix_t q_mu;           /**< process-noise sd per step, differential part, Q30 */
    rfe_fix_t r_ax;           /**< ax measurement-noise sd [m/s^2], Q24 */
    rfe_fix_t r_ay;           /**< ay measurement-noise sd [m/s^2], Q24 */
    rfe_fix_t r_yaw_acc;      /**< yaw-acceleration noise sd [rad/s^2], Q24 */
    rfe_fix_t mu_min;         /**< lower projection bound, Q29 */
    rfe_fix_t mu_max;         /**< upper projection bound, Q29 */
    rfe_fix_t v_est_min;      /**< no measurement update below this vx [m/s], Q23 */
    rfe_fix_t sd0_common;     /**< prior sd, common-mode part, Q30 */
    rfe_fix_t q_common;       /**< process-noise sd per step, common-mode part, Q30 */
    rfe_fix_t dt;             /**< sample period of the input filter [s], Q30 (< 2 s) */
    rfe_fix_t tau_v;          /**< complementary-filter time constant [s], Q26 (< 32 s), 0 = off */
    rfe_fix_t sd_in_delta;    /**< input noise sd of delta [rad], Q29 */
    rfe_fix_t sd_in_vx;       /**< input noise sd of vx [m/s], Q23 */
    rfe_fix_t sd_in_vy;       /**< input noise sd of vy [m/s], Q23 */
    rfe_fix_t sd_in_yaw_rate; /**< input noise sd of r [rad/s], Q27 */
    rfe_fix_t sd_in_omega;    /**< input noise sd of each wheel speed [rad/s], Q22 */
    rfe_fix_t r_model_rel;    /**< tyre-model error relative to each acceleration, Q30 */
    rfe_fix_t info_min;       /**< minimum Fisher information [1/mu^2], Q10, 0 = off */
    rfe_fix_t sd_max;         /**< bound on every sd, Q30, 0 = off */
    rfe_fix_t sd_floor_rel;   /**< floor on sd as a fraction of mu, Q30, 0 = off */
    rfe_fix_t sd_valid;       /**< valid when sd <= sd_valid off the mu bounds, Q30, 0 = paper rule */
    rfe_fix_t rear_hold_k;    /**< the rear wheels' hold threshold [sd], Q24, 0 = off */
    rfe_fix_t jump_hold_k;    /**< the jump hold's threshold [sd], Q24, 0 = off */
    rfe_fix_t jump_hold_len;  /**< the distance a jump holds a side's wheels [m], Q27 */
    rfe_fix_t stale_omega;    /**< the stale-wheel-speed rule's move [rad/s], Q22, 0 = off */
    rfe_fix_t yaw_check;      /**< the yaw-rate input check's threshold [rad/s], Q27, 0 = off */
    rfe_fix_t valid_bound_k;  /**< the bound margin: valid only mu - mu_min >= this many sd [sd],
                                   Q24 (RFE_FIX_Q_BOUND_K), 0 = off, at most 10 */
    /* Derived. */
    rfe_fix_t b_v;            /**< dt / (tau_v + dt): complementary-filter gain, Q30, in (0, 1] */
} rfe_filter_params_q31_t;

/** Fractional bits of the monitor's normal quantiles z: Q24, +-128 (z <= 8 is used). */
#define RFE_FIX_Q_MON_Z 24
/** Fractional bits of the monitor's EWMA weights: Q30 (RFE_FIX_Q_SD), in (0, 1). */
#define RFE_FIX_Q_MON_L 30
/** The largest quantile the monitor's integer thresholds take: 8 in Q24 (z(1 - 6e-16)). */
#define RFE_FIX_MON_Z_MAX ((rfe_fix_t)134217728)

/** The model-validity monitor (docs/MONITOR.md §2) as the constants its integer code uses:
 *  rfe_params_to_q31 derives them from the keys mon_* (rfe_monitor_params_t) and dt exactly
 *  as rfe_monitor_init does in double, then rounds each once. The quantiles need the inverse
 *  normal distribution, which the integer library does not carry, so they are stored, not
 *  recomputed. Within the ranges below, each field is checked by rfe_params_validate_q31. */
typedef struct {
    uint32_t enable;       /**< key mon_enable: 1 acts on valid, status and sd (SCKF only); 0 off */
    uint32_t inflate;      /**< key mon_inflate: 1 multiplies the sd by sqrt(max(1, D / 3)) while fired */
    uint32_t hold_steps;   /**< ceil(mon_hold / dt): shortest time fired after the last exceedance [steps], < 2^31 */
    uint32_t warmup_steps; /**< ceil(mon_warmup / dt): evaluated steps that only count [steps], < 2^31 */
    rfe_fix_t l_d;         /**< dt / (mon_tau_nis + dt): weight of the NIS average, Q30, in [2^-14, 1) */
    rfe_fix_t l_m;         /**< dt / (mon_tau_mean + dt): weight of the means, Q30, in [2^-14, 1) */
    rfe_fix_t z_d_fire;    /**< z(1 - mon_p_fire / 2), Q24, in (z_d_clear, 8] */
    rfe_fix_t z_d_clear;   /**< z(1 - mon_p_clear / 2), Q24, > 0 */
    rfe_fix_t z_m_fire;    /**< z(1 - mon_p_fire / 12), Q24, in (z_m_clear, 8] */
    rfe_fix_t z_m_clear;   /**< z(1 - mon_p_clear / 12), Q24, > 0 */
} rfe_monitor_params_q31_t;

/** Everything the fixed-point friction estimator needs. */
typedef struct {
    rfe_vehicle_q31_t vehicle;
    rfe_tyre_params_q31_t tyre;
    rfe_filter_params_q31_t filter;
    rfe_monitor_params_q31_t monitor;
} rfe_params_q31_t;

/**
 * The default preset (rfe_params_default) in Q formats: an integer table, equal bit for bit to
 * rfe_params_to_q31_f64(rfe_params_default_f64).
 * @param[out] p  the parameters to fill.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_params_default_q31(rfe_params_q31_t *p);

/** The paper preset (rfe_params_paper) in Q formats, likewise.
 *  @param[out] p  the parameters to fill.
 *  @return RFE_OK; RFE_ERR_NULL. */
RFE_NODISCARD rfe_status_t rfe_params_paper_q31(rfe_params_q31_t *p);

/**
 * The checks of rfe_params_validate on the Q values (positive where physical, hg, eps >= 0,
 * 0 < alpha_max < 1.5 rad, 0 <= mu_min < mu_max, mu0 within them, the additions >= 0, the
 * CKF subset, enums in range), and:
 *  - every derived constant positive (k_pitch, k_roll_* >= 0: zero when hg = 0), b_v <= 1;
 *  - every derived constant within 2^-13 relative (+ 2 LSB) of its recomputation from the base
 *    fields (integer arithmetic, error below 2^-26 relative);
 *  - each nonzero base field that a derived constant uses (m, Lf, Lr, Bf, Br, J, hg, g, dt,
 *    tau_v) and each nonzero derived constant at least 2^16 LSB (16 significant bits), so that
 *    the rounding of the converter (<= 5 * 2^-17 relative: at most five base fields per
 *    constant) always passes the 2^-13 check;
 *  - the monitor's constants within the ranges of rfe_monitor_params_q31_t (enable and
 *    inflate 0 or 1, 0 < z_clear < z_fire <= 8 per test), and enable = 1 only with the SCKF.
 * @param[in] p  the parameters to check.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_params_validate_q31(const rfe_params_q31_t *p);

/**
 * Sets the vehicle mass of a fixed-point parameter set at run time (the twin of
 * rfe_params_set_mass), atomically. The constants that depend on the mass (inv_m,
 * fz_static_f, fz_static_r, k_pitch, k_roll_f, k_roll_r) are recomputed in integer arithmetic,
 * by the recomputation rfe_params_validate_q31 checks them against (30-bit mantissas, below
 * 2^-26 relative), rounded to their Q formats: they may differ by a few LSB from those
 * rfe_params_to_q31 rounds from double (both within the validation's 2^-13).
 * @param[in,out] p  a parameter set rfe_params_validate_q31 accepts.
 * @param[in]     m  the new mass [kg], Q16 (RFE_FIX_Q_MASS), > 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (@p p invalid, or a mass whose constants leave
 *         their formats or their 16 significant bits: then @p p is untouched).
 */
RFE_NODISCARD rfe_status_t rfe_params_set_mass_q31(rfe_params_q31_t *p, rfe_fix_t m);

/**
 * Sets the lateral tyre curve of a fixed-point parameter set at run time (the twin of
 * rfe_params_set_lateral_tyre), atomically. No constant derives from these fields: they are
 * set and the whole set validated.
 * @param[in,out] p            a parameter set rfe_params_validate_q31 accepts.
 * @param[in]     cy           cornering stiffness per unit load [1/rad], Q24 (RFE_FIX_Q_STIFF), > 0.
 * @param[in]     shape_Cy     the lateral shape C, Q24, 1 < C < 2.
 * @param[in]     shape_Ey     the lateral curvature E, Q24, -4 <= E < 1.
 * @param[in]     r_model_rel  the tyre-model error relative to each acceleration, Q30, >= 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (@p p, or @p p with these values, invalid: then
 *         @p p is untouched).
 */
RFE_NODISCARD rfe_status_t rfe_params_set_lateral_tyre_q31(rfe_params_q31_t *p, rfe_fix_t cy,
                                                           rfe_fix_t shape_Cy, rfe_fix_t shape_Ey,
                                                           rfe_fix_t r_model_rel);

/**
 * Checks the monitor's integer constants against the ranges of rfe_monitor_params_q31_t:
 * enable and inflate 0 or 1; hold_steps, warmup_steps < 2^31; each weight in [2^-14, 1);
 * per test 0 < z_clear < z_fire <= 8 (RFE_FIX_MON_Z_MAX). rfe_params_validate_q31 and
 * rfe_monitor_init_q31 both use it.
 * @param[in] mp  the monitor's constants.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_monitor_params_validate_q31(const rfe_monitor_params_q31_t *mp);

#endif /* RFE_PARAMS_Q31_H */
