/**
 * @file params_q31.c
 * @brief The two parameter presets in Q formats (integer tables) and their validation
 *        (rfe/params_q31.h). Integer operations only.
 */
#include "rfe/params_q31.h"

#include "rfe/component/fxmath.h"

#include "numerics/internal_q31.h"

/* The largest stale_omega and yaw_check (rfe_params_validate's RFE_LIMIT_OMEGA = 500 rad/s and
 * RFE_LIMIT_YAW_RATE = 10 rad/s) in their formats, Q22 and Q27: 500 * 2^22 and 10 * 2^27. */
#define STALE_OMEGA_MAX_Q22 2097152000
#define YAW_CHECK_MAX_Q27 1342177280
/* The largest valid_bound_k (rfe_params_validate's 10 sd) in Q24: 10 * 2^24. */
#define VALID_BOUND_K_MAX_Q24 167772160

/* ---- presets ------------------------------------------------------------------------------
 * The tables are rfe_params_to_q31_f64() of rfe_params_paper_f64() / rfe_params_default_f64()
 * (test/params/test_params_q31.c checks that bit for bit); the real value is in each comment. */

static const rfe_params_q31_t paper_q31 = {
    {
        119930880,  /* m = 1830 kg, Q16 */
        751619277,  /* Lf = 1.40 m, Q29 */
        885837005,  /* Lr = 1.65 m, Q29 */
        858993459,  /* Bf = 1.60 m, Q29 */
        858993459,  /* Br = 1.60 m, Q29 */
        174483046,  /* R = 0.325 m, Q29 */
        13246464,   /* J = 3234 kg m^2, Q12 */
        289910292,  /* hg = 0.54 m, Q29 */
        164584489,  /* g = 9.81 m/s^2, Q24 */
        429496730,  /* yf = 0.80 m, Q29 */
        429496730,  /* yr = 0.80 m, Q29 */
        150206507,  /* inv_m = 1/1830 1/kg, Q38 */
        118994765,  /* lf_J = 1.40/3234, Q38 */
        140243830,  /* lr_J = 1.65/3234, Q38 */
        67997009,   /* yf_J = 0.80/3234, Q38 */
        67997009,   /* yr_J = 0.80/3234, Q38 */
        159119770,  /* fz_static_f = 4855.95 N, Q15 */
        135010714,  /* fz_static_r = 4120.20 N, Q15 */
        169869312,  /* k_pitch = 162.00 kg, Q20 */
        350355456,  /* k_roll_f = 334.125 kg, Q20 */
        297271296   /* k_roll_r = 283.5 kg, Q20 */
    },
    {
        RFE_TYRE_PAPER,
        335544320,  /* Cx_n = 20, Q24 */
        251658240,  /* Cy_n = 15, Q24 */
        335544320,  /* cx = 20, Q24 */
        251658240,  /* cy = 15, Q24 */
        64424509,   /* eps = 0.015 s/m, Q32 */
        4194304,    /* v_min = 0.5 m/s, Q23 */
        751619277,  /* alpha_max = 1.4 rad, Q29 */
        27682406,   /* shape_Cx = 1.65, Q24 */
        0,          /* shape_Ex = 0, Q24 */
        21810381,   /* shape_Cy = 1.3, Q24 */
        0           /* shape_Ey = 0, Q24 */
    },
    {
        RFE_FILTER_SCKF,
        RFE_STRUCT_WHEELS,
        268435456,  /* mu0 = 0.5, Q29 */
        322122547,  /* sd0 = 0.3, Q30 */
        3221225,    /* q_mu = 0.003, Q30 */
        838861,     /* r_ax = 0.05 m/s^2, Q24 */
        838861,     /* r_ay = 0.05 m/s^2, Q24 */
        838861,     /* r_yaw_acc = 0.05 rad/s^2, Q24 */
        26843546,   /* mu_min = 0.05, Q29 */
        644245094,  /* mu_max = 1.2, Q29 */
        25165824,   /* v_est_min = 3 m/s, Q23 */
        0,          /* sd0_common = 0, Q30 */
        0,          /* q_common = 0, Q30 */
        10737418,   /* dt = 0.01 s, Q30 */
        0,          /* tau_v = 0 (off), Q26 */
        0,          /* sd_in_delta = 0, Q29 */
        0,          /* sd_in_vx = 0, Q23 */
        0,          /* sd_in_vy = 0, Q23 */
        0,          /* sd_in_yaw_rate = 0, Q27 */
        0,          /* sd_in_omega = 0, Q22 */
        0,          /* r_model_rel = 0, Q30 */
        0,          /* info_min = 0 (off), Q10 */
        0,          /* sd_max = 0 (off), Q30 */
        0,          /* sd_floor_rel = 0 (off), Q30 */
        0,          /* sd_valid = 0 (paper rule), Q30 */
        0,          /* rear_hold_k = 0 (off), Q24 */
        0,          /* jump_hold_k = 0 (off), Q24 */
        0,          /* jump_hold_len = 0, Q27 */
        0,          /* stale_omega = 0 (off), Q22 */
        0,          /* yaw_check = 0 (off), Q27 */
        0,          /* valid_bound_k = 0 (off), Q24 */
        1073741824  /* b_v = 1 (tau_v = 0), Q30 */
    },
    {
        0u,         /* enable = 0 (off in the paper preset; on in the default) */
        1u,         /* inflate = 1 */
        50u,        /* hold_steps = ceil(0.5 s / 0.01 s) */
        100u,       /* warmup_steps = ceil(1 s / 0.01 s) */
        21053761,   /* l_d = 0.01 / 0.51, Q30 */
        21053761,   /* l_m = 0.01 / 0.51, Q30 */
        55205878,   /* z_d_fire = z(1 - 1e-3 / 2) = 3.2905, Q24 */
        27596065,   /* z_d_clear = z(1 - 0.1 / 2) = 1.6449, Q24 */
        63163260,   /* z_m_fire = z(1 - 1e-3 / 12) = 3.7648, Q24 */
        40164316    /* z_m_clear = z(1 - 0.1 / 12) = 2.3940, Q24 */
    }};

rfe_status_t rfe_params_paper_q31(rfe_params_q31_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    *p = paper_q31;
    return RFE_OK;
}

rfe_status_t rfe_params_default_q31(rfe_params_q31_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    /* docs/ESTIMATOR.md, "default preset" column: the paper preset plus every addition. */
    *p = paper_q31;
    p->tyre.mode = RFE_TYRE_MAGIC;
    p->filter.structure = RFE_STRUCT_SIDES;
    p->filter.sd0 = 107374182;          /* 0.1, Q30 */
    p->filter.sd0_common = 322122547;   /* 0.3, Q30 */
    p->filter.q_mu = 2147484;           /* 0.002, Q30 */
    p->filter.q_common = 6442451;       /* 0.006, Q30 */
    p->filter.tau_v = 20132659;         /* 0.3 s, Q26 */
    p->filter.sd_in_delta = 536871;     /* 0.001 rad, Q29 */
    p->filter.sd_in_vx = 83886;         /* 0.01 m/s, Q23 */
    p->filter.sd_in_vy = 83886;         /* 0.01 m/s, Q23 */
    p->filter.sd_in_yaw_rate = 671089;  /* 0.005 rad/s, Q27 */
    p->filter.sd_in_omega = 209715;     /* 0.05 rad/s, Q22 */
    p->filter.r_model_rel = 53687091;   /* 0.05, Q30 */
    p->filter.info_min = 25600;         /* 25 1/mu^2, Q10 */
    p->filter.sd_max = 343597384;       /* 0.32, Q30 */
    p->filter.sd_floor_rel = 161061274; /* 0.15, Q30 */
    p->filter.sd_valid = 161061274;     /* 0.15, Q30 */
    p->filter.rear_hold_k = 33554432;   /* 2 sd, Q24 */
    p->filter.jump_hold_k = 33554432;   /* 2 sd, Q24 */
    p->filter.jump_hold_len = 201326592; /* 1.5 m, Q27 */
    p->filter.stale_omega = 1048576;    /* 0.25 rad/s, Q22 */
    p->filter.yaw_check = 13421773;     /* 0.1 rad/s, Q27 */
    p->filter.valid_bound_k = 50331648; /* 3 sd, Q24 */
    p->filter.b_v = 34636833;           /* 0.01 / 0.31, Q30 */
    p->monitor.enable = 1u;             /* docs/MONITOR.md: the model-validity monitor acts */
    return RFE_OK;
}

/* ---- recomputation of the derived constants -------------------------------------------------
 * A nonnegative real as mant * 2^-q with mant in [2^29, 2^30] (or 0): 30 significant bits, so
 * each product or quotient below adds at most 2^-29 relative error, and a derived constant
 * (at most five operations) is recomputed to better than 2^-26. */
typedef struct {
    int64_t mant;
    int q;
} pf_t;

/* Number of significant bits of v > 0. */
static int pf_bit_length(uint64_t v)
{
    uint64_t r = v;
    int n = 0;
    while (r != 0u) {
        r >>= 1;
        ++n;
    }
    return n;
}

/* v * 2^-q (0 <= v < 2^62) normalised; one rounding (half up) when v has more than 30 bits. */
static pf_t pf_make(int64_t v, int q)
{
    pf_t r = {0, 0};
    if (v > 0) {
        const int len = pf_bit_length((uint64_t)v);
        if (len > 30) {
            r.mant = rfe_fix_shr64_round(v, (unsigned int)len - 30u);
            r.q = q - (len - 30);
        } else {
            r.mant = v * rfe_q31_pow2(30u - (unsigned int)len);
            r.q = q + (30 - len);
        }
    }
    return r;
}

static pf_t pf_mul(pf_t a, pf_t b) { return pf_make(a.mant * b.mant, a.q + b.q); }

/* a / b for b > 0: the quotient of two mantissas in [2^29, 2^30] lies in [1/2, 2], so
 * round(a 2^29 / b) <= 2^30 and the division never saturates. */
static pf_t pf_div(pf_t a, pf_t b)
{
    uint32_t sat = 0u;
    int32_t quo = 0;
    /* b > 0 after the positivity checks; were it 0, the division would fail with quo = 0 */
    const rfe_status_t st = rfe_fix_div((int32_t)a.mant, (int32_t)b.mant, 29, &quo, &sat);
    (void)st;
    return pf_make((int64_t)quo, a.q - b.q + 29);
}

/* The value in Q(qt) as int64, or -1 when it exceeds INT32_MAX there. */
static int64_t pf_to_q(pf_t a, int qt)
{
    const int sh = qt - a.q;
    int64_t v;
    if (a.mant == 0) {
        v = 0;
    } else if (sh >= 0) {
        v = (sh > 2) ? -1 : (a.mant * rfe_q31_pow2((unsigned int)sh));
    } else {
        v = rfe_fix_shr64_round(a.mant, (unsigned int)(-sh));
    }
    return ((v < 0) || (v > (int64_t)RFE_FIX_MAX)) ? -1 : v;
}

/* The stored constant agrees with its recomputation: |stored - ref| <= ref 2^-13 + 2 LSB. */
static int agrees(rfe_fix_t stored, pf_t ref, int qt)
{
    const int64_t r = pf_to_q(ref, qt);
    const int64_t d = (int64_t)stored - r;
    return (r >= 0) && (((d < 0) ? -d : d) <= ((r / rfe_q31_pow2(13u)) + 2));
}

/* ---- validation ------------------------------------------------------------------------- */

static int is_pos_q31(rfe_fix_t x) { return x > 0; }
static int is_nonneg_q31(rfe_fix_t x) { return x >= 0; }
/* 0, or at least 16 significant bits (2^16 LSB); used on fields already checked >= 0. */
static int sig16(rfe_fix_t x) { return (x == 0) || (x >= 65536); }

/* The per-field rules of the checks below, as bit sets over a list of fields: > 0, >= 0, and
 * 0 or at least 16 significant bits (sig16). One loop checks a list against its rules (a
 * table instead of one inlined comparison per field: 261 B less of the Cortex-M0+'s flash,
 * docs/FIRMWARE.md "Headroom for the next ports"). Pure checks: their order does not matter. */
#define FIELD_POS 1u
#define FIELD_NONNEG 2u
#define FIELD_SIG16 4u
#define FIELD_POS16 (FIELD_POS | FIELD_SIG16)
#define FIELD_NONNEG16 (FIELD_NONNEG | FIELD_SIG16)

/* 1 when every v[i] (i < n) meets rule[i]. */
static int fields_ok(const rfe_fix_t *v, const uint8_t *rule, size_t n)
{
    int ok = 1;
    size_t i;
    for (i = 0u; i < n; ++i) {
        const uint32_t r = rule[i];
        /* Every rule is > 0 or >= 0 (FIELD_POS, else FIELD_NONNEG), so the sign test is one
         * choice, not two conditions of which one could never be shown to act (MC/DC). */
        const int sign_ok = ((r & FIELD_POS) != 0u) ? is_pos_q31(v[i]) : is_nonneg_q31(v[i]);
        if ((sign_ok == 0) || (((r & FIELD_SIG16) != 0u) && !sig16(v[i]))) {
            ok = 0;
        }
    }
    return ok;
}

/* The base fields: m, Lf, Lr, Bf, Br, J, g > 0, hg >= 0, each with 16 significant bits, R > 0. */
static int vehicle_base_ok(const rfe_vehicle_q31_t *v)
{
    static const uint8_t rule[9] = {FIELD_POS16, FIELD_POS16, FIELD_POS16,
                                    FIELD_POS16, FIELD_POS16, FIELD_POS,
                                    FIELD_POS16, FIELD_NONNEG16, FIELD_POS16};
    const rfe_fix_t val[9] = {v->m, v->Lf, v->Lr, v->Bf, v->Br, v->R, v->J, v->hg, v->g};
    return fields_ok(val, rule, 9u);
}

/* The derived constants: > 0, the three load-transfer gains >= 0, each with 16 significant
 * bits. */
static int vehicle_derived_sign_ok(const rfe_vehicle_q31_t *v)
{
    static const uint8_t rule[12] = {FIELD_POS16,    FIELD_POS16,    FIELD_POS16, FIELD_POS16,
                                     FIELD_POS16,    FIELD_POS16,    FIELD_POS16, FIELD_POS16,
                                     FIELD_POS16,    FIELD_NONNEG16, FIELD_NONNEG16,
                                     FIELD_NONNEG16};
    const rfe_fix_t val[12] = {v->yf,   v->yr,          v->inv_m,       v->lf_J,
                               v->lr_J, v->yf_J,        v->yr_J,        v->fz_static_f,
                               v->fz_static_r, v->k_pitch, v->k_roll_f, v->k_roll_r};
    return fields_ok(val, rule, 12u);
}

/* The recomputation of the constants that depend on the mass (inv_m, fz_static_f,
 * fz_static_r, k_pitch, k_roll_f, k_roll_r) from the (positive) base fields; shared by the
 * validation and rfe_params_set_mass_q31, so a mass set at run time always passes it. */
typedef struct {
    pf_t inv_m;
    pf_t fz_static_f;
    pf_t fz_static_r;
    pf_t k_pitch;
    pf_t k_roll_f;
    pf_t k_roll_r;
} mass_terms_t;

static mass_terms_t mass_terms(const rfe_vehicle_q31_t *v)
{
    const pf_t m = pf_make(v->m, RFE_FIX_Q_MASS);
    const pf_t lf = pf_make(v->Lf, RFE_FIX_Q_LEN);
    const pf_t lr = pf_make(v->Lr, RFE_FIX_Q_LEN);
    const pf_t bf = pf_make(v->Bf, RFE_FIX_Q_LEN);
    const pf_t br = pf_make(v->Br, RFE_FIX_Q_LEN);
    const pf_t hg = pf_make(v->hg, RFE_FIX_Q_LEN);
    const pf_t g = pf_make(v->g, RFE_FIX_Q_ACC);
    /* 2 La in Q29 as 2 (Lf + Lr) = Q28 of the sum; La itself in Q29 */
    const pf_t la = pf_make((int64_t)v->Lf + (int64_t)v->Lr, RFE_FIX_Q_LEN);
    const pf_t la2 = pf_make((int64_t)v->Lf + (int64_t)v->Lr, RFE_FIX_Q_LEN - 1);
    const pf_t mg = pf_mul(m, g);
    const pf_t mh = pf_mul(m, hg);
    mass_terms_t t;
    t.inv_m = pf_div(pf_make(1, 0), m);
    t.fz_static_f = pf_div(pf_mul(mg, lr), la2);
    t.fz_static_r = pf_div(pf_mul(mg, lf), la2);
    t.k_pitch = pf_div(mh, la2);
    t.k_roll_f = pf_div(pf_mul(mh, lr), pf_mul(la, bf));
    t.k_roll_r = pf_div(pf_mul(mh, lf), pf_mul(la, br));
    return t;
}

/* Each derived constant against its recomputation from the (positive) base fields. */
static int vehicle_derived_agree(const rfe_vehicle_q31_t *v)
{
    const pf_t lf = pf_make(v->Lf, RFE_FIX_Q_LEN);
    const pf_t lr = pf_make(v->Lr, RFE_FIX_Q_LEN);
    const pf_t J = pf_make(v->J, RFE_FIX_Q_INERTIA);
    const mass_terms_t t = mass_terms(v);

    return agrees(v->yf, pf_make(v->Bf, RFE_FIX_Q_LEN + 1), RFE_FIX_Q_LEN) &&
           agrees(v->yr, pf_make(v->Br, RFE_FIX_Q_LEN + 1), RFE_FIX_Q_LEN) &&
           agrees(v->inv_m, t.inv_m, RFE_FIX_Q_INV) &&
           agrees(v->lf_J, pf_div(lf, J), RFE_FIX_Q_INV) &&
           agrees(v->lr_J, pf_div(lr, J), RFE_FIX_Q_INV) &&
           agrees(v->yf_J, pf_div(pf_make(v->Bf, RFE_FIX_Q_LEN + 1), J), RFE_FIX_Q_INV) &&
           agrees(v->yr_J, pf_div(pf_make(v->Br, RFE_FIX_Q_LEN + 1), J), RFE_FIX_Q_INV) &&
           agrees(v->fz_static_f, t.fz_static_f, RFE_FIX_Q_FORCE) &&
           agrees(v->fz_static_r, t.fz_static_r, RFE_FIX_Q_FORCE) &&
           agrees(v->k_pitch, t.k_pitch, RFE_FIX_Q_KLOAD) &&
           agrees(v->k_roll_f, t.k_roll_f, RFE_FIX_Q_KLOAD) &&
           agrees(v->k_roll_r, t.k_roll_r, RFE_FIX_Q_KLOAD);
}

/* A Magic Formula shape (Q24): 1 < C < 2 (a peak, and a positive force beyond it),
 * -4 <= E < 1 (the curve rises monotonically to its peak; docs/ESTIMATOR.md). */
static int shape_ok_q31(rfe_fix_t C, rfe_fix_t E)
{
    const rfe_fix_t one = RFE_FIX_ONE(RFE_FIX_Q_STIFF);
    return (C > one) && (C < (2 * one)) && (E >= (-4 * one)) && (E < one);
}

/* The mode and the shape factors, checked in every mode (as rfe_params_validate; split from
 * tyre_ok_q31 to bound its cyclomatic complexity). */
static int tyre_mode_shape_ok_q31(const rfe_tyre_params_q31_t *t)
{
    return ((t->mode == RFE_TYRE_PAPER) || (t->mode == RFE_TYRE_ABSOLUTE) ||
            (t->mode == RFE_TYRE_MAGIC)) &&
           shape_ok_q31(t->shape_Cx, t->shape_Ex) && shape_ok_q31(t->shape_Cy, t->shape_Ey);
}

static int tyre_ok_q31(const rfe_tyre_params_q31_t *t)
{
    /* alpha_max < 1.5 rad keeps tan(alpha) bounded and inside the fixed-point tan's domain (RFE_FIX_TAN_LIMIT_Q29). */
    static const uint8_t rule[7] = {FIELD_POS, FIELD_POS,    FIELD_POS, FIELD_POS,
                                    FIELD_NONNEG, FIELD_POS, FIELD_POS};
    const rfe_fix_t val[7] = {t->Cx_n, t->Cy_n, t->cx, t->cy, t->eps, t->v_min, t->alpha_max};
    return tyre_mode_shape_ok_q31(t) && fields_ok(val, rule, 7u) &&
           (t->alpha_max < RFE_FIX_TAN_LIMIT_Q29);
}

/* Every field's own rule, sd0 to b_v in their order (the rows of rule and val match): sd0, q_mu,
 * the measurement noise, mu_max, dt and b_v > 0, every other field >= 0 (0 = off), dt, tau_v
 * and b_v with 16 significant bits (mu0 is checked against the bounds in filter_ok_q31). */
static int filter_fields_ok_q31(const rfe_filter_params_q31_t *f)
{
    static const uint8_t rule[29] = {
        FIELD_POS,    FIELD_POS,    FIELD_POS,    FIELD_POS,    FIELD_POS,      /* sd0 .. r_yaw_acc */
        FIELD_NONNEG, FIELD_POS,    FIELD_NONNEG,                               /* mu_min .. v_est_min */
        FIELD_NONNEG, FIELD_NONNEG, FIELD_POS16,  FIELD_NONNEG16,               /* sd0_common .. tau_v */
        FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG,   /* sd_in_* */
        FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG,   /* r_model_rel .. sd_valid */
        FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG, FIELD_NONNEG,   /* rear_hold_k .. yaw_check */
        FIELD_NONNEG, FIELD_POS16};                                             /* valid_bound_k, b_v */
    const rfe_fix_t val[29] = {
        f->sd0,           f->q_mu,         f->r_ax,        f->r_ay,           f->r_yaw_acc,
        f->mu_min,        f->mu_max,       f->v_est_min,
        f->sd0_common,    f->q_common,     f->dt,          f->tau_v,
        f->sd_in_delta,   f->sd_in_vx,     f->sd_in_vy,    f->sd_in_yaw_rate, f->sd_in_omega,
        f->r_model_rel,   f->info_min,     f->sd_max,      f->sd_floor_rel,   f->sd_valid,
        f->rear_hold_k,   f->jump_hold_k,  f->jump_hold_len, f->stale_omega,  f->yaw_check,
        f->valid_bound_k, f->b_v};
    return fields_ok(val, rule, 29u);
}

/* Enums in range; the fields' own rules; the mu bounds. */
static int filter_ok_q31(const rfe_filter_params_q31_t *f)
{
    return ((f->kind == RFE_FILTER_SCKF) || (f->kind == RFE_FILTER_CKF)) &&
           ((f->structure == RFE_STRUCT_WHEELS) || (f->structure == RFE_STRUCT_SIDES)) &&
           filter_fields_ok_q31(f) && (f->mu_min < f->mu_max) && (f->mu0 >= f->mu_min) &&
           (f->mu0 <= f->mu_max);
}

/* The upper bounds of the docs/ESTIMATOR.md additions (their signs and significant bits are
 * filter_fields_ok_q31's): step 9's stale-wheel-speed move <= RFE_LIMIT_OMEGA, the yaw-rate
 * check's threshold <= RFE_LIMIT_YAW_RATE, the bound margin <= 10 sd (as rfe_params_validate),
 * the gain b_v <= 1. */
static int additions_ok_q31(const rfe_filter_params_q31_t *f)
{
    return (f->stale_omega <= STALE_OMEGA_MAX_Q22) && (f->yaw_check <= YAW_CHECK_MAX_Q27) &&
           (f->valid_bound_k <= VALID_BOUND_K_MAX_Q24) && (f->b_v <= RFE_FIX_ONE(RFE_FIX_Q_DT));
}

/* b_v = dt / (tau_v + dt), with tau_v (Q26) brought to Q30: the sum fits int64. */
static int gain_agrees(const rfe_filter_params_q31_t *f)
{
    const pf_t dt = pf_make(f->dt, RFE_FIX_Q_DT);
    const pf_t den =
        pf_make(((int64_t)f->tau_v *
                 rfe_q31_pow2((unsigned int)RFE_FIX_Q_DT - (unsigned int)RFE_FIX_Q_TAU)) +
                    (int64_t)f->dt,
                RFE_FIX_Q_DT);
    return agrees(f->b_v, pf_div(dt, den), RFE_FIX_Q_DT);
}

/* The CKF runs only the paper-compatible subset (as rfe_params_validate). */
static int ckf_subset_ok_q31(const rfe_filter_params_q31_t *f)
{
    return (f->kind != RFE_FILTER_CKF) ||
           ((f->structure == RFE_STRUCT_WHEELS) && (f->sd0_common == 0) && (f->q_common == 0) &&
            (f->tau_v == 0) && (f->sd_in_delta == 0) && (f->sd_in_vx == 0) &&
            (f->sd_in_vy == 0) && (f->sd_in_yaw_rate == 0) && (f->sd_in_omega == 0) &&
            (f->r_model_rel == 0) && (f->info_min == 0) && (f->sd_max == 0) &&
            (f->sd_floor_rel == 0));
}

/* One test's quantiles: 0 < z_clear < z_fire <= RFE_FIX_MON_Z_MAX. */
static int quantiles_ok_q31(rfe_fix_t z_fire, rfe_fix_t z_clear)
{
    return (z_clear > 0) && (z_clear < z_fire) && (z_fire <= RFE_FIX_MON_Z_MAX);
}

/* An EWMA weight with 16 significant bits, below 1: [2^-14, 1) in Q30. */
static int weight_ok_q31(rfe_fix_t l)
{
    return is_pos_q31(l) && sig16(l) && (l < RFE_FIX_ONE(RFE_FIX_Q_MON_L));
}

rfe_status_t rfe_monitor_params_validate_q31(const rfe_monitor_params_q31_t *mp)
{
    if (mp == NULL) {
        return RFE_ERR_NULL;
    }
    if ((mp->enable > 1u) || (mp->inflate > 1u) || (mp->hold_steps > (uint32_t)INT32_MAX) ||
        (mp->warmup_steps > (uint32_t)INT32_MAX) || !weight_ok_q31(mp->l_d) ||
        !weight_ok_q31(mp->l_m) || !quantiles_ok_q31(mp->z_d_fire, mp->z_d_clear) ||
        !quantiles_ok_q31(mp->z_m_fire, mp->z_m_clear)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}

/* The monitor's constants, and the SCKF when it is on (it reads the SCKF's innovations). */
static int monitor_ok_q31(const rfe_monitor_params_q31_t *m, rfe_filter_kind_t kind)
{
    return (rfe_monitor_params_validate_q31(m) == RFE_OK) &&
           ((m->enable == 0u) || (kind == RFE_FILTER_SCKF));
}

rfe_status_t rfe_params_validate_q31(const rfe_params_q31_t *p)
{
    if (p == NULL) {
        return RFE_ERR_NULL;
    }
    /* The recomputations divide by base fields: only after those are known positive. */
    if (!vehicle_base_ok(&p->vehicle) || !vehicle_derived_sign_ok(&p->vehicle) ||
        !vehicle_derived_agree(&p->vehicle) || !tyre_ok_q31(&p->tyre) ||
        !filter_ok_q31(&p->filter) || !additions_ok_q31(&p->filter) || !gain_agrees(&p->filter) ||
        !ckf_subset_ok_q31(&p->filter) || !monitor_ok_q31(&p->monitor, p->filter.kind)) {
        return RFE_ERR_PARAM;
    }
    return RFE_OK;
}

/* A constant in Q(qt) from its recomputation; -1 (refused by the validation's sign checks)
 * when it leaves int32 there. */
static rfe_fix_t mass_term_q(pf_t a, int qt)
{
    const int64_t v = pf_to_q(a, qt);
    return (v < 0) ? -1 : (rfe_fix_t)v;
}

rfe_status_t rfe_params_set_lateral_tyre_q31(rfe_params_q31_t *p, rfe_fix_t cy, rfe_fix_t shape_Cy,
                                             rfe_fix_t shape_Ey, rfe_fix_t r_model_rel)
{
    rfe_status_t st = RFE_ERR_NULL;
    if (p != NULL) {
        const rfe_tyre_params_q31_t tyre_was = p->tyre;
        const rfe_fix_t r_was = p->filter.r_model_rel;
        p->tyre.cy = cy;
        p->tyre.shape_Cy = shape_Cy;
        p->tyre.shape_Ey = shape_Ey;
        p->filter.r_model_rel = r_model_rel;
        st = rfe_params_validate_q31(p);
        if (st != RFE_OK) {
            p->tyre = tyre_was; /* an invalid result leaves p as it was */
            p->filter.r_model_rel = r_was;
        }
    }
    return st;
}

rfe_status_t rfe_params_set_mass_q31(rfe_params_q31_t *p, rfe_fix_t m)
{
    rfe_status_t st = RFE_ERR_NULL;
    if (p != NULL) {
        const rfe_vehicle_q31_t was = p->vehicle;
        p->vehicle.m = m;
        if (vehicle_base_ok(&p->vehicle) != 0) { /* the recomputation divides by base fields */
            const mass_terms_t t = mass_terms(&p->vehicle);
            p->vehicle.inv_m = mass_term_q(t.inv_m, RFE_FIX_Q_INV);
            p->vehicle.fz_static_f = mass_term_q(t.fz_static_f, RFE_FIX_Q_FORCE);
            p->vehicle.fz_static_r = mass_term_q(t.fz_static_r, RFE_FIX_Q_FORCE);
            p->vehicle.k_pitch = mass_term_q(t.k_pitch, RFE_FIX_Q_KLOAD);
            p->vehicle.k_roll_f = mass_term_q(t.k_roll_f, RFE_FIX_Q_KLOAD);
            p->vehicle.k_roll_r = mass_term_q(t.k_roll_r, RFE_FIX_Q_KLOAD);
        }
        st = rfe_params_validate_q31(p);
        if (st != RFE_OK) {
            p->vehicle = was; /* an invalid result leaves p as it was */
        }
    }
    return st;
}
