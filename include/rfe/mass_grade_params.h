/**
 * @file mass_grade_params.h
 * @brief Parameters of the mass and road-grade estimator (docs/MASS_GRADE.md §6), their
 *        presets and their validation. Each field is the parameter-file key mg_<field>
 *        (R and g: the vehicle keys of DATA.md).
 */
#ifndef RFE_MASS_GRADE_PARAMS_H
#define RFE_MASS_GRADE_PARAMS_H

#include "rfe/mass_grade_bits.h"
#include "rfe/types.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_mass_grade_params_default  rfe_mass_grade_params_default_f64
#define rfe_mass_grade_params_preset   rfe_mass_grade_params_preset_f64
#define rfe_mass_grade_params_validate rfe_mass_grade_params_validate_f64
#else
#define rfe_mass_grade_params_default  rfe_mass_grade_params_default_f32
#define rfe_mass_grade_params_preset   rfe_mass_grade_params_preset_f32
#define rfe_mass_grade_params_validate rfe_mass_grade_params_validate_f32
#endif

/** The estimator's parameters; after each the car's value of the recommended preset. */
typedef struct {
    rfe_real_t R;          /**< rolling radius r [m]: 0.325 */
    rfe_real_t g;          /**< gravity [m/s^2]: 9.81 */
    rfe_real_t fc;         /**< rolling resistance, constant part f_c [1]: 0.010 */
    rfe_real_t fr;         /**< rolling resistance, speed part f_r [s/m]: 0.00015 */
    rfe_real_t rho;        /**< air density [kg/m^3]: 1.2 */
    rfe_real_t cd;         /**< drag coefficient C_d [1]: 0.30 */
    rfe_real_t area;       /**< frontal area S [m^2]: 2.2 */
    rfe_real_t m_rot;      /**< equivalent mass of the parts the drive torque spins up [kg]:
                                45.4 (0 in the seed's model) */
    rfe_real_t m0;         /**< initial mass [kg]: 1830 */
    rfe_real_t theta0;     /**< initial grade [rad], uphill positive: 0 */
    rfe_real_t sd_m0;      /**< initial sd of the mass [kg]: 500 */
    rfe_real_t sd_theta0;  /**< initial sd of the grade [rad]: 0.05 */
    rfe_real_t q_v;        /**< process noise density of v [m/s/sqrt(s)]: 0.02 */
    rfe_real_t q_mc;       /**< constant part of the mass process noise [kg/sqrt(s)]: 1 */
    rfe_real_t q_mv0;      /**< initial adaptive part, q_mv = q_mv0^2 at a start
                                [kg/sqrt(s)]: 300 */
    rfe_real_t q_theta;    /**< process noise density of the grade [rad/sqrt(s)]: 0.004 */
    rfe_real_t r_v;        /**< speed measurement noise sd [m/s]: 0.05 */
    rfe_real_t r_ax;       /**< accelerometer row noise sd, sensor and model [m/s^2]: 0.1 */
    rfe_real_t ut_alpha;   /**< unscented transform spread alpha [1]: 1 */
    rfe_real_t ut_beta;    /**< unscented transform prior parameter beta [1]: 2 */
    rfe_real_t ut_kappa;   /**< unscented transform secondary scaling kappa [1]: 0 */
    uint32_t adaptive;     /**< 1: the seed's AUKF (adaptive mass noise, §4.4); 0: plain
                                UKF: 0 */
    uint32_t use_ax;       /**< 1: the accelerometer row (§5; every sample must carry ax);
                                0: speed only, the seed's: 1 */
    rfe_real_t t_adapt;    /**< adaptation period [s] (0: every step): 1 */
    rfe_real_t mv_stop;    /**< the adaptation ends at q_mv <= mv_stop q_mc^2 [1]: 0.001 */
    rfe_real_t v_min;      /**< below this speed the filter holds [m/s]: 3 */
    rfe_real_t t_brake;    /**< hold after the last braked sample [s]: 1 */
    rfe_real_t t_shift;    /**< hold after a gear change [s]: 1 */
    rfe_real_t p_brake_on; /**< brake pressure that means braking [Pa]: 1e5 */
    rfe_real_t slip_max;   /**< the wheels' speed v departing from a given ground speed vx
                                by more than slip_max max(|vx|, v_min) holds the filter
                                (§4.2) [1]; 0: no slip pause: 0.05 */
    rfe_real_t ay_max;     /**< a given |ay| above ay_max holds the filter (§4.2, the curve
                                pause) [m/s^2]; 0: no curve pause: 0 */
    rfe_real_t t_curve;    /**< hold after the last sample over ay_max [s]: 1 */
    rfe_real_t m_min;      /**< lower mass bound [kg]: 300 */
    rfe_real_t m_max;      /**< upper mass bound [kg]: 60000 */
    rfe_real_t theta_max;  /**< grade bound |theta| [rad]: 0.35 */
    rfe_real_t dt_max;     /**< a longer sample period restarts the filter [s]: 1 */
    rfe_real_t pause_grade; /**< the pauses during which the grade keeps being learned from
                                 ax while M is held (§4.2; inert without use_ax), a sum of 1 brake,
                                 2 gear shift, 4 curve, an integer in 0..7 [-]; 0: none: 1
                                 (the brake; 0 in the seed's preset) */
    rfe_real_t pause_grade_slip; /**< the ABS gate of pause_grade (§4.2): a paused sample
                                      whose wheels' speed v departs from a given ground speed
                                      vx by more than pause_grade_slip max(|vx|, v_min) ends
                                      the grade's learning until the pause ends (the rest of
                                      it holds) [1], in [0, 1]; 0: no gate: 0.05 */
    rfe_real_t pause_grade_dv; /**< the change test of pause_grade (§4.2): a pause learns the
                                    grade only once the speed (vx if given, else v) has left
                                    the held grade's prediction, the sum over the pause of
                                    du - dt (ax - g sin theta), by more than pause_grade_dv;
                                    held grades that ax and the speed confirm stay untouched
                                    [m/s], in [0, 10]; 0: no test (learn at once): 0.2 */
    rfe_real_t q_theta_hi; /**< the grade's looser walk while the grade moves (§4.7, the
                                two-level walk) [rad/sqrt(s)]: 0 (off: q_theta always) or in
                                [q_theta, 0.1]: 0 */
    rfe_real_t theta_rate_on;  /**< the grade rate's RMS above which the walk loosens (§4.7)
                                    [rad/s], in (0, 0.1], >= theta_rate_off: 0.002 */
    rfe_real_t theta_rate_off; /**< ... below which it tightens again [rad/s], > 0: 0.001 */
    rfe_real_t theta_rate_tau; /**< the grade rate's low-pass time constant (§4.7) [s], in
                                    [dt_max, 60]: 1 */
    rfe_real_t theta_rate_avg; /**< the time constant of the mean of its square (§4.7) [s],
                                    in [dt_max, 60]: 3 */
    rfe_real_t mm_tau; /**< the model-mismatch monitor's time constant (§4.8) [s], in
                            [dt_max, 60]: 10 */
    rfe_real_t mm_e;   /**< its threshold on the EMA of the ax row's normalised innovation
                            (§4.8) [1], in [0, 100] (0: never flagged): 0.3 */
} rfe_mass_grade_params_t;

/**
 * The recommended preset for the passenger car: rfe_mass_grade_params_preset(p, RFE_MG_CAR,
 * RFE_MG_RECOMMENDED).
 * @param[out] p  the parameters to fill.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_params_default(rfe_mass_grade_params_t *p);

/**
 * A preset: the vehicle's values (MASS_GRADE.md §6, columns car and truck) with the
 * configuration's (§6 "Presets": recommended, or the seed's).
 * @param[out] p        the parameters to fill (untouched on error).
 * @param[in]  vehicle  RFE_MG_CAR or RFE_MG_TRUCK.
 * @param[in]  config   RFE_MG_RECOMMENDED or RFE_MG_SEED.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (an unknown vehicle or configuration).
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_params_preset(rfe_mass_grade_params_t *p,
                                                        rfe_mg_vehicle_t vehicle,
                                                        rfe_mg_config_t config);

/**
 * Checks every field (MASS_GRADE.md §6 "Validation"): finite; R, g, m0, sd_m0, sd_theta0,
 * q_v, q_mc, q_theta, r_v, r_ax, ut_alpha, m_min, theta_max, dt_max > 0; the resistance
 * and drag values, m_rot, q_mv0, t_adapt, mv_stop, the pause values (slip_max, ay_max,
 * t_curve too) and
 * ut_beta >= 0;
 * adaptive, use_ax in {0, 1}; pause_grade an integer in 0..7 (inert without use_ax);
 * 0 <= pause_grade_slip <= 1; 0 <= pause_grade_dv <= 10; m_min < m0 < m_max; |theta0| < theta_max < 1.5;
 * q_theta_hi 0 or in [q_theta, 0.1]; 0 < theta_rate_off <= theta_rate_on <= 0.1;
 * theta_rate_tau, theta_rate_avg in [dt_max, 60] (§4.7); mm_tau in [dt_max, 60],
 * 0 <= mm_e <= 100 (§4.8);
 * n + lambda > 0; with adaptive, mv_stop q_mc^2 < q_mv0^2.
 * @param[in] p  the parameters to check.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_params_validate(const rfe_mass_grade_params_t *p);

#endif /* RFE_MASS_GRADE_PARAMS_H */
