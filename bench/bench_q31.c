/**
 * @file bench_q31.c
 * @brief Benchmark cases of the fixed-point library (librfe_q31.a), the twin of bench_flt.c:
 *        the whole estimator step and every module, on the samples of one sensor log.
 *
 * Filter-level cases (sckf.*, ckf.*, qr.*, chol.*) start from the states a paper-preset run
 * of the same log passes through (recorded once by bench_setup, the estimator's own
 * sequence: predict, meas_setup, update, clamp), restored before every call; the restore
 * alone is the baseline case the caller subtracts.
 */
#include <math.h>

#include "rfe/component/chol_q31.h"
#include "rfe/component/ckf_q31.h"
#include "rfe/friction_q31.h"
#include "host/fixed_conv.h"
#include "rfe/component/meas_q31.h"
#include "rfe/component/obsmat_q31.h"
#include "rfe/component/params_conv.h"
#include "rfe/component/qr_q31.h"
#include "rfe/component/sckf_q31.h"
#include "rfe/component/tyre_q31.h"

#include "csv_log.h"
#include "param_file.h"
#include "replay_real.h"

#include "harness.h"

const char *const bench_flavour = "q31";
static uint32_t sat; /* saturation counter every q31 call takes */

#define NM ((size_t)RFE_N_MAX)
#define TC ((size_t)RFE_TRIA_COLS_MAX)
#define MAXN 4096u

static size_t n_samples;
static rfe_sample_q31_t samples[MAXN];
static rfe_fix_t ys[MAXN][RFE_MEAS];
static rfe_fix_t mu_true[MAXN][RFE_WHEELS];
static rfe_wheel_kin_q31_t kins[MAXN];
static rfe_fix_t f0x[MAXN][RFE_WHEELS];
static rfe_fix_t f0y[MAXN][RFE_WHEELS];
static rfe_meas_q31_t meas_paper[MAXN];
static rfe_meas_q31_t meas_abs[MAXN];
static rfe_params_q31_t par_paper;    /* paper preset, paper tyre */
static rfe_params_q31_t par_abs;      /* paper preset, absolute tyre */
static rfe_params_q31_t par_magic;    /* paper preset, Magic Formula tyre */
static rfe_params_q31_t par_step;     /* the parameters of the step case being run */
static rfe_friction_q31_t est;
static rfe_estimate_q31_t out;

/* Recorded filter states: before the time update (post[k], i.e. after step k-1) and before
 * the measurement update (pre[k]). x and the whole factor (SCKF S / CKF P, ld RFE_N_MAX). */
typedef struct {
    rfe_fix_t x[RFE_N_MAX];
    rfe_fix_t F[RFE_N_MAX * RFE_N_MAX];
} snap_t;
static snap_t sckf_post[MAXN];
static snap_t sckf_pre[MAXN];
static snap_t ckf_post[MAXN];
static snap_t ckf_pre[MAXN];
static rfe_sckf_q31_t sckf;
static rfe_ckf_q31_t ckf;
static rfe_fix_t tria_in[MAXN][RFE_WHEELS * 12];
static rfe_fix_t tria_work[RFE_N_MAX * RFE_TRIA_COLS_MAX];
static rfe_fix_t chol_L[RFE_N_MAX * RFE_N_MAX];

/* ---- measurement callbacks (as the estimator's, for T = I) ----------------------------- */
static const rfe_meas_q31_t *cur_meas;
static const rfe_params_q31_t *cur_par;
static rfe_status_t bench_measure(void *ctx, const rfe_fix_t *x, rfe_fix_t *z, size_t n, size_t m)
{
    (void)ctx;
    (void)n;
    (void)m;
    return rfe_meas_eval_q31(cur_meas, &cur_par->vehicle, &cur_par->tyre, x, z, &sat);
}

static void restore(snap_t *s, rfe_fix_t *x, rfe_fix_t *F)
{
    memcpy(x, s->x, sizeof s->x);
    memcpy(F, s->F, sizeof s->F);
}
static void save(snap_t *s, const rfe_fix_t *x, const rfe_fix_t *F)
{
    memcpy(s->x, x, sizeof s->x);
    memcpy(s->F, F, sizeof s->F);
}

/* ---- step cases ----------------------------------------------------------------------- */
static void prep_step(const rfe_params_q31_t *p)
{
    par_step = *p;
    if (rfe_friction_init_q31(&est, &par_step) != RFE_OK) {
        fprintf(stderr, "bench: estimator init failed\n");
        exit(1);
    }
}
static rfe_params_q31_t par_default;
static rfe_params_q31_t par_paper_ckf;
static rfe_params_q31_t par_abs_ckf;
static void prep_step_sckf_paper(void) { prep_step(&par_paper); }
static void prep_step_ckf_paper(void) { prep_step(&par_paper_ckf); }
static void prep_step_sckf_abs(void) { prep_step(&par_abs); }
static void prep_step_ckf_abs(void) { prep_step(&par_abs_ckf); }
static void prep_step_default(void) { prep_step(&par_default); }
static void run_step(size_t k)
{
    bench_sink += (uint32_t)rfe_friction_step_q31(&est, &samples[k], &out);
}

/* ---- module cases --------------------------------------------------------------------- */
static void run_kin(size_t k)
{
    rfe_wheel_kin_q31_t kin;
    bench_sink += (uint32_t)rfe_tyre_kinematics_q31(&par_paper.vehicle, &par_paper.tyre,
                                                       &samples[k], &kin, &sat);
}
static void run_forces_norm(size_t k)
{
    rfe_fix_t fx[RFE_WHEELS];
    rfe_fix_t fy[RFE_WHEELS];
    bench_sink += (uint32_t)rfe_tyre_forces_norm_q31(&par_paper.tyre, &kins[k], fx, fy, &sat);
}
static void run_forces_abs(size_t k)
{
    rfe_fix_t fx[RFE_WHEELS];
    rfe_fix_t fy[RFE_WHEELS];
    bench_sink +=
        (uint32_t)rfe_tyre_forces_abs_q31(&par_abs.tyre, &kins[k], mu_true[k], fx, fy, &sat);
}
static void run_forces_magic(size_t k)
{
    rfe_fix_t fx[RFE_WHEELS];
    rfe_fix_t fy[RFE_WHEELS];
    bench_sink +=
        (uint32_t)rfe_tyre_forces_abs_q31(&par_magic.tyre, &kins[k], mu_true[k], fx, fy, &sat);
}
static void run_obsmat(size_t k)
{
    rfe_fix_t H[RFE_H_Q31_SIZE];
    bench_sink += (uint32_t)rfe_obsmat_build_q31(&par_paper.vehicle, samples[k].delta,
                                                    f0x[k], f0y[k], H, &sat);
}
static void run_setup_paper(size_t k)
{
    rfe_meas_q31_t h;
    bench_sink += (uint32_t)rfe_meas_setup_q31(&h, &par_paper.vehicle, &par_paper.tyre,
                                                  &samples[k], &sat);
}
static void run_setup_abs(size_t k)
{
    rfe_meas_q31_t h;
    bench_sink +=
        (uint32_t)rfe_meas_setup_q31(&h, &par_abs.vehicle, &par_abs.tyre, &samples[k], &sat);
}
static void run_eval_paper(size_t k)
{
    rfe_fix_t z[RFE_MEAS];
    bench_sink += (uint32_t)rfe_meas_eval_q31(&meas_paper[k], &par_paper.vehicle,
                                                 &par_paper.tyre, mu_true[k], z, &sat);
}
static void run_eval_abs(size_t k)
{
    rfe_fix_t z[RFE_MEAS];
    bench_sink += (uint32_t)rfe_meas_eval_q31(&meas_abs[k], &par_abs.vehicle, &par_abs.tyre,
                                                 mu_true[k], z, &sat);
}

static void run_restore_sckf(size_t k) { restore(&sckf_post[k], sckf.x, sckf.S); }
static void run_sckf_predict(size_t k)
{
    restore(&sckf_post[k], sckf.x, sckf.S);
    bench_sink += (uint32_t)rfe_sckf_predict_q31(&sckf, NULL, NULL);
}
static void run_sckf_update_paper(size_t k)
{
    restore(&sckf_pre[k], sckf.x, sckf.S);
    cur_meas = &meas_paper[k];
    cur_par = &par_paper;
    bench_sink += (uint32_t)rfe_sckf_update_q31(&sckf, bench_measure, NULL, ys[k]);
}
static void run_sckf_update_abs(size_t k)
{
    restore(&sckf_pre[k], sckf.x, sckf.S);
    cur_meas = &meas_abs[k];
    cur_par = &par_abs;
    bench_sink += (uint32_t)rfe_sckf_update_q31(&sckf, bench_measure, NULL, ys[k]);
}
static void run_restore_ckf(size_t k) { restore(&ckf_post[k], ckf.x, ckf.P); }
static void run_ckf_predict(size_t k)
{
    restore(&ckf_post[k], ckf.x, ckf.P);
    bench_sink += (uint32_t)rfe_ckf_predict_q31(&ckf, NULL, NULL);
}
static void run_ckf_update_paper(size_t k)
{
    restore(&ckf_pre[k], ckf.x, ckf.P);
    cur_meas = &meas_paper[k];
    cur_par = &par_paper;
    bench_sink += (uint32_t)rfe_ckf_update_q31(&ckf, bench_measure, NULL, ys[k]);
}
static void run_ckf_update_abs(size_t k)
{
    restore(&ckf_pre[k], ckf.x, ckf.P);
    cur_meas = &meas_abs[k];
    cur_par = &par_abs;
    bench_sink += (uint32_t)rfe_ckf_update_q31(&ckf, bench_measure, NULL, ys[k]);
}
/* Tria of the cubature time update's input, 4 x 12 ([Xc, S_Q], Xc = [S, -S]/sqrt(2)). */
static void load_tria(size_t k)
{
    size_t i;
    for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
        memcpy(&tria_work[i * TC], &tria_in[k][i * 12u], 12u * sizeof(rfe_fix_t));
    }
}
static void run_restore_tria(size_t k)
{
    load_tria(k);
    bench_sink += (uint32_t)(tria_work[0] > 0);
}
static void run_tria(size_t k)
{
    load_tria(k);
    bench_sink += (uint32_t)rfe_qr_tria_q31(tria_work, RFE_WHEELS, 12u, TC, &sat);
}
static void run_chol(size_t k)
{
    bench_sink += (uint32_t)rfe_chol_factor_q31(ckf_pre[k].F, RFE_WHEELS, NM, chol_L, NM, RFE_Q31_QP, 30u, &sat);
}

const bench_case_t bench_cases[] = {
    {"step.paper.sckf.paper", NULL, prep_step_sckf_paper, run_step},
    {"step.paper.ckf.paper", NULL, prep_step_ckf_paper, run_step},
    {"step.paper.sckf.absolute", NULL, prep_step_sckf_abs, run_step},
    {"step.paper.ckf.absolute", NULL, prep_step_ckf_abs, run_step},
    {"step.default", NULL, prep_step_default, run_step},
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
                      const char *tyre, rfe_params_q31_t *q)
{
    rfe_param_set_t ps;
    rfe_io_error_t err;
    rfe_params_t p;
    memset(&err, 0, sizeof err);
    (void)rfe_param_set_preset_f64(&ps, preset);
    if (rfe_param_set_apply_meta(&ps, log, "log", &err) != 0) {
        return -1;
    }
    if ((filter != NULL) && (rfe_filter_kind_parse(filter, &ps.filter) != 0)) {
        return -1;
    }
    if ((tyre != NULL) && (rfe_tyre_mode_parse(tyre, &ps.tyre) != 0)) {
        return -1;
    }
    return ((rfe_replay_params_f64(&ps, &p, NULL) == RFE_OK) && (rfe_params_to_q31_f64(&p, q) == RFE_OK))
               ? 0
               : -1;
}

static void to_sample(const rfe_sensor_row_t *r, rfe_sample_q31_t *s)
{
    size_t w;
    s->delta = rfe_fix_from_double(r->delta, RFE_FIX_Q_ANGLE, &sat);
    s->vx = rfe_fix_from_double(r->vx, RFE_FIX_Q_SPEED, &sat);
    s->vy = rfe_fix_from_double(r->vy, RFE_FIX_Q_SPEED, &sat);
    s->yaw_rate = rfe_fix_from_double(r->yaw_rate, RFE_FIX_Q_YAWRATE, &sat);
    s->yaw_acc = rfe_fix_from_double(r->yaw_acc, RFE_FIX_Q_ACC, &sat);
    s->ax = rfe_fix_from_double(r->ax, RFE_FIX_Q_ACC, &sat);
    s->ay = rfe_fix_from_double(r->ay, RFE_FIX_Q_ACC, &sat);
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        s->omega[w] = rfe_fix_from_double(r->omega[w], RFE_FIX_Q_OMEGA, &sat);
    }
}

/* The paper-preset pipeline of the estimator (tau_v = 0: the conditioner copies), run with
 * both filters to record the states every filter-level case starts from. */
static int record_states(void)
{
    size_t k;
    rfe_friction_q31_t e;
    int clamped;
    if (rfe_friction_init_q31(&e, &par_paper) != RFE_OK) {
        return -1;
    }
    sckf = e.filter.sckf;
    if (rfe_friction_init_q31(&e, &par_paper_ckf) != RFE_OK) {
        return -1;
    }
    ckf = e.filter.ckf;
    cur_par = &par_paper;
    for (k = 0u; k < n_samples; ++k) {
        const int upd = samples[k].vx >= par_paper.filter.v_est_min;
        cur_meas = &meas_paper[k];
        save(&sckf_post[k], sckf.x, sckf.S);
        save(&ckf_post[k], ckf.x, ckf.P);
        if ((rfe_sckf_predict_q31(&sckf, NULL, NULL) != RFE_OK) ||
            (rfe_ckf_predict_q31(&ckf, NULL, NULL) != RFE_OK)) {
            return -1;
        }
        save(&sckf_pre[k], sckf.x, sckf.S);
        save(&ckf_pre[k], ckf.x, ckf.P);
        if (upd && ((rfe_sckf_update_q31(&sckf, bench_measure, NULL, ys[k]) != RFE_OK) ||
                    (rfe_ckf_update_q31(&ckf, bench_measure, NULL, ys[k]) != RFE_OK) ||
                    (rfe_sckf_clamp_q31(&sckf, par_paper.filter.mu_min,
                                            par_paper.filter.mu_max, &clamped) != RFE_OK) ||
                    (rfe_ckf_clamp_q31(&ckf, par_paper.filter.mu_min,
                                           par_paper.filter.mu_max, &clamped) != RFE_OK))) {
            return -1;
        }
    }
    /* Tria inputs of the time update from the recorded factors. */
    for (k = 0u; k < n_samples; ++k) {
        const double c = 1.0 / sqrt(2.0);
        size_t i;
        size_t j;
        for (i = 0u; i < (size_t)RFE_WHEELS; ++i) {
            for (j = 0u; j < (size_t)RFE_WHEELS; ++j) {
                const rfe_fix_t s = (rfe_fix_t)lround((double)sckf_post[k].F[(i * NM) + j] * c);
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
        ys[k][0] = samples[k].ax;
        ys[k][1] = samples[k].ay;
        ys[k][2] = samples[k].yaw_acc;
        for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
            mu_true[k][w] = rfe_fix_from_double(log.has_truth ? r->mu_true[w] : 0.5, RFE_FIX_Q_MU, &sat);
        }
        if ((rfe_tyre_kinematics_q31(&par_paper.vehicle, &par_paper.tyre, &samples[k],
                                         &kins[k], &sat) != RFE_OK) ||
            (rfe_tyre_forces_norm_q31(&par_paper.tyre, &kins[k], f0x[k], f0y[k], &sat) != RFE_OK) ||
            (rfe_meas_setup_q31(&meas_paper[k], &par_paper.vehicle, &par_paper.tyre,
                                    &samples[k], &sat) != RFE_OK) ||
            (rfe_meas_setup_q31(&meas_abs[k], &par_abs.vehicle, &par_abs.tyre,
                                    &samples[k], &sat) != RFE_OK)) {
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
