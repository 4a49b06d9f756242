/**
 * @file tyre_id_params.h
 * @brief Parameters of the tyre identifier (docs/TYRE_ID.md §2), their defaults and their
 *        validation. The vehicle and the tyre data (the prior's centre) are the friction
 *        estimator's (rfe/params.h): one calibration serves both.
 */
#ifndef RFE_TYRE_ID_PARAMS_H
#define RFE_TYRE_ID_PARAMS_H

#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_tyre_id_params_default  rfe_tyre_id_params_default_f64
#define rfe_tyre_id_params_validate rfe_tyre_id_params_validate_f64
#else
#define rfe_tyre_id_params_default  rfe_tyre_id_params_default_f32
#define rfe_tyre_id_params_validate rfe_tyre_id_params_validate_f32
#endif

/** The filter (key tid_filter; TYRE_ID.md §5.2, §5.6, §15). */
typedef enum {
    RFE_TID_APF = 0, /**< apf: the auxiliary particle filter (the patent's) */
    RFE_TID_SIR = 1, /**< sir: the plain bootstrap filter (the baseline) */
    RFE_TID_SCKF = 2 /**< sckf: the augmented-state square-root cubature Kalman filter
                          (deterministic: the seed, resample, neff_frac, rough_k unused) */
} rfe_tid_filter_t;

/** How parents are drawn (key tid_resample; TYRE_ID.md §5.3). */
typedef enum {
    RFE_TID_MULTINOMIAL = 0, /**< multinomial: one uniform per parent (the patent's) */
    RFE_TID_SYSTEMATIC = 1   /**< systematic: one uniform, evenly spaced positions */
} rfe_tid_resample_t;

/** The identifier's parameters; each field is the parameter-file key tid_<field>. The
 *  particle count is RFE_TID_N (rfe/config.h) and the seed an argument of the init. */
typedef struct {
    rfe_tid_filter_t filter;     /**< apf */
    rfe_tid_resample_t resample; /**< multinomial */
    uint32_t substeps;           /**< RK4 steps per sample period, 1..RFE_TID_SUBSTEPS_MAX: 1 */
    rfe_real_t v_min;            /**< below this vx (this or the previous sample) the step
                                      holds [m/s], > 0: 5 */
    rfe_real_t dt_max;           /**< longest accepted sample period [s] (the C port's: a
                                      longer gap needs a new init), > 0: 0.1 */
    rfe_real_t sd_r;             /**< likelihood sd of the yaw rate [rad/s], > 0: 0.01 */
    rfe_real_t sd_ay;            /**< likelihood sd of ay [m/s^2], > 0: 0.2 */
    rfe_real_t sd_delta;         /**< steering-angle noise through each particle's front
                                      slope [rad], >= 0: 0.001 */
    rfe_real_t q_vy;             /**< process noise density of vy [m/s/sqrt(s)]: 0.02 */
    rfe_real_t q_r;              /**< process noise density of r [rad/s/sqrt(s)]: 0.01 */
    rfe_real_t q_mu;             /**< random walk of D/Fz0 [1/sqrt(s)]: 0.02 */
    rfe_real_t q_C;              /**< random walk of C [1/sqrt(s)]: 0.02 */
    rfe_real_t q_cy;             /**< random walk of K/Fz0 [1/rad/sqrt(s)]: 0.3 */
    rfe_real_t q_E;              /**< random walk of E [1/sqrt(s)]: 0.05 */
    rfe_real_t mu0;              /**< prior mean of D/Fz0 [1]: 0.7 */
    rfe_real_t sd0_mu;           /**< prior sd of D/Fz0 [1]: 0.3 */
    rfe_real_t sd0_C;            /**< prior sd of C (mean shape_Cy) [1]: 0.2 */
    rfe_real_t sd0_E;            /**< prior sd of E (mean shape_Ey) [1]: 0.5 */
    rfe_real_t sd0_cy_rel;       /**< prior sd of K/Fz0 relative to its mean cy [1]: 0.3 */
    rfe_real_t sd0_vy;           /**< prior sd of vy (mean 0) [m/s]: 0.2 */
    rfe_real_t sd0_r;            /**< prior sd of r (mean: the first yaw rate) [rad/s]: 0.01 */
    rfe_real_t mu_lo;            /**< bounds of D/Fz0, 0 < lo < hi: 0.1 */
    rfe_real_t mu_hi;            /**< 1.3 */
    rfe_real_t C_lo;             /**< bounds of C, 0 < lo < hi: 1.0 */
    rfe_real_t C_hi;             /**< 2.0 */
    rfe_real_t cy_lo;            /**< bounds of K/Fz0 [1/rad], 0 < lo < hi: 4 */
    rfe_real_t cy_hi;            /**< 40 */
    rfe_real_t E_lo;             /**< bounds of E, lo < hi: -3 */
    rfe_real_t E_hi;             /**< 0.95 */
    rfe_real_t neff_frac;        /**< resample when N_eff < neff_frac N, in [0, 1]: 1/3 */
    rfe_real_t rough_k;          /**< roughening constant K, >= 0: 0.2 */
    rfe_real_t ellipse;          /**< 1: each axle's lateral force under ax, its load and
                                      the friction ellipse (§3.5); 0: the lateral-only model
                                      of §3.3, bit for bit. 0 or 1: 0 */
    rfe_real_t fx_front;         /**< the front axle's share of m ax (§3.5: the brake
                                      balance), in [0, 1]: 0.625 */
    rfe_real_t ell_min;          /**< the smallest factor the ellipse leaves of a lateral
                                      force (§3.5), in (0, 1]: 0.1 */
    rfe_real_t ell_ax_min;       /**< the ellipse's dead band (§3.5): below this |ax| it
                                      takes ax as 0, the factor exactly 1 [m/s^2], in
                                      [0, 20] (0: none): 0.6 */
    rfe_real_t delta_q;          /**< the steering-angle filter (§4.4): white-acceleration
                                      noise density of a two-state Kalman filter that the
                                      identifier reads delta through [rad/s^2/sqrt(s)], >= 0
                                      (0: off, delta as measured, bit for bit): 0 */
    rfe_real_t delta_state_q;    /**< the sigma-point filter only (§15.7): delta as its
                                      eleventh state, a random walk of this density
                                      [rad/sqrt(s)] measured by the steering sensor (sd
                                      sd_delta), >= 0, not with delta_q > 0 (0: off, n = 10,
                                      bit for bit): 0 */
} rfe_tyre_id_params_t;

/**
 * The defaults of docs/TYRE_ID.md §2.
 * @param[out] p  the parameters to fill.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_tyre_id_params_default(rfe_tyre_id_params_t *p);

/**
 * Checks every field: finite; filter and resample in range; substeps in
 * 1..RFE_TID_SUBSTEPS_MAX; v_min, dt_max, sd_r, sd_ay > 0; sd_delta, every q and sd0,
 * rough_k, delta_q and delta_state_q >= 0, not both delta_q and delta_state_q > 0; neff_frac in [0, 1]; each pair of bounds lo < hi, and mu_lo, C_lo, cy_lo
 * > 0 (B = K / (C D) needs C, D > 0); ellipse 0 or 1, fx_front in [0, 1], ell_min in
 * (0, 1], ell_ax_min in [0, 20]. Whether the prior's means lie within the bounds
 * depends on the tyre data: rfe_tyre_id_init checks it.
 * @param[in] p  the parameters to check.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_tyre_id_params_validate(const rfe_tyre_id_params_t *p);

#endif /* RFE_TYRE_ID_PARAMS_H */
