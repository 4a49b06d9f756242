/**
 * @file pil_main.c
 * @brief Processor-in-the-loop image: the estimator over a whole sensor log on an emulated
 *        Cortex-M (QEMU mps2-an386 / mps2-an385), results written through semihosting.
 *
 * Built per core and variant by mk/firmware.mk (PIL_Q31: rfe_friction_*_q31, else the float32
 * rfe_friction_*_f32) with the data that src/host/pil/pil_gen.c generated from the log
 * (pil_data.h: parameters and samples as the host replay sees them), newlib's semihosting
 * start-up (--specs=rdimon.specs) and firmware/common/startup_cm.c. The command line
 * (QEMU -append) may give the number of samples to run; default all.
 *
 * Output (stdout, one line each; scripts/firmware/firmware_pil.py parses it):
 *   R <row> <status> <valid bits> <sat> <mu x4> <sd x4>   every step; mu and sd as the raw
 *       32-bit words in hex (Q29 / Q30, or the float32 bit patterns): exact
 *   S <bytes>   the deepest stack any step used, measured: before each step the 4 KB below
 *               the stack pointer are painted, after it the lowest overwritten word is found
 *   E <rows>    end of the run
 * Every step is bracketed by calls to pil_step_begin() and pil_step_end(), two empty
 * functions whose addresses the instruction-count run looks for in QEMU's execution trace.
 * Exit status: 0, or 2 when the estimator does not initialise.
 */
#include <stdint.h>
#include <string.h>
#include <unistd.h>

#include "pil_data.h"

#if defined(PIL_Q31)
typedef rfe_friction_q31_t pil_estimator_t;
typedef rfe_estimate_q31_t pil_estimate_t;
#define PIL_INIT rfe_friction_init_q31
#define PIL_STEP rfe_friction_step_q31
#else
typedef rfe_friction_t pil_estimator_t;
typedef rfe_estimate_t pil_estimate_t;
#define PIL_INIT rfe_friction_init_f32
#define PIL_STEP rfe_friction_step_f32
#endif

#define PIL_PAINT_WORDS 1024u   /* 4 KB painted below the stack pointer before each step */
#define PIL_PAINT 0xC5A5C5A5u

void pil_step_begin(void) __attribute__((noinline));
void pil_step_end(void) __attribute__((noinline));
int main(int argc, char **argv);

static pil_estimator_t g_est;
static char g_out[4096];
static uint32_t g_out_len;
static uint32_t *g_paint_low;

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

static void put_hex(uint32_t v)
{
    static const char digits[] = "0123456789abcdef";
    int s;
    put_char(' ');
    for (s = 28; s >= 0; s -= 4) {
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

static uint32_t word_of(const void *p)
{
    uint32_t w;
    memcpy(&w, p, sizeof w);
    return w;
}

static uint32_t *stack_pointer(void)
{
    uint32_t *sp;
    __asm__ volatile("mov %0, sp" : "=r"(sp));
    return sp;
}

/* Paints PIL_PAINT_WORDS words below this function's own frame (free stack: no interrupt
 * runs here) and remembers the lowest painted word. */
static void __attribute__((noinline)) paint_stack(void)
{
    uint32_t *p = stack_pointer() - 16;
    uint32_t i;
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
    uint32_t n = pil_n_samples, i, w, deepest = 0u;
    if (argc > 1) {
        const uint32_t want = parse_count(argv[argc - 1]);
        if (want > 0u && want < n) {
            n = want;
        }
    }
    if (PIL_INIT(&g_est, &pil_params) != RFE_OK) {
        static const char msg[] = "pil: the estimator does not initialise\n";
        (void)write(2, msg, sizeof msg - 1u);
        return 2;
    }
    for (i = 0u; i < n; ++i) {
        pil_estimate_t e;
        rfe_status_t st;
        uint32_t valid = 0u, sat = 0u, used;
        const uint32_t *top = stack_pointer();
        memset(&e, 0, sizeof e);
        paint_stack();
        pil_step_begin();
        st = PIL_STEP(&g_est, &pil_samples[i], &e);
        pil_step_end();
        used = stack_used(top);
        deepest = used > deepest ? used : deepest;
#if defined(PIL_Q31)
        sat = e.sat;
#endif
        for (w = 0u; w < (uint32_t)RFE_WHEELS; ++w) {
            valid |= (e.valid[w] != 0u ? 1u : 0u) << w;
        }
        put_char('R');
        put_dec(i);
        put_dec((uint32_t)st);
        put_dec(valid);
        put_dec(sat);
        for (w = 0u; w < (uint32_t)RFE_WHEELS; ++w) {
            put_hex(word_of(&e.mu[w]));
        }
        for (w = 0u; w < (uint32_t)RFE_WHEELS; ++w) {
            put_hex(word_of(&e.sd[w]));
        }
        put_char('\n');
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
