/**
 * @file test_pipeline_q31.c
 * @brief The fixed-point composed entry (rfe/pipeline_q31.h) and the friction estimator's
 *        per-step input noise in Q31: statuses, the untouched state on error, that each step
 *        hands the observer's estimate and sd to the friction estimator, and back to back
 *        against the double pipeline on observer scenarios.
 *
 * Bounds of the back-to-back run (end to end as test_velocity_q31.c: rounded samples,
 * converted parameters). The velocity outputs keep test_velocity_q31.c's bounds (the
 * friction input of the observer differs only by the friction estimators' difference, which
 * moves the lateral model's ay by at most dmu g ~ 0.05 m/s^2 times the model's gain: the
 * same 5e-4 m/s on vy). The friction estimate: REQ-FXP-006's 0.005 on every wheel, which
 * the friction estimator twins meet on their own (test_friction_q31.c); the observer's
 * differences (vx 1e-4 m/s, vy 5e-4 m/s, r-dot 1e-4 rad/s^2) are far below the input noise
 * the pipeline hands the estimator (sd_vx ~ 0.005 m/s and up, sd(r-dot) ~ 0.05), so they
 * move mu by a small fraction of that bound. Asserted on the samples where the estimate is
 * valid on both sides (an invalid, unsettled estimate is not a result), measured worst cases
 * printed.
 */
#include "test_common.h"

#include <math.h>
#include <string.h>

#include "csv_log.h"
#include "host/fixed_conv.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/component/params_conv.h"
#include "test_params_both.h"
#include "rfe/pipeline.h"
#include "rfe/pipeline_q31.h"
#include "rfe/component/fxmath.h"

#define TOL_MU 0.005  /* REQ-FXP-006 */
#define TOL_VX 1e-4   /* test_velocity_q31.c */
#define TOL_VY 5e-4

static uint32_t conv_sat;

static rfe_fix_t fx(double v, unsigned int q) { return rfe_fix_from_double(v, q, &conv_sat); }

static rfe_velocity_input_q31_t rolling_q31(const both_t *b, double v, double dt)
{
    rfe_velocity_input_q31_t in;
    size_t i;
    memset(&in, 0, sizeof(in));
    in.dt = fx(dt, RFE_FIX_Q_DT);
    for (i = 0u; i < 4u; ++i) {
        in.omega[i] = fx(v / b->pd.vehicle.R, RFE_FIX_Q_OMEGA);
    }
    return in;
}

/* REQ-FXP-016 */
static void test_set_input_noise(void **state)
{
    both_t b;
    static rfe_friction_q31_t est;
    static rfe_friction_q31_t before;
    (void)state;
    params_of(NULL, &b);
    memset(&est, 0, sizeof(est));
    assert_int_equal(rfe_friction_set_input_noise_q31(NULL, 1, 1, 1), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_set_input_noise_q31(&est, 1, 1, 1), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_friction_init_q31(&est, &b.pq), RFE_OK);
    memcpy(&before, &est, sizeof before);
    assert_int_equal(rfe_friction_set_input_noise_q31(&est, -1, 1, 1), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise_q31(&est, 1, -1, 1), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise_q31(&est, 1, 1, 0), RFE_ERR_RANGE);
    assert_memory_equal(&est, &before, sizeof(est));
    assert_int_equal(rfe_friction_set_input_noise_q31(&est, 0, 5, 7), RFE_OK);
    assert_int_equal(est.params.filter.sd_in_vx, 0);
    assert_int_equal(est.params.filter.sd_in_vy, 5);
    assert_int_equal(est.params.filter.r_yaw_acc, 7);
}

/* REQ-FXP-016 */
static void test_pipeline_steps_both_estimators(void **state)
{
    both_t b;
    static rfe_pipeline_q31_t pl;
    rfe_pipeline_out_q31_t o;
    rfe_velocity_input_q31_t in;
    rfe_velocity_params_q31_t bad;
    size_t k;
    double r_want;
    (void)state;
    params_of(NULL, &b);
    memset(&pl, 0, sizeof pl);
    assert_int_equal(rfe_pipeline_init_q31(NULL, &b.pq, &b.vq), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_init_q31(&pl, NULL, &b.vq), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_init_q31(&pl, &b.pq, NULL), RFE_ERR_NULL);
    bad = b.vq;
    bad.driven = 0u;
    assert_int_equal(rfe_pipeline_init_q31(&pl, &b.pq, &bad), RFE_ERR_PARAM);
    assert_int_equal(rfe_pipeline_init_q31(&pl, &b.pq, &b.vq), RFE_OK);
    for (k = 0u; k < 100u; ++k) {
        in = rolling_q31(&b, 20.0, (k == 0u) ? 0.0 : 0.01);
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pl, &in, &o)));
    }
    /* the friction estimator ran on the observer's vx, with the observer's sd as its input
     * noise; r_yaw_acc is the exactly rounded norm (rfe_fix_norm), which the double's root
     * of the exact integer sum of squares (< 2^53) rounds the same way */
    assert_close(rfe_fix_to_double(o.velocity.vx, 23u), 20.0, 1e-3, 0.0, "vx");
    assert_int_equal(pl.friction.params.filter.sd_in_vx, o.velocity.sd_vx);
    assert_int_equal(pl.friction.params.filter.sd_in_vy, o.velocity.sd_vy);
    r_want = floor(sqrt((double)b.pq.filter.r_yaw_acc * (double)b.pq.filter.r_yaw_acc +
                        (double)o.velocity.sd_yaw_acc * (double)o.velocity.sd_yaw_acc) + 0.5);
    assert_int_equal(pl.friction.params.filter.r_yaw_acc, (rfe_fix_t)r_want);
    assert_memory_equal(&pl.last, &o.friction, sizeof(o.friction));
    assert_int_equal(o.friction.sat, 0u);
}

/* REQ-FXP-016 */
static void test_an_error_leaves_the_pipeline_untouched(void **state)
{
    both_t b;
    static rfe_pipeline_q31_t pl;
    static rfe_pipeline_q31_t before;
    rfe_pipeline_out_q31_t o;
    rfe_velocity_input_q31_t in;
    (void)state;
    params_of(NULL, &b);
    memset(&pl, 0, sizeof pl); /* padding and scratch defined, so whole-struct compares are */
    assert_int_equal(rfe_pipeline_init_q31(&pl, &b.pq, &b.vq), RFE_OK);
    in = rolling_q31(&b, 20.0, 0.0);
    assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pl, &in, &o)));
    memcpy(&before, &pl, sizeof before);
    assert_int_equal(rfe_pipeline_step_q31(NULL, &in, &o), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_step_q31(&pl, NULL, &o), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_step_q31(&pl, &in, NULL), RFE_ERR_NULL);
    in = rolling_q31(&b, 20.0, 0.01);
    in.ax = RFE_FIX_LIMIT_ACC + 1; /* the observer rejects it */
    assert_int_equal(rfe_pipeline_step_q31(&pl, &in, &o), RFE_ERR_RANGE);
    assert_int_equal(o.friction.sat, 0u);
    assert_memory_equal(&pl, &before, sizeof(pl));
    /* the observer accepts a sample the friction estimator rejects: an uninitialised
     * friction estimator */
    pl.friction.magic = 0u;
    memcpy(&before, &pl, sizeof before);
    in = rolling_q31(&b, 20.0, 0.01);
    assert_int_equal(rfe_pipeline_step_q31(&pl, &in, &o), RFE_ERR_NOT_INITIALISED);
    assert_int_equal(o.friction.status, RFE_ERR_NOT_INITIALISED);
    assert_memory_equal(&pl, &before, sizeof(pl));
}

/* REQ-FXP-016: back to back against the double pipeline. */
static void run_log(const char *name, double *worst_mu, double *worst_vx, double *worst_vy,
                    size_t *n_valid)
{
    char path[512];
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    both_t b;
    static rfe_pipeline_t pd;
    static rfe_pipeline_q31_t pq;
    size_t k;
    memset(&log, 0, sizeof(log));
    snprintf(path, sizeof(path), "scenarios/observer/%s", name);
    assert_int_equal(rfe_sensor_log_read(path, &log, &err), 0);
    params_of(&log, &b);
    memset(&pd, 0, sizeof pd);
    memset(&pq, 0, sizeof pq);
    assert_int_equal(rfe_pipeline_init(&pd, &b.pd, &b.vd), RFE_OK);
    assert_int_equal(rfe_pipeline_init_q31(&pq, &b.pq, &b.vq), RFE_OK);
    conv_sat = 0u;
    for (k = 0u; k < log.n_rows; ++k) {
        const rfe_sensor_row_t *r = &log.rows[k];
        rfe_velocity_input_t in;
        rfe_velocity_input_q31_t iq;
        rfe_pipeline_out_t od;
        rfe_pipeline_out_q31_t oq;
        rfe_status_t sd;
        rfe_status_t sq;
        size_t w;
        char what[160];
        memset(&in, 0, sizeof in);
        memset(&iq, 0, sizeof iq);
        in.dt = (k > 0u) ? r->t - log.rows[k - 1u].t : 0.0;
        in.delta = r->delta;
        in.yaw_rate = r->yaw_rate;
        in.ax = r->ax;
        in.ay = r->ay;
        iq.dt = fx(in.dt, RFE_FIX_Q_DT);
        iq.delta = fx(in.delta, RFE_FIX_Q_ANGLE);
        iq.yaw_rate = fx(in.yaw_rate, RFE_FIX_Q_YAWRATE);
        iq.ax = fx(in.ax, RFE_FIX_Q_ACC);
        iq.ay = fx(in.ay, RFE_FIX_Q_ACC);
        for (w = 0u; w < 4u; ++w) {
            in.omega[w] = r->omega[w];
            iq.omega[w] = fx(in.omega[w], RFE_FIX_Q_OMEGA);
        }
        sd = rfe_pipeline_step(&pd, &in, &od);
        sq = rfe_pipeline_step_q31(&pq, &iq, &oq);
        assert_false(rfe_status_is_error(sd));
        assert_false(rfe_status_is_error(sq));
        assert_int_equal(oq.velocity.sat, 0u);
        assert_int_equal(oq.friction.sat, 0u);
        snprintf(what, sizeof(what), "%s row %zu", name, k);
        *worst_vx = fmax(*worst_vx, fabs(rfe_fix_to_double(oq.velocity.vx, 23u) - od.velocity.vx));
        *worst_vy = fmax(*worst_vy, fabs(rfe_fix_to_double(oq.velocity.vy, 23u) - od.velocity.vy));
        ASSERT_LE(fabs(rfe_fix_to_double(oq.velocity.vx, 23u) - od.velocity.vx), TOL_VX, what);
        ASSERT_LE(fabs(rfe_fix_to_double(oq.velocity.vy, 23u) - od.velocity.vy), TOL_VY, what);
        for (w = 0u; w < 4u; ++w) {
            if ((oq.friction.valid[w] != 0u) && (od.friction.valid[w] != 0u)) {
                const double d = fabs(rfe_fix_to_double(oq.friction.mu[w], 29u) -
                                      od.friction.mu[w]);
                *worst_mu = fmax(*worst_mu, d);
                ++*n_valid;
                ASSERT_LE(d, TOL_MU, what);
            }
        }
    }
    assert_int_equal(conv_sat, 0u);
    rfe_sensor_log_free(&log);
}

/* REQ-FXP-016 */
static void test_back_to_back(void **state)
{
    /* braking, a lane change and a sine with dwell at two friction levels: the logs where
     * the friction estimate updates (excitation) */
    static const char *const LOGS[] = {"abs_brake_mu09.csv", "dlc_mu035.csv",
                                       "dlc_mu09.csv", "sine_dwell_mu035.csv",
                                       "abs_brake_split_mu.csv"};
    double worst_mu = 0.0;
    double worst_vx = 0.0;
    double worst_vy = 0.0;
    size_t n_valid = 0u;
    size_t i;
    (void)state;
    for (i = 0u; i < sizeof LOGS / sizeof LOGS[0]; ++i) {
        run_log(LOGS[i], &worst_mu, &worst_vx, &worst_vy, &n_valid);
    }
    printf("pipeline q31 vs f64: |dmu| %.3g over %zu valid wheel samples, |dvx| %.3g m/s, "
           "|dvy| %.3g m/s\n", worst_mu, n_valid, worst_vx, worst_vy);
    assert_true(n_valid > 1000u); /* the comparison saw settled estimates */
}

/* REQ-ABI-001 */
static void test_inits_q31_refuse_other_layout_or_word(void **state)
{
    /* As the float test: another size of the state or another configuration word. */
    static rfe_pipeline_q31_t pl, pl0;
    rfe_params_q31_t p;
    rfe_velocity_params_q31_t vp;
    const uint32_t other = RFE_CONFIG_Q31 ^ 2u; /* the float word */
    (void)state;
    assert_int_equal(rfe_params_default_q31(&p), RFE_OK);
    assert_int_equal(rfe_velocity_params_default_q31(&vp), RFE_OK);
    memset(&pl, 0x5A, sizeof pl);
    pl0 = pl;
    assert_int_equal((rfe_friction_init_q31)(&pl.friction, &p, sizeof pl.friction - 8u, RFE_CONFIG_Q31), RFE_ERR_ABI);
    assert_int_equal((rfe_friction_init_q31)(&pl.friction, &p, sizeof pl.friction, other), RFE_ERR_ABI);
    assert_int_equal((rfe_velocity_init_q31)(&pl.velocity, &vp, &p, sizeof pl.velocity + 8u, RFE_CONFIG_Q31), RFE_ERR_ABI);
    assert_int_equal((rfe_velocity_init_q31)(&pl.velocity, &vp, &p, sizeof pl.velocity, other), RFE_ERR_ABI);
    assert_int_equal((rfe_pipeline_init_q31)(&pl, &p, &vp, sizeof pl - 8u, RFE_CONFIG_Q31), RFE_ERR_ABI);
    assert_int_equal((rfe_pipeline_init_q31)(&pl, &p, &vp, sizeof pl, other), RFE_ERR_ABI);
    assert_memory_equal(&pl, &pl0, sizeof pl);
    assert_int_equal(rfe_pipeline_init_q31(&pl, &p, &vp), RFE_OK);
}

/* A braking sample (ax -6 m/s^2, 5 % slip at 20 m/s) at period dt, in both number types. */
static void brake_both(const both_t *b, double dt, double ax, double v_wheel,
                       rfe_velocity_input_t *in, rfe_velocity_input_q31_t *iq)
{
    size_t w;
    memset(in, 0, sizeof *in);
    in->dt = dt;
    in->ax = ax;
    for (w = 0u; w < 4u; ++w) {
        in->omega[w] = v_wheel / b->pd.vehicle.R;
    }
    memset(iq, 0, sizeof *iq);
    iq->dt = fx(dt, RFE_FIX_Q_DT);
    iq->ax = fx(ax, RFE_FIX_Q_ACC);
    for (w = 0u; w < 4u; ++w) {
        iq->omega[w] = fx(in->omega[w], RFE_FIX_Q_OMEGA);
    }
}

/* REQ: gaps in fixed point (REQ-OBS-023) as the double pipeline: after 100 braking steps a
 * gap of 0.05 s, 0.09 s (no restart) or 0.5 s (beyond obs_dt_max: restart); the same
 * missed periods and restart as the double twin, the same status, and vx, vy and the valid
 * mu within the back-to-back bounds above. Composed by hand from the public parts
 * (rfe_velocity_restart_q31, rfe_velocity_step_q31, rfe_friction_set_input_noise_q31,
 * rfe_friction_skip_q31, rfe_friction_step_q31) the pipeline's step is the same bit for
 * bit. A sample the restarted observer takes but the friction estimator refuses (wheels at
 * 110 m/s) leaves the pipeline as it was, the gap's time updates included. */
/* REQ-OBS-023 REQ-FXP-016 */
static void test_gaps_as_the_double_pipeline(void **state)
{
    both_t b;
    static rfe_pipeline_t pd;
    static rfe_pipeline_q31_t pq;
    static rfe_velocity_q31_t obs;
    static rfe_friction_q31_t fr;
    static rfe_pipeline_q31_t before;
    const double gaps[] = {0.05, 0.09, 0.5};
    const uint32_t missed[] = {4u, 8u, 49u};
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_pipeline_out_t od;
    rfe_pipeline_out_q31_t oq;
    size_t g;
    size_t k;
    size_t w;
    (void)state;
    params_of(NULL, &b);
    for (g = 0u; g < 3u; ++g) {
        memset(&pd, 0, sizeof pd);
        memset(&pq, 0, sizeof pq);
        assert_int_equal(rfe_pipeline_init(&pd, &b.pd, &b.vd), RFE_OK);
        assert_int_equal(rfe_pipeline_init_q31(&pq, &b.pq, &b.vq), RFE_OK);
        for (k = 0u; k < 101u; ++k) {
            brake_both(&b, (k == 0u) ? 0.0 : 0.01, -6.0, 19.0, &in, &iq);
            assert_false(rfe_status_is_error(rfe_pipeline_step(&pd, &in, &od)));
            assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pq, &iq, &oq)));
        }
        brake_both(&b, gaps[g], -5.0, 18.0, &in, &iq);
        /* by hand, from the public parts */
        obs = pq.velocity;
        fr = pq.friction;
        {
            rfe_velocity_mu_q31_t mu;
            rfe_velocity_estimate_q31_t ve;
            rfe_estimate_q31_t fe;
            rfe_sample_q31_t u;
            const rfe_fix_t v[2] = {pq.r_yaw_acc, 0};
            rfe_fix_t r = 0;
            uint32_t sat = 0u;
            rfe_fix_t vv[2];
            for (w = 0u; w < 4u; ++w) {
                mu.mu[w] = pq.last.mu[w];
                mu.sd[w] = pq.last.sd[w];
            }
            if (gaps[g] > 0.1) {
                assert_int_equal(rfe_velocity_restart_q31(&obs), RFE_OK);
            }
            assert_int_equal(rfe_velocity_step_q31(&obs, &iq, &mu, &ve), RFE_OK);
            vv[0] = v[0];
            vv[1] = ve.sd_yaw_acc;
            assert_int_equal(rfe_fix_norm(vv, 2u, &r, &sat), RFE_OK);
            assert_int_equal(rfe_friction_set_input_noise_q31(&fr, ve.sd_vx, ve.sd_vy, r), RFE_OK);
            memset(&u, 0, sizeof u);
            u.delta = ve.delta;
            u.vx = ve.vx;
            u.vy = ve.vy;
            u.yaw_rate = iq.yaw_rate;
            u.yaw_acc = ve.yaw_acc;
            u.ax = iq.ax;
            u.ay = iq.ay;
            for (w = 0u; w < 4u; ++w) {
                u.omega[w] = iq.omega[w];
            }
            assert_int_equal(rfe_friction_skip_q31(&fr, missed[g]), RFE_OK);
            assert_false(rfe_status_is_error(rfe_friction_step_q31(&fr, &u, &fe)));
            assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pq, &iq, &oq)));
            assert_memory_equal(&oq.velocity, &ve, sizeof ve);
            assert_memory_equal(oq.friction.mu, fe.mu, sizeof fe.mu);
            assert_memory_equal(oq.friction.sd, fe.sd, sizeof fe.sd);
            assert_memory_equal(oq.friction.valid, fe.valid, sizeof fe.valid);
        }
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pd, &in, &od)));
        assert_int_equal(oq.missed, missed[g]);
        assert_int_equal(od.missed, missed[g]);
        assert_int_equal(oq.restarted, (gaps[g] > 0.1) ? 1u : 0u);
        assert_int_equal(od.restarted, oq.restarted);
        assert_int_equal(oq.friction.status, od.friction.status);
        ASSERT_LE(fabs(rfe_fix_to_double(oq.velocity.vx, 23u) - od.velocity.vx), TOL_VX, "gap vx");
        ASSERT_LE(fabs(rfe_fix_to_double(oq.velocity.vy, 23u) - od.velocity.vy), TOL_VY, "gap vy");
        for (w = 0u; w < 4u; ++w) {
            if ((oq.friction.valid[w] != 0u) && (od.friction.valid[w] != 0u)) {
                ASSERT_LE(fabs(rfe_fix_to_double(oq.friction.mu[w], 29u) - od.friction.mu[w]),
                          TOL_MU, "gap mu");
            }
        }
    }
    /* refused after a gap: untouched but for the friction estimator's backup (scratch) */
    memcpy(&before, &pq, sizeof before);
    brake_both(&b, 0.5, -5.0, 110.0, &in, &iq);
    assert_int_equal(rfe_pipeline_step_q31(&pq, &iq, &oq), RFE_ERR_RANGE);
    assert_memory_equal(&pq.velocity, &before.velocity, sizeof pq.velocity);
    assert_memory_equal(&pq.friction.filter, &before.friction.filter, sizeof pq.friction.filter);
    assert_memory_equal(&pq.friction.cond, &before.friction.cond, sizeof pq.friction.cond);
    assert_memory_equal(&pq.friction.params, &before.friction.params, sizeof pq.friction.params);
    assert_memory_equal(&pq.last, &before.last, sizeof pq.last);
    assert_int_equal(oq.missed, 0u);
    assert_int_equal(oq.restarted, 0u);
}

/* REQ: the period against the fixed one in fixed point (REQ-OBS-023): shorter than half of
 * filter.dt refused (RFE_ERR_RANGE, untouched, the previous estimates reported, sat 0); half
 * of it (Q30: filter.dt / 2, floored) taken; the first sample's period ignored. */
/* REQ-OBS-023 REQ-FXP-016 */
static void test_a_period_shorter_than_half_is_refused_q31(void **state)
{
    both_t b;
    static rfe_pipeline_q31_t pl;
    static rfe_pipeline_q31_t before;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_pipeline_out_q31_t o;
    size_t k;
    (void)state;
    params_of(NULL, &b);
    memset(&pl, 0, sizeof pl);
    assert_int_equal(rfe_pipeline_init_q31(&pl, &b.pq, &b.vq), RFE_OK);
    brake_both(&b, 0.001, -6.0, 19.0, &in, &iq); /* first: ignored */
    assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pl, &iq, &o)));
    for (k = 0u; k < 20u; ++k) {
        brake_both(&b, 0.01, -6.0, 19.0, &in, &iq);
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pl, &iq, &o)));
    }
    memcpy(&before, &pl, sizeof before);
    iq.dt = (b.pq.filter.dt / 2) - 1;
    assert_int_equal(rfe_pipeline_step_q31(&pl, &iq, &o), RFE_ERR_RANGE);
    assert_memory_equal(&pl, &before, sizeof pl);
    assert_int_equal(o.friction.status, RFE_ERR_RANGE);
    assert_int_equal(o.velocity.status, RFE_ERR_RANGE);
    assert_int_equal(o.friction.sat, 0u);
    assert_int_equal(o.velocity.sat, 0u);
    assert_memory_equal(o.friction.mu, pl.last.mu, sizeof o.friction.mu);
    assert_int_equal(o.velocity.vx, pl.velocity.last.vx);
    iq.dt = b.pq.filter.dt / 2;
    assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pl, &iq, &o)));
}

/* REQ: every member a step writes is undone when the step is refused, in fixed point (the
 * undo copy's one list, scripts/codegen/templates/pipeline_undo.c.in; as the float test's
 * case): the pipeline's observer restarted by hand, then a sample it takes (its first: the
 * three filters initialised, the time on r_ref reset, started set, a new last output, the
 * saturation count added to) but the friction estimator refuses after its input noise was
 * set (wheels at 110 m/s). Composed by hand from the public parts, each listed member
 * changes, so a member missing from the list would leave the refused step's pipeline
 * different from the one before it. */
/* REQ-OBS-023 REQ-FXP-016 */
static void test_every_member_a_step_writes_is_undone_q31(void **state)
{
    both_t b;
    static rfe_pipeline_q31_t pl;
    static rfe_pipeline_q31_t before;
    static rfe_velocity_q31_t obs;
    rfe_velocity_input_t in;
    rfe_velocity_input_q31_t iq;
    rfe_pipeline_out_q31_t o;
    rfe_velocity_estimate_q31_t ve;
    rfe_velocity_mu_q31_t mu;
    rfe_fix_t v[2];
    rfe_fix_t r = 0;
    uint32_t sat = 0u;
    uint32_t magic;
    size_t k;
    (void)state;
    params_of(NULL, &b);
    memset(&pl, 0, sizeof pl);
    assert_int_equal(rfe_pipeline_init_q31(&pl, &b.pq, &b.vq), RFE_OK);
    for (k = 0u; k < 50u; ++k) {
        brake_both(&b, (k == 0u) ? 0.0 : 0.01, -6.0, 19.0, &in, &iq);
        assert_false(rfe_status_is_error(rfe_pipeline_step_q31(&pl, &iq, &o)));
    }
    /* the saturation count first: a later sample the observer saturates on (the yaw rate at
     * its limit after straight braking: the observer's count grows) refused by the friction
     * estimator made uninitialised by hand (nothing of it written) */
    brake_both(&b, 0.01, -6.0, 19.0, &in, &iq);
    iq.yaw_rate = RFE_FIX_LIMIT_YAW_RATE;
    obs = pl.velocity;
    for (k = 0u; k < 4u; ++k) {
        mu.mu[k] = pl.last.mu[k];
        mu.sd[k] = pl.last.sd[k];
        assert_true(mu.mu[k] >= 0);
    }
    assert_int_equal(rfe_velocity_step_q31(&obs, &iq, &mu, &ve), RFE_OK);
    assert_true(obs.sat != pl.velocity.sat);
    magic = pl.friction.magic;
    pl.friction.magic = 0u;
    memcpy(&before, &pl, sizeof before);
    assert_int_equal(rfe_pipeline_step_q31(&pl, &iq, &o), RFE_ERR_NOT_INITIALISED);
    assert_memory_equal(&pl, &before, sizeof pl);
    pl.friction.magic = magic;
    /* then every other member */
    assert_int_equal(rfe_velocity_restart_q31(&pl.velocity), RFE_OK);
    brake_both(&b, 0.01, -6.0, 110.0, &in, &iq);
    /* by hand: what the pipeline's observer step writes (the friction estimate's mu >= 0
     * here, so the pipeline's max(mu, 0) hands the same) */
    obs = pl.velocity;
    for (k = 0u; k < 4u; ++k) {
        mu.mu[k] = pl.last.mu[k];
        mu.sd[k] = pl.last.sd[k];
        assert_true(mu.mu[k] >= 0);
    }
    assert_int_equal(rfe_velocity_step_q31(&obs, &iq, &mu, &ve), RFE_OK);
    assert_true(memcmp(&obs.yaw, &pl.velocity.yaw, sizeof obs.yaw) != 0);
    assert_true(memcmp(&obs.lon, &pl.velocity.lon, sizeof obs.lon) != 0);
    assert_true(memcmp(&obs.lat, &pl.velocity.lat, sizeof obs.lat) != 0);
    assert_true(obs.r_on_ref != pl.velocity.r_on_ref);
    assert_true(obs.sd_vy_filter != pl.velocity.sd_vy_filter);
    assert_true(memcmp(&obs.last, &pl.velocity.last, sizeof obs.last) != 0);
    assert_true(obs.started != pl.velocity.started);
    /* and the friction estimator's input noise its set-up writes */
    v[0] = pl.r_yaw_acc;
    v[1] = ve.sd_yaw_acc;
    assert_int_equal(rfe_fix_norm(v, 2u, &r, &sat), RFE_OK);
    assert_true(ve.sd_vx != pl.friction.params.filter.sd_in_vx);
    assert_true(ve.sd_vy != pl.friction.params.filter.sd_in_vy);
    assert_true(r != pl.friction.params.filter.r_yaw_acc);
    memcpy(&before, &pl, sizeof before);
    assert_int_equal(rfe_pipeline_step_q31(&pl, &iq, &o), RFE_ERR_RANGE);
    /* untouched but for the friction estimator's backup (scratch) */
    assert_memory_equal(&pl.velocity, &before.velocity, sizeof pl.velocity);
    assert_memory_equal(&pl.friction.params, &before.friction.params, sizeof pl.friction.params);
    assert_memory_equal(&pl.friction.filter, &before.friction.filter, sizeof pl.friction.filter);
    assert_memory_equal(&pl.friction.cond, &before.friction.cond, sizeof pl.friction.cond);
    assert_memory_equal(&pl.last, &before.last, sizeof pl.last);
    assert_int_equal(pl.started, before.started);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inits_q31_refuse_other_layout_or_word),
        cmocka_unit_test(test_set_input_noise),
        cmocka_unit_test(test_pipeline_steps_both_estimators),
        cmocka_unit_test(test_an_error_leaves_the_pipeline_untouched),
        cmocka_unit_test(test_back_to_back),
        cmocka_unit_test(test_gaps_as_the_double_pipeline),
        cmocka_unit_test(test_a_period_shorter_than_half_is_refused_q31),
        cmocka_unit_test(test_every_member_a_step_writes_is_undone_q31),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
