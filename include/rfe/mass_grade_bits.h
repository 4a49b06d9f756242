/**
 * @file mass_grade_bits.h
 * @brief What the mass and grade estimator's float/double and fixed-point faces share
 *        (docs/MASS_GRADE.md): which optional inputs a sample carries and the presets. No
 *        real type in it.
 */
#ifndef RFE_MASS_GRADE_BITS_H
#define RFE_MASS_GRADE_BITS_H

/** Bits of the input's `has`: which optional inputs the sample carries (§1). */
#define RFE_MG_HAS_BRAKE 1u    /**< brake (the pedal flag) is given */
#define RFE_MG_HAS_PRESSURE 2u /**< p_brake (the brake pressure) is given */
#define RFE_MG_HAS_GEAR 4u     /**< gear is given */
#define RFE_MG_HAS_AX 8u       /**< ax (the accelerometer) is given */
#define RFE_MG_HAS_VX 16u      /**< vx (the car's speed over ground, not the wheels') is
                                    given: the slip pause (§4.2) */
#define RFE_MG_HAS_AY 32u      /**< ay (the lateral accelerometer) is given: the curve pause
                                    (§4.2) */
/** mass_grade_params pause_grade's bits (MASS_GRADE.md §4.2): the pauses during which the
 *  grade keeps being learned from ax while the mass is held. */
#define RFE_MG_PAUSE_GRADE_BRAKE 1u /**< the brake pause (RFE_MG_PAUSED_BRAKE) */
#define RFE_MG_PAUSE_GRADE_SHIFT 2u /**< the gear-shift pause (RFE_MG_PAUSED_SHIFT) */
#define RFE_MG_PAUSE_GRADE_CURVE 4u /**< the curve pause (RFE_MG_PAUSED_CURVE) */
#define RFE_MG_PAUSE_GRADE_ALL 7u   /**< every bit pause_grade may set */
/** The largest pause_grade_dv, the change test's speed (MASS_GRADE.md §4.2, §6) [m/s]. */
#define RFE_MG_PAUSE_GRADE_DV_MAX_MS 10
/** The largest q_theta_hi, theta_rate_on (MASS_GRADE.md §4.7, §6), in thousandths
 *  [mrad/sqrt(s), mrad/s], and the largest theta_rate_tau, theta_rate_avg [s]. */
#define RFE_MG_WALK_MAX_MILLI 100
#define RFE_MG_WALK_TAU_MAX_S 60
/** The largest mm_e, the model-mismatch monitor's threshold (MASS_GRADE.md §4.8, §6) [1]. */
#define RFE_MG_MM_E_MAX 100
/** Every bit a sample may set. */
#define RFE_MG_HAS_ALL 63u

/** The vehicle of a preset (MASS_GRADE.md §6). */
typedef enum {
    RFE_MG_CAR = 0,  /**< the simulator's passenger car (1 500-2 100 kg) */
    RFE_MG_TRUCK = 1 /**< the seed's 5 758 kg two-axle truck */
} rfe_mg_vehicle_t;

/** The configuration of a preset (MASS_GRADE.md §6, "Presets"). */
typedef enum {
    RFE_MG_RECOMMENDED = 0, /**< plain UKF with the accelerometer row, rotating mass modelled:
                                 what measured best (MASS_GRADE_RESULTS.md) */
    RFE_MG_SEED = 1         /**< the seed's AUKF on speed and torque only, adaptation every
                                 step, no rotating mass */
} rfe_mg_config_t;

#endif /* RFE_MASS_GRADE_BITS_H */
