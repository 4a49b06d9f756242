/**
 * @file log_units.c
 * @brief Unit words of sensor-log columns and their factors to SI (log_units.h).
 */
#include "log_units.h"

#include <stddef.h>
#include <string.h>

/** pi, to double precision (C99 has no M_PI). */
#define PI_D 3.14159265358979323846
/** Standard gravity [m/s^2] (CGPM 1901): what an accelerometer's "g" means. */
#define G_STANDARD 9.80665

/** One unit word of one quantity and its factor to SI. */
typedef struct {
    rfe_dim_t dim;
    const char *word;
    double factor;
} unit_t;

/* Several spellings of one unit are listed, because logging tools write them differently
 * ("m/s^2", "m/s2"); the first of each quantity is the SI unit. */
static const unit_t k_units[] = {
    {RFE_DIM_TIME, "s", 1.0},
    {RFE_DIM_TIME, "ms", 1e-3},
    {RFE_DIM_TIME, "us", 1e-6},
    {RFE_DIM_ANGLE, "rad", 1.0},
    {RFE_DIM_ANGLE, "deg", PI_D / 180.0},
    {RFE_DIM_ANGLE, "mrad", 1e-3},
    {RFE_DIM_RATE, "rad/s", 1.0},
    {RFE_DIM_RATE, "deg/s", PI_D / 180.0},
    {RFE_DIM_RATE, "rpm", 2.0 * PI_D / 60.0},
    {RFE_DIM_ANG_ACC, "rad/s^2", 1.0},
    {RFE_DIM_ANG_ACC, "rad/s2", 1.0},
    {RFE_DIM_ANG_ACC, "deg/s^2", PI_D / 180.0},
    {RFE_DIM_ANG_ACC, "deg/s2", PI_D / 180.0},
    {RFE_DIM_SPEED, "m/s", 1.0},
    {RFE_DIM_SPEED, "km/h", 1.0 / 3.6},
    {RFE_DIM_SPEED, "kph", 1.0 / 3.6},
    {RFE_DIM_SPEED, "mph", 0.44704}, /* international mile 1609.344 m per hour */
    {RFE_DIM_ACC, "m/s^2", 1.0},
    {RFE_DIM_ACC, "m/s2", 1.0},
    {RFE_DIM_ACC, "g", G_STANDARD},
    {RFE_DIM_PRESSURE, "MPa", 1.0},
    {RFE_DIM_PRESSURE, "kPa", 1e-3},
    {RFE_DIM_PRESSURE, "bar", 0.1},
    {RFE_DIM_PRESSURE, "Pa", 1e-6},
    {RFE_DIM_PRESSURE, "psi", 6.894757293168361e-3}, /* 0.45359237 kgf / (0.0254 m)^2 */
    {RFE_DIM_TORQUE, "N m", 1.0},
    {RFE_DIM_TORQUE, "Nm", 1.0},
    {RFE_DIM_TORQUE, "kN m", 1e3},
    {RFE_DIM_TORQUE, "kNm", 1e3},
    {RFE_DIM_NONE, "1", 1.0},
    {RFE_DIM_PRESSURE_PA, "Pa", 1.0},
    {RFE_DIM_PRESSURE_PA, "kPa", 1e3},
    {RFE_DIM_PRESSURE_PA, "bar", 1e5},
    {RFE_DIM_PRESSURE_PA, "MPa", 1e6},
    {RFE_DIM_PRESSURE_PA, "psi", 6.894757293168361e3},
    {RFE_DIM_MASS, "kg", 1.0},
    {RFE_DIM_MASS, "t", 1e3},
};
#define N_UNITS (sizeof k_units / sizeof k_units[0])

/* The factor of @p unit among the units of @p dim; -1 if it is not one of them. */
static int find(rfe_dim_t dim, const char *unit, double *factor)
{
    size_t i;
    for (i = 0u; i < N_UNITS; ++i) {
        if ((k_units[i].dim == dim) && (strcmp(k_units[i].word, unit) == 0)) {
            *factor = k_units[i].factor;
            return 0;
        }
    }
    return -1;
}

int rfe_unit_factor(rfe_dim_t dim, const char *unit, double *factor, int *linear)
{
    double f = 0.0;
    if (dim == RFE_DIM_WHEEL) {
        if (find(RFE_DIM_RATE, unit, &f) == 0) {
            *factor = f;
            *linear = 0;
            return 0;
        }
        if (find(RFE_DIM_SPEED, unit, &f) == 0) {
            *factor = f;
            *linear = 1;
            return 0;
        }
        return -1;
    }
    if (find(dim, unit, &f) != 0) {
        return -1;
    }
    *factor = f;
    *linear = 0;
    return 0;
}

const char *rfe_unit_words(rfe_dim_t dim)
{
    static const char *const words[] = {
        "s, ms, us",
        "rad, deg, mrad",
        "rad/s, deg/s, rpm",
        "rad/s^2 (rad/s2), deg/s^2 (deg/s2)",
        "m/s, km/h (kph), mph",
        "m/s^2 (m/s2), g",
        "MPa, kPa, bar, Pa, psi",
        "N m (Nm), kN m (kNm)",
        "1",
        "rad/s, deg/s, rpm (spin) or m/s, km/h (kph), mph (circumferential speed)",
        "Pa, kPa, bar, MPa, psi",
        "kg, t",
    };
    return ((size_t)dim < (sizeof words / sizeof words[0])) ? words[dim] : "?";
}
