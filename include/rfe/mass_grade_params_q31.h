/**
 * @file mass_grade_params_q31.h
 * @brief Fixed-point twin of rfe/mass_grade_params.h: the mass and grade estimator's
 *        parameters as int32 Q values (docs/MASS_GRADE.md §6, docs/FIXED_POINT.md "Mass and
 *        grade"), and their validation on the Q values.
 *
 * Each field states its Q format (the RFE_MG_Q_* below). The host converts a real parameter
 * set with rfe_mass_grade_params_to_q31_f32/_f64 (rfe/component/params_conv.h), which checks
 * every value against its format.
 */
#ifndef RFE_MASS_GRADE_PARAMS_Q31_H
#define RFE_MASS_GRADE_PARAMS_Q31_H

#include <stdint.h>

#include "rfe/common.h"
#include "rfe/fixed.h"
#include "rfe/mass_grade_bits.h"

/* Q formats (fractional bits) of the mass and grade estimator (FIXED_POINT.md "Mass and
 * grade": each range from MASS_GRADE.md §1 and §6). */
#define RFE_MG_Q_V 24        /**< speed v, its sd, r_v, q_v, v_min [m/s]; ax, r_ax, v-dot
                                  [m/s^2]: Q24, +-128 (|v| <= 100 m/s, |ax| <= 50 m/s^2) */
#define RFE_MG_Q_M 14        /**< mass M, its sd, m0, sd_m0, m_rot, m_min, m_max, q_mc, q_mv0
                                  [kg, kg/sqrt(s)]: Q14, +-131072 kg */
#define RFE_MG_Q_TH 29       /**< grade theta, its sd, theta0, sd_theta0, q_theta,
                                  theta_max [rad]: Q29, +-4 */
#define RFE_MG_Q_DT 30       /**< sample period dt, dt_max [s]: Q30, +-2 s */
#define RFE_MG_Q_TIME 24     /**< t_brake, t_shift, t_adapt [s]: Q24, +-128 s */
#define RFE_MG_Q_TORQUE 14   /**< drive torque at the wheels [N m]: Q14, +-131072 (limit 1e5) */
#define RFE_MG_Q_PRESSURE 25 /**< brake pressure [MPa] (the observer's format): Q25, +-64 */
#define RFE_MG_Q_QMV 28      /**< q_mv [kg^2/s], int64: Q28 (the square of Q14) */
#define RFE_MG_Q_R 28        /**< rolling radius R [m]: Q28, +-8 */
#define RFE_MG_Q_G 26        /**< gravity g [m/s^2]: Q26, +-32 */
#define RFE_MG_Q_FC 30       /**< rolling resistance f_c, slip_max, pause_grade_slip [1]:
                                  Q30, +-2 */
#define RFE_MG_Q_FR 36       /**< rolling resistance f_r [s/m]: Q36, +-0.031 */
#define RFE_MG_Q_COEF 24     /**< rho [kg/m^3], C_d, S [m^2], mv_stop [1]: Q24, +-128 */
#define RFE_MG_Q_UT 28       /**< ut_alpha, ut_beta, ut_kappa [1]: Q28, +-8 */
#define RFE_MG_Q_RATE 30     /**< §4.7 the grade rate: theta_rate_on/off, the low-passed
                                  rate r [rad/s] and its mean square s [rad^2/s^2], compared
                                  with on^2, off^2 (Q30 products): Q30, +-2 (on, off <= 0.1;
                                  r, s saturate beyond, where s > on^2 long before) */
#define RFE_MG_Q_E 24        /**< §4.8 the ax row's normalised innovation, its EMA and mm_e
                                  [1]: Q24, +-128 (mm_e <= 100) */

/** The estimator's parameters; fields and meaning as rfe_mass_grade_params_t. */
typedef struct {
    rfe_fix_t R;          /**< rolling radius [m], Q28 */
    rfe_fix_t g;          /**< gravity [m/s^2], Q26 */
    rfe_fix_t fc;         /**< rolling resistance f_c [1], Q30 */
    rfe_fix_t fr;         /**< rolling resistance f_r [s/m], Q36 */
    rfe_fix_t rho;        /**< air density [kg/m^3], Q24 */
    rfe_fix_t cd;         /**< drag coefficient [1], Q24 */
    rfe_fix_t area;       /**< frontal area [m^2], Q24 */
    rfe_fix_t m_rot;      /**< rotating mass [kg], Q14 */
    rfe_fix_t m0;         /**< initial mass [kg], Q14 */
    rfe_fix_t theta0;     /**< initial grade [rad], Q29 */
    rfe_fix_t sd_m0;      /**< initial sd of the mass [kg], Q14 */
    rfe_fix_t sd_theta0;  /**< initial sd of the grade [rad], Q29 */
    rfe_fix_t q_v;        /**< process noise density of v [m/s/sqrt(s)], Q24 */
    rfe_fix_t q_mc;       /**< constant mass process noise [kg/sqrt(s)], Q14 */
    rfe_fix_t q_mv0;      /**< initial adaptive part [kg/sqrt(s)], Q14 */
    rfe_fix_t q_theta;    /**< process noise density of the grade [rad/sqrt(s)], Q29 */
    rfe_fix_t r_v;        /**< speed noise sd [m/s], Q24 */
    rfe_fix_t r_ax;       /**< accelerometer row noise sd [m/s^2], Q24 */
    rfe_fix_t ut_alpha;   /**< unscented transform alpha [1], Q28 */
    rfe_fix_t ut_beta;    /**< unscented transform beta [1], Q28 */
    rfe_fix_t ut_kappa;   /**< unscented transform kappa [1], Q28 */
    uint32_t adaptive;    /**< 1: AUKF; 0: plain UKF */
    uint32_t use_ax;      /**< 1: the accelerometer row; 0: speed only */
    rfe_fix_t t_adapt;    /**< adaptation period [s], Q24 */
    rfe_fix_t mv_stop;    /**< the adaptation ends at q_mv <= mv_stop q_mc^2 [1], Q24 */
    rfe_fix_t v_min;      /**< below this speed the filter holds [m/s], Q24 */
    rfe_fix_t t_brake;    /**< hold after the last braked sample [s], Q24 */
    rfe_fix_t t_shift;    /**< hold after a gear change [s], Q24 */
    rfe_fix_t p_brake_on; /**< brake pressure that means braking [MPa], Q25 */
    rfe_fix_t slip_max;   /**< slip that holds the filter [1], Q30 (0: no slip pause) */
    rfe_fix_t ay_max;     /**< |ay| that holds the filter [m/s^2], Q24 (0: no curve pause) */
    rfe_fix_t t_curve;    /**< hold after the last sample over ay_max [s], Q24 */
    rfe_fix_t m_min;      /**< lower mass bound [kg], Q14 */
    rfe_fix_t m_max;      /**< upper mass bound [kg], Q14 */
    rfe_fix_t theta_max;  /**< grade bound [rad], Q29 */
    rfe_fix_t dt_max;     /**< a longer period restarts the filter [s], Q30 */
    uint32_t pause_grade; /**< the pauses that learn the grade from ax: 1 brake, 2 shift,
                               4 curve (0..7; inert without use_ax) */
    rfe_fix_t pause_grade_slip; /**< the ABS gate's slip [1], Q30, in [0, 1] (0: no gate) */
    rfe_fix_t pause_grade_dv;   /**< the change test's speed [m/s], Q24, in [0, 10] (0: no
                                     test) */
    rfe_fix_t q_theta_hi;     /**< the grade's looser walk [rad/sqrt(s)], Q29 (0: off) */
    rfe_fix_t theta_rate_on;  /**< the rate RMS that loosens the walk [rad/s], Q30 */
    rfe_fix_t theta_rate_off; /**< ... that tightens it [rad/s], Q30 */
    rfe_fix_t theta_rate_tau; /**< the rate's low-pass time constant [s], Q24, in [dt_max, 60]:
                                   dt/tau <= 1 fits Q30 */
    rfe_fix_t theta_rate_avg; /**< its mean square's time constant [s], Q24, in [dt_max, 60] */
    rfe_fix_t mm_tau;         /**< §4.8 the mismatch monitor's time constant [s], Q24, in
                                   [dt_max, 60]: dt/tau <= 1 fits Q30 */
    rfe_fix_t mm_e;           /**< §4.8 its threshold [1], Q24, in [0, 100] (0: never) */
} rfe_mass_grade_params_q31_t;

/** The unscented transform's weights (MASS_GRADE.md §3) in the forms the square-root filter
 *  uses. */
typedef struct {
    rfe_fix_t wm0;      /**< w_m,0 = lambda / (n + lambda), Q30, in (-2, 1) */
    rfe_fix_t wi;       /**< w_i = 1 / (2 (n + lambda)), Q30, in (0, 1/2) */
    rfe_fix_t sqrt_wc0; /**< sqrt(w_c,0), w_c,0 = w_m,0 + 1 - alpha^2 + beta, Q30, [0, 2) */
    rfe_fix_t sqrt_wi;  /**< sqrt(w_i), Q30 */
    rfe_fix_t sqrt_c;   /**< sqrt(n + lambda), Q29, (1, 4) */
} rfe_mg_weights_q31_t;

/**
 * The weights of @p p's unscented transform in integers: alpha^2 rounded to Q28, c = n +
 * lambda = alpha^2 (3 + kappa) exact in Q56 and rounded to Q27, then each weight by an
 * exactly rounded division or square root (rfe/component/fxmath.h), so w_m,0 + 6 w_i = 1
 * within 4 LSB of Q30.
 * @param[in]  p  the parameters (only ut_alpha, ut_beta, ut_kappa are read).
 * @param[out] w  the weights; written only on RFE_OK.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM when c is outside (1, 16) or w_c,0 outside
 *         [0, 4) (the fixed-point domain; the defaults give c = 3, w_c,0 = 2).
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_weights_q31(const rfe_mass_grade_params_q31_t *p,
                                                      rfe_mg_weights_q31_t *w);

/**
 * The checks of rfe_mass_grade_params_validate on the Q values (MASS_GRADE.md §6), and the
 * fixed-point domain (FIXED_POINT.md "Mass and grade"): R, g, m0, sd_m0, sd_theta0, q_v,
 * q_mc, q_theta, r_v, r_ax, ut_alpha, m_min, theta_max, dt_max > 0; fc, fr, rho, cd, area,
 * m_rot, q_mv0, t_adapt, mv_stop, v_min, t_brake, t_shift, p_brake_on, slip_max, ay_max,
 * t_curve, ut_beta >= 0;
 * adaptive, use_ax in {0, 1}; pause_grade <= 7 (inert without use_ax); 0 <= pause_grade_slip <= 1, 0 <= pause_grade_dv <= 10
 * (Q30); m_min < m0 < m_max; |theta0| < theta_max < 1.5 rad; q_theta_hi 0 or in
 * [q_theta, 0.1]; 0 < theta_rate_off <= theta_rate_on <= 0.1; theta_rate_tau,
 * theta_rate_avg in [dt_max, 60] s (§4.7); mm_tau in [dt_max, 60] s, 0 <= mm_e <= 100
 * (§4.8); with
 * adaptive, mv_stop q_mc^2 < q_mv0^2. Beyond the float's: rfe_mass_grade_weights_q31
 * succeeds (the spread c = alpha^2 (3 + kappa) in (1, 16), so that w_m,0 = 1 - 3/c and
 * w_i = 1/(2c) fit Q30 and sqrt(c) Q29; the centre's covariance weight w_c,0 in [0, 4),
 * since the square-root filter takes its square root).
 * @param[in] p  the parameters to check.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_mass_grade_params_validate_q31(const rfe_mass_grade_params_q31_t *p);

#endif /* RFE_MASS_GRADE_PARAMS_Q31_H */
