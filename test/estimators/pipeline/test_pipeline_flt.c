/**
 * @file test_pipeline_flt.c
 * @brief The composed entry (rfe/pipeline.h) and the friction estimator's per-step input
 *        noise: statuses, the untouched state on error, and that each step hands the
 *        observer's estimate and sd to the friction estimator.
 */
#include "test_common.h"

#include <string.h>

#include "rfe/pipeline.h"

static rfe_velocity_input_t rolling(const rfe_params_t *p, rfe_real_t v, rfe_real_t dt)
{
    rfe_velocity_input_t in;
    size_t i;
    memset(&in, 0, sizeof(in));
    in.dt = dt;
    for (i = 0u; i < 4u; ++i) {
        in.omega[i] = v / p->vehicle.R;
    }
    return in;
}

static void test_set_input_noise(void **state)
{
    rfe_params_t p;
    rfe_friction_t est;
    rfe_friction_t before;
    (void)state;
    memset(&p, 0, sizeof p); /* the estimators copy it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&est, 0, sizeof(est));
    assert_int_equal(rfe_friction_set_input_noise(NULL, 0.1f, 0.1f, 0.1f), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_set_input_noise(&est, 0.1f, 0.1f, 0.1f),
                     RFE_ERR_NOT_INITIALISED);
    assert_int_equal(rfe_friction_init(&est, &p), RFE_OK);
    memcpy(&before, &est, sizeof before); /* bytes, padding included (not a member copy) */
    assert_int_equal(rfe_friction_set_input_noise(&est, -0.1f, 0.1f, 0.1f), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise(&est, 0.1f, (rfe_real_t)NAN, 0.1f),
                     RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_set_input_noise(&est, 0.1f, 0.1f, 0.0f), RFE_ERR_RANGE);
    assert_memory_equal(&est, &before, sizeof(est));
    assert_int_equal(rfe_friction_set_input_noise(&est, 0.2f, 0.3f, 0.4f), RFE_OK);
    assert_close(est.params.filter.sd_in_vx, 0.2, 1e-7, 0.0, "sd_in_vx");
    assert_close(est.params.filter.sd_in_vy, 0.3, 1e-7, 0.0, "sd_in_vy");
    assert_close(est.params.filter.r_yaw_acc, 0.4, 1e-7, 0.0, "r_yaw_acc");
}

/* REQ-OBS-007 */
static void test_pipeline_steps_both_estimators(void **state)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_t pl;
    rfe_pipeline_out_t o;
    rfe_velocity_input_t in;
    size_t k;
    (void)state;
    memset(&p, 0, sizeof p); /* the estimators copy it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&vp, 0, sizeof vp);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    assert_int_equal(rfe_pipeline_init(NULL, &p, &vp), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_init(&pl, NULL, &vp), RFE_ERR_NULL);
    assert_int_equal(rfe_pipeline_init(&pl, &p, NULL), RFE_ERR_NULL);
    vp.driven = 0u;
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_ERR_PARAM);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
    for (k = 0u; k < 100u; ++k) {
        in = rolling(&p, 20.0f, (k == 0u) ? 0.0f : 0.01f);
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    }
    /* the friction estimator ran on the observer's vx (straight rolling: no excitation, so
     * its estimate is held), with the observer's sd as its input noise */
    assert_close(o.velocity.vx, 20.0, 1e-3, 0.0, "vx");
    assert_close(pl.friction.params.filter.sd_in_vx, o.velocity.sd_vx, 0.0, 0.0, "sd_in_vx");
    assert_close(pl.friction.params.filter.sd_in_vy, o.velocity.sd_vy, 0.0, 0.0, "sd_in_vy");
    assert_close(pl.friction.params.filter.r_yaw_acc,
                 sqrt((double)p.filter.r_yaw_acc * p.filter.r_yaw_acc +
                      (double)o.velocity.sd_yaw_acc * o.velocity.sd_yaw_acc),
                 1e-6, 1e-6, "r_yaw_acc");
    assert_memory_equal(&pl.last, &o.friction, sizeof(o.friction));
}

/* REQ-OBS-007 */
static void test_an_error_leaves_the_pipeline_untouched(void **state)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_t pl;
    rfe_pipeline_t before;
    rfe_pipeline_out_t o;
    rfe_velocity_input_t in;
    (void)state;
    memset(&p, 0, sizeof p); /* the estimators copy it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    memset(&vp, 0, sizeof vp);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    memset(&pl, 0, sizeof pl); /* padding and scratch defined, so whole-struct compares are */
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
    in = rolling(&p, 20.0f, 0.0f);
    assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    memcpy(&before, &pl, sizeof before); /* bytes, padding included (not a member copy) */
    assert_int_equal(rfe_pipeline_step(NULL, &in, &o), RFE_ERR_NULL);
    in = rolling(&p, 20.0f, 0.01f);
    in.ax = (rfe_real_t)NAN; /* the observer rejects it */
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_NONFINITE);
    assert_memory_equal(&pl, &before, sizeof(pl));
    /* the observer accepts a sample that the friction estimator rejects: a wheel speed
     * beyond the friction estimator's limit is within the observer's too, so use an
     * uninitialised friction estimator instead */
    pl.friction.magic = 0u;
    memcpy(&before, &pl, sizeof before); /* bytes, padding included (not a member copy) */
    in = rolling(&p, 20.0f, 0.01f);
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_NOT_INITIALISED);
    assert_memory_equal(&pl, &before, sizeof(pl));
}

/* REQ-ABI-001 */
static void test_inits_refuse_other_layout_or_word(void **state)
{
    /* Each init called as its wrapper would be from a caller compiled otherwise: another
     * size of the state, or another configuration word (maxima, number type). */
    static rfe_pipeline_t pl, pl0;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    const uint32_t other = RFE_CONFIG_REAL ^ 3u; /* float <-> double, or the q31 word */
    (void)state;
    assert_int_equal(rfe_params_default(&p), RFE_OK);
    assert_int_equal(rfe_velocity_params_default(&vp), RFE_OK);
    memset(&pl, 0x5A, sizeof pl);
    pl0 = pl;
    assert_int_equal((rfe_friction_init)(&pl.friction, &p, sizeof pl.friction - 8u, RFE_CONFIG_REAL), RFE_ERR_ABI);
    assert_int_equal((rfe_friction_init)(&pl.friction, &p, sizeof pl.friction, other), RFE_ERR_ABI);
    assert_int_equal((rfe_velocity_init)(&pl.velocity, &vp, &p, sizeof pl.velocity + 8u, RFE_CONFIG_REAL), RFE_ERR_ABI);
    assert_int_equal((rfe_velocity_init)(&pl.velocity, &vp, &p, sizeof pl.velocity, other), RFE_ERR_ABI);
    assert_int_equal((rfe_pipeline_init)(&pl, &p, &vp, sizeof pl - 8u, RFE_CONFIG_REAL), RFE_ERR_ABI);
    assert_int_equal((rfe_pipeline_init)(&pl, &p, &vp, sizeof pl, other), RFE_ERR_ABI);
    assert_memory_equal(&pl, &pl0, sizeof pl);
    /* and through the wrappers, this file's own layout: accepted */
    assert_int_equal(rfe_pipeline_init(&pl, &p, &vp), RFE_OK);
}

static void init_pipeline(rfe_pipeline_t *pl, rfe_params_t *p, rfe_velocity_params_t *vp)
{
    memset(p, 0, sizeof *p); /* the estimators copy it, padding included: keep it defined */
    assert_int_equal(rfe_params_default(p), RFE_OK);
    memset(vp, 0, sizeof *vp);
    assert_int_equal(rfe_velocity_params_default(vp), RFE_OK);
    memset(pl, 0, sizeof *pl); /* padding defined, so whole-struct compares are */
    assert_int_equal(rfe_pipeline_init(pl, p, vp), RFE_OK);
}

/* 100 braking steps at 100 Hz: a friction estimate below the prior's sd, so a gap's time
 * updates have room to grow it. */
static rfe_velocity_input_t brake(const rfe_params_t *p, rfe_real_t dt)
{
    rfe_velocity_input_t in = rolling(p, 20.0f, dt);
    size_t i;
    in.ax = (rfe_real_t)-6.0;
    for (i = 0u; i < 4u; ++i) {
        in.omega[i] = (rfe_real_t)(20.0 * 0.95) / p->vehicle.R;
    }
    return in;
}

/* REQ: a gap before a sample (rfe/pipeline.h, OBSERVER.md §6 "Gaps"). Expected results
 * come from the public parts composed by hand: the pipeline's step after a gap of k periods
 * equals, bit for bit, the observer's step with the real period, then rfe_friction_skip(k)
 * and rfe_friction_step on the observer's outputs with its sd as input noise; k =
 * round(dt / filter.dt) - 1 beyond two periods (0.05 s: 4), none at two (jitter). Beyond
 * obs_dt_max (0.5 s: 49 periods) the observer starts afresh: its estimate is a fresh
 * observer's first. The first sample's dt is ignored. */
/* REQ-OBS-023 REQ-EST-015 */
static void test_a_gap_is_told_to_both_estimators(void **state)
{
    static rfe_pipeline_t pl;
    static rfe_velocity_t obs;
    static rfe_friction_t fr;
    static rfe_velocity_t fresh;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_out_t o;
    rfe_velocity_estimate_t ve;
    rfe_estimate_t fe;
    rfe_velocity_input_t in;
    const struct {
        float dt;
        uint32_t missed;
        uint32_t restarted;
    } gaps[] = {{0.02f, 0u, 0u}, {0.05f, 4u, 0u}, {0.09f, 8u, 0u}, {0.5f, 49u, 1u}};
    size_t g;
    size_t k;
    (void)state;
    for (g = 0u; g < sizeof gaps / sizeof gaps[0]; ++g) {
        init_pipeline(&pl, &p, &vp);
        in = brake(&p, 5.0f); /* the first sample's dt is ignored */
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
        assert_int_equal(o.missed, 0u);
        assert_int_equal(o.restarted, 0u);
        for (k = 0u; k < 100u; ++k) {
            in = brake(&p, 0.01f);
            assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
        }
        obs = pl.velocity;
        fr = pl.friction;
        in = brake(&p, gaps[g].dt);
        in.ax = (rfe_real_t)-5.0;
        {
            rfe_velocity_mu_t mu;
            rfe_status_t sv;
            size_t i;
            const rfe_real_t r = pl.r_yaw_acc;
            for (i = 0u; i < 4u; ++i) {
                mu.mu[i] = pl.last.mu[i];
                mu.sd[i] = pl.last.sd[i];
            }
            if (gaps[g].restarted != 0u) {
                assert_int_equal(rfe_velocity_restart(&obs), RFE_OK);
            }
            sv = rfe_velocity_step(&obs, &in, &mu, &ve);
            assert_int_equal(sv, RFE_OK);
            assert_int_equal(rfe_friction_set_input_noise(&fr, ve.sd_vx, ve.sd_vy,
                                                          (rfe_real_t)sqrt((double)(r * r) + (double)(ve.sd_yaw_acc * ve.sd_yaw_acc))),
                             RFE_OK);
            {
                rfe_sample_t u;
                memset(&u, 0, sizeof u);
                u.delta = ve.delta;
                u.vx = ve.vx;
                u.vy = ve.vy;
                u.yaw_rate = in.yaw_rate;
                u.yaw_acc = ve.yaw_acc;
                u.ax = in.ax;
                u.ay = in.ay;
                for (i = 0u; i < 4u; ++i) {
                    u.omega[i] = in.omega[i];
                }
                assert_int_equal(rfe_friction_skip(&fr, gaps[g].missed), RFE_OK);
                assert_false(rfe_status_is_error(rfe_friction_step(&fr, &u, &fe)));
            }
        }
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
        assert_int_equal(o.missed, gaps[g].missed);
        assert_int_equal(o.restarted, gaps[g].restarted);
        assert_memory_equal(&o.velocity, &ve, sizeof ve);
        assert_memory_equal(&o.friction, &fe, sizeof fe);
        assert_memory_equal(pl.friction.filter.sckf.S, fr.filter.sckf.S, sizeof fr.filter.sckf.S);
        if (gaps[g].restarted != 0u) {
            rfe_velocity_estimate_t first;
            assert_int_equal(rfe_velocity_init(&fresh, &vp, &p), RFE_OK);
            assert_int_equal(rfe_velocity_step(&fresh, &in, NULL, &first), RFE_OK);
            assert_memory_equal(&o.velocity, &first, sizeof first);
        }
    }
}

/* Everything of two pipelines but the friction estimator's backup (scratch that each step
 * writes before it updates, so that an error can restore what it held). */
static void assert_same_pipeline(const rfe_pipeline_t *a, const rfe_pipeline_t *b)
{
    assert_memory_equal(&a->velocity, &b->velocity, sizeof a->velocity);
    assert_memory_equal(&a->last, &b->last, sizeof a->last);
    assert_int_equal(a->started, b->started);
    assert_memory_equal(&a->friction.params, &b->friction.params, sizeof a->friction.params);
    assert_memory_equal(&a->friction.filter, &b->friction.filter, sizeof a->friction.filter);
    assert_memory_equal(&a->friction.cond, &b->friction.cond, sizeof a->friction.cond);
    assert_memory_equal(&a->friction.mon, &b->friction.mon, sizeof a->friction.mon);
}

/* REQ: a sample after a gap that the friction estimator refuses leaves the pipeline as it
 * was: the observer's restart and the gap's time updates are undone too, whether the gap's
 * time update fails (a factor made non-finite by hand) or the sample is out of the friction
 * estimator's range; a sample the observer refuses does not restart it. */
/* REQ-OBS-023 */
static void test_a_refused_sample_after_a_gap_changes_nothing(void **state)
{
    static rfe_pipeline_t pl;
    static rfe_pipeline_t before;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_out_t o;
    rfe_velocity_input_t in;
    rfe_real_t s00;
    size_t k;
    (void)state;
    init_pipeline(&pl, &p, &vp);
    for (k = 0u; k < 50u; ++k) {
        in = brake(&p, (k == 0u) ? 0.0f : 0.01f);
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    }
    s00 = pl.friction.filter.sckf.S[0];
    pl.friction.filter.sckf.S[0] = (rfe_real_t)INFINITY;
    memcpy(&before, &pl, sizeof before);
    in = brake(&p, 0.5f);
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_NONFINITE);
    assert_same_pipeline(&pl, &before);
    assert_int_equal(o.missed, 0u);
    assert_int_equal(o.restarted, 0u);
    /* a sample the observer takes but the friction estimator refuses (wheels at 110 m/s:
     * the restarted observer's vx is beyond RFE_LIMIT_VX): the gap's time updates, which
     * would succeed, are not made either */
    pl.friction.filter.sckf.S[0] = s00;
    memcpy(&before, &pl, sizeof before);
    in = brake(&p, 0.5f);
    for (k = 0u; k < 4u; ++k) {
        in.omega[k] = (rfe_real_t)110.0 / p.vehicle.R;
    }
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_RANGE);
    assert_same_pipeline(&pl, &before);
    /* and a sample the observer refuses after a long gap: not restarted either */
    memcpy(&before, &pl, sizeof before);
    in = brake(&p, 0.5f);
    in.ay = (rfe_real_t)NAN;
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_NONFINITE);
    assert_memory_equal(&pl, &before, sizeof pl);
}

/* REQ: every member a step writes is undone when the step is refused (the undo copy's one
 * list, scripts/codegen/templates/pipeline_undo.c.in, written for both twins). The step is
 * chosen to write every member the list holds: the pipeline's observer restarted by hand
 * (its next sample a first one: the three filters initialised, the time on r_ref reset,
 * started set, a new last output) and a sample the observer takes but the friction estimator
 * refuses after its input noise was set (wheels at 110 m/s: vx beyond RFE_LIMIT_VX). The
 * same step composed by hand from the public parts shows that each listed member changes,
 * so a member missing from the list would leave the refused step's pipeline different from
 * the one before it (assert_same_pipeline compares the whole observer). */
/* REQ-OBS-023 */
static void test_every_member_a_step_writes_is_undone(void **state)
{
    static rfe_pipeline_t pl;
    static rfe_pipeline_t before;
    static rfe_velocity_t obs;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_out_t o;
    rfe_velocity_input_t in;
    rfe_velocity_estimate_t ve;
    rfe_velocity_mu_t mu;
    double r_new;
    size_t k;
    (void)state;
    init_pipeline(&pl, &p, &vp);
    for (k = 0u; k < 50u; ++k) {
        in = brake(&p, (k == 0u) ? 0.0f : 0.01f);
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    }
    assert_int_equal(rfe_velocity_restart(&pl.velocity), RFE_OK);
    in = brake(&p, 0.01f);
    for (k = 0u; k < 4u; ++k) {
        in.omega[k] = (rfe_real_t)110.0 / p.vehicle.R;
    }
    /* by hand: what the pipeline's observer step writes (the friction estimate's mu >= 0
     * here, so the pipeline's max(mu, 0) hands the same) */
    obs = pl.velocity;
    for (k = 0u; k < 4u; ++k) {
        mu.mu[k] = pl.last.mu[k];
        mu.sd[k] = pl.last.sd[k];
        assert_true(mu.mu[k] >= (rfe_real_t)0.0);
    }
    assert_int_equal(rfe_velocity_step(&obs, &in, &mu, &ve), RFE_OK);
    assert_true(memcmp(&obs.yaw, &pl.velocity.yaw, sizeof obs.yaw) != 0);
    assert_true(memcmp(&obs.lon, &pl.velocity.lon, sizeof obs.lon) != 0);
    assert_true(memcmp(&obs.lat, &pl.velocity.lat, sizeof obs.lat) != 0);
    assert_true(obs.r_on_ref != pl.velocity.r_on_ref);
    assert_true(obs.sd_vy_filter != pl.velocity.sd_vy_filter);
    assert_true(memcmp(&obs.last, &pl.velocity.last, sizeof obs.last) != 0);
    assert_true(obs.started != pl.velocity.started);
    /* and the friction estimator's input noise its set-up writes */
    assert_true(ve.sd_vx != pl.friction.params.filter.sd_in_vx);
    assert_true(ve.sd_vy != pl.friction.params.filter.sd_in_vy);
    r_new = sqrt((double)pl.r_yaw_acc * pl.r_yaw_acc + (double)ve.sd_yaw_acc * ve.sd_yaw_acc);
    /* the set-up's root is in rfe_real_t: apart by more than float's rounding (1e-6 relative) */
    assert_true(fabs(r_new - (double)pl.friction.params.filter.r_yaw_acc) > (1e-6 * r_new));
    memcpy(&before, &pl, sizeof before);
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_RANGE);
    assert_same_pipeline(&pl, &before);
}

/* REQ: the period against the fixed one (rfe/pipeline.h): a period shorter than half of
 * filter.dt (the caller runs faster than filter.dt says; the friction step would take it as
 * a whole period) is refused with RFE_ERR_RANGE, the pipeline untouched and the previous
 * estimates reported; half of it is taken; a non-finite period is the observer's refusal
 * (RFE_ERR_NONFINITE), not a restart; the first sample's period is ignored. */
/* REQ-OBS-023 */
static void test_a_period_shorter_than_half_is_refused(void **state)
{
    static rfe_pipeline_t pl;
    static rfe_pipeline_t before;
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_pipeline_out_t o;
    rfe_velocity_input_t in;
    size_t k;
    (void)state;
    init_pipeline(&pl, &p, &vp);
    in = brake(&p, 0.001f); /* first: ignored */
    assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    for (k = 0u; k < 20u; ++k) {
        in = brake(&p, 0.01f);
        assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    }
    memcpy(&before, &pl, sizeof before);
    in = brake(&p, (rfe_real_t)0.0049);
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_RANGE);
    assert_memory_equal(&pl, &before, sizeof pl);
    assert_int_equal(o.friction.status, RFE_ERR_RANGE);
    assert_int_equal(o.velocity.status, RFE_ERR_RANGE);
    assert_memory_equal(o.friction.mu, pl.last.mu, sizeof o.friction.mu);
    assert_true(o.velocity.vx == pl.velocity.last.vx);
    in = brake(&p, (rfe_real_t)NAN);
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_NONFINITE);
    assert_memory_equal(&pl, &before, sizeof pl);
    in = brake(&p, (rfe_real_t)INFINITY);
    assert_int_equal(rfe_pipeline_step(&pl, &in, &o), RFE_ERR_NONFINITE);
    assert_memory_equal(&pl, &before, sizeof pl);
    in = brake(&p, (rfe_real_t)0.005); /* half of 0.01, exactly in both types */
    assert_false(rfe_status_is_error(rfe_pipeline_step(&pl, &in, &o)));
    assert_int_equal(o.missed, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_inits_refuse_other_layout_or_word),
        cmocka_unit_test(test_set_input_noise),
        cmocka_unit_test(test_pipeline_steps_both_estimators),
        cmocka_unit_test(test_an_error_leaves_the_pipeline_untouched),
        cmocka_unit_test(test_a_gap_is_told_to_both_estimators),
        cmocka_unit_test(test_a_refused_sample_after_a_gap_changes_nothing),
        cmocka_unit_test(test_a_period_shorter_than_half_is_refused),
        cmocka_unit_test(test_every_member_a_step_writes_is_undone),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
