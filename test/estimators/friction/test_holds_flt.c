/**
 * @file test_holds_flt.c
 * @brief Step 9's holds (docs/ESTIMATOR.md): the rear wheels' hold (`rear_hold_k`) and the
 *        jump hold (`jump_hold_k`, `jump_hold_len`). The estimator's valid flags against the
 *        rules recomputed here from its own outputs, on the bundled mu step (the front wheels
 *        reach the new surface one wheelbase before the rear ones) and on the spike fault log
 *        (an ax spike jerks the estimate), with a long gap and a standstill; the holds' reach
 *        (sides only, off at 0). Built twice: float32 and double.
 *
 * The independent check: the monitor off (its sd inflation would hide the filter's sd) and the
 * input filter off (tau_v = 0: the step's vx is the log's), so a front wheel's mu and sd are
 * its side's state x_j and sd_j. From them, the log's vx and the step's missed periods the
 * test computes mbar_j, d_j, the last estimate, the jump's distance and both holds in double,
 * and requires every flag to be the sd rule's (recomputed from mu and sd) unless held: a rear
 * wheel by either hold, a front wheel by the jump hold. The library computes the same
 * recursion in the build's real type: in float32 a comparison |x - ref| > k sd within a few ulp
 * of equality could go the other way, so the float32 build allows mismatches on rows where the
 * two sides of a comparison are within 1e-5 of each other (relative to sd; none seen) and the
 * double build none.
 */
#include "test_common.h"

#include <stdlib.h>
#include <string.h>

#include "friction_log.h"
#include "replay_real.h"
#include "rfe/friction.h"

#define LOG_PATH "scenarios/mu_step_hard_brake.mf.csv"
#define SPIKE_PATH "scenarios/faults/spike_ax.hard_brake_low_mu.mf.csv"
#if defined(RFE_REAL_DOUBLE)
#define TIE 0.0
#else
#define TIE 1e-5
#endif

/* The holds recomputed in double (docs/ESTIMATOR.md step 9). */
typedef struct {
    double k, len, dt, mbar[2], dist[2];
    double kj, jlen, prev[2], jdist[2];
    int held[2];  /* the rear wheels' hold */
    int jheld[2]; /* the jump hold: both wheels */
    int near_tie; /* this step's comparison was within TIE sd of equality */
} hold_ref_t;

static void ref_init(hold_ref_t *h, const rfe_params_t *p)
{
    h->k = (double)p->filter.rear_hold_k;
    h->kj = (double)p->filter.jump_hold_k;
    h->jlen = (double)p->filter.jump_hold_len;
    h->len = (double)p->vehicle.Lf + (double)p->vehicle.Lr;
    h->dt = (double)p->filter.dt;
    h->mbar[0] = h->mbar[1] = (double)p->filter.mu0;
    h->prev[0] = h->prev[1] = (double)p->filter.mu0;
    h->dist[0] = h->dist[1] = 0.0;
    h->jdist[0] = h->jdist[1] = 0.0;
    h->held[0] = h->held[1] = 0;
    h->jheld[0] = h->jheld[1] = 0;
    h->near_tie = 0;
}

/* |x - ref| > k sd, noting a near tie. */
static int beyond(hold_ref_t *h, double x, double ref, double k, double sd)
{
    const double dev = fabs(x - ref);
    if (fabs(dev - k * sd) <= TIE * sd) {
        h->near_tie = 1;
    }
    return dev > k * sd;
}

static void ref_update(hold_ref_t *h, const rfe_estimate_t *e, double vx, unsigned missed)
{
    const double ds = (vx > 0.0 ? vx : 0.0) * (h->dt * ((double)missed + 1.0));
    const double a = (ds < h->len) ? ds / h->len : 1.0;
    size_t j;
    h->near_tie = 0;
    for (j = 0; j < 2; ++j) {
        const double x = (double)e->mu[j]; /* fl, fr: the left and the right state */
        const double sd = (double)e->sd[j];
        if (h->k > 0.0) {
            h->mbar[j] += a * (x - h->mbar[j]);
            h->dist[j] = (h->dist[j] > ds) ? h->dist[j] - ds : 0.0;
            if (beyond(h, x, h->mbar[j], h->k, sd)) {
                h->dist[j] = h->len;
            }
        }
        h->held[j] = h->dist[j] > 0.0;
        if (h->kj > 0.0) {
            h->jdist[j] = (h->jdist[j] > ds) ? h->jdist[j] - ds : 0.0;
            if (beyond(h, x, h->prev[j], h->kj, sd)) {
                h->jdist[j] = h->jlen;
            }
            h->prev[j] = x;
        }
        h->jheld[j] = h->jdist[j] > 0.0;
    }
}

/* The log and its parameters (friction_log.h), the monitor and the input filter off (above). */
static void load(const char *path, rfe_sensor_log_t *log, rfe_params_t *p)
{
    friction_log_load(path, log, p);
    p->monitor.enable = ((rfe_real_t)(0.0));
    p->filter.tau_v = ((rfe_real_t)(0.0));
}

/* The sd rule's flag of wheel w (docs/ESTIMATOR.md step 9), from the step's outputs, with the
 * bound margin (mu - mu_min >= valid_bound_k sd: the same two operations in the same type as
 * the library's, so the same result; the monitor is off here, so the sd is the filter's). */
static uint8_t by_sd(const rfe_params_t *p, const rfe_estimate_t *e, size_t w)
{
    return ((e->sd[w] <= p->filter.sd_valid) && (e->mu[w] > p->filter.mu_min) &&
            (e->mu[w] < p->filter.mu_max) &&
            ((e->mu[w] - p->filter.mu_min) >= (p->filter.valid_bound_k * e->sd[w])))
               ? 1u
               : 0u;
}

/* Flags that the sd rule set and a hold turned off. */
typedef struct {
    size_t rear; /* rear wheels, by the rear wheels' hold alone */
    size_t jump; /* any wheel, by the jump hold */
} held_count_t;

/* Steps the estimator over the log (row gap: the row `gap_at` is preceded by `gap_missed`
 * missed periods once), then `stand` standstill samples, checking every flag against the
 * recomputed holds. Returns how many flags each hold turned off. */
static held_count_t run_checked(const rfe_params_t *p, const rfe_sensor_log_t *log, size_t gap_at,
                                unsigned gap_missed, size_t stand)
{
    rfe_friction_t est;
    hold_ref_t ref;
    rfe_estimate_t e;
    rfe_sample_t u;
    held_count_t n = {0u, 0u};
    size_t i, w;
    assert_int_equal(rfe_friction_init(&est, p), RFE_OK);
    ref_init(&ref, p);
    for (i = 0; i < log->n_rows + stand; ++i) {
        const unsigned missed = (i == gap_at) ? gap_missed : 0u;
        rfe_status_t st;
        if (i < log->n_rows) {
            rfe_replay_sample_from_row(&log->rows[i], &u);
        } else { /* standing: vx 0, wheels still, no slip */
            memset(&u, 0, sizeof u);
        }
        st = rfe_friction_step_after(&est, missed, &u, &e);
        assert_false(rfe_status_is_error(st));
        ref_update(&ref, &e, (double)u.vx, missed);
        for (w = 0; w < 4; ++w) {
            const size_t side = w % 2u; /* fl, rl: the left side; fr, rr: the right */
            const int rear = (w >= 2u) && (ref.held[side] != 0);
            const uint8_t rule = by_sd(p, &e, w);
            const uint8_t want = (rear || (ref.jheld[side] != 0)) ? 0u : rule;
            if ((e.valid[w] != want) && (ref.near_tie == 0)) {
                fail_msg("row %zu wheel %zu: valid %u, the rules say %u (rear held %d, jump "
                         "held %d)",
                         i, w, (unsigned)e.valid[w], (unsigned)want, ref.held[side],
                         ref.jheld[side]);
            }
            if (rule != 0u) {
                n.jump += (size_t)(ref.jheld[side] != 0);
                n.rear += (size_t)(rear && (ref.jheld[side] == 0));
            }
        }
        /* a side's wheels share the state: the holds change flags only */
        assert_true(e.sd[0] == e.sd[2] && e.mu[0] == e.mu[2]);
    }
    return n;
}

/* REQ: with the structure sides, a rear wheel is not valid for one wheelbase of travel after
 * its side's estimate moved by more than rear_hold_k sd from its smoothed value, and
 * otherwise valid exactly by the sd rule, on the bundled mu step (and through a gap and a
 * standstill); the hold turns some valid rear flags off there (the test is not vacuous). Also
 * with the jump hold off, so the rear wheels' hold alone is seen to act. */
/* REQ-EST-016 */
static void test_rear_hold_follows_the_rule(void **state)
{
    rfe_sensor_log_t log;
    rfe_params_t p;
    rfe_params_t q;
    held_count_t held;
    (void)state;
    load(LOG_PATH, &log, &p);
    assert_true(p.filter.rear_hold_k > ((rfe_real_t)(0.0)));
    assert_int_equal(p.filter.structure, RFE_STRUCT_SIDES);
    held = run_checked(&p, &log, (size_t)-1, 0u, 0u);
    print_message("[holds] %zu rear flags held, %zu by a jump on %s\n", held.rear, held.jump,
                  LOG_PATH);
    assert_true(held.rear > 10u);
    q = p;
    q.filter.jump_hold_k = ((rfe_real_t)(0.0));
    held = run_checked(&q, &log, (size_t)-1, 0u, 0u);
    assert_true(held.rear > 10u && held.jump == 0u);
    /* a gap of 400 periods (longer than a wheelbase at any speed above 0.8 m/s: the hold's
     * distance runs out and the smoothing takes a = 1) right after the step, then standing */
    (void)run_checked(&p, &log, 322u, 400u, 50u);
    rfe_sensor_log_free(&log);
}

/* REQ: with the structure sides, a step that moved a side's estimate by more than jump_hold_k
 * (new) sd holds both its wheels not valid for jump_hold_len of travel, and the flags are
 * otherwise the sd rule's (and the rear wheels' hold's), on the ax spike fault log (each spike
 * jerks the estimate: the test is not vacuous there), through a gap and a standstill; with the
 * rear wheels' hold off too, so the jump hold alone is seen to act on the front wheels. */
/* REQ-EST-018 */
static void test_jump_hold_follows_the_rule(void **state)
{
    rfe_sensor_log_t log;
    rfe_params_t p;
    rfe_params_t q;
    held_count_t held;
    (void)state;
    load(SPIKE_PATH, &log, &p);
    assert_true(p.filter.jump_hold_k > ((rfe_real_t)(0.0)));
    assert_true(p.filter.jump_hold_len > ((rfe_real_t)(0.0)));
    held = run_checked(&p, &log, (size_t)-1, 0u, 0u);
    print_message("[holds] %zu rear flags held, %zu by a jump on %s\n", held.rear, held.jump,
                  SPIKE_PATH);
    assert_true(held.jump > 10u);
    q = p;
    q.filter.rear_hold_k = ((rfe_real_t)(0.0));
    held = run_checked(&q, &log, (size_t)-1, 0u, 0u);
    assert_true(held.jump > 10u && held.rear == 0u);
    (void)run_checked(&p, &log, 300u, 400u, 50u);
    /* a hold longer than a wheelbase: the jump's distance, not the wheelbase, sets it */
    q = p;
    q.filter.jump_hold_len = ((rfe_real_t)(6.0));
    (void)run_checked(&q, &log, 300u, 7u, 50u);
    rfe_sensor_log_free(&log);
}

/* REQ: the holds are off at rear_hold_k = jump_hold_k = 0 and with the structure wheels (four
 * states: every wheel its own), where every flag is the sd rule's. */
/* REQ-EST-016 REQ-EST-018 */
static void test_holds_reach(void **state)
{
    rfe_sensor_log_t log;
    rfe_params_t p;
    rfe_friction_t est;
    rfe_estimate_t e;
    rfe_sample_t u;
    size_t i;
    int pass;
    (void)state;
    load(SPIKE_PATH, &log, &p);
    for (pass = 0; pass < 2; ++pass) {
        rfe_params_t q = p;
        if (pass == 0) {
            q.filter.rear_hold_k = ((rfe_real_t)(0.0));
            q.filter.jump_hold_k = ((rfe_real_t)(0.0));
        } else {
            q.filter.structure = RFE_STRUCT_WHEELS;
            q.filter.sd0_common = ((rfe_real_t)(0.0));
            q.filter.q_common = ((rfe_real_t)(0.0));
        }
        assert_int_equal(rfe_friction_init(&est, &q), RFE_OK);
        for (i = 0; i < log.n_rows; ++i) {
            size_t w;
            rfe_replay_sample_from_row(&log.rows[i], &u);
            assert_false(rfe_status_is_error(rfe_friction_step(&est, &u, &e)));
            for (w = 0; w < 4; ++w) {
                assert_int_equal(e.valid[w], by_sd(&q, &e, w));
            }
        }
    }
    rfe_sensor_log_free(&log);
}

/* REQ: rear_hold_k, jump_hold_k and jump_hold_len must be finite and >= 0 (RFE_ERR_PARAM
 * otherwise, nothing written). */
/* REQ-EST-016 REQ-EST-018 REQ-EST-003 */
static void test_hold_parameters(void **state)
{
    rfe_params_t p;
    rfe_friction_t est;
    int which;
    (void)state;
    for (which = 0; which < 3; ++which) {
        rfe_real_t *v;
        assert_int_equal(rfe_params_default(&p), RFE_OK);
        v = (which == 0)   ? &p.filter.rear_hold_k
            : (which == 1) ? &p.filter.jump_hold_k
                           : &p.filter.jump_hold_len;
        *v = ((rfe_real_t)(-0.5));
        memset(&est, 0x5A, sizeof est);
        assert_int_equal(rfe_friction_init(&est, &p), RFE_ERR_PARAM);
        assert_int_equal(est.magic, 0x5A5A5A5Au);
        *v = (rfe_real_t)NAN;
        assert_int_equal(rfe_params_validate(&p), RFE_ERR_PARAM);
        *v = ((rfe_real_t)(0.0));
        assert_int_equal(rfe_params_validate(&p), RFE_OK);
    }
}

/* REQ: the periods of rfe_friction_skip count in the next step's hold as step_after's missed
 * ones do (skip(n) then step = step_after(n), bit for bit, while the rear wheels are held), and
 * saturate far beyond any wheelbase: after skips of 2^32 - 1 and more periods in all, the next
 * step travels more than a wheelbase and nothing is held. */
/* REQ-EST-016 REQ-EST-015 */
static void test_rear_hold_skip_counts(void **state)
{
    rfe_sensor_log_t log;
    rfe_params_t p;
    static rfe_friction_t a;
    static rfe_friction_t b;
    rfe_estimate_t ea, eb;
    rfe_sample_t u;
    size_t i;
    (void)state;
    load(LOG_PATH, &log, &p);
    assert_int_equal(rfe_friction_init(&a, &p), RFE_OK);
    for (i = 0; i < 325u; ++i) { /* into the mu step, where the rear wheels are held */
        rfe_replay_sample_from_row(&log.rows[i], &u);
        assert_false(rfe_status_is_error(rfe_friction_step(&a, &u, &ea)));
    }
    assert_true((a.hold.held[0] != 0u) || (a.hold.held[1] != 0u));
    b = a;
    rfe_replay_sample_from_row(&log.rows[325], &u);
    assert_int_equal(rfe_friction_skip(&b, 3u), RFE_OK);
    assert_int_equal(b.hold.pending, 3u);
    assert_int_equal(rfe_friction_step(&b, &u, &eb), rfe_friction_step_after(&a, 3u, &u, &ea));
    assert_memory_equal(&ea, &eb, sizeof ea);
    assert_memory_equal(&a.hold, &b.hold, sizeof a.hold);
    assert_int_equal(b.hold.pending, 0u);
    /* saturation: in skip, then in the step */
    assert_int_equal(rfe_friction_skip(&b, UINT32_MAX), RFE_OK);
    assert_int_equal(rfe_friction_skip(&b, 7u), RFE_OK);
    assert_int_equal(b.hold.pending, UINT32_MAX);
    assert_false(rfe_status_is_error(rfe_friction_step_after(&b, 9u, &u, &eb)));
    assert_true(b.hold.held[0] == 0u && b.hold.held[1] == 0u && b.hold.pending == 0u);
    assert_int_equal(eb.valid[RFE_RL], eb.valid[RFE_FL]);
    assert_int_equal(eb.valid[RFE_RR], eb.valid[RFE_FR]);
    rfe_sensor_log_free(&log);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rear_hold_follows_the_rule),
        cmocka_unit_test(test_jump_hold_follows_the_rule),
        cmocka_unit_test(test_holds_reach),
        cmocka_unit_test(test_hold_parameters),
        cmocka_unit_test(test_rear_hold_skip_counts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
