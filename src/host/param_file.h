/**
 * @file param_file.h
 * @brief Precision-independent parameter set (DATA.md keys, as doubles) with its sources:
 *        a preset of the library < a sensor log's `# key = value` metadata < an explicit
 *        parameter file.
 *
 * Host only. The replay code (replay_real.h) fills a set from a library preset
 * (rfe_param_set_preset_f64, rfe_param_set_default) and converts it to rfe_params_t of
 * either precision.
 */
#ifndef RFE_HOST_PARAM_FILE_H
#define RFE_HOST_PARAM_FILE_H

#include <stddef.h>

#include "csv_log.h"
#include "rfe/mass_grade_bits.h"
#include "rfe/params.h"
#include "rfe/tyre_id_params.h"
#include "text_io.h"

/**
 * THE key table: X(key, rfe_params_t member, unit, doc), one line per numeric DATA.md key,
 * in the order they are written to estimate-log metadata. It holds no values: every key
 * starts from a preset of the library (rfe_params_default / rfe_params_paper, copied by
 * rfe_param_set_preset_f64 in replay_real.h), so the library is the one source of preset
 * values. Adding a numeric key to the library is one line here.
 */
#define RFE_PARAM_KEYS(X)                                                                      \
    X(m, vehicle.m, "kg", "vehicle mass")                                                      \
    X(Lf, vehicle.Lf, "m", "CoG to front axle")                                                \
    X(Lr, vehicle.Lr, "m", "CoG to rear axle")                                                 \
    X(Bf, vehicle.Bf, "m", "front track")                                                      \
    X(Br, vehicle.Br, "m", "rear track")                                                       \
    X(R, vehicle.R, "m", "effective rolling radius")                                           \
    X(J, vehicle.J, "kg m^2", "yaw moment of inertia")                                         \
    X(hg, vehicle.hg, "m", "CoG height")                                                       \
    X(g, vehicle.g, "m/s^2", "gravity")                                                        \
    X(Cx_n, tyre.Cx_n, "1", "normalised longitudinal stiffness (paper mode)")                  \
    X(Cy_n, tyre.Cy_n, "1/rad", "normalised cornering stiffness (paper mode)")                 \
    X(cx, tyre.cx, "1", "longitudinal stiffness per unit Fz (absolute, magic modes)")          \
    X(cy, tyre.cy, "1/rad", "cornering stiffness per unit Fz (absolute, magic modes)")         \
    X(eps, tyre.eps, "s/m", "Dugoff velocity-reduction factor")                                \
    X(v_min, tyre.v_min, "m/s", "slip denominator guard")                                      \
    X(alpha_max, tyre.alpha_max, "rad", "slip-angle bound (< pi/2)")                           \
    X(shape_Cx, tyre.shape_Cx, "1", "Magic Formula shape factor C, longitudinal (1 < C < 2)")  \
    X(shape_Ex, tyre.shape_Ex, "1", "Magic Formula curvature factor E, longitudinal (-4..1)") \
    X(shape_Cy, tyre.shape_Cy, "1", "Magic Formula shape factor C, lateral (1 < C < 2)")       \
    X(shape_Ey, tyre.shape_Ey, "1", "Magic Formula curvature factor E, lateral (-4..1)")      \
    X(mu0, filter.mu0, "1", "initial estimate on every wheel")                                 \
    X(sd0, filter.sd0, "1", "initial standard deviation, S0 = sd0 I")                          \
    X(q_mu, filter.q_mu, "1", "process-noise sd per step, S_Q = q_mu I")                       \
    X(r_ax, filter.r_ax, "m/s^2", "ax measurement-noise sd")                                   \
    X(r_ay, filter.r_ay, "m/s^2", "ay measurement-noise sd")                                   \
    X(r_yaw_acc, filter.r_yaw_acc, "rad/s^2", "yaw-acceleration measurement-noise sd")         \
    X(mu_min, filter.mu_min, "1", "lower projection bound")                                    \
    X(mu_max, filter.mu_max, "1", "upper projection bound")                                    \
    X(v_est_min, filter.v_est_min, "m/s", "no measurement update below this vx")              \
    X(sd0_common, filter.sd0_common, "1", "prior sd, common-mode part")                         \
    X(q_common, filter.q_common, "1", "process-noise sd per step, common-mode part")           \
    X(dt, filter.dt, "s", "sample period (input filter)")                                      \
    X(tau_v, filter.tau_v, "s", "complementary-filter time constant for vx, vy (0 = off)")      \
    X(sd_in_delta, filter.sd_in_delta, "rad", "input noise sd of delta")                       \
    X(sd_in_vx, filter.sd_in_vx, "m/s", "input noise sd of the (filtered) vx")                 \
    X(sd_in_vy, filter.sd_in_vy, "m/s", "input noise sd of the (filtered) vy")                 \
    X(sd_in_yaw_rate, filter.sd_in_yaw_rate, "rad/s", "input noise sd of the yaw rate")        \
    X(sd_in_omega, filter.sd_in_omega, "rad/s", "input noise sd of each wheel speed")          \
    X(r_model_rel, filter.r_model_rel, "1", "tyre-model error relative to each acceleration")  \
    X(info_min, filter.info_min, "1/mu^2", "update only with this Fisher information (0 = off)") \
    X(sd_max, filter.sd_max, "1", "bound on every sd (0 = off)")                               \
    X(sd_floor_rel, filter.sd_floor_rel, "1", "floor on sd as a fraction of mu (0 = off)")      \
    X(sd_valid, filter.sd_valid, "1", "valid when sd <= sd_valid (0 = valid when updated)")     \
    X(rear_hold_k, filter.rear_hold_k, "sd", "sides: hold the rear wheels after a move (0 = off)") \
    X(jump_hold_k, filter.jump_hold_k, "sd", "sides: hold both wheels after a step's jump (0 = off)") \
    X(jump_hold_len, filter.jump_hold_len, "m", "sides: the distance a jump holds the wheels")    \
    X(stale_omega, filter.stale_omega, "rad/s", "stale wheel speed: the others' move (0 = off)") \
    X(yaw_check, filter.yaw_check, "rad/s", "yaw-rate input check: largest jump (0 = off)")    \
    X(valid_bound_k, filter.valid_bound_k, "sd", "valid only this many sd above mu_min (0 = off)") \
    X(mon_enable, monitor.enable, "1", "model-validity monitor: 1 acts on valid, status, sd; 0 off") \
    X(mon_tau_nis, monitor.tau_nis, "s", "monitor: time constant of the NIS average")           \
    X(mon_tau_mean, monitor.tau_mean, "s", "monitor: time constant of the innovation means")    \
    X(mon_p_fire, monitor.p_fire, "1", "monitor: per-step false-alarm probability of firing")   \
    X(mon_p_clear, monitor.p_clear, "1", "monitor: the same for clearing (> mon_p_fire)")        \
    X(mon_hold, monitor.hold, "s", "monitor: shortest time fired after the last exceedance")    \
    X(mon_warmup, monitor.warmup, "s", "monitor: evaluated steps at the start that only count") \
    X(mon_inflate, monitor.inflate, "1", "monitor: 1 inflates the sd while fired; 0 not")

/**
 * The velocity observer's keys (docs/OBSERVER.md §2): X(key, rfe_velocity_params_t member,
 * unit, doc), each an rfe_real_t; obs_driven (an integer bit mask) and obs_lat_every (an
 * integer, RFE_PK_OBS_INTS in all) come before them. As
 * above, no values: they start from rfe_velocity_params_default.
 */
#define RFE_OBS_KEYS(X) \
    X(obs_steer_ratio, steer_ratio, "1", "steering-wheel angle / road-wheel angle (a log or sample with swa)") \
    X(obs_dt_min, dt_min, "s", "shortest accepted sample period")                                              \
    X(obs_dt_max, dt_max, "s", "longest accepted sample period")                                               \
    X(obs_q_jerk, q_jerk, "rad/s^3 sqrt(s)", "yaw-jerk density of the yaw-rate differentiator")                \
    X(obs_sd_r, sd_r, "rad/s", "yaw-rate sensor noise")                                                        \
    X(obs_sd_ax, sd_ax, "m/s^2", "ax noise per sample")                                                        \
    X(obs_sd_ay, sd_ay, "m/s^2", "ay noise per sample")                                                        \
    X(obs_q_bx, q_bx, "m/s^2/sqrt(s)", "random walk of the longitudinal offset b_x")                           \
    X(obs_q_by, q_by, "m/s^2/sqrt(s)", "random walk of the lateral offset b_y")                                \
    X(obs_ay_turn, ay_turn, "m/s^2", "a turn: |ay| at least this (driven wheels not free while rolling); 0 is off") \
    X(obs_q_bx_turn, q_bx_turn, "m/s^2/sqrt(s)", "random walk of b_x in a turn while not braking")          \
    X(obs_sd_wheel, sd_wheel, "m/s", "wheel reference noise")                                                  \
    X(obs_sd_wheel_rel, sd_wheel_rel, "1", "wheel reference error relative to vx")                             \
    X(obs_k_gate, k_gate, "sd", "plausibility gate of a wheel")                                                \
    X(obs_k_agree, k_agree, "sd", "wheels this close (in sd) agree: taken although outside the gate")          \
    X(obs_v_stand, v_stand, "m/s", "every wheel below this: standing")                                         \
    X(obs_q_vx_brake, q_vx_brake, "m/s/sqrt(s)", "growth of vx's sd while braking without a wheel")           \
    X(obs_ax_brake_on, ax_brake_on, "m/s^2", "net deceleration that means braking")                            \
    X(obs_ax_drive_on, ax_drive_on, "m/s^2", "net acceleration that means driving")                            \
    X(obs_p_brake_on, p_brake_on, "MPa", "brake pressure that means braking")                                  \
    X(obs_torque_on, torque_on, "N m", "drive torque that marks a wheel driven")                               \
    X(obs_sd_model_ay, sd_model_ay, "m/s^2", "error of the tyre model's lateral acceleration")                 \
    X(obs_model_ay_rel, model_ay_rel, "1", "the same, relative to |ay|")                                       \
    X(obs_sd_model_rdot, sd_model_rdot, "rad/s^2", "error of the tyre model's yaw acceleration")             \
    X(obs_sd_vydot, sd_vydot, "m/s^2", "v-dot_y as noise of the offset's kinematic update")                    \
    X(obs_vydot_rdot, vydot_rdot, "m/s^2 per rad/s^2", "its growth with |r-dot|")                              \
    X(obs_vydot_rerr, vydot_rerr, "m/s^2 per rad/s", "its growth with the yaw rate beyond vx delta / L; 0 is off") \
    X(obs_v_lat_min, v_lat_min, "m/s", "below this vx, vy follows the rear-axle kinematics")                   \
    X(obs_sd_lowspeed, sd_lowspeed, "m/s", "sd of that kinematic vy")                                          \
    X(obs_mu_default, mu_default, "1", "friction the model uses while the friction estimator gives none")      \
    X(obs_sd_mu_default, sd_mu_default, "1", "its sd")                                                         \
    X(obs_mu_margin, mu_margin, "1", "the measured ay raises the model's friction to (1 + margin) |ay| / g")   \
    X(obs_sd_vx0, sd_vx0, "m/s", "initial sd of vx")                                                           \
    X(obs_sd_bx0, sd_bx0, "m/s^2", "initial sd of b_x")                                                        \
    X(obs_sd_vy0, sd_vy0, "m/s", "initial sd of vy")                                                           \
    X(obs_sd_by0, sd_by0, "m/s^2", "initial sd of b_y")                                                        \
    X(obs_sd_vy_lin, sd_vy_lin, "m/s", "sd of the linear range's vy; 0 turns it off")                           \
    X(obs_lin_r_tol, lin_r_tol, "rad/s", "linear range: the yaw rate this close to vx delta / L")               \
    X(obs_lin_r_rel, lin_r_rel, "1", "linear range: plus this share of |vx delta / L|")                        \
    X(obs_lin_ay_max, lin_ay_max, "m/s^2", "linear range: |ay| at most this")                                   \
    X(obs_lin_ay_steady, lin_ay_steady, "m/s^2", "linear range: |ay| at most this in a steady turn")              \
    X(obs_lin_dwell, lin_dwell, "s", "linear range: a steady turn has the yaw rate on vx delta / L this long") \
    X(obs_lin_mu_gain, lin_mu_gain, "1", "in that steady turn the model's friction is at least this times |ay| / g") \
    X(obs_vy_out_floor_mu, vy_out_floor_mu, "1", "reported sd(vy) >= this |vx ay / (cy g)| max sd_mu / mu; 0 is off")

/**
 * The mass and grade estimator's keys (docs/MASS_GRADE.md §6): X(key, rfe_mass_grade_params_t
 * member, unit, doc), each an rfe_real_t; mg_adaptive and mg_use_ax (0 or 1) and the
 * replay's mg_feed_sd_rel, mg_feed_excitation, mg_feed_ax_min, mg_feed_slip_max and
 * mg_feed_band come before them
 * (RFE_PK_MG_SPECIAL). R and g are the vehicle keys
 * above. No values: they start from the library preset
 * the run's --mass-grade names (rfe_mass_grade_params_preset, the car).
 */
#define RFE_MG_KEYS(X) \
    X(mg_fc, fc, "1", "rolling resistance, constant part f_c")                                   \
    X(mg_fr, fr, "s/m", "rolling resistance, speed part f_r")                                    \
    X(mg_rho, rho, "kg/m^3", "air density")                                                      \
    X(mg_cd, cd, "1", "drag coefficient")                                                        \
    X(mg_area, area, "m^2", "frontal area")                                                      \
    X(mg_m_rot, m_rot, "kg", "equivalent mass of the parts the drive torque spins up")           \
    X(mg_m0, m0, "kg", "initial mass")                                                           \
    X(mg_theta0, theta0, "rad", "initial grade")                                                 \
    X(mg_sd_m0, sd_m0, "kg", "initial sd of the mass")                                           \
    X(mg_sd_theta0, sd_theta0, "rad", "initial sd of the grade")                                 \
    X(mg_q_v, q_v, "m/s/sqrt(s)", "process noise density of v")                                  \
    X(mg_q_mc, q_mc, "kg/sqrt(s)", "constant part of the mass process noise")                    \
    X(mg_q_mv0, q_mv0, "kg/sqrt(s)", "initial adaptive part of the mass process noise (AUKF)")   \
    X(mg_q_theta, q_theta, "rad/sqrt(s)", "process noise density of the grade")                  \
    X(mg_r_v, r_v, "m/s", "speed measurement noise sd")                                          \
    X(mg_r_ax, r_ax, "m/s^2", "accelerometer row noise sd (sensor and model)")                   \
    X(mg_ut_alpha, ut_alpha, "1", "unscented transform: spread alpha")                           \
    X(mg_ut_beta, ut_beta, "1", "unscented transform: prior parameter beta")                     \
    X(mg_ut_kappa, ut_kappa, "1", "unscented transform: secondary scaling kappa")                \
    X(mg_t_adapt, t_adapt, "s", "adaptation period (0: every step)")                             \
    X(mg_mv_stop, mv_stop, "1", "the adaptation ends at q_mv <= mg_mv_stop q_mc^2")              \
    X(mg_v_min, v_min, "m/s", "below this speed the filter holds")                               \
    X(mg_t_brake, t_brake, "s", "hold after the last braked sample")                             \
    X(mg_t_shift, t_shift, "s", "hold after a gear change")                                      \
    X(mg_p_brake_on, p_brake_on, "Pa", "brake pressure that means braking")                      \
    X(mg_slip_max, slip_max, "1", "wheel slip against a given vx that holds the filter (0: off)") \
    X(mg_ay_max, ay_max, "m/s^2", "a given |ay| above it holds the filter (0: off)")              \
    X(mg_t_curve, t_curve, "s", "hold after the last sample over mg_ay_max")                     \
    X(mg_pause_grade, pause_grade, "-", "pauses that learn the grade from ax (mg_use_ax 1): 1 brake + 2 shift + 4 curve (0: none)") \
    X(mg_pause_grade_slip, pause_grade_slip, "1", "ABS gate: wheel slip against a given vx that ends the grade's learning until the pause ends (0: off)") \
    X(mg_pause_grade_dv, pause_grade_dv, "m/s", "change test: the pause learns the grade once the speed (vx if given) leaves the held grade's prediction by this (0: at once)") \
    X(mg_m_min, m_min, "kg", "lower mass bound")                                                 \
    X(mg_m_max, m_max, "kg", "upper mass bound")                                                 \
    X(mg_theta_max, theta_max, "rad", "grade bound")                                             \
    X(mg_dt_max, dt_max, "s", "a longer sample period restarts the filter")                   \
    X(mg_q_theta_hi, q_theta_hi, "rad/sqrt(s)", "the grade's looser walk while the grade moves (0: off)") \
    X(mg_theta_rate_on, theta_rate_on, "rad/s", "grade rate RMS above which the walk loosens") \
    X(mg_theta_rate_off, theta_rate_off, "rad/s", "grade rate RMS below which it tightens")   \
    X(mg_theta_rate_tau, theta_rate_tau, "s", "the grade rate's low-pass time constant")     \
    X(mg_theta_rate_avg, theta_rate_avg, "s", "time constant of the mean of its square")   \
    X(mg_mm_tau, mm_tau, "s", "time constant of the ax row's mismatch monitor (EMA)")          \
    X(mg_mm_e, mm_e, "1", "mismatch flag's threshold on the EMA's magnitude (0: off)")

/**
 * The tyre identifier's keys (docs/TYRE_ID.md §2): X(key, rfe_tyre_id_params_t member, unit,
 * doc), each an rfe_real_t; tid_filter and tid_resample (words), tid_substeps (an integer) and
 * tid_seed (the init's seed, no member) come before them (RFE_PK_TID_SPECIAL). The vehicle and
 * the prior's tyre data are the friction estimator's keys. No values: they start from
 * rfe_tyre_id_params_default. The particle count is RFE_TID_N, fixed at compile time: no key.
 */
#define RFE_TID_KEYS(X) \
    X(tid_v_min, v_min, "m/s", "below this vx (this or the previous sample) the identifier holds") \
    X(tid_dt_max, dt_max, "s", "longest sample period; a longer one starts the identifier afresh") \
    X(tid_sd_r, sd_r, "rad/s", "likelihood sd of the yaw rate")                                  \
    X(tid_sd_ay, sd_ay, "m/s^2", "likelihood sd of ay")                                          \
    X(tid_sd_delta, sd_delta, "rad", "steering-angle noise through each particle's front slope") \
    X(tid_q_vy, q_vy, "m/s/sqrt(s)", "process noise density of vy")                              \
    X(tid_q_r, q_r, "rad/s/sqrt(s)", "process noise density of r")                               \
    X(tid_q_mu, q_mu, "1/sqrt(s)", "random walk of D/Fz0")                                       \
    X(tid_q_C, q_C, "1/sqrt(s)", "random walk of C")                                             \
    X(tid_q_cy, q_cy, "1/rad/sqrt(s)", "random walk of K/Fz0")                                   \
    X(tid_q_E, q_E, "1/sqrt(s)", "random walk of E")                                             \
    X(tid_mu0, mu0, "1", "prior mean of D/Fz0")                                                  \
    X(tid_sd0_mu, sd0_mu, "1", "prior sd of D/Fz0")                                              \
    X(tid_sd0_C, sd0_C, "1", "prior sd of C (mean shape_Cy)")                                    \
    X(tid_sd0_E, sd0_E, "1", "prior sd of E (mean shape_Ey)")                                    \
    X(tid_sd0_cy_rel, sd0_cy_rel, "1", "prior sd of K/Fz0 relative to its mean cy")              \
    X(tid_sd0_vy, sd0_vy, "m/s", "prior sd of vy (mean 0)")                                      \
    X(tid_sd0_r, sd0_r, "rad/s", "prior sd of r (mean: the first yaw rate)")                     \
    X(tid_mu_lo, mu_lo, "1", "lower bound of D/Fz0")                                             \
    X(tid_mu_hi, mu_hi, "1", "upper bound of D/Fz0")                                             \
    X(tid_C_lo, C_lo, "1", "lower bound of C")                                                   \
    X(tid_C_hi, C_hi, "1", "upper bound of C")                                                   \
    X(tid_cy_lo, cy_lo, "1/rad", "lower bound of K/Fz0")                                         \
    X(tid_cy_hi, cy_hi, "1/rad", "upper bound of K/Fz0")                                         \
    X(tid_E_lo, E_lo, "1", "lower bound of E")                                                   \
    X(tid_E_hi, E_hi, "1", "upper bound of E")                                                   \
    X(tid_neff_frac, neff_frac, "1", "resample when N_eff < tid_neff_frac N")                    \
    X(tid_rough_k, rough_k, "1", "roughening constant K")                                        \
    X(tid_ellipse, ellipse, "-", "1: each axle's lateral force under ax (its load, the friction ellipse); 0: lateral only") \
    X(tid_fx_front, fx_front, "1", "the front axle's share of m ax (brake balance) for tid_ellipse") \
    X(tid_ell_min, ell_min, "1", "the smallest factor tid_ellipse leaves of a lateral force") \
    X(tid_ell_ax_min, ell_ax_min, "m/s^2", "tid_ellipse's dead band: below this |ax| ax is taken as 0 (0: none)") \
    X(tid_delta_q, delta_q, "rad/s^2/sqrt(s)", "steering-angle filter's noise density (0: delta as measured)") \
    X(tid_delta_state_q, delta_state_q, "rad/sqrt(s)", "sckf: delta as a state, its random walk's density (0: off)")

/** Index of each key: the friction estimator's numeric keys RFE_PK_m, RFE_PK_Lf, ...; its
 *  three word-valued keys; then the observer's keys, obs_driven first; then the mass and
 *  grade estimator's, mg_adaptive, mg_use_ax and the replay's five mg_feed_* first; then
 *  the tyre identifier's, tid_filter, tid_resample, tid_substeps, tid_seed, tid_feed_sd_rel,
 *  tid_feed_evidence and tid_feed_ax_max first. */
typedef enum {
#define RFE_PK_ENUM_(key, member, unit, doc) RFE_PK_##key,
    RFE_PARAM_KEYS(RFE_PK_ENUM_)
    RFE_PK_TYRE,        /**< key tyre = paper|absolute|magic */
    RFE_PK_FILTER,      /**< key filter = sckf|ckf */
    RFE_PK_STRUCTURE,   /**< key structure = wheels|sides */
    RFE_PK_obs_driven,  /**< key obs_driven: driven wheels, bit mask fl 1, fr 2, rl 4, rr 8 */
    RFE_PK_obs_lat_every, /**< key obs_lat_every: the lateral model's rows every n-th step */
    RFE_OBS_KEYS(RFE_PK_ENUM_)
    RFE_PK_mg_adaptive, /**< key mg_adaptive: 1 the seed's AUKF, 0 the plain UKF */
    RFE_PK_mg_use_ax,   /**< key mg_use_ax: 1 the accelerometer row, 0 speed only */
    /** key mg_feed_sd_rel: a replay key, not a library parameter (no member of
     *  rfe_mass_grade_params_t): the replay feeds the friction estimator the estimated mass
     *  after an update with sd_mass <= mg_feed_sd_rel * mass_est (0 = never; MASS_GRADE.md
     *  §10). Kept with the mg_* keys so files, metadata and the estimate log's metadata treat
     *  it as every mass and grade key. */
    RFE_PK_mg_feed_sd_rel,
    /** key mg_feed_excitation (m/s): a replay key (no member): the feed waits until the
     *  longitudinal excitation since the estimator's start (the sum of |ax| dt over its updates
     *  with |ax| >= mg_feed_ax_min) reaches this: a mass identified from the accelerometer's
     *  specific force (inertia and grade), not from the rolling and drag resistances alone
     *  (0 = no gate; MASS_GRADE.md §10). */
    RFE_PK_mg_feed_excitation,
    /** key mg_feed_ax_min (m/s^2): a replay key (no member): the smallest |ax| that counts as
     *  excitation for mg_feed_excitation. */
    RFE_PK_mg_feed_ax_min,
    /** key mg_feed_slip_max (1): a replay key (no member): an update whose wheels' speed
     *  departs from the car's by more than this share of it, |v_wheels - vx| / max(|vx|,
     *  mg_v_min), is not fed and empties the excitation gate's sum (the driven wheels slip:
     *  the estimator's speed and drive force are not the car's; 0 = no slip hold;
     *  MASS_GRADE.md §10). */
    RFE_PK_mg_feed_slip_max,
    /** key mg_feed_band (1): a replay key (no member): a mass otherwise due is fed only when
     *  |mass_est - m| <= mg_feed_band * m, m the friction estimator's parameter; a refusal is
     *  counted (0 = no band; MASS_GRADE.md §10). */
    RFE_PK_mg_feed_band,
    RFE_MG_KEYS(RFE_PK_ENUM_)
    RFE_PK_tid_filter,   /**< key tid_filter = apf|sir (rfe_tid_filter_t; mu_replay --tyre-id) */
    RFE_PK_tid_resample, /**< key tid_resample = multinomial|systematic (rfe_tid_resample_t) */
    RFE_PK_tid_substeps, /**< key tid_substeps: RK4 steps per sample period, an integer */
    /** key tid_seed: the key word k0 of the identifier's random stream, the argument of
     *  rfe_tyre_id_init (no member of rfe_tyre_id_params_t); an integer 0 .. 2^53, which a
     *  double holds exactly. */
    RFE_PK_tid_seed,
    /** key tid_feed_sd_rel: a replay key (no member): the friction estimator takes the
     *  identified lateral curve after an update whose summed cornering stiffness has a
     *  relative sd <= tid_feed_sd_rel (0 = never, the default; TYRE_ID.md §14). */
    RFE_PK_tid_feed_sd_rel,
    /** key tid_feed_evidence (s): a replay key (no member): the feed starts only once the
     *  friction estimator has spent this long, summed, with status 1 (its mean projected onto
     *  a μ bound) or 4 (model mismatch), its own evidence that its curve is wrong (0, the
     *  default: from the start; TYRE_ID.md §14). */
    RFE_PK_tid_feed_evidence,
    /** key tid_feed_ax_max (m/s^2): a replay key (no member): no curve is fed after a sample
     *  whose |ax| exceeds this (braking or driving: the tyres' combined slip lowers the lateral
     *  force the identifier's lateral-only model reads, TYRE_ID.md §3.3), the friction
     *  estimator keeping the curve it has (0 = no hold; TYRE_ID.md §14). */
    RFE_PK_tid_feed_ax_max,
    /** key tid_feed_refresh (s): a replay key (no member): after a sample that taints the
     *  identifier's curve (held by tid_feed_ax_max, or implausible by tid_feed_outlier_k) no
     *  curve is fed until the identifier has updated on this long, summed, of untainted
     *  samples with |ay| >= tid_feed_outlier_k * tid_sd_ay, and then first at a sample with
     *  |ay| below that (0 = off, the default; MONITOR.md §7). */
    RFE_PK_tid_feed_refresh,
    /** key tid_feed_outlier_k (1): a replay key (no member), used when tid_feed_refresh > 0:
     *  a sample is implausible when |ay - ay_p| > tid_feed_outlier_k * tid_sd_ay, ay_p the
     *  lateral acceleration of the identifier's last estimate; the first of a taint sets the
     *  friction estimator's model error back to the set's r_model_rel before its step
     *  (0 = no test; MONITOR.md §7). */
    RFE_PK_tid_feed_outlier_k,
    RFE_TID_KEYS(RFE_PK_ENUM_)
#undef RFE_PK_ENUM_
    RFE_PK_COUNT        /**< number of keys */
} rfe_param_key_t;

/** Number of the friction estimator's numeric keys (the first RFE_PK_NUMERIC indices). */
#define RFE_PK_NUMERIC ((size_t)RFE_PK_TYRE)
/** The observer's keys: indices RFE_PK_OBS_FIRST .. RFE_PK_MG_FIRST - 1, all numeric. */
#define RFE_PK_OBS_FIRST ((size_t)RFE_PK_obs_driven)
/** The observer's integer keys, obs_driven and obs_lat_every, before its real ones. */
#define RFE_PK_OBS_INTS 2u
/** The mass and grade estimator's keys: indices RFE_PK_MG_FIRST .. RFE_PK_TID_FIRST - 1, all
 *  numeric. */
#define RFE_PK_MG_FIRST ((size_t)RFE_PK_mg_adaptive)
/** The tyre identifier's keys: indices RFE_PK_TID_FIRST .. RFE_PK_COUNT - 1 (tid_filter and
 *  tid_resample take words, stored as their enum values; the others numbers). */
#define RFE_PK_TID_FIRST ((size_t)RFE_PK_tid_filter)
#define RFE_PK_OBS_COUNT (RFE_PK_MG_FIRST - RFE_PK_OBS_FIRST)
#define RFE_PK_MG_COUNT (RFE_PK_TID_FIRST - RFE_PK_MG_FIRST)
#define RFE_PK_TID_COUNT ((size_t)RFE_PK_COUNT - RFE_PK_TID_FIRST)

/** The mass and grade keys before the RFE_MG_KEYS table: mg_adaptive, mg_use_ax,
 *  mg_feed_sd_rel, mg_feed_excitation, mg_feed_ax_min, mg_feed_slip_max, mg_feed_band. */
#define RFE_PK_MG_SPECIAL 7u

/** mg_feed_sd_rel of every preset: fed once sd_mass / mass_est <= 2 % (MASS_GRADE.md §10). */
#define RFE_MG_FEED_SD_REL_DEFAULT 0.02

/** mg_feed_excitation of every preset: 1 m/s of |ax| dt since the start (MASS_GRADE.md §10:
 *  the mass and grade logs reach it 0-1.3 s after their first feed by the sd rule, the observer
 *  logs' steady cruise and banked curves, which fed a wrong mass, never). */
#define RFE_MG_FEED_EXCITATION_DEFAULT 1.0

/** mg_feed_ax_min of every preset: 0.2 m/s^2, above the accelerometer's noise on a steady
 *  cruise and above the rolling resistance's g (f_c + f_r v) of a car (0.10-0.14 m/s^2), so
 *  an update counted is one whose force balance the resistances do not dominate
 *  (MASS_GRADE.md §10). */
#define RFE_MG_FEED_AX_MIN_DEFAULT 0.2

/** mg_feed_slip_max of every preset: 0.05, five times the largest 99th percentile of
 *  |v_wheels - vx| / vx on the observer logs that do not slip (0.01) and below the traction
 *  logs' 0.08-0.18 on mu = 0.3 (MASS_GRADE.md §10). */
#define RFE_MG_FEED_SLIP_MAX_DEFAULT 0.05

/** mg_feed_band of every preset: 0.3, wider than a passenger car's load range (1 500-2 100
 *  kg, +-17 % around its middle) and than a parameter m 20 % low (the truth then +25 %), so
 *  a right mass is fed whatever m within +-20 % was given (MASS_GRADE.md §10). */
#define RFE_MG_FEED_BAND_DEFAULT 0.3

/** The tyre identifier's keys before the RFE_TID_KEYS table: tid_filter, tid_resample,
 *  tid_substeps, tid_seed, tid_feed_sd_rel, tid_feed_evidence, tid_feed_ax_max,
 *  tid_feed_refresh, tid_feed_outlier_k. */
#define RFE_PK_TID_SPECIAL 9u

/** tid_feed_sd_rel of every preset: 0, the identified curve is not fed (TYRE_ID.md §14). */
#define RFE_TID_FEED_SD_REL_DEFAULT 0.0

/** tid_feed_evidence of every preset: 0 s, the feed (when on) needs no evidence first. */
#define RFE_TID_FEED_EVIDENCE_DEFAULT 0.0

/** tid_feed_ax_max of every preset: 0.5 m/s^2. The steering logs' braking reaches 0.9-1.1
 *  m/s^2 on low mu and 2.5 m/s^2 on high mu, their cornering at a steady speed at most
 *  0.56 m/s^2 (drag and noise, on 1 % of the samples); a fed curve identified under braking
 *  raised brake_in_turn.mf's RMSE when valid from 0.139 to 0.325 (TYRE_ID_RESULTS.md). */
#define RFE_TID_FEED_AX_MAX_DEFAULT 0.5

/** tid_feed_refresh of every preset: 0 s, off (MONITOR.md §7: measured at 1 s, not adopted). */
#define RFE_TID_FEED_REFRESH_DEFAULT 0.0

/** tid_feed_outlier_k of every preset: 5, i.e. 1 m/s^2 at tid_sd_ay 0.2; a Gaussian
 *  residual exceeds 5 sd on about 6e-7 of the samples. Only read when tid_feed_refresh > 0
 *  (MONITOR.md §7: 4 and 6 gave the same logs meeting the trust invariant). */
#define RFE_TID_FEED_OUTLIER_K_DEFAULT 5.0

/** tid_seed of every preset (docs/TYRE_ID.md §2). */
#define RFE_TID_SEED_DEFAULT 1.0

/** Largest tid_seed: 2^53, up to which a double holds every integer. */
#define RFE_TID_SEED_MAX 9007199254740992.0

/** 1 when key @p k is an observer key (obs_*). */
static inline int rfe_param_is_obs(size_t k)
{
    return ((k >= RFE_PK_OBS_FIRST) && (k < RFE_PK_MG_FIRST)) ? 1 : 0;
}

/** 1 when key @p k is a mass and grade key (mg_*). */
static inline int rfe_param_is_mg(size_t k)
{
    return ((k >= RFE_PK_MG_FIRST) && (k < RFE_PK_TID_FIRST)) ? 1 : 0;
}

/** 1 when key @p k is a tyre identifier key (tid_*). */
static inline int rfe_param_is_tid(size_t k)
{
    return ((k >= RFE_PK_TID_FIRST) && (k < (size_t)RFE_PK_COUNT)) ? 1 : 0;
}

/** 1 when key @p k takes a word of the tyre identifier (tid_filter, tid_resample). */
static inline int rfe_param_is_tid_word(size_t k)
{
    return ((k == (size_t)RFE_PK_tid_filter) || (k == (size_t)RFE_PK_tid_resample)) ? 1 : 0;
}

/** 1 when key @p k takes a word (tyre, filter, structure), not a number. */
static inline int rfe_param_is_word(size_t k)
{
    return ((k >= RFE_PK_NUMERIC) && (k < RFE_PK_OBS_FIRST)) ? 1 : 0;
}

/** "No key" answer of rfe_param_find and the replay's diagnosis. */
#define RFE_PK_NONE ((size_t)RFE_PK_COUNT)

/** Description of one key (from the table above). */
typedef struct {
    const char *key;
    const char *unit;
    const char *doc;
} rfe_param_info_t;

/** The base parameter sets of the library (include/rfe/params.h). */
typedef enum {
    RFE_PRESET_DEFAULT = 0, /**< rfe_params_default: the library's current best configuration */
    RFE_PRESET_PAPER = 1    /**< rfe_params_paper: the paper's configuration (reference baseline) */
} rfe_preset_t;

/** Where a key's value came from, for messages and metadata. */
typedef struct {
    const char *file;   /**< NULL = the preset; "command line"; else a file name (not owned) */
    size_t line;        /**< 1-based line in that file, 0 if none */
} rfe_param_origin_t;

/** The parameter set: every key's value as a double, plus the three word keys, and the
 *  preset it started from (the replay starts rfe_params_t from the same preset, so a
 *  library field without a key follows the preset too). */
typedef struct {
    rfe_preset_t preset;
    double value[RFE_PK_NUMERIC];
    double obs[RFE_PK_OBS_COUNT]; /**< the observer's keys, index k - RFE_PK_OBS_FIRST */
    double mg[RFE_PK_MG_COUNT];   /**< the mass and grade keys, index k - RFE_PK_MG_FIRST */
    double tid[RFE_PK_TID_COUNT]; /**< the tyre identifier's keys, index k - RFE_PK_TID_FIRST
                                       (its words as their enum values) */
    rfe_tyre_mode_t tyre;
    rfe_filter_kind_t filter;
    rfe_structure_t structure;
    rfe_param_origin_t origin[RFE_PK_COUNT];
    int mass_grade;            /**< nonzero: the replay runs the mass and grade estimator on a
                                    log with drive_torque (mu_replay --mass-grade; 0 in every
                                    preset, so a plain replay runs as before) */
    rfe_mg_vehicle_t mg_vehicle; /**< the vehicle of that preset (mu_replay
                                      --mass-grade-vehicle car|truck; car by default) */
    rfe_mg_config_t mg_config; /**< the library preset the mg_* values started from (for the
                                    diagnosis of an invalid one) */
    int tyre_id;               /**< nonzero: the replay runs the tyre identifier beside the
                                    friction estimator (mu_replay --tyre-id apf|sir; 0 in every
                                    preset) */
} rfe_param_set_t;

/** Info for key index @p k (< RFE_PK_COUNT), or NULL. */
const rfe_param_info_t *rfe_param_info(size_t k);

/** Index of the key named @p name, or RFE_PK_NONE. */
size_t rfe_param_find(const char *name);

/** Value of a key as text (numbers round-trip; tyre/filter/structure as their words). */
void rfe_param_format(const rfe_param_set_t *ps, size_t k, char buf[RFE_NUM_BUF]);

/**
 * Sets key @p k from text @p value (a finite decimal number, or a word for
 * tyre/filter/structure).
 * @return RFE_NUM_OK, else the reason (RFE_NUM_SYNTAX for an unknown word).
 */
RFE_NODISCARD rfe_num_status_t rfe_param_set_text(rfe_param_set_t *ps, size_t k,
                                                  const char *value);

/**
 * Applies a parameter file: `key = value` lines, '#' starts a comment anywhere on a line,
 * blank lines ignored. Errors (set left partly applied): unknown key (FILE:LINE:COL of the
 * key), a line without '=', a malformed value (FILE:LINE:COL of the value), a key given twice.
 * @return 0, or -1 with @p err filled (err->file = @p path).
 */
RFE_NODISCARD int rfe_param_set_apply_file(rfe_param_set_t *ps, const char *path,
                                           rfe_io_error_t *err);

/** As rfe_param_set_apply_file, from a stream; @p name is used in messages and origins. */
RFE_NODISCARD int rfe_param_set_apply_stream(rfe_param_set_t *ps, FILE *f, const char *name,
                                             rfe_io_error_t *err);

/**
 * Applies the known keys among a sensor log's metadata; unknown keys are information and
 * ignored. A malformed value of a known key is an error naming @p log_name and its line.
 */
RFE_NODISCARD int rfe_param_set_apply_meta(rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                           const char *log_name, rfe_io_error_t *err);

/** Word of a tyre mode / filter kind / structure / preset ("paper", "sckf", "sides",
 *  "default", ...; "?" when out of range). */
const char *rfe_tyre_mode_str(rfe_tyre_mode_t m);
const char *rfe_filter_kind_str(rfe_filter_kind_t k);
const char *rfe_structure_str(rfe_structure_t s);
const char *rfe_preset_str(rfe_preset_t p);

/** Parses "paper"/"absolute"/"magic", "sckf"/"ckf", "wheels"/"sides" and "default"/"paper"
 *  (case-sensitive); 0 on success, -1 otherwise (@p out then untouched). */
RFE_NODISCARD int rfe_tyre_mode_parse(const char *s, rfe_tyre_mode_t *out);
RFE_NODISCARD int rfe_filter_kind_parse(const char *s, rfe_filter_kind_t *out);
RFE_NODISCARD int rfe_structure_parse(const char *s, rfe_structure_t *out);
RFE_NODISCARD int rfe_preset_parse(const char *s, rfe_preset_t *out);

/** Word of the tyre identifier's filter ("apf", "sir") and resampling ("multinomial",
 *  "systematic"); "?" when out of range. */
const char *rfe_tid_filter_str(rfe_tid_filter_t f);
const char *rfe_tid_resample_str(rfe_tid_resample_t r);

/** Parses "apf"/"sir" and "multinomial"/"systematic" (case-sensitive); 0 on success, -1
 *  otherwise (@p out then untouched). */
RFE_NODISCARD int rfe_tid_filter_parse(const char *s, rfe_tid_filter_t *out);
RFE_NODISCARD int rfe_tid_resample_parse(const char *s, rfe_tid_resample_t *out);

#endif /* RFE_HOST_PARAM_FILE_H */
