/**
 * @file config.h
 * @brief Compile-time maxima and input limits. Each may be overridden with -D.
 */
#ifndef RFE_CONFIG_H
#define RFE_CONFIG_H

#include <stdint.h>

/** Largest state dimension the generic filters (SCKF, CKF) support. */
#ifndef RFE_N_MAX
#define RFE_N_MAX 8
#endif
/** Largest measurement dimension the generic filters support. */
#ifndef RFE_M_MAX
#define RFE_M_MAX 4
#endif
/** Widest matrix Tria() is asked to triangularise: [n x 2n | n x max(n, m)]. */
#define RFE_TRIA_COLS_MAX ((2 * RFE_N_MAX) + ((RFE_N_MAX > RFE_M_MAX) ? RFE_N_MAX : RFE_M_MAX))
/** Number of cubature points at the largest state dimension. */
#define RFE_CUB_MAX (2 * RFE_N_MAX)
/** Largest state dimension of the tyre identifier's sigma-point filter (rfe/tyre_id.h,
 *  docs/TYRE_ID.md §15): vy, r, the eight Magic Formula parameters and, with delta_state_q > 0
 *  (§15.7), the steering angle. Not an override: the model fixes it. */
#define RFE_TID_SCKF_N 11
/** Most rows Tria() (rfe/component/qr.h) reduces: the generic filters' RFE_N_MAX or the tyre
 *  identifier's RFE_TID_SCKF_N, the larger. It sizes only Tria's two row arrays on the stack
 *  (a real and an int per row), no filter state: the friction estimator's stays RFE_N_MAX. */
#define RFE_TRIA_ROWS_MAX ((RFE_N_MAX > RFE_TID_SCKF_N) ? RFE_N_MAX : RFE_TID_SCKF_N)
/** Widest matrix Tria() accepts: [r x 2r | r x max(r, m)] at r = RFE_TRIA_ROWS_MAX (33 with the
 *  defaults; RFE_TRIA_COLS_MAX, the generic filters' work matrices, stays 24). */
#define RFE_TRIA_COLS_LIMIT \
    ((2 * RFE_TRIA_ROWS_MAX) + ((RFE_TRIA_ROWS_MAX > RFE_M_MAX) ? RFE_TRIA_ROWS_MAX : RFE_M_MAX))

/** Particle count of the tyre identifier (rfe/tyre_id.h, docs/TYRE_ID.md §2 tid_n), at least 2
 *  and at most 65535 (the parent indices are 16-bit). Its state holds 26 reals and three
 *  16-bit indices per particle and the sigma-point filter's 928 reals (rfe_tid_sckf_t): with
 *  the default 256, 32.4 kB in float and 63.3 kB in double (sizeof(rfe_tyre_id_t);
 *  test_tyre_id_flt.c checks the figure). A build that runs only the sigma-point filter
 *  (tid_filter sckf) needs no particles: -DRFE_TID_N=2. */
#ifndef RFE_TID_N
#define RFE_TID_N 256
#endif
/** Most RK4 steps per sample period the tyre identifier accepts (tid_substeps). */
#ifndef RFE_TID_SUBSTEPS_MAX
#define RFE_TID_SUBSTEPS_MAX 16
#endif

/** The configuration a translation unit was compiled with, in one word: the maxima above,
 *  then the number type in the low byte (1 float, 2 double, 3 fixed point). Each init's
 *  wrapper (rfe_friction_init, rfe_velocity_init, rfe_pipeline_init and their _q31 twins;
 *  the component inits rfe_sckf_init, rfe_ckf_init and their _q31 twins, rfe_kf2_init,
 *  rfe_conditioner_init, rfe_monitor_init) passes the caller's word and the caller's sizeof
 *  of the state; the library compares them with its own and returns RFE_ERR_ABI, writing
 *  nothing, when they differ (an application built with -DRFE_N_MAX=4 linked against a
 *  library built with the defaults). */
#define RFE_CONFIG_MAXIMA ((((uint32_t)RFE_N_MAX) << 16u) | (((uint32_t)RFE_M_MAX) << 8u))
#if defined(RFE_REAL_DOUBLE)
#define RFE_CONFIG_REAL (RFE_CONFIG_MAXIMA | 2u) /**< a double translation unit's word */
#else
#define RFE_CONFIG_REAL (RFE_CONFIG_MAXIMA | 1u) /**< a float translation unit's word */
#endif
#define RFE_CONFIG_Q31 (RFE_CONFIG_MAXIMA | 3u)  /**< a fixed-point translation unit's word */

/* Input limits of rfe_friction_step (absolute values, SI). A sample outside them is
 * rejected with RFE_ERR_RANGE and leaves the estimator untouched. They are physical
 * plausibility bounds for a passenger car, not tuning. */
#ifndef RFE_LIMIT_DELTA
#define RFE_LIMIT_DELTA 1.0      /**< |delta| [rad]: road-wheel angle at the stops */
#endif
#ifndef RFE_LIMIT_VX
#define RFE_LIMIT_VX 100.0       /**< |vx| [m/s] (360 km/h) */
#endif
#ifndef RFE_LIMIT_VY
#define RFE_LIMIT_VY 50.0        /**< |vy| [m/s] */
#endif
#ifndef RFE_LIMIT_YAW_RATE
#define RFE_LIMIT_YAW_RATE 10.0  /**< |r| [rad/s] */
#endif
#ifndef RFE_LIMIT_YAW_ACC
#define RFE_LIMIT_YAW_ACC 100.0  /**< |r-dot| [rad/s^2] */
#endif
#ifndef RFE_LIMIT_ACC
#define RFE_LIMIT_ACC 50.0       /**< |ax|, |ay| [m/s^2] (about 5 g) */
#endif
#ifndef RFE_LIMIT_OMEGA
#define RFE_LIMIT_OMEGA 500.0    /**< |omega| [rad/s] (about 160 m/s at R = 0.325 m) */
#endif
#ifndef RFE_LIMIT_PRESSURE
#define RFE_LIMIT_PRESSURE 50.0  /**< |brake pressure| [MPa] (velocity observer; a sensor reads a little below 0 around zero) */
#endif
#ifndef RFE_LIMIT_TORQUE
#define RFE_LIMIT_TORQUE 20000.0 /**< |drive torque at a wheel| [N m] (velocity observer) */
#endif
#ifndef RFE_LIMIT_DRIVE_TORQUE
#define RFE_LIMIT_DRIVE_TORQUE 1.0e5 /**< |total drive torque at the wheels| [N m] (mass and grade) */
#endif
#ifndef RFE_LIMIT_GRADE
#define RFE_LIMIT_GRADE 0.6      /**< |road grade| [rad] (about 35 degrees) */
#endif

#endif /* RFE_CONFIG_H */
