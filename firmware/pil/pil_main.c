/**
 * @file pil_main.c
 * @brief Processor-in-the-loop image: an estimator over a whole sensor log on an emulated
 *        Cortex-M (QEMU mps2-an386 / mps2-an385 / microbit), results written through
 *        semihosting; the same program built for the host is a reference it is compared with.
 *
 * Built per core, variant and estimator by mk/firmware.mk with the data that
 * src/host/pil/pil_gen.c generated from the log (pil_data.h: parameters and samples as the
 * host replay sees them), newlib's semihosting start-up (--specs=rdimon.specs) and
 * firmware/common/startup_cm.c. The estimator entry (one #if block below each):
 *   default       the friction estimator, rfe_friction_*_f32;
 *   PIL_Q31       the friction estimator, rfe_friction_*_q31;
 *   PIL_PIPELINE  the composed pipeline, rfe_pipeline_*_f32 (the velocity observer, then the
 *                 friction estimator on its outputs);
 *   PIL_PIPELINE with PIL_Q31  the composed pipeline in fixed point, rfe_pipeline_*_q31.
 *   PIL_MASS_GRADE  the mass and grade estimator, rfe_mass_grade_*_f32;
 *   PIL_MASS_GRADE with PIL_Q31  its fixed-point twin, rfe_mass_grade_*_q31;
 *   PIL_TYRE_ID     the tyre identifier, rfe_tyre_id_*_f32 with its default parameters and
 *                   seed 1 (float only; RFE_TID_N particles); with PIL_TID_SCKF its
 *                   sigma-point filter (tid_filter = sckf, docs/TYRE_ID.md §15), and with
 *                   PIL_TID_DSTATE too the steering angle as its state (§15.7).
 * Another estimator is one more block giving pil_estimator_t, pil_output_t, pil_init,
 * PIL_STEP_CALL and put_output. PIL_HOST: the host build of the
 * same program (no stack painting; rfe_real_t may be double, printed as 16 hex digits). The
 * command line (QEMU -append) may give the number of samples to run; default all.
 *
 * Output (stdout, one line each; scripts/firmware/firmware_pil.py parses it):
 *   R <row> <status> <valid bits> <sat> <mu x4> <sd x4>   every step; mu and sd as the raw
 *       words in hex (Q29 / Q30, or the bit patterns of rfe_real_t): exact
 *   V <row> <status> <flags> <sat> <vx> <vy> <beta> <yaw_acc> <sd_vx> <sd_vy> <sd_beta>
 *       <sd_yaw_acc>   every step of an entry with the velocity observer, after its R line:
 *       the observer's status, flags and saturations (0 in float), its values as raw words
 *       (Q23 / Q29 / Q24, or the bits of rfe_real_t); the R line's sat is the friction
 *       estimator's (in the fixed-point pipeline with the input-noise norm's)
 *   A <row> <status> <flags> <value>...   every step of PIL_MASS_GRADE or PIL_TYRE_ID instead
 *       of R: the step's status, its flags (the tyre identifier's RFE_TID_* bits; the mass
 *       and grade estimator's mismatch flag, §4.8; its saturation count in fixed point) and
 *       every output as raw bits: mass, sd_mass, grade, sd_grade, v, sd_v, q_mv, e_ax (in
 *       fixed point Q14, Q14, Q29, Q29, Q24, Q24, the int64 Q28, Q24, then the mismatch flag
 *       as a word); or the 17 means, the 17 sds and n_eff
 *   S <bytes>   the deepest stack any step used, measured: before each step the 4 KB below
 *               the stack pointer are painted, after it the lowest overwritten word is found
 *               (0 on the host)
 *   E <rows>    end of the run
 * Every step is bracketed by calls to pil_step_begin() and pil_step_end(), two empty
 * functions whose addresses the instruction-count run looks for in QEMU's execution trace.
 * Exit status: 0, or 2 when the estimator does not initialise.
 */
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include "pil_data.h"

#define PIL_PAINT_WORDS 1024u   /* 4 KB painted below the stack pointer before each step */
#define PIL_PAINT 0xC5A5C5A5u

/* no_icf: under link-time optimisation the two empty bodies would be folded into one
 * function, one address for both markers (make firmware-opt's -flto builds). */
void pil_step_begin(void) __attribute__((noinline, no_icf));
void pil_step_end(void) __attribute__((noinline, no_icf));
int main(int argc, char **argv);

static void put_char(char c);
static void put_dec(uint32_t v);
static void put_bits(const void *p, uint32_t bytes);
#if !defined(PIL_MASS_GRADE) && !defined(PIL_TYRE_ID)
static void put_friction(uint32_t row, rfe_status_t st, uint32_t sat, const void *mu,
                         const void *sd, const uint8_t *valid, uint32_t real_bytes);
#endif
#if defined(PIL_PIPELINE)
static void put_velocity(uint32_t row, rfe_status_t st, uint32_t flags, uint32_t sat);
#endif
#if (defined(PIL_MASS_GRADE) && !defined(PIL_Q31)) || defined(PIL_TYRE_ID)
static void put_aux(uint32_t row, rfe_status_t st, uint32_t flags, const rfe_real_t *v, uint32_t n);
#endif

#if defined(PIL_MASS_GRADE) && defined(PIL_Q31)
typedef rfe_mass_grade_q31_t pil_estimator_t;
typedef rfe_mass_grade_estimate_q31_t pil_output_t;
static pil_estimator_t g_est;
#define PIL_STEP_CALL(i, o) rfe_mass_grade_step_q31(&g_est, &pil_mg_inputs[(i)], (o))
static rfe_status_t pil_init(void)
{
    return rfe_mass_grade_init_q31(&g_est, &pil_mg_params);
}
static void put_output(uint32_t i, rfe_status_t st, const pil_output_t *o)
{
    const uint32_t b = (uint32_t)sizeof(rfe_fix_t);
    put_char('A');
    put_dec(i);
    put_dec((uint32_t)st);
    put_dec(o->sat);
    put_bits(&o->mass, b);
    put_bits(&o->sd_mass, b);
    put_bits(&o->grade, b);
    put_bits(&o->sd_grade, b);
    put_bits(&o->v, b);
    put_bits(&o->sd_v, b);
    put_bits(&o->q_mv, (uint32_t)sizeof o->q_mv);
    put_bits(&o->e_ax, b);                              /* §4.8 the monitor's EMA */
    put_bits(&o->mismatch, (uint32_t)sizeof o->mismatch); /* and its flag */
    put_char('\n');
}
#elif defined(PIL_MASS_GRADE)
typedef rfe_mass_grade_t pil_estimator_t;
typedef rfe_mass_grade_estimate_t pil_output_t;
static pil_estimator_t g_est;
#define PIL_STEP_CALL(i, o) rfe_mass_grade_step(&g_est, &pil_mg_inputs[(i)], (o))
static rfe_status_t pil_init(void)
{
    return rfe_mass_grade_init(&g_est, &pil_mg_params);
}
static void put_output(uint32_t i, rfe_status_t st, const pil_output_t *o)
{
    /* the mismatch flag (§4.8) as the line's discrete flags, the monitor's EMA as a value */
    const rfe_real_t v[8] = {o->mass, o->sd_mass, o->grade, o->sd_grade, o->v, o->sd_v, o->q_mv, o->e_ax};
    put_aux(i, st, o->mismatch, v, 8u);
}
#elif defined(PIL_TYRE_ID)
typedef rfe_tyre_id_t pil_estimator_t;
typedef rfe_tyre_id_estimate_t pil_output_t;
static pil_estimator_t g_est;
#define PIL_STEP_CALL(i, o) rfe_tyre_id_step(&g_est, &pil_tid_samples[(i)], (o))
static rfe_status_t pil_init(void)
{
    rfe_tyre_id_params_t tp;
    const rfe_status_t st = rfe_tyre_id_params_default(&tp);
#if defined(PIL_TID_SCKF)
    tp.filter = RFE_TID_SCKF;
#endif
#if defined(PIL_TID_DSTATE)
    tp.delta_state_q = 0.04f; /* delta as the SCKF's state (TYRE_ID.md §15.7) */
#endif
    return (st != RFE_OK) ? st : rfe_tyre_id_init(&g_est, &tp, &pil_params, 1u);
}
static void put_output(uint32_t i, rfe_status_t st, const pil_output_t *o)
{
    rfe_real_t v[2u * (uint32_t)RFE_TID_OUTPUTS + 1u];
    memcpy(v, o->mean, sizeof o->mean);
    memcpy(&v[RFE_TID_OUTPUTS], o->sd, sizeof o->sd);
    v[2u * (uint32_t)RFE_TID_OUTPUTS] = o->n_eff;
    put_aux(i, st, o->flags, v, 2u * (uint32_t)RFE_TID_OUTPUTS + 1u);
}
#elif defined(PIL_PIPELINE) && defined(PIL_Q31)
typedef rfe_pipeline_q31_t pil_estimator_t;
typedef rfe_pipeline_out_q31_t pil_output_t;
static pil_estimator_t g_est;
#define PIL_STEP_CALL(i, o) rfe_pipeline_step_q31(&g_est, &pil_inputs[(i)], (o))
static rfe_status_t pil_init(void)
{
    return rfe_pipeline_init_q31(&g_est, &pil_params, &pil_velocity_params);
}
static void put_output(uint32_t i, rfe_status_t st, const pil_output_t *o)
{
    const rfe_velocity_estimate_q31_t *v = &o->velocity;
    const uint32_t b = (uint32_t)sizeof(rfe_fix_t);
    put_friction(i, st, o->friction.sat, o->friction.mu, o->friction.sd, o->friction.valid, b);
    put_velocity(i, v->status, v->flags, v->sat);
    put_bits(&v->vx, b);
    put_bits(&v->vy, b);
    put_bits(&v->beta, b);
    put_bits(&v->yaw_acc, b);
    put_bits(&v->sd_vx, b);
    put_bits(&v->sd_vy, b);
    put_bits(&v->sd_beta, b);
    put_bits(&v->sd_yaw_acc, b);
    put_char('\n');
}
#elif defined(PIL_PIPELINE)
typedef rfe_pipeline_t pil_estimator_t;
typedef rfe_pipeline_out_t pil_output_t;
static pil_estimator_t g_est;
#define PIL_STEP_CALL(i, o) rfe_pipeline_step(&g_est, &pil_inputs[(i)], (o))
static rfe_status_t pil_init(void)
{
    return rfe_pipeline_init(&g_est, &pil_params, &pil_velocity_params);
}
static void put_output(uint32_t i, rfe_status_t st, const pil_output_t *o)
{
    const rfe_velocity_estimate_t *v = &o->velocity;
    const uint32_t b = (uint32_t)sizeof(rfe_real_t);
    put_friction(i, st, 0u, o->friction.mu, o->friction.sd, o->friction.valid, b);
    put_velocity(i, v->status, v->flags, 0u);
    put_bits(&v->vx, b);
    put_bits(&v->vy, b);
    put_bits(&v->beta, b);
    put_bits(&v->yaw_acc, b);
    put_bits(&v->sd_vx, b);
    put_bits(&v->sd_vy, b);
    put_bits(&v->sd_beta, b);
    put_bits(&v->sd_yaw_acc, b);
    put_char('\n');
}
#elif defined(PIL_Q31)
typedef rfe_friction_q31_t pil_estimator_t;
typedef rfe_estimate_q31_t pil_output_t;
static pil_estimator_t g_est;
#define PIL_STEP_CALL(i, o) rfe_friction_step_q31(&g_est, &pil_samples[(i)], (o))
static rfe_status_t pil_init(void)
{
    return rfe_friction_init_q31(&g_est, &pil_params);
}
static void put_output(uint32_t i, rfe_status_t st, const pil_output_t *e)
{
    put_friction(i, st, e->sat, e->mu, e->sd, e->valid, (uint32_t)sizeof e->mu[0]);
}
#else
typedef rfe_friction_t pil_estimator_t;
typedef rfe_estimate_t pil_output_t;
static pil_estimator_t g_est;
#define PIL_STEP_CALL(i, o) rfe_friction_step(&g_est, &pil_samples[(i)], (o))
static rfe_status_t pil_init(void)
{
    return rfe_friction_init(&g_est, &pil_params);
}
static void put_output(uint32_t i, rfe_status_t st, const pil_output_t *e)
{
    put_friction(i, st, 0u, e->mu, e->sd, e->valid, (uint32_t)sizeof(rfe_real_t));
}
#endif

static char g_out[4096];
static uint32_t g_out_len;

void pil_step_begin(void) { __asm__ volatile("" ::: "memory"); }
void pil_step_end(void) { __asm__ volatile("" ::: "memory"); }

static void flush(void)
{
    if (g_out_len > 0u) {
        (void)write(1, g_out, g_out_len);
        g_out_len = 0u;
    }
}

static void put_char(char c)
{
    if (g_out_len == (uint32_t)sizeof g_out) {
        flush();
    }
    g_out[g_out_len] = c;
    ++g_out_len;
}

/* The bytes at @p p (4 or 8) as one hexadecimal number: the exact bits of a word. */
static void put_bits(const void *p, uint32_t bytes)
{
    static const char digits[] = "0123456789abcdef";
    uint64_t v;
    int s;
    if (bytes == 8u) {
        memcpy(&v, p, sizeof v);
    } else {
        uint32_t w;
        memcpy(&w, p, sizeof w);
        v = w;
    }
    put_char(' ');
    for (s = (int)(bytes * 8u) - 4; s >= 0; s -= 4) {
        put_char(digits[(v >> (uint32_t)s) & 0xFu]);
    }
}

static void put_dec(uint32_t v)
{
    char d[10];
    uint32_t n = 0u;
    put_char(' ');
    do {
        d[n] = (char)('0' + (int)(v % 10u));
        ++n;
        v /= 10u;
    } while (v != 0u);
    while (n > 0u) {
        --n;
        put_char(d[n]);
    }
}

#if !defined(PIL_MASS_GRADE) && !defined(PIL_TYRE_ID)
/* One R line: status, valid bits, saturations, mu and sd per wheel (each real_bytes long). */
static void put_friction(uint32_t row, rfe_status_t st, uint32_t sat, const void *mu,
                         const void *sd, const uint8_t *valid, uint32_t real_bytes)
{
    uint32_t w, bits = 0u;
    for (w = 0u; w < (uint32_t)RFE_WHEELS; ++w) {
        bits |= (valid[w] != 0u ? 1u : 0u) << w;
    }
    put_char('R');
    put_dec(row);
    put_dec((uint32_t)st);
    put_dec(bits);
    put_dec(sat);
    for (w = 0u; w < (uint32_t)RFE_WHEELS; ++w) {
        put_bits((const char *)mu + w * real_bytes, real_bytes);
    }
    for (w = 0u; w < (uint32_t)RFE_WHEELS; ++w) {
        put_bits((const char *)sd + w * real_bytes, real_bytes);
    }
    put_char('\n');
}
#endif

#if defined(PIL_PIPELINE)
/* The head of a V line: row, the observer's status, flags and saturations (its values
 * follow, put_bits each). */
static void put_velocity(uint32_t row, rfe_status_t st, uint32_t flags, uint32_t sat)
{
    put_char('V');
    put_dec(row);
    put_dec((uint32_t)st);
    put_dec(flags);
    put_dec(sat);
}
#endif

#if (defined(PIL_MASS_GRADE) && !defined(PIL_Q31)) || defined(PIL_TYRE_ID)
/* One A line: row, status, flags, then the n outputs as the bits of rfe_real_t. */
static void put_aux(uint32_t row, rfe_status_t st, uint32_t flags, const rfe_real_t *v, uint32_t n)
{
    uint32_t k;
    put_char('A');
    put_dec(row);
    put_dec((uint32_t)st);
    put_dec(flags);
    for (k = 0u; k < n; ++k) {
        put_bits(&v[k], (uint32_t)sizeof(rfe_real_t));
    }
    put_char('\n');
}
#endif

#if defined(PIL_HOST)
/* The host build measures no stack (the host's frames are not the target's). */
static const uint32_t *stack_pointer(void)
{
    return NULL;
}
static void paint_stack(void) {}
static uint32_t stack_used(const uint32_t *top)
{
    (void)top;
    return 0u;
}
#else
static uint32_t *g_paint_low;

static const uint32_t *stack_pointer(void)
{
    uint32_t *sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

/* Paints PIL_PAINT_WORDS words below this function's own frame (free stack: no interrupt
 * runs here) and remembers the lowest painted word. */
static void __attribute__((noinline)) paint_stack(void)
{
    uint32_t *p;
    uint32_t i;
    __asm__ volatile("mov %0, sp" : "=r"(p));
    p -= 16;
    for (i = 0u; i < PIL_PAINT_WORDS; ++i) {
        --p;
        *(volatile uint32_t *)p = PIL_PAINT;
    }
    g_paint_low = p;
}

/* Bytes between @p top (the caller's stack pointer at the step) and the lowest overwritten
 * painted word. */
static uint32_t stack_used(const uint32_t *top)
{
    const uint32_t *p = g_paint_low;
    while (p < top && *(const volatile uint32_t *)p == PIL_PAINT) {
        ++p;
    }
    return (uint32_t)((uintptr_t)top - (uintptr_t)p);
}
#endif

static uint32_t parse_count(const char *s)
{
    uint32_t v = 0u;
    while (*s >= '0' && *s <= '9') {
        v = v * 10u + (uint32_t)(*s - '0');
        ++s;
    }
    return v;
}

int main(int argc, char **argv)
{
    uint32_t n = pil_n_samples, i, deepest = 0u;
    if (argc > 1) {
        const uint32_t want = parse_count(argv[argc - 1]);
        if (want > 0u && want < n) {
            n = want;
        }
    }
    if (pil_init() != RFE_OK) {
        static const char msg[] = "pil: the estimator does not initialise\n";
        (void)write(2, msg, sizeof msg - 1u);
        return 2;
    }
    for (i = 0u; i < n; ++i) {
        pil_output_t o;
        rfe_status_t st;
        uint32_t used;
        const uint32_t *top = stack_pointer();
        memset(&o, 0, sizeof o);
        paint_stack();
        pil_step_begin();
        st = PIL_STEP_CALL(i, &o);
        pil_step_end();
        used = stack_used(top);
        deepest = used > deepest ? used : deepest;
        put_output(i, st, &o);
    }
    put_char('S');
    put_dec(deepest);
    put_char('\n');
    put_char('E');
    put_dec(n);
    put_char('\n');
    flush();
    return 0;
}
