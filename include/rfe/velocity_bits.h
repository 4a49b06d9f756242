/**
 * @file velocity_bits.h
 * @brief The bit masks of the velocity observer that both number types share (velocity.h,
 *        velocity_q31.h, velocity_params.h and its q31 twin): which optional inputs a sample
 *        carries, what corrected an estimate, which wheels are driven. No real type in it.
 */
#ifndef RFE_VELOCITY_BITS_H
#define RFE_VELOCITY_BITS_H

/** Bits of the input's `has`: which optional inputs the sample carries. */
#define RFE_VEL_HAS_PRESSURE 1u /**< p_brake is given */
#define RFE_VEL_HAS_TORQUE 2u   /**< torque is given */
#define RFE_VEL_HAS_STEER_WHEEL 4u /**< the steering angle is steer_wheel (delta is ignored):
                                        delta = steer_wheel / steer_ratio */

/** Bits of the estimate's `flags`: what corrected the estimate (OBSERVER.md §5). */
#define RFE_VEL_FLAG_VX_WHEEL 1u     /**< vx corrected by a wheel reference */
#define RFE_VEL_FLAG_BRAKING 2u      /**< driving state: braking */
#define RFE_VEL_FLAG_DRIVING 4u      /**< driving state: driving */
#define RFE_VEL_FLAG_VY_MODEL 8u     /**< vy corrected by the tyre model */
#define RFE_VEL_FLAG_VY_LOWSPEED 16u /**< vy corrected by the low-speed kinematics */
#define RFE_VEL_FLAG_MU_RAISED 32u   /**< the measured ay raised the model's friction */
#define RFE_VEL_FLAG_VY_LINEAR 64u   /**< vy corrected by the linear range (OBSERVER.md §4.2b) */

/** Driven-wheel bits of the parameters' `driven` (fl, fr, rl, rr). */
#define RFE_DRIVEN_FL 1u
#define RFE_DRIVEN_FR 2u
#define RFE_DRIVEN_RL 4u
#define RFE_DRIVEN_RR 8u
/** Every wheel driven (all-wheel drive). */
#define RFE_DRIVEN_ALL (RFE_DRIVEN_FL | RFE_DRIVEN_FR | RFE_DRIVEN_RL | RFE_DRIVEN_RR)

/** The largest `lat_every` (OBSERVER.md §4.2: the model's rows every lat_every-th step; 8
 *  steps are 0.08 s at 100 Hz, beyond which the kinematics alone would carry vy through a
 *  lane change's yaw-rate reversal). */
#define RFE_VEL_LAT_EVERY_MAX 8u

#endif /* RFE_VELOCITY_BITS_H */
