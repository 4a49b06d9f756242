/**
 * @file test_robust_q31.c
 * @brief The fixed-point twin of test_robust_flt.c (the robustness issue): the q31 estimator
 *        step (rfe_friction_step_q31) under every input class a Q format can carry, in the
 *        operating corners, with a huge prior, and the q31 invariants of
 *        test/support/invariants.h (the INV_Q31 block) after every step of every bundled log
 *        (the .csv of scenarios/, 57) and every fault log (the .csv of scenarios/faults/, 15).
 *
 * Configurations (test/support/robust_gen.h, shared with the float twin): "paper.sckf",
 * "paper.ckf", "default.sckf" and, for the synthetic classes, "paper-absolute.sckf"; each
 * built as the double parameters (rfe_params_t) converted by rfe_params_to_q31_f64, what
 * mu_replay --real q31 does. Samples: the float twin's generators (double samples,
 * robust_gen.h) and the logs' rows, rounded to the Q formats of rfe_sample_q31_t by
 * rfe_fix_from_double (host/fixed_conv.h, the conversion of src/host/replay_q31.c).
 *
 * Input classes. A Q value has no NaN/Inf: the float test's non-finite class becomes the
 * host's conversion of +-Inf, +-1e30, +-DBL_MAX (saturated to +-RFE_FIX_MAX, counted, beyond
 * every limit) and the integer extremes INT32_MIN, -INT32_MAX, INT32_MAX; plus one LSB beyond
 * each RFE_FIX_LIMIT_* and 1.5 x the limit. Each must give RFE_ERR_RANGE (there is no
 * RFE_ERR_NONFINITE in Q), leave the whole rfe_friction_q31_t bit-identical (memcmp), report
 * the previous estimate with valid 0 and sat 0, and the next valid sample must give bit for
 * bit what it gives when the bad one never came. A value exactly at +-limit is accepted.
 *
 * What "unharmed" means for a valid sample: no error status (the CKF included: its
 * RFE_ERR_NOT_POSITIVE_DEFINITE would be a failure here), and after every step
 * inv_check_step_q31: x and mu inside [mu_min, mu_max] EXACTLY (Q29 integers, no slack),
 * S lower-triangular with a positive diagonal / P symmetric (exactly after a time update,
 * INV_Q31_CKF_SYM_LSB after an update) with Cholesky succeeding, sd > 0, valid in {0, 1};
 * the running saturation total grows by the step's count. Saturations are not failures (the
 * library counts them, docs/FIXED_POINT.md), they are printed per class; where a class must
 * have none (the 57 bundled logs, docs/FIXED_POINT.md "on all 57 bundled logs ... the count
 * is 0"), that is asserted, and where the double twin's sd leaves the Q30 range (sd >= 2) the
 * q31 step must report a saturation (never silent).
 *
 * Tolerances.
 *  - mu held while unobservable (status 2): exactly (TOL 0; the random-walk time update
 *    keeps the mean, rfe_cub_hold_random_walk_mean_q31), also with the largest prior sd the
 *    format holds and mu0 on a bound;
 *  - sd non-decreasing while unobservable: to the rounding of the default preset's cap,
 *    S <- c S with c = sd_max / sd rounded in Q24 (RFE_Q31_QC, relative 2^-24 at c ~ 1) and
 *    the row norms rounded to Q30: relative TOL_SD_CAP = 1e-5 (the float twin's) plus
 *    TOL_SD_LSB = 4 LSB of Q30;
 *  - q31 vs the double twin (double estimator on the unrounded rows, as
 *    test_friction_q31.c) on the sweep: |mu_q31 - mu_double| <= TOL_B2B = 0.005 (the issue's
 *    requirement, which test_friction_q31.c asserts on the settled samples of the 57 logs;
 *    here on every row of every log, fault logs included, whose q31 run has no saturation;
 *    documented worst over all samples 4.6e-4, paper CKF) and statuses agreeing on >= 99 % of
 *    the rows. A run with saturations (e.g. an sd driven beyond Q30's 2) departs from the
 *    double one by design: printed, not asserted; so do the rows after the first step whose
 *    status differs (a gate decision within the information's stated 1e-3 info_min of the
 *    threshold, docs/FIXED_POINT.md: one step of sine_steer_high_mu.mf in the default preset,
 *    information 25.0000 in Q10 against 24.9999 in double), where the two trajectories may
 *    part: printed with the deviation before and after, not asserted after;
 *  - projection shares of the corners: the float twin's bounds (about twice the measured
 *    share; NOT_ASSERTED where the data force the bounds), compared with the q31 count.
 * Besides, on every step of the sweep with status 2 or 3 (no measurement update) mu must
 * equal the previous step's exactly (the projection follows updates only, the sd bounds
 * only scale S).
 *
 * Measured (x86-64, gcc -O2; printed by the test):
 *  - sweep, 54 logs x 54 034 steps per configuration, 4 out-of-limits rows rejected: no
 *    saturation anywhere (estimator and input conversion); max |mu_q31 - mu_double| 1.0e-5
 *    (paper SCKF), 4.6e-4 (paper CKF), 3.7e-4 (default, sine_steer_low_mu.nf at t = 4.81 s,
 *    with today's sd-bound change; 3.0e-5 before it); statuses agree on every row; the
 *    default preset's 27 209 held steps keep mu bit for bit;
 *  - saturations of the synthetic classes (counted, invariants hold): every field at its
 *    limit at once 240 events in 80 of 160 steps (paper SCKF), 23 (CKF), 245 (default);
 *    extreme_load 2374 / 216 / 1760 in 800 steps; every other corner 0; the largest prior
 *    (SCKF sd0 = 2 - 2^-30): 4 events per step, and there the q31 sd SHRINKS at standstill
 *    (2.0 -> 1.75 in 300 steps at mu0 0.5, 1.5 -> 1.40 at mu0 = mu_max = 1.2 where the points
 *    0.5 + 2 sd leave +-4; the double's grows to 2.0007 / 1.5009): the saturated points
 *    carry a smaller spread. Reported, and never silent (asserted);
 *  - runtime: ~6 s (full), 0.5 s (light), ~25 s light under valgrind.
 *
 * Light mode (RFE_TEST_LIGHT=1, test_light.h, or valgrind detected by its LD_PRELOAD): the
 * sweep takes every LIGHT_FILE_STRIDE-th log (bundled and fault logs both) and their first
 * VG_ROWS rows, the interleaved run VG_ROWS rows, each corner VG_CORNER_STEPS steps (their
 * projection and validity bounds then not asserted), the huge prior 20 steps. The ASan/UBSan
 * build sweeps every row of the same subset of logs. The optimised build runs everything.
 */
#include "test_common.h"
#include "test_light.h"

#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define INV_Q31 1
#include "csv_log.h"
#include "invariants.h"
#include "param_file.h"
#include "replay_real.h"
#include "rfe/friction.h"
#include "rfe/friction_q31.h"
#include "host/fixed_conv.h"
#include "rfe/component/params_conv.h"
#include "robust_gen.h"

#define N_FIELDS 11
#define VG_ROWS 300
#define LIGHT_FILE_STRIDE 13 /* logs 0, 13, 26, 39, 52 (bundled), 65 (a fault log) */
#define VG_CORNER_STEPS 120
#define SETTLE 300           /* as the float twin: the input filter's v-hat settles first */
#define TOL_SD_CAP 1e-5
#define TOL_SD_LSB 4.0
#define TOL_B2B 0.005
#define MIN_STATUS_AGREE 0.99
#define N_BUNDLED 57
#define N_FAULT_LOGS 15
#define Q30_SD_MAX 2.0 /* sd beyond this does not fit Q30 */

static const char *const FIELD[N_FIELDS] = {"delta", "vx", "vy", "yaw_rate", "yaw_acc", "ax",
                                            "ay", "omega_fl", "omega_fr", "omega_rl", "omega_rr"};
static const rfe_fix_t QLIM[N_FIELDS] = {
    RFE_FIX_LIMIT_DELTA, RFE_FIX_LIMIT_VX,    RFE_FIX_LIMIT_VY,    RFE_FIX_LIMIT_YAW_RATE,
    RFE_FIX_LIMIT_YAW_ACC, RFE_FIX_LIMIT_ACC, RFE_FIX_LIMIT_ACC,   RFE_FIX_LIMIT_OMEGA,
    RFE_FIX_LIMIT_OMEGA, RFE_FIX_LIMIT_OMEGA, RFE_FIX_LIMIT_OMEGA};
static const unsigned int QFMT[N_FIELDS] = {
    RFE_FIX_Q_ANGLE, RFE_FIX_Q_SPEED, RFE_FIX_Q_SPEED, RFE_FIX_Q_YAWRATE, RFE_FIX_Q_ACC,
    RFE_FIX_Q_ACC,   RFE_FIX_Q_ACC,   RFE_FIX_Q_OMEGA, RFE_FIX_Q_OMEGA,   RFE_FIX_Q_OMEGA,
    RFE_FIX_Q_OMEGA};

static int light(void) { return rfe_test_light() || under_valgrind(); }

/* ---- samples and parameters -------------------------------------------------------------- */

static rfe_fix_t *field_q(rfe_sample_q31_t *u, int f)
{
    switch (f) {
    case 0: return &u->delta;
    case 1: return &u->vx;
    case 2: return &u->vy;
    case 3: return &u->yaw_rate;
    case 4: return &u->yaw_acc;
    case 5: return &u->ax;
    case 6: return &u->ay;
    default: return &u->omega[f - 7];
    }
}

static double field_d(const rfe_sample_t *u, int f)
{
    switch (f) {
    case 0: return u->delta;
    case 1: return u->vx;
    case 2: return u->vy;
    case 3: return u->yaw_rate;
    case 4: return u->yaw_acc;
    case 5: return u->ax;
    case 6: return u->ay;
    default: return u->omega[f - 7];
    }
}

/* The double sample in Q formats, rounded as the host does (src/host/replay_q31.c). */
static void to_q(const rfe_sample_t *d, rfe_sample_q31_t *q, uint32_t *sat)
{
    int f;
    for (f = 0; f < N_FIELDS; ++f) {
        *field_q(q, f) = rfe_fix_from_double(field_d(d, f), QFMT[f], sat);
    }
}

static void row_to_d(const rfe_sensor_row_t *row, rfe_sample_t *u)
{
    int w;
    u->delta = row->delta;
    u->vx = row->vx;
    u->vy = row->vy;
    u->yaw_rate = row->yaw_rate;
    u->yaw_acc = row->yaw_acc;
    u->ax = row->ax;
    u->ay = row->ay;
    for (w = 0; w < 4; ++w) {
        u->omega[w] = row->omega[w];
    }
}

/* Independent of the library: RFE_ERR_RANGE when a field is beyond its RFE_FIX_LIMIT_*. */
static rfe_status_t classify_q(const rfe_sample_q31_t *u)
{
    int f;
    for (f = 0; f < N_FIELDS; ++f) {
        rfe_sample_q31_t copy = *u;
        const int64_t v = *field_q(&copy, f);
        if (v > (int64_t)QLIM[f] || v < -(int64_t)QLIM[f]) {
            return RFE_ERR_RANGE;
        }
    }
    return RFE_OK;
}

static rfe_fix_t clamp32(int64_t v)
{
    return (rfe_fix_t)(v > INT32_MAX ? INT32_MAX : (v < INT32_MIN ? INT32_MIN : v));
}

typedef struct {
    rfe_params_t pd;     /* double parameters (the generators' measurement model) */
    rfe_params_q31_t pq; /* the same converted */
} both_t;

static void cfg_both(const cfg_t *c, both_t *b)
{
    cfg_params(c, &b->pd);
    memset(&b->pq, 0, sizeof(b->pq)); /* padding too: whole estimators are compared */
    assert_int_equal(rfe_params_to_q31_f64(&b->pd, &b->pq), RFE_OK);
}

/* Saturation counts of the class being run (printed by each test). */
typedef struct {
    uint64_t events;
    long steps;
} sat_count_t;

/* One step with every check of a valid sample; returns the status. */
static rfe_status_t step_valid(rfe_friction_q31_t *est, const rfe_sample_q31_t *u,
                               rfe_estimate_q31_t *out, const char *what, long k,
                               sat_count_t *sc)
{
    char why[INV_WHY];
    const uint32_t total = est->sat;
    rfe_status_t st = rfe_friction_step_q31(est, u, out);
    if (rfe_status_is_error(st)) {
        fail_msg("%s step %ld: valid sample rejected with status %d (%s)", what, k, (int)st,
                 rfe_status_str(st));
    }
    if (inv_check_step_q31(est, out, st, why)) {
        fail_msg("%s step %ld: %s", what, k, why);
    }
    if (total <= UINT32_MAX - out->sat && est->sat != total + out->sat) {
        fail_msg("%s step %ld: running saturation total %u, want %u + %u", what, k,
                 (unsigned)est->sat, (unsigned)total, (unsigned)out->sat);
    }
    if (sc != NULL) {
        sc->events += out->sat;
        sc->steps += (out->sat != 0u);
    }
    return st;
}

/* ---- bad input values -------------------------------------------------------------------- */

/* The float twin's warm-up: 150 model-consistent braking samples at mu 0.6, a little steer. */
static void warm_up(rfe_friction_q31_t *est, const both_t *b, rfe_sample_q31_t *next)
{
    rfe_estimate_q31_t out;
    uint32_t sat = 0;
    int k;
    for (k = 0; k < 150; ++k) {
        rfe_sample_t d = braking(25.0 - 0.02 * k, -0.05 - 0.0005 * k, 0.03 * sin(0.1 * k));
        rfe_sample_q31_t u;
        make_consistent(&b->pd, &d, 0.6);
        to_q(&d, &u, &sat);
        (void)step_valid(est, &u, &out, "warm-up", k, NULL);
    }
    {
        rfe_sample_t d = braking(21.0, -0.08, 0.02);
        make_consistent(&b->pd, &d, 0.6);
        to_q(&d, next, &sat);
    }
    assert_int_equal(sat, 0);
}

#define N_BAD 10

/* The bad values of field f and how many conversion saturations each must have counted. */
static void bad_values(int f, rfe_fix_t bad[N_BAD], uint32_t conv[N_BAD])
{
    const int64_t lim = QLIM[f];
    const double far[4] = {INFINITY, -INFINITY, 1e30, -DBL_MAX};
    int i;
    bad[0] = clamp32(lim + 1);
    bad[1] = clamp32(-lim - 1);
    bad[2] = clamp32(lim + lim / 2);
    bad[3] = INT32_MAX;
    bad[4] = INT32_MIN;
    bad[5] = -INT32_MAX;
    for (i = 0; i < N_BAD; ++i) {
        conv[i] = 0;
    }
    for (i = 0; i < 4; ++i) {
        bad[6 + i] = rfe_fix_from_double(far[i], QFMT[f], &conv[6 + i]);
    }
}

/* REQ: each field one LSB beyond its limit (both signs), 1.5 x the limit, INT32_MIN,
 * -INT32_MAX, INT32_MAX and the host's conversion of +-Inf, 1e30, -DBL_MAX (saturated, one
 * counted conversion saturation each) -> RFE_ERR_RANGE; the estimator bit-identical, the
 * output the previous estimate with valid 0 and sat 0; the next valid sample gives exactly
 * what it gives without the bad one. */
/* REQ-ROB-003 */
static void test_rfe_robust_q31_bad_field_rejected_state_untouched(void **state)
{
    static rfe_friction_q31_t est, before, twin;
    size_t c;
    int f, v, n_checked = 0;
    (void)state;
    for (c = 0; c < N_CFG; ++c) {
        both_t b;
        rfe_sample_q31_t good;
        rfe_estimate_q31_t prev;
        cfg_both(&CFG[c], &b);
        memset(&est, 0, sizeof(est));
        assert_int_equal(rfe_friction_init_q31(&est, &b.pq), RFE_OK);
        warm_up(&est, &b, &good);
        assert_int_equal(rfe_friction_get_q31(&est, &prev), RFE_OK);
        for (f = 0; f < N_FIELDS; ++f) {
            rfe_fix_t bad[N_BAD];
            uint32_t conv[N_BAD];
            bad_values(f, bad, conv);
            for (v = 0; v < N_BAD; ++v) {
                rfe_sample_q31_t u = good;
                rfe_estimate_q31_t out, out_twin;
                rfe_status_t st;
                int w;
                assert_int_equal(conv[v], v >= 6 ? 1u : 0u);
                *field_q(&u, f) = bad[v];
                assert_int_equal(classify_q(&u), RFE_ERR_RANGE);
                memcpy(&before, &est, sizeof(est));
                memset(&out, 0x5A, sizeof(out));
                st = rfe_friction_step_q31(&est, &u, &out);
                if (st != RFE_ERR_RANGE) {
                    fail_msg("%s: %s = %ld: status %d, want %d", CFG[c].name, FIELD[f],
                             (long)bad[v], (int)st, (int)RFE_ERR_RANGE);
                }
                if (memcmp(&est, &before, sizeof(est)) != 0) {
                    fail_msg("%s: %s = %ld changed the estimator", CFG[c].name, FIELD[f],
                             (long)bad[v]);
                }
                assert_int_equal(out.status, RFE_ERR_RANGE);
                assert_int_equal(out.sat, 0);
                assert_memory_equal(out.mu, prev.mu, sizeof(out.mu));
                assert_memory_equal(out.sd, prev.sd, sizeof(out.sd));
                for (w = 0; w < 4; ++w) {
                    assert_int_equal(out.valid[w], 0);
                }
                /* the next valid sample: the same as a twin that never saw the bad one */
                memcpy(&twin, &before, sizeof(est));
                st = rfe_friction_step_q31(&est, &good, &out);
                assert_int_equal(rfe_friction_step_q31(&twin, &good, &out_twin), st);
                assert_false(rfe_status_is_error(st));
                assert_memory_equal(&est, &twin, sizeof(est));
                assert_memory_equal(out.mu, out_twin.mu, sizeof(out.mu));
                assert_memory_equal(out.sd, out_twin.sd, sizeof(out.sd));
                assert_memory_equal(out.valid, out_twin.valid, sizeof(out.valid));
                assert_int_equal(out.sat, out_twin.sat);
                memcpy(&est, &before, sizeof(est)); /* every bad value meets the same state */
                ++n_checked;
            }
        }
    }
    assert_int_equal(n_checked, (int)N_CFG * N_FIELDS * N_BAD);
}

/* REQ: several fields beyond at once are one rejection (RFE_ERR_RANGE); NULL arguments give
 * RFE_ERR_NULL and an estimator that was never initialised RFE_ERR_NOT_INITIALISED (and writes
 * nothing, as the float twin); none of them changes the estimator. */
/* REQ-ROB-003 */
static void test_rfe_robust_q31_bad_combinations(void **state)
{
    static rfe_friction_q31_t est, before, zero;
    both_t b;
    rfe_sample_q31_t good, u;
    rfe_estimate_q31_t out, out_copy;
    int f;
    (void)state;
    cfg_both(&CFG[2], &b);
    memset(&est, 0, sizeof(est));
    assert_int_equal(rfe_friction_init_q31(&est, &b.pq), RFE_OK);
    warm_up(&est, &b, &good);
    memcpy(&before, &est, sizeof(est));
    for (f = 0; f < N_FIELDS; ++f) { /* two bad fields: INT32_MIN and one LSB beyond */
        u = good;
        *field_q(&u, f) = INT32_MIN;
        *field_q(&u, (f + 5) % N_FIELDS) = QLIM[(f + 5) % N_FIELDS] + 1;
        assert_int_equal(rfe_friction_step_q31(&est, &u, &out), RFE_ERR_RANGE);
    }
    u = good;
    for (f = 0; f < N_FIELDS; ++f) {
        *field_q(&u, f) = (f % 2) ? INT32_MIN : INT32_MAX;
    }
    assert_int_equal(rfe_friction_step_q31(&est, &u, &out), RFE_ERR_RANGE);
    assert_int_equal(rfe_friction_step_q31(&est, NULL, &out), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_step_q31(&est, &good, NULL), RFE_ERR_NULL);
    assert_int_equal(rfe_friction_step_q31(NULL, &good, &out), RFE_ERR_NULL);
    assert_memory_equal(&est, &before, sizeof(est));
    /* never initialised: the error, nothing written (no previous estimate to report) */
    memset(&zero, 0, sizeof(zero));
    memset(&out, 0x5A, sizeof(out));
    out_copy = out;
    assert_int_equal(rfe_friction_step_q31(&zero, &good, &out), RFE_ERR_NOT_INITIALISED);
    assert_memory_equal(&out, &out_copy, sizeof(out));
    memset(&before, 0, sizeof(before));
    assert_memory_equal(&zero, &before, sizeof(zero));
}

/* REQ: values exactly at +-limit, 0 and +-1 LSB are valid inputs, each accepted alone; all
 * fields at +limit or -limit at once (8 sign patterns: vx, ax/ay, the rest; 360 km/h, 5 g,
 * steer at the stops, 10 rad/s, 500 rad/s wheels) give no error and the invariants hold.
 * The saturations of this class are printed. */
/* REQ-ROB-004 */
static void test_rfe_robust_q31_values_at_limits_accepted(void **state)
{
    static rfe_friction_q31_t est;
    size_t c;
    int f, v, s;
    (void)state;
    for (c = 0; c < N_CFG; ++c) {
        both_t b;
        rfe_sample_q31_t good, u;
        rfe_estimate_q31_t out;
        sat_count_t alone = {0, 0}, all = {0, 0};
        long k = 0;
        cfg_both(&CFG[c], &b);
        memset(&est, 0, sizeof(est));
        assert_int_equal(rfe_friction_init_q31(&est, &b.pq), RFE_OK);
        warm_up(&est, &b, &good);
        for (f = 0; f < N_FIELDS; ++f) {
            const rfe_fix_t edge[5] = {QLIM[f], -QLIM[f], 0, 1, -1};
            for (v = 0; v < 5; ++v) {
                u = good;
                *field_q(&u, f) = edge[v];
                assert_int_equal(classify_q(&u), RFE_OK);
                (void)step_valid(&est, &u, &out, CFG[c].name, k++, &alone);
            }
        }
        for (s = 0; s < 1 << 3; ++s) {
            for (f = 0; f < N_FIELDS; ++f) {
                const int bit = (f == 1) ? 0 : ((f == 5 || f == 6) ? 1 : 2);
                *field_q(&u, f) = ((s >> bit) & 1) ? -QLIM[f] : QLIM[f];
            }
            for (v = 0; v < 20; ++v) {
                (void)step_valid(&est, &u, &out, CFG[c].name, k++, &all);
            }
        }
        printf("  at limits %-20s saturations: one field at a time %llu (%ld steps of 55), "
               "all fields %llu (%ld steps of 160)\n",
               CFG[c].name, (unsigned long long)alone.events, alone.steps,
               (unsigned long long)all.events, all.steps);
    }
}

/* ---- every step of a log, with its metadata ----------------------------------------------- */

/* The q31 parameters of a log (preset, the log's metadata, the filter kind; through the
 * double path, as mu_replay --real q31) and the double ones. */
static void log_params(const rfe_sensor_log_t *log, const char *path, const cfg_t *c, both_t *b)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    assert_int_equal(rfe_param_set_preset_f64(&ps, c->preset), 0);
    if (rfe_param_set_apply_meta(&ps, log, path, &err) != 0) {
        fail_msg("%s: %s", path, err.msg);
    }
    ps.filter = c->kind;
    memset(&b->pd, 0, sizeof(b->pd));
    memset(&b->pq, 0, sizeof(b->pq));
    assert_int_equal(rfe_replay_params_f64(&ps, &b->pd, NULL), RFE_OK);
    assert_int_equal(rfe_params_to_q31_f64(&b->pd, &b->pq), RFE_OK);
}

static void read_log(const char *path, rfe_sensor_log_t *log)
{
    rfe_io_error_t err;
    memset(log, 0, sizeof(*log));
    if (rfe_sensor_log_read(path, log, &err) != 0) {
        fail_msg("%s:%zu: %s", err.file, err.line, err.msg);
    }
}

/* REQ: one bad sample every 7 (a rotating field: one LSB beyond, INT32_MIN, -1.25 x the
 * limit) through a whole real log: at every valid sample the estimator is bit-identical to a
 * twin that only ever saw the valid samples. */
/* REQ-ROB-003 */
static void test_rfe_robust_q31_interleaved_errors_change_nothing(void **state)
{
    static rfe_friction_q31_t est, twin;
    const char *path = "scenarios/mu_step_hard_brake.mf.csv";
    rfe_sensor_log_t log;
    size_t c, r;
    (void)state;
    read_log(path, &log);
    for (c = 0; c < N_SWEEP_CFG; ++c) {
        both_t b;
        size_t n_bad = 0;
        log_params(&log, path, &CFG[c], &b);
        memset(&est, 0, sizeof(est));
        assert_int_equal(rfe_friction_init_q31(&est, &b.pq), RFE_OK);
        memcpy(&twin, &est, sizeof(est));
        for (r = 0; r < log.n_rows && (!light() || r < VG_ROWS); ++r) {
            rfe_sample_t d;
            rfe_sample_q31_t u;
            rfe_estimate_q31_t a, bo;
            uint32_t sat = 0;
            row_to_d(&log.rows[r], &d);
            to_q(&d, &u, &sat);
            assert_int_equal(sat, 0);
            if (r % 7 == 3) {
                rfe_sample_q31_t bad = u;
                const int f = (int)((r / 7) % N_FIELDS);
                const rfe_fix_t vals[3] = {QLIM[f] + 1, INT32_MIN,
                                           clamp32(-(int64_t)QLIM[f] - QLIM[f] / 4)};
                *field_q(&bad, f) = vals[(r / 7) % 3];
                assert_int_equal(rfe_friction_step_q31(&est, &bad, &a), RFE_ERR_RANGE);
                ++n_bad;
            }
            (void)step_valid(&est, &u, &a, CFG[c].name, (long)r, NULL);
            assert_int_equal(rfe_friction_step_q31(&twin, &u, &bo), a.status);
            if (memcmp(&est, &twin, sizeof(est)) != 0 || memcmp(a.mu, bo.mu, sizeof(a.mu)) != 0 ||
                memcmp(a.sd, bo.sd, sizeof(a.sd)) != 0 || a.sat != bo.sat) {
                fail_msg("%s row %zu: differs from the twin that never saw the %zu bad samples",
                         CFG[c].name, r, n_bad);
            }
        }
        assert_true(n_bad > 40);
    }
    rfe_sensor_log_free(&log);
}

/* ---- operating corners ------------------------------------------------------------------ */

typedef struct {
    const char *name;
    corner_fn_t fn;
    long steps;
    corner_kind_t kind;
    double max_projected[2]; /* paper presets, default preset; NOT_ASSERTED: see below */
    int sat_free;            /* SAT_FREE: no saturation may occur (asserted on full runs);
                                SAT_FREE_PAPER: in the paper presets only; 0: counted */
} corner_t;

#define NOT_ASSERTED 1.0
#define SAT_FREE 1
#define SAT_FREE_PAPER 2

/* The float twin's corners and projection bounds (about twice the share measured there;
 * NOT_ASSERTED where the data themselves force the bounds: see test_robust_flt.c). The q31
 * run takes the same samples rounded to Q (every generated value fits its format: asserted),
 * so its shares must meet the same bounds (measured: the float shares to +-0.03, e.g.
 * default slip_angle 0.477 / float 0.498, steer_stops 0.969 / 0.981).
 * Saturation-free: every corner but extreme_load stays inside the documented ranges of the
 * formats (speeds <= 25 m/s of Q23's 256, wheel speeds <= 300 rad/s of Q22's 512,
 * accelerations of the model-consistent samples well inside Q24's 128): measured 0 events.
 * extreme_load (ax, ay at +-50 m/s^2 at 100 m/s, loads clamped to 0) saturates by
 * construction: measured 2374 events in 800 steps (paper SCKF), 216 (CKF), 1760 (default);
 * printed, the invariants asserted. slip_angle and steer_stops, default preset (Magic Formula
 * tyre): their samples contradict the kinematics (test_robust_flt.c), and some updates move
 * mu beyond Q29's +-4 before the projection: measured 27 events in 24 of 1200 steps and 9
 * events (the paper presets 0, still asserted). */
static const corner_t CORNERS[] = {
    {"standstill", c_standstill, 3000, UNOBSERVABLE, {0.0, 0.0}, 1},
    {"creep", c_creep, 2000, UNOBSERVABLE, {0.0, 0.0}, 1},
    {"reverse", c_reverse, 2000, UNOBSERVABLE, {0.0, 0.0}, 1},
    {"through_zero", c_through_zero, 4200, OBSERVABLE, {0.01, 0.05}, 1},
    {"locked", c_locked, 800, OBSERVABLE, {NOT_ASSERTED, 0.05}, 1},
    {"spinning", c_spinning, 1000, OBSERVABLE, {0.01, NOT_ASSERTED}, 1},
    {"slip_angle", c_slip_angle, 1200, OBSERVABLE, {0.01, NOT_ASSERTED}, SAT_FREE_PAPER},
    {"steer_stops", c_steer_stops, 1200, OBSERVABLE, {0.15, NOT_ASSERTED}, SAT_FREE_PAPER},
    {"extreme_load", c_extreme_load, 800, OBSERVABLE, {NOT_ASSERTED, NOT_ASSERTED}, 0},
};
#define N_CORNERS (sizeof CORNERS / sizeof CORNERS[0])

/* REQ: in every corner and configuration: no error, the invariants after every step,
 * projections within the corner's bound; unobservable corners (vx below v_est_min) hold mu
 * exactly with a non-decreasing sd (TOL_SD_CAP, TOL_SD_LSB), and the default preset ends
 * them not valid. Saturations printed per corner. */
/* REQ-ROB-005 */
static void test_rfe_robust_q31_operating_corners(void **state)
{
    static rfe_friction_q31_t est;
    size_t c, i;
    (void)state;
    for (i = 0; i < N_CORNERS; ++i) {
        const corner_t *cn = &CORNERS[i];
        for (c = 0; c < N_CFG; ++c) {
            both_t b;
            rfe_sample_q31_t w0;
            rfe_estimate_q31_t out, start;
            sat_count_t sc = {0, 0};
            char what[96];
            const long n_steps = light() ? VG_CORNER_STEPS : cn->steps;
            long k, n_proj = 0, n_upd = 0, n_low = 0;
            int w;
            double sd_prev, sd_min = 1e300, sd_max = 0.0, bound;
            cfg_both(&CFG[c], &b);
            snprintf(what, sizeof(what), "%s/%s", cn->name, CFG[c].name);
            memset(&est, 0, sizeof(est));
            assert_int_equal(rfe_friction_init_q31(&est, &b.pq), RFE_OK);
            warm_up(&est, &b, &w0);
            assert_int_equal(rfe_friction_get_q31(&est, &start), RFE_OK);
            sd_prev = (double)start.sd[0];
            for (k = 0; k < n_steps; ++k) {
                rfe_sample_t d;
                rfe_sample_q31_t u;
                uint32_t conv = 0;
                rfe_status_t st;
                cn->fn(k, &b.pd, &d);
                to_q(&d, &u, &conv);
                if (conv != 0u) {
                    fail_msg("%s step %ld: a generated value does not fit its Q format", what, k);
                }
                st = step_valid(&est, &u, &out, what, k, &sc);
                n_proj += (st == RFE_PROJECTED) && !(cn->kind == UNOBSERVABLE && k < SETTLE);
                n_upd += (st == RFE_OK || st == RFE_PROJECTED);
                n_low += (st == RFE_NO_UPDATE_LOW_SPEED);
                sd_min = fmin(sd_min, rfe_fix_to_double(out.sd[0], RFE_FIX_Q_SD));
                sd_max = fmax(sd_max, rfe_fix_to_double(out.sd[0], RFE_FIX_Q_SD));
                if (cn->kind == UNOBSERVABLE && k < SETTLE) {
                    start = out;
                } else if (cn->kind == UNOBSERVABLE) {
                    if (st != RFE_NO_UPDATE_LOW_SPEED) {
                        fail_msg("%s step %ld: status %d, want 2 (below v_est_min)", what, k,
                                 (int)st);
                    }
                    for (w = 0; w < 4; ++w) {
                        if (out.mu[w] != start.mu[w]) {
                            fail_msg("%s step %ld: mu_%d moved from %ld to %ld (Q29) while "
                                     "unobservable", what, k, w, (long)start.mu[w],
                                     (long)out.mu[w]);
                        }
                    }
                    if (!((double)out.sd[0] >= sd_prev * (1.0 - TOL_SD_CAP) - TOL_SD_LSB)) {
                        fail_msg("%s step %ld: sd fell from %.0f to %ld (Q30) while "
                                 "unobservable", what, k, sd_prev, (long)out.sd[0]);
                    }
                }
                sd_prev = (double)out.sd[0];
            }
            printf("  %-14s %-20s updated %5ld  low-speed %5ld  projected %4ld (%.3f)  "
                   "sd %.3g..%.3g  mu_fl %.3f  saturations %llu in %ld steps\n",
                   cn->name, CFG[c].name, n_upd, n_low, n_proj,
                   (double)n_proj / (double)n_steps, sd_min, sd_max,
                   rfe_fix_to_double(out.mu[0], RFE_FIX_Q_MU), (unsigned long long)sc.events,
                   sc.steps);
            bound = cn->max_projected[CFG[c].preset == RFE_PRESET_DEFAULT];
            if (bound < NOT_ASSERTED && n_steps == cn->steps &&
                (double)n_proj > bound * (double)n_steps) {
                fail_msg("%s: %ld of %ld steps projected (bound %.2f)", what, n_proj, n_steps,
                         bound);
            }
            if ((cn->sat_free == SAT_FREE ||
                 (cn->sat_free == SAT_FREE_PAPER && CFG[c].preset == RFE_PRESET_PAPER)) &&
                sc.events != 0u) {
                fail_msg("%s: %llu saturations in a corner inside the formats' ranges", what,
                         (unsigned long long)sc.events);
            }
            if (cn->kind == UNOBSERVABLE && b.pq.filter.sd_valid > 0 && n_steps == cn->steps) {
                assert_int_equal(out.valid[0] | out.valid[1] | out.valid[2] | out.valid[3], 0);
            }
        }
    }
}

/* Whether one held step of a filter whose sd was sd_prev (every state) and becomes sd_new
 * fits the formats: the cubature points x +- sqrt(n) S e_j (|S_ij| <= sd_i) inside Q29's
 * +-4, the new S inside Q30's 2 (SCKF) or P = sd^2 inside Q31's 1 (CKF); with a relative
 * margin of 1e-3 for the rounding of the q31 run against the double one. sd_new is the
 * time update's sd before the default preset's cap. */
static int prior_fits(const cfg_t *c, size_t n, double mu0, double sd_prev, double sd_new)
{
    const double m = 1.0 - 1e-3;
    const int points = fabs(mu0) + sqrt((double)n) * sd_prev < 4.0 * m;
    return points && ((c->kind == RFE_FILTER_CKF) ? sd_new * sd_new < m : sd_new < 2.0 * m);
}

/* REQ: a time update does not move the mean, whatever the prior: with the largest prior sd
 * the Q formats hold (SCKF: S0 = sqrt_prior(sd0, sd0_common) < 2 in Q30, so sd0 up to
 * RFE_FIX_MAX = 2 - 2^-30 with sd0_common = 0 and sqrt(4 - sd0_common^2) - 2^-20 with it; the
 * CKF: P0 = sd0^2 < 1 in Q31, sd0 up to 1 - 2^-30), and 1.0 and 1.5 (SCKF) / 0.5 and 0.75
 * (CKF), mu0 inside and on each bound: 300 standstill steps (20 in light mode) hold mu0
 * exactly, status 2, every invariant. Where the cubature points leave Q29's +-4 or S (P)
 * leaves Q30 (Q31), the step saturates: counted, never silent, so
 *  - a step on which the double twin (same prior, rfe_friction_*_f64) fits the formats
 *    (prior_fits) must report no saturation in q31;
 *  - the paper preset (no sd bounds) must not lower an sd on a step that reports no
 *    saturation (a time update only adds process noise); the default preset keeps every sd
 *    within its cap sd_max (TOL_SD_CAP, TOL_SD_LSB). */
/* REQ-ROB-005 REQ-ROB-006 */
static void test_rfe_robust_q31_huge_prior_held(void **state)
{
    static rfe_friction_q31_t est;
    static rfe_friction_t ed;
    size_t c;
    int s, bnd, k, w;
    (void)state;
    for (c = 0; c < N_CFG; ++c) {
        for (s = 0; s < 3; ++s) {
            for (bnd = 0; bnd < 3; ++bnd) {
                both_t b;
                rfe_sample_q31_t u;
                rfe_sample_t ud;
                rfe_estimate_q31_t out, prev;
                rfe_estimate_t od;
                sat_count_t sc = {0, 0};
                char what[96];
                double sd0, sd_d_prev, q2;
                long n_fit = 0;
                cfg_both(&CFG[c], &b);
                if (CFG[c].kind == RFE_FILTER_CKF) {
                    b.pq.filter.sd0 = (s == 0) ? (1 << 29) : (s == 1) ? (3 << 28) : (1 << 30) - 1;
                } else if (s < 2) {
                    b.pq.filter.sd0 = (s == 0) ? (1 << 30) : (3 << 29);
                } else if (b.pq.filter.sd0_common == 0) {
                    b.pq.filter.sd0 = RFE_FIX_MAX;
                } else {
                    const double cc = rfe_fix_to_double(b.pq.filter.sd0_common, RFE_FIX_Q_SD);
                    uint32_t cs = 0;
                    b.pq.filter.sd0 = rfe_fix_from_double(sqrt(4.0 - cc * cc) - ldexp(1.0, -20),
                                                          RFE_FIX_Q_SD, &cs);
                    assert_int_equal(cs, 0);
                }
                b.pq.filter.mu0 = (bnd == 0)   ? b.pq.filter.mu0
                                  : (bnd == 1) ? b.pq.filter.mu_min
                                               : b.pq.filter.mu_max;
                sd0 = rfe_fix_to_double(b.pq.filter.sd0, RFE_FIX_Q_SD);
                b.pd.filter.sd0 = sd0; /* the double twin: the same prior, exactly */
                b.pd.filter.mu0 = rfe_fix_to_double(b.pq.filter.mu0, RFE_FIX_Q_MU);
                snprintf(what, sizeof(what), "%s sd0 %.9g mu0 %.3f", CFG[c].name, sd0,
                         b.pd.filter.mu0);
                memset(&est, 0, sizeof(est));
                if (rfe_friction_init_q31(&est, &b.pq) != RFE_OK) {
                    fail_msg("%s: init failed for a prior that fits the format", what);
                }
                assert_int_equal(rfe_friction_init_f64(&ed, &b.pd), RFE_OK);
                assert_int_equal(rfe_friction_get_q31(&est, &prev), RFE_OK);
                assert_int_equal(rfe_friction_get_f64(&ed, &od), RFE_OK);
                sd_d_prev = od.sd[0];
                q2 = b.pd.filter.q_mu * b.pd.filter.q_mu +
                     b.pd.filter.q_common * b.pd.filter.q_common;
                memset(&u, 0, sizeof(u));
                memset(&ud, 0, sizeof(ud));
                for (k = 0; k < (light() ? 20 : 300); ++k) {
                    int fits;
                    assert_int_equal(step_valid(&est, &u, &out, what, k, &sc),
                                     RFE_NO_UPDATE_LOW_SPEED);
                    assert_int_equal(rfe_friction_step_f64(&ed, &ud, &od),
                                     RFE_NO_UPDATE_LOW_SPEED);
                    /* the time update's sd before any bound: sqrt(sd^2 + row norm of S_Q ^2) */
                    fits = prior_fits(&CFG[c], est.n, b.pd.filter.mu0, sd_d_prev,
                                      sqrt(sd_d_prev * sd_d_prev + q2));
                    n_fit += fits;
                    if (fits && out.sat != 0u) {
                        fail_msg("%s step %d: %u saturations where the double twin (sd %.9g, "
                                 "predicted %.9g) fits the formats", what, k, (unsigned)out.sat,
                                 sd_d_prev, sqrt(sd_d_prev * sd_d_prev + q2));
                    }
                    sd_d_prev = od.sd[0];
                    for (w = 0; w < 4; ++w) {
                        if (out.mu[w] != b.pq.filter.mu0) {
                            fail_msg("%s step %d: mu_%d = %ld (Q29), held value %ld", what, k, w,
                                     (long)out.mu[w], (long)b.pq.filter.mu0);
                        }
                        if (b.pq.filter.sd_max == 0 && out.sd[w] < prev.sd[w] && out.sat == 0u) {
                            fail_msg("%s step %d: sd_%d fell from %ld to %ld (Q30) without a "
                                     "saturation", what, k, w, (long)prev.sd[w], (long)out.sd[w]);
                        }
                        if (b.pq.filter.sd_max > 0 &&
                            !((double)out.sd[w] <= (double)b.pq.filter.sd_max * (1.0 + TOL_SD_CAP) +
                                                       TOL_SD_LSB)) {
                            fail_msg("%s step %d: sd_%d = %ld (Q30) above the cap %ld", what, k,
                                     w, (long)out.sd[w], (long)b.pq.filter.sd_max);
                        }
                    }
                    prev = out;
                }
                printf("  huge prior %-20s sd0 %.9f mu0 %.3f: saturations %4llu in %3ld of %d "
                       "steps (%3ld fit the formats), sd at the end %.6f (double %.6f)\n",
                       CFG[c].name, sd0, b.pd.filter.mu0, (unsigned long long)sc.events,
                       sc.steps, k, n_fit, rfe_fix_to_double(out.sd[0], RFE_FIX_Q_SD), od.sd[0]);
            }
        }
    }
}

/* ---- every step of every bundled log ---------------------------------------------------- */

typedef struct {
    long steps, rows_bad, status[RFE_REPLAY_STATUS_SLOTS], status_agree, held;
    uint64_t sat, input_sat;
    long sat_steps, sd_beyond_q30;
    double mu_min, mu_max, sd_min, sd_max, dev_max;
    char dev_log[256];
} sweep_stats_t;

/* One log in one configuration: the q31 estimator on the rounded rows with every check, the
 * double twin on the rows as they are. Returns the largest |mu_q31 - mu_double|. */
static double sweep_file(const char *path, const cfg_t *c, size_t max_rows, sweep_stats_t *s,
                         int is_bundled)
{
    static rfe_friction_q31_t est, before;
    static rfe_friction_t ed;
    rfe_sensor_log_t log;
    rfe_estimate_q31_t prev;
    both_t b;
    size_t r;
    double dev = 0.0, dev_after = 0.0, dev_diverged_at = 0.0;
    int diverged = 0;
    uint64_t sat_log = 0;
    long agree = 0, rows = 0;
    read_log(path, &log);
    log_params(&log, path, c, &b);
    memset(&est, 0, sizeof(est));
    assert_int_equal(rfe_friction_init_q31(&est, &b.pq), RFE_OK);
    assert_int_equal(rfe_friction_init_f64(&ed, &b.pd), RFE_OK);
    assert_int_equal(rfe_friction_get_q31(&est, &prev), RFE_OK);
    for (r = 0; r < log.n_rows && r < max_rows; ++r) {
        const rfe_sensor_row_t *row = &log.rows[r];
        rfe_sample_t d;
        rfe_sample_q31_t u;
        rfe_estimate_q31_t out;
        rfe_estimate_t od;
        rfe_status_t st, std_;
        uint32_t in_sat = 0;
        char what[600];
        int w;
        double sd_d_max = 0.0;
        row_to_d(row, &d);
        to_q(&d, &u, &in_sat);
        s->input_sat += in_sat;
        snprintf(what, sizeof(what), "%s [%s] row %zu (t = %g)", path, c->name, r, row->t);
        std_ = rfe_friction_step_f64(&ed, &d, &od);
        if (classify_q(&u) == RFE_OK) {
            st = step_valid(&est, &u, &out, what, (long)r, NULL);
        } else {
            char why[INV_WHY];
            memcpy(&before, &est, sizeof(est));
            st = rfe_friction_step_q31(&est, &u, &out);
            if (st != RFE_ERR_RANGE || memcmp(&est, &before, sizeof(est)) != 0) {
                fail_msg("%s: out-of-limits sample: status %d (want %d) or state changed", what,
                         (int)st, (int)RFE_ERR_RANGE);
            }
            if (inv_check_step_q31(&est, &out, st, why)) {
                fail_msg("%s: %s", what, why);
            }
            ++s->rows_bad;
        }
        /* a step without a measurement update holds the mean exactly (the random-walk time
         * update keeps it, the sd bounds only scale S, the projection follows updates only) */
        if ((st == RFE_NO_UPDATE_LOW_SPEED || st == RFE_HELD_NOT_OBSERVABLE) &&
            memcmp(out.mu, prev.mu, sizeof(out.mu)) != 0) {
            fail_msg("%s: status %d moved mu_fl from %ld to %ld (Q29)", what, (int)st,
                     (long)prev.mu[0], (long)out.mu[0]);
        }
        prev = out;
        s->held += (st == RFE_NO_UPDATE_LOW_SPEED || st == RFE_HELD_NOT_OBSERVABLE);
        ++s->steps;
        ++s->status[rfe_replay_status_slot((int)st)];
        ++rows;
        agree += (st == std_);
        if (st != std_ && diverged == 0) {
            diverged = 1; /* a gate/projection decision differs: trajectories may part */
            dev_diverged_at = row->t;
        }
        s->sat += out.sat;
        sat_log += out.sat;
        s->sat_steps += (out.sat != 0u);
        for (w = 0; w < 4; ++w) {
            const double mu = rfe_fix_to_double(out.mu[w], RFE_FIX_Q_MU);
            const double sd = rfe_fix_to_double(out.sd[w], RFE_FIX_Q_SD);
            s->mu_min = fmin(s->mu_min, mu);
            s->mu_max = fmax(s->mu_max, mu);
            s->sd_min = fmin(s->sd_min, sd);
            s->sd_max = fmax(s->sd_max, sd);
            if (diverged == 0) {
                dev = fmax(dev, fabs(mu - od.mu[w]));
            } else {
                dev_after = fmax(dev_after, fabs(mu - od.mu[w]));
            }
            if (!rfe_status_is_error(std_)) {
                sd_d_max = fmax(sd_d_max, od.sd[w]);
            }
        }
        /* never silent: where the double sd leaves Q30 the q31 step reports it (the sd of a
         * rejected row is the previous one, already reported) */
        if (sd_d_max >= Q30_SD_MAX && !rfe_status_is_error(st)) {
            ++s->sd_beyond_q30;
            if (out.sat == 0u) {
                fail_msg("%s: the double sd is %.4g (beyond Q30) but the q31 step reports no "
                         "saturation", what, sd_d_max);
            }
        }
    }
    s->status_agree += agree;
    if (dev > s->dev_max) {
        s->dev_max = dev;
        snprintf(s->dev_log, sizeof(s->dev_log), "%s", path);
    }
    if (is_bundled) { /* docs/FIXED_POINT.md: no saturation on the 57 bundled logs */
        if (sat_log != 0u) {
            fail_msg("%s [%s]: %llu saturations on a bundled log", path, c->name,
                     (unsigned long long)sat_log);
        }
    }
    if (diverged != 0) {
        printf("    %s [%s]: a decision differs from the double twin's at t = %g s; "
               "|mu_q31 - mu_double| %.3g before, %.3g after (not asserted after)\n",
               path, c->name, dev_diverged_at, dev, dev_after);
    }
    if (sat_log == 0u) {
        if (!(dev <= TOL_B2B)) {
            fail_msg("%s [%s]: |mu_q31 - mu_double| = %.3g > %.3g", path, c->name, dev, TOL_B2B);
        }
    } else {
        printf("    %s [%s]: %llu saturations; |mu_q31 - mu_double| up to %.3g (not asserted)\n",
               path, c->name, (unsigned long long)sat_log, dev);
    }
    if (!((double)agree >= MIN_STATUS_AGREE * (double)rows)) {
        fail_msg("%s [%s]: statuses agree with the double twin on %ld of %ld rows", path,
                 c->name, agree, rows);
    }
    rfe_sensor_log_free(&log);
    return dev;
}

/* REQ: after every step of every bundled log (57) and every fault log (15), in the paper
 * preset (SCKF, CKF) and the default preset: the q31 invariants hold, valid rows never fail,
 * out-of-limits rows are rejected without a trace; no saturation on the bundled logs, every
 * sd beyond Q30 reported; q31 within TOL_B2B of the double twin where nothing saturated. */
/* REQ-ROB-006 */
static void test_rfe_robust_q31_every_step_of_every_scenario(void **state)
{
    static char names[160][256];
    size_t n, n_bundled, i, c;
    const int lt = light();
    const size_t stride = (lt || ASAN_BUILD) ? LIGHT_FILE_STRIDE : 1u;
    (void)state;
    n_bundled = list_logs("scenarios", names, 128);
    assert_int_equal(n_bundled, N_BUNDLED);
    n = n_bundled + list_logs("scenarios/faults", names + n_bundled, 160 - n_bundled);
    assert_int_equal(n - n_bundled, N_FAULT_LOGS);
    for (c = 0; c < N_SWEEP_CFG; ++c) {
        sweep_stats_t s;
        int k;
        size_t n_run = 0;
        memset(&s, 0, sizeof(s));
        s.mu_min = s.sd_min = 1e300;
        for (i = 0; i < n; i += stride) {
            (void)sweep_file(names[i], &CFG[c], lt ? VG_ROWS : (size_t)-1, &s, i < n_bundled);
            ++n_run;
        }
        printf("  sweep %-14s %zu logs, %ld steps, %ld rejected (out of limits), statuses",
               CFG[c].name, n_run, s.steps, s.rows_bad);
        for (k = 0; k < RFE_REPLAY_STATUS_SLOTS; ++k) {
            if (s.status[k] != 0) {
                printf(" %d:%ld", k, s.status[k]);
            }
        }
        printf("; mu %.3f..%.3f, sd %.3g..%.3g\n", s.mu_min, s.mu_max, s.sd_min, s.sd_max);
        printf("        saturations %llu in %ld steps (input conversion %llu), double sd beyond "
               "Q30 on %ld rows; %ld held steps, mu exactly kept; max |mu_q31 - mu_double| %.3g "
               "(%s); statuses agree %.4f\n",
               (unsigned long long)s.sat, s.sat_steps, (unsigned long long)s.input_sat,
               s.sd_beyond_q30, s.held, s.dev_max, s.dev_log,
               (double)s.status_agree / (double)s.steps);
        assert_true(s.steps > 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rfe_robust_q31_bad_field_rejected_state_untouched),
        cmocka_unit_test(test_rfe_robust_q31_bad_combinations),
        cmocka_unit_test(test_rfe_robust_q31_values_at_limits_accepted),
        cmocka_unit_test(test_rfe_robust_q31_interleaved_errors_change_nothing),
        cmocka_unit_test(test_rfe_robust_q31_operating_corners),
        cmocka_unit_test(test_rfe_robust_q31_huge_prior_held),
        cmocka_unit_test(test_rfe_robust_q31_every_step_of_every_scenario),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
