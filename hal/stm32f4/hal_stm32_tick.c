/*
 * hal_stm32_tick.c - hal/hal_time.h on the STM32F405 time base
 * (hal_stm32_time.h): the main loop's wait for its 10 ms deadline, on TIM2's
 * compare channel 1, sleeping (WFI) in between when the clock was set up
 * with sleep_between. Apart from hal_stm32_time.c so that an image with
 * another hal_time.h backend (the bench's replay) can use the time base.
 */
#include "hal/stm32f4/hal_stm32_time.h"

uint64_t hal_time_now_us(hal_time_t *time)
{
    (void)time;
    return hal_stm32_now_us();
}

int hal_time_wait_until_us(hal_time_t *time, uint64_t deadline_us)
{
    if (hal_stm32_now_us() >= deadline_us) {
        time->waits_late++;
        return 0;
    }
    /* Compare channel 1 at the deadline's low word wakes the core. */
    HAL_STM32_WR(time->tim->ccr1, (uint32_t)deadline_us);
    HAL_STM32_WR(time->tim->sr, ~TIM_SR_CC1IF);
    HAL_STM32_WR(time->tim->dier, TIM_DIER_UIE | TIM_DIER_CC1IE);
    while (hal_stm32_now_us() < deadline_us) {
#ifndef HAL_STM32_REG_MODEL
        if (time->sleep_between != 0U) {
            __asm__ volatile("wfi" ::: "memory");
        }
#endif
    }
    HAL_STM32_WR(time->tim->dier, TIM_DIER_UIE);
    return 0;
}
