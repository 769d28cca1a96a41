/* hal_stm32_time.c - 64-bit microseconds from TIM2 (contract in hal_stm32_time.h). */
#include "hal/stm32f4/hal_stm32_time.h"

#include <stddef.h>

#include "hal/stm32f4/stm32f4_irq.h"

static hal_time_t *s_clock;

void hal_stm32_time_init(hal_time_t *t, stm32_tim_t *tim, uint32_t tim_clock_hz,
                         uint8_t sleep_between)
{
    t->tim = tim;
    t->wraps = 0U;
    t->waits_late = 0U;
    t->sleep_between = sleep_between;
    HAL_STM32_WR(tim->cr1, 0U);
    HAL_STM32_WR(tim->psc, (tim_clock_hz / 1000000U) - 1U);
    HAL_STM32_WR(tim->arr, 0xFFFFFFFFU);
    HAL_STM32_WR(tim->egr, TIM_EGR_UG);  /* load the prescaler now */
    HAL_STM32_WR(tim->sr, 0U);           /* the forced update set UIF */
    HAL_STM32_WR(tim->cnt, 0U);
    HAL_STM32_WR(tim->dier, TIM_DIER_UIE);
    HAL_STM32_WR(tim->cr1, TIM_CR1_CEN);
}

void hal_stm32_time_use(hal_time_t *t)
{
    s_clock = t;
}

uint64_t hal_stm32_time_read(const stm32_tim_t *tim, uint32_t wraps)
{
    uint32_t hi = wraps;
    uint32_t cnt = tim->cnt;
    if ((tim->sr & TIM_SR_UIF) != 0U) {
        /* Wrapped, not yet counted: the counter read may predate the wrap. */
        hi++;
        cnt = tim->cnt;
    }
    return ((uint64_t)hi << 32) | cnt;
}

uint64_t hal_stm32_now_us(void)
{
    if (s_clock == NULL) {
        return 0U;
    }
    const uint32_t primask = hal_stm32_irq_save();
    const uint64_t now = hal_stm32_time_read(s_clock->tim, s_clock->wraps);
    hal_stm32_irq_restore(primask);
    return now;
}

void hal_stm32_time_isr(hal_time_t *t)
{
    const uint32_t sr = t->tim->sr;
    if ((sr & TIM_SR_UIF) != 0U) {
        t->wraps = t->wraps + 1U;
    }
    /* Flags clear by writing 0 (rc_w0); the others are written 1, unchanged. */
    HAL_STM32_WR(t->tim->sr, ~(sr & (TIM_SR_UIF | TIM_SR_CC1IF)));
}
