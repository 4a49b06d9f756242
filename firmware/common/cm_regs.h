/**
 * @file cm_regs.h
 * @brief The few Cortex-M system registers the example firmware and the PIL images touch
 *        (ARMv6-M / ARMv7-M architecture reference manuals, "System Control Space"); no
 *        vendor header needed.
 */
#ifndef FW_CM_REGS_H
#define FW_CM_REGS_H

#include <stdint.h>

/* SysTick: control/status, reload, current value (ARMv6-M and ARMv7-M). */
#define CM_SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define CM_SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define CM_SYST_CVR (*(volatile uint32_t *)0xE000E018u)
#define CM_SYST_CSR_ENABLE 0x1u
#define CM_SYST_CSR_TICKINT 0x2u
#define CM_SYST_CSR_CLKSOURCE 0x4u /* the processor clock */

/* Coprocessor access control (ARMv7-M with FP): CP10 and CP11 full access = 0xF << 20. */
#define CM_SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)
#define CM_SCB_CPACR_CP10_CP11 (0xFu << 20)

#endif /* FW_CM_REGS_H */
