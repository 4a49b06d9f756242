/**
 * @file velocity_params_q31.h
 * @brief Fixed-point twin of rfe/velocity_params.h: the observer's parameters as int32 Q
 *        values (docs/OBSERVER.md §2, docs/FIXED_POINT.md "Observer"), their defaults and
 *        their validation. The vehicle and the tyre are the friction estimator's
 *        (rfe/params_q31.h): one calibration serves both.
 *
 * Each field states its Q format. The host converts a real parameter set with
 * rfe_velocity_params_to_q31_f32/_f64 (rfe/component/params_conv.h).
 */
#ifndef RFE_VELOCITY_PARAMS_Q31_H
#define RFE_VELOCITY_PARAMS_Q31_H

#include <stdint.h>

#include "rfe/common.h"
#include "rfe/fixed.h"
#include "rfe/velocity_bits.h"

/** Q formats of the observer's quantities that rfe/params_q31.h does not name. */
#define RFE_FIX_Q_STEER_WHEEL 26 /**< steering-wheel angle [rad]: Q26, +-32 rad */
#define RFE_FIX_Q_RATIO 24       /**< steering ratio, gate [1], rates per rate: Q24, +-128 */
#define RFE_FIX_Q_PRESSURE 25    /**< brake pressures [MPa]: Q25, +-64 */
#define RFE_FIX_Q_TORQUE 15      /**< drive torques [N m]: Q15, +-65536 */

/** The observer's parameters; fields as rfe_velocity_params_t. */
typedef struct {
    uint32_t driven;          /**< driven wheels, RFE_DRIVEN_* bits (1..15) */
    uint32_t lat_every;       /**< the lateral model's rows every lat_every-th step */
    rfe_fix_t steer_ratio;    /**< steering-wheel / road-wheel angle [1], Q24 */
    rfe_fix_t dt_min;         /**< shortest accepted sample period [s], Q30 */
    rfe_fix_t dt_max;         /**< longest accepted sample period [s], Q30 (<= 1 s) */
    rfe_fix_t q_jerk;         /**< yaw-jerk density [rad/s^3 sqrt(s)], Q24 */
    rfe_fix_t sd_r;           /**< yaw-rate sensor noise [rad/s], Q27 */
    rfe_fix_t sd_ax;          /**< ax noise per sample [m/s^2], Q24 */
    rfe_fix_t sd_ay;          /**< ay noise per sample [m/s^2], Q24 */
    rfe_fix_t q_bx;           /**< random walk of b_x [m/s^2/sqrt(s)], Q24 */
    rfe_fix_t q_by;           /**< random walk of b_y [m/s^2/sqrt(s)], Q24 */
    rfe_fix_t sd_wheel;       /**< wheel reference noise [m/s], Q23 */
    rfe_fix_t sd_wheel_rel;   /**< wheel reference error relative to vx [1], Q30 */
    rfe_fix_t k_gate;         /**< plausibility gate of a wheel [sd], Q24 */
    rfe_fix_t k_agree;        /**< wheels in agreement within k_agree sd_w [sd], Q24 */
    rfe_fix_t v_stand;        /**< every wheel below this: standing [m/s], Q23 */
    rfe_fix_t q_vx_brake;     /**< vx's variance growth while braking unchecked [m/s/sqrt(s)], Q23 */
    rfe_fix_t ax_brake_on;    /**< net deceleration that means braking [m/s^2], Q24 */
    rfe_fix_t ax_drive_on;    /**< net acceleration that means driving [m/s^2], Q24 */
    rfe_fix_t p_brake_on;     /**< brake pressure that means braking [MPa], Q25 */
    rfe_fix_t torque_on;      /**< drive torque that marks a wheel driven [N m], Q15 */
    rfe_fix_t sd_model_ay;    /**< error of the model's ay [m/s^2], Q24 */
    rfe_fix_t model_ay_rel;   /**< the same relative to |ay| [1], Q30 */
    rfe_fix_t sd_model_rdot;  /**< error of the model's yaw acceleration [rad/s^2], Q24; 0: off */
    rfe_fix_t sd_vydot;       /**< v-dot_y as noise of the offset's update [m/s^2], Q24 */
    rfe_fix_t vydot_rdot;     /**< its growth with |r-dot| [m/s^2 per rad/s^2], Q24 */
    rfe_fix_t vydot_rerr;     /**< its growth with max(0, |r| - |r_ref|) [m/s^2 per rad/s],
                                   Q24, at most 100; 0: off */
    rfe_fix_t v_lat_min;      /**< below this vx, vy = Lr r [m/s], Q23 */
    rfe_fix_t sd_lowspeed;    /**< sd of that kinematic vy [m/s], Q23 */
    rfe_fix_t mu_default;     /**< friction while none is given, Q29 */
    rfe_fix_t sd_mu_default;  /**< its sd, Q30 */
    rfe_fix_t mu_margin;      /**< the model's friction >= (1 + margin) |ay| / g, Q30 */
    rfe_fix_t sd_vx0;         /**< initial sd of vx [m/s], Q23 */
    rfe_fix_t sd_bx0;         /**< initial sd of b_x [m/s^2], Q24 */
    rfe_fix_t sd_vy0;         /**< initial sd of vy [m/s], Q23 */
    rfe_fix_t sd_by0;         /**< initial sd of b_y [m/s^2], Q24 */
    rfe_fix_t sd_vy_lin;      /**< sd of the linear range's vy [m/s], Q23; 0: off */
    rfe_fix_t lin_r_tol;      /**< the linear range: |r - r_ref| within this [rad/s], Q27 */
    rfe_fix_t lin_r_rel;      /**< ... plus this share of |r_ref| [1], Q30 */
    rfe_fix_t lin_ay_max;     /**< ... and |ay| at most this [m/s^2], Q24 */
    rfe_fix_t lin_ay_steady;  /**< ... or at most this after lin_dwell on r_ref [m/s^2], Q24 */
    rfe_fix_t lin_dwell;      /**< that time [s], Q30, at most 1 s */
    rfe_fix_t lin_mu_gain;    /**< the steady turn's friction floor, times |ay| / g [1], Q24 */
    rfe_fix_t vy_out_floor_mu; /**< the reported sd(vy)'s floor factor [1], Q24, at most 8;
                                    0: off; 4 by default */
    rfe_fix_t ay_turn;        /**< a turn: |ay| at least this [m/s^2], Q24; 0: off */
    rfe_fix_t q_bx_turn;      /**< random walk of b_x in a turn, not braking
                                   [m/s^2/sqrt(s)], Q24 */
} rfe_velocity_params_q31_t;

/**
 * The defaults of docs/OBSERVER.md §2 in Q formats: an integer table, equal bit for bit to
 * rfe_velocity_params_to_q31_f64(rfe_velocity_params_default_f64).
 * @param[out] p  the parameters to fill.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_params_default_q31(rfe_velocity_params_q31_t *p);

/**
 * The checks of rfe_velocity_params_validate on the Q values: driven in 1..15;
 * lat_every in 1..RFE_VEL_LAT_EVERY_MAX;
 * 0 < dt_min <= dt_max <= 1 s; q_jerk, sd_r, sd_ax, sd_ay, v_lat_min, sd_lowspeed,
 * mu_default, sd_vydot, steer_ratio > 0; every other field >= 0 (sd_model_rdot, sd_vy_lin 0:
 * off); lin_dwell <= 1 s; lin_mu_gain <= 4;
 * vy_out_floor_mu <= 8; vydot_rerr <= 100.
 * @param[in] p  the parameters to check.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_params_validate_q31(const rfe_velocity_params_q31_t *p);

#endif /* RFE_VELOCITY_PARAMS_Q31_H */
