/**
 * @file tyre_id.h
 * @brief The online tyre identifier (docs/TYRE_ID.md): the yaw rate and the lateral
 *        acceleration of a car with ESC in; sideslip, yaw rate, the axle lateral forces and
 *        the lateral Magic Formula per axle (D, C, B, E; the cornering stiffness K = B C D;
 *        mu = D / Fz), each with its spread, out.
 *
 * A particle filter over the single-track model's states (vy, r) and the eight parameters:
 * the auxiliary particle filter of the patent CN104408265 (§5.2) or a plain bootstrap filter
 * (§5.6), RK4 steps of the model (§4.1), weights kept as logarithms (§5.1), multinomial or
 * systematic resampling (§5.3), the patent's resampling with roughening within the bounds
 * (§5.4-5.5), and a counter-based random stream (rfe/component/philox.h, §6) so that the
 * double build reproduces the reference (scripts/reference/tyre_id.py, libm backend) bit for
 * bit from the same seed. RFE_TID_N particles (rfe/config.h) live in the caller-owned state:
 * no heap. A rejected sample returns an error status and leaves the state as it was.
 *
 * @code
 * #include "rfe/tyre_id.h"
 *
 * static rfe_tyre_id_t tid;                      // caller-owned: sizeof(rfe_tyre_id_t)
 *
 * rfe_status_t tid_setup(void)
 * {
 *     rfe_params_t veh;                           // vehicle and tyre data (the prior's centre)
 *     rfe_tyre_id_params_t tp;
 *     rfe_status_t st = rfe_params_default(&veh);
 *     if (st == RFE_OK) {
 *         st = rfe_tyre_id_params_default(&tp);
 *     }
 *     if (st == RFE_OK) {
 *         st = rfe_tyre_id_init(&tid, &tp, &veh, 1u); // seed 1
 *     }
 *     return st;
 * }
 *
 * void tid_task(const rfe_tyre_id_sample_t *s)    // SI units, ISO 8855 axes
 * {
 *     rfe_tyre_id_estimate_t e;
 *     if (!rfe_status_is_error(rfe_tyre_id_step(&tid, s, &e))) {
 *         // e.mean[RFE_TID_OUT_MU_F], e.sd[RFE_TID_OUT_MU_F], e.mean[RFE_TID_OUT_K_F], ...
 *     }
 * }
 * @endcode
 */
#ifndef RFE_TYRE_ID_H
#define RFE_TYRE_ID_H

#include "rfe/component/philox.h"
#include "rfe/config.h"
#include "rfe/params.h"
#include "rfe/tyre_id_params.h"

/* The particle count fits the 16-bit parent indices and is at least 2. */
#if (RFE_TID_N < 2) || (RFE_TID_N > 65535)
#error "RFE_TID_N must lie in 2..65535"
#endif

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_tyre_id_init rfe_tyre_id_init_f64
#define rfe_tyre_id_step rfe_tyre_id_step_f64
#define rfe_tyre_id_get  rfe_tyre_id_get_f64
#else
#define rfe_tyre_id_init rfe_tyre_id_init_f32
#define rfe_tyre_id_step rfe_tyre_id_step_f32
#define rfe_tyre_id_get  rfe_tyre_id_get_f32
#endif

/** A particle's columns (TYRE_ID.md §4, §6.3): the states, then per axle D, C, K, E. */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum {
    RFE_TID_VY = 0,
    RFE_TID_R = 1,
    RFE_TID_D_F = 2,
    RFE_TID_C_F = 3,
    RFE_TID_K_F = 4,
    RFE_TID_E_F = 5,
    RFE_TID_D_R = 6,
    RFE_TID_C_R = 7,
    RFE_TID_K_R = 8,
    RFE_TID_E_R = 9,
    RFE_TID_DIM = 10,  /**< columns of a particle */
    RFE_TID_STATES = 2, /**< vy, r */
    RFE_TID_PAR = 8,    /**< the parameters, roughened (§5.5) */
    RFE_TID_DELTA = 10, /**< the SCKF's eleventh state, delta, with delta_state_q > 0 (§15.7) */
    RFE_TID_SCKF_DIM = 11, /**< the SCKF's largest state: a particle's columns and delta */
    RFE_TID_CUB = 22,   /**< the SCKF's most cubature points, 2 RFE_TID_SCKF_DIM (§15.3) */
    RFE_TID_MEAS = 3,   /**< the SCKF's most measurements (yaw rate, ay; delta with §15.7) */
    RFE_TID_TRIA_COLS = 33 /**< the SCKF's widest Tria input [points | S_Q], 3 SCKF_DIM */
};

/** The outputs (TYRE_ID.md §7), the index of each in rfe_tyre_id_estimate_t's mean and sd;
 *  the order of the reference's OUTPUT_NAMES. */
/* cppcheck-suppress misra-c2012-2.4 ; MISRA-FP-01: an anonymous enum has no tag */
enum {
    RFE_TID_OUT_BETA = 0, /**< sideslip atan2(vy, vx) [rad] */
    RFE_TID_OUT_R = 1,    /**< yaw rate [rad/s] */
    RFE_TID_OUT_VY = 2,   /**< [m/s] */
    RFE_TID_OUT_FY_F = 3, /**< front axle lateral force (wheel axes) [N] */
    RFE_TID_OUT_FY_R = 4, /**< rear axle lateral force [N] */
    RFE_TID_OUT_D_F = 5,  /**< peak D of the front axle [N] */
    RFE_TID_OUT_C_F = 6,  /**< shape C [1] */
    RFE_TID_OUT_K_F = 7,  /**< cornering stiffness K = B C D [N/rad] */
    RFE_TID_OUT_E_F = 8,  /**< curvature E [1] */
    RFE_TID_OUT_D_R = 9,
    RFE_TID_OUT_C_R = 10,
    RFE_TID_OUT_K_R = 11,
    RFE_TID_OUT_E_R = 12,
    RFE_TID_OUT_B_F = 13, /**< stiffness factor B = K / (C D) [1/rad] */
    RFE_TID_OUT_B_R = 14,
    RFE_TID_OUT_MU_F = 15, /**< mu = D / Fz of the front axle [1] */
    RFE_TID_OUT_MU_R = 16,
    RFE_TID_OUTPUTS = 17
};

/** Bits of rfe_tyre_id_estimate_t's flags (TYRE_ID.md §7). */
#define RFE_TID_UPDATED 1u   /**< the filter stepped */
#define RFE_TID_RESAMPLED 2u /**< it drew parents (the APF's draw, the SIR's resampling) */
#define RFE_TID_HELD 4u      /**< vx below v_min: nothing changed but the stored inputs */
#define RFE_TID_FIRST 8u     /**< the first sample: the prior was drawn */
#define RFE_TID_LOST 16u     /**< every weight was zero: the prior was drawn again */

/** One sample (TYRE_ID.md §1), SI units, ISO 8855 axes. */
typedef struct {
    rfe_real_t dt;       /**< period since the previous sample [s] (first: ignored) */
    rfe_real_t delta;    /**< front road-wheel angle [rad] */
    rfe_real_t vx;       /**< longitudinal velocity (the velocity observer's) [m/s] */
    rfe_real_t yaw_rate; /**< measured r [rad/s] */
    rfe_real_t ay;       /**< measured lateral acceleration [m/s^2] */
    rfe_real_t ax;       /**< longitudinal acceleration: the axle loads of mu, and with
                              ellipse the axle forces (§3.5) [m/s^2] */
} rfe_tyre_id_sample_t;

/** Output of one step: the weighted mean and sd over the particles of each output. */
typedef struct {
    rfe_real_t mean[RFE_TID_OUTPUTS]; /**< indexed by RFE_TID_OUT_* */
    rfe_real_t sd[RFE_TID_OUTPUTS];   /**< indexed by RFE_TID_OUT_* */
    rfe_real_t n_eff;                 /**< effective particle count 1 / sum w^2 */
    uint32_t flags;                   /**< RFE_TID_* bits */
    rfe_status_t status;              /**< status of the step (same as the return value) */
} rfe_tyre_id_estimate_t;

/** The identifier's constants, derived at init from its parameters and the vehicle. */
typedef struct {
    rfe_real_t m;                      /**< mass [kg] */
    rfe_real_t Lf;                     /**< CoG to front axle [m] */
    rfe_real_t Lr;                     /**< CoG to rear axle [m] */
    rfe_real_t J;                      /**< yaw moment of inertia [kg m^2] */
    rfe_real_t alpha_max;              /**< slip-angle bound [rad] */
    rfe_real_t fz0[2];                 /**< static axle loads [N] (§3.4) */
    rfe_real_t gx;                     /**< load transfer per ax, (m hg) / (Lf + Lr) [kg] */
    rfe_real_t lo[RFE_TID_PAR];        /**< bounds of the parameters (§2; N, 1, N/rad, 1) */
    rfe_real_t hi[RFE_TID_PAR];
    rfe_real_t q[RFE_TID_PAR];         /**< random-walk densities of the parameters */
    rfe_real_t mean0[RFE_TID_PAR];     /**< the prior's means and sds (§4.2) */
    rfe_real_t sd0[RFE_TID_PAR];
    rfe_real_t rough;                  /**< rough_k N^(-1/8) (§5.5) */
    rfe_real_t kxm[2];                 /**< fx_front m, (1 - fx_front) m: each axle's share
                                            of m ax [kg] (§3.5) */
    rfe_real_t u_max;                  /**< 1 - ell_min ell_min (§3.5) */
} rfe_tid_consts_t;

/** The sigma-point filter's mean, square-root covariance and scratch (filter RFE_TID_SCKF,
 *  TYRE_ID.md §15; 928 reals: 3.6 kB in float, 7.3 kB in double), sized for its largest
 *  state (delta_state_q > 0, §15.7: n = 11, m = 3); without delta n = 10, m = 2 and only the
 *  leading parts are used. Matrices row-major, the leading dimension after "ld" (n: the
 *  state dimension in use). */
typedef struct {
    rfe_real_t x[RFE_TID_SCKF_DIM];                 /**< the mean (a particle's columns[, delta]) */
    rfe_real_t S[RFE_TID_SCKF_DIM * RFE_TID_SCKF_DIM]; /**< lower-triangular S, P = S S^T, ld n */
    rfe_real_t pts[RFE_TID_CUB * RFE_TID_SCKF_DIM]; /**< cubature points, one per row, ld n */
    rfe_real_t zp[RFE_TID_CUB * RFE_TID_MEAS];      /**< their measurements, ld m */
    rfe_real_t A[RFE_TID_SCKF_DIM * RFE_TID_TRIA_COLS]; /**< Tria input and output, ld 3 n */
    rfe_real_t Z[RFE_TID_MEAS * (RFE_TID_CUB + RFE_TID_MEAS)]; /**< [Zc | S_R], ld 2 n + m */
    rfe_real_t Kt[RFE_TID_MEAS * RFE_TID_SCKF_DIM]; /**< the gain, transposed, ld n */
    rfe_real_t xn[RFE_TID_SCKF_DIM];                /**< the predicted mean */
    rfe_real_t sr[RFE_TID_MEAS];                    /**< diagonal of S_R */
    rfe_real_t zhat[RFE_TID_MEAS];                  /**< the predicted measurement */
} rfe_tid_sckf_t;

/** Identifier state (caller-owned; fields read-only for the caller). The part after `last`
 *  is the step's scratch, kept here so that no particle array sits on the stack. */
typedef struct {
    uint32_t magic;
    uint32_t started;                  /**< 0 until the first accepted sample */
    rfe_tyre_id_params_t p;            /**< the identifier's parameters */
    rfe_tid_consts_t c;                /**< the constants derived from them */
    uint64_t seed;                     /**< key word k0 of the stream */
    uint64_t k;                        /**< the sample counter (counter word c1) */
    rfe_real_t prev_delta;             /**< the previous sample's delta, vx and ax */
    rfe_real_t prev_vx;
    rfe_real_t prev_ax;
    rfe_real_t dlt[5];                 /**< the steering-angle filter (§4.4, delta_q > 0): delta,
                                            its rate, and their covariance p00, p01, p11 */
    rfe_real_t sd_delta;               /**< the steering noise of §5.1 and §15.3: sd_delta, or
                                            the steering-angle filter's posterior sd */
    rfe_real_t x[RFE_TID_N][RFE_TID_DIM]; /**< the particles */
    rfe_real_t logw[RFE_TID_N];        /**< their normalised log weights */
    rfe_tyre_id_estimate_t last;       /**< the output of the last step */
    rfe_tid_sckf_t sk;                 /**< the sigma-point filter (filter RFE_TID_SCKF; the
                                            particles then unused: RFE_TID_N = 2 saves them) */
    /* scratch of one step */
    rfe_real_t aux[RFE_TID_N][RFE_TID_STATES]; /**< the noise-free RK4 step (the APF's
                                                    auxiliary points) */
    rfe_real_t la[RFE_TID_N];          /**< log-likelihood at the auxiliary points */
    rfe_real_t w[RFE_TID_N];           /**< normalised weights */
    rfe_real_t cum[RFE_TID_N];         /**< their cumulative sum */
    rfe_real_t nx[RFE_TID_N][RFE_TID_DIM]; /**< the resampled particles */
    uint16_t idx[RFE_TID_N];           /**< the particle (ancestor) of each slot */
    uint16_t order[RFE_TID_N];         /**< the particles by descending weight */
    uint16_t tmp[RFE_TID_N];           /**< the merge sort's other buffer */
} rfe_tyre_id_t;

/**
 * Validates and copies the parameters; the next accepted sample draws the prior (§4.2).
 * @param[out] tid   the identifier's state; written only on RFE_OK.
 * @param[in]  tp    its parameters (rfe_tyre_id_params_default, then tuning).
 * @param[in]  veh   the vehicle and tyre data (the friction estimator's rfe_params_t: m, Lf,
 *                   Lr, J, hg, g, alpha_max; cy, shape_Cy, shape_Ey as the prior's centre).
 * @param[in]  seed  key word k0 of the random stream (tid_seed).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (rfe_tyre_id_params_validate or
 *         rfe_params_validate fails, a prior mean lies outside its bounds, or a constant
 *         derived from the axle loads is not finite or leaves a pair of bounds not lo < hi,
 *         TYRE_ID.md §12).
 * @note The call goes through a macro of the full name that adds the caller's sizeof of
 *       the state (which RFE_TID_N sets) and its RFE_CONFIG_* word (rfe/config.h):
 *       RFE_ERR_ABI, nothing written, when the caller was compiled with another particle
 *       count, other maxima or another number type than the library.
 */
RFE_NODISCARD rfe_status_t rfe_tyre_id_init(rfe_tyre_id_t *tid, const rfe_tyre_id_params_t *tp,
                                            const rfe_params_t *veh, uint64_t seed,
                                            size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_TYRE_ID_IMPL), where the name is the function's own. */
#if !defined(RFE_TYRE_ID_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_tyre_id_init_f64(tid, tp, veh, seed) \
    rfe_tyre_id_init_f64((tid), (tp), (veh), (seed), sizeof(rfe_tyre_id_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_tyre_id_init_f32(tid, tp, veh, seed) \
    rfe_tyre_id_init_f32((tid), (tp), (veh), (seed), sizeof(rfe_tyre_id_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * One sample (TYRE_ID.md §7): the first draws the prior; while vx (this or the previous
 * sample) is below v_min the step holds; else the filter's step (§5.2 or §5.6).
 * @param[in,out] tid  an identifier set up by rfe_tyre_id_init.
 * @param[in]     s    the sample; dt in (0, dt_max] (but on the first sample).
 * @param[out]    out  the estimate (on error: the previous one, with the error status).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NONFINITE (an input);
 *         RFE_ERR_RANGE (dt, or an input outside config.h's limits). On error the state is
 *         untouched.
 */
RFE_NODISCARD rfe_status_t rfe_tyre_id_step(rfe_tyre_id_t *tid, const rfe_tyre_id_sample_t *s,
                                            rfe_tyre_id_estimate_t *out);

/**
 * The estimate of the last step without stepping.
 * @param[in]  tid  an identifier set up by rfe_tyre_id_init.
 * @param[out] out  the estimate.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_tyre_id_get(const rfe_tyre_id_t *tid,
                                           rfe_tyre_id_estimate_t *out);

#endif /* RFE_TYRE_ID_H */
