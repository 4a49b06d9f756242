/**
 * @file main.c
 * @brief Example firmware: the friction estimator in a bare-metal image, static state, one
 *        step per 10 ms tick (SysTick at 100 Hz), the way an application integrates it.
 *
 * Built by `make firmware` for the Cortex-M4F (float32: rfe_friction_*_f32; fixed point with
 * FW_EXAMPLE_Q31: rfe_friction_*_q31) and the Cortex-M0+ (fixed point), linked with
 * firmware/common/startup_cm.c and a part's linker script (firmware/ld/). What to replace:
 *  - board_read_sample(): your sensor acquisition (CAN decoding, IMU, wheel-speed capture)
 *    into SI units (float) or the Q formats of rfe_sample_q31_t (rfe/component/tyre_q31.h);
 *  - board_publish(): hand the estimate to the rest of the application;
 *  - FW_CORE_HZ: the core clock SysTick counts (here 100 MHz).
 * Both hooks are weak: the defaults feed a constant 20 m/s cruise and keep the last estimate
 * in g_estimate, so the image links and runs on its own.
 *
 * Everything is static (no heap, no RTOS): the estimator state (g_est, sizeof in the README
 * table), one sample, one estimate. The step runs in thread mode, not in the interrupt; an
 * overrun (a step longer than the tick) is counted in g_overruns and the missed tick
 * skipped, never queued.
 */
#include <stdint.h>

#include "cm_regs.h"

#if defined(FW_EXAMPLE_Q31)
#include "rfe/friction_q31.h"
typedef rfe_friction_q31_t fw_estimator_t;
typedef rfe_params_q31_t fw_params_t;
typedef rfe_sample_q31_t fw_sample_t;
typedef rfe_estimate_q31_t fw_estimate_t;
#define FW_PARAMS_DEFAULT rfe_params_default_q31
#define FW_INIT rfe_friction_init_q31
#define FW_STEP rfe_friction_step_q31
#define FW_GET rfe_friction_get_q31
#else
#include "rfe/friction.h"
typedef rfe_friction_t fw_estimator_t;
typedef rfe_params_t fw_params_t;
typedef rfe_sample_t fw_sample_t;
typedef rfe_estimate_t fw_estimate_t;
#define FW_PARAMS_DEFAULT rfe_params_default_f32
#define FW_INIT rfe_friction_init_f32
#define FW_STEP rfe_friction_step_f32
#define FW_GET rfe_friction_get_f32
#endif

#ifndef FW_CORE_HZ
#define FW_CORE_HZ 100000000u /**< SysTick clock = core clock [Hz] */
#endif
#define FW_STEP_HZ 100u /**< estimator rate; params.filter.dt must be 1 / FW_STEP_HZ */

/* The only state: static, zero-initialised, sized at compile time. */
static fw_estimator_t g_est;
static volatile uint32_t g_ticks;
volatile uint32_t g_overruns;
volatile uint32_t g_rejected;
fw_estimate_t g_estimate;

int board_read_sample(fw_sample_t *s);
void board_publish(const fw_estimate_t *e);
int main(void);

void SysTick_Handler(void)
{
    g_ticks = g_ticks + 1u;
}

/** Default sensor hook: straight-line cruise at 20 m/s (wheel speeds 20 / 0.325 m). */
__attribute__((weak)) int board_read_sample(fw_sample_t *s)
{
    uint32_t w;
#if defined(FW_EXAMPLE_Q31)
    s->delta = 0;
    s->vx = 167772160;  /* 20 m/s, Q23 */
    s->vy = 0;
    s->yaw_rate = 0;
    s->yaw_acc = 0;
    s->ax = 0;
    s->ay = 0;
    for (w = 0u; w < (uint32_t)RFE_WHEELS; ++w) {
        s->omega[w] = 258111212; /* 61.538 rad/s, Q22 */
    }
#else
    s->delta = 0.0f;
    s->vx = 20.0f;
    s->vy = 0.0f;
    s->yaw_rate = 0.0f;
    s->yaw_acc = 0.0f;
    s->ax = 0.0f;
    s->ay = 0.0f;
    for (w = 0u; w < (uint32_t)RFE_WHEELS; ++w) {
        s->omega[w] = 61.538462f;
    }
#endif
    return 0;
}

/** Default output hook: keep the estimate where a debugger (or the application) reads it. */
__attribute__((weak)) void board_publish(const fw_estimate_t *e)
{
    g_estimate = *e;
}

static void systick_start(void)
{
    CM_SYST_RVR = (FW_CORE_HZ / FW_STEP_HZ) - 1u;
    CM_SYST_CVR = 0u;
    CM_SYST_CSR = CM_SYST_CSR_ENABLE | CM_SYST_CSR_TICKINT | CM_SYST_CSR_CLKSOURCE;
}

int main(void)
{
    fw_params_t p;
    uint32_t done;

    /* The library's default configuration; a calibration would overwrite members here. Every
     * status must be checked (the functions are warn_unused_result). */
    if (FW_PARAMS_DEFAULT(&p) != RFE_OK || FW_INIT(&g_est, &p) != RFE_OK) {
        for (;;) {
            /* invalid parameters: stay here (a real application reports it) */
        }
    }
    if (FW_GET(&g_est, &g_estimate) != RFE_OK) {
        g_rejected = g_rejected + 1u;
    }
    systick_start();
    done = g_ticks;
    for (;;) {
        fw_sample_t s;
        fw_estimate_t e;
        while (g_ticks == done) {
            __asm__ volatile("wfi");
        }
        done = done + 1u;
        if (board_read_sample(&s) == 0) {
            /* An error status leaves the estimator unchanged and reports the previous
             * estimate with valid = 0: publish it all the same. */
            if (rfe_status_is_error(FW_STEP(&g_est, &s, &e))) {
                g_rejected = g_rejected + 1u;
            }
            board_publish(&e);
        }
        if (g_ticks != done) { /* the step took longer than one tick */
            g_overruns = g_overruns + 1u;
            done = g_ticks;
        }
    }
}
