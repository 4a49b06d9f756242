/**
 * @file monitor.h
 * @brief Model-validity monitor (docs/MONITOR.md §2): tests, over a window, the filter's own
 *        claim that its innovation nu = y - z_hat is N(0, S_zz S_zz^T), and says when the
 *        data contradict the model. It reads the innovations only; it never changes the
 *        filter (it is not an update gate).
 *
 * Per step that evaluated the measurement model, with m = RFE_MEAS channels:
 *   w = S_zz \ nu, d = |w|^2 (NIS); e_r = nu_r / sqrt(S_rr); c_r = clip(C_rr / S_rr, 0, 1),
 *   C_rr the diagonal of the persistent part of S (the state's share, the tyre-model error,
 *   the low-passed speeds' columns: errors that do not change from one step to the next);
 *   D = (1 - l_d) D + l_d d (D_0 = m), M_r = (1 - l_m) M_r + l_m e_r (M_0 = 0),
 *   C_r = (1 - l_m) C_r + l_m c_r (starting at the first counted step's c), l = dt / (tau + dt).
 * Thresholds from the per-step false-alarm probability under the model (a white part of
 * share 1 - C_r plus a persistent part of share C_r, constant over the window): D against
 * a + b chi2(nu) with three cumulants matched (Pearson), its quantile by Wilson-Hilferty; each
 * M_r against z sigma_r, sigma_r^2 = C_r + (1 - C_r) l' (l' = l / (2 - l)). Fire when D or any
 * |M_r| exceeds its fire threshold; stay fired at least hold_steps after the last exceedance;
 * clear when every statistic is below its clear threshold. The first warmup_steps steps only
 * count.
 */
#ifndef RFE_MONITOR_H
#define RFE_MONITOR_H

#include "rfe/config.h"
#include "rfe/params.h"

/* Full names of the functions declared here: _f32 in the float build, _f64 with
 * RFE_REAL_DOUBLE (rfe/types.h). Sources define and call them by the short name. */
#if defined(RFE_REAL_DOUBLE)
#define rfe_monitor_init      rfe_monitor_init_f64
#define rfe_monitor_step      rfe_monitor_step_f64
#define rfe_monitor_inflation rfe_monitor_inflation_f64
#define rfe_monitor_limits    rfe_monitor_limits_f64
#else
#define rfe_monitor_init      rfe_monitor_init_f32
#define rfe_monitor_step      rfe_monitor_step_f32
#define rfe_monitor_inflation rfe_monitor_inflation_f32
#define rfe_monitor_limits    rfe_monitor_limits_f32
#endif

/** Monitor state (caller-owned; fields read-only for the caller). The eight 32-bit words
 *  come first so that the struct has no padding in either real type (whole-state copies and
 *  comparisons see defined bytes only). */
typedef struct {
    uint32_t magic;             /**< set by init; guards use before init */
    uint32_t hold_steps;        /**< ceil(hold / dt) */
    uint32_t warmup_steps;      /**< ceil(warmup / dt) */
    uint32_t seen;              /**< steps seen (saturates): the warm-up counts them */
    uint32_t hold;              /**< hold counter while fired */
    uint32_t started;           /**< 0 until the first counted step set C */
    uint32_t fired;             /**< 1: the data contradict the model */
    uint32_t inflate;           /**< 1: rfe_monitor_inflation gives sqrt(max(1, D / m)) */
    rfe_real_t l_d;             /**< EWMA weight of D, dt / (tau_nis + dt) */
    rfe_real_t l_m;             /**< EWMA weight of M and C, dt / (tau_mean + dt) */
    rfe_real_t z_d_fire;        /**< z(1 - p_fire / 2): the NIS test's normal quantile */
    rfe_real_t z_d_clear;       /**< z(1 - p_clear / 2) */
    rfe_real_t z_m_fire;        /**< z(1 - p_fire / (4 m)): each channel's two-sided test */
    rfe_real_t z_m_clear;       /**< z(1 - p_clear / (4 m)) */
    rfe_real_t D;               /**< NIS average */
    rfe_real_t M[RFE_MEAS];     /**< innovation means, normalised, per channel */
    rfe_real_t C[RFE_MEAS];     /**< persistent shares, averaged, per channel */
} rfe_monitor_t;

/** The thresholds at given averaged persistent shares (rfe_monitor_limits). */
typedef struct {
    rfe_real_t d_fire;          /**< D above this fires */
    rfe_real_t d_clear;         /**< D below this may clear */
    rfe_real_t m_fire[RFE_MEAS];  /**< |M_r| above this fires */
    rfe_real_t m_clear[RFE_MEAS]; /**< |M_r| below this may clear */
} rfe_monitor_limits_t;

/**
 * Initialises the monitor from its parameters and the sample period: D = m, M = 0, not
 * fired; the weights, quantiles and step counts from rfe_monitor_consts (rfe/params.h).
 * @param[out] mon  written only on RFE_OK
 * @param[in]  p    tau_nis, tau_mean > 0; 0 < p_fire < p_clear < 1; hold, warmup >= 0 and
 *                  below 2^31 dt; inflate 0 or 1 (enable is the caller's: it is not read)
 * @param[in]  dt   sample period [s], finite and > 0
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_PARAM (a parameter or dt outside the above);
 *         RFE_ERR_ABI (below; nothing written).
 * @note The call goes through a macro of the full name that adds the caller's
 *       sizeof of the state and its RFE_CONFIG_* word (rfe/config.h): RFE_ERR_ABI,
 *       nothing written, when the caller was compiled with other maxima or another
 *       number type than the library (the state's layout depends on the number type).
 */
RFE_NODISCARD rfe_status_t rfe_monitor_init(rfe_monitor_t *mon, const rfe_monitor_params_t *p,
                                           rfe_real_t dt, size_t size, uint32_t config);
/* MISRA-DEV-08: the wrapper passes the caller's layout of the state and its compile-time
 * configuration, which the init checks (RFE_ERR_ABI). Not in the source that defines the
 * function (RFE_MONITOR_IMPL), where the name is the function's own. */
#if !defined(RFE_MONITOR_IMPL)
#if defined(RFE_REAL_DOUBLE)
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_monitor_init_f64(mon, p, dt) \
    rfe_monitor_init_f64((mon), (p), (dt), sizeof(rfe_monitor_t), RFE_CONFIG_REAL)
#else
/* cppcheck-suppress misra-c2012-2.5 ; MISRA-DEV-08: the application's entry, unused by the library */
#define rfe_monitor_init_f32(mon, p, dt) \
    rfe_monitor_init_f32((mon), (p), (dt), sizeof(rfe_monitor_t), RFE_CONFIG_REAL)
#endif
#endif

/**
 * One step with an innovation: during the warm-up it only counts; after it, the averages
 * and the hysteresis advance.
 * @param[in] nu    the innovation y - z_hat (RFE_MEAS values)
 * @param[in] Szz   lower factor of its covariance (RFE_MEAS x RFE_MEAS, row-major, ld
 *                  RFE_MEAS; only the lower triangle is read), non-zero diagonal
 * @param[in] pers  the diagonal of the persistent part of S_zz S_zz^T (RFE_MEAS values,
 *                  >= 0; each share is clipped to [0, 1])
 * @param[out] fired 1 when the monitor is fired after this step, else 0 (may be NULL)
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NONFINITE (an input, or a
 *         statistic that overflows); RFE_ERR_NOT_POSITIVE_DEFINITE (a zero diagonal of Szz).
 *         On error the state is untouched.
 */
RFE_NODISCARD rfe_status_t rfe_monitor_step(rfe_monitor_t *mon, const rfe_real_t nu[RFE_MEAS],
                                           const rfe_real_t Szz[RFE_MEAS * RFE_MEAS],
                                           const rfe_real_t pers[RFE_MEAS], uint32_t *fired);

/**
 * The factor for the reported sd: sqrt(max(1, D / m)) while fired and inflate = 1, else 1.
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED.
 */
RFE_NODISCARD rfe_status_t rfe_monitor_inflation(const rfe_monitor_t *mon, rfe_real_t *c);

/**
 * The fire and clear thresholds at persistent shares @p c (each clipped to [0, 1]), with
 * @p mon's weights and quantiles (docs/MONITOR.md §2 items 4-5).
 * @return RFE_OK; RFE_ERR_NULL; RFE_ERR_NOT_INITIALISED; RFE_ERR_NONFINITE (a share).
 */
RFE_NODISCARD rfe_status_t rfe_monitor_limits(const rfe_monitor_t *mon,
                                             const rfe_real_t c[RFE_MEAS],
                                             rfe_monitor_limits_t *out);

#endif /* RFE_MONITOR_H */
