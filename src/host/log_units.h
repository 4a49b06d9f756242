/**
 * @file log_units.h
 * @brief Units of sensor-log columns (DATA.md "Units, scales and names of a recorded log"),
 *        host only: a recorded car's log gives km/h, deg/s, rpm, bar, g, ms; the library
 *        wants SI. One table of unit words per physical quantity, and the conversion factor.
 */
#ifndef RFE_HOST_LOG_UNITS_H
#define RFE_HOST_LOG_UNITS_H

/** The physical quantity of a column: it decides which unit words are accepted. */
typedef enum {
    RFE_DIM_TIME = 0,     /**< s; ms, us */
    RFE_DIM_ANGLE = 1,    /**< rad; deg, mrad */
    RFE_DIM_RATE = 2,     /**< rad/s; deg/s, rpm */
    RFE_DIM_ANG_ACC = 3,  /**< rad/s^2; deg/s^2 */
    RFE_DIM_SPEED = 4,    /**< m/s; km/h, mph */
    RFE_DIM_ACC = 5,      /**< m/s^2; g (standard gravity 9.80665 m/s^2) */
    RFE_DIM_PRESSURE = 6, /**< MPa; kPa, bar, Pa, psi */
    RFE_DIM_TORQUE = 7,   /**< N m; kN m */
    RFE_DIM_NONE = 8,     /**< dimensionless: 1 */
    RFE_DIM_WHEEL = 9,    /**< a wheel speed: a RATE unit (spin), or a SPEED unit (the wheel's
                               circumferential speed, divided by the rolling radius later) */
    RFE_DIM_PRESSURE_PA = 10, /**< a pressure in Pa (the mass and grade estimator's
                                   brake_pressure); kPa, bar, MPa, psi */
    RFE_DIM_MASS = 11     /**< kg; t */
} rfe_dim_t;

/**
 * The factor that takes a value in unit @p unit to SI, for a column of quantity @p dim.
 * For RFE_DIM_WHEEL a speed unit gives the factor to m/s and sets @p *linear to 1 (a rate
 * unit gives the factor to rad/s and 0).
 * @return 0, or -1 when @p unit is not a unit of @p dim (outputs then untouched).
 */
int rfe_unit_factor(rfe_dim_t dim, const char *unit, double *factor, int *linear);

/** The accepted unit words of @p dim, comma separated, for messages ("rad, deg, mrad"). */
const char *rfe_unit_words(rfe_dim_t dim);

#endif /* RFE_HOST_LOG_UNITS_H */
