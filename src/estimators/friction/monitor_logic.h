/**
 * @file monitor_logic.h
 * @brief What the model-validity monitor's twins (monitor_flt.c, monitor_q31.c) decide alike,
 *        whatever their arithmetic (docs/MONITOR.md §2): the warm-up count and the
 *        hysteresis. Written once, so the twins cannot drift.
 */
#ifndef RFE_MONITOR_LOGIC_H
#define RFE_MONITOR_LOGIC_H

#include <stdint.h>

/* The count of steps seen after one more (saturating at UINT32_MAX). */
static inline uint32_t rfe_monitor_count_seen(uint32_t seen)
{
    uint32_t n = seen;
    if (n < UINT32_MAX) {
        ++n;
    }
    return n;
}

/* The hysteresis after the averages moved (docs/MONITOR.md §2 item 6): over != 0 when a
 * statistic exceeds its fire threshold, under != 0 when every statistic is below its clear
 * threshold. An exceedance fires and restarts the hold; while fired, the hold counts down
 * and the monitor clears once it is out and everything is under. */
static inline void rfe_monitor_hysteresis(uint32_t *fired, uint32_t *hold, uint32_t hold_steps,
                                          int over, int under)
{
    if (over != 0) {
        *fired = 1u;
        *hold = hold_steps;
    } else if (*fired != 0u) {
        const uint32_t h = *hold;
        if (h > 0u) {
            *hold = h - 1u;
        }
        if ((*hold == 0u) && (under != 0)) {
            *fired = 0u;
        }
    } else {
        /* not fired, nothing exceeded: nothing changes */
    }
}

#endif /* RFE_MONITOR_LOGIC_H */
