/**
 * @file bench_flt.c
 * @brief Benchmark cases of the float32 (default) or double (-DRFE_REAL_DOUBLE) library:
 *        the whole estimator step and every module, on the samples of one sensor log.
 *
 * Filter-level cases (sckf.*, ckf.*, qr.*, chol.*) start from the states a paper-preset run
 * of the same log passes through (recorded once by bench_setup, the estimator's own
 * sequence: predict, meas_setup, update, clamp), restored before every call; the restore
 * alone is the baseline case the caller subtracts.
 */
#include <math.h>

#include "rfe/component/chol.h"
#include "rfe/component/ckf.h"
#include "rfe/friction.h"
#include "rfe/pipeline.h"
#include "rfe/velocity.h"
#include "rfe/component/meas.h"
#include "rfe/component/obsmat.h"
#include "rfe/component/qr.h"
#include "rfe/component/sckf.h"
#include "rfe/component/tyre.h"

#include "csv_log.h"
#include "param_file.h"
#include "replay_real.h"

#include "harness.h"

#if defined(RFE_REAL_DOUBLE)
const char *const bench_flavour = "f64";
#else
const char *const bench_flavour = "f32";
#endif

#define NM ((size_t)RFE_N_MAX)
#define TC ((size_t)RFE_TRIA_COLS_MAX)
#define MAXN 4096u
#define RFE_R(x) ((rfe_real_t)(x))

static size_t n_samples;
static rfe_sample_t samples[MAXN];
static rfe_real_t ys[MAXN][RFE_MEAS];
static rfe_real_t mu_true[MAXN][RFE_WHEELS];
static rfe_wheel_kin_t kins[MAXN];
static rfe_real_t f0x[MAXN][RFE_WHEELS];
static rfe_real_t f0y[MAXN][RFE_WHEELS];
static rfe_meas_t meas_paper[MAXN];
static rfe_meas_t meas_abs[MAXN];
static rfe_params_t par_paper;    /* paper preset, paper tyre */
static rfe_params_t par_abs;      /* paper preset, absolute tyre */
static rfe_params_t par_magic;    /* paper preset, Magic Formula tyre */
static rfe_params_t par_step;     /* the parameters of the step case being run */
static rfe_friction_t est;
static rfe_estimate_t out;
/* The velocity observer and the composed entry on the log's ESC signals (docs/OBSERVER.md),
 * with the log's true friction (sd 0.05) as the observer's friction input. */
static rfe_velocity_input_t esc[MAXN];
static rfe_velocity_mu_t esc_mu[MAXN];
static rfe_velocity_params_t vel_par;
static rfe_velocity_t vel;
static rfe_velocity_estimate_t vel_out;
static rfe_pipeline_t pipe_state;
static rfe_pipeline_out_t pipe_out;

/* Recorded filter states: before the time update (post[k], i.e. after step k-1) and before
 * the measurement update (pre[k]). x and the whole factor (SCKF S / CKF P, ld RFE_N_MAX). */
typedef struct {
    rfe_real_t x[RFE_N_MAX];
    rfe_real_t F[RFE_N_MAX * RFE_N_MAX];
} snap_t;
static snap_t sckf_post[MAXN];
static snap_t sckf_pre[MAXN];
static snap_t ckf_post[MAXN];
static snap_t ckf_pre[MAXN];
static rfe_sckf_t sckf;
static rfe_ckf_t ckf;
static rfe_real_t tria_in[MAXN][RFE_WHEELS * 12];
static rfe_real_t tria_work[RFE_N_MAX * RFE_TRIA_COLS_MAX];
static rfe_real_t chol_L[RFE_N_MAX * RFE_N_MAX];

/* ---- measurement callbacks (as the estimator's, for T = I) ----------------------------- */
static const rfe_meas_t *cur_meas;
static const rfe_params_t *cur_par;
static rfe_status_t bench_measure(void *ctx, const rfe_real_t *x, rfe_real_t *z, size_t n, size_t m)
{
    (void)ctx;
    (void)n;
    (void)m;
    return rfe_meas_eval(cur_meas, &cur_par->vehicle, &cur_par->tyre, x, z);
}

static void restore(snap_t *s, rfe_real_t *x, rfe_real_t *F)
{
    memcpy(x, s->x, sizeof s->x);
    memcpy(F, s->F, sizeof s->F);
}
static void save(snap_t *s, const rfe_real_t *x, const rfe_real_t *F)
{
    memcpy(s->x, x, sizeof s->x);
    memcpy(s->F, F, sizeof s->F);
}

/* ---- step cases ----------------------------------------------------------------------- */
static void prep_step(const rfe_params_t *p)
{
    par_step = *p;
    if (rfe_friction_init(&est, &par_step) != RFE_OK) {
        fprintf(stderr, "bench: estimator init failed\n");
        exit(1);
    }
}
static rfe_params_t par_default;
static rfe_params_t par_paper_ckf;
static rfe_params_t par_abs_ckf;
static void prep_step_sckf_paper(void) { prep_step(&par_paper); }
static void prep_step_ckf_paper(void) { prep_step(&par_paper_ckf); }
static void prep_step_sckf_abs(void) { prep_step(&par_abs); }
static void prep_step_ckf_abs(void) { prep_step(&par_abs_ckf); }
static void prep_step_default(void) { prep_step(&par_default); }
static void run_step(size_t k)
{
    bench_sink += (uint32_t)rfe_friction_step(&est, &samples[k], &out);
}
static void prep_velocity(void)
{
    if (rfe_velocity_init(&vel, &vel_par, &par_default) != RFE_OK) {
        fprintf(stderr, "bench: observer init failed\n");
    }
}
static void run_velocity(size_t k)
{
    bench_sink += (uint32_t)rfe_velocity_step(&vel, &esc[k], &esc_mu[k], &vel_out);
}
static void prep_pipeline(void)
{
    if (rfe_pipeline_init(&pipe_state, &par_default, &vel_par) != RFE_OK) {
        fprintf(stderr, "bench: pipeline init failed\n");
    }
}
static void run_pipeline(size_t k)
{
    bench_sink += (uint32_t)rfe_pipeline_step(&pipe_state, &esc[k], &pipe_out);
}

/* ---- module cases --------------------------------------------------------------------- */
static void run_kin(size_t k)
{
    rfe_wheel_kin_t kin;
    bench_sink += (uint32_t)rfe_tyre_kinematics(&par_paper.vehicle, &par_paper.tyre,
                                               &samples[k], &kin);
}
static void run_forces_norm(size_t k)
{
    rfe_real_t fx[RFE_WHEELS];
    rfe_real_t fy[RFE_WHEELS];
    bench_sink += (uint32_t)rfe_tyre_forces_norm(&par_paper.tyre, &kins[k], fx, fy);
}
static void run_forces_abs(size_t k)
{
    rfe_real_t fx[RFE_WHEELS];
    rfe_real_t fy[RFE_WHEELS];
    bench_sink +=
        (uint32_t)rfe_tyre_forces_abs(&par_abs.tyre, &kins[k], mu_true[k], fx, fy);
}
static void run_forces_magic(size_t k)
{
    rfe_real_t fx[RFE_WHEELS];
    rfe_real_t fy[RFE_WHEELS];
    bench_sink +=
        (uint32_t)rfe_tyre_forces_abs(&par_magic.tyre, &kins[k], mu_true[k], fx, fy);
}
static void run_obsmat(size_t k)
{
    rfe_real_t H[RFE_H_SIZE];
    bench_sink += (uint32_t)rfe_obsmat_build(&par_paper.vehicle, samples[k].delta,
                                            f0x[k], f0y[k], H);
}
static void run_setup_paper(size_t k)
{
    rfe_meas_t h;
    bench_sink += (uint32_t)rfe_meas_setup(&h, &par_paper.vehicle, &par_paper.tyre,
                                          &samples[k]);
}
static void run_setup_abs(size_t k)
{
    rfe_meas_t h;
    bench_sink +=
        (uint32_t)rfe_meas_setup(&h, &par_abs.vehicle, &par_abs.tyre, &samples[k]);
}
static void run_eval_paper(size_t k)
{
    rfe_real_t z[RFE_MEAS];
    bench_sink += (uint32_t)rfe_meas_eval(&meas_paper[k], &par_paper.vehicle,
                                         &par_paper.tyre, mu_true[k], z);
}
static void run_eval_abs(size_t k)
{
    rfe_real_t z[RFE_MEAS];
    bench_sink += (uint32_t)rfe_meas_eval(&meas_abs[k], &par_abs.vehicle, &par_abs.tyre,
                                         mu_true[k], z);
}

static void run_restore_sckf(size_t k) { restore(&sckf_post[k], sckf.x, sckf.S); }
static void run_sckf_predict(size_t k)
{
    restore(&sckf_post[k], sckf.x, sckf.S);
    bench_sink += (uint32_t)rfe_sckf_predict(&sckf, NULL, NULL);
}
static void run_sckf_update_paper(size_t k)
{
    restore(&sckf_pre[k], sckf.x, sckf.S);
    cur_meas = &meas_paper[k];
    cur_par = &par_paper;
    bench_sink += (uint32_t)rfe_sckf_update(&sckf, bench_measure, NULL, ys[k]);
}
static void run_sckf_update_abs(size_t k)
{
    restore(&sckf_pre[k], sckf.x, sckf.S);
    cur_meas = &meas_abs[k];
    cur_par = &par_abs;
    bench_sink += (uint32_t)rfe_sckf_update(&sckf, bench_measure, NULL, ys[k]);
}
static void run_restore_ckf(size_t k) { restore(&ckf_post[k], ckf.x, ckf.P); }
static void run_ckf_predict(size_t k)
{
    restore(&ckf_post[k], ckf.x, ckf.P);
    bench_sink += (uint32_t)rfe_ckf_predict(&ckf, NULL, NULL);
}
static void run_ckf_update_paper(size_t k)
{
    restore(&ckf_pre[k], ckf.x, ckf.P);
    cur_meas = &meas_paper[k];
    cur_par = &par_paper;
    bench_sink += (uint32_t)rfe_ckf_update(&ckf, bench_measure, NULL, ys[k]);
}
static void run_ckf_update_abs(size_t k)
{
    restore(&ckf_pre[k], ckf.x, ckf.P);
    cur_meas = &meas_abs[k];
    cur_par = &par_abs;
    bench_sink += (uint32_t)rfe_ckf_update(&ckf, bench_measure, NULL, ys[k]);
}
/* Tria of the cubature time update's input, 4 x 12 ([Xc, S_Q], Xc = [S, -S]/sqrt(2)). */
static void load_tria(size_t k)
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        memcpy(&tria_work[i * TC], &tria_in[k][i * 12u], 12u * sizeof(rfe_real_t));
    }
}
static void run_restore_tria(size_t k)
{
    load_tria(k);
    bench_sink += (uint32_t)(tria_work[0] > RFE_R(0.0));
}
static void run_tria(size_t k)
{
    load_tria(k);
    bench_sink += (uint32_t)rfe_qr_tria(tria_work, RFE_WHEELS, 12u, TC);
}
static void run_chol(size_t k)
{
    bench_sink += (uint32_t)rfe_chol_factor(ckf_pre[k].F, RFE_WHEELS, NM, chol_L, NM);
}

const bench_case_t bench_cases[] = {
    {"step.paper.sckf.paper", NULL, prep_step_sckf_paper, run_step},
    {"step.paper.ckf.paper", NULL, prep_step_ckf_paper, run_step},
    {"step.paper.sckf.absolute", NULL, prep_step_sckf_abs, run_step},
    {"step.paper.ckf.absolute", NULL, prep_step_ckf_abs, run_step},
    {"step.default", NULL, prep_step_default, run_step},
    {"velocity.step", NULL, prep_velocity, run_velocity},
    {"pipeline.step", NULL, prep_pipeline, run_pipeline},
    {"tyre.kinematics", NULL, NULL, run_kin},
    {"tyre.forces_norm", NULL, NULL, run_forces_norm},
    {"tyre.forces_abs", NULL, NULL, run_forces_abs},
    {"tyre.forces_magic", NULL, NULL, run_forces_magic},
    {"obsmat.build", NULL, NULL, run_obsmat},
    {"meas.setup.paper", NULL, NULL, run_setup_paper},
    {"meas.setup.absolute", NULL, NULL, run_setup_abs},
    {"meas.eval.paper", NULL, NULL, run_eval_paper},
    {"meas.eval.absolute", NULL, NULL, run_eval_abs},
    {"restore.sckf", NULL, NULL, run_restore_sckf},
    {"sckf.predict", "restore.sckf", NULL, run_sckf_predict},
    {"sckf.update.paper", "restore.sckf", NULL, run_sckf_update_paper},
    {"sckf.update.absolute", "restore.sckf", NULL, run_sckf_update_abs},
    {"restore.ckf", NULL, NULL, run_restore_ckf},
    {"ckf.predict", "restore.ckf", NULL, run_ckf_predict},
    {"ckf.update.paper", "restore.ckf", NULL, run_ckf_update_paper},
    {"ckf.update.absolute", "restore.ckf", NULL, run_ckf_update_abs},
    {"restore.tria", NULL, NULL, run_restore_tria},
    {"qr.tria.4x12", "restore.tria", NULL, run_tria},
    {"chol.4x4", NULL, NULL, run_chol},
};
const size_t bench_n_cases = sizeof bench_cases / sizeof bench_cases[0];

/* ---- set-up --------------------------------------------------------------------------- */
static int params_for(const rfe_sensor_log_t *log, rfe_preset_t preset, const char *filter,
                      const char *tyre, rfe_params_t *p)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    memset(&err, 0, sizeof err);
    (void)rfe_param_set_preset(&ps, preset);
    if (rfe_param_set_apply_meta(&ps, log, "log", &err) != 0) {
        return -1;
    }
    if ((filter != NULL) && (rfe_filter_kind_parse(filter, &ps.filter) != 0)) {
        return -1;
    }
    if ((tyre != NULL) && (rfe_tyre_mode_parse(tyre, &ps.tyre) != 0)) {
        return -1;
    }
    return (rfe_replay_params(&ps, p, NULL) == RFE_OK) ? 0 : -1;
}

static void to_sample(const rfe_sensor_row_t *r, rfe_sample_t *s)
{
    size_t w;
    s->delta = (rfe_real_t)r->delta;
    s->vx = (rfe_real_t)r->vx;
    s->vy = (rfe_real_t)r->vy;
    s->yaw_rate = (rfe_real_t)r->yaw_rate;
    s->yaw_acc = (rfe_real_t)r->yaw_acc;
    s->ax = (rfe_real_t)r->ax;
    s->ay = (rfe_real_t)r->ay;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        s->omega[w] = (rfe_real_t)r->omega[w];
    }
}

/* The paper-preset pipeline of the estimator (tau_v = 0: the conditioner copies), run with
 * both filters to record the states every filter-level case starts from. */
static int record_states(void)
{
    size_t k;
    rfe_friction_t e;
    int clamped;
    if (rfe_friction_init(&e, &par_paper) != RFE_OK) {
        return -1;
    }
    sckf = e.filter.sckf;
    if (rfe_friction_init(&e, &par_paper_ckf) != RFE_OK) {
        return -1;
    }
    ckf = e.filter.ckf;
    cur_par = &par_paper;
    for (k = 0u; k < n_samples; ++k) {
        const int upd = samples[k].vx >= par_paper.filter.v_est_min;
        cur_meas = &meas_paper[k];
        save(&sckf_post[k], sckf.x, sckf.S);
        save(&ckf_post[k], ckf.x, ckf.P);
        if ((rfe_sckf_predict(&sckf, NULL, NULL) != RFE_OK) ||
            (rfe_ckf_predict(&ckf, NULL, NULL) != RFE_OK)) {
            return -1;
        }
        save(&sckf_pre[k], sckf.x, sckf.S);
        save(&ckf_pre[k], ckf.x, ckf.P);
        if (upd && ((rfe_sckf_update(&sckf, bench_measure, NULL, ys[k]) != RFE_OK) ||
                    (rfe_ckf_update(&ckf, bench_measure, NULL, ys[k]) != RFE_OK) ||
                    (rfe_sckf_clamp(&sckf, par_paper.filter.mu_min,
                                            par_paper.filter.mu_max, &clamped) != RFE_OK) ||
                    (rfe_ckf_clamp(&ckf, par_paper.filter.mu_min,
                                           par_paper.filter.mu_max, &clamped) != RFE_OK))) {
            return -1;
        }
    }
    /* Tria inputs of the time update from the recorded factors. */
    for (k = 0u; k < n_samples; ++k) {
        const rfe_real_t c = RFE_R(1.0) / (rfe_real_t)sqrt(2.0);
        size_t i;
        size_t j;
        for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
            for (j = 0u; j < (size_t)RFE_WHEELS; ++j) {
                const rfe_real_t s = sckf_post[k].F[(i * NM) + j] * c;
                tria_in[k][(i * 12u) + j] = s;
                tria_in[k][(i * 12u) + 4u + j] = -s;
                tria_in[k][(i * 12u) + 8u + j] = sckf.SQ[(i * NM) + j];
            }
        }
    }
    return 0;
}

size_t bench_setup(const char *log_path)
{
    rfe_sensor_log_t log;
    rfe_io_error_t err;
    size_t k;
    memset(&log, 0, sizeof log);
    memset(&err, 0, sizeof err);
    if (rfe_sensor_log_read(log_path, &log, &err) != 0) {
        fprintf(stderr, "bench: cannot read %s\n", log_path);
        return 0u;
    }
    n_samples = (log.n_rows < MAXN) ? log.n_rows : MAXN;
    if (rfe_velocity_params_default(&vel_par) != RFE_OK) {
        rfe_sensor_log_free(&log);
        return 0u;
    }
    if ((params_for(&log, RFE_PRESET_PAPER, "sckf", "paper", &par_paper) != 0) ||
        (params_for(&log, RFE_PRESET_PAPER, "ckf", "paper", &par_paper_ckf) != 0) ||
        (params_for(&log, RFE_PRESET_PAPER, "sckf", "absolute", &par_abs) != 0) ||
        (params_for(&log, RFE_PRESET_PAPER, "sckf", "magic", &par_magic) != 0) ||
        (params_for(&log, RFE_PRESET_PAPER, "ckf", "absolute", &par_abs_ckf) != 0) ||
        (params_for(&log, RFE_PRESET_DEFAULT, NULL, NULL, &par_default) != 0)) {
        fprintf(stderr, "bench: parameters rejected\n");
        rfe_sensor_log_free(&log);
        return 0u;
    }
    for (k = 0u; k < n_samples; ++k) {
        const rfe_sensor_row_t *r = &log.rows[k];
        size_t w;
        to_sample(r, &samples[k]);
        memset(&esc[k], 0, sizeof esc[k]);
        esc[k].dt = (k > 0u) ? (rfe_real_t)(r->t - log.rows[k - 1u].t) : RFE_R(0.0);
        esc[k].delta = samples[k].delta;
        esc[k].yaw_rate = samples[k].yaw_rate;
        esc[k].ax = samples[k].ax;
        esc[k].ay = samples[k].ay;
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            esc[k].omega[w] = samples[k].omega[w];
            esc_mu[k].mu[w] = log.has_truth ? (rfe_real_t)r->mu_true[w] : RFE_R(0.5);
            esc_mu[k].sd[w] = RFE_R(0.05);
        }
        ys[k][0] = samples[k].ax;
        ys[k][1] = samples[k].ay;
        ys[k][2] = samples[k].yaw_acc;
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            mu_true[k][w] = log.has_truth ? (rfe_real_t)r->mu_true[w] : RFE_R(0.5);
        }
        if ((rfe_tyre_kinematics(&par_paper.vehicle, &par_paper.tyre, &samples[k],
                                         &kins[k]) != RFE_OK) ||
            (rfe_tyre_forces_norm(&par_paper.tyre, &kins[k], f0x[k], f0y[k]) != RFE_OK) ||
            (rfe_meas_setup(&meas_paper[k], &par_paper.vehicle, &par_paper.tyre,
                                    &samples[k]) != RFE_OK) ||
            (rfe_meas_setup(&meas_abs[k], &par_abs.vehicle, &par_abs.tyre,
                                    &samples[k]) != RFE_OK)) {
            fprintf(stderr, "bench: sample %zu rejected\n", k);
            rfe_sensor_log_free(&log);
            return 0u;
        }
    }
    rfe_sensor_log_free(&log);
    if (record_states() != 0) {
        fprintf(stderr, "bench: recording the filter states failed\n");
        return 0u;
    }
    return n_samples;
}
