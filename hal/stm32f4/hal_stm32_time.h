/*
 * hal_stm32_time.h - the STM32F4 backend's clock: a 1 us monotonic time
 * base from TIM2 (32 bits, 84 MHz timer clock / 84), extended to 64 bits,
 * and hal/hal_time.h's wait on TIM2's compare channel 1.
 *
 * Extension without a race: TIM2's update interrupt (the counter wrapping,
 * every 2^32 us = 71.6 min) adds one to the high word. A reader masks
 * interrupts, reads the high word and the counter, and if the update flag
 * is still pending (the wrap happened but its interrupt has not run, being
 * masked or of lower priority than the caller) counts it itself and reads
 * the counter again, which is then past the wrap. So hal_stm32_now_us() is
 * correct from the main loop and from any interrupt handler.
 */
#ifndef HAL_STM32_TIME_H
#define HAL_STM32_TIME_H

#include <stdint.h>

#include "hal/hal_time.h"
#include "hal/stm32f4/stm32f4_regs.h"

struct hal_time {
    stm32_tim_t *tim;
    volatile uint32_t wraps;     /* high word, written by hal_stm32_time_isr() */
    uint32_t waits_late;         /* waits whose deadline had passed on entry */
    uint8_t sleep_between;       /* 1: WFI while waiting (the MCU); 0: spin */
};

/* Starts tim counting microseconds: prescaler tim_clock_hz / 1 MHz - 1,
 * auto-reload 2^32 - 1, update interrupt on. The caller enables TIM2's
 * interrupt in the NVIC. */
void hal_stm32_time_init(hal_time_t *t, stm32_tim_t *tim, uint32_t tim_clock_hz,
                         uint8_t sleep_between);

/* Microseconds since hal_stm32_time_init(), from the time base set up by
 * hal_stm32_time_use() (the backend's one clock). Any context. O(1). */
uint64_t hal_stm32_now_us(void);
void hal_stm32_time_use(hal_time_t *t);

/* The 64-bit time from a timer and its high word (what
 * hal_stm32_now_us() computes; interrupts masked by the caller). */
uint64_t hal_stm32_time_read(const stm32_tim_t *tim, uint32_t wraps);

/* TIM2's interrupt: counts a wrap (update flag), ends a wait (compare 1). */
void hal_stm32_time_isr(hal_time_t *t);

#endif /* HAL_STM32_TIME_H */
