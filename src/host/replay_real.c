/**
 * @file replay_real.c
 * @brief The precision-specific part of mu_replay: double parameter set -> rfe_params_t,
 *        sensor rows -> rfe_sample_t, estimator steps -> double estimate rows.
 *
 * Compiled twice (float by default, double with -DRFE_REAL_DOUBLE); public names carry the
 * precision suffix (replay_real.h) so both objects link into one program. Keep everything else out of this file.
 */
#include "replay_real.h"

#include <math.h>
#include <string.h>

#include "rfe/friction.h"
#include "rfe/mass_grade.h"
#include "rfe/pipeline.h"
#include "rfe/params.h"
#include "rfe/tyre_id.h"
#include "rfe/velocity_params.h"

#include "log_timing.h"

/* The tyre identifier of a run (ps->tyre_id): its parameters, the vehicle it was set up with
 * and its seed (a restart sets it up again with them), the time of the last row it accepted,
 * the feed's keys. */
typedef struct {
    rfe_tyre_id_t tid;
    rfe_tyre_id_params_t tp;
    rfe_params_t veh;
    uint64_t seed;
    double t_last;    /* the last accepted row's time (have_last) */
    double feed;      /* key tid_feed_sd_rel */
    double evidence;  /* key tid_feed_evidence (s) */
    double ax_max;    /* key tid_feed_ax_max (m/s^2; 0: no hold) */
    double t_wrong;   /* time so far at a mu bound or in model mismatch (s) */
    double t_row;     /* the previous row's time (have_row), for t_wrong */
    int have_row;
    double r_model;   /* key r_model_rel: the model error the curve's joins */
    int have_last;
    int on;
    int feed_on;      /* on and tid_feed_sd_rel > 0 */
    double refresh;   /* key tid_feed_refresh (s; 0: off) */
    double outlier_k; /* key tid_feed_outlier_k (1; 0: no test) */
    double fresh;     /* untainted excited time since the last taint (s) */
    double t_fresh;   /* the previous row's time (have_fresh), for fresh */
    int have_fresh;
    int tainted;      /* a held or implausible sample since the last refresh: no feed */
    int bad;          /* this sample is held or implausible */
    int ref_ok;       /* the identifier's last step updated: its estimate predicts ay */
    int resume;       /* the taint lifted, no curve fed since: the next only at a low |ay| */
} tid_run_t;

/** The per-log state of a replay (replay_real.h): the estimators, which columns the log has,
 *  the times a period is measured from, the counters. Opaque outside this file. */
struct rfe_replay_state {
    rfe_pipeline_t pl;        /**< the observer and friction estimator; measured velocities:
                                   pl.friction alone */
    rfe_mass_grade_t mg;      /**< when mg_on */
    tid_run_t tid;            /**< the tyre identifier (tid.on) */
    rfe_sensor_log_t shape;   /**< the log's has_* flags (no rows, no metadata) */
    rfe_replay_stats_t stats;
    double dt;                /**< key dt: the gaps of a measuring run */
    double feed_sd_rel;       /**< key mg_feed_sd_rel */
    rfe_replay_mass_gate_t gate; /**< the feed's excitation gate (mg_feed_excitation) */
    double t_prev;            /**< the previous row's time (have_prev) */
    double t_last;            /**< the observer's last accepted row's time (have_last) */
    double t_mg_last;         /**< the mass and grade estimator's (have_mg_last) */
    int have_prev;
    int have_last;
    int have_mg_last;
    int observer;             /**< the pipeline runs (else the friction estimator alone) */
    int mg_on;                /**< the mass and grade estimator runs */
    int ready;                /**< rfe_replay_begin succeeded */
};

static rfe_status_t preset_params(rfe_preset_t preset, rfe_params_t *p);
static void set_key(rfe_params_t *p, const rfe_param_set_t *ps, size_t k);
static rfe_status_t to_lib_params(const rfe_param_set_t *ps, rfe_params_t *p);
static size_t diagnose_params(const rfe_param_set_t *ps);
static void step_row(rfe_friction_t *est, const rfe_sensor_row_t *row, rfe_est_row_t *out);

/* Where each numeric key lives in rfe_params_t of this precision (the RFE_PARAM_KEYS
 * table): one table instead of a switch, so a new key needs no code here. */
static const size_t k_member_offset[RFE_PK_NUMERIC] = {
#define RFE_OFFSET_(key, member, unit, doc) offsetof(rfe_params_t, member),
    RFE_PARAM_KEYS(RFE_OFFSET_)
#undef RFE_OFFSET_
};

/* Compile-time check (C99 has no static_assert): every keyed member is an rfe_real_t, as
 * set_key's memcpy assumes. A non-real key would make this array size negative. */
#define RFE_IS_REAL_(key, member, unit, doc)                                               \
    typedef char rfe_key_is_real_##key[(sizeof(((rfe_params_t *)0)->member) == sizeof(rfe_real_t)) ? 1 : -1];
RFE_PARAM_KEYS(RFE_IS_REAL_)
#undef RFE_IS_REAL_

/* Where each observer key after the integer ones lives in rfe_velocity_params_t
 * (RFE_OBS_KEYS). */
static const size_t k_obs_offset[RFE_PK_OBS_COUNT - RFE_PK_OBS_INTS] = {
#define RFE_OFFSET_(key, member, unit, doc) offsetof(rfe_velocity_params_t, member),
    RFE_OBS_KEYS(RFE_OFFSET_)
#undef RFE_OFFSET_
};

/* As above: every observer key after the integer ones is an rfe_real_t. */
#define RFE_IS_REAL_(key, member, unit, doc)                                               \
    typedef char rfe_key_is_real_##key[(sizeof(((rfe_velocity_params_t *)0)->member) == sizeof(rfe_real_t)) ? 1 : -1];
RFE_OBS_KEYS(RFE_IS_REAL_)
#undef RFE_IS_REAL_

/* Where each mass and grade key after the special ones (mg_adaptive, mg_use_ax,
 * mg_feed_sd_rel) lives in rfe_mass_grade_params_t (RFE_MG_KEYS). */
static const size_t k_mg_offset[RFE_PK_MG_COUNT - RFE_PK_MG_SPECIAL] = {
#define RFE_OFFSET_(key, member, unit, doc) offsetof(rfe_mass_grade_params_t, member),
    RFE_MG_KEYS(RFE_OFFSET_)
#undef RFE_OFFSET_
};

/* As above: every mass and grade key of RFE_MG_KEYS is an rfe_real_t. */
#define RFE_IS_REAL_(key, member, unit, doc)                                               \
    typedef char rfe_key_is_real_##key[(sizeof(((rfe_mass_grade_params_t *)0)->member) == sizeof(rfe_real_t)) ? 1 : -1];
RFE_MG_KEYS(RFE_IS_REAL_)
#undef RFE_IS_REAL_

/* Where each tyre identifier key after the special ones (tid_filter, tid_resample,
 * tid_substeps, tid_seed, tid_feed_sd_rel) lives in rfe_tyre_id_params_t (RFE_TID_KEYS). */
static const size_t k_tid_offset[RFE_PK_TID_COUNT - RFE_PK_TID_SPECIAL] = {
#define RFE_OFFSET_(key, member, unit, doc) offsetof(rfe_tyre_id_params_t, member),
    RFE_TID_KEYS(RFE_OFFSET_)
#undef RFE_OFFSET_
};

/* As above: every tyre identifier key of RFE_TID_KEYS is an rfe_real_t. */
#define RFE_IS_REAL_(key, member, unit, doc)                                               \
    typedef char rfe_key_is_real_##key[(sizeof(((rfe_tyre_id_params_t *)0)->member) == sizeof(rfe_real_t)) ? 1 : -1];
RFE_TID_KEYS(RFE_IS_REAL_)
#undef RFE_IS_REAL_

/* A group of keys beside the friction estimator's (the observer's, the mass and grade
 * estimator's, the tyre identifier's) and the library struct they fill: how the struct
 * starts (the library's defaults or preset), how one key of the set goes into it (-1: a
 * value its member cannot take, such as a switch that is not 0 or 1), and the library's
 * validation of the whole. group_params runs it; one sequence for every group. */
typedef struct {
    size_t n;                                           /* keys applied */
    size_t (*key)(size_t i);                            /* the i-th, in the order applied */
    int (*start)(const rfe_param_set_t *ps, void *p);   /* 0, or -1 */
    int (*set)(void *p, const rfe_param_set_t *ps, size_t k); /* 0, or -1 */
    int (*check)(const void *p);                        /* 0 when the library accepts it */
} key_group_t;

/* The group's struct of the set in @p p: started, every key applied, checked. On
 * RFE_ERR_PARAM, *bad_key (when not NULL) is the key that alone, applied to the start, fails
 * (RFE_PK_NONE: only a combination does); @p one is scratch of the struct's type. */
static rfe_status_t group_params(const key_group_t *g, const rfe_param_set_t *ps, void *p,
                                 void *one, size_t *bad_key)
{
    size_t i;
    int bad;
    if (bad_key != NULL) {
        *bad_key = RFE_PK_NONE;
    }
    bad = g->start(ps, p);
    for (i = 0u; (bad == 0) && (i < g->n); ++i) {
        bad |= g->set(p, ps, g->key(i));
    }
    if ((bad == 0) && (g->check(p) == 0)) {
        return RFE_OK;
    }
    /* Which key alone makes it fail, from the (valid) start. */
    for (i = 0u; (bad_key != NULL) && (i < g->n); ++i) {
        if ((g->start(ps, one) != 0) || (g->set(one, ps, g->key(i)) != 0) ||
            (g->check(one) != 0)) {
            *bad_key = g->key(i);
            break;
        }
    }
    return RFE_ERR_PARAM;
}

rfe_replay_preset_fn_t rfe_replay_preset_fn(rfe_preset_t preset)
{
    switch (preset) {
    case RFE_PRESET_DEFAULT:
        return rfe_params_default;
    case RFE_PRESET_PAPER:
        return rfe_params_paper;
    default:
        return NULL;
    }
}

/* The library's parameters of @p preset; RFE_ERR_PARAM for an unknown preset. */
static rfe_status_t preset_params(rfe_preset_t preset, rfe_params_t *p)
{
    const rfe_replay_preset_fn_t fill = rfe_replay_preset_fn(preset);
    return (fill != NULL) ? fill(p) : RFE_ERR_PARAM;
}

int rfe_param_set_preset(rfe_param_set_t *ps, rfe_preset_t preset)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    size_t k;
    if ((ps == NULL) || (preset_params(preset, &p) != RFE_OK) ||
        (rfe_velocity_params_default(&vp) != RFE_OK)) {
        return -1;
    }
    memset(ps, 0, sizeof *ps);
    ps->preset = preset;
    for (k = 0u; k < RFE_PK_NUMERIC; ++k) {
        rfe_real_t v;
        memcpy(&v, (const char *)&p + k_member_offset[k], sizeof v);
        ps->value[k] = (double)v;
    }
    ps->tyre = p.tyre.mode;
    ps->filter = p.filter.kind;
    ps->structure = p.filter.structure;
    ps->obs[0] = (double)vp.driven;
    ps->obs[1] = (double)vp.lat_every;
    for (k = RFE_PK_OBS_INTS; k < RFE_PK_OBS_COUNT; ++k) {
        rfe_real_t v;
        memcpy(&v, (const char *)&vp + k_obs_offset[k - RFE_PK_OBS_INTS], sizeof v);
        ps->obs[k] = (double)v;
    }
    return (rfe_param_set_tyre_id(ps) == 0) ? rfe_param_set_mass_grade(ps, RFE_MG_CAR, RFE_MG_RECOMMENDED)
                                             : -1;
}

int rfe_param_set_tyre_id(rfe_param_set_t *ps)
{
    rfe_tyre_id_params_t tp;
    size_t k;
    if ((ps == NULL) || (rfe_tyre_id_params_default(&tp) != RFE_OK)) {
        return -1;
    }
    ps->tid[RFE_PK_tid_filter - RFE_PK_TID_FIRST] = (double)tp.filter;
    ps->tid[RFE_PK_tid_resample - RFE_PK_TID_FIRST] = (double)tp.resample;
    ps->tid[RFE_PK_tid_substeps - RFE_PK_TID_FIRST] = (double)tp.substeps;
    ps->tid[RFE_PK_tid_seed - RFE_PK_TID_FIRST] = RFE_TID_SEED_DEFAULT; /* the init's argument */
    ps->tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST] = RFE_TID_FEED_SD_REL_DEFAULT; /* the replay's */
    ps->tid[RFE_PK_tid_feed_evidence - RFE_PK_TID_FIRST] = RFE_TID_FEED_EVIDENCE_DEFAULT;
    ps->tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST] = RFE_TID_FEED_AX_MAX_DEFAULT;
    ps->tid[RFE_PK_tid_feed_refresh - RFE_PK_TID_FIRST] = RFE_TID_FEED_REFRESH_DEFAULT;
    ps->tid[RFE_PK_tid_feed_outlier_k - RFE_PK_TID_FIRST] = RFE_TID_FEED_OUTLIER_K_DEFAULT;
    for (k = RFE_PK_TID_SPECIAL; k < RFE_PK_TID_COUNT; ++k) {
        rfe_real_t v;
        memcpy(&v, (const char *)&tp + k_tid_offset[k - RFE_PK_TID_SPECIAL], sizeof v);
        ps->tid[k] = (double)v;
    }
    for (k = 0u; k < RFE_PK_TID_COUNT; ++k) {
        ps->origin[RFE_PK_TID_FIRST + k].file = NULL;
        ps->origin[RFE_PK_TID_FIRST + k].line = 0u;
    }
    return 0;
}

int rfe_param_set_mass_grade(rfe_param_set_t *ps, rfe_mg_vehicle_t vehicle, rfe_mg_config_t config)
{
    rfe_mass_grade_params_t mp;
    size_t k;
    if ((ps == NULL) || (rfe_mass_grade_params_preset(&mp, vehicle, config) != RFE_OK)) {
        return -1;
    }
    ps->mg_vehicle = vehicle;
    ps->mg_config = config;
    ps->mg[RFE_PK_mg_adaptive - RFE_PK_MG_FIRST] = (double)mp.adaptive;
    ps->mg[RFE_PK_mg_use_ax - RFE_PK_MG_FIRST] = (double)mp.use_ax;
    /* the replay's five feed keys, not the library's */
    ps->mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST] = RFE_MG_FEED_SD_REL_DEFAULT;
    ps->mg[RFE_PK_mg_feed_excitation - RFE_PK_MG_FIRST] = RFE_MG_FEED_EXCITATION_DEFAULT;
    ps->mg[RFE_PK_mg_feed_ax_min - RFE_PK_MG_FIRST] = RFE_MG_FEED_AX_MIN_DEFAULT;
    ps->mg[RFE_PK_mg_feed_slip_max - RFE_PK_MG_FIRST] = RFE_MG_FEED_SLIP_MAX_DEFAULT;
    ps->mg[RFE_PK_mg_feed_band - RFE_PK_MG_FIRST] = RFE_MG_FEED_BAND_DEFAULT;
    for (k = RFE_PK_MG_SPECIAL; k < RFE_PK_MG_COUNT; ++k) {
        rfe_real_t v;
        memcpy(&v, (const char *)&mp + k_mg_offset[k - RFE_PK_MG_SPECIAL], sizeof v);
        ps->mg[k] = (double)v;
    }
    for (k = 0u; k < RFE_PK_MG_COUNT; ++k) {
        ps->origin[RFE_PK_MG_FIRST + k].file = NULL;
        ps->origin[RFE_PK_MG_FIRST + k].line = 0u;
    }
    return 0;
}

/* Key k of the set into rfe_params_t, rounded to the build's real type. */
static void set_key(rfe_params_t *p, const rfe_param_set_t *ps, size_t k)
{
    if (k < RFE_PK_NUMERIC) {
        const rfe_real_t v = (rfe_real_t)ps->value[k];
        memcpy((char *)p + k_member_offset[k], &v, sizeof v);
    } else if (k == (size_t)RFE_PK_TYRE) {
        p->tyre.mode = ps->tyre;
    } else if (k == (size_t)RFE_PK_FILTER) {
        p->filter.kind = ps->filter;
    } else if (k == (size_t)RFE_PK_STRUCTURE) {
        p->filter.structure = ps->structure;
    } else {
        /* an observer key: rfe_replay_velocity_params */
    }
}

/* Observer key @p k of the set into @p vp; 0, or -1 when obs_driven is not an integer
 * bit mask 0..15 or obs_lat_every not an integer 0..255 (a double would otherwise be
 * truncated without a word; the library's check then names a value out of its range). */
static int set_obs_key(rfe_velocity_params_t *vp, const rfe_param_set_t *ps, size_t k)
{
    const double v = ps->obs[k - RFE_PK_OBS_FIRST];
    const double top = (k == RFE_PK_OBS_FIRST) ? 15.0 : 255.0;
    if ((k < (RFE_PK_OBS_FIRST + RFE_PK_OBS_INTS)) &&
        !((v >= 0.0) && (v <= top) && (v == floor(v)))) {
        return -1;
    }
    if (k == RFE_PK_OBS_FIRST) {
        vp->driven = (uint32_t)v;
    } else if (k == (size_t)RFE_PK_obs_lat_every) {
        vp->lat_every = (uint32_t)v;
    } else {
        const rfe_real_t r = (rfe_real_t)v;
        memcpy((char *)vp + k_obs_offset[k - RFE_PK_OBS_FIRST - RFE_PK_OBS_INTS], &r, sizeof r);
    }
    return 0;
}

/* The preset first, so a library field without a key keeps the preset's value. */
static rfe_status_t to_lib_params(const rfe_param_set_t *ps, rfe_params_t *p)
{
    size_t k;
    const rfe_status_t st = preset_params(ps->preset, p); /* fails only for a bad preset */
    for (k = 0u; (st == RFE_OK) && (k < (size_t)RFE_PK_COUNT); ++k) {
        set_key(p, ps, k);
    }
    return st;
}

/* Which key alone makes validation fail, starting from the (valid) library preset. The
 * filter key is also blamed when the set is valid except for filter = ckf (the CKF baseline
 * runs only the paper subset, rfe_params_validate). */
static size_t diagnose_params(const rfe_param_set_t *ps)
{
    size_t k;
    rfe_params_t all;
    if ((ps->filter == RFE_FILTER_CKF) && (to_lib_params(ps, &all) == RFE_OK)) {
        all.filter.kind = RFE_FILTER_SCKF;
        if (rfe_params_validate(&all) == RFE_OK) {
            return (size_t)RFE_PK_FILTER;
        }
    }
    for (k = 0u; k < (size_t)RFE_PK_COUNT; ++k) {
        rfe_params_t p;
        if (preset_params(ps->preset, &p) != RFE_OK) {
            return RFE_PK_NONE; /* the preset itself is unknown: no key to blame */
        }
        set_key(&p, ps, k);
        if (rfe_params_validate(&p) != RFE_OK) {
            return k;
        }
    }
    return RFE_PK_NONE;
}

/* Mass and grade key @p k of the set into @p mp; 0, or -1 when mg_adaptive or mg_use_ax is
 * not 0 or 1 (a double would otherwise be truncated without a word), mg_feed_sd_rel is
 * negative or mg_feed_excitation, mg_feed_ax_min, mg_feed_slip_max or mg_feed_band is not a
 * finite number >= 0 (the replay's five have no member: the replay reads them from the
 * set). R and g are the vehicle keys. */
static int set_mg_key(rfe_mass_grade_params_t *mp, const rfe_param_set_t *ps, size_t k)
{
    const double v = (k < RFE_PK_MG_FIRST) ? ps->value[k] : ps->mg[k - RFE_PK_MG_FIRST];
    if ((k == (size_t)RFE_PK_mg_adaptive) || (k == (size_t)RFE_PK_mg_use_ax)) {
        if (!((v == 0.0) || (v == 1.0))) {
            return -1;
        }
        *((k == (size_t)RFE_PK_mg_adaptive) ? &mp->adaptive : &mp->use_ax) = (uint32_t)v;
    } else if (k == (size_t)RFE_PK_mg_feed_sd_rel) {
        if (!(v >= 0.0)) {
            return -1;
        }
    } else if ((k == (size_t)RFE_PK_mg_feed_excitation) || (k == (size_t)RFE_PK_mg_feed_ax_min) ||
               (k == (size_t)RFE_PK_mg_feed_slip_max) || (k == (size_t)RFE_PK_mg_feed_band)) {
        if (!((v >= 0.0) && isfinite(v))) {
            return -1;
        }
    } else if (k == (size_t)RFE_PK_R) {
        mp->R = (rfe_real_t)v;
    } else if (k == (size_t)RFE_PK_g) {
        mp->g = (rfe_real_t)v;
    } else {
        const rfe_real_t r = (rfe_real_t)v;
        memcpy((char *)mp + k_mg_offset[k - RFE_PK_MG_FIRST - RFE_PK_MG_SPECIAL], &r, sizeof r);
    }
    return 0;
}

/* The keys the mass and grade parameters take, in the order they are applied: R, g, then
 * the mg_* keys; index i of RFE_PK_MG_COUNT + 2. */
static size_t mg_key(size_t i)
{
    return (i == 0u) ? (size_t)RFE_PK_R : ((i == 1u) ? (size_t)RFE_PK_g : RFE_PK_MG_FIRST + i - 2u);
}

/* The mass and grade group (key_group_t): the preset of the set's vehicle and config, then R,
 * g and the mg_* keys. */
static int mg_start(const rfe_param_set_t *ps, void *p)
{
    return (rfe_mass_grade_params_preset((rfe_mass_grade_params_t *)p, ps->mg_vehicle,
                                         ps->mg_config) ==
            RFE_OK)
               ? 0
               : -1;
}

static int mg_set(void *p, const rfe_param_set_t *ps, size_t k)
{
    return set_mg_key((rfe_mass_grade_params_t *)p, ps, k);
}

static int mg_check(const void *p)
{
    return (rfe_mass_grade_params_validate((const rfe_mass_grade_params_t *)p) == RFE_OK) ? 0 : -1;
}

rfe_status_t rfe_replay_mass_grade_params(const rfe_param_set_t *ps, rfe_mass_grade_params_t *mp,
                                          size_t *bad_key)
{
    static const key_group_t group = {RFE_PK_MG_COUNT + 2u, mg_key, mg_start, mg_set, mg_check};
    rfe_mass_grade_params_t one;
    if ((ps == NULL) || (mp == NULL)) {
        return RFE_ERR_NULL;
    }
    return group_params(&group, ps, mp, &one, bad_key);
}

/* Tyre identifier key @p k of the set into @p tp; 0, or -1 when a word key holds no enum
 * value, tid_substeps is not an integer 0 .. 2^32 - 1 (a double would otherwise be
 * truncated without a word; the library checks its range), tid_seed is not an integer
 * 0 .. 2^53 (it has no member: rfe_replay_tyre_id_params reads it from the set) or
 * tid_feed_sd_rel, tid_feed_evidence, tid_feed_ax_max, tid_feed_refresh or
 * tid_feed_outlier_k is not a finite number >= 0 (the replay's). */
static int set_tid_key(rfe_tyre_id_params_t *tp, const rfe_param_set_t *ps, size_t k)
{
    const double v = ps->tid[k - RFE_PK_TID_FIRST];
    const int whole = (v >= 0.0) && (v == floor(v));
    if (k == (size_t)RFE_PK_tid_filter) {
        if (!((v == 0.0) || (v == 1.0) || (v == 2.0))) {
            return -1;
        }
        tp->filter = (v == 0.0) ? RFE_TID_APF : ((v == 1.0) ? RFE_TID_SIR : RFE_TID_SCKF);
    } else if (k == (size_t)RFE_PK_tid_resample) {
        if (!((v == 0.0) || (v == 1.0))) {
            return -1;
        }
        tp->resample = (v == 0.0) ? RFE_TID_MULTINOMIAL : RFE_TID_SYSTEMATIC;
    } else if (k == (size_t)RFE_PK_tid_substeps) {
        if (!whole || (v > 4294967295.0)) {
            return -1;
        }
        tp->substeps = (uint32_t)v;
    } else if (k == (size_t)RFE_PK_tid_seed) {
        if (!whole || (v > RFE_TID_SEED_MAX)) {
            return -1;
        }
    } else if ((k == (size_t)RFE_PK_tid_feed_sd_rel) || (k == (size_t)RFE_PK_tid_feed_evidence) ||
               (k == (size_t)RFE_PK_tid_feed_ax_max) || (k == (size_t)RFE_PK_tid_feed_refresh) ||
               (k == (size_t)RFE_PK_tid_feed_outlier_k)) {
        if (!((v >= 0.0) && isfinite(v))) {
            return -1;
        }
    } else {
        const rfe_real_t r = (rfe_real_t)v;
        memcpy((char *)tp + k_tid_offset[k - RFE_PK_TID_FIRST - RFE_PK_TID_SPECIAL], &r, sizeof r);
    }
    return 0;
}

/* The tyre identifier's group (key_group_t): its defaults, then every tid_* key. */
static size_t tid_key(size_t i)
{
    return RFE_PK_TID_FIRST + i;
}

static int tid_start(const rfe_param_set_t *ps, void *p)
{
    (void)ps;
    return (rfe_tyre_id_params_default((rfe_tyre_id_params_t *)p) == RFE_OK) ? 0 : -1;
}

static int tid_set(void *p, const rfe_param_set_t *ps, size_t k)
{
    return set_tid_key((rfe_tyre_id_params_t *)p, ps, k);
}

static int tid_check(const void *p)
{
    return (rfe_tyre_id_params_validate((const rfe_tyre_id_params_t *)p) == RFE_OK) ? 0 : -1;
}

rfe_status_t rfe_replay_tyre_id_params(const rfe_param_set_t *ps, rfe_tyre_id_params_t *tp,
                                       uint64_t *seed, size_t *bad_key)
{
    static const key_group_t group = {RFE_PK_TID_COUNT, tid_key, tid_start, tid_set, tid_check};
    rfe_tyre_id_params_t one;
    rfe_status_t st;
    if ((ps == NULL) || (tp == NULL) || (seed == NULL)) {
        return RFE_ERR_NULL;
    }
    st = group_params(&group, ps, tp, &one, bad_key);
    if (st == RFE_OK) {
        /* an integer 0 .. 2^53 (set_tid_key): exact in uint64_t */
        *seed = (uint64_t)ps->tid[RFE_PK_tid_seed - RFE_PK_TID_FIRST];
    }
    return st;
}

/* The mass and grade sample (replay_real.h). */
rfe_status_t rfe_replay_mass_grade_input_row(const rfe_sensor_log_t *log,
                                             const rfe_sensor_row_t *row, const double *t_prev,
                                             double R, rfe_mass_grade_input_t *in)
{
    const double v = ((((row->omega[RFE_FL] + row->omega[RFE_FR]) + row->omega[RFE_RL]) +
                       row->omega[RFE_RR]) /
                      4.0) *
                     R;
    memset(in, 0, sizeof *in);
    in->dt = (t_prev != NULL) ? (rfe_real_t)(row->t - *t_prev) : (rfe_real_t)0.0;
    in->v = (rfe_real_t)v;
    in->torque = (rfe_real_t)row->drive_torque;
    in->ax = (rfe_real_t)row->ax;
    in->p_brake = log->has_brake_pressure ? (rfe_real_t)row->brake_pressure : (rfe_real_t)0.0;
    in->has = RFE_MG_HAS_AX | (log->has_brake_pressure ? RFE_MG_HAS_PRESSURE : 0u) |
              (log->has_brake ? RFE_MG_HAS_BRAKE : 0u) | (log->has_gear ? RFE_MG_HAS_GEAR : 0u);
    /* the slip pause's ground speed: the log's measured vx only (never the observer's,
     * which takes this estimator's grade: MASS_GRADE.md §10); a bad cell is refused by the
     * library as the other inputs' are */
    if (log->has_velocity != 0) {
        in->vx = (rfe_real_t)row->vx;
        in->has |= RFE_MG_HAS_VX;
    }
    /* the curve pause's lateral acceleration (a required column; used with mg_ay_max > 0) */
    in->ay = (rfe_real_t)row->ay;
    in->has |= RFE_MG_HAS_AY;
    if ((log->has_brake && !isfinite(row->brake)) || (log->has_gear && !isfinite(row->gear))) {
        return RFE_ERR_NONFINITE;
    }
    if (log->has_gear && (fabs(row->gear) > RFE_REPLAY_GEAR_MAX)) {
        return RFE_ERR_RANGE;
    }
    in->brake = (log->has_brake && (row->brake >= 0.5)) ? 1u : 0u;
    in->gear = log->has_gear ? (int32_t)floor(row->gear + 0.5) : 0; /* the nearest gear */
    return RFE_OK;
}

/* One mass and grade step on @p row into @p out; a row the library (or the sample's checks)
 * refuses gets the held estimate and its error status. */
static void mass_grade_row(rfe_replay_state_t *st, const rfe_sensor_row_t *row, rfe_est_row_t *out)
{
    rfe_mass_grade_input_t in;
    rfe_mass_grade_t *mg = &st->mg;
    /* the estimate of the last step (rfe_mass_grade_t.last: zero before the first accepted
     * sample), held should the row be refused here; the library's step refusing it gives
     * the same (mass_grade.h) */
    rfe_mass_grade_estimate_t e = mg->last;
    rfe_status_t s = rfe_replay_mass_grade_input_row(&st->shape, row,
                                                     st->have_mg_last ? &st->t_mg_last : NULL,
                                                     (double)mg->p.R, &in);
    /* the library's start (mass_grade.h: not started, or a period beyond dt_max), in its
     * arithmetic, for the feed's gate */
    const int start = ((mg->started == 0u) || (in.dt > mg->p.dt_max)) ? 1 : 0;
    const double dt = st->have_mg_last ? (row->t - st->t_mg_last) : 0.0;
    if (s == RFE_OK) {
        s = rfe_mass_grade_step(mg, &in, &e);
    }
    if (!rfe_status_is_error(s)) {
        st->t_mg_last = row->t;
        st->have_mg_last = 1;
    }
    rfe_replay_mass_gate_step(&st->gate, rfe_status_is_error(s) ? 0 : start, (int)s, row->ax, dt,
                              rfe_replay_mass_gate_slips(&st->gate, row, (double)mg->p.R));
    st->stats.mg_excitation = st->gate.excitation;
    out->has_mass_grade = 1;
    out->mass = (double)e.mass;
    out->sd_mass = (double)e.sd_mass;
    out->grade = (double)e.grade;
    out->sd_grade = (double)e.sd_grade;
    out->mg_status = (int)s;
    out->grade_walk = (int)mg->wq_hi; /* §4.7 the level after this step (an error leaves it) */
    out->mg_mismatch = (int)e.mismatch; /* §4.8 the flag after this step */
    ++st->stats.mg_status_count[rfe_replay_status_slot(out->mg_status)];
}

/* Records the friction estimator's mass of this sample in @p out and the run's counters:
 * @p fed_st is the status of this sample's feed (RFE_OK: fed), or -1 when none was due. */
static void mass_used_row(rfe_real_t m_used, int fed_st, rfe_est_row_t *out,
                          rfe_replay_stats_t *stats)
{
    out->mass_used = (double)m_used;
    stats->n_mass_fed += (fed_st == (int)RFE_OK) ? 1u : 0u;
    stats->mass_used_last = out->mass_used;
}

/* Whether this run steps the mass and grade estimator, and if so its init (RFE_OK: *on set). */
static rfe_status_t mass_grade_init(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                    rfe_mass_grade_t *mg, int *on, size_t *bad_key)
{
    rfe_mass_grade_params_t mp;
    rfe_status_t st = RFE_OK;
    *on = (ps->mass_grade != 0) && (log->has_drive_torque != 0);
    if (*on) {
        st = rfe_replay_mass_grade_params(ps, &mp, bad_key);
    }
    if (*on && (st == RFE_OK)) {
        st = rfe_mass_grade_init(mg, &mp);
    }
    return st;
}

/* The observer's group (key_group_t): its defaults, then obs_driven .. the last obs_* key. */
static size_t obs_key(size_t i)
{
    return RFE_PK_OBS_FIRST + i;
}

static int obs_start(const rfe_param_set_t *ps, void *p)
{
    (void)ps;
    return (rfe_velocity_params_default((rfe_velocity_params_t *)p) == RFE_OK) ? 0 : -1;
}

static int obs_set(void *p, const rfe_param_set_t *ps, size_t k)
{
    return set_obs_key((rfe_velocity_params_t *)p, ps, k);
}

static int obs_check(const void *p)
{
    return (rfe_velocity_params_validate((const rfe_velocity_params_t *)p) == RFE_OK) ? 0 : -1;
}

rfe_status_t rfe_replay_velocity_params(const rfe_param_set_t *ps, rfe_velocity_params_t *vp,
                                        size_t *bad_key)
{
    static const key_group_t group = {RFE_PK_OBS_COUNT, obs_key, obs_start, obs_set, obs_check};
    rfe_velocity_params_t one;
    if ((ps == NULL) || (vp == NULL)) {
        return RFE_ERR_NULL;
    }
    return group_params(&group, ps, vp, &one, bad_key);
}

/* Whether this run steps the tyre identifier, and if so its init with the friction
 * estimator's vehicle and tyre data @p p (RFE_OK: t->on set). */
static rfe_status_t tyre_id_init(const rfe_param_set_t *ps, const rfe_params_t *p, tid_run_t *t,
                                 size_t *bad_key)
{
    rfe_status_t st = RFE_OK;
    t->on = (ps->tyre_id != 0);
    t->have_last = 0;
    t->feed = ps->tid[RFE_PK_tid_feed_sd_rel - RFE_PK_TID_FIRST];
    t->evidence = ps->tid[RFE_PK_tid_feed_evidence - RFE_PK_TID_FIRST];
    t->ax_max = ps->tid[RFE_PK_tid_feed_ax_max - RFE_PK_TID_FIRST];
    t->t_wrong = 0.0;
    t->have_row = 0;
    t->r_model = ps->value[RFE_PK_r_model_rel];
    t->feed_on = t->on && (t->feed > 0.0);
    t->refresh = ps->tid[RFE_PK_tid_feed_refresh - RFE_PK_TID_FIRST];
    t->outlier_k = ps->tid[RFE_PK_tid_feed_outlier_k - RFE_PK_TID_FIRST];
    t->fresh = 0.0;
    t->t_fresh = 0.0;
    t->have_fresh = 0;
    t->tainted = 0;
    t->bad = 0;
    t->ref_ok = 0;
    t->resume = 0;
    if (t->on) {
        st = rfe_replay_tyre_id_params(ps, &t->tp, &t->seed, bad_key);
    }
    if (t->on && (st == RFE_OK)) {
        t->veh = *p;
        st = rfe_tyre_id_init(&t->tid, &t->tp, &t->veh, t->seed);
    }
    return st;
}

/* Row @p out's tyre identifier columns from its estimate @p e and the status @p st of this
 * sample, and the run's counters. */
static void tyre_id_out(const rfe_tyre_id_estimate_t *e, rfe_status_t st, rfe_est_row_t *out,
                        rfe_replay_stats_t *stats)
{
    uint32_t b;
    out->has_tyre_id = 1;
    out->mu_id[0] = (double)e->mean[RFE_TID_OUT_MU_F];
    out->mu_id[1] = (double)e->mean[RFE_TID_OUT_MU_R];
    out->sd_mu_id[0] = (double)e->sd[RFE_TID_OUT_MU_F];
    out->sd_mu_id[1] = (double)e->sd[RFE_TID_OUT_MU_R];
    out->mf_B[0] = (double)e->mean[RFE_TID_OUT_B_F];
    out->mf_C[0] = (double)e->mean[RFE_TID_OUT_C_F];
    out->mf_D[0] = (double)e->mean[RFE_TID_OUT_D_F];
    out->mf_E[0] = (double)e->mean[RFE_TID_OUT_E_F];
    out->mf_B[1] = (double)e->mean[RFE_TID_OUT_B_R];
    out->mf_C[1] = (double)e->mean[RFE_TID_OUT_C_R];
    out->mf_D[1] = (double)e->mean[RFE_TID_OUT_D_R];
    out->mf_E[1] = (double)e->mean[RFE_TID_OUT_E_R];
    out->tid_status = (int)st;
    /* a refused sample's estimate is the held one: its flags are not this sample's */
    out->tid_flags = rfe_status_is_error(st) ? 0u : (unsigned)e->flags;
    ++stats->tid_status_count[rfe_replay_status_slot(out->tid_status)];
    for (b = 0u; b < RFE_REPLAY_TID_FLAGS; ++b) {
        stats->tid_flag_count[b] += ((out->tid_flags >> b) & 1u);
    }
}

/* One tyre identifier step on @p row with the vx and road-wheel angle of this sample's
 * velocity (the log's, or the observer's), into @p out. The period is the time since the last
 * row it accepted; beyond tid_dt_max the identifier starts afresh at this row (its prior drawn
 * again from the same seed), as the observer does after obs_dt_max. A row it refuses gets the
 * held estimate and the error status. */
static void tyre_id_row(tid_run_t *t, const rfe_sensor_row_t *row, rfe_real_t vx,
                        rfe_real_t delta, rfe_est_row_t *out, rfe_replay_stats_t *stats)
{
    rfe_tyre_id_sample_t s;
    rfe_tyre_id_estimate_t e;
    rfe_status_t st;
    s.dt = t->have_last ? (rfe_real_t)(row->t - t->t_last) : (rfe_real_t)0.0;
    s.delta = delta;
    s.vx = vx;
    s.yaw_rate = (rfe_real_t)row->yaw_rate;
    s.ay = (rfe_real_t)row->ay;
    s.ax = (rfe_real_t)row->ax;
    if (t->have_last && (s.dt > t->tp.dt_max) &&
        (rfe_tyre_id_init(&t->tid, &t->tp, &t->veh, t->seed) == RFE_OK)) {
        ++stats->tid_restarts; /* the init took these parameters before: it cannot fail */
    }
    st = rfe_tyre_id_step(&t->tid, &s, &e);
    if (!rfe_status_is_error(st)) {
        t->t_last = row->t;
        t->have_last = 1;
    }
    tyre_id_out(&e, st, out, stats);
}

/* The friction estimator's evidence that its curve is wrong (TYRE_ID.md §14), called after
 * each sample's friction step (@p out, at time @p t): the time between this row and the
 * previous one is added to t_wrong when this sample's status is 1 (its mean projected onto a
 * mu bound) or 4 (model mismatch). */
static void tyre_feed_evidence(tid_run_t *t, double time, const rfe_est_row_t *out)
{
    if (t->have_row && ((out->status == (int)RFE_PROJECTED) ||
                        (out->status == (int)RFE_MODEL_MISMATCH))) {
        t->t_wrong += time - t->t_row;
    }
    t->t_row = time;
    t->have_row = 1;
}

/* The feed's taint (MONITOR.md §7), called with tid_feed_refresh > 0 before this sample's
 * friction step (@p row): the sample is held (|ax| > tid_feed_ax_max, when positive: the
 * identifier's lateral-only model learns the combined slip's curve) or implausible (its
 * |ay - ay_p| > tid_feed_outlier_k * tid_sd_ay, ay_p = (F_f cos(delta) + F_r) / m of the
 * identifier's last estimate, when that step updated: a jump of ay no tyre force follows
 * within a sample, which the identifier's weights nevertheless take); either taints the
 * identifier's curve (no feed until tid_feed_refresh). 1 on the first implausible sample of a
 * taint: the friction estimator's model error is to be set back to the set's before this
 * step (the fed curve's uncertainty joined to it would otherwise hide the sample from its
 * model-validity monitor). In double. */
static int tyre_feed_taint(tid_run_t *t, const rfe_sensor_row_t *row)
{
    const rfe_tyre_id_estimate_t *e = &t->tid.last;
    const double ay_p = (((double)e->mean[RFE_TID_OUT_FY_F] * cos(row->delta)) +
                         (double)e->mean[RFE_TID_OUT_FY_R]) /
                        (double)t->tid.c.m;
    const int held = (t->ax_max > 0.0) && (fabs(row->ax) > t->ax_max);
    const int implausible = (t->ref_ok != 0) && (t->outlier_k > 0.0) &&
                            (fabs(row->ay - ay_p) > (t->outlier_k * (double)t->tp.sd_ay));
    const int first = implausible && (t->tainted == 0);
    t->bad = held || implausible;
    if (t->bad != 0) {
        t->tainted = 1;
        t->fresh = 0.0;
    }
    return first;
}

/* The feed's refresh (MONITOR.md §7), called with the feed on after this sample's identifier
 * step (@p out); nothing with tid_feed_refresh 0. An untainted sample on which it updated with |ay| >=
 * tid_feed_outlier_k * tid_sd_ay (lateral force it can learn the curve from) adds the
 * period since the previous row to fresh; once fresh reaches tid_feed_refresh the taint is
 * lifted, and the feed resumes at the first due sample with |ay| < tid_feed_outlier_k *
 * tid_sd_ay (resume: a curve changed where the tyres carry little lateral force moves the
 * friction estimator's lateral rows least; at the limit it moves its mu, MONITOR.md §7). */
static void tyre_feed_refresh(tid_run_t *t, const rfe_sensor_row_t *row, const rfe_est_row_t *out)
{
    const int updated = ((out->tid_flags & RFE_TID_UPDATED) != 0u) ? 1 : 0;
    const double dt = (t->have_fresh != 0) ? (row->t - t->t_fresh) : 0.0;
    const int excited = fabs(row->ay) >= (t->outlier_k * (double)t->tp.sd_ay);
    if (!(t->refresh > 0.0)) {
        return;
    }
    t->t_fresh = row->t;
    t->have_fresh = 1;
    t->ref_ok = updated;
    if ((t->tainted != 0) && (t->bad == 0) && (updated != 0) && excited) {
        t->fresh += dt;
        t->tainted = (t->fresh >= t->refresh) ? 0 : 1;
        t->resume = (t->tainted == 0) ? 1 : 0;
    }
}

/* The feed rule (TYRE_ID.md §14), called with tid_feed_sd_rel > 0: 1, with the curve to feed
 * in @p v (cy, shape_Cy, shape_Ey, r_model_rel), when the friction estimator's evidence
 * (t_wrong) has reached tid_feed_evidence, this sample's |ax| (@p ax, the log's) is at most
 * tid_feed_ax_max (when positive: under braking or driving the identifier's lateral-only
 * model reads the combined slip's lower lateral force as a different curve, so the friction
 * estimator keeps the one it has), the curve is not tainted and, on the first feed after a
 * taint, this sample's |ay| (@p ay) is below tid_feed_outlier_k * tid_sd_ay (tid_feed_refresh,
 * MONITOR.md §7; neither with the key 0), this sample's identifier step (@p out)
 * updated (its flags are 0 on a refused sample) and the relative sd of the summed cornering
 * stiffness, rel = sqrt(sd_Kf^2 + sd_Kr^2) / (K_f + K_r) (the axles' spreads taken as
 * independent), is at most tid_feed_sd_rel. The curve: cy =
 * (K_f + K_r) / (Fz0_f + Fz0_r) (the identifier's static axle loads), shape_Cy and shape_Ey
 * the axles' C and E weighted by those loads, r_model_rel = sqrt(r^2 + rel^2) with r the
 * parameter set's (key r_model_rel): the curve's uncertainty joins the model error. In double, each rounded to
 * the build's real type. */
static int tyre_feed_due(const tid_run_t *t, const rfe_est_row_t *out, double ax, double ay,
                         rfe_real_t v[4])
{
    const rfe_tyre_id_estimate_t *e = &t->tid.last;
    const double feed = t->feed;
    const double r = t->r_model;
    const double fz_f = (double)t->tid.c.fz0[0];
    const double fz_r = (double)t->tid.c.fz0[1];
    const double k = (double)e->mean[RFE_TID_OUT_K_F] + (double)e->mean[RFE_TID_OUT_K_R];
    const double sd_f = (double)e->sd[RFE_TID_OUT_K_F];
    const double sd_r = (double)e->sd[RFE_TID_OUT_K_R];
    const double rel = sqrt((sd_f * sd_f) + (sd_r * sd_r)) / k;
    const int held = (t->ax_max > 0.0) && (fabs(ax) > t->ax_max);
    const int calm = (t->resume == 0) || (fabs(ay) < (t->outlier_k * (double)t->tp.sd_ay));
    if (!((t->t_wrong >= t->evidence) && !held && (t->tainted == 0) && calm &&
          ((out->tid_flags & RFE_TID_UPDATED) != 0u) &&
          (rel <= feed))) {
        return 0;
    }
    v[0] = (rfe_real_t)(k / (fz_f + fz_r));
    v[1] = (rfe_real_t)(((fz_f * (double)e->mean[RFE_TID_OUT_C_F]) +
                         (fz_r * (double)e->mean[RFE_TID_OUT_C_R])) /
                        (fz_f + fz_r));
    v[2] = (rfe_real_t)(((fz_f * (double)e->mean[RFE_TID_OUT_E_F]) +
                         (fz_r * (double)e->mean[RFE_TID_OUT_E_R])) /
                        (fz_f + fz_r));
    v[3] = (rfe_real_t)sqrt((r * r) + (rel * rel));
    return 1;
}

/* The friction estimator's lateral curve of this sample's step into @p out (when fed). */
static void tyre_used_row(const rfe_params_t *p, rfe_est_row_t *out)
{
    out->has_tyre_feed = 1;
    out->cy_used = (double)p->tyre.cy;
    out->shape_Cy_used = (double)p->tyre.shape_Cy;
    out->shape_Ey_used = (double)p->tyre.shape_Ey;
    out->r_model_rel_used = (double)p->filter.r_model_rel;
}

void rfe_replay_sample_from_row(const rfe_sensor_row_t *row, rfe_sample_t *s)
{
    size_t w;
    s->delta = (rfe_real_t)row->delta;
    s->vx = (rfe_real_t)row->vx;
    s->vy = (rfe_real_t)row->vy;
    s->yaw_rate = (rfe_real_t)row->yaw_rate;
    s->yaw_acc = (rfe_real_t)row->yaw_acc;
    s->ax = (rfe_real_t)row->ax;
    s->ay = (rfe_real_t)row->ay;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        s->omega[w] = (rfe_real_t)row->omega[w];
    }
}

rfe_status_t rfe_replay_params(const rfe_param_set_t *ps, rfe_params_t *p,
                               size_t *bad_key)
{
    rfe_status_t st;
    if ((ps == NULL) || (p == NULL)) {
        return RFE_ERR_NULL;
    }
    if (bad_key != NULL) {
        *bad_key = RFE_PK_NONE;
    }
    st = to_lib_params(ps, p);
    if (st == RFE_OK) {
        st = rfe_params_validate(p);
    }
    if ((st == RFE_ERR_PARAM) && (bad_key != NULL)) {
        *bad_key = diagnose_params(ps);
    }
    return st;
}

/* The friction estimator's step on @p row. On a rejected sample the estimator is unchanged:
 * log its current estimate, not valid, with the error status, and carry on. */
static void step_row(rfe_friction_t *est, const rfe_sensor_row_t *row, rfe_est_row_t *out)
{
    rfe_sample_t s;
    rfe_estimate_t e;
    rfe_status_t st;
    size_t w;
    rfe_replay_sample_from_row(row, &s);
    memset(&e, 0, sizeof e);
    /* friction.h: on a rejected sample e holds the previous estimate, valid = 0. */
    st = rfe_friction_step(est, &s, &e);
    out->t = row->t;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        out->mu[w] = (double)e.mu[w];
        out->sd[w] = (double)e.sd[w];
        out->valid[w] = rfe_status_is_error(st) ? 0u : e.valid[w];
    }
    out->status = (int)st;
    out->has_velocity = 0; /* has_mass_grade: the caller's (mass_grade_row sets it) */
}

void rfe_replay_esc_input_row(const rfe_sensor_log_t *log, const rfe_sensor_row_t *row,
                              const double *t_prev, rfe_velocity_input_t *in)
{
    size_t w;
    memset(in, 0, sizeof *in);
    in->dt = (t_prev != NULL) ? (rfe_real_t)(row->t - *t_prev) : (rfe_real_t)0.0;
    in->delta = (rfe_real_t)row->delta;
    in->steer_wheel = log->has_swa ? (rfe_real_t)row->swa : (rfe_real_t)0.0;
    in->yaw_rate = (rfe_real_t)row->yaw_rate;
    in->ax = (rfe_real_t)row->ax;
    in->ay = (rfe_real_t)row->ay;
    in->grade = log->has_grade ? (rfe_real_t)row->grade : (rfe_real_t)0.0;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        in->omega[w] = (rfe_real_t)row->omega[w];
        in->p_brake[w] = log->has_pressure ? (rfe_real_t)row->p_brake[w] : (rfe_real_t)0.0;
        in->torque[w] = log->has_torque ? (rfe_real_t)row->torque[w] : (rfe_real_t)0.0;
    }
    in->has = (log->has_pressure ? RFE_VEL_HAS_PRESSURE : 0u) |
              (log->has_torque ? RFE_VEL_HAS_TORQUE : 0u) |
              (log->has_swa ? RFE_VEL_HAS_STEER_WHEEL : 0u);
}

void rfe_replay_esc_input(const rfe_sensor_log_t *log, size_t i, size_t prev,
                          rfe_velocity_input_t *in)
{
    rfe_replay_esc_input_row(log, &log->rows[i], (prev < i) ? &log->rows[prev].t : NULL, in);
}

size_t rfe_replay_state_size(void)
{
    return sizeof(rfe_replay_state_t);
}

rfe_status_t rfe_replay_begin(rfe_replay_state_t *st, const rfe_param_set_t *ps,
                              const rfe_sensor_log_t *log, int observer, size_t *bad_key)
{
    rfe_params_t p;
    rfe_velocity_params_t vp;
    rfe_status_t s;
    if ((st == NULL) || (ps == NULL) || (log == NULL)) {
        return RFE_ERR_NULL;
    }
    /* not yet rad/s (and, measuring, a road-wheel angle): csv_log.h; the state untouched */
    if ((log->omega_linear != 0) || ((observer == 0) && (log->has_swa != 0))) {
        return RFE_ERR_RANGE;
    }
    memset(st, 0, sizeof *st); /* padding defined: a run is a function of its input */
    st->shape = rfe_sensor_log_shape(log); /* the columns it has, not its rows nor metadata */
    st->observer = (observer != 0) ? 1 : 0;
    st->dt = ps->value[RFE_PK_dt];
    st->feed_sd_rel = ps->mg[RFE_PK_mg_feed_sd_rel - RFE_PK_MG_FIRST];
    st->gate = rfe_replay_mass_gate_of(ps);
    s = rfe_replay_params(ps, &p, bad_key);
    if ((s == RFE_OK) && (observer != 0)) {
        s = rfe_replay_velocity_params(ps, &vp, bad_key);
    }
    if (s == RFE_OK) {
        s = (observer != 0) ? rfe_pipeline_init(&st->pl, &p, &vp)
                            : rfe_friction_init(&st->pl.friction, &p);
    }
    if (s == RFE_OK) {
        s = mass_grade_init(ps, log, &st->mg, &st->mg_on, bad_key);
    }
    if (s == RFE_OK) {
        s = tyre_id_init(ps, &p, &st->tid, bad_key);
    }
    if ((s == RFE_OK) && (observer != 0) && (st->tid.feed_on != 0)) {
        /* the pipeline has no lateral tyre setter: the feed runs with measured velocities */
        s = RFE_ERR_PARAM;
        if (bad_key != NULL) {
            *bad_key = (size_t)RFE_PK_tid_feed_sd_rel;
        }
    }
    st->ready = (s == RFE_OK) ? 1 : 0;
    return s;
}

/* The mass and grade step first, so this sample's friction step takes the mass fed from
 * this sample's update (causal; one way: the estimator takes nothing of the friction
 * estimator's or the observer's); behind the observer, the observer's grade input when the
 * log has none. */
static void mass_grade_first(rfe_replay_state_t *st, const rfe_sensor_row_t *row,
                             rfe_est_row_t *out, rfe_real_t *grade)
{
    int fed = -1;
    rfe_replay_feed_t due;
    if (st->shape.has_velocity != 0) {
        rfe_replay_mass_gate_vx(&st->gate, row->vx); /* the measured vx: the slip's reference */
    }
    mass_grade_row(st, row, out);
    *grade = st->shape.has_grade ? *grade : (rfe_real_t)out->grade;
    due = rfe_replay_mass_feed_due(st->feed_sd_rel, &st->gate, out);
    rfe_replay_mass_feed_count(due, &st->stats);
    if (due == RFE_REPLAY_FEED_DUE) {
        /* a mass rfe_params_set_mass refuses (not finite, <= 0: not an estimate in
         * [mg_m_min, mg_m_max]) leaves the last one; the observer keeps the friction
         * estimator's vehicle */
        const rfe_real_t m = (rfe_real_t)out->mass;
        fed = (int)((st->observer != 0) ? rfe_pipeline_set_mass(&st->pl, m)
                                        : rfe_friction_set_mass(&st->pl.friction, m));
    }
    mass_used_row(st->pl.friction.params.vehicle.m, fed, out, &st->stats);
}

/* One pipeline step (the observer feeding the friction estimator) on @p row. The period is
 * the time since the last accepted row (rfe/pipeline.h). */
static void step_observer_row(rfe_replay_state_t *st, const rfe_sensor_row_t *row,
                              rfe_est_row_t *out)
{
    rfe_velocity_input_t in;
    rfe_pipeline_out_t o;
    rfe_status_t s;
    size_t w;
    rfe_replay_esc_input_row(&st->shape, row, st->have_last ? &st->t_last : NULL, &in);
    if (st->mg_on != 0) {
        mass_grade_first(st, row, out, &in.grade);
    }
    memset(&o, 0, sizeof o);
    s = rfe_pipeline_step(&st->pl, &in, &o);
    if (!rfe_status_is_error(s)) {
        st->t_last = row->t; /* the next period starts here */
        st->have_last = 1;
        st->stats.n_gaps += (o.missed > 0u) ? 1u : 0u;
        st->stats.n_skipped += o.missed;
        st->stats.n_restarts += o.restarted;
        if (st->shape.has_velocity == 0) {
            /* no measured vx: the next row's slip is taken against this observer vx */
            rfe_replay_mass_gate_vx(&st->gate, (double)o.velocity.vx);
        }
    }
    out->t = row->t;
    for (w = 0u; w < (size_t)RFE_WHEELS; ++w) {
        out->mu[w] = (double)o.friction.mu[w];
        out->sd[w] = (double)o.friction.sd[w];
        out->valid[w] = rfe_status_is_error(s) ? 0u : o.friction.valid[w];
    }
    out->status = (int)s;
    out->has_velocity = 1;
    out->vx = (double)o.velocity.vx;
    out->vy = (double)o.velocity.vy;
    out->beta = (double)o.velocity.beta;
    out->yaw_acc = (double)o.velocity.yaw_acc;
    out->sd_vx = (double)o.velocity.sd_vx;
    out->sd_vy = (double)o.velocity.sd_vy;
    out->sd_beta = (double)o.velocity.sd_beta;
    if ((st->tid.on != 0) && !rfe_status_is_error(s)) {
        /* after the pipeline, on this sample's observer vx and the road-wheel angle it
         * used (swa / obs_steer_ratio on a steering-wheel log) */
        tyre_id_row(&st->tid, row, o.velocity.vx, o.velocity.delta, out, &st->stats);
    } else if (st->tid.on != 0) {
        /* a sample the pipeline refused has no observer vx: the identifier is not
         * stepped, its estimate held with the pipeline's status */
        tyre_id_out(&st->tid.tid.last, s, out, &st->stats);
    } else {
        /* not run */
    }
}

/* With the feed and tid_feed_refresh on, the taint of this sample (tyre_feed_taint) before its
 * friction step; on the first implausible sample of a taint the estimator keeps its curve
 * with the set's r_model_rel. */
static void tyre_feed_reset(rfe_replay_state_t *st, const rfe_sensor_row_t *row)
{
    const rfe_params_t *p = &st->pl.friction.params;
    if ((st->tid.feed_on == 0) || !(st->tid.refresh > 0.0)) {
        return; /* the rule off: nothing of it runs */
    }
    if ((tyre_feed_taint(&st->tid, row) != 0) &&
        (rfe_friction_set_lateral_tyre(&st->pl.friction, p->tyre.cy, p->tyre.shape_Cy,
                                       p->tyre.shape_Ey, (rfe_real_t)st->tid.r_model) == RFE_OK)) {
        ++st->stats.n_tyre_reset; /* the set's own value: it cannot be refused */
    }
}

/* One friction step on measured velocities: a gap's missed periods time-updated before the
 * sample that ends it. */
static void step_measured_row(rfe_replay_state_t *st, const rfe_sensor_row_t *row,
                              rfe_est_row_t *out)
{
    const uint32_t missed = st->have_prev ? rfe_log_missed(row->t - st->t_prev, st->dt) : 0u;
    if (missed > 0u) {
        ++st->stats.n_gaps;
        if (rfe_friction_skip(&st->pl.friction, missed) == RFE_OK) {
            st->stats.n_skipped += missed;
        }
    }
    if (st->mg_on != 0) {
        rfe_real_t unused = (rfe_real_t)0.0; /* measured velocities: the grade feeds nothing */
        mass_grade_first(st, row, out, &unused);
    }
    tyre_feed_reset(st, row);
    if (st->tid.feed_on != 0) {
        tyre_used_row(&st->pl.friction.params, out); /* the curve of this sample's step */
    }
    step_row(&st->pl.friction, row, out);
    if (st->tid.on != 0) {
        /* beside the friction estimator, on the log's vx and delta: it takes nothing of
         * the estimator's; with tid_feed_sd_rel > 0 it gives it its curve for the next
         * sample's step (causal: this sample's step has run) */
        rfe_real_t v[4];
        tyre_id_row(&st->tid, row, (rfe_real_t)row->vx, (rfe_real_t)row->delta, out,
                    &st->stats);
        if (st->tid.feed_on != 0) {
            tyre_feed_evidence(&st->tid, row->t, out);
            tyre_feed_refresh(&st->tid, row, out);
        }
        if ((st->tid.feed_on != 0) && (tyre_feed_due(&st->tid, out, row->ax, row->ay, v) != 0) &&
            (rfe_friction_set_lateral_tyre(&st->pl.friction, v[0], v[1], v[2], v[3]) ==
             RFE_OK)) {
            ++st->stats.n_tyre_fed; /* a curve it refuses (C at a bound of (1, 2)) is not fed */
            st->tid.resume = 0;
        }
    }
}

rfe_status_t rfe_replay_step(rfe_replay_state_t *st, const rfe_sensor_row_t *row,
                             rfe_est_row_t *out)
{
    if ((st == NULL) || (row == NULL) || (out == NULL)) {
        return RFE_ERR_NULL;
    }
    if (st->ready == 0) {
        return RFE_ERR_NOT_INITIALISED;
    }
    if (st->have_prev && !(row->t > st->t_prev)) {
        return RFE_ERR_RANGE; /* time must increase (the reader's rule for a log) */
    }
    out->has_mass_grade = 0;
    out->has_tyre_id = 0;
    out->has_tyre_feed = 0;
    if (st->observer != 0) {
        step_observer_row(st, row, out);
    } else {
        step_measured_row(st, row, out);
    }
    st->t_prev = row->t;
    st->have_prev = 1;
    ++st->stats.status_count[rfe_replay_status_slot(out->status)];
    ++st->stats.n_steps;
    return RFE_OK;
}

rfe_status_t rfe_replay_feed(rfe_replay_state_t *st, const rfe_sensor_row_t *rows, size_t n,
                             rfe_est_row_t *out)
{
    size_t i;
    rfe_status_t s = ((rows == NULL) || (out == NULL)) ? RFE_ERR_NULL : RFE_OK;
    for (i = 0u; (s == RFE_OK) && (i < n); ++i) {
        s = rfe_replay_step(st, &rows[i], &out[i]);
    }
    return s;
}

rfe_status_t rfe_replay_get_stats(const rfe_replay_state_t *st, rfe_replay_stats_t *stats)
{
    if ((st == NULL) || (stats == NULL)) {
        return RFE_ERR_NULL;
    }
    *stats = st->stats;
    return RFE_OK;
}

/* A whole log: begin, then every row (the one loop, rfe_replay_feed). */
static rfe_status_t run_log(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                            rfe_est_row_t *out, rfe_replay_stats_t *stats, size_t *bad_key,
                            int observer)
{
    static rfe_replay_state_t st; /* large; a whole-log run is single-threaded host code */
    rfe_status_t s;
    if ((ps == NULL) || (log == NULL) || (out == NULL) || (stats == NULL)) {
        return RFE_ERR_NULL;
    }
    memset(stats, 0, sizeof *stats);
    s = rfe_replay_begin(&st, ps, log, observer, bad_key);
    if (s == RFE_OK) {
        s = rfe_replay_feed(&st, log->rows, log->n_rows, out);
        *stats = st.stats;
    }
    return s;
}

rfe_status_t rfe_replay_run(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                            rfe_est_row_t *out, rfe_replay_stats_t *stats,
                            size_t *bad_key)
{
    return run_log(ps, log, out, stats, bad_key, 0);
}

rfe_status_t rfe_replay_run_observer(const rfe_param_set_t *ps, const rfe_sensor_log_t *log,
                                     rfe_est_row_t *out, rfe_replay_stats_t *stats,
                                     size_t *bad_key)
{
    return run_log(ps, log, out, stats, bad_key, 1);
}
