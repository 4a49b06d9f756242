/**
 * @file test_velocity_q31.c
 * @brief The fixed-point velocity observer (rfe_velocity_*_q31) and its parameters: the
 *        API contract (input validation, untouched state on every error status), the
 *        parameter defaults and conversion, the first sample, the steering-wheel input, and
 *        back to back against the double observer (_f64) on every observer scenario.
 *
 * How the two are fed (end to end, like test_friction_q31.c): the double observer gets the
 * log's samples and the double parameters (the default preset and the log's metadata, the
 * observer's defaults); the q31 observer gets the samples rounded to their Q formats and the
 * parameters converted by rfe_params_to_q31_f64 / rfe_velocity_params_to_q31_f64. The
 * friction input is the log's truth with sd 0.05 (as the goldens), NULL without truth.
 *
 * Bounds (each output, at every step of all 50 scenarios; measured worst cases are printed
 * and quoted in docs/FIXED_POINT.md "Observer").
 *  - The error sources per step: the inputs' rounding (0.5 LSB: 3e-8 m/s^2 on ax, ay,
 *    6e-8 m/s^2 Q24; 1.2e-7 rad/s Q22 on omega, so 4e-8 m/s on a wheel reference; 4e-9
 *    rad/s on r), the parameters' rounding (relative 2^-24 at worst, sd_r: 2e-6 relative of
 *    0.005 in Q27), the filters' arithmetic (kf2_q31: 1 LSB plus 2^-28 of the correction,
 *    test_kf2_q31.c), dt's rounding (2e-8 relative in Q30) and the measurement model (1.6e-6
 *    m/s^2 per evaluation, test_meas_q31.c), which enters the lateral filter's innovation
 *    directly; its H is the analytic derivative (rfe_meas_lateral_jac_q31), within 1e-5 of
 *    the wheels' term scale of the double's (test_meas_q31.c: 2.4e-4 1/s at 15 m/s, 1e-3 at
 *    the 3 m/s where the model starts; measured at most 1.3 % of that bound), which the
 *    3.2e-4 1/s on h0 ~ 1..50 1/s used below (the former difference over 0.01 m/s: 2 x
 *    1.6e-6 / 0.01) covers above ~11 m/s and the measured error everywhere: at most 3e-4
 *    relative of the model's gain.
 *  - The filters are stable (gains in (0, 1), the same on both sides), so these per-step
 *    errors do not accumulate beyond their memory: vx integrates ax with a wheel gain near
 *    0.1 per step while a wheel corrects it; while none does (ABS braking for seconds) it
 *    integrates the ax error for up to 800 steps: 800 x 0.01 s x 6e-8 m/s^2 = 5e-7 m/s,
 *    plus the same of the offset's drift. TOL_VX = 1e-4 m/s is 100 times that, and 400 Q23
 *    LSB: it also covers a trajectory where a wheel sits on its gate and one twin takes it
 *    one step before the other (such a step is then off by at most the wheel's gate share
 *    of the innovation, and is forgotten at the filter's rate; these steps are counted by
 *    the flags, below).
 *  - vy: the model's gain error (3e-4 relative) times the model innovation (< 1 m/s^2)
 *    times the lateral gain (K0 ~ 0.01 s): 3e-6 m/s per step, forgotten within ~ 30
 *    steps: 1e-4 m/s. The yaw row (OBSERVER.md §4.2, second update) adds its own: its
 *    h1 = d r-dot / d vy carries the same 3.2e-4 1/s absolute error (the model's r-dot row,
 *    the same analytic derivative), which changes its gain K = p00 h1 / (h1^2 p00 + R1) by
 *    at most p00 / R1 times that (|dK/dh1| <= p00 / S); on an innovation within 3 sqrt(S)
 *    the correction's error is <= 3 p00 / sqrt(R1) x 3.2e-4 <= 3 x 0.05^2 / 0.3 x 3.2e-4 =
 *    8e-6 m/s per step (R1 >= sd_model_rdot^2 = 0.09; sd_vy <= 0.05 m/s, as on 98 % of
 *    the logs' model steps), forgotten within ~ 30 steps: 2.4e-4 m/s; its innovation's own
 *    error (the model's 1.6e-6 and the differentiator's r-dot, 5e-7 measured, rad/s^2)
 *    times K <= sd_vy / (2 sd_model_rdot) = 0.08 adds < 2e-7 per step. TOL_VY = 5e-4 m/s
 *    covers the sum 3.5e-4. Where sd_vy is larger (up to 0.21 m/s where the tyres
 *    saturate, sine_dwell_mu035.mf) this estimate is no bound; the measured worst over all
 *    logs, 6.9e-6 m/s, lies there, 70 times inside TOL_VY.
 *    beta = vy / vx at vx >= 3 m/s: TOL_BETA = 2e-4 rad.
 *  - yaw_acc: the differentiator amplifies the r input rounding (4e-9 rad/s) by its gain
 *    K1 / dt ~ 10 1/s^... (0.053 rad/s^2 out of 0.005 rad/s in, REQ-OBS-005: x 10.6): 5e-8
 *    rad/s^2, and sd_r's rounding changes its gain by ~2e-6 relative on r-dot < 10
 *    rad/s^2: 2e-5; TOL_RDOT = 1e-4 rad/s^2.
 *  - sds: the covariances' rounding (1 LSB per operation, relative 2^-28 of the gain)
 *    and the parameters' (2^-24): 1e-6 relative of sds < 1: TOL_SD = 1e-5 (sd_yaw_acc: the
 *    sd_r rounding, 2e-6 relative, on 0.05..1 rad/s^2: 1e-5 too).
 *  - Decision splits. A threshold (a wheel's gate, the braking or driving acceleration,
 *    vx reaching 0) that a value crosses within an LSB may be decided one step apart by the
 *    two twins; the flags then differ. The bounds above hold on every step up to a log's
 *    first differing flags. From there on the longitudinal filter may have taken one wheel
 *    correction more: at most its gain (p00 / (p00 + r) < 0.01 at the settled sd 0.0045
 *    m/s and the wheel noise 0.05 m/s) times the gate (3 sqrt(p00 + r) = 0.15 m/s), 1.5e-3
 *    m/s, plus the offset's share, which integrates until the next correction joins the
 *    two again: TOL_VX_SPLIT = 2e-3 m/s; and one twin's sd_vx may grow uncorrected while
 *    the other's is corrected, by at most the growth of an uncorrected filter over the
 *    split (sd_ax dt per step and sd(b_x) t: 0.01 + 0.01 x 4 s): TOL_SD_SPLIT = 0.05 m/s.
 *    vy, beta and r-dot keep their bounds (vx enters them only through r vx, r small
 *    where a split happens). Flags agree on >= 90 % of each log's steps
 *    (MIN_FLAG_AGREE_LOG) and on >= 99.9 % of all steps (MIN_FLAG_AGREE_ALL): measured, one
 *    split on the 50 logs (creep_stop.nf: the braking onset of a noise-free deceleration
 *    ramp, decided one step apart; 117 steps until both have stopped).
 *  - Saturation: 0 on every log: speeds < 60 m/s (Q23: 256), wheel speeds < 200 rad/s
 *    (Q22: 512), accelerations and r-dot < 30 (Q24: 128), pressures < 20 MPa (Q25: 64),
 *    torques < 5000 N m (Q15: 65536), variances far inside 2^61.
 */
#include "test_light.h"
#include "test_common.h"

#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "csv_log.h"
#include "host/fixed_conv.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/component/params_conv.h"
#include "test_params_both.h"
#include "rfe/params_q31.h"
#include "rfe/velocity.h"
#include "rfe/velocity_q31.h"

#include "numerics/fxmath_internal_q31.h"

#define OBS_DIR "scenarios/observer"
#define MIN_LOGS 50 /* the bundled observer scenarios; fewer means files went missing */
#define MU_SD 0.05  /* the goldens' friction input sd */
#define TOL_VX 1e-4
#define TOL_VY 5e-4
#define TOL_BETA 2e-4
#define TOL_RDOT 1e-4
#define TOL_SD 1e-5
#define TOL_VX_SPLIT 2e-3
#define TOL_SD_SPLIT 5e-2
#define MIN_FLAG_AGREE_LOG 0.90
#define MIN_FLAG_AGREE_ALL 0.999

static uint32_t conv_sat; /* saturations of the test's own conversions */

static rfe_fix_t fx(double v, unsigned int q) { return rfe_fix_from_double(v, q, &conv_sat); }

/* The double sample of a log row and its Q31 rounding. */
static void inputs_of(const rfe_sensor_log_t *log, size_t k, rfe_velocity_input_t *in,
                      rfe_velocity_input_q31_t *iq)
{
    const rfe_sensor_row_t *r = &log->rows[k];
    size_t w;
    memset(in, 0, sizeof(*in));
    memset(iq, 0, sizeof(*iq));
    in->dt = (k > 0u) ? r->t - log->rows[k - 1u].t : 0.0;
    in->delta = r->delta;
    in->steer_wheel = log->has_swa ? r->swa : 0.0;
    in->yaw_rate = r->yaw_rate;
    in->ax = r->ax;
    in->ay = r->ay;
    in->grade = log->has_grade ? r->grade : 0.0;
    for (w = 0u; w < 4u; ++w) {
        in->omega[w] = r->omega[w];
        in->p_brake[w] = log->has_pressure ? r->p_brake[w] : 0.0;
        in->torque[w] = log->has_torque ? r->torque[w] : 0.0;
    }
    in->has = (log->has_pressure ? RFE_VEL_HAS_PRESSURE : 0u) |
              (log->has_torque ? RFE_VEL_HAS_TORQUE : 0u) |
              (log->has_swa ? RFE_VEL_HAS_STEER_WHEEL : 0u);
    iq->dt = fx(in->dt, RFE_FIX_Q_DT);
    iq->delta = fx(in->delta, RFE_FIX_Q_ANGLE);
    iq->steer_wheel = fx(in->steer_wheel, RFE_FIX_Q_STEER_WHEEL);
    iq->yaw_rate = fx(in->yaw_rate, RFE_FIX_Q_YAWRATE);
    iq->ax = fx(in->ax, RFE_FIX_Q_ACC);
    iq->ay = fx(in->ay, RFE_FIX_Q_ACC);
    iq->grade = fx(in->grade, RFE_FIX_Q_ANGLE);
    for (w = 0u; w < 4u; ++w) {
        iq->omega[w] = fx(in->omega[w], RFE_FIX_Q_OMEGA);
        iq->p_brake[w] = fx(in->p_brake[w], RFE_FIX_Q_PRESSURE);
        iq->torque[w] = fx(in->torque[w], RFE_FIX_Q_TORQUE);
    }
    iq->has = in->has;
}

/* A free-rolling sample at v [m/s] straight ahead (the default preset's R). */
static void rolling(const both_t *b, double v, double dt, rfe_velocity_input_t *in,
                    rfe_velocity_input_q31_t *iq)
{
    size_t w;
    memset(in, 0, sizeof(*in));
    in->dt = dt;
    for (w = 0u; w < 4u; ++w) {
        in->omega[w] = v / b->pd.vehicle.R;
    }
    memset(iq, 0, sizeof(*iq));
    iq->dt = fx(dt, RFE_FIX_Q_DT);
    for (w = 0u; w < 4u; ++w) {
        iq->omega[w] = fx(in->omega[w], RFE_FIX_Q_OMEGA);
    }
}

/* Sample k of the steady turn the floor tests drive (test_velocity_flt.c's floor_turn): 20 m/s
 * (the first sample with dt 0), delta 0.02 rad, the yaw rate on r_ref = vx delta / L, ay
 * 2.5 m/s^2, in double and in the fixed-point formats. */
static void steady_turn(const both_t *b, size_t k, rfe_velocity_input_t *in,
                        rfe_velocity_input_q31_t *iq)
{
    rolling(b, 20.0, (k == 0u) ? 0.0 : 0.01, in, iq);
    in->delta = 0.02;
    in->yaw_rate = 20.0 * (0.02 / (b->pd.vehicle.Lf + b->pd.vehicle.Lr));
    in->ay = 2.5;
    iq->delta = fx(in->delta, RFE_FIX_Q_ANGLE);
    iq->yaw_rate = fx(in->yaw_rate, RFE_FIX_Q_YAWRATE);
    iq->ay = fx(in->ay, RFE_FIX_Q_ACC);
}

typedef struct {
    double vx, vy, beta, rdot, sd; /* the worst |q31 - double| over the log (vx, sd: before
                                      the first decision split) */
    double vx_split, sd_split;     /* vx, sd after it */
    size_t flag_diff;
    size_t n;
    int splits;
} worst_t;

static void compare(const rfe_velocity_estimate_t *e, const rfe_velocity_estimate_q31_t *q,
                    worst_t *w, int split, const char *what)
{
    const double tol_vx = (split != 0) ? TOL_VX_SPLIT : TOL_VX;
    const double tol_sd = (split != 0) ? TOL_SD_SPLIT : TOL_SD;
    const double d[7] = {
        fabs(rfe_fix_to_double(q->vx, 23u) - e->vx),
        fabs(rfe_fix_to_double(q->vy, 23u) - e->vy),
        fabs(rfe_fix_to_double(q->beta, 29u) - e->beta),
        fabs(rfe_fix_to_double(q->yaw_acc, 24u) - e->yaw_acc),
        fabs(rfe_fix_to_double(q->sd_vx, 23u) - e->sd_vx),
        fabs(rfe_fix_to_double(q->sd_vy, 23u) - e->sd_vy),
        fabs(rfe_fix_to_double(q->sd_yaw_acc, 24u) - e->sd_yaw_acc)};
    const double dsb = fabs(rfe_fix_to_double(q->sd_beta, 29u) - e->sd_beta);
    if (split == 0) {
        w->vx = fmax(w->vx, d[0]);
        w->sd = fmax(w->sd, fmax(fmax(d[4], d[5]), fmax(d[6], dsb)));
    } else {
        w->vx_split = fmax(w->vx_split, d[0]);
        w->sd_split = fmax(w->sd_split, fmax(fmax(d[4], d[5]), fmax(d[6], dsb)));
    }
    w->vy = fmax(w->vy, d[1]);
    w->beta = fmax(w->beta, d[2]);
    w->rdot = fmax(w->rdot, d[3]);
    ASSERT_LE(d[0], tol_vx, what);
    ASSERT_LE(d[1], TOL_VY, what);
    ASSERT_LE(d[2], TOL_BETA, what);
    ASSERT_LE(d[3], TOL_RDOT, what);
    ASSERT_LE(fmax(fmax(d[4], d[5]), fmax(d[6], dsb)), tol_sd, what);
    ASSERT_LE(fabs(rfe_fix_to_double(q->delta, 29u) - e->delta), 1e-8, what);
}

static worst_t run_log(const char *name)
{
    char path[512];
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    worst_t w = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0u, 0u, 0};
    size_t k;
    memset(&log, 0, sizeof(log));
    snprintf(path, sizeof(path), "%s/%s", OBS_DIR, name);
    assert_int_equal(rfe_sensor_log_read(path, &log, &err), 0);
    params_of(&log, &b);
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    conv_sat = 0u;
    for (k = 0u; k < log.n_rows; ++k) {
        rfe_velocity_input_t in;
        rfe_velocity_input_q31_t iq;
        rfe_velocity_mu_t mu;
        rfe_velocity_mu_q31_t mq;
        rfe_velocity_estimate_t e;
        rfe_velocity_estimate_q31_t q;
        size_t i;
        char what[200];
        inputs_of(&log, k, &in, &iq);
        for (i = 0u; i < 4u; ++i) {
            mu.mu[i] = log.rows[k].mu_true[i];
            mu.sd[i] = MU_SD;
            mq.mu[i] = fx(mu.mu[i], RFE_FIX_Q_MU);
            mq.sd[i] = fx(MU_SD, RFE_FIX_Q_SD);
        }
        assert_int_equal(rfe_velocity_step(&od, &in, log.has_truth ? &mu : NULL, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, log.has_truth ? &mq : NULL, &q), RFE_OK);
        assert_int_equal(q.sat, 0u);
        snprintf(what, sizeof(what), "%s row %zu", name, k);
        if (q.flags != e.flags) {
            ++w.flag_diff;
            w.splits = 1;
        }
        compare(&e, &q, &w, w.splits, what);
    }
    assert_int_equal(conv_sat, 0u);
    assert_int_equal(oq.sat, 0u);
    w.n = log.n_rows;
    if ((double)w.flag_diff > (1.0 - MIN_FLAG_AGREE_LOG) * (double)log.n_rows) {
        fail_msg("%s: flags differ on %zu of %zu steps", name, w.flag_diff, log.n_rows);
    }
    rfe_sensor_log_free(&log);
    return w;
}

/* One step of both observers on the same sample, compared (no decision split expected:
 * the flags must agree). */
static void step_both(rfe_velocity_t *od, rfe_velocity_q31_t *oq, const rfe_velocity_input_t *in,
                      const rfe_velocity_input_q31_t *iq, rfe_velocity_estimate_t *e,
                      const char *what)
{
    rfe_velocity_estimate_q31_t q;
    worst_t w = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0u, 0u, 0};
    assert_int_equal(rfe_velocity_step(od, in, NULL, e), RFE_OK);
    assert_int_equal(rfe_velocity_step_q31(oq, iq, NULL, &q), RFE_OK);
    assert_int_equal(q.sat, 0u);
    assert_int_equal(q.flags, e->flags);
    compare(e, &q, &w, 0, what);
}

/* The lock-out of test_velocity_flt.c (REQ-OBS-010) through both twins: 5 s rolling at
 * 20 m/s, ABS braking to 5 m/s with every wheel 15 % slow and ax 0.8 m/s^2 short, then
 * (q_vx_brake as given) 1 s rolling with one wheel 1 m/s fast, braking on to standstill and
 * 1 s parked with the brake held. Returns the last double estimate. */
static rfe_velocity_estimate_t lockout_both(double q_vx_brake)
{
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_t e;
    double v = 20.0;
    size_t k, w;
    params_of(NULL, &b);
    b.vd.q_vx_brake = q_vx_brake;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&b.vd, &b.vq), RFE_OK);
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    conv_sat = 0u;
    for (k = 0u; k < 1000u; ++k) {
        if (k < 500u) { /* rolling */
        } else if (k < 580u) { /* braking, ABS */
            v -= 0.06;
        } else if (k < 680u) { /* rolling, one wheel fast */
        } else if (k < 760u) { /* braking on to 0.2 m/s */
            v -= 0.06;
        } else { /* parked */
            v = 0.0;
        }
        rolling(&b, ((k >= 500u && k < 580u) || (k >= 680u && k < 760u)) ? 0.85 * v : v,
                (k == 0u) ? 0.0 : 0.01, &in, &iq);
        if ((k >= 500u && k < 580u) || k >= 680u) {
            in.ax = (k < 760u) ? -5.2 : 0.0;
            iq.ax = fx(in.ax, RFE_FIX_Q_ACC);
            for (w = 0u; w < 4u; ++w) {
                in.p_brake[w] = 3.0;
                iq.p_brake[w] = fx(3.0, RFE_FIX_Q_PRESSURE);
            }
            in.has = (uint32_t)RFE_VEL_HAS_PRESSURE;
            iq.has = in.has;
        }
        if (k >= 580u && k < 680u) {
            in.omega[3] = (v + 1.0) / b.pd.vehicle.R;
            iq.omega[3] = fx(in.omega[3], RFE_FIX_Q_OMEGA);
        }
        step_both(&od, &oq, &in, &iq, &e, "lock-out sequence");
    }
    assert_int_equal(conv_sat, 0u);
    return e;
}

/* REQ-FXP-014 (REQ-OBS-010): the re-acquisition and the braking drift decide the same in
 * both twins, and the fixed-point vx regains its wheels too */
static void test_back_to_back_through_a_lockout(void **state)
{
    rfe_velocity_estimate_t e;
    (void)state;
    e = lockout_both(0.5);  /* a braking drift of 0.5 (off by default) */
    assert_true(e.vx < 0.05); /* parked: within sd_wheel of 0 */
    e = lockout_both(0.0);  /* none: only the re-acquisition at standstill */
    assert_true(e.vx < 0.05);
    assert_true((e.flags & (uint32_t)RFE_VEL_FLAG_VX_WHEEL) != 0u);
}

static int cmp_name(const void *a, const void *b)
{
    return strcmp((const char *)a, (const char *)b);
}

/* REQ-FXP-014 */
static void test_back_to_back_on_every_observer_scenario(void **state)
{
    static char names[128][256];
    DIR *d = opendir(OBS_DIR);
    struct dirent *de;
    int n = 0;
    worst_t all = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0u, 0u, 0};
    size_t seen = 0u;
    size_t k;
    /* light mode (valgrind): every 10th log of the sorted list (readdir's order is the file
     * system's: sorted, the subset is the same everywhere) */
    const size_t stride = rfe_test_stride(10u);
    (void)state;
    assert_non_null(d);
    while ((de = readdir(d)) != NULL) {
        const size_t len = strlen(de->d_name);
        if ((len > 4u) && (strcmp(de->d_name + len - 4u, ".csv") == 0) &&
            (len < sizeof names[0])) {
            assert_true(seen < (sizeof names / sizeof names[0]));
            memcpy(names[seen], de->d_name, len + 1u);
            ++seen;
        }
    }
    closedir(d);
    qsort(names, seen, sizeof names[0], cmp_name);
    for (k = 0u; k < seen; k += stride) {
        const worst_t w = run_log(names[k]);
        all.vx = fmax(all.vx, w.vx);
        all.vy = fmax(all.vy, w.vy);
        all.beta = fmax(all.beta, w.beta);
        all.rdot = fmax(all.rdot, w.rdot);
        all.sd = fmax(all.sd, w.sd);
        all.vx_split = fmax(all.vx_split, w.vx_split);
        all.sd_split = fmax(all.sd_split, w.sd_split);
        all.flag_diff += w.flag_diff;
        all.n += w.n;
        all.splits += w.splits;
        ++n;
    }
    assert_true(seen >= MIN_LOGS);
    printf("observer q31 vs f64 over %d logs (%zu steps): |dvx| %.3g m/s, |dvy| %.3g m/s, "
           "|dbeta| %.3g rad, |dr-dot| %.3g rad/s^2, |dsd| %.3g; %d log(s) with a decision "
           "split, after it |dvx| %.3g m/s, |dsd| %.3g; flags differ on %zu steps\n",
           n, all.n, all.vx, all.vy, all.beta, all.rdot, all.sd, all.splits, all.vx_split,
           all.sd_split, all.flag_diff);
    if (stride == 1u) { /* a subset's share is not the whole set's */
        ASSERT_LE((double)all.flag_diff, (1.0 - MIN_FLAG_AGREE_ALL) * (double)all.n,
                  "flag steps differing, all logs");
    }
}

/* REQ-FXP-015: the defaults are the conversion of the double defaults, bit for bit; the
 * validation rejects what the double one does. */
static void test_params(void **state)
{
    rfe_velocity_params_t vd;
    rfe_velocity_params_q31_t conv;
    rfe_velocity_params_q31_t def;
    rfe_velocity_params_q31_t bad;
    size_t i;
    (void)state;
    assert_int_equal(rfe_velocity_params_default(&vd), RFE_OK);
    assert_int_equal(rfe_velocity_params_to_q31_f64(&vd, &conv), RFE_OK);
    assert_int_equal(rfe_velocity_params_default_q31(&def), RFE_OK);
    assert_memory_equal(&conv, &def, sizeof(def));
    assert_int_equal(rfe_velocity_params_validate_q31(&def), RFE_OK);
    assert_int_equal(rfe_velocity_params_default_q31(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_params_validate_q31(NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_params_to_q31_f64(NULL, &conv), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_params_to_q31_f64(&vd, NULL), RFE_ERR_NULL);
    /* driven */
    bad = def;
    bad.driven = 0u;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    bad.driven = 16u;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    /* lat_every in 1 .. RFE_VEL_LAT_EVERY_MAX, and converted as it is */
    bad = def;
    bad.lat_every = 0u;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    bad.lat_every = RFE_VEL_LAT_EVERY_MAX + 1u;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    bad.lat_every = RFE_VEL_LAT_EVERY_MAX;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_OK);
    vd.lat_every = 5u;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&vd, &conv), RFE_OK);
    assert_int_equal(conv.lat_every, 5u);
    vd.lat_every = 0u;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&vd, &conv), RFE_ERR_PARAM);
    vd.lat_every = 1u;
    /* dt range */
    bad = def;
    bad.dt_min = 0;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    bad = def;
    bad.dt_min = bad.dt_max + 1;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    bad = def;
    bad.dt_max = RFE_FIX_ONE(30) + 1;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    /* lin_dwell at most 1 s (Q30 2^30: the time on r_ref plus a period stays in Q30) */
    bad = def;
    bad.lin_dwell = RFE_FIX_ONE(30);
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_OK);
    bad.lin_dwell = RFE_FIX_ONE(30) + 1;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    /* lin_mu_gain at most 4 (Q24 2^26: the gain in Q30 times |ay| stays within int64) */
    bad = def;
    bad.lin_mu_gain = RFE_FIX_ONE(26);
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_OK);
    bad.lin_mu_gain = RFE_FIX_ONE(26) + 1;
    assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
    /* every field that must be > 0 rejects 0, every other one a negative value; in the
     * order of the struct after dt_max (steer_ratio is checked positive too; sd_model_rdot
     * is 0 when off) */
    {
        rfe_fix_t *const pos[] = {&bad.q_jerk, &bad.sd_r, &bad.sd_ax, &bad.sd_ay,
                                    &bad.v_lat_min, &bad.sd_lowspeed, &bad.mu_default,
                                    &bad.sd_vydot, &bad.steer_ratio};
        rfe_fix_t *const nonneg[] = {&bad.ay_turn, &bad.q_bx_turn, &bad.vydot_rerr, &bad.vy_out_floor_mu, &bad.lin_mu_gain, &bad.sd_vy_lin, &bad.lin_r_tol, &bad.lin_r_rel, &bad.lin_ay_max,
            &bad.lin_ay_steady, &bad.lin_dwell,
            &bad.sd_model_rdot, &bad.vydot_rdot, &bad.q_bx, &bad.q_by, &bad.sd_wheel, &bad.sd_wheel_rel,
            &bad.k_gate, &bad.k_agree, &bad.v_stand, &bad.q_vx_brake, &bad.ax_brake_on, &bad.ax_drive_on, &bad.p_brake_on, &bad.torque_on,
            &bad.sd_model_ay, &bad.model_ay_rel, &bad.sd_mu_default, &bad.mu_margin,
            &bad.sd_vx0, &bad.sd_bx0, &bad.sd_vy0, &bad.sd_by0};
        /* the lengths from the lists: a new key is added in one place */
        for (i = 0u; i < (sizeof(pos) / sizeof(pos[0])); ++i) {
            bad = def;
            *pos[i] = 0;
            assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
        }
        for (i = 0u; i < (sizeof(nonneg) / sizeof(nonneg[0])); ++i) {
            bad = def;
            *nonneg[i] = 0;
            assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_OK);
            *nonneg[i] = -1;
            assert_int_equal(rfe_velocity_params_validate_q31(&bad), RFE_ERR_PARAM);
        }
    }
    /* the converter: an invalid double set; a value beyond its format (a gate of 200 sd in
     * Q24, +-128); a nonzero value rounding to 0 */
    conv = def;
    vd.sd_r = -1.0;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&vd, &conv), RFE_ERR_PARAM);
    assert_int_equal(rfe_velocity_params_default(&vd), RFE_OK);
    vd.k_gate = 200.0;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&vd, &conv), RFE_ERR_RANGE);
    assert_int_equal(rfe_velocity_params_default(&vd), RFE_OK);
    vd.sd_wheel = 1e-9;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&vd, &conv), RFE_ERR_RANGE);
    assert_memory_equal(&conv, &def, sizeof(def)); /* untouched on error */
}

/* REQ-FXP-015 */
static void test_init_and_get(void **state)
{
    both_t b;
    rfe_velocity_q31_t o;
    rfe_velocity_q31_t before;
    rfe_velocity_params_q31_t bad;
    rfe_params_q31_t badp;
    rfe_velocity_estimate_q31_t e;
    (void)state;
    params_of(NULL, &b);
    memset(&o, 0x5a, sizeof(o));
    memcpy(&before, &o, sizeof before);
    assert_int_equal(rfe_velocity_init_q31(NULL, &b.vq, &b.pq), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_init_q31(&o, NULL, &b.pq), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_init_q31(&o, &b.vq, NULL), RFE_ERR_NULL);
    bad = b.vq;
    bad.driven = 0u;
    assert_int_equal(rfe_velocity_init_q31(&o, &bad, &b.pq), RFE_ERR_PARAM);
    badp = b.pq;
    badp.vehicle.m = -1;
    assert_int_equal(rfe_velocity_init_q31(&o, &b.vq, &badp), RFE_ERR_PARAM);
    assert_memory_equal(&o, &before, sizeof(o));
    assert_int_equal(rfe_velocity_get_q31(&o, &e), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_velocity_init_q31(&o, &b.vq, &b.pq), RFE_OK);
    assert_int_equal(rfe_velocity_get_q31(NULL, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_get_q31(&o, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_get_q31(&o, &e), RFE_OK);
    assert_int_equal(e.vx, 0);
    assert_int_equal(e.sat, 0u);
}

/* REQ-FXP-015: every error status leaves the observer as it was and reports the previous
 * estimate with the status and sat 0. */
static void test_bad_inputs_leave_the_observer_untouched(void **state)
{
    both_t b;
    rfe_velocity_q31_t o;
    rfe_velocity_q31_t before;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t good;
    rfe_velocity_input_q31_t x;
    rfe_velocity_mu_q31_t mu;
    rfe_velocity_estimate_q31_t e;
    rfe_velocity_estimate_q31_t prev;
    size_t i;
    int c;
    (void)state;
    params_of(NULL, &b);
    memset(&o, 0, sizeof o); /* padding defined, so whole-struct compares see bytes */
    assert_int_equal(rfe_velocity_init_q31(&o, &b.vq, &b.pq), RFE_OK);
    rolling(&b, 20.0, 0.01, &in, &good);
    assert_int_equal(rfe_velocity_step_q31(&o, &good, NULL, &e), RFE_OK);
    assert_int_equal(rfe_velocity_step_q31(&o, &good, NULL, &prev), RFE_OK);
    memcpy(&before, &o, sizeof before); /* bytes, padding included (not a member copy) */
    assert_int_equal(rfe_velocity_step_q31(NULL, &good, NULL, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_step_q31(&o, NULL, NULL, &e), RFE_ERR_NULL);
    assert_int_equal(rfe_velocity_step_q31(&o, &good, NULL, NULL), RFE_ERR_NULL);
    for (i = 0u; i < 4u; ++i) {
        mu.mu[i] = fx(0.8, RFE_FIX_Q_MU);
        mu.sd[i] = fx(0.1, RFE_FIX_Q_SD);
    }
    for (c = 0; c < 16; ++c) {
        rfe_velocity_mu_q31_t m = mu;
        x = good;
        switch (c) {
        case 0: x.dt = b.vq.dt_min - 1; break;
        case 1: x.dt = b.vq.dt_max + 1; break;
        case 2: x.delta = RFE_FIX_LIMIT_DELTA + 1; break;
        case 3: x.yaw_rate = -RFE_FIX_LIMIT_YAW_RATE - 1; break;
        case 4: x.ax = RFE_FIX_LIMIT_ACC + 1; break;
        case 5: x.ay = -RFE_FIX_LIMIT_ACC - 1; break;
        case 6: x.grade = RFE_FIX_LIMIT_GRADE + 1; break;
        case 7: x.omega[2] = RFE_FIX_LIMIT_OMEGA + 1; break;
        case 8: x.p_brake[1] = -RFE_FIX_LIMIT_PRESSURE - 1; break;
        case 9: x.torque[3] = RFE_FIX_LIMIT_TORQUE + 1; break;
        case 10: m.mu[0] = -1; break;
        case 11: m.mu[1] = RFE_FIX_LIMIT_MU_IN + 1; break;
        case 12: m.sd[2] = -1; break;
        case 13: /* a steering-wheel angle whose road-wheel angle is beyond the stops */
            x.has = RFE_VEL_HAS_STEER_WHEEL;
            x.steer_wheel = fx(17.0, RFE_FIX_Q_STEER_WHEEL);
            break;
        case 14: x.dt = 0; break;
        default: x.dt = -good.dt; break;
        }
        assert_int_equal(rfe_velocity_step_q31(&o, &x, &m, &e), RFE_ERR_RANGE);
        assert_memory_equal(&o, &before, sizeof(o));
        assert_int_equal(e.status, RFE_ERR_RANGE);
        assert_int_equal(e.sat, 0u);
        assert_int_equal(e.vx, prev.vx);
        assert_int_equal(e.flags, prev.flags);
    }
    /* the limits themselves are accepted */
    x = good;
    x.delta = RFE_FIX_LIMIT_DELTA;
    x.grade = -RFE_FIX_LIMIT_GRADE;
    x.p_brake[0] = -RFE_FIX_LIMIT_PRESSURE;
    x.torque[0] = RFE_FIX_LIMIT_TORQUE;
    mu.mu[0] = RFE_FIX_LIMIT_MU_IN;
    mu.mu[1] = 0;
    mu.sd[1] = 0;
    assert_int_equal(rfe_velocity_step_q31(&o, &x, &mu, &e), RFE_OK);
    /* not initialised */
    memset(&o, 0, sizeof(o));
    memcpy(&before, &o, sizeof before);
    assert_int_equal(rfe_velocity_step_q31(&o, &good, NULL, &e), RFE_ERR_NOT_INITIALISED);
    assert_memory_equal(&o, &before, sizeof(o));
}

/* REQ-FXP-015: a failure of the model (tyre parameters it rejects) or of a filter (a
 * corrupted state format), in a state that bypassed init's validation, is an error of the
 * step and leaves the observer untouched. */
static void test_model_error_leaves_the_observer_untouched(void **state)
{
    both_t b;
    rfe_velocity_q31_t o;
    rfe_velocity_q31_t before;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_q31_t e;
    (void)state;
    params_of(NULL, &b);
    memset(&o, 0, sizeof o);
    assert_int_equal(rfe_velocity_init_q31(&o, &b.vq, &b.pq), RFE_OK);
    rolling(&b, 20.0, 0.01, &in, &iq);
    assert_int_equal(rfe_velocity_step_q31(&o, &iq, NULL, &e), RFE_OK);
    {
        rfe_velocity_q31_t good;
        int c;
        memcpy(&good, &o, sizeof good);
        for (c = 0; c < 4; ++c) {
            memcpy(&o, &good, sizeof o);
            switch (c) {
            case 0: o.tyre.mode = (rfe_tyre_mode_t)7; break; /* rfe_meas_setup_q31 rejects it */
            case 1: o.yaw.qf = 40u; break; /* the filters reject a corrupted format */
            case 2: o.lon.qf = 40u; break;
            default: o.lat.qf = 40u; break;
            }
            memcpy(&before, &o, sizeof before);
            assert_int_not_equal(rfe_velocity_step_q31(&o, &iq, NULL, &e), RFE_OK);
            assert_true(rfe_status_is_error(e.status));
            assert_int_equal(e.sat, 0u);
            assert_memory_equal(&o, &before, sizeof(o));
        }
    }
}

/* test_velocity_flt.c's turn_with_driven_slip in fixed point: 1 s straight at 20 m/s, then
 * 2 s with ay 2 m/s^2 and the driven front wheels 0.1 m/s fast, rolling without a torque
 * signal; obs_ay_turn @p ay_turn (Q24). Returns the last vx in m/s; every step a wheel
 * corrects vx, and the double observer on the same inputs takes the same decisions. */
static double turn_with_driven_slip_q31(rfe_fix_t ay_turn)
{
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_t e;
    rfe_velocity_estimate_q31_t q;
    size_t k;
    params_of(NULL, &b);
    b.vq.ay_turn = ay_turn;
    b.vd.ay_turn = rfe_fix_to_double(ay_turn, 24u);
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    for (k = 0u; k < 300u; ++k) {
        rolling(&b, 20.0, (k == 0u) ? 0.0 : 0.01, &in, &iq);
        if (k >= 100u) {
            in.ay = 2.0;
            iq.ay = fx(2.0, RFE_FIX_Q_ACC);
            in.omega[0] = 20.1 / b.pd.vehicle.R;
            in.omega[1] = in.omega[0];
            iq.omega[0] = fx(in.omega[0], RFE_FIX_Q_OMEGA);
            iq.omega[1] = iq.omega[0];
        }
        assert_int_equal(rfe_velocity_step(&od, &in, NULL, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &q), RFE_OK);
        if (k > 0u) {
            assert_int_equal(q.flags & ((uint32_t)RFE_VEL_FLAG_BRAKING |
                                        (uint32_t)RFE_VEL_FLAG_DRIVING |
                                        (uint32_t)RFE_VEL_FLAG_VX_WHEEL),
                             (uint32_t)RFE_VEL_FLAG_VX_WHEEL);
            assert_int_equal(q.flags, e.flags);
        }
    }
    return rfe_fix_to_double(q.vx, 23u);
}

/* REQ-OBS-028 in fixed point: in the turn vx is the rear wheels' 20 m/s within 0.01 m/s (the
 * float test's bound; the Q23 vx and the rounding of omega are 1e-7 m/s), with the rule off
 * (ay_turn 0) above the four wheels' mean less that bound, as in float. */
static void test_rolling_in_a_turn_in_fixed_point(void **state)
{
    (void)state;
    assert_close(turn_with_driven_slip_q31(fx(1.0, RFE_FIX_Q_ACC)), 20.0, 0.01, 0.0,
                 "in a turn: the rear wheels");
    assert_true(turn_with_driven_slip_q31(0) > 20.04);
}

/* REQ-FXP-014: the first sample initialises vx from the wheels' mean, r from the sample,
 * the rest at 0, every sd at its initial value, like the double observer. */
static void test_first_sample(void **state)
{
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_t e;
    rfe_velocity_estimate_q31_t q;
    (void)state;
    params_of(NULL, &b);
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    rolling(&b, 17.3, 0.0, &in, &iq);
    in.yaw_rate = 0.2;
    iq.yaw_rate = fx(0.2, RFE_FIX_Q_YAWRATE);
    in.delta = 0.05;
    iq.delta = fx(0.05, RFE_FIX_Q_ANGLE);
    assert_int_equal(rfe_velocity_step(&od, &in, NULL, &e), RFE_OK);
    assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &q), RFE_OK);
    /* the mean of four references, each from omega (0.5 LSB22 = 1.2e-7 rad/s: 4e-8 m/s at
     * R = 0.325 m) through sin/cos (0.5 LSB30) and one division: 1e-6 m/s covers it */
    assert_close(rfe_fix_to_double(q.vx, 23u), e.vx, 1e-6, 0.0, "first vx");
    assert_int_equal(q.vy, 0);
    assert_int_equal(q.yaw_acc, 0);
    assert_int_equal(q.bx, 0);
    assert_int_equal(q.by, 0);
    assert_int_equal(q.flags, 0u);
    assert_int_equal(q.sd_vx, b.vq.sd_vx0);
    assert_int_equal(q.sd_vy, b.vq.sd_vy0);
    assert_int_equal(q.sd_yaw_acc, RFE_FIX_ONE(24));
    assert_int_equal(oq.yaw.x[0], iq.yaw_rate);
    assert_int_equal(q.beta, fx(e.beta, RFE_FIX_Q_ANGLE)); /* atan2(0, vx) = 0 */
    /* sd_beta = sd_vy0 vx / vx^2 = 0.3 / 17.3: 2 LSB29 of the 30-bit quotient */
    assert_close(rfe_fix_to_double(q.sd_beta, 29u), e.sd_beta, 4e-9, 0.0, "first sd_beta");
    /* the first sample's dt is ignored (0 here), a later one is checked */
    iq.dt = 0;
    assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &q), RFE_ERR_RANGE);
}

/* REQ-FXP-014 (REQ-OBS-008): the steering-wheel angle through the ratio gives the road-wheel
 * angle the double observer uses, and the observer reports it. */
/* REQ-FXP-015: a noise parameter at the top of its Q format (sd_model_ay = INT32_MAX in Q24,
 * about 128 m/s^2) squares beyond the filters' variance range: the variance and the model
 * row's summed noise (with a little ay, so its relative part adds to it) are clamped to
 * RFE_KF2_Q31_PMAX and counted (a saturation is not an error), and the step goes on with finite outputs. With the default the same step counts
 * none, so the count is the clamp's. */
static void test_a_huge_noise_parameter_saturates_and_is_counted(void **state)
{
    both_t b;
    rfe_velocity_q31_t o;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_q31_t e;
    uint32_t sat_default = 0u;
    int run;
    (void)state;
    for (run = 0; run < 2; ++run) {
        params_of(NULL, &b);
        if (run == 1) {
            b.vq.sd_model_ay = INT32_MAX;
        }
        assert_int_equal(rfe_velocity_params_validate_q31(&b.vq), RFE_OK);
        memset(&o, 0, sizeof o);
        assert_int_equal(rfe_velocity_init_q31(&o, &b.vq, &b.pq), RFE_OK);
        rolling(&b, 20.0, 0.01, &in, &iq);
        iq.ay = fx(0.5, RFE_FIX_Q_ACC); /* a little ay: the relative model error is not 0 */
        assert_int_equal(rfe_velocity_step_q31(&o, &iq, NULL, &e), RFE_OK); /* the start */
        assert_int_equal(rfe_velocity_step_q31(&o, &iq, NULL, &e), RFE_OK); /* a model step */
        assert_true((e.flags & RFE_VEL_FLAG_VY_MODEL) != 0u);
        if (run == 0) {
            sat_default = e.sat;
        } else {
            /* two clamps: the squared parameter, then the row's summed noise */
            assert_true(e.sat >= sat_default + 2u);
            assert_true(e.sd_vy >= 0);
        }
    }
    assert_int_equal(sat_default, 0u);
}

static void test_steering_wheel_input(void **state)
{
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    rfe_velocity_q31_t oq2;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_input_q31_t iq2;
    rfe_velocity_estimate_t e;
    rfe_velocity_estimate_q31_t q;
    rfe_velocity_estimate_q31_t q2;
    int k;
    (void)state;
    params_of(NULL, &b);
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq2, &b.vq, &b.pq), RFE_OK);
    for (k = 0; k < 200; ++k) {
        const double sw = 1.6 * sin(0.02 * k); /* up to 0.1 rad at the road wheels */
        rolling(&b, 15.0, 0.01, &in, &iq);
        in.has = RFE_VEL_HAS_STEER_WHEEL;
        in.steer_wheel = sw;
        in.delta = 0.7; /* ignored */
        in.yaw_rate = 15.0 * sw / 16.0 / 2.7;
        in.ay = 15.0 * in.yaw_rate;
        iq.has = RFE_VEL_HAS_STEER_WHEEL;
        iq.steer_wheel = fx(sw, RFE_FIX_Q_STEER_WHEEL);
        iq.delta = fx(0.7, RFE_FIX_Q_ANGLE);
        iq.yaw_rate = fx(in.yaw_rate, RFE_FIX_Q_YAWRATE);
        iq.ay = fx(in.ay, RFE_FIX_Q_ACC);
        /* the same sample with the road-wheel angle the ratio gives, in Q29 */
        iq2 = iq;
        iq2.has = 0u;
        iq2.delta = fx(sw / 16.0, RFE_FIX_Q_ANGLE);
        assert_int_equal(rfe_velocity_step(&od, &in, NULL, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &q), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&oq2, &iq2, NULL, &q2), RFE_OK);
        /* the input's rounding (0.5 LSB26 / 16 = 4.7e-10) and the division's (0.5 LSB29 =
         * 9.3e-10) */
        assert_close(rfe_fix_to_double(q.delta, 29u), e.delta, 1.4e-9, 0.0, "delta used");
        /* the quotient and the directly rounded angle differ by at most 1 LSB29 */
        assert_true(abs(q.delta - q2.delta) <= 1);
        assert_close(rfe_fix_to_double(q.vy, 23u), e.vy, TOL_VY, 0.0, "vy");
    }
}

/* A steady turn (vx 20 m/s, r 0.2 rad/s, ay = r vx, delta 0.08 rad; r constant, so the
 * differentiator's r-dot is 0) with the lateral row's error made large (30 m/s^2, inside
 * Q24 and its square inside RFE_KF2_Q31_PMAX): the yaw row is what moves vy. Both twins over
 * 3 s, vy compared at every step within TOL_VY; the final vy of each in @p vy_d, @p vy_q. */
static void turn_by_the_yaw_row(double sd_model_rdot, double *vy_d, double *vy_q)
{
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    rfe_velocity_mu_t mu;
    rfe_velocity_mu_q31_t mq;
    size_t i;
    size_t k;
    params_of(NULL, &b);
    b.vd.sd_model_ay = 30.0;
    b.vd.sd_model_rdot = sd_model_rdot;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&b.vd, &b.vq), RFE_OK);
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    for (i = 0u; i < 4u; ++i) {
        mu.mu[i] = 1.0;
        mu.sd[i] = 0.0;
        mq.mu[i] = fx(1.0, RFE_FIX_Q_MU);
        mq.sd[i] = 0;
    }
    for (k = 0u; k <= 300u; ++k) {
        rfe_velocity_input_t in;
        rfe_velocity_input_q31_t iq;
        rfe_velocity_estimate_t e;
        rfe_velocity_estimate_q31_t q;
        rolling(&b, 20.0, (k == 0u) ? 0.0 : 0.01, &in, &iq);
        in.delta = 0.08;
        in.yaw_rate = 0.2;
        in.ay = 4.0;
        iq.delta = fx(in.delta, RFE_FIX_Q_ANGLE);
        iq.yaw_rate = fx(in.yaw_rate, RFE_FIX_Q_YAWRATE);
        iq.ay = fx(in.ay, RFE_FIX_Q_ACC);
        assert_int_equal(rfe_velocity_step(&od, &in, &mu, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, &mq, &q), RFE_OK);
        assert_int_equal(q.sat, 0u);
        assert_int_equal(q.flags, e.flags);
        assert_close(rfe_fix_to_double(q.vy, 23u), e.vy, TOL_VY, 0.0, "vy in the turn");
        *vy_d = e.vy;
        *vy_q = rfe_fix_to_double(q.vy, 23u);
    }
}

/* REQ-OBS-009 (REQ-FXP-014): the fixed-point lateral filter weighs the yaw row as the double
 * one does: with the row (sd_model_rdot 0.3 rad/s^2; off by default) and without it (0, off)
 * the q31 vy follows the double vy within TOL_VY, and the row
 * moves the final vy by more than 20 TOL_VY, so agreeing within TOL_VY needs the row. */
static void test_the_yaw_row_in_fixed_point(void **state)
{
    double on_d = 0.0;
    double on_q = 0.0;
    double off_d = 0.0;
    double off_q = 0.0;
    (void)state;
    turn_by_the_yaw_row(0.3, &on_d, &on_q);
    turn_by_the_yaw_row(0.0, &off_d, &off_q);
    printf("yaw row, final vy: with it %.6g m/s (q31 %.6g), without %.6g m/s (q31 %.6g)\n",
           on_d, on_q, off_d, off_q);
    assert_true(fabs(on_d - off_d) > 20.0 * TOL_VY);
    assert_true(fabs(on_q - off_q) > 20.0 * TOL_VY);
}

/* REQ-OBS-012 (REQ-FXP-014): the steady turn of test_velocity_flt.c through both twins: 20 m/s,
 * delta 0.02 rad, the yaw rate on its neutral reference, ay 3.5 m/s^2 (between lin_ay_max 3
 * and lin_ay_steady 4), 100 Hz, the friction input 1.0 (sd 0.1) as in test_velocity_flt.c;
 * the yaw rate 0.1 rad/s off it on step @p off (0: never). Both take the same flags on every
 * step; returns the first later step with the linear range (0: none). */
static size_t steady_turn_both(double ay, size_t off)
{
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_t e;
    rfe_velocity_estimate_q31_t q;
    rfe_velocity_mu_t mu;
    rfe_velocity_mu_q31_t mq;
    size_t first = 0u;
    size_t k;
    params_of(NULL, &b);
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    conv_sat = 0u;
    for (k = 0u; k < 4u; ++k) {
        mu.mu[k] = 1.0;
        mu.sd[k] = 0.1;
        mq.mu[k] = fx(1.0, RFE_FIX_Q_MU);
        mq.sd[k] = fx(0.1, RFE_FIX_Q_SD);
    }
    for (k = 0u; k <= 40u; ++k) {
        rolling(&b, 20.0, (k == 0u) ? 0.0 : 0.01, &in, &iq);
        in.delta = 0.02;
        in.yaw_rate = 20.0 * (0.02 / (b.pd.vehicle.Lf + b.pd.vehicle.Lr)) + ((k == off) ? 0.1 : 0.0);
        in.ay = ay;
        iq.delta = fx(in.delta, RFE_FIX_Q_ANGLE);
        iq.yaw_rate = fx(in.yaw_rate, RFE_FIX_Q_YAWRATE);
        iq.ay = fx(in.ay, RFE_FIX_Q_ACC);
        assert_int_equal(rfe_velocity_step(&od, &in, &mu, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, &mq, &q), RFE_OK);
        /* the first step after starting in the turn saturates twice, the same before the
         * time on r_ref existed (measured on the parent commit with this sequence; not in
         * this test's subject); none after it */
        assert_true(q.sat <= ((k == 1u) ? 2u : 0u));
        assert_int_equal(q.flags, e.flags);
        if ((k > 0u) && (first == 0u) && ((e.flags & RFE_VEL_FLAG_VY_LINEAR) != 0u)) {
            first = k;
        }
    }
    assert_int_equal(conv_sat, 0u);
    return first;
}

/* REQ-OBS-012 REQ-FXP-014: the time on r_ref (Q30) reaches lin_dwell = 0.125 s on the 13th
 * period of 0.01 s (step 12 is 0.005 s short, far more than the Q30 rounding of 13 periods,
 * 13 LSB); an off step restarts it (on from step 11: step 23); above lin_ay_steady never. */
static void test_a_steady_turn_in_fixed_point(void **state)
{
    (void)state;
    assert_int_equal(steady_turn_both(3.5, 0u), 13u);
    assert_int_equal(steady_turn_both(3.5, 10u), 23u);
    assert_int_equal(steady_turn_both(4.5, 0u), 0u);
}

/* REQ-OBS-012 REQ-FXP-014: the steady turn's friction floor through both twins: the turn of
 * test_velocity_flt.c's floor_turn (20 m/s, delta 0.02 rad, the yaw rate on r_ref, ay
 * 2.5 m/s^2, the friction input 0.3, sd 0.05): (1 + mu_margin) 2.5 / 9.81 = 0.28 does not
 * raise 0.3, lin_mu_gain 2.5 / 9.81 = 0.51 does, from the step the turn is steady (13) on.
 * Both twins raise it on the same steps (the flags equal on every step) and their vy agree
 * within TOL_VY on every step (the tyres are far from their limit here: the file's bound
 * applies). With lin_mu_gain @p gain; @p first_raised: the step from which the friction is
 * raised (0: never). */
static void floor_turn_both(double gain, size_t first_raised)
{
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_t e;
    rfe_velocity_estimate_q31_t q;
    rfe_velocity_mu_t mu;
    rfe_velocity_mu_q31_t mq;
    size_t k;
    params_of(NULL, &b);
    b.vd.lin_mu_gain = gain;
    b.vq.lin_mu_gain = fx(gain, RFE_FIX_Q_RATIO);
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    for (k = 0u; k < 4u; ++k) {
        mu.mu[k] = 0.3;
        mu.sd[k] = 0.05;
        mq.mu[k] = fx(0.3, RFE_FIX_Q_MU);
        mq.sd[k] = fx(0.05, RFE_FIX_Q_SD);
    }
    for (k = 0u; k <= 40u; ++k) {
        steady_turn(&b, k, &in, &iq);
        assert_int_equal(rfe_velocity_step(&od, &in, &mu, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, &mq, &q), RFE_OK);
        assert_int_equal(q.flags, e.flags);
        if (k > 0u) {
            /* the model (and its friction) on the later steps 1, 1 + lat_every, .. */
            assert_int_equal(((e.flags & RFE_VEL_FLAG_MU_RAISED) != 0u) ? 1 : 0,
                             ((first_raised != 0u) && (k >= first_raised) &&
                              (((k - 1u) % b.vd.lat_every) == 0u)) ? 1 : 0);
        }
        assert_close(rfe_fix_to_double(q.vy, 23u), e.vy, TOL_VY, 0.0, "vy in the steady turn");
    }
}

static void test_the_steady_turns_floor_in_fixed_point(void **state)
{
    (void)state;
    floor_turn_both(2.0, 13u);
    /* a gain at most 1 + mu_margin is no floor: 1.0 * 2.5 / 9.81 = 0.25 < 0.3, never */
    floor_turn_both(1.0, 0u);
}

/* The lateral model's rate (OBSERVER.md §4.2, lat_every 3) in both twins: a turn at 20 m/s
 * (ay 2.5 m/s^2, friction 0.5 with sd 0.05: the tyres far from their limit, so the file's
 * TOL_VY holds), the model's rows on the later steps 1, 4, 7, ... only (the flag VY_MODEL),
 * the same flags in both twins on every step, vy within TOL_VY of the double's. A skipped
 * step leaves out one scalar update of the same form in both twins, so it adds no error
 * source to those the bound counts. */
static void test_the_lateral_model_every_third_step(void **state)
{
    both_t b;
    rfe_velocity_t od;
    rfe_velocity_q31_t oq;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_t e;
    rfe_velocity_estimate_q31_t q;
    rfe_velocity_mu_t mu;
    rfe_velocity_mu_q31_t mq;
    size_t k;
    size_t n_model = 0u;
    (void)state;
    params_of(NULL, &b);
    b.vd.lat_every = 3u;
    b.vq.lat_every = 3u;
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    for (k = 0u; k < 4u; ++k) {
        mu.mu[k] = 0.5;
        mu.sd[k] = 0.05;
        mq.mu[k] = fx(0.5, RFE_FIX_Q_MU);
        mq.sd[k] = fx(0.05, RFE_FIX_Q_SD);
    }
    for (k = 0u; k <= 30u; ++k) {
        rolling(&b, 20.0, (k == 0u) ? 0.0 : 0.01, &in, &iq);
        in.delta = 0.02;
        in.yaw_rate = 0.12;
        in.ay = 2.5;
        iq.delta = fx(in.delta, RFE_FIX_Q_ANGLE);
        iq.yaw_rate = fx(in.yaw_rate, RFE_FIX_Q_YAWRATE);
        iq.ay = fx(in.ay, RFE_FIX_Q_ACC);
        assert_int_equal(rfe_velocity_step(&od, &in, &mu, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, &mq, &q), RFE_OK);
        assert_int_equal(q.flags, e.flags);
        assert_int_equal(((q.flags & RFE_VEL_FLAG_VY_MODEL) != 0u) ? 1 : 0,
                         ((k > 0u) && ((k % 3u) == 1u)) ? 1 : 0);
        n_model += ((q.flags & RFE_VEL_FLAG_VY_MODEL) != 0u) ? 1u : 0u;
        assert_close(rfe_fix_to_double(q.vy, 23u), e.vy, TOL_VY, 0.0, "vy, model every 3rd");
    }
    assert_int_equal(n_model, 10u); /* steps 1, 4, .., 28 */
}

/* REQ: rfe_velocity_restart_q31 (REQ-OBS-023): the sample after a gap beyond dt_max is
 * refused, and after a restart taken as the first: bit for bit a fresh observer's first
 * step, and the same next step; NULL and an uninitialised observer are refused. */
/* REQ-OBS-023 REQ-FXP-014 */
static void test_restart_after_a_long_gap(void **state)
{
    both_t b;
    static rfe_velocity_q31_t oq;
    static rfe_velocity_q31_t fresh;
    static rfe_velocity_q31_t blank;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_q31_t e;
    rfe_velocity_estimate_q31_t f;
    size_t k;
    (void)state;
    params_of(NULL, &b);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    for (k = 0u; k < 100u; ++k) {
        rolling(&b, 25.0, (k == 0u) ? 0.0 : 0.01, &in, &iq);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &e), RFE_OK);
    }
    rolling(&b, 18.0, 0.5, &in, &iq);
    iq.yaw_rate = fx(0.1, RFE_FIX_Q_YAWRATE);
    assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &e), RFE_ERR_RANGE);
    assert_int_equal(rfe_velocity_restart_q31(&oq), RFE_OK);
    memset(&e, 0, sizeof e);
    memset(&f, 0, sizeof f);
    assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &e), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&fresh, &b.vq, &b.pq), RFE_OK);
    assert_int_equal(rfe_velocity_step_q31(&fresh, &iq, NULL, &f), RFE_OK);
    assert_memory_equal(&e, &f, sizeof e);
    iq.dt = fx(0.01, RFE_FIX_Q_DT);
    assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &e), RFE_OK);
    assert_int_equal(rfe_velocity_step_q31(&fresh, &iq, NULL, &f), RFE_OK);
    assert_memory_equal(&e, &f, sizeof e);
    assert_int_equal(rfe_velocity_restart_q31(NULL), RFE_ERR_NULL);
    memset(&blank, 0, sizeof blank);
    assert_int_equal(rfe_velocity_restart_q31(&blank), RFE_ERR_NOT_INITIALISED);
}

/* REQ-FXP-014: the longitudinal filter skips the sine of a grade of 0 (longitudinal_q31.c
 * net_acc_q31, the input's default when the grade is unknown) and takes sin = 0 for it: the
 * integer rfe_q31_sincos_q29 gives for 0, exactly (so the skip changes no bit). A grade
 * one LSB from 0 is not 0: its sine, 2^-29 rad = 2 LSB of Q30 (sin x = x within x^3 / 6),
 * within the sine's 0.66 LSB (fxmath_q31.c), is 1 to 3, never the 0 of the skip. */
static void test_the_zero_grade_skips_its_sine(void **state)
{
    int32_t s = 7;
    int32_t c = 7;
    (void)state;
    rfe_q31_sincos_q29(0, &s, &c);
    assert_int_equal(s, 0);
    rfe_q31_sincos_q29(1, &s, &c);
    assert_in_range(s, 1, 3);
}

/* vy (Q23) after the first model step (step 1 after the first sample) of the turn of
 * test_the_lateral_model_every_third_step in the Q31 twin at lat_every @p every and
 * sd_model_ay @p sd_ay: the lateral row's variance sd_ay^2 alone (model_ay_rel 0, the
 * default friction with sd 0, the yaw row off as by default). */
static rfe_fix_t vy_q31_after_one_model_step(uint32_t every, double sd_ay)
{
    both_t b;
    rfe_velocity_q31_t oq;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_q31_t q;
    size_t k;
    params_of(NULL, &b);
    b.vd.model_ay_rel = 0.0;
    b.vd.sd_mu_default = 0.0;
    b.vd.sd_model_rdot = 0.0;
    b.vd.sd_model_ay = sd_ay;
    b.vd.lat_every = every;
    assert_int_equal(rfe_velocity_params_to_q31_f64(&b.vd, &b.vq), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&oq, &b.vq, &b.pq), RFE_OK);
    for (k = 0u; k <= 1u; ++k) {
        rolling(&b, 20.0, (k == 0u) ? 0.0 : 0.01, &in, &iq);
        iq.delta = fx(0.02, RFE_FIX_Q_ANGLE);
        iq.yaw_rate = fx(0.12, RFE_FIX_Q_YAWRATE);
        iq.ay = fx(2.5, RFE_FIX_Q_ACC);
        assert_int_equal(rfe_velocity_step_q31(&oq, &iq, NULL, &q), RFE_OK);
    }
    assert_true((q.flags & RFE_VEL_FLAG_VY_MODEL) != 0u);
    return q.vy;
}

/* OBSERVER.md §4.2: at lat_every N > 1 the model rows' variances are divided by N (exact
 * integer division, rounded) on the steps they run. sd_model_ay 0.25 is exact in Q24 (2^22)
 * and its variance 2^44 in Q48 a multiple of 4, so at N = 4 the lateral row's variance is
 * exactly (0.125)^2's: one model step at N = 4 and sd 0.25 equals bit for bit the step at
 * N = 1 and sd 0.125, and differs from the step at N = 1 and sd 0.25 (the comparison can
 * fail). */
static void test_the_models_variance_over_the_rate_q31(void **state)
{
    const rfe_fix_t at4 = vy_q31_after_one_model_step(4u, 0.25);
    const rfe_fix_t at1_quarter = vy_q31_after_one_model_step(1u, 0.125);
    const rfe_fix_t at1 = vy_q31_after_one_model_step(1u, 0.25);
    (void)state;
    assert_int_equal(at4, at1_quarter);
    /* the quartered variance moves vy by far more than 1e-3 m/s (8389 LSB of Q23) */
    assert_true(llabs((long long)at4 - (long long)at1) > 8389LL);
}

/* REQ-OBS-025 REQ-FXP-014: the reported sd(vy)'s floor in fixed point (rfe_vel_sd_vy_floor_q31,
 * OBSERVER.md §5): the turn and friction input of test_velocity_flt.c's
 * test_the_reported_sd_vy_floor (the largest sd / mu on a wheel the measured ay raises) through
 * three observers: q31 off (obs_vy_out_floor_mu 0), q31 and double at 4 (the default).
 *  - q31 on against off: the filters and vx, vy, beta, sd(vx) equal bit for bit, both keep
 *    the filter's sd (off reports it), the first sample has no floor;
 *  - q31 on against the closed form k |vx ay / (cy g)| max sd / max(mu, 1.1 |ay| / g) in
 *    double on the Q values themselves (vx the output, ay, mu, sd, cy, g, k as converted):
 *    the fixed-point path rounds cy g (Q20: 2^-21 on 147, 3e-9 relative), ay / (cy g)
 *    (Q29: 2^-30 on 0.017, 6e-8 relative), the raised friction (Q29: 1e-9 relative), the
 *    slip part (Q23: 6e-8 m/s on 0.34, 2e-7 relative), s sd / m (Q23: 6e-8 m/s) and k times
 *    it (Q23: 6e-8 m/s): at most 0.58 m/s x 3e-7 + 4 x 6e-8 + 6e-8 = 5e-7 m/s; 1e-6 m/s
 *    (8 Q23 LSB) bounds it with a factor 2;
 *  - sd(beta) against its closed form from the q31 outputs: the 30-bit mantissas of
 *    sd_beta_q31 (2^-30 relative each) and its Q29 rounding, far inside 1e-6 relative;
 *  - q31 against the double twin: within TOL_SD (the vx twins' TOL_VX 1e-4 on 20 m/s is
 *    5e-6 relative of the 0.58 m/s floor, plus the 1e-6 above: 4e-6 m/s);
 *  - no saturation; the parameter's check (at most 8, Q24 2^27; not negative). */
static void test_the_reported_sd_vy_floor_q31(void **state)
{
    both_t b;
    static rfe_velocity_t od;
    static rfe_velocity_q31_t off;
    static rfe_velocity_q31_t on;
    rfe_velocity_params_q31_t vq_on;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_t e;
    rfe_velocity_estimate_q31_t qa;
    rfe_velocity_estimate_q31_t qb;
    const double mu_d[4] = {0.3, 0.3, 0.1, 0.9};
    const double sd_d[4] = {0.05, 0.1, 0.12, 0.05};
    rfe_velocity_mu_t mu;
    rfe_velocity_mu_q31_t mq;
    size_t k;
    int acted = 0;
    (void)state;
    params_of(NULL, &b);
    assert_true(b.vd.vy_out_floor_mu == 4.0); /* 4 by default (OBSERVER.md §2) */
    vq_on = b.vq;
    assert_int_equal(vq_on.vy_out_floor_mu, RFE_FIX_ONE(26)); /* 4 in Q24, exactly */
    b.vd.vy_out_floor_mu = 0.0; /* b.vq: the floor off */
    assert_int_equal(rfe_velocity_params_to_q31_f64(&b.vd, &b.vq), RFE_OK);
    assert_int_equal(b.vq.vy_out_floor_mu, 0);
    b.vd.vy_out_floor_mu = 4.0; /* the double twin at 4 */
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&off, &b.vq, &b.pq), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&on, &vq_on, &b.pq), RFE_OK);
    for (k = 0u; k < 4u; ++k) {
        mu.mu[k] = mu_d[k];
        mu.sd[k] = sd_d[k];
        mq.mu[k] = fx(mu_d[k], RFE_FIX_Q_MU);
        mq.sd[k] = fx(sd_d[k], RFE_FIX_Q_SD);
    }
    for (k = 0u; k <= 40u; ++k) {
        steady_turn(&b, k, &in, &iq);
        assert_int_equal(rfe_velocity_step(&od, &in, &mu, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&off, &iq, &mq, &qa), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&on, &iq, &mq, &qb), RFE_OK);
        assert_int_equal(qb.sat, 0u);
        assert_memory_equal(&off.lat, &on.lat, sizeof(on.lat));
        assert_memory_equal(&off.lon, &on.lon, sizeof(on.lon));
        assert_memory_equal(&off.yaw, &on.yaw, sizeof(on.yaw));
        assert_true((qa.vx == qb.vx) && (qa.vy == qb.vy) && (qa.beta == qb.beta) &&
                    (qa.sd_vx == qb.sd_vx) && (qa.flags == qb.flags));
        assert_int_equal(qa.sd_vy, off.sd_vy_filter);
        assert_int_equal(on.sd_vy_filter, off.sd_vy_filter);
        if (k == 0u) {
            assert_int_equal(qb.sd_vy, qa.sd_vy);
        } else {
            const double g = rfe_fix_to_double(b.pq.vehicle.g, RFE_FIX_Q_ACC);
            const double cy = rfe_fix_to_double(b.pq.tyre.cy, RFE_FIX_Q_RATIO);
            const double ay = rfe_fix_to_double(iq.ay, RFE_FIX_Q_ACC);
            const double vx = rfe_fix_to_double(qb.vx, 23u);
            const double vy = rfe_fix_to_double(qb.vy, 23u);
            const double svx = rfe_fix_to_double(qb.sd_vx, 23u);
            const double mu_low =
                (1.0 + rfe_fix_to_double(vq_on.mu_margin, RFE_FIX_Q_SD)) * fabs(ay) / g;
            double rho = 0.0;
            double fl;
            double want;
            double sb;
            size_t i;
            for (i = 0u; i < 4u; ++i) {
                rho = fmax(rho, rfe_fix_to_double(mq.sd[i], RFE_FIX_Q_SD) /
                                    fmax(rfe_fix_to_double(mq.mu[i], RFE_FIX_Q_MU), mu_low));
            }
            fl = 4.0 * fabs(vx * ay / (cy * g)) * rho;
            want = fmax(rfe_fix_to_double(qa.sd_vy, 23u), fl);
            sb = sqrt(vx * vx * want * want + vy * vy * svx * svx) /
                 fmax(vx * vx + vy * vy, 9.0); /* v_lat_min 3 m/s */
            assert_close(rfe_fix_to_double(qb.sd_vy, 23u), want, 1e-6, 0.0, "q31 floored sd(vy)");
            assert_close(rfe_fix_to_double(qb.sd_beta, 29u), sb, 0.0, 1e-6, "q31 sd(beta)");
            assert_close(rfe_fix_to_double(qb.sd_vy, 23u), e.sd_vy, TOL_SD, 0.0,
                         "q31 against double, floored sd(vy)");
            acted |= (fl > rfe_fix_to_double(qa.sd_vy, 23u)) ? 1 : 0;
        }
    }
    assert_true(acted != 0);
    /* no lateral acceleration: the slip part is 0 and so is the floor, whatever the friction
     * (a wheel's friction 0 included, which no ay raises): the reported sd is the filter's */
    mq.mu[0] = 0;
    for (k = 0u; k <= 5u; ++k) {
        rolling(&b, 20.0, 0.01, &in, &iq);
        iq.ay = 0;
        assert_int_equal(rfe_velocity_step_q31(&off, &iq, &mq, &qa), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&on, &iq, &mq, &qb), RFE_OK);
        assert_int_equal(qb.sd_vy, qa.sd_vy);
        assert_int_equal(qb.sd_vy, on.sd_vy_filter);
    }
    /* below v_lat_min (3 m/s) no floor (the float twin's test): the filter's sd */
    for (k = 0u; k <= 5u; ++k) {
        rolling(&b, 2.0, 0.01, &in, &iq);
        iq.ay = fx(2.5, RFE_FIX_Q_ACC);
        assert_int_equal(rfe_velocity_step_q31(&off, &iq, &mq, &qa), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&on, &iq, &mq, &qb), RFE_OK);
        assert_true(rfe_fix_to_double(qb.vx, 23u) < 3.0);
        assert_int_equal(qb.sd_vy, qa.sd_vy);
        assert_int_equal(qb.sd_vy, on.sd_vy_filter);
    }
    /* at most 8 (Q24 2^27), not negative */
    vq_on.vy_out_floor_mu = RFE_FIX_ONE(27);
    assert_int_equal(rfe_velocity_params_validate_q31(&vq_on), RFE_OK);
    vq_on.vy_out_floor_mu = RFE_FIX_ONE(27) + 1;
    assert_int_equal(rfe_velocity_params_validate_q31(&vq_on), RFE_ERR_PARAM);
    vq_on.vy_out_floor_mu = -1;
    assert_int_equal(rfe_velocity_params_validate_q31(&vq_on), RFE_ERR_PARAM);
}

/* Sample k of REQ-OBS-027's turn (test_velocity_flt.c's test_the_yaw_error_grows_the_offsets_noise):
 * 20 m/s, the yaw rate 0.05 rad/s under r_ref at delta 0.06 rad, ay = 20 r; @p slide: the
 * same r with delta taken back to r_ref = r - 0.2 rad/s and ay - r vx = -2 m/s^2. */
static void yaw_error_turn(const both_t *b, size_t k, int slide, rfe_velocity_input_t *in,
                           rfe_velocity_input_q31_t *iq)
{
    const double len = b->pd.vehicle.Lf + b->pd.vehicle.Lr;
    rolling(b, 20.0, (k == 0u) ? 0.0 : 0.01, in, iq);
    in->yaw_rate = (20.0 * (0.06 / len)) - 0.05;
    in->delta = (slide != 0) ? (((in->yaw_rate - 0.2) * len) / 20.0) : 0.06;
    in->ay = (slide != 0) ? ((in->yaw_rate * 20.0) - 2.0) : (20.0 * in->yaw_rate);
    iq->delta = fx(in->delta, RFE_FIX_Q_ANGLE);
    iq->yaw_rate = fx(in->yaw_rate, RFE_FIX_Q_YAWRATE);
    iq->ay = fx(in->ay, RFE_FIX_Q_ACC);
}

/* REQ-OBS-027 REQ-FXP-014: §4.4's yaw-error term in fixed point (vydot_rerr Q24 times the
 * Q27 r_over into §4.4's Q24 sd), the float twin's turn through three observers: q31 off
 * (obs_vydot_rerr 0), q31 and double at 25 (the default).
 *  - understeer (r under r_ref) and below v_lat_min: q31 on equals off bit for bit;
 *  - sliding out: on keeps less information on b_y than off (p11 larger) on every step,
 *    and follows the double twin within the back-to-back bounds (TOL_VY on vy, TOL_SD on
 *    sd(vy)); the double's own §4.4 row is checked in closed form by the float test;
 *  - no saturation; the parameter's check (at most 100, Q24 1677721600; not negative). */
static void test_the_yaw_error_term_q31(void **state)
{
    both_t b;
    static rfe_velocity_t od;
    static rfe_velocity_q31_t off;
    static rfe_velocity_q31_t on;
    rfe_velocity_params_q31_t vq_on;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_velocity_estimate_t e;
    rfe_velocity_estimate_q31_t qa;
    rfe_velocity_estimate_q31_t qb;
    double dvy = 0.0;
    double dsd = 0.0;
    size_t k;
    (void)state;
    params_of(NULL, &b);
    assert_true(b.vd.vydot_rerr == 25.0); /* 25 by default (OBSERVER.md §2) */
    vq_on = b.vq;
    assert_int_equal(vq_on.vydot_rerr, 25 * RFE_FIX_ONE(24)); /* 25 in Q24, exactly */
    b.vd.vydot_rerr = 0.0; /* b.vq: the term off */
    assert_int_equal(rfe_velocity_params_to_q31_f64(&b.vd, &b.vq), RFE_OK);
    assert_int_equal(b.vq.vydot_rerr, 0);
    b.vd.vydot_rerr = 25.0; /* the double twin at 25 */
    assert_int_equal(rfe_velocity_init(&od, &b.vd, &b.pd), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&off, &b.vq, &b.pq), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&on, &vq_on, &b.pq), RFE_OK);
    for (k = 0u; k <= 100u; ++k) {
        yaw_error_turn(&b, k, 0, &in, &iq);
        assert_int_equal(rfe_velocity_step(&od, &in, NULL, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&off, &iq, NULL, &qa), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&on, &iq, NULL, &qb), RFE_OK);
        assert_memory_equal(&off.lat, &on.lat, sizeof(on.lat));
        assert_memory_equal(&qa, &qb, sizeof(qa));
    }
    for (k = 1u; k <= 50u; ++k) {
        yaw_error_turn(&b, k, 1, &in, &iq);
        assert_int_equal(rfe_velocity_step(&od, &in, NULL, &e), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&off, &iq, NULL, &qa), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&on, &iq, NULL, &qb), RFE_OK);
        assert_int_equal(qb.sat, 0u);
        assert_true(on.lat.p11 > off.lat.p11);
        dvy = fmax(dvy, fabs(rfe_fix_to_double(qb.vy, 23u) - e.vy));
        dsd = fmax(dsd, fabs(rfe_fix_to_double(qb.sd_vy, 23u) - e.sd_vy));
    }
    printf("REQ-OBS-027 q31 against double, sliding: |vy| %.3g m/s, |sd(vy)| %.3g m/s\n", dvy, dsd);
    assert_true(dvy <= TOL_VY);
    assert_true(dsd <= TOL_SD);
    /* below v_lat_min (2 m/s), r 0.5 rad/s far beyond r_ref: bit for bit */
    assert_int_equal(rfe_velocity_init_q31(&off, &b.vq, &b.pq), RFE_OK);
    assert_int_equal(rfe_velocity_init_q31(&on, &vq_on, &b.pq), RFE_OK);
    for (k = 0u; k <= 20u; ++k) {
        rolling(&b, 2.0, (k == 0u) ? 0.0 : 0.01, &in, &iq);
        iq.delta = fx(0.03, RFE_FIX_Q_ANGLE);
        iq.yaw_rate = fx(0.5, RFE_FIX_Q_YAWRATE);
        assert_int_equal(rfe_velocity_step_q31(&off, &iq, NULL, &qa), RFE_OK);
        assert_int_equal(rfe_velocity_step_q31(&on, &iq, NULL, &qb), RFE_OK);
        assert_true(rfe_fix_to_double(qb.vx, 23u) < 3.0);
        assert_memory_equal(&off.lat, &on.lat, sizeof(on.lat));
        assert_memory_equal(&qa, &qb, sizeof(qa));
    }
    /* at most 100 (Q24 1677721600), not negative; a refused set leaves the state untouched */
    vq_on.vydot_rerr = 1677721600;
    assert_int_equal(rfe_velocity_params_validate_q31(&vq_on), RFE_OK);
    vq_on.vydot_rerr = 1677721601;
    assert_int_equal(rfe_velocity_params_validate_q31(&vq_on), RFE_ERR_PARAM);
    vq_on.vydot_rerr = -1;
    assert_int_equal(rfe_velocity_params_validate_q31(&vq_on), RFE_ERR_PARAM);
    off = on;
    assert_int_equal(rfe_velocity_init_q31(&on, &vq_on, &b.pq), RFE_ERR_PARAM);
    assert_memory_equal(&off, &on, sizeof(on));
    /* the double set's conversion refuses what the float check refuses */
    b.vd.vydot_rerr = 100.5;
    assert_int_equal(rfe_velocity_params_validate(&b.vd), RFE_ERR_PARAM);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_params),
        cmocka_unit_test(test_init_and_get),
        cmocka_unit_test(test_bad_inputs_leave_the_observer_untouched),
        cmocka_unit_test(test_model_error_leaves_the_observer_untouched),
        cmocka_unit_test(test_first_sample),
        cmocka_unit_test(test_rolling_in_a_turn_in_fixed_point),
        cmocka_unit_test(test_restart_after_a_long_gap),
        cmocka_unit_test(test_the_zero_grade_skips_its_sine),
        cmocka_unit_test(test_steering_wheel_input),
        cmocka_unit_test(test_a_huge_noise_parameter_saturates_and_is_counted),
        cmocka_unit_test(test_the_yaw_row_in_fixed_point),
        cmocka_unit_test(test_a_steady_turn_in_fixed_point),
        cmocka_unit_test(test_the_steady_turns_floor_in_fixed_point),
        cmocka_unit_test(test_the_reported_sd_vy_floor_q31),
        cmocka_unit_test(test_the_yaw_error_term_q31),
        cmocka_unit_test(test_the_lateral_model_every_third_step),
        cmocka_unit_test(test_the_models_variance_over_the_rate_q31),
        cmocka_unit_test(test_back_to_back_through_a_lockout),
        cmocka_unit_test(test_back_to_back_on_every_observer_scenario),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
