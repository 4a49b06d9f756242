/**
 * @file velocity_params.h
 * @brief Parameters of the velocity and sideslip observer (docs/OBSERVER.md §2), their
 *        defaults and their validation. The vehicle and the tyre are the friction
 *        estimator's (rfe/params.h): one calibration serves both.
 */
#ifndef RFE_VELOCITY_PARAMS_H
#define RFE_VELOCITY_PARAMS_H

#include "rfe/types.h"
#include "rfe/velocity_bits.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_velocity_params_default  rfe_velocity_params_default_f64
#define rfe_velocity_params_validate rfe_velocity_params_validate_f64
#else
#define rfe_velocity_params_default  rfe_velocity_params_default_f32
#define rfe_velocity_params_validate rfe_velocity_params_validate_f32
#endif

/* The driven-wheel bits (RFE_DRIVEN_*): rfe/velocity_bits.h. */

/** The observer's parameters; each field is the parameter-file key obs_<field>. */
typedef struct {
    uint32_t driven;          /**< driven wheels, RFE_DRIVEN_* bits (1..15): 3 (front drive) */
    uint32_t lat_every;       /**< the lateral model's rows every lat_every-th step (§4.2),
                                   1 .. RFE_VEL_LAT_EVERY_MAX: 8 (1 is every step; OBSERVER.md §2) */
    rfe_real_t steer_ratio;   /**< steering-wheel angle / road-wheel angle, used when a sample
                                   gives the steering-wheel angle (RFE_VEL_HAS_STEER_WHEEL) [1]:
                                   16 */
    rfe_real_t dt_min;        /**< shortest accepted sample period [s]: 0.001 */
    rfe_real_t dt_max;        /**< longest accepted sample period [s]: 0.1 */
    rfe_real_t q_jerk;        /**< yaw-jerk density of the differentiator [rad/s^3 sqrt(s)]: 0.5 */
    rfe_real_t sd_r;          /**< yaw-rate sensor noise [rad/s]: 0.005 */
    rfe_real_t sd_ax;         /**< ax noise per sample [m/s^2]: 0.05 */
    rfe_real_t sd_ay;         /**< ay noise per sample [m/s^2]: 0.05 */
    rfe_real_t q_bx;          /**< random walk of the longitudinal offset [m/s^2/sqrt(s)]: 0.005 */
    rfe_real_t q_by;          /**< random walk of the lateral offset [m/s^2/sqrt(s)]: 0.05 */
    rfe_real_t sd_wheel;      /**< wheel reference noise [m/s]: 0.05 */
    rfe_real_t sd_wheel_rel;  /**< wheel reference error relative to vx [1]: 0.005 */
    rfe_real_t k_gate;        /**< plausibility gate of a wheel [sd]: 3 */
    rfe_real_t k_agree;       /**< wheels within k_agree sd_w of each other agree, and are
                                   taken although outside the gate (re-acquisition) [sd]: 3 */
    rfe_real_t v_stand;       /**< every wheel below this: standing [m/s]: 0.3 */
    rfe_real_t q_vx_brake;    /**< growth of vx's variance while braking without a wheel
                                   [m/s/sqrt(s)]: 0 (off: OBSERVER.md §2) */
    rfe_real_t ax_brake_on;   /**< net deceleration that means braking [m/s^2]: 0.5 */
    rfe_real_t ax_drive_on;   /**< net acceleration that means driving [m/s^2]: 0.5 */
    rfe_real_t p_brake_on;    /**< brake pressure that means braking [MPa]: 0.2 */
    rfe_real_t torque_on;     /**< drive torque that marks a wheel driven [N m]: 50 */
    rfe_real_t sd_model_ay;   /**< error of the model's lateral acceleration [m/s^2]: 0.3 */
    rfe_real_t model_ay_rel;  /**< the same relative to |ay| [1]: 0.1 */
    rfe_real_t sd_model_rdot; /**< error of the model's yaw acceleration [rad/s^2]; 0 turns
                                   the yaw row of §4.2 off: 0 (off, OBSERVER.md §2) */
    rfe_real_t sd_vydot;      /**< v-dot_y as noise of the offset's kinematic update [m/s^2]: 1 */
    rfe_real_t vydot_rdot;    /**< its growth with |r-dot| [m/s^2 per rad/s^2]: 15 */
    rfe_real_t vydot_rerr;    /**< its growth with the yaw rate beyond the neutral-steer
                                   reference, max(0, |r| - |r_ref|), at vx >= v_lat_min
                                   (§4.4) [m/s^2 per rad/s], in [0, 100], 0 is off: 15 */
    rfe_real_t v_lat_min;     /**< below this vx, vy = Lr r [m/s]: 3 */
    rfe_real_t sd_lowspeed;   /**< sd of that kinematic vy [m/s]: 0.1 */
    rfe_real_t mu_default;    /**< friction the model uses while none is given: 1.0 */
    rfe_real_t sd_mu_default; /**< its sd: 0.3 */
    rfe_real_t mu_margin;     /**< the model's friction >= (1 + margin) |ay| / g: 0.1 */
    rfe_real_t sd_vx0;        /**< initial sd of vx [m/s]: 1.0 */
    rfe_real_t sd_bx0;        /**< initial sd of the longitudinal offset [m/s^2]: 0.3 */
    rfe_real_t sd_vy0;        /**< initial sd of vy [m/s]: 0.3 */
    rfe_real_t sd_by0;        /**< initial sd of the lateral offset [m/s^2]: 0.1 */
    rfe_real_t sd_vy_lin;     /**< sd of the linear range's vy (§4.2b) [m/s]; 0 turns it off: 0.3 */
    rfe_real_t lin_r_tol;     /**< the linear range: |r - r_ref| within this [rad/s]: 0.01 */
    rfe_real_t lin_r_rel;     /**< ... plus this share of |r_ref| [1]: 0.05 */
    rfe_real_t lin_ay_max;    /**< ... and |ay| at most this [m/s^2]: 3 */
    rfe_real_t lin_ay_steady; /**< ... or at most this once the yaw rate has stayed on its
                                   reference for lin_dwell (a steady turn) [m/s^2]: 4 */
    rfe_real_t lin_dwell;     /**< that time [s], in [0, 1]: 0.125 */
    rfe_real_t lin_mu_gain;   /**< in such a steady turn of the linear range the model's
                                   friction is at least lin_mu_gain |ay| / g [1], in [0, 4]
                                   (at most 1 + mu_margin: no effect): 2 */
    rfe_real_t vy_out_floor_mu; /**< the reported sd(vy) (and so sd(beta)) is at least this
                                     times |vx ay / (cy g)| max_i sd_mu,i / mu_i (§5) [1], in
                                     [0, 8], 0 is off; the filter and the friction's input
                                     noise are untouched: 4 */
    rfe_real_t ay_turn;       /**< a turn: |ay| at least this [m/s^2], 0 is off (§3.4): while
                                   rolling in a turn the driven wheels are not free (they carry
                                   the turn's drag), and b_x's walk is q_bx_turn: 1 */
    rfe_real_t q_bx_turn;     /**< random walk of b_x in a turn while not braking
                                   [m/s^2/sqrt(s)] (it follows r (vy error)): 0.03 */
} rfe_velocity_params_t;

/**
 * The defaults of docs/OBSERVER.md §2.
 * @param[out] p  the parameters to fill.
 * @return RFE_OK; RFE_ERR_NULL.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_params_default(rfe_velocity_params_t *p);

/**
 * Checks every field: finite; driven in 1..15; lat_every in 1..RFE_VEL_LAT_EVERY_MAX; 0 < dt_min <= dt_max <= 1; q_jerk, sd_r,
 * sd_ax, sd_ay, v_lat_min, sd_lowspeed, mu_default, sd_vydot, steer_ratio > 0;
 * every other sd, q, gate, threshold and margin (sd_model_rdot, sd_vy_lin and
 * vy_out_floor_mu included: 0 is off) >= 0; lin_dwell <= 1; lin_mu_gain <= 4;
 * vy_out_floor_mu <= 8; vydot_rerr <= 100.
 * @param[in] p  the parameters to check.
 * @return RFE_OK, RFE_ERR_NULL or RFE_ERR_PARAM.
 */
RFE_NODISCARD rfe_status_t rfe_velocity_params_validate(const rfe_velocity_params_t *p);

#endif /* RFE_VELOCITY_PARAMS_H */
