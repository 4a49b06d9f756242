/**
 * @file params.h
 * @brief Run-time parameters: vehicle, tyre, filter (MODEL.md §2, DATA.md parameter keys).
 *
 * Nothing in the algorithms is a literal: every number comes from these structs. Vehicle and
 * tyre values are the MODEL.md §2 values in both presets; each field names its DATA.md key.
 */
#ifndef RFE_PARAMS_H
#define RFE_PARAMS_H

#include "rfe/modes.h"
#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_params_default  rfe_params_default_f64
#define rfe_params_paper    rfe_params_paper_f64
#define rfe_params_validate rfe_params_validate_f64
#define rfe_params_set_mass rfe_params_set_mass_f64
#define rfe_params_set_lateral_tyre rfe_params_set_lateral_tyre_f64
#define rfe_monitor_params_validate rfe_monitor_params_validate_f64
#define rfe_monitor_consts  rfe_monitor_consts_f64
#define rfe_normal_quantile rfe_normal_quantile_f64
#else
#define rfe_params_default  rfe_params_default_f32
#define rfe_params_paper    rfe_params_paper_f32
#define rfe_params_validate rfe_params_validate_f32
#define rfe_params_set_mass rfe_params_set_mass_f32
#define rfe_params_set_lateral_tyre rfe_params_set_lateral_tyre_f32
#define rfe_monitor_params_validate rfe_monitor_params_validate_f32
#define rfe_monitor_consts  rfe_monitor_consts_f32
#define rfe_normal_quantile rfe_normal_quantile_f32
#endif

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

/** Dugoff tyre and slip-computation parameters (MODEL.md §3-4). */
typedef struct {
    rfe_tyre_mode_t mode; /**< key tyre (paper|absolute|magic): paper / magic (preset paper / default) */
    rfe_real_t Cx_n;      /**< key Cx_n: normalised longitudinal stiffness [1], default 20 */
    rfe_real_t Cy_n;      /**< key Cy_n: normalised cornering stiffness [1/rad], default 15 */
    rfe_real_t cx;        /**< key cx: longitudinal stiffness per unit Fz, absolute mode, default 20 */
    rfe_real_t cy;        /**< key cy: cornering stiffness per unit Fz, absolute mode [1/rad], default 15 */
    rfe_real_t eps;       /**< key eps: Dugoff velocity-reduction factor [s/m], default 0.015 */
    rfe_real_t v_min;     /**< key v_min: slip denominator guard [m/s], default 0.5 */
    rfe_real_t alpha_max; /**< key alpha_max: slip-angle bound [rad], default 1.4, must be < pi/2 */
    rfe_real_t shape_Cx;  /**< key shape_Cx: Magic Formula shape factor C, longitudinal, 1 < C < 2, default 1.65 */
    rfe_real_t shape_Ex;  /**< key shape_Ex: Magic Formula curvature factor E, longitudinal, -4 <= E < 1, default 0 */
    rfe_real_t shape_Cy;  /**< key shape_Cy: Magic Formula shape factor C, lateral, 1 < C < 2, default 1.3 */
    rfe_real_t shape_Ey;  /**< key shape_Ey: Magic Formula curvature factor E, lateral, -4 <= E < 1, default 0 */
} rfe_tyre_params_t;

/**
 * Filter tuning (MODEL.md §6, docs/ESTIMATOR.md). Each field names its DATA.md key and its
 * value in the two presets as "paper / default" (rfe_params_paper / rfe_params_default);
 * one value means both. A 0 in the paper column switches the addition off.
 */
typedef struct {
    rfe_filter_kind_t kind; /**< key filter (sckf|ckf): sckf */
    rfe_structure_t structure; /**< key structure (wheels|sides): wheels / sides */
    rfe_real_t mu0;       /**< key mu0: initial estimate on every state: 0.5 */
    rfe_real_t sd0;       /**< key sd0: prior sd, differential (per-state) part: 0.3 / 0.1 */
    rfe_real_t q_mu;      /**< key q_mu: process-noise sd per step, differential part: 0.003 / 0.002 */
    rfe_real_t r_ax;      /**< key r_ax: ax measurement-noise sd [m/s^2]: 0.05 */
    rfe_real_t r_ay;      /**< key r_ay: ay measurement-noise sd [m/s^2]: 0.05 */
    rfe_real_t r_yaw_acc; /**< key r_yaw_acc: yaw-acceleration noise sd [rad/s^2]: 0.05 */
    rfe_real_t mu_min;    /**< key mu_min: lower projection bound: 0.05 */
    rfe_real_t mu_max;    /**< key mu_max: upper projection bound: 1.2 */
    rfe_real_t v_est_min; /**< key v_est_min: below this vx no measurement update [m/s]: 3.0 */
    /* docs/ESTIMATOR.md additions (0 = off). The prior is S0 = sqrt_prior(sd0, sd0_common),
     * the process noise S_Q = sqrt_prior(q_mu, q_common): the lower Cholesky factor of
     * common^2 11^T + diff^2 I, exactly diff I when common = 0. */
    rfe_real_t sd0_common;   /**< key sd0_common: prior sd, common-mode part: 0 / 0.3 */
    rfe_real_t q_common;     /**< key q_common: process-noise sd per step, common-mode part: 0 / 0.006 */
    rfe_real_t dt;           /**< key dt: sample period of the input filter [s]: 0.01 */
    rfe_real_t tau_v;        /**< key tau_v: complementary-filter time constant for vx, vy [s], 0 = off: 0 / 0.3 */
    rfe_real_t sd_in_delta;  /**< key sd_in_delta: input noise sd of delta [rad]: 0 / 0.001 */
    rfe_real_t sd_in_vx;     /**< key sd_in_vx: input noise sd of the (filtered) vx [m/s]: 0 / 0.01 */
    rfe_real_t sd_in_vy;     /**< key sd_in_vy: input noise sd of the (filtered) vy [m/s]: 0 / 0.01 */
    rfe_real_t sd_in_yaw_rate; /**< key sd_in_yaw_rate: input noise sd of r [rad/s]: 0 / 0.005 */
    rfe_real_t sd_in_omega;  /**< key sd_in_omega: input noise sd of each wheel speed [rad/s]: 0 / 0.05 */
    rfe_real_t r_model_rel;  /**< key r_model_rel: tyre-model error relative to each predicted acceleration: 0 / 0.05 */
    rfe_real_t info_min;     /**< key info_min: a step updates only with at least this Fisher information [1/mu^2], 0 = off: 0 / 25 */
    rfe_real_t sd_max;       /**< key sd_max: bound on every sd, 0 = off: 0 / 0.32 */
    rfe_real_t sd_floor_rel; /**< key sd_floor_rel: floor on sd_k as a fraction of mu_k, 0 = off: 0 / 0.15 */
    rfe_real_t sd_valid;     /**< key sd_valid: valid when sd <= sd_valid, off the mu bounds; 0 = the paper rule (valid when updated): 0 / 0.15 */
    rfe_real_t rear_hold_k;  /**< key rear_hold_k: structure sides: a move of a side's estimate by more than this many sd from its value one wheelbase back holds its rear wheels not valid for one wheelbase [1], 0 = off: 0 / 2 */
    rfe_real_t jump_hold_k;  /**< key jump_hold_k: structure sides: a step that moves a side's estimate by more than this many (new) sd holds both its wheels not valid for jump_hold_len of travel [1], 0 = off: 0 / 2 */
    rfe_real_t jump_hold_len; /**< key jump_hold_len: the distance a jump holds a side's wheels [m], below 16: 0 / 1.5 */
    rfe_real_t stale_omega;  /**< key stale_omega: the stale-wheel-speed rule (step 9): while a wheel speed, not 0, equals its previous sample and the median of the other three moved by more than this since it last changed, every valid flag is 0 [rad/s], 0 = off, at most 500: 0 / 0.25 */
    rfe_real_t yaw_check;    /**< key yaw_check: the yaw-rate input check (step 0b): a yaw rate further than this from the last accepted one advanced by the measured yaw acceleration is replaced by that prediction [rad/s], 0 = off, at most 10: 0 / 0.1 */
    rfe_real_t valid_bound_k; /**< key valid_bound_k: the bound margin (step 9, with the sd rule): a wheel is valid only when its estimate lies at least this many sd above mu_min [1], 0 = off (today's rule), at most 10: 0 / 3 */
} rfe_filter_params_t;

/**
 * The model-validity monitor (docs/MONITOR.md §2, rfe/component/monitor.h): a windowed test of
 * the innovations against the covariance the filter claims; while it is fired every valid flag
 * is 0, the status is RFE_MODEL_MISMATCH and the reported sd is inflated. Values as
 * "paper / default"; the default preset keeps it off until the fixed-point twin has it too.
 */
typedef struct {
    rfe_real_t enable;   /**< key mon_enable: 1 acts on valid, status and sd (SCKF only); 0 off: 0 / 0 */
    rfe_real_t tau_nis;  /**< key mon_tau_nis: time constant of the NIS average [s]: 0.5 */
    rfe_real_t tau_mean; /**< key mon_tau_mean: time constant of the innovation means [s]: 0.5 */
    rfe_real_t p_fire;   /**< key mon_p_fire: per-step probability, under the model, of exceeding a fire threshold: 1e-3 */
    rfe_real_t p_clear;  /**< key mon_p_clear: the same for the clear thresholds (p_fire < p_clear < 1): 0.1 */
    rfe_real_t hold;     /**< key mon_hold: shortest time fired after the last exceedance [s]: 0.5 */
    rfe_real_t warmup;   /**< key mon_warmup: evaluated steps at the start that only count [s]: 1 */
    rfe_real_t inflate;  /**< key mon_inflate: 1: sd x sqrt(max(1, D / 3)) while fired; 0: sd untouched: 1 */
} rfe_monitor_params_t;

/**
 * Everything the friction estimator needs.
 *
 * Padding: the enums' size is the ABI's, so the struct has padding bytes on some targets (4
 * after tyre.mode in the double build on x86-64; 3 after tyre.mode and 2 after
 * filter.structure on arm-none-eabi, whose enums are 1 byte; none in the float build on
 * x86-64). The presets fill the fields only, and rfe_friction_init copies the whole struct
 * into the estimator's state: a caller who compares or checksums whole states or parameter
 * sets (memcmp, a CRC) must zero the struct (memset) before filling it. No spare field removes
 * the padding on every ABI without changing the firmware's layouts (docs/PORTABILITY.md).
 */
typedef struct {
    rfe_vehicle_t vehicle;
    rfe_tyre_params_t tyre;
    rfe_filter_params_t filter;
    rfe_monitor_params_t monitor;
} rfe_params_t;

/**
 * Fills @p p with the library's default configuration: the observability-aware estimator of
 * docs/ESTIMATOR.md ("default preset" column: sides, absolute tyre, common-mode prior and
 * process noise, input filter, errors in variables, information gate, sd bounds, validity
 * by sd).
 * @param[out] p  the parameters to fill.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_params_default(rfe_params_t *p);

/**
 * Fills @p p with the paper configuration (MODEL.md §2, §6; docs/ESTIMATOR.md "paper
 * preset" column): four independent mu, normalised tyre, x0 = 0.5, S0 = 0.3 I,
 * S_Q = 0.003 I, S_R = 0.05 I, every addition off. Kept as the reference baseline.
 * @param[out] p  the parameters to fill.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_params_paper(rfe_params_t *p);

/**
 * Checks every field: finite; positive where physical (m, L, B, R, J, g, stiffnesses,
 * sd0, q_mu, r_*, dt); hg >= 0, eps >= 0, 0 < alpha_max < 1.5, 0 <= mu_min < mu_max, mu0
 * within [mu_min, mu_max], v_est_min >= 0; sd0_common, q_common, tau_v, sd_in_*,
 * r_model_rel, info_min, sd_max, sd_floor_rel, sd_valid >= 0 (sd_max: 0 = off, else any
 * positive bound); enums in range.
 * The CKF (the paper's baseline) runs only the paper-compatible subset: with filter = ckf,
 * structure must be wheels and sd0_common, q_common, tau_v, every sd_in_*, r_model_rel,
 * info_min, sd_max and sd_floor_rel must be 0 (any tyre, any sd_valid, any dt), and the
 * monitor off (mon_enable = 0). The monitor's parameters: rfe_monitor_params_validate at dt.
 * @param[in] p  the parameters to check.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_params_validate(const rfe_params_t *p);

/**
 * Sets the vehicle mass of a parameter set at run time (issue 19: the mass and grade
 * estimator's mass), atomically: the set is changed only when it stays valid.
 * @param[in,out] p  a parameter set rfe_params_validate accepts.
 * @param[in]     m  the new mass [kg], finite and > 0.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (@p p, or @p p with mass @p m, invalid: then
 *         @p p is untouched).
 */
RFE_NODISCARD rfe_status_t rfe_params_set_mass(rfe_params_t *p, rfe_real_t m);

/**
 * Sets the lateral tyre curve of a parameter set at run time (issue 20: the tyre identifier's
 * cornering stiffness and shape, docs/TYRE_ID.md §14), atomically: the set is changed only
 * when it stays valid.
 * @param[in,out] p            a parameter set rfe_params_validate accepts.
 * @param[in]     cy           cornering stiffness per unit load [1/rad] (key cy), > 0.
 * @param[in]     shape_Cy     the lateral Magic Formula's shape C (key shape_Cy), 1 < C < 2.
 * @param[in]     shape_Ey     its curvature E (key shape_Ey), -4 <= E < 1.
 * @param[in]     r_model_rel  the tyre-model error relative to each predicted acceleration
 *                             (key r_model_rel), >= 0: where the curve's uncertainty goes.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (@p p, or @p p with these values, invalid: then
 *         @p p is untouched).
 */
RFE_NODISCARD rfe_status_t rfe_params_set_lateral_tyre(rfe_params_t *p, rfe_real_t cy,
                                                       rfe_real_t shape_Cy, rfe_real_t shape_Ey,
                                                       rfe_real_t r_model_rel);

/**
 * Checks the monitor's parameters at sample period @p dt (finite, > 0): enable and inflate
 * 0 or 1; tau_nis, tau_mean finite and > 0; 0 < p_fire < p_clear < 1; hold, warmup finite,
 * >= 0 and shorter than 2^31 periods. rfe_params_validate and rfe_monitor_init both use it.
 * @param[in] mp  the monitor's parameters.
 * @param[in] dt  the sample period [s].
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_monitor_params_validate(const rfe_monitor_params_t *mp,
                                                      rfe_real_t dt);

/** The monitor's constants at a sample period (rfe_monitor_consts): what its statistics use
 *  of the parameters, in every number type (the fixed-point ones are these, rounded). */
typedef struct {
    uint32_t hold_steps;   /**< ceil(hold / dt) */
    uint32_t warmup_steps; /**< ceil(warmup / dt) */
    rfe_real_t l_d;        /**< EWMA weight of D, dt / (tau_nis + dt) */
    rfe_real_t l_m;        /**< EWMA weight of M and C, dt / (tau_mean + dt) */
    rfe_real_t z_d_fire;   /**< z(1 - p_fire / 2): the NIS test's normal quantile */
    rfe_real_t z_d_clear;  /**< z(1 - p_clear / 2) */
    rfe_real_t z_m_fire;   /**< z(1 - p_fire / (4 m)): each channel's two-sided test */
    rfe_real_t z_m_clear;  /**< z(1 - p_clear / (4 m)) */
} rfe_monitor_consts_t;

/**
 * The monitor's constants from its parameters at sample period @p dt (docs/MONITOR.md §2):
 * the weights, the normal quantiles (rfe_normal_quantile) and the step counts (a duration
 * within 1e-6 relative of a whole number of periods is that number). rfe_monitor_init and
 * rfe_params_to_q31 both use it.
 * @param[in]  mp   as rfe_monitor_params_validate accepts at @p dt
 * @param[out] out  written only on RFE_OK
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (a parameter or dt invalid, or a probability
 *         so small that 1 - p rounds to 1 in the real type).
 */
RFE_NODISCARD rfe_status_t rfe_monitor_consts(const rfe_monitor_params_t *mp, rfe_real_t dt,
                                             rfe_monitor_consts_t *out);

/**
 * The standard-normal quantile z(q), 0 < q < 1 (Acklam's rational approximation: relative
 * error below 1.2e-9 in double; the float build's rounding above that).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_RANGE (q not in (0, 1), or not finite).
 */
RFE_NODISCARD rfe_status_t rfe_normal_quantile(rfe_real_t q, rfe_real_t *z);

#endif /* RFE_PARAMS_H */
