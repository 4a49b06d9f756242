/**
 * @file modes.h
 * @brief The configuration choices both number types share (tyre curve, filter, state
 *        structure): enums only, so the fixed-point build includes this and never the
 *        float parameters of rfe/params.h.
 */
#ifndef RFE_MODES_H
#define RFE_MODES_H

/** Which tyre curve the measurement model uses (MODEL.md §4, docs/ESTIMATOR.md). */
typedef enum {
    RFE_TYRE_PAPER = 0,    /**< normalised Dugoff: F = mu * F0(u), stiffness ∝ mu*Fz; h = H(u) x */
    RFE_TYRE_ABSOLUTE = 1, /**< load-scaled Dugoff: Cx = cx*Fz, Cy = cy*Fz; h nonlinear in mu */
    RFE_TYRE_MAGIC = 2     /**< load-scaled Magic Formula (similarity combined slip), the same
                                slip stiffnesses cx*Fz, cy*Fz and curve shapes shape_C*, shape_E* */
} rfe_tyre_mode_t;

/** Which filter runs the estimator (MODEL.md §6). */
typedef enum {
    RFE_FILTER_SCKF = 0,  /**< square-root cubature Kalman filter (the paper's method) */
    RFE_FILTER_CKF = 1    /**< full-covariance cubature Kalman filter (the paper's baseline) */
} rfe_filter_kind_t;

/** The estimator's state (docs/ESTIMATOR.md): the map T from states to wheels. */
typedef enum {
    RFE_STRUCT_WHEELS = 0, /**< n = 4: one mu per wheel, T = I */
    RFE_STRUCT_SIDES = 1   /**< n = 2: [mu_left, mu_right]; fl, rl on the left, fr, rr on the right */
} rfe_structure_t;

#endif /* RFE_MODES_H */
