/**
 * @file robust_gen.h
 * @brief Shared by the robustness tests of the float/double estimator (test/robustness/test_robust_flt.c)
 *        and of the fixed-point one (test/robustness/test_robust_q31.c): the configurations, the
 *        model-consistent sample generators of the operating corners (double / rfe_real_t
 *        samples: the q31 test rounds them to the Q formats with rfe_fix_from_double, as
 *        mu_replay --real q31 does), and the list of the bundled logs.
 * Uses the estimator of the including translation unit's precision (short names, rfe/types.h) for the presets
 * and the measurement model. Include after test_common.h (cmocka).
 */
#ifndef RFE_TEST_ROBUST_GEN_H
#define RFE_TEST_ROBUST_GEN_H

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rfe/friction.h"
#include "rfe/component/meas.h"

typedef struct {
    const char *name;
    rfe_preset_t preset;
    rfe_filter_kind_t kind;
    int absolute; /* paper preset with the absolute tyre */
} cfg_t;

static const cfg_t CFG[] = {
    {"paper.sckf", RFE_PRESET_PAPER, RFE_FILTER_SCKF, 0},
    {"paper.ckf", RFE_PRESET_PAPER, RFE_FILTER_CKF, 0},
    {"default.sckf", RFE_PRESET_DEFAULT, RFE_FILTER_SCKF, 0},
    {"paper-absolute.sckf", RFE_PRESET_PAPER, RFE_FILTER_SCKF, 1},
};
#define N_CFG (sizeof CFG / sizeof CFG[0])
#define N_SWEEP_CFG 3 /* the scenario sweep: the first three (the presets x filters) */

static inline int under_valgrind(void)
{
    const char *pre = getenv("LD_PRELOAD");
    return pre != NULL && strstr(pre, "vgpreload") != NULL;
}

/* AddressSanitizer build (GCC and clang define __SANITIZE_ADDRESS__ / have the feature). */
#if defined(__SANITIZE_ADDRESS__)
#define ASAN_BUILD 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ASAN_BUILD 1
#endif
#endif
#ifndef ASAN_BUILD
#define ASAN_BUILD 0
#endif

static inline void cfg_params(const cfg_t *c, rfe_params_t *p)
{
    /* zero the padding too (double build): the estimator copies the struct, and the tests
     * compare whole estimators with memcmp */
    memset(p, 0, sizeof(*p));
    if (c->preset == RFE_PRESET_PAPER) {
        assert_int_equal(rfe_params_paper(p), RFE_OK);
    } else {
        assert_int_equal(rfe_params_default(p), RFE_OK);
    }
    p->filter.kind = c->kind;
    if (c->absolute) {
        p->tyre.mode = RFE_TYRE_ABSOLUTE;
    }
}

static inline double clampd(double x, double lim) { return x > lim ? lim : (x < -lim ? -lim : x); }

/* Writes ax, ay, yaw_acc = h(mu_true, u) of the library's own measurement model (the tyre
 * mode of p), iterating the loads (ax, ay are also load inputs), clamped to the limits: a
 * sample consistent with the model, so the corner tests see what a real car would give. */
static inline void make_consistent(const rfe_params_t *p, rfe_sample_t *u, double mu_true)
{
    rfe_meas_t m;
    rfe_real_t mu[4], z[3];
    int k, w;
    for (w = 0; w < 4; ++w) {
        mu[w] = (rfe_real_t)mu_true;
    }
    for (k = 0; k < 4; ++k) {
        assert_int_equal(rfe_meas_setup(&m, &p->vehicle, &p->tyre, u), RFE_OK);
        assert_int_equal(rfe_meas_eval(&m, &p->vehicle, &p->tyre, mu, z), RFE_OK);
        u->ax = (rfe_real_t)clampd((double)z[0], RFE_LIMIT_ACC);
        u->ay = (rfe_real_t)clampd((double)z[1], RFE_LIMIT_ACC);
        u->yaw_acc = (rfe_real_t)clampd((double)z[2], RFE_LIMIT_YAW_ACC);
    }
}

/* A braking sample at speed v with slip kappa on every wheel (omega R = (1 + kappa) v). */
static inline rfe_sample_t braking(double v, double kappa, double delta)
{
    rfe_sample_t u;
    int w;
    memset(&u, 0, sizeof(u));
    u.vx = (rfe_real_t)v;
    u.delta = (rfe_real_t)delta;
    u.yaw_rate = (rfe_real_t)(v * delta / 3.05);
    for (w = 0; w < 4; ++w) {
        u.omega[w] = (rfe_real_t)((1.0 + kappa) * v / 0.325);
    }
    return u;
}

typedef enum { UNOBSERVABLE, OBSERVABLE } corner_kind_t;

/* Sample k of a corner (valid inputs). mu_true shapes ax, ay, yaw_acc where the corner is
 * model-consistent. */
typedef void (*corner_fn_t)(long k, const rfe_params_t *p, rfe_sample_t *u);

static inline double wobble(long k, double a) { return a * sin(0.37 * (double)k + 0.2); }

static inline void c_standstill(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    int w;
    (void)p;
    memset(u, 0, sizeof(*u));
    u->ax = (rfe_real_t)wobble(k, 0.05); /* sensor noise, car at rest */
    u->ay = (rfe_real_t)wobble(k + 3, 0.05);
    u->yaw_acc = (rfe_real_t)wobble(k + 5, 0.05);
    u->delta = (rfe_real_t)(0.5 * sin(0.01 * (double)k)); /* steering at rest */
    for (w = 0; w < 4; ++w) {
        u->omega[w] = (rfe_real_t)wobble(k + w, 0.05);
    }
}

/* 0.05 .. 2.5 m/s forwards, wheels rolling, the car steered. */
static inline void c_creep(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    const double v = 1.275 + 1.225 * sin(0.005 * (double)k);
    *u = braking(v, 0.0, 0.4 * sin(0.003 * (double)k));
    make_consistent(p, u, 0.8);
}

/* 0 .. -10 m/s (reversing), wheels turning backwards, locked now and then. */
static inline void c_reverse(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    const double v = -5.0 + 5.0 * cos(0.004 * (double)k);
    int w;
    *u = braking(v, 0.0, -0.3 * sin(0.002 * (double)k));
    if ((k / 50) % 4 == 1) {
        for (w = 0; w < 4; ++w) {
            u->omega[w] = 0; /* locked while reversing */
        }
    }
    make_consistent(p, u, 0.5);
}

/* Forwards -> stop -> reverse -> stop -> forwards: vx passes through 0 (and v_min) with the
 * wheel speeds and the accelerations of a slow, consistent manoeuvre. */
static inline void c_through_zero(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    const double v = 6.0 * cos(0.003 * (double)k);
    (void)p;
    *u = braking(v, 0.0, 0.0);
    u->ax = (rfe_real_t)(-6.0 * 0.3 * sin(0.003 * (double)k)); /* dv/dt at 100 Hz */
}

/* Hard braking at 25 m/s with the front-left wheel locked (kappa = -1) and the others at the
 * ABS slip, then all four locked. */
static inline void c_locked(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    const double v = 25.0 - 0.02 * (double)(k % 800);
    int w;
    *u = braking(v, -0.10, 0.0);
    u->omega[RFE_FL] = 0;
    if (k >= 400) {
        for (w = 0; w < 4; ++w) {
            u->omega[w] = 0;
        }
    }
    make_consistent(p, u, 0.4);
}

/* Wheel spin: driven front wheels at kappa 0.5 .. 0.95 (omega R up to 20 x vx) just above
 * v_est_min, and a wheel spinning at 300 rad/s on a car at 4 m/s. */
static inline void c_spinning(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    const double v = 3.5 + 0.5 * sin(0.01 * (double)k);
    const double kap = 0.725 + 0.225 * sin(0.02 * (double)k);
    *u = braking(v, 0.0, 0.0);
    u->omega[RFE_FL] = u->omega[RFE_FR] = (rfe_real_t)(v / (1.0 - kap) / 0.325);
    if (k % 100 < 20) {
        u->omega[RFE_FR] = 300;
    }
    make_consistent(p, u, 0.3);
}

/* Slip angles up to and beyond alpha_max: vy = +-vx (45 deg drift), vy = 30 at vx 5 (80 deg,
 * clamped to alpha_max), yaw rate at its 10 rad/s limit (a spinning car). */
static inline void c_slip_angle(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    const long phase = (k / 200) % 3;
    *u = braking(phase == 1 ? 5.0 : 20.0, -0.02, 0.05);
    if (phase == 0) {
        u->vy = (rfe_real_t)(20.0 * sin(0.01 * (double)k));
    } else if (phase == 1) {
        u->vy = (rfe_real_t)(k % 2 ? 30.0 : -30.0);
    } else {
        u->yaw_rate = (rfe_real_t)(RFE_LIMIT_YAW_RATE * sin(0.05 * (double)k));
        u->vy = (rfe_real_t)(8.0 * cos(0.05 * (double)k));
    }
    make_consistent(p, u, 0.7);
}

/* Steer at its stops (+-1 rad road-wheel angle) while driving and braking at 5 .. 15 m/s. */
static inline void c_steer_stops(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    const double d = (k % 300 < 150) ? RFE_LIMIT_DELTA : -RFE_LIMIT_DELTA;
    *u = braking(10.0 + 5.0 * sin(0.004 * (double)k), -0.05, d);
    u->yaw_rate = (rfe_real_t)clampd((double)u->yaw_rate, 3.0);
    make_consistent(p, u, 0.9);
}

/* Accelerations at +-50 m/s^2 (loads of some wheels clamped to 0) and 100 m/s. */
static inline void c_extreme_load(long k, const rfe_params_t *p, rfe_sample_t *u)
{
    (void)p;
    *u = braking((k % 400 < 200) ? 30.0 : RFE_LIMIT_VX, -0.1, 0.02);
    u->ax = (rfe_real_t)(RFE_LIMIT_ACC * ((k % 4 < 2) ? 1.0 : -1.0));
    u->ay = (rfe_real_t)(RFE_LIMIT_ACC * ((k % 3 == 0) ? 1.0 : -1.0));
    u->yaw_acc = (rfe_real_t)(RFE_LIMIT_YAW_ACC * sin((double)k));
}

static inline int ends_with(const char *s, const char *suffix)
{
    const size_t a = strlen(s), b = strlen(suffix);
    return a >= b && strcmp(s + a - b, suffix) == 0;
}

/* The sensor logs of @p dir (*.csv), sorted, into names (at most max). */
static inline int cmp_str(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

static inline size_t list_logs(const char *dir, char names[][256], size_t max)
{
    DIR *d = opendir(dir);
    struct dirent *e;
    size_t n = 0, i;
    char *ptrs[128];
    char tmp[128][256];
    if (d == NULL) {
        return 0;
    }
    while ((e = readdir(d)) != NULL && n < max && n < 128) {
        if (ends_with(e->d_name, ".csv") && strlen(dir) + strlen(e->d_name) + 2 < 256) {
            snprintf(tmp[n], sizeof(tmp[n]), "%s/%s", dir, e->d_name);
            ptrs[n] = tmp[n];
            ++n;
        }
    }
    closedir(d);
    qsort(ptrs, n, sizeof(ptrs[0]), cmp_str);
    for (i = 0; i < n; ++i) {
        memcpy(names[i], ptrs[i], 256);
    }
    return n;
}

#endif /* RFE_TEST_ROBUST_GEN_H */
