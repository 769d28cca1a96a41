/*
 * SysTick as a 64-bit instruction counter: the 24-bit down-counter gives the
 * low part, the wrap count kept by the interrupt the high part.
 */
#include "hal/mps2/icount.h"

#include <stdbool.h>

#define SYST_CSR (*(volatile uint32_t *)0xE000E010U)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014U)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018U)
#define SCB_ICSR (*(volatile uint32_t *)0xE000ED04U)

#define SYST_CSR_ENABLE (1U << 0)
#define SYST_CSR_TICKINT (1U << 1)
#define SYST_CSR_CLKSOURCE_CPU (1U << 2)
#define SCB_ICSR_PENDSTCLR (1U << 25)
#define SCB_ICSR_PENDSTSET (1U << 26)

#define RELOAD 0x00FFFFFFU /* largest value: one wrap per 2^24 ticks */
#define TICKS_PER_WRAP_LOG2 24U

static volatile uint32_t s_wraps;
static volatile bool s_running;

void SysTick_Handler(void)
{
    s_wraps = s_wraps + 1U;
}

void hal_mps2_icount_start(void)
{
    SYST_CSR = 0U;
    SYST_RVR = RELOAD;
    SYST_CVR = 0U; /* any write clears the counter; it reloads on the next tick */
    SCB_ICSR = SCB_ICSR_PENDSTCLR;
    s_wraps = 0U;
    s_running = true;
    SYST_CSR = SYST_CSR_CLKSOURCE_CPU | SYST_CSR_TICKINT | SYST_CSR_ENABLE;
}

uint64_t hal_mps2_icount_now(void)
{
    if (!s_running) {
        return 0U;
    }
    uint32_t primask;
    __asm__ volatile("mrs %0, primask\n\tcpsid i" : "=r"(primask)::"memory");

    uint32_t wraps = s_wraps;
    uint32_t cvr = SYST_CVR;
    /* With interrupts masked a wrap shows only as a pending SysTick: count it
     * here, and re-read the counter, which may have been read just before
     * the wrap. */
    if ((SCB_ICSR & SCB_ICSR_PENDSTSET) != 0U) {
        wraps += 1U;
        cvr = SYST_CVR;
    }

    if ((primask & 1U) == 0U) {
        __asm__ volatile("cpsie i" ::: "memory");
    }

    /* The counter runs RELOAD, RELOAD-1, ..., 1, 0, RELOAD, ...: it shows 0
     * for one tick, and the wrap is counted when it reaches 0. Ticks within
     * the period are therefore (2^24 - cvr) mod 2^24, which also reads 0 in
     * the tick after hal_mps2_icount_start() cleared the counter. */
    uint32_t phase = (RELOAD + 1U - cvr) & RELOAD;
    uint64_t ticks = ((uint64_t)wraps << TICKS_PER_WRAP_LOG2) + phase;
    return ticks * HAL_MPS2_ICOUNT_INSNS_PER_TICK;
}
