/**
 * @file startup_cm.c
 * @brief Minimal Cortex-M start-up in C: the vector table, the reset handler and default
 *        fault handlers. One file for every core of the firmware build (ARMv6-M, ARMv7-M).
 *
 * Reset: enable the FPU when the image is built for one (CPACR CP10/CP11 full access,
 * before any floating-point instruction runs, else the first one raises a NOCP usage
 * fault), copy .data from flash to RAM, zero .bss, then
 *  - main() (the example firmware), or
 *  - with STARTUP_NEWLIB_CRT0 (the PIL images): newlib's semihosting crt0 `_start`
 *    (--specs=rdimon.specs), which sets up the C library and the command line, calls main
 *    and reports its return value to the debugger (QEMU: its exit status).
 * A fault never returns: under semihosting it reports "run-time error" (QEMU exits with
 * status 1), else it parks the core for the debugger.
 * The linker script (firmware/ld/sections.ld) provides _estack, _sidata, _sdata, _edata,
 * _sbss and _ebss.
 */
#include <stdint.h>

#include "cm_regs.h"

extern uint32_t _estack;
extern uint32_t _sidata;
extern uint32_t _sdata;
extern uint32_t _edata;
extern uint32_t _sbss;
extern uint32_t _ebss;

void Reset_Handler(void);
void Default_Handler(void);

#if defined(STARTUP_NEWLIB_CRT0)
extern void _start(void);
#else
extern int main(void);
#endif

/* Weak hooks an application overrides (the example firmware: SysTick_Handler). */
void NMI_Handler(void) __attribute__((weak, alias("Default_Handler")));
void HardFault_Handler(void) __attribute__((weak, alias("Default_Handler")));
void SVC_Handler(void) __attribute__((weak, alias("Default_Handler")));
void PendSV_Handler(void) __attribute__((weak, alias("Default_Handler")));
void SysTick_Handler(void) __attribute__((weak, alias("Default_Handler")));

typedef void (*fw_vector_t)(void);

/** Initial stack pointer, then the 15 system exception vectors (ARMv6-M leaves the
 *  ARMv7-M fault vectors reserved: they are never taken there). No device interrupts. */
typedef struct {
    uint32_t *initial_sp;
    fw_vector_t vector[15];
} fw_vector_table_t;

__attribute__((section(".isr_vector"), used)) const fw_vector_table_t fw_vector_table = {
    &_estack,
    {
        Reset_Handler,     /* 1 reset */
        NMI_Handler,       /* 2 NMI */
        HardFault_Handler, /* 3 hard fault */
        Default_Handler,   /* 4 MemManage (ARMv7-M) */
        Default_Handler,   /* 5 BusFault (ARMv7-M) */
        Default_Handler,   /* 6 UsageFault (ARMv7-M) */
        0, 0, 0, 0,        /* 7-10 reserved */
        SVC_Handler,       /* 11 SVCall */
        Default_Handler,   /* 12 debug monitor (ARMv7-M) */
        0,                 /* 13 reserved */
        PendSV_Handler,    /* 14 PendSV */
        SysTick_Handler,   /* 15 SysTick */
    },
};

void Default_Handler(void)
{
#if defined(STARTUP_NEWLIB_CRT0)
    /* Semihosting SYS_EXIT (0x18) with ADP_Stopped_RunTimeErrorUnknown (0x20023). */
    __asm__ volatile("movs r0, #0x18\n\t"
                     "ldr r1, =0x20023\n\t"
                     "bkpt 0xab" ::: "r0", "r1", "memory");
#endif
    for (;;) {
    }
}

void Reset_Handler(void)
{
    uint32_t *src = &_sidata;
    uint32_t *dst;
#if defined(__ARM_FP)
    CM_SCB_CPACR |= CM_SCB_CPACR_CP10_CP11;
    __asm__ volatile("dsb\n\tisb" ::: "memory");
#endif
    for (dst = &_sdata; dst < &_edata; ++dst) {
        *dst = *src;
        ++src;
    }
    for (dst = &_sbss; dst < &_ebss; ++dst) {
        *dst = 0u;
    }
#if defined(STARTUP_NEWLIB_CRT0)
    _start();
#else
    (void)main();
#endif
    for (;;) {
    }
}
